"""Which `during` actions of composite states both engines run (docs/semantics.md §4.1).

A composite state's during action starts once its first child has been entered and then runs
beside the children, which go on moving among themselves, as a second thread of control sharing
the machine's variables; a transition that leaves the state abandons it.  Both engines encode it
(BMC as a product of the two threads' locations, the interpreter as a second stack of
activations), within the limits that `composite_during_problem` checks, one rule list for both,
so that they refuse the same models with the same reason.
"""

from __future__ import annotations

from collections.abc import Callable

from tockbmc.model import ast

Resolve = Callable[[ast.OperationCall], "ast.OperationDef | None"]


def composite_durings(b: ast.Behaviour) -> list[ast.Node]:
    """The composite states of `b` that have a during action."""
    return [n for n in b.nodes if n.composite and n.during is not None]


def composite_during_problem(b: ast.Behaviour, resolve: Resolve,
                             in_operation: bool) -> tuple[ast.Pos, str] | None:
    """Why a composite state's during action in `b` is not run, or None if every one is.

    `resolve` gives the definition a call runs (None for a platform operation); `in_operation`
    says that `b` is an operation's body, run where it is called."""
    for n in composite_durings(b):
        assert n.during is not None
        pos = n.during.pos
        if in_operation:
            return pos, "a during action of a composite state inside an operation is not encoded yet"
        inside = {x.path for x in b.nodes if x.path.startswith(n.path + "::")}
        for x in b.nodes:
            if x.path in inside and x.composite and x.during is not None:
                return pos, (f"a during action of a composite state ({x.path}) inside a composite state with one "
                             f"({n.path}) is not encoded yet")
        for t in b.transitions:
            target = b.node(t.target)
            if t.target in inside and target.kind == "junction" and (
                    t.source not in inside or b.node(t.source).kind == "initial"):
                return pos, (f"a composite state with a during action ({n.path}) entered through a junction "
                             f"(transition {t.name}) is not encoded yet")
        problem = _thread_problem(n.during, resolve, ())
        if problem is not None:
            return problem
    return None


def _thread_problem(s: ast.Stmt, resolve: Resolve, calls: tuple[str, ...]) -> tuple[ast.Pos, str] | None:
    """What a composite state's during action `s` does that its thread does not run: a statement
    deadline, or an operation it calls with a deadline or a composite state's during action."""
    for st in ast.statements(s):
        if isinstance(st, ast.Deadline):
            return st.pos, "a deadline inside a composite state's during action is not encoded yet"
        if not isinstance(st, ast.OperationCall):
            continue
        op = resolve(st)
        if op is None or op.qname in calls:
            continue  # a platform operation, or a recursive call (refused where operations are inlined)
        for t in op.transitions:
            if t.deadline is not None:
                return t.deadline.pos, (f"operation {op.name}, called by a composite state's during action, has a "
                                        "deadline, which is not encoded there yet")
        for x in op.nodes:
            if x.composite and x.during is not None:
                return st.pos, (f"operation {op.name}, called by a composite state's during action, has a composite "
                                "state with a during action of its own, which is not encoded yet")
        for body in [*(x.entry for x in op.nodes), *(x.during for x in op.nodes), *(x.exit for x in op.nodes),
                     *(t.action for t in op.transitions)]:
            if body is not None:
                problem = _thread_problem(body, resolve, (*calls, op.qname))
                if problem is not None:
                    return problem
    return None
