"""`check`: decide the assertions of a loaded project (the API behind `tockbmc check`)."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator

from tockbmc.bmc.engine import bmc
from tockbmc.bmc.result import Result
from tockbmc.encodings.automaton import Unsupported
from tockbmc.encodings.composition import network_of
from tockbmc.encodings.system import System, check_encodable
from tockbmc.encodings.values import Ranges
from tockbmc.model import ast
from tockbmc.model.csp import CspError
from tockbmc.model.limits import TOO_DEEP_TO_CHECK
from tockbmc.properties.inclusion import Following, TraceFollower, Unenumerable, included
from tockbmc.properties.process import MonitorExtension
from tockbmc.properties.queries import Goal, NotSupported, Query, query
from tockbmc.report.trace import decode, initial_choices

DEFAULT_BOUND = 40


def check(project: ast.Project, names: Iterable[str] | None = None, bound: int = DEFAULT_BOUND,
          ranges: Ranges | None = None, settings: dict[str, ast.Expr] | None = None,
          timeout: float | None = None, induction: bool = True, shortest: str = "steps") -> list[Result]:
    """One `Result` per selected assertion (all by default), in file order.

    `induction=False` leaves BMC alone (to measure it); verdicts within the bound are the same.
    `shortest="events"` makes each counterexample one with the fewest visible steps (events and
    `tock`s) within the bound, rather than the first found, of fewest steps; it costs an unrolling
    to the bound.
    """
    return list(iter_check(project, names, bound, ranges, settings, timeout, induction, shortest))


def iter_check(project: ast.Project, names: Iterable[str] | None = None, bound: int = DEFAULT_BOUND,
               ranges: Ranges | None = None, settings: dict[str, ast.Expr] | None = None,
               timeout: float | None = None, induction: bool = True, shortest: str = "steps") -> Iterator[Result]:
    """`check`'s results one at a time, each as soon as it is decided."""
    ranges = ranges or Ranges()
    wanted = set(names) if names is not None else None
    for a in project.assertions:
        if wanted is None or a.name in wanted:
            yield check_assertion(project, a, bound, ranges, settings or {}, timeout, induction, shortest)


def check_assertion(project: ast.Project, a: ast.Assertion, bound: int, ranges: Ranges,
                    settings: dict[str, ast.Expr], timeout: float | None, induction: bool = True,
                    shortest: str = "steps") -> Result:
    """The verdict of one assertion: its goals searched in order (see `properties.queries.Query`)."""
    start = time.perf_counter()
    described = ranges.describe()
    pos = str(a.pos)

    def result(verdict: str, reason: str | None, trace: tuple = (), searched: int | None = bound,
               extra: dict | None = None) -> Result:
        return Result(a.name, a.text, verdict, searched, described, time.perf_counter() - start, reason,
                      trace=trace, pos=pos, extra=extra or {})

    try:
        q = query(project, a)
        network = network_of(q.element, dict(q.defined))
        check_encodable(network)
        consts = dict(settings)
        consts.update(dict(q.settings))
        consts.update({s.constant: s.value for s in a.settings if s.kind == "constant"})
        reasons: list[str] = []
        for goal in q.goals:
            remaining = None if timeout is None else max(0.001, timeout - (time.perf_counter() - start))
            def build(tag: str = "", goal: Goal = goal) -> System:
                s = System(network, ranges, consts, tag=tag, context=q.context)
                if goal.prepare is not None:
                    goal.prepare(s)
                return s

            system = build()
            if not goal.applies(system):
                if goal.skipped:
                    reasons.append(goal.skipped)
                continue
            prover = (lambda: build("k.")) if goal.stateless and induction else None
            outcome = bmc(system, goal.target, bound, remaining, prover, fewest_visible=shortest == "events")
            if outcome.status == "unknown":
                return result("unknown", outcome.reason)
            if outcome.status == "found":
                assert outcome.model is not None
                trace = decode(system, outcome.model, outcome.depth)
                if isinstance(system.extension, MonitorExtension):
                    trace = system.extension.around(system, outcome.model, outcome.depth, trace)
                why = goal.describe(system, outcome.model, outcome.depth)
                if outcome.reason:
                    why = f"{why} ({outcome.reason})"
                if goal.found == "holds" and reasons:  # earlier goals found nothing wrong
                    why = "; ".join([*reasons, f"witness: {why}"])
                replayed = replay_trace(q, a, goal, trace, initial_choices(system, outcome.model), ranges, consts)
                extra = {"replayed": replayed}
                if outcome.reason:  # `shortest="events"` could not finish
                    extra["shortest"] = outcome.reason
                return result(goal.found, why, trace=trace, extra=extra)
            if outcome.status == "proved":
                verdict = goal.unreachable
                why = (f"{goal.claim}, shown for runs of every length, not only up to {bound} steps "
                       f"({outcome.reason})" if verdict == "holds"
                       else f"no run of any length reaches {goal.sought} ({outcome.reason})")
            elif goal.not_found == "holds":
                verdict, why = "holds", f"{goal.claim} within {bound} steps"
            else:
                verdict, why = "unknown", f"not found within {bound} steps; a bounded search alone gives no verdict"
            if verdict != "holds":
                return result(verdict, why)
            reasons.append(why)
        if q.inclusion is not None:
            assert q.context is not None
            context = q.context

            def make(follower: Callable[[System], TraceFollower] | None, tag: str) -> System:
                assert follower is not None
                return System(network, ranges, consts, tag=tag, context=Following(context, follower))

            def time_left() -> float | None:
                return None if timeout is None else max(0.001, timeout - (time.perf_counter() - start))

            inc = included(make, context.sem, q.inclusion, q.spec_name, q.element.name, bound, time_left)
            if a.negated:
                if inc.verdict == "violated":
                    return result("holds", inc.reason, trace=inc.trace)
                return result("unknown", f"{inc.reason}; a bounded search alone gives no verdict"
                              if inc.verdict == "holds" else inc.reason, trace=inc.trace)
            if inc.verdict != "holds":
                return result(inc.verdict, inc.reason, trace=inc.trace)
            reasons.append(inc.reason)
    except Unenumerable as exc:
        return result("unsupported", f"the traces of the specification cannot be listed: {exc}", searched=None)
    except NotSupported as exc:
        return result("unsupported", str(exc), searched=None)
    except (Unsupported, CspError) as exc:
        return result("unsupported", f"{exc.what} ({exc.pos})")
    except RecursionError:
        return result("unsupported", TOO_DEEP_TO_CHECK, searched=None)
    return result("holds", "; ".join(reasons))


def replay_trace(q: Query, a: ast.Assertion, goal: Goal, trace: tuple, choices: dict[str, object], ranges: Ranges,
                 consts: dict[str, ast.Expr]) -> str:
    """Replay a counterexample with the independent interpreter (`explicit.replay`).

    Returns "yes", or "no: why" when the interpreter cannot run the model (a construct it does
    not interpret); raises `ReplayFailure` when it runs it but cannot follow the trace.
    """
    from tockbmc.explicit.engine import is_state, python_settings, ranges_dict
    from tockbmc.explicit.interpreter import Interpreter, NotInterpretable, Unbounded
    from tockbmc.explicit.replay import replay
    from tockbmc.properties.queries import stuck, terminated, timelocked

    try:
        interp = Interpreter(q.element, ranges_dict(ranges), python_settings(consts), dict(q.defined))

        def final(config: object, steps: list) -> bool:
            if goal.target is terminated:
                return interp.terminated(config)  # type: ignore[arg-type]
            if goal.target is stuck:
                return not steps and not interp.terminated(config)  # type: ignore[arg-type]
            if goal.target is timelocked or a.kind == "timelock-free":
                return not any(s.kind in ("internal", "tock") for s in steps)
            if a.kind == "reachable":
                return any(is_state(m, s, a.subject) for m, s in interp.states(config).items())  # type: ignore[arg-type]
            return True

        replay(interp, trace, choices, q.context, final)
    except (NotInterpretable, Unbounded, NotSupported) as exc:
        return f"no: {getattr(exc, 'what', None) or exc}"
    return "yes"
