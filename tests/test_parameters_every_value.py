"""A constant made a parameter (`--param`) is considered at every value: an assertion holds when it
holds for every value (docs/semantics.md §6.3).  Both engines search the runs from all values at once,
so a claim that some run exists (a witness), or that each trace of a specification is performed,
shown by the runs of some values, gives no verdict for the others (`goals.one_value_only`).

By hand, for KT with k in -1..1: only k = 1 reaches the final state f, so `KT terminates` and
`f is reachable in KT` are violated at k = 0 (found before session 14: `holds` in both engines, the
witness starting from k = 1); now `unknown`.  `KT does not terminate` is violated (the witness
with k = 1 is a violation at that value), `s is not reachable in KT`, likewise.  Kd offers `a` at
k = 1 and `b` otherwise, so `Q refines Kd` (Q = a -> STOP on the left) and `KB refines Kd` (Kd on
the specification's side) fail at k = 0 (both were `holds`).
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
stm KT {
  const k: int
  initial i
  junction j
  state s {}
  final f
  transition tj { from i to j }
  transition t0 { from j to f condition k == 1 }
  transition t1 { from j to s condition k != 1 }
}
stm Kd {
  const k: int
  event a
  event b
  initial i
  junction j
  state s {}
  state t {}
  state d {}
  transition tj { from i to j }
  transition t0 { from j to s condition k == 1 }
  transition t1 { from j to t condition k != 1 }
  transition t2 { from s to d trigger a }
  transition t3 { from t to d trigger b }
}
stm KB {
  event a
  initial i
  state s {}
  state d {}
  transition t0 { from i to s }
  transition t2 { from s to d trigger a }
}
"""

ASSERTIONS = """
timed csp Q csp-begin
Timed(OneStep) { Q = Kd::a.in -> STOP }
csp-end
assertion T1: KT terminates.
assertion T2: f is reachable in KT.
assertion T3: KT does not terminate.
assertion T4: s is not reachable in KT.
assertion P1: Q refines Kd.
untimed assertion P2: Q refines Kd in the failures divergences model.
assertion E1: KB refines Kd.
assertion E3: KB does not refine Kd.
"""

EXPECTED = {"T1": "unknown", "T2": "unknown", "T3": "violated", "T4": "violated", "P1": "unknown",
            "P2": "unknown", "E1": "unknown", "E3": "unknown"}
ONE = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})


@pytest.fixture
def project(tmp_path: Path) -> tockbmc.Project:
    write_files(tmp_path, {"m.rct": MODEL, "m.assertions": ASSERTIONS})
    return tockbmc.load(tmp_path)


def test_claims_shown_for_some_values_give_no_verdict(project: tockbmc.Project) -> None:
    config = configure(project, ONE, params=["KT::k", "Kd::k"])
    symbolic = {r.assertion: r for r in check(project, bound=20, config=config, timeout=60)}
    concrete = {r.assertion: r for r in check_explicit(project, None, 20, ONE, {}, 60, config=config)}
    for results in (symbolic, concrete):
        assert {n: r.verdict for n, r in results.items()} == EXPECTED, {n: r.reason for n, r in results.items()}
        assert "shown for some values of the parameters" in (results["T1"].reason or "")


def test_with_the_value_fixed_the_same_claims_are_decided(project: tockbmc.Project) -> None:
    """k = 1: KT terminates and Q's trace is Kd's; the witnesses stand for the one value there is."""
    config = configure(project, ONE, settings={"KT::k": "1", "Kd::k": "1"})
    for results in (check(project, ["T1", "T2", "P1", "E1"], bound=20, config=config, timeout=60),
                    check_explicit(project, ["T1", "T2", "P1", "E1"], 20, ONE, {}, 60, config=config)):
        assert {r.assertion: r.verdict for r in results} == {n: "holds" for n in ("T1", "T2", "P1", "E1")}
