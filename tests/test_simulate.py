"""`tockbmc simulate` draws values as the run needs them: any element, any range, bounded time and memory."""

from __future__ import annotations

import resource
import select
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import EXAMPLE, run_cli, write_files

REALISTIC = ["--range", "core_int=-1..1", "--range", "core_real=-1..1"]


def simulate(*args: object) -> tuple[str, float]:
    start = time.perf_counter()
    result = run_cli(["simulate", *map(str, args)])
    assert result.crash is None and result.exit_code == 0, result.output
    return result.stdout, time.perf_counter() - start


def test_the_default_element_of_the_example_runs_in_bounded_time_and_memory() -> None:
    """The module has dozens of variables without initial values: listing every initial
    configuration took more than 6 GB and never ended; a run draws one. Run apart, within 2 GB."""
    def limited() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))

    runs = [subprocess.Popen([sys.executable, "-c", "from tockbmc.cli import main; main()", "simulate", str(EXAMPLE),
                              "--steps", "20", *ranges], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             preexec_fn=limited) for ranges in ([], REALISTIC)]
    try:
        (bare, bare_err), (realistic, realistic_err) = (p.communicate(timeout=60) for p in runs)
    finally:  # none left running, whatever happened
        for p in runs:
            p.kill()
            p.wait()
    assert [p.returncode for p in runs] == [0, 0], bare_err + realistic_err
    # The types it draws values of with no range say so (n_waypoints is a constant: RoboTool's default, 0).
    assert bare.startswith("a random run of main (seed 0)\n")
    assert "→ 20 steps taken (with no range given, values drawn from core_int=-2..2, core_real=-2..2)" in bare
    assert "→ 20 steps taken\n" in realistic  # core_nat: core_int's range from 0
    for out in (bare, realistic):
        assert "\n   20  " in out


def test_huge_ranges_are_drawn_from_not_listed() -> None:
    wide = ["--range", "core_int=-1000000000000..1000000000000", "--range", "core_real=-1000000000000..1000000000000"]
    out, seconds = simulate(EXAMPLE, "--steps", "30", *wide)
    assert "→ 30 steps taken" in out and seconds < 10


def test_a_long_wait_is_drawn_from_not_listed(tmp_path: Path) -> None:
    rct = "stm M {\n  initial i\n  state s { entry wait([0, 1000000000000]) }\n  transition t0 { from i to s }\n}\n"
    out, seconds = simulate(write_files(tmp_path, {"m.rct": rct}), "--steps", "3")
    assert "M: wait(" in out and seconds < 10


def test_a_run_gives_every_kind_of_step_a_chance() -> None:
    """Steps are chosen by what happens, then with which values: internal steps are not crowded
    out by the thousands of values an input can carry."""
    out, _ = simulate(EXAMPLE, "--steps", "20")
    assert out.count("  τ  ") >= 3


def test_no_initial_configuration_is_a_run_of_no_steps(tmp_path: Path) -> None:
    rct = "stm M {\n  var n : nat = 0 - 1\n  initial i\n  state s {}\n  transition t0 { from i to s }\n}\n"
    out, _ = simulate(write_files(tmp_path, {"m.rct": rct}), "--steps", "3")
    assert "M has no initial configuration" in out


def test_an_operation_s_locals_are_drawn_from_not_listed(tmp_path: Path) -> None:
    rct = """interface I { Op() }
operation Op() {
  var l : int
  initial i
  final f
  transition t0 { from i to f action l = l + 1 }
}
stm M {
  requires I
  initial i
  state s { entry Op() }
  transition t0 { from i to s }
  transition t1 { from s to s }
}
controller C {
  requires I
  sref m = M
  opref o = Op
}
"""
    wide = ["--range", "core_int=-1000000000000..1000000000000"]
    out, seconds = simulate(write_files(tmp_path, {"m.rct": rct}), "--element", "C", "--steps", "8", *wide)
    assert "M: call Op()" in out and "M: l := " in out and seconds < 10


def test_an_unknown_element_is_a_usage_error_with_the_closest_name() -> None:
    out = run_cli(["simulate", str(EXAMPLE), "--element", "EXAXX"])
    assert out.exit_code == 2 and out.crash is None, out.output
    assert "did you mean 'EXAX'?" in out.output and "known:" in out.output


def _resident_kib(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError("no VmRSS")


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads memory from /proc")
def test_a_long_random_run_streams_its_steps_in_flat_memory() -> None:
    """`--steps 100000000`: each step is printed as it is taken, none kept: from the 2,000th step to
    the 20,000th the process grows by less than 16 MiB (kept, they would take far more)."""
    p = subprocess.Popen([sys.executable, "-m", "tockbmc", "simulate", str(EXAMPLE), "--steps", "100000000"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout is not None
        sizes = {}
        for n in range(1, 20_002):  # the header, then steps
            ready, _, _ = select.select([p.stdout], [], [], 300)
            assert ready, "no step printed in five minutes: the run is not streamed"
            line = p.stdout.readline()
            assert line, p.communicate()[1]
            if n in (2_001, 20_001):
                assert line.lstrip().startswith(f"{n - 1}  "), line
                sizes[n] = _resident_kib(p.pid)
    finally:
        p.kill()
        p.wait()
    assert sizes[20_001] - sizes[2_001] < 16 * 1024, sizes
