"""One small model per CSP operator of /work/shared/semantics.md, §4 ("CSP blocks").

Every expected verdict and every expected visible trace (FDR event names, `tock` included,
internal steps left out) is derived by hand from §1–§4 and from these conventions:

- `P refines Q in the traces model`: every trace of P (tock included) is a trace of Q; the
  counterexample is the shortest trace of P whose last event Q cannot do.
- Inside `Timed(OneStep) { … }` a prefix `e -> P` lets time pass while waiting for `e` and `STOP`
  lets time pass for ever; outside a Timed section both refuse `tock`.
- Hidden events are internal, hence urgent; `timed_priority` (maximal progress) is always applied.
- `M::D__(id, c1, …)` / `M::O__(id, …)` is machine `M` with its constants set in declaration
  order; after `M::terminate` it terminates successfully, so `M::D__(0) ; P` continues as `P`.

Where several shortest counterexamples exist only what they share is asserted. Where a semantic
point was unclear, the model was chosen so that the verdict does not depend on it; the docstring
says what was assumed. Machines never terminate unless the specification can terminate at the
same point, so that no verdict depends on whether ✓ counts as an event of a trace.
"""

from __future__ import annotations

import re
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.model.config import configure
from tockbmc.model.result import Result

MINUS1_1 = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})


def run(tmp_path: Path, rct: str, assertions: str, bound: int = 14, ranges: Ranges | None = None,
        names: list[str] | None = None, params: tuple[str, ...] = ()) -> dict[str, Result]:
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    config = configure(project, ranges or Ranges(), params=params)
    return {r.assertion: r for r in check(project, names, bound=bound, config=config)}


def events(r: Result) -> list[str]:
    return [s.event for s in r.trace if s.kind != "internal"]


def expect(r: Result, verdict: str, trace: list[str] | None = None) -> None:
    assert r.verdict == verdict, f"{r.assertion}: {r.verdict} ({r.reason}); trace {events(r)}"
    if trace is not None:
        assert events(r) == trace, f"{r.assertion}: trace {events(r)}"


# ---------------------------------------------------------------------------- machines

# Lets only time pass: traces tock*.
IDLE = """
stm Z {
  initial i
  state s {}
  transition t0 { from i to s }
}
"""

# Outputs e!1 (not urgent), then terminates: traces tock* M::e.out.1 tock* M::terminate.
OUT = """
stm M {
  event e : int
  initial i
  state s { entry e!1 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
"""

# Terminates at once: traces tock* T0::terminate.
TERM = """
stm T0 {
  initial i
  final f
  transition t0 { from i to f }
}
"""

# Waits for go, then terminates: traces tock* T::go.in tock* T::terminate.
GO = """
stm T {
  event go
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger go }
}
"""

# Outputs e!1 for ever: traces (tock* L::e.out.1)* tock*; never terminates.
LOOP = """
stm L {
  event e : int
  initial i
  state s { entry e!1 }
  transition t0 { from i to s }
  transition t1 { from s to s }
}
"""

# Urgent counter: e!0, e!1, e!2 at time 0 (deadline 0 each), then only tocks. Its only maximal
# trace is <N::e.out.0, N::e.out.1, N::e.out.2, tock, tock, ...>: no tock before e.out.2.
COUNTER = """
stm N {
  event e : int
  var n : int = 0
  initial i
  state s { entry e!n <{0} ; n = n + 1 }
  transition t0 { from i to s }
  transition t1 { from s to s condition n < 3 }
}
"""

# After input a, outputs b or c (nondeterministic): traces tock* X::a.in tock* (X::b.out |
# X::c.out) tock*.
ABC = """
stm X {
  event a
  event b
  event c
  initial i
  state s0 {}
  state s1 {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to s1 trigger a action b }
  transition t2 { from s0 to s1 trigger a action c }
}
"""

# Accepts a or b once: traces tock* (Y::a.in | Y::b.in) tock*.
AORB = """
stm Y {
  event a
  event b
  initial i
  state s {}
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u trigger a }
  transition t2 { from s to u trigger b }
}
"""


# ---------------------------------------------------------------------------- STOP, SKIP


def test_stop_untimed_and_timed(tmp_path) -> None:
    """§4 `Timed(OneStep)`: outside a Timed section STOP refuses tock, inside it lets time pass.

    Z's traces are tock*. SU (untimed STOP) has only <>, so the shortest trace of Z it cannot do
    is <tock>; ST (timed STOP) has tock*, so Z refines it.
    """
    text = """
csp SU csp-begin
SU = STOP
csp-end
timed csp ST csp-begin
Timed(OneStep) {
  ST = STOP
}
csp-end
assertion U: Z refines SU in the traces model.
assertion T: Z refines ST in the traces model.
"""
    rs = run(tmp_path, IDLE, text)
    expect(rs["U"], "violated", ["tock"])
    expect(rs["T"], "holds")


@pytest.mark.xfail(strict=True, reason="a CSP process with no model element in it cannot be the subject of an assertion yet")
def test_stop_timelock_freedom_of_a_csp_process(tmp_path) -> None:
    """§3 timelock-free on a process of a CSP block (§3: `P` may be "a process defined in a CSP
    block"): the untimed STOP is stable and refuses tock at once, a timelock at <>; the timed
    STOP never refuses tock and never terminates."""
    text = """
csp SU csp-begin
SU = STOP
csp-end
timed csp ST csp-begin
Timed(OneStep) {
  ST = STOP
}
csp-end
assertion UTL: SU is timelock-free.
assertion UNTL: SU is not timelock-free.
assertion TTL: ST is timelock-free.
"""
    rs = run(tmp_path, IDLE, text)
    expect(rs["UTL"], "violated", [])
    expect(rs["UNTL"], "holds", [])
    expect(rs["TTL"], "holds")


def test_skip_terminates_without_events(tmp_path) -> None:
    """§4 SKIP: it terminates at once and does no event.

    T0's traces: tock* T0::terminate (then ✓). SS = SKIP ; (T0::terminate -> SKIP) in a Timed
    section behaves as the timed prefix, so T0 refines it (a SKIP that behaved like STOP would
    refuse terminate). PT = T0 |\\ {|T0::terminate|} has traces <>, <T0::terminate> (tock hidden):
    the bare SKIP (no Timed section) cannot do T0::terminate, so the counterexample is
    <T0::terminate>; the untimed `T0::terminate -> SKIP` can, and terminates as PT does.
    """
    text = """
timed csp SS csp-begin
Timed(OneStep) {
  SS = SKIP ; (T0::terminate -> SKIP)
}
csp-end
csp Skips csp-begin
PT = T0::D__(0) |\\ {| T0::terminate |}
Sk = SKIP
TS = T0::terminate -> SKIP
csp-end
assertion A: T0 refines SS in the traces model.
assertion B: PT refines Sk in the traces model.
assertion C: PT refines TS in the traces model.
"""
    rs = run(tmp_path, TERM, text)
    expect(rs["A"], "holds")
    expect(rs["B"], "violated", ["T0::terminate"])
    expect(rs["C"], "holds")


# ---------------------------------------------------------------------------- prefix, c?x


def test_prefix_with_output_values(tmp_path) -> None:
    """§4 `e -> P`, `c!v -> P`, §1 event names. M's traces: tock* M::e.out.1 tock* M::terminate.

    P1 (`M::e.out.1`) and P2 (`M::e.out!1`) name the same event; in a Timed section tock is
    allowed while waiting, so both hold. P3 offers e.out.2 only: the shortest trace of M it
    cannot do is <M::e.out.1> (<tock> is allowed). P4 stops after e.out.1 (timed STOP: tocks
    only): <M::e.out.1, M::terminate>. PU is the same prefix outside a Timed section, so it
    refuses tock: <tock>.
    """
    text = """
timed csp Prefixes csp-begin
Timed(OneStep) {
  P1 = M::e.out.1 -> M::terminate -> SKIP
  P2 = M::e.out!1 -> M::terminate -> SKIP
  P3 = M::e.out.2 -> M::terminate -> SKIP
  P4 = M::e.out!1 -> STOP
}
csp-end
csp PU csp-begin
PU = M::e.out.1 -> M::terminate -> SKIP
csp-end
assertion A1: M refines P1 in the traces model.
assertion A2: M refines P2 in the traces model.
assertion A3: M refines P3 in the traces model.
assertion A4: M refines P4 in the traces model.
assertion AU: M refines PU in the traces model.
"""
    rs = run(tmp_path, OUT, text)
    expect(rs["A1"], "holds")
    expect(rs["A2"], "holds")
    expect(rs["A3"], "violated", ["M::e.out.1"])
    expect(rs["A4"], "violated", ["M::e.out.1", "M::terminate"])
    expect(rs["AU"], "violated", ["tock"])


def test_input_prefix_binds_value(tmp_path) -> None:
    """§4 `c?x -> P` with core_int = -1..1. M echoes its input: tock* M::c.in.v tock* M::e.out.v
    tock*.

    Any accepts every input and every output: holds. In0 accepts only c.in.0: the shortest
    counterexample is <M::c.in.v> with v in {-1, 1}. Echo binds x and outputs it: holds. Plus
    outputs x+1, never v: the shortest counterexample is <M::c.in.v, M::e.out.v> for some v in
    -1..1 (any v will do).
    """
    rct = """
stm M {
  event c : int
  event e : int
  var x : int = 0
  initial i
  state s {}
  state t { entry e!x }
  transition t0 { from i to s }
  transition t1 { from s to t trigger c?x }
}
"""
    text = """
timed csp Inputs csp-begin
Timed(OneStep) {
  Any = M::c.in?x -> M::e.out?y -> STOP
  In0 = M::c.in.0 -> M::e.out?y -> STOP
  Echo = M::c.in?x -> M::e.out!x -> STOP
  Plus = M::c.in?x -> M::e.out!(x + 1) -> STOP
}
csp-end
assertion A: M refines Any in the traces model.
assertion I0: M refines In0 in the traces model.
assertion E: M refines Echo in the traces model.
assertion P: M refines Plus in the traces model.
"""
    rs = run(tmp_path, rct, text, ranges=MINUS1_1)
    expect(rs["A"], "holds")
    expect(rs["I0"], "violated")
    assert events(rs["I0"]) in (["M::c.in.-1"], ["M::c.in.1"]), events(rs["I0"])
    expect(rs["E"], "holds")
    expect(rs["P"], "violated")
    ev = events(rs["P"])
    assert len(ev) == 2, ev
    v = ev[0].rsplit(".", 1)[1]
    assert ev[0] == f"M::c.in.{v}" and int(v) in (-1, 0, 1), ev
    assert ev[1] == f"M::e.out.{v}", ev


# ---------------------------------------------------------------------------- choice


def test_external_choice(tmp_path) -> None:
    """§4 `P [] Q`. Y accepts a or b (after any number of tocks). EC offers both; tock does not
    resolve the choice in a Timed section, so <tock, Y::b.in> is allowed: holds. OnlyA offers a
    only: the shortest counterexample is <Y::b.in>."""
    text = """
timed csp Choices csp-begin
Timed(OneStep) {
  EC = (Y::a.in -> STOP) [] (Y::b.in -> STOP)
  OnlyA = Y::a.in -> STOP
}
csp-end
assertion AEC: Y refines EC in the traces model.
assertion OA: Y refines OnlyA in the traces model.
"""
    rs = run(tmp_path, AORB, text)
    expect(rs["AEC"], "holds")
    expect(rs["OA"], "violated", ["Y::b.in"])


def test_internal_choice_spec_accepts_both_continuations(tmp_path) -> None:
    """§4 `P |~| Q`: traces of P |~| Q are those of P [] Q. X, after a, outputs b or c. ND =
    a -> b -> STOP |~| a -> c -> STOP has both continuations: holds. OnlyB lacks c: the
    shortest counterexample is <X::a.in, X::c.out>. On Y (a or b), IC = a -> STOP |~| b -> STOP
    has both first events: holds."""
    text = """
timed csp Nondet csp-begin
Timed(OneStep) {
  ND = (X::a.in -> X::b.out -> STOP) |~| (X::a.in -> X::c.out -> STOP)
  OnlyB = X::a.in -> X::b.out -> STOP
  IC = (Y::a.in -> STOP) |~| (Y::b.in -> STOP)
}
csp-end
assertion NDBoth: X refines ND in the traces model.
assertion OB: X refines OnlyB in the traces model.
assertion AIC: Y refines IC in the traces model.
"""
    rs = run(tmp_path, ABC + AORB, text)
    expect(rs["NDBoth"], "holds")
    expect(rs["OB"], "violated", ["X::a.in", "X::c.out"])
    expect(rs["AIC"], "holds")


def test_replicated_internal_choice_over_a_channel_has_a_branch_per_listed_event(tmp_path) -> None:
    """§4 `|~| ev : {| c |} @ ev -> P`: a branch per event of c, each offering that event alone
    (not one offering every value, as `c?x` does). W outputs e.0 for ever: its stable failures
    (refusing all but e.out.0) are failures of the branch for e.out.0, so W refines Each in the
    failures model; Stuck outputs e.0 once and then refuses everything, which no branch does.
    Both engines read the specification alike, with e's values listed within the ranges."""
    rct = """
stm W {
  event e : nat
  initial i
  state A { }
  transition t0 { from i to A }
  transition t1 { from A to A action e!0 }
}
stm Stuck {
  event e : nat
  initial i
  state A { }
  state B { }
  transition t0 { from i to A }
  transition t1 { from A to B action e!0 }
}
"""
    text = """
csp Each csp-begin
Each = |~| ev : {| W::e |} @ ev -> Each
EachStuck = |~| ev : {| Stuck::e.out |} @ ev -> EachStuck
csp-end
untimed assertion Holds: W refines Each in the failures model.
untimed assertion Stops: Stuck refines EachStuck in the failures model.
"""
    from tockbmc.explicit.engine import check_explicit
    nat = Ranges({"core_nat": Range(Fraction(0), Fraction(2))})
    rs = run(tmp_path, rct, text, ranges=nat)
    by_search = {r.assertion: r for r in check_explicit(tockbmc.load(tmp_path), None, 14, nat, {}, 60)}
    for results in (rs, by_search):
        expect(results["Holds"], "holds")
        expect(results["Stops"], "violated", ["Stuck::e.out.0"])


# ---------------------------------------------------------------------------- sequential composition


def test_sequential_composition_after_machine_termination(tmp_path) -> None:
    """§4 `P ; Q`: after T::terminate, T::D__(0) terminates and Q starts.

    Seq = T ; (T::go.in -> STOP) in a Timed section: traces tock* go tock* terminate tock* go
    tock*. SpecSeq = go -> terminate -> STOP (timed) allows every tock and <go, terminate>, but
    no second go: the shortest counterexample is <T::go.in, T::terminate, T::go.in>.
    """
    text = """
timed csp Seqs csp-begin
Timed(OneStep) {
  Seq = T::D__(0) ; (T::go.in -> STOP)
  SpecSeq = T::go.in -> T::terminate -> STOP
}
csp-end
assertion S: Seq refines SpecSeq in the traces model.
"""
    rs = run(tmp_path, GO, text)
    expect(rs["S"], "violated", ["T::go.in", "T::terminate", "T::go.in"])


def test_sequential_composition_into_untimed_and_timed_stop(tmp_path) -> None:
    """§4 `P ; Q`, `Timed`, §3 timelock-free. SeqU = T ; STOP outside a Timed section: after
    terminate, STOP is stable and refuses tock, and it never terminates: a timelock after
    <T::go.in, T::terminate> (before that T lets time pass: go is an input, terminate is not
    urgent). SeqT, the same with a timed STOP, is timelock-free."""
    text = """
timed csp SeqT csp-begin
Timed(OneStep) {
  SeqT = T::D__(0) ; STOP
}
csp-end
csp SeqU csp-begin
SeqU = T::D__(0) ; STOP
csp-end
assertion UTL: SeqU is timelock-free.
assertion TTL: SeqT is timelock-free.
"""
    rs = run(tmp_path, GO, text)
    expect(rs["UTL"], "violated", ["T::go.in", "T::terminate"])
    expect(rs["TTL"], "holds")


# ---------------------------------------------------------------------------- guards, if, let


def test_guard_with_definition_parameter(tmp_path) -> None:
    """§4 `b & P` with `N(x) = …`. N's only trace is e.out.0, e.out.1, e.out.2, then tocks (no
    tock before e.out.2: every output has deadline 0).

    G(x) = x < 5 & e!x -> G(x+1): the guard is true for x = 0..3, so G(0) does e.out.0..2 and
    then waits in G(3), a timed prefix, while N tocks: holds. H(x) = x != 1 & e!x -> H(x+1): at
    x = 1 the guard is false (STOP), so <N::e.out.0, N::e.out.1> is the counterexample. Assumed
    nothing about whether a false guard's STOP lets time pass: N never tocks before e.out.2.
    """
    text = """
timed csp Guards csp-begin
Timed(OneStep) {
  G(x) = x < 5 & N::e.out!x -> G(x + 1)
  H(x) = x != 1 & N::e.out!x -> H(x + 1)
  SpecG = G(0)
  SpecH = H(0)
}
csp-end
assertion AG: N refines SpecG in the traces model.
assertion AH: N refines SpecH in the traces model.
"""
    rs = run(tmp_path, COUNTER, text)
    expect(rs["AG"], "holds")
    expect(rs["AH"], "violated", ["N::e.out.0", "N::e.out.1"])


def test_robotool_instantiation_names_in_a_specification(tmp_path) -> None:
    """What a specification reads from RoboTool's generated instantiation (SRangerRC2RS writes
    `WAIT(MinusNoNeg(Div(PI, av, core_nat), 2, core_nat))`): a `nametype` is a name for its set,
    `member(x, S)` is CSPm's, and the generated `Plus(e1,e2,T) = if member(e1+e2,T) then e1+e2
    else e1` is read as RoboTool's helper (exact, T unread: DESIGN.md, "CSP blocks"), while a
    function of the user's own there is evaluated as written.

    By hand: Twice(x) = Plus(x, x, core_nat) is exact, so Twice(2) = 4 although 4 is not in
    core_nat = {0..3}; Capped(x) = if member(x, core_nat) then x else 0 gives Capped(1) = 1 and
    Capped(7) = 0.  N's trace is e.out.0, e.out.1, e.out.2 (as in the guard's test), so
    S = e.out!Capped(7) -> e.out!Capped(1) -> e.out!Minus(Twice(2), 2, core_nat) -> ... holds,
    and T, expecting e.out.4 third (Twice(2) itself), is violated there."""
    text = """
timed csp Instantiations csp-begin
nametype core_nat = {0..3}
Plus(e1,e2,T) = if member(e1+e2,T) then e1+e2 else e1
Minus(e1,e2,T) = if member(e1-e2,T) then e1-e2 else e1
Twice(x) = Plus(x, x, core_nat)
Capped(x) = if member(x, core_nat) then x else 0
csp-end
timed csp Specs csp-begin
Timed(OneStep) {
  S = N::e.out!Capped(7) -> N::e.out!Capped(1) -> N::e.out!Minus(Twice(2), 2, core_nat) -> STOP
  T = N::e.out!Capped(7) -> N::e.out!Capped(1) -> N::e.out!Twice(2) -> STOP
}
csp-end
assertion AS: N refines S in the traces model.
assertion AT: N refines T in the traces model.
"""
    rs = run(tmp_path, COUNTER, text)
    expect(rs["AS"], "holds")
    expect(rs["AT"], "violated", ["N::e.out.0", "N::e.out.1", "N::e.out.2"])


def test_a_channel_of_the_specifications_own(tmp_path) -> None:
    """`channel h` declares an event of the specification's own (test1 hides its `int__`). Hidden, it
    is an internal step of the specification: S = (h -> e.out.0 -> e.out.1 -> e.out.2 -> STOP) \\ {|h|}
    has N's trace, so N refines S. Not hidden, T = h -> e.out.0 -> STOP starts with h, which N never
    does: N's first event e.out.0 is the counterexample."""
    text = """
timed csp Specs csp-begin
channel h, unused
Timed(OneStep) {
  S = (h -> N::e.out.0 -> N::e.out.1 -> N::e.out.2 -> STOP) \\ {|h|}
  T = h -> N::e.out.0 -> STOP
}
csp-end
assertion AS: N refines S in the traces model.
assertion AT: N refines T in the traces model.
"""
    rs = run(tmp_path, COUNTER, text)
    expect(rs["AS"], "holds")
    expect(rs["AT"], "violated", ["N::e.out.0"])


def test_if_then_else_with_definition_parameter(tmp_path) -> None:
    """§4 `if b then P else Q` with `N(x) = …`. N: e.out.0, e.out.1, e.out.2, then tocks.

    I(x) = if x < 3 then e!x -> I(x+1) else STOP: e.out.0..2, then a timed STOP (tocks): holds.
    J stops at x = 2: <N::e.out.0, N::e.out.1, N::e.out.2>. K takes the then-branch at x = 1
    and offers e.out.5 instead of e.out.1: <N::e.out.0, N::e.out.1>.
    """
    text = """
timed csp Ifs csp-begin
Timed(OneStep) {
  I(x) = if x < 3 then N::e.out!x -> I(x + 1) else STOP
  J(x) = if x < 2 then N::e.out!x -> J(x + 1) else STOP
  K(x) = if x == 1 then N::e.out.5 -> STOP else N::e.out!x -> K(x + 1)
  SpecI = I(0)
  SpecJ = J(0)
  SpecK = K(0)
}
csp-end
assertion AI: N refines SpecI in the traces model.
assertion AJ: N refines SpecJ in the traces model.
assertion AK: N refines SpecK in the traces model.
"""
    rs = run(tmp_path, COUNTER, text)
    expect(rs["AI"], "holds")
    expect(rs["AJ"], "violated", ["N::e.out.0", "N::e.out.1", "N::e.out.2"])
    expect(rs["AK"], "violated", ["N::e.out.0", "N::e.out.1"])


def test_let_within(tmp_path) -> None:
    """§4 `let … within P`. N: e.out.0, e.out.1, e.out.2, then tocks.

    LetOk defines a parameterised Step and a constant process Rest (a timed STOP) locally: Step(0)
    does e.out.0..2 then Rest: holds. LetBad = let A = e.0 -> B, B = e.2 -> STOP within A: after
    e.out.0 only e.out.2 is offered: <N::e.out.0, N::e.out.1>.
    """
    text = """
timed csp Lets csp-begin
Timed(OneStep) {
  LetOk = let
      Step(y) = if y < 3 then N::e.out!y -> Step(y + 1) else Rest
      Rest = STOP
    within Step(0)
  LetBad = let
      A = N::e.out.0 -> B
      B = N::e.out.2 -> STOP
    within A
}
csp-end
assertion Ok: N refines LetOk in the traces model.
assertion Bad: N refines LetBad in the traces model.
"""
    rs = run(tmp_path, COUNTER, text)
    expect(rs["Ok"], "holds")
    expect(rs["Bad"], "violated", ["N::e.out.0", "N::e.out.1"])


def test_recursion(tmp_path) -> None:
    """§4 recursion. L outputs e!1 for ever, any tocks in between. Loop = e.1 -> Loop and the
    mutual recursion A = e.1 -> B, B = e!1 -> A allow every trace of L (timed prefixes): hold.
    Two allows only two outputs: <L::e.out.1, L::e.out.1, L::e.out.1>."""
    text = """
timed csp Recs csp-begin
Timed(OneStep) {
  Loop = L::e.out.1 -> Loop
  A = L::e.out.1 -> B
  B = L::e.out!1 -> A
  Two = L::e.out.1 -> L::e.out.1 -> STOP
}
csp-end
assertion ALoop: L refines Loop in the traces model.
assertion AMutual: L refines A in the traces model.
assertion ATwo: L refines Two in the traces model.
"""
    rs = run(tmp_path, LOOP, text)
    expect(rs["ALoop"], "holds")
    expect(rs["AMutual"], "holds")
    expect(rs["ATwo"], "violated", ["L::e.out.1", "L::e.out.1", "L::e.out.1"])


# ---------------------------------------------------------------------------- hiding, projection

HIDE = """
interface I { op() }
stm H {
  event e
  event early
  event late
  clock C
  var t : int = 0
  initial i
  state s { entry e ; t = since(C) }
  state sa { entry early }
  state sb { entry late }
  transition t0 { from i to s }
  transition t1 { from s to sa condition t == 0 }
  transition t2 { from s to sb condition t >= 1 }
}
stm P {
  requires I
  initial i
  state s { entry op() }
  transition t0 { from i to s }
}
"""


def test_hiding_makes_event_urgent(tmp_path) -> None:
    """§4 `P \\ A`, §2.4, §2.2, §3 timelock-free.

    H's output e is not urgent (§2.4): e at time 0 leads to early, e after a tock to late. So
    H's traces include <tock, H::e.out, H::late.out>, the shortest one SH = e -> early -> STOP
    (timed) cannot do. H is timelock-free: every stable configuration allows tock.
    HE = H \\ {|H::e|}: e is internal, hence urgent, so it happens at time 0, t = 0 and only
    early follows: HE refines SE = early -> STOP. HE is timelock-free too: the configuration
    offering the hidden e is not stable, and after it early waits while time passes.
    P's call op() is urgent (§2.2): the stable configuration offering P::opCall refuses tock, a
    timelock at <>. PH = P \\ {|P::opCall|} makes the call internal: that configuration is no
    longer stable, and afterwards only tocks happen, so PH is timelock-free (IntelliWelder A2).
    """
    text = """
timed csp Hides csp-begin
Timed(OneStep) {
  HE = H::D__(0) \\ {| H::e |}
  SE = H::early.out -> STOP
  SH = H::e.out -> H::early.out -> STOP
  PH = P::D__(0) \\ {| P::opCall |}
}
csp-end
assertion H_SH: H refines SH in the traces model.
assertion HE_SE: HE refines SE in the traces model.
assertion H_TL: H is timelock-free.
assertion HE_TL: HE is timelock-free.
assertion P_TL: P is timelock-free.
assertion PH_TL: PH is timelock-free.
"""
    rs = run(tmp_path, HIDE, text)
    expect(rs["H_SH"], "violated", ["tock", "H::e.out", "H::late.out"])
    expect(rs["HE_SE"], "holds")
    expect(rs["H_TL"], "holds")
    expect(rs["HE_TL"], "holds")
    expect(rs["P_TL"], "violated", [])
    expect(rs["PH_TL"], "holds")


def test_projection_hides_all_but_the_set(tmp_path) -> None:
    """§4 `P |\\ A` hides every event not in A, tock included. M: tock* e.out.1 tock* terminate.

    PT = M |\\ {|M::terminate|} has traces <>, <M::terminate> (then ✓): untimed STOP cannot do
    terminate, so <M::terminate> is the counterexample (A7 of IntelliWelder); the untimed
    `M::terminate -> SKIP` refuses tock, so it holds only because tock is hidden.
    PE = M |\\ {|M::e|} has traces <>, <M::e.out.1> (then ✓): it refines e.out.1 -> SKIP
    (untimed), and not e.out.2 -> SKIP, with counterexample <M::e.out.1>.
    """
    text = """
csp Projs csp-begin
PT = M::D__(0) |\\ {| M::terminate |}
PE = M::D__(0) |\\ {| M::e |}
Stop = STOP
TS = M::terminate -> SKIP
ES1 = M::e.out.1 -> SKIP
ES2 = M::e.out.2 -> SKIP
csp-end
assertion T_Stop: PT refines Stop in the traces model.
assertion T_TS: PT refines TS in the traces model.
assertion E_1: PE refines ES1 in the traces model.
assertion E_2: PE refines ES2 in the traces model.
"""
    rs = run(tmp_path, OUT, text)
    expect(rs["T_Stop"], "violated", ["M::terminate"])
    expect(rs["T_TS"], "holds")
    expect(rs["E_1"], "holds")
    expect(rs["E_2"], "violated", ["M::e.out.1"])


# ---------------------------------------------------------------------------- parallel


def test_parallel_with_skip_blocks_event(tmp_path) -> None:
    """§4 `P [| A |] SKIP` (IntelliWelder A7). M loops on b and terminates on a.

    Blocked = M [| {|M::a|} |] SKIP: SKIP never does a, so a is blocked and M never reaches its
    final state; Blocked never terminates, and BT = (Blocked ; terminate -> SKIP) |\\ {|terminate|}
    has only the trace <>: it refines STOP. Free blocks b instead: a, then M::terminate, so
    FT refines STOP fails at <M::terminate>. Directly: Blocked refines BS = b -> BS (timed),
    while M itself does not: <M::a.in>.
    """
    rct = """
stm M {
  event a
  event b
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger a }
  transition t2 { from s to s trigger b }
}
"""
    text = """
timed csp Blocks associated to M csp-begin
Blocked = M::D__(0) [| {| M::a |} |] SKIP
Free = M::D__(0) [| {| M::b |} |] SKIP
BT = (Blocked ; M::terminate -> SKIP) |\\ {| M::terminate |}
FT = (Free ; M::terminate -> SKIP) |\\ {| M::terminate |}
csp-end
csp Stop csp-begin
Stop = STOP
csp-end
timed csp BS csp-begin
Timed(OneStep) {
  BS = M::b.in -> BS
}
csp-end
assertion ABT: BT refines Stop in the traces model.
assertion AFT: FT refines Stop in the traces model.
assertion BB: Blocked refines BS in the traces model.
assertion MB: M refines BS in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["ABT"], "holds")
    expect(rs["AFT"], "violated", ["M::terminate"])
    expect(rs["BB"], "holds")
    expect(rs["MB"], "violated", ["M::a.in"])


INTERLEAVE = """
stm IA {
  event a
  initial i
  state s { entry a }
  transition t0 { from i to s }
}
stm IB {
  event b
  initial i
  state s { entry b }
  transition t0 { from i to s }
}
controller C {
  event a
  event b
  sref ia = IA
  sref ib = IB
  connection ia on a to C on a
  connection ib on b to C on b
}
"""


def test_interleaving_in_the_specification(tmp_path) -> None:
    """§4 `P ||| Q` in a specification. C's machines output a and b independently, each when
    the environment wants (§2.4, §2.12): C can do C::b.out first, so the sequential spec
    a -> b -> STOP fails at <C::b.out>; (a -> STOP) ||| (b -> STOP) allows both orders and,
    both sides allowing tock everywhere, every placement of tocks: holds (whether tock is
    synchronised between the sides does not matter here)."""
    text = """
timed csp Inter csp-begin
Timed(OneStep) {
  SeqC = C::a.out -> C::b.out -> STOP
  ParC = (C::a.out -> STOP) ||| (C::b.out -> STOP)
}
csp-end
assertion Seq: C refines SeqC in the traces model.
assertion Par: C refines ParC in the traces model.
"""
    rs = run(tmp_path, INTERLEAVE, text)
    expect(rs["Seq"], "violated", ["C::b.out"])
    expect(rs["Par"], "holds")


@pytest.mark.xfail(strict=True, reason="model processes can only be hidden, projected, blocked, sequenced and prefixed; '|||' of two is unsupported")
def test_interleaving_model_processes(tmp_path) -> None:
    """§4 `P ||| Q` with model processes on both sides (nothing in §4 restricts the operands).
    Both = IA ||| IB can do IB::b.out first: a -> b -> STOP fails at <IB::b.out>; the
    interleaved spec allows every order and every placement of tocks: holds."""
    text = """
timed csp InterM csp-begin
Timed(OneStep) {
  Both = IA::D__(0) ||| IB::D__(0)
  Seq = IA::a.out -> IB::b.out -> STOP
  Par = (IA::a.out -> STOP) ||| (IB::b.out -> STOP)
}
csp-end
assertion ASeq: Both refines Seq in the traces model.
assertion APar: Both refines Par in the traces model.
"""
    rs = run(tmp_path, INTERLEAVE, text)
    expect(rs["ASeq"], "violated", ["IB::b.out"])
    expect(rs["APar"], "holds")


# ---------------------------------------------------------------------------- exception


def test_exception_hands_over(tmp_path) -> None:
    """§4 `P [| A |> Q`: on P's first event of A, Q takes over and P is discarded. X: a, then b
    or c. Ex1 = (a -> c -> STOP) [| {|X::a|} |> (b -> STOP): after a only b is possible (P's c
    is gone), so <X::a.in, X::c.out> is the counterexample. Ex2's handler offers b and c:
    holds."""
    text = """
timed csp Exc csp-begin
Timed(OneStep) {
  Ex1 = (X::a.in -> X::c.out -> STOP) [| {| X::a |} |> (X::b.out -> STOP)
  Ex2 = (X::a.in -> X::c.out -> STOP) [| {| X::a |} |> ((X::b.out -> STOP) [] (X::c.out -> STOP))
}
csp-end
assertion AEx1: X refines Ex1 in the traces model.
assertion AEx2: X refines Ex2 in the traces model.
"""
    rs = run(tmp_path, ABC, text)
    expect(rs["AEx1"], "violated", ["X::a.in", "X::c.out"])
    expect(rs["AEx2"], "holds")


# ---------------------------------------------------------------------------- RUN, CHAOS


def test_run(tmp_path) -> None:
    """§4 RUN(A), event sets `{| |}`, `{ }`, `union`, `inter`. PL = L |\\ {|L::e|} has traces
    e.out.1* (tock hidden, L never terminates). RUN over any set holding L::e.out.1 allows them
    all; RUN over {e.out.2, e.out.3} does not: <L::e.out.1>."""
    text = """
csp Runs csp-begin
PL = L::D__(0) |\\ {| L::e |}
R1 = RUN({| L::e |})
R2 = RUN({ L::e.out.1 })
R3 = RUN(inter({| L::e |}, { L::e.out.1, L::e.out.2 }))
R4 = RUN(union({ L::e.out.2 }, { L::e.out.3 }))
csp-end
assertion AR1: PL refines R1 in the traces model.
assertion AR2: PL refines R2 in the traces model.
assertion AR3: PL refines R3 in the traces model.
assertion AR4: PL refines R4 in the traces model.
"""
    rs = run(tmp_path, LOOP, text)
    expect(rs["AR1"], "holds")
    expect(rs["AR2"], "holds")
    expect(rs["AR3"], "holds")
    expect(rs["AR4"], "violated", ["L::e.out.1"])


def test_chaos(tmp_path) -> None:
    """§4 CHAOS(A), `Events`, `diff`. L (never terminates) refines CHAOS(Events), which can do
    every event, tock included. CHAOS(diff(Events, {|L::e|})) still does tock (assumed: tock is
    in Events, as in FDR) but not L::e.out.1: <L::e.out.1>."""
    text = """
timed csp Chaos csp-begin
Timed(OneStep) {
  C1 = CHAOS(Events)
  C2 = CHAOS(diff(Events, {| L::e |}))
}
csp-end
assertion AC1: L refines C1 in the traces model.
assertion AC2: L refines C2 in the traces model.
"""
    rs = run(tmp_path, LOOP, text)
    expect(rs["AC1"], "holds")
    expect(rs["AC2"], "violated", ["L::e.out.1"])


# ---------------------------------------------------------------------------- WAIT, deadlines


def test_wait(tmp_path) -> None:
    """§4 WAIT(n): exactly n tocks, then it terminates. W: wait(2) then e (not urgent), so its
    traces are tock tock tock* W::e.out tock*. WAIT(2) ; e -> STOP allows them all: holds.
    WAIT(3) needs a third tock before e: <tock, tock, W::e.out>."""
    rct = """
stm W {
  event e
  initial i
  state s { entry wait(2) ; e }
  transition t0 { from i to s }
}
"""
    text = """
timed csp Waits csp-begin
Timed(OneStep) {
  SW2 = WAIT(2) ; (W::e.out -> STOP)
  SW3 = WAIT(3) ; (W::e.out -> STOP)
}
csp-end
assertion W2: W refines SW2 in the traces model.
assertion W3: W refines SW3 in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["W2"], "holds")
    expect(rs["W3"], "violated", ["tock", "tock", "W::e.out"])


def test_edeadline(tmp_path) -> None:
    """§4 EDeadline(e, d): e within d tocks, then termination. E: after a, exactly one tock
    (wait(1)) then b with deadline 0: tock* E::a.in tock E::b.out tock*. With d = 1 the spec
    allows it (then a timed STOP): holds. With d = 0 tock is refused after a:
    <E::a.in, tock>."""
    rct = """
stm E {
  event a
  event b
  initial i
  state s {}
  state u { entry wait(1) ; b <{0} }
  transition t0 { from i to s }
  transition t1 { from s to u trigger a }
}
"""
    text = """
timed csp EDs csp-begin
Timed(OneStep) {
  ED1 = E::a.in -> (EDeadline(E::b.out, 1) ; STOP)
  ED0 = E::a.in -> (EDeadline(E::b.out, 0) ; STOP)
}
csp-end
assertion AED1: E refines ED1 in the traces model.
assertion AED0: E refines ED0 in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["AED1"], "holds")
    expect(rs["AED0"], "violated", ["E::a.in", "tock"])


def test_adeadline_after_exception(tmp_path) -> None:
    """§4 ADeadline(A, d), CHAOS, `[| A |>`, `let`, `timed_priority` (IntelliWelder A1 pattern).

    R: after req, other (deadline 0), exactly one tock (wait(1)), then the urgent call go(), and
    back to idle: tock* req other tock goCall tock* req … SpecD1: CHAOS until req, then
    ADeadline({|R::goCall|}, 1): any event (here other) and at most one tock before goCall, then
    terminate and start again: holds. Assumed, from the brief: ADeadline lets events outside A
    happen. SpecD0 (d = 0) refuses tock after req: <R::req.in, R::other.out, tock> (other is
    urgent, so it precedes the tock).
    """
    rct = """
interface I { go() }
stm R {
  requires I
  event req
  event other
  initial i
  state idle {}
  state busy { entry other <{0} ; wait(1) ; go() }
  transition t0 { from i to idle }
  transition t1 { from idle to busy trigger req }
  transition t2 { from busy to idle }
}
"""
    text = """
timed csp SpecD1 csp-begin
Timed (OneStep) {
  SpecD1 = let
      Def = (CHAOS(Events) [| {| R::req |} |> ADeadline({| R::goCall |}, 1)) ; Def
    within timed_priority(Def)
}
csp-end
timed csp SpecD0 csp-begin
Timed(OneStep) {
  SpecD0 = let
      Def = (CHAOS(Events) [| {| R::req |} |> ADeadline({| R::goCall |}, 0)) ; Def
    within timed_priority(Def)
}
csp-end
timed assertion D1: R refines SpecD1 in the traces model.
timed assertion D0: R refines SpecD0 in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["D1"], "holds")
    expect(rs["D0"], "violated", ["R::req.in", "R::other.out", "tock"])


def test_timed_priority(tmp_path) -> None:
    """§4 timed_priority: tock only when no internal step is possible.

    TPn = timed_priority(((a -> EDeadline(b, 0)) \\ {|a|}) ; STOP): the hidden a is internal, so
    it happens before any tock, and then b must come before any tock: traces <>, <b, tock…>.
    Bn's b is not urgent, so Bn can tock first: <tock>. Bu's b has deadline 0 (at time 0):
    holds. NPn is TPn without timed_priority: tockbmc always applies maximal progress (§4), so
    its verdict is the same as TPn's (FDR, without timed_priority, could delay the hidden a).
    """
    rct = """
stm Bn {
  event a
  event b
  initial i
  state s { entry b }
  transition t0 { from i to s }
}
stm Bu {
  event a
  event b
  initial i
  state s { entry b <{0} }
  transition t0 { from i to s }
}
"""
    text = """
timed csp TPs csp-begin
Timed(OneStep) {
  TPn = timed_priority(((Bn::a.in -> EDeadline(Bn::b.out, 0)) \\ {| Bn::a |}) ; STOP)
  TPu = timed_priority(((Bu::a.in -> EDeadline(Bu::b.out, 0)) \\ {| Bu::a |}) ; STOP)
  NPn = ((Bn::a.in -> EDeadline(Bn::b.out, 0)) \\ {| Bn::a |}) ; STOP
}
csp-end
assertion N: Bn refines TPn in the traces model.
assertion U: Bu refines TPu in the traces model.
assertion NP: Bn refines NPn in the traces model.
"""
    rs = run(tmp_path, rct, text)
    expect(rs["N"], "violated", ["tock"])
    expect(rs["U"], "holds")
    expect(rs["NP"], "violated", ["tock"])


# ---------------------------------------------------------------------------- model processes


K_MACHINE = """
stm K {
  const p : int
  const q : int
  event e : int
  event f : int
  initial i
  state s { entry e!p ; f!q }
  transition t0 { from i to s }
}
"""


def test_model_process_arguments_set_constants(tmp_path) -> None:
    """§4 `M::D__(id, c1, …)` / `M::O__(id, …)`: arguments after id set K's constants in
    declaration order (p, then q). K outputs e!p then f!q (not urgent). KS = e.1 -> f.0 -> STOP.
    D__(0, 1, 0): p = 1, q = 0: holds. D__(0, 0, 1): p = 0: <K::e.out.0>. O__(0, 1, 1): q = 1:
    <K::e.out.1, K::f.out.1>. K itself takes RoboTool's default p = q = 0: <K::e.out.0>; with p a
    parameter (core_int = -1..1), the counterexample is one event K::e.out.v with v in {-1, 0}.
    With p and q set by `with constant`: holds.
    """
    rct = K_MACHINE
    text = """
timed csp Ks csp-begin
Timed(OneStep) {
  K10 = K::D__(0, 1, 0)
  K01 = K::D__(0, 0, 1)
  K11 = K::O__(0, 1, 1)
  KS = K::e.out.1 -> K::f.out.0 -> STOP
}
csp-end
assertion AK10: K10 refines KS in the traces model.
assertion AK01: K01 refines KS in the traces model.
assertion AK11: K11 refines KS in the traces model.
assertion KAll: K refines KS in the traces model.
assertion KSet: K refines KS in the traces model with constant p of K set to 1 and constant q of K set to 0.
"""
    rs = run(tmp_path, rct, text, ranges=MINUS1_1)
    expect(rs["AK10"], "holds")
    expect(rs["AK01"], "violated", ["K::e.out.0"])
    expect(rs["AK11"], "violated", ["K::e.out.1", "K::f.out.1"])
    expect(rs["KAll"], "violated", ["K::e.out.0"])
    expect(rs["KSet"], "holds")
    ps = run(tmp_path, rct, text, ranges=MINUS1_1, names=["KAll", "AK10"], params=("p", "q"))
    expect(ps["KAll"], "violated")
    assert events(ps["KAll"]) in (["K::e.out.-1"], ["K::e.out.0"]), events(ps["KAll"])
    expect(ps["AK10"], "holds")  # D__ arguments set a parameter too


def test_model_process_arguments_in_robotools_constant_names(tmp_path) -> None:
    """RoboTool's assertion files pass a constant's instantiated value by its generated name,
    `K::D__(0, const_K_p, const_K_q)` (ChemicalDetector-autonomous8's `GasAnalysis::O__(0,
    const_GasAnalysis_thr)`): the value the configuration gives that constant. The Instantiations
    block sets p = 1 and leaves q at RoboTool's default 0, so KI (by the names) is K: e.1 then f.0,
    which KS allows (holds); with q = 1 by `with constant`, <K::e.out.1, K::f.out.1>. Another
    constant's name in p's place is refused, naming the one understood there."""
    rct = K_MACHINE
    text = """
csp Instantiations csp-begin
const_K_p = 1
csp-end
timed csp Ks csp-begin
Timed(OneStep) {
  KI = K::D__(0, const_K_p, const_K_q)
  KX = K::D__(0, const_K_q)
  KS = K::e.out.1 -> K::f.out.0 -> STOP
}
csp-end
assertion AKI: KI refines KS in the traces model.
assertion AKIq: KI refines KS in the traces model with constant q of K set to 1.
assertion AKX: KX refines KS in the traces model.
"""
    rs = run(tmp_path, rct, text, ranges=MINUS1_1)
    expect(rs["AKI"], "holds")
    expect(rs["AKIq"], "violated", ["K::e.out.1", "K::f.out.1"])
    expect(rs["AKX"], "unsupported")
    assert "the argument for constant p of K is const_K_q; only RoboTool's name of that constant (const_K_p)" \
        in (rs["AKX"].reason or ""), rs["AKX"].reason


# ---------------------------------------------------------------------------- outside the subset


def test_renaming_is_unsupported_with_its_line(tmp_path) -> None:
    """§4: renaming is outside the subset, but for a model element compared with another
    (semantics.md §7.5). The assertion on a renamed specification is `unsupported`, with a reason
    naming the line of the renaming; another CSP assertion in the same file (M refines e.2 ->
    STOP, counterexample <M::e.out.1>) and a machine assertion still get their verdicts."""
    text = """
timed csp Good csp-begin
Timed(OneStep) {
  Good = M::e.out.2 -> STOP
}
csp-end
timed csp Ren csp-begin
Ren = (M::terminate -> SKIP) [[ M::terminate <- M::terminate ]]
csp-end
assertion C: M refines Ren in the traces model.
assertion G: M refines Good in the traces model.
assertion NT: M does not terminate.
"""
    line = text.splitlines().index("Ren = (M::terminate -> SKIP) [[ M::terminate <- M::terminate ]]") + 1
    rs = run(tmp_path, OUT, text)
    r = rs["C"]
    assert r.verdict == "unsupported", (r.verdict, r.reason)
    assert r.reason and re.search(rf"(m\.assertions:|line ){line}\b", r.reason), (line, r.reason)
    expect(rs["G"], "violated", ["M::e.out.1"])
    expect(rs["NT"], "violated", ["M::e.out.1", "M::terminate"])


COLOURS_RCT = """
package pk
enumeration Colour { Red Green Blue }
stm M {
  event c : Colour
  var x : Colour
  initial i
  state S {}
  transition t0 { from i to S }
  transition t1 { from S to S trigger c?x }
}
"""


def test_replicated_choice_over_an_enumeration_named_as_robotool_names_it(tmp_path) -> None:
    """`pk_Colour` (RoboTool's name for type Colour of package pk) and `Colour` are the set of its
    literals (`pk::Colour` is left to channels, as `Arm::Mode` for event Mode of machine Arm): M accepts any colour, so it refines a specification offering every one
    (A1) and not one offering every one but Blue (A2, whose counterexample is `M::c.in.Colour::Blue`)."""
    assertions = """
untimed csp Specs csp-begin
All = [] x : pk_Colour @ pk::M::c.in.x -> All
AllToo = [] x : Colour @ pk::M::c.in.x -> AllToo
NoBlue = [] x : diff(Colour, {Colour_Blue}) @ pk::M::c.in.x -> NoBlue
csp-end
untimed assertion A1: pk::M refines All in the traces model.
untimed assertion A3: pk::M refines AllToo in the traces model.
untimed assertion A2: pk::M refines NoBlue in the traces model.
"""
    r = run(tmp_path, COLOURS_RCT, assertions)
    assert r["A1"].verdict == "holds" and r["A3"].verdict == "holds", (r["A1"].reason, r["A3"].reason)
    assert r["A2"].verdict == "violated" and [s.event for s in r["A2"].trace if s.kind != "internal"] == [
        "M::c.in.Colour::Blue"], r["A2"]


def test_a_channel_named_like_a_package_enumeration_stays_a_channel(tmp_path) -> None:
    """With `enumeration Mode` in package Arm and `event Mode` of machine Arm,
    `Arm::Mode.in?x` is the event's channel; reading `Arm::Mode` as the type's set of literals
    would leave both assertions unsupported.  S1 accepts any mode (holds); S3 only On (violated by Off)."""
    rct = """
package Arm
enumeration Mode { On Off }
stm Arm {
  event Mode : Mode
  var p : Mode
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger Mode?p }
}
"""
    assertions = """import Arm::*
csp S csp-begin
S1 = Arm::Mode.in?x -> S1
S3 = Arm::Mode.in.Mode_On -> S3
csp-end
untimed assertion E1: Arm refines S1 .
untimed assertion E3: Arm refines S3 .
"""
    r = run(tmp_path, rct, assertions)
    assert r["E1"].verdict == "holds" and r["E3"].verdict == "violated", (r["E1"].reason, r["E3"].reason)
