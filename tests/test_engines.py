"""Every engine on one tiny system, in the manner of pono's `tests/test_engines.cpp`.

The system is a counter: `tick` three times (an internal step after each
adds one to `x`), then the machine moves to a final state and terminates.
For each engine, one property holds (`x` never exceeds 3) and one fails
(it terminates), and the tests pin the verdict, how it was shown and the
counterexample.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
import z3
from conftest import COUNTER

from tockbmc import Project, load
from tockbmc.bmc.engine import Status, bmc
from tockbmc.bmc.witness import decode
from tockbmc.check import check
from tockbmc.encodings import names
from tockbmc.encodings.composition import network_of
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Proof, Verdict
from tockbmc.properties.goals import terminated, true_at

ASSERTIONS = """\
assertion stops: Counter does not terminate.
assertion free: Counter is deadlock-free.
"""
EVENTS = ["Counter::tick.in"] * 3 + ["Counter::terminate"]


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> Project:
    d: Path = tmp_path_factory.mktemp("counter")
    (d / "counter.rct").write_text(COUNTER)
    (d / "counter.assertions").write_text(ASSERTIONS)
    return load(d)


def _system(project: Project) -> TransitionSystem:
    [machine] = project.machines
    return TransitionSystem(network_of(machine, {}), Ranges())


def _x_above_3(system: TransitionSystem) -> z3.BoolRef:
    return system.cur[names.variable("Counter", "x")] > 3  # type: ignore[operator, no-any-return]


def test_bmc_finds_a_shortest_counterexample(project: Project) -> None:
    system = _system(project)
    outcome = bmc(system, terminated, bound=20)
    assert outcome.status == Status.FOUND and outcome.depth == 9  # 4 events, 5 internal steps
    assert outcome.unroller is not None and outcome.model is not None
    trace = decode(outcome.unroller, outcome.model, outcome.depth)
    assert [s.event for s in trace if s.event] == EVENTS
    assert [s.changed.get("Counter.x") for s in trace if s.changed.get("Counter.x")] == ["0", "1", "2", "3"]


def test_bmc_below_the_counterexample_finds_nothing(project: Project) -> None:
    outcome = bmc(_system(project), terminated, bound=8)
    assert outcome.status == Status.NOT_FOUND and outcome.depth == 8


def test_bmc_alone_shows_a_property_to_the_bound(project: Project) -> None:
    outcome = bmc(_system(project), _x_above_3, bound=15)
    assert outcome.status == Status.NOT_FOUND and outcome.depth == 15 and outcome.model is None


def test_k_induction_proves_a_property_for_every_length(project: Project) -> None:
    outcome = bmc(_system(project), _x_above_3, bound=15, induction=True)
    assert outcome.status == Status.PROVED and outcome.depth < 15
    assert outcome.reason is not None and "inductive" in outcome.reason


def test_k_induction_does_not_prove_what_fails(project: Project) -> None:
    outcome = bmc(_system(project), terminated, bound=20, induction=True)
    assert outcome.status == Status.FOUND and outcome.depth == 9


def test_the_unroller_names_each_step(project: Project) -> None:
    system = _system(project)
    u = Unroller(system)
    x = names.variable("Counter", "x")
    assert u.at(system.cur[x], 4).eq(u.frame(4)[x]) and u.at(system.nxt[x], 4).eq(u.frame(5)[x])
    assert u.at(system.act, 2).eq(u.action(2))


def test_check_gives_verdicts_with_their_proof(project: Project) -> None:
    stops, free = check(project, bound=20)
    assert stops.verdict == Verdict.VIOLATED and stops.proof == Proof.TRACE and stops.depth == 9
    assert [s.event for s in stops.trace if s.event] == EVENTS and stops.extra["replayed"] == "yes"
    assert free.verdict == Verdict.HOLDS and free.proof == Proof.K_INDUCTION and free.proof.every_length


def test_check_without_induction_holds_to_the_bound(project: Project) -> None:
    _, free = check(project, bound=20, induction=False)
    assert free.verdict == Verdict.HOLDS and free.proof == Proof.BOUNDED and free.depth == 20
    assert not free.proof.every_length


def test_explicit_engine_gives_the_same_verdicts(project: Project) -> None:
    ranges = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
    stops, free = check_explicit(project, None, 10, ranges, {}, None)
    assert stops.verdict == Verdict.VIOLATED and stops.proof == Proof.TRACE
    assert [s.event for s in stops.trace if s.event] == EVENTS
    assert free.verdict == Verdict.HOLDS and free.proof == Proof.EXHAUSTIVE


def test_explicit_engine_short_of_the_counterexample_is_bounded(project: Project) -> None:
    ranges = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
    [stops] = check_explicit(project, ["stops"], 3, ranges, {}, None)
    assert stops.verdict == Verdict.HOLDS and stops.proof == Proof.BOUNDED


def test_verdicts_carry_their_exit_status() -> None:
    from tockbmc.model.result import exit_code
    assert exit_code([Verdict.HOLDS, Verdict.UNKNOWN, Verdict.VIOLATED]) == 10
    assert exit_code([Verdict.HOLDS, Verdict.UNSUPPORTED]) == 20
    assert exit_code([Verdict.HOLDS]) == 0 and exit_code([]) == 0


def test_pdr_finds_an_invariant_that_checks_again(project: Project) -> None:
    from tockbmc.bmc.pdr import Spacer, applicable, confirmed
    system = _system(project)
    goal = _x_above_3(system)
    assert applicable(system, goal) is None
    spacer = Spacer(system, goal)
    assert spacer.run(30) == "proved"
    assert confirmed(system, goal, spacer.invariant())
    assert not confirmed(system, goal, z3.BoolVal(True))  # True is inductive but does not exclude x > 3
    from tockbmc.bmc.pdr import describe
    text = describe(system, spacer.invariant())
    assert "Counter.x" in text and "@0" not in text  # in the model's names


def test_pdr_says_reachable_for_what_fails(project: Project) -> None:
    from tockbmc.bmc.pdr import Spacer
    system = _system(project)
    assert Spacer(system, terminated(system)).run(30) == "reachable"


def test_the_portfolio_reports_an_invariant_proof(project: Project) -> None:
    """With k-induction off, only PDR can show the counter never exceeds 3 for every length."""
    from tockbmc.bmc.portfolio import decide
    system = _system(project)
    outcome = decide(system, _x_above_3, bound=3, induction=True)
    assert outcome.status == Status.PROVED and outcome.method in ("k-induction", "invariant")


def test_a_quantified_formula_is_read_in_a_run_even_where_the_model_cannot_evaluate_it(project: Project) -> None:
    """A run's model leaves a quantified formula unevaluated (a sequence's elements, a function's
    axioms); `true_at` then proves it closed.  It used to read every such formula as false, so a
    refinement goal found by BMC fell through to the divergence explanation of a system that does
    not watch for loops, and crashed (`KeyError: 'loop.saved'`, found by benchmarks/differential.py)."""
    system = _system(project)
    outcome = bmc(system, terminated, bound=20)
    assert outcome.unroller is not None and outcome.model is not None
    x = system.cur[names.variable("Counter", "x")]
    n, seq = z3.Int("n"), z3.Unit(x)  # the sequence <x>: every element at most 3, or above 3
    inside = z3.And(n >= 0, n < z3.Length(seq))
    at_most_3 = z3.ForAll([n], z3.Implies(inside, seq[n] <= 3))
    above_3 = z3.ForAll([n], z3.Implies(inside, seq[n] > 3))
    assert not z3.is_true(outcome.model.eval(outcome.unroller.at(at_most_3, 9), model_completion=True))
    assert true_at(outcome.unroller, outcome.model, at_most_3, 9)
    assert not true_at(outcome.unroller, outcome.model, above_3, 9)


def test_a_z3_failure_is_an_unknown_with_z3s_message(project: Project, monkeypatch: pytest.MonkeyPatch) -> None:
    """Z3 raised 'Overflow encountered when expanding vector' in k-induction on one public project
    (not reproduced since): the check is `unknown` with Z3's message, not an internal error that ends
    the run."""
    def failing(*args: object, **kwargs: object) -> object:
        raise z3.Z3Exception(b"Overflow encountered when expanding vector")

    monkeypatch.setattr("tockbmc.check.decide", failing)
    [r] = check(project, ["stops"], bound=5)
    assert r.verdict == Verdict.UNKNOWN and r.reason == "Z3 failed: Overflow encountered when expanding vector", r
