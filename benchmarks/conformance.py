"""Check the supported assertions of RoboTool's regression suite at a given bound and print the counts.

Run: python benchmarks/conformance.py [--bound 40] [--timeout 120]
Ranges are RoboTool's defaults: core_int=-2..2, core_real=-2..2, core_nat=0..2.
"""

from __future__ import annotations

import argparse
import collections
import time
from fractions import Fraction
from pathlib import Path

import tockbmc
from tockbmc.check import DEFAULT_BOUND, check
from tockbmc.encodings.values import Range, Ranges

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "conformance" / "robochart-tests" / "robochart"
RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_real": Range(Fraction(-2), Fraction(2)),
                 "core_nat": Range(Fraction(0), Fraction(2))})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--corpus", type=Path, default=CORPUS)
    args = parser.parse_args()
    counts: collections.Counter[str] = collections.Counter()
    start = time.perf_counter()
    for case in sorted(args.corpus.iterdir()):
        try:
            project = tockbmc.load(case)
        except tockbmc.ModelError:
            counts["case does not load"] += 1
            continue
        for r in check(project, bound=args.bound, ranges=RANGES, timeout=args.timeout):
            counts[r.verdict] += 1
            if r.verdict != "unsupported":
                print(f"{case.name:24} {r.assertion:20} {r.verdict:9} {r.seconds:7.2f}s  {(r.reason or '')[:80]}",
                      flush=True)
    print(f"bound {args.bound}: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())),
          f"({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
