"""A constant made a parameter (`--param`) is considered at every value: an assertion holds when it
holds for every value (docs/semantics.md §6.3).  Both engines search the runs from all values at once,
so a claim that some run exists (a witness), or that each trace of a specification is performed,
shown by the runs of some values, gives no verdict for the others (`goals.one_value_only`).

By hand, for KT with k in -1..1: only k = 1 reaches the final state f, so `KT terminates` and
`f is reachable in KT` are violated at k = 0 (a witness starting from k = 1 does not show them for
every value: `unknown`, not `holds`).  `KT does not terminate` is violated (the witness
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
from tockbmc.model.readings import Reading

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


FREE = """
function g(x : int) : int { }
function h(x : int) : int { precondition x > 0 postcondition result == x }
function twice(x : int) : int { postcondition result == h(x) + h(x) }
stm U {
  const k : int
  initial i
  junction j
  state s {}
  final f
  transition tj { from i to j }
  transition t0 { from j to f condition g(k) == 1 }
  transition t1 { from j to s condition g(k) != 1 }
}
stm V {
  initial i
  junction j
  state s {}
  final f
  transition tj { from i to j }
  transition t0 { from j to f condition twice(0) == 4 }
  transition t1 { from j to s condition twice(0) != 4 }
}
stm W {
  initial i
  junction j
  state s {}
  final f
  transition tj { from i to j }
  transition t0 { from j to f condition h(2) == 2 }
  transition t1 { from j to s condition h(2) != 2 }
}
"""
FREE_ASSERTIONS = """
assertion R1: f is reachable in U.
assertion R2: U does not terminate.
assertion R3: s is not reachable in U.
assertion R4: U is deadlock-free.
assertion V1: f is reachable in V.
assertion W1: f is reachable in W.
"""


def test_a_witness_that_chose_what_a_function_without_a_body_computes_gives_no_verdict(tmp_path: Path) -> None:
    """A claim holds when it holds whatever a function without a body computes (docs/semantics.md
    §6.4): BMC's witness for `f is reachable in U` chose g(0) = 1 (which would
    say `holds`), and V's chose h(0), outside h's precondition, through twice's body. W calls h only inside
    its precondition, where the body fixes it: the interpreter, which evaluates no function without
    a body, replays the witness whole, so it stands whatever the functions compute. Violations
    stand: some g makes each. (The open reading: by default g is RoboTool's placeholder.)"""
    write_files(tmp_path, {"m.rct": FREE, "m.assertions": FREE_ASSERTIONS})
    project = tockbmc.load(tmp_path)
    config = configure(project, ONE, settings={"U::k": "0"}, reading=Reading.OPEN)
    results = {r.assertion: r for r in check(config.project, bound=10, config=config, timeout=60)}
    assert {n: r.verdict for n, r in results.items()} == {
        "R1": "unknown", "R2": "violated", "R3": "violated", "R4": "violated", "V1": "unknown", "W1": "holds"}
    assert "the run rests on what the model leaves open (g)" in (results["R1"].reason or "")
    assert "(h)" in (results["V1"].reason or "") and results["W1"].extra["replayed"] == "yes"


CONDITIONS = """
function g(a : int) : int { postcondition result > a }
stm M {
  var z : int = 0
  event out : int
  initial i
  state s { entry z = g(3) ; out!z }
  state big {}
  state hundred {}
  transition t0 { from i to s }
  transition t1 { from s to big condition z > 3 }
  transition t2 { from s to hundred condition z == 100 }
}
"""


def test_a_witness_that_holds_for_every_function_its_conditions_allow_stands(tmp_path: Path) -> None:
    """With the run's moves and choices fixed, `z > 3` holds for every g with g(a) > a, so `big is
    reachable` holds (its output's value is g's, whatever it is); `z == 100` does not, so `hundred
    is reachable` stays unknown (`bmc.interpretations`)."""
    write_files(tmp_path, {"m.rct": CONDITIONS, "m.assertions": "assertion Big: big is reachable in M.\n"
                                                                 "assertion Hundred: hundred is reachable in M.\n"})
    results = {r.assertion: r for r in check(tockbmc.load(tmp_path), bound=10, timeout=60)}
    assert results["Big"].verdict == "holds" and "unspecified" in results["Big"].extra
    assert results["Hundred"].verdict == "unknown" and "(g)" in (results["Hundred"].reason or "")


OPEN = """
function g() : int { }
function k1(a : int) : int { postcondition result > a }
stm A {
  var x : int = g()
  initial i
  state s {}
  state yes {}
  transition t0 { from i to s }
  transition t1 { from s to yes condition x == 1 }
}
stm B {
  const k : int = k1(1)
  var x : int = 0
  initial i
  state s {}
  state yes {}
  transition t0 { from i to s action x = k }
  transition t1 { from s to yes condition x == 3 }
}
stm L {
  var f : int -> int
  var x : int = 0
  initial i
  state s {}
  state yes {}
  transition t0 { from i to s action f = lambda y : int | y > 0 @ y ; x = f(0 - 1) }
  transition t1 { from s to yes condition x == 2 }
}
stm Q {
  var s : Seq(int) = <1, 2>
  var x : int = 0
  var z : int = 0
  initial i
  state a {}
  state yes {}
  state no {}
  transition t0 { from i to a action x = s[5] }
  transition t1 { from a to yes condition x == 7 }
  transition t2 { from a to no condition 7 / z == 3 }
}
stm E {
  var s : Seq(nat) = <>
  var b : boolean = exists i : nat | i <= 2 @ s[i] == 7
  initial i
  state a {}
  state yes {}
  transition t0 { from i to a }
  transition t1 { from a to yes condition b }
}
"""


def test_a_witness_resting_on_any_value_the_model_leaves_open_gives_no_verdict(tmp_path: Path) -> None:
    """None of these is `holds`. A's initial value calls g, which has no parameters (a
    Z3 constant); B's constant rests on k1 (the replay took its value from the run); L applies a
    lambda outside its condition, Q reads an item past a sequence's end and divides by zero: any
    value there is possible (docs/semantics.md §6.4, §6.5), so no one run shows them for every value.
    E's initial value reads past the sequence's end inside a quantifier (the scan missed it, and the
    replay had taken the start from the run: a wrong `holds`). Functions and variables are read
    open; constants take RoboTool's defaults."""
    write_files(tmp_path, {"m.rct": OPEN, "m.assertions": "".join(
        f"assertion {n}: {st} is reachable in {m}.\n" for n, st, m in
        (("A1", "yes", "A"), ("B1", "yes", "B"), ("L1", "yes", "L"), ("Q1", "yes", "Q"), ("Q2", "no", "Q"),
         ("E1", "yes", "E")))})
    config = configure(tockbmc.load(tmp_path), reading=Reading.OPEN, open_defaults=False)
    results = {r.assertion: r for r in check(config.project, bound=10, config=config, timeout=60)}
    assert {n: r.verdict for n, r in results.items()} == {n: "unknown" for n in ("A1", "B1", "L1", "Q1", "Q2", "E1")}, \
        {n: r.reason for n, r in results.items()}
    assert "(g)" in (results["A1"].reason or "") and "(k1)" in (results["B1"].reason or "")
    assert "a lambda outside its condition" in (results["L1"].reason or "")
    assert "a sequence's item outside its length" in (results["Q1"].reason or "")
    assert "a division by zero" in (results["Q2"].reason or "")
    assert "a sequence's item outside its length" in (results["E1"].reason or "")


OPEN_VALUES = Path(__file__).parent / "models" / "open_values"


@pytest.mark.parametrize(("case", "expected"), [
    # a user's function `index` with a precondition beside a sequence's item outside its length
    ("c1", {"N": "violated"}),
    # a pair of runs, one through `1 / z == 5` with z = 0: it rests on the division's value
    ("d1", {"ND": "unknown", "DT": "violated"}),
    # the specification on the left, its trace through `s[3] == 5` on <1>
    ("r3", {"Q": "unknown"}),
    # a function-typed variable without an initial value is any function into nat at every step
    ("q9c", {"D": "holds"}),
])
def test_what_the_model_leaves_open(case: str, expected: dict[str, str]) -> None:
    """Verdicts that rest on a value the model leaves open: c1, q9c, d1 ND and r3 Q."""
    ranges = Ranges({"core_int": Range(Fraction(-3), Fraction(3)), "core_nat": Range(Fraction(0), Fraction(3))})
    results = check(tockbmc.load(OPEN_VALUES / case), bound=10, ranges=ranges, timeout=60)
    assert {r.assertion: r.verdict for r in results} == expected, {r.assertion: r.reason for r in results}


def test_a_division_by_a_constant_that_is_not_zero_leaves_nothing_open(tmp_path: Path) -> None:
    """`since(C) >= PI / av` with av = 2 (SRangerRC2RS's A1/A3 had become `unknown`, the division
    counted as one that might be by zero): only a divisor the constants' values allow to be 0 counts."""
    write_files(tmp_path, {"m.rct": """
stm M {
  const PI : real = 3
  const av : real = 2
  const z : real = 0
  var x : real = 0
  initial i
  state s {}
  state a {}
  state b {}
  transition t0 { from i to s }
  transition t1 { from s to a condition x + 2 >= PI / av }
  transition t2 { from s to b condition x / z == 4 }
}
""", "m.assertions": "assertion A: a is reachable in M.\nassertion B: b is reachable in M.\n"})
    results = {r.assertion: r for r in check(tockbmc.load(tmp_path), bound=10, timeout=60)}
    assert results["A"].verdict == "holds" and results["B"].verdict == "unknown"
    assert "a division by zero" in (results["B"].reason or "")
