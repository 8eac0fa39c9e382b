"""The explicit-state engine: an interpreter of RoboChart models on concrete values, and search over it.

The interpreter (`interpreter.py`) implements `docs/semantics.md` §3–§6 directly on the resolved model
(`tockbmc.model.ast`) and shares no code with the symbolic encoding (`tockbmc.encodings`); the
search (`engine.py`) reads assertions through `properties.queries` and specifications through
the CSP monitors of `properties.spec`, and `replay.py` follows BMC's counterexamples.
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
