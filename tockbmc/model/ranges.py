"""Ranges: the bounds a user (or RoboTool's instantiation) puts on the values the environment supplies."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from fractions import Fraction

from tockbmc.model import ast
from tockbmc.model.numbers import real_text


@dataclass(frozen=True)
class Range:
    """A closed interval bounding values the environment supplies."""

    low: Fraction
    high: Fraction

    def __str__(self) -> str:
        return f"{real_text(self.low)}..{real_text(self.high)}"


@dataclass(frozen=True)
class Ranges:
    """Ranges by built-in or model type name (`core_int`, `MyType`) and by path (`EXAX::move.time`)."""

    by_type: dict[str, Range] = field(default_factory=dict)
    by_path: dict[str, Range] = field(default_factory=dict)
    # Names (types or paths, as above) whose bounds are parameters: symbols rather than numbers,
    # so that one query covers every range (`tockbmc explore`).  They win over a range of the same name.
    parametric: tuple[str, ...] = ()
    # Whether the environment's reals are the integers of their range, as FDR's are (`--robotool`).
    integral_reals: bool = False
    # The length of a sequence the environment supplies where no range is on its path; None:
    # unbounded (`--robotool`: 0..2, RoboTool's `LSeq(T,2)`, docs/robotool-evidence.md §9.5).
    sequence_length: Range | None = None

    @classmethod
    def named(cls, ranges: Mapping[str, Range]) -> Ranges:
        """Ranges given by name, a type's or a path's: `{"core_int": …, "M::e.x": …}`."""
        return cls({k: r for k, r in ranges.items() if not is_path(k)}, {k: r for k, r in ranges.items() if is_path(k)})

    def by_name(self) -> dict[str, Range]:
        """Every range by its name, a type's or a path's (the inverse of `named`)."""
        return {**self.by_type, **self.by_path}

    def length(self, paths: Iterable[str]) -> Range | None:
        """The length range of a sequence the environment supplies at `paths` (spellings of one path,
        the first tried first): the first of them with a range, else `sequence_length`."""
        return next((self.by_path[p] for p in paths if p in self.by_path), self.sequence_length)

    def describe(self) -> dict[str, str]:
        return {**{k: str(v) for k, v in self.by_type.items()}, **{k: str(v) for k, v in self.by_path.items()},
                **{k: "parameter" for k in self.parametric}}


TYPE_RANGE_NAMES = {"int": "core_int", "nat": "core_nat", "real": "core_real"}


def is_path(name: str) -> bool:
    """A range name that is a path (`EXAX::move.time`) rather than a type (`core_int`, `Speed`)."""
    return "::" in name or "." in name


def holds_sequence(t: ast.Type | None) -> bool:
    """Whether a value of type `t` holds a sequence: is one, or has one in a field, a part, an item
    or a literal's parameter."""
    stack, seen = [t], set()
    while stack:
        u = stack.pop()
        if u is None or id(u) in seen:
            continue
        seen.add(id(u))
        if isinstance(u, ast.SeqType):
            return True
        if isinstance(u, ast.SetType):
            stack.append(u.element)
        elif isinstance(u, ast.RecordType):
            stack += [f.type for f in u.fields]
        elif isinstance(u, ast.ProductType):
            stack += u.parts
        elif isinstance(u, ast.EnumType):
            stack += [p for ps in u.params for p in ps]
    return False


def supplied_sequence(element: object) -> bool:
    """Whether the environment may supply `element` a sequence, whose length `Ranges.length` bounds:
    an input `e?x` (of a transition or an action) of a type holding a sequence, a shared variable
    (required, or the platform's) of such a type, which the environment may write, or a variable
    bound by a quantifier or a set comprehension, which takes its values as an input does."""
    for item in ast.parts(element):
        if isinstance(item, ast.Trigger) and item.kind == "input" or isinstance(item, ast.Receive):
            if holds_sequence(item.event.type):
                return True
        elif isinstance(item, (ast.Quantifier, ast.SetComprehension)):
            if any(holds_sequence(v.type) for v in item.variables):
                return True
        elif isinstance(item, ast.RoboticPlatform):
            if any(holds_sequence(v.type) for v in item.variables if not v.constant):
                return True
        elif isinstance(item, ast.Variable) and item.kind == "interface" and not item.constant:
            if holds_sequence(item.type):
                return True
    return False
