"""Regions: the exact set of parameter values for which a target is reachable within a bound.

A parameter is a symbol every step shares: the bound of a range (`range[core_int].low`) or a
constant without a value.  The region is found by find, generalise, block: ask for a run that
reaches the target at depth k with the parameters outside the region found so far; project
the run's formula onto the parameters around the run's values (Z3's model-based projection),
which gives a cube of parameter values every point of which has such a run; add the cube to the
region and ask again.  When the question is unsatisfiable at every depth up to the bound, the
region is exact: inside it every point has a run to the target (a cube is an under-approximation
of the projection, never more), outside it none within the bound.  If time runs out first, what
was found is still inside, but the outside is not known (`Region.complete` is False).

The same machinery answers which values a field of an input can carry in some run of a given
length (`carried`): project onto a fresh symbol equal to the field at whichever step takes it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import z3

from tockbmc.bmc.engine import Clock, Progress, Status
from tockbmc.bmc.portfolio import decide
from tockbmc.encodings.system import Target, TransitionSystem
from tockbmc.encodings.terms import constants
from tockbmc.encodings.unroller import Unroller
from tockbmc.model.numbers import real_text

MAX_CUBES = 200  # cubes per region before giving up on exactness (a region that is many points, not a few intervals)


@dataclass
class Witness:
    """A run the search found: the unrolling, the model, and its depth."""

    unroller: Unroller
    model: z3.ModelRef
    depth: int


@dataclass
class Region:
    """Parameter values for which the target is reachable within the bound."""

    cubes: list[z3.BoolRef] = field(default_factory=list)  # each an under-approximation: all its points reach the target
    witnesses: list[Witness] = field(default_factory=list)  # one run per cube, in the order found
    complete: bool = False  # no point outside the cubes reaches the target within the bound
    reason: str = ""  # why it is not complete
    proof: str = ""  # when complete for every length, not only to the bound: how that was shown

    def formula(self) -> z3.BoolRef:
        return z3.Or(self.cubes) if self.cubes else z3.BoolVal(False)


def project(formula: z3.BoolRef, keep: Sequence[z3.ExprRef], model: z3.ModelRef) -> z3.BoolRef:
    """A cube over `keep` that holds in `model` and implies `formula` projected onto `keep`
    (every other symbol existentially quantified): Z3's model-based projection.  Symbols it cannot
    eliminate are fixed to their values in the model, which keeps the cube an under-approximation."""
    kept = {k.get_id() for k in keep}
    bound = [v for v in constants(formula) if v.get_id() not in kept]
    ctx = formula.ctx
    array = (z3.Ast * len(bound))(*(v.as_ast() for v in bound))
    cube = z3.z3._to_expr_ref(z3.Z3_qe_model_project(ctx.ref(), model.model, len(bound), array,  # noqa: SLF001
                                                     formula.as_ast()), ctx)
    left = [v for v in constants(cube) if v.get_id() not in kept]
    if left:  # not eliminated (an uninterpreted function's value, say): pinned as the model has it
        cube = z3.substitute(cube, *[(v, model.eval(v, model_completion=True)) for v in left])
    return z3.simplify(cube)  # type: ignore[return-value]


def region(system: Callable[[Sequence[z3.BoolRef]], TransitionSystem], target: Target, bound: int,
           params: Sequence[z3.ExprRef], assume: Sequence[z3.BoolRef] = (), timeout: float | None = None,
           induction: bool = True, progress: Progress | None = None) -> Region:
    """The parameter values (within `assume`) for which some run of up to `bound` steps reaches `target`.

    `system(outside)` builds the transition system with `outside` added to its constraints on
    constants: each round searches (`bmc.portfolio.decide`: BMC, k-induction, PDR) for a run
    outside the region found so far; what proves no run reaches the target there, for every
    length or to the bound, makes the region exact.
    """
    start = time.monotonic()
    found = Region()
    while True:
        left = None if timeout is None else timeout - (time.monotonic() - start)
        if left is not None and left <= 0:
            found.reason = "timed out"
            return found
        outside = [*assume, *(z3.Not(c) for c in found.cubes)]
        s = system(outside)
        outcome = decide(s, target, bound, left, induction, progress=progress)
        if outcome.status == Status.UNKNOWN:
            found.reason = outcome.reason or "unknown"
            return found
        if outcome.status != Status.FOUND:
            found.complete = True
            found.proof = (outcome.reason or "") if outcome.status == Status.PROVED else ""
            return found
        u, model = outcome.unroller, outcome.model
        assert u is not None and model is not None
        found.witnesses.append(Witness(u, model, outcome.depth))
        cube = project(z3.And(_path(u, outcome.depth, target)), params, model)
        found.cubes.append(cube)
        if z3.is_true(cube) or not params:  # every point reaches it
            found.complete = True
            return found
        if len(found.cubes) >= MAX_CUBES:
            found.reason = f"more than {MAX_CUBES} pieces"
            return found


def _path(u: Unroller, depth: int, target: Target) -> list[z3.BoolRef]:
    """A run of `depth` steps from the start to the target, as the unrolling `u` states it."""
    s = u.system
    return [u.at(s.init(), 0), *(u.bool_at(s.trans(), i) for i in range(depth)), u.bool_at(target(s), depth),
            *u.axioms_upto(depth)]


def carried(system: TransitionSystem, target: Target, depth: int,
            choices: Callable[[Unroller, int], list[tuple[z3.BoolRef, z3.ExprRef]]], assume: Sequence[z3.BoolRef] = (),
            timeout: float | None = None) -> Region:
    """The values a field takes in runs of exactly `depth` steps that reach `target`, at a step
    where one of `choices(u, i)` holds (a move, and the field's term at step i): a region over
    the symbol `value`."""
    clock = Clock(timeout)
    u = Unroller(system)
    sample = choices(u, 0)
    if not sample:
        return Region(complete=True)
    v = z3.FreshConst(sample[0][1].sort(), "carried")
    taken = [z3.And(when, v == value) for i in range(depth) for when, value in choices(u, i)]
    path = [*_path(u, depth, target), *assume, z3.Or(taken)]
    solver = z3.Solver()
    solver.add(*path)
    found = Region()
    formula = z3.And(path)
    while True:
        if not clock.arm(solver):
            found.reason = "timed out"
            return found
        result = solver.check()
        if result == z3.unsat:
            break
        if result == z3.unknown:
            found.reason = f"Z3 gave up: {solver.reason_unknown()}"
            return found
        cube = project(formula, [v], solver.model())
        found.cubes.append(z3.substitute(cube, (v, _placeholder(v))))
        if z3.is_true(cube):
            break
        if len(found.cubes) >= MAX_CUBES:
            found.reason = f"more than {MAX_CUBES} pieces"
            return found
        solver.add(z3.Not(cube))
    found.complete = True
    return found


def _placeholder(v: z3.ExprRef) -> z3.ExprRef:
    """The symbol a carried value's region speaks of (`value`), whatever fresh name the search gave it."""
    return z3.Const("value", v.sort())


# ----------------------------------------------------------------------------- for reading

Literal = tuple[dict[str, Fraction], str, Fraction]  # sum of coefficient * symbol, then <=, <, =, != and a number


def literals(cube: z3.BoolRef) -> list[z3.BoolRef]:
    """The conjuncts of a cube, nested conjunctions flattened."""
    out: list[z3.BoolRef] = []
    stack = [cube]
    while stack:
        t = stack.pop()
        if z3.is_and(t):
            stack.extend(reversed(t.children()))  # type: ignore[arg-type]
        elif not z3.is_true(t):
            out.append(t)
    return out


def simplified(cubes: Sequence[z3.BoolRef], assume: Sequence[z3.BoolRef], timeout_ms: int = 5000) -> list[list[z3.BoolRef]]:
    """The same region (under `assume`) as fewer cubes of fewer literals: each literal dropped whose
    cube, without it, stays inside the region; each cube dropped that the others cover.  A question
    Z3 does not answer in time keeps what it asked about, so the region never changes."""
    whole = z3.Or(list(cubes)) if cubes else z3.BoolVal(False)
    solver = z3.Solver()
    solver.set("timeout", timeout_ms)
    solver.add(*assume)

    def inside(cube: Sequence[z3.BoolRef], region: z3.BoolRef) -> bool:
        return solver.check(*cube, z3.Not(region)) == z3.unsat

    out: list[list[z3.BoolRef]] = []
    for cube in cubes:
        kept = [lit for lit in literals(cube) if not inside([], lit)]  # what `assume` implies says nothing
        for lit in list(kept):
            rest = [x for x in kept if x is not lit]
            if inside(rest, whole):
                kept = rest
        if kept not in out:
            out.append(kept)
    i = 0
    while i < len(out):
        others = [z3.And(c) if c else z3.BoolVal(True) for j, c in enumerate(out) if j != i]
        if others and inside(out[i], z3.Or(others)):
            out.pop(i)
        else:
            i += 1
    return out


def _linear(t: z3.ExprRef) -> tuple[dict[str, Fraction], Fraction] | None:
    """A linear term as coefficients by symbol name and a constant; None if it is not one."""
    if z3.is_int_value(t) or z3.is_rational_value(t):
        return {}, Fraction(t.as_fraction()) if z3.is_rational_value(t) else Fraction(t.as_long())  # type: ignore[attr-defined]
    if z3.is_const(t) and t.decl().kind() == z3.Z3_OP_UNINTERPRETED:
        return {t.decl().name(): Fraction(1)}, Fraction(0)
    if z3.is_app_of(t, z3.Z3_OP_TO_REAL):
        return _linear(t.arg(0))
    if z3.is_add(t) or z3.is_sub(t):
        parts = [_linear(a) for a in t.children()]
        if any(p is None for p in parts):
            return None
        coeffs: dict[str, Fraction] = {}
        const = Fraction(0)
        for n, (cs, c) in enumerate(p for p in parts if p is not None):
            sign = -1 if z3.is_sub(t) and n > 0 else 1
            for k, v in cs.items():
                coeffs[k] = coeffs.get(k, Fraction(0)) + sign * v
            const += sign * c
        return {k: v for k, v in coeffs.items() if v}, const
    if z3.is_mul(t):
        parts = [_linear(a) for a in t.children()]
        if any(p is None for p in parts):
            return None
        factor, term = Fraction(1), None
        for cs, c in (p for p in parts if p is not None):
            if not cs:
                factor *= c
            elif term is None:
                term = (cs, c)
            else:
                return None  # a product of symbols
        if term is None:
            return {}, factor
        return {k: v * factor for k, v in term[0].items()}, term[1] * factor
    if z3.is_app_of(t, z3.Z3_OP_UMINUS):
        p = _linear(t.arg(0))
        return None if p is None else ({k: -v for k, v in p[0].items()}, -p[1])
    return None


_FLIP = {"<=": ">", "<": ">=", ">=": "<", ">": "<=", "==": "!=", "!=": "=="}


def literal(lit: z3.BoolRef) -> Literal | None:
    """A comparison as `sum(coefficient * symbol) op number` with op one of <=, <, ==, != (None if
    it is not a linear comparison)."""
    negated = False
    while z3.is_not(lit):
        negated, lit = not negated, lit.arg(0)
    ops = {z3.Z3_OP_LE: "<=", z3.Z3_OP_LT: "<", z3.Z3_OP_GE: ">=", z3.Z3_OP_GT: ">", z3.Z3_OP_EQ: "=="}
    if not z3.is_app(lit) or lit.decl().kind() not in ops or lit.num_args() != 2:
        return None
    op = ops[lit.decl().kind()]
    if negated:
        op = _FLIP[op]
    left, right = _linear(lit.arg(0)), _linear(lit.arg(1))
    if left is None or right is None:
        return None
    coeffs = dict(left[0])
    for k, v in right[0].items():
        coeffs[k] = coeffs.get(k, Fraction(0)) - v
    coeffs = {k: v for k, v in coeffs.items() if v}
    const = right[1] - left[1]
    if op in (">=", ">"):  # as <= and <
        coeffs, const, op = {k: -v for k, v in coeffs.items()}, -const, "<=" if op == ">=" else "<"
    return coeffs, op, const


def condition_text(cubes: Sequence[Sequence[z3.BoolRef]], names: dict[str, str], integers: set[str]) -> str:
    """A region as text in the model's names: cubes joined by "or", literals by "and", one symbol's
    bounds as one interval (`-3 ≤ core_int.low ≤ -1`); `names` maps symbols to what to print,
    `integers` are the symbols whose strict bounds read better as `≤` (`x < 0` as `x ≤ -1`)."""
    if not cubes:
        return "false"
    texts = [_cube_text(c, names, integers) for c in cubes]
    if any(t == "true" for t in texts):
        return "true"
    if len(texts) == 1:
        return texts[0]
    return " or ".join(f"({t})" if " and " in t else t for t in texts)


def _cube_text(cube: Sequence[z3.BoolRef], names: dict[str, str], integers: set[str]) -> str:
    bounds: dict[str, list[tuple[str, Fraction]]] = {}
    others: list[str] = []
    for lit in cube:
        parsed = literal(lit)
        if parsed is None:
            others.append(term_text(lit, names, _BINDS[z3.Z3_OP_AND]))
            continue
        coeffs, op, const = parsed
        if len(coeffs) == 1:
            (sym, c), = coeffs.items()
            value = const / c
            if c < 0 and op in ("<=", "<"):
                op = ">=" if op == "<=" else ">"
            if sym in integers:
                op, value = _integer_bound(op, value)
            bounds.setdefault(sym, []).append((op, value))
        else:
            others.append(_relation_text(coeffs, op, const, names))
    parts = [_bounds_text(names.get(sym, sym), bs) for sym, bs in bounds.items()]
    return " and ".join([*parts, *others]) or "true"


def _integer_bound(op: str, value: Fraction) -> tuple[str, Fraction]:
    """A bound on an integer with `≤`/`≥` and a whole number: `x < 0` as `x ≤ -1`, `x ≥ 1/2` as `x ≥ 1`."""
    if op == "<":
        return "<=", Fraction(math.ceil(value) - 1)
    if op == ">":
        return ">=", Fraction(math.floor(value) + 1)
    if op == "<=":
        return "<=", Fraction(math.floor(value))
    if op == ">=":
        return ">=", Fraction(math.ceil(value))
    return op, value


_SHOW = {"<=": "≤", "<": "<", ">=": "≥", ">": ">", "==": "=", "!=": "≠"}


def _bounds_text(name: str, bounds: list[tuple[str, Fraction]]) -> str:
    lows = [(op, v) for op, v in bounds if op in (">=", ">")]
    highs = [(op, v) for op, v in bounds if op in ("<=", "<")]
    rest = [(op, v) for op, v in bounds if op in ("==", "!=")]
    low = max(lows, key=lambda b: (b[1], b[0] == ">")) if lows else None
    high = min(highs, key=lambda b: (b[1], b[0] == "<=")) if highs else None
    texts = []
    if low is not None and high is not None:
        if low[1] == high[1] and low[0] == ">=" and high[0] == "<=":
            texts.append(f"{name} = {real_text(low[1])}")
        else:
            texts.append(f"{real_text(low[1])} {_SHOW[_FLIP_SIDE[low[0]]]} {name} {_SHOW[high[0]]} {real_text(high[1])}")
    elif low is not None:
        texts.append(f"{name} {_SHOW[low[0]]} {real_text(low[1])}")
    elif high is not None:
        texts.append(f"{name} {_SHOW[high[0]]} {real_text(high[1])}")
    texts += [f"{name} {_SHOW[op]} {real_text(v)}" for op, v in rest]
    return " and ".join(texts)


_FLIP_SIDE = {">=": "<=", ">": "<"}


def _relation_text(coeffs: dict[str, Fraction], op: str, const: Fraction, names: dict[str, str]) -> str:
    """`sum(c * x) op const`, the positive terms on the left, the others and the number on the right."""
    if all(c < 0 for c in coeffs.values()):  # -x - y <= c  as  x + y >= -c
        coeffs, const = {k: -v for k, v in coeffs.items()}, -const
        op = {"<=": ">=", "<": ">", "==": "==", "!=": "!="}[op]

    def term(sym: str, c: Fraction) -> str:
        n = names.get(sym, sym)
        return n if c == 1 else f"{real_text(c)}·{n}"

    left = " + ".join(term(s, c) for s, c in coeffs.items() if c > 0)
    right = " + ".join(term(s, -c) for s, c in coeffs.items() if c < 0)
    if not right:
        right = real_text(const)
    elif const:
        right += f" - {real_text(-const)}" if const < 0 else f" + {real_text(const)}"
    return f"{left} {_SHOW[op]} {right}"


_INFIX = {z3.Z3_OP_LE: "≤", z3.Z3_OP_LT: "<", z3.Z3_OP_GE: "≥", z3.Z3_OP_GT: ">", z3.Z3_OP_EQ: "=",
          z3.Z3_OP_ADD: "+", z3.Z3_OP_SUB: "-", z3.Z3_OP_MUL: "·", z3.Z3_OP_DIV: "/", z3.Z3_OP_IDIV: "div",
          z3.Z3_OP_MOD: "mod", z3.Z3_OP_AND: "and", z3.Z3_OP_OR: "or", z3.Z3_OP_IMPLIES: "⇒"}
# How tightly each operator binds: an operand binding less tightly than its operator is parenthesised.
_BINDS = {z3.Z3_OP_IMPLIES: 0, z3.Z3_OP_OR: 1, z3.Z3_OP_AND: 2, z3.Z3_OP_NOT: 3,
          z3.Z3_OP_LE: 4, z3.Z3_OP_LT: 4, z3.Z3_OP_GE: 4, z3.Z3_OP_GT: 4, z3.Z3_OP_EQ: 4,
          z3.Z3_OP_ADD: 5, z3.Z3_OP_SUB: 5, z3.Z3_OP_MUL: 6, z3.Z3_OP_DIV: 6, z3.Z3_OP_IDIV: 6, z3.Z3_OP_MOD: 6,
          z3.Z3_OP_UMINUS: 7}
_NEGATED = {z3.Z3_OP_LE: ">", z3.Z3_OP_LT: "≥", z3.Z3_OP_GE: "<", z3.Z3_OP_GT: "≤", z3.Z3_OP_EQ: "≠"}


def term_text(t: z3.ExprRef, names: dict[str, str], context: int = -1) -> str:
    """Any other condition as text in the model's names (a disjunction inside a cube, a product of
    two symbols): the logical and arithmetic operators spelt out, a negated comparison turned
    round, parentheses only where an operand binds less tightly than its operator (`context`: how
    tightly the enclosing operator binds). What has no spelling here keeps Z3's."""
    if z3.is_int_value(t) or z3.is_rational_value(t):
        return real_text(Fraction(t.as_fraction()) if z3.is_rational_value(t) else Fraction(t.as_long()))  # type: ignore[attr-defined]
    if z3.is_true(t) or z3.is_false(t):
        return "true" if z3.is_true(t) else "false"
    if not z3.is_app(t):
        return str(t)
    kind = t.decl().kind()
    if z3.is_const(t) and kind == z3.Z3_OP_UNINTERPRETED:
        return names.get(t.decl().name(), t.decl().name())
    if kind == z3.Z3_OP_TO_REAL:
        return term_text(t.arg(0), names, context)
    if kind == z3.Z3_OP_NOT and t.arg(0).num_args() == 2 and t.arg(0).decl().kind() in _NEGATED:
        inner = t.arg(0)
        text = f"{term_text(inner.arg(0), names, 4)} {_NEGATED[inner.decl().kind()]} {term_text(inner.arg(1), names, 4)}"
        kind = z3.Z3_OP_LE  # binds as a comparison
    elif kind == z3.Z3_OP_NOT:
        text = f"not {term_text(t.arg(0), names, 3)}"
    elif kind == z3.Z3_OP_UMINUS:
        text = f"-{term_text(t.arg(0), names, 7)}"
    elif kind == z3.Z3_OP_ITE:
        text = " ".join(f"{w} {term_text(x, names)}" for w, x in zip(("if", "then", "else"), t.children(), strict=True))
        kind = z3.Z3_OP_IMPLIES  # parenthesised wherever it is an operand
    elif kind in _INFIX and t.num_args() >= 2:
        # the right operand of `-`, `/`, `div`, `mod` binds as if one level tighter (a - (b - c))
        tight = [_BINDS[kind] + (i > 0 and kind in (z3.Z3_OP_SUB, z3.Z3_OP_DIV, z3.Z3_OP_IDIV, z3.Z3_OP_MOD))
                 for i in range(t.num_args())]
        text = f" {_INFIX[kind]} ".join(term_text(x, names, b) for x, b in zip(t.children(), tight, strict=True))
    else:
        return str(t)
    return f"({text})" if _BINDS.get(kind, 8) < context or (_BINDS.get(kind, 8) == context and context == 4) else text
