"""Compile a state machine into a flat automaton of atomic steps.

Every location is a point where the machine may pause: stable in a state, at a
junction, between two statements of an action, waiting, offering an output or
`terminate`.  Every edge is one step of `semantics.md` §2: an internal step
(`tau`), a visible event (`in`, `out`, `call`, `terminate`).  Time (`tock`) is
not an edge: it is possible at a location when no internal step and no urgent
call is possible there (maximal progress), and it advances clocks and `wait`s.

Entry and exit actions are resolved statically: the location a transition
leaves says which states are active, so the exits to run and the entries to
perform are known when the automaton is built.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from tockbmc.model import ast


class Unsupported(Exception):
    """A construct the encoding does not handle yet; carries its position."""

    def __init__(self, pos: ast.Pos, what: str):
        super().__init__(what)
        self.pos = pos
        self.what = what


@dataclass(frozen=True)
class Location:
    """A point where the machine pauses; `active` lists the active states, outermost first."""

    index: int
    description: str
    active: tuple[str, ...]
    kind: str = "action"  # stable | junction | action | waiting | final | terminated


@dataclass(frozen=True)
class Edge:
    """One atomic step from `source` to `target`.

    kind: tau | in | out | call | terminate | wait (tau that starts a wait of
    `wait_low..wait_high` tocks).  `guard` holds conditions over the variables
    (for `in` edges also over the input value, which `binds` stores in a
    variable); `updates` assigns variables in order; `value` is the sent value
    or the accepted value of a synchronisation; `args` are call arguments.
    """

    index: int
    source: int
    target: int
    kind: str
    event: ast.Event | None = None
    operation: ast.OperationSig | None = None
    guard: tuple[ast.Expr, ...] = ()
    binds: ast.Variable | None = None
    value: ast.Expr | None = None
    args: tuple[ast.Expr, ...] = ()
    updates: tuple[ast.Assign, ...] = ()
    resets: tuple[ast.Clock, ...] = ()
    wait_low: ast.Expr | None = None
    wait_high: ast.Expr | None = None
    transition: str | None = None  # name of the transition this step belongs to
    negated_guards: tuple[tuple[ast.Expr, ...], ...] = ()  # for `else`: none of these holds


@dataclass
class Automaton:
    """A machine as locations and edges; location 0 is the initial one."""

    machine: ast.StateMachine
    locations: list[Location] = field(default_factory=list)
    edges: list[Edge] = field(default_factory=list)

    def location(self, description: str, active: tuple[str, ...], kind: str = "action") -> int:
        self.locations.append(Location(len(self.locations), description, active, kind))
        return len(self.locations) - 1

    def edge(self, source: int, target: int, kind: str, **kw: object) -> Edge:
        e = Edge(len(self.edges), source, target, kind, **kw)  # type: ignore[arg-type]
        self.edges.append(e)
        return e

    @property
    def name(self) -> str:
        return self.machine.name


class _Builder:
    def __init__(self, machine: ast.StateMachine):
        self.m = machine
        self.a = Automaton(machine)
        self.stable: dict[str, int] = {}
        self.junction: dict[str, int] = {}
        self.final_top: dict[str, int] = {}
        self.terminated: int | None = None
        self._check_supported()

    # ------------------------------------------------------------ support checks

    def _check_supported(self) -> None:
        for n in self.m.nodes:
            if n.during is not None:
                raise Unsupported(n.during.pos, "during actions are not encoded yet")
            if n.kind == "probabilistic":
                raise Unsupported(n.pos, "probabilistic junctions")
            for s in (n.entry, n.exit):
                self._check_stmt(s)
        for t in self.m.transitions:
            if t.deadline is not None:
                raise Unsupported(t.deadline.pos, "transition deadlines '<{d}' are not encoded yet")
            self._check_stmt(t.action)
            for e in (t.condition, t.trigger.value if t.trigger else None):
                self._check_expr(e)

    def _check_stmt(self, s: ast.Stmt | None) -> None:
        for st in ast.statements(s):
            if isinstance(st, ast.Deadline):
                raise Unsupported(st.pos, "statement deadlines '<{d}' are not encoded yet")
            if isinstance(st, ast.OperationCall) and isinstance(st.operation, ast.OperationDef):
                raise Unsupported(st.pos, "calls of defined operations are not encoded yet")

    def _check_expr(self, e: ast.Expr | None) -> None:
        if isinstance(e, ast.SinceEntry):
            raise Unsupported(e.pos, "sinceEntry is not encoded yet")

    # ------------------------------------------------------------ structure

    def ancestors(self, path: str) -> tuple[str, ...]:
        """The states containing node `path`, outermost first (not the node itself)."""
        parts = path.split("::")
        return tuple("::".join(parts[:i]) for i in range(1, len(parts)))

    def chain(self, path: str) -> tuple[str, ...]:
        """`path` and its ancestors, outermost first."""
        return (*self.ancestors(path), path)

    def build(self) -> Automaton:
        # Stable locations first so that their numbers are easy to read.
        start = self.a.location("start", (), "action")
        for n in self.m.nodes:
            if n.kind in ("state",) or (n.kind == "final" and n.parent is not None):
                self.stable[n.path] = self.a.location(n.path, self.chain(n.path), "stable")
            elif n.kind == "junction":
                self.junction[n.path] = self.a.location(n.path, self.ancestors(n.path), "junction")
            elif n.kind == "final":
                self.final_top[n.path] = self.a.location(n.path, (n.path,), "final")
        if self.final_top:
            self.terminated = self.a.location("terminated", (), "terminated")
            for loc in self.final_top.values():
                self.a.edge(loc, self.terminated, "terminate")
        # The machine starts by taking its top-level initial transition.
        init = self._initial(None)
        cur = start
        if init.action is not None:
            cur = self._stmt(cur, init.action, (), f"{init.name}: action")
        self._follow(cur, init, ())
        for n in self.m.nodes:
            if n.path in self.stable:
                here, active = self.stable[n.path], self.chain(n.path)
            elif n.kind == "junction":
                here, active = self.junction[n.path], self.ancestors(n.path)
            else:
                continue
            # Candidates: the transitions of the active node and of every state containing it.
            for source in reversed(self.chain(n.path)):
                group = self._outgoing(source)
                for t in group:
                    self._fire(here, t, group, active)
        return self.a

    def _initial(self, region: str | None) -> ast.Transition:
        for n in self.m.nodes:
            if n.parent == region and n.kind == "initial":
                for t in self.m.transitions:
                    if t.source == n.path:
                        return t
        raise Unsupported(self.m.pos, f"region {region or self.m.name} has no initial transition")

    def _outgoing(self, path: str) -> list[ast.Transition]:
        return [t for t in self.m.transitions if t.source == path]

    # ------------------------------------------------------------ transitions

    def _common(self, a: str, b: str) -> tuple[str, ...]:
        """The states strictly containing both nodes, outermost first."""
        common = []
        for x, y in zip(self.ancestors(a), self.ancestors(b)):
            if x != y:
                break
            common.append(x)
        return tuple(common)

    def _fire(self, here: int, t: ast.Transition, group: list[ast.Transition], active: tuple[str, ...]) -> None:
        """Take `t` from location `here`: trigger, exits innermost first, action, entries."""
        guard = (t.condition,) if t.condition is not None else ()
        negated: tuple[tuple[ast.Expr, ...], ...] = ()
        if t.is_else:
            negated = tuple((o.condition,) for o in group
                            if o is not t and o.condition is not None and o.trigger == t.trigger)
        taken = self.a.location(f"taking {t.name}", active)
        trig = t.trigger
        common = dict(guard=guard, negated_guards=negated, resets=t.clock_resets, transition=t.name)
        if trig is None:
            self.a.edge(here, taken, "tau", **common)
        elif trig.kind == "output":
            self.a.edge(here, taken, "out", event=trig.event, value=trig.value, **common)
        else:
            self.a.edge(here, taken, "in", event=trig.event, binds=trig.variable, value=trig.value, **common)
        cur = taken
        shared = self._common(t.source, t.target)
        remaining = list(active)
        for s in reversed(active):
            if s in shared:
                break
            node = self.m.node(s)
            if node.exit is not None:
                cur = self._stmt(cur, node.exit, tuple(remaining), f"{s}: exit")
            remaining.remove(s)
        if t.action is not None:
            cur = self._stmt(cur, t.action, tuple(remaining), f"{t.name}: action")
        self._follow(cur, t, tuple(remaining))

    def _follow(self, cur: int, t: ast.Transition, active: tuple[str, ...]) -> None:
        """After `t`'s action: enter the states around its target, then the target."""
        target = self.m.node(t.target)
        for s in self.ancestors(target.path):
            if s not in active:
                cur = self._entry(cur, s, active)
                active = (*active, s)
        self._enter(cur, target, active)

    def _entry(self, cur: int, state: str, active: tuple[str, ...]) -> int:
        node = self.m.node(state)
        inside = (*active, state)
        if node.entry is not None:
            cur = self._stmt(cur, node.entry, inside, f"{state}: entry")
        return cur

    def _enter(self, cur: int, target: ast.Node, active: tuple[str, ...]) -> None:
        if target.kind == "junction":
            self._goto(cur, self.junction[target.path])
        elif target.kind == "final" and target.parent is None:
            self._goto(cur, self.final_top[target.path])
        elif target.path in self.stable:
            cur = self._entry(cur, target.path, active)
            if target.composite:
                init = self._initial(target.path)
                inside = (*active, target.path)
                if init.action is not None:
                    cur = self._stmt(cur, init.action, inside, f"{init.name}: action")
                self._follow(cur, init, inside)
            else:
                self._goto(cur, self.stable[target.path])
        else:
            raise Unsupported(target.pos, f"entering a {target.kind}")

    def _goto(self, cur: int, target: int) -> None:
        """Continue at `target`: redirect the one step into `cur` when that loses nothing."""
        into = [e for e in self.a.edges if e.target == cur]
        leaving = [e for e in self.a.edges if e.source == cur]
        if cur != 0 and len(into) == 1 and not leaving and self.a.locations[cur].kind == "action":
            e = into[0]
            self.a.edges[e.index] = dataclasses.replace(e, target=target)
        else:
            self.a.edge(cur, target, "tau")

    # ------------------------------------------------------------ statements

    def _stmt(self, cur: int, s: ast.Stmt, active: tuple[str, ...], where: str) -> int:
        """Emit the steps of `s` from location `cur`; returns the location after it."""
        if isinstance(s, ast.Skip):
            return cur
        if isinstance(s, ast.Seq):
            for x in s.statements:
                cur = self._stmt(cur, x, active, where)
            return cur
        nxt = self.a.location(where, active)
        if isinstance(s, ast.Assign):
            self.a.edge(cur, nxt, "tau", updates=(s,))
        elif isinstance(s, ast.Send):
            self.a.edge(cur, nxt, "out", event=s.event, value=s.value)
        elif isinstance(s, ast.Receive):
            self.a.edge(cur, nxt, "in", event=s.event, binds=s.variable)
        elif isinstance(s, ast.OperationCall):
            assert isinstance(s.operation, ast.OperationSig)
            self.a.edge(cur, nxt, "call", operation=s.operation, args=s.args)
        elif isinstance(s, ast.ClockReset):
            self.a.edge(cur, nxt, "tau", resets=(s.clock,))
        elif isinstance(s, ast.Wait):
            waiting = self.a.location(f"{where}: waiting", active, "waiting")
            self.a.edge(cur, waiting, "wait", wait_low=s.low, wait_high=s.high)
            self.a.edge(waiting, nxt, "tau", transition="wait over")
        elif isinstance(s, ast.If):
            then_start = self.a.location(where, active)
            else_start = self.a.location(where, active)
            self.a.edge(cur, then_start, "tau", guard=(s.condition,))
            self.a.edge(cur, else_start, "tau", negated_guards=((s.condition,),))
            self._goto(self._stmt(then_start, s.then, active, where), nxt)
            self._goto(self._stmt(else_start, s.otherwise, active, where), nxt)
        else:
            raise Unsupported(s.pos, f"statement {type(s).__name__}")
        return nxt


def compile_machine(machine: ast.StateMachine) -> Automaton:
    """The automaton of one state machine; raises `Unsupported` for what is not encoded yet."""
    return _Builder(machine).build()
