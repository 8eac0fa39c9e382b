"""Model values and expressions as Z3 terms.

A value is a Z3 term for a scalar, or a dict from field name to value for a
record.  Integers and naturals are Z3 integers, reals are Z3 reals (exact),
enumerations and given types are integers (enumeration literal i is i).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Union

import z3

from tockbmc.encodings.automaton import entry_clock
from tockbmc.model import ast
from tockbmc.model.errors import Unsupported
from tockbmc.model.ranges import TYPE_RANGE_NAMES, Range, Ranges, is_path

__all__ = ["TYPE_RANGE_NAMES", "Range", "Ranges", "Value"]  # the ranges are the model layer's; re-exported

Value = Union[z3.ExprRef, dict[str, "Value"]]




def sort_of(t: ast.Type) -> z3.SortRef:
    """The Z3 sort of a value of `t` kept in one term: sequences are Z3 sequences, sets arrays to
    booleans (Z3's sets), records and tuples (inside sequences and sets, and as arguments of
    uninterpreted functions) a datatype with one constructor."""
    if t == ast.BOOLEAN:
        return z3.BoolSort()
    if t == ast.REAL:
        return z3.RealSort()
    if isinstance(t, ast.EnumType) and t.params:
        return _variants(t)
    if t in (ast.INT, ast.NAT) or isinstance(t, (ast.EnumType, ast.GivenType)):
        return z3.IntSort()
    if isinstance(t, ast.SeqType):
        return z3.SeqSort(sort_of(t.element))
    if isinstance(t, ast.SetType):
        return z3.SetSort(sort_of(t.element))
    if isinstance(t, (ast.RecordType, ast.ProductType)):
        return _datatype(t)
    if isinstance(t, ast.FunctionType):  # a Z3 array: a total function, equal when equal everywhere
        return z3.ArraySort(sort_of(t.domain), sort_of(t.range))
    raise Unsupported(ast.Pos("<model>", 1, 1), f"values of type {t} are not encoded yet")


def _datatype(t: ast.RecordType | ast.ProductType) -> z3.DatatypeSortRef:
    """The datatype of a record or tuple type in the current Z3 context, made once per context.

    The sorts are kept on the context object itself, so they live and die with it (each check has a
    context of its own), rather than in a module-level table that would keep every context alive."""
    ctx = z3.main_ctx()
    kept: dict[ast.Type, z3.DatatypeSortRef] = ctx.__dict__.setdefault("tockbmc_datatypes", {})
    if t not in kept:
        name = _qualified(t)
        dt = z3.Datatype(name)
        dt.declare(f"mk {name}", *[(f"{name}.{f}", sort_of(ft)) for f, ft in parts(t)])
        kept[t] = dt.create()
    return kept[t]


def _variants(t: ast.EnumType) -> z3.DatatypeSortRef:
    """An enumeration with parameterised literals as a Z3 datatype: one constructor per literal, in
    declaration order, whose fields are the literal's parameters (`EM3(nat)`: `EM3` with field
    `EM3.1`); made once per context, as `_datatype`'s are."""
    ctx = z3.main_ctx()
    kept: dict[object, z3.DatatypeSortRef] = ctx.__dict__.setdefault("tockbmc_datatypes", {})
    key = (t, t.params)  # `params` is left out of an EnumType's equality
    if key not in kept:
        dt = z3.Datatype(t.qname)
        for lit, params in zip(t.literals, t.params, strict=True):
            dt.declare(f"{t.qname}::{lit}", *[(f"{t.qname}::{lit}.{i}", sort_of(pt)) for i, pt in enumerate(params, 1)])
        kept[key] = dt.create()
    return kept[key]


def variant(t: ast.EnumType, literal: str, args: list[Value]) -> z3.ExprRef:
    """The value `literal(args…)` of an enumeration with parameterised literals."""
    i = t.literals.index(literal)
    return _variants(t).constructor(i)(*[pack(a, pt) for a, pt in zip(args, t.params[i], strict=True)])


def _qualified(t: ast.Type) -> str:
    """A type's name with every declared type in it qualified (two packages' `ID * ID` differ)."""
    if isinstance(t, ast.ProductType):
        return "(" + "*".join(_qualified(p) for p in t.parts) + ")"
    if isinstance(t, (ast.SeqType, ast.SetType)):
        return f"{'Seq' if isinstance(t, ast.SeqType) else 'Set'}({_qualified(t.element)})"
    if isinstance(t, ast.FunctionType):
        return f"({_qualified(t.domain)} -> {_qualified(t.range)})"
    return getattr(t, "qname", t.name)


def parts(t: ast.Type) -> list[tuple[str, ast.Type]]:
    """The fields of a record type, or the parts of a tuple type named "1", "2", … (else none)."""
    if isinstance(t, ast.RecordType):
        return [(f.name, f.type) for f in t.fields]
    if isinstance(t, ast.ProductType):
        return [(str(i), pt) for i, pt in enumerate(t.parts, 1)]
    return []


def pack(v: Value, t: ast.Type) -> z3.ExprRef:
    """A value as one term of `sort_of(t)` (a record's or tuple's fields into its datatype)."""
    if isinstance(v, dict):
        sort = sort_of(t)
        assert isinstance(sort, z3.DatatypeSortRef)
        return sort.constructor(0)(*[pack(v[f], ft) for f, ft in parts(t)])
    if t == ast.REAL:
        return _to_real(v)
    return v


def unpack(x: z3.ExprRef, t: ast.Type) -> Value:
    """The value of a term of `sort_of(t)`: records and tuples as dicts of their fields."""
    fs = parts(t)
    if not fs:
        return x
    sort = sort_of(t)
    assert isinstance(sort, z3.DatatypeSortRef)
    return {f: unpack(sort.accessor(0, i)(x), ft) for i, (f, ft) in enumerate(fs)}


def as_type(v: Value, t: ast.Type, pos: ast.Pos) -> Value:
    """`v` with its integers made reals where `t` has reals (an integer sent on a real event, a
    `Seq(nat)` cast to a `Seq(real)`: `widened`); `pos` is the expression's, for `Unsupported`."""
    if isinstance(v, dict):
        return {f: as_type(v[f], ft, pos) for f, ft in parts(t)} if parts(t) else v
    return widened(v, t, pos)


def widened(x: z3.ExprRef, t: ast.Type, pos: ast.Pos) -> z3.ExprRef:
    """The term `x` as one of `sort_of(t)`, its integers made reals where `t` has reals (the
    checker casts only where `ast.widens` holds): a real `ToReal(x)`; a sequence its items mapped,
    `SeqMap(lambda y @ widened(y), x)`; a tuple part by part; a set the reals that are its
    integers, `lambda r @ is_int(r) and x[to_int(r)]` (`_preimage`)."""
    target = sort_of(t)
    if x.sort() == target:
        return x
    if t == ast.REAL:
        return z3.ToReal(x)
    if isinstance(t, ast.SeqType):
        sort = x.sort()
        assert isinstance(sort, z3.SeqSortRef)
        y = z3.FreshConst(sort.basis(), "widen!item")
        return z3.SeqMap(z3.Lambda([y], widened(y, t.element, pos)), x)
    if isinstance(t, ast.SetType):
        sort = x.sort()
        assert isinstance(sort, z3.ArraySortRef)
        r = z3.FreshConst(sort_of(t.element), "widen!member")
        inside, source = _preimage(r, sort.domain(), t.element, pos)
        return z3.Lambda([r], z3.And(inside, z3.Select(x, source)))
    if isinstance(t, ast.ProductType):
        sort, dt = x.sort(), _datatype(t)
        assert isinstance(sort, z3.DatatypeSortRef)
        return dt.constructor(0)(*[widened(sort.accessor(0, i)(x), pt, pos) for i, pt in enumerate(t.parts)])
    raise Unsupported(pos, f"a value of sort {x.sort()} cast to {t}")  # pragma: no cover - `ast.widens` builds none


def _preimage(y: z3.ExprRef, sort: z3.SortRef, t: ast.Type, pos: ast.Pos) -> tuple[z3.BoolRef, z3.ExprRef]:
    """For `y` of `sort_of(t)`: whether it is `widened(x, t)` for some `x` of `sort`, and that `x`
    (`widened` is one to one): a real that is an integer, a tuple whose parts are."""
    if y.sort() == sort:
        return z3.BoolVal(True), y
    if t == ast.REAL:
        assert isinstance(y, z3.ArithRef)
        return z3.IsInt(y), z3.ToInt(y)
    if isinstance(t, ast.ProductType) and isinstance(sort, z3.DatatypeSortRef):
        dt = _datatype(t)
        found = [_preimage(dt.accessor(0, i)(y), sort.accessor(0, i).range(), pt, pos) for i, pt in enumerate(t.parts)]
        return z3.And([c for c, _ in found]), sort.constructor(0)(*[x for _, x in found])
    # a member of a set of sequences (or sets) made reals is one all of whose items are integers:
    # a quantifier over each member's items, which tockbmc does not build
    raise Unsupported(pos, f"a set whose members' integers are made reals inside sequences or sets (members of "
                           f"type {t}): tockbmc converts sets of numbers and of tuples of numbers only")


def fresh(name: str, t: ast.Type) -> Value:
    """A fresh symbolic value of type `t`."""
    if parts(t):
        return {f: fresh(f"{name}.{f}", ft) for f, ft in parts(t)}
    return z3.Const(name, sort_of(t))


def leaves(v: Value, prefix: str = "") -> list[tuple[str, z3.ExprRef]]:
    """The scalar parts of a value with their field paths (`.dist`, `.time`)."""
    if isinstance(v, dict):
        out: list[tuple[str, z3.ExprRef]] = []
        for k in v:
            out += leaves(v[k], f"{prefix}.{k}")
        return out
    return [(prefix, v)]


def leaf_type(t: ast.Type, path: str) -> ast.Type:
    """The type of the scalar at field path `path` (`.dist`) of a value of type `t`."""
    for part in [p for p in path.split(".") if p]:
        t = dict(parts(t))[part]
    return t


def equal(a: Value, b: Value) -> z3.BoolRef:
    if isinstance(a, dict) and isinstance(b, dict):
        return z3.And([equal(a[k], b[k]) for k in a if k in b])
    assert not isinstance(a, dict) and not isinstance(b, dict)
    return _coerce_eq(a, b)


def _coerce_eq(a: z3.ExprRef, b: z3.ExprRef) -> z3.BoolRef:
    if a.sort() != b.sort() and z3.is_arith(a) and z3.is_arith(b):
        a, b = _to_real(a), _to_real(b)
    return a == b


def _to_real(x: z3.ExprRef) -> z3.ExprRef:
    return z3.ToReal(x) if x.sort() == z3.IntSort() else x


def initially(v: Value, t: ast.Type, expr: ast.Expr, ev: Evaluator, ranges: Ranges, path: str) -> list[z3.BoolRef]:
    """Constraints making `v` the initial value `expr` of a place of type `t`: a record literal's
    omitted fields take any value of their type and range (`path`'s), as a place without one does."""
    if isinstance(expr, ast.RecordLiteral) and expr.omitted:
        assert isinstance(v, dict)
        given = dict(expr.fields)
        return [c for f, ft in parts(t)
                for c in ([equal(v[f], as_type(ev.value(given[f]), ft, given[f].pos)), *fits(v[f], ft)] if f in given
                          else domain(v[f], ft, ranges, f"{path}.{f}"))]
    return [equal(v, ev.value(expr)), *fits(v, t)]


# Terms already known to be values of a type (a place's value before the step: `stored`), by
# Z3's id of the term, with the term kept alive beside its type.
Stored = dict[int, tuple[z3.ExprRef, ast.Type]]


def stored(values: Iterable[tuple[Value, ast.Type]]) -> Stored:
    """`fits`'s table of the values places hold, each in its place's type already."""
    out: Stored = {}
    for v, t in values:
        for path, term in leaves(v):
            out[term.get_id()] = (term, leaf_type(t, path))
    return out


def fits(v: Value, t: ast.Type, known: Stored | None = None, length: int | None = None) -> list[z3.BoolRef]:
    """That a value the model computes may be stored in a place of type `t`: a `nat` is not
    negative, in a record's fields, a tuple's parts, an enumeration literal's parameters and a
    sequence's or set's items too (as the explicit engine's `_fits`). `known` holds values already
    of their type, which a new sequence or set built from them need not check again; `length`
    bounds a sequence's length (its range), whose items are then checked one by one."""
    if parts(t):
        assert isinstance(v, dict)
        return [c for f, ft in parts(t) for c in fits(v[f], ft, known)]
    if t == ast.NAT:
        assert isinstance(v, z3.ArithRef)
        return [v >= 0]
    if isinstance(t, ast.EnumType) and t.params:
        sort = _variants(t)
        out: list[z3.BoolRef] = []
        for i, params in enumerate(t.params):
            inner = [c for j, pt in enumerate(params) for c in fits(unpack(sort.accessor(i, j)(v), pt), pt)]
            if inner:
                out.append(z3.Implies(sort.recognizer(i)(v), z3.And(inner)))
        return out
    if isinstance(t, (ast.SeqType, ast.SetType)) and _checked(t.element):
        assert isinstance(v, z3.ExprRef)
        return _items_fit(v, t, known or {}, length)
    return []


def _checked(t: ast.Type) -> bool:
    """Whether some value of `t`'s sort is not a value of `t` for `fits`."""
    if t == ast.NAT:
        return True
    if isinstance(t, (ast.SeqType, ast.SetType)):
        return _checked(t.element)
    if isinstance(t, ast.EnumType):
        return any(_checked(pt) for params in t.params for pt in params)
    return any(_checked(ft) for _, ft in parts(t))


def _items_fit(v: z3.ExprRef, t: ast.SeqType | ast.SetType, known: Stored,
               length: int | None = None) -> list[z3.BoolRef]:
    """`fits` for a sequence or set, by how the term was built: a concatenation's or union's
    parts, a unit's item, a set with an item added, an `If`'s branches, each checked down to values
    already of the type; a part of one value (a slice, a difference, a set without an item, a
    reverse or filter: folds that only move items) needs no check where that value needs none.
    Otherwise by a quantifier over the items (one by one, within `length`)."""
    kind = v.decl().kind() if z3.is_app(v) else None
    args = v.children()
    if v.get_id() in known and known[v.get_id()][1] == t:
        return []
    if kind == z3.Z3_OP_SEQ_EMPTY or (kind == z3.Z3_OP_CONST_ARRAY and z3.is_false(args[0])):
        return []
    if kind == z3.Z3_OP_UNINTERPRETED and v.decl().name() == f"{UPDATE_OUTSIDE}:{_qualified(t)}":
        return []  # `s[i] = e` outside 1..#s: any sequence of s's type (`Evaluator._update_outside`'s axiom)
    if kind == z3.Z3_OP_SEQ_UNIT:
        return fits(unpack(args[0], t.element), t.element, known)
    if kind in (z3.Z3_OP_SEQ_CONCAT, z3.Z3_OP_SET_UNION):
        return [c for a in args for c in _items_fit(a, t, known)]
    if kind == z3.Z3_OP_ITE:
        then, other = _items_fit(args[1], t, known), _items_fit(args[2], t, known)
        return [z3.If(args[0], z3.And(then), z3.And(other))] if then or other else []
    added = kind == z3.Z3_OP_STORE and isinstance(t, ast.SetType) and z3.is_true(args[2])
    if added:
        return _items_fit(args[0], t, known) + fits(unpack(args[1], t.element), t.element, known)
    removed = kind == z3.Z3_OP_STORE and isinstance(t, ast.SetType) and z3.is_false(args[2])
    if (kind in (z3.Z3_OP_SEQ_EXTRACT, z3.Z3_OP_SET_DIFFERENCE) or removed) and not _items_fit(args[0], t, known):
        return []
    if kind == z3.Z3_OP_SET_INTERSECT and any(not _items_fit(a, t, known) for a in args):
        return []
    if kind in (z3.Z3_OP_SEQ_FOLDL, z3.Z3_OP_SEQ_FOLDLI) and _moves_items(args[0]) and \
            not _items_fit(args[-1], t, known):
        return _items_fit(args[-2], t, known)  # the items of the start value and of the folded one
    return _every_item(v, t, length)


def folds(v: Value) -> bool:
    """Whether a value's terms fold a sequence (`reverse`, `filter`, `extract`, …)."""
    seen: set[int] = set()
    stack = [term for _, term in leaves(v)]
    while stack:
        t = stack.pop()
        if t.get_id() in seen:
            continue
        seen.add(t.get_id())
        if z3.is_app(t) and t.decl().kind() in (z3.Z3_OP_SEQ_FOLDL, z3.Z3_OP_SEQ_FOLDLI):
            return True
        stack += t.children()
    return False


def kept_items(v: z3.ExprRef, t: ast.SeqType | ast.SetType) -> list[z3.BoolRef]:
    """That every item of a sequence or set `v` of type `t` is of its item's type (for `fits`:
    `nat` items not negative), none where every value of the sort is."""
    return _every_item(v, t) if _checked(t.element) else []


def _every_item(v: z3.ExprRef, t: ast.SeqType | ast.SetType, length: int | None = None) -> list[z3.BoolRef]:
    """That every item of `v` fits `t`'s item type: one by one within `length`, else a quantifier."""
    if isinstance(t, ast.SeqType):
        if length is not None and length < UNROLLED_LENGTH:
            return [z3.Implies(z3.Length(v) > k, z3.And(fits(unpack(v[k], t.element), t.element)))
                    for k in range(max(0, length))]
        i = z3.FreshInt("item")
        inner = fits(unpack(v[i], t.element), t.element)
        return [z3.ForAll([i], z3.Implies(z3.And(i >= 0, i < z3.Length(v)), z3.And(inner)))]
    x = z3.FreshConst(sort_of(t.element), "item")
    inner = fits(unpack(x, t.element), t.element)
    return [z3.ForAll([x], z3.Implies(z3.IsMember(x, v), z3.And(inner)))]


def _moves_items(f: z3.ExprRef) -> bool:
    """Whether a fold's function `lambda (i,) acc, x @ …` only puts items `x` into the accumulator
    (`reverse`, `filter`, `extract`): its result's items are the start value's and the sequence's."""
    def moves(b: z3.ExprRef) -> bool:
        if z3.is_var(b):
            return z3.get_var_index(b) == 1  # the accumulator
        kind = b.decl().kind() if z3.is_app(b) else None
        if kind == z3.Z3_OP_SEQ_UNIT:
            return z3.is_var(b.arg(0)) and z3.get_var_index(b.arg(0)) == 0  # the item
        if kind == z3.Z3_OP_SEQ_CONCAT:
            return all(moves(c) for c in b.children())
        if kind == z3.Z3_OP_ITE:
            return moves(b.arg(1)) and moves(b.arg(2))
        return kind == z3.Z3_OP_SEQ_EMPTY
    return z3.is_quantifier(f) and f.is_lambda() and moves(f.body())


def domain(v: Value, t: ast.Type, ranges: Ranges, path: str) -> list[z3.BoolRef]:
    """Constraints on a value the environment chooses: its type's domain and any ranges."""
    if parts(t):
        assert isinstance(v, dict)
        return [c for f, ft in parts(t) for c in domain(v[f], ft, ranges, f"{path}.{f}")]
    assert not isinstance(v, dict)
    cs: list[z3.BoolRef] = []
    if isinstance(t, (ast.SeqType, ast.SetType)):
        return _container_domain(v, t, ranges, path)
    if isinstance(t, ast.FunctionType):
        # Its results are in their type at each point a run applies it (`Evaluator._apply`), as an
        # uninterpreted function's are: exact, since only applied points matter, and free of the
        # quantifier `forall x @ f(x) in T`, on which Z3 timed out at depth 2 (LambdaExpVarTest).
        return []
    if isinstance(t, ast.EnumType) and t.params:
        # Each literal's parameters in their types and ranges, when the value is that literal.
        sort = _variants(t)
        for i, (lit, params) in enumerate(zip(t.literals, t.params, strict=True)):
            inner = [c for j, pt in enumerate(params)
                     for c in domain(unpack(sort.accessor(i, j)(v), pt), pt, ranges, f"{path}.{lit}.{j + 1}")]
            if inner:
                cs.append(z3.Implies(sort.recognizer(i)(v), z3.And(inner)))
        return cs
    if t == ast.NAT:
        cs.append(v >= 0)
    if t == ast.REAL and ranges.integral_reals and z3.is_real(v):
        cs.append(z3.IsInt(v))
    if isinstance(t, ast.EnumType):
        cs += [v >= 0, v < len(t.literals)]
    if not z3.is_arith(v):
        return cs
    name = TYPE_RANGE_NAMES.get(t.name, t.name) if isinstance(t, ast.PrimitiveType) else t.name
    for bounded in (path, name):
        if bounded in ranges.parametric:
            low, high = range_bounds(bounded, v.sort())
            cs += [v >= low, v <= high]
        else:
            r = ranges.by_path.get(path) if bounded == path else ranges.by_type.get(name)
            if r is None:
                continue
            cs += [v >= _const(r.low, v.sort()), v <= _const(r.high, v.sort())]
        if not isinstance(t, ast.GivenType):
            return cs  # a path's range replaces its type's
        # A given type's range is the type (RoboTool's `nametype T = {0..2}`): a path's range
        # narrows it, and every value of the type is in it (`_set_size` counts on it).
    return cs


def given_types(ranges: Ranges) -> Ranges:
    """The ranges of given types alone (`type T`): what bounds a function's result, which is a value
    of its type (a number's result is any number: only the environment's choices are bounded)."""
    core = set(TYPE_RANGE_NAMES.values())
    return Ranges({k: r for k, r in ranges.by_type.items() if k not in core},
                  parametric=tuple(k for k in ranges.parametric if k not in core and not is_path(k)))


def range_bounds(name: str, sort: z3.SortRef) -> tuple[z3.ArithRef, z3.ArithRef]:
    """The lower and upper bound of a parametric range, as symbols (the same at every step)."""
    return z3.Const(f"range[{name}].low", sort), z3.Const(f"range[{name}].high", sort)  # type: ignore[return-value]


UNROLLED_LENGTH = 16  # a sequence whose length range ends below this has its items constrained one by one


def _container_domain(v: z3.ExprRef, t: ast.SeqType | ast.SetType, ranges: Ranges, path: str) -> list[z3.BoolRef]:
    """A sequence's or set's elements in their type's domain (a quantified constraint); a range
    on the sequence's own path bounds its length, else the default length if any (`Ranges.length`)."""
    cs: list[z3.BoolRef] = []
    if isinstance(t, ast.SeqType):
        r = ranges.length((path,))
        if r is not None:
            cs += [z3.Length(v) >= _const(r.low, z3.IntSort()), z3.Length(v) <= _const(r.high, z3.IntSort())]
        if r is not None and r.high < UNROLLED_LENGTH:
            # A short sequence's items one by one: no quantifier, which under the universal of a
            # refusal ("no value of d is accepted") left Z3 without an answer at depth 1.
            for k in range(max(0, math.floor(r.high)) + 1):
                inner = domain(unpack(v[k], t.element), t.element, ranges, f"{path}[]")
                if inner:
                    cs.append(z3.Implies(z3.Length(v) > k, z3.And(inner)))
            return cs
        i = z3.Int(f"{path}!i")
        inner = domain(unpack(v[i], t.element), t.element, ranges, f"{path}[]")
        if inner:
            cs.append(z3.ForAll([i], z3.Implies(z3.And(i >= 0, i < z3.Length(v)), z3.And(inner))))
        return cs
    x = z3.Const(f"{path}!x", sort_of(t.element))
    inner = domain(unpack(x, t.element), t.element, ranges, f"{path}[]")
    if inner:
        cs.append(z3.ForAll([x], z3.Implies(z3.IsMember(x, v), z3.And(inner))))
    return cs


def _const(x: Fraction, sort: z3.SortRef) -> z3.ExprRef:
    if sort == z3.IntSort():
        return z3.IntVal(int(x) if x.denominator == 1 else x.numerator // x.denominator)
    return z3.RealVal(f"{x.numerator}/{x.denominator}")


class _Binder:
    """A quantifier or comprehension, as the origin of the function values its variables take."""


CHOSEN = "chosen"  # a function nobody set: any function into its type, whichever step applies it
MADE = "made"  # a function the model made (a lambda): its results are in their type where applied


@dataclass(eq=False)
class Unset:
    """A function read from a place that may hold a function nobody set and, at another time, one
    the model made (`TransitionSystem._declare_unset`): the first (CHOSEN) while `flag` holds."""

    flag: z3.BoolRef


Origin = Union[str, _Binder, Unset]  # CHOSEN, MADE, the quantifier whose variable it is, or Unset


@dataclass(eq=False)
class Parts:
    """The origins of the function-typed parts of a record or tuple name, or of a variable with
    `Unset` flags, by the part's path (`""` for the name itself, `.f` for a record's field)."""

    by_path: dict[str, Origin]


def function_parts(t: ast.Type, prefix: str = "") -> list[str]:
    """The paths of a type's function-typed parts (`""` for a function type itself)."""
    if isinstance(t, ast.FunctionType):
        return [prefix]
    return [path for f, ft in parts(t) for path in function_parts(ft, f"{prefix}.{f}")]

# What a bound scope assumes of a quantifier's function-typed variables (its results in type):
# each with the quantifier it belongs to, which takes it into its domain.
Assumed = list[tuple[_Binder, z3.BoolRef]]


@dataclass
class _Scope:
    """A bound scope's evaluator (`Evaluator._bound_scope`) and what it collects."""

    ev: Evaluator
    side: list[z3.BoolRef] = field(default_factory=list)  # the functions' axioms at its points
    guards: list[z3.BoolRef] = field(default_factory=list)  # the step's conditions at its points
    assumed: Assumed = field(default_factory=list)
    binder: _Binder = field(default_factory=_Binder)

    def own(self) -> list[z3.BoolRef]:
        """What it assumes of its own variables."""
        return [c for b, c in self.assumed if b is self.binder]


class Evaluator:
    """Translates typed model expressions into Z3 terms over an environment."""

    def __init__(self, env: dict[int, Value], constants: dict[int, Value], side: list[z3.BoolRef],
                 clocks: dict[str, z3.ExprRef] | None = None, ranges: Ranges | None = None,
                 guards: list[z3.BoolRef] | None = None, origins: Mapping[int, Origin | Parts] | None = None,
                 assumed: Assumed | None = None):
        self.env = env  # id(Variable) -> value
        self.constants = constants
        self.side = side  # constraints that calls of uninterpreted functions add
        self.clocks = clocks or {}  # clock name (or `sinceEntry(S)`) -> tocks counted
        self.ranges = ranges or Ranges()  # the ranges quantified variables take their values in
        # Where a step's own conditions go (set by the step that evaluates): that a function value
        # applied here gives a value of its result type concerns this step only, not every step
        # (a lambda's result reads the configuration). None: with the functions' axioms.
        self.guards = guards
        # Where the function values of names in scope come from (`Origin`, by id(Variable)): a
        # quantifier's variables, a function's parameters and `let` names of function type; and
        # the `Flags` of the variables that have no initial value but are assigned.
        self.origins: dict[int, Origin | Parts] = dict(origins or {})
        self.assumed = assumed  # inside a quantifier or comprehension: its `_Scope.assumed`

    def _inner(self, env: dict[int, Value], origins: Mapping[int, Origin | Parts] | None = None) -> Evaluator:
        """An evaluator for a nested scope that is evaluated once, where this one is (a `let`)."""
        return type(self)(env, self.constants, self.side, self.clocks, self.ranges, self.guards,
                          {**self.origins, **(origins or {})}, self.assumed)

    def origin(self, e: ast.Expr, path: str = "") -> Origin:
        """Where the function value `e` (the part at `path` of it) comes from: a name's origin if
        it has one, else a variable or constant without an initial value is any function (CHOSEN;
        `Unset` where the model also assigns it), and anything else (a lambda, `override`, a
        variable with a lambda for its initial value) MADE."""
        if isinstance(e, ast.FieldRef):  # a record's field, or a tuple's part: the record's origin
            return self.origin(e.record, f".{e.field_name}{path}")
        if isinstance(e, ast.Index) and isinstance(e.value.type, ast.ProductType):
            return self.origin(e.value, f".{e.index.value}{path}" if isinstance(e.index, ast.Literal) else path)
        if isinstance(e, (ast.RecordLiteral, ast.TupleLiteral)) and path:
            head, _, rest = path[1:].partition(".")
            given = dict(e.fields) if isinstance(e, ast.RecordLiteral) else \
                {str(i): x for i, x in enumerate(e.items, 1)}
            # a field the literal leaves out is any value of its type: a function nobody set
            return self.origin(given[head], f".{rest}" if rest else "") if head in given else CHOSEN
        if not isinstance(e, ast.VarRef):
            return MADE
        var = e.variable
        found = self.origins.get(id(var))
        if isinstance(found, Parts):
            found = found.by_path.get(path)
        if found is not None:
            return found
        return CHOSEN if var.initial is None and var.kind not in ("bound", "let") else MADE

    def origins_of(self, names: Iterable[tuple[ast.Variable, ast.Expr]]) -> dict[int, Origin | Parts]:
        """The origins of the function values that names (a function's parameters, a `let`) are
        given by expressions: of each function-typed part of a record or tuple too."""
        out: dict[int, Origin | Parts] = {}
        for v, x in names:
            paths = function_parts(v.type)
            if paths == [""]:
                out[id(v)] = self.origin(x)
            elif paths:
                out[id(v)] = Parts({p: self.origin(x, p) for p in paths})
        return out

    def _bound_scope(self, env: dict[int, Value], quantified: Iterable[ast.Variable] = ()) -> _Scope:
        """An evaluator for a scope evaluated at every value of its bound variables (a
        quantifier's, a lambda's, a comprehension's: `quantified`, a quantifier's or a
        comprehension's), with lists of its own for the functions' axioms, the step's conditions
        (`guards`) and what it assumes of its function-typed bound variables, at those values."""
        scope = _Scope(self)
        origins = {**self.origins, **{id(v): scope.binder for v in quantified if isinstance(v.type, ast.FunctionType)}}
        scope.ev = type(self)(env, self.constants, scope.side, self.clocks, self.ranges, scope.guards, origins,
                              scope.assumed)
        return scope

    def _lift(self, consts: list[z3.ExprRef], scope: _Scope, where: z3.BoolRef) -> None:
        """A bound scope's axioms, for every value of its bound variables; its step conditions
        for every value where it is evaluated (`where`: in the domain, the condition true), as
        conditions of this evaluator's step (or with the axioms where there is no step)."""
        self.side += [z3.ForAll(consts, c) for c in scope.side]
        # what it assumes of an enclosing quantifier's functions, at every value of its variables
        for b, c in scope.assumed:
            if b is not scope.binder:
                assert self.assumed is not None
                self.assumed.append((b, z3.ForAll(consts, z3.Implies(where, c))))
        if scope.guards:
            lifted = z3.ForAll(consts, z3.Implies(where, z3.And(scope.guards)))
            (self.side if self.guards is None else self.guards).append(lifted)

    def value(self, e: ast.Expr) -> Value:
        """The Z3 value of `e`: operands first, from an explicit stack (expressions may nest
        hundreds deep), each subexpression once."""
        done: dict[int, Value] = {}
        stack: list[tuple[ast.Expr, bool]] = [(e, False)]
        while stack:
            node, expanded = stack.pop()
            if id(node) in done:
                continue
            inner = _operands(node)
            if inner and not expanded:
                stack.append((node, True))
                stack.extend((x, False) for x in reversed(inner))
                continue
            done[id(node)] = self._apply(node, [done[id(x)] for x in inner])
        return done[id(e)]

    def scalar(self, e: ast.Expr) -> z3.ExprRef:
        v = self.value(e)
        assert not isinstance(v, dict)
        return v

    def _apply(self, e: ast.Expr, operands: list[Value]) -> Value:
        """The value of `e` given the values of its `_operands`."""
        if isinstance(e, ast.Literal):
            if isinstance(e.value, bool):
                return z3.BoolVal(e.value)
            if isinstance(e.value, Fraction):
                return z3.RealVal(f"{e.value.numerator}/{e.value.denominator}")
            if isinstance(e.value, int):
                return z3.IntVal(e.value)
            raise Unsupported(e.pos, "string values are not encoded yet")
        if isinstance(e, ast.EnumLiteral):
            if e.enum.params:
                return variant(e.enum, e.literal, operands)
            return z3.IntVal(e.enum.literals.index(e.literal))
        if isinstance(e, ast.VarRef):
            key = id(e.variable)
            if key in self.env:
                return self.env[key]
            if key in self.constants:
                return self.constants[key]
            raise Unsupported(e.pos, f"variable '{e.variable.name}' has no value here")
        if isinstance(e, ast.FieldRef):
            [rec] = operands
            assert isinstance(rec, dict)
            return rec[e.field_name]
        if isinstance(e, ast.RecordLiteral):
            assert isinstance(e.type, ast.RecordType)
            if e.omitted:
                raise Unsupported(e.pos, "a record literal omitting fields, other than as an initial value")
            given = {name: v for (name, _), v in zip(e.fields, operands, strict=True)}
            return {f.name: given[f.name] for f in e.type.fields}
        if isinstance(e, ast.Unary):
            [v] = operands
            assert not isinstance(v, dict)
            if e.op == "trunc":  # towards zero, as FDR's integer reals divide
                return z3.If(v >= 0, z3.ToReal(z3.ToInt(v)), -z3.ToReal(z3.ToInt(-v)))
            return z3.Not(v) if e.op == "not" else -v
        if isinstance(e, ast.Binary):
            return _binary(e, *operands)
        if isinstance(e, ast.IfExpr):
            c, a, b = operands
            assert not isinstance(c, dict)
            if isinstance(a, dict) or isinstance(b, dict):
                assert isinstance(a, dict) and isinstance(b, dict)
                return {k: z3.If(c, a[k], b[k]) for k in a}
            if a.sort() != b.sort():
                a, b = _to_real(a), _to_real(b)
            return z3.If(c, a, b)
        if isinstance(e, ast.Call):
            return self._call(e, operands)
        if isinstance(e, ast.Builtin) and e.op in ("min", "max"):
            [a] = operands
            assert not isinstance(a, dict)
            r, axiom = _extremum(e, a)
            self.side.append(axiom)
            return r
        if isinstance(e, ast.Builtin) and e.op == "size" and isinstance(e.args[0].type, ast.SetType):
            [a] = operands
            assert not isinstance(a, dict)
            return _set_size(e, e.args[0].type, a, self.ranges)
        if isinstance(e, ast.Index) and not isinstance(operands[0], dict) or \
                isinstance(e, ast.Builtin) and e.op in ("head", "last"):
            self._item_outside(e, operands)
        if isinstance(e, (ast.SeqLiteral, ast.SetLiteral, ast.TupleLiteral, ast.Index, ast.Builtin)):
            value = _collection(e, operands)
            if isinstance(e, ast.Builtin) and e.op == "update":
                self._update_outside(e, value)
            return value
        if isinstance(e, ast.Let):
            [bound] = operands
            return self._inner({**self.env, id(e.variable): bound},
                               self.origins_of([(e.variable, e.value)])).value(e.body)
        if isinstance(e, ast.Quantifier):
            return self._quantifier(e)
        if isinstance(e, ast.Lambda):
            return self._lambda(e)
        if isinstance(e, ast.SetComprehension):
            return self._comprehension(e)
        if isinstance(e, ast.Apply):
            f, *args = operands
            assert isinstance(e.function.type, ast.FunctionType) and not isinstance(f, dict)
            result = unpack(f[_argument(e.function.type, args)], e.type)
            # A result is a value of its type. Of a function nobody set (CHOSEN) that is what the
            # environment chose, at every step; of a quantifier's variable (`exists f : nat -> nat
            # @ f(0) == 3`), what the quantifier assumes, as of its domain; of one the model made
            # (a lambda), a condition of the step that applies it; of a variable's that may be
            # either (Unset), the first while its flag holds, and the step's condition too (which
            # the first makes true).
            origin = self.origin(e.function)
            kept = domain(result, e.type, Ranges(), "result")
            if isinstance(origin, _Binder):
                assert self.assumed is not None
                self.assumed += [(origin, c) for c in kept]
            elif isinstance(origin, Unset):
                self.side.extend(z3.Implies(origin.flag, c) for c in kept)
                if self.guards is not None:  # else read outside a step (an initial value: flag true)
                    self.guards.extend(kept)
            else:
                (self.side if origin == CHOSEN or self.guards is None else self.guards).extend(kept)
            return result
        if isinstance(e, (ast.Since, ast.SinceEntry)):
            name = e.clock.name if isinstance(e, ast.Since) else entry_clock(e.state)
            if name not in self.clocks:
                raise Unsupported(e.pos, f"clock '{name}' has no value here")
            return self.clocks[name]
        if isinstance(e, ast.UnsupportedExpr):  # `properties.queries.query` refuses it first
            raise Unsupported(e.pos, e.what)
        raise Unsupported(e.pos, f"{type(e).__name__} expressions are not encoded yet")

    def _item_outside(self, e: ast.Expr, operands: list[Value]) -> None:
        """An item read outside its sequence's length (`s[i]`, `head`, `last` of an empty one) is
        any value of the item's type: Z3's `nth` is unspecified there, and this keeps it in the
        type (a constraint on that unspecified value alone, so it removes no run; at every step,
        for the sequence and index the read has there)."""
        t = e.type
        if isinstance(t, (ast.SeqType, ast.SetType, ast.FunctionType)) or self.assumed is not None:
            # a container's items would need a quantifier, and so would a read inside a quantifier,
            # a lambda or a comprehension (`forall i @ s[i] < b`: Z3 did not answer at depth 1)
            return
        seq = operands[0]
        assert isinstance(seq, z3.SeqRef)
        at = operands[1] if isinstance(e, ast.Index) else z3.IntVal(1) if e.op == "head" else z3.Length(seq)  # type: ignore[attr-defined]
        assert isinstance(at, z3.ArithRef)
        kept = domain(unpack(seq[at - 1], t), t, given_types(self.ranges), "item")
        if kept:
            self.side.append(z3.Implies(z3.Not(z3.And(at >= 1, at <= z3.Length(seq))), z3.And(kept)))

    def _update_outside(self, e: ast.Builtin, value: Value) -> None:
        """`s[i] = v` outside 1..#s is any sequence of s's type: an axiom keeps the items of that
        uninterpreted value (`UPDATE_OUTSIDE`, the `If`'s last branch) in their type, so that a step
        storing it stores a value of its place (`_items_fit` takes it as one)."""
        t = e.type
        if isinstance(t, ast.SeqType) and _checked(t.element):
            assert isinstance(value, z3.ExprRef) and z3.is_app(value) and value.decl().kind() == z3.Z3_OP_ITE
            self.side += _every_item(value.arg(2), t)

    def _call(self, e: ast.Call, args: list[Value]) -> Value:
        f = e.function
        if f.unchecked:
            raise Unsupported(e.pos, ast.unchecked_function(f))
        if f.definition is not None:
            origins = self.origins_of(zip(f.parameters, e.args))
            inner = Evaluator({**self.constants, **{id(p): a for p, a in zip(f.parameters, args)}}, {}, self.side,
                              ranges=self.ranges, guards=self.guards, origins=origins, assumed=self.assumed)
            defined = inner.value(f.definition)
            if not f.preconditions:
                return defined
            # Outside its preconditions the function is not defined: any value is possible there.
            if isinstance(defined, dict):
                raise Unsupported(e.pos, "functions over records with preconditions are not encoded yet")
            sorts = [sort_of(p.type) for p in f.parameters]
            anything = z3.Function(f"{f.qname}.outside", *sorts, sort_of(f.result))
            points = [pack(a, p.type) for a, p in zip(args, f.parameters)]
            pre = z3.And([inner.scalar(c) for c in f.preconditions])
            self.side += domain(anything(*points), f.result, given_types(self.ranges), f.qname)  # any value of its type
            return z3.If(pre, defined, anything(*points))
        # Uninterpreted: any function meeting its pre/postconditions (records and tuples passed
        # and returned in their datatype).
        sorts = [sort_of(p.type) for p in f.parameters]
        fn = z3.Function(f.qname, *sorts, sort_of(f.result))
        packed = fn(*[pack(a, p.type) for a, p in zip(args, f.parameters)])
        # Whatever the function, its result is a value of its type: a natural is not negative, an
        # enumeration's value one of its literals (without this, a call could answer 31 for a Status).
        self.side += domain(unpack(packed, f.result), f.result, given_types(self.ranges), f.qname)
        if parts(f.result):
            if f.postconditions:
                raise Unsupported(e.pos, "postconditions of functions returning records or tuples are not encoded yet")
            return unpack(packed, f.result)
        result = packed
        # The axiom `pre => post`, instantiated at this call: exact, since only called points matter.
        # The conditions read the arguments as values (a record's fields by name), not packed.
        # A function value passed in and applied there: as where the call is (the step's conditions).
        ev = Evaluator({id(p): a for p, a in zip(f.parameters, args)}, {}, self.side, ranges=self.ranges,
                       guards=self.guards, origins=self.origins_of(zip(f.parameters, e.args)), assumed=self.assumed)
        pre = [ev.scalar(c) for c in f.preconditions]
        post = [_with_result(ev, c, result) for c in f.postconditions]
        if post:
            self.side.append(z3.Implies(z3.And(pre), z3.And(post)))
        return result


    def _bound(self, variables: tuple[ast.Variable, ...], pos: ast.Pos) -> tuple[list[z3.ExprRef], dict[int, Value]]:
        """Fresh constants for bound variables (a quantifier's, a lambda's) and their values."""
        consts: list[z3.ExprRef] = []
        values: dict[int, Value] = {}
        for v in variables:
            x = z3.Const(f"{v.name}!{pos.line}:{pos.column}", sort_of(v.type))
            consts.append(x)
            values[id(v)] = unpack(x, v.type)
        return consts, values

    def _lambda(self, e: ast.Lambda) -> z3.ExprRef:
        """`lambda x : T, … | c @ b` as a Z3 lambda (an array term) over one constant of the domain
        (a product domain's parts read by its accessors); where `c` fails, any value (an
        uninterpreted function of the point, as outside a function's precondition)."""
        t = e.type
        assert isinstance(t, ast.FunctionType)
        x = z3.Const(f"lambda!{e.pos.line}:{e.pos.column}", sort_of(t.domain))
        if len(e.variables) == 1:
            values: dict[int, Value] = {id(e.variables[0]): unpack(x, t.domain)}
        else:
            point = unpack(x, t.domain)
            assert isinstance(point, dict)
            values = {id(v): point[str(i)] for i, v in enumerate(e.variables, 1)}
        scope = self._bound_scope({**self.env, **values})
        body = pack(scope.ev.value(e.body), t.range)
        if e.condition is not None:
            outside = z3.Function(f"lambda!{e.pos.line}:{e.pos.column}.outside", x.sort(), sort_of(t.range))
            body = z3.If(scope.ev.scalar(e.condition), body, outside(x))
        if scope.guards:
            # They would concern the steps that apply this lambda, which its value cannot carry.
            raise Unsupported(e.pos, "a function value applied in a lambda's body is not encoded yet")
        self._lift([x], scope, z3.BoolVal(True))
        return z3.Lambda([x], body)

    def _comprehension(self, e: ast.SetComprehension) -> z3.ExprRef:
        """`{x : T | p @ t}` as a Z3 set: without a term, the `x` in their domain that satisfy `p`
        (a lambda); with one, the values `y` for which some such `x` gives `t == y` (a lambda over
        an existential, which Z3 may answer `unknown` on)."""
        consts, values = self._bound(e.variables, e.pos)
        dom = [c for v in e.variables for c in domain(values[id(v)], v.type, self.ranges, f"{v.owner}::{v.name}")]
        scope = self._bound_scope({**self.env, **values}, e.variables)
        cond = scope.ev.scalar(e.condition) if e.condition is not None else z3.BoolVal(True)
        dom += scope.own()
        self._lift(consts, scope, z3.And(*dom))
        guard = z3.And(*dom, cond)
        assert isinstance(e.type, ast.SetType)
        if e.term is None:
            return z3.Lambda(consts, guard)
        y = z3.Const(f"member!{e.pos.line}:{e.pos.column}", sort_of(e.type.element))
        scope = self._bound_scope({**self.env, **values}, e.variables)
        term = pack(scope.ev.value(e.term), e.type.element)
        guard = z3.And(guard, *scope.own())
        self._lift(consts, scope, guard)
        return z3.Lambda([y], z3.Exists(consts, z3.And(guard, _coerce_eq(term, y))))

    def _quantifier(self, e: ast.Quantifier) -> z3.BoolRef:
        """`forall`/`exists`/`exists1` as a Z3 quantifier over fresh constants, each in its type's
        domain within the ranges in force (as a value the environment supplies). The side
        constraints the body adds (axioms of uninterpreted functions at the bound points) hold for
        every value of the bound variables, so they are quantified too."""
        consts, values = self._bound(e.variables, e.pos)
        dom = [c for v in e.variables for c in domain(values[id(v)], v.type, self.ranges, f"{v.owner}::{v.name}")]
        scope = self._bound_scope({**self.env, **values}, e.variables)
        cond = scope.ev.scalar(e.condition) if e.condition is not None else z3.BoolVal(True)
        dom += scope.own()
        self._lift(consts, scope, z3.And(*dom))
        guard = z3.And(*dom, cond)
        scope = self._bound_scope({**self.env, **values}, e.variables)
        body = scope.ev.scalar(e.body)
        guard = z3.And(guard, *scope.own())
        self._lift(consts, scope, guard)
        if e.kind == "forall":
            return z3.ForAll(consts, z3.Implies(guard, body))
        found = z3.Exists(consts, z3.And(guard, body))
        if e.kind == "exists":
            return found
        # exists1: some value does, and any value that does is that one.
        others = [z3.Const(f"{x}'", x.sort()) for x in consts]
        renamed = [z3.substitute(z3.And(guard, body), *zip(consts, others, strict=True))]
        unique = z3.ForAll(consts, z3.ForAll(others, z3.Implies(z3.And(guard, body, *renamed),
                                                                   z3.And([a == b for a, b in zip(consts, others, strict=True)]))))
        return z3.And(found, unique)


def _operands(e: ast.Expr) -> tuple[ast.Expr, ...]:
    """The subexpressions whose values `Evaluator._apply` needs for `e`."""
    if isinstance(e, ast.Binary):
        return (e.left, e.right)
    if isinstance(e, ast.Unary):
        return (e.operand,)
    if isinstance(e, ast.IfExpr):
        return (e.condition, e.then, e.otherwise)
    if isinstance(e, ast.FieldRef):
        return (e.record,)
    if isinstance(e, ast.RecordLiteral):
        return tuple(v for _, v in e.fields)
    if isinstance(e, ast.Call):
        return e.args
    if isinstance(e, (ast.SeqLiteral, ast.SetLiteral, ast.TupleLiteral)):
        return e.items
    if isinstance(e, ast.Index):
        return (e.value, e.index)
    if isinstance(e, ast.Builtin):
        return e.args
    if isinstance(e, ast.Let):
        return (e.value,)
    if isinstance(e, ast.Apply):
        return (e.function, *e.args)
    if isinstance(e, ast.EnumLiteral):
        return e.args
    return ()


def _argument(t: ast.FunctionType, args: list[Value]) -> z3.ExprRef:
    """The point a function is applied at: one argument of its domain, or its product domain's
    parts given one by one (packed into the product's datatype)."""
    if len(args) == 1:
        return pack(args[0], t.domain)
    assert isinstance(t.domain, ast.ProductType)
    return pack({str(i): a for i, a in enumerate(args, 1)}, t.domain)


UPDATE_OUTSIDE = "!update.outside"  # not a name a model can give a function (`bmc.interpretations`)


def _collection(e: ast.Expr, operands: list[Value]) -> Value:
    """The value of a sequence, set or tuple expression given its operands' values."""
    t = e.type
    if isinstance(e, ast.TupleLiteral):
        assert isinstance(t, ast.ProductType)
        return {str(i): v for i, v in enumerate(operands, 1)}
    if isinstance(e, ast.SeqLiteral):
        assert isinstance(t, ast.SeqType)
        units = [z3.Unit(pack(v, t.element)) for v in operands]
        if not units:
            return z3.Empty(sort_of(t))
        return units[0] if len(units) == 1 else z3.Concat(*units)
    if isinstance(e, ast.SetLiteral):
        assert isinstance(t, ast.SetType)
        s = z3.EmptySet(sort_of(t.element))
        for v in operands:
            s = z3.SetAdd(s, pack(v, t.element))
        return s
    if isinstance(e, ast.Index):
        value, index = operands
        if isinstance(value, dict):  # a tuple's part, chosen by a literal
            assert isinstance(e.index, ast.Literal)
            return value[str(e.index.value)]
        assert not isinstance(index, dict)
        # Outside 1..#s Z3's `nth` is unspecified: any value, as a function outside its
        # precondition (`bmc.interpretations` tells a witness that rests on it). An uninterpreted
        # function there instead slows Z3 down on RoboArch's SkillsManager, and makes it fail
        # ("Overflow encountered when expanding vector").
        return unpack(value[index - 1], e.type)
    assert isinstance(e, ast.Builtin)
    return _builtin(e, operands)


# The longest `range(x, y)` BMC writes out as a sequence literal.
MAX_RANGE = 4096


def _range(e: ast.Builtin, low: z3.ExprRef, high: z3.ExprRef) -> z3.ExprRef:
    """sequence_toolkit's `range(x, y)`, `<x, x+1, …, y>` (`<>` when y < x), for bounds that are
    constants once simplified (`range(1, 3)` -> `Unit(1) ++ Unit(2) ++ Unit(3)`). Z3 has no sequence
    of a symbolic length other than by a quantifier or a recursive definition, so other bounds are
    `unsupported`, at the call."""
    low, high = z3.simplify(low), z3.simplify(high)
    if not (z3.is_int_value(low) and z3.is_int_value(high)):
        raise Unsupported(e.pos, "range(x, y) whose bounds are not constants (a sequence of a length "
                                 "chosen by the run)")
    lo, hi = low.as_long(), high.as_long()
    if hi - lo >= MAX_RANGE:
        raise Unsupported(e.pos, f"range(x, y) of {hi - lo + 1} integers (more than {MAX_RANGE})")
    if hi < lo:
        return z3.Empty(z3.SeqSort(z3.IntSort()))
    items = [z3.Unit(z3.IntVal(i)) for i in range(lo, hi + 1)]
    return items[0] if len(items) == 1 else z3.Concat(*items)


def _builtin(e: ast.Builtin, operands: list[Value]) -> Value:
    op, args = e.op, e.args
    xs: list[z3.ExprRef] = []
    for a, v in zip(args, operands, strict=True):
        xs.append(pack(v, a.type))
    a = xs[0]
    if op in ("in", "notin"):
        set_type = args[1].type
        assert isinstance(set_type, ast.SetType)
        member = z3.IsMember(pack(operands[0], set_type.element), xs[1])
        return member if op == "in" else z3.Not(member)
    st = args[0].type
    if op == "as":  # a cast that changes no value, but its integers to reals (the checker builds no other)
        return as_type(operands[0], e.type, e.pos)
    if op == "interval":
        low, high, closed_low, closed_high = xs
        i = z3.Int(f"interval!{e.pos.line}:{e.pos.column}")
        above = i >= low if z3.is_true(closed_low) else i > low
        below = i <= high if z3.is_true(closed_high) else i < high
        return z3.Lambda([i], z3.And(above, below))
    if op == "range":
        return _range(e, xs[0], xs[1])
    if op == "extract":
        assert isinstance(args[1].type, ast.SeqType)
        s = xs[1]
        i, acc, x = z3.Int("extract!i"), z3.Const("extract!acc", s.sort()), z3.Const("extract!x", sort_of(args[1].type.element))
        keep = z3.If(z3.IsMember(i, a), z3.Concat(acc, z3.Unit(x)), acc)
        return z3.SeqFoldLeftI(z3.Lambda([i, acc, x], keep), z3.IntVal(1), z3.Empty(s.sort()), s)
    if op == "override":
        return _override(e, a, xs[1])
    if op == "update":
        # `s[i] = v` within 1..#s replaces the i-th item; outside it the result is any sequence
        # (as an index outside 1..#s has any value), one uninterpreted function of (s, i, v).
        i, item = xs[1], xs[2]
        n = z3.Length(a)
        replaced = z3.Concat(z3.SubSeq(a, 0, i - 1), z3.Unit(item), z3.SubSeq(a, i, n - i))
        # one function per sequence type: a Seq(nat)'s outside value is kept a Seq(nat) by an
        # axiom (`Evaluator._update_outside`), which must not bind a Seq(int) of the same sort
        outside = z3.Function(f"{UPDATE_OUTSIDE}:{_qualified(st)}", a.sort(), z3.IntSort(), item.sort(), a.sort())
        return z3.If(z3.And(i >= 1, i <= n), replaced, outside(a, i, item))
    if op == "size":  # of a sequence (a set's: `_set_size`, which needs the ranges)
        return z3.Length(a)
    if op == "isNonEmpty":
        return z3.Length(a) > 0
    if op in ("head", "last"):
        assert isinstance(st, ast.SeqType)
        return unpack(a[0] if op == "head" else a[z3.Length(a) - 1], st.element)
    if op == "tail":
        return z3.SubSeq(a, 1, z3.Length(a) - 1)
    if op == "front":
        return z3.SubSeq(a, 0, z3.Length(a) - 1)
    if op == "concat":
        return z3.Concat(a, xs[1])
    if op == "prefix":
        return z3.PrefixOf(a, xs[1])
    if op == "suffix":
        return z3.SuffixOf(a, xs[1])
    if op == "infix":  # set_toolkit's `exists u, v @ u ^ s ^ v == t`: a stretch of t
        return z3.Contains(xs[1], a)
    element = sort_of(st.element) if isinstance(st, (ast.SeqType, ast.SetType)) else None
    if op == "reverse":
        acc, x = z3.Const("rev!acc", a.sort()), z3.Const("rev!x", element)
        return z3.SeqFoldLeft(z3.Lambda([acc, x], z3.Concat(z3.Unit(x), acc)), z3.Empty(a.sort()), a)
    if op == "filter":
        acc, x = z3.Const("filter!acc", a.sort()), z3.Const("filter!x", element)
        keep = z3.If(z3.IsMember(x, xs[1]), z3.Concat(acc, z3.Unit(x)), acc)
        return z3.SeqFoldLeft(z3.Lambda([acc, x], keep), z3.Empty(a.sort()), a)
    if op == "dom":
        i = z3.Int("dom!i")
        return z3.Lambda([i], z3.And(i >= 1, i <= z3.Length(a)))
    if op in ("ran", "elems"):
        x = z3.Const("ran!x", element)
        return z3.Lambda([x], z3.Contains(a, z3.Unit(x)))
    b = xs[1]
    if op == "union":
        return z3.SetUnion(a, b)
    if op == "inter":
        return z3.SetIntersect(a, b)
    if op == "diff":
        return z3.SetDifference(a, b)
    if op == "symetric_diff":  # set_toolkit's spelling: the members of exactly one
        return z3.SetDifference(z3.SetUnion(a, b), z3.SetIntersect(a, b))
    if op == "subseteq":
        return z3.IsSubset(a, b)
    if op == "subset":
        return z3.And(z3.IsSubset(a, b), a != b)
    raise Unsupported(e.pos, f"the operation '{op}' is not encoded yet")


GIVEN_SIZE_CAP = 64  # a set of a given type is counted over at most this many values


def _set_size(e: ast.Builtin, st: ast.SetType, a: z3.ExprRef, ranges: Ranges) -> z3.ArithRef:
    """The size of a set whose element type has finitely many values, known here, each counted
    when it is a member: an enumeration's literals, the two booleans, or a given type's range.  A
    given type's count is exact since it has no arithmetic and every value of it is within its range
    (`domain`: inputs, variables and constants the environment chooses, and the results of
    functions); without a range, or with one that is a parameter, its values are not known.  Z3's
    sets have no cardinality, and arithmetic takes numbers out of any range, so a set of numbers is
    `unsupported`."""
    t = st.element
    if isinstance(t, ast.EnumType) and not t.params:
        values: list[z3.ExprRef] = [z3.IntVal(i) for i in range(len(t.literals))]
    elif t == ast.BOOLEAN:
        values = [z3.BoolVal(False), z3.BoolVal(True)]
    elif isinstance(t, ast.GivenType):
        r = ranges.by_type.get(t.name)
        if t.name in ranges.parametric or r is None:
            raise Unsupported(e.pos, f"the size of a set of {t.name} without a range for {t.name} (Z3's sets have no "
                                     f"cardinality; with --range {t.name}=LO..HI, or RoboTool's nametype, the set's "
                                     "members are counted over the range)")
        low, high = math.ceil(r.low), math.floor(r.high)
        if high - low + 1 > GIVEN_SIZE_CAP:
            raise Unsupported(e.pos, f"the size of a set of {t.name}, whose range {r} has more than "
                                     f"{GIVEN_SIZE_CAP} values")
        values = [z3.IntVal(v) for v in range(low, high + 1)]
    else:
        raise Unsupported(e.pos, f"the size of a set of {t} (Z3's sets have no cardinality; sets of "
                                 "enumerations, booleans and given types with a range are counted)")
    return z3.Sum([z3.If(z3.IsMember(v, a), 1, 0) for v in values]) if values else z3.IntVal(0)


def _extremum(e: ast.Builtin, a: z3.ExprRef) -> tuple[z3.ExprRef, z3.BoolRef]:
    """sequence_toolkit's `min(a)` (`max(a)`): a member of `a` no greater (less) than any other,
    when `a` has one (its precondition `hasMin(a)`); outside it any value. One uninterpreted
    function of the set per operation, with that axiom at this set; the axiom is quantified, so Z3
    may answer `unknown`."""
    sort = a.sort()
    assert isinstance(sort, z3.ArraySortRef)
    element = sort.domain()
    f = z3.Function(f"toolkit.{e.op}", sort, element)
    r = f(a)
    m, n = z3.Const(f"{e.op}!m", element), z3.Const(f"{e.op}!n", element)

    def bound(x: z3.ExprRef, y: z3.ExprRef) -> z3.BoolRef:
        return x <= y if e.op == "min" else x >= y  # type: ignore[operator, return-value]

    has = z3.Exists([m], z3.And(z3.IsMember(m, a), z3.ForAll([n], z3.Implies(z3.IsMember(n, a), bound(m, n)))))
    is_extremum = z3.And(z3.IsMember(r, a), z3.ForAll([n], z3.Implies(z3.IsMember(n, a), bound(r, n))))
    return r, z3.Implies(has, is_extremum)


def _override(e: ast.Builtin, r: z3.ExprRef, s: z3.ExprRef) -> z3.ExprRef:
    """relation_toolkit's `override(r, s)`, `(dom(s) ⩤ r) ∪ s`: for a function `r` and a set of
    pairs `s`, the function that at `x` is `s`'s `y` where `s` has a pair `(x, y)` and `r(x)`
    elsewhere. A literal `s` is a chain of `If`s; where it pairs one `x` twice the result is not
    a function, and the pair written last is taken (the explicit engine refuses to choose). Any
    other `s` is not encoded yet."""
    rt = e.args[0].type
    if not isinstance(rt, ast.FunctionType):
        raise Unsupported(e.pos, "override of a relation that is not a function is not encoded yet")
    given = e.args[1]
    if not isinstance(given, ast.SetLiteral):
        raise Unsupported(e.pos, "override by a set that is not a literal is not encoded yet")
    x = z3.Const(f"override!{e.pos.line}:{e.pos.column}", sort_of(rt.domain))
    body = r[x]
    sort = sort_of(ast.ProductType((rt.domain, rt.range)))
    assert isinstance(sort, z3.DatatypeSortRef)
    members = _literal_members(s)
    for m in members:
        key, value = sort.accessor(0, 0)(m), sort.accessor(0, 1)(m)
        body = z3.If(x == key, value, body)
    return z3.Lambda([x], body)


def _literal_members(s: z3.ExprRef) -> list[z3.ExprRef]:
    """The members a set literal's term adds (`SetAdd` chains over the empty set), first first."""
    out: list[z3.ExprRef] = []
    while z3.is_app_of(s, z3.Z3_OP_STORE):
        out.append(s.arg(1))
        s = s.arg(0)
    return out[::-1]


def _binary(e: ast.Binary, left: Value, right: Value) -> Value:
    if e.op in ("==", "!="):
        eq = equal(left, right)
        return eq if e.op == "==" else z3.Not(eq)
    assert not isinstance(left, dict) and not isinstance(right, dict)
    a, b = left, right
    if e.op in ("and", "or", "implies", "iff"):
        return {"and": z3.And, "or": z3.Or, "implies": z3.Implies, "iff": lambda x, y: x == y}[e.op](a, b)
    if a.sort() != b.sort() or e.type == ast.REAL:
        a, b = _to_real(a), _to_real(b)
    if e.op == "+":
        return a + b
    if e.op == "-":
        return a - b
    if e.op == "*":
        return a * b
    if e.op == "/":
        return a / b
    if e.op == "%":
        return a % b
    return {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b}[e.op]


def _with_result(ev: Evaluator, cond: ast.Expr, result: z3.ExprRef) -> z3.BoolRef:
    class _R(Evaluator):
        def _apply(self, e: ast.Expr, operands: list[Value]) -> Value:  # noqa: D102 - binds `result`
            if isinstance(e, ast.ResultRef):
                return result
            return super()._apply(e, operands)

    return _R(ev.env, ev.constants, ev.side, ev.clocks, ev.ranges, ev.guards, ev.origins, ev.assumed).scalar(cond)
