"""The `tockbmc` command line: a thin shell over the Python API."""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.util
import io
import json
import math
import os
import signal
import stat
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import NoReturn, TypeVar

import click
from rich.console import Console
from rich.text import Text

from tockbmc import __version__
from tockbmc.check import DEFAULT_BOUND
from tockbmc.explicit.interpreter import Unbounded
from tockbmc.interrupt import Decided, Terminated, decide, interrupted, terminate_as_interrupt
from tockbmc.model import ModelError, Project, ast, load
from tockbmc.model.config import ConfigError, Configuration, configure, parse_number
from tockbmc.model.core import core_assertions
from tockbmc.model.diagnostics import suggestion
from tockbmc.model.limits import recursion_room
from tockbmc.model.ranges import Range
from tockbmc.model.readings import Reading
from tockbmc.model.result import Result, exit_code
from tockbmc.parallel import InProcess, InProcesses, Job, OnDask, Unreachable, overran, stop_servers, warm_up
from tockbmc.report import itf, junit, sarif
from tockbmc.report.diagnostics import render, summary
from tockbmc.report.progress import ProgressDisplay
from tockbmc.report.results import ResultTable, print_details, print_step
from tockbmc.report.results import to_json as results_json
from tockbmc.report.streams import PipeConsole, reader_may_leave, usable_streams
from tockbmc.report.structure import project_data, project_tree

EXIT_INTERRUPTED = 130
EXIT_MODEL_ERROR = 3
EXIT_INTERNAL_ERROR = 1
EXIT_REPORT_UNWRITTEN = 4  # the verdicts were printed; the HTML report could not be written

T = TypeVar("T")


def _load(paths: tuple[str, ...], fmt: str = "text") -> Project:
    """Load a project, or print its diagnostics and exit 3 (also on stdout in the document of `fmt`, but itf's)."""
    try:
        project = load(*paths)
    except ModelError as exc:
        with reader_may_leave(sys.stdout):
            if fmt == "json":
                click.echo(json.dumps(results_json([], __version__, "model-error", exc.diagnostics), indent=2))
            elif fmt == "sarif":
                click.echo(json.dumps(sarif.model_error_log(exc.diagnostics, __version__), indent=2))
            elif fmt == "junit":
                click.echo(junit.model_error_report(exc.diagnostics, exc.sources))
        with reader_may_leave(sys.stderr):
            click.echo(render(exc.diagnostics, exc.sources), err=True)
            click.echo(summary(exc.diagnostics), err=True)
        sys.exit(EXIT_MODEL_ERROR)
    if project.warnings:
        with reader_may_leave(sys.stderr):
            click.echo(render(project.warnings, project.sources), err=True)
    return project


class _Commands(click.Group):
    """The commands, each with Ctrl-C and SIGTERM taken as interruptions here: left to click, they
    become its `Abort`, after a blank line on stderr, and SIGTERM would pass for Ctrl-C."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt as exc:
            _exit_interrupted(signum=signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
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
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI or NAME=unbounded", param_hint="'--range'")
    if spec == "unbounded":
        return name, None
    low, sep, high = spec.partition("..")
    if not sep:
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI, e.g. core_int=-1..1", param_hint="'--range'")
    try:
        lo, hi = parse_number(low, "--range"), parse_number(high, "--range")
    except ConfigError as exc:
        raise click.BadParameter(f"'{text}': {exc}", param_hint="'--range'") from None
    if lo > hi:
        raise click.BadParameter(f"'{text}': expected NAME=LO..HI with LO <= HI", param_hint="'--range'")
    return name, Range(lo, hi)


def _ranges(specs: tuple[str, ...]) -> dict[str, Range | None]:
    """`--range` options by name, the last one of a name winning; names are checked against the model later."""
    return dict(_parse_range(spec) for spec in specs)


def _settings(specs: tuple[str, ...]) -> dict[str, str]:
    """`--set` options by name; names and values are checked against the model later."""
    result: dict[str, str] = {}
    for spec in specs:
        name, sep, text = spec.partition("=")
        if not sep or not name or not text:
            raise click.BadParameter(f"'{spec}': expected NAME=VALUE", param_hint="'--set'")
        if result.get(name, text) != text:
            raise click.BadParameter(f"{name} is given two values, {result[name]} and {text}", param_hint="'--set'")
        result[name] = text
    return result


def _known_assertions(project: Project, names: tuple[str, ...]) -> None:
    """A usage error, with the closest name and the known ones, for a name `-a` gives that no
    assertion has (an assertion's name, or its label `file.assertions:name` where two files share it)."""
    known = sorted({a.label for a in project.assertions})
    for n in names:
        if not any(a.selected_by(n) for a in project.assertions):
            closest = suggestion(n, known + [a.name for a in project.assertions])
            raise click.BadParameter(f"no assertion named '{n}'{closest} (known: "
                                     f"{', '.join(known) or 'none'})", param_hint="'-a'")


def _range_hint(exc: Unbounded, config: Configuration) -> str:
    """What to give for a value the explicit engine cannot list: the `--range` that `check` takes
    for it (a core or model type, else a path, whose range bounds a sequence's length), never one it
    would refuse (it used to suggest `--range Seq(int)=LO..HI`)."""
    for name in (exc.name, *exc.paths):
        try:
            t = config.names.range_type(name)[1]
        except ConfigError:
            continue
        what = "its length" if isinstance(t, ast.SeqType) else "its values"
        return f"give a range for {exc.path or name} ({what}: --range {name}=LO..HI)"
    return f"no range can be given for {exc.path or exc.name} (of type {exc.name})"


def _configure(project: Project, range_specs: tuple[str, ...], set_specs: tuple[str, ...],
               param_specs: tuple[str, ...] = (), reading: Reading = Reading.DEFAULT) -> Configuration:
    """Resolve `--range`, `--set` and `--param` against the model and its instantiation (exit 2 if one
    does not fit), in `reading`; print the instantiation's warnings."""
    ranges, settings = _ranges(range_specs), _settings(set_specs)
    try:
        config = configure(project, ranges, settings, param_specs, reading=reading)
    except ConfigError as exc:
        raise click.BadParameter(str(exc), param_hint=f"'{exc.option}'") from None
    if config.warnings:
        click.echo(render(config.warnings, {**project.sources, **config.texts}), err=True)
    return config


def _finite(ctx: click.Context, param: click.Parameter, value: float | None) -> float | None:
    """`FloatRange` lets `nan` and `inf` through: neither is a number of seconds."""
    if value is not None and not math.isfinite(value):
        raise click.BadParameter(f"{value} is not a finite number of seconds")
    return value


def _report_file(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """`--report`'s file goes in a directory that exists and may be written, which is checked before
    the assertions are decided (`click.Path` checks an existing file only)."""
    if value is not None:
        folder = Path(value).resolve().parent
        if not folder.is_dir():
            raise click.BadParameter(f"'{value}': no directory {folder}")
        if not os.access(folder, os.W_OK):
            raise click.BadParameter(f"'{value}': directory {folder} is not writable")
    return value


def default_jobs() -> int:
    """The number of cores.  Measured on two cores, idle, RoboTool's suite (`benchmarks/conformance.py
    --timeout 20`): 107 s with `-j 2` against 200 s with `-j 1`, since many checks
    leave the second core idle (Spacer does not apply, or a check waits out its timeout)."""
    return max(1, os.cpu_count() or 1)


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("-a", "--assertion", "names", multiple=True,
              help="Check only the assertions of this name, or the one of this label (FILE.assertions:NAME, "
                   "where two files reuse the name) (repeatable).")
@click.option("-k", "--bound", type=click.IntRange(0), default=DEFAULT_BOUND, show_default=True,
              help="Maximum number of steps (events, tocks and internal steps) searched.")
@click.option("--range", "range_specs", multiple=True, metavar="NAME=LO..HI",
              help="Bound a type (core_int, core_nat, core_real, a model type) or a path (EXAX::move.time); "
                   "NAME=unbounded lifts it.")
@click.option("--set", "set_specs", multiple=True, metavar="NAME=VALUE",
              help="Give a constant a value (NAME: n, UR::n, main::ctrl::ur_ref::n, …); overrides the instantiation. "
                   "A name qualified by its element (UR::n) sets every instance of the machine; a path of "
                   "instances (main::ctrl::ur_ref::n) sets that instance's constant only, and wins over the "
                   "element's name for it.")
@click.option("--param", "param_specs", multiple=True, metavar="NAME",
              help="Make a constant without a value a parameter: every value of its type and range is considered.")
@click.option("--open", "open_reading", is_flag=True,
              help="The open reading: nothing the model leaves unset is filled in (variables start at any value, "
                   "functions without a body are any function meeting their contract, constants without a value "
                   "are parameters). By default RoboTool's instantiation fills them in.")
@click.option("--robotool", "robotool_reading", is_flag=True,
              help="FDR's finite check: RoboTool's instantiation with its default ranges (core_int=-2..2, "
                   "core_nat=0..2, core_real=-2..2) for every type nothing else bounds, reals as integers and "
                   "RoboTool's bounded arithmetic (a result outside its type's range leaves the first operand). "
                   "Excludes --open.")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None, callback=_finite,
              help="Seconds per assertion; past it the verdict is 'unknown'.")
@click.option("--format", "fmt", type=click.Choice(["text", "json", "itf", "sarif", "junit"]), default="text",
              show_default=True, help="A table and traces, the JSON contract, the traces in Apalache's ITF, "
                                      "SARIF 2.1.0 (code scanning), or JUnit XML (CI test reports).")
@click.option("--engine", type=click.Choice(["auto", "bmc", "explicit"]), default="auto", show_default=True,
              help="auto: BMC (with k-induction and PDR) and, where its answer is sound for the reading, the explicit "
                   "engine race, the first answer for every run deciding; bmc: symbolic BMC in Z3 alone; explicit: "
                   "breadth-first search over concrete configurations alone (finite ranges).")
@click.option("--max-states", type=click.IntRange(1), default=1_000_000, show_default=True,
              help="The explicit engine's configurations explored before it gives up with 'unknown'.")
@click.option("--shortest", type=click.Choice(["steps", "events"]), default="steps", show_default=True,
              help="BMC's counterexamples: fewest steps (found first), or fewest events and tocks within the "
                   "bound (searches on to the bound; slower). The explicit engine's always have fewest events.")
@click.option("--core", is_flag=True, help="Also check RoboTool's core assertions of every machine, controller and "
                                           "module (deadlock-free, deterministic, divergence-free, timelock-free); "
                                           "a model without assertions gets them anyway.")
@click.option("--report", "report_path", type=click.Path(dir_okay=False, writable=True), default=None,
              callback=_report_file,
              metavar="FILE.html", help="Also write the results as one self-contained HTML page: the verdict table, "
                                        "the scope, and each trace as a sequence diagram beside its steps.")
@click.option("-j", "--jobs", type=click.IntRange(1), default=None, metavar="N",
              help="Decide the assertions in N worker processes (default: the number of cores); 1 decides them "
                   "in this process.  The results and their order are the same, but that a worker still deciding "
                   "at twice --timeout plus 5 s is ended (Z3 overran) and its assertion is unknown (so is a lone "
                   "assertion; several with -j 1 have no such limit).")
@click.option("--dask", "dask_address", default=None, metavar="ADDRESS",
              help="Decide the assertions as tasks on the Dask cluster whose scheduler is at ADDRESS "
                   "(tcp://host:8786); needs pip install 'tockbmc[dask]', here and on the workers.")
def check(paths: tuple[str, ...], names: tuple[str, ...], bound: int, range_specs: tuple[str, ...],
          set_specs: tuple[str, ...], param_specs: tuple[str, ...], open_reading: bool, robotool_reading: bool,
          timeout: float | None, fmt: str, engine: str, max_states: int, shortest: str, core: bool,
          report_path: str | None, jobs: int | None, dask_address: str | None) -> None:
    """Check the assertions of the model in PATHS.

    Exit status: 0 all hold, 10 some violated, 20 none violated but some unknown or
    unsupported, 2 usage error, 3 model error, 4 the --report file could not be written (the
    verdicts were printed), 1 internal error, 130 interrupted (Ctrl-C: the verdicts decided so far
    are printed), 143 terminated (SIGTERM: as Ctrl-C).
    """
    _ranges(range_specs)  # malformed options are usage errors, found before any loading
    _settings(set_specs)
    if open_reading and robotool_reading:
        raise click.UsageError("--open and --robotool exclude each other: a check has one reading")
    reading = Reading.OPEN if open_reading else Reading.ROBOTOOL if robotool_reading else Reading.DEFAULT
    workers = jobs if jobs is not None else default_jobs()
    if dask_address is not None:
        if jobs is not None:
            raise click.UsageError("--dask and -j/--jobs exclude each other: the cluster's workers decide")
        if importlib.util.find_spec("distributed") is None:
            raise click.UsageError("--dask needs Dask's distributed scheduler: pip install 'tockbmc[dask]'")
    elif workers > 1 and len(names) != 1:
        warm_up()  # worker processes are likely wanted: their server starts while the model loads
    project = _load(paths, fmt)
    if core or not project.assertions:
        if not project.assertions:
            click.echo("tockbmc: the model has no assertions: checking RoboTool's core assertions", err=True)
        project = dataclasses.replace(project, assertions=project.assertions + core_assertions(project))
    config = _configure(project, range_specs, set_specs, param_specs, reading)
    _known_assertions(project, names)
    selected = [i for i, a in enumerate(config.project.assertions) if not names or any(a.selected_by(n) for n in names)]
    results, decided = _decide(Job(config, bound, timeout, shortest, engine, max_states), selected, fmt, workers,
                               dask_address)
    with reader_may_leave(sys.stdout):  # `tockbmc check … | head`: the verdicts still decide the status
        if fmt == "json":
            status = "interrupted" if decided.interrupted else "checked"
            click.echo(json.dumps(results_json(results, __version__, status), indent=2))
        elif fmt == "itf":
            click.echo(json.dumps(itf.document(results, __version__), indent=2))
        elif fmt == "sarif":
            click.echo(json.dumps(sarif.log(results, __version__, project.assertions), indent=2))
        elif fmt == "junit":
            click.echo(junit.report(results))
        else:
            print_details(results, _stdout_console())
    written = report_path is None or _report_written(report_path, results, " ".join(paths))
    if decided.interrupted:
        _exit_interrupted(decided.worker_done, decided.signal)
    code = exit_code(r.verdict for r in results) if written else EXIT_REPORT_UNWRITTEN
    if not decided.worker_done:  # given up at its hard limit, the deciding thread is still inside Z3
        _exit_now(code)
    sys.exit(code)


def _report_written(path: str, results: list[Result], title: str) -> bool:
    """Write the HTML report, after the verdicts are printed; where it cannot be written (a full disk,
    a directory gone), say so in one line and return False."""
    from tockbmc.report.html import write_report

    try:
        write_report(path, results, title=title, version=__version__)
    except OSError as exc:
        click.echo(f"tockbmc: the report {path} was not written: {exc.strerror or exc}", err=True)
        return False
    return True


def _stdout_console() -> PipeConsole:
    # A pipe or a CI log has no width: a wide one, so that rows are not wrapped.
    return PipeConsole(width=None if sys.stdout.isatty() else 160, soft_wrap=True)


def _shows_progress(fmt: str) -> bool:
    """Whether to show a progress display on stderr: when it is a terminal, unless the text table's rows
    go down a pipe, whose reader (`| tee`, `| head`) may write them to that terminal while the display
    redraws itself over them."""
    if not sys.stderr.isatty():
        return False
    if fmt != "text" or sys.stdout.isatty():
        return True
    try:
        mode = os.fstat(sys.stdout.fileno()).st_mode
    except (OSError, ValueError, io.UnsupportedOperation):  # no descriptor (a test's capture): not a terminal
        return False
    return not (stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode))


def _decide(job: Job, selected: list[int], fmt: str, workers: int,
            dask_address: str | None) -> tuple[list[Result], Decided[tuple[int, Result]]]:
    """Decide the assertions `selected` (indices in the project), in this process, in `workers` processes or on
    a Dask cluster, with a progress display on a terminal's stderr and, in text, each row of the table printed
    as soon as the rows before it are in.  The results, in the order of `selected` (the assertions Ctrl-C
    stopped `interrupted`), and how the drawing ended."""
    assertions = [job.config.project.assertions[i] for i in selected]
    labels = [a.label for a in assertions]
    display = ProgressDisplay(labels, job.bound, Console(stderr=True)) if _shows_progress(fmt) else None
    progress = display.progress_of if display is not None else None
    work = [(job, i) for i in selected]
    runner: InProcess | InProcesses | OnDask
    if dask_address is not None:
        runner = OnDask(work, dask_address, progress)
    elif workers == 1 or len(work) <= 1:
        # Decided here (a worker costs about a second to start); a lone assertion is given up at its
        # hard limit (Job.hard_limit) by the waiting thread, -j 1's several are not (the next ones
        # would share the process with a thread still inside Z3).
        runner = InProcess(work, progress)
    else:
        runner = InProcesses(work, workers, progress)
    table = None
    if fmt == "text":
        # On a terminal beside the display, rows go through the display's console, which prints them
        # above itself; printed past it, they would be drawn over.
        console = display.progress.console if display is not None and sys.stdout.isatty() else _stdout_console()
        table = ResultTable(console, labels, explicit=job.engine == "explicit")

    def show(item: tuple[int, Result]) -> None:
        n, r = item
        if display is not None:
            display.decided(n, r)
        if table is not None:
            with reader_may_leave(sys.stdout):
                table.add(n, r)

    with display or contextlib.nullcontext():
        try:
            watch = runner.overdue if isinstance(runner, InProcess) and len(work) == 1 else None
            decided = decide(runner, on_item=show, stop=runner.stop, overdue=watch)
        except Unbounded as exc:
            raise click.UsageError(f"--engine explicit needs finite data: {_range_hint(exc, job.config)}") from None
        except Unreachable as exc:
            raise click.BadParameter(str(exc), param_hint="'--dask'") from None
        got = dict(decided.results)
        n = decided.overran
        if n is not None and n not in got and isinstance(runner, InProcess) and runner.given_up is not None:
            got[n] = overran(job, selected[n], time.perf_counter() - runner.given_up[1], in_process=True)
            show((n, got[n]))
    ranges = job.config.ranges()
    results = [got[n] if n in got else interrupted(a, ranges, job.reported_engine) for n, a in enumerate(assertions)]
    if table is not None:
        for n, r in enumerate(results):
            table.results.setdefault(n, r)
        with reader_may_leave(sys.stdout):
            table.finish()
    return results, decided


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("-a", "--assertion", "names", multiple=True,
              help="Explore only the assertions of this name, or the one of this label (FILE.assertions:NAME, "
                   "where two files reuse the name) (repeatable).")
@click.option("--param", "param_specs", multiple=True, metavar="NAME",
              help="What varies (repeatable): a range (core_int, core_nat, core_real, a model type, a path "
                   "EXAX::move.time), whose bounds become parameters, or a constant without a value.  Default: "
                   "every core range --range does not fix, and every constant without a value.")
@click.option("--range", "range_specs", multiple=True, metavar="NAME=LO..HI", help="Fix a range (as for check).")
@click.option("--set", "set_specs", multiple=True, metavar="NAME=VALUE", help="Fix a constant (as for check).")
@click.option("-k", "--bound", type=click.IntRange(0), default=DEFAULT_BOUND, show_default=True,
              help="Maximum number of steps searched where no proof for every length is found.")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=120.0, show_default=True,
              callback=_finite, help="Seconds per assertion; past it the region is reported as not complete.")
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="Text, or JSON.")
def explore(paths: tuple[str, ...], names: tuple[str, ...], param_specs: tuple[str, ...],
            range_specs: tuple[str, ...], set_specs: tuple[str, ...], bound: int, timeout: float, fmt: str) -> None:
    """Say, for each assertion of the model in PATHS, exactly which ranges and constants violate it.

    The bounds of the ranges and the constants that vary are symbols: for each assertion the
    exact set of their values with a counterexample is computed (to the bound, or for runs of
    every length where a proof is found), printed as a condition in the model's names with the
    parameters it does not depend on, one counterexample replayed at a point inside, and the
    values each input field of a shortest counterexample can carry.

    Exit status: 0 every region found, 20 some not complete or unsupported, 2 usage error,
    3 model error, 1 internal error.
    """
    from tockbmc.explore import explore as explore_project
    from tockbmc.model.exploration import Exploration
    from tockbmc.report.explore import print_exploration, print_scope
    from tockbmc.report.explore import to_json as explore_json

    ranges, settings = _ranges(range_specs), _settings(set_specs)
    project = _load(paths, fmt)
    if not project.assertions:  # as `check` does
        click.echo("tockbmc: the model has no assertions: exploring RoboTool's core assertions", err=True)
        project = dataclasses.replace(project, assertions=core_assertions(project))
    _known_assertions(project, names)
    console = _stdout_console()

    def show(e: Exploration) -> None:
        if fmt == "text":
            with reader_may_leave(sys.stdout):
                print_exploration(e, console)

    try:  # in a worker thread, as `check` decides: Ctrl-C and SIGTERM stop it within a moment
        decided = decide(explore_project(project, names or None, bound, ranges, settings, param_specs, timeout),
                         on_item=show)
    except ConfigError as exc:
        raise click.BadParameter(str(exc), param_hint=f"'{exc.option}'") from None
    found = decided.results
    if decided.interrupted:
        _exit_interrupted(clean=decided.worker_done, signum=decided.signal)
    with reader_may_leave(sys.stdout):
        if fmt == "json":
            click.echo(json.dumps(explore_json(found, __version__, bound), indent=2, ensure_ascii=False))
        else:
            print_scope(found, bound, console)
    sys.exit(0 if all(e.status == "region" for e in found) else 20)


@cli.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("--element", default=None, help="The machine, controller or module to run (default: the first module, "
                                                "else controller, else machine).")
@click.option("--steps", type=click.IntRange(0), default=30, show_default=True, help="Steps to take.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random choices.")
@click.option("--range", "range_specs", multiple=True, metavar="NAME=LO..HI",
              help="Bound a type or path the environment's values come from (a type without one: RoboTool's "
                   "default range, core_int=-2..2, …).")
@click.option("--set", "set_specs", multiple=True, metavar="NAME=VALUE", help="Give a constant a value.")
def simulate(paths: tuple[str, ...], element: str | None, steps: int, seed: int, range_specs: tuple[str, ...],
             set_specs: tuple[str, ...]) -> None:
    """Print a random run of an element of the model in PATHS, as a trace."""
    from tockbmc.explicit.interpreter import NotInterpretable, Unbounded
    from tockbmc.explicit.simulate import RandomRun, pick
    project = _load(paths)
    config = _configure(project, range_specs, set_specs)
    try:
        chosen = pick(config.project, element)
    except LookupError as exc:
        raise click.BadParameter(str(exc), param_hint="'--element'") from None
    width = None if sys.stdout.isatty() else 160
    try:
        setup = config.setup(None, chosen)
        run = RandomRun(config.project, element, steps, seed, setup.ranges, setup.constants)
        # the interpreter evaluates a nested expression by recursion, two frames a level
        with reader_may_leave(sys.stdout), recursion_room():  # `tockbmc simulate … | head`
            console = PipeConsole(width=width, soft_wrap=True)
            console.print(Text(run.text, style="bold"))
            for step in run:  # each as it is taken: a long run streams, in flat memory
                print_step(step, console)
            console.print(Text(f"  → {run.end()}", style="bold"))
    except Unbounded as exc:
        raise click.UsageError(f"simulate needs finite data: {_range_hint(exc, config)}") from None
    except NotInterpretable as exc:
        click.echo(f"{exc.pos}: unsupported: {exc.what}", err=True)
        sys.exit(EXIT_MODEL_ERROR)


def _guarded(command: Callable[[], T]) -> Callable[[], T]:
    def run() -> T:
        try:
            return command()
        except SystemExit:
            raise
        except KeyboardInterrupt as exc:
            _exit_interrupted(signum=signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
        except RecursionError:
            click.echo("tockbmc: internal error: input nested too deeply", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)
        except Exception as exc:  # one line, never a traceback
            click.echo(f"tockbmc: internal error: {type(exc).__name__}: {exc}", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)

    return run


def _exit_interrupted(clean: bool = True, signum: int = signal.SIGINT) -> NoReturn:
    """Exit as interrupted (128 + the signal: 130 for Ctrl-C, 143 for SIGTERM), at once if a worker
    thread may still be inside Z3."""
    with reader_may_leave(sys.stderr):
        click.echo("tockbmc: interrupted" if signum == signal.SIGINT else "tockbmc: terminated (SIGTERM)", err=True)
    code = 128 + signum
    if clean:
        sys.exit(code)
    _exit_now(code)


def _exit_now(code: int) -> NoReturn:
    """Exit at once, without the interpreter's shutdown, which would wait on a thread still inside Z3;
    the output is flushed and the fork server (if `check -j` started one) ended first."""
    with contextlib.suppress(OSError):
        sys.stdout.flush()
        sys.stderr.flush()
    stop_servers()
    os._exit(code)


def _run() -> None:
    """The click group, with Ctrl-C (outside `check`'s own handling) an interruption, not an error."""
    try:
        status = cli.main(standalone_mode=False)
    except click.ClickException as exc:
        exc.show()
        sys.exit(exc.exit_code)
    except click.Abort as exc:  # click turns KeyboardInterrupt (and so SIGTERM's `Terminated`) into Abort
        _exit_interrupted(signum=signal.SIGTERM if isinstance(exc.__cause__, Terminated) else signal.SIGINT)
    sys.exit(status if isinstance(status, int) else 0)


def main() -> None:
    """Console entry point."""
    terminate_as_interrupt()
    for name in usable_streams():
        if name == "stdout":
            click.echo("tockbmc: standard output is closed: nothing is printed there", err=True)
    _guarded(_run)()
