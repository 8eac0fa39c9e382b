"""RoboTool's untimed semantics of a model, as a rewriting of the model (docs/semantics.md §7.11).

RoboTool's untimed translation (`csp-gen/defs`, docs/robotool-evidence.md §1.1) has no `tock`
and no clocks: `wait(e)` and a clock reset `#C` become `SKIP`, deadlines disappear, and a
transition condition that reads a clock (`since(C) >= e`, `sinceEntry(S) > e`, or a larger
condition with such a comparison in it) becomes `true` as a whole.  Both engines run the
rewritten model with `tock` never possible (the encoding's `Network.timed`, the interpreter's
`timed`), so the rules are written once, here.

A clock read anywhere else (in an action, a trigger value or an `if`) has no evidence of what
RoboTool does with it: such models are `Unsupported` untimed.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TypeVar, cast

from tockbmc.model import ast
from tockbmc.model.errors import Unsupported

Element = ast.StateMachine | ast.Controller | ast.Module
B = TypeVar("B", bound=ast.Behaviour)


def _reads_clock(x: object) -> ast.Expr | None:
    return next((e for e in ast.subexpressions(x) if isinstance(e, (ast.Since, ast.SinceEntry))), None)


def _refuse(e: ast.Expr, where: str) -> Unsupported:
    return Unsupported(e.pos, f"a clock read {where} in an untimed assertion: RoboTool's untimed semantics is "
                              "evidenced only for a transition condition that reads a clock (it becomes true)")


class _Untimed:
    def __init__(self) -> None:
        self.done: dict[int, ast.Behaviour] = {}

    def behaviour(self, b: B) -> B:
        key = id(b)
        if key not in self.done:
            nodes = tuple(replace(n, entry=self.optional(n.entry), during=self.optional(n.during),
                                  exit=self.optional(n.exit)) for n in b.nodes)
            self.done[key] = replace(b, nodes=nodes, transitions=tuple(self.transition(t) for t in b.transitions))
        return cast("B", self.done[key])

    def transition(self, t: ast.Transition) -> ast.Transition:
        condition = t.condition
        clock = _reads_clock(condition) if condition is not None else None
        if condition is not None and clock is not None:
            condition = None  # RoboTool: `(true)&(…)`, whatever else the condition reads
        if t.trigger is not None:
            clock = _reads_clock(t.trigger.value)
            if clock is not None:
                raise _refuse(clock, "in a trigger")
        return replace(t, condition=condition, deadline=None, clock_resets=(), action=self.optional(t.action))

    def optional(self, s: ast.Stmt | None) -> ast.Stmt | None:
        return None if s is None else self.stmt(s)

    def stmt(self, s: ast.Stmt) -> ast.Stmt:
        if isinstance(s, (ast.Wait, ast.ClockReset)):
            return ast.Skip(s.pos)
        if isinstance(s, ast.Deadline):
            return self.stmt(s.statement)
        if isinstance(s, ast.Seq):
            return replace(s, statements=tuple(self.stmt(x) for x in s.statements))
        if isinstance(s, ast.If):
            clock = _reads_clock(s.condition)
            if clock is not None:
                raise _refuse(clock, "in an 'if' condition")
            return replace(s, then=self.stmt(s.then), otherwise=self.stmt(s.otherwise))
        clock = _reads_clock(s)
        if clock is not None:
            raise _refuse(clock, "in an action")
        if isinstance(s, ast.OperationCall) and isinstance(s.operation, ast.OperationDef):
            return replace(s, operation=self.behaviour(s.operation))
        return s

    def controller(self, c: ast.Controller) -> ast.Controller:
        machines = tuple(replace(m, machine=self.behaviour(m.machine)) for m in c.machines)
        operations = tuple(replace(o, operation=self.behaviour(o.operation)) for o in c.operations)
        return replace(c, machines=machines, operations=operations)

    def element(self, e: Element) -> Element:
        if isinstance(e, ast.StateMachine):
            return self.behaviour(e)
        if isinstance(e, ast.Controller):
            return self.controller(e)
        return replace(e, controllers=tuple(replace(c, controller=self.controller(c.controller))
                                            for c in e.controllers))


def untimed(element: Element, defined: dict[str, ast.OperationDef] | None = None
            ) -> tuple[Element, dict[str, ast.OperationDef]]:
    """The element (and the operations its controller defines) as RoboTool's untimed semantics
    reads it; raises `Unsupported` for a clock read whose untimed meaning is not evidenced."""
    u = _Untimed()
    out = u.element(element)
    return out, {k: u.behaviour(d) for k, d in (defined or {}).items()}
