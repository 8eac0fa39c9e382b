"""The command line under hostile conditions: odd option values, closed or narrow streams,
special files, Ctrl-C."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import EXAMPLE, run_cli, write_files

from tockbmc import ModelError, load

# -------------------------------------------------------------------- option values


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e400", "0"])
def test_timeout_must_be_a_finite_positive_number(value: str) -> None:
    result = run_cli(["check", EXAMPLE, "-a", "A1", "--timeout", value])
    assert result.crash is None and result.exit_code == 2, result.output
    assert "Invalid value for '--timeout'" in result.stderr


# -------------------------------------------------------------------- streams and files

TOCKBMC = [sys.executable, "-c", "from tockbmc.cli import main; main()"]
SMALL_CHECK = ["check", EXAMPLE, "-a", "A5", "-k", "6", "--range", "core_int=-1..1", "--range", "core_real=-1..1"]
SIMULATE = ["simulate", EXAMPLE, "--element", "EXAX", "--steps", "12", "--range", "core_int=-1..1", "--range",
            "core_real=-1..1"]


def run_all(runs: list[tuple[list, dict]]) -> list[subprocess.CompletedProcess]:
    """Run `tockbmc` once per (arguments, Popen keywords), all at once; their outcomes in order."""
    procs = [subprocess.Popen([*TOCKBMC, *map(str, args)], stdout=kw.pop("stdout", subprocess.PIPE),
                              stderr=subprocess.PIPE, **{"text": True, **kw}) for args, kw in runs]
    out = []
    try:
        for p in procs:
            stdout, stderr = p.communicate(timeout=120)
            out.append(subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr))
    finally:  # none left running, whatever happened
        for p in procs:
            p.kill()
            p.wait()
    return out


def test_output_to_a_reader_that_left_is_dropped_and_the_status_kept() -> None:
    """`tockbmc … | head -1`, made certain: the pipe's reading end is closed before tockbmc writes."""
    read, write = os.pipe()
    os.close(read)
    try:
        show, simulate, check = run_all([(args, {"stdout": write}) for args in (["show", EXAMPLE], SIMULATE, SMALL_CHECK)])
    finally:
        os.close(write)
    for result, status in ((show, 0), (simulate, 0), (check, 10)):
        assert result.returncode == status and result.stderr == "", (result.args, result.stderr)


def test_closed_stdout_prints_nothing_and_keeps_the_status() -> None:
    """`tockbmc … >&-`: one line on stderr says so; the exit status is the command's own."""
    closed = {"preexec_fn": lambda: os.close(1), "stdout": None}
    show, check = run_all([(["show", EXAMPLE], dict(closed)), (SMALL_CHECK, dict(closed))])
    for result, status in ((show, 0), (check, 10)):
        assert result.returncode == status, (result.args, result.stderr)
        assert result.stderr == "tockbmc: standard output is closed: nothing is printed there\n"


def test_symbols_a_narrow_encoding_lacks_are_spelt_in_ascii(tmp_path: Path) -> None:
    """With a Latin-1 terminal, `τ` is `tau`, `✓` is `tick`, `→` is `->`, in traces and diagnostics."""
    write_files(tmp_path, {"m.rct": "stm M {\n  initial i\n  state s {}\n  transition t0 { from i to s condition x } "
                                    "// début → fin\n}\n"})
    latin = {"env": {**os.environ, "PYTHONIOENCODING": "latin-1"}, "encoding": "latin-1"}
    check, bad = run_all([(SMALL_CHECK, dict(latin)), (["show", tmp_path], dict(latin))])
    assert check.returncode == 10 and "internal error" not in check.stderr, check.stderr
    assert "    1  tau  EXAX: wait_for_move" in check.stdout and "\n  -> EXAX has terminated" in check.stdout
    assert bad.returncode == 3, bad.stderr
    assert "m.rct:4:41: error: unknown name 'x'\n    transition t0 { from i to s condition x } // début -> fin\n" \
        in bad.stderr


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_special_files_are_refused_unopened(tmp_path: Path) -> None:
    fifo = tmp_path / "m.rct"
    os.mkfifo(fifo)  # opening it would wait for a writer for ever: run it apart, with a time limit
    result = subprocess.run([*TOCKBMC, "show", str(fifo)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 3, result.stderr
    assert f"{fifo}:1:1: error: not a regular file" in result.stderr
    with pytest.raises(ModelError, match="not a regular file"):
        load(os.devnull)


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
    # Z3 spends minutes on Hard's cubic (no solution) and the explicit search on Count's hundred million
    "m.assertions": "assertion Q1: Quick terminates.\nassertion H: Hard terminates.\nassertion C: Count terminates.\n"
                    "assertion Q2: Quick terminates.\n",
}


def test_ctrl_c_prints_what_was_decided_and_exits_130_at_once(tmp_path: Path) -> None:
    """Ctrl-C during Z3's solving (BMC) and during the explicit search: within two seconds, exit
    130 with the verdicts decided so far and the other assertions marked interrupted. Elsewhere
    (loading, showing, simulating): "interrupted", exit 130, not click's "Aborted!" and 1."""
    write_files(tmp_path, SLOW)
    bmc = ["check", tmp_path, "-k", "4", "-a", "Q1", "-a", "H", "-a", "Q2"]
    explicit = ["check", tmp_path, "-k", "4", "-a", "Q1", "-a", "C", "-a", "Q2", "--engine", "explicit", "--range",
                "core_int=-1..1", "--max-states", "100000000", "--format", "json"]
    simulate = ["simulate", tmp_path, "--element", "Count", "--steps", "100000000"]
    procs = [subprocess.Popen([*TOCKBMC, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for args in (bmc, explicit, simulate)]
    try:
        time.sleep(4)  # started, Q1 decided, stuck in the second assertion
        for p in procs:
            p.send_signal(signal.SIGINT)
        sent = time.monotonic()
        (text, text_err), (data, data_err), (_, simulate_err) = (p.communicate(timeout=10) for p in procs)
    finally:  # none left running, whatever happened
        for p in procs:
            p.kill()
            p.wait()
    assert time.monotonic() - sent < 2
    assert [p.returncode for p in procs] == [130, 130, 130], text_err + data_err + simulate_err
    rows = [line.split("│")[1:3] for line in text.splitlines() if line.startswith("│")]
    assert [[c.strip() for c in row] for row in rows] == [["Q1", "holds"], ["H", "interrupted"],
                                                          ["Q2", "interrupted"]]
    assert "H: interrupted   assertion H: Hard terminates.\n  interrupted (Ctrl-C) before a verdict" in text
    assert text_err == data_err == "tockbmc: interrupted\n"
    results = json.loads(data)
    assert [(r["assertion"], r["verdict"]) for r in results["results"]] == [
        ("Q1", "holds"), ("C", "interrupted"), ("Q2", "interrupted")]
    assert results["summary"] == {"holds": 1, "violated": 0, "unknown": 0, "unsupported": 0, "interrupted": 2,
                                  "total": 3}
    assert simulate_err.endswith("tockbmc: interrupted\n") and "Aborted" not in simulate_err
