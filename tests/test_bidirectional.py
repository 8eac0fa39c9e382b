"""Bidirectional connections (`[ mult ]`) at a boundary, in both engines (docs/semantics.md §5.3).

`tests/models/bidirectional`: machine `Echo` receives on `e` and answers on `e` with one more;
`connection m on e to C on e [ mult ]` and `connection P on e to c on e ( _async ) [ mult ]` make
both directions the controller's, then the module's, as RoboTool's renaming of the whole channel
(`ctrl_ref1::receive <- receive`) does.  The verdicts are worked out by hand.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache
from pathlib import Path

import pytest
from conftest import both_engines, write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.result import Result

MODEL = Path(__file__).parent / "models" / "bidirectional"
RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
EXPECTED = {"M1": "holds", "M2": "violated", "M3": "holds", "M4": "holds", "C1": "holds", "C2": "holds"}


@cache
def results(engine: str) -> dict[str, Result]:
    bmc, explicit = both_engines(tockbmc.load(MODEL), RANGES, 20)
    return {r.assertion: r for r in (bmc if engine == "bmc" else explicit)}


@pytest.mark.parametrize("engine", ["bmc", "explicit"])
def test_both_directions_are_the_outer_elements(engine: str) -> None:
    got = {n: r.verdict.value for n, r in results(engine).items()}
    assert got == EXPECTED, got
    visible = [s.event for s in results(engine)["M2"].trace if s.kind != "internal"]
    assert len(visible) == 2 and visible[0].startswith("Mod::e.in."), visible
    assert visible[1] == f"Mod::e.out.{int(visible[0].rsplit('.', 1)[1]) + 1}", visible


def test_a_bidirectional_connection_between_two_machines_is_unsupported(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": """
interface IE { event e : int }
stm A { uses IE initial i state S {} transition t { from i to S action e!1 } }
stm B { uses IE initial i state S {} state T {} transition t { from i to S } transition u { from S to T trigger e } }
controller C {
  sref a = A
  sref b = B
  connection a on e to b on e [ mult ]
}
""", "m.assertions": "assertion A0: C is deadlock-free.\n"})
    project = tockbmc.load(tmp_path)
    for r in (*check(project, bound=6), *check_explicit(project, None, 6, RANGES, {}, 10)):
        assert r.verdict == "unsupported" and "bidirectional connections between two machines" in (r.reason or ""), r


ECHO_AND_CONTROLLER = """
package b
interface IE { event e : int }
stm Echo {
  uses IE
  var x : int
  initial i
  state Wait {}
  state Reply {}
  transition t0 { from i to Wait }
  transition t1 { from Wait to Reply trigger e?x }
  transition t2 { from Reply to Wait action e!(x + 1) }
}
"""


def test_a_bidirectional_port_also_joined_to_another_machine_is_unsupported(tmp_path: Path) -> None:
    """`m1 on e to m2 on e` beside `m1 on e to C on e [ mult ]` is an event in two connections
    (docs/semantics.md §10); BMC must not skip the second (which would make `C refines STOP` hold)."""
    write_files(tmp_path, {"m.rct": """
package b
interface IE { event e : int }
stm Recv { uses IE var x : int initial i state s {} transition t0 { from i to s } transition t1 { from s to s trigger e?x } }
stm Send { uses IE initial i state s {} transition t0 { from i to s } transition t1 { from s to s action e!1 } }
controller C {
  uses IE
  sref m1 = Send
  sref m2 = Recv
  connection m1 on e to m2 on e
  connection m1 on e to C on e [ mult ]
}
""", "m.assertions": "import b::*\ncsp N csp-begin\nNothing = STOP\ncsp-end\n"
                     "untimed assertion C1: C refines Nothing .\n"})
    project = tockbmc.load(tmp_path)
    for r in (*check(project, bound=8), *check_explicit(project, None, 8, RANGES, {}, 10)):
        assert r.verdict == "unsupported" and "one-to-many" in (r.reason or ""), r


def test_a_platform_connection_joins_the_controllers_whole_channel(tmp_path: Path) -> None:
    """`[ mult ]` inside the controller, one-way at the module.  RoboTool renames the controller's
    whole channel at the module (`ctrl_ref1::receive <- receive`, `[ mult ]` or not), so both
    directions are `Mod::e`: M1 holds and M2 (an output on `C::e`) is violated, in both engines.
    (BMC carrying both directions as `Mod::e` while the explicit engine kept the output as
    `C::e.out` would be a ReplayFailure, exit 1.)"""
    write_files(tmp_path, {"m.rct": ECHO_AND_CONTROLLER + """
controller C { uses IE sref m = Echo connection m on e to C on e [ mult ] }
module Mod { robotic platform P { uses IE } cref c = C connection P on e to c on e }
""", "m.assertions": """import b::*
csp S csp-begin
EchoesMod = b::Mod::e.in?v -> b::Mod::e.out!(v + 1) -> EchoesMod
EchoesMixed = b::Mod::e.in?v -> b::C::e.out!(v + 1) -> EchoesMixed
csp-end
untimed assertion M1: Mod refines EchoesMod .
untimed assertion M2: Mod refines EchoesMixed .
"""})
    for rs in both_engines(tockbmc.load(tmp_path), RANGES, 8, 10):
        assert {r.assertion: r.verdict for r in rs} == {"M1": "holds", "M2": "violated"}, rs


def test_a_machine_receiving_on_an_event_drawn_outwards_receives_the_controllers(tmp_path: Path) -> None:
    """RoboTool renames the machine's whole channel (`stm_ref0::broadcast <- broadcast` for
    AlphaAlgorithm's `connection stm_ref0 on broadcast to CommunicationC on broadcast`, whose
    machine also receives on it), so Echo's input on `e` is `C::e.in` though the connection is drawn
    from Echo to C, in both engines."""
    write_files(tmp_path, {"m.rct": ECHO_AND_CONTROLLER + """
controller C { uses IE sref m = Echo connection m on e to C on e }
""", "m.assertions": """import b::*
csp S csp-begin
Echoes = b::C::e.in?v -> b::C::e.out!(v + 1) -> Echoes
csp-end
untimed assertion C1: C refines Echoes .
untimed assertion C2: C is deterministic .
"""})
    for rs in both_engines(tockbmc.load(tmp_path), RANGES, 8, 10):
        assert {r.assertion: r.verdict for r in rs} == {"C1": "holds", "C2": "holds"}, rs


def test_an_operation_sending_on_a_bidirectional_event_drawn_inwards_loads(tmp_path: Path) -> None:
    """Differential finding: the loader's rule that a controller's operation uses the controller's
    events the way its connections go ignored `[ mult ]`, refusing an operation that sends on
    `connection M on b to Q on b [ mult ]`; drawn the other way round, the same model loaded."""
    write_files(tmp_path, {"m.rct": """
interface Ops { op(n : int) }
stm Q {
  requires Ops
  event b : int
  var x : int
  initial i
  state S0 { entry op(1) }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S0 trigger b?x action b!x }
}
controller M {
  event b : int
  operation op(n : int) {
    event b : int
    initial i
    state s { entry b!n }
    final f
    transition t0 { from i to s }
    transition t1 { from s to f }
  }
  sref Q = Q
  connection M on b to Q on b [ mult ]
}
""", "m.assertions": "assertion A0: M is deadlock-free.\n"})
    project = tockbmc.load(tmp_path)
    for rs in (check(project, bound=8, ranges=RANGES), check_explicit(project, None, 8, RANGES, {}, 10)):
        assert [r.verdict for r in rs] == ["holds"], rs


def test_a_connection_between_machines_joins_only_the_senders_output_with_the_receivers_input(
        tmp_path: Path) -> None:
    """Not every edge of the two ends of a machine-to-machine connection is paired: pairing two
    outputs would make B's own `e!1` a hidden step with A's, and `C refines STOP` hold;
    docs/semantics.md §5.1 joins A's output with B's input only, and B's output, against the
    connection, is seen as `B::e.out.1` (§5.3), in both engines."""
    write_files(tmp_path, {"m.rct": """
package b
interface IE { event e : int }
stm A { uses IE initial i state S {} state U {} transition t0 { from i to S } transition t2 { from S to U action e!1 } }
stm B { uses IE var x : int initial i state S {} state U {} state W {}
  transition t0 { from i to S } transition t1 { from S to U action e!1 } transition t2 { from U to W trigger e?x } }
controller C {
  sref a = A
  sref b = B
  connection a on e to b on e
}
""", "m.assertions": "import b::*\ncsp S csp-begin\nNothing = STOP\ncsp-end\n"
                     "untimed assertion A1: C refines Nothing .\nuntimed assertion A3: C is deterministic .\n"})
    project = tockbmc.load(tmp_path)
    for rs in (check(project, bound=10, ranges=RANGES), check_explicit(project, None, 10, RANGES, {}, 10)):
        got = {r.assertion: r for r in rs}
        assert {n: r.verdict for n, r in got.items()} == {"A1": "violated", "A3": "holds"}, rs
        assert [s.event for s in got["A1"].trace if s.kind != "internal"] == ["B::e.out.1"], got["A1"].trace
