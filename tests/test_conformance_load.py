"""Load every model of RoboTool's regression suite (`../shared/conformance/robochart-tests`)
and every public project of `../shared/realworld`.

`robochart/<case>` models are valid RoboChart: each either loads, or is rejected
only with `unsupported: …` diagnostics naming a construct that language.md lists
as "Later".  `robochart-fail/<case>` models are invalid: each is rejected with a
real (not `unsupported`) error that names the reason RoboTool rejects it and cites
RoboTool's rule (docs/language.md §5.1).  The projects of PROJECTS.txt load, but
those RoboTool refuses too, which are refused for the rules recorded here.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import re
from fractions import Fraction
from functools import cache
from pathlib import Path

import pytest
from conftest import CONFORMANCE, SHARED, load_realworld, run_cli

from tockbmc import ModelError, Project, load
from tockbmc.model import Diagnostic

VALID = CONFORMANCE / "robochart"
INVALID = CONFORMANCE / "robochart-fail"

# The valid cases that load today.  A case that starts loading must be added
# here (and one that stops loading is a regression).
EXPECTED_LOAD = {
    "AlphaAlgorithm", "AsyncBuffers", "AutonomousChemicalDetector", "ChemicalDetector", "LetExpTest", "clocks0", "clocks1", "clocks2", "clocks3",
    "clocks5", "clocks6", "set1", "DuringAndDeadline", "DuringAndDeadline2", "Example1", "Example2",
    "clock-wait-op", "clocks-ops1", "clocks-ops2", "clocks-ops3", "clocks4-required", "clocks7", "clocks8",
    "const1", "const_ref", "multi_final_state", "ops1", "ops2", "ops3", "ops4", "refsem", "rp-var-visible",
    "rp-var-visible-uses", "simGeneric-1", "simGeneric-5", "simGeneric-8", "test-core-assertions",
    "test-simple-machine", "test1", "test10", "test11", "test12", "test13", "test14", "test2", "test3", "test4",
    "test5", "test6", "test7", "test8", "test9",
    # lambda, function types, override and `as`
    "FunctionToolkitCallMultiArgTest", "FunctionToolkitCallTest", "LambdaExpLetTest", "LambdaExpLetToolkitTest",
    "LambdaExpMultiArgTest", "LambdaExpTest", "LambdaExpToolkitTest", "LambdaExpVarTest", "LambdaExpVarToolkitTest",
    "SequenceAndProductTest",  # s[i] = e
    "test-vector-matrix",  # vectors and matrices as tuples
    "test15",  # enumeration literals with parameters load; a check that meets them is unsupported
}

# Valid cases rejected for a reason that is neither a bug nor on language.md's
# "Later" list: each must fail with exactly the recorded kind of message.  None today.
KNOWN_DEVIATIONS: dict[str, str] = {}
# The `unsupported:` message each known deviation must give.
DEVIATION_MESSAGES: dict[str, str] = {}

# language.md, "Later": sets, sequences, tuples, forall/exists, let, lambda,
# vectors and matrices, toolkits, collections.  forall/exists are reported as
# "quantified expressions".
LATER = re.compile(r"\b(sets?|sequences?|tuples?|quantified|let|lambda|vectors?|matri(x|ces)|toolkits?|collections?)\b")

# Why each robochart-fail case is invalid, as the diagnostic must say it, and the RoboTool rule it cites.
FAIL_REASONS = {
    "opcall-scope-fail": "not in scope",
    "operationInput*": "sends",
    "operationOutput*": "receives",
    "transitionsOutsideNodeContainer": "must stay inside",
}
FAIL_RULES = {
    "opcall-scope-fail": "linking",  # `op()` names no operation of a required interface
    "operationInput*": "Cn8",  # the connection ends at a machine whose operation sends the event
    "operationOutput*": "Cn9",  # the connection starts at a machine whose operation receives it
    "transitionsOutsideNodeContainer": "linking",  # a transition's source is outside its state
}


def cases(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.is_dir()) if directory.is_dir() else []


VALID_CASES = cases(VALID)
INVALID_CASES = cases(INVALID)


@cache
def outcome(directory: Path) -> Project | ModelError:
    """Load a case once per session: the project, or the ModelError (any other exception propagates)."""
    try:
        return load(directory)
    except ModelError as exc:
        return exc


def errors(exc: ModelError) -> list[Diagnostic]:
    return [d for d in exc.diagnostics if d.severity == "error"]


def describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(str(d) for d in diagnostics)


def assert_positions_in_files(diagnostics: list[Diagnostic]) -> None:
    """Every diagnostic points at a real line of a real file."""
    for d in diagnostics:
        path = Path(d.pos.path)
        assert path.is_file(), d
        n_lines = len(path.read_text(encoding="utf-8").split("\n"))
        assert 1 <= d.pos.line <= n_lines, d
        assert d.pos.column >= 1, d


def test_corpus_is_present() -> None:
    assert VALID.is_dir() and INVALID.is_dir(), f"clone the shared/ directory beside the repository: {CONFORMANCE}"
    assert len(VALID_CASES) == 64
    assert len(INVALID_CASES) == 14
    assert EXPECTED_LOAD <= set(VALID_CASES)
    assert set(KNOWN_DEVIATIONS) <= set(VALID_CASES) - EXPECTED_LOAD
    assert set(DEVIATION_MESSAGES) == set(KNOWN_DEVIATIONS)


@pytest.mark.parametrize("case", [c for c in VALID_CASES if c not in KNOWN_DEVIATIONS])
def test_valid_case(case: str) -> None:
    result = outcome(VALID / case)
    if case in EXPECTED_LOAD:
        assert isinstance(result, Project), f"{case} should load:\n{result}"
        assert not [w for w in result.warnings if w.severity == "error"]
        on_disk = {str(p) for p in (VALID / case).rglob("*") if p.suffix in (".rct", ".assertions")}
        assert set(result.files) == on_disk
        assert result.machines or result.controllers or result.modules or result.operations
        return
    assert isinstance(result, ModelError), f"{case} loads: add it to EXPECTED_LOAD"
    errs = errors(result)
    assert errs
    assert_positions_in_files(errs)
    not_unsupported = [d for d in errs if not d.message.startswith("unsupported: ")]
    assert not not_unsupported, f"{case}: errors other than 'unsupported':\n{describe(not_unsupported)}"
    assert any(LATER.search(d.message.removeprefix("unsupported: ")) for d in errs), \
        f"{case}: no diagnostic names a construct listed as Later:\n{describe(errs)}"


@pytest.mark.parametrize("case", sorted(KNOWN_DEVIATIONS))
def test_known_deviation(case: str) -> None:
    result = outcome(VALID / case)
    assert isinstance(result, ModelError), f"{case} now loads: remove it from KNOWN_DEVIATIONS"
    errs = errors(result)
    expected = DEVIATION_MESSAGES[case]
    assert any(d.message == expected for d in errs), describe(errs)
    unsupported = [d for d in errs if d.message.startswith("unsupported: ")]
    assert all(d.message == expected for d in unsupported), describe(unsupported)
    assert not any(LATER.search(d.message.removeprefix("unsupported: ")) for d in unsupported)


def test_parameterised_enumeration_is_checked() -> None:
    """test15's `enumeration EM { EM1 EM2(real) EM3(nat) }` and `var o : EM = EM3(1)`: the model
    loads (RoboTool accepts it) and BMC decides its machine.  Its one assertion, whose specification reads a
    received record's fields with RoboTool's `test15_DT_p(x)`, is checked, and undecided: the
    specification's traces, a record and tocks, are too many to list. The explicit engine decides
    the core assertions with func1's placeholder (RoboTool's `func1(e) = 0`); in the open reading,
    where func1 has no body, both engines decide them for every function func1 may be (the explicit
    engine choosing its values as runs read them), past the enumeration and the initial value
    `DT(|p=0|)` that omits field q."""
    from tockbmc.check import check
    from tockbmc.explicit.engine import check_explicit
    from tockbmc.model.config import configure
    from tockbmc.model.core import core_assertions
    from tockbmc.model.ranges import Range, Ranges
    from tockbmc.model.readings import Reading

    project = outcome(VALID / "test15")
    assert isinstance(project, Project)
    ranges = Ranges({"core_nat": Range(Fraction(0), Fraction(2)), "core_real": Range(Fraction(0), Fraction(1))})
    [bmc] = check(project, ranges=ranges, timeout=30)
    assert bmc.verdict == "unknown" and "more than 256 traces" in (bmc.reason or ""), bmc.reason
    project = dataclasses.replace(project, assertions=core_assertions(project))
    core = ["stm0_deadlock_free", "stm0_divergence_free"]
    assert {r.assertion: r.verdict for r in check(project, core, ranges=ranges, timeout=30)} == {
        a: "holds" for a in core}
    for r in check_explicit(project, core, 8, ranges, {}, 30, 10_000):
        assert r.verdict == "holds" and r.defaults["test15::func1"] == "0", (r.verdict, r.reason)
    config = configure(project, ranges, reading=Reading.OPEN)
    open_bmc = {r.assertion: r.verdict for r in check(config.project, core, ranges=ranges, timeout=30, config=config)}
    open_explicit = {r.assertion: r.verdict for r in check_explicit(config.project, core, 8, ranges, {}, 30, 10_000,
                                                                    config=config)}
    assert open_bmc == open_explicit == {a: "holds" for a in core}  # func1 any function


def test_loading_cases_count(capsys: pytest.CaptureFixture[str]) -> None:
    loading = sorted(c for c in cases(VALID) if isinstance(outcome(VALID / c), Project))
    with capsys.disabled():
        print(f"\n{len(loading)} of {len(cases(VALID))} robochart conformance cases load")
    assert len(loading) == len(EXPECTED_LOAD)
    assert set(loading) == EXPECTED_LOAD


def fail_reason(case: str, table: dict[str, str] = FAIL_REASONS) -> str:
    reasons = [reason for pattern, reason in table.items() if fnmatch.fnmatchcase(case, pattern)]
    assert len(reasons) == 1, f"record why {case} is invalid in FAIL_REASONS and FAIL_RULES"
    return reasons[0]


@pytest.mark.parametrize("case", INVALID_CASES)
def test_invalid_case(case: str) -> None:
    result = outcome(INVALID / case)
    assert isinstance(result, ModelError), f"{case} is invalid RoboChart but loads"
    errs = errors(result)
    real = [d for d in errs if not d.message.startswith("unsupported: ")]
    assert real, f"{case} is rejected only as unsupported:\n{describe(errs)}"
    assert_positions_in_files(errs)
    reason = fail_reason(case)
    assert any(reason in d.message for d in real), f"{case}: no error says {reason!r}:\n{describe(errs)}"


@pytest.mark.parametrize("case", INVALID_CASES)
def test_invalid_case_cites_robotool_s_rule(case: str) -> None:
    """Every error of a robochart-fail case cites the rule RoboTool refuses the model by."""
    result = outcome(INVALID / case)
    assert isinstance(result, ModelError)
    assert {d.rule for d in errors(result)} == {fail_rule(case)}, describe(errors(result))


def fail_rule(case: str) -> str:
    return fail_reason(case, FAIL_RULES)


def test_invalid_case_positions() -> None:
    """Spot checks: the error points at the offending element."""
    scope = errors(outcome(INVALID / "opcall-scope-fail"))  # type: ignore[arg-type]
    assert [(d.pos.line, d.pos.column) for d in scope] == [(9, 37)]
    assert scope[0].message.startswith("operation 'op' is not in scope")
    outside = errors(outcome(INVALID / "transitionsOutsideNodeContainer"))  # type: ignore[arg-type]
    assert [(d.pos.line, d.pos.column) for d in outside] == [(8, 24), (8, 30)]
    assert "'S0' is outside" in outside[0].message and "'S3' is outside" in outside[1].message


# -------------------------------------------------------------------- through the CLI (needs tockbmc/cli.py)


@pytest.mark.parametrize("case", INVALID_CASES)
def test_cli_rejects_invalid_case(case: str) -> None:
    result = run_cli(["show", str(INVALID / case)])
    assert result.crash is None, result.crash
    assert result.exit_code == 3, result.output
    assert "Traceback" not in result.output
    assert ": error: " in result.output
    assert fail_reason(case) in result.output
    assert f"[RoboTool rule {fail_rule(case)}]" in result.output


@pytest.mark.parametrize("case", ["Example1", "test1", "AsyncBuffers"])
def test_cli_shows_valid_case(case: str) -> None:
    result = run_cli(["show", str(VALID / case)])
    assert result.crash is None, result.crash
    assert result.exit_code == 0, result.output
    assert "Traceback" not in result.output


# -------------------------------------------------------------------- the public projects of shared/realworld

REALWORLD = SHARED / "realworld"
# The projects RoboTool refuses too, and the RoboTool rules their errors cite.
REALWORLD_REFUSED = {
    # its assertions name ctrl3, which no file declares
    "UoY-RoboStar+AURO/week_6/robochart/buffer-example": {"linking"},
    # a copy that names interfaces, machines and a platform left out of it: no module has a platform
    "laila-fangyan+RoboChart2Circus_2024/Test1": {"linking", "M1"},
}


def realworld_lines() -> list[object]:
    if not (REALWORLD / "PROJECTS.txt").is_file():
        return []
    return load_realworld().read_projects(REALWORLD / "PROJECTS.txt")  # type: ignore[no-any-return]


REALWORLD_LINES = realworld_lines()


def test_realworld_corpus_is_present() -> None:
    assert len(REALWORLD_LINES) >= 70, f"clone the shared/ directory beside the repository: {REALWORLD}"
    assert set(REALWORLD_REFUSED) <= {line.label for line in REALWORLD_LINES}  # type: ignore[attr-defined]


@pytest.mark.parametrize("line", REALWORLD_LINES, ids=lambda line: line.label)  # type: ignore[attr-defined]
def test_realworld_project_loads_unless_robotool_refuses_it(line: object) -> None:
    """Loading only, as benchmarks/realworld.py reads each line of PROJECTS.txt."""
    files = load_realworld().files_of(REALWORLD, line)
    label = line.label  # type: ignore[attr-defined]
    try:
        project = load(*files)
    except ModelError as exc:
        errs = errors(exc)
        assert label in REALWORLD_REFUSED, f"{label} does not load:\n{describe(errs)}"
        assert_positions_in_files(errs)
        assert {d.rule for d in errs} == REALWORLD_REFUSED[label], describe(errs)
        return
    assert label not in REALWORLD_REFUSED, f"{label} loads: remove it from REALWORLD_REFUSED"
    assert project.machines or project.controllers or project.modules or project.operations
