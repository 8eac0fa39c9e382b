"""RoboChart's probabilistic junctions, read as RoboTool's CSP semantics reads them.

RoboChart's probabilistic extension adds `probabilistic p`, a junction whose transitions each
carry `probability e` (`RoboChart.xtext` in UoY-RoboStar/robochart-textual: `ProbabilisticJunction:
'probabilistic' name=ID`, and `'trigger' trigger=Communication | 'probability' probability=Expression`
in `Transition`). Its probabilities are for PRISM. CSP has no probabilistic choice, and RoboTool's
metamodel makes a `ProbabilisticJunction` a `Junction` (`robochart.ecore` in
UoY-RoboStar/robochart-metamodel), so RoboTool's CSP semantics makes the choice among its
transitions the nondeterministic one a junction makes (an inference: the generator's text is not
public, docs/robotool-evidence.md §10). tockbmc reads it so: the resolver gives the node the kind
`junction` with `probabilistic` set and drops the probabilities once they are checked, and every
result on an element that holds one says so (`notes`).

What RoboTool's validator (`RoboChartValidator.xtend`, `transitionWFC` and `junctionWFC_PJ3`) makes
an error is one here (the resolver): a transition from a probabilistic junction without a
probability (PJ1) or with a condition (PJ2), a probability on a transition from any other node
(PT1), and a number literal outside [0, 1] (PT2). Its warning that the literal probabilities of a
junction do not add up to 1 (PJ3) is a warning here.
"""

from __future__ import annotations

from tockbmc.model import ast


def note(junction: str) -> str:
    """What a result states for a probabilistic junction (`M::p`) its element holds."""
    return (f"probabilistic choice at junction {junction} read as nondeterministic choice, "
            "as RoboTool's CSP semantics does")


def junctions(*roots: object) -> list[str]:
    """The probabilistic junctions `roots` hold (model elements, operations), by qualified name
    (`M::p`, `M::s::p`), sorted."""
    return sorted({f"{b.qname}::{n.path}" for b in ast.parts(*roots) if isinstance(b, ast.Behaviour)
                   for n in b.nodes if n.probabilistic})


def notes(*roots: object) -> tuple[str, ...]:
    """One `note` per probabilistic junction `roots` hold."""
    return tuple(note(j) for j in junctions(*roots))
