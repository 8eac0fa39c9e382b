"""Mangled input never crashes the loader or the CLI.

Hypothesis mutates the IntelliWelder example (truncation, splicing, deletion,
character and token replacement); whatever comes out, `load` returns a
`Project` or raises `ModelError` whose diagnostics point into the files, and
`tockbmc show` exits 0 or 3 without a traceback.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from conftest import EXAMPLE, run_cli, write_files
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tockbmc import ModelError, Project, load
from tockbmc.model.limits import MAX_NESTING

RCT = (EXAMPLE / "intelliwelder.rct").read_text(encoding="utf-8")
ASSERTIONS = (EXAMPLE / "intelliwelder.assertions").read_text(encoding="utf-8")
SOURCES = {"intelliwelder.rct": RCT, "intelliwelder.assertions": ASSERTIONS}

TOKENS = ["{", "}", "(", ")", ";", "::", "=", "?", "!", "state", "transition", ".", ",", ":", "#", "<{", "(|", "|)",
          "[|", "|]", "/\\", "\\/", "not", "-", "==", "initial", "final", "junction", "from", "to", "trigger",
          "condition", "action", "entry", "stm", "sref", "connection", "on", "event", "var", "const", "if", "then",
          "else", "end", "true", "wait", "since", "csp-begin", "csp-end", "assertion", "refines", "terminates",
          "does", "EXAX", "System", "SystemState::working", "\"", "/*", "*/", "//", "\n", "\t", "\u00e9", "\x00"]
DIGITS = st.from_regex(r"-?[0-9]{1,12}(\.[0-9]{1,4})?", fullmatch=True)
IDENTIFIERS = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,12}", fullmatch=True)
REPLACEMENTS = st.one_of(st.sampled_from(TOKENS), DIGITS, IDENTIFIERS, st.characters(codec="utf-8"))

MUTATION = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def positions(draw: st.DrawFn, text: str) -> int:
    return draw(st.integers(0, len(text)))


@st.composite
def truncated(draw: st.DrawFn, text: str) -> str:
    return text[: draw(positions(text))]


@st.composite
def spliced(draw: st.DrawFn, text: str) -> str:
    """A slice of the text copied to another position."""
    start = draw(positions(text))
    end = draw(st.integers(start, min(len(text), start + 400)))
    at = draw(positions(text))
    return text[:at] + text[start:end] + text[at:]


@st.composite
def deleted(draw: st.DrawFn, text: str) -> str:
    start = draw(positions(text))
    end = draw(st.integers(start, min(len(text), start + 400)))
    return text[:start] + text[end:]


@st.composite
def replaced(draw: st.DrawFn, text: str) -> str:
    """Characters, or whole words, replaced by tokens, numbers or names."""
    if draw(st.booleans()):
        chars = list(text)
        for _ in range(draw(st.integers(1, 6))):
            chars[draw(st.integers(0, len(chars) - 1))] = draw(REPLACEMENTS)
        return "".join(chars)
    words = text.split(" ")
    for _ in range(draw(st.integers(1, 4))):
        words[draw(st.integers(0, len(words) - 1))] = draw(REPLACEMENTS)
    return " ".join(words)


def mutated_project(mutation: st.SearchStrategy[str] | None = None) -> st.SearchStrategy[dict[str, str]]:
    """The example with one of its two files mutated (by `mutation`, or by any kind)."""
    kinds = [truncated, spliced, deleted, replaced] if mutation is None else [mutation]

    @st.composite
    def project(draw: st.DrawFn) -> dict[str, str]:
        name = draw(st.sampled_from(sorted(SOURCES)))
        kind = draw(st.sampled_from(kinds))
        return {**SOURCES, name: draw(kind(SOURCES[name]))}

    return project()


def check_load(files: dict[str, str]) -> Project | ModelError:
    """Load the files; any outcome but a Project or a well-formed ModelError fails the test."""
    with tempfile.TemporaryDirectory() as tmp:
        directory = write_files(Path(tmp), files)
        try:
            return load(directory)
        except ModelError as exc:
            assert exc.diagnostics, "a ModelError without diagnostics"
            assert any(d.severity == "error" for d in exc.diagnostics)
            for d in exc.diagnostics:
                name = Path(d.pos.path).name
                assert name in files, d
                assert 1 <= d.pos.line <= files[name].count("\n") + 1, d
                assert d.pos.column >= 1, d
                assert d.message and str(d)
            return exc


@MUTATION
@given(mutated_project(truncated))
def test_truncated(files: dict[str, str]) -> None:
    check_load(files)


@MUTATION
@given(mutated_project(spliced))
def test_spliced(files: dict[str, str]) -> None:
    check_load(files)


@MUTATION
@given(mutated_project(deleted))
def test_deleted(files: dict[str, str]) -> None:
    check_load(files)


@MUTATION
@given(mutated_project(replaced))
def test_replaced(files: dict[str, str]) -> None:
    check_load(files)


def test_unmutated_example_loads() -> None:
    assert isinstance(check_load(SOURCES), Project)


def test_truncation_gives_a_syntax_error_at_the_end() -> None:
    cut = RCT[: RCT.index("stm UR {") + len("stm UR {")]
    result = check_load({**SOURCES, "intelliwelder.rct": cut})
    assert isinstance(result, ModelError)
    syntax = [d for d in result.diagnostics if d.message.startswith("syntax error")]
    assert len(syntax) == 1
    assert syntax[0].message.startswith("syntax error: unexpected end of file")
    assert syntax[0].pos.line == cut.count("\n") + 1


# -------------------------------------------------------------------- the CLI (needs tockbmc/cli.py)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_project())
def test_cli_on_mutants(files: dict[str, str]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        directory = write_files(Path(tmp), files)
        for args in (["show", str(directory)], ["show", str(directory), "--format", "json"]):
            result = run_cli(args)
            assert result.crash is None, result.crash
            assert result.exit_code in (0, 3), result.output
            assert "Traceback" not in result.output


# -------------------------------------------------------------------- deep nesting

DEEP = "stm M {{\n  var x : int = {}\n  initial i\n  state s {{}}\n  transition t0 {{ from i to s }}\n}}\n"
TOO_DEEP = f"nested too deeply: more than {MAX_NESTING} levels of states, statements and expressions"


def deep_outcome(expression: str) -> Project | ModelError:
    result = check_load({"m.rct": DEEP.format(expression)})
    if isinstance(result, ModelError):
        assert [(d.pos.line, d.message) for d in result.diagnostics] == [(2, TOO_DEEP)]
    return result


def test_5000_nested_parentheses() -> None:
    result = deep_outcome("(" * 5000 + "1" + ")" * 5000)
    if isinstance(result, Project):
        (x,) = result.machines[0].variables
        assert x.initial is not None and getattr(x.initial, "value", None) == 1


def test_100000_term_sum() -> None:
    """A flat sum nests as deep as it is long (left-associative): past the limit, a diagnostic."""
    assert isinstance(deep_outcome("+".join(["1"] * 100_000)), ModelError)


def test_deeply_nested_statements_and_states() -> None:
    statements = "stm M {\n  initial i\n  state s { entry " + "if true then " * 3000 + "skip" + " end" * 3000 \
        + " }\n  transition t0 { from i to s }\n}\n"
    states = "stm M {\n  initial i\n" + "  state s {\n  initial i\n" * 3000 + "}\n" * 3000 \
        + "  transition t0 { from i to s }\n}\n"
    for text in (statements, states):
        result = check_load({"m.rct": text})
        assert isinstance(result, ModelError)
        assert [d.message for d in result.diagnostics] == [TOO_DEEP]


def test_cli_on_deep_nesting(tmp_path: Path) -> None:
    """Needs tockbmc/cli.py."""
    write_files(tmp_path, {"m.rct": DEEP.format("(" * 5000 + "1" + ")" * 5000)})
    result = run_cli(["show", str(tmp_path)])
    assert result.crash is None, result.crash
    assert result.exit_code in (0, 3), result.output
    assert "Traceback" not in result.output


def test_sums_load_up_to_the_nesting_limit() -> None:
    """A 480-term sum loads; a 1000-term one is nested deeper than `MAX_NESTING` (README, "Limits")."""
    assert isinstance(check_load({"m.rct": DEEP.format("+".join(["1"] * 480))}), Project)
    assert isinstance(deep_outcome("+".join(["1"] * 1000)), ModelError)


def test_a_real_with_a_huge_power_of_two_denominator_is_written_as_a_fraction() -> None:
    """The differential benchmark hung in a worker (2.4 GB, minutes) writing a real whose
    denominator was a huge power of two as an exact decimal, one digit per halving: a decimal with
    more than 64 places beyond its denominator's digits is written as the fraction it is."""
    from fractions import Fraction

    from tockbmc.model.numbers import real_text

    assert real_text(Fraction(3, 4)) == "0.75" and real_text(Fraction(-5, 2)) == "-2.5"
    assert real_text(Fraction(1, 2**64)) == "0." + str(5**64).rjust(64, "0")
    assert real_text(Fraction(1, 2**200)) == f"1/{2**200}"
    assert real_text(Fraction(1, 10**400)) == "0." + "0" * 399 + "1"
    assert real_text(Fraction(1, 2**200_000)).startswith("1/")


def test_a_long_sequence_is_written_with_its_count() -> None:
    """A differential worker hung writing a sequence value item by item (each integer's text
    computed 10**1000 to decide how to write it): 32 items are written, then the count."""
    from tockbmc.model import ast
    from tockbmc.model.data import text_of

    text = text_of(ast.SeqType(ast.INT), tuple(range(10**6)))
    assert text.endswith(", 31, … (1000000 in all)>") and len(text) < 200
    assert text_of(ast.SetType(ast.INT), frozenset({2, 1})) == "{1, 2}"
