"""The model layer: parse `.rct`/`.assertions` files into a resolved `Project`."""

from tockbmc.model.ast import Project
from tockbmc.model.diagnostics import Diagnostic, ModelError
from tockbmc.model.loader import load

__all__ = ["Diagnostic", "ModelError", "Project", "load"]
