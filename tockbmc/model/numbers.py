"""Exact text of numbers of any size, never through `float`.

Python refuses to convert integers of more than `sys.get_int_max_str_digits()` digits to and from
text, and `float` overflows beyond 1e308 and underflows below 1e-308; model values can be either
(a real literal with 400 zeros, a value squared a few times). `decimal.Decimal` converts exactly
and without that limit.
"""

from __future__ import annotations

import sys
from decimal import Decimal
from fractions import Fraction


def int_text(n: int) -> str:
    """The decimal digits of `n`, whatever its size."""
    if n.bit_length() < 3300:  # under 1000 digits, far below any limit Python sets (no power computed per call)
        return str(n)
    return str(Decimal(n))


_PLACES = 64  # decimal places allowed beyond the denominator's digits (a denominator of 2**1000000 hung)


def real_text(value: Fraction) -> str:
    """`value` as an exact decimal (`0.5`, `-1.25`, `3`) when it has one, else as `p/q`."""
    num, den = value.numerator, value.denominator
    if den == 1:
        return int_text(num)
    twos = (den & -den).bit_length() - 1
    rest = den >> twos
    fives = 0
    while rest % 5 == 0:
        rest //= 5
        fives += 1
    # A decimal with many more places than the denominator has digits (1/2**N has N) is written as
    # the fraction it is; a decimal literal's (1e-400: 10**400) is not longer than its fraction.
    if rest != 1 or max(twos, fives) > _PLACES + den.bit_length() // 3:
        return f"{int_text(num)}/{int_text(den)}"
    places = max(twos, fives)
    digits = int_text(abs(num) * 10**places // den).rjust(places + 1, "0")
    return f"{'-' if num < 0 else ''}{digits[:-places]}.{digits[-places:]}"


def parse_int(text: str) -> int | None:
    """The integer a literal's digits denote, or None when it is longer than Python converts."""
    try:
        return int(text)
    except ValueError:
        return None


def parse_real(text: str) -> Fraction | None:
    """The exact value of a decimal literal (`12.5`), or None when it is longer than Python converts."""
    try:
        return Fraction(text)
    except ValueError:
        return None


def max_digits() -> int:
    """The most digits a number literal may have (Python's limit on converting text to integers)."""
    return sys.get_int_max_str_digits() or sys.maxsize
