"""Every rule of RoboTool's grammars is read as docs/language.md §7 says: its model loads, or it is
reported `unsupported` at the construct (refused with the model, or, with a warning, for the
assertions that reach it), or (an older syntax) read with a warning.

The models are `tests/models/grammar_rules/<Rule>.rct` (and `<Rule>.assertions`, about
`RAPackage.rct`), one a rule of RoboChart.xtext or Assertions.xtext, or a small group of rules
that are written together; each exercises its rule's optional parts and alternatives.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.model import ast
from tockbmc.model.expressions import PER_ASSERTION
from tockbmc.model.result import Verdict

RULES = Path(__file__).parent / "models" / "grammar_rules"
SUBJECT = RULES / "RAPackage.rct"

# Models whose rules tockbmc reads: each loads with neither an error nor a warning.
READ_MODELS = [
    "RCPackage.rct", "TypeDecl.rct", "Type.rct", "Event.rct", "Interface.rct", "RoboticPlatform.rct",
    "ControllerDef.rct", "StateMachineDef.rct", "Function.rct", "OperationDef.rct", "Node.rct",
    "Transition.rct", "Transition_probability.rct", "Communication.rct", "Statement.rct",
    "Expression.rct", "Atomic.rct", "RCModule.rct",
]
READ_ASSERTIONS = ["RAPackage.assertions", "Assertion.assertions", "CSPProcess.assertions",
                   "ClockInitialisationAssertion.assertions"]

BROADCAST = "unsupported: broadcast events ('_broadcast')"
PREDICATE = "unsupported: trigger predicates ('[| … |]')"
NESTED = "unsupported: an assignment to a part of an item ('s[i].f = e', 's[i][j] = e')"
ANN_CONTROLLER = "unsupported: controllers given by a neural network ('anncontroller')"
ANN_OPERATION = "unsupported: operations given by a neural network ('annoperation')"
IN_MODULE = "unsupported: state machines placed directly in a module (put them in a controller)"
PROB = "unsupported: probabilistic properties ('prob')"
FORMULA = "unsupported: formulas of probabilistic properties ('formula')"

# Models of rules tockbmc parses and refuses: (line, column, message) of every error, in order.
UNSUPPORTED_MODELS = {
    "Event_broadcast.rct": [(2, 21, BROADCAST)],
    "GeneralController.rct": [(3, 1, "unsupported: general controllers ('generalcontroller')")],
    "GeneralOperation.rct": [(2, 1, "unsupported: general operations ('generaloperation')")],
    "ANNController.rct": [(4, 1, ANN_CONTROLLER), (17, 2, ANN_CONTROLLER)],
    "ANNOperation.rct": [(3, 1, ANN_OPERATION), (15, 2, ANN_OPERATION)],
    "RCModule_stm.rct": [(11, 2, IN_MODULE), (12, 2, IN_MODULE)],
}
# Models of rules tockbmc parses and loads, whose constructs make the assertions that reach them
# unsupported: (line, column, message) of every warning, in order.
UNSUPPORTED_WHEN_CHECKED = {
    "Communication_predicate.rct": [(10, 38, PREDICATE), (11, 38, PREDICATE), (12, 38, PREDICATE),
                                    (13, 38, PREDICATE)],
    "Assignment_nested.rct": [(7, 18, NESTED), (7, 31, NESTED)],
    "DefiniteDescription.rct": [(3, 27, "unsupported: definite descriptions ('the')")],
    "TypedExpression_is.rct": [(3, 27, "unsupported: toolkits (type tests 'is')")],
    "VectorOrMatrixExp_inverse.rct": [(3, 26, "unsupported: matrix inverses ('inverse')"),
                                      (4, 26, "unsupported: matrix transposes ('transpose')")],
    "Atomic_to_from.rct": [(7, 22, "unsupported: the expression 'to'"),
                           (7, 31, "unsupported: the expression 'from'")],
}
UNSUPPORTED_ASSERTIONS = {
    "TypeInstantiation.assertions": [(2, 1, "unsupported: type instantiations ('instantiate')")],
}
# PRISM's items: each a warning where it is written, the file's other items loaded.
UNCHECKED_ASSERTIONS = {
    "Constant.assertions": [(2, 1, "unsupported: constants of probabilistic properties ('const')")],
    "Constants.assertions": [(3, 1, "unsupported: constant settings of probabilistic properties ('constants')"),
                             (5, 1, "unsupported: constant settings of probabilistic properties ('constants')")],
    "Label.assertions": [(2, 1, "unsupported: labels of probabilistic properties ('label')")],
    "Formula.assertions": [(2, 1, FORMULA)],
    "pExpression.assertions": [(line, 1, FORMULA) for line in range(4, 10)],
    "Rewards.assertions": [(2, 1, "unsupported: reward structures of probabilistic properties ('rewards')")],
    "ProbAssertion.assertions": [(line, 1, PROB) for line in (*range(5, 17), 18, 20, 21)],
    "Definitions.assertions": [(2, 1, "unsupported: definitions of probabilistic properties ('defs')")],
    "pModules.assertions": [(3, 1, "unsupported: modules of probabilistic properties ('pmodules')")],
}


def errors(*paths: Path) -> list[tuple[int, int, str]]:
    """(line, column, message) of each error loading `paths`, in report order."""
    with pytest.raises(ModelError) as info:
        load(*paths)
    return [(d.pos.line, d.pos.column, d.message) for d in info.value.diagnostics if d.severity == "error"]


def test_every_model_of_the_folder_is_pinned_here() -> None:
    """A model added to the folder without a line here would be checked by nothing."""
    named = {*READ_MODELS, *READ_ASSERTIONS, *UNSUPPORTED_MODELS, *UNSUPPORTED_WHEN_CHECKED, *UNSUPPORTED_ASSERTIONS,
             *UNCHECKED_ASSERTIONS,
             "RAPackage.rct", "Transition_empty_trigger.rct"}
    assert sorted(p.name for p in RULES.iterdir()) == sorted(named)


@pytest.mark.parametrize("name", READ_MODELS)
def test_read_rule_loads_without_a_diagnostic(name: str) -> None:
    project = load(RULES / name)
    assert project.warnings == ()


@pytest.mark.parametrize("name", READ_ASSERTIONS)
def test_read_assertion_rule_loads_without_a_diagnostic(name: str) -> None:
    project = load(SUBJECT, RULES / name)
    assert project.warnings == ()
    assert project.assertions


@pytest.mark.parametrize(("name", "expected"), UNSUPPORTED_MODELS.items())
def test_unsupported_rule_is_reported_at_the_construct(name: str, expected: list) -> None:
    assert errors(RULES / name) == expected


@pytest.mark.parametrize(("name", "expected"), UNSUPPORTED_WHEN_CHECKED.items())
def test_construct_without_a_meaning_loads_with_a_warning_at_it(name: str, expected: list) -> None:
    project = load(RULES / name)
    assert [(d.pos.line, d.pos.column, d.message.removesuffix(PER_ASSERTION)) for d in project.warnings] == expected


@pytest.mark.parametrize(("name", "expected"), UNSUPPORTED_ASSERTIONS.items())
def test_unsupported_assertion_rule_is_reported_at_the_item(name: str, expected: list) -> None:
    assert errors(SUBJECT, RULES / name) == expected


@pytest.mark.parametrize(("name", "expected"), UNCHECKED_ASSERTIONS.items())
def test_probabilistic_item_is_a_warning_and_the_file_still_loads(name: str, expected: list) -> None:
    project = load(SUBJECT, RULES / name)
    assert [(d.pos.line, d.pos.column, d.message) for d in project.warnings] == expected


def test_trigger_with_no_event_reads_as_no_trigger_with_a_warning() -> None:
    project = load(RULES / "Transition_empty_trigger.rct")
    [warning] = project.warnings
    assert (warning.pos.line, warning.pos.column) == (7, 30)
    assert "'trigger' with no event after it" in warning.message
    [machine] = project.machines
    t1 = next(t for t in machine.transitions if t.name == "t1")
    assert t1.trigger is None


# ------------------------------------------------------------------ rules read in full


@pytest.fixture(scope="module")
def assertions() -> Project:
    return load(SUBJECT, RULES / "Assertion.assertions")


def by_name(project: Project, name: str) -> ast.Assertion:
    return next(a for a in project.assertions if a.name == name)


def test_assertion_bodies_timings_and_models(assertions: Project) -> None:
    got = [(a.name, a.kind, a.negated, a.timing, a.semantic_model) for a in assertions.assertions[:12]]
    assert got == [
        ("a1", "reachable", False, None, None), ("a2", "reachable", True, None, None),
        ("a3", "refines", False, "timed", "traces"), ("a4", "equals", False, "untimed", "failures"),
        ("a5", "refines", True, None, "failures divergences"), ("a6", "equals", True, None, "tick-tock"),
        ("a7", "deadlock-free", False, None, None), ("a8", "divergence-free", True, None, None),
        ("a9", "deterministic", False, None, None), ("a10", "timelock-free", True, None, None),
        ("a11", "terminates", False, None, None), ("a12", "terminates", True, None, None),
    ]


def test_constant_setting_takes_any_expression(assertions: Project) -> None:
    """Assertions.xtext's `value=Expression`: sums, sequences, records, parentheses, negation (each
    typed as written: a literal `1` is a `nat`, which fits an `int` constant)."""
    got = {a.name: [(s.constant, s.kind, str(s.value.type)) for s in a.settings]
           for a in assertions.assertions if a.name in ("a13", "a14", "a15", "a16")}
    assert got == {
        "a13": [("k", "constant", "nat"), ("ks", "constant", "Seq(nat)"), ("pr", "constant", "Pair")],
        "a14": [("k", "constant", "int"), ("ks", "constant", "Seq(nat)")],
        "a15": [("pr", "constant", "Pair"), ("k", "constant", "nat")],
        "a16": [("d", "parameter", "nat")],
    }


def test_final_dot_after_a_selection_ends_the_assertion(assertions: Project) -> None:
    [setting] = by_name(assertions, "a17").settings
    assert isinstance(setting.value, ast.FieldRef) and setting.value.field_name == "a"
    assert by_name(assertions, "a18").kind == "terminates"


def test_expression_settings_are_decided(assertions: Project) -> None:
    results = check(assertions, ["a1", "a14", "a17"], bound=8)
    assert {r.assertion: r.verdict for r in results} == {"a1": "holds", "a14": "holds", "a17": "holds"}


def test_clock_initialisation_assertion_is_unsupported_when_checked() -> None:
    project = load(SUBJECT, RULES / "ClockInitialisationAssertion.assertions")
    results = check(project, bound=4)
    assert [(r.assertion, r.verdict) for r in results] == [("c1", "unsupported"), ("c2", "unsupported")]
    assert all("initialised" in r.reason for r in results)


def sends_of(project: Project, machine: str, state: str) -> list[ast.Send]:
    m = next(m for m in project.machines if m.name == machine)
    entry = next(n for n in m.nodes if n.name == state).entry
    assert isinstance(entry, ast.Seq)
    return [s for s in entry.statements if isinstance(s, ast.Send)]


def test_sync_value_is_any_call_expression() -> None:
    """RoboChart's `e.v` takes a CallExp: every atomic expression, and a call."""
    sends = sends_of(load(RULES / "Communication.rct"), "Talks", "s")
    assert [(s.event.name, type(s.value).__name__) for s in sends] == [
        ("num", "Literal"), ("real_", "Literal"), ("flag", "Literal"), ("num", "Binary"), ("num", "Unary"),
        ("seq", "SeqLiteral"), ("set_", "SetLiteral"), ("set_", "Builtin"), ("set_", "SetComprehension"),
        ("pair", "TupleLiteral"), ("rec", "RecordLiteral"), ("en", "EnumLiteral"), ("en", "EnumLiteral"),
        ("num", "Call"), ("num", "Since"), ("num", "VarRef"), ("num", "FieldRef"), ("text", "Literal"),
    ]


def test_relation_type_groups_a_function_type_on_its_left() -> None:
    """RoboChart.xtext's `RelationType: FunctionType ('<->' RelationType)?`: `int -> nat <-> boolean`
    relates functions to booleans (a set of pairs), not integers to relations."""
    [machine] = load(RULES / "Type.rct").machines
    g = next(v for v in machine.variables if v.name == "g")
    assert g.type == ast.SetType(ast.ProductType((ast.FunctionType(ast.INT, ast.NAT), ast.BOOLEAN)))


def test_a_probabilistic_property_leaves_the_assertions_beside_it_checked(tmp_path: Path) -> None:
    """A `prob property` is PRISM's, for nothing here to check: it is reported, and the CSP
    assertions of its file still load and are checked."""
    (tmp_path / "p.assertions").write_text("prob property p1 : Prob=? of [ Finally deadlock ]\n"
                                           "assertion A : Beeper is deadlock-free\n")
    project = load(SUBJECT, tmp_path / "p.assertions")
    assert [d.message for d in project.warnings] == [PROB]
    [result] = check(project, ["A"], bound=4)
    assert result.verdict in (Verdict.HOLDS, Verdict.VIOLATED)
