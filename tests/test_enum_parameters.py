"""Enumerations whose literals take parameters (`EM2(real)`): an algebraic datatype in
Z3 for BMC, `Variant` values in the interpreter; both engines decide them and agree, BMC's
counterexamples are replayed, and misuse is a load error with its position."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import both_engines, write_files

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.model import ast
from tockbmc.model.config import ConfigError, configure
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

MODEL = """\
enumeration EM {
  EM1
  EM2(real)
  EM3(nat)
}
interface I { event out : EM event inp : EM }
stm S {
  uses I
  var o : EM = EM3(1)
  var p : EM = EM1
  initial i0
  state s0 { }
  state s1 { }
  transition t0 { from i0 to s0 action out!o ; out!EM2(2) }
  transition t1 { from s0 to s0 trigger inp?p condition p != EM3(0) /\\ p != EM2(1) action out!p }
  transition t2 { from s0 to s1 condition p == EM3(2) }
}
"""
ASSERTIONS = """\
assertion R1: S::s1 is not reachable in S.
assertion D1: S is deadlock-free.
assertion T1: S does not terminate.
"""


def _project(tmp_path: Path) -> Project:
    return load(write_files(tmp_path / "m", {"m.rct": MODEL, "m.assertions": ASSERTIONS}))


def _ranges(nat_high: int) -> Ranges:
    return Ranges({"core_nat": Range(Fraction(0), Fraction(nat_high)), "core_real": Range(Fraction(0), Fraction(1))})


def test_a_literal_received_with_its_argument_is_shown_and_replayed(tmp_path: Path) -> None:
    """s1 is entered once `inp` brings EM3(2): the only input that makes t2's condition true."""
    project = _project(tmp_path)
    bmc, explicit = both_engines(project, _ranges(2), 20)
    assert {r.assertion: r.verdict for r in bmc} == {r.assertion: r.verdict for r in explicit} == {
        "R1": Verdict.VIOLATED, "D1": Verdict.VIOLATED, "T1": Verdict.HOLDS}
    reach = next(r for r in bmc if r.assertion == "R1")
    events = [s.event for s in reach.trace if s.kind == "event"]
    assert events == ["S::out.out.EM::EM3(1)", "S::out.out.EM::EM2(2)", "S::inp.in.EM::EM3(2)",
                      "S::out.out.EM::EM3(2)"]
    assert reach.extra["replayed"] == "yes"
    changed = {k: v for s in reach.trace for k, v in s.changed.items()}
    assert changed["S.p"] == "EM::EM3(2)"


def test_a_parameter_s_range_bounds_what_may_come_in(tmp_path: Path) -> None:
    """With naturals in 0..1, EM3(2) cannot come in, so s1 is never entered: both engines say so."""
    project = _project(tmp_path)
    bmc, explicit = both_engines(project, _ranges(1), 20)
    assert {r.assertion: r.verdict for r in bmc} == {r.assertion: r.verdict for r in explicit}
    assert {r.assertion: r.verdict for r in bmc}["R1"] == Verdict.HOLDS


def test_unbounded_parameters_in_bmc(tmp_path: Path) -> None:
    """Without ranges, BMC still finds the one value that enters s1."""
    project = _project(tmp_path)
    [reach] = check(project, ["R1"], bound=20)
    assert reach.verdict == Verdict.VIOLATED
    assert any(s.event == "S::inp.in.EM::EM3(2)" for s in reach.trace)


@pytest.mark.parametrize("expr, message", [
    ("EM3", "'EM3' takes 1 argument(s) (nat): write EM3(…)"),
    ("EM3(true)", "type error: argument '1' of 'EM3' must be nat, but this is boolean"),
    ("EM3(1, 2)", "'EM3' takes 1 argument(s), but 2 given"),
    ("EM1(1)", "unsupported: arguments given to 'EM1', an enumeration literal without parameters"),
])
def test_misused_literals_are_load_errors(tmp_path: Path, expr: str, message: str) -> None:
    model = MODEL.replace("var o : EM = EM3(1)", f"var o : EM = {expr}")
    with pytest.raises(ModelError) as info:
        load(write_files(tmp_path / "m", {"m.rct": model}))
    assert any(d.message == message and d.pos.line == 9 for d in info.value.diagnostics), \
        [d.message for d in info.value.diagnostics]


def test_a_literal_without_parameters_called_with_none_is_the_literal_with_a_warning(tmp_path: Path) -> None:
    """`EM1()`: RoboTool warns (ParameterlessConstructorWithCall) and reads EM1; so does tockbmc."""
    model = MODEL.replace("var o : EM = EM3(1)", "var o : EM = EM1()")
    project = load(write_files(tmp_path / "m", {"m.rct": model}))
    [warning] = [d for d in project.warnings if "EM1" in d.message]
    assert warning.severity == "warning" and warning.pos.line == 9
    [o] = [v for m in project.machines for v in m.variables if v.name == "o"]
    assert isinstance(o.initial, ast.EnumLiteral) and o.initial.literal == "EM1"


def test_a_constant_cannot_be_set_to_a_literal_with_parameters(tmp_path: Path) -> None:
    model = MODEL.replace("var o : EM = EM3(1)", "const c : EM\n  var o : EM = c")
    project = load(write_files(tmp_path / "m", {"m.rct": model}))
    with pytest.raises(ConfigError, match="literal EM3 has parameters"):
        configure(project, Ranges(), settings={"c": "EM3"})


def test_a_range_path_names_one_literal_s_argument(tmp_path: Path) -> None:
    """`--range S::inp.EM3.1=0..1` bounds the argument of EM3 coming in on inp, in both engines;
    a literal without parameters, or an argument number out of place, is a usage error."""
    project = _project(tmp_path)
    ranges = Ranges({**_ranges(2).by_type, "S::inp.EM3.1": Range(Fraction(0), Fraction(1))})
    bmc, explicit = both_engines(project, ranges, 20)
    assert {r.assertion: r.verdict for r in bmc}["R1"] == {r.assertion: r.verdict for r in explicit}["R1"] \
        == Verdict.HOLDS
    for path, message in (("S::inp.EM1.1", "no literal 'EM1' with parameters"),
                          ("S::inp.EM3.2", "needs the number of an argument of EM3, 1 to 1")):
        with pytest.raises(ConfigError, match=message):
            configure(project, Ranges({path: Range(Fraction(0), Fraction(1))}))


def test_a_specification_cannot_pass_on_such_a_value(tmp_path: Path) -> None:
    """A specification that receives a value of such an enumeration and sends it back
    (`inp.in?x -> out.out!x`) would need RoboTool's CSP spelling of the values: `unsupported`, never
    a verdict from comparing values the two sides write differently."""
    spec = """\
timed csp Echo csp-begin
  Echo = S::out.out?x -> Echo [] S::inp.in?x -> S::out.out!x -> Echo [] tock -> Echo
csp-end
assertion E: S refines Echo in the traces model.
"""
    project = load(write_files(tmp_path / "m", {"m.rct": MODEL, "m.assertions": spec}))
    [r] = check(project, bound=12, ranges=_ranges(1))
    assert r.verdict in (Verdict.UNSUPPORTED, Verdict.UNKNOWN), (r.verdict, r.reason)


def test_a_literal_with_parameters_beside_an_imported_toolkit(tmp_path: Path) -> None:
    """With a toolkit imported, `EM3(1)` is still the literal, not an unknown toolkit function (the
    differential's `--enums --data` cases import one)."""
    project = load(write_files(tmp_path / "m", {"m.rct": "import sequence_toolkit::*\n" + MODEL}))
    [machine] = project.machines
    assert {v.name: str(v.initial.args[0].value) for v in machine.variables if v.name == "o"} == {"o": "1"}
