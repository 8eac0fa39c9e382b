"""Walking Z3 terms without recursion (a term is a DAG: each shared subterm is visited once)."""

from __future__ import annotations

from collections.abc import Iterator

import z3


def subterms(term: z3.ExprRef) -> Iterator[z3.ExprRef]:
    """`term` and every term below it, each once, in no particular order."""
    seen: set[int] = set()
    stack = [term]
    while stack:
        t = stack.pop()
        if t.get_id() in seen:
            continue
        seen.add(t.get_id())
        yield t
        stack += t.children()


def quantified(term: z3.ExprRef) -> bool:
    """Whether a quantifier occurs in `term`."""
    return any(z3.is_quantifier(t) for t in subterms(term))


def constants(*terms: z3.ExprRef) -> list[z3.ExprRef]:
    """The uninterpreted constants (0-ary symbols) in `terms`, each once."""
    out: dict[int, z3.ExprRef] = {}
    seen: set[int] = set()
    for term in terms:
        for t in subterms(term):
            if t.get_id() in seen:
                continue
            seen.add(t.get_id())
            if z3.is_const(t) and t.decl().kind() == z3.Z3_OP_UNINTERPRETED:
                out.setdefault(t.decl().get_id(), t)
    return list(out.values())
