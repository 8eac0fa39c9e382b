"""Terms of a transition system at step k, in the manner of pono's `core/unroller.h`.

The transition system builds every formula once, over its template step:
the configuration before it (`x@0`), after it (`x@1`), the move taken
(`act@0`) and the values chosen during it (`name@0`).  `at(term, k)` renames
those to `x@k`, `x@k+1`, `act@k` and `name@k` with one `Z3_substitute` call,
which costs far less than building the formula again in Python.  Each engine
(BMC, the k-induction step case) keeps an unroller of its own.
"""

from __future__ import annotations

import z3

from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.values import Value, fresh, leaves

_QE_MS = 2000  # to eliminate the quantifiers of a value a model defines by a formula


def int_value(model: z3.ModelRef, term: z3.ExprRef) -> int:
    """The value of an integer term in a model.  A model may define one by a quantified formula
    (`If(Exists(…), 1, 4)`, as a refusal's values leave the monitor's state); its quantifiers are
    then eliminated and the result solved for."""
    value = model.eval(term, model_completion=True)
    if z3.is_int_value(value):
        return value.as_long()  # type: ignore[attr-defined, no-any-return]
    n = z3.Int("int_value", value.ctx)
    goal = z3.Goal(ctx=value.ctx)
    goal.add(n == value)
    solver = z3.Solver(ctx=value.ctx)
    solver.set(timeout=_QE_MS)
    solver.add(z3.Then("simplify", "qe", "simplify", ctx=value.ctx)(goal).as_expr())
    found = solver.model().eval(n, model_completion=True) if solver.check() == z3.sat else None
    if not z3.is_int_value(found):
        raise RuntimeError(f"the value of {term} in the run could not be computed")
    return found.as_long()  # type: ignore[union-attr, no-any-return]


class _Renaming:
    """A substitution of constants, prepared once and applied to many terms.

    `z3.substitute` re-checks every pair's sorts in Python at each call, which costs more than the
    substitution itself when the same pairs rename hundreds of terms."""

    def __init__(self, pairs: list[tuple[z3.ExprRef, z3.ExprRef]]):
        assert all(a.sort().eq(b.sort()) for a, b in pairs)
        self.size = len(pairs)
        self.old = (z3.Ast * self.size)(*(a.as_ast() for a, _ in pairs))
        self.new = (z3.Ast * self.size)(*(b.as_ast() for _, b in pairs))
        self.keep = pairs  # the arrays hold raw pointers: keep their owners alive

    def __call__(self, term: z3.ExprRef) -> z3.ExprRef:
        ctx = term.ctx
        return z3.z3._to_expr_ref(z3.Z3_substitute(ctx.ref(), term.as_ast(), self.size, self.old, self.new), ctx)


class Unroller:
    """The steps of one unrolling of `system`: configurations, moves and chosen values by step."""

    def __init__(self, system: TransitionSystem, tag: str = ""):
        self.system = system
        self.tag = tag  # prefixed to every name: two unrollings of one system side by side (`bmc.determinism`)
        self._frames: list[dict[str, z3.ExprRef]] = []
        self._actions: list[z3.ArithRef] = []
        self._inputs: dict[tuple[str, int], Value] = {}
        self._renamings: dict[int, tuple[int, _Renaming]] = {}
        self._axioms_given: dict[int, int] = {}  # step -> how many of the system's axioms were given for it
        self._seen: set[int] = set()

    def frame(self, k: int) -> dict[str, z3.ExprRef]:
        """The configuration at step k, as scalars by name."""
        while len(self._frames) <= k:
            i = len(self._frames)
            self._frames.append({n: z3.Const(f"{self.tag}{n}@{i}", s) for n, s in self.system.sorts.items()})
        return self._frames[k]

    def action(self, k: int) -> z3.ArithRef:
        """The index of the move taken at step k."""
        while len(self._actions) <= k:
            self._actions.append(z3.Int(f"{self.tag}act@{len(self._actions)}"))
        return self._actions[k]

    def input(self, name: str, k: int) -> Value:
        """The value named `name` chosen during step k."""
        key = (name, k)
        if key not in self._inputs:
            self._inputs[key] = fresh(f"{self.tag}{name}@{k}", self.system.inputs[name][0])
        return self._inputs[key]

    def at(self, term: z3.ExprRef, k: int) -> z3.ExprRef:
        """`term`, a formula over the template step, about step k instead."""
        return self._renaming(k)(term)

    def value_at(self, value: Value, k: int) -> Value:
        """A value (a term, or a record of them) over the template step, at step k."""
        if isinstance(value, dict):
            return {f: self.value_at(v, k) for f, v in value.items()}
        return self.at(value, k)

    def bool_at(self, term: z3.BoolRef, k: int) -> z3.BoolRef:
        return self.at(term, k)  # type: ignore[return-value]

    def axioms(self, k: int) -> list[z3.BoolRef]:
        """The function axioms of the formulas built so far, at step k, that were not given before.

        An axiom holds of the function at any argument, so giving each at every step is sound
        whether or not that step's formulas call the function there."""
        side = self.system.side
        done = self._axioms_given.get(k, 0)
        self._axioms_given[k] = len(side)
        out = []
        for a in side[done:]:
            renamed = self.bool_at(a, k)
            if renamed.get_id() not in self._seen:
                self._seen.add(renamed.get_id())
                out.append(renamed)
        return out

    def axioms_upto(self, k: int) -> list[z3.BoolRef]:
        """`axioms(j)` for every step j up to k."""
        return [a for j in range(k + 1) for a in self.axioms(j)]

    def _renaming(self, k: int) -> _Renaming:
        """What turns a formula about the template step into the same formula about step k."""
        known = len(self.system.inputs)  # a value first chosen after the last call is renamed too
        if k not in self._renamings or self._renamings[k][0] != known:
            s = self.system
            pairs: list[tuple[z3.ExprRef, z3.ExprRef]] = [(s.act, self.action(k))]
            for template, actual in ((s.cur, self.frame(k)), (s.nxt, self.frame(k + 1))):
                pairs += [(template[n], actual[n]) for n in s.sorts]
            for name, (_t, value) in s.inputs.items():
                pairs += zip((term for _, term in leaves(value)), (term for _, term in leaves(self.input(name, k))),
                             strict=True)
            self._renamings[k] = known, _Renaming(pairs)
        return self._renamings[k][1]
