"""Model errors cite the RoboTool rule they enforce; what RoboTool accepts, tockbmc loads.

`model/rules.py` names RoboTool's rules; docs/language.md §5.1 lists each error with its rule.
A model RoboTool accepts is not refused for want of a rule: declaration order does not matter
where RoboTool's scoping does not make it matter, and what tockbmc cannot give a meaning to is
`unsupported`, not an error.
"""

from __future__ import annotations

import ast as pyast
import re
from pathlib import Path

import pytest
from conftest import REPO, both_engines, run_cli, write_files

from tockbmc import ModelError, load
from tockbmc.model import ast
from tockbmc.model.ranges import Ranges
from tockbmc.model.rules import LINKING, RULES

SOURCES = [REPO / "tockbmc" / "model" / name for name in ("resolver.py", "expressions.py", "parser.py")]
LANGUAGE = REPO / "docs" / "language.md"


def cited_rules(path: Path) -> set[str]:
    """The rules the error calls of a source file cite, by name or by constant."""
    constants = {"LINKING": "linking", "UNIQUE": "NamesAreUnique", "TYPING": "typing", "GRAMMAR": "grammar",
                 "LIMIT": "tockbmc limit"}
    found = set()
    for node in pyast.walk(pyast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, pyast.keyword) and node.arg == "rule":
            if isinstance(node.value, pyast.Constant):
                found.add(node.value.value)
            elif isinstance(node.value, pyast.Name) and node.value.id in constants:
                found.add(constants[node.value.id])
    return found


def table_rules() -> set[str]:
    """The rules docs/language.md §5.1's table cites (its second column)."""
    text = LANGUAGE.read_text(encoding="utf-8")
    section = text[text.index("### 5.1"):text.index("## 6.")]
    return {m.group(1) for m in re.finditer(r"^\|[^|\n]*\|\s*`([^`]+)`", section, re.M)}


def test_every_rule_cited_in_the_code_is_named_in_the_rules_table() -> None:
    cited = set().union(*(cited_rules(p) for p in SOURCES))
    assert cited - {""} <= set(RULES), sorted(cited - set(RULES))
    assert len(cited) >= 30


def test_the_diagnostics_table_of_language_md_cites_exactly_the_rules() -> None:
    assert table_rules() == set(RULES), sorted(table_rules() ^ set(RULES))


def test_an_error_is_printed_with_its_rule_after_the_message_and_the_caret_below(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": "stm S {\n\tinitial i\n\tstate s { }\n\ttransition t0 { from i to s }\n"
                                    "\ttransition t1 { from s to i }\n}\n"})
    result = run_cli(["show", str(tmp_path)])
    assert result.exit_code == 3 and result.crash is None
    lines = result.stderr.splitlines()
    at = next(i for i, line in enumerate(lines) if ": error: " in line)
    assert lines[at].endswith("m.rct:5:28: error: a transition cannot enter initial junction 'i' [RoboTool rule IJ1]")
    assert lines[at + 2] == "  " + " " * 27 + "^"  # under column 28


def test_an_unknown_name_cites_linking(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": "stm S {\n\tvar x : int = y\n\tinitial i\n\tstate s { }\n"
                                    "\ttransition t0 { from i to s }\n}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    [d] = info.value.diagnostics
    assert d.message == "unknown name 'y'" and d.rule == LINKING


ORDER = """\
interface I { event e }
stm S {
	uses I
	const a : int = b + 1
	const b : int = 2
	var x : int = a
	initial i
	state s { }
	transition t0 { from i to s }
	transition t1 { from s to s trigger e condition x == 3 }
}
controller C {
	uses I
	connection C on e to S on e
	sref S = S
}
module M {
	connection RP on e to C on e ( _async )
	cref C = C
	robotic platform RP { uses I }
}
"""


def test_a_constant_may_be_initialised_from_a_constant_declared_after_it(tmp_path: Path) -> None:
    """RoboTool's scoping puts all an element's variables in scope in each initial value
    (RoboChartScopeProvider.variablesDeclared): `a = b + 1` before `b = 2` loads, and each engine
    gives the same answers as with `b` declared first."""
    assertions = "assertion A1 : s is reachable in S\nassertion A2 : S is deadlock-free\n"
    later = load(write_files(tmp_path / "later", {"m.rct": ORDER, "a.assertions": assertions}))
    earlier = load(write_files(tmp_path / "earlier", {"m.rct": ORDER.replace(
        "const a : int = b + 1\n\tconst b : int = 2", "const b : int = 2\n\tconst a : int = b + 1"),
        "a.assertions": assertions}))
    [machine] = later.machines
    assert [v.name for v in machine.variables] == ["b", "a", "x"]  # each after those it names
    [value] = [v.initial for v in machine.variables if v.name == "a"]
    assert isinstance(value, ast.Binary) and isinstance(value.left, ast.VarRef) and value.left.variable.initial is not None

    def verdicts(project: object) -> list[tuple[str, str, str]]:
        bmc, explicit = both_engines(project, Ranges(), 6, timeout=60)
        return [(r.assertion, r.verdict.value, s.verdict.value) for r, s in zip(bmc, explicit, strict=True)]

    assert verdicts(later) == verdicts(earlier)
    assert [v[2] for v in verdicts(later)] == ["holds", "holds"]  # decided by the explicit engine


def test_a_controller_reference_may_follow_the_connection_that_names_it(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": ORDER})
    project = load(tmp_path)
    [module] = project.modules
    assert [c.name for c in module.controllers] == ["C"]


def test_constants_initialised_from_each_other_are_unsupported_not_invalid(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": "stm S {\n\tconst a : int = b\n\tconst b : int = a\n\tinitial i\n"
                                    "\tstate s { }\n\ttransition t0 { from i to s }\n}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    messages = [(d.pos.line, d.message, d.rule) for d in info.value.diagnostics]
    assert messages == [(line, "unsupported: constants whose values name each other ('a', 'b')", "")
                        for line in (2, 3)]


def test_an_initial_value_reading_a_variable_declared_after_it_is_unsupported(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": "stm S {\n\tvar x : int = y\n\tvar y : int = 1\n\tinitial i\n"
                                    "\tstate s { }\n\ttransition t0 { from i to s }\n}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    [d] = info.value.diagnostics
    assert d.message == "unsupported: the initial value of 'x' reads 'y', a variable declared after it"
    assert (d.pos.line, d.pos.column) == (2, 16)


def test_a_platform_constant_may_name_another(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": ORDER.replace("robotic platform RP { uses I }",
                                                  "robotic platform RP { uses I const p : int = q const q : int = 1 }")})
    [module] = load(tmp_path).modules
    assert [(v.name, isinstance(v.initial, ast.Expr)) for v in module.platform.variables] == [("q", True), ("p", True)]


@pytest.mark.parametrize("write, rule, unsupported", [
    ("action c = 1", "", True),
    ("trigger e?c", "", True),
    ("action p = 1", "assignmentToParameter", False),
])
def test_a_write_to_a_constant_is_unsupported_and_one_to_a_parameter_breaks_rule_assignment_to_parameter(
        tmp_path: Path, write: str, rule: str, unsupported: bool) -> None:
    """RoboTool's scoping lets an assignment or input name a constant, and its validator refuses
    only a write to an operation's parameter (checkAssignmentToParameter)."""
    machine = "operation O(p : int)" if rule else "stm S"
    write_files(tmp_path, {"m.rct": f"{machine} {{\n\tconst c : int = 0\n\tevent e : int\n\tinitial i\n"
                                    f"\tstate s {{ }}\n\ttransition t0 {{ from i to s }}\n"
                                    f"\ttransition t1 {{ from s to s {write} }}\n}}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    [d] = info.value.diagnostics
    assert d.message.startswith("unsupported: ") == unsupported and d.rule == rule, d


@pytest.mark.parametrize("declaration", ["datatype R { next : R }", "enumeration E { Leaf Node(E) }"])
def test_a_type_defined_in_terms_of_itself_is_unsupported_not_invalid(tmp_path: Path, declaration: str) -> None:
    """RoboTool has no rule against a recursive record or enumeration; tockbmc's values are finite."""
    name = declaration.split()[1]
    write_files(tmp_path, {"m.rct": f"{declaration}\nstm S {{\n\tvar x : {name}\n\tinitial i\n\tstate s {{ }}\n"
                                    "\ttransition t0 { from i to s }\n}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    errors = [d for d in info.value.diagnostics if d.severity == "error"]
    assert errors and all(d.message.startswith("unsupported: ") and not d.rule for d in errors), errors
    assert any(f"'{name}' is defined in terms of itself" in d.message for d in errors)


@pytest.mark.parametrize("deadline", ["<{true}", "action e <{true}"])
def test_a_deadline_that_is_not_a_number_is_unsupported_not_invalid(tmp_path: Path, deadline: str) -> None:
    """RoboTool checks no type in a deadline."""
    write_files(tmp_path, {"m.rct": "stm S {\n\tevent e\n\tinitial i\n\tstate s { }\n"
                                    "\ttransition t0 { from i to s }\n"
                                    f"\ttransition t1 {{ from s to s trigger e {deadline} }}\n}}\n"})
    with pytest.raises(ModelError) as info:
        load(tmp_path)
    [d] = info.value.diagnostics
    assert d.message == "unsupported: a deadline of type boolean (tockbmc reads a deadline as a nat)" and not d.rule
