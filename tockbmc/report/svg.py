"""A sequence diagram (`report/sequence.py`) drawn as inline SVG, built with `xml.etree` (which escapes text).

Lifelines stand left to right with room for the widest label that crosses each gap; each step is
one row: a label over its arrow, or a τ note beside the lifeline, then the states entered as boxes
on the lifelines; a `tock` is a dashed line across the diagram with the time so far.  Text is
monospaced, so its width is known without a browser.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass

from tockbmc.report.sequence import BOUNDARY, ENVIRONMENT, Diagram, Message, Row

FONT = 12  # px, DejaVu Sans Mono or another monospace font
CHAR = 0.61 * FONT  # the advance of one character
LINE = 15  # px between lines of a label
LABEL_CHARS = 56  # longer labels wrap at their commas
GUTTER = 44  # the step numbers' column
MARGIN = 16
TOCK_LABEL = 100  # right of the last lifeline: "tock  t=12"
HEAD = 30  # height of a lifeline's name box
TAB = 24  # height of the tab with the frame's name
BOX = 22  # height of a state box
ARROW = 8  # arrowhead length
MIN_GAP = 120

# A white outline under text, so a label stays readable where it crosses a lifeline.
HALO = {"paint_order": "stroke", "stroke": "#ffffff", "stroke_width": 4, "stroke_linejoin": "round"}
COLOURS = {"input": "#1f5fbf", "output": "#1d7a3a", "call": "#7b3fb0", "terminate": "#b3261e", "sync": "#c26a00",
           "event": "#555555"}


def text_width(text: str) -> float:
    return len(text) * CHAR


def label_lines(label: str) -> list[str]:
    """A long event label on a few lines: broken after its channel (`….in.`) and at the commas of its values."""
    if len(label) <= LABEL_CHARS:
        return [label]
    lines: list[str] = []
    head, sep, values = label.partition(".(")
    if sep:
        lines.append(head + ".")
        rest = "(" + values
    else:
        rest = label
    current = ""
    for piece in rest.split(", "):
        candidate = f"{current}, {piece}" if current else piece
        if current and len(candidate) > LABEL_CHARS:
            lines.append(current + ",")
            current = piece
        else:
            current = candidate
    return [*lines, current]


@dataclass(frozen=True)
class _Layout:
    x: dict[str, float]  # lifeline -> x
    frame: tuple[float, float] | None  # the element's frame: left and right edge
    width: float

    def end(self, name: str, other: str) -> float:
        """Where an arrow ends at `name`: its lifeline, or the frame's edge nearer the other end."""
        if name != BOUNDARY:
            return self.x[name]
        assert self.frame is not None
        left, right = self.frame
        return left if self.x.get(other, left) <= left else right


def _box_width(text: str) -> float:
    return text_width(text) + 14


def layout(d: Diagram) -> _Layout:
    """Lifelines' positions: each gap wide enough for the boxes on either side, the notes beside the left
    lifeline and the labels of the arrows that cross it; the element's frame just clears its machines' boxes."""
    lines = d.lifelines
    half = {name: _box_width(name) / 2 for name in lines}
    for r in d.rows:
        for m, st in r.states:
            half[m] = max(half[m], _box_width(st) / 2)
    left_pad = half[d.machines[0]] + 12 if d.framed else 0.0
    right_pad = half[d.machines[-1]] + 12 if d.framed else 0.0
    gaps = [max(MIN_GAP, half[a] + half[b] + 16) for a, b in zip(lines, lines[1:])]
    gaps[0] = max(gaps[0], half[lines[0]] + left_pad + 16)
    if d.platform:
        gaps[-1] = max(gaps[-1], half[lines[-1]] + right_pad + 16)
    index = {name: i for i, name in enumerate(lines)}
    needs: list[tuple[int, int, float]] = []
    beyond = 0.0  # how far notes on the rightmost lifeline reach past it
    for r in d.rows:
        for m, note in r.notes:
            width = text_width("τ " + note) + 16
            if index[m] < len(gaps):
                needs.append((index[m], index[m] + 1, width + 8))
            else:
                beyond = max(beyond, width)
        if r.message is not None:
            a, b = _span(r.message, index, len(d.machines))
            width = max(text_width(line) for line in label_lines(r.message.label)) + 24
            if BOUNDARY in (r.message.source, r.message.target):
                width += left_pad if a == 0 else right_pad
            needs.append((a, b, width))
    for a, b, width in sorted(needs, key=lambda n: n[1] - n[0]):
        deficit = width - sum(gaps[a:b])
        if deficit > 0:
            for i in range(a, b):
                gaps[i] += deficit / (b - a)
    x = {lines[0]: GUTTER + MARGIN + half[lines[0]]}
    for (left, name), gap in zip(zip(lines, lines[1:]), gaps):
        x[name] = x[left] + gap
    frame = (x[d.machines[0]] - left_pad, x[d.machines[-1]] + right_pad) if d.framed else None
    right = max(x[lines[-1]] + max(half[lines[-1]], beyond), frame[1] if frame else 0.0)
    tocks = any(r.kind == "tock" for r in d.rows)
    return _Layout(x, frame, right + (TOCK_LABEL if tocks else 0) + MARGIN)


def _span(m: Message, index: dict[str, int], machines: int) -> tuple[int, int]:
    """The gaps an arrow crosses, as a slice of lifeline indices (the boundary counts as its nearer machine)."""
    def at(name: str, other: str) -> int:
        if name != BOUNDARY:
            return index[name]
        return 1 if index.get(other, 0) == 0 else machines
    a, b = at(m.source, m.target), at(m.target, m.source)
    return (min(a, b), max(a, b)) if a != b else (a, a + 1)


def _el(parent: ET.Element, tag: str, text: str | None = None, **attrs: object) -> ET.Element:
    e = ET.SubElement(parent, tag, {k.rstrip("_").replace("_", "-"): _fmt(v) for k, v in attrs.items() if v is not None})
    if text is not None:
        e.text = text
    return e


def _fmt(v: object) -> str:
    return f"{v:.1f}".removesuffix(".0") if isinstance(v, float) else str(v)


def render(d: Diagram, title: str = "") -> ET.Element:
    """The diagram as an `<svg>` element."""
    lay = layout(d)
    head = float(MARGIN + (TAB if lay.frame is not None and d.element else 0))  # the frame's name tab above
    top = head + HEAD + 12
    height = top + sum(_row_height(r) for r in d.rows) + MARGIN
    # No xmlns: the SVG lives inside HTML, where the parser puts it in the SVG namespace itself.
    svg = ET.Element("svg", {"class": "sequence", "role": "img",
                             "width": _fmt(lay.width), "height": _fmt(height),
                             "viewBox": f"0 0 {_fmt(lay.width)} {_fmt(height)}",
                             "font-family": "DejaVu Sans Mono, Menlo, Consolas, monospace",
                             "font-size": str(FONT)})
    if title:
        _el(svg, "title", title)
    if lay.frame is not None:  # UML's frame: the element's name in a tab at its top left
        left, right = lay.frame
        _el(svg, "rect", class_="frame", x=left, y=float(MARGIN - 6), width=right - left,
            height=height - 2 * MARGIN + 12, rx=6, fill="#f6f8fb", stroke="#8a9bb3", stroke_dasharray="6 4")
        if d.element:
            w = text_width(d.element) + 16
            _el(svg, "path", class_="frame-tab", d=f"M {_fmt(left)} {MARGIN - 6} h {_fmt(w)} v {TAB - 6} "
                                                   f"l -6 6 h {_fmt(-w + 6)} z", fill="#dfe6ef", stroke="#8a9bb3")
            _el(svg, "text", d.element, class_="frame-label", x=left + 8, y=float(MARGIN + TAB / 2 - 1),
                fill="#3b4a5e", font_weight="bold")
    for name in d.lifelines:
        x = lay.x[name]
        kind = "machine" if name in d.machines else "environment" if name == ENVIRONMENT else "platform"
        g = _el(svg, "g", class_=f"lifeline {kind}", data_name=name)
        _el(g, "line", x1=x, y1=head + HEAD, x2=x, y2=height - MARGIN, stroke="#9aa5b1", stroke_dasharray="4 4")
        w = _box_width(name)
        _el(g, "rect", x=x - w / 2, y=head, width=w, height=float(HEAD), rx=4,
            fill="#ffffff" if kind == "machine" else "#eef1f4", stroke="#34495e")
        _el(g, "text", name, x=x, y=head + HEAD / 2 + 4, text_anchor="middle", font_weight="bold")
    y = float(top)
    for r in d.rows:
        _draw_row(svg, d, lay, r, y)
        y += _row_height(r)
    return svg


def _row_height(r: Row) -> float:
    label = len(label_lines(r.message.label)) * LINE if r.message is not None else 0
    return label + 16 + (BOX + 10 if r.states else 0) + 4


def _draw_row(svg: ET.Element, d: Diagram, lay: _Layout, r: Row, y: float) -> None:
    g = _el(svg, "g", class_=f"step {r.kind}", data_step=r.step)
    lines = label_lines(r.message.label) if r.message is not None else []
    mid = y + len(lines) * LINE + 8  # the arrow's (or the note's, or the tock's) height
    _el(g, "text", str(r.step), class_="step-number", x=float(GUTTER), y=mid + 4, text_anchor="end",
        fill="#7a8591")
    if r.kind == "tock":
        label = f"tock  t={r.time}"
        _el(g, "line", class_="tock", x1=float(GUTTER + 8), y1=mid, x2=lay.width - MARGIN - text_width(label) - 8,
            y2=mid,
            stroke="#d08a00", stroke_width=1.5, stroke_dasharray="10 4")
        _el(g, "text", label, class_="tock-label", x=lay.width - MARGIN, y=mid + 4,
            text_anchor="end", fill="#a86b00", font_weight="bold")
    if r.message is not None:
        _arrow(g, lay, r.message, lines, y, mid)
    for m, note in r.notes:
        x = lay.x[m]
        _el(g, "circle", class_="tau", cx=x, cy=mid, r=3.5, fill="#7a8591")
        _el(g, "text", f"τ {note}", class_="note", x=x + 8, y=mid + 4, fill="#5f6b77", font_style="italic",
            **HALO)
    for m, state in r.states:
        x, w = lay.x[m], _box_width(state)
        box = _el(g, "g", class_="state", data_machine=m)
        _el(box, "rect", x=x - w / 2, y=mid + 8, width=w, height=float(BOX), rx=10, fill="#fff8e1",
            stroke="#b08900")
        _el(box, "text", state, x=x, y=mid + 8 + BOX / 2 + 4, text_anchor="middle", fill="#4d3b00")


def _arrow(g: ET.Element, lay: _Layout, m: Message, lines: Sequence[str], y: float, mid: float) -> None:
    x1, x2 = lay.end(m.source, m.target), lay.end(m.target, m.source)
    colour = COLOURS[m.kind]
    a = _el(g, "g", class_=f"message {m.kind}", data_from=m.source, data_to=m.target)
    _el(a, "line", x1=x1, y1=mid, x2=x2, y2=mid, stroke=colour, stroke_width=1.6,
        stroke_dasharray="6 3" if m.kind == "terminate" else None)
    _head(a, x1, x2, mid, colour)
    if m.kind == "event":
        _head(a, x2, x1, mid, colour)
    centre = (x1 + x2) / 2
    for i, line in enumerate(lines):
        _el(a, "text", line, class_="label", x=centre, y=y + (i + 1) * LINE - 2, text_anchor="middle", fill=colour,
            **HALO)


def _head(parent: ET.Element, x1: float, x2: float, y: float, colour: str) -> None:
    """An arrowhead at `x2`, pointing away from `x1`."""
    d = ARROW if x2 >= x1 else -ARROW
    _el(parent, "polygon", class_="head", points=f"{_fmt(x2)},{_fmt(y)} {_fmt(x2 - d)},{_fmt(y - 4)} "
                                                  f"{_fmt(x2 - d)},{_fmt(y + 4)}", fill=colour)


def to_string(svg: ET.Element) -> str:
    return ET.tostring(svg, encoding="unicode", short_empty_elements=True)
