"""The command line under hostile conditions: odd option values, closed or narrow streams,
special files, Ctrl-C."""

from __future__ import annotations

import contextlib
import io
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import TextIO

import pytest
from conftest import EXAMPLE, REUSED_NAMES, run_cli, write_files

from tockbmc import ModelError, load
from tockbmc.cli import main

# -------------------------------------------------------------------- option values


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e400", "0"])
def test_timeout_must_be_a_finite_positive_number(value: str) -> None:
    result = run_cli(["check", EXAMPLE, "-a", "A1", "--timeout", value])
    assert result.crash is None and result.exit_code == 2, result.output
    assert "Invalid value for '--timeout'" in result.stderr


@pytest.mark.parametrize(("names", "chosen"), [
    (["A1"], ["paper.assertions:A1", "work.assertions:A1"]),
    (["work.assertions:A1"], ["work.assertions:A1"]),
    (["A2", "paper.assertions:A1"], ["paper.assertions:A1", "A2"]),
])
def test_a_name_picks_every_assertion_of_that_name_and_a_label_just_one(tmp_path: Path, names: list[str],
                                                                          chosen: list[str]) -> None:
    out = run_cli(["check", write_files(tmp_path, REUSED_NAMES), "-j", "1", "--format", "json",
                   *(arg for n in names for arg in ("-a", n))])
    assert out.crash is None and out.exit_code == 10, out.output
    assert [r["assertion"] for r in json.loads(out.stdout)["results"]] == chosen


@pytest.mark.parametrize(("name", "closest"), [("A11", "A1"), ("work.assertion:A1", "work.assertions:A1")])
def test_a_name_no_assertion_has_is_a_usage_error_with_the_closest(tmp_path: Path, name: str, closest: str) -> None:
    out = run_cli(["check", write_files(tmp_path, REUSED_NAMES), "-a", name])
    assert out.crash is None and out.exit_code == 2, out.output
    assert f"no assertion named '{name}'; did you mean '{closest}'? (known: A2, paper.assertions:A1, " \
           "work.assertions:A1)" in " ".join(out.stderr.split()), out.stderr


# -------------------------------------------------------------------- streams and files

TOCKBMC = [sys.executable, "-c", "from tockbmc.cli import main; main()"]
SMALL_CHECK = ["check", EXAMPLE, "-a", "A5", "-k", "6", "--range", "core_int=-1..1", "--range", "core_real=-1..1"]
SIMULATE = ["simulate", EXAMPLE, "--element", "EXAX", "--steps", "12", "--range", "core_int=-1..1", "--range",
            "core_real=-1..1"]


NARROW_MODEL = {"m.rct": "stm M {\n  initial i\n  state s {}\n  transition t0 { from i to s condition x } "
                         "// début → fin\n}\n"}


def run_main(args: list, stdout: TextIO | None, stderr: TextIO) -> int:
    """Run the console entry point in this process with these standard streams; its exit status."""
    saved = sys.argv, sys.stdout, sys.stderr
    sys.argv, sys.stdout, sys.stderr = ["tockbmc", *map(str, args)], stdout, stderr  # type: ignore[assignment]
    try:
        main()
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else 0
    finally:
        sys.argv, sys.stdout, sys.stderr = saved
    return 0


def test_output_to_a_reader_that_left_is_dropped_and_the_status_kept() -> None:
    """`tockbmc … | head -1`, made certain: the pipe's reading end is closed before tockbmc writes."""
    for args, status in ((["show", EXAMPLE], 0), (SIMULATE, 0), (SMALL_CHECK, 10)):
        read, write = os.pipe()
        os.close(read)
        err = io.StringIO()
        with open(write, "w") as pipe:
            assert run_main(args, pipe, err) == status and err.getvalue() == "", (args, err.getvalue())


def test_closed_stdout_prints_nothing_and_keeps_the_status() -> None:
    """`tockbmc … >&-`: one line on stderr says so; the exit status is the command's own. Once with
    descriptor 1 really closed (apart), once with Python's `sys.stdout` None (here)."""
    closed = subprocess.run([*TOCKBMC, *map(str, SMALL_CHECK)], stderr=subprocess.PIPE, text=True, timeout=120,
                            preexec_fn=lambda: os.close(1))
    err = io.StringIO()
    for status, stderr in ((closed.returncode, closed.stderr), (run_main(["show", EXAMPLE], None, err), err.getvalue())):
        assert status in (0, 10) and stderr == "tockbmc: standard output is closed: nothing is printed there\n"
    assert closed.returncode == 10


def test_a_usage_error_found_by_worker_processes_prints_no_traceback(tmp_path: Path) -> None:
    """`check --open --engine explicit -j 2` on unbounded data: the workers find it, and the usage error
    was followed by multiprocessing's tracebacks (the pool's semaphores cleaned up twice at exit)."""
    write_files(tmp_path, {"m.rct": "stm M {\n  var x : int\n  event e : int\n  initial i\n  state s {}\n"
                                    "  transition t0 { from i to s action e!x }\n}\n",
                           "m.assertions": "assertion A: M is deadlock-free.\nassertion B: M terminates.\n"})
    done = subprocess.run([*TOCKBMC, "check", str(tmp_path), "--open", "--engine", "explicit", "-j", "2", "--timeout", "20"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "needs finite data" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr and "leaked" not in done.stderr, done.stderr


def test_symbols_a_narrow_encoding_lacks_are_spelt_in_ascii(tmp_path: Path) -> None:
    """With a Latin-1 terminal, `τ` is `tau`, `✓` is `tick`, `→` is `->`, `⇔` is `<=>`, `≤` is `<=`, in
    traces, `explore`'s answers and diagnostics."""
    def latin() -> io.TextIOWrapper:
        return io.TextIOWrapper(io.BytesIO(), encoding="latin-1")

    def text(stream: io.TextIOWrapper) -> str:
        stream.flush()
        return stream.buffer.getvalue().decode("latin-1")  # type: ignore[attr-defined]

    out, err = latin(), latin()
    assert run_main(SMALL_CHECK, out, err) == 10, text(err)
    assert "    1  tau  EXAX: wait_for_move" in text(out) and "\n  -> EXAX has terminated" in text(out)
    out, err = latin(), latin()
    assert run_main(["explore", str(EXAMPLE), "-a", "A1"], out, err) == 0, text(err)
    assert "violated <=> core_int.low <= -1" in text(out), text(out)
    out, err = latin(), latin()
    assert run_main(["show", write_files(tmp_path, NARROW_MODEL)], out, err) == 3, text(err)
    assert "m.rct:4:41: error: unknown name 'x' [RoboTool rule linking]\n    transition t0 { from i to s condition x } // début -> fin\n" \
        in text(err)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_special_files_are_refused_unopened(tmp_path: Path) -> None:
    fifo = tmp_path / "m.rct"
    os.mkfifo(fifo)
    unblock = threading.Timer(10, _open_for_writing, [fifo])  # were it opened, the open would wait for a writer
    unblock.start()
    try:
        err = io.StringIO()
        assert run_main(["show", fifo], io.StringIO(), err) == 3, err.getvalue()
        assert f"{fifo}:1:1: error: not a regular file" in err.getvalue()
        with pytest.raises(ModelError, match="not a regular file"):
            load(os.devnull)
    finally:
        unblock.cancel()


def _open_for_writing(fifo: Path) -> None:
    with contextlib.suppress(OSError):  # no reader waiting: nothing to unblock
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))


# -------------------------------------------------------------------- Ctrl-C

SLOW = {
    "m.rct": """stm Quick {
  initial i
  final f
  transition t0 { from i to f }
}
stm Hard {
  var x : int
  var y : int
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f condition x * x * x == 2 * y * y * y + 1 /\\ x > 1 /\\ y > 1 }
}
stm Count {
  var n : int = 0
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to s condition n < 100000000 action n = n + 1 }
}
""",
    # Z3 spends minutes on Hard's cubic (no solution; read --open, where x and y start anywhere) and
    # the explicit search on Count's hundred million
    "m.assertions": "assertion Q1: Quick terminates.\nassertion H: Hard terminates.\nassertion C: Count terminates.\n"
                    "assertion Q2: Quick terminates.\n",
}


def busy_for(pid: int, seconds: float) -> None:
    """Wait until process `pid` has used `seconds` of processor time (a loaded machine takes longer)."""
    stat = Path(f"/proc/{pid}/stat")
    if not stat.exists():  # no /proc here: guess by the clock
        time.sleep(3 * seconds)
        return
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        fields = stat.read_text().rsplit(")", 1)[1].split()
        if (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK") >= seconds:
            return
        time.sleep(0.05)


def test_ctrl_c_prints_what_was_decided_and_exits_130_at_once(tmp_path: Path) -> None:
    """Ctrl-C during Z3's solving (BMC) and during the explicit search, in this process (`-j 1`;
    worker processes: tests/test_parallel.py): without running the checks to their end, exit
    130 with the verdicts decided so far and the other assertions marked interrupted. Elsewhere
    (loading, showing, simulating): "interrupted", exit 130, not click's "Aborted!" and 1."""
    write_files(tmp_path, SLOW)
    bmc = ["check", tmp_path, "--open", "-k", "4", "-a", "Q1", "-a", "H", "-a", "Q2", "-j", "1"]
    explicit = ["check", tmp_path, "-k", "4", "-a", "Q1", "-a", "C", "-a", "Q2", "--engine", "explicit", "--range",
                "core_int=-1..1", "--max-states", "100000000", "--format", "json", "-j", "1"]
    simulate = ["simulate", tmp_path, "--element", "Count", "--steps", "100000000"]
    procs = [subprocess.Popen([*TOCKBMC, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for args in (bmc, explicit, simulate)]
    try:
        for p in procs:  # started, Q1 decided, stuck in the second assertion
            busy_for(p.pid, 2.5)  # CPU seconds: room for loading and Q1 on a slow day
        for p in procs:
            p.send_signal(signal.SIGINT)
        sent = time.monotonic()
        (text, text_err), (data, data_err), (_, simulate_err) = (p.communicate(timeout=120) for p in procs)
    finally:  # none left running, whatever happened
        for p in procs:
            p.kill()
            p.wait()
    assert time.monotonic() - sent < 60  # not run to the end (minutes); not a measure of speed, on a busy machine
    assert [p.returncode for p in procs] == [130, 130, 130], text_err + data_err + simulate_err
    rows = [line.split("│")[1:3] for line in text.splitlines() if line.startswith("│")]
    assert [[c.strip() for c in row] for row in rows] == [["Q1", "holds"], ["H", "interrupted"],
                                                          ["Q2", "interrupted"]]
    assert "H: interrupted   assertion H: Hard terminates.\n  interrupted (Ctrl-C or SIGTERM) before a verdict" in text
    assert text_err == data_err == "tockbmc: interrupted\n"
    results = json.loads(data)
    assert [(r["assertion"], r["verdict"]) for r in results["results"]] == [
        ("Q1", "holds"), ("C", "interrupted"), ("Q2", "interrupted")]
    assert results["summary"] == {"holds": 1, "violated": 0, "unknown": 0, "unsupported": 0, "interrupted": 2,
                                  "total": 3}
    assert simulate_err.endswith("tockbmc: interrupted\n") and "Aborted" not in simulate_err


def test_ctrl_c_stops_explore_between_its_queries_and_inside_one() -> None:
    """explore solves in a worker thread with Z3's own Ctrl-C handler off (which would end one query
    as `unknown` and go on): once the first assertion is printed, Ctrl-C ends it with 130 and one
    line, what it printed kept, the other assertions not explored."""
    p = subprocess.Popen([*TOCKBMC, "explore", str(EXAMPLE)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout is not None
        first = p.stdout.readline()  # the event waited for: the first assertion explored
        p.send_signal(signal.SIGINT)
        rest, err = p.communicate(timeout=60)
    finally:
        p.kill()
        p.wait()
    assert first.startswith("A1 ") and (p.returncode, err) == (130, "tockbmc: interrupted\n"), err
    assert "A7 " not in rest


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full here")
def test_a_report_that_cannot_be_written_is_one_line_after_the_verdicts() -> None:
    """`--report /dev/full`: the verdicts are printed, then one line says the report was not
    written, and the exit status is 4 (not 2 or 3, which mean bad usage and a bad model)."""
    result = run_cli(["check", EXAMPLE, "-a", "A7", "-j", "1", "--report", "/dev/full"])
    assert result.crash is None and result.exit_code == 4, result.output
    assert "A7: holds" in result.stdout
    assert result.stderr.strip().splitlines()[-1] == ("tockbmc: the report /dev/full was not written: "
                                                      "No space left on device")


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="no /proc here")
def test_a_tree_whose_folders_vanish_while_read_is_no_internal_error() -> None:
    """`/proc` has folders that vanish while it is walked (processes ending): they are passed over,
    and the answer is the model error of a tree with no model in it."""
    result = run_cli(["show", "/proc"])
    assert result.crash is None and result.exit_code == 3, result.output
    assert "no .rct or .assertions files found" in result.stderr


@pytest.mark.parametrize(("sig", "status", "line"), [(signal.SIGINT, 130, "tockbmc: interrupted\n"),
                                                      (signal.SIGTERM, 143, "tockbmc: terminated (SIGTERM)\n")])
def test_a_signal_ends_a_long_random_run_with_its_own_status_and_one_line(sig: int, status: int, line: str) -> None:
    """simulate, streaming a run of 10^8 steps: Ctrl-C and SIGTERM each end it with their own status
    and line (click, left to it, would take SIGTERM for Ctrl-C and print a blank line first)."""
    p = subprocess.Popen([*TOCKBMC, "simulate", str(EXAMPLE), "--steps", "100000000"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout is not None
        p.stdout.readline()
        p.stdout.readline()  # the event waited for: the run's first step printed
        p.send_signal(sig)
        _rest, err = p.communicate(timeout=60)
    finally:
        p.kill()
        p.wait()
    assert (p.returncode, err) == (status, line)
