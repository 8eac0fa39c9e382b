"""Print resolved expressions and statements back in RoboChart's notation."""

from __future__ import annotations

from fractions import Fraction

from tockbmc.model import ast
from tockbmc.model.numbers import int_text, real_text

_SYMBOL = {"and": "/\\", "or": "\\/", "implies": "=>", "iff": "<=>"}
_PRECEDENCE = {"iff": 1, "implies": 2, "or": 3, "and": 4, "==": 6, "!=": 6, "<": 6, "<=": 6, ">": 6,
               ">=": 6, "+": 7, "-": 7, "*": 8, "/": 8, "%": 8}


def value_text(value: object) -> str:
    """A literal value: integers, exact reals, booleans, strings."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Fraction):
        return f"{int_text(value.numerator)}.0" if value.denominator == 1 else real_text(value)
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, int):
        return int_text(value)
    return str(value)


def expr_text(e: ast.Expr, parent: int = 0) -> str:
    """An expression as RoboChart text, with only the parentheses it needs."""
    if isinstance(e, ast.Literal):
        return value_text(e.value)
    if isinstance(e, ast.EnumLiteral):
        args = f"({', '.join(expr_text(a) for a in e.args)})" if e.args else ""
        return f"{e.enum.name}::{e.literal}{args}"
    if isinstance(e, ast.VarRef):
        return e.variable.name
    if isinstance(e, ast.ResultRef):
        return "result"
    if isinstance(e, ast.FieldRef):
        return f"{expr_text(e.record, 10)}.{e.field_name}"
    if isinstance(e, ast.RecordLiteral):
        fields = ", ".join(f"{n} = {expr_text(v)}" for n, v in e.fields)
        return f"{e.type.name}(| {fields} |)"
    if isinstance(e, ast.Unary):
        inner = expr_text(e.operand, 9)
        if e.op == "trunc":
            return f"trunc({expr_text(e.operand)})"
        text = f"not {inner}" if e.op == "not" else f"-{inner}"
        return f"({text})" if parent > 9 else text
    if isinstance(e, ast.Binary):
        prec = _PRECEDENCE[e.op]
        text = f"{expr_text(e.left, prec)} {_SYMBOL.get(e.op, e.op)} {expr_text(e.right, prec + 1)}"
        return f"({text})" if parent > prec else text
    if isinstance(e, ast.IfExpr):
        return f"if {expr_text(e.condition)} then {expr_text(e.then)} else {expr_text(e.otherwise)} end"
    if isinstance(e, ast.Call):
        return f"{e.function.name}({', '.join(expr_text(a) for a in e.args)})"
    if isinstance(e, ast.Since):
        return f"since({e.clock.name})"
    if isinstance(e, ast.SinceEntry):
        return f"sinceEntry({e.state})"
    if isinstance(e, ast.Interval):
        return f"{'[' if e.low_closed else '('}{expr_text(e.low)}, {expr_text(e.high)}{']' if e.high_closed else ')'}"
    return "<?>"


def trigger_text(t: ast.Trigger) -> str:
    if t.kind == "input":
        return f"{t.event.name}?{t.variable.name if t.variable else '_'}"
    if t.kind == "output" and t.value is not None:
        return f"{t.event.name}!{expr_text(t.value)}"
    if t.kind == "sync" and t.value is not None:
        return f"{t.event.name}.{expr_text(t.value)}"
    return t.event.name


def stmt_text(s: ast.Stmt) -> str:
    """A statement as RoboChart text."""
    if isinstance(s, ast.Skip):
        return "skip"
    if isinstance(s, ast.Seq):
        return " ; ".join(stmt_text(x) for x in s.statements)
    if isinstance(s, ast.Assign):
        return f"{'.'.join([s.variable.name, *s.fields])} = {expr_text(s.value)}"
    if isinstance(s, ast.Send):
        return s.event.name if s.value is None else f"{s.event.name}!{expr_text(s.value)}"
    if isinstance(s, ast.Receive):
        return f"{s.event.name}?{s.variable.name if s.variable else '_'}"
    if isinstance(s, ast.OperationCall):
        return f"{s.operation.name}({', '.join(expr_text(a) for a in s.args)})"
    if isinstance(s, ast.If):
        text = f"if {expr_text(s.condition)} then {stmt_text(s.then)}"
        if not isinstance(s.otherwise, ast.Skip):
            text += f" else {stmt_text(s.otherwise)}"
        return text + " end"
    if isinstance(s, ast.Wait):
        if s.low == s.high:
            return f"wait({expr_text(s.low)})"
        return f"wait([{expr_text(s.low)}, {expr_text(s.high)}])"
    if isinstance(s, ast.ClockReset):
        return f"#{s.clock.name}"
    if isinstance(s, ast.Deadline):
        inner = stmt_text(s.statement)
        if isinstance(s.statement, ast.Seq):
            inner = f"({inner})"
        return f"{inner} <{{{expr_text(s.bound)}}}"
    return "<?>"


def transition_label(t: ast.Transition) -> str:
    """`trigger #C <{d} [condition] / action`, as RoboChart diagrams label transitions."""
    parts = []
    if t.trigger is not None:
        parts.append(trigger_text(t.trigger))
    parts += [f"#{c.name}" for c in t.clock_resets]
    if t.deadline is not None:
        parts.append(f"<{{{expr_text(t.deadline)}}}")
    if t.is_else:
        parts.append("[else]")
    elif t.condition is not None:
        parts.append(f"[{expr_text(t.condition)}]")
    if t.action is not None:
        parts.append(f"/ {stmt_text(t.action)}")
    return " ".join(parts)
