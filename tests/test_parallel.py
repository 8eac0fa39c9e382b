"""`check -j N` and `check --dask`: the same results in the same order as in one process; progress from
the engines on a terminal only; rows printed as soon as they can be; Ctrl-C ends the workers too."""

from __future__ import annotations

import dataclasses
import json
import os
import pty
import re
import select
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from conftest import COUNTER, EXAMPLE, run_cli, write_files
from test_cli_robustness import SLOW, TOCKBMC

from tockbmc import load
from tockbmc.check import own_z3_context
from tockbmc.launch import HOLD_IMPORT
from tockbmc.model.config import configure
from tockbmc.parallel import InProcess, InProcesses, Job, OnDask


def comparable(results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Results without what may differ from run to run: the time, and for a property proved for every
    length, which of k-induction and Spacer's PDR won the race (and its depth, reason and invariant: with
    PDR's proof, the depth is how far BMC had got when Spacer answered)."""
    out = []
    for r in results:
        r = {k: v for k, v in r.items() if k != "seconds"}
        if r["proof"] in ("k-induction", "invariant"):
            r = {k: v for k, v in r.items() if k not in ("proof", "depth", "reason", "invariant")}
        out.append(r)
    return out


def test_two_processes_give_the_json_of_one(tmp_path: Path) -> None:
    """The paper's model, unbounded data (six violations with traces, one proof): `-j 2` prints the
    document `-j 1` prints, but for the times (and the race of two proofs of every length)."""
    one, two = (run_cli(["check", EXAMPLE, "-j", jobs, "--format", "json"]) for jobs in ("1", "2"))
    assert one.crash is None and two.crash is None
    assert one.exit_code == two.exit_code == 10, one.output + two.output
    a, b = json.loads(one.stdout), json.loads(two.stdout)
    assert [r["assertion"] for r in b["results"]] == ["A1", "A2", "A3", "A4", "A5", "A6", "A7"]
    assert comparable(a.pop("results")) == comparable(b.pop("results"))
    assert a == b
    assert sum(len(r["trace"]) for r in json.loads(two.stdout)["results"]) > 20  # the traces were compared


def test_the_explicit_engine_in_two_processes_gives_the_json_of_one() -> None:
    """Its traces carry record values (`EXAX::move.in.(dist=…, time=…)`), which cross to the parent too."""
    args = ["check", EXAMPLE, "-a", "A1", "-a", "A2", "-a", "A5", "-a", "A7", "--engine", "explicit", "--range",
            "core_int=-1..1", "--range", "core_real=-1..1", "--range", "core_nat=0..3", "--format", "json"]
    one, two = (run_cli([*args, "-j", jobs]) for jobs in ("1", "2"))
    assert one.crash is None and two.crash is None and one.exit_code == two.exit_code == 10, two.output
    a, b = json.loads(one.stdout), json.loads(two.stdout)
    assert [r["verdict"] for r in b["results"]] == ["violated", "violated", "violated", "holds"]
    assert comparable(a.pop("results")) == comparable(b.pop("results")) and a == b


def counter_project(tmp_path: Path) -> Path:
    return write_files(tmp_path, {"c.rct": COUNTER, "c.assertions": "assertion T: Counter terminates.\n"
                                  "assertion D: Counter is deadlock-free.\nassertion N: Counter does not terminate.\n"})


def test_the_engines_report_each_depth_they_clear_from_worker_processes(tmp_path: Path) -> None:
    """The progress hook is the engine's: BMC tells each depth it clears, in this process and from
    workers alike; `N: Counter does not terminate` is violated at depth 9, so depths 0..8 are cleared."""
    project = load(counter_project(tmp_path))
    job = Job(configure(project), bound=12)
    seen: dict[str, list[tuple[int, int | None]]] = {}
    work = [(job, 0), (job, 1), (job, 2)]
    for name in ("here", "workers"):
        told: list[tuple[int, int | None]] = []
        def tell(n: int, depth: int | None, told: list = told) -> None:
            told.append((n, depth))

        decided = dict(InProcess(work, tell) if name == "here" else InProcesses(work, 2, tell))
        assert [decided[i].verdict for i in range(3)] == ["holds", "holds", "violated"]
        assert decided[2].depth == 9
        seen[name] = told
    for told in seen.values():
        assert set(told) == set(seen["here"])
        n = [d for i, d in told if i == 2]
        assert n == [None, *range(9)], n  # started, then depths 0..8 cleared in order, none lost


def descendants(pid: int) -> list[int]:
    """Every process below `pid` (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                ppid = int(Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(ppid, []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def running(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def deciding_h(tmp_path: Path) -> tuple[subprocess.Popen[str], list[str]]:
    """`check -j 2` on Q1, H (Z3 spends minutes on it, Spacer beside it) and Q2, started and read up
    to Q1's row: H is then being decided. The process, and the lines read."""
    write_files(tmp_path, SLOW)
    p = subprocess.Popen([*TOCKBMC, "check", str(tmp_path), "--open", "-k", "4", "-a", "Q1", "-a", "H", "-a", "Q2", "-j", "2"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout is not None
    lines: list[str] = []
    while not any(line.startswith("│ Q1") for line in lines):
        lines.append(p.stdout.readline())
        if not lines[-1]:
            p.kill()
            p.wait()
            raise AssertionError("the output ended before Q1's row")
    return p, lines


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads the process tree from /proc")
def test_rows_stream_and_ctrl_c_ends_the_workers_and_their_spacer_children(tmp_path: Path) -> None:
    """`-j 2` on Q1, H (Z3 spends minutes on it, Spacer beside it) and Q2: Q1's row is printed while H is
    still being decided; Ctrl-C then exits 130 (long before H would be decided), with Q2's verdict (decided by the
    other worker) and H interrupted, and no worker process or Spacer child left soon after."""
    p, lines = deciding_h(tmp_path)
    try:
        time.sleep(1)  # Q2 decided meanwhile, H not (its worker and Spacer busy)
        assert p.poll() is None
        below = descendants(p.pid)
        assert len(below) >= 3, below  # a fork server, two workers, Spacer's child
        p.send_signal(signal.SIGINT)
        sent = time.monotonic()
        rest, err = p.communicate(timeout=120)
        took = time.monotonic() - sent
    finally:
        p.kill()
        p.wait()
    assert p.returncode == 130 and took < 60, (took, err)  # not run to the end: H takes minutes
    text = "".join(lines) + rest
    rows = [[c.strip() for c in line.split("│")[1:3]] for line in text.splitlines() if line.startswith("│")]
    assert rows == [["Q1", "holds"], ["H", "interrupted"], ["Q2", "holds"]]
    assert err == "tockbmc: interrupted\n"
    deadline = time.monotonic() + 30  # the event waited for: every process below it gone
    while [pid for pid in below if running(pid)] and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [pid for pid in below if running(pid)] == []


def on_terminal(args: list[str], stdout: Any) -> str:
    """What `args` writes on stderr when stderr is a terminal (stdout goes to `stdout`)."""
    leader, follower = pty.openpty()
    p = subprocess.Popen(args, stdout=stdout, stderr=follower)
    os.close(follower)
    screen = b""
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            ready, _, _ = select.select([leader], [], [], 10)
            try:
                chunk = os.read(leader, 65536) if ready else b""
            except OSError:  # the terminal's other side closed
                chunk = b""
            if not chunk:
                break
            screen += chunk
        p.wait(timeout=60)
    finally:
        os.close(leader)
        p.kill()
        p.wait()
    return screen.decode("utf-8", "replace")


def test_progress_is_shown_on_a_terminal_and_not_in_a_log(tmp_path: Path) -> None:
    """With stderr a terminal, the display names the assertion and the depth its search has cleared;
    with stderr a pipe, stderr stays empty, and so it does when the text table goes down a pipe (whose
    reader may write it on the terminal under the display).  The table is the same either way."""
    project = write_files(tmp_path, {"c.rct": COUNTER.replace("x < 3", "x < 400").replace("x == 3", "x == 400"),
                                     "c.assertions": "assertion Slow: Counter does not terminate.\n"})
    # Spacer is given a second once BMC reaches the bound: the display is redrawn meanwhile
    args = [*TOCKBMC, "check", str(project), "-k", "8", "-j", "1"]
    with (tmp_path / "out.txt").open("w") as out:
        shown = on_terminal(args, out)
    assert "Slow" in shown and re.search(r"depth \d+ of 8", shown) and "none decided yet" in shown, shown[-2000:]
    quick = [*args[:-4], "-k", "2", "-j", "1"]
    logged = subprocess.run(quick, capture_output=True, text=True, timeout=120)
    assert logged.stderr == ""
    assert on_terminal(quick, subprocess.PIPE) == ""
    rows = [[c.strip() for c in line.split("│")[1:3]] for text in ((tmp_path / "out.txt").read_text(), logged.stdout)
            for line in text.splitlines() if line.startswith("│")]
    assert rows == [["Slow", "holds"], ["Slow", "holds"]]


def test_dask_gives_the_results_of_one_process(tmp_path: Path) -> None:
    """`--dask` on a local cluster (one worker process, daemonic as Dask's are, two threads): the JSON of
    `-j 1`, but for the times; Spacer's child processes start there too (`bmc.pdr` forks them itself)."""
    distributed = pytest.importorskip("distributed")
    project = counter_project(tmp_path)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True, dashboard_address=None) as cluster:
        on_dask = run_cli(["check", project, "--dask", cluster.scheduler_address, "--format", "json", "-k", "12"])
        job = Job(configure(load(project)), bound=12)
        told: list[tuple[int, int | None]] = []
        decided = dict(OnDask([(job, 2)], cluster.scheduler_address, lambda n, d: told.append((n, d))))
    here = run_cli(["check", project, "-j", "1", "--format", "json", "-k", "12"])
    assert on_dask.crash is None and on_dask.exit_code == here.exit_code == 10, on_dask.output
    a, b = json.loads(here.stdout), json.loads(on_dask.stdout)
    assert comparable(a.pop("results")) == comparable(b.pop("results"))
    assert a == b
    assert decided[0].verdict == "violated" and told == [(0, None), *((0, d) for d in range(9))]


def test_dask_without_dask_installed_is_a_usage_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "distributed" else real(name, *a))
    result = run_cli(["check", counter_project(tmp_path), "--dask", "tcp://127.0.0.1:1"])
    assert result.exit_code == 2 and "pip install 'tockbmc[dask]'" in result.stderr, result.output


def test_dask_with_no_scheduler_there_is_a_usage_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("distributed")
    import tockbmc.parallel
    monkeypatch.setattr(tockbmc.parallel, "CONNECT_TIMEOUT", 0.5)
    result = run_cli(["check", counter_project(tmp_path), "--dask", "tcp://127.0.0.1:1"])
    assert result.crash is None and result.exit_code == 2, result.output
    assert "cannot reach a Dask scheduler at tcp://127.0.0.1:1" in result.stderr


@dataclasses.dataclass(frozen=True)
class _Slow(Job):
    """A job whose check takes `delay` seconds before it starts: by default one that never returns in
    time, as Z3 sometimes does not at its timeout (differential seed 3's untimed determinism check).
    A short hard limit keeps the tests fast."""

    delay: float = 120.0

    def decide(self, index: int, progress: Any = None) -> Any:
        if _TEST_OVER.wait(self.delay):  # given up in this process: nothing more may touch Z3 here
            raise RuntimeError("the test that gave this check up is over")
        return super().decide(index, progress)

    def hard_limit(self) -> float | None:
        return 1.0


# Set when a test that leaves a `_Slow` check behind in this process ends: the thread must not wake
# up to solve in Z3's main context beside the tests after it (a Z3 context is not for two threads).
_TEST_OVER = threading.Event()


def test_a_worker_past_its_hard_limit_is_ended_and_its_assertion_is_unknown(tmp_path: Path) -> None:
    """The others are decided as without it, in new workers where the old ones were ended with it."""
    project = load(counter_project(tmp_path))
    stuck, job = _Slow(configure(project), bound=12, timeout=0.1), Job(configure(project), bound=12)
    start = time.perf_counter()
    decided = dict(InProcesses([(stuck, 0), (job, 1), (job, 2)], 2))
    assert time.perf_counter() - start < 30
    assert decided[0].verdict == "unknown" and decided[0].assertion == "T" and decided[0].proof == "none"
    assert "the check did not stop at its timeout (0.1 s): the worker process deciding it was ended" in (decided[0].reason or "")
    assert decided[2].verdict == "violated"  # as in one process: Counter terminates
    assert [decided[n].verdict for n in (1, 2)] == [job.decide(n).verdict for n in (1, 2)]


def test_a_lone_assertion_decided_here_is_given_up_at_its_hard_limit(tmp_path: Path) -> None:
    """`check` decides a single assertion in its own process; the waiting thread gives the deciding
    thread up once the check has run past its hard limit, and says which assertion it was."""
    from tockbmc.interrupt import decide

    project = load(counter_project(tmp_path))
    runner = InProcess([(_Slow(configure(project), bound=12, timeout=0.1), 0)])
    start = time.perf_counter()
    _TEST_OVER.clear()
    with own_z3_context():  # the interrupt of Z3 it makes stays in a context of its own
        try:
            decided = decide(runner, grace=0.2, overdue=runner.overdue)
        finally:
            _TEST_OVER.set()
    assert time.perf_counter() - start < 10
    assert decided.overran == 0 and decided.results == [] and not decided.worker_done
    assert runner.current is not None and runner.current[0] == 0


def test_a_result_that_comes_within_the_grace_is_kept(tmp_path: Path) -> None:
    """A check finishing in the grace after it was given up keeps its result, not 'interrupted'."""
    from tockbmc.interrupt import decide

    project = load(counter_project(tmp_path))
    runner = InProcess([(_Slow(configure(project), bound=12, timeout=30, delay=1.4), 2)])
    _TEST_OVER.clear()
    with own_z3_context():  # the interrupt of Z3 at the hard limit stays in a context of its own
        decided = decide(runner, grace=3.0, overdue=runner.overdue)
    assert decided.overran == 0 and decided.worker_done
    assert [(n, r.verdict) for n, r in decided.results] == [(0, "violated")]


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads the process tree from /proc")
def test_sigterm_to_the_main_process_prints_what_was_decided_and_ends_every_worker(tmp_path: Path) -> None:
    """SIGTERM (a CI runner's, `timeout`'s) to tockbmc alone, not its group, while H is decided:
    exit 143, Q1's and Q2's verdicts printed and H interrupted, one line on stderr, and no worker
    process, fork server or Spacer child left running."""
    p, lines = deciding_h(tmp_path)
    try:
        below = descendants(p.pid)
        assert below, "no worker process"
        p.send_signal(signal.SIGTERM)
        rest, err = p.communicate(timeout=30)
    finally:
        p.kill()
        p.wait()
    assert p.returncode == 143, err
    rows = [[c.strip() for c in line.split("│")[1:3]] for line in ("".join(lines) + rest).splitlines()
            if line.startswith("│")]
    assert rows[0] == ["Q1", "holds"] and ["H", "interrupted"] in rows, rows
    assert err == "tockbmc: terminated (SIGTERM)\n"
    deadline = time.monotonic() + 30  # the event waited for: every process below it gone
    while [pid for pid in below if running(pid)] and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [pid for pid in below if running(pid)] == []


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads the process tree from /proc")
def test_workers_end_when_the_main_process_is_killed_outright(tmp_path: Path) -> None:
    """SIGKILL (or the out-of-memory killer) gives tockbmc no chance to end its workers: they notice
    that it is gone and end themselves, with their Spacer children, and the fork server with them."""
    p, _lines = deciding_h(tmp_path)
    try:
        below = descendants(p.pid)
        assert below, "no worker process"
        p.kill()
        p.wait()
    finally:
        p.kill()
        p.wait()
    deadline = time.monotonic() + 30  # the event waited for: every process below it gone
    while [pid for pid in below if running(pid)] and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [pid for pid in below if running(pid)] == []


@pytest.mark.parametrize(("sig", "status", "line"), [(signal.SIGINT, 130, "tockbmc: interrupted\n"),
                                                      (signal.SIGTERM, 143, "tockbmc: terminated (SIGTERM)\n")])
def test_a_signal_while_tockbmc_is_still_being_imported_ends_it_with_one_line(
        tmp_path: Path, sig: int, status: int, line: str) -> None:
    """Ctrl-C or SIGTERM before the checker is imported (the first few tenths of a second): the
    documented status and line, no traceback. The hook holds the command where the import starts."""
    held = tmp_path / "importing"
    p = subprocess.Popen([sys.executable, "-m", "tockbmc", "check", str(EXAMPLE)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env={**os.environ, HOLD_IMPORT: str(held)})
    try:
        deadline = time.monotonic() + 60  # the event waited for: the hold reached
        while not held.exists() and time.monotonic() < deadline and p.poll() is None:
            time.sleep(0.02)
        p.send_signal(sig)
        out, err = p.communicate(timeout=30)
    finally:
        p.kill()
        p.wait()
    assert (p.returncode, out, err) == (status, "", line)


IGNORING_CTRL_C = """\
import os, signal, subprocess, sys
from tockbmc.parallel import _start_ignoring_ctrl_c
children = []
def start():
    os.kill(os.getpid(), signal.SIGINT)  # held, not lost
    children.append(subprocess.Popen([sys.executable, "-c",
                                      "import signal; print(signal.getsignal(signal.SIGINT) == signal.SIG_IGN)"],
                                     stdout=subprocess.PIPE, text=True))
try:
    _start_ignoring_ctrl_c(start)
except KeyboardInterrupt:
    print("delivered after the start")
print("child ignores it:", children[0].communicate()[0].strip())
print("handler back:", signal.getsignal(signal.SIGINT) is signal.default_int_handler)
"""


def test_a_process_started_for_tockbmc_ignores_ctrl_c_from_its_start_and_none_is_lost() -> None:
    """The fork server is started so (`_start_ignoring_ctrl_c`): it ignores Ctrl-C before it has
    imported anything (Python keeps an ignored SIGINT ignored), while tockbmc's own Ctrl-C, sent
    during the start, is delivered once the start is over (in a process of its own: the main thread's)."""
    out = subprocess.run([sys.executable, "-c", IGNORING_CTRL_C], capture_output=True, text=True, timeout=120)
    assert out.stdout.splitlines() == ["delivered after the start", "child ignores it: True", "handler back: True"], \
        out.stderr


def test_a_helper_process_ends_when_its_owner_is_a_zombie_nobody_has_reaped() -> None:
    """A worker watches tockbmc, which need not be its parent: tockbmc ended but not yet reaped (its
    own parent busy reading its output) is gone all the same, though `kill(pid, 0)` still answers."""
    owner = subprocess.Popen([sys.executable, "-c", "pass"])
    try:
        deadline = time.monotonic() + 60  # the event waited for: the owner a zombie
        while running(owner.pid) and time.monotonic() < deadline:
            time.sleep(0.02)
        os.kill(owner.pid, 0)  # a zombie still answers
        watcher = subprocess.Popen([sys.executable, "-c", "import time; from tockbmc.model.lifetime import end_with; "
                                    f"end_with({owner.pid}); time.sleep(120); raise SystemExit(1)"])
        assert watcher.wait(timeout=90) == 0
    finally:
        owner.wait()


STILL_DECIDING = """\
import multiprocessing, time
from tockbmc.parallel import _context, stop_servers
child = _context().Process(target=time.sleep, args=(600,))
child.start()
stop_servers()  # as tockbmc's exit after Ctrl-C: the child is ended, not waited for
print(child.is_alive())
"""


def test_the_exit_after_ctrl_c_ends_a_worker_still_deciding_rather_than_waiting_for_it() -> None:
    """A worker started just as Ctrl-C came (after the workers were ended) is still deciding when
    tockbmc exits: multiprocessing's exit work joins every child, which waited for its whole check."""
    out = subprocess.run([sys.executable, "-c", STILL_DECIDING], capture_output=True, text=True, timeout=300)
    assert out.stdout.strip() == "False", out.stderr
