"""A portfolio, in the manner of Kind 2: BMC with k-induction, and Spacer's PDR beside it in a process.

BMC finds shortest counterexamples and k-induction proves what is inductive
after a few steps; PDR proves what needs a stronger invariant (a whole module
that never terminates).  Spacer runs in a process of its own, on the other
core; BMC asks between depths whether it has answered.  (No thread interrupts BMC's solver
call: a Z3 interrupt from another thread was seen to corrupt the main context's solver now and
then, as a Horn query solved in a thread beside it did.)
Whichever decides first decides; the other is stopped.  When BMC reaches its
bound with nothing found, Spacer is given a little longer (as long as BMC took, between 1 s and `GRACE`) to turn
"within the bound" into "for every length".  Every invariant is checked again
in a fresh solver before a verdict rests on it (`pdr.confirmed`).
"""

from __future__ import annotations

import time

from tockbmc.bmc.engine import Outcome, Progress, Status, bmc
from tockbmc.bmc.pdr import Spacer, applicable, confirmed, describe
from tockbmc.encodings.system import Target, TransitionSystem

GRACE = 10.0  # most seconds Spacer may go on once BMC has reached its bound (at least 1 s, at most as long as BMC took)


def decide(system: TransitionSystem, target: Target, bound: int, timeout: float | None = None,
           induction: bool = True, fewest_visible: bool = False, progress: Progress | None = None) -> Outcome:
    """BMC (with k-induction when `induction`) and, when it applies, PDR: the first to decide.
    `progress` is told each depth BMC clears."""
    start = time.monotonic()
    goal = target(system)
    if not induction or applicable(system, goal) is not None:
        return bmc(system, target, bound, timeout, induction, fewest_visible, progress=progress)
    spacer = Spacer(system, goal)
    spacer.start(timeout)
    try:
        outcome = bmc(system, target, bound, timeout, induction, fewest_visible,
                      stop=lambda: spacer.wait(0) == "proved", progress=progress)
        if outcome.status in (Status.FOUND, Status.PROVED):
            return outcome
        took = time.monotonic() - start
        grace = min(GRACE, max(1.0, took))
        left = None if timeout is None else timeout - took
        spacer.wait(grace if left is None else max(0.0, min(grace, left)))
    finally:
        spacer.kill()
        spacer.wait(None)  # reaps the child
    if spacer.status == "proved":
        invariant = spacer.invariant()
        if confirmed(system, goal, invariant):
            return Outcome(Status.PROVED, outcome.depth, reason="an inductive invariant excludes it (found by "
                           "Spacer's PDR, checked again in a fresh solver)", method="invariant",
                           invariant=describe(system, invariant))
    return outcome
