"""CSP specifications as finite monitors (docs/semantics.md §8).

A specification is evaluated into process terms with an explicit operational
semantics in tock-CSP: `after(p, e)` for a visible event (`tock` included),
`taus(p)` for internal steps (✓ hidden by `;` among them), `ticks(p)` for
successful termination.  Maximal progress always applies: a term offers
`tock` only when it has no internal step and cannot terminate.

`Monitor` determinises the specification over the implementation's events,
as a set of terms after each trace (so nondeterministic specifications are
followed along every path; the traces of `P |~| Q` are those of `P [] Q`).
Events carry values; a specification only distinguishes the values it
mentions, so per channel the monitor has one atom per mentioned value and one
for every other value (`OTHER`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import cast

from lark import Token, Tree

from tockbmc.model import ast
from tockbmc.model.csp import CspError, Definition, canonical, pos_of
from tockbmc.model.errors import Unsupported


class _Other:
    """A value the specification does not mention."""

    def __repr__(self) -> str:
        return "…"


OTHER = _Other()
TOCK: tuple = ("tock",)
Event = tuple  # ("EXAX::move", "in", value, …): a channel's canonical name, then its fields


@dataclass(frozen=True)
class EnumValue:
    """A literal of a model enumeration, `Colour::RED` (or RoboTool's `Colour_RED`)."""

    type_name: str
    index: int
    text: str

    def __str__(self) -> str:
        return self.text


@dataclass(frozen=True)
class Input:
    """`?x` in a prefix: binds x to the field's value.  `used`: what follows the prefix reads x, so
    the monitor tells every value of the field apart where the channel's values are few
    (`Semantics.field_values`), instead of one class for the values the specification never names."""

    name: str
    used: bool = False


class Any_:
    """Every value of a field (from enumerating `{| c |}`)."""

    def __repr__(self) -> str:
        return "_"


ANY = Any_()
# The most events of one channel an internal choice over the channel's events takes one by one.
BRANCHES_LISTED = 3


# ---------------------------------------------------------------- event sets


@dataclass(frozen=True)
class EventSet:
    """A set of events: `Events`, `{| c, … |}` (prefixes), `{ e, … }` (exact), and set algebra."""

    kind: str  # all | closure | exact | union | diff | inter
    items: tuple = ()

    def contains(self, e: Event) -> bool:
        if self.kind == "all":
            return True
        if self.kind == "closure":
            return any(_extends(e, p) for p in self.items)
        if self.kind == "exact":
            return any(len(e) == len(p) and _extends(e, p) for p in self.items)
        a, b = self.items
        if self.kind == "union":
            return a.contains(e) or b.contains(e)
        if self.kind == "inter":
            return a.contains(e) and b.contains(e)
        return a.contains(e) and not b.contains(e)

    def mentions(self) -> set[Event]:
        if self.kind in ("closure", "exact"):
            return set(self.items)
        if self.kind == "all":
            return set()
        return self.items[0].mentions() | self.items[1].mentions()


def _extends(e: Event, prefix: Event) -> bool:
    if len(e) < len(prefix):
        return False
    return all(p is ANY or _same(x, p) for x, p in zip(e, prefix, strict=False))


def _same(a: object, b: object) -> bool:
    if a is OTHER or b is OTHER:
        return False
    return bool(a == b)


EVENTS = EventSet("all")


# ---------------------------------------------------------------- environments and terms


class Env:
    """Names in scope: parameters and let-bound values, local definitions, and whether in `Timed`."""

    def __init__(self, values: dict[str, object], defs: dict[str, Definition], timed: bool,
                 parent: Env | None = None):
        self.values, self.defs, self.timed, self.parent = values, defs, timed, parent
        self._key: tuple = (tuple(sorted((k, _key(v)) for k, v in values.items())),
                     tuple(sorted((k, id(d.body)) for k, d in defs.items())), timed,
                     parent._key if parent else None)

    def lookup(self, name: str) -> tuple[str, object] | None:
        env: Env | None = self
        while env is not None:
            if name in env.values:
                return "value", env.values[name]
            if name in env.defs:
                return "def", (env.defs[name], env)
            env = env.parent
        return None

    def __hash__(self) -> int:
        return hash(self._key)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Env) and self._key == other._key


def _key(v: object) -> object:
    return v if not isinstance(v, (Tree, Env)) else id(v)


class Proc:
    """A specification process term."""


@dataclass(frozen=True, eq=False)
class Thunk(Proc):
    """An expression not evaluated yet (so recursion unfolds only when it is reached)."""

    tree: Tree
    env: Env

    def __hash__(self) -> int:
        return hash((id(self.tree), self.env))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Thunk) and self.tree is other.tree and self.env == other.env


@dataclass(frozen=True)
class Stop(Proc):
    timed: bool  # in a Timed section STOP lets time pass; outside it refuses tock


@dataclass(frozen=True)
class Skip(Proc):
    pass


@dataclass(frozen=True)
class Omega(Proc):
    """Terminated."""


@dataclass(frozen=True)
class Run(Proc):
    events: EventSet
    timed: bool  # RUN and CHAOS have the same traces


@dataclass(frozen=True)
class Wait(Proc):
    n: int


@dataclass(frozen=True)
class Prefix(Proc):
    pattern: tuple
    then: Tree
    env: Env
    timed: bool

    def __hash__(self) -> int:
        return hash((self.pattern, id(self.then), self.env, self.timed))

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Prefix) and self.pattern == other.pattern and self.then is other.then
                and self.env == other.env and self.timed == other.timed)


@dataclass(frozen=True)
class Binary(Proc):
    """external | internal | seq | interrupt | timeout | parallel | exception | hide."""

    op: str
    left: Proc
    right: Proc | None = None
    events: EventSet | None = None
    timed: bool = False


@dataclass(frozen=True)
class Deadline(Proc):
    """ADeadline(A, d) (`event` False) and EDeadline(e, d) (`event` True) after `n` tocks."""

    events: EventSet
    d: int
    n: int
    event: bool


@dataclass(frozen=True)
class EndBy(Proc):
    """P must terminate before d + 1 tocks have passed (EndBy and Deadline)."""

    p: Proc
    d: int
    n: int


class LtsGraph:
    """A model element's state graph as a specification (`Lts` terms are its nodes): per node, its
    moves as (event, next node), the event None for an internal step; and the nodes that have
    terminated (they can do ✓).  Built by the explicit interpreter (`explicit.lts`), so that a model
    element can stand where a specification does (refinement between two elements).  Compared by
    identity: each is built once per check."""

    def __init__(self, moves: tuple[tuple[tuple[tuple | None, int], ...], ...], ticks: frozenset[int]):
        self.moves, self.ticks = moves, ticks


@dataclass(frozen=True, eq=False)
class Lts(Proc):
    """A node of an `LtsGraph`."""

    graph: LtsGraph
    node: int

    def __hash__(self) -> int:
        return hash((id(self.graph), self.node))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Lts) and self.graph is other.graph and self.node == other.node


# ---------------------------------------------------------------- evaluation


class ModelProcess:
    """`M::D__(id, …)`: an element of the model, met where only a specification may be."""

    def __init__(self, name: str, args: tuple[object, ...], node: Tree):
        self.name, self.args, self.node = name, args, node


def _member_order(v: object) -> tuple:
    """A set's members in a fixed order: numbers and booleans by value, enumeration literals by
    their place in the declaration (they have no order of their own)."""
    if isinstance(v, EnumValue):
        return (1, v.type_name, v.index)
    return (0, v)


class Evaluator:
    """Evaluates CSP expressions; `lookup_top` finds top-level definitions by name."""

    def __init__(self, lookup_top: Callable[[str], Definition | None], block: ast.CspBlock,
                 literals: dict[str, EnumValue] | None = None, memory: frozenset[str] = frozenset(),
                 enumerations: dict[str, frozenset[EnumValue]] | None = None,
                 fields: dict[str, tuple[str, int]] | None = None,
                 arithmetic: dict[str, tuple[Fraction, Fraction]] | None = None):
        self.lookup_top = lookup_top
        # with `--robotool`, the ranges RoboTool's bounded arithmetic keeps results in, by type name
        self.arithmetic = arithmetic or {}
        self.block = block
        self.literals = literals or {}
        self.fields = fields or {}  # RoboTool's `pkg_R_f`: a record's field by name and by place
        self.enumerations = enumerations or {}  # an enumeration type's name (RoboTool's `pkg_E` too): its literals
        self.memory = memory  # RoboTool's `set_x`/`get_x` channel names of the model's variables, not its events
        self.semantics: Semantics | None = None  # the steps' side, which knows the model's channels and values

    def error(self, node: Tree | Token, what: str) -> CspError:
        return CspError(pos_of(self.block, node), what)

    def definition(self, d: Definition, args: tuple[object, ...] = ()) -> object:
        if len(args) != len(d.params):
            raise CspError(d.pos, f"'{d.name}' takes {len(d.params)} arguments, not {len(args)}")
        self.block = d.block
        env = Env(dict(zip(d.params, args, strict=True)), {}, d.timed)
        return self.eval(d.body, env)

    def eval(self, t: Tree | Token, env: Env) -> object:  # noqa: C901 - one case per construct
        if isinstance(t, Token):
            return str(t)
        k = t.data
        c = t.children
        if k == "name":
            return self.name(cast(Token, c[0]), env)
        if k == "number":
            return int(str(c[0]))
        if k == "true":
            return True
        if k == "false":
            return False
        if k == "tuple":
            return tuple(self.eval(x, env) for x in c)
        if k == "closure":
            return EventSet("closure", tuple(self.event(x, env) for x in c))
        if k == "set":
            items = [self.eval(x, env) for x in c]
            if all(isinstance(x, tuple) for x in items):
                return EventSet("exact", tuple(items))
            return frozenset(items)
        if k == "interval":
            lo, hi = self.number(c[0], env), self.number(c[1], env)
            return frozenset(range(lo, hi + 1))
        if k == "dot":
            head = self.eval(c[0], env)
            if not isinstance(head, tuple):
                raise self.error(t, "'.' builds events; its left side must be a channel")
            return (*head, self.field(c[1], env))
        if k == "comm":
            return self.pattern(t, env)
        if k == "channel_event":  # a channel the block declares, without values: its one event
            return (str(c[0]),)
        if k in ("or_", "and_"):
            first = self.boolean(c[0], env)
            if k == "or_" and first or k == "and_" and not first:
                return first
            return self.boolean(c[1], env)
        if k == "not_":
            return not self.boolean(c[0], env)
        if k == "compare":
            a, op, b = self.eval(c[0], env), str(c[1]), self.eval(c[2], env)
            _no_other(self, t, a, b)
            if op in ("==", "!="):
                return (a == b) == (op == "==")
            try:  # only the operator asked for: enumeration literals have no order
                return {"<": lambda: a < b, "<=": lambda: a <= b, ">": lambda: a > b,  # type: ignore[operator]
                        ">=": lambda: a >= b}[op]()  # type: ignore[operator]
            except TypeError:
                raise self.error(t, f"'{op}' compares numbers") from None
        if k == "arith":
            x, op, y = self.number(c[0], env), str(c[1]), self.number(c[2], env)
            if op in "/%" and y == 0:
                raise self.error(t, "division by zero")
            if op in "/%":
                return _div(x, y) if op == "/" else _mod(x, y)
            return {"+": x + y, "-": x - y, "*": x * y}[op]
        if k == "negate":
            return -self.number(c[0], env)
        if k == "if_":
            return self.eval(c[1] if self.boolean(c[0], env) else c[2], env)
        if k == "let":
            defs = {d.name: d for d in (self._local(x) for x in c[:-1])}
            return self.eval(c[-1], Env({}, defs, env.timed, env))
        if k == "apply":
            return self.apply(t, env)
        if k == "prefix":
            if any(isinstance(x, Tree) and x.data == "restricted" for x in c[0].children):
                return self.restricted_prefix(t, env)
            return Prefix(self.pattern(c[0], env, _names_in(c[1])), c[1], env, env.timed)
        if k == "guard":
            return self.proc(c[1], env) if self.boolean(c[0], env) else Stop(env.timed)
        if k in ("external", "internal", "seq", "interrupt", "timeout"):
            return Binary(k, self.proc(c[0], env), self.proc(c[1], env), None, env.timed)
        if k in ("parallel", "exception"):
            return Binary(k, self.proc(c[0], env), self.proc(c[2], env), self.events(c[1], env), env.timed)
        if k == "interleave":
            return Binary("parallel", self.proc(c[0], env), self.proc(c[1], env), EventSet("exact"), env.timed)
        if k == "hide":
            return Binary("hide", self.proc(c[0], env), None, self.events(c[1], env), env.timed)
        if k == "project":
            kept = self.events(c[1], env)
            return Binary("hide", self.proc(c[0], env), None, EventSet("diff", (EVENTS, kept)), env.timed)
        if k == "replicated":
            return self.replicated(t, env)
        if k == "rename":
            raise self.error(t, "renaming '[[ … ]]' is outside the CSP subset tockbmc understands")
        raise self.error(t, f"'{k}' is outside the CSP subset tockbmc understands")

    def _local(self, t: Tree) -> Definition:
        from tockbmc.model.csp import definition
        return definition(self.block, t, False)

    def name(self, tok: Token, env: Env) -> object:
        name = str(tok)
        found = env.lookup(name)
        if found is not None:
            kind, value = found
            if kind == "value":
                return value
            d, denv = cast("tuple[Definition, Env]", value)
            return self._use(d, Env({}, {}, denv.timed or d.timed, denv), ())
        if name == "STOP":
            return Stop(env.timed)
        if name == "USTOP":
            return Stop(False)
        if name == "SKIP":
            return Skip()
        if name == "Events":
            return EVENTS
        if name in ("in", "out"):
            return name
        if name == "tock":
            return TOCK
        top = self.lookup_top(name)
        if top is not None:
            return self._use(top, Env({}, {}, top.timed), ())
        literal = self.literals.get(name) or self.literals.get("::".join(name.split("::")[-2:]))
        if literal is not None:
            return literal
        if name in self.enumerations:
            return self.enumerations[name]
        if "::" in name:
            memory = _MEMORY_CHANNEL.fullmatch(name.rsplit("::", 1)[-1])
            if memory is not None and memory.group(0) in self.memory and memory.group(1) != "set":
                raise self.error(tok, f"'{name}' is RoboTool's channel for "
                                      f"{'reading' if memory.group(1) == 'get' else 'writing'} variable "
                                      f"{memory.group(2)}; RoboTool hides its reads and tockbmc has no events "
                                      "for them (docs/semantics.md §5.5), so a specification naming one is not "
                                      "supported")
            return (canonical(name),)
        raise self.error(tok, f"unknown name '{name}'")

    def _use(self, d: Definition, env: Env, args: tuple[object, ...]) -> object:
        """A definition applied to arguments: processes stay unevaluated (recursion), values are computed."""
        if len(args) != len(d.params):
            raise CspError(d.pos, f"'{d.name}' takes {len(d.params)} arguments, not {len(args)}")
        inner = Env(dict(zip(d.params, args, strict=True)), {}, env.timed or d.timed, env)
        if _is_process(d.body):
            return Thunk(d.body, inner)
        return self.eval(d.body, inner)

    def apply(self, t: Tree, env: Env) -> object:
        head, *args_t = t.children
        if head.data != "name":
            raise self.error(t, "only named processes and functions can be applied")
        name = str(head.children[0])
        if name.endswith("::D__") or name.endswith("::O__"):
            return ModelProcess(name[:-5], tuple(self.eval(a, env) for a in args_t), t)
        found = env.lookup(name)
        top = self.lookup_top(name) if found is None else None
        # RoboTool's helpers, also where its generated instantiation defines them (`Plus(e1,e2,T) = if
        # member(e1+e2,T) then e1+e2 else e1` in a block named Instantiations): exact, as below.
        generated = top is not None and top.block.name == "Instantiations"
        if found is None and (top is None or generated) and name in _BOUNDED_ARITHMETIC \
                and len(args_t) == _BOUNDED_ARITHMETIC[name] + 1:
            return self.bounded_arithmetic(t, name, args_t[:-1], env, args_t[-1])
        args = tuple(self.eval(a, env) for a in args_t)
        if found is not None and found[0] == "def":
            d, denv = cast("tuple[Definition, Env]", found[1])
            return self._use(d, denv, args)
        if top is not None:
            return self._use(top, Env({}, {}, top.timed), args)
        if name in self.fields and len(args) == 1:
            return self.record_field(t, name, args[0])
        builtin = _BUILTINS.get(name)
        if builtin is None:
            raise self.error(t, f"'{name}' is outside the CSP subset tockbmc understands")
        try:
            return builtin(env.timed, *args)
        except (TypeError, ValueError):
            raise self.error(t, f"wrong arguments for '{name}'") from None

    def record_field(self, t: Tree, name: str, v: object) -> object:
        """RoboTool's `pkg_R_f(v)`: field f of record v, or the part in f's place of a tuple (RoboTool
        writes a record as the tuple of its fields, so test15 reads `test15_DT_p((a, 1))` as 1)."""
        field, place = self.fields[name]
        if v is OTHER:
            raise self.error(t, "this value comes from an input the specification does not track")
        if isinstance(v, dict) and field in v:
            return v[field]
        if isinstance(v, tuple) and place < len(v):
            return v[place]
        raise self.error(t, f"'{name}' reads field {field} of a record, and this is not one")

    def bounded_arithmetic(self, t: Tree, name: str, args_t: list, env: Env, type_t: Tree | Token) -> int:
        """RoboTool's `Plus(a, b, T)`, `Minus`, `Mult`, `Div`, `Modulus`, `Neg(a, T)`: its generated
        instantiation keeps a result outside T at the first operand. The model's arithmetic is exact
        by default (docs/semantics.md §6.5), and so is the specification's, the type argument unread,
        so that a specification that repeats the model's computation computes what the model does;
        with `--robotool` (§6.6) both are RoboTool's, T read as the reading's range of `core_int`,
        `core_nat`, `core_real`, or as the set written."""
        xs = [self.number(a, env) for a in args_t]
        if name == "Neg":
            exact = -xs[0]
        else:
            x, y = xs
            if name in ("Div", "Modulus") and y == 0:
                raise self.error(t, "division by zero")
            exact = _div(x, y) if name == "Div" else {"Plus": x + y, "Minus": x - y, "Mult": x * y,
                                                      "Modulus": _mod(x, y) if y else 0}[name]
        if not self.arithmetic:
            return exact
        kept = self._bounds(type_t, env)
        return exact if kept is None or kept(exact) else xs[0]

    def _bounds(self, type_t: Tree | Token, env: Env) -> Callable[[int], bool] | None:
        """Membership in the type argument of RoboTool's arithmetic helpers (None: unbounded)."""
        name = str(type_t.children[0]) if isinstance(type_t, Tree) and type_t.data == "name" else None
        if name is not None and name in self.arithmetic:
            low, high = self.arithmetic[name]
            return lambda v: low <= v <= high
        if name is not None and name in ("core_int", "core_nat", "core_real"):
            return None
        values = self.eval(type_t, env)
        if isinstance(values, frozenset):
            return lambda v: v in values
        raise self.error(type_t, "the type argument of RoboTool's arithmetic is not a set")

    def replicated(self, t: Tree, env: Env) -> Proc:
        op, var, over, body = t.children
        op_text = str(op.children[0])
        values = self.eval(over, env)
        if isinstance(values, EventSet):
            listed = _members(values)
            if listed is None:
                raise self.error(t, "replicated operators range over listed events, their unions, and differences "
                                    "that remove whole channels or listed events, only")
            members: list[object] = listed
        elif isinstance(values, frozenset):
            members = sorted(values, key=_member_order)
        else:
            raise self.error(over, "a replicated operator needs a set")
        if op_text == "|~|" and isinstance(values, EventSet):
            members = self._branches(members)
        procs: list[Proc] = [Thunk(body, Env({str(var): m}, {}, env.timed, env)) for m in members]
        return _fold({"|~|": "internal", "[]": "external", "|||": "parallel"}[op_text], procs, env.timed)

    def _branches(self, members: list[object]) -> list[object]:
        """The branches of an internal choice over events. A channel's closure is one member that
        offers every value of the channel, where CSP has a branch per event, each offering that
        event alone: the traces are the same, but such a branch refuses less. So each of the
        model's channels the closure covers is a branch of its own, and where the engines list
        the channel's values, at most `BRANCHES_LISTED` of them (the specification's states
        multiply with its branches), each listed event is one too (beside the channel's, which keeps the
        values the listing may miss, such as an output the model computes outside the ranges):
        each branch is one CSP has, or refuses no more than one it has, so a refinement shown
        holds for CSP's choice; a violation shown by a refusal is CSP's too, unless the model
        offers there only values of the channel the listing misses (docs/semantics.md §10)."""
        sem = self.semantics
        out: list[object] = []
        for m in members:
            if sem is None or not (isinstance(m, tuple) and m and m[-1] is ANY):
                out.append(m)
                continue
            prefix = m[:-1]
            channels = [(tuple(p), n) for p, n in sem.alphabet if _extends(tuple(p), prefix)]
            if not channels or any(_extends(prefix, p) and p != prefix for p, _ in channels):
                out.append(m)  # not (only) the model's channels, or a closure inside one: as it is
                continue
            for p, n in channels:
                if n == 0:
                    out.append(p)
                    continue
                listed = sem.values(p) if sem.values is not None else None
                if listed is not None and len(listed) <= BRANCHES_LISTED:
                    out += [(*p, *v) for v in listed]
                out.append((*p, ANY))
        return list(dict.fromkeys(out))

    # --- typed views

    def proc(self, t: Tree, env: Env) -> Proc:
        if _is_process(t):
            return Thunk(t, env)
        v = self.eval(t, env)
        if isinstance(v, ModelProcess):
            raise self.error(t, "a model process inside a specification or under this operator is not supported")
        if not isinstance(v, Proc):
            raise self.error(t, "expected a process")
        return v

    def events(self, t: Tree, env: Env) -> EventSet:
        v = self.eval(t, env)
        if isinstance(v, tuple):
            return EventSet("exact", (v,))
        if not isinstance(v, EventSet):
            raise self.error(t, "expected a set of events")
        return v

    def event(self, t: Tree, env: Env) -> Event:
        v = self.eval(t, env)
        if not isinstance(v, tuple):
            raise self.error(t, "expected an event or a channel")
        return v

    def number(self, t: Tree, env: Env) -> int:
        v = self.eval(t, env)
        if v is OTHER:
            raise self.error(t, "this value comes from an input the specification does not track")
        if not isinstance(v, (int, Fraction)) or isinstance(v, bool):
            raise self.error(t, "expected a number")
        return v  # type: ignore[return-value]

    def boolean(self, t: Tree, env: Env) -> bool:
        v = self.eval(t, env)
        if not isinstance(v, bool):
            raise self.error(t, "expected a boolean")
        return v

    def field(self, t: Tree, env: Env) -> object:
        v = self.eval(t, env)
        if v is OTHER:
            raise self.error(t, "this value comes from an input the specification does not track")
        return v

    def restricted_prefix(self, t: Tree, env: Env) -> Proc:
        """`c?x:S -> P`, CSP's `[] v:S @ c.v -> P[v/x]`: a prefix per value of each restricted input
        (their combinations), the other inputs as they are, offered as an external choice."""
        comm, then = t.children
        parts = comm.children
        base = self.eval(parts[0], env)
        if not isinstance(base, tuple):
            raise self.error(t, "expected an event")
        combos: list[tuple[tuple, dict[str, object]]] = [(base, {})]
        read = _names_in(then)
        for kind, arg in zip(parts[1::2], parts[2::2], strict=True):
            if str(kind) == "?" and isinstance(arg, Tree) and arg.data == "restricted":
                name, over = str(arg.children[0]), arg.children[1]
                grown = []
                for e, b in combos:  # the set may read an input before it: `c?x:S?y:{x}`
                    values = self.eval(over, Env(b, {}, env.timed, env))
                    if isinstance(values, EventSet) and values.kind == "exact" and not values.items:
                        values = frozenset()  # `{}`
                    if not isinstance(values, frozenset):
                        raise self.error(over, "the set an input is restricted to must be a set of values")
                    _no_other(self, over, *values)
                    grown += [((*e, v), {**b, name: v}) for v in sorted(values, key=_member_order)]
                combos = grown
            elif str(kind) == "?":
                combos = [((*e, Input(str(arg), str(arg) in read)), b) for e, b in combos]
            else:
                combos = [((*e, self.field(arg, Env(b, {}, env.timed, env))), b) for e, b in combos]
        return _fold("external", [Prefix(e, then, Env(b, {}, env.timed, env), env.timed) for e, b in combos], env.timed)

    def pattern(self, t: Tree, env: Env, read: frozenset[str] = frozenset()) -> tuple:
        """An event with its inputs (`?x`); `read` holds the names what follows the prefix reads."""
        c = t.children
        base = self.eval(c[0], env)
        if not isinstance(base, tuple):
            raise self.error(t, "expected an event")
        out = list(base)
        i = 1
        while i < len(c):
            kind, arg = str(c[i]), c[i + 1]
            if isinstance(arg, Tree) and arg.data == "restricted":
                raise self.error(arg, "an input restricted to a set, '?x:S', is understood in a prefix 'c?x:S -> P' only")
            out.append(Input(str(arg), str(arg) in read) if kind == "?" else self.field(arg, env))
            i += 2
        return tuple(out)


def _fold(kind: str, procs: list[Proc], timed: bool) -> Proc:
    """`procs` under a replicated operator (internal or external choice, interleaving); none is STOP."""
    if not procs:
        return Stop(timed)
    out = procs[0]
    for p in procs[1:]:
        out = Binary(kind, out, p, EventSet("exact") if kind == "parallel" else None, timed)
    return out


def _div(a: int, b: int) -> int:
    q = abs(a) // abs(b)  # CSPM's `/` truncates towards zero
    return q if (a >= 0) == (b >= 0) else -q


def _mod(a: int, b: int) -> int:
    """CSPM's `%`: the remainder of `_div`, of `a`'s sign (a == b * (a / b) + a % b)."""
    return a - b * _div(a, b)


# RoboTool's channels for a variable's reads and writes (`M::set_reqx`): tockbmc has the visible writes (`set_`) only.
_MEMORY_CHANNEL = re.compile(r"(set|get|setL|setR)_(\w+)")
# RoboTool's bounded arithmetic helpers, by the number of operands before the type argument.
_BOUNDED_ARITHMETIC = {"Plus": 2, "Minus": 2, "Mult": 2, "Div": 2, "Modulus": 2, "Neg": 1}
_NAMES_READ: dict[int, tuple[Tree | Token, frozenset[str]]] = {}


def _names_in(t: Tree | Token) -> frozenset[str]:
    """The names a process expression mentions (a prefix's inputs it may read), cached per tree."""
    hit = _NAMES_READ.get(id(t))
    if hit is not None and hit[0] is t:
        return hit[1]
    names = frozenset(str(n.children[0]) for n in t.find_data("name")) if isinstance(t, Tree) else frozenset()
    _NAMES_READ[id(t)] = (t, names)
    return names


def _no_other(ev: Evaluator, t: Tree, *values: object) -> None:
    if any(v is OTHER for v in values):
        raise ev.error(t, "this value comes from an input the specification does not track")


_PROCESS_NODES = {"prefix", "guard", "external", "internal", "seq", "interrupt", "timeout", "parallel",
                  "exception", "interleave", "hide", "project", "replicated"}


def _is_process(t: Tree | Token) -> bool:
    """Whether an expression is a process by its shape (so it can stay unevaluated)."""
    return isinstance(t, Tree) and t.data in _PROCESS_NODES


def _chaos(timed: bool, a: EventSet) -> Proc:
    return Run(a, timed)


def _tocks(name: str, d: object) -> int:
    """A number of tocks a timed operator counts: a value the environment chose from a range the
    specification does not list (`time.in?t -> WAIT(t)` on an unbounded channel) is not followed."""
    if d is OTHER:
        raise Unsupported(None, f"{name} over a value the specification received from an unbounded channel "
                                "(every value of it would be a different process): give the channel a range "
                                "(--range), so that its values are listed")
    assert isinstance(d, int)
    return d


def _wait(timed: bool, n: int) -> Proc:
    return Wait(_tocks("WAIT", n))


def _edeadline(timed: bool, e: Event, d: int) -> Proc:
    return Deadline(EventSet("exact", (e,)) if isinstance(e, tuple) else e, _tocks("EDeadline", d), 0, True)


def _adeadline(timed: bool, a: EventSet, d: int) -> Proc:
    return Deadline(a, _tocks("ADeadline", d), 0, False)


def _endby(timed: bool, p: Proc, d: int) -> Proc:
    return EndBy(p, _tocks("EndBy", d), 0)


def _startby(timed: bool, p: Proc, d: int) -> Proc:
    """tick-tock-CSP's `StartBy(P, d) = P [] (WAIT(d) ; USTOP)` in a Timed section (UoY-RoboStar
    tick-tock-CSP, fdr/tick-tock.csp): P, with at most d tocks before its first event."""
    if not isinstance(p, Proc) or not (isinstance(d, int) or d is OTHER):
        raise TypeError("StartBy takes a process and a number")
    return Binary("external", p, Binary("seq", Wait(_tocks("StartBy", d)), Stop(False), None, True), None, True)


def _set_op(kind: str) -> Callable[..., EventSet | frozenset]:
    return lambda timed, a, b: EventSet(kind, (a, b)) if isinstance(a, EventSet) else _value_set_op(kind, a, b)


def _value_set_op(kind: str, a: object, b: object) -> frozenset:
    if not isinstance(a, frozenset) or not isinstance(b, frozenset):
        raise TypeError("not two sets")
    return a | b if kind == "union" else a - b if kind == "diff" else a & b


def _distributed(kind: str) -> Callable[..., object]:
    """`Union(S)` and `Inter(S)`: the union or intersection of a set of sets (of events or values)."""
    def fold(timed: bool, sets: object) -> object:
        if not isinstance(sets, frozenset) or not sets:
            raise TypeError("not a non-empty set of sets")
        items = sorted(sets, key=repr)
        out = items[0]
        for x in items[1:]:
            out = _set_op(kind)(timed, out, x)
        return out
    return fold


def _members(a: EventSet) -> list[object] | None:
    """The events of a set one by one, for a replicated operator: a channel's closure as one member
    (`(*channel, ANY)`, any value), listed events as they are; None where a difference removes part
    of a channel, or for intersections and `Events`."""
    if a.kind == "closure":
        return [(*p, ANY) for p in a.items]
    if a.kind == "exact":
        return list(a.items)
    if a.kind == "union":
        left, right = _members(a.items[0]), _members(a.items[1])
        if left is None or right is None:
            return None
        both = list(dict.fromkeys([*left, *right]))
        # members must not overlap (`|||` runs one process per member): one a channel's closure covers goes
        closures = [m for m in both if isinstance(m, tuple) and m and m[-1] is ANY]
        return [m for m in both if not (isinstance(m, tuple)
                                        and any(c != m and _extends(_open(m), c[:-1]) for c in closures))]
    if a.kind == "diff":
        kept = _members(a.items[0])
        if kept is None:
            return None
        out = []
        for m in kept:
            if not isinstance(m, tuple) or not m or m[-1] is not ANY:  # a listed event
                if not a.items[1].contains(m):
                    out.append(m)
                continue
            prefix = m[:-1]
            if a.items[1].contains((*prefix, ANY)):
                if _whole(prefix, a.items[1]):
                    continue
                return None  # removed in part, or by a set whose extent is not read off (`diff(Events, …)`)
            if any(_extends(e, prefix) or _extends(prefix, e) for e in a.items[1].mentions()) \
                    or a.items[1].kind == "all":
                return None  # part of the channel removed
            out.append(m)
        return out
    return None


def _open(m: tuple) -> tuple:
    """A member's fixed fields: a closure's without its `ANY`."""
    return m[:-1] if m and m[-1] is ANY else m


def _whole(prefix: tuple, b: EventSet) -> bool:
    """Whether b holds every event of the channel `prefix` (a closure of it or of a shorter prefix)."""
    if b.kind == "closure":
        return any(_extends(prefix, q) for q in b.items)
    if b.kind == "union":
        return _whole(prefix, b.items[0]) or _whole(prefix, b.items[1])
    return b.kind == "all"


def _member(timed: bool, x: object, s: object) -> bool:
    """CSPm's `member(x, S)`: an event of an event set, or a value of a set of values."""
    if isinstance(s, EventSet):
        if not isinstance(x, tuple):
            raise TypeError("member: an event set holds events")
        return s.contains(x)
    if not isinstance(s, frozenset):
        raise TypeError("member: the second argument is a set")
    return x in s


_BUILTINS: dict[str, Callable[..., object]] = {
    "CHAOS": _chaos, "RUN": _chaos, "WAIT": _wait, "EDeadline": _edeadline, "ADeadline": _adeadline,
    "EndBy": _endby, "Deadline": _endby, "StartBy": _startby, "wait": _wait, "timed_priority": lambda timed, p: p,
    "union": _set_op("union"), "diff": _set_op("diff"), "inter": _set_op("inter"),
    "Union": _distributed("union"), "Inter": _distributed("inter"), "member": _member,
}


# ---------------------------------------------------------------- operational semantics


@dataclass
class Semantics:
    """Steps of specification terms; `force` evaluates thunks (and bounds unguarded recursion)."""

    evaluator: Evaluator
    # The implementation's channels as (fixed fields, number of values), so that terms that accept
    # events they do not name (`RUN(Events)`, a hidden `Events`) can be probed.
    alphabet: list[tuple[Event, int]] = field(default_factory=list)
    _forced: dict[Proc, Proc] = field(default_factory=dict)
    timed: bool = True  # False in RoboTool's untimed semantics: no term ever does `tock`
    # Every value tuple of a channel of the implementation (by its fixed fields), where its types
    # and ranges make them few, else None: lets the specification's traces be listed where a term
    # accepts any value (`c?x`).  Set by the engines, which know the ranges.
    values: Callable[[Event], list[tuple] | None] | None = None

    def __post_init__(self) -> None:
        self.evaluator.semantics = self

    def force(self, p: Proc, depth: int = 0) -> Proc:
        if not isinstance(p, Thunk):
            return p
        if p in self._forced:
            return self._forced[p]
        if depth > 200:
            raise self.evaluator.error(p.tree, "unguarded recursion")
        v = self.evaluator.eval(p.tree, p.env)
        if isinstance(v, ModelProcess):
            raise self.evaluator.error(v.node, "a model process inside a specification or under this operator "
                                               "is not supported")
        if not isinstance(v, Proc):
            raise self.evaluator.error(p.tree, "expected a process")
        out = self.force(v, depth + 1)
        self._forced[p] = out
        return out

    def ticks(self, p: Proc) -> bool:
        p = self.force(p)
        if isinstance(p, Skip):
            return True
        if isinstance(p, Lts):
            return p.node in p.graph.ticks
        if isinstance(p, Wait):
            return p.n <= 0
        if isinstance(p, EndBy):
            return self.ticks(p.p)
        if isinstance(p, Binary):
            if p.op in ("external", "interrupt"):
                return self.ticks(p.left) or (p.right is not None and self.ticks(p.right))
            if p.op in ("exception", "timeout", "hide"):
                return self.ticks(p.left)
            if p.op == "parallel":
                return isinstance(self.force(p.left), Omega) and isinstance(self.force(p.right), Omega)  # type: ignore[arg-type]
        return False

    def taus(self, p: Proc) -> list[Proc]:  # noqa: C901 - one case per operator
        p = self.force(p)
        if isinstance(p, Lts):
            return [Lts(p.graph, n) for e, n in p.graph.moves[p.node] if e is None]
        if isinstance(p, Deadline) and p.event is False:
            return []
        if isinstance(p, EndBy):
            return [EndBy(q, p.d, p.n) for q in self.taus(p.p)]  # once p can terminate, so can EndBy (`ticks`)
        if not isinstance(p, Binary):
            return []
        left, right = p.left, p.right
        if p.op == "internal":
            return [left, right]  # type: ignore[list-item]
        out: list[Proc] = []
        if p.op == "seq":
            out += [Binary("seq", q, right, None, p.timed) for q in self.taus(left)]
            if self.ticks(left):
                out.append(right)  # type: ignore[arg-type]
            return out
        if p.op == "hide":
            assert p.events is not None
            out += [Binary("hide", q, None, p.events, p.timed) for q in self.taus(left)]
            for _e, q in self._visible_moves(left, p.events):
                out.append(Binary("hide", q, None, p.events, p.timed))
            return out
        if p.op in ("external", "interrupt", "exception"):
            out += [Binary(p.op, q, right, p.events, p.timed) for q in self.taus(left)]
            if p.op != "exception":
                out += [Binary(p.op, left, q, p.events, p.timed) for q in self.taus(right)]  # type: ignore[arg-type]
            return out
        if p.op == "timeout":
            out = [Binary("timeout", q, right, None, p.timed) for q in self.taus(left)]
            return [*out, right] if right is not None else out
        if p.op == "parallel":
            assert right is not None
            out += [Binary("parallel", q, right, p.events, p.timed) for q in self.taus(left)]
            out += [Binary("parallel", left, q, p.events, p.timed) for q in self.taus(right)]
            if self.ticks(left) and not isinstance(self.force(left), Omega):
                out.append(Binary("parallel", Omega(), right, p.events, p.timed))
            if self.ticks(right) and not isinstance(self.force(right), Omega):
                out.append(Binary("parallel", left, Omega(), p.events, p.timed))
            return out
        return out

    def _visible_moves(self, p: Proc, hidden: EventSet) -> list[tuple[Event, Proc]]:
        """Moves of p on the events of `hidden` (which become internal): the events p's terms and
        the hidden set name, and one event of every channel of the alphabet with unnamed values."""
        out = []
        for e in sorted(self.candidates(p, hidden.mentions()), key=repr):
            if hidden.contains(e):
                out += [(e, q) for q in self.after(p, e)]
        return out

    def field_values(self, prefix: Event, j: int) -> list[object] | None:
        """Every value of field j of the channel with these fixed fields, where the engine lists
        them (`values`), else None."""
        listed = self.values(prefix) if self.values is not None else None
        return None if listed is None else list(dict.fromkeys(v[j] for v in listed))

    def _listed_inputs(self, p: Prefix, e: Event) -> set[str]:
        """The inputs of p read later whose every value is listed, on an input from outside (`….in`),
        where the ranges bound what the model receives: for them `OTHER` stands for no value."""
        for prefix, arity in self.alphabet:
            if prefix[-1:] == ("in",) and len(e) == len(prefix) + arity and tuple(e[: len(prefix)]) == tuple(prefix):
                return {x.name for j, x in enumerate(p.pattern[len(prefix):])
                        if isinstance(x, Input) and x.used and self.field_values(prefix, j) is not None}
        return set()

    def _complete(self, pattern: tuple, e: Event) -> None:
        """Raise `Unsupported` where a prefix names a channel of the model with fewer fields than it
        has (`M::a -> P` for `event a`, whose events are `M::a.in` and `M::a.out`): FDR rejects it as
        a type error, and here it would match no event of the model and be a silent STOP."""
        if not pattern or pattern[-1] is ANY or len(pattern) >= len(e) or _match(pattern, e[: len(pattern)]) is None:
            return
        for prefix, arity in self.alphabet:
            if len(e) == len(prefix) + arity and _extends(e, prefix):
                shown = ".".join(f"?{x.name}" if isinstance(x, Input) else "…" if x is OTHER else str(x)
                                 for x in pattern)
                channel = ".".join(str(x) for x in prefix)
                if isinstance(pattern[-1], Input):  # read later: bound to several fields at once
                    raise Unsupported(None, f"the input {shown} binds {pattern[-1].name} to the rest of channel "
                                            f"{channel}'s fields at once, and what follows reads it: not supported")
                raise Unsupported(None, f"the prefix {shown} names the model's channel {channel} without "
                                        f"{len(e) - len(pattern)} of its fields; FDR rejects it as a type error")

    def candidates(self, p: Proc, extra: Iterable[Event] = ()) -> set[Event]:
        """Concrete events that stand for all of p's possible moves: per alphabet channel, the
        values p's terms (and `extra`) name in each field, every value of a field an input that is
        read later receives (where they are listed), `OTHER` elsewhere; events on channels outside
        the alphabet as named; and `tock`."""
        out: set[Event] = {TOCK}
        for e in set(self.mentions(p)) | set(extra):
            matched = False
            for prefix, arity in self.alphabet:
                if _extends(e, prefix):
                    combos: list[tuple] = [()]
                    for j, x in enumerate(e[len(prefix): len(prefix) + arity]):
                        listed = self.field_values(prefix, j) if isinstance(x, Input) and x.used else None
                        options = listed if listed is not None else [
                            OTHER if x is ANY or isinstance(x, Input) else x]
                        combos = [(*c, v) for c in combos for v in options]
                    out.update((*prefix, *c, *(OTHER,) * (arity - len(c))) for c in combos)
                    matched = True
                elif _extends(prefix, e):
                    matched = True  # `{| c |}` of a channel: the probe below stands for it
            if not matched and not any(x is ANY or isinstance(x, Input) for x in e):
                out.add(e)
        for prefix, arity in self.alphabet:
            out.add((*prefix, *(OTHER,) * arity))
        return out

    def stable(self, p: Proc) -> bool:
        return not self.taus(p) and not self.ticks(p)

    def after(self, p: Proc, e: Event) -> list[Proc]:  # noqa: C901 - one case per operator
        """Successors of p on visible event e (tock included); maximal progress is the caller's."""
        p = self.force(p)
        tock = e == TOCK
        if tock and not self.timed:
            return []
        if isinstance(p, Stop):
            return [p] if tock and p.timed else []
        if isinstance(p, (Skip, Omega)):
            return []
        if isinstance(p, Lts):  # its events name every value, so a class of unnamed values (OTHER) matches none
            return [Lts(p.graph, n) for x, n in p.graph.moves[p.node] if x is not None and x == e]
        if isinstance(p, Run):
            return [p] if p.events.contains(e) or (tock and p.timed) else []
        if isinstance(p, Wait):
            return [Wait(p.n - 1)] if tock and p.n > 0 else []
        if isinstance(p, Deadline):
            if tock:
                return [Deadline(p.events, p.d, p.n + 1, p.event)] if p.n < p.d else []
            if p.events.contains(e):
                return [Skip()]
            return [] if p.event else [p]
        if isinstance(p, EndBy):
            if tock and p.n >= p.d:
                return []
            return [EndBy(q, p.d, p.n + (1 if tock else 0)) for q in self.after(p.p, e)]
        if isinstance(p, Prefix):
            if tock and p.timed:
                return [p]
            bound = _match(p.pattern, e)
            if bound is None:
                self._complete(p.pattern, e)
                return []
            if any(v is OTHER and k in self._listed_inputs(p, e) for k, v in bound.items()):
                return []
            env = Env(bound, {}, p.env.timed, p.env) if bound else p.env
            return [self.evaluator.proc(p.then, env)]
        assert isinstance(p, Binary)
        left, right, op = p.left, p.right, p.op
        if op == "internal":
            return []
        if op == "seq":
            return list[Proc]([Binary("seq", q, right, None, p.timed) for q in self.after(left, e)])
        if op == "hide":
            assert p.events is not None
            if p.events.contains(e):
                return []
            return [Binary("hide", q, None, p.events, p.timed) for q in self.after(left, e)]
        assert right is not None
        if op == "external" or op == "interrupt":
            if tock and p.timed:
                return [Binary(op, a, b, None, p.timed) for a in self.after(left, e) for b in self.after(right, e)]
            out = [Binary(op, q, right, None, p.timed) if op == "interrupt" else q for q in self.after(left, e)]
            return out + self.after(right, e)
        if op == "timeout":
            return self.after(left, e)
        if op == "exception":
            assert p.events is not None
            if p.events.contains(e) and not tock:
                return [right for _ in self.after(left, e)][:1]
            return [Binary(op, q, right, p.events, p.timed) for q in self.after(left, e)]
        # parallel
        assert p.events is not None
        if tock and p.timed:  # a side that has terminated does not stop time
            lefts = [left] if isinstance(self.force(left), Omega) else self.after(left, e)
            rights = [right] if isinstance(self.force(right), Omega) else self.after(right, e)
            return [Binary(op, a, b, p.events, p.timed) for a in lefts for b in rights]
        if p.events.contains(e):
            return [Binary(op, a, b, p.events, p.timed) for a in self.after(left, e) for b in self.after(right, e)]
        moves: list[Proc] = [Binary(op, q, right, p.events, p.timed) for q in self.after(left, e)]
        return moves + [Binary(op, left, q, p.events, p.timed) for q in self.after(right, e)]

    def mentions(self, p: Proc) -> set[Event]:
        """Events (with values) that p's current terms name, so the monitor can tell them apart."""
        p = self.force(p)
        if isinstance(p, Prefix):  # an input read later stays, so its values can be told apart
            return {tuple(ANY if isinstance(x, Input) and not x.used else x for x in p.pattern)}
        if isinstance(p, Lts):
            return {e for e, _n in p.graph.moves[p.node] if e is not None and e != TOCK}
        if isinstance(p, Run):
            return p.events.mentions()
        if isinstance(p, Deadline):
            return p.events.mentions()
        if isinstance(p, EndBy):
            return self.mentions(p.p)
        if isinstance(p, Binary):
            out = self.mentions(p.left)
            if p.right is not None and p.op not in ("seq",):
                out |= self.mentions(p.right)
            if p.events is not None:
                out |= p.events.mentions()
            return out
        return set()


def _match(pattern: tuple, e: Event) -> dict[str, object] | None:
    if pattern and pattern[-1] is ANY:  # from enumerating `{| c |}`: any fields after the channel's
        pattern = pattern[:-1]
        e = e[: len(pattern)]
    if pattern and isinstance(pattern[-1], Input) and not pattern[-1].used and len(pattern) < len(e):
        # `c?x` on a channel of several fields binds x to all of the rest (CSPM's dotted value);
        # read nowhere, it is only matched
        e = (*e[: len(pattern) - 1], tuple(e[len(pattern) - 1:]))
    if len(pattern) != len(e):
        return None
    bound: dict[str, object] = {}
    for p, x in zip(pattern, e, strict=True):
        if isinstance(p, Input):
            bound[p.name] = x
        elif p is ANY:
            continue
        elif not _same(x, p):
            return None
    return bound


# ---------------------------------------------------------------- the monitor


@dataclass(frozen=True)
class Channel:
    """An implementation event class: its fixed fields, and how many value fields follow."""

    prefix: Event
    arity: int


class TooLarge(Exception):
    pass


class Monitor:
    """The determinised specification: states are τ-closed sets of terms, numbered from 0.

    `DEAD` is the state after a trace the specification cannot do.
    """

    DEAD = -1

    def __init__(self, sem: Semantics, root: Proc, channels: Iterable[Channel], limit: int = 5000):
        self.sem = sem
        self.channels = list(channels)
        if self.channels and not sem.alphabet:
            sem.alphabet = [(ch.prefix, ch.arity) for ch in self.channels if ch.prefix != TOCK]
        self.limit = limit
        self.states: list[frozenset[Proc]] = []
        self.index: dict[frozenset[Proc], int] = {}
        self.named: dict[tuple[int, int], list[list[object]]] = {}  # (state, channel) -> values named per field
        self.initial = self._state(self._closure([root]))

    def _closure(self, procs: Iterable[Proc]) -> frozenset[Proc]:
        seen: set[Proc] = set()
        todo = [self.sem.force(p) for p in procs]
        while todo:
            p = todo.pop()
            if p in seen:
                continue
            seen.add(p)
            if len(seen) > self.limit:
                raise TooLarge
            todo += [self.sem.force(q) for q in self.sem.taus(p)]
        return frozenset(seen)

    def _state(self, s: frozenset[Proc]) -> int:
        if not s:
            return self.DEAD
        if s not in self.index:
            if len(self.states) >= self.limit:
                raise TooLarge
            self.index[s] = len(self.states)
            self.states.append(s)
        return self.index[s]

    def can_tick(self, state: int) -> bool:
        return state != self.DEAD and any(self.sem.ticks(p) for p in self.states[state])

    def fields(self, state: int, ch: Channel) -> list[list[object]]:
        """Per value field of `ch`, the values the terms of `state` name there, and every value of
        a field whose input is read later, where the engine lists them (`Semantics.field_values`)."""
        out: list[set[object]] = [set() for _ in range(ch.arity)]
        if state != self.DEAD:
            n = len(ch.prefix)
            for e in set().union(*(self.sem.mentions(p) for p in self.states[state])):
                if len(e) > n and _extends(ch.prefix, e[:n]):
                    for j, x in enumerate(e[n: n + ch.arity]):
                        if isinstance(x, Input):
                            out[j].update((self.sem.field_values(ch.prefix, j) or []) if x.used else [])
                        elif x is not ANY:
                            out[j].add(x)
        return [sorted(f, key=repr) for f in out]

    def values(self, state: int, ch: Channel) -> list[tuple]:
        """The value tuples of `ch` that the terms of `state` tell apart: per field a named value
        or `OTHER` (every value not named there).  No `OTHER` in a field of an input from outside
        (`….in`) that names every listed value: the ranges bound what the model receives (§6.2)."""
        combos: list[tuple] = [()]
        for j, named in enumerate(self.fields(state, ch)):
            listed = self.sem.field_values(ch.prefix, j) if ch.prefix[-1:] == ("in",) and named else None
            every = listed is not None and all(any(_same(v, x) for x in named) for v in listed)
            combos = [(*c, v) for c in combos for v in (named if every else (*named, OTHER))]
            if len(combos) > 256:
                raise TooLarge
        return combos

    def after(self, state: int, e: Event) -> int:
        if state == self.DEAD:
            return self.DEAD
        procs = self.states[state]
        if e == TOCK:  # maximal progress: only stable terms let time pass
            procs = frozenset(p for p in procs if self.sem.stable(p))
        return self._state(self._closure(q for p in procs for q in self.sem.after(p, e)))

    def after_tock(self, state: int, terms: Iterable[Proc]) -> int:
        """The state after `tock` taken by `terms` only (stable terms of `state`): in the tick-tock
        model, those whose refusal matched the one observed before the tock."""
        if state == self.DEAD:
            return self.DEAD
        return self._state(self._closure(q for p in terms for q in self.sem.after(p, TOCK)))

    def table(self, more: Callable[[int], None] | None = None) -> dict[tuple[int, int], list[tuple[tuple, int]]]:
        """δ for every reachable state and channel: [(values, next state)], explored to a fixpoint;
        `more(i)` is called for each state, so that a caller can add the states its own moves reach
        (the tick-tock model's filtered tocks)."""
        out: dict[tuple[int, int], list[tuple[tuple, int]]] = {}
        i = 0
        while i < len(self.states):
            if more is not None:
                more(i)
            for c, ch in enumerate(self.channels):
                self.named[(i, c)] = self.fields(i, ch)
                out[(i, c)] = [(vs, self.after(i, (*ch.prefix, *vs))) for vs in self.values(i, ch)]
            i += 1
        return out
