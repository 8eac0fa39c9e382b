"""The paper's Tables 1 and 2 by tockbmc: each assertion's verdict and time beside FDR's.

Run: python benchmarks/paper_tables.py [--bound 40] [--also-unbounded]
Checks A1–A7 of the IntelliWelder example with core_int=0..2 (Table 1) and core_int=-1..1
(Table 2), core_real=-1..1, in one process as `tockbmc check` does, and prints per assertion
tockbmc's verdict and seconds next to the verdict and total time FDR took in the paper (on a
64-core server, compilation included).  The last lines give the sums and the wall time of the
whole run (loading the model included).
"""

from __future__ import annotations

import argparse
import resource
import time
from fractions import Fraction
from pathlib import Path

import tockbmc
from tockbmc.check import DEFAULT_BOUND, check
from tockbmc.encodings.values import Range, Ranges

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"

# Murray et al., FMAS 2024, Tables 1 and 2: (verdict, total seconds) per assertion.
FDR = {
    "core_int=0..2": {"A1": ("holds", 11.13), "A2": ("holds", 11.42), "A3": ("holds", 14.93),
                      "A4": ("holds", 15.72), "A5": ("holds", 0.51), "A6": ("holds", 0.72),
                      "A7": ("holds", 1.19)},
    "core_int=-1..1": {"A1": ("violated", 11.42), "A2": ("violated", 11.22), "A3": ("violated", 15.49),
                       "A4": ("violated", 14.54), "A5": ("violated", 0.50), "A6": ("violated", 0.60),
                       "A7": ("holds", 1.28)},
}
CASES = {"core_int=0..2": (0, 2), "core_int=-1..1": (-1, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--also-unbounded", action="store_true", help="also check with no ranges at all")
    args = parser.parse_args()
    start = time.perf_counter()
    project = tockbmc.load(EXAMPLE)
    load = time.perf_counter() - start
    cases: dict[str, Ranges] = {
        label: Ranges({"core_int": Range(Fraction(lo), Fraction(hi)), "core_real": Range(Fraction(-1), Fraction(1))})
        for label, (lo, hi) in CASES.items()}
    if args.also_unbounded:
        cases["unbounded"] = Ranges()
    print(f"loaded {EXAMPLE.name} in {load:.2f} s; bound {args.bound}; core_real=-1..1")
    print(f"{'table':16} {'assertion':9} {'tockbmc':9} {'trace':>5} {'seconds':>8}   {'FDR':9} {'FDR s':>6}  agree")
    ours_total = fdr_total = 0.0
    agree = checks = 0
    for label, ranges in cases.items():
        for r in check(project, bound=args.bound, ranges=ranges):
            fdr_verdict, fdr_seconds = FDR.get(label, {}).get(r.assertion, ("-", 0.0))
            same = "-" if fdr_verdict == "-" else "yes" if fdr_verdict == r.verdict else "NO"
            ours_total += r.seconds
            fdr_total += fdr_seconds
            checks += 1
            agree += same == "yes"
            print(f"{label:16} {r.assertion:9} {r.verdict:9} {len(r.trace) or '-':>5} {r.seconds:>8.2f}   "
                  f"{fdr_verdict:9} {fdr_seconds:>6.2f}  {same}", flush=True)
    wall = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"sum of check times: tockbmc {ours_total:.2f} s for {checks} checks; FDR {fdr_total:.2f} s")
    print(f"verdicts agreeing with the paper: {agree} of {sum(len(v) for v in FDR.values())}")
    print(f"wall time of this run (load included): {wall:.2f} s; peak memory {peak:.0f} MB")


if __name__ == "__main__":
    main()
