"""Timed deadlock (`docs/semantics.md` §7.2): what `P is deadlock-free` rules out.

Two ways to be deadlocked in time, searched together so that the shortest comes first:
- *time only*: nothing but `tock` is possible, and nothing ever will be: no
  `wait` or deadline is running, and advancing every clock by any amount
  enables nothing (so only time passes, for ever);
- *divergence*: a lasso of internal steps (the configuration repeats with
  nothing but internal steps in between).
Termination is not a deadlock, and neither is a configuration that refuses every event, `tock`
included: no run of tocks goes on from it (it is a timelock, which `is timelock-free` finds).  This
is RoboTool's check too: `tock` is given lower priority than every other event and hidden, and the
result must be divergence-free, so only "time passes for ever and nothing else" counts.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping
from typing import TypeVar

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import TransitionSystem
from tockbmc.encodings.terms import quantified
from tockbmc.encodings.unroller import Unroller
from tockbmc.model import ast
from tockbmc.properties.goals import Describe, Goal, true_at

N = TypeVar("N", bound=Hashable)


def _nothing_ever(system: TransitionSystem) -> z3.BoolRef:
    """From now on only tock is possible, for every number of tocks to come."""
    return system.once("nothing ever", lambda: _without_quantifier(_nothing_ever_now(system)))


QE_MS = 2000  # milliseconds for eliminating the quantifier of one time-only formula


_ELIMINATED: dict[tuple[int, int], tuple[z3.BoolRef, z3.BoolRef]] = {}  # by context and id: (formula, result)
_ELIMINATED_CAP = 4096


def _without_quantifier(formula: z3.BoolRef) -> z3.BoolRef:
    """An equivalent quantifier-free formula when Z3's elimination finds one (linear guards on
    clocks), which every later check then solves without quantifier instantiation; else `formula`.

    Z3 shares equal terms, so one formula asked again (a specification's refusal, checked after each
    of its traces on a system built anew) has the same id in its context: the answer is kept, with
    the formula (and so its context), so that neither the id nor the context is reused meanwhile."""
    key = (id(formula.ctx), formula.get_id())
    kept = _ELIMINATED.get(key)
    if kept is not None:
        return kept[1]
    if len(_ELIMINATED) >= _ELIMINATED_CAP:
        _ELIMINATED.clear()
    out = _eliminate(formula)
    _ELIMINATED[key] = (formula, out)
    return out


def _eliminate(formula: z3.BoolRef) -> z3.BoolRef:
    goal = z3.Goal()
    goal.add(formula)
    try:
        result = z3.TryFor(z3.Tactic("qe"), QE_MS)(goal)  # past it, the quantified formula
    except z3.Z3Exception:
        return formula
    if len(result) != 1:
        return formula
    out = result[0].as_expr()
    return formula if quantified(out) else out


def _nothing_ever_now(system: TransitionSystem) -> z3.BoolRef:
    now = z3.And(z3.Not(system.internal_enabled()), z3.Not(system.event_offered()))
    f = system.cur
    clocks = [f[names.clock(comp.name, clock)] for comp in system.components for clock in comp.automaton.clocks]
    if not clocks:
        return now
    later = z3.Int("later")
    shifted = z3.substitute(now, *[(c, c + later) for c in clocks])  # type: ignore[operator]
    return z3.ForAll([later], z3.Implies(later >= 0, shifted))


def time_only(system: TransitionSystem) -> z3.BoolRef:
    f = system.cur
    calm = []
    for c, comp in enumerate(system.components):
        a = comp.automaton
        calm.append(z3.Not(z3.And(system.located(c, a.waiting), f[names.wait(comp.name)] > 0)))
        if a.threaded:
            calm.append(z3.Not(z3.And(system.located(c, a.during_waiting), f[names.wait(comp.name, 1)] > 0)))
        calm.append(z3.Not(system.located(c, a.deadlined)))
        calm += [z3.Not(system.armed(c, td)) for td in a.trigger_deadlines]
    return z3.And(z3.Not(system.halted()), system.tock_enabled(), *calm, _nothing_ever(system))


def may_diverge(system: TransitionSystem, limit: int = 200_000) -> bool:
    """Whether some run might repeat internal steps for ever; False means none does.

    Cheap first: a cycle of internal moves returns every machine that took part to
    where it was, so some machine has a cycle of its own among those edges.  If one
    does, the network is explored with data abstracted away (locations and buffer
    fullness only, every guard assumed true): a divergence needs a cycle of internal
    moves among the abstract configurations reachable from the initial one.
    """
    if not _machine_cycle(system):
        return False
    return _abstract_cycle(system, limit)


def _abstract_cycle(system: TransitionSystem, limit: int) -> bool:
    """A cycle of internal moves among reachable (location, buffer-full) configurations, or too many."""
    links = [link for link in system.network.links if link.asynchronous]
    slot = {link.index: i for i, link in enumerate(links)}
    n = len(system.components)

    by_source: dict[tuple[int, int], list] = {}
    free = []  # the environment's side of a buffer: no machine takes part
    for m in system.moves:
        if m.kind == "tock" or m.blocked or m.role == "pass":  # a memory passes each write on once
            continue
        if m.parts:
            c, e = m.parts[0]
            by_source.setdefault((c, e.source), []).append(m)
        else:
            free.append(m)

    def successors(state: tuple[int, ...]) -> list[tuple[bool, tuple[int, ...]]]:
        out = []
        for m in [*free, *(x for c in range(n) for x in by_source.get((c, state[c]), ()))]:
            new = list(state)
            if any(state[c] != e.source for c, e in m.parts):
                continue
            for c, e in m.parts:
                new[c] = e.target
            if m.link is not None and m.link.index in slot:
                full = n + slot[m.link.index]
                if m.role in ("read", "env-read"):
                    if not state[full]:
                        continue
                    new[full] = 0
                elif m.role in ("write", "env-write"):
                    new[full] = 1
            out.append((m.kind == "internal", tuple(new)))
        return out

    start = tuple([0] * n + [0] * len(links))
    seen = {start}
    todo = [start]
    internal: dict[tuple[int, ...], set[tuple[int, ...]]] = {}
    while todo:
        state = todo.pop()
        for is_internal, nxt in successors(state):
            if is_internal:
                internal.setdefault(state, set()).add(nxt)
            if nxt not in seen:
                if len(seen) >= limit:
                    return True  # too many to tell: search for a lasso
                seen.add(nxt)
                todo.append(nxt)
    return _has_cycle(internal)


def _machine_cycle(system: TransitionSystem) -> bool:
    for c in range(len(system.components)):
        graph: dict[int, set[int]] = {}
        for m in system.moves:
            if m.kind == "internal":
                for cc, e in m.parts:
                    if cc == c:
                        graph.setdefault(e.source, set()).add(e.target)
        if _has_cycle(graph):
            return True
    return False


def _has_cycle(graph: Mapping[N, Iterable[N]]) -> bool:
    """Whether the directed graph (node -> successors) has a cycle."""
    return on_cycle(graph) is not None


def on_cycle(graph: Mapping[N, Iterable[N]]) -> N | None:
    """A node on a cycle of the directed graph (node -> successors; a successor that is not a key
    has none), found depth first; None if there is no cycle."""
    done: set[N] = set()
    for root in graph:
        if root in done:
            continue
        path, stack = {root}, [(root, iter(graph.get(root, ())))]
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                stack.pop()
                path.discard(node)
                done.add(node)
            elif child in path:
                return child
            elif child not in done:
                path.add(child)
                stack.append((child, iter(graph.get(child, ()))))
    return None


class LoopWatch:
    """Liveness to safety for divergence: a copy of one configuration, chosen freely, after which
    every step must be internal; a lasso is the configuration coming back to the copy.

    The target then reads only the configuration at k (the copy is part of it), so each depth adds
    one comparison rather than one per earlier step, and k-induction applies.
    """

    order_sensitive = True  # the saved copy is of a configuration between steps

    def __init__(self, system: TransitionSystem):
        self.watched = [n for n in system.sorts if not names.is_loop_slot(n) and n != names.PREVIOUS]
        self.sorts = {n: system.sorts[n] for n in self.watched}
        self.internal = [m.index for m in system.moves if m.kind == "internal"]

    def slots(self) -> dict[str, z3.SortRef]:
        return {names.LOOP_SAVED: z3.BoolSort(), **{names.loop_copy(n): s for n, s in self.sorts.items()}}

    def init(self, system: TransitionSystem) -> z3.BoolRef:
        return z3.Not(system.cur[names.LOOP_SAVED])

    def step(self, system: TransitionSystem) -> z3.BoolRef:
        f, g = system.cur, system.nxt
        save = system.input(names.LOOP_SAVE, ast.BOOLEAN)
        assert isinstance(save, z3.BoolRef)
        saved = z3.Or(f[names.LOOP_SAVED], save)
        copy = [g[names.loop_copy(n)] == z3.If(f[names.LOOP_SAVED], f[names.loop_copy(n)], f[n]) for n in self.watched]
        internal = z3.Or([system.act == x for x in self.internal] or [z3.BoolVal(False)])
        return z3.And(g[names.LOOP_SAVED] == saved, z3.Implies(saved, internal), *copy)

    def back(self, system: TransitionSystem) -> z3.BoolRef:
        f = system.cur
        return z3.And(f[names.LOOP_SAVED], *[f[n] == f[names.loop_copy(n)] for n in self.watched])


def unbounded_loops(system: TransitionSystem) -> str | None:
    """Why no lasso at any depth would not rule out divergence: with a number variable, an endless
    run of internal steps need not repeat a configuration (`x = x + 1` for ever), so a proof that no
    lasso is reachable proves nothing about divergence.  None when every variable has finitely
    many values (booleans, enumerations), where an endless run must repeat one."""
    if not any(isinstance(e, LoopWatch) for e in system.extensions):
        return None  # no lasso is searched for: the data-free graph has no cycle of internal steps
    numeric = sorted(base for base, (t, *_rest) in system.initial.items()
                     if not (t == ast.BOOLEAN or (isinstance(t, ast.EnumType) and not t.params)))
    if not numeric:
        return None
    return (f"no proof for every length is attempted: {', '.join(numeric[:3])}{' …' if len(numeric) > 3 else ''} "
            "can take ever new values, so an endless run of internal steps need not repeat a configuration")


def watch_loops(system: TransitionSystem) -> None:
    if may_diverge(system) and not watching_loops(system):
        system.add(LoopWatch(system))


def watching_loops(system: TransitionSystem) -> bool:
    """Whether the system records a configuration to find a lasso of internal steps."""
    return any(isinstance(e, LoopWatch) for e in system.extensions)


def diverges(system: TransitionSystem) -> z3.BoolRef:
    """A configuration seen earlier comes back with only internal steps in between (a lasso)."""
    watch = next((e for e in system.extensions if isinstance(e, LoopWatch)), None)
    return watch.back(system) if watch is not None else z3.BoolVal(False)


def deadlocked(system: TransitionSystem) -> z3.BoolRef:
    return z3.Or(time_only(system), diverges(system))


def _loop_start(unroller: Unroller, model: z3.ModelRef, k: int) -> int:
    """The step after which a lasso found at step k starts: the copy is saved one step later."""
    saved = unroller.system.cur[names.LOOP_SAVED]
    return next((j - 1 for j in range(1, k + 1) if true_at(unroller, model, saved, j)), 0)


def _describe_divergence(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
    start = _loop_start(unroller, model, k)
    where = "the start" if start == 0 else f"step {start}"
    return (f"{unroller.system.name} can repeat internal steps for ever (divergence): steps {start + 1}–{k} are "
            f"internal and come back to the configuration after {where}, so they can be taken again and again")


def _describe(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
    system = unroller.system
    if true_at(unroller, model, diverges(system), k):
        return _describe_divergence(unroller, model, k)
    return f"{system.name} offers nothing but tock, now and at every later time"


def stopped(system: TransitionSystem) -> z3.BoolRef:
    """Time only: reads only the configuration, so k-induction applies."""
    return time_only(system)


def deadlock_goals(name: str, negated: bool) -> tuple[Goal, ...]:
    """`is not deadlock-free` searches the three together for a shortest witness. `is deadlock-free`
    first rules out refusal and time-only configurations (with k-induction, so possibly for every
    length), then divergence (bounded: a lasso reads earlier configurations), which is searched only
    when some machine has a cycle of internal steps."""
    if negated:
        return (Goal.witness(deadlocked, _describe, prepare=watch_loops, unprovable=unbounded_loops,
                             sought="a deadlock (time only, or divergence)"),)
    return (Goal.violation(stopped, _describe,
                           claim="no configuration offers only tock for ever"),
            _no_divergence(_describe))


def _no_divergence(describe: Describe) -> Goal:
    """The goal every deadlock- and divergence-freedom check ends with: no lasso of internal steps,
    searched only when the data-free graph has a cycle of them."""
    return Goal.violation(diverges, describe, prepare=watch_loops,
                          claim="no run repeats a configuration by internal steps alone", applies=may_diverge,
                          skipped=NO_INTERNAL_CYCLE, unprovable=unbounded_loops)


NO_INTERNAL_CYCLE = ("no run can repeat internal steps for ever (even with data ignored, internal steps form no "
                     "cycle)")


def divergence_goals(name: str, negated: bool) -> tuple[Goal, ...]:
    """`P is divergence-free` (docs/semantics.md §7.9): no reachable endless run of internal steps,
    found as a lasso.  When the model with its data ignored has no cycle of internal steps
    (`may_diverge`), no run of any length diverges and nothing is searched."""
    if negated:
        return (Goal.witness(diverges, _describe_divergence, prepare=watch_loops, applies=may_diverge,
                             skipped=NO_INTERNAL_CYCLE, sought="a divergence", unprovable=unbounded_loops),)
    return (_no_divergence(_describe_divergence),)


def refuses_everything(system: TransitionSystem) -> z3.BoolRef:
    """Stable and offering no event: a deadlock in FDR's sense, termination included (a terminated
    element refuses every event)."""
    return z3.And(z3.Not(system.internal_enabled()), z3.Not(system.event_offered()))


def untimed_deadlocked(system: TransitionSystem) -> z3.BoolRef:
    return z3.Or(refuses_everything(system), diverges(system))


def _describe_untimed(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
    system = unroller.system
    if true_at(unroller, model, diverges(system), k):
        return _describe_divergence(unroller, model, k)
    if true_at(unroller, model, system.halted(), k):
        return (f"{system.name} has terminated, and so refuses every event: untimed, FDR's :[deadlock free] counts "
                "termination as a deadlock")
    return f"{system.name} has not terminated and refuses every event"


def untimed_deadlock_goals(name: str, negated: bool) -> tuple[Goal, ...]:
    """Untimed `P is deadlock-free` (docs/semantics.md §7.11): FDR's `P :[deadlock free]` on the
    untimed process, in the failures-divergences model: no reachable stable configuration refuses
    every event (a terminated one included: FDR reports the state after ✓ as a deadlock), and no
    divergence."""
    if negated:
        return (Goal.witness(untimed_deadlocked, _describe_untimed, prepare=watch_loops, unprovable=unbounded_loops,
                             sought="a deadlock (a refusal of every event, termination included, or divergence)"),)
    return (Goal.violation(refuses_everything, _describe_untimed,
                           claim="no configuration refuses every event (termination included)"),
            _no_divergence(_describe_untimed))
