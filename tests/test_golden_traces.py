"""Rendered counterexample traces compared with reviewed golden files under `tests/golden/`.

Ranges pin every value the environment supplies, so each trace is unique.
Regenerate after an intended change with `UPDATE_GOLDEN=1 python -m pytest tests/test_golden_traces.py`
and review the diff as text.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import CONFORMANCE, EXAMPLE
from rich.console import Console

from tockbmc import load
from tockbmc.check import check
from tockbmc.encodings.values import Range, Ranges
from tockbmc.model.config import configure
from tockbmc.report.results import print_trace

GOLDEN = Path(__file__).parent / "golden"


def _pin(**values: int) -> Ranges:
    return Ranges({k: Range(Fraction(v), Fraction(v)) for k, v in values.items()})


CASES: dict[str, tuple[Path, str, Ranges, tuple[str, ...]]] = {
    # A machine on its own: the paper's A5 with a move request of time -1.
    "exax_a5": (EXAMPLE, "A5", _pin(core_int=-1, core_real=0), ()),
    # A CSP specification as a monitor: the paper's A1, a tock before EXAX::go_to_posCall.
    "exax_a1": (EXAMPLE, "A1", _pin(core_int=-1, core_real=0), ()),
    # A model process in a CSP context: A2, EXAX::D__(0, 1) with its calls hidden.
    "exax2_a2": (EXAMPLE, "A2", _pin(core_int=-1, core_real=0), ()),
    # A controller: its event e, connected to STM1, is visible as C1::e (z a parameter, pinned to 2).
    "controller_c1_term": (CONFORMANCE / "robochart" / "test-core-assertions", "C1_term", _pin(core_nat=2), ("z",)),
    # A module: the platform's e is M's visible event, joined directly to C1 though the connection is (_async).
    "module_m_term": (CONFORMANCE / "robochart" / "test-core-assertions", "M_term", _pin(core_nat=2), ("z",)),
}


def render(path: Path, name: str, ranges: Ranges, params: tuple[str, ...]) -> str:
    project = load(path)
    [r] = check(project, [name], bound=12, config=configure(project, ranges, params=params))
    assert r.verdict == "violated"
    console = Console(record=True, width=240, color_system=None, file=open(os.devnull, "w"))
    print_trace(r, console)
    return console.export_text()


@pytest.mark.parametrize("case", sorted(CASES))
def test_trace_matches_golden_file(case: str) -> None:
    path, name, ranges, params = CASES[case]
    text = render(path, name, ranges, params)
    golden = GOLDEN / f"{case}.txt"
    if os.environ.get("UPDATE_GOLDEN"):
        golden.write_text(text)
    assert text == golden.read_text()
