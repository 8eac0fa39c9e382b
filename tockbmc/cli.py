"""The `tockbmc` command line: a thin shell over the Python API."""

from __future__ import annotations

import json
import sys
from typing import Callable, TypeVar

import click
from rich.console import Console

from tockbmc import __version__
from tockbmc.model import ModelError, Project, load
from tockbmc.report.diagnostics import render, summary
from tockbmc.report.structure import project_data, project_tree

EXIT_MODEL_ERROR = 3
EXIT_INTERNAL_ERROR = 1

T = TypeVar("T")


def _load(paths: tuple[str, ...]) -> Project:
    """Load a project, or print its diagnostics and exit 3."""
    try:
        project = load(*paths)
    except ModelError as exc:
        click.echo(render(exc.diagnostics, exc.sources), err=True)
        click.echo(summary(exc.diagnostics), err=True)
        sys.exit(EXIT_MODEL_ERROR)
    if project.warnings:
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
        click.echo(json.dumps({"tool": "tockbmc", "version": __version__, **project_data(project)}, indent=2))
    else:
        # A pipe or a CI log has no width: never crop the tree there.
        width = None if sys.stdout.isatty() else 100_000
        Console(soft_wrap=True, width=width).print(project_tree(project))


def _guarded(command: Callable[[], T]) -> Callable[[], T]:
    def run() -> T:
        try:
            return command()
        except (KeyboardInterrupt, SystemExit):
            raise
        except RecursionError:
            click.echo("tockbmc: internal error: input nested too deeply", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)
        except Exception as exc:  # one line, never a traceback
            click.echo(f"tockbmc: internal error: {type(exc).__name__}: {exc}", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)

    return run


def main() -> None:
    """Console entry point."""
    _guarded(lambda: cli.main(standalone_mode=True))()
