"""The three readings of a model (docs/semantics.md §6.6): RoboTool's instantiation by default,
FDR's finite check with `--robotool`, nothing filled in with `--open`; each decided by both engines."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.cli import cli
from tockbmc.explicit.engine import check_explicit
from tockbmc.model import ast
from tockbmc.model.config import configure
from tockbmc.model.contracts import placeholder_meets
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.readings import Reading
from tockbmc.model.result import Result
from tockbmc.report.html import render_report
from tockbmc.report.results import configuration

SMALL = Ranges({"core_int": Range(Fraction(-3), Fraction(3))})

# x, u and q start where the reading puts them; a state for each value the checks tell apart.
UNSET = """\
import sequence_toolkit::*
stm M {
  var x : int
  var q : boolean
  var s : Seq(int)
  initial i
  state s0 { entry x = x + 1 }
  state one {}
  state three {}
  state yes {}
  state empty {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to one condition x == 1 }
  transition t2 { from s0 to three condition x == 3 }
  transition t3 { from s0 to yes condition q }
  transition t4 { from s0 to empty condition size(s) == 0 }
}
"""
UNSET_ASSERTIONS = """\
assertion One: one is reachable in M.
assertion Three: three is reachable in M.
assertion Yes: yes is reachable in M.
assertion Empty: empty is reachable in M.
"""


def both(tmp_path: Path, files: dict[str, str], reading: Reading, ranges: Ranges = SMALL,
         bound: int = 12) -> tuple[dict[str, Result], dict[str, Result]]:
    """BMC's and the explicit engine's results, by assertion, in `reading`."""
    write_files(tmp_path, files)
    config = configure(tockbmc.load(tmp_path), ranges, reading=reading)
    bmc = {r.assertion: r for r in check(config.project, bound=bound, config=config, timeout=60)}
    explicit = {r.assertion: r for r in check_explicit(config.project, None, bound, ranges, {}, 60, 100_000,
                                                       config=config)}
    return bmc, explicit


def verdicts(results: dict[str, Result]) -> dict[str, str]:
    return {n: r.verdict.value for n, r in results.items()}


def test_a_variable_without_an_initial_value_starts_at_its_types_default(tmp_path: Path) -> None:
    """By default x starts at 0, q at true, s at <> (RoboTool's memory: `Memory_x(0)`), in both
    engines; each result lists those defaults with where they come from."""
    files = {"m.rct": UNSET, "m.assertions": UNSET_ASSERTIONS}
    bmc, explicit = both(tmp_path, files, Reading.DEFAULT, ranges=Ranges({**SMALL.by_type}, {"M::s": Range(Fraction(0), Fraction(1))}))
    expected = {"One": "holds", "Three": "violated", "Yes": "holds", "Empty": "holds"}
    assert verdicts(bmc) == expected and verdicts(explicit) == expected, [r.reason for r in bmc.values()]
    for r in (bmc["Three"], explicit["Three"]):
        assert r.reading == "default"
        assert r.defaults == {"M::x": "0", "M::q": "true", "M::s": "<>"}
        assert r.sources["defaults"]["M::x"].startswith("RoboTool default (") and "m.rct:3" in r.sources["defaults"]["M::x"]


def test_the_open_reading_starts_a_variable_without_an_initial_value_anywhere(tmp_path: Path) -> None:
    """With `--open`, x starts at any value of core_int: `three` is reachable, from the start 2
    the witness chose."""
    rct = UNSET.replace("  var s : Seq(int)\n", "").replace("  transition t4 { from s0 to empty condition size(s) == 0 }\n", "")
    files = {"m.rct": rct, "m.assertions": "assertion Three: three is reachable in M.\n"}
    bmc, explicit = both(tmp_path, files, Reading.OPEN)
    assert bmc["Three"].verdict == explicit["Three"].verdict == "holds", (bmc["Three"].reason, explicit["Three"].reason)
    assert bmc["Three"].reading == "open" and bmc["Three"].defaults == {}


FUNCTIONS = """\
function f(n : int) : int { }
function pos(n : int) : int {
  postcondition result >= 0
}
function bigger(n : int) : int {
  precondition n > 0
  postcondition result > n
}
function ok(n : int) : boolean { }
stm M {
  var x : int = 0
  initial i
  state s0 { entry x = f(x) + pos(x) }
  state zero {}
  state other {}
  state fine {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to zero condition x == 0 }
  transition t2 { from s0 to other condition x != 0 }
  transition t3 { from s0 to fine condition ok(x) }
}
"""
FUNCTIONS_ASSERTIONS = """\
assertion Zero: zero is reachable in M.
assertion Other: other is not reachable in M.
assertion Fine: fine is reachable in M.
"""


def test_a_function_without_a_body_is_robotools_placeholder_in_both_engines(tmp_path: Path) -> None:
    """f and pos are `0` (pos's placeholder meets `result >= 0`), ok is `true`; bigger's `0`
    contradicts `result > n`, so bigger stays any function meeting its contract, and says why. The
    explicit engine, which cannot apply a function nobody set, decides the model."""
    bmc, explicit = both(tmp_path, {"m.rct": FUNCTIONS, "m.assertions": FUNCTIONS_ASSERTIONS}, Reading.DEFAULT)
    expected = {"Zero": "holds", "Other": "holds", "Fine": "holds"}
    assert verdicts(bmc) == expected, [r.reason for r in bmc.values()]
    assert verdicts(explicit) == expected, [r.reason for r in explicit.values()]
    r = bmc["Other"]
    assert r.defaults == {"f": "0", "pos": "0", "ok": "true"}  # bigger is not called
    [kept] = [f for f in configure(tockbmc.load(tmp_path)).filled if f.name == "bigger"]
    assert kept.value == "" and "the placeholder 0 contradicts its postcondition" in kept.source


def test_the_open_reading_keeps_a_function_without_a_body_open(tmp_path: Path) -> None:
    """With `--open`, f is any function: `other is not reachable` is violated (f(0) + pos(0) may be
    other than 0), in both engines: the explicit engine chooses a function's value at a point where
    a run first reads it, among those its contract allows. A witness (`zero is reachable`) rests on
    the choice it made, and the claim needs every function: unknown in both."""
    bmc, explicit = both(tmp_path, {"m.rct": FUNCTIONS, "m.assertions": FUNCTIONS_ASSERTIONS}, Reading.OPEN)
    expected = {"Zero": "unknown", "Other": "violated", "Fine": "unknown"}
    assert verdicts(bmc) == verdicts(explicit) == expected, [r.reason for r in explicit.values()]
    assert "results of the functions without a body (f, ok, pos)" in (explicit["Zero"].reason or "")
    assert "states" in explicit["Other"].extra and "open points" not in explicit["Other"].extra


EVERY_CHOICE = """\
function f(n : int) : int { }
stm M {
  var x : int = 0
  initial i
  state s0 { entry x = f(x) }
  state read {}
  state positive {}
  final done
  transition t0 { from i to s0 }
  transition t1 { from s0 to read condition x > 0 \\/ x <= 0 }
  transition t2 { from read to positive condition x > 0 }
  transition t3 { from read to done condition x <= 0 }
  transition t4 { from positive to done }
}
"""
EVERY_CHOICE_ASSERTIONS = """\
assertion Read: read is reachable in M.
assertion Ends: M terminates.
assertion Positive: positive is reachable in M.
"""


def test_a_witness_that_stands_for_every_value_of_an_open_function_holds_in_the_open_reading(tmp_path: Path) -> None:
    """`read` is entered whatever f(0) is, and M terminates whatever it is: each witness reads f, yet
    every value it may have leads on to the target, so both engines decide them. `positive` is
    entered only where f(0) > 0: unknown in both, the claim needing every function."""
    bmc, explicit = both(tmp_path, {"m.rct": EVERY_CHOICE, "m.assertions": EVERY_CHOICE_ASSERTIONS}, Reading.OPEN)
    assert verdicts(explicit) == {"Read": "holds", "Ends": "holds", "Positive": "unknown"}, \
        [r.reason for r in explicit.values()]
    assert verdicts(bmc)["Read"] == "holds" and verdicts(bmc)["Positive"] == "unknown", [r.reason for r in bmc.values()]
    assert "results of the functions without a body (f)" in (explicit["Positive"].reason or "")


@pytest.mark.parametrize(("post", "meets"), [("result >= 0", True), ("result > n", False),
                                             ("result == 0 \\/ n < 0", True), ("result <= n * n", True),
                                             ("forall k : int @ result <= k * k", None)])
def test_a_placeholder_is_checked_against_the_postcondition_for_every_argument(
        tmp_path: Path, post: str, meets: bool | None) -> None:
    write_files(tmp_path, {"m.rct": f"function g(n : int) : int {{\n  postcondition {post}\n}}\n"
                                    "stm M { initial i state s {} transition t { from i to s } }\n"})
    [g] = tockbmc.load(tmp_path).functions
    assert placeholder_meets(g, ast.Literal(ast.NAT, g.pos, 0)) is meets


OVERFLOW = """\
stm M {
  var x : int = 2
  var y : int = -7
  var z : int = 0
  var r : real = 0
  event e : real
  initial i
  state s0 { entry x = x + 1 ; z = y / 2 }
  state three {}
  state two {}
  state truncated {}
  state half {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to three condition x == 3 }
  transition t2 { from s0 to two condition x == 2 }
  transition t3 { from s0 to truncated condition z == -3 }
  transition t4 { from s0 to half trigger e?r condition r > 0 /\\ r < 1 }
}
"""
OVERFLOW_ASSERTIONS = """\
assertion Three: three is reachable in M.
assertion Two: two is reachable in M.
assertion Truncated: truncated is reachable in M.
assertion Half: half is reachable in M.
"""


def test_robotool_reading_is_fdrs_bounded_arithmetic_over_integers(tmp_path: Path) -> None:
    """With `--robotool` (core_int=-2..2): `2 + 1` leaves the range and RoboTool's `Plus` keeps 2;
    `-7 / 2` rounds towards zero to -3 (-4 is not in the range either, so Div keeps -7 then:
    `truncated` is not reachable); a real input strictly between 0 and 1 is not an integer."""
    files = {"m.rct": OVERFLOW, "m.assertions": OVERFLOW_ASSERTIONS}
    bmc, explicit = both(tmp_path, files, Reading.ROBOTOOL, ranges=Ranges())
    expected = {"Three": "violated", "Two": "holds", "Truncated": "violated", "Half": "violated"}
    assert verdicts(bmc) == expected, [r.reason for r in bmc.values()]
    assert verdicts(explicit) == expected, [r.reason for r in explicit.values()]
    assert bmc["Two"].reading == "robotool" and bmc["Two"].ranges["core_int"] == "-2..2"
    assert any("core_clock_type" in n for n in bmc["Two"].not_reproduced)
    default, _ = both(tmp_path, files, Reading.DEFAULT, ranges=Ranges({"core_real": Range(Fraction(-2), Fraction(2))}))
    assert verdicts(default) == {"Three": "holds", "Two": "violated", "Truncated": "violated", "Half": "holds"}


def test_robotool_division_rounds_towards_zero_within_the_range(tmp_path: Path) -> None:
    """`-7 / 2` is -3 in FDR (towards zero), -4 in tockbmc's exact reading (Euclidean)."""
    files = {"m.rct": OVERFLOW, "m.assertions": OVERFLOW_ASSERTIONS}
    wide = Ranges({"core_int": Range(Fraction(-9), Fraction(9)), "core_real": Range(Fraction(-2), Fraction(2))})
    write_files(tmp_path, files)
    project = tockbmc.load(tmp_path)
    for reading, truncated in ((Reading.ROBOTOOL, "holds"), (Reading.DEFAULT, "violated")):
        config = configure(project, wide, reading=reading)
        [r] = check(config.project, ["Truncated"], bound=12, config=config, timeout=60)
        [e] = check_explicit(config.project, ["Truncated"], 12, wide, {}, 60, 100_000, config=config)
        assert r.verdict == e.verdict == truncated, (reading, r.reason, e.reason)


REAL_DIVISION = """\
stm M {
  var r : real
  var q : real
  event e : real
  initial i
  state wait {}
  state got { entry q = r / 2 }
  state half {}
  state minus {}
  transition t0 { from i to wait }
  transition t1 { from wait to got trigger e?r }
  transition t2 { from got to half condition q > 0 /\\ q < 1 }
  transition t3 { from got to minus condition q == -1 }
}
"""


def test_robotool_real_division_rounds_towards_zero_as_fdrs_integer_reals(tmp_path: Path) -> None:
    """FDR's reals are integers: `1 / 2` is 0 there, so `half` is not reachable with `--robotool`
    and is by default (exact reals); `-2 / 2` is -1 in both."""
    files = {"m.rct": REAL_DIVISION,
             "m.assertions": "assertion Half: half is reachable in M.\nassertion Minus: minus is reachable in M.\n"}
    robotool, robotool_explicit = both(tmp_path, files, Reading.ROBOTOOL, ranges=Ranges())
    assert verdicts(robotool) == verdicts(robotool_explicit) == {"Half": "violated", "Minus": "holds"}
    default, default_explicit = both(tmp_path, files, Reading.DEFAULT,
                                     ranges=Ranges({"core_real": Range(Fraction(-2), Fraction(2))}))
    assert verdicts(default) == {"Half": "holds", "Minus": "holds"}
    assert verdicts(default_explicit) == {"Half": "holds", "Minus": "holds"}


SHARED_REQUIRED = """\
interface I { var v : int }
stm R {
  requires I
  initial i
  state s {}
  state big {}
  transition t0 { from i to s }
  transition t1 { from s to big condition v > 1 }
}
"""


def test_a_variable_a_machine_checked_alone_requires_is_written_by_its_environment(tmp_path: Path) -> None:
    """The copy starts at the type's default, 0, and RoboTool's environment writes it at any time
    by `R::set_EXT_v`: `big` is reached through that event, in both engines."""
    bmc, explicit = both(tmp_path, {"m.rct": SHARED_REQUIRED, "m.assertions": "assertion B: big is reachable in R.\n"},
                         Reading.DEFAULT)
    assert bmc["B"].verdict == explicit["B"].verdict == "holds"
    for r in (bmc["B"], explicit["B"]):
        assert any((s.event or "").startswith("R::set_EXT_v.") for s in r.trace), [s.event for s in r.trace]


def test_the_readings_on_the_command_line(tmp_path: Path) -> None:
    """`--open` and `--robotool` exclude each other; the text and the JSON say the reading and the
    defaults; the JSON validates against schema version 2."""
    write_files(tmp_path, {"m.rct": UNSET, "m.assertions": "assertion Three: three is reachable in M.\n"})
    both_flags = CliRunner().invoke(cli, ["check", str(tmp_path), "--open", "--robotool", "-j", "1"])
    assert both_flags.exit_code == 2 and "exclude each other" in both_flags.output
    text = CliRunner().invoke(cli, ["check", str(tmp_path), "-j", "1"])
    assert text.exit_code == 10 and "reading: default;" in text.output and "M::x=0 [RoboTool default" in text.output
    opened = CliRunner().invoke(cli, ["check", str(tmp_path), "--open", "--format", "json", "-j", "1"])
    doc = json.loads(opened.output)
    assert doc["schema_version"] == 2 and doc["results"][0]["reading"] == "open"
    assert doc["results"][0]["verdict"] == "holds" and doc["results"][0]["defaults"] == {}
    robotool = CliRunner().invoke(cli, ["check", str(tmp_path), "--robotool", "--format", "json", "-j", "1"])
    [r] = json.loads(robotool.output)["results"]
    assert r["reading"] == "robotool" and r["ranges"]["core_int"] == "-2..2" and r["not_reproduced"]


def test_the_html_report_says_the_reading_and_the_defaults(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": UNSET, "m.assertions": "assertion Three: three is reachable in M.\n"})
    config = configure(tockbmc.load(tmp_path), SMALL)
    page = render_report(check(config.project, config=config, bound=10), title="m", version="0")
    assert "<dt>Reading</dt>" in page and "default: RoboTool&#39;s instantiation" in page
    assert "<code>M::x = 0</code>" in page


PLUS_SPEC = """\
stm M {
  var x : int = 2
  event o : int
  initial i
  state s { entry x = x + 1 ; o!x }
  transition t0 { from i to s }
}
"""
PLUS_ASSERTIONS = """\
timed csp Bounded csp-begin
Timed(OneStep) {
  Bounded = M::o.out!Plus(2, 1, core_int) -> STOP
}
csp-end
timed csp Three csp-begin
Timed(OneStep) {
  Three = M::o.out!3 -> STOP
}
csp-end
timed assertion A: M refines Bounded in the traces model.
timed assertion B: M refines Three in the traces model.
"""


def test_a_specifications_plus_is_robotools_bounded_arithmetic_with_robotool(tmp_path: Path) -> None:
    """RoboTool's `Plus(2, 1, core_int)` in a CSP block is 3 by default, as the model's `x + 1` is,
    and 2 with `--robotool`, as the model's is there: `A` holds in both readings, `B` (which
    expects 3) only by default."""
    write_files(tmp_path, {"m.rct": PLUS_SPEC, "m.assertions": PLUS_ASSERTIONS})
    project = tockbmc.load(tmp_path)
    for reading, b in ((Reading.DEFAULT, "holds"), (Reading.ROBOTOOL, "violated")):
        config = configure(project, reading=reading)
        found = {r.assertion: r.verdict.value for r in check(config.project, bound=12, config=config, timeout=60)}
        assert found == {"A": "holds", "B": b}, (reading, found)


REMAINDER = """\
stm M {
  var y : int = -1
  var q : int
  event e : int
  initial i
  state s { entry q = y % 2 ; e!q }
  transition t0 { from i to s }
}
"""
REMAINDER_ASSERTIONS = """\
timed csp SpecMod csp-begin
Timed(OneStep) {
  SpecMod = M::e.out!Modulus(-1, 2, core_int) -> STOP
}
csp-end
timed csp SpecPct csp-begin
Timed(OneStep) {
  SpecPct = M::e.out!((-1) % 2) -> STOP
}
csp-end
timed assertion A1: M refines SpecMod in the traces model.
timed assertion A2: M refines SpecPct in the traces model.
"""


def test_robotools_remainder_has_the_dividends_sign_in_the_model_and_in_csp(tmp_path: Path) -> None:
    """With `--robotool`, `-1 % 2` is -1 in the model (RoboTool's `Modulus`, FDR's `%`) and in the
    specification's `%` and `Modulus` alike: each refinement holds, in both engines."""
    bmc, explicit = both(tmp_path, {"m.rct": REMAINDER, "m.assertions": REMAINDER_ASSERTIONS}, Reading.ROBOTOOL,
                         ranges=Ranges())
    assert verdicts(bmc) == verdicts(explicit) == {"A1": "holds", "A2": "holds"}, [r.reason for r in bmc.values()]


def test_a_function_the_instantiation_defines_computes_exactly_with_robotool(tmp_path: Path) -> None:
    """`f(x) = x + 1` written in the project's instantiation is CSP the user wrote: RoboTool's
    bounded arithmetic is not put into it (f(2) is 3 although 3 is outside core_int=-2..2)."""
    rct = ("function f(x : int) : int { }\nstm M {\n  var a : int = 2\n  initial i\n  state s {}\n  state b {}\n"
           "  transition t0 { from i to s }\n  transition t1 { from s to b condition f(a) == 3 }\n}\n")
    assertions = "csp Instantiations csp-begin\nf(x) = x + 1\ncsp-end\nassertion R: b is reachable in M.\n"
    bmc, explicit = both(tmp_path, {"m.rct": rct, "m.assertions": assertions}, Reading.ROBOTOOL, ranges=Ranges())
    assert bmc["R"].verdict == explicit["R"].verdict == "holds", (bmc["R"].reason, explicit["R"].reason)
    assert "f" not in bmc["R"].defaults


def test_a_generic_functions_copy_for_a_call_gets_the_placeholder(tmp_path: Path) -> None:
    """`gsize(s : Set(?X)) : nat` called on a `Set(int)` is checked as its copy `gsize[?X=int]`,
    which gets RoboTool's placeholder 0 (RoboTool's `card(A) = 0`); one whose result type is generic
    stays open, listed with why."""
    rct = ("import set_toolkit::*\nfunction gsize(s : Set(?X)) : nat { }\nfunction gid(x : ?X) : ?X { }\n"
           "stm M {\n  var a : int = 1\n  initial i\n  state s {}\n  state b {}\n  state c {}\n"
           "  transition t0 { from i to s }\n  transition t1 { from s to b condition gsize({a}) == 5 }\n"
           "  transition t2 { from s to c condition gid(a) == 7 }\n}\n")
    write_files(tmp_path, {"m.rct": rct, "m.assertions": "assertion NB: b is not reachable in M.\n"})
    config = configure(tockbmc.load(tmp_path))
    [r] = check(config.project, bound=10, config=config, timeout=60)
    assert r.verdict == "holds", r.reason
    assert r.defaults["gsize[?X=int]"] == "0" and r.defaults["gid[?X=int]"] == ""
    assert "generic result type" in r.sources["defaults"]["gid[?X=int]"]


OPERATION_REQUIRES = """\
interface RV { var x : int }
interface IE { event out : int }
interface Ops { op() }
operation op() {
  requires RV
  uses IE
  var c : int
  initial i
  final f
  transition t0 { from i to f action out!x ; out!c ; x = x + 1 }
}
stm M {
  uses IE
  requires Ops
  var x : int = 1
  initial I
  state A {}
  state B {}
  transition t0 { from I to A action op() }
  transition t1 { from A to B action op() }
}
controller C {
  uses IE
  sref m = M
  opref o = op
  connection m on out to C on out
}
"""


def test_a_required_variable_the_caller_declares_is_not_listed_as_a_default(tmp_path: Path) -> None:
    """op reads the x its caller M declares (= 1), so RV's x is no default the verdict rests on;
    op's own c, reset to 0 at each call, is. C outputs 1, 0, 2, 0 in both engines."""
    assertions = ("timed csp Spec csp-begin\nTimed(OneStep) {\nSpec = C::out.out!1 -> C::out.out!0 -> C::out.out!2 "
                  "-> C::out.out!0 -> STOP\n}\ncsp-end\ntimed assertion A: C refines Spec in the traces model.\n")
    bmc, explicit = both(tmp_path, {"m.rct": OPERATION_REQUIRES, "m.assertions": assertions}, Reading.DEFAULT)
    assert bmc["A"].verdict == explicit["A"].verdict == "holds", (bmc["A"].reason, explicit["A"].reason)
    assert bmc["A"].defaults == {"op::c": "0"}


def test_a_range_on_an_initial_value_the_reading_fills_in_is_warned_of(tmp_path: Path) -> None:
    """`--range M::x=2..2` bounds x's initial value only where x starts anywhere (`--open`); by default
    x starts at 0 and the range bounds nothing: a warning with the declaration's line says so."""
    write_files(tmp_path, {"m.rct": UNSET, "m.assertions": "assertion Three: three is reachable in M.\n"})
    project = tockbmc.load(tmp_path)
    config = configure(project, {"M::x": Range(Fraction(2), Fraction(2))})
    [w] = config.warnings
    assert "--range M::x has no effect in the default reading" in w.message and w.pos.line == 3
    assert not configure(project, {"M::x": Range(Fraction(2), Fraction(2))}, reading=Reading.OPEN).warnings


def test_the_html_report_lists_what_robotool_does_not_reproduce(tmp_path: Path) -> None:
    write_files(tmp_path, {"m.rct": UNSET, "m.assertions": "assertion Three: three is reachable in M.\n"})
    config = configure(tockbmc.load(tmp_path), reading=Reading.ROBOTOOL)
    page = render_report(check(config.project, config=config, bound=10), title="m", version="0")
    assert "not reproduced: " in page and "core_clock_type" in page


TERMINATES = """\
interface E { event a }
stm M {
  uses E
  initial i
  state s {}
  final f
  transition t0 { from i to s }
  transition t1 { from s to f trigger a }
}
"""


def test_robotool_reading_checks_an_unprefixed_assertion_in_both_semantics(tmp_path: Path) -> None:
    """Termination is a deadlock in RoboTool's untimed semantics and not in its timed one: the
    unprefixed assertion holds in the default reading (timed only) and is violated with `--robotool`,
    which checks it in both, as RoboTool does; timelock-freedom RoboTool generates timed only."""
    files = {"m.rct": TERMINATES,
             "m.assertions": "assertion D: M is deadlock-free.\nassertion T: M is timelock-free.\n"}
    default, default_explicit = both(tmp_path, files, Reading.DEFAULT)
    assert verdicts(default) == verdicts(default_explicit) == {"D": "holds", "T": "violated"}
    robotool, robotool_explicit = both(tmp_path, files, Reading.ROBOTOOL, ranges=Ranges())
    assert verdicts(robotool) == verdicts(robotool_explicit) == {"D": "violated", "T": "violated"}
    for results in (robotool, robotool_explicit):
        assert results["D"].extra["semantics"] == {"untimed": "violated"}  # checked first, it settles it
        assert "in the untimed semantics" in (results["D"].reason or "")
        assert results["T"].extra["semantics"] == {"timed": "violated"}
    assert [s.event for s in robotool["D"].trace if s.event] == ["M::a.in", "M::terminate"]


CONTRACTS = """\
function pos(n : int) : int {
  postcondition result >= 0
}
function bigger(n : int) : int {
  precondition n > 0
  postcondition result > n
}
stm M {
  var x : int = 0
  var y : int = 0
  var z : int = 0
  initial i
  state s0 { entry x = pos(1) ; y = bigger(1) ; z = bigger(0) }
  state neg {}
  state small {}
  state any {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to neg condition x < 0 }
  transition t2 { from s0 to small condition y <= 1 }
  transition t3 { from s0 to any condition z < 0 }
}
"""
CONTRACTS_ASSERTIONS = """\
assertion Neg: neg is not reachable in M.
assertion Small: small is not reachable in M.
assertion Any: any is not reachable in M.
"""


def test_the_open_reading_chooses_only_what_a_functions_contract_allows(tmp_path: Path) -> None:
    """pos(1) is never negative, bigger(1) is above 1; bigger(0), outside its precondition, may be
    anything (docs/semantics.md §6.4): both engines agree, the explicit engine choosing each value
    where a run reads it."""
    bmc, explicit = both(tmp_path, {"m.rct": CONTRACTS, "m.assertions": CONTRACTS_ASSERTIONS}, Reading.OPEN)
    expected = {"Neg": "holds", "Small": "holds", "Any": "violated"}
    assert verdicts(bmc) == expected, [r.reason for r in bmc.values()]
    assert verdicts(explicit) == expected, [r.reason for r in explicit.values()]


NO_VALUE_ALLOWED = """\
function f(n : int) : int {
  postcondition result > 10
}
function g(n : int) : boolean { }
stm M {
  initial i
  state s0 {}
  state s1 {}
  state target {}
  transition t0 { from i to s0 }
  transition t1 { from s0 to target condition g(0) }
  transition t2 { from s0 to s1 condition not g(0) }
  transition t3 { from s1 to target condition f(0) == 0 }
}
"""


def test_a_point_where_no_value_meets_the_contract_is_no_way_to_the_target(tmp_path: Path) -> None:
    """Within core_int=-2..2 no value of f(0) meets `result > 10`: that branch reaches nothing, and with
    g(0) false no run enters target (f(0) = 11, say): the witness stands for some functions only."""
    write_files(tmp_path, {"m.rct": NO_VALUE_ALLOWED, "m.assertions": "assertion T: target is reachable in M.\n"})
    config = configure(tockbmc.load(tmp_path), Ranges({"core_int": Range(Fraction(-2), Fraction(2))}),
                       reading=Reading.OPEN)
    [r] = check_explicit(config.project, None, 8, config.ranges(), {}, 60, 100_000, config=config)
    assert r.verdict == "unknown", r.reason


# `get` supplies a sequence: `two` needs one of length 2, `three` one of length 3.
SEQUENCE_INPUT = """\
import sequence_toolkit::*
interface I { event get : Seq(int) }
stm M {
  uses I
  var s : Seq(int)
  initial i
  state w {}
  state two {}
  state three {}
  transition t0 { from i to w }
  transition t1 { from w to two trigger get?s condition size(s) == 2 }
  transition t2 { from w to three trigger get?s condition size(s) == 3 }
}
"""
SEQUENCE_ASSERTIONS = """\
assertion Two: two is not reachable in M.
assertion Three: three is not reachable in M.
"""
LSEQ_SOURCE = "RoboTool's LSeq(T,2) (docs/robotool-evidence.md §9.5)"


def test_robotool_gives_a_sequence_input_lengths_up_to_two_in_both_engines(tmp_path: Path) -> None:
    """With `--robotool` the input on `get` is RoboTool's `LSeq(int,2)`: a length-2 input reaches
    `two` in both engines, no length-3 input exists, so `three` is never entered; each result
    lists the default length with its source, and what FDR does with a longer computed sequence
    as not reproduced."""
    bmc, explicit = both(tmp_path, {"m.rct": SEQUENCE_INPUT, "m.assertions": SEQUENCE_ASSERTIONS}, Reading.ROBOTOOL,
                         ranges=Ranges())
    expected = {"Two": "violated", "Three": "holds"}
    assert verdicts(bmc) == expected, [r.reason for r in bmc.values()]
    assert verdicts(explicit) == expected, [r.reason for r in explicit.values()]
    for results in (bmc, explicit):
        inputs = [s.event for s in results["Two"].trace if (s.event or "").startswith("M::get.in.")]
        assert len(inputs) == 1 and inputs[0].count(",") == 1, inputs  # `M::get.in.<a, b>`
        for r in results.values():
            assert r.ranges["sequence input length"] == "0..2"
            assert r.sources["ranges"]["sequence input length"] == LSEQ_SOURCE
            assert f"sequence input length=0..2 [{LSEQ_SOURCE}]" in configuration(r)
            assert any("LSeq(T,2)" in n for n in r.not_reproduced)
    page = render_report(list(bmc.values()), title="m", version="0")
    assert "<code>sequence input length = 0..2</code> [RoboTool&#39;s LSeq(T,2) (docs/robotool-evidence.md §9.5)]" in page


def test_a_range_on_a_sequence_inputs_path_wins_over_robotools_length(tmp_path: Path) -> None:
    """`--range M::get=0..3` lets the input be of length 3: `three` is entered with `--robotool`, in
    both engines, by a length-3 input."""
    ranges = Ranges(by_path={"M::get": Range(Fraction(0), Fraction(3))})
    bmc, explicit = both(tmp_path, {"m.rct": SEQUENCE_INPUT, "m.assertions": SEQUENCE_ASSERTIONS}, Reading.ROBOTOOL,
                         ranges=ranges)
    assert verdicts(bmc) == verdicts(explicit) == {"Two": "violated", "Three": "violated"}
    for r in (bmc["Three"], explicit["Three"]):
        assert r.ranges["M::get"] == "0..3" and r.sources["ranges"]["M::get"] == "--range"
        assert [s.event.count(",") for s in r.trace if (s.event or "").startswith("M::get.in.")] == [2]


def test_robotools_length_bounds_a_records_sequence_field_and_a_shared_sequence(tmp_path: Path) -> None:
    """The default length bounds a sequence inside an input (a record's field, `M::get.items`) and
    the environment's writes of a shared sequence variable (`R::set_EXT_v`), alike in both engines."""
    record = SEQUENCE_INPUT.replace("interface I { event get : Seq(int) }",
                                    "datatype Reading { items : Seq(boolean) n : nat }\n"
                                    "interface I { event get : Reading }")
    record = record.replace("var s : Seq(int)", "var s : Reading").replace("size(s)", "size(s.items)")
    shared = """\
import sequence_toolkit::*
interface I { var v : Seq(boolean) }
stm R {
  requires I
  initial i
  state w {}
  state two {}
  state three {}
  transition t0 { from i to w }
  transition t1 { from w to two condition size(v) == 2 }
  transition t2 { from w to three condition size(v) == 3 }
}
"""
    for rct, name in ((record, "M"), (shared, "R")):
        assertions = SEQUENCE_ASSERTIONS.replace(" M.", f" {name}.")
        bmc, explicit = both(tmp_path / name, {"m.rct": rct, "m.assertions": assertions}, Reading.ROBOTOOL,
                             ranges=Ranges())
        assert verdicts(bmc) == verdicts(explicit) == {"Two": "violated", "Three": "holds"}, name
        assert bmc["Three"].ranges["sequence input length"] == "0..2"


def test_robotools_length_is_listed_only_where_the_element_has_a_sequence_input(tmp_path: Path) -> None:
    """UNSET's `s : Seq(int)` is the machine's own variable, never supplied by the environment: no
    result on it lists the default length."""
    bmc, explicit = both(tmp_path, {"m.rct": UNSET, "m.assertions": UNSET_ASSERTIONS}, Reading.ROBOTOOL, ranges=Ranges())
    for r in (*bmc.values(), *explicit.values()):
        assert "sequence input length" not in r.ranges and "sequence input length" not in r.sources["ranges"]


def test_the_default_reading_asks_for_the_length_of_a_sequence_input_by_its_path(tmp_path: Path) -> None:
    """Without `--robotool` the input's length has no default: the explicit engine asks for a range
    on `M::get`, and BMC, over unbounded lengths, enters `three`; no result lists a default length."""
    write_files(tmp_path, {"m.rct": SEQUENCE_INPUT, "m.assertions": SEQUENCE_ASSERTIONS})
    explicit = CliRunner().invoke(cli, ["check", str(tmp_path), "--engine", "explicit", "--range", "core_int=-2..2",
                                        "-j", "1"])
    assert explicit.exit_code == 2, explicit.output
    assert "give a range for M::get (its length: --range M::get=LO..HI)" in explicit.output
    bmc = CliRunner().invoke(cli, ["check", str(tmp_path), "--engine", "bmc", "--format", "json", "-j", "1"])
    results = {r["assertion"]: r for r in json.loads(bmc.output)["results"]}
    assert {n: r["verdict"] for n, r in results.items()} == {"Two": "violated", "Three": "violated"}
    assert all("sequence input length" not in r["ranges"] for r in results.values())
