"""`P is divergence-free` (docs/semantics.md §7.9): no reachable endless run of internal steps.

A divergence is shown as a lasso (internal steps that come back to a configuration).  "Holds for
every length" needs either the model with its data ignored to have no cycle of internal steps, or
finitely many values in every variable: `x = x + 1` for ever is a divergence no lasso shows.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import tockbmc
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.result import Proof, Verdict

MODELS = Path(__file__).parent / "models" / "divergence"


@pytest.fixture(scope="module")
def bmc() -> dict:
    return {r.assertion: r for r in check(tockbmc.load(MODELS), bound=20)}


@pytest.fixture(scope="module")
def explicit() -> dict:
    return {r.assertion: r for r in check_explicit(tockbmc.load(MODELS), None, 8, None, {}, 20, 10_000)}


def test_an_internal_loop_is_a_divergence_shown_as_a_lasso(bmc: dict, explicit: dict) -> None:
    s1, s2 = bmc["S1"], bmc["S2"]
    assert (s1.verdict, s2.verdict) == (Verdict.VIOLATED, Verdict.HOLDS)
    assert [s.kind for s in s1.trace] == ["internal", "internal", "internal"]
    assert "steps 2–3 are internal and come back to the configuration after step 1" in (s1.reason or "")
    assert s1.extra["replayed"] == "yes"
    assert (explicit["S1"].verdict, explicit["S2"].verdict) == (Verdict.VIOLATED, Verdict.HOLDS)


def test_no_cycle_with_data_ignored_is_a_proof_for_every_length(bmc: dict, explicit: dict) -> None:
    for name, verdict in (("K1", Verdict.HOLDS), ("K2", Verdict.VIOLATED)):
        assert bmc[name].verdict == verdict and bmc[name].proof == Proof.ABSTRACTION, bmc[name]
        assert bmc[name].proof.every_length
        assert explicit[name].verdict == verdict and explicit[name].proof == Proof.EXHAUSTIVE


def test_a_guarded_loop_holds_only_to_the_bound_when_a_number_changes(bmc: dict, explicit: dict) -> None:
    """Count's loop stops when x reaches 3: no divergence.  BMC finds no lasso but, x being a number,
    does not claim every length; the explicit engine explores all 11 configurations."""
    c1, c2 = bmc["C1"], bmc["C2"]
    assert c1.verdict == Verdict.HOLDS and c1.proof == Proof.BOUNDED
    assert "Count.x can take ever new values" in (c1.reason or "")
    assert c2.verdict == Verdict.UNKNOWN
    assert explicit["C1"].verdict == Verdict.HOLDS and explicit["C1"].proof == Proof.EXHAUSTIVE
    assert explicit["C2"].verdict == Verdict.VIOLATED


def test_a_divergence_that_never_repeats_is_not_proved_away(bmc: dict) -> None:
    """Up counts for ever by internal steps: a divergence without a repeated configuration.  A proof
    that no lasso is reachable (Spacer finds one) said nothing about it, and was reported as 'holds for
    every length' for both divergence-free and deadlock-free."""
    for name in ("U1", "U2"):
        r = bmc[name]
        assert r.verdict == Verdict.HOLDS and not r.proof.every_length, (name, r.proof, r.reason)
    assert bmc["U3"].verdict == Verdict.UNKNOWN


def test_a_timelock_is_not_a_timed_deadlock() -> None:
    """docs/semantics.md §7.2: a timed deadlock is a configuration from which time passes for ever
    with nothing else offered (or a divergence).  Late's `wait(2) <{1}` refuses tock after one: a
    timelock, refusing everything, from which no run of tocks goes on.  RoboTool's check (tock given
    the lowest priority and hidden, then divergence-freedom) passes it too; both engines used to call
    it a deadlock."""
    project = tockbmc.load(Path(__file__).parent / "models" / "timelock")
    for results in (check(project, bound=10), check_explicit(project, None, 8, None, {}, 20, 10_000)):
        verdicts = {r.assertion: r.verdict for r in results}
        assert verdicts == {"D1": Verdict.HOLDS, "D2": Verdict.VIOLATED, "T1": Verdict.VIOLATED}


def test_a_replay_that_gives_up_reports_the_trace_not_replayed(monkeypatch: pytest.MonkeyPatch) -> None:
    """The interpreter looks for the lasso's cycle among at most `LIMIT` configurations; past that
    (as on a model with many internal configurations) it had raised `ReplayFailure`, an internal
    error. The counterexample is now shown with `replayed: no: …`, as where the interpreter cannot
    run the model."""
    from tockbmc.explicit import replay

    monkeypatch.setattr(replay, "LIMIT", 1)
    [s1] = [r for r in check(tockbmc.load(MODELS), bound=20) if r.assertion == "S1"]
    assert s1.verdict == Verdict.VIOLATED
    assert str(s1.extra["replayed"]).startswith("no: ") and "1 configurations" in str(s1.extra["replayed"])
