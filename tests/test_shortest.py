"""`--shortest events`: a counterexample with the fewest visible steps within the bound.

In this machine, the run of fewest steps to a timelock has two visible steps (`c` and the
termination that follows: a terminated machine refuses tock); a longer run of internal steps
reaches one with no visible step at all (state L's entry ends in an urgent platform call, so time
cannot pass).  The explicit engine finds the latter too.
"""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from tockbmc.cli import cli

MODEL = Path(__file__).parent / "models" / "fewest_events"


def _trace(*args: str) -> list[dict]:
    result = CliRunner().invoke(cli, ["check", str(MODEL), "--range", "core_int=-1..1", "-k", "16",
                                      "--format", "json", *args])
    assert result.exit_code == 10, result.output
    (only,) = json.loads(result.output)["results"]
    assert only["verdict"] == "violated"
    return only["trace"]


def _visible(trace: list[dict]) -> list[str]:
    return [s["event"] for s in trace if s["kind"] != "internal"]


def test_default_is_fewest_steps_and_events_is_fewest_visible() -> None:
    steps, events = _trace(), _trace("--shortest", "events")
    assert len(steps) < len(events)
    assert _visible(steps) == ["P::c.in", "P::terminate"]
    assert _visible(events) == []


def test_explicit_engine_agrees_on_the_fewest_visible() -> None:
    assert _visible(_trace("--engine", "explicit", "-k", "8")) == []
