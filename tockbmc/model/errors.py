"""The one exception every layer raises for what tockbmc does not check yet.

A check that meets such a construct reports the assertion `unsupported` with
the reason and, where the construct has one, its source position; it never
skips it silently.
"""

from __future__ import annotations

from tockbmc.model.position import Pos


class Unsupported(Exception):
    """A construct or assertion form tockbmc cannot check yet: what it is, and where (if known)."""

    def __init__(self, pos: Pos | None, what: str):
        super().__init__(what)
        self.pos = pos
        self.what = what

    @property
    def reason(self) -> str:
        """The text a result gives: what is unsupported, then where."""
        return self.what if self.pos is None else f"{self.what} ({self.pos})"
