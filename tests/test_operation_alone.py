"""An operation checked on its own (docs/semantics.md §4.8), in both engines.

`tests/models/operation_alone`: `addk(k)` reads `a` and outputs `a + k` on `b`, then ends at its
final state; `ping()` calls the platform operation `go(1)` and stays where it is.  The verdicts are
worked out by hand from §4.8: events named `OP_addk::…`, parameters as constants (RoboTool's
default 0 when not set), and the final state ending the process with ✓, its `terminate` hidden.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache
from pathlib import Path

from conftest import both_engines

import tockbmc
from tockbmc.encodings.values import Range, Ranges
from tockbmc.model.result import Result

MODEL = Path(__file__).parent / "models" / "operation_alone"
RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
EXPECTED = {
    "E1": "holds",      # b.out carries a + 1, as AddOne's does
    "E2": "violated",   # b.out carries a + 2
    "E0": "violated",   # k unset: RoboTool's default 0, so b.out carries a
    "T1": "holds",      # the final state is reached after a and b, and nothing stops short of it
    "D1": "holds",
    "U1": "violated",   # untimed, FDR's :[deadlock free] counts termination as a deadlock (§7.11)
    "P1": "holds",      # after goCall, only tock for ever
    "P2": "violated",   # untimed: stuck after goCall
    "P3": "holds",      # no final state
}


@cache
def results(engine: str) -> dict[str, Result]:
    bmc, explicit = both_engines(tockbmc.load(MODEL), RANGES, 20)
    return {r.assertion: r for r in (bmc if engine == "bmc" else explicit)}


def test_the_verdicts_worked_out_by_hand_in_both_engines() -> None:
    for engine in ("bmc", "explicit"):
        got = {n: r.verdict.value for n, r in results(engine).items()}
        assert got == EXPECTED, (engine, got)


def test_events_are_named_after_the_operations_process_and_termination_is_hidden() -> None:
    for engine in ("bmc", "explicit"):
        t1 = results(engine)["T1"]
        visible = [s.event for s in t1.trace if s.kind != "internal"]
        assert len(visible) == 2 and visible[0].startswith("OP_addk::a.in.") \
            and visible[1] == f"OP_addk::b.out.{int(visible[0].rsplit('.', 1)[1]) + 1}", (engine, visible)
        assert not any("terminate" in e for e in visible), (engine, visible)
        p1 = [s.event for s in results(engine)["P1"].trace if s.kind != "internal"]
        assert p1[0] == "OP_ping::goCall.1", (engine, p1)


def test_a_parameter_is_a_constant_stated_with_where_its_value_came_from() -> None:
    r = results("bmc")
    assert r["E1"].constants == {"ops::addk::k": "1"}, r["E1"].constants
    assert "with constant" in r["E1"].sources["constants"]["ops::addk::k"]
    assert r["E0"].constants == {"ops::addk::k": "0"} and r["E0"].sources["constants"]["ops::addk::k"] == \
        "RoboTool default"
    # E2's counterexample: AddOne cannot follow b.out carrying a + 2
    e2 = [s.event for s in r["E2"].trace if s.kind != "internal"]
    a, b = int(e2[0].rsplit(".", 1)[1]), int(e2[1].rsplit(".", 1)[1])
    assert e2[0].startswith("OP_addk::a.in.") and b == a + 2, e2


def test_a_state_qualified_by_the_operations_name(tmp_path: Path) -> None:
    """`addk::s is reachable in addk` names the state by the operation, as RoboTool's users do, not
    only by its view `OP_addk` (which alone would leave it violated in both engines)."""
    (tmp_path / "ops.rct").write_text((MODEL / "ops.rct").read_text())
    (tmp_path / "r.assertions").write_text("import ops::*\nassertion R1: addk::s is reachable in addk .\n"
                                           "assertion R2: ops::addk::s is reachable in addk .\n"
                                           "assertion R3: addk::f is reachable in addk .\n")
    for rs in both_engines(tockbmc.load(tmp_path), RANGES, 12, 30):
        assert {r.assertion: r.verdict.value for r in rs} == {"R1": "holds", "R2": "holds", "R3": "holds"}, rs
