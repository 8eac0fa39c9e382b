"""The JSON contract (`tockbmc/report/results.schema.json`) and RoboTool's core assertions."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import jsonschema
import pytest
from conftest import COUNTER, EXAMPLE, run_cli, write_files

from tockbmc.report.results import schema


def _validate(document: dict) -> None:
    jsonschema.Draft202012Validator(schema()).validate(document)


def test_the_schema_is_a_valid_schema() -> None:
    jsonschema.Draft202012Validator.check_schema(schema())


def test_the_paper_example_validates() -> None:
    out = run_cli(["check", EXAMPLE, "--range", "core_int=-1..1", "--range", "core_real=-1..1", "--format", "json"])
    assert out.exit_code == 10 and out.crash is None
    document = json.loads(out.stdout)
    _validate(document)
    assert document["status"] == "checked" and document["summary"]["violated"] == 6
    a1 = document["results"][0]
    assert a1["proof"] == "trace" and a1["depth"] == len(a1["trace"]) and a1["replayed"] == "yes"
    a7 = document["results"][6]
    assert a7["verdict"] == "holds" and a7["proof"] in ("bounded", "k-induction", "invariant")


def test_a_result_proved_for_every_length_says_so() -> None:
    out = run_cli(["check", EXAMPLE, "-a", "A5", "--range", "core_int=0..2", "--range", "core_real=-1..1",
                   "--format", "json"])
    [a5] = json.loads(out.stdout)["results"]
    assert a5["verdict"] == "holds" and a5["proof"] in ("k-induction", "invariant") and a5["depth"] < a5["bound"]


def test_a_model_error_is_a_json_document_with_diagnostics(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": "stm M {\n  event stpo\n  initial i\n  state s {}\n"
                                    "  transition t { from i to s }\n  transition t1 { from s to s trigger stop }\n}\n"})
    out = run_cli(["check", tmp_path, "--format", "json"])
    assert out.exit_code == 3
    document = json.loads(out.stdout)
    _validate(document)
    assert document["status"] == "model-error" and document["results"] == []
    [d] = document["diagnostics"]
    assert (d["line"], d["column"], d["severity"]) == (6, 39, "error") and "did you mean 'stpo'" in d["message"]
    assert d["rule"] == "linking"  # the RoboTool rule it enforces, apart from the message


def test_explicit_and_unsupported_results_validate(tmp_path: Path) -> None:
    write_files(tmp_path, {"c.rct": COUNTER, "c.assertions": "assertion a: Counter does not terminate.\n"
                                                             "untimed assertion b: Counter is timelock-free.\n"})
    out = run_cli(["check", tmp_path, "--engine", "explicit", "--range", "core_int=-1..1", "--format", "json"])
    document = json.loads(out.stdout)
    _validate(document)
    a, b = document["results"]
    assert a["engine"] == "explicit" and a["states"] > 0 and a["verdict"] == "violated"
    assert b["verdict"] == "unsupported" and b["proof"] == "none" and b["bound"] is None


def test_the_schema_rejects_what_the_contract_does_not_allow() -> None:
    out = run_cli(["check", EXAMPLE, "-a", "A7", "--format", "json"])
    document = json.loads(out.stdout)
    _validate(document)
    for mutate in (lambda d: d["results"][0].update(verdict="passed"),
                   lambda d: d["results"][0].update(surprise=1),
                   lambda d: d.pop("status"),
                   lambda d: d["results"][0].update(proof="bounded-ish")):
        bad = copy.deepcopy(document)
        mutate(bad)
        with pytest.raises(jsonschema.ValidationError):
            _validate(bad)


def test_a_model_without_assertions_gets_the_core_assertions(tmp_path: Path) -> None:
    write_files(tmp_path, {"c.rct": COUNTER})
    out = run_cli(["check", tmp_path, "--format", "json"])
    document = json.loads(out.stdout)
    _validate(document)
    verdicts = {r["assertion"]: r["verdict"] for r in document["results"]}
    assert verdicts == {"Counter_deadlock_free": "holds", "Counter_deterministic": "holds",
                        "Counter_divergence_free": "holds", "Counter_timelock_free": "violated"}
    assert "no assertions" in out.stderr and out.exit_code == 10


def test_core_adds_the_core_assertions_to_the_users(tmp_path: Path) -> None:
    write_files(tmp_path, {"c.rct": COUNTER, "c.assertions": "assertion mine: Counter does not terminate.\n"})
    out = run_cli(["check", tmp_path, "--core", "-a", "mine", "-a", "Counter_deadlock_free", "--format", "json"])
    names = [r["assertion"] for r in json.loads(out.stdout)["results"]]
    assert names == ["mine", "Counter_deadlock_free"]
