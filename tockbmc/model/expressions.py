"""Resolve and type-check expressions, statements and communications.

A `Scope` says what names an expression may use; `ExprChecker` turns syntax
trees into the typed expressions and statements of `tockbmc.model.ast`,
reporting problems through a callback rather than raising, so that one run
reports every independent error.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from lark import Token, Tree

from tockbmc.model import ast
from tockbmc.model.ast import BOOLEAN, ERROR, INT, NAT, REAL, STRING, Pos
from tockbmc.model.diagnostics import suggestion
from tockbmc.model.numbers import max_digits, parse_int, parse_real
from tockbmc.model.rules import GRAMMAR, LIMIT, LINKING, TYPING
from tockbmc.model.scope import qname_text


class Report(Protocol):
    """Where an `ExprChecker` sends a problem (`Resolver.report`)."""

    def __call__(self, pos: Pos, message: str, severity: str = "error", rule: str = "") -> None: ...

# Constructs of the expression language that docs/language.md §6 lists as unsupported.
UNSUPPORTED_EXPRESSIONS = {
    "definite_description": "definite descriptions ('the')",
    "is_expr": "toolkits (type tests 'is')",
    "inverse_expr": "matrix inverses ('inverse')",
    "transpose_expr": "matrix transposes ('transpose')",
    "to_expr": "the expression 'to'",
    "from_expr": "the expression 'from'",
}

TRIGGER_PREDICATES = "trigger predicates ('[| … |]')"
# The end of the warning about a construct kept without a meaning (`ExprChecker.meaningless`).
PER_ASSERTION = "; the assertions that reach it are reported unsupported"

# The toolkit functions built in (RoboTool's sequence_toolkit, set_toolkit and the parts of
# relation_toolkit that read sequences), by name: how many arguments, and the kinds they take.
TOOLKIT_FUNCTIONS = {
    "size": 1, "head": 1, "last": 1, "tail": 1, "front": 1, "reverse": 1, "isNonEmpty": 1, "concat": 2,
    "filter": 2, "prefix": 2, "suffix": 2, "infix": 2, "dom": 1, "ran": 1, "elems": 1,
    "union": 2, "inter": 2, "diff": 2, "symetric_diff": 2, "notin": 2, "subseteq": 2, "subset": 2,
    "min": 1, "max": 1, "extract": 2, "override": 2, "range": 2,
}

# Built-ins of two sequences or two sets of one type: those giving one (their items' type the
# join of both), and those comparing them.
_JOINED = ("concat", "union", "inter", "diff", "symetric_diff")
_COMPARED = ("subseteq", "subset", "prefix", "suffix", "infix")

_ARITHMETIC = {"+", "-", "*", "/", "%"}
_ORDER = {"<", "<=", ">", ">="}
_EQUALITY = {"==", "!="}
_LOGIC = {"/\\": "and", "\\/": "or", "=>": "implies", "iff": "iff", "<=>": "iff"}


def pos_of(path: str, node: Tree | Token) -> Pos:
    """The source span of a tree or token."""
    if isinstance(node, Token):
        return Pos(path, node.line or 1, node.column or 1, node.end_line or 0, node.end_column or 0)
    meta = node.meta
    if getattr(meta, "empty", True):
        for child in node.children:
            if isinstance(child, (Tree, Token)):
                return pos_of(path, child)
        return Pos(path, 1, 1)
    return Pos(path, meta.line, meta.column, meta.end_line, meta.end_column)


@dataclass
class Scope:
    """The names visible to the expressions and statements of one element."""

    path: str
    owner: str
    variables: dict[str, ast.Variable] = field(default_factory=dict)
    events: dict[str, ast.Event] = field(default_factory=dict)
    clocks: dict[str, ast.Clock] = field(default_factory=dict)
    operations: dict[str, ast.OperationSig] = field(default_factory=dict)
    interfaces: set[str] = field(default_factory=set)  # qualified names of those it uses, provides or requires
    # Looks up a global name among functions, enumerations, operations, interfaces, types.
    resolve_global: Callable[[str, str], object | None] = lambda name, kind: None
    global_names: Callable[[str], list[str]] = lambda kind: []
    states: dict[str, str] = field(default_factory=dict)  # name or path -> node path
    result_type: ast.Type | None = None
    toolkit: bool = False  # the file imports a toolkit: its functions are unknown here
    # The instance of a generic function for bindings of its `?X` (None: could not be built).
    instantiate: Callable[[ast.Function, dict[str, ast.Type]], ast.Function | None] = lambda f, b: None


class ExprChecker:
    """Builds typed expressions and statements for one scope."""

    def __init__(self, scope: Scope, report: Report, resolve_type: Callable[[Tree], ast.Type],
                 kept: list[tuple[Pos, str]] | None = None):
        self.scope = scope
        self.report = report
        self.resolve_type = resolve_type
        # (position, what) of each construct kept without a meaning (`meaningless`), for the
        # resolver to refuse one an enclosing expression dropped (`Resolver.refuse_dropped`)
        self.kept = kept if kept is not None else []

    # ----------------------------------------------------------------- helpers

    def pos(self, node: Tree | Token) -> Pos:
        return pos_of(self.scope.path, node)

    def error(self, node: Tree | Token, message: str, rule: str = "") -> None:
        """An error at `node`, citing the RoboTool rule (`model.rules`) it enforces."""
        self.report(self.pos(node), message, rule=rule)

    def expect(self, node: Tree | Token, e: ast.Expr, expected: ast.Type, what: str, rule: str = TYPING) -> ast.Expr:
        """`e`, checked to fit a place of type `expected` (a literal retyped to it, `conform`);
        `rule` is RoboTool's check of that place (`VarInitType` for an initial value)."""
        e = conform(e, expected)
        if not ast.assignable(expected, e.type):
            self.error(node, f"type error: {what} must be {expected}, but this is {e.type}", rule=rule)
        return e

    def condition(self, node: Tree, rule: str = TYPING) -> ast.Expr:
        e = self.expr(node)
        return self.expect(node, e, BOOLEAN, "a condition", rule)

    def meaningless(self, node: Tree | Token, what: str) -> None:
        """A warning that `node`, which RoboTool accepts, has no meaning in tockbmc: the model loads,
        and the assertions that reach it are `unsupported` (`ast.unsupported_in`)."""
        self.report(self.pos(node), f"unsupported: {what}{PER_ASSERTION}", "warning")
        self.kept.append((self.pos(node), what))

    def _unsupported(self, node: Tree | Token, p: Pos, what: str) -> ast.Expr:
        """`node` kept as an `ast.UnsupportedExpr` (`meaningless`)."""
        self.meaningless(node, what)
        return ast.UnsupportedExpr(ERROR, p, what)

    def _unknown(self, node: Tree | Token, what: str, name: str, known: list[str]) -> None:
        self.error(node, f"unknown {what} '{name}'{suggestion(name, known)}", rule=LINKING)

    # ----------------------------------------------------------------- expressions

    def expr(self, node: Tree | Token) -> ast.Expr:
        """Resolve and type-check one expression tree."""
        p = self.pos(node)
        if isinstance(node, Token):  # pragma: no cover - the grammar wraps tokens
            self.error(node, "syntax error: expected an expression", rule=GRAMMAR)
            return ast.Literal(ERROR, p, 0)
        kind = node.data
        if kind in UNSUPPORTED_EXPRESSIONS:
            return self._unsupported(node, p, UNSUPPORTED_EXPRESSIONS[kind])
        method = getattr(self, f"_x_{kind}", None)
        if method is None:
            self.error(node, f"unsupported: expression '{kind}'")
            return ast.Literal(ERROR, p, 0)
        return method(node, p)

    def _x_int_lit(self, node: Tree, p: Pos) -> ast.Expr:
        value = parse_int(str(node.children[0]))
        if value is None:
            return self._too_long(node, p)
        return ast.Literal(NAT, p, value)

    def _x_float_lit(self, node: Tree, p: Pos) -> ast.Expr:
        value = parse_real(str(node.children[0]))
        if value is None:
            return self._too_long(node, p)
        return ast.Literal(REAL, p, value)

    def _too_long(self, node: Tree, p: Pos) -> ast.Expr:
        self.error(node, f"number literal too long: at most {max_digits()} digits", rule=LIMIT)
        return ast.Literal(ERROR, p, 0)

    def _x_bool_lit(self, node: Tree, p: Pos) -> ast.Expr:
        return ast.Literal(BOOLEAN, p, str(node.children[0]) == "true")

    def _x_string_lit(self, node: Tree, p: Pos) -> ast.Expr:
        text = str(node.children[0])[1:-1]
        return ast.Literal(STRING, p, text)

    def _x_result_expr(self, node: Tree, p: Pos) -> ast.Expr:
        if self.scope.result_type is None:
            self.error(node, "'result' is only meaningful in a function's postcondition", rule=TYPING)
            return ast.ResultRef(ERROR, p)
        return ast.ResultRef(self.scope.result_type, p)

    def _x_name_expr(self, node: Tree, p: Pos) -> ast.Expr:
        qn = node.children[0]
        name = qname_text(qn)
        var = self.scope.variables.get(name)
        if var is not None:
            return ast.VarRef(var.type, p, var)
        literal = self.enum_literal(name, p)
        if literal is not None:
            return literal
        enum = self.scope.resolve_global(name, "enum_literal")
        if isinstance(enum, ast.EnumType):  # RoboChart also accepts a literal's bare name
            return self._bare_literal(p, enum, name)
        function = self.scope.resolve_global(name, "function")
        if isinstance(function, ast.Function) and not function.generic and function.parameters:
            return function_value(function, p)
        if name in self.scope.events:
            self.error(node, f"'{name}' is an event, not a value", rule=LINKING)
            return ast.Literal(ERROR, p, 0)
        known = list(self.scope.variables) + self.scope.global_names("enum_literal")
        self._unknown(node, "name", name, known)
        return ast.Literal(ERROR, p, 0)

    def _bare_literal(self, p: Pos, enum: ast.EnumType, literal: str) -> ast.Expr:
        """A literal named without arguments: an error if it has parameters (`EM3` for `EM3(nat)`)."""
        wanted = enum.parameters(literal)
        if wanted:
            self.report(p, f"'{literal}' takes {len(wanted)} argument(s) ({', '.join(map(str, wanted))}): "
                           f"write {literal}(…)", rule="IncorrectNumberOfArguments")
            return ast.Literal(ERROR, p, 0)
        return ast.EnumLiteral(enum, p, enum, literal)

    def _is_literal(self, name: str) -> bool:
        """Whether `name` (`L` or `E::L`) names an enumeration literal."""
        if "::" not in name:
            return isinstance(self.scope.resolve_global(name, "enum_literal"), ast.EnumType)
        type_name, _, literal = name.rpartition("::")
        enum = self.scope.resolve_global(type_name, "type")
        return isinstance(enum, ast.EnumType) and literal in enum.literals

    def enum_literal(self, name: str, p: Pos) -> ast.Expr | None:
        if "::" not in name:
            return None
        type_name, _, literal = name.rpartition("::")
        enum = self.scope.resolve_global(type_name, "type")
        if isinstance(enum, ast.EnumType):
            if literal in enum.literals:
                return self._bare_literal(p, enum, literal)
            self.report(p, f"enumeration {enum.name} has no literal '{literal}'"
                        f"{suggestion(literal, list(enum.literals))}", rule=LINKING)
            return ast.Literal(ERROR, p, 0)
        return None

    def _x_select(self, node: Tree, p: Pos) -> ast.Expr:
        record = self.expr(node.children[0])
        field_name = str(node.children[1])
        if isinstance(record.type, ast.ErrorType):
            return ast.FieldRef(ERROR, p, record, field_name)
        if not isinstance(record.type, ast.RecordType):
            self.error(node, f"type error: '.{field_name}' selects a field, but this is {record.type}, not a record", rule=LINKING)
            return ast.FieldRef(ERROR, p, record, field_name)
        ftype = record.type.field_type(field_name)
        if ftype is None:
            known = [f.name for f in record.type.fields]
            self.error(node.children[1], f"record {record.type.name} has no field "
                       f"'{field_name}'{suggestion(field_name, known)}", rule=LINKING)
            return ast.FieldRef(ERROR, p, record, field_name)
        return ast.FieldRef(ftype, p, record, field_name)

    def _x_record_expr(self, node: Tree, p: Pos) -> ast.Expr:
        name = qname_text(node.children[0])
        rtype = self.scope.resolve_global(name, "type")
        if not isinstance(rtype, ast.RecordType):
            self._unknown(node.children[0], "record type", name, self.scope.global_names("record"))
            return ast.Literal(ERROR, p, 0)
        values: dict[str, ast.Expr] = {}
        for fd in node.children[1].children:
            fname = str(fd.children[0])
            value = self.expr(fd.children[1])
            ftype = rtype.field_type(fname)
            if ftype is None:
                self.error(fd, f"record {rtype.name} has no field '{fname}'"
                           f"{suggestion(fname, [f.name for f in rtype.fields])}", rule=LINKING)
                continue
            values[fname] = self.expect(fd.children[1], value, ftype, f"field '{fname}'", rule="FieldDefinitionTypeError")
        return ast.RecordLiteral(rtype, p, tuple(values.items()))

    def _x_not_expr(self, node: Tree, p: Pos) -> ast.Expr:
        operand = self.expr(node.children[0])
        self.expect(node.children[0], operand, BOOLEAN, "the operand of 'not'")
        return ast.Unary(BOOLEAN, p, "not", operand)

    def _x_neg(self, node: Tree, p: Pos) -> ast.Expr:
        operand = self.expr(node.children[0])
        if _dims(operand.type):
            return _elementwise(p, operand.type, lambda k: _neg(p, _part(p, operand, k)))
        if not ast.is_numeric(operand.type):
            self.error(node, f"type error: '-' needs a number, but this is {operand.type}", rule=TYPING)
            return ast.Unary(ERROR, p, "-", operand)
        rtype = INT if operand.type == NAT else operand.type
        return ast.Unary(rtype, p, "-", operand)

    def _x_binop(self, node: Tree, p: Pos) -> ast.Expr:
        left_node, op_token, right_node = node.children
        op = str(op_token)
        left, right = self.expr(left_node), self.expr(right_node)
        if op in _LOGIC:
            self.expect(left_node, left, BOOLEAN, f"the left operand of '{op}'")
            self.expect(right_node, right, BOOLEAN, f"the right operand of '{op}'")
            return ast.Binary(BOOLEAN, p, _LOGIC[op], left, right)
        if op in _EQUALITY:  # a literal takes the other side's type (`s == <>`: `<>` a Seq(Skills))
            left, right = conform(left, right.type), conform(right, left.type)
            if not ast.comparable(left.type, right.type):
                self.error(node, f"type error: cannot compare {left.type} with {right.type}", rule=TYPING)
            return ast.Binary(BOOLEAN, p, op, left, right)
        if op in _ORDER:
            if self.scope.result_type is not None and isinstance(left.type, ast.GivenType) and left.type == right.type:
                # RoboTool gives `a > b` on a given type no type, and checks types in conditions,
                # guards and actions, but not in a function's pre- and postconditions, where it is
                # accepted; its CSP orders the type's values, which are integers (as tockbmc's are).
                return ast.Binary(BOOLEAN, p, op, left, right)
            for side, e in ((left_node, left), (right_node, right)):
                if not ast.is_numeric(e.type):
                    self.error(side, f"type error: '{op}' compares numbers, but this is {e.type}", rule=TYPING)
            return ast.Binary(BOOLEAN, p, op, left, right)
        assert op in _ARITHMETIC
        if op in ("+", "-", "*") and (_dims(left.type) or _dims(right.type)):
            return self._linear(node, p, op, left, right)
        for side, e in ((left_node, left), (right_node, right)):
            if not ast.is_numeric(e.type):
                self.error(side, f"type error: '{op}' needs numbers, but this is {e.type}", rule=TYPING)
                return ast.Binary(ERROR, p, op, left, right)
        rtype = ast.numeric_join(left.type, right.type)
        if op == "-" and rtype == NAT:
            rtype = INT
        if op == "/" and rtype != REAL and not isinstance(rtype, ast.ErrorType):
            rtype = INT if rtype == NAT else rtype  # integer division on integers
        return ast.Binary(rtype, p, op, left, right)

    def _linear(self, node: Tree, p: Pos, op: str, left: ast.Expr, right: ast.Expr) -> ast.Expr:
        """Vector and matrix arithmetic, written out item by item over the tuples they are:
        `v + w` and `v - w` of one shape, a number times a vector or matrix, `v * w` the dot
        product, `m * v` and `m * n` the matrix products (RoboChart's `Plus`, `Minus`, `Mult` on
        `VectorType` and `MatrixType`)."""
        a, b = _dims(left.type), _dims(right.type)
        if isinstance(left.type, ast.ErrorType) or isinstance(right.type, ast.ErrorType):
            return ast.Literal(ERROR, p, 0)  # reported where it arose
        if a is None or b is None:
            self.error(node, f"type error: '{op}' cannot take {left.type} and {right.type}", rule=TYPING)
            return ast.Literal(ERROR, p, 0)
        if op in ("+", "-"):
            if a != b:
                self.error(node, f"type error: '{op}' needs two vectors or matrices of one shape, but these are "
                                 f"{left.type} and {right.type}", rule=TYPING)
                return ast.Literal(ERROR, p, 0)
            return _pointwise(p, op, left, right)
        if not a or not b:  # a number times a vector or matrix
            scalar, shaped = (left, right) if not a else (right, left)
            return _scaled(p, scalar, shaped)
        if len(a) == 1 and a == b:
            return _dot(p, [_part(p, left, k) for k in range(1, a[0] + 1)], [_part(p, right, k) for k in range(1, a[0] + 1)])
        if len(a) == 2 and a[1] == b[0]:
            rows = [_part(p, left, i) for i in range(1, a[0] + 1)]
            if len(b) == 1:
                items = [_dot(p, [_part(p, r, k) for k in range(1, a[1] + 1)], [_part(p, right, k) for k in range(1, a[1] + 1)])
                         for r in rows]
            else:
                items = []
                for r in rows:
                    entries = [_dot(p, [_part(p, r, k) for k in range(1, a[1] + 1)],
                                    [_part(p, _part(p, right, k), j) for k in range(1, a[1] + 1)]) for j in range(1, b[1] + 1)]
                    items.append(ast.TupleLiteral(_tuple_type(entries), p, tuple(entries)))
            return ast.TupleLiteral(_tuple_type(items), p, tuple(items))
        self.error(node, f"type error: '*' cannot multiply {left.type} by {right.type} (their sizes do not match)", rule=TYPING)
        return ast.Literal(ERROR, p, 0)

    def _x_if_expr(self, node: Tree, p: Pos) -> ast.Expr:
        c, a, b = (self.expr(n) for n in node.children)
        self.expect(node.children[0], c, BOOLEAN, "the condition of 'if'")
        if ast.is_numeric(a.type) and ast.is_numeric(b.type):
            rtype = ast.numeric_join(a.type, b.type)
        elif ast.comparable(a.type, b.type):
            rtype = b.type if isinstance(a.type, ast.ErrorType) else a.type
        else:
            self.error(node, f"type error: the branches of 'if' have types {a.type} and {b.type}", rule=TYPING)
            rtype = ERROR
        return ast.IfExpr(rtype, p, c, a, b)

    def _x_call_expr(self, node: Tree, p: Pos) -> ast.Expr:
        callee = node.children[0]
        args_nodes = node.children[1].children if len(node.children) > 1 else []
        name = qname_text(callee.children[0]) if isinstance(callee, Tree) and callee.data == "name_expr" else None
        var = self.scope.variables.get(name) if name is not None else None
        if name is None or var is not None and isinstance(var.type, ast.FunctionType):
            # A value of a function type applied: a variable, a `lambda`, a cast (RoboChart's
            # `CallExp` whose function is any expression).
            return self._apply(node, p, self.expr(callee), args_nodes)
        function = self.scope.resolve_global(name, "function")
        if isinstance(function, ast.ErrorType):  # a function that failed to resolve, reported at its declaration
            for a in args_nodes:
                self.expr(a)
            return ast.Literal(ERROR, p, 0)
        if not isinstance(function, ast.Function) and self.scope.toolkit and name in TOOLKIT_FUNCTIONS \
                and name not in self.scope.variables:
            return self._toolkit_call(node, p, name, [self.expr(a) for a in args_nodes])
        if not isinstance(function, ast.Function):
            var = self.scope.variables.get(name)
            if var is not None:
                if not isinstance(var.type, ast.ErrorType):  # else its type was already reported
                    self.error(callee, f"'{name}' is a variable of type {var.type}, not a function", rule=TYPING)
            elif self._is_literal(name):
                enum = (self.scope.resolve_global(name, "enum_literal") if "::" not in name
                        else self.scope.resolve_global(name.rpartition("::")[0], "type"))
                literal = name.rpartition("::")[2]
                if isinstance(enum, ast.EnumType) and enum.parameters(literal):
                    params = tuple(ast.Variable(str(i), t, False, enum.qname, p)
                                   for i, t in enumerate(enum.parameters(literal), 1))
                    args = self._arguments(node, name, args_nodes, params)
                    if any(isinstance(a.type, ast.ErrorType) for a in args) or len(args) != len(params):
                        return ast.Literal(ERROR, p, 0)
                    return ast.EnumLiteral(enum, p, enum, literal, args)
                if isinstance(enum, ast.EnumType) and literal in enum.literals:
                    # RoboTool warns (ParameterlessConstructorWithCall) and reads the literal
                    self.report(self.pos(callee), f"'{name}' is an enumeration literal without parameters: "
                                                  f"write it without '()'", "warning")
                    for a in args_nodes:
                        self.expr(a)
                    if args_nodes:  # RoboTool only warns here too, and gives them no meaning
                        self.error(node, f"unsupported: arguments given to '{name}', an enumeration literal "
                                         "without parameters")
                        return ast.Literal(ERROR, p, 0)
                    return ast.EnumLiteral(enum, p, enum, literal)
                self.error(callee, f"'{name}' is an enumeration literal without parameters", rule=TYPING)
            elif name in self.scope.operations or self.scope.resolve_global(name, "operation"):
                self.error(callee, f"'{name}' is an operation: call it as a statement, not in an expression", rule=LINKING)
            elif self.scope.toolkit:  # after the literals: `V1(0)` is a literal with a toolkit imported too
                for a in args_nodes:
                    self.expr(a)
                return self._unsupported(callee, self.pos(callee), f"toolkit function '{name}' (built in: "
                                         f"{', '.join(sorted(TOOLKIT_FUNCTIONS))})")
            else:
                self._unknown(callee, "function", name, self.scope.global_names("function"))
            for a in args_nodes:
                self.expr(a)
            return ast.Literal(ERROR, p, 0)
        args = tuple(self.expr(a) for a in args_nodes)
        if function.generic and len(args) == len(function.parameters):
            bindings: dict[str, ast.Type] = {}
            if not all(ast.unify(q.type, a.type, bindings) for q, a in zip(function.parameters, args, strict=True)):
                self.error(node, f"type error: the arguments of '{name}' give one generic type two types: "
                           f"{', '.join(str(a.type) for a in args)}", rule=TYPING)
                return ast.Literal(ERROR, p, 0)
            unbound = sorted(set().union(ast.type_vars(function.result), *(ast.type_vars(q.type) for q in function.parameters))
                             - set(bindings))
            if unbound:
                return self._unsupported(node, p, f"a call of '{name}' whose arguments do not fix its generic "
                                         f"type{'s' if len(unbound) > 1 else ''} {', '.join('?' + v for v in unbound)}")
            instance = self.scope.instantiate(function, bindings)
            if instance is None:
                return ast.Literal(ERROR, p, 0)
            function = instance
        args = self._check_arguments(node, name, args_nodes, args, function.parameters)
        return ast.Call(function.result, p, function, args)

    def _apply(self, node: Tree, p: Pos, value: ast.Expr, args_nodes: list) -> ast.Expr:
        """`f(a, …)` for a value `f` of a function type: one argument per part of a product
        domain (or one tuple of the domain), else one argument of the domain."""
        args = tuple(self.expr(a) for a in args_nodes)
        t = value.type
        if isinstance(t, ast.ErrorType):
            return ast.Literal(ERROR, p, 0)
        if not isinstance(t, ast.FunctionType):
            self.error(node.children[0], f"type error: only functions can be called, but this is {t}", rule=TYPING)
            return ast.Literal(ERROR, p, 0)
        wanted = t.arguments if len(args) != 1 else (t.domain,)
        if len(args) != len(wanted):
            self.error(node, f"a function of type {t} takes {len(wanted)} argument(s), but {len(args)} given", rule="IncorrectNumberOfArguments")
            return ast.Literal(ERROR, p, 0)
        args = tuple(self.expect(a_node, a, w, "an argument", rule="UndefinedTypeInArguments") for a_node, a, w in zip(args_nodes, args, wanted, strict=True))
        return ast.Apply(t.range, p, value, args)

    def _x_lambda_expr(self, node: Tree, p: Pos) -> ast.Expr:
        decls, *rest = node.children
        saved = dict(self.scope.variables)
        try:
            bound = self._bind(decls, "lambda", p)
            condition = self.condition(rest[0]) if len(rest) == 2 else None
            body = self.expr(rest[-1])
        finally:
            self.scope.variables.clear()
            self.scope.variables.update(saved)
        if isinstance(body.type, ast.ErrorType) or any(isinstance(v.type, ast.ErrorType) for v in bound):
            return ast.Literal(ERROR, p, 0)
        # RoboTool types `lambda x : A, y : B @ e` as `A * B -> T` (`typeFor(LambdaExp)`).
        domain = bound[0].type if len(bound) == 1 else ast.ProductType(tuple(v.type for v in bound))
        return ast.Lambda(ast.FunctionType(domain, body.type), p, tuple(bound), condition, body)

    def _x_set_comprehension(self, node: Tree, p: Pos) -> ast.Expr:
        """`{x : T, … | p @ e}` (RoboChart's `SetComp`): without `@ e`, the set of the bound
        variable's values (of the tuples of them, for several) that satisfy `p`."""
        decls, *rest = node.children
        condition_node = next((c.children[0] for c in rest if c.data == "such_that"), None)
        term_node = next((c.children[0] for c in rest if c.data == "comprehension_term"), None)
        saved = dict(self.scope.variables)
        try:
            bound = self._bind(decls, "set", p)
            condition = self.condition(condition_node) if condition_node is not None else None
            term = self.expr(term_node) if term_node is not None else None
        finally:
            self.scope.variables.clear()
            self.scope.variables.update(saved)
        if term is None and len(bound) > 1:
            refs = tuple(ast.VarRef(v.type, p, v) for v in bound)
            term = ast.TupleLiteral(ast.ProductType(tuple(v.type for v in bound)), p, refs)
        element = term.type if term is not None else bound[0].type
        if isinstance(element, ast.ErrorType) or any(isinstance(v.type, ast.ErrorType) for v in bound):
            return ast.Literal(ERROR, p, 0)
        return ast.SetComprehension(ast.SetType(element), p, tuple(bound), condition, term)

    def _x_as_expr(self, node: Tree, p: Pos) -> ast.Expr:
        """`e as T`: `e` seen as a value of `T` (RoboTool's `AsExp`, whose type is `T`). Only a
        cast that changes no value is built: `T` must hold `e`'s values as they are."""
        value = self.expr(node.children[0])
        target = self.resolve_type(node.children[1])
        if isinstance(value.type, ast.ErrorType) or isinstance(target, ast.ErrorType):
            return ast.Literal(ERROR, p, 0)
        value = conform(value, target)
        if not ast.assignable(target, value.type):
            return self._unsupported(node, p, f"a cast 'as {target}' of a value of type {value.type} (only casts "
                                              "to a type that holds the value, its integers made reals, are built)")
        if isinstance(value, ast.Builtin) and value.op == "as" and value.type == target:
            return ast.Builtin(target, p, "as", value.args)  # `conform` cast it already
        return ast.Builtin(target, p, "as", (value,))

    def _arguments(self, node: Tree, name: str, args_nodes: list, params: tuple[ast.Variable, ...]) -> tuple[ast.Expr, ...]:
        return self._check_arguments(node, name, args_nodes, tuple(self.expr(a) for a in args_nodes), params)

    def _check_arguments(self, node: Tree, name: str, args_nodes: list, args: tuple[ast.Expr, ...],
                         params: tuple[ast.Variable, ...]) -> tuple[ast.Expr, ...]:
        if len(args) != len(params):
            self.error(node, f"'{name}' takes {len(params)} argument(s), but {len(args)} given", rule="IncorrectNumberOfArguments")
            return args
        return tuple(self.expect(a_node, a, param.type, f"argument '{param.name}' of '{name}'", rule="UndefinedTypeInArguments")
                     for a_node, a, param in zip(args_nodes, args, params, strict=True))

    # ----------------------------------------------------------------- sequences, sets, tuples

    def _items(self, node: Tree) -> list[ast.Expr]:
        return [self.expr(c) for c in node.children[0].children] if node.children else []

    def _element_type(self, node: Tree, items: list[ast.Expr], what: str) -> ast.Type:
        """The element type of a literal's items: their common type (numbers joined)."""
        t: ast.Type = ast.ANY
        for x in items:
            if isinstance(x.type, ast.ErrorType):
                return ERROR
            if isinstance(t, ast.AnyElement):
                t = x.type
            elif ast.is_numeric(t) and ast.is_numeric(x.type):
                t = ast.numeric_join(t, x.type)
            elif ast.assignable(t, x.type):
                pass
            elif ast.assignable(x.type, t):
                t = x.type
            else:
                self.error(node, f"type error: the items of {what} have types {t} and {x.type}", rule=TYPING)
                return ERROR
        return t

    def _x_seq_expr(self, node: Tree, p: Pos) -> ast.Expr:
        items = self._items(node)
        t = self._element_type(node, items, "a sequence")
        if isinstance(t, ast.ErrorType):
            return ast.SeqLiteral(ERROR, p, tuple(items))
        return ast.SeqLiteral(ast.SeqType(t), p, tuple(conform(x, t) for x in items))

    def _x_set_expr(self, node: Tree, p: Pos) -> ast.Expr:
        items = self._items(node)
        t = self._element_type(node, items, "a set")
        if isinstance(t, ast.ErrorType):
            return ast.SetLiteral(ERROR, p, tuple(items))
        return ast.SetLiteral(ast.SetType(t), p, tuple(conform(x, t) for x in items))

    def _x_tuple_expr(self, node: Tree, p: Pos) -> ast.Expr:
        items = self._items(node)
        if len(items) < 2:
            self.error(node, "a tuple has at least two parts", rule=GRAMMAR)
            return ast.Literal(ERROR, p, 0)
        if any(isinstance(x.type, ast.ErrorType) for x in items):
            return ast.TupleLiteral(ERROR, p, tuple(items))
        return ast.TupleLiteral(ast.ProductType(tuple(x.type for x in items)), p, tuple(items))

    def _x_set_range_expr(self, node: Tree, p: Pos) -> ast.Expr:
        """`{a to b}` (RoboChart's `SetRange`): the integers from `a` to `b`."""
        low, high = self.expr(node.children[0]), self.expr(node.children[1])
        for side, e in zip(node.children, (low, high), strict=True):
            if e.type not in (NAT, ast.INT) and not isinstance(e.type, ast.ErrorType):
                self.error(side, f"type error: the bounds of '{{a to b}}' must be integers, but this is {e.type}", rule=TYPING)
                return ast.Literal(ERROR, p, 0)
        t = ast.numeric_join(low.type, high.type)
        if isinstance(t, ast.ErrorType):
            return ast.Literal(ERROR, p, 0)
        yes = ast.Literal(BOOLEAN, p, True)
        return ast.Builtin(ast.SetType(t), p, "interval", (low, high, yes, yes))

    def _x_vector_expr(self, node: Tree, p: Pos) -> ast.Expr:
        """`[|a, b|]` a vector, `[|a, b; c, d|]` a matrix of rows: tuples (`Resolver._vector_type`)."""
        rows = []
        for row_node in node.children:
            items = [self.expr(c) for c in row_node.children]
            if any(isinstance(x.type, ast.ErrorType) for x in items):
                return ast.Literal(ERROR, p, 0)
            t = self._element_type(row_node, items, "a vector")
            if isinstance(t, ast.ErrorType):
                return ast.Literal(ERROR, p, 0)
            rows.append(ast.TupleLiteral(ast.ProductType((t,) * len(items)), p, tuple(conform(x, t) for x in items)))
        if len(rows) == 1:
            return rows[0]
        if len({len(r.items) for r in rows}) != 1:
            self.error(node, "type error: the rows of a matrix have different lengths", rule=TYPING)
            return ast.Literal(ERROR, p, 0)
        return ast.TupleLiteral(ast.ProductType(tuple(r.type for r in rows)), p, tuple(rows))

    def _x_index_expr(self, node: Tree, p: Pos) -> ast.Expr:
        indices = node.children[1].children
        if len(indices) > 1:  # `m[i, j]` of a matrix: row i's item j
            inner = Tree("index_expr", [node.children[0], Tree("exprs", indices[:-1], meta=node.children[1].meta)], meta=node.meta)
            outer = Tree("index_expr", [inner, Tree("exprs", indices[-1:], meta=node.children[1].meta)], meta=node.meta)
            return self._x_index_expr(outer, p)
        value = self.expr(node.children[0])
        index = self.expr(indices[0])
        t = value.type
        if isinstance(t, ast.ErrorType) or isinstance(index.type, ast.ErrorType):
            return ast.Index(ERROR, p, value, index)
        if isinstance(t, ast.SeqType):
            if index.type not in (ast.NAT, ast.INT):
                self.error(indices[0], f"type error: a sequence's index must be an integer, but this is {index.type}", rule=TYPING)
            return ast.Index(t.element, p, value, index)
        if isinstance(t, ast.ProductType):
            if not (isinstance(index, ast.Literal) and type(index.value) is int and 1 <= index.value <= len(t.parts)):
                self.error(indices[0], f"a tuple's part is chosen by a literal from 1 to {len(t.parts)}", rule="TupleIndexOutOfBounds")
                return ast.Index(ERROR, p, value, index)
            assert isinstance(index.value, int)
            return ast.Index(t.parts[index.value - 1], p, value, index)
        self.error(node, f"type error: only sequences and tuples are indexed, but this is {t}", rule=TYPING)
        return ast.Index(ERROR, p, value, index)

    def _x_cat_expr(self, node: Tree, p: Pos) -> ast.Expr:
        left, right = self.expr(node.children[0]), self.expr(node.children[1])
        return self._builtin(node, p, "concat", [left, right])

    def _x_in_expr(self, node: Tree, p: Pos) -> ast.Expr:
        member, collection = self.expr(node.children[0]), self.expr(node.children[1])
        return self._builtin(node, p, "in", [member, collection])

    def _toolkit_call(self, node: Tree, p: Pos, name: str, args: list[ast.Expr]) -> ast.Expr:
        if len(args) != TOOLKIT_FUNCTIONS[name]:
            self.error(node, f"'{name}' takes {TOOLKIT_FUNCTIONS[name]} argument(s), but {len(args)} given", rule="IncorrectNumberOfArguments")
            return ast.Literal(ERROR, p, 0)
        return self._builtin(node, p, name, args)

    def _builtin(self, node: Tree, p: Pos, op: str, args: list[ast.Expr]) -> ast.Expr:
        """A built-in operation on sequences and sets, type-checked."""
        args = [as_set(a) for a in args]
        if any(isinstance(a.type, ast.ErrorType) for a in args):
            return ast.Builtin(ERROR, p, op, tuple(args))
        t = builtin_type(op, [a.type for a in args])
        if t is None:
            self.error(node, f"type error: '{op}' cannot take {', '.join(str(a.type) for a in args)}", rule=TYPING)
            return ast.Builtin(ERROR, p, op, tuple(args))
        if op in (*_JOINED, *_COMPARED, "filter") and isinstance(args[0].type, (ast.SeqType, ast.SetType)):
            args = [conform(a, t if op in _JOINED else a.type) for a in args]
            if op in (*_JOINED, *_COMPARED):
                args = [conform(a, args[0].type) for a in args]
        if op == "override":
            pairs = ast.SetType(ast.ProductType((t.domain, t.range))) if isinstance(t, ast.FunctionType) else t
            args = [args[0], conform(args[1], pairs)]
        if op in ("in", "notin"):
            element = args[1].type.element  # type: ignore[attr-defined]
            args = [conform(args[0], element), args[1]]
        return ast.Builtin(t, p, op, tuple(args))

    def _x_let_expr(self, node: Tree, p: Pos) -> ast.Expr:
        *decls, body_node = node.children
        saved = dict(self.scope.variables)
        bound: list[tuple[ast.Variable, ast.Expr]] = []
        try:
            for d in decls:
                name = str(d.children[0])
                value = self.expr(d.children[1])
                var = ast.Variable(name, value.type, True, f"{self.scope.owner}::let@{p.line}:{p.column}",
                                   self.pos(d.children[0]), None, "let")
                self.scope.variables[name] = var
                bound.append((var, value))
            body = self.expr(body_node)
        finally:
            self.scope.variables.clear()
            self.scope.variables.update(saved)
        for var, value in reversed(bound):
            body = ast.Let(body.type, p, var, value, body)
        return body

    def _bind(self, decls: Tree, what: str, p: Pos) -> list[ast.Variable]:
        """The variables `x : T, …` a quantifier or lambda declares, added to the scope (the caller
        restores it)."""
        bound = []
        for d in decls.children:
            name = str(d.children[0])
            var = ast.Variable(name, self.resolve_type(d.children[1]), True,
                               f"{self.scope.owner}::{what}@{p.line}:{p.column}", self.pos(d.children[0]), None, "bound")
            self.scope.variables[name] = var
            bound.append(var)
        return bound

    def _quantifier(self, node: Tree, p: Pos, kind: str) -> ast.Expr:
        decls, *rest = node.children
        saved = dict(self.scope.variables)
        try:
            bound = self._bind(decls, kind, p)
            condition = self.condition(rest[0]) if len(rest) == 2 else None
            body = self.expect(rest[-1], self.expr(rest[-1]), BOOLEAN, f"the predicate of '{kind}'")
        finally:
            self.scope.variables.clear()
            self.scope.variables.update(saved)
        return ast.Quantifier(BOOLEAN, p, kind, tuple(bound), condition, body)

    def _x_forall_expr(self, node: Tree, p: Pos) -> ast.Expr:
        return self._quantifier(node, p, "forall")

    def _x_exists_expr(self, node: Tree, p: Pos) -> ast.Expr:
        return self._quantifier(node, p, "exists")

    def _x_exists1_expr(self, node: Tree, p: Pos) -> ast.Expr:
        return self._quantifier(node, p, "exists1")

    def _x_since_expr(self, node: Tree, p: Pos) -> ast.Expr:
        name = qname_text(node.children[0])
        clock = self.scope.clocks.get(name)
        if clock is None:
            self._unknown(node.children[0], "clock", name, list(self.scope.clocks))
            return ast.Literal(ERROR, p, 0)
        return ast.Since(NAT, p, clock)

    def _x_since_entry_expr(self, node: Tree, p: Pos) -> ast.Expr:
        name = qname_text(node.children[0])
        path = self.scope.states.get(name)
        if path is None:
            self._unknown(node.children[0], "state", name, list(self.scope.states))
            return ast.Literal(ERROR, p, 0)
        return ast.SinceEntry(NAT, p, path)

    def _range(self, node: Tree, p: Pos, low_closed: bool) -> ast.Expr:
        low, high = self.expr(node.children[0]), self.expr(node.children[1])
        for side, e in zip(node.children[:2], (low, high)):
            if not ast.is_numeric(e.type):
                self.error(side, f"type error: an interval bound must be a number, but this is {e.type}", rule=TYPING)
        high_closed = node.children[2].data == "closed"
        return ast.Interval(ast.numeric_join(low.type, high.type) if ast.is_numeric(low.type) and ast.is_numeric(high.type) else ERROR,
                            p, low, high, low_closed, high_closed)

    def _x_closed_range_expr(self, node: Tree, p: Pos) -> ast.Expr:
        return self._range(node, p, True)

    def _x_open_range_expr(self, node: Tree, p: Pos) -> ast.Expr:
        return self._range(node, p, False)

    # ----------------------------------------------------------------- communications

    def event(self, node: Tree | Token) -> ast.Event | None:
        name = qname_text(node)
        event = self.scope.events.get(name)
        if event is None:
            self._unknown(node, "event", name, list(self.scope.events))
        return event

    def communication(self, node: Tree) -> tuple[ast.Event | None, str, ast.Variable | None, ast.Expr | None]:
        """(event, kind, variable, value) for a communication: kind is plain, input, output or sync."""
        kind = node.data
        if kind == "comm_predicate":  # kept by the caller as an `ast.UnsupportedExpr` or `UnsupportedStmt`
            self.meaningless(node, TRIGGER_PREDICATES)
            return None, "predicate", None, None
        if kind == "comm_plain":
            parts = node.children[0].children
            event = self.event(parts[0])
            if len(parts) == 1:
                return event, "plain", None, None
            value = self._designator_value(parts[1:])
            if event is not None:
                value = conform(value, event.type) if event.type is not None else value
                self._check_value(parts[1], event, value)
            return event, "sync", None, value
        event = self.event(node.children[0])
        if kind == "comm_input":
            name = qname_text(node.children[1])
            var = self.scope.variables.get(name)
            if var is None:
                self._unknown(node.children[1], "variable", name, list(self.scope.variables))
            elif var.constant:
                self.error(node.children[1], _constant_written(var, f"'{name}' is a constant: an input cannot change it"),
                           rule="assignmentToParameter" if var.kind == "parameter" else "")
            elif event is not None:
                if event.type is None:
                    self.error(node, f"event '{event.name}' carries no value, so '?{name}' has nothing to receive", rule="Tg5")
                elif not ast.assignable(var.type, event.type):
                    self.error(node.children[1], f"type error: '{name}' is {var.type}, but event "
                               f"'{event.name}' carries {event.type}", rule="InputCommunicationTypeError")
            return event, "input", var, None
        value = self.expr(node.children[1])
        if event is not None:
            value = conform(value, event.type) if event.type is not None else value
            self._check_value(node.children[1], event, value)
        return event, ("output" if kind == "comm_output" else "sync"), None, value

    def _designator_value(self, parts: list) -> ast.Expr:
        """The value of `e.v` or `e.v.f` as written in a designator."""
        value = self._x_name_expr(_name_tree(parts[0]), self.pos(parts[0]))
        for part in parts[1:]:
            value = self._select_known(value, qname_text(part), part)
        return value

    def _select_known(self, record: ast.Expr, fname: str, node: Tree) -> ast.Expr:
        p = self.pos(node)
        if isinstance(record.type, ast.RecordType):
            ftype = record.type.field_type(fname)
            if ftype is not None:
                return ast.FieldRef(ftype, p, record, fname)
            self.error(node, f"record {record.type.name} has no field '{fname}'"
                       f"{suggestion(fname, [f.name for f in record.type.fields])}", rule=LINKING)
        elif not isinstance(record.type, ast.ErrorType):
            self.error(node, f"type error: '.{fname}' selects a field, but this is {record.type}", rule=LINKING)
        return ast.FieldRef(ERROR, p, record, fname)

    def _check_value(self, node: Tree | Token, event: ast.Event, value: ast.Expr) -> None:
        if event.type is None:
            self.error(node, f"event '{event.name}' carries no value", rule="Tg5")
        elif not ast.assignable(event.type, value.type):
            self.error(node, f"type error: event '{event.name}' carries {event.type}, but this is {value.type}", rule="OutputCommunicationTypeError")

    # ----------------------------------------------------------------- statements

    def statement(self, node: Tree) -> ast.Stmt:
        """Resolve and type-check one statement tree."""
        p = self.pos(node)
        method = getattr(self, f"_s_{node.data}", None)
        if method is None:
            if node.data in ("comm_plain", "comm_input", "comm_output", "comm_sync", "comm_predicate"):
                return self._communication_stmt(node, p)
            self.error(node, f"unsupported: statement '{node.data}'")
            return ast.Skip(p)
        return method(node, p)

    def _s_seq_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        return ast.Seq(p, tuple(self.statement(c) for c in node.children))

    def _s_deadline_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        inner = self.statement(node.children[0])
        return ast.Deadline(p, inner, self.deadline(node.children[1]))

    def deadline(self, node: Tree) -> ast.Expr:
        """A deadline's bound, a `nat`.  RoboTool checks no type there (no validator rule reads
        it), and gives one of another type no meaning tockbmc could follow: unsupported."""
        bound = conform(self.expr(node), NAT)
        if not ast.assignable(NAT, bound.type) and not isinstance(bound.type, ast.ErrorType):
            self.error(node, f"unsupported: a deadline of type {bound.type} (tockbmc reads a deadline as a nat)")
        return bound

    def _s_if_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        cond = self.condition(node.children[0], rule="IfStmtTypeError")
        then = self.statement(node.children[1])
        otherwise = self.statement(node.children[2]) if len(node.children) > 2 else ast.Skip(p)
        return ast.If(p, cond, then, otherwise)

    def _s_skip_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        return ast.Skip(p)

    def _s_wait_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        arg = self.expr(node.children[0])
        if isinstance(arg, ast.Interval):
            low, high = arg.low, arg.high
            for e in (low, high):
                self.expect(node.children[0], e, NAT, "a wait bound", rule="WaitTypeError")
            return ast.Wait(p, low, high)
        self.expect(node.children[0], arg, NAT, "a wait duration", rule="WaitTypeError")
        return ast.Wait(p, arg, arg)

    def _s_clock_reset(self, node: Tree, p: Pos) -> ast.Stmt:
        clock = self.clock(node.children[0])
        return ast.ClockReset(p, clock) if clock is not None else ast.Skip(p)

    def clock(self, node: Tree) -> ast.Clock | None:
        name = qname_text(node)
        clock = self.scope.clocks.get(name)
        if clock is None:
            self._unknown(node, "clock", name, list(self.scope.clocks))
        return clock

    def _s_send_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        return self._communication_stmt(node.children[0], p)

    def _s_comm_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        return self._communication_stmt(node.children[0], p)

    def _communication_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        event, kind, var, value = self.communication(node)
        if kind == "predicate":
            return ast.UnsupportedStmt(p, TRIGGER_PREDICATES)
        if event is None:
            return ast.Skip(p)
        if kind == "input":
            return ast.Receive(p, event, var)
        if kind == "plain" and event.type is not None:
            self.error(node, f"event '{event.name}' carries {event.type}: send a value with "
                       f"'{event.name}!v'", rule="Tg2")
        return ast.Send(p, event, value)

    def _assignable(self, designator: Tree) -> tuple[ast.Variable, tuple[str, ...], ast.Expr] | None:
        """The variable `x.f.g` assigns, the field path, and the target's value as an expression
        (None, reported, when `x` is unknown)."""
        parts = designator.children
        name = qname_text(parts[0])
        var = self.scope.variables.get(name)
        if var is None:
            self._unknown(parts[0], "variable", name, list(self.scope.variables))
            return None
        if var.constant:
            self.error(parts[0], _constant_written(var, f"'{name}' is a constant and cannot be assigned"),
                       rule="assignmentToParameter" if var.kind == "parameter" else "")
        target: ast.Expr = ast.VarRef(var.type, self.pos(parts[0]), var)
        fields = []
        for part in parts[1:]:
            fname = qname_text(part)
            target = self._select_known(target, fname, part)
            fields.append(fname)
        return var, tuple(fields), target

    def _s_assign_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        value = self.expr(node.children[1])
        found = self._assignable(node.children[0])
        if found is None:
            return ast.Skip(p)
        var, fields, target = found
        name = var.name
        value = conform(value, target.type)
        if not ast.assignable(target.type, value.type):
            self.error(node.children[1], f"type error: cannot assign {value.type} to "
                       f"'{'.'.join([name, *fields])}' of type {target.type}", rule="AssignmentTypeError")
        return ast.Assign(p, var, fields, value)

    def _s_array_assign_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        """`s[i] = e` on a sequence (or `p[k] = e` on a tuple, `k` a literal): the assignment of
        `s` with its `i`-th item replaced (RoboChart's `ArrayAssignable`; Z's `s ⊕ {i ↦ e}`)."""
        designator, indices_node, value_node = node.children
        value = self.expr(value_node)
        indices = [self.expr(i) for i in indices_node.children]
        found = self._assignable(designator)
        if found is None:
            return ast.Skip(p)
        var, fields, target = found
        t = target.type
        if isinstance(t, ast.ErrorType) or any(isinstance(i.type, ast.ErrorType) for i in indices):
            return ast.Skip(p)
        if len(indices) != 1:
            what = "an assignment to a matrix's item ('m[i, j] = e')"
            self.meaningless(indices_node, what)
            return ast.UnsupportedStmt(self.pos(indices_node), what)
        [index] = indices
        if isinstance(t, ast.SeqType):
            if index.type not in (NAT, ast.INT):
                self.error(indices_node, f"type error: a sequence's index must be an integer, but this is {index.type}", rule=TYPING)
            item = self.expect(value_node, value, t.element, "the item assigned", rule="AssignmentTypeError")
            return ast.Assign(p, var, fields, ast.Builtin(t, p, "update", (target, index, item)))
        if isinstance(t, ast.ProductType):
            if not (isinstance(index, ast.Literal) and type(index.value) is int and 1 <= index.value <= len(t.parts)):
                self.error(indices_node, f"a tuple's part is chosen by a literal from 1 to {len(t.parts)}", rule="TupleIndexOutOfBounds")
                return ast.Skip(p)
            k = index.value
            assert isinstance(k, int)
            item = self.expect(value_node, value, t.parts[k - 1], f"part {k}", rule="AssignmentTypeError")
            items = tuple(item if j == k else ast.Index(pt, p, target, ast.Literal(NAT, p, j))
                          for j, pt in enumerate(t.parts, 1))
            return ast.Assign(p, var, fields, ast.TupleLiteral(t, p, items))
        self.error(node, f"type error: only sequences and tuples are indexed, but this is {t}", rule=TYPING)
        return ast.Skip(p)

    def _s_nested_assign_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        """`s[i].f = e` or `s[i][j] = e`: RoboChart's assignable chains, whose updates past the
        first item (a record or sequence inside a sequence's item) are not built yet."""
        what = "an assignment to a part of an item ('s[i].f = e', 's[i][j] = e')"
        self.meaningless(node, what)
        return ast.UnsupportedStmt(p, what)

    def _s_call_stmt(self, node: Tree, p: Pos) -> ast.Stmt:
        name = qname_text(node.children[0])
        args_nodes = node.children[1].children if len(node.children) > 1 else []
        op = self._called(node.children[0], name)
        if op is None:
            for a in args_nodes:
                self.expr(a)
            return ast.Skip(p)
        args = self._arguments(node, name, args_nodes, op.parameters)
        return ast.OperationCall(p, op, args)

    def _called(self, node: Tree, name: str) -> ast.OperationSig | None:
        """The operation a call names (None, reported, when there is none): `move`, or `IMove::move`
        through an interface `IMove` of the caller's, as RoboTool's `Call` takes a qualified name.
        Both give the interface's one signature, so the two calls are the same call."""
        # A machine calls only what its interfaces declare: a defined operation
        # reaches it through a required interface holding its signature.
        iface_name, _, op_name = name.rpartition("::")
        iface = self.scope.resolve_global(iface_name, "interface") if iface_name else None
        if isinstance(iface, ast.Interface):
            if iface.qname not in self.scope.interfaces:
                self.error(node, f"interface '{iface_name}' is not required, provided or used by {self.scope.owner}: "
                           f"require it to call '{op_name}(…)'", rule=LINKING)
                return None
            op = next((o for o in iface.operations if o.name == op_name), None)
            if op is None:
                self.error(node, f"interface '{iface_name}' declares no operation '{op_name}'"
                           f"{suggestion(op_name, [o.name for o in iface.operations])}", rule=LINKING)
            return op
        op = self.scope.operations.get(name)
        if op is not None:
            return op
        if isinstance(self.scope.resolve_global(name, "function"), ast.Function):
            self.error(node, f"'{name}' is a function: use it in an expression", rule=LINKING)
        elif self.scope.resolve_global(name, "operation") is not None:
            self.error(node, f"operation '{name}' is not in scope: require an interface that declares '{name}(…)'", rule=LINKING)
        else:
            known = list(self.scope.operations)
            if iface_name:  # an unknown interface: offer the calls through the caller's interfaces
                known += [f"{o.owner.rsplit('::', 1)[-1]}::{o.name}" for o in self.scope.operations.values()]
            self._unknown(node, "operation", name, known)
        return None


def _dims(t: ast.Type) -> tuple[int, ...] | None:
    """The shape of a vector `(n,)` or matrix `(m, n)` of numbers (tuples of one numeric type),
    `()` for a number, None for anything else."""
    if t in ast.NUMERIC:
        return ()
    if isinstance(t, ast.ProductType) and len(set(t.parts)) == 1:
        inner = _dims(t.parts[0])
        if inner is not None and len(inner) < 2:
            return (len(t.parts), *inner)
    return None


def _part(p: Pos, e: ast.Expr, k: int) -> ast.Expr:
    """Part `k` of a tuple-typed expression (a literal's item itself)."""
    if isinstance(e, ast.TupleLiteral):
        return e.items[k - 1]
    assert isinstance(e.type, ast.ProductType)
    return ast.Index(e.type.parts[k - 1], p, e, ast.Literal(NAT, p, k))


def _tuple_type(items: list[ast.Expr]) -> ast.ProductType:
    return ast.ProductType(tuple(x.type for x in items))


def _elementwise(p: Pos, t: ast.Type, item: Callable[[int], ast.Expr]) -> ast.Expr:
    assert isinstance(t, ast.ProductType)
    items = [item(k) for k in range(1, len(t.parts) + 1)]
    return ast.TupleLiteral(_tuple_type(items), p, tuple(items))


def _arith(p: Pos, op: str, a: ast.Expr, b: ast.Expr) -> ast.Expr:
    t = ast.numeric_join(a.type, b.type)
    return ast.Binary(ast.INT if op == "-" and t == NAT else t, p, op, a, b)


def _neg(p: Pos, e: ast.Expr) -> ast.Expr:
    if _dims(e.type):
        return _elementwise(p, e.type, lambda k: _neg(p, _part(p, e, k)))
    return ast.Unary(ast.INT if e.type == NAT else e.type, p, "-", e)


def _pointwise(p: Pos, op: str, a: ast.Expr, b: ast.Expr) -> ast.Expr:
    if not _dims(a.type):
        return _arith(p, op, a, b)
    return _elementwise(p, a.type, lambda k: _pointwise(p, op, _part(p, a, k), _part(p, b, k)))


def _scaled(p: Pos, scalar: ast.Expr, shaped: ast.Expr) -> ast.Expr:
    if not _dims(shaped.type):
        return _arith(p, "*", scalar, shaped)
    return _elementwise(p, shaped.type, lambda k: _scaled(p, scalar, _part(p, shaped, k)))


def _dot(p: Pos, xs: list[ast.Expr], ys: list[ast.Expr]) -> ast.Expr:
    total = _arith(p, "*", xs[0], ys[0])
    for x, y in zip(xs[1:], ys[1:], strict=True):
        total = _arith(p, "+", total, _arith(p, "*", x, y))
    return total


def as_set(e: ast.Expr) -> ast.Expr:
    """An interval `[a, b]` given where a set is expected (`union([331, 359], [0, 30])`): the set
    of the integers it holds (RoboChart's `RangeExp`, which `wait` reads as an interval)."""
    if not isinstance(e, ast.Interval) or e.type not in (NAT, ast.INT):
        return e
    return ast.Builtin(ast.SetType(e.type), e.pos, "interval",
                       (e.low, e.high, ast.Literal(BOOLEAN, e.pos, e.low_closed), ast.Literal(BOOLEAN, e.pos, e.high_closed)))


def function_value(f: ast.Function, p: Pos) -> ast.Lambda:
    """A declared function named as a value (`override(add, …)`): `lambda x : T, … @ f(x, …)`."""
    domain = f.parameters[0].type if len(f.parameters) == 1 else ast.ProductType(tuple(q.type for q in f.parameters))
    args = tuple(ast.VarRef(q.type, p, q) for q in f.parameters)
    return ast.Lambda(ast.FunctionType(domain, f.result), p, f.parameters, None, ast.Call(f.result, p, f, args))


def _constant_written(var: ast.Variable, message: str) -> str:
    """The error for a write to a constant: RoboTool refuses one to an operation's parameter
    (checkAssignmentToParameter) and accepts one to a declared constant, whose write its semantics
    gives no meaning (a constant has no channel to set): unsupported."""
    return message if var.kind == "parameter" else f"unsupported: {message}"


def conform(e: ast.Expr, t: ast.Type) -> ast.Expr:
    """`e` retyped for a place of type `t` where it is a literal whose items fit: `<1, 2>` in a
    `Seq(real)` place is a sequence of reals, `<>` in a `Seq(nat)` place a sequence of naturals;
    another expression whose integers must become reals to fit (`ast.widens`) cast to `t`."""
    if isinstance(e, ast.SeqLiteral) and isinstance(t, ast.SeqType) or \
            isinstance(e, ast.SetLiteral) and isinstance(t, ast.SetType):
        items = tuple(conform(x, t.element) for x in e.items)  # type: ignore[union-attr]
        if all(ast.assignable(t.element, x.type) for x in items):  # type: ignore[union-attr]
            return type(e)(t, e.pos, items)
    if isinstance(e, ast.TupleLiteral) and isinstance(t, ast.ProductType) and len(t.parts) == len(e.items):
        items = tuple(conform(x, pt) for x, pt in zip(e.items, t.parts, strict=True))
        if all(ast.assignable(pt, x.type) for x, pt in zip(items, t.parts, strict=True)):
            return ast.TupleLiteral(t, e.pos, items)
    if isinstance(e, ast.Literal) and t == REAL and e.type in (NAT, ast.INT) and type(e.value) is int:
        return e  # integers fit real places as they are (the encoders convert)
    if ast.widens(t, e.type) and not ast.kept_alike(t, e.type):
        # a `Seq(nat)` where a `Seq(real)` is expected: its items made reals, by a cast (which the
        # engines encode), as a value keeps its own type's representation
        return ast.Builtin(t, e.pos, "as", (e,))
    return e


def builtin_type(op: str, args: list[ast.Type]) -> ast.Type | None:
    """The type of a built-in operation on arguments of these types, or None when it does not apply."""
    a = args[0]
    b = args[1] if len(args) > 1 else None
    seq = isinstance(a, ast.SeqType)
    if op == "size" and isinstance(a, ast.SetType):
        return NAT
    if op in ("size", "isNonEmpty", "head", "last", "tail", "front", "reverse", "dom", "ran", "elems"):
        if not seq:
            return None
        assert isinstance(a, ast.SeqType)
        return {"size": NAT, "isNonEmpty": BOOLEAN, "head": a.element, "last": a.element, "dom": ast.SetType(NAT),
                "ran": ast.SetType(a.element), "elems": ast.SetType(a.element)}.get(op, a)
    if op in ("concat", "prefix", "suffix", "infix"):  # sequence_toolkit: `s` starts, ends, or is a stretch of `t`
        if seq and isinstance(b, ast.SeqType) and (ast.assignable(a, b) or ast.assignable(b, a)):
            if op != "concat":
                return BOOLEAN
            return b if isinstance(a.element, ast.AnyElement) else a  # type: ignore[attr-defined]
        return None
    if op == "filter":
        if seq and isinstance(b, ast.SetType) and ast.comparable(a.element, b.element):  # type: ignore[attr-defined]
            return a
        return None
    if op in ("union", "inter", "diff", "symetric_diff", "subseteq", "subset"):
        if isinstance(a, ast.SetType) and isinstance(b, ast.SetType) and (ast.assignable(a, b) or ast.assignable(b, a)):
            if op in ("subseteq", "subset"):
                return BOOLEAN
            return b if isinstance(a.element, ast.AnyElement) else a
        return None
    if op in ("in", "notin"):
        if isinstance(b, ast.SetType) and ast.comparable(b.element, a):
            return BOOLEAN
        return None
    if op in ("min", "max"):  # sequence_toolkit's, on a set of numbers: its least (greatest) member
        return a.element if isinstance(a, ast.SetType) and a.element in ast.NUMERIC else None
    if op == "range":  # sequence_toolkit's `range(x, y) : Seq(int)`: the integers from x to y, in order
        return ast.SeqType(ast.INT) if a in (NAT, ast.INT) and b in (NAT, ast.INT) else None
    if op == "extract":  # the items of `b` at the indices in `a`, in order (Z's extraction)
        if isinstance(a, ast.SetType) and a.element in (NAT, ast.INT) and isinstance(b, ast.SeqType):
            return b
        return None
    if op == "override":  # relation_toolkit's `r ⊕ s`: `s`'s pairs, and `r`'s outside dom(s)
        if isinstance(a, ast.FunctionType) and isinstance(b, ast.SetType) and \
                ast.assignable(ast.SetType(ast.ProductType((a.domain, a.range))), b):
            return a
        if isinstance(a, ast.SetType) and isinstance(b, ast.SetType) and isinstance(a.element, ast.ProductType) \
                and len(a.element.parts) == 2 and ast.assignable(a, b):
            return a
        return None
    return None


def _name_tree(qn: Tree) -> Tree:
    return Tree("name_expr", [qn], meta=qn.meta)
