"""A construct RoboTool accepts and tockbmc gives no meaning loads with a warning, and makes only
the assertions whose element reaches it `unsupported`, in both engines, naming it and its place
(docs/language.md §6): an assertion on another machine of the same model is still decided."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import both_engines, write_files

import tockbmc
from tockbmc import ModelError
from tockbmc.model.ranges import Range, Ranges

INT = Ranges({"core_int": Range(Fraction(-2), Fraction(2))})

# A machine no construct reaches: its assertion is decided.
PLAIN = """\
stm Plain {
	uses I
	var x : int = 0
	initial i
	state s { }
	transition t0 { from i to s }
	transition t1 { from s to s trigger e?x }
}
"""
ASSERTIONS = "assertion P : Plain is deadlock-free.\nassertion U : User is deadlock-free.\n"


def user(declarations: str, transition: str = "", entry: str = "") -> str:
    """Machine `User`, reaching the construct in its transition `t1` or in the entry action of `s`."""
    return (f"stm User {{\n\tuses I\n\tvar t : int = 0\n{declarations}\tinitial i\n\tstate s {{ {entry} }}\n"
            f"\ttransition t0 {{ from i to s }}\n\ttransition t1 {{ from s to s trigger e?t {transition} }}\n}}\n")


# (what the model holds besides the two machines, User, the construct's name, its line and column)
CASES = {
    "the": ("", user("", transition="condition (the z : int | z > t @ z) > 0"),
            "definite descriptions ('the')", 16, 53),
    "is": ("", user("\tvar b : boolean = false\n", entry="entry b = (t is nat)"),
           "toolkits (type tests 'is')", 15, 23),
    "inverse, in a function the machine calls": (
        "function inv(m : matrix(real, 2, 2)) : matrix(real, 2, 2) {\n\tpostcondition result == inverse(m)\n}\n",
        user("\tvar m : matrix(real, 2, 2)\n", entry="entry m = inv(m)"),
        "matrix inverses ('inverse')", 2, 26),
    "to": ("", user("", entry="entry t = to"), "the expression 'to'", 14, 22),
    "a toolkit function not built in": (
        "import relation_toolkit::*\n", user("\tvar q : Seq(int) = <1>\n", entry="entry q = squash(q)"),
        "toolkit function 'squash'", 16, 22),
    "a cast to a type that does not hold the value": (
        "", user("\tvar n : nat = 0\n", entry="entry n = true as nat"),
        "a cast 'as nat' of a value of type boolean", 15, 22),
    "a call that does not fix a generic type": (
        "function none(n : nat) : Set(?X) {\n\tpostcondition result == {}\n}\n",
        user("\tvar q : Set(int) = {}\n", entry="entry q = none(1)"),
        "a call of 'none' whose arguments do not fix its generic type ?X", 18, 22),
    "an assignment past an item": (
        "record R { a : int }\n", user("\tvar q : Seq(R) = <R (| a = 1 |)>\n", entry="entry q[1].a = 2"),
        "an assignment to a part of an item", 16, 18),
    "an assignment to a matrix's item": (
        "", user("\tvar m : matrix(int, 2, 2)\n", entry="entry m[1, 2] = 3"),
        "an assignment to a matrix's item", 15, 20),
    "a trigger predicate": ("", user("").replace("trigger e?t", "trigger e[| t > 0 |]?t"),
                            "trigger predicates ('[| … |]')", 16, 38),
}


@pytest.mark.parametrize(("before", "machine", "what", "line", "column"), CASES.values(), ids=list(CASES))
def test_only_the_assertion_that_reaches_the_construct_is_unsupported(
        tmp_path: Path, before: str, machine: str, what: str, line: int, column: int) -> None:
    rct = before + "interface I { event e : int }\n" + PLAIN + machine
    project = tockbmc.load(write_files(tmp_path, {"m.rct": rct, "m.assertions": ASSERTIONS}))
    assert [(w.pos.line, w.pos.column) for w in project.warnings if what in w.message] == [(line, column)], \
        [str(w) for w in project.warnings]
    for results in both_engines(project, INT, 6):
        verdicts = {r.assertion: r for r in results}
        assert verdicts["P"].verdict.value == "holds", verdicts["P"].reason
        assert verdicts["U"].verdict.value == "unsupported", verdicts["U"].reason
        assert what in verdicts["U"].reason and f"{tmp_path / 'm.rct'}:{line}:{column}" in verdicts["U"].reason


def test_a_construct_an_enclosing_expression_drops_is_refused_with_the_model(tmp_path: Path) -> None:
    """An operator whose operand has no type may be built as an error value, and the construct
    with it: no check could then see it, so the model is refused where it is, as before."""
    machine = user("", entry="entry t = (the z : int | z > 0 @ z) as int")
    rct = "interface I { event e : int }\n" + PLAIN + machine
    with pytest.raises(ModelError) as info:
        tockbmc.load(write_files(tmp_path, {"m.rct": rct, "m.assertions": ASSERTIONS}))
    assert [d.message for d in info.value.diagnostics if d.severity == "error"] == \
        ["unsupported: definite descriptions ('the')"]
