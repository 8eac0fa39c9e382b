"""Specifications that read the values they receive (docs/semantics.md §8.3), RoboTool's bounded
arithmetic in them, and the variables an operation requires (§4.7): both engines.

The models are RoboTool's test13 cut down: a controller receives `In.in?y` and must output
`Out.out.(y + 1)`, computed by an operation that requires the machine's variable.
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
from tockbmc.model.ast import CspBlock, Pos
from tockbmc.model.config import configure
from tockbmc.model.csp import CspError, parse_block
from tockbmc.model.result import Result
from tockbmc.properties.spec import OTHER, Binary, Evaluator, Prefix, Thunk

NAT = Ranges({"core_nat": Range(Fraction(0), Fraction(2)), "core_int": Range(Fraction(-2), Fraction(2))})

# STM receives i, calls Inc() (which requires i: the machine's own variable), then outputs i.
BUFFER = """
interface IEvents { event In : nat  event Out : nat }
interface IShared { var i : nat }
interface Ops { Inc() }
operation Inc() {
  requires IShared
  initial I
  final F
  transition T0 { from I to F action i = i + 1 }
}
controller CT {
  event In : nat
  event Out : nat
  opref inc = Inc
  sref STM = STM
  connection CT on In to STM on In
  connection STM on Out to CT on Out
}
stm STM {
  var i : nat
  requires Ops
  uses IEvents
  initial I
  state S0 {}
  state S1 { entry Inc() ; Out!i }
  transition T0 { from I to S0 }
  transition T1 { from S0 to S1 trigger In?i }
  transition T2 { from S1 to S0 }
}
"""

SPECS = """
untimed csp Echo csp-begin
Echo = CT::In.in?y -> CT::Out.out!Plus(y, 1, core_nat) -> Echo
csp-end
untimed csp Same csp-begin
Same = CT::In.in?y -> CT::Out.out!y -> Same
csp-end
untimed csp Zero csp-begin
Zero = CT::In.in?y -> CT::Out.out!(y + 0 + 1) -> Zero
csp-end
untimed assertion E : CT refines Echo in the traces model
untimed assertion F : CT equals Echo in the failures divergences model
untimed assertion S : CT refines Same in the traces model
untimed assertion Z : CT refines Zero in the traces model
"""


def symbolic_only(tmp_path: Path, rct: str, assertions: str, name: str, ranges: Ranges) -> Result:
    """One assertion checked by BMC alone (bound 12)."""
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    [r] = check(project, [name], bound=12, config=configure(project, ranges))
    return r


def visible(r: Result) -> list[str]:
    """The events of a result's trace, internal steps left out."""
    return [step.event for step in r.trace if step.kind != "internal"]


def both(tmp_path: Path, rct: str, assertions: str, ranges: Ranges = NAT) -> tuple[dict[str, Result], dict[str, Result]]:
    write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})
    project = tockbmc.load(tmp_path)
    symbolic = {r.assertion: r for r in check(project, bound=24, config=configure(project, ranges), timeout=60)}
    concrete = {r.assertion: r for r in check_explicit(project, None, 8, ranges, {}, 60, 200_000)}
    return symbolic, concrete


def test_a_specification_reads_what_it_received(tmp_path: Path) -> None:
    """`In.in?y -> Out.out!Plus(y,1,core_nat)` is told apart value by value over core_nat = 0..2:
    CT outputs y + 1 (its operation increments the machine's own `i`), so E, F and Z hold in both
    engines (`Plus` exact, as the model's `+` is, its type argument unread; `y + 0` is no division
    by zero), and S, which wants y back, is violated after In.in.v, Out.out.(v + 1)."""
    symbolic, concrete = both(tmp_path, BUFFER, SPECS)
    for results in (symbolic, concrete):
        for name in ("E", "F", "Z"):
            assert results[name].verdict == "holds", (name, results[name].reason)
        s = results["S"]
        assert s.verdict == "violated", s.reason
        shown = visible(s)
        v = int(shown[0].rsplit(".", 1)[1])
        assert shown == [f"CT::In.in.{v}", f"CT::Out.out.{v + 1}"], shown


def test_an_unbounded_input_the_specification_reads_is_unsupported(tmp_path: Path) -> None:
    """Without a range on nat, BMC cannot list the values of `y`: unsupported, with the reason and
    the specification's line (the explicit engine needs a range for every value anyway)."""
    write_files(tmp_path, {"m.rct": BUFFER, "m.assertions": SPECS})
    project = tockbmc.load(tmp_path)
    [e] = check(project, ["E"], bound=24, config=configure(project, Ranges()), timeout=60)
    assert e.verdict == "unsupported"
    assert "does not track" in (e.reason or "") and "m.assertions:3" in (e.reason or ""), e.reason


def test_a_wait_over_a_value_from_an_unbounded_channel_is_unsupported(tmp_path: Path) -> None:
    """`M::time.in?t -> WAIT(t)` with `time` an unbounded nat: each value is another process, which
    a specification's listing cannot follow; `unsupported` with the reason (it was an internal error:
    a comparison of the value standing for the rest with a number). With a range, it is decided."""
    rct = """
stm M {
  event time : nat
  var x : nat
  initial i
  state s {}
  state w {}
  transition t0 { from i to s }
  transition t1 { from s to w trigger time?x }
}
"""
    text = "timed csp Spec csp-begin\nSpec = M::time.in?t -> WAIT(t) ; STOP\ncsp-end\ntimed assertion A: Spec equals M.\n"
    write_files(tmp_path, {"m.rct": rct, "m.assertions": text})
    project = tockbmc.load(tmp_path)
    [a] = check(project, ["A"], bound=12, config=configure(project, Ranges()), timeout=60)
    assert a.verdict == "unsupported" and "WAIT over a value" in (a.reason or ""), a.reason
    [ranged] = check(project, ["A"], bound=12, config=configure(project, NAT), timeout=60)
    assert ranged.verdict != "unsupported", ranged.reason


def test_robotool_read_channels_are_unsupported(tmp_path: Path) -> None:
    """RoboTool's reads of a variable (`M::get_x`) are hidden and are no events here, so a
    specification naming one is unsupported; its writes (`set_x`) are events (docs/semantics.md §5.5)."""
    rct = BUFFER + "module M { rref rp = RP  cref c = CT  connection rp on In to c on In ( _async ) }\n" \
                   "robotic platform RP { uses IEvents  var x : nat }\n"
    spec = """
untimed csp W csp-begin
W = M::In.in?y -> M::get_x!y -> W
csp-end
untimed assertion W : M refines W in the traces model
"""
    symbolic, concrete = both(tmp_path, rct, spec)
    for results in (symbolic, concrete):
        assert results["W"].verdict == "unsupported"
        assert "RoboTool's channel for reading variable x" in (results["W"].reason or "")


def test_a_variable_an_operation_requires_from_its_calling_operation_is_that_operation_s(tmp_path: Path) -> None:
    """RoboChart: the caller provides what an operation requires.  A machine's own variable does
    (the first test); so does a variable the calling operation declares (ops4's opA/opB):
    here Inc increments Outer's own i, so the machine's i, output after Outer(), is what came in
    (S holds, E, which wants it plus one, is violated), in both engines."""
    rct = BUFFER.replace("state S1 { entry Inc() ; Out!i }", "state S1 { entry Outer() ; Out!i }").replace(
        "interface Ops { Inc() }", "interface Ops { Outer() }\ninterface IInc { Inc() }") + """
operation Outer() {
  requires IInc
  var i : nat = 2
  initial I
  final F
  transition T0 { from I to F action Inc() }
}
"""
    rct = rct.replace("opref inc = Inc", "opref inc = Inc\n  opref outer = Outer")
    spec = SPECS.split("untimed assertion")[0] + "untimed assertion S : CT refines Same in the traces model\n" \
        "untimed assertion E : CT refines Echo in the traces model\n"
    symbolic, concrete = both(tmp_path, rct, spec)
    for results in (symbolic, concrete):
        assert {k: r.verdict for k, r in results.items()} == {"S": "holds", "E": "violated"}


def test_distributed_union_and_replicated_choice_over_a_difference(tmp_path: Path) -> None:
    """RoboArch's property files write `Union({A, B, C})` and `|~| ev : diff(All, {|c|}) @ ev -> P`
    (roboarch-examples ObstacleAvoidance): a replicated operator ranges over the channels of a
    union or of a difference that removes whole channels.  CT answers every In with an Out, so
    `Answer` (after In, only Out) holds, and `NoOut` (never Out) is violated after In, Out."""
    spec = """
csp Sets csp-begin
  All = Union({ {| CT::In.in |}, {| CT::Out.out |} })
  Answer = |~| ev : diff(All, {| CT::Out.out |}) @ ev -> CT::Out.out?v -> Answer
  NoOut = |~| ev : diff(All, {| CT::Out.out |}) @ ev -> NoOut
csp-end
untimed assertion A : CT refines Answer in the traces model
untimed assertion N : CT refines NoOut in the traces model
"""
    symbolic, concrete = both(tmp_path, BUFFER, spec)
    for results in (symbolic, concrete):
        assert results["A"].verdict == "holds", results["A"].reason
        n = results["N"]
        assert n.verdict == "violated", n.reason
        shown = visible(n)
        assert shown[0].startswith("CT::In.in.") and shown[1].startswith("CT::Out.out."), shown


def test_an_empty_sequence_takes_the_type_it_is_compared_with(tmp_path: Path) -> None:
    """`s == < >` with `s : Seq(Skills)`: the literal was left a sequence of unknown type, and every
    assertion on the machine was unsupported ("values of type ? are not encoded yet")."""
    rct = """
import sequence_toolkit::*
enumeration Skills { MOVE EXPLORE }
stm M {
  var s : Seq(Skills) = < Skills::MOVE >
  event e
  initial i
  state A {}
  state B {}
  transition t0 { from i to A }
  transition t1 { from A to B trigger e condition s == < > }
}
"""
    symbolic, concrete = both(tmp_path, rct, "assertion R : B is reachable in M\n")
    for results in (symbolic, concrete):
        assert results["R"].verdict == "violated", results["R"].reason  # s is never empty


def test_an_unprefixed_assertion_says_it_was_checked_timed(tmp_path: Path) -> None:
    """RoboArch's property files write `assertion P: M refines S` with S in an untimed `csp` block,
    whose prefixes refuse tock: checked in the timed semantics (docs/semantics.md §7.8), the first
    tock violates it, and the result says which default decided that; `timed assertion` does not."""
    spec = """
csp S csp-begin
  S = CT::In.in?y -> CT::Out.out!Plus(y, 1, core_nat) -> S
csp-end
assertion U : CT refines S in the traces model
timed assertion T : CT refines S in the traces model
untimed assertion N : CT refines S in the traces model
"""
    symbolic, concrete = both(tmp_path, BUFFER, spec)
    for results in (symbolic, concrete):
        for name in ("U", "T"):
            r = results[name]
            assert r.verdict == "violated" and visible(r) == ["tock"], r.reason
        assert "says neither `timed` nor `untimed`" in (results["U"].reason or "")
        assert "says neither" not in (results["T"].reason or "")
        assert results["N"].verdict == "holds", results["N"].reason


# The values the interpreter lists must be those BMC's runs can take, or a
# specification that names (or reads) every listed value treats an unlisted one wrongly.
ECHO_REAL = """
interface IE { event inp : real  event f  event g }
stm M { uses IE  var v : real  initial I  state S0 {} state S1 {} state S2 {}
  transition T0 { from I to S0 }  transition T1 { from S0 to S1 trigger inp?v }
  transition T2 { from S1 to S2 action f } }
"""


def test_a_real_input_is_not_listed_for_bmc(tmp_path: Path) -> None:
    """BMC takes every real of `core_real=0..1` (0.5 too); the interpreter lists 0 and 1.  A
    specification reading the value is unsupported in BMC (it said `holds`, missing inp.in.0.5,
    f.out)."""
    a = symbolic_only(tmp_path, ECHO_REAL, """
untimed csp Sp csp-begin
Sp = M::inp.in?x -> ((x == 0 or x == 1) & M::f.out -> STOP [] (x != 0 and x != 1) & M::g.out -> STOP)
csp-end
untimed assertion A : M refines Sp in the traces model
""", "A",
                      Ranges({"core_real": Range(Fraction(0), Fraction(1))}))
    assert a.verdict == "unsupported" and "does not track" in (a.reason or ""), (a.verdict, a.reason)


def test_a_natural_bounded_only_by_core_int_is_not_listed_for_bmc(tmp_path: Path) -> None:
    """With `core_int=-1..1` alone BMC leaves `nat` unbounded (the interpreter lists 0..1): a
    specification naming inp.in.0 and inp.in.1 is violated by inp.in.2 (it said `holds`)."""
    b = symbolic_only(tmp_path, ECHO_REAL.replace("real", "nat"), """
untimed csp Sq csp-begin
Sq = M::inp.in.0 -> M::f.out -> STOP [] M::inp.in.1 -> M::f.out -> STOP
csp-end
untimed assertion B : M refines Sq in the traces model
""", "B",
                      Ranges({"core_int": Range(Fraction(-1), Fraction(1))}))
    assert b.verdict == "violated", b.reason
    assert visible(b)[0] not in ("M::inp.in.0", "M::inp.in.1")


def test_an_event_named_like_a_memory_channel_is_the_models(tmp_path: Path) -> None:
    """`set_speed` is refused as RoboTool's write of variable `speed` only when it is not an event of
    the model."""
    a = symbolic_only(tmp_path, """
interface IE { event set_speed : int }
stm M { uses IE  var speed : int  initial I  state S0 {}
  transition T0 { from I to S0 }  transition T1 { from S0 to S0 trigger set_speed?speed } }
""", """
untimed csp Sp csp-begin
Sp = M::set_speed.in?x -> Sp
csp-end
untimed assertion A : M refines Sp in the traces model
""", "A",
                      Ranges({"core_int": Range(Fraction(-1), Fraction(1))}))
    assert a.verdict == "holds", a.reason


def test_startby_bounds_the_time_before_the_first_event(tmp_path: Path) -> None:
    """tick-tock-CSP's `StartBy(P, d) = P [] (WAIT(d) ; USTOP)` (const1's Spec): M outputs e after
    exactly two tocks (its deadline 0 makes it urgent), so `StartBy(e -> …, 2)` holds and `StartBy(e -> …, 1)` is violated by its
    second tock; `wait(2) ; e -> …` (RoboTool's lowercase wait) holds too."""
    rct = """
interface IE { event e }
stm M { uses IE  initial I  state S0 { entry wait(2) ; e <{0} }  final F
  transition T0 { from I to S0 }  transition T1 { from S0 to F } }
"""
    spec = """
timed csp Specs csp-begin
Timed(OneStep) {
  Two = StartBy(M::e.out -> M::terminate -> SKIP, 2)
  One = StartBy(M::e.out -> M::terminate -> SKIP, 1)
  Low = wait(2) ; M::e.out -> M::terminate -> SKIP
}
csp-end
timed assertion T : M refines Two in the traces model
timed assertion O : M refines One in the traces model
timed assertion L : M refines Low in the traces model
"""
    symbolic, concrete = both(tmp_path, rct, spec)
    for results in (symbolic, concrete):
        assert results["T"].verdict == "holds", results["T"].reason
        assert results["L"].verdict == "holds", results["L"].reason
        o = results["O"]
        assert o.verdict == "violated", o.reason
        assert visible(o) == ["tock", "tock"], o.trace


def test_replicated_operators_over_sets_they_cannot_read_off_exactly(tmp_path: Path) -> None:
    """`diff({|M::a|}, diff(Events, {|M::b|}))` is empty, but the channel was kept
    (a wrong `holds`): a difference whose removed set's extent is not read off is unsupported.
    `union({|M::a.in|}, {M::a.in})` is one event, but `|||` ran two copies (a wrong `holds`): a
    member a closure covers is dropped.  An `if` on an enumeration literal no longer crashes."""
    rct = """
enumeration E { X Y }
stm M { event a event b event c : E
  initial i state s {} state u {} state v {}
  transition t0 { from i to s } transition t1 { from s to u trigger a } transition t2 { from u to v trigger a } }
"""
    spec = """
timed csp S csp-begin
Timed(OneStep) {
  Sp1 = [] e : diff({|M::a|}, diff(Events, {|M::b|})) @ e -> e -> STOP
  Sp2 = ||| e : union({|M::a.in|}, {M::a.in}) @ e -> STOP
  Sp3 = M::c.in?x -> (if x == E::X then STOP else STOP) [] M::a.in -> M::a.in -> STOP
}
csp-end
timed assertion A1 : M refines Sp1 in the traces model
timed assertion A2 : M refines Sp2 in the traces model
timed assertion A3 : M refines Sp3 in the traces model
"""
    symbolic, concrete = both(tmp_path, rct, spec)
    for results in (symbolic, concrete):
        assert results["A1"].verdict == "unsupported", results["A1"].reason
        a2 = results["A2"]
        assert a2.verdict == "violated" and visible(a2) == ["M::a.in", "M::a.in"], a2.reason
        assert results["A3"].verdict == "holds", results["A3"].reason


ECHO = """
stm M {
  event a : int
  event e : int
  var x : int
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger a?x action e!x }
}
"""


def test_an_input_restricted_to_a_set(tmp_path: Path) -> None:
    """`c?x:S -> P` is `[] v:S @ c.v -> P` (AlphaAlgorithm's `broadcast.in?x:diff(ID, {id})`). M echoes
    what it receives, any of core_int = -2..2. Any holds; Low, which takes only 0 and 1 on a, is
    violated by one event a.in.v, v in {-2, -1, 2}, in the traces model and in the failures model; Back, whose output is restricted to what M sent, holds: after a.in.y every
    e.out.z with z in {y} is offered (a one-element set of a read value)."""
    specs = """
untimed csp Specs csp-begin
Any = M::a.in?y:{-2..2} -> M::e.out?z:{-2..2} -> Any
Low = M::a.in?y:{0, 1} -> M::e.out!y -> Low
Back = M::a.in?y -> M::e.out?z:{y} -> Back
csp-end
untimed assertion A : M refines Any in the traces model
untimed assertion L : M refines Low in the traces model
untimed assertion LF : M refines Low in the failures model
untimed assertion B : M refines Back in the failures divergences model
"""
    symbolic, concrete = both(tmp_path, ECHO, specs)
    for results in (symbolic, concrete):
        for name in ("A", "B"):
            assert results[name].verdict == "holds", (name, results[name].reason)
        for name in ("L", "LF"):
            assert results[name].verdict == "violated", (name, results[name].reason)
            assert visible(results[name]) in (["M::a.in.-2"], ["M::a.in.-1"], ["M::a.in.2"]), visible(results[name])



def _prefixes(text: str, name: str, *args: object) -> list[tuple]:
    """The events the prefixes of definition `name` (applied to `args`) offer, in order."""
    block = CspBlock("S", "untimed", (), text, Pos("s.assertions", 1, 1), ())
    defs = {d.name: d for d in parse_block(block)}
    ev = Evaluator(defs.get, block)
    out, todo = [], [ev.definition(defs[name], args)]
    while todo:
        p = todo.pop(0)
        if isinstance(p, Thunk):
            p = ev.eval(p.tree, p.env)
        if isinstance(p, Binary):
            todo += [p.left, p.right]
        elif isinstance(p, Prefix):
            out.append(p.pattern)
        else:
            out.append(p)
    return out


def test_a_restricted_input_reads_the_inputs_before_it() -> None:
    """In `c?x:S?y:{x}` and `c?x:S!x` the later fields read the x just bound, not an outer one (`P(7)`
    offers c.0.0 and c.1.1, not c.0.7 and c.1.7); `?x:{}` offers nothing (STOP); a set holding a value the
    specification does not track (an input that is not listed) is refused, as `c!y` is."""
    text = "P(x) = M::c?x:{0, 1}!x -> STOP\nQ = M::c?x:{0, 1}?y:{x} -> STOP\nE = M::c?x:{} -> STOP\n"
    assert _prefixes(text, "P", 7) == [("M::c", 0, 0), ("M::c", 1, 1)]
    assert _prefixes(text, "Q") == [("M::c", 0, 0), ("M::c", 1, 1)]
    assert [type(p).__name__ for p in _prefixes(text, "E")] == ["Stop"]
    with pytest.raises(CspError, match="does not track"):
        _prefixes("R(y) = M::c?x:{y} -> STOP\n", "R", OTHER)


def test_a_specification_names_the_values_of_a_tuple_typed_event(tmp_path: Path) -> None:
    """AlphaAlgorithm b1's `receive.out!(x, id)` on `receive : ID * ID`. M receives y on a and sends
    the pair (y, y) on b (core_int = -2..2). Same, which wants (y, y) back, holds in both engines;
    Zero, which wants (y, 0), is violated after a.in.v, b.out.(v, v) for some v other than 0."""
    rct = """
stm M {
  event a : int
  event b : int * int
  var x : int
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger a?x action b!(| x, x |) }
}
"""
    specs = """
untimed csp Specs csp-begin
Same = M::a.in?y -> M::b.out!(y, y) -> Same
Zero = M::a.in?y -> M::b.out!(y, 0) -> Zero
csp-end
untimed assertion S : M refines Same in the traces model
untimed assertion Z : M refines Zero in the traces model
"""
    symbolic, concrete = both(tmp_path, rct, specs)
    for results in (symbolic, concrete):
        assert results["S"].verdict == "holds", results["S"].reason
        assert results["Z"].verdict == "violated", results["Z"].reason
        shown = visible(results["Z"])
        v = shown[0].rsplit(".", 1)[1]
        assert v != "0" and shown == [f"M::a.in.{v}", f"M::b.out.({v}, {v})"], shown


RECORD_MODEL = """\
package P
datatype DT { q : nat p : nat }
interface I { event input : DT event output : nat }
stm M {
  uses I
  var i : DT = DT (| q = 0, p = 0 |)
  var t : nat = 0
  initial i0
  state s0 { }
  transition t0 { from i0 to s0 }
  transition t1 { from s0 to s0 trigger input?i action t = i.p + i.q ; output!t }
}
"""
RECORD_SPECS = """\
untimed csp Sum csp-begin
  Sum = P::M::input.in?x -> P::M::output.out!Plus(P_DT_p(x), P_DT_q(x), core_nat) -> Sum
csp-end
untimed csp Wrong csp-begin
  Wrong = P::M::input.in?x -> P::M::output.out!Plus(P_DT_p((P_DT_p(x), 1)), P_DT_q(x), core_nat) -> Wrong
csp-end
untimed assertion S: P::M refines Sum in the traces model.
untimed assertion W: P::M refines Wrong in the traces model.
"""


def test_a_specification_reads_a_received_record_s_fields_as_robotool_writes_them(tmp_path: Path) -> None:
    """RoboTool's `pkg_R_f(x)` reads field f of record x (test15's `test15_DT_p(x)`), and of a tuple the
    part in f's place, RoboTool writing a record as the tuple of its fields: `P_DT_p((a, 1))` is 1.
    Sum outputs p + q, as the machine does; Wrong outputs 1 + q.  Both engines."""
    bmc, explicit = both(tmp_path, RECORD_MODEL, RECORD_SPECS)
    assert {k: r.verdict for k, r in bmc.items()} == {k: r.verdict for k, r in explicit.items()} == {
        "S": "holds", "W": "violated"}
    for r in (bmc["W"], explicit["W"]):
        assert [s.event for s in r.trace if s.kind == "event"] == ["M::input.in.(q=0, p=0)", "M::output.out.0"]
