"""The Lark parsers of tockbmc's grammars, built once per machine and kept in the user's cache.

Building an LALR parser from a grammar takes most of a second (the RoboChart grammar about 0.7 s,
the CSP one 0.2 s), which every command and every worker process would pay. Lark's own
`save`/`load` keep the built tables instead: in `$XDG_CACHE_HOME/tockbmc` (else
`~/.cache/tockbmc`), under a name that hashes the grammar, the options and the Lark and Python
versions, written whole (a temporary file renamed into place) so that processes started together
never read half a file. Where the directory cannot be written the parser is built each time, and a
cache file that cannot be read is built again; neither changes what is parsed.
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
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "tockbmc"


def build(grammar_file: str, **options: Any) -> Lark:
    """The LALR parser of `tockbmc/model/<grammar_file>` with these Lark options."""
    text = resources.files("tockbmc.model").joinpath(grammar_file).read_text()
    key = hashlib.sha256(repr((text, sorted(options.items()), lark.__version__, sys.version)).encode()).hexdigest()
    try:
        path = cache_dir() / f"{Path(grammar_file).stem}-{key[:20]}.lark"
        with path.open("rb") as f:
            return Lark.load(f)
    except Exception:  # no home, no cache file yet, or a damaged one: build the parser again
        pass
    parser = Lark(text, parser="lalr", **options)
    try:
        path = cache_dir() / f"{Path(grammar_file).stem}-{key[:20]}.lark"
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
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
