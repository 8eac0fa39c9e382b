"""Decode a Z3 model of an unrolling into a tock trace in FDR's naming."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import z3

from tockbmc.bmc.result import TraceStep
from tockbmc.encodings.automaton import Edge
from tockbmc.encodings.composition import External
from tockbmc.encodings.system import Move, System
from tockbmc.encodings.values import Value, leaf_type, leaves
from tockbmc.model import ast
from tockbmc.model.numbers import real_text


def scalar_text(term: z3.ExprRef, model: z3.ModelRef, t: ast.Type) -> str:
    v = model.eval(term, model_completion=True)
    if isinstance(t, ast.EnumType):
        i = v.as_long()
        return f"{t.name}::{t.literals[i]}" if 0 <= i < len(t.literals) else str(i)
    if z3.is_true(v):
        return "true"
    if z3.is_false(v):
        return "false"
    if z3.is_rational_value(v) or z3.is_int_value(v):
        return real_text(_fraction(v))
    if z3.is_algebraic_value(v):
        return v.as_decimal(6)
    return str(v)


def python_value(value: Value, model: z3.ModelRef, t: ast.Type) -> object:
    """A value in a model as a Python value: int, Fraction, bool, "Type::LIT", or a dict for a record."""
    if isinstance(t, ast.RecordType):
        assert isinstance(value, dict)
        return {f.name: python_value(value[f.name], model, f.type) for f in t.fields}
    assert not isinstance(value, dict)
    v = model.eval(value, model_completion=True)
    if isinstance(t, ast.EnumType):
        i = v.as_long()
        return f"{t.name}::{t.literals[i]}" if 0 <= i < len(t.literals) else i
    if z3.is_true(v) or z3.is_false(v):
        return z3.is_true(v)
    if z3.is_rational_value(v):
        f = _fraction(v)
        return int(f) if f.denominator == 1 and t != ast.REAL else f
    if z3.is_int_value(v):
        return int(_fraction(v))
    return str(v)


def _fraction(v: z3.RatNumRef | z3.IntNumRef) -> Fraction:
    """A Z3 numeral as a Fraction, exactly, whatever its size (`as_long` refuses more than 4300 digits)."""
    if z3.is_int_value(v):
        return Fraction(int(Decimal(v.as_string())))
    return Fraction(int(Decimal(v.numerator().as_string())), int(Decimal(v.denominator().as_string())))


def initial_choices(system: System, model: z3.ModelRef) -> dict[str, object]:
    """The values a run starts from that the model leaves open: constants and variables without a value."""
    out: dict[str, object] = {}
    for c, comp in enumerate(system.components):
        for v in (*comp.machine.variables, *comp.machine.interface_variables):
            value = system.constants[c].get(id(v))
            if value is not None:
                out[v.name] = python_value(value, model, v.type)
    for base, (t, initial, _c) in system.initial.items():
        if initial is None:
            out[base] = python_value(system.value(base, t, 0), model, t)
    return out


def value_text(value: Value, model: z3.ModelRef, t: ast.Type) -> str:
    """A value as FDR-style text: records as `(f=v, g=w)`."""
    if isinstance(t, ast.RecordType):
        assert isinstance(value, dict)
        return "(" + ", ".join(f"{f.name}={value_text(value[f.name], model, f.type)}" for f in t.fields) + ")"
    assert not isinstance(value, dict)
    return scalar_text(value, model, t)


def _edge_event(system: System, c: int, e: Edge, i: int, model: z3.ModelRef, link_name: str | None) -> str:
    """FDR's name for a machine's visible step: `N::e.in.v`, `N::e.out.v`, `N::opCall.a`, `N::terminate`."""
    if e.kind == "terminate":
        return f"{system.name}::terminate"
    if e.kind == "call":
        assert e.operation is not None
        ev = system.evaluator(c, i)
        args = [value_text(ev.value(a), model, a.type) for a in e.args]
        return f"{system.name}::{e.operation.name}Call" + "".join(f".{a}" for a in args)
    assert e.event is not None
    name = link_name or system.network.visible_name(c, e.event.name)
    direction = "in" if e.kind == "in" else "out"
    if e.event.type is None:
        return f"{name}.{direction}"
    if e.kind == "in":
        value = system.chosen(f"in.{name}", e.event.type, i)
    else:
        assert e.value is not None
        value = system.evaluator(c, i).value(e.value)
    return f"{name}.{direction}.{value_text(value, model, e.event.type)}"


def _move_event(system: System, m: Move, i: int, model: z3.ModelRef) -> str:
    if m.role in ("env-write", "env-read"):
        assert m.link is not None
        end = m.link.sender if m.role == "env-write" else m.link.receiver
        assert isinstance(end, External)
        direction = "in" if m.role == "env-write" else "out"
        if end.event.type is None:
            return f"{end.name}.{direction}"
        value = (system.chosen(f"in.{end.name}", end.event.type, i) if m.role == "env-write"
                 else system.value(f"buffer{m.link.index}.value", end.event.type, i))
        return f"{end.name}.{direction}.{value_text(value, model, end.event.type)}"
    c, e = m.parts[0]
    return _edge_event(system, c, e, i, model, None)


def _note(system: System, m: Move) -> str:
    """What an internal step does, for the dimmed context lines."""
    notes = []
    for c, e in m.parts:
        who = system.components[c].name
        if e.kind == "wait":
            notes.append(f"{who}: wait starts")
        elif m.role == "sync" and e.kind == "out" and e.event is not None:
            assert m.link is not None
            notes.append(f"{who} sends {e.event.name}")
        elif m.role == "write" and e.event is not None:
            notes.append(f"{who}: {e.event.name} into buffer")
        elif m.role == "read" and e.event is not None:
            notes.append(f"{who}: {e.event.name} from buffer")
        elif e.updates:
            notes.append(f"{who}: " + "; ".join(f"{'.'.join([u.variable.name, *u.fields])} := …" for u in e.updates))
        elif e.transition and e.kind != "out":
            notes.append(f"{who}: transition {e.transition}")
        else:
            notes.append(f"{who}: {system.components[c].automaton.locations[e.target].description}")
    return ", ".join(notes)


def _state(system: System, c: int, loc: int) -> str:
    """The innermost active state, or where the machine is when no state is active."""
    location = system.components[c].automaton.locations[loc]
    return location.active[-1] if location.active else location.description


def _changed(system: System, model: z3.ModelRef, i: int, m: Move) -> dict[str, str]:
    """Variables that step i wrote or changed (at step 0 also the declared initial values)."""
    out = {}
    before, after = system.frame(i), system.frame(i + 1)
    written = set(system.effect(m, i).post)
    for base, (t, initial, _c) in system.initial.items():
        for path, _term in leaves(system.value(base, t, 0)):
            name = base + path
            new = model.eval(after[name], model_completion=True)
            old = model.eval(before[name], model_completion=True)
            if (name in written or (i == 0 and initial is not None)
                    or not z3.is_true(model.eval(new == old, model_completion=True))):
                out[name] = scalar_text(after[name], model, leaf_type(t, path))
    return out


def decode(system: System, model: z3.ModelRef, depth: int) -> tuple[TraceStep, ...]:
    """The first `depth` steps of the run that `model` describes."""
    steps = []
    for i in range(depth):
        index = model.eval(system.action(i), model_completion=True).as_long()
        m = system.moves[index]
        states = {comp.name: _state(system, c, model.eval(system.loc(c, i + 1), model_completion=True).as_long())
                  for c, comp in enumerate(system.components)}
        changed = _changed(system, model, i, m)
        if m.kind == "tock":
            steps.append(TraceStep(i + 1, "tock", "tock", "", states, changed, ("tock",)))
        elif m.kind == "internal":
            steps.append(TraceStep(i + 1, None, "internal", _note(system, m), states, changed))
        else:
            transition = next((e.transition for _, e in m.parts if e.transition), "")
            channel, _ = system.label(m)
            values = tuple(python_value(v, model, t) for v, t in system.label_values(m, i))
            steps.append(TraceStep(i + 1, _move_event(system, m, i, model), "event", transition or "",
                                   states, changed, channel, values))
    return tuple(steps)
