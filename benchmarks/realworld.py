"""Load and check every project of the public RoboChart projects (`../shared/realworld/PROJECTS.txt`).

Run: python benchmarks/realworld.py [--bound 40] [--timeout 60] [--budget 300] [--only TEXT] [--core]

Each line of PROJECTS.txt is a project: a folder and options (`exclude=`, `only=`, `include=`,
`generated`, `expect=`; the folder's README.md explains them).  Each project is loaded and its
assertions checked as RoboTool reads them: RoboTool's default ranges under the project's own
instantiation (as benchmarks/conformance.py does), each assertion with `--timeout` seconds and
the project with `--budget` seconds in all (assertions past it are counted `skipped`).  Printed:
per project, whether it loaded (else its first errors) and its verdict counts; in total, the
counts, the load failures by the RoboTool rule their errors cite (docs/language.md §5.1), the
commonest load errors and unsupported reasons, and every verdict that contradicts an
`expect=` entry (a verdict its authors recorded with RoboTool/FDR).  With `--core`, a project
without assertions is checked for RoboTool's core assertions of each of its elements, as `tockbmc
check` does; an internal error in a check is printed (`CRASH`) and counted, and the run goes on.
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import tockbmc
from tockbmc.check import DEFAULT_BOUND
from tockbmc.model.config import ROBOTOOL_RANGES, configure
from tockbmc.model.core import core_assertions
from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.loader import SUFFIXES
from tockbmc.model.readings import Reading
from tockbmc.model.result import Verdict
from tockbmc.parallel import InProcess, Job

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "realworld"


@dataclass
class Line:
    """One line of PROJECTS.txt."""

    folder: str
    exclude: list[str] = field(default_factory=list)
    only: list[str] | None = None  # None: every .assertions file; []: none
    include: list[str] | None = None
    generated: bool = False
    expect: dict[str, str] = field(default_factory=dict)

    @property
    def label(self) -> str:
        extra = [f"only={','.join(self.only) or '(none)'}"] if self.only is not None else []
        extra += [f"include={','.join(self.include)}"] if self.include is not None else []
        return " ".join([self.folder, *extra])


def read_projects(path: Path) -> list[Line]:
    """The lines of a PROJECTS.txt."""
    lines = []
    for text in path.read_text().splitlines():
        words = text.split()
        if not words or words[0].startswith("#"):
            continue
        line = Line(words[0])
        for w in words[1:]:
            key, _, value = w.partition("=")
            items = [v for v in value.split(",") if v]
            if key == "exclude":
                line.exclude = items
            elif key == "only":
                line.only = [] if value == "(none)" else items
            elif key == "include":
                line.include = items
            elif key == "generated":
                line.generated = True
            elif key == "expect":
                line.expect = dict(item.split(":", 1) for item in items)
            else:
                raise SystemExit(f"PROJECTS.txt: unknown option {w!r} in {text!r}")
        lines.append(line)
    return lines


def files_of(corpus: Path, line: Line) -> list[Path]:
    """The .rct and .assertions files of a project line."""
    base = corpus / line.folder
    chosen = []
    for f in sorted(base.rglob("*")):
        if f.suffix not in SUFFIXES or not f.is_file():
            continue
        rel = f.relative_to(base).as_posix()
        if any(rel.startswith(x) for x in line.exclude):
            continue
        if f.suffix == ".assertions" and line.only is not None and f.name not in line.only and rel not in line.only:
            continue
        if f.suffix == ".rct" and line.include is not None and not any(
                f.name.startswith(p) or rel.startswith(p) for p in line.include):
            continue
        chosen.append(f)
    return chosen


_QUOTED = re.compile(r"'[^']*'|`[^`]*`|\"[^\"]*\"|\b\d+\b")


def reason_kind(message: str) -> str:
    """A message with its names and numbers blanked, so that like reasons count together."""
    return _QUOTED.sub("…", message.split("\n")[0])[:100]


def rule_of(d: Diagnostic) -> str:
    """The RoboTool rule an error cites (`model.rules`), or why it cites none."""
    if d.rule:
        return d.rule
    return "unsupported (RoboTool accepts it)" if d.message.startswith("unsupported: ") else "no rule"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per assertion")
    parser.add_argument("--budget", type=float, default=300.0, help="seconds per project")
    parser.add_argument("--corpus", type=Path, default=CORPUS)
    parser.add_argument("--engine", choices=["auto", "bmc", "explicit"], default="auto",
                        help="the portfolio (as `check`), or one engine alone")
    parser.add_argument("--reading", choices=[r.value for r in Reading], default=Reading.ROBOTOOL.value,
                        help="the reading the projects are checked in (docs/semantics.md §6.6)")
    parser.add_argument("--only", default="", help="check only the project lines containing this text")
    parser.add_argument("--load-only", action="store_true", help="load the projects, check nothing")
    parser.add_argument("--top", type=int, default=12, help="how many reasons to list")
    parser.add_argument("--core", action="store_true",
                        help="check RoboTool's core assertions of a project that has none, as `tockbmc check` does")
    args = parser.parse_args()
    totals: collections.Counter[str] = collections.Counter()
    load_reasons: collections.Counter[str] = collections.Counter()
    load_rules: collections.Counter[str] = collections.Counter()
    unsupported: collections.Counter[str] = collections.Counter()
    contradictions: list[str] = []
    start = time.perf_counter()
    for line in read_projects(args.corpus / "PROJECTS.txt"):
        if args.only not in line.label:
            continue
        totals["projects"] += 1
        files = files_of(args.corpus, line)
        try:
            project = tockbmc.load(*files)
        except tockbmc.ModelError as exc:
            errors = [d for d in exc.diagnostics if d.severity == "error"]
            totals["not loaded"] += 1
            for kind in {reason_kind(d.message) for d in errors}:
                load_reasons[kind] += 1
            cited = sorted({rule_of(d) for d in errors})
            load_rules.update(cited)
            first = "; ".join(f"{Path(d.pos.path).name}:{d.pos.line}: {d.message.splitlines()[0]}" for d in errors[:2])
            print(f"{line.label}\n    NOT LOADED ({len(errors)} errors; RoboTool rules {', '.join(cited)}): "
                  f"{first[:200]}", flush=True)
            continue
        totals["loaded"] += 1
        project = dataclasses.replace(project, root=str(args.corpus / line.folder))
        counts: collections.Counter[str] = collections.Counter()
        if args.core and not project.assertions:
            project = dataclasses.replace(project, assertions=core_assertions(project))
        if not args.load_only and project.assertions:
            job = Job(configure(project, default_ranges=ROBOTOOL_RANGES, reading=Reading(args.reading)), args.bound,
                      args.timeout, engine=args.engine)
            began = time.perf_counter()
            for i in range(len(project.assertions)):
                left = args.budget - (time.perf_counter() - began)
                if left <= 0:
                    counts["skipped"] += 1
                    continue
                job = dataclasses.replace(job, timeout=min(args.timeout, left))
                try:
                    _, r = next(iter(InProcess([(job, i)])))
                except Exception as exc:  # an internal error is a finding: shown, and the run goes on
                    counts["crashed"] += 1
                    print(f"    CRASH {project.assertions[i].name}: {type(exc).__name__}: {exc}", flush=True)
                    continue
                counts[r.verdict.value] += 1
                if r.verdict == Verdict.UNSUPPORTED:
                    unsupported[reason_kind(r.reason or "")] += 1
                wanted = line.expect.get(r.assertion)
                if wanted and r.verdict.value in ("holds", "violated") and r.verdict.value != wanted:
                    contradictions.append(f"{line.label}: {r.assertion} {r.verdict.value}, its authors: {wanted}")
                if wanted:
                    counts[f"expect {'met' if r.verdict.value == wanted else 'not met'}"] += 1
        totals.update(counts)
        shown = ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "no assertions"
        print(f"{line.label}\n    loaded: {len(project.assertions)} assertions: {shown}", flush=True)
    print()
    print("total: " + ", ".join(f"{k} {totals[k]}" for k in
                                ("projects", "loaded", "not loaded", "holds", "violated", "unknown", "unsupported",
                                 "skipped", "crashed", "expect met", "expect not met")),
          f"({time.perf_counter() - start:.0f} s)")
    print("load failures by the RoboTool rule their errors cite (projects):")
    for rule, n in load_rules.most_common():
        print(f"  {n:4} {rule}")
    print("commonest load errors (projects):")
    for kind, n in load_reasons.most_common(args.top):
        print(f"  {n:4} {kind}")
    print("commonest unsupported reasons (assertions):")
    for kind, n in unsupported.most_common(args.top):
        print(f"  {n:4} {kind}")
    print(f"contradicting an expect= entry: {len(contradictions)}")
    for c in contradictions:
        print("  " + c)


if __name__ == "__main__":
    main()
