"""The explicit engine's figures: time to verdict, configurations explored and bytes per configuration.

Run: python benchmarks/explicit.py [--max-states 1000000] [--timeout 300] [--rows welder ur suite]

Each row is one `tockbmc check --engine explicit --format json` process, timed whole (wall
seconds), with its peak resident memory (the process's `ru_maxrss`); the configurations come from
the result's `states`, and bytes per configuration are the peak memory over them (an upper bound:
the interpreter, the model and Python are in the peak too). Rows:

- `welder`: the IntelliWelder module `main`, `main does not terminate`, `--robotool` at the tiny
  ranges FDR needed (`core_int=-1..1`, `core_real=-1..1`, `core_nat=0..3`);
- `ur`: the UR machine's A3 and A6 at growing ranges (distances `-d..d` as reals, times `0..t`
  as integers), the rows of `benchmarks/peers.py`, where Spin's figures for the same model are;
- `suite`: every assertion of RoboTool's suite with `--robotool --engine explicit --timeout 20`,
  as counts of verdicts, the total time and the largest configuration count.

Nothing is written to the repository; the welder's assertion is written to a temporary folder.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "intelliwelder"
CORPUS = REPO.parent / "shared" / "conformance" / "robochart-tests" / "robochart"
TINY = ["--range", "core_int=-1..1", "--range", "core_real=-1..1", "--range", "core_nat=0..3"]
UR_ROWS = [(1, 2), (5, 10), (10, 20)]  # (d, t): distances -d..d, times 0..t


def run(args: list[str]) -> tuple[list[dict], float, float, int]:
    """The results of `tockbmc check ARGS --format json`, wall seconds, peak MiB, exit status."""
    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as out:
        p = subprocess.Popen([sys.executable, "-c", "from tockbmc.cli import main; main()", "check", *args,
                              "--format", "json", "-j", "1"], stdout=out, stderr=subprocess.DEVNULL, text=True)
        try:
            _pid, status, usage = os.wait4(p.pid, 0)  # this process's own peak, not the largest child's so far
        except BaseException:
            p.kill()
            raise
        p.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.perf_counter() - start
        out.seek(0)
        try:
            results = json.loads(out.read())["results"]
        except (json.JSONDecodeError, KeyError):
            results = []
    return results, seconds, usage.ru_maxrss / 1024, p.returncode  # ru_maxrss: KiB on Linux


def line(label: str, r: dict, seconds: float, mib: float) -> str:
    states = r.get("states") or 0
    per = f"{mib * 2**20 / states:,.0f} B/config" if states else "–"
    return (f"{label:34} {r['verdict']:11} {r['proof']:11} {seconds:8.2f} s {states:>11,} configs "
            f"{mib:8.0f} MiB  {per}")


def welder(max_states: int, timeout: float) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(EXAMPLE / "intelliwelder.rct", tmp)
        Path(tmp, "main.assertions").write_text("assertion M: main does not terminate.\n")
        results, seconds, mib, _ = run([tmp, "--robotool", *TINY, "--engine", "explicit", "--max-states",
                                        str(max_states), "--timeout", str(timeout)])
    for r in results:
        print(line("welder main, does not terminate", r, seconds, mib), flush=True)


def ur(max_states: int, timeout: float) -> None:
    for d, t in UR_ROWS:
        ranges = ["--range", f"core_real=-{d}..{d}", "--range", f"core_int=0..{t}", "--range", "core_nat=0..3"]
        for a in ("A3", "A6"):
            results, seconds, mib, _ = run([str(EXAMPLE), "-a", a, "--robotool", *ranges, "--engine", "explicit",
                                            "--max-states", str(max_states), "--timeout", str(timeout)])
            for r in results:
                print(line(f"UR {a} d ±{d}, t 0..{t}", r, seconds, mib), flush=True)


def suite(max_states: int, _timeout: float) -> None:
    counts: collections.Counter[str] = collections.Counter()
    total, largest = 0.0, 0
    for case in sorted(CORPUS.iterdir()):
        results, seconds, _mib, status = run([str(case), "--robotool", "--engine", "explicit", "--timeout", "20",
                                              "--max-states", str(max_states)])
        total += seconds
        if not results:
            counts[f"not run (exit {status})"] += 1
        for r in results:
            counts[r["verdict"]] += 1
            largest = max(largest, r.get("states") or 0)
    print("suite, --robotool --engine explicit --timeout 20: "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + f"; {total:.0f} s in all; the most configurations of one assertion {largest:,}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--max-states", type=int, default=1_000_000)
    parser.add_argument("--timeout", type=float, default=300.0, help="seconds per check")
    parser.add_argument("--rows", nargs="*", default=["welder", "ur", "suite"], choices=["welder", "ur", "suite"])
    args = parser.parse_args()
    for row in args.rows:
        {"welder": welder, "ur": ur, "suite": suite}[row](args.max_states, args.timeout)


if __name__ == "__main__":
    main()
