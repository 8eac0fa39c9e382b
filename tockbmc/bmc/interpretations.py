"""Whether a witness stands whatever the functions without a body compute.

BMC keeps a function without a body uninterpreted: a Z3 function symbol, constrained by its
conditions (docs/semantics.md §6.4). A run found as a witness (`S is reachable`, `P terminates`,
the negated forms) may rest on the values it chose for such a function, and then shows the claim
for that interpretation only. `every_interpretation` asks whether the same run stands for every
one: the moves and every value chosen in the run (inputs, fresh values, the initial
configuration) fixed, each step's guards and the target are then formulas over the functions
alone, the configurations being computed from the moves' effects step by step, and the run stands
for every interpretation allowed by the functions' conditions when no interpretation makes one
of them false. That is one query without quantifiers over the configurations (a sufficient
condition: another interpretation might need another run, which this does not look for).
"""

from __future__ import annotations

import z3

from tockbmc.encodings import names
from tockbmc.encodings.terms import subterms
from tockbmc.encodings.unroller import Unroller, int_value
from tockbmc.encodings.values import leaves

_MOST_SECONDS = 5.0


def _calls_functions(term: z3.ExprRef) -> bool:
    return any(z3.is_app(t) and t.decl().kind() == z3.Z3_OP_UNINTERPRETED and t.decl().arity() > 0
               for t in subterms(term))


def every_interpretation(u: Unroller, model: z3.ModelRef, depth: int, target: z3.BoolRef,
                         seconds: float | None = None) -> bool:
    """Whether the run `model` gives `u` up to `depth` reaches `target` whatever the functions
    without a body compute (within their conditions), its moves and chosen values kept. False
    when that is not shown: an extension steps beside the network (a specification's monitor), the
    initial configuration or the target calls a function, or Z3 does not answer within `seconds`
    (at most 5)."""
    s = u.system
    if s.extensions or _calls_functions(s.init()) or _calls_functions(target) \
            or any(_calls_functions(c) for c in s.invariants()):
        return False
    moves = {m.index: m for m in s.moves}
    frame = {n: model.eval(u.frame(0)[n], model_completion=True) for n in s.sorts}
    holds: list[z3.BoolRef] = []  # each step's guards, then the target: all must hold
    assumed: list[z3.BoolRef] = []  # the functions' conditions, at the arguments each step gives them
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
        assumed += [z3.substitute(a, *pairs) for a in s.side]
        frame = {n: z3.substitute(eff.post[n], *pairs) if n in eff.post else frame[n] for n in s.sorts}
        frame[names.PREVIOUS] = z3.IntVal(m.index)
    holds.append(z3.substitute(target, *[(s.cur[n], frame[n]) for n in s.sorts]))
    assumed += [z3.substitute(a, *[(s.cur[n], frame[n]) for n in s.sorts]) for a in s.side]
    solver = z3.Solver()
    solver.set(timeout=max(1, int(1000 * min(_MOST_SECONDS, seconds if seconds is not None else _MOST_SECONDS))))
    solver.add(assumed)
    solver.add(z3.Not(z3.And(holds)))
    return solver.check() == z3.unsat
