"""RoboTool's memory model, where it shapes the model itself: an output reads the shared variables
it sends before it is offered (docs/semantics.md §5.5).

In RoboTool's generated CSP a machine keeps its own copy of each variable it requires, which the
controller's memory updates when another machine writes (`set_EXT_x`); the engines build those
copies (`encodings.composition.Copies`, the interpreter's `_Copies`).  An output `e!x` is
`get_x?x -> e!x`: the copy is read once, by a hidden step, and the event offers that value until it
happens, even if the copy is updated meanwhile.  So each output whose value reads a variable the
behaviour requires becomes `e_value = x; e!e_value`, with a variable of the behaviour's own that
both engines read as any other.
"""

from __future__ import annotations

import dataclasses

from tockbmc.model import ast
from tockbmc.model.instantiation import replaced
from tockbmc.model.readings import default_value


def read_before_sending(project: ast.Project) -> ast.Project:
    """The project with every output that sends a value read from a required variable split into
    the read (an assignment to a fresh variable of the behaviour's) and the output of that value."""
    new: dict[int, object] = {}
    for b in [x for x in ast.parts(project) if isinstance(x, ast.Behaviour)]:
        own = (*b.provided_interfaces, *b.used_interfaces)
        required = {id(v) for v in b.interface_variables if not v.constant and not ast.in_interfaces(v, own)}
        if not required:
            continue
        taken = {v.name for v in (*b.variables, *b.interface_variables)} | {e.name for e in b.events}
        added: list[ast.Variable] = []
        for st in ast.parts(b.nodes, b.transitions):
            if not (isinstance(st, ast.Send) and st.value is not None and st.event.type is not None
                    and _reads(st.value, required)):
                continue
            name = f"{st.event.name}_value"
            while name in taken:
                name += "_"
            taken.add(name)
            v = ast.Variable(name, st.event.type, False, b.qname, st.pos, default_value(st.event.type, st.pos))
            added.append(v)
            new[id(st)] = ast.Seq(st.pos, (ast.Assign(st.pos, v, (), st.value),
                                           ast.Send(st.pos, st.event, ast.VarRef(st.event.type, st.pos, v))))
        if added:
            new[id(b)] = dataclasses.replace(b, variables=(*b.variables, *added))
    return replaced(project, new, {}) if new else project


def _reads(e: ast.Expr, variables: set[int]) -> bool:
    return any(isinstance(x, ast.VarRef) and id(x.variable) in variables for x in ast.subexpressions((e,)))
