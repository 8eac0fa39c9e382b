"""The six-joint IntelliWelder example and the Promela model that benchmarks/peers.py writes for Spin."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from fractions import Fraction

import pytest
from conftest import REPO, _load_benchmark

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges

SIX = REPO / "examples" / "intelliwelder-6joints"
PEERS = REPO / "benchmarks" / "peers.py"
REALISTIC = Ranges({"core_int": Range(Fraction(-1), Fraction(1)), "core_real": Range(Fraction(-1), Fraction(1))})
JOINTS = [f"dist{i}" for i in range(1, 7)]


@pytest.fixture(scope="module")
def six() -> tockbmc.Project:
    return tockbmc.load(SIX)


def test_six_joint_example_loads_with_six_distances(six) -> None:
    [ur] = [m for m in six.machines if m.name == "UR"]
    [move] = [v for v in ur.variables if v.name == "ur_move"]
    assert [f.name for f in move.type.fields][:6] == JOINTS
    assert {op.name: [p.name for p in op.parameters] for op in ur.operations} == {
        op: ["d1", "d2", "d3", "d4", "d5", "d6", "time"] for op in ("moveJ", "moveL", "moveP", "moveL_with_t")}
    [big] = [f for f in six.functions if f.name == "check_big_dist"]
    assert len(big.parameters) == 6
    assert [c.initial for c in ur.constants if c.name == "n_waypoints"] == [None]
    assert {a.name for a in six.assertions} == {f"A{i}" for i in range(1, 8)}


def test_six_joint_a6_violated_by_a_late_move(six) -> None:
    start = time.perf_counter()
    [r] = check(six, ["A6"], bound=8, ranges=REALISTIC)
    assert time.perf_counter() - start < 10
    assert r.verdict == "violated"
    visible = [s.event for s in r.trace if s.kind != "internal"]
    assert visible[0].startswith("UR::move.in.(dist1=") and "dist6=" in visible[0] and "time=-1" in visible[0]
    assert visible[1:] == ["UR::out_of_sync.out", "UR::terminate"]


def promela(*args: str) -> str:
    out = subprocess.run([sys.executable, str(PEERS), "--promela-only", *args], capture_output=True, text=True,
                         check=True, timeout=60)
    return out.stdout


def test_promela_of_the_ur_machine() -> None:
    text = promela("--joints", "6", "--dist", "2", "--time=-1..1", "--assertion", "A3")
    assert "active proctype UR()" in text
    # The move input: one atomic step choosing every field over its range.
    for field in JOINTS:
        assert f"if :: ur_move_{field} = -2 :: ur_move_{field} = -1 :: ur_move_{field} = 0 " \
               f":: ur_move_{field} = 1 :: ur_move_{field} = 2 fi;" in text
    assert "if :: ur_move_time = -1 :: ur_move_time = 0 :: ur_move_time = 1 fi;" in text
    assert "if :: ur_move_blending = false :: ur_move_blending = true fi;" in text
    assert "/* UR::move.in: every value in range */" in text
    # The guards and check_big_dist are the model's, over all six joints.
    assert "((ur_move_time < 0))" in text and "(ur_move_dist6 < -(1))" in text
    # Outputs, urgent calls, termination; A3's monitor on move.in, the calls and tock.
    for event in ("UR::out_of_sync.out offered", "UR::done.out offered", "UR::terminate offered",
                  "UR::moveJCall offered, urgent", "UR::movePCall offered, urgent", "UR::moveLCall offered, urgent",
                  "UR::moveL_with_tCall offered, urgent"):
        assert event in text
    assert "pending = true;" in text and "pending = false;" in text and "/* tock */ assert(!pending);" in text


def test_promela_of_a6_asserts_on_terminate_only() -> None:
    text = promela("--assertion", "A6")
    assert "pending" not in text
    assert "assert(false);  /* A6: UR terminates */" in text
    assert "ur_move_dist3" not in text  # the two-joint model by default


@pytest.mark.skipif(shutil.which("spin") is None or shutil.which("gcc") is None, reason="needs spin and gcc")
@pytest.mark.parametrize("times, verdict", [((-1, 1), "violated"), ((0, 2), "holds")])
def test_spin_agrees_with_tockbmc_on_a3(times, verdict) -> None:
    peers = _load_benchmark("tockbmc_benchmarks_peers", PEERS)
    result = peers.spin(peers.promela(2, peers.Ranges(1, times), "A3"), timeout=60, memory_mb=1024)
    assert result.verdict == verdict
