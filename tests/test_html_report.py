"""`check --report FILE.html`: the page's structure, read by `html.parser` and by headless Chromium.

The report of the paper's realistic case (A1–A6 violated, A7 holds) must show the verdict table,
one sequence diagram per counterexample with a lifeline per machine, and A1's events; the page
must load nothing from the network and escape the model's text.  The diagram's reading of a trace
(who sends to whom) is tested on hand-made traces.
"""

from __future__ import annotations

import importlib.util
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path

import pytest
from conftest import EXAMPLE, REPO, REUSED_LABELS, REUSED_NAMES, run_cli, write_files

from tockbmc.model.result import Proof, Result, TraceStep, Verdict
from tockbmc.report.html import render_report
from tockbmc.report.sequence import BOUNDARY, ENVIRONMENT, PLATFORM, diagram
from tockbmc.report.svg import LABEL_CHARS, label_lines, render, to_string

REALISTIC = ["--range", "core_int=-1..1", "--range", "core_real=-1..1"]
VERDICTS = {**{f"A{i}": "violated" for i in range(1, 7)}, "A7": "holds"}
# The distance does not matter to A1 (any value keeps the violation), so a run may show another one.
A1_MOVE = re.compile(r"EXAX::move\.in\.\(dist=-?[0-9./]+, time=-1\)")
A1_STATES = ["wait_for_move", "time_check", "taking t2"]
VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


@dataclass
class Node:
    tag: str
    attrs: dict[str, str]
    children: list[Node] = field(default_factory=list)
    text: list[str] = field(default_factory=list)

    def iter(self, tag: str | None = None) -> Iterator[Node]:
        if tag is None or self.tag == tag:
            yield self
        for c in self.children:
            yield from c.iter(tag)

    def all_text(self) -> str:
        return "".join(self.text) + "".join(c.all_text() for c in self.children)

    def classes(self) -> set[str]:
        return set(self.attrs.get("class", "").split())


class _Tree(HTMLParser):
    """A small DOM from `html.parser`: enough to count rows, diagrams and lifelines."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.root = Node("#document", {})
        self.stack = [self.root]

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        node = Node(tag, {k: v or "" for k, v in attrs})
        self.stack[-1].children.append(node)
        if tag not in VOID:
            self.stack.append(node)

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.stack[-1].children.append(Node(tag, {k: v or "" for k, v in attrs}))

    def handle_endtag(self, tag: str) -> None:
        for i in range(len(self.stack) - 1, 0, -1):
            if self.stack[i].tag == tag:
                del self.stack[i:]
                return

    def handle_data(self, data: str) -> None:
        self.stack[-1].text.append(data)


def parse(text: str) -> Node:
    tree = _Tree()
    tree.feed(text)
    tree.close()
    return tree.root


def check_paper_report(text: str) -> None:
    """What the report of the paper's realistic case must show, whoever parsed it."""
    dom = parse(text)
    rows = [tr for table in dom.iter("table") if "verdicts" in table.classes() for tr in table.iter("tr")
            if "data-assertion" in tr.attrs]
    assert {tr.attrs["data-assertion"]: tr.attrs["data-verdict"] for tr in rows} == VERDICTS
    for tr in rows:
        cells = [td.all_text().strip() for td in tr.iter("td")]
        assert cells[0] == tr.attrs["data-assertion"] and cells[1] == tr.attrs["data-verdict"]
        # A7 holds for every length: by k-induction (or an invariant, where an engine finds one first)
        assert cells[6] in (("trace",) if cells[1] == "violated" else ("k-induction", "invariant"))
    articles = {a.attrs["data-assertion"]: a for a in dom.iter("article")}
    svgs = {name: list(a.iter("svg")) for name, a in articles.items()}
    assert {name: len(s) for name, s in svgs.items()} == {name: int(v == "violated") for name, v in VERDICTS.items()}
    machine = {"A1": "EXAX", "A2": "EXAX", "A3": "UR", "A4": "UR", "A5": "EXAX", "A6": "UR"}
    for name, m in machine.items():
        lifelines = [g.attrs["data-name"] for g in svgs[name][0].iter("g") if "lifeline" in g.classes()]
        assert lifelines == [ENVIRONMENT, m], name
    a1 = svgs["A1"][0]
    labels = [t.all_text() for t in a1.iter("text")]
    assert any(A1_MOVE.fullmatch(lab) for lab in labels), labels
    for label in A1_STATES:
        assert label in labels
    assert any(lab.startswith("tock") and "t=1" in lab for lab in labels)
    steps = [tr for tr in articles["A1"].iter("tr") if "data-step" in tr.attrs]
    assert [tr.attrs["class"] for tr in steps] == ["internal", "event", "internal", "tock"]
    assert [bool(A1_MOVE.search(tr.all_text())) for tr in steps] == [False, True, False, False]
    for ranges in ("core_int = -1..1", "core_real = -1..1"):
        assert ranges in dom.all_text()


@pytest.fixture(scope="module")
def paper_report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The report `check --report` writes for the paper's realistic case."""
    path = tmp_path_factory.mktemp("report") / "intelliwelder.html"
    outcome = run_cli(["check", str(EXAMPLE), *REALISTIC, "--report", str(path)])
    assert outcome.crash is None and outcome.exit_code == 10, outcome.output
    return path


def test_report_structure_without_a_browser(paper_report: Path) -> None:
    check_paper_report(paper_report.read_text(encoding="utf-8"))


def test_report_loads_nothing(paper_report: Path) -> None:
    text = paper_report.read_text(encoding="utf-8")
    assert not re.search(r"https?:", text), re.search(r".{40}https?:.{40}", text)
    dom = parse(text)
    assert not [n for n in dom.iter() if n.tag in ("script", "link", "img", "iframe", "object", "embed")]
    assert not [n for n in dom.iter() if {"src", "href"} & n.attrs.keys() and not n.attrs.get("href", "#").startswith("#")]
    assert "url(" not in text and "@import" not in text


def _screenshot_module():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("tockbmc_report_screenshot", REPO / "benchmarks" / "report_screenshot.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_report_in_headless_chromium(paper_report: Path) -> None:
    shot = _screenshot_module()
    browser = shot.chromium()
    if browser is None:
        pytest.skip("no chromium on PATH (Debian: apt-get install chromium)")
    dom = shot.headless(browser, "--dump-dom", paper_report.as_uri()).stdout
    assert "<svg" in dom
    check_paper_report(dom)


# --- the diagram's reading of a trace ---------------------------------------------------------

def _step(i: int, kind: str, event: str | None, note: str, states: dict[str, str], changed: dict[str, str] | None = None,
          channel: tuple = ()) -> TraceStep:
    return TraceStep(i, event, kind, note, states, changed or {}, channel)


CONTROLLER_TRACE = (
    _step(1, "internal", None, "A: s0", {"A": "s0", "B": "u0"}),
    _step(2, "event", "C::go.in.1", "t1", {"A": "s1", "B": "u0"}, {"A.x": "1"}, ("C::go", "in")),
    _step(3, "internal", None, "A sends ping, B: transition t2", {"A": "s1", "B": "u1"}),
    _step(4, "event", "C::moveCall.1", "", {"A": "s1", "B": "u1"}, {}, ("C::moveCall",)),
    _step(5, "tock", "tock", "", {"A": "s1", "B": "u1"}, {}, ("tock",)),
    _step(6, "event", "C::done.out", "", {"A": "s1", "B": "u2"}, {}, ("C::done", "out")),
    _step(7, "internal", None, "B: y := …", {"A": "s1", "B": "u2"}, {"B.y": "2"}),
    _step(8, "tock", "tock", "", {"A": "s1", "B": "u2"}, {}, ("tock",)),
    _step(9, "event", "C::terminate", "", {"A": "f", "B": "f"}, {}, ("C::terminate",)),
)


def test_diagram_reads_who_sends_to_whom() -> None:
    d = diagram(CONTROLLER_TRACE)
    assert d.lifelines == (ENVIRONMENT, "A", "B", PLATFORM) and d.element == "C" and d.framed
    arrows = [(r.step, r.message.kind, r.message.source, r.message.target) for r in d.rows if r.message]
    assert arrows == [(2, "input", ENVIRONMENT, "A"),  # the machine whose state changed
                      (3, "sync", "A", "B"),  # the note says who sends
                      (4, "call", BOUNDARY, PLATFORM),  # no machine changed: the controller's boundary
                      (6, "output", "B", ENVIRONMENT),
                      (9, "terminate", BOUNDARY, ENVIRONMENT)]
    assert [(r.step, r.time) for r in d.rows if r.kind == "tock"] == [(5, 1), (8, 2)]
    assert [(r.step, r.states) for r in d.rows if r.states] == [
        (1, (("A", "s0"), ("B", "u0"))), (2, (("A", "s1"),)), (3, (("B", "u1"),)), (6, (("B", "u2"),)),
        (9, (("A", "f"), ("B", "f")))]
    assert [(r.step, r.notes) for r in d.rows if r.notes] == [(1, (("A", "s0"),)), (7, (("B", "y := 2"),))]  # the value from `changed`


def test_diagram_reads_the_interpreters_notes_and_bare_traces() -> None:
    explicit = diagram([_step(1, "internal", None, "A.ping to B.pong (3)", {"A": "s", "B": "u"})])
    assert explicit.rows[0].message is not None
    assert (explicit.rows[0].message.source, explicit.rows[0].message.target) == ("A", "B")
    assert explicit.rows[0].message.label == "ping.3"
    # a specification's trace: no states, channels only in the event's text
    bare = diagram([_step(1, "event", "M::e.in.2", "", {}), _step(2, "event", "M::stopCall", "", {}),
                    _step(3, "tock", "tock", "", {})])
    assert bare.machines == ("M",) and not bare.framed
    assert [(r.message.kind, r.message.source, r.message.target) for r in bare.rows if r.message] == [
        ("input", ENVIRONMENT, "M"), ("call", "M", PLATFORM)]


def _arrows(svg_text: str) -> list[tuple[str, float, float, float]]:
    """(kind, x where the arrow starts, x where it ends, x of its head's tip) for each arrow drawn."""
    out = []
    for g in parse(svg_text).iter("g"):
        if "message" in g.classes():
            line = next(g.iter("line"))
            tip = float(next(g.iter("polygon")).attrs["points"].split()[0].split(",")[0])
            kind = (g.classes() - {"message"}).pop()
            out.append((kind, float(line.attrs["x1"]), float(line.attrs["x2"]), tip))
    return out


def test_arrows_point_from_sender_to_receiver() -> None:
    d = diagram(CONTROLLER_TRACE)
    svg = to_string(render(d))
    lifeline_x = {g.attrs["data-name"]: float(next(g.iter("line")).attrs["x1"])
                  for g in parse(svg).iter("g") if "lifeline" in g.classes()}
    env, a, b, platform = (lifeline_x[n] for n in d.lifelines)
    assert env < a < b < platform
    arrows = _arrows(svg)
    assert [k for k, *_ in arrows] == ["input", "sync", "call", "output", "terminate"]
    for _kind, _x1, x2, tip in arrows:
        assert tip == x2  # the head is at the receiving end
    (_, i1, i2, _), (_, s1, s2, _), (_, c1, c2, _), (_, o1, o2, _), (_, t1, t2, _) = arrows
    assert (i1, i2) == (env, a) and (s1, s2) == (a, b) and (o1, o2) == (b, env) and t2 == env
    assert b < c1 < platform and c2 == platform  # from the frame's right edge
    assert env < t1 < a  # the frame's left edge
    frame = next(r for r in parse(svg).iter("rect") if "frame" in r.classes())
    assert float(frame.attrs["x"]) == pytest.approx(t1) and float(frame.attrs["x"]) + float(frame.attrs["width"]) == pytest.approx(c1)


def test_labels_fit_between_their_lifelines() -> None:
    long = "UR::move.in.(dist1=1, dist2=0, time=-1, blending=false, large_offset=true, sharp_corner=false)"
    lines = label_lines(long)
    assert len(lines) > 1 and all(len(line) <= LABEL_CHARS for line in lines)
    assert "".join(lines).replace(" ", "") == long.replace(" ", "")
    trace = (_step(1, "event", long, "t1", {"UR": "time_check"}, {}, ("UR::move", "in")),)
    svg = parse(to_string(render(diagram(trace))))
    x = {g.attrs["data-name"]: float(next(g.iter("line")).attrs["x1"]) for g in svg.iter("g") if "lifeline" in g.classes()}
    widest = max(len(t.all_text()) for g in svg.iter("g") if "message" in g.classes() for t in g.iter("text"))
    assert x["UR"] - x[ENVIRONMENT] >= widest * 0.6 * 12


def test_model_text_is_escaped() -> None:
    nasty = "<script>alert('x')</script>&amp;"
    step = _step(1, "event", f"M::e.in.{nasty}", nasty, {"M": nasty}, {"M.v": nasty}, ("M::e", "in"))
    result = Result(assertion="A<1>", text=nasty, verdict=Verdict.VIOLATED, bound=5, ranges={"core_int": nasty},
                    seconds=0.1, reason=nasty, trace=(step,), proof=Proof.TRACE, pos="m.rct:1:1")
    text = render_report([result], title=nasty, version="0")
    assert "<script" not in text
    dom = parse(text)
    assert not list(dom.iter("script"))
    assert nasty in dom.all_text()  # shown as text, not markup


@dataclass(frozen=True)
class _SourcedStep(TraceStep):
    source: str = ""  # as `TraceStep` has it where steps know their model text


def test_step_table_shows_the_source_when_there_is_one() -> None:
    def page(steps: tuple[TraceStep, ...]) -> Node:
        result = Result(assertion="A", text="t", verdict=Verdict.VIOLATED, bound=5, ranges={}, seconds=0.1,
                        reason="r", trace=steps, proof=Proof.TRACE)
        return parse(render_report([result], title="m", version="0"))

    sourced = _SourcedStep(1, "M::e.in", "event", "t1", {"M": "s"}, {}, ("M::e", "in"), source="/models/m.rct:3:5")
    cells = [td for td in page((sourced,)).iter("td") if "source" in td.classes()]
    assert [(td.all_text(), td.attrs["title"]) for td in cells] == [("m.rct:3:5", "/models/m.rct:3:5")]
    plain = page((_step(1, "event", "M::e.in", "t1", {"M": "s"}, {}, ("M::e", "in")),))
    assert "Source" not in [th.all_text() for th in plain.iter("th")]


def test_a_report_in_a_directory_that_does_not_exist_is_a_usage_error(tmp_path: Path) -> None:
    """Refused before the check (it had been an internal error after it, the verdicts lost)."""
    outcome = run_cli(["check", str(EXAMPLE), "-a", "A7", "--report", str(tmp_path / "missing" / "r.html")])
    assert outcome.exit_code == 2 and outcome.crash is None, outcome.output
    assert "no directory" in outcome.output


def test_assertions_of_one_name_in_two_files_are_named_by_their_files(tmp_path: Path) -> None:
    """As in the other formats (tests/test_formats.py): the table's rows and the traces' sections."""
    outcome = run_cli(["check", write_files(tmp_path, REUSED_NAMES), "-j", "1", "--report", str(tmp_path / "r.html")])
    assert outcome.crash is None and outcome.exit_code == 10, outcome.output
    dom = parse((tmp_path / "r.html").read_text(encoding="utf-8"))
    rows = [tr.attrs["data-assertion"] for table in dom.iter("table") if "verdicts" in table.classes()
            for tr in table.iter("tr") if "data-assertion" in tr.attrs]
    assert rows == REUSED_LABELS
    assert [a.attrs["data-assertion"] for a in dom.iter("article")] == REUSED_LABELS
