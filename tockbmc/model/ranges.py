"""Ranges: the bounds a user (or RoboTool's instantiation) puts on the values the environment supplies."""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from tockbmc.model.numbers import real_text


@dataclass(frozen=True)
class Range:
    """A closed interval bounding values the environment supplies."""

    low: Fraction
    high: Fraction

    def __str__(self) -> str:
        return f"{real_text(self.low)}..{real_text(self.high)}"


@dataclass(frozen=True)
class Ranges:
    """Ranges by built-in or model type name (`core_int`, `MyType`) and by path (`EXAX::move.time`)."""

    by_type: dict[str, Range] = field(default_factory=dict)
    by_path: dict[str, Range] = field(default_factory=dict)
    # Names (types or paths, as above) whose bounds are parameters: symbols rather than numbers,
    # so that one query covers every range (`tockbmc explore`).  They win over a range of the same name.
    parametric: tuple[str, ...] = ()
    # Whether the environment's reals are the integers of their range, as FDR's are (`--robotool`).
    integral_reals: bool = False

    def describe(self) -> dict[str, str]:
        return {**{k: str(v) for k, v in self.by_type.items()}, **{k: str(v) for k, v in self.by_path.items()},
                **{k: "parameter" for k in self.parametric}}


TYPE_RANGE_NAMES = {"int": "core_int", "nat": "core_nat", "real": "core_real"}


def is_path(name: str) -> bool:
    """A range name that is a path (`EXAX::move.time`) rather than a type (`core_int`, `Speed`)."""
    return "::" in name or "." in name
