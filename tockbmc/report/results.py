"""Render check results: a table in the shape of the paper's, then each trace."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from rich.console import Console
from rich.table import Table
from rich.text import Text

from tockbmc.bmc.result import Result

VERDICT_STYLE = {"holds": "green", "violated": "bold red", "unknown": "yellow", "unsupported": "magenta",
                 "interrupted": "yellow"}


def summary(results: Iterable[Result]) -> dict[str, int]:
    """How many of each verdict; "interrupted" (Ctrl-C) only when there are some."""
    counts = {"holds": 0, "violated": 0, "unknown": 0, "unsupported": 0}
    for r in results:
        counts[r.verdict] = counts.get(r.verdict, 0) + 1
    return counts


def to_json(results: list[Result], version: str) -> dict[str, Any]:
    return {"tool": "tockbmc", "version": version, "results": [r.to_json() for r in results],
            "summary": {**summary(results), "total": len(results)}}


def _scope(r: Result) -> str:
    ranges = ", ".join(f"{k}={v}" for k, v in r.ranges.items()) or "none (unbounded data)"
    return f"bound {r.bound} steps; ranges: {ranges}"


def print_results(results: list[Result], console: Console) -> None:
    table = Table(title="tockbmc results", title_justify="left")
    explicit = any("states" in r.extra for r in results)  # the paper's "complexity" columns
    columns = ("Assertion", "Result", "Time", "Bound", "Trace", *(("States", "Transitions") if explicit else ()))
    for col in columns:
        table.add_column(col, justify="left" if col in ("Assertion", "Result") else "right")
    for r in results:
        row: list[str | Text] = [r.assertion, Text(r.verdict, style=VERDICT_STYLE[r.verdict]), f"{r.seconds:.2f}s",
               str(r.bound) if r.bound is not None else "–", str(len(r.trace)) if r.trace else "–"]
        if explicit:
            row += [f"{r.extra['states']:,}" if "states" in r.extra else "–",
                    f"{r.extra['transitions']:,}" if "transitions" in r.extra else "–"]
        table.add_row(*row)
    console.print(table)
    bounded = [r for r in results if r.bound is not None]
    if bounded:
        console.print(Text(_scope(bounded[0]), style="dim"))
    for r in results:
        console.print()
        head = Text(f"{r.assertion}: ", style="bold")
        head.append(r.verdict, style=VERDICT_STYLE[r.verdict])
        head.append(f"   {r.text}", style="dim")
        console.print(head)
        if r.verdict == "holds":
            console.print(Text(f"  {r.reason or f'holds for every run of up to {r.bound} steps'}; "
                               f"{_scope(r).split('; ')[1]}"))
        elif r.reason and not r.trace:
            console.print(Text(f"  {r.reason}" + (f"  [{r.pos}]" if r.verdict == "unsupported" else "")))
        if r.trace:
            print_trace(r, console)


def print_trace(r: Result, console: Console) -> None:
    for s in r.trace:
        line = Text(f"  {s.step:>3}  ")
        if s.kind == "internal":
            line.append(f"τ  {s.note}", style="dim")
        else:
            line.append(s.event or "", style="bold")
        states = ", ".join(f"{m}: {st}" for m, st in s.states.items())
        line.append(f"   [{states}]", style="cyan")
        if s.changed:
            line.append("   " + ", ".join(f"{k} = {v}" for k, v in s.changed.items()), style="yellow")
        console.print(line)
    console.print(Text(f"  → {r.reason}", style="bold"))
