"""Limits on the shape of input that every later stage is built to handle.

Past these the input gets a diagnostic at the place it crosses the limit, rather than a crash
somewhere downstream (many walkers of the model recurse once per level of nesting).
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager

from lark import Token, Tree

from tockbmc.model.numbers import max_digits

# Levels of the syntax tree: a state inside a state, a statement inside a statement, an operator
# inside an expression, each count one, and they add up (README, "Limits").
MAX_NESTING = 500
# Levels of a CSP block's syntax tree: each operator counts one. Lower, because the
# specifications' process terms are compared and hashed recursively (three frames a level).
MAX_CSP_NESTING = 200
# Declarations resolved while resolving another (a record type's field of a record type, a function
# called in a function's definition, …): walkers of types and calls recurse once per link.
MAX_DECLARATION_CHAIN = 100


def too_deep(tree: Tree, limit: int = MAX_NESTING) -> Tree | None:
    """The first subtree (in text order) at a depth beyond `limit`, or None."""
    stack: list[tuple[Tree, int]] = [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > limit:
            return node
        stack.extend((child, depth + 1) for child in reversed(node.children) if isinstance(child, Tree))
    return None


def long_numbers(tree: Tree, types: set[str]) -> Iterator[Token]:
    """The tokens of `types` (number terminals) with more digits than Python converts to a number."""
    limit = max_digits()
    stack: list[Tree | Token] = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, Tree):
            stack.extend(reversed(node.children))
        elif isinstance(node, Token) and node.type in types and sum(c.isdigit() for c in node) > limit:
            yield node


@contextmanager
def recursion_room(depth: int = 20_000) -> Iterator[None]:
    """Let Python recurse `depth` deep inside the block.

    For code that recurses once per level of nesting, within `MAX_NESTING` but past Python's
    default limit of 1000 frames: the resolver (a few frames per level), `json` writing nested
    states. Calls between Python functions use no C stack (Python 3.11), so this is safe.
    """
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, depth))
    try:
        yield
    finally:
        sys.setrecursionlimit(limit)


# An assertion whose check recursed past Python's limit anyway (a CSP process defined by a process
# defined by …, hundreds deep, is evaluated by recursion) is reported with this reason.
TOO_DEEP_TO_CHECK = ("nested too deeply to check: definitions defined through definitions, or operators inside "
                     "operators, hundreds deep")

# Both engines, where no configuration can start (a check of every run would hold vacuously).
NO_START = ("no run starts: no initial configuration fits the model's types (an initial value outside "
            "its variable's type, such as a negative nat, or constants' values that contradict each other)")
