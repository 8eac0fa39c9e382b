"""Compile a state machine into a flat automaton of atomic steps.

Every location is a point where the machine may pause: stable in a state, at a
junction, between two statements of an action, waiting, offering an output or
`terminate`.  Every edge is one step of `docs/semantics.md` §3.2: an internal step
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
from tockbmc.model.during import composite_during_problem, composite_durings
from tockbmc.model.errors import Unsupported
from tockbmc.model.limits import MAX_DECLARATION_CHAIN


def entry_clock(state: str) -> str:
    """The name of the counter behind `sinceEntry(state)`: a clock reset once the state's entry action has run."""
    return f"sinceEntry({state})"


@dataclass(frozen=True)
class Location:
    """A point where the machine pauses; `active` lists the active states, outermost first."""

    index: int
    description: str
    active: tuple[str, ...]
    kind: str = "action"  # stable | junction | action | waiting | final | terminated
    deadline: bool = False  # inside a statement `S <{d}`: tock only while its counter is positive
    during_waiting: bool = False  # a composite state's during action (thread 1) is in a `wait` here


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
    resets: tuple[str, ...] = ()  # clocks set to 0 (`#C`, and `sinceEntry(S)` on entering S)
    deadline: ast.Expr | None = None  # starts a statement deadline of this many tocks
    wait_low: ast.Expr | None = None
    wait_high: ast.Expr | None = None
    transition: str | None = None  # name of the transition this step belongs to
    negated_guards: tuple[tuple[ast.Expr, ...], ...] = ()  # for `else`: none of these holds
    ends_wait: bool = False  # leaves a `wait` once its tocks have passed
    havoc: tuple[ast.Variable, ...] = ()  # variables that take any value of their type and range (fresh locals)
    exits: tuple[str, ...] = ()  # on a transition's first step: the states it leaves
    pos: ast.Pos | None = None  # the model text this step runs: a transition, a statement, a final state
    thread: int = 0  # 1: a step of a composite state's during action, beside its children (§4.1)


@dataclass(frozen=True)
class TriggerDeadline:
    """`trigger … <{bound}` on a transition: once its source is stable (`armed` locations) and its
    condition true, it must be taken within `bound` tocks (docs/semantics.md §4.6)."""

    transition: str
    source: str
    bound: ast.Expr
    condition: ast.Expr | None
    armed: frozenset[int]


@dataclass
class Automaton:
    """A machine as locations and edges; location 0 is the initial one."""

    machine: ast.StateMachine
    locations: list[Location] = field(default_factory=list)
    edges: list[Edge] = field(default_factory=list)
    trigger_deadlines: list[TriggerDeadline] = field(default_factory=list)
    # Declarations of the defined operations inlined at its calls: their variables and parameters
    # (with the operation's name for their own, "" for interface variables shared by name) and clocks.
    extra_variables: list[tuple[str, ast.Variable]] = field(default_factory=list)
    extra_clocks: list[str] = field(default_factory=list)
    inlined: dict[str, int] = field(default_factory=dict)  # operation name -> calls inlined so far
    # Edge indices by target and by source, kept by `edge` and `retarget` (lookups while building).
    _into: dict[int, list[int]] = field(default_factory=dict, repr=False, compare=False)
    _from: dict[int, list[int]] = field(default_factory=dict, repr=False, compare=False)
    _clocks: tuple[tuple[int, int], tuple[str, ...]] = field(default=((-1, -1), ()), repr=False, compare=False)

    def location(self, description: str, active: tuple[str, ...], kind: str = "action",
                 deadline: bool = False, during_waiting: bool = False) -> int:
        self.locations.append(Location(len(self.locations), description, active, kind, deadline, during_waiting))
        return len(self.locations) - 1

    def edge(self, source: int, target: int, kind: str, **kw: object) -> Edge:
        e = Edge(len(self.edges), source, target, kind, **kw)  # type: ignore[arg-type]
        self.edges.append(e)
        self._into.setdefault(target, []).append(e.index)
        self._from.setdefault(source, []).append(e.index)
        return e

    def edges_into(self, location: int) -> list[Edge]:
        return [self.edges[i] for i in self._into.get(location, ())]

    def edges_from(self, location: int) -> list[Edge]:
        return [self.edges[i] for i in self._from.get(location, ())]

    def retarget(self, e: Edge, target: int, pos: ast.Pos | None = None) -> None:
        """Make edge `e` lead to `target` instead (keeping its own source text, else taking `pos`)."""
        self._into[e.target].remove(e.index)
        self._into.setdefault(target, []).append(e.index)
        self.edges[e.index] = dataclasses.replace(e, target=target, pos=e.pos or pos)

    @property
    def name(self) -> str:
        return self.machine.name

    def copy_edge(self, e: Edge, source: int, target: int, **changes: object) -> Edge:
        """A copy of step `e` from `source` to `target` (with `changes` to its other fields)."""
        fields = {f.name: getattr(e, f.name) for f in dataclasses.fields(e)
                  if f.name not in ("index", "source", "target", "kind")}
        return self.edge(source, target, e.kind, **{**fields, **changes})

    def prune(self) -> None:
        """Drop the locations no step reaches from location 0, and their steps, numbering the rest
        in their order (so location 0 stays the initial one)."""
        reached = {0}
        todo = [0]
        while todo:
            for e in self.edges_from(todo.pop()):
                if e.target not in reached:
                    reached.add(e.target)
                    todo.append(e.target)
        number = {old: new for new, old in enumerate(sorted(reached))}
        self.locations = [dataclasses.replace(loc, index=number[loc.index]) for loc in self.locations
                          if loc.index in reached]
        edges = [e for e in self.edges if e.source in reached]
        self.edges, self._into, self._from = [], {}, {}
        for e in edges:
            self.copy_edge(e, number[e.source], number[e.target])
        self.trigger_deadlines = [dataclasses.replace(td, armed=frozenset(number[x] for x in td.armed if x in reached))
                                  for td in self.trigger_deadlines]

    @property
    def clocks(self) -> tuple[str, ...]:
        """The machine's clocks, then the `sinceEntry` counters its expressions read."""
        # Read once per edge while the unrolling is built: computed again only when edges are added.
        key = (len(self.edges), len(self.extra_clocks))
        if self._clocks[0] != key:
            own = [c.name for c in self.machine.clocks]
            extra = sorted(({r for e in self.edges for r in e.resets} | set(self.extra_clocks)) - set(own))
            self._clocks = (key, (*own, *extra))
        return self._clocks[1]

    def _kinds(self, *kinds: str) -> frozenset[int]:
        return frozenset(loc.index for loc in self.locations if loc.kind in kinds)

    @property
    def terminated(self) -> frozenset[int]:
        return self._kinds("terminated")

    @property
    def waiting(self) -> frozenset[int]:
        return self._kinds("waiting")

    @property
    def during_waiting(self) -> frozenset[int]:
        """Locations where a composite state's during action (thread 1) is in a `wait`."""
        return frozenset(loc.index for loc in self.locations if loc.during_waiting)

    @property
    def threaded(self) -> bool:
        """Whether a composite state's during action runs beside its children somewhere (thread 1)."""
        return any(e.thread == 1 for e in self.edges)

    @property
    def urgent(self) -> frozenset[int]:
        """Locations offering an operation call, which is urgent (docs/semantics.md §4.7)."""
        return frozenset(e.source for e in self.edges if e.kind == "call")

    @property
    def deadlined(self) -> frozenset[int]:
        return frozenset(loc.index for loc in self.locations if loc.deadline)


class _Builder:
    """Builds a machine's automaton; a nested builder inlines a defined operation at a call.

    `defined` maps operation names to the definitions a controller binds (`opref`); `outer`
    holds the caller's active states (prefixed to every location of an inlined operation), and
    `calls` the operations being inlined (recursion is unsupported).
    """

    def __init__(self, machine: ast.Behaviour, automaton: Automaton | None = None,
                 defined: dict[str, ast.OperationDef] | None = None, outer: tuple[str, ...] = (),
                 in_deadline: bool = False, calls: tuple[str, ...] = ()):
        self.m = machine
        self.a = automaton or Automaton(machine)  # type: ignore[arg-type]
        self.defined = defined or {}
        self.outer = outer
        self.calls = calls
        self.ret: int | None = None  # for an inlined operation: where its final state returns to
        self.stable: dict[str, int] = {}
        self.junction: dict[str, int] = {}
        self.final_top: dict[str, int] = {}
        self.terminated: int | None = None
        self.in_state: dict[str, list[int]] = {}  # leaf state -> locations of its during action
        self.during_start: dict[str, int] = {}
        self.since_entry = self._since_entry_states()
        self._in_deadline = in_deadline
        # Composite states whose during action runs beside their children (thread 1), and the steps
        # that enter their first child (where that thread starts), by state.
        self.threaded = {n.path: n for n in composite_durings(machine)}
        self.thread_starts: dict[str, list[int]] = {p: [] for p in self.threaded}
        # Looked up once per node: states may nest hundreds deep, and paths grow with the nesting.
        self._nodes = {n.path: n for n in machine.nodes}
        self._ancestors: dict[str, tuple[str, ...]] = {}
        self._initials: dict[str | None, ast.Transition] = {}
        self._from: dict[str, list[ast.Transition]] = {}
        for t in machine.transitions:
            self._from.setdefault(t.source, []).append(t)
        self._check_supported()

    def _location(self, description: str, active: tuple[str, ...], kind: str = "action",
                  deadline: bool = False) -> int:
        return self.a.location(description, (*self.outer, *active), kind, deadline or self._in_deadline)

    # ------------------------------------------------------------ support checks

    def _check_supported(self) -> None:
        problem = composite_during_problem(self.m, self._definition, bool(self.calls))
        if problem is not None:
            raise Unsupported(*problem)
        for n in self.m.nodes:
            if n.kind == "probabilistic":
                raise Unsupported(n.pos, "probabilistic junctions")
            for s in (n.entry, n.during, n.exit):
                self._check_stmt(s)
        for t in self.m.transitions:
            if t.deadline is not None and t.is_else:
                raise Unsupported(t.deadline.pos, "deadlines on 'else' transitions are not encoded yet")
            if t.deadline is not None and t.trigger is not None and t.trigger.variable is not None \
                    and _reads(t.condition, t.trigger.variable):
                raise Unsupported(t.deadline.pos, "a deadline on a transition whose condition reads its "
                                                  "input is not encoded yet")
            self._check_stmt(t.action)

    def _check_stmt(self, s: ast.Stmt | None) -> None:
        for st in ast.statements(s):
            if isinstance(st, ast.OperationCall):
                op = self._definition(st)
                if op is not None and op.qname in self.calls:
                    raise Unsupported(st.pos, f"operation {op.name} calls itself; recursive operations are not "
                                              "encoded")
                if op is not None and len(self.calls) >= MAX_DECLARATION_CHAIN:  # inlining recurses per call
                    raise Unsupported(st.pos, f"operations calling operations more than {MAX_DECLARATION_CHAIN} "
                                              "deep are not encoded")

    def _definition(self, call: ast.OperationCall) -> ast.OperationDef | None:
        """The definition a call runs (inlined), or None for a platform operation (an event)."""
        op = call.operation if isinstance(call.operation, ast.OperationDef) else self.defined.get(call.operation.name)
        if op is None or (op.terminates and not op.nodes):
            return None  # an operation whose body is only `terminates` is the platform's (docs/semantics.md §4.7)
        return op

    def _since_entry_states(self) -> set[str]:
        """The states whose time since entry some expression of the machine reads."""
        parts: list[tuple[object, ...]] = [(n.entry, n.during, n.exit) for n in self.m.nodes]
        parts += [(t.condition, t.action, t.deadline, t.trigger.value if t.trigger else None)
                  for t in self.m.transitions]
        return {e.state for e in ast.subexpressions(tuple(parts)) if isinstance(e, ast.SinceEntry)}

    # ------------------------------------------------------------ structure

    def ancestors(self, path: str) -> tuple[str, ...]:
        """The states containing node `path`, outermost first (not the node itself)."""
        known = self._ancestors
        todo = []
        p = path
        while p not in known:
            todo.append(p)
            if "::" not in p:
                known[p] = ()
                break
            p = p.rsplit("::", 1)[0]
        for q in reversed(todo):
            if q not in known:
                parent = q.rsplit("::", 1)[0]
                known[q] = (*known[parent], parent)
        return known[path]

    def chain(self, path: str) -> tuple[str, ...]:
        """`path` and its ancestors, outermost first."""
        return (*self.ancestors(path), path)

    def build(self) -> Automaton:
        # Stable locations first so that their numbers are easy to read.
        start = self._location("start", (), "action")
        self._layout()
        # The machine starts by taking its top-level initial transition.
        self._start(start)
        self._transitions()
        self._threads()
        if self.threaded:
            self.a.prune()  # the product leaves its templates and the children's side alone unreachable
        return self.a

    def inline(self, cur: int) -> int:
        """Run the operation from `cur` to one of its final states; returns where the caller goes on."""
        self.ret = self._location("return", ())
        self._layout()
        self._start(cur)
        self._transitions()
        return self.ret

    def _start(self, cur: int) -> None:
        init = self._initial(None)
        if init.action is not None:
            cur = self._stmt(cur, init.action, (), f"{init.name}: action")
        self._follow(cur, init, ())

    def _layout(self) -> None:
        for n in self.m.nodes:
            if n.kind in ("state",) or (n.kind == "final" and n.parent is not None):
                self.stable[n.path] = self._location(n.path, self.chain(n.path), "stable")
            elif n.kind == "junction":
                self.junction[n.path] = self._location(n.path, self.ancestors(n.path), "junction")
            elif n.kind == "final" and self.ret is not None:
                self.final_top[n.path] = self.ret  # an operation's final state returns to its caller
            elif n.kind == "final":
                self.final_top[n.path] = self._location(n.path, (n.path,), "final")
        if self.final_top and self.ret is None:
            self.terminated = self._location("terminated", (), "terminated")
            for path, loc in self.final_top.items():
                self.a.edge(loc, self.terminated, "terminate", pos=self.m.node(path).pos)
        for n in self.m.nodes:
            if n.during is not None and n.path in self.stable and not n.composite:
                self._during(n, self.chain(n.path))

    def _transitions(self) -> None:
        armed: dict[str, set[int]] = {}
        for n in self.m.nodes:
            if n.path in self.stable:
                here, active = self.stable[n.path], self.chain(n.path)
            elif n.kind == "junction":
                here, active = self.junction[n.path], self.ancestors(n.path)
            else:
                continue
            # Candidates: the transitions of the active node and of every state containing it;
            # a during action is abandoned when one is taken (docs/semantics.md §4.1).
            for loc in (here, *self.in_state.get(n.path, ())):
                for source in reversed(self.chain(n.path)):
                    group = self._outgoing(source)
                    for t in group:
                        self._fire(loc, t, group, active)
                        if t.deadline is not None and n.kind != "junction":
                            armed.setdefault(t.name, set()).add(loc)
        for t in self.m.transitions:
            if t.deadline is not None and t.name in armed:
                self.a.trigger_deadlines.append(TriggerDeadline(t.name, t.source, t.deadline, t.condition,
                                                                frozenset(armed[t.name])))

    def _initial(self, region: str | None) -> ast.Transition:
        if region not in self._initials:
            initials = [n for n in self.m.nodes if n.parent == region and n.kind == "initial"]
            if len(initials) > 1:  # RoboTool warns (STM3) and gives entering the region no meaning
                raise Unsupported(initials[1].pos, f"region {region or self.m.name} has more than one initial junction")
            for n in initials:
                for t in self.m.transitions:
                    if t.source == n.path:
                        self._initials[region] = t
                        return t
            raise Unsupported(self.m.pos, f"region {region or self.m.name} has no initial transition")
        return self._initials[region]

    def _outgoing(self, path: str) -> list[ast.Transition]:
        return self._from.get(path, [])

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
        taken = self._location(f"taking {t.name}", active)
        trig = t.trigger
        resets = tuple(c.name for c in t.clock_resets)
        shared = self._common(t.source, t.target)
        exits = tuple(x for x in active if x not in shared)
        common = dict(guard=guard, negated_guards=negated, resets=resets, transition=t.name, exits=exits, pos=t.pos)
        if trig is None:
            self.a.edge(here, taken, "tau", **common)
        elif trig.kind == "output":
            self.a.edge(here, taken, "out", event=trig.event, value=trig.value, **common)
        else:
            self.a.edge(here, taken, "in", event=trig.event, binds=trig.variable, value=trig.value, **common)
        cur = taken
        remaining = list(active)
        for s in reversed(active):
            if s in shared:
                break
            node = self._nodes[s]
            if node.exit is not None:
                cur = self._stmt(cur, node.exit, tuple(remaining), f"{s}: exit")
            remaining.remove(s)
        if t.action is not None:
            cur = self._stmt(cur, t.action, tuple(remaining), f"{t.name}: action")
        self._follow(cur, t, tuple(remaining))

    def _follow(self, cur: int, t: ast.Transition, active: tuple[str, ...]) -> None:
        """After `t`'s action: enter the states around its target, then the target, and on through
        the initial transitions of composite states (a loop: states may nest hundreds deep)."""
        # A composite state is entered once the states its initial transitions lead to are
        # (docs/semantics.md §4.2): its `sinceEntry` counts from there, so its reset waits.
        step: tuple[int, ast.Transition, tuple[str, ...], tuple[str, ...]] | None = (cur, t, active, ())
        while step is not None:
            cur, t, active, pending = step
            target = self._nodes[t.target]
            outer = self.ancestors(target.path)
            # `active` and `outer` are both chains from the top: their common part is a prefix.
            shared = next((k + 1 for k in range(min(len(active), len(outer)) - 1, -1, -1)
                           if active[k] == outer[k]), 0)
            for s in outer[shared:]:
                cur = self._entry(cur, s, active, defer=True)
                active = (*active, s)
                pending = (*pending, s)
            step = self._enter(cur, target, active, t.pos, pending)

    def _entered(self, cur: int, states: tuple[str, ...], active: tuple[str, ...], pos: ast.Pos | None) -> int:
        """The states just entered start counting `sinceEntry`, as RoboTool's `S::entered` does."""
        clocks = tuple(entry_clock(s) for s in states if s in self.since_entry)
        if not clocks:
            return cur
        nxt = self._location(f"{states[-1]}: entered", active)
        self.a.edge(cur, nxt, "tau", resets=clocks, pos=pos)
        return nxt

    def _entry(self, cur: int, state: str, active: tuple[str, ...], defer: bool = False) -> int:
        node = self._nodes[state]
        inside = (*active, state)
        if node.entry is not None or state in self.since_entry:
            # The state is entered when its entry action starts (docs/semantics.md §7.4 `is reachable`): the entry runs
            # from a location where the state is already active (no extra step when the step into
            # `cur` can lead here directly).
            nxt = self._location(f"{state}: entering", inside)
            self._goto(cur, nxt)
            cur = nxt
        if node.entry is not None:
            cur = self._stmt(cur, node.entry, inside, f"{state}: entry")
        if not defer:  # counted from the end of the entry action, as RoboTool's `S::entered`
            cur = self._entered(cur, (state,), inside, node.pos)
        return cur

    def _enter(self, cur: int, target: ast.Node, active: tuple[str, ...], pos: ast.Pos | None = None,
               pending: tuple[str, ...] = ()) -> tuple[int, ast.Transition, tuple[str, ...], tuple[str, ...]] | None:
        """Enter `target` at the end of a transition (`pos`); for a composite state, returns its
        initial transition for `_follow` to take.  `pending`: the states being entered around it,
        whose `sinceEntry` starts once `target` (and its initial states) are entered."""
        if target.kind == "junction" or (target.kind == "final" and target.parent is None):
            # a junction's location is shared by every way in: what is being entered counts from here
            cur = self._entered(cur, pending, active, pos)
            self._goto(cur, self.junction[target.path] if target.kind == "junction" else self.final_top[target.path],
                       pos)
        elif target.path in self.stable:
            cur = self._entry(cur, target.path, active, defer=True)
            pending = (*pending, target.path)
            if target.composite:
                init = self._initial(target.path)
                inside = (*active, target.path)
                if init.action is not None:
                    cur = self._stmt(cur, init.action, inside, f"{init.name}: action")
                return cur, init, inside, pending
            cur = self._entered(cur, pending, (*active, target.path), target.pos)
            if target.during is not None:
                step = self._goto(cur, self._during(target, (*active, target.path)))
            else:
                step = self._goto(cur, self.stable[target.path], pos)
            # A composite state entered by this transition starts its during action beside the child.
            for s in pending:
                if s in self.threaded:
                    self.thread_starts[s].append(step)
        else:
            raise Unsupported(target.pos, f"entering a {target.kind}")
        return None

    def _during(self, state: ast.Node, active: tuple[str, ...]) -> int:
        """The start of a leaf state's during action, built once; it ends in the stable location of `state`."""
        if state.path not in self.during_start:
            first = len(self.a.locations)
            start = self._location(f"{state.path}: during", active)
            self.during_start[state.path] = start
            assert state.during is not None
            end = self._stmt(start, state.during, active, f"{state.path}: during")
            self._goto(end, self.stable[state.path])
            self.in_state[state.path] = [loc.index for loc in self.a.locations[first:]
                                         if loc.index != self.stable[state.path]]
        return self.during_start[state.path]

    def _threads(self) -> None:
        """Run each composite state's during action beside its children: a product of two threads.

        For a state S, the children's side is every location reached from the child locations that
        S's starts (the steps entering S's first child) lead to, without leaving S; the during
        action's side is its own statements, built here once as a template.  Each pair is a
        location; a child's step keeps the during action where it is, a step of the during action
        (thread 1) keeps the children where they are, and a step leaving S leaves the during action
        behind (docs/semantics.md §4.1).  Every state's pairs are made before any step is copied,
        so that a step that leaves one state and enters another, or re-enters the same one (folded
        by `_goto` into the step that starts its thread), starts the thread it enters."""
        a = self.a
        built: list[tuple[str, int, list[Location], list[Edge], list[int], dict[tuple[int, int], int]]] = []
        for path, state in self.threaded.items():
            assert state.during is not None
            active = self.chain(path)
            first, first_edge = len(a.locations), len(a.edges)
            d0 = self._location(f"{path}: during", active)
            self._stmt(d0, state.during, active, f"{path}: during")
            template, steps = a.locations[first:], a.edges[first_edge:]
            side = self._side(path, [a.edges[s].target for s in self.thread_starts[path]])
            pair: dict[tuple[int, int], int] = {}
            for c in side:
                loc = a.locations[c]
                for d in template:
                    pair[c, d.index] = a.location(f"{loc.description} ∥ {d.description}", loc.active, loc.kind,
                                                  loc.deadline, during_waiting=d.kind == "waiting")
            built.append((path, d0, template, steps, side, pair))
        start = {s: pair[a.edges[s].target, d0] for path, d0, _t, _s, _side, pair in built
                 for s in self.thread_starts[path]}
        for path, _d0, template, steps, side, pair in built:
            for c in side:
                for e in a.edges_from(c):
                    for d in template:
                        target = start.get(e.index, e.target) if path in e.exits else pair[e.target, d.index]
                        a.copy_edge(e, pair[c, d.index], target)
            for e in steps:
                for c in side:
                    a.copy_edge(e, pair[c, e.source], pair[c, e.target], thread=1)
        for s, target in start.items():
            a.retarget(a.edges[s], target)
        for _path, _d0, template, _steps, side, pair in built:
            a.trigger_deadlines = [
                dataclasses.replace(td, armed=td.armed | {pair[c, d.index] for c in td.armed & set(side)
                                                          for d in template})
                for td in a.trigger_deadlines]

    def _side(self, path: str, entered: list[int]) -> list[int]:
        """The locations reached from `entered` by steps that stay inside state `path`."""
        side: list[int] = []
        seen: set[int] = set()
        todo = list(entered)
        while todo:
            c = todo.pop()
            if c in seen:
                continue
            seen.add(c)
            side.append(c)
            if path not in self.a.locations[c].active:  # pragma: no cover - every step inside keeps it active
                raise Unsupported(self._nodes[path].pos, f"a step of {path}'s children leaves it without exiting it")
            todo += [e.target for e in self.a.edges_from(c) if path not in e.exits]
        return side

    def _goto(self, cur: int, target: int, pos: ast.Pos | None = None) -> int:
        """Continue at `target`: redirect the one step into `cur` when that loses nothing; returns
        the step that now leads to `target`."""
        into = self.a.edges_into(cur)
        if cur != 0 and len(into) == 1 and not self.a.edges_from(cur) and self.a.locations[cur].kind == "action":
            self.a.retarget(into[0], target, pos)
            return into[0].index
        return self.a.edge(cur, target, "tau", pos=pos).index

    # ------------------------------------------------------------ statements

    def _stmt(self, cur: int, s: ast.Stmt, active: tuple[str, ...], where: str) -> int:
        """Emit the steps of `s` from location `cur`; returns the location after it."""
        if isinstance(s, ast.Skip):
            return cur
        if isinstance(s, ast.Seq):
            for x in s.statements:
                cur = self._stmt(cur, x, active, where)
            return cur
        if isinstance(s, ast.Deadline):
            if self._in_deadline:
                raise Unsupported(s.pos, "nested deadlines '<{d}' are not encoded yet")
            start = self._location(where, active, deadline=True)
            self.a.edge(cur, start, "tau", deadline=s.bound, pos=s.pos)
            self._in_deadline = True
            try:
                end = self._stmt(start, s.statement, active, where)
            finally:
                self._in_deadline = False
            nxt = self._location(where, active)
            self.a.edge(end, nxt, "tau")
            return nxt
        nxt = self._location(where, active, deadline=self._in_deadline)
        if isinstance(s, ast.Assign):
            self.a.edge(cur, nxt, "tau", updates=(s,), pos=s.pos)
        elif isinstance(s, ast.Send):
            self.a.edge(cur, nxt, "out", event=s.event, value=s.value, pos=s.pos)
        elif isinstance(s, ast.Receive):
            self.a.edge(cur, nxt, "in", event=s.event, binds=s.variable, pos=s.pos)
        elif isinstance(s, ast.OperationCall):
            op = self._definition(s)
            if op is None:
                self.a.edge(cur, nxt, "call", operation=s.operation, args=s.args, pos=s.pos)
            else:
                self._goto(self._inline(cur, op, s, active), nxt)
        elif isinstance(s, ast.ClockReset):
            self.a.edge(cur, nxt, "tau", resets=(s.clock.name,), pos=s.pos)
        elif isinstance(s, ast.Wait):
            waiting = self._location(f"{where}: waiting", active, "waiting", self._in_deadline)
            self.a.edge(cur, waiting, "wait", wait_low=s.low, wait_high=s.high, pos=s.pos)
            self.a.edge(waiting, nxt, "tau", transition="wait over", ends_wait=True, pos=s.pos)
        elif isinstance(s, ast.If):
            then_start = self._location(where, active, deadline=self._in_deadline)
            else_start = self._location(where, active, deadline=self._in_deadline)
            self.a.edge(cur, then_start, "tau", guard=(s.condition,), pos=s.pos)
            self.a.edge(cur, else_start, "tau", negated_guards=((s.condition,),), pos=s.pos)
            self._goto(self._stmt(then_start, s.then, active, where), nxt)
            self._goto(self._stmt(else_start, s.otherwise, active, where), nxt)
        elif isinstance(s, ast.UnsupportedStmt):  # `properties.queries.query` refuses it first
            raise Unsupported(s.pos, s.what)
        else:
            raise Unsupported(s.pos, f"statement {type(s).__name__}")
        return nxt


    def _inline(self, cur: int, op: ast.OperationDef, call: ast.OperationCall, active: tuple[str, ...]) -> int:
        """Inline a defined operation: parameters take the arguments, then its graph runs to a final state.

        Its nodes and transitions are renamed `op().path` (numbered when inlined again) so that
        they are distinct from the machine's; its variables and clocks are declared once.
        """
        op = ast.provided_for(self.m, op)  # the variables it requires that the calling operation declares
        self.a.inlined[op.name] = self.a.inlined.get(op.name, 0) + 1
        label = f"{op.name}()" + (f"#{self.a.inlined[op.name]}" if self.a.inlined[op.name] > 1 else "")
        for v in (*op.parameters, *op.variables):
            if (op.name, v) not in self.a.extra_variables:
                self.a.extra_variables.append((op.name, v))
        for v in op.interface_variables:
            if ("", v) not in self.a.extra_variables:
                self.a.extra_variables.append(("", v))
        self.a.extra_clocks += [c.name for c in op.clocks if c.name not in self.a.extra_clocks]
        # Each call is a new activation: parameters take the arguments, the operation's variables
        # their initial values, or any value when they have none.
        locals_ = [v for v in op.variables if not v.constant]
        if op.parameters or locals_:
            nxt = self._location(f"call {op.name}", active)
            updates = tuple(ast.Assign(call.pos, p, (), a) for p, a in zip(op.parameters, call.args, strict=True))
            updates += tuple(ast.Assign(call.pos, v, (), v.initial) for v in locals_ if v.initial is not None)
            havoc = tuple(v for v in locals_ if v.initial is None)
            self.a.edge(cur, nxt, "tau", updates=updates, havoc=havoc, pos=call.pos)
            cur = nxt
        inner = _Builder(_renamed(op, label), self.a, self.defined, (*self.outer, *active), self._in_deadline,
                         (*self.calls, op.qname))
        return inner.inline(cur)


def _renamed(op: ast.OperationDef, label: str) -> ast.OperationDef:
    """The operation with its node paths and transition names prefixed by `label.`."""

    def path(p: str | None) -> str | None:
        return None if p is None else f"{label}.{p}"

    nodes = tuple(dataclasses.replace(n, path=f"{label}.{n.path}", parent=path(n.parent),
                                      children=tuple(path(c) or "" for c in n.children)) for n in op.nodes)
    transitions = tuple(dataclasses.replace(t, name=f"{label}.{t.name}", source=path(t.source) or "",
                                            target=path(t.target) or "", container=path(t.container))
                        for t in op.transitions)
    return dataclasses.replace(op, nodes=nodes, transitions=transitions)


def _reads(e: ast.Expr | None, v: ast.Variable) -> bool:
    """Whether expression `e` reads variable `v`."""
    return any(isinstance(x, ast.VarRef) and x.variable is v for x in ast.subexpressions(e))


def compile_machine(machine: ast.StateMachine, defined: dict[str, ast.OperationDef] | None = None) -> Automaton:
    """The automaton of one state machine; raises `Unsupported` for what is not encoded yet.

    `defined` gives the definitions its controller binds to the operations it calls (`opref`).
    """
    return _Builder(machine, defined=defined).build()
