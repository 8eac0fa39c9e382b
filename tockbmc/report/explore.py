"""`tockbmc explore`'s output: each assertion's region as text, or all of them as JSON."""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

from rich.console import Console
from rich.markup import escape

from tockbmc.model.exploration import Exploration

EXPLORE_SCHEMA_VERSION = 1  # of `explore.schema.json`: raised whenever a field changes meaning or goes away


def to_json(explorations: list[Exploration], version: str, bound: int) -> dict[str, Any]:
    """The document `tockbmc explore --format json` prints (`explore.schema.json`)."""
    return {"schema_version": EXPLORE_SCHEMA_VERSION, "tool": "tockbmc", "version": version, "bound": bound,
            "explorations": [e.to_json() for e in explorations]}


def schema() -> dict[str, Any]:
    """The JSON schema of `to_json`'s document."""
    text = resources.files("tockbmc.report").joinpath("explore.schema.json").read_text(encoding="utf-8")
    return json.loads(text)  # type: ignore[no-any-return]


def _point(point: dict[str, str]) -> str:
    """Parameter values, a range's two bounds as one `LO..HI`."""
    parts: list[str] = []
    done: set[str] = set()
    for name, value in point.items():
        if name in done:
            continue
        base, _, end = name.rpartition(".")
        if end == "low" and f"{base}.high" in point:
            parts.append(f"{base} = {value}..{point[f'{base}.high']}")
            done.add(f"{base}.high")
        else:
            parts.append(f"{name} = {value}")
    return ", ".join(parts)


def _statement(e: Exploration) -> str:
    other = "holds" if e.inside == "violated" else "violated"
    if e.reach == "partial":  # nothing is known outside the region: only where it is, what holds there
        if e.condition == "false":
            return f"undecided: no {'witness' if e.inside == 'holds' else 'counterexample'} found"
        return f"{e.inside} where {e.condition}" if e.condition != "true" else f"{e.inside} for every value"
    if e.condition == "false":
        return f"{other} for every value of the parameters" if e.parameters else f"{other} whatever the ranges"
    if e.condition == "true":
        return f"{e.inside} for every value of the parameters" if e.parameters else f"{e.inside} whatever the ranges"
    return f"{e.inside} ⇔ {e.condition}"


def _reach(e: Exploration) -> str:
    if e.reach == "every length":
        how = f" ({e.proof})" if e.proof else ""
        return f"exact for runs of every length{how}"
    if e.reach == "bound":
        return f"exact for runs of up to {e.bound} steps"
    if e.condition == "false":
        return f"not complete ({e.reason})"
    return (f"not complete ({e.reason}): every point of the region shown has a "
            f"{'witness' if e.inside == 'holds' else 'counterexample'}; outside it, nothing is known")


def print_exploration(e: Exploration, console: Console) -> None:
    """One assertion's findings, a few lines."""
    console.print(f"[bold]{escape(e.assertion)}[/]  {escape(e.text)}  [dim]{escape(e.pos)}[/]")
    if e.fixed_here:
        console.print(f"    [dim]with {escape(', '.join(f'{k} = {v}' for k, v in e.fixed_here.items()))}[/]")
    if e.status == "unsupported":
        console.print(f"    unsupported: {escape(e.reason)}")
        return
    console.print(f"    {escape(_statement(e))}")
    console.print(f"    [dim]{escape(_reach(e))}[/]")
    if e.independent and e.condition not in ("true", "false"):
        console.print(f"    does not depend on: {escape(', '.join(e.independent))}")
    if e.carried:
        by_event: dict[str, list[str]] = {}
        for c in e.carried:
            text = c.condition if c.condition != "any" else f"{c.field or 'value'} any"
            by_event.setdefault(c.event, []).append(text + ("" if c.exact else " (at least)"))
        inputs = "; ".join(f"{ev}: {', '.join(fields)}" for ev, fields in by_event.items())
        what = "counterexample" if e.inside == "violated" else "witness"
        console.print(f"    inputs of a shortest {what} ({e.depth} steps): {escape(inputs)}")
    if e.trace:
        events = ", ".join(s.event or "" for s in e.trace if s.kind != "internal") or "no event"
        replayed = "replayed" if e.replayed == "yes" else f"replay: {e.replayed}"
        at = f"at {_point(e.point)}: " if e.point else ""
        console.print(f"    for example {escape(at)}{escape(events)}  [dim]({escape(replayed)})[/]")


def print_scope(explorations: list[Exploration], bound: int, console: Console) -> None:
    """What varied and what was held fixed, once for all the assertions (after them: they stream)."""
    params: list[str] = []
    assumed: list[str] = []
    for e in explorations:
        params += [p for p in e.parameters if p not in params]
        assumed += [a for a in e.assumed if a not in assumed]
    fixed = common_fixed(explorations)
    console.print(f"\nparameters: {escape(', '.join(params) or 'none')}")
    if fixed:
        console.print(f"fixed: {escape(', '.join(f'{k} = {v}' for k, v in fixed.items()))}")
    if assumed:
        console.print(f"every point has: {escape(', '.join(assumed))}")
    console.print(f"bound: {bound} steps")
    console.print("reading: open (variables without an initial value start at any value, functions without a "
                  "body are any function meeting their contract)")


def common_fixed(explorations: list[Exploration]) -> dict[str, str]:
    """What every exploration holds fixed at the same value (a range given on the command line, say)."""
    fixed = [{k: v for k, v in e.fixed.items() if k not in e.fixed_here} for e in explorations
             if e.status != "unsupported"]
    if not fixed:
        return {}
    return {k: v for k, v in fixed[0].items() if all(f.get(k) == v for f in fixed[1:])}
