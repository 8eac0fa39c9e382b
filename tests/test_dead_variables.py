"""Dead-variable reduction in the explicit engine (`explicit.liveness`).

While a machine rests in a state, a variable no run from there reads before writing it holds one
value (`DEAD`) in the search's configurations: configurations that differ only there are one, and
every verdict, and its counterexample's number of visible steps, is that of the search without
the reduction.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from tockbmc import load
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit import liveness
from tockbmc.explicit.engine import check_explicit
from tockbmc.explicit.interpreter import Interpreter

RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2))})

# `Forward` keeps the value it forwards (`v`), read only by the action that sends it on; `Keep`
# keeps one (`k`) that a later state's condition reads, and one (`w`) that it never reads.
MODEL = """
interface I { event get : int event put : int event go }
stm Forward {
	uses I
	var v : int
	initial i
	state idle { }
	transition t0 { from i to idle }
	transition t1 { from idle to idle trigger get?v action put!v }
}
stm Keep {
	uses I
	var k : int
	var w : int
	initial i
	state a { }
	state b { }
	transition t0 { from i to a }
	transition t1 { from a to b trigger get?k action w = k }
	transition t2 { from b to a trigger go condition k > 0 }
}
"""

# A composite state whose exit action reads `a`, a junction whose conditions read the input `b`,
# and `c`, written on the way out and never read.
NESTED = """
interface J { event e : int event f }
stm Nested {
	uses J
	var a : int
	var b : int
	var c : int
	initial i
	state P {
		exit c = a
		initial j
		state Q { }
		transition u { from j to Q }
	}
	junction K
	state R { }
	transition t0 { from i to P }
	transition t1 { from P to K trigger e?b }
	transition t2 { from K to R condition b > 0 }
	transition t3 { from K to R condition b <= 0 action a = 0 }
	transition t4 { from R to P trigger f }
}
"""

ASSERTIONS = """
timed csp NoPutTwo csp-begin
NoPutTwo = CHAOS(diff(Events, {| Forward::put.out.2 |}))
csp-end
timed assertion F1: Forward is deadlock-free.
timed assertion F2: Forward refines NoPutTwo in the traces model.
timed assertion F3: Forward is deterministic.
timed assertion K1: Keep is deadlock-free.
timed assertion K2: Keep does not terminate.
timed assertion K3: Keep is deterministic.
"""


def _graph(model: Path, machine: str) -> Any:
    project = load(model)
    element = next(m for m in project.machines if m.name == machine)
    interp = Interpreter(element, RANGES)
    return interp.behs[interp.insts[0].beh]


@pytest.fixture
def model(tmp_path: Path) -> Path:
    (tmp_path / "m.rct").write_text(MODEL)
    (tmp_path / "m.assertions").write_text(ASSERTIONS)
    return tmp_path


def test_an_input_forwarded_at_once_is_dead_at_rest(model: Path) -> None:
    g = _graph(model, "Forward")
    dead = liveness.dead_at_rest(g, g.b.variables)
    assert {name for _, name in dead["idle"]} == {"v"}


def test_a_value_a_later_condition_reads_is_live(model: Path) -> None:
    g = _graph(model, "Keep")
    dead = liveness.dead_at_rest(g, g.b.variables)
    assert {name for _, name in dead["a"]} == {"k", "w"}  # written by t1's input before any read
    assert {name for _, name in dead["b"]} == {"w"}  # t2's condition reads k


def _results(model: Path, reduced: bool, monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    if not reduced:
        monkeypatch.setattr(Interpreter, "_dead_at_rest", lambda self: {})
    return {r.assertion: r for r in check_explicit(load(model), None, 10, RANGES, {}, timeout=120)}


def test_the_reduction_keeps_every_verdict_with_fewer_configurations(model: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    reduced = _results(model, True, monkeypatch)
    full = _results(model, False, monkeypatch)
    for name, r in reduced.items():
        f = full[name]
        assert (r.verdict, r.proof) == (f.verdict, f.proof), (name, r.reason, f.reason)
        # as few visible steps (which values a counterexample shows may differ: any that shows it)
        assert len([s for s in r.trace if s.kind != "internal"]) == len([s for s in f.trace if s.kind != "internal"]), name
    assert reduced["F2"].verdict == "violated"
    assert reduced["F1"].extra["states"] < full["F1"].extra["states"]


def test_an_exit_action_keeps_what_it_reads_live_in_the_states_below(tmp_path: Path) -> None:
    (tmp_path / "m.rct").write_text(NESTED)
    g = _graph(tmp_path, "Nested")
    dead = {state: {name for _, name in names} for state, names in liveness.dead_at_rest(g, g.b.variables).items()}
    assert dead["P::Q"] == {"b", "c"}  # leaving P runs its exit, which reads a; the trigger writes b first
    assert dead["R"] == {"b", "c"}  # t4 leads back into P::Q, where a is live


# Trigger deadlines are read wherever the machine is: every bound at each step, and the condition
# of an ancestor's deadline transition at a junction below it (`d` is written again before `go`
# is taken, and `y` is read at the initial junction of P, where the machine may stay).
DEADLINES = {
    "bound": """
interface I { event go event back }
stm M {
  uses I
  var d : int
  initial i
  state A {}
  state B {}
  transition t0 { from i to A action d = 1 }
  transition t1 { from A to B trigger go <{d} }
  transition t2 { from B to A trigger back action d = 1 }
}
""",
    "condition at a junction": """
interface I { event go event e event back }
stm M {
  uses I
  var y : int = 1
  var z : int = 0
  initial i
  state S {}
  state P {
    initial j
    state Q {}
    transition u { from j to Q condition z > 0 action y = 1 }
  }
  state R {}
  transition t0 { from i to S }
  transition t1 { from S to P trigger go }
  transition t2 { from P to R trigger e <{1} condition y == 1 }
  transition t3 { from R to S trigger back }
}
""",
}


@pytest.mark.parametrize("case", sorted(DEADLINES))
def test_what_trigger_deadlines_read_stays_live(case: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "m.rct").write_text(DEADLINES[case])
    (tmp_path / "m.assertions").write_text("timed assertion D: M is deadlock-free.\ntimed assertion T: M is timelock-free.\n")
    reduced = _results(tmp_path, True, monkeypatch)
    full = _results(tmp_path, False, monkeypatch)
    assert {n: r.verdict for n, r in reduced.items()} == {n: r.verdict for n, r in full.items()} == \
        {"D": "holds", "T": "violated"}
