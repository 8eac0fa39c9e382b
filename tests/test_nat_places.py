"""A place of type nat never holds a negative value, whichever way the value comes (an input, a
parameter, a constant set from outside, a function nobody set), and a model no run starts gives no
verdict from either side of a refinement: in both engines (tests/models/nat_places)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import verdicts_are

from tockbmc import load
from tockbmc.model.ranges import Range, Ranges

MODELS = Path(__file__).parent / "models" / "nat_places"
RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})


@pytest.mark.parametrize(("case", "expected"), [
    # `e?x` into a nat x: no run receives -1, so BMC's run to `bad` replays
    ("n1", {"R": "violated"}),
    # a defined operation's nat parameter given n - 1 from 0: the call cannot be made, in
    # either engine
    ("n2", {"R": "violated"}),
    # a record's function-typed field nobody set is any function into nat, not a lambda
    ("fn1", {"D": "holds", "R": "holds", "N": "holds"}),
    # the model on the right of a refinement, which no run starts: the specification's trace is
    # no violation
    ("ns2", {"A2": "unknown"}),
    # ... and on the specification's side, a model element (N refines M, M not starting)
    ("ns1", {"A6": "unknown"}),
    # `with constant K of M set to -1` of a nat K: no run starts (R, D), in
    # the interpreter as in BMC
    ("k2", {"R": "unknown", "D": "unknown", "E": "violated"}),
])
def test_both_engines(case: str, expected: dict[str, str]) -> None:
    verdicts_are(load(MODELS / case), RANGES, 10, expected, explicit=case != "fn1")

