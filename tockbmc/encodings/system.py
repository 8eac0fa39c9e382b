"""The symbolic transition system of a network of machines, unrolled step by step in Z3.

A configuration is a flat set of named scalars: per machine its location,
variables, clocks and `wait`/deadline counters; the shared variables; per
asynchronous link its buffer.  A step is one `Move` (`semantics.md` §2): an
internal step, a visible event or `tock`.  Step `i` picks the move `act@i`;
`step(i)` relates the configurations at `i` and `i + 1`, each scalar's next
value being an if-then-else over the moves that change it, so one constraint
per scalar is written rather than a frame per move.  Names follow pySMT's
`at_time` convention: `x@i` is `x` at step `i`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Protocol

import z3

from tockbmc.encodings.automaton import Edge, TriggerDeadline, Unsupported
from tockbmc.encodings.composition import External, Link, Network, Port
from tockbmc.encodings.values import Evaluator, Ranges, Value, domain, equal, fresh, leaf_type, leaves, sort_of
from tockbmc.model import ast
from tockbmc.model.config import constant_setting


@dataclass(frozen=True)
class Move:
    """One kind of step.

    kind: internal | event | tock.  `parts` are the (component, edge) pairs
    that move together: none for tock and for the environment's side of a
    buffer, one for a machine's own step, two for a synchronous connection.
    role: local | sync | write | read | env-write | env-read | tock.
    """

    index: int
    kind: str
    role: str
    parts: tuple[tuple[int, Edge], ...] = ()
    link: Link | None = None
    hidden: bool = False  # a visible event that a CSP context hides, so internal (and urgent)
    blocked: bool = False  # a visible event that a CSP context blocks (`P [| A |] SKIP`)

    @property
    def urgent(self) -> bool:
        """Internal steps and operation calls may not wait for `tock` (§2.1–2)."""
        return self.kind == "internal" or any(e.kind == "call" for _, e in self.parts)


@dataclass
class _Effect:
    enabled: list[z3.BoolRef]  # determined by the configuration and the chosen values
    choose: list[z3.BoolRef]  # constraints on values chosen in the step (inputs, wait lengths)
    post: dict[str, z3.ExprRef]  # scalars the step changes
    chosen: list[z3.ExprRef]  # the values the environment chooses (event inputs)
    side: list[z3.BoolRef]  # function axioms instantiated at the calls this step makes


class _Renaming:
    """A substitution of constants, prepared once and applied to many terms.

    `z3.substitute` re-checks every pair's sorts in Python at each call, which costs more than the
    substitution itself when the same pairs rename hundreds of terms."""

    def __init__(self, pairs: list[tuple[z3.ExprRef, z3.ExprRef]]):
        assert all(a.sort().eq(b.sort()) for a, b in pairs)
        self.size = len(pairs)
        self.old = (z3.Ast * self.size)(*(a.as_ast() for a, _ in pairs))
        self.new = (z3.Ast * self.size)(*(b.as_ast() for _, b in pairs))
        self.keep = pairs  # the arrays hold raw pointers: keep their owners alive

    def __call__(self, term: z3.ExprRef) -> z3.ExprRef:
        ctx = term.ctx
        return z3.z3._to_expr_ref(z3.Z3_substitute(ctx.ref(), term.as_ast(), self.size, self.old, self.new), ctx)


class Context(Protocol):
    """What a CSP context does to the element's events (see `encodings.process`)."""

    def status(self, label: tuple, arity: int) -> str:
        """'visible', 'hidden' or 'blocked' for the events of one channel."""
        ...

    def attach(self, system: System) -> Extension | None:
        """Extra state that runs beside the element (a specification monitor), if any."""
        ...


class Extension(Protocol):
    """Scalars and constraints added to every configuration and step."""

    def slots(self) -> dict[str, z3.SortRef]: ...

    def init(self, system: System) -> z3.BoolRef: ...

    def step(self, system: System, i: int) -> z3.BoolRef: ...


class System:
    """The unrolling of a network; configurations and inputs are created on demand."""

    def __init__(self, network: Network, ranges: Ranges, settings: dict[str, ast.Expr] | None = None,
                 tag: str = "", context: Context | None = None):
        self.network = network
        self.ranges = ranges
        self.settings = settings or {}
        self.tag = tag
        self.name = network.name
        self.components = network.components
        self.sorts: dict[str, z3.SortRef] = {}
        self.frames: list[dict[str, z3.ExprRef]] = []
        self.actions: list[z3.ArithRef] = []
        self.fresh_values: dict[str, Value] = {}
        self.side: list[z3.BoolRef] = []
        self.constraints: list[z3.BoolRef] = []  # on constants: they hold at every step
        self.constants: dict[int, dict[int, Value]] = {}  # component -> id(constant) -> value
        self.slots: dict[int, dict[int, tuple[str, ast.Type]]] = {}  # component -> id(variable) -> slot
        self.initial: dict[str, tuple[ast.Type, ast.Expr | None, int]] = {}  # slot -> (type, initial, component)
        self._effects: dict[tuple[int, int], _Effect] = {}
        self._chosen0: list[tuple[str, ast.Type]] = []  # the values chosen in step 0, in order
        self._renamed0: dict[int, int] = {}  # step -> how many of `_sides0` have been renamed to it
        self._renamings: dict[int, tuple[int, _Renaming]] = {}
        self._per_step: dict[tuple[str, int], z3.BoolRef] = {}
        self._sides0: list[z3.BoolRef] = []  # function axioms of every formula built for step 0
        self._halted: dict[int, z3.BoolRef] = {}
        self._side_seen: set[int] = set()
        self._declare()
        self.moves = self._moves()
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
        """Run extra state beside the network (before any configuration is created)."""
        assert not self.frames, "extensions are added before the unrolling starts"
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
        c, e = m.parts[0]
        if e.kind == "terminate":
            return (canonical(f"{self.name}::terminate"),), 0
        if e.kind == "call":
            assert e.operation is not None
            return (canonical(f"{self.name}::{e.operation.name}Call"),), len(e.args)
        assert e.event is not None
        name = self.network.visible_name(c, e.event.name)
        return (canonical(name), "in" if e.kind == "in" else "out"), int(e.event.type is not None)

    def label_values(self, m: Move, i: int) -> list[tuple[Value, ast.Type]]:
        """The values a visible move at step i carries, with their types."""
        if m.kind == "tock":
            return []
        if m.role in ("env-write", "env-read"):
            assert m.link is not None
            end = m.link.sender if m.role == "env-write" else m.link.receiver
            assert isinstance(end, External)
            t = end.event.type
            if t is None:
                return []
            value = (self.chosen(f"in.{end.name}", t, i) if m.role == "env-write"
                     else self.value(f"buffer{m.link.index}.value", t, i))
            return [(value, t)]
        c, e = m.parts[0]
        if e.kind == "terminate":
            return []
        ev = self.evaluator(c, i)
        if e.kind == "call":
            return [(ev.value(a), a.type) for a in e.args]
        assert e.event is not None
        t = e.event.type
        if t is None:
            return []
        if e.kind == "in":
            name = self.network.visible_name(c, e.event.name)
            return [(self.chosen(f"in.{name}", t, i), t)]
        assert e.value is not None
        return [(ev.value(e.value), t)]

    # ------------------------------------------------------------ declarations

    def _slot(self, name: str, sort: z3.SortRef) -> str:
        self.sorts[name] = sort
        return name

    def _scalars(self, base: str, t: ast.Type) -> None:
        for path, _ in leaves(fresh("probe", t)):
            self._slot(base + path, sort_of(leaf_type(t, path)))

    def _declare(self) -> None:
        shared_consts: dict[str, Value] = {}
        for c, comp in enumerate(self.components):
            m = comp.machine
            self._slot(f"{comp.name}.loc", z3.IntSort())
            self._slot(f"{comp.name}.wait", z3.IntSort())
            self._slot(f"{comp.name}.deadline", z3.IntSort())
            for clock in comp.automaton.clocks:
                self._slot(f"{comp.name}.clock.{clock}", z3.IntSort())
            for td in comp.automaton.trigger_deadlines:
                self._slot(f"{comp.name}.armed.{td.transition}", z3.IntSort())
            slots: dict[int, tuple[str, ast.Type]] = {}
            consts: dict[int, Value] = {}
            own = [("", v) for v in (*m.variables, *m.interface_variables)]
            for scope, v in (*own, *comp.automaton.extra_variables):
                if v.type == ast.STRING:
                    raise Unsupported(v.pos, "string variables are not encoded yet")
                # A required variable is shared under its scope key; anything else is the machine's own.
                key = self.network.scopes.get((c, v.name)) if v.kind == "interface" else None
                decl = self.network.shared.get(key, v) if key is not None else v
                if v.constant and v.kind != "parameter":  # parameters of inlined operations are assigned
                    if key is not None and key in shared_consts:
                        consts[id(v)] = shared_consts[key]
                        continue
                    # an inlined operation's constant is its own: opB's x2 is not opC's x2
                    own_name = f"{comp.name}::{scope}().{v.name}" if scope else f"{comp.name}::{v.name}"
                    consts[id(v)] = self._constant(v, decl, key or own_name)
                    if key is not None:
                        shared_consts[key] = consts[id(v)]
                    continue
                base = key or (f"{comp.name}.{scope}().{v.name}" if scope else f"{comp.name}.{v.name}")
                slots[id(v)] = (base, v.type)
                if base not in self.initial:
                    self._scalars(base, v.type)
                    self.initial[base] = (v.type, decl.initial, c)
            self.slots[c] = slots
            self.constants[c] = consts
        for link in self.network.links:
            if link.asynchronous:
                self._slot(f"buffer{link.index}.full", z3.BoolSort())
                t = _end_event(link).type
                if t is not None:
                    self._scalars(f"buffer{link.index}.value", t)

    def _constant(self, v: ast.Variable, decl: ast.Variable, name: str) -> Value:
        value = fresh(f"{self.tag}{name}", v.type)
        given = constant_setting(self.settings, v, decl)  # keyed by declaration (model/config.py)
        expr = given if given is not None else decl.initial
        if expr is not None:
            self.constraints.append(equal(value, Evaluator({}, {}, self.side).value(expr)))
        else:
            self.constraints += domain(value, v.type, self.ranges, name)
        return value

    # ------------------------------------------------------------ symbols

    def frame(self, i: int) -> dict[str, z3.ExprRef]:
        """The configuration at step i, as scalars by name."""
        while len(self.frames) <= i:
            k = len(self.frames)
            self.frames.append({n: z3.Const(f"{self.tag}{n}@{k}", s) for n, s in self.sorts.items()})
        return self.frames[i]

    def action(self, i: int) -> z3.ArithRef:
        """The index of the move taken at step i."""
        while len(self.actions) <= i:
            self.actions.append(z3.Int(f"{self.tag}act@{len(self.actions)}"))
        return self.actions[i]

    def chosen(self, name: str, t: ast.Type, i: int) -> Value:
        """A value chosen during step i (an input, a wait length), created once."""
        key = f"{name}@{i}"
        if key not in self.fresh_values:
            if i == 0:
                self._chosen0.append((name, t))
            self.fresh_values[key] = fresh(f"{self.tag}{key}", t)
        return self.fresh_values[key]

    def loc(self, c: int, i: int) -> z3.ArithRef:
        return self.frame(i)[f"{self.components[c].name}.loc"]  # type: ignore[return-value]

    def value(self, base: str, t: ast.Type, i: int) -> Value:
        f = self.frame(i)
        if isinstance(t, ast.RecordType):
            return {fd.name: self.value(f"{base}.{fd.name}", fd.type, i) for fd in t.fields}
        return f[base]

    def evaluator(self, c: int, i: int, extra: dict[int, Value] | None = None) -> Evaluator:
        env = {key: self.value(base, t, i) for key, (base, t) in self.slots[c].items()}
        if extra:
            env.update(extra)
        name = self.components[c].name
        clocks = {clock: self.frame(i)[f"{name}.clock.{clock}"] for clock in self.components[c].automaton.clocks}
        return Evaluator(env, self.constants[c], self.side, clocks)

    # ------------------------------------------------------------ moves

    def _moves(self) -> list[Move]:
        moves: list[Move] = []

        def add(kind: str, role: str, parts: tuple[tuple[int, Edge], ...] = (), link: Link | None = None) -> None:
            moves.append(Move(len(moves), kind, role, parts, link))

        for c, comp in enumerate(self.components):
            for e in comp.automaton.edges:
                if e.kind in ("tau", "wait"):
                    add("internal", "local", ((c, e),))
                elif e.kind in ("call", "terminate"):
                    add("event", "local", ((c, e),))
                else:
                    assert e.event is not None
                    found = self.network.route(c, e.event.name)
                    if found is None:
                        add("event", "local", ((c, e),))
                        continue
                    link, role = found
                    other = link.receiver if role == "sender" else link.sender
                    if isinstance(other, External) and not link.asynchronous:
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
                        if ea.kind == eb.kind == "in" and a.event.type is not None:
                            raise Unsupported(link.pos, f"both ends of the connection on '{a.event.name}' "
                                                        "receive; neither sends a value")
                        add("internal", "sync", ((a.component, ea), (b.component, eb)), link)
            elif link.asynchronous and isinstance(link.sender, External):
                add("event", "env-write", (), link)
            elif link.asynchronous and isinstance(link.receiver, External):
                add("event", "env-read", (), link)
        add("tock", "tock")
        return moves

    # ------------------------------------------------------------ effects of one move

    def _edge(self, c: int, e: Edge, i: int, incoming: Value | None, post: dict[str, z3.ExprRef]
              ) -> tuple[list[z3.BoolRef], list[z3.BoolRef], Value | None]:
        """Component c takes edge e at step i, receiving `incoming` on an input.

        Returns (conditions fixed by the configuration, constraints on chosen
        values, the value sent on an output); writes the changed scalars into `post`.
        """
        comp = self.components[c]
        f = self.frame(i)
        enabled: list[z3.BoolRef] = [self.loc(c, i) == e.source]
        choose: list[z3.BoolRef] = []
        bound: dict[int, Value] = {}
        if incoming is not None and e.binds is not None:
            bound[id(e.binds)] = incoming
        ev = self.evaluator(c, i, bound)
        if incoming is not None and e.value is not None and e.kind == "in":
            enabled.append(equal(incoming, ev.value(e.value)))
        enabled += [ev.scalar(g) for g in e.guard]
        for group in e.negated_guards:
            enabled.append(z3.Not(z3.And([ev.scalar(g) for g in group])))
        if e.ends_wait:
            enabled.append(f[f"{comp.name}.wait"] == 0)
        sent = ev.value(e.value) if e.kind == "out" and e.value is not None else None
        # Updates in order, each reading the values the previous ones wrote.
        current = {key: self.value(base, t, i) for key, (base, t) in self.slots[c].items()}
        current.update(bound)
        for a in e.updates:
            new = Evaluator(current, self.constants[c], self.side, ev.clocks).value(a.value)
            key = id(a.variable)
            current[key] = _set_field(current[key], a.fields, new) if a.fields else new
        for v in e.havoc:  # any value of its type and range (an operation's fresh variable)
            base, t = self.slots[c][id(v)]
            value = self.chosen(f"{base}.fresh", t, i)
            choose += domain(value, t, self.ranges, base)
            current[id(v)] = value
        for key, (base, _t) in self.slots[c].items():
            if key in bound or any(id(a.variable) == key for a in e.updates) or any(id(v) == key for v in e.havoc):
                for path, term in leaves(current[key]):
                    post[base + path] = term
        if e.target != e.source:
            post[f"{comp.name}.loc"] = z3.IntVal(e.target)
        for clock in e.resets:
            post[f"{comp.name}.clock.{clock}"] = z3.IntVal(0)
        if e.kind == "wait":
            length = self.chosen(f"{comp.name}.wait_length", ast.INT, i)
            low, high = ev.scalar(e.wait_low), ev.scalar(e.wait_high)  # type: ignore[arg-type]
            enabled.append(low <= high)
            choose += [length >= low, length <= high]  # type: ignore[list-item, operator]
            post[f"{comp.name}.wait"] = length  # type: ignore[assignment]
        if e.deadline is not None:
            post[f"{comp.name}.deadline"] = ev.scalar(e.deadline)  # type: ignore[assignment]
        for td in comp.automaton.trigger_deadlines:
            if e.target not in td.armed or td.source in e.exits:
                post[f"{comp.name}.armed.{td.transition}"] = z3.IntVal(0)
        return enabled, choose, sent

    def _input(self, name: str, event: ast.Event, i: int, path: str) -> tuple[Value, list[z3.BoolRef]]:
        """A value the environment supplies on `event` at step i, within its type and ranges."""
        assert event.type is not None
        value = self.chosen(name, event.type, i)
        return value, domain(value, event.type, self.ranges, path)

    def effect(self, m: Move, i: int) -> _Effect:
        """What taking move m at step i requires and changes."""
        key = (m.index, i)
        if key not in self._effects:
            if i == 0:
                before = len(self.side)
                eff = self._effect(m, i)
                eff.side = self.side[before:]
                self._sides0 += eff.side
            else:  # step 0's, renamed: building terms in Python costs far more than Z3's substitution
                template, rename = self.effect(m, 0), self._renaming(i)
                eff = _Effect([rename(c) for c in template.enabled],
                              [rename(c) for c in template.choose],
                              {n: rename(t) for n, t in template.post.items()},
                              [rename(c) for c in template.chosen],
                              [rename(c) for c in template.side])
                self._renamed_sides(i)
            self._effects[key] = eff
        return self._effects[key]

    def _renaming(self, i: int) -> _Renaming:
        """What turns a formula about step 0 (configurations 0 and 1, the values chosen in step 0)
        into the same formula about step i."""
        known = len(self._chosen0)  # a value first chosen in step 0 after the last call is renamed too
        if i not in self._renamings or self._renamings[i][0] != known:
            pairs: list[tuple[z3.ExprRef, z3.ExprRef]] = [(self.action(0), self.action(i))]
            for k in (0, 1):
                old, new = self.frame(k), self.frame(i + k)
                pairs += [(old[n], new[n]) for n in self.sorts]
            for name, t in self._chosen0[:known]:
                pairs += zip((term for _, term in leaves(self.fresh_values[f"{name}@0"])),
                             (term for _, term in leaves(self.chosen(name, t, i))))
            self._renamings[i] = known, _Renaming(pairs)
        return self._renamings[i][1]

    def _renamed_sides(self, i: int) -> None:
        """The function axioms of the step-0 formulas, renamed to step i (some formula renamed to
        step i may contain calls whose axioms were made while building another: all go, and
        `side_constraints` drops repeats).  Instances of a function's axiom at more arguments than
        needed are still true of the function, so this is sound."""
        done = self._renamed0.get(i, 0)
        if done < len(self._sides0):
            rename = self._renaming(i)
            self.side += [rename(c) for c in self._sides0[done:]]  # type: ignore[misc]
            self._renamed0[i] = len(self._sides0)

    def _effect(self, m: Move, i: int) -> _Effect:
        if m.role == "tock":
            return _Effect([self.tock_enabled(i)], [], self._tock_post(i), [], [])
        post: dict[str, z3.ExprRef] = {}
        inputs: list[z3.ExprRef] = []
        enabled: list[z3.BoolRef] = [z3.Not(self.halted(i))]
        if m.blocked:
            enabled.append(z3.BoolVal(False))
        choose: list[z3.BoolRef] = []
        link = m.link
        if m.role == "local":
            c, e = m.parts[0]
            incoming = None
            if e.kind == "in" and e.event is not None and e.event.type is not None:
                name = self.network.visible_name(c, e.event.name)
                incoming, dom = self._input(f"in.{name}", e.event, i, name)
                choose += dom
                inputs += [term for _, term in leaves(incoming)]
            en, ch, _ = self._edge(c, e, i, incoming, post)
            enabled += en
            choose += ch
        elif m.role == "sync":
            (a, ea), (b, eb) = m.parts
            out_first = ea.kind == "out" or eb.kind != "out"
            (s, es), (r, er) = ((a, ea), (b, eb)) if out_first else ((b, eb), (a, ea))
            en1, ch1, sent = self._edge(s, es, i, None, post)
            en2, ch2, sent2 = self._edge(r, er, i, sent, post)
            enabled += en1 + en2
            choose += ch1 + ch2
            if sent is not None and sent2 is not None:
                enabled.append(equal(sent, sent2))
        elif m.role in ("write", "read"):
            assert link is not None
            c, e = m.parts[0]
            buffer = self._buffer(link, i)
            if m.role == "write":
                en, ch, sent = self._edge(c, e, i, None, post)
                post[f"buffer{link.index}.full"] = z3.BoolVal(True)
                if sent is not None:
                    self._write(link, sent, post)
            else:
                en, ch, _ = self._edge(c, e, i, buffer, post)
                en.append(self.frame(i)[f"buffer{link.index}.full"])  # type: ignore[arg-type]
                post[f"buffer{link.index}.full"] = z3.BoolVal(False)
            enabled += en
            choose += ch
        elif m.role == "env-write":
            assert link is not None and isinstance(link.sender, External)
            post[f"buffer{link.index}.full"] = z3.BoolVal(True)
            if link.sender.event.type is not None:
                value, dom = self._input(f"in.{link.sender.name}", link.sender.event, i, link.sender.name)
                choose += dom
                inputs += [term for _, term in leaves(value)]
                self._write(link, value, post)
        else:  # env-read
            assert link is not None
            enabled.append(self.frame(i)[f"buffer{link.index}.full"])  # type: ignore[arg-type]
            post[f"buffer{link.index}.full"] = z3.BoolVal(False)
        return _Effect(enabled, choose, post, inputs, [])

    def _buffer(self, link: Link, i: int) -> Value | None:
        t = _end_event(link).type
        return None if t is None else self.value(f"buffer{link.index}.value", t, i)

    def _write(self, link: Link, value: Value, post: dict[str, z3.ExprRef]) -> None:
        for path, term in leaves(value):
            post[f"buffer{link.index}.value{path}"] = term

    def _tock_post(self, i: int) -> dict[str, z3.ExprRef]:
        f = self.frame(i)
        post: dict[str, z3.ExprRef] = {}
        for c, comp in enumerate(self.components):
            for clock in comp.automaton.clocks:
                post[f"{comp.name}.clock.{clock}"] = f[f"{comp.name}.clock.{clock}"] + 1  # type: ignore[operator]
            waiting = self._at(c, i, comp.automaton.waiting)
            w = f[f"{comp.name}.wait"]
            post[f"{comp.name}.wait"] = z3.If(waiting, w - 1, w)  # type: ignore[operator]
            bounded = self._at(c, i, comp.automaton.deadlined)
            d = f[f"{comp.name}.deadline"]
            post[f"{comp.name}.deadline"] = z3.If(bounded, d - 1, d)  # type: ignore[operator]
            for td in comp.automaton.trigger_deadlines:
                name = f"{comp.name}.armed.{td.transition}"
                post[name] = z3.If(self._armed(c, td, i), f[name] + 1, 0)  # type: ignore[operator]
        return post

    def _armed(self, c: int, td: TriggerDeadline, i: int) -> z3.BoolRef:
        """The source of a deadline transition is stable and its condition true."""
        cond = self.evaluator(c, i).scalar(td.condition) if td.condition is not None else z3.BoolVal(True)
        return z3.And(self._at(c, i, td.armed), cond)

    # ------------------------------------------------------------ predicates on a configuration

    def _at(self, c: int, i: int, locations: frozenset[int]) -> z3.BoolRef:
        loc = self.loc(c, i)
        return z3.Or([loc == x for x in sorted(locations)]) if locations else z3.BoolVal(False)

    def halted(self, i: int) -> z3.BoolRef:
        """Some machine has terminated, so the whole network has (§2.8, §2.12)."""
        if i not in self._halted:
            self._halted[i] = z3.Or([self._at(c, i, comp.automaton.terminated)
                                     for c, comp in enumerate(self.components)])
        return self._halted[i]

    def enabled(self, m: Move, i: int) -> z3.BoolRef:
        """Move m is possible at step i; for a visible input, for some value the environment may offer."""
        eff = self.effect(m, i)
        if eff.chosen:
            if eff.side:  # the function axioms must hold at every value, not only at the one chosen
                self.side.append(z3.ForAll(eff.chosen, z3.And(eff.side)))
            return z3.Exists(eff.chosen, z3.And(eff.enabled + eff.choose))
        return z3.And(eff.enabled)

    def at_step(self, what: str, i: int, build: Callable[[int], z3.BoolRef]) -> z3.BoolRef:
        """`build(i)`, made once for step 0 and renamed for the others (see `effect`)."""
        key = (what, i)
        if key not in self._per_step:
            if i == 0:
                before = len(self.side)
                self._per_step[key] = build(0)
                self._sides0 += self.side[before:]
            else:
                term, renaming = self.at_step(what, 0, build), self._renaming(i)
                self._per_step[key] = renaming(term)  # type: ignore[assignment]
                self._renamed_sides(i)
        return self._per_step[key]

    def visible(self, i: int) -> z3.BoolRef:
        """Step i is a visible event or `tock` (not an internal step, nor a hidden `tock`)."""
        act = self.action(i)
        shown = [m for m in self.moves if m.kind != "internal" and not (m.kind == "tock" and self.tock_hidden)]
        return z3.Or([act == m.index for m in shown] or [z3.BoolVal(False)])

    def event_offered(self, i: int) -> z3.BoolRef:
        """Some visible event other than tock is possible at step i."""
        return self.at_step("event", i, self._event_offered)

    def internal_enabled(self, i: int) -> z3.BoolRef:
        """Some internal step is possible at step i (internal steps choose no values)."""
        return self.at_step("internal", i, self._internal_enabled)

    def tock_enabled(self, i: int) -> z3.BoolRef:
        """Time may pass at step i: maximal progress, urgent calls, deadlines, termination (§2.1)."""
        return self.at_step("tock", i, self._tock_enabled)

    def _event_offered(self, i: int) -> z3.BoolRef:
        return z3.Or([self.enabled(m, i) for m in self.moves if m.kind == "event"] or [z3.BoolVal(False)])

    def _internal_enabled(self, i: int) -> z3.BoolRef:
        return z3.Or([self.enabled(m, i) for m in self.moves if m.kind == "internal"] or [z3.BoolVal(False)])

    def _tock_enabled(self, i: int) -> z3.BoolRef:
        cs = [z3.Not(self.halted(i)), z3.Not(self.internal_enabled(i))]
        f = self.frame(i)
        for c, comp in enumerate(self.components):
            cs.append(z3.Not(self._at(c, i, comp.automaton.urgent)))
            cs.append(z3.Implies(self._at(c, i, comp.automaton.deadlined), f[f"{comp.name}.deadline"] > 0))
            for td in comp.automaton.trigger_deadlines:
                bound = self.evaluator(c, i).scalar(td.bound)
                cs.append(z3.Not(z3.And(self._armed(c, td, i), f[f"{comp.name}.armed.{td.transition}"] >= bound)))
        return z3.And(cs)

    # ------------------------------------------------------------ formulas

    def init(self) -> z3.BoolRef:
        """The initial configuration (and the constants' values or ranges)."""
        f = self.frame(0)
        cs = list(self.constraints)
        for comp in self.components:
            cs += [f[f"{comp.name}.loc"] == 0, f[f"{comp.name}.wait"] == 0, f[f"{comp.name}.deadline"] == 0]
            cs += [f[f"{comp.name}.clock.{clock}"] == 0 for clock in comp.automaton.clocks]
            cs += [f[f"{comp.name}.armed.{td.transition}"] == 0 for td in comp.automaton.trigger_deadlines]
        for base, (t, initial, c) in self.initial.items():
            value = self.value(base, t, 0)
            if initial is not None:
                cs.append(equal(value, self.evaluator(c, 0).value(initial)))
            else:
                cs += domain(value, t, self.ranges, base.replace(".", "::", 1) if "." in base else base)
        for link in self.network.links:
            if link.asynchronous:
                cs.append(z3.Not(f[f"buffer{link.index}.full"]))
        cs += [ext.init(self) for ext in self.extensions]
        return z3.And(cs)

    def invariants(self) -> list[z3.BoolRef]:
        """What holds in every configuration whatever the history: the constants' constraints."""
        return list(self.constraints)

    def step(self, i: int) -> z3.BoolRef:
        """One step from i to i + 1: the move that `act@i` names."""
        return z3.And([self.at_step("step", i, self._network_step), *(ext.step(self, i) for ext in self.extensions)])

    def _network_step(self, i: int) -> z3.BoolRef:
        s, t = self.frame(i), self.frame(i + 1)
        act = self.action(i)
        cs = [act >= 0, act <= self.TOCK]
        changes: dict[str, list[tuple[z3.BoolRef, z3.ExprRef]]] = {}
        for m in self.moves:
            taken = act == m.index
            eff = self.effect(m, i)
            cs.append(z3.Implies(taken, z3.And(eff.enabled + eff.choose)))
            for name, term in eff.post.items():
                if not term.eq(s[name]):
                    changes.setdefault(name, []).append((taken, term))
        for name, old in s.items():
            if name in self.extension_slots:
                continue
            new = old
            for taken, term in changes.get(name, []):
                new = z3.If(taken, term, new)
            cs.append(t[name] == new)
        return z3.And(cs)

    def side_constraints(self) -> list[z3.BoolRef]:
        """Constraints added by calls of uninterpreted functions; collect after building formulas."""
        out = [c for c in self.side if c.get_id() not in self._side_seen]
        self._side_seen.update(c.get_id() for c in out)
        self.side[:] = []
        return out


def canonical(name: str) -> str:
    """CSP names compare by their last two parts (`pkg::EXAX::move` is `EXAX::move`)."""
    return "::".join(name.split("::")[-2:])


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
