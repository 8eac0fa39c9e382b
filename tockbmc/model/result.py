"""The verdict of one assertion: what every engine returns and every printer reads.

`Verdict` and `Proof` are the contract's vocabulary.  A verdict carries the
exit status it gives `tockbmc check` (as CrossHair's message types carry
theirs); a proof kind says how far a verdict that holds reaches: up to the bound, or for
runs of every length (and by what argument).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from enum import StrEnum
from typing import Any

from tockbmc.model.readings import Reading


class Verdict(StrEnum):
    """The outcome of one assertion (a `str`, so JSON and text print its value)."""

    HOLDS = "holds"
    VIOLATED = "violated"
    UNKNOWN = "unknown"
    UNSUPPORTED = "unsupported"
    INTERRUPTED = "interrupted"  # Ctrl-C came before a verdict

    @property
    def exit_code(self) -> int:
        """The exit status of a run whose worst verdict is this one."""
        return {Verdict.HOLDS: 0, Verdict.VIOLATED: 10, Verdict.UNKNOWN: 20, Verdict.UNSUPPORTED: 20,
                Verdict.INTERRUPTED: 130}[self]

    @property
    def severity(self) -> int:
        """Which verdict decides a run's exit status: a violation over an unknown over a hold."""
        return {Verdict.HOLDS: 0, Verdict.UNKNOWN: 1, Verdict.UNSUPPORTED: 1, Verdict.VIOLATED: 2,
                Verdict.INTERRUPTED: 3}[self]

    @property
    def opposite(self) -> Verdict:
        """`holds` for `violated` and back (a negated assertion); others stay."""
        return {Verdict.HOLDS: Verdict.VIOLATED, Verdict.VIOLATED: Verdict.HOLDS}.get(self, self)


def exit_code(verdicts: Iterable[Verdict]) -> int:
    """0 when every assertion holds, 10 when some is violated, 20 when none is but some is undecided."""
    worst = max(verdicts, key=lambda v: v.severity, default=Verdict.HOLDS)
    return worst.exit_code


class Proof(StrEnum):
    """How a verdict was established."""

    BOUNDED = "bounded"  # holds for every run of up to `bound` steps
    K_INDUCTION = "k-induction"  # holds for runs of every length: the property is k-inductive
    INVARIANT = "invariant"  # holds for runs of every length: an inductive invariant (PDR) excludes a violation
    EXHAUSTIVE = "exhaustive"  # every reachable configuration was explored (explicit engine)
    ABSTRACTION = "abstraction"  # holds for runs of every length: the model with its data ignored has no such run
    TRACE = "trace"  # decided by the trace shown (a counterexample or a witness)
    NONE = "none"  # undecided, or not checked

    @property
    def every_length(self) -> bool:
        """Whether the verdict covers runs of every length, not only those up to the bound."""
        return self in (Proof.K_INDUCTION, Proof.INVARIANT, Proof.EXHAUSTIVE, Proof.ABSTRACTION)


@dataclass(frozen=True)
class TraceStep:
    step: int
    event: str | None  # FDR's name for the event; None for an internal step
    kind: str  # event | tock | internal
    note: str  # for internal steps: what happened (transition, entry, assignment…)
    states: dict[str, str]  # machine -> active state (innermost) after the step
    changed: dict[str, str]  # variable -> new value
    channel: tuple = ()  # for an event: its channel as CSP names it, ("EXAX::move", "in"); ("tock",) for tock
    values: tuple = ()  # for an event: the values it carries, as Python values (for replay)
    source: str = ""  # where in the model the step comes from (`path:line:col` of a transition, statement…)
    free: tuple[str, ...] = ()  # for an input: the fields any value of which keeps the violation

    def to_json(self) -> dict[str, Any]:
        return {"step": self.step, "event": self.event, "kind": self.kind, "note": self.note, "states": self.states,
                "changed": self.changed, "source": self.source or None, "free_fields": list(self.free)}


@dataclass(frozen=True, kw_only=True)
class Result:
    assertion: str
    text: str
    verdict: Verdict
    bound: int | None  # the bound asked for (None: no search ran)
    ranges: dict[str, str]
    seconds: float
    reason: str | None = None
    trace: tuple[TraceStep, ...] = ()
    proof: Proof = Proof.BOUNDED
    engine: str = "bmc"
    depth: int | None = None  # how deep the search went: the trace's steps, the depth reached, or k of k-induction
    pos: str | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    constants: dict[str, str] = field(default_factory=dict)  # constant (owner::name) -> value, or "parameter (…)"
    sources: dict[str, dict[str, str]] = field(default_factory=dict)  # "ranges"/"constants"/"defaults" -> name -> source
    reading: str = "default"  # the model's reading: default | open | robotool (`model.readings.Reading`)
    # what the reading filled in that the verdict rests on: a variable's initial value, a function's
    # placeholder ("" where the function stays open under its contract), by qualified name
    defaults: dict[str, str] = field(default_factory=dict)
    # For a nondeterminism: the second run, with the visible events of `trace` but its last, ending
    # stable where that last event is refused.
    other_trace: tuple[TraceStep, ...] = ()
    # How the checked elements were read where RoboChart says more than the semantics checked: one
    # sentence per probabilistic junction they hold (`model.probabilistic.notes`)
    notes: tuple[str, ...] = ()

    @property
    def not_reproduced(self) -> tuple[str, ...]:
        """What of the result's reading tockbmc does not reproduce (`--robotool`'s list; none otherwise)."""
        return Reading(self.reading).not_reproduced

    def to_json(self) -> dict[str, Any]:
        return {
            "assertion": self.assertion, "text": self.text, "verdict": self.verdict.value,
            "proof": self.proof.value, "bound": self.bound, "depth": self.depth, "reading": self.reading,
            "not_reproduced": list(self.not_reproduced),
            "ranges": self.ranges, "constants": self.constants, "defaults": self.defaults, "sources": self.sources,
            "engine": self.engine,
            "seconds": round(self.seconds, 4), "reason": self.reason, "pos": self.pos,
            "trace": [s.to_json() for s in self.trace],
            **({"other_trace": [s.to_json() for s in self.other_trace]} if self.other_trace else {}),
            **({"notes": list(self.notes)} if self.notes else {}),
            **self.extra,
        }


NO_STEPS = ("a bound of 0 steps searches no step of any run, so a holds within it claims nothing: give a bound "
            "of 1 or more (-k/--bound)")


def within_no_steps(r: Result) -> Result:
    """`r`, but `unknown` where it holds only within a bound of 0 steps (a proof for every length,
    a trace or an exhaustive search still stands)."""
    if r.verdict == Verdict.HOLDS and r.proof == Proof.BOUNDED and r.bound == 0:
        return replace(r, verdict=Verdict.UNKNOWN, proof=Proof.NONE, reason=NO_STEPS)
    return r
