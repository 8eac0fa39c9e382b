"""Problems found in input files, as values with a source position."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass

from tockbmc.model.position import Pos
from tockbmc.model.rules import cite


@dataclass(frozen=True)
class Diagnostic:
    """One problem: where it is, what it is, and the RoboTool rule it enforces (`model.rules`;
    '' for a warning, an `unsupported` construct or a problem with the files themselves)."""

    pos: Pos
    message: str
    severity: str = "error"
    rule: str = ""

    def __str__(self) -> str:
        return f"{self.pos}: {self.severity}: {self.message}{cite(self.rule)}"


class ModelError(Exception):
    """Raised by `load` when the input has errors; carries all of them."""

    def __init__(self, diagnostics: Iterable[Diagnostic], sources: dict[str, str]):
        self.diagnostics = tuple(sorted(diagnostics, key=_order))
        self.sources = sources
        super().__init__("\n".join(str(d) for d in self.diagnostics))


def _order(d: Diagnostic) -> tuple[str, int, int]:
    return (d.pos.path, d.pos.line, d.pos.column)


def suggestion(name: str, known: Iterable[str]) -> str:
    """`; did you mean 'x'?` for the closest known name, or ''."""
    candidates = sorted(set(known) - {name})
    match = [c for c in candidates if c.lower() == name.lower()][:1] or \
        difflib.get_close_matches(name, candidates, n=1, cutoff=0.6)
    if not match:
        short = name.rsplit("::", 1)[-1]
        by_short = {c.rsplit("::", 1)[-1]: c for c in candidates}
        close = difflib.get_close_matches(short, sorted(by_short), n=1, cutoff=0.6)
        match = [by_short[close[0]]] if close else []
    return f"; did you mean '{match[0]}'?" if match else ""
