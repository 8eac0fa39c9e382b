"""The command line under hostile conditions: odd option values, closed or narrow streams,
special files, Ctrl-C."""

from __future__ import annotations

import pytest
from conftest import EXAMPLE, run_cli

# -------------------------------------------------------------------- option values


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e400", "0"])
def test_timeout_must_be_a_finite_positive_number(value: str) -> None:
    result = run_cli(["check", EXAMPLE, "-a", "A1", "--timeout", value])
    assert result.crash is None and result.exit_code == 2, result.output
    assert "Invalid value for '--timeout'" in result.stderr
