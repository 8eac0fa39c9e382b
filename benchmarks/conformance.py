"""Check the supported assertions of RoboTool's regression suite at a given bound and print the counts.

Run: python benchmarks/conformance.py [--bound 40] [--timeout 120] [--jobs N] [--reading robotool|default|open]
With --jobs N (default 1) the assertions of every case are decided in N worker processes
(`tockbmc.parallel`, as `check -j N`); the lines and counts are the same, in the same order.
Each case is checked as RoboTool reads it (`--reading robotool`, the default here: FDR's finite
check, docs/semantics.md §6.6): RoboTool's default ranges (core_int=-2..2, core_real=-2..2,
core_nat=0..2) under the case's own instantiation, RoboTool's default values for constants and
variables without one and placeholders for functions without a body, and its bounded arithmetic;
`--reading default` keeps the default ranges but reads the data exact.  Every assertion of the suite is written to hold, so any
other definite verdict is one decided differently from RoboTool.  One line per assertion (an
`unsupported` one with the start of its reason), then the counts.
"""

from __future__ import annotations

import argparse
import collections
import time
from pathlib import Path

import tockbmc
from tockbmc.check import DEFAULT_BOUND
from tockbmc.model.config import ROBOTOOL_RANGES, configure
from tockbmc.model.readings import Reading
from tockbmc.model.result import Result
from tockbmc.parallel import InProcess, InProcesses, Job, Work

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "conformance" / "robochart-tests" / "robochart"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--corpus", type=Path, default=CORPUS)
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (1: this process)")
    parser.add_argument("--engine", choices=["auto", "bmc", "explicit"], default="auto",
                        help="the portfolio (as `check`), or one engine alone")
    parser.add_argument("--reading", choices=[r.value for r in Reading], default=Reading.ROBOTOOL.value,
                        help="the reading the cases are checked in (docs/semantics.md §6.6)")
    args = parser.parse_args()
    counts: collections.Counter[str] = collections.Counter()
    start = time.perf_counter()
    work: Work = []
    cases: list[str] = []  # the case of each assertion of the work
    for case in sorted(args.corpus.iterdir()):
        try:
            project = tockbmc.load(case)
        except tockbmc.ModelError:
            counts["case does not load"] += 1
            continue
        job = Job(configure(project, default_ranges=ROBOTOOL_RANGES, reading=Reading(args.reading)), args.bound,
                  args.timeout, engine=args.engine)
        work += [(job, i) for i in range(len(job.config.project.assertions))]
        cases += [case.name] * len(job.config.project.assertions)
    runner = InProcess(work) if args.jobs == 1 else InProcesses(work, args.jobs)
    decided: dict[int, Result] = {}
    shown = 0
    for n, r in runner:  # printed in the order of the work, whatever order they are decided in
        decided[n] = r
        while shown in decided:
            report(cases[shown], decided[shown], counts)
            shown += 1
    print(f"bound {args.bound}: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())),
          f"({time.perf_counter() - start:.0f} s)")


def report(case: str, r: Result, counts: collections.Counter[str]) -> None:
    counts[r.verdict] += 1
    if r.verdict == "violated":  # every assertion of the suite holds in RoboTool
        counts["decided differently from RoboTool"] += 1
    print(f"{case:24} {r.assertion:20} {r.verdict:9} {r.seconds:7.2f}s {r.engine:8}  {(r.reason or '')[:80]}",
          flush=True)


if __name__ == "__main__":
    main()
