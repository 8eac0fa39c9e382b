"""`tockbmc simulate`: a random run of an element, by the interpreter, shown as a trace."""

from __future__ import annotations

import random
import time
from fractions import Fraction

from tockbmc.explicit.engine import python_settings, ranges_dict
from tockbmc.explicit.interpreter import Interpreter, Sampler, Step
from tockbmc.model import ast
from tockbmc.model.diagnostics import suggestion
from tockbmc.model.numbers import real_text
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
    raise LookupError(f"no machine, controller or module named '{name}'{suggestion(name, known)} "
                      f"(known: {', '.join(known)})")


# Where a type with no range takes its values in a random run: RoboTool's default ranges, and
# 0..2 for given types (README, "simulate").
WINDOWS = {"core_int": (Fraction(-2), Fraction(2)), "core_nat": (Fraction(0), Fraction(2)),
           "core_real": (Fraction(-2), Fraction(2)), "given": (Fraction(0), Fraction(2))}


def run_random(project: ast.Project, name: str | None, steps: int, seed: int, ranges: Ranges,
               settings: dict[str, ast.Expr]) -> Result:
    """Take up to `steps` random steps from a random initial configuration.

    Values are drawn as the run needs them (`Sampler`), so that the run takes memory and time in
    proportion to its steps, whatever the number of values the element could take.
    """
    start = time.perf_counter()
    element = pick(project, name)
    rng = random.Random(seed)
    sampler = Sampler(rng, WINDOWS)
    interp = Interpreter(element, ranges_dict(ranges), python_settings(settings), sampler=sampler)
    trace = []
    initial = interp.initial()
    if not initial:
        steps = 0
        why = f"{element.name} has no initial configuration: no choice of initial values fits their types"
    else:
        config = rng.choice(initial)
        why = f"{steps} steps taken"
    for i in range(steps):
        options = interp.steps(config)
        if not options:
            why = f"{element.name} has terminated" if interp.terminated(config) else \
                f"{element.name} can do nothing more"
            break
        s = _pick(options, rng)
        config = s.target
        states = interp.states(config)
        if s.kind == "internal" or s.event is None:
            trace.append(TraceStep(i + 1, None, "internal", s.note, states, {}))
        else:
            trace.append(TraceStep(i + 1, s.event.name, s.kind, "", states, {}, s.event.channel, s.event.values))
    windows = ", ".join(f"{n}={real_text(lo)}..{real_text(hi)}" for n, (lo, hi) in sorted(sampler.used.items()))
    text = f"a random run of {element.name} (seed {seed}" + (f"; with no range given, {windows})" if windows else ")")
    return Result(assertion=f"simulate {element.name}", text=text, verdict=Verdict.HOLDS, bound=None,
                  ranges=ranges.describe(), seconds=time.perf_counter() - start, reason=why, trace=tuple(trace),
                  proof=Proof.TRACE, engine="explicit")


def _pick(options: list[Step], rng: random.Random) -> Step:
    """A step: first what happens (a channel, an internal move, `tock`), then its values, each at random.

    Choosing among steps directly would let a channel with many values crowd out everything else.
    """
    groups: dict[object, list[Step]] = {}
    for s in options:
        key = s.note if s.event is None else s.event.channel
        groups.setdefault(key, []).append(s)
    return rng.choice(rng.choice(list(groups.values())))
