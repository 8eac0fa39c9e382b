"""Decode a Z3 model of an unrolling into a tock trace in FDR's naming."""

from __future__ import annotations

from fractions import Fraction

import z3

from tockbmc.bmc.result import TraceStep
from tockbmc.encodings.automaton import Edge
from tockbmc.encodings.system import MachineSystem
from tockbmc.encodings.values import Value, leaves
from tockbmc.model import ast


def scalar_text(term: z3.ExprRef, model: z3.ModelRef, t: ast.Type) -> str:
    v = model.eval(term, model_completion=True)
    if isinstance(t, ast.EnumType):
        i = v.as_long()
        return f"{t.name}::{t.literals[i]}" if 0 <= i < len(t.literals) else str(i)
    if z3.is_true(v):
        return "true"
    if z3.is_false(v):
        return "false"
    if z3.is_rational_value(v):
        f = Fraction(v.numerator_as_long(), v.denominator_as_long())
        return str(f.numerator) if f.denominator == 1 else str(float(f)) if Fraction(float(f)) == f else str(f)
    if z3.is_algebraic_value(v):
        return v.as_decimal(6)
    return str(v)


def value_text(value: Value, model: z3.ModelRef, t: ast.Type) -> str:
    """A value as FDR-style text: records as `(f=v, g=w)`."""
    if isinstance(t, ast.RecordType):
        assert isinstance(value, dict)
        return "(" + ", ".join(f"{f.name}={value_text(value[f.name], model, f.type)}" for f in t.fields) + ")"
    assert not isinstance(value, dict)
    return scalar_text(value, model, t)


def _event_name(system: MachineSystem, e: Edge, i: int, model: z3.ModelRef) -> str:
    m = system.name
    if e.kind == "terminate":
        return f"{m}::terminate"
    if e.kind == "call":
        assert e.operation is not None
        ev = system.evaluator(i)
        args = [value_text(ev.value(a), model, a.type) for a in e.args]
        return f"{m}::{e.operation.name}Call" + "".join(f".{a}" for a in args)
    assert e.event is not None
    direction = "in" if e.kind == "in" else "out"
    name = f"{m}::{e.event.name}.{direction}"
    if e.event.type is None:
        return name
    if e.kind == "in":
        value = system.input(i, e.event)
    else:
        assert e.value is not None
        value = system.evaluator(i).value(e.value)
    return f"{name}.{value_text(value, model, e.event.type)}"


def _note(system: MachineSystem, e: Edge) -> str:
    target = system.automaton.locations[e.target]
    if e.kind == "wait":
        return "wait starts"
    if e.updates:
        return "; ".join(f"{'.'.join([u.variable.name, *u.fields])} := …" for u in e.updates)
    if e.transition:
        return f"transition {e.transition}"
    return target.description


def decode(system: MachineSystem, model: z3.ModelRef, depth: int) -> tuple[TraceStep, ...]:
    """The first `depth` steps of the run that `model` describes."""
    steps = []
    locations = system.automaton.locations
    for i in range(depth):
        act = model.eval(system.action(i), model_completion=True).as_long()
        after = system.state(i + 1)
        loc = model.eval(after.loc, model_completion=True).as_long()
        active = locations[loc].active
        state = active[-1] if active else locations[loc].description
        changed = {}
        before = system.state(i)
        for v in system.variables:
            for path, term in leaves(after.variables[id(v)], v.name):
                old = dict(leaves(before.variables[id(v)], v.name))[path]
                new_val = model.eval(term, model_completion=True)
                if not model.eval(new_val == model.eval(old, model_completion=True), model_completion=True) or i == 0:
                    leaf_type = _leaf_type(v.type, path[len(v.name):])
                    if i > 0 or v.initial is not None:
                        changed[path] = scalar_text(term, model, leaf_type)
        if act == system.TOCK:
            steps.append(TraceStep(i + 1, "tock", "tock", "", {system.name: state}, changed))
            continue
        e = system.automaton.edges[act]
        if e.kind in ("tau", "wait"):
            steps.append(TraceStep(i + 1, None, "internal", _note(system, e), {system.name: state}, changed))
        else:
            steps.append(TraceStep(i + 1, _event_name(system, e, i, model), "event", e.transition or "",
                                   {system.name: state}, changed))
    return tuple(steps)


def _leaf_type(t: ast.Type, path: str) -> ast.Type:
    for part in [p for p in path.split(".") if p]:
        assert isinstance(t, ast.RecordType)
        ft = t.field_type(part)
        assert ft is not None
        t = ft
    return t
