"""BMC and the explicit engine agree on random small machines (Hypothesis).

`tockbmc/explicit/differential.py` writes the machines and compares definite outcomes;
`benchmarks/differential.py --cases N` runs many more and prints the counts.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tockbmc.explicit.differential import assertions_text, compare, machine_text, network_text, random_case


@st.composite
def cases(draw: st.DrawFn) -> tuple[str, str]:
    def pick(options: list) -> object:
        return draw(st.sampled_from(options))

    def number(lo: int, hi: int) -> int:
        return draw(st.integers(lo, hi))

    make = network_text if draw(st.integers(0, 3)) == 0 else machine_text  # a controller of two machines
    rct, states = make(pick, number)
    return rct, assertions_text(states, pick)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cases())
def test_engines_agree_on_random_machines(case: tuple[str, str]) -> None:
    rct, assertions = case
    wrong = [o for o in compare(rct, assertions) if o.agree is False]
    assert not wrong, (rct, wrong)


# Seeds of `random_case` whose machines showed a disagreement before it was fixed (the explicit
# engine's time-only deadlock was found late; a reason claimed a complete search that was not;
# 20263: BMC counted a state as entered only once its entry action had made a step).
@pytest.mark.parametrize("seed", [2, 7, 11, 16, 1254, 20263])
def test_former_disagreements(seed: int) -> None:
    rct, assertions = random_case(seed)
    assert not [o for o in compare(rct, assertions) if o.agree is False]
