"""`check --report FILE.html`: the results as one self-contained HTML page.

The page has the verdict table, the scope of the search, and for each trace a sequence diagram
(inline SVG, `report/svg.py`) beside a table of its steps.  It loads nothing: the CSS is inline and
there is no script.  Jinja2 renders `templates/report.html` with autoescaping on, so every piece of
model text (names, values, notes, reasons) is escaped; the SVG is built by `xml.etree`, which escapes
its own text, and is the one piece passed through as markup.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape
from markupsafe import Markup

from tockbmc.model.readings import Reading
from tockbmc.model.result import Result, TraceStep, Verdict
from tockbmc.report.results import summary
from tockbmc.report.sequence import diagram
from tockbmc.report.svg import render, to_string


@dataclass(frozen=True)
class StepRow:
    """One line of a trace's step table."""

    step: int
    kind: str
    event: str  # the event, or the note of an internal step
    states: tuple[tuple[str, str, bool], ...]  # (machine, state, entered at this step)
    changed: tuple[tuple[str, str], ...]
    source: str  # "path:line:col" of the model text behind the step, or ""
    time: int | None  # for a tock: the time after it

    @property
    def source_short(self) -> str:
        """The source without the file's directories ("file.rct:12:5"), for a narrow column."""
        return self.source.replace("\\", "/").rpartition("/")[2]


@dataclass(frozen=True)
class Section:
    """One assertion's part of the page."""

    result: Result
    anchor: str
    svg: Markup | None
    steps: tuple[StepRow, ...]


def _steps(trace: Sequence[TraceStep]) -> tuple[StepRow, ...]:
    """The step table: of the states, those entered at each step, and all of them at the first and the last."""
    rows = []
    before: dict[str, str] = {}
    time = 0
    for i, s in enumerate(trace):
        time += s.kind == "tock"
        every = i in (0, len(trace) - 1)
        states = tuple((m, st, before.get(m) != st) for m, st in s.states.items() if every or before.get(m) != st)
        before = {**before, **s.states}
        event = s.event if s.kind != "internal" and s.event is not None else s.note
        rows.append(StepRow(s.step, s.kind, event or "", states, tuple(s.changed.items()),
                            getattr(s, "source", "") or "", time if s.kind == "tock" else None))
    return tuple(rows)


def _anchor(name: str, taken: set[str]) -> str:
    base = "r-" + "".join(c if c.isalnum() or c in "-_" else "-" for c in name)
    anchor, n = base, 1
    while anchor in taken:
        n += 1
        anchor = f"{base}-{n}"
    taken.add(anchor)
    return anchor


def sections(results: Sequence[Result]) -> list[Section]:
    """Each result with its anchor on the page, and its trace as a diagram and a table."""
    taken: set[str] = set()
    out = []
    for r in results:
        svg = None
        if r.trace:
            kind = "counterexample" if r.verdict == Verdict.VIOLATED else "trace"
            svg = Markup(to_string(render(diagram(r.trace), f"{r.assertion}: {kind} as a sequence diagram")))
        out.append(Section(r, _anchor(r.assertion, taken), svg, _steps(r.trace)))
    return out


def _scope(results: Sequence[Result]) -> tuple[int | None, dict[str, str], dict[str, str], str, str]:
    """The bound, ranges (with their sources), engine and reading of the run: the same for every
    result that searched, but for a range listed only with the results that rest on it (the
    default length of a sequence input with `--robotool`), which is listed if one does."""
    searched = [r for r in results if r.bound is not None] or list(results)
    if not searched:
        return None, {}, {}, "", ""
    first = searched[0]
    ranges = {k: v for r in searched for k, v in r.ranges.items()}
    sources = {k: v for r in searched for k, v in r.sources.get("ranges", {}).items() if k in ranges}
    return first.bound, ranges, sources, first.engine, first.reading


def render_report(results: Sequence[Result], *, title: str, version: str) -> str:
    """The HTML page of a run's results; `title` names what was checked (the model's paths)."""
    env = Environment(loader=PackageLoader("tockbmc.report", "templates"), autoescape=select_autoescape(["html"]),
                      trim_blocks=True, lstrip_blocks=True)
    bound, ranges, range_sources, engine, reading = _scope(results)
    counts = {k: n for k, n in summary(results).items() if n}
    return env.get_template("report.html").render(
        title=title, version=version, bound=bound, ranges=ranges, range_sources=range_sources, engine=engine,
        counts=counts,
        reading=reading, reading_summary=Reading(reading).summary if reading else "",
        not_reproduced=Reading(reading).not_reproduced if reading else (),
        sections=sections(results), explicit=any("states" in r.extra for r in results))


def write_report(path: str | Path, results: Sequence[Result], *, title: str, version: str) -> None:
    """Write the HTML page of a run's results to `path` (UTF-8)."""
    Path(path).write_text(render_report(results, title=title, version=version), encoding="utf-8")
