"""The explicit-state interpreter (tockbmc/explicit), tested directly on small models.

Each expectation is derived by hand from /work/shared/semantics.md §1–§2 (the rule is cited), as in
tests/test_semantics_rules.py, whose models several of these tests reuse.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import CONFORMANCE, EXAMPLE, write_files

import tockbmc
from tockbmc.explicit.interpreter import Config, Interpreter, NotInterpretable, Step, Unbounded

F = Fraction
M1_1 = {"core_int": (F(-1), F(1))}


def make(tmp_path: Path, rct: str, name: str, ranges: dict | None = None, **kw: object) -> Interpreter:
    write_files(tmp_path, {"m.rct": rct})
    project = tockbmc.load(tmp_path)
    element = project.element(name)
    assert element is not None, name
    return Interpreter(element, ranges or {}, **kw)  # type: ignore[arg-type]


def visible(trace: list[Step]) -> list[str]:
    return [s.event.name for s in trace if s.event is not None]


def search(it: Interpreter, goal: Callable[[Config], bool], max_visible: int = 8, limit: int = 20000,
           starts: list[Config] | None = None) -> list[str] | None:
    """A trace with the fewest visible events (tock included) to a configuration satisfying `goal`,
    or None if none is found within `max_visible` visible events (0-1 breadth-first search)."""
    starts = starts if starts is not None else it.initial()
    dist: dict[Config, int] = {}
    queue: deque[tuple[Config, tuple[str, ...]]] = deque()
    for c in starts:
        dist[c] = 0
        queue.append((c, ()))
    while queue:
        c, trace = queue.popleft()
        if dist[c] < len(trace):
            continue
        if goal(c):
            return list(trace)
        if len(dist) > limit:
            raise AssertionError("search limit reached")
        for s in it.steps(c):
            t = trace if s.event is None else (*trace, s.event.name)
            if len(t) > max_visible:
                continue
            if s.target not in dist or dist[s.target] > len(t):
                dist[s.target] = len(t)
                if s.event is None:
                    queue.appendleft((s.target, t))
                else:
                    queue.append((s.target, t))
    return None


def in_state(it: Interpreter, machine: str, state: str) -> Callable[[Config], bool]:
    return lambda c: it.states(c).get(machine) == state


def names(steps: list[Step]) -> list[str]:
    return sorted(s.event.name if s.event is not None else "τ" for s in steps)


def settle(it: Interpreter, c: Config) -> Config:
    """Follow internal steps while there is exactly one step and it is internal."""
    while True:
        ss = it.steps(c)
        if len(ss) == 1 and ss[0].kind == "internal":
            c = ss[0].target
        else:
            return c


def run_internal(it: Interpreter, c: Config, inputs: dict | None = None) -> Config:
    """Take the first internal step while there is one."""
    while True:
        internal = [s for s in it.steps(c, inputs) if s.kind == "internal"]
        if not internal:
            return c
        c = internal[0].target


def take(it: Interpreter, c: Config, name: str) -> Config:
    [s] = [s for s in it.steps(c) if s.event is not None and s.event.name == name]
    return s.target


# ---------------------------------------------------------------------------- rules 1–4


def test_rule1_maximal_progress(tmp_path) -> None:
    """§2.1: at time 0 the triggerless t1 is enabled, so tock is refused; `later` is never entered."""
    it = make(tmp_path, """
stm M {
  clock C
  initial i
  state s {}
  state now {}
  state later {}
  transition t0 { from i to s }
  transition t1 { from s to now condition since(C) == 0 }
  transition t2 { from s to later condition since(C) >= 1 }
}
""", "M")
    [c0] = it.initial()
    steps = it.steps(c0)
    assert [s.kind for s in steps] == ["internal"] and "t0" in steps[0].note
    c1 = steps[0].target
    assert it.states(c1) == {"M": "s"}
    assert [s.kind for s in it.steps(c1)] == ["internal"]  # t1 only, no tock
    assert search(it, in_state(it, "M", "now")) == []
    assert search(it, in_state(it, "M", "later"), max_visible=4) is None
    c2 = it.steps(c1)[0].target
    assert [s.kind for s in it.steps(c2)] == ["tock"]  # stable, nothing enabled: time passes


@pytest.mark.parametrize("stub", ["", "operation op(n : int) {\n  terminates\n}\n"], ids=["signature", "stub"])
def test_rule2_platform_call_is_urgent(tmp_path, stub) -> None:
    """§2.2: op(2) is the visible, urgent M::opCall.2; x = since(C) after it is 0."""
    it = make(tmp_path, """
interface I { op(n : int) }
""" + stub + """
stm M {
  requires I
  clock C
  var x : int = 0
  initial i
  state s { entry op(2) ; x = since(C) }
  state late {}
  state later {}
  transition t0 { from i to s }
  transition t1 { from s to late condition x >= 1 }
  transition t2 { from s to later condition since(C) >= 1 }
}
""", "M")
    [c0] = it.initial()
    c1 = settle(it, c0)
    steps = it.steps(c1)
    assert [(s.kind, s.event.name if s.event else None) for s in steps] == [("event", "M::opCall.2")]
    ev = steps[0].event
    assert ev is not None and ev.channel == ("M::opCall",) and ev.values == (2,)
    assert search(it, in_state(it, "M", "later")) == ["M::opCall.2", "tock"]
    assert search(it, in_state(it, "M", "late"), max_visible=4) is None


def test_rule2_defined_operation_runs_inline(tmp_path) -> None:
    """§2.2, §2.7: C defines double; M's call runs its graph (k = 6, output k on leaving s), then
    M's entry goes on with out!1: C::out.out.6 before C::out.out.1."""
    it = make(tmp_path, """
interface Ops { double(n : int) }
stm M {
  requires Ops
  event out : int
  initial i
  state s { entry double(3) ; out!1 }
  transition t0 { from i to s }
}
controller C {
  event out : int
  operation double(n : int) {
    event out : int
    var k : int = 0
    initial i
    state s { entry k = n * 2 }
    final f
    transition t0 { from i to s }
    transition t1 { from s to f action out!k }
  }
  sref m = M
  connection m on out to C on out
}
""", "C")
    [c0] = it.initial()
    c = settle(it, c0)
    assert names(it.steps(c)) == ["C::out.out.6", "tock"]
    assert it.variables(c)["M.double().k"] == 6
    c = settle(it, take(it, c, "C::out.out.6"))
    assert names(it.steps(c)) == ["C::out.out.1", "tock"]
    c = take(it, c, "C::out.out.1")
    assert it.states(c) == {"M": "s"}


def test_rule2_machine_alone_calls_required_operation_as_platform(tmp_path) -> None:
    """DESIGN.md: a machine checked on its own treats a required operation as the platform's."""
    write_files(tmp_path, {"m.rct": """
interface Ops { double(n : int) }
stm M {
  requires Ops
  initial i
  state s { entry double(3) }
  transition t0 { from i to s }
}
operation double(n : int) {
  initial i
  final f
  transition t0 { from i to f }
}
"""})
    project = tockbmc.load(tmp_path)
    machine = project.element("M")
    alone = Interpreter(machine, {})  # type: ignore[arg-type]
    assert names(it_steps_after_settle(alone)) == ["M::doubleCall.3"]
    inside = Interpreter(machine, {}, defined={"double": project.element("double")})  # type: ignore[arg-type,dict-item]
    c = settle(inside, inside.initial()[0])
    assert names(inside.steps(c)) == ["tock"]  # the operation ran to its final state


def it_steps_after_settle(it: Interpreter) -> list[Step]:
    return it.steps(settle(it, it.initial()[0]))


def test_rule3_and_4_assignments_urgent_outputs_not(tmp_path) -> None:
    """§2.3, §2.4: the assignment runs at time 0; the output e!5 may wait while time passes."""
    it = make(tmp_path, """
stm M {
  event e : int
  clock C
  var x : int = 0
  initial i
  state s { entry x = 7 ; e!5 ; x = since(C) }
  state late {}
  transition t0 { from i to s }
  transition t1 { from s to late condition x >= 1 /\\ x < 7 }
}
""", "M")
    [c0] = it.initial()
    c = settle(it, c0)
    assert it.variables(c)["M.x"] == 7
    steps = it.steps(c)
    assert names(steps) == ["M::e.out.5", "tock"]
    ev = next(s.event for s in steps if s.kind == "event")
    assert ev is not None and ev.channel == ("M::e", "out") and ev.values == (5,)
    assert search(it, in_state(it, "M", "late")) == ["tock", "M::e.out.5"]


# ---------------------------------------------------------------------------- rules 5–6


RULE5 = """
stm M {
  event e : int
  var x : int = 0
  initial i
  state s {}
  state big {}
  state pos {}
  transition t0 { from i to s }
  transition t1 { from s to big trigger e?x condition x > 5 }
  transition t2 { from s to pos trigger e?x condition x > 0 }
}
"""


def test_rule5_input_values_filtered_by_condition(tmp_path) -> None:
    """§2.5, §2.14: with core_int = -1..1 only e.in.1 is accepted; it binds x."""
    it = make(tmp_path, RULE5, "M", M1_1)
    c = settle(it, it.initial()[0])
    steps = it.steps(c)
    assert names(steps) == ["M::e.in.1", "tock"]
    c = take(it, c, "M::e.in.1")
    assert it.states(c) == {"M": "pos"} and it.variables(c)["M.x"] == 1


def test_rule5_unbounded_input_and_given_input(tmp_path) -> None:
    """§2.14: without a range the input cannot be enumerated (Unbounded names core_int), unless the
    caller gives the value."""
    it = make(tmp_path, RULE5, "M")
    [c] = it.initial()
    c = it.steps(c)[0].target
    with pytest.raises(Unbounded) as info:
        it.steps(c)
    assert info.value.name == "core_int"
    steps = it.steps(c, {("M::e", "in"): (7,)})
    assert sorted(it.states(s.target)["M"] for s in steps if s.kind == "event") == ["big", "pos"]


def test_rule5_triggerless_transition_is_urgent(tmp_path) -> None:
    """§2.5: t1 is taken at time 2, before the tock that would enable t2."""
    it = make(tmp_path, """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  state v {}
  transition t0 { from i to s }
  transition t1 { from s to u condition since(C) >= 2 }
  transition t2 { from s to v trigger e condition since(C) >= 3 }
}
""", "M")
    assert search(it, in_state(it, "M", "u")) == ["tock", "tock"]
    assert search(it, in_state(it, "M", "v"), max_visible=6) is None


def test_rule6_junctions(tmp_path) -> None:
    """§2.6: no true condition in j: time passes until since(C) >= 2; two true conditions: both."""
    it = make(tmp_path, """
stm M {
  event go
  clock C
  var x : int = 0
  initial i
  state s0 {}
  junction j
  state u {}
  state never {}
  state a {}
  state b {}
  junction k
  transition t0 { from i to s0 }
  transition t1 { from s0 to j trigger go action #C }
  transition t2 { from j to u condition since(C) >= 2 }
  transition t3 { from j to never condition x > 0 }
  transition t4 { from u to k }
  transition t5 { from k to a condition true }
  transition t6 { from k to b condition else }
  transition t7 { from k to b condition x == 0 }
}
""", "M")
    assert search(it, in_state(it, "M", "u")) == ["M::go.in", "tock", "tock"]
    assert search(it, in_state(it, "M", "never"), max_visible=5) is None
    assert search(it, in_state(it, "M", "a")) == ["M::go.in", "tock", "tock"]
    assert search(it, in_state(it, "M", "b")) == ["M::go.in", "tock", "tock"]


# ---------------------------------------------------------------------------- rules 7–8


def test_rule7_composite_entry_exit_order(tmp_path) -> None:
    """§2.7: entry A (x=1), initial into B (x=3); on go: exit B (4), exit A (40), action (45),
    entry Tgt outputs 45."""
    it = make(tmp_path, """
stm M {
  event go
  event res : int
  var x : int = 0
  initial i
  state A {
    entry x = 1
    exit x = x * 10
    initial ai
    state B {
      entry x = x + 2
      exit x = x + 1
    }
    transition ta { from ai to B }
  }
  state Tgt { entry res!x }
  state Done {}
  transition t0 { from i to A }
  transition t1 { from A to Tgt trigger go action x = x + 5 }
  transition t2 { from Tgt to Done }
}
""", "M")
    c = settle(it, it.initial()[0])
    assert it.states(c) == {"M": "A::B"} and it.variables(c)["M.x"] == 3
    assert names(it.steps(c)) == ["M::go.in", "tock"]
    c = settle(it, take(it, c, "M::go.in"))
    assert it.variables(c)["M.x"] == 45
    assert names(it.steps(c)) == ["M::res.out.45", "tock"]
    assert search(it, in_state(it, "M", "Done")) == ["M::go.in", "M::res.out.45"]


def test_rule7_during_of_leaf_and_composite(tmp_path) -> None:
    """§2.7: the during of s starts after its entry (x = 2 enables t1). The during of composite S
    starts once its child c is stable (f before e), and leaving S abandons it."""
    it = make(tmp_path, """
stm M {
  var x : int = 0
  initial i
  state s {
    entry x = 1
    during x = 2
  }
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u condition x == 2 }
}
stm N {
  event e
  event f
  event g
  state S {
    initial i
    state c { entry f }
    transition t0 { from i to c }
    during e
  }
  state out {}
  initial i0
  transition t { from i0 to S }
  transition leave { from S to out trigger g }
}
""", "M")
    assert search(it, in_state(it, "M", "u")) == []
    project = tockbmc.load(tmp_path)
    n = Interpreter(project.element("N"), {})  # type: ignore[arg-type]
    c = settle(n, n.initial()[0])
    assert names(n.steps(c)) == ["N::f.out", "tock"]
    c = take(n, c, "N::f.out")
    assert names(n.steps(c)) == ["N::e.out", "N::g.in", "tock"]
    assert search(n, in_state(n, "N", "out")) == ["N::f.out", "N::g.in"]
    assert search(n, lambda k: False, max_visible=4) is None  # terminates the search
    after_e = take(n, c, "N::e.out")
    assert names(n.steps(after_e)) == ["N::g.in", "tock"]


def test_rule8_terminate(tmp_path) -> None:
    """§2.8: a top-level final offers M::terminate (tock may come first); then nothing at all.
    An inner final state is just stable."""
    it = make(tmp_path, """
stm M {
  initial i
  final f
  transition t0 { from i to f }
}
stm N {
  initial i
  state A {
    initial ai
    final af
    transition ta { from ai to af }
  }
  transition t0 { from i to A }
}
""", "M")
    c = settle(it, it.initial()[0])
    steps = it.steps(c)
    assert names(steps) == ["M::terminate", "tock"]
    ev = next(s.event for s in steps if s.kind == "event")
    assert ev is not None and ev.channel == ("M::terminate",) and ev.values == ()
    t = take(it, c, "M::terminate")
    assert it.terminated(t) and it.steps(t) == []
    assert not it.terminated(c)
    n = Interpreter(tockbmc.load(tmp_path).element("N"), {})  # type: ignore[arg-type]
    c = settle(n, n.initial()[0])
    assert n.states(c) == {"N": "A::af"} and names(n.steps(c)) == ["tock"]


# ---------------------------------------------------------------------------- rules 9–11


def test_rule9_wait(tmp_path) -> None:
    """§2.9: wait(2) lets exactly two tocks pass before e; wait([1, 3]) one to three."""
    it = make(tmp_path, """
stm M {
  event e
  clock C
  var x : int = 0
  initial i
  state s { entry wait(2) ; e ; wait([1, 3]) ; x = since(C) }
  state three {}
  state five {}
  state other {}
  transition t0 { from i to s }
  transition t1 { from s to three condition x == 3 }
  transition t2 { from s to five condition x == 5 }
  transition t3 { from s to other condition x != 0 /\\ x < 3 }
}
""", "M")
    c = settle(it, it.initial()[0])
    assert names(it.steps(c)) == ["tock"]
    c = settle(it, it.steps(c)[0].target)
    assert names(it.steps(c)) == ["tock"]
    c = settle(it, it.steps(c)[0].target)
    assert names(it.steps(c)) == ["M::e.out", "tock"]
    c = take(it, c, "M::e.out")
    assert len([s for s in it.steps(c) if s.kind == "internal"]) == 3  # wait 1, 2 or 3
    assert search(it, in_state(it, "M", "three")) == ["tock", "tock", "M::e.out", "tock"]
    assert search(it, in_state(it, "M", "five")) == ["tock", "tock", "M::e.out", "tock", "tock", "tock"]
    assert search(it, in_state(it, "M", "other"), max_visible=8) is None


def test_rule10_clocks_and_since_entry(tmp_path) -> None:
    """§2.10: #C at time 2 resets C; s is entered at time 2, so at time 3 since(C) == 1 and
    sinceEntry(s) == 1."""
    it = make(tmp_path, """
stm M {
  event e
  clock C
  initial i
  state a {}
  state s {}
  state u {}
  transition t0 { from i to a }
  transition t1 { from a to s condition since(C) >= 2 action #C }
  transition t2 { from s to u trigger e condition since(C) == 1 /\\ sinceEntry(s) == 1 }
}
""", "M")
    assert search(it, in_state(it, "M", "u")) == ["tock", "tock", "tock", "M::e.in"]


def test_rule11_statement_deadline(tmp_path) -> None:
    """§2.11: e <{2}: after two tocks without e, tock is refused (e is still offered)."""
    it = make(tmp_path, """
stm M {
  event e
  initial i
  state s { entry e <{2} }
  transition t0 { from i to s }
}
""", "M")
    c = settle(it, it.initial()[0])
    for _ in range(2):
        assert names(it.steps(c)) == ["M::e.out", "tock"]
        c = [s for s in it.steps(c) if s.kind == "tock"][0].target
    assert names(it.steps(c)) == ["M::e.out"]
    c = take(it, c, "M::e.out")
    assert names(it.steps(c)) == ["tock"]


def test_rule11_trigger_deadline(tmp_path) -> None:
    """§2.11: the condition is true from time 1; the transition must be taken within 1 tock, so
    after two tocks, tock is refused; taking e at any time is fine."""
    it = make(tmp_path, """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u trigger e <{1} condition since(C) >= 1 }
}
""", "M")
    c = settle(it, it.initial()[0])
    assert names(it.steps(c)) == ["tock"]
    c = it.steps(c)[0].target
    assert names(it.steps(c)) == ["M::e.in", "tock"]
    c2 = [s for s in it.steps(c) if s.kind == "tock"][0].target
    assert names(it.steps(c2)) == ["M::e.in"]
    u = take(it, c2, "M::e.in")
    assert names(it.steps(u)) == ["tock"]


# ---------------------------------------------------------------------------- rules 12–13

SYNC = """
stm A {
  event x : int
  initial i
  state s { entry x!1 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm BNow {
  event x : int
  event res : int
  var v : int = 0
  var y : int = 0
  clock C
  initial i
  state w {}
  state got { entry y = since(C) }
  final f
  transition t0 { from i to w }
  transition t1 { from w to got trigger x?v }
  transition t2 { from got to f condition y == 0 action res!v }
}
controller CNow {
  event res : int
  sref a = A
  sref b = BNow
  connection a on x to b on x
  connection b on res to CNow on res
}
"""


def test_rule12_sync_connection_is_one_internal_step(tmp_path) -> None:
    """§2.12: x is a joint internal step at time 0; CNow terminates once A and BNow are both at
    final states (§5.6), A right after its output, BNow after res."""
    it = make(tmp_path, SYNC, "CNow")
    [c0] = it.initial()
    assert search(it, it.terminated) == ["CNow::res.out.1", "CNow::terminate"]
    seen, c = 0, c0
    while it.states(c)["BNow"] != "got":
        steps = it.steps(c)
        assert all(s.kind == "internal" for s in steps)
        joint = [s for s in steps if "A.x to BNow.x" in s.note]
        c = (joint or steps)[0].target
        seen += bool(joint)
    assert seen == 1 and it.variables(c)["BNow.v"] == 1


ASYNC = """
stm A {
  event x : int
  initial i
  state s { entry x!1 ; x!2 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm B {
  event x : int
  event res : int
  var v : int = 0
  clock C
  initial i
  state w0 {}
  state w {}
  state got { entry res!v }
  final f
  transition t0 { from i to w0 }
  transition t1 { from w0 to w condition since(C) >= 1 }
  transition t2 { from w to got trigger x?v }
  transition t3 { from got to f }
}
controller CAsync {
  event res : int
  sref a = A
  sref b = B
  connection a on x to b on x ( _async )
  connection b on res to CAsync on res
}
controller CSync {
  event res : int
  sref a = A
  sref b = B
  connection a on x to b on x
  connection b on res to CSync on res
}
"""


def test_rule12_async_buffer_overwrites(tmp_path) -> None:
    """§2.12: asynchronously A writes 1 then 2 at time 0 (never blocking); B reads 2 at time 1.
    Synchronously A blocks on x!1 until B is ready at time 1, and then on x!2 for ever, which B
    never takes: B reaches its final state, A never does, so CSync never terminates (§5.6)."""
    it = make(tmp_path, ASYNC, "CAsync")
    assert search(it, it.terminated) == ["tock", "CAsync::res.out.2", "CAsync::terminate"]
    c = run_internal(it, it.initial()[0])
    assert it.states(c) == {"A": "f", "B": "w0"} and names(it.steps(c)) == ["tock"]
    it = make(tmp_path, ASYNC, "CSync")
    assert search(it, lambda c: it.states(c)["B"] == "f") == ["tock", "CSync::res.out.1"]
    assert search(it, it.terminated) is None


def test_rule12_controller_and_module_events(tmp_path) -> None:
    """§2.12, §1: the controller's event is Ctrl::e.in.v; at module level the platform's event is
    Mod::e.in.v, joined directly to the controller although the connection is `(_async)` (RoboTool
    buffers only connections between controllers: DESIGN.md); terminate is the element's, and a
    module's is hidden (an internal step, then ✓: §5.6)."""
    rct = """
interface IE { event e : int }
robotic platform RP { uses IE }
stm M {
  uses IE
  var x : int = 0
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger e?x condition x == 1 }
}
controller Ctrl {
  uses IE
  sref m = M
  connection Ctrl on e to m on e
}
module Mod {
  rref rp = RP
  cref c = Ctrl
  connection rp on e to c on e ( _async )
}
"""
    it = make(tmp_path, rct, "Ctrl", M1_1)
    c = settle(it, it.initial()[0])
    assert names(it.steps(c)) == ["Ctrl::e.in.1", "tock"]
    assert search(it, it.terminated) == ["Ctrl::e.in.1", "Ctrl::terminate"]
    mod = Interpreter(tockbmc.load(tmp_path).element("Mod"), M1_1)  # type: ignore[arg-type]
    c = settle(mod, mod.initial()[0])
    assert names(mod.steps(c)) == ["Mod::e.in.1", "tock"]  # only what the machine accepts: no buffer
    c = take(mod, c, "Mod::e.in.1")
    assert [(s.kind, s.note) for s in mod.steps(c)] == [("internal", "Mod terminates")]  # urgent: no tock
    assert search(mod, mod.terminated) == ["Mod::e.in.1"]


def test_rule12_conformance_controller_c1(tmp_path) -> None:
    """The golden trace of C1_term (tests/golden/controller_c1_term.txt), with core_nat = 2 and the
    constant z (no value) taking 2."""
    project = tockbmc.load(CONFORMANCE / "robochart" / "test-core-assertions")
    it = Interpreter(project.element("C1"), {"core_nat": (F(2), F(2))})  # type: ignore[arg-type]
    assert search(it, it.terminated) == ["C1::e.in.2", "C1::terminate"]
    mod = Interpreter(project.element("M"), {"core_nat": (F(2), F(2))})  # type: ignore[arg-type]
    assert search(mod, mod.terminated) == ["M::e.in.2"]  # a module's terminate is hidden (§5.6)


SHARED_VAR = """
interface SV { var sv : int }
stm W {
  requires SV
  initial i
  state s { entry sv = 3 }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f }
}
stm R {
  requires SV
  event res : int
  initial i
  state w {}
  final f
  transition t0 { from i to w }
  transition t1 { from w to f condition sv == 3 action res!sv }
}
controller Ctrl {
  var sv : int = 0
  event res : int
  sref wr = W
  sref rd = R
  connection rd on res to Ctrl on res
}
"""


def test_rule13_shared_variable(tmp_path) -> None:
    """§2.13, §5.5: W writes the controller's sv = 3; R reads its copy (initially 0). R alone has its
    own copy, any value of its range in the open reading."""
    it = make(tmp_path, SHARED_VAR, "Ctrl")
    [c0] = it.initial()
    assert it.variables(c0) == {"sv": 0, "W.sv": 0, "R.sv": 0}
    assert search(it, it.terminated) == ["Ctrl::res.out.3", "Ctrl::terminate"]
    alone = make(tmp_path, SHARED_VAR, "R", M1_1)
    assert sorted(alone.variables(c)["R.sv"] for c in alone.initial()) == [-1, 0, 1]
    assert search(alone, alone.terminated, max_visible=4) is None
    with pytest.raises(Unbounded):
        make(tmp_path, SHARED_VAR, "R").initial()
    assert search(alone, alone.terminated, starts=make(tmp_path, SHARED_VAR, "R").initial({"sv": 3})) == [
        "R::res.out.3", "R::terminate"]


# ---------------------------------------------------------------------------- rules 14–15


def test_rule14_data(tmp_path) -> None:
    """§2.14: nat is never negative; reals are exact; records print with field names."""
    it = make(tmp_path, """
datatype P { a : real  b : nat }
stm M {
  event out : P
  var n : nat
  var r : real = 0
  var p : P
  initial i
  state s { entry r = 0.5 + 0.25 ; p.a = r * 4 ; p.b = 1 - 2 }
  state ok {}
  transition t0 { from i to s }
  transition t1 { from s to ok condition r * 4 == 3 action out!p }
}
""", "M", {"core_int": (F(-1), F(1)), "core_real": (F(0), F(1))})
    inits = it.initial()
    assert sorted({it.variables(c)["M.n"] for c in inits}) == [0, 1]  # nat: core_int cut at 0
    c = settle(it, inits[0])
    assert it.variables(c)["M.r"] == F(3, 4)
    # p.b = -1 does not fit a nat: the assignment cannot happen; the machine waits for ever
    assert names(it.steps(c)) == ["tock"] and it.variables(it.steps(c)[0].target)["M.p"] == {"a": 3, "b": 0}
    it2 = make(tmp_path, """
datatype P { a : real  b : nat }
stm M {
  event out : P
  var r : real = 0
  var p : P = P (| a = 0, b = 0 |)
  initial i
  state s { entry r = 0.5 + 0.25 ; p.a = r * 2 }
  state ok {}
  transition t0 { from i to s }
  transition t1 { from s to ok condition r * 4 == 3 action out!p }
}
""", "M")
    c = settle(it2, it2.initial()[0])
    [ev] = [s.event for s in it2.steps(c) if s.kind == "event"]
    assert ev is not None and ev.name == "M::out.out.(a=1.5, b=0)" and ev.values == ({"a": F(3, 2), "b": 0},)
    hash(ev)


def test_rule15_constants_and_functions(tmp_path) -> None:
    """§2.15: a constant without value takes every value of its range unless set; a function
    `result == e` is evaluated; any other function is not interpretable."""
    rct = """
function dbl(a : int) : int {
  postcondition result == 2 * a
}
function g(a : int) : int {
  postcondition result > a
}
stm M {
  const k : int = 2
  const p : int
  event e
  var y : int = 0
  initial i
  state s { entry y = dbl(p) }
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger e condition p == 1 /\\ k == 2 /\\ y == 2 }
}
stm N {
  var z : int = 0
  initial i
  state s { entry z = g(3) }
  transition t0 { from i to s }
}
"""
    it = make(tmp_path, rct, "M", M1_1)
    assert len(it.initial()) == 3
    assert search(it, it.terminated) == ["M::e.in", "M::terminate"]
    it0 = make(tmp_path, rct, "M", M1_1, settings={"p": 0})
    assert len(it0.initial()) == 1
    assert search(it0, it0.terminated, max_visible=4) is None
    with pytest.raises(Unbounded) as info:
        make(tmp_path, rct, "M").initial()
    assert info.value.name == "core_int"
    n = make(tmp_path, rct, "N")
    c = n.steps(n.initial()[0])[0].target
    with pytest.raises(NotInterpretable) as ni:
        n.steps(c)
    assert "g" in ni.value.what and ni.value.pos.line > 0


def test_not_interpretable_constructs(tmp_path) -> None:
    """Strings and connections of one event to two machines are reported, with a position."""
    it = make(tmp_path, """
stm M {
  var s : string = "a"
  initial i
  state q {}
  transition t0 { from i to q }
}
""", "M")
    with pytest.raises(NotInterpretable):
        it.initial()
    with pytest.raises(NotInterpretable) as info:
        make(tmp_path, """
stm A {
  event x
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger x }
}
controller C {
  event x
  sref a = A
  sref b = A
  connection C on x to a on x
  connection C on x to b on x
}
""", "C")
    assert "one-to-many" in info.value.what and info.value.pos is not None


def test_configurations_are_values(tmp_path) -> None:
    """Configurations reached by different routes are equal and hash alike."""
    it = make(tmp_path, RULE5, "M", M1_1)
    [c0] = it.initial()
    a = settle(it, c0)
    b = settle(it, it.initial()[0])
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    with pytest.raises(AttributeError):
        a.done = True  # type: ignore[misc]


# ---------------------------------------------------------------------------- IntelliWelder


def exax(ranges: dict) -> Interpreter:
    return Interpreter(tockbmc.load(EXAMPLE).element("EXAX"), ranges)  # type: ignore[arg-type]


def bfs_terminating_trace(it: Interpreter, limit: int) -> tuple[list[str] | None, int]:
    starts = it.initial()
    seen = set(starts)
    queue = deque((c, ()) for c in starts)
    while queue and len(seen) < limit:
        c, trace = queue.popleft()
        if it.terminated(c):
            return list(trace), len(seen)
        for s in it.steps(c):
            if s.target not in seen:
                seen.add(s.target)
                queue.append((s.target, trace if s.event is None else (*trace, s.event.name)))
    return None, len(seen)


def test_intelliwelder_exax_nominal_never_terminates() -> None:
    """Paper Table 1 (A5): with core_int = 0..2 no time budget is negative, so EXAX never reaches
    its final state; the whole configuration space is explored (it is finite)."""
    it = exax({"core_int": (F(0), F(2)), "core_real": (F(-1), F(1))})
    trace, explored = bfs_terminating_trace(it, 5000)
    assert trace is None and explored < 5000


def test_intelliwelder_exax_realistic_terminates() -> None:
    """Paper Table 2 (A5): with core_int = -1..1, move.in with time -1, out_of_sync, terminate."""
    it = exax({"core_int": (F(-1), F(1)), "core_real": (F(-1), F(1))})
    trace, _ = bfs_terminating_trace(it, 5000)
    assert trace is not None and len(trace) == 3
    assert trace[0].startswith("EXAX::move.in.(dist=") and trace[0].endswith(", time=-1)")
    assert trace[1:] == ["EXAX::out_of_sync.out", "EXAX::terminate"]
    # the golden trace's exact first event, with A1's urgent call on the other branch
    c = settle(it, it.initial({"n_waypoints": 1, "EXAX.exax_move": {"dist": 0, "time": 0}})[0])
    steps = it.steps(c, {("EXAX::move", "in"): ({"dist": 0, "time": -1},)})
    assert names(steps) == ["EXAX::move.in.(dist=0, time=-1)", "tock"]
    ev = steps[0].event
    assert ev is not None and ev.channel == ("EXAX::move", "in") and ev.values == ({"dist": 0, "time": -1},)
    c = settle(it, it.steps(c, {("EXAX::move", "in"): ({"dist": 1, "time": 1},)})[0].target)
    assert names(it.steps(c)) == ["EXAX::go_to_posCall.1.1"]


def test_rule7_defined_operation_in_a_during_is_abandoned(tmp_path) -> None:
    """§2.7, §2.9: the during of s calls slow(), which waits two tocks and outputs tick; stop
    abandons it at any point. So tick comes only after two tocks, and after stop never."""
    it = make(tmp_path, """
interface Ops { slow() }
stm M {
  requires Ops
  event tick
  event stop
  initial i
  state s { during slow() }
  state done {}
  transition t0 { from i to s }
  transition t1 { from s to done trigger stop }
}
controller C {
  event tick
  event stop
  operation slow() {
    event tick
    initial i
    state w { entry wait(2) }
    final f
    transition t0 { from i to w }
    transition t1 { from w to f action tick }
  }
  sref m = M
  connection m on tick to C on tick
  connection C on stop to m on stop
}
""", "C")
    got_tick = lambda c: any(s.event is not None and s.event.name == "C::tick.out" for s in it.steps(c))  # noqa: E731
    assert search(it, got_tick) == ["tock", "tock"]
    c = run_internal(it, it.initial()[0])
    assert names(it.steps(c)) == ["C::stop.in", "tock"] and it.states(c) == {"M": "s / slow(): w"}
    c = run_internal(it, take(it, c, "C::stop.in"))
    assert it.states(c) == {"M": "done"}
    assert search(it, got_tick, starts=[c], max_visible=5) is None


def test_clocks_saturate_only_when_unobservable(tmp_path) -> None:
    """A clock only compared with literals stops growing one above the largest (the space is
    finite); a clock whose value is stored keeps growing."""
    rct = """
stm M {
  event e
  clock C
  initial i
  state s {}
  state u {}
  transition t0 { from i to s }
  transition t1 { from s to u trigger e condition since(C) >= 2 }
  transition t2 { from u to s trigger e action #C }
}
stm N {
  clock C
  var x : int = 0
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s condition since(C) > x action x = since(C) }
}
"""
    it = make(tmp_path, rct, "M")
    seen = set(it.initial())
    todo = list(seen)
    while todo:
        for s in it.steps(todo.pop()):
            if s.target not in seen:
                seen.add(s.target)
                todo.append(s.target)
    assert len(seen) < 20
    n = make(tmp_path, rct, "N")
    c = run_internal(n, n.initial()[0])
    for k in range(1, 6):
        c = run_internal(n, [s for s in n.steps(c) if s.kind == "tock"][0].target)
        assert n.variables(c)["N.x"] == k
