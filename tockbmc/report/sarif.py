"""Results as a SARIF 2.1.0 log, for code-scanning tools (GitHub's, GitLab's, editors' SARIF viewers).

One SARIF result for each assertion that does not hold, at the assertion's
line in its `.assertions` file: `violated` at level `error`, `unknown` at
`warning` (the check could not decide: it is not a pass), `unsupported` at
`note` (tockbmc cannot check that form yet).  An assertion that holds gives no
result.  The rule of a result is the assertion's form (`deadlock-free`,
`does-not-terminate`, `refines`, …), its message the verdict and the reason.
A counterexample is a code flow with one location per step: the model text
behind the step when the trace has it, else the assertion; its message is the
event (or `τ` and what the internal step did) and its `state` the machines'
active states and the values of the variables after the step.

A model with errors gives a log whose results are the diagnostics, at their
positions, with the rule `model-error` (level `error`) or `model-warning`.
Paths are written relative to the working directory when they are below it
(against `%SRCROOT%`, the root a code-scanning upload resolves them from),
else as `file:` URIs.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any
from urllib.parse import quote

from tockbmc.model import ast
from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.position import Pos
from tockbmc.model.result import Result, Verdict, exit_code
from tockbmc.report.steps import Place, label, place, source, values_after_each_step

SCHEMA_URI = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
EXIT_MODEL_ERROR = 3

LEVEL = {Verdict.VIOLATED: "error", Verdict.UNKNOWN: "warning", Verdict.UNSUPPORTED: "note"}

# An assertion's form: (kind, negated) -> the rule's id and what it asserts.
RULES: dict[tuple[str, bool], tuple[str, str]] = {
    ("deadlock-free", False): ("deadlock-free", "P is deadlock-free"),
    ("deadlock-free", True): ("not-deadlock-free", "P is not deadlock-free"),
    ("divergence-free", False): ("divergence-free", "P is divergence-free"),
    ("divergence-free", True): ("not-divergence-free", "P is not divergence-free"),
    ("deterministic", False): ("deterministic", "P is deterministic"),
    ("deterministic", True): ("not-deterministic", "P is not deterministic"),
    ("timelock-free", False): ("timelock-free", "P is timelock-free"),
    ("timelock-free", True): ("not-timelock-free", "P is not timelock-free"),
    ("terminates", False): ("terminates", "P terminates"),
    ("terminates", True): ("does-not-terminate", "P does not terminate"),
    ("reachable", False): ("reachable", "S is reachable in P"),
    ("reachable", True): ("not-reachable", "S is not reachable in P"),
    ("refines", False): ("refines", "P refines Q"),
    ("refines", True): ("does-not-refine", "P does not refine Q"),
    ("equals", False): ("equals", "P equals Q"),
    ("equals", True): ("does-not-equal", "P does not equal Q"),
    ("clock-initialised", False): ("clock-initialised", "P is clock-initialised"),
    ("clock-initialised", True): ("not-clock-initialised", "P is not clock-initialised"),
}
OTHER_RULE = ("assertion", "an assertion of a form this version of tockbmc does not name")
MODEL_RULES = {"error": ("model-error", "an error in the model or its assertions"),
               "warning": ("model-warning", "a warning about the model or its assertions")}


def log(results: Iterable[Result], version: str, assertions: Iterable[ast.Assertion] = ()) -> dict[str, Any]:
    """The SARIF log of a `check`: a result for each assertion that does not hold."""
    results = list(results)
    forms = {a.label: (a.kind, a.negated) for a in assertions}
    rules: dict[str, dict[str, Any]] = {}
    out = []
    for r in results:
        if r.verdict not in LEVEL:
            continue
        rule_id, text = RULES.get(forms.get(r.assertion, ("", False)), OTHER_RULE)
        rule = rules.setdefault(rule_id, _rule(len(rules), rule_id, text))
        result: dict[str, Any] = {
            "ruleId": rule_id, "ruleIndex": rule["index"], "level": LEVEL[r.verdict],
            "message": {"text": f"{r.assertion} {r.verdict.value}: {r.reason or r.text}"},
            "locations": _locations(place(r.pos)),
            "properties": {"assertion": r.assertion, "verdict": r.verdict.value, "proof": r.proof.value,
                           "bound": r.bound, "depth": r.depth, "engine": r.engine, "seconds": round(r.seconds, 4)}}
        if r.trace:
            result["codeFlows"] = [_code_flow(r)]
        out.append(result)
    return _log(version, list(rules.values()), out, exit_code(r.verdict for r in results))


def model_error_log(diagnostics: Iterable[Diagnostic], version: str) -> dict[str, Any]:
    """The SARIF log of a model that did not load: its diagnostics as results."""
    rules: dict[str, dict[str, Any]] = {}
    out = []
    for d in diagnostics:
        rule_id, text = MODEL_RULES["error" if d.severity == "error" else "warning"]
        rule = rules.setdefault(rule_id, _rule(len(rules), rule_id, text))
        out.append({"ruleId": rule_id, "ruleIndex": rule["index"], "level": "error" if d.severity == "error" else "warning",
                    "message": {"text": d.message}, "locations": [_location(d.pos)]})
    return _log(version, list(rules.values()), out, EXIT_MODEL_ERROR)


def _log(version: str, rules: list[dict[str, Any]], results: list[dict[str, Any]], status: int) -> dict[str, Any]:
    driver = {"name": "tockbmc", "version": version, "semanticVersion": version,
              "rules": [{k: v for k, v in rule.items() if k != "index"} for rule in rules]}
    run = {"tool": {"driver": driver}, "columnKind": "unicodeCodePoints",
           "invocations": [{"executionSuccessful": status != EXIT_MODEL_ERROR, "exitCode": status}],
           "results": results}
    return {"$schema": SCHEMA_URI, "version": "2.1.0", "runs": [run]}


def _rule(index: int, rule_id: str, text: str) -> dict[str, Any]:
    return {"index": index, "id": rule_id, "shortDescription": {"text": text}}


def _code_flow(r: Result) -> dict[str, Any]:
    """The trace as one thread flow: a location per step, with the configuration after it."""
    steps = []
    for step, values in zip(r.trace, values_after_each_step(r.trace)):
        at = place(source(step)) or place(r.pos)
        state = {**step.states, **values}
        steps.append({"location": {**_located(at), "message": {"text": label(step)}},
                      "executionOrder": step.step, "importance": "unimportant" if step.kind == "internal" else "essential",
                      "state": {name: {"text": value} for name, value in state.items()}})
    return {"message": {"text": f"counterexample to {r.assertion}"}, "threadFlows": [{"locations": steps}]}


def _locations(at: Place | None) -> list[dict[str, Any]]:
    return [_located(at)] if at is not None else []


def _located(at: Place | None) -> dict[str, Any]:
    if at is None:
        return {}
    return {"physicalLocation": {"artifactLocation": _artifact(at.path),
                                 "region": {"startLine": at.line, "startColumn": at.column}}}


def _location(pos: Pos) -> dict[str, Any]:
    region: dict[str, int] = {"startLine": max(1, pos.line), "startColumn": max(1, pos.column)}
    if pos.end_line >= pos.line and (pos.end_line, pos.end_column) > (pos.line, pos.column):
        region.update(endLine=pos.end_line, endColumn=pos.end_column)
    return {"physicalLocation": {"artifactLocation": _artifact(pos.path), "region": region}}


def _artifact(path: str) -> dict[str, str]:
    """A file as a URI: relative to `%SRCROOT%` (the working directory) when it is below it."""
    p = Path(path)
    if p.is_absolute():
        try:
            p = p.relative_to(Path.cwd())
        except ValueError:
            return {"uri": p.as_uri()}
    return {"uri": quote(p.as_posix()), "uriBaseId": "%SRCROOT%"}
