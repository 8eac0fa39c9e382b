"""Engines: incremental bounded model checking, strengthened by k-induction.

BMC keeps one solver and only ever extends the unrolling: at each depth k the
target is asked under an activation literal, so the first satisfiable depth
gives a counterexample of fewest steps; the step k → k+1 is then added for good.

A user reads the visible events (and `tock`s) of a trace, and a run of fewest
steps may have more of them than a longer run with more internal steps.  With
`fewest_visible`, once a counterexample is found the search goes on to the
bound asking for one with fewer visible steps: the trace returned has the
fewest visible steps of all runs within the bound.  The explicit engine's
counterexamples are shortest in that sense, which is what the differential
tests compare.  It is not the default: unrolling to the bound after the first
counterexample multiplies the time of a violation (2 s to 41 s for the
paper's tables).

After depth k is cleared, k-induction tries to show that no depth can reach
the target: a second solver asks for a loop-free path of k + 1 non-target
configurations, from any configuration, whose next one is a target.  If there
is none, every shortest run to a target would be such a path, so none exists
at any depth; the search stops early with `proved`.  This is sound for
targets that read only the configuration at k (`Goal.stateless`).  Engines
never print: they return an `Outcome`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import Target, TransitionSystem
from tockbmc.encodings.unroller import Unroller

INDUCTION_DEPTH = 12  # deepest induction tried; beyond it the simple-path constraints cost more than they save


class Status(Enum):
    FOUND = "found"  # a run reaches the target: `Outcome.model` describes it
    NOT_FOUND = "not found"  # no run of up to the bound does
    PROVED = "proved"  # no run of any length does (k-induction)
    UNKNOWN = "unknown"  # the solver gave up or the time ran out


@dataclass
class Outcome:
    status: Status
    depth: int  # steps in the trace when found; the depth searched otherwise
    unroller: Unroller | None = None  # the unrolling the model speaks of (when found)
    model: z3.ModelRef | None = None
    reason: str | None = None
    method: str = ""  # for PROVED: "k-induction" or "invariant"
    invariant: str = ""  # for a proof by invariant: the invariant, in the model's names


SPENT = 0.001  # seconds: what a check's time left reads once its timeout has passed (never 0 for Z3)


def spent(time_left: Callable[[], float | None]) -> bool:
    """Whether a check's time is up (`time_left` as `_Check.time_left` gives it: at least `SPENT`)."""
    left = time_left()
    return left is not None and left <= SPENT


class Clock:
    """The time left of one search, given to each solver call (Z3's timeout is per call)."""

    def __init__(self, timeout: float | None):
        self.deadline = time.monotonic() + timeout if timeout is not None else None

    def arm(self, solver: z3.Solver) -> bool:
        """Give the solver what is left; False when nothing is."""
        if self.deadline is None:
            return True
        left = self.deadline - time.monotonic()
        if left <= 0:
            return False
        solver.set("timeout", max(1, int(left * 1000)))
        return True


class Restarting:
    """A solver that decides each `check` afresh, on every fact added so far (and the assumptions
    as facts). Z3's incremental core (used once a solver has checked, or is given assumptions)
    answers `unknown` or times out on a lambda stored in a state slot, which its one-shot
    preprocessing solves at once: `Good is reachable` with `f = lambda y : nat @ y + x` timed out
    at depth 5 incrementally and took 15 ms afresh. Only systems with function-typed slots use it."""

    def __init__(self) -> None:
        self.facts: list[z3.BoolRef] = []
        self.params: dict[str, object] = {}
        self.last = z3.Solver()

    def add(self, *facts: z3.BoolRef | list[z3.BoolRef]) -> None:
        for f in facts:
            self.facts.extend(f if isinstance(f, list) else [f])

    def set(self, key: str, value: object) -> None:
        self.params[key] = value

    def check(self, *assumptions: z3.BoolRef) -> z3.CheckSatResult:
        self.last = z3.Solver()
        for key, value in self.params.items():
            self.last.set(key, value)
        self.last.add(self.facts)
        self.last.add(list(assumptions))
        return self.last.check()

    def model(self) -> z3.ModelRef:
        return self.last.model()

    def reason_unknown(self) -> str:
        return self.last.reason_unknown()

    def assertions(self) -> list[z3.BoolRef]:
        return list(self.facts)


def new_solver(system: TransitionSystem) -> z3.Solver:
    """A solver for queries over `system`'s runs: `Restarting` when a slot holds a function."""
    if any(isinstance(s, z3.ArraySortRef) and s.range() != z3.BoolSort() for s in system.sorts.values()):
        return Restarting()  # type: ignore[return-value]  # the methods the engines call
    return z3.Solver()


class _Induction:
    """The step case of k-induction, extended one configuration at a time."""

    def __init__(self, system: TransitionSystem, target: z3.BoolRef, clock: Clock):
        self.system, self.target, self.clock = system, target, clock
        self.unroller = Unroller(system)
        self.solver = new_solver(system)
        self.solver.add(system.invariants())
        self.length = 0  # configurations 0..length-1 are constrained to be non-targets

    def _distinct(self, i: int, j: int) -> z3.BoolRef:
        a, b = self.unroller.frame(i), self.unroller.frame(j)
        # The previous move is bookkeeping of the step order, not part of the configuration.
        return z3.Or([a[n] != b[n] for n in self.system.sorts if n != names.PREVIOUS])

    def proves(self, k: int) -> bool | None:
        """Whether k non-target configurations are always followed by a non-target (None: gave up)."""
        u = self.unroller
        while self.length < k:
            j = self.length
            self.solver.add(z3.Not(u.at(self.target, j)), u.at(self.system.trans(), j))
            self.solver.add([self._distinct(i, j) for i in range(j)])
            self.length += 1
        self.solver.add([self._distinct(i, k) for i in range(k)])
        if not self.clock.arm(self.solver):
            return None
        literal = z3.Bool(f"induction@{k}")
        self.solver.add(z3.Implies(literal, u.at(self.target, k)))
        self.solver.add(u.axioms_upto(k))
        result = self.solver.check(literal)
        return True if result == z3.unsat else (False if result == z3.sat else None)


Progress = Callable[[int], None]  # told each depth k a search has cleared: no run of k steps reaches the target


def bmc_each(system: TransitionSystem, targets: list[Target], bound: int, timeout: float | None = None) -> list[bool]:
    """For each target, whether some run of up to `bound` steps reaches it: one unrolling, each
    depth asked once per target not yet reached (no k-induction; False also when time ran out)."""
    clock = Clock(timeout)
    goals = [t(system) for t in targets]
    trans = system.trans()
    u = Unroller(system)
    solver = new_solver(system)
    solver.add(u.at(system.init(), 0))
    reached = [False] * len(goals)
    for k in range(bound + 1):
        solver.add(u.axioms_upto(k))
        for j, goal in enumerate(goals):
            if reached[j]:
                continue
            literal = z3.Bool(f"target{j}@{k}")
            solver.add(z3.Implies(literal, u.at(goal, k)))
            if not clock.arm(solver):
                return reached
            reached[j] = solver.check(literal) == z3.sat
        if all(reached):
            break
        if k < bound:
            solver.add(u.at(trans, k))
    return reached


def bmc(system: TransitionSystem, target: Target, bound: int, timeout: float | None = None,
        induction: bool = False, fewest_visible: bool = False, stop: Callable[[], bool] | None = None,
        progress: Progress | None = None) -> Outcome:
    """Search runs of up to `bound` steps for one that reaches `target`.

    With `induction`, k-induction may prove after each depth that no run of any length does.
    `stop` is asked before each depth; when it says so, the search ends `unknown` (another
    engine has decided).  `progress` is told each depth cleared (for a display; it must be quick).
    """
    clock = Clock(timeout)
    goal = target(system)
    trans = system.trans()
    u = Unroller(system)
    solver = new_solver(system)
    solver.add(u.at(system.init(), 0))
    prover = _Induction(system, goal, clock) if induction else None
    for k in range(bound + 1):
        literal = z3.Bool(f"target@{k}")
        solver.add(z3.Implies(literal, u.at(goal, k)))
        solver.add(u.axioms_upto(k))
        if not clock.arm(solver):
            return Outcome(Status.UNKNOWN, k, reason=f"timed out at depth {k}")
        if stop is not None and stop():
            return Outcome(Status.UNKNOWN, k, reason=f"stopped at depth {k}")
        result = solver.check(literal)
        if result == z3.sat:
            if fewest_visible:
                return _fewest_visible(u, goal, bound, solver, k, solver.model(), clock, progress)
            return Outcome(Status.FOUND, k, u, solver.model())
        if result == z3.unknown:
            why = solver.reason_unknown()
            if why in ("canceled", "timeout", "interrupted"):
                return Outcome(Status.UNKNOWN, k, reason=f"timed out at depth {k}")
            return Outcome(Status.UNKNOWN, k, reason=f"Z3 gave up at depth {k}: {why}")
        if progress is not None:
            progress(k)
        if prover is not None and k < INDUCTION_DEPTH and prover.proves(k + 1):
            return Outcome(Status.PROVED, k, reason=f"it is {k + 1}-inductive, so no depth reaches it",
                           method="k-induction")
        if k < bound:
            solver.add(u.at(trans, k))
    return Outcome(Status.NOT_FOUND, bound)


def _visible(u: Unroller, model: z3.ModelRef, depth: int) -> int:
    shown = u.system.visible()
    return sum(1 for i in range(depth) if z3.is_true(model.eval(u.at(shown, i), model_completion=True)))


def _fewest_visible(u: Unroller, goal: z3.BoolRef, bound: int, solver: z3.Solver, k: int,
                    model: z3.ModelRef, clock: Clock, progress: Progress | None) -> Outcome:
    """From a counterexample at depth k, one with the fewest visible steps within `bound`."""
    best, depth = _visible(u, model, k), k
    d = k
    unfinished = None  # why the trace may not have the fewest visible steps
    shown = u.system.visible()
    while best > 0 and d <= bound:
        if not clock.arm(solver):
            unfinished = f"fewer visible steps were searched for up to depth {d - 1} only (timed out)"
            break
        fewer = z3.Bool(f"fewer@{d}.{best}")
        count = z3.Sum([z3.If(u.at(shown, i), 1, 0) for i in range(d)]) if d else z3.IntVal(0)
        solver.add(z3.Implies(fewer, z3.And(u.at(goal, d), count < best)))
        solver.add(u.axioms_upto(d))
        result = solver.check(fewer)
        if result == z3.sat:
            model, depth = solver.model(), d
            best = _visible(u, model, d)
            continue  # perhaps fewer still at this depth
        if result == z3.unknown:  # keep the one found: a counterexample, if perhaps not the fewest
            unfinished = f"fewer visible steps were searched for up to depth {d - 1} only ({solver.reason_unknown()})"
            break
        if progress is not None:
            progress(d)
        if d < bound:
            solver.add(u.at(u.system.trans(), d))
        d += 1
    return Outcome(Status.FOUND, depth, u, model, unfinished)
