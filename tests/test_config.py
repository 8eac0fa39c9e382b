"""Where ranges and constants come from: RoboTool's instantiation, the command line, the defaults.

One resolution (`tockbmc/model/config.py`) serves BMC and the interpreter: names given on the
command line are resolved against the model (usage errors, with "did you mean", otherwise);
`instantiations.csp` and `Instantiations` blocks are read as RoboTool reads them.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from conftest import CONFORMANCE, EXAMPLE, run_cli, write_files

import tockbmc
from tockbmc.check import check
from tockbmc.model.config import ConfigError, configure
from tockbmc.model.instantiation import read

# A machine whose termination depends on its constant p, an enumeration constant, a function
# without a body and a given type.
RCT = """
type Speed
enumeration Mode { Slow Fast }
datatype Pair { a : int  b : int }
function sign(x : int) : int { }
function idle(m : Mode) : nat { }
stm M {
  const p : int
  const mode : Mode
  const pair : Pair
  const limit : nat = 3
  var s : Speed
  var x : int
  event e : int
  initial i
  state w {}
  final f
  transition t0 { from i to w }
  transition t1 { from w to f trigger e?x condition p == 1 /\\ sign(x) == 1 }
}
stm N {
  const p : int
  initial i
  state w {}
  transition t0 { from i to w }
}
"""
ASSERTIONS = "assertion T: M does not terminate.\n"


def project(tmp_path: Path, instantiations: str | None = None, where: str = "instantiations.csp",
            assertions: str = ASSERTIONS) -> tockbmc.Project:
    files = {"m.rct": RCT, "m.assertions": assertions}
    if instantiations is not None:
        (tmp_path / where).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / where).write_text(instantiations)
    return tockbmc.load(write_files(tmp_path, files))


def messages(config: object) -> list[str]:
    return [f"{w.pos.line}: {w.message}" for w in config.warnings]  # type: ignore[attr-defined]


# ---------------------------------------------------------------------------- reading the instantiation


def test_instantiation_definitions_are_parsed_with_their_lines() -> None:
    text = """-- generate nat
nametype core_nat = {0..3}

-- generate sign not
sign(x) =
  let
    y = abs(x)
  within
    if y == 0 then 0 else x / y

abs(n) = if n >= 0 then n else -n
nametype core_int = union({ -2..2},{calc_type_min(Union({{0},{Plus(c, 1, core_nat)|c <- {0..2}}}))..calc_type_max(Union({{0}}))})
aux(<g>^gs, m) = if g > m then aux(gs, g) else aux(gs, m)
const_M_p = -1
"""
    inst = read(text, "i.csp", lambda line, column: tockbmc.model.ast.Pos("i.csp", line, column))
    assert [(d.name, d.pos.line, d.nametype) for d in inst.definitions] == [
        ("core_nat", 2, True), ("sign", 5, False), ("abs", 11, False), ("core_int", 12, True), ("aux", 13, False),
        ("const_M_p", 14, False)]
    assert not inst.problems


def test_a_definition_outside_cspm_is_skipped_and_reported() -> None:
    text = "const_M_p = 1\nbroken(x) = x +* 2\nnametype core_int = {0..1}\n"
    inst = read(text, "i.csp", lambda line, column: tockbmc.model.ast.Pos("i.csp", line, column))
    assert [d.name for d in inst.definitions] == ["const_M_p", "core_int"]
    [problem] = inst.problems
    assert problem.pos.line == 2 and problem.severity == "warning"


def test_ranges_constants_and_functions_from_instantiations_csp(tmp_path: Path) -> None:
    p = project(tmp_path, """nametype core_int = { -1..1}
nametype core_nat = {0,1,2}
nametype Speed = {0..4}
const_M_p = 1
const_M_mode = Mode_Fast
const_M_pair = ((1, -1))
sign(x) = if x > 0 then 1 else if x == 0 then 0 else -1
idle(Mode_Slow) = 0
idle(Mode_Fast) = 1
""")
    config = configure(p)
    assert not config.warnings
    assert config.ranges().describe() == {"core_int": "-1..1", "core_nat": "0..2", "Speed": "0..4"}
    assert config.range_sources()["core_nat"] == f"instantiation {tmp_path / 'instantiations.csp'}:2"
    [r] = check(p, bound=10, config=config)
    assert r.constants == {"M::p": "1", "M::mode": "Mode::Fast", "M::pair": "(a=1, b=-1)", "M::limit": "3"}
    assert r.sources["constants"]["M::p"].endswith("instantiations.csp:4")
    assert r.sources["constants"]["M::limit"].startswith("model ")
    # p == 1 and sign(x) == 1 for x = 1: M terminates, as FDR would find with this instantiation
    assert r.verdict == "violated" and r.extra["replayed"] == "yes"
    sign, idle = (next(f for f in config.project.functions if f.name == n) for n in ("sign", "idle"))
    assert sign.definition is not None and not sign.preconditions
    assert idle.definition is not None and len(idle.preconditions) == 1  # defined on both literals


def test_a_range_bound_may_name_a_constant_of_the_instantiation(tmp_path: Path) -> None:
    """`nametype core_int = {LOW..HIGH}` with `LOW = -1` and `HIGH = LOW + 2` defined beside it, as
    public projects write their instantiations."""
    p = project(tmp_path, "HIGH = LOW + 2\nLOW = -1\nnametype core_int = { LOW..HIGH}\nSELF = SELF\n"
                          "nametype core_nat = {0..SELF}\n")
    config = configure(p)
    assert config.ranges().describe()["core_int"] == "-1..1"
    # a name defined by itself gives no number: that range is not used, and says so
    assert [w.message for w in config.warnings] == ["unsupported: expected a number; 'core_nat' is not used"]
    assert config.warnings[0].pos.line == 5


def test_unset_constants_take_robotools_default_values(tmp_path: Path) -> None:
    p = project(tmp_path)
    [r] = check(p, bound=10)
    assert r.constants == {"M::p": "0", "M::mode": "Mode::Slow", "M::pair": "(a=0, b=0)", "M::limit": "3"}
    assert set(r.sources["constants"].values()) == {"RoboTool default", f"model {tmp_path / 'm.rct'}:11"}
    assert r.verdict == "holds"  # p == 0: the trigger's condition never holds


def test_the_command_line_overrides_the_instantiation(tmp_path: Path) -> None:
    p = project(tmp_path, "nametype core_int = {0..1}\nconst_M_p = 1\nsign(x) = 1\n")
    [r] = check(p, bound=10)
    assert r.verdict == "violated" and r.constants["M::p"] == "1"
    config = configure(p, {"core_int": _range(-1, 0)}, {"M::p": "0"})
    [r] = check(p, bound=10, config=config)
    assert r.verdict == "holds"
    assert r.ranges == {"core_int": "-1..0"} and r.sources["ranges"] == {"core_int": "--range"}
    assert r.constants["M::p"] == "0" and r.sources["constants"]["M::p"] == "--set"
    unbounded = configure(p, {"core_int": None})
    assert unbounded.ranges().describe() == {}


def test_the_explicit_engine_reads_the_same_configuration(tmp_path: Path) -> None:
    from tockbmc.explicit.engine import check_explicit
    from tockbmc.model.ranges import Ranges
    p = project(tmp_path, "nametype core_int = {0..1}\nnametype Speed = {0..1}\nconst_M_p = 1\nsign(x) = 1\n")
    [r] = check_explicit(p, None, 10, Ranges(), {}, 10)
    assert r.verdict == "violated" and r.engine == "explicit"
    assert r.constants["M::p"] == "1" and r.sources["constants"]["M::p"].endswith("instantiations.csp:3")
    [r] = check_explicit(p, None, 10, Ranges(), {}, 10, config=configure(p, settings={"M::p": "0"}))
    assert r.verdict == "holds"


def test_the_file_in_csp_gen_is_read_when_the_root_has_none(tmp_path: Path) -> None:
    p = project(tmp_path, "const_M_p = 1\nnametype core_int = {0..1}\n", where="csp-gen/instantiations.csp")
    config = configure(p)
    assert config.ranges().describe() == {"core_int": "0..1"}
    [r] = check(p, bound=10, config=config)
    assert r.constants["M::p"] == "1"


def test_an_instantiations_block_overrides_the_file(tmp_path: Path) -> None:
    block = "csp Instantiations csp-begin\nconst_M_p = 1\ncsp-end\n"
    p = project(tmp_path, "const_M_p = 0\n", assertions=block + ASSERTIONS)
    config = configure(p)
    [r] = check(p, bound=10, config=config)
    assert r.constants["M::p"] == "1" and r.sources["constants"]["M::p"].endswith("m.assertions:2")
    assert any("also defined" in m for m in messages(config))


def test_what_the_instantiation_cannot_give_is_reported_with_its_line(tmp_path: Path) -> None:
    p = project(tmp_path, """nametype core_int = {0, 2, 5}
nametype core_real = union({ -2..2},{calc_type_min(Union({{0}}))..calc_type_max(Union({{0}}))})
const_M_q = 1
const_M_mode = Mode_Medium
sign(<x>) = x
Plus(e1,e2,T) = if member(e1+e2,T) then e1+e2 else e1
nametype core_string = LSeq(Char,2)
const_M_limit = 4
go_BOUND = 2
mystery = 3
""")
    config = configure(p)
    found = messages(config)
    assert any(m.startswith("1: unsupported: a set of values with gaps") for m in found), found
    assert any(m.startswith("2: unsupported: not an interval") for m in found), found
    assert any(m.startswith("3: no constant of the model is named 'const_M_q'") and "did you mean 'const_M_p'" in m
               for m in found), found
    assert any(m.startswith("4: unsupported: expected a literal of Mode") for m in found), found
    assert any(m.startswith("5: unsupported: a sequence") and "function sign stays uninterpreted" in m
               for m in found), found
    assert any(m.startswith("8: the model gives M::limit the value") for m in found), found
    assert any(m.startswith("10: 'mystery' is not a constant, type or function") for m in found), found
    assert len(found) == 7  # RoboTool's own helpers (Plus, core_string, *_BOUND) are not reported
    assert config.ranges().describe() == {}
    assert next(f for f in config.project.functions if f.name == "sign").definition is None


# ---------------------------------------------------------------------------- names on the command line


def test_constant_names_resolve_to_declarations(tmp_path: Path) -> None:
    p = project(tmp_path)
    config = configure(p, settings={"M::p": "1", "mode": "Fast", "N::p": "-2"})
    [r] = check(p, bound=10, config=config)
    assert r.constants["M::p"] == "1" and r.constants["M::mode"] == "Mode::Fast"
    assert r.sources["constants"]["M::p"] == "--set"
    with pytest.raises(ConfigError, match="'p' is ambiguous: it names M::p, N::p"):
        configure(p, settings={"p": "1"})
    with pytest.raises(ConfigError, match="'M' has no constant 'pp'; did you mean 'M::p'"):
        configure(p, settings={"M::pp": "1"})
    with pytest.raises(ConfigError, match="no element 'MM' to hold constant 'p'; did you mean 'M'"):
        configure(p, settings={"MM::p": "1"})
    with pytest.raises(ConfigError, match="no constant named 'mod'; did you mean 'mode'"):
        configure(p, settings={"mod": "Fast"})
    # Two names of one declaration are not two instances: two values for it are refused, not the last taken.
    with pytest.raises(ConfigError, match="mode and M::mode both name constant M::mode"):
        configure(p, settings={"mode": "Fast", "M::mode": "Slow"})


@pytest.mark.parametrize("name, value, message", [
    ("M::p", "0.5", "M::p is int: 0.5 is not an integer"),
    ("M::limit", "-1", "M::limit is nat: -1 is negative"),
    ("M::mode", "Fats", "no literal 'Fats'; did you mean 'Fast'"),
    ("M::mode", "Colour::Fast", "no literal 'Colour::Fast'"),
    ("M::p", "true", "M::p is int: 'true' is not a number"),
    ("M::pair", "1", "M::pair is of type Pair: only numbers, booleans and enumeration literals"),
    ("M::p", "1e999999999", "the exponent is too large"),
    ("M::p", "9" * 100, "is too long for a number"),
])
def test_values_outside_their_type_are_rejected(tmp_path: Path, name: str, value: str, message: str) -> None:
    p = project(tmp_path)
    with pytest.raises(ConfigError, match=message):
        configure(p, settings={name: value})


def test_param_makes_a_constant_a_parameter(tmp_path: Path) -> None:
    p = project(tmp_path, "sign(x) = 1\n")
    [r] = check(p, bound=10, config=configure(p, {"core_int": _range(-1, 1)}, params=["M::p"]))
    assert r.verdict == "violated" and r.constants["M::p"] == "parameter (-1..1)"
    assert r.extra["replayed"] == "yes"
    with pytest.raises(ConfigError, match="given a value with --set and made a parameter"):
        configure(p, settings={"M::p": "1"}, params=["M::p"])
    with pytest.raises(ConfigError, match="M::limit has a value in the model"):
        configure(p, params=["M::limit"])
    twice = configure(p, {"core_int": _range(-1, 1)}, params=["M::p", "M::p"])  # taken once
    [again] = check(p, bound=10, config=twice)
    assert again.verdict == "violated" and again.constants["M::p"] == "parameter (-1..1)"


def _range(low: int, high: int) -> tockbmc.model.ranges.Range:
    from fractions import Fraction

    from tockbmc.model.ranges import Range
    return Range(Fraction(low), Fraction(high))


@pytest.mark.parametrize("name, low, high, message", [
    ("int", 0, 1, "no type 'int' to bound; did you mean 'core_int'"),
    ("Mode", 0, 1, "'Mode' is an enumeration"),
    ("core_nat", -1, 1, "bounds naturals: LO must be at least 0"),
    ("core_int", 2, 1, "LO must not exceed HI"),
    ("M::e.x", 0, 1, "'M::e' is of type int, which has no field 'x'"),
    ("M::ee", 0, 1, "'M' has no event, variable or constant 'ee'.*did you mean 'e'"),
    ("MM::e", 0, 1, "no element 'MM' in range path 'MM::e'; did you mean 'M'"),
])
def test_range_names_must_exist(tmp_path: Path, name: str, low: int, high: int, message: str) -> None:
    p = project(tmp_path)
    with pytest.raises(ConfigError, match=message):
        configure(p, {name: _range(low, high)})


# ---------------------------------------------------------------------------- the command line


@pytest.mark.parametrize("args, text", [
    (["--set", "UR::n_waypoint=1"], "did you mean 'UR::n_waypoints'"),
    (["--set", "n_waypoints=1"], "'n_waypoints' is ambiguous: it names EXAX::n_waypoints, UR::n_waypoints"),
    (["--set", "M::z=0"], "no element 'M' to hold constant 'z'"),
    (["--set", "UR::n_waypoints=-1"], "UR::n_waypoints is nat: -1 is negative"),
    (["--set", "UR::n_waypoints=0.5"], "is not an integer"),
    (["--range", "EXAX::move.tme=0..2"], "'EXAX::move' has no field 'tme'; did you mean 'time'"),
    (["--range", "core_nat=-1..2"], "bounds naturals"),
    (["--range", "core_int=2..1"], "LO <= HI"),
    (["--range", "core_itn=0..1"], "did you mean 'core_int'"),
    (["--param", "UR::n_waypoint"], "did you mean 'UR::n_waypoints'"),
    # two values for one constant are refused rather than the last taken silently
    (["--set", "UR::n_waypoints=1", "--set", "UR::n_waypoints=2"], "UR::n_waypoints is given two values, 1 and 2"),
    (["-a", "A11"], "no assertion named 'A11'; did you mean 'A1'? (known: A1, A2"),
    (["-a", "a5"], "did you mean 'A5'?"),
])
def test_usage_errors_exit_2_with_a_suggestion(args: list[str], text: str) -> None:
    out = run_cli(["check", str(EXAMPLE), "-a", "A5", *args])
    assert out.exit_code == 2 and out.crash is None, out.output
    assert text in " ".join(out.output.split()), out.output


@pytest.mark.parametrize("args", [["--range", "core_int=-1e999999999..1"], ["--set", "UR::n_waypoints=1e999999999"],
                                  ["--range", "core_real=0..1e-999999999"]])
def test_absurd_numbers_are_refused_at_once(args: list[str]) -> None:
    start = time.perf_counter()
    out = run_cli(["check", str(EXAMPLE), "-a", "A5", *args])
    assert out.exit_code == 2 and "exponent is too large" in out.output, out.output
    assert time.perf_counter() - start < 10


def test_set_with_a_qualified_name_reaches_bmc_and_replay(tmp_path: Path) -> None:
    """`--set EXAX::n_waypoints=2`: EXAX says `done` only after three moves.  BMC's counterexample has
    the three moves, and the interpreter, reading the same value, replays it (BMC used to read
    constants by bare name only, so a qualified `--set` reached the interpreter but not BMC)."""
    write_files(tmp_path, {"iw.rct": (EXAMPLE / "intelliwelder.rct").read_text(),
                           "d.assertions": "timed csp NoDone csp-begin\nNoDone = CHAOS(diff(Events, {| EXAX::done |}))"
                                           "\ncsp-end\ntimed assertion D: EXAX refines NoDone in the traces model.\n"})
    out = run_cli(["check", str(tmp_path), "-k", "20", "--range", "core_int=0..0", "--range", "core_real=0..0",
                   "--set", "EXAX::n_waypoints=2", "--format", "json"])
    assert out.exit_code == 10, out.output
    [r] = json.loads(out.stdout)["results"]
    assert r["replayed"] == "yes" and r["constants"] == {"EXAX::n_waypoints": "2"}
    assert r["sources"]["constants"] == {"EXAX::n_waypoints": "--set"}
    events = [s["event"] for s in r["trace"] if s["event"]]
    assert sum(e.startswith("EXAX::move.in") for e in events) == 3 and events[-1] == "EXAX::done.out", events


def test_instance_paths_name_the_machines_constants() -> None:
    p = tockbmc.load(EXAMPLE)
    for name in ("UR::n_waypoints", "main::ctrl::ur_ref::n_waypoints", "Controller::ur_ref::n_waypoints"):
        config = configure(p, settings={name: "3"})
        [r] = check(p, ["A6"], bound=3, config=config)
        assert r.constants["UR::n_waypoints"] == "3" and r.sources["constants"]["UR::n_waypoints"] == "--set", name
    with pytest.raises(ConfigError, match="no element 'ctrl::ur_ref'.*did you mean 'main::ctrl::ur_ref'"):
        configure(p, settings={"ctrl::ur_ref::n_waypoints": "3"})


def test_text_output_states_each_range_and_constant_with_its_source() -> None:
    out = run_cli(["check", str(EXAMPLE), "-a", "A5", "-k", "12", "--range", "core_int=0..2", "--range",
                   "core_real=-1..1"])
    assert "ranges: core_int=0..2 [--range], core_real=-1..1 [--range]; constants: " \
           "EXAX::n_waypoints=0 [RoboTool default]" in out.stdout, out.stdout


@pytest.mark.parametrize("path", ["C::x", "S1::x", "S2::x", "test8::CV::x"])
def test_every_path_to_a_shared_variable_bounds_it_in_both_engines(path: str) -> None:
    """`test8`'s controller variable `x` (interface CV, used by C, required by S1 and S2) is one
    declaration, whichever path names it, and each engine bounds every machine's copy of it by
    that range.  In the open reading x starts anywhere in its range: pinned to 0..0, it starts at
    RoboTool's 0, and A1 holds in both engines as it does in the default reading."""
    case = CONFORMANCE / "robochart" / "test8"
    for engine in ("bmc", "explicit"):
        out = run_cli(["check", str(case), "-a", "A1", "--open", "--engine", engine, "--range", f"{path}=0..0",
                       "--format", "json"])
        assert out.exit_code == 0, out.output
        [r] = json.loads(out.stdout)["results"]
        assert r["ranges"]["test8::CV::x"] == "0..0", r["ranges"]


# Two instances of one machine, each with its own value for the constant its used interface holds.
TWO_INSTANCES = """
enumeration Value { VA VB VC }
interface I { const CC : Value }
controller ctrl0 {
  event e1 : Value
  event e2 : Value
  sref stm_ref0 = STM
  sref stm_ref1 = STM
  connection stm_ref0 on e to ctrl0 on e1
  connection stm_ref1 on e to ctrl0 on e2
}
stm STM {
  event e : Value
  uses I
  initial i0
  final f0
  transition t0 { from i0 to f0 action e!CC }
}
"""
SPEC = """untimed csp Spec csp-begin
Spec = (ctrl0::e1.out.Value_VB -> SKIP ||| ctrl0::e2.out.Value_VC -> SKIP) ; ctrl0::terminate -> SKIP
csp-end
"""


@pytest.mark.parametrize("source", ["with constant", "instantiation"])
def test_each_instance_of_a_machine_has_its_own_constants(tmp_path: Path, source: str) -> None:
    """RoboTool names an instance's constant by its path (`const_ctrl0_stm_ref0_CC`), so two
    instances of one machine can hold two values; tockbmc used to give the declaration one value
    (the first instance's), and RoboTool's test12 A1/A2 were violated.  Both engines, both sources."""
    if source == "with constant":
        text = SPEC + ("untimed assertion A: ctrl0 equals Spec with constant CC of ctrl0::stm_ref0 set to Value::VB, "
                       "and constant CC of ctrl0::stm_ref1 set to Value::VC.\n")
    else:
        text = SPEC + "untimed assertion A: ctrl0 equals Spec.\n"
        (tmp_path / "instantiations.csp").write_text("const_ctrl0_stm_ref0_CC = Value_VB\n"
                                                     "const_ctrl0_stm_ref1_CC = Value_VC\n")
    write_files(tmp_path, {"m.rct": TWO_INSTANCES, "m.assertions": text})
    for engine in ("bmc", "explicit"):
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--format", "json"])
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "holds", (engine, r)
        assert (r["constants"]["ctrl0::stm_ref0::CC"], r["constants"]["ctrl0::stm_ref1::CC"]) == ("Value::VB", "Value::VC")
        assert "I::CC" not in r["constants"], r["constants"]  # every instance has its own: not shown


REQUIRED = """
interface I { const CC : int }
controller ctrl0 {
  provides I
  event e1 : int
  sref stm_ref0 = STM
  connection stm_ref0 on e to ctrl0 on e1
}
stm STM {
  event e : int
  requires I
  initial i0
  final f0
  transition t0 { from i0 to f0 action e!CC }
}
csp Spec csp-begin
Spec = tock -> Spec [] ctrl0::e1.out.1 -> Spec [] ctrl0::terminate -> SKIP
csp-end
assertion A: ctrl0 refines Spec in the traces model with constant CC of ctrl0::stm_ref0 set to 1.
"""


def test_a_required_constant_named_through_an_instance_is_the_controllers(tmp_path: Path) -> None:
    """The machine requires CC, which its controller provides: one constant, whichever path names it.
    Stored as the instance's alone, BMC used the default 0 and the interpreter 1 (a replay failure)."""
    write_files(tmp_path, {"m.rct": REQUIRED.split("csp Spec")[0], "m.assertions": "csp Spec" + REQUIRED.split("csp Spec")[1]})
    for engine in ("bmc", "explicit"):
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--range", "core_int=-1..1", "--format", "json"])
        assert out.exit_code == 0, out.output
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "holds" and r["constants"] == {"I::CC": "1"}, (engine, r)


def test_open_constants_of_two_instances_are_two_parameters(tmp_path: Path) -> None:
    """`--param` on a constant two instances use: each instance takes its own value, in BMC's run, in
    its replay (which used to give both the second's value and fail) and in explore's parameters."""
    spec = ("csp Spec csp-begin\nSpec = tock -> Spec [] ctrl0::e1.out.0 -> A0 [] ctrl0::e1.out.1 -> A1 "
            "[] ctrl0::e2.out.0 -> A0 [] ctrl0::e2.out.1 -> A1\n"
            "A0 = tock -> A0 [] ctrl0::e1.out.0 -> A0 [] ctrl0::e2.out.0 -> A0 [] ctrl0::terminate -> SKIP\n"
            "A1 = tock -> A1 [] ctrl0::e1.out.1 -> A1 [] ctrl0::e2.out.1 -> A1 [] ctrl0::terminate -> SKIP\n"
            "csp-end\nassertion A: ctrl0 refines Spec in the traces model.\n")
    write_files(tmp_path, {"m.rct": TWO_INSTANCES.replace("Value", "int").replace("enumeration int { VA VB VC }", ""),
                           "m.assertions": spec})
    for engine in ("bmc", "explicit"):  # the two outputs differ: Spec allows only equal values
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--range", "core_int=0..1", "--param", "I::CC",
                       "--format", "json"])
        assert out.exit_code == 10, out.output
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "violated" and (engine == "explicit" or r["replayed"] == "yes"), (engine, r)
    out = run_cli(["explore", str(tmp_path), "--range", "core_int=0..1", "--format", "json"])
    assert "ctrl0::stm_ref0::CC" in out.stdout and "ctrl0::stm_ref1::CC" in out.stdout, out.output


def test_a_negative_constant_reaches_the_explicit_engine(tmp_path: Path) -> None:
    """`set to -1` is a negated literal; the explicit engine called it "not a literal" (unsupported)."""
    write_files(tmp_path, {"m.rct": "stm M {\n  const k : int\n  event e : int\n  initial i\n  final f\n"
                                    "  transition t0 { from i to f action e!k }\n}\n",
                           "m.assertions": "csp Spec csp-begin\nSpec = tock -> Spec [] M::e.out.(-1) -> Spec "
                                           "[] M::terminate -> SKIP\ncsp-end\n"
                                           "assertion A: M refines Spec with constant k of M set to -1.\n"})
    for engine in ("bmc", "explicit"):
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--range", "core_int=-1..1", "--format", "json"])
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "holds", (engine, r)


def test_a_value_set_through_an_instance_path_is_that_instances_alone(tmp_path: Path) -> None:
    """`explore` names each instance's open constant by its path (`ctrl0::stm_ref0::CC`, as in
    `test_open_constants_of_two_instances_are_two_parameters`); `--set` refused that name, or (`C::m1::k`) gave every instance the value. It now sets that instance's
    constant alone, in both engines; `--param` on such a name is a usage error, with the
    declaration's name to use."""
    write_files(tmp_path, {"m.rct": TWO_INSTANCES, "m.assertions": SPEC + "untimed assertion A: ctrl0 equals Spec.\n"})
    for engine in ("bmc", "explicit"):
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--format", "json",
                       "--set", "ctrl0::stm_ref0::CC=Value::VB", "--set", "ctrl0::stm_ref1::CC=Value::VC"])
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "holds", (engine, r)
        assert (r["constants"]["ctrl0::stm_ref0::CC"], r["constants"]["ctrl0::stm_ref1::CC"]) == ("Value::VB", "Value::VC")
        # one instance set: the other keeps the declaration's value (RoboTool's default, the first literal)
        out = run_cli(["check", str(tmp_path), "--engine", engine, "--format", "json",
                       "--set", "ctrl0::stm_ref0::CC=Value::VB"])
        [r] = json.loads(out.stdout)["results"]
        assert r["verdict"] == "violated" and r["constants"]["ctrl0::stm_ref0::CC"] == "Value::VB", (engine, r)
    out = run_cli(["explore", str(tmp_path), "--param", "ctrl0::stm_ref0::CC"])
    assert out.exit_code == 2 and "name it by its declaration" in out.output, out.output


INSTANCES_IN_A_MODULE = """
controller ctrl0 {
  const K : int
  event e1 : int
  event e2 : int
  sref stm_ref0 = STM
  sref stm_ref1 = STM
  connection stm_ref0 on e to ctrl0 on e1
  connection stm_ref1 on e to ctrl0 on e2
}
stm STM {
  const CC : int
  const D : int = 0
  event e : int
  initial i0
  state s {}
  final f0
  transition t0 { from i0 to s action e!CC }
  transition t1 { from s to f0 condition CC == 1 }
}
interface IE { event e1 : int event e2 : int }
module Mod {
  robotic platform rp { uses IE }
  cref c = ctrl0
  connection c on e1 to rp on e1 ( _async )
  connection c on e2 to rp on e2 ( _async )
}
"""


def test_an_instance_is_one_instance_whichever_element_it_is_named_from(tmp_path: Path) -> None:
    """`Mod::c::stm_ref0::CC` applies when ctrl0 is checked alone, as it does to STM alone; two names
    of one instance with two values are refused, and so is a value for a constant with a value in
    the model, or for a controller's (one for all its instances), rather than taken for every
    instance."""
    write_files(tmp_path, {"m.rct": INSTANCES_IN_A_MODULE, "m.assertions": (
        "assertion M: Mod terminates.\nassertion C: ctrl0 terminates.\nassertion S: STM terminates.\n")})
    out = run_cli(["check", str(tmp_path), "--format", "json", "--set", "Mod::c::stm_ref0::CC=1",
                   "--set", "Mod::c::stm_ref1::CC=1"])
    results = {r["assertion"]: r for r in json.loads(out.stdout)["results"]}
    assert results["M"]["constants"]["Mod::c::stm_ref1::CC"] == "1", results["M"]
    assert results["C"]["constants"]["ctrl0::stm_ref1::CC"] == "1", results["C"]
    assert results["S"]["constants"]["STM::CC"] == "1" and results["S"]["verdict"] == "holds", results["S"]
    # two instances, two values: STM on its own takes neither (RoboTool's default, shown as such)
    out = run_cli(["check", str(tmp_path), "-a", "S", "--format", "json", "--set", "ctrl0::stm_ref0::CC=1",
                   "--set", "ctrl0::stm_ref1::CC=2"])
    [s] = json.loads(out.stdout)["results"]
    assert s["constants"]["STM::CC"] == "0" and s["sources"]["constants"]["STM::CC"] == "RoboTool default", s
    for settings, message in [
        (["ctrl0::stm_ref0::CC=1", "Mod::c::stm_ref0::CC=2"], "give one instance's constant two values"),
        (["ctrl0::stm_ref0::D=1"], "has a value in the model"),
        (["Mod::c::K=1"], "whose constants are one for every instance"),
    ]:
        out = run_cli(["check", str(tmp_path), *[x for v in settings for x in ("--set", v)]])
        assert out.exit_code == 2 and message in out.output, out.output


def test_an_instance_path_does_not_reach_the_same_machine_in_another_controller() -> None:
    """`--set ctrl0::stm_ref0::CC=1` sets ctrl0's instance only, not ctrl1's stm_ref0, though both
    end at STM."""
    out = run_cli(["check", str(Path(__file__).parent / "models" / "instance_paths"), "--format", "json",
                   "--set", "ctrl0::stm_ref0::CC=1"])
    results = {r["assertion"]: r for r in json.loads(out.stdout)["results"]}
    assert results["B"]["verdict"] == "holds" and "ctrl1::stm_ref0::CC" not in results["B"]["constants"]
    assert results["C"]["verdict"] == "violated" and results["C"]["constants"]["ctrl0::stm_ref0::CC"] == "1"
    assert results["A"]["constants"]["Mod::c0::stm_ref0::CC"] == "1"
    assert "Mod::c1::stm_ref0::CC" not in results["A"]["constants"]


def test_an_instantiation_line_nothing_reads_is_not_parsed_and_a_pathological_one_is_refused(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A definition of a name the model has nothing for is read for its name alone (it is warned about,
    never parsed, however large); one the model would use, nested 40,000 deep, is refused with its
    line before the parser recurses into it; the ranges around them are read as usual."""
    import tockbmc.model.instantiation as inst

    deep = "if true then " * 40_000 + "0" + " else 0" * 40_000
    project = write_files(tmp_path, {"m.rct": (EXAMPLE / "intelliwelder.rct").read_text(),
                                     "instantiations.csp": f"nametype core_int = {{-1..1}}\njunk = {deep}\n"
                                                           f"const_EXAX_n_waypoints = {deep}\n"
                                                           "nametype core_real = {-1..1}\n"})
    parsed: list[str] = []
    real_parse = inst._parse
    monkeypatch.setattr(inst, "_parse", lambda text: parsed.append(text) or real_parse(text))
    config = configure(tockbmc.load(project))
    assert not any("if true" in text for text in parsed)
    warnings = {(w.pos.line, w.message) for w in config.warnings if w.pos.path.endswith("instantiations.csp")}
    assert (2, "'junk' is not a constant, type or function of the model, so it is not used") in warnings
    assert (3, "this definition is nested more than 200 levels deep; it is ignored") in warnings
    assert config.ranges().describe() == {"core_int": "-1..1", "core_real": "-1..1"}


def test_a_helper_in_the_instantiation_file_serves_a_function_defined_in_a_block(tmp_path: Path) -> None:
    """What to parse is decided over the file and the blocks together: `h`, named by the block's `f`
    alone, is read from the file, and f is interpreted (`f(0)` is 1, so `one` is entered)."""
    project = write_files(tmp_path, {
        "m.rct": "function f(n : int) : int { }\nstm M {\n  var x : int = 0\n  initial i\n  state s {}\n"
                 "  state one {}\n  transition t0 { from i to s action x = f(0) }\n"
                 "  transition t1 { from s to one condition x == 1 }\n}\n",
        "instantiations.csp": "h(n) = n + 1\n",
        "m.assertions": "csp Instantiations csp-begin\nf(n) = h(n)\ncsp-end\nassertion One: one is reachable in M.\n"})
    config = configure(tockbmc.load(project))
    assert not [w for w in config.warnings if "h" in w.message.split("'")], config.warnings
    [r] = check(config.project, bound=10, config=config)
    assert r.verdict == "holds", r.reason


@pytest.mark.parametrize("body", [" + ".join(["(if n == 0 then 0 else 0)"] * 250),
                                  "".join(f"if n == {k} then 0 else " for k in range(250)) + "0"])
def test_an_instantiation_body_long_but_shallow_is_read(tmp_path: Path, body: str) -> None:
    """Two hundred and fifty `if`s side by side, or one after another's `else`, are not nested 250 deep."""
    project = write_files(tmp_path, {"m.rct": "function f(n : int) : int { }\nstm M { initial i state s {} "
                                              "transition t { from i to s } }\n",
                                     "instantiations.csp": f"f(n) = {body}\n"})
    config = configure(tockbmc.load(project))
    assert not [w for w in config.warnings if "nested" in w.message], config.warnings
    [f] = config.project.functions
    assert f.definition is not None
