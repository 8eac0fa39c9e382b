"""An assertion that says neither `timed` nor `untimed`, read as FDR's finite check (`--robotool`).

RoboTool writes such an assertion into both of its output files, the untimed semantics and the
timed one, and its users' checks pass only where FDR passes both (docs/robotool-evidence.md §0).
So under `--robotool` it is decided twice, once in each semantics (the untimed one first), and the
two verdicts are put together: violated where either is, holds where both hold. The other
readings keep tockbmc's own rule, the timed semantics alone (docs/semantics.md §7.8).

Forms RoboTool generates in the timed semantics only (timelock-freedom, the tick-tock model) are
decided once, timed. Both engines decide through `decide_in_both`, each with its own check of one
semantics.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace

from tockbmc.model import ast
from tockbmc.model.readings import Reading
from tockbmc.model.result import Proof, Result, Verdict
from tockbmc.properties.ticktock import TICK_TOCK

BOTH = ("timed", "untimed")
WHY = "an assertion without `timed` or `untimed` is checked in both semantics, as RoboTool checks it"


def semantics_of(a: ast.Assertion, reading: str) -> tuple[str, ...]:
    """The semantics `a` is decided in: its own prefix's, or both under `--robotool` where RoboTool
    generates both; () where the assertion's own query picks (tockbmc's rule: timed)."""
    if a.timing is not None or reading != Reading.ROBOTOOL:
        return ()
    if a.kind == "timelock-free" or (a.kind in ("refines", "equals") and a.semantic_model == TICK_TOCK):
        return ("timed",)  # RoboTool writes these into its timed file only
    return BOTH


def decide_in_both(a: ast.Assertion, reading: str, timeout: float | None,
                   decide: Callable[[ast.Assertion, float | None], Result]) -> Result:
    """`decide(a, timeout)` in each semantics `a` is read in, the verdicts put together.

    The untimed semantics, usually the cheaper (no `tock`), goes first with half the timeout; the
    timed one has what is left; a violation in the first ends it."""
    halves = semantics_of(a, reading)
    if not halves:
        return decide(a, timeout)
    order = sorted(halves, key=lambda timing: timing != "untimed")
    start = time.perf_counter()
    results: list[tuple[str, Result]] = []
    for n, timing in enumerate(order):
        if timeout is None:
            left: float | None = None
        elif n == 0 and len(order) > 1:
            left = timeout / 2
        else:
            left = timeout - (time.perf_counter() - start)
            if left <= 0:
                results.append((timing, replace(results[-1][1], verdict=Verdict.UNKNOWN, proof=Proof.NONE,
                                                 trace=(), other_trace=(), seconds=0.0,
                                                 reason=f"no time left for the {timing} semantics")))
                break
        decided = decide(replace(a, timing=timing), left)
        results.append((timing, decided))
        if decided.verdict == Verdict.VIOLATED:
            break  # one semantics that breaks it is enough
    return combined(results, len(halves), time.perf_counter() - start)


def combined(results: list[tuple[str, Result]], planned: int, seconds: float) -> Result:
    """One result of an assertion decided in the `planned` semantics (`results` in the order
    decided, short of `planned` where a violation ended it)."""
    verdicts = {timing: r.verdict.value for timing, r in results}
    extra: dict[str, object] = {"semantics": verdicts}
    if planned == 1:
        timing, only = results[0]
        return replace(only, seconds=seconds, extra={**only.extra, **extra},
                       reason=f"{only.reason or only.verdict.value} (in the {timing} semantics: RoboTool generates "
                              f"this form in the timed semantics only)")
    for timing, r in results:
        if r.verdict == Verdict.VIOLATED:
            return _told(r, timing, seconds, extra)
    if all(r.verdict == Verdict.HOLDS for _, r in results):
        base = next(r for timing, r in results if timing == "timed")  # its trace, where it has one
        proofs = [r.proof for _, r in results]
        bounded = [r for _, r in results if r.proof == Proof.BOUNDED]
        if bounded:  # the whole claim is as strong as its weaker half
            proof, depths = Proof.BOUNDED, [r.depth for r in bounded if r.depth is not None]
            depth = min(depths) if depths else None
        else:
            proof = Proof.TRACE if Proof.TRACE in proofs else base.proof
            depths = [r.depth for _, r in results if r.depth is not None]
            depth = max(depths) if depths else None
        reason = "; ".join(f"{timing}: {r.reason}" for timing, r in results if r.reason)
        return replace(base, seconds=seconds, proof=proof, depth=depth, extra={**base.extra, **extra},
                       reason=f"holds in both the timed and the untimed semantics ({WHY})"
                              + (f"; {reason}" if reason else ""))
    for wanted in (Verdict.UNSUPPORTED, Verdict.UNKNOWN):
        for timing, r in results:
            if r.verdict == wanted:
                return _told(r, timing, seconds, extra)
    raise AssertionError(f"no verdict to put together from {verdicts}")


def _told(r: Result, timing: str, seconds: float, extra: dict[str, object]) -> Result:
    """`r`, decided in `timing`, as the result of the assertion read in both semantics."""
    proof = r.proof if r.verdict in (Verdict.VIOLATED, Verdict.HOLDS) else Proof.NONE
    return replace(r, seconds=seconds, proof=proof, extra={**r.extra, **extra},
                   reason=f"in the {timing} semantics ({WHY}): {r.reason or r.verdict.value}")
