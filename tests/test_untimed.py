"""RoboTool's untimed semantics (docs/semantics.md §7.11), in both engines.

Each expected verdict and trace is derived by hand from the rules: no `tock`, `wait` and `#C`
are `SKIP`, deadlines are dropped, a transition condition that is one clock comparison is true,
and untimed deadlock freedom (FDR's `:[deadlock free]`) counts termination as a deadlock.
"""

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

RANGES = Ranges({"core_int": Range(Fraction(0), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})


def both(tmp_path: Path, rct: str, assertions: str, bound: int = 14) -> tuple[dict[str, Result], dict[str, Result]]:
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    config = configure(project, RANGES)
    bmc = {r.assertion: r for r in check(project, bound=bound, config=config)}
    explicit = {r.assertion: r for r in check_explicit(project, None, bound, RANGES, {}, 60, config=config)}
    return bmc, explicit


def events(r: Result) -> list[str]:
    return [s.event for s in r.trace if s.kind != "internal"]


CLOCKED = """
stm M {
  clock C
  event a
  initial i
  state s { entry wait(3) }
  final f
  transition t0 { from i to s action #C }
  transition t1 { from s to f condition since(C) >= 5 }
}
"""


def test_waits_clock_resets_and_clock_conditions_are_dropped(tmp_path) -> None:
    """Untimed, the wait is SKIP and `since(C) >= 5` is true, so M terminates at once: the trace
    <M::terminate> with no tock; the terminated machine refuses everything, which FDR's untimed
    deadlock check counts as a deadlock. Timed, M terminates only after 5 tocks, and termination
    is not a deadlock."""
    text = """
untimed assertion U1: M is deadlock-free.
untimed assertion U2: M terminates.
untimed assertion U3: M does not terminate.
untimed assertion U4: M is not deadlock-free.
assertion T1: M is deadlock-free.
assertion T2: M does not terminate.
"""
    for rs in both(tmp_path, CLOCKED, text):
        assert rs["U1"].verdict == "violated" and events(rs["U1"]) == ["M::terminate"], rs["U1"]
        assert "termination as a deadlock" in (rs["U1"].reason or "")
        assert rs["U2"].verdict == "holds", rs["U2"]
        assert rs["U3"].verdict == "violated" and events(rs["U3"]) == ["M::terminate"]
        assert rs["U4"].verdict == "holds" and events(rs["U4"]) == ["M::terminate"]
        assert rs["T1"].verdict == "holds", rs["T1"]
        assert rs["T2"].verdict == "violated" and events(rs["T2"]) == ["tock"] * 5 + ["M::terminate"]


def test_untimed_deadlock_of_a_stable_state_and_no_tock_in_traces(tmp_path) -> None:
    """A machine waiting for `a` offers `a` for ever: not deadlocked untimed (no tock needed); after
    `a` it is in a state with no transitions, which refuses everything. The untimed trace has no tock."""
    rct = """
stm M {
  event a
  initial i
  state s {}
  state d { entry wait(2) }
  transition t0 { from i to s }
  transition t1 { from s to d trigger a }
}
"""
    rs_both = both(tmp_path, rct, "untimed assertion U: M is deadlock-free.\nuntimed assertion R: d is reachable in M.\n")
    for rs in rs_both:
        assert rs["U"].verdict == "violated" and events(rs["U"]) == ["M::a.in"], rs["U"]
        assert rs["R"].verdict == "holds" and events(rs["R"]) == ["M::a.in"]


def test_untimed_refinement_against_an_untimed_specification(tmp_path) -> None:
    """Untimed, the wait between the two outputs is gone and no tock is ever offered, so M has
    exactly the traces of b -> c -> terminate -> SKIP. Timed, an output is not urgent, so time may
    pass before `b`: the trace <tock>, which the specification (outside a Timed section) refuses."""
    rct = """
stm M {
  event b
  event c
  initial i
  final f
  transition t0 { from i to f action b; wait(1); c }
}
"""
    text = """
csp Spec csp-begin
Spec = M::b.out -> M::c.out -> M::terminate -> SKIP
csp-end
untimed assertion U: M refines Spec.
untimed assertion E: M equals Spec.
assertion T: M refines Spec.
"""
    for rs in both(tmp_path, rct, text):
        assert rs["U"].verdict == "holds", rs["U"]
        assert rs["E"].verdict == "holds", rs["E"]
        assert rs["T"].verdict == "violated" and events(rs["T"]) == ["tock"], rs["T"]


def test_a_condition_reading_a_clock_becomes_true_as_a_whole_untimed(tmp_path) -> None:
    """RoboTool's untimed CSP writes `(true)&(…)` for a condition with a clock read anywhere in it
    (ChemicalDetector's `since(T) >= stuckPeriod /\\ d1 - d0 <= stuckDist`), not just for the clock
    comparison: here `x > 0` is false (x starts at 0), yet the machine terminates untimed."""
    rct = """
stm M {
  clock C
  var x: int
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f condition since(C) >= 1 /\\ x > 0 }
}
"""
    text = "untimed assertion U: M terminates.\nuntimed assertion L: M is timelock-free.\nassertion T: M does not terminate.\n"
    for rs in both(tmp_path, rct, text):
        assert rs["U"].verdict == "holds", rs["U"].reason
        assert rs["L"].verdict == "unsupported" and "tock" in (rs["L"].reason or "")
        assert rs["T"].verdict == "holds", rs["T"].reason  # timed, x > 0 never holds
