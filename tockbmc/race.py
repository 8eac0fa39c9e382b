"""The portfolio: BMC (with k-induction and Spacer's PDR) and the explicit engine race on one assertion.

Each engine decides in a process of its own, forked from this one: nothing is pickled on the way
in, the result is on the way out, and the engine that loses is ended at once, even inside Z3.
The first answer that covers every run decides — a counterexample or witness trace, a proof for
every length, an exhaustive exploration. A verdict only to the bound waits for the other engine
for as long again as it took (at least `GRACE`, at most the timeout); `unknown`, `unsupported` or
a failure of one engine waits for the other's answer as long as that engine takes. Then the
better answer is reported (a verdict to the bound over `unknown` over `unsupported`; BMC's where
they are equal). The result
names the engine that decided (`Result.engine`); which engine wins may change from run to run,
the verdict does not.

The explicit engine races only where its answer means what the reading asks: always with
`--robotool` (finite by construction, reals are integers); in the default and open readings only
where the data it would explore are bounded (`core_int` and `core_nat` given ranges) and no real
is sampled at its integers. Elsewhere BMC decides alone, in this process, as `--engine bmc` does.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing import Pipe
from multiprocessing.connection import Connection, wait

from tockbmc.check import check_assertion as check_bmc
from tockbmc.explicit.engine import check_assertion as check_explicit
from tockbmc.model import ast
from tockbmc.model.config import Configuration
from tockbmc.model.lifetime import end_with
from tockbmc.model.result import Proof, Result, Verdict

GRACE = 10.0  # seconds the other engine is waited for after a first answer short of a complete one (no timeout)
HARD_SLACK = 2.0  # seconds past twice the timeout after which both engines are ended (Z3 not stopping in time;
# before `parallel.Job.hard_limit` ends the process the race is in)

_LIVE: set[int] = set()  # pids of the engines racing now, ended by `stop_all` (Ctrl-C)
_LIVE_LOCK = threading.Lock()
_STOPPED = threading.Event()  # set by `stop_all`: no race starts after it
_REALS: dict[int, tuple[ast.Project, bool]] = {}  # `uses_reals` by project (kept: the id stays its own)


def complete(r: Result) -> bool:
    """Whether `r` covers every run: it needs nothing more from another engine."""
    return r.verdict in (Verdict.HOLDS, Verdict.VIOLATED) and (r.proof.every_length or r.proof == Proof.TRACE)


def explicit_races(config: Configuration) -> bool:
    """Whether the explicit engine's answer is sound for the configuration's reading (see above).
    Never with a range on one path or a parametric one: the interpreter spells paths its own way."""
    ranges = config.ranges()
    if ranges.by_path or ranges.parametric:
        return False
    if ranges.integral_reals:
        return True
    if not all(name in ranges.by_type for name in ("core_int", "core_nat")):
        return False
    project = config.project
    known = _REALS.get(id(project))
    if known is None or known[0] is not project:
        known = _REALS[id(project)] = (project, uses_reals(project))
    return not known[1]


def uses_reals(project: ast.Project) -> bool:
    """Whether anything of the project's model has a real type (a value, a variable, an event's)."""
    return any(isinstance(item, ast.PrimitiveType) and item == ast.REAL
               for item in ast.parts(project.machines, project.operations, project.controllers, project.functions,
                                     project.modules, project.interfaces, project.platforms))


def decide(project: ast.Project, a: ast.Assertion, bound: int, config: Configuration, timeout: float | None,
           induction: bool = True, shortest: str = "steps", max_states: int | None = None,
           progress: Callable[[int], None] | None = None) -> Result:
    """The verdict of assertion `a` by the portfolio (see the module's text)."""
    def bmc(tell: Callable[[int], None] | None) -> Result:
        return check_bmc(project, a, bound, config, timeout, induction, shortest, tell)

    if not explicit_races(config):
        return bmc(progress)
    if _STOPPED.is_set():  # Ctrl-C: the thread deciding goes on to the next assertion, whose result is dropped
        raise RaceError("stopped")

    def explicit(_tell: Callable[[int], None] | None) -> Result:
        if max_states is None:
            return check_explicit(project, a, bound, config, timeout)
        return check_explicit(project, a, bound, config, timeout, max_states)

    def overran(seconds: float) -> Result:
        limit = f"its timeout ({timeout:g} s)" if timeout is not None else "the other engine's answer"
        return Result(assertion=a.label, text=a.text, verdict=Verdict.UNKNOWN, bound=bound,
                      ranges=config.ranges().describe(), seconds=seconds, proof=Proof.NONE, pos=str(a.pos),
                      reading=config.reading,
                      reason=f"no engine answered within {limit}: they were ended after {seconds:.0f} s")

    return _Race([_Engine("bmc", bmc), _Engine("explicit", explicit)], timeout, progress, overran).run()


def stop_all() -> None:
    """End every engine racing in this process, and start no other (Ctrl-C)."""
    with _LIVE_LOCK:
        _STOPPED.set()
        pids = list(_LIVE)
    for pid in pids:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)


def reset() -> None:
    """Let races start again after `stop_all` (a long-lived process that goes on after Ctrl-C)."""
    _STOPPED.clear()


@dataclass
class _Engine:
    name: str
    work: Callable[[Callable[[int], None] | None], Result]
    pid: int | None = None
    conn: Connection | None = None
    result: Result | None = None
    failure: str | None = None  # an error the engine raised, as one line

    def start(self, tells: bool) -> None:
        """Fork: the child decides and sends ("depth", k)… then ("result", r) or ("error", text)."""
        receive, send = Pipe(duplex=False)
        parent = os.getpid()
        with _LIVE_LOCK:  # registered before `stop_all` can look; none started once it has
            if _STOPPED.is_set():
                receive.close()
                send.close()
                raise RaceError("stopped")
            pid = os.fork()
            if pid != 0:
                _LIVE.add(pid)
        if pid == 0:  # the child: decide, answer, and end without running the parent's exit handlers
            try:
                receive.close()
                _detach(parent)

                def tell(depth: int) -> None:
                    send.send(("depth", depth))

                try:
                    send.send(("result", self.work(tell if tells else None)))
                except BaseException as exc:  # noqa: BLE001 - whatever ends the engine is told to the parent
                    send.send(("error", f"{type(exc).__name__}: {exc}"))
            finally:
                os._exit(0)
        send.close()
        self.pid, self.conn = pid, receive

    def receive(self, progress: Callable[[int], None] | None) -> None:
        """Take what the child has sent; its end (a result, an error, or none: it died) closes it."""
        assert self.conn is not None
        try:
            while self.conn.poll():
                kind, value = self.conn.recv()
                if kind == "depth":
                    if progress is not None:
                        progress(value)
                    continue
                if kind == "result":
                    self.result = value
                else:
                    self.failure = value
                self.end()
                return
        except (EOFError, OSError):
            self.failure = self.failure or f"the {self.name} engine's process ended without an answer"
            self.end()

    @property
    def running(self) -> bool:
        return self.conn is not None

    def end(self) -> None:
        """Kill the child if it is still deciding, and reap it."""
        if self.conn is not None:
            self.conn.close()
            self.conn = None
        if self.pid is not None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.pid, signal.SIGKILL)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(self.pid, 0)
            with _LIVE_LOCK:
                _LIVE.discard(self.pid)
            self.pid = None


def _detach(parent: int) -> None:
    """In an engine's process: Ctrl-C is the parent's to handle, the terminal's streams are let go
    (whoever reads the parent's output must see it end when the parent does; fresh Python streams,
    as another thread of the parent may have held their locks when it forked, and no warnings), and
    the process ends when its parent does, however that ends."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    devnull = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(devnull, fd)
    sys.stdout = sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - for the life of the process
    warnings.simplefilter("ignore")
    if os.getppid() != parent:  # the parent ended before this process looked
        os._exit(0)
    end_with()


class _Race:
    def __init__(self, engines: list[_Engine], timeout: float | None, progress: Callable[[int], None] | None,
                 overran: Callable[[float], Result]):
        self.engines, self.timeout, self.progress, self.overran = engines, timeout, progress, overran

    def run(self) -> Result:
        start = time.monotonic()
        try:
            for n, engine in enumerate(self.engines):
                engine.start(tells=n == 0)  # the display follows BMC's depths
            first_done: float | None = None
            while True:
                running = [e for e in self.engines if e.running]
                if not running:
                    break
                assert all(e.conn is not None for e in running)
                wait([e.conn for e in running if e.conn is not None], timeout=0.5)
                for e in running:
                    e.receive(self.progress if e is self.engines[0] else None)
                decided = [e.result for e in self.engines if e.result is not None and complete(e.result)]
                if decided:
                    return decided[0]
                now = time.monotonic()
                if first_done is None and any(e.result is not None and e.result.verdict in
                                              (Verdict.HOLDS, Verdict.VIOLATED) for e in self.engines):
                    first_done = now  # a verdict to the bound: the other engine has a grace to better it
                if self._past(start, first_done, now):
                    break
        finally:
            for e in self.engines:
                e.end()
        return self._best(time.monotonic() - start)

    def _past(self, start: float, first_done: float | None, now: float) -> bool:
        """Whether the engines still deciding are waited for no longer: past the hard limit, or
        past the grace after a verdict to the bound (each engine keeps to the timeout itself)."""
        if self.timeout is not None and now - start > 2 * self.timeout + HARD_SLACK:
            return True
        return first_done is not None and now - first_done > max(GRACE, first_done - start)

    def _best(self, seconds: float) -> Result:
        """The better of the answers short of complete ones (BMC's where they are equal)."""
        bmc = self.engines[0]
        if bmc.failure is not None:  # an internal error is never hidden behind the other's partial answer
            raise RaceError(bmc.failure)
        rank = {Verdict.HOLDS: 0, Verdict.VIOLATED: 0, Verdict.UNKNOWN: 1, Verdict.UNSUPPORTED: 2}
        answers = [e.result for e in self.engines if e.result is not None]
        if answers:
            return min(answers, key=lambda r: rank[r.verdict])
        return self.overran(seconds)


class RaceError(Exception):
    """BMC failed (an internal error, told as one line: its type and message) and no engine
    answered for every run."""
