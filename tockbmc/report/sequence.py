"""A trace read as a sequence diagram: who sends what to whom at each step, and where states change.

This is what the diagram says, apart from how it is drawn (`report/svg.py`).  The participants are
the environment (left), the machines, and the robotic platform (right) when the trace calls an
operation.  A step's arrow comes from its event's channel (`in`: environment to machine, `out` and
`terminate`: machine to environment, `…Call`: machine to platform) or, for an internal step, from a
note that says who sends to whom.  An event of a controller or module whose machine the trace does
not tell arrives at the element's boundary (`BOUNDARY`), drawn as a frame around its machines.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from tockbmc.model.result import TraceStep

ENVIRONMENT = "environment"
PLATFORM = "robotic platform"
# Not a RoboChart identifier, so never a machine's name: an end at the frame around the machines.
BOUNDARY = "<boundary>"

# An event's text in FDR's naming: the channel (`M::ctrl::e`), then `.in`/`.out`, then its values.
_EVENT = re.compile(r"(?P<channel>[A-Za-z_]\w*(?:::[A-Za-z_]\w*)*)(?:\.(?P<direction>in|out)\b)?")
# Notes of internal steps: BMC's "A sends e, B: transition t" and the interpreter's "A.e to B.f (v)".
_SENDS = re.compile(r"(?:^|, )(?P<sender>\w+) sends (?P<event>\w+)")
_WHO = re.compile(r"(?:^|, )(?P<who>\w+): (?P<what>.*?)(?=, \w+(?::| sends )|$)")
_ASSIGNED = re.compile(r"(?P<variable>[\w.]+) := …")  # BMC's note of an assignment; the value is in `changed`
_LINK = re.compile(r"^(?P<sender>\w+)\.(?P<event>\w+) to (?P<receiver>\w+)\.\w+(?: \((?P<value>.*)\))?$")


@dataclass(frozen=True)
class Message:
    """An arrow: `kind` is input, output, call, terminate, sync (machine to machine) or event (undirected)."""

    source: str
    target: str
    label: str
    kind: str


@dataclass(frozen=True)
class Row:
    """One step of the trace, as one row of the diagram."""

    step: int
    kind: str  # event | tock | internal (the step's)
    message: Message | None = None
    time: int | None = None  # for a tock: the time after it (tocks so far)
    notes: tuple[tuple[str, str], ...] = ()  # (machine, what it did) for internal steps without an arrow
    states: tuple[tuple[str, str], ...] = ()  # (machine, state) where the machine's state changed


@dataclass(frozen=True)
class Diagram:
    element: str  # the controller or module whose events the trace shows, if its channels name one
    machines: tuple[str, ...]
    platform: bool  # whether the trace calls an operation of the platform
    framed: bool  # whether some arrow ends at the element's boundary, drawn as a frame around the machines
    rows: tuple[Row, ...]

    @property
    def lifelines(self) -> tuple[str, ...]:
        """Left to right: the environment, the machines, then the platform if it is called."""
        return (ENVIRONMENT, *self.machines, *((PLATFORM,) if self.platform else ()))


def channel_of(step: TraceStep) -> tuple[str, str]:
    """The step's channel and direction ("in", "out" or ""), from `channel` or else from the event's text."""
    if step.channel:
        return str(step.channel[0]), str(step.channel[1]) if len(step.channel) > 1 else ""
    match = _EVENT.match(step.event or "")
    if match is None:
        return step.event or "", ""
    return match["channel"], match["direction"] or ""


def _owner(channel: str) -> str:
    """The element a channel belongs to: `EXAX` of `EXAX::move`, `ctrl` of `M::ctrl::e` ("" if none)."""
    head, sep, _ = channel.rpartition("::")
    return head.rpartition("::")[2] if sep else ""


def diagram(trace: Sequence[TraceStep]) -> Diagram:
    """The sequence diagram of a trace."""
    machines: list[str] = []
    for s in trace:
        machines += [m for m in s.states if m not in machines]
    owners = [_owner(channel_of(s)[0]) for s in trace if s.kind == "event"]
    if not machines:  # a trace of events alone (a specification's): its elements stand for machines
        machines = list(dict.fromkeys(o for o in owners if o)) or ["model"]
    element = next((o for o in owners if o and o not in machines), "")
    rows = []
    before: dict[str, str] = {}
    time = 0
    for s in trace:
        states = tuple((m, st) for m, st in s.states.items() if before.get(m) != st)
        before = {**before, **s.states}
        if s.kind == "tock":
            time += 1
            rows.append(Row(s.step, "tock", time=time, states=states))
        elif s.kind == "internal" or s.event is None:
            message, notes = _internal(s.note, machines)
            notes = tuple((m, _with_values(what, s.changed)) for m, what in notes)
            rows.append(Row(s.step, "internal", message, notes=notes, states=states))
        else:
            rows.append(Row(s.step, "event", _event(s, machines, states), states=states))
    platform = any(r.message is not None and r.message.kind == "call" for r in rows)
    return Diagram(element, tuple(machines), platform, any(_ends(r, BOUNDARY) for r in rows), tuple(rows))


def _ends(row: Row, end: str) -> bool:
    return row.message is not None and end in (row.message.source, row.message.target)


def _event(s: TraceStep, machines: Sequence[str], changed: tuple[tuple[str, str], ...]) -> Message:
    """The arrow of a visible event, from its channel: the machine is the channel's owner, or else the
    one machine whose state or variables the step changed, or else the element's boundary."""
    channel, direction = channel_of(s)
    label = s.event or channel
    owner = _owner(channel)
    if owner in machines or len(machines) == 1:
        machine = owner if owner in machines else machines[0]
    else:
        moved = {m for m, _ in changed} or {v.partition(".")[0] for v in s.changed} & set(machines)
        machine = moved.pop() if len(moved) == 1 else BOUNDARY
    if direction == "in":
        return Message(ENVIRONMENT, machine, label, "input")
    if direction == "out":
        return Message(machine, ENVIRONMENT, label, "output")
    if channel.endswith("Call"):
        return Message(machine, PLATFORM, label, "call")
    if channel.rpartition("::")[2] == "terminate":
        return Message(machine, ENVIRONMENT, label, "terminate")
    return Message(ENVIRONMENT, machine, label, "event")


def _with_values(note: str, changed: dict[str, str]) -> str:
    """Each `x := …` of a note with the value the step gave x (when exactly one changed variable is x)."""
    def value(assigned: re.Match[str]) -> str:
        name = assigned["variable"]
        values = [v for k, v in changed.items() if k == name or k.endswith("." + name)]
        return f"{name} := {values[0]}" if len(values) == 1 else assigned[0]
    return _ASSIGNED.sub(value, note)


def _internal(note: str, machines: Sequence[str]) -> tuple[Message | None, tuple[tuple[str, str], ...]]:
    """An internal step's arrow, when its note says one machine sends to another, and what else it notes."""
    link = _LINK.match(note)
    if link and link["sender"] in machines and link["receiver"] in machines:
        label = link["event"] + (f".{link['value']}" if link["value"] else "")
        return Message(link["sender"], link["receiver"], label, "sync"), ()
    parts = tuple((m["who"], m["what"]) for m in _WHO.finditer(note) if m["who"] in machines)
    sends = _SENDS.search(note)
    if sends and sends["sender"] in machines:
        receivers = [who for who, _ in parts if who != sends["sender"]]
        if receivers:
            return Message(sends["sender"], receivers[0], sends["event"], "sync"), ()
    return None, parts
