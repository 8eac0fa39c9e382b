"""Timed deadlock (`semantics.md` §3): what `P is deadlock-free` rules out.

Three ways to be stuck, searched together so that the shortest comes first:
- *refusal*: not terminated, and every event refused, `tock` included;
- *time only*: nothing but `tock` is possible, and nothing ever will be: no
  `wait` or deadline is running, and advancing every clock by any amount
  enables nothing (so only time passes, for ever);
- *divergence*: a lasso of internal steps (the configuration repeats with
  nothing but internal steps in between).
Termination is not a deadlock.
"""

from __future__ import annotations

import z3

from tockbmc.encodings.system import System
from tockbmc.properties.queries import Goal, stuck


def _nothing_ever(system: System, k: int) -> z3.BoolRef:
    """From step k only tock is possible, for every number of tocks to come."""
    now = z3.And(z3.Not(system.internal_enabled(k)), z3.Not(system.event_offered(k)))
    f = system.frame(k)
    clocks = [f[f"{comp.name}.clock.{clock}"] for comp in system.components for clock in comp.automaton.clocks]
    if not clocks:
        return now
    later = z3.Int(f"{system.tag}later@{k}")
    shifted = z3.substitute(now, *[(c, c + later) for c in clocks])  # type: ignore[operator]
    return z3.ForAll([later], z3.Implies(later >= 0, shifted))


def time_only(system: System, k: int) -> z3.BoolRef:
    f = system.frame(k)
    calm = []
    for c, comp in enumerate(system.components):
        a = comp.automaton
        calm.append(z3.Not(z3.And(system._at(c, k, a.waiting), f[f"{comp.name}.wait"] > 0)))
        calm.append(z3.Not(system._at(c, k, a.deadlined)))
        calm += [z3.Not(system._armed(c, td, k)) for td in a.trigger_deadlines]
    return z3.And(z3.Not(system.halted(k)), system.tock_enabled(k), *calm, _nothing_ever(system, k))


def may_diverge(system: System) -> bool:
    """Whether some machine has a cycle of steps that can be internal; without one, no run diverges.

    A cycle of internal moves returns every machine that took part to where it
    was, so at least one machine has a cycle of its own among those edges.
    """
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


def _has_cycle(graph: dict[int, set[int]]) -> bool:
    done: set[int] = set()
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
                return True
            elif child not in done:
                path.add(child)
                stack.append((child, iter(graph.get(child, ()))))
    return False


def diverges(system: System, k: int) -> z3.BoolRef:
    """The configuration at k repeats one at j < k, with only internal steps in between."""
    if not may_diverge(system):
        return z3.BoolVal(False)
    internal = [m.index for m in system.moves if m.kind == "internal"]
    loops = []
    for j in range(k):
        same = [system.frame(j)[n] == system.frame(k)[n] for n in system.sorts]
        steps = [z3.Or([system.action(i) == x for x in internal]) for i in range(j, k)]
        loops.append(z3.And(*same, *steps))
    return z3.Or(loops) if loops else z3.BoolVal(False)


def deadlocked(system: System, k: int) -> z3.BoolRef:
    return z3.Or(stuck(system, k), time_only(system, k), diverges(system, k))


def _describe(system: System, model: z3.ModelRef, k: int) -> str:
    name = system.name
    if z3.is_true(model.eval(diverges(system, k), model_completion=True)):
        return f"{name} can repeat internal steps for ever (divergence)"
    if z3.is_true(model.eval(system.tock_enabled(k), model_completion=True)):
        return f"{name} offers nothing but tock, now and at every later time"
    return f"{name} has not terminated and refuses every event, tock included"


def deadlock_goals(name: str, negated: bool) -> tuple[Goal, ...]:
    if negated:
        return (Goal(deadlocked, "holds", "unknown", "violated", _describe, stateless=False),)
    return (Goal(deadlocked, "violated", "holds", "holds", _describe, stateless=False),)
