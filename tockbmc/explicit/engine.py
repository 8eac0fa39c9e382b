"""The explicit-state engine: breadth-first search over concrete configurations.

It decides the same assertions as BMC with the independent interpreter
(`explicit.interpreter`), for finite data ranges only.  The search is by the
number of visible steps (events and tocks; internal steps cost nothing), so a
counterexample has as few visible steps as any, and it stops at `bound`
visible steps or at `max_states` configurations (then the verdict is
`unknown`).  Specifications of `refines` run as the same monitors BMC uses,
fed with the interpreter's concrete events.  The number of configurations and
transitions explored is reported, like FDR's "states" and "transitions".  Inputs
are chosen lazily, where a step depends on them (`Search`; DESIGN.md, "Lazy
inputs"), and counterexamples are made concrete afterwards.
"""

from __future__ import annotations

import itertools
import math
import time
from collections import deque
from collections.abc import Callable, Hashable, Iterable, Iterator
from dataclasses import replace
from fractions import Fraction
from functools import partial
from typing import NamedTuple, cast

from tockbmc.explicit.interpreter import (
    Config,
    Interpreter,
    NotInterpretable,
    Split,
    Step,
    Unbounded,
    fill,
    has_unknowns,
    unknowns,
)
from tockbmc.explicit.lts import element_lts
from tockbmc.model import ast, probabilistic
from tockbmc.model.config import Configuration, Setup, configure
from tockbmc.model.data import Variant
from tockbmc.model.errors import Unsupported
from tockbmc.model.limits import NO_START, TOO_DEEP_TO_CHECK
from tockbmc.model.ranges import Ranges
from tockbmc.model.result import Proof, Result, TraceStep, Verdict, within_no_steps
from tockbmc.properties.both import decide_in_both
from tockbmc.properties.deadlock import on_cycle
from tockbmc.properties.failures import (
    FAILURES_MODELS,
    Offer,
    SpecRefusal,
    acceptance_text,
    acceptances,
    divergent_state,
    offer_text,
    refuse_context,
    spec_refusals,
)
from tockbmc.properties.goals import Query, one_value_only, per_value_reason
from tockbmc.properties.inclusion import INCLUSION_LENGTH, SpecTrace, next_events, spec_traces
from tockbmc.properties.process import _event_text, after_termination
from tockbmc.properties.queries import given_spec, query, unprefixed_tock
from tockbmc.properties.spec import OTHER, Channel, EnumValue, Monitor, TooLarge, _same
from tockbmc.properties.ticktock import (
    TICK_TOCK,
    kept_after,
    observation_checks,
    observation_steps,
    tock_groups,
    tock_refusal_list,
)

DEFAULT_MAX_STATES = 1_000_000
OPEN_POINTS = "open points"  # a result's note of the open functions whose values the search chose
REFUSAL_MODELS = (*FAILURES_MODELS, TICK_TOCK)  # the models whose checks read what a configuration refuses
# The assertions searched lazily: each decided by a condition on one node at a time.
LAZY_KINDS = ("refines", "equals", "terminates", "timelock-free", "reachable")


def python_settings(settings: dict[str, ast.Expr]) -> dict[str, object]:
    """Constant values as Python values (literals, enumeration literals, records of them)."""

    def python(name: str, e: ast.Expr) -> object:
        if isinstance(e, ast.Literal):
            return e.value
        if isinstance(e, ast.EnumLiteral) and e.args:
            return Variant((f"{e.enum.name}::{e.literal}", *(python(name, a) for a in e.args)))
        if isinstance(e, ast.EnumLiteral):
            return f"{e.enum.name}::{e.literal}"
        if isinstance(e, ast.RecordLiteral):
            if e.omitted:  # open fields only as an initial value (DESIGN.md, record literals)
                raise Unsupported(e.pos, f"a record literal omitting fields as the value given to constant {name}")
            return {f: python(name, v) for f, v in e.fields}  # a Record once the interpreter coerces it
        if isinstance(e, ast.Unary) and e.op == "-" and isinstance(e.operand, ast.Literal) \
                and isinstance(e.operand.value, (int, Fraction)) and not isinstance(e.operand.value, bool):
            return -e.operand.value  # `set to -1` is a negated literal in the grammar
        raise Unsupported(None, f"the value given to constant {name} is not a literal")

    return {name: python(name, e) for name, e in settings.items()}


class Edge(NamedTuple):
    """A step of the search: as it counts (an event its context hides is internal), the node it
    leads to (with a lazy interpreter, before `Search.parts` splits its configuration), and the
    step as the interpreter gave it."""

    step: Step
    node: Hashable
    raw: Step


WITNESS_NODES = 20_000  # the most nodes `Search.for_every_choice` looks at before it gives up


class _OutOfBudget(Exception):
    """`Search.for_every_choice` has looked at `WITNESS_NODES` nodes."""


class _Strict(Exception):
    """The specification tells apart values of `channel` that the lazy search left unchosen."""

    def __init__(self, channel: tuple) -> None:
        super().__init__(f"values of {channel} are told apart")
        self.channel = channel


MONITOR_CHOICES = 4096  # past this many values of an event's Unknowns, the monitor's terms are read instead


class Search:
    """One assertion's search; `found(node, steps)` says whether a node is a target.

    A node is a configuration and a monitor state. With a lazy interpreter, a configuration may
    hold Unknowns (inputs and open initial values no step has read yet); the search's nodes are the
    configurations `Interpreter.expand` gives, whose steps do not depend on their Unknowns' values,
    so that every configuration a node stands for has the same steps, and a condition on one node
    (no tock, no step, terminated, in a state, a dead monitor) holds of all of them. A step whose event carries
    Unknowns to the monitor must lead to one monitor state whatever their values; otherwise the
    channel's values are chosen at once (`Interpreter.strict`) and the search starts again.
    """

    def __init__(self, interp: Interpreter, q: Query, bound: int, max_states: int, deadline: float | None,
                 progress: Callable[[int], None] | None = None):
        self.interp, self.q, self.bound, self.max_states, self.deadline = interp, q, bound, max_states, deadline
        self.progress = progress  # told each number of visible steps the search has got past
        # Partial-order reduction (`Interpreter.private_steps`): not where the verdict reads the
        # states internal steps pass through (reachability of a state).
        self.reduce = q.assertion.kind != "reachable"
        self.reached = -1
        self.context = q.context
        self.monitor: Monitor | None = None
        if q.context is not None and q.context.spec is not None:
            try:
                q.context.sem.alphabet = element_alphabet(q.element)
                q.context.sem.values = channel_values(interp, q.element,
                                                      {v.text: v for v in q.context.sem.evaluator.literals.values()})
                self.monitor = Monitor(q.context.sem, q.context.spec, [])
            except TooLarge:
                raise Unsupported(None, "the specification has too many states") from None
        self.literals = _literals(q)
        self._after: dict[tuple, int] = {}
        # The tick-tock model: the monitor state after a tock, from the state before and the stable
        # configuration's visible steps (`ConcreteRefusals.after_tock`); None elsewhere.
        self.tock_filter: Callable[[int, list[Step]], int] | None = None
        self.reset()

    def reset(self) -> None:
        self.transitions = 0
        self.complete = True  # every configuration within the bound was expanded
        self.parent: dict[Hashable, tuple[Hashable, Edge] | None] = {}
        self.depth: dict[Hashable, int] = {}
        self.succ: dict[Hashable, list[Edge]] = {}
        self.raw: dict[Config, tuple[Config, list[Step]]] = {}  # the canonical configuration and its steps
        self.split: dict[Config, list[Config]] = {}  # a configuration to the canonical ones it stands for
        self.configs: dict[Config, Config] = {}  # every configuration a step leads to, one object each
        self.witness: tuple[Hashable, tuple[TraceStep, ...]] | None = None  # the last run `trace` gave
        self.every_choice: Hashable | None = None  # a witness `for_every_choice` showed for every function

    # --- the element in its CSP context

    def parts(self, config: Config) -> list[Config]:
        """The configurations that are nodes for `config` (itself unless the interpreter splits it)."""
        if not self.interp.splits:
            return [config]
        hit = self.raw.get(config)
        if hit is not None:
            return [hit[0]]
        parts = self.split.get(config)
        if parts is not None:
            return parts
        parts = []
        for part, steps in self.interp.expand(config):
            known = self.raw.get(part)
            if known is None:
                known = self.raw[part] = (part, self._canonical(steps))
            parts.append(known[0])
        if len(parts) != 1 or parts[0] is not config:
            self.split[config] = parts
        return parts

    def check_time(self) -> None:
        """Raise `TimeoutError` once the check's deadline has passed (every search loop asks)."""
        if self.deadline is not None and time.monotonic() > self.deadline:
            raise TimeoutError

    def steps(self, key: Hashable) -> list[Edge]:
        if key in self.succ:
            return self.succ[key]
        config, mon = cast("tuple[Config, int | None]", key)
        hit = self.raw.get(config)
        known = None
        # With configurations that split, only one `expand` gave (whose steps read no Unknown) is reduced.
        if self.reduce and (hit is not None or not self.interp.splits):
            ample, known = self.interp.private_steps(config)
            # The cycle proviso: a node whose ample step leads to a node already expanded, or back
            # to itself, is expanded in full, so that on every cycle of the reduced graph (a loop
            # included) the node expanded last is.
            if ample is not None and not any(st.target == config or (st.target, mon) in self.succ for st in ample):
                hit = (config, self._canonical(ample))
        if hit is None:
            if self.interp.splits:
                self.parts(config)
                hit = self.raw.get(config)
                if hit is None:  # split, yet asked for as a node by a search that does not take parts
                    raise Unsupported(None, "this check of a model with a function it leaves open (or an input "
                                            "read late) needs the configurations the explicit engine splits")
            else:
                hit = (config, self._canonical(self.interp.steps(config, known=known)))
                if self.monitor is not None:  # kept for the configuration's other monitor states
                    self.raw[config] = hit
        raw = hit[1]
        out: list[Edge] = []
        hidden_possible = False
        classified = []
        for s in raw:
            status = self._status(s)
            if status == "blocked":
                continue
            if status == "hidden" and s.kind == "event":
                hidden_possible = True
            classified.append((s, status))
        shown = [s for s, status in classified if s.kind in ("event", "tock") and status != "hidden"]
        for s, status in classified:
            if s.kind == "tock" and hidden_possible:
                continue  # hidden events are internal, hence urgent (maximal progress)
            visible = s.kind in ("event", "tock") and status != "hidden"
            nxt_mon = mon
            if visible and self.monitor is not None and mon is not None:
                nxt_mon = (self.tock_filter(mon, shown) if s.kind == "tock" and self.tock_filter is not None
                           else self._monitor_after(mon, s))
            kind = s.kind if visible else "internal"
            note = s.note or (_hidden_note(s) if status == "hidden" else "")
            event = s.event if visible else None
            shown_as = s if (kind, event, note) == (s.kind, s.event, s.note) else Step(kind, event, s.target, note)
            out.append(Edge(shown_as, (s.target, nxt_mon), s))
        self.succ[key] = out
        self.transitions += len(out)
        return out

    def _canonical(self, steps: list[Step]) -> list[Step]:
        """`steps`, each leading to the one object of its target configuration that the search
        keeps: a configuration reached again is stored once, not once per step into it. Not one
        that holds Unknowns: equal ones may hold different Unknowns, which a lazy run's steps tell
        apart by identity (`Interpreter.concretize`)."""
        out = []
        canon = self.configs
        lazy = self.interp.lazy
        for st in steps:
            if lazy and has_unknowns(st.target):
                out.append(st)
                continue
            target = canon.setdefault(st.target, st.target)
            out.append(st if target is st.target else Step(st.kind, st.event, target, st.note))
        return out

    def _status(self, s: Step) -> str:
        if self.context is None or s.event is None:
            return "visible"
        ch = s.event.channel
        return self.context.status(ch, len(s.event.values))

    def _monitor_after(self, mon: int, s: Step) -> int:
        """The monitor's state after `s`'s event, the same for every value its Unknowns stand for."""
        assert self.monitor is not None and s.event is not None
        channel, values = s.event.channel, s.event.values
        unknown, sharing = unknowns(values)
        key = (mon, s.kind, channel, values, sharing)
        nxt = self._after.get(key)
        if nxt is None:
            if not unknown:
                nxt = self.monitor.after(mon, self._event(s.kind, channel, values))
            elif math.prod(len(u.values) for u in unknown) <= MONITOR_CHOICES:
                ids = [id(u) for u in unknown]
                nexts = {self.monitor.after(mon, self._event(s.kind, channel,
                                                             cast("tuple", fill(values, dict(zip(ids, combo))))))
                         for combo in itertools.product(*(u.values for u in unknown))}
                if len(nexts) > 1:
                    raise _Strict(channel)
                nxt = nexts.pop()
            else:  # too many to try: the monitor tells apart only the values its terms name (DESIGN.md)
                named = self.monitor.fields(mon, Channel(channel, len(values)))
                if any(named[j] for j, v in enumerate(values) if unknowns(v)[0]):
                    raise _Strict(channel)
                nxt = self.monitor.after(mon, self._event(s.kind, channel, cast("tuple", fill(values, {}))))
            self._after[key] = nxt
        return nxt

    def _event(self, kind: str, channel: tuple, values: tuple) -> tuple:
        if kind == "tock":
            return ("tock",)
        return (*channel, *(self.literals.get(v, v) if isinstance(v, str) else v for v in values))

    # --- breadth-first by visible steps

    def run(self, found: Callable[[Hashable, list[Edge]], str | None]) -> tuple[Hashable, str] | None:
        """The first target node (as few visible steps as possible) and why, or None."""
        while True:
            try:
                return self._run(found)
            except _Strict as exc:
                self.interp.strict.add(exc.channel)
                self.reset()

    def _first_monitor_state(self) -> int | None:
        """The specification monitor's state as the element starts: after the events its context
        puts before it (None without a specification)."""
        if self.monitor is None:
            return None
        first = self.monitor.initial
        for e in self.context.impl.head if self.context is not None else ():
            first = self.monitor.after(first, e)
        return first

    def _run(self, found: Callable[[Hashable, list[Edge]], str | None]) -> tuple[Hashable, str] | None:
        first = self._first_monitor_state()
        todo: deque[Hashable] = deque()
        for start in ((part, first) for c in self.interp.initial_configs() for part in self.parts(c)):
            self.check_time()
            if start not in self.depth:
                if len(self.depth) >= self.max_states:
                    raise MemoryError
                self.depth[start] = 0
                self.parent[start] = None
                todo.append(start)
        while todo:
            self.check_time()
            key = todo.popleft()
            d = self.depth[key]
            if d > self.reached:  # 0-1 search: depths come in order, so every run of fewer visible steps is explored
                if self.progress is not None and d > 0:
                    self.progress(d - 1)
                self.reached = d
            if key[1] == Monitor.DEAD:  # type: ignore[index]
                return key, "dead"
            succ = self.steps(key)
            why = found(key, succ)
            if why is not None:
                return key, why
            for edge in succ:
                cost = 0 if edge.step.kind == "internal" else 1
                if d + cost > self.bound:
                    self.complete = False
                    continue
                target, mon = cast("tuple[Config, int | None]", edge.node)
                parts = self.parts(target)
                self.transitions += len(parts) - 1  # a step into each configuration the target stands for
                for part in parts:
                    nxt = (part, mon)
                    if nxt in self.depth and self.depth[nxt] <= d + cost:
                        continue
                    if len(self.depth) >= self.max_states:
                        raise MemoryError
                    self.depth[nxt] = d + cost
                    self.parent[nxt] = (key, edge)
                    if cost == 0:
                        todo.appendleft(nxt)
                    else:
                        todo.append(nxt)
        return None

    def trace(self, key: Hashable) -> tuple[TraceStep, ...]:
        """The run to `key`, in concrete values (the lazy interpreter's Unknowns chosen)."""
        path: list[tuple[Config, Step, Config]] = []
        node = key
        cur = self.parent.get(key)
        while cur is not None:
            prev, edge = cur
            path.append((prev[0], edge.raw, node[0]))  # type: ignore[index]
            node = prev
            cur = self.parent.get(prev)
        path.reverse()
        raws = self.interp.concretize(path) if self.interp.lazy else [(raw, ()) for _, raw, _ in path]
        out = []
        for i, (s, free) in enumerate(raws):
            states = self.interp.states(s.target)
            if s.kind == "internal" or self._status(s) == "hidden":
                out.append(TraceStep(i + 1, None, "internal", s.note or _hidden_note(s), states, {}))
            else:
                assert s.event is not None
                out.append(TraceStep(i + 1, s.event.name, s.kind, "", states, {}, s.event.channel, s.event.values,
                                     free=free))
        self.witness = (key, tuple(out))
        return self.witness[1]

    def points_rested_on(self, trace: tuple[TraceStep, ...]) -> tuple[str, ...]:
        """The open functions whose chosen values a verdict with `trace` may rest on: those chosen
        along the run, when `trace` is the last run `trace()` gave; else any the search chose."""
        if trace and self.witness is not None and self.witness[1] is trace:
            if self.every_choice is not None and self.every_choice == self.witness[0]:
                return ()
            return self.interp.points_in(cast("tuple[Config, int | None]", self.witness[0])[0])
        return tuple(self.interp.points_chosen)

    def for_every_choice(self, witness: Hashable, target: Callable[[Hashable, list[Edge]], bool]) -> bool:
        """Whether, whatever the open functions compute, some run reaches a node where `target`
        holds; if so, `witness` (such a node, found for the values the search chose) stands for
        every choice, and `points_rested_on` says so. The game looks `bound` visible steps ahead of
        each node first tried (a node once won stays won, however it is reached again: the claim
        is that the target is reached, not within how many steps).

        A game over the lazily chosen values: where a step reads an open function at a point not
        chosen yet, every value its contract allows must lead on to a target (the function is any
        function meeting it); where it reads an input, one value may (the environment chooses); at
        a configuration, one of its steps may. A run so chosen depends only on the values read
        before it, so it is a run of each function that agrees with them. Internal cycles and a
        budget of `WITNESS_NODES` give `False`: the claim stays for the values chosen only."""
        if not self.interp.points_in(cast("tuple[Config, int | None]", witness)[0]):
            return True
        vain: dict[tuple[Config, int | None], int] = {}  # the most visible steps left it was tried with, in vain
        won: set[tuple[Config, int | None]] = set()
        left_nodes = [WITNESS_NODES]

        def wins(config: Config, mon: int | None, left: int) -> bool:
            node = (config, mon)
            if node in won:
                return True
            if vain.get(node, -1) >= left:
                return False
            vain[node] = left  # in vain until shown otherwise: a cycle back here does not win
            left_nodes[0] -= 1
            if left_nodes[0] < 0:
                raise _OutOfBudget
            self.check_time()
            unfolded = self.interp.unfold(config)
            if isinstance(unfolded, Split):  # no value the contract allows: no function gets here, no win
                ways = (wins(part, mon, left) for part in unfolded.parts)
                shown = bool(unfolded.parts) and all(ways) if unfolded.point else any(ways)
            else:
                self.raw.setdefault(config, (config, unfolded))
                succ = self.steps(node)
                shown = mon == Monitor.DEAD or target(node, succ) or any(
                    wins(*cast("tuple[Config, int | None]", e.node), left - (e.step.kind != "internal"))
                    for e in succ if e.step.kind == "internal" or left > 0)
            if shown:
                won.add(node)
            return shown

        first = self._first_monitor_state()
        try:
            shown = any(wins(c, first, self.bound) for c in self.interp.initial_configs())
        except (_OutOfBudget, RecursionError, TimeoutError, NotInterpretable, Unbounded):
            return False  # a part of the game the search did not reach may be out of reach of the interpreter
        if shown:
            self.every_choice = witness
        return shown

    def time_only(self, alive: Callable[[Hashable], bool]) -> Hashable | None:
        """The nearest explored configuration from which only tock is ever possible (every
        configuration it reaches offers tock alone), if any: a greatest fixpoint (of an eager
        search: a lazy one's nodes stand for configurations whose futures may differ)."""
        doomed = {k for k, succ in self.succ.items()
                  if alive(k) and succ and all(e.step.kind == "tock" for e in succ)}
        changed = True
        while changed:
            changed = False
            for k in list(doomed):
                if any(e.node not in doomed for e in self.succ[k]):
                    doomed.discard(k)
                    changed = True
        return min(doomed, key=lambda k: self.depth[k]) if doomed else None

    def cycle(self, edge: Callable[[Step], bool], where: Callable[[Hashable], bool]) -> Hashable | None:
        """A node (explored, where `where` holds) on a cycle of steps for which `edge` holds."""
        graph = {k: [e.node for e in succ if edge(e.step) and e.node in self.succ] for k, succ in self.succ.items()
                 if where(k)}
        return on_cycle(graph)

    def nearest_divergence(self) -> Hashable | None:
        """The explored node nearest the start on a cycle of internal steps (a divergence)."""
        return self.nearest_cycle(lambda s: s.kind == "internal")

    def nearest_cycle(self, edge: Callable[[Step], bool]) -> Hashable | None:
        """The explored node nearest the start (fewest visible steps) that lies on a cycle of steps
        for which `edge` holds: the nodes of strongly connected components with a cycle (Tarjan's
        algorithm, iteratively)."""
        graph = {k: [e.node for e in succ if edge(e.step) and e.node in self.succ] for k, succ in self.succ.items()}
        index: dict[Hashable, int] = {}
        low: dict[Hashable, int] = {}
        on_stack: set[Hashable] = set()
        stack: list[Hashable] = []
        cyclic: list[Hashable] = []
        for root in graph:
            if root in index:
                continue
            work = [(root, iter(graph[root]))]
            index[root] = low[root] = len(index)
            stack.append(root)
            on_stack.add(root)
            while work:
                node, children = work[-1]
                child = next(children, None)
                if child is not None:
                    if child not in index:
                        index[child] = low[child] = len(index)
                        stack.append(child)
                        on_stack.add(child)
                        work.append((child, iter(graph[child])))
                    elif child in on_stack:
                        low[node] = min(low[node], index[child])
                    continue
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        x = stack.pop()
                        on_stack.discard(x)
                        component.append(x)
                        if x == node:
                            break
                    if len(component) > 1 or node in graph[node]:
                        cyclic += component
        return min(cyclic, key=lambda k: self.depth[k], default=None)


def _hidden_note(s: Step) -> str:
    return f"{s.event.name} (hidden)" if s.event is not None else ""


def _literals(q: Query) -> dict[str, EnumValue]:
    if q.context is None:
        return {}
    return {v.text: v for v in q.context.sem.evaluator.literals.values()}


def check_explicit(project: ast.Project, names: Iterable[str] | None, bound: int, ranges: Ranges,
                   settings: dict[str, ast.Expr], timeout: float | None,
                   max_states: int = DEFAULT_MAX_STATES, config: Configuration | None = None) -> list[Result]:
    """One `Result` per selected assertion, by explicit search; raises `Unbounded` for a missing range.
    Ranges and constants come from `config`, else from `ranges` and `settings` as `check` reads them."""
    return list(iter_check_explicit(project, names, bound, ranges, settings, timeout, max_states, config))


def iter_check_explicit(project: ast.Project, names: Iterable[str] | None, bound: int, ranges: Ranges,
                        settings: dict[str, ast.Expr], timeout: float | None,
                        max_states: int = DEFAULT_MAX_STATES, config: Configuration | None = None) -> Iterator[Result]:
    """`check_explicit`'s results one at a time, each as soon as it is decided."""
    config = config or configure(project, ranges, settings)
    wanted = set(names) if names is not None else None
    for a in config.project.assertions:
        if wanted is None or any(a.selected_by(n) for n in wanted):
            yield check_assertion(config.project, a, bound, config, timeout, max_states)


def check_assertion(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration,
                    timeout: float | None, max_states: int = DEFAULT_MAX_STATES,
                    progress: Callable[[int], None] | None = None) -> Result:
    """The verdict of one assertion by explicit search; `progress` is told each number of visible
    steps up to which every run has been explored."""
    return within_no_steps(decide_in_both(
        a, config.reading, timeout, lambda half, left: _check_one(project, half, bound, config, left, max_states,
                                                                  progress)))


def _check_one(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration, timeout: float | None,
               max_states: int, progress: Callable[[int], None] | None) -> Result:
    """`check_assertion` in the one semantics `a` is read in."""
    seen: list[tuple[Query, Setup]] = []
    decided = _check_assertion(project, a, bound, config, timeout, max_states, progress, seen)
    if not seen:
        return decided
    functions: tuple[str, ...] = decided.extra.get(OPEN_POINTS, ())
    if OPEN_POINTS in decided.extra:
        decided = replace(decided, extra={k: v for k, v in decided.extra.items() if k != OPEN_POINTS})
    q, setup = seen[0]
    parameters = setup.parameters + (config.setup(a, q.spec_element.element, q.spec_element.settings).parameters
                                     if q.spec_element is not None else ())
    if (parameters or functions) and one_value_only(q, decided.verdict):
        # a run or trace the verdict rests on may have chosen what an open function computes
        return replace(decided, verdict=Verdict.UNKNOWN, proof=Proof.NONE,
                       reason=per_value_reason(parameters, decided.reason, functions))
    return decided


def _check_assertion(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration,
                     timeout: float | None, max_states: int, progress: Callable[[int], None] | None,
                     seen: list[tuple[Query, Setup]]) -> Result:
    """`check_assertion` before the parameters are considered; `seen` is given the query and setup."""
    start = time.perf_counter()
    deadline = time.monotonic() + timeout if timeout is not None else None
    search: Search | None = None
    described: dict[str, str] = config.ranges().describe()
    constants: dict[str, str] = {}
    sources: dict[str, dict[str, str]] = {"ranges": config.range_sources()}
    defaults: dict[str, str] = {}
    notes: tuple[str, ...] = ()

    def result(verdict: Verdict, reason: str, trace: tuple = (), more: dict | None = None) -> Result:
        extra: dict[str, object] = ({"states": len(search.depth), "transitions": search.transitions}
                                    if search is not None else {})
        if search is not None and search.interp.points_chosen:  # read by `_check_one`, then dropped
            extra[OPEN_POINTS] = search.points_rested_on(trace)
        extra.update(more or {})
        if trace:
            proof = Proof.TRACE
        elif verdict in (Verdict.HOLDS, Verdict.VIOLATED):  # shown by the search having run out
            proof = Proof.EXHAUSTIVE if search is not None and search.complete else Proof.BOUNDED
        else:
            proof = Proof.NONE
        return Result(assertion=a.label, text=a.text, verdict=verdict,
                      bound=bound if verdict != Verdict.UNSUPPORTED else None, ranges=described,
                      seconds=time.perf_counter() - start, reason=reason, trace=trace, proof=proof,
                      engine="explicit", pos=str(a.pos), extra=extra, constants=constants, sources=sources,
                      reading=config.reading, defaults=defaults, notes=notes)

    try:
        q = query(project, a)
        if q.spec_element is not None:
            q = with_element_spec(q, a, config)
        setup = config.setup(a, q.element, q.settings)
        seen.append((q, setup))
        described, constants, sources = setup.described_ranges, setup.described_constants, setup.sources
        defaults, notes = setup.defaults, probabilistic.notes(*q.reached)
        consts = python_settings(setup.constants)

        def interpreter(lazy: bool) -> Interpreter:
            return Interpreter(q.element, setup.ranges, consts, dict(q.defined), lazy=lazy,
                               timed=q.timed, dead_variables=True)

        def starts() -> bool:
            """Whether a run of the element, and of the model element on the specification's side
            if any, starts: a verdict on no run is vacuous (as BMC's `_starts`, asked after the
            verdict, so that an assertion tockbmc cannot check is `unsupported` either way)."""
            if next(iter(interpreter(True).initial_configs()), None) is None:
                return False
            if q.spec_element is None:
                return True
            spec = q.spec_element
            spec_setup = config.setup(a, spec.element, spec.settings)
            spec_interp = Interpreter(spec.element, spec_setup.ranges, python_settings(spec_setup.constants),
                                      dict(spec.defined), lazy=True, timed=q.timed)
            return next(iter(spec_interp.initial_configs()), None) is not None

        def decide() -> Result:
            nonlocal search
            # Lazy where the verdict reads one node at a time (DESIGN.md, "Lazy inputs"); a deadlock's
            # greatest fixpoint and the traces the specification lists are searched over every value.
            if q.inclusion is None or q.goals:  # equals: this direction first
                lazy = a.kind in LAZY_KINDS and a.semantic_model not in REFUSAL_MODELS  # refusals read every value
                search = Search(interpreter(lazy), q, bound, max_states, deadline, progress)
                decided = _decide(a, q, search, result)
                # On to the other direction when this one shows no difference: `equals`, once this one
                # holds; `is not equal to`, once it is not shown to hold (it holds if either differs).
                if q.inclusion is None or decided.verdict != Verdict.HOLDS and not a.negated or \
                        a.negated and decided.verdict == Verdict.HOLDS:
                    return decided
                search = Search(interpreter(False), q, bound, max_states, deadline, progress)
                other = _included(a, q, search, result)
                return other if other.verdict == Verdict.HOLDS or decided.verdict != Verdict.UNKNOWN else decided
            search = Search(interpreter(False), q, bound, max_states, deadline, progress)
            return _included(a, q, search, result)

        decided = decide()
        if decided.verdict in (Verdict.HOLDS, Verdict.VIOLATED) and not starts():
            return result(Verdict.UNKNOWN, NO_START)
        return decided
    except Unsupported as exc:
        return result(Verdict.UNSUPPORTED, exc.reason)
    except NotInterpretable as exc:
        return result(Verdict.UNSUPPORTED, f"{exc.what} ({exc.pos})")
    except RecursionError:
        return result(Verdict.UNSUPPORTED, TOO_DEEP_TO_CHECK)
    except TimeoutError:
        return result(Verdict.UNKNOWN, "timed out")
    except MemoryError:
        return result(Verdict.UNKNOWN, f"stopped at the state limit ({max_states} configurations); the search is not "
                                 "complete")


VALUES_LISTED = 64  # values of one channel listed where a specification accepts any (`c?x`)


def channel_values(interp: Interpreter, element: ast.StateMachine | ast.Controller | ast.Module,
                   literals: dict[str, EnumValue]) -> Callable[[tuple], list[tuple] | None]:
    """`Semantics.values` for an element: every value tuple of a channel within the interpreter's
    ranges (a record as a `Record`), None where a type has no range or gives more than
    `VALUES_LISTED`."""
    types = element_types(element)

    def values(prefix: tuple) -> list[tuple] | None:
        ts = types.get(tuple(prefix))
        if ts is None:
            return None
        try:
            domains = [interp.domain(t, (prefix[0],)) for t in ts]
        except Unbounded:
            return None
        if math.prod(len(d) for d in domains) > VALUES_LISTED:
            return None
        return [tuple(literals.get(v, v) if isinstance(v, str) else v for v in combo)
                for combo in itertools.product(*domains)]

    return values


def with_element_spec(q: Query, a: ast.Assertion, config: Configuration) -> Query:
    """Refinement between two model elements: the query with the state graph of the element on the
    specification's side (`explicit.lts`) as its specification, listed within that element's
    ranges and constants as the assertion sets them."""
    assert q.spec_element is not None and q.context is not None
    spec = q.spec_element
    setup = config.setup(a, spec.element, spec.settings)
    try:
        interp = Interpreter(spec.element, setup.ranges, python_settings(setup.constants),
                             dict(spec.defined), timed=q.timed)
        literals = {v.text: v for v in q.context.sem.evaluator.literals.values()}
        owner = None if spec.impl.renames else (spec.element.name, q.element.name)  # renamed as RoboTool does
        graph = element_lts(interp, spec.impl.renames, literals, q.spec_name, owner=owner)
    except Unbounded as exc:
        raise Unsupported(None, f"{q.spec_name} stands for a specification, so its state graph is listed, which needs "
                                f"a finite range for every value from outside: {exc}") from None
    except NotInterpretable as exc:
        raise Unsupported(None, f"{q.spec_name} stands for a specification, and the interpreter cannot list its "
                                f"states: {exc.what} ({exc.pos})") from None
    return given_spec(q, graph)


def _included(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result]) -> Result:
    """Every listed trace of the specification is one the element can perform (`properties.inclusion`)."""
    assert q.inclusion is not None and q.context is not None
    sem = q.context.sem
    sem.alphabet = element_alphabet(q.element)
    sem.values = channel_values(search.interp, q.element, {v.text: v for v in sem.evaluator.literals.values()})
    channels = [Channel(prefix, arity) for prefix, arity in sem.alphabet] + [Channel(("tock",), 0)]
    wanted = max(1, min(INCLUSION_LENGTH, search.bound // 2))
    if a.semantic_model == TICK_TOCK:
        return _observed(a, q, search, result, wanted)
    if a.semantic_model == "failures divergences":
        # A divergence on a prefix of a listed trace allows every later trace and refusal, which the
        # listing does not see (it alone would give a false `violated`); the pairs below do.
        return _subsets(a, q, search, result, channels)
    traces, length = spec_traces(sem, q.inclusion, channels, wanted, 256)
    if length < wanted:  # too many to list: follow the element's configurations after each trace at once
        return _subsets(a, q, search, result, channels)
    for t in traces:
        if not _performs(search, t):
            names = [_event_text(e) for e in t.events] + (["✓"] if t.ticks else [])  # as BMC's inclusion shows it
            shown = tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", f"a trace of {q.spec_name}", {}, {})
                          for j, e in enumerate(names))
            verdict = Verdict.HOLDS if a.negated else Verdict.VIOLATED
            return result(verdict, f"{q.spec_name} has this trace{' and then terminates' if t.ticks else ''}, "
                                   f"and {q.element.name} cannot perform it", shown)
    refusals = ""
    if a.semantic_model in FAILURES_MODELS:
        decided = _refusals_included(a, q, search, result, [t.events for t in traces])
        if decided is not None:
            return decided
        refusals = ", and each stable refusal of it after them one of the model's"
    complete = _for_every_length(a, q, search, result, channels)
    if complete is not None:
        return complete
    if a.negated:
        return result(Verdict.UNKNOWN, f"every trace of {q.spec_name} with up to {length} events is one of "
                                 f"{q.element.name}'s{refusals}; a bounded search alone gives no verdict")
    return result(Verdict.HOLDS, f"every trace of {q.spec_name} with up to {length} events is a trace of "
                           f"{q.element.name}{refusals} ({len(traces)} traces listed)")


def _for_every_length(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result],
                      channels: list[Channel]) -> Result | None:
    """The listed traces show no difference: the same question for traces of every length
    (`_subsets`), or None where that search does not end within the check's time and state limit
    (the listing's bounded answer stands then)."""
    try:
        return _subsets(a, q, search, result, channels)
    except (TimeoutError, MemoryError, RecursionError, Unsupported, Unbounded, NotInterpretable):
        return None


def _subsets(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result],
             channels: list[Channel]) -> Result:
    """Every trace of the specification is one of the element's, and in the failures models each of
    its stable refusals one the element makes after the same trace, decided for traces of every
    length: the specification's monitor states paired with the set of the element's configurations
    reachable by the same trace (internal steps closed), explored breadth first (the subset
    construction FDR applies to the side it normalises).  Used where the traces are too many to
    list (`_included`); complete when the pairs are finitely many and all explored."""
    assert q.context is not None and q.inclusion is not None
    sem = q.context.sem
    sem.alphabet = element_alphabet(q.element)  # the events to list, and every value of each
    sem.values = channel_values(search.interp, q.element, {v.text: v for v in sem.evaluator.literals.values()})
    failures = a.semantic_model in FAILURES_MODELS
    try:
        checker, mon = _refusal_monitor(a, q, search) if failures else (None, Monitor(sem, q.inclusion, channels))
    except TooLarge:
        raise Unsupported(None, f"{q.spec_name} has too many states") from None

    def closure(keys: Iterable[Hashable]) -> frozenset[Hashable]:
        return _internal_closure(search, keys)

    def diverges(group: frozenset[Hashable]) -> bool:  # a cycle of internal steps among them (closed)
        inner = {k: [n for st, n, _ in search.steps(k) if st.kind == "internal"] for k in group}
        return on_cycle(inner) is not None

    def shown(events: tuple[tuple, ...], tick: bool = False) -> tuple[TraceStep, ...]:
        names = [_event_text(e) for e in events] + (["✓"] if tick else [])
        return tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", f"a trace of {q.spec_name}", {}, {})
                     for j, e in enumerate(names))

    differ = Verdict.HOLDS if a.negated else Verdict.VIOLATED
    start = (mon.initial, closure((c, None) for c in search.interp.initial()))
    seen_pairs: set[tuple[int, frozenset[Hashable]]] = {start}
    todo: deque[tuple[tuple[int, frozenset[Hashable]], tuple[tuple, ...]]] = deque([(start, ())])
    held = 0  # configurations held in the explored pairs
    while todo:
        search.check_time()
        (state, group), trace = todo.popleft()
        if a.semantic_model == "failures divergences" and diverges(group):
            continue  # the element diverges after this trace: every extension and refusal is one of its own
        if mon.can_tick(state) and not any(search.interp.terminated(k[0]) for k in group):  # type: ignore[index]
            return result(differ, f"{q.spec_name} has this trace and then terminates, and {q.element.name} cannot "
                                  "perform it (every configuration it reaches by the trace was explored)",
                          shown(trace, True))
        if checker is not None:
            for acc in acceptances(mon, sem, state, checker.channels):
                r = SpecRefusal(trace, state, acc)
                if any(_made(search, checker, r, k[0], search.steps(k)) for k in group):  # type: ignore[index]
                    continue
                what = (f"{'after this trace' if trace else 'at the start'} {q.spec_name} can be stable accepting "
                        f"{acceptance_text(checker.channels, acc)}, and {q.element.name}")
                return result(differ, f"{what} has no stable configuration, short of termination, refusing "
                                      "everything else (every configuration it reaches by the trace was explored)",
                              shown(trace))
        for e, after in next_events(mon, sem, state):
            name, tock = _event_text(e), e == ("tock",)
            moved = closure(nxt for k in group for step, nxt, _ in search.steps(k)
                            if tock and step.kind == "tock" or step.event is not None and step.event.name == name)
            if not moved:
                return result(differ, f"{q.spec_name} has this trace, and {q.element.name} cannot perform it "
                                      "(every configuration it reaches by the trace before it was explored)",
                              shown((*trace, e)))
            pair = (after, moved)
            if pair not in seen_pairs:
                held += len(moved)
                if held > search.max_states:
                    raise MemoryError
                seen_pairs.add(pair)
                todo.append((pair, (*trace, e)))
    refusals = ", and each of its stable refusals after it one of the element's" if checker is not None else ""
    if a.negated:
        return result(Verdict.VIOLATED, f"every trace of {q.spec_name} is one of {q.element.name}'s{refusals}, for "
                                        f"traces of every length ({len(seen_pairs)} pairs of its state and "
                                        f"{q.element.name}'s configurations after the same trace, all explored)")
    return result(Verdict.HOLDS, f"every trace of {q.spec_name} is a trace of {q.element.name}{refusals}, for "
                                 f"traces of every length ({len(seen_pairs)} pairs of its state and the "
                                 f"configurations of {q.element.name} after the same trace, all explored)")


def included_by_subsets(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration,
                        timeout: float | None, max_states: int = DEFAULT_MAX_STATES) -> Result | None:
    """The specification-on-the-left half of `a` (`Q refines M`, the second half of `equals`)
    decided by `_subsets`, for BMC where the specification's traces are too many to list; None
    where the element's data is not finite under the configuration's ranges (the interpreter
    cannot list its configurations), or the search gives no verdict."""
    start = time.perf_counter()
    deadline = time.monotonic() + timeout if timeout is not None else None
    q = query(project, a)
    if q.spec_element is not None:
        q = with_element_spec(q, a, config)
    setup = config.setup(a, q.element, q.settings)
    notes = probabilistic.notes(*q.reached)

    def result(verdict: Verdict, reason: str, trace: tuple = (), more: dict | None = None) -> Result:
        return Result(assertion=a.label, text=a.text, verdict=verdict, bound=bound, ranges=setup.described_ranges,
                      seconds=time.perf_counter() - start, reason=reason, trace=trace,
                      proof=Proof.TRACE if trace else Proof.EXHAUSTIVE, engine="explicit", pos=str(a.pos),
                      extra=more or {}, constants=setup.described_constants, sources=setup.sources,
                      reading=config.reading, defaults=setup.defaults, notes=notes)

    try:
        interp = Interpreter(q.element, setup.ranges, python_settings(setup.constants),
                             dict(q.defined), lazy=False, timed=q.timed)
        search = Search(interp, q, bound, max_states, deadline)
        channels = [Channel(prefix, arity) for prefix, arity in element_alphabet(q.element)] + [Channel(("tock",), 0)]
        decided = _subsets(a, q, search, result, channels)
    except (Unbounded, NotInterpretable, Unsupported, TimeoutError, MemoryError, RecursionError):
        return None
    return decided if decided.verdict in (Verdict.HOLDS, Verdict.VIOLATED) else None


def _internal_closure(search: Search, nodes: Iterable[Hashable]) -> frozenset[Hashable]:
    """The nodes reachable from `nodes` by internal steps; keeps to the search's deadline (internal
    steps that never repeat a configuration go on for ever) and state limit (`MemoryError`)."""
    seen = set(nodes)
    todo = list(seen)
    while todo:
        search.check_time()
        for step, nxt, _ in search.steps(todo.pop()):
            if step.kind == "internal" and nxt not in seen:
                if len(seen) >= search.max_states:
                    raise MemoryError
                seen.add(nxt)
                todo.append(nxt)
    return frozenset(seen)


def _refusal_monitor(a: ast.Assertion, q: Query, search: Search) -> tuple[ConcreteRefusals, Monitor]:
    """The specification on the left's monitor over the refusal checker's channels, and the checker;
    in the failures-divergences model a divergent specification is unsupported."""
    assert q.context is not None and q.inclusion is not None
    sem = q.context.sem
    checker = ConcreteRefusals(search.interp, q, Monitor(sem, q.inclusion, []))
    mon = checker.monitor = Monitor(sem, q.inclusion, checker.channels)
    if a.semantic_model == "failures divergences":
        mon.table()
        if divergent_state(mon, sem) is not None:
            raise Unsupported(None, f"{q.spec_name} can diverge; refinement in the failures-divergences model "
                                    "against a divergent specification is not supported")
    return checker, mon


def _refusals_included(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result],
                       traces: list[tuple[tuple, ...]]) -> Result | None:
    """In the failures models, the specification on the right: after each listed trace, each stable
    refusal of the specification is made by some stable configuration of the element, short of
    termination, offering nothing outside the acceptance (docs/semantics.md §7.12); None if so."""
    assert q.context is not None and q.inclusion is not None
    sem = q.context.sem
    checker, mon = _refusal_monitor(a, q, search)
    wanted = spec_refusals(mon, sem, checker.channels, traces)
    if len(wanted) > 256:
        return result(Verdict.UNKNOWN, f"{q.spec_name} has more than 256 stable refusals after its listed traces, "
                                       "which gives no verdict")
    for r in wanted:
        if _refuses_as(search, checker, r):
            continue
        shown = tuple(TraceStep(j + 1, _event_text(e), "tock" if e == ("tock",) else "event",
                                f"a trace of {q.spec_name}", {}, {}) for j, e in enumerate(r.events))
        what = (f"{'after this trace' if r.events else 'at the start'} {q.spec_name} can be stable accepting "
                f"{acceptance_text(checker.channels, r.acceptance)}, and {q.element.name}")
        if not search.complete:
            return result(Verdict.UNKNOWN, f"{what} was not found refusing everything else in a stable configuration "
                                           f"within {search.bound} visible steps", shown)
        if a.semantic_model == "failures divergences" and search.cycle(lambda s: s.kind == "internal",
                                                                         lambda k: True) is not None:
            return result(Verdict.UNKNOWN, f"{what} has no stable configuration refusing the rest, but it can diverge, "
                                           "which in the failures-divergences model allows every refusal", shown)
        return result(Verdict.HOLDS if a.negated else Verdict.VIOLATED,
                      f"{what} has no stable configuration, short of termination, refusing everything else "
                      "(every reachable configuration was explored)", shown)
    return None


def _observed(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result], length: int) -> Result:
    """The tick-tock model with the specification on the left (docs/semantics.md §7.13): the element
    makes every observation of it with up to `length` events, the refusals before its tocks and
    its stable refusals at the end included (as `bmc.inclusion` checks it)."""
    assert q.context is not None and q.inclusion is not None
    sem = q.context.sem
    checker = ConcreteRefusals(search.interp, q, Monitor(sem, q.inclusion, []))
    mon = Monitor(sem, q.inclusion, checker.channels)
    checker.monitor = mon
    observations, checks, length = observation_checks(mon, sem, checker.channels, length)

    def within(r: SpecRefusal) -> Callable[[Config, list[Edge]], bool]:
        return partial(_made, search, checker, r)

    def terminates(ticks: bool) -> Callable[[Config, list[Edge]], bool]:
        return lambda config, steps: not ticks or search.interp.terminated(config)

    for o, r in checks:
        ticks = o.ticks and o.maximal and r is None
        end = within(r) if r is not None else terminates(ticks)
        if _runs_to(search, o.events, end, {j: within(t) for j, t in o.tocks}):
            continue
        what = (f"{q.spec_name} has this observation{' and then terminates' if ticks else ''}"
                + (f", stable at its end accepting {acceptance_text(checker.channels, r.acceptance)}"
                   if r is not None else "") + f", and {q.element.name}")
        shown = observation_steps(o, checker.channels, q.spec_name, ticks)
        seen: dict[str, object] = {"tock_refusals": tock_refusal_list(o, checker.channels)}
        if not search.complete:
            return result(Verdict.UNKNOWN, f"{what} was not shown to make it within {search.bound} visible steps",
                          shown, seen)
        return result(Verdict.HOLDS if a.negated else Verdict.VIOLATED,
                      f"{what} cannot make it (the refusals before its tocks included; every reachable configuration "
                      "was explored)", shown, seen)
    if a.negated:
        return result(Verdict.UNKNOWN, f"every tick-tock observation of {q.spec_name} with up to {length} events is "
                                       f"one of {q.element.name}'s; a bounded search alone gives no verdict")
    return result(Verdict.HOLDS, f"every tick-tock observation of {q.spec_name} with up to {length} events is one of "
                                 f"{q.element.name}'s ({sum(1 for o in observations if o.maximal)} observations "
                                 f"listed, each with the refusals before its tocks, and {len(checks)} checks in all)")


def _refuses_as(search: Search, checker: ConcreteRefusals, r: SpecRefusal) -> bool:
    """Whether the element can perform r's events and then make r (`_made`)."""
    return _runs_to(search, r.events, partial(_made, search, checker, r))


def _made(search: Search, checker: ConcreteRefusals, r: SpecRefusal, config: Config, steps: list[Edge]) -> bool:
    """Whether a configuration (with its steps) makes refusal `r`: stable, short of termination,
    offering only events of r's acceptance."""
    return (not search.interp.terminated(config) and not any(e.step.kind == "internal" for e in steps)
            and all(checker.within(r, e.step) for e in steps))


def _performs(search: Search, t: SpecTrace) -> bool:
    """Whether the element can perform the visible events of t in order (internal steps between),
    terminating at the end if t does; raises MemoryError past the state limit."""
    return _runs_to(search, t.events, lambda config, steps: not t.ticks or search.interp.terminated(config))


def _runs_to(search: Search, events: tuple[tuple, ...], end: Callable[[Config, list[Edge]], bool],
             guards: dict[int, Callable[[Config, list[Edge]], bool]] | None = None) -> bool:
    """Whether some run performs `events` in order (internal steps between) and ends in a
    configuration for which `end` holds (given its steps); `guards[i]`, where given, must hold of
    the configuration that takes event i (tick-tock: the refusal before a tock); raises
    MemoryError past the state limit."""
    names = [_event_text(e) for e in events]
    start: list[tuple[Hashable, int]] = [((c, None), 0) for c in search.interp.initial()]
    seen = set(start)
    todo = deque(start)
    while todo:
        search.check_time()  # internal steps growing a sequence for ever took minutes a state
        node_key, i = todo.popleft()
        config = cast("tuple[Config, None]", node_key)[0]
        steps = search.steps((config, None))
        if i == len(names) and end(config, steps):
            return True
        for step, nxt, _ in steps:
            node: tuple[Hashable, int]
            if step.kind == "internal":
                node = (nxt, i)
            elif i < len(names) and (step.kind == "tock" and names[i] == "tock" or
                                     step.event is not None and step.event.name == names[i]):
                if guards and i in guards and not guards[i](config, steps):
                    continue
                node = (nxt, i + 1)
            else:
                continue
            if node not in seen:
                if len(seen) >= search.max_states:
                    raise MemoryError
                seen.add(node)
                todo.append(node)
    return False


def _decide(a: ast.Assertion, q: Query, search: Search, result: Callable[..., Result]) -> Result:
    interp = search.interp
    name = q.element.name
    def scope() -> str:  # read after the search: whether it explored everything
        return ("every configuration reachable at any length was explored" if search.complete
                else f"for every run of up to {search.bound} visible steps")

    def done(holds_reason: str) -> Result:
        return result(Verdict.HOLDS, f"{holds_reason}; {scope()}")

    def internal(succ: list[Edge]) -> bool:
        return any(e.step.kind == "internal" for e in succ)

    def tock(succ: list[Edge]) -> bool:
        return any(e.step.kind == "tock" for e in succ)

    def terminated(key: Hashable) -> bool:
        return interp.terminated(key[0])  # type: ignore[index]

    kind, negated = a.kind, a.negated
    tick_tock = a.semantic_model == TICK_TOCK
    if kind in ("refines", "equals"):
        assert q.context is not None and search.monitor is not None
        context, monitor = q.context, search.monitor
        rests: dict[int, list[str] | None] = {}

        def after_end(key: Hashable, succ: list) -> str | None:
            config, state = cast("tuple[Config, int | None]", key)
            if not interp.terminated(config) or state is None:
                return None
            if state not in rests:
                rests[state] = after_termination(context.sem, monitor, context.impl.tail, state)
            return "after" if rests[state] is not None else None

        refusals = ConcreteRefusals(interp, q, monitor) if a.semantic_model in REFUSAL_MODELS else None
        if refusals is not None:
            refuse_context(context.impl, "the tick-tock model" if tick_tock else "the failures models")
        if refusals is not None and tick_tock:
            search.tock_filter = refusals.after_tock
        if refusals is not None and a.semantic_model == "failures divergences":
            assert context.spec is not None
            whole = Monitor(context.sem, context.spec, refusals.channels)  # every reachable state, to look for divergence
            whole.table()
            if divergent_state(whole, context.sem) is not None:
                raise Unsupported(None, f"{q.spec_name} can diverge; refinement in the failures-divergences model "
                                        "against a divergent specification is not supported")
        refused: dict[Hashable, list[str]] = {}

        def found(key: Hashable, succ: list) -> str | None:
            why = after_end(key, succ)
            if why is not None or refusals is None:
                return why
            config, state = cast("tuple[Config, int | None]", key)
            if state is None or state == Monitor.DEAD or internal(succ) or interp.terminated(config):
                return None
            shown = refusals.failure(state, [e.step for e in succ])
            if shown is None:
                return None
            refused[key] = shown
            return "refusal"

        hit = search.run(found)
        spec = q.spec_name
        if hit is not None and negated and refusals is not None and a.semantic_model == "failures divergences":
            found_at = search.depth[hit[0]]
            search.reset()  # explore everything: a divergence nearer the start is the shorter witness
            search.run(lambda key, succ: None)
            loop = search.nearest_divergence()
            if loop is not None and search.depth[loop] < found_at:
                return result(Verdict.HOLDS, f"{name} can repeat internal steps for ever (divergence), which "
                                             f"{spec} cannot", search.trace(loop))
        if hit is not None:
            verdict = Verdict.HOLDS if negated else Verdict.VIOLATED
            trace = search.trace(hit[0])
            seen = _tock_refusals(search, hit[0], refusals) if tick_tock and refusals is not None else None
            more: dict[str, object] = {"tock_refusals": seen} if seen is not None else {}
            tocks = (" (each tock keeping only the states of the specification that make the refusal before it)"
                     if seen else "")
            head = tuple(TraceStep(0, ".".join(str(x) for x in e), "event", "before the model starts", {}, {})
                         for e in context.impl.head)
            if hit[1] == "after":
                rest = rests[hit[0][1]] or []  # type: ignore[index]
                trace += tuple(TraceStep(len(trace) + 1 + j, e, "tock" if e == "tock" else "event",
                                         "after the model terminates", {}, {}) for j, e in enumerate(rest))
                return result(verdict, f"after {name} terminates, the process goes on with {' '.join(rest)}, which "
                                       f"{spec} cannot do", head + trace)
            if hit[1] == "refusal":
                offers = sorted({_label(e.step) for e in search.steps(hit[0]) if e.step.kind != "internal"})
                return result(verdict, f"{name} is stable and offers only {', '.join(offers) or 'nothing'}; every "
                                       f"stable state of {spec} after this trace accepts an event the model refuses "
                                       f"({'; '.join(sorted(set(refused[hit[0]])))}){tocks}", head + trace,
                              {"refusal": sorted(set(refused[hit[0]])), **more})
            if seen and "refused" in seen[-1] and seen[-1]["step"] == len(trace):
                offered = ", ".join(cast("list[str]", seen[-1]["offered"])) or "nothing"
                why = (f"{name} is stable, offers only {offered} and lets time pass (tick-tock records the refusal of "
                       f"everything else before the tock); every stable state of {spec} that can let time pass there "
                       f"accepts an event the model refuses ({'; '.join(cast('list[str]', seen[-1]['refused']))})"
                       if seen[-1]["refused"] else
                       f"{name} is stable, offers only {offered} and lets time pass; {spec} cannot let time pass "
                       "after the events before it")
                return result(verdict, why, head + trace, more)
            last = trace[-1].event if trace else ""
            return result(verdict, f"{spec} cannot do the last event of this trace{tocks}"
                                   f"{unprefixed_tock(a) if last == 'tock' else ''}", head + trace, more)
        if refusals is not None and a.semantic_model == "failures divergences":
            loop = search.nearest_divergence()
            if loop is not None:
                return result(Verdict.HOLDS if negated else Verdict.VIOLATED,
                              f"{name} can repeat internal steps for ever (divergence), which {spec} cannot",
                              search.trace(loop))
        claim = (f"every tick-tock observation is one of {spec}'s: its trace, the refusal before each tock and the "
                 "stable refusal at its end" if tick_tock else f"every trace is a trace of {spec}")
        if negated:
            return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, f"{claim}; {scope()}")
        return done(claim)
    if q.context is not None and (q.context.impl.head or q.context.impl.continues):
        raise Unsupported(None, "a process with a prefix or a continuation after termination is checked for "
                           "refinement only")
    if kind == "terminates" and not negated:
        hit = search.run(lambda key, succ: "stuck" if not succ and not terminated(key) else None)
        if hit is not None:
            return result(Verdict.VIOLATED, f"{name} has not terminated and refuses every event, tock included",
                          search.trace(hit[0]))
        ends = [k for k in search.depth if terminated(k)]
        if ends:
            best = min(ends, key=lambda k: search.depth[k])
            search.for_every_choice(best, lambda key, succ: terminated(key))
            if not search.complete:  # the witness is whole, the claim about every configuration is not
                return replace(result(Verdict.HOLDS, f"no configuration short of termination within {search.bound} "
                                      f"visible steps refuses every event; witness: {name} has terminated",
                                      search.trace(best)), proof=Proof.BOUNDED)
            return result(Verdict.HOLDS, f"no configuration short of termination refuses every event; witness: {name} "
                                   "has terminated", search.trace(best))
        if search.complete:
            return result(Verdict.VIOLATED, f"termination is unreachable ({scope()})")
        return result(Verdict.UNKNOWN, f"termination not found within {search.bound} visible steps")
    if kind == "terminates":  # does not terminate
        hit = search.run(lambda key, succ: "terminated" if terminated(key) else None)
        if hit is not None:
            return result(Verdict.VIOLATED, f"{name} has terminated", search.trace(hit[0]))
        return done(f"{name} never terminates")
    if kind == "timelock-free":
        hit = search.run(lambda key, succ: "timelock" if not internal(succ) and not tock(succ) else None)
        if hit is not None:
            why = f"{name} has terminated, so tock is refused" if terminated(hit[0]) else f"{name} refuses tock here"
            trace = search.trace(hit[0])
            if negated:
                search.for_every_choice(hit[0], lambda key, succ: not internal(succ) and not tock(succ))
            return result(Verdict.HOLDS if negated else Verdict.VIOLATED, why, trace)
        if negated:
            return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, f"no configuration refuses tock; {scope()}")
        return done("no configuration refuses tock")
    if kind == "deadlock-free" and not q.timed:  # FDR's :[deadlock free]: a refusal of everything, or divergence
        hit = search.run(lambda key, succ: "deadlock" if not succ else None)
        if hit is not None:
            why = (f"{name} has terminated, and so refuses every event: untimed, FDR's :[deadlock free] counts "
                   "termination as a deadlock" if terminated(hit[0]) else
                   f"{name} has not terminated and refuses every event")
            trace = search.trace(hit[0])
            if negated:
                search.for_every_choice(hit[0], lambda key, succ: not succ)
            return result(Verdict.HOLDS if negated else Verdict.VIOLATED, why, trace)
        loop = search.nearest_divergence()
        if loop is not None:
            return result(Verdict.HOLDS if negated else Verdict.VIOLATED,
                          f"{name} can repeat internal steps for ever (divergence)", search.trace(loop))
        if negated:
            return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, f"no deadlock; {scope()}")
        return done("no deadlock")
    if kind == "deadlock-free":  # time only for ever, or divergence; a refusal of everything is a timelock
        search.run(lambda key, succ: None)
        loop = search.time_only(lambda k: not terminated(k))
        why = f"{name} offers nothing but tock, now and at every later time"
        if loop is None:
            loop = search.cycle(lambda s: s.kind == "internal", lambda k: True)
            why = f"{name} can repeat internal steps for ever (divergence)"
        hit = (loop, why) if loop is not None else None
        if hit is not None:
            return result(Verdict.HOLDS if negated else Verdict.VIOLATED, why, search.trace(hit[0]))
        if negated:
            return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, f"no deadlock; {scope()}")
        return done("no deadlock")
    if kind == "deterministic":
        return _deterministic(search, name, negated, result, scope)
    if kind == "divergence-free":
        search.run(lambda key, succ: None)  # explore, then look for a cycle of internal steps
        loop = search.nearest_divergence()
        if loop is not None:
            return result(Verdict.HOLDS if negated else Verdict.VIOLATED,
                          f"{name} can repeat internal steps for ever (divergence)", search.trace(loop))
        if negated:
            return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, f"no divergence; {scope()}")
        return done("no run repeats a configuration by internal steps alone")
    if kind == "reachable":
        state = a.subject

        def entered(key: Hashable, succ: list) -> str | None:
            active = interp.states(key[0]).items()  # type: ignore[index]
            return "entered" if any(is_state(m, s, state) for m, s in active) else None

        hit = search.run(entered)
        if hit is not None:
            trace = search.trace(hit[0])
            if not negated:  # a violation found with one function is a violation
                search.for_every_choice(hit[0], lambda key, succ: entered(key, succ) is not None)
            return result(Verdict.VIOLATED if negated else Verdict.HOLDS, f"state {state} is entered", trace)
        if negated:
            return done(f"state {state} is never entered")
        if search.complete:
            return result(Verdict.VIOLATED, f"state {state} is never entered ({scope()})")
        return result(Verdict.UNKNOWN, f"state {state} not entered within {search.bound} visible steps")
    raise Unsupported(None, f"'{kind}' assertions are not supported by the explicit engine")


def is_state(machine: str, active: str, state: str) -> bool:
    """Whether machine `machine`, innermost in `active`, is in the state an assertion names: the
    state's path or one of its ancestors', maybe qualified by names ending with the machine's."""
    parts = active.split("::")
    for i in range(1, len(parts) + 1):
        path = "::".join(parts[:i])
        if state == path:
            return True
        if state.endswith("::" + path):
            qualifier = state[: -len(path) - 2].rsplit("::", 1)[-1]
            if ast.qualifies(qualifier, machine.rsplit("::", 1)[-1]):
                return True
    return False


def element_alphabet(element: ast.StateMachine | ast.Controller | ast.Module) -> list[tuple[tuple, int]]:
    """Channels the element might show, over-approximated (so specifications can be probed with them):
    every event of the element and of its machines in both directions, its calls and `terminate`."""
    return [(prefix, len(types)) for prefix, types in element_types(element).items()]


def element_types(element: ast.StateMachine | ast.Controller | ast.Module) -> dict[tuple, tuple[ast.Type, ...]]:
    """The channels of `element_alphabet`, each with the types of its values."""
    name = element.name
    machines: list[ast.StateMachine] = []
    defined: list[ast.OperationDef] = []  # a controller's operations: the calls they make are its too
    events: list[tuple[str, ast.Event]] = []
    if isinstance(element, ast.StateMachine):
        machines = [element]
    elif isinstance(element, ast.Controller):
        machines = [m.machine for m in element.machines]
        defined = [oi.operation for oi in element.operations]
        events += [(name, e) for e in element.events]
    else:
        for ci in element.controllers:
            machines += [m.machine for m in ci.controller.machines]
            defined += [oi.operation for oi in ci.controller.operations]
            events += [(ci.controller.name, e) for e in ci.controller.events]
        if element.platform is not None:
            events += [(name, e) for e in element.platform.events]
    out: dict[tuple, tuple[ast.Type, ...]] = {(f"{name}::terminate",): ()}
    for m in (*machines, *defined):
        if isinstance(m, ast.StateMachine):
            events += [(m.name, e) for e in m.events]
        for op in m.operations:
            out.setdefault(("::".join(f"{name}::{op.name}Call".split("::")[-2:]),),
                           tuple(p.type for p in op.parameters))
    for owner, e in events:
        channel = "::".join(f"{owner}::{e.name}".split("::")[-2:])
        for d in ("in", "out"):
            out.setdefault((channel, d), () if e.type is None else (e.type,))
    return out


REFUSAL_CHOICES = 100_000  # values of one refused class tried before the check is given up


class ConcreteRefusals:
    """The failures check on one concrete configuration (docs/semantics.md §7.12): stable, not
    terminated, and every stable term of the specification in the monitor state accepts some event
    (within the types and ranges) that the configuration does not offer."""

    def __init__(self, interp: Interpreter, q: Query, monitor: Monitor):
        assert q.context is not None
        self.interp, self.monitor, self.sem = interp, monitor, q.context.sem
        self.sem.alphabet = element_alphabet(q.element)
        tock = q.timed and q.context.status(("tock",), 0) != "hidden"
        self.channels = [Channel(p, a) for p, a in self.sem.alphabet] + ([Channel(("tock",), 0)] if tock else [])
        self.types = element_types(q.element)
        self.literals = {v.text: v for v in self.sem.evaluator.literals.values()}
        self.accept: dict[int, list[tuple[Offer, ...]]] = {}

    def event(self, s: Step) -> tuple:
        if s.kind == "tock":
            return ("tock",)
        assert s.event is not None
        return (*s.event.channel, *(self.literals.get(v, v) if isinstance(v, str) else v for v in s.event.values))

    def refused(self, offered: set[tuple], state: int, o: Offer) -> bool:
        if o.channel is None:
            return True
        ch = self.channels[o.channel]
        if ch.prefix == ("tock",):
            return ("tock",) not in offered
        named = self.monitor.fields(state, ch)
        fields = []
        for j, t in enumerate(self.types.get(ch.prefix, ())):
            values = [self.literals.get(v, v) if isinstance(v, str) else v
                      for v in self.interp.domain(t, (ch.prefix[0],))]
            x = o.values[j]
            if x is OTHER:
                fields.append([v for v in values if not any(_same(v, y) for y in named[j])])
            else:
                fields.append([v for v in values if _same(v, x)])
        if math.prod(len(f) for f in fields) > REFUSAL_CHOICES:
            raise Unsupported(None, f"too many values on {ch.prefix[0]} to compare refusals")
        return any((*ch.prefix, *combo) not in offered for combo in itertools.product(*fields))

    def within(self, r: SpecRefusal, s: Step) -> bool:
        """Whether a visible step's event is in one of the classes of r's acceptance."""
        e = self.event(s)
        for o in r.acceptance:
            if o.channel is None:
                continue
            ch = self.channels[o.channel]
            if e[: len(ch.prefix)] != ch.prefix or len(e) != len(ch.prefix) + len(o.values):
                continue
            named = self.monitor.fields(r.state, ch)
            if all((not any(_same(v, y) for y in named[j])) if x is OTHER else _same(v, x)
                   for j, (v, x) in enumerate(zip(e[len(ch.prefix):], o.values, strict=True))):
                return True
        return False

    def after_tock(self, state: int, steps: list[Step]) -> int:
        """The tick-tock model: the monitor state after a tock from a stable configuration with these
        visible steps, kept to the specification's stable terms that can let time pass and accept
        nothing the configuration refuses (`properties.ticktock`)."""
        groups = tock_groups(self.monitor, self.sem, state, self.channels)
        offered = {self.event(s) for s in steps}
        kept = frozenset(i for i, g in enumerate(groups)
                         if not any(self.refused(offered, state, o) for o in g.acceptance))
        return kept_after(self.monitor, state, groups, kept)

    def tock_refusal(self, state: int, steps: list[Step]) -> list[str]:
        """Per group of the specification's stable terms that can let time pass, an event it
        accepts that a stable configuration with these visible steps refuses."""
        offered = {self.event(s) for s in steps}
        shown = []
        for g in tock_groups(self.monitor, self.sem, state, self.channels):
            o = next((o for o in g.acceptance if self.refused(offered, state, o)), None)
            if o is not None:
                shown.append(offer_text(self.channels, o))
        return sorted(set(shown))

    def failure(self, state: int, steps: list[Step]) -> list[str] | None:
        """The events refused (one per stable term of the specification), if the refusal of a stable
        configuration with these visible steps is not one the specification can make; else None."""
        if state not in self.accept:
            self.accept[state] = acceptances(self.monitor, self.sem, state, self.channels)
        offered = {self.event(s) for s in steps}
        shown = []
        for acc in self.accept[state]:
            o = next((o for o in acc if self.refused(offered, state, o)), None)
            if o is None:
                return None
            shown.append(offer_text(self.channels, o))
        return shown


def _tock_refusals(search: Search, key: Hashable, refusals: ConcreteRefusals) -> list[dict[str, object]]:
    """The refusal observed before each tock of the run to `key` (tick-tock), numbered as
    `Search.trace` numbers its steps: what the configuration offers (it refuses the rest), and for
    a tock that left the monitor dead, per group of the specification's stable states that can let
    time pass, an event the group accepts and the configuration refuses."""
    path: list[tuple[Hashable, Edge]] = []
    cur = search.parent.get(key)
    while cur is not None:
        path.append(cur)
        cur = search.parent.get(cur[0])
    path.reverse()
    out: list[dict[str, object]] = []
    for i, (prev, edge) in enumerate(path):
        if edge.step.kind != "tock":
            continue
        steps = [e.step for e in search.steps(prev) if e.step.kind != "internal"]
        entry: dict[str, object] = {"step": i + 1, "offered": sorted({_label(s) for s in steps})}
        before, after = cast("tuple[Config, int]", prev)[1], cast("tuple[Config, int]", edge.node)[1]
        if after == Monitor.DEAD and before != Monitor.DEAD:
            entry["refused"] = refusals.tock_refusal(before, steps)
        out.append(entry)
    return out


def _label(step: Step) -> str:
    return "tock" if step.kind == "tock" else step.event.name if step.event is not None else "?"


def _deterministic(search: Search, name: str, negated: bool, result: Callable[..., Result],
                   scope: Callable[[], str]) -> Result:
    """`P is deterministic` by subset construction: for each initial configuration (the values a run
    starts from are the environment's choice, as in BMC's `bmc.determinism`), the sets of
    configurations reachable after each trace; an event that one member offers and a stable member
    refuses is a nondeterminism.  A divergence makes the process nondeterministic too."""
    interp = search.interp
    search.run(lambda key, succ: None)  # explore within the bound (and see whether that was everything)

    def closure(nodes: Iterable[Hashable]) -> frozenset[Hashable]:
        return _internal_closure(search, nodes)

    def shown(trace: tuple[str, ...]) -> tuple[TraceStep, ...]:
        return tuple(TraceStep(j + 1, e, "tock" if e == "tock" else "event", "", {}, {}) for j, e in enumerate(trace))

    for start in [(c, None) for c in interp.initial()]:
        first = closure([start])
        todo: deque[tuple[frozenset[Hashable], tuple[str, ...]]] = deque([(first, ())])
        visited = {first}
        while todo:
            search.check_time()
            nodes, trace = todo.popleft()
            offers = {n: {_label(e.step) for e in search.steps(n) if e.step.kind != "internal"} for n in nodes}
            everything = set().union(*offers.values())
            for n in nodes:
                if any(e.step.kind == "internal" for e in search.steps(n)):
                    continue  # not stable: it refuses nothing yet
                refused = sorted(everything - offers[n])
                if refused:
                    event = refused[0]
                    states = ", ".join(f"{m}: {st}" for m, st in interp.states(n[0]).items())  # type: ignore[index]
                    after = f"the trace ⟨{', '.join(trace)}⟩" if trace else "the empty trace"
                    why = (f"{name} is not deterministic: after {after}, one run can do {event} and another, "
                           f"stable in [{states}], refuses it")
                    r = result(Verdict.HOLDS if negated else Verdict.VIOLATED, why, shown((*trace, event)))
                    return replace(r, other_trace=shown(trace))
            if len(trace) >= search.bound:
                if everything:
                    search.complete = False
                continue
            for event in sorted(everything):
                successors = closure(e.node for n in nodes for e in search.steps(n)
                                     if e.step.kind != "internal" and _label(e.step) == event)
                if successors not in visited:
                    visited.add(successors)
                    todo.append((successors, (*trace, event)))
    loop = search.nearest_divergence()
    if loop is not None:
        return result(Verdict.HOLDS if negated else Verdict.VIOLATED,
                      f"{name} can repeat internal steps for ever (divergence); a process that can diverge is not "
                      "deterministic", search.trace(loop))
    why = f"no event is both possible and refused after the same trace, and no divergence; {scope()}"
    if negated:
        return result(Verdict.VIOLATED if search.complete else Verdict.UNKNOWN, why)
    return result(Verdict.HOLDS, why)
