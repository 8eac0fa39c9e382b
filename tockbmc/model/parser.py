"""Parse `.rct` and `.assertions` text into Lark syntax trees.

The Lark tree is the syntax tree: every node keeps its source position in
`meta` (tokens in their own fields), and the resolver walks it once to build
the resolved model in `tockbmc.model.ast`.
"""

from __future__ import annotations

from functools import lru_cache

from lark import Lark, Token, Tree, UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from tockbmc.model import grammars
from tockbmc.model.ast import Pos
from tockbmc.model.diagnostics import Diagnostic
from tockbmc.model.limits import MAX_NESTING, too_deep
from tockbmc.model.rules import LIMIT

# Readable names for the grammar's pattern terminals, used in syntax error messages;
# string terminals are shown as their text.
_TERMINAL_NAMES = {
    "ID": "a name", "INT": "a number", "FLOAT": "a number", "BOOLEAN": "'true'", "STRING": "a string",
    "CSP_CODE": "'csp-begin … csp-end'", "$END": "end of file",
}


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return grammars.build("robochart.lark", start=["rct", "assertions"], propagate_positions=True,
                          maybe_placeholders=False)


def parse(text: str, path: str, kind: str) -> tuple[Tree | None, list[Diagnostic]]:
    """Parse one file; `kind` is "rct" or "assertions".

    Returns the tree, or None and the syntax error as a diagnostic.
    """
    try:
        tree = _parser().parse(text, start=kind)
    except UnexpectedInput as exc:
        return None, [_syntax_error(exc, text, path)]
    deep = too_deep(tree)
    if deep is not None:
        return None, [Diagnostic(_start(path, deep), f"nested too deeply: more than {MAX_NESTING} levels of states, "
                                                     "statements and expressions", rule=LIMIT)]
    return tree, []


def _start(path: str, tree: Tree) -> Pos:
    """Where `tree` starts (a one-character span: the subtree may run over many lines)."""
    node: Tree | Token = tree
    while isinstance(node, Tree) and getattr(node.meta, "empty", True) and node.children:
        node = node.children[0]
    if isinstance(node, Token):
        return Pos(path, node.line or 1, node.column or 1)
    return Pos(path, getattr(node.meta, "line", 1), getattr(node.meta, "column", 1))


def _describe(token_type: str, value: str) -> str:
    if token_type == "$END":
        return "end of file"
    if token_type == "CSP_CODE":
        return "'csp-begin … csp-end' block"
    first_line = value.split("\n", 1)[0]
    if len(first_line) > 30 or first_line != value:
        first_line = first_line[:30] + "…"
    return f"'{first_line}'"


def _syntax_error(exc: UnexpectedInput, text: str, path: str) -> Diagnostic:
    line = getattr(exc, "line", 1) or 1
    column = getattr(exc, "column", 1) or 1
    if isinstance(exc, UnexpectedToken):
        token = exc.token
        if token.type == "$END":
            line, column = _end_position(text)
        found = _describe(token.type, str(token))
        expected = _expected(exc.expected)
        message = f"syntax error: unexpected {found}" + (f"; expected {expected}" if expected else "")
    elif isinstance(exc, UnexpectedCharacters):
        message = f"syntax error: unexpected character {text[exc.pos_in_stream or 0]!r}"
    elif isinstance(exc, UnexpectedEOF):
        line, column = _end_position(text)
        message = "syntax error: unexpected end of file"
    else:  # pragma: no cover - Lark has no other kinds
        message = "syntax error"
    return Diagnostic(Pos(path, line, column), message)


def _end_position(text: str) -> tuple[int, int]:
    lines = text.split("\n")
    return len(lines), len(lines[-1]) + 1


def _expected(terminals: set[str]) -> str:
    names = set()
    for t in terminals:
        if t in _TERMINAL_NAMES:
            names.add(_TERMINAL_NAMES[t])
            continue
        try:
            pattern = _parser().get_terminal(t).pattern
        except KeyError:
            continue
        if pattern.type == "str":
            names.add(f"'{pattern.value}'")
    ordered = sorted(names)
    if not ordered:
        return ""
    if len(ordered) > 8:
        return ", ".join(ordered[:8]) + ", …"
    return ", ".join(ordered)
