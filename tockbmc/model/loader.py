"""`load`: read a RoboChart project from files and directories."""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Iterable, Iterator
from pathlib import Path

from lark import Tree

from tockbmc.model.ast import Pos, Project
from tockbmc.model.diagnostics import Diagnostic, ModelError
from tockbmc.model.limits import recursion_room
from tockbmc.model.parser import parse
from tockbmc.model.resolver import Resolver

SUFFIXES = {".rct": "rct", ".assertions": "assertions"}


def project_files(paths: Iterable[str | os.PathLike[str]]) -> list[Path]:
    """The `.rct` and `.assertions` files named by `paths`, directories searched below."""
    found: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            found += sorted(_model_files(p))
        else:
            found.append(p)
    # One file named two ways ('d/a.rct', 'd/../d/a.rct') is loaded once.
    unique: dict[Path, Path] = {}
    for f in found:
        unique.setdefault(f.resolve(), f)
    return list(unique.values())


def _model_files(root: Path) -> Iterator[Path]:
    """The model files below a directory. A folder that cannot be read, or that vanishes while it
    is walked (`/proc`'s), is passed over: its files are not the model's."""
    for folder, _dirs, names in os.walk(root, onerror=lambda _error: None):
        for name in names:
            f = Path(folder, name)
            with contextlib.suppress(OSError):
                if f.suffix in SUFFIXES and f.is_file():
                    yield f


def load(*paths: str | os.PathLike[str]) -> Project:
    """Load, resolve and check a project; raises `ModelError` with every problem found."""
    files = project_files(paths)
    texts: dict[str, str] = {}
    diagnostics: list[Diagnostic] = []
    parsed: list[tuple[str, str, Tree]] = []
    for f in files:
        name = str(f)
        kind = SUFFIXES.get(f.suffix)
        if not f.exists():
            diagnostics.append(Diagnostic(Pos(name, 1, 1), "no such file or directory"))
            continue
        if not f.is_file():  # a FIFO or a device would block or never end
            diagnostics.append(Diagnostic(Pos(name, 1, 1), "not a regular file: expected a .rct or .assertions file"))
            continue
        if kind is None:
            diagnostics.append(Diagnostic(Pos(name, 1, 1), "not a RoboChart file: expected a .rct or .assertions file"))
            continue
        try:
            text = f.read_text(encoding="utf-8-sig")  # tolerate a byte order mark
        except (OSError, UnicodeDecodeError) as exc:
            diagnostics.append(Diagnostic(Pos(name, 1, 1), f"cannot read file: {exc}"))
            continue
        texts[name] = text
        tree, errors = parse(text, name, kind)
        diagnostics += errors
        if tree is not None:
            parsed.append((name, kind, tree))
    if not files:
        raise ModelError([Diagnostic(Pos(str(next(iter(map(str, paths)), ".")), 1, 1),
                                     "no .rct or .assertions files found")], texts)
    resolver = Resolver(parsed)
    root = str(paths[0]) if paths else "."
    # The resolver recurses a few frames per level of nesting (at most `MAX_NESTING`, see `parse`).
    with recursion_room():
        project = resolver.resolve(root, texts)
    diagnostics += resolver.diagnostics
    errors = [d for d in diagnostics if d.severity == "error"]
    if errors or project is None:
        raise ModelError(diagnostics, texts)
    return dataclasses.replace(project, warnings=tuple(diagnostics))
