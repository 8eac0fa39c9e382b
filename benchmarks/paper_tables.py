"""The paper's Tables 1 and 2 by tockbmc: each assertion's verdict and time beside FDR's.

Run: python benchmarks/paper_tables.py [--bound 40] [--also-unbounded] [--engine explicit]
Checks A1–A7 of the IntelliWelder example with core_int=0..2 (Table 1) and core_int=-1..1
(Table 2), core_real=-1..1, in one process as `tockbmc check` does, and prints per assertion
tockbmc's verdict and seconds next to the verdict and total time FDR took in the paper (on a
64-core server, compilation included).  The last lines give the sums and the wall time of the
whole run (loading the model included).  With `--engine explicit` (core_nat=0..3 added, as the
explicit engine needs every range finite) the configurations and transitions explored are printed
beside FDR's states and transitions: they differ because FDR counts the states of the compiled
tock-CSP process (hidden bookkeeping events, its own data ranges, normalised specification),
while the interpreter counts configurations reached, one per internal step, a configuration
whose input values no step has read yet counting once for all of them (DESIGN.md, "Lazy inputs").
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
from tockbmc.explicit.engine import check_explicit

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"

# Murray et al., FMAS 2024, Tables 1 and 2: (verdict, total seconds, states, transitions) per assertion.
FDR = {
    "core_int=0..2": {"A1": ("holds", 11.13, 228, 713), "A2": ("holds", 11.42, 228, 713),
                      "A3": ("holds", 14.93, 5060, 17001), "A4": ("holds", 15.72, 5060, 17001),
                      "A5": ("holds", 0.51, 228, 713), "A6": ("holds", 0.72, 5060, 17001),
                      "A7": ("holds", 1.19, 32, 197)},
    "core_int=-1..1": {"A1": ("violated", 11.42, 11, 87), "A2": ("violated", 11.22, 99, 388),
                       "A3": ("violated", 15.49, 75, 1235), "A4": ("violated", 14.54, 931, 4412),
                       "A5": ("violated", 0.50, 153, 554), "A6": ("violated", 0.60, 1497, 6329),
                       "A7": ("holds", 1.28, 32, 197)},
}
CASES = {"core_int=0..2": (0, 2), "core_int=-1..1": (-1, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--also-unbounded", action="store_true", help="also check with no ranges at all")
    parser.add_argument("--engine", choices=["bmc", "explicit"], default="bmc")
    args = parser.parse_args()
    explicit = args.engine == "explicit"
    start = time.perf_counter()
    project = tockbmc.load(EXAMPLE)
    load = time.perf_counter() - start
    nat = {"core_nat": Range(Fraction(0), Fraction(3))} if explicit else {}
    cases: dict[str, Ranges] = {
        label: Ranges({"core_int": Range(Fraction(lo), Fraction(hi)), "core_real": Range(Fraction(-1), Fraction(1)),
                       **nat})
        for label, (lo, hi) in CASES.items()}
    if args.also_unbounded and not explicit:
        cases["unbounded"] = Ranges()
    print(f"loaded {EXAMPLE.name} in {load:.2f} s; bound {args.bound}; core_real=-1..1")
    counts = f" {'states':>8} {'transitions':>11} {'FDR st.':>8} {'FDR tr.':>8}" if explicit else ""
    print(f"{'table':16} {'assertion':9} {'tockbmc':9} {'trace':>5} {'seconds':>8}   {'FDR':9} {'FDR s':>6}  agree"
          + counts)
    ours_total = fdr_total = 0.0
    agree = checks = 0
    for label, ranges in cases.items():
        results = (check_explicit(project, None, args.bound, ranges, {}, None) if explicit
                   else check(project, bound=args.bound, ranges=ranges))
        for r in results:
            fdr_verdict, fdr_seconds, fdr_states, fdr_transitions = FDR.get(label, {}).get(r.assertion,
                                                                                      ("-", 0.0, 0, 0))
            same = "-" if fdr_verdict == "-" else "yes" if fdr_verdict == r.verdict else "NO"
            ours_total += r.seconds
            fdr_total += fdr_seconds
            checks += 1
            agree += same == "yes"
            more = (f" {r.extra.get('states', 0):>8,} {r.extra.get('transitions', 0):>11,} {fdr_states:>8,} "
                    f"{fdr_transitions:>8,}") if explicit else ""
            print(f"{label:16} {r.assertion:9} {r.verdict:9} {len(r.trace) or '-':>5} {r.seconds:>8.2f}   "
                  f"{fdr_verdict:9} {fdr_seconds:>6.2f}  {same:5}" + more, flush=True)
    wall = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"sum of check times: tockbmc {ours_total:.2f} s for {checks} checks; FDR {fdr_total:.2f} s")
    print(f"verdicts agreeing with the paper: {agree} of {sum(len(v) for v in FDR.values())}")
    print(f"wall time of this run (load included): {wall:.2f} s; peak memory {peak:.0f} MB")


if __name__ == "__main__":
    main()
