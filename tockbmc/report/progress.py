"""What `check` is doing, on a terminal: the assertions being checked, each with the depth its search has
cleared, and how many are decided (rich's live progress display, on stderr).

The depths are the engines' own (`bmc.engine.Progress`, the explicit search's visible steps); the
display only shows them.  Nothing here decides anything, and a log that is not a terminal gets none
of it.
"""

from __future__ import annotations

import threading

from rich.console import Console
from rich.progress import BarColumn, Progress, SpinnerColumn, TaskID, TextColumn, TimeElapsedColumn

from tockbmc.model.result import Result, Verdict
from tockbmc.report.results import VERDICT_STYLE


class ProgressDisplay:
    """A live display of a `check` run on `console` (a terminal): a line per assertion being
    checked, with a bar of the depth its search has cleared out of the bound, under a line counting
    the verdicts so far.  Its methods may be called from any thread; what is printed on `console`
    meanwhile appears above the display (rich moves it)."""

    def __init__(self, names: list[str], bound: int | None, console: Console):
        self.names, self.bound = names, bound
        self.progress = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(bar_width=24),
                                 TextColumn("{task.fields[status]}"), TimeElapsedColumn(),
                                 console=console, transient=True)
        self.overall = self.progress.add_task("checked", total=len(names), status=self._tally({}))
        self.running: dict[int, TaskID] = {}
        self.verdicts: dict[Verdict, int] = {}
        self.lock = threading.Lock()  # `running` and `verdicts` are shared by the threads that report

    def __enter__(self) -> ProgressDisplay:
        self.progress.start()
        return self

    def __exit__(self, *_: object) -> None:
        self.progress.stop()

    @staticmethod
    def _tally(verdicts: dict[Verdict, int]) -> str:
        return ", ".join(f"[{VERDICT_STYLE[v]}]{n} {v.value}[/]" for v, n in verdicts.items()) or "none decided yet"

    def progress_of(self, index: int, depth: int | None) -> None:
        """`started` when `depth` is None, else `reached` (the form `parallel.Progress` takes)."""
        if depth is None:
            self.started(index)
        else:
            self.reached(index, depth)

    def started(self, index: int) -> None:
        """Assertion `index` (of `names`) is being checked."""
        with self.lock:
            if index not in self.running:
                self.running[index] = self.progress.add_task(self.names[index], total=self.bound or None,
                                                             status="starting")

    def reached(self, index: int, depth: int) -> None:
        """The search for assertion `index` has cleared `depth`: no run of that length reaches what it seeks."""
        self.started(index)
        with self.lock:
            task = self.running.get(index)
            if task is not None:
                of = f" of {self.bound}" if self.bound is not None else ""
                self.progress.update(task, completed=depth, status=f"depth {depth}{of}")

    def decided(self, index: int, result: Result) -> None:
        """Assertion `index` has its verdict."""
        with self.lock:
            task = self.running.pop(index, None)
            if task is not None:
                self.progress.remove_task(task)
            self.verdicts[result.verdict] = self.verdicts.get(result.verdict, 0) + 1
            self.progress.update(self.overall, advance=1, status=self._tally(self.verdicts))
