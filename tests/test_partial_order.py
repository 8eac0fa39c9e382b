"""Partial-order reduction in the explicit engine (`Interpreter.private_steps`).

A machine that can only take internal steps touching its own configuration and store takes them
before the rest of its network moves: the search explores fewer configurations, and every verdict,
its proof and its counterexample's visible steps are those of the search without the reduction.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from tockbmc import load
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.explicit.interpreter import Interpreter

RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})

# Two machines that each count through internal steps, independently, then offer an event; a
# third that loops through internal steps for ever beside one that offers `e` then `f`.
MODEL = """
interface IA { event a event b }
interface IE { event e event f }
stm Counter {
	uses IA
	var x : int = 0
	initial i
	state s0 { entry x = 1 - x }
	state s1 { entry x = 1 - x }
	state s2 { entry x = 1 - x }
	state s3 { }
	transition t0 { from i to s0 }
	transition t1 { from s0 to s1 }
	transition t2 { from s1 to s2 }
	transition t3 { from s2 to s3 }
	transition t4 { from s3 to s0 trigger a }
}
stm Other {
	uses IE
	var y : int = 0
	initial i
	state s0 { entry y = 1 }
	state s1 { entry y = 0 }
	state s2 { }
	transition t0 { from i to s0 }
	transition t1 { from s0 to s1 }
	transition t2 { from s1 to s2 }
	transition t3 { from s2 to s0 trigger e }
}
stm Spinner {
	var z : int = 0
	initial i
	state s0 { }
	transition t0 { from i to s0 }
	transition t1 { from s0 to s0 action z = 1 - z }
}
stm Talker {
	uses IE
	initial i
	state s0 { }
	state s1 { }
	state s2 { }
	transition t0 { from i to s0 }
	transition t1 { from s0 to s1 trigger e }
	transition t2 { from s1 to s2 trigger f }
}
controller Pair {
	uses IA uses IE
	sref c = Counter
	sref o = Other
	connection Pair on a to c on a
	connection Pair on b to c on b
	connection Pair on e to o on e
}
controller Diverging {
	uses IE
	sref s = Spinner
	sref t = Talker
	connection Diverging on e to t on e
	connection Diverging on f to t on f
}
"""

ASSERTIONS = """
timed csp NoB csp-begin
NoB = CHAOS(diff(Events, {| Pair::b |}))
csp-end
timed csp NoF csp-begin
NoF = CHAOS(diff(Events, {| Diverging::f |}))
csp-end
timed assertion P1: Pair is deadlock-free.
timed assertion P2: Pair is divergence-free.
timed assertion P3: Pair is deterministic.
timed assertion P4: Pair does not terminate.
timed assertion P5: Pair refines NoB in the traces model.
untimed assertion P6: Pair is deadlock-free.
timed assertion D1: Diverging refines NoF in the traces model.
timed assertion D2: Diverging is divergence-free.
timed assertion D3: Diverging is deterministic.
"""


def _results(tmp_path: Path, reduced: bool, monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    """Each assertion's result, with the reduction or (`reduced=False`, for the rest of the test) without."""
    folder = tmp_path / ("reduced" if reduced else "full")
    folder.mkdir()
    (folder / "m.rct").write_text(MODEL)
    (folder / "m.assertions").write_text(ASSERTIONS)
    if not reduced:
        monkeypatch.setattr(Interpreter, "private_steps", lambda self, config: (None, {}))
    return {r.assertion: r for r in check_explicit(load(folder), None, 12, RANGES, {}, timeout=120)}


def test_the_reduction_keeps_every_verdict_and_visible_trace(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    reduced = _results(tmp_path, True, monkeypatch)
    full = _results(tmp_path, False, monkeypatch)
    for name, r in reduced.items():
        f = full[name]
        assert (r.verdict, r.proof) == (f.verdict, f.proof), (name, r.reason, f.reason)
        visible = [s.event for s in r.trace if s.kind != "internal"]
        assert visible == [s.event for s in f.trace if s.kind != "internal"], name
    assert reduced["D1"].verdict == "violated"
    assert [s.event for s in reduced["D1"].trace if s.kind != "internal"] == ["Diverging::e.in", "Diverging::f.in"]
    assert reduced["D2"].verdict == "violated" and reduced["P2"].verdict == "holds"


def test_the_reduction_explores_fewer_configurations(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    reduced = _results(tmp_path, True, monkeypatch)["P4"]
    full = _results(tmp_path, False, monkeypatch)["P4"]
    assert reduced.verdict == full.verdict == "holds"
    assert reduced.extra["states"] < full.extra["states"]


def test_an_internal_step_back_to_the_same_configuration_does_not_hide_the_others(tmp_path: Path) -> None:
    """The cycle proviso for a loop: Spinner's step from s0 to s0 changes nothing, so the reduced
    graph would take it for ever; the node is expanded in full, and Talker's e, f are found."""
    looping = MODEL.replace("transition t1 { from s0 to s0 action z = 1 - z }", "transition t1 { from s0 to s0 }")
    assert looping != MODEL
    folder = tmp_path / "loop"
    folder.mkdir()
    (folder / "m.rct").write_text(looping)
    (folder / "m.assertions").write_text(ASSERTIONS)
    [r] = check_explicit(load(folder), ["D1"], 12, RANGES, {}, timeout=120)
    assert r.verdict == "violated"
    assert [s.event for s in r.trace if s.kind != "internal"] == ["Diverging::e.in", "Diverging::f.in"]
