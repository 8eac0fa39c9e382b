"""Functions an instantiation defines in CSPm, as RoboTool's own suite writes them: clauses matched
against sequence patterns, recursion, local functions of a `let`, a datatype's fields read by
RoboTool's names, and comparisons of a given type's values (tockbmc/model/instantiation.py).

Each is unfolded into the model function's body, so both engines run it; where the unfolding stops
(a sequence longer than it goes) or no clause matches, the function is any function there, and a
verdict that rests on it says so.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from conftest import both_engines, verdicts_are, write_files

import tockbmc
from tockbmc.model.config import configure
from tockbmc.model.ranges import Range, Ranges

RCT = """
datatype G { c : nat  i : nat }
type Level
function total(s : Seq(nat)) : nat { }
function lastOf(s : Seq(nat)) : nat { }
function peak(s : Seq(G)) : nat { }
function atLeast(a : Level, b : Level) : boolean { }
stm M {
  var s : Seq(nat) = <3, 1, 2>
  var g : Seq(G) = <G(| c = 0, i = 2 |), G(| c = 1, i = 5 |), G(| c = 0, i = 4 |)>
  var long : Seq(nat) = <1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1>
  const lo : Level
  const hi : Level
  initial i
  state A {}
  state Right {}
  state Wrong {}
  state Long {}
  transition t0 { from i to A }
  transition t1 { from A to Right condition total(s) == 6 /\\ lastOf(s) == 2 /\\ peak(g) == 5 /\\ atLeast(hi, lo) }
  transition t2 { from A to Wrong condition not (total(s) == 6 /\\ lastOf(s) == 2 /\\ peak(g) == 5 /\\ atLeast(hi, lo)) }
  transition t3 { from A to Long condition total(long) == 12 }
}
"""

INSTANTIATION = """csp Instantiations csp-begin
nametype Level = {0..2}
const_M_lo = 0
const_M_hi = 2
total(<>) = 0
total(<x>^xs) = x + total(xs)
lastOf(xs^<x>) = x
peak(s) = let
  aux(<>, m) = m
  aux(<x>^xs, m) = if G_i(x) > m then aux(xs, G_i(x)) else aux(xs, m)
within aux(s, 0)
atLeast(a, b) = a >= b
csp-end
"""

# Where a function is open, the explicit engine lists its values: naturals up to 15.
NAT = Ranges({"core_nat": Range(Fraction(0), Fraction(15))})
ASSERTIONS = INSTANTIATION + """assertion Right: M::Right is reachable in M.
assertion Wrong: M::Wrong is reachable in M.
"""


def _project(tmp_path: Path, assertions: str = ASSERTIONS) -> tockbmc.Project:
    return tockbmc.load(write_files(tmp_path, {"m.rct": RCT, "m.assertions": assertions}))


def test_recursive_and_local_functions_over_sequences_are_understood(tmp_path: Path) -> None:
    config = configure(_project(tmp_path))
    assert not [w for w in config.warnings if "uninterpreted" in w.message], config.warnings
    functions = {f.name: f for f in config.project.functions}
    for name in ("total", "lastOf", "peak", "atLeast"):
        assert functions[name].definition is not None, name
    assert not functions["atLeast"].preconditions  # one clause, no recursion: defined everywhere
    # `total` is defined as far as its unfolding goes (and `lastOf` where its pattern matches)
    assert functions["total"].preconditions and functions["lastOf"].preconditions


def test_both_engines_compute_what_the_csp_computes(tmp_path: Path) -> None:
    verdicts_are(_project(tmp_path), NAT, 12, {"Right": "holds", "Wrong": "violated"})


def test_a_sequence_longer_than_the_unfolding_leaves_the_function_open_there(tmp_path: Path) -> None:
    project = _project(tmp_path, INSTANTIATION + "assertion Long: M::Long is reachable in M.\n")
    bmc, explicit = both_engines(project, NAT, 12)
    for r in (*bmc, *explicit):
        assert r.verdict == "unknown", (r.engine, r.verdict, r.reason)
        assert "total" in (r.reason or ""), (r.engine, r.reason)


def test_a_clause_that_matches_nothing_is_not_a_definition_everywhere(tmp_path: Path) -> None:
    """`lastOf(<>)` matches no clause: CSPm stops there, so tockbmc takes any value."""
    rct = RCT.replace("condition total(long) == 12", "condition lastOf(<>) == 7")
    project = tockbmc.load(write_files(tmp_path, {
        "m.rct": rct, "m.assertions": INSTANTIATION + "assertion Long: M::Long is reachable in M.\n"}))
    bmc, explicit = both_engines(project, NAT, 12)
    for r in (*bmc, *explicit):
        assert r.verdict == "unknown" and "lastOf" in (r.reason or ""), (r.engine, r.verdict, r.reason)


def test_what_is_not_understood_is_named_and_the_function_stays_open(tmp_path: Path) -> None:
    bad = INSTANTIATION.replace("lastOf(xs^<x>) = x", "lastOf(xs) = { x | x <- xs }")
    config = configure(_project(tmp_path, bad + "assertion Right: M::Right is reachable in M.\n"))
    [warning] = [w for w in config.warnings if "lastOf" in w.message]
    assert "a set cannot be a function body" in warning.message and warning.pos.line == 7
