"""The names of a configuration's scalars and of a step's inputs: made here and nowhere else.

A configuration is a flat set of named scalars (`EXAX.loc`, `EXAX.clock.C`,
`buffer0.full`, `monitor`); the unroller appends `@k` to name one at step k.
"""

from __future__ import annotations


def location(component: str) -> str:
    """The machine's location in its automaton."""
    return f"{component}.loc"


def wait(component: str, thread: int = 0) -> str:
    """Tocks left of a running `wait`; thread 1 is a composite state's `during` action, which runs
    beside the state's children (docs/semantics.md §4.1) and has a `wait` of its own."""
    return f"{component}.wait" if thread == 0 else f"{component}.during_wait"


def deadline(component: str) -> str:
    """Tocks left of a statement deadline."""
    return f"{component}.deadline"


def clock(component: str, name: str) -> str:
    return f"{component}.clock.{name}"


def armed(component: str, transition: str) -> str:
    """Tocks that a trigger deadline's transition has waited armed."""
    return f"{component}.armed.{transition}"


# The machine's bookkeeping scalars above are `M.<word>`: a variable of one of these names is kept
# apart from them by a `#` (no RoboChart name has one), so that `var loc : int` is not `M.loc`.
_BOOKKEEPING = frozenset({"loc", "wait", "during_wait", "deadline", "clock", "armed", "wait_length"})


def variable(component: str, name: str, operation: str = "") -> str:
    """A machine's own variable (or an inlined operation's: `M.op().x`)."""
    if operation:
        return f"{component}.{operation}().{name}"
    slot = f"{component}.{name}"
    return f"{slot}#" if name in _BOOKKEEPING or _global(slot) else slot


def shared(key: str) -> str:
    """The slot of a variable machines share: a controller's (`C.x`) or the platform's (`x`)."""
    return f"{key}#" if _global(key) else key


def _global(slot: str) -> bool:
    """Whether a variable's slot would be one of the scalars below that belong to no machine, or
    lead to one (a record's fields are `slot.field`): a machine or controller named `loop` with
    `var saved` or `var copy`, `buffer0` with `var full`, a platform's `var prev`."""
    if slot in (PREVIOUS, MONITOR, FOLLOW, LOOP_SAVED, LOOP_SAVE) or slot == "loop.copy" or slot.startswith("loop.copy."):
        return True
    head, _, field = slot.partition(".")
    return head.startswith("buffer") and head[6:].isdigit() and field in ("full", "value")


def next_copy(key: str) -> str:
    """Which copy a shared variable's memory passes its value to next (RoboTool's memory model;
    the number of copies when it passes none)."""
    return f"{key}#next"


def passing(key: str) -> str:
    """The value a shared variable's memory is passing on to the copies."""
    return f"{key}#passing"


def constant(component: str, name: str) -> str:
    return f"{component}::{name}"


def buffer_full(link: int) -> str:
    return f"buffer{link}.full"


def buffer_value(link: int) -> str:
    return f"buffer{link}.value"


def input_value(event: str) -> str:
    """The value the environment offers on an input event during a step."""
    return f"in.{event}"


def fresh_value(slot: str) -> str:
    """Any value of a variable's type, chosen during a step (an operation's uninitialised variable)."""
    return f"{slot}.fresh"


def wait_length(component: str) -> str:
    """The length a `wait(a, b)` picks during the step that starts it."""
    return f"{component}.wait_length"


PREVIOUS = "prev"  # the move the step before took (-1 before the first): orders independent internal steps
MONITOR = "monitor"  # a specification monitor's state (properties.process)
FOLLOW = "follow"  # how much of a specification trace the model has done (properties.inclusion)
LOOP_SAVED = "loop.saved"  # divergence: a configuration has been saved (properties.deadlock)
LOOP_SAVE = "loop.save"  # divergence: the configuration is saved in this step


def loop_copy(slot: str) -> str:
    """The saved copy of a scalar (divergence)."""
    return f"loop.copy.{slot}"


def is_loop_slot(slot: str) -> bool:
    """The divergence check's own scalars (not a machine's: a machine may be named `loop`)."""
    return slot in (LOOP_SAVED, LOOP_SAVE) or slot.startswith("loop.copy.")
