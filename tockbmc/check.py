"""`check`: decide the assertions of a loaded project (the API behind `tockbmc check`).

Each assertion is a `Query` (`properties.queries`): its goals are searched in
order by BMC with k-induction (`bmc.engine`), and a specification on the model's
right is followed trace by trace (`bmc.inclusion`).  Every counterexample is
replayed by the independent interpreter (`explicit.replay`) before it is returned.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Hashable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from typing import TYPE_CHECKING

import z3

from tockbmc.bmc.determinism import Pair, configuration_of, nondeterminism
from tockbmc.bmc.engine import SPENT, Outcome, Progress, Status
from tockbmc.bmc.inclusion import Inclusion, included
from tockbmc.bmc.interpretations import every_interpretation, start_unspecified, unspecified
from tockbmc.bmc.portfolio import decide
from tockbmc.bmc.witness import decode, free_fields, initial_choices
from tockbmc.encodings.composition import Network, network_of
from tockbmc.encodings.system import TransitionSystem, check_encodable
from tockbmc.model import ast, probabilistic
from tockbmc.model.config import Configuration, configure
from tockbmc.model.errors import Unsupported
from tockbmc.model.limits import NO_START, TOO_DEEP_TO_CHECK
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import Proof, Result, TraceStep, Verdict, within_no_steps
from tockbmc.properties.both import decide_in_both
from tockbmc.properties.deadlock import diverges, may_diverge, refuses_everything, untimed_deadlocked
from tockbmc.properties.determinism import locally_nondeterministic
from tockbmc.properties.failures import FAILURES_MODELS
from tockbmc.properties.goals import Goal, Query, one_value_only, per_value_reason, stuck, terminated, timelocked
from tockbmc.properties.inclusion import Following, TraceFollower
from tockbmc.properties.process import MonitorExtension
from tockbmc.properties.queries import query
from tockbmc.properties.ticktock import TICK_TOCK

if TYPE_CHECKING:  # the interpreter is imported when a replay needs it
    from tockbmc.explicit.interpreter import Interpreter, Step

DEFAULT_BOUND = 40
SPLIT_DEPTH = 8  # steps of two runs searched from a configuration where the next step is open


def check(project: ast.Project, names: Iterable[str] | None = None, bound: int = DEFAULT_BOUND,
          ranges: Ranges | None = None, settings: dict[str, ast.Expr] | None = None,
          timeout: float | None = None, induction: bool = True, shortest: str = "steps",
          config: Configuration | None = None) -> list[Result]:
    """One `Result` per selected assertion (all by default), in file order.

    Ranges and constants come from `config` (`model.config`), else from `ranges` and
    `settings` (by constant name, as `--range` and `--set` give them) over the project's
    instantiation; raises `model.config.ConfigError` for a name or value that does not fit.
    `induction=False` leaves BMC alone (to measure it); verdicts within the bound are the same.
    `shortest="events"` makes each counterexample one with the fewest visible steps (events and
    `tock`s) within the bound, rather than the first found, of fewest steps; it costs an unrolling
    to the bound.
    """
    return list(iter_check(project, names, bound, ranges, settings, timeout, induction, shortest, config))


def iter_check(project: ast.Project, names: Iterable[str] | None = None, bound: int = DEFAULT_BOUND,
               ranges: Ranges | None = None, settings: dict[str, ast.Expr] | None = None,
               timeout: float | None = None, induction: bool = True, shortest: str = "steps",
               config: Configuration | None = None) -> Iterator[Result]:
    """`check`'s results one at a time, each as soon as it is decided."""
    config = config or configure(project, ranges, settings)
    wanted = set(names) if names is not None else None
    for a in config.project.assertions:
        if wanted is None or any(a.selected_by(n) for n in wanted):
            yield check_assertion(config.project, a, bound, config, timeout, induction, shortest)


class _Check:
    """The search for one assertion's verdict, and the `Result` it gives."""

    def __init__(self, a: ast.Assertion, bound: int, config: Configuration, timeout: float | None,
                 induction: bool, shortest: str, progress: Progress | None = None):
        self.a, self.bound, self.config, self.timeout = a, bound, config, timeout
        self.induction, self.shortest, self.progress = induction, shortest, progress
        self.ranges = config.ranges()
        # What the result states it was checked with; the assertion's constants are known once it is queried.
        self.described: dict[str, str] = self.ranges.describe()
        self.constants: dict[str, str] = {}
        self.defaults: dict[str, str] = {}  # what the reading filled in that the element reaches
        self.notes: tuple[str, ...] = ()  # how the element was read (`model.probabilistic.notes`)
        self.sources: dict[str, dict[str, str]] = {"ranges": config.range_sources()}
        self.consts: dict[str, ast.Expr] = {}
        self.start = time.perf_counter()
        self.reasons: list[str] = []  # what the goals searched so far have shown
        self.proof = Proof.K_INDUCTION  # of a verdict that holds: weakened to BOUNDED by the first goal shown only to the bound
        self.depth: int | None = None  # the deepest depth a k-induction proof needed
        self.extra: dict[str, object] = {}  # what the goals searched so far add to the result
        self.searched = False  # whether some goal was searched (rather than shown unreachable by abstraction)
        self.abstracted = False
        self.q: Query | None = None
        self.parameters: tuple[str, ...] = ()  # constants left parameters (`one_value_only`)
        self.functions: tuple[str, ...] = ()  # functions without a body the elements call (`one_value_only`)
        self.witnessed = False  # whether `found` decided a witness (and weighed what it rests on)
        self.network: Network | None = None
        self.spec_consts: dict[str, ast.Expr] = {}  # the constants of a model element on the specification's side

    def time_left(self) -> float | None:
        return None if self.timeout is None else max(SPENT, self.timeout - (time.perf_counter() - self.start))

    def result(self, verdict: Verdict, reason: str | None, *, proof: Proof, depth: int | None,
               trace: tuple[TraceStep, ...] = (), extra: dict | None = None) -> Result:
        return Result(assertion=self.a.label, text=self.a.text, verdict=verdict, bound=self.bound, depth=depth,
                      ranges=self.described, seconds=time.perf_counter() - self.start, reason=reason,
                      trace=trace, proof=proof, pos=str(self.a.pos), extra=extra or {}, constants=self.constants,
                      sources=self.sources, reading=self.config.reading, defaults=self.defaults, notes=self.notes)

    def unsupported(self, exc: Unsupported) -> Result:
        return Result(assertion=self.a.label, text=self.a.text, verdict=Verdict.UNSUPPORTED, bound=None, depth=None,
                      ranges=self.described, seconds=time.perf_counter() - self.start, reason=exc.reason,
                      proof=Proof.NONE, pos=str(self.a.pos), constants=self.constants, sources=self.sources,
                      reading=self.config.reading, defaults=self.defaults, notes=self.notes)

    def run(self, project: ast.Project) -> Result:
        decided = self._run(project)
        if decided.verdict in (Verdict.HOLDS, Verdict.VIOLATED) and self.network is not None \
                and not (_starts(TransitionSystem(self.network, self.ranges, self.consts)) and self._spec_starts()):
            # shown of no run at all (a trace shown may be the specification's, the model on the
            # right): asked after the verdict, as building a system beforehand changes what Z3
            # meets first (a determinism check gave up on it)
            return replace(decided, verdict=Verdict.UNKNOWN, proof=Proof.NONE, reason=NO_START)
        q = self.q
        if q is None or not one_value_only(q, decided.verdict):
            return decided
        # A verdict one run or trace shows (a witness, the specification on the left, a pair of
        # runs) rests on the choices it made: of a parameter's value, or of what the model leaves
        # open. A witness run (`found`), and a pair both replayed whole, were weighed already.
        functions = self.functions if not self.witnessed else ()
        if self.parameters:
            return replace(decided, verdict=Verdict.UNKNOWN, proof=Proof.NONE,
                           reason=per_value_reason(self.parameters, decided.reason, functions))
        left = list(functions) or ([] if self.witnessed else self.open_values())
        if left:
            return replace(decided, verdict=Verdict.UNKNOWN, proof=Proof.NONE,
                           reason=f"shown by a run or trace that rests on what the model leaves open "
                                  f"({', '.join(left)}), and the claim needs every choice there "
                                  f"(docs/semantics.md §6.4): {decided.reason}")
        return decided

    def _spec_starts(self) -> bool:
        """Whether the model element on the specification's side, if any, has a run that starts."""
        q = self.q
        if q is None or q.spec_element is None:
            return True
        spec = q.spec_element
        return _starts(TransitionSystem(network_of(spec.element, dict(spec.defined), timed=q.timed), self.ranges,
                                        self.spec_consts))

    def open_values(self) -> list[str]:
        """What the element's runs can meet that the model leaves open (`bmc.interpretations`)."""
        if self.network is None:
            return []
        return unspecified(TransitionSystem(self.network, self.ranges, self.consts), z3.BoolVal(True), self.functions)

    def _run(self, project: ast.Project) -> Result:
        try:
            q = self.q = query(project, self.a)
            if q.spec_element is not None:  # two model elements: the other one's state graph, from the interpreter
                from tockbmc.explicit.engine import with_element_spec
                q = with_element_spec(q, self.a, self.config)
            setup = self.config.setup(self.a, q.element, q.settings)
            self.described, self.constants, self.sources = (setup.described_ranges, setup.described_constants,
                                                            setup.sources)
            self.defaults = setup.defaults
            self.notes = probabilistic.notes(*q.reached)
            spec_setup = (self.config.setup(self.a, q.spec_element.element, q.spec_element.settings)
                          if q.spec_element is not None else None)
            self.spec_consts = spec_setup.constants if spec_setup is not None else {}
            self.parameters = setup.parameters + (spec_setup.parameters if spec_setup is not None else ())
            self.functions = tuple(f.qname for f in ast.free_functions(*q.reached))
            network = self.network = network_of(q.element, dict(q.defined), timed=q.timed)
            check_encodable(network)
            consts = self.consts = setup.constants
            if q.context is not None:  # a specification's input read later is told apart value by value
                q.context.sem.values = _values_of(q, self.ranges, consts)
            if q.determinism:
                return self.deterministic(q, network, consts)
            first: Result | None = None  # `is not equal to`: the first direction, when it shows no difference
            for goal in q.goals:
                decided = self.search(q, goal, network, consts)
                if decided is not None:
                    if q.inclusion is not None and self.a.negated and decided.verdict != Verdict.HOLDS:
                        first = decided  # the other direction may still tell them apart
                        break
                    return decided
            if q.inclusion is not None:
                decided = self.follow(q, network, consts)
                if first is not None and (decided is None or decided.verdict != Verdict.HOLDS):
                    return first if first.verdict == Verdict.UNKNOWN else decided or first
                if decided is not None:
                    return decided
        except Unsupported as exc:
            return self.unsupported(exc)
        except RecursionError:
            return self.unsupported(Unsupported(None, TOO_DEEP_TO_CHECK))  # the result carries the assertion's line
        except z3.Z3Exception as exc:  # Z3 itself failed on a query (seen once: 'Overflow encountered when
            # expanding vector' in k-induction on a RoboArch property file): no verdict, and the others still run
            why = exc.value.decode(errors="replace") if isinstance(exc.value, bytes) else str(exc.value)
            return self.result(Verdict.UNKNOWN, f"Z3 failed: {why}", proof=Proof.NONE, depth=None)
        if self.abstracted and not self.searched and q.inclusion is None:
            self.proof = Proof.ABSTRACTION
        return self.result(Verdict.HOLDS, "; ".join(self.reasons), proof=self.proof,
                           depth=self.bound if self.proof == Proof.BOUNDED else self.depth, extra=self.extra)

    def search(self, q: Query, goal: Goal, network: Network, consts: dict[str, ast.Expr]) -> Result | None:
        """Search one goal; a `Result` if it decides the assertion, None if the next goal is to be searched."""
        system = TransitionSystem(network, self.ranges, consts, context=q.context)
        if goal.prepare is not None:
            goal.prepare(system)
        if not goal.applies(system):  # the target is unreachable at every length (e.g. data ignored, no cycle)
            if goal.unreachable != Verdict.HOLDS:
                return self.result(goal.unreachable, goal.skipped, proof=Proof.ABSTRACTION, depth=None)
            if goal.skipped:
                self.reasons.append(goal.skipped)
            self.abstracted = True
            return None
        self.searched = True
        why_not = goal.unprovable(system) if goal.unprovable is not None else None
        outcome = decide(system, goal.target, self.bound, self.time_left(),
                         goal.stateless and self.induction and why_not is None, fewest_visible=self.shortest == "events",
                         progress=self.progress)
        if outcome.status == Status.UNKNOWN:
            return self.result(Verdict.UNKNOWN, outcome.reason, proof=Proof.NONE, depth=outcome.depth)
        if outcome.status == Status.FOUND:
            return self.found(q, goal, outcome)
        if outcome.status == Status.PROVED:
            verdict = goal.unreachable
            why = (f"{goal.claim}, shown for runs of every length, not only up to {self.bound} steps "
                   f"({outcome.reason})" if verdict == Verdict.HOLDS
                   else f"no run of any length reaches {goal.sought} ({outcome.reason})")
            proof = self.proved(outcome)
        elif goal.not_found == Verdict.HOLDS:
            verdict, why, proof = Verdict.HOLDS, f"{goal.claim} within {self.bound} steps", Proof.BOUNDED
            if why_not:
                why = f"{why} ({why_not})"
        else:
            verdict, why = Verdict.UNKNOWN, f"not found within {self.bound} steps; a bounded search alone gives no verdict"
            proof = Proof.NONE
        if verdict != Verdict.HOLDS:
            return self.result(verdict, why, proof=proof, depth=outcome.depth, extra=self.extra)
        if proof == Proof.BOUNDED:
            self.proof = Proof.BOUNDED
        self.reasons.append(why)
        return None

    def proved(self, outcome: Outcome) -> Proof:
        """Record a proof for every length: its kind (an invariant weakens k-induction in the
        result's proof), the deepest k it needed, and the invariant to print."""
        proof = Proof.INVARIANT if outcome.method == "invariant" else Proof.K_INDUCTION
        self.depth = max(self.depth or 0, outcome.depth)
        if proof == Proof.INVARIANT and self.proof == Proof.K_INDUCTION:
            self.proof = Proof.INVARIANT
        if outcome.invariant:
            self.extra["invariant"] = outcome.invariant
        return proof

    def found(self, q: Query, goal: Goal, outcome: Outcome) -> Result:
        """The target was reached: decode the run, replay it, and say what it shows."""
        u, model = outcome.unroller, outcome.model
        assert u is not None and model is not None
        trace = decode(u, model, outcome.depth)
        if goal.found == Verdict.VIOLATED:  # mark the input fields the violation does not depend on
            free = free_fields(u, model, outcome.depth, goal.target(u.system))
            trace = tuple(replace(s, free=free.get(s.step - 1, ())) for s in trace)
        if isinstance(u.system.extension, MonitorExtension):
            trace = u.system.extension.around(u, model, outcome.depth, trace)
        why = goal.describe(u, model, outcome.depth)
        if outcome.reason:
            why = f"{why} ({outcome.reason})"
        if goal.found == Verdict.HOLDS and self.reasons:  # earlier goals found nothing wrong
            why = "; ".join([*self.reasons, f"witness: {why}"])
        replayed = replay_trace(q, self.a, goal, trace, initial_choices(u, model), self.ranges, self.consts)
        extra: dict[str, object] = {"replayed": replayed}
        if goal.found == Verdict.HOLDS and not self.parameters:  # a witness: does it rest on a choice?
            self.witnessed = True
            target = goal.target(u.system)
            left = unspecified(u.system, target, self.functions)
            if left:
                # The interpreter evaluates none of these: a run it replays whole met none, unless
                # it began with values that rest on one (the replay takes them from the run).
                if replayed == "yes" and not start_unspecified(u.system, self.functions) or \
                        every_interpretation(u, model, outcome.depth, target, self.functions, self.time_left()):
                    extra["unspecified"] = f"the run stands whatever the model leaves open ({', '.join(left)})"
                else:
                    return self.result(Verdict.UNKNOWN, f"{why}, but the run rests on what the model leaves open "
                                       f"({', '.join(left)}), and the claim needs every choice there (docs/"
                                       "semantics.md §6.4)", proof=Proof.NONE, depth=outcome.depth, trace=trace,
                                       extra=extra)
        if goal.details is not None:
            extra.update(goal.details(u, model, outcome.depth))
        if outcome.reason:  # `shortest="events"` could not finish
            extra["shortest"] = outcome.reason
        # a witness after goals shown only to the bound (`terminates`: nothing stuck within it) is
        # itself only to the bound
        proof = Proof.BOUNDED if goal.found == Verdict.HOLDS and self.proof == Proof.BOUNDED else Proof.TRACE
        return self.result(goal.found, why, proof=proof, depth=outcome.depth, trace=trace, extra=extra)

    def deterministic(self, q: Query, network: Network, consts: dict[str, ast.Expr]) -> Result:
        """`P is deterministic` (docs/semantics.md §7.10): no trace after which an event is both possible
        and stably refused (two runs side by side, `bmc.determinism`), and no divergence (a divergent
        process is not deterministic in the failures-divergences model, as FDR's check has it)."""
        negated = self.a.negated
        # First one run at a time: no configuration where the next visible event leaves the next step open.
        local = decide(TransitionSystem(network, self.ranges, consts), locally_nondeterministic, self.bound,
                       self.time_left(), self.induction, progress=self.progress)
        if local.status == Status.UNKNOWN:
            return self.result(Verdict.UNKNOWN, local.reason, proof=Proof.NONE, depth=local.depth)
        if local.status == Status.PROVED:
            self.proved(local)
            self.reasons.append("no configuration leaves the next step open once the next event is known (two "
                                "internal steps, an internal step beside an event, or one event two ways), shown for "
                                f"runs of every length ({local.reason}), so two runs with one trace are one run")
        elif local.status == Status.NOT_FOUND:
            self.proof = Proof.BOUNDED
            self.reasons.append(f"no configuration within {self.bound} steps leaves the next step open once the next "
                                "event is known, so two runs with one trace are one run")
        else:  # somewhere the next step is open: search pairs of runs for an event one does and the other refuses
            pair = self.from_open_step(local, network, consts)
            if pair is not None:
                return self.nondeterministic(q, pair)
            pair = nondeterminism(TransitionSystem(network, self.ranges, consts), self.bound, self.time_left())
            if pair.status == Status.UNKNOWN:
                return self.result(Verdict.UNKNOWN, pair.reason, proof=Proof.NONE, depth=pair.depth)
            if pair.status == Status.FOUND:
                return self.nondeterministic(q, pair)
            self.reasons.append(f"no event is both possible and refused after the same trace within {self.bound} "
                                "steps of two runs together")
            self.proof = Proof.BOUNDED
        for goal in q.goals:  # divergence
            decided = self.search(q, goal, network, consts)
            if decided is None:
                continue
            if decided.verdict == (Verdict.HOLDS if negated else Verdict.VIOLATED):  # a divergence
                return replace(decided, reason=f"{decided.reason}; a process that can diverge is not deterministic")
            if negated:  # no divergence: that alone does not make it deterministic
                return self.result(Verdict.UNKNOWN, "; ".join([*self.reasons, decided.reason or ""]) +
                                   "; a bounded search alone gives no verdict", proof=Proof.NONE, depth=self.bound)
            return decided
        if negated:
            return self.result(Verdict.UNKNOWN, "; ".join(self.reasons) + "; a bounded search alone gives no verdict",
                               proof=Proof.NONE, depth=self.bound)
        return self.result(Verdict.HOLDS, "; ".join(self.reasons), proof=self.proof,
                           depth=self.bound if self.proof == Proof.BOUNDED else self.depth, extra=self.extra)

    def from_open_step(self, local: Outcome, network: Network, consts: dict[str, ast.Expr]) -> Pair | None:
        """Two runs that part where the run `local` found leaves the next step open, searched from
        there (a few steps), with that run as their common prefix; None if they are not found so."""
        u, model = local.unroller, local.model
        assert u is not None and model is not None
        if u.system.side:  # functions without a body: their values along the prefix are not pinned down
            return None
        system = TransitionSystem(network, self.ranges, consts)
        left = self.time_left()
        pair = nondeterminism(system, SPLIT_DEPTH, None if left is None else left / 2,
                              configuration_of(u, model, local.depth))
        if pair.status != Status.FOUND:
            return None
        pair.prefix = decode(u, model, local.depth)
        pair.choices = initial_choices(u, model)
        return pair

    def nondeterministic(self, q: Query, pair: Pair) -> Result:
        """Two runs with the same trace, one doing an event the other refuses: decoded, replayed."""
        a, b, model = pair.a, pair.b, pair.model
        assert a is not None and b is not None and model is not None
        first = decode(a, model, pair.depth + 1)
        second = decode(b, model, pair.depth)
        run_a = [*pair.prefix, *(s for s, (moved, _) in zip(first, [*pair.moved, (True, False)], strict=True) if moved)]
        run_b = [*pair.prefix, *(s for s, (_, moved) in zip(second, pair.moved, strict=True) if moved)]
        trace = tuple(replace(s, step=j + 1) for j, s in enumerate(run_a))
        other = tuple(replace(s, step=j + 1) for j, s in enumerate(run_b))
        last = trace[-1]
        stable = ", ".join(f"{m}: {st}" for m, st in (other[-1].states if other else trace[0].states).items())
        before = [s.event for s in trace[:-1] if s.kind != "internal"]
        after = f"the trace ⟨{', '.join(str(e) for e in before)}⟩" if before else "the empty trace"
        why = (f"{q.element.name} is not deterministic: after {after}, one run can do {last.event} and another, "
               f"stable in [{stable}], refuses it")
        choices = pair.choices if pair.choices is not None else initial_choices(a, model)
        replayed = replay_pair(q, trace, other, choices, self.ranges, self.consts)
        verdict = Verdict.HOLDS if self.a.negated else Verdict.VIOLATED
        if replayed == "yes" and not self.parameters and not start_unspecified(a.system, self.functions):
            self.witnessed = True  # both runs replayed whole: neither met a function without a body
        return replace(self.result(verdict, why, proof=Proof.TRACE, depth=len(trace), trace=trace,
                                   extra={"replayed": replayed}), other_trace=other)

    def by_subsets(self, why: str) -> Result | None:
        """The specification-on-the-left half decided over the element's configurations, where the
        specification's traces are too many to list (`explicit.engine.included_by_subsets`): the
        result for the whole assertion, since the other half (if any) was shown to hold (or, for a
        negated one, to give no verdict), or None where the element's data is not finite."""
        from tockbmc.explicit.engine import included_by_subsets

        if self.q is None or not _interpreted_as_bmc(self.config.project, self.q, self.ranges):
            return None
        found = included_by_subsets(self.config.project, self.a, self.bound, self.config, self.time_left())
        if found is None:
            return None
        self.witnessed = True  # the interpreter's own configurations: it evaluated nothing left open
        how = (f"{why}, so the specification's states were paired with the sets of configurations the "
               "interpreter reaches by the same trace (finite under these ranges) instead: ")
        if found.verdict == Verdict.HOLDS and self.reasons:
            how = "; ".join(self.reasons) + "; " + how
        # A first half shown only up to the bound keeps the whole bounded.
        proof = Proof.TRACE if found.trace else Proof.BOUNDED if self.reasons and self.proof == Proof.BOUNDED \
            else Proof.EXHAUSTIVE
        return self.result(found.verdict, how + (found.reason or ""), trace=found.trace, depth=None, proof=proof,
                           extra=found.extra)

    def follow(self, q: Query, network: Network, consts: dict[str, ast.Expr]) -> Result | None:
        """Every trace of the specification on the model's right is one of the model's."""
        assert q.context is not None and q.inclusion is not None
        context = q.context

        def make(follower: Callable[[TransitionSystem], TraceFollower]) -> TransitionSystem:
            return TransitionSystem(network, self.ranges, consts, context=Following(context, follower))

        failures = self.a.semantic_model if self.a.semantic_model in (*FAILURES_MODELS, TICK_TOCK) else None
        # Where the interpreter could decide it over the element's configurations, the listing gets
        # half the time left, and the construction the rest (test13 UC0: 81 traces, each with its
        # refusal searches, spent 20 s; the construction takes 0.5 s).
        fallback = (self.a.semantic_model != TICK_TOCK and not self.functions
                    and _interpreted_as_bmc(self.config.project, q, self.ranges))
        start, share = time.perf_counter(), self.time_left()

        def listing_time() -> float | None:
            if share is None or not fallback:
                return self.time_left()
            return max(SPENT, share / 2 - (time.perf_counter() - start))

        inc = included(make, context.sem, q.inclusion, q.spec_name, q.element.name, self.bound, listing_time,
                       progress=self.progress, refusals=failures)
        if fallback and (inc.unlisted or inc.verdict == Verdict.UNKNOWN):
            whole = self.by_subsets(inc.reason)
            if whole is not None:
                return whole
        if inc.verdict == Verdict.VIOLATED and self.a.semantic_model == "failures divergences":
            # The element may have diverged on a prefix of the trace, after which the model allows
            # every trace and refusal: decided over its configurations where they are finite, else
            # only where no divergence is possible.
            whole = self.by_subsets(f"{inc.reason}, but in the failures-divergences model a divergence on the way "
                                    "allows every later trace and refusal")
            if whole is not None:
                return whole
            if may_diverge(TransitionSystem(network, self.ranges, consts, context=context)):
                inc = Inclusion(Verdict.UNKNOWN, f"{inc.reason}; but {q.element.name} may diverge, and after a "
                                                 "divergence the failures-divergences model allows every later trace "
                                                 "and refusal, so this decides nothing", inc.trace, inc.extra)
        if self.a.negated:
            if inc.verdict == Verdict.VIOLATED:
                return self.result(Verdict.HOLDS, inc.reason, proof=Proof.TRACE, depth=None, trace=inc.trace,
                                   extra=inc.extra)
            return self.result(Verdict.UNKNOWN, f"{inc.reason}; a bounded search alone gives no verdict"
                               if inc.verdict == Verdict.HOLDS else inc.reason, proof=Proof.NONE, depth=None,
                               trace=inc.trace, extra=inc.extra)
        if inc.verdict != Verdict.HOLDS:
            return self.result(inc.verdict, inc.reason, trace=inc.trace, depth=None,
                               proof=Proof.TRACE if inc.verdict == Verdict.VIOLATED else Proof.NONE, extra=inc.extra)
        self.proof = Proof.BOUNDED  # traces are listed up to a length only
        self.reasons.append(inc.reason)
        return None


def _values_of(q: Query, ranges: Ranges, consts: dict[str, ast.Expr]) -> Callable[[tuple], list[tuple] | None]:
    """Every value of each of the element's channels within the ranges, by the interpreter, so that
    a specification that accepts any value (`c?x`) can still have its traces listed."""
    from tockbmc.explicit.engine import channel_values, element_types, python_settings
    from tockbmc.explicit.interpreter import Interpreter, NotInterpretable

    assert q.context is not None
    literals = {v.text: v for v in q.context.sem.evaluator.literals.values()}
    made: list[Callable[[tuple], list[tuple] | None]] = []
    types = element_types(q.element)

    def values(prefix: tuple) -> list[tuple] | None:
        ts = types.get(tuple(prefix))
        event = str(prefix[0]).rsplit("::", 1)[-1]
        if ts is None or ranges.parametric or any(event in re.split(r"::|\.", path) for path in ranges.by_path) \
                or not all(_listed_as_bmc_bounds(t, ranges) for t in ts):
            return None  # the interpreter's listing might not be every value BMC's run can take
        if not made:  # the interpreter is built when a specification first asks
            try:
                interp = Interpreter(q.element, ranges, python_settings(consts), dict(q.defined),
                                     timed=q.timed)
                made.append(channel_values(interp, q.element, literals))
            except (NotInterpretable, Unsupported):
                made.append(lambda prefix: None)
        return made[0](prefix)

    return values


def _interpreted_as_bmc(project: ast.Project, q: Query, ranges: Ranges) -> bool:
    """Whether the interpreter's configurations of the element are exactly those BMC's runs reach:
    every value from outside (an input, a variable or constant without a value) of a type the
    interpreter lists as BMC bounds it (`_listed_as_bmc_bounds`: no real, whose range BMC takes
    whole and the interpreter by its integers; a natural only under `core_nat`), and no range of
    one path or parameter.  Every variable of the project counts, initialised or not."""
    from tockbmc.explicit.engine import element_types

    if ranges.parametric or ranges.by_path:
        return False
    groups: tuple[tuple[ast.Variable, ...], ...] = (
        *(h.variables for h in project.interfaces), *(h.variables for h in project.platforms),
        *(h.variables for h in project.machines), *(h.variables for h in project.controllers),
        *(h.variables for h in project.operations))
    types = [v.type for g in groups for v in g]
    types += [t for ts in element_types(q.element).values() for t in ts]
    return all(_listed_as_bmc_bounds(t, ranges) for t in types)


def _listed_as_bmc_bounds(t: ast.Type, ranges: Ranges) -> bool:
    """Whether the interpreter lists exactly the values of type `t` that BMC lets come from outside:
    an enumeration or a boolean, or an integer type with its own range (BMC reads `core_nat` for a
    natural, where the interpreter falls back on `core_int`); never a real (BMC takes every real of
    a range, the interpreter its integers).  Not an enumeration whose literals take parameters: a
    specification cannot name its values (RoboTool's CSP spelling of them is not known)."""
    if t == ast.BOOLEAN or (isinstance(t, ast.EnumType) and not t.params):
        return True
    if isinstance(t, ast.RecordType):  # a record's values, field by field
        return all(_listed_as_bmc_bounds(f.type, ranges) for f in t.fields)
    if t == ast.INT:
        return "core_int" in ranges.by_type
    if t == ast.NAT:
        return "core_nat" in ranges.by_type
    return isinstance(t, ast.GivenType) and t.name in ranges.by_type


def check_assertion(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration,
                    timeout: float | None, induction: bool = True, shortest: str = "steps",
                    progress: Progress | None = None) -> Result:
    """The verdict of one assertion: its goals searched in order (see `properties.goals.Query`).

    `progress` is told each depth a search clears.  The check has a Z3 context of its own, so its
    verdict, trace and time do not depend on what was checked before it in the same process: the
    same assertion gives the same result alone, after others, or in a worker process (`check -j`).
    """
    def decide(half: ast.Assertion, left: float | None) -> Result:
        with own_z3_context():
            return _Check(half, bound, config, left, induction, shortest, progress).run(project)

    return within_no_steps(decide_in_both(a, config.reading, timeout, decide))


@contextmanager
def own_z3_context() -> Iterator[None]:
    """Give Z3's main context (the one every term is built in by default) a fresh value inside the block.

    Z3's models depend on what its context has seen (the numbering of terms), so a counterexample
    found after other checks in one context can differ from the one found alone.  The engines build
    their terms in the main context; swapping it is the one place that knows.  Not for two threads
    at once: the main context is one per process.
    """
    previous = z3.z3._main_ctx  # noqa: SLF001 - z3py keeps it there; `main_ctx()` creates it on demand
    z3.z3._main_ctx = z3.Context()
    try:
        yield
    finally:
        z3.z3._main_ctx = previous


def replay_pair(q: Query, trace: tuple, other: tuple, choices: dict[str, object], ranges: Ranges,
                consts: dict[str, ast.Expr]) -> str:
    """Replay a nondeterminism: the interpreter follows the first run to its last event, and the
    second to a stable configuration that does not offer that event."""
    from tockbmc.explicit.replay import replay

    last = trace[-1]
    offered = {last.channel: last.values} if last.kind == "event" else {}

    def refuses(config: object, steps: list) -> bool:
        if any(s.kind == "internal" for s in steps):
            return False
        if last.kind == "tock":
            return not any(s.kind == "tock" for s in steps)
        return not any(s.event is not None and s.event.name == last.event for s in steps)

    def follow(interp: Interpreter) -> None:
        replay(interp, trace, choices, None, lambda config, steps: True)
        replay(interp, other, choices, None, lambda config, steps: refuses(config, interp.steps(config, offered)))

    return _replayed(q, ranges, consts, follow)


def _replayed(q: Query, ranges: Ranges, consts: dict[str, ast.Expr], follow: Callable[[Interpreter], None]) -> str:
    """Run `follow` with an interpreter of the query's element: "yes", or "no: why" when the
    interpreter cannot run the model or gave up following the trace (`ReplayGaveUp`: a bound on
    the configurations it explores); `ReplayFailure`, where it could not follow it, passes through."""
    from tockbmc.explicit.engine import python_settings
    from tockbmc.explicit.interpreter import Interpreter, NotInterpretable, Unbounded
    from tockbmc.explicit.replay import ReplayGaveUp

    try:
        follow(Interpreter(q.element, ranges, python_settings(consts), dict(q.defined), timed=q.timed))
    except (NotInterpretable, Unbounded, Unsupported) as exc:
        return f"no: {getattr(exc, 'what', None) or exc}"
    except ReplayGaveUp as exc:
        return f"no: {exc}"
    return "yes"


def _starts(system: TransitionSystem) -> bool:
    """Whether some initial configuration exists (False only when Z3 shows there is none)."""
    solver = z3.Solver()
    solver.set(timeout=5000)
    solver.add(system.init(), *system.invariants())
    return solver.check() != z3.unsat


def replay_trace(q: Query, a: ast.Assertion, goal: Goal, trace: tuple, choices: dict[str, object], ranges: Ranges,
                 consts: dict[str, ast.Expr]) -> str:
    """Replay a counterexample with the independent interpreter (`explicit.replay`).

    Returns "yes", or "no: why" when the interpreter cannot run the model (a construct it does
    not interpret); raises `ReplayFailure` when it runs it but cannot follow the trace.
    """
    from tockbmc.explicit.engine import is_state
    from tockbmc.explicit.replay import can_diverge, replay, replay_watched

    def follow(interp: Interpreter) -> None:
        if goal.failures:
            start, watch, refused = _refusal_check(q, a, interp)
            replay_watched(interp, trace, choices, q.context, start, watch, refused)
            return

        def final(config: object, steps: list) -> bool:
            if goal.target is diverges:  # the lasso: internal steps go on for ever from here
                return can_diverge(interp, config, q.context)  # type: ignore[arg-type]
            if goal.target is untimed_deadlocked:
                return not steps or can_diverge(interp, config, q.context)  # type: ignore[arg-type]
            if goal.target is terminated:
                return interp.terminated(config)  # type: ignore[arg-type]
            if goal.target is stuck:
                return not steps and not interp.terminated(config)  # type: ignore[arg-type]
            if goal.target is refuses_everything:  # untimed deadlock: termination included
                return not steps
            if goal.target is timelocked or a.kind == "timelock-free":
                return not any(s.kind in ("internal", "tock") for s in steps)
            if a.kind == "reachable":
                return any(is_state(m, s, a.subject) for m, s in interp.states(config).items())  # type: ignore[arg-type]
            return True

        replay(interp, trace, choices, q.context, final)

    return _replayed(q, ranges, consts, follow)


def _refusal_check(q: Query, a: ast.Assertion, interp: Interpreter
                   ) -> tuple[int, Callable[..., Hashable], Callable[[object, list, Hashable], bool]]:
    """How the interpreter checks where a failures or tick-tock refinement counterexample ends,
    following the specification's monitor along the run (the start, the step, the end):

    the monitor is dead (a traces violation, or, in the tick-tock model, a tock after a refusal
    no stable state of the specification that can let time pass makes, the monitor being
    filtered at each tock by the configuration's own offers, `ConcreteRefusals.after_tock`) or the
    element has terminated (what follows it is refused), or the configuration is stable and
    refuses, for each stable state of the specification, an event that state accepts
    (`ConcreteRefusals`); a divergence (a lasso) ends where internal steps go on, in the
    failures-divergences model."""
    from tockbmc.explicit.engine import ConcreteRefusals
    from tockbmc.properties.spec import Monitor

    context = q.context
    assert context is not None and context.spec is not None
    monitor = Monitor(context.sem, context.spec, [])
    refusals = ConcreteRefusals(interp, q, monitor)
    tick_tock = a.semantic_model == TICK_TOCK

    def visible(config: object) -> list | None:
        """The configuration's visible steps (None if it is not stable)."""
        steps = []
        for st in interp.steps(config):  # type: ignore[arg-type]
            status = "visible" if st.event is None else context.status(st.event.channel, len(st.event.values))
            if st.kind == "internal" or status == "hidden":
                return None
            if status != "blocked":
                steps.append(st)
        return steps

    def watch(state: Hashable, config: object, _steps: list, s: Step) -> Hashable:
        assert isinstance(state, int)
        if s.kind == "tock" and tick_tock:
            return refusals.after_tock(state, visible(config) or [])
        return monitor.after(state, refusals.event(s))

    def final(config: object, _steps: list, state: Hashable) -> bool:
        assert isinstance(state, int)
        if state == Monitor.DEAD or interp.terminated(config):  # type: ignore[arg-type]
            return True
        steps = visible(config)
        if steps is None:
            return a.semantic_model == "failures divergences"
        return refusals.failure(state, steps) is not None

    return monitor.initial, watch, final
