"""Random small machines checked by BMC and by the explicit engine: how many agree.

Run: python benchmarks/differential.py [--cases 1000] [--seed 0] [--jobs 2] [--timeout 5] [--controllers 0.25]
[--specs] [--data] [--untimed] [--tick-tock] [--operations] [--bidirectional] [--enums] [--durings]
Each case is a random state machine, or (`--controllers`, one in four) a controller of two or three of them
(benchmarks/differential_cases.py), with nine assertions of the supported forms (and with `--specs` five
refinements of specifications that tell values of its events apart; with `--untimed`, seven untimed
assertions and seven refinements in the failures models; with `--tick-tock`, five refinements in the
tick-tock model, the model on the left of three and the specification on the left of two), checked with
core_int=-1..1 by BMC (bound 16) and by the explicit engine (8 visible steps), each given
`--timeout` seconds per assertion (BMC's in a worker process that is ended where Z3 overruns it:
`tockbmc.parallel.Job.hard_limit`).  With `--data` the machines also hold a sequence, a set and a
tuple, updated and read by their actions and guards (quantifiers too), and receive a sequence
whose length is at most 2 (`DATA_RANGES`).  With `--operations`, the machine's body (a controller's
first machine's; not with `--data`) is also an operation `Mop(k : int)` whose parameter its statements
and guards read, checked on its own (docs/semantics.md §4.8): the core forms timed and untimed, a
reachability and five traces refinements over `OP_Mop::…` events, with `k` set to -1, 0 or 1.  With
`--bidirectional`, one boundary connection of each controller is `[ mult ]` (§5.3), its machine both
sending and receiving on it, and four traces refinements tell that event's two directions apart.
With `--enums`, every case is a machine holding, sending and receiving a value of an enumeration
whose literals take parameters (`enumeration V { V0 V1(int) V2(boolean, int) }`); with `--durings`,
every case is a machine whose composite state has a during action, which runs beside its children
as they move between them (docs/semantics.md §4.1).
Without these four flags a seed's case is as it was before them.  Definite outcomes are compared, counterexample lengths
included (see that module); two holds of which one or both are only within the engine's bound agree
as far as the weaker claim goes, and are counted apart ("within a bound"); every disagreement is printed with its seed, so that
`random_case(seed)` reproduces it.
"""

from __future__ import annotations

import argparse
import collections
import json
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from differential_cases import DATA_RANGES, RANGES, compare, random_case  # noqa: E402

import tockbmc  # noqa: E402
from tockbmc.model.readings import Reading  # noqa: E402


def run(job: tuple[int, float, float, bool, bool, bool, bool, bool, bool, bool, bool, bool, str, bool]
        ) -> tuple[int, list | str | None]:
    (seed, timeout, controllers, specs, data, untimed, tick_tock, operations, bidirectional, enums, durings,
     unset, reading, shared) = job
    # past the timeout an outcome is unknown
    rct, assertions = random_case(seed, controllers, specs, data, untimed, tick_tock, operations, bidirectional,
                                  enums, durings, unset, shared)
    try:
        return seed, compare(rct, assertions, timeout=timeout, ranges=DATA_RANGES if data else RANGES,
                             reading=Reading(reading))
    except tockbmc.ModelError:
        return seed, None
    except Exception as exc:  # an internal error is a finding too: reported with its seed, the run goes on
        return seed, f"{type(exc).__name__}: {exc}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=0, help="seed of the first case")
    parser.add_argument("--jobs", type=int, default=1, help="processes to run cases in")
    parser.add_argument("--timeout", type=float, default=5.0, help="seconds per assertion and engine")
    parser.add_argument("--controllers", type=float, default=0.25,
                        help="the share of cases that are controllers of two or three machines (each costs "
                             "about five machines)")
    parser.add_argument("--specs", action="store_true",
                        help="also check refinements of specifications that tell values apart")
    parser.add_argument("--data", action="store_true", help="machines with sequences, sets and tuples")
    parser.add_argument("--untimed", action="store_true",
                        help="also check the untimed forms and refinements in the failures models")
    parser.add_argument("--tick-tock", action="store_true", help="also check refinements in the tick-tock model")
    parser.add_argument("--operations", action="store_true",
                        help="also check the machine's body as an operation on its own, with a parameter")
    parser.add_argument("--bidirectional", action="store_true",
                        help="make one boundary connection of a controller bidirectional ([ mult ])")
    parser.add_argument("--enums", action="store_true",
                        help="machines with a value of an enumeration whose literals take parameters")
    parser.add_argument("--durings", action="store_true",
                        help="machines whose composite state has a during action, beside its children")
    parser.add_argument("--unset", action="store_true",
                        help="machines with variables without an initial value, functions without a body and "
                             "arithmetic that leaves core_int, for the reading to fill in")
    parser.add_argument("--shared", action="store_true",
                        help="controllers whose machines share a variable (RoboTool's memory model: a copy per "
                             "machine), or a machine that requires one")
    parser.add_argument("--reading", choices=[r.value for r in Reading], default=Reading.DEFAULT.value,
                        help="the reading both engines check in (docs/semantics.md §6.6)")
    parser.add_argument("--log", type=Path, default=None,
                        help="append each case's outcome to this file (JSON lines: commit, options, seed, counts, "
                             "disagreements); a case already there for this commit and these options is not run "
                             "again, so that a long run can be made in parts and added up (--summary)")
    parser.add_argument("--summary", action="store_true", help="only print the totals of --log, per commit and options")
    args = parser.parse_args()
    if args.summary and args.log is None:
        parser.error("--summary reads the file of --log")
    options = {k: v for k, v in vars(args).items() if k not in ("cases", "seed", "jobs", "log", "summary")}
    key = {"commit": _commit(), "options": options}
    logged = _logged(args.log, key) if args.log is not None else {}
    if args.summary:
        _summarise(args.log)
        return
    counts: collections.Counter[str] = collections.Counter()
    start = time.perf_counter()
    seeds = [(seed, args.timeout, args.controllers, args.specs, args.data, args.untimed, args.tick_tock,
              args.operations, args.bidirectional, args.enums, args.durings, args.unset, args.reading, args.shared)
             for seed in range(args.seed, args.seed + args.cases)
             if seed not in logged]
    if logged:
        print(f"{args.cases - len(seeds)} of the {args.cases} cases are in {args.log} already", flush=True)
    # Not multiprocessing.Pool: its workers are daemons, which may not start the worker process each
    # case's BMC checks run in (`differential_cases._bmc`).
    with ProcessPoolExecutor(args.jobs) as pool:
        done = (f.result() for f in as_completed([pool.submit(run, s) for s in seeds])) if args.jobs > 1 \
            else map(run, seeds)
        for seed, outcomes in done:
            if args.log is not None:
                _append(args.log, key, seed, outcomes)
            if outcomes is None:
                counts["model rejected"] += 1
                continue
            if isinstance(outcomes, str):
                counts["crashed"] += 1
                print(f"CRASH seed {seed}: {outcomes}", flush=True)
                continue
            counts["cases"] += 1
            _count(seed, outcomes, counts)
            if counts["cases"] % 100 == 0:
                print(f"... {counts['cases']} cases: {counts['agree']} agree, {counts['disagree']} disagree "
                      f"({time.perf_counter() - start:.0f} s)", flush=True)
    total = counts["agree"] + counts["disagree"]
    print(f"{counts['cases']} cases, {total} comparisons: {counts['agree']} agree "
          f"({counts['agree within a bound']} of them within a bound), "
          f"{counts['disagree']} disagree; {counts['not comparable']} not comparable; "
          f"{counts['model rejected']} models rejected; {counts['crashed']} crashed; "
          f"{time.perf_counter() - start:.0f} s")


def _count(seed: int, outcomes: list, counts: collections.Counter[str]) -> None:
    for o in outcomes:
        key = "agree" if o.agree else "disagree" if o.agree is False else "not comparable"
        counts[key] += 1
        counts["agree within a bound"] += o.bounded
        if o.agree is False:
            print(f"DISAGREE seed {seed} {o.assertion}: bmc {o.bmc}, explicit {o.explicit} {o.note}", flush=True)


def _commit() -> str:
    """The checkout's commit, with "+changes" where its tracked files differ from it."""
    root = Path(__file__).resolve().parent.parent
    def git(*a: str) -> str:
        return subprocess.run(["git", *a], cwd=root, capture_output=True, text=True).stdout.strip()
    return (git("rev-parse", "HEAD") or "unknown") + ("+changes" if git("status", "--porcelain", "-uno") else "")


def _logged(log: Path, key: dict) -> dict[int, dict]:
    if not log.exists():
        return {}
    lines = (json.loads(line) for line in log.read_text().splitlines() if line.strip())
    return {r["seed"]: r for r in lines if r["commit"] == key["commit"] and r["options"] == key["options"]}


def _append(log: Path, key: dict, seed: int, outcomes: list | str | None) -> None:
    record = {**key, "seed": seed}
    if outcomes is None:
        record["rejected"] = True
    elif isinstance(outcomes, str):
        record["crash"] = outcomes
    else:
        kinds = collections.Counter("agree" if o.agree else "disagree" if o.agree is False else "not comparable"
                                    for o in outcomes)
        record.update(kinds)
        record["agree within a bound"] = sum(o.bounded for o in outcomes)
        record["disagreements"] = [f"{o.assertion}: bmc {o.bmc}, explicit {o.explicit} {o.note}"
                                   for o in outcomes if o.agree is False]
    with log.open("a") as f:
        f.write(json.dumps(record) + "\n")


def _summarise(log: Path) -> None:
    totals: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
    for line in log.read_text().splitlines():
        r = json.loads(line)
        c = totals[json.dumps({"commit": r["commit"], "options": r["options"]}, sort_keys=True)]
        c["cases"] += not r.get("rejected") and "crash" not in r
        c["crashed"] += "crash" in r
        c["model rejected"] += bool(r.get("rejected"))
        for k in ("agree", "agree within a bound", "disagree", "not comparable"):
            c[k] += r.get(k, 0)
    for what, c in totals.items():
        outcomes = c["agree"] + c["disagree"] + c["not comparable"]
        share = f" ({100 * c['not comparable'] / outcomes:.1f} %)" if outcomes else ""
        print(f"{what}\n  {c['cases']} cases: {c['agree']} agree ({c['agree within a bound']} of them "
              f"within a bound), {c['disagree']} disagree; {c['not comparable']} not comparable{share}; "
              f"{c['model rejected']} models rejected; {c['crashed']} crashed")


if __name__ == "__main__":
    main()
