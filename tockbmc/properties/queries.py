"""Each assertion as a `Query`: the element to unroll, its CSP context, and the goals to search.

Assertion forms that are not supported yet raise `Unsupported` with the reason.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import z3

from tockbmc.encodings import names
from tockbmc.encodings.system import Target, TransitionSystem
from tockbmc.encodings.unroller import Unroller
from tockbmc.model import ast
from tockbmc.model.config import robotool_slots
from tockbmc.model.csp import CspError, Definition, parse_block
from tockbmc.model.errors import Unsupported
from tockbmc.properties.deadlock import (
    _describe_divergence,
    deadlock_goals,
    divergence_goals,
    diverges,
    unbounded_loops,
    untimed_deadlock_goals,
    watch_loops,
    watching_loops,
)
from tockbmc.properties.failures import FAILURES_MODELS, Refusals, offered_at
from tockbmc.properties.goals import ElementSpec, Goal, Query, number_at, says, stuck, terminated, timelocked, true_at
from tockbmc.properties.process import Context, Implementation, MonitorExtension, RoboToolConstant, implementation
from tockbmc.properties.spec import EnumValue, Env, Evaluator, Monitor, Proc, Semantics, Stop
from tockbmc.properties.ticktock import TICK_TOCK, TickTockMonitor


def _reaches(state: str) -> Target:
    def target(system: TransitionSystem) -> z3.BoolRef:
        found = []
        for c, comp in enumerate(system.components):
            locs = [loc.index for loc in comp.automaton.locations
                    if any(_names(a, state, comp.name, comp.machine.name) for a in loc.active)]
            found += [system.loc(c) == i for i in locs]
        return z3.Or(found) if found else z3.BoolVal(False)

    return target


def _names(path: str, state: str, *component: str) -> bool:
    """Whether node `path` (`a::b`) of a component is the state an assertion calls `state`.

    `state` is the node's path, maybe qualified by names that end with the component's
    (`stm0::s`, `ctrl0::stm0::s`, `pkg::ctrl0::stm0::s`).
    """
    if path == state:
        return True
    if not state.endswith("::" + path):
        return False
    qualifier = state[: -len(path) - 2].rsplit("::", 1)[-1]
    return any(ast.qualifies(qualifier, name.rsplit("::", 1)[-1]) for name in component)


def _what_refuses(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
    if true_at(unroller, model, unroller.system.halted(), k):
        return f"{unroller.system.name} has terminated, so tock is refused"
    return f"{unroller.system.name} refuses tock here"


def query(project: ast.Project, a: ast.Assertion) -> Query:
    """The query for assertion `a`; raises `Unsupported` for forms not checked yet."""
    q = _query(project, a)
    # A construct RoboTool accepts and tockbmc gives no meaning loads (`ast.UnsupportedExpr`):
    # it is refused here, for the assertions whose elements hold it only.
    meaningless = ast.unsupported_in(*q.reached)
    if meaningless is not None:
        raise Unsupported(meaningless.pos, meaningless.what)
    return replace(q, timed=False) if a.timing == "untimed" else q


def _query(project: ast.Project, a: ast.Assertion) -> Query:
    timed = a.timing != "untimed"
    if not timed and a.kind == "timelock-free":
        raise Unsupported(None, "timelock-freedom is about tock, which RoboTool's untimed semantics does not have: "
                                "RoboTool generates it in the timed semantics only")
    if a.semantic_model == TICK_TOCK and a.kind in ("refines", "equals") and not timed:
        raise Unsupported(None, "the tick-tock model records refusals before each tock, and RoboTool's untimed "
                                "semantics has no tock")
    if a.kind == "clock-initialised":
        raise Unsupported(None, "clock initialisation (`clock C is [not] initialised`): RoboTool's meaning for it "
                                "was not found in any public source (docs/robotool-evidence.md §8), so it is not "
                                "checked")
    ev = Evaluator(_top_level(project), _any_block(project), _literals(project), _memory_channels(project),
                   _enumerations(project), _record_fields(project),
                   {name: (low, high) for name, low, high in project.arithmetic})
    sem = Semantics(ev, timed=timed)
    if a.kind in ("refines", "equals"):
        return _refinement(project, a, ev, sem)
    subject, subject_is_process = (a.other, a.other_is_process) if a.kind == "reachable" else (a.subject,
                                                                                               a.subject_is_process)
    impl = _side(ev, project, subject or "", subject_is_process, a.pos)
    if not isinstance(impl, Implementation):
        raise Unsupported(None, f"'{subject}' is a CSP process with no model element in it; checking a "
                           "specification on its own is not supported")
    element, name, settings = _resolve(project, impl)
    if impl.head:
        raise Unsupported(None, f"'{subject}' starts with a prefix before the model process; only refinement checks "
                           "(with the model on the left) support that")
    context = Context(impl, sem) if subject_is_process else None
    if context is not None and impl.continues:
        if a.kind != "timelock-free":
            raise Unsupported(None, f"'{subject}' runs a process after the model terminates; only refinement and "
                               "timelock-freedom checks support that")
        return _timelock_after(a, element, name, context, settings, _defined(project, impl))
    if a.kind == "deterministic":
        if context is not None:
            raise Unsupported(None, f"'{subject}' puts the model in a CSP process; determinism is checked for model "
                               "elements on their own")
        return Query(assertion=a, element=element, goals=divergence_goals(name, a.negated), settings=settings,
                     defined=_defined(project, impl), determinism=True)
    return Query(assertion=a, element=element, goals=_goals(a, name), context=context, settings=settings,
                 defined=_defined(project, impl))


def _goals(a: ast.Assertion, name: str) -> tuple[Goal, ...]:
    if a.kind == "deadlock-free" and a.timing == "untimed":
        return untimed_deadlock_goals(name, a.negated)
    if a.kind == "terminates":
        if a.negated:
            return (Goal.violation(terminated, says(f"{name} has terminated")),)
        stuck_goal = Goal.violation(stuck, says(f"{name} has not terminated and refuses every event, tock included"),
                                    claim="no configuration short of termination refuses every event")
        return (stuck_goal, Goal.witness(terminated, says(f"{name} has terminated"), sought="termination"))
    if a.kind == "timelock-free":
        return (_negatable(a.negated, timelocked, _what_refuses, sought="a configuration that refuses tock"),)
    if a.kind == "deadlock-free":
        return deadlock_goals(name, a.negated)
    if a.kind == "divergence-free":
        return divergence_goals(name, a.negated)
    if a.kind == "reachable":
        entered = says(f"state {a.subject} is entered")
        if a.negated:
            return (Goal.violation(_reaches(a.subject), entered),)
        return (Goal.witness(_reaches(a.subject), entered, sought=f"state {a.subject}"),)
    raise Unsupported(None, f"'{a.kind}' assertions are not supported yet")


def _negatable(negated: bool, target: Target, describe: Callable[[Unroller, z3.ModelRef, int], str],
               **more: object) -> Goal:
    """`P is X`: reaching the target violates it; `P is not X`: reaching it is the witness."""
    return (Goal.witness if negated else Goal.violation)(target, describe, **more)


def _side(ev: Evaluator, project: ast.Project, name: str, is_process: bool, pos: ast.Pos) -> Implementation | Proc:
    return _process(ev, project, name) if is_process else Implementation(name, (), pos)


def _resolve(project: ast.Project, impl: Implementation) -> tuple[ast.StateMachine | ast.Controller | ast.Module,
                                                                   str, tuple[tuple[str, ast.Expr], ...]]:
    element = _element(project, impl.element)
    if element is None:
        raise Unsupported(None, f"'{impl.element}' names no machine, controller, module or operation")
    if isinstance(element, ast.OperationDef):
        element = ast.operation_machine(element)
    return element, element.name, _arguments(project, element, impl)


def _refinement(project: ast.Project, a: ast.Assertion, ev: Evaluator, sem: Semantics) -> Query:
    """`P refines Q` and `P equals Q`: one side a model element in context, the other a CSP specification.

    With the model on the left, a monitor of the specification runs beside it; with the model
    on the right, the specification's traces are checked one by one (`properties.inclusion`).
    """
    left = _side(ev, project, a.subject, a.subject_is_process, a.pos)
    right = _side(ev, project, a.other or "", a.other_is_process, a.pos)
    spec_element = None
    spec: Proc
    if isinstance(left, Implementation) and isinstance(right, Implementation):
        # Two model elements: the renamed one (else the right one) stands for the specification,
        # as its state graph (`explicit.lts`); the other is checked as a model element.
        impl, other = (right, left) if left.renames and not right.renames else (left, right)
        if impl.renames:
            raise Unsupported(None, "refinement between two renamed model elements is not supported")
        if other.ops or other.head or other.continues:
            raise Unsupported(None, "a model element on the specification's side is supported renamed only, not "
                                    "under other CSP operators")
        found, _name, found_settings = _resolve(project, other)
        spec_element = ElementSpec(other, found, found_settings, _defined(project, other))
        spec = Stop(True)  # replaced by the element's state graph (`given_spec`)
        left_spec = other is left
    elif isinstance(left, Implementation) and isinstance(right, Proc):
        impl, spec, left_spec = left, right, False
    elif isinstance(right, Implementation) and isinstance(left, Proc):
        impl, spec, left_spec = right, left, True
    else:
        raise Unsupported(None, "refinement between two CSP specifications is not supported; one side must be a "
                                "model element (possibly in a CSP context)")
    if impl.renames:
        raise Unsupported(None, "renaming the model element checked is not supported; rename the other side")
    spec_name = a.subject if left_spec else a.other
    element, name, settings = _resolve(project, impl)
    goals: tuple[Goal, ...] = ()
    tick_tock = a.semantic_model == TICK_TOCK
    failures = a.semantic_model in FAILURES_MODELS or tick_tock
    if not left_spec or a.kind == "equals":  # equality is refinement both ways, whichever side the model is on
        spec_text = spec_name or ""
        goals = _failures_goals(a, name, spec_text) if failures else (_refinement_goal(a, name, spec_text),)
    inclusion = a.kind == "equals" or left_spec
    if inclusion and impl.head:
        raise Unsupported(None, f"checking that {name} has every trace of {spec_name} is not supported when a prefix "
                           "comes before the model")
    if inclusion and impl.continues:
        raise Unsupported(None, f"checking that {name} has every trace of {spec_name} is not supported when a process "
                           "follows the model's termination")
    return Query(assertion=a, element=element, goals=goals,
                 context=Context(impl, sem, spec if goals else None, spec_name or "",
                                 TickTockMonitor if tick_tock else None), defined=_defined(project, impl),
                 settings=settings, inclusion=spec if inclusion else None, spec_name=spec_name or "",
                 spec_element=spec_element)


def given_spec(q: Query, spec: Proc) -> Query:
    """The query with `spec` (a model element's state graph) as its specification, on whichever
    side the assertion put it (refinement between two model elements)."""
    assert q.context is not None
    context = Context(q.context.impl, q.context.sem, spec if q.context.spec is not None else None,
                      q.context.spec_name, q.context.monitor)
    return replace(q, context=context, inclusion=spec if q.inclusion is not None else None)


def _timelock_after(a: ast.Assertion, element: ast.StateMachine | ast.Controller | ast.Module, name: str,
                    context: Context, settings: tuple[tuple[str, ast.Expr], ...],
                    defined: tuple[tuple[str, ast.OperationDef], ...]) -> Query:
    """Timelock-freedom of `P ; T`: a terminated element is a timelock only if what follows can be one."""
    rest = context.tail_timelock()

    def target(system: TransitionSystem) -> z3.BoolRef:
        stable = z3.And(z3.Not(system.internal_enabled()), z3.Not(system.tock_enabled()))
        return stable if rest is not None else z3.And(stable, z3.Not(system.halted()))

    def describe(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
        if true_at(unroller, model, unroller.system.halted(), k):
            after = " ".join(rest or []) or "nothing"
            return f"{name} has terminated; what follows ({after}) then refuses tock"
        return f"{name} refuses tock here"

    goal = _negatable(a.negated, target, describe, sought="a configuration that refuses tock")
    return Query(assertion=a, element=element, goals=(goal,), context=context, settings=settings, defined=defined)


def unprefixed_tock(a: ast.Assertion) -> str:
    """What to add where a specification refuses a tock of the model, for an assertion that says
    neither `timed` nor `untimed`: a default that decided the verdict is said with it (§7.8)."""
    if a.timing is not None:
        return ""
    return ("; the assertion says neither `timed` nor `untimed`, so it is checked in the timed semantics, where "
            "time passes (`untimed assertion` checks RoboTool's untimed semantics)")


def _refinement_goal(a: ast.Assertion, name: str, spec: str) -> Goal:
    """Every trace of the model `name` is one of the specification `spec` (a monitor beside the model)."""
    def violated(system: TransitionSystem) -> z3.BoolRef:
        assert isinstance(system.extension, MonitorExtension)
        return system.extension.violated(system)

    def describe(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
        ext = unroller.system.extension
        assert isinstance(ext, MonitorExtension)
        system = unroller.system
        state = number_at(unroller, model, system.cur[names.MONITOR], k)
        if state == Monitor.DEAD:
            before = number_at(unroller, model, system.cur[names.MONITOR], k - 1) if k else -1
            m = system.moves[number_at(unroller, model, system.act, k - 1)] if k else None
            last = "tock" if m is not None and m.kind == "tock" else "the last event"
            allowed = ext.allowed(before)
            offer = (f"; there it can do {allowed[0]}" if allowed == ["any event but tock"]
                     else f"; there it can do only {', '.join(allowed)}" if allowed else "; there it can do nothing")
            return f"{spec} cannot do {last} after the events before it{offer}" + (
                unprefixed_tock(a) if last == "tock" else "")
        rest = " ".join(ext.bad_end.get(state, []))
        return f"after {name} terminates, the process goes on with {rest}, which {spec} cannot do"

    claim = f"every trace is a trace of {spec}"
    if a.negated:
        return Goal.witness(violated, describe, sought=f"a trace {spec} cannot do", claim=claim)
    return Goal.violation(violated, describe, claim=claim)


def _failures_goals(a: ast.Assertion, name: str, spec: str) -> tuple[Goal, ...]:
    """`M refines Q in the failures [divergences] model`, M on the left (docs/semantics.md §7.12):
    traces refinement, then no stable refusal of M that Q cannot make after the same trace, then (in
    the failures-divergences model, Q being divergence-free) no divergence of M.  In the tick-tock
    model (§7.13) the same, with Q's monitor filtered at each tock by M's refusal there
    (`TickTockMonitor`), so a tock no stable state of Q can match leaves the monitor dead."""
    divergences = a.semantic_model == "failures divergences"
    made: dict[int, tuple[MonitorExtension, Refusals]] = {}

    def refusals(system: TransitionSystem) -> Refusals:
        ext = system.extension
        assert isinstance(ext, MonitorExtension)
        if isinstance(ext, TickTockMonitor):
            return ext.refusals
        if id(ext) not in made:
            made[id(ext)] = (ext, Refusals(ext, divergences, spec))
        return made[id(ext)][1]

    def refused(system: TransitionSystem) -> z3.BoolRef:
        return refusals(system).violated(system)

    def describe(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
        return refusals(unroller.system).describe(unroller, model, k, spec)

    traces = _refinement_goal(a, name, spec)
    claim = f"every trace is a trace of {spec}, and every stable refusal one {spec} can make after it"
    if a.semantic_model == TICK_TOCK:
        claim = (f"every tick-tock observation is one of {spec}'s: its trace, the refusal before each tock and the "
                 "stable refusal at its end")

    def either(system: TransitionSystem) -> z3.BoolRef:  # searched together: the shortest of either kind first
        found = [traces.target(system), refused(system)]
        return z3.Or(found + [diverges(system)] if divergences and a.negated else found)

    def which(unroller: Unroller, model: z3.ModelRef, k: int) -> str:
        if _refused_tock(unroller, model, k):
            return _describe_tock(unroller, model, k, spec)
        tocks = " (each tock keeping only the states of the specification that make the refusal before it)" if (
            isinstance(unroller.system.extension, TickTockMonitor)
            and any(number_at(unroller, model, unroller.system.act, j) == unroller.system.TOCK
                    for j in range(k))) else ""
        if true_at(unroller, model, traces.target(unroller.system), k):
            return traces.describe(unroller, model, k) + tocks
        if true_at(unroller, model, refused(unroller.system), k) or not watching_loops(unroller.system):
            return describe(unroller, model, k) + tocks
        return _describe_divergence(unroller, model, k)

    def details(unroller: Unroller, model: z3.ModelRef, k: int) -> dict[str, object]:
        if isinstance(unroller.system.extension, TickTockMonitor):
            return {"tock_refusals": _tock_refusals(unroller, model, k),
                    **({"refusal": refusals(unroller.system).refused(unroller, model, k)}
                       if true_at(unroller, model, refused(unroller.system), k) else {})}
        if true_at(unroller, model, refused(unroller.system), k):
            return {"refusal": refusals(unroller.system).refused(unroller, model, k)}
        return {}

    if a.negated:
        more: dict[str, object] = dict(prepare=watch_loops, unprovable=unbounded_loops) if divergences else {}
        return (Goal.witness(either, which, sought=f"a trace, refusal or divergence {spec} does not allow",
                             claim=claim, failures=True, details=details, **more),)
    goals: tuple[Goal, ...] = (Goal.violation(either, which, claim=claim, failures=True, details=details),)
    if divergences:
        goals += divergence_goals(name, False)
    return goals


def _refused_tock(unroller: Unroller, model: z3.ModelRef, k: int) -> bool:
    """In the tick-tock model: the run's last step is a tock that left the monitor dead (the
    model's refusal before it is not one the specification can make)."""
    system = unroller.system
    if not isinstance(system.extension, TickTockMonitor) or k == 0:
        return False
    return (number_at(unroller, model, system.cur[names.MONITOR], k) == Monitor.DEAD
            and number_at(unroller, model, system.cur[names.MONITOR], k - 1) != Monitor.DEAD
            and number_at(unroller, model, system.act, k - 1) == system.TOCK)


def _tock_refusals(unroller: Unroller, model: z3.ModelRef, k: int) -> list[dict[str, object]]:
    """The refusal observed before each tock of a run to step k (tick-tock): the tock's step in
    the trace, what the model offers there (it refuses everything else), and, for a tock no state
    of the specification can match, per group of its stable states that can let time pass an
    event the group accepts and the model refuses."""
    system = unroller.system
    ext = system.extension
    assert isinstance(ext, TickTockMonitor)
    out: list[dict[str, object]] = []
    for j in range(k):
        if number_at(unroller, model, system.act, j) != system.TOCK:
            continue
        entry: dict[str, object] = {"step": j + 1, "offered": offered_at(unroller, model, j)}
        if j == k - 1 and _refused_tock(unroller, model, k):
            entry["refused"] = ext.tock_refusal(unroller, model, j)
        out.append(entry)
    return out


def _describe_tock(unroller: Unroller, model: z3.ModelRef, k: int, spec: str) -> str:
    ext = unroller.system.extension
    assert isinstance(ext, TickTockMonitor)
    offered = ", ".join(offered_at(unroller, model, k - 1)) or "nothing"
    refused = ext.tock_refusal(unroller, model, k - 1)
    name = unroller.system.name
    if not refused:
        return (f"{name} is stable, offers only {offered} and lets time pass; {spec} cannot let time pass after the "
                "events before it")
    return (f"{name} is stable, offers only {offered} and lets time pass (tick-tock records the refusal of "
            f"everything else before the tock); every stable state of {spec} that can let time pass there accepts an "
            f"event the model refuses ({'; '.join(refused)})")


def _top_level(project: ast.Project) -> Callable[[str], Definition | None]:
    def lookup(name: str) -> Definition | None:
        # Blocks that seem to define the name first (their syntax errors are reported), then the
        # others that parse (`defines` is found by a pattern, which misses `Timed(…) { N = …`).
        for block in sorted(project.csp_blocks, key=lambda b: name not in b.defines):
            try:
                found = [d for d in parse_block(block) if d.name == name]
            except CspError:
                if name in block.defines:
                    raise
                continue
            if found:
                return found[0]
        return None

    return lookup


def _memory_channels(project: ast.Project) -> frozenset[str]:
    """RoboTool's channels for the reads and writes of the model's variables (`set_x`, `get_x`,
    `setL_x`, `setR_x`), except names the model gives its own events."""
    groups: tuple[tuple[ast.Variable, ...], ...] = (
        *(h.variables for h in project.interfaces), *(h.variables for h in project.platforms),
        *(h.variables for h in project.machines), *(h.variables for h in project.controllers),
        *(h.variables for h in project.operations))
    declared: tuple[tuple[ast.Event, ...], ...] = (
        *(h.events for h in project.interfaces), *(h.events for h in project.platforms),
        *(h.events for h in project.machines), *(h.events for h in project.controllers),
        *(h.events for h in project.operations))
    events = {e.name for g in declared for e in g}
    return frozenset(f"{k}_{v.name}" for g in groups for v in g for k in ("set", "get", "setL", "setR")) - events


def _enumerations(project: ast.Project) -> dict[str, frozenset[EnumValue]]:
    """Enumeration types as sets of their literals, by the names a specification may write: `E` or
    RoboTool's `pkg_E` (`|~| x : AggregationSw_Position @ …`).  Not `pkg::E`: a name with `::` is a
    channel's (`Arm::Mode.in` for event Mode of machine Arm, beside a type Mode of package Arm)."""
    literals = _literals(project)
    out: dict[str, frozenset[EnumValue]] = {}
    for t in project.types:
        if isinstance(t, ast.EnumType) and not t.params:  # RoboTool's CSP spelling of a literal's arguments is not known
            values = frozenset(literals[f"{t.qname}::{lit}"] for lit in t.literals)
            for key in (t.name, t.qname.replace("::", "_")):
                out[key] = values
    return out


def _record_fields(project: ast.Project) -> dict[str, tuple[str, int]]:
    """RoboTool's CSP functions that read a record's field, `pkg_R_f` (test15's `test15_DT_p(x)`),
    each with its field's name and place among the record's fields (RoboTool writes a record value
    as the tuple of its fields, in declaration order)."""
    return {f"{t.qname.replace('::', '_')}_{f.name}": (f.name, i)
            for t in project.types if isinstance(t, ast.RecordType) for i, f in enumerate(t.fields)}


def _literals(project: ast.Project) -> dict[str, EnumValue]:
    """Enumeration literals as a specification may write them: `E::L`, `pkg::E::L` or RoboTool's `E_L`."""
    out: dict[str, EnumValue] = {}
    for t in project.types:
        if isinstance(t, ast.EnumType) and not t.params:
            for i, lit in enumerate(t.literals):
                value = EnumValue(t.name, i, f"{t.name}::{lit}")
                mangled = f"{t.qname.replace('::', '_')}_{lit}"  # RoboTool's `pkg_E_L`
                for key in (f"{t.name}::{lit}", f"{t.qname}::{lit}", f"{t.name}_{lit}", mangled):
                    out[key] = value
    return out


def _any_block(project: ast.Project) -> ast.CspBlock:
    return project.csp_blocks[0] if project.csp_blocks else ast.CspBlock("", None, (), "", ast.Pos("", 1, 1), ())


def _process(ev: Evaluator, project: ast.Project, name: str) -> Implementation | Proc:
    d = ev.lookup_top(name)
    if d is None:
        raise Unsupported(None, f"process '{name}' is not defined at the top level of any CSP block")
    if d.params:
        raise CspError(d.pos, f"process '{name}' takes arguments")
    ev.block = d.block
    return implementation(ev, d.body, Env({}, {}, d.timed))


def _arguments(project: ast.Project, element: ast.StateMachine | ast.Controller | ast.Module,
               impl: Implementation) -> tuple[tuple[str, ast.Expr], ...]:
    """`M::D__(id, c1, …)`: the arguments after `id` set M's constants in declaration order."""
    if len(impl.args) <= 1:
        return ()
    constants = _constants(element)
    given = impl.args[1:]
    if len(given) > len(constants):
        raise CspError(impl.pos, f"{element.name} has {len(constants)} constant(s) "
                                 f"({', '.join(c.name for c in constants) or 'none'}), "
                                 f"but {len(given)} argument(s) are given after the id")
    out = []
    for c, v in zip(constants, given, strict=False):
        if isinstance(v, RoboToolConstant):
            # RoboTool's generated name of this very constant (`const_GasAnalysis_thr` for GasAnalysis's
            # thr): the value its instantiation gives, which is what the configuration gives it anyway.
            names = [n for slot in robotool_slots(project, element) if slot.variable.name == c.name
                     for n in slot.names]
            if v.name not in names:
                raise CspError(impl.pos, f"the argument for constant {c.name} of {element.name} is {v.name}; "
                                         f"only RoboTool's name of that constant ({', '.join(names)}) "
                                         "is understood there")
            continue
        if not isinstance(v, (int, bool)):
            raise CspError(impl.pos, f"the argument for constant {c.name} must be a number or a boolean")
        out.append((c.name, ast.Literal(c.type, impl.pos, v)))
    return tuple(out)


def _constants(element: ast.StateMachine | ast.Controller | ast.Module) -> list[ast.Variable]:
    found: dict[str, ast.Variable] = {}
    if isinstance(element, ast.Module):
        for ci in element.controllers:
            for v in _constants(ci.controller):
                found.setdefault(v.name, v)
    elif isinstance(element, ast.Controller):
        for v in element.variables:
            if v.constant:
                found.setdefault(v.name, v)
        for op in element.operations:
            for v in (*op.operation.variables, *op.operation.interface_variables):
                if v.constant:
                    found.setdefault(v.name, v)
        for m in element.machines:
            for v in _constants(m.machine):
                found.setdefault(v.name, v)
    else:
        for v in (*element.variables, *element.interface_variables):
            if v.constant:
                found.setdefault(v.name, v)
    return list(found.values())


def _defined(project: ast.Project, impl: Implementation) -> tuple[tuple[str, ast.OperationDef], ...]:
    return tuple(_controller_operations(project, impl.element).items())


def _controller_operations(project: ast.Project, name: str) -> dict[str, ast.OperationDef]:
    """For a machine named inside its controller (`Ctrl::stm`, `Mod::ctrl::stm`): the operations the
    controller defines (`opref`), which its calls run."""
    for c in (*project.controllers, *(ci.controller for mod in project.modules for ci in mod.controllers)):
        for m in c.machines:
            if name.endswith(f"{c.name}::{m.name}"):
                return {op.operation.name: op.operation for op in c.operations}
    return {}


def _element(project: ast.Project, name: str) -> ast.StateMachine | ast.Controller | ast.Module | ast.OperationDef | None:
    for group in (project.machines, project.controllers, project.modules, project.operations):
        for item in group:
            if item.qname == name or item.name == name or item.qname.endswith("::" + name):
                return item
    for c in project.controllers:
        for m in c.machines:
            if name in (f"{c.qname}::{m.name}", f"{c.name}::{m.name}"):
                return m.machine
    for mod in project.modules:
        for ci in mod.controllers:
            if name in (f"{mod.qname}::{ci.name}", f"{mod.name}::{ci.name}"):
                return ci.controller
            for m in ci.controller.machines:
                if name in (f"{mod.qname}::{ci.name}::{m.name}", f"{mod.name}::{ci.name}::{m.name}"):
                    return m.machine
    return None
