"""Large generated projects (benchmarks/generate.py) load completely."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import load_generator

from tockbmc import Project, load
from tockbmc.model import ast

generate = load_generator().generate


def counts(project: Project) -> dict[str, int]:
    nodes = [n for m in project.machines for n in m.nodes]
    return {
        "machines": len(project.machines),
        "states": sum(n.kind == "state" for n in nodes),
        "junctions": sum(n.kind == "junction" for n in nodes),
        "transitions": sum(len(m.transitions) for m in project.machines),
        "assertions": len(project.assertions),
    }


def expected_counts(generated: object) -> dict[str, int]:
    return {k: getattr(generated, k) for k in ("machines", "states", "junctions", "transitions", "assertions")}


def test_generator_is_deterministic() -> None:
    assert generate(3000) == generate(3000)
    assert generate(3000) != generate(3100)


@pytest.mark.parametrize("n", [1, 200, 1000, 2500])
def test_small_generated_projects_load(tmp_path: Path, n: int) -> None:
    generated = generate(n)
    assert generated.lines >= n
    project = load(generated.write(tmp_path))
    assert project.warnings == ()
    assert counts(project) == expected_counts(generated)


def test_10000_line_project_loads(tmp_path: Path) -> None:
    generated = generate(10_000)
    root = generated.write(tmp_path)
    on_disk = sum(p.read_text(encoding="utf-8").count("\n") for p in root.iterdir())
    assert on_disk == generated.lines
    assert 10_000 <= generated.lines < 10_100

    project = load(root)

    assert project.warnings == ()
    assert len(project.files) == len(generated.files) == generated.machines + 3
    assert counts(project) == expected_counts(generated)
    assert generated.machines >= 10
    assert generated.states >= 400
    controller = project.controllers[0]
    assert len(controller.machines) == generated.machines
    assert len(controller.connections) == generated.machines  # the input, then one per pair of machines
    (module,) = project.modules
    assert module.platform_name == "Robot" and module.controllers[0].controller is controller
    first = project.element("M0")
    assert isinstance(first, ast.StateMachine)
    assert first.node("s3").composite and first.node("s3::p").kind == "state"
    assert [a.settings[0].constant for a in project.assertions[:-1]] == ["limit"] * generated.machines
