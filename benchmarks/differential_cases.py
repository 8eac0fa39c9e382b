"""Differential testing: random small models, checked by BMC and by the explicit engine.

`machine_text` writes a random RoboChart state machine (states, a composite
state, a junction, guards over a small integer and a clock, inputs, outputs,
waits, platform calls, statement and trigger deadlines, a final state) and
`network_text` a controller of two or three of them in a chain of synchronous
or asynchronous connections, calling a platform operation or one the
controller defines; `compare` checks the assertions with both engines and
says where they disagree.  Only definite outcomes are compared:
a counterexample or witness found, a proof for every length (BMC's
k-induction), or a search that explored every reachable configuration (the
explicit engine).  A counterexample found by one engine and ruled out by the
other is a disagreement; so is a pair of counterexamples whose visible lengths
differ (both engines are asked for the fewest visible steps), except that BMC
may show a time-only deadlock after tocks that the explicit engine need not
show (see `_same_length`).  Used by
`tests/test_differential.py` (Hypothesis) and `benchmarks/differential.py`.
"""

from __future__ import annotations

import random
import re
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import tockbmc
from tockbmc.explicit.engine import check_explicit
from tockbmc.model import ast
from tockbmc.model.config import configure
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.readings import Reading
from tockbmc.model.result import Proof, Result
from tockbmc.parallel import InProcesses, Job

RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
STATEMENTS = ["b!x", "x = 0", "x = 1", "x = -x", "wait(1)", "#C", "c", "b!(x + 1)", "op(x)", "c <{1}"]
CONDITIONS = ["x > 0", "x == 0", "x < 1", "since(C) >= 1", "since(C) < 2", "x != 1"]
# With `data`: a sequence, a set and a tuple, updated and read, and an input sequence `d` whose
# length is bounded by a range on its path (`M::d`), as the explicit engine needs one; and a
# sequence and a set of nat, whose items a step may not make negative (docs/semantics.md §10).
DATA_DECLARATIONS = ["  event d : Seq(int)", "  var s : Seq(int) = <>", "  var u : Set(int) = {}",
                     "  var p : int * boolean = (| 0, true |)", "  var f : int -> int = lambda k : int @ k + 1",
                     "  var n : Seq(nat) = <>", "  var w : Set(nat) = {}"]
DATA_STATEMENTS = ["s = s ^ <x>", "s = tail(s)", "u = union(u, {x})", "u = diff(u, {x, 1})", "p = (| x, not p[2] |)",
                   "x = size(s) - 1", "s = reverse(s) ^ <p[1]>", "b!size(filter(s, u))", "x = p[1]",
                   # lambda (a closure over x), application, s[i] = e, p[k] = e, set comprehensions
                   "f = lambda k : int @ k - x", "x = f(x)", "if size(s) > 0 then s[1] = x end", "p[2] = x > 0",
                   "u = {k : int | k in u /\\ k != x}", "u = {k : int | k in u @ -k}",
                   "n = <x> ^ n", "n = tail(n)", "w = union(w, {x + 1})", "n = s", "d?n"]
DATA_CONDITIONS = ["size(s) < 2", "x in u", "p[2]", "size(s) > 0 /\\ head(s) == x", "s == <>",
                   "subseteq(u, {0, 1})", "exists i : int @ i in u /\\ i > x", "forall i : int | i in u @ i <= p[1]",
                   "elems(s) == u", "p == (| x, true |)", "f(x) > 0", "x in {k : int | k > 0}",
                   "1 in {k : int | k in u @ k + 1}", "size(n) > 1", "0 in w", "x in elems(n)"]
DATA_TRIGGERS = ["d?s", "d.<1>"]
# With `enums`: an enumeration whose literals take parameters (an algebraic datatype), in a
# variable and on an event, built, compared and received (ten values with core_int=-1..1).
ENUM_TYPE = "enumeration V { V0 V1(int) V2(boolean, int) }\n"
ENUM_DECLARATIONS = ["  var v : V = V1(0)", "  event g : V"]
ENUM_STATEMENTS = ["v = V1(x)", "v = V2(x > 0, -x)", "v = V0", "g!v", "g!V2(true, x)"]
ENUM_CONDITIONS = ["v == V1(x)", "v != V0", "v == V2(false, 0) \\/ v == V1(1)", "v != V1(-x)"]
ENUM_TRIGGERS = ["g?v", "g.V0"]
# With `durings`: the composite state's during action, which runs beside its children (§4.1).
DURING_ACTIONS = ["wait(1) ; x = 1", "b!x", "x = -x ; c", "wait(1) ; b!(x + 1)", "op(x) ; x = 0", "a?x", "wait(2)"]
# With `unset`: what the model leaves for the reading to fill in (docs/semantics.md §6.6), variables
# without an initial value and functions without a body, with arithmetic that leaves core_int.
UNSET_DECLARATIONS = ["  var u : int", "  var q : boolean"]
UNSET_FUNCTIONS = "function fz(n : int) : int { }\nfunction fb(n : int) : boolean { }\n"
UNSET_STATEMENTS = ["u = u + 1", "x = fz(x)", "u = x * 2", "q = not q", "u = -u", "b!u", "u = u - x",
                    "q = fb(u)"]
UNSET_CONDITIONS = ["u > 1", "q", "fb(x)", "fz(u) == 0", "u == x + 1", "u < -1"]
# With `shared`: a variable the machines require (RoboTool's memory model, docs/semantics.md §5.5): in
# a controller each machine keeps a copy that the controller's memory updates; a machine on its own
# writes it visibly (`M::set_s`) and its environment writes it (`M::set_EXT_s`).
SHARED_INTERFACE = "interface Shared { var s : int }\n"
SHARED_STATEMENTS = ["s = x", "s = s + 1", "b!s", "x = s", "s = -s"]
SHARED_CONDITIONS = ["s > 0", "s == x", "s != 1"]
SHARED_KEEPERS = ["  var s : int", "  var s : int = 1", "  requires Shared"]
DATA_RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))},
                     {"M::d": Range(Fraction(0), Fraction(2))})


def machine_text(pick: Callable[[list], object], number: Callable[[int, int], int],
                 name: str = "M", data: bool = False, enums: bool = False,
                 durings: bool = False, unset: bool = False, shared: bool = False) -> tuple[str, list[str]]:
    """A random machine and the names of its states; `pick(options)` and `number(lo, hi)` choose.
    With `data`, its variables include a sequence, a set and a tuple (`DATA_STATEMENTS`, …); with
    `enums`, a value of an enumeration whose literals take parameters (`ENUM_STATEMENTS`, …); with
    `durings`, its composite state (always there) has a during action (`DURING_ACTIONS`); with
    `unset`, variables without an initial value and functions without a body (`UNSET_STATEMENTS`, …)."""
    statements = STATEMENTS + DATA_STATEMENTS if data else STATEMENTS
    conditions = CONDITIONS + DATA_CONDITIONS if data else CONDITIONS
    triggers = ["", "a?x", "c", "a.1", "c <{1}", *(DATA_TRIGGERS if data else [])]
    if enums:
        statements, conditions, triggers = (statements + ENUM_STATEMENTS, conditions + ENUM_CONDITIONS,
                                            triggers + ENUM_TRIGGERS)
    if unset:
        statements, conditions = statements + UNSET_STATEMENTS, conditions + UNSET_CONDITIONS
    if shared:
        statements, conditions = statements + SHARED_STATEMENTS, conditions + SHARED_CONDITIONS
    n = number(1, 4)
    states = [f"S{k}" for k in range(n)]
    composite = number(0, 1) == 1 or durings
    lines = [f"stm {name} {{", "  requires Ops", "  event a : int", "  event b : int", "  event c",
             "  var x : int = 0", "  clock C", *(DATA_DECLARATIONS if data else []),
             *(ENUM_DECLARATIONS if enums else []), *(UNSET_DECLARATIONS if unset else []),
             *(["  requires Shared"] if shared else []), "  initial i"]
    for s in states:
        entry = f" entry {pick(statements)}" if number(0, 1) else ""
        if s == "S0" and composite:
            during = [f"    during {pick(DURING_ACTIONS)}"] if durings else []
            lines += [f"  state S0 {{{entry}", *during, "    initial j", "    state In {}", "    state Out {}",
                      "    transition u0 { from j to In }",
                      f"    transition u1 {{ from In to Out condition {pick(conditions)} }}",
                      *(["    transition u2 { from Out to In trigger a?x }"] if durings else []), "  }"]
        else:
            lines.append(f"  state {s} {{{entry} }}")
    targets = list(states)
    if number(0, 1):
        lines.append("  junction J")
        targets.append("J")
    if number(0, 1):
        lines.append("  final F")
        targets.append("F")
    lines.append("  transition t0 { from i to S0 }")
    sources = [*states, *(["J"] if "J" in targets else [])]
    count = number(1, 5)
    for k in range(count):
        src = pick(sources)
        dst = pick(targets)
        parts = [f"from {src} to {dst}"]
        if src != "J":
            trigger = pick(triggers)
            if trigger:
                parts.append(f"trigger {trigger}")
        if number(0, 1) or src == "J":
            parts.append(f"condition {pick(conditions)}")
        if number(0, 2) == 0:
            parts.append(f"action {pick(statements)}")
        lines.append(f"  transition t{k + 1} {{ {' '.join(parts)} }}")
    if "J" in targets and not any("from J " in line for line in lines):
        lines.append(f"  transition tj {{ from J to {states[0]} }}")
    lines.append("}")
    return ((ENUM_TYPE if enums else "") + (UNSET_FUNCTIONS if unset else "") + (SHARED_INTERFACE if shared else "")
            + "interface Ops { op(n : int) }\n" + "\n".join(lines) + "\n", states)


def data_machine_text(pick: Callable[[list], object], number: Callable[[int, int], int],
                      enums: bool = False, durings: bool = False) -> tuple[str, list[str]]:
    """A random machine with sequences, sets and tuples among its data (`machine_text`)."""
    rct, states = machine_text(pick, number, data=True, enums=enums, durings=durings)
    return "import sequence_toolkit::*\nimport set_toolkit::*\n" + rct, states


def network_text(pick: Callable[[list], object], number: Callable[[int, int], int],
                 bidirectional: bool = False, shared: bool = False) -> tuple[str, list[str]]:
    """A random controller M of two or three random machines in a chain: P's output b feeds Q's input
    a, and so on (each link synchronous or asynchronous); the environment feeds P's a, and the last
    machine's b is M's output.  The machines' `op(x)` is a platform operation, or one M defines
    (a small graph with a variable, a wait or a guard, and perhaps an output on b).  With
    `bidirectional`, one of the two boundary connections is `[ mult ]` and its machine both sends
    and receives on it (`_bidirectional`, drawn after everything else, so that a seed's case without
    it is unchanged)."""
    names = ["P", "Q", "R"][:number(2, 3)]
    texts: list[str] = []
    p_states: list[str] = []
    all_states: list[list[str]] = []
    for k, name in enumerate(names):
        text, states = machine_text(pick, number, name, shared=shared)
        texts.append(text if k == 0 else text.split("\n", 2 if shared else 1)[-1])  # one `interface Ops`
        p_states = p_states or states
        all_states.append(states)
    lines = ["controller M {", "  event a : int", "  event b : int"]
    if shared:  # the controller keeps the variable (with or without an initial value) or requires it
        lines.append(str(pick(SHARED_KEEPERS)))
    lines += _operation(pick, number) if number(0, 1) else ["  requires Ops"]
    lines += [f"  sref {n} = {n}" for n in names]
    lines.append(f"  connection M on a to {names[0]} on a")
    for sender, receiver in zip(names, names[1:]):
        lines.append(f"  connection {sender} on b to {receiver} on a{pick(['', ' (_async)'])}")
    lines += [f"  connection {names[-1]} on b to M on b", "}"]
    if bidirectional:
        _bidirectional(pick, number, names, texts, all_states, lines)
    return "".join(texts) + "\n".join(lines) + "\n", [f"P::{s}" for s in p_states]


def _bidirectional(pick: Callable[[list], object], number: Callable[[int, int], int], names: list[str],
                   texts: list[str], states: list[list[str]], lines: list[str]) -> None:
    """Make M's input a (the first machine's) or its output b (the last machine's) a bidirectional
    connection, `[ mult ]`, drawn either way round (docs/semantics.md §5.3: both directions are M's,
    `M::e.in` and `M::e.out`); its machine gets a transition that sends on that event and, unless it
    has one, one that receives on it.  (Synchronous only: an asynchronous bidirectional connection of
    a machine is not encoded yet.)"""
    event = pick(["a", "b"])
    k = 0 if event == "a" else len(names) - 1
    machine = names[k]
    boundary = [i for i, line in enumerate(lines) if line.strip() in
                (f"connection M on a to {machine} on a", f"connection {machine} on b to M on b")]
    i = boundary[0] if event == "a" else boundary[-1]
    ends = (f"M on {event}", f"{machine} on {event}")
    source, target = ends if number(0, 1) else ends[::-1]
    lines[i] = f"  connection {source} to {target} [ mult ]"
    extra = []
    send = pick([f"{event}!x", f"{event}!(x + 1)", f"{event}!0"])
    trigger = pick(["", "c", f"{event}?x", f"{event}.1", "a?x" if event == "b" else "c"])
    parts = [f"from {pick(states[k])} to {pick(states[k])}", *([f"trigger {trigger}"] if trigger else []),
             f"action {send}"]
    extra.append(f"  transition m0 {{ {' '.join(parts)} }}")
    if f"trigger {event}" not in texts[k] and not trigger.startswith(event):
        extra.append(f"  transition m1 {{ from {pick(states[k])} to {pick(states[k])} "
                     f"trigger {pick([f'{event}?x', f'{event}.1'])} }}")
    body = texts[k].rstrip("\n")
    assert body.endswith("\n}")
    texts[k] = body[:-1] + "\n".join(extra) + "\n}\n"


def _operation(pick: Callable[[list], object], number: Callable[[int, int], int]) -> list[str]:
    entry = pick(["k = n + 1", "k = -n", "wait(1)", "b!n", "k = n ; b!k"])
    parts = ["from s to f"]
    if number(0, 1):
        parts.append(f"condition {pick(['n > 0', 'k == 0', 'n != 1'])}")
    if number(0, 1):
        parts.append(f"action {pick(['b!k', 'k = k + n', 'wait(1)'])}")
    lines = ["  operation op(n : int) {", "    event b : int", "    var k : int = 0", "    initial i",
             f"    state s {{ entry {entry} }}", "    final f", "    transition t0 { from i to s }",
             f"    transition t1 {{ {' '.join(parts)} }}"]
    if any(part.startswith("condition") for part in parts):
        lines.append("    transition t2 { from s to f condition true }")  # a way out when the guard fails
    return [*lines, "  }"]


# With `operations`, the machine's body (the first machine's, in a controller) as a defined operation
# `Mop(k : int)` checked on its own (docs/semantics.md §4.8): `k` initialises x and replaces some
# constants its statements and guards read, each occurrence with probability 1/2.
PARAMETER_USES = [(r"x > 0", "x > k"), (r"x = 1\b", "x = k"), (r"b!\(x \+ 1\)", "b!(x + k)"), (r"x != 1", "x != k"),
                  (r"x < 1", "x < k"), (r"x == 0", "x == k"), (r"trigger a\.1", "trigger a.k"), (r"op\(x\)", "op(k)")]


def operation_text(rct: str, machine: str, pick: Callable[[list], object],
                   number: Callable[[int, int], int]) -> str:
    """Machine `machine`'s body in `rct` as `operation Mop(k : int)`, whose x starts at k and whose
    statements and guards read k in place of some constants (`PARAMETER_USES`)."""
    start = rct.index(f"stm {machine} {{\n")
    end = rct.index("\n}\n", start) + 3
    body = rct[start:end].replace(f"stm {machine} {{", "operation Mop(k : int) {", 1)
    body = body.replace("var x : int = 0", "var x : int = k", 1)
    for pattern, replacement in PARAMETER_USES:
        body = re.sub(pattern, lambda m, r=replacement: r if number(0, 1) else m.group(0), body)
    return body


def operation_assertions(states: list[str], pick: Callable[[list], object]) -> str:
    """The core forms of `Mop`, timed and untimed, one reachability, and traces refinements of
    specifications over its events (`OP_Mop::…`, `OPERATION_SPECS`), each with k set to -1, 0 or 1
    (or, for one, left at RoboTool's default 0)."""
    def k() -> str:
        return f" with parameter k of Mop set to {pick(['-1', '0', '1'])}"

    timed = ["does not terminate", "is timelock-free", "is deadlock-free", "terminates", "is divergence-free",
             "is deterministic"]
    untimed = ["does not terminate", "is deadlock-free", "terminates", "is divergence-free", "is deterministic"]
    text = "".join(f"assertion O{n}: Mop {f}{k()}.\n" for n, f in enumerate(timed))
    text += f"assertion O{len(timed)}: {pick(states)} is reachable in Mop{k()}.\n"
    text += "".join(f"untimed assertion OU{n}: Mop {f}{k()}.\n" for n, f in enumerate(untimed))
    text += OPERATION_SPECS
    refinements = [("untimed", "OAny"), ("untimed", "ONoB1"), ("timed", "OTAny"), ("timed", "OTNoCall0"),
                   ("timed", "OEchoAEnds")]
    text += "".join(f"{t} assertion OR{n}: Mop refines {spec} in the traces model{k() if n else ''}.\n"
                    for n, (t, spec) in enumerate(refinements))
    return text


# Permissive specifications of the operation: every event (`OAny`, `OTAny` with tock too), every
# event but one value (`ONoB1`, `OTNoCall0`), and `OEchoA` (`EchoA` of `SPECS`); each may end with ✓
# at any time, as the operation does at its final state (its terminate hidden, docs/semantics.md
# §4.8).  In a Timed section `P [] SKIP` and `P /\ SKIP` refuse tock (tock is shared by both sides,
# §8.1, and SKIP refuses it), so there ✓ comes from `OTEnd`, which lets any number of tocks pass first.
OPERATION_SPECS = """csp OSpecs csp-begin
OAny = (OP_Mop::a.in?x -> OAny) [] (OP_Mop::a.out?x -> OAny) [] (OP_Mop::b.in?x -> OAny)
       [] (OP_Mop::b.out?x -> OAny) [] (OP_Mop::c.in -> OAny) [] (OP_Mop::c.out -> OAny)
       [] (OP_Mop::opCall?x -> OAny) [] SKIP
ONoB1 = CHAOS(diff(Events, {OP_Mop::b.out.1})) /\\ SKIP
csp-end
timed csp OTSpecs csp-begin
Timed(OneStep) {
  OTEnd = SKIP |~| (WAIT(1) ; OTEnd)
  OTEvery = (OP_Mop::a.in?x -> OTEvery) [] (OP_Mop::a.out?x -> OTEvery) [] (OP_Mop::b.in?x -> OTEvery)
            [] (OP_Mop::b.out?x -> OTEvery) [] (OP_Mop::c.in -> OTEvery) [] (OP_Mop::c.out -> OTEvery)
            [] (OP_Mop::opCall?x -> OTEvery)
  OTAny = OTEvery /\\ OTEnd
  OTNoCall0 = CHAOS(diff(Events, {OP_Mop::opCall.0})) /\\ OTEnd
  OOthers(P) = (OP_Mop::a.out?y -> P) [] (OP_Mop::b.in?y -> P) [] (OP_Mop::c.in -> P) [] (OP_Mop::c.out -> P)
               [] (OP_Mop::opCall?y -> P)
  OEchoA = (OP_Mop::a.in?x -> OEchoed(x)) [] (OP_Mop::b.out?w -> OEchoA) [] OOthers(OEchoA)
  OEchoed(x) = (OP_Mop::a.in?z -> OEchoed(z)) [] (OP_Mop::b.out!x -> OEchoA) [] OOthers(OEchoA)
  OEchoAEnds = OEchoA /\\ OTEnd
}
csp-end
"""


def bidirectional_assertions(rct: str) -> str:
    """Traces refinements of specifications that tell apart values in both directions of M's
    bidirectional event (`network_text(bidirectional=True)`), timed and untimed."""
    e = re.search(r"connection \w+ on (\w+) to \w+ on \w+ \[ mult \]", rct).group(1)  # type: ignore[union-attr]
    return f"""timed csp BSpecs csp-begin
Timed(OneStep) {{
  BEnds(P) = P [| {{|M::terminate|}} |> SKIP
  BNoOut1 = BEnds(CHAOS(diff(Events, {{M::{e}.out.1}})))
  BNoIn0 = BEnds(CHAOS(diff(Events, {{M::{e}.in.0}})))
  BNoOut1AfterIn1 = BEnds(CHAOS(Events) [| {{M::{e}.in.1}} |> CHAOS(diff(Events, {{M::{e}.out.1}})))
}}
csp-end
csp BUSpecs csp-begin
BUNoIn1AfterOut0 = CHAOS(Events) [| {{M::{e}.out.0}} |> CHAOS(diff(Events, {{M::{e}.in.1}}))
BUNoIn1AfterOut0Ends = BUNoIn1AfterOut0 [| {{|M::terminate|}} |> SKIP
csp-end
timed assertion B0: M refines BNoOut1 in the traces model.
timed assertion B1: M refines BNoIn0 in the traces model.
timed assertion B2: M refines BNoOut1AfterIn1 in the traces model.
untimed assertion B3: M refines BUNoIn1AfterOut0Ends in the traces model.
"""


def assertions_text(states: list[str], pick: Callable[[list], object], specs: bool = False,
                    untimed: bool = False, timed: bool = True, tick_tock: bool = False) -> str:
    """Nine assertions of M; with `specs`, also four refinements of specifications that tell some
    values of M's events apart (an input, an output, a call), after the nine; with `untimed`, the
    untimed forms (docs/semantics.md §7.11), refinements in the failures models (§7.12) and the
    timed negations the nine leave out (`NEGATED`); with
    `tick_tock`, refinements in the tick-tock model (§7.13), either side; `timed=False` leaves the
    nine out."""
    forms = ["M does not terminate", "M is timelock-free", "M is deadlock-free", "M is not timelock-free",
             f"{pick(states)} is reachable in M", f"{pick(states)} is not reachable in M", "M terminates",
             "M is divergence-free", "M is deterministic"]
    text = "".join(f"assertion A{k}: {f}.\n" for k, f in enumerate(forms)) if timed else ""
    if specs:
        text += SPECS
    if untimed:
        reach = f"{pick(states)} is reachable in M"
        text += "".join(f"untimed assertion U{k}: {f}.\n" for k, f in enumerate(UNTIMED + [reach]))
        text += FAILURES
        text += "".join(f"timed assertion N{k}: {f}.\n" for k, f in enumerate(NEGATED))
    if tick_tock:
        text += TICK_TOCK
    return text


# The timed negations the nine leave out (checked with the untimed forms).
NEGATED = ["M is not deadlock-free", "M is not divergence-free", "M is not deterministic"]

UNTIMED = ["M does not terminate", "M is deadlock-free", "M terminates", "M is divergence-free",
           "M is deterministic", "M is not deadlock-free", "M is not divergence-free", "M is not deterministic"]

# Specifications over every channel of M: `Any` is stable only in states accepting one channel
# (every value of it), so M refines it in the failures model exactly where, stable and short of
# termination, M offers every value of some channel; `AnyOrStop` may also refuse everything at the
# start; `Ext` accepts every channel at once; `TAny`, in a Timed section, also accepts tock.  `Few`
# and `Stopped` refine M (the specification on the left) where M has their traces and refusals;
# `equals` and `is not equal to` check both directions.
FAILURES = """csp FSpecs csp-begin
Any = (M::a.in?x -> Any) |~| (M::b.out?x -> Any) |~| (M::c.in -> Any) |~| (M::c.out -> Any)
      |~| (M::opCall?x -> Any) |~| (M::terminate -> SKIP)
AnyOrStop = Any |~| STOP
Few = (M::c.in -> STOP) |~| (M::a.in.0 -> STOP) |~| (M::terminate -> SKIP)
Stopped = STOP
Ext = (M::a.in?x -> Ext) [] (M::b.out?x -> Ext) [] (M::c.in -> Ext) [] (M::c.out -> Ext)
      [] (M::opCall?x -> Ext) [] (M::terminate -> SKIP)
csp-end
timed csp TSpecs csp-begin
Timed(OneStep) {
  TAny = (M::a.in?x -> TAny) |~| (M::b.out?x -> TAny) |~| (M::c.in -> TAny) |~| (M::c.out -> TAny)
         |~| (M::opCall?x -> TAny) |~| (M::terminate -> SKIP)
}
csp-end
untimed assertion F0: M refines Any in the failures model.
untimed assertion F1: M refines AnyOrStop in the failures divergences model.
untimed assertion F2: M refines Ext in the failures model.
untimed assertion F3: M does not refine Any in the failures divergences model.
timed assertion F4: M refines TAny in the failures model.
untimed assertion F5: Few refines M in the failures model.
untimed assertion F6: Stopped refines M in the failures divergences model.
untimed assertion F7: M equals Few in the traces model.
untimed assertion F8: M is not equal to Few in the failures divergences model.
"""


# The tick-tock model, specifications in a Timed section (each prefix lets time pass while it waits).
# `TTAny` chooses one channel internally and keeps it while time passes, so after a tock of M only
# the branches accepting nothing M refuses there go on; `TTAnyOrStop` may also stop; `TTExt`
# accepts every channel, so M refines it only where it refuses nothing before a tock.  `TTFew` and
# `TTStopped` are on the left: M must make their observations, refusals before tocks included.
TICK_TOCK = """timed csp TTSpecs csp-begin
Timed(OneStep) {
  TTAny = (M::a.in?x -> TTAny) |~| (M::b.out?x -> TTAny) |~| (M::c.in -> TTAny) |~| (M::c.out -> TTAny)
          |~| (M::opCall?x -> TTAny) |~| (M::terminate -> SKIP)
  TTAnyOrStop = TTAny |~| STOP
  TTExt = (M::a.in?x -> TTExt) [] (M::b.out?x -> TTExt) [] (M::c.in -> TTExt) [] (M::c.out -> TTExt)
          [] (M::opCall?x -> TTExt) [] (M::terminate -> SKIP)
  TTFew = (M::c.in -> STOP) |~| (M::a.in.0 -> STOP) |~| (M::terminate -> SKIP) |~| STOP
  TTStopped = STOP
}
csp-end
timed assertion TT0: M refines TTAny in the tick-tock model.
timed assertion TT1: M refines TTAnyOrStop in the tick-tock model.
timed assertion TT2: M does not refine TTExt in the tick-tock model.
timed assertion TT3: TTFew refines M in the tick-tock model.
timed assertion TT4: TTStopped refines M in the tick-tock model.
"""


# Each names values of one of M's channels (its input a, its output b, its call op), and lets M
# terminate (`Ends`): CHAOS cannot do ✓, which M does after its terminate.  `EchoA` reads the value
# a receives: an output on b that follows an input on a, with no other event between, carries it.
SPECS = """timed csp Specs csp-begin
Timed(OneStep) {
  Ends(P) = P [| {|M::terminate|} |> SKIP
  NoB1 = Ends(CHAOS(diff(Events, {M::b.out.1})))
  NoCall0 = Ends(CHAOS(diff(Events, {M::opCall.0})))
  AnswerA1 = let Def = (CHAOS(Events) [| {M::a.in.1} |> ADeadline({|M::b.out|}, 1)); Def within Ends(timed_priority(Def))
  NoA0AfterB0 = Ends(CHAOS(Events) [| {M::b.out.0} |> CHAOS(diff(Events, {M::a.in.0})))
  Others(P) = (M::c.in -> P) [] (M::c.out -> P) [] (M::opCall?y -> P) [] (M::terminate -> SKIP)
  EchoA = (M::a.in?x -> Echoed(x)) [] (M::b.out?w -> EchoA) [] Others(EchoA)
  Echoed(x) = (M::a.in?z -> Echoed(z)) [] (M::b.out!x -> EchoA) [] Others(EchoA)
}
csp-end
timed assertion R0: M refines NoB1 in the traces model.
timed assertion R1: M refines NoCall0 in the traces model.
timed assertion R2: M refines AnswerA1 in the traces model.
timed assertion R3: M refines NoA0AfterB0 in the traces model.
timed assertion R4: M refines EchoA in the traces model.
"""


@dataclass
class Outcome:
    assertion: str
    bmc: str
    explicit: str
    agree: bool | None  # None: not comparable (unknown, unsupported, or a bounded verdict beside another)
    note: str = ""
    bounded: bool = False  # agree: both say holds, one or both only within its bound


def _definite_bmc(r: Result) -> str | None:
    if r.verdict not in ("holds", "violated"):  # an unknown may show the trace it could not decide
        return None
    if r.trace:
        return f"found:{r.verdict}"
    if r.proof.every_length:
        return f"proved:{r.verdict}"
    return None


def _definite_explicit(r: Result) -> str | None:
    if r.verdict not in ("holds", "violated"):
        return None
    if r.trace:
        return f"found:{r.verdict}"
    if r.proof == Proof.EXHAUSTIVE:
        return f"proved:{r.verdict}"
    return None


def compare(rct: str, assertions: str, bound: int = 16, explicit_bound: int = 8, timeout: float = 20,
            ranges: Ranges = RANGES, reading: Reading = Reading.DEFAULT) -> list[Outcome]:
    """Check a model with both engines; one `Outcome` per assertion.

    Both engines' counterexamples must have as many visible steps.  The explicit engine's have the
    fewest; BMC's have the fewest steps, internal ones included, so when the counts differ BMC is
    asked again for the fewest visible steps (`shortest="events"`), and if the explicit engine's still
    has fewer, with thrice the bound (BMC's internal steps count towards its bound) before it counts
    as a disagreement.  Two exceptions, where the engines differ by design: deadlocks of different
    kinds (each engine tries the kinds in its own order) are not compared by length, and a time-only
    deadlock may be shown by BMC after a few more tocks (`_same_length`).  Both engines read the
    model in `reading` (docs/semantics.md §6.6).
    """
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "m.rct").write_text(rct)
        (Path(d) / "m.assertions").write_text(assertions)
        project = tockbmc.load(d)
        symbolic = {r.assertion: r for r in _bmc(project, bound, ranges, timeout, reading=reading)}
        config = configure(project, ranges, reading=reading)
        concrete = {r.assertion: r for r in check_explicit(config.project, None, explicit_bound, ranges, {}, timeout,
                                                           200_000, config=config)}
        out = []
        for name, b in symbolic.items():
            e = concrete[name]
            db, de = _definite_bmc(b), _definite_explicit(e)
            if b.verdict == e.verdict == "holds" and (db is None or de is None) and not b.trace and not e.trace:
                # Both claim holds, one or both only within its bound (BMC's steps, the explicit
                # engine's visible steps): the claims agree as far as the weaker one goes.
                out.append(Outcome(name, b.verdict, e.verdict, True, _bounds(b, e, db, de), bounded=True))
                continue
            if db is None or de is None or "unsupported" in (b.verdict, e.verdict):
                out.append(Outcome(name, b.verdict, e.verdict, None))
                continue
            same: bool | None = b.verdict == e.verdict
            note = ""
            if same and db.startswith("found") and de.startswith("found"):
                same, note = _same_length(project, name, b, e, bound, timeout, ranges, reading)
            out.append(Outcome(name, b.verdict, e.verdict, same, note))
    return out


def _bounds(b: Result, e: Result, db: str | None, de: str | None) -> str:
    said = [f"bmc {'for every length' if db else f'within {b.bound} steps'}",
            f"explicit {'for every length' if de else 'within its bound'}"]
    return "holds: " + ", ".join(said)


def _same_length(project: object, name: str, b: Result, e: Result,
                 bound: int, timeout: float, ranges: Ranges, reading: Reading) -> tuple[bool | None, str]:
    """Whether two counterexamples of one verdict have as many visible steps (None: not comparable)."""
    if "is not deterministic" in (b.reason or "") and "is not deterministic" in (e.reason or ""):
        # BMC's pair of runs has the fewest steps of the two together, not the fewest visible events.
        return True, "nondeterminism: lengths not compared"
    kinds = _deadlock_kind(b), _deadlock_kind(e)
    if kinds[0] != kinds[1]:
        # Both engines find a deadlock, each by its own order of kinds (BMC: time only, then
        # divergence, or both together for `is not deadlock-free`; the explicit engine: time only,
        # then divergence).  Refusals of everything are compared, lengths included, by
        # `terminates`, whose violation is exactly one.
        return True, f"deadlocks of different kinds ({kinds[0]}, {kinds[1]}): lengths not compared"
    vb, ve = _visible(b), _visible(e)
    # A time-only deadlock is a configuration from which only tock is ever possible.  The explicit
    # engine computes that set exactly (a greatest fixpoint), so it can show one in the middle of a
    # `wait`; BMC recognises one only where no wait or deadline runs (a test on one configuration),
    # so it shows the same deadlock after the tocks that run the wait out, or another that needs no
    # wait.  Its trace is still replayed by the interpreter and the verdicts compared; not lengths
    # (so BMC is not asked again for fewer visible steps: that took 11 s of seed 100735's 13).
    if vb > ve and kinds == ("time only", "time only"):
        return True, f"time-only deadlock: bmc's has {vb - ve} more visible step(s)"
    note = ""
    for k in (bound, 3 * bound):
        if vb <= ve:
            break
        b = _bmc(project, k, ranges, timeout, "events", name, reading)[0]  # type: ignore[arg-type]
        if b.verdict != e.verdict or not b.trace or _deadlock_kind(b) != kinds[1] or "shortest" in b.extra:
            return None, f"BMC asked for the fewest visible steps within {k} steps: {b.verdict}, {b.reason}"
        vb, note = _visible(b), f"as many visible steps ({ve}) when BMC looks for the fewest"
    if vb != ve:
        return False, f"visible lengths {vb} (bmc) and {ve} (explicit)"
    return True, note


def _bmc(project: ast.Project, bound: int, ranges: Ranges, timeout: float, shortest: str = "steps",
         name: str | None = None, reading: Reading = Reading.DEFAULT) -> list[Result]:
    """BMC's results, one assertion after another in a worker process, which is ended where Z3 does
    not stop at the timeout (`parallel.Job.hard_limit`: the assertion is then `unknown`)."""
    config = configure(project, ranges, reading=reading)
    job = Job(config, bound, timeout, shortest, engine="bmc")
    work = [(job, i) for i, a in enumerate(config.project.assertions) if name is None or a.name == name]
    decided = dict(InProcesses(work, 1))
    return [decided[n] for n in range(len(work))]


def _deadlock_kind(r: Result) -> str | None:
    why = r.reason or ""
    for phrase, kind in (("refuses every event", "refusal"), ("nothing but tock", "time only"),
                         ("divergence", "divergence")):
        if phrase in why:
            return kind
    return None


def _visible(r: Result) -> int:
    return sum(1 for s in r.trace if s.kind != "internal")


def random_case(seed: int, controllers: float = 0.25, specs: bool = False, data: bool = False,
                untimed: bool = False, tick_tock: bool = False, operations: bool = False,
                bidirectional: bool = False, enums: bool = False, durings: bool = False,
                unset: bool = False, shared: bool = False) -> tuple[str, str]:
    """The case of a seed: a random machine, or with probability `controllers` a random controller;
    with `specs`, refinements of specifications too, with `untimed` the untimed and failures forms,
    with `tick_tock` refinements in the tick-tock model (`assertions_text`); with `data`, a machine
    with sequences, sets and tuples (`data_machine_text`; check it with `DATA_RANGES`).  With
    `operations`, the machine's body (the first machine's, in a controller) is also the operation
    `Mop(k : int)`, checked on its own (`operation_text`, `operation_assertions`); with
    `bidirectional`, a controller's boundary connection on a or b is `[ mult ]`
    (`network_text`, `bidirectional_assertions`).  Their draws come after all the others, so that
    without them a seed's case is as before.  With `enums`, the case is a machine (never a
    controller) with a value of an enumeration whose literals take parameters (`ENUM_TYPE`); with
    `durings`, a machine whose composite state has a during action (`DURING_ACTIONS`); with `unset`, a
    machine with variables without an initial value and functions without a body (`UNSET_STATEMENTS`);
    with `shared`, a controller (three cases in four) whose machines share a variable, or a machine
    that requires one (`SHARED_STATEMENTS`)."""
    rng = random.Random(seed)
    if shared:
        network = rng.random() < 0.75
        rct, states = (network_text(rng.choice, rng.randint, shared=True) if network
                       else machine_text(rng.choice, rng.randint, shared=True))
        return rct, assertions_text(states, rng.choice, specs, untimed, tick_tock=tick_tock)
    network = not data and not enums and not durings and not unset and rng.random() < controllers
    make = data_machine_text if data else network_text if network else machine_text
    extra = {k: True for k, on in (("enums", enums), ("durings", durings), ("unset", unset)) if on}
    rct, states = (network_text(rng.choice, rng.randint, bidirectional) if network and bidirectional
                   else make(rng.choice, rng.randint, **extra) if extra  # type: ignore[call-arg]
                   else make(rng.choice, rng.randint))
    assertions = assertions_text(states, rng.choice, specs, untimed, tick_tock=tick_tock)
    if network and bidirectional:
        assertions += bidirectional_assertions(rct)
    if operations and not data:
        machine = "P" if network else "M"
        rct += operation_text(rct, machine, rng.choice, rng.randint)
        body_states = [s.removeprefix("P::") for s in states]
        assertions += operation_assertions(body_states, rng.choice)
    return rct, assertions
