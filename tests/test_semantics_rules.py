"""One small model per rule of /work/shared/semantics.md, §2 ("Steps") and §3 ("Assertions").

Every expected verdict and every expected visible trace (FDR event names, internal steps
left out) is derived by hand from the rule cited in the test's docstring, never copied from
the tool's output. Where several shortest runs exist, only what they share is asserted.
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
from tockbmc.model.readings import Reading
from tockbmc.model.result import Result

MINUS1_1 = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})


def run(tmp_path: Path, rct: str, assertions: str, bound: int = 14, ranges: Ranges | None = None,
        names: list[str] | None = None, params: tuple[str, ...] = (),
        reading: Reading = Reading.DEFAULT) -> dict[str, Result]:
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    config = configure(project, ranges or Ranges(), params=params, reading=reading)
    return {r.assertion: r for r in check(config.project, names, bound=bound, config=config)}


def events(r: Result) -> list[str]:
    return [s.event for s in r.trace if s.kind != "internal"]


def expect(r: Result, verdict: str, trace: list[str] | None = None) -> None:
    assert r.verdict == verdict, f"{r.assertion}: {r.verdict} ({r.reason}); trace {events(r)}"
    if trace is not None:
        assert events(r) == trace, f"{r.assertion}: trace {events(r)}"


# ---------------------------------------------------------------------------- rule 1


def test_rule1_tock_refused_while_internal_step_possible(tmp_path) -> None:
    """§2.1: at time 0 the triggerless t1 is enabled, so tock is refused and t1 is taken;
    `later` (needs one tock in s) is never entered."""
    rct = """
stm M {
  clock C
  initial i
  state s {}
  state now {}
  state later {}
  transition t0 { from i to s }
  transition t1 { from s to now condition since(C) == 0 }
  transition t2 { from s to later condition since(C) >= 1 }
}
"""
    rs = run(tmp_path, rct, "assertion Now: now is reachable in M.\n"
                            "assertion Later: later is not reachable in M.\n")
    expect(rs["Now"], "holds", [])
    expect(rs["Later"], "holds")


def test_rule1_tock_allowed_in_stable_state_without_enabled_transition(tmp_path) -> None:
    """§2.1 and §3: a stable state with no transition lets time pass (timelock-free), but only
    tocks are ever offered there, a timed deadlock."""
    rct = """
stm M {
  initial i
  state s {}
  transition t0 { from i to s }
}
"""
    rs = run(tmp_path, rct, "assertion TL: M is timelock-free.\nassertion DL: M is deadlock-free.\n")
    expect(rs["TL"], "holds")
    expect(rs["DL"], "violated")
    assert [e for e in events(rs["DL"]) if e != "tock"] == []


def test_rule1_tock_is_global_in_a_controller(tmp_path) -> None:
    """§2.1, §2.11, §2.12: P's output has deadline 0, so no machine of G may tock until it
    happens; Q needs two tocks to reach its final state, where P already is, so G terminates
    (a controller terminates when all its machines are at final states, §5.6)."""
    rct = """
stm P {
  event res : int
  initial i
  state s { entry res!1 <{0} }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm Q {
  clock C
  initial i
  state w {}
  final f
  transition t0 { from i to w }
  transition t1 { from w to f condition since(C) >= 2 }
}
controller G {
  event res : int
  sref p = P
  sref q = Q
  connection p on res to G on res
}
"""
    rs = run(tmp_path, rct, "assertion NT: G does not terminate.\nassertion TL: G is timelock-free.\n", bound=20)
    expect(rs["NT"], "violated", ["G::res.out.1", "tock", "tock", "G::terminate"])
    expect(rs["TL"], "violated", [])


# ---------------------------------------------------------------------------- rule 2


@pytest.mark.parametrize("stub", ["", "operation op(n : int) {\n  terminates\n}\n"], ids=["signature", "stub"])
def test_rule2_operation_call_is_urgent(tmp_path, stub) -> None:
    """§2.2: the call op(2) is visible (M::opCall.2) and urgent: the stable configuration before
    it refuses tock (a timelock), it precedes every tock, and x = since(C) right after it is 0."""
    rct = """
interface I { op(n : int) }
""" + stub + """
stm M {
  requires I
  clock C
  var x : int = 0
  initial i
  state s { entry op(2) ; x = since(C) }
  state late {}
  state later {}
  transition t0 { from i to s }
  transition t1 { from s to late condition x >= 1 }
  transition t2 { from s to later condition since(C) >= 1 }
}
"""
    rs = run(tmp_path, rct, "assertion TL: M is timelock-free.\n"
                            "assertion Late: late is not reachable in M.\n"
                            "assertion Later: later is reachable in M.\n")
    expect(rs["TL"], "violated", [])
    expect(rs["Late"], "holds")
    expect(rs["Later"], "holds", ["M::opCall.2", "tock"])


def test_rule2_defined_operation_runs_to_its_final_state(tmp_path) -> None:
    """§2.2 read with §2.7: `double(3)` is not a platform operation but one the controller defines,
    so the call runs its graph: the parameter n is 3, its own variable k becomes 6 on entering s,
    and leaving s outputs k; only then does M's entry go on to output 1. So the outputs are
    <C::out.out.6, C::out.out.1> in that order (tocks may come between: outputs are not urgent)."""
    rct = """
interface Ops { double(n : int) }
stm M {
  requires Ops
  event out : int
  initial i
  state s { entry double(3) ; out!1 }
  transition t0 { from i to s }
}
controller C {
  event out : int
  operation double(n : int) {
    event out : int
    var k : int = 0
    initial i
    state s { entry k = n * 2 }
    final f
    transition t0 { from i to s }
    transition t1 { from s to f action out!k }
  }
  sref m = M
  connection m on out to C on out
}
"""
    text = """
timed csp Both csp-begin
Timed(OneStep) { Both = C::out.out.6 -> C::out.out.1 -> STOP }
csp-end
timed csp OneFirst csp-begin
Timed(OneStep) { OneFirst = C::out.out.1 -> STOP }
csp-end
assertion A: C refines Both in the traces model.
assertion B: C refines OneFirst in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["A"], "holds")
    expect(rs["B"], "violated", ["C::out.out.6"])


def test_rule7_defined_operation_in_a_during_is_abandoned(tmp_path) -> None:
    """§2.7 and §2.9: the during of s calls `slow()`, which waits exactly 2 tocks and then outputs
    tick; stop (a transition of s) abandons it at any time. So tick comes only after two tocks
    (Two holds), and a specification demanding three tocks first is violated by
    <tock, tock, C::tick.out>."""
    rct = """
interface Ops { slow() }
stm M {
  requires Ops
  event tick
  event stop
  initial i
  state s { during slow() }
  state done {}
  transition t0 { from i to s }
  transition t1 { from s to done trigger stop }
}
controller C {
  event tick
  event stop
  operation slow() {
    event tick
    initial i
    state w { entry wait(2) }
    final f
    transition t0 { from i to w }
    transition t1 { from w to f action tick }
  }
  sref m = M
  connection m on tick to C on tick
  connection C on stop to m on stop
}
"""
    text = """
timed csp Two csp-begin
Two = C::stop.in -> RUN({tock}) [] tock -> Two1
Two1 = C::stop.in -> RUN({tock}) [] tock -> Two2
Two2 = C::stop.in -> RUN({tock}) [] tock -> Two2 [] C::tick.out -> After
After = C::stop.in -> RUN({tock}) [] tock -> After
csp-end
timed csp Three csp-begin
Three = C::stop.in -> RUN({tock}) [] tock -> Three1
Three1 = C::stop.in -> RUN({tock}) [] tock -> Three2
Three2 = C::stop.in -> RUN({tock}) [] tock -> Three3
Three3 = C::stop.in -> RUN({tock}) [] tock -> Three3 [] C::tick.out -> After3
After3 = C::stop.in -> RUN({tock}) [] tock -> After3
csp-end
assertion A: C refines Two in the traces model.
assertion B: C refines Three in the traces model.
assertion R: done is reachable in C.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["A"], "holds")
    expect(rs["B"], "violated", ["tock", "tock", "C::tick.out"])
    expect(rs["R"], "holds")


# ---------------------------------------------------------------------------- rule 3


def test_rule3_assignments_are_internal_and_urgent(tmp_path) -> None:
    """§2.3: both assignments run at time 0 with no visible event: x = 1, y = 2."""
    rct = """
stm M {
  clock C
  var x : int = 0
  var y : int = 0
  initial i
  state s { entry x = since(C) + 1 ; y = x * 2 }
  state ok {}
  state late {}
  transition t0 { from i to s }
  transition t1 { from s to ok condition y == 2 }
  transition t2 { from s to late condition y > 2 }
}
"""
    rs = run(tmp_path, rct, "assertion OK: ok is reachable in M.\n"
                            "assertion Late: late is not reachable in M.\n"
                            "assertion TL: M is timelock-free.\n")
    expect(rs["OK"], "holds", [])
    expect(rs["Late"], "holds")
    expect(rs["TL"], "holds")


# ---------------------------------------------------------------------------- rule 4


def test_rule4_outputs_are_not_urgent(tmp_path) -> None:
    """§2.4: e!5 may wait for the environment while time passes (timelock-free), so a tock can
    come before it; `late` needs exactly that."""
    rct = """
stm M {
  event e : int
  clock C
  var x : int = 0
  initial i
  state s { entry e!5 ; x = since(C) }
  state late {}
  transition t0 { from i to s }
  transition t1 { from s to late condition x >= 1 }
}
"""
    rs = run(tmp_path, rct, "assertion TL: M is timelock-free.\nassertion Late: late is reachable in M.\n")
    expect(rs["TL"], "holds")
    expect(rs["Late"], "holds", ["tock", "M::e.out.5"])


# ---------------------------------------------------------------------------- rule 5


def test_rule5_input_condition_filters_values(tmp_path) -> None:
    """§2.5 and §2.14: with core_int = -1..1 no input satisfies x > 5, and only 1 satisfies x > 0;
    unbounded, some value > 5 is accepted."""
    rct = """
stm M {
  event e : int
  var x : int = 0
  initial i
  state s {}
  state big {}
  state pos {}
  transition t0 { from i to s }
  transition t1 { from s to big trigger e?x condition x > 5 }
  transition t2 { from s to pos trigger e?x condition x > 0 }
}
"""
    text = ("assertion NoBig: big is not reachable in M.\n"
            "assertion Pos: pos is reachable in M.\n")
    rs = run(tmp_path, rct, text, ranges=MINUS1_1)
    expect(rs["NoBig"], "holds")
    expect(rs["Pos"], "holds", ["M::e.in.1"])
    rs = run(tmp_path, rct, text)
    expect(rs["NoBig"], "violated")
    [ev] = events(rs["NoBig"])
    assert ev.startswith("M::e.in.") and int(ev.rsplit(".", 1)[1]) > 5


def test_rule5_triggerless_transition_is_urgent(tmp_path) -> None:
    """§2.5: t1 is taken as soon as since(C) >= 2 (time 2), before the tock that would make
    t2's condition true."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  state v {}
  transition t0 { from i to s }
  transition t1 { from s to u condition since(C) >= 2 }
  transition t2 { from s to v trigger e condition since(C) >= 3 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\nassertion V: v is not reachable in M.\n")
    expect(rs["U"], "holds", ["tock", "tock"])
    expect(rs["V"], "holds")


# ---------------------------------------------------------------------------- rule 6


def test_rule6_junction_without_true_condition_lets_time_pass(tmp_path) -> None:
    """§2.6: in j no condition is true at first; time passes until since(C) >= 2; the branch
    x > 0 is never true."""
    rct = """
stm M {
  event go
  clock C
  var x : int = 0
  initial i
  state s0 {}
  junction j
  state u {}
  state never {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to j trigger go action #C }
  transition t2 { from j to u condition since(C) >= 2 }
  transition t3 { from j to never condition x > 0 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n"
                            "assertion N: never is not reachable in M.\n"
                            "assertion TL: M is timelock-free.\n")
    expect(rs["U"], "holds", ["M::go.in", "tock", "tock"])
    expect(rs["N"], "holds")
    expect(rs["TL"], "holds")


def test_rule6_junction_choice_is_nondeterministic(tmp_path) -> None:
    """§2.6: both conditions are true, so both targets are reachable."""
    rct = """
stm M {
  event go
  initial i
  state s0 {}
  junction j
  state a {}
  state b {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to j trigger go }
  transition t2 { from j to a condition true }
  transition t3 { from j to b condition true }
}
"""
    rs = run(tmp_path, rct, "assertion A: a is reachable in M.\nassertion B: b is reachable in M.\n")
    expect(rs["A"], "holds", ["M::go.in"])
    expect(rs["B"], "holds", ["M::go.in"])


# ---------------------------------------------------------------------------- rule 7


def test_rule7_entry_exit_order_in_composite_state(tmp_path) -> None:
    """§2.7: entry A (x=1), initial into B (x=3); on go, A's transition is a candidate while B is
    active; exit B (x=4) then exit A (x=40), action (x=45), entry Tgt outputs 45."""
    rct = """
stm M {
  event go
  event res : int
  var x : int = 0
  initial i
  state A {
    entry x = 1
    exit x = x * 10
    initial ai
    state B {
      entry x = x + 2
      exit x = x + 1
    }
    transition ta { from ai to B }
  }
  state Tgt { entry res!x }
  state Done {}
  transition t0 { from i to A }
  transition t1 { from A to Tgt trigger go action x = x + 5 }
  transition t2 { from Tgt to Done }
}
"""
    rs = run(tmp_path, rct, "assertion D: Done is reachable in M.\n", bound=20)
    expect(rs["D"], "holds", ["M::go.in", "M::res.out.45"])


def test_rule7_during_runs_once_state_is_stable(tmp_path) -> None:
    """§2.7: after the entry (x=1) the during action sets x=2, enabling t1; no visible event."""
    rct = """
stm M {
  var x : int = 0
  initial i
  state s {
    entry x = 1
    during x = 2
  }
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u condition x == 2 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n")
    expect(rs["U"], "holds", [])


# ---------------------------------------------------------------------------- rule 8


def test_rule7_during_of_composite_starts_once_child_is_stable(tmp_path) -> None:
    """§2.7: entering composite S runs its initial transition into c (whose entry outputs f), and
    only then is S stable and its during (output e) starts. So f comes before e: Order holds,
    and EFirst (e before anything else) is violated by the trace <M::f.out>. A transition out of
    S abandons the during: with g taken at once, e need not happen (Leave)."""
    rct = """
stm M {
  event e
  event f
  event g
  state S {
    initial i
    state c { entry f }
    transition t0 { from i to c }
    during e
  }
  state out {}
  initial i0
  transition t { from i0 to S }
  transition leave { from S to out trigger g }
}
"""
    text = """
timed csp Order csp-begin
Timed(OneStep) { Order = M::f.out -> (M::e.out -> M::g.in -> STOP [] M::g.in -> STOP) }
csp-end
timed csp EFirst csp-begin
Timed(OneStep) { EFirst = M::e.out -> STOP }
csp-end
timed csp Leave csp-begin
Timed(OneStep) { Leave = M::f.out -> M::g.in -> STOP }
csp-end
assertion A: M refines Order in the traces model.
assertion B: M refines EFirst in the traces model.
assertion C: Leave refines M in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["A"], "holds")
    expect(rs["B"], "violated", ["M::f.out"])
    expect(rs["C"], "holds")


def test_rule8_top_level_final_offers_terminate(tmp_path) -> None:
    """§2.8, §3: terminate is not urgent (tock allowed before it), then the machine refuses tock;
    termination is not a deadlock."""
    rct = """
stm M {
  initial i
  final f
  transition t0 { from i to f }
}
"""
    rs = run(tmp_path, rct, "assertion NT: M does not terminate.\n"
                            "assertion T: M terminates.\n"
                            "assertion TL: M is timelock-free.\n"
                            "assertion NTL: M is not timelock-free.\n"
                            "assertion DL: M is deadlock-free.\n")
    expect(rs["NT"], "violated", ["M::terminate"])
    expect(rs["T"], "holds")
    expect(rs["TL"], "violated", ["M::terminate"])
    expect(rs["NTL"], "holds", ["M::terminate"])
    expect(rs["DL"], "holds")


def test_rule8_inner_final_state_is_just_stable(tmp_path) -> None:
    """§2.8: reaching af inside A neither terminates M nor stops time."""
    rct = """
stm M {
  initial i
  state A {
    initial ai
    final af
    transition ta { from ai to af }
  }
  transition t0 { from i to A }
}
"""
    rs = run(tmp_path, rct, "assertion NT: M does not terminate.\nassertion TL: M is timelock-free.\n")
    expect(rs["NT"], "holds")
    expect(rs["TL"], "holds")


# ---------------------------------------------------------------------------- rule 9


def test_rule9_wait_then_output(tmp_path) -> None:
    """§2.9 and §2.4: wait(2) lets exactly two tocks pass before e; since e is not urgent, x is
    at least 2, and the shortest way to x == 2 is tock, tock, e."""
    rct = """
stm M {
  event e
  clock C
  var x : int = 0
  initial i
  state s { entry wait(2) ; e ; x = since(C) }
  state two {}
  state early {}
  transition t0 { from i to s }
  transition t1 { from s to two condition x == 2 }
  transition t2 { from s to early condition x < 2 }
}
"""
    rs = run(tmp_path, rct, "assertion Two: two is reachable in M.\n"
                            "assertion Early: early is not reachable in M.\n")
    expect(rs["Two"], "holds", ["tock", "tock", "M::e.out"])
    expect(rs["Early"], "holds")


def test_rule9_wait_is_exact(tmp_path) -> None:
    """§2.9: the assignment after wait(2) is urgent, so x is exactly 2."""
    rct = """
stm M {
  clock C
  var x : int = 0
  initial i
  state s { entry wait(2) ; x = since(C) }
  state two {}
  state other {}
  transition t0 { from i to s }
  transition t1 { from s to two condition x == 2 }
  transition t2 { from s to other condition x != 2 }
}
"""
    rs = run(tmp_path, rct, "assertion Two: two is reachable in M.\n"
                            "assertion Other: other is not reachable in M.\n")
    expect(rs["Two"], "holds", ["tock", "tock"])
    expect(rs["Other"], "holds")


def test_rule9_wait_interval(tmp_path) -> None:
    """§2.9: wait([1, 3]) lets 1, 2 or 3 tocks pass, never 0 or 4."""
    rct = """
stm M {
  clock C
  var x : int = 0
  initial i
  state s { entry wait([1, 3]) ; x = since(C) }
  state lo {}
  state hi {}
  state outside {}
  transition t0 { from i to s }
  transition t1 { from s to lo condition x == 1 }
  transition t2 { from s to hi condition x == 3 }
  transition t3 { from s to outside condition x < 1 \\/ x > 3 }
}
"""
    rs = run(tmp_path, rct, "assertion Lo: lo is reachable in M.\n"
                            "assertion Hi: hi is reachable in M.\n"
                            "assertion Out: outside is not reachable in M.\n")
    expect(rs["Lo"], "holds", ["tock"])
    expect(rs["Hi"], "holds", ["tock", "tock", "tock"])
    expect(rs["Out"], "holds")


# ---------------------------------------------------------------------------- rule 10


def test_rule10_since_needs_tocks(tmp_path) -> None:
    """§2.10: C is reset on entry to s; e is accepted only once since(C) >= 2."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  transition t0 { from i to s action #C }
  transition t1 { from s to u trigger e condition since(C) >= 2 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n")
    expect(rs["U"], "holds", ["tock", "tock", "M::e.in"])


def test_rule10_clock_reset(tmp_path) -> None:
    """§2.10: #C at time 2 resets C, so since(C) == 1 again at time 3."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state a {}
  state s {}
  state u {}
  transition t0 { from i to a }
  transition t1 { from a to s condition since(C) >= 2 action #C }
  transition t2 { from s to u trigger e condition since(C) == 1 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n")
    expect(rs["U"], "holds", ["tock", "tock", "tock", "M::e.in"])


def test_rule10_since_entry(tmp_path) -> None:
    """§2.10: s is entered at time 1, so sinceEntry(s) == 2 at time 3."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state a {}
  state s {}
  state u {}
  transition t0 { from i to a }
  transition t1 { from a to s condition since(C) >= 1 }
  transition t2 { from s to u trigger e condition sinceEntry(s) == 2 }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n")
    expect(rs["U"], "holds", ["tock", "tock", "tock", "M::e.in"])


def test_rule10_since_entry_of_a_composite_counts_once_its_initial_state_is_entered(tmp_path) -> None:
    """§4.5 (docs/semantics.md): the composite s is entered once its initial substate in has run
    its entry (`wait(2)`), at time 2; so `sinceEntry(s) >= 2` holds at time 4, not 2, as RoboTool's
    `clocks5` expects.  The explicit engine finds the same run."""
    rct = """
stm M {
  event e
  initial i
  state s {
    initial j
    state in { entry wait(2) }
    transition u0 { from j to in }
  }
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u condition sinceEntry(s) >= 2 action e }
}
"""
    rs = run(tmp_path, rct, "assertion U: u is reachable in M.\n")
    expect(rs["U"], "holds", ["tock", "tock", "tock", "tock", "M::e.out"])
    from tockbmc.explicit.engine import check_explicit
    project = tockbmc.load(tmp_path)
    [r] = check_explicit(project, None, 8, Ranges(), {}, None)
    expect(r, "holds", ["tock", "tock", "tock", "tock", "M::e.out"])


# ---------------------------------------------------------------------------- rule 11


def test_rule11_statement_deadline_expires(tmp_path) -> None:
    """§2.11: e <{2}: after two tocks without e, tock is refused (a timelock)."""
    rct = """
stm M {
  event e
  initial i
  state s { entry e <{2} }
  transition t0 { from i to s }
}
"""
    rs = run(tmp_path, rct, "assertion TL: M is timelock-free.\nassertion NTL: M is not timelock-free.\n")
    expect(rs["TL"], "violated", ["tock", "tock"])
    expect(rs["NTL"], "holds", ["tock", "tock"])


def test_rule11_trigger_deadline_expires(tmp_path) -> None:
    """§2.11: the condition becomes true at time 1; the transition must be taken within 1 tock,
    so at time 2 tock is refused."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u trigger e <{1} condition since(C) >= 1 }
}
"""
    rs = run(tmp_path, rct, "assertion TL: M is timelock-free.\n")
    expect(rs["TL"], "violated", ["tock", "tock"])


# ---------------------------------------------------------------------------- rule 12

SYNC = """
stm A {
  event x : int
  initial i
  state s { entry x!1 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm BNow {
  event x : int
  event res : int
  var v : int = 0
  var y : int = 0
  clock C
  initial i
  state w {}
  state got { entry y = since(C) }
  final f
  transition t0 { from i to w }
  transition t1 { from w to got trigger x?v }
  transition t2 { from got to f condition y == 0 action res!v }
}
stm BLate {
  event x : int
  var v : int = 0
  var y : int = 0
  clock C
  initial i
  state w {}
  state got { entry y = since(C) }
  final f
  transition t0 { from i to w }
  transition t1 { from w to got trigger x?v }
  transition t2 { from got to f condition y >= 1 }
}
controller CNow {
  event res : int
  sref a = A
  sref b = BNow
  connection a on x to b on x
  connection b on res to CNow on res
}
controller CLate {
  sref a = A
  sref b = BLate
  connection a on x to b on x
}
"""


def test_rule12_synchronous_connection_is_hidden_and_urgent(tmp_path) -> None:
    """§2.12, §2.1: x is a joint internal step, taken at time 0 (so y == 0, and CLate never
    terminates); CNow terminates when BNow reaches its final state, where A already is (§5.6)."""
    rs = run(tmp_path, SYNC, "assertion Now: CNow does not terminate.\nassertion Late: CLate does not terminate.\n",
             bound=20)
    expect(rs["Now"], "violated", ["CNow::res.out.1", "CNow::terminate"])
    expect(rs["Late"], "holds")


def test_rule12_controller_input_is_visible(tmp_path) -> None:
    """§2.12, §1: the controller's own event e reaches the machine as Ctrl::e.in.v."""
    rct = """
stm M {
  event e : int
  var x : int = 0
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger e?x condition x == 1 }
}
controller Ctrl {
  event e : int
  sref m = M
  connection Ctrl on e to m on e
}
"""
    rs = run(tmp_path, rct, "assertion NT: Ctrl does not terminate.\n", ranges=MINUS1_1, bound=16)
    expect(rs["NT"], "violated", ["Ctrl::e.in.1", "Ctrl::terminate"])


ASYNC = """
stm A {
  event x : int
  initial i
  state s { entry x!1 ; x!2 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm B {
  event x : int
  event res : int
  var v : int = 0
  clock C
  initial i
  state w0 {}
  state w {}
  state got { entry res!v }
  final f
  transition t0 { from i to w0 }
  transition t1 { from w0 to w condition since(C) >= 1 }
  transition t2 { from w to got trigger x?v }
  transition t3 { from got to f }
}
controller CAsync {
  event res : int
  sref a = A
  sref b = B
  connection a on x to b on x ( _async )
  connection b on res to CAsync on res
}
controller CSync {
  event res : int
  sref a = A
  sref b = B
  connection a on x to b on x
  connection b on res to CSync on res
}
"""


def test_rule12_async_connection_sender_never_blocks(tmp_path) -> None:
    """§2.12: asynchronously A writes 1 then 2 at time 0 into a one-place overwriting buffer; B
    reads 2 at time 1. Synchronously A blocks on x!1 until B is ready at time 1, then on x!2 for
    ever, which B, at its final state, never takes: CSync never terminates (§5.6; the run itself is
    tests/test_interpreter.py's `test_rule12_async_buffer_overwrites`)."""
    rs = run(tmp_path, ASYNC, "assertion Async: CAsync does not terminate.\n"
                              "assertion Sync: CSync does not terminate.\n", bound=24)
    expect(rs["Async"], "violated", ["tock", "CAsync::res.out.2", "CAsync::terminate"])
    expect(rs["Sync"], "holds")


def test_rule12_module_with_platform_and_async_connection(tmp_path) -> None:
    """§2.12, §1: the platform's event is visible at module level (Mod::e.in.v); Mod terminates
    when its controller's machine does, with a hidden terminate (§5.6): the trace ends in ✓."""
    rct = """
interface IE { event e : int }
robotic platform RP { uses IE }
stm M {
  uses IE
  var x : int = 0
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger e?x condition x == 1 }
}
controller Ctrl {
  uses IE
  sref m = M
  connection Ctrl on e to m on e
}
module Mod {
  rref rp = RP
  cref c = Ctrl
  connection rp on e to c on e ( _async )
}
"""
    rs = run(tmp_path, rct, "assertion NT: Mod does not terminate.\n", ranges=MINUS1_1, bound=20)
    expect(rs["NT"], "violated", ["Mod::e.in.1"])


# ---------------------------------------------------------------------------- rule 13

SHARED_VAR = """
interface SV { var sv : int }
stm W {
  requires SV
  initial i
  state s { entry sv = 3 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm R {
  requires SV
  event res : int
  initial i
  state w {}
  final f
  transition t0 { from i to w }
  transition t1 { from w to f condition sv == 3 action res!sv }
}
controller Ctrl {
  var sv : int = 0
  event res : int
  sref wr = W
  sref rd = R
  connection rd on res to Ctrl on res
}
"""


def test_rule13_shared_controller_variable(tmp_path) -> None:
    """§2.13: W writes the controller's sv = 3 and stops; R reads it (initially 0) and stops; Ctrl
    then terminates."""
    rs = run(tmp_path, SHARED_VAR, "assertion NT: Ctrl does not terminate.\n", bound=20)
    expect(rs["NT"], "violated", ["Ctrl::res.out.3", "Ctrl::terminate"])


def test_rule13_machine_alone_has_own_copy(tmp_path) -> None:
    """§2.13, §5.5: R alone keeps its own copy of sv, from RoboTool's default 0, which only its
    environment's visible writes (`R::set_EXT_sv`) change, within the range; W alone's write is
    the visible event `W::set_sv`."""
    text = "assertion NR: R does not terminate.\nassertion NW: W does not terminate.\n"
    rs = run(tmp_path, SHARED_VAR, text, ranges=MINUS1_1)
    expect(rs["NR"], "holds")
    rs = run(tmp_path, SHARED_VAR, text)
    expect(rs["NR"], "violated", ["R::set_EXT_sv.3", "R::res.out.3", "R::terminate"])
    expect(rs["NW"], "violated", ["W::set_sv.3", "W::terminate"])


def test_rule13_copies_are_updated_late(tmp_path) -> None:
    """§5.5: each machine keeps a copy of sv; W's write reaches R's copy by a hidden step of the
    controller's memory, which may come after R has read its copy: R may see 0 after W wrote 3, so
    `res.out.0` is possible.  The copies start at int's default 0, not the controller's 5, which
    the memory passes on at the start."""
    late = SHARED_VAR.replace("condition sv == 3 action res!sv", "action res!sv").replace("var sv : int = 0",
                                                                                             "var sv : int = 5")
    text = ("csp S35 csp-begin\nS35 = Ctrl::res.out.3 -> SKIP [] Ctrl::res.out.5 -> SKIP\ncsp-end\n"
            "csp S03 csp-begin\nS03 = Ctrl::res.out.0 -> SKIP [] Ctrl::res.out.3 -> SKIP\ncsp-end\n"
            "assertion A35: Ctrl refines S35 in the traces model.\nassertion A03: Ctrl refines S03 in the traces model.\n")
    rs = run(tmp_path, late, text, bound=20)
    expect(rs["A35"], "violated", ["Ctrl::res.out.0"])
    expect(rs["A03"], "violated", ["Ctrl::res.out.5"])


def test_rule13_an_environment_write_read_by_a_deadline_is_chosen_when_read(tmp_path) -> None:
    """The environment's write `M::set_EXT_s` carries a value the explicit engine chooses only when
    a step reads it; here the trigger deadline's condition `s != 1`, re-armed after the write. (It
    once stopped the explicit engine with an internal error: the value was in neither the
    configuration nor an input it split.)"""
    rct = """
interface Shared { var s : int }
stm M {
  event c
  requires Shared
  initial i
  state S0 { }
  state S1 { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S1 trigger c <{1} condition s != 1 }
}
"""
    text = "assertion T: M is timelock-free.\nassertion R: S1 is reachable in M.\n"
    bmc = run(tmp_path, rct, text, ranges=MINUS1_1)
    config = configure(tockbmc.load(tmp_path), MINUS1_1)
    explicit = {r.assertion: r for r in check_explicit(config.project, None, 14, MINUS1_1, {}, 60, 100_000,
                                                       config=config)}
    for rs in (bmc, explicit):
        expect(rs["T"], "violated")
        expect(rs["R"], "holds")


# ---------------------------------------------------------------------------- rule 14


def test_rule14_data_ranges_and_nat(tmp_path) -> None:
    """§2.14, §2.16: in the open reading an uninitialised int is unbounded, bounded by core_int;
    by default it starts at RoboTool's 0; a nat variable or input is never negative."""
    rct = """
stm M {
  event e : nat
  var x : int
  var n : nat
  var m : nat = 0
  initial i
  state s {}
  state big {}
  state neg {}
  state neginput {}
  transition t0 { from i to s }
  transition t1 { from s to big condition x > 100 }
  transition t2 { from s to neg condition n < 0 }
  transition t3 { from s to neginput trigger e?m condition m < 0 }
}
"""
    text = ("assertion Big: big is reachable in M.\n"
            "assertion NoBig: big is not reachable in M.\n"
            "assertion Neg: neg is not reachable in M.\n"
            "assertion NegIn: neginput is not reachable in M.\n")
    rs = run(tmp_path, rct, text, reading=Reading.OPEN)
    expect(rs["Big"], "holds", [])
    expect(rs["NoBig"], "violated", [])
    expect(rs["Neg"], "holds")
    expect(rs["NegIn"], "holds")
    rs = run(tmp_path, rct, text, ranges=MINUS1_1, names=["NoBig"], reading=Reading.OPEN)
    expect(rs["NoBig"], "holds")
    rs = run(tmp_path, rct, text)
    expect(rs["Big"], "violated")
    expect(rs["NoBig"], "holds")
    assert rs["NoBig"].defaults == {"M::x": "0", "M::n": "0"} and rs["NoBig"].reading == "default"


def test_rule14_real_arithmetic_is_exact(tmp_path) -> None:
    """§2.14: 0.5 + 0.25 is exactly 0.75."""
    rct = """
stm M {
  var r : real = 0
  initial i
  state s { entry r = 0.5 + 0.25 }
  state ok {}
  state bad {}
  transition t0 { from i to s }
  transition t1 { from s to ok condition r * 4 == 3 }
  transition t2 { from s to bad condition r * 4 != 3 }
}
"""
    rs = run(tmp_path, rct, "assertion OK: ok is reachable in M.\nassertion Bad: bad is not reachable in M.\n")
    expect(rs["OK"], "holds", [])
    expect(rs["Bad"], "holds")


# ---------------------------------------------------------------------------- rule 15


def test_rule15_constants_with_and_without_value(tmp_path) -> None:
    """§2.15, §3: p has no value, so it takes RoboTool's default, 0, and M never terminates; made a
    parameter (`--param p`), every p in -1..1 is considered and p == 1 terminates; `with constant`
    fixes it either way; k == 2 from its declaration. With p = 0, s only lets time pass."""
    rct = """
stm M {
  const k : int = 2
  const p : int
  event e
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger e condition p == 1 /\\ k == 2 }
}
"""
    text = ("assertion NT: M does not terminate.\n"
            "assertion NT0: M does not terminate with constant p of M set to 0.\n"
            "assertion NT1: M does not terminate with constant p of M set to 1.\n"
            "assertion DL0: M is deadlock-free with constant p of M set to 0.\n"
            "assertion DL1: M is deadlock-free with constant p of M set to 1.\n")
    rs = run(tmp_path, rct, text, ranges=MINUS1_1)
    expect(rs["NT"], "holds")
    assert rs["NT"].constants == {"M::k": "2", "M::p": "0"}
    assert rs["NT"].sources["constants"]["M::p"] == "RoboTool default"
    expect(rs["NT0"], "holds")
    expect(rs["NT1"], "violated", ["M::e.in", "M::terminate"])
    expect(rs["DL0"], "violated")
    assert [e for e in events(rs["DL0"]) if e != "tock"] == []
    expect(rs["DL1"], "holds")
    ps = run(tmp_path, rct, text, ranges=MINUS1_1, params=("p",))
    expect(ps["NT"], "violated", ["M::e.in", "M::terminate"])
    assert ps["NT"].constants["M::p"] == "parameter (-1..1)" and ps["NT"].sources["constants"]["M::p"] == "--param"
    expect(ps["NT1"], "violated", ["M::e.in", "M::terminate"])  # `with constant` still fixes a parameter
    expect(ps["NT0"], "holds")


def test_rule15_defined_and_uninterpreted_functions(tmp_path) -> None:
    """§2.15: dbl is defined (dbl(3) == 6 only); g is uninterpreted apart from result > a, so
    g(3) may be 100 but never <= 3. Every such g is considered: `zbig is reachable` needs g(3) == 100,
    so it does not hold for every g (a witness that chose g would say `holds`). `six is
    reachable` holds for every g: its witness runs s's entry, which calls g, so the interpreter
    cannot replay it, but with its moves fixed no g falsifies a guard on its way
    (`bmc.interpretations`)."""
    rct = """
function dbl(a : int) : int {
  postcondition result == 2 * a
}
function g(a : int) : int {
  postcondition result > a
}
stm M {
  var y : int = 0
  var z : int = 0
  initial i
  state s { entry y = dbl(3) ; z = g(3) }
  state six {}
  state notsix {}
  state zbig {}
  state zsmall {}
  transition t0 { from i to s }
  transition t1 { from s to six condition y == 6 }
  transition t2 { from s to notsix condition y != 6 }
  transition t3 { from s to zbig condition z == 100 }
  transition t4 { from s to zsmall condition z <= 3 }
}
"""
    rs = run(tmp_path, rct, "assertion Six: six is reachable in M.\n"
                            "assertion NotSix: notsix is not reachable in M.\n"
                            "assertion ZBig: zbig is reachable in M.\n"
                            "assertion ZSmall: zsmall is not reachable in M.\n")
    expect(rs["Six"], "holds", [])
    assert rs["Six"].extra["unspecified"] == "the run stands whatever the model leaves open (g)"
    expect(rs["NotSix"], "holds")
    expect(rs["ZBig"], "unknown")
    assert "the run rests on what the model leaves open (g)" in (rs["ZBig"].reason or "")
    expect(rs["ZSmall"], "holds")


# ---------------------------------------------------------------------------- section 3


def test_section3_terminates(tmp_path) -> None:
    """§3 `terminates`: N can always terminate. In M, after b, wait(2) <{1} is stuck after one
    tock: the wait needs a tock, the deadline refuses it, nothing else is offered."""
    rct = """
stm M {
  event a
  event b
  initial i
  state s0 {}
  state s { entry wait(2) <{1} }
  final f
  transition t0 { from i to s0 }
  transition t1 { from s0 to f trigger a }
  transition t2 { from s0 to s trigger b }
}
stm N {
  event a
  initial i
  state s0 {}
  final f
  transition t0 { from i to s0 }
  transition t1 { from s0 to f trigger a }
}
"""
    rs = run(tmp_path, rct, "assertion TM: M terminates.\nassertion TN: N terminates.\n")
    expect(rs["TM"], "violated", ["M::b.in", "tock"])
    expect(rs["TN"], "holds")


def test_section3_deadlock_free(tmp_path) -> None:
    """§3 `is deadlock-free` (timed): Live always offers e; Dead offers only tock after e;
    Div loops internally for ever; Term terminates, which is not a deadlock."""
    rct = """
stm Live {
  event e
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger e }
}
stm Dead {
  event e
  initial i
  state s {}
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u trigger e }
}
stm Div {
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s }
}
stm Term {
  initial i
  final f
  transition t0 { from i to f }
}
"""
    rs = run(tmp_path, rct, "assertion L: Live is deadlock-free.\n"
                            "assertion D: Dead is deadlock-free.\n"
                            "assertion ND: Dead is not deadlock-free.\n"
                            "assertion V: Div is deadlock-free.\n"
                            "assertion T: Term is deadlock-free.\n")
    expect(rs["L"], "holds")
    expect(rs["D"], "violated")
    assert [e for e in events(rs["D"]) if e != "tock"] == ["Dead::e.in"]
    expect(rs["ND"], "holds")
    assert [e for e in events(rs["ND"]) if e != "tock"] == ["Dead::e.in"]
    expect(rs["V"], "violated")
    assert events(rs["V"]) == []
    expect(rs["T"], "holds")


def test_section3_untimed_and_csp_assertions(tmp_path) -> None:
    """§3: untimed assertions are checked in RoboTool's untimed semantics: M, stable in s with
    nothing to do, refuses every event, an untimed deadlock (U1), while timelock-freedom has no
    untimed meaning (U4, unsupported). §4: a
    CSP process with no model element in it cannot be the subject of an assertion (C1); M refines
    Spec is checked (C2): outside a Timed section the prefix refuses tock, and M, stable in s,
    lets time pass, so the trace <tock> is M's but not Spec's."""
    rct = """
stm M {
  initial i
  state s {}
  transition t0 { from i to s }
}
"""
    text = """
untimed assertion U1: M is deadlock-free.
untimed assertion U2: s is reachable in M.
untimed assertion U3: M does not terminate.
untimed assertion U4: M is timelock-free.
timed csp Spec csp-begin
Spec = M::terminate -> SKIP
csp-end
assertion C1: Spec is timelock-free.
assertion C2: M refines Spec in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["U1"], "violated", [])
    expect(rs["U2"], "holds")
    expect(rs["U3"], "holds")
    for name in ["U4", "C1"]:
        assert rs[name].verdict == "unsupported", (name, rs[name].verdict, rs[name].reason)
        assert rs[name].reason
    expect(rs["C2"], "violated", ["tock"])


def test_section3_csp_outside_subset_is_unsupported(tmp_path) -> None:
    """§4: a CSP construct outside the subset (renaming) is unsupported, and the other
    assertions still run."""
    rct = """
stm M {
  initial i
  final f
  transition t0 { from i to f }
}
"""
    text = """
timed csp Spec csp-begin
Spec = (M::terminate -> SKIP) [[ M::terminate <- M::terminate ]]
csp-end
assertion C: M refines Spec in the traces model.
assertion NT: M does not terminate.
"""
    rs = run(tmp_path, rct, text)
    assert rs["C"].verdict == "unsupported", (rs["C"].verdict, rs["C"].reason)
    expect(rs["NT"], "violated", ["M::terminate"])


def test_rule2_each_call_of_an_operation_starts_afresh(tmp_path) -> None:
    """§2.2/§2.15 (found by comparing the engines): an operation's variable is initialised at each
    call, so `bump()` called twice outputs k = 1 both times, never 2."""
    rct = """
interface Ops { bump() }
stm M {
  requires Ops
  event out : int
  initial i
  state s { entry bump() ; bump() }
  transition t0 { from i to s }
}
controller C {
  event out : int
  operation bump() {
    event out : int
    var k : int = 0
    initial i
    final f
    transition t0 { from i to f action k = k + 1 ; out!k }
  }
  sref m = M
  connection m on out to C on out
}
"""
    text = """
timed csp Ones csp-begin
Timed(OneStep) { Ones = C::out.out.1 -> C::out.out.1 -> STOP }
csp-end
assertion A: C refines Ones in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["A"], "holds")
