"""Numbers nest inside containers as RoboTool's type checker has them: a `Seq(nat)` value is
accepted where a `Seq(real)` is expected (and so in sets and tuples), converted by a cast that both
engines encode; function types do not widen (docs/language.md §3)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from conftest import verdicts_are, write_files

from tockbmc import ModelError, load
from tockbmc.check import check
from tockbmc.model import ast
from tockbmc.model.ranges import Range, Ranges
from tockbmc.model.result import Verdict

SMALL = Ranges({"core_nat": Range(Fraction(0), Fraction(3)), "core_int": Range(Fraction(-3), Fraction(3))})

# Each state after A is reached only if the converted values are the integers' own: `Wrong` if a
# conversion lost or changed an item.
SEQUENCES = """\
import sequence_toolkit::*
function second(q : Seq(real)) : real {
  postcondition result == q[2]
}
datatype Pt {
  x : real
  ys : Seq(real)
}
stm M {
  var s : Seq(nat) = <1, 2>
  var r : Seq(real) = <>
  var n : nat = 3
  var z : real = 0
  var p : Pt = Pt(| x = 0, ys = <> |)
  var pair : Seq(real) * real = (| <>, 0 |)
  event out : Seq(real)
  event back : Seq(real)
  initial i
  state A { }
  state Sent { }
  state Two { }
  state Equal { }
  state Rec { }
  state Wrong { }
  transition t0 { from i to A action r = s ; z = second(s) ; p = Pt(| x = n, ys = s |) ; pair = (| s, n |) }
  transition t1 { from A to Sent action out!s }
  transition t2 { from Sent to Two condition r[2] == 2 /\\ z == 2 /\\ size(r) == 2 }
  transition t3 { from Two to Equal condition r == s /\\ s == r /\\ s as Seq(real) == r /\\ pair[1] == s }
  transition t4 { from Equal to Rec condition p.x == 3 /\\ second(p.ys) == 2 /\\ p.ys == s }
  transition t5 { from A to Wrong condition r[2] != 2 \\/ r != s \\/ p.ys != s }
}
"""
SEQUENCE_ASSERTIONS = """\
assertion Rec: Rec is not reachable in M.
assertion Wrong: Wrong is not reachable in M.
"""


def test_a_seq_of_naturals_is_a_seq_of_reals_in_both_engines(tmp_path: Path) -> None:
    project = load(write_files(tmp_path, {"m.rct": SEQUENCES, "m.assertions": SEQUENCE_ASSERTIONS}))
    bmc, explicit = verdicts_are(project, SMALL, 12, {"Rec": "violated", "Wrong": "holds"})
    for results in (bmc, explicit):
        [rec] = [r for r in results if r.assertion == "Rec"]
        assert "M::out.out.<1, 2>" in [s.event for s in rec.trace]


def test_the_checker_casts_a_container_value_and_keeps_a_literal_retyped(tmp_path: Path) -> None:
    [m] = load(write_files(tmp_path, {"m.rct": SEQUENCES})).machines
    [t0] = [t for t in m.transitions if t.name == "t0"]
    assign = t0.action.statements[0]  # type: ignore[union-attr]
    assert isinstance(assign.value, ast.Builtin) and assign.value.op == "as"
    assert assign.value.type == ast.SeqType(ast.REAL) and assign.value.args[0].type == ast.SeqType(ast.NAT)
    r = next(v for v in m.variables if v.name == "r")
    assert isinstance(r.initial, ast.SeqLiteral) and r.initial.type == ast.SeqType(ast.REAL)


SETS = """\
stm M {
  var a : Set(nat) = {1, 2}
  var b : Set(real) = {}
  var c : Set(real * real) = {}
  var d : Set(nat * int) = {(| 1, 2 |)}
  initial i
  state A { }
  state Found { }
  state Wrong { }
  transition t0 { from i to A action b = a ; c = d }
  transition t1 { from A to Found condition 2 in b /\\ 1.0 in b /\\ (| 1, 2 |) in c }
  transition t2 { from A to Wrong condition 1.5 in b \\/ 3 in b \\/ not (2 in b) \\/ (| 1, 2.5 |) in c }
}
"""
SET_ASSERTIONS = """\
assertion Found: Found is not reachable in M.
assertion Wrong: Wrong is not reachable in M.
"""


def test_a_set_of_integers_is_a_set_of_reals_holding_only_them(tmp_path: Path) -> None:
    project = load(write_files(tmp_path, {"m.rct": SETS, "m.assertions": SET_ASSERTIONS}))
    verdicts_are(project, SMALL, 8, {"Found": "violated", "Wrong": "holds"})


def test_a_set_of_sequences_made_reals_is_unsupported_in_bmc_at_its_cast(tmp_path: Path) -> None:
    model = """\
stm M {
  var a : Set(Seq(nat)) = {<1>}
  var b : Set(Seq(real)) = {}
  initial i
  state A { }
  transition t0 { from i to A action b = a }
}
"""
    project = load(write_files(tmp_path, {"m.rct": model, "m.assertions": "assertion R: A is not reachable in M.\n"}))
    [r] = check(project, bound=4, ranges=SMALL)
    assert r.verdict == Verdict.UNSUPPORTED
    assert "made reals inside sequences" in (r.reason or "") and "m.rct:6:" in (r.reason or ""), r.reason


@pytest.mark.parametrize(("body", "message"), [
    # reals never narrow to integers, in a container either
    ("  var r : Seq(real) = <>\n  var s : Seq(int) = r", "type error: the initial value of 's' must be Seq(int)"),
    # function types keep their domain and range: RoboTool's widening of a domain is unsound
    ("  var f : nat -> nat\n  var g : int -> real = f", "type error: the initial value of 'g' must be int -> real"),
])
def test_what_does_not_widen(tmp_path: Path, body: str, message: str) -> None:
    with pytest.raises(ModelError) as info:
        load(write_files(tmp_path, {"m.rct": "stm M {\n" + body + "\n  initial i\n  state S { }\n"
                                               "  transition t0 { from i to S }\n}\n"}))
    assert any(d.message.startswith(message) for d in info.value.diagnostics), info.value
