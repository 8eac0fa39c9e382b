"""Quantifiers, generic functions, lambda and the rest of RoboChart's data language:
loaded, decided by BMC in Z3's theories and by the explicit engine, which must agree."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.explicit.interpreter import Unbounded
from tockbmc.model import ast
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

NAT03 = Ranges({"core_nat": Range(Fraction(0), Fraction(3))})

QUANTIFIERS = """\
import sequence_toolkit::*
function allBelow(s : Seq(nat), b : nat) : boolean {
  postcondition result == (forall i : nat | 1 <= i /\\ i <= size(s) @ s[i] < b)
}
stm M {
  var s : Seq(nat) = <>
  var x : nat = 0
  event e : nat
  event ok
  event bad
  initial i
  state S0 { }
  state S1 { }
  state S2 { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S0 trigger e?x condition size(s) < 3 action s = s ^ <x> }
  transition t2 { from S0 to S1 condition exists j : nat | j < 3 @ j * j == x /\\ x > 1 action ok }
  transition t3 { from S0 to S2 condition size(s) == 3 /\\ not allBelow(s, 3) action bad }
  transition t4 { from S1 to S0 condition exists1 k : nat @ k + k == x action ok }
}
"""
QUANTIFIER_ASSERTIONS = """\
assertion R1: S1 is reachable in M.
assertion R2: S2 is reachable in M.
assertion A1: M is deadlock-free.
"""


def _project(tmp_path: Path, model: str, assertions: str = "") -> Project:
    (tmp_path / "m.rct").write_text(model)
    if assertions:
        (tmp_path / "m.assertions").write_text(assertions)
    return load(tmp_path)


def test_quantifiers_in_bmc_and_the_explicit_engine(tmp_path: Path) -> None:
    project = _project(tmp_path, QUANTIFIERS, QUANTIFIER_ASSERTIONS)
    bmc = {r.assertion: r for r in check(project, bound=14, ranges=NAT03)}
    # `j * j == x /\ x > 1` needs x = 4, outside core_nat=0..3: S1 is not reachable; three
    # inputs, one of them 3, make `allBelow(s, 3)` false: S2 is.
    assert bmc["R1"].verdict == Verdict.VIOLATED
    assert bmc["R2"].verdict == Verdict.HOLDS
    assert bmc["R2"].extra["replayed"] == "yes"
    assert [s.event for s in bmc["R2"].trace if s.event and s.event != "tock"][-1] == "M::bad.out"
    assert bmc["A1"].verdict == Verdict.VIOLATED  # in S2 nothing but tock
    explicit = {r.assertion: r.verdict for r in check_explicit(project, ["R1", "R2", "A1"], 14, NAT03, {}, None)}
    assert explicit == {k: r.verdict for k, r in bmc.items()}


def test_exists1_and_an_unbounded_quantifier(tmp_path: Path) -> None:
    # Without ranges BMC quantifies over every natural (x = 4 = 2 * 2 reaches S1, and then
    # `exists1 k @ k + k == 4` holds: no deadlock there); the explicit engine cannot list them.
    project = _project(tmp_path, QUANTIFIERS, QUANTIFIER_ASSERTIONS)
    results = {r.assertion: r for r in check(project, ["R1"], bound=14)}
    assert results["R1"].verdict == Verdict.HOLDS
    assert [s.event for s in results["R1"].trace if s.event and s.event != "tock"][:1] == ["M::e.in.4"]
    with pytest.raises(Unbounded, match="core_nat"):
        check_explicit(project, ["R1"], 14, Ranges(), {}, None)


def test_a_quantifier_s_predicate_must_be_boolean(tmp_path: Path) -> None:
    model = "stm M {\n  var x : nat = 0\n  initial i\n  state s {}\n" \
            "  transition t0 { from i to s condition forall y : nat @ y + 1 }\n}\n"
    with pytest.raises(ModelError, match="the predicate of 'forall' must be boolean"):
        _project(tmp_path, model)

GENERIC = """\
function first(p : ?X * ?Y) : ?X { postcondition result == p[1] }
function both(a : ?X, b : ?X) : Seq(?X) { postcondition result == <a, b> }
function card(A : Set(?X)) : nat { }
function UpdateValue(value : ?X * nat, newValue : ?X * nat) : boolean { }
stm M {
  var x : nat = 0
  var b : boolean = false
  event e : nat
  event out : int
  initial i
  state S0 { }
  state S1 { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S1 trigger e?x
                  condition first((| x, true |)) == 2 /\\ first((| false, x |)) == false /\\ both(x, -1)[2] < 0
                  action out!first((| both(x, -1)[2], 0 |)) }
}
"""


def test_generic_functions_are_instantiated_at_each_call(tmp_path: Path) -> None:
    project = _project(tmp_path, GENERIC, "assertion R: S1 is reachable in M.\n")
    calls = {c.function.qname for t in project.machines[0].transitions
             for c in ast.subexpressions((t.condition, t.action)) if isinstance(c, ast.Call)}
    assert calls == {"first[?X=nat, ?Y=boolean]", "first[?X=boolean, ?Y=nat]", "both[?X=int]",
                     "first[?X=int, ?Y=nat]"}
    [bmc] = check(project, bound=8, ranges=NAT03)
    assert bmc.verdict == Verdict.HOLDS and bmc.extra["replayed"] == "yes"
    assert [s.event for s in bmc.trace if s.event and s.event != "tock"] == ["M::e.in.2", "M::out.out.-1"]
    [explicit] = check_explicit(project, ["R"], 8, NAT03, {}, None)
    assert explicit.verdict == Verdict.HOLDS




def test_a_generic_call_that_gives_one_type_two_types_is_an_error(tmp_path: Path) -> None:
    statement = "b = UpdateValue((| 1, 2 |), (| true, 2 |))"
    model = GENERIC.replace("action out!", f"action {statement} ; out!")
    with pytest.raises(ModelError, match="the arguments of 'UpdateValue' give one generic type two types"):
        _project(tmp_path, model)


def test_a_generic_call_that_fixes_no_type_makes_its_assertions_unsupported(tmp_path: Path) -> None:
    """RoboTool accepts it; tockbmc cannot choose the type (tests/test_unsupported_per_assertion.py)."""
    model = ("function pick() : ?X { }\n" + GENERIC).replace("action out!", "action x = pick() ; out!")
    project = _project(tmp_path, model, "assertion R: S1 is reachable in M.\n")
    [bmc] = check(project, bound=8, ranges=NAT03)
    [explicit] = check_explicit(project, ["R"], 8, NAT03, {}, None)
    for r in (bmc, explicit):
        assert r.verdict == Verdict.UNSUPPORTED
        assert "a call of 'pick' whose arguments do not fix its generic type ?X" in (r.reason or "")


GIVEN_ORDER = """\
type Intensity
function goreq(i1 : Intensity, i2 : Intensity) : boolean { postcondition result == (i1 > i2) }
stm M {
  var a : Intensity
  var b : Intensity
  event e : Intensity
  initial i
  state S0 { }
  state S1 { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S1 trigger e?a condition goreq(a, b) }
}
"""


def test_order_on_a_given_type_in_a_function_s_conditions_as_robotool(tmp_path: Path) -> None:
    # RoboTool's type checker gives `i1 > i2` on a given type no type, but checks only guards,
    # actions and the like, not functions' conditions: there it is accepted (its CSP orders the
    # type's values, integers, as tockbmc does).
    project = _project(tmp_path, GIVEN_ORDER, "assertion R: S1 is reachable in M.\n")
    ranges = Ranges({"Intensity": Range(Fraction(0), Fraction(1))})
    [bmc] = check(project, bound=8, ranges=ranges)
    assert bmc.verdict == Verdict.HOLDS and bmc.extra["replayed"] == "yes"
    assert [s.event for s in bmc.trace if s.event and s.event != "tock"] == ["M::e.in.1"]
    [explicit] = check_explicit(project, ["R"], 8, ranges, {}, None)
    assert explicit.verdict == Verdict.HOLDS


def test_order_on_a_given_type_in_a_guard_is_refused_as_by_robotool(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="'>' compares numbers, but this is Intensity"):
        _project(tmp_path, GIVEN_ORDER.replace("condition goreq(a, b)", "condition a > b"))
