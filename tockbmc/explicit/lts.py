"""A model element as a specification: its state graph, explored by the interpreter.

Refinement between two model elements (RoboTool's simGeneric cases compare a machine, renamed,
with another) needs one of them on the specification's side, where both engines follow
specifications as sets of terms (`properties.spec.Monitor`).  The interpreter lists that element's
configurations and steps within the ranges (every value of every input), and the graph becomes
`Lts` terms: an internal step is a τ, `tock` is `tock`, an event is the event its channel is
renamed to, and a terminated configuration can do ✓ (as `terminate -> SKIP` does).  The
environment's choice of starting values is an internal choice among the initial configurations.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Hashable

from tockbmc.explicit.interpreter import Config, Interpreter, Step
from tockbmc.model.errors import Unsupported
from tockbmc.properties.spec import TOCK, EnumValue, Lts, LtsGraph

LTS_LIMIT = 20_000  # configurations of the element on the specification's side


def element_lts(interp: Interpreter, renames: tuple[tuple[tuple, tuple], ...], literals: dict[str, EnumValue],
                name: str, limit: int = LTS_LIMIT, owner: tuple[str, str] | None = None) -> Lts:
    """The state graph of the interpreter's element, its channels renamed by `renames` (`[[ a <- b ]]`:
    a channel `a`, or an event of it, becomes `b`), or, with `owner` = (this element's name, the
    other's), each channel `this::x` named `other::x`, as RoboTool renames the events of two
    elements compared (its issue robochart-csp-gen#91, quoted in the suite's test10); raises
    `Unsupported` past `limit` configurations."""
    index: dict[Hashable, int] = {}
    moves: list[tuple[tuple[tuple | None, int], ...]] = [()]  # node 0: the choice of starting values
    ticks: set[int] = set()
    todo: deque[Config] = deque()

    def node(c: Config) -> int:
        if c not in index:
            if len(index) >= limit:
                raise Unsupported(None, f"{name} has more than {limit} configurations, too many to follow as a "
                                        "specification")
            index[c] = len(moves)
            moves.append(())
            todo.append(c)
        return index[c]

    moves[0] = tuple((None, node(c)) for c in interp.initial())
    while todo:
        c = todo.popleft()
        n = index[c]
        if interp.terminated(c):
            ticks.add(n)
        moves[n] = tuple((_event(s, renames, literals, owner), node(s.target)) for s in interp.steps(c))
    return Lts(LtsGraph(tuple(moves), frozenset(ticks)), 0)


def _event(s: Step, renames: tuple[tuple[tuple, tuple], ...], literals: dict[str, EnumValue],
           owner: tuple[str, str] | None) -> tuple | None:
    if s.kind == "internal":
        return None
    if s.kind == "tock":
        return TOCK
    assert s.event is not None
    e: tuple = (*s.event.channel, *(literals.get(v, v) if isinstance(v, str) else v for v in s.event.values))
    if owner is not None and isinstance(e[0], str) and e[0].startswith(f"{owner[0]}::"):
        e = (f"{owner[1]}::{e[0][len(owner[0]) + 2:]}", *e[1:])
    for old, new in renames:
        if e[: len(old)] == old:  # renamings apply at once: the first that matches
            return (*new, *e[len(old):])
    return e
