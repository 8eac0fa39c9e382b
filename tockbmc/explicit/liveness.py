"""Which of a machine's variables are dead while it rests in a state: no run from there reads
them before writing them.

The explicit engine stores every configuration it reaches, and a value a machine keeps but will
never read again (an input already forwarded, a move already carried out) multiplies them for
nothing. Where a machine rests in a state, its dead variables are set to one value (`DEAD`), so
that configurations that differ only there are one (dead-variable reduction, as explicit-state
checkers do). A read of `DEAD` would be an error of this analysis, and it fails loudly: the
interpreter's every read of a variable (`_Ctx.get`) refuses it.

The analysis is the usual backward one, over the machine's graph as the interpreter runs it
(docs/semantics.md §4): from a state at rest, a transition of the state or of an ancestor is taken
(its trigger's input written first, then its condition read), the states it leaves are exited
(innermost first), its action runs, the states it enters are entered (outermost first), and the
run goes on from the target: through a junction's transitions, into a composite state's initial
junction, or to rest in a leaf. `live(s)` is the least set closed under those paths, and what
trigger deadlines read is live everywhere (the interpreter reads every bound at each step, and an
ancestor's deadline condition at junctions too). Machines
that call defined operations or run `during` actions are left alone (those read the machine's
variables from places this analysis does not follow).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Protocol

from tockbmc.model import ast


class DeadValue:
    """The value every dead variable holds: equal to itself only, and nothing computes with it."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "DEAD"

    def __reduce__(self) -> str:
        return "DEAD"


DEAD = DeadValue()

Key = tuple[str, str]  # a variable by (owner, name)


class Graph(Protocol):
    """What the analysis reads of a machine's graph (the interpreter's `_Beh`)."""

    nodes: dict[str, ast.Node]
    initial: dict[str | None, str]
    deadlines: list[ast.Transition]  # the transitions with a trigger deadline

    def candidates(self, path: str) -> list[ast.Transition]: ...

    def path(self, leaf: str, source: str, target: str) -> tuple[tuple[str, ...], tuple[str, ...]]: ...


def key(v: ast.Variable) -> Key:
    return (v.owner, v.name)


def _reads(x: object) -> set[Key]:
    return {key(e.variable) for e in ast.subexpressions(x) if isinstance(e, ast.VarRef)}


def live_before(s: ast.Stmt | None, after: set[Key]) -> set[Key]:
    """The variables read before being written when `s` runs and then something that reads
    `after`; a statement this analysis does not know reads everything (`_Unknown`)."""
    if s is None or isinstance(s, (ast.Skip, ast.ClockReset)):
        return after
    if isinstance(s, ast.Seq):
        live = after
        for st in reversed(s.statements):
            live = live_before(st, live)
        return live
    if isinstance(s, ast.Assign):
        kept = after - {key(s.variable)} if not s.fields else after | {key(s.variable)}
        return kept | _reads(s.value)
    if isinstance(s, ast.Receive):
        return after - {key(s.variable)} if s.variable is not None else after
    if isinstance(s, ast.Send):
        return after | _reads(s.value)
    if isinstance(s, ast.If):
        return _reads(s.condition) | live_before(s.then, after) | live_before(s.otherwise, after)
    if isinstance(s, ast.Wait):
        return after | _reads((s.low, s.high))
    if isinstance(s, ast.Deadline):
        return _reads(s.bound) | live_before(s.statement, after)
    if isinstance(s, ast.OperationCall) and isinstance(s.operation, ast.OperationSig):
        return after | _reads(s.args)
    raise _Unknown


class _Unknown(Exception):
    """A statement the analysis does not follow: every variable is live."""


def analysable(b: ast.Behaviour, defined: Callable[[ast.OperationCall], bool]) -> bool:
    """Whether the analysis follows every read of `b`: no `during` action runs, and no call runs a
    defined operation (`defined` tells, as the interpreter resolves the call)."""
    for n in b.nodes:
        if n.during is not None:
            return False
    for st in ast.behaviour_statements(b):
        if isinstance(st, ast.OperationCall) and (not isinstance(st.operation, ast.OperationSig) or defined(st)):
            return False
    return True


def dead_at_rest(g: Graph, own: Iterable[ast.Variable]) -> dict[str, frozenset[Key]]:
    """For each leaf state and final state of `g`, the variables of `own` dead while the machine
    rests there; {} where the analysis cannot tell (see `analysable`, which the caller asks first)."""
    own_keys = {key(v) for v in own}
    live: dict[str, set[Key]] = {p: set() for p in g.nodes}

    def node(path: str) -> set[Key]:
        """What is live as the run arrives at `path`, its entry actions done."""
        n = g.nodes[path]
        if n.composite:
            return live[g.initial[path]]
        return live[path]

    def taken(leaf: str, t: ast.Transition) -> set[Key]:
        exits, enters = g.path(leaf, t.source, t.target)
        after = node(t.target)
        for p in reversed(enters):
            after = live_before(g.nodes[p].entry, after)
        after = live_before(t.action, after)
        for p in reversed(exits):
            after = live_before(g.nodes[p].exit, after)
        if t.trigger is not None:
            after = after | _reads(t.trigger.value) | _reads(t.condition)
            if t.trigger.kind == "input" and t.trigger.variable is not None:
                after = after - {key(t.trigger.variable)}
        else:
            after = after | _reads(t.condition)
        return after | _reads(t.deadline)

    # Trigger deadlines are read at rest and beyond: every deadline's bound at each step, and the
    # condition of a deadline transition of any ancestor while the machine is anywhere below it,
    # junctions included (the interpreter's `_armed`). What they read is live everywhere.
    always = set().union(*(_reads(t.deadline) | _reads(t.condition) for t in g.deadlines))
    step: Callable[[str], set[Key]] = lambda p: always.union(*(taken(p, t) for t in g.candidates(p)))  # noqa: E731
    try:
        changed = True
        while changed:
            changed = False
            for p, n in g.nodes.items():
                if n.composite:
                    continue
                new = step(p) & own_keys
                if new != live[p]:
                    live[p] = new
                    changed = True
    except _Unknown:
        return {}
    return {p: frozenset(own_keys - live[p]) for p, n in g.nodes.items() if n.kind in ("state", "final") and not n.composite}
