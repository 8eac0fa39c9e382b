"""`P is deterministic` (docs/semantics.md §7.10): no trace after which an event is both possible and
stably refused, and no divergence.  BMC runs two copies of the model side by side with the same
visible trace (`bmc/determinism.py`); the explicit engine builds the sets of configurations after
each trace.  Both must agree, and BMC's two runs are replayed by the interpreter."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import run_cli

import tockbmc
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

MODELS = Path(__file__).parent / "models" / "determinism"


@pytest.fixture(scope="module")
def both() -> tuple[dict, dict]:
    project = tockbmc.load(MODELS)
    ranges = Ranges({"core_int": Range(-1, 1)})
    bmc = {r.assertion: r for r in check(project, bound=12, ranges=ranges)}
    explicit = {r.assertion: r for r in check_explicit(project, None, 8, ranges, {}, 30, 50_000)}
    return bmc, explicit


EXPECTED = {"N1": Verdict.VIOLATED, "N2": Verdict.HOLDS, "D1": Verdict.HOLDS, "W1": Verdict.VIOLATED,
            "V1": Verdict.HOLDS}


def test_both_engines_decide_determinism_alike(both: tuple[dict, dict]) -> None:
    bmc, explicit = both
    assert {k: r.verdict for k, r in bmc.items()} == EXPECTED
    assert {k: r.verdict for k, r in explicit.items()} == EXPECTED


def test_an_internal_choice_shows_two_runs_one_refusing_what_the_other_does(both: tuple[dict, dict]) -> None:
    r = both[0]["N1"]
    assert r.extra["replayed"] == "yes"
    last = r.trace[-1]
    assert last.event in ("ND::a.in", "ND::b.in") and r.other_trace
    assert [s.kind for s in r.other_trace] == ["internal", "internal"]
    refusing = r.other_trace[-1].states["ND"]
    assert refusing == ("s2" if last.event == "ND::a.in" else "s1")
    assert "after the empty trace" in (r.reason or "")


def test_a_nondeterministic_wait_is_nondeterminism_in_time(both: tuple[dict, dict]) -> None:
    """clocks2's case: `wait([1, 2])`: after one tock, one run can take `a`, the other still waits."""
    r = both[0]["W1"]
    assert r.extra["replayed"] == "yes"
    assert [s.event for s in r.trace if s.kind != "internal"] == ["tock", "W::a.in"]
    assert [s.event for s in r.other_trace if s.kind != "internal"] == ["tock"]


def test_values_a_run_starts_from_are_the_environments_not_a_nondeterminism(both: tuple[dict, dict]) -> None:
    """D outputs its uninitialised x first: each starting value is a process of its own, deterministic."""
    assert both[0]["D1"].verdict == Verdict.HOLDS and both[1]["D1"].verdict == Verdict.HOLDS


def test_json_carries_the_second_run() -> None:
    out = run_cli(["check", str(MODELS), "-a", "W1", "-k", "12", "--range", "core_int=-1..1", "--format", "json"])
    assert out.exit_code == 10, out.output
    [r] = json.loads(out.stdout)["results"]
    assert r["verdict"] == "violated" and r["replayed"] == "yes"
    assert [s["event"] for s in r["other_trace"] if s["kind"] != "internal"] == ["tock"]
