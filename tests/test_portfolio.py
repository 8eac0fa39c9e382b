"""The portfolio (`tockbmc.race`): BMC and the explicit engine race where the explicit engine's
answer is sound for the reading; the first answer for every run decides, the loser is ended."""

from __future__ import annotations

import os
import threading
import time
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import EXAMPLE, write_files

import tockbmc
from tockbmc import race
from tockbmc.model.config import ROBOTOOL_RANGES, configure
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.readings import Reading
from tockbmc.model.result import Proof, Result, Verdict
from tockbmc.race import RaceError, _Engine, _Race, complete, explicit_races

CONFORMANCE = Path(__file__).resolve().parents[2] / "shared" / "conformance" / "robochart-tests" / "robochart"

INTS = """\
interface E { event e : int }
stm M {
  uses E
  var x : int
  initial i
  state s {}
  state big {}
  transition t0 { from i to s }
  transition t1 { from s to big trigger e?x condition x > 1 }
}
"""


def _result(verdict: Verdict, proof: Proof, engine: str = "bmc") -> Result:
    return Result(assertion="A", text="A", verdict=verdict, bound=4, ranges={}, seconds=0.0, proof=proof,
                  engine=engine)


def _unknown(seconds: float) -> Result:
    return _result(Verdict.UNKNOWN, Proof.NONE)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_the_explicit_engine_races_only_where_its_answer_is_sound(tmp_path: Path) -> None:
    """With --robotool always; in the default reading only with ranges on the integers and no reals."""
    project = tockbmc.load(write_files(tmp_path, {"m.rct": INTS}))
    bounded = Ranges({"core_int": Range(Fraction(-1), Fraction(1)), "core_nat": Range(Fraction(0), Fraction(2))})
    assert explicit_races(configure(project, default_ranges=ROBOTOOL_RANGES, reading=Reading.ROBOTOOL))
    assert not explicit_races(configure(project))  # unbounded integers: the explicit engine cannot list them
    assert explicit_races(configure(project, bounded))
    welder = tockbmc.load(EXAMPLE)  # real-typed events, whose ranges the explicit engine samples at integers
    assert not explicit_races(configure(welder, bounded))
    assert explicit_races(configure(welder, bounded, reading=Reading.ROBOTOOL))


def test_a_complete_answer_ends_the_race_and_the_other_engine() -> None:
    """The first answer for every run decides; the engine still deciding is killed, not waited for."""
    pids: list[int] = []

    def slow(_tell: object) -> Result:
        time.sleep(60)
        return _result(Verdict.UNKNOWN, Proof.NONE)

    engines = [_Engine("bmc", slow), _Engine("explicit", lambda _t: _result(Verdict.HOLDS, Proof.EXHAUSTIVE,
                                                                             "explicit"))]
    original = _Engine.start

    def start(self: _Engine, tells: bool) -> None:
        original(self, tells)
        assert self.pid is not None
        pids.append(self.pid)

    _Engine.start = start  # type: ignore[method-assign]
    try:
        decided = _Race(engines, 60, None, _unknown).run()
    finally:
        _Engine.start = original  # type: ignore[method-assign]
    assert decided.verdict == Verdict.HOLDS and decided.engine == "explicit"
    assert not any(_alive(pid) for pid in pids)


def test_a_partial_answer_waits_for_the_other_engine() -> None:
    """A `holds` up to the bound does not end the race while the other engine may still prove it."""
    def bounded(_tell: object) -> Result:
        return _result(Verdict.HOLDS, Proof.BOUNDED)

    def proves(_tell: object) -> Result:
        time.sleep(0.5)
        return _result(Verdict.HOLDS, Proof.EXHAUSTIVE, "explicit")

    decided = _Race([_Engine("bmc", bounded), _Engine("explicit", proves)], 60, None, _unknown).run()
    assert decided.proof == Proof.EXHAUSTIVE and decided.engine == "explicit"
    both_partial = _Race([_Engine("bmc", bounded), _Engine("explicit", lambda _t: _result(
        Verdict.UNSUPPORTED, Proof.NONE, "explicit"))], 60, None, _unknown).run()
    assert both_partial.verdict == Verdict.HOLDS and both_partial.engine == "bmc"


def test_an_internal_error_of_bmc_is_not_hidden_by_a_partial_answer() -> None:
    def fails(_tell: object) -> Result:
        raise TypeError("boom")

    with pytest.raises(RaceError, match="TypeError: boom"):
        _Race([_Engine("bmc", fails), _Engine("explicit", lambda _t: _result(Verdict.UNKNOWN, Proof.NONE))],
              60, None, _unknown).run()


def test_stopping_the_race_ends_both_engines() -> None:
    """Ctrl-C (`InProcess.stop` calls `race.stop_all`): the engines' processes end at once, and the
    race returns rather than wait for them."""
    def slow(_tell: object) -> Result:
        time.sleep(60)
        return _result(Verdict.UNKNOWN, Proof.NONE)

    outcome: list[object] = []

    def run() -> None:
        try:
            outcome.append(_Race([_Engine("bmc", slow), _Engine("explicit", slow)], None, None, _unknown).run())
        except RaceError as exc:
            outcome.append(exc)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    while not race._LIVE:  # noqa: SLF001 - the pids the race started
        time.sleep(0.01)
    try:
        race.stop_all()
        thread.join(30)
        assert not thread.is_alive() and not race._LIVE  # noqa: SLF001
        assert isinstance(outcome[0], RaceError)
        with pytest.raises(RaceError, match="stopped"):  # no race starts after it
            _Race([_Engine("bmc", slow)], None, None, _unknown).run()
    finally:
        race.reset()


def test_the_portfolio_decides_equals_for_every_run_with_robotool() -> None:
    """RoboTool's Example1: `C0_T_eq_C1` (traces equality of two controllers) holds for every run, by
    whichever engine answers first; `--engine bmc` alone reached no such answer in 20 s on this
    project's machine."""
    config = configure(tockbmc.load(CONFORMANCE / "Example1"), default_ranges=ROBOTOOL_RANGES,
                       reading=Reading.ROBOTOOL)
    a = next(a for a in config.project.assertions if a.name == "C0_T_eq_C1")
    decided = race.decide(config.project, a, 40, config, 120)
    assert decided.verdict == Verdict.HOLDS and complete(decided), decided.reason
