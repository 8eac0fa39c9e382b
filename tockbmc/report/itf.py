"""Traces in Apalache's Informal Trace Format (ITF, ADR-015): the full configuration at every step.

`check --format itf` prints `{"traces": {assertion: <ITF document>}}`: one
document for each result with a trace (a counterexample, or the witness of a
reachability).  ITF state i is the configuration after step i + 1 of the text
trace, with these variables:

- `mbt::actionTaken`: the step's event in FDR's naming, `τ` for an internal
  step (Quint's model-based-testing convention; `::` cannot occur in a
  RoboChart name, so it never meets a model variable);
- one per machine, named as the machine: its innermost active state;
- one per variable, named as in the text trace (`EXAX.curr_waypoint`), a
  record variable as an ITF record of its fields (`EXAX.exax_move` is
  `{"dist": …, "time": …}`).

Values: integers as `{"#bigint": "…"}`, booleans as JSON booleans,
enumeration literals as strings (`"SystemState::working"`).  ITF has no reals:
a real is a string holding its exact value (`"0.5"`, `"1/3"`; an irrational
solution as Z3's decimal with a trailing `?`).  A decoded trace carries values
as text without their type, so a variable is written as a real, in every state,
when some value of it in the trace is not a whole number; a real variable
whose values are all whole numbers is written as integers.  A variable the
trace has not given a value yet (declared without an initial value, before
its first assignment) is `{"#unserializable": "unset"}`, ITF's form for a value
it cannot show, since every state must define every variable.

Each state's `#meta` holds its `index`, the text trace's `step` number, its
`kind` (event, tock, internal), its `note` and, when the trace has it, the
`source` position of the model text behind the step.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any

from tockbmc.model.result import Result, TraceStep
from tockbmc.report.steps import place, source, values_after_each_step

ACTION = "mbt::actionTaken"
FORMAT_DESCRIPTION = "https://apalache-mc.org/docs/adr/015adr-trace.html"
UNSET = {"#unserializable": "unset"}

_INTEGER = re.compile(r"-?[0-9]+")


def document(results: Iterable[Result], version: str) -> dict[str, Any]:
    """`{"traces": {assertion: ITF document}}` for the results that have a trace."""
    return {"traces": {r.assertion: trace(r, version) for r in results if r.trace}}


def trace(r: Result, version: str) -> dict[str, Any]:
    """One result's trace as an ITF document."""
    machines = _first_seen(name for step in r.trace for name in step.states)
    values = values_after_each_step(r.trace)
    variables = _variables(_first_seen(key for step in r.trace for key in step.changed), machines)
    reals = {key for step in r.trace for key, text in step.changed.items() if _is_real(text)}
    states = []
    for index, (step, known) in enumerate(zip(r.trace, values)):
        state: dict[str, Any] = {"#meta": _step_meta(index, step), ACTION: "τ" if step.event is None else step.event}
        state.update({m: step.states.get(m, "") for m in machines})
        for name, leaves in variables.items():
            state[name] = _value(leaves, known, reals)
        states.append(state)
    at = place(r.pos)
    meta = {"format": "ITF", "format-description": FORMAT_DESCRIPTION, "source": at.path if at else "",
            "description": f"Created by tockbmc {version}: {r.assertion} {r.verdict.value}",
            "assertion": r.assertion, "verdict": r.verdict.value, "reason": r.reason or ""}
    return {"#meta": meta, "vars": [ACTION, *machines, *variables], "states": states}


def _step_meta(index: int, step: TraceStep) -> dict[str, Any]:
    meta: dict[str, Any] = {"index": index, "step": step.step, "kind": step.kind, "note": step.note}
    if source(step):
        meta["source"] = source(step)
    return meta


def _first_seen(names: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(names))


# A variable: its ITF name and its leaves, each a field path (empty for a scalar) and the text trace's key.
Leaves = list[tuple[tuple[str, ...], str]]


def _variables(keys: list[str], machines: list[str]) -> dict[str, Leaves]:
    """Group the text trace's keys (`EXAX.exax_move.dist`) into variables and the field paths of their leaves."""
    out: dict[str, Leaves] = {}
    for key in keys:
        name, fields = _split(key, machines)
        out.setdefault(name, []).append((fields, key))
    return out


def _split(key: str, machines: list[str]) -> tuple[str, tuple[str, ...]]:
    """A key as (variable, field path).

    A machine's variable is `M.x` (`M.op().x` for an inlined operation's); the
    rest of the key is the path of a record field.  Any other key is a
    controller's shared variable `C.x`, or a platform's `x`: a platform's
    record variable is not told apart from a controller's scalar and stays flat.
    """
    owner = max((m for m in machines if key.startswith(m + ".")), key=len, default=None)
    if owner is None:
        parts = key.split(".")
        return (".".join(parts[:2]), tuple(parts[2:])) if len(parts) > 1 else (key, ())
    parts = key[len(owner) + 1:].split(".")
    i = 0
    while i < len(parts) - 1 and parts[i].endswith("()"):
        i += 1
    return ".".join([owner, *parts[:i + 1]]), tuple(parts[i + 1:])


def _value(leaves: Leaves, known: dict[str, str], reals: set[str]) -> Any:
    """A variable's ITF value: a scalar, or a record built from its leaves."""
    if len(leaves) == 1 and not leaves[0][0]:
        key = leaves[0][1]
        return _scalar(known[key], key in reals) if key in known else UNSET
    record: dict[str, Any] = {}
    for fields, key in leaves:
        node = record
        for f in fields[:-1]:
            node = node.setdefault(f, {})
        node[fields[-1]] = _scalar(known[key], key in reals) if key in known else UNSET
    return record


def _is_real(text: str) -> bool:
    """A number that is not whole: `0.5`, `1/3`, `1.414214?`."""
    return bool(text) and (text[0].isdigit() or text[0] == "-") and not _INTEGER.fullmatch(text)


def _scalar(text: str, real: bool) -> Any:
    if text in ("true", "false"):
        return text == "true"
    if _INTEGER.fullmatch(text) and not real:
        return {"#bigint": text}
    return text
