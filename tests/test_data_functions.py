"""Function types, `lambda`, set comprehensions, `s[i] = e` and the toolkit functions of
RoboChart's data language: each model's verdicts worked out by hand, decided by BMC and by the explicit
engine, which must agree."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import SHARED, both_engines

from tockbmc import ModelError, Project, load
from tockbmc.check import check
from tockbmc.explicit.engine import check_explicit
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

NAT03 = Ranges({"core_nat": Range(Fraction(0), Fraction(3))})

LAMBDAS = """\
stm M {
  var f : nat -> nat
  var g : nat * nat -> nat = lambda a : nat, b : nat @ a * b
  var x : nat = 0
  event e : nat
  initial i
  state S0 { }
  state S1 { }
  state Good { }
  state Bad { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to S1 trigger e?x action f = lambda y : nat @ y + x }
  transition t2 { from S1 to S1 trigger e?x }
  transition t3 { from S1 to Good condition f(2) == 5 /\\ x == 0 /\\ g(x, 3) == 0 }
  transition t4 { from S1 to Bad condition f(1) != x + 1 /\\ (let h == lambda z : nat @ z - 1 @ h(x)) > 2 }
}
"""
REACH = """\
assertion R1: Good is reachable in M.
assertion R2: Bad is reachable in M.
"""

COLLECTIONS = """\
import sequence_toolkit::*
import set_toolkit::*
import relation_toolkit::*
function inc(n : nat) : nat { postcondition result == n + 1 }
stm M {
  var s : Seq(nat) = <3, 1, 2, 0>
  var r : nat = 0
  var p : nat * boolean = (| 0, false |)
  initial i
  state S0 { }
  state Good { }
  state Bad { }
  transition t0 { from i to S0 action s[2] = 5 ; p[2] = true ; r = (override(inc, {(| 1, 7 |)}) as nat -> nat)(1) + inc(1) }
  transition t1 { from S0 to Good condition 3 in {x : nat | x in ran(s) /\\ x > 0} /\\ s == <3, 5, 2, 0> /\\
    p == (| 0, true |) /\\ r == 9 /\\ extract(union([2, 3], {1}), s) == <3, 5, 2> }
  transition t2 { from S0 to Bad condition 0 in {x : nat | x in ran(s) /\\ x > 0} \\/ 10 in {x : nat | x in ran(s) @ x * 2} }
}
"""


def _project(tmp_path: Path, model: str, assertions: str = "") -> Project:
    (tmp_path / "m.rct").write_text(model)
    if assertions:
        (tmp_path / "m.assertions").write_text(assertions)
    return load(tmp_path)


def _both(project: Project, names: list[str]) -> dict[str, Verdict]:
    bmc = {r.assertion: r for r in check(project, names, bound=10, ranges=NAT03, timeout=60)}
    for r in bmc.values():
        if r.verdict == Verdict.HOLDS and r.trace:
            assert r.extra["replayed"] == "yes"
    explicit = {r.assertion: r.verdict for r in check_explicit(project, names, 10, NAT03, {}, None)}
    assert explicit == {k: r.verdict for k, r in bmc.items()}
    return explicit


def test_a_lambda_keeps_the_values_it_read(tmp_path: Path) -> None:
    # t1 stores `y + x` with x = 3 (the input); t2 then inputs 0: f(2) is still 2 + 3 = 5, and
    # g(0, 3) = 0, so Good is reachable. Bad needs h(x) = x - 1 > 2, x >= 4: outside core_nat=0..3.
    project = _project(tmp_path, LAMBDAS, REACH)
    assert _both(project, ["R1", "R2"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED}


def test_comprehensions_indexed_assignment_override_and_extract(tmp_path: Path) -> None:
    # After t0: s = <3, 5, 2, 0>, p = (0, true), r = override(inc, {1 |-> 7})(1) + inc(1) = 7 + 2.
    # {x : nat | x in ran(s) /\ x > 0} within core_nat=0..3 is {3, 1, 2}: 3 is in it, 0 is not;
    # {x * 2 | x in ran(s)} is {6, 4, 0} (5 is outside core_nat), without 10. extract({1, 2, 3}, s)
    # is s's first three items.
    project = _project(tmp_path, COLLECTIONS, REACH)
    assert _both(project, ["R1", "R2"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED}


def test_min_of_a_set_in_the_explicit_engine(tmp_path: Path) -> None:
    model = COLLECTIONS.replace("r == 9 /\\\\", "r == 9 /\\\\ min(ran(s)) == 0 /\\\\ max(ran(s)) == 5 /\\\\")
    model = model.replace("r == 9 /\\", "r == 9 /\\ min(ran(s)) == 0 /\\ max(ran(s)) == 5 /\\")
    project = _project(tmp_path, model, REACH)
    explicit = {r.assertion: r.verdict for r in check_explicit(project, ["R1"], 10, NAT03, {}, None)}
    assert explicit == {"R1": Verdict.HOLDS}
    # BMC states min's postcondition as a quantified axiom: it finds the run, or says why not.
    [r] = check(project, ["R1"], bound=10, ranges=NAT03, timeout=3)
    assert r.verdict in (Verdict.HOLDS, Verdict.UNKNOWN)
    assert r.verdict == Verdict.HOLDS or r.reason


@pytest.mark.parametrize(("expression", "message"), [
    ("(lambda a : nat @ a + 1)(true)", "an argument must be nat, but this is boolean"),
    ("(lambda a : nat @ a + 1)(1, 2)", "takes 1 argument(s), but 2 given"),
    ("n(1)", "'n' is a variable of type int, not a function"),
    ("size({x : nat | x + 1})", "a condition must be boolean, but this is nat"),
])
def test_function_errors(tmp_path: Path, expression: str, message: str) -> None:
    model = f"""\
import sequence_toolkit::*
stm S {{
  var n : int = 0
  initial i
  state s {{ }}
  transition t0 {{ from i to s action n = {expression} }}
}}
"""
    with pytest.raises(ModelError) as info:
        _project(tmp_path, model)
    assert message in str(info.value)


def test_an_indexed_assignment_outside_the_sequence_is_not_interpreted(tmp_path: Path) -> None:
    # s[4] = 1 on a sequence of length 2: any sequence (as an index outside 1..#s has any value);
    # BMC reaches Any with some value, the explicit engine refuses to choose one.
    model = """\
stm M {
  var s : Seq(nat) = <1, 2>
  initial i
  state S0 { }
  state Any { }
  transition t0 { from i to S0 action s[4] = 1 }
  transition t1 { from S0 to Any }
}
"""
    project = _project(tmp_path, model, "assertion R1: Any is reachable in M.\n")
    [r] = check(project, ["R1"], bound=6, ranges=NAT03)
    assert r.verdict == Verdict.HOLDS
    [x] = check_explicit(project, ["R1"], 6, NAT03, {}, None)
    assert x.verdict == Verdict.UNSUPPORTED and "item 4 assigned in a sequence of length 2" in (x.reason or "")


REALWORLD = SHARED / "realworld"

# Public projects that load since function types, lambda, set comprehensions and `s[i] = e`
# (folder, what it uses); PROJECTS.txt excludes the generated `rc2rs/` and `normalForm/` copies.
NEWLY_LOADING = {
    "UoY-RoboStar+rc2rs-examples/Harvester": ("rc2rs/", "variables, events and functions of type Coord3D -> …"),
    "UoY-RoboStar+robochart-normalisation-tests/HarvesterProject": ("normalForm/", "the same Harvester"),
    "UoY-RoboStar+laptop-refurbishing-case-study/Concept/RoboChart": (None, "comprehensions, nat -> real * real, s[i] = e"),
    # its own copies of RoboTool's toolkits: generic functions whose text does not check with ?X unbound
    "laila-fangyan+RoboChart2Circus_2024/ChemicalDetector-autonomous-v4_fun_modified": (None, "generic toolkit copies"),
}


@pytest.mark.parametrize("folder", sorted(NEWLY_LOADING))
def test_public_projects_with_functions_and_comprehensions_load(folder: str) -> None:
    base = REALWORLD / folder
    if not base.is_dir():
        pytest.skip("the public projects are not here")
    excluded = NEWLY_LOADING[folder][0]
    files = [f for f in sorted(base.rglob("*")) if f.suffix in (".rct", ".assertions") and f.is_file()
             and not (excluded and f.relative_to(base).as_posix().startswith(excluded))]
    project = load(*files)
    assert project.machines


VECTORS = """\
stm V {
  const R : matrix(int, 2, 2) = [|0, -1; 1, 0|]
  var v : vector(int, 2) = [|1, 2|]
  var n : int = 0
  initial i
  state S0 { }
  state Good { }
  state Bad { }
  transition t0 { from i to S0 action v = R * v + [|1, 1|] ; n = v * v ; v[1] = -v[1] }
  transition t1 { from S0 to Good condition v == [|1, 2|] /\\ n == 5 /\\ R[2, 1] == 1 /\\ (R * R)[1, 1] == -1
    /\\ 2 * [|1, 2|] - [|0, 1|] == [|2, 3|] }
  transition t2 { from S0 to Bad condition not (v == [|1, 2|]) }
}
"""


def test_vectors_and_matrices_are_tuples_with_their_arithmetic(tmp_path: Path) -> None:
    # R * v = (0*1 - 1*2, 1*1 + 0*2) = (-2, 1); plus (1, 1): (-1, 2); n = v * v = 1 + 4 = 5; then
    # v[1] = 1, so v = (1, 2). R * R = -I, whose item (1, 1) is -1. Good is reachable, Bad is not.
    project = _project(tmp_path, VECTORS, REACH.replace("in M", "in V"))
    assert _both(project, ["R1", "R2"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED}


@pytest.mark.parametrize(("expression", "message"), [
    ("[|1, 2|] + [|1, 2, 3|]", "'+' needs two vectors or matrices of one shape"),
    ("[|1, 2; 3, 4|] * [|1, 2, 3|]", "'*' cannot multiply"),
    ("[|1, 2; 3|]", "the rows of a matrix have different lengths"),
])
def test_vector_errors(tmp_path: Path, expression: str, message: str) -> None:
    model = f"stm S {{\n  var n : int = 0\n  initial i\n  state s {{ }}\n  transition t0 {{ from i to s action n = ({expression})[1] }}\n}}\n"
    with pytest.raises(ModelError) as info:
        _project(tmp_path, model)
    assert message in str(info.value)


def test_a_set_range_is_the_integers_between_its_bounds(tmp_path: Path) -> None:
    # {1 to 3} = {1, 2, 3}: Good's condition holds at once; Bad's never.
    model = """\
stm M {
  var n : nat = 3
  initial i
  state S0 { }
  state Good { }
  state Bad { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to Good condition 2 in {1 to n} /\\ not (4 in {1 to n}) }
  transition t2 { from S0 to Bad condition 0 in {1 to n} }
}
"""
    project = _project(tmp_path, model, REACH)
    assert _both(project, ["R1", "R2"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED}


GENERIC = """
function pairs(x : ?X) : Set(?X * ?X) {
  postcondition result == {y : ?X | (|y, x|)}
}
function twice(x : ?X) : ?X * ?X {
  postcondition result == (|x, x|)
}
stm M {
  event out : int * int
  initial i
  state s { entry out!twice(1) }
  transition t0 { from i to s }
}
"""


def test_a_generic_function_is_checked_where_it_is_called(tmp_path: Path) -> None:
    """RoboTool's own relation_toolkit has `id() … {x : ?X | maplet(x, x)}`, whose condition is not
    boolean: with ?X unbound the text of a generic function is not checked (`pairs`, never called,
    loads); an instance is (`twice(1)` works), and an instance whose conditions do not type-check
    makes the checks that call it unsupported, with the error at its text."""
    (tmp_path / "m.rct").write_text(GENERIC)
    project = load(tmp_path)
    assert [f.name for f in project.functions if f.name.startswith("twice")]
    (tmp_path / "m.rct").write_text(GENERIC.replace("entry out!twice(1)", "entry out!(|1, 1|); x = pairs(1)")
                                    .replace("event out : int * int", "event out : int * int\n  var x : Set(int * int)"))
    (tmp_path / "m.assertions").write_text("assertion D : M is deadlock-free\n")
    project = load(tmp_path)
    [d] = check(project, ["D"], timeout=30)
    assert d.verdict == Verdict.UNSUPPORTED and "m.rct:3" in (d.reason or "") \
        and "condition must be boolean" in (d.reason or ""), d.reason


def test_a_function_whose_conditions_do_not_type_check_loads(tmp_path: Path) -> None:
    """turtlebot-robochart-move-composite (AURO): `postcondition result == v < c` is
    `(result == v) < c` in RoboChart's left-associative comparisons, and RoboTool does not check
    types in a function's conditions, so it loads there.  It loads here too; a call of the function
    is unsupported, with the type error, in both engines, and what does not call it is checked."""
    (tmp_path / "m.rct").write_text("""
function lt(v : real, c : real) : boolean {
  postcondition result == v < c
}
stm Uses {
  var x : real = 0
  event e
  initial i
  state s {}
  transition t0 { from i to s }
  transition t1 { from s to s trigger e condition lt(x, 1) }
}
stm Other {
  initial i
  state s {}
  transition t0 { from i to s }
}
""")
    (tmp_path / "m.assertions").write_text("assertion U : Uses is deadlock-free\nassertion O : Other is timelock-free\n")
    project = load(tmp_path)
    ranges = Ranges({"core_real": Range(Fraction(0), Fraction(1))})
    symbolic = {r.assertion: r for r in check(project, ranges=ranges, timeout=30)}
    concrete = {r.assertion: r for r in check_explicit(project, None, 8, ranges, {}, 30, 10_000)}
    for results in (symbolic, concrete):
        assert results["U"].verdict == Verdict.UNSUPPORTED, results["U"].reason
        assert "lt's conditions do not type-check" in (results["U"].reason or "")
        assert "m.rct:3" in (results["U"].reason or "")
        assert results["O"].verdict == Verdict.HOLDS, results["O"].reason



SUFFIXES = """\
import sequence_toolkit::*
import set_toolkit::*
stm M {
  var s : Seq(nat) = <1, 2, 3>
  var a : Set(nat) = {1, 2}
  event e : nat
  var x : nat = 0
  initial i
  state S0 { }
  state Good { }
  state Bad { }
  state Odd { }
  state Empty { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to Good trigger e?x condition suffix(<2, 3>, s) /\\ infix(<x, 3>, s) }
  transition t2 { from S0 to Bad condition suffix(<1, 2>, s) \\/ infix(<1, 3>, s) \\/ infix(<3, 2>, s) }
  transition t3 { from S0 to Odd trigger e?x condition symetric_diff(a, {x}) == {1, 2, 3} /\\ suffix(<x>, s) }
  transition t4 { from S0 to Empty trigger e?x condition symetric_diff(a, {x}) == {} }
}
"""


def test_suffix_infix_and_symmetric_difference(tmp_path: Path) -> None:
    # sequence_toolkit: suffix(s, t) iff some u has u ^ s == t; infix(s, t) iff some u, v have
    # u ^ s ^ v == t; set_toolkit's symetric_diff(a, b) holds the members of exactly one.
    # Good: <2, 3> ends <1, 2, 3>, and <x, 3> is a stretch of it for x = 2.  Bad: <1, 2> does not
    # end s, and neither <1, 3> nor <3, 2> is a stretch of it.  Odd: {1, 2} and {x} differ in
    # {1, 2, 3} for x = 3, and <3> ends s.  Empty: {1, 2} and a singleton always differ.
    project = _project(tmp_path, SUFFIXES, "".join(f"assertion R{n}: {s} is reachable in M.\n"
                                                   for n, s in enumerate(("Good", "Bad", "Odd", "Empty"), 1)))
    assert _both(project, ["R1", "R2", "R3", "R4"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED,
                                                        "R3": Verdict.HOLDS, "R4": Verdict.VIOLATED}


RECORD_CONDITIONS = """\
datatype R { w : nat  h : nat }
function area(r : R) : nat {
  precondition r.w > 0
  postcondition result == r.w * r.h
}
function bigger(r : R) : nat {
  precondition r.w > 0
  postcondition result > r.h
}
stm M {
  event out : nat
  var r : R = R (| w = 2, h = 3 |)
  var a : nat = 0
  var b : nat = 0
  initial i
  state S { }
  state Small { }
  transition t0 { from i to S action a = area(r) ; b = bigger(r) }
  transition t1 { from S to Small condition a != 6 \\/ b <= 3 }
}
"""


def test_a_function_whose_conditions_read_a_record_parameter(tmp_path: Path) -> None:
    """Laptop-refurbishing's `checkImage(image : ImageData, …)` has the precondition
    `size(image.pixels) == image.height`: BMC passed the record to the conditions in its datatype,
    where `image.pixels` failed (AssertionError, exit 1).  By hand: r = (w=2, h=3) meets both
    preconditions, so area(r) = 6 and bigger(r) > 3, and Small is never reached (BMC; the
    interpreter cannot run `bigger`, which has no body)."""
    (tmp_path / "m.rct").write_text(RECORD_CONDITIONS)
    (tmp_path / "m.assertions").write_text("assertion A: Small is not reachable in M.\n")
    [r] = check(load(tmp_path), bound=8)
    assert r.verdict == Verdict.HOLDS, r.reason


def test_a_function_value_s_result_type_binds_only_the_step_that_applies_it(tmp_path: Path) -> None:
    """`f : nat -> nat = lambda x : nat @ x - 5` applied only on a transition never taken: BMC had
    asserted `f(y + 1) >= 0` at every step, which with y = 0 cut every run (deadlock-free was proved,
    dead unreachable). It is now a condition of the step that applies it."""
    (tmp_path / "m.rct").write_text("""
stm M {
  var f : nat -> nat = lambda x : nat @ x - 5
  var y : int = 0
  var n : nat = 0
  event e
  initial i
  state s {}
  state dead {}
  state t {}
  transition t0 { from i to s }
  transition t1 { from s to dead condition y == 0 }
  transition t2 { from s to t trigger e condition y > 10 action n = f(y + 1) }
}
""")
    (tmp_path / "m.assertions").write_text("assertion D: M is deadlock-free.\nassertion R: dead is reachable in M.\n")
    ranges = Ranges({"core_int": Range(Fraction(-3), Fraction(3)), "core_nat": Range(Fraction(0), Fraction(3))})
    bmc, explicit = both_engines(load(tmp_path), ranges, 10, timeout=30)
    for results in (bmc, explicit):
        assert {r.assertion: r.verdict for r in results} == {"D": "violated", "R": "holds"}


@pytest.mark.parametrize("where", [
    "condition y > 10 /\\ (forall z : nat | z < 2 @ f(z + y) >= 0)",
    "condition y > 10 /\\ (exists z : nat | z < 2 @ f(z + y) == 0)",
    "condition y > 10 action s2 = {z : nat | z < 2 @ f(z + y)}",
    "condition y > 10 action s2 = {z : nat | z < 2 /\\ f(z + y) > 0}",
    "condition y > 10 action n = g(f, y + 1)",
    "condition y > 10 action out!f(y + 1)",
])
def test_a_function_value_applied_in_a_nested_scope_binds_only_its_step(tmp_path: Path, where: str) -> None:
    """The same, applied inside a quantifier, a set comprehension, a function's body or an
    output's value: BMC had still asserted the result's type at every step there (a known
    difference then, docs/semantics.md §10); it is now a condition of the step that evaluates it,
    for every value of the bound variables where the scope is evaluated."""
    (tmp_path / "m.rct").write_text(f"""
function g(h : nat -> nat, a : int) : nat {{ postcondition result == h(a) }}
stm M {{
  var f : nat -> nat = lambda x : nat @ x - 5
  var y : int = 0
  var n : nat = 0
  var s2 : Set(nat)
  event e
  event out : nat
  initial i
  state s {{}}
  state dead {{}}
  state t {{}}
  transition t0 {{ from i to s }}
  transition t1 {{ from s to dead condition y == 0 }}
  transition t2 {{ from s to t trigger e {where} }}
}}
""")
    (tmp_path / "m.assertions").write_text("assertion D: M is deadlock-free.\nassertion R: dead is reachable in M.\n")
    ranges = Ranges({"core_int": Range(Fraction(-3), Fraction(3)), "core_nat": Range(Fraction(0), Fraction(3))})
    bmc, _explicit = both_engines(load(tmp_path), ranges, 10, timeout=30)
    assert {r.assertion: r.verdict for r in bmc} == {"D": "violated", "R": "holds"}


@pytest.mark.parametrize(("condition", "reachable"), [
    ("exists f : nat -> nat @ f(0) == 3", "holds"),
    ("forall f : nat -> nat @ f(0) >= 0", "holds"),
    ("forall f : nat -> nat @ f(0) == 0", "violated"),
    ("exists f : nat -> nat @ f(0) < 0", "violated"),
    # assumed by the scope binding f, not the innermost one (which would give a wrong `holds`)
    ("exists f : nat -> nat @ forall x : nat @ f(x) < 0", "violated"),
    ("exists f : nat -> nat @ not (exists x : nat @ f(x) >= 0)", "violated"),
    ("exists f : nat -> nat @ {x : nat | f(x) >= 0} == {}", "violated"),
    # ... and through a function's parameter or a `let` (wrong `violated`)
    ("exists f : nat -> nat @ g(f, 0) == 1", "holds"),
    ("exists f : nat -> nat @ (let h == f @ h(0) == 1)", "holds"),
])
def test_a_quantified_function_ranges_over_the_functions_into_its_type(tmp_path: Path, condition: str,
                                                                       reachable: str) -> None:
    """`exists f : nat -> nat @ f(0) == 3`: the result's type was asserted for every f (false in
    Z3, whose arrays hold any integers) as an axiom or a condition of the step, so the transition
    never fired. It is now assumed by the quantifier, as its domain is."""
    (tmp_path / "m.rct").write_text(f"""
function g(h : nat -> nat, a : nat) : nat {{ postcondition result == h(a) }}
stm M {{
  initial i
  state s {{}}
  state good {{}}
  transition t0 {{ from i to s }}
  transition t1 {{ from s to good condition {condition} }}
}}
""")
    (tmp_path / "m.assertions").write_text("assertion R: good is reachable in M.\n")
    [r] = check(load(tmp_path), bound=5, timeout=90)  # `forall f @ f(0) == 0`: 8 s idle, 25 s beside other work
    assert r.verdict == reachable, r.reason


@pytest.mark.parametrize("condition", ["f(0) >= 0", "g(f, 0) >= 0", "(let h == f @ h(0) >= 0)"])
def test_a_function_nobody_set_gives_results_in_its_type_wherever_it_is_applied(tmp_path: Path,
                                                                                condition: str) -> None:
    """`var f : nat -> nat` without a value is any function into nat: `e` is always offered. Passed
    to a function's parameter or named by a `let`, its result's type had become a condition of the
    step, and BMC chose f(0) = -1 to block it (a wrong `violated`); applied
    directly, the replay of the divergence check had ended in an internal error."""
    (tmp_path / "m.rct").write_text(f"""
function g(h : nat -> nat, a : nat) : int {{ postcondition result == h(a) }}
stm M {{
  var f : nat -> nat
  event e
  initial i
  state s {{}}
  state bad {{}}
  transition t0 {{ from i to s }}
  transition t1 {{ from s to s trigger e condition {condition} }}
  transition t2 {{ from s to bad condition f(1) < 0 }}
}}
""")
    (tmp_path / "m.assertions").write_text("assertion D: M is deadlock-free.\nassertion N: bad is not reachable in M.\n")
    results = check(load(tmp_path), bound=6, timeout=30)
    assert [r.verdict for r in results] == ["holds", "holds"], [r.reason for r in results]


@pytest.mark.parametrize("transition", ["trigger e <{1} condition f(y) == 0", "trigger e <{f(y)}"])
def test_a_function_value_applied_in_a_trigger_deadline_is_unsupported(tmp_path: Path, transition: str) -> None:
    """Its result's type was made a condition of every configuration at the source, which cut the
    step into it (`s is reachable` violated); it would be a condition of the
    tock, which the deadline's counting does not carry."""
    (tmp_path / "m.rct").write_text(f"""
stm M {{
  var f : nat -> nat = lambda x : nat @ x - 5
  var y : nat = 0
  event e
  initial i
  state s {{}}
  state good {{}}
  transition t0 {{ from i to s }}
  transition t1 {{ from s to good {transition} }}
}}
""")
    (tmp_path / "m.assertions").write_text("assertion R: s is reachable in M.\n")
    [r] = check(load(tmp_path), bound=6, timeout=30)
    assert r.verdict == "unsupported" and "trigger deadline" in (r.reason or ""), r.reason


def test_the_explicit_engine_keeps_a_result_in_the_type_of_the_place_applied(tmp_path: Path) -> None:
    """`nat -> nat = lambda x : nat @ x - 5` applied to 1: the interpreter checked the lambda's own
    range (int) and went on with -4, where BMC keeps the result in nat."""
    (tmp_path / "m.rct").write_text("""
stm M {
  var f : nat -> nat = lambda x : nat @ x - 5
  var y : nat = 1
  initial i
  state s {}
  state good {}
  transition t0 { from i to s }
  transition t1 { from s to good condition f(y) == -4 }
}
""")
    (tmp_path / "m.assertions").write_text("assertion R: good is reachable in M.\n")
    ranges = Ranges({"core_int": Range(Fraction(-6), Fraction(6)), "core_nat": Range(Fraction(0), Fraction(6))})
    [r] = check_explicit(load(tmp_path), None, 6, ranges, {}, 30, 10_000)
    assert r.verdict == "unsupported" and "outside its type nat" in (r.reason or ""), r.reason


RANGES = """\
import sequence_toolkit::*
stm M {
  var s : Seq(int) = <>
  var t : Seq(int) = <>
  initial i
  state S0 { }
  state Good { }
  state Bad { }
  transition t0 { from i to S0 action s = range(1, 3) ; t = range(2, -1) }
  transition t1 { from S0 to Good condition s == <1, 2, 3> /\\ t == <> /\\ size(range(0, 0)) == 1 }
  transition t2 { from S0 to Bad condition head(s) != 1 \\/ size(t) > 0 }
}
stm N {
  var n : nat = 0
  event e : nat
  initial i
  state S0 { }
  state Chosen { }
  transition t0 { from i to S0 }
  transition t1 { from S0 to Chosen trigger e?n condition size(range(1, n)) == 2 }
}
"""


def test_range_is_the_sequence_of_the_integers_between_its_bounds(tmp_path: Path) -> None:
    # sequence_toolkit's range(x, y) : Seq(int) is <x, …, y>, empty when y < x: Good is reachable,
    # Bad is not.  N's Chosen needs range(1, n) with n an input, a sequence of a length the run
    # picks: the explicit engine computes it (n = 2), BMC reports N's assertion unsupported, and
    # still decides M's.
    project = _project(tmp_path, RANGES, "assertion R1: Good is reachable in M.\n"
                       "assertion R2: Bad is reachable in M.\nassertion R3: Chosen is reachable in N.\n")
    assert _both(project, ["R1", "R2"]) == {"R1": Verdict.HOLDS, "R2": Verdict.VIOLATED}
    bmc = {r.assertion: r for r in check(project, ["R3"], bound=10, ranges=NAT03, timeout=60)}
    assert bmc["R3"].verdict == Verdict.UNSUPPORTED
    assert "range(x, y) whose bounds are not constants" in (bmc["R3"].reason or "")
    explicit = {r.assertion: r.verdict for r in check_explicit(project, ["R3"], 10, NAT03, {}, None)}
    assert explicit == {"R3": Verdict.HOLDS}
