"""Refinement with the model on either side, and `equals` (semantics.md §3, §4).

`M refines S` runs a monitor of S beside M; `S refines M` lists S's traces and asks, for each,
whether M can perform it.  Verdicts and traces are derived by hand from the model below:
M waits (letting time pass) for input a, then may output b, and then only lets time pass.
Inside `Timed(OneStep)` a prefix and STOP let time pass too, so
  traces(M)  = tock* a (tock* b)? tock*  (prefix-closed),
  traces(S1) = the same, so M equals S1;
  traces(S2) = tock* a tock*: M's <a, b> is not one of them;
  traces(S3) = tock* a tock* b tock* a tock*: includes every trace of M, and <a, b, a>, which M cannot do.
"""

from __future__ import annotations

from pathlib import Path

from conftest import write_files

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Ranges
from tockbmc.model.result import Result

MODEL = """
stm M {
  event a
  event b
  initial i
  state s {}
  state t {}
  transition t0 { from i to s }
  transition t1 { from s to t trigger a action b }
}
"""

SPECS = """
timed csp S1 csp-begin
Timed(OneStep) { S1 = M::a.in -> M::b.out -> STOP }
csp-end
timed csp S2 csp-begin
Timed(OneStep) { S2 = M::a.in -> STOP }
csp-end
timed csp S3 csp-begin
Timed(OneStep) { S3 = M::a.in -> M::b.out -> M::a.in -> STOP }
csp-end
"""


def run(tmp_path: Path, assertions: str, bound: int = 10) -> dict[str, Result]:
    write_files(tmp_path, {"m.rct": MODEL, "m.assertions": SPECS + assertions})
    return {r.assertion: r for r in check(tockbmc.load(tmp_path), bound=bound)}


def visible(r: Result) -> list[str]:
    return [s.event or "" for s in r.trace if s.kind != "internal"]


def test_equals_holds_both_ways(tmp_path) -> None:
    rs = run(tmp_path, "assertion E: M equals S1.\nassertion F: S1 equals M.\n")
    assert rs["E"].verdict == "holds", rs["E"].reason
    assert rs["F"].verdict == "holds", rs["F"].reason
    assert "every trace of S1" in (rs["E"].reason or "")


def test_model_with_a_trace_the_spec_lacks(tmp_path) -> None:
    rs = run(tmp_path, "assertion R: M refines S2 in the traces model.\nassertion E: M equals S2.\n"
                       "assertion Back: S2 refines M in the traces model.\nassertion F: S2 equals M.\n")
    # F: equality with the specification written first is still refinement both ways (not only that S2's
    # traces are M's, which would say "holds").
    for name in ("R", "E", "F"):
        assert rs[name].verdict == "violated"
        assert visible(rs[name]) == ["M::a.in", "M::b.out"]
    assert rs["Back"].verdict == "holds"  # every trace of S2 is one of M's


def test_spec_with_a_trace_the_model_lacks(tmp_path) -> None:
    rs = run(tmp_path, "assertion R: M refines S3 in the traces model.\n"
                       "assertion Back: S3 refines M in the traces model.\n"
                       "assertion NotBack: S3 does not refine M in the traces model.\n"
                       "assertion E: M equals S3.\n")
    assert rs["R"].verdict == "holds"
    for name, verdict in (("Back", "violated"), ("NotBack", "holds"), ("E", "violated")):
        r = rs[name]
        assert r.verdict == verdict, (name, r.verdict, r.reason)
        events = [e for e in visible(r) if e != "tock"]
        assert events == ["M::a.in", "M::b.out", "M::a.in"], (name, visible(r))


def test_is_not_equal_to_holds_when_either_direction_differs(tmp_path) -> None:
    """`M is not equal to S3`: M refines S3, but S3 has a trace M lacks, so both directions are
    checked, not only M's own. `M is not equal to S1` is violated: M equals S1, which BMC shows for
    a bound only (S1's traces are listed up to a length) and the explicit engine for traces of
    every length (S1's states paired with M's configurations after the same trace)."""
    from tockbmc.explicit.engine import check_explicit

    rs = run(tmp_path, "assertion N3: M is not equal to S3.\nassertion N2: M is not equal to S2.\n"
                       "assertion N1: M is not equal to S1.\n")
    concrete = {r.assertion: r for r in check_explicit(tockbmc.load(tmp_path), None, 10, Ranges(), {}, 60)}
    for results, equal in ((rs, "unknown"), (concrete, "violated")):
        for name, verdict in (("N3", "holds"), ("N2", "holds"), ("N1", equal)):
            assert results[name].verdict == verdict, (name, results[name].reason)
        events = [e for e in visible(results["N3"]) if e != "tock"]
        assert events == ["M::a.in", "M::b.out", "M::a.in"], visible(results["N3"])
    assert "bounded search alone" in (rs["N1"].reason or "")
    assert "for traces of every length" in (concrete["N1"].reason or "")


def test_a_prefix_short_of_the_channel_s_fields_is_unsupported(tmp_path) -> None:
    """`M::a -> STOP` for `event a` (whose events are M::a.in and M::a.out): FDR's type error; it had
    matched none of M's events, so `S4 refines M` held with S4 as STOP."""
    from tockbmc.explicit.engine import check_explicit

    more = "timed csp S4 csp-begin\nTimed(OneStep) { S4 = M::a -> STOP }\ncsp-end\n"
    rs = run(tmp_path, more + "assertion Q: S4 refines M in the traces model.\n")
    concrete = check_explicit(tockbmc.load(tmp_path), None, 10, Ranges(), {}, 60)
    for r in (rs["Q"], concrete[0]):
        assert r.verdict == "unsupported" and "FDR rejects it as a type error" in (r.reason or ""), r.reason


def test_an_input_binds_the_rest_of_a_channel_s_fields(tmp_path) -> None:
    """`N::c?x` on `event c : int` binds x to `in.v` (CSPM's dotted rest of the event): matched
    where x is read nowhere, as a realworld specification (GasAnalysis::gas?x) needs; it had been a
    prefix matching nothing.  N receives on c for ever; S takes one input, so N violates it at the
    second."""
    from fractions import Fraction

    from tockbmc.encodings.values import Range
    from tockbmc.explicit.engine import check_explicit

    write_files(tmp_path, {"m.rct": "interface I { event c : int }\nstm N {\n  uses I\n  var v : int = 0\n"
                                    "  initial i\n  state s {}\n  transition t0 { from i to s }\n"
                                    "  transition t1 { from s to s trigger c?v }\n}\n",
                           "m.assertions": "untimed csp S csp-begin\nS = N::c?x -> STOP\ncsp-end\n"
                                           "untimed assertion R: N refines S in the traces model\n"})
    project = tockbmc.load(tmp_path)
    one = Ranges({"core_int": Range(Fraction(0), Fraction(0))})
    from tockbmc.model.config import configure
    for [r] in (check(project, bound=10, config=configure(project, one)), check_explicit(project, None, 10, one, {}, 60)):
        assert r.verdict == "violated" and visible(r) == ["N::c.in.0", "N::c.in.0"], (r.reason, visible(r))


def test_two_specifications_are_unsupported_and_two_models_checked(tmp_path) -> None:
    """Between two model elements, the right one stands for the specification, as the state graph
    the interpreter lists (docs/semantics.md §7.5): M refines itself."""
    rs = run(tmp_path, "assertion SS: S1 refines S2 in the traces model.\n"
                       "assertion MM: M refines M in the traces model.\n")
    assert rs["SS"].verdict == "unsupported" and rs["MM"].verdict == "holds"


def test_blocking_tock_is_unsupported(tmp_path) -> None:
    write_files(tmp_path, {"m.rct": MODEL, "m.assertions": SPECS + """
timed csp B csp-begin
B = M::D__(0) [| {| tock |} |] SKIP
csp-end
assertion T: B refines S1 in the traces model.
"""})
    [r] = check(tockbmc.load(tmp_path), bound=6)
    assert r.verdict == "unsupported" and "tock" in (r.reason or "")
