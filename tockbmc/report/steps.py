"""A trace read as a whole, for the tool formats: the values after each step, each step's label and place.

A decoded `TraceStep` carries the active state of every machine but only the
variables the step changed (step 1 also the declared initial values); the
formats for tools want the full configuration at every step, so the values are
carried forward here.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from tockbmc.model.result import TraceStep


class Place(NamedTuple):
    """A "path:line:col" position, split."""

    path: str
    line: int
    column: int


def place(text: str | None) -> Place | None:
    """`Place` of "path:line:col" (the path may hold colons), or None when there is none."""
    if not text:
        return None
    path, _, rest = text.rpartition(":")
    path, _, line = path.rpartition(":")
    if not path or not line.isdigit() or not rest.isdigit():
        return None
    return Place(path, max(1, int(line)), max(1, int(rest)))


def source(step: TraceStep) -> str:
    """The "path:line:col" of the model text behind a step, or "" (older traces have no `source`)."""
    return getattr(step, "source", "") or ""


def label(step: TraceStep) -> str:
    """What a step does, as one line: its event in FDR's naming, or `τ` and what the internal step did."""
    if step.event is not None:
        return step.event
    return f"τ {step.note}".rstrip()


def values_after_each_step(trace: Sequence[TraceStep]) -> list[dict[str, str]]:
    """For each step, every variable the trace has given a value so far, with its latest value (as text)."""
    current: dict[str, str] = {}
    out = []
    for step in trace:
        current = {**current, **step.changed}
        out.append(current)
    return out
