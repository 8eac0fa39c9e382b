"""A composite state's `during` action runs beside its children (docs/semantics.md §4.1): it starts
once the first child is entered, keeps running while the children move among themselves, and is
abandoned by a transition that leaves the state.  BMC (a product of the two threads' locations)
and the explicit engine (a second stack of activations) decide it alike, and refuse the same
models with the same reason."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import CONFORMANCE, both_engines, write_files

from tockbmc import load
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

MODEL = """\
stm M {
  var x : int = 0
  event a
  event c
  event b : int
  initial i
  state S {
    during wait(1) ; x = 1
    initial j
    state P { }
    state Q { }
    transition u0 { from j to P }
    transition u1 { from P to Q trigger a }
    transition u2 { from Q to P condition x == 1 action b!x }
  }
  state T { entry wait(2) ; b!(x + 2) }
  transition t0 { from i to S }
  transition t1 { from S to T trigger c }
}
"""
ASSERTIONS = """\
timed csp NoB csp-begin
  NoB = M::a.in -> NoB [] M::c.in -> Any [] tock -> NoB
  Any = M::a.in -> Any [] M::c.in -> Any [] M::b.out?v -> Any [] tock -> Any
csp-end
timed csp NoEarlyB csp-begin
  NoEarlyB = M::a.in -> NoEarlyB [] M::c.in -> Any [] tock -> Any
csp-end
assertion R1: M refines NoB in the traces model.
assertion R2: M refines NoEarlyB in the traces model.
assertion D1: M is deadlock-free.
assertion T1: M is timelock-free.
assertion V1: M is divergence-free.
"""
RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    return load(write_files(tmp_path_factory.mktemp("during"), {"m.rct": MODEL, "m.assertions": ASSERTIONS}))


def test_the_during_action_goes_on_while_the_children_move(project) -> None:  # type: ignore[no-untyped-def]
    """`a` moves P to Q before the during action's wait is over; the action still sets x after the
    tock, and u2 then sends b.1.  Had `a` abandoned the action (or restarted it), x would stay 0
    and b would never be sent.  R2: b.1 is never sent before the first tock."""
    bmc, explicit = both_engines(project, RANGES, 20)
    verdicts = {r.assertion: r.verdict for r in bmc}
    assert verdicts == {r.assertion: r.verdict for r in explicit}
    assert verdicts["R1"] == Verdict.VIOLATED and verdicts["R2"] == Verdict.HOLDS
    for results in (bmc, explicit):
        r1 = next(r for r in results if r.assertion == "R1")
        visible = [s.event for s in r1.trace if s.kind in ("event", "tock")]
        assert visible[-1] == "M::b.out.1" and "tock" in visible, visible
    assert next(r for r in bmc if r.assertion == "R1").extra["replayed"] == "yes"


def test_leaving_the_state_abandons_its_during_action(tmp_path: Path) -> None:
    """`c` before the first tock leaves S: the during action is abandoned, so x stays 0 and T's
    entry, two tocks later, sends b.2 (b.3 had the action gone on to set x)."""
    assertions = """\
timed csp Abandoned csp-begin
  Abandoned = M::a.in -> Abandoned [] tock -> Any [] M::c.in -> AfterC
  AfterC = tock -> AfterC [] M::b.out.2 -> AfterC
  Any = M::a.in -> Any [] M::c.in -> Any [] M::b.out?v -> Any [] tock -> Any
csp-end
assertion Z: M refines Abandoned in the traces model.
"""
    project = load(write_files(tmp_path / "m", {"m.rct": MODEL, "m.assertions": assertions}))
    bmc, explicit = both_engines(project, RANGES, 24)
    assert [r.verdict for r in bmc] == [r.verdict for r in explicit] == [Verdict.HOLDS]


@pytest.mark.parametrize("change, reason", [
    ("during wait(1) ; x = 1", None),
    ("during (wait(1) ; x = 1) <{2}", "a deadline inside a composite state's during action is not encoded yet"),
])
def test_what_the_during_thread_refuses(tmp_path: Path, change: str, reason: str | None) -> None:
    model = MODEL.replace("during wait(1) ; x = 1", change)
    project = load(write_files(tmp_path / "m", {"m.rct": model, "m.assertions": "assertion D1: M is deadlock-free.\n"}))
    [b] = check(project, bound=12, ranges=RANGES)
    [e] = check_explicit(project, None, 8, RANGES, {}, 30)
    if reason is None:  # T, once entered, only lets time pass
        assert b.verdict == e.verdict == Verdict.VIOLATED
    else:
        assert b.verdict == e.verdict == Verdict.UNSUPPORTED
        assert reason in (b.reason or "") and reason in (e.reason or "")


def test_nested_composite_durings_are_unsupported_in_both_engines(tmp_path: Path) -> None:
    model = MODEL.replace("state P { }", "state P { during x = 0 initial k state R { } transition v { from k to R } }")
    project = load(write_files(tmp_path / "m", {"m.rct": model, "m.assertions": "assertion D1: M is deadlock-free.\n"}))
    [b] = check(project, bound=12, ranges=RANGES)
    [e] = check_explicit(project, None, 8, RANGES, {}, 30)
    assert b.verdict == e.verdict == Verdict.UNSUPPORTED
    assert "(S::P) inside a composite state with one (S)" in (b.reason or "") and b.reason == e.reason


def test_robotool_s_example1() -> None:
    """RoboTool's Example1, ctrl1: the during action `opWaitD()` of s0 (an operation whose one
    transition waits a tock, then adds 1 to x) runs while s0's children wait in their entries;
    x == 0 may still hold when s0_s1 is entered, so t3 leads to an inner final state where only
    time passes: RoboTool's "genuine timed deadlock" (A0, with the action written out, and A1).
    The explicit engine here (BMC needs 13 steps and about 5 s each: benchmarks/conformance.py)."""
    project = load(CONFORMANCE / "robochart" / "Example1")
    ranges = Ranges({"core_int": Range(Fraction(-2), Fraction(2))})
    results = check_explicit(project, ["A0", "A1"], 40, ranges, {}, 60)
    assert [r.verdict for r in results] == [Verdict.HOLDS, Verdict.HOLDS]


REENTRY = """\
stm M {
  event c
  event d
  event b : int
  initial i
  state S {
    during b!1
    initial j
    state P { }
    transition u0 { from j to P }
  }
  state T {
    during b!2
    initial k
    state Q { }
    transition v0 { from k to Q }
  }
  transition t0 { from i to S }
  transition t1 { from S to S trigger c }
  transition t2 { from S to T trigger d }
}
"""


@pytest.mark.parametrize("spec, trace", [
    # re-entering S by its self-transition restarts its during action (b.1 again after c)
    # (T's b.2 allowed, so that no other violation is as short)
    ("Spec = M::b.out.1 -> Spec [] M::c.in -> After [] M::d.in -> InT [] tock -> Spec\n"
     "  After = M::c.in -> After [] M::d.in -> InT [] tock -> After\n"
     "  InT = tock -> InT [] M::b.out.2 -> InT", ["M::c.in", "M::b.out.1"]),
    # entering T from S starts T's during action (b.2 after d)
    ("Spec = M::b.out.1 -> Spec [] M::c.in -> Spec [] M::d.in -> InT [] tock -> Spec\n"
     "  InT = tock -> InT", ["M::d.in", "M::b.out.2"]),
])
def test_a_transition_without_actions_restarts_or_starts_a_during_action(tmp_path: Path, spec: str,
                                                                      trace: list[str]) -> None:
    """A transition with no exit, transition or entry action in between is one step from the state
    left to the child entered, which is also the step that starts the entered state's during action
    (BMC's product must not copy such steps to the child without its action)."""
    assertions = f"timed csp Spec csp-begin\n  {spec}\ncsp-end\nassertion R: M refines Spec in the traces model.\n"
    project = load(write_files(tmp_path / "m", {"m.rct": REENTRY, "m.assertions": assertions}))
    bmc, explicit = both_engines(project, RANGES, 20)
    for results in (bmc, explicit):
        [r] = results
        assert r.verdict == Verdict.VIOLATED
        assert [s.event for s in r.trace if s.kind in ("event", "tock")] == trace


def test_variables_named_like_the_machine_s_bookkeeping_stay_apart(tmp_path: Path) -> None:
    """A variable `during_wait` (or `deadline`, `loc`) is not the during action's wait counter
    (were both the scalar `M.during_wait`, the assignment would cut the wait short)."""
    model = """\
stm M {
  var during_wait : int = 0
  var loc : int = 0
  event c
  event b : int
  initial i
  state S {
    during wait(2) ; b!1
    initial j
    state P { }
    transition u0 { from j to P }
    transition u1 { from P to P trigger c action during_wait = 0 ; loc = 5 }
  }
  transition t0 { from i to S }
}
"""
    spec = """\
timed csp Spec csp-begin
  Spec = M::c.in -> Spec [] tock -> Spec1
  Spec1 = M::c.in -> Spec1 [] tock -> Any
  Any = M::c.in -> Any [] M::b.out?v -> Any [] tock -> Any
csp-end
assertion R: M refines Spec in the traces model.
"""
    project = load(write_files(tmp_path / "m", {"m.rct": model, "m.assertions": spec}))
    bmc, explicit = both_engines(project, RANGES, 20)
    assert [r.verdict for r in bmc] == [r.verdict for r in explicit] == [Verdict.HOLDS]
