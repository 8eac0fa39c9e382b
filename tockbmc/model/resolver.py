"""Turn parsed files into the resolved, checked `Project`.

Declarations are entered into a global table first, then resolved on demand
(memoised), so that the order of files and declarations does not matter.
Every problem is collected as a `Diagnostic`; nothing here raises for bad
input.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Iterable
from fractions import Fraction
from pathlib import Path
from typing import Any, TypeVar

from lark import Token, Tree

from tockbmc.model import ast, recursion
from tockbmc.model.ast import BOOLEAN, ERROR, INT, NAT, REAL, STRING, Pos
from tockbmc.model.diagnostics import Diagnostic, suggestion
from tockbmc.model.expressions import PER_ASSERTION, TRIGGER_PREDICATES, ExprChecker, Scope, conform, pos_of
from tockbmc.model.limits import MAX_DECLARATION_CHAIN
from tockbmc.model.numbers import real_text
from tockbmc.model.rules import LIMIT, LINKING, UNIQUE
from tockbmc.model.scope import Declaration, FileScope, GlobalTable, qname_text

T = TypeVar("T")

BUILTIN_TYPES = {"int": INT, "nat": NAT, "real": REAL, "boolean": BOOLEAN, "string": STRING}

UNSUPPORTED_TYPES = {
    "any_type": "generic types ('?T')",
}

UNSUPPORTED_DECLARATIONS = {
    "general_controller": "general controllers ('generalcontroller')",
    "general_operation": "general operations ('generaloperation')",
    "ann_controller": "controllers given by a neural network ('anncontroller')",
    "ann_operation": "operations given by a neural network ('annoperation')",
}

# Assertions.xtext's properties for PRISM, parsed so that each is reported where it is written (a
# warning: the item is not checked, the rest of its file is).
UNSUPPORTED_PROBABILISTIC = {
    "prob_assertion": "probabilistic properties ('prob')",
    "prob_constant": "constants of probabilistic properties ('const')",
    "prob_constants": "constant settings of probabilistic properties ('constants')",
    "prob_label": "labels of probabilistic properties ('label')",
    "prob_formula": "formulas of probabilistic properties ('formula')",
    "prob_rewards": "reward structures of probabilistic properties ('rewards')",
    "prob_definitions": "definitions of probabilistic properties ('defs')",
    "prob_modules": "modules of probabilistic properties ('pmodules')",
}

TOOLKITS = {"relation_toolkit", "sequence_toolkit", "set_toolkit", "function_toolkit", "collection_toolkit",
            "arith_toolkit", "number_toolkit", "core"}

_CSP_CHANNELS = re.compile(r"^[ \t]*channel[ \t]+([A-Za-z_][A-Za-z0-9_']*(?:[ \t]*,[ \t]*[A-Za-z_][A-Za-z0-9_']*)*)[ \t]*$",
                           re.M)  # `channel a, b` without a type: the specification's own events
_CSP_DEFINITION = re.compile(r"(?:^|\{)[ \t]*(?:nametype[ \t]+)?([A-Za-z_][A-Za-z0-9_']*)[ \t]*(\([^)\n]*\))?[ \t]*=(?!=)",
                             re.M)


def children(tree: Tree, data: str) -> list[Tree]:
    return [c for c in tree.children if isinstance(c, Tree) and c.data == data]


def name_of(tree: Tree) -> Token:
    """The first token child of a declaration tree: its name."""
    for c in tree.children:
        if isinstance(c, Token) and c.type == "ID":
            return c
    raise ValueError(f"{tree.data} has no name")


class Resolver:
    """Resolves all the parsed files of one project."""

    def __init__(self, files: list[tuple[str, str, Tree]]):
        self.files = files  # (path, kind, tree)
        self.table = GlobalTable()
        self.diagnostics: list[Diagnostic] = []
        self._memo: dict[tuple[str, str], object] = {}
        self._in_progress: set[tuple[str, str]] = set()
        self._kept: list[tuple[Pos, str]] = []  # constructs kept without a meaning (`refuse_dropped`)

    # ----------------------------------------------------------------- reporting

    def report(self, pos: Pos, message: str, severity: str = "error", rule: str = "") -> None:
        self.diagnostics.append(Diagnostic(pos, message, severity, rule))

    def error(self, path: str, node: Tree | Token, message: str, rule: str = "") -> None:
        """An error at `node`, citing the RoboTool rule (`model.rules`) it enforces."""
        self.report(pos_of(path, node), message, rule=rule)

    def memo(self, kind: str, qname: str, build: Callable[[], T], path: str, node: Tree | Token) -> T | None:
        key = (kind, qname)
        if key in self._memo:
            return self._memo[key]  # type: ignore[return-value]
        if key in self._in_progress:
            # RoboTool has no rule against a record or enumeration of itself; tockbmc's values are finite
            self.error(path, node, f"unsupported: '{qname}' is defined in terms of itself")
            return None
        if len(self._in_progress) >= MAX_DECLARATION_CHAIN:  # each one waits for the next: a chain
            self.error(path, node, f"'{qname}' is defined through a chain of more than {MAX_DECLARATION_CHAIN} "
                                   "declarations (a record inside a record…, a function calling a function…)", rule=LIMIT)
            return None
        self._in_progress.add(key)
        try:
            value = build()
        finally:
            self._in_progress.discard(key)
        self._memo[key] = value
        return value

    # ----------------------------------------------------------------- phase 1: declare

    def declare(self) -> None:
        for path, kind, tree in self.files:
            scope = FileScope(path, None)
            for item in tree.children:
                if item.data == "package_decl":
                    scope.package = qname_text(item.children[0])
                elif item.data == "import_decl":
                    target = qname_text(item.children[0])
                    if len(item.children) > 1:
                        scope.wildcard_imports.append(target)
                    else:
                        scope.exact_imports.append(target)
            self._scopes[path] = scope
            if kind != "rct":
                continue
            for item in tree.children:
                if item.data in ("package_decl", "import_decl", "diagram"):
                    continue
                token = name_of(item)
                decl = Declaration(item.data, scope.qualify(str(token)), item, scope)
                earlier = self.table.add(decl)
                if earlier is not None:
                    e_pos = pos_of(earlier.file.path, name_of(earlier.tree))
                    self.error(path, token, f"'{decl.qname}' is already declared at {e_pos}", rule=UNIQUE)
        # Packages must exist for imports to make sense.
        # RoboTool ignores an import it cannot resolve; say so, but load.
        packages = {s.package for s in self._scopes.values() if s.package}
        for path, _, tree in self.files:
            for item in children(tree, "import_decl"):
                target = qname_text(item.children[0])
                if target.split("::")[0] in TOOLKITS:
                    # Their functions are built in (`expressions.TOOLKIT_FUNCTIONS`); others are
                    # reported where they are called.
                    self._scopes[path].toolkit = True
                elif len(item.children) > 1 and not any(p == target or p.startswith(target + "::") for p in packages):
                    self.report(pos_of(path, item.children[0]),
                                f"import of unknown package '{target}' is ignored{suggestion(target, packages)}",
                                "warning")

    _scopes: dict[str, FileScope]

    # ----------------------------------------------------------------- types

    def type_of(self, scope: FileScope, node: Tree, bindings: dict[str, ast.Type] | None = None) -> ast.Type:
        """The type a type expression denotes; in a function's signature and body (`bindings` not
        None) `?X` is the generic type X, or the type an instance binds it to."""
        if node.data == "any_type" and bindings is not None:
            var = str(node.children[0])
            return bindings.get(var, ast.TypeVar(var))
        if node.data in UNSUPPORTED_TYPES:
            self.error(scope.path, node, f"unsupported: {UNSUPPORTED_TYPES[node.data]}")
            return ERROR
        if node.data in ("seq_type", "set_type"):
            element = self.type_of(scope, node.children[0], bindings)
            if isinstance(element, ast.ErrorType):
                return ERROR
            return ast.SeqType(element) if node.data == "seq_type" else ast.SetType(element)
        if node.data in ("function_type", "relation_type"):
            domain, range_ = (self.type_of(scope, c, bindings) for c in node.children)
            if isinstance(domain, ast.ErrorType) or isinstance(range_, ast.ErrorType):
                return ERROR
            if node.data == "function_type":
                return ast.FunctionType(domain, range_)
            # `X <-> Y` is Z's relation type, the sets of pairs P(X × Y), as in RoboChart's toolkits
            # (relation_toolkit's `dom(r : ?X <-> ?Y)` reads `p in r` for `p : ?X*?Y`).
            return ast.SetType(ast.ProductType((domain, range_)))
        if node.data in ("vector_type", "matrix_type"):
            return self._vector_type(scope, node, bindings)
        if node.data == "product_type":
            parts = [self.type_of(scope, c, bindings) for c in node.children]
            if any(isinstance(p, ast.ErrorType) for p in parts):
                return ERROR
            return ast.ProductType(tuple(parts))
        if node.data != "named_type":  # parenthesised types are inlined by the grammar
            self.error(scope.path, node, f"unsupported: type '{node.data}'")
            return ERROR
        name = qname_text(node.children[0])
        if name in BUILTIN_TYPES:
            return BUILTIN_TYPES[name]
        decl = self.table.lookup(scope, name, ("primitive_type", "record_type", "enumeration"))
        if decl is None:
            known = list(BUILTIN_TYPES) + self.table.names(("primitive_type", "record_type", "enumeration"))
            self.error(scope.path, node, f"unknown type '{name}'{suggestion(name, known)}", rule=LINKING)
            return ERROR
        return self.type_decl(decl) or ERROR

    def _vector_type(self, scope: FileScope, node: Tree, bindings: dict[str, ast.Type] | None) -> ast.Type:
        """`vector(T, n)` as the tuple type of `n` parts `T`, `matrix(T, m, n)` as `m` rows of
        `vector(T, n)`: RoboTool's CSP writes a vector's value as a tuple (`(1, 1)`, the suite's
        test-vector-matrix), and tuples are built in both engines. The sizes must be literals."""
        element = self.type_of(scope, node.children[0], bindings)
        sizes = []
        for atom in node.children[1:]:
            text = str(atom.children[0]) if isinstance(atom, Tree) and atom.data == "int_lit" else ""
            if not text.isdigit() or not 1 <= int(text[:3]) <= 64 or len(text) > 2:
                self.error(scope.path, atom, "unsupported: a vector's or matrix's size that is not a number "
                                             "literal from 1 to 64")
                return ERROR
            sizes.append(int(text))
        if isinstance(element, ast.ErrorType):
            return ERROR
        t = element
        for n in reversed(sizes):
            t = ast.ProductType((t,) * n)
        return t

    def type_decl(self, decl: Declaration) -> ast.Type | None:
        def build() -> ast.Type:
            tree, scope = decl.tree, decl.file
            if decl.kind == "primitive_type":
                return ast.GivenType(decl.qname)
            if decl.kind == "enumeration":
                literals: list[str] = []
                params: list[tuple[ast.Type, ...]] = []
                parameterised = None
                for lit in tree.children[1:]:
                    token = lit.children[0]
                    if len(lit.children) > 1 and parameterised is None:
                        parameterised = pos_of(scope.path, lit)
                    if str(token) in literals:
                        self.error(scope.path, token, f"duplicate literal '{token}'", rule=UNIQUE)
                        continue
                    literals.append(str(token))
                    params.append(tuple(self.type_of(scope, c) for c in lit.children[1:]))
                return ast.EnumType(decl.qname, tuple(literals), parameterised,
                                    tuple(params) if parameterised is not None else ())
            fields = []
            seen = set()
            for f in tree.children[1:]:
                fname = str(f.children[0])
                if fname in seen:
                    self.error(scope.path, f.children[0], f"duplicate field '{fname}'", rule=UNIQUE)
                seen.add(fname)
                fields.append(ast.RecordField(fname, self.type_of(scope, f.children[1])))
            return ast.RecordType(decl.qname, tuple(fields))

        return self.memo("type", decl.qname, build, decl.file.path, name_of(decl.tree))

    # ----------------------------------------------------------------- global lookups for expressions

    def global_resolver(self, scope: FileScope) -> Callable[[str, str], object | None]:
        def resolve(name: str, kind: str) -> object | None:
            if kind == "type":
                decl = self.table.lookup(scope, name, ("primitive_type", "record_type", "enumeration"))
                return self.type_decl(decl) if decl else None
            if kind == "function":
                decl = self.table.lookup(scope, name, ("function_def",))
                if decl is None:
                    return None
                return self.function(decl) or ERROR  # declared, but could not be resolved: reported there
            if kind == "operation":
                decl = self.table.lookup(scope, name, ("operation_def",))
                return self.operation(decl) if decl else None
            if kind == "interface":
                decl = self.table.lookup(scope, name, ("interface",))
                return self.interface(decl) if decl else None
            if kind == "enum_literal":
                found = [t for t in self._visible_enums(scope) if name in t.literals]
                return found[0] if len(found) == 1 else None
            return None

        return resolve

    def _visible_enums(self, scope: FileScope) -> list[ast.EnumType]:
        enums = []
        for q, d in self.table.declarations.items():
            if d.kind == "enumeration" and self.table.lookup(scope, q.rsplit("::", 1)[-1], ("enumeration",)) is d:
                t = self.type_decl(d)
                if isinstance(t, ast.EnumType):
                    enums.append(t)
        return enums

    def global_names(self, kind: str) -> list[str]:
        if kind == "function":
            return self.table.names(("function_def",))
        if kind == "operation":
            return self.table.names(("operation_def",))
        if kind == "record":
            return self.table.names(("record_type",))
        if kind == "enum_literal":
            names = []
            for q in self.table.names(("enumeration",)):
                t = self.type_decl(self.table.declarations[q])
                if isinstance(t, ast.EnumType):
                    names += [f"{t.name}::{lit}" for lit in t.literals]
                    names += [f"{t.qname}::{lit}" for lit in t.literals]
            return names
        return []

    def checker(self, scope: FileScope, expr_scope: Scope, bindings: dict[str, ast.Type] | None = None) -> ExprChecker:
        expr_scope.resolve_global = self.global_resolver(scope)
        expr_scope.global_names = self.global_names
        expr_scope.toolkit = scope.toolkit
        expr_scope.instantiate = self.instance
        return ExprChecker(expr_scope, self.report, lambda node: self.type_of(scope, node, bindings), self._kept)

    # ----------------------------------------------------------------- variables, events, operations

    def variables(self, scope: FileScope, var_lists: list[Tree], owner: str, checker: ExprChecker | None,
                  kind: str = "local") -> list[ast.Variable]:
        """The variables and constants `var_lists` declare, each entered into the checker's scope
        once its initial value is checked: in their order, except that a constant comes after those
        its value names.  RoboTool's scoping puts every variable
        of an element in scope in each initial value (RoboChartScopeProvider.variablesDeclared), so a
        constant's value may name a constant declared after it: constants are checked after those
        they name, whatever their order.  A value that names a variable declared after it, or
        constants whose values name each other, have no value tockbmc can give: unsupported."""
        checker = checker or self.checker(scope, Scope(scope.path, owner))
        decls = [(str(vl.children[0]) == "const", v) for vl in var_lists for v in vl.children[1:]]
        index = {str(v.children[0]): i for i, (_, v) in enumerate(decls)}
        first: dict[int, int] = {}  # a later variable each value names: unsupported
        needs: list[set[int]] = []
        for i, (_, v) in enumerate(decls):
            named = {qname_text(n.children[0]) for n in v.children[2].iter_subtrees() if n.data == "name_expr"} \
                if len(v.children) > 2 else set()
            wanted = {index[n] for n in named if n in index and index[n] != i}
            later = sorted(j for j in wanted if j > i and not decls[j][0])
            if later:
                first[i] = later[0]
            needs.append({j for j in wanted if decls[j][0] or j < i})
        order: list[int] = []
        while len(order) < len(decls):
            done = set(order)
            ready = [i for i in range(len(decls)) if i not in done and needs[i] <= done]
            if not ready:  # constants whose values name each other
                cycle = [i for i in range(len(decls)) if i not in done]
                names = ", ".join(f"'{decls[i][1].children[0]}'" for i in cycle)
                for i in cycle:
                    self.error(scope.path, decls[i][1].children[0],
                               f"unsupported: constants whose values name each other ({names})")
                    first[i] = i
                ready = cycle
            order.append(ready[0])
        result: dict[int, ast.Variable] = {}
        for i in order:
            constant, v = decls[i]
            name = v.children[0]
            vtype = self.type_of(scope, v.children[1])
            initial = None
            if i in first and first[i] != i:
                self.error(scope.path, v.children[2], f"unsupported: the initial value of '{name}' reads "
                                                      f"'{decls[first[i]][1].children[0]}', a variable declared after it")
            elif len(v.children) > 2 and i not in first:
                initial = checker.expr(v.children[2])
                initial = checker.expect(v.children[2], initial, vtype, f"the initial value of '{name}'",
                                         rule="VarInitType")
            result[i] = ast.Variable(str(name), vtype, constant, owner, pos_of(scope.path, name), initial, kind)
            checker.scope.variables[str(name)] = result[i]
        # in the order they are checked in: each after those it names, so that every engine can give
        # them their values in turn
        return [result[i] for i in order]

    def event(self, scope: FileScope, tree: Tree, owner: str) -> ast.Event:
        broadcast = any(isinstance(c, Token) and c.type == "BROADCAST" for c in tree.children)
        toks = [c for c in tree.children if isinstance(c, Token) and c.type == "ID"]
        types = [c for c in tree.children if isinstance(c, Tree)]
        etype = self.type_of(scope, types[0]) if types else None
        if broadcast:
            self.error(scope.path, tree, "unsupported: broadcast events ('_broadcast')")
        return ast.Event(str(toks[0]), etype, owner, pos_of(scope.path, toks[0]), broadcast)

    def parameters(self, scope: FileScope, tree: Tree | None, owner: str,
                   bindings: dict[str, ast.Type] | None = None) -> tuple[ast.Variable, ...]:
        if tree is None:
            return ()
        return tuple(ast.Variable(str(p.children[0]), self.type_of(scope, p.children[1], bindings), True, owner,
                                  pos_of(scope.path, p.children[0]), None, "parameter")
                     for p in tree.children)

    def op_sig(self, scope: FileScope, tree: Tree, owner: str) -> ast.OperationSig:
        name = tree.children[0]
        params = next((c for c in tree.children if isinstance(c, Tree) and c.data == "params"), None)
        terminates = any(isinstance(c, Token) and c.type == "TERMINATES" for c in tree.children)
        return ast.OperationSig(str(name), self.parameters(scope, params, f"{owner}::{name}"), owner,
                                pos_of(scope.path, name), terminates)

    # ----------------------------------------------------------------- interfaces

    def interface_ref(self, scope: FileScope, node: Tree) -> ast.Interface | None:
        name = qname_text(node)
        decl = self.table.lookup(scope, name, ("interface",))
        if decl is None:
            self.error(scope.path, node, f"unknown interface '{name}'{suggestion(name, self.table.names(('interface',)))}", rule=LINKING)
            return None
        return self.interface(decl)

    def interface(self, decl: Declaration) -> ast.Interface | None:
        def build() -> ast.Interface:
            scope, tree = decl.file, decl.tree
            events, variables, operations, clocks = [], [], [], []
            expr_scope = Scope(scope.path, decl.qname)
            checker = self.checker(scope, expr_scope)
            for item in tree.children[1:]:
                if item.data == "event":
                    events.append(self.event(scope, item, decl.qname))
                elif item.data == "op_sig":
                    operations.append(self.op_sig(scope, item, decl.qname))
                elif item.data == "clock":
                    clocks.append(ast.Clock(str(item.children[0]), decl.qname, pos_of(scope.path, item.children[0])))
            variables = self.variables(scope, children(tree, "var_list"), decl.qname, checker, "interface")
            self._no_duplicates(scope.path, [*events, *variables, *operations, *clocks], "interface " + decl.qname)
            return ast.Interface(decl.qname, tuple(events), tuple(variables), tuple(operations), tuple(clocks),
                                 pos_of(scope.path, name_of(tree)))

        return self.memo("interface", decl.qname, build, decl.file.path, name_of(decl.tree))

    def _no_duplicates(self, path: str, items: Iterable, where: str) -> None:
        seen: dict[str, ast.Pos] = {}
        for item in items:
            if item.name in seen:
                self.report(item.pos, f"'{item.name}' is declared twice in {where} (first at {seen[item.name]})", rule=UNIQUE)
            else:
                seen[item.name] = item.pos

    # ----------------------------------------------------------------- functions

    def function(self, decl: Declaration) -> ast.Function | None:
        return self.memo("function", decl.qname, lambda: self._generic_or_not(decl), decl.file.path, name_of(decl.tree))

    def _generic_or_not(self, decl: Declaration, bindings: dict[str, ast.Type] | None = None,
                        suffix: str = "") -> ast.Function:
        """A function's declaration, checked.  A generic one (`f(x : ?X)`) is checked for its types
        where it is called (`instance`); its own text, with `?X` unbound, may not check (RoboTool's
        own function_toolkit has `{x : ?X | maplet(x, x)}`, which RoboTool accepts), so errors
        inside it are left to its instances: a generic function nobody calls decides nothing."""
        bindings = bindings or {}
        variables = {str(n.children[0]) for n in decl.tree.find_data("any_type")}
        unbound = bool(variables) and (not variables <= bindings.keys()
                                       or any("?" in str(t) for t in bindings.values()))  # inside a generic one
        if not unbound:
            return self._function(decl, bindings, suffix)
        mark = len(self.diagnostics)
        f = self._function(decl, bindings, suffix)
        meta = decl.tree.meta
        inside = [d for d in self.diagnostics[mark:] if d.pos.path == decl.file.path and not meta.empty
                  and meta.line <= d.pos.line <= meta.end_line]
        self.diagnostics[mark:] = [d for d in self.diagnostics[mark:] if d not in inside]
        return f

    def instance(self, f: ast.Function, bindings: dict[str, ast.Type]) -> ast.Function | None:
        """The instance of generic function `f` with its types `?X` bound: its signature and
        conditions checked again with them (once per binding)."""
        decl = self.table.declarations[f.qname]
        suffix = "[" + ", ".join(f"?{k}={bindings[k]}" for k in sorted(bindings)) + "]"
        return self.memo("function", f.qname + suffix, lambda: self._generic_or_not(decl, bindings, suffix),
                         decl.file.path, name_of(decl.tree))

    def _function(self, decl: Declaration, bindings: dict[str, ast.Type], suffix: str = "") -> ast.Function:
        scope, tree = decl.file, decl.tree
        qname = decl.qname + suffix
        params_tree = next((c for c in tree.children if isinstance(c, Tree) and c.data == "params"), None)
        params = self.parameters(scope, params_tree, qname, bindings)
        type_tree = next(c for c in tree.children if isinstance(c, Tree) and c.data not in ("params", "precondition", "postcondition"))
        result = self.type_of(scope, type_tree, bindings)
        expr_scope = Scope(scope.path, qname, variables={p.name: p for p in params}, result_type=result)
        checker = self.checker(scope, expr_scope, bindings)
        mark = len(self.diagnostics)
        # A call of the function inside its own conditions is a call of its signature, open, until
        # the definition it gives is unfolded into itself (`model.recursion`).
        own = ast.Function(qname, params, result, (), (), None, pos_of(scope.path, name_of(tree)))
        self._memo[("function", qname)] = own
        try:
            pre = tuple(checker.condition(c.children[0]) for c in children(tree, "precondition"))
            post = tuple(checker.condition(c.children[0]) for c in children(tree, "postcondition"))
        finally:
            del self._memo[("function", qname)]
        # RoboTool does not check types in a function's conditions (turtlebot's `result == v < c`
        # is `(result == v) < c`): their errors make the function's calls unsupported, not the model.
        errors = [d for d in self.diagnostics[mark:] if d.severity == "error" and d.pos.path == scope.path
                  and "type error" in d.message]
        self.diagnostics[mark:] = [d for d in self.diagnostics[mark:] if d not in errors]
        unchecked = (f"function {qname.rsplit('::', 1)[-1]}'s conditions do not type-check, which RoboTool "
                     f"does not check there: {errors[0].message} ({errors[0].pos})") if errors else ""
        definition = defining = None
        for cond in post:
            if isinstance(cond, ast.Binary) and cond.op == "==":
                if isinstance(cond.left, ast.ResultRef):
                    definition, defining = cond.right, cond
                elif isinstance(cond.right, ast.ResultRef):
                    definition, defining = cond.left, cond
        f = ast.Function(qname, params, result, pre, post, None if unchecked else definition,
                         pos_of(scope.path, name_of(tree)), unchecked)
        if not recursion.calls((pre, post), own):
            return f
        others = tuple(c for c in post if c is not defining)
        if f.definition is None or recursion.calls((pre, others), own):
            # RoboTool has no rule against it; tockbmc unfolds only a `result == e` definition
            return dataclasses.replace(f, definition=None, postconditions=(), unchecked=f.unchecked or (
                f"function {f.name} is defined in terms of itself other than by a postcondition result == e "
                f"({f.pos})"))
        return recursion.unfolded(dataclasses.replace(f, postconditions=others), own)

    # ----------------------------------------------------------------- machines and operations

    def machine(self, decl: Declaration) -> ast.StateMachine | None:
        return self.memo("machine", decl.qname,
                         lambda: self.behaviour(decl.file, decl.tree, decl.qname, ast.StateMachine),  # type: ignore[arg-type, return-value]
                         decl.file.path, name_of(decl.tree))

    def operation(self, decl: Declaration) -> ast.OperationDef | None:
        return self.memo("operation", decl.qname,
                         lambda: self.behaviour(decl.file, decl.tree, decl.qname, ast.OperationDef),  # type: ignore[arg-type, return-value]
                         decl.file.path, name_of(decl.tree))

    def behaviour(self, scope: FileScope, tree: Tree, qname: str, cls: type) -> ast.Behaviour:
        """A state machine or defined operation: declarations, nodes, transitions."""
        path = scope.path
        iface_vars: list[ast.Variable] = []
        events: list[ast.Event] = []
        clocks: list[ast.Clock] = []
        operations: list[ast.OperationSig] = []
        relations: dict[str, list[str]] = {"uses": [], "provides": [], "requires": []}
        params: tuple[ast.Variable, ...] = ()
        terminates = False
        for item in tree.children:
            if not isinstance(item, Tree):
                continue
            if item.data in relations:
                iface = self.interface_ref(scope, item.children[0])
                if iface is None:
                    continue
                relations[item.data].append(iface.qname)
                events += iface.events
                iface_vars += iface.variables
                operations += iface.operations
                clocks += iface.clocks
            elif item.data == "event":
                events.append(self.event(scope, item, qname))
            elif item.data == "clock":
                clocks.append(ast.Clock(str(item.children[0]), qname, pos_of(path, item.children[0])))
            elif item.data == "params":
                params = self.parameters(scope, item, qname)
            elif item.data == "terminates":
                terminates = True
        expr_scope = Scope(path, qname)
        expr_scope.variables.update({v.name: v for v in iface_vars})
        expr_scope.variables.update({p.name: p for p in params})
        checker = self.checker(scope, expr_scope)
        variables = self.variables(scope, children(tree, "var_list"), qname, checker)
        self._no_duplicates(path, [*variables, *params], qname)
        self._no_duplicates(path, events, qname)
        self._no_duplicates(path, clocks, qname)
        self._no_duplicates(path, operations, qname)
        # RoboTool refuses one name twice by Xtext's NamesAreUniqueValidator (the composedCheck of
        # robochart-textual's GenerateRoboChart.mwe2): named elements of one file clash where their
        # qualified names meet, so an event and a variable clash only when both are declared in the
        # machine itself (`M::x` twice). One that comes in through an interface is the interface's
        # (`I::x`) and meets nothing of the machine's; the two stay apart, as events and variables
        # are apart in expressions (`ExprChecker`).
        own = {v.name for v in (*variables, *params)}
        for e in events:
            if e.owner == qname and e.name in own:
                self.report(e.pos, f"'{e.name}' names both an event and a variable of {qname}", rule=UNIQUE)
        expr_scope.events = {e.name: e for e in events}
        expr_scope.clocks = {c.name: c for c in clocks}
        expr_scope.operations = {o.name: o for o in operations}
        expr_scope.interfaces = {q for qs in relations.values() for q in qs}

        nodes: list[ast.Node] = []
        raw_nodes: list[tuple[Tree, str | None]] = []
        self._collect_nodes(path, tree, None, nodes, raw_nodes)
        by_path = {n.path: n for n in nodes}
        for n in nodes:
            expr_scope.states.setdefault(n.name, n.path)
            expr_scope.states[n.path] = n.path
        # Actions, now that every name is in scope.
        final_nodes = []
        for node, (ntree, _) in zip(nodes, raw_nodes):
            actions = {}
            for kind in ("entry", "during", "exit"):
                for a in children(ntree, kind):
                    if kind in actions:
                        self.error(path, a, f"state '{node.name}' has more than one {kind} action", rule="S2")
                    actions[kind] = checker.statement(a.children[0])
            final_nodes.append(dataclasses.replace(node, entry=actions.get("entry"), during=actions.get("during"),
                                                   exit=actions.get("exit")))
        nodes = final_nodes
        by_path = {n.path: n for n in nodes}
        transitions = []
        probabilities: dict[str, list[Fraction | None]] = {}  # probabilistic junction -> its transitions' literals
        for ttree, container in self._collect_transitions(tree, None):
            built = self.transition(scope, ttree, container, by_path, checker)
            if built is not None:
                t, probability = built
                transitions.append(t)
                if by_path[t.source].probabilistic:
                    probabilities.setdefault(t.source, []).append(probability)
        self._check_structure(path, qname, tree, nodes, transitions)
        self._check_probabilities(nodes, probabilities)
        fields: dict[str, Any] = dict(qname=qname, pos=pos_of(path, name_of(tree)), variables=tuple(variables),
                      interface_variables=tuple(iface_vars), events=tuple(events), clocks=tuple(clocks),
                      operations=tuple(operations), nodes=tuple(nodes), transitions=tuple(transitions),
                      required_interfaces=tuple(relations["requires"]),
                      provided_interfaces=tuple(relations["provides"]),
                      used_interfaces=tuple(relations["uses"]))
        if cls is ast.OperationDef:
            return ast.OperationDef(**fields, parameters=params, terminates=terminates)
        return ast.StateMachine(**fields)

    def _collect_nodes(self, path: str, tree: Tree, parent: str | None, out: list[ast.Node],
                       raw: list[tuple[Tree, str | None]]) -> list[str]:
        names = []
        for item in tree.children:
            if not isinstance(item, Tree) or item.data not in ("state", "initial", "junction", "final", "probabilistic"):
                continue
            token = item.children[0]
            npath = f"{parent}::{token}" if parent else str(token)
            if str(token) in names:
                self.error(path, token, f"'{token}' is declared twice in the same region", rule=UNIQUE)
                continue
            names.append(str(token))
            index = len(out)
            # a probabilistic junction is a junction whose choice is nondeterministic (`model.probabilistic`)
            probabilistic = item.data == "probabilistic"
            out.append(ast.Node("junction" if probabilistic else item.data, str(token), npath, parent,
                                pos_of(path, token), probabilistic=probabilistic))
            raw.append((item, parent))
            if item.data == "state":
                kids = self._collect_nodes(path, item, npath, out, raw)
                out[index] = dataclasses.replace(out[index], children=tuple(f"{npath}::{k}" for k in kids))
        return names

    def _collect_transitions(self, tree: Tree, container: str | None) -> list[tuple[Tree, str | None]]:
        result = []
        for item in tree.children:
            if not isinstance(item, Tree):
                continue
            if item.data == "transition":
                result.append((item, container))
            elif item.data == "state":
                name = str(item.children[0])
                result += self._collect_transitions(item, f"{container}::{name}" if container else name)
        return result

    def _node_ref(self, path: str, node: Tree, container: str | None, by_path: dict[str, ast.Node]) -> str | None:
        """The node a transition names: a node of the region that declares it, or nested in it."""
        name = qname_text(node)
        prefix = f"{container}::" if container else ""
        if prefix + name in by_path:
            return prefix + name
        matches = [p for p in by_path if p.startswith(prefix) and (p == name or p.endswith("::" + name))]
        if len(matches) == 1:
            return matches[0]
        if len(matches) > 1:
            self.error(path, node, f"'{name}' is ambiguous here: it may be {', '.join(sorted(matches))}", rule=LINKING)
            return None
        outside = [p for p in by_path if p == name or p.endswith("::" + name)]
        if outside:
            self.error(path, node, f"a transition declared in state '{container}' must stay inside it, "
                       f"but '{name}' is outside", rule=LINKING)
            return None
        known = [p.rsplit("::", 1)[-1] for p in by_path]
        self.error(path, node, f"unknown state or junction '{name}'{suggestion(name, known)}", rule=LINKING)
        return None

    def transition(self, scope: FileScope, tree: Tree, container: str | None, by_path: dict[str, ast.Node],
                   checker: ExprChecker) -> tuple[ast.Transition, Fraction | None] | None:
        """The transition `tree` declares, and its probability where that is a number literal (the
        probability is checked, then dropped: `model.probabilistic`)."""
        path = scope.path
        name = tree.children[0]
        source = self._node_ref(path, tree.children[1], container, by_path)
        target = self._node_ref(path, tree.children[2], container, by_path)
        trigger = None
        resets: list[ast.Clock] = []
        deadline = condition = action = None
        is_else = False
        probability: Tree | None = None
        literal: Fraction | None = None
        guard: Tree | None = None  # `condition …`, for the error of one leaving a probabilistic junction
        predicate: ast.Expr | None = None
        for item in tree.children[3:]:
            if item.data.startswith("comm_"):
                event, kind, var, value = checker.communication(item)
                if kind == "predicate":
                    # kept in place of the condition, so that the assertions that reach it are unsupported
                    predicate = ast.UnsupportedExpr(BOOLEAN, pos_of(path, item), TRIGGER_PREDICATES)
                elif event is not None:
                    trigger = ast.Trigger(event, kind, var, value)
            elif item.data == "empty_trigger":
                self.report(pos_of(path, item.children[0]), "'trigger' with no event after it (an older RoboChart "
                            "form) is read as no trigger; today's RoboTool requires an event here", "warning")
            elif item.data == "probability":
                probability = item
                literal = self._probability(path, item.children[0], checker)
            elif item.data == "clock_reset":
                clock = checker.clock(item.children[0])
                if clock is not None:
                    resets.append(clock)
            elif item.data == "deadline":
                deadline = checker.deadline(item.children[0])
            elif item.data == "condition":
                condition = checker.condition(item.children[0], rule="TransitionConditionTypeError")
                guard = item
            elif item.data == "else_condition":
                is_else = True
                guard = item
            elif item.data == "action":
                action = checker.statement(item.children[0])
        if source is None or target is None:
            return None
        condition = predicate or condition
        src, tgt = by_path[source], by_path[target]
        if src.kind == "final":
            self.error(path, tree.children[1], f"a transition cannot leave final state '{src.name}'", rule="FS1")
        if tgt.kind == "initial":
            self.error(path, tree.children[2], f"a transition cannot enter initial junction '{tgt.name}'", rule="IJ1")
        if src.kind == "initial" and (trigger is not None or predicate is not None):
            self.error(path, tree, f"the transition from initial junction '{src.name}' cannot have a trigger", rule="J3")
        # RoboTool's rules PJ1, PJ2 and PT1 (RoboChartValidator.transitionWFC), errors there too
        if src.probabilistic and probability is None:
            self.error(path, name, f"transition '{name}' leaves probabilistic junction '{src.name}', so it must "
                                   "have a probability", rule="PJ1")
        if src.probabilistic and guard is not None:
            self.error(path, guard, f"transition '{name}' leaves probabilistic junction '{src.name}', so it cannot "
                                    "have a condition", rule="PJ2")
        if probability is not None and not src.probabilistic:
            self.error(path, probability, f"only a transition from a probabilistic junction has a probability, "
                                          f"and '{name}' leaves '{src.name}'", rule="PT1")
        return (ast.Transition(str(name), source, target, pos_of(path, name), container, trigger, tuple(resets),
                               deadline, condition, is_else, action), literal)

    def _probability(self, path: str, tree: Tree, checker: ExprChecker) -> Fraction | None:
        """Check a transition's `probability e`: a real expression, and, where `e` is a number
        literal, one from 0 to 1 (RoboTool's rule PT2, an error there for a literal); returns the
        literal's value (None for any other expression: RoboTool only warns that it might lie outside).
        One that is not a number is a warning, as RoboTool warns of it (PT2, "might not be between 0
        to 1") and checks no type there; tockbmc drops probabilities, so no check reads it."""
        e = conform(checker.expr(tree), REAL)
        if not ast.assignable(REAL, e.type) and not isinstance(e.type, ast.ErrorType):
            self.report(pos_of(path, tree), f"a probability should be real, but this is {e.type}", "warning")
            return None
        if tree.data not in ("int_lit", "float_lit") or not isinstance(e, ast.Literal) \
                or isinstance(e.type, ast.ErrorType) or not isinstance(e.value, (int, Fraction)):
            return None
        value = Fraction(e.value)
        if not 0 <= value <= 1:
            self.error(path, tree, f"a probability must be from 0 to 1, but this is {tree.children[0]}", rule="PT2")
        return value

    def _check_probabilities(self, nodes: list[ast.Node], probabilities: dict[str, list[Fraction | None]]) -> None:
        """Warn where the literal probabilities of a probabilistic junction's transitions do not add
        up to 1 (RoboTool's warning PJ3, RoboChartValidator.junctionWFC_PJ3; added exactly here)."""
        for n in nodes:
            if not n.probabilistic:
                continue
            values = probabilities.get(n.path, [])
            if all(v is not None for v in values):
                total = sum((v for v in values if v is not None), Fraction(0))
                if total != 1:
                    self.report(n.pos, f"the probabilities of the transitions from probabilistic junction "
                                       f"'{n.name}' add up to {real_text(total)}, not 1", "warning")

    def _check_structure(self, path: str, qname: str, tree: Tree, nodes: list[ast.Node],
                         transitions: list[ast.Transition]) -> None:
        regions: dict[str | None, list[ast.Node]] = {}
        for n in nodes:
            regions.setdefault(n.parent, []).append(n)
        seen: set[tuple[str | None, str]] = set()
        for t in transitions:
            if (t.container, t.name) in seen:
                where = f"state '{t.container}'" if t.container else qname
                self.report(t.pos, f"transition '{t.name}' is declared twice in {where}", rule=UNIQUE)
            seen.add((t.container, t.name))
        for region, members in regions.items():
            where = f"state '{region}'" if region else qname
            initials = [n for n in members if n.kind == "initial"]
            # RoboTool's STM3 is an error for a state machine's own region only; for a composite
            # state's, or an operation's, it warns (checkStateMachineHasInitialState(NodeContainer))
            # and gives entering it no meaning: each engine reports the assertions that enter it
            # unsupported.
            machine = region is None and tree.data == "stm_def"
            severity = "error" if machine else "warning"
            after = "" if machine else ": entering it is unsupported"
            if not initials:
                pos = next(n.pos for n in nodes if n.path == region) if region else pos_of(path, name_of(tree))
                self.report(pos, f"{where} has no initial junction{after}", severity, "STM3" if machine else "")
            for extra in initials[1:]:
                self.report(extra.pos, f"{where} has more than one initial junction{after}", severity,
                            "STM3" if machine else "")
            for init in initials:
                out = [t for t in transitions if t.source == init.path]
                if len(out) != 1:
                    self.report(init.pos, f"initial junction '{init.name}' must have exactly one transition, "
                                f"but has {len(out)}", rule="IJ2")
                for t in out:
                    if self._parent(t.target) != region:
                        self.report(t.pos, f"the initial transition of {where} must stay in its region", rule="T1")

    @staticmethod
    def _parent(node_path: str) -> str | None:
        return node_path.rpartition("::")[0] or None

    # ----------------------------------------------------------------- controllers

    def controller(self, decl: Declaration) -> ast.Controller | None:
        return self.memo("controller", decl.qname, lambda: self._controller(decl), decl.file.path, name_of(decl.tree))

    def _controller(self, decl: Declaration) -> ast.Controller:
        scope, tree, qname = decl.file, decl.tree, decl.qname
        path = scope.path
        events: list[ast.Event] = []
        machines: list[ast.MachineInstance] = []
        operations: list[ast.OperationInstance] = []
        relations: dict[str, list[str]] = {"uses": [], "provides": [], "requires": []}
        expr_scope = Scope(path, qname)
        checker = self.checker(scope, expr_scope)
        variables = self.variables(scope, children(tree, "var_list"), qname, checker)
        for item in tree.children[1:]:
            if item.data in relations:
                iface = self.interface_ref(scope, item.children[0])
                if iface is not None:
                    relations[item.data].append(iface.qname)
                    # A controller's events are its own and those of the interfaces it uses, requires
                    # or provides, as RoboTool's scoping resolves a connection's event at a controller
                    # (RoboChartScopeProvider.eventsDeclared(ControllerDef)); machines and platforms
                    # take theirs the same way (`behaviour`, `platform`).
                    events += iface.events
            elif item.data == "event":
                events.append(self.event(scope, item, qname))
            elif item.data == "clock":
                self.error(path, item, "unsupported: clocks declared in a controller")
            elif item.data == "stm_def":
                inner = Declaration("stm_def", f"{qname}::{name_of(item)}", item, scope)
                m = self.machine(inner)
                if m is not None:
                    machines.append(ast.MachineInstance(m.name, m, m.pos))
            elif item.data == "stm_ref":
                ref_name, target = item.children
                m_decl = self.table.lookup(scope, qname_text(target), ("stm_def",))
                if m_decl is None:
                    t = qname_text(target)
                    self.error(path, target, f"unknown state machine '{t}'{suggestion(t, self.table.names(('stm_def',)))}", rule=LINKING)
                    continue
                m = self.machine(m_decl)
                if m is not None:
                    machines.append(ast.MachineInstance(str(ref_name), m, pos_of(path, ref_name)))
            elif item.data == "operation_def":
                inner = Declaration("operation_def", f"{qname}::{name_of(item)}", item, scope)
                op = self.operation(inner)
                if op is not None:
                    operations.append(ast.OperationInstance(op.name, op, op.pos))
            elif item.data == "operation_ref":
                ref_name, target = item.children
                o_decl = self.table.lookup(scope, qname_text(target), ("operation_def",))
                if o_decl is None:
                    t = qname_text(target)
                    self.error(path, target, f"unknown operation '{t}'{suggestion(t, self.table.names(('operation_def',)))}", rule=LINKING)
                    continue
                op = self.operation(o_decl)
                if op is not None:
                    operations.append(ast.OperationInstance(str(ref_name), op, pos_of(path, ref_name)))
            elif item.data in UNSUPPORTED_DECLARATIONS:
                self.error(path, item, f"unsupported: {UNSUPPORTED_DECLARATIONS[item.data]}")
        self._no_duplicates(path, events, qname)
        self._no_duplicates(path, machines, qname)
        ends: dict[str, object] = {decl.qname.rsplit("::", 1)[-1]: "self"}
        for inst in machines:
            ends[inst.name] = inst.machine
        own_events = {e.name: e for e in events}
        connections = [c for c in (self.connection(path, item, ends, own_events) for item in children(tree, "connection")) if c]
        self._check_operation_directions(qname, connections, operations)
        return ast.Controller(qname, pos_of(path, name_of(tree)), tuple(events), tuple(variables), tuple(machines),
                              tuple(connections), tuple(operations), tuple(relations["requires"]),
                              tuple(relations["provides"]), tuple(relations["uses"]))

    def _check_operation_directions(self, qname: str, connections: list[ast.Connection],
                                    operations: list[ast.OperationInstance]) -> None:
        """An operation's events are the controller's: it must use them the same way round."""
        me = qname.rsplit("::", 1)[-1]
        # a bidirectional connection (`[ mult ]`) carries the event both ways
        inputs = {c.source_event.name for c in connections if c.source == me} | \
            {c.target_event.name for c in connections if c.target == me and c.bidirectional}
        outputs = {c.target_event.name for c in connections if c.target == me} | \
            {c.source_event.name for c in connections if c.source == me and c.bidirectional}
        for inst in operations:
            sends, receives = ast.event_directions(inst.operation)
            for e in inst.operation.events:
                if e.name in sends and e.name in inputs - outputs:
                    self.report(e.pos, f"operation '{inst.operation.name}' sends '{e.name}', but controller "
                                f"'{me}' only receives it", rule="Cn8")
                elif e.name in receives and e.name in outputs - inputs:
                    self.report(e.pos, f"operation '{inst.operation.name}' receives '{e.name}', but controller "
                                f"'{me}' only sends it", rule="Cn9")

    def connection(self, path: str, tree: Tree, ends: dict[str, object], own_events: dict[str, ast.Event]) -> ast.Connection | None:
        src_node, src_event, tgt_node, tgt_event = tree.children[:4]
        is_async = bool(children(tree, "async_mark"))
        mult = bool(children(tree, "mult_mark"))
        resolved: list[tuple[str, object, ast.Event] | None] = []
        for end_node, event_token, role in ((src_node, src_event, "source"), (tgt_node, tgt_event, "target")):
            end_name = qname_text(end_node)
            element = ends.get(end_name)
            if element is None:
                self.error(path, end_node, f"unknown connection {role} '{end_name}'{suggestion(end_name, list(ends))}", rule=LINKING)
                resolved.append(None)
                continue
            element_events = own_events if element == "self" else {e.name: e for e in _events_of(element)}
            event = element_events.get(str(event_token))
            if event is None:
                self.error(path, event_token, f"'{end_name}' has no event '{event_token}'"
                           f"{suggestion(str(event_token), list(element_events))}", rule=LINKING)
                resolved.append(None)
                continue
            resolved.append((end_name, element, event))
        if None in resolved:
            return None
        (s_name, s_elem, s_ev), (t_name, t_elem, t_ev) = resolved  # type: ignore[misc]
        if s_ev.type != t_ev.type and not (isinstance(s_ev.type, ast.ErrorType) or isinstance(t_ev.type, ast.ErrorType)):
            self.error(path, tree, f"type error: connection joins '{s_name}.{s_ev.name}' "
                       f"({s_ev.type or 'no value'}) to '{t_name}.{t_ev.name}' ({t_ev.type or 'no value'})", rule="RPConnectionIncompatibleType")
        flipped = self._boundary_the_other_way(s_elem, s_ev, t_elem, t_ev) if not mult else None
        if flipped is not None:
            # RoboTool's controller renames a machine's channel to its own whole (`stm_ref0::stop <- stop`,
            # both directions), so a connection between a machine and its controller carries the
            # event the way the machine uses it, whichever end is written first.
            self.report(pos_of(path, tree), f"'{flipped}' is used the other way round by its machine: the "
                        "connection is read in the direction the machine uses it, as RoboTool's controller "
                        "renames the machine's channel in both directions", "warning")
            (s_name, s_elem, s_ev), (t_name, t_elem, t_ev) = (t_name, t_elem, t_ev), (s_name, s_elem, s_ev)
        if isinstance(s_elem, ast.StateMachine) and not mult:
            sends, receives = ast.event_directions(s_elem)
            if s_ev.name in receives and s_ev.name not in sends:
                self.error(path, src_event, f"'{s_name}' only receives '{s_ev.name}', so it cannot be the source "
                           f"of this connection", rule="Cn9")
        if isinstance(t_elem, ast.StateMachine) and not mult:
            sends, receives = ast.event_directions(t_elem)
            if t_ev.name in sends and t_ev.name not in receives:
                self.error(path, tgt_event, f"'{t_name}' only sends '{t_ev.name}', so it cannot be the target "
                           f"of this connection", rule="Cn8")
        return ast.Connection(s_name, s_ev, t_name, t_ev, is_async, mult, pos_of(path, tree))

    @staticmethod
    def _boundary_the_other_way(s_elem: object, s_ev: ast.Event, t_elem: object, t_ev: ast.Event) -> str | None:
        """The event of a connection between a machine and its own controller written against the
        way the machine uses it (the machine only receives what it would send, or only sends what
        it would receive), or None."""
        if isinstance(s_elem, ast.StateMachine) and t_elem == "self":
            sends, receives = ast.event_directions(s_elem)
            return s_ev.name if s_ev.name in receives and s_ev.name not in sends else None
        if s_elem == "self" and isinstance(t_elem, ast.StateMachine):
            sends, receives = ast.event_directions(t_elem)
            return t_ev.name if t_ev.name in sends and t_ev.name not in receives else None
        return None

    # ----------------------------------------------------------------- platforms and modules

    def platform(self, scope: FileScope, tree: Tree, qname: str) -> ast.RoboticPlatform:
        path = scope.path
        events: list[ast.Event] = []
        variables: list[ast.Variable] = []
        operations: list[ast.OperationSig] = []
        relations: dict[str, list[str]] = {"uses": [], "provides": [], "requires": []}
        for item in tree.children[1:]:
            if item.data in relations:
                iface = self.interface_ref(scope, item.children[0])
                if iface is None:
                    continue
                relations[item.data].append(iface.qname)
                events += iface.events
                variables += iface.variables
                operations += iface.operations
            elif item.data == "event":
                events.append(self.event(scope, item, qname))
            elif item.data == "op_sig":
                operations.append(self.op_sig(scope, item, qname))
        variables += self.variables(scope, children(tree, "var_list"), qname, None)
        self._no_duplicates(path, events, qname)
        return ast.RoboticPlatform(qname, pos_of(path, name_of(tree)), tuple(events), tuple(variables),
                                   tuple(operations), tuple(relations["provides"]), tuple(relations["uses"]),
                                   tuple(relations["requires"]))

    def platform_decl(self, decl: Declaration) -> ast.RoboticPlatform | None:
        return self.memo("platform", decl.qname, lambda: self.platform(decl.file, decl.tree, decl.qname),
                         decl.file.path, name_of(decl.tree))

    def module(self, decl: Declaration) -> ast.Module | None:
        return self.memo("module", decl.qname, lambda: self._module(decl), decl.file.path, name_of(decl.tree))

    def _module(self, decl: Declaration) -> ast.Module:
        scope, tree, qname = decl.file, decl.tree, decl.qname
        path = scope.path
        platform: ast.RoboticPlatform | None = None
        platform_name: str | None = None
        controllers: list[ast.ControllerInstance] = []
        for item in tree.children[1:]:
            if item.data == "platform_def":
                if platform is not None:
                    self.error(path, item, "a module has one robotic platform", rule="M1")
                inner = Declaration("platform_def", f"{qname}::{name_of(item)}", item, scope)
                platform = self.platform_decl(inner)
                platform_name = str(name_of(item))
            elif item.data == "platform_ref":
                if platform is not None:
                    self.error(path, item, "a module has one robotic platform", rule="M1")
                ref_name, target = item.children
                p_decl = self.table.lookup(scope, qname_text(target), ("platform_def",))
                if p_decl is None:
                    t = qname_text(target)
                    self.error(path, target, f"unknown robotic platform '{t}'{suggestion(t, self.table.names(('platform_def',)))}", rule=LINKING)
                    continue
                platform = self.platform_decl(p_decl)
                platform_name = str(ref_name)
            elif item.data == "controller_def":
                inner = Declaration("controller_def", f"{qname}::{name_of(item)}", item, scope)
                c = self.controller(inner)
                if c is not None:
                    controllers.append(ast.ControllerInstance(c.name, c, c.pos))
            elif item.data == "controller_ref":
                ref_name, target = item.children
                c_decl = self.table.lookup(scope, qname_text(target), ("controller_def",))
                if c_decl is None:
                    t = qname_text(target)
                    self.error(path, target, f"unknown controller '{t}'{suggestion(t, self.table.names(('controller_def',)))}", rule=LINKING)
                    continue
                c = self.controller(c_decl)
                if c is not None:
                    controllers.append(ast.ControllerInstance(str(ref_name), c, pos_of(path, ref_name)))
            elif item.data in ("stm_def", "stm_ref"):
                self.error(path, item, "unsupported: state machines placed directly in a module (put them in a controller)")
            elif item.data in UNSUPPORTED_DECLARATIONS:
                self.error(path, item, f"unsupported: {UNSUPPORTED_DECLARATIONS[item.data]}")
        if platform is None:
            self.error(path, name_of(tree), f"module '{qname}' has no robotic platform", rule="M1")
        ends: dict[str, object] = {c.name: c.controller for c in controllers}
        if platform is not None and platform_name is not None:
            ends[platform_name] = platform
        connections = [c for c in (self.connection(path, item, ends, {}) for item in children(tree, "connection")) if c]
        return ast.Module(qname, pos_of(path, name_of(tree)), platform, platform_name, tuple(controllers),
                          tuple(connections))

    # ----------------------------------------------------------------- assertions

    def assertions(self, path: str, tree: Tree, blocks: list[ast.CspBlock],
                   process_names: set[str]) -> list[ast.Assertion]:
        scope = self._scopes[path]
        result = []
        for item in tree.children:
            if item.data == "type_instantiation":
                self.error(path, item, "unsupported: type instantiations ('instantiate')")
            elif item.data in UNSUPPORTED_PROBABILISTIC:
                # PRISM's items are checked by nothing here, and no CSP assertion refers to them:
                # each is reported, as itself left unchecked, and the file's other items still load.
                self.report(pos_of(path, item), f"unsupported: {UNSUPPORTED_PROBABILISTIC[item.data]}", "warning")
            elif item.data == "assertion":
                a = self.assertion(scope, item, process_names)
                if a is not None:
                    result.append(a)
        return result

    def csp_block(self, path: str, tree: Tree, text: str) -> ast.CspBlock:
        timing = None
        associated: tuple[str, ...] = ()
        code = ""
        name = ""
        start = (1, 1)
        for c in tree.children:
            if isinstance(c, Tree) and c.data in ("timed", "untimed"):
                timing = c.data
            elif isinstance(c, Tree) and c.data == "associated":
                associated = tuple(qname_text(q) for q in c.children)
            elif isinstance(c, Token) and c.type == "CSP_CODE":
                code = str(c)[len("csp-begin"):-len("csp-end")]
                start = (c.line or 1, (c.column or 1) + len("csp-begin"))
            elif isinstance(c, Token) and c.type == "ID":
                name = str(c)
        declared = [n.strip() for m in _CSP_CHANNELS.finditer(code) for n in m.group(1).split(",")]
        defines = tuple(dict.fromkeys([*(m.group(1) for m in _CSP_DEFINITION.finditer(code)), *declared]))
        return ast.CspBlock(name, timing, associated, code, pos_of(path, tree), defines, *start)

    def element_names(self) -> list[str]:
        return self.table.names(("stm_def", "controller_def", "module_def", "operation_def"))

    def resolve_element(self, scope: FileScope, name: str) -> object | None:
        """A machine, controller, module or operation named in an assertion."""
        decl = self.table.lookup(scope, name, ("stm_def", "controller_def", "module_def", "operation_def"))
        if decl is not None:
            return {"stm_def": self.machine, "controller_def": self.controller, "module_def": self.module,
                    "operation_def": self.operation}[decl.kind](decl)
        # An element inside another: `Controller::stm`, `Module::ctrl`.
        head, _, last = name.rpartition("::")
        if head:
            outer = self.resolve_element(scope, head)
            if isinstance(outer, ast.Controller):
                for m in outer.machines:
                    if m.name == last:
                        return m.machine
                for o in outer.operations:
                    if o.name == last:
                        return o.operation
            if isinstance(outer, ast.Module):
                for c in outer.controllers:
                    if c.name == last:
                        return c.controller
        return None

    def assertion(self, scope: FileScope, tree: Tree, process_names: set[str]) -> ast.Assertion | None:
        path = scope.path
        timing = None
        body = model = settings_tree = None
        name_token = None
        for c in tree.children:
            if isinstance(c, Token) and c.type == "ID":
                name_token = c
            elif isinstance(c, Tree):
                if c.data in ("timed", "untimed"):
                    timing = c.data
                elif c.data == "model_clause":
                    model = c.children[0].data.replace("_model", "").replace("_", " ")
                elif c.data == "with_clause":
                    settings_tree = c
                else:
                    body = c
        assert name_token is not None and body is not None
        negated = any(isinstance(c, Token) and c.type == "NOT" for c in body.children)
        names = [c for c in body.children if isinstance(c, Tree) and c.data == "qname"]
        kind = {
            "reachable_assertion": "reachable", "refines_assertion": "refines", "equals_assertion": "equals",
            "not_refines_assertion": "refines", "not_equal_assertion": "equals",
            "terminates_assertion": "terminates", "not_terminates_assertion": "terminates",
            "clock_assertion": "clock-initialised",
        }.get(body.data)
        if body.data == "unary_assertion":
            prop = next(c for c in body.children if isinstance(c, Tree) and c.data == "unary_property")
            kind = str(prop.children[0])
        if model == "tick tock":
            model = "tick-tock"
        text = self._source_text(path, tree)
        subject_node = names[0]
        subject = qname_text(subject_node)
        other = qname_text(names[1]) if len(names) > 1 else None
        subject_is_process = other_is_process = False
        pos = pos_of(path, name_token)
        if kind == "reachable":
            # `S is reachable in P`: P is the element, S one of its states.
            element = self.resolve_element(scope, other or "")
            if element is None:
                self._unknown_process(path, names[1], other or "", process_names)
            else:
                nodes = [n for b in _behaviours_of(element) for n in b.nodes]
                if not any(subject == n.path or subject.endswith("::" + n.path) for n in nodes):
                    known = [n.path for n in nodes]
                    self.error(path, subject_node, f"'{other}' has no state '{subject}'{suggestion(subject, known)}", rule=LINKING)
        elif kind == "clock-initialised":
            pass  # reported as unsupported by the checker, with the rest of the untimed forms
        else:
            for node, nm in ((subject_node, subject), (names[1] if other else None, other)):
                if node is None or nm is None:
                    continue
                if self.resolve_element(scope, nm) is None:
                    if nm in process_names:
                        if nm == subject:
                            subject_is_process = True
                        else:
                            other_is_process = True
                    else:
                        self._unknown_process(path, node, nm, process_names)
        settings = self._settings(scope, settings_tree) if settings_tree is not None else ()
        return ast.Assertion(str(name_token), kind or body.data, subject, negated, pos, text, timing, other, model,
                             settings, subject_is_process, other_is_process)

    def _unknown_process(self, path: str, node: Tree, name: str, process_names: set[str]) -> None:
        known = self.element_names() + sorted(process_names)
        self.error(path, node, f"unknown machine, controller, module or process '{name}'{suggestion(name, known)}", rule=LINKING)

    def _settings(self, scope: FileScope, tree: Tree) -> tuple[ast.ConstantSetting, ...]:
        result = []
        for s in tree.children:
            const_token, element_node, _, value_node = s.children
            element_name = qname_text(element_node)
            element = self.resolve_element(scope, element_name)
            checker = self.checker(scope, Scope(scope.path, "assertion"))
            value = checker.expr(value_node)
            if element is None:
                self.error(scope.path, element_node, f"unknown machine, controller or module '{element_name}'"
                           f"{suggestion(element_name, self.element_names())}", rule=LINKING)
                continue
            if s.data == "parameter_setting":
                what = "parameter"
                constants = {p.name: p for p in getattr(element, "parameters", ())}
            else:
                what = "constant"
                constants = self._constants_of(element)
            const = constants.get(str(const_token))
            if const is None:
                self.error(scope.path, const_token, f"'{element_name}' has no {what} '{const_token}'"
                           f"{suggestion(str(const_token), list(constants))}", rule=LINKING)
                continue
            checker.expect(value_node, value, const.type, f"the value of constant '{const_token}'")
            result.append(ast.ConstantSetting(str(const_token), element_name, value, pos_of(scope.path, s), what))
        return tuple(result)

    def _constants_of(self, element: object) -> dict[str, ast.Variable]:
        """Constants an assertion may set on an element: its own, its interfaces', its parts'."""
        consts: dict[str, ast.Variable] = {}

        def add(variables: Iterable[ast.Variable]) -> None:
            consts.update({v.name: v for v in variables if v.constant})

        def interfaces(qnames: Iterable[str]) -> None:
            for q in qnames:
                iface = self._memo.get(("interface", q))
                if isinstance(iface, ast.Interface):
                    add(iface.variables)

        for b in _behaviours_of(element):
            add(b.variables)
            add(b.interface_variables)
        controllers = [element] if isinstance(element, ast.Controller) else (
            [c.controller for c in element.controllers] if isinstance(element, ast.Module) else [])
        for c in controllers:
            add(c.variables)
            interfaces(c.required_interfaces + c.provided_interfaces + c.used_interfaces)
        if isinstance(element, ast.Module) and element.platform is not None:
            add(element.platform.variables)
        return consts

    def _source_text(self, path: str, tree: Tree) -> str:
        text = self._texts[path]
        meta = tree.meta
        lines = text.split("\n")[meta.line - 1: meta.end_line]
        if not lines:
            return ""
        if len(lines) == 1:
            return lines[0][meta.column - 1: meta.end_column - 1].strip()
        lines[0] = lines[0][meta.column - 1:]
        lines[-1] = lines[-1][: meta.end_column - 1]
        return " ".join(line.strip() for line in lines).strip()

    _texts: dict[str, str]

    # ----------------------------------------------------------------- everything

    def resolve(self, root: str, texts: dict[str, str]) -> ast.Project:
        self._scopes = {}
        self._texts = texts
        self.declare()
        types: list = []
        interfaces: list = []
        functions: list = []
        machines: list = []
        operations: list = []
        controllers: list = []
        platforms: list = []
        modules: list = []
        builders = {
            "primitive_type": (self.type_decl, types), "record_type": (self.type_decl, types),
            "enumeration": (self.type_decl, types), "interface": (self.interface, interfaces),
            "function_def": (self.function, functions), "stm_def": (self.machine, machines),
            "operation_def": (self.operation, operations), "controller_def": (self.controller, controllers),
            "platform_def": (self.platform_decl, platforms), "module_def": (self.module, modules),
        }
        for decl in list(self.table.declarations.values()):
            if decl.kind in UNSUPPORTED_DECLARATIONS:
                self.error(decl.file.path, decl.tree, f"unsupported: {UNSUPPORTED_DECLARATIONS[decl.kind]}")
                continue
            build, sink = builders[decl.kind]
            value = build(decl)
            if value is not None:
                sink.append(value)
        blocks: list[ast.CspBlock] = []
        for path, kind, tree in self.files:
            if kind == "assertions":
                blocks += [self.csp_block(path, t, texts[path]) for t in children(tree, "csp_process")]
        process_names = {n for b in blocks for n in (b.name, *b.defines)}
        assertions: list[ast.Assertion] = []
        for path, kind, tree in self.files:
            if kind == "assertions":
                assertions += self.assertions(path, tree, blocks, process_names)
        assertions = self._assertions_apart(assertions)
        project = ast.Project(root, tuple(p for p, _, _ in self.files), tuple(types), tuple(interfaces),
                              tuple(functions), tuple(machines), tuple(operations), tuple(controllers),
                              tuple(platforms), tuple(modules), tuple(blocks), tuple(assertions), sources=dict(texts))
        self.refuse_dropped(project)
        return project

    def refuse_dropped(self, project: ast.Project) -> None:
        """Make an error of each construct kept without a meaning (`ExprChecker.meaningless`) that
        the project does not hold: an expression around one that has the error type may be built
        as an error literal, so no check would see it and an assertion reaching it would be decided."""
        held = {(x.pos, x.what) for x in ast.parts(project) if isinstance(x, (ast.UnsupportedExpr, ast.UnsupportedStmt))}
        dropped = {(pos, f"unsupported: {what}{PER_ASSERTION}"): what for pos, what in self._kept
                   if (pos, what) not in held}
        for i, d in enumerate(self.diagnostics):
            what = dropped.get((d.pos, d.message)) if d.severity == "warning" else None
            if what is not None:
                self.diagnostics[i] = Diagnostic(d.pos, f"unsupported: {what}", "error", d.rule)

    def _assertions_apart(self, assertions: list[ast.Assertion]) -> list[ast.Assertion]:
        """The assertions, each whose name another file also declares labelled with its file (its
        name, or its path where two such files share a name): RoboTool writes each `.assertions` file
        as a CSP file of its own, so two files may reuse a name. In one file a name is declared once."""
        seen: dict[tuple[str, str], ast.Pos] = {}
        files: dict[str, list[str]] = {}
        for a in assertions:
            key = (a.pos.path, a.name)
            if key in seen:
                self.report(a.pos, f"assertion '{a.name}' is declared twice (first at {seen[key]})", rule=UNIQUE)
                continue
            seen[key] = a.pos
            files.setdefault(a.name, []).append(a.pos.path)
        result = []
        for a in assertions:
            paths = files[a.name]
            if len(paths) > 1:
                names = [Path(p).name for p in paths]
                unique = len(set(names)) == len(names)
                a = dataclasses.replace(a, file=Path(a.pos.path).name if unique else a.pos.path)
            result.append(a)
        return result


def _events_of(element: object) -> tuple[ast.Event, ...]:
    if isinstance(element, (ast.Behaviour, ast.Controller, ast.RoboticPlatform)):
        return element.events
    return ()


def _behaviours_of(element: object) -> list[ast.Behaviour]:
    """The machines and operations an element contains (itself, for a machine)."""
    if isinstance(element, ast.Behaviour):
        return [element]
    if isinstance(element, ast.Controller):
        return [m.machine for m in element.machines] + [o.operation for o in element.operations]
    if isinstance(element, ast.Module):
        return [b for c in element.controllers for b in _behaviours_of(c.controller)]
    return []


