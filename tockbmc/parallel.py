"""Deciding assertions in this process, in worker processes (`check -j N`), or as tasks on a Dask
cluster (`check --dask ADDRESS`).

A `Job` is what a worker needs to decide the assertions of one project: the configuration (which
holds the resolved project) and the options of `check`.  It is pickled once and handed to the
workers, which decide assertions by their index in the project; nothing is read from disk there, so
a cluster's workers need tockbmc but not the model's files.  The work is a list of `(job, index)`
pairs, from one project or many.  Each assertion is checked in a Z3 context of its own
(`check.check_assertion`), so its result does not depend on which worker decided it or what that
worker decided before: `-j N` gives what `-j 1` gives, but for the times (and, where Spacer's PDR
and k-induction race to prove the same property, which of the two proofs is reported).

Each way of deciding is an iterable of `(n, Result)` pairs, `n` the position in the work, in the
order the results are decided, with a `stop()` for Ctrl-C; the caller puts them back in order.
Progress (an assertion started, a depth its search cleared) goes to a `Progress` callback, from
worker processes and Dask tasks through a queue.
"""

from __future__ import annotations

import atexit
import contextlib
import multiprocessing
import os
import pickle
import signal
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from multiprocessing import forkserver, resource_tracker, util
from typing import Any

import z3

from tockbmc import race
from tockbmc.check import check_assertion
from tockbmc.explicit.engine import DEFAULT_MAX_STATES
from tockbmc.explicit.engine import check_assertion as check_assertion_explicit
from tockbmc.model.config import Configuration
from tockbmc.model.lifetime import end_with
from tockbmc.model.limits import recursion_room
from tockbmc.model.result import Proof, Result, Verdict

# Told (n, depth): the depth the search for the n-th assertion of the work has cleared, None when its check starts.
Progress = Callable[[int, int | None], None]


HARD_LIMIT_SLACK = 5.0  # seconds past twice the timeout (replay, and k-induction's and PDR's share) before a worker is ended


@dataclass(frozen=True)
class Job:
    """What deciding an assertion needs besides its index: the configuration and `check`'s options."""

    config: Configuration
    bound: int
    timeout: float | None = None
    shortest: str = "steps"
    engine: str = "auto"  # the portfolio (`race`), or "bmc" or "explicit" alone
    max_states: int = DEFAULT_MAX_STATES
    induction: bool = True

    def decide(self, index: int, progress: Callable[[int], None] | None = None) -> Result:
        """The result of assertion `index` of the project; `progress` is told each depth cleared."""
        project = self.config.project
        a = project.assertions[index]
        if self.engine == "explicit":
            return check_assertion_explicit(project, a, self.bound, self.config, self.timeout, self.max_states,
                                            progress)
        if self.engine == "auto":
            return race.decide(project, a, self.bound, self.config, self.timeout, self.induction, self.shortest,
                               self.max_states, progress)
        return check_assertion(project, a, self.bound, self.config, self.timeout, self.induction, self.shortest,
                               progress)

    @property
    def reported_engine(self) -> str:
        """The engine a result no engine decided names (interrupted, overran)."""
        return "explicit" if self.engine == "explicit" else "bmc"

    def hard_limit(self) -> float | None:
        """Seconds after which a worker still deciding an assertion of this job is ended: Z3 does not
        always stop at its timeout (its model-based quantifier instantiation can build array axioms
        for minutes without looking at the clock: differential seed 3's untimed determinism check, with
        a 2 s timeout, ran for 20 minutes), and no call stops it from outside, so the process is ended."""
        if self.timeout is None or self.engine == "explicit":  # pure Python, which keeps to its deadline
            return None
        return 2 * self.timeout + HARD_LIMIT_SLACK

    def pickled(self) -> bytes:
        """The job as bytes, for a worker (a model nested to the limit pickles deeper than Python's default)."""
        with recursion_room():
            return pickle.dumps(self)


Work = list[tuple[Job, int]]  # assertions to decide: each a job and the index of an assertion of its project


@lru_cache(maxsize=8)
def _unpickled(blob: bytes) -> Job:
    """The job of `blob`, unpickled once per worker process (its tasks all carry the same bytes)."""
    with recursion_room():
        job = pickle.loads(blob)
    assert isinstance(job, Job)
    return job


def _decide(blob: bytes, index: int, n: int, sink: Any) -> Result:
    """Decide assertion `index` of the job of `blob`, the n-th of the work, telling `sink` (a queue or None)."""
    job = _unpickled(blob)
    if sink is None:
        return job.decide(index)
    sink.put((n, None))
    return job.decide(index, lambda depth: sink.put((n, depth)))


class InProcess:
    """The assertions decided one after another in this process (`-j 1`)."""

    def __init__(self, work: Work, progress: Progress | None = None):
        self.work, self.progress = work, progress
        self.current: tuple[int, float] | None = None  # the assertion being decided, and since when
        self.given_up: tuple[int, float] | None = None  # the one `overdue` named, and since when

    def __iter__(self) -> Iterator[tuple[int, Result]]:
        for n, (job, index) in enumerate(self.work):
            told = None
            if self.progress is not None:
                self.progress(n, None)
                told = _told(self.progress, n)
            self.current = (n, time.perf_counter())
            result = job.decide(index, told)
            self.current = None
            yield n, result

    def overdue(self) -> int | None:
        """The assertion being decided, if it has run past its hard limit (`Job.hard_limit`): asked
        from another thread, which can give the deciding thread up (`interrupt.decide`)."""
        current = self.current
        if current is None:
            return None
        n, start = current
        limit = self.work[n][0].hard_limit()
        if limit is None or time.perf_counter() - start <= limit:
            return None
        self.given_up = current
        return n

    def stop(self) -> None:
        """Ctrl-C stops Z3 in this process (`interrupt.decide`); the engines racing in processes of
        their own are ended."""
        race.stop_all()


def _told(progress: Progress, n: int) -> Callable[[int], None]:
    return lambda depth: progress(n, depth)


def _blobs(work: Work) -> dict[int, bytes]:
    """Each job of the work pickled once, by its identity."""
    return {id(job): job.pickled() for job in {id(job): job for job, _ in work}.values()}


class _Relay:
    """A thread that hands what the workers report (`take()`: the items waiting, after a short wait
    when there are none) to `progress`, until closed."""

    def __init__(self, take: Callable[[], list[tuple[int, int | None]]], progress: Progress):
        self.take, self.progress = take, progress
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, name="tockbmc-progress", daemon=True)
        self.thread.start()

    def _run(self) -> None:
        while True:
            closing = self.done.is_set()  # before taking: what was put before `close` is handed on
            try:
                items = self.take()
            except (EOFError, OSError):  # the queue was closed under us (Ctrl-C)
                return
            for n, depth in items:
                self.progress(n, depth)
            if not items and closing:
                return

    def close(self) -> None:
        self.done.set()
        self.thread.join(1)


# --------------------------------------------------------------------------- worker processes

_SINK: list[Any] = []  # in a worker process: the progress queue (or None), set once when it starts


def _start_worker(sink: Any, owner: int) -> None:
    """A worker process's start: Ctrl-C at the terminal is its parent's to handle (the parent ends the
    workers), so it is ignored here, and in Spacer's child processes, which inherit this; Z3 would
    otherwise catch it while it solves and end the query as `unknown`, a verdict the parent could
    receive before it ends the worker.  The worker ends itself within a second of `owner`, the
    process that started the pool, ending however it ends (killed outright, out of memory)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    z3.set_param("ctrl_c", False)
    _SINK.append(sink)
    end_with(owner)


def _decide_in_worker(blob: bytes, index: int, n: int) -> Result:
    return _decide(blob, index, n, _SINK[0])


def _taker(sink: Any) -> Callable[[], list[tuple[int, int | None]]]:
    """`take` of a `SimpleQueue`, whose `put` has written the item when it returns (a `Queue`'s is
    written later, by a thread: a worker's last depths could then come after its result)."""
    def take() -> list[tuple[int, int | None]]:
        if sink.empty():
            time.sleep(0.05)
            return []
        return [sink.get()]

    return take


def stop_servers() -> None:
    """End the fork server and the resource tracker, and wait for them.  Left to end when this
    process ends, they outlive it for a moment as orphans, which an init that does not reap
    (a container's) keeps as zombies in the process group (farm-bench saw them after `check -j 2`).

    multiprocessing's own exit work (the finalizers of queues and semaphores still alive, such as a
    pool's left by an error) is done first: run after the resource tracker has ended, it found
    their semaphores already cleaned up and printed tracebacks (after a usage error of `check -j`)."""
    # A worker still deciding (started just as Ctrl-C came, after the workers were ended) is ended
    # here: multiprocessing's exit work joins every child, and would wait for its whole check.
    for child in multiprocessing.active_children():
        with contextlib.suppress(Exception):
            child.kill()
    with contextlib.suppress(Exception):
        util._exit_function()  # type: ignore[attr-defined]  # noqa: SLF001 - idempotent; no public way
    for owner in (forkserver._forkserver, resource_tracker._resource_tracker):  # noqa: SLF001 - no public way
        stop = getattr(owner, "_stop", None)
        if stop is not None:
            with contextlib.suppress(Exception):
                stop()


@lru_cache(maxsize=1)
def _stop_servers_at_exit() -> None:
    atexit.register(stop_servers)  # once (cached)


@contextmanager
def ctrl_c_held() -> Iterator[None]:
    """Ctrl-C is delivered when the block ends, not inside it (where it would cut output in two)."""
    mask = getattr(signal, "pthread_sigmask", None)  # not on Windows: there the block can be cut
    if mask is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    mask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        mask(signal.SIG_UNBLOCK, {signal.SIGINT})


def _start_ignoring_ctrl_c(start: Callable[[], None]) -> None:
    """`start` a process that ignores Ctrl-C from its first instruction: an ignored signal stays
    ignored across exec. The fork server would otherwise take a Ctrl-C to the process group while it
    imports tockbmc, before it ignores Ctrl-C itself, and print a traceback; tockbmc ends its workers
    itself, and they ignore Ctrl-C (`_start_worker`). Meanwhile Ctrl-C is held here, not lost (Linux
    keeps a blocked signal pending even while it is ignored), and delivered once the handler is back."""
    if threading.current_thread() is not threading.main_thread():
        start()
        return
    with ctrl_c_held():
        handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            start()
        finally:
            signal.signal(signal.SIGINT, handler)


def _context() -> multiprocessing.context.BaseContext:
    """forkserver (spawn where there is none): Z3 is not forked with state in it, and workers start
    from a server that has imported tockbmc once."""
    _stop_servers_at_exit()
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(["tockbmc.parallel"])
        _start_ignoring_ctrl_c(forkserver.ensure_running)
        return context
    return multiprocessing.get_context("spawn")


def warm_up() -> None:
    """Start the fork server that worker processes come from, so that it imports tockbmc while this
    process loads the model (about half a second saved at the start of `check -j`)."""
    _context()


def overran(job: Job, index: int, seconds: float, in_process: bool = False) -> Result:
    """The result of an assertion given up at its hard limit (`Job.hard_limit`): its worker process
    ended, or (`in_process`) the thread deciding it in tockbmc's own process left behind."""
    a = job.config.project.assertions[index]
    what = "tockbmc gave it up" if in_process else "the worker process deciding it was ended"
    return Result(assertion=a.label, text=a.text, verdict=Verdict.UNKNOWN, bound=job.bound,
                  ranges=job.config.ranges().describe(), seconds=seconds, proof=Proof.NONE, engine=job.reported_engine,
                  pos=str(a.pos), reading=job.config.reading,
                  reason=f"the check did not stop at its timeout ({job.timeout:g} s): {what} after {seconds:.0f} s")


class InProcesses:
    """The assertions decided in `jobs` worker processes (`concurrent.futures`), results as decided.

    An assertion whose worker is still deciding it at its hard limit (`Job.hard_limit`) is `unknown`
    (`overran`): the workers are ended, and the assertions not yet decided start again in new ones."""

    def __init__(self, work: Work, jobs: int, progress: Progress | None = None):
        self.work, self.jobs, self.progress = work, jobs, progress
        self.executor: ProcessPoolExecutor | None = None
        self._stopped = False  # by `stop` (Ctrl-C): no pool is started after it
        self._lock = threading.Lock()  # `stop` comes from another thread, maybe while a new pool starts

    def __iter__(self) -> Iterator[tuple[int, Result]]:
        left = dict(enumerate(self.work))
        while left and not self._stopped:
            overrun: list[int] = []
            started: dict[int, float] = {}  # this pool's: a report from an earlier pool cannot land here
            for n, result in self._round(left, overrun, started):
                del left[n]
                yield n, result
            for n in overrun:  # the workers were ended; the others left start again
                job, index = left.pop(n)
                yield n, overran(job, index, time.perf_counter() - started[n])

    def _round(self, left: dict[int, tuple[Job, int]], overrun: list[int],
               started: dict[int, float]) -> Iterator[tuple[int, Result]]:
        """Decide the assertions `left` in a fresh pool, until they are decided or one overruns (put
        in `overrun`, and the pool's workers ended); `started` is told when each check starts."""
        context = _context()
        limited = any(job.timeout is not None for job, _ in left.values())
        sink = context.SimpleQueue() if self.progress is not None or limited else None
        blobs = _blobs(list(left.values()))
        with self._lock:
            if self._stopped:
                return
            executor = self.executor = ProcessPoolExecutor(
                max_workers=max(1, min(self.jobs, len(left))), mp_context=context, initializer=_start_worker,
                initargs=(sink, os.getpid()))

        def told(n: int, depth: int | None) -> None:
            if depth is None:  # the check starts: its hard limit counts from here
                started[n] = time.perf_counter()
            if self.progress is not None:
                self.progress(n, depth)

        relay = _Relay(_taker(sink), told) if sink is not None else None
        finished = False
        try:
            pending: dict[Future[Result], int] = {
                executor.submit(_decide_in_worker, blobs[id(job)], index, n): n for n, (job, index) in left.items()}
            while pending:
                ready, _ = wait(pending, timeout=0.5 if limited else None, return_when=FIRST_COMPLETED)
                for future in sorted(ready, key=pending.__getitem__):
                    yield pending.pop(future), future.result()
                now = time.perf_counter()
                late = [n for n in pending.values() if n in started
                        and (limit := left[n][0].hard_limit()) is not None and now - started[n] > limit]
                if late:
                    overrun.extend(sorted(late))
                    return
            finished = True
        finally:
            if not finished:  # an error, an overrun, or the caller stopped drawing: no worker goes on solving
                _kill(executor)
            executor.shutdown(wait=finished, cancel_futures=True)
            if relay is not None:
                relay.close()

    def stop(self) -> None:
        """End the worker processes at once (their Spacer children notice and end too, `bmc.pdr`),
        and start no others."""
        with self._lock:
            self._stopped = True
            executor = self.executor
        if executor is not None:
            _kill(executor)


def _kill(executor: ProcessPoolExecutor) -> None:
    """End a pool's worker processes at once."""
    kill = getattr(executor, "kill_workers", None)  # Python 3.14
    if kill is not None:
        kill()
        return
    for process in list((executor._processes or {}).values()):  # noqa: SLF001 - no public way before 3.14
        if process.is_alive():
            process.kill()


# --------------------------------------------------------------------------- Dask

_Z3_LOCK = threading.Lock()  # a Dask worker runs tasks in threads; Z3's main context is one per process


def _decide_on_dask(blob: bytes, index: int, n: int, queue_name: str | None) -> Result:
    """A Dask task: decide one assertion, one at a time in this worker process; progress goes to the
    cluster's queue `queue_name` (a name: a queue itself in a task's arguments is opened by the scheduler)."""
    with _Z3_LOCK:
        if queue_name is None:
            return _decide(blob, index, n, None)
        import distributed

        return _decide(blob, index, n, distributed.Queue(queue_name))


CONNECT_TIMEOUT = 10  # seconds to reach a Dask scheduler


class Unreachable(Exception):
    """No Dask scheduler answered at `address`."""

    def __init__(self, address: str, why: str):
        super().__init__(f"cannot reach a Dask scheduler at {address}: {why}")
        self.address, self.why = address, why


class OnDask:
    """The assertions decided as tasks on the Dask cluster whose scheduler is at `address`.

    The workers need tockbmc installed (not the model's files).  Ctrl-C cancels the tasks not
    started; those running finish on the cluster and their results are dropped.
    """

    def __init__(self, work: Work, address: Any, progress: Progress | None = None):
        self.work, self.address, self.progress = work, address, progress
        self.futures: list[Any] = []
        self.client: Any = None

    def __iter__(self) -> Iterator[tuple[int, Result]]:
        import distributed

        try:
            client = distributed.Client(self.address, timeout=CONNECT_TIMEOUT)
        except OSError as exc:  # refused, timed out, no such host
            raise Unreachable(str(self.address), str(exc)) from None
        with client:
            self.client = client
            sink = distributed.Queue(client=client) if self.progress is not None else None
            relay = None
            if sink is not None and self.progress is not None:
                def take() -> list[tuple[int, int | None]]:
                    items = sink.get(batch=True)  # what is waiting, at once (a timeout is an error in the scheduler's log)
                    if not items:
                        time.sleep(0.05)
                    return [(n, depth) for n, depth in items]

                relay = _Relay(take, self.progress)
            try:
                blobs = _blobs(self.work)
                scattered = dict(zip(blobs, client.scatter(list(blobs.values()), broadcast=True)))
                name = sink.name if sink is not None else None
                position = {client.submit(_decide_on_dask, scattered[id(job)], index, n, name, pure=False): n
                            for n, (job, index) in enumerate(self.work)}
                self.futures = list(position)
                for future in distributed.as_completed(self.futures):
                    yield position[future], future.result()
            finally:
                self.stop()
                if relay is not None:
                    relay.close()

    def stop(self) -> None:
        """Cancel the tasks that have not finished."""
        if self.client is not None and self.futures:
            self.client.cancel(self.futures)
