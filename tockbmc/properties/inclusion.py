"""The other direction of refinement: every trace of a specification Q is a trace of the model P.

`Q refines P` (and the second half of `P equals Q`) needs, for every trace of Q,
some run of P with that trace.  Q is finite-state, so its traces up to a length
are enumerated from its determinised monitor (`spec.Monitor`); for each
maximal one, BMC asks whether P can perform it, with a `TraceFollower`
counting how much of the trace P has done.  A trace that P provably cannot
perform (k-induction shows the end of the trace unreachable) is a violation
with that trace as witness; one that P is not shown to perform within the
bound leaves the verdict unknown.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import z3

from tockbmc.bmc.engine import bmc
from tockbmc.bmc.result import TraceStep
from tockbmc.encodings.system import System
from tockbmc.properties.process import Context, _event_text, alphabet_of, channels_of
from tockbmc.properties.spec import OTHER, Channel, Monitor, Proc, Semantics, TooLarge


class Unenumerable(Exception):
    """The specification's traces cannot be listed (it offers every value of a channel)."""


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
            nexts = [] if len(trace) == length else _moves(mon, sem, state)
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


def _moves(mon: Monitor, sem: Semantics, state: int) -> list[tuple[tuple, int]]:
    """The specification's next events from a monitor state, each with the state after it."""
    events: set[tuple] = set()
    for p in mon.states[state]:
        if sem.after(p, _FOREIGN):
            raise Unenumerable("it offers events the model does not have (such as every event of `Events`)")
        for e in sem.candidates(p):
            if OTHER in e[1:] and sem.after(p, e):
                raise Unenumerable(f"it offers any value on {_event_text(e[:2])}, so its traces cannot be "
                                   "listed")
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

    def __init__(self, system: System, trace: SpecTrace):
        self.trace = trace
        self.system = system

    def slots(self) -> dict[str, z3.SortRef]:
        return {"follow": z3.IntSort()}

    def init(self, system: System) -> z3.BoolRef:
        return system.frame(0)["follow"] == 0

    def step(self, system: System, i: int) -> z3.BoolRef:
        pos = system.frame(i)["follow"]
        act = system.action(i)
        cs = []
        new: z3.ArithRef = pos  # type: ignore[assignment]
        for m in system.moves:
            visible = (m.kind == "event" and not m.blocked) or (m.kind == "tock" and not system.tock_hidden)
            if not visible:
                continue
            label, _arity = system.label(m)
            values = [v for v, _t in system.label_values(m, i)]
            try:
                matches = [z3.And(pos == j, _matches(label, values, e)) for j, e in enumerate(self.trace.events)]
            except ValueError as exc:
                raise Unenumerable(str(exc)) from None
            cs.append(z3.Implies(act == m.index, z3.Or(matches) if matches else z3.BoolVal(False)))
            new = z3.If(act == m.index, pos + 1, new)  # type: ignore[assignment]
        cs.append(system.frame(i + 1)["follow"] == new)
        return z3.And(cs)

    def done(self, system: System, k: int) -> z3.BoolRef:
        end = system.frame(k)["follow"] == len(self.trace.events)
        return z3.And(end, system.halted(k)) if self.trace.ticks else end


def _matches(label: tuple, values: list, e: tuple) -> z3.BoolRef:
    if len(e) != len(label) + len(values) or tuple(e[: len(label)]) != label:
        return z3.BoolVal(False)
    from tockbmc.properties.process import _equals
    return z3.And([_equals(v, x) for v, x in zip(values, e[len(label):], strict=True)])


def _shortest_failing_prefix(make: Callable[[Callable[[System], TraceFollower] | None, str], System],
                             t: SpecTrace, bound: int, timeout: Callable[[], float | None]) -> SpecTrace:
    """The shortest prefix of t that the element provably cannot perform (t itself if none shorter)."""
    for n in range(1, len(t.events) + 1):
        prefix = SpecTrace(t.events[:n], t.ticks and n == len(t.events))
        system = make(lambda s, p=prefix: TraceFollower(s, p), "")  # type: ignore[misc]
        prover = lambda p=prefix: make(lambda s: TraceFollower(s, p), "k.")  # noqa: E731
        outcome = bmc(system, lambda s, k: s.extension.done(s, k), bound, timeout(), prover)  # type: ignore[union-attr]
        if outcome.status == "proved":
            return prefix
    return t


class Following:
    """A CSP context whose extra state is a `TraceFollower` rather than a monitor."""

    def __init__(self, base: Context, follower: Callable[[System], TraceFollower]):
        self.base, self.follower = base, follower

    def status(self, label: tuple, arity: int) -> str:
        return self.base.status(label, arity)

    def attach(self, system: System) -> TraceFollower:
        return self.follower(system)


@dataclass
class Inclusion:
    verdict: str  # holds | violated | unknown
    reason: str
    trace: tuple[TraceStep, ...] = ()


INCLUSION_LENGTH = 8  # most events in a specification trace listed by default (and at most half the bound)


def included(make: Callable[[Callable[[System], TraceFollower] | None, str], System], sem: Semantics,
             spec: Proc, spec_name: str, element: str, bound: int, timeout: Callable[[], float | None],
             cap: int = 256) -> Inclusion:
    """Whether every trace of `spec` (up to a length) is one of the element's.

    `make(follower, tag)` builds the element's system with a follower attached.
    """
    probe = make(lambda s: TraceFollower(s, SpecTrace((), False)), "")
    channels, _ = channels_of(probe)
    sem.alphabet = alphabet_of(probe)
    wanted = max(1, min(INCLUSION_LENGTH, bound // 2))
    traces, length = spec_traces(sem, spec, channels, wanted, cap)
    if length < wanted:
        return Inclusion("unknown", f"{spec_name} has more than {cap} traces of {wanted} events; only those of up "
                                    f"to {length} events could be listed, which gives no verdict")
    for t in traces:
        system = make(lambda s, t=t: TraceFollower(s, t), "")  # type: ignore[misc]
        prover = lambda t=t: make(lambda s: TraceFollower(s, t), "k.")  # noqa: E731
        follower = system.extension
        assert isinstance(follower, TraceFollower)
        outcome = bmc(system, lambda s, k: s.extension.done(s, k), bound, timeout(), prover)  # type: ignore[union-attr]
        if outcome.status == "found":
            continue
        if outcome.status == "proved":
            t = _shortest_failing_prefix(make, t, bound, timeout)
        shown = [_event_text(e) for e in t.events] + (["✓"] if t.ticks else [])
        steps = tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", f"a trace of {spec_name}", {}, {})
                      for j, e in enumerate(shown))
        if outcome.status == "proved":
            return Inclusion("violated", f"{spec_name} has this trace and {element} cannot perform it in any "
                                         f"number of steps ({outcome.reason})", steps)
        why = outcome.reason if outcome.status == "unknown" else f"not within {bound} steps"
        return Inclusion("unknown", f"{spec_name} has this trace and {element} was not shown to perform it "
                                    f"({why})", steps)
    return Inclusion("holds", f"every trace of {spec_name} with up to {length} events is a trace of {element} "
                              f"({len(traces)} traces listed, each performed within {bound} steps)")
