"""Packages, imports and the global table of top-level declarations."""

from __future__ import annotations

from dataclasses import dataclass, field

from lark import Token, Tree

# Kinds of top-level declarations, as the grammar's rule names give them.
TYPE_KINDS = ("primitive_type", "record_type", "enumeration")
MACHINE_KINDS = ("stm_def",)
CONTROLLER_KINDS = ("controller_def",)
OPERATION_KINDS = ("operation_def",)


@dataclass
class Declaration:
    """A top-level declaration: its kind (grammar rule), name, tree and file."""

    kind: str
    qname: str
    tree: Tree
    file: FileScope


@dataclass
class FileScope:
    """What names a file sees: its own package and its imports."""

    path: str
    package: str | None
    wildcard_imports: list[str] = field(default_factory=list)
    exact_imports: list[str] = field(default_factory=list)
    toolkit: bool = False  # imports a RoboChart toolkit: its functions are built in

    def qualify(self, name: str) -> str:
        return f"{self.package}::{name}" if self.package else name

    def candidates(self, name: str) -> list[str]:
        """Qualified names that `name`, written in this file, may refer to."""
        result = []
        if self.package:
            result.append(f"{self.package}::{name}")
        result.append(name)
        for imp in self.wildcard_imports:
            result.append(f"{imp}::{name}")
        head, _, rest = name.partition("::")
        for imp in self.exact_imports:
            if imp.rsplit("::", 1)[-1] == head:
                result.append(imp + (f"::{rest}" if rest else ""))
        return result


class GlobalTable:
    """Every top-level declaration of the project, by qualified name."""

    def __init__(self) -> None:
        self.declarations: dict[str, Declaration] = {}

    def add(self, decl: Declaration) -> Declaration | None:
        """Add a declaration; returns the earlier one of the same name, if any."""
        existing = self.declarations.get(decl.qname)
        if existing is None:
            self.declarations[decl.qname] = decl
        return existing

    def lookup(self, scope: FileScope, name: str, kinds: tuple[str, ...]) -> Declaration | None:
        for candidate in scope.candidates(name):
            decl = self.declarations.get(candidate)
            if decl is not None and decl.kind in kinds:
                return decl
        return None

    def names(self, kinds: tuple[str, ...]) -> list[str]:
        return [q for q, d in self.declarations.items() if d.kind in kinds]


def qname_text(tree: Tree | Token) -> str:
    """The text of a `qname` tree (`a::b::c`) or of a single name token."""
    if isinstance(tree, Token):
        return str(tree)
    return "::".join(str(t) for t in tree.children)
