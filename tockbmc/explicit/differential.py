"""Differential testing: random small models, checked by BMC and by the explicit engine.

`machine_text` writes a random RoboChart state machine (states, a composite
state, a junction, guards over a small integer and a clock, inputs, outputs,
waits, platform calls, statement and trigger deadlines, a final state) and
`network_text` a controller of two of them joined by a synchronous or an
asynchronous connection; `compare` checks the assertions with both engines and
says where they disagree.  Only definite outcomes are compared:
a counterexample or witness found, a proof for every length (BMC's
k-induction), or a search that explored every reachable configuration (the
explicit engine).  A counterexample found by one engine and ruled out by the
other is a disagreement; so is a pair of counterexamples whose visible lengths
differ when both are shortest in visible steps.  Used by
`tests/test_differential.py` (Hypothesis) and `benchmarks/differential.py`.
"""

from __future__ import annotations

import random
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import tockbmc
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.explicit.engine import check_explicit

RANGES = Ranges({"core_int": Range(Fraction(-1), Fraction(1))})
STATEMENTS = ["b!x", "x = 0", "x = 1", "x = -x", "wait(1)", "#C", "c", "b!(x + 1)", "op(x)", "c <{1}"]
CONDITIONS = ["x > 0", "x == 0", "x < 1", "since(C) >= 1", "since(C) < 2", "x != 1"]


def machine_text(pick: Callable[[list], object], number: Callable[[int, int], int],
                 name: str = "M") -> tuple[str, list[str]]:
    """A random machine and the names of its states; `pick(options)` and `number(lo, hi)` choose."""
    n = number(1, 4)
    states = [f"S{k}" for k in range(n)]
    composite = number(0, 1) == 1
    lines = [f"stm {name} {{", "  requires Ops", "  event a : int", "  event b : int", "  event c",
             "  var x : int = 0", "  clock C", "  initial i"]
    for s in states:
        entry = f" entry {pick(STATEMENTS)}" if number(0, 1) else ""
        if s == "S0" and composite:
            lines += [f"  state S0 {{{entry}", "    initial j", "    state In {}", "    state Out {}",
                      "    transition u0 { from j to In }",
                      f"    transition u1 {{ from In to Out condition {pick(CONDITIONS)} }}", "  }"]
        else:
            lines.append(f"  state {s} {{{entry} }}")
    targets = list(states)
    if number(0, 1):
        lines.append("  junction J")
        targets.append("J")
    if number(0, 1):
        lines.append("  final F")
        targets.append("F")
    lines.append("  transition t0 { from i to S0 }")
    sources = [*states, *(["J"] if "J" in targets else [])]
    count = number(1, 5)
    for k in range(count):
        src = pick(sources)
        dst = pick(targets)
        parts = [f"from {src} to {dst}"]
        if src != "J":
            trigger = pick(["", "a?x", "c", "a.1", "c <{1}"])
            if trigger:
                parts.append(f"trigger {trigger}")
        if number(0, 1) or src == "J":
            parts.append(f"condition {pick(CONDITIONS)}")
        if number(0, 2) == 0:
            parts.append(f"action {pick(STATEMENTS)}")
        lines.append(f"  transition t{k + 1} {{ {' '.join(parts)} }}")
    if "J" in targets and not any("from J " in line for line in lines):
        lines.append(f"  transition tj {{ from J to {states[0]} }}")
    lines.append("}")
    return "interface Ops { op(n : int) }\n" + "\n".join(lines) + "\n", states


def network_text(pick: Callable[[list], object], number: Callable[[int, int], int]) -> tuple[str, list[str]]:
    """A random controller M of two random machines P and Q: P's output b feeds Q's input a
    (synchronous or asynchronous), the environment feeds P's a, Q's b is M's output."""
    p_text, p_states = machine_text(pick, number, "P")
    q_text, _ = machine_text(pick, number, "Q")
    q_text = q_text.split("\n", 1)[1]  # one `interface Ops`
    kind = pick(["", " (_async)"])
    controller = ("controller M {\n  requires Ops\n  event a : int\n  event b : int\n  sref P = P\n  sref Q = Q\n"
                  f"  connection M on a to P on a\n  connection P on b to Q on a{kind}\n"
                  "  connection Q on b to M on b\n}\n")
    return p_text + q_text + controller, [f"P::{s}" for s in p_states]


def assertions_text(states: list[str], pick: Callable[[list], object]) -> str:
    forms = ["M does not terminate", "M is timelock-free", "M is deadlock-free", "M is not timelock-free",
             f"{pick(states)} is reachable in M", f"{pick(states)} is not reachable in M", "M terminates"]
    return "".join(f"assertion A{k}: {f}.\n" for k, f in enumerate(forms))


@dataclass
class Outcome:
    assertion: str
    bmc: str
    explicit: str
    agree: bool | None  # None: not comparable (a bounded verdict, unknown or unsupported)
    note: str = ""


def _definite_bmc(r: tockbmc.Result) -> str | None:  # type: ignore[name-defined]
    if r.trace:
        return f"found:{r.verdict}"
    if "every length" in (r.reason or "") or "any length" in (r.reason or ""):
        return f"proved:{r.verdict}"
    return None


def _definite_explicit(r: tockbmc.Result) -> str | None:  # type: ignore[name-defined]
    if r.trace or "never entered (every configuration" in (r.reason or ""):
        return f"found:{r.verdict}" if r.trace else f"proved:{r.verdict}"
    if "every configuration reachable at any length" in (r.reason or ""):
        return f"proved:{r.verdict}"
    return None


def compare(rct: str, assertions: str, bound: int = 16, explicit_bound: int = 8) -> list[Outcome]:
    """Check a model with both engines; one `Outcome` per assertion."""
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "m.rct").write_text(rct)
        (Path(d) / "m.assertions").write_text(assertions)
        project = tockbmc.load(d)
        symbolic = {r.assertion: r for r in check(project, bound=bound, ranges=RANGES, timeout=20)}
        concrete = {r.assertion: r for r in check_explicit(project, None, explicit_bound, RANGES, {}, 20, 200_000)}
    out = []
    for name, b in symbolic.items():
        e = concrete[name]
        db, de = _definite_bmc(b), _definite_explicit(e)
        if db is None or de is None or "unsupported" in (b.verdict, e.verdict):
            out.append(Outcome(name, b.verdict, e.verdict, None))
            continue
        same = b.verdict == e.verdict
        note = ""
        if same and db.startswith("found") and de.startswith("found"):
            vb = sum(1 for s in b.trace if s.kind != "internal")
            ve = sum(1 for s in e.trace if s.kind != "internal")
            if ve > vb:  # the explicit engine's are shortest in visible steps
                same, note = False, f"visible lengths {vb} (bmc) and {ve} (explicit)"
            elif vb != ve:
                note = f"visible lengths {vb} (bmc, shortest in all steps) and {ve} (explicit)"
        out.append(Outcome(name, b.verdict, e.verdict, same, note))
    return out


def random_case(seed: int) -> tuple[str, str]:
    rng = random.Random(seed)
    make = network_text if rng.randint(0, 3) == 0 else machine_text
    rct, states = make(rng.choice, rng.randint)
    return rct, assertions_text(states, rng.choice)
