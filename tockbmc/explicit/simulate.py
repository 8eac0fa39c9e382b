"""`tockbmc simulate`: a random run of an element, by the interpreter, shown as a trace."""

from __future__ import annotations

import random
import time

from tockbmc.explicit.engine import python_settings, ranges_dict
from tockbmc.explicit.interpreter import Interpreter
from tockbmc.model import ast
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import Proof, Result, TraceStep, Verdict


def pick(project: ast.Project, name: str | None) -> ast.StateMachine | ast.Controller | ast.Module:
    """The element to run: named, or the first module, else controller, else machine."""
    groups = (project.modules, project.controllers, project.machines)
    if name is None:
        for group in groups:
            if group:
                return group[0]
        raise LookupError("the model has no machine, controller or module")
    for group in groups:
        for item in group:
            if name in (item.name, item.qname) or item.qname.endswith("::" + name):
                return item
    known = [item.name for group in groups for item in group]
    raise LookupError(f"no machine, controller or module named '{name}' (known: {', '.join(known)})")


def run_random(project: ast.Project, name: str | None, steps: int, seed: int, ranges: Ranges,
               settings: dict[str, ast.Expr]) -> Result:
    """Take up to `steps` random steps from a random initial configuration."""
    start = time.perf_counter()
    element = pick(project, name)
    interp = Interpreter(element, ranges_dict(ranges), python_settings(settings))
    rng = random.Random(seed)
    config = rng.choice(interp.initial())
    trace = []
    why = f"{steps} steps taken"
    for i in range(steps):
        options = interp.steps(config)
        if not options:
            why = f"{element.name} has terminated" if interp.terminated(config) else \
                f"{element.name} can do nothing more"
            break
        s = rng.choice(options)
        config = s.target
        states = interp.states(config)
        if s.kind == "internal" or s.event is None:
            trace.append(TraceStep(i + 1, None, "internal", s.note, states, {}))
        else:
            trace.append(TraceStep(i + 1, s.event.name, s.kind, "", states, {}, s.event.channel, s.event.values))
    return Result(assertion=f"simulate {element.name}", text=f"a random run of {element.name} (seed {seed})",
                  verdict=Verdict.HOLDS, bound=None, ranges=ranges.describe(), seconds=time.perf_counter() - start,
                  reason=why, trace=tuple(trace), proof=Proof.TRACE, engine="explicit")
