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
from dataclasses import dataclass

from tockbmc.bmc.engine import Progress, Status, bmc
from tockbmc.encodings.system import TransitionSystem
from tockbmc.model.result import TraceStep, Verdict
from tockbmc.properties.inclusion import INCLUSION_LENGTH, SpecTrace, TraceFollower, followed, spec_traces
from tockbmc.properties.process import _event_text, alphabet_of, channels_of
from tockbmc.properties.spec import Proc, Semantics

Make = Callable[[Callable[[TransitionSystem], TraceFollower]], TransitionSystem]


@dataclass
class Inclusion:
    verdict: Verdict  # holds, violated or unknown
    reason: str
    trace: tuple[TraceStep, ...] = ()


def _following(make: Make, t: SpecTrace) -> TransitionSystem:
    return make(lambda s: TraceFollower(s, t))


def _shortest_failing_prefix(make: Make, t: SpecTrace, bound: int, timeout: Callable[[], float | None],
                             progress: Progress | None) -> SpecTrace:
    """The shortest prefix of t that the element provably cannot perform (t itself if none shorter)."""
    for n in range(1, len(t.events) + 1):
        prefix = SpecTrace(t.events[:n], t.ticks and n == len(t.events))
        if bmc(_following(make, prefix), followed, bound, timeout(), induction=True,
               progress=progress).status == Status.PROVED:
            return prefix
    return t


def included(make: Make, sem: Semantics, spec: Proc, spec_name: str, element: str, bound: int,
             timeout: Callable[[], float | None], cap: int = 256, progress: Progress | None = None) -> Inclusion:
    """Whether every trace of `spec` (up to a length) is one of the element's.

    `make(follower)` builds the element's system with a follower attached; `progress` is told each
    depth each search clears.
    """
    probe = _following(make, SpecTrace((), False))
    channels, _ = channels_of(probe)
    sem.alphabet = alphabet_of(probe)
    wanted = max(1, min(INCLUSION_LENGTH, bound // 2))
    traces, length = spec_traces(sem, spec, channels, wanted, cap)
    if length < wanted:
        return Inclusion(Verdict.UNKNOWN, f"{spec_name} has more than {cap} traces of {wanted} events; only those "
                                          f"of up to {length} events could be listed, which gives no verdict")
    for t in traces:
        outcome = bmc(_following(make, t), followed, bound, timeout(), induction=True, progress=progress)
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
    return Inclusion(Verdict.HOLDS, f"every trace of {spec_name} with up to {length} events is a trace of {element} "
                                    f"({len(traces)} traces listed, each performed within {bound} steps)")
