"""Standard streams the command line can always write to.

A stream may be closed when tockbmc starts (`tockbmc show … >&-`), its reader may leave while
tockbmc writes (`tockbmc simulate … | head -1`), and its encoding may lack the symbols tockbmc
prints (`PYTHONIOENCODING=latin-1`). None of these is an error in the model or in tockbmc: output
that cannot be written is dropped, symbols that cannot be encoded are spelt in ASCII, and the exit
status still says what was found.
"""

from __future__ import annotations

import codecs
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

from rich.console import Console

ASCII_ERRORS = "tockbmc-ascii"

# What a character the stream cannot encode becomes; any other becomes "?" (one column, so that
# a caret under a source line stays under the right character).
SPELLINGS = {"τ": "tau", "✓": "tick", "→": "->", "…": "...", "–": "-", "—": "-", "§": "S", "δ": "delta",
             "├": "|", "└": "`", "│": "|", "─": "-", "┃": "|", "━": "-", "⇔": "<=>", "⇒": "=>", "≤": "<=",
             "≥": ">=", "≠": "!=", "∧": "/\\", "∨": "\\/", "⟨": "<", "⟩": ">", "∥": "||", "∪": "union",
             "·": ".", "⩤": "<|"}


def _spell(error: UnicodeError) -> tuple[str, int]:
    if not isinstance(error, UnicodeEncodeError):
        raise error
    text = error.object[error.start:error.end]
    return "".join(SPELLINGS.get(c, "?") for c in text), error.end


def usable_streams() -> list[str]:
    """Make `sys.stdout` and `sys.stderr` always writable; returns the names of those that were closed.

    A closed stream is replaced by one to the null device (on its own descriptor when that is free,
    so that nothing else opened later lands there); the others spell what they cannot encode in ASCII.
    """
    codecs.register_error(ASCII_ERRORS, _spell)
    closed = []
    for name, fd in (("stdout", 1), ("stderr", 2)):
        stream = getattr(sys, name)
        if stream is None:
            closed.append(name)
            setattr(sys, name, _null_stream(fd))
        elif hasattr(stream, "reconfigure"):
            stream.reconfigure(errors=ASCII_ERRORS)
    return closed


def _null_stream(fd: int) -> TextIO:
    try:
        os.fstat(fd)
    except OSError:  # free: put the null device there
        null = os.open(os.devnull, os.O_WRONLY)
        if null != fd:
            os.dup2(null, fd)
            os.close(null)
        return open(fd, "w", encoding="utf-8", closefd=False)
    return open(os.devnull, "w", encoding="utf-8")


@contextmanager
def reader_may_leave(stream: TextIO) -> Iterator[None]:
    """Write to `stream` in the block; if its reader leaves (a broken pipe), drop the rest of the output."""
    try:
        yield
        stream.flush()
    except BrokenPipeError:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, stream.fileno())  # Python's last flush at exit then finds a stream to write to
        os.close(null)


class PipeConsole(Console):
    """A rich console that lets `reader_may_leave` handle a broken pipe (rich itself exits with status 1)."""

    def on_broken_pipe(self) -> None:
        self.quiet = True
        raise BrokenPipeError
