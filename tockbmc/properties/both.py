"""An assertion that says neither `timed` nor `untimed`, read as FDR's finite check (`--robotool`).

RoboTool writes such an assertion into both of its output files, the untimed semantics and the
timed one, and its users' checks pass only where FDR passes both (docs/robotool-evidence.md §0).
So under `--robotool` it is decided twice, once in each semantics, and the two verdicts are put
together: violated where either is, holds where both hold. The other readings keep tockbmc's own
rule, the timed semantics alone (docs/semantics.md §7.8).

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

    The halves share the timeout: the second gets what the first left."""
    halves = semantics_of(a, reading)
    if not halves:
        return decide(a, timeout)
    start = time.perf_counter()
    results: list[tuple[str, Result]] = []
    for timing in halves:
        left = None if timeout is None else max(1.0, timeout - (time.perf_counter() - start))
        decided = decide(replace(a, timing=timing), left)
        results.append((timing, decided))
        if decided.verdict == Verdict.VIOLATED:
            break  # one semantics that breaks it is enough
    return combined(results, time.perf_counter() - start)


def combined(results: list[tuple[str, Result]], seconds: float) -> Result:
    """One result of an assertion decided in one or both semantics (in order, the last maybe short)."""
    verdicts = {timing: r.verdict.value for timing, r in results}
    extra: dict[str, object] = {"semantics": verdicts}
    if len(results) == 1:
        timing, only = results[0]
        return replace(only, seconds=seconds, extra={**only.extra, **extra},
                       reason=f"{only.reason or only.verdict.value} (in the {timing} semantics: RoboTool generates "
                              f"this form in the timed semantics only)")
    for timing, r in results:
        if r.verdict == Verdict.VIOLATED:
            return _told(r, timing, seconds, extra)
    if all(r.verdict == Verdict.HOLDS for _, r in results):
        first = results[0][1]
        weakest = next((r.proof for _, r in results if not r.proof.every_length), first.proof)
        depths = [r.depth for _, r in results if r.depth is not None]
        reason = "; ".join(f"{timing}: {r.reason}" for timing, r in results if r.reason)
        return replace(first, seconds=seconds, proof=weakest, depth=max(depths) if depths else None,
                       extra={**first.extra, **extra},
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
