"""Parse the CSP blocks of an `.assertions` file (the subset of `docs/language.md` §4).

A block is parsed when an assertion needs one of its processes, not when the
file is loaded: a block that is outside the subset (RoboTool's
`instantiations` blocks, for instance) only makes the assertions that use it
`unsupported`.  The Lark tree is the syntax tree; positions are mapped from
the block's text to the file.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from lark import Lark, Token, Tree, UnexpectedInput

from tockbmc.model import ast, grammars
from tockbmc.model.errors import Unsupported
from tockbmc.model.limits import MAX_CSP_NESTING, long_numbers, too_deep
from tockbmc.model.numbers import max_digits


class CspError(Unsupported):
    """Something outside the subset, or wrong, at a position in a CSP block."""

    def __init__(self, pos: ast.Pos, what: str):
        super().__init__(pos, what)

    def __str__(self) -> str:
        return f"{self.pos}: {self.what}"


def canonical(name: str) -> str:
    """CSP names compare by their last two parts (`pkg::EXAX::move` is `EXAX::move`)."""
    return "::".join(name.split("::")[-2:])


@dataclass(frozen=True)
class Definition:
    """`N = P` or `N(x, …) = P`; `timed` when it is inside `Timed(…) { … }`."""

    name: str
    params: tuple[str, ...]
    body: Tree
    timed: bool
    pos: ast.Pos
    block: ast.CspBlock


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return grammars.build("csp.lark", propagate_positions=True, maybe_placeholders=False)


def position(block: ast.CspBlock, line: int, column: int) -> ast.Pos:
    """The file position of (line, column) in the block's text."""
    if line == 1:
        return ast.Pos(block.pos.path, block.code_line, block.code_column + column - 1)
    return ast.Pos(block.pos.path, block.code_line + line - 1, column)


def pos_of(block: ast.CspBlock, node: Tree | Token) -> ast.Pos:
    if isinstance(node, Token):
        return position(block, node.line or 1, node.column or 1)
    meta = node.meta
    return position(block, getattr(meta, "line", 1), getattr(meta, "column", 1))


@lru_cache(maxsize=256)
def parse_block(block: ast.CspBlock) -> tuple[Definition, ...]:
    """The definitions of a block, or `CspError` at the first syntax error."""
    try:
        tree = _parser().parse(block.text)
    except UnexpectedInput as exc:
        pos = position(block, getattr(exc, "line", 1) or 1, getattr(exc, "column", 1) or 1)
        raise CspError(pos, "this CSP is outside the subset tockbmc understands (docs/language.md §4)") from None
    deep = too_deep(tree, MAX_CSP_NESTING)
    if deep is not None:
        raise CspError(pos_of(block, deep), f"nested too deeply: more than {MAX_CSP_NESTING} levels of CSP operators")
    for token in long_numbers(tree, {"NUMBER"}):
        raise CspError(pos_of(block, token), f"number too long: at most {max_digits()} digits")
    out: list[Definition] = []
    for item in tree.children:
        if not isinstance(item, Tree):
            continue
        if item.data == "timed_section":
            out += [definition(block, d, True) for d in item.children[1:] if isinstance(d, Tree)]
        elif item.data == "definition":
            out.append(definition(block, item, False))
        elif item.data == "nametype":  # `nametype core_nat = {0..3}`: a name for a set of values
            out.append(definition(block, item, False))
        elif item.data == "channels":  # `channel int__`: events of the specification's own, without values
            out += [Definition(str(n), (), Tree("channel_event", [n]), False, pos_of(block, n), block)
                    for n in item.children]
    return tuple(out)


def definition(block: ast.CspBlock, tree: Tree, timed: bool) -> Definition:
    name = str(tree.children[0])
    params: tuple[str, ...] = ()
    body = tree.children[-1]
    if len(tree.children) == 3:
        params = tuple(str(t) for t in tree.children[1].children)
    return Definition(name, params, body, timed, pos_of(block, tree), block)


def find(blocks: tuple[ast.CspBlock, ...], name: str) -> Definition:
    """The top-level definition of process `name` in the blocks that define it."""
    for block in blocks:
        if name in block.defines:
            for d in parse_block(block):
                if d.name == name:
                    return d
            raise CspError(block.pos, f"'{name}' is not defined at the top level of block '{block.name}'")
    raise KeyError(name)
