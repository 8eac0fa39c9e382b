"""Wrong verdicts and disagreements between the engines found in session 17 (tests/models/review17)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import both_engines

from tockbmc import load
from tockbmc.model.ranges import Range, Ranges

MODELS = Path(__file__).parent / "models" / "review17"
RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})


@pytest.mark.parametrize(("case", "expected"), [
    # a specification naming `M::a` without its `.in`, beside a model that no run starts: the
    # explicit engine said `unknown` (no run starts) before it read the specification, BMC
    # `unsupported`; both read the assertion first now
    ("ns3", {"A2": "unsupported"}),
])
def test_both_engines(case: str, expected: dict[str, str]) -> None:
    bmc, explicit = both_engines(load(MODELS / case), RANGES, 10, timeout=30)
    assert {r.assertion: r.verdict for r in bmc} == expected, [r.reason for r in bmc]
    assert {r.assertion: r.verdict for r in explicit} == expected, [r.reason for r in explicit]
