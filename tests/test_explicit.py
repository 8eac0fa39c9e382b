"""The explicit engine, `simulate` and replay: the independent interpreter as a second opinion.

The interpreter (`tockbmc/explicit/interpreter.py`) shares nothing with `encodings/`; here it
replays BMC's counterexamples, and runs the CLI commands that
expose it.
"""

from __future__ import annotations

import dataclasses
import json
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import CONFORMANCE, EXAMPLE

from tockbmc import load
from tockbmc.bmc.witness import initial_choices
from tockbmc.check import check
from tockbmc.cli import cli
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit, python_settings
from tockbmc.explicit.interpreter import Interpreter
from tockbmc.explicit.replay import ReplayFailure, replay
from tockbmc.properties.queries import query

REALISTIC = Ranges({"core_int": Range(Fraction(-1), Fraction(1)), "core_real": Range(Fraction(-1), Fraction(1)),
                    "core_nat": Range(Fraction(0), Fraction(3))})


@pytest.mark.parametrize("name, verdict", [("A1", "violated"), ("A2", "violated"), ("A5", "violated"),
                                           ("A7", "holds")])
def test_paper_realistic_case_by_the_explicit_engine(name: str, verdict: str) -> None:
    [r] = check_explicit(load(EXAMPLE), [name], 40, REALISTIC, {}, timeout=60)
    assert r.verdict == verdict, r.reason
    assert r.engine == "explicit" and r.extra["states"] > 0 and r.extra["transitions"] >= r.extra["states"] - 1
    if verdict == "violated":
        visible = [s.event for s in r.trace if s.kind != "internal"]
        assert visible[0].startswith("EXAX::move.in.(") and "time=-1" in visible[0]


def test_explicit_engine_needs_finite_ranges() -> None:
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A5", "--engine", "explicit"])
    assert result.exit_code == 2
    assert "core_int" in result.output or "core_real" in result.output


def test_an_unbounded_sequence_gets_a_range_hint_check_accepts() -> None:
    """In the open reading a sequence variable without an initial value starts at any sequence:
    the hint names a path whose range bounds its length (it used to suggest `--range
    Seq(int)=LO..HI`, which `check` refuses). By default it starts empty, as RoboTool's memory does,
    and needs no range."""
    case = str(CONFORMANCE / "robochart" / "SequenceAndProductTest")
    base = ["check", case, "--range", "core_int=-1..1", "--engine", "explicit", "-j", "1"]
    result = CliRunner().invoke(cli, [*base, "--open"])
    assert result.exit_code == 2 and "its length: --range SequenceAndProductTest::test::a=LO..HI" in result.output, \
        result.output
    again = CliRunner().invoke(cli, [*base, "--open", "--range", "SequenceAndProductTest::test::a=0..2"])
    assert again.exit_code != 2 and "needs finite data" not in again.output, again.output
    default = CliRunner().invoke(cli, base)
    assert default.exit_code == 0 and "SequenceAndProductTest::test::a=<> [RoboTool default" in default.output, \
        default.output


def test_state_limit_gives_unknown() -> None:
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A6", "--engine", "explicit", "--range",
                                      "core_int=0..2", "--range", "core_real=-1..1", "--max-states", "20",
                                      "--format", "json"])
    [r] = json.loads(result.output)["results"]
    assert r["verdict"] == "unknown" and "state limit" in r["reason"] and r["states"] <= 20


GROWING = """\
import sequence_toolkit::*
stm M {
  var s : Seq(int) = <>
  event d
  initial i
  state S {}
  state T {}
  transition t0 { from i to S }
  transition t1 { from S to S action s = s ^ <1> }
  transition t2 { from S to T trigger d condition size(s) < 0 }
}
"""


def test_a_specification_on_the_left_keeps_to_the_timeout(tmp_path) -> None:
    """Few's trace <d> is one M never performs, and M's internal steps grow `s` for ever: the
    search for a run performing it (explicit engine, `_runs_to`) had no deadline, and with a 3 s
    timeout gave no answer in a minute (each new configuration copies a longer sequence).  It now
    stops at the deadline: unknown, timed out."""
    (tmp_path / "m.rct").write_text(GROWING)
    (tmp_path / "m.assertions").write_text("csp Few csp-begin\nFew = M::d.in -> STOP\ncsp-end\n"
                                           "untimed assertion F: Few refines M in the failures model.\n")
    [r] = check_explicit(load(tmp_path), None, 40, Ranges(), {}, timeout=2)
    assert r.verdict == "unknown" and "timed out" in (r.reason or ""), r
    assert r.seconds < 20, r.seconds  # a tenfold margin for a loaded machine; it was over a minute


def test_simulate_prints_a_reproducible_random_run() -> None:
    args = ["simulate", str(EXAMPLE), "--element", "EXAX", "--steps", "12", "--seed", "3",
            "--range", "core_int=-1..1", "--range", "core_real=-1..1"]
    first = CliRunner().invoke(cli, args)
    assert first.exit_code == 0, first.output
    assert "EXAX::" in first.output and "random run of EXAX" in first.output
    assert CliRunner().invoke(cli, args).output == first.output
    assert CliRunner().invoke(cli, ["simulate", str(EXAMPLE), "--element", "NoSuch"]).exit_code == 2


def test_counterexamples_are_replayed() -> None:
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "--range", "core_int=-1..1", "--range",
                                      "core_real=-1..1", "--format", "json"])
    replayed = {r["assertion"]: r.get("replayed") for r in json.loads(result.output)["results"]}
    assert all(replayed[n] == "yes" for n in ("A1", "A2", "A3", "A4", "A5", "A6")), replayed


def test_replay_rejects_a_trace_the_interpreter_cannot_follow() -> None:
    """A BMC trace with one event changed (a time budget the model never reads) cannot be followed."""
    project = load(EXAMPLE)
    a = next(x for x in project.assertions if x.name == "A5")
    [r] = check(project, ["A5"], bound=12, ranges=REALISTIC)
    q = query(project, a)
    interp = Interpreter(q.element, REALISTIC, python_settings({}), dict(q.defined))
    steps = list(r.trace)
    i = next(k for k, s in enumerate(steps) if s.event == "EXAX::out_of_sync.out")
    steps[i] = dataclasses.replace(steps[i], event="EXAX::done.out", channel=("EXAX::done", "out"))
    with pytest.raises(ReplayFailure) as failure:
        replay(interp, tuple(steps), {}, None, lambda config, succ: interp.terminated(config))
    assert failure.value.bmc == "EXAX::done.out" and "EXAX::out_of_sync.out" in failure.value.interpreter


def test_initial_choices_feed_replay_with_unbounded_data() -> None:
    """With no ranges, replay starts from the values BMC chose and feeds the trace's inputs."""
    result = CliRunner().invoke(cli, ["check", str(EXAMPLE), "-a", "A5", "--format", "json"])
    [r] = json.loads(result.output)["results"]
    assert r["verdict"] == "violated" and r["replayed"] == "yes"
    assert initial_choices  # the decoder's view of the starting values is what replay is given


def test_a_specifications_record_input_is_named_as_the_models_event(tmp_path) -> None:
    """`Spec refines M` with `Spec = M::input.in?x -> STOP` over a record type: the explicit engine
    named the specification's event `M::input.in.Record({'q': 0, 'p': 0})`, which no event of M
    matched (`M::input.in.(q=0, p=0)`), and said `violated` where BMC says `holds` (RoboTool's test15
    A0 the same)."""
    from conftest import write_files

    from tockbmc.explicit.engine import check_explicit
    from tockbmc.model.ranges import Range, Ranges
    write_files(tmp_path, {
        "m.rct": "datatype DT { q : nat  p : nat }\nstm M {\n  event input : DT\n  var i : DT\n  initial I\n"
                 "  state A { }\n  state B { }\n  transition t0 { from I to A }\n"
                 "  transition t1 { from A to B trigger input?i }\n}\n",
        "m.assertions": "timed csp Spec csp-begin\nTimed(OneStep) {\nSpec = M::input.in?x -> STOP\n}\ncsp-end\n"
                        "timed assertion A1: Spec refines M\n"})
    ranges = Ranges({"core_nat": Range(Fraction(0), Fraction(1))})
    project = load(tmp_path)
    [bmc] = check(project, bound=12, ranges=ranges, timeout=60)
    [explicit] = check_explicit(project, None, 8, ranges, {}, 60, 100_000)
    assert bmc.verdict == explicit.verdict == "holds", (bmc.reason, explicit.reason)


def test_a_specification_elements_tuple_values_are_named_as_the_models() -> None:
    """RoboTool's test-vector-matrix A1, `test1::S1 equals test2::S2` over `vector(int, 2)` events:
    the element on the specification's side once named its values `Product((-1, -1))`, the model
    `(-1, -1)`, and the explicit engine, which matches events by name, called it violated."""
    small = Ranges({"core_int": Range(Fraction(-1), Fraction(1)), "core_nat": Range(Fraction(0), Fraction(1))})
    [r] = check_explicit(load(CONFORMANCE / "robochart" / "test-vector-matrix"), ["A1"], 12, small, {}, 60, 100_000)
    assert r.verdict == "holds", r.reason


def test_a_lazy_run_reached_two_ways_is_made_concrete(tmp_path: Path) -> None:
    """S1 is reached by a?x after go and by b?x then an internal step: equal configurations
    holding different Unknowns, which the lazy search must not take one for the other (the run
    to S2 is made concrete, its value of x chosen where it was received)."""
    (tmp_path / "m.rct").write_text("""
interface I { event go event a : int event b : int }
stm M {
 uses I
 var x : int
 initial i
 state S0 {}
 state X {}
 state Y {}
 state S1 {}
 state S2 {}
 transition t0 { from i to S0 }
 transition t1 { from S0 to X trigger go }
 transition t2 { from S0 to Y trigger b?x }
 transition t3 { from X to S1 trigger a?x }
 transition t4 { from Y to S1 }
 transition t5 { from S1 to S2 condition x == 1 }
}
""")
    (tmp_path / "m.assertions").write_text("timed assertion R: S2 is not reachable in M.\n")
    [r] = check_explicit(load(tmp_path), None, 10, Ranges({"core_int": Range(Fraction(-1), Fraction(1))}), {},
                         timeout=60)
    assert r.verdict == "violated"
    assert [s.event for s in r.trace if s.kind != "internal"] == ["M::b.in.1"]
