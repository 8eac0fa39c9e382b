"""Wrong verdicts and internal errors a review found in session 16's changes (tests/models/review16)."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import run_cli, verdicts_are

from tockbmc import load
from tockbmc.model.ranges import Range, Ranges

MODELS = Path(__file__).parent / "models" / "review16"
RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})


@pytest.mark.parametrize(("case", "expected"), [
    # `e?x` into a nat x: BMC received -1, and the replay of its run to `bad` was an internal error
    ("n1", {"R": "violated"}),
    # a defined operation's nat parameter given n - 1 from 0: the interpreter made the call
    ("n2", {"R": "violated"}),
    # a record's function-typed field nobody set is any function into nat (BMC took it for a lambda)
    ("fn1", {"D": "holds", "R": "holds", "N": "holds"}),
    # the model on the right of a refinement, which no run starts: the specification's trace had
    # been shown as a violation
    ("ns2", {"A2": "unknown"}),
    # ... and on the specification's side, a model element (N refines M, M not starting)
    ("ns1", {"A6": "unknown"}),
    # `with constant K of M set to -1` of a nat K: the interpreter took -1 (no run starts, in BMC)
    ("k2", {"R": "unknown", "D": "unknown", "E": "violated"}),
])
def test_both_engines(case: str, expected: dict[str, str]) -> None:
    verdicts_are(load(MODELS / case), RANGES, 10, expected, explicit=case != "fn1")


def test_an_instance_path_does_not_reach_the_same_machine_in_another_controller() -> None:
    """`--set ctrl0::stm_ref0::CC=1` had set ctrl1's stm_ref0 too (both end at STM)."""
    out = run_cli(["check", str(MODELS / "st1"), "--format", "json", "--set", "ctrl0::stm_ref0::CC=1"])
    results = {r["assertion"]: r for r in json.loads(out.stdout)["results"]}
    assert results["B"]["verdict"] == "holds" and "ctrl1::stm_ref0::CC" not in results["B"]["constants"]
    assert results["C"]["verdict"] == "violated" and results["C"]["constants"]["ctrl0::stm_ref0::CC"] == "1"
    assert results["A"]["constants"]["Mod::c0::stm_ref0::CC"] == "1"
    assert "Mod::c1::stm_ref0::CC" not in results["A"]["constants"]
