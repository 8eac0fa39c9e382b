"""RoboTool's instantiation of a project: what the model leaves open, read as RoboTool reads it.

RoboTool keeps the data ranges, the values of constants and the bodies of functions that the
model does not give in CSPm: the project's `instantiations.csp` (at its root, else in
`csp-gen/`, where RoboTool generates it with a default for everything), or a CSP block named
`Instantiations` in an assertions file.  This module parses both (grammar
`instantiation.lark`) into definitions with their positions, and turns the parts tockbmc
understands into the model's values: intervals, literal values of a type, and function
bodies as expressions over the function's parameters.  `model/config.py` decides which
definition applies to which type, constant or function; see DESIGN.md for what RoboTool
generates.
"""

from __future__ import annotations

import dataclasses
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from pathlib import Path
from typing import NamedTuple

from lark import Lark, Token, Tree, UnexpectedInput

from tockbmc.model import ast, expressions, grammars
from tockbmc.model.csp import position as block_position
from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.limits import MAX_CSP_NESTING

FILE_NAME = "instantiations.csp"
BLOCK_NAME = "instantiations"  # a CSP block of an assertions file, compared without case

Node = Tree | Token
Locate = Callable[[int, int], ast.Pos]


@dataclass(frozen=True)
class Definition:
    """`nametype N = S`, `N = e` or `f(p, …) = e` (`params` is None for `N = e`)."""

    name: str
    params: tuple[Node, ...] | None
    body: Node
    pos: ast.Pos
    nametype: bool = False
    locate: Locate | None = dataclasses.field(default=None, compare=False, repr=False)
    skipped: bool = False  # not parsed: nothing of the model reads it (`read`'s `wanted`); `body` is empty

    def at(self, node: Node) -> ast.Pos:
        """The file position of a part of this definition."""
        line, column = _line_column(node)
        if self.locate is None or line is None:
            return self.pos
        return self.locate(line, column or 1)


@dataclass(frozen=True)
class Instantiation:
    """The definitions of one file or block, in order, and what of it could not be read."""

    path: str
    definitions: tuple[Definition, ...]
    problems: tuple[Diagnostic, ...] = ()


class NotUnderstood(Exception):
    """A definition, or a part of one, that tockbmc does not turn into a model value."""

    def __init__(self, pos: ast.Pos, what: str):
        super().__init__(f"{pos}: {what}")
        self.pos, self.what = pos, what


# ----------------------------------------------------------------------------- reading


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return grammars.build("instantiation.lark", propagate_positions=True, maybe_placeholders=False)


def project_file(root: str | Path) -> Path | None:
    """The project's `instantiations.csp`: at its root, else in `csp-gen/` (where RoboTool writes it)."""
    base = Path(root)
    if base.is_file():
        base = base.parent
    for candidate in (base / FILE_NAME, base / "csp-gen" / FILE_NAME):
        if candidate.is_file():
            return candidate
    return None


def read_file(path: Path, wanted: Callable[[str], bool] | None = None) -> tuple[Instantiation, str]:
    """The definitions of an instantiation file, and its text (for diagnostics); see `read`."""
    text = path.read_text(encoding="utf-8-sig", errors="replace")
    name = str(path)
    return read(text, name, lambda line, column: ast.Pos(name, line, column), wanted), text


def read_block(block: ast.CspBlock, wanted: Callable[[str], bool] | None = None) -> Instantiation:
    """The definitions of an `Instantiations` CSP block of an assertions file; see `read`."""
    return read(block.text, block.pos.path, lambda line, column: block_position(block, line, column), wanted)


def is_instantiation_block(block: ast.CspBlock) -> bool:
    return block.name.lower() == BLOCK_NAME


# A definition starts a line: `nametype N`, `N =` or `N(…) =` in the first column.
_START = re.compile(r"^(nametype\s|[A-Za-z_][A-Za-z0-9_']*\s*(\([^=]*\))?\s*=[^=])", re.M)
_MAX_MERGED = 40


_NAME = re.compile(r"(nametype\s+)?([A-Za-z_][A-Za-z0-9_']*)")


def read(text: str, path: str, locate: Locate, wanted: Callable[[str], bool] | None = None) -> Instantiation:
    """Parse CSPm definitions.  A part that does not parse is reported and skipped: the text is
    cut where definitions start a line, and each piece is parsed with as few of the following
    ones as make it whole (a `let` spans several such lines).

    With `wanted`, a definition is parsed only if its name is wanted (the caller wants the helpers
    the parsed bodies name too: `config` asks again with them, over the file and its blocks): the
    others are `skipped`, read for their name and position alone, so that a line nothing reads
    costs nothing, however large. A piece nested past `MAX_CSP_NESTING` is refused unparsed, with
    its line."""
    if wanted is None:
        try:
            return Instantiation(path, tuple(_definitions(_parse(text), 0, locate)))
        except UnexpectedInput:
            pass
    starts = [m.start() for m in _START.finditer(text)] or [0]
    if starts[0] != 0:
        starts.insert(0, 0)
    starts.append(len(text))
    if wanted is None:
        return _read_pieces(text, path, locate, starts, None)
    names = [_NAME.match(text, s) for s in starts[:-1]]
    return _read_pieces(text, path, locate, starts,
                        {i for i, m in enumerate(names) if m is not None and wanted(m.group(2))})


def names_in(node: Node) -> set[str]:
    """The names a definition's part uses (a helper such as `abs` is used this way)."""
    out: set[str] = set()
    nodes = [node]
    while nodes:
        n = nodes.pop()
        if isinstance(n, Token):
            if n.type == "NAME":
                out.add(str(n))
        elif isinstance(n, Tree):
            nodes += n.children
    return out


def _nesting(piece: str) -> int:
    """A cheap bound on how deep a piece nests, counted before the parser recurses into it: open
    brackets, plus the `if`s whose `else` has not come yet and the `let`s whose `within` has not."""
    depth = deepest = 0
    for token in re.findall(r"[()\[\]{}]|\b(?:if|else|let|within)\b", piece):
        depth += 1 if token in ("(", "[", "{", "if", "let") else -1
        deepest = max(deepest, depth)
    return deepest


def _read_pieces(text: str, path: str, locate: Locate, starts: list[int], parse: set[int] | None) -> Instantiation:
    """The definitions of the pieces `starts` cuts the text into: those in `parse` (all if None)
    parsed, the others `skipped`."""
    definitions: list[Definition] = []
    problems: list[Diagnostic] = []
    i = 0
    while i < len(starts) - 1:
        if parse is not None and i not in parse:
            line = text.count("\n", 0, starts[i]) + 1
            m = _NAME.match(text, starts[i])
            if m is not None:
                definitions.append(Definition(m.group(2), None, Tree("skipped", []),
                                              locate(line, m.start(2) - starts[i] + 1), bool(m.group(1)), skipped=True))
            i += 1
            continue
        for j in range(i + 1, min(len(starts), i + 1 + _MAX_MERGED)):
            piece = text[starts[i]:starts[j]]
            if _nesting(piece) > MAX_CSP_NESTING:
                line = text.count("\n", 0, starts[i]) + 1
                problems.append(Diagnostic(locate(line, 1), f"this definition is nested more than {MAX_CSP_NESTING} "
                                           "levels deep; it is ignored", "warning"))
                i = j
                break
            try:
                tree = _parse(piece)
            except UnexpectedInput:
                continue
            definitions += _definitions(tree, text.count("\n", 0, starts[i]), locate)
            i = j
            break
        else:
            first_line = text.count("\n", 0, starts[i]) + 1
            problems.append(Diagnostic(locate(first_line, 1), "this definition is not CSPm that tockbmc reads; "
                                       "it is ignored", "warning"))
            i += 1
    return Instantiation(path, tuple(definitions), tuple(problems))


def _parse(text: str) -> Tree:
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 20_000))
    try:
        return _parser().parse(text)
    finally:
        sys.setrecursionlimit(limit)


def _definitions(tree: Tree, line_offset: int, locate: Locate) -> list[Definition]:
    def at(line: int, column: int) -> ast.Pos:
        return locate(line + line_offset, column)

    out = []
    for item in tree.children:
        if not isinstance(item, Tree):
            continue
        name = item.children[0]
        line, column = _line_column(name)
        pos = at(line or 1, column or 1)
        if item.data == "nametype":
            out.append(Definition(str(name), None, item.children[1], pos, True, at))
        else:
            params = None
            if len(item.children) == 3:
                params = tuple(c for c in item.children[1].children if isinstance(c, (Tree, Token)))
            out.append(Definition(str(name), params, item.children[-1], pos, False, at))
    return out


def _line_column(node: Node) -> tuple[int | None, int | None]:
    if isinstance(node, Token):
        return node.line, node.column
    meta = node.meta
    if getattr(meta, "empty", True):
        for child in node.children:
            if isinstance(child, (Tree, Token)):
                return _line_column(child)
        return None, None
    return meta.line, meta.column


# ----------------------------------------------------------------------------- values


def mangle(qname: str) -> str:
    """RoboTool's CSP identifier for a qualified name: `main::Controller` is `main_Controller`."""
    return qname.replace("::", "_")


def number(d: Definition, node: Node, named: Mapping[str, Definition] | None = None) -> Fraction:
    """An integer constant expression: a number, a negation, arithmetic of numbers, and (with
    `named`, the block's definitions `N = e`) a name defined so (`REAL_MAX = 2`)."""
    if isinstance(node, Tree):
        if node.data == "number":
            return Fraction(int(str(node.children[0])))
        if node.data == "name" and named:
            other = named.get(str(node.children[0]))
            if other is not None and other.params is None and not other.nametype and not other.skipped:
                rest = {k: v for k, v in named.items() if k != other.name}  # a name defined by itself stops here
                try:
                    return number(other, other.body, rest)
                except NotUnderstood:
                    pass
        if node.data == "negate":
            return -number(d, node.children[0], named)
        if node.data == "arith":
            left, op, right = node.children
            a, b = number(d, left, named), number(d, right, named)
            if str(op) == "+":
                return a + b
            if str(op) == "-":
                return a - b
            if str(op) == "*":
                return a * b
    raise NotUnderstood(d.at(node), "expected a number")


def interval(d: Definition, node: Node, named: Mapping[str, Definition] | None = None) -> tuple[Fraction, Fraction]:
    """`{a..b}`, or a set of integers without gaps (`{-1,0,1}`), as its bounds; its numbers may
    name the block's constants (`number`)."""
    if isinstance(node, Tree) and node.data == "interval":
        low, high = number(d, node.children[0], named), number(d, node.children[1], named)
        if low > high:
            raise NotUnderstood(d.at(node), "an empty interval")
        return low, high
    if isinstance(node, Tree) and node.data == "set" and node.children:
        values = sorted({number(d, c, named) for c in node.children})
        if all(b - a == 1 for a, b in zip(values, values[1:], strict=False)):
            return values[0], values[-1]
        raise NotUnderstood(d.at(node), "a set of values with gaps; tockbmc's ranges are intervals")
    raise NotUnderstood(d.at(node), "not an interval {a..b}; RoboTool computes this set, tockbmc takes "
                                    "ranges that are intervals")


def enum_literal(name: str, t: ast.EnumType) -> ast.EnumLiteral | None:
    """RoboTool writes literal `L` of enumeration `pkg::E` as `pkg_E_L` (`E_L` is accepted too)."""
    for lit in t.literals:
        if t.parameters(lit):
            continue  # RoboTool's CSP spelling of a literal's arguments is not known
        if name in (f"{mangle(t.qname)}_{lit}", f"{t.name}_{lit}"):
            return ast.EnumLiteral(t, ast.Pos("<instantiation>", 1, 1), t, lit)
    return None


def value(d: Definition, node: Node, t: ast.Type) -> ast.Expr:
    """A value of type `t` written in CSPm: a number, `true`/`false`, an enumeration literal, or a
    record as the tuple of its fields."""
    pos = d.at(node)
    if isinstance(node, Tree) and node.data == "tuple" and not isinstance(t, ast.RecordType):
        raise NotUnderstood(pos, f"a tuple is not a value of type {t}")
    if t in ast.NUMERIC or isinstance(t, ast.GivenType):
        n = number(d, node)
        if t != ast.REAL and n.denominator != 1:
            raise NotUnderstood(pos, f"{n} is not a value of type {t}")
        if t == ast.NAT and n < 0:
            raise NotUnderstood(pos, f"{n} is not a value of type nat")
        kind = t if t == ast.REAL or isinstance(t, ast.GivenType) else (ast.NAT if n >= 0 else ast.INT)
        return ast.Literal(kind, pos, n if t == ast.REAL else int(n))
    if t == ast.BOOLEAN:
        if isinstance(node, Tree) and node.data in ("true", "false"):
            return ast.Literal(ast.BOOLEAN, pos, node.data == "true")
        raise NotUnderstood(pos, "expected true or false")
    if isinstance(t, ast.EnumType):
        if isinstance(node, Tree) and node.data == "name":
            lit = enum_literal(str(node.children[0]), t)
            if lit is not None:
                return dataclasses.replace(lit, pos=pos)
        literals = ", ".join(f"{mangle(t.qname)}_{x}" for x in t.literals)
        raise NotUnderstood(pos, f"expected a literal of {t.name} ({literals})")
    if isinstance(t, ast.RecordType):
        while isinstance(node, Tree) and node.data == "tuple" and len(node.children) == 1:
            node = node.children[0]
        parts = node.children if isinstance(node, Tree) and node.data == "tuple" else [node]
        if len(t.fields) == 1 and len(parts) == 1:
            return ast.RecordLiteral(t, pos, ((t.fields[0].name, value(d, parts[0], t.fields[0].type)),))
        if len(parts) != len(t.fields):
            raise NotUnderstood(pos, f"a {t.name} is a tuple of its {len(t.fields)} fields in order")
        return ast.RecordLiteral(t, pos, tuple((f.name, value(d, p, f.type))
                                                for f, p in zip(t.fields, parts, strict=True)))
    raise NotUnderstood(pos, f"values of type {t} are not read from an instantiation")


# ----------------------------------------------------------------------------- functions

_OPS = {"and_": "and", "or_": "or"}
# RoboTool's bounded arithmetic helpers of instantiations.csp (`Plus(e1, e2, T)`), by name: the
# operator and how many operands come before the type argument.
_BOUNDED_ARITHMETIC = {"Plus": ("+", 2), "Minus": ("-", 2), "Mult": ("*", 2), "Div": ("/", 2),
                       "Modulus": ("%", 2), "Neg": ("neg", 1)}
# How many calls deep a body is unfolded (a recursive function over a sequence: about one call per
# item), and the most expression nodes an unfolded body may have; past either, the function is
# undefined there, so any value (its precondition says where).
UNFOLD_DEPTHS = (8, 6, 4, 3, 2)
MAX_BODY_NODES = 6_000


class _Built(NamedTuple):
    """A CSPm expression as a model expression, and when evaluating it gets stuck (None: never).

    It gets stuck where no clause of a function matches its arguments (CSPm's evaluation error) and
    where calls nest deeper than the unfolding goes. `expr` is None where it always does; elsewhere
    it is the value wherever it does not (what it is where it does is never used)."""

    expr: ast.Expr | None
    stuck: ast.Expr | None


@dataclass(frozen=True)
class _Local:
    """A function of the instantiation, or of a `let`, to unfold where it is called: its clauses
    and the names they see (for a `let`'s, those of the `let`, its own functions included)."""

    name: str
    clauses: tuple[Definition, ...]
    scope: dict[str, object]


_STUCK: _Built = _Built(None, None)


class FunctionBody:
    """Turns the clauses of an instantiation function into the model function's definition.

    Understood: parameters bound by name or matched against patterns (enumeration literals, numbers,
    `true`/`false`, `<>`, `<x, y>`, `<x>^s`, `s^<x>`), numbers, booleans, enumeration literals, a
    record's fields read as RoboTool writes them (`pkg_Rec_field(r)`), arithmetic, comparisons (of
    given types' values too, numbers in RoboTool's instance), `and`/`or`/`not`, `if … then … else`,
    `#s`, `s ^ t`, `let` of values and of functions, and calls of the model's functions or of the
    instantiation's own functions, recursive ones included. A call of the instantiation's functions
    is unfolded (CSPm evaluates it the same way), up to `UNFOLD_DEPTHS` calls deep: the function is
    defined where its evaluation ends within that depth, and anything (docs/semantics.md §6.4) where
    it does not or where no clause matches; its precondition says which.
    """

    def __init__(self, functions: dict[str, ast.Function], helpers: dict[str, list[Definition]],
                 enums: list[ast.EnumType], records: list[ast.RecordType] | None = None):
        self.functions = functions  # RoboTool name -> model function
        self.helpers = {name: _Local(name, tuple(ds), {}) for name, ds in helpers.items()}
        self.enums = enums
        self.fields: dict[str, tuple[ast.RecordType, str]] = {}  # RoboTool's field reader -> record, field
        for t in records or ():
            for f in t.fields:
                for prefix in (mangle(t.qname), t.name):
                    self.fields.setdefault(f"{prefix}_{f.name}", (t, f.name))
        self.depth_limit = UNFOLD_DEPTHS[0]
        self.defining: tuple[str, _Local] | None = None

    def define(self, f: ast.Function, clauses: list[Definition]) -> ast.Function:
        """`f` defined by its clauses: the first clause whose patterns match applies, unfolded as
        deep as `UNFOLD_DEPTHS` allows; where none applies or the unfolding stops, the function is
        undefined, hence any value (its precondition)."""
        for d in clauses:
            if len(d.params or ()) != len(f.parameters):
                raise NotUnderstood(d.pos, f"{f.name} takes {len(f.parameters)} argument(s), this clause "
                                           f"{len(d.params or ())}")
        pos = clauses[0].pos
        args = [_Built(ast.VarRef(p.type, pos, p), None) for p in f.parameters]
        own = _Local(mangle(f.qname), tuple(clauses), {})
        built = None
        for depth in UNFOLD_DEPTHS:
            self.depth_limit = depth
            self.defining = (own.name, own)
            try:
                built = self._unfold(own, args, pos, 0)
            finally:
                self.defining = None
            size = ast.tree_size(built.expr, MAX_BODY_NODES) + ast.tree_size(built.stuck, MAX_BODY_NODES)
            if built.expr is not None and size <= MAX_BODY_NODES:
                break
        assert built is not None
        if built.expr is None:
            raise NotUnderstood(pos, f"{f.name} gives no value within {self.depth_limit} nested calls")
        if ast.tree_size(built.expr, MAX_BODY_NODES) > MAX_BODY_NODES:
            raise NotUnderstood(pos, f"{f.name} unfolds to more than {MAX_BODY_NODES} expression nodes")
        body = built.expr
        if not (ast.assignable(f.result, body.type) or _given_number(f.result, body.type)):
            raise NotUnderstood(clauses[0].at(clauses[0].body), f"{f.name} returns {f.result}, this is {body.type}")
        pre = () if built.stuck is None else (_not(built.stuck),)
        return dataclasses.replace(f, definition=body, preconditions=pre, postconditions=())

    def _literal(self, name: str, pos: ast.Pos) -> ast.EnumLiteral | None:
        for t in self.enums:
            lit = enum_literal(name, t)
            if lit is not None:
                return dataclasses.replace(lit, pos=pos)
        return None

    # --- calls

    def _unfold(self, fn: _Local, args: list[_Built], pos: ast.Pos, depth: int) -> _Built:
        """A call of `fn`: its clauses in order, each where its patterns match the arguments."""
        if any(a.expr is None for a in args):
            return _STUCK
        if depth >= self.depth_limit:
            return _STUCK
        stuck = _any_of([a.stuck for a in args])
        branches: list[tuple[ast.Expr | None, _Built]] = []
        for d in fn.clauses:
            params = d.params or ()
            if len(params) != len(args):
                raise NotUnderstood(pos, f"'{fn.name}' takes {len(params)} argument(s)")
            scope = dict(fn.scope)
            conditions: list[ast.Expr] = []
            for p, a in zip(params, args, strict=True):
                assert a.expr is not None
                conditions += self._match(d, p, a.expr, scope)
            body = self.expr(d, d.body, scope, depth + 1)
            branches.append((_all_of(conditions), body))
            if not conditions:
                break  # later clauses are never reached
        result = _STUCK  # no clause matches: CSPm's evaluation stops with an error
        for condition, body in reversed(branches):
            result = body if condition is None else self._if(_Built(condition, None), body, result, pos)
        return _Built(result.expr, _or(stuck, result.stuck) if result.expr is not None else None)

    def _match(self, d: Definition, p: Node, arg: ast.Expr, scope: dict[str, object]) -> list[ast.Expr]:
        """The conditions under which `arg` matches pattern `p`, binding its names in `scope`."""
        pos = d.at(p)
        if isinstance(p, Tree) and p.data == "name" and self._literal(str(p.children[0]), pos) is None:
            scope[str(p.children[0])] = _Built(arg, None)
            return []
        if isinstance(p, Tree) and p.data in ("sequence", "concat"):
            if not isinstance(arg.type, ast.SeqType):
                raise NotUnderstood(pos, f"a sequence pattern for a value of type {arg.type}")
            return self._match_sequence(d, p, arg, scope)
        value = self.expr(d, p, {}, 0)
        if value.expr is None or value.stuck is not None:
            raise NotUnderstood(pos, "a pattern tockbmc does not match")
        return [_eq(arg, value.expr)]

    def _match_sequence(self, d: Definition, p: Tree, arg: ast.Expr, scope: dict[str, object]) -> list[ast.Expr]:
        pos = d.at(p)
        t = arg.type
        assert isinstance(t, ast.SeqType)

        def items(seq: Tree, from_end: bool) -> list[ast.Expr]:
            """Conditions for the items `<x, …>` of `seq` at the start (or the end) of `arg`."""
            out: list[ast.Expr] = []
            kids = _kids(seq)
            for k, item in enumerate(kids):
                if from_end:
                    element = _builtin("last", t.element, pos, _drop("front", arg, len(kids) - 1 - k, t, pos))
                else:
                    element = _builtin("head", t.element, pos, _drop("tail", arg, k, t, pos))
                out += self._match(d, item, element, scope)
            return out

        size = _builtin("size", ast.NAT, pos, arg)
        if p.data == "sequence":
            n = len(_kids(p))
            return [_compare("==", size, _number(n, pos)), *items(p, False)]
        left, right = _kids(p)
        if isinstance(left, Tree) and left.data == "sequence" and isinstance(right, Tree) and right.data == "name":
            n = len(_kids(left))
            return [_compare(">=", size, _number(n, pos)), *items(left, False),
                    *self._match(d, right, _drop("tail", arg, n, t, pos), scope)]
        if isinstance(right, Tree) and right.data == "sequence" and isinstance(left, Tree) and left.data == "name":
            n = len(_kids(right))
            return [_compare(">=", size, _number(n, pos)), *items(right, True),
                    *self._match(d, left, _drop("front", arg, n, t, pos), scope)]
        raise NotUnderstood(pos, "a sequence pattern other than <…>, <…>^s or s^<…>")

    def _call(self, d: Definition, name: str, args: list[_Built], scope: dict[str, object], pos: ast.Pos,
              depth: int) -> _Built:
        local = scope.get(name)
        if isinstance(local, _Local):
            return self._unfold(local, args, pos, depth)
        if self.defining is not None and name == self.defining[0]:
            return self._unfold(self.defining[1], args, pos, depth)
        if name in self.functions:
            f = self.functions[name]
            if len(args) != len(f.parameters):
                raise NotUnderstood(pos, f"{f.name} takes {len(f.parameters)} argument(s)")
            return _strict(args, lambda xs: ast.Call(f.result, pos, f, tuple(xs)))
        if name in self.fields and len(args) == 1:
            record, field = self.fields[name]
            [a] = args
            if a.expr is not None and not ast.comparable(a.expr.type, record):
                raise NotUnderstood(pos, f"'{name}' reads a {record.name}, this is {a.expr.type}")
            ftype = next(f.type for f in record.fields if f.name == field)
            return _strict(args, lambda xs: ast.FieldRef(ftype, pos, xs[0], field))
        if name in self.helpers:
            return self._unfold(self.helpers[name], args, pos, depth)
        raise NotUnderstood(pos, f"'{name}' is neither a function of the model nor defined here")

    # --- expressions

    def expr(self, d: Definition, node: Node, scope: dict[str, object], depth: int) -> _Built:
        pos = d.at(node)
        if not isinstance(node, Tree):
            raise NotUnderstood(pos, "unexpected token")
        kind = node.data
        kids = _kids(node)
        if kind == "number":
            return _Built(_number(int(str(kids[0])), pos), None)
        if kind in ("true", "false"):
            return _Built(ast.Literal(ast.BOOLEAN, pos, kind == "true"), None)
        if kind == "name":
            name = str(kids[0])
            bound = scope.get(name)
            if isinstance(bound, _Built):
                return bound
            lit = self._literal(name, pos)
            if lit is not None:
                return _Built(lit, None)
            if name in self.helpers and self.helpers[name].clauses[0].params is None:
                return self._unfold(self.helpers[name], [], pos, depth)
            raise NotUnderstood(pos, f"'{name}' is not a parameter, a literal or a value defined here")
        if kind == "negate":
            [x] = [self.expr(d, kids[0], scope, depth)]
            if x.expr is not None:
                _numeric(x.expr, pos)
            return _strict([x], lambda xs: ast.Unary(ast.INT if xs[0].type == ast.NAT else xs[0].type, pos, "-", xs[0]))
        if kind == "not_":
            x = self.expr(d, kids[0], scope, depth)
            if x.expr is not None:
                _boolean(x.expr, pos)
            return _strict([x], lambda xs: ast.Unary(ast.BOOLEAN, pos, "not", xs[0]))
        if kind in _OPS:
            operands = [self.expr(d, k, scope, depth) for k in kids]
            for x in operands:
                if x.expr is not None:
                    _boolean(x.expr, pos)
            return _strict(operands, lambda xs: ast.Binary(ast.BOOLEAN, pos, _OPS[kind], xs[0], xs[1]))
        if kind == "compare":
            left, right = self.expr(d, kids[0], scope, depth), self.expr(d, kids[2], scope, depth)
            op = str(kids[1].children[0]) if isinstance(kids[1], Tree) else str(kids[1])
            return _strict([left, right], lambda xs: _compare(op, xs[0], xs[1]))
        if kind == "arith":
            left, right = self.expr(d, kids[0], scope, depth), self.expr(d, kids[2], scope, depth)
            return _strict([left, right], lambda xs: _arith(str(kids[1]), xs[0], xs[1], pos))
        if kind == "length":
            x = self.expr(d, kids[0], scope, depth)
            if x.expr is not None and not isinstance(x.expr.type, (ast.SeqType, ast.SetType)):
                raise NotUnderstood(pos, f"# of a value of type {x.expr.type}")
            return _strict([x], lambda xs: _builtin("size", ast.NAT, pos, xs[0]))
        if kind == "concat":
            left, right = self.expr(d, kids[0], scope, depth), self.expr(d, kids[1], scope, depth)

            def concat(xs: list[ast.Expr]) -> ast.Expr:
                t = expressions.builtin_type("concat", [xs[0].type, xs[1].type])
                if t is None:
                    raise NotUnderstood(pos, f"^ of values of types {xs[0].type} and {xs[1].type}")
                return ast.Builtin(t, pos, "concat", (xs[0], xs[1]))
            return _strict([left, right], concat)
        if kind == "sequence" and kids:
            items = [self.expr(d, k, scope, depth) for k in kids]
            return _strict(items, lambda xs: _sequence(xs, pos))
        if kind == "if_":
            c, a, b = (self.expr(d, k, scope, depth) for k in kids)
            if c.expr is not None:
                _boolean(c.expr, pos)
            return self._if(c, a, b, pos)
        if kind == "let":
            inner: dict[str, object] = dict(scope)
            local_clauses: dict[str, list[Definition]] = {}
            for local in kids[:-1]:
                assert isinstance(local, Tree)
                lname = str(local.children[0])
                if len(local.children) == 3:
                    params = tuple(c for c in local.children[1].children if isinstance(c, (Tree, Token)))
                    local_clauses.setdefault(lname, []).append(
                        Definition(lname, params, local.children[-1], d.at(local), locate=d.locate))
                else:
                    inner[lname] = self.expr(d, local.children[-1], inner, depth)
            for lname, ds in local_clauses.items():
                inner[lname] = _Local(lname, tuple(ds), inner)  # its scope is the let's, itself included
            return self.expr(d, kids[-1], inner, depth)
        if kind == "apply":
            head, args = kids[0], kids[1:]
            if not (isinstance(head, Tree) and head.data == "name"):
                raise NotUnderstood(pos, "only named functions are applied")
            name = str(head.children[0])
            if name in _BOUNDED_ARITHMETIC and len(args) == _BOUNDED_ARITHMETIC[name][1] + 1 and name not in scope:
                # RoboTool's bounded arithmetic `Plus(a, b, core_nat)`: tockbmc's is exact
                # (docs/semantics.md §6.5), so the type argument is dropped, as the helpers are.
                operands = [self.expr(d, a, scope, depth) for a in args[:-1]]
                op = _BOUNDED_ARITHMETIC[name][0]
                if op == "neg":
                    return self.expr(d, Tree("negate", [args[0]], meta=node.meta), scope, depth)
                return _strict(operands, lambda xs: _arith(op, xs[0], xs[1], pos))
            return self._call(d, name, [self.expr(d, a, scope, depth) for a in args], scope, pos, depth)
        raise NotUnderstood(pos, f"{_describe(kind)} cannot be a function body tockbmc runs")

    def _if(self, c: _Built, a: _Built, b: _Built, pos: ast.Pos) -> _Built:
        """`if c then a else b`: stuck where `c` is, or where the branch taken is."""
        if c.expr is None or (a.expr is None and b.expr is None):
            return _STUCK
        if a.expr is None:  # wherever c holds it is stuck, so the value is b's
            return _Built(b.expr, _or(c.stuck, _or(c.expr, b.stuck)))
        if b.expr is None:
            return _Built(a.expr, _or(c.stuck, _or(_not(c.expr), a.stuck)))
        rtype = _join(a.expr.type, b.expr.type)
        if rtype is None:
            raise NotUnderstood(pos, f"the branches of 'if' have types {a.expr.type} and {b.expr.type}")
        stuck = _or(c.stuck, _or(_and(c.expr, a.stuck), _and(_not(c.expr), b.stuck)))
        return _Built(ast.IfExpr(rtype, pos, c.expr, a.expr, b.expr), stuck)


def _strict(operands: list[_Built], make: Callable[[list[ast.Expr]], ast.Expr]) -> _Built:
    """An operation of these operands: stuck wherever one of them is."""
    if any(x.expr is None for x in operands):
        return _STUCK
    return _Built(make([x.expr for x in operands]), _any_of([x.stuck for x in operands]))  # type: ignore[misc]


def _number(n: int, pos: ast.Pos) -> ast.Expr:
    return ast.Literal(ast.NAT, pos, n)


def _builtin(op: str, t: ast.Type, pos: ast.Pos, *args: ast.Expr) -> ast.Expr:
    return ast.Builtin(t, pos, op, args)


def _kids(node: Tree) -> list[Node]:
    return [c for c in node.children if isinstance(c, (Tree, Token))]


def _drop(op: str, s: ast.Expr, n: int, t: ast.Type, pos: ast.Pos) -> ast.Expr:
    """`s` without its first (`tail`) or last (`front`) n items."""
    for _ in range(n):
        s = _builtin(op, t, pos, s)
    return s


def _sequence(items: list[ast.Expr], pos: ast.Pos) -> ast.Expr:
    t = items[0].type
    for x in items[1:]:
        joined = _join(t, x.type)
        if joined is None:
            raise NotUnderstood(pos, f"a sequence of values of types {t} and {x.type}")
        t = joined
    return ast.SeqLiteral(ast.SeqType(t), pos, tuple(items))


def _given_number(a: ast.Type, b: ast.Type) -> bool:
    """A given type's values are numbers in RoboTool's instance (`nametype Intensity = {0,1}`), and
    integers in both of tockbmc's engines: an integer stands for one."""
    return isinstance(a, ast.GivenType) and b in (ast.NAT, ast.INT)


def _join(a: ast.Type, b: ast.Type) -> ast.Type | None:
    """The type of a value that is either of these, or None."""
    if ast.is_numeric(a) and ast.is_numeric(b):
        return ast.numeric_join(a, b)
    if _given_number(a, b):
        return a
    if _given_number(b, a):
        return b
    if ast.assignable(a, b):
        return a
    if ast.assignable(b, a):
        return b
    return None


def _orderable(t: ast.Type) -> bool:
    return ast.is_numeric(t) or isinstance(t, ast.GivenType)


def _compare(op: str, left: ast.Expr, right: ast.Expr) -> ast.Expr:
    pos = left.pos
    if op in ("==", "!="):
        if _join(left.type, right.type) is None:
            raise NotUnderstood(pos, f"cannot compare {left.type} with {right.type}")
    elif not (_orderable(left.type) and _orderable(right.type) and _join(left.type, right.type) is not None):
        raise NotUnderstood(pos, f"cannot order {left.type} and {right.type}")
    return ast.Binary(ast.BOOLEAN, pos, op, left, right)


def _arith(op: str, left: ast.Expr, right: ast.Expr, pos: ast.Pos) -> ast.Expr:
    _numeric(left, pos)
    _numeric(right, pos)
    rtype = ast.numeric_join(left.type, right.type)
    if op == "-" and rtype == ast.NAT:
        rtype = ast.INT
    return ast.Binary(rtype, pos, op, left, right)


def _not(e: ast.Expr) -> ast.Expr:
    if isinstance(e, ast.Literal) and isinstance(e.value, bool):
        return ast.Literal(ast.BOOLEAN, e.pos, not e.value)
    return ast.Unary(ast.BOOLEAN, e.pos, "not", e)


def _or(a: ast.Expr | None, b: ast.Expr | None) -> ast.Expr | None:
    """Disjunction, where None is false."""
    if a is None or b is None:
        return b if a is None else a
    return ast.Binary(ast.BOOLEAN, a.pos, "or", a, b)


def _and(a: ast.Expr, b: ast.Expr | None) -> ast.Expr | None:
    """Conjunction of a condition with a stuck condition (None: false)."""
    if b is None:
        return None
    return ast.Binary(ast.BOOLEAN, a.pos, "and", a, b)


def _any_of(cs: list[ast.Expr | None]) -> ast.Expr | None:
    out = None
    for c in cs:
        out = _or(out, c)
    return out


def _all_of(cs: list[ast.Expr]) -> ast.Expr | None:
    if not cs:
        return None
    out = cs[0]
    for c in cs[1:]:
        out = ast.Binary(ast.BOOLEAN, c.pos, "and", out, c)
    return out


_DESCRIPTIONS = {"set": "a set", "interval": "a set", "comprehension": "a set", "sequence": "an empty sequence",
                 "sequence_comprehension": "a sequence", "tuple": "a tuple", "dot": "a dotted (channel or datatype) value"}


def _describe(kind: str) -> str:
    return _DESCRIPTIONS.get(kind, f"'{kind}'")


def _numeric(e: ast.Expr, pos: ast.Pos) -> None:
    if not ast.is_numeric(e.type):
        raise NotUnderstood(pos, f"expected a number, this is {e.type}")


def _boolean(e: ast.Expr, pos: ast.Pos) -> None:
    if e.type != ast.BOOLEAN:
        raise NotUnderstood(pos, f"expected a boolean, this is {e.type}")


def _eq(a: ast.Expr, b: ast.Expr) -> ast.Expr:
    if _join(a.type, b.type) is None:
        raise NotUnderstood(b.pos, f"a pattern of type {b.type} for a parameter of type {a.type}")
    return ast.Binary(ast.BOOLEAN, b.pos, "==", a, b)


# ----------------------------------------------------------------------------- the project


def with_functions(project: ast.Project, defined: dict[int, ast.Function]) -> ast.Project:
    """The project with each function `id(f) -> g` of `defined` replaced by `g` everywhere it is
    called.  Parts that call none of them stay the same objects (engines key them by identity)."""
    if not defined:
        return project
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 20_000))
    try:
        return replaced(project, dict(defined), {})
    finally:
        sys.setrecursionlimit(limit)


def replaced(project: ast.Project, new: dict[int, object], memo: dict[int, object]) -> ast.Project:
    """The project with each part `id(old) -> new` of `new` (a function, a variable) put in its
    place everywhere it occurs; `memo` is left mapping the id of every part rebuilt to what it
    became.  Parts that hold none of them stay the same objects (engines key them by identity)."""
    out = _rebuild(project, new, memo)
    assert isinstance(out, ast.Project)
    return out


def _rebuild(obj: object, defined: dict[int, object], memo: dict[int, object]) -> object:
    key = id(obj)
    if key in memo:
        return memo[key]
    out: object = obj
    if key in defined:
        out = defined[key]
        # the new part may itself hold replaced ones (a definition calling a replaced function)
        out = _rebuild_fields(out, defined, memo)
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        out = _rebuild_fields(obj, defined, memo)
    elif isinstance(obj, tuple):
        items = [_rebuild(x, defined, memo) for x in obj]
        if any(a is not b for a, b in zip(items, obj, strict=True)):
            out = tuple(items)
    elif isinstance(obj, dict):
        pairs = {k: _rebuild(v, defined, memo) for k, v in obj.items()}
        if any(pairs[k] is not v for k, v in obj.items()):
            out = pairs
    memo[key] = out
    return out


def _rebuild_fields(obj: object, defined: dict[int, object], memo: dict[int, object]) -> object:
    changes = {}
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        if not f.compare:  # caches and texts, not structure
            continue
        old = getattr(obj, f.name)
        new = _rebuild(old, defined, memo)
        if new is not old:
            changes[f.name] = new
    return dataclasses.replace(obj, **changes) if changes else obj  # type: ignore[type-var]
