"""The explicit engine's lazy inputs: a configuration holding Unknowns stands for every
configuration its Unknowns' values make, and the search over them decides as the search over
every value would (DESIGN.md, "Lazy inputs").

The interpreter is checked against itself without laziness: the configurations reachable within
a few steps are the same, and every configuration a lazy one stands for offers the same kinds of
step. The engine is checked against BMC where a specification tells values apart.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import EXAMPLE, load_differential, write_files
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.explicit.interpreter import Config, Interpreter, Unknown, fill, unknowns

F = Fraction
_cases = load_differential()


def members(config: Config) -> list[Config]:
    """Every configuration without Unknowns that `config` stands for."""
    distinct, _ = unknowns(config.store)
    ids = [id(u) for u in distinct]
    return [Config(config.machines, fill(config.store, dict(zip(ids, combo, strict=True))), config.done)  # type: ignore[arg-type]
            for combo in itertools.product(*(u.values for u in distinct))]


def kinds(steps: list) -> set[tuple]:
    return {(s.kind, s.event.channel if s.event is not None else None) for s in steps}


def reachable_eagerly(it: Interpreter, depth: int) -> set[Config]:
    seen = set(it.initial())
    layer = list(seen)
    for _ in range(depth):
        layer = [s.target for c in layer for s in it.steps(c) if s.target not in seen]
        seen.update(layer)
    return seen


def reachable_lazily(it: Interpreter, depth: int) -> set[Config]:
    """Every configuration the lazy nodes within `depth` steps stand for; on the way, each node's
    configurations offer the steps the node offers (kinds and channels)."""
    eager = Interpreter(it.element, it.ranges, it.settings, it.defined)
    nodes: dict[Config, list] = {}

    def parts(c: Config) -> list[Config]:
        out = []
        for part, steps in it.expand(c):
            nodes.setdefault(part, steps)
            out.append(part)
        return out

    layer = [p for c in it.initial() for p in parts(c)]
    seen = set(layer)
    for _ in range(depth):
        nxt = []
        for c in layer:
            for s in nodes[c]:
                nxt += [p for p in parts(s.target) if p not in seen]
        seen.update(nxt)
        layer = nxt
    out: set[Config] = set()
    for node in seen:
        for m in members(node):
            assert kinds(eager.steps(m)) == kinds(nodes[node]), (node, m)
            out.add(m)
    return out


def same_configurations(element: object, ranges: dict, depth: int) -> None:
    lazy = Interpreter(element, ranges, lazy=True)  # type: ignore[arg-type]
    eager = Interpreter(element, ranges)  # type: ignore[arg-type]
    assert reachable_lazily(lazy, depth) == reachable_eagerly(eager, depth)


@st.composite
def cases(draw: st.DrawFn, make: Callable) -> str:
    def pick(options: list) -> object:
        return draw(st.sampled_from(options))

    def number(lo: int, hi: int) -> int:
        return draw(st.integers(lo, hi))

    return make(pick, number)[0]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(cases(_cases.machine_text))
def test_lazy_machines_stand_for_the_eager_configurations(tmp_path: Path, rct: str) -> None:
    write_files(tmp_path, {"m.rct": rct})
    same_configurations(tockbmc.load(tmp_path).element("M"), {"core_int": (F(-1), F(1))}, 6)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(cases(_cases.network_text))
def test_lazy_controllers_stand_for_the_eager_configurations(tmp_path: Path, rct: str) -> None:
    write_files(tmp_path, {"m.rct": rct})
    same_configurations(tockbmc.load(tmp_path).element("M"), {"core_int": (F(-1), F(1))}, 5)


@pytest.mark.parametrize("machine", ["EXAX", "UR"])
def test_lazy_paper_machines_stand_for_the_eager_configurations(machine: str) -> None:
    # two values a field (64 moves of UR), so that every configuration can be listed in time
    ranges = {"core_int": (F(-1), F(0)), "core_real": (F(0), F(1)), "core_nat": (F(0), F(1))}
    same_configurations(tockbmc.load(EXAMPLE).element(machine), ranges, 10)


def test_an_input_no_guard_reads_is_one_step() -> None:
    """UR's move carries 216 values with these ranges; until a guard reads a field, it is one."""
    ur = tockbmc.load(EXAMPLE).element("UR")
    it = Interpreter(ur, {"core_int": (F(-1), F(1)), "core_real": (F(-1), F(1))}, lazy=True)  # type: ignore[arg-type]
    [(start, steps)] = it.expand(it.initial()[0])  # ur_move has no initial value: one Unknown record
    [(waiting, steps)] = it.expand(steps[0].target)  # UR's initial transition
    [move] = [s for s in steps if s.event is not None and s.event.channel == ("UR::move", "in")]
    assert all(isinstance(v, Unknown) for v in move.event.values[0].values())  # type: ignore[union-attr]
    parts = it.expand(move.target)  # the junction's guards read the time, and only the time
    assert [p.store for p, _ in parts] != [move.target.store] and len(parts) == 3


def test_an_expression_with_one_value_for_every_input_splits_nothing() -> None:
    """With the nominal ranges no time is negative and no distance big: UR's guards and
    check_big_dist read the move's time and distances, but their values are the same whatever
    those are, so no configuration reached holds a chosen time or distance."""
    ur = tockbmc.load(EXAMPLE).element("UR")
    it = Interpreter(ur, {"core_int": (F(0), F(2)), "core_real": (F(-1), F(1)), "core_nat": (F(0), F(3))},  # type: ignore[arg-type]
                     lazy=True)
    slot = next(k for k, info in enumerate(it.slots) if info.display == "UR.ur_move")
    layer = [p for c in it.initial() for p, _ in it.expand(c)]
    seen = set(layer)
    steps = {p: ps for c in it.initial() for p, ps in it.expand(c)}
    for _ in range(30):
        nxt = []
        for c in layer:
            for s in steps[c]:
                for p, ps in it.expand(s.target):
                    if p not in seen:
                        seen.add(p)
                        steps[p] = ps
                        nxt.append(p)
        layer = nxt
    moves = [c.store[slot] for c in seen]
    assert any(m["blending"] is True for m in moves) and any(m["blending"] is False for m in moves)
    assert any("moveL_with_t" in it.states(c)["UR"] and c.store[slot]["blending"] is False for c in seen)
    assert all(isinstance(m[f], Unknown) for m in moves for f in ("dist1", "dist2", "time"))


REALISTIC = Ranges({"core_int": Range(F(-1), F(1)), "core_real": Range(F(-1), F(1)), "core_nat": Range(F(0), F(3))})


def test_fields_no_step_reads_are_marked_in_the_trace() -> None:
    """A3's counterexample needs a negative time; the other fields of the move take any value."""
    [r] = check_explicit(tockbmc.load(EXAMPLE), ["A3"], 40, REALISTIC, {}, timeout=60)
    [move] = [s for s in r.trace if s.event is not None and s.event.startswith("UR::move.in")]
    assert move.values[0]["time"] == -1
    assert set(move.free) == {"dist1", "dist2", "blending", "large_offset", "sharp_corner"}


ECHO = """interface Ops { op(n : int) }
stm M {
  requires Ops
  event a : int
  event b : int
  var x : int = 0
  initial i
  state S { }
  transition t0 { from i to S }
  transition t1 { from S to S trigger a?x action b!x ; op(x) }
}
"""

SPECS = """csp Specs csp-begin
  NoB1 = CHAOS(diff(Events, {M::b.out.1}))
  NoB2 = CHAOS(diff(Events, {M::b.out.2}))
  NoA0 = CHAOS(diff(Events, {M::a.in.0}))
  NoOp1 = CHAOS(diff(Events, {M::opCall.1}))
csp-end
timed assertion A1: M refines NoB1 in the traces model.
timed assertion A2: M refines NoB2 in the traces model.
timed assertion A3: M refines NoA0 in the traces model.
timed assertion A4: M refines NoOp1 in the traces model.
"""


def test_specifications_that_tell_values_apart(tmp_path: Path) -> None:
    """Each specification names a value of a channel whose values the lazy search left unchosen:
    the engine chooses them, and agrees with BMC, traces and their values included."""
    write_files(tmp_path, {"m.rct": ECHO, "m.assertions": SPECS})
    project = tockbmc.load(tmp_path)
    ranges = Ranges({"core_int": Range(F(-1), F(1))})
    explicit = {r.assertion: r for r in check_explicit(project, None, 8, ranges, {}, timeout=60)}
    bmc = {r.assertion: r for r in check(project, bound=12, ranges=ranges)}
    assert {n: r.verdict for n, r in explicit.items()} == {"A1": "violated", "A2": "holds", "A3": "violated",
                                                         "A4": "violated"}
    for name, r in explicit.items():
        assert r.verdict == bmc[name].verdict
        events = [s.event for s in r.trace if s.kind != "internal"]
        assert events == [s.event for s in bmc[name].trace if s.kind != "internal"]
    assert [s.event for s in explicit["A1"].trace if s.kind != "internal"] == ["M::a.in.1", "M::b.out.1"]
    assert [s.free for s in explicit["A1"].trace if s.kind != "internal"] == [(), ()]
