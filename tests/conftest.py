"""Shared paths, fixtures and helpers for the tockbmc tests.

Test modules that need these values at collection time (for parametrisation
or inside Hypothesis tests, where function-scoped fixtures do not fit) import
them with `from conftest import …`.
"""

from __future__ import annotations

import importlib.util
import sys
import traceback
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import click
import pytest
from click.testing import CliRunner

REPO = Path(__file__).resolve().parents[1]
# The repository is cloned next to `shared/` (locally and in CI).
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
CONFORMANCE = SHARED / "conformance" / "robochart-tests"
EXAMPLE = REPO / "examples" / "intelliwelder"
GENERATOR = REPO / "benchmarks" / "generate.py"
# A counter: `tick` three times (an internal step after each adds one to `x`), then terminate.
COUNTER = """\
stm Counter {
	var x : int = 0
	event tick
	initial i0
	state S { }
	final F
	transition t0 { from i0 to S }
	transition t1 { from S to S trigger tick condition x < 3 action x = x + 1 }
	transition t2 { from S to F condition x == 3 }
}
"""

# Two assertion files that reuse the name A1, as a case study keeps its paper's assertions beside its
# working ones (RoboTool writes each file as a CSP file of its own): both A1 are violated, A2 holds.
REUSED_NAMES = {"m.rct": COUNTER, "paper.assertions": "assertion A1: Counter does not terminate.\n",
                "work.assertions": "assertion A1: S is not reachable in Counter.\nassertion A2: Counter terminates.\n"}
# How every report names them.
REUSED_LABELS = ["paper.assertions:A1", "work.assertions:A1", "A2"]

DIFFERENTIAL = REPO / "benchmarks" / "differential_cases.py"


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def shared() -> Path:
    return SHARED


@pytest.fixture(scope="session")
def example() -> Path:
    """The IntelliWelder example project (a directory)."""
    return EXAMPLE


def write_files(directory: Path, files: dict[str, str]) -> Path:
    """Write `{name: text}` into `directory`; returns the directory."""
    directory.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (directory / name).write_text(text, encoding="utf-8")
    return directory


def both_engines(project: object, ranges: object, bound: int, timeout: float = 60) -> tuple[list, list]:
    """One project's results from BMC and from the explicit engine, under the same configuration
    (these ranges, RoboTool's defaults for the rest), for tests that expect the two to agree."""
    from tockbmc.check import check
    from tockbmc.explicit.engine import check_explicit
    from tockbmc.model.config import configure
    config = configure(project, ranges)  # type: ignore[arg-type]
    return (check(project, bound=bound, config=config),  # type: ignore[arg-type]
            check_explicit(project, None, bound, ranges, {}, timeout, config=config))  # type: ignore[arg-type]


def verdicts_are(project: object, ranges: object, bound: int, expected: dict[str, str],
                 explicit: bool = True) -> tuple[list, list]:
    """Both engines' verdicts on a project (`both_engines`) are `expected`: BMC's, and the explicit
    engine's unless `explicit` is false (it cannot apply a function nobody set)."""
    bmc, by_search = both_engines(project, ranges, bound, timeout=30)
    assert {r.assertion: r.verdict for r in bmc} == expected, [r.reason for r in bmc]
    if explicit:
        assert {r.assertion: r.verdict for r in by_search} == expected, [r.reason for r in by_search]
    return bmc, by_search


def load_generator() -> ModuleType:
    """`benchmarks/generate.py`, imported by path (benchmarks/ is not a package)."""
    return _load_benchmark("tockbmc_benchmarks_generate", GENERATOR)


def load_differential() -> ModuleType:
    """`benchmarks/differential_cases.py`: the random machines that BMC and the explicit engine both check."""
    return _load_benchmark("tockbmc_benchmarks_differential_cases", DIFFERENTIAL)


def load_realworld() -> ModuleType:
    """`benchmarks/realworld.py`: how the public projects of `shared/realworld` are read."""
    return _load_benchmark("tockbmc_benchmarks_realworld", REPO / "benchmarks" / "realworld.py")


def _load_benchmark(name: str, path: Path) -> ModuleType:
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


@dataclass(frozen=True)
class CliOutcome:
    """What one run of the `tockbmc` command did."""

    exit_code: int
    stdout: str
    stderr: str
    crash: str | None  # the traceback of an exception that escaped the command, if any

    @property
    def output(self) -> str:
        return self.stdout + self.stderr


def run_cli(args: list[str]) -> CliOutcome:
    """Run `tockbmc.cli.main` with `args`, capturing its output and exit status.

    `main` may be the click command itself (then `CliRunner.invoke` runs it) or
    the console entry point, a plain function that runs the click group from
    `sys.argv` (then it runs as the installed `tockbmc` script would).
    """
    from tockbmc import cli

    main = cli.main
    runner = CliRunner()
    args = [str(a) for a in args]
    if isinstance(main, click.Command):
        result = runner.invoke(main, args, prog_name="tockbmc")
        crash = None
        if result.exception is not None and not isinstance(result.exception, SystemExit):
            crash = "".join(traceback.format_exception(*result.exc_info)) if result.exc_info else repr(result.exception)
        return CliOutcome(result.exit_code, result.stdout, result.stderr, crash)
    saved_argv = sys.argv
    code, crash = 0, None
    with runner.isolation() as (out, err, _mixed):
        sys.argv = ["tockbmc", *args]
        try:
            main()
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except Exception:  # a crash: the test reports it
            code, crash = 1, traceback.format_exc()
        finally:
            sys.argv = saved_argv
            sys.stdout.flush()
            sys.stderr.flush()
    return CliOutcome(code, out.getvalue().decode("utf-8", "replace"), err.getvalue().decode("utf-8", "replace"), crash)
