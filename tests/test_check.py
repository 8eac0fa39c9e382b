"""The checker on the IntelliWelder example and on small machines, verdicts and traces by hand."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import COUNTER, SHARED, write_files

import tockbmc
from tockbmc.check import check
from tockbmc.cli import cli
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.result import NO_STEPS

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"
NOMINAL = Ranges({"core_int": Range(Fraction(0), Fraction(2)), "core_real": Range(Fraction(-1), Fraction(1))})
REALISTIC = Ranges({"core_int": Range(Fraction(-1), Fraction(1)), "core_real": Range(Fraction(-1), Fraction(1))})


@pytest.fixture(scope="module")
def project() -> tockbmc.Project:
    return tockbmc.load(EXAMPLE)


def events(result) -> list[str]:
    return [s.event for s in result.trace if s.kind != "internal"]


@pytest.mark.parametrize("ranges", [REALISTIC, Ranges()], ids=["-1..1", "unbounded"])
@pytest.mark.parametrize("name,machine", [("A5", "EXAX"), ("A6", "UR")])
def test_negative_time_leads_to_termination(project, ranges, name, machine) -> None:
    [r] = check(project, [name], bound=40, ranges=ranges)
    assert r.verdict == "violated"
    evs = events(r)
    assert evs[0].startswith(f"{machine}::move.in.(") and "time=-" in evs[0]
    assert evs[1:] == [f"{machine}::out_of_sync.out", f"{machine}::terminate"]
    assert r.trace[-1].states == {machine: "terminated"}


@pytest.mark.parametrize("name", ["A5", "A6"])
def test_nominal_times_never_terminate(project, name) -> None:
    # The default bound (40) is exercised by benchmarks/bmc_growth.py; a shorter one keeps tests fast.
    [r] = check(project, [name], bound=14, ranges=NOMINAL)
    assert r.verdict == "holds"
    assert r.bound == 14 and r.ranges == {"core_int": "0..2", "core_real": "-1..1"}


@pytest.mark.parametrize("ranges, expected", [
    (NOMINAL, dict.fromkeys(["A1", "A2", "A3", "A4", "A7"], "holds")),
    (REALISTIC, {"A1": "violated", "A2": "violated", "A3": "violated", "A4": "violated", "A7": "holds"}),
])
def test_paper_csp_assertions(project, ranges, expected) -> None:
    # The paper's Tables 1 and 2 for the CSP-block assertions (A5 and A6 are tested above).
    results = {r.assertion: r.verdict for r in check(project, list(expected), bound=12, ranges=ranges)}
    assert results == expected


def test_a1_counterexample_is_a_tock_before_go_to_pos(project) -> None:
    [r] = check(project, ["A1"], bound=12, ranges=REALISTIC)
    visible = [s.event for s in r.trace if s.kind != "internal"]
    assert visible[0].startswith("EXAX::move.in.(") and "time=-1" in visible[0]
    assert visible[-1] == "tock" and not any("go_to_posCall" in e for e in visible)


def test_cli_json_and_exit_status() -> None:
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A5", "--range", "core_int=-1..1",
                                      "--format", "json"])
    assert result.exit_code == 10, result.output
    data = json.loads(result.output)
    [r] = data["results"]
    assert r["verdict"] == "violated" and r["engine"] == "bmc" and r["proof"] == "trace" and r["bound"] == 40 and r["depth"] == len(r["trace"])
    assert [s["event"] for s in r["trace"] if s["kind"] == "event"][-1] == "EXAX::terminate"
    assert data["summary"]["violated"] == 1


def test_cli_unsupported_only_exits_20(tmp_path) -> None:
    machine(tmp_path, "stm M {\n initial i\n state s {}\n transition t { from i to s }\n}\n",
            "untimed assertion U: M is timelock-free.\n")
    result = CliRunner().invoke(cli, ["check", str(tmp_path)])
    assert result.exit_code == 20, result.output


@pytest.mark.parametrize("args", [["--range", "core_int=2..1"], ["--range", "core_int"], ["-a", "A9"],
                                  ["--set", "n=abc"]])
def test_cli_usage_errors_exit_2(args) -> None:
    assert CliRunner().invoke(cli, ["check", str(EXAMPLE), *args]).exit_code == 2


def machine(tmp_path: Path, body: str, assertions: str) -> tockbmc.Project:
    (tmp_path / "m.rct").write_text(body)
    (tmp_path / "m.assertions").write_text(assertions)
    return tockbmc.load(tmp_path)


def test_final_state_refuses_tock_after_terminate(tmp_path) -> None:
    # §2.8: terminate is offered (tock may come first), then the machine refuses tock: a timelock.
    p = machine(tmp_path, "stm M {\n initial i\n final f\n transition t { from i to f }\n}\n",
                "assertion T: M is timelock-free.\n")
    [r] = check(p, bound=10)
    assert r.verdict == "violated"
    assert events(r) == ["M::terminate"]


def test_operation_call_is_urgent(tmp_path) -> None:
    # §2.2: a platform call has deadline 0, so the stable configuration before it refuses tock.
    p = machine(tmp_path, "interface I { op() }\nstm M {\n requires I\n initial i\n state s { entry op() }\n"
                " transition t { from i to s }\n}\n", "assertion T: M is timelock-free.\n")
    [r] = check(p, bound=10)
    assert r.verdict == "violated"
    assert events(r) == []


def test_outputs_are_not_urgent_and_wait_counts_tocks(tmp_path) -> None:
    # §2.4 and §2.9: `wait(2); e` lets exactly two tocks pass, then e may wait for the environment.
    p = machine(tmp_path, "stm M {\n event e\n initial i\n state s { entry wait(2) ; e }\n"
                " state u {}\n transition t { from i to s }\n transition t2 { from s to u }\n}\n",
                "assertion R: u is reachable in M.\n")
    [r] = check(p, bound=20)
    assert r.verdict == "holds"
    assert events(r) == ["tock", "tock", "M::e.out"]


def test_guarded_input_accepts_only_values_meeting_the_condition(tmp_path) -> None:
    # §2.5: e?x with condition x > 5 only accepts such values; reaching `big` needs one.
    p = machine(tmp_path, "stm M {\n var x : int\n event e : int\n initial i\n state s {}\n state big {}\n"
                " transition t { from i to s }\n transition t2 { from s to big trigger e?x condition x > 5 }\n}\n",
                "assertion R: big is reachable in M.\nassertion N: big is not reachable in M.\n")
    results = {r.assertion: r for r in check(p, bound=10, ranges=Ranges({"core_int": Range(Fraction(0),
                                                                                          Fraction(5))}))}
    # k-induction shows `big` is never entered, so the positive form is violated outright.
    assert results["R"].verdict == "violated" and "any length" in (results["R"].reason or "")
    assert results["N"].verdict == "holds"
    results = {r.assertion: r for r in check(p, bound=10)}
    assert results["R"].verdict == "holds" and results["N"].verdict == "violated"
    [ev] = events(results["N"])
    assert ev.startswith("M::e.in.") and int(ev.rsplit(".", 1)[1]) > 5


def test_input_fields_the_violation_does_not_need_are_marked() -> None:
    """A1 breaks on a negative time budget whatever the distance: only `time` matters."""
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A1", "--range", "core_int=-1..1",
                                      "--range", "core_real=-1..1", "--format", "json"])
    [r] = json.loads(result.output)["results"]
    [move] = [s for s in r["trace"] if s["event"] and s["event"].startswith("EXAX::move.in")]
    assert move["free_fields"] == ["dist"]
    assert move["source"].endswith("intelliwelder.rct:243:3") or ":243:" in move["source"]
    assert "(dist: any value)" in CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A1", "--range",
                                                           "core_int=-1..1", "--range", "core_real=-1..1"]).output


def test_a_counterexample_in_a_module_starts_from_the_values_bmc_chose() -> None:
    """robocert-evaluation's Foraging (a module of two controllers, machines with variables
    without initial values): BMC's timelock of `Foraging is timelock-free` under RoboTool's ranges
    was named `ForagingC::DTP.source` and so on, which the interpreter did not find under its own
    names for them (`ForagingC.DTP`); it tried every start (234,375 of them), gave up past its
    limit and reported a failure to follow (exit 1).  The counterexample is now replayed from the
    one start BMC chose, in the open reading, where those variables start anywhere.  (Both engines
    find the timelock: DTP's `during Explore()` calls an operation, which is urgent, while
    PositionEstimation waits.)"""
    import dataclasses

    from tockbmc.model.config import ROBOTOOL_RANGES, configure
    from tockbmc.model.core import core_assertions
    from tockbmc.model.readings import Reading
    project = tockbmc.load(SHARED / "realworld" / "UoY-RoboStar+robocert-evaluation" / "foraging")
    project = dataclasses.replace(project, assertions=core_assertions(project))
    config = configure(project, default_ranges=ROBOTOOL_RANGES, reading=Reading.OPEN)
    [r] = check(config.project, ["Foraging_timelock_free"], bound=40, config=config, timeout=60)
    assert r.verdict == "violated" and r.extra.get("replayed") == "yes", r.reason


def test_a_bound_of_zero_steps_claims_nothing(tmp_path: Path) -> None:
    """`-k 0` searches no step: a `holds` within it is `unknown` with the reason, in both engines,
    while a proof for every length still stands (and `-k 1` searches one step)."""
    write_files(tmp_path, {"c.rct": COUNTER, "c.assertions": "assertion N: Counter does not terminate.\n"
                                                           "assertion D: Counter is divergence-free.\n"})
    project = tockbmc.load(tmp_path)
    ranges = Ranges({"core_int": Range(Fraction(-1), Fraction(3)), "core_nat": Range(Fraction(0), Fraction(3))})
    for results in (check(project, bound=0, timeout=60, induction=False),
                    check_explicit(project, None, 0, ranges, {}, 60, 100_000)):
        by = {r.assertion: r for r in results}
        assert by["N"].verdict == "unknown" and by["N"].reason == NO_STEPS, by["N"].reason
    proved = {r.assertion: r for r in check(project, bound=0, timeout=60)}
    assert proved["D"].verdict == "holds" and proved["D"].proof.every_length
    [n1] = check(project, ["N"], bound=1, timeout=60, induction=False)
    assert n1.verdict == "holds" and n1.proof == "bounded"
