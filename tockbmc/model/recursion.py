"""A function the model defines by recursion (`postcondition result == … f(n - 1) …`), unfolded.

RoboTool's CSP evaluates such a function by calling it; the engines evaluate a function's body
where it is called, so a recursive body is unfolded into itself, its parameters bound by `let`,
up to `DEPTHS` calls deep. A call deeper than that is a call of `cut`: a function of the same
signature that nothing defines, kept open in every reading (docs/semantics.md §6.4), so a verdict
that rests on a value past the unfolding says so and is `unknown`, never a guess.
"""

from __future__ import annotations

import dataclasses
from typing import Any, cast

from tockbmc.model import ast

# How many nested calls a recursive function is unfolded to, tried in turn until its body has at
# most `MAX_NODES` expression nodes (a body calling itself twice doubles with each level).
DEPTHS = (8, 6, 4, 3, 2, 1)
MAX_NODES = 6_000


def calls(e: object, f: ast.Function) -> bool:
    """Whether `e` calls `f` (the very object)."""
    return any(isinstance(x, ast.Call) and x.function is f for x in ast.parts(e))


def unfolded(f: ast.Function, own: ast.Function) -> ast.Function:
    """`f`, whose definition calls `own` (its own signature, open) for its recursive calls, with
    those calls unfolded; the deepest ones call `own` kept open (`ast.Function.unfolding_of`)."""
    assert f.definition is not None
    cut = dataclasses.replace(own, unfolding_of=f.qname)
    body = f.definition
    for depth in DEPTHS:
        body = _unfold(f.definition, f, own, cut, depth, 0)
        if ast.tree_size(body, MAX_NODES) <= MAX_NODES:
            break
    return dataclasses.replace(f, definition=body)


def _unfold(e: ast.Expr, f: ast.Function, own: ast.Function, cut: ast.Function, depth: int, level: int) -> ast.Expr:
    def visit(x: object) -> object:
        if isinstance(x, ast.Call) and x.function is own:
            args = cast("tuple[ast.Expr, ...]", tuple(visit(a) for a in x.args))
            if level >= depth:
                return dataclasses.replace(x, function=cut, args=args)
            inner = _unfold(e, f, own, cut, depth, level + 1)
            return _bound(f, args, inner, level, x.pos)
        if isinstance(x, ast.Expr):
            changes: dict[str, Any] = {}
            for field in dataclasses.fields(x):
                if field.name in ("type", "pos"):
                    continue
                old = getattr(x, field.name)
                new = visit(old)
                if new is not old:
                    changes[field.name] = new
            return dataclasses.replace(x, **changes) if changes else x
        if isinstance(x, tuple):
            items = tuple(visit(i) for i in x)
            return items if any(a is not b for a, b in zip(items, x, strict=True)) else x
        return x

    return visit(e)  # type: ignore[return-value]


def _bound(f: ast.Function, args: tuple[ast.Expr, ...], body: ast.Expr, level: int, pos: ast.Pos) -> ast.Expr:
    """`body` with `f`'s parameters bound to `args`, each argument read where the call is: first
    into a name of its own (an argument may read a parameter the binding changes), then into the
    parameter."""
    temps = [dataclasses.replace(p, name=f"{p.name}'{level}", kind="parameter") for p in f.parameters]
    out = body
    for p, t in reversed(list(zip(f.parameters, temps, strict=True))):
        out = ast.Let(out.type, pos, p, ast.VarRef(t.type, pos, t), out)
    for t, a in reversed(list(zip(temps, args, strict=True))):
        out = ast.Let(out.type, pos, t, a, out)
    return out
