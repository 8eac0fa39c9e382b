"""The command line under hostile conditions: odd option values, closed or narrow streams,
special files, Ctrl-C."""

from __future__ import annotations

import os
import subprocess
import sys
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
                              stderr=subprocess.PIPE, text=True, **kw) for args, kw in runs]
    out = []
    for p in procs:
        stdout, stderr = p.communicate(timeout=120)
        out.append(subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr))
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
