"""Proofs where k-induction fails: property-directed reachability on Z3's Horn-clause solver (Spacer).

The transition system becomes three constrained Horn clauses over one unknown
relation `Inv` of a configuration (and the constants, which never change):

    init(x)                    → Inv(x)
    Inv(x) ∧ trans(x, x', …)   → Inv(x')
    Inv(x) ∧ target(x)         → false

Spacer (IC3/PDR over linear arithmetic) either finds an interpretation of `Inv`
— an inductive invariant that excludes the target, so no run of any length
reaches it — or shows the target reachable (BMC then finds the run and shows
it).  The invariant is not taken on trust: it is checked again, in a fresh
solver, to contain the initial configurations, to be closed under a step and to
exclude the target, before a verdict rests on it.

Spacer runs in a process of its own, beside BMC (`bmc.portfolio`); it applies when the formulas are quantifier-free and call no
uninterpreted function (functions without a body, or with pre/postconditions),
which Horn clauses over arithmetic cannot express.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
from multiprocessing.connection import Connection

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.terms import constants, subterms
from tockbmc.encodings.values import leaves
from tockbmc.model.lifetime import end_with


def applicable(system: TransitionSystem, target: z3.BoolRef) -> str | None:
    """None when Spacer can decide the target; else why not."""
    if system.side:
        return "the model's functions have axioms (pre- or postconditions)"
    for term in (system.init(), system.trans(), target):
        why = _outside(term)
        if why:
            return why
    return None


def _outside(term: z3.ExprRef) -> str | None:
    """What in `term` Horn clauses over arithmetic cannot take: a quantifier or a function application."""
    for t in subterms(term):
        if z3.is_quantifier(t):
            return "the property quantifies over values"
        if z3.is_app(t) and t.decl().kind() == z3.Z3_OP_UNINTERPRETED and t.num_args() > 0:
            return f"the model calls function {t.decl().name()}, which has no body"
    return None


def _solve(query: str, timeout: float | None, answer: Connection) -> None:
    """In a process of its own: solve the Horn query (SMT-LIB text) and send back ("proved", the
    invariant as an SMT-LIB term over the relation's arguments), ("reachable", "") or ("unknown", "")."""
    _detach()
    try:
        solver = z3.SolverFor("HORN")
        if timeout is not None:
            solver.set("timeout", max(1, int(timeout * 1000)))
        solver.from_string(query)
        result = solver.check()
        if result == z3.sat:
            model = solver.model()
            inv = next(d for d in model.decls() if d.name() == "Inv")
            interp = model[inv]
            body = interp.else_value() if isinstance(interp, z3.FuncInterp) else interp
            names = query.split("\n", 1)[0].removeprefix("; arguments: ").split("\t")
            args = [z3.Const(n, inv.domain(i)) for i, n in enumerate(names)]
            # The interpretation reads argument i as variable i.
            term = z3.substitute_vars(body, *args) if body is not None else z3.BoolVal(True)
            answer.send(("proved", term.sexpr()))
        else:
            answer.send(("reachable" if result == z3.unsat else "unknown", ""))
    except Exception:  # noqa: BLE001 - any failure of the child is "no answer"
        answer.send(("unknown", ""))


def _detach() -> None:
    """In the child: let go of the terminal's streams (whoever reads the parent's output must see it
    end when the parent does) and end when the parent ends, however it ends."""
    devnull = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(devnull, fd)
    end_with()


class Spacer:
    """One Horn-clause query for one target, solved in a process of its own.

    Z3 contexts are meant to be usable from several threads, but a Horn query solved in a thread
    beside BMC was seen to corrupt BMC's solver (bogus models); a process shares nothing."""

    def __init__(self, system: TransitionSystem, target: z3.BoolRef):
        init, trans = system.init(), system.trans()  # built first: building them declares the inputs
        names = list(system.sorts)
        inputs = [t for _t, v in system.inputs.values() for _p, t in leaves(v)]
        # What every step shares (the constants, a parametric range's bounds) is carried unchanged
        # by the relation: left free, Spacer would choose its value instead of covering every one.
        stepwise = {t.get_id() for t in [*system.cur.values(), *system.nxt.values(), system.act, *inputs]}
        rigid = [t for t in constants(init, trans, target) if t.get_id() not in stepwise]
        self.args = [system.cur[n] for n in names] + rigid
        nxt = [system.nxt[n] for n in names] + rigid
        inv = z3.Function("Inv", *[x.sort() for x in self.args], z3.BoolSort())
        cur = self.args
        steps = cur + [system.nxt[n] for n in names] + [system.act] + inputs
        solver = z3.Solver()
        solver.add(z3.ForAll(cur, z3.Implies(init, inv(*cur))),
                   z3.ForAll(steps, z3.Implies(z3.And(inv(*cur), trans), inv(*nxt))),
                   z3.ForAll(cur, z3.Implies(z3.And(inv(*cur), target), z3.BoolVal(False))))
        self.query = "; arguments: " + "\t".join(str(x) for x in cur) + "\n" + solver.sexpr()
        self.status = "unknown"
        self._invariant = ""
        self._pid: int | None = None  # the child solving, until it is reaped
        self._answer: Connection | None = None

    def start(self, timeout: float | None) -> None:
        """Start solving in a child process: a fork (no re-import, nothing to pickle but text), by
        `os.fork` rather than `multiprocessing`, which refuses children to a daemonic process such as
        a Dask worker's."""
        receive, send = multiprocessing.Pipe(duplex=False)
        pid = os.fork()
        if pid == 0:  # the child: solve, answer, and end without running the parent's exit handlers
            try:
                receive.close()
                _solve(self.query, timeout, send)
            finally:
                os._exit(0)
        send.close()
        self._pid, self._answer = pid, receive

    def wait(self, seconds: float | None) -> str:
        """Wait up to `seconds` (None: until it answers or is killed) for the answer; returns the status
        so far.  One thread waits; another may `kill` the child meanwhile."""
        if self.status == "unknown" and self._answer is not None and self._answer.poll(seconds):
            try:
                self.status, self._invariant = self._answer.recv()
            except EOFError:  # the child was killed, or died
                self.status = "unknown"
            self._answer.close()
            self._answer = None
            self._reap()
        return self.status

    def _reap(self) -> None:
        if self._pid is not None:
            os.waitpid(self._pid, 0)
            self._pid = None

    def run(self, timeout: float | None) -> str:
        """Solve and wait: "proved" (an invariant was found), "reachable", or "unknown"."""
        self.start(timeout)
        try:
            return self.wait(None if timeout is None else timeout + 5)
        finally:
            self.kill()
            self.wait(None)  # reaps the child

    def invariant(self) -> z3.BoolRef:
        """The invariant found, over the template configuration and the constants."""
        decls = {str(x): x for x in self.args}
        return z3.And(z3.parse_smt2_string(f"(assert {self._invariant})", decls=decls))  # type: ignore[arg-type]

    def kill(self) -> None:
        """Stop the child, if it is still solving (its waiter then sees no answer)."""
        if self._pid is not None:
            with contextlib.suppress(ProcessLookupError):  # it has ended, and is not reaped yet
                os.kill(self._pid, signal.SIGKILL)


def confirmed(system: TransitionSystem, target: z3.BoolRef, invariant: z3.BoolRef, timeout: float = 10) -> bool:
    """Whether `invariant` holds initially, is kept by every step and excludes the target (a fresh solver)."""
    after = z3.substitute(invariant, *[(system.cur[n], system.nxt[n]) for n in system.sorts])
    for claim in (z3.Implies(system.init(), invariant),
                  z3.Implies(z3.And(invariant, system.trans()), after),
                  z3.Implies(invariant, z3.Not(target))):
        solver = z3.Solver()
        solver.set("timeout", max(1, int(timeout * 1000)))
        solver.add(z3.Not(claim))
        if solver.check() != z3.unsat:
            return False
    return True


_INFIX = {z3.Z3_OP_LE: "<=", z3.Z3_OP_LT: "<", z3.Z3_OP_GE: ">=", z3.Z3_OP_GT: ">", z3.Z3_OP_ADD: "+",
          z3.Z3_OP_SUB: "-", z3.Z3_OP_MUL: "*", z3.Z3_OP_AND: "and", z3.Z3_OP_OR: "or", z3.Z3_OP_IMPLIES: "=>"}


_FLIP = {z3.Z3_OP_LE: ">", z3.Z3_OP_LT: ">=", z3.Z3_OP_GE: "<", z3.Z3_OP_GT: "<="}


def describe(system: TransitionSystem, invariant: z3.BoolRef, most: int = 2000) -> str:
    """The invariant in the model's names: `EXAX at time_check`, `UR.curr_waypoint`, `monitor`."""
    where: dict[int, str] = {}  # id of a location slot -> its component
    for comp in system.components:
        where[system.cur[names.location(comp.name)].get_id()] = comp.name
    located = {comp.name: comp.automaton.locations for comp in system.components}
    named = {system.cur[n].get_id(): n for n in system.sorts}

    def text(t: z3.ExprRef, top: bool = False) -> str:
        if z3.is_true(t) or z3.is_false(t):
            return str(z3.is_true(t)).lower()
        if z3.is_int_value(t) or z3.is_rational_value(t):
            return str(t)
        if z3.is_const(t) and t.get_id() in named:
            return named[t.get_id()]
        if z3.is_const(t):
            return str(t).removesuffix("@0")
        if not z3.is_app(t):  # a quantifier or a bound variable: Z3's own text
            return str(t)
        kind, args = t.decl().kind(), t.children()
        if kind == z3.Z3_OP_EQ and len(args) == 2:
            for a, b in (args, args[::-1]):
                if a.get_id() in where and z3.is_int_value(b):
                    comp = where[a.get_id()]
                    locations = located[comp]
                    i = b.as_long()  # type: ignore[attr-defined]
                    return f"{comp} at {locations[i].description}" if 0 <= i < len(locations) else f"{names.location(comp)} = {i}"
            out = f"{text(args[0])} = {text(args[1])}"
        elif kind == z3.Z3_OP_NOT:
            inner = args[0]
            if z3.is_eq(inner):
                return text(inner).replace(" = ", " ≠ ").replace(" at ", " not at ", 1)
            flipped = _FLIP.get(inner.decl().kind()) if z3.is_app(inner) else None
            if flipped is not None and inner.num_args() == 2:
                out = f"{text(inner.arg(0))} {flipped} {text(inner.arg(1))}"
            else:
                out = f"not {text(inner)}"
        elif kind in _INFIX:
            out = f" {_INFIX[kind]} ".join(text(a) for a in args)
        else:
            out = str(t)
        return out if top else f"({out})"

    conjuncts = invariant.children() if z3.is_and(invariant) else [invariant]
    rendered = "; ".join(text(c, top=True) for c in conjuncts)
    return rendered if len(rendered) <= most else rendered[:most] + " …"
