"""Fuzzing the loader: whatever bytes a model's files hold, `load` returns a project or raises
`ModelError`, and its diagnostics render.

Hypothesis mutates one file of a project (the IntelliWelder example, or a case of RoboTool's
regression suite in `../shared/conformance`, when it is there) at the level of bytes, characters,
lines or words, or makes its numbers extreme, and loads the whole project.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

from conftest import CONFORMANCE, EXAMPLE
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tockbmc import ModelError, Project, load
from tockbmc.report.diagnostics import render, summary


def _projects() -> list[dict[str, bytes]]:
    """Each project as {relative path: content}: the example, then the corpus cases that have a .rct file."""
    roots = [EXAMPLE]
    if (CONFORMANCE / "robochart").is_dir():
        roots += sorted(p for p in (CONFORMANCE / "robochart").iterdir() if p.is_dir() and any(p.rglob("*.rct")))
    return [{str(f.relative_to(root)): f.read_bytes() for f in sorted(root.rglob("*"))
             if f.suffix in (".rct", ".assertions") and f.is_file()} for root in roots]


PROJECTS = _projects()
LINES_FROM_ELSEWHERE = sorted({line for p in PROJECTS for text in p.values() for line in text.splitlines()[:400]})
WORDS = sorted({w for p in PROJECTS for text in p.values() for w in re.findall(rb"\w+", text)})


@st.composite
def byte_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    """Bytes flipped, inserted or deleted (the result need not be UTF-8)."""
    out = bytearray(data)
    for _ in range(draw(st.integers(1, 8))):
        at = draw(st.integers(0, len(out)))
        kind = draw(st.sampled_from(["flip", "insert", "delete"]))
        if kind == "insert" or not out:
            out[at:at] = draw(st.binary(min_size=1, max_size=4))
        elif kind == "flip":
            out[min(at, len(out) - 1)] ^= 1 << draw(st.integers(0, 7))
        else:
            del out[at:at + draw(st.integers(1, 16))]
    return bytes(out)


@st.composite
def character_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    """Characters (any Unicode, punctuation of the grammar, digits) inserted, replaced or deleted,
    or one repeated thousands of times (deep nesting, long numbers)."""
    text = data.decode("utf-8", "replace")
    pieces = st.one_of(st.characters(codec="utf-8"), st.sampled_from(list("{}()[]|;:,.!?#<>=-+*/\\\"'@$0123456789")),
                       st.text(alphabet="0123456789.", min_size=1, max_size=6))
    for _ in range(draw(st.integers(1, 8))):
        at = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["insert", "replace", "delete", "repeat"]))
        if kind == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 8)):]
        elif kind == "repeat":
            text = text[:at] + draw(pieces) * draw(st.integers(100, 6000)) + text[at:]
        else:
            text = text[:at] + draw(pieces) + text[at + (kind == "replace"):]
    return text.encode("utf-8")


@st.composite
def line_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    """Lines deleted, duplicated, swapped, or copied in from another model of the corpus."""
    lines = data.splitlines(keepends=True) or [b""]
    for _ in range(draw(st.integers(1, 6))):
        i, j = draw(st.integers(0, len(lines) - 1)), draw(st.integers(0, len(lines) - 1))
        kind = draw(st.sampled_from(["delete", "duplicate", "swap", "foreign"]))
        if kind == "delete" and len(lines) > 1:
            del lines[i]
        elif kind == "duplicate":
            lines[j:j] = [lines[i]] * draw(st.integers(1, 3))
        elif kind == "swap":
            lines[i], lines[j] = lines[j], lines[i]
        else:
            lines[j:j] = [draw(st.sampled_from(LINES_FROM_ELSEWHERE)) + b"\n"]
    return b"".join(lines)


@st.composite
def word_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    """Words (names, keywords, numbers) replaced by other words of the corpus: mostly still parses,
    so the resolver and the type checker see it."""
    parts = re.split(rb"(\w+)", data)
    words = list(range(1, len(parts), 2))
    for _ in range(draw(st.integers(1, 4)) if words else 0):
        parts[draw(st.sampled_from(words))] = draw(st.sampled_from(WORDS))
    return b"".join(parts)


@st.composite
def extreme_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    """Numbers (where expressions are) made huge, or nested or summed hundreds of times: past the
    digits Python reads, past the nesting limit."""
    parts = re.split(rb"(\w+)", data)
    numbers = [k for k in range(1, len(parts), 2) if parts[k].isdigit()]
    for k in draw(st.lists(st.sampled_from(numbers), min_size=1, max_size=3, unique=True)) if numbers else []:
        n = draw(st.sampled_from([600, 5000]))
        parts[k] = draw(st.sampled_from([b"9" * n, parts[k] + b"." + b"5" * n, b"-" * n + parts[k],
                                         b"(" * n + parts[k] + b")" * n, b"+".join([parts[k]] * n)]))
    return b"".join(parts)


@st.composite
def mutated_projects(draw: st.DrawFn) -> dict[str, bytes]:
    project = draw(st.sampled_from(PROJECTS))
    name = draw(st.sampled_from(sorted(project)))
    mutation = draw(st.sampled_from([byte_mutation, character_mutation, line_mutation, word_mutation,
                                     extreme_mutation]))
    return {**project, name: draw(mutation(project[name]))}


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(mutated_projects())
def test_load_returns_a_project_or_raises_model_error(files: dict[str, bytes]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for name, data in files.items():
            path = Path(tmp, name)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        try:
            assert isinstance(load(tmp), Project)
        except ModelError as exc:
            assert any(d.severity == "error" for d in exc.diagnostics)
            assert render(exc.diagnostics, exc.sources) and summary(exc.diagnostics)
