"""tockbmc: a symbolic bounded model checker for RoboChart models."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # imported when first used: the command starts without them (tockbmc.launch)
    from tockbmc.model import Diagnostic, ModelError, Project, load

__version__ = "0.1.0"

__all__ = ["Diagnostic", "ModelError", "Project", "__version__", "load"]


def __getattr__(name: str) -> Any:
    if name in ("Diagnostic", "ModelError", "Project", "load"):
        from tockbmc import model

        return getattr(model, name)
    raise AttributeError(f"module 'tockbmc' has no attribute {name!r}")
