"""A function the model defines by recursion (`postcondition result == … f(n - 1) …`), read as
RoboTool's CSP evaluates it (tockbmc/model/recursion.py): its body unfolded into itself; past the
unfolding, the explicit engine calls the function again, and BMC leaves it open, so a claim
about every run holds for any value there and a witness found there is replayed exactly."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from conftest import both_engines, verdicts_are, write_files

import tockbmc
from tockbmc.model.ranges import Range, Ranges

RCT = """
function fact(n : nat) : nat {
  postcondition result == if n == 0 then 1 else n * fact(n - 1) end
}
function fib(n : nat) : nat {
  postcondition result == if n < 2 then n else fib(n - 1) + fib(n - 2) end
}
function swap(a : int, b : int) : int {
  postcondition result == if a <= 0 then b else swap(b - 1, a - 1) end
}
stm M {
  initial i
  state A { }
  state Good { }
  state Bad { }
  state Deep { }
  transition t0 { from i to A }
  transition t1 { from A to Good condition fact(4) == 24 /\\ fib(6) == 8 /\\ swap(2, 5) == 3 }
  transition t2 { from A to Bad condition not (fact(4) == 24 /\\ fib(6) == 8 /\\ swap(2, 5) == 3) }
  transition t3 { from A to Deep condition fact(20) == 2432902008176640000 }
}
"""
ASSERTIONS = ("assertion Good: M::Good is reachable in M.\nassertion Bad: M::Bad is reachable in M.\n"
              "assertion Deep: M::Deep is reachable in M.\n")
NAT = Ranges({"core_nat": Range(Fraction(0), Fraction(30))})


def test_a_recursive_function_computes_what_the_csp_computes_in_both_engines(tmp_path: Path) -> None:
    """fact(4), fib(6) and swap(2, 5) (whose arguments trade places, each read before either is
    bound) are within the unfolding; fact(20) is deeper, and is still entered by both engines'
    runs, which the interpreter replays exactly."""
    project = tockbmc.load(write_files(tmp_path, {"m.rct": RCT, "m.assertions": ASSERTIONS}))
    verdicts_are(project, NAT, 10, {"Good": "holds", "Bad": "violated", "Deep": "holds"})


def test_calls_past_the_unfolding_stay_open_in_every_reading(tmp_path: Path) -> None:
    """Past the unfolding a recursive function is not RoboTool's placeholder (0 for a nat): it is
    the function itself, so no reading fills it in, and results list it as kept open."""
    from tockbmc.model.config import configure
    from tockbmc.model.readings import Reading
    project = tockbmc.load(write_files(tmp_path, {"m.rct": RCT, "m.assertions": ASSERTIONS}))
    for reading in Reading:
        defaults = configure(project, NAT, reading=reading).setup(None, project.machines[0]).defaults
        assert all(defaults.get(name, "") == "" for name in ("fact", "fib", "swap")), (reading, defaults)


def test_a_function_recursive_through_a_precondition_loads_and_its_calls_are_unsupported(tmp_path: Path) -> None:
    """RoboTool has no rule against it, and tockbmc unfolds only a `result == e` definition."""
    rct = ("function f(n : nat) : nat {\n  precondition f(n) > 0\n  postcondition result == n\n}\n"
           "stm M {\n  var x : nat = 0\n  initial i\n  state s { }\n  transition t0 { from i to s action x = f(1) }\n}\n")
    project = tockbmc.load(write_files(tmp_path, {"m.rct": rct, "m.assertions": "assertion A: M is deadlock-free.\n"}))
    [bmc], [explicit] = both_engines(project, NAT, 4)
    for r in (bmc, explicit):
        assert r.verdict.value == "unsupported", r
        assert "function f is defined in terms of itself other than by a postcondition result == e" in (r.reason or "")


def test_a_generic_function_defined_by_recursion_is_unfolded_for_each_instance(tmp_path: Path) -> None:
    rct = """import sequence_toolkit::*
function len(s : Seq(?X)) : nat {
  postcondition result == if size(s) == 0 then 0 else 1 + len(tail(s)) end
}
stm M {
  var q : Seq(int) = <5, 6, 7>
  var b : Seq(boolean) = <true>
  initial i
  state A { }
  state Good { }
  state Bad { }
  transition t0 { from i to A }
  transition t1 { from A to Good condition len(q) == 3 /\\ len(b) == 1 }
  transition t2 { from A to Bad condition len(q) != 3 \\/ len(b) != 1 }
}
"""
    project = tockbmc.load(write_files(tmp_path, {"m.rct": rct, "m.assertions": (
        "assertion Good: M::Good is reachable in M.\nassertion Bad: M::Bad is reachable in M.\n")}))
    verdicts_are(project, NAT, 10, {"Good": "holds", "Bad": "violated"})
