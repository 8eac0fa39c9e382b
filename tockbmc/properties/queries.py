"""What a violation (or witness) of each assertion looks like, as a target for the engines.

A `Query` names the machine to unroll and a `target(system, k)`: a formula over
the first `k` steps that holds exactly when those steps end in a violation of
the assertion (or, for `is reachable`, in a witness).  Assertion forms that are
not supported yet raise `NotSupported` with the reason.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import z3

from tockbmc.encodings.system import MachineSystem
from tockbmc.model import ast


class NotSupported(Exception):
    """An assertion tockbmc cannot check yet; the message says why."""


Target = Callable[[MachineSystem, int], z3.BoolRef]


@dataclass(frozen=True)
class Query:
    assertion: ast.Assertion
    machine: ast.StateMachine
    target: Target
    found: str  # verdict when the target is reached: "violated" or "holds"
    not_found: str  # verdict when it is not reached within the bound: "holds" or "unknown"
    describe: str  # what reaching the target means, for the report's last line


def _terminates(system: MachineSystem, k: int) -> z3.BoolRef:
    if k == 0:
        return z3.BoolVal(False)
    ids = [e.index for e in system.automaton.edges if e.kind == "terminate"]
    return z3.Or([system.action(k - 1) == i for i in ids]) if ids else z3.BoolVal(False)


def _timelock(system: MachineSystem, k: int) -> z3.BoolRef:
    return z3.And(z3.Not(system.enabled_internal(k)), z3.Not(system.tock_enabled(k)))


def _reaches(state: str) -> Target:
    def target(system: MachineSystem, k: int) -> z3.BoolRef:
        locs = [loc.index for loc in system.automaton.locations
                if any(a == state or a.endswith("::" + state) or state.endswith("::" + a) for a in loc.active)]
        s = system.state(k)
        return z3.Or([s.loc == i for i in locs]) if locs else z3.BoolVal(False)

    return target


def query(project: ast.Project, a: ast.Assertion) -> Query:
    """The query for assertion `a`, or `NotSupported`."""
    if a.timing == "untimed":
        raise NotSupported("untimed assertions need RoboTool's untimed semantics, which is not built yet")
    if a.semantic_model not in (None, "traces") and a.kind in ("refines", "equals"):
        raise NotSupported(f"the {a.semantic_model} model is not supported")
    if a.subject_is_process or a.other_is_process:
        raise NotSupported("assertions over processes defined in CSP blocks need the CSP parser (next issue)")
    element_name = a.other if a.kind == "reachable" else a.subject
    element = _element(project, element_name or "")
    if not isinstance(element, ast.StateMachine):
        kind = type(element).__name__.lower() if element is not None else "element"
        raise NotSupported(f"checking a {kind} needs the composition of machines, which is not encoded yet; "
                           "state machines are checked on their own")
    if a.kind == "terminates":
        if a.negated:
            return Query(a, element, _terminates, "violated", "holds", f"{element.name} has terminated")
        raise NotSupported("'terminates' needs a proof that termination is reachable; "
                           "a bounded search alone gives no verdict")
    if a.kind == "timelock-free":
        if a.negated:
            return Query(a, element, _timelock, "holds", "unknown", f"{element.name} refuses tock here")
        return Query(a, element, _timelock, "violated", "holds", f"{element.name} refuses tock here")
    if a.kind == "reachable":
        if a.negated:
            return Query(a, element, _reaches(a.subject), "violated", "holds", f"state {a.subject} is entered")
        return Query(a, element, _reaches(a.subject), "holds", "unknown", f"state {a.subject} is entered")
    raise NotSupported(f"'{a.kind}' assertions are not supported yet")


def _element(project: ast.Project, name: str) -> object | None:
    for group in (project.machines, project.controllers, project.modules, project.operations):
        for item in group:
            if item.qname == name or item.name == name or item.qname.endswith("::" + name):
                return item
    for c in project.controllers:
        for m in c.machines:
            if name in (f"{c.qname}::{m.name}", f"{c.name}::{m.name}"):
                return m.machine
    return None
