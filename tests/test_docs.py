"""The documentation stands alone and says what the code does.

- Every relative link in README.md, DESIGN.md and docs/*.md names a file of the repository (and,
  with `#anchor`, a heading of that file).
- Every ```rct example of docs/language.md loads, together with the ```assertions block that
  follows it, if any; each assertion there is checked, and its verdict is the one its trailing
  `// verdict` comment states (or anything but `unsupported` when it has none).
- Every ```rct-unsupported example is refused, with `unsupported` diagnostics only.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest
from conftest import REPO, write_files

import tockbmc
from tockbmc.check import DEFAULT_BOUND, check

DOCS = REPO / "docs"
LANGUAGE = DOCS / "language.md"
LINKED = [REPO / "README.md", REPO / "DESIGN.md", *sorted(DOCS.glob("*.md"))]

FENCE = re.compile(r"^```([\w-]*)[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)
LINK = re.compile(r"\[[^\]\n]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#{1,6}[ \t]+(.+?)[ \t]*#*[ \t]*$", re.M)
ASSERTION = re.compile(r"^[ \t]*(?:(?:timed|untimed)[ \t]+)?assertion[ \t]+(\w+)[ \t]*:(.*)$", re.M)
VERDICTS = ("holds", "violated", "unknown", "unsupported")
BOUND = DEFAULT_BOUND  # what `tockbmc check` uses unless told otherwise


def _prose(text: str) -> str:
    """The text without fenced blocks and inline code, where link syntax is not a link."""
    text = FENCE.sub("", text)
    return re.sub(r"`[^`\n]*`", "", text)


def _slug(heading: str) -> str:
    """GitHub's anchor for a heading."""
    text = re.sub(r"`", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    return {_slug(h) for h in HEADING.findall(FENCE.sub("", path.read_text(encoding="utf-8")))}


def _links() -> list[tuple[Path, str]]:
    out = []
    for doc in LINKED:
        for target in LINK.findall(_prose(doc.read_text(encoding="utf-8"))):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # https:, mailto: …
                continue
            out.append((doc, target))
    return out


@pytest.mark.parametrize("doc,target", _links(), ids=lambda x: x.name if isinstance(x, Path) else x)
def test_relative_links_resolve(doc: Path, target: str) -> None:
    path_part, _, anchor = target.partition("#")
    resolved = (doc.parent / path_part).resolve() if path_part else doc
    assert resolved.exists(), f"{doc.name}: link to {target}: no file {resolved}"
    assert REPO in resolved.parents or resolved == REPO, f"{doc.name}: link to {target} leaves the repository"
    if anchor:
        assert resolved.suffix == ".md", f"{doc.name}: anchor #{anchor} in a file that is not markdown"
        assert anchor in _anchors(resolved), f"{doc.name}: link to {target}: no heading with that anchor"


def test_no_pointer_to_the_shared_directory() -> None:
    """The semantics and the languages are described in docs/, not in a directory beside the repository."""
    sources = [*LINKED, *sorted((REPO / "tockbmc").rglob("*.py")), *sorted((REPO / "tockbmc").rglob("*.lark"))]
    found = [f"{p.relative_to(REPO)}:{n}" for p in sources
             for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
             if re.search(r"shared/(semantics|language)\.md", line)]
    assert not found, f"pointers to ../shared instead of docs/: {found}"


def test_readme_links_the_docs() -> None:
    targets = {target.partition("#")[0] for doc, target in _links() if doc.name == "README.md"}
    assert {"docs/semantics.md", "docs/language.md"} <= targets


@dataclass
class Example:
    kind: str  # rct | rct-unsupported
    line: int
    rct: str
    assertions: str | None = None


def _examples() -> list[Example]:
    text = LANGUAGE.read_text(encoding="utf-8")
    out: list[Example] = []
    for m in FENCE.finditer(text):
        kind, body = m.group(1), m.group(2)
        line = text.count("\n", 0, m.start()) + 1
        if kind in ("rct", "rct-unsupported"):
            out.append(Example(kind, line, body))
        elif kind == "assertions":
            assert out and out[-1].kind == "rct" and out[-1].assertions is None, \
                f"language.md:{line}: an assertions block must follow its own rct example"
            out[-1].assertions = body
    return out


EXAMPLES = _examples()


def _id(e: Example) -> str:
    return f"language.md:{e.line}"


def test_language_has_examples() -> None:
    kinds = [e.kind for e in EXAMPLES]
    assert kinds.count("rct") >= 5 and kinds.count("rct-unsupported") >= 3
    assert sum(1 for e in EXAMPLES if e.assertions) >= 3


def _expected(assertions: str) -> dict[str, str | None]:
    out: dict[str, str | None] = {}
    for name, rest in ASSERTION.findall(assertions):
        _, sep, comment = rest.partition("//")
        verdict = comment.strip().removeprefix("reported as ").strip() if sep else None
        assert verdict is None or verdict in VERDICTS, f"assertion {name}: '// {comment.strip()}' is not a verdict"
        out[name] = verdict
    return out


@pytest.mark.parametrize("example", [e for e in EXAMPLES if e.kind == "rct"], ids=_id)
def test_rct_example_loads_and_checks_as_stated(example: Example, tmp_path: Path) -> None:
    files = {"example.rct": example.rct}
    if example.assertions is not None:
        files["example.assertions"] = example.assertions
    write_files(tmp_path, files)
    try:
        project = tockbmc.load(tmp_path)
    except tockbmc.ModelError as exc:
        pytest.fail(f"{_id(example)} does not load: " + "; ".join(d.message for d in exc.diagnostics))
    assert not project.warnings, [d.message for d in project.warnings]
    if example.assertions is None:
        return
    expected = _expected(example.assertions)
    assert expected, f"{_id(example)}: the assertions block has no assertion"
    results = {r.assertion: r for r in check(project, bound=BOUND)}
    assert set(results) == set(expected)
    for name, verdict in expected.items():
        r = results[name]
        if verdict is None:
            assert r.verdict != "unsupported", f"{_id(example)} {name}: unsupported ({r.reason})"
        else:
            assert r.verdict == verdict, f"{_id(example)} {name}: {r.verdict}, not {verdict} ({r.reason})"


@pytest.mark.parametrize("example", [e for e in EXAMPLES if e.kind == "rct-unsupported"], ids=_id)
def test_unsupported_example_is_refused_as_unsupported(example: Example, tmp_path: Path) -> None:
    write_files(tmp_path, {"example.rct": example.rct})
    with pytest.raises(tockbmc.ModelError) as info:
        tockbmc.load(tmp_path)
    errors = [d.message for d in info.value.diagnostics if d.severity == "error"]
    assert errors and all(m.startswith("unsupported: ") for m in errors), errors
