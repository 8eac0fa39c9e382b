"""Whether RoboTool's placeholder for a function meets the function's own contract.

RoboTool's instantiation gives a function without a body a constant placeholder (`f(…) = 0`).
Where the function states a postcondition, the default reading uses the placeholder only if it
meets it for every argument the preconditions allow (docs/semantics.md §6.6):

    forall args @ pre(args) => post(args, result := placeholder)

decided by Z3 in a context of its own. The conditions are read in the fragment of numbers,
booleans and literals (arithmetic, comparisons, connectives, `if`); anything else (a quantifier, a
sequence, a call) is not decided here, and the function stays open under its contract.
"""

from __future__ import annotations

from fractions import Fraction

import z3

from tockbmc.model import ast

_TIMEOUT_MS = 2000


class _Outside(Exception):
    """A condition outside the fragment read here."""


def placeholder_meets(f: ast.Function, value: ast.Expr) -> bool | None:
    """True if `value` meets `f`'s postconditions wherever its preconditions hold, False if some
    argument shows it does not, None where that is not decided here."""
    ctx = z3.Context()
    params: dict[int, z3.ExprRef] = {}
    side: list[z3.BoolRef] = []
    for p in f.parameters:
        params[id(p)] = _fresh(p, ctx, side)
    try:
        result = _term(value, params, None, ctx)
        pre = [_bool(_term(c, params, result, ctx)) for c in f.preconditions]
        post = [_bool(_term(c, params, result, ctx)) for c in f.postconditions]
    except _Outside:
        return None
    s = z3.Solver(ctx=ctx)
    s.set("timeout", _TIMEOUT_MS)
    s.add(*side, *pre, z3.Not(z3.And(*post, ctx)) if post else z3.BoolVal(False, ctx))
    answer = s.check()
    return True if answer == z3.unsat else False if answer == z3.sat else None


def _bool(t: z3.ExprRef) -> z3.BoolRef:
    if not z3.is_bool(t):
        raise _Outside
    assert isinstance(t, z3.BoolRef)
    return t


def _fresh(p: ast.Variable, ctx: z3.Context, side: list[z3.BoolRef]) -> z3.ExprRef:
    if p.type == ast.REAL:
        return z3.Real(p.name, ctx)
    if p.type == ast.BOOLEAN:
        return z3.Bool(p.name, ctx)
    if p.type in (ast.INT, ast.NAT):
        x = z3.Int(p.name, ctx)
        if p.type == ast.NAT:
            side.append(x >= 0)
        return x
    return z3.Const(p.name, z3.DeclareSort("Other", ctx))  # usable only where compared for equality


def _term(e: ast.Expr, params: dict[int, z3.ExprRef], result: z3.ExprRef | None, ctx: z3.Context) -> z3.ExprRef:
    if isinstance(e, ast.Literal):
        if isinstance(e.value, bool):
            return z3.BoolVal(e.value, ctx)
        if isinstance(e.value, Fraction) or e.type == ast.REAL:
            return z3.RealVal(str(Fraction(e.value)), ctx)
        if isinstance(e.value, int) and e.type in ast.NUMERIC:
            return z3.IntVal(e.value, ctx)
        raise _Outside
    if isinstance(e, ast.VarRef) and id(e.variable) in params:
        return params[id(e.variable)]
    if isinstance(e, ast.ResultRef) and result is not None:
        return result
    if isinstance(e, ast.Unary):
        x = _term(e.operand, params, result, ctx)
        if e.op == "not":
            return z3.Not(_bool(x))
        if e.op == "-" and z3.is_arith(x):
            return -x  # type: ignore[operator]
        raise _Outside
    if isinstance(e, ast.IfExpr):
        return z3.If(_bool(_term(e.condition, params, result, ctx)), _term(e.then, params, result, ctx),
                     _term(e.otherwise, params, result, ctx))
    if isinstance(e, ast.Binary):
        a, b = _term(e.left, params, result, ctx), _term(e.right, params, result, ctx)
        return _binary(e.op, a, b)
    raise _Outside


def _binary(op: str, a: z3.ExprRef, b: z3.ExprRef) -> z3.ExprRef:
    if op in ("and", "or", "implies", "iff"):
        x, y = _bool(a), _bool(b)
        return {"and": lambda: z3.And(x, y), "or": lambda: z3.Or(x, y), "implies": lambda: z3.Implies(x, y),
                "iff": lambda: x == y}[op]()
    if op in ("==", "!="):
        if a.sort() != b.sort() and not (z3.is_arith(a) and z3.is_arith(b)):
            raise _Outside
        return a == b if op == "==" else a != b  # type: ignore[return-value]
    if not (z3.is_arith(a) and z3.is_arith(b)):
        raise _Outside
    x, y = a, b  # type: ignore[assignment]
    if op == "%":
        if not (z3.is_int(x) and z3.is_int(y)):
            raise _Outside
        return x % y  # type: ignore[operator]
    arith = {"+": lambda: x + y, "-": lambda: x - y, "*": lambda: x * y, "/": lambda: x / y,  # type: ignore[operator]
             "<": lambda: x < y, "<=": lambda: x <= y, ">": lambda: x > y, ">=": lambda: x >= y}  # type: ignore[operator]
    if op not in arith:
        raise _Outside
    return arith[op]()
