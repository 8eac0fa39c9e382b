"""Whether a witness stands whatever the model leaves unspecified.

BMC keeps what the model does not fix open: a function without a body, or outside its
preconditions, is a Z3 function symbol constrained by its conditions (docs/semantics.md §6.4),
and so is a lambda applied outside its condition, a `min`/`max` of a set without one, a
sequence's item outside its length and an update there, and a division by zero (Z3 leaves those
unspecified). A claim about every run is decided for every such choice at once. A run found as a
witness (`S is reachable`, `P terminates`, the negated forms) may rest on the choice it made, and
then shows the claim for that choice only: `unspecified` says which of those its system can meet.

`every_interpretation` asks whether the same run stands for every choice: the moves and every
value chosen in the run (inputs, fresh values, the initial configuration) fixed, each step's
guards and the target are formulas over the unspecified values alone, the configurations being
computed from the moves' effects step by step, and the run stands for every choice allowed by the
functions' conditions when no choice makes one of them false. That is one query without
quantifiers over the configurations (a sufficient condition: another choice might need another
run, which this does not look for).
"""

from __future__ import annotations

from collections.abc import Iterable

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.unroller import Unroller, int_value
from tockbmc.encodings.values import UPDATE_OUTSIDE, leaves

_MOST_SECONDS = 5.0
_DIVISIONS = (z3.Z3_OP_DIV, z3.Z3_OP_IDIV, z3.Z3_OP_MOD, z3.Z3_OP_REM)


def _nonzero_numeral(x: z3.ExprRef) -> bool:
    if z3.is_int_value(x):
        return x.as_long() != 0  # type: ignore[attr-defined, no-any-return]
    if z3.is_rational_value(x):
        return x.as_fraction() != 0  # type: ignore[attr-defined, no-any-return]
    return False


def _found(terms: Iterable[z3.ExprRef], functions: frozenset[str], facts: Iterable[z3.BoolRef] = ()) -> list[str]:
    """What the terms leave unspecified, as the report names it: a function by its name (one with no
    parameters is a constant in Z3, known by `functions`), else the kind of value. A division counts
    unless `facts` (the constants' values) rule out a zero divisor (`PI / av` with av = 2)."""
    out: dict[str, None] = {}
    facts = list(facts)

    def may_be_zero(divisor: z3.ExprRef) -> bool:
        if _nonzero_numeral(divisor):
            return False
        solver = z3.Solver()
        solver.set(timeout=1000)
        solver.add(facts)
        solver.add(divisor == 0)  # type: ignore[arg-type]
        return solver.check() != z3.unsat

    # Each subterm once, with whether it is inside a quantifier: Z3's `nth` counts (the model's own
    # reads of an item, `s[i - 1]`, and head, last) but inside a quantifier at a bound variable
    # itself, which only the domain constraints read (`values._container_domain`: items within the
    # length).
    seen: set[tuple[int, bool]] = set()
    stack = [(t, False) for t in terms]
    while stack:
        t, quantified = stack.pop()
        if (t.get_id(), quantified) in seen:
            continue
        seen.add((t.get_id(), quantified))
        if z3.is_quantifier(t):
            stack.append((t.body(), True))
            continue
        stack += [(c, quantified) for c in t.children()]
        if not z3.is_app(t):
            continue
        decl = t.decl()
        kind, name = decl.kind(), decl.name()
        if kind == z3.Z3_OP_SEQ_NTH and not (quantified and z3.is_var(t.arg(1))):
            out["a sequence's item outside its length"] = None
        elif kind == z3.Z3_OP_UNINTERPRETED and (decl.arity() > 0 or name.removesuffix(".outside") in functions):
            if name.startswith("lambda!"):
                out[f"a lambda outside its condition (line {name[7:].split(':')[0]})"] = None
            elif name.startswith(UPDATE_OUTSIDE):
                out["a sequence updated outside its length"] = None
            elif name.startswith("toolkit."):
                out[f"{name[8:]} of a set without one"] = None
            else:
                out[name.removesuffix(".outside")] = None
        elif kind in _DIVISIONS and "a division by zero" not in out and may_be_zero(t.arg(1)):
            out["a division by zero"] = None
    return list(out)


def unspecified(system: TransitionSystem, target: z3.BoolRef, functions: Iterable[str] = ()) -> list[str]:
    """What the runs of `system` to `target` can meet that the model leaves unspecified."""
    return _found([system.init(), system.trans(), target, *system.invariants(), *system.side], frozenset(functions),
                  system.invariants())


def start_unspecified(system: TransitionSystem, functions: Iterable[str] = ()) -> bool:
    """Whether the initial configuration or the constants' values rest on something unspecified
    (a replay takes those from the run, so it does not show that the run stands without them)."""
    return bool(_found([system.init(), *system.invariants()], frozenset(functions)))


def every_interpretation(u: Unroller, model: z3.ModelRef, depth: int, target: z3.BoolRef,
                         functions: Iterable[str] = (), seconds: float | None = None) -> bool:
    """Whether the run `model` gives `u` up to `depth` reaches `target` whatever the model leaves
    unspecified (within the functions' conditions), its moves and chosen values kept. False when
    that is not shown: an extension steps beside the network (a specification's monitor), the
    initial configuration or the constants' values rest on something unspecified, or Z3 does not
    answer within `seconds` (at most 5)."""
    s = u.system
    known = frozenset(functions)
    if s.extensions or start_unspecified(s, known) or _found([target], known):
        return False
    moves = {m.index: m for m in s.moves}
    frame = {n: model.eval(u.frame(0)[n], model_completion=True) for n in s.sorts}
    holds: list[z3.BoolRef] = []  # each step's guards, then the target: all must hold
    # The constants' constraints (over the constants alone), and the functions' conditions at the
    # arguments each step gives them.
    assumed: list[z3.BoolRef] = list(s.invariants())
    for i in range(depth):
        m = moves.get(int_value(model, u.action(i)))
        if m is None:
            return False
        pairs = [(s.cur[n], frame[n]) for n in s.sorts]
        for name, (_t, value) in s.inputs.items():
            pairs += [(template, model.eval(actual, model_completion=True))
                      for (_, template), (_, actual) in zip(leaves(value), leaves(u.input(name, i)), strict=True)]
        eff = s.effect(m)
        holds += [z3.substitute(c, *pairs) for c in (*eff.enabled, *eff.choose)]
        # Only this move's own: an axiom of another move's call may read the configuration (a
        # lambda's result in its type), which is no condition on the functions here. Of its own,
        # one about an unspecified value is a condition on the choices; one that reads only the
        # configuration (that lambda's result, applied by this move) is one more guard.
        for a in eff.side:
            (assumed if _found([a], known) else holds).append(z3.substitute(a, *pairs))
        frame = {n: z3.substitute(eff.post[n], *pairs) if n in eff.post else frame[n] for n in s.sorts}
        frame[names.PREVIOUS] = z3.IntVal(m.index)
    holds.append(z3.substitute(target, *[(s.cur[n], frame[n]) for n in s.sorts]))
    solver = z3.Solver()
    solver.set(timeout=max(1, int(1000 * min(_MOST_SECONDS, seconds if seconds is not None else _MOST_SECONDS))))
    solver.add(assumed)
    solver.add(z3.Not(z3.And(holds)))
    return solver.check() == z3.unsat
