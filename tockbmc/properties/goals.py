"""Goals and queries: an assertion as searches for targets, and what each outcome means.

A `Query` names the element to unroll and its `Goal`s, searched in order.  A
goal's target is a formula over a configuration (`encodings.system.Target`)
that holds exactly where a run ends in a violation of the assertion (or, for
`is reachable`, in a witness); the goal says which verdict reaching it,
not reaching it within the bound, and proving it unreachable each give.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import z3

from tockbmc.encodings.system import Target, TransitionSystem
from tockbmc.encodings.unroller import Unroller, int_value
from tockbmc.model import ast
from tockbmc.model.result import Verdict
from tockbmc.properties.process import Context, Implementation
from tockbmc.properties.spec import Proc

_CLOSED_FORMULA_MS = 2000  # to decide a quantified formula whose values the model fixed

Describe = Callable[[Unroller, z3.ModelRef, int], str]  # what reaching the target at step k means, for the report


def _always(system: TransitionSystem) -> bool:
    return True


@dataclass(frozen=True, kw_only=True)
class Goal:
    """One search: a target and what reaching it (or proving it unreachable) means."""

    target: Target
    found: Verdict  # when the target is reached: violated, or holds (a witness)
    not_found: Verdict  # when it is not reached within the bound: holds, or unknown
    unreachable: Verdict  # when it is proved unreachable at every depth
    describe: Describe
    stateless: bool = True  # the target reads only the configuration at k (so induction applies)
    claim: str = "no run reaches a violation"  # what not reaching the target shows
    applies: Callable[[TransitionSystem], bool] = _always  # searched only when this holds
    skipped: str = ""  # what not applying shows
    sought: str = "it"  # what the target is, for "no run of any length reaches …"
    prepare: Callable[[TransitionSystem], None] | None = None  # adds what the target needs (before the unrolling)
    # Why the target's unreachability at every depth would not show the claim (so no proof is
    # attempted and only the bounded search counts), or None when it would.
    unprovable: Callable[[TransitionSystem], str | None] | None = None
    failures: bool = False  # a refusal the specification cannot make is among the targets (the replay checks it)
    details: Callable[[Unroller, z3.ModelRef, int], dict[str, object]] | None = None  # more for the result

    @staticmethod
    def violation(target: Target, describe: Describe, **more: object) -> Goal:
        """Reaching the target violates the assertion; not reaching it within the bound, it holds."""
        return Goal(target=target, found=Verdict.VIOLATED, not_found=Verdict.HOLDS, unreachable=Verdict.HOLDS,
                    describe=describe, **more)  # type: ignore[arg-type]

    @staticmethod
    def witness(target: Target, describe: Describe, **more: object) -> Goal:
        """Reaching the target shows the assertion holds; a bounded search for it alone decides nothing."""
        return Goal(target=target, found=Verdict.HOLDS, not_found=Verdict.UNKNOWN, unreachable=Verdict.VIOLATED,
                    describe=describe, **more)  # type: ignore[arg-type]


@dataclass(frozen=True)
class ElementSpec:
    """A model element on the specification's side of a refinement: as written (with its
    renaming), resolved, its `D__` settings and the operations its controller defines."""

    impl: Implementation
    element: ast.StateMachine | ast.Controller | ast.Module
    settings: tuple[tuple[str, ast.Expr], ...]
    defined: tuple[tuple[str, ast.OperationDef], ...]


@dataclass(frozen=True, kw_only=True)
class Query:
    """How to decide one assertion: the element, its goals, and the CSP context it runs in."""

    assertion: ast.Assertion
    element: ast.StateMachine | ast.Controller | ast.Module
    goals: tuple[Goal, ...]  # searched in order; the first that reaches its target decides
    context: Context | None = None  # the CSP operators around the element, and a monitor
    settings: tuple[tuple[str, ast.Expr], ...] = ()  # constants set by `D__` arguments
    defined: tuple[tuple[str, ast.OperationDef], ...] = ()  # a machine in its controller: the operations it defines
    inclusion: Proc | None = None  # a specification every trace of which must be the element's
    determinism: bool = False  # searched before the goals: two runs, one trace, an event offered and refused
    spec_name: str = ""
    # Refinement between two model elements: the one on the specification's side (with its
    # resolved element and `D__` settings), whose state graph the engines build (`explicit.lts`)
    # and give the query as its specification (`queries.given_spec`) before anything runs.
    spec_element: ElementSpec | None = None
    timed: bool = True  # False: RoboTool's untimed semantics (no tock; `model.untimed` rewrites the element)

    @property
    def reached(self) -> tuple[object, ...]:
        """What the check runs: the element, the operations it calls that its controller defines, and
        the model element on the specification's side, if any."""
        return (self.element, self.defined, self.spec_element.element if self.spec_element is not None else None)


def says(text: str) -> Describe:
    """A description that does not depend on the run."""
    return lambda unroller, model, k: text


def terminated(system: TransitionSystem) -> z3.BoolRef:
    return system.halted()


def timelocked(system: TransitionSystem) -> z3.BoolRef:
    """A stable configuration that refuses tock (a terminated one included)."""
    return z3.And(z3.Not(system.internal_enabled()), z3.Not(system.tock_enabled()))


def stuck(system: TransitionSystem) -> z3.BoolRef:
    """Not terminated, and refusing every event, tock included."""
    return z3.And(z3.Not(system.halted()), z3.Not(system.internal_enabled()), z3.Not(system.tock_enabled()),
                  z3.Not(system.event_offered()))


def true_at(unroller: Unroller, model: z3.ModelRef, term: z3.BoolRef, k: int) -> bool:
    """Whether a formula over the template configuration holds at step k of the run `model` describes.

    A quantified formula (a sequence's elements, a function's axioms) may not evaluate to a
    truth value in a model; it is then closed (the model's values put in) and proved, briefly:
    "unknown" counts as not holding."""
    value = model.eval(unroller.at(term, k), model_completion=True)
    if z3.is_true(value) or z3.is_false(value):
        return z3.is_true(value)
    solver = z3.Solver(ctx=value.ctx)
    solver.set(timeout=_CLOSED_FORMULA_MS)
    solver.add(z3.Not(value))
    return solver.check() == z3.unsat


def number_at(unroller: Unroller, model: z3.ModelRef, term: z3.ExprRef, k: int) -> int:
    """An integer term over the template step, its value at step k."""
    return int_value(model, unroller.at(term, k))


_SAFETY = ("deadlock-free", "timelock-free", "divergence-free", "deterministic")


def one_value_only(q: Query, verdict: Verdict) -> bool:
    """Whether `verdict`, found over every parameter value at once, may stand for some values only.

    Both engines search the runs from every value of a constant made a parameter together (the
    element as the internal choice of its instances), which decides a claim about every run for
    every value.  A claim that some run exists does not carry over: a witness shows it for the
    values it starts from (`M terminates` with `--param k`, where only k = 1 terminates), and the
    specification-on-the-left direction finds each of its traces in some instance, not in each
    (docs/semantics.md §6.3: the assertion holds when it holds for every value)."""
    a = q.assertion
    refinement = a.kind in ("refines", "equals")
    # A specification side with instances: the specification on the left, or a model element on the
    # right whose instances make one internal choice (a union of their traces, not each one's).
    instances = q.inclusion is not None or q.spec_element is not None
    if verdict == Verdict.HOLDS:
        return (not a.negated and a.kind in ("reachable", "terminates")
                or a.negated and a.kind in _SAFETY
                or refinement and a.negated and bool(q.goals)
                or refinement and not a.negated and instances)
    if verdict == Verdict.VIOLATED:
        return refinement and a.negated and instances
    return False


def per_value_reason(parameters: tuple[str, ...], reason: str | None, functions: tuple[str, ...] = ()) -> str:
    """Why a verdict `one_value_only` names is unknown: it rests on one choice of the parameters'
    values, or of what the functions without a body compute (docs/semantics.md §6.3, §6.4)."""
    some = [f"values of the parameters ({', '.join(parameters)})"] if parameters else []
    some += [f"results of the functions without a body ({', '.join(functions)})"] if functions else []
    return (f"shown for some {' and some '.join(some)} only: one run, or one trace, stands for the choice it "
            f"makes, and the claim needs every one ({reason})")
