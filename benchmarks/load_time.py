"""How long `tockbmc.load` takes on generated projects of growing size.

Run: `.venv/bin/python benchmarks/load_time.py [LINES ...]` (default 1000 10000 50000).
Prints a table (best of 3 loads per size) and the time to load the
IntelliWelder example; asserts nothing.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from generate import generate  # noqa: E402

from tockbmc import Project, load  # noqa: E402

REPEAT = 3
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"


def best_load(path: Path) -> tuple[Project, float]:
    """The project and the best wall-clock time of REPEAT loads."""
    best = float("inf")
    project = None
    for _ in range(REPEAT):
        start = time.perf_counter()
        project = load(path)
        best = min(best, time.perf_counter() - start)
    assert project is not None
    return project, best


def row(name: str, path: Path) -> str:
    project, seconds = best_load(path)
    files = [Path(f) for f in project.files]
    lines = sum(f.read_text(encoding="utf-8").count("\n") for f in files)
    states = sum(n.kind == "state" for m in project.machines for n in m.nodes)
    transitions = sum(len(m.transitions) for m in project.machines)
    return f"{name:<14} {lines:>8} {len(files):>6} {states:>7} {transitions:>12} {seconds:>9.3f}"


def main(sizes: list[int]) -> None:
    load(EXAMPLE)  # warm up: the grammar is compiled once per process
    print(f"tockbmc load time, best of {REPEAT} (Python {sys.version.split()[0]})")
    print(f"{'model':<14} {'lines':>8} {'files':>6} {'states':>7} {'transitions':>12} {'seconds':>9}")
    for n in sizes:
        with tempfile.TemporaryDirectory() as tmp:
            root = generate(n).write(tmp)
            print(row(f"generated {n // 1000}k" if n >= 1000 else f"generated {n}", root), flush=True)
    print(row("intelliwelder", EXAMPLE))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="How long tockbmc.load takes on generated projects of growing "
                                                 "size (best of 3 loads each), and on the IntelliWelder example.")
    parser.add_argument("lines", nargs="*", type=int, default=[1_000, 10_000, 50_000],
                        help="sizes of the generated projects, in lines (default: 1000 10000 50000)")
    main(parser.parse_args().lines)
