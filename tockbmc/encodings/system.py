"""The symbolic transition system of one machine, unrolled step by step in Z3.

Step `i` has a state (location, variables, clocks, wait counter) and an action
`act@i`: the index of the automaton edge taken, or `TOCK`.  `step(i)` relates
the states at `i` and `i + 1`.  Names follow pySMT's `at_time` convention:
`x@i` is `x` at step `i`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import z3

from tockbmc.encodings.automaton import Automaton, Edge, Unsupported
from tockbmc.encodings.values import Evaluator, Ranges, Value, domain, equal, fresh, leaves
from tockbmc.model import ast


@dataclass
class StepState:
    loc: z3.ArithRef
    variables: dict[int, Value]
    clocks: dict[str, z3.ArithRef]
    wait: z3.ArithRef


@dataclass
class MachineSystem:
    """The unrolling of one automaton; states and inputs are created on demand."""

    automaton: Automaton
    ranges: Ranges
    settings: dict[str, ast.Expr] = field(default_factory=dict)  # constant name -> value

    def __post_init__(self) -> None:
        m = self.automaton.machine
        self.name = m.name
        self.variables = [v for v in (*m.variables, *m.interface_variables) if not v.constant]
        self.constant_vars = [v for v in (*m.variables, *m.interface_variables) if v.constant]
        self.TOCK = len(self.automaton.edges)
        self.states: list[StepState] = []
        self.actions: list[z3.ArithRef] = []
        self.inputs: list[dict[int, Value]] = []  # per step: event id -> input value
        self.choices: list[z3.ArithRef] = []
        self.side: list[z3.BoolRef] = []
        self.constants: dict[int, Value] = {}
        self.constraints: list[z3.BoolRef] = []  # on constants
        for c in self.constant_vars:
            v = fresh(f"{self.name}::{c.name}", c.type)
            self.constants[id(c)] = v
            given = self.settings.get(c.name)
            expr = given if given is not None else c.initial
            if expr is not None:
                self.constraints.append(equal(v, Evaluator({}, self.constants, self.side).value(expr)))
            else:
                self.constraints += domain(v, c.type, self.ranges, f"{self.name}::{c.name}")
        self._urgent_locs = {e.source for e in self.automaton.edges if e.kind == "call"}
        self._terminated = {loc.index for loc in self.automaton.locations if loc.kind == "terminated"}
        self._waiting = {loc.index for loc in self.automaton.locations if loc.kind == "waiting"}

    # ------------------------------------------------------------ symbols

    def state(self, i: int) -> StepState:
        while len(self.states) <= i:
            k = len(self.states)
            self.states.append(StepState(
                z3.Int(f"{self.name}.loc@{k}"),
                {id(v): fresh(f"{self.name}.{v.name}@{k}", v.type) for v in self.variables},
                {c.name: z3.Int(f"{self.name}.clock.{c.name}@{k}") for c in self.automaton.machine.clocks},
                z3.Int(f"{self.name}.wait@{k}"),
            ))
        return self.states[i]

    def action(self, i: int) -> z3.ArithRef:
        while len(self.actions) <= i:
            self.actions.append(z3.Int(f"{self.name}.act@{len(self.actions)}"))
        return self.actions[i]

    def input(self, i: int, event: ast.Event) -> Value:
        while len(self.inputs) <= i:
            self.inputs.append({})
        table = self.inputs[i]
        if id(event) not in table:
            assert event.type is not None
            table[id(event)] = fresh(f"{self.name}.{event.name}.in@{i}", event.type)
        return table[id(event)]

    def choice(self, i: int) -> z3.ArithRef:
        while len(self.choices) <= i:
            self.choices.append(z3.Int(f"{self.name}.wait_choice@{len(self.choices)}"))
        return self.choices[i]

    def evaluator(self, i: int, extra: dict[int, Value] | None = None) -> Evaluator:
        env = dict(self.state(i).variables)
        if extra:
            env.update(extra)
        return Evaluator(env, self.constants, self.side)

    # ------------------------------------------------------------ formulas

    def init(self) -> z3.BoolRef:
        s = self.state(0)
        cs = [s.loc == 0, s.wait == 0, *self.constraints]
        cs += [c == 0 for c in s.clocks.values()]
        ev = self.evaluator(0)
        for v in self.variables:
            if v.initial is not None:
                cs.append(equal(s.variables[id(v)], ev.value(v.initial)))
            else:
                cs += domain(s.variables[id(v)], v.type, self.ranges, f"{self.name}::{v.name}")
        return z3.And(cs)

    def _guard(self, e: Edge, i: int, env: Evaluator) -> list[z3.BoolRef]:
        cs = [env.scalar(g) for g in e.guard]
        for group in e.negated_guards:
            cs.append(z3.Not(z3.And([env.scalar(g) for g in group])))
        if self.automaton.locations[e.source].kind == "waiting":
            cs.append(self.state(i).wait == 0)
        return cs

    def enabled_internal(self, i: int) -> z3.BoolRef:
        """Some internal step is possible at step i."""
        s = self.state(i)
        env = self.evaluator(i)
        return z3.Or([z3.And(s.loc == e.source, *self._guard(e, i, env))
                      for e in self.automaton.edges if e.kind in ("tau", "wait")] or [z3.BoolVal(False)])

    def tock_enabled(self, i: int) -> z3.BoolRef:
        """Time may pass at step i (maximal progress, urgent calls, termination)."""
        s = self.state(i)
        blocked = [s.loc == loc for loc in sorted(self._urgent_locs | self._terminated)]
        return z3.And(z3.Not(self.enabled_internal(i)), z3.Not(z3.Or(blocked)) if blocked else z3.BoolVal(True))

    def _effects(self, e: Edge, i: int) -> tuple[list[z3.BoolRef], dict[int, Value]]:
        """(what must hold to take `e` at step i, the variables' values after it)."""
        s = self.state(i)
        bound: dict[int, Value] = {}
        cs = [s.loc == e.source]
        if e.kind == "in" and e.event is not None and e.event.type is not None:
            value = self.input(i, e.event)
            cs += domain(value, e.event.type, self.ranges, f"{self.name}::{e.event.name}")
            if e.binds is not None:
                bound[id(e.binds)] = value
            if e.value is not None:
                cs.append(equal(value, self.evaluator(i).value(e.value)))
        cs += self._guard(e, i, self.evaluator(i, bound))
        current = dict(s.variables)
        current.update(bound)
        for a in e.updates:
            new = Evaluator(current, self.constants, self.side).value(a.value)
            key = id(a.variable)
            current[key] = _set_field(current[key], a.fields, new) if a.fields else new
        if e.kind == "wait":
            ev = self.evaluator(i)
            ch = self.choice(i)
            cs += [ch >= ev.scalar(e.wait_low), ch <= ev.scalar(e.wait_high)]  # type: ignore[arg-type]
        return cs, current

    def step(self, i: int) -> z3.BoolRef:
        """One step from i to i + 1: the edge or tock that `act@i` names.

        Next-state values are functions of `act@i` (if-then-else chains over the
        edges that change them), so each step adds one constraint per variable
        rather than a frame per edge.
        """
        s, t = self.state(i), self.state(i + 1)
        act = self.action(i)
        cs = [act >= 0, act <= self.TOCK, z3.Implies(act == self.TOCK, self.tock_enabled(i))]
        next_loc: z3.ArithRef = s.loc
        changes: dict[tuple[int, str], list[tuple[z3.BoolRef, z3.ExprRef]]] = {}
        for e in self.automaton.edges:
            taken = act == e.index
            pre, after = self._effects(e, i)
            cs.append(z3.Implies(taken, z3.And(pre)))
            if e.target != e.source:
                next_loc = z3.If(taken, e.target, next_loc)
            for key, value in after.items():
                old = dict(leaves(s.variables[key]))
                for path, term in leaves(value):
                    if not term.eq(old[path]):
                        changes.setdefault((key, path), []).append((taken, term))
        cs.append(t.loc == next_loc)
        for v in self.variables:
            for path, term in leaves(s.variables[id(v)]):
                new = term
                for taken, value in changes.get((id(v), path), []):
                    new = z3.If(taken, value, new)
                cs.append(dict(leaves(t.variables[id(v)]))[path] == new)
        for name, c in s.clocks.items():
            resets = [act == e.index for e in self.automaton.edges if any(r.name == name for r in e.resets)]
            reset = z3.Or(resets) if resets else z3.BoolVal(False)
            cs.append(t.clocks[name] == z3.If(act == self.TOCK, c + 1, z3.If(reset, 0, c)))
        waiting = z3.Or([s.loc == w for w in self._waiting]) if self._waiting else z3.BoolVal(False)
        starts = [act == e.index for e in self.automaton.edges if e.kind == "wait"]
        start = z3.Or(starts) if starts else z3.BoolVal(False)
        cs.append(t.wait == z3.If(act == self.TOCK, z3.If(waiting, s.wait - 1, s.wait),
                                  z3.If(start, self.choice(i), s.wait)))
        return z3.And(cs)

    def side_constraints(self) -> list[z3.BoolRef]:
        """Constraints added by calls of uninterpreted functions; collect after building formulas."""
        out, self.side[:] = list(self.side), []
        return out


def _set_field(record: Value, path: tuple[str, ...], new: Value) -> Value:
    assert isinstance(record, dict)
    copy = dict(record)
    head, rest = path[0], path[1:]
    copy[head] = _set_field(copy[head], rest, new) if rest else new
    return copy


def check_encodable(machine: ast.StateMachine) -> None:
    """Raise `Unsupported` for string-typed data, which the encoding does not handle."""
    for v in (*machine.variables, *machine.interface_variables):
        if v.type == ast.STRING:
            raise Unsupported(v.pos, "string variables are not encoded yet")
    for e in machine.events:
        if e.type == ast.STRING:
            raise Unsupported(e.pos, "string events are not encoded yet")
