"""Random small machines checked by BMC and by the explicit engine: how many agree.

Run: python benchmarks/differential.py [--cases 1000] [--seed 0]
Each case is a random state machine (tockbmc/explicit/differential.py) with seven assertions of
the supported forms, checked with core_int=-1..1 by BMC (bound 16) and by the explicit engine
(8 visible steps).  Definite outcomes are compared (see that module); every disagreement is
printed with its seed, so that `random_case(seed)` reproduces it.
"""

from __future__ import annotations

import argparse
import collections
import time

import tockbmc
from tockbmc.explicit.differential import compare, random_case


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=0, help="seed of the first case")
    args = parser.parse_args()
    counts: collections.Counter[str] = collections.Counter()
    start = time.perf_counter()
    for seed in range(args.seed, args.seed + args.cases):
        rct, assertions = random_case(seed)
        try:
            outcomes = compare(rct, assertions)
        except tockbmc.ModelError:
            counts["model rejected"] += 1
            continue
        counts["cases"] += 1
        for o in outcomes:
            key = "agree" if o.agree else "disagree" if o.agree is False else "not comparable"
            counts[key] += 1
            if o.agree is False:
                print(f"DISAGREE seed {seed} {o.assertion}: bmc {o.bmc}, explicit {o.explicit} {o.note}", flush=True)
    total = counts["agree"] + counts["disagree"]
    print(f"{counts['cases']} cases, {total} definite comparisons: {counts['agree']} agree, "
          f"{counts['disagree']} disagree; {counts['not comparable']} not comparable; "
          f"{counts['model rejected']} models rejected; {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
