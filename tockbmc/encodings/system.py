"""The symbolic transition system of a network of machines, over one template step.

A configuration is a flat set of named scalars (`encodings.names`): per
machine its location, variables, clocks and `wait`/deadline counters; the
shared variables; per asynchronous link its buffer.  A step is one `Move`
(`docs/semantics.md` §3.2): an internal step, a visible event or `tock`.

Every formula is built once, over the template step: the configuration before
it (`cur`, scalars named `x@0`), the one after it (`nxt`, `x@1`), the move it
takes (`act`, `act@0`) and the values chosen during it (`inputs`, `name@0`).
`trans()` relates `cur` and `nxt`, each scalar's next value an if-then-else
over the moves that change it.  The `Unroller` (`encodings.unroller`) puts
these terms at step k; this module never names a step other than the template.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Protocol

import z3

from tockbmc.encodings import names
from tockbmc.encodings.automaton import Edge, TriggerDeadline
from tockbmc.encodings.composition import Copies, External, Link, Network, Port
from tockbmc.encodings.values import (
    CHOSEN,
    Evaluator,
    Origin,
    Parts,
    Ranges,
    Unset,
    Value,
    as_type,
    domain,
    equal,
    fits,
    folds,
    fresh,
    function_parts,
    initially,
    kept_items,
    leaf_type,
    leaves,
    parts,
    sort_of,
    stored,
)
from tockbmc.model import ast
from tockbmc.model.config import constant_setting, declaration_key, instance_key, instance_name
from tockbmc.model.csp import canonical
from tockbmc.model.errors import Unsupported
from tockbmc.model.readings import default_value

_MAX_TERMINATIONS = 64  # combinations of final states, one `terminate` move each


@dataclass(frozen=True)
class Move:
    """One kind of step.

    kind: internal | event | tock.  `parts` are the (component, edge) pairs
    that move together: none for tock and for the environment's side of a
    buffer, one for a machine's own step, two for a synchronous connection, one
    per machine for the element's `terminate`.
    role: local | sync | write | read | env-write | env-read | terminate | tock, and for
    RoboTool's memory model (docs/semantics.md §5.5) set (a machine's visible write of a shared
    variable), env-set (the environment's) and pass (the memory passes a value on to one copy).
    """

    index: int
    kind: str
    role: str
    parts: tuple[tuple[int, Edge], ...] = ()
    link: Link | None = None
    hidden: bool = False  # a visible event that a CSP context hides, so internal (and urgent)
    blocked: bool = False  # a visible event that a CSP context blocks (`P [| A |] SKIP`)
    copies: Copies | None = None  # set, env-set, pass: the shared variable's memory (RoboTool's)
    reader: int = -1  # pass: which of its copies the memory passes the value to

    @property
    def urgent(self) -> bool:
        """Internal steps, operation calls and RoboTool's visible writes of shared variables may not
        wait for `tock` (docs/semantics.md §3.3–§3.4, §5.5)."""
        return self.kind == "internal" or self.role == "set" or any(e.kind == "call" for _, e in self.parts)


@dataclass
class _Effect:
    enabled: list[z3.BoolRef]  # determined by the configuration and the chosen values
    choose: list[z3.BoolRef]  # constraints on values chosen in the step (inputs, wait lengths)
    post: dict[str, z3.ExprRef]  # scalars the step changes
    chosen: list[z3.ExprRef]  # the values the environment chooses (event inputs)
    side: list[z3.BoolRef]  # function axioms instantiated at the calls this step makes


class Context(Protocol):
    """What a CSP context does to the element's events (see `properties.process`)."""

    def status(self, label: tuple, arity: int) -> str:
        """'visible', 'hidden' or 'blocked' for the events of one channel."""
        ...

    def attach(self, system: TransitionSystem) -> Extension | None:
        """Extra state that runs beside the element (a specification monitor), if any."""
        ...


class Extension(Protocol):
    """Scalars and constraints added to every configuration and step (over the template step).

    An extension that reads configurations between steps other than through visible events (a
    lasso's saved copy) says so with a true `order_sensitive` attribute: independent internal
    steps are then not put in order (see `TransitionSystem.ordered`).
    """

    def slots(self) -> dict[str, z3.SortRef]: ...

    def init(self, system: TransitionSystem) -> z3.BoolRef: ...

    def step(self, system: TransitionSystem) -> z3.BoolRef: ...


Target = Callable[["TransitionSystem"], z3.BoolRef]
"""What an engine searches for: a formula over the template configuration `cur` (and, through an
extension's state, over the history) that holds where a run ends in a violation or a witness."""


class TransitionSystem:
    """A network's configurations, moves, initial condition and step relation, over the template step."""

    def __init__(self, network: Network, ranges: Ranges, settings: dict[str, ast.Expr] | None = None,
                 context: Context | None = None):
        self.network = network
        self.ranges = ranges
        self.settings = settings or {}
        self.name = network.name
        self.components = network.components
        self.sorts: dict[str, z3.SortRef] = {}
        self._states: tuple[dict[str, z3.ExprRef], dict[str, z3.ExprRef]] | None = None
        self.act = z3.Int("act@0")  # the index of the move the template step takes
        self.inputs: dict[str, tuple[ast.Type, Value]] = {}  # values chosen during the step, by name
        self.side: list[z3.BoolRef] = []  # function axioms at the calls the formulas make (grows as they are built)
        self.constraints: list[z3.BoolRef] = []  # on constants: they hold at every step
        self.open_constants: dict[str, Value] = {}  # constants without a value (parameters), by declaration key
        self.constants: dict[int, dict[int, Value]] = {}  # component -> id(constant) -> value
        self.slots: dict[int, dict[int, tuple[str, ast.Type]]] = {}  # component -> id(variable) -> slot
        self.initial: dict[str, tuple[ast.Type, ast.Expr | None, int, str]] = {}  # slot -> (type, initial, component, declaration)
        self.copy_slots: dict[tuple[int, str], str] = {}  # (component, shared key) -> its copy's slot
        self._effects: dict[int, _Effect] = {}
        self._built: dict[str, z3.BoolRef] = {}
        self._declare()
        self.moves = self._moves()
        # per component, the locations where it offers a visible write (RoboTool's `set_x`), urgent
        # as RoboTool's `prioritise(…, <visible memory events, {tock}>)` makes it
        self._writing = [frozenset(e.source for m in self.moves if m.role == "set" for c2, e in m.parts if c2 == c)
                         for c in range(len(self.components))]
        self.TOCK = len(self.moves) - 1
        self.tock_hidden = False
        self.extension: Extension | None = None  # the CSP context's (a monitor or a trace follower)
        self.extensions: list[Extension] = []  # every extension, that one included
        self.extension_slots: dict[str, z3.SortRef] = {}
        if context is not None:
            self.moves = [self._in_context(context, m) for m in self.moves]
            self.tock_hidden = context.status(("tock",), 0) == "hidden"
            self.extension = context.attach(self)
            if self.extension is not None:
                self.add(self.extension)

    def add(self, extension: Extension) -> None:
        """Run extra state beside the network (before any formula names a configuration)."""
        assert self._states is None, "extensions are added before any formula is built"
        self.extensions.append(extension)
        slots = extension.slots()
        self.extension_slots.update(slots)
        self.sorts.update(slots)

    def _in_context(self, context: Context, m: Move) -> Move:
        if m.kind != "event":
            return m
        label, arity = self.label(m)
        status = context.status(label, arity)
        if status == "hidden":
            return replace(m, kind="internal", hidden=True)
        return replace(m, blocked=True) if status == "blocked" else m

    # ------------------------------------------------------------ the template step's symbols

    @property
    def cur(self) -> dict[str, z3.ExprRef]:
        """The configuration before the template step, as scalars by name (`x@0`)."""
        return self._template()[0]

    @property
    def nxt(self) -> dict[str, z3.ExprRef]:
        """The configuration after the template step (`x@1`)."""
        return self._template()[1]

    def _template(self) -> tuple[dict[str, z3.ExprRef], dict[str, z3.ExprRef]]:
        if self._states is None:
            self._states = tuple({n: z3.Const(f"{n}@{k}", s) for n, s in self.sorts.items()}  # type: ignore[assignment]
                                 for k in (0, 1))
        assert self._states is not None
        return self._states

    def input(self, name: str, t: ast.Type) -> Value:
        """A value chosen during the template step (an input, a wait length), created once."""
        if name not in self.inputs:
            self.inputs[name] = (t, fresh(f"{name}@0", t))
        return self.inputs[name][1]

    def loc(self, c: int) -> z3.ArithRef:
        return self.cur[names.location(self.components[c].name)]  # type: ignore[return-value]

    def value(self, base: str, t: ast.Type, after: bool = False) -> Value:
        """A variable's value before the template step (after it, with `after`)."""
        f = self.nxt if after else self.cur
        if parts(t):
            return {fd: self.value(f"{base}.{fd}", ft, after) for fd, ft in parts(t)}
        return f[base]

    def evaluator(self, c: int, extra: dict[int, Value] | None = None, guards: list[z3.BoolRef] | None = None,
                  flags: dict[int, dict[str, z3.BoolRef]] | None = None) -> Evaluator:
        env = {key: self.value(base, t) for key, (base, t) in self.slots[c].items()}
        if extra:
            env.update(extra)
        name = self.components[c].name
        clocks = {clock: self.cur[names.clock(name, clock)] for clock in self.components[c].automaton.clocks}
        return Evaluator(env, self.constants[c], self.side, clocks, self.ranges, guards,
                         _origins(self._flags(c) if flags is None else flags))

    # ------------------------------------------------------------ event labels (CSP's view)

    def label(self, m: Move) -> tuple[tuple, int]:
        """A visible move's channel as CSP names it, `("EXAX::move", "in")`, and how many values follow."""
        if m.kind == "tock":
            return ("tock",), 0
        if m.role in ("env-write", "env-read"):
            assert m.link is not None
            end = m.link.sender if m.role == "env-write" else m.link.receiver
            assert isinstance(end, External)
            return (canonical(end.name), "in" if m.role == "env-write" else "out"), int(end.event.type is not None)
        if m.role in ("set", "env-set"):
            assert m.copies is not None
            return (canonical((m.copies.written if m.role == "set" else m.copies.external) or ""),), 1
        c, e = m.parts[0]
        if e.kind == "terminate":
            return (canonical(f"{self.name}::terminate"),), 0
        if e.kind == "call":
            assert e.operation is not None
            return (canonical(f"{self.name}::{e.operation.name}Call"),), len(e.args)
        assert e.event is not None
        name = self.network.visible_name(c, e.event.name)
        return (canonical(name), "in" if e.kind == "in" else "out"), int(e.event.type is not None)

    def label_values(self, m: Move) -> list[tuple[Value, ast.Type]]:
        """The values a visible move carries in the template step, with their types."""
        if m.kind == "tock":
            return []
        if m.role in ("env-write", "env-read"):
            assert m.link is not None
            end = m.link.sender if m.role == "env-write" else m.link.receiver
            assert isinstance(end, External)
            t = end.event.type
            if t is None:
                return []
            value = (self.input(names.input_value(end.name), t) if m.role == "env-write"
                     else self.value(names.buffer_value(m.link.index), t))
            return [(value, t)]
        if m.role in ("set", "env-set"):
            return [(self.written_value(m), m.copies.variable.type)]  # type: ignore[union-attr]
        c, e = m.parts[0]
        if e.kind == "terminate":
            return []
        # The conditions these values put on the step (a function's result in its type) are the
        # step's own, which `_edge` adds where it evaluates the same expressions.
        ev = self.evaluator(c, guards=[])
        if e.kind == "call":
            if e.operation is not None and len(e.operation.parameters) == len(e.args):
                # each argument in its parameter's type: `op(1)` and `op(x)` on a real parameter carry reals
                return [(as_type(ev.value(a), p.type, a.pos), p.type) for a, p in zip(e.args, e.operation.parameters)]
            return [(ev.value(a), a.type) for a in e.args]
        assert e.event is not None
        t = e.event.type
        if t is None:
            return []
        if e.kind == "in":
            name = self.network.visible_name(c, e.event.name)
            return [(self.input(names.input_value(name), t), t)]
        assert e.value is not None
        return [(as_type(ev.value(e.value), t, e.value.pos), t)]

    def written_value(self, m: Move) -> Value:
        """The value a write of a shared variable carries (`set`: the whole variable after the
        step, as RoboTool's `set_x` does; `env-set`: the one the environment chose)."""
        cp = m.copies
        assert cp is not None
        t = cp.variable.type
        if m.role == "env-set":
            assert cp.external is not None
            return self.input(names.input_value(cp.external), t)
        c, e = m.parts[0]
        a = e.updates[0]
        new = self.evaluator(c, guards=[]).value(a.value)
        whole = _set_field(self.value(self.slots[c][id(a.variable)][0], t), a.fields, new) if a.fields else new
        return as_type(whole, t, a.value.pos)

    # ------------------------------------------------------------ declarations

    def _slot(self, name: str, sort: z3.SortRef) -> str:
        self.sorts[name] = sort
        return name

    def _scalars(self, base: str, t: ast.Type) -> None:
        for path, _ in leaves(fresh("probe", t)):
            self._slot(base + path, sort_of(leaf_type(t, path)))

    def _declare(self) -> None:
        self._slot(names.PREVIOUS, z3.IntSort())
        shared_consts: dict[str, Value] = {}
        for c, comp in enumerate(self.components):
            m = comp.machine
            self._slot(names.location(comp.name), z3.IntSort())
            self._slot(names.wait(comp.name), z3.IntSort())
            if comp.automaton.threaded:
                self._slot(names.wait(comp.name, 1), z3.IntSort())
            self._slot(names.deadline(comp.name), z3.IntSort())
            for clock in comp.automaton.clocks:
                self._slot(names.clock(comp.name, clock), z3.IntSort())
            for td in comp.automaton.trigger_deadlines:
                self._slot(names.armed(comp.name, td.transition), z3.IntSort())
            slots: dict[int, tuple[str, ast.Type]] = {}
            consts: dict[int, Value] = {}
            own = [("", v) for v in (*m.variables, *m.interface_variables)]
            for scope, v in (*own, *comp.automaton.extra_variables):
                if v.type == ast.STRING:
                    raise Unsupported(v.pos, "string variables are not encoded yet")
                # A required variable is shared under its scope key; anything else is the machine's own.
                key = self.shared_key(c, v)
                decl = self.network.shared.get(key, v) if key is not None else v
                # parameters of inlined operations are assigned; an operation's own, checked alone, are constants
                if v.constant and (v.kind != "parameter" or not scope):
                    if key is not None and key in shared_consts:
                        consts[id(v)] = shared_consts[key]
                        continue
                    # an inlined operation's constant is its own: opB's x2 is not opC's x2
                    own_name = names.constant(comp.name, f"{scope}().{v.name}" if scope else v.name)
                    consts[id(v)] = self._constant(v, decl, key or own_name, () if key else comp.instance)
                    if key is not None:
                        shared_consts[key] = consts[id(v)]
                    continue
                cp = self.network.copies.get(key) if key is not None else None
                base = names.variable(comp.name, v.name) if cp is not None else key or names.variable(comp.name, v.name, scope)
                slots[id(v)] = (base, v.type)
                if cp is not None:
                    self.copy_slots[(c, cp.key)] = base
                if base not in self.initial:
                    self._scalars(base, v.type)
                    # a copy whose memory passes a value on at the start starts at its type's default
                    start = default_value(v.type, v.pos) if cp is not None and cp.start is not None else decl.initial
                    self.initial[base] = (v.type, start, c, declaration_key(decl))
            self.slots[c] = slots
            self.constants[c] = consts
        for cp in self.network.copies.values():
            if cp.stateful:
                self._slot(names.next_copy(cp.key), z3.IntSort())
                self._scalars(names.passing(cp.key), cp.variable.type)
        self._declare_unset()
        self._kept: set[str] = set()  # variables whose items are kept in type by an axiom (`_keep_items`)
        for link in self.network.links:
            if link.asynchronous:
                self._slot(names.buffer_full(link.index), z3.BoolSort())
                t = _end_event(link).type
                if t is not None:
                    self._scalars(names.buffer_value(link.index), t)

    def _declare_unset(self) -> None:
        """A flag for each function-typed part of a variable that may hold, at different times, a
        function nobody set (its initial value where it has none, a copy of such a value, an
        operation's fresh local) and one the model made (a lambda, `override`, …): true while it
        holds the first, whose results are in their type at every point, false while it holds the
        second, whose results are in their type where a step applies it (`values.Unset`). Which
        variables may hold which is found from the assignments, to a fixpoint."""
        base_of = {key: base for c in range(len(self.components)) for key, (base, _t) in self.slots[c].items()}
        chosen = {b for b, (_t, initial, _c, _k) in self.initial.items() if initial is None}
        made = {b for b, (_t, initial, _c, _k) in self.initial.items() if initial is not None}

        def gives(e: ast.Expr, held: set[str], as_chosen: bool) -> bool:
            """Whether `e` may give a function of the kind `held` gathers."""
            if isinstance(e, ast.FieldRef):
                return gives(e.record, held, as_chosen)
            if isinstance(e, ast.Index) and isinstance(e.value.type, ast.ProductType):
                return gives(e.value, held, as_chosen)
            if isinstance(e, ast.RecordLiteral):
                return any(gives(x, held, as_chosen) for _, x in e.fields) or as_chosen and bool(e.omitted)
            if isinstance(e, ast.TupleLiteral):
                return any(gives(x, held, as_chosen) for x in e.items)
            if isinstance(e, ast.VarRef):
                base = base_of.get(id(e.variable))
                return base in held if base is not None else (e.variable.initial is None) == as_chosen
            return not as_chosen

        writes = [(base_of[id(a.variable)], a.value) for comp in self.components for e in comp.automaton.edges
                  for a in e.updates if id(a.variable) in base_of]
        chosen |= {base_of[id(v)] for comp in self.components for e in comp.automaton.edges for v in e.havoc
                   if id(v) in base_of}
        # a function received on an event: chosen by the environment, or made by the machine sending it
        received = {base_of[id(e.binds)] for comp in self.components for e in comp.automaton.edges
                    if e.binds is not None and id(e.binds) in base_of}
        chosen |= received
        made |= received
        grown = True
        while grown:
            grown = False
            for base, value in writes:
                for held, as_chosen in ((chosen, True), (made, False)):
                    if base not in held and gives(value, held, as_chosen):
                        held.add(base)
                        grown = True
        self.unset: dict[str, dict[str, str]] = {}  # variable's slot -> function part's path -> flag's slot
        self.unset_at_start: dict[str, bool] = {}  # variable's slot -> whether it starts with a chosen function
        for base in sorted(chosen & made):
            t, initial, _c, _k = self.initial[base]
            paths = function_parts(t)
            if paths:
                self.unset[base] = {path: self._slot(f"{base}{path}!unset", z3.BoolSort()) for path in paths}
                self.unset_at_start[base] = initial is None or \
                    gives(initial, chosen, True) and not gives(initial, made, False)

    def _keep_items(self, base: str, t: ast.Type) -> None:
        """The items of a variable's sequences and sets of `nat` (in records, tuples, …) are of
        their type in every configuration, as every step that stores one checks (`fits`). For a
        variable some step gives a fold's value (`reverse`, `filter`), that is an axiom of each
        step: Z3 does not derive it through the fold (`unknown` on
        tests/models/seq_and_function_values/filt), and elsewhere it would only add a quantifier
        (`unknown` on a deadlock of seq_and_function_values/dw's V)."""
        if base in self._kept:
            return
        self._kept.add(base)
        for path, term in leaves(self.value(base, t)):
            lt = leaf_type(t, path)
            if isinstance(lt, (ast.SeqType, ast.SetType)):
                self.side += kept_items(term, lt)

    def _flags(self, c: int) -> dict[int, dict[str, z3.BoolRef]]:
        """The `unset` flags of component c's variables before the template step, by id(Variable)."""
        return {key: {path: self.cur[flag] for path, flag in self.unset[base].items()}  # type: ignore[misc]
                for key, (base, _t) in self.slots[c].items() if base in self.unset}

    def shared_key(self, c: int, v: ast.Variable) -> str | None:
        """The scope key under which component c shares a variable or constant it requires, if it does."""
        return self.network.scopes.get((c, v.name)) if v.kind == "interface" else None

    def _constant(self, v: ast.Variable, decl: ast.Variable, name: str, instance: tuple[str, ...] = ()) -> Value:
        value = fresh(name, v.type)
        # this instance's value, else the declaration's (model/config.py)
        given = self.settings.get(instance_key(instance, decl)) if instance else None
        given = given if given is not None else constant_setting(self.settings, v, decl)
        expr = given if given is not None else decl.initial
        if given is not None and ast.omits_fields(given):  # open fields only as an initial value (DESIGN.md)
            raise Unsupported(given.pos, f"a record literal omitting fields as the value given to constant {v.name}")
        if expr is not None:
            self.constraints += initially(value, v.type, expr, Evaluator({}, {}, self.side, ranges=self.ranges),
                                          self.ranges, declaration_key(decl))
            if ast.omits_fields(expr):  # its open fields, shown with the trace as an open constant's value
                self.open_constants.setdefault(instance_name(self.network.qname or self.name, instance, v) if instance else declaration_key(decl),
                                               value)
        else:
            self.constraints += domain(value, v.type, self.ranges, declaration_key(decl))
            # one parameter per instance of a machine's own constant (`stm_ref0::CC`), as its values are
            self.open_constants.setdefault(instance_name(self.network.qname or self.name, instance, v) if instance else declaration_key(decl), value)
        return value

    # ------------------------------------------------------------ moves

    def _moves(self) -> list[Move]:
        moves: list[Move] = []

        def add(kind: str, role: str, parts: tuple[tuple[int, Edge], ...] = (), link: Link | None = None) -> None:
            moves.append(Move(len(moves), kind, role, parts, link))

        for c, comp in enumerate(self.components):
            for e in comp.automaton.edges:
                written = self._visible_write(c, e)
                if written is not None:
                    moves.append(Move(len(moves), "event", "set", ((c, e),), copies=written))
                elif e.kind in ("tau", "wait"):
                    add("internal", "local", ((c, e),))
                elif e.kind == "terminate":
                    # the element's joint moves, where the first machine's termination is (the order
                    # of moves shapes the encoding, and Spacer is sensitive to it)
                    if not any(m.role == "terminate" for m in moves):
                        for ends in self._terminations():
                            add("internal" if self.network.hidden_termination else "event", "terminate", ends)
                elif e.kind == "call":
                    add("event", "local", ((c, e),))
                else:
                    assert e.event is not None
                    found = self.network.route(c, e.event.name)
                    if found is None:
                        add("event", "local", ((c, e),))
                        continue
                    link, role = found
                    other = link.receiver if role == "sender" else link.sender
                    if isinstance(other, Port) and not link.asynchronous and e.kind != ("out" if role == "sender"
                                                                                            else "in"):
                        # against its connection's direction (the sender receiving, the receiver sending):
                        # not joined, so visible under the machine's name, as an unconnected event is
                        add("event", "local", ((c, e),))
                    elif isinstance(other, External) and not link.asynchronous:
                        add("event", "local", ((c, e),), link)
                    elif link.asynchronous:
                        wants = "out" if role == "sender" else "in"
                        if e.kind != wants:
                            raise Unsupported(link.pos, f"{comp.name} uses '{e.event.name}' as an "
                                                        f"{'input' if e.kind == 'in' else 'output'}, against the "
                                                        "direction of its asynchronous connection")
                        add("internal", "write" if role == "sender" else "read", ((c, e),), link)
        for link in self.network.links:
            if isinstance(link.sender, Port) and isinstance(link.receiver, Port) and not link.asynchronous:
                a, b = link.sender, link.receiver
                for ea in self.components[a.component].automaton.edges:
                    if ea.event is None or ea.event.name != a.event.name or ea.kind not in ("in", "out"):
                        continue
                    for eb in self.components[b.component].automaton.edges:
                        if eb.event is None or eb.event.name != b.event.name or eb.kind not in ("in", "out"):
                            continue
                        if (ea.kind, eb.kind) == ("out", "in"):  # the sender's output with the receiver's input
                            add("internal", "sync", ((a.component, ea), (b.component, eb)), link)
            elif link.asynchronous and isinstance(link.sender, External):
                add("event", "env-write", (), link)
            elif link.asynchronous and isinstance(link.receiver, External):
                add("event", "env-read", (), link)
        for cp in self.network.copies.values():
            if cp.external is not None:
                moves.append(Move(len(moves), "event", "env-set", copies=cp))
            if cp.stateful:
                moves += [Move(len(moves) + j, "internal", "pass", copies=cp, reader=j) for j in range(len(cp.readers))]
        add("tock", "tock")
        return moves

    def _copies(self, c: int, v: ast.Variable) -> Copies | None:
        """The memory of a shared variable component c keeps a copy of, if it does."""
        key = self.shared_key(c, v)
        return self.network.copies.get(key) if key is not None else None

    def _visible_write(self, c: int, e: Edge) -> Copies | None:
        """The memory of the shared variable edge e writes where the write is a visible event
        (RoboTool's `set_x`), if it is."""
        for v in _writes(e):
            cp = self._copies(c, v)
            if cp is not None and cp.written is not None:
                if e.kind != "tau":
                    raise Unsupported(e.pos or v.pos, f"an input into variable {v.name}, whose writes are visible "
                                                      f"as RoboTool's {cp.written}, is not encoded yet")
                return cp
        return None

    def _terminations(self) -> list[tuple[tuple[int, Edge], ...]]:
        """The element's `terminate`: every machine at a final state takes its `terminate` edge at
        once (docs/semantics.md §5.6: RoboTool synchronises `terminate` across the machines of a
        controller and the controllers of a module).  One move per choice of final state."""
        per_machine = [[(c, e) for e in comp.automaton.edges if e.kind == "terminate"]
                       for c, comp in enumerate(self.components)]
        if not all(per_machine):
            return []  # a machine without a final state never terminates, so neither does the element
        count = math.prod(len(edges) for edges in per_machine)
        if count > _MAX_TERMINATIONS:
            raise Unsupported(self.components[0].machine.pos,
                              f"{count} combinations of final states end the element: more than "
                              f"{_MAX_TERMINATIONS} are not encoded")
        return list(itertools.product(*per_machine))

    # ------------------------------------------------------------ effects of one move

    def _edge(self, c: int, e: Edge, incoming: Value | None, post: dict[str, z3.ExprRef], chosen: str | None = None
              ) -> tuple[list[z3.BoolRef], list[z3.BoolRef], Value | None]:
        """Component c takes edge e in the template step, receiving `incoming` on an input (a value
        the environment chose on the event at path `chosen`, else one another machine sent).

        Returns (conditions fixed by the configuration, constraints on chosen
        values, the value sent on an output); writes the changed scalars into `post`.
        """
        comp = self.components[c]
        f = self.cur
        enabled: list[z3.BoolRef] = [self.loc(c) == e.source]
        choose: list[z3.BoolRef] = []
        bound: dict[int, Value] = {}
        flags = self._flags(c)
        if incoming is not None and e.binds is not None:
            bound[id(e.binds)] = incoming
            # a function the environment chose is any function into its type; one another machine
            # sent may be one it made
            if id(e.binds) in self.slots[c]:
                self._set_unset(c, id(e.binds), "", lambda _part: z3.BoolVal(chosen is not None), flags, post)
            # `e?x` into a nat x: not a negative value. A value the environment chose is one of the
            # event's type, within the range of its path (a sequence's length); a value another
            # machine sent is checked whole.
            known = stored([(incoming, e.event.type)]) if chosen is not None and e.event and e.event.type else {}
            r = self.ranges.length((chosen,)) if chosen is not None else None
            enabled += fits(incoming, e.binds.type, known, math.floor(r.high) if r is not None else None)
        ev = self.evaluator(c, bound, guards=enabled, flags=flags)
        if incoming is not None and e.value is not None and e.kind == "in":
            enabled.append(equal(incoming, ev.value(e.value)))
        enabled += [ev.scalar(g) for g in e.guard]
        for group in e.negated_guards:
            enabled.append(z3.Not(z3.And([ev.scalar(g) for g in group])))
        if e.ends_wait:
            enabled.append(f[names.wait(comp.name, e.thread)] == 0)
        sent = ev.value(e.value) if e.kind == "out" and e.value is not None else None
        for arg in e.args:  # a call's arguments are its label's values (`label_values`): their conditions
            ev.value(arg)
        # Updates in order, each reading the values (and `unset` flags) the previous ones wrote.
        current = {key: self.value(base, t) for key, (base, t) in self.slots[c].items()}
        current.update(bound)
        # values already of their places' types, which `fits` need not check again: the places'
        # values before the step, and each value a step stores (checked as it is stored)
        known = stored((current[key], t) for key, (_base, t) in self.slots[c].items())
        for a in e.updates:
            writer = Evaluator(current, self.constants[c], self.side, ev.clocks, self.ranges, enabled, _origins(flags))
            new = writer.value(a.value)
            # the value fits its place (a `nat` not negative), or the step cannot be taken
            path = "".join(f".{f}" for f in a.fields)
            enabled += fits(new, leaf_type(a.variable.type, path), known)
            known.update(stored([(new, leaf_type(a.variable.type, path))]))
            key = id(a.variable)
            if folds(new):
                self._keep_items(*self.slots[c][key])
            current[key] = _set_field(current[key], a.fields, new) if a.fields else new
            self._set_unset(c, key, path, functools.partial(_chosen_part, writer, a.value), flags, post)
        for v in e.havoc:  # any value of its type and range (an operation's fresh variable)
            base, t = self.slots[c][id(v)]
            value = self.input(names.fresh_value(base), t)
            choose += domain(value, t, self.ranges, base)
            current[id(v)] = value
            self._set_unset(c, id(v), "", lambda _part: z3.BoolVal(True), flags, post)  # a function chosen afresh
        for key, (base, _t) in self.slots[c].items():
            if key in bound or any(id(a.variable) == key for a in e.updates) or any(id(v) == key for v in e.havoc):
                for path, term in leaves(current[key]):
                    post[base + path] = term
        for v in _writes(e):
            cp = self._copies(c, v)
            if cp is not None and cp.passes_writes and cp.stateful:
                # the memory takes the write once it has passed the last one on, and passes it on
                enabled.append(self._idle(cp))
                post[names.next_copy(cp.key)] = z3.IntVal(0)
                for path, term in leaves(current[id(v)]):
                    post[names.passing(cp.key) + path] = term
        if e.target != e.source:
            post[names.location(comp.name)] = z3.IntVal(e.target)
        for clock in e.resets:
            post[names.clock(comp.name, clock)] = z3.IntVal(0)
        if e.kind == "wait":
            length = self.input(names.wait_length(comp.name), ast.INT)
            low, high = ev.scalar(e.wait_low), ev.scalar(e.wait_high)  # type: ignore[arg-type]
            enabled.append(low <= high)
            choose += [length >= low, length <= high]  # type: ignore[list-item, operator]
            post[names.wait(comp.name, e.thread)] = length  # type: ignore[assignment]
        if e.deadline is not None:
            post[names.deadline(comp.name)] = ev.scalar(e.deadline)  # type: ignore[assignment]
        for td in comp.automaton.trigger_deadlines:
            if e.target not in td.armed or td.source in e.exits:
                post[names.armed(comp.name, td.transition)] = z3.IntVal(0)
        return enabled, choose, sent

    def _idle(self, cp: Copies) -> z3.BoolRef:
        """The memory of a shared variable is passing no value on."""
        return self.cur[names.next_copy(cp.key)] == len(cp.readers)  # type: ignore[return-value]

    def _copy(self, cp: Copies, reader: int) -> Value:
        """The copy of a shared variable that the memory's `reader`-th machine keeps."""
        return self.value(self.copy_slots[(cp.readers[reader], cp.key)], cp.variable.type)

    def _passing(self, cp: Copies) -> Value:
        return self.value(names.passing(cp.key), cp.variable.type)

    def _memory_effect(self, m: Move, post: dict[str, z3.ExprRef]) -> tuple[list[z3.BoolRef], list[z3.BoolRef], list[z3.ExprRef]]:
        """RoboTool's memory model: the environment writes a shared variable (`env-set`), or the
        memory passes the value it holds on to one copy (`pass`).  Returns (conditions, constraints
        on chosen values, the values chosen)."""
        cp = m.copies
        assert cp is not None
        t = cp.variable.type
        if m.role == "pass":
            slot = self.copy_slots[(cp.readers[m.reader], cp.key)]
            for path, term in leaves(self._passing(cp)):
                post[slot + path] = term
            post[names.next_copy(cp.key)] = z3.IntVal(m.reader + 1)
            return [self.cur[names.next_copy(cp.key)] == m.reader], [], []  # type: ignore[list-item]
        assert cp.external is not None
        value = self.input(names.input_value(cp.external), t)
        choose = domain(value, t, self.ranges, declaration_key(cp.variable))
        if cp.direct:
            slot = self.copy_slots[(cp.readers[0], cp.key)]
            enabled: list[z3.BoolRef] = []
        else:
            slot = names.passing(cp.key)
            post[names.next_copy(cp.key)] = z3.IntVal(0)
            enabled = [self._idle(cp)]
        for path, term in leaves(value):
            post[slot + path] = term
        return enabled, choose, [term for _, term in leaves(value)]

    def _input(self, name: str, event: ast.Event, path: str) -> tuple[Value, list[z3.BoolRef]]:
        """A value the environment supplies on `event`, within its type and ranges."""
        assert event.type is not None
        value = self.input(name, event.type)
        return value, domain(value, event.type, self.ranges, path)

    def effect(self, m: Move) -> _Effect:
        """What taking move m requires and changes."""
        if m.index not in self._effects:
            before = len(self.side)
            eff = self._effect(m)
            eff.side = self.side[before:]
            self._effects[m.index] = eff
        return self._effects[m.index]

    def _effect(self, m: Move) -> _Effect:
        if m.role == "tock":
            return _Effect([self.tock_enabled()], [], self._tock_post(), [], [])
        post: dict[str, z3.ExprRef] = {}
        inputs: list[z3.ExprRef] = []
        enabled: list[z3.BoolRef] = [z3.Not(self.halted())]
        if m.blocked:
            enabled.append(z3.BoolVal(False))
        choose: list[z3.BoolRef] = []
        link = m.link
        if m.role == "terminate":
            for c, e in m.parts:
                en, ch, _ = self._edge(c, e, None, post)
                enabled += en
                choose += ch
        elif m.role in ("env-set", "pass"):
            en, ch, inputs = self._memory_effect(m, post)
            enabled += en
            choose += ch
        elif m.role in ("local", "set"):
            c, e = m.parts[0]
            incoming = None
            if e.kind == "in" and e.event is not None and e.event.type is not None:
                name = self.network.visible_name(c, e.event.name)
                incoming, dom = self._input(names.input_value(name), e.event, name)
                choose += dom
                inputs += [term for _, term in leaves(incoming)]
            en, ch, _ = self._edge(c, e, incoming, post, name if incoming is not None else None)
            enabled += en
            choose += ch
        elif m.role == "sync":
            (a, ea), (b, eb) = m.parts
            out_first = ea.kind == "out" or eb.kind != "out"
            (s, es), (r, er) = ((a, ea), (b, eb)) if out_first else ((b, eb), (a, ea))
            en1, ch1, sent = self._edge(s, es, None, post)
            en2, ch2, sent2 = self._edge(r, er, sent, post)
            enabled += en1 + en2
            choose += ch1 + ch2
            if sent is not None and sent2 is not None:
                enabled.append(equal(sent, sent2))
        elif m.role in ("write", "read"):
            assert link is not None
            c, e = m.parts[0]
            buffer = self._buffer(link)
            if m.role == "write":
                en, ch, sent = self._edge(c, e, None, post)
                post[names.buffer_full(link.index)] = z3.BoolVal(True)
                if sent is not None:
                    self._write(link, sent, post)
            else:
                en, ch, _ = self._edge(c, e, buffer, post)
                en.append(self.cur[names.buffer_full(link.index)])  # type: ignore[arg-type]
                post[names.buffer_full(link.index)] = z3.BoolVal(False)
            enabled += en
            choose += ch
        elif m.role == "env-write":
            assert link is not None and isinstance(link.sender, External)
            post[names.buffer_full(link.index)] = z3.BoolVal(True)
            if link.sender.event.type is not None:
                value, dom = self._input(names.input_value(link.sender.name), link.sender.event, link.sender.name)
                choose += dom
                inputs += [term for _, term in leaves(value)]
                self._write(link, value, post)
        else:  # env-read
            assert link is not None
            enabled.append(self.cur[names.buffer_full(link.index)])  # type: ignore[arg-type]
            post[names.buffer_full(link.index)] = z3.BoolVal(False)
        self._restart_trigger_deadlines(post)
        return _Effect(enabled, choose, post, inputs, [])

    def _restart_trigger_deadlines(self, post: dict[str, z3.ExprRef]) -> None:
        """A trigger deadline's count restarts whenever its condition is false (docs/semantics.md
        §4.6), whatever step made it so: a step from a configuration where it is false leaves the
        count 0, so that it is 0 when the condition next holds (a tock resets it too)."""
        for c, comp in enumerate(self.components):
            for td in comp.automaton.trigger_deadlines:
                if td.condition is not None:
                    name = names.armed(comp.name, td.transition)
                    post[name] = z3.If(self.armed(c, td), post.get(name, self.cur[name]), 0)  # type: ignore[assignment]

    def _buffer(self, link: Link) -> Value | None:
        t = _end_event(link).type
        return None if t is None else self.value(names.buffer_value(link.index), t)

    def _set_unset(self, c: int, key: int, path: str, chosen: Callable[[str], z3.BoolRef],
                   flags: dict[int, dict[str, z3.BoolRef]], post: dict[str, z3.ExprRef]) -> None:
        """After a step writes the part at `path` of variable `key`: the `unset` flag of each
        function-typed part within it is `chosen(its path within the value written)`, for the rest
        of the step and after it."""
        base = self.slots[c][key][0]
        for part, flag in self.unset.get(base, {}).items():
            if part == path or part.startswith(f"{path}.") or not path:
                flags[key][part] = post[flag] = chosen(part[len(path):])

    def _write(self, link: Link, value: Value, post: dict[str, z3.ExprRef]) -> None:
        for path, term in leaves(value):
            post[names.buffer_value(link.index) + path] = term

    def _tock_post(self) -> dict[str, z3.ExprRef]:
        f = self.cur
        post: dict[str, z3.ExprRef] = {}
        for c, comp in enumerate(self.components):
            for clock in comp.automaton.clocks:
                name = names.clock(comp.name, clock)
                post[name] = f[name] + 1  # type: ignore[operator]
            w = f[names.wait(comp.name)]
            post[names.wait(comp.name)] = z3.If(self.located(c, comp.automaton.waiting), w - 1, w)  # type: ignore[operator]
            if comp.automaton.threaded:
                w = f[names.wait(comp.name, 1)]
                post[names.wait(comp.name, 1)] = z3.If(self.located(c, comp.automaton.during_waiting), w - 1, w)  # type: ignore[operator]
            d = f[names.deadline(comp.name)]
            post[names.deadline(comp.name)] = z3.If(self.located(c, comp.automaton.deadlined), d - 1, d)  # type: ignore[operator]
            for td in comp.automaton.trigger_deadlines:
                name = names.armed(comp.name, td.transition)
                post[name] = z3.If(self.armed(c, td), f[name] + 1, 0)  # type: ignore[operator]
        return post

    # ------------------------------------------------------------ predicates on the configuration before the step

    def armed(self, c: int, td: TriggerDeadline) -> z3.BoolRef:
        """The source of a deadline transition is stable and its condition true."""
        located = self.located(c, td.armed)
        return located if td.condition is None else z3.And(located, self._deadline_scalar(c, td.condition))

    def _deadline_scalar(self, c: int, e: ast.Expr) -> z3.ExprRef:
        """A trigger deadline's condition or bound, read in the configuration before each step."""
        guards: list[z3.BoolRef] = []
        value = self.evaluator(c, guards=guards).scalar(e)
        if guards:  # they would be the tock's conditions, which the deadline's counting does not carry
            raise Unsupported(e.pos, _DEADLINE_APPLIES)
        return value

    def located(self, c: int, locations: frozenset[int]) -> z3.BoolRef:
        """Component c is at one of `locations`."""
        loc = self.loc(c)
        return z3.Or([loc == x for x in sorted(locations)]) if locations else z3.BoolVal(False)

    def halted(self) -> z3.BoolRef:
        """The element has terminated: its machines terminate together (docs/semantics.md §4.4, §5.6)."""
        return self.once("halted", lambda: z3.Or([self.located(c, comp.automaton.terminated)
                                                  for c, comp in enumerate(self.components)]))

    def enabled(self, m: Move) -> z3.BoolRef:
        """Move m is possible; for a visible input, for some value the environment may offer."""
        eff = self.effect(m)
        if m.role == "env-set":  # every type has a value within its ranges: no quantifier needed
            return z3.And(eff.enabled)
        if eff.chosen:
            if eff.side:  # the function axioms must hold at every value, not only at the one chosen
                self.side.append(z3.ForAll(eff.chosen, z3.And(eff.side)))
            return z3.Exists(eff.chosen, z3.And(eff.enabled + eff.choose))
        return z3.And(eff.enabled)

    def once(self, what: str, build: Callable[[], z3.BoolRef]) -> z3.BoolRef:
        """`build()`, made the first time `what` is asked for."""
        if what not in self._built:
            self._built[what] = build()
        return self._built[what]

    def visible(self) -> z3.BoolRef:
        """The template step is a visible event or `tock` (not an internal step, nor a hidden `tock`)."""
        shown = [m for m in self.moves if m.kind != "internal" and not (m.kind == "tock" and self.tock_hidden)]
        return z3.Or([self.act == m.index for m in shown] or [z3.BoolVal(False)])

    def event_offered(self) -> z3.BoolRef:
        """Some visible event other than tock is possible."""
        return self.once("event", lambda: z3.Or([self.enabled(m) for m in self.moves if m.kind == "event"]
                                                or [z3.BoolVal(False)]))

    def internal_enabled(self) -> z3.BoolRef:
        """Some internal step is possible (internal steps choose no values)."""
        return self.once("internal", lambda: z3.Or([self.enabled(m) for m in self.moves if m.kind == "internal"]
                                                   or [z3.BoolVal(False)]))

    def tock_enabled(self) -> z3.BoolRef:
        """Time may pass: maximal progress, urgent calls, deadlines, termination (docs/semantics.md §3.3)."""
        return self.once("tock", self._tock_enabled)

    def _tock_enabled(self) -> z3.BoolRef:
        if not self.network.timed:  # RoboTool's untimed semantics has no tock (docs/semantics.md §7.11)
            return z3.BoolVal(False)
        cs = [z3.Not(self.halted()), z3.Not(self.internal_enabled())]
        f = self.cur
        for c, comp in enumerate(self.components):
            cs.append(z3.Not(self.located(c, comp.automaton.urgent | self._writing[c])))
            cs.append(z3.Implies(self.located(c, comp.automaton.deadlined), f[names.deadline(comp.name)] > 0))
            for td in comp.automaton.trigger_deadlines:
                bound = self._deadline_scalar(c, td.bound)
                cs.append(z3.Not(z3.And(self.armed(c, td), f[names.armed(comp.name, td.transition)] >= bound)))
        return z3.And(cs)

    # ------------------------------------------------------------ formulas

    def init(self) -> z3.BoolRef:
        """The initial configuration (and the constants' values or ranges), over `cur`."""
        f = self.cur
        cs = [*self.constraints, f[names.PREVIOUS] == -1]
        for comp in self.components:
            cs += [f[names.location(comp.name)] == 0, f[names.wait(comp.name)] == 0,
                   f[names.deadline(comp.name)] == 0]
            if comp.automaton.threaded:
                cs.append(f[names.wait(comp.name, 1)] == 0)
            cs += [f[names.clock(comp.name, clock)] == 0 for clock in comp.automaton.clocks]
            cs += [f[names.armed(comp.name, td.transition)] == 0 for td in comp.automaton.trigger_deadlines]
        cs += [f[flag] == z3.BoolVal(self.unset_at_start[base]) for base, flags in self.unset.items()
               for flag in flags.values()]
        for base, (t, initial, c, key) in self.initial.items():
            value = self.value(base, t)
            if initial is not None:
                cs += initially(value, t, initial, self.evaluator(c), self.ranges, key)
            else:  # ranges on variables are kept under the declaration's key (model/config.py)
                cs += domain(value, t, self.ranges, key)
        for link in self.network.links:
            if link.asynchronous:
                cs.append(z3.Not(f[names.buffer_full(link.index)]))
        for cp in self.network.copies.values():
            if cp.stateful:
                cs.append(f[names.next_copy(cp.key)] == (0 if cp.start is not None else len(cp.readers)))
            if cp.start is not None:
                cs += initially(self._passing(cp), cp.variable.type, cp.start, self.evaluator(cp.readers[0]),
                                self.ranges, declaration_key(cp.variable))
        cs += [ext.init(self) for ext in self.extensions]
        return z3.And(cs)

    def invariants(self) -> list[z3.BoolRef]:
        """What holds in every configuration whatever the history: the constants' constraints."""
        return list(self.constraints)

    def trans(self) -> z3.BoolRef:
        """The template step from `cur` to `nxt`: the move that `act` names, and every extension's step."""
        return self.once("trans", lambda: z3.And([self._network_step(), *(ext.step(self) for ext in self.extensions)]))

    def _network_step(self) -> z3.BoolRef:
        s, t = self.cur, self.nxt
        act = self.act
        cs = [act >= 0, act <= self.TOCK, t[names.PREVIOUS] == act]
        if self.ordered():
            cs += self._in_order()
        changes: dict[str, list[tuple[z3.BoolRef, z3.ExprRef]]] = {}
        for m in self.moves:
            taken = act == m.index
            eff = self.effect(m)
            cs.append(z3.Implies(taken, z3.And(eff.enabled + eff.choose)))
            for name, term in eff.post.items():
                if not term.eq(s[name]):
                    changes.setdefault(name, []).append((taken, term))
        for name, old in s.items():
            if name in self.extension_slots or name == names.PREVIOUS:
                continue
            new = old
            for taken, term in changes.get(name, []):
                new = z3.If(taken, term, new)
            cs.append(t[name] == new)
        return z3.And(cs)


    # ------------------------------------------------------------ independent internal steps in one order

    def ordered(self) -> bool:
        """Whether independent internal steps are taken in one order only (partial-order reduction).

        Two internal moves are independent when neither writes what the other reads or writes:
        taking them in either order leaves the same configuration after both, and neither enables
        or disables the other.  So every run can be rearranged, step count and visible events
        unchanged, into one where an internal move never directly follows an independent internal
        move of a higher index; only such runs are unrolled.  Targets read a configuration and the
        visible events before it, so they are reached at the same depth as before; an extension
        that watches configurations between steps (a lasso) turns the reduction off."""
        return not any(getattr(ext, "order_sensitive", False) for ext in self.extensions)

    def _in_order(self) -> list[z3.BoolRef]:
        internal = [m for m in self.moves if m.kind == "internal"]
        touched = {m.index: self._footprint(m) for m in internal}
        prev = self.cur[names.PREVIOUS]
        cs = []
        for later in internal:
            reads, writes = touched[later.index]
            earlier = [m.index for m in internal if m.index > later.index
                       and not (touched[m.index][1] & (reads | writes)) and not (writes & touched[m.index][0])]
            if earlier:
                cs.append(z3.Implies(self.act == later.index, z3.And([prev != i for i in earlier])))
        return cs

    def footprint(self, m: Move) -> tuple[set[str], set[str]] | None:
        """What move m reads and writes (not counting that every move reads `halted()`, which a
        termination writes); None for `tock`, which touches every machine, and for the
        environment's side of a buffer."""
        if m.kind == "tock" or not m.parts:
            return None
        eff = self.effect(m)
        if not eff.enabled or not eff.enabled[0].eq(z3.Not(self.halted())):
            return None
        return self._footprint(m)

    def _footprint(self, m: Move) -> tuple[set[str], set[str]]:
        """The scalars a move reads and those it writes.  Not reading `halted()`: only the element's
        `terminate` changes it (internal in a module), and that move writes every machine's location,
        so every other move depends on it anyway."""
        eff = self.effect(m)
        assert eff.enabled and eff.enabled[0].eq(z3.Not(self.halted())), "the first condition is 'not halted'"
        slot_of = {self.cur[n].get_id(): n for n in self.sorts}
        writes = {n for n, term in eff.post.items() if not term.eq(self.cur[n])}
        reads: set[str] = set()
        seen: set[int] = set()
        stack: list[z3.ExprRef] = [*eff.enabled[1:], *eff.choose, *eff.post.values()]
        while stack:
            t = stack.pop()
            if t.get_id() in seen:
                continue
            seen.add(t.get_id())
            if t.get_id() in slot_of:
                reads.add(slot_of[t.get_id()])
            elif z3.is_app(t) and not z3.is_const(t) or z3.is_quantifier(t):
                stack += t.children()
            elif not z3.is_const(t):
                stack += t.children()
        return reads, writes


def _origins(flags: dict[int, dict[str, z3.BoolRef]]) -> dict[int, Origin | Parts]:
    """The origins of the variables with `unset` flags, for an evaluator."""
    return {key: Parts({path: Unset(flag) for path, flag in by_path.items()}) for key, by_path in flags.items()}


def _chosen_part(writer: Evaluator, value: ast.Expr, part: str) -> z3.BoolRef:
    """Whether the function at path `part` of the value `value` gives is one nobody set."""
    return _chosen(writer.origin(value, part))


def _chosen(origin: Origin) -> z3.BoolRef:
    """Whether a function of this origin is one nobody set (the value of an `unset` flag)."""
    if isinstance(origin, Unset):
        return origin.flag
    return z3.BoolVal(origin == CHOSEN)


def _end_event(link: Link) -> ast.Event:
    return link.receiver.event if isinstance(link.receiver, (Port, External)) else link.sender.event


def _set_field(record: Value, path: tuple[str, ...], new: Value) -> Value:
    assert isinstance(record, dict)
    copy = dict(record)
    head, rest = path[0], path[1:]
    copy[head] = _set_field(copy[head], rest, new) if rest else new
    return copy


def check_encodable(network: Network) -> None:
    """Raise `Unsupported` for string-typed events, which the encoding does not handle."""
    for comp in network.components:
        for e in comp.machine.events:
            if e.type == ast.STRING:
                raise Unsupported(e.pos, "string events are not encoded yet")


_DEADLINE_APPLIES = ("a function value applied in a trigger deadline's condition or bound is not encoded yet (that its "
                     "result is in its type would be a condition of each tock)")


def _writes(e: Edge) -> list[ast.Variable]:
    """The variables edge e writes: those it assigns and the one its input binds."""
    return [a.variable for a in e.updates] + ([e.binds] if e.binds is not None else [])
