"""What determinism needs of one configuration, and what a second run offers.

`P is deterministic` is a property of two runs (`bmc.determinism` searches pairs).  A cheaper,
sufficient condition reads one configuration at a time: *local nondeterminism* is a configuration
where the next step is not determined by the next visible event, because

- two internal moves are possible that do not commute (one writes what the other reads or writes),
  or a move chooses a value its event does not carry (a nondeterministic `wait`, an operation's
  local without a value);
- an internal move and a visible event are both possible and do not commute (one run takes the
  event, another the internal step and perhaps no longer offers it);
- two moves of one event are possible with the same values, or a visible move chooses a value its
  event does not carry.

Moves that commute (neither writes what the other reads or writes, the independence of the
partial-order reduction in `encodings.system`) reach the same configuration in either order and
neither disables the other, so they leave nothing open (Milner's confluence).  If no reachable
configuration is locally nondeterministic, two runs with the same trace reach the same
configurations, so none refuses what the other does: the element is deterministic (divergence
aside).
The converse does not hold (two moves of one event may lead to the same place), so a local
nondeterminism only sends the search to pairs of runs.
"""

from __future__ import annotations

import itertools

import z3

from tockbmc.encodings.system import Move, TransitionSystem
from tockbmc.encodings.terms import subterms
from tockbmc.encodings.values import leaves


class Offers:
    """Whether a move is possible with given values, as a template formula with placeholders."""

    def __init__(self, system: TransitionSystem):
        self.system = system
        self._made: dict[int, tuple[z3.BoolRef, list[z3.ExprRef]]] = {}

    def carried(self, m: Move) -> list[z3.ExprRef]:
        """The scalars move m's event carries, over the template step."""
        return [term for value, _t in self.system.label_values(m) for _p, term in leaves(value)]

    def template(self, m: Move) -> tuple[z3.BoolRef, list[z3.ExprRef]]:
        """`m` is possible with its values equal to the placeholders returned (over the template step)."""
        if m.index not in self._made:
            eff = self.system.effect(m)
            carried = self.carried(m)
            holes = [z3.FreshConst(term.sort(), "offered") for term in carried]
            body = z3.And([*eff.enabled, *eff.choose, *(t == h for t, h in zip(carried, holes, strict=True))])
            formula = z3.Exists(eff.chosen, body) if eff.chosen else body
            self._made[m.index] = formula, holes  # type: ignore[assignment]
        return self._made[m.index]


def visible_moves(system: TransitionSystem) -> list[Move]:
    return [m for m in system.moves if m.kind != "internal" and not (m.kind == "tock" and system.tock_hidden)]


def locally_nondeterministic(system: TransitionSystem) -> z3.BoolRef:
    """A configuration where the next visible event does not determine the next step (see above)."""
    return system.once("locally nondeterministic", lambda: _local(system))


def _local(system: TransitionSystem) -> z3.BoolRef:
    offers = Offers(system)
    visible = visible_moves(system)
    internal = [m for m in system.moves if m not in visible]
    enabled = {m.index: system.enabled(m) for m in system.moves}
    chosen = {term.get_id() for _t, value in system.inputs.values() for _p, term in leaves(value)}

    def chooses(m: Move) -> bool:
        """Whether move m picks a value its event does not carry (a wait's length, a local's value)."""
        eff = system.effect(m)
        carried = {term.get_id() for term in offers.carried(m)} if m in visible else set()
        used = z3.And([*eff.choose, *(t == t for t in eff.post.values())])
        return any(t.get_id() in chosen and t.get_id() not in carried for t in subterms(used))

    prints = {m.index: system.footprint(m) for m in system.moves}

    def terminates(m: Move) -> bool:
        return any(e.kind == "terminate" for _, e in m.parts)

    def dependent(m: Move, o: Move) -> bool:
        """Whether taking one of two moves may change the other (else they commute: a diamond).
        A termination `o` beside an internal move `m` that leaves what `o` reads alone leaves
        nothing open: `o` stays possible after `m`, and either way the run ends halted after the
        same events, refusing everything."""
        fm, fo = prints[m.index], prints[o.index]
        if fm is None or fo is None:
            return True
        (rm, wm), (ro, wo) = fm, fo
        if terminates(m) or terminates(o):
            return terminates(m) == terminates(o) or bool((wm if terminates(o) else wo) & (ro if terminates(o) else rm))
        return bool(wm & (ro | wo) or wo & rm)

    cs = [z3.And(enabled[m.index], enabled[o.index]) for m, o in itertools.combinations(internal, 2)
          if dependent(m, o)]
    cs += [enabled[m.index] for m in system.moves if chooses(m)]
    cs += [z3.And(enabled[m.index], enabled[v.index]) for m in internal for v in visible
           if v.kind != "tock" and dependent(m, v)]  # tock waits for every internal step (maximal progress)
    by_label: dict[tuple, list[Move]] = {}
    for m in visible:
        by_label.setdefault(system.label(m), []).append(m)
    for group in by_label.values():
        for m, o in itertools.combinations(group, 2):
            if terminates(m) and terminates(o):
                continue  # either way the element has terminated after the same events: nothing differs
            fm, hm = offers.template(m)
            fo, ho = offers.template(o)
            both = z3.And(fm, z3.substitute(fo, *zip(ho, hm, strict=True)) if ho else fo)
            cs.append(z3.Exists(hm, both) if hm else both)
    return z3.Or(cs) if cs else z3.BoolVal(False)
