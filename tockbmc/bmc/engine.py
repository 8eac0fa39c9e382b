"""Incremental bounded model checking: one solver, the unrolling only ever extended.

At each depth k the target is asked under an activation literal, so the
first satisfiable depth gives a shortest counterexample; the step k → k+1 is
then added for good.  Engines never print: they return an `Outcome`.
"""

from __future__ import annotations

from dataclasses import dataclass

import z3

from tockbmc.encodings.system import MachineSystem
from tockbmc.properties.queries import Target


@dataclass
class Outcome:
    status: str  # "found" | "not found" | "unknown"
    depth: int  # steps in the trace when found; the bound searched otherwise
    model: z3.ModelRef | None = None
    reason: str | None = None


def bmc(system: MachineSystem, target: Target, bound: int, timeout: float | None = None) -> Outcome:
    """Search runs of up to `bound` steps for one that reaches `target`."""
    solver = z3.Solver()
    if timeout is not None:
        solver.set("timeout", max(1, int(timeout * 1000)))
    solver.add(system.init())
    solver.add(system.side_constraints())
    for k in range(bound + 1):
        goal = target(system, k)
        solver.add(system.side_constraints())
        literal = z3.Bool(f"target@{k}")
        solver.add(z3.Implies(literal, goal))
        result = solver.check(literal)
        if result == z3.sat:
            return Outcome("found", k, solver.model())
        if result == z3.unknown:
            return Outcome("unknown", k, None, f"Z3 gave up at depth {k}: {solver.reason_unknown()}")
        if k < bound:
            solver.add(system.step(k))
            solver.add(system.side_constraints())
    return Outcome("not found", bound)
