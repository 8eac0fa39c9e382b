"""What `tockbmc explore` finds for one assertion: the parameter values that break it, and the inputs."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from tockbmc.model.result import TraceStep


@dataclass(frozen=True)
class Carried:
    """The values one field of an input event takes in some shortest counterexample."""

    event: str  # `EXAX::move.in`
    field: str  # `time`, or "" for an event carrying one value
    condition: str  # over `value`... printed with the field's name: `time ≤ -1`, or "any"
    exact: bool = True  # False: the search stopped early; the condition is part of the values only


@dataclass(frozen=True)
class Exploration:
    """The region of parameter values where an assertion is violated (or, for an assertion a
    witness shows, where it holds), exact to the bound or for runs of every length."""

    assertion: str
    text: str
    pos: str
    status: str  # "region", "unknown" (the computation stopped early) or "unsupported"
    parameters: tuple[str, ...] = ()  # what varies: `core_int.low`, `UR::n_waypoints`
    fixed: dict[str, str] = field(default_factory=dict)  # ranges and constants held fixed, with their values
    fixed_here: dict[str, str] = field(default_factory=dict)  # those the assertion sets (`D__` arguments, `with constant`)
    assumed: tuple[str, ...] = ()  # what every point satisfies (`core_int.low ≤ core_int.high`)
    inside: str = "violated"  # the verdict inside the region ("holds" for a witness: `is reachable`)
    condition: str = ""  # the region, in the model's names; "false": nowhere, "true": everywhere
    independent: tuple[str, ...] = ()  # parameters the region does not depend on
    reach: str = ""  # "every length", "bound", or "partial" (inside is certain, outside unknown)
    proof: str = ""  # how "every length" was shown
    bound: int = 0
    depth: int | None = None  # steps of the shortest counterexample found
    point: dict[str, str] = field(default_factory=dict)  # the example's parameter values
    trace: tuple[TraceStep, ...] = ()  # the example, replayed
    replayed: str = ""
    carried: tuple[Carried, ...] = ()
    seconds: float = 0.0
    reason: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "assertion": self.assertion, "text": self.text, "pos": self.pos, "status": self.status,
            "parameters": list(self.parameters), "fixed": self.fixed, "fixed_here": self.fixed_here, "assumed": list(self.assumed),
            "inside": self.inside, "condition": self.condition, "independent": list(self.independent),
            "reach": self.reach, "proof": self.proof, "bound": self.bound, "depth": self.depth,
            "example": {"point": self.point, "trace": [s.to_json() for s in self.trace], "replayed": self.replayed}
            if self.trace else None,
            "inputs": [{"event": c.event, "field": c.field, "condition": c.condition, "exact": c.exact}
                       for c in self.carried],
            "seconds": round(self.seconds, 3), "reason": self.reason,
        }
