"""The three readings of a model: what fills in what the model leaves unset (docs/semantics.md §6.6).

* `Reading.DEFAULT`: RoboTool's instantiation. A variable without an initial value starts at its
  type's default (RoboTool's generated memory starts there: 0, `true`, the first literal, a record
  of defaults, an empty sequence or set); a function without a body is RoboTool's placeholder
  (its generated `instantiations.csp` writes `f(…) = 0`, `true`, the first literal), unless the
  placeholder contradicts the function's own postcondition. Data stay unbounded and exact.
* `Reading.ROBOTOOL`: the same, over the finite instantiation FDR checks (`model/config.py`).
* `Reading.OPEN`: nothing is filled in: variables start anywhere, functions are any function
  meeting their contract, constants without a value are parameters.

`fill_unset` gives the project with the defaults written in, so that every engine, the replay and
every report read one model; each default is a `Filled`, listed with the results it bears on.
"""

from __future__ import annotations

import dataclasses
import sys
from dataclasses import dataclass, field
from enum import StrEnum
from fractions import Fraction

from tockbmc.model import ast
from tockbmc.model.contracts import placeholder_meets
from tockbmc.model.instantiation import replaced


class Reading(StrEnum):
    """Which meaning a check gives what the model leaves unset (a `str`: JSON prints its value)."""

    DEFAULT = "default"
    OPEN = "open"
    ROBOTOOL = "robotool"

    @property
    def not_reproduced(self) -> tuple[str, ...]:
        """What of the reading tockbmc does not reproduce yet: listed with every result."""
        return ROBOTOOL_NOT_REPRODUCED if self == Reading.ROBOTOOL else ()

    @property
    def summary(self) -> str:
        """One line for the results: what this reading fills in and over which data."""
        return {Reading.DEFAULT: "RoboTool's instantiation over unbounded, exact data",
                Reading.OPEN: "nothing unset filled in: every initial value, function and constant the model "
                              "leaves open",
                Reading.ROBOTOOL: "FDR's finite check: RoboTool's instantiation and default ranges"}[self]


# What `--robotool` does not reproduce of FDR's finite check (docs/robotool-evidence.md §9), listed
# with every result in that reading.
ROBOTOOL_NOT_REPRODUCED = (
    "RoboTool's widening of core_int, core_nat and core_real by the values the model's own expressions take "
    "(calc_type_min/calc_type_max): the default ranges are used as they are",
    "real literals with a fraction (0.5): exact here, where FDR's reals are integers",
    "a sequence the model computes is exact here at any length, where FDR stops with an error when one longer "
    "than 2 goes through a channel or variable of RoboTool's type LSeq(T,2)",
    "RoboTool's clock count, which stops one past the largest value since(C) is compared with: exact here, which "
    "decides every comparison alike but can differ where since(C) is used as a value; a model that compares it "
    "with 10 or more, which FDR refuses (core_clock_type = {0..10}), is checked here",
    "the functions the project's instantiation defines compute exactly, its Plus(a, b, T) and the like included",
    "RoboTool's memory model at its finest: an update reaches a copy between two steps of the machine (not "
    "between the read and the write of one assignment), and each variable's memory passes writes on by itself",
)


@dataclass(frozen=True)
class Filled:
    """Something the model leaves unset, and what the reading puts there.

    `value` is the default's text (`0`, `Status::noGas`), or "" where the function stays open;
    `source` says where the value comes from, or why the placeholder is not used."""

    kind: str  # "variable" | "function"
    name: str  # `S1::x`, `Chemical::analysis`
    value: str
    source: str
    pos: ast.Pos
    # the object of the filled project that carries it, to tell which checks reach it
    target: object = field(compare=False, repr=False, default=None)


ROBOTOOL_DEFAULT = "RoboTool default"
PLACEHOLDER = "RoboTool placeholder"


def default_value(t: ast.Type, pos: ast.Pos) -> ast.Expr | None:
    """RoboTool's default value of a type: 0, `true`, the first literal, a record or tuple of
    defaults, the empty sequence or set; None where RoboTool has none (a function, a string)."""
    if t in ast.NUMERIC or isinstance(t, ast.GivenType):
        return ast.Literal(ast.NAT if t != ast.REAL and not isinstance(t, ast.GivenType) else t, pos,
                           Fraction(0) if t == ast.REAL else 0)
    if t == ast.BOOLEAN:
        return ast.Literal(ast.BOOLEAN, pos, True)
    if isinstance(t, ast.EnumType) and t.literals:
        args = [default_value(pt, pos) for pt in t.parameters(t.literals[0])]
        if any(a is None for a in args):
            return None
        return ast.EnumLiteral(t, pos, t, t.literals[0], tuple(a for a in args if a is not None))
    if isinstance(t, ast.RecordType):
        fields = [(f.name, default_value(f.type, pos)) for f in t.fields]
        if all(v is not None for _, v in fields):
            return ast.RecordLiteral(t, pos, tuple((n, v) for n, v in fields if v is not None))
    if isinstance(t, ast.ProductType):
        parts = [default_value(p, pos) for p in t.parts]
        if all(p is not None for p in parts):
            return ast.TupleLiteral(t, pos, tuple(p for p in parts if p is not None))
    if isinstance(t, ast.SeqType):
        return ast.SeqLiteral(t, pos, ())
    if isinstance(t, ast.SetType):
        return ast.SetLiteral(t, pos, ())
    return None


def given_initial(v: ast.Variable) -> ast.Expr | None:
    """v's initial value where the model gives one other than its type's default: not one a
    reading filled in (`fill_unset` places the default at the declaration), nor a literal equal to
    the default."""
    if v.initial is None or v.initial.pos == v.pos:
        return None
    default = default_value(v.type, v.pos)
    if default is not None and describe_value(v.initial) == describe_value(default) != "an expression":
        return None
    return v.initial


def describe_value(e: ast.Expr) -> str:
    """A value as the report prints it."""
    if isinstance(e, ast.Literal):
        if isinstance(e.value, bool):
            return "true" if e.value else "false"
        if isinstance(e.value, Fraction):
            return str(e.value.numerator) if e.value.denominator == 1 else str(e.value)
        return str(e.value)
    if isinstance(e, ast.EnumLiteral):
        args = f"({', '.join(describe_value(a) for a in e.args)})" if e.args else ""
        return f"{e.enum.name}::{e.literal}{args}"
    if isinstance(e, ast.RecordLiteral):
        return "(" + ", ".join(f"{n}={describe_value(v)}" for n, v in e.fields) + ")"
    if isinstance(e, ast.TupleLiteral):
        return "(|" + ", ".join(describe_value(v) for v in e.items) + "|)"
    if isinstance(e, ast.SeqLiteral) and not e.items:
        return "<>"
    if isinstance(e, ast.SetLiteral) and not e.items:
        return "{}"
    if isinstance(e, ast.Unary) and e.op == "-":
        return f"-{describe_value(e.operand)}"
    return "an expression"


def _at(pos: ast.Pos) -> str:
    return f"{pos.path}:{pos.line}"


def _declared_variables(project: ast.Project) -> list[ast.Variable]:
    """Every variable a declaration of the model holds (machines', operations', controllers',
    platforms' and interfaces'), once each, in the model's order."""
    out: dict[int, ast.Variable] = {}
    holders: list[tuple[ast.Variable, ...]] = [i.variables for i in project.interfaces]
    holders += [b.variables for b in (*project.machines, *project.operations)]
    holders += [b.interface_variables for b in (*project.machines, *project.operations)]
    holders += [c.variables for c in project.controllers]
    holders += [p.variables for p in project.platforms]
    for m in project.modules:
        if m.platform is not None:
            holders.append(m.platform.variables)
    for c in project.controllers:
        holders += [op.operation.variables for op in c.operations]
    for vs in holders:
        for v in vs:
            if not v.constant and v.initial is None and v.kind in ("local", "interface"):
                out.setdefault(id(v), v)
    return list(out.values())


def fill_unset(project: ast.Project, unread: dict[str, ast.Pos] | None = None
               ) -> tuple[ast.Project, tuple[Filled, ...]]:
    """The project with RoboTool's instantiation written into what it leaves unset: each variable
    without an initial value given its type's default, each function without a body (whose result
    type is not generic) its placeholder where the placeholder meets the function's postconditions. The
    placeholder is total, as RoboTool's is: it replaces the function's preconditions too. A
    function the project's instantiation defines in a way not understood (`unread`, by qualified
    name, at the definition) stays open: its placeholder is not what the user wrote."""
    new: dict[int, object] = {}
    old: dict[int, object] = {}  # the parts filled or kept open, by id
    filled: list[tuple[str, str, str, str, ast.Pos, int]] = []  # kind, name, value, source, pos, id of the old object
    for v in _declared_variables(project):
        value = default_value(v.type, v.pos)
        if value is None:
            continue
        new[id(v)] = dataclasses.replace(v, initial=value)
        old[id(v)] = v
        filled.append(("variable", f"{v.owner}::{v.name}", describe_value(value),
                       f"{ROBOTOOL_DEFAULT} ({_at(v.pos)})", v.pos, id(v)))
    functions: dict[int, ast.Function] = {}
    originals = {f.qname: f for f in project.functions}
    for f in _functions(project):
        if f.definition is not None or ast.type_vars(f.result):
            continue
        old[id(f)] = f
        if f.unfolding_of:
            filled.append(("function", f.qname, "", f"kept open: {f.unfolding_of}'s calls nested deeper than its "
                                                    "unfolding", f.pos, id(f)))
            continue
        original = originals.get(f.qname.split("[", 1)[0])  # a generic function's copy for a call: `g[?X=int]`
        if original is not None and ast.type_vars(original.result):
            filled.append(("function", f.qname, "", "kept open: RoboTool's placeholder for a generic result type "
                                                    "is not evidenced", f.pos, id(f)))
            continue
        if f.qname in (unread or {}):
            filled.append(("function", f.qname, "", "kept open: the instantiation's definition at "
                                                    f"{_at((unread or {})[f.qname])} is not understood", f.pos, id(f)))
            continue
        value = default_value(f.result, f.pos)
        if value is None:
            filled.append(("function", f.qname, "", f"kept open: RoboTool has no placeholder of type {f.result}",
                           f.pos, id(f)))
            continue
        meets = placeholder_meets(f, value) if f.postconditions else True
        if meets is not True:
            why = "contradicts its postcondition" if meets is False else "is not shown to meet its postcondition"
            filled.append(("function", f.qname, "", f"kept open: the placeholder {describe_value(value)} {why} "
                                                    f"({_at(f.postconditions[0].pos)})", f.pos, id(f)))
            continue
        functions[id(f)] = dataclasses.replace(f, definition=value, preconditions=(), postconditions=())
        filled.append(("function", f.qname, describe_value(value), f"{PLACEHOLDER} ({_at(f.pos)})", f.pos, id(f)))
    new.update(functions)
    memo: dict[int, object] = {}
    out = project
    if new:
        limit = sys.getrecursionlimit()
        sys.setrecursionlimit(max(limit, 20_000))
        try:
            out = replaced(project, new, memo)
        finally:
            sys.setrecursionlimit(limit)
    return out, tuple(Filled(k, n, val, s, p, memo.get(key, old[key])) for k, n, val, s, p, key in filled)


def _functions(project: ast.Project) -> list[ast.Function]:
    """Every function the project holds: its declarations, and the copies of generic functions
    made for their calls (`g[?X=int]`), in the order of their names."""
    found = {id(f): f for f in ast.parts(project) if isinstance(f, ast.Function)}
    return sorted(found.values(), key=lambda f: f.qname)


def reached(filled: tuple[Filled, ...], *roots: object) -> tuple[Filled, ...]:
    """The defaults that the model elements `roots` reach (hold or call), in `filled`'s order."""
    wanted = {id(f.target) for f in filled if f.target is not None}
    found = {id(item) for item in ast.parts(*roots) if id(item) in wanted}
    return tuple(f for f in filled if id(f.target) in found)


_ARITHMETIC = ("+", "-", "*", "/", "%")


def bounded_arithmetic(project: ast.Project, ranges: dict[str, tuple[Fraction, Fraction]],
                       written: frozenset[str] = frozenset()) -> ast.Project:
    """The project with RoboTool's bounded arithmetic written into the model's expressions (its
    machines, operations, controllers and functions; not the CSP blocks, which are CSP already, nor
    the functions the project's instantiation defines, `written` by qualified name, whose CSP
    arithmetic is exact):
    `a + b` of a type whose range `ranges` gives (`core_int`, `core_nat`, `core_real`) is

        if lo <= a + b <= hi then a + b else a        (RoboTool's `Plus(a, b, T)`)

    and likewise `-`, `*`, `/`, `%` and the negation `-a` (`if lo <= -a <= hi then -a else a`),
    with `/` and `%` on integers rounding towards zero, as FDR's do."""
    found: list[ast.Expr] = []
    seen: set[int] = set()
    stack: list[object] = [project.machines, project.operations, project.controllers, project.functions,
                           project.modules, project.interfaces, project.platforms]
    while stack:
        item = stack.pop()
        if isinstance(item, (str, int, float, bool, Fraction, ast.Pos, ast.Type)) or item is None or id(item) in seen:
            continue
        seen.add(id(item))
        if isinstance(item, (tuple, list)):
            stack.extend(item)
        elif isinstance(item, ast.Function) and item.qname in written:
            continue
        elif dataclasses.is_dataclass(item) and not isinstance(item, type):
            if _bounded(item, ranges) is not None:
                found.append(item)  # type: ignore[arg-type]
            stack.extend(getattr(item, f.name) for f in dataclasses.fields(item) if f.compare)
    bounds = tuple((name, low, high) for name, (low, high) in sorted(ranges.items()))
    if not found:
        return dataclasses.replace(project, arithmetic=bounds)
    new: dict[int, object] = {}
    for e in found:
        low_high = _bounded(e, ranges)
        assert low_high is not None
        new[id(e)] = _robotool_op(e, *low_high)
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 20_000))
    try:
        return dataclasses.replace(replaced(project, new, {}), arithmetic=bounds)
    finally:
        sys.setrecursionlimit(limit)


_RANGE_OF = {ast.INT: "core_int", ast.NAT: "core_nat", ast.REAL: "core_real"}


def _bounded(e: object, ranges: dict[str, tuple[Fraction, Fraction]]) -> tuple[Fraction, Fraction] | None:
    """The range RoboTool's arithmetic keeps `e` in, if `e` is arithmetic of a bounded type."""
    arithmetic = isinstance(e, ast.Binary) and e.op in _ARITHMETIC or isinstance(e, ast.Unary) and e.op == "-"
    if not arithmetic:
        return None
    assert isinstance(e, (ast.Binary, ast.Unary))
    name = _RANGE_OF.get(e.type) if isinstance(e.type, ast.PrimitiveType) else None
    return ranges.get(name) if name is not None else None


def _literal(t: ast.Type, pos: ast.Pos, x: Fraction | int) -> ast.Literal:
    return ast.Literal(t, pos, Fraction(x) if t == ast.REAL else int(x))


def _robotool_op(e: ast.Expr, low: Fraction, high: Fraction) -> ast.Expr:
    """`e` as RoboTool's generated helper computes it (see `bounded_arithmetic`)."""
    t, pos = e.type, e.pos
    if isinstance(e, ast.Unary):
        exact: ast.Expr = dataclasses.replace(e)  # a new node: the old one maps to what this returns
        first = e.operand
    else:
        assert isinstance(e, ast.Binary)
        if e.op in ("/", "%"):
            exact = _towards_zero(e) if t != ast.REAL else _real_towards_zero(e)
        else:
            exact = dataclasses.replace(e)
        first = e.left
    inside = ast.Binary(ast.BOOLEAN, pos, "and", ast.Binary(ast.BOOLEAN, pos, "<=", _literal(t, pos, low), exact),
                        ast.Binary(ast.BOOLEAN, pos, "<=", exact, _literal(t, pos, high)))
    return ast.IfExpr(t, pos, inside, exact, first)


def _real_towards_zero(e: ast.Binary) -> ast.Expr:
    """Real `a / b` and `a % b` as FDR computes them: its reals are integers (`core_real` is a set
    of integers), so the quotient is rounded towards zero and the remainder is `a - b * q`."""
    t, pos, a, b = e.type, e.pos, e.left, e.right
    quotient = ast.Unary(t, pos, "trunc", ast.Binary(t, pos, "/", a, b))
    if e.op == "/":
        return quotient
    return ast.Binary(t, pos, "-", a, ast.Binary(t, pos, "*", b, quotient))


def _towards_zero(e: ast.Binary) -> ast.Expr:
    """Integer `a / b` and `a % b` as FDR computes them (the quotient rounded towards zero, the
    remainder of `a`'s sign), from tockbmc's Euclidean ones (remainder never negative): they differ
    only where `a` is negative and `b` does not divide it."""
    t, pos, a, b = e.type, e.pos, e.left, e.right
    zero = _literal(t, pos, 0)
    euclid_q = ast.Binary(t, pos, "/", a, b)
    euclid_r = ast.Binary(t, pos, "%", a, b)
    differs = ast.Binary(ast.BOOLEAN, pos, "and", ast.Binary(ast.BOOLEAN, pos, "<", a, zero),
                         ast.Binary(ast.BOOLEAN, pos, "!=", euclid_r, zero))
    if e.op == "/":
        step = ast.IfExpr(t, pos, ast.Binary(ast.BOOLEAN, pos, ">", b, zero), _literal(t, pos, 1), _literal(t, pos, -1))
        return ast.IfExpr(t, pos, differs, ast.Binary(t, pos, "+", euclid_q, step), euclid_q)
    # the remainder of a's sign: a - b * trunc(a / b) = r - |b| where a < 0 and r != 0
    size = ast.IfExpr(t, pos, ast.Binary(ast.BOOLEAN, pos, ">", b, zero), b, ast.Unary(t, pos, "-", b))
    return ast.IfExpr(t, pos, differs, ast.Binary(t, pos, "-", euclid_r, size), euclid_r)
