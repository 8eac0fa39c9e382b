"""Python values of sequences, sets and tuples, shared by the interpreter and the witness decoder.

A sequence is a Python `tuple`, a set a `frozenset`, a tuple (product) a `Product` (a tuple kept
apart from sequences, so that each prints as RoboChart and FDR write it: `<1, 2>`, `{1, 2}`,
`(1, 2)`), and a literal with parameters a `Variant` (`E::L(1)`).
"""

from __future__ import annotations

from fractions import Fraction

from tockbmc.model import ast
from tockbmc.model.numbers import int_text, real_text


class Product(tuple):
    """A tuple value `(| a, b |)`: its parts in order."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "Product(" + tuple.__repr__(self) + ")"


class Variant(tuple):
    """A value `E::L(a, …)` of an enumeration literal with parameters: the literal's qualified name
    ("E::L", as a literal without parameters is written), then its arguments."""

    __slots__ = ()

    @property
    def literal(self) -> str:
        return self[0]

    @property
    def args(self) -> tuple:
        return tuple(self[1:])

    def __repr__(self) -> str:
        return "Variant(" + tuple.__repr__(self) + ")"


_SHOWN = 32  # items of a sequence or set written out; the rest are counted (a run can build millions)


def text_of(t: ast.Type | None, v: object) -> str:
    """FDR-style text of a value of type `t`."""
    if isinstance(v, dict):
        fields = [f.name for f in t.fields] if isinstance(t, ast.RecordType) else list(v)
        ftype = (lambda n: t.field_type(n)) if isinstance(t, ast.RecordType) else (lambda n: None)
        return "(" + ", ".join(f"{n}={text_of(ftype(n), v[n])}" for n in fields) + ")"
    if isinstance(v, Variant):
        ps = t.parameters(v.literal.rsplit("::", 1)[-1]) if isinstance(t, ast.EnumType) else (None,) * len(v.args)
        return v.literal + "(" + ", ".join(text_of(pt, x) for pt, x in zip(ps, v.args, strict=True)) + ")"
    if isinstance(v, Product):
        ts = t.parts if isinstance(t, ast.ProductType) else (None,) * len(v)
        return "(" + ", ".join(text_of(pt, x) for pt, x in zip(ts, v, strict=True)) + ")"
    element = t.element if isinstance(t, (ast.SeqType, ast.SetType)) else None
    if isinstance(v, tuple):
        shown = [text_of(element, x) for x in list(v)[:_SHOWN]]
        return "<" + ", ".join(shown) + (f", … ({len(v)} in all)" if len(v) > _SHOWN else "") + ">"
    if isinstance(v, frozenset):
        items = sorted(text_of(element, x) for x in list(v)[: 4 * _SHOWN])
        return "{" + ", ".join(items[:_SHOWN]) + (f", … ({len(v)} in all)" if len(v) > _SHOWN else "") + "}"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, Fraction):
        return real_text(v)
    if isinstance(v, int):
        return int_text(v)
    return str(v)
