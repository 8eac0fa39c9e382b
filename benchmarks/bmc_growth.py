"""Time and peak memory of checking A5 and A6 of the IntelliWelder example at growing bounds.

Run: python benchmarks/bmc_growth.py [--bounds 10 20 40 80] [--bmc-only]
Each check runs in its own process so that peak memory (ru_maxrss) is per check.  By default the
checker runs as `tockbmc check` does (BMC with k-induction); `--bmc-only` measures plain BMC, whose
cost on a "holds" grows with the bound.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"

CHILD = """
import json, resource, sys, time
from fractions import Fraction
import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
path, name, bound, ranges = sys.argv[1], sys.argv[2], int(sys.argv[3]), json.loads(sys.argv[4])
induction = sys.argv[5] == "1"
project = tockbmc.load(path)
rs = Ranges({k: Range(Fraction(lo), Fraction(hi)) for k, (lo, hi) in ranges.items()})
start = time.perf_counter()
[r] = check(project, [name], bound=bound, ranges=rs, induction=induction)
seconds = time.perf_counter() - start
print(json.dumps({"verdict": r.verdict, "seconds": seconds, "trace": len(r.trace),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bounds", type=int, nargs="+", default=[10, 20, 40, 80])
    parser.add_argument("--assertions", nargs="+", default=["A5", "A6"])
    parser.add_argument("--bmc-only", action="store_true", help="measure BMC without k-induction")
    args = parser.parse_args()
    cases = {"core_int=0..2, core_real=-1..1": {"core_int": ("0", "2"), "core_real": ("-1", "1")},
             "core_int=-1..1, core_real=-1..1": {"core_int": ("-1", "1"), "core_real": ("-1", "1")},
             "unbounded": {}}
    print(f"{'ranges':34} {'assertion':9} {'bound':>5} {'verdict':9} {'trace':>5} {'seconds':>8} {'peak MB':>8}")
    for label, ranges in cases.items():
        for name in args.assertions:
            for bound in args.bounds:
                out = subprocess.run([sys.executable, "-c", CHILD, str(EXAMPLE), name, str(bound), json.dumps(ranges),
                                      "0" if args.bmc_only else "1"],
                                     capture_output=True, text=True, check=True)
                r = json.loads(out.stdout)
                print(f"{label:34} {name:9} {bound:>5} {r['verdict']:9} {r['trace']:>5} {r['seconds']:>8.2f} "
                      f"{r['peak_mb']:>8.0f}", flush=True)


if __name__ == "__main__":
    main()
