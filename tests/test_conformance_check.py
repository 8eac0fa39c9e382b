"""Check every assertion of RoboTool's regression suite that tockbmc supports.

Every assertion in `robochart/` is written to hold.  Each supported-form
assertion is checked with RoboTool's default ranges (`core_int=-2..2`,
`core_real=-2..2`, `core_nat=0..2`) and must hold, except the ones listed in
`DIFFERENCES` with the reason.  The bound here is kept small so that the suite
stays fast; `benchmarks/conformance.py` runs the same check at the default
bound and prints the counts.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache

import pytest
from conftest import CONFORMANCE

from tockbmc import ModelError, load
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.model import ast

BOUND = 12
ROBOTOOL_RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_real": Range(Fraction(-2), Fraction(2)),
                          "core_nat": Range(Fraction(0), Fraction(2))})

_Z_UNSET = ("constant z has no value: semantics.md §15 considers every value in core_nat=0..2, and z=2 lets STM1 "
            "reach its final state; RoboTool's instantiations.csp gives it 0 (see the model's comment), and with "
            "z=0 the assertion holds")
# (case, assertion) -> (tockbmc's verdict, why it differs from RoboTool's intended one)
DIFFERENCES = {
    ("test-core-assertions", name): ("violated", _Z_UNSET)
    for name in ("M_term", "C1_term", "STM1_term", "M_timelock_free", "C1_timelock_free", "STM1_timelock_free")
}
DIFFERENCES[("test8", "A2")] = (
    "violated", "controller variable x has no initial value: semantics.md §2.14 lets it start at any value of "
                "core_nat=0..2, so M can output e1.1; RoboTool starts it at 0, nat's default, as TSpec assumes")

_ITYPE2NAT = ("function IType2nat has no body in the model: semantics.md §15 makes it uninterpreted, so "
              "IType2nat(L2) may be 0 and the output 2; RoboTool's instantiations block defines it "
              "(IType2nat(IType_L2) = 1), which gives the specification's 3")
for _case in ("clocks-ops2", "clocks-ops3"):
    DIFFERENCES[(_case, "A1")] = ("violated", _ITYPE2NAT)

# Refinement and equality assertions of the corpus whose specifications fall in the CSP subset.
CSP_CHECKED = {("test2", "t2a_timed"): "holds", ("test2", "t2b_timed"): "holds", ("test9", "A2"): "holds",
               ("test8", "A2"): "violated"}


@cache
def results() -> dict[tuple[str, str], tuple[str, str]]:
    out = {}
    for case in sorted((CONFORMANCE / "robochart").iterdir()):
        try:
            project = load(case)
        except ModelError:
            continue  # test_conformance_load.py says which cases load
        for r in check(project, bound=BOUND, ranges=ROBOTOOL_RANGES, timeout=60):
            out[(case.name, r.assertion)] = (r.verdict, r.reason or "")
    return out


def test_every_supported_assertion_holds_or_is_a_recorded_difference() -> None:
    checked = {k: v for k, v in results().items() if v[0] != "unsupported"}
    wrong = {k: v for k, v in checked.items() if v[0] != "holds" and DIFFERENCES.get(k, ("",))[0] != v[0]}
    assert not wrong
    holding = sum(1 for v in checked.values() if v[0] == "holds")
    print(f"\n{len(checked)} corpus assertions checked, {holding} hold, "
          f"{len(results()) - len(checked)} unsupported")
    assert holding >= 52  # the count when this test was written; a drop is a regression


def test_csp_refinements_in_the_subset_are_checked() -> None:
    for key, verdict in CSP_CHECKED.items():
        assert results()[key][0] == verdict, (key, results()[key])


def test_differences_are_still_differences() -> None:
    """A recorded difference that no longer occurs must be removed from the list."""
    for key, (verdict, _why) in DIFFERENCES.items():
        assert results()[key][0] == verdict, key


@pytest.mark.parametrize("name", ["M_term", "C1_term", "STM1_term", "STM1_timelock_free"])
def test_with_robotools_default_for_z_the_differences_hold(name: str) -> None:
    project = load(CONFORMANCE / "robochart" / "test-core-assertions")
    zero = ast.Literal(ast.NAT, ast.Pos("<command line>", 1, 1), 0)
    [r] = check(project, [name], bound=BOUND, ranges=ROBOTOOL_RANGES, settings={"z": zero})
    assert r.verdict == "holds"


def test_unsupported_results_name_their_reason() -> None:
    for key, (verdict, reason) in results().items():
        if verdict == "unsupported":
            assert reason, key
