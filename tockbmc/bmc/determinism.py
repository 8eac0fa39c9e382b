"""Determinism by self-composition: two runs of one system with the same visible trace.

`P is deterministic` (docs/semantics.md §7.10) fails when, after some trace, an event is possible
and can also be refused: one run performs the trace and then the event, another performs the same
trace and reaches a stable configuration (no internal step possible) that does not offer it.

Both runs are unrolled side by side, run A under names `A.x@k` and run B under `B.x@k`, in one
solver.  At each step of the pair one of four things happens: A takes an internal step while B
stays where it is, B takes one while A stays, or both take a visible step with the same event and
the same values, or both take an internal step (so two runs that share a long prefix need no more
steps of the pair than one of them alone).  So after k steps of the pair both runs have performed the same visible trace.
The target at k is that B is stable and A's next step is a visible event that no move of B offers
with those values (`tock` included: B refuses it when time cannot pass there).

Both runs start from the same configuration: the values a configuration starts from (constants and
variables without an initial value) are a choice of the environment, not of the process, and the
assertion must hold for each choice (docs/semantics.md §2.14); choices made inside a run (a
nondeterministic `wait`, an operation's local without a value) differ between the runs.

Between two visible steps, A's internal steps are taken before B's, so each pair of runs is
unrolled in one order only rather than in every interleaving of the two.

Only runs up to the bound are searched: a verdict that holds is bounded.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import z3

from tockbmc.bmc.engine import Clock, Status, new_solver
from tockbmc.encodings.system import Move, TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.encodings.values import leaves
from tockbmc.model.result import TraceStep
from tockbmc.properties.determinism import Offers, visible_moves


@dataclass
class Pair:
    """What a search found: the two runs, and which of them moved at each step of the pair."""

    status: Status
    depth: int  # steps of the pair before A's last event (when found); the depth searched otherwise
    a: Unroller | None = None
    b: Unroller | None = None
    model: z3.ModelRef | None = None
    reason: str | None = None
    moved: list[tuple[bool, bool]] = field(default_factory=list)  # per step of the pair: (A moved, B moved)
    prefix: tuple[TraceStep, ...] = ()  # the run both share before the pair starts (searched from a split)
    choices: dict[str, object] | None = None  # the values that shared run starts from, for replay


def nondeterminism(system: TransitionSystem, bound: int, timeout: float | None = None,
                   start: list[z3.BoolRef] | None = None) -> Pair:
    """Search pairs of runs of up to `bound` steps for an event one run offers and the other refuses.

    `start`, when given, is a configuration over the template's `cur` (and the constants' values)
    that both runs start from instead of the initial one: a reachable configuration where the next
    step is open (`properties.determinism`), from which a short search often finds the two runs
    that the search from the start would need many more steps for."""
    clock = Clock(timeout)
    a, b = Unroller(system, "A."), Unroller(system, "B.")
    solver = new_solver(system)
    if start is None:
        solver.add(a.at(system.init(), 0), b.at(system.init(), 0))
    else:
        solver.add(*system.invariants(), *(a.at(c, 0) for c in start), *(b.at(c, 0) for c in start))
    solver.add([a.frame(0)[n] == b.frame(0)[n] for n in system.sorts])
    trans, shown = system.trans(), system.visible()
    visible = visible_moves(system)
    by_label: dict[tuple, list[Move]] = {}
    for m in visible:
        by_label.setdefault(system.label(m), []).append(m)
    offers = Offers(system)
    moved: list[tuple[z3.BoolRef, z3.BoolRef]] = []

    def values(u: Unroller, m: Move, k: int) -> list[z3.ExprRef]:
        return [u.at(term, k) for term in offers.carried(m)]

    def stays(u: Unroller, k: int) -> z3.BoolRef:
        before, after = u.frame(k), u.frame(k + 1)
        return z3.And([after[n] == before[n] for n in system.sorts])

    def refused(m: Move, k: int) -> z3.BoolRef:
        """B, at step k, offers no move of m's event with the values A's move m carries there."""
        carried = values(a, m, k)
        out = []
        for other in by_label[system.label(m)]:
            formula, holes = offers.template(other)
            at_b = b.at(formula, k)
            out.append(z3.Not(z3.substitute(at_b, *zip(holes, carried, strict=True)) if holes else at_b))
        return z3.And(out)

    stable_b = z3.Not(system.internal_enabled())
    previous_b_internal: z3.BoolRef = z3.BoolVal(False)
    for k in range(bound + 1):
        literal = z3.Bool(f"nondeterministic@{k}")
        a_event = z3.And(a.at(trans, k), a.at(shown, k))
        refusal = z3.And([z3.Implies(a.action(k) == m.index, refused(m, k)) for m in visible])
        solver.add(z3.Implies(literal, z3.And(a_event, b.at(stable_b, k), refusal)))
        solver.add(*a.axioms_upto(k + 1), *b.axioms_upto(k + 1))
        if not clock.arm(solver):
            return Pair(Status.UNKNOWN, k, reason=f"timed out at depth {k}")
        result = solver.check(literal)
        if result == z3.sat:
            model = solver.model()
            steps = [(z3.is_true(model.eval(x, model_completion=True)), z3.is_true(model.eval(y, model_completion=True)))
                     for x, y in moved]
            return Pair(Status.FOUND, k, a, b, model, moved=steps)
        if result == z3.unknown:
            why = solver.reason_unknown()
            if why in ("canceled", "timeout", "interrupted"):
                return Pair(Status.UNKNOWN, k, reason=f"timed out at depth {k}")
            return Pair(Status.UNKNOWN, k, reason=f"Z3 gave up at depth {k}: {why}")
        if k == bound:
            break
        a_internal = z3.And(a.at(trans, k), z3.Not(a.at(shown, k)), stays(b, k))
        b_internal = z3.And(b.at(trans, k), z3.Not(b.at(shown, k)), stays(a, k))
        same = [z3.And(a.action(k) == m.index, b.action(k) == o.index,
                       *(x == y for x, y in zip(values(a, m, k), values(b, o, k), strict=True)))
                for ms in by_label.values() for m in ms for o in ms]
        joint = z3.And(a.at(trans, k), b.at(trans, k), z3.Or(same or [z3.BoolVal(False)]))
        # Both take an internal step at once: two runs that share a long prefix need half the depth.
        both_internal = z3.And(a.at(trans, k), z3.Not(a.at(shown, k)), b.at(trans, k), z3.Not(b.at(shown, k)))
        solver.add(z3.Or(a_internal, b_internal, joint, both_internal))
        if moved:  # between visible steps, A's internal steps first, then B's: one order of each pair of runs
            solver.add(z3.Implies(previous_b_internal, z3.Not(a_internal)))
        previous_b_internal = b_internal
        solver.add(a.action(k) >= 0, a.action(k) <= system.TOCK, b.action(k) >= 0, b.action(k) <= system.TOCK)
        # Named by Boolean constants, whose values a model always gives: evaluating the formulas
        # themselves in a model fails where they hold quantifiers (the elements of an input sequence).
        a_moved, b_moved = z3.Bool(f"A moved@{k}"), z3.Bool(f"B moved@{k}")
        solver.add(a_moved == z3.Or(a_internal, joint, both_internal), b_moved == z3.Or(b_internal, joint, both_internal))
        moved.append((a_moved, b_moved))
    return Pair(Status.NOT_FOUND, bound)


def configuration_of(unroller: Unroller, model: z3.ModelRef, k: int) -> list[z3.BoolRef]:
    """The configuration a run reaches at step k, and its constants' values, as equations over the
    template's `cur`: a start for `nondeterminism`."""
    system = unroller.system
    frame = unroller.frame(k)
    out = [system.cur[n] == model.eval(frame[n], model_completion=True) for n in system.sorts]
    for values in system.constants.values():
        for value in values.values():
            out += [term == model.eval(term, model_completion=True) for _p, term in leaves(value)]
    return out
