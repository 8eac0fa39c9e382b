"""Sequences, sets, tuples and `let`: loaded, checked by BMC in Z3's theories, run by
the interpreter, and each counterexample replayed; both engines give the same verdicts."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import both_engines, write_files

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

MODEL = """\
import sequence_toolkit::*
import set_toolkit::*
stm M {
  var s : Seq(nat) = <1, 2>
  var r : Seq(real) = <1>
  var p : nat * boolean = (| 1, true |)
  var a : Set(nat) = {0}
  var n : nat = 0
  event e : nat
  event out : Seq(nat)
  event pair : nat * nat
  initial i
  state S0 { }
  state S1 { }
  state S2 { }
  transition t0 { from i to S0 action s = s ^ <3> ; n = size(s) ; a = union(a, {n}) }
  transition t1 { from S0 to S1 trigger e?n condition n in a /\\ p[2]
                  action out!tail(s) ; n = let k == head(s) @ k + s[2] }
  transition t2 { from S1 to S2 condition reverse(s) == <3, 2, 1> /\\ last(r) == 1.0 /\\ not (2 in a)
                  action pair!(| n, size(filter(s, {1, 3})) |) }
  transition t3 { from S2 to S0 condition diff(a, {0}) == {3} /\\ subset({3}, a) }
}
"""
ASSERTIONS = """\
assertion free: M is deadlock-free.
assertion A2: M does not terminate.
assertion R2: S2 is not reachable in M.
csp Spec csp-begin
Spec = M::e.in.3 -> M::out.out.<2, 3> -> M::pair.out.(3, 2) -> Spec
csp-end
"""
RANGES = Ranges({"core_nat": Range(Fraction(0), Fraction(3))})


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> Project:
    d = tmp_path_factory.mktemp("data")
    (d / "m.rct").write_text(MODEL)
    (d / "m.assertions").write_text(ASSERTIONS)
    return load(d)


def test_bmc_decides_with_replayed_counterexamples(project: Project) -> None:
    results = {r.assertion: r for r in check(project, bound=20, ranges=RANGES)}
    assert results["A2"].verdict == Verdict.HOLDS
    reach = results["R2"]
    assert reach.verdict == Verdict.VIOLATED
    events = [s.event for s in reach.trace if s.event and s.event != "tock"]
    assert events[:3] == ["M::e.in.0", "M::out.out.<2, 3>", "M::pair.out.(3, 2)"][:len(events)]
    assert reach.extra["replayed"] == "yes"
    changed = {k: v for s in reach.trace for k, v in s.changed.items()}
    assert changed["M.s"] == "<1, 2, 3>" and changed["M.a"] == "{0, 3}"


def test_explicit_engine_agrees(project: Project) -> None:
    bmc = {r.assertion: r.verdict for r in check(project, ["free", "A2", "R2"], bound=20, ranges=RANGES)}
    explicit = {r.assertion: r.verdict for r in check_explicit(project, ["free", "A2", "R2"], 20, RANGES, {}, None)}
    assert explicit == bmc


def _load(tmp_path: Path, body: str) -> Project:
    (tmp_path / "m.rct").write_text("import sequence_toolkit::*\nstm M {\n" + body +
                                    "\n  initial i\n  state s {}\n  transition t0 { from i to s }\n}\n")
    return load(tmp_path)


def test_literals_take_their_place_s_type(tmp_path: Path) -> None:
    project = _load(tmp_path, "  var r : Seq(real) = <1, 2>\n  var e : Seq(nat) = <>")
    [m] = project.machines
    assert [str(v.initial.type) for v in m.variables if v.initial] == ["Seq(real)", "Seq(nat)"]  # type: ignore[union-attr]


@pytest.mark.parametrize(("body", "message"), [
    ("  var s : Seq(nat) = <true>", "type error: the initial value of 's' must be Seq(nat), but this is Seq(boolean)"),
    ("  var s : nat = head(1)", "type error: 'head' cannot take nat"),
    ("  var s : nat * nat = (| 1, 2 |)\n  var t : nat = s[3]", "a tuple's part is chosen by a literal from 1 to 2"),
])
def test_type_errors(tmp_path: Path, body: str, message: str) -> None:
    with pytest.raises(ModelError) as info:
        _load(tmp_path, body)
    assert any(d.message.startswith(message) for d in info.value.diagnostics), info.value


def test_size_of_a_set_is_unsupported_in_bmc_with_its_position(tmp_path: Path) -> None:
    (tmp_path / "m.rct").write_text("import set_toolkit::*\nstm M {\n  var a : Set(nat) = {1}\n  var n : nat = 0\n"
                                    "  initial i\n  state s {}\n  transition t0 { from i to s action n = size(a) }\n}\n")
    (tmp_path / "m.assertions").write_text("assertion A: M does not terminate.\n")
    [r] = check(load(tmp_path), bound=5)
    assert r.verdict == Verdict.UNSUPPORTED
    assert "the size of a set" in (r.reason or "") and r.reason and "m.rct:7:" in r.reason


def test_size_of_a_set_of_an_enumeration_or_of_booleans_in_both_engines(tmp_path: Path) -> None:
    """An enumeration's set is counted literal by literal.  `c?k` adds a colour: after Red and
    Red again the set has one member, after Red then Blue two; three needs three inputs (Full).
    Two booleans make a set of size 2 (Both), never 3 (Three)."""
    (tmp_path / "m.rct").write_text("""import set_toolkit::*
enumeration Colour { Red Green Blue }
stm M {
  var a : Set(Colour) = {}
  var b : Set(boolean) = {}
  var k : Colour
  event c : Colour
  initial i
  state S {}
  state Full {}
  state Both {}
  state Three {}
  transition t0 { from i to S }
  transition t1 { from S to S trigger c?k action a = union(a, {k}) ; b = union(b, {size(a) > 1}) }
  transition t2 { from S to Full condition size(a) == 3 }
  transition t3 { from S to Both condition size(b) == 2 }
  transition t4 { from S to Three condition size(b) == 3 }
}
""")
    (tmp_path / "m.assertions").write_text("assertion F: Full is reachable in M.\nassertion B: Both is reachable in M.\n"
                                           "assertion T: Three is reachable in M.\n")
    project = load(tmp_path)
    bmc = {r.assertion: r for r in check(project, bound=16)}
    explicit = {r.assertion: r for r in check_explicit(project, None, 16, Ranges({}), {}, 60)}
    for rs in (bmc, explicit):
        assert {n: r.verdict for n, r in rs.items()} == {"F": Verdict.HOLDS, "B": Verdict.HOLDS,
                                                         "T": Verdict.VIOLATED}, rs
    visible = [s.event for s in bmc["F"].trace if s.kind != "internal"]
    assert len(visible) == 3 and len(set(visible)) == 3, visible  # three different colours, fewest inputs


def test_input_sequences_need_a_length_range_for_the_explicit_engine(tmp_path: Path) -> None:
    (tmp_path / "m.rct").write_text("stm M {\n  var s : Seq(nat)\n  event e : Seq(nat)\n  initial i\n  state a {}\n"
                                    "  state b {}\n  transition t0 { from i to a }\n"
                                    "  transition t1 { from a to b trigger e?s condition s == <1, 1> }\n}\n")
    (tmp_path / "m.assertions").write_text("assertion R: b is not reachable in M.\n")
    project = load(tmp_path)
    [r] = check(project, bound=6, ranges=Ranges({"core_nat": Range(Fraction(0), Fraction(1))}))
    assert r.verdict == Verdict.VIOLATED and r.extra["replayed"] == "yes"
    assert [s.event for s in r.trace if s.event] == ["M::e.in.<1, 1>"]


SHORT_INPUT = """\
stm M {
  event a : int
  event d : Seq(int)
  var x : int = 0
  var s : Seq(int) = <>
  initial i
  state S0 { }
  final F
  transition t0 { from i to S0 }
  transition t1 { from S0 to S0 trigger d?s }
  transition t2 { from S0 to F trigger a?x }
}
"""


def test_a_refusal_of_an_input_sequence_of_bounded_length_is_decided(tmp_path: Path) -> None:
    """`d?s` with `M::d`'s length in 0..2: a refusal says "no value of d is accepted", a universal
    over the sequence, whose items' range was a second quantifier inside it; Z3 gave no answer at
    depth 1 in 10 s.  The items of a sequence shorter than 16 are now constrained one by one.  By
    hand: M takes `a` and terminates, which untimed deadlock freedom counts as a deadlock (3 steps:
    the initial transition is internal, then `a.in`, then `terminate`); in the timed model
    termination is no deadlock, and S0 offers `a` and `d` for ever."""
    write_files(tmp_path, {"m.rct": SHORT_INPUT, "m.assertions": "untimed assertion U1: M is deadlock-free.\n"
                                                                 "assertion A2: M is deadlock-free.\n"})
    ranges = Ranges({"core_int": Range(Fraction(-1), Fraction(1))}, {"M::d": Range(Fraction(0), Fraction(2))})
    symbolic, concrete = both_engines(load(tmp_path), ranges, bound=12, timeout=20)
    for results in (symbolic, concrete):
        assert [(r.assertion, r.verdict) for r in results] == [("U1", Verdict.VIOLATED), ("A2", Verdict.HOLDS)]
    shown = [s.event for s in symbolic[0].trace if s.kind != "internal"]
    assert len(shown) == 2 and shown[0].startswith("M::a.in.") and shown[1] == "M::terminate"


GIVEN_SETS = """\
import set_toolkit::*
type ID
function pick(k : nat) : ID { }
stm M {
  event e : ID
  event n : nat
  var s : Set(ID) = {}
  var y : ID
  initial i
  state S { }
  transition t0 { from i to S }
  transition t1 { from S to S trigger e?y action s = union(s, {y}) ; n!size(s) }
}
stm P {
  event f : nat
  event n : nat
  var s : Set(ID) = {}
  var k : nat = 0
  initial i
  state S { }
  transition t0 { from i to S }
  transition t1 { from S to S trigger f?k action s = {pick(k)} ; n!size(s) }
}
"""
GIVEN_SPECS = """\
timed csp Specs csp-begin
Timed(OneStep) {
  NoThree = CHAOS(diff(Events, {M::n.out.3}))
  NoTwo = CHAOS(diff(Events, {M::n.out.2}))
  NeverEmpty = CHAOS(diff(Events, {P::n.out.0}))
}
csp-end
timed assertion A3: M refines NoThree in the traces model.
timed assertion A2: M refines NoTwo in the traces model.
timed assertion P0: P refines NeverEmpty in the traces model.
"""


def test_the_size_of_a_set_of_a_given_type_counts_its_range(tmp_path: Path) -> None:
    """A given type's range is the type (RoboTool's `nametype ID = {0..1}`), so a set of ID has at
    most two members: by hand, M outputs sizes 1 and 2 and never 3.  A path's range narrows the type's
    (`M::e=1..3` leaves only 1: size 2 is never reached), in both engines.  A function's result is a
    value of its type within that range, so `{pick(k)}` is never empty (BMC; the interpreter cannot
    run `pick`).  Without a range for ID the size is unsupported, with the range to give."""
    project = load(write_files(tmp_path, {"m.rct": GIVEN_SETS, "m.assertions": GIVEN_SPECS}))
    scope = {"ID": Range(Fraction(0), Fraction(1)), "core_nat": Range(Fraction(0), Fraction(4))}
    narrowed = {"M::e": Range(Fraction(1), Fraction(3))}
    for paths, expected in (({}, ["holds", "violated"]), (narrowed, ["holds", "holds"])):
        ranges = Ranges(scope, paths)
        symbolic = check(project, ["A3", "A2"], bound=12, ranges=ranges)
        concrete = check_explicit(project, ["A3", "A2"], 12, ranges, {}, 60)
        for results in (symbolic, concrete):
            assert [r.verdict.value for r in results] == expected, paths
    [p0] = check(project, ["P0"], bound=12, ranges=Ranges(scope))
    assert p0.verdict == Verdict.HOLDS
    [a2] = check(project, ["A2"], bound=12, ranges=Ranges({"core_nat": Range(Fraction(0), Fraction(4))}))
    assert a2.verdict == Verdict.UNSUPPORTED and "--range ID=LO..HI" in (a2.reason or "")



PARTIAL_RECORD = """\
datatype R { p : nat  q : nat }
stm M {
  var r : R = R(|p = 1|)
  event out : nat
  event go
  initial i
  state S0 { }
  state A1 { }
  state A3 { }
  state S1 { }
  transition t0 { from i to S0 action out!r.q }
  transition ta { from S0 to A1 condition r.q == 1 }
  transition tb { from S0 to A3 condition r.q == 3 }
  transition t1 { from S0 to S1 condition r.q == 2 /\\ r.p == 1 action go }
}
"""
PARTIAL_ASSERTIONS = """\
assertion R1: A1 is not reachable in M.
assertion R3: A3 is not reachable in M.
assertion free: M is deadlock-free.
csp Spec csp-begin
Spec = M::out.out?x:{0..2} -> RUN({| M::go |})
csp-end
untimed assertion A: M refines Spec.
"""


def test_a_record_literal_omitting_fields_leaves_them_open(tmp_path: Path) -> None:
    """`var r : R = R(|p = 1|)`: q takes every value of its range (DESIGN.md, record literals), in
    both engines alike."""
    (tmp_path / "m.rct").write_text(PARTIAL_RECORD)
    (tmp_path / "m.assertions").write_text(PARTIAL_ASSERTIONS)
    project = load(tmp_path)
    ranges = Ranges({"core_nat": Range(Fraction(0), Fraction(2))})
    bmc, explicit = both_engines(project, ranges, 10, timeout=30)
    expected = {"R1": "violated", "R3": "holds", "free": "violated", "A": "holds"}
    assert {r.assertion: r.verdict for r in bmc} == expected
    assert {r.assertion: r.verdict for r in explicit} == expected


def test_a_record_literal_omitting_fields_in_an_action_is_not_interpreted(tmp_path: Path) -> None:
    """Both engines read such a literal only as an initial value; written by an action, it is
    `unsupported` with its position (BMC had given every omitted field named q one value, at every
    step and in every literal, outside its range too)."""
    (tmp_path / "m.rct").write_text("datatype R { p : nat  q : nat }\nstm M {\n  var r : R\n  event out : nat\n"
                                    "  initial i\n  state s {}\n"
                                    "  transition t0 { from i to s action r = R(|p = 1|) ; out!r.q }\n}\n")
    (tmp_path / "m.assertions").write_text("assertion free: M is deadlock-free.\n")
    project = load(tmp_path)
    ranges = Ranges({"core_nat": Range(Fraction(0), Fraction(2))})
    bmc, explicit = both_engines(project, ranges, 10, timeout=30)
    for r in (*bmc, *explicit):
        assert r.verdict == "unsupported"
        assert "a record literal omitting fields, other than as an initial value" in (r.reason or "")
        assert "m.rct:7:" in (r.reason or "")


def test_a_given_field_keeps_its_value_whatever_its_range(tmp_path: Path) -> None:
    """Only the omitted fields are open: the given p = 5 is not drawn from core_real's range, which
    has no integer the interpreter could list (it had been, leaving no initial configuration: the
    explicit engine said `holds` where both now say `violated`)."""
    (tmp_path / "m.rct").write_text("datatype R { p : real  q : nat }\nstm M {\n  var r : R = R(|p = 5|)\n"
                                    "  event out : nat\n  initial i\n  state S0 { }\n  state Bad { }\n"
                                    "  transition t0 { from i to S0 action out!r.q }\n"
                                    "  transition t1 { from S0 to Bad condition r.p != 5 }\n}\n")
    (tmp_path / "m.assertions").write_text("assertion free: M is deadlock-free.\n"
                                           "assertion B: Bad is not reachable in M.\n")
    ranges = Ranges({"core_nat": Range(Fraction(0), Fraction(2)),
                     "core_real": Range(Fraction(1, 10), Fraction(9, 10))})
    bmc, explicit = both_engines(load(tmp_path), ranges, 8, timeout=30)
    for results in (bmc, explicit):
        assert {r.assertion: r.verdict for r in results} == {"free": "violated", "B": "holds"}


def test_a_record_literal_omitting_fields_given_to_a_constant_is_unsupported(tmp_path: Path) -> None:
    """`with constant c of N set to (R(|p = 1|))`: a value given, not an initial value; the
    interpreter took it as a record without q (BMC's subset construction then said `violated`
    where the answer is `holds`)."""
    (tmp_path / "m.rct").write_text("datatype R { p : nat  q : nat }\nstm N {\n  const c : R\n  event go\n"
                                    "  initial i\n  state S0 { }\n  state Q { }\n  transition t0 { from i to S0 }\n"
                                    "  transition tc { from S0 to Q condition c == R(|p = 1, q = 0|) action go }\n}\n")
    (tmp_path / "m.assertions").write_text("csp Spec csp-begin\nSpec = N::go.out -> STOP\ncsp-end\n"
                                           "untimed assertion W: Spec refines N with constant c of N set to "
                                           "(R(|p = 1|)).\n")
    bmc, explicit = both_engines(load(tmp_path), Ranges({"core_nat": Range(Fraction(0), Fraction(2))}), 4, timeout=30)
    for r in (*bmc, *explicit):
        assert r.verdict == "unsupported" and "omitting fields as the value given to constant" in (r.reason or "")


NEGATIVE_NAT = """
enumeration E { A B(nat) }
record R { k : nat }
stm M {
  var n : nat = 0
  var r : E = A
  var q : R = R(| k = 0 |)
  event e
  initial i
  state s {}
  state bad {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger e action ACTION }
  transition t2 { from s to bad condition CONDITION }
}
"""


@pytest.mark.parametrize(("action", "condition"), [
    ("n = n - 1", "n < 0"),
    ("r = B(n - 1)", "r != A"),
    ("q.k = q.k - 2", "q.k < 0"),
    ("q = R(| k = n - 1 |)", "q.k < 0"),
])
def test_a_negative_value_is_never_stored_in_a_nat(tmp_path: Path, action: str, condition: str) -> None:
    """`n = n - 1` from 0 in a `nat`: the explicit engine blocks the step, BMC took it, and the replay
    of BMC's run to `bad` ended in an internal error. BMC
    now blocks it too: in a field, a record and a literal's parameter as well."""
    write_files(tmp_path, {"m.rct": NEGATIVE_NAT.replace("ACTION", action).replace("CONDITION", condition),
                           "m.assertions": "assertion R: bad is reachable in M.\n"})
    ranges = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})
    for results in both_engines(load(tmp_path), ranges, 8, timeout=30):
        assert [r.verdict for r in results] == ["violated"], results


def test_no_initial_configuration_is_said_not_decided_vacuously(tmp_path: Path) -> None:
    """`var n : nat = 0 - 1`: no run starts, and both engines had decided every claim about it
    vacuously (deadlock-free held, a state was unreachable). It is now `unknown`, saying why."""
    write_files(tmp_path, {"m.rct": "stm M {\n var n : nat = 0 - 1\n initial i\n state s {}\n"
                                    " transition t0 { from i to s }\n}\n",
                           "m.assertions": "assertion D: M is deadlock-free.\nassertion R: s is reachable in M.\n"})
    ranges = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})
    for results in both_engines(load(tmp_path), ranges, 8, timeout=30):
        assert [(r.verdict, (r.reason or "")[:12]) for r in results] == [("unknown", "no run start")] * 2, results
