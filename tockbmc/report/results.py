"""Render check results: a table in the shape of the paper's, then each trace."""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from importlib import resources
from typing import Any

from rich.console import Console
from rich.segment import Segments
from rich.table import Table
from rich.text import Text

from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.result import Result, TraceStep, Verdict

VERDICT_STYLE = {Verdict.HOLDS: "green", Verdict.VIOLATED: "bold red", Verdict.UNKNOWN: "yellow",
                 Verdict.UNSUPPORTED: "magenta", Verdict.INTERRUPTED: "yellow"}


def summary(results: Iterable[Result]) -> dict[str, int]:
    """How many results have each verdict, by the verdict's name."""
    counts = {v.value: 0 for v in Verdict}
    for r in results:
        counts[r.verdict.value] += 1
    return counts


SCHEMA_VERSION = 2  # of `results.schema.json`: raised whenever a field changes meaning or goes away


def to_json(results: list[Result], version: str, status: str = "checked",
            diagnostics: Iterable[Diagnostic] = ()) -> dict[str, Any]:
    """The document `check --format json` prints (`results.schema.json`)."""
    return {"schema_version": SCHEMA_VERSION, "tool": "tockbmc", "version": version, "status": status,
            "results": [r.to_json() for r in results], "summary": {**summary(results), "total": len(results)},
            "diagnostics": [diagnostic_json(d) for d in diagnostics]}


def diagnostic_json(d: Diagnostic) -> dict[str, Any]:
    out = {"path": d.pos.path, "line": d.pos.line, "column": d.pos.column, "end_line": d.pos.end_line,
           "end_column": d.pos.end_column, "severity": d.severity, "message": d.message}
    return {**out, "rule": d.rule} if d.rule else out


def schema() -> dict[str, Any]:
    """The JSON schema of `to_json`'s document."""
    text = resources.files("tockbmc.report").joinpath("results.schema.json").read_text(encoding="utf-8")
    return json.loads(text)  # type: ignore[no-any-return]


def _scope(r: Result) -> str:
    ranges = ", ".join(f"{k}={v}" for k, v in r.ranges.items()) or "none (unbounded data)"
    missing = f" (not reproduced: {'; '.join(r.not_reproduced)})" if r.not_reproduced else ""
    return f"bound {r.bound} steps; ranges: {ranges}; reading: {r.reading}{missing}"


def configuration(r: Result) -> str:
    """What a result was checked with, in one line: each range and constant with where it came from."""
    ranges, constants = r.sources.get("ranges", {}), r.sources.get("constants", {})
    parts = [f"{k}={v} [{ranges[k]}]" if k in ranges else f"{k}={v}" for k, v in r.ranges.items()]
    line = "ranges: " + (", ".join(parts) or "none (unbounded data)")
    if r.constants:
        line += "; constants: " + ", ".join(f"{k}={v} [{constants[k]}]" if k in constants else f"{k}={v}"
                                             for k, v in r.constants.items())
    defaults = r.sources.get("defaults", {})
    if r.defaults:
        line += "; defaults: " + ", ".join(f"{k}={v} [{defaults.get(k, '')}]" if v else f"{k} [{defaults.get(k, '')}]"
                                            for k, v in r.defaults.items())
    decided = f"; decided by {r.engine} ({r.proof.value})" if r.verdict in (Verdict.HOLDS, Verdict.VIOLATED) else ""
    return f"reading: {r.reading}; {line}{decided}"


class ResultTable:
    """The results table, printed a row at a time: row i as soon as results 0..i are in, whatever
    order they are decided in (the columns have fixed widths, so each row can be printed alone)."""

    def __init__(self, console: Console, names: list[str], explicit: bool = False):
        self.console, self.names, self.explicit = console, names, explicit
        self.results: dict[int, Result] = {}
        self.rows = 0  # results printed as rows: those of indices below this
        self.printed = 0  # lines of the table printed so far
        self.widths = {"Assertion": max(len("Assertion"), *map(len, names), 1),
                       "Result": max(len(v.value) for v in Verdict), "Time": 9, "Bound": 5, "Trace": 5,
                       "States": 11, "Transitions": 11}

    def _table(self) -> Table:
        table = Table(title="tockbmc results", title_justify="left")
        columns = ("Assertion", "Result", "Time", "Bound", "Trace", *(("States", "Transitions") if self.explicit else ()))
        for col in columns:
            table.add_column(col, justify="left" if col in ("Assertion", "Result") else "right",
                             min_width=self.widths[col])
        for r in (self.results[i] for i in range(self.rows)):
            row: list[str | Text] = [r.assertion, Text(r.verdict.value, style=VERDICT_STYLE[r.verdict]),
                                     f"{r.seconds:.2f}s", str(r.bound) if r.bound is not None else "–",
                                     str(len(r.trace)) if r.trace else "–"]
            if self.explicit:
                row += [f"{r.extra['states']:,}" if "states" in r.extra else "–",
                        f"{r.extra['transitions']:,}" if "transitions" in r.extra else "–"]
            table.add_row(*row)
        return table

    def _print(self, final: bool) -> None:
        """Print the lines of the table not printed yet: all but its bottom edge unless `final`."""
        lines = self.console.render_lines(self._table(), self.console.options, pad=False, new_lines=True)
        new = lines[self.printed:] if final else lines[self.printed:-1]
        if new:
            self.console.print(Segments([s for line in new for s in line]), soft_wrap=True)
            self.printed += len(new)

    def start(self) -> None:
        """Print the title and the header."""
        self._print(final=False)

    def add(self, index: int, result: Result) -> None:
        """Result `index` (of `names`) is in: print the rows that now can be."""
        self.results[index] = result
        if index == self.rows:
            while self.rows in self.results:
                self.rows += 1
            self._print(final=False)

    def finish(self) -> None:
        """Print the rows still missing (every result must be in) and the bottom edge."""
        self.rows = len(self.names)
        self._print(final=True)


def print_results(results: list[Result], console: Console) -> None:
    """The results table, then what each result says."""
    table = ResultTable(console, [r.assertion for r in results], explicit=any("states" in r.extra for r in results))
    for i, r in enumerate(results):
        table.results[i] = r
    table.finish()
    print_details(results, console)


def print_details(results: list[Result], console: Console) -> None:
    """What the table's results say: the scope, then each result's reason, configuration and trace."""
    bounded = [r for r in results if r.bound is not None]
    if bounded:
        console.print(Text(_scope(bounded[0]), style="dim"))
    for r in results:
        console.print()
        head = Text(f"{r.assertion}: ", style="bold")
        head.append(r.verdict.value, style=VERDICT_STYLE[r.verdict])
        head.append(f"   {r.text}", style="dim")
        console.print(head)
        if r.verdict == Verdict.HOLDS:
            console.print(Text(f"  {r.reason or f'holds for every run of up to {r.bound} steps'}"))
            if "invariant" in r.extra:
                console.print(Text(f"  invariant: {r.extra['invariant'][:600]}", style="dim"))
        elif r.reason and not r.trace:
            console.print(Text(f"  {r.reason}" + (f"  [{r.pos}]" if r.verdict == Verdict.UNSUPPORTED else "")))
        if r.verdict != Verdict.UNSUPPORTED:
            console.print(Text(f"  {configuration(r)}", style="dim"))
        for note in r.notes:
            console.print(Text(f"  note: {note}", style="dim"))
        if r.trace:
            print_trace(r, console)


def where(position: str) -> str:
    """`path:line` for a reader: the path relative to the working directory when that is shorter."""
    path, _, rest = position.rpartition(":")  # drop the column
    path, _, line = path.rpartition(":")
    if not path:
        return position
    try:
        shorter = os.path.relpath(path)
    except ValueError:  # another drive
        shorter = path
    return f"{shorter if len(shorter) < len(path) else path}:{line}"


def print_trace(r: Result, console: Console) -> None:
    if r.other_trace:
        console.print(Text("  one run:", style="dim"))
    _print_steps(r.trace, console, {t["step"]: t for t in r.extra.get("tock_refusals", [])})
    if r.other_trace:
        console.print(Text("  another run, with the same events before the last:", style="dim"))
        _print_steps(r.other_trace, console)
    _print_end(r, console)


def _print_steps(trace: tuple, console: Console, refusals: dict[int, dict] | None = None) -> None:
    """The steps of a run; `refusals` (tick-tock) are the refusals observed before its tocks, by step."""
    for s in trace:
        print_step(s, console, refusals)


def print_step(s: TraceStep, console: Console, refusals: dict[int, dict] | None = None) -> None:
    """One step of a run, on a line of its own."""
    line = Text(f"  {s.step:>3}  ")
    if s.kind == "internal":
        line.append(f"τ  {s.note}", style="dim")
    else:
        line.append(s.event or "", style="bold")
        if s.free:
            fields = ", ".join(s.free) if any(s.free) else "its value"
            line.append(f"  ({fields}: any value)", style="dim")
    states = ", ".join(f"{m}: {st}" for m, st in s.states.items())
    line.append(f"   [{states}]", style="cyan")
    if s.changed:
        line.append("   " + ", ".join(f"{k} = {v}" for k, v in s.changed.items()), style="yellow")
    if s.source:
        line.append(f"   @ {where(s.source)}", style="dim")
    seen = (refusals or {}).get(s.step) if s.kind == "tock" else None
    if seen is not None:
        line.append(f"   refusing all but {{{', '.join(seen['offered'])}}} before it", style="magenta")
        if seen.get("refused"):
            line.append(f"; no stable state of the specification refuses {'; '.join(seen['refused'])}",
                        style="magenta")
    console.print(line)


def _print_end(r: Result, console: Console) -> None:
    console.print(Text(f"  → {r.reason}", style="bold"))
    last = next((s.source for s in reversed(r.trace) if s.source), "")
    if r.pos or last:
        at = [f"assertion at {where(r.pos)}"] if r.pos else []
        at += [f"last model step at {where(last)}"] if last else []
        console.print(Text(f"    ({'; '.join(at)})", style="dim"))
