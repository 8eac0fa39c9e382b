"""Probabilistic junctions: read as junctions whose choice is nondeterministic, as RoboTool's CSP
semantics reads them (`tockbmc.model.probabilistic`), and said so by every result they bear on;
RoboTool's validator rules on probabilities (PJ1, PJ2, PT1, PT2 errors; PJ3 a warning)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
from conftest import run_cli, verdicts_are, write_files

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.model.probabilistic import note
from tockbmc.model.result import Result
from tockbmc.report.html import render_report
from tockbmc.report.results import schema

CHOICE = """\
interface I {
	event a
	event b
}
stm M {
	uses I
	initial i
	probabilistic p
	state s1 { }
	state s2 { }
	transition t0 { from i to p }
	transition t1 { from p to s1 probability 0.3 }
	transition t2 { from p to s2 probability 0.7 }
	transition t3 { from s1 to s1 trigger a }
	transition t4 { from s2 to s2 trigger b }
}
stm Plain {
	uses I
	initial i
	state s { }
	transition t0 { from i to s }
	transition t1 { from s to s trigger a }
}
"""

ASSERTIONS = """\
assertion S1: s1 is reachable in M
assertion S2: s2 is reachable in M
assertion D: M is deterministic
assertion P: Plain is deterministic
"""

NOTE = ("probabilistic choice at junction M::p read as nondeterministic choice, "
        "as RoboTool's CSP semantics does")
BOUND = 8


@pytest.fixture(scope="module")
def choice(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_files(tmp_path_factory.mktemp("choice"), {"m.rct": CHOICE, "m.assertions": ASSERTIONS})


@pytest.fixture(scope="module")
def results(choice: Path) -> tuple[list[Result], list[Result]]:
    """Both engines' results on `CHOICE`, which must agree: either branch is taken, so M is not
    deterministic; Plain, without a probabilistic junction, is."""
    return verdicts_are(load(choice), None, BOUND,
                        {"S1": "holds", "S2": "holds", "D": "violated", "P": "holds"})


def test_a_probabilistic_junction_is_a_junction_marked_probabilistic(choice: Path) -> None:
    project: Project = load(choice)
    assert not project.warnings
    m = next(m for m in project.machines if m.name == "M")
    p = m.node("p")
    assert (p.kind, p.probabilistic) == ("junction", True)
    assert [(t.name, t.source, t.target) for t in m.transitions if t.source == "p"] == [
        ("t1", "p", "s1"), ("t2", "p", "s2")]


def test_both_engines_take_either_branch_of_the_choice(results: tuple[list[Result], list[Result]]) -> None:
    """Each branch's target is reachable, and M is not deterministic: the two runs of the
    nondeterminism part at the junction, one to s1 doing `a`, the other to s2 refusing it (or the
    other way round). Plain, without a probabilistic junction, is deterministic."""
    for engine in results:
        assert {r.assertion: r.verdict for r in engine} == {"S1": "holds", "S2": "holds", "D": "violated",
                                                            "P": "holds"}
        [d] = [r for r in engine if r.assertion == "D"]
        assert d.reason is not None
        assert d.reason.removeprefix("M is not deterministic: ") in (
            "after the empty trace, one run can do M::a.in and another, stable in [M: s2], refuses it",
            "after the empty trace, one run can do M::b.in and another, stable in [M: s1], refuses it")


def test_every_result_on_an_element_with_a_probabilistic_junction_says_how_it_was_read(
        results: tuple[list[Result], list[Result]]) -> None:
    for engine in results:
        assert {r.assertion: r.notes for r in engine} == {"S1": (NOTE,), "S2": (NOTE,), "D": (NOTE,), "P": ()}


def test_the_note_is_printed_in_text_json_and_html(choice: Path, results: tuple[list[Result], list[Result]]) -> None:
    text = run_cli(["check", choice, "-a", "S1", "-k", str(BOUND)])
    assert text.crash is None and f"note: {NOTE}" in text.stdout
    out = run_cli(["check", choice, "-a", "S1", "-a", "P", "-k", str(BOUND), "--format", "json"])
    document = json.loads(out.stdout)
    jsonschema.Draft202012Validator(schema()).validate(document)
    s1, plain = document["results"]
    assert s1["notes"] == [NOTE] and "notes" not in plain
    page = render_report(results[0], title="choice", version="test")
    assert page.count("read as nondeterministic choice") == 3


NESTED = """\
interface I {
	event a
}
interface J { Op() }
operation Op() {
	uses I
	initial i
	probabilistic q
	final f
	transition t0 { from i to q }
	transition t1 { from q to f probability 1 action a }
}
stm M {
	uses I
	requires J
	initial i
	state s {
		initial j
		probabilistic p
		state u { }
		transition t0 { from j to p }
		transition t1 { from p to u probability 1 }
	}
	transition t0 { from i to s }
	transition t1 { from s to s trigger a action Op() }
}
controller C {
	uses I
	sref m = M
	opref o = Op
}
"""


def test_the_notes_name_every_probabilistic_junction_the_check_runs(tmp_path: Path) -> None:
    """A junction inside a state, and one in an operation the controller defines: the machine in its
    controller calls that operation; checked alone, it calls a platform operation of that name."""
    write_files(tmp_path, {"m.rct": NESTED, "m.assertions": "assertion InC: C::m is deadlock-free\n"
                                                            "assertion Alone: M is deadlock-free\n"})
    notes = {r.assertion: r.notes for r in check(load(tmp_path), bound=4)}
    assert notes == {"InC": (note("M::s::p"), note("Op::q")), "Alone": (note("M::s::p"),)}


def load_diagnostics(tmp_path: Path, transitions: str) -> list[tuple[int, int, str, str]]:
    """(line, column, severity, message) of each diagnostic of a machine with a probabilistic
    junction `p` and states `s1`, `s2`, whose transitions from line 7 on are `transitions`."""
    write_files(tmp_path, {"m.rct": "stm M {\n  var x : int = 0\n  initial i\n  probabilistic p\n"
                                    "  state s1 {}\n  state s2 {}\n" + transitions + "}\n"})
    try:
        diagnostics = load(tmp_path).warnings
    except ModelError as exc:
        diagnostics = exc.diagnostics
    return [(d.pos.line, d.pos.column, d.severity, d.message) for d in diagnostics]


START = "  transition t0 { from i to p }\n"


def test_a_boolean_probability_is_a_warning_with_a_caret_and_the_model_loads(tmp_path: Path) -> None:
    """RoboTool checks no type in a probability (it warns that `true` might not lie from 0 to 1), and
    tockbmc drops probabilities: the model loads, with a warning."""
    write_files(tmp_path, {"m.rct": "stm M {\n  initial i\n  probabilistic p\n  state s {}\n" + START
                                    + "  transition t1 { from p to s probability true }\n}\n"})
    out = run_cli(["show", tmp_path])
    assert out.exit_code == 0 and out.crash is None, out.output
    assert "m.rct:6:43: warning: a probability should be real, but this is boolean" in out.stderr
    lines = out.stderr.splitlines()
    [at] = [i for i, line in enumerate(lines) if line.endswith("transition t1 { from p to s probability true }")]
    assert lines[at + 1].rstrip() == " " * lines[at].index("true") + "^~~~"


@pytest.mark.parametrize(("transitions", "expected"), [
    pytest.param("  transition t1 { from p to s1 probability 1.5 }\n  transition t2 { from p to s2 probability 0 }\n",
                 [(4, 17, "warning", "the probabilities of the transitions from probabilistic junction 'p' add up "
                                     "to 1.5, not 1"),
                  (8, 44, "error", "a probability must be from 0 to 1, but this is 1.5")], id="PT2-literal-above-1"),
    pytest.param("  transition t1 { from p to s1 }\n  transition t2 { from p to s2 probability 1 }\n",
                 [(8, 14, "error", "transition 't1' leaves probabilistic junction 'p', so it must have a probability")],
                 id="PJ1-no-probability"),
    pytest.param("  transition t1 { from p to s1 probability 0.5 condition x > 0 }\n"
                 "  transition t2 { from p to s2 probability 0.5 condition else }\n",
                 [(8, 48, "error", "transition 't1' leaves probabilistic junction 'p', so it cannot have a condition"),
                  (9, 48, "error", "transition 't2' leaves probabilistic junction 'p', so it cannot have a condition")],
                 id="PJ2-condition"),
    pytest.param("  transition t1 { from p to s1 probability 1 }\n  transition t2 { from s1 to s2 probability 1 }\n",
                 [(9, 33, "error", "only a transition from a probabilistic junction has a probability, and 't2' "
                                   "leaves 's1'")], id="PT1-probability-from-a-state"),
    pytest.param("  transition t1 { from p to s1 probability 0.3 }\n  transition t2 { from p to s2 probability 0.6 }\n",
                 [(4, 17, "warning", "the probabilities of the transitions from probabilistic junction 'p' add up "
                                     "to 0.9, not 1")], id="PJ3-sum-not-1"),
    pytest.param("  transition t1 { from p to s1 probability x }\n  transition t2 { from p to s2 probability 0.6 }\n",
                 [], id="PJ3-not-judged-for-an-expression"),
    pytest.param("  transition t1 { from p to s1 probability 0.1 }\n  transition t2 { from p to s2 probability 0.2 }\n"
                 "  transition t3 { from p to s2 probability 0.7 }\n", [], id="PJ3-exact-sum"),
])
def test_robotool_rules_on_probabilities(tmp_path: Path, transitions: str,
                                         expected: list[tuple[int, int, str, str]]) -> None:
    assert load_diagnostics(tmp_path, START + transitions) == expected
