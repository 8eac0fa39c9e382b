"""The other direction of refinement: the traces of a specification Q, and a model following one.

`Q refines P` (and the second half of `P equals Q`) needs, for every trace of Q,
some run of P with that trace.  Q is finite-state, so its traces up to a length
are listed from its determinised monitor (`spec.Monitor`, `spec_traces`); a
`TraceFollower` beside P counts how much of one trace P has done, so "P can
perform it" is a target (`done`).  The search for each trace is the engines'
(`bmc.inclusion`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import TransitionSystem
from tockbmc.model.errors import Unsupported
from tockbmc.properties.process import Context, _equals, _event_text
from tockbmc.properties.spec import OTHER, Channel, Monitor, Proc, Semantics, TooLarge


class Unenumerable(Unsupported):
    """The specification's traces cannot be listed (it offers every value of a channel)."""

    def __init__(self, why: str):
        super().__init__(None, f"the traces of the specification cannot be listed: {why}")
        self.why = why


@dataclass(frozen=True)
class SpecTrace:
    events: tuple[tuple, ...]
    ticks: bool  # the specification can terminate (✓) after it


def spec_traces(sem: Semantics, root: Proc, channels: list[Channel], length: int,
                cap: int) -> tuple[list[SpecTrace], int]:
    """The traces of the specification to check: the maximal ones with at most `length` events,
    and every one after which it can terminate (with ✓).

    If there are more than `cap`, the length is reduced until there are not; returns the
    traces and the length they cover.
    """
    try:
        mon = Monitor(sem, root, channels)
    except TooLarge:
        raise Unenumerable("the specification has too many states") from None
    while length >= 0:
        out: list[SpecTrace] = []
        todo: list[tuple[int, tuple[tuple, ...]]] = [(mon.initial, ())]
        while todo and len(out) <= cap:
            state, trace = todo.pop()
            nexts = [] if len(trace) == length else next_events(mon, sem, state)
            if mon.can_tick(state):
                out.append(SpecTrace(trace, True))
            elif not nexts:
                out.append(SpecTrace(trace, False))
            todo += [(s, (*trace, e)) for e, s in nexts]
        if len(out) <= cap:
            return sorted(out, key=lambda t: (len(t.events), repr(t.events))), length
        length -= 1
    return [], 0


_FOREIGN = ("a channel outside the model's alphabet",)


def _every_value(sem: Semantics, e: tuple) -> list[tuple] | None:
    """The events a class of values (`OTHER` in some fields) stands for, every value listed, when
    the channel's types and ranges make them few (`Semantics.values`); else None."""
    for prefix, arity in sem.alphabet:
        if len(e) != len(prefix) + arity or tuple(e[: len(prefix)]) != tuple(prefix):
            continue
        values = sem.values(prefix) if sem.values is not None else None
        if values is None:
            return None
        fields = e[len(prefix):]
        return [(*prefix, *v) for v in values
                if all(x is OTHER or x == y for x, y in zip(fields, v, strict=True))]
    return None


def next_events(mon: Monitor, sem: Semantics, state: int) -> list[tuple[tuple, int]]:
    """The specification's next events from a monitor state, each with the state after it."""
    events: set[tuple] = set()
    for p in mon.states[state]:
        if sem.after(p, _FOREIGN):
            raise Unenumerable("it offers events the model does not have (such as every event of `Events`)")
        for e in sem.candidates(p):
            if OTHER in e[1:] and sem.after(p, e):
                concrete = _every_value(sem, e)
                if concrete is None:
                    raise Unenumerable(f"it offers any value on {_event_text(e[:2])}, so its traces cannot be "
                                       "listed (give the channel's type a small range)")
                events.update(concrete)
                continue
            events.add(e)
    out = []
    for e in sorted(events, key=repr):
        if OTHER in e[1:]:
            continue
        s = mon.after(state, e)
        if s != Monitor.DEAD:
            out.append((e, s))
    return out


class TraceFollower:
    """How many events of a fixed trace the element has performed (`follow`); other visible events are barred."""

    def __init__(self, system: TransitionSystem, trace: SpecTrace,
                 guards: dict[int, Callable[[TransitionSystem], z3.BoolRef]] | None = None):
        self.trace = trace
        self.system = system
        # What the configuration must satisfy to take the trace's event at a position (the
        # tick-tock model: the refusal before a tock), read before the step.
        self.guards = guards or {}

    def slots(self) -> dict[str, z3.SortRef]:
        return {names.FOLLOW: z3.IntSort()}

    def init(self, system: TransitionSystem) -> z3.BoolRef:
        return system.cur[names.FOLLOW] == 0

    def step(self, system: TransitionSystem) -> z3.BoolRef:
        pos = system.cur[names.FOLLOW]
        act = system.act
        cs = []
        new: z3.ArithRef = pos  # type: ignore[assignment]
        for m in system.moves:
            visible = (m.kind == "event" and not m.blocked) or (m.kind == "tock" and not system.tock_hidden)
            if not visible:
                continue
            label, _arity = system.label(m)
            values = [v for v, _t in system.label_values(m)]
            try:
                matches = [z3.And(pos == j, _matches(label, values, e), *([self.guards[j](system)] if j in self.guards
                                                                          else []))
                           for j, e in enumerate(self.trace.events)]
            except ValueError as exc:
                raise Unenumerable(str(exc)) from None
            cs.append(z3.Implies(act == m.index, z3.Or(matches) if matches else z3.BoolVal(False)))
            new = z3.If(act == m.index, pos + 1, new)  # type: ignore[assignment]
        cs.append(system.nxt[names.FOLLOW] == new)
        return z3.And(cs)

    def done(self, system: TransitionSystem) -> z3.BoolRef:
        end = system.cur[names.FOLLOW] == len(self.trace.events)
        return z3.And(end, system.halted()) if self.trace.ticks else end


def followed(system: TransitionSystem) -> z3.BoolRef:
    """The target of a search for a run that performs the followed trace."""
    assert isinstance(system.extension, TraceFollower)
    return system.extension.done(system)


def _matches(label: tuple, values: list, e: tuple) -> z3.BoolRef:
    if len(e) != len(label) + len(values) or tuple(e[: len(label)]) != label:
        return z3.BoolVal(False)
    return z3.And([_equals(v, x) for v, x in zip(values, e[len(label):], strict=True)])


class Following:
    """A CSP context whose extra state is a `TraceFollower` rather than a monitor."""

    def __init__(self, base: Context, follower: Callable[[TransitionSystem], TraceFollower]):
        self.base, self.follower = base, follower

    def status(self, label: tuple, arity: int) -> str:
        return self.base.status(label, arity)

    def attach(self, system: TransitionSystem) -> TraceFollower:
        return self.follower(system)


INCLUSION_LENGTH = 8  # most events in a specification trace listed by default (and at most half the bound)
