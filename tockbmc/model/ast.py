"""The resolved, type-checked model: the value every later layer consumes.

Everything here is a frozen dataclass.  Names are resolved to declarations,
expressions carry their types, and every node keeps its source position so
that later layers can point back at the model text.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.position import Pos as Pos  # re-exported: every node carries one

# --------------------------------------------------------------------- types


@dataclass(frozen=True)
class Type:
    """Base of the model's types."""

    def __str__(self) -> str:
        return self.name

    @property
    def name(self) -> str:
        raise NotImplementedError


@dataclass(frozen=True)
class PrimitiveType(Type):
    """A built-in type: int, nat, real, boolean or string."""

    kind: str

    @property
    def name(self) -> str:
        return self.kind


INT = PrimitiveType("int")
NAT = PrimitiveType("nat")
REAL = PrimitiveType("real")
BOOLEAN = PrimitiveType("boolean")
STRING = PrimitiveType("string")
NUMERIC = (NAT, INT, REAL)


@dataclass(frozen=True)
class GivenType(Type):
    """A `type T` declaration: values are opaque and compared only for equality."""

    qname: str

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]


@dataclass(frozen=True)
class EnumType(Type):
    """An `enumeration E { A B(real) C(nat, E2) }`: `params` gives each literal's parameter types (none
    for `A`).  An enumeration with a literal that has parameters is an algebraic datatype
    (docs/semantics.md §6.5); `parameterised` is where the first such literal is declared."""

    qname: str
    literals: tuple[str, ...]
    parameterised: Pos | None = field(default=None, compare=False)
    params: tuple[tuple[Type, ...], ...] = field(default=(), compare=False)

    def parameters(self, literal: str) -> tuple[Type, ...]:
        """The parameter types of `literal` (none for a literal without parameters)."""
        return self.params[self.literals.index(literal)] if self.params else ()

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]


@dataclass(frozen=True)
class RecordField:
    name: str
    type: Type


@dataclass(frozen=True)
class RecordType(Type):
    """A `datatype R { f : T ... }` (also written `record`)."""

    qname: str
    fields: tuple[RecordField, ...]

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    def field_type(self, name: str) -> Type | None:
        for f in self.fields:
            if f.name == name:
                return f.type
        return None


@dataclass(frozen=True)
class SeqType(Type):
    """`Seq(T)`: finite sequences of `T`, indexed from 1."""

    element: Type

    @property
    def name(self) -> str:
        return f"Seq({self.element})"


@dataclass(frozen=True)
class SetType(Type):
    """`Set(T)`: sets of `T` (finite or not: a set is its membership predicate)."""

    element: Type

    @property
    def name(self) -> str:
        return f"Set({self.element})"


@dataclass(frozen=True)
class ProductType(Type):
    """`T1 * T2 * …`: tuples, written `(| a, b |)`, whose parts are read `p[1]`, `p[2]`, …"""

    parts: tuple[Type, ...]

    @property
    def name(self) -> str:
        return "*".join(f"({p})" if isinstance(p, ProductType) else str(p) for p in self.parts)


@dataclass(frozen=True)
class FunctionType(Type):
    """`D -> R`: total functions from `D` to `R`; a function of several arguments has a product
    `D1 * D2` as its domain (RoboChart's `FunctionType`, whose domain is a `ProductType`)."""

    domain: Type
    range: Type

    @property
    def name(self) -> str:
        return f"{self.domain} -> {self.range}"

    @property
    def arguments(self) -> tuple[Type, ...]:
        """The types of the arguments a call passes: a product domain's parts, else the domain."""
        return self.domain.parts if isinstance(self.domain, ProductType) else (self.domain,)


@dataclass(frozen=True)
class AnyElement(Type):
    """The element type of an empty literal (`<>`, `{}`): fits any element type."""

    @property
    def name(self) -> str:
        return "?"


ANY = AnyElement()


@dataclass(frozen=True)
class TypeVar(Type):
    """A generic type `?X` in a function's signature: each call fixes it from its arguments."""

    var: str

    @property
    def name(self) -> str:
        return f"?{self.var}"


def type_vars(t: Type | None) -> set[str]:
    """The generic types `?X` occurring in `t`."""
    if isinstance(t, TypeVar):
        return {t.var}
    if isinstance(t, (SeqType, SetType)):
        return type_vars(t.element)
    if isinstance(t, ProductType):
        return set().union(*(type_vars(p) for p in t.parts))
    if isinstance(t, FunctionType):
        return type_vars(t.domain) | type_vars(t.range)
    return set()


def unify(param: Type, arg: Type, bindings: dict[str, Type]) -> bool:
    """Extend `bindings` so that an argument of type `arg` fits a parameter of type `param`
    (numbers joined: `nat` and `int` arguments for one `?X` make it `int`); False on a clash."""
    if isinstance(param, TypeVar):
        if isinstance(arg, (AnyElement, ErrorType)):
            return True
        prev = bindings.get(param.var)
        if prev is None or isinstance(prev, AnyElement):
            bindings[param.var] = arg
        elif is_numeric(prev) and is_numeric(arg):
            bindings[param.var] = numeric_join(prev, arg)
        elif assignable(arg, prev):
            bindings[param.var] = arg
        elif not assignable(prev, arg):
            return False
        return True
    if isinstance(param, SeqType) and isinstance(arg, SeqType) or isinstance(param, SetType) and isinstance(arg, SetType):
        return unify(param.element, arg.element, bindings)  # type: ignore[union-attr]
    if isinstance(param, ProductType) and isinstance(arg, ProductType) and len(param.parts) == len(arg.parts):
        return all(unify(p, a, bindings) for p, a in zip(param.parts, arg.parts, strict=True))
    if isinstance(param, FunctionType) and isinstance(arg, FunctionType):
        return unify(param.domain, arg.domain, bindings) and unify(param.range, arg.range, bindings)
    return True  # a mismatch is the argument's type error, reported once the types are fixed


@dataclass(frozen=True)
class ErrorType(Type):
    """The type of an expression that failed to check; compatible with all."""

    @property
    def name(self) -> str:
        return "<error>"


ERROR = ErrorType()


def is_numeric(t: Type) -> bool:
    return t in NUMERIC or isinstance(t, ErrorType)


def numeric_join(a: Type, b: Type) -> Type:
    """The smallest numeric type holding both (nat < int < real)."""
    if isinstance(a, ErrorType) or isinstance(b, ErrorType):
        return ERROR
    order = {NAT: 0, INT: 1, REAL: 2}
    return a if order[a] >= order[b] else b  # type: ignore[index]


def in_interfaces(v: Variable, interfaces: Iterable[str]) -> bool:
    """Whether `v` is declared by one of `interfaces`, named qualified or by their short names."""
    names = set(interfaces)
    return v.owner in names or v.owner.rsplit("::", 1)[-1] in names


def provided_for(caller: Behaviour, op: OperationDef) -> OperationDef:
    """`op` as `caller` runs it: each variable `op` requires that the operation `caller` declares is
    that very variable of `caller` (RoboChart: the calling operation provides it), read and written
    in its place; `op` itself when there is none."""
    if not isinstance(caller, OperationDef):
        return op
    declared = {v.name: v for v in (*caller.variables, *caller.parameters) if not v.constant}
    mapping = {id(v): declared[v.name] for v in op.interface_variables if v.name in declared and not v.constant}
    if not mapping:
        return op
    body = _with_variables((op.nodes, op.transitions), mapping)
    return dataclasses.replace(op, nodes=body[0], transitions=body[1],
                               interface_variables=tuple(v for v in op.interface_variables if id(v) not in mapping))


def _with_variables(x: Any, mapping: dict[int, Variable]) -> Any:
    """`x` (statements, expressions, nodes, transitions) with each variable `v` whose id `mapping`
    holds replaced by `mapping[id(v)]`; unchanged parts are kept as they are."""
    if isinstance(x, Variable):
        return mapping.get(id(x), x)
    if isinstance(x, tuple):
        items = tuple(_with_variables(i, mapping) for i in x)
        return items if any(a is not b for a, b in zip(items, x, strict=True)) else x
    if isinstance(x, (Expr, Stmt, Node, Transition, Trigger)):
        changes = {f.name: _with_variables(getattr(x, f.name), mapping) for f in dataclasses.fields(x)}
        changed = {k: v for k, v in changes.items() if v is not getattr(x, k)}
        return dataclasses.replace(x, **changed) if changed else x
    return x


def unchecked_function(f: Function) -> str:
    """Why a call of a function RoboTool accepts but tockbmc gives no meaning is not supported."""
    return f.unchecked


def assignable(target: Type, value: Type) -> bool:
    """Whether a value of type `value` may be stored where `target` is expected.

    Integers fit reals; an `int` value fits a `nat` place (whether it is
    non-negative is a property of the run, checked by the engines, as in
    RoboChart).  A `real` never fits an integer place.
    """
    if isinstance(target, (ErrorType, AnyElement)) or isinstance(value, (ErrorType, AnyElement)):
        return True
    if target == value:
        return True
    if isinstance(target, SeqType) and isinstance(value, SeqType) or \
            isinstance(target, SetType) and isinstance(value, SetType):
        # Elements keep their representation: an integer sequence is not a real one. The checker
        # converts one where a real one is expected (`widens`; `expressions.conform`).
        return assignable(target.element, value.element) and \
            (target.element != REAL or value.element in (REAL, ANY) or isinstance(value.element, ErrorType))
    if isinstance(target, ProductType) and isinstance(value, ProductType):
        return len(target.parts) == len(value.parts) and \
            all(assignable(a, b) for a, b in zip(target.parts, value.parts, strict=True))
    if isinstance(target, FunctionType) and isinstance(value, FunctionType):
        # A function is kept as one term (a Z3 array): its domain and range as they are, but for
        # a natural range where an integer one is expected (both are Z3 integers).
        return same_representation(target.domain, value.domain) and assignable(target.range, value.range) \
            and same_representation(target.range, value.range)
    if target == REAL and value in (INT, NAT):
        return True
    if target in (INT, NAT) and value in (INT, NAT):
        return True
    return False


def widens(target: Type, value: Type) -> bool:
    """Whether a value of type `value` fits a `target` place once its integers are made reals, at
    any depth of sequences, sets and tuples (RoboTool's `nat` < `int` < `real` inside them too):
    `Seq(nat)` widens to `Seq(real)`, `Set(int * real)` to `Set(real * real)`.

    Function types do not widen: RoboTool accepts a `nat -> nat` where an `int -> int` is
    expected, which is unsound for the domain (the function is applied to negative integers it
    has no value for), so tockbmc keeps `assignable`'s rule for them.  Records are nominal: their
    fields are converted where a record literal gives them (`ExprChecker._x_record_expr`)."""
    if isinstance(target, SeqType) and isinstance(value, SeqType) or \
            isinstance(target, SetType) and isinstance(value, SetType):
        return widens(target.element, value.element)
    if isinstance(target, ProductType) and isinstance(value, ProductType):
        return len(target.parts) == len(value.parts) and \
            all(widens(a, b) for a, b in zip(target.parts, value.parts, strict=True))
    return assignable(target, value)


def kept_alike(a: Type, b: Type, boxed: bool = False) -> bool:
    """Whether the engines keep values of `a` and `b` alike, or convert one to the other as they
    store it: a number is converted (an integer in a real place), but inside a sequence or set
    (`boxed`) only integers and naturals are alike, and a tuple is one value of its own tuple type
    (`nat * nat` and `int * int` are not alike there)."""
    if a == b or isinstance(a, (ErrorType, AnyElement)) or isinstance(b, (ErrorType, AnyElement)):
        return True
    if isinstance(a, SeqType) and isinstance(b, SeqType) or isinstance(a, SetType) and isinstance(b, SetType):
        return kept_alike(a.element, b.element, boxed=True)
    if isinstance(a, ProductType) and isinstance(b, ProductType):
        return not boxed and len(a.parts) == len(b.parts) and \
            all(kept_alike(x, y) for x, y in zip(a.parts, b.parts, strict=True))
    if isinstance(a, FunctionType) and isinstance(b, FunctionType):
        return True  # one term of one sort: `assignable` admits no other
    return a in NUMERIC and b in NUMERIC and (not boxed or (a == REAL) == (b == REAL))


def same_representation(a: Type, b: Type) -> bool:
    """Whether values of `a` and `b` are kept alike (integers and naturals are; reals are not)."""
    return assignable(a, b) and assignable(b, a) and (a == REAL) == (b == REAL) or \
        isinstance(a, (ErrorType, AnyElement)) or isinstance(b, (ErrorType, AnyElement))


def comparable(a: Type, b: Type) -> bool:
    return assignable(a, b) or assignable(b, a)


# --------------------------------------------------------------------- declarations


@dataclass(frozen=True)
class Variable:
    """A variable, constant or parameter.

    `owner` is the qualified name of the element declaring it (a machine,
    controller, interface, operation or function).  `initial` is None for a
    variable without an initial value, or a constant that is a parameter.
    """

    name: str
    type: Type
    constant: bool
    owner: str
    pos: Pos
    initial: Expr | None = None
    kind: str = "local"  # local | interface | parameter


@dataclass(frozen=True)
class Event:
    name: str
    type: Type | None
    owner: str
    pos: Pos
    broadcast: bool = False


@dataclass(frozen=True)
class Clock:
    name: str
    owner: str
    pos: Pos


@dataclass(frozen=True)
class OperationSig:
    """A platform operation: visible as `M::nameCall.args` when called."""

    name: str
    parameters: tuple[Variable, ...]
    owner: str
    pos: Pos
    terminates: bool = False


@dataclass(frozen=True)
class Function:
    """`function f(x : T) : U { precondition … postcondition … }`.

    `definition` is set when a postcondition reads `result == e`; otherwise the
    function is uninterpreted, constrained by its conditions.
    """

    qname: str
    parameters: tuple[Variable, ...]
    result: Type
    preconditions: tuple[Expr, ...]
    postconditions: tuple[Expr, ...]
    definition: Expr | None
    pos: Pos
    # Why a call of it is `unsupported`, for a function RoboTool accepts and tockbmc gives no meaning:
    # the first type error of its conditions, which RoboTool does not check there (docs/semantics.md
    # §6.4), or a recursion other than through `result == e`.  The model loads.
    unchecked: str = ""
    # The recursive function whose calls past its unfolding this stands for (`model.recursion`):
    # then it is any function of its signature, in every reading.
    unfolding_of: str = ""

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    @property
    def generic(self) -> bool:
        """Whether the signature has generic types `?X` (then only its instances are called)."""
        return bool(type_vars(self.result) or any(type_vars(p.type) for p in self.parameters))


@dataclass(frozen=True)
class Interface:
    qname: str
    events: tuple[Event, ...]
    variables: tuple[Variable, ...]
    operations: tuple[OperationSig, ...]
    clocks: tuple[Clock, ...]
    pos: Pos

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]


# --------------------------------------------------------------------- expressions


@dataclass(frozen=True)
class Expr:
    type: Type
    pos: Pos


@dataclass(frozen=True)
class Literal(Expr):
    """An integer (int), real (Fraction), boolean (bool) or string (str) literal."""

    value: int | Fraction | bool | str


@dataclass(frozen=True)
class EnumLiteral(Expr):
    """A literal of an enumeration, with its arguments if the literal has parameters (`EM3(1)`)."""

    enum: EnumType
    literal: str
    args: tuple[Expr, ...] = ()


@dataclass(frozen=True)
class VarRef(Expr):
    variable: Variable


@dataclass(frozen=True)
class ResultRef(Expr):
    """`result` in a function's postcondition."""


@dataclass(frozen=True)
class FieldRef(Expr):
    record: Expr
    field_name: str


@dataclass(frozen=True)
class RecordLiteral(Expr):
    fields: tuple[tuple[str, Expr], ...]

    @property
    def omitted(self) -> tuple[RecordField, ...]:
        """The fields of its record type it leaves out (RoboTool accepts `R(|p = 0|)`; DESIGN.md)."""
        given = {name for name, _ in self.fields}
        return tuple(f for f in self.type.fields if f.name not in given) if isinstance(self.type, RecordType) else ()


def omits_fields(e: Expr | None) -> bool:
    """Whether `e` is a record literal leaving fields out: as an initial value, those are open (any
    value of their type and range), as a variable without an initial value is; elsewhere they are
    not encoded."""
    return isinstance(e, RecordLiteral) and bool(e.omitted)


@dataclass(frozen=True)
class Unary(Expr):
    op: str  # "not" | "-" | "trunc" (a real rounded towards zero: `--robotool`'s real division)
    operand: Expr


@dataclass(frozen=True)
class Binary(Expr):
    """`op` is one of + - * / % == != < <= > >= and or implies iff."""

    op: str
    left: Expr
    right: Expr


@dataclass(frozen=True)
class IfExpr(Expr):
    condition: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True)
class Call(Expr):
    function: Function
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class SeqLiteral(Expr):
    """`<a, b, …>`."""

    items: tuple[Expr, ...]


@dataclass(frozen=True)
class SetLiteral(Expr):
    """`{a, b, …}`."""

    items: tuple[Expr, ...]


@dataclass(frozen=True)
class TupleLiteral(Expr):
    """`(| a, b, … |)`."""

    items: tuple[Expr, ...]


@dataclass(frozen=True)
class Index(Expr):
    """`s[i]` of a sequence (1-based; outside `1..#s` any value, as outside a precondition) or
    `p[k]` of a tuple (`k` a literal)."""

    value: Expr
    index: Expr


@dataclass(frozen=True)
class Builtin(Expr):
    """An operation on sequences, sets or tuples: `op` names it (see `BUILTINS`), `args` its operands."""

    op: str
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class Let(Expr):
    """`let x == e @ body`: `variable` (kind "let") stands for `value` in `body`."""

    variable: Variable
    value: Expr
    body: Expr


@dataclass(frozen=True)
class Quantifier(Expr):
    """`forall x : T | c @ p`, `exists …`, `exists1 …` (`kind`): `variables` (kind "bound") range
    over their types' values (within the ranges in force); `condition` (None: true) restricts them."""

    kind: str  # forall | exists | exists1
    variables: tuple[Variable, ...]
    condition: Expr | None
    body: Expr


@dataclass(frozen=True)
class Lambda(Expr):
    """`lambda x : T, … | c @ e`, of type `FunctionType`: `variables` (kind "bound") are the
    arguments; where `condition` (None: true) fails the function's value is any value."""

    variables: tuple[Variable, ...]
    condition: Expr | None
    body: Expr


@dataclass(frozen=True)
class Apply(Expr):
    """`f(a, …)` where `f` is a value of a function type (a variable, a `lambda`, a cast)."""

    function: Expr
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class SetComprehension(Expr):
    """`{x : T, … | p @ e}` (RoboChart's `SetComp`): the values of `e` (without `@ e`: of the one
    bound variable) for the values of `variables` (kind "bound") that satisfy `condition`."""

    variables: tuple[Variable, ...]
    condition: Expr | None
    term: Expr | None


@dataclass(frozen=True)
class Since(Expr):
    clock: Clock


@dataclass(frozen=True)
class SinceEntry(Expr):
    state: str  # node path within the machine


@dataclass(frozen=True)
class Interval(Expr):
    """`[a, b]` as used by `wait`: bounds and whether each end is closed."""

    low: Expr
    high: Expr
    low_closed: bool
    high_closed: bool


@dataclass(frozen=True)
class UnsupportedExpr(Expr):
    """An expression RoboTool accepts and tockbmc gives no meaning (`the`, `inverse`, a toolkit
    function not built in): the model loads, and each assertion whose element holds it is
    `unsupported` (`unsupported_in`), naming `what` at `pos`. Its type is the error type."""

    what: str


# --------------------------------------------------------------------- statements


@dataclass(frozen=True)
class Stmt:
    pos: Pos


@dataclass(frozen=True)
class Skip(Stmt):
    pass


@dataclass(frozen=True)
class Seq(Stmt):
    statements: tuple[Stmt, ...]


@dataclass(frozen=True)
class Assign(Stmt):
    """`x = e` or `x.f.g = e`: `fields` is the path into a record variable."""

    variable: Variable
    fields: tuple[str, ...]
    value: Expr


@dataclass(frozen=True)
class Send(Stmt):
    """An output in an action: `e`, `e!v` or `e.v`."""

    event: Event
    value: Expr | None


@dataclass(frozen=True)
class Receive(Stmt):
    """An input in an action: `e?x`."""

    event: Event
    variable: Variable | None


@dataclass(frozen=True)
class OperationCall(Stmt):
    """A call of a platform operation (`operation` is an OperationSig) or of a
    defined operation (an OperationDef, inlined by the encoder)."""

    operation: OperationSig | OperationDef
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class If(Stmt):
    condition: Expr
    then: Stmt
    otherwise: Stmt


@dataclass(frozen=True)
class Wait(Stmt):
    """`wait(n)` (low == high) or `wait([a, b])`."""

    low: Expr
    high: Expr


@dataclass(frozen=True)
class ClockReset(Stmt):
    clock: Clock


@dataclass(frozen=True)
class Deadline(Stmt):
    """`s <{d}`: `s` must complete within `bound` tocks."""

    statement: Stmt
    bound: Expr


@dataclass(frozen=True)
class UnsupportedStmt(Stmt):
    """A statement RoboTool accepts and tockbmc gives no meaning (`s[i].f = e`): as
    `UnsupportedExpr`, it makes the assertions whose element holds it `unsupported`."""

    what: str


def unsupported_in(*roots: object) -> UnsupportedExpr | UnsupportedStmt | None:
    """The first construct without a meaning (`UnsupportedExpr`, `UnsupportedStmt`) in the source
    that `roots` hold (`parts`: through the operations and functions they call), else None."""
    found = [x for x in parts(*roots) if isinstance(x, (UnsupportedExpr, UnsupportedStmt))]
    return min(found, key=lambda x: (x.pos.path, x.pos.line, x.pos.column, x.what), default=None)


def statements(s: Stmt | None) -> list[Stmt]:
    """`s` and every statement nested in it (sequences, branches, deadlines), without recursion."""
    found: list[Stmt] = []
    stack = [s]
    while stack:
        st = stack.pop()
        if st is None:
            continue
        found.append(st)
        if isinstance(st, Seq):
            stack.extend(st.statements)
        elif isinstance(st, If):
            stack.extend((st.then, st.otherwise))
        elif isinstance(st, Deadline):
            stack.append(st.statement)
    return found


def subexpressions(x: object) -> list[Expr]:
    """Every expression inside `x` (an expression, a statement, or a tuple of them), without recursion."""
    found: list[Expr] = []
    stack = [x]
    while stack:
        item = stack.pop()
        if isinstance(item, tuple):
            stack.extend(item)
        elif isinstance(item, (Expr, Stmt)):
            if isinstance(item, Expr):
                found.append(item)
            stack.extend(getattr(item, f.name) for f in dataclasses.fields(item))
    return found


def free_functions(*roots: object) -> list[Function]:
    """The functions called from `roots` (model elements, operations, expressions: everything they
    hold, through the definitions of the functions called) whose results no body fixes: without a
    `result == e` postcondition, or with preconditions, outside which any value is possible
    (docs/semantics.md §6.4). A claim decided over every run holds whatever they compute, but a run
    found as a witness stands for the interpretation it chose."""
    found = {id(item): item for item in parts(*roots)
             if isinstance(item, Function) and (item.definition is None or item.preconditions)}
    return sorted(found.values(), key=lambda f: f.qname)


def tree_size(e: Expr | None, limit: int) -> int:
    """How many nodes the expression tree has, a part shared by several counted each time (as an
    engine evaluates it), counted up to just past `limit`."""
    count = 0
    todo: list[object] = [] if e is None else [e]
    while todo and count <= limit:
        x = todo.pop()
        if isinstance(x, Expr):
            count += 1
            todo += [getattr(x, f.name) for f in dataclasses.fields(x) if f.name not in ("type", "pos")]
        elif isinstance(x, tuple):
            todo += list(x)
    return count


def parts(*roots: object) -> Iterator[object]:
    """Every model object `roots` hold, themselves included, each once: the fields of dataclasses
    and the items of tuples, lists, sets and dicts, walked with a stack (models nest deep)."""
    seen: set[int] = set()
    stack: list[object] = list(roots)
    while stack:
        item = stack.pop()
        if isinstance(item, (str, int, float, bool, Fraction, Pos)) or item is None or id(item) in seen:
            continue
        seen.add(id(item))
        yield item
        if isinstance(item, (tuple, list, frozenset, set)):
            stack.extend(item)
        elif isinstance(item, dict):
            stack.extend(item.values())
        elif dataclasses.is_dataclass(item) and not isinstance(item, type):
            stack.extend(getattr(item, f.name) for f in dataclasses.fields(item))


# --------------------------------------------------------------------- behaviour


@dataclass(frozen=True)
class Node:
    """A state, initial junction, junction or final state.

    `path` is unique within its machine: ancestor names joined by `::`.  A probabilistic junction
    is a junction with `probabilistic` set: its choice is read as a nondeterministic one and its
    transitions' probabilities are dropped (`model.probabilistic`), so the engines see a junction.
    """

    kind: str  # state | initial | junction | final
    name: str
    path: str
    parent: str | None
    pos: Pos
    entry: Stmt | None = None
    during: Stmt | None = None
    exit: Stmt | None = None
    children: tuple[str, ...] = ()
    probabilistic: bool = False  # declared `probabilistic` (kind "junction")

    @property
    def composite(self) -> bool:
        return self.kind == "state" and bool(self.children)


@dataclass(frozen=True)
class Trigger:
    """The event part of a transition: `e`, `e?x`, `e!v` or `e.v`."""

    event: Event
    kind: str  # plain | input | output | sync
    variable: Variable | None = None
    value: Expr | None = None


@dataclass(frozen=True)
class Transition:
    name: str
    source: str
    target: str
    pos: Pos
    container: str | None  # node path of the state declaring it, None at top level
    trigger: Trigger | None = None
    clock_resets: tuple[Clock, ...] = ()
    deadline: Expr | None = None
    condition: Expr | None = None
    is_else: bool = False
    action: Stmt | None = None


@dataclass(frozen=True)
class Behaviour:
    """What machines and defined operations share: declarations and a graph."""

    qname: str
    pos: Pos
    variables: tuple[Variable, ...]  # local variables and constants
    interface_variables: tuple[Variable, ...]  # from required/provided interfaces
    events: tuple[Event, ...]
    clocks: tuple[Clock, ...]
    operations: tuple[OperationSig, ...]  # platform operations it may call
    nodes: tuple[Node, ...]
    transitions: tuple[Transition, ...]
    required_interfaces: tuple[str, ...] = ()
    provided_interfaces: tuple[str, ...] = ()
    used_interfaces: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    def node(self, path: str) -> Node:
        for n in self.nodes:
            if n.path == path:
                return n
        raise KeyError(path)

    def event(self, name: str) -> Event | None:
        for e in self.events:
            if e.name == name:
                return e
        return None

    @property
    def constants(self) -> tuple[Variable, ...]:
        return tuple(v for v in self.variables if v.constant)


@dataclass(frozen=True)
class StateMachine(Behaviour):
    pass


@dataclass(frozen=True)
class OperationDef(Behaviour):
    parameters: tuple[Variable, ...] = ()
    terminates: bool = False


@dataclass(frozen=True)
class OperationMachine(StateMachine):
    """A defined operation checked on its own, as RoboTool's `OP_<name>` process (its generated
    `STM(id__) = Stateful(id__) \\ {terminate}`): a machine named `OP_<name>`, so that its events
    read `OP_<name>::e` as FDR's do; its parameters are constants (`with parameter x of op set to
    v`); reaching its final state ends it with ✓ alone, its `terminate` hidden (docs/semantics.md §4.8)."""

    operation: OperationDef | None = None


def event_directions(behaviour: Behaviour) -> tuple[set[str], set[str]]:
    """(events the behaviour sends, events it receives), from its actions and triggers."""
    sends: set[str] = set()
    receives: set[str] = set()

    for st in behaviour_statements(behaviour):
        if isinstance(st, Send):
            sends.add(st.event.name)
        elif isinstance(st, Receive):
            receives.add(st.event.name)
    for t in behaviour.transitions:
        if t.trigger is not None:
            (sends if t.trigger.kind == "output" else receives).add(t.trigger.event.name)
    return sends, receives


def behaviour_statements(behaviour: Behaviour) -> Iterator[Stmt]:
    """Every statement of a behaviour's actions: its nodes' entry, during and exit actions, then
    its transitions' actions, nested ones included (`statements`)."""
    for n in behaviour.nodes:
        for a in (n.entry, n.during, n.exit):
            yield from statements(a)
    for t in behaviour.transitions:
        yield from statements(t.action)


def uses_event(behaviours: Iterable[Behaviour], event: str, sends: bool) -> bool:
    """Whether any of these behaviours (a machine and the operations it may call) sends (else
    receives) on `event`."""
    for b in behaviours:
        out, into = event_directions(b)
        if event in (out if sends else into):
            return True
    return False


def qualifies(qualifier: str, machine: str) -> bool:
    """Whether `qualifier` (the last part of the name before a state's, as in `stm0::s`) names
    machine `machine`: its own name, or for an operation checked on its own (`OP_op`) the operation's."""
    return qualifier == machine or f"OP_{qualifier}" == machine


def operation_machine(op: OperationDef) -> OperationMachine:
    """The operation as the element an assertion checks (`OperationMachine`)."""
    package, _, name = op.qname.rpartition("::")
    return OperationMachine(
        qname=f"{package}::OP_{name}" if package else f"OP_{name}", pos=op.pos,
        variables=(*op.parameters, *op.variables), interface_variables=op.interface_variables, events=op.events,
        clocks=op.clocks, operations=op.operations, nodes=op.nodes, transitions=op.transitions,
        required_interfaces=op.required_interfaces, provided_interfaces=op.provided_interfaces,
        used_interfaces=op.used_interfaces, operation=op)


@dataclass(frozen=True)
class Connection:
    """`connection A on e to B on f`: ends are element names local to the owner."""

    source: str
    source_event: Event
    target: str
    target_event: Event
    asynchronous: bool
    bidirectional: bool
    pos: Pos


@dataclass(frozen=True)
class MachineInstance:
    """A machine inside a controller: `sref name = S` or an inline `stm`."""

    name: str
    machine: StateMachine
    pos: Pos


@dataclass(frozen=True)
class OperationInstance:
    """A defined operation inside a controller: `opref name = Op` or an inline `operation`."""

    name: str
    operation: OperationDef
    pos: Pos


@dataclass(frozen=True)
class Controller:
    qname: str
    pos: Pos
    events: tuple[Event, ...]
    variables: tuple[Variable, ...]
    machines: tuple[MachineInstance, ...]
    connections: tuple[Connection, ...]
    operations: tuple[OperationInstance, ...]
    required_interfaces: tuple[str, ...] = ()
    provided_interfaces: tuple[str, ...] = ()
    used_interfaces: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    def event(self, name: str) -> Event | None:
        for e in self.events:
            if e.name == name:
                return e
        return None


@dataclass(frozen=True)
class ControllerInstance:
    name: str
    controller: Controller
    pos: Pos


@dataclass(frozen=True)
class RoboticPlatform:
    qname: str
    pos: Pos
    events: tuple[Event, ...]
    variables: tuple[Variable, ...]
    operations: tuple[OperationSig, ...]
    provided_interfaces: tuple[str, ...] = ()
    used_interfaces: tuple[str, ...] = ()
    required_interfaces: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]


@dataclass(frozen=True)
class Module:
    qname: str
    pos: Pos
    platform: RoboticPlatform | None
    platform_name: str | None
    controllers: tuple[ControllerInstance, ...]
    connections: tuple[Connection, ...]

    @property
    def name(self) -> str:
        return self.qname.rsplit("::", 1)[-1]


# --------------------------------------------------------------------- assertions


@dataclass(frozen=True)
class CspBlock:
    """A `csp NAME csp-begin … csp-end` block, kept as text until it is parsed."""

    name: str
    timing: str | None  # "timed" | "untimed" | None
    associated: tuple[str, ...]
    text: str
    pos: Pos
    defines: tuple[str, ...]  # process names defined at its top level
    code_line: int = 1  # where the text after `csp-begin` starts in the file
    code_column: int = 1


@dataclass(frozen=True)
class ConstantSetting:
    """`constant c of P set to v`: `element` is the qualified name of P."""

    constant: str
    element: str
    value: Expr
    pos: Pos
    kind: str = "constant"  # constant | parameter (of an operation)


@dataclass(frozen=True)
class Assertion:
    """One assertion of an `.assertions` file.

    `kind` is one of: deadlock-free, divergence-free, deterministic,
    timelock-free, terminates, reachable, refines, equals, clock-initialised.
    `subject` and `other` are qualified names of model elements or names of
    CSP processes (`subject_is_process` says which).
    """

    name: str
    kind: str
    subject: str
    negated: bool
    pos: Pos
    text: str
    timing: str | None = None
    other: str | None = None
    semantic_model: str | None = None  # traces | failures | failures divergences | tick-tock
    settings: tuple[ConstantSetting, ...] = ()
    subject_is_process: bool = False
    other_is_process: bool = False
    # The file that tells it apart where another `.assertions` file of the project has an assertion
    # of the same name ("" where none has): RoboTool keeps each file's assertions apart, each file
    # becoming a CSP file of its own.
    file: str = ""

    @property
    def label(self) -> str:
        """How results name it: `A1`, or `props.assertions:A1` where another file has an `A1` too."""
        return f"{self.file}:{self.name}" if self.file else self.name

    def selected_by(self, name: str) -> bool:
        """Whether `-a name` picks it: its name picks every assertion of that name, its label this one."""
        return name in (self.name, self.label)


# --------------------------------------------------------------------- the project


@dataclass(frozen=True)
class Project:
    """A loaded directory of `.rct` and `.assertions` files, fully resolved."""

    root: str
    files: tuple[str, ...]
    types: tuple[Type, ...] = ()
    interfaces: tuple[Interface, ...] = ()
    functions: tuple[Function, ...] = ()
    machines: tuple[StateMachine, ...] = ()
    operations: tuple[OperationDef, ...] = ()
    controllers: tuple[Controller, ...] = ()
    platforms: tuple[RoboticPlatform, ...] = ()
    modules: tuple[Module, ...] = ()
    csp_blocks: tuple[CspBlock, ...] = ()
    assertions: tuple[Assertion, ...] = ()
    warnings: tuple[Diagnostic, ...] = ()
    sources: dict[str, str] = field(default_factory=dict, compare=False, hash=False)
    # With `--robotool` (docs/semantics.md §6.6): the ranges RoboTool's bounded arithmetic keeps
    # results in, by type name (`core_int`), which the model's expressions are rewritten for and
    # the CSP blocks' `Plus(a, b, T)` reads; empty for exact arithmetic.
    arithmetic: tuple[tuple[str, Fraction, Fraction], ...] = ()

    def element(self, qname: str) -> StateMachine | Controller | Module | OperationDef | None:
        """The machine, controller, module or operation with this qualified name."""
        for group in (self.machines, self.controllers, self.modules, self.operations):
            for item in group:
                if item.qname == qname:
                    return item
        return None
