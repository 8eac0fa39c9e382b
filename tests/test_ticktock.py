"""Refinement in the tick-tock model (docs/semantics.md §7.13), both engines, both directions.

The model `tests/models/ticktock` holds machines whose tick-tock verdicts differ from their
failures verdicts; each verdict is worked out by hand in the comments of `tt.assertions`: a
tick-tock observation records the refusal of the stable state each tock happens in, so an
internal choice made before time passes is told apart from one that is still open after it.
"""

from __future__ import annotations

import json
from fractions import Fraction
from functools import cache
from pathlib import Path

import jsonschema
from conftest import load_differential, run_cli

import tockbmc
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.config import configure
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Result
from tockbmc.report.results import schema

MODEL = Path(__file__).parent / "models" / "ticktock"
BOUND = 6

EXPECTED = {"F1": "holds", "T1": "violated", "T1n": "holds", "F2": "holds", "T2": "holds", "F3": "holds",
            "T3": "holds", "F4": "holds", "T4": "violated", "T4n": "holds", "E1": "violated", "T5": "holds",
            "T6": "holds", "T7": "violated", "T8": "holds", "T9": "violated",
            "M1": "holds", "M2": "violated", "N1": "holds", "N2": "holds"}


@cache
def results(engine: str) -> dict[str, Result]:
    project = tockbmc.load(MODEL)
    config = configure(project)
    if engine == "bmc":
        return {r.assertion: r for r in check(project, bound=BOUND, config=config)}
    return {r.assertion: r for r in check_explicit(project, None, BOUND, Ranges({}), {}, 60, config=config)}


def test_the_verdicts_worked_out_by_hand_in_both_engines() -> None:
    for engine in ("bmc", "explicit"):
        assert {k: r.verdict for k, r in results(engine).items()} == EXPECTED, engine


def test_the_model_on_the_left_shows_and_replays_the_refusal_before_the_tock() -> None:
    """T1: Choose, stable in sa or sb, refuses the other event and lets time pass; ExtOrStop is
    then STOP, and the event Choose does next is one it cannot do (F1 holds: failures do not see it)."""
    for engine in ("bmc", "explicit"):
        r = results(engine)["T1"]
        visible = [s.event for s in r.trace if s.kind != "internal"]
        assert visible in (["tock", "Choose::a.in"], ["tock", "Choose::b.in"]), (engine, visible)
        [seen] = r.extra["tock_refusals"]
        assert seen["step"] == next(s.step for s in r.trace if s.kind == "tock")
        assert seen["offered"] == sorted([visible[1], "tock"])
        assert "each tock keeping only the states of the specification" in (r.reason or "")
    assert results("bmc")["T1"].extra["replayed"] == "yes"


def test_a_tock_no_state_of_the_specification_can_match() -> None:
    """T7: after a, Term lets time pass; TermUrgent must terminate first."""
    for engine in ("bmc", "explicit"):
        r = results(engine)["T7"]
        assert [s.event for s in r.trace if s.kind != "internal"] == ["Term::a.in", "tock"]
        assert r.extra["tock_refusals"][-1]["offered"] == ["Term::terminate", "tock"]
        assert "cannot let time pass" in (r.reason or "")
    assert results("bmc")["T7"].extra["replayed"] == "yes"


def test_the_specification_on_the_left_shows_its_observation() -> None:
    """T4: EachOrStop's a->STOP refuses b before a tock, then does a; Offer refuses b only in stop."""
    for engine in ("bmc", "explicit"):
        r = results(engine)["T4"]
        assert [s.event for s in r.trace] == ["tock", "Offer::a.in"], engine
        [seen] = r.extra["tock_refusals"]
        assert seen == {"step": 1, "offered": ["Offer::a.in", "tock"]}
        assert "EachOrStop has this observation" in (r.reason or "")


def test_the_json_report_carries_the_refusals_and_validates() -> None:
    out = run_cli(["check", MODEL, "-a", "T1", "-a", "T4", "--bound", str(BOUND), "--format", "json"])
    document = json.loads(out.stdout)
    jsonschema.Draft202012Validator(schema()).validate(document)
    t1, t4 = document["results"]
    assert t1["tock_refusals"][0]["offered"][-1] == "tock" and t1["replayed"] == "yes"
    assert t4["tock_refusals"] == [{"step": 1, "offered": ["Offer::a.in", "tock"]}]


def test_the_text_report_shows_the_refusal_at_the_tock() -> None:
    out = run_cli(["check", MODEL, "-a", "T1", "--bound", str(BOUND)])
    tock = next(line for line in out.stdout.splitlines() if " tock " in line)
    assert "refusing all but {Choose::" in tock and "tock} before it" in tock


def test_untimed_tick_tock_is_unsupported(tmp_path: Path) -> None:
    text = (MODEL / "tt.assertions").read_text() + "untimed assertion U : Choose refines ExtOrStop in the tick-tock model\n"
    (tmp_path / "tt.rct").write_text((MODEL / "tt.rct").read_text())
    (tmp_path / "tt.assertions").write_text(text)
    [r] = check(tockbmc.load(tmp_path), ["U"], bound=BOUND)
    assert r.verdict == "unsupported" and "untimed" in (r.reason or "")


def test_two_model_elements_one_renamed_as_the_specification() -> None:
    """M2: Choose, renamed to Offer's channels, stands for the specification on the left; its
    observation <[everything but a] tock, a> is not Offer's (N2: the failures model does not see it)."""
    for engine in ("bmc", "explicit"):
        r = results(engine)["M2"]
        assert [s.event for s in r.trace] == ["tock", "Offer::a.in"], engine
        assert r.extra["tock_refusals"] == [{"step": 1, "offered": ["Offer::a.in", "tock"]}]
        assert "ChooseAsOffer has this observation" in (r.reason or "")


VALUES_RCT = """
stm In {
  event a : int
  var x : int
  initial i
  state s {}
  state t {}
  transition t0 { from i to s }
  transition t1 { from s to t trigger a?x condition x != 1 }
}
"""
VALUES_ASSERTIONS = """
timed csp S csp-begin
Timed(OneStep) {
  AnyA = In::a.in?v -> STOP
}
csp-end
timed assertion V0 : AnyA refines In in the tick-tock model
timed assertion V1 : AnyA refines In
"""


def test_a_specification_accepting_any_value_is_listed_value_by_value(tmp_path: Path) -> None:
    """AnyA accepts a.in with any value; In refuses a.in.1.  With core_int = 0..1 both values are
    listed, and <a.in.1> is a trace of AnyA but not of In: V0 and V1 are violated, shown by a trace
    (or observation) of AnyA starting with it (both engines).  Without a range the values cannot be listed: unsupported, saying why."""
    (tmp_path / "m.rct").write_text(VALUES_RCT)
    (tmp_path / "m.assertions").write_text(VALUES_ASSERTIONS)
    project = tockbmc.load(tmp_path)
    config = configure(project, default_ranges=Ranges({"core_int": Range(Fraction(0), Fraction(1))}))
    for rs in (check(project, bound=BOUND, config=config), check_explicit(project, None, BOUND, Ranges({}), {}, 60,
                                                                          config=config)):
        for r in rs:
            assert r.verdict == "violated" and [s.event for s in r.trace][0] == "In::a.in.1", r
    for r in check(project, bound=BOUND, config=configure(project)):
        assert r.verdict == "unsupported" and "give the channel's type a small range" in (r.reason or ""), r


def test_explore_refuses_a_model_element_as_the_specification() -> None:
    """explore varies ranges as parameters; the element standing for the specification is listed
    within fixed ones, so explore says so rather than follow a placeholder."""
    out = run_cli(["explore", MODEL, "-a", "M1", "--bound", str(BOUND)])
    assert "unsupported: explore's ranges are parameters" in out.stdout



def test_a_specification_with_many_observations_keeps_to_the_timeout(tmp_path: Path) -> None:
    """Differential seed 5000 (data, quantifiers): TTFew on the left has about a hundred
    observations, each a system with a follower that takes a while to build.  With a 1 s timeout
    the check stopped only after 50 s (each search was handed the 1 ms left, after building its
    system); now it stops building once the time is up and says so (or, on a faster run, its
    search is the one the timeout stops: either is the timeout kept)."""
    cases = load_differential()
    rct, assertions = cases.random_case(5000, 0.25, True, True, True, True)
    (tmp_path / "m.rct").write_text(rct)
    (tmp_path / "m.assertions").write_text(assertions)
    r, = check(tockbmc.load(tmp_path), ["TT3"], bound=16, ranges=cases.DATA_RANGES, timeout=1)
    assert r.verdict == "unknown" and ("(out of time)" in (r.reason or "") or "timed out" in (r.reason or "")), r
    assert r.seconds < 10, r.seconds  # a tenfold margin for a loaded machine; it was fifty
