"""RoboTool's core assertions: the four it generates for every machine, controller and module.

RoboTool checks each element of a model for deadlock, nondeterminism,
divergence and timelock even when the user writes no assertion; `check`
does the same for a project without assertions (or with `--core`).  Each is
the assertion-language form a user would write (`M is deadlock-free`), so it
means what that form means (`docs/semantics.md`), and a form tockbmc does not
check yet is reported `unsupported`, never skipped.
"""

from __future__ import annotations

from tockbmc.model import ast

CORE_KINDS = ("deadlock-free", "deterministic", "divergence-free", "timelock-free")


def core_assertions(project: ast.Project) -> tuple[ast.Assertion, ...]:
    """For every machine, controller and module (in that order, by name), its four core assertions."""
    elements: list[ast.StateMachine | ast.Controller | ast.Module] = [
        *sorted(project.machines, key=lambda e: e.qname), *sorted(project.controllers, key=lambda e: e.qname),
        *sorted(project.modules, key=lambda e: e.qname)]
    out = []
    for e in elements:
        for kind in CORE_KINDS:
            name = f"{e.name}_{kind.replace('-', '_')}"
            text = f"assertion {name}: {e.name} is {kind}."
            out.append(ast.Assertion(name, kind, e.qname, False, e.pos, text))
    return tuple(out)
