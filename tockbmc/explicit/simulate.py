"""`tockbmc simulate`: a random run of an element, by the interpreter, shown as a trace."""

from __future__ import annotations

import random
from collections.abc import Iterator
from fractions import Fraction

from tockbmc.explicit.engine import python_settings
from tockbmc.explicit.interpreter import Interpreter, Sampler, Step
from tockbmc.model import ast
from tockbmc.model.diagnostics import suggestion
from tockbmc.model.numbers import real_text
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import TraceStep


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


class RandomRun:
    """A random run of up to `steps` steps from a random initial configuration, its steps drawn one
    at a time as they are iterated (a long run is streamed: memory stays flat), then `why` it ended.

    Values are drawn as the run needs them (`Sampler`), so that the run takes memory and time in
    proportion to its steps, whatever the number of values the element could take.
    """

    def __init__(self, project: ast.Project, name: str | None, steps: int, seed: int, ranges: Ranges,
                 settings: dict[str, ast.Expr]) -> None:
        self.element = pick(project, name)
        self.steps, self.seed = steps, seed
        self.rng = random.Random(seed)
        self.sampler = Sampler(self.rng, WINDOWS)
        self.interp = Interpreter(self.element, ranges, python_settings(settings), sampler=self.sampler)
        self.text = f"a random run of {self.element.name} (seed {seed})"
        self.why = ""

    def __iter__(self) -> Iterator[TraceStep]:
        interp, rng, name = self.interp, self.rng, self.element.name
        initial = interp.initial()
        if not initial:
            self.why = f"{name} has no initial configuration: no choice of initial values fits their types"
            return
        config = rng.choice(initial)
        self.why = f"{self.steps} steps taken"
        for i in range(self.steps):
            options = interp.steps(config)
            if not options:
                self.why = f"{name} has terminated" if interp.terminated(config) else f"{name} can do nothing more"
                return
            s = _pick(options, rng)
            config = s.target
            states = interp.states(config)
            if s.kind == "internal" or s.event is None:
                yield TraceStep(i + 1, None, "internal", s.note, states, {})
            else:
                yield TraceStep(i + 1, s.event.name, s.kind, "", states, {}, s.event.channel, s.event.values)

    def windows(self) -> str:
        """Where the values of types without a range were drawn from, if any were (`WINDOWS`)."""
        return ", ".join(f"{n}={real_text(lo)}..{real_text(hi)}" for n, (lo, hi) in sorted(self.sampler.used.items()))

    def end(self) -> str:
        """How the run ended, after its steps, with the windows its values were drawn from."""
        windows = self.windows()
        return self.why + (f" (with no range given, values drawn from {windows})" if windows else "")


def _pick(options: list[Step], rng: random.Random) -> Step:
    """A step: first what happens (a channel, an internal move, `tock`), then its values, each at random.

    Choosing among steps directly would let a channel with many values crowd out everything else.
    """
    groups: dict[object, list[Step]] = {}
    for s in options:
        key = s.note if s.event is None else s.event.channel
        groups.setdefault(key, []).append(s)
    return rng.choice(rng.choice(list(groups.values())))
