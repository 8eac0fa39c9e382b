"""A sequence's or set's items of type `nat` are never negative (docs/semantics.md §10): a step that
would store a negative item cannot be taken, in both engines. BMC had not checked the items, so
its run to `bad` in M (`s = s ^ <x>` with x = -1) ended in an internal error when replayed."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from tockbmc import load
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges

MODEL = Path(__file__).parent / "models" / "nat_items"
EXPECTED = {
    "R": "holds",  # s = s ^ <x>: a concatenation's new item
    "R2": "violated",
    "RS": "holds",  # s = union(s, {x - 1}) of a Set(nat)
    "RS2": "violated",
    "RT": "violated",  # s = t of a Seq(int) t (a quantifier over t's items): t's items may all be positive
    "RU": "holds",  # f?s of a Seq(nat) s on a Seq(int) event
    "RV": "holds",  # s[2] = x
    "RW": "holds",  # a record's Seq(nat) field
}


def _range(lo: int, hi: int) -> Range:
    return Range(Fraction(lo), Fraction(hi))


def test_bmc_unbounded() -> None:
    results = check(load(MODEL), bound=8, timeout=60)
    assert {r.assertion: r.verdict for r in results} == EXPECTED, [r.reason for r in results]
    for r in results:
        if r.trace:
            assert r.extra["replayed"] == "yes", r.assertion


def test_explicit_engine() -> None:
    ranges = Ranges({"core_int": _range(-1, 1), "core_nat": _range(0, 1)},
                    {"T::f": _range(0, 2), "U::f": _range(0, 2), "W::r.items": _range(0, 2)})
    results = check_explicit(load(MODEL), None, 8, ranges, {}, 60)
    assert {r.assertion: r.verdict for r in results} == EXPECTED, [r.reason for r in results]
