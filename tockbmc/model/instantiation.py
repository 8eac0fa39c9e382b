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
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from pathlib import Path

from lark import Lark, Token, Tree, UnexpectedInput

from tockbmc.model import ast, grammars
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


def number(d: Definition, node: Node) -> Fraction:
    """An integer constant expression: a number, a negation, arithmetic of numbers."""
    if isinstance(node, Tree):
        if node.data == "number":
            return Fraction(int(str(node.children[0])))
        if node.data == "negate":
            return -number(d, node.children[0])
        if node.data == "arith":
            left, op, right = node.children
            a, b = number(d, left), number(d, right)
            if str(op) == "+":
                return a + b
            if str(op) == "-":
                return a - b
            if str(op) == "*":
                return a * b
    raise NotUnderstood(d.at(node), "expected a number")


def interval(d: Definition, node: Node) -> tuple[Fraction, Fraction]:
    """`{a..b}`, or a set of integers without gaps (`{-1,0,1}`), as its bounds."""
    if isinstance(node, Tree) and node.data == "interval":
        low, high = number(d, node.children[0]), number(d, node.children[1])
        if low > high:
            raise NotUnderstood(d.at(node), "an empty interval")
        return low, high
    if isinstance(node, Tree) and node.data == "set" and node.children:
        values = sorted({number(d, c) for c in node.children})
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
_MAX_INLINE = 16


class FunctionBody:
    """Turns the clauses of an instantiation function into the model function's definition.

    Understood: parameters bound by name or matched against enumeration literals and numbers,
    numbers, booleans, enumeration literals, arithmetic, comparisons, `and`/`or`/`not`,
    `if … then … else`, `let` of values, and calls of the model's functions or of other
    (non-recursive) functions of the instantiation, which are inlined.
    """

    def __init__(self, functions: dict[str, ast.Function], helpers: dict[str, list[Definition]],
                 enums: list[ast.EnumType]):
        self.functions = functions  # RoboTool name -> model function
        self.helpers = helpers  # other definitions of the instantiation, by name
        self.enums = enums

    def define(self, f: ast.Function, clauses: list[Definition]) -> ast.Function:
        """`f` defined by its clauses: the first clause whose patterns match applies; where none
        does (a function given only on some literals), the function is undefined, hence any value."""
        branches: list[tuple[ast.Expr | None, ast.Expr]] = []
        for d in clauses:
            params = d.params or ()
            if len(params) != len(f.parameters):
                raise NotUnderstood(d.pos, f"{f.name} takes {len(f.parameters)} argument(s), this clause "
                                           f"{len(params)}")
            env: dict[str, ast.Expr] = {}
            conditions: list[ast.Expr] = []
            for p, var in zip(params, f.parameters, strict=True):
                ref = ast.VarRef(var.type, d.at(p), var)
                if isinstance(p, Tree) and p.data == "name" and self._literal(str(p.children[0]), d.at(p)) is None:
                    env[str(p.children[0])] = ref
                else:
                    conditions.append(_eq(ref, self.expr(d, p, {}, 0)))
            body = self.expr(d, d.body, env, 0)
            if not ast.assignable(f.result, body.type):
                raise NotUnderstood(d.at(d.body), f"{f.name} returns {f.result}, this is {body.type}")
            branches.append((_all(conditions) if conditions else None, body))
        definition = branches[-1][1]
        for condition, body in reversed(branches[:-1]):
            definition = body if condition is None else ast.IfExpr(f.result, body.pos, condition, body, definition)
        covered = None if any(c is None for c, _ in branches) else _any([c for c, _ in branches if c is not None])
        return dataclasses.replace(f, definition=definition, preconditions=() if covered is None else (covered,),
                                   postconditions=())

    def _literal(self, name: str, pos: ast.Pos) -> ast.EnumLiteral | None:
        for t in self.enums:
            lit = enum_literal(name, t)
            if lit is not None:
                return dataclasses.replace(lit, pos=pos)
        return None

    def expr(self, d: Definition, node: Node, env: dict[str, ast.Expr], depth: int) -> ast.Expr:
        pos = d.at(node)
        if not isinstance(node, Tree):
            raise NotUnderstood(pos, "unexpected token")
        kind = node.data
        kids = [c for c in node.children if isinstance(c, (Tree, Token))]
        if kind == "number":
            n = int(str(kids[0]))
            return ast.Literal(ast.NAT, pos, n)
        if kind in ("true", "false"):
            return ast.Literal(ast.BOOLEAN, pos, kind == "true")
        if kind == "name":
            name = str(kids[0])
            if name in env:
                return env[name]
            lit = self._literal(name, pos)
            if lit is not None:
                return lit
            if name in self.helpers and self.helpers[name][0].params is None:
                return self._inline(name, [], pos, depth)
            raise NotUnderstood(pos, f"'{name}' is not a parameter, a literal or a value defined here")
        if kind == "negate":
            operand = self.expr(d, kids[0], env, depth)
            _numeric(operand, pos)
            return ast.Unary(ast.INT if operand.type == ast.NAT else operand.type, pos, "-", operand)
        if kind == "not_":
            operand = self.expr(d, kids[0], env, depth)
            _boolean(operand, pos)
            return ast.Unary(ast.BOOLEAN, pos, "not", operand)
        if kind in _OPS:
            left, right = (self.expr(d, k, env, depth) for k in kids)
            _boolean(left, pos)
            _boolean(right, pos)
            return ast.Binary(ast.BOOLEAN, pos, _OPS[kind], left, right)
        if kind == "compare":
            left, right = self.expr(d, kids[0], env, depth), self.expr(d, kids[2], env, depth)
            op = str(kids[1].children[0]) if isinstance(kids[1], Tree) else str(kids[1])
            if op in ("==", "!="):
                if not ast.comparable(left.type, right.type):
                    raise NotUnderstood(pos, f"cannot compare {left.type} with {right.type}")
            else:
                _numeric(left, pos)
                _numeric(right, pos)
            return ast.Binary(ast.BOOLEAN, pos, op, left, right)
        if kind == "arith":
            left, op, right = self.expr(d, kids[0], env, depth), str(kids[1]), self.expr(d, kids[2], env, depth)
            _numeric(left, pos)
            _numeric(right, pos)
            rtype = ast.numeric_join(left.type, right.type)
            if op in ("-", "/") and rtype == ast.NAT:
                rtype = ast.INT if op == "-" else rtype
            return ast.Binary(rtype, pos, op, left, right)
        if kind == "if_":
            c, a, b = (self.expr(d, k, env, depth) for k in kids)
            _boolean(c, pos)
            if ast.is_numeric(a.type) and ast.is_numeric(b.type):
                rtype = ast.numeric_join(a.type, b.type)
            elif ast.comparable(a.type, b.type):
                rtype = a.type
            else:
                raise NotUnderstood(pos, f"the branches of 'if' have types {a.type} and {b.type}")
            return ast.IfExpr(rtype, pos, c, a, b)
        if kind == "let":
            inner = dict(env)
            for local in kids[:-1]:
                assert isinstance(local, Tree)
                lname = str(local.children[0])
                if len(local.children) == 3:
                    raise NotUnderstood(d.at(local), f"'{lname}' is a local function; tockbmc inlines only values "
                                                     "in a let")
                inner[lname] = self.expr(d, local.children[-1], inner, depth)
            return self.expr(d, kids[-1], inner, depth)
        if kind == "apply":
            head, args = kids[0], kids[1:]
            if not (isinstance(head, Tree) and head.data == "name"):
                raise NotUnderstood(pos, "only named functions are applied")
            name = str(head.children[0])
            if name in _BOUNDED_ARITHMETIC and len(args) == _BOUNDED_ARITHMETIC[name][1] + 1:
                # RoboTool's bounded arithmetic `Plus(a, b, core_nat)`: tockbmc's is exact
                # (docs/semantics.md §6.5), so the type argument is dropped, as the helpers are.
                operands = [self.expr(d, a, env, depth) for a in args[:-1]]
                for x in operands:
                    _numeric(x, pos)
                op = _BOUNDED_ARITHMETIC[name][0]
                if op == "neg":
                    [x] = operands
                    return ast.Unary(ast.INT if x.type == ast.NAT else x.type, pos, "-", x)
                left, right = operands
                rtype = ast.numeric_join(left.type, right.type)
                if op == "-" and rtype == ast.NAT:
                    rtype = ast.INT
                return ast.Binary(rtype, pos, op, left, right)
            values = [self.expr(d, a, env, depth) for a in args]
            if name in self.functions:
                f = self.functions[name]
                if len(values) != len(f.parameters):
                    raise NotUnderstood(pos, f"{f.name} takes {len(f.parameters)} argument(s)")
                return ast.Call(f.result, pos, f, tuple(values))
            if name in self.helpers:
                return self._inline(name, values, pos, depth)
            raise NotUnderstood(pos, f"'{name}' is neither a function of the model nor defined here")
        raise NotUnderstood(pos, f"{_describe(kind)} cannot be a function body tockbmc runs")

    def _inline(self, name: str, args: list[ast.Expr], pos: ast.Pos, depth: int) -> ast.Expr:
        if depth >= _MAX_INLINE:
            raise NotUnderstood(pos, f"'{name}' is recursive (or nested too deeply) to be inlined")
        clauses = self.helpers[name]
        if len(clauses) != 1:
            raise NotUnderstood(pos, f"'{name}' is defined by {len(clauses)} clauses; only one is inlined")
        d = clauses[0]
        params = d.params or ()
        if len(params) != len(args):
            raise NotUnderstood(pos, f"'{name}' takes {len(params)} argument(s)")
        env: dict[str, ast.Expr] = {}
        for p, a in zip(params, args, strict=True):
            if not (isinstance(p, Tree) and p.data == "name"):
                raise NotUnderstood(d.at(p), f"'{name}' matches its arguments against patterns; tockbmc inlines "
                                             "functions with plain parameters")
            env[str(p.children[0])] = a
        return self.expr(d, d.body, env, depth + 1)


_DESCRIPTIONS = {"set": "a set", "interval": "a set", "comprehension": "a set", "sequence": "a sequence",
                 "sequence_comprehension": "a sequence", "tuple": "a tuple", "concat": "a sequence",
                 "length": "a sequence length", "dot": "a dotted (channel or datatype) value"}


def _describe(kind: str) -> str:
    return _DESCRIPTIONS.get(kind, f"'{kind}'")


def _numeric(e: ast.Expr, pos: ast.Pos) -> None:
    if not ast.is_numeric(e.type):
        raise NotUnderstood(pos, f"expected a number, this is {e.type}")


def _boolean(e: ast.Expr, pos: ast.Pos) -> None:
    if e.type != ast.BOOLEAN:
        raise NotUnderstood(pos, f"expected a boolean, this is {e.type}")


def _eq(a: ast.Expr, b: ast.Expr) -> ast.Expr:
    if not ast.comparable(a.type, b.type):
        raise NotUnderstood(b.pos, f"a pattern of type {b.type} for a parameter of type {a.type}")
    return ast.Binary(ast.BOOLEAN, b.pos, "==", a, b)


def _all(cs: list[ast.Expr]) -> ast.Expr:
    out = cs[0]
    for c in cs[1:]:
        out = ast.Binary(ast.BOOLEAN, c.pos, "and", out, c)
    return out


def _any(cs: list[ast.Expr]) -> ast.Expr:
    out = cs[0]
    for c in cs[1:]:
        out = ast.Binary(ast.BOOLEAN, c.pos, "or", out, c)
    return out


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
