"""Deciding assertions so that Ctrl-C stops at once, even inside Z3, and keeps what was decided.

Python delivers Ctrl-C to the main thread, between two bytecodes: a thread inside a long Z3 call
would not see it until the call returns. So the assertions are decided in a worker thread while
the main thread only waits; on Ctrl-C the main thread stops Z3 with `Z3_interrupt` (which is meant
to be called from another thread) and reports what the worker had decided.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Generic, TypeVar

import z3

from tockbmc.model import ast
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import Proof, Result, Verdict
from tockbmc.parallel import ctrl_c_held

T = TypeVar("T")


class Terminated(KeyboardInterrupt):
    """SIGTERM (a CI runner's, `timeout`'s): handled as Ctrl-C is, and told apart by its exit status."""


def terminate_as_interrupt() -> None:
    """Make SIGTERM raise `Terminated` in the main thread, as SIGINT raises KeyboardInterrupt, so
    that the verdicts decided are printed and the worker processes ended (only from the main thread)."""
    def raise_terminated(_signum: int, _frame: object) -> None:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # a second SIGTERM ends tockbmc at once
        raise Terminated

    signal.signal(signal.SIGTERM, raise_terminated)


@dataclass(frozen=True)
class Decided(Generic[T]):
    """The items drawn, in order, and whether Ctrl-C stopped the drawing (`worker_done`: whether the
    worker had stopped within the grace period after it)."""

    results: list[T]
    interrupted: bool = False
    worker_done: bool = True
    overran: int | None = None  # the item `overdue` named: its worker thread was given up
    signal: int = signal.SIGINT  # what interrupted it: SIGINT (Ctrl-C) or SIGTERM


def decide(items: Iterable[T], grace: float = 0.5, on_item: Callable[[T], None] | None = None,
           stop: Callable[[], None] | None = None, overdue: Callable[[], int | None] | None = None) -> Decided[T]:
    """Draw `items` (results, or anything that carries them) in a worker thread until they end or
    Ctrl-C; an exception of theirs is raised here.

    `on_item` is called in this thread with each item as soon as it is drawn (to print it), Ctrl-C
    held back meanwhile so that a line is never cut in two; after Ctrl-C it still gets each item
    drawn before.  On Ctrl-C, `stop` is called to stop whatever decides the items elsewhere (worker
    processes, a cluster's tasks).

    Z3 handles Ctrl-C itself while it solves (it ends that one query as `unknown` and carries on),
    so its handler is switched off: Ctrl-C must reach Python to stop the whole run. After Ctrl-C, a
    second one ends tockbmc at once, and the worker gets `grace` seconds to stop.

    `overdue`, asked as the main thread waits, names an item whose decision has run past its hard
    limit (Z3 not stopping at its timeout): the drawing stops as on Ctrl-C, and `overran` says which.
    """
    z3.set_param("ctrl_c", False)
    drawn: list[T] = []
    failure: list[BaseException] = []
    done = threading.Event()  # not Thread.join: a join that Ctrl-C interrupts can wrongly report the end
    handed = 0  # items given to `on_item`

    def work() -> None:
        try:
            for item in items:
                drawn.append(item)
        except BaseException as exc:  # noqa: B036 - handed to the main thread, which raises it
            failure.append(exc)
        finally:
            done.set()

    def hand_over(upto: int) -> None:
        nonlocal handed
        while on_item is not None and handed < upto:
            with ctrl_c_held():
                on_item(drawn[handed])
                handed += 1

    threading.Thread(target=work, name="tockbmc-decide", daemon=True).start()
    try:
        while not done.wait(0.05):
            hand_over(len(drawn))
            late = overdue() if overdue is not None else None
            if late is not None:
                z3.main_ctx().interrupt()
                finished = done.wait(grace)  # a result that comes in the grace is kept
                decided = list(drawn)
                hand_over(len(decided))
                return Decided(decided, worker_done=finished, overran=late)
        hand_over(len(drawn))
    except KeyboardInterrupt as exc:
        decided = list(drawn)  # before Z3 is stopped: the query it stops would read "unknown"
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        z3.main_ctx().interrupt()
        if stop is not None:
            stop()
        hand_over(len(decided))
        received = signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT
        return Decided(decided, interrupted=True, worker_done=done.wait(grace), signal=received)
    if failure:
        raise failure[0]
    return Decided(drawn)


def interrupted(a: ast.Assertion, ranges: Ranges, engine: str) -> Result:
    """The result of an assertion that Ctrl-C (or SIGTERM) stopped before its verdict."""
    return Result(assertion=a.label, text=a.text, verdict=Verdict.INTERRUPTED, bound=None, ranges=ranges.describe(),
                  seconds=0.0, reason="interrupted (Ctrl-C or SIGTERM) before a verdict", proof=Proof.NONE,
                  engine=engine, pos=str(a.pos))
