"""Input at and past the documented limits (README, "Limits"): a diagnostic past them, every
command working up to them, and numbers of any size printed exactly."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from decimal import Decimal
from pathlib import Path

import pytest
from conftest import run_cli, write_files

from tockbmc import load
from tockbmc.check import check
from tockbmc.model.limits import MAX_CSP_NESTING, MAX_DECLARATION_CHAIN, MAX_NESTING, TOO_DEEP_TO_CHECK

RANGE = ["--range", "core_int=-1..1", "--range", "core_real=-1..1"]


def machine(variable: str = "var x : int = 1", state: str = "state s {}", transition: str = "",
            action: str = "") -> str:
    """M: variable, `e : real`, state(s), `t0` from the initial junction to `s` (with `action`), `transition`."""
    t0 = f"transition t0 {{ from i to s{' action ' + action if action else ''} }}"
    return f"stm M {{\n  {variable}\n  event e : real\n  initial i\n  {state}\n  {t0}\n  {transition}\n}}\n"


def project(tmp_path: Path, rct: str, assertions: str = "assertion A: M is deadlock-free.\n") -> Path:
    return write_files(tmp_path, {"m.rct": rct, "m.assertions": assertions})


def nested_states(n: int) -> str:
    inner = "state s { }"
    for k in range(n):
        inner = f"state s {{ initial i {inner} transition t{k} {{ from i to s }} }}"
    return inner


# -------------------------------------------------------------------- numbers


@pytest.mark.parametrize("literal", ["1" * 5000, "1." + "5" * 5000])
def test_a_number_literal_too_long_for_python_is_a_diagnostic(tmp_path: Path, literal: str) -> None:
    path = project(tmp_path, machine(f"var x : real = {literal}"))
    result = run_cli(["show", path])
    assert result.crash is None and result.exit_code == 3, result.output
    assert f"m.rct:2:18: error: number literal too long: at most {sys.get_int_max_str_digits()} digits" \
        in result.stderr
    assert "\n                   ^~~" in result.stderr  # the caret under the literal


def test_a_long_number_in_a_csp_block_makes_its_assertions_unsupported(tmp_path: Path) -> None:
    block = "timed csp P csp-begin\nP = M::e.out." + "1" * 5000 + " -> STOP\ncsp-end\n"
    path = project(tmp_path, machine(), block + "assertion A: M refines P in the traces model.\n")
    result = run_cli(["check", path, "-k", "2", "--format", "json"])
    assert result.crash is None and result.exit_code == 20, result.output
    [r] = json.loads(result.stdout)["results"]
    assert r["verdict"] == "unsupported" and "number too long" in r["reason"] and "m.assertions:2:14" in r["reason"]


BIG = "1" + "0" * 400 + ".5"
TINY = "0." + "0" * 400 + "1"


@pytest.mark.parametrize("literal", [BIG, TINY])
def test_reals_beyond_floats_print_exactly(tmp_path: Path, literal: str) -> None:
    """Neither 10^400 + 0.5 nor 10^-401 is a float: both print digit for digit."""
    path = project(tmp_path, machine("var x : real = " + literal, action="e!x"))
    shown = run_cli(["show", path])
    assert shown.exit_code == 0 and f"var x : real = {literal}" in shown.stdout, shown.output
    checked = run_cli(["check", path, "-k", "3", "--format", "json"])
    assert checked.exit_code == 10, checked.output
    [r] = json.loads(checked.stdout)["results"]
    assert [s["event"] for s in r["trace"]][-1] == f"M::e.out.{literal}" and r["replayed"] == "yes"
    # A random run may let time pass instead of sending: some seed among the first few sends.
    runs = [run_cli(["simulate", path, "--steps", "3", "--seed", str(seed)]) for seed in range(12)]
    assert all(r.exit_code == 0 for r in runs), runs[0].output
    assert any(f"M::e.out.{literal}" in r.stdout for r in runs), runs[0].output


def test_values_computed_past_python_s_digit_limit_print(tmp_path: Path) -> None:
    """A 3000-digit literal squared has 6000 digits: the interpreter's trace still prints it."""
    big = "7" * 3000
    rct = machine(f"var x : real = {big}", action="x = x * x ; e!x")
    result = run_cli(["simulate", project(tmp_path, rct), "--steps", "4"])
    assert result.crash is None and result.exit_code == 0, result.output
    assert f"M: x := {Decimal(int(big) ** 2)}" in result.stdout


# -------------------------------------------------------------------- nesting


def test_nesting_past_the_limit_is_a_diagnostic_at_the_place(tmp_path: Path) -> None:
    sum_ = "+".join(["x"] * (MAX_NESTING + 10))
    path = project(tmp_path, machine(transition=f"transition t1 {{ from s to s condition {sum_} > 0 }}"))
    result = run_cli(["check", path])
    assert result.crash is None and result.exit_code == 3, result.output
    column = len("  transition t1 { from s to s condition ") + 1
    assert f"m.rct:7:{column}: error: nested too deeply: more than {MAX_NESTING} levels" in result.stderr


@pytest.mark.parametrize("text", [
    "not (" * 1000 + "true" + ")" * 1000,
    "-(" * 1000 + "1" + ")" * 1000,
    "if true then " * 1000 + "1" + " else 0 end" * 1000,
])
def test_deep_expressions_of_every_kind_are_diagnosed(tmp_path: Path, text: str) -> None:
    result = run_cli(["show", project(tmp_path, machine(f"var x : int = {text}"))])
    assert result.crash is None and result.exit_code == 3 and "nested too deeply" in result.stderr, result.output


def test_csp_nested_past_its_limit_is_unsupported(tmp_path: Path) -> None:
    spec = " [] ".join(["M::e.out.1 -> STOP"] * (MAX_CSP_NESTING + 50))
    block = f"timed csp P csp-begin\nP = {spec}\ncsp-end\n"
    path = project(tmp_path, machine(), block + "assertion A: M refines P in the traces model.\n")
    result = run_cli(["check", path, "-k", "2", "--format", "json"])
    assert result.crash is None and result.exit_code == 20, result.output
    [r] = json.loads(result.stdout)["results"]
    assert r["verdict"] == "unsupported" and f"more than {MAX_CSP_NESTING} levels" in r["reason"]


def test_csp_nested_up_to_its_limit_is_checked(tmp_path: Path) -> None:
    spec = " [] ".join(["M::e.out.1 -> STOP"] * (MAX_CSP_NESTING - 10))
    block = f"timed csp P csp-begin\nP = {spec}\ncsp-end\n"
    rct = machine("var x : real = 1", transition="transition t1 { from s to s action e!x }")
    path = project(tmp_path, rct, block + "assertion A: M refines P in the traces model.\n")
    for engine in ("bmc", "explicit"):
        result = run_cli(["check", path, "-k", "3", "--engine", engine, "--format", "json", *RANGE])
        assert result.crash is None and result.exit_code == 10, result.output
        assert json.loads(result.stdout)["results"][0]["verdict"] == "violated"


AT_THE_LIMIT = {
    # the condition sits 7 levels down (file, machine, transition, condition, comparison)
    "sum": machine(transition="transition t1 { from s to s condition " + "+".join(["x"] * (MAX_NESTING - 10))
                   + " > 0 action e!1 }"),
    "negation": machine(transition="transition t1 { from s to s action e!(" + "-(" * (MAX_NESTING - 10) + "x"
                        + ")" * (MAX_NESTING - 10) + ") }"),
    "states": machine(state=nested_states(MAX_NESTING - 10), transition="transition t1 { from s to s action e!1 }"),
}


@pytest.mark.parametrize("shape", sorted(AT_THE_LIMIT))
def test_every_command_runs_on_nesting_up_to_the_limit(tmp_path: Path, shape: str) -> None:
    path = project(tmp_path, AT_THE_LIMIT[shape])
    runs = [["show", path], ["show", path, "--format", "json"], ["simulate", path, "--steps", "4", *RANGE],
            ["check", path, "-k", "2", "--engine", "explicit", *RANGE]]
    if shape != "states":  # BMC on states nested 490 deep takes 15 s: see the next test
        runs.append(["check", path, "-k", "2"])
    for args in runs:
        result = run_cli(args)
        assert result.crash is None and result.exit_code in (0, 10, 20), (args, result.output[-2000:])


@contextmanager
def stack_of(frames: int) -> Iterator[None]:
    """Run the block with only `frames` more Python frames than the caller has."""
    depth = 0
    f = sys._getframe()
    while f is not None:
        depth, f = depth + 1, f.f_back
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(depth + frames)
    try:
        yield
    finally:
        sys.setrecursionlimit(limit)


def test_bmc_of_nested_states_takes_no_stack_per_level(tmp_path: Path) -> None:
    """States 150 deep, checked in 120 frames: entering them is a loop, not a recursion."""
    loaded = load(project(tmp_path, machine(state=nested_states(150), transition="transition t1 { from s to s action e!1 }")))
    with stack_of(120):
        [r] = check(loaded, bound=2)
    assert r.verdict == "holds"


def record_chain(n: int) -> str:
    """Record types R0 … Rn, each Ri's field of type Ri+1, and a machine sending an R0."""
    types = "".join(f"datatype R{i} {{ f : R{i + 1} }}\n" for i in range(n)) + f"datatype R{n} {{ f : int }}\n"
    return types + "stm M {\n  var x : R0\n  event e : R0\n  initial i\n  state s {}\n  transition t0 { from i to s action e!x }\n}\n"


def function_chain(n: int) -> str:
    """Functions f0 … fn, each fi defined by fi+1, and a machine sending f0(x)."""
    functions = "".join(f"function f{i}(a : int) : int {{ postcondition result == f{i + 1}(a) + 1 }}\n" for i in range(n))
    functions += f"function f{n}(a : int) : int {{ postcondition result == a }}\n"
    return functions + ("stm M {\n  var x : int = 1\n  event e : int\n  initial i\n  state s {}\n"
                        "  transition t0 { from i to s action e!f0(x) }\n}\n")


@pytest.mark.parametrize("chain", [record_chain, function_chain])
def test_declarations_chained_past_the_limit_are_diagnosed(tmp_path: Path, chain: Callable[[int], str]) -> None:
    """A thousand record types inside each other, or functions each calling the next, crashed BMC
    and the interpreter (recursion per link); past the limit, each link crossing it is an error."""
    result = run_cli(["check", project(tmp_path, chain(1000))])
    assert result.crash is None and result.exit_code == 3, result.output
    errors = [line for line in result.stderr.splitlines() if ": error: " in line]
    assert errors and all(f"through a chain of more than {MAX_DECLARATION_CHAIN} declarations" in e for e in errors)
    assert f"m.rct:{MAX_DECLARATION_CHAIN + 1}:10: error: " in errors[0]  # the declaration the limit is crossed at


@pytest.mark.parametrize("chain", [record_chain, function_chain])
def test_declarations_chained_up_to_the_limit_run_everywhere(tmp_path: Path, chain: Callable[[int], str]) -> None:
    path = project(tmp_path, chain(MAX_DECLARATION_CHAIN - 2))
    for args in (["show", path, "--format", "json"], ["check", path, "-k", "2"], ["simulate", path, "--steps", "3"]):
        result = run_cli(args)
        assert result.crash is None and result.exit_code in (0, 10, 20), (args, result.output[-2000:])


def operation_chain(n: int) -> str:
    """Operations O0 … On, each Oi calling Oi+1, run by a machine of controller C."""
    out = ["interface I { " + " ".join(f"O{i}()" for i in range(n + 1)) + " }"]
    out += [f"operation O{i}() {{\n  requires I\n  initial i\n  final f\n  transition t {{ from i to f action O{i + 1}() }}\n}}"
            for i in range(n)]
    out.append(f"operation O{n}() {{\n  initial i\n  final f\n  transition t {{ from i to f }}\n}}")
    out.append("stm M {\n  requires I\n  initial i\n  state s { entry O0() }\n  transition t0 { from i to s }\n}")
    out.append("controller C {\n  requires I\n  sref m = M\n" + "".join(f"  opref o{i} = O{i}\n" for i in range(n + 1)) + "}")
    return "\n".join(out) + "\n"


def test_operations_calling_operations_past_the_limit_are_unsupported(tmp_path: Path) -> None:
    """Each call is inlined by a recursion: 300 deep crashed BMC; past the limit the assertion is
    unsupported, at the call that crosses it; up to it, both engines decide it."""
    deep = project(tmp_path / "deep", operation_chain(300), "assertion A: C is deadlock-free.\n")
    result = run_cli(["check", deep, "-k", "2", "--format", "json"])
    assert result.crash is None and result.exit_code == 20, result.output
    [r] = json.loads(result.stdout)["results"]
    assert r["verdict"] == "unsupported"
    assert f"operations calling operations more than {MAX_DECLARATION_CHAIN} deep are not encoded" in r["reason"]
    within = project(tmp_path / "within", operation_chain(MAX_DECLARATION_CHAIN - 2), "assertion A: C is deadlock-free.\n")
    for engine in ("bmc", "explicit"):
        result = run_cli(["check", within, "-k", "2", "--engine", engine, "--format", "json"])
        assert result.crash is None and json.loads(result.stdout)["results"][0]["verdict"] == "violated", result.output


def test_csp_definitions_chained_hundreds_deep_are_unsupported(tmp_path: Path) -> None:
    """P0 = P1, P1 = P2, …: evaluated by recursion, it crashed both engines; now that assertion is
    unsupported and the others are still checked."""
    chain = "\n".join(f"P{i} = P{i + 1}" for i in range(1000)) + "\nP1000 = M::e.out.1 -> P1000"
    block = f"timed csp P0 csp-begin\nTimed(OneStep) {{\n{chain}\n}}\ncsp-end\n"
    path = project(tmp_path, machine(), block + "assertion A: M refines P0 in the traces model.\n"
                                                "assertion B: M is deadlock-free.\n")
    for engine in ("bmc", "explicit"):
        result = run_cli(["check", path, "-k", "3", "--engine", engine, "--format", "json", *RANGE])
        assert result.crash is None and result.exit_code in (10, 20), result.output
        a, b = json.loads(result.stdout)["results"]
        assert a["verdict"] == "unsupported" and a["reason"] == TOO_DEEP_TO_CHECK
        assert b["verdict"] in ("holds", "violated")
