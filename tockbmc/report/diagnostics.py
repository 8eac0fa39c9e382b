"""Render diagnostics the way compilers do: location, message, source line, caret."""

from __future__ import annotations

from collections.abc import Iterable

from tockbmc.model.diagnostics import Diagnostic


def render(diagnostics: Iterable[Diagnostic], sources: dict[str, str]) -> str:
    """`path:line:col: error: message`, the offending line, and a caret under the column."""
    blocks = []
    for d in diagnostics:
        lines = [str(d)]
        text = sources.get(d.pos.path)
        if text is not None:
            source_lines = text.split("\n")
            if 1 <= d.pos.line <= len(source_lines):
                line = source_lines[d.pos.line - 1].replace("\t", " ")
                if len(line) > 200:  # keep very long lines readable around the column
                    start = max(0, d.pos.column - 100)
                    line = line[start:start + 200]
                    column = d.pos.column - start
                else:
                    column = d.pos.column
                width = 1
                if d.pos.end_line == d.pos.line and d.pos.end_column > d.pos.column:
                    width = min(d.pos.end_column - d.pos.column, max(1, len(line) - column + 1))
                lines.append(f"  {line}")
                lines.append("  " + " " * (column - 1) + "^" + "~" * (width - 1))
        blocks.append("\n".join(lines))
    return "\n".join(blocks)


def summary(diagnostics: Iterable[Diagnostic]) -> str:
    ds = list(diagnostics)
    errors = sum(1 for d in ds if d.severity == "error")
    warnings = len(ds) - errors
    parts = []
    if errors:
        parts.append(f"{errors} error{'s' if errors != 1 else ''}")
    if warnings:
        parts.append(f"{warnings} warning{'s' if warnings != 1 else ''}")
    return ", ".join(parts)
