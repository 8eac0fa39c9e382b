"""Refinement in the failures and failures-divergences models (docs/semantics.md §7.12), both
engines, both directions.  Every verdict is derived by hand from the rule: after each trace, every
stable refusal of the refining process is one the refined process can make (and, in the FD model,
no divergence the refined process does not have)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.config import configure
from tockbmc.model.result import Result

RANGES = Ranges({"core_int": Range(Fraction(0), Fraction(2))})

RCT = """
stm M {
  event a
  event b
  initial i
  junction j
  state s {}
  state t {}
  final f
  transition tj { from i to j }
  transition t0 { from j to s }
  transition t1 { from j to t }
  transition t2 { from s to f trigger a }
  transition t3 { from t to f trigger b }
}
stm N {
  event a
  event b
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger a }
  transition t2 { from s to f trigger b }
}
stm P {
  event c: int
  initial i
  state s {}
  transition t0 { from i to s action c!1 }
}
stm L {
  event a
  var x: int
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger a }
  transition t2 { from s to s condition x == 0 }
}
"""

SPECS = """
csp Specs csp-begin
Ext = (M::a.in -> M::terminate -> SKIP) [] (M::b.in -> M::terminate -> SKIP)
Int = (M::a.in -> M::terminate -> SKIP) |~| (M::b.in -> M::terminate -> SKIP)
NInt = (N::a.in -> N::terminate -> SKIP) |~| (N::b.in -> N::terminate -> SKIP)
AnyC = P::c.out?x -> STOP
OneC = P::c.out!1 -> STOP
TwoC = P::c.out!1 -> STOP [] P::c.out!2 -> STOP
Stop = STOP
RunA = L::a.in -> RunA
csp-end
"""


def both(tmp_path: Path, assertions: str) -> tuple[dict[str, Result], dict[str, Result]]:
    write_files(tmp_path, {"m.rct": RCT, "m.assertions": SPECS + assertions})
    project = tockbmc.load(tmp_path)
    config = configure(project, RANGES)
    bmc = {r.assertion: r for r in check(project, bound=14, config=config)}
    explicit = {r.assertion: r for r in check_explicit(project, None, 14, RANGES, {}, 60, config=config)}
    return bmc, explicit


def test_the_model_on_the_left(tmp_path) -> None:
    """M chooses internally between a state offering only a and one offering only b: it has the
    traces of Ext, but stable in s it refuses b, which Ext's only stable state accepts (F1); Int can
    refuse b there (F2). P offers only c.out.1: AnyC accepts every value of c, so P's refusal of
    c.out.0 is not AnyC's (F3); OneC is (F4); TwoC accepts c.out.2 (F5). L can loop on the hidden
    condition for ever when x == 0: a divergence RunA does not have (F6), which the failures model
    does not see (F7)."""
    text = """
untimed assertion T1: M refines Ext in the traces model.
untimed assertion F1: M refines Ext in the failures model.
untimed assertion F1n: M does not refine Ext in the failures model.
untimed assertion F2: M refines Int in the failures model.
untimed assertion F3: P refines AnyC in the failures divergences model.
untimed assertion F4: P refines OneC in the failures divergences model.
untimed assertion F5: P refines TwoC in the failures model.
untimed assertion F6: L refines RunA in the failures divergences model.
untimed assertion F7: L refines RunA in the failures model.
"""
    for rs in both(tmp_path, text):
        verdicts = {k: r.verdict for k, r in rs.items()}
        assert verdicts == {"T1": "holds", "F1": "violated", "F1n": "holds", "F2": "holds", "F3": "violated",
                            "F4": "holds", "F5": "violated", "F6": "violated", "F7": "holds"}, rs
        assert [s.event for s in rs["F1"].trace if s.kind != "internal"] == []
        assert "every stable state of Ext" in (rs["F1"].reason or "")
        assert "P::c.out.2" in (rs["F5"].reason or "") and rs["F5"].extra["refusal"] == ["P::c.out.2"]
        assert rs["F1"].extra["refusal"] in (["M::a.in"], ["M::b.in"])  # whichever branch M took
        assert rs["F3"].extra["refusal"] == ["P::c.out.…"]  # a value of c that AnyC accepts and P refuses
        assert "divergence" in (rs["F6"].reason or "")


def test_the_model_on_the_right_and_equality(tmp_path) -> None:
    """NInt, stable after <> accepting only N::a.in, refuses N::b.in; N's only stable state offers
    both, so it cannot (G1), though the traces agree (G2); Int refines M (G3: M can be stable in s
    offering only a, or in t offering only b); Ext refines M in the FD model too (M's stable s offers
    only a, within {a, b}); STOP refuses c.out.1, which P, stable, always offers (G5); M equals Int
    both ways (G6) but not Ext (G7: M's refusal of b)."""
    text = """
untimed assertion G1: NInt refines N in the failures model.
untimed assertion G2: NInt refines N in the traces model.
untimed assertion G3: Int refines M in the failures model.
untimed assertion G4: Ext refines M in the failures divergences model.
untimed assertion G5: Stop refines P in the failures model.
untimed assertion G6: M equals Int in the failures divergences model.
untimed assertion G7: Ext equals M in the failures model.
untimed assertion G8: NInt does not refine N in the failures model.
"""
    for rs in both(tmp_path, text):
        verdicts = {k: r.verdict for k, r in rs.items()}
        assert verdicts == {"G1": "violated", "G2": "holds", "G3": "holds", "G4": "holds", "G5": "violated",
                            "G6": "holds", "G7": "violated", "G8": "holds"}, rs
        assert "accepting only {N::" in (rs["G1"].reason or "")
        assert "accepting nothing" in (rs["G5"].reason or "")


def test_tick_tock_includes_the_failures_check_at_the_end_of_a_trace(tmp_path) -> None:
    """The tick-tock model records the stable refusal at the end of every trace too
    (docs/semantics.md §7.13, case (c)): as for F1, M stable in s refuses b, which Ext accepts,
    before any event; tests/test_ticktock.py has what the tick-tock model adds."""
    for rs in both(tmp_path, "assertion T: M refines Ext in the tick-tock model.\n"):
        assert rs["T"].verdict == "violated" and [s.event for s in rs["T"].trace if s.kind != "internal"] == []
        assert "every stable state of Ext" in (rs["T"].reason or "") and rs["T"].extra["tock_refusals"] == []


def test_a_specification_that_ends_by_terminating_cannot_refuse_to(tmp_path: Path) -> None:
    """`a -> EndBy(SKIP, 0)` terminates after a, as `a -> SKIP` does: it cannot refuse ✓, so a
    machine stuck after a (S) does not refine it in the failures model, and one that terminates
    (T) does, both ways.  EndBy's termination is ✓, not an internal step into a terminated state
    that refuses everything (with which S would "refine" it and T could not match it)."""
    rct = """\
stm S {
  event a
  initial i
  state s0 { }
  state s1 { }
  transition t0 { from i to s0 }
  transition t1 { from s0 to s1 trigger a }
}
stm T {
  event a
  initial i
  state s0 { }
  final f
  transition t0 { from i to s0 }
  transition t1 { from s0 to f trigger a }
}
"""
    assertions = """\
untimed csp Specs csp-begin
  QS = S::a.in -> EndBy(SKIP, 0)
  QT = T::a.in -> T::terminate -> EndBy(SKIP, 0)
csp-end
untimed assertion FS: S refines QS in the failures model.
untimed assertion FT: T equals QT in the failures model.
"""
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    bmc = {r.assertion: r.verdict for r in check(project, bound=14)}
    explicit = {r.assertion: r.verdict for r in check_explicit(project, None, 14, Ranges(), {}, 60)}
    assert bmc == explicit == {"FS": "violated", "FT": "holds"}
