"""An explicit-state interpreter of RoboChart models: the second opinion on the symbolic encoding.

It implements `docs/semantics.md` §3–§6 directly on the resolved model (`tockbmc.model.ast`)
and shares no code with `tockbmc.encodings`, `tockbmc.properties` or `tockbmc.bmc`.
"""

from tockbmc.explicit.interpreter import (
    Config,
    Event,
    Interpreter,
    NotInterpretable,
    Record,
    Step,
    Unbounded,
)

__all__ = ["Config", "Event", "Interpreter", "NotInterpretable", "Record", "Step", "Unbounded"]
