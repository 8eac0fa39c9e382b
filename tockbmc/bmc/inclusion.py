"""Every trace of a specification is one of the model's: one BMC search per listed trace.

For each maximal trace of the specification (`properties.inclusion.spec_traces`),
BMC asks whether the element can perform it, a `TraceFollower` beside it.  A
trace the element provably cannot perform (k-induction shows the end of the
trace unreachable) is a violation, shown as its shortest prefix that fails;
one the element is not shown to perform within the bound leaves the verdict
unknown.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import TypeVar

import z3

from tockbmc.bmc.engine import Outcome, Progress, Status, bmc, bmc_each, spent
from tockbmc.encodings.system import Target, TransitionSystem
from tockbmc.model.errors import Unsupported
from tockbmc.model.result import TraceStep, Verdict
from tockbmc.properties.deadlock import may_diverge
from tockbmc.properties.failures import SpecRefusal, acceptance_text, divergent_state, offers_within, spec_refusals
from tockbmc.properties.inclusion import INCLUSION_LENGTH, SpecTrace, TraceFollower, followed, spec_traces
from tockbmc.properties.process import _event_text, alphabet_of, channels_of
from tockbmc.properties.spec import Monitor, Proc, Semantics
from tockbmc.properties.ticktock import (
    TICK_TOCK,
    Observation,
    observation_checks,
    observation_steps,
    tock_refusal_list,
)

Make = Callable[[Callable[[TransitionSystem], TraceFollower]], TransitionSystem]


@dataclass
class Inclusion:
    verdict: Verdict  # holds, violated or unknown
    reason: str
    trace: tuple[TraceStep, ...] = ()
    extra: dict[str, object] = field(default_factory=dict)  # more for the result (tick-tock: `tock_refusals`)
    unlisted: bool = False  # unknown because the specification's traces or refusals are too many to list


def _following(make: Make, t: SpecTrace) -> TransitionSystem:
    return make(lambda s: TraceFollower(s, t))


def _shortest_failing_prefix(make: Make, t: SpecTrace, bound: int, timeout: Callable[[], float | None],
                             progress: Progress | None) -> SpecTrace:
    """The shortest prefix of t that the element provably cannot perform (t itself if none shorter)."""
    for n in range(1, len(t.events) + 1):
        if spent(timeout):
            break
        prefix = SpecTrace(t.events[:n], t.ticks and n == len(t.events))
        if bmc(_following(make, prefix), followed, bound, timeout(), induction=True,
               progress=progress).status == Status.PROVED:
            return prefix
    return t


def _performs(make_system: Callable[[], TransitionSystem], target: Target, bound: int,
              timeout: Callable[[], float | None], progress: Progress | None) -> Outcome:
    """Whether the element can perform what the specification does (reach `target`): searched first
    without trying k-induction at each depth, since the element usually can and the proofs are most
    of the cost; only a search that finds nothing is repeated with k-induction, which may show that
    no number of steps reaches it.  Once the check's time is up, nothing is built (a system with a
    follower takes a while: a specification with a hundred observations overran a 3 s timeout by 50 s)."""
    if spent(timeout):
        return Outcome(Status.UNKNOWN, 0, reason="out of time")
    system = make_system()
    quick = bmc(system, target, bound, timeout(), induction=False, progress=progress)
    if quick.status != Status.NOT_FOUND:  # found, or out of time, or Z3 gave up: induction would not help
        return quick
    return bmc(system, target, bound, timeout(), induction=True, progress=progress)


def included(make: Make, sem: Semantics, spec: Proc, spec_name: str, element: str, bound: int,
             timeout: Callable[[], float | None], cap: int = 256, progress: Progress | None = None,
             refusals: str | None = None) -> Inclusion:
    """Whether every trace of `spec` (up to a length) is one of the element's; with `refusals` (the
    failures model of the assertion), also every stable refusal of `spec` after those traces.

    `make(follower)` builds the element's system with a follower attached; `progress` is told each
    depth each search clears.
    """
    probe = _following(make, SpecTrace((), False))
    channels, _ = channels_of(probe)
    sem.alphabet = alphabet_of(probe)
    wanted = max(1, min(INCLUSION_LENGTH, bound // 2))
    if refusals == TICK_TOCK:
        return _observations(make, sem, spec, spec_name, element, wanted, bound, timeout, progress)
    traces, length = spec_traces(sem, spec, channels, wanted, cap)
    if length < wanted:
        return Inclusion(Verdict.UNKNOWN, f"{spec_name} has more than {cap} traces of {wanted} events; only those "
                                          f"of up to {length} events could be listed, which gives no verdict",
                         unlisted=True)
    for t in traces:
        outcome = _performs(partial(_following, make, t), followed, bound, timeout, progress)
        if outcome.status == Status.FOUND:
            continue
        if outcome.status == Status.PROVED:
            t = _shortest_failing_prefix(make, t, bound, timeout, progress)
        shown = [_event_text(e) for e in t.events] + (["✓"] if t.ticks else [])
        steps = tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", f"a trace of {spec_name}", {}, {})
                      for j, e in enumerate(shown))
        if outcome.status == Status.PROVED:
            return Inclusion(Verdict.VIOLATED, f"{spec_name} has this trace and {element} cannot perform it in any "
                                               f"number of steps ({outcome.reason})", steps)
        why = outcome.reason if outcome.status == Status.UNKNOWN else f"not within {bound} steps"
        return Inclusion(Verdict.UNKNOWN, f"{spec_name} has this trace and {element} was not shown to perform it "
                                          f"({why})", steps)
    if refusals:
        return _refusals(make, sem, spec, spec_name, element, [t.events for t in traces], length, bound, timeout,
                         progress, refusals)
    return Inclusion(Verdict.HOLDS, f"every trace of {spec_name} with up to {length} events is a trace of {element} "
                                    f"({len(traces)} traces listed, each performed within {bound} steps)")


def _refusals(make: Make, sem: Semantics, spec: Proc, spec_name: str, element: str, traces: list[tuple[tuple, ...]],
              length: int, bound: int, timeout: Callable[[], float | None], progress: Progress | None,
              model: str) -> Inclusion:
    """In the failures models: after each listed trace, each stable refusal of the specification is
    one of the element's (docs/semantics.md §7.12).  `model` is the assertion's model; in the
    failures-divergences model a divergence of the element after the trace would allow every
    refusal, so a missing one is a violation only when the element cannot diverge."""
    probe = _following(make, SpecTrace((), False))
    channels, channel_of = channels_of(probe)
    mon = Monitor(sem, spec, channels)
    if model == "failures divergences":
        mon.table()  # every reachable state
        if divergent_state(mon, sem) is not None:
            raise Unsupported(None, f"{spec_name} can diverge; refinement in the failures-divergences model "
                                    "against a divergent specification is not supported")
    wanted = spec_refusals(mon, sem, channels, traces)
    if len(wanted) > REFUSALS_CAP:
        return Inclusion(Verdict.UNKNOWN, f"{spec_name} has more than {REFUSALS_CAP} stable refusals after its traces "
                                          f"of up to {length} events, which gives no verdict", unlisted=True)
    def target_for(r: SpecRefusal) -> Target:
        return lambda s: z3.And(followed(s), offers_within(s, mon, r, channels, channel_of))

    def settle(r: SpecRefusal) -> Inclusion | None:
        """Refusal `r` searched on its own, where k-induction may show that none is reachable: None if made."""
        trace = SpecTrace(r.events, False)
        outcome = _performs(partial(_following, make, trace), target_for(r), bound, timeout, progress)
        if outcome.status == Status.FOUND:
            return None
        shown = [_event_text(e) for e in r.events]
        steps = tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", f"a trace of {spec_name}", {}, {})
                      for j, e in enumerate(shown))
        what = (f"{_after(r)} {spec_name} can be stable accepting {acceptance_text(channels, r.acceptance)}, "
                f"and {element}")
        if outcome.status == Status.PROVED:
            if model == "failures divergences" and may_diverge(_following(make, trace)):
                return Inclusion(Verdict.UNKNOWN, f"{what} has no stable configuration refusing the rest in any number "
                                                  f"of steps ({outcome.reason}), but it may diverge, which in the "
                                                  "failures-divergences model allows every refusal", steps)
            return Inclusion(Verdict.VIOLATED, f"{what} has no stable configuration, short of termination, refusing "
                                               f"everything else, in any number of steps ({outcome.reason})", steps)
        why = outcome.reason if outcome.status == Status.UNKNOWN else f"not within {bound} steps"
        return Inclusion(Verdict.UNKNOWN, f"{what} was not shown to refuse everything else in a stable configuration "
                                          f"({why})", steps)

    by_trace: dict[tuple, list[SpecRefusal]] = {}
    for r in wanted:
        by_trace.setdefault(tuple(r.events), []).append(r)
    failed = _first_failure([(partial(_following, make, SpecTrace(events, False)), group, [target_for(r) for r in group])
                             for events, group in by_trace.items()], settle, bound, timeout)
    if failed is not None:
        return failed
    return Inclusion(Verdict.HOLDS, f"every trace of {spec_name} with up to {length} events is a trace of {element}, "
                                    f"and each of its {len(wanted)} stable refusals after them one of {element}'s "
                                    f"({len(traces)} traces listed, each within {bound} steps)")


REFUSALS_CAP = 256

C = TypeVar("C")


def _first_failure(groups: list[tuple[Callable[[], TransitionSystem], list[C], list[Target]]],
                   settle: Callable[[C], Inclusion | None], bound: int,
                   timeout: Callable[[], float | None]) -> Inclusion | None:
    """The checks of one group (the refusals after one trace, the checks of one observation) are
    searched together on one unrolling of its system (`bmc_each`, built only while time is left);
    a check not made there is settled on its own at once (`settle`: k-induction may show that it
    cannot be made), and the first that fails ends the search, before the groups after it."""
    for system, members, targets in groups:
        shared = [False] * len(members) if spent(timeout) else bmc_each(system(), targets, bound, timeout())
        for m, ok in zip(members, shared, strict=True):
            failed = None if ok else settle(m)
            if failed is not None:
                return failed
    return None


def _observations(make: Make, sem: Semantics, spec: Proc, spec_name: str, element: str, length: int, bound: int,
                  timeout: Callable[[], float | None], progress: Progress | None) -> Inclusion:
    """In the tick-tock model (docs/semantics.md §7.13): every observation of the specification with
    up to `length` events is one of the element's.  The element must perform each maximal one, at
    each tock stable and offering nothing outside the acceptance the observation gives there
    (`ticktock.tock_refusals`), and after each observation make each of the specification's
    stable refusals there (stable, short of termination, offering nothing outside it)."""
    probe = _following(make, SpecTrace((), False))
    channels, channel_of = channels_of(probe)
    mon = Monitor(sem, spec, channels)
    observations, checks, length = observation_checks(mon, sem, channels, length)

    def refused_before(r: SpecRefusal) -> Callable[[TransitionSystem], z3.BoolRef]:
        return lambda s: offers_within(s, mon, r, channels, channel_of)

    def system_for(o: Observation, ticks: bool) -> TransitionSystem:
        guards = {j: refused_before(r) for j, r in o.tocks}
        return make(lambda s: TraceFollower(s, SpecTrace(o.events, ticks), guards))

    def target_for(r: SpecRefusal | None) -> Target:
        return lambda s: (z3.And(followed(s), offers_within(s, mon, r, channels, channel_of)) if r is not None
                          else followed(s))

    def settle(n: int) -> Inclusion | None:
        """Check `n` on its own, where k-induction may show that it cannot be made: None if made."""
        o, r = checks[n]
        ticks = o.ticks and o.maximal and r is None  # the element must then terminate too
        outcome = _performs(partial(system_for, o, ticks), target_for(r), bound, timeout, progress)
        if outcome.status == Status.FOUND:
            return None
        steps = observation_steps(o, channels, spec_name, ticks)
        seen: dict[str, object] = {"tock_refusals": tock_refusal_list(o, channels)}
        what = (f"{spec_name} has this observation{' and then terminates' if ticks else ''}"
                + (f", stable at its end accepting {acceptance_text(channels, r.acceptance)}" if r is not None else "")
                + f", and {element}")
        if outcome.status == Status.PROVED:
            return Inclusion(Verdict.VIOLATED, f"{what} cannot make it (the refusals before its tocks included) in any "
                                               f"number of steps ({outcome.reason})", steps, seen)
        why = outcome.reason if outcome.status == Status.UNKNOWN else f"not within {bound} steps"
        return Inclusion(Verdict.UNKNOWN, f"{what} was not shown to make it ({why})", steps, seen)

    groups: dict[tuple[int, bool], list[int]] = {}
    for n, (o, r) in enumerate(checks):
        groups.setdefault((id(o), o.ticks and o.maximal and r is None), []).append(n)
    failed = _first_failure([(partial(system_for, checks[members[0]][0], ticks), members,
                              [target_for(checks[n][1]) for n in members])
                             for (_o, ticks), members in groups.items()], settle, bound, timeout)
    if failed is not None:
        return failed
    return Inclusion(Verdict.HOLDS, f"every tick-tock observation of {spec_name} with up to {length} events is one of "
                                    f"{element}'s: {sum(1 for o in observations if o.maximal)} observations listed, "
                                    f"each with the refusals before its tocks, and {len(checks)} checks in all, each "
                                    f"within {bound} steps")


def _after(r: SpecRefusal) -> str:
    return "after this trace" if r.events else "at the start"
