"""Results as JUnit XML, for the test reports of CI services.

One test suite per file of assertions (its path is the suite's name and each
test case's `classname`), one test case per assertion, its `time` the seconds
the check took.  A violated assertion is a `<failure>` (message: the reason;
text: the assertion and its counterexample as `check` prints it); an unknown
one is an `<error>` (the check stopped undecided: a report must not count it
as passed); an unsupported one is `<skipped>` with the reason.  An assertion
that holds has the reason it holds as its `<system-out>`.

A model with errors is one failing test case, `load`, whose text is the
diagnostics as `check` prints them on stderr.
"""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET
from collections.abc import Iterable

from rich.console import Console

from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.result import Result, Verdict
from tockbmc.report.diagnostics import render, summary
from tockbmc.report.results import print_trace
from tockbmc.report.steps import place

SUITE = "tockbmc"  # the suite, and class, of what belongs to no file of assertions


def report(results: Iterable[Result]) -> str:
    """The JUnit XML document of a `check`."""
    suites: dict[str, list[Result]] = {}
    for r in results:
        at = place(r.pos)
        suites.setdefault(at.path if at else SUITE, []).append(r)
    root = ET.Element("testsuites", name=SUITE)
    for name, members in suites.items():
        suite = ET.SubElement(root, "testsuite", name=name)
        for r in members:
            _testcase(suite, name, r)
        _count(suite)
    _count(root)
    return _text(root)


def model_error_report(diagnostics: Iterable[Diagnostic], sources: dict[str, str]) -> str:
    """The JUnit XML document of a model that did not load: one failing test case, `load`."""
    diagnostics = list(diagnostics)
    root = ET.Element("testsuites", name=SUITE)
    suite = ET.SubElement(root, "testsuite", name=SUITE)
    case = ET.SubElement(suite, "testcase", classname=SUITE, name="load", time="0.000")
    failure = ET.SubElement(case, "failure", message=f"the model has {summary(diagnostics)}", type="model-error")
    failure.text = render(diagnostics, sources)
    _count(suite)
    _count(root)
    return _text(root)


def _testcase(suite: ET.Element, classname: str, r: Result) -> None:
    case = ET.SubElement(suite, "testcase", classname=classname, name=r.assertion, time=f"{r.seconds:.3f}")
    reason = r.reason or ""
    if r.verdict == Verdict.VIOLATED:
        failure = ET.SubElement(case, "failure", message=reason, type=Verdict.VIOLATED.value)
        failure.text = f"{r.text}\n{_trace_text(r)}" if r.trace else f"{r.text}\n{reason}"
    elif r.verdict == Verdict.UNKNOWN:
        error = ET.SubElement(case, "error", message=reason, type="unknown")
        depth = f"; the search reached depth {r.depth} of {r.bound}" if r.depth is not None else ""
        error.text = f"{r.text}\nundecided: {reason}{depth}"
    elif r.verdict == Verdict.UNSUPPORTED:
        ET.SubElement(case, "skipped", message=f"unsupported: {reason}")
    else:
        out = ET.SubElement(case, "system-out")
        out.text = f"{r.text}\nholds: {reason or f'every run of up to {r.bound} steps'}"
        if r.trace:
            out.text += "\n" + _trace_text(r)


def _trace_text(r: Result) -> str:
    """The trace as `check` prints it, without colour."""
    buffer = io.StringIO()
    print_trace(r, Console(file=buffer, width=100_000, color_system=None, soft_wrap=True))
    return buffer.getvalue()


def _count(element: ET.Element) -> None:
    """The totals of a suite (or of all suites) as its attributes."""
    cases = list(element.iter("testcase"))
    element.set("tests", str(len(cases)))
    for tag, attribute in (("failure", "failures"), ("error", "errors"), ("skipped", "skipped")):
        element.set(attribute, str(sum(1 for c in cases if c.find(tag) is not None)))
    element.set("time", f"{sum(float(c.get('time', '0')) for c in cases):.3f}")


def _text(root: ET.Element) -> str:
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True)
