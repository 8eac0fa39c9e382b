"""Refinement in the failures and failures-divergences models, with the model on the left
(docs/semantics.md §7.12).

`M refines Q in the failures model` adds to traces refinement: after every trace, each stable
refusal of M is one of Q's.  Q's refusals after a trace are those of its stable terms (no internal
step, no ✓) in the monitor state the trace leads to: a stable term with acceptance `A` refuses
exactly the sets disjoint from `A`.  So M, stable and not terminated after trace t, violates the
refinement when every stable term of Q after t accepts some event that M refuses there.  (A
terminated M refuses only what Q's ✓ after the same trace allows, which traces refinement already
requires; a term that can do ✓ cannot refuse ✓, which M, short of termination, refuses.)

Values: a stable term accepts, per channel, whole classes of values (`Monitor.values`: each
value the state names, and `OTHER` for all the others), so M refuses an accepted event when some
value of a class, within its type and ranges, is one M does not offer.  Events on channels M
never shows (hidden, blocked, or not M's) are refused by M.

In the failures-divergences model M must also not diverge where Q does not; Q is required to be
divergence-free (else `Unsupported`), so M must be divergence-free.
"""

from __future__ import annotations

from dataclasses import dataclass

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import Move, TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.encodings.values import domain, equal, fresh, leaves
from tockbmc.model.csp import CspError
from tockbmc.model.errors import Unsupported
from tockbmc.properties.deadlock import _has_cycle, _without_quantifier
from tockbmc.properties.goals import number_at, true_at
from tockbmc.properties.process import Implementation, MonitorExtension, _event_text, field_is
from tockbmc.properties.spec import ANY, OTHER, TOCK, Channel, Input, Monitor, Proc, Semantics, TooLarge, _extends

FAILURES_MODELS = ("failures", "failures divergences")
FOREIGN = ("a channel outside the model's alphabet",)  # an event no implementation channel carries


@dataclass(frozen=True)
class Offer:
    """A class of events a stable specification term accepts: a channel (an index into the
    channels given, or None for events the element never shows) and per value field a named value
    or `OTHER`."""

    channel: int | None
    values: tuple = ()


def acceptances(mon: Monitor, sem: Semantics, state: int, channels: list[Channel]) -> list[tuple[Offer, ...]]:
    """The acceptance of each stable term of the specification in a monitor state."""
    return [acceptance(mon, sem, state, p, channels) for p in mon.states[state] if sem.stable(p)]


def acceptance(mon: Monitor, sem: Semantics, state: int, p: Proc, channels: list[Channel]) -> tuple[Offer, ...]:
    """The classes of events the stable term `p` of monitor state `state` accepts."""
    offers: list[Offer] = []
    if sem.after(p, FOREIGN):  # accepts events of every channel (`RUN(Events)`)
        offers.append(Offer(None))
    for c, ch in enumerate(channels):
        try:
            classes = mon.values(state, ch)
        except TooLarge:
            raise Unsupported(None, "the specification names too many values of one channel to compare "
                                    "refusals") from None
        offers += [Offer(c, vs) for vs in classes if sem.after(p, (*ch.prefix, *vs))]
    for e in sem.mentions(p):  # named events of channels the element never shows
        if any(_extends(e, ch.prefix) or _extends(ch.prefix, e) for ch in channels) or e == TOCK:
            continue
        if sem.after(p, tuple(OTHER if x is ANY or isinstance(x, Input) else x for x in e)):
            offers.append(Offer(None))
            break
    return tuple(dict.fromkeys(offers))


def offer_text(channels: list[Channel], o: Offer) -> str:
    if o.channel is None:
        return "an event it never shows"
    ch = channels[o.channel]
    return _event_text((*ch.prefix, *o.values))


def divergent_state(mon: Monitor, sem: Semantics) -> int | None:
    """A monitor state (all reachable ones explored) whose terms have a cycle of internal steps."""
    for s, terms in enumerate(mon.states):
        if _has_cycle({p: {sem.force(q) for q in sem.taus(p)} for p in terms}):
            return s
    return None


def refuse_context(impl: Implementation, models: str = "the failures models") -> None:
    """The refusals checks cover the element's own configurations: not a prefix before it, nor a
    process after its termination."""
    if impl.head:
        raise Unsupported(None, f"refinement in {models} is not supported when a prefix comes before the model")
    if impl.continues:
        raise Unsupported(None, f"refinement in {models} is not supported when a process follows the model's "
                                "termination")


class Refusals:
    """The failures check beside a specification monitor (`MonitorExtension`) in BMC."""

    def __init__(self, ext: MonitorExtension, divergences: bool, spec_name: str,
                 models: str = "the failures models"):
        self.ext = ext
        mon, sem = ext.monitor, ext.context.sem
        refuse_context(ext.context.impl, models)
        self.accept = {s: acceptances(mon, sem, s, ext.channels) for s in range(ext.count)}
        if divergences:
            s = divergent_state(mon, sem)
            if s is not None:
                raise Unsupported(None, f"{spec_name} can diverge; refinement in the failures-divergences model "
                                        "against a divergent specification is not supported")
        self._made: dict[tuple, z3.BoolRef] = {}

    def _offered(self, system: TransitionSystem, m: Move, v: list) -> z3.BoolRef:
        """Move m is possible now carrying the values `v`."""
        eff = system.effect(m)
        system.enabled(m)  # registers the axioms of the functions its values call
        labelled = system.label_values(m)
        body = z3.And(eff.enabled + eff.choose + [equal(x, y) for (x, _t), y in zip(labelled, v, strict=True)])
        return z3.Exists(eff.chosen, body) if eff.chosen else body

    def refuses(self, system: TransitionSystem, state: int, o: Offer) -> z3.BoolRef:
        """The element, now, refuses some event of the class `o` (within its types and ranges)."""
        key = (state, o)
        if key in self._made:
            return self._made[key]
        if o.channel is None:
            return z3.BoolVal(True)
        ch = self.ext.channels[o.channel]
        if ch.prefix == TOCK:
            return z3.Not(system.tock_enabled())
        moves = [m for m in system.moves if self.ext.channel_of.get(m.index) == o.channel]
        types = [t for _v, t in system.label_values(moves[0])]
        named = self.ext.monitor.named.get((state, o.channel)) or self.ext.monitor.fields(state, ch)
        n = len(self._made)
        v = [fresh(f"refused{n}.{j}", t) for j, t in enumerate(types)]
        cs: list[z3.BoolRef] = []
        try:
            for j, (x, t) in enumerate(zip(v, types, strict=True)):
                cs += domain(x, t, system.ranges, ch.prefix[0])
                cs.append(field_is(x, o.values[j], named[j]))
        except ValueError as exc:
            raise CspError(self.ext.context.impl.pos, str(exc)) from None
        offered = z3.Or([self._offered(system, m, v) for m in moves])
        bound = [leaf for x in v for _p, leaf in leaves(x)]
        out = _without_quantifier(z3.Exists(bound, z3.And([*cs, z3.Not(offered)])) if bound
                                  else z3.And([*cs, z3.Not(offered)]))
        self._made[key] = out
        return out

    def violated(self, system: TransitionSystem) -> z3.BoolRef:
        """Stable, not terminated, and every stable term of the specification accepts an event refused here."""
        mon = system.cur[names.MONITOR]
        cases = []
        for s, accs in self.accept.items():
            cases.append(z3.And(mon == s, *[z3.Or([self.refuses(system, s, o) for o in acc]) for acc in accs]))
        return z3.And(z3.Not(system.internal_enabled()), z3.Not(system.halted()), z3.Or(cases or [z3.BoolVal(False)]))

    def refused(self, unroller: Unroller, model: z3.ModelRef, k: int) -> list[str]:
        """Per stable term of the specification where the run ends, a class it accepts that the element refuses."""
        system = unroller.system
        s = number_at(unroller, model, system.cur[names.MONITOR], k)
        refused = []
        for acc in self.accept.get(s, []):
            o = next((o for o in acc if true_at(unroller, model, self.refuses(system, s, o), k)), None)
            if o is not None:
                refused.append(offer_text(self.ext.channels, o))
        return sorted(set(refused))

    def describe(self, unroller: Unroller, model: z3.ModelRef, k: int, spec_name: str) -> str:
        system = unroller.system
        offered = offered_at(unroller, model, k)
        refused = self.refused(unroller, model, k)
        shown = ", ".join(offered) if offered else "nothing"
        if not refused:
            return (f"{system.name} is stable and offers {shown}, and {spec_name} has no stable state after this "
                    "trace, so it cannot refuse what the model refuses")
        return (f"{system.name} is stable and offers only {shown}; every stable state of {spec_name} after this trace "
                f"accepts an event the model refuses ({'; '.join(refused)})")


def offered_at(unroller: Unroller, model: z3.ModelRef, k: int) -> list[str]:
    """The visible events (by channel, `tock` included) the element offers at step k of the run."""
    system = unroller.system
    return sorted({".".join(str(x) for x in system.label(m)[0]) for m in system.moves
                   if m.kind != "internal" and not m.blocked and true_at(unroller, model, system.enabled(m), k)})


# ------------------------------------------------------------------ the specification refining the model

@dataclass(frozen=True)
class SpecRefusal:
    """After `events`, a stable state of the specification (monitor state `state`) accepts only
    `acceptance`: the model must have a stable configuration after the same events, short of
    termination, that offers nothing outside it."""

    events: tuple[tuple, ...]
    state: int
    acceptance: tuple[Offer, ...]


def spec_refusals(mon: Monitor, sem: Semantics, channels: list[Channel], traces: list[tuple[tuple, ...]]
                  ) -> list[SpecRefusal]:
    """The stable refusals of the specification after every prefix of `traces` (each once), the
    shortest traces first (so both engines report a missing refusal after the fewest events)."""
    out: dict[tuple, SpecRefusal] = {}
    for t in traces:
        state = mon.initial
        for n in range(len(t) + 1):
            if n:
                state = mon.after(state, t[n - 1])
            if state == Monitor.DEAD:
                break
            for acc in acceptances(mon, sem, state, channels):
                key = (t[:n], frozenset(acc))
                if key not in out:
                    out[key] = SpecRefusal(t[:n], state, acc)
    return sorted(out.values(), key=lambda r: (len(r.events), repr(r.events)))


def accepted(o: Offer, channels: list[Channel], values: list, named: list[list[object]]) -> z3.BoolRef:
    """A move's values are in the class `o` of its channel."""
    return z3.And([field_is(v, x, named[j]) for j, (v, x) in enumerate(zip(values, o.values, strict=True))])


def offers_within(system: TransitionSystem, mon: Monitor, r: SpecRefusal, channels: list[Channel],
                  channel_of: dict[int, int]) -> z3.BoolRef:
    """Stable, not terminated, and every event the element offers is one the acceptance holds."""
    cs: list[z3.BoolRef] = [z3.Not(system.internal_enabled()), z3.Not(system.halted())]
    for m in system.moves:
        c = channel_of.get(m.index)
        if c is None:
            continue
        classes = [o for o in r.acceptance if o.channel == c]
        if channels[c].prefix == TOCK:
            if not classes:
                cs.append(z3.Not(system.tock_enabled()))
            continue
        eff = system.effect(m)
        system.enabled(m)  # registers the axioms of the functions its values call
        values = [v for v, _t in system.label_values(m)]
        named = mon.fields(r.state, channels[c])
        try:
            member = z3.Or([accepted(o, channels, values, named) for o in classes] or [z3.BoolVal(False)])
        except ValueError as exc:
            raise Unsupported(None, str(exc)) from None
        body = z3.Implies(z3.And(eff.enabled + eff.choose), member)
        cs.append(z3.ForAll(eff.chosen, body) if eff.chosen else body)
    return _without_quantifier(z3.And(cs))


def acceptance_text(channels: list[Channel], acc: tuple[Offer, ...]) -> str:
    shown = [offer_text(channels, o) for o in acc]
    return "only {" + ", ".join(shown) + "}" if shown else "nothing"
