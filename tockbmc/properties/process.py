"""Processes over the model: a model element in a CSP context, and specifications as monitors.

An implementation process is a model element (`M::D__(id, c1, …)`, or the
element named directly) under the operators of `docs/semantics.md` §8.2 that the
encoding understands: hiding `\\` and projection `|\\` (events become internal,
hence urgent), `[| A |] SKIP` and `[| A |] STOP` (events of A are blocked),
`P ; T` (after the element terminates, T runs), and prefix `e -> P` outside a
Timed section.  `Context` tells the `TransitionSystem` which moves are hidden or
blocked; `MonitorExtension` runs a specification's `Monitor` beside the
element, so `P refines Q` becomes "the monitor never reaches DEAD".
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import cast

import z3
from lark import Tree

from tockbmc.encodings import names
from tockbmc.encodings.composition import External
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.unroller import Unroller, int_value
from tockbmc.model import ast
from tockbmc.model.csp import CspError, Definition, canonical, pos_of
from tockbmc.model.data import Product, Variant, text_of
from tockbmc.model.result import TraceStep
from tockbmc.properties.spec import (
    EVENTS,
    OTHER,
    TOCK,
    Binary,
    Channel,
    EnumValue,
    Env,
    Evaluator,
    EventSet,
    Monitor,
    Proc,
    Semantics,
    Skip,
    Stop,
    TooLarge,
)


@dataclass
class Implementation:
    """A model element in context: the operators between it and the top, outermost first."""

    element: str
    args: tuple[object, ...]
    pos: ast.Pos
    ops: list[tuple[str, EventSet]] = field(default_factory=list)  # ("hide" | "block", events)
    tail: Proc = field(default_factory=Skip)  # what runs after the element terminates, in context
    head: tuple[tuple, ...] = ()  # events before the element starts
    continues: bool = False  # something other than ✓ follows the element's termination
    # `[[ a <- b ]]` around the element: its channels' new names (outermost last).  Only a model
    # element that stands for a specification (refinement between two elements) may be renamed.
    renames: tuple[tuple[tuple, tuple], ...] = ()


@dataclass(frozen=True)
class RoboToolConstant:
    """An argument of `M::D__(id, …)` written as RoboTool's generated name of a constant,
    `const_M_c`: the value its instantiation gives (`properties.queries._arguments`)."""

    name: str


def _argument(ev: Evaluator, t: Tree, env: Env) -> object:
    """An argument of `M::D__`/`M::O__`: a value, or RoboTool's name of a constant no block defines."""
    if isinstance(t, Tree) and t.data == "name":
        name = str(t.children[0])
        if name.startswith("const_") and env.lookup(name) is None and ev.lookup_top(name) is None:
            return RoboToolConstant(name)
    return ev.eval(t, env)


def implementation(ev: Evaluator, t: Tree, env: Env, seen: frozenset[int] = frozenset()) -> Implementation | Proc:
    """Walk an expression: an `Implementation` if it contains a model process, else a specification term.

    `seen` holds the definitions being unfolded: a recursive one is a specification (a model
    process under recursion is not supported).
    """
    k = t.data
    c = t.children
    if k == "name":
        found = env.lookup(str(c[0]))
        if found is not None and found[0] == "def":
            d, denv = cast("tuple[Definition, Env]", found[1])
            return _definition(ev, d, Env({}, {}, denv.timed or d.timed, denv), (), seen)
        top = ev.lookup_top(str(c[0])) if found is None else None
        if top is not None:
            return _definition(ev, top, Env({}, {}, top.timed), (), seen)
        return ev.proc(t, env)
    if k == "apply":
        head = c[0]
        name = str(head.children[0]) if head.data == "name" else ""
        if name.endswith("::D__") or name.endswith("::O__"):
            return Implementation(name[:-5], tuple(_argument(ev, a, env) for a in c[1:]), pos_of(ev.block, t))
        if name == "timed_priority" and len(c) == 2:
            return implementation(ev, c[1], env, seen)
        found = env.lookup(name)
        args = tuple(ev.eval(a, env) for a in c[1:])
        if found is not None and found[0] == "def":
            local, denv = cast("tuple[Definition, Env]", found[1])
            return _definition(ev, local, Env({}, {}, denv.timed or local.timed, denv), args, seen)
        top = ev.lookup_top(name) if found is None else None
        if top is not None:  # evaluated where it is defined, not where it is used
            return _definition(ev, top, Env({}, {}, top.timed), args, seen)
        return ev.proc(t, env)
    if k == "let":
        defs = {d.name: d for d in (ev._local(x) for x in c[:-1])}
        return implementation(ev, c[-1], Env({}, defs, env.timed, env), seen)
    if k == "if_":
        return implementation(ev, c[1] if ev.boolean(c[0], env) else c[2], env, seen)
    if k in ("hide", "project", "parallel", "seq", "prefix"):
        inner_t = c[1] if k == "prefix" else c[0]
        try:
            inner = implementation(ev, inner_t, env, seen)
        except CspError:
            if k != "prefix" or "?" not in [str(x) for x in c[0].children]:
                raise
            # What follows reads the prefix's inputs (`c?x -> e!x -> …`), unbound in this walk: a
            # specification term, evaluated as it is reached (a model process in it is refused then).
            return ev.proc(t, env)
        if not isinstance(inner, Implementation):
            return ev.proc(t, env)
        if k in ("hide", "project"):
            events = ev.events(c[1], env)
            hidden = events if k == "hide" else EventSet("diff", (EVENTS, events))
            inner.ops.insert(0, ("hide", hidden))
            inner.tail = Binary("hide", inner.tail, None, hidden, env.timed)
            inner.head = tuple(e for e in inner.head if not hidden.contains(e))  # now internal
        elif k == "parallel":
            p = ev.eval(c[2], env)
            if not isinstance(p, (Skip, Stop)):
                raise ev.error(t, "a model process can only be put in parallel with SKIP or STOP "
                                  "(to block events)")
            events = ev.events(c[1], env)
            if any(events.contains(e) for e in inner.head):
                raise ev.error(t, "blocking an event of a prefix before a model process is not supported")
            inner.ops.insert(0, ("block", events))
            tail = inner.tail if isinstance(p, Skip) else Binary("seq", inner.tail, p, None, env.timed)
            inner.continues |= isinstance(p, Stop)
            inner.tail = Binary("parallel", tail, Skip(), events, env.timed)
        elif k == "seq":
            inner.tail = Binary("seq", inner.tail, ev.proc(c[1], env), None, env.timed)
            inner.continues = True
        else:  # prefix
            if env.timed:
                raise ev.error(t, "a prefix before a model process inside a Timed section is not supported")
            event = ev.pattern(c[0], env)
            if any(not _concrete(x) for x in event):
                raise ev.error(c[0], "a prefix before a model process must name one event")
            inner.head = (event, *inner.head)
        return inner
    if k == "rename":
        inner = implementation(ev, c[0], env, seen)
        if not isinstance(inner, Implementation):
            return ev.proc(t, env)
        if inner.ops or inner.head or inner.continues:
            raise ev.error(t, "renaming a model process inside other operators is not supported")
        pairs = tuple((ev.event(r.children[0], env), ev.event(r.children[-1], env)) for r in c[1:])
        inner.renames = (*inner.renames, *pairs)
        return inner
    if k in ("external", "internal", "interrupt", "timeout", "exception", "interleave", "replicated"):
        for x in c:
            if isinstance(x, Tree) and isinstance(_peek(ev, x, env, seen), Implementation):
                raise ev.error(t, f"a model process under '{k}' is not supported; only hiding, projection, "
                                  "[| A |] SKIP/STOP, ';' and prefix may be applied to it")
    return ev.proc(t, env)


def _peek(ev: Evaluator, t: Tree, env: Env, seen: frozenset[int]) -> object:
    try:
        return implementation(ev, t, env, seen)
    except CspError:
        return None


def _concrete(x: object) -> bool:
    return isinstance(x, (int, bool, str))


def _definition(ev: Evaluator, d: Definition, env: Env, args: tuple[object, ...],
                seen: frozenset[int]) -> Implementation | Proc:
    if id(d.body) in seen:
        return ev._use(d, env, args)  # type: ignore[return-value]
    if len(args) != len(d.params):
        raise CspError(d.pos, f"'{d.name}' takes {len(d.params)} arguments, not {len(args)}")
    ev.block = d.block
    inner = Env(dict(zip(d.params, args, strict=True)), {}, env.timed or d.timed, env)
    return implementation(ev, d.body, inner, seen | {id(d.body)})


class Context:
    """An `Implementation`'s operators as a `TransitionSystem` sees them, plus an optional monitor."""

    def __init__(self, impl: Implementation, sem: Semantics, spec: Proc | None = None, spec_name: str = "",
                 monitor: type[MonitorExtension] | None = None):
        self.impl, self.sem, self.spec, self.spec_name = impl, sem, spec, spec_name
        self.monitor = monitor or MonitorExtension  # the tick-tock model filters the monitor at each tock

    def status(self, label: tuple, arity: int) -> str:
        """Inside out: the first operator that hides or blocks the channel decides."""
        for kind, events in reversed(self.impl.ops):
            mentioned = [e for e in events.mentions() if len(e) > len(label) and e[: len(label)] == label]
            if mentioned:
                raise CspError(self.impl.pos, "hiding or blocking particular values of a channel is not supported")
            if events.contains((*label, *(OTHER,) * arity)):
                if kind == "block" and label == TOCK:
                    raise CspError(self.impl.pos, "blocking tock ([| {tock} |] SKIP) is not supported")
                return "hidden" if kind == "hide" else "blocked"
        return "visible"

    def tail_timelock(self) -> list[str] | None:
        """Events after which what follows the element's termination refuses tock (✓ included), if any."""
        sem = self.sem
        todo: list[tuple[Proc, list[str]]] = [(self.impl.tail, [])]
        seen: set[Proc] = set()
        while todo:
            p, trace = todo.pop(0)
            p = sem.force(p)
            if p in seen:
                continue
            seen.add(p)
            if len(seen) > 5000:
                raise CspError(self.impl.pos, "what follows the model's termination has too many states")
            if sem.ticks(p):
                return [*trace, "✓"]
            taus = sem.taus(p)
            if not taus and not sem.after(p, TOCK):
                return trace
            todo += [(q, trace) for q in taus]
            for e in sorted(sem.candidates(p) - {TOCK}, key=repr):
                todo += [(q, [*trace, _event_text(e)]) for q in sem.after(p, e)]
            if not taus:
                todo += [(q, [*trace, "tock"]) for q in sem.after(p, TOCK)]
        return None

    def attach(self, system: TransitionSystem) -> MonitorExtension | None:
        if self.spec is None:
            return None
        return self.monitor(system, self)


def channels_of(system: TransitionSystem) -> tuple[list[Channel], dict[int, int]]:
    """The channels of the visible moves (`tock` last, unless hidden), and each move's channel."""
    channels: list[Channel] = []
    channel_of: dict[int, int] = {}
    for m in system.moves:
        if m.kind != "event" or m.blocked:
            continue
        label, arity = system.label(m)
        ch = Channel(label, arity)
        if ch not in channels:
            channels.append(ch)
        channel_of[m.index] = channels.index(ch)
    if not system.tock_hidden:
        channels.append(Channel(TOCK, 0))
        channel_of[system.TOCK] = len(channels) - 1
    return channels, channel_of


def alphabet_of(system: TransitionSystem) -> list[tuple[tuple, int]]:
    """Every channel the element declares, as (fixed fields, number of values): its machines'
    events in both directions, its operation calls and `terminate`, whether used or not."""
    out: list[tuple[tuple, int]] = [((canonical(f"{system.name}::terminate"),), 0)]
    for c, comp in enumerate(system.components):
        for e in comp.machine.events:
            found = system.network.route(c, e.name)
            ends = (found[0].receiver, found[0].sender) if found is not None else ()
            name = canonical(system.network.visible_name(c, e.name))
            if found is not None and not any(isinstance(end, External) for end in ends):
                # machine to machine: internal, but for the direction against the link (the sender
                # receiving, the receiver sending), which is seen under the machine's name
                against = "in" if found[1] == "sender" else "out"
                out.append(((name, against), int(e.type is not None)))
                continue
            out += [((name, d), int(e.type is not None)) for d in ("in", "out")]
        for op in comp.machine.operations:
            out.append(((canonical(f"{system.name}::{op.name}Call"),), len(op.parameters)))
    channels, _ = channels_of(system)
    out += [(ch.prefix, ch.arity) for ch in channels if ch.prefix != TOCK]
    return list(dict.fromkeys(out))


class MonitorExtension:
    """The specification's monitor state `monitor`, updated by every visible step."""

    def __init__(self, system: TransitionSystem, context: Context):
        self.context = context
        sem = context.sem
        self.channels, self.channel_of = channels_of(system)
        sem.alphabet = alphabet_of(system)
        assert context.spec is not None
        try:
            self.monitor = Monitor(sem, context.spec, self.channels)
            start = self.monitor.initial
            for e in context.impl.head:
                start = self.monitor.after(start, e)
            self.start = start
            self.table = self._explore()
            self.count = len(self.monitor.states)
            self.bad_end = self._bad_end()
        except TooLarge:
            raise CspError(context.impl.pos, f"the specification {context.spec_name} has too many states "
                                             "to monitor") from None

    def _explore(self) -> dict[tuple[int, int], list[tuple[tuple, int]]]:
        """The monitor's moves from every state it can reach (a subclass may reach more)."""
        return self.monitor.table()

    def slots(self) -> dict[str, z3.SortRef]:
        return {names.MONITOR: z3.IntSort()}

    def init(self, system: TransitionSystem) -> z3.BoolRef:
        return system.cur[names.MONITOR] == self.start

    def step(self, system: TransitionSystem) -> z3.BoolRef:
        mon = system.cur[names.MONITOR]
        new: z3.ArithRef = mon  # type: ignore[assignment]
        for m in system.moves:
            c = self.channel_of.get(m.index)
            if c is None:
                continue
            values = [v for v, _t in system.label_values(m)]
            by_state: z3.ArithRef = z3.IntVal(Monitor.DEAD)
            for s in reversed(range(self.count)):
                by_state = z3.If(mon == s, self._next(system, s, c, values), by_state)
            new = z3.If(system.act == m.index, by_state, new)
        return system.nxt[names.MONITOR] == new

    def _next(self, system: TransitionSystem, s: int, c: int, values: list) -> z3.ArithRef:
        """The next monitor state after channel c's event with `values` from state s, in the
        configuration before the step (which only the tick-tock model's tock reads)."""
        return self._delta(s, c, values)

    def _delta(self, s: int, c: int, values: list) -> z3.ArithRef:
        """The next monitor state after channel c's event with `values`; the atoms' conditions are
        exclusive (per field: a named value, or none of them), so their order does not matter."""
        entries = self.table[(s, c)]
        named = self.monitor.named[(s, c)]
        # Without an "other values" class (every listed value named), a value that matches no entry
        # would be one the listing missed: the dead state shows it, rather than a class it is not in.
        every = all(OTHER not in vs for vs, _nxt in entries) and any(vs for vs, _nxt in entries)
        out: z3.ArithRef = z3.IntVal(Monitor.DEAD if every else entries[-1][1])
        try:
            for vs, nxt in reversed(entries if every else entries[:-1]):
                out = z3.If(z3.And([field_is(v, x, named[j]) for j, (v, x) in enumerate(zip(values, vs, strict=True))]),
                            nxt, out)
        except ValueError as exc:
            raise CspError(self.context.impl.pos, str(exc)) from None
        return out

    def allowed(self, state: int, most: int = 6) -> list[str]:
        """The channels (and `tock`) the specification can do in a monitor state, for the report."""
        if state < 0:
            return []
        names = [".".join(str(x) for x in ch.prefix) for c, ch in enumerate(self.channels)
                 if any(nxt != Monitor.DEAD for _vs, nxt in self.table[(state, c)])]
        others = [".".join(str(x) for x in ch.prefix) for ch in self.channels if ch.prefix != TOCK]
        if "tock" not in names and len(names) == len(others) and len(names) > 1:
            return ["any event but tock"]
        return names[:most] + (["…"] if len(names) > most else [])

    def violated(self, system: TransitionSystem) -> z3.BoolRef:
        mon = system.cur[names.MONITOR]
        ends = [mon == s for s in sorted(self.bad_end)]
        return z3.Or(mon == Monitor.DEAD, z3.And(system.halted(), z3.Or(ends))) if ends else mon == Monitor.DEAD

    def around(self, unroller: Unroller, model: z3.ModelRef, k: int,
               trace: tuple[TraceStep, ...]) -> tuple[TraceStep, ...]:
        """A decoded run with the events before the element (a prefix) and after it (`P ; T`)."""
        before = tuple(TraceStep(0, _event_text(e), "event", "before the model starts", {}, {})
                       for e in self.context.impl.head)
        state = int_value(model, unroller.frame(k)[names.MONITOR])
        if not z3.is_true(model.eval(unroller.at(unroller.system.halted(), k), model_completion=True)):
            state = Monitor.DEAD  # nothing follows an element that has not terminated (a refusal, a divergence)
        last = trace[-1].states if trace else {}
        after = tuple(TraceStep(k + 1 + j, e, "tock" if e == "tock" else "event",
                                "after the model terminates", last, {})
                      for j, e in enumerate(self.bad_end.get(state, [])))
        return before + trace + after

    def _bad_end(self) -> dict[int, list[str]]:
        """Monitor states from which what follows the element's termination has a trace the spec refuses.

        Maps each such state to that trace (event names, `✓` for termination).
        """
        out: dict[int, list[str]] = {}
        for s in range(self.count):
            rest = after_termination(self.context.sem, self.monitor, self.context.impl.tail, s)
            if rest is not None:
                out[s] = rest
        return out


def after_termination(sem: Semantics, mon: Monitor, tail: Proc, state: int) -> list[str] | None:
    """A trace of `tail` (what runs once the element has terminated) that the specification, in
    monitor state `state`, refuses (`✓` for a termination it cannot do); None if there is none."""
    todo: list[tuple[Proc, int, list[str]]] = [(tail, state, [])]
    seen: set[tuple[Proc, int]] = set()
    while todo:
        p, q, trace = todo.pop(0)
        p = sem.force(p)
        if (p, q) in seen:
            continue
        seen.add((p, q))
        if len(seen) > 5000:
            raise TooLarge
        if sem.ticks(p) and not mon.can_tick(q):
            return [*trace, "✓"]
        todo += [(r, q, trace) for r in sem.taus(p)]
        events = sem.candidates(p, (e for t in mon.states[q] for e in sem.mentions(t)))
        if sem.stable(p):
            events.add(TOCK)
        else:
            events.discard(TOCK)
        for e in sorted(events, key=repr):
            for r in sem.after(p, e):
                nxt = mon.after(q, e)
                name = _event_text(e)
                if nxt == Monitor.DEAD:
                    return [*trace, name]
                todo.append((r, nxt, [*trace, name]))
    return None


def _event_text(e: tuple) -> str:
    """An event of a specification as the model's events are named (a record as `(q=0, p=1)`, a
    tuple or vector as `(1, 2)`, as the interpreter names them: the explicit engine matches names)."""
    return ".".join("…" if x is OTHER else str(x).lower() if isinstance(x, bool) else text_of(None, x)
                    if isinstance(x, (dict, Product, Variant)) else str(x) for x in e)


def field_is(term: object, value: object, named: list[object]) -> z3.BoolRef:
    """A model value (a Z3 term) is the specification's value, or, for `OTHER`, none it names."""
    if value is OTHER:
        return z3.And([z3.Not(_equals(term, x)) for x in named])
    return _equals(term, value)


def _equals(term: object, value: object) -> z3.BoolRef:
    if isinstance(term, dict):
        # a tuple's parts are named "1", "2", … (`encodings.values.parts`); a record's by its fields
        if all(k.isdigit() for k in term):  # a tuple type's parts
            if not isinstance(value, tuple) or len(value) != len(term):
                raise ValueError(f"the specification's value {value!r} is not a tuple of {len(term)} parts, "
                                 "as the event's values are")
            return z3.And([_equals(term[str(i)], v) for i, v in enumerate(value, 1)])
        # a record received by the specification (`c?x`, its values listed), field by field; a record
        # the specification writes itself (RoboTool's tuple of its fields) is not compared yet
        if isinstance(value, dict) and set(value) == set(term):
            return z3.And([_equals(term[f], value[f]) for f in term])
        raise ValueError("a specification that writes a value of a record-typed event is not supported (only one "
                         "it received is compared)")
    assert isinstance(term, z3.ExprRef)
    if isinstance(value, bool):
        return term == z3.BoolVal(value) if z3.is_bool(term) else z3.BoolVal(False)
    if isinstance(value, EnumValue):
        return term == value.index if z3.is_int(term) else z3.BoolVal(False)  # type: ignore[return-value]
    if isinstance(value, int) and z3.is_arith(term):
        return term == value  # type: ignore[return-value]
    return z3.BoolVal(False)


