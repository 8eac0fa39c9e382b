"""The verdict of one assertion: what every engine returns and every printer reads."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


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


@dataclass(frozen=True)
class Result:
    assertion: str
    text: str
    verdict: str  # holds | violated | unknown | unsupported
    bound: int | None
    ranges: dict[str, str]
    seconds: float
    reason: str | None = None
    trace: tuple[TraceStep, ...] = ()
    proof: str = "bounded"
    engine: str = "bmc"
    pos: str | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    constants: dict[str, str] = field(default_factory=dict)  # constant (owner::name) -> value, or "parameter (…)"
    sources: dict[str, dict[str, str]] = field(default_factory=dict)  # "ranges"/"constants" -> name -> source

    def to_json(self) -> dict[str, Any]:
        return {
            "assertion": self.assertion, "text": self.text, "verdict": self.verdict, "proof": self.proof,
            "bound": self.bound, "ranges": self.ranges, "constants": self.constants, "sources": self.sources,
            "engine": self.engine, "seconds": round(self.seconds, 4),
            "reason": self.reason, "pos": self.pos,
            "trace": [{"step": s.step, "event": s.event, "kind": s.kind, "note": s.note, "states": s.states,
                       "changed": s.changed} for s in self.trace],
            **self.extra,
        }
