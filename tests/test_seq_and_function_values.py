"""The items of a sequence or set of nat, and the results of function-typed values, stay in their
types wherever they come from, without making runs impossible that the model allows
(tests/models/seq_and_function_values)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import verdicts_are

from tockbmc import load
from tockbmc.check import check
from tockbmc.model.ranges import Range, Ranges

MODELS = Path(__file__).parent / "models" / "seq_and_function_values"
RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2))})


@pytest.mark.parametrize(("case", "expected"), [
    # a specification naming `M::a` without its `.in`, beside a model that no run starts: the
    # assertion is read before the model's runs, so both engines say `unsupported` (not the
    # explicit engine's `unknown` for a model no run starts)
    ("ns3", {"A2": "unsupported"}),
    # a function-typed variable without an initial value, later given `lambda k : nat @ k - 5`:
    # the chosen function's results are kept in type only while the variable holds it, so storing
    # the lambda does not make the runs through it impossible (R); the lambda's application is a
    # condition of its step only (C), and the chosen function's results stay in type (D: no run
    # stops at `a` for f(1) < 0)
    ("fn2", {"R": "violated", "C": "holds", "D": "holds"}),
])
def test_both_engines(case: str, expected: dict[str, str]) -> None:
    verdicts_are(load(MODELS / case), RANGES, 10, expected, explicit=case != "fn2")


# A sequence's or set's nat items are not negative, whichever expression made them.
SEQ_RANGES = Ranges(RANGES.by_type, {"U::f": Range(Fraction(0), Fraction(2)), "W::f": Range(Fraction(0), Fraction(2))})


@pytest.mark.parametrize(("case", "expected"), [
    # a slice, a difference and a set without an item are checked as themselves, not as the whole
    # they came from: `s = tail(<x> ^ s)`, `diff({x}, {x})`, `front(s ^ <x>)` with x < 0 are allowed
    ("over", {"RA": "violated", "RB": "violated", "RC": "violated"}),
    # `f?s` of a Seq(int) event into a Seq(nat) s, deadlock: within a length range the items are
    # checked one by one, since Z3 leaves a quantifier under the refusal unanswered
    ("dw", {"DU": "violated", "DV": "violated", "DW": "holds"}),
    # a reverse and a filter of a Seq(nat) are of nat without a check Z3 would have to see through
    # a fold for (it answers `unknown` there)
    ("rev", {"R": "holds"}),
    ("filt", {"R": "holds"}),
    # a value another machine sends, synchronously or through a buffer, is not one of the event's
    # type as an input the environment chooses is: no run stores -1, and BMC's runs replay
    ("sync", {"R": "holds"}),
    ("async", {"R": "holds"}),
])
def test_nat_items(case: str, expected: dict[str, str]) -> None:
    bmc, _ = verdicts_are(load(MODELS / case), SEQ_RANGES if case == "dw" else RANGES, 8, expected)
    assert all(r.extra.get("replayed", "yes") == "yes" for r in bmc if r.trace)


def test_an_update_outside_the_sequence_is_a_sequence_of_its_type() -> None:
    """`s[2] = 1` on an empty Seq(nat): any sequence, of nat, so `holds` (BMC only: the explicit
    engine does not interpret the update)."""
    [r] = check(load(MODELS / "upd2"), bound=6, timeout=30)
    assert r.verdict == "holds", r.reason


# Whether a function-typed variable holds a function nobody set, or one the model made; BMC only:
# the interpreter does not apply a function nobody set, nor these functions' arguments.
@pytest.mark.parametrize(("case", "expected"), [
    # `f = g` of a function nobody set keeps f a function nobody set, its results in type: no deadlock at `a`
    ("fv_a1", {"D": "holds"}),
    # the same through an operation's parameter, `ap(g)`
    ("fv_o3", {"D": "holds"}),
    # a lambda passed to an uninterpreted function whose postcondition applies it: its result
    # outside nat is a condition of the step that applies it, not an axiom of every step
    ("fv_u2", {"R": "violated"}),
    # ... and as a record argument's field, to a defined function
    ("fv_u3", {"R": "violated"}),
])
def test_function_values(case: str, expected: dict[str, str]) -> None:
    results = check(load(MODELS / case), bound=8, timeout=30)
    assert {r.assertion: r.verdict for r in results} == expected, [r.reason for r in results]


# Updates outside a sequence and received functions, BMC only (the interpreter refuses these
# updates and results).
@pytest.mark.parametrize(("case", "expected"), [
    # `t[2] = 1` on an empty Seq(int) beside an `s[2] = 1` on an empty Seq(nat): each sequence's
    # values outside it have a function of their own, so the Seq(nat)'s axiom does not bind t
    ("two_seqs_updated_outside", {"R": "violated"}),
    # a lambda received on an event into a function variable without an initial value: taken
    # for a function the model made, so its result outside nat is no axiom of every step
    ("received_lambda", {"R": "violated"}),
    pytest.param("read_outside_length", {"R": "violated"}, marks=pytest.mark.xfail(
        strict=True, reason="known (docs/semantics.md §10): a Seq(nat)'s item read outside its length is kept a "
                            "nat by an axiom on Z3's nth, which also binds an equal Seq(int)'s read")),
])
def test_updates_outside_a_sequence_and_received_functions(case: str, expected: dict[str, str]) -> None:
    results = check(load(MODELS / case), bound=6, timeout=30)
    assert {r.assertion: r.verdict for r in results} == expected, [r.reason for r in results]
