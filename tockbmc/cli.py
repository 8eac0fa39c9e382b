"""The `tockbmc` command line: a thin shell over the Python API."""

from __future__ import annotations

import contextlib
import json
import math
import os
import sys
from collections.abc import Callable
from fractions import Fraction
from typing import NoReturn, TypeVar

import click
from rich.text import Text

from tockbmc import __version__
from tockbmc.check import DEFAULT_BOUND, iter_check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.interrupt import decide, interrupted
from tockbmc.model import ModelError, Project, ast, load
from tockbmc.model.limits import recursion_room
from tockbmc.report.diagnostics import render, summary
from tockbmc.report.results import print_results, print_trace
from tockbmc.report.results import summary as summary_counts
from tockbmc.report.results import to_json as results_json
from tockbmc.report.streams import PipeConsole, reader_may_leave, usable_streams
from tockbmc.report.structure import project_data, project_tree

EXIT_MODEL_ERROR = 3
EXIT_INTERNAL_ERROR = 1
EXIT_INTERRUPTED = 130

T = TypeVar("T")


def _load(paths: tuple[str, ...]) -> Project:
    """Load a project, or print its diagnostics and exit 3."""
    try:
        project = load(*paths)
    except ModelError as exc:
        with reader_may_leave(sys.stderr):
            click.echo(render(exc.diagnostics, exc.sources), err=True)
            click.echo(summary(exc.diagnostics), err=True)
        sys.exit(EXIT_MODEL_ERROR)
    if project.warnings:
        with reader_may_leave(sys.stderr):
            click.echo(render(project.warnings, project.sources), err=True)
    return project


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="tockbmc")
def cli() -> None:
    """Bounded model checking of RoboChart models against RoboTool assertions."""


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="Print a tree, or JSON.")
def show(paths: tuple[str, ...], fmt: str) -> None:
    """Print the resolved structure of the model in PATHS (files or directories)."""
    project = _load(paths)
    if fmt == "json":
        with recursion_room():  # json writes nested states recursively, two levels each
            text = json.dumps({"tool": "tockbmc", "version": __version__, **project_data(project)}, indent=2)
        with reader_may_leave(sys.stdout):
            click.echo(text)
    else:
        # A pipe or a CI log has no width: never crop the tree there.
        width = None if sys.stdout.isatty() else 100_000
        with reader_may_leave(sys.stdout):
            PipeConsole(soft_wrap=True, width=width).print(project_tree(project))


def _parse_range(text: str) -> tuple[str, Range | None]:
    name, sep, spec = text.partition("=")
    if not sep or not name:
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI or NAME=unbounded")
    if spec == "unbounded":
        return name, None
    low, sep, high = spec.partition("..")
    try:
        lo, hi = Fraction(low), Fraction(high)
    except (ValueError, ZeroDivisionError):
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI with numbers, e.g. core_int=-1..1") from None
    if not sep or lo > hi:
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI with LO <= HI")
    return name, Range(lo, hi)


def _ranges(specs: tuple[str, ...]) -> Ranges:
    by_type: dict[str, Range] = {}
    by_path: dict[str, Range] = {}
    for spec in specs:
        name, r = _parse_range(spec)
        table = by_path if ("::" in name or "." in name) else by_type
        table.pop(name, None)
        if r is not None:
            table[name] = r
    return Ranges(by_type, by_path)


def _settings(specs: tuple[str, ...]) -> dict[str, ast.Expr]:
    result: dict[str, ast.Expr] = {}
    pos = ast.Pos("<command line>", 1, 1)
    for spec in specs:
        name, sep, text = spec.partition("=")
        if not sep or not name:
            raise click.BadParameter(f"'{spec}': expected NAME=VALUE")
        if text in ("true", "false"):
            result[name] = ast.Literal(ast.BOOLEAN, pos, text == "true")
            continue
        try:
            value = Fraction(text)
        except (ValueError, ZeroDivisionError):
            raise click.BadParameter(f"'{spec}': VALUE must be a number, true or false") from None
        if value.denominator == 1:
            result[name] = ast.Literal(ast.NAT if value >= 0 else ast.INT, pos, int(value))
        else:
            result[name] = ast.Literal(ast.REAL, pos, value)
    return result


def _finite(ctx: click.Context, param: click.Parameter, value: float | None) -> float | None:
    """`FloatRange` lets `nan` and `inf` through: neither is a number of seconds."""
    if value is not None and not math.isfinite(value):
        raise click.BadParameter(f"{value} is not a finite number of seconds")
    return value


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("-a", "--assertion", "names", multiple=True, help="Check only this assertion (repeatable).")
@click.option("-k", "--bound", type=click.IntRange(0), default=DEFAULT_BOUND, show_default=True,
              help="Maximum number of steps (events, tocks and internal steps) searched.")
@click.option("--range", "range_specs", multiple=True, metavar="NAME=LO..HI",
              help="Bound a type (core_int, core_nat, core_real, a model type) or a path (EXAX::move.time); "
                   "NAME=unbounded lifts it.")
@click.option("--set", "set_specs", multiple=True, metavar="NAME=VALUE", help="Give a constant a value.")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None, callback=_finite,
              help="Seconds per assertion; past it the verdict is 'unknown'.")
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True)
@click.option("--engine", type=click.Choice(["bmc", "explicit"]), default="bmc", show_default=True,
              help="Symbolic BMC in Z3, or breadth-first search over concrete configurations (finite ranges).")
@click.option("--max-states", type=click.IntRange(1), default=1_000_000, show_default=True,
              help="With --engine explicit: configurations explored before giving up with 'unknown'.")
@click.option("--shortest", type=click.Choice(["steps", "events"]), default="steps", show_default=True,
              help="BMC's counterexamples: fewest steps (found first), or fewest events and tocks within the "
                   "bound (searches on to the bound; slower). The explicit engine's always have fewest events.")
def check(paths: tuple[str, ...], names: tuple[str, ...], bound: int, range_specs: tuple[str, ...],
          set_specs: tuple[str, ...], timeout: float | None, fmt: str, engine: str, max_states: int,
          shortest: str) -> None:
    """Check the assertions of the model in PATHS.

    Exit status: 0 all hold, 10 some violated, 20 none violated but some unknown or
    unsupported, 2 usage error, 3 model error, 1 internal error, 130 interrupted (Ctrl-C: the
    verdicts decided so far are printed).
    """
    ranges = _ranges(range_specs)
    settings = _settings(set_specs)
    project = _load(paths)
    known = {a.name for a in project.assertions}
    for n in names:
        if n not in known:
            raise click.BadParameter(f"no assertion named '{n}' (known: {', '.join(sorted(known)) or 'none'})",
                                     param_hint="'-a'")
    if engine == "explicit":
        from tockbmc.explicit.engine import iter_check_explicit
        from tockbmc.explicit.interpreter import Unbounded
        try:
            decided = decide(iter_check_explicit(project, names or None, bound, ranges, settings, timeout, max_states))
        except Unbounded as exc:
            raise click.UsageError(f"--engine explicit needs finite data: give a range for {exc.name} "
                                   f"(--range {exc.name}=LO..HI)") from None
    else:
        decided = decide(iter_check(project, names or None, bound, ranges, settings, timeout, shortest=shortest))
    results = decided.results
    if decided.interrupted:  # Ctrl-C: what was decided, then the rest as interrupted
        seen = {r.assertion for r in results}
        results = [*results, *(interrupted(a, ranges, engine) for a in project.assertions
                               if (not names or a.name in names) and a.name not in seen)]
    with reader_may_leave(sys.stdout):  # `tockbmc check … | head`: the verdicts still decide the status
        if fmt == "json":
            click.echo(json.dumps(results_json(results, __version__), indent=2))
        else:
            width = None if sys.stdout.isatty() else 160
            print_results(results, PipeConsole(width=width, soft_wrap=True))
    if decided.interrupted:
        _exit_interrupted(decided.worker_done)
    counts = summary_counts(results)
    sys.exit(10 if counts["violated"] else 20 if counts["unknown"] or counts["unsupported"] else 0)


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("--element", default=None, help="The machine, controller or module to run (default: the first module, "
                                                "else controller, else machine).")
@click.option("--steps", type=click.IntRange(0), default=30, show_default=True, help="Steps to take.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random choices.")
@click.option("--range", "range_specs", multiple=True, metavar="NAME=LO..HI",
              help="Range of a type or path the environment's values come from (needed for inputs).")
@click.option("--set", "set_specs", multiple=True, metavar="NAME=VALUE", help="Give a constant a value.")
def simulate(paths: tuple[str, ...], element: str | None, steps: int, seed: int, range_specs: tuple[str, ...],
             set_specs: tuple[str, ...]) -> None:
    """Print a random run of an element of the model in PATHS, as a trace."""
    from tockbmc.explicit.interpreter import NotInterpretable, Unbounded
    from tockbmc.explicit.simulate import run_random
    project = _load(paths)
    ranges = _ranges(range_specs)
    settings = _settings(set_specs)
    try:
        result = run_random(project, element, steps, seed, ranges, settings)
    except LookupError as exc:
        raise click.BadParameter(str(exc), param_hint="'--element'") from None
    except Unbounded as exc:
        raise click.UsageError(f"simulate needs finite data: give a range for {exc.name} "
                               f"(--range {exc.name}=LO..HI)") from None
    except NotInterpretable as exc:
        click.echo(f"{exc.pos}: unsupported: {exc.what}", err=True)
        sys.exit(EXIT_MODEL_ERROR)
    width = None if sys.stdout.isatty() else 160
    with reader_may_leave(sys.stdout):  # `tockbmc simulate … | head`
        console = PipeConsole(width=width, soft_wrap=True)
        console.print(Text(result.text, style="bold"))
        print_trace(result, console)


def _guarded(command: Callable[[], T]) -> Callable[[], T]:
    def run() -> T:
        try:
            return command()
        except SystemExit:
            raise
        except KeyboardInterrupt:
            _exit_interrupted()
        except RecursionError:
            click.echo("tockbmc: internal error: input nested too deeply", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)
        except Exception as exc:  # one line, never a traceback
            click.echo(f"tockbmc: internal error: {type(exc).__name__}: {exc}", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)

    return run


def _exit_interrupted(clean: bool = True) -> NoReturn:
    """Exit as interrupted (128 + SIGINT), at once if a worker thread may still be inside Z3."""
    with reader_may_leave(sys.stderr):
        click.echo("tockbmc: interrupted", err=True)
    if clean:
        sys.exit(EXIT_INTERRUPTED)
    with contextlib.suppress(OSError):
        sys.stdout.flush()
        sys.stderr.flush()
    os._exit(EXIT_INTERRUPTED)  # no interpreter shutdown under a thread that is still running Z3


def _run() -> None:
    """The click group, with Ctrl-C (outside `check`'s own handling) an interruption, not an error."""
    try:
        status = cli.main(standalone_mode=False)
    except click.ClickException as exc:
        exc.show()
        sys.exit(exc.exit_code)
    except click.Abort:  # click turns KeyboardInterrupt into Abort
        _exit_interrupted()
    sys.exit(status if isinstance(status, int) else 0)


def main() -> None:
    """Console entry point."""
    for name in usable_streams():
        if name == "stdout":
            click.echo("tockbmc: standard output is closed: nothing is printed there", err=True)
    _guarded(_run)()
