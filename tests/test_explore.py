"""`tockbmc explore`: regions of ranges and constants, checked against `check` at points inside and outside."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import jsonschema
import pytest
from click.testing import CliRunner

import tockbmc
from tockbmc.check import check
from tockbmc.cli import cli
from tockbmc.explore import explore
from tockbmc.model.ranges import Range
from tockbmc.model.result import Verdict
from tockbmc.report.explore import schema

MODELS = Path(__file__).parent / "models" / "explore"
EXAMPLE = Path(__file__).parents[1] / "examples" / "intelliwelder"


@pytest.fixture(scope="module")
def project() -> tockbmc.Project:
    return tockbmc.load(MODELS)


@pytest.fixture(scope="module")
def found(project: tockbmc.Project) -> dict:
    return {e.assertion: e for e in explore(project, timeout=60)}


def verdict(project: tockbmc.Project, name: str, ranges: dict | None = None, settings: dict | None = None) -> Verdict:
    [r] = check(project, [name], ranges={k: Range(Fraction(lo), Fraction(hi)) for k, (lo, hi) in
                                                 (ranges or {}).items()}, settings=settings, timeout=60)
    return r.verdict


def test_threshold_guard_region_is_the_upper_bound(project: tockbmc.Project, found: dict) -> None:
    """`e?x` with `x > 5` ends the machine: violated exactly when core_int's upper bound reaches 6."""
    e = found["T"]
    assert (e.status, e.inside, e.condition, e.reach) == ("region", "violated", "core_int.high ≥ 6", "every length")
    assert e.independent == ("core_int.low",)
    assert [(c.event, c.condition) for c in e.carried] == [("Threshold::e.in", "value ≥ 6")]
    assert e.replayed == "yes" and e.trace[-1].event == "Threshold::terminate"
    assert verdict(project, "T", {"core_int": (0, 6)}) == Verdict.VIOLATED  # inside
    assert verdict(project, "T", {"core_int": (-3, 5)}) == Verdict.HOLDS  # outside


def test_two_interacting_constants(project: tockbmc.Project, found: dict) -> None:
    """Constants without a value are parameters; the region relates the two."""
    e = found["P"]
    assert e.condition == "Pair::a + Pair::b > 3 and Pair::a < Pair::b"
    assert set(e.independent) == {"core_int.low", "core_int.high"}
    assert int(e.point["Pair::a"]) < int(e.point["Pair::b"])  # the example is a point inside
    for a, b, inside in [(1, 3, True), (0, 5, True), (2, 2, False), (3, 1, False), (-1, 4, False)]:
        expected = Verdict.VIOLATED if inside else Verdict.HOLDS
        assert verdict(project, "P", {"core_int": (-5, 5)}, {"Pair::a": str(a), "Pair::b": str(b)}) == expected, (a, b)


def test_one_field_matters_and_the_other_does_not(project: tockbmc.Project, found: dict) -> None:
    e = found["F"]
    assert e.condition == "core_int.low ≤ -1"
    assert {c.field: c.condition for c in e.carried} == {"time": "time ≤ -1", "dist": "any"}
    assert verdict(project, "F", {"core_int": (-1, 0)}) == Verdict.VIOLATED
    assert verdict(project, "F", {"core_int": (0, 4)}) == Verdict.HOLDS


def test_a_witness_gives_the_region_where_the_assertion_holds(found: dict) -> None:
    e = found["R"]
    assert (e.inside, e.condition) == ("holds", "core_int.high ≥ 6")


def test_forms_explore_does_not_decide_are_unsupported_with_the_reason(found: dict) -> None:
    e = found["D"]
    assert e.status == "unsupported" and "two runs" in e.reason and e.pos.endswith("explore.assertions:5:11")


def test_param_names_a_range_or_a_constant(project: tockbmc.Project) -> None:
    [e] = explore(project, ["P"], params=["Pair::a"], settings={"Pair::b": "4"}, timeout=60)
    assert e.parameters == ("Pair::a",) and e.condition == "0 ≤ Pair::a ≤ 3"  # a + 4 > 3 and a < 4
    assert e.fixed_here == {} and e.fixed["Pair::b"] == "4"
    [e] = explore(project, ["T"], params=["core_int"], ranges={"core_int": Range(Fraction(0), Fraction(1))},
                  timeout=60)
    assert e.condition == "core_int.high ≥ 6"  # --param wins over the range given


def test_unknown_param_is_a_usage_error_with_a_suggestion() -> None:
    out = CliRunner().invoke(cli, ["explore", str(MODELS), "--param", "core_itn"])
    assert out.exit_code == 2 and "core_int" in out.output


def test_json_follows_its_schema() -> None:
    out = CliRunner().invoke(cli, ["explore", str(MODELS), "--format", "json", "-a", "T", "-a", "D"])
    assert out.exit_code == 20, out.output  # D is unsupported
    doc = json.loads(out.output)
    jsonschema.validate(doc, schema())
    assert [e["status"] for e in doc["explorations"]] == ["region", "unsupported"]


def test_the_readme_question_negative_times_break_a1_to_a6_and_a7_always_holds() -> None:
    """The paper's question, answered directly (the README's example)."""
    project = tockbmc.load(EXAMPLE)
    found = {e.assertion: e for e in explore(project, ranges={"core_real": Range(Fraction(-1), Fraction(1))},
                                             timeout=120)}
    for name in ("A1", "A2", "A3", "A4", "A5", "A6"):
        e = found[name]
        assert (e.condition, e.reach, e.replayed) == ("core_int.low ≤ -1", "every length", "yes"), name
        assert "core_int.high" in e.independent
        assert any(c.field == "time" and c.condition == "time ≤ -1" for c in e.carried)
    assert found["A7"].condition == "false" and found["A7"].reach == "every length"


def test_outside_the_region_an_invariant_proves_it_for_every_length(found: dict) -> None:
    """Drift adds inputs to x and stops below 0: k-induction cannot show the complement, PDR can."""
    e = found["G"]
    assert (e.condition, e.reach) == ("core_int.low ≤ -1", "every length") and "invariant" in e.proof


def test_spacer_does_not_choose_a_parametric_bound(project: tockbmc.Project) -> None:
    """The bounds of a parametric range are carried by PDR's relation like constants: left free in the
    Horn clauses, Spacer could pick a harmless range (low = 0) and call the target unreachable."""
    from dataclasses import replace

    from tockbmc.bmc.pdr import Spacer
    from tockbmc.encodings.composition import network_of
    from tockbmc.encodings.system import TransitionSystem
    from tockbmc.model.config import configure
    from tockbmc.properties.queries import query

    config = configure(project)
    [a] = [x for x in config.project.assertions if x.name == "G"]
    q = query(config.project, a)
    setup = config.setup(a, q.element, q.settings)
    system = TransitionSystem(network_of(q.element, {}), replace(setup.ranges, parametric=("core_int",)),
                              setup.constants, context=q.context)
    [goal] = q.goals
    assert Spacer(system, goal.target(system)).run(30) == "reachable"


def test_conditions_read_as_the_model_names_them() -> None:
    import z3

    from tockbmc.bmc.regions import condition_text

    lo, hi, r = z3.Int("lo"), z3.Int("hi"), z3.Real("r")
    names = {"lo": "core_int.low", "hi": "core_int.high", "r": "limit"}
    assert condition_text([[z3.Not(0 <= lo)]], names, {"lo", "hi"}) == "core_int.low ≤ -1"
    assert condition_text([[lo > -5, lo < 3, lo <= hi]], names, {"lo", "hi"}) == \
        "-4 ≤ core_int.low ≤ 2 and core_int.low ≤ core_int.high"
    assert condition_text([[r < hi - z3.RealVal("1/2")], [lo == 2]], names, {"lo", "hi"}) == \
        "limit < core_int.high - 0.5 or core_int.low = 2"
    assert condition_text([], names, set()) == "false" and condition_text([[]], names, set()) == "true"
    # what is not one comparison (a disjunction inside a cube, a product): the model's names, not Z3's
    assert condition_text([[lo > -5, z3.Or(hi == 1, z3.Not(r * r <= 2))]], names, {"lo", "hi"}) == \
        "core_int.low ≥ -4 and (core_int.high = 1 or limit · limit > 2)"
    assert condition_text([[z3.Not(z3.And(lo - (hi - 1) == 2 * (lo + 1), z3.Implies(lo > 0, hi % 2 == 0)))]], names,
                          set()) == "not (core_int.low - (core_int.high - 1) = 2 · (core_int.low + 1) and " \
                                    "(core_int.low > 0 ⇒ core_int.high mod 2 = 0))"


def test_a_computation_cut_short_says_so(project: tockbmc.Project) -> None:
    """Out of time: the region found so far is certain, the outside is not known, and it is said."""
    [e] = explore(project, ["G"], timeout=0.001)
    assert e.status == "unknown" and e.reach == "partial" and e.reason


def test_an_untimed_assertion_is_explored_in_the_untimed_semantics(tmp_path: Path) -> None:
    """An untimed refinement: explore built the timed system, so its counterexample had a tock the
    untimed interpreter could not follow (ReplayFailure, exit 1).  With no parameters it is violated
    everywhere, by the inputs that are not 0; the example has no tock and is replayed."""
    (tmp_path / "m.rct").write_text("""
stm M {
  event a : int
  event b : int
  var x : int = 0
  initial i
  state s {}
  state t { entry b!x }
  transition t0 { from i to s }
  transition t1 { from s to t trigger a?x }
  transition t2 { from t to s }
}
""")
    (tmp_path / "m.assertions").write_text("""
untimed csp S csp-begin
S = M::a.in?y -> M::b.out.0 -> S
csp-end
untimed assertion U : M refines S in the traces model
""")
    [e] = explore(tockbmc.load(tmp_path), ranges={"core_int": Range(Fraction(-2), Fraction(2))}, timeout=60)
    assert e.status == "region", e.reason
    assert e.condition == "true" and e.reach == "every length", (e.condition, e.reach)
    [carried] = e.carried
    assert carried.condition == "-2 ≤ value ≤ -1 or 1 ≤ value ≤ 2", carried
    shown = [s.event for s in e.trace if s.kind != "internal"]
    assert "tock" not in shown and shown[-1].startswith("M::b.out."), shown


WITNESS_MODEL = """
function g(x : int) : int { }
stm V {
  const k : int
  var x : int = 0
  initial i
  state a {}
  state c {}
  transition t0 { from i to a }
  transition t1 { from a to a condition x < k action x = x + 1 }
  transition t2 { from a to c condition x >= k }
}
stm U {
  const k : int
  initial i
  junction j
  state s {}
  final f
  transition tj { from i to j }
  transition t0 { from j to f condition g(k) == 1 }
  transition t1 { from j to s condition g(k) != 1 }
}
"""


def test_no_witness_within_the_bound_decides_nothing(tmp_path: Path) -> None:
    """`c is reachable in V` holds for every k, reached after max(k, 0) internal steps: within 6 steps
    only for k ≤ 2. The region says where a witness was found, and nothing of the rest (it read
    "holds ⇔ k ≤ 2, exact for runs of up to 6 steps", as if k = 8 were a violation)."""
    (tmp_path / "m.rct").write_text(WITNESS_MODEL)
    (tmp_path / "m.assertions").write_text("assertion R1: c is reachable in V.\n")
    [e] = explore(tockbmc.load(tmp_path), bound=6, ranges={"core_int": Range(Fraction(0), Fraction(10))}, timeout=60)
    assert (e.status, e.inside, e.condition, e.reach) == ("unknown", "holds", "V::k ≤ 2", "partial")
    assert "no witness within 6 steps" in e.reason
    out = CliRunner().invoke(cli, ["explore", str(tmp_path), "-k", "6", "--range", "core_int=0..10"]).output
    assert "holds where V::k ≤ 2" in out and "outside it, nothing is known" in out and "⇔" not in out


def test_functions_without_a_body_make_regions_unsupported(tmp_path: Path) -> None:
    """A region over `g(k)` is not a set of values of k (such as `holds ⇔ 1 == g(U::k)`)."""
    (tmp_path / "m.rct").write_text(WITNESS_MODEL)
    (tmp_path / "m.assertions").write_text("assertion R1: f is reachable in U.\nassertion R2: U is deadlock-free.\n")
    for e in explore(tockbmc.load(tmp_path), ranges={"core_int": Range(Fraction(-1), Fraction(1))}, timeout=60):
        assert e.status == "unsupported" and "functions without a body (g)" in e.reason, e


def test_a_model_without_assertions_explores_the_core_assertions(tmp_path: Path) -> None:
    """As `check` does (rather than printing `parameters: none` and nothing else)."""
    (tmp_path / "m.rct").write_text("stm M {\n  initial i\n  state s {}\n  transition t0 { from i to s }\n}\n")
    out = CliRunner().invoke(cli, ["explore", str(tmp_path), "--format", "json"])
    assert out.exception is None or isinstance(out.exception, SystemExit), out.output
    assert "exploring RoboTool's core assertions" in out.stderr
    names = [e["assertion"] for e in json.loads(out.stdout)["explorations"]]
    assert names == ["M_deadlock_free", "M_deterministic", "M_divergence_free", "M_timelock_free"]
