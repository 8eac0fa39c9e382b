"""The witness of a search: a Z3 model of an unrolling decoded into a tock trace in FDR's naming."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import z3

from tockbmc.encodings import names
from tockbmc.encodings.automaton import Edge
from tockbmc.encodings.composition import External
from tockbmc.encodings.system import Move, TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.encodings.values import Value, leaf_type, leaves, parts
from tockbmc.model import ast
from tockbmc.model.config import declaration_key, instance_key
from tockbmc.model.data import Product, Variant, text_of
from tockbmc.model.errors import Unsupported
from tockbmc.model.numbers import real_text
from tockbmc.model.result import TraceStep
from tockbmc.properties.process import MonitorExtension


def scalar_text(term: z3.ExprRef, model: z3.ModelRef, t: ast.Type) -> str:
    v = model.eval(term, model_completion=True)
    if isinstance(t, (ast.SeqType, ast.SetType)) or (isinstance(t, ast.EnumType) and t.params):
        return text_of(t, term_value(v, t))
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
    if parts(t):
        assert isinstance(value, dict)
        return {f: python_value(value[f], model, ft) for f, ft in parts(t)}
    assert not isinstance(value, dict)
    v = model.eval(value, model_completion=True)
    if isinstance(t, (ast.SeqType, ast.SetType)) or (isinstance(t, ast.EnumType) and t.params):
        return term_value(v, t)
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


def term_value(v: z3.ExprRef, t: ast.Type) -> object:
    """A value term of a model (`model.eval`'s) as a Python value: a tuple for a sequence, a
    frozenset for a set, a tuple (of `Product`) for a tuple, a dict for a record."""
    if isinstance(t, ast.SeqType):
        items: list[object] = []
        stack = [v]
        while stack:
            x = stack.pop()
            if z3.is_app_of(x, z3.Z3_OP_SEQ_CONCAT):
                stack.extend(reversed(x.children()))
            elif z3.is_app_of(x, z3.Z3_OP_SEQ_UNIT):
                items.append(term_value(x.arg(0), t.element))
            elif not z3.is_app_of(x, z3.Z3_OP_SEQ_EMPTY):
                raise Unsupported(ast.Pos("<model>", 1, 1), f"a sequence value Z3 gave as {x}")
        return tuple(items)
    if isinstance(t, ast.SetType):
        return frozenset(_members(v, t))
    if parts(t):
        sort = v.sort()
        assert isinstance(sort, z3.DatatypeSortRef)
        fields = {f: term_value(v.arg(i), ft) for i, (f, ft) in enumerate(parts(t))}
        return fields if isinstance(t, ast.RecordType) else Product(fields.values())
    if isinstance(t, ast.EnumType) and t.params:
        sort = v.sort()
        assert isinstance(sort, z3.DatatypeSortRef)
        for i, lit in enumerate(t.literals):
            if v.decl() == sort.constructor(i):
                name = f"{t.name}::{lit}"
                ps = t.params[i]
                return Variant((name, *(term_value(v.arg(j), pt) for j, pt in enumerate(ps)))) if ps else name
        raise Unsupported(ast.Pos("<model>", 1, 1), f"a value Z3 gave as {v}")
    if isinstance(t, ast.EnumType):
        i = v.as_long()  # type: ignore[attr-defined]
        return f"{t.name}::{t.literals[i]}" if 0 <= i < len(t.literals) else i
    if z3.is_true(v) or z3.is_false(v):
        return z3.is_true(v)
    if z3.is_rational_value(v) or z3.is_int_value(v):
        f = _fraction(v)  # type: ignore[arg-type]
        return int(f) if f.denominator == 1 and t != ast.REAL else f
    raise Unsupported(ast.Pos("<model>", 1, 1), f"a value Z3 gave as {v}")


def _members(v: z3.ExprRef, t: ast.SetType) -> list[object]:
    """The members of a finite set value (a constant array with stores, or a lambda over equalities).
    A set of an enumeration or of booleans is read value by value: Z3 may give it as a complement
    (`Store(K(Bool, True), True, False)` for `{false}`), and its members are its type's values in it."""
    finite = _finite_values(t.element)
    if finite is not None:
        return [term_value(x, t.element) for x in finite if z3.is_true(z3.simplify(z3.Select(v, x)))]
    out: list[object] = []
    x = v
    while z3.is_app_of(x, z3.Z3_OP_STORE):
        if z3.is_true(x.arg(2)):
            out.append(term_value(x.arg(1), t.element))
        x = x.arg(0)
    if z3.is_app_of(x, z3.Z3_OP_CONST_ARRAY) and z3.is_false(x.arg(0)):
        return out
    if z3.is_quantifier(x) and x.is_lambda():
        body = x.body()
        disjuncts = body.children() if z3.is_or(body) else [body]
        for d in disjuncts:
            if z3.is_false(d):
                continue
            if z3.is_eq(d) and z3.is_var(d.arg(0)):
                out.append(term_value(d.arg(1), t.element))
            elif z3.is_eq(d) and z3.is_var(d.arg(1)):
                out.append(term_value(d.arg(0), t.element))
            else:
                raise Unsupported(ast.Pos("<model>", 1, 1), f"a set value Z3 gave as {v}")
        return out
    raise Unsupported(ast.Pos("<model>", 1, 1), f"a set value Z3 gave as {v} (not a finite set)")


def _finite_values(t: ast.Type) -> list[z3.ExprRef] | None:
    """Every value of a type with finitely many, as terms (an enumeration's literals are 0, 1, …)."""
    if isinstance(t, ast.EnumType) and not t.params:
        return [z3.IntVal(i) for i in range(len(t.literals))]
    if t == ast.BOOLEAN:
        return [z3.BoolVal(False), z3.BoolVal(True)]
    return None


def _fraction(v: z3.RatNumRef | z3.IntNumRef) -> Fraction:
    """A Z3 numeral as a Fraction, exactly, whatever its size (`as_long` refuses more than 4300 digits)."""
    if z3.is_int_value(v):
        return Fraction(int(Decimal(v.as_string())))
    return Fraction(int(Decimal(v.numerator().as_string())), int(Decimal(v.denominator().as_string())))


def initial_choices(u: Unroller, model: z3.ModelRef) -> dict[str, object]:
    """The values a run starts from that the model leaves open: constants and variables without a value."""
    system = u.system
    out: dict[str, object] = {}
    for c, comp in enumerate(system.components):
        inlined = [v for _, v in comp.automaton.extra_variables]
        for v in (*comp.machine.variables, *comp.machine.interface_variables, *inlined):
            value = system.constants[c].get(id(v))
            if value is not None:  # keyed by declaration, as the configuration keys constants
                out[declaration_key(v)] = python_value(value, model, v.type)
                if comp.instance and system.shared_key(c, v) is None:
                    out[instance_key(comp.instance, v)] = out[declaration_key(v)]  # this instance's own
    for base, (t, initial, c, key) in system.initial.items():
        if initial is None:
            out[base] = python_value(u.value_at(system.value(base, t), 0), model, t)
            # Also under the names the interpreter looks a variable up by: the instance's own key
            # (a machine inside a module's controller is `ForagingC::DTP` here, `ForagingC.DTP`
            # there), and the declaration's.  Unpinned, the interpreter tries every value of each
            # (234,375 starts for robocert-evaluation's Foraging, past the replay's limit).
            instance = system.components[c].instance
            if instance:
                out.setdefault(f"{'::'.join(instance)}/{key}", out[base])
            out.setdefault(key, out[base])
    return out


def value_text(value: Value, model: z3.ModelRef, t: ast.Type) -> str:
    """A value as FDR-style text: records as `(f=v, g=w)`."""
    if isinstance(t, ast.RecordType):
        assert isinstance(value, dict)
        return "(" + ", ".join(f"{f.name}={value_text(value[f.name], model, f.type)}" for f in t.fields) + ")"
    if isinstance(t, ast.ProductType):
        assert isinstance(value, dict)
        return "(" + ", ".join(value_text(value[f], model, ft) for f, ft in parts(t)) + ")"
    assert not isinstance(value, dict)
    return scalar_text(value, model, t)


def _edge_event(u: Unroller, c: int, e: Edge, i: int, model: z3.ModelRef, link_name: str | None) -> str:
    """FDR's name for a machine's visible step: `N::e.in.v`, `N::e.out.v`, `N::opCall.a`, `N::terminate`."""
    system = u.system
    if e.kind == "terminate":
        return f"{system.name}::terminate"
    if e.kind == "call":
        assert e.operation is not None
        ev = system.evaluator(c)
        args = [value_text(u.value_at(ev.value(a), i), model, a.type) for a in e.args]
        return f"{system.name}::{e.operation.name}Call" + "".join(f".{a}" for a in args)
    assert e.event is not None
    name = link_name or system.network.visible_name(c, e.event.name)
    direction = "in" if e.kind == "in" else "out"
    if e.event.type is None:
        return f"{name}.{direction}"
    if e.kind == "in":
        value = u.input(names.input_value(name), i)
    else:
        assert e.value is not None
        value = u.value_at(system.evaluator(c).value(e.value), i)
    return f"{name}.{direction}.{value_text(value, model, e.event.type)}"


def _move_event(u: Unroller, m: Move, i: int, model: z3.ModelRef) -> str:
    if m.role in ("env-write", "env-read"):
        assert m.link is not None
        end = m.link.sender if m.role == "env-write" else m.link.receiver
        assert isinstance(end, External)
        direction = "in" if m.role == "env-write" else "out"
        if end.event.type is None:
            return f"{end.name}.{direction}"
        value = (u.input(names.input_value(end.name), i) if m.role == "env-write"
                 else u.value_at(u.system.value(names.buffer_value(m.link.index), end.event.type), i))
        return f"{end.name}.{direction}.{value_text(value, model, end.event.type)}"
    if m.role in ("set", "env-set"):  # RoboTool's memory model: `C::set_x.v`, `C::set_EXT_x.v`
        assert m.copies is not None
        name = m.copies.written if m.role == "set" else m.copies.external
        t = m.copies.variable.type
        return f"{name}.{value_text(u.value_at(u.system.written_value(m), i), model, t)}"
    c, e = m.parts[0]
    return _edge_event(u, c, e, i, model, None)


def _note(u: Unroller, m: Move) -> str:
    """What an internal step does, for the dimmed context lines."""
    system = u.system
    if m.role == "terminate":  # a module's: hidden, so an internal step (docs/semantics.md §5.6)
        return f"{system.name} terminates"
    if m.role == "pass":  # RoboTool's memory model: the memory passes a write on to one copy
        assert m.copies is not None
        reader = system.components[m.copies.readers[m.reader]].name
        return f"{m.copies.variable.name} passed on to {reader}'s copy"
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


def _state(u: Unroller, c: int, loc: int) -> str:
    """The innermost active state, or where the machine is when no state is active."""
    location = u.system.components[c].automaton.locations[loc]
    return location.active[-1] if location.active else location.description


def _changed(u: Unroller, model: z3.ModelRef, i: int, m: Move) -> dict[str, str]:
    """Variables that step i wrote or changed (at step 0 every variable's start: its declared initial
    value, or the value the run chose for one that starts anywhere)."""
    system = u.system
    out = {}
    before, after = u.frame(i), u.frame(i + 1)
    written = set(system.effect(m).post)
    for base, (t, _initial, _c, _key) in system.initial.items():
        for path, _term in leaves(system.value(base, t)):
            name = base + path
            new = model.eval(after[name], model_completion=True)
            old = model.eval(before[name], model_completion=True)
            if (name in written or i == 0
                    or not z3.is_true(model.eval(new == old, model_completion=True))):
                out[name.replace("#", "")] = scalar_text(after[name], model, leaf_type(t, path))  # `M.loc#`: names.variable
    return out


def _source(m: Move) -> str:
    """Where the model says what the move does: its first part's statement or transition, or its connection."""
    for _c, e in m.parts:
        if e.pos is not None:
            return str(e.pos)
    return str(m.link.pos) if m.link is not None and m.link.pos is not None else ""


def decode(u: Unroller, model: z3.ModelRef, depth: int) -> tuple[TraceStep, ...]:
    """The first `depth` steps of the run that `model` describes."""
    system = u.system
    steps = []
    for i in range(depth):
        index = model.eval(u.action(i), model_completion=True).as_long()
        m = system.moves[index]
        after = u.frame(i + 1)
        states = {comp.name: _state(u, c, model.eval(after[names.location(comp.name)], model_completion=True).as_long())
                  for c, comp in enumerate(system.components)}
        changed = _changed(u, model, i, m)
        if m.kind == "tock":
            steps.append(TraceStep(i + 1, "tock", "tock", "", states, changed, ("tock",)))
        elif m.kind == "internal":
            steps.append(TraceStep(i + 1, None, "internal", _note(u, m), states, changed, source=_source(m)))
        else:
            transition = next((e.transition for _, e in m.parts if e.transition), "")
            channel, _ = system.label(m)
            values = tuple(python_value(u.value_at(v, i), model, t) for v, t in system.label_values(m))
            steps.append(TraceStep(i + 1, _move_event(u, m, i, model), "event", transition or "",
                                   states, changed, channel, values, source=_source(m)))
    return tuple(steps)


def free_fields(u: Unroller, model: z3.ModelRef, depth: int, target: z3.BoolRef,
                timeout_ms: int = 2000) -> dict[int, tuple[str, ...]]:
    """For each step of the run that takes an input, the fields whose value does not matter: with
    every other choice of the run kept, every value of the field's type and range still ends in
    the target.

    With the moves fixed, a configuration is a function of the one before and of the step's
    inputs, so each field is asked about with the configurations computed from it by
    substitution: is there a value of it for which some step is disabled or the target missed?
    Only runs whose extensions define their next state by one equality (a specification
    monitor) are analysed; a field whose question Z3 does not answer in time is not marked.
    """
    system = u.system
    if any(not isinstance(ext, MonitorExtension) for ext in system.extensions):
        return {}
    moves = [system.moves[model.eval(u.action(j), model_completion=True).as_long()] for j in range(depth)]
    start = {n: model.eval(term, model_completion=True) for n, term in u.frame(0).items()}
    fixed: list[list[tuple[z3.ExprRef, z3.ExprRef]]] = []  # per step: template input leaf -> its value
    fixed_constants: list[tuple[z3.ExprRef, z3.ExprRef]] = []
    for j in range(depth):
        pairs = []
        for name, (_t, value) in system.inputs.items():
            for (_p, template), (_q, actual) in zip(leaves(value), leaves(u.input(name, j)), strict=True):
                pairs.append((template, model.eval(actual, model_completion=True)))
        fixed.append(pairs)
    for c in system.constants.values():  # the run's constants, as the model chose them
        for value in c.values():
            for _p, term in leaves(value):
                fixed_constants.append((term, model.eval(term, model_completion=True)))
    fixed = [pairs + fixed_constants for pairs in fixed]
    nexts = {n: ext.step(system).arg(1) for ext in system.extensions for n in ext.slots()}
    out: dict[int, tuple[str, ...]] = {}
    for i, m in enumerate(moves):
        chosen = {c.get_id() for c in system.effect(m).chosen}
        if not chosen:
            continue
        free = []
        for _name, (_t, value) in system.inputs.items():
            for path, template in leaves(value):
                if template.get_id() in chosen and _free(system, moves, start, fixed, nexts, target, i, template,
                                                         depth, timeout_ms):
                    free.append(path.lstrip("."))
        if free:
            out[i] = tuple(free)
    return out


def _free(system: TransitionSystem, moves: list[Move], start: dict[str, z3.ExprRef],
          fixed: list[list[tuple[z3.ExprRef, z3.ExprRef]]], nexts: dict[str, z3.ExprRef], target: z3.BoolRef,
          i: int, leaf: z3.ExprRef, depth: int, timeout_ms: int) -> bool:
    v = z3.FreshConst(leaf.sort(), "field")
    frame = dict(start)
    domain: list[z3.BoolRef] = []
    path: list[z3.BoolRef] = []
    for j, m in enumerate(moves):
        inputs = [(t, v if j == i and t.eq(leaf) else x) for t, x in fixed[j]]
        pairs = [(system.cur[n], frame[n]) for n in system.sorts] + inputs + [(system.act, z3.IntVal(m.index))]
        eff = system.effect(m)
        path += [z3.substitute(c, *pairs) for c in eff.enabled]
        (domain if j == i else path).extend(z3.substitute(c, *pairs) for c in eff.choose)
        new = dict(frame)
        for n, term in eff.post.items():
            new[n] = z3.simplify(z3.substitute(term, *pairs))
        for n, term in nexts.items():
            new[n] = z3.simplify(z3.substitute(term, *pairs))
        frame = new
    end = [(system.cur[n], frame[n]) for n in system.sorts]
    path.append(z3.substitute(target, *end))
    solver = z3.Solver()
    solver.set("timeout", timeout_ms)
    solver.add(*domain)
    taken = dict((t.get_id(), x) for t, x in fixed[i])[leaf.get_id()]
    if solver.check(v != taken) != z3.sat:  # one value only (a pinned range): nothing to tell
        return False
    solver.add(z3.Not(z3.And(path)))
    return solver.check() == z3.unsat
