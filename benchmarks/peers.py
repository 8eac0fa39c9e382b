"""Spin beside tockbmc on the UR machine of the IntelliWelder example: A3 and A6.

Run: python benchmarks/peers.py [--spin-timeout 120] [--spin-memory-mb 3072] [--rows 0 1 2 ...] [--robotool]
     python benchmarks/peers.py --promela-only [--joints 2|6] [--dist 5] [--time 0..10] [--assertion A3]

For each row (joints, distance range, time range) the script writes the UR machine as a Promela
model, compiles and runs Spin's verifier (`spin -a`, `gcc`, `./pan`) once for A3 and once for A6,
runs `tockbmc check -a A3` and `-a A6` (JSON output) on the same model with the matching ranges
(`--range core_real=-d..d` for distances, `--range core_int=lo..hi` for times), and prints one
line per assertion: each tool's verdict, time, memory and, for Spin, the states stored, with the
ratio of the two times. Runs happen in temporary directories; nothing is written to the repository.
`--promela-only` prints the Promela text of one model on stdout and runs nothing.

The Promela model is generated from the resolved model (`tockbmc.load`), not written by hand:
  - Every machine variable is a local variable of `proctype UR`, a record one variable per field
    (`ur_move_dist1`, …), so that Spin's dead-variable reduction (on by default) can forget a
    request once it has been handled; a constant with no value (`n_waypoints`) is chosen once, at
    the start, from 0..`--waypoints` (default 3: the paper's four UR waypoints), where tockbmc
    considers every natural number.
  - Each place where the machine waits for the environment is a label: a stable state (every
    transition of it and of its ancestors is offered), a pending output in an action (`out_of_sync`,
    `done`), a pending operation call, a junction none of whose conditions holds, a top-level final
    state offering `terminate`. From each, every visible event is one `atomic` step that also runs
    the internal steps after it (exit actions, transition action, entry actions, junctions,
    initial transitions, untriggered transitions whose conditions hold), up to the next such label:
    internal steps are invisible and urgent, so no event and no `tock` can come between them.
    Guards, actions and `check_big_dist` (inlined from its postcondition) are the model's
    expressions, translated one for one.
  - The input `move?ur_move` is one atomic step that chooses every field of the request with an
    `if` of one branch per value: reals over the integers -d..d, integers over the time range,
    booleans both ways. Spin's exhaustive search therefore enumerates every input value in range.
  - Time: `tock` is a Promela step like any event (a self-loop on the label), offered wherever
    tock-CSP lets time pass in RoboTool's semantics (docs/semantics.md §3.3): in a stable state
    with no untriggered transition enabled, while an output waits for the environment, at a stuck
    junction and in a final state before `terminate`; not while internal steps are pending, not at
    an operation call (calls are urgent), not after termination. UR has no clocks, so `tock`
    changes nothing but the monitor.
  - A6 "UR does not terminate": `assert(false)` on the `UR::terminate` step. Reaching the final
    state is not itself the violation: `terminate` is offered there, and its occurrence is.
  - A3 "UR refines SpecA3 in the traces model", with `SpecA3 = CHAOS(Events) [| {|UR::move.in|} |>
    ADeadline({|UR::moveJCall, …|}, 0); Def`: the sets and the deadline are read from the CSP
    block of the assertions file. SpecA3 is deterministic on these events and needs one bit:
    `pending`, set by a `UR::move.in` event, cleared by any of the four calls; every other event
    leaves it. A trace of UR is a trace of SpecA3 exactly when no `tock` happens while `pending`
    (ADeadline with deadline 0 refuses `tock`, CHAOS refuses nothing), so `tock` asserts
    `!pending`. SpecA3 never terminates (`CHAOS` cannot, and `; Def` restarts), so `✓` after
    `UR::terminate` is a violation too, as tockbmc checks it (docs/semantics.md §7.5): the
    `terminate` step also asserts false for A3.
  - Spin runs breadth-first (`-DBFS`, `-DSAFETY`): its counterexamples are shortest, like
    tockbmc's, and it needs no depth limit (a depth-first search goes as deep as there are states
    here, and re-enumerates every input value on each visit of a waiting state, which made it 30x
    slower at d ±5). A breadth-first search also stores the states inside atomic sequences, so
    "states stored" counts the partial choices of an input too (Spin prints the "nominal" count,
    without them, beside it).

What differs from tockbmc's check, beyond the engine:
  - Distances: Spin takes the integers -d..d; tockbmc's `core_real=-d..d` is the whole real
    interval (and no --range at all is every real). n_waypoints: Spin 0..3, tockbmc every value.
  - Bound: Spin explores every reachable state; tockbmc searches runs of up to 40 steps and proves
    "holds" for every length by k-induction (its verdict says so: "holds (k-ind.)").
  - Time: in both, `tock` is one step of the machine, refused while internal steps are pending, at
    a call and after termination, and it counts towards nothing else (UR has no clocks). tockbmc
    takes each internal step as a step of its own (they count towards its bound of 40); Spin runs
    them inside the atomic step of the event before them, so the two see the same traces (events
    and tocks in order) through different configurations, and Spin's state counts are not
    RoboTool's or FDR's either. Spin keeps no clock and no count of tocks: a trace with any
    number of tocks in a waiting place is one state.

Times are wall-clock seconds of the whole tool: Spin is `spin -a` + `gcc` + `./pan` (the search
alone in brackets), tockbmc the `tockbmc check` process (start-up and load included; its own check
time in brackets). Memory: Spin's reported "total actual memory usage" (128 MB of it pan's default
hash table, -w24) / the peak RSS of `pan`; tockbmc's peak RSS. Spin runs under `-DMEMLIM` (and `ulimit -v` a little above it) and a
time limit, and is reported as "out of memory" or "timeout" where it gives up, with the states it
had stored by then.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import tockbmc
from tockbmc.model import ast

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = {2: REPO / "examples" / "intelliwelder", 6: REPO / "examples" / "intelliwelder-6joints"}
MACHINE = "UR"

Code = list[str]


class Untranslatable(Exception):
    """The model uses something this translation does not cover."""


# ----------------------------------------------------------------------------- the specification


@dataclass(frozen=True)
class Monitor:
    """What Spin checks beside the machine: code run on each visible event and on `tock`."""

    assertion: str
    triggers: tuple[str, ...] = ()  # channels that open the deadline (A3: UR::move.in)
    answers: tuple[str, ...] = ()  # channels that close it (A3: the four calls)
    terminate_violates: bool = False

    def declarations(self) -> Code:
        """The monitor's variables."""
        return ["bool pending = false;  /* SpecA3's state: a move.in not yet answered by a call */"] if self.triggers else []

    def on_event(self, name: str) -> Code:
        """What the monitor does on visible event `name` (FDR's naming: `UR::move.in`, `UR::moveJCall`)."""
        code: Code = []
        if any(_on_channel(name, c) for c in self.triggers):
            code.append("pending = true;")
        if any(_on_channel(name, c) for c in self.answers):
            code.append("pending = false;")
        if name.endswith("::terminate") and self.terminate_violates:
            code.append(f"assert(false);  /* {self.assertion}: {'✓ follows, which the specification cannot do' if self.triggers else 'UR terminates'} */")
        return code

    def on_tock(self) -> Code:
        """What the monitor does on `tock`."""
        # Nothing in UR depends on time, so without a monitor tock changes nothing; Spin rejects a
        # self-loop of `skip` ("unconditional self-loop"), and `assert(true)` is the no-op it accepts.
        return ["assert(!pending);"] if self.triggers else ["assert(true);"]


def _on_channel(event: str, channel: str) -> bool:
    return event == channel or event.startswith(channel + ".")


SPEC = re.compile(r"CHAOS\s*\(\s*Events\s*\)\s*\[\|\s*\{\|(?P<triggers>[^}]*)\|\}\s*\|>\s*"
                  r"ADeadline\s*\(\s*\{\|(?P<answers>[^}]*)\|\}\s*,\s*(?P<deadline>\d+)\s*\)\s*\)\s*;\s*Def")


def monitor_for(project: ast.Project, name: str) -> Monitor:
    """The Spin check of assertion `name` (A3: a refinement of a SpecA3-shaped process; A6: does not terminate)."""
    [assertion] = [a for a in project.assertions if a.name == name]
    if assertion.subject != MACHINE:
        raise Untranslatable(f"{name} is not about {MACHINE}")
    if assertion.kind == "terminates" and assertion.negated:
        return Monitor(name, terminate_violates=True)
    if assertion.kind == "refines" and assertion.other is not None:
        block = next(b for b in project.csp_blocks if assertion.other in b.defines)
        m = SPEC.search(block.text)
        if m is None or int(m["deadline"]) != 0:
            raise Untranslatable(f"{assertion.other} is not CHAOS(Events) [| {{|…|}} |> ADeadline({{|…|}}, 0); Def")
        return Monitor(name, _channels(m["triggers"]), _channels(m["answers"]), terminate_violates=True)
    raise Untranslatable(f"{name}: only 'does not terminate' and the SpecA3 refinement are translated")


def _channels(text: str) -> tuple[str, ...]:
    return tuple(c.strip() for c in text.split(",") if c.strip())


# ----------------------------------------------------------------------------- the machine


@dataclass(frozen=True)
class Ranges:
    """The values Spin enumerates: integers -dist..dist for reals, time[0]..time[1] for integers."""

    dist: int
    time: tuple[int, int]
    waypoints: int = 3

    def values(self, t: ast.Type) -> list[str]:
        """Every value of type `t` that Spin enumerates, as Promela literals."""
        if isinstance(t, ast.PrimitiveType):
            if t.kind == "boolean":
                return ["false", "true"]
            if t.kind == "real":
                return [str(v) for v in range(-self.dist, self.dist + 1)]
            if t.kind == "int":
                return [str(v) for v in range(self.time[0], self.time[1] + 1)]
            if t.kind == "nat":
                return [str(v) for v in range(self.waypoints + 1)]
        raise Untranslatable(f"values of type {t}")


def _ptype(t: ast.Type) -> str:
    if isinstance(t, ast.PrimitiveType):
        return {"boolean": "bool", "nat": "short", "int": "short", "real": "short"}[t.kind]
    raise Untranslatable(f"a variable of type {t}")


def _label(prefix: str, path: str) -> str:
    return f"{prefix}_{path.replace('::', '__')}"


@dataclass
class Translation:
    """`machine` of `project` as `proctype UR`, with `monitor` beside it."""

    project: ast.Project
    machine: ast.StateMachine
    monitor: Monitor
    ranges: Ranges
    blocks: list[Code] = field(default_factory=list)
    made: set[str] = field(default_factory=set)
    visible_labels: dict[tuple[int, str], str] = field(default_factory=dict)
    chain: list[str] = field(default_factory=list)  # the nodes of the internal steps being written
    counter: int = 0

    # -- names and expressions

    def scalars(self, v: ast.Variable) -> list[tuple[str, ast.Type]]:
        """The Promela variables of `v`: itself, or one per field of a record."""
        if isinstance(v.type, ast.RecordType):
            return [(f"{v.name}_{f.name}", f.type) for f in v.type.fields]
        return [(v.name, v.type)]

    def expr(self, e: ast.Expr, bound: dict[str, str] | None = None) -> str:
        """`e` in Promela; `bound` maps a function's parameters to its arguments while inlining it."""
        bound = bound or {}
        if isinstance(e, ast.Literal):
            if isinstance(e.value, bool):
                return "true" if e.value else "false"
            if isinstance(e.value, (int, Fraction)) and Fraction(e.value).denominator == 1:
                return str(int(e.value))
            raise Untranslatable(f"the literal {e.value!r}")
        if isinstance(e, ast.VarRef):
            return bound.get(e.variable.name, e.variable.name)
        if isinstance(e, ast.FieldRef) and isinstance(e.record, ast.VarRef):
            return f"{e.record.variable.name}_{e.field_name}"
        if isinstance(e, ast.Unary):
            return f"!({self.expr(e.operand, bound)})" if e.op == "not" else f"-({self.expr(e.operand, bound)})"
        if isinstance(e, ast.Binary):
            left, right = self.expr(e.left, bound), self.expr(e.right, bound)
            ops = {"and": "&&", "or": "||", "==": "==", "!=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">=",
                   "+": "+", "-": "-", "*": "*", "iff": "=="}
            if e.op == "implies":
                return f"(!({left}) || ({right}))"
            if e.op in ops:
                return f"({left} {ops[e.op]} {right})"
        if isinstance(e, ast.Call) and e.function.definition is not None and not e.function.preconditions:
            args = {p.name: self.expr(a, bound) for p, a in zip(e.function.parameters, e.args, strict=True)}
            return f"/* {e.function.name} */ {self.expr(e.function.definition, args)}"
        raise Untranslatable(f"the expression {type(e).__name__} at {e.pos.line}")

    def event(self, kind: str, name: str) -> str:
        """The event's name as FDR prints it."""
        return {"in": f"{MACHINE}::{name}.in", "out": f"{MACHINE}::{name}.out", "call": f"{MACHINE}::{name}Call",
                "terminate": f"{MACHINE}::terminate"}[kind]

    def fresh(self, prefix: str) -> str:
        """A new label."""
        self.counter += 1
        return f"{prefix}{self.counter}"

    # -- statements, in continuation-passing style: `k` writes what follows, `key` names it, so that the
    #    block of a visible statement is written once for each place it continues to

    def stmt(self, s: ast.Stmt | None, k: Callable[[], Code], key: str) -> Code:
        if s is None or isinstance(s, ast.Skip):
            return k()
        if isinstance(s, ast.Seq):
            return self.stmts(list(s.statements), k, key)
        if isinstance(s, ast.Assign):
            if s.fields or not isinstance(s.variable.type, ast.RecordType):
                name = "_".join((s.variable.name, *s.fields))
                return [f"{name} = {self.expr(s.value)};", *k()]
            raise Untranslatable(f"a record assignment at {s.pos.line}")
        if isinstance(s, ast.If):
            return ["if", f":: ({self.expr(s.condition)}) ->", *self.stmt(s.then, k, key), ":: else ->",
                    *self.stmt(s.otherwise, k, key), "fi;"]
        if isinstance(s, (ast.Send, ast.OperationCall)):
            label = self.visible_labels.get((id(s), key))
            if label is None:
                label = self.visible_labels[(id(s), key)] = self.visible(s, k)
            return [f"goto {label}"]
        raise Untranslatable(f"the statement {type(s).__name__} at {s.pos.line}")

    def visible(self, s: ast.Send | ast.OperationCall, k: Callable[[], Code]) -> str:
        """The block where the machine offers the output or call `s`, then goes on with `k`."""
        saved, self.chain = self.chain, []
        try:
            return self._visible(s, k)
        finally:
            self.chain = saved

    def _visible(self, s: ast.Send | ast.OperationCall, k: Callable[[], Code]) -> str:
        if isinstance(s, ast.Send):
            if s.value is not None:
                raise Untranslatable(f"an output with a value at {s.pos.line}")
            name = self.event("out", s.event.name)
            label = self.fresh("OUT")
            # An output waits for the environment, and time may pass meanwhile (docs/semantics.md §3.4).
            self.blocks.append([f"{label}:  /* {name} offered */", "if", f":: {self.tock()} goto {label}",
                                f":: atomic {{  /* {name} */", *self.monitor.on_event(name), *k(), "}", "fi;"])
            return label
        name = self.event("call", s.operation.name)
        args = ".".join(self.expr(a) for a in s.args)
        label = self.fresh("CALL")
        # A platform call is urgent: no tock while it is offered.
        self.blocks.append([f"{label}:  /* {name} offered, urgent: no tock */",
                            f"atomic {{  /* {name}.{args} */", *self.monitor.on_event(name), *k(), "}"])
        return label

    def stmts(self, ss: list[ast.Stmt | None], k: Callable[[], Code], key: str) -> Code:
        if not ss:
            return k()
        return self.stmt(ss[0], lambda: self.stmts(ss[1:], k, key), key)

    def tock(self) -> str:
        return "/* tock */ " + " ".join(self.monitor.on_tock())

    # -- the graph

    def ancestors(self, path: str | None) -> list[str]:
        out = []
        while path is not None:
            out.append(path)
            path = self.machine.node(path).parent
        return out

    def available(self, leaf: str) -> list[ast.Transition]:
        """The transitions that may be taken with `leaf` the innermost active node: its own and its ancestors'."""
        paths = self.ancestors(leaf)
        return [t for t in self.machine.transitions if t.source in paths]

    def take(self, t: ast.Transition, leaf: str) -> Code:
        """Exit from `leaf` up to the closest state containing source and target, the action, the entries."""
        source_up = self.ancestors(self.machine.node(t.source).parent)
        target_up = self.ancestors(t.target)
        common = next((p for p in source_up if p in target_up and p != t.target), None)
        exits = self.ancestors(leaf)
        exits = exits[: exits.index(common)] if common else exits
        enters = list(reversed(target_up[: target_up.index(common)] if common else target_up))
        steps: list[ast.Stmt | None] = [self.machine.node(p).exit for p in exits]
        steps.append(t.action)
        steps.extend(self.machine.node(p).entry for p in enters[:-1])
        return [f"/* {t.name}: {t.source} -> {t.target} */",
                *self.stmts(steps, lambda: self.arrive(t.target), f"{t.name} from {leaf}")]

    def arrive(self, path: str) -> Code:
        """Code for having just reached node `path` (its ancestors entered), up to the next waiting place."""
        node = self.machine.node(path)
        if path in self.chain:
            raise Untranslatable(f"a cycle of internal steps through {path}")
        self.chain.append(path)
        try:
            return self._arrive(node)
        finally:
            self.chain.pop()

    def _arrive(self, node: ast.Node) -> Code:
        path = node.path
        if node.kind == "junction":
            out = self.machine.transitions
            leaving = [t for t in out if t.source == path]
            if any(t.trigger is not None for t in leaving):
                raise Untranslatable(f"a triggered transition out of junction {path}")
            return self.choose(leaving, path, _label("J", path), allow_tock=True)
        if node.kind == "final" and node.parent is None:
            return [f"goto {self.final_label(path)}"]
        if node.kind in ("state", "final"):
            def settle() -> Code:
                if node.composite:
                    [start] = [c for c in node.children if self.machine.node(c).kind == "initial"]
                    [t0] = [t for t in self.machine.transitions if t.source == start]
                    return self.take(t0, start)
                return self.settle(path)
            return self.stmt(node.entry, settle, f"entry of {path}")
        raise Untranslatable(f"arriving at a {node.kind}")

    def choose(self, leaving: list[ast.Transition], leaf: str, stuck: str, allow_tock: bool) -> Code:
        """Take one of the untriggered `leaving` whose condition holds; if none does, wait at label `stuck`."""
        self.waiting(stuck, leaf, leaving, [], allow_tock)
        if not leaving:
            return [f"goto {stuck}"]
        code = ["if"]
        for t in leaving:
            code += [f":: ({self.guard(t)}) ->", *self.take(t, leaf)]
        return [*code, f":: else -> goto {stuck}", "fi;"]

    def guard(self, t: ast.Transition) -> str:
        """The condition of `t` in Promela."""
        if t.is_else:
            raise Untranslatable(f"'else' condition on {t.name}")
        return "true" if t.condition is None else self.expr(t.condition)

    def settle(self, leaf: str) -> Code:
        """Having entered leaf state `leaf`: internal transitions if only those leave it, else wait there."""
        available = self.available(leaf)
        internal = [t for t in available if t.trigger is None]
        if len(internal) == len(available):
            return self.choose(internal, leaf, _label("S", leaf), allow_tock=True)
        self.waiting(_label("S", leaf), leaf, internal, [t for t in available if t.trigger is not None], True)
        return [f"goto {_label('S', leaf)}"]

    def waiting(self, label: str, leaf: str, internal: list[ast.Transition], triggered: list[ast.Transition],
                allow_tock: bool) -> None:
        """The block at `label`: every internal transition whose condition holds, every trigger, and tock."""
        if label in self.made:
            return
        self.made.add(label)
        saved, self.chain = self.chain, []
        try:
            self._waiting(label, leaf, internal, triggered, allow_tock)
        finally:
            self.chain = saved

    def _waiting(self, label: str, leaf: str, internal: list[ast.Transition], triggered: list[ast.Transition],
                 allow_tock: bool) -> None:
        code = [f"{label}:  /* waiting in {leaf} */", "if"]
        for t in internal:
            code += [f":: ({self.guard(t)}) -> atomic {{", *self.take(t, leaf), "}"]
        for t in triggered:
            code += self.triggered(t, leaf)
        if allow_tock:
            enabled = " || ".join(f"({self.guard(t)})" for t in internal)
            code.append(f":: {'!(' + enabled + ') -> ' if enabled else ''}{self.tock()} goto {label}")
        self.blocks.append([*code, "fi;"])

    def triggered(self, t: ast.Transition, leaf: str) -> Code:
        """The branch of a waiting block that takes triggered transition `t`: the event, then what follows."""
        trig = t.trigger
        assert trig is not None
        guard = f"({self.guard(t)}) -> " if t.condition is not None else ""
        if trig.kind == "input" and trig.variable is not None:
            if t.condition is not None and trig.variable.name in self.expr(t.condition):
                raise Untranslatable(f"{t.name}: a condition on the value received")
            name = self.event("in", trig.event.name)
            choices = [f"if {' '.join(f':: {n} = {v}' for v in self.ranges.values(ty))} fi;"
                       for n, ty in self.scalars(trig.variable)]
            return [f":: {guard}atomic {{  /* {name}: every value in range */", *choices, *self.monitor.on_event(name),
                    *self.take(t, leaf), "}"]
        if trig.kind == "plain":
            name = self.event("in", trig.event.name)
            return [f":: {guard}atomic {{  /* {name} */", *self.monitor.on_event(name), *self.take(t, leaf), "}"]
        raise Untranslatable(f"{t.name}: a trigger of kind {trig.kind}")

    def final_label(self, path: str) -> str:
        """The block of top-level final state `path`: `terminate` offered, and tock meanwhile."""
        label = _label("F", path)
        if label not in self.made:
            self.made.add(label)
            name = self.event("terminate", "")
            # `terminate` is visible and not urgent: tock may come first (docs/semantics.md §4.4).
            self.blocks.append([f"{label}:  /* in final state {path}: {name} offered */", "if",
                                f":: {self.tock()} goto {label}",
                                f":: atomic {{  /* {name} */", *self.monitor.on_event(name), "goto terminated", "}",
                                "fi;"])
        return label

    # -- the whole process

    def promela(self, title: str) -> str:
        """The whole Promela text."""
        m = self.machine
        if m.clocks or m.interface_variables or any(n.during for n in m.nodes) or \
                any(t.deadline is not None or t.clock_resets for t in m.transitions):
            raise Untranslatable(f"{m.name} has clocks, deadlines, during actions or shared variables")
        decls: Code = []
        for v in m.variables:
            if v.constant:
                continue
            if v.initial is not None and isinstance(v.type, ast.RecordType):
                raise Untranslatable(f"the initial value of record {v.name}")
            for name, ty in self.scalars(v):
                # No initial value: 0. UR's only such variable, ur_move, is set by `move` before it is read.
                init = self.expr(v.initial) if v.initial is not None else "false" if _ptype(ty) == "bool" else "0"
                decls.append(f"{_ptype(ty)} {name} = {init};")
        start: Code = []
        for c in m.constants:
            if c.initial is not None:
                decls.append(f"{_ptype(c.type)} {c.name} = {self.expr(c.initial)};")
            else:
                decls.append(f"{_ptype(c.type)} {c.name};")
                options = " ".join(f":: {c.name} = {v}" for v in self.ranges.values(c.type))
                start.append(f"if {options} fi;  /* a constant with no value: every value in range */")
        [initial] = [n for n in m.nodes if n.kind == "initial" and n.parent is None]
        [t0] = [t for t in m.transitions if t.source == initial.path]
        body = ["atomic {", *start, *self.take(t0, initial.path), "}"]
        lines = [f"/* {title} */", f"/* {self.monitor.assertion}, generated by benchmarks/peers.py */", "",
                 f"active proctype {MACHINE}() {{", *_indent(decls + self.monitor.declarations(), 1), *_indent(body, 1)]
        for block in self.blocks:
            lines += _indent(block, 1)
        lines += ["terminated:  /* after UR::terminate: refuses everything, tock included */", "  skip", "}", ""]
        return "\n".join(_format(lines))


def _indent(code: Code, n: int) -> Code:
    return ["  " * n + line for line in code]


def _format(lines: Code) -> Code:
    """Indent the nested `if`/`atomic` blocks of generated code (labels stay at the left)."""
    out, depth = [], 0
    for raw in lines:
        line = raw.strip()
        code = re.sub(r"/\*.*?\*/", "", line).strip()
        if code.startswith(("fi", "}")):
            depth -= 1
        if re.match(r"^[A-Za-z_]\w*:(\s|$)", line):
            out.append(line)
        elif line.startswith("::"):
            out.append("  " * (depth - 1) + line)
        else:
            out.append("  " * depth + line)
        if code == "if" or code.endswith("{"):
            depth += 1
    return out


def promela(joints: int, ranges: Ranges, assertion: str) -> str:
    """The Promela text of the UR machine of the `joints`-joint example with the check of `assertion`."""
    project = tockbmc.load(EXAMPLES[joints])
    [machine] = [m for m in project.machines if m.name == MACHINE]
    monitor = monitor_for(project, assertion)
    title = (f"UR of {EXAMPLES[joints].relative_to(REPO)}: distances -{ranges.dist}..{ranges.dist}, "
             f"times {ranges.time[0]}..{ranges.time[1]}, n_waypoints 0..{ranges.waypoints}")
    return Translation(project, machine, monitor, ranges).promela(title)


# ----------------------------------------------------------------------------- running the tools


@dataclass
class Run:
    returncode: int | None  # None: killed at the time limit
    output: str
    errors: str
    seconds: float
    peak_mb: float


def measured(cmd: list[str], cwd: Path, timeout: float, memory_mb: int | None = None) -> Run:
    """Run `cmd`, with its own peak RSS (os.wait4), killed after `timeout` seconds."""
    def limit() -> None:
        if memory_mb is not None:
            size = memory_mb * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (size, size))
    out, err = cwd / ".out", cwd / ".err"
    start = time.perf_counter()
    with open(out, "w") as sink, open(err, "w") as errors:
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=sink, stderr=errors, preexec_fn=limit)
        killed = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - start > timeout and not killed:
                proc.kill()
                killed = True
            time.sleep(0.02)
    proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.perf_counter() - start
    return Run(None if killed else proc.returncode, out.read_text(errors="replace"), err.read_text(errors="replace"),
               seconds, usage.ru_maxrss / 1024)


@dataclass
class SpinResult:
    verdict: str  # holds | violated | out of memory | timeout | error
    seconds: float  # spin -a + gcc + pan
    search: float
    reported_mb: float | None
    peak_mb: float
    states: int | None
    nominal: int | None


def spin(text: str, timeout: float, memory_mb: int) -> SpinResult:
    """Compile and run Spin's verifier on `text` in a temporary directory."""
    with tempfile.TemporaryDirectory(prefix="tockbmc-peers-") as tmp:
        work = Path(tmp)
        (work / "ur.pml").write_text(text)
        start = time.perf_counter()
        for cmd in (["spin", "-a", "ur.pml"],
                    ["gcc", "-O2", "-DSAFETY", "-DBFS", f"-DMEMLIM={memory_mb}", "-o", "pan", "pan.c"]):
            r = subprocess.run(cmd, cwd=work, capture_output=True, text=True)
            if r.returncode != 0:
                raise RuntimeError(f"{' '.join(cmd)}: {r.stdout}{r.stderr}")
        compile_seconds = time.perf_counter() - start
        run = measured(["./pan", "-n"], work, timeout, memory_mb + 512)
    out = run.output
    states = _number(r"(\d+) states, stored", out)
    nominal = _number(r"(\d+) nominal states", out)
    reported = re.search(r"([\d.]+)\s+total actual memory usage", out)
    if run.returncode is None:
        verdict = "timeout"
        progress = re.findall(r"States=\s*([\d.e+]+)", out)
        states = int(float(progress[-1])) if progress else None
    elif "MEMLIM" in out or "out of memory" in out:
        verdict = "out of memory"
    elif re.search(r"errors: [1-9]", out):
        verdict = "violated"
    elif "errors: 0" in out:
        verdict = "holds"
    else:
        verdict = "error"
    if verdict not in ("holds", "violated"):
        nominal = None  # the count of a search cut short means little
    return SpinResult(verdict, compile_seconds + run.seconds, run.seconds,
                      float(reported[1]) if reported else None, run.peak_mb, states, nominal)


def _number(pattern: str, text: str) -> int | None:
    m = re.search(pattern, text)
    return int(m[1]) if m else None


@dataclass
class TockbmcResult:
    verdict: str
    proof: str
    seconds: float  # the process
    check: float  # tockbmc's own time for the assertion
    peak_mb: float


def tockbmc_check(joints: int, assertion: str, ranges: list[str], timeout: float, options: tuple[str, ...] = ()
                  ) -> TockbmcResult:
    """`tockbmc check -a ASSERTION --format json` on the `joints`-joint example, as a process of its own."""
    cmd = [sys.executable, "-c", "from tockbmc.cli import main; main()", "check", str(EXAMPLES[joints]),
           "-a", assertion, "--format", "json", *(a for r in ranges for a in ("--range", r)), *options]
    with tempfile.TemporaryDirectory(prefix="tockbmc-peers-") as tmp:
        run = measured(cmd, Path(tmp), timeout)
    if run.returncode is None:
        return TockbmcResult("timeout", "none", run.seconds, run.seconds, run.peak_mb)
    doc = json.loads(run.output[run.output.index("{"):])
    [r] = doc["results"]
    return TockbmcResult(r["verdict"], r["proof"], run.seconds, r["seconds"], run.peak_mb)


# ----------------------------------------------------------------------------- the table


@dataclass(frozen=True)
class Row:
    joints: int
    dist: int | None  # None: unbounded (tockbmc only)
    time: tuple[int, int] | None

    @property
    def label(self) -> str:
        """How the row is printed."""
        if self.dist is None or self.time is None:
            return f"{self.joints} joints, unbounded"
        return f"{self.joints} joints, d ±{self.dist}, t {self.time[0]}..{self.time[1]}"

    def tockbmc_ranges(self) -> list[str]:
        """The `--range` arguments of tockbmc for this row."""
        if self.dist is None or self.time is None:
            return []
        return [f"core_int={self.time[0]}..{self.time[1]}", f"core_real=-{self.dist}..{self.dist}"]


ROWS = [Row(2, 1, (-1, 1)), Row(2, 1, (0, 2)), Row(2, 5, (0, 10)), Row(2, 20, (0, 40)),
        Row(6, 1, (0, 2)), Row(6, 5, (0, 10)), Row(6, None, None)]


def _mb(x: float | None) -> str:
    return "-" if x is None else f"{x:.0f}"


def main() -> None:
    """Print the table, or with --promela-only one Promela model."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--promela-only", action="store_true", help="print the Promela model on stdout and stop")
    parser.add_argument("--joints", type=int, choices=sorted(EXAMPLES), default=2)
    parser.add_argument("--dist", type=int, default=1, help="distances -DIST..DIST (with --promela-only)")
    parser.add_argument("--time", default="0..2", help="times LO..HI (with --promela-only)")
    parser.add_argument("--assertion", choices=["A3", "A6"], default="A3")
    parser.add_argument("--waypoints", type=int, default=3, help="n_waypoints ranges over 0..N in Spin")
    parser.add_argument("--rows", type=int, nargs="+", help=f"which rows (0..{len(ROWS) - 1}; default all)")
    parser.add_argument("--spin-timeout", type=float, default=120.0, help="seconds per Spin search")
    parser.add_argument("--spin-memory-mb", type=int, default=3072, help="pan's -DMEMLIM")
    parser.add_argument("--tockbmc-timeout", type=float, default=300.0)
    parser.add_argument("--robotool", action="store_true",
                        help="check with tockbmc's --robotool (FDR's finite check: reals as integers, as in the "
                             "Promela model; the portfolio races the explicit engine there)")
    args = parser.parse_args()
    if args.promela_only:
        lo, hi = (int(x) for x in args.time.split(".."))
        sys.stdout.write(promela(args.joints, Ranges(args.dist, (lo, hi), args.waypoints), args.assertion))
        return
    if shutil.which("spin") is None or shutil.which("gcc") is None:
        sys.exit("needs spin and gcc on PATH (Debian: apt-get install -y spin gcc)")
    rows = [ROWS[i] for i in args.rows] if args.rows else ROWS
    print(f"Spin: BFS, -DMEMLIM={args.spin_memory_mb}, {args.spin_timeout:.0f} s per search; "
          f"n_waypoints 0..{args.waypoints} in Spin, unbounded in tockbmc; times are wall seconds"
          + ("; tockbmc with --robotool" if args.robotool else ""))
    head = (f"{'model and ranges':30} {'':3} {'Spin':>14} {'s (search)':>15} {'MB rep/RSS':>11} {'states (nominal)':>22}"
            f"   {'tockbmc':>16} {'s (check)':>14} {'MB':>5} {'Spin/tockbmc':>12}")
    print(head)
    print("-" * len(head))
    for row in rows:
        for name in ("A3", "A6"):
            if row.dist is None or row.time is None:
                s = None
            else:
                text = promela(row.joints, Ranges(row.dist, row.time, args.waypoints), name)
                s = spin(text, args.spin_timeout, args.spin_memory_mb)
            t = tockbmc_check(row.joints, name, row.tockbmc_ranges(), args.tockbmc_timeout,
                              ("--robotool",) if args.robotool else ())
            verdict = t.verdict + (" (k-ind.)" if t.proof == "k-induction" else " (PDR)" if t.proof == "invariant" else "")
            if s is None:
                spin_part = f"{'n/a: unbounded':>14} {'':>15} {'':>11} {'':>22}"
                ratio = "-"
            else:
                states = "-" if s.states is None else f"{s.states:,}" + (f" ({s.nominal:,})" if s.nominal else "")
                spin_part = (f"{s.verdict:>14} {s.seconds:>6.1f} ({s.search:>6.1f}) "
                             f"{_mb(s.reported_mb) + '/' + _mb(s.peak_mb):>11} {states:>22}")
                ratio = f"{s.seconds / t.seconds:.1f}" + ("+" if s.verdict in ("timeout", "out of memory") else "")
            print(f"{row.label:30} {name:3} {spin_part}   {verdict:>16} {t.seconds:>5.1f} ({t.check:>5.1f}) "
                  f"{t.peak_mb:>5.0f} {ratio:>12}", flush=True)


if __name__ == "__main__":
    main()
