"""Refinement in the tick-tock model (docs/semantics.md §7.13).

A tick-tock observation of a tock-CSP process is a trace in which each `tock` is preceded by a
refusal `[X]` of the stable state it happened in, plus, where the process is stable after the
trace, a final refusal.  RoboTool checks `A refines B in the tick-tock model` as the traces
refinement `MS::TT(B) [T= MS::TT(A)` of processes that record those refusals
(docs/robotool-evidence.md §2.2).  Refusals are subset-closed, so the model's maximal refusal
(everything outside what it offers) at each tock and at the end stands for all of its smaller ones.

With the model on the left, the specification is followed as a set of terms (the monitor's
subset construction), and a tock keeps only the stable terms that refuse what the model refuses
there and can let time pass (`TickTockMonitor`): the terms of the monitor state are grouped by
acceptance (`TockGroup`), each group kept or dropped by the model's offers, and the monitor moves to
the state of the groups kept.  A tock that keeps none leaves the monitor dead (the model's
refusal before the tock is not one the specification can make), and the end of a run is checked as
in the failures model (`failures.Refusals`) against the filtered state.

With the specification on the left, its observations are listed (`spec_observations`): traces
in which each tock carries the acceptance the model must stay within when it takes it.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.model.errors import Unsupported
from tockbmc.model.result import TraceStep
from tockbmc.properties.failures import (
    Offer,
    Refusals,
    SpecRefusal,
    acceptance,
    acceptance_text,
    offer_text,
    refuse_context,
)
from tockbmc.properties.goals import number_at, true_at
from tockbmc.properties.inclusion import next_events
from tockbmc.properties.process import Context, MonitorExtension, _event_text
from tockbmc.properties.spec import TOCK, Channel, Monitor, Proc, Semantics

TICK_TOCK = "tick-tock"
MODELS = "the tick-tock model"
MAX_GROUPS = 8  # distinct acceptances among the terms that can let time pass in one monitor state
OBSERVATIONS_CAP = 256


class TooManyObservations(Unsupported):
    """More observations of the specification than are listed (the length is then cut)."""


@dataclass(frozen=True)
class TockGroup:
    """Stable terms of a monitor state that can do `tock` and accept the same classes of events
    (tock left out): a tock keeps them all or none, by what the model refuses."""

    acceptance: tuple[Offer, ...]
    terms: frozenset[Proc]


def tock_groups(mon: Monitor, sem: Semantics, state: int, channels: list[Channel]) -> tuple[TockGroup, ...]:
    """The groups of a monitor state's stable terms that can let time pass."""
    if state == Monitor.DEAD:
        return ()
    found: dict[tuple[Offer, ...], set[Proc]] = {}
    for p in mon.states[state]:
        if not sem.stable(p) or not sem.after(p, TOCK):
            continue
        acc = tuple(o for o in acceptance(mon, sem, state, p, channels)
                    if o.channel is None or channels[o.channel].prefix != TOCK)
        found.setdefault(acc, set()).add(p)
    if len(found) > MAX_GROUPS:
        raise Unsupported(None, f"the specification has more than {MAX_GROUPS} stable states with different "
                                "acceptances after one trace, too many to follow in the tick-tock model")
    return tuple(TockGroup(acc, frozenset(ps)) for acc, ps in sorted(found.items(), key=lambda kv: repr(kv[0])))


def kept_after(mon: Monitor, state: int, groups: tuple[TockGroup, ...], kept: frozenset[int]) -> int:
    """The monitor state after a tock that the groups `kept` (their indices) can take."""
    return mon.after_tock(state, (p for i in sorted(kept) for p in groups[i].terms))


class TickTockMonitor(MonitorExtension):
    """The specification's monitor beside the model, its tocks filtered by the model's refusals."""

    def __init__(self, system: TransitionSystem, context: Context):
        self.groups: dict[int, tuple[TockGroup, ...]] = {}
        self.tock_next: dict[int, dict[frozenset[int], int]] = {}
        refuse_context(context.impl, MODELS)
        super().__init__(system, context)
        self.refusals = Refusals(self, False, context.spec_name, MODELS)

    def _explore(self) -> dict[tuple[int, int], list[tuple[tuple, int]]]:
        sem = self.context.sem
        tock = [c for c, ch in enumerate(self.channels) if ch.prefix == TOCK]

        def tocks(s: int) -> None:
            if not tock:  # tock hidden: nothing to filter
                return
            groups = self.groups[s] = tock_groups(self.monitor, sem, s, self.channels)
            self.tock_next[s] = {frozenset(k): kept_after(self.monitor, s, groups, frozenset(k))
                                 for n in range(len(groups) + 1) for k in itertools.combinations(range(len(groups)), n)}

        return self.monitor.table(tocks)

    def keeps(self, system: TransitionSystem, s: int, g: TockGroup) -> z3.BoolRef:
        """The model, now, refuses nothing the group accepts (so the group's terms can match its refusal)."""
        return z3.And([z3.Not(self.refusals.refuses(system, s, o)) for o in g.acceptance])

    def _next(self, system: TransitionSystem, s: int, c: int, values: list) -> z3.ArithRef:
        if self.channels[c].prefix != TOCK:
            return self._delta(s, c, values)
        keeps = [self.keeps(system, s, g) for g in self.groups[s]]

        def decide(i: int, kept: frozenset[int]) -> z3.ArithRef:
            if i == len(keeps):
                return z3.IntVal(self.tock_next[s][kept])
            return z3.If(keeps[i], decide(i + 1, kept | {i}), decide(i + 1, kept))

        return decide(0, frozenset())

    def tock_refusal(self, unroller: Unroller, model: z3.ModelRef, k: int) -> list[str]:
        """Before a tock at step k that no state of the specification can match: per group of stable
        terms that can let time pass, an event it accepts that the model refuses."""
        system = unroller.system
        s = number_at(unroller, model, system.cur[names.MONITOR], k)
        shown = []
        for g in self.groups.get(s, ()):
            o = next((o for o in g.acceptance if true_at(unroller, model, self.refusals.refuses(system, s, o), k)),
                     None)
            if o is not None:
                shown.append(offer_text(self.channels, o))
        return sorted(set(shown))


# ------------------------------------------------------------------ the specification on the left

@dataclass(frozen=True)
class Observation:
    """A tick-tock observation of the specification to be matched by the model: its events, and
    for each tock among them (by position) the acceptance the model must stay within when it
    takes it (everything else refused), as a `SpecRefusal` naming the monitor state there; and the
    monitor state after it."""

    events: tuple[tuple, ...]
    tocks: tuple[tuple[int, SpecRefusal], ...]
    state: int
    ticks: bool = False  # the specification can terminate after it
    maximal: bool = False  # no event follows within the length listed, or it can terminate


def tock_refusals(mon: Monitor, sem: Semantics, state: int, channels: list[Channel],
                  events: tuple[tuple, ...]) -> list[tuple[SpecRefusal, int]]:
    """The refusals the specification can show before a tock from a monitor state, each with the
    state after the tock.  A refusal `X` can be made by a stable term that can tock and accepts
    nothing in `X`; the terms that go on are all those accepting nothing in `X`.  So the refusals
    that matter are the complements of unions `U` of the groups' acceptances: each keeps the groups
    within `U`, and the model must offer nothing outside `U` (and `tock`).  An empty refusal
    (no refusal observed) keeps every group and asks less of the model than the largest union."""
    groups = tock_groups(mon, sem, state, channels)
    tock = [Offer(c) for c, ch in enumerate(channels) if ch.prefix == TOCK]
    out: dict[frozenset[Offer], tuple[SpecRefusal, int]] = {}
    for n in range(1, len(groups) + 1):
        for chosen in itertools.combinations(range(len(groups)), n):
            union = frozenset(o for i in chosen for o in groups[i].acceptance)
            if union in out:
                continue
            kept = frozenset(i for i, g in enumerate(groups) if set(g.acceptance) <= union)
            nxt = kept_after(mon, state, groups, kept)
            out[union] = (SpecRefusal(events, state, tuple(sorted(union, key=repr)) + tuple(tock)), nxt)
    return list(out.values())


def spec_observations(mon: Monitor, sem: Semantics, channels: list[Channel], length: int) -> list[Observation]:
    """Every observation of the specification with at most `length` events (each tock with each
    refusal that matters, `tock_refusals`), shortest first; `maximal` marks those no event follows
    within the length and those after which the specification can terminate.  Raises
    `Unsupported` past `OBSERVATIONS_CAP`."""
    out: list[Observation] = []
    todo = [Observation((), (), mon.initial)]
    while todo:
        o = todo.pop()
        nexts: list[Observation] = []
        if len(o.events) < length:
            nexts += [Observation((*o.events, e), o.tocks, s) for e, s in next_events(mon, sem, o.state) if e != TOCK]
            nexts += [Observation((*o.events, TOCK), (*o.tocks, (len(o.events), r)), s)
                      for r, s in tock_refusals(mon, sem, o.state, channels, o.events) if s != Monitor.DEAD]
        ticks = mon.can_tick(o.state)
        out.append(Observation(o.events, o.tocks, o.state, ticks, ticks or not nexts))
        if len(out) > OBSERVATIONS_CAP:
            raise TooManyObservations(None, f"the specification has more than {OBSERVATIONS_CAP} tick-tock observations "
                                    f"of up to {length} events, too many to list")
        todo += nexts
    return sorted(out, key=lambda o: (len(o.events), repr(o.events), repr(o.tocks)))


def observation_checks(mon: Monitor, sem: Semantics, channels: list[Channel], length: int, cap: int = OBSERVATIONS_CAP
                       ) -> tuple[list[Observation], list[tuple[Observation, SpecRefusal | None]], int]:
    """What the model must show, with the specification on the left: each maximal observation (to
    be made, refusals before tocks included) and each observation with each stable refusal at its
    end.  Each tock multiplies the observations by the refusals that matter there, so the length is
    cut (as `spec_traces` cuts it) until there are at most `cap` checks; returns the observations,
    the checks and the length they cover."""
    while length >= 1:
        try:
            observations = spec_observations(mon, sem, channels, length)
        except TooManyObservations:
            length -= 1
            continue
        checks: list[tuple[Observation, SpecRefusal | None]] = [(o, None) for o in observations if o.maximal]
        checks += [(o, r) for o in observations for r in final_refusals(mon, sem, channels, o)]
        if len(checks) <= cap:  # the fewest events first, so that a failure is shown as short as it is found
            return observations, sorted(checks, key=lambda c: (len(c[0].events), c[1] is not None)), length
        length -= 1
    raise TooManyObservations(None, f"the specification has more than {cap} tick-tock observations and refusals "
                                    "of one event, too many to list")


def final_refusals(mon: Monitor, sem: Semantics, channels: list[Channel], o: Observation) -> list[SpecRefusal]:
    """The specification's stable refusals at the end of an observation: per stable term there, its
    acceptance (the model must be stable, short of termination, offering nothing outside it)."""
    if o.state == Monitor.DEAD:
        return []
    accs = dict.fromkeys(acceptance(mon, sem, o.state, p, channels) for p in mon.states[o.state] if sem.stable(p))
    return [SpecRefusal(o.events, o.state, acc) for acc in accs]


def observation_steps(o: Observation, channels: list[Channel], spec_name: str, ticks: bool) -> tuple[TraceStep, ...]:
    """An observation as trace steps (then ✓ if `ticks`), each tock's note naming the acceptance it
    carries."""
    tocks = dict(o.tocks)
    shown = [_event_text(e) for e in o.events] + (["✓"] if ticks else [])
    return tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event",
                           f"a trace of {spec_name}" + (f", stable accepting {acceptance_text(channels, tocks[j].acceptance)}"
                                                        f" before the tock" if j in tocks else ""), {}, {})
                 for j, e in enumerate(shown))


def tock_refusal_list(o: Observation, channels: list[Channel]) -> list[dict[str, object]]:
    """The refusals an observation of the specification carries before its tocks, as the results'
    `tock_refusals` give them (by step: what may be offered there, everything else refused)."""
    return [{"step": j + 1, "offered": [offer_text(channels, x) for x in r.acceptance]} for j, r in o.tocks]
