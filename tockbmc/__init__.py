"""tockbmc: a symbolic bounded model checker for RoboChart models."""

from tockbmc.model import Diagnostic, ModelError, Project, load

__version__ = "0.1.0"

__all__ = ["Diagnostic", "ModelError", "Project", "__version__", "load"]
