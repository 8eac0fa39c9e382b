"""Deciding assertions so that Ctrl-C stops at once, even inside Z3, and keeps what was decided.

Python delivers Ctrl-C to the main thread, between two bytecodes: a thread inside a long Z3 call
would not see it until the call returns. So the assertions are decided in a worker thread while
the main thread only waits; on Ctrl-C the main thread stops Z3 with `Z3_interrupt` (which is meant
to be called from another thread) and reports what the worker had decided.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from dataclasses import dataclass

import z3

from tockbmc.model import ast
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import Proof, Result, Verdict


@dataclass(frozen=True)
class Decided:
    """The results drawn, in order, and whether Ctrl-C stopped the drawing (`worker_done`: whether the
    worker had stopped within the grace period after it)."""

    results: list[Result]
    interrupted: bool = False
    worker_done: bool = True


def decide(results: Iterator[Result], grace: float = 0.5) -> Decided:
    """Draw `results` in a worker thread until they end or Ctrl-C; an exception of theirs is raised here.

    Z3 handles Ctrl-C itself while it solves (it ends that one query as `unknown` and carries on),
    so its handler is switched off: Ctrl-C must reach Python to stop the whole run. After Ctrl-C, a
    second one ends tockbmc at once, and the worker gets `grace` seconds to stop.
    """
    z3.set_param("ctrl_c", False)
    drawn: list[Result] = []
    failure: list[BaseException] = []
    done = threading.Event()  # not Thread.join: a join that Ctrl-C interrupts can wrongly report the end

    def work() -> None:
        try:
            for r in results:
                drawn.append(r)
        except BaseException as exc:  # noqa: B036 - handed to the main thread, which raises it
            failure.append(exc)
        finally:
            done.set()

    threading.Thread(target=work, name="tockbmc-decide", daemon=True).start()
    try:
        while not done.wait(0.05):
            pass
    except KeyboardInterrupt:
        decided = list(drawn)  # before Z3 is stopped: the query it stops would read "unknown"
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        z3.main_ctx().interrupt()
        return Decided(decided, interrupted=True, worker_done=done.wait(grace))
    if failure:
        raise failure[0]
    return Decided(drawn)


def interrupted(a: ast.Assertion, ranges: Ranges, engine: str) -> Result:
    """The result of an assertion that Ctrl-C stopped before its verdict."""
    return Result(assertion=a.name, text=a.text, verdict=Verdict.INTERRUPTED, bound=None, ranges=ranges.describe(),
                  seconds=0.0, reason="interrupted (Ctrl-C) before a verdict", proof=Proof.NONE, engine=engine,
                  pos=str(a.pos))
