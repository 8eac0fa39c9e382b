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

import z3

from tockbmc.encodings.system import System
from tockbmc.properties.queries import Target

INDUCTION_DEPTH = 12  # deepest induction tried; beyond it the simple-path constraints cost more than they save


@dataclass
class Outcome:
    status: str  # "found" | "not found" | "proved" | "unknown"
    depth: int  # steps in the trace when found; the depth searched otherwise
    model: z3.ModelRef | None = None
    reason: str | None = None


def _solver(deadline: float | None) -> z3.Solver:
    s = z3.Solver()
    if deadline is not None:
        s.set("timeout", max(1, int((deadline - time.monotonic()) * 1000)))
    return s


class _Induction:
    """The step case of k-induction, extended one configuration at a time."""

    def __init__(self, system: System, target: Target, deadline: float | None):
        self.system, self.target = system, target
        self.solver = _solver(deadline)
        self.deadline = deadline
        self.solver.add(system.invariants())
        self.length = 0  # configurations 0..length-1 are constrained to be non-targets

    def _distinct(self, i: int, j: int) -> z3.BoolRef:
        a, b = self.system.frame(i), self.system.frame(j)
        return z3.Or([a[n] != b[n] for n in self.system.sorts])

    def proves(self, k: int) -> bool | None:
        """Whether k non-target configurations are always followed by a non-target (None: gave up)."""
        s = self.system
        while self.length < k:
            j = self.length
            self.solver.add(z3.Not(self.target(s, j)), s.step(j))
            self.solver.add([self._distinct(i, j) for i in range(j)])
            self.length += 1
        self.solver.add([self._distinct(i, k) for i in range(k)])
        if self.deadline is not None:
            left = self.deadline - time.monotonic()
            if left <= 0:
                return None
            self.solver.set("timeout", max(1, int(left * 1000)))
        literal = z3.Bool(f"induction@{k}")
        self.solver.add(z3.Implies(literal, self.target(s, k)))
        self.solver.add(s.side_constraints())
        result = self.solver.check(literal)
        return True if result == z3.unsat else (False if result == z3.sat else None)


def bmc(system: System, target: Target, bound: int, timeout: float | None = None,
        induction: Callable[[], System] | None = None, fewest_visible: bool = False) -> Outcome:
    """Search runs of up to `bound` steps for one that reaches `target`.

    `induction`, when given, makes a fresh system for the k-induction step case.
    """
    deadline = time.monotonic() + timeout if timeout is not None else None
    solver = _solver(deadline)
    solver.add(system.init())
    prover = _Induction(induction(), target, deadline) if induction is not None else None
    for k in range(bound + 1):
        goal = target(system, k)
        solver.add(system.side_constraints())
        literal = z3.Bool(f"target@{k}")
        solver.add(z3.Implies(literal, goal))
        if deadline is not None:  # Z3's timeout is per check: give each what is left
            left = deadline - time.monotonic()
            if left <= 0:
                return Outcome("unknown", k, None, f"timed out at depth {k}")
            solver.set("timeout", max(1, int(left * 1000)))
        result = solver.check(literal)
        if result == z3.sat:
            if fewest_visible:
                return _fewest_visible(system, target, bound, solver, k, solver.model(), deadline)
            return Outcome("found", k, solver.model())
        if result == z3.unknown:
            why = solver.reason_unknown()
            if why in ("canceled", "timeout"):
                return Outcome("unknown", k, None, f"timed out at depth {k}")
            return Outcome("unknown", k, None, f"Z3 gave up at depth {k}: {why}")
        if prover is not None and k < INDUCTION_DEPTH:
            if prover.proves(k + 1):
                return Outcome("proved", k, None, f"it is {k + 1}-inductive, so no depth reaches it")
        if k < bound:
            solver.add(system.step(k))
            solver.add(system.side_constraints())
    return Outcome("not found", bound)


def _visible(system: System, model: z3.ModelRef, depth: int) -> int:
    return sum(1 for i in range(depth) if z3.is_true(model.eval(system.visible(i), model_completion=True)))


def _fewest_visible(system: System, target: Target, bound: int, solver: z3.Solver, k: int,
                    model: z3.ModelRef, deadline: float | None) -> Outcome:
    """From a counterexample at depth k, one with the fewest visible steps within `bound`."""
    best, depth = _visible(system, model, k), k
    d = k
    unfinished = None  # why the trace may not have the fewest visible steps
    while best > 0 and d <= bound:
        if deadline is not None:
            left = deadline - time.monotonic()
            if left <= 0:
                unfinished = f"fewer visible steps were searched for up to depth {d - 1} only (timed out)"
                break
            solver.set("timeout", max(1, int(left * 1000)))
        fewer = z3.Bool(f"fewer@{d}.{best}")
        count = z3.Sum([z3.If(system.visible(i), 1, 0) for i in range(d)]) if d else z3.IntVal(0)
        solver.add(z3.Implies(fewer, z3.And(target(system, d), count < best)))
        solver.add(system.side_constraints())
        result = solver.check(fewer)
        if result == z3.sat:
            model, depth = solver.model(), d
            best = _visible(system, model, d)
            continue  # perhaps fewer still at this depth
        if result == z3.unknown:  # keep the one found: a counterexample, if perhaps not the fewest
            unfinished = f"fewer visible steps were searched for up to depth {d - 1} only ({solver.reason_unknown()})"
            break
        if d < bound:
            solver.add(system.step(d))
            solver.add(system.side_constraints())
        d += 1
    return Outcome("found", depth, model, unfinished)
