"""An explicit-state interpreter of RoboChart machines, controllers and modules.

This is an independent implementation of `docs/semantics.md` §2–§6 (the event names and
the step rules), written from that text and from the user-visible choices recorded in DESIGN.md
("Resolution choices", "Checking: encoding choices"). It imports nothing from `tockbmc.encodings`,
`tockbmc.properties` or `tockbmc.bmc`, so that it can cross-check them.

A `Config` is one configuration: per machine a stack of frames (the machine itself, then the
defined operations it is running), one value per slot (variables, constants, clocks,
`sinceEntry` counters, trigger-deadline counters, asynchronous buffers), and whether the element
has terminated. `Interpreter.steps` lists every step from a configuration: internal steps, visible
events (named exactly as tockbmc prints them) and `tock`.

Choices made where docs/semantics.md is silent (and DESIGN.md too, or where it is only implied):

* **Granularity of internal steps.** Each of these is one internal step: taking a transition
  (trigger, condition, clock resets, and the binding of `e?x` together), an assignment, an `if`
  (the condition is read atomically), the choice of `n` for `wait`, `#C`, the call of a defined
  operation (arguments bound to parameters), a synchronous machine-to-machine communication, a
  write into or a read from an asynchronous buffer. Pure bookkeeping is not a step: flattening
  sequences, `skip`, entering/leaving a state without entry/exit action, arriving at a node,
  starting/ending a statement deadline, the end of a `wait`, returning from an operation.
  Visible traces do not depend on this; internal-step counts do.
* **Entry into states.** An entry action runs before the state is stable; the transitions of a
  state are candidates only once it is stable (or while its `during` runs). A transition from an
  ancestor exits the innermost active state first. The exited states are the active states up to
  (excluding) the deepest common proper ancestor of source and target, so a self-transition exits
  and re-enters its state, and a transition into a nested state enters every state on the way
  (their entry actions outside-in, without their initial transitions).
* **`during` actions.** On becoming stable in a leaf state (or an inner final state), the machine
  runs, in sequence, the `during` actions of the states entered by the run of transitions that
  led there (outermost first), restricted to states still active; any transition of an active
  state abandons them. So the during of a composite is not restarted by a transition between its
  children (DESIGN.md encodes only the case where this does not matter).
* **`else`.** `condition else` holds when no other transition from the same node that has no
  input trigger (`e?x`) has a true condition (an absent condition is true).
* **Triggers.** `e?x` is an input binding `x`; `e.v` an input of exactly `v`; `e!v` an output of
  `v` (as tockbmc does); a plain `e` on a typed event accepts any value of its range and binds
  nothing.
* **`nat`.** A step that would store a negative value in a `nat` place (a variable or one of its
  record fields) is not possible: `nat` values are never negative. A machine whose next
  statement is such an assignment is stuck there (it lets time pass, like a junction with no
  true condition).
* **Display.** `states` gives the innermost active node's path, `taking t` while a transition's
  exit actions and action run, `terminated` after `terminate`, and `M / op(): node` inside a
  defined operation. `Unbounded.name` is the type's range name (`core_int`); `.path` the path.
* **Ranges.** A path range (`EXAX::move.time`, `Ctrl::e`, `M::x`) wins over the type's range.
  `nat` uses `core_nat`, else `core_int` cut at 0. `real` uses `core_real`, and a bounded real
  range offers only its integer values (FDR's reals are integers); pass exact values through
  `inputs`/`choices` to try others. A given type `T` (values opaque) uses a range named `T`, its
  values being integers.
* **Sampling.** With a `Sampler` (`tockbmc simulate`), a choice among more values than the
  sampler's size is made among that many drawn at random, initial configurations are drawn rather
  than listed, and types with no range take the sampler's windows. Whether an input trigger with a
  deadline is armed is then decided on at most 4096 of its values. Without one, every value is
  taken, as the explicit engine and replay need.
* **Lazy mode** (`lazy=True`, the explicit engine's search): an input's value, field by field,
  and at the start a variable's without an initial value or a constant's without a value, is an
  `Unknown` until a step depends on it. An expression reading Unknowns is tried with each of their
  values; if its value differs, or a value is copied, `NeedValue` says which Unknown, and
  `expand` splits the configuration (or `steps` the input) holding it into one per value. Visible
  events carry Unknowns as they are, except on the channels in `strict`. `concretize` turns a run
  found this way into one of concrete configurations. Without it (replay, `simulate`, the
  deadlock search), every value is taken.
* **Integer division** is Euclidean (`div`/`mod` of SMT-LIB: the remainder is never negative);
  division by zero is `NotInterpretable`. `/` on reals is exact.
* **Functions.** `postcondition result == e` defines `f` inside its preconditions. Outside them,
  and for a function with no such postcondition, any value its contract allows is possible: each
  such function has a table slot (not with a `Sampler`), a call at a point not in it raises
  `NeedPoint`, and `expand` splits the configuration into one per allowed value (the
  postconditions hold of it inside the preconditions; any value of the result's type outside);
  where no `expand` splits (replay, `simulate`), such a call is `NotInterpretable`.
* **Operation-local variables** without an initial value take every value of their range at each
  call (one internal step per value).
* **Trigger deadlines** `<{d}`: a transition with a deadline is armed when its frame is stable (or
  running a during), its source is active, and its condition holds (for `e?x`, for some value of
  the range). At a `tock`, an armed transition whose counter has reached `d` refuses it, otherwise
  its counter grows by one; a transition leaving its source (a self-transition too) restarts it;
  after every step, the counter of a transition that is not armed is
  0 again.
* **Statement deadlines** `S <{d}`: a counter per deadline, decremented by every `tock`; a counter
  at 0 refuses `tock`. Abandoning a `during` drops its deadlines.
* **Names.** A machine is displayed (in `states`/`variables` and for its unconnected events,
  `M::e`) under its machine name, or under its instance name when two instances share a machine.
  A controller's event left unconnected by the module stays visible under the controller's name.
  Values print as tockbmc prints them: records `(f=v, g=w)`, enumeration literals `Type::LIT`,
  booleans `true`/`false`, reals as integers when whole, else as a decimal when exact, else `p/q`.
* **Networks.** The element terminates when every machine is at a final state, all at once. A machine connected
  to itself synchronously, one-to-many connections, bidirectional connections and two buffers in
  series are `NotInterpretable`.
* **Clocks** saturate when that is unobservable: if every read of a clock (or `sinceEntry`) is a
  comparison with a literal, it stops growing one above the largest literal (a clock never read
  stays 0). Otherwise it grows without bound, and a model has infinitely many configurations; a
  search over them must bound its depth.

`NotInterpretable`: strings, sets and sequences (anything the resolver keeps but this interpreter
does not evaluate), uninterpreted functions, record literals omitting fields (but as a variable's or constant's
initial value, where the omitted fields are open as a variable without one is), probabilistic
junctions, recursive operations, an output without a value on a typed event, division by zero,
reading a variable that has no value, and the network shapes above.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import operator
import random
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import partial
from typing import Any, NamedTuple, cast

from tockbmc.explicit import liveness
from tockbmc.model import ast
from tockbmc.model.config import instance_key
from tockbmc.model.data import Product, Variant, text_of
from tockbmc.model.during import composite_during_problem
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.readings import default_value, given_initial
from tockbmc.model.untimed import untimed

# ----------------------------------------------------------------------------- public values


MAX_COLLECTIONS = 4096  # the most sequences one choice of the explicit engine lists


class Unbounded(Exception):
    """A value must be chosen from a type or path with no finite range.

    `name` is the range to give (`core_int`, `core_nat`, `core_real` or a model type's name);
    `path` is the path that needed it (`EXAX::move.time`, `EXAX.n_waypoints`), which may be
    given as a range too.
    """

    def __init__(self, name: str, path: str | None = None, paths: tuple[str, ...] = ()) -> None:
        where = f" (for {path})" if path else ""
        super().__init__(f"no finite range for {name}{where}: give a range for {name!r}")
        self.name = name
        self.path = path
        self.paths = paths or ((path,) if path else ())  # every spelling of the path, for a hint `--range` takes

    def __reduce__(self) -> tuple[type[Unbounded], tuple[str, str | None, tuple[str, ...]]]:
        """Rebuilt from its name and paths (a worker process of `check -j` raises it in the parent)."""
        return Unbounded, (self.name, self.path, self.paths)


class NotInterpretable(Exception):
    """A construct the interpreter does not handle, at `pos`."""

    def __init__(self, pos: ast.Pos | None, what: str) -> None:
        super().__init__(f"{pos}: not interpretable: {what}" if pos else f"not interpretable: {what}")
        self.pos = pos
        self.what = what

    def __reduce__(self) -> tuple[type[NotInterpretable], tuple[ast.Pos | None, str]]:
        return NotInterpretable, (self.pos, self.what)


class NeedPoint(NotInterpretable):
    """Lazy mode: a function the model leaves open (`--open`: no body, or called outside its
    preconditions) is called at a point whose value no step has chosen yet; `expand` splits the
    configuration into one per value the function's contract allows there (`values`), each with the
    point in the function's table (`slot`). Anywhere else it is not interpretable."""

    def __init__(self, pos: ast.Pos | None, name: str, slot: int, point: tuple,
                 values: Callable[[], tuple]) -> None:
        super().__init__(pos, f"the function {name}, which the model leaves open")
        self.slot, self.point, self.values = slot, point, values  # `values()`: listed only by `expand`

    def __reduce__(self) -> tuple[type[NotInterpretable], tuple[ast.Pos | None, str]]:  # type: ignore[override]
        return NotInterpretable, (self.pos, self.what)


RESULT = ("#result",)  # the key of `result` among a postcondition's bound names


class Record(dict):
    """A record value: a read-only, hashable dict from field names to values."""

    __slots__ = ("_hash",)
    _hash: int

    def __hash__(self) -> int:  # type: ignore[override]
        try:
            return self._hash
        except AttributeError:  # computed once: a configuration hashes its records whenever it is made
            self._hash = hash(tuple(sorted(self.items())))
            return self._hash

    def _readonly(self, *args: Any, **kwargs: Any) -> Any:
        raise TypeError("a record value is immutable")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = _readonly  # type: ignore[assignment]

    def __repr__(self) -> str:
        return "Record(" + dict.__repr__(self) + ")"

    def __reduce__(self) -> tuple[type[Record], tuple[dict]]:
        """Rebuilt from a plain dict (pickle's own way fills the dict in place, which a record refuses)."""
        return Record, (dict(self),)

    def with_field(self, name: str, value: object) -> Record:
        d = dict(self)
        d[name] = value
        return Record(d)


class Unknown:
    """A value not chosen yet (lazy mode): stands for each of `values`, all of type `type`.

    Configurations compare Unknowns by their values; the interpreter tells two of them apart by
    identity (`is`), since each is made for one place, an input or an open initial value, and
    never copied to another (a read that copies or inspects it raises `NeedValue` instead). Any
    arithmetic, ordering or truth test on one raises `NeedValue` too, as a safety net.
    """

    __slots__ = ("values", "type", "_hash")
    values: tuple
    type: ast.Type
    _hash: int

    def __init__(self, values: tuple, type_: ast.Type) -> None:
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "type", type_)
        object.__setattr__(self, "_hash", hash(("unknown", values)))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Unknown is immutable")

    def __eq__(self, other: object) -> bool:
        return self is other or (type(other) is Unknown and self._hash == other._hash
                                 and self.values == other.values and self.type == other.type)

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    def __hash__(self) -> int:
        return self._hash

    def __repr__(self) -> str:
        return f"Unknown({self.values!r})"

    def __str__(self) -> str:
        return "?"

    def _need(self, *args: object) -> Any:
        raise NeedValue(self)

    __bool__ = __lt__ = __le__ = __gt__ = __ge__ = __neg__ = _need  # type: ignore[assignment]
    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = __truediv__ = __rtruediv__ = _need
    __floordiv__ = __rfloordiv__ = __mod__ = __rmod__ = _need


class Closure:
    """A function value: a `lambda` (or a declared function named as a value), the values its
    free names had when it was made (a function's value does not change when the variables it
    read do), and the points an `override` gave other results (the last one for a point wins).
    Two closures are equal when they are the same lambda over the same values: configurations
    compare so; a model's `f == g` compares functions everywhere, which is not interpreted."""

    __slots__ = ("fn", "bind", "overrides", "_key")

    def __init__(self, fn: ast.Lambda, bind: tuple, overrides: tuple = ()) -> None:
        self.fn, self.bind, self.overrides = fn, bind, overrides
        self._key = (fn.pos, bind, overrides)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Closure) and self._key == other._key

    def __hash__(self) -> int:
        return hash(self._key)

    def __str__(self) -> str:
        return f"lambda@{self.fn.pos.line}:{self.fn.pos.column}"

    __repr__ = __str__


@dataclass(frozen=True)
class AnyFunction:
    """The value of a function-typed place nobody has set (an input, a variable without an initial
    value): any function of `type`. Applying it is not interpreted (its results cannot be listed)."""

    type: ast.FunctionType

    def __str__(self) -> str:
        return f"any {self.type}"


class NeedValue(Exception):
    """A step reads `unknown` (lazy mode): the configuration or input holding it must be split."""

    def __init__(self, unknown: Unknown) -> None:
        super().__init__("a value not chosen yet is read")
        self.unknown = unknown


def _unknown_in(v: object) -> Unknown | None:
    """The first Unknown in a value (records and buffers looked into), or None."""
    if isinstance(v, Unknown):
        return v
    if isinstance(v, (Record, tuple)):
        for x in v.values() if isinstance(v, Record) else v:
            u = _unknown_in(x)
            if u is not None:
                return u
    return None


def has_unknowns(config: Config) -> bool:
    """Whether a configuration holds a value not chosen yet (lazy mode), anywhere in it."""
    return _unknown_in(config.store) is not None or _unknown_in(config.machines) is not None


def _holds(v: object, u: Unknown) -> bool:
    """Whether `u` itself (not an equal Unknown) is in the value `v`."""
    if v is u:
        return True
    if isinstance(v, Record):
        return any(_holds(x, u) for x in v.values())
    if isinstance(v, tuple):
        return any(_holds(x, u) for x in v)
    return False


def _replace(v: object, u: Unknown, x: object) -> object:
    """`v` with `u` itself replaced by `x`."""
    if v is u:
        return x
    if isinstance(v, Record):
        return Record({k: _replace(y, u, x) for k, y in v.items()})
    if isinstance(v, tuple):
        return _same_kind(v, (_replace(y, u, x) for y in v))
    return v


def _unknowns(v: object, at: tuple, out: list[tuple[tuple, Unknown]]) -> None:
    """Append (position, Unknown) for each Unknown in `v`, whose position is `at`."""
    if isinstance(v, Unknown):
        out.append((at, v))
    elif isinstance(v, Record):
        for k, y in v.items():
            _unknowns(y, (*at, k), out)
    elif isinstance(v, tuple):
        for n, y in enumerate(v):
            _unknowns(y, (*at, n), out)


def fill(v: object, chosen: dict[int, object]) -> object:
    """`v` with each Unknown `u` replaced by `chosen[id(u)]`, else by its first value."""
    if isinstance(v, Unknown):
        return chosen.get(id(v), v.values[0])
    if isinstance(v, Record):
        return Record({k: fill(y, chosen) for k, y in v.items()})
    if isinstance(v, tuple):
        return _same_kind(v, (fill(y, chosen) for y in v))
    return v


def _same_kind(v: tuple, items: Iterable[object]) -> tuple:
    """`items` as a tuple of the kind of `v` (a `Product` or a `Variant` stays one)."""
    if isinstance(v, Variant):
        return Variant(items)
    return Product(items) if isinstance(v, Product) else tuple(items)


def unknowns(v: object) -> tuple[list[Unknown], tuple[int, ...]]:
    """The Unknowns in a value (records and tuples looked into), each once, in order; and for each
    place holding one, which of them it is (`(u, u)` is not `(u, w)`, though they compare equal)."""
    found: list[tuple[tuple, Unknown]] = []
    _unknowns(v, (), found)
    index: dict[int, int] = {}
    for _, u in found:
        index.setdefault(id(u), len(index))
    distinct = list({id(u): u for _, u in found}.values())
    return distinct, tuple(index[id(u)] for _, u in found)


def _assumed(v: object, assume: dict[int, object]) -> object:
    """`v` with the Unknowns that `assume` gives a value (by identity) replaced by it."""
    if isinstance(v, Unknown):
        return assume.get(id(v), v)
    if isinstance(v, Record):
        return Record({k: _assumed(y, assume) for k, y in v.items()})
    return v


def _at(v: object, path: tuple) -> object:
    for k in path:
        v = v[k]  # type: ignore[index]
    return v


class Event:
    """A visible event: its channel as CSP names it, the values it carries, and FDR's name for it,
    made from those when it is first read (most events a search makes are never printed)."""

    __slots__ = ("channel", "values", "_name")
    channel: tuple
    values: tuple
    _name: str | None

    def __init__(self, name: str | None, channel: tuple, values: tuple) -> None:
        object.__setattr__(self, "channel", channel)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "_name", name)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Event is immutable")

    @property
    def name(self) -> str:
        if self._name is None:  # records list their fields in their type's order (`_coerce`, `domain`)
            object.__setattr__(self, "_name", ".".join((*self.channel, *(value_text(None, v) for v in self.values))))
        return self._name  # type: ignore[return-value]

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Event) and self.channel == other.channel and self.values == other.values

    def __hash__(self) -> int:
        return hash((self.channel, self.values))

    def __repr__(self) -> str:
        return f"Event({self.name!r})"


@dataclass(frozen=True)
class Step:
    kind: str  # "internal" | "event" | "tock"
    event: Event | None
    target: Config
    note: str = ""


TOCK = Event("tock", ("tock",), ())


class Split(NamedTuple):
    """A configuration whose steps read a value not chosen yet, as the configurations of each
    value: an open function's at a point (`point`: every one must be allowed for), or an input's."""

    point: bool
    parts: list[Config]


class Frame(NamedTuple):
    """One activation: the machine, or a defined operation it runs.

    `node` is the innermost active node (None between leaving and entering at top level);
    `cont` the instructions still to run; `intr` whether `cont` is a `during` (transitions may
    abandon it); `dls` the statement-deadline counters; `pend` the states whose `during` starts
    once a leaf is stable; `via` the transition being taken; `entering` the composite states being
    entered, whose `sinceEntry` starts once the states their initial transitions lead to are entered.
    `bg` is the second thread of control: the activations running composite state `bg_of`'s during
    action beside its children (docs/semantics.md §4.1), whose base frame has no node (empty
    when no such action runs).
    """

    beh: int
    node: str | None
    cont: tuple
    intr: bool
    dls: tuple
    pend: tuple
    via: str | None
    entering: tuple = ()
    bg: tuple = ()
    bg_of: str | None = None


class Config:
    """A configuration: hashable and immutable; equal configurations compare equal."""

    __slots__ = ("machines", "store", "done", "_hash")
    machines: tuple
    store: tuple
    done: bool
    _hash: int

    def __init__(self, machines: tuple, store: tuple, done: bool) -> None:
        object.__setattr__(self, "machines", machines)
        object.__setattr__(self, "store", store)
        object.__setattr__(self, "done", done)
        object.__setattr__(self, "_hash", hash((machines, store, done)))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Config is immutable")

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Config) and self._hash == other._hash and self.done == other.done
                and self.store == other.store and self.machines == other.machines)

    def __repr__(self) -> str:
        return f"Config(machines={self.machines!r}, store={self.store!r}, done={self.done!r})"


def _with_slot(config: Config, slot: int, value: object) -> Config:
    """`config` with one slot of its store holding `value`."""
    store = config.store
    return Config(config.machines, (*store[:slot], value, *store[slot + 1:]), config.done)


# ----------------------------------------------------------------------------- value helpers


def value_text(t: ast.Type | None, v: object) -> str:
    """FDR-style text of a value, as tockbmc prints it."""
    return text_of(t, v)


def _ediv(a: int, b: int) -> int:
    return a // b if b > 0 else -(a // -b)


# How many times over a recursive function's unfolding a call may go on (model/recursion.py).
MAX_RECURSION = 25

# Binary operators that are Python's own on the values the interpreter keeps.
_BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "==": operator.eq, "!=": operator.ne,
    "<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge, "iff": lambda a, b: bool(a) == bool(b)}


def _coerce(t: ast.Type | None, v: object) -> object:
    """`v` as a value of type `t`: integers in real places become Fractions; dicts become Records."""
    if type(v) is Unknown:
        if v.type == t or all(type(_coerce(t, x)) is type(x) for x in v.values):  # type: ignore[union-attr]
            return v
        raise NeedValue(v)  # type: ignore[arg-type]  # its values would change type: choose one
    if t == ast.REAL and isinstance(v, int) and not isinstance(v, bool):
        return Fraction(v)
    if isinstance(t, ast.RecordType) and isinstance(v, dict):
        fields = {f.name: _coerce(f.type, v[f.name]) for f in t.fields if f.name in v}
        if isinstance(v, Record) and list(fields) == list(v) and \
                all(x is y for x, y in zip(fields.values(), v.values(), strict=True)):
            return v  # already a value of `t`: kept, with its hash
        return Record(fields)
    if t in (ast.INT, ast.NAT) and isinstance(v, Fraction) and v.denominator == 1:
        return int(v)
    if isinstance(t, ast.SeqType) and isinstance(v, tuple):
        return tuple(_coerce(t.element, x) for x in v)
    if isinstance(t, ast.SetType) and isinstance(v, frozenset):
        return frozenset(_coerce(t.element, x) for x in v)
    if isinstance(t, ast.ProductType) and isinstance(v, tuple):
        return Product(_coerce(pt, x) for pt, x in zip(t.parts, v, strict=True))
    if isinstance(t, ast.ProductType) and isinstance(v, dict) and set(v) == {str(i) for i in range(1, len(t.parts) + 1)}:
        # a tuple given by its parts "1", "2", … (a constant's value as the configuration reads it)
        return Product(_coerce(pt, v[str(i)]) for i, pt in enumerate(t.parts, 1))
    return v


def _fits(t: ast.Type | None, v: object) -> bool:
    """Whether `v` may be stored in a place of type `t` (nat values are never negative)."""
    if type(v) is Unknown:
        fits = [_fits(t, x) for x in v.values]  # type: ignore[union-attr]
        if all(fits) or not any(fits):
            return fits[0]
        raise NeedValue(v)  # type: ignore[arg-type]
    if t == ast.NAT:
        return not (isinstance(v, (int, Fraction)) and not isinstance(v, bool) and v < 0)
    if isinstance(t, ast.RecordType) and isinstance(v, dict):
        return all(_fits(f.type, v.get(f.name)) for f in t.fields)
    if isinstance(t, (ast.SeqType, ast.SetType)) and isinstance(v, (tuple, frozenset)):
        return all(_fits(t.element, x) for x in v)
    if isinstance(t, ast.ProductType) and isinstance(v, tuple):
        return all(_fits(pt, x) for pt, x in zip(t.parts, v, strict=True))
    if isinstance(t, ast.EnumType) and isinstance(v, Variant):
        return all(_fits(pt, x) for pt, x in zip(t.parameters(v.literal.rsplit("::", 1)[-1]), v.args, strict=True))
    return True


def _to_range(r: object) -> tuple[Fraction, Fraction]:
    try:
        lo, hi = r  # type: ignore[misc]
    except (TypeError, ValueError):
        if dataclasses.is_dataclass(r):
            lo, hi = (getattr(r, f.name) for f in dataclasses.fields(r)[:2])
        else:
            for a, b in (("low", "high"), ("lo", "hi"), ("lower", "upper"), ("min", "max")):
                if hasattr(r, a) and hasattr(r, b):
                    lo, hi = getattr(r, a), getattr(r, b)
                    break
            else:
                raise TypeError(f"not a range: {r!r}") from None
    return Fraction(lo), Fraction(hi)


def _worklist(todo: list) -> Iterable:
    """The items of `todo`, last first, including those added while it is read."""
    while todo:
        yield todo.pop()


class _Given(Mapping[tuple, tuple]):
    """Inputs for `Interpreter.steps`: `values` on `channel`, and no value on any other channel."""

    def __init__(self, channel: tuple | None, values: tuple) -> None:
        self.channel, self.given = channel, values

    def __getitem__(self, channel: tuple) -> tuple:
        return self.given if channel == self.channel else ()

    def __contains__(self, channel: object) -> bool:
        return True

    def __iter__(self) -> Iterator[tuple]:
        return iter([self.channel or ()])

    def __len__(self) -> int:
        return 1


# An expression reading Unknowns is tried with each of their values, at most this many times per
# step, before the configuration holding them is split (lazy mode).
TOTAL = 4096


# ----------------------------------------------------------------------------- static structure


class _Beh:
    """A machine's or defined operation's graph, indexed."""

    def __init__(self, b: ast.Behaviour, is_op: bool) -> None:
        self.b = b
        self.is_op = is_op
        self.nodes = {n.path: n for n in b.nodes}
        self.out: dict[str, list[ast.Transition]] = defaultdict(list)
        for t in b.transitions:
            self.out[t.source].append(t)
        self.initial: dict[str | None, str] = {}
        for n in b.nodes:
            if n.kind == "initial":
                if n.parent in self.initial:  # RoboTool warns (STM3) and gives entering it no meaning
                    raise NotInterpretable(n.pos, f"region {n.parent or b.name} has more than one initial junction")
                self.initial[n.parent] = n.path
            if n.kind == "probabilistic":
                raise NotInterpretable(n.pos, "probabilistic junctions")
        for n in b.nodes:
            if n.composite and n.path not in self.initial:
                raise NotInterpretable(n.pos, f"region {n.path} has no initial junction")
        if b.nodes and None not in self.initial:
            raise NotInterpretable(b.pos, f"region {b.name} has no initial junction")
        self.deadlines = [t for t in b.transitions if t.deadline is not None]
        self._cands: dict[str, list[ast.Transition]] = {}
        self._paths: dict[tuple[str, str, str], tuple[tuple[str, ...], tuple[str, ...]]] = {}

    def ancestors(self, path: str | None) -> list[str]:
        """`path` and its ancestors, innermost first."""
        out = []
        while path is not None:
            out.append(path)
            path = self.nodes[path].parent
        return out

    def candidates(self, path: str) -> list[ast.Transition]:
        """Transitions of the node and (for a state) of all its ancestors."""
        c = self._cands.get(path)
        if c is None:
            node = self.nodes[path]
            if node.kind in ("initial", "junction"):
                c = list(self.out.get(path, ()))
            else:
                c = [t for p in self.ancestors(path) for t in self.out.get(p, ())]
            self._cands[path] = c
        return c

    def path(self, leaf: str, source: str, target: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """The nodes exited (innermost first) and entered (outermost first) by a transition."""
        key = (leaf, source, target)
        r = self._paths.get(key)
        if r is None:
            anc_s = self.ancestors(self.nodes[source].parent)
            anc_g = set(self.ancestors(self.nodes[target].parent))
            lca = next((a for a in anc_s if a in anc_g), None)
            exits = []
            p: str | None = leaf
            while p is not None and p != lca:
                exits.append(p)
                p = self.nodes[p].parent
            enters = []
            p = target
            while p is not None and p != lca:
                enters.append(p)
                p = self.nodes[p].parent
            r = (tuple(exits), tuple(reversed(enters)))
            self._paths[key] = r
        return r


class _Inst(NamedTuple):
    name: str  # display name
    local: str  # instance name in its controller
    machine: ast.StateMachine
    beh: int
    defined: dict


class _Link:
    """A connection: `src`/`dst` are (machine index, event name), or None for the environment."""

    def __init__(self, asynchronous: bool, src: tuple | None, dst: tuple | None, vis: str | None,
                 type_: ast.Type | None, pos: ast.Pos | None) -> None:
        self.asynchronous = asynchronous
        self.src = src
        self.dst = dst
        self.vis = vis
        self.type = type_
        self.pos = pos
        self.slot: int | None = None


class _Slot(NamedTuple):
    key: tuple
    kind: str  # var | const | oplocal | clock | since | tdl | buf
    var: ast.Variable | None
    display: str
    inst: int | None


class _Copies(NamedTuple):
    """RoboTool's memory model for one shared variable (docs/semantics.md §5.5): each machine that
    requires it keeps a copy (`readers`, by instance); a write changes the writer's copy and, where
    the memory is inside the element (`passes_writes`), the memory passes it on to every copy, one
    internal step each, taking no other write meanwhile (slot `mem`: None, or (value, next reader)).
    `written`/`external` name the visible writes of the machines and of the environment; `start` is
    the initial value the model gives it, passed on at the start (the copies start at the default)."""

    name: str
    decl: ast.Variable
    readers: tuple[int, ...]
    passes_writes: bool
    written: str | None
    external: str | None
    start: ast.Expr | None
    direct: bool
    mem: int | None  # the memory's slot, where it holds a value being passed on


class _Ctx:
    """A configuration's store being changed: reads see the writes made so far."""

    __slots__ = ("base", "upd", "i", "bind", "assume", "budget")

    def __init__(self, base: tuple, i: int, upd: dict | None = None) -> None:
        self.base = base
        self.upd = dict(upd) if upd else {}
        self.i = i
        self.bind: dict | None = None
        # lazy mode: values assumed for Unknowns (by identity) while an expression is tried with each
        self.assume: dict[int, object] | None = None
        self.budget = TOTAL

    def get(self, s: int) -> object:
        u = self.upd
        v = u[s] if s in u else self.base[s]
        if v is liveness.DEAD:  # the liveness analysis said no run reads it here: a bug, stop rather than guess
            raise AssertionError(f"slot {s} was read where the liveness analysis found it dead")
        return v

    def set(self, s: int, v: object) -> None:
        self.upd[s] = v


# ----------------------------------------------------------------------------- sampling


class Sampler:
    """How a random run chooses values, instead of listing every one (`tockbmc simulate`).

    A choice among more than `size` values (an input, an initial value, a local without an initial
    value, how long a `wait` lasts) is made among `size` values drawn at random; a type with no
    range takes its values from `windows` (by range name, `given` for given types). Which windows
    were used is kept in `used`.
    """

    def __init__(self, rng: random.Random, windows: dict[str, tuple[Fraction, Fraction]], size: int = 16) -> None:
        self.rng = rng
        self.windows = windows
        self.size = size
        self.used: dict[str, tuple[Fraction, Fraction]] = {}

    def window(self, name: str, given: bool) -> tuple[Fraction, Fraction] | None:
        key = "given" if given else name
        r = self.windows.get(key)
        if r is not None:
            self.used[name] = r
        return r


# ----------------------------------------------------------------------------- the interpreter


class Interpreter:
    """The steps of one machine, controller or module (docs/semantics.md §3–§5)."""

    def __init__(self, element: ast.StateMachine | ast.Controller | ast.Module,
                 ranges: Ranges | Mapping[str, object] | None = None,
                 settings: dict[str, object] | None = None,
                 defined: dict[str, ast.OperationDef] | None = None, sampler: Sampler | None = None,
                 lazy: bool = False, timed: bool = True, dead_variables: bool = False) -> None:
        # RoboTool's untimed semantics (docs/semantics.md §7.11): the model as `model.untimed`
        # rewrites it (no waits, deadlines, clock resets or clock conditions) and no `tock` step.
        self.timed = timed
        self._evaluate_by_type = self._evaluators()
        # recursive functions, by name, for their calls past the unfolding (`model.recursion`):
        # found on the first such call, as few models have one
        self._recursive: dict[str, ast.Function] | None = None
        self._recursing = 0
        if not timed:
            element, defined = untimed(element, defined)
        self.element = element
        self.sampler = sampler  # None: every value of every choice (the explicit engine, replay)
        # Lazy mode (the explicit engine's search): an input or an open initial value is an Unknown
        # until a step reads it, and then the configuration or input holding it is split into one per
        # value (`expand`); visible events may carry Unknowns, except on the channels in `strict`.
        self.lazy = lazy and sampler is None
        self.strict: set[tuple] = set()
        self.points_chosen: list[str] = []  # the open functions whose values at a point `expand` chose
        self.ename = element.name
        # the ranges as a check gives them (or by name: `{"core_int": (-2, 2)}`), and by name as pairs of bounds
        self.data_ranges = ranges if isinstance(ranges, Ranges) else \
            Ranges.named({k: Range(*_to_range(v)) for k, v in (ranges or {}).items()})
        self.ranges = {k: (r.low, r.high) for k, r in self.data_ranges.by_name().items()}
        self.settings = dict(settings or {})
        self.defined = dict(defined or {})
        self.stmts: list[ast.Stmt] = []
        self._sid: dict[int, int] = {}
        self.behs: list[_Beh] = []
        self._beh_of: dict[int, int] = {}
        self._provided: dict[tuple[int, int], tuple[object, object, ast.OperationDef]] = {}  # `_resolve_call`
        self.insts: list[_Inst] = []
        self.links: list[_Link] = []
        self.out_link: dict[tuple, _Link] = {}
        self.in_links: dict[tuple, list[_Link]] = defaultdict(list)
        self.slots: list[_Slot] = []
        self._slot_of: dict[tuple, int] = {}
        self._domains: dict[tuple, list] = {}
        self._tuples: dict[tuple, tuple] = {}
        self._shared_owners: set[str] = set()
        self.network = not isinstance(element, ast.StateMachine)
        # a module's terminate is hidden: an internal step, then ✓ (docs/semantics.md §5.6); so is an
        # operation's checked on its own (§4.8)
        self.hidden_termination = isinstance(element, (ast.Module, ast.OperationMachine))
        self._shared_vars: list[ast.Variable] = []
        # who keeps a shared variable's memory, by name: "controller", "platform", "provided" (an
        # interface the platform provides); one not listed is required from outside, named
        # after `_outside[name]` (RoboTool's `C::set_x`)
        self._keeper: dict[str, str] = {}
        self._outside: dict[str, str] = {}

        if isinstance(element, ast.StateMachine):
            self._add_inst(element, element.name, self.defined)
        elif isinstance(element, ast.Controller):
            self._shared_owners.add(element.qname)
            self._shared_vars.extend(element.variables)
            self._keep(element)
            b_in, b_out = self._flatten_controller(element, "")
            for ename, entries in b_in.items():
                self._boundary_env(entries, f"{self.ename}::{ename}", True)
            for ename, entries in b_out.items():
                self._boundary_env(entries, f"{self.ename}::{ename}", False)
        elif isinstance(element, ast.Module):
            self._flatten_module(element)
        else:
            raise NotInterpretable(getattr(element, "pos", None), f"{type(element).__name__} as the element")

        # display names: the machine's name unless two instances share it
        counts: dict[str, int] = defaultdict(int)
        for inst in self.insts:
            counts[inst.machine.name] += 1
        self.insts = [inst._replace(name=inst.machine.name if counts[inst.machine.name] == 1 else inst.local)
                      for inst in self.insts]
        for v in self._shared_vars:
            self._reg(("shared", v.name), "const" if v.constant else "var", v, v.name, None)
        for i, inst in enumerate(self.insts):
            self._scan(i, inst.beh, [])
        self.copies = self._memory()
        self._copy_of = {(i, cp.name): cp for cp in self.copies for i in cp.readers}
        self._copy_slot: dict[int, _Copies] = {self._slot(i, cp.decl): cp for cp in self.copies for i in cp.readers}
        for n, link in enumerate(self.links):
            if link.asynchronous:
                link.slot = self._reg(("buf", n), "buf", None, f"buffer {n}", None)
        if sampler is None:  # a function the model leaves open: its values so far, chosen where first read
            for f in ast.free_functions(element, self.defined):
                self._reg(("fun", f.qname), "fun", None, f.name, None)
        # whether a search must take its nodes from `expand`: Unknowns, or open functions' points, to choose
        self.splits = self.lazy or any(info.kind == "fun" for info in self.slots)
        # Machines whose internal steps read and write only what no other part of the network
        # writes or reads (`private_steps`): in a network every variable a machine reads is its own
        # or its copy of a shared one (`_vkey`), which the memory writes; constants do not change.
        self._private = () if len(self.insts) < 2 else tuple(
            i for i in range(len(self.insts)) if not any(i in cp.readers for cp in self.copies))
        # (instance, leaf state) -> slots of the machine's variables dead while it rests there
        # (`liveness`): a search's configurations hold `DEAD` there; other users see every value.
        self._dead = self._dead_at_rest() if dead_variables else {}
        self._tdl: dict[int, list[tuple[int, int, ast.Transition]]] = defaultdict(list)
        for key, s in self._slot_of.items():
            if key[0] == "tdl":
                _, i, bi, tname = key
                t = next(t for t in self.behs[bi].deadlines if t.name == tname)
                self._tdl[i].append((s, bi, t))
        self._timed_slots = [s for s, info in enumerate(self.slots) if info.kind in ("clock", "since")]
        self._caps = self._clock_caps()

    # ------------------------------------------------------------------ structure

    def _beh(self, b: ast.Behaviour, is_op: bool) -> int:
        k = id(b)
        if k not in self._beh_of:
            self._beh_of[k] = len(self.behs)
            self.behs.append(_Beh(b, is_op))
        return self._beh_of[k]

    def _add_inst(self, m: ast.StateMachine, local: str, defined: dict) -> int:
        self.insts.append(_Inst(m.name, local, m, self._beh(m, False), defined))
        return len(self.insts) - 1

    def _link(self, asynchronous: bool, src: tuple | None, dst: tuple | None, vis: str | None,
              type_: ast.Type | None, pos: ast.Pos | None) -> None:
        if src is not None and dst is not None and src[0] == dst[0] and not asynchronous:
            raise NotInterpretable(pos, "a synchronous connection of a machine with itself")
        link = _Link(asynchronous, src, dst, vis, type_, pos)
        if src is not None:
            if src in self.out_link:
                raise NotInterpretable(pos, "one-to-many connections")
            self.out_link[src] = link
        if dst is not None:
            self.in_links[dst].append(link)
        self.links.append(link)

    def _flatten_controller(self, ctrl: ast.Controller, prefix: str) -> tuple[dict, dict]:
        defined = dict(self.defined)
        for oi in ctrl.operations:
            defined[oi.operation.name] = oi.operation
            defined[oi.name] = oi.operation
        local: dict[str, int] = {}
        machines = {mi.name: mi.machine for mi in ctrl.machines}
        ctrl_ops = [oi.operation for oi in ctrl.operations]
        for mi in ctrl.machines:
            local[mi.name] = self._add_inst(mi.machine, prefix + mi.name, defined)
        b_in: dict[str, list] = defaultdict(list)
        b_out: dict[str, list] = defaultdict(list)
        for c in ctrl.connections:
            if c.bidirectional and (c.source in local) == (c.target in local):
                raise NotInterpretable(c.pos, "bidirectional connections between two machines")
            if c.bidirectional and c.asynchronous:
                raise NotInterpretable(c.pos, "asynchronous bidirectional connections of a machine")
            if c.source in local and c.target in local:
                self._link(c.asynchronous, (local[c.source], c.source_event.name),
                           (local[c.target], c.target_event.name), None, c.target_event.type, c.pos)
            # A synchronous connection with the controller's own event joins the whole channel, both
            # directions, whichever way it is drawn (RoboTool renames `stm_ref0::e <- e`): a machine
            # that also uses the event the other way round is listed that way too.
            elif c.source == ctrl.name and c.target in local:
                b_in[c.source_event.name].append((local[c.target], c.target_event.name, c.asynchronous, c))
                if not c.asynchronous and ast.uses_event((machines[c.target], *ctrl_ops), c.target_event.name,
                                                         sends=True):
                    b_out[c.source_event.name].append((local[c.target], c.target_event.name, False, c))
            elif c.source in local and c.target == ctrl.name:
                b_out[c.target_event.name].append((local[c.source], c.source_event.name, c.asynchronous, c))
                if not c.asynchronous and ast.uses_event((machines[c.source], *ctrl_ops), c.source_event.name,
                                                         sends=False):
                    b_in[c.target_event.name].append((local[c.source], c.source_event.name, False, c))
            else:
                raise NotInterpretable(c.pos, f"connection from {c.source} to {c.target}")
        return b_in, b_out

    def _both_ways(self, info: tuple, event: str, vis: str, pos: ast.Pos) -> None:
        """A connection to the platform: RoboTool renames the controller's whole channel, so every
        machine port behind the event, inputs and outputs, is joined to the module's event, each in its
        direction (a port used both ways, joined synchronously inside the controller, is in both
        tables; the BMC encoding's one synchronous link carries both).  Only the links not made yet
        are added."""
        _ctrl, b_in, b_out = info
        for table, inbound in ((b_in, True), (b_out, False)):
            for entry in table.get(event, []):
                key = (entry[0], entry[1])
                if not (self.in_links.get(key) if inbound else self.out_link.get(key)):
                    self._boundary_env([entry], vis, inbound, False, pos)

    def _boundary_env(self, entries: list, vis: str, inbound: bool, outer_async: bool = False,
                      pos: ast.Pos | None = None) -> None:
        if inbound and len(entries) > 1:
            raise NotInterpretable(entries[1][3].pos, "one-to-many connections")
        for i, port, a, c in entries:
            if a and outer_async:
                raise NotInterpretable(pos or c.pos, "two buffers in series")
            t = c.target_event.type if inbound else c.source_event.type
            if inbound:
                self._link(a or outer_async, None, (i, port), vis, t, pos or c.pos)
            else:
                self._link(a or outer_async, (i, port), None, vis, t, pos or c.pos)

    def _flatten_module(self, mod: ast.Module) -> None:
        pname = mod.platform_name
        if mod.platform is not None:
            self._shared_owners.add(mod.platform.qname)
            self._shared_vars.extend(mod.platform.variables)
            for v in mod.platform.variables:
                self._keeper.setdefault(
                    v.name, "provided" if ast.in_interfaces(v, mod.platform.provided_interfaces) else "platform")
        cinfo: dict[str, tuple] = {}
        for ci in mod.controllers:
            self._shared_owners.add(ci.controller.qname)
            self._shared_vars.extend(ci.controller.variables)
            self._keep(ci.controller)
            b_in, b_out = self._flatten_controller(ci.controller, ci.name + ".")
            cinfo[ci.name] = (ci.controller, b_in, b_out)
        used: set[tuple] = set()
        for c in mod.connections:
            if c.bidirectional and c.source in cinfo and c.target in cinfo:
                raise NotInterpretable(c.pos, "bidirectional connections between two controllers")
            if c.source == pname and c.target in cinfo:
                used.add((c.target, "in", c.target_event.name))
                entries = cinfo[c.target][1].get(c.target_event.name, [])
                # The platform is the environment: RoboTool joins its connections directly, `(_async)` or not.
                self._boundary_env(entries, f"{self.ename}::{c.source_event.name}", True, False, c.pos)
                # the controller's whole channel, both directions (RoboTool renames `ctrl_ref1::e <- e`)
                used.add((c.target, "out", c.target_event.name))
                self._both_ways(cinfo[c.target], c.target_event.name, f"{self.ename}::{c.source_event.name}", c.pos)
            elif c.source in cinfo and c.target == pname:
                used.add((c.source, "out", c.source_event.name))
                entries = cinfo[c.source][2].get(c.source_event.name, [])
                self._boundary_env(entries, f"{self.ename}::{c.target_event.name}", False, False, c.pos)
                used.add((c.source, "in", c.source_event.name))
                self._both_ways(cinfo[c.source], c.source_event.name, f"{self.ename}::{c.target_event.name}", c.pos)
            elif c.source in cinfo and c.target in cinfo:
                used.add((c.source, "out", c.source_event.name))
                used.add((c.target, "in", c.target_event.name))
                outs = cinfo[c.source][2].get(c.source_event.name, [])
                ins = cinfo[c.target][1].get(c.target_event.name, [])
                if len(ins) > 1:
                    raise NotInterpretable(c.pos, "one-to-many connections")
                for i, p, a, _ in outs:
                    for j, q, b, _ in ins:
                        if [a, b, c.asynchronous].count(True) > 1:
                            raise NotInterpretable(c.pos, "two buffers in series")
                        self._link(a or b or c.asynchronous, (i, p), (j, q), None, c.target_event.type, c.pos)
            else:
                raise NotInterpretable(c.pos, f"connection from {c.source} to {c.target}")
        for cname, (ctrl, b_in, b_out) in cinfo.items():
            for ename, entries in b_in.items():
                if (cname, "in", ename) not in used:
                    self._boundary_env(entries, f"{ctrl.name}::{ename}", True)
            for ename, entries in b_out.items():
                if (cname, "out", ename) not in used:
                    self._boundary_env(entries, f"{ctrl.name}::{ename}", False)

    def _keep(self, ctrl: ast.Controller) -> None:
        """A controller keeps the memory of its variables and of the interfaces it uses or
        provides; the variables its machines require otherwise come from outside it."""
        for v in ctrl.variables:
            self._keeper.setdefault(v.name, "controller")
        own = (*ctrl.used_interfaces, *ctrl.provided_interfaces)
        for mi in ctrl.machines:
            for v in mi.machine.interface_variables:
                if ast.in_interfaces(v, own):
                    self._keeper.setdefault(v.name, "controller")
                self._outside.setdefault(v.name, ctrl.name)
        for oi in ctrl.operations:
            for v in oi.operation.interface_variables:
                self._outside.setdefault(v.name, ctrl.name)

    def _memory(self) -> list[_Copies]:
        """The shared variables whose machines keep copies, once their slots are known."""
        readers: dict[str, list[int]] = defaultdict(list)
        variables: dict[str, ast.Variable] = {}
        for info in self.slots:
            key = info.key
            if key[0] == "copy" or key[0] == "v" and key[2] == "#iface" and not self.network:
                assert info.var is not None and info.inst is not None
                if not self.network and (info.var.constant or self._own_interface(info.inst, info.var)):
                    continue
                readers[key[-1]].append(info.inst)
                variables.setdefault(key[-1], info.var)
        declared = {v.name: v for v in self._shared_vars}
        out: list[_Copies] = []
        for name, found in readers.items():
            decl = declared.get(name, variables[name])
            keeper = self._keeper.get(name) if self.network else None
            if keeper is None:
                outer = self._outside.get(name, self.ename) if self.network else self.ename
                cp = _Copies(name, decl, tuple(sorted(found)), False, f"{outer}::set_{name}",
                             f"{outer}::set_EXT_{name}", None, not self.network, None)
            else:
                cp = _Copies(name, decl, tuple(sorted(found)), True,
                             f"{self.ename}::set_{name}" if keeper == "provided" else None, None,
                             given_initial(decl), False, None)
            # the rule of `encodings.composition.Copies.stateful`, written again here so that
            # the differential checks one against the other
            stateful = (cp.start is not None or cp.passes_writes and len(cp.readers) > 1
                        or cp.external is not None and not cp.direct)
            if stateful:
                cp = cp._replace(mem=self._reg(("mem", name), "mem", None, f"memory of {name}", None))
            out.append(cp)
        return out

    def _sid_of(self, s: ast.Stmt) -> int:
        k = id(s)
        n = self._sid.get(k)
        if n is None:
            n = self._sid[k] = len(self.stmts)
            self.stmts.append(s)
        return n

    def _reg(self, key: tuple, kind: str, var: ast.Variable | None, display: str, inst: int | None) -> int:
        s = self._slot_of.get(key)
        if s is None:
            s = self._slot_of[key] = len(self.slots)
            self.slots.append(_Slot(key, kind, var, display, inst))
        return s

    def _vkey(self, i: int, var: ast.Variable) -> tuple:
        if var.kind == "interface" and not var.constant:  # an operation's required variable: the calling machine's
            local = next((v for v in self.insts[i].machine.variables if v.name == var.name and not v.constant), None)
            if local is not None:
                return self._vkey(i, local)
        if var.kind == "interface" and self._own_interface(i, var):
            return ("v", i, "#iface", var.name)
        if var.kind == "interface" or var.owner in self._shared_owners:
            if not self.network:
                return ("v", i, "#iface", var.name)
            # a machine's copy of a shared variable (RoboTool's memory model); constants are shared
            return ("shared", var.name) if var.constant else ("copy", i, var.name)
        return ("v", i, var.owner, var.name)

    def _start(self, info: _Slot) -> ast.Expr | None:
        """A variable's initial value: a copy of a shared variable whose memory passes the model's
        initial value on at the start starts at its type's default (RoboTool's memory model)."""
        var = info.var
        assert var is not None
        if info.key[0] in ("copy", "v") and info.inst is not None:
            cp = self._copy_of.get((info.inst, var.name))
            if cp is not None:  # the declaration's initial value (a controller's, a platform's)
                return default_value(var.type, var.pos) if cp.start is not None else cp.decl.initial
        return var.initial

    def _own_interface(self, i: int, var: ast.Variable) -> bool:
        """A variable or constant of an interface the machine provides or uses is its own, one per
        instance (RoboTool: `const_test12_ctrl0_stm_ref0_CC`); a required one is its controller's."""
        m = self.insts[i].machine
        return ast.in_interfaces(var, (*m.provided_interfaces, *m.used_interfaces))

    def _slot(self, i: int, var: ast.Variable) -> int:
        s = self._slot_of.get(self._vkey(i, var))
        if s is None:
            raise NotInterpretable(var.pos, f"variable {var.name} is not one of the machine's")
        return s

    def _reg_var(self, i: int, var: ast.Variable, op: ast.OperationDef | None) -> None:
        if var.kind in ("let", "bound"):  # named inside an expression: bound there, never stored
            return
        key = self._vkey(i, var)
        inst = self.insts[i].name
        if key[0] == "shared":
            display = var.name
        elif key[0] == "copy":
            display = f"{inst}.{var.name}"
        elif op is not None and var.owner == op.qname and var.constant and var.kind != "parameter":
            display = f"{inst}.{op.name}().{var.name}"  # an operation's constant: set like the machine's
        elif op is not None and var.owner == op.qname:
            self._reg(key, "oplocal", var, f"{inst}.{op.name}().{var.name}", i)
            return
        else:
            display = f"{inst}.{var.name}"
        self._reg(key, "const" if var.constant else "var", var, display, i)

    def _resolve_call(self, i: int, st: ast.OperationCall, caller: ast.Behaviour | None = None) -> ast.OperationDef | None:
        """The defined operation a call runs (as `caller` runs it: with the variables it requires
        that the calling operation declares, `ast.provided_for`), or None for a platform operation."""
        op = st.operation
        # docs/semantics.md §4.7: a platform operation is a signature, or an operation whose body is only `terminates`.
        if isinstance(op, ast.OperationDef):
            d: ast.OperationDef | None = op if op.nodes else None
        else:
            d = self.insts[i].defined.get(op.name)
            d = d if d is not None and d.nodes else None
        if d is None or caller is None:
            return d
        key = (id(caller), id(d))
        if key not in self._provided:  # one object per caller, so that it is one behaviour (`_beh`)
            self._provided[key] = (caller, d, ast.provided_for(caller, d))
        return self._provided[key][2]

    def _scan(self, i: int, bi: int, stack: list[int]) -> None:
        beh = self.behs[bi]
        b = beh.b
        op = b if isinstance(b, ast.OperationDef) else None
        problem = composite_during_problem(b, partial(self._resolve_call, i), beh.is_op)
        if problem is not None:
            raise NotInterpretable(*problem)
        for v in b.variables:
            self._reg_var(i, v, op)
        if op is not None:
            for v in op.parameters:
                self._reg_var(i, v, op)
        for v in b.interface_variables:
            self._reg_var(i, v, op)
        inst = self.insts[i].name
        for c in b.clocks:
            self._reg(("clk", i, c.name), "clock", None, f"{inst}.{c.name}", i)
        stmts: list[ast.Stmt] = []
        exprs: list[object] = []
        for n in b.nodes:
            for a in (n.entry, n.during, n.exit):
                stmts.extend(ast.statements(a))
        for t in b.transitions:
            stmts.extend(ast.statements(t.action))
            exprs.extend(x for x in (t.condition, t.deadline) if x is not None)
            if t.trigger is not None:
                if t.trigger.value is not None:
                    exprs.append(t.trigger.value)
                if t.trigger.variable is not None:
                    self._reg_var(i, t.trigger.variable, op)
            for c in t.clock_resets:
                self._reg(("clk", i, c.name), "clock", None, f"{inst}.{c.name}", i)
            if t.deadline is not None:
                self._reg(("tdl", i, bi, t.name), "tdl", None, f"{inst}: deadline of {t.name}", i)
        exprs.extend(stmts)
        for e in ast.subexpressions(tuple(exprs)):
            if isinstance(e, ast.VarRef):
                self._reg_var(i, e.variable, op)
            elif isinstance(e, ast.Since):
                self._reg(("clk", i, e.clock.name), "clock", None, f"{inst}.{e.clock.name}", i)
            elif isinstance(e, ast.SinceEntry):
                self._reg(("since", i, bi, e.state), "since", None, f"{inst}.sinceEntry({e.state})", i)
        for st in stmts:
            self._sid_of(st)
            if isinstance(st, ast.Assign):
                self._reg_var(i, st.variable, op)
            elif isinstance(st, ast.Receive) and st.variable is not None:
                self._reg_var(i, st.variable, op)
            elif isinstance(st, ast.ClockReset):
                self._reg(("clk", i, st.clock.name), "clock", None, f"{inst}.{st.clock.name}", i)
            elif isinstance(st, ast.OperationCall):
                d = self._resolve_call(i, st, b)
                if d is not None:
                    di = self._beh(d, True)
                    if any(self.behs[s].b.qname == d.qname for s in (*stack, bi)):  # the copies of `provided_for` too
                        raise NotInterpretable(st.pos, f"recursive operation {d.name}")
                    self._scan(i, di, [*stack, bi])

    def _clock_caps(self) -> dict[int, int]:
        """Per clock (and `sinceEntry`) slot, a value beyond which it need not grow.

        When every read of a clock is a comparison with a literal, all values above the largest
        literal behave alike, so the clock saturates at that literal + 1 (a clock never read stays
        0). Any other read (`x = since(C)`, arithmetic on it) leaves the clock unbounded.
        """
        limits: dict[int, int | None] = {s: 0 for s in self._timed_slots}
        comparisons = ("<", "<=", ">", ">=", "==", "!=")

        def clock_slot(e: ast.Expr, i: int, bi: int) -> int | None:
            if isinstance(e, ast.Since):
                return self._slot_of.get(("clk", i, e.clock.name))
            if isinstance(e, ast.SinceEntry):
                return self._slot_of.get(("since", i, bi, e.state))
            return None

        def literal(e: ast.Expr) -> Fraction | None:
            if isinstance(e, ast.Literal) and isinstance(e.value, (int, Fraction)) and not isinstance(e.value, bool):
                return Fraction(e.value)
            if isinstance(e, ast.Unary) and e.op == "-":
                v = literal(e.operand)
                return None if v is None else -v
            return None

        def walk(x: object, i: int, bi: int) -> None:
            stack = [x]
            while stack:
                item = stack.pop()
                if isinstance(item, tuple):
                    stack.extend(item)
                    continue
                if not isinstance(item, (ast.Expr, ast.Stmt)):
                    continue
                if isinstance(item, ast.Binary) and item.op in comparisons:
                    for a, b in ((item.left, item.right), (item.right, item.left)):
                        s = clock_slot(a, i, bi)
                        lit = literal(b)
                        if s is not None and lit is not None:
                            if limits.get(s) is not None:
                                limits[s] = max(limits[s] or 0, math.floor(lit) + 1)  # type: ignore[type-var]
                            break
                    else:
                        stack.extend((item.left, item.right))
                    continue
                s = clock_slot(item, i, bi) if isinstance(item, ast.Expr) else None
                if s is not None:
                    limits[s] = None
                    continue
                stack.extend(getattr(item, f.name) for f in dataclasses.fields(item))

        for i, inst in enumerate(self.insts):
            todo = [inst.beh]
            done: set[int] = set()
            while todo:
                bi = todo.pop()
                if bi in done:
                    continue
                done.add(bi)
                b = self.behs[bi].b
                for n in b.nodes:
                    walk((n.entry, n.during, n.exit), i, bi)
                for t in b.transitions:
                    walk((t.condition, t.deadline, t.action, t.trigger.value if t.trigger else None), i, bi)
                    for st in ast.statements(t.action):
                        if isinstance(st, ast.OperationCall):
                            d = self._resolve_call(i, st, b)
                            if d is not None:
                                todo.append(self._beh(d, True))
                for n in b.nodes:
                    for st in (*ast.statements(n.entry), *ast.statements(n.during), *ast.statements(n.exit)):
                        if isinstance(st, ast.OperationCall):
                            d = self._resolve_call(i, st, b)
                            if d is not None:
                                todo.append(self._beh(d, True))
        return {s: v for s, v in limits.items() if v is not None}

    # ------------------------------------------------------------------ data

    def _type_range(self, t: ast.Type) -> tuple[str, tuple[Fraction, Fraction] | None]:
        name, r = self._given_range(t)
        if r is None and self.sampler is not None:
            r = self.sampler.window(name, isinstance(t, ast.GivenType))
        return name, r

    def _given_range(self, t: ast.Type) -> tuple[str, tuple[Fraction, Fraction] | None]:
        if t == ast.INT:
            return "core_int", self.ranges.get("core_int")
        if t == ast.NAT:
            r = self.ranges.get("core_nat")
            if r is None and "core_int" in self.ranges:
                lo, hi = self.ranges["core_int"]
                r = (max(lo, Fraction(0)), hi)
            return "core_nat", r
        if t == ast.REAL:
            return "core_real", self.ranges.get("core_real")
        if isinstance(t, ast.GivenType):
            return t.name, self.ranges.get(t.name, self.ranges.get(t.qname))
        raise NotInterpretable(None, f"values of type {t}")

    def _open_call(self, ctx: _Ctx, e: ast.Call, f: ast.Function, slot: int, point: tuple, inside: bool) -> object:
        """The value of a function the model leaves open at `point`: the one its table holds, or
        (`NeedPoint`) each value its contract allows there, to be chosen by splitting the
        configuration. Outside its preconditions any value of its type is allowed; inside, those
        its postconditions hold of (docs/semantics.md §6.4). ctx.bind holds its parameters."""
        self._concrete(point)  # a point is compared with the table's: its Unknowns are chosen first
        for at, value in ctx.get(slot):  # type: ignore[attr-defined]
            if at == point:
                return value
        bound = dict(ctx.bind or {})

        def allowed() -> tuple:
            out = []
            for v in self.domain(f.result, (f.qname,)):
                if inside:
                    ctx.bind = {**bound, RESULT: v}
                    if not all(self._ev(ctx, post) is True for post in f.postconditions):
                        continue
                out.append(v)
            return tuple(out)

        raise NeedPoint(e.pos, f.name, slot, point, allowed)

    def domain(self, t: ast.Type | None, paths: tuple[str, ...] = ()) -> list:
        """Every value of `t` within the ranges (`paths` are the range paths to try first)."""
        key = (t, paths)
        d = self._domains.get(key)
        if d is not None:
            return d
        if t is None:
            d = [None]
        elif t == ast.BOOLEAN:
            d = [False, True]
        elif isinstance(t, ast.EnumType):
            d = []
            for lit in t.literals:
                ps = t.parameters(lit)
                name = f"{t.name}::{lit}"
                parts = [self.domain(pt, tuple(f"{p}.{lit}.{i}" for p in paths)) for i, pt in enumerate(ps, 1)]
                d += [Variant((name, *combo)) for combo in itertools.product(*parts)] if ps else [name]
        elif isinstance(t, ast.RecordType):
            parts = [self.domain(f.type, tuple(f"{p}.{f.name}" for p in paths)) for f in t.fields]
            d = [Record(zip([f.name for f in t.fields], combo, strict=True)) for combo in itertools.product(*parts)]
        elif isinstance(t, ast.ProductType):
            parts = [self.domain(pt, tuple(f"{p}.{i}" for p in paths)) for i, pt in enumerate(t.parts, 1)]
            d = [Product(combo) for combo in itertools.product(*parts)]
        elif isinstance(t, (ast.SeqType, ast.SetType)):
            d = self._collections(t, paths)
        elif isinstance(t, ast.FunctionType):
            d = [AnyFunction(t)]
        else:
            lo, hi = self._bounds(t, paths)
            d = [Fraction(n) for n in range(lo, hi + 1)] if t == ast.REAL else list(range(lo, hi + 1))
        self._domains[key] = d
        return d

    def _collections(self, t: ast.SeqType | ast.SetType, paths: tuple[str, ...]) -> list:
        """Every sequence or set the environment may choose: a sequence's length within the range
        given on its path (none: it is unbounded), a set any subset of its element type's domain;
        elements take their type's range.  At most `MAX_COLLECTIONS` of them."""
        elements = self.domain(t.element, tuple(f"{p}[]" for p in paths))
        if isinstance(t, ast.SetType):
            if len(elements) > 12:
                raise NotInterpretable(None, f"every value of {t}: 2^{len(elements)} sets")
            return [frozenset(c) for n in range(len(elements) + 1) for c in itertools.combinations(elements, n)]
        length = self.data_ranges.length(paths)
        if length is None:
            raise Unbounded(str(t), paths[0] if paths else None, paths)
        lo, hi = max(0, math.ceil(length.low)), math.floor(length.high)
        if sum(len(elements) ** n for n in range(lo, hi + 1)) > MAX_COLLECTIONS:
            raise NotInterpretable(None, f"every value of {t} of length {lo}..{hi}: more than {MAX_COLLECTIONS}")
        return [tuple(c) for n in range(lo, hi + 1) for c in itertools.product(elements, repeat=n)]

    def _bounds(self, t: ast.Type, paths: tuple[str, ...]) -> tuple[int, int]:
        """The integers a scalar of type `t` takes (a real's integer values): a path's range, else its type's."""
        if t == ast.STRING or not isinstance(t, (ast.PrimitiveType, ast.GivenType)):
            raise NotInterpretable(None, f"values of type {t}")
        r = next((self.ranges[p] for p in paths if p in self.ranges), None)
        name, tr = self._type_range(t)
        if r is None:
            r = tr
        elif isinstance(t, ast.GivenType) and (own := self._given_range(t)[1]) is not None:
            r = (max(r[0], own[0]), min(r[1], own[1]))  # a given type's range is the type: a path's narrows it
        if r is None:
            raise Unbounded(name, paths[0] if paths else None, paths)
        lo, hi = math.ceil(r[0]), math.floor(r[1])
        if t == ast.NAT:
            lo = max(lo, 0)
        return lo, hi

    def _size(self, t: ast.Type | None, paths: tuple[str, ...]) -> int:
        """How many values `domain(t, paths)` has, without listing them."""
        if t is None:
            return 1
        if t == ast.BOOLEAN:
            return 2
        if isinstance(t, ast.EnumType) and not t.params:
            return len(t.literals)
        if isinstance(t, ast.RecordType):
            return math.prod(self._size(f.type, tuple(f"{p}.{f.name}" for p in paths)) for f in t.fields)
        if isinstance(t, (ast.ProductType, ast.SeqType, ast.SetType, ast.FunctionType, ast.EnumType)):
            return len(self.domain(t, paths))
        lo, hi = self._bounds(t, paths)
        return max(0, hi - lo + 1)

    def _draw(self, t: ast.Type | None, paths: tuple[str, ...]) -> object:
        """One value of `t` drawn at random by the sampler (the domain must not be empty)."""
        assert self.sampler is not None
        rng = self.sampler.rng
        if t is None:
            return None
        if t == ast.BOOLEAN:
            return rng.choice((False, True))
        if isinstance(t, ast.EnumType):
            lit = rng.choice(t.literals)
            ps = t.parameters(lit)
            args = [self._draw(pt, tuple(f"{p}.{lit}.{i}" for p in paths)) for i, pt in enumerate(ps, 1)]
            return Variant((f"{t.name}::{lit}", *args)) if ps else f"{t.name}::{lit}"
        if isinstance(t, ast.RecordType):
            return Record({f.name: self._draw(f.type, tuple(f"{p}.{f.name}" for p in paths)) for f in t.fields})
        if isinstance(t, (ast.ProductType, ast.SeqType, ast.SetType, ast.FunctionType)):
            return rng.choice(self.domain(t, paths))
        lo, hi = self._bounds(t, paths)
        n = rng.randint(lo, hi)
        return Fraction(n) if t == ast.REAL else n

    def _fresh(self, t: ast.Type | None, paths: tuple[str, ...]) -> list:
        """Lazy mode: the one value standing for every value of `t` (records field by field; a type
        with one value is that value), or none when `t` has no value in its range."""
        if isinstance(t, ast.RecordType):
            parts = [self._fresh(f.type, tuple(f"{p}.{f.name}" for p in paths)) for f in t.fields]
            if any(not part for part in parts):
                return []
            return [Record(zip([f.name for f in t.fields], [part[0] for part in parts], strict=True))]
        key = (t, paths)
        d = self._tuples.get(key)
        if d is None:
            d = self._tuples[key] = tuple(self.domain(t, paths))
        if len(d) <= 1:
            return list(d)
        return [Unknown(d, t)]  # type: ignore[arg-type]

    def _choices(self, t: ast.Type | None, paths: tuple[str, ...] = (), limit: int | None = None) -> list:
        """The values a choice of `t` is made among: every one, or when sampling and there are more
        than `limit` (the sampler's size by default), that many drawn at random."""
        if self.sampler is None:
            return self.domain(t, paths)
        limit = limit or self.sampler.size
        size = self._size(t, paths)
        if size <= limit:
            return self.domain(t, paths)
        return list(dict.fromkeys(self._draw(t, paths) for _ in range(limit)))

    def _get(self, ctx: _Ctx, var: ast.Variable) -> object:
        b = ctx.bind
        if b is not None:
            k = (var.owner, var.name)
            if k in b:
                return b[k]
        v = ctx.get(self._slot(ctx.i, var))
        if v is None:
            raise NotInterpretable(var.pos, f"variable {var.name} is read before it has a value")
        return v

    def _eval(self, ctx: _Ctx, e: ast.Expr) -> Any:
        """The value of `e`. In lazy mode, where `e` reads Unknowns, its value if that is the same
        for every value they stand for (tried, up to `TOTAL` evaluations), else `NeedValue`."""
        if not self.lazy:
            return self._ev(ctx, e)
        try:
            return self._ev(ctx, e)
        except NeedValue as nv:
            return self._total(ctx, e, nv)

    def _total(self, ctx: _Ctx, e: ast.Expr, nv: NeedValue) -> Any:
        u = nv.unknown
        saved = ctx.assume
        first: list[object] = []
        try:
            for x in u.values:
                ctx.budget -= 1
                if ctx.budget < 0:
                    raise nv
                ctx.assume = {**(saved or {}), id(u): x}
                r = self._eval(ctx, e)
                if first and r != first[0]:
                    raise nv  # the value depends on u's: the configuration or input holding u is split
                first[:1] = [r]
        finally:
            ctx.assume = saved
        return first[0]

    def _known(self, ctx: _Ctx, v: object) -> object:
        """`v` read by an expression (lazy mode): its Unknowns must be ones assumed to have a value."""
        u = _unknown_in(v)
        if u is None:
            return v
        if ctx.assume:
            v = _assumed(v, ctx.assume)
            u = _unknown_in(v)
        if u is not None:
            raise NeedValue(u)
        return v

    def _ev(self, ctx: _Ctx, e: ast.Expr) -> Any:
        return self._evaluate_by_type.get(type(e), self._ev_other)(ctx, e)

    def _evaluators(self) -> dict[type, Callable[[_Ctx, Any], Any]]:
        """The evaluation of each kind of expression, by the expression's class (`_ev` dispatches
        on it), each in a method of its own."""
        return {ast.Literal: self._ev_literal, ast.VarRef: self._ev_var, ast.Binary: self._ev_binary,
                ast.EnumLiteral: self._ev_enum, ast.FieldRef: self._ev_field, ast.Unary: self._ev_unary,
                ast.IfExpr: self._ev_if, ast.RecordLiteral: self._ev_record, ast.Since: self._ev_since,
                ast.SinceEntry: lambda ctx, e: ctx.get(self._since_slot(ctx, e)), ast.Call: self._ev_call,
                ast.ResultRef: self._ev_result, ast.SeqLiteral: self._ev_seq, ast.SetLiteral: self._ev_set,
                ast.TupleLiteral: self._ev_tuple, ast.Index: self._ev_index,
                ast.Builtin: lambda ctx, e: self._builtin(e, [self._ev(ctx, a) for a in e.args]),
                ast.Let: self._ev_let, ast.Quantifier: self._quantifier, ast.Lambda: self._closure,
                ast.Apply: lambda ctx, e: self._apply(ctx, e, self._ev(ctx, e.function), [self._ev(ctx, a) for a in e.args]),
                ast.SetComprehension: self._comprehension}

    def _ev_other(self, ctx: _Ctx, e: ast.Expr) -> Any:
        raise NotInterpretable(e.pos, e.what if isinstance(e, ast.UnsupportedExpr) else
                               f"the expression {type(e).__name__}")

    def _ev_literal(self, ctx: _Ctx, e: ast.Literal) -> Any:
        if isinstance(e.value, str):
            raise NotInterpretable(e.pos, "strings")
        return e.value

    def _ev_var(self, ctx: _Ctx, e: ast.VarRef) -> Any:
        v = self._get(ctx, e.variable)
        return self._known(ctx, v) if self.lazy else v

    def _ev_binary(self, ctx: _Ctx, e: ast.Binary) -> Any:
        op = e.op
        if op == "and":
            return bool(self._ev(ctx, e.left)) and bool(self._ev(ctx, e.right))
        if op == "or":
            return bool(self._ev(ctx, e.left)) or bool(self._ev(ctx, e.right))
        if op == "implies":
            return (not self._ev(ctx, e.left)) or bool(self._ev(ctx, e.right))
        a = self._ev(ctx, e.left)
        b = self._ev(ctx, e.right)
        simple = _BINARY.get(op)
        if simple is not None:
            if op in ("==", "!=") and isinstance(a, (Closure, AnyFunction)):
                raise NotInterpretable(e.pos, "equality of functions (equal at every point)")
            return simple(a, b)
        if op in ("/", "%"):
            if b == 0:
                raise NotInterpretable(e.pos, "division by zero")
            real = e.type == ast.REAL or isinstance(a, Fraction) or isinstance(b, Fraction)
            if op == "/":
                return Fraction(a) / Fraction(b) if real else _ediv(a, b)
            if real:
                raise NotInterpretable(e.pos, "% on reals")
            return a - b * _ediv(a, b)
        raise NotInterpretable(e.pos, f"operator {op}")

    def _ev_enum(self, ctx: _Ctx, e: ast.EnumLiteral) -> Any:
        if e.args:
            ps = e.enum.parameters(e.literal)
            return Variant((f"{e.enum.name}::{e.literal}",
                            *(_coerce(pt, self._ev(ctx, a)) for pt, a in zip(ps, e.args, strict=True))))
        return f"{e.enum.name}::{e.literal}"

    def _ev_field(self, ctx: _Ctx, e: ast.FieldRef) -> Any:
        r = self._eval_ref(ctx, e.record) if self.lazy else self._ev(ctx, e.record)
        v = r.get(e.field_name) if isinstance(r, dict) else None
        if v is None:
            raise NotInterpretable(e.pos, f"field {e.field_name} has no value")
        return self._known(ctx, v) if self.lazy else v

    def _ev_unary(self, ctx: _Ctx, e: ast.Unary) -> Any:
        v = self._ev(ctx, e.operand)
        if e.op == "not":
            return not v
        if e.op == "-":
            return -v
        if e.op == "trunc":  # towards zero, as FDR's integer reals divide
            return Fraction(math.trunc(v))
        raise NotInterpretable(e.pos, f"operator {e.op}")

    def _ev_if(self, ctx: _Ctx, e: ast.IfExpr) -> Any:
        return self._ev(ctx, e.then) if self._ev(ctx, e.condition) else self._ev(ctx, e.otherwise)

    def _ev_record(self, ctx: _Ctx, e: ast.RecordLiteral) -> Any:
        if ast.omits_fields(e):
            raise NotInterpretable(e.pos, "a record literal omitting fields, other than as an initial value")
        return _coerce(e.type, Record({n: self._ev(ctx, x) for n, x in e.fields}))

    def _ev_since(self, ctx: _Ctx, e: ast.Since) -> Any:
        return ctx.get(self._slot_of[("clk", ctx.i, e.clock.name)])

    def _ev_call(self, ctx: _Ctx, e: ast.Call) -> Any:
        f = e.function
        if f.unchecked:
            raise NotInterpretable(e.pos, ast.unchecked_function(f))
        if f.unfolding_of:  # past the unfolding: the recursive function itself, called again
            return self._ev_recursion(ctx, e, f.unfolding_of)
        table = self._slot_of.get(("fun", f.qname))
        if f.definition is None and table is None:
            raise NotInterpretable(e.pos, f"the uninterpreted function {f.name}")
        args = [_coerce(p.type, self._ev(ctx, a)) for p, a in zip(f.parameters, e.args, strict=False)]
        saved = ctx.bind
        ctx.bind = {(p.owner, p.name): a for p, a in zip(f.parameters, args, strict=False)}
        try:
            inside = all(self._ev(ctx, pre) is True for pre in f.preconditions)
            if inside and f.definition is not None:
                return self._ev(ctx, f.definition)
            if table is None:
                # Outside its preconditions the function is unconstrained (docs/semantics.md §6.4): any value.
                raise NotInterpretable(e.pos, f"{f.name} called outside its precondition")
            return self._open_call(ctx, e, f, table, tuple(args), inside)
        finally:
            ctx.bind = saved

    def _ev_recursion(self, ctx: _Ctx, e: ast.Call, name: str) -> Any:
        """A call of recursive function `name` past the calls its body unfolds: the function's body
        again, as RoboTool's CSP evaluates it, at most `MAX_RECURSION` times over."""
        if self._recursive is None:
            self._recursive = {f.qname: f for f in ast.parts(self.element, *self.defined.values())
                               if isinstance(f, ast.Function) and f.definition is not None}
        recursive = self._recursive.get(name)
        if recursive is None:  # pragma: no cover - the unfolding's function is in the model it came from
            raise NotInterpretable(e.pos, f"{name} called deeper than its unfolding")
        if self._recursing >= MAX_RECURSION:
            raise NotInterpretable(e.pos, f"{name} called more than {MAX_RECURSION} times its unfolding deep")
        self._recursing += 1
        try:
            return self._ev_call(ctx, dataclasses.replace(e, function=recursive))
        finally:
            self._recursing -= 1

    def _ev_result(self, ctx: _Ctx, e: ast.ResultRef) -> Any:
        if ctx.bind is not None and RESULT in ctx.bind:
            return ctx.bind[RESULT]
        raise NotInterpretable(e.pos, "result outside a postcondition")

    def _ev_seq(self, ctx: _Ctx, e: ast.SeqLiteral) -> Any:
        return _coerce(e.type, tuple(self._ev(ctx, x) for x in e.items))

    def _ev_set(self, ctx: _Ctx, e: ast.SetLiteral) -> Any:
        return _coerce(e.type, frozenset(self._ev(ctx, x) for x in e.items))

    def _ev_tuple(self, ctx: _Ctx, e: ast.TupleLiteral) -> Any:
        return _coerce(e.type, Product(self._ev(ctx, x) for x in e.items))

    def _ev_index(self, ctx: _Ctx, e: ast.Index) -> Any:
        v = self._ev(ctx, e.value)
        i = self._ev(ctx, e.index)
        if isinstance(v, Product):
            return v[i - 1]
        if not 1 <= i <= len(v):
            # Outside 1..#s an index has any value (as a function outside its precondition).
            raise NotInterpretable(e.pos, f"index {i} outside a sequence of length {len(v)}")
        return v[i - 1]

    def _ev_let(self, ctx: _Ctx, e: ast.Let) -> Any:
        value = self._ev(ctx, e.value)
        saved = ctx.bind
        ctx.bind = {**(saved or {}), (e.variable.owner, e.variable.name): value}
        try:
            return self._ev(ctx, e.body)
        finally:
            ctx.bind = saved

    def _closure(self, ctx: _Ctx, e: ast.Lambda) -> Closure:
        """A lambda's value: the values of the names it reads from outside, read now."""
        own = {(v.owner, v.name) for v in e.variables}
        bind: dict[tuple[str, str], object] = {}
        for x in ast.subexpressions((e.condition, e.body)):
            if not isinstance(x, ast.VarRef):
                continue
            var = x.variable
            key = (var.owner, var.name)
            if key in own or key in bind:
                continue
            if ctx.bind is not None and key in ctx.bind or var.kind not in ("bound", "let"):
                value = self._get(ctx, var)
                # Lazy mode: a value not chosen yet is chosen now (its configuration split), as a
                # closure hides it from the search for Unknowns in configurations.
                bind[key] = self._known(ctx, value) if self.lazy else value
            # else bound inside the body, by a let or a quantifier
        return Closure(e, tuple(sorted(bind.items(), key=lambda kv: kv[0])))

    def _apply(self, ctx: _Ctx, e: ast.Expr, f: object, args: list) -> object:
        """A function value applied to its arguments (several, or one tuple of a product domain)."""
        if isinstance(f, AnyFunction):
            raise NotInterpretable(e.pos, f"a function of type {f.type} that has no value is applied")
        if not isinstance(f, Closure):  # a function value taken from a BMC run (a replay's start)
            raise NotInterpretable(e.pos, "a function value the interpreter did not make is applied")
        t = f.fn.type
        assert isinstance(t, ast.FunctionType)
        point = _coerce(t.domain, args[0] if len(args) == 1 else Product(args))
        for key, value in reversed(f.overrides):
            if key == point:
                return value
        variables = f.fn.variables
        values = [point] if len(variables) == 1 else list(point)  # type: ignore[call-overload]
        saved = ctx.bind
        ctx.bind = {**dict(f.bind), **{(v.owner, v.name): _coerce(v.type, x) for v, x in zip(variables, values, strict=True)}}
        try:
            if f.fn.condition is not None and not self._ev(ctx, f.fn.condition):
                raise NotInterpretable(e.pos, "a lambda applied where its condition fails (any value)")
            result = _coerce(t.range, self._ev(ctx, f.fn.body))
        finally:
            ctx.bind = saved
        # BMC keeps a function's results in their type: the type the application has (a lambda's
        # own range may be wider than that of the place holding it: `nat -> nat = lambda x : nat @ x - 5`)
        expected = e.type if isinstance(e, ast.Apply) and e.type is not None else t.range
        if not _fits(t.range, result) or not _fits(expected, result):
            raise NotInterpretable(e.pos, f"a function's result {value_text(expected, result)} outside its type {expected}")
        return result

    def _comprehension(self, ctx: _Ctx, e: ast.SetComprehension) -> frozenset:
        """`{x : T | p @ t}`, by trying every value of the bound variables' types within the ranges."""
        domains = [self.domain(v.type) for v in e.variables]
        saved = ctx.bind
        out = set()
        try:
            for combo in itertools.product(*domains):
                ctx.bind = {**(saved or {}), **{(v.owner, v.name): x for v, x in zip(e.variables, combo, strict=True)}}
                if e.condition is not None and not self._ev(ctx, e.condition):
                    continue
                out.add(combo[0] if e.term is None else self._ev(ctx, e.term))
        finally:
            ctx.bind = saved
        return _coerce(e.type, frozenset(out))  # type: ignore[return-value]

    def _quantifier(self, ctx: _Ctx, e: ast.Quantifier) -> bool:
        """`forall`/`exists`/`exists1`, by trying every value of the bound variables' types within
        the ranges (a type without one is `Unbounded`: its values cannot be listed)."""
        domains = [self.domain(v.type) for v in e.variables]
        saved = ctx.bind
        found = 0
        try:
            for combo in itertools.product(*domains):
                ctx.bind = {**(saved or {}), **{(v.owner, v.name): x for v, x in zip(e.variables, combo, strict=True)}}
                if e.condition is not None and not self._ev(ctx, e.condition):
                    continue
                holds = bool(self._ev(ctx, e.body))
                if e.kind == "forall" and not holds:
                    return False
                if holds and e.kind != "forall":
                    found += 1
                    if e.kind == "exists" or found > 1:
                        return e.kind == "exists"
        finally:
            ctx.bind = saved
        return e.kind == "forall" or found == 1

    def _builtin(self, e: ast.Builtin, args: list) -> object:
        """A built-in operation on sequences and sets, on Python tuples and frozensets."""
        op, a = e.op, args[0]
        if op in ("in", "notin"):
            return (a in args[1]) == (op == "in")
        if op in ("head", "last"):
            if not a:
                raise NotInterpretable(e.pos, f"{op} of an empty sequence")
            return a[0] if op == "head" else a[-1]
        if op == "as":
            return _coerce(e.type, a)
        if op == "update":
            i, item = args[1], args[2]
            if not 1 <= i <= len(a):  # outside 1..#s the result is any sequence (BMC: uninterpreted)
                raise NotInterpretable(e.pos, f"item {i} assigned in a sequence of length {len(a)}")
            return a[:i - 1] + (item,) + a[i:]
        if op in ("min", "max"):
            if not a:  # outside the precondition hasMin(a): any value
                raise NotInterpretable(e.pos, f"{op} of an empty set")
            return min(a) if op == "min" else max(a)
        if op == "interval":
            lo, hi, closed_lo, closed_hi = args
            lo, hi = math.ceil(lo) + (0 if closed_lo or lo != math.ceil(lo) else 1), \
                math.floor(hi) - (0 if closed_hi or hi != math.floor(hi) else 1)
            if hi - lo >= MAX_COLLECTIONS:
                raise NotInterpretable(e.pos, f"a set of {hi - lo + 1} integers")
            return frozenset(range(lo, hi + 1))
        if op == "range":
            if args[1] - a >= MAX_COLLECTIONS:
                raise NotInterpretable(e.pos, f"a sequence of {args[1] - a + 1} integers")
            return tuple(range(a, args[1] + 1))
        if op == "override":
            b = args[1]
            if isinstance(a, AnyFunction):
                raise NotInterpretable(e.pos, f"a function of type {a.type} that has no value is overridden")
            if isinstance(a, Closure):
                if len({p[0] for p in b}) < len(b):  # not a function there: BMC takes the pair written last
                    raise NotInterpretable(e.pos, "override by a set that pairs one point with two values")
                pairs = tuple((p[0], p[1]) for p in sorted(b, key=repr))
                return Closure(a.fn, a.bind, a.overrides + pairs)
            keys = {p[0] for p in b}
            return frozenset(p for p in a if p[0] not in keys) | b
        simple: dict[str, Callable[[], object]] = {
            "size": lambda: len(a), "isNonEmpty": lambda: len(a) > 0, "tail": lambda: a[1:], "front": lambda: a[:-1],
            "reverse": lambda: a[::-1], "dom": lambda: frozenset(range(1, len(a) + 1)),
            "ran": lambda: frozenset(a), "elems": lambda: frozenset(a),
        }
        if op in simple:
            return simple[op]()
        b = args[1]
        pair: dict[str, Callable[[], object]] = {
            "concat": lambda: _coerce(e.type, a + b), "prefix": lambda: b[:len(a)] == a,
            "suffix": lambda: len(a) <= len(b) and b[len(b) - len(a):] == a,
            "infix": lambda: any(b[i:i + len(a)] == a for i in range(len(b) - len(a) + 1)),
            "symetric_diff": lambda: _coerce(e.type, a ^ b),
            "filter": lambda: tuple(x for x in a if x in b),
            "extract": lambda: tuple(x for i, x in enumerate(b, 1) if i in a),
            "union": lambda: _coerce(e.type, a | b), "inter": lambda: a & b, "diff": lambda: a - b,
            "subseteq": lambda: a <= b, "subset": lambda: a < b,
        }
        if op in pair:
            return pair[op]()
        raise NotInterpretable(e.pos, f"the operation {op}")

    def _eval_ref(self, ctx: _Ctx, e: ast.Expr) -> Any:
        """`e`'s value, which may hold Unknowns when `e` only names a variable or one of its fields
        (lazy mode: what goes out on a visible event as it is, or a record whose field is read)."""
        if isinstance(e, ast.VarRef):
            return self._get(ctx, e.variable)
        if isinstance(e, ast.FieldRef):
            r = self._eval_ref(ctx, e.record)
            v = r.get(e.field_name) if isinstance(r, dict) else None
            if v is None:
                raise NotInterpretable(e.pos, f"field {e.field_name} has no value")
            return v
        return self._eval(ctx, e)

    def _since_slot(self, ctx: _Ctx, e: ast.SinceEntry) -> int:
        for key in (k for k in self._slot_of if k[0] == "since" and k[1] == ctx.i and k[3] == e.state):
            return self._slot_of[key]
        raise NotInterpretable(e.pos, f"sinceEntry({e.state})")

    def _truth(self, ctx: _Ctx, e: ast.Expr | None) -> bool:
        return True if e is None else bool(self._eval(ctx, e))

    def _assign(self, ctx: _Ctx, var: ast.Variable, fields: tuple[str, ...], value: object,
                visible: bool = False) -> bool:
        """Store `value` in `var` (or one of its fields); False if a nat place would go negative, or
        if the memory of a shared variable is still passing a write on. `visible`: the step is the
        visible write of a shared variable (RoboTool's `set_x`)."""
        slot = self._slot(ctx.i, var)
        t = var.type
        if fields:
            old = ctx.get(slot)
            if not isinstance(old, dict):
                raise NotInterpretable(var.pos, f"a field of {var.name}, which has no value")

            def put(rec: dict, rt: ast.Type, path: tuple[str, ...]) -> Record:
                ft = rt.field_type(path[0]) if isinstance(rt, ast.RecordType) else None
                if len(path) == 1:
                    v = _coerce(ft, value)
                else:
                    v = put(rec[path[0]], ft, path[1:])  # type: ignore[arg-type]
                return Record(rec).with_field(path[0], v)

            value = put(old, t, fields)
        value = _coerce(t, value)
        if not _fits(t, value):
            return False
        ctx.set(slot, value)
        cp = self._copy_slot.get(slot)
        if cp is not None:
            if cp.written is not None and not visible:
                raise NotInterpretable(var.pos, f"an input into variable {var.name}, whose writes are visible as "
                                                f"RoboTool's {cp.written}")
            if cp.passes_writes and cp.mem is not None:
                # the memory takes the write once it has passed the last one on, and passes it on
                if ctx.get(cp.mem) is not None:
                    return False
                self._concrete(value)
                ctx.set(cp.mem, (value, 0))
        return True

    # ------------------------------------------------------------------ configurations

    def _match(self, table: dict, info: _Slot) -> tuple[bool, object]:
        if info.var is None:
            return False, None
        names = [info.display, info.var.name]
        if info.inst is not None and self.network:  # this instance's own value first (model/config.py)
            names.insert(0, instance_key(tuple(self.insts[info.inst].local.split(".")), info.var))
        if info.inst is not None:
            m = self.insts[info.inst]
            names += [f"{m.name}::{info.var.name}", f"{m.machine.qname}::{info.var.name}",
                      f"{m.local}.{info.var.name}"]
        names.append(f"{info.var.owner}::{info.var.name}")
        for n in names:
            if n in table:
                return True, table[n]
        return False, None

    def initial(self, choices: dict[str, object] | None = None) -> list[Config]:
        """Every initial configuration: one per choice of the constants without a value and the
        variables without an initial value (over their ranges, or from `choices`)."""
        return list(self.initial_configs(choices))

    def initial_configs(self, choices: dict[str, object] | None = None) -> Iterator[Config]:
        """`initial`'s configurations one at a time (a search may stop before there are millions)."""
        choices = choices or {}
        base: list[object] = [None] * len(self.slots)
        open_slots: list[tuple[int, ast.Type, tuple[str, ...]]] = []
        deferred: list[tuple[int, _Slot]] = []
        for s, info in enumerate(self.slots):
            if info.kind in ("clock", "since", "tdl"):
                base[s] = 0
            elif info.kind == "fun":
                base[s] = ()  # no point chosen yet
            elif info.kind in ("var", "const"):
                var = info.var
                assert var is not None
                found, val = self._match(self.settings, info) if info.kind == "const" else (False, None)
                if not found:
                    found, val = self._match(choices, info)
                if found:
                    base[s] = _coerce(var.type, val)
                    if not _fits(var.type, base[s]):  # `with constant K set to -1` of a nat K: no run starts
                        return
                elif self._start(info) is not None:
                    deferred.append((s, info))
                    if isinstance(var.initial, ast.RecordLiteral) and var.initial.omitted:
                        # the omitted fields are open (a record of those only), the given ones set after
                        assert isinstance(var.type, ast.RecordType)
                        partial = ast.RecordType(var.type.qname, var.initial.omitted)
                        open_slots.append((s, partial, self._paths_of(info)))
                else:
                    open_slots.append((s, var.type, self._paths_of(info)))
        # constants first, then variables, each in declaration order
        deferred.sort(key=lambda x: 0 if x[1].kind == "const" else 1)
        frames = tuple((Frame(inst.beh, self.behs[inst.beh].initial[None], (), False, (), (), None),)
                       for inst in self.insts)
        seen: set[Config] = set()
        todo: list[tuple] = []
        if self.lazy:  # one combination of Unknowns, split where an initial value or a deadline reads one
            fresh = [self._fresh(t, p) for _, t, p in open_slots]
            if any(not f for f in fresh):
                return
            todo = [tuple(f[0] for f in fresh)]
            combos: Iterable[tuple] = _worklist(todo)
        elif self.sampler is None:
            combos = itertools.product(*(self.domain(t, p) for _, t, p in open_slots))
        else:  # a random run needs one: draw them until the initial values fit, a bounded number of times
            if any(self._size(t, p) == 0 for _, t, p in open_slots):
                return
            combos = (tuple(self._draw(t, p) for _, t, p in open_slots) for _ in range(self.sampler.size))
        for combo in combos:
            try:
                c = self._initial_config(base, frames, open_slots, deferred, combo)
            except NeedValue as nv:
                k = next((k for k, v in enumerate(combo) if _holds(v, nv.unknown)), None)
                if k is None:
                    raise
                todo.extend(combo[:k] + (_replace(combo[k], nv.unknown, x),) + combo[k + 1:]
                            for x in reversed(nv.unknown.values))
                continue
            if c is not None and c not in seen:
                seen.add(c)
                yield c
                if self.sampler is not None:
                    break

    def _initial_config(self, base: list, frames: tuple, open_slots: list, deferred: list,
                        combo: tuple) -> Config | None:
        store = list(base)
        for (s, _, _), v in zip(open_slots, combo, strict=True):
            store[s] = v
        for s, info in deferred:
            ctx = _Ctx(tuple(store), info.inst if info.inst is not None else 0)
            init = self._start(info)
            assert info.var is not None and init is not None
            if ast.omits_fields(init):
                assert isinstance(init, ast.RecordLiteral)
                given = {n: self._eval(ctx, x) for n, x in init.fields}
                v = _coerce(info.var.type, Record({**store[s], **given}))  # type: ignore[dict-item]
            else:
                v = _coerce(info.var.type, self._eval(ctx, init))
            if not _fits(info.var.type, v):
                return None
            store[s] = v
        for cp in self.copies:  # a memory passes the model's initial value on at the start
            if cp.start is not None and cp.mem is not None:
                v = _coerce(cp.decl.type, self._eval(_Ctx(tuple(store), cp.readers[0]), cp.start))
                if not _fits(cp.decl.type, v):
                    return None
                store[cp.mem] = (v, 0)
        return Config(frames, self._fix_deadlines(frames, tuple(store)), False)

    def _paths_of(self, info: _Slot) -> tuple[str, ...]:
        assert info.var is not None
        paths = [info.display]
        if info.inst is not None:
            m = self.insts[info.inst]
            paths += [f"{m.name}::{info.var.name}", f"{m.machine.qname}::{info.var.name}"]
        paths.append(f"{info.var.owner}::{info.var.name}")
        return tuple(dict.fromkeys(paths))

    def terminated(self, config: Config) -> bool:
        return config.done

    def states(self, config: Config) -> dict[str, str]:
        out = {}
        for inst, frames in zip(self.insts, config.machines, strict=True):
            if config.done:
                out[inst.name] = "terminated"
                continue
            parts = []
            for k, f in enumerate(frames):
                d = f"taking {f.via}" if f.via else (f.node or "?")
                if k > 0:
                    d = f"{self.behs[f.beh].b.name}(): {d}"
                if f.bg:
                    d += f" ∥ {f.bg_of}: during" + "".join(f" / {self.behs[g.beh].b.name}(): {g.node or '?'}"
                                                         for g in f.bg[1:])
                parts.append(d)
            out[inst.name] = " / ".join(parts)
        return out

    def variables(self, config: Config) -> dict[str, object]:
        return {info.display: config.store[s] for s, info in enumerate(self.slots)
                if info.kind in ("var", "oplocal") and config.store[s] is not None}

    # ------------------------------------------------------------------ one machine

    def _norm(self, ctx: _Ctx, frames: list[Frame]) -> tuple:
        """Run the bookkeeping instructions of the top frame (no step); returns the frames."""
        while True:
            f = frames[-1]
            beh = self.behs[f.beh]
            if not f.cont:
                if f.intr:
                    frames[-1] = f = f._replace(intr=False)
                if len(frames) > 1 and f.via is None and f.node is not None:
                    node = beh.nodes[f.node]
                    if node.kind == "final" and node.parent is None:
                        frames.pop()
                        continue
                break
            head = f.cont[0]
            rest = f.cont[1:]
            tag = head[0]
            if tag == "s":
                st = self.stmts[head[1]]
                if isinstance(st, ast.Seq):
                    frames[-1] = f._replace(cont=tuple(("s", self._sid_of(s)) for s in st.statements) + rest)
                elif isinstance(st, ast.Skip):
                    frames[-1] = f._replace(cont=rest)
                elif isinstance(st, ast.Deadline):
                    bound = self._eval(ctx, st.bound)
                    frames[-1] = f._replace(cont=(("s", self._sid_of(st.statement)), ("d",)) + rest,
                                            dls=(*f.dls, int(bound)))
                else:
                    break
            elif tag == "d":
                frames[-1] = f._replace(cont=rest, dls=f.dls[:-1])
            elif tag == "w":
                if head[1] > 0:
                    break
                frames[-1] = f._replace(cont=rest)
            elif tag == "x":
                node = beh.nodes[head[1]]
                pre = (("s", self._sid_of(node.exit)),) if node.kind == "state" and node.exit is not None else ()
                frames[-1] = f._replace(cont=(*pre, ("l", head[1]), *rest))
            elif tag == "l":
                frames[-1] = f._replace(node=beh.nodes[head[1]].parent, cont=rest)
            elif tag == "e":
                path = head[1]
                node = beh.nodes[path]
                pre = (("s", self._sid_of(node.entry)),) if node.kind == "state" and node.entry is not None else ()
                frames[-1] = f._replace(node=path, cont=(*pre, *rest), via=None)
            elif tag == "a":
                target, durs, entering = head[1], head[2], head[3]
                node = beh.nodes[target]
                if node.kind == "state" and node.children:
                    frames[-1] = f._replace(node=beh.initial[target], cont=rest, pend=durs, via=None,
                                            entering=entering)
                    continue
                # Every state entered on the way here now is: sinceEntry counts from here (RoboTool's `S::entered`).
                for p in entering:
                    slot = self._slot_of.get(("since", ctx.i, f.beh, p))
                    if slot is not None:
                        ctx.set(slot, 0)
                f = frames[-1] = f._replace(entering=())
                if node.kind == "state" or (node.kind == "final" and node.parent is not None):
                    active = set(beh.ancestors(target))
                    cont = tuple(("s", self._sid_of(d)) for p in durs
                                 if p in active and not beh.nodes[p].composite and (d := beh.nodes[p].during) is not None)
                    frames[-1] = f = f._replace(node=target, cont=cont + rest, intr=bool(cont), pend=(), via=None,
                                                dls=())
                    # A composite state entered on the way starts its during action beside its children.
                    for p in durs:
                        during = beh.nodes[p].during
                        if p in active and beh.nodes[p].composite and during is not None:
                            start = Frame(f.beh, None, (("s", self._sid_of(during)),), False, (), (), None)
                            frames[-1] = f._replace(bg=self._norm(ctx, [start]), bg_of=p)
                else:
                    frames[-1] = f._replace(node=target, cont=rest, pend=durs, via=None)
            else:  # pragma: no cover
                raise AssertionError(head)
        return tuple(frames)

    def _result(self, ctx: _Ctx, frames: list[Frame]) -> tuple[tuple, dict]:
        return self._norm(ctx, frames), ctx.upd

    def _else_holds(self, ctx: _Ctx, beh: _Beh, t: ast.Transition) -> bool:
        for o in beh.out.get(t.source, ()):
            if o is t or o.is_else or (o.trigger is not None and o.trigger.kind == "input"):
                continue
            if self._truth(ctx, o.condition):
                return False
        return True

    def _guard(self, ctx: _Ctx, beh: _Beh, t: ast.Transition) -> bool:
        return self._else_holds(ctx, beh, t) if t.is_else else self._truth(ctx, t.condition)

    def _take(self, ctx: _Ctx, frames: tuple, k: int, t: ast.Transition) -> tuple[tuple, dict]:
        f = frames[k]
        beh = self.behs[f.beh]
        for c in t.clock_resets:
            ctx.set(self._slot_of[("clk", ctx.i, c.name)], 0)
        exits, enters = beh.path(f.node, t.source, t.target)  # type: ignore[arg-type]
        # Leaving a state (a self-transition included) restarts its transitions' deadlines (docs/semantics.md §4.6).
        for slot, bi, dt in self._tdl.get(ctx.i, ()):
            if bi == f.beh and dt.source in exits:
                ctx.set(slot, 0)
        durs = f.pend + tuple(p for p in enters if beh.nodes[p].during is not None)
        cont = (*(("x", p) for p in exits),
                *((("s", self._sid_of(t.action)),) if t.action is not None else ()),
                *(("e", p) for p in enters),
                ("a", t.target, durs, (*f.entering, *enters)))
        kept = f.bg_of is not None and f.bg_of not in exits  # a transition leaving `bg_of` abandons its during
        nf = Frame(f.beh, f.node, cont, False, (), (), t.name, (), f.bg if kept else (), f.bg_of if kept else None)
        return self._result(ctx, [*frames[:k], nf])

    def _moves(self, cfg: Config, i: int) -> list[tuple]:
        """The moves machine `i` offers: ("tau", note, result), ("out", port, type, value, result),
        ("in", port, type, acceptor), ("call", name, params, args, result), ("term", result)."""
        frames = cfg.machines[i]
        out: list[tuple] = []
        top = len(frames) - 1
        if frames[top].cont:
            self._instr_moves(cfg, i, frames, out)
        for k in range(top, -1, -1):
            f = frames[k]
            if (k == top and not f.cont) or f.intr:
                self._transition_moves(cfg, i, frames, k, out)
            if f.bg:
                self._during_moves(cfg, i, frames, k, out)
        return out

    def _during_moves(self, cfg: Config, i: int, frames: tuple, k: int, out: list) -> None:
        """The moves of the during action running beside frame `k`'s children (`Frame.bg`): those of
        its own activations, each leaving the children's where they are."""
        bg = frames[k].bg
        inner: list[tuple] = []
        if bg[-1].cont:
            self._instr_moves(cfg, i, bg, inner)
        for kk in range(len(bg) - 1, -1, -1):
            g = bg[kk]
            if (kk == len(bg) - 1 and not g.cont) or g.intr:
                self._transition_moves(cfg, i, bg, kk, inner)

        def lift(result: tuple) -> tuple:
            thread, upd = result
            return (*frames[:k], self._with_during(frames[k], thread), *frames[k + 1:]), upd

        for m in inner:
            if m[0] == "in":
                accept = m[3]
                out.append((*m[:3], lambda v, accept=accept: [(note, lift(r)) for note, r in accept(v)]))
            else:
                out.append((*m[:-1], lift(m[-1])))

    @staticmethod
    def _with_during(f: Frame, thread: tuple) -> Frame:
        """Frame `f` with its during action's activations now `thread` (none once it has ended)."""
        done = len(thread) == 1 and not thread[0].cont
        return f._replace(bg=(), bg_of=None) if done else f._replace(bg=thread)

    def _transition_moves(self, cfg: Config, i: int, frames: tuple, k: int, out: list) -> None:
        f = frames[k]
        beh = self.behs[f.beh]
        if f.node is None:
            return
        node = beh.nodes[f.node]
        if node.kind == "final" and node.parent is None:
            if k == 0:
                out.append(("term", (frames, {})))
            return
        mname = self.insts[i].name
        for t in beh.candidates(f.node):
            trig = t.trigger
            note = f"{mname}: transition {t.name}"
            if trig is None:
                ctx = _Ctx(cfg.store, i)
                if self._guard(ctx, beh, t):
                    out.append(("tau", note, self._take(ctx, frames, k, t)))
            elif trig.kind == "output":
                ctx = _Ctx(cfg.store, i)
                if self._guard(ctx, beh, t):
                    etype = trig.event.type
                    v = _coerce(etype, self._eval_ref(ctx, trig.value)) if trig.value is not None else None
                    if etype is not None and v is None:
                        raise NotInterpretable(t.pos, "an output without a value on a typed event")
                    out.append(("out", trig.event.name, etype, v, self._take(ctx, frames, k, t)))
            else:
                out.append(("in", trig.event.name, trig.event.type,
                            self._trigger_acceptor(cfg, i, frames, k, t, note)))

    def _trigger_acceptor(self, cfg: Config, i: int, frames: tuple, k: int, t: ast.Transition, note: str):
        beh = self.behs[frames[k].beh]
        trig = t.trigger
        assert trig is not None

        def accept(v: object) -> list[tuple[str, tuple]]:
            ctx = _Ctx(cfg.store, i)
            if trig.kind == "input" and trig.variable is not None:
                if not self._assign(ctx, trig.variable, (), v):
                    return []
            elif trig.kind == "sync" and trig.value is not None:
                u = _unknown_in(v)
                if u is not None:
                    raise NeedValue(u)
                if _coerce(trig.event.type, self._eval(ctx, trig.value)) != v:
                    return []
            if not self._guard(ctx, beh, t):
                return []
            return [(note, self._take(ctx, frames, k, t))]

        return accept

    def _instr_moves(self, cfg: Config, i: int, frames: tuple, out: list) -> None:
        f = frames[-1]
        head = f.cont[0]
        if head[0] != "s":
            return  # waiting
        st = self.stmts[head[1]]
        rest = f.cont[1:]
        mname = self.insts[i].name
        done = [*frames[:-1], f._replace(cont=rest)]
        if isinstance(st, ast.Assign):
            ctx = _Ctx(cfg.store, i)
            v = self._eval(ctx, st.value)
            cp = self._copy_slot.get(self._slot(i, st.variable))
            if self._assign(ctx, st.variable, st.fields, v, visible=True):
                target = ".".join((st.variable.name, *st.fields))
                if cp is not None and cp.written is not None:  # RoboTool's visible `set_x`: the whole variable
                    out.append(("set", cp.written, ctx.get(self._slot(i, st.variable)), self._result(ctx, done)))
                else:
                    out.append(("tau", f"{mname}: {target} := {value_text(st.value.type, _coerce(st.value.type, v))}",
                                self._result(ctx, done)))
        elif isinstance(st, ast.Send):
            ctx = _Ctx(cfg.store, i)
            etype = st.event.type
            v = _coerce(etype, self._eval_ref(ctx, st.value)) if st.value is not None else None
            if etype is not None and v is None:
                raise NotInterpretable(st.pos, "an output without a value on a typed event")
            out.append(("out", st.event.name, etype, v, self._result(ctx, done)))
        elif isinstance(st, ast.Receive):
            var = st.variable

            def accept(v: object) -> list[tuple[str, tuple]]:
                ctx = _Ctx(cfg.store, i)
                if var is not None and not self._assign(ctx, var, (), v):
                    return []
                return [(f"{mname}: receive {st.event.name}", self._result(ctx, list(done)))]

            out.append(("in", st.event.name, st.event.type, accept))
        elif isinstance(st, ast.OperationCall):
            ctx = _Ctx(cfg.store, i)
            d = self._resolve_call(i, st, self.behs[f.beh].b)
            if d is None:
                params = st.operation.parameters
                args = tuple(_coerce(p.type, self._eval_ref(ctx, a)) for p, a in zip(params, st.args, strict=False))
                out.append(("call", st.operation.name, params, args, self._result(ctx, done)))
            else:
                self._call_defined(cfg, i, ctx, d, st, done, out)
        elif isinstance(st, ast.If):
            ctx = _Ctx(cfg.store, i)
            branch = st.then if self._truth(ctx, st.condition) else st.otherwise
            nf = f._replace(cont=(("s", self._sid_of(branch)), *rest))
            out.append(("tau", f"{mname}: if", self._result(ctx, [*frames[:-1], nf])))
        elif isinstance(st, ast.Wait):
            ctx = _Ctx(cfg.store, i)
            lo = self._eval(ctx, st.low)
            hi = self._eval(ctx, st.high)
            first, last = math.ceil(lo), math.floor(hi)
            durations: Iterable[int] = range(first, last + 1)
            if self.sampler is not None and last - first + 1 > self.sampler.size:
                durations = sorted({self.sampler.rng.randint(first, last) for _ in range(self.sampler.size)})
            for n in durations:
                c2 = _Ctx(cfg.store, i)
                nf = f._replace(cont=(("w", n), *rest))
                out.append(("tau", f"{mname}: wait({n})", self._result(c2, [*frames[:-1], nf])))
        elif isinstance(st, ast.ClockReset):
            ctx = _Ctx(cfg.store, i)
            ctx.set(self._slot_of[("clk", i, st.clock.name)], 0)
            out.append(("tau", f"{mname}: #{st.clock.name}", self._result(ctx, done)))
        else:
            raise NotInterpretable(st.pos, st.what if isinstance(st, ast.UnsupportedStmt) else
                                   f"the statement {type(st).__name__}")

    def _call_defined(self, cfg: Config, i: int, ctx: _Ctx, d: ast.OperationDef, st: ast.OperationCall,
                      done: list, out: list) -> None:
        bi = self._beh(d, True)
        args = [_coerce(p.type, self._eval(ctx, a)) for p, a in zip(d.parameters, st.args, strict=False)]
        if not all(_fits(p.type, a) for p, a in zip(d.parameters, args, strict=False)):
            return  # a nat parameter given a negative value: the call cannot be made (as BMC's `fits`)
        for p, a in zip(d.parameters, args, strict=False):
            ctx.set(self._slot(i, p), a)
        locals_ = [v for v in d.variables if not v.constant]  # constants are set once, like the machine's
        fixed = [(v, None) for v in locals_ if v.initial is not None]
        free = [v for v in locals_ if v.initial is None]
        paths = [(f"{self.insts[i].name}.{d.name}().{v.name}", f"{d.qname}::{v.name}") for v in free]
        combos: Iterable[tuple]
        if self.sampler is not None and math.prod(self._size(v.type, p) for v, p in zip(free, paths)) > self.sampler.size:
            combos = [tuple(self._draw(v.type, p) for v, p in zip(free, paths)) for _ in range(self.sampler.size)]
        else:
            combos = itertools.product(*(self.domain(v.type, p) for v, p in zip(free, paths)))
        for combo in combos:
            c2 = _Ctx(cfg.store, i, ctx.upd)
            for v, val in zip(free, combo, strict=True):
                c2.set(self._slot(i, v), val)
            for v, _ in fixed:
                assert v.initial is not None
                if not self._assign(c2, v, (), self._eval(c2, v.initial)):
                    break
            else:
                nf = Frame(bi, self.behs[bi].initial[None], (), False, (), (), None)
                text = ", ".join(value_text(p.type, a) for p, a in zip(d.parameters, args, strict=False))
                out.append(("tau", f"{self.insts[i].name}: call {d.name}({text})",
                            self._result(c2, [*done, nf])))

    # ------------------------------------------------------------------ deadlines

    def _armed(self, machines: tuple, store: tuple, i: int) -> dict[int, tuple[bool, int]]:
        res: dict[int, tuple[bool, int]] = {}
        frames = machines[i]
        top = len(frames) - 1
        active: dict[int, int] = {f.beh: k for k, f in enumerate(frames)}
        for s, bi, t in self._tdl.get(i, ()):
            ctx = _Ctx(store, i)
            bound = int(self._eval(ctx, t.deadline))  # type: ignore[arg-type]
            armed = False
            k = active.get(bi)
            if k is not None:
                f = frames[k]
                beh = self.behs[bi]
                if ((k == top and not f.cont) or f.intr) and f.node is not None \
                        and t.source in beh.ancestors(f.node):
                    armed = self._could_fire(ctx, beh, t)
            res[s] = (armed, bound)
        return res

    def _could_fire(self, ctx: _Ctx, beh: _Beh, t: ast.Transition) -> bool:
        trig = t.trigger
        if trig is not None and trig.kind == "input" and trig.variable is not None:
            var = trig.variable
            for v in self._choices(trig.event.type, (), limit=4096):
                c2 = _Ctx(ctx.base, ctx.i)
                if self._assign(c2, var, (), v) and self._guard(c2, beh, t):
                    return True
            return False
        return self._guard(ctx, beh, t)

    def _fix_deadlines(self, machines: tuple, store: tuple) -> tuple:
        """Trigger-deadline counters of transitions that are not armed are 0."""
        if not self._tdl:
            return store
        st = None
        for i in self._tdl:
            for s, (armed, _) in self._armed(machines, store, i).items():
                if not armed and store[s] != 0:
                    if st is None:
                        st = list(store)
                    st[s] = 0
        return tuple(st) if st is not None else store

    # ------------------------------------------------------------------ the network

    def _dead_at_rest(self) -> dict[tuple[int, str], tuple[int, ...]]:
        out: dict[tuple[int, str], tuple[int, ...]] = {}
        for i, inst in enumerate(self.insts):
            beh = self.behs[inst.beh]
            if not liveness.analysable(beh.b, partial(self._runs_defined, i)):
                continue
            slots = {liveness.key(v): self._slot_of[k] for v in beh.b.variables if not v.constant
                     if (k := ("v", i, v.owner, v.name)) in self._slot_of}
            for path, dead in liveness.dead_at_rest(beh, [v for v in beh.b.variables if liveness.key(v) in slots]).items():
                if dead:
                    out[(i, path)] = tuple(sorted(slots[d] for d in dead))
        return out

    def _runs_defined(self, i: int, st: ast.OperationCall) -> bool:
        return self._resolve_call(i, st) is not None

    def _config(self, cfg: Config, changes: list[tuple[int, tuple, dict]], extra: dict | None = None,
                done: bool = False) -> Config:
        machines = list(cfg.machines)
        store = list(cfg.store)
        for i, frames, upd in changes:
            machines[i] = frames
            for s, v in upd.items():
                store[s] = v
            if self._dead and len(frames) == 1:
                f = frames[0]
                if not (f.cont or f.via or f.entering or f.bg or f.pend):
                    for s in self._dead.get((i, f.node), ()):  # type: ignore[arg-type]
                        store[s] = liveness.DEAD
        if extra:
            for s, v in extra.items():
                store[s] = v
        m = tuple(machines)
        return Config(m, self._fix_deadlines(m, tuple(store)), done)

    def _event(self, base: str, direction: str | None, t: ast.Type | None, v: object) -> Event:
        if direction is None:
            return Event(base, (base,), ())
        if t is None:
            return Event(f"{base}.{direction}", (base, direction), ())
        return Event(None, (base, direction), (v,))

    def _inputs_for(self, base: str, t: ast.Type | None, paths: tuple[str, ...],
                    inputs: Mapping[tuple, tuple] | None, channel: tuple | None = None) -> list:
        ch = channel or (base, "in")
        if inputs and ch in inputs:
            given = inputs[ch]
            if t is None:
                return [None]
            if given == ():  # no value offered on this channel
                return []
            return [_coerce(t, given[0] if isinstance(given, tuple) else given)]
        if inputs is not None:  # values given for some channels (replay): the others offer their range if any
            try:
                return self.domain(t, paths)
            except Unbounded:
                return []
        if self.lazy and ch not in self.strict:
            return self._fresh(t, paths)
        return self._choices(t, paths)

    def _each(self, values: list, make: Callable[[object], list[Step]]) -> list[Step]:
        """The steps `make(v)` for each input value `v`; where one reads an Unknown of `v` (lazy
        mode), those of each value it stands for instead."""
        out: list[Step] = []
        todo = list(reversed(values))
        while todo:
            v = todo.pop()
            try:
                out.extend(make(v))
            except NeedValue as nv:
                if not _holds(v, nv.unknown):
                    raise
                todo.extend(_replace(v, nv.unknown, x) for x in reversed(nv.unknown.values))
        return out

    def _concrete(self, v: object, channel: tuple | None = None) -> None:
        """Lazy mode: `v` is copied into the configuration, or shown on a channel in `strict`
        (`channel` given), so its Unknowns must be chosen first."""
        if self.lazy and (channel is None or channel in self.strict):
            u = _unknown_in(v)
            if u is not None:
                raise NeedValue(u)

    def private_steps(self, config: Config) -> tuple[list[Step] | None, dict[int, list[tuple]]]:
        """The internal steps of the first machine that can take only internal steps, each of which
        reads and writes only the machine's own configuration and store, or None; with the moves
        computed on the way (for `steps`).

        Such steps commute with every step of the rest of the network, and none of the rest can
        disable them (the machine's part of the configuration changes only by its own steps), nor
        can tock pass while they are possible (internal steps are urgent). Taking them first loses
        no visible trace, no stable configuration and its refusals, and no divergence: an ample set
        of partial-order reduction (conditions C0-C2; the search keeps C3, the cycle proviso)."""
        known: dict[int, list[tuple]] = {}
        if config.done:
            return None, known
        for i in self._private:
            ms = known[i] = self._moves(config, i)
            if ms and all(m[0] == "tau" for m in ms):
                return [Step("internal", None, self._config(config, [(i, frames, upd)]), note)
                        for _, note, (frames, upd) in ms], known
        return None, known

    def steps(self, config: Config, inputs: Mapping[tuple, tuple] | None = None,
              known: dict[int, list[tuple]] | None = None) -> list[Step]:
        """Every step possible from `config` (docs/semantics.md §3.2); `known`: moves of some
        machines, already computed for this configuration."""
        if config.done:
            return []
        n = len(self.insts)
        moves = [known[i] if known and i in known else self._moves(config, i) for i in range(n)]
        steps: list[Step] = []
        urgent = False
        # receivers of synchronous machine-to-machine links, by port
        ins_by_port: dict[tuple, list] = defaultdict(list)
        for i, ms in enumerate(moves):
            for m in ms:
                if m[0] == "in":
                    ins_by_port[(i, m[1])].append(m)
        for i, ms in enumerate(moves):
            mname = self.insts[i].name
            for m in ms:
                kind = m[0]
                if kind == "tau":
                    _, note, (frames, upd) = m
                    steps.append(Step("internal", None, self._config(config, [(i, frames, upd)]), note))
                elif kind == "call":
                    _, opname, params, args, (frames, upd) = m
                    base = f"{self.ename}::{opname}Call"
                    self._concrete(tuple(args), (base,))
                    urgent = True
                    steps.append(Step("event", Event(None if args else base, (base,), tuple(args)),
                                      self._config(config, [(i, frames, upd)])))
                elif kind == "term":
                    continue  # the element's terminate: every machine at once, below
                elif kind == "set":  # urgent, as RoboTool's `prioritise(…, <visible memory events, {tock}>)`
                    _, base, v, (frames, upd) = m
                    self._concrete(v, (base,))
                    urgent = True
                    steps.append(Step("event", Event(None, (base,), (v,)), self._config(config, [(i, frames, upd)])))
                elif kind == "out":
                    _, port, t, v, (frames, upd) = m
                    link = self.out_link.get((i, port))
                    if link is None or (link.dst is None and not link.asynchronous):
                        base = link.vis if link is not None and link.vis is not None else f"{mname}::{port}"
                        self._concrete(v, (base, "out"))
                        steps.append(Step("event", self._event(base, "out", t, v),
                                          self._config(config, [(i, frames, upd)])))
                    elif link.asynchronous:
                        assert link.slot is not None
                        self._concrete(v)
                        steps.append(Step("internal", None,
                                          self._config(config, [(i, frames, upd)], {link.slot: (v,)}),
                                          f"{mname}: {port} into buffer"))
                    else:
                        assert link.dst is not None
                        j, q = link.dst
                        self._concrete(v)
                        for rm in ins_by_port.get((j, q), ()):
                            for _note, (rframes, rupd) in rm[3](v):
                                merged = dict(upd)
                                merged.update(rupd)
                                steps.append(Step("internal", None,
                                                  self._config(config, [(i, frames, {}), (j, rframes, merged)]),
                                                  f"{mname}.{port} to {self.insts[j].name}.{q}"
                                                  + ("" if t is None else f" ({value_text(t, v)})")))
                elif kind == "in":
                    _, port, t, accept = m
                    links = self.in_links.get((i, port), [])
                    if not links:
                        base = f"{mname}::{port}"
                        steps += self._each(
                            self._inputs_for(base, t, (base, f"{self.insts[i].machine.qname}::{port}"), inputs),
                            lambda v, base=base, t=t, accept=accept, i=i: [  # type: ignore[misc]
                                Step("event", self._event(base, "in", t, v), self._config(config, [(i, frames, upd)]))
                                for _note, (frames, upd) in accept(v)])
                    for link in links:
                        if link.asynchronous:
                            assert link.slot is not None
                            buf = config.store[link.slot]
                            if buf is None:
                                continue
                            for note, (frames, upd) in accept(buf[0]):
                                steps.append(Step("internal", None,
                                                  self._config(config, [(i, frames, upd)], {link.slot: None}),
                                                  f"{note} ({port} from buffer)"))
                        elif link.src is None:
                            assert link.vis is not None
                            steps += self._each(
                                self._inputs_for(link.vis, t, (link.vis, f"{mname}::{port}"), inputs),
                                lambda v, vis=link.vis, t=t, accept=accept, i=i: [  # type: ignore[misc]
                                    Step("event", self._event(vis, "in", t, v), self._config(config, [(i, frames, upd)]))
                                    for _note, (frames, upd) in accept(v)])
        steps += self._terminations(config, moves)
        # the environment's side of asynchronous links
        for link in self.links:
            if not link.asynchronous or link.vis is None:
                continue
            assert link.slot is not None
            if link.src is None:
                assert link.dst is not None
                j, q = link.dst
                for v in self._inputs_for(link.vis, link.type, (link.vis, f"{self.insts[j].name}::{q}"), inputs):
                    steps.append(Step("event", self._event(link.vis, "in", link.type, v),
                                      self._config(config, [], {link.slot: (v,)})))
            elif link.dst is None:
                buf = config.store[link.slot]
                if buf is not None:
                    self._concrete(buf[0], (link.vis, "out"))
                    steps.append(Step("event", self._event(link.vis, "out", link.type, buf[0]),
                                      self._config(config, [], {link.slot: None})))
        steps += self._memory_steps(config, inputs)
        tock = self._tock(config, steps, urgent) if self.timed else None
        if tock is not None:
            steps.append(Step("tock", TOCK, tock))
        return steps

    def _memory_steps(self, config: Config, inputs: Mapping[tuple, tuple] | None) -> list[Step]:
        """RoboTool's memory model: a memory passes the value it holds on to its next copy (an
        internal step), and the environment writes a variable it can write (`C::set_EXT_x.v`)."""
        steps: list[Step] = []
        for cp in self.copies:
            held = config.store[cp.mem] if cp.mem is not None else None
            if held is not None:
                v, j = held
                self._concrete(v)  # passed on, it is copied: an Unknown is chosen first (lazy mode)
                reader = cp.readers[j]
                after = (v, j + 1) if j + 1 < len(cp.readers) else None
                steps.append(Step("internal", None,
                                  self._config(config, [], {self._slot(reader, cp.decl): v, cp.mem: after}),  # type: ignore[dict-item]
                                  f"{cp.name} passed on to {self.insts[reader].name}'s copy"))
            if cp.external is None or held is not None:
                continue
            paths = (cp.external, *(f"{self.insts[r].name}::{cp.name}" for r in cp.readers), f"{cp.decl.owner}::{cp.name}")
            steps += self._each(self._inputs_for(cp.external, cp.decl.type, paths, inputs, (cp.external,)),
                                partial(self._written, config, cp))
        return steps

    def _written(self, config: Config, cp: _Copies, v: object) -> list[Step]:
        """The environment's write of `v` into a variable it can write (`C::set_EXT_x.v`): none
        where `v` does not fit the variable's type."""
        v = _coerce(cp.decl.type, v)
        if not _fits(cp.decl.type, v):
            return []
        extra = {self._slot(cp.readers[0], cp.decl): v} if cp.direct else {cp.mem: (v, 0)}
        return [Step("event", Event(None, (cp.external,), (v,)), self._config(config, [], extra))]  # type: ignore[arg-type]

    def _terminations(self, config: Config, moves: list[list]) -> list[Step]:
        """The element's `terminate`: once every machine is at a final state, all of them at once
        (docs/semantics.md §5.6, as RoboTool synchronises `terminate`); one step per choice of final state."""
        ends = [[m[1] for m in ms if m[0] == "term"] for ms in moves]
        if not all(ends):
            return []
        base = f"{self.ename}::terminate"
        event = None if self.hidden_termination else Event(base, (base,), ())
        return [Step("internal" if event is None else "event", event,
                     self._config(config, [(i, frames, upd) for i, (frames, upd) in enumerate(choice)], done=True),
                     f"{self.ename} terminates" if event is None else "")
                for choice in itertools.product(*ends)]

    def expand(self, config: Config) -> list[tuple[Config, list[Step]]]:
        """`config` with its steps, or (lazy mode) where its steps read one of its Unknowns, the
        configurations it stands for, split by that Unknown's values as far as their steps need,
        each with its steps. Each configuration returned is one whose steps read none of its
        Unknowns, so every configuration it stands for has the same steps up to those values."""
        out = []
        todo = [config]
        while todo:
            c = todo.pop()
            unfolded = self.unfold(c)
            if isinstance(unfolded, Split):
                todo.extend(reversed(unfolded.parts))
            else:
                out.append((c, unfolded))
        return out

    def unfold(self, config: Config) -> list[Step] | Split:
        """`config`'s steps, or the configurations it splits into where its steps read a value not
        chosen yet: an input's or an open initial value's (the environment's choice), or an open
        function's at a point (the model's: `Split.point`)."""
        try:
            return self.steps(config)
        except NeedValue as nv:
            return Split(False, self._split(config, nv.unknown))
        except NeedPoint as np:  # one configuration per value the function may have there
            name = self.slots[np.slot].display
            if name not in self.points_chosen:
                self.points_chosen.append(name)
            table = config.store[np.slot]
            return Split(True, [_with_slot(config, np.slot, (*table, (np.point, v))) for v in np.values()])

    def points_in(self, config: Config) -> tuple[str, ...]:
        """The open functions whose value at some point `config` has chosen: on a run's last
        configuration, those whose choices the run rests on (a table only grows along a run)."""
        return tuple(sorted(info.display for s, info in enumerate(self.slots) if info.kind == "fun" and config.store[s]))

    def _split(self, config: Config, u: Unknown) -> list[Config]:
        slot = next((s for s, v in enumerate(config.store) if _holds(v, u)), None)
        if slot is None:  # pragma: no cover - an Unknown read must be in the configuration or an input
            raise AssertionError(f"a step read {u!r}, which is neither in its configuration nor in an input")
        return [_with_slot(config, slot, _replace(config.store[slot], u, x)) for x in u.values]

    def concretize(self, path: list[tuple[Config, Step, Config]]) -> list[tuple[Step, tuple[str, ...]]]:
        """The steps of a run of concrete configurations along `path`, found by a lazy search, each
        with the fields of its input that no later step reads (any value of them gives the same run).

        `path` holds, per step, the configuration it was taken from, the step (as `steps` gave it:
        its target is computed from that configuration, and the next configuration is the target or
        one of the configurations `expand` split it into) and the next configuration. Going back from
        the last configuration (each Unknown at its first value), each configuration's Unknowns take
        the values they have after the step: where the step left or moved one, its value there;
        where the step dropped it, its first value. Each step is then one the interpreter takes
        without Unknowns, with concrete values in its event; an AssertionError says that there is
        none, which would be a bug in the lazy mode.
        """
        lazy, self.lazy = self.lazy, False
        try:
            if not path:
                return []
            # An open function's values are chosen as the run first reads them, and never change: the
            # concrete run has them all from the start (the last configuration's tables).
            tables = {s: path[-1][2].store[s] for s, info in enumerate(self.slots) if info.kind == "fun"}

            def whole(c: Config) -> Config:
                if not tables:
                    return c
                return Config(c.machines, tuple(tables.get(s, v) for s, v in enumerate(c.store)), c.done)

            last: list[tuple[tuple, Unknown]] = []
            _unknowns(path[-1][2].store, (), last)
            free_after = {pos for pos, _ in last}  # positions of Unknowns no later step reads
            cur = whole(self._filled(path[-1][2], {}))
            out: list[tuple[Step, tuple[str, ...]]] = []
            for source, step, _nxt in reversed(path):
                after: list[tuple[tuple, Unknown]] = []
                _unknowns(step.target.store, (), after)
                where = {id(u): pos for pos, u in after}
                before: list[tuple[tuple, Unknown]] = []
                _unknowns(source.store, (), before)
                events: list[tuple[tuple, Unknown]] = []
                if step.event is not None:
                    _unknowns(step.event.values, (), events)
                chosen: dict[int, object] = {}
                free: set[int] = set()
                for _, u in (*before, *events):
                    pos = where.get(id(u))
                    chosen[id(u)] = u.values[0] if pos is None else _at(cur.store, pos)
                    if pos is None or pos in free_after:
                        free.add(id(u))
                prev = whole(self._filled(source, chosen))
                values = cast("tuple", fill(step.event.values, chosen)) if step.event is not None else ()
                only = _Given(step.event.channel if step.event is not None else None, values)
                match = next((s for s in self.steps(prev, only) if s.kind == step.kind and s.target == cur and
                              (s.event is None or step.event is not None and s.event.channel == step.event.channel
                               and s.event.values == values)), None)
                if match is None:  # pragma: no cover
                    raise AssertionError(f"the lazy search's step {step.event or step.note} has no concrete match")
                fields = tuple(".".join(str(k) for k in pos[1:]) for pos, u in events
                               if id(u) in free and step.event is not None and step.event.channel[-1:] == ("in",))
                out.append((match, tuple(dict.fromkeys(fields))))
                free_after = {pos for pos, u in before if id(u) in free}
                cur = prev
            out.reverse()
            return out
        finally:
            self.lazy = lazy

    def _filled(self, config: Config, chosen: dict[int, object]) -> Config:
        return Config(config.machines, fill(config.store, chosen), config.done)  # type: ignore[arg-type]

    def _tocked(self, ctx: _Ctx, frames: tuple) -> list[Frame]:
        """Activations after a tock: deadlines and the running wait count down, in the during
        actions running beside children too (`Frame.bg`)."""
        fl = [f._replace(dls=tuple(d - 1 for d in f.dls)) if f.dls else f for f in frames]
        top = fl[-1]
        if top.cont and top.cont[0][0] == "w":
            fl[-1] = top._replace(cont=(("w", top.cont[0][1] - 1), *top.cont[1:]))
        for k, f in enumerate(fl):
            if f.bg:
                fl[k] = self._with_during(f, self._norm(ctx, self._tocked(ctx, f.bg)))
        return fl

    def _tock(self, config: Config, steps: list[Step], urgent: bool) -> Config | None:
        """The configuration after `tock`, or None if `tock` is refused (docs/semantics.md §3.3, §4.6)."""
        if urgent or any(s.kind == "internal" for s in steps):
            return None
        for frames in config.machines:
            for f in (*frames, *(g for h in frames for g in h.bg)):
                if any(d <= 0 for d in f.dls):
                    return None
        store = list(config.store)
        for i in self._tdl:
            for s, (armed, bound) in self._armed(config.machines, config.store, i).items():
                if armed:
                    if config.store[s] >= bound:
                        return None
                    store[s] = config.store[s] + 1
        caps = self._caps
        for s in self._timed_slots:
            cap = caps.get(s)
            store[s] = store[s] + 1 if cap is None or store[s] < cap else cap
        machines = []
        base = tuple(store)
        upd: dict = {}
        for i, frames in enumerate(config.machines):
            ctx = _Ctx(base, i, upd)
            machines.append(self._norm(ctx, self._tocked(ctx, frames)))
            upd = ctx.upd
        for s, v in upd.items():
            store[s] = v
        m = tuple(machines)
        return Config(m, self._fix_deadlines(m, tuple(store)), False)
