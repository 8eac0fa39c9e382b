"""The Lark parsers of tockbmc's grammars, built once per machine and kept in the user's cache.

Building an LALR parser from a grammar takes most of a second (the RoboChart grammar about 0.7 s,
the CSP one 0.2 s), which every command and every worker process would pay. Lark's own
`save`/`load` keep the built tables instead: in `$XDG_CACHE_HOME/tockbmc` (else
`~/.cache/tockbmc`), under a name that hashes the grammar, the options and the Lark and Python
versions, written whole (a temporary file renamed into place) so that processes started together
never read half a file. A cache file is a pickle, which runs code when it is loaded, so it is read
only when it and its directory belong to this user and nobody else may write them. Where the
directory cannot be written, or is not private, the parser is built each time, and a cache file that
cannot be read is built again; neither changes what is parsed.
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
from importlib import resources
from pathlib import Path
from typing import Any

import lark
from lark import Lark


def cache_dir() -> Path:
    """`$XDG_CACHE_HOME/tockbmc`, else `~/.cache/tockbmc` (a relative `XDG_CACHE_HOME` is ignored, as
    the XDG specification says)."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    return (Path(base) if os.path.isabs(base) else Path.home() / ".cache") / "tockbmc"


def _private(path: Path) -> bool:
    """Whether `path` belongs to this user and nobody else may write it: a cache file is a pickle,
    which runs code when loaded, so one that someone else could have written is never read."""
    getuid = getattr(os, "getuid", None)
    if getuid is None:  # no POSIX owners (Windows): a user's own profile directory
        return True
    st = path.stat()
    return st.st_uid == getuid() and not st.st_mode & 0o022


def build(grammar_file: str, **options: Any) -> Lark:
    """The LALR parser of `tockbmc/model/<grammar_file>` with these Lark options."""
    text = resources.files("tockbmc.model").joinpath(grammar_file).read_text()
    key = hashlib.sha256(repr((text, sorted(options.items()), lark.__version__, sys.version)).encode()).hexdigest()
    try:
        path = cache_dir() / f"{Path(grammar_file).stem}-{key[:20]}.lark"
        if _private(path.parent) and _private(path):
            with path.open("rb") as f:
                return Lark.load(f)
    except Exception:  # no home, no cache file yet, or a damaged one: build the parser again
        pass
    parser = Lark(text, parser="lalr", **options)
    try:
        path = cache_dir() / f"{Path(grammar_file).stem}-{key[:20]}.lark"
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        if not _private(path.parent):  # someone else's, or open to others: no cache here
            return parser
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                parser.save(f)
            os.replace(tmp, path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    except (OSError, RuntimeError):  # RuntimeError: Path.home() with no home directory
        pass
    return parser
