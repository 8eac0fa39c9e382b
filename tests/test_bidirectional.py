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
from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.config import configure
from tockbmc.model.result import Result

MODEL = Path(__file__).parent / "models" / "bidirectional"
RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
EXPECTED = {"M1": "holds", "M2": "violated", "M3": "holds", "M4": "holds", "C1": "holds", "C2": "holds"}


@cache
def results(engine: str) -> dict[str, Result]:
    project = tockbmc.load(MODEL)
    config = configure(project, RANGES)
    rs = (check(project, bound=20, config=config) if engine == "bmc"
          else check_explicit(project, None, 20, RANGES, {}, 60, config=config))
    return {r.assertion: r for r in rs}


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
    """Review finding: `m1 on e to m2 on e` beside `m1 on e to C on e [ mult ]` is an event in two
    connections (docs/semantics.md §10); BMC skipped the second and said `C refines STOP` held."""
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


def test_the_two_directions_joined_to_different_events_are_unsupported_in_bmc(tmp_path: Path) -> None:
    """Review finding: `[ mult ]` inside the controller, one-way at the module.  The module joins
    only the input, so the output stays `C::e.out` (the explicit engine, direction by direction);
    BMC's one link carried both as `Mod::e` and its replay failed (exit 1).  BMC now says the two
    directions reach different events, `unsupported`; the explicit engine decides."""
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
    project = tockbmc.load(tmp_path)
    for r in check(project, bound=8, ranges=RANGES):
        assert r.verdict == "unsupported" and "reach different events" in (r.reason or ""), r
    explicit = {r.assertion: r.verdict for r in check_explicit(project, None, 8, RANGES, {}, 10)}
    assert explicit == {"M1": "violated", "M2": "holds"}, explicit
