"""The specification on the left with too many traces to list (docs/semantics.md §7.5): its monitor
states paired with the sets of the model's configurations after the same trace, explored breadth
first (`explicit.engine._subsets`), which decides for traces of every length.

M receives ten values on `a` (each of -1..1), then stops.  `Spec` receives for ever, `Ten` ten
times, so with three values a trace of eight events has 3^8 = 6,561 forms, past the 256 listed.
By hand: Spec has the trace of eleven inputs, which M cannot perform (A, C violated); Ten's traces
are exactly M's (B, D hold), so `Ten does not refine M` is violated (E).
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.config import configure

MODEL = """
interface I { event a : int }
stm M {
  uses I
  var x : int = 0
  var n : int = 0
  initial i
  state S {}
  state T {}
  transition t0 { from i to S }
  transition t1 { from S to S trigger a?x condition n < 9 action n = n + 1 }
  transition t2 { from S to T trigger a?x condition n >= 9 }
}
"""

ASSERTIONS = """
untimed csp Spec csp-begin
Spec = M::a.in?x -> Spec
csp-end
untimed csp Ten csp-begin
Ten = let P(k) = if k < 10 then M::a.in?x -> P(k + 1) else STOP within P(0)
csp-end
untimed assertion A: Spec refines M in the traces model
untimed assertion B: Ten refines M in the traces model
untimed assertion C: Spec refines M in the failures divergences model
untimed assertion D: M equals Ten in the traces model
untimed assertion E: Ten does not refine M in the traces model
"""

EXPECTED = {"A": "violated", "B": "holds", "C": "violated", "D": "holds", "E": "violated"}
ONE = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})


@pytest.fixture
def project(tmp_path: Path) -> tockbmc.Project:
    write_files(tmp_path, {"m.rct": MODEL, "m.assertions": ASSERTIONS})
    return tockbmc.load(tmp_path)


def test_the_explicit_engine_decides_for_every_length(project: tockbmc.Project) -> None:
    results = {r.assertion: r for r in check_explicit(project, None, 40, ONE, {}, 60)}
    assert {n: r.verdict for n, r in results.items()} == EXPECTED, {n: r.reason for n, r in results.items()}
    assert "for traces of every length" in (results["B"].reason or "")
    for name in ("A", "C"):
        events = [s.event for s in results[name].trace]
        assert events == ["M::a.in.-1"] * 11, events


def test_bmc_turns_to_the_same_construction_where_the_traces_are_too_many(project: tockbmc.Project) -> None:
    """BMC lists at most 256 traces of the specification; past that, with finite data, it decides by
    the construction above (listing alone leaves all five `unknown`)."""
    results = {r.assertion: r for r in check(project, bound=40, config=configure(project, ONE), timeout=60)}
    assert {n: r.verdict for n, r in results.items()} == EXPECTED, {n: r.reason for n, r in results.items()}
    for name in ("A", "B", "C", "E"):
        assert "could be listed" in (results[name].reason or "") and "paired with the sets" in (results[name].reason or "")
    assert [s.event for s in results["A"].trace] == ["M::a.in.-1"] * 11


def test_without_ranges_bmc_stays_unknown(project: tockbmc.Project) -> None:
    """Unbounded data: the interpreter cannot list the configurations, so the listing's `unknown`
    stands (the specification's inputs are listed over the values M's ranges allow; none here)."""
    [b] = check(project, ["B"], bound=40, config=configure(project, Ranges()), timeout=60)
    assert b.verdict in ("unknown", "unsupported"), b.reason
