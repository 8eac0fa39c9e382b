"""Flatten a machine, controller or module into a network of machine automata joined by links.

`docs/semantics.md` §5: a connection between two machines is a hidden joint
step (synchronous) or a one-place overwriting buffer (`_async`); a connection
to the enclosing controller's or module's own event, or to the platform, is a
visible event named after that outer element.  Shared variables are the
variables a controller declares or a platform provides, and that machines
require by name.  The network is plain data; `system.py` turns it into Z3.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from tockbmc.encodings import names
from tockbmc.encodings.automaton import Automaton, compile_machine
from tockbmc.model import ast
from tockbmc.model.errors import Unsupported
from tockbmc.model.readings import given_initial
from tockbmc.model.untimed import untimed


@dataclass(frozen=True)
class Port:
    """Event `event` of component number `component`."""

    component: int
    event: ast.Event


@dataclass(frozen=True)
class External:
    """The environment's end of a link: a visible event such as `Ctrl::e` or `Mod::e`."""

    name: str
    event: ast.Event


@dataclass(frozen=True)
class Link:
    """A connection, flattened: `sender` outputs what `receiver` inputs."""

    index: int
    sender: Port | External
    receiver: Port | External
    asynchronous: bool
    pos: ast.Pos

    def port_of(self, component: int, event: str) -> str | None:
        """'sender' or 'receiver' when this link ends at that component's event."""
        for role, end in (("sender", self.sender), ("receiver", self.receiver)):
            if isinstance(end, Port) and end.component == component and end.event.name == event:
                return role
        return None


@dataclass(frozen=True)
class Component:
    """One machine of the network; `name` is how traces refer to it."""

    name: str
    automaton: Automaton
    instance: tuple[str, ...] = ()  # instance names from the element checked (model/config.py `instance_key`)

    @property
    def machine(self) -> ast.StateMachine:
        return self.automaton.machine


@dataclass(frozen=True)
class Copies:
    """RoboTool's memory model for one shared variable (docs/semantics.md §5.5).

    Each machine that requires the variable keeps a copy of it (`readers`, in the order RoboTool's
    memory passes a value on).  A machine's write changes its own copy at once and, where the
    memory is inside the element (`passes_writes`), is passed on to every copy, the writer's
    included, one hidden step each; the memory takes no other write until it has passed one on.
    The write is the visible event `written` (RoboTool's `set_x`) where RoboTool leaves it
    visible; the environment writes the variable by the visible event `external` (`set_EXT_x`)
    where it can.  `start` is the initial value the model gives the variable, which the memory
    passes on at the start: the copies start at their type's default, as RoboTool's do."""

    key: str
    variable: ast.Variable
    readers: tuple[int, ...]
    passes_writes: bool
    written: str | None = None
    external: str | None = None
    start: ast.Expr | None = None
    direct: bool = False  # the environment writes the one copy at once (a machine checked on its own)

    @property
    def stateful(self) -> bool:
        """Whether the memory holds a value being passed on (`names.passing`); else a write
        reaches no copy but the writer's and the environment's reaches the one copy at once."""
        return (self.start is not None or self.passes_writes and len(self.readers) > 1
                or self.external is not None and not self.direct)


@dataclass(frozen=True)
class Network:
    """The element checked: its machines, its links, and what the machines share."""

    name: str  # the element's name: visible calls and `terminate` are named after it
    components: tuple[Component, ...]
    links: tuple[Link, ...]
    # Shared variables and constants by scope key (`Ctrl.v` for a controller's, `v` for a platform's),
    # and, per (component, name) of a variable the machine requires, the key it shares.
    shared: dict[str, ast.Variable] = field(default_factory=dict)
    scopes: dict[tuple[int, str], str] = field(default_factory=dict)
    # The shared variables whose machines keep copies (RoboTool's memory model), by scope key.
    copies: dict[str, Copies] = field(default_factory=dict)
    # False in RoboTool's untimed semantics (docs/semantics.md §7.11): the machines are the model
    # rewritten by `model.untimed` and `tock` is never possible.
    timed: bool = True
    # A module's `terminate` is hidden (RoboTool's module ends `\ {|terminate|}`): it terminates
    # with an internal step, and its trace ends in ✓ alone (docs/semantics.md §5.6).
    hidden_termination: bool = False
    qname: str = ""  # the element's qualified name (results name its instances' constants from it)

    def route(self, component: int, event: str) -> tuple[Link, str] | None:
        """The link that carries a component's event, and which end the component is."""
        for link in self.links:
            role = link.port_of(component, event)
            if role is not None:
                return link, role
        return None

    def visible_name(self, component: int, event: str) -> str:
        """FDR's name for a component's event that the environment sees directly."""
        found = self.route(component, event)
        if found is not None:
            link, role = found
            other = link.receiver if role == "sender" else link.sender
            if isinstance(other, External):
                return other.name
            # a machine-to-machine link joins only the sender's output with the receiver's input; the
            # event used the other way round is not joined, and is seen as an unconnected one
        return f"{self.components[component].machine.name}::{event}"


class _Flattener:
    def __init__(self, name: str):
        self.name = name
        self.components: list[Component] = []
        self.links: list[Link] = []
        self.shared: dict[str, ast.Variable] = {}
        self.scopes: dict[tuple[int, str], str] = {}
        self.platform: set[str] = set()
        # who keeps each shared variable's memory: "controller", "platform" (a variable of an
        # interface the platform provides: "provided"); a key not listed is required from outside
        # the element, named after `outside[key]`
        self.keeper: dict[str, str] = {}
        self.outside: dict[str, str] = {}
        self.alone = False  # a machine checked on its own
        # (component, event) of a machine's event on a bidirectional boundary connection: listed
        # as both an input and an output of its controller, and joined to the outside once
        self.both_ways: set[tuple[int, str]] = set()

    def machine(self, m: ast.StateMachine, instance: str,
                defined: dict[str, ast.OperationDef] | None = None, path: tuple[str, ...] = ()) -> int:
        self.components.append(Component(instance, compile_machine(m, defined), path))
        return len(self.components) - 1

    def link(self, sender: Port | External, receiver: Port | External, asynchronous: bool, pos: ast.Pos) -> None:
        for end in (sender, receiver):
            if isinstance(end, Port) and any(
                    link.port_of(end.component, end.event.name) for link in self.links):
                raise Unsupported(pos, f"event '{end.event.name}' of "
                                       f"{self.components[end.component].name} is in two connections; "
                                       "one-to-many connections are not encoded yet")
        self.links.append(Link(len(self.links), sender, receiver, asynchronous, pos))

    def share(self, variables: tuple[ast.Variable, ...], scope: str, keeper: str,
              provided: tuple[str, ...] = ()) -> None:
        for v in variables:
            key = names.shared(f"{scope}{v.name}")
            self.shared.setdefault(key, v)
            self.keeper.setdefault(key, "provided" if ast.in_interfaces(v, provided) else keeper)

    def require_alone(self, m: ast.StateMachine) -> None:
        """A machine checked on its own: each variable it requires is its own copy, which its
        environment writes (RoboTool's `M::set_EXT_x`) and its writes are visible (`M::set_x`)."""
        self.alone = True
        local = {v.name for v in m.variables if not v.constant}
        inlined = [v for scope, v in self.components[0].automaton.extra_variables
                   if not scope and not v.constant and v.name not in local]
        for v in (*m.interface_variables, *inlined):
            if v.constant or ast.in_interfaces(v, (*m.provided_interfaces, *m.used_interfaces)):
                continue
            key = names.variable(self.components[0].name, v.name)
            self.shared.setdefault(key, v)
            self.scopes[(0, v.name)] = key
            self.outside[key] = m.name

    def require(self, c: int, m: ast.StateMachine, controller: str, own: tuple[str, ...] = ()) -> None:
        """Bind the variables machine c requires to its controller's, else the platform's (docs/semantics.md §5.5).

        A variable of an interface the machine provides or uses is its own (RoboTool names a used
        interface's constant after the instance: `const_test12_ctrl0_stm_ref0_CC`), and so is one an
        operation it calls requires when the machine declares a variable of that name (test13).  One that no
        enclosing element declares is shared by the controller's machines.
        """
        # An inlined operation's required variable is the machine's own when the machine declares
        # it (it then has the machine's slot: the same name in the same scope).
        local = {v.name for v in m.variables if not v.constant}
        inlined = [v for scope, v in self.components[c].automaton.extra_variables
                   if not scope and (v.constant or v.name not in local)]
        for v in (*m.interface_variables, *inlined):
            if ast.in_interfaces(v, (*m.provided_interfaces, *m.used_interfaces)):
                continue
            key = names.shared(f"{controller}.{v.name}")
            if key not in self.shared and v.name in self.platform:
                key = names.shared(v.name)
            if key not in self.shared and not v.constant:
                # a variable of an interface the controller uses or provides is its own
                if ast.in_interfaces(v, own):
                    self.keeper[key] = "controller"
                else:
                    self.outside[key] = controller.rsplit("::", 1)[-1]
            self.shared.setdefault(key, v)
            self.scopes[(c, v.name)] = key

    def controller(self, c: ast.Controller, prefix: str, path: tuple[str, ...] = ()) -> tuple[dict[str, list[tuple[Port, bool]]],
                                                                  dict[str, list[tuple[Port, bool]]]]:
        """Add a controller's machines and internal links.

        Returns, per event of the controller, the machine ports behind it:
        (inputs: controller event → receiving ports, outputs: sending ports),
        each with whether that inner connection is asynchronous.
        """
        defined = {op.operation.name: op.operation for op in c.operations}
        names = [mi.machine.name for mi in c.machines]
        index: dict[str, int] = {}
        machines = {mi.name: mi.machine for mi in c.machines}
        self.share(c.variables, f"{prefix}{c.name}.", "controller")
        for mi in c.machines:
            label = mi.machine.name if names.count(mi.machine.name) == 1 else mi.name
            index[mi.name] = self.machine(mi.machine, f"{prefix}{label}", defined, (*path, mi.name))
            self.require(index[mi.name], mi.machine, f"{prefix}{c.name}", (*c.used_interfaces, *c.provided_interfaces))
        inputs: dict[str, list[tuple[Port, bool]]] = {}
        outputs: dict[str, list[tuple[Port, bool]]] = {}
        for conn in c.connections:
            src = index.get(conn.source)
            dst = index.get(conn.target)
            if conn.bidirectional:
                _boundary_only(conn, src is not None and dst is not None, "two machines")
            if src is not None and dst is not None:
                self.link(Port(src, conn.source_event), Port(dst, conn.target_event), conn.asynchronous, conn.pos)
            # A synchronous connection with the controller's own event joins the whole channel, both
            # directions, whichever way it is drawn (RoboTool renames `stm_ref0::e <- e`): a machine
            # that also uses the event the other way round is listed that way too.
            elif dst is not None:
                inputs.setdefault(conn.source_event.name, []).append((Port(dst, conn.target_event), conn.asynchronous))
                if not conn.asynchronous and ast.uses_event((machines[conn.target], *defined.values()),
                                                            conn.target_event.name, sends=True):
                    outputs.setdefault(conn.source_event.name, []).append((Port(dst, conn.target_event), False))
                    self.both_ways.add((dst, conn.target_event.name))
            elif src is not None:
                outputs.setdefault(conn.target_event.name, []).append((Port(src, conn.source_event), conn.asynchronous))
                if not conn.asynchronous and ast.uses_event((machines[conn.source], *defined.values()),
                                                            conn.source_event.name, sends=False):
                    inputs.setdefault(conn.target_event.name, []).append((Port(src, conn.source_event), False))
                    self.both_ways.add((src, conn.source_event.name))
            else:
                raise Unsupported(conn.pos, "a connection that joins no state machine")
        return inputs, outputs

    def expose(self, outer: str, event: ast.Event, ports: list[tuple[Port, bool]], incoming: bool,
               asynchronous: bool, pos: ast.Pos) -> None:
        """Join the machine ports behind an event to the visible event `outer::event`."""
        external = External(f"{outer}::{event.name}", event)
        for port, inner_async in ports:
            if (port.component, port.event.name) in self.both_ways:
                joined = [x for x in self.links if x.port_of(port.component, port.event.name)]
                outside = [end.name for x in joined for end in (x.sender, x.receiver) if isinstance(end, External)]
                if joined and len(outside) == len(joined):  # joined to the outside only (else: one-to-many, below)
                    if set(outside) == {external.name}:
                        continue  # joined already, the other way round: a synchronous link carries both directions
                    raise Unsupported(pos, f"the two directions of bidirectional event '{port.event.name}' of "
                                           f"{self.components[port.component].name} reach different events "
                                           f"({', '.join(sorted({*outside, external.name}))}); this is not encoded yet")
            if asynchronous and inner_async:
                raise Unsupported(pos, "two asynchronous connections in series are not encoded yet")
            if incoming:
                self.link(external, port, asynchronous or inner_async, pos)
            else:
                self.link(port, external, asynchronous or inner_async, pos)

    def network(self) -> Network:
        return Network(self.name, tuple(self.components), tuple(self.links), dict(self.shared), dict(self.scopes),
                       self.copies())

    def copies(self) -> dict[str, Copies]:
        """The shared variables RoboTool's memory model makes more than one variable (docs/semantics.md
        §5.5).  One kept inside the element that one machine requires, with nothing to pass on at the
        start, stays one variable: its copy changes only when it writes it."""
        out: dict[str, Copies] = {}
        for key, v in self.shared.items():
            readers = tuple(sorted({c for (c, _n), k in self.scopes.items() if k == key}))
            if v.constant or not readers:
                continue
            keeper = self.keeper.get(key)
            if keeper is None:
                outer = self.outside[key]
                found = Copies(key, v, readers, False, f"{outer}::set_{v.name}", f"{outer}::set_EXT_{v.name}",
                               direct=self.alone)
            else:
                start = given_initial(v)
                found = Copies(key, v, readers, True, f"{self.name}::set_{v.name}" if keeper == "provided" else None,
                               None, start)
            if found.stateful or found.written is not None:
                out[key] = found
        return out


def of_machine(m: ast.StateMachine, defined: dict[str, ast.OperationDef] | None = None) -> Network:
    """A machine on its own: every event visible under the machine's name.

    `defined`: for a machine named inside its controller, the operations the controller defines.
    """
    f = _Flattener(m.name)
    f.machine(m, m.name, defined)
    f.require_alone(m)
    return f.network()


def of_controller(c: ast.Controller) -> Network:
    """A controller: machines joined by its connections; its own events visible as `C::e`."""
    f = _Flattener(c.name)
    inputs, outputs = f.controller(c, "")
    for name, ports in inputs.items():
        event = c.event(name)
        assert event is not None
        f.expose(c.name, event, ports, True, False, ports[0][0].event.pos)
    for name, ports in outputs.items():
        event = c.event(name)
        assert event is not None
        f.expose(c.name, event, ports, False, False, ports[0][0].event.pos)
    return f.network()


def of_module(m: ast.Module) -> Network:
    """A module: its controllers joined to each other and to the platform (visible as `Mod::e`)."""
    f = _Flattener(m.name)
    if m.platform is not None:
        f.share(m.platform.variables, "", "platform", m.platform.provided_interfaces)
        f.platform = {v.name for v in m.platform.variables}
    ends: dict[str, tuple[ast.Controller, dict, dict]] = {}
    for ci in m.controllers:
        prefix = f"{ci.name}::" if len(m.controllers) > 1 else ""
        ins, outs = f.controller(ci.controller, prefix, (ci.name,))
        ends[ci.name] = (ci.controller, ins, outs)
    used: set[tuple[str, str, bool]] = set()  # (controller, event, incoming): a direction the module joins
    for conn in m.connections:
        src, dst = ends.get(conn.source), ends.get(conn.target)
        if conn.bidirectional:
            _boundary_only(conn, src is not None and dst is not None, "two controllers")
        if src is not None and dst is not None:
            used |= {(conn.source, conn.source_event.name, False), (conn.target, conn.target_event.name, True)}
            for p, a in src[2].get(conn.source_event.name, []):
                for q, b in dst[1].get(conn.target_event.name, []):
                    if [a, b, conn.asynchronous].count(True) > 1:
                        raise Unsupported(conn.pos, "two asynchronous connections in series are not encoded yet")
                    f.link(p, q, a or b or conn.asynchronous, conn.pos)
        # The platform is the environment: RoboTool joins its connections directly (a visible event of
        # the module), `(_async)` or not; only connections between controllers get a buffer.
        # A connection with the platform joins the controller's whole channel, both directions, as
        # RoboTool's renaming `ctrl_ref1::e <- e` does, `[ mult ]` or not.
        elif dst is not None or src is not None:  # platform → controller, or controller → platform
            name, ev, outer = ((conn.target, conn.target_event.name, conn.source_event) if dst is not None
                               else (conn.source, conn.source_event.name, conn.target_event))
            _c, ins, outs = ends[name]
            used |= {(name, ev, True), (name, ev, False)}
            f.expose(m.name, outer, ins.get(ev, []), True, False, conn.pos)
            f.expose(m.name, outer, outs.get(ev, []), False, False, conn.pos)
    # Controller events the module leaves unconnected, in either direction, stay visible under the
    # controller's name (as the interpreter's `_flatten_module` keeps them).
    for name, (c, ins, outs) in ends.items():
        for table, incoming in ((ins, True), (outs, False)):
            for ev_name, ports in table.items():
                if (name, ev_name, incoming) not in used:
                    event = c.event(ev_name)
                    assert event is not None
                    f.expose(c.name, event, ports, incoming, False, c.pos)
    return f.network()


def _boundary_only(conn: ast.Connection, inner: bool, what: str) -> None:
    """A bidirectional connection (`[mult]`) is encoded between a machine and its controller's own
    event, or a controller and the platform: RoboTool renames the whole channel there, so both
    directions are the outer element's (docs/semantics.md §5.3).  Not between two machines or two
    controllers, nor asynchronous inside a controller."""
    if inner:
        raise Unsupported(conn.pos, f"bidirectional connections between {what} are not encoded yet")
    if conn.asynchronous and what == "two machines":
        raise Unsupported(conn.pos, "asynchronous bidirectional connections of a machine are not encoded yet")


def network_of(element: ast.StateMachine | ast.Controller | ast.Module,
               defined: dict[str, ast.OperationDef] | None = None, timed: bool = True) -> Network:
    """The network of a machine (with the operations its controller defines), controller or module;
    with `timed=False`, in RoboTool's untimed semantics (`model.untimed`; no `tock`)."""
    if not timed:
        element, defined = untimed(element, defined)
        return replace(network_of(element, defined), timed=False)
    if isinstance(element, ast.StateMachine):  # an operation on its own ends with ✓ alone, as a module does
        return replace(of_machine(element, defined), hidden_termination=isinstance(element, ast.OperationMachine),
                       qname=element.qname)
    if isinstance(element, ast.Controller):
        return replace(of_controller(element), qname=element.qname)
    return replace(of_module(element), hidden_termination=True, qname=element.qname)
