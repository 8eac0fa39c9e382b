"""What a check runs with: the data ranges and the constants' values, each with where it came from.

One resolution serves every engine.  Layers, lowest first:

* defaults: for ranges, those the caller passes (`ROBOTOOL_RANGES` for RoboTool's); for a
  constant the model leaves without a value, the default value of its type, as RoboTool
  generates it (0, `true`, the first literal, a record of defaults);
* the project's instantiation (`instantiations.csp`, or an `Instantiations` CSP block):
  `nametype` intervals, `const_…` values, function bodies (`model/instantiation.py`);
* the command line: `--range`, `--set`, `--param` (a constant made a parameter takes every
  value of its type and range);
* per assertion, the arguments of `M::D__(id, …)`, then the assertion's `with constant`.

Every name a user gives is resolved against the model here, with "did you mean" for
unknown names; a name or value that does not fit is a `ConfigError` (a usage error).
Constants are keyed by their declaration (`owner::name`, see `declaration_key`), so that
BMC and the interpreter read the same value for the same constant.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from fractions import Fraction

from tockbmc.model import ast
from tockbmc.model import instantiation as inst
from tockbmc.model.diagnostics import Diagnostic, suggestion
from tockbmc.model.memory import read_before_sending
from tockbmc.model.ranges import Range, Ranges, holds_sequence, is_path, supplied_sequence
from tockbmc.model.readings import (
    Filled,
    Reading,
    bounded_arithmetic,
    default_value,
    describe_value,
    fill_unset,
    reached,
)

Element = ast.Behaviour | ast.Controller | ast.Module | ast.RoboticPlatform | ast.Interface
Checked = ast.StateMachine | ast.Controller | ast.Module | ast.OperationDef

CORE_TYPES = {"core_int": ast.INT, "core_nat": ast.NAT, "core_real": ast.REAL}
ROBOTOOL_RANGES = Ranges({"core_int": Range(Fraction(-2), Fraction(2)), "core_nat": Range(Fraction(0), Fraction(2)),
                          "core_real": Range(Fraction(-2), Fraction(2))})
# RoboTool's instance of `Seq(T)`, `LSeq(T,2)`: the sequences of length 0, 1 or 2, written into
# the generated channel declarations (docs/robotool-evidence.md §9.5).  The length of a sequence
# the environment supplies under `--robotool`, unless a range is on its path; listed with a result
# as `SEQUENCE_LENGTH` where the element checked has such an input.
ROBOTOOL_SEQUENCE_LENGTH = Range(Fraction(0), Fraction(2))
SEQUENCE_LENGTH = "sequence input length"
# RoboTool's own definitions in an instantiation, which tockbmc's semantics replaces: bounded
# arithmetic (tockbmc's is exact, docs/semantics.md §6.5), strings, clocks (unbounded, §4.5).
_ROBOTOOL_HELPERS = {"Plus", "Minus", "Mult", "Div", "Neg", "Modulus", "MinusNoNeg", "calc_type_min",
                     "calc_type_max", "no_zero_div"}
_IGNORED_TYPES = {"core_boolean", "core_string", "core_clock_type"}
_NUMBER = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?")
_RATIO = re.compile(r"[+-]?\d+/\d+")
_MAX_NUMBER_TEXT = 64
_MAX_EXPONENT = 64


class ConfigError(ValueError):
    """A name or value given for a check that does not fit the model (a usage error)."""

    def __init__(self, message: str, option: str = "--set"):
        super().__init__(message)
        self.option = option

    def __reduce__(self) -> tuple[type[ConfigError], tuple[str, str]]:
        """Rebuilt with its option (a worker process of `check -j` raises it in the parent)."""
        return ConfigError, (str(self), self.option)


@dataclass(frozen=True)
class Source:
    """Where a range or a constant's value comes from: `--range`, `instantiations.csp:12`, …"""

    what: str
    where: str | None = None

    def __str__(self) -> str:
        return f"{self.what} {self.where}" if self.where else self.what


# How directly a value was given, weakest first (see `Configuration._bind_required`).
_RANK = {"RoboTool default": 0, "model": 1, "instantiation": 2, "--set": 3, "--param": 3, "D__ argument": 4,
         "with constant": 5}

FLAG_RANGE = Source("--range")
FLAG_SET = Source("--set")
FLAG_PARAM = Source("--param")
ROBOTOOL_DEFAULT = Source("RoboTool default")
ROBOTOOL_LSEQ = Source("RoboTool's LSeq(T,2)", "(docs/robotool-evidence.md §9.5)")
UNSET_PARAM = Source("no value given: a parameter")


def _at(pos: ast.Pos) -> str:
    return f"{pos.path}:{pos.line}"


@dataclass(frozen=True)
class Setup:
    """What one assertion is checked with."""

    ranges: Ranges
    constants: dict[str, ast.Expr]  # declaration key -> value; a parameter has none
    described_ranges: dict[str, str]
    described_constants: dict[str, str]
    range_sources: dict[str, str]
    constant_sources: dict[str, str]
    parameters: tuple[str, ...] = ()  # the constants left parameters: every value of each is considered
    reading: Reading = Reading.DEFAULT
    # what the reading filled in that the element reaches: variable or function -> value ("" if kept open)
    defaults: dict[str, str] = field(default_factory=dict)
    default_sources: dict[str, str] = field(default_factory=dict)

    @property
    def sources(self) -> dict[str, dict[str, str]]:
        out = {"ranges": self.range_sources, "constants": self.constant_sources}
        return {**out, "defaults": self.default_sources} if self.default_sources else out


def declaration_key(v: ast.Variable) -> str:
    """A constant's identity across engines: the qualified name of its declaration."""
    return f"{v.owner}::{v.name}"


def constant_setting(settings: Mapping[str, ast.Expr], v: ast.Variable, shared: ast.Variable | None = None
                     ) -> ast.Expr | None:
    """The value a configuration gives a constant (`shared`: the declaration it is bound to)."""
    for d in (shared, v):
        if d is not None:
            got = settings.get(declaration_key(d))
            if got is not None:
                return got
    return None


# ----------------------------------------------------------------------------- numbers and values


def parse_number(text: str, option: str) -> Fraction:
    """A decimal, `p/q` or exponent number; huge exponents and over-long numbers are refused at once."""
    t = text.strip()
    if len(t) > _MAX_NUMBER_TEXT:
        raise ConfigError(f"'{text[:20]}…' is too long for a number", option)
    if _RATIO.fullmatch(t):
        num, den = t.split("/")
        if int(den) == 0:
            raise ConfigError(f"'{text}': division by zero", option)
        return Fraction(int(num), int(den))
    m = _NUMBER.fullmatch(t)
    if m is None:
        raise ConfigError(f"'{text}' is not a number", option)
    if m.group(3) and abs(int(m.group(3)[1:])) > _MAX_EXPONENT:
        raise ConfigError(f"'{text}': the exponent is too large (at most {_MAX_EXPONENT})", option)
    return Fraction(t)


def _num(x: Fraction) -> str:
    return str(x.numerator) if x.denominator == 1 else str(x)


def _value_of_text(text: str, t: ast.Type, name: str) -> ast.Expr:
    pos = ast.Pos("<command line>", 1, 1)
    if t == ast.BOOLEAN:
        if text in ("true", "false"):
            return ast.Literal(ast.BOOLEAN, pos, text == "true")
        raise ConfigError(f"{name} is a boolean: '{text}' is not true or false")
    if t in ast.NUMERIC or isinstance(t, ast.GivenType):
        if text in ("true", "false"):
            raise ConfigError(f"{name} is {t}: '{text}' is not a number")
        try:
            n = parse_number(text, "--set")
        except ConfigError as exc:
            raise ConfigError(f"{name}: {exc}") from None
        if t != ast.REAL and n.denominator != 1:
            raise ConfigError(f"{name} is {t}: {text} is not an integer")
        if t == ast.NAT and n < 0:
            raise ConfigError(f"{name} is nat: {text} is negative")
        if t == ast.REAL:
            return ast.Literal(ast.REAL, pos, n)
        kind = t if isinstance(t, ast.GivenType) else (ast.NAT if n >= 0 else ast.INT)
        return ast.Literal(kind, pos, int(n))
    if isinstance(t, ast.EnumType):
        short = text.rsplit("::", 1)[-1]
        qualifier = text.rpartition("::")[0]
        if short in t.literals and qualifier in ("", t.name, t.qname):
            if t.parameters(short):
                raise ConfigError(f"{name} is a {t.name}: literal {short} has parameters, and only literals without "
                                  "parameters can be set here")
            return ast.EnumLiteral(t, pos, t, short)
        known = [f"{t.name}::{lit}" for lit in t.literals]
        raise ConfigError(f"{name} is a {t.name}: no literal '{text}'{suggestion(text, known + list(t.literals))} "
                          f"(literals: {', '.join(known)})")
    raise ConfigError(f"{name} is of type {t}: only numbers, booleans and enumeration literals can be set here")


# ----------------------------------------------------------------------------- the model's names


def _walk(project: ast.Project) -> dict[str, list[Element]]:
    """Every way to name an element: qualified and short names, and instance paths
    (`main::ctrl::ur_ref`, `M::C::op_ref0`)."""
    table: dict[str, list[Element]] = defaultdict(list)

    def add(path: str, e: Element) -> None:
        if not any(x is e for x in table[path]):
            table[path].append(e)

    def walk(e: Element, names: list[str], depth: int = 0) -> None:
        qname = e.qname
        for n in dict.fromkeys([*names, qname, qname.rsplit("::", 1)[-1]]):
            add(n, e)
        if depth > 8:
            return
        paths = list(dict.fromkeys([*names, qname]))
        if isinstance(e, ast.Controller):
            for mi in e.machines:
                walk(mi.machine, [f"{p}::{mi.name}" for p in paths], depth + 1)
            for oi in e.operations:
                walk(oi.operation, [f"{p}::{oi.name}" for p in paths], depth + 1)
        elif isinstance(e, ast.Module):
            if e.platform is not None:
                walk(e.platform, [f"{p}::{n}" for p in paths for n in {e.platform_name or e.platform.name,
                                                                         e.platform.name}], depth + 1)
            for ci in e.controllers:
                walk(ci.controller, [f"{p}::{ci.name}" for p in paths], depth + 1)

    for group in (project.interfaces, project.platforms, project.operations, project.machines, project.controllers,
                  project.modules):
        for e in group:
            walk(e, [])
    return dict(table)


def _interface_constants(project: ast.Project, names: Iterable[str]) -> list[ast.Variable]:
    return [v for v in _interface_variables(project, names) if v.constant]


def _interface_variables(project: ast.Project, names: Iterable[str]) -> list[ast.Variable]:
    by_name = {i.qname: i for i in project.interfaces}
    by_short: dict[str, list[ast.Interface]] = defaultdict(list)
    for i in project.interfaces:
        by_short[i.name].append(i)
    out: list[ast.Variable] = []
    for n in names:
        iface = by_name.get(n) or (by_short[n][0] if len(by_short.get(n, [])) == 1 else None)
        if iface is not None:
            out += list(iface.variables)
    return out


def constants_of(project: ast.Project, e: Element) -> list[ast.Variable]:
    """The constants `with constant c of E` may name: E's own, its interfaces', its parts'."""
    out: list[ast.Variable] = []
    if isinstance(e, ast.Behaviour):
        # an operation's parameters are assigned where it is called, and constants only when it is checked alone
        out += [v for v in (*e.variables, *e.interface_variables)
                if v.constant and (v.kind != "parameter" or isinstance(e, ast.OperationMachine))]
    elif isinstance(e, ast.Controller):
        for mi in e.machines:
            out += constants_of(project, mi.machine)
        for oi in e.operations:
            out += constants_of(project, oi.operation)
        out += [v for v in e.variables if v.constant]
        out += _interface_constants(project, (*e.required_interfaces, *e.provided_interfaces, *e.used_interfaces))
    elif isinstance(e, ast.Module):
        for ci in e.controllers:
            out += constants_of(project, ci.controller)
        if e.platform is not None:
            out += constants_of(project, e.platform)
    elif isinstance(e, ast.RoboticPlatform):
        out += [v for v in e.variables if v.constant]
        out += _interface_constants(project, e.provided_interfaces)
    elif isinstance(e, ast.Interface):
        out += [v for v in e.variables if v.constant]
    return _unique(out)


def _unique(vs: Iterable[ast.Variable]) -> list[ast.Variable]:
    seen: dict[str, ast.Variable] = {}
    for v in vs:
        seen.setdefault(declaration_key(v), v)
    return list(seen.values())


@dataclass(frozen=True)
class _Slot:
    """A constant of a checked element with RoboTool's names for it, most specific first."""

    variable: ast.Variable
    names: tuple[str, ...]
    in_operation: bool = False  # a constant a defined operation declares or requires
    # The instance names from the checked element down to the machine that holds the constant
    # (`("stm_ref0",)`, `("ctrl", "stm_ref0")`); empty for the element's own constants and for a
    # defined operation's, which is inlined where it is called and has one value per declaration.
    instance: tuple[str, ...] = ()


def instance_key(instance: tuple[str, ...], v: ast.Variable) -> str:
    """The key of one instance's value for a constant: two instances of a machine declaration are
    two constants in RoboTool (`const_test12_ctrl0_stm_ref0_CC`), each settable on its own."""
    return f"{'::'.join(instance)}/{declaration_key(v)}"


def instance_name(element: str, instance: tuple[str, ...], v: ast.Variable) -> str:
    """How results name one instance's constant, from the checked element's qualified name:
    `ctrl0::stm_ref0::CC`, which `--set` accepts."""
    return f"{element}::{'::'.join(instance)}::{v.name}"


def instance_paths(element: Checked, instance: tuple[str, ...]) -> set[str]:
    """Every name of an instance path inside `element`: from the element (`Mod::c::m1`), or from
    any element on the way (`C::m1` for the machine m1 of controller C, instantiated as c)."""
    out: set[str] = set()
    e: object = element
    for k, step in enumerate(instance):
        if isinstance(e, (ast.StateMachine, ast.Controller, ast.Module, ast.OperationDef)):
            rest = "::".join(instance[k:])
            out |= {f"{e.qname}::{rest}", f"{e.qname.rsplit('::', 1)[-1]}::{rest}"}
        if isinstance(e, ast.Module):
            e = next((ci.controller for ci in e.controllers if ci.name == step), None)
        elif isinstance(e, ast.Controller):
            e = next((mi.machine for mi in e.machines if mi.name == step), None)
        else:
            break
    return out


Chain = tuple[tuple[object, tuple[str, ...]], ...]  # (element, the instance path below it to the machine)


def _below(e: object, name: str) -> object | None:
    """The element instance `name` of `e` stands for (a controller's machine or operation, a
    module's controller)."""
    if isinstance(e, ast.Module):
        return next((ci.controller for ci in e.controllers if ci.name == name), None)
    if isinstance(e, ast.Controller):
        return next((x.machine for x in e.machines if x.name == name), None) or \
            next((x.operation for x in e.operations if x.name == name), None)
    return None


def instance_chain(start: object, path: tuple[str, ...]) -> Chain | None:
    """The elements a path of instances from `start` goes through, each with the rest of the path
    from it (the last with none); None where an instance does not exist."""
    out: list[tuple[object, tuple[str, ...]]] = [(start, path)]
    e: object | None = start
    for k, step in enumerate(path):
        e = _below(e, step)
        if e is None:
            return None
        out.append((e, path[k + 1:]))
    return tuple(out)


def _same_instance(flag: Chain, slot: Chain) -> bool:
    """Whether two chains reach one instance: seen from the first element of one chain that the
    other goes through (`ctrl0::stm_ref0` is `Mod::c::stm_ref0` in Mod, where c is ctrl0), the
    paths below it agree."""
    (first, rest), (ffirst, frest) = slot[0], flag[0]
    for f, at in flag:  # the slot's element on the flag's way
        if f is first:
            return at == rest
    for e, at in slot:  # the flag's first element on the slot's way (ctrl1's STM is not ctrl0's)
        if e is ffirst:
            return at == frest
    return False


def _text(entry: _ConstEntry) -> str:
    return describe_value(entry.value) if entry.value is not None else "(a parameter)"


def _instances_named(head: str, constant: str, element: Checked, slots: list[_Slot]) -> list[_Slot]:
    """The constants named `constant` that an instance path `head` inside the checked element names
    (`ctrl0::stm_ref0` for controller `ctrl0`, in `with constant c of P` or `--set P::c`), one
    instance's constant each."""
    return [s for s in slots if s.instance and s.variable.name == constant and s.variable.initial is None
            and head in instance_paths(element, s.instance)]


def robotool_slots(project: ast.Project, element: Checked) -> list[_Slot]:
    """The constants an element's `D__` takes, named as RoboTool's instantiation names them:
    `const_` and the mangled path of the element that holds the constant, through instance names
    (`const_main_Controller_stm_ref1_n`), or the definition's own (`const_EXAX_n`); generators
    of different versions use one or the other, so both are accepted. Where an instantiation
    gives both, the one the generator that writes such names passes comes first: the path where
    the definition's name is its own (`const_GasAnalysis_thr`, RoboTool 3.0's generated CSP), the
    definition's where it carries the definition's package
    (`const_AutonomousChemicalDetector_GasAnalysis_GasAnalysis_thr`: that generator's module
    process takes the definitions' constants; docs/robotool-evidence.md §6)."""
    out: list[_Slot] = []

    def names(prefixes: list[str], v: ast.Variable) -> tuple[str, ...]:
        return tuple(f"const_{p}_{v.name}" for p in dict.fromkeys(prefixes))

    def behaviour(b: ast.Behaviour, prefixes: list[str], instance: tuple[str, ...] = ()) -> None:
        for v in constants_of(project, b):
            # a required interface's constant is its controller's (one per name), not the instance's
            shared = v.kind == "interface" and ast.in_interfaces(v, b.required_interfaces)
            own = inst.mangle(b.qname)
            order = [own, *prefixes] if "::" in b.qname else [*prefixes, own]
            out.append(_Slot(v, names(order, v), isinstance(b, ast.OperationDef), () if shared else instance))

    def controller(c: ast.Controller, prefixes: list[str], instance: tuple[str, ...] = ()) -> None:
        ps = [*prefixes, inst.mangle(c.qname)]
        own = [v for v in c.variables if v.constant]
        own += _interface_constants(project, (*c.required_interfaces, *c.provided_interfaces, *c.used_interfaces))
        for v in _unique(own):
            out.append(_Slot(v, names(ps, v)))
        for mi in c.machines:
            behaviour(mi.machine, [f"{p}_{mi.name}" for p in dict.fromkeys(ps)], (*instance, mi.name))
        for oi in c.operations:  # inlined where called: one value per declaration, whichever `opref` names it
            behaviour(oi.operation, [f"{p}_{oi.name}" for p in dict.fromkeys(ps)])

    if isinstance(element, ast.Behaviour):
        behaviour(element, [])
    elif isinstance(element, ast.Controller):
        controller(element, [])
    elif isinstance(element, ast.Module):
        m = inst.mangle(element.qname)
        if element.platform is not None:
            p = element.platform
            for v in constants_of(project, p):
                out.append(_Slot(v, names([f"{m}_{element.platform_name or p.name}", inst.mangle(p.qname)], v)))
        for ci in element.controllers:
            controller(ci.controller, [f"{m}_{ci.name}"], (ci.name,))
    return out


# ----------------------------------------------------------------------------- resolution of user names


class Names:
    """The model's names for `--set`, `--param` and `--range`, with suggestions."""

    def __init__(self, project: ast.Project):
        self.project = project
        self.elements = _walk(project)
        self.all_constants: list[tuple[str, ast.Variable]] = []  # (path::name, declaration)
        for path, es in self.elements.items():
            for e in es:
                for v in constants_of(project, e):
                    self.all_constants.append((f"{path}::{v.name}", v))
        self.types: dict[str, ast.Type] = {}
        for t in project.types:
            if isinstance(t, (ast.GivenType, ast.EnumType, ast.RecordType)):
                self.types.setdefault(t.qname, t)
                self.types.setdefault(t.name, t)

    def constant(self, name: str, option: str = "--set") -> list[ast.Variable]:
        """The declarations a name denotes: `n` (when only one constant has that name), `UR::n`,
        `main::ctrl::ur_ref::n`, `pkg::IConsts::z` …"""
        if not name or name.startswith("::") or name.endswith("::"):
            raise ConfigError(f"'{name}' is not a constant's name", option)
        head, _, last = name.rpartition("::")
        if not head:
            found = _unique(v for _, v in self.all_constants if v.name == name)
            if not found:
                raise ConfigError(f"no constant named '{name}'{self._suggest(name)}", option)
            if len(found) > 1:
                options = ", ".join(sorted(declaration_key(v) for v in found))
                raise ConfigError(f"'{name}' is ambiguous: it names {options}; qualify it", option)
            return found
        elements = self.elements.get(head)
        if not elements:
            raise ConfigError(f"no element '{head}' to hold constant '{last}'"
                              f"{suggestion(head, list(self.elements))}", option)
        found = _unique(v for e in elements for v in constants_of(self.project, e) if v.name == last)
        if not found:
            known = [f"{head}::{v.name}" for e in elements for v in constants_of(self.project, e)]
            hint = suggestion(name, known) or self._suggest(name)
            raise ConfigError(f"'{head}' has no constant '{last}'{hint}", option)
        if len(found) > 1:
            options = ", ".join(sorted(declaration_key(v) for v in found))
            raise ConfigError(f"'{name}' is ambiguous: it names {options}; qualify it", option)
        return found

    def instance_chain(self, name: str) -> Chain | None:
        """The elements a constant's name goes through when it names it by a path of instances
        (`ctrl0::stm_ref0::CC`: ctrl0, then STM), or None when it names the declaration (`STM::CC`,
        `CC`)."""
        segments = name.split("::")[:-1]
        for k in range(len(segments) - 1, 0, -1):
            prefix = "::".join(segments[:k])
            for e in self.elements.get(prefix, []):
                if prefix in (e.qname, e.qname.rsplit("::", 1)[-1]):
                    chain = instance_chain(e, tuple(segments[k:]))
                    if chain is not None:
                        return chain
        return None

    def _suggest(self, name: str) -> str:
        return suggestion(name, [p for p, _ in self.all_constants] + [v.name for _, v in self.all_constants])

    def range_type(self, name: str) -> tuple[str, ast.Type]:
        """A range name and what it bounds: `core_int`, a model type (by its short name, as the
        engines key it), or a path `Machine::event.field` that must exist."""
        if name in CORE_TYPES:
            return name, CORE_TYPES[name]
        if is_path(name):
            return self._path_key(name), self._path_type(name)
        t = self.types.get(name)
        if t is None:
            hint = f"; did you mean 'core_{name}'?" if name in ("int", "nat", "real") else \
                suggestion(name, [*CORE_TYPES, *self.types])
            raise ConfigError(f"no type '{name}' to bound{hint}", "--range")
        if not isinstance(t, ast.GivenType):
            kind = "an enumeration" if isinstance(t, ast.EnumType) else "a record type"
            raise ConfigError(f"'{name}' is {kind}: ranges bound numbers (core_int, core_nat, core_real, "
                              "types declared with 'type', or paths to numeric fields)", "--range")
        return t.name, t

    def _path_key(self, name: str) -> str:
        """The key a range path is kept under.  A path to a variable or constant becomes its
        declaration's key (`C::x`, `S1::x` and `CV::x` all name `pkg::CV::x`), which every engine
        looks a variable's range up by; a path to an event is kept as given."""
        head, dot, fields = name.partition(".")
        owner, _, member = head.rpartition("::")
        found = _unique(v for e in self.elements.get(owner, []) for v in _variables(self.project, e)
                        if v.name == member)
        is_event = any(member in {ev.name for ev in getattr(e, "events", ())} for e in self.elements.get(owner, []))
        if len(found) != 1 or is_event:
            return name
        return f"{declaration_key(found[0])}{dot}{fields}"

    @staticmethod
    def _argument_type(t: ast.EnumType, walked: str, literal: str, index: str) -> ast.Type:
        """The type of argument `index` (from 1) of literal `literal` of `t`, in a range path."""
        with_params = [lit for lit, ps in zip(t.literals, t.params, strict=True) if ps]
        if literal not in with_params:
            raise ConfigError(f"'{walked}' is of type {t}, which has no literal '{literal}' with parameters"
                              f"{suggestion(literal, with_params)}", "--range")
        ps = t.parameters(literal)
        if not index.isdigit() or not 1 <= int(index) <= len(ps):
            raise ConfigError(f"'{walked}.{literal}' needs the number of an argument of {literal}, 1 to {len(ps)}",
                              "--range")
        return ps[int(index) - 1]

    def _path_type(self, name: str) -> ast.Type:
        head, _, fields = name.partition(".")
        owner, _, member = head.rpartition("::")
        elements = self.elements.get(owner) if owner else None
        if not elements:
            known = [p for p, es in self.elements.items() if any(isinstance(e, (ast.Behaviour, ast.Controller,
                                                                               ast.Module)) for e in es)]
            raise ConfigError(f"no element '{owner or head}' in range path '{name}'"
                              f"{suggestion(owner or head, known)}", "--range")
        members: dict[str, ast.Type | None] = {}
        for e in elements:
            members.update(_members(self.project, e))
        if member not in members:
            raise ConfigError(f"'{owner}' has no event, variable or constant '{member}' (range path '{name}')"
                              f"{suggestion(member, list(members))}", "--range")
        t = members[member]
        if t is None:
            raise ConfigError(f"'{head}' carries no value to bound", "--range")
        walked = head
        steps = [x for x in fields.split(".") if x] if fields else []
        while steps:
            f = steps.pop(0)
            if isinstance(t, ast.EnumType) and t.params:  # `x.EM3.1`: literal EM3's first argument
                index = steps.pop(0) if steps else ""
                t, walked = self._argument_type(t, walked, f, index), f"{walked}.{f}.{index}"
                continue
            if not isinstance(t, ast.RecordType):
                raise ConfigError(f"'{walked}' is of type {t}, which has no field '{f}'", "--range")
            ft = t.field_type(f)
            if ft is None:
                raise ConfigError(f"'{walked}' has no field '{f}'{suggestion(f, [x.name for x in t.fields])}",
                                  "--range")
            t, walked = ft, f"{walked}.{f}"
        if isinstance(t, ast.RecordType):
            raise ConfigError(f"'{name}' is a record; bound one of its fields "
                              f"({', '.join(f'{name}.{x.name}' for x in t.fields)})", "--range")
        if isinstance(t, ast.SeqType):
            return t  # the range bounds the sequence's length (DESIGN.md, "Data types")
        if not (ast.is_numeric(t) or isinstance(t, ast.GivenType)):
            raise ConfigError(f"'{name}' is of type {t}: ranges bound numbers (and sequences' lengths)", "--range")
        return t


def _variables(project: ast.Project, e: Element) -> list[ast.Variable]:
    """The variables and constants an element holds: its own, and those of the interfaces it
    requires, provides or uses (a controller's `uses` interface declares shared variables)."""
    if isinstance(e, ast.Behaviour):
        return [*e.variables, *e.interface_variables]
    if isinstance(e, ast.Controller):
        return [*e.variables, *_interface_variables(project, (*e.used_interfaces, *e.provided_interfaces))]
    if isinstance(e, ast.Module):
        return _variables(project, e.platform) if e.platform is not None else []
    if isinstance(e, ast.RoboticPlatform):
        return [*e.variables, *_interface_variables(project, e.provided_interfaces)]
    if isinstance(e, ast.Interface):
        return list(e.variables)
    return []


def _members(project: ast.Project, e: Element) -> dict[str, ast.Type | None]:
    out: dict[str, ast.Type | None] = {}
    if isinstance(e, (ast.Behaviour, ast.Controller, ast.RoboticPlatform)):
        out.update({ev.name: ev.type for ev in e.events})
    elif isinstance(e, ast.Module):
        out.update(_members(project, e.platform) if e.platform is not None else {})
        for c in e.connections:
            out.setdefault(c.source_event.name, c.source_event.type)
            out.setdefault(c.target_event.name, c.target_event.type)
    for v in _variables(project, e):
        out.setdefault(v.name, v.type)
    return out


def check_range(name: str, t: ast.Type, r: Range, option: str = "--range") -> None:
    """A range fits what it bounds: integer bounds for integers, non-negative for naturals."""
    if r.low > r.high:
        raise ConfigError(f"'{name}={_num(r.low)}..{_num(r.high)}': LO must not exceed HI", option)
    if t != ast.REAL and (r.low.denominator != 1 or r.high.denominator != 1):
        raise ConfigError(f"'{name}' bounds {t} values: {_num(r.low)}..{_num(r.high)} are not integers", option)
    if (t == ast.NAT or isinstance(t, ast.SeqType)) and r.low < 0:
        what = "a sequence's length" if isinstance(t, ast.SeqType) else "naturals"
        raise ConfigError(f"'{name}' bounds {what}: LO must be at least 0, not {_num(r.low)}", option)


# ----------------------------------------------------------------------------- the configuration


@dataclass(frozen=True)
class _RangeEntry:
    range: Range | None  # None: unbounded
    source: Source


@dataclass(frozen=True)
class _ConstEntry:
    value: ast.Expr | None  # None: a parameter
    source: Source


class Configuration:
    """Ranges and constant values for every check of a project (see the module's docstring).

    `ranges` and `settings` are the command line's (`Range` or None for unbounded; an
    `ast.Expr` or the text of a value), `params` the names made parameters; `default_ranges`
    sit below the project's instantiation.  Raises `ConfigError` for a name or value that does
    not fit the model.  `project` is the model with the instantiation's function bodies.
    """

    def __init__(self, project: ast.Project, ranges: Ranges | Mapping[str, Range | None] | None = None,
                 settings: Mapping[str, ast.Expr | str] | None = None, params: Iterable[str] = (),
                 default_ranges: Ranges | None = None, instantiation: bool = True, open_defaults: bool | None = None,
                 reading: Reading = Reading.DEFAULT):
        self.reading = reading
        # a constant with no value anywhere is a parameter, not RoboTool's default (by default: in the open reading)
        self.open_defaults = reading == Reading.OPEN if open_defaults is None else open_defaults
        if reading == Reading.ROBOTOOL and default_ranges is None:
            default_ranges = ROBOTOOL_RANGES
        self.warnings: list[Diagnostic] = []
        self.texts: dict[str, str] = {}  # instantiation files read, for diagnostics
        self._ranges: dict[str, _RangeEntry] = {}
        for name, r in _range_items(default_ranges):
            if r is not None:
                self._ranges[name] = _RangeEntry(r, ROBOTOOL_DEFAULT)
        self._instantiated: dict[str, tuple[ast.Expr, Source]] = {}
        self._unread: dict[str, ast.Pos] = {}  # functions whose instantiation's body is not understood, by qname
        self._written: set[str] = set()  # functions the instantiation defines, by qname
        self.project = self._read_instantiation(project) if instantiation else project
        self.filled: tuple[Filled, ...] = ()  # what the reading filled in (none in the open one)
        # by the element's id, the element kept beside what it reaches so that the id is never another's
        self._reached: dict[int, tuple[Checked, tuple[Filled, ...]]] = {}
        if reading != Reading.OPEN:
            self.project, self.filled = fill_unset(self.project, self._unread)
        self.project = read_before_sending(self.project)  # RoboTool's memory model (model/memory.py)
        if reading == Reading.ROBOTOOL:
            self.project = bounded_arithmetic(self.project, self._core_ranges(ranges), frozenset(self._written))
        self.names = Names(self.project)  # of the project the checks read: instance chains are its elements
        self._flags: dict[str, _ConstEntry] = {}
        for name, r in _range_items(ranges):
            key, t = self.names.range_type(name)
            if r is not None:
                check_range(name, t, r)
            self._ranges[key] = _RangeEntry(r, FLAG_RANGE)
            for f in self.filled:  # a range on an initial value the reading fills in bounds nothing
                if r is not None and f.kind == "variable" and (f.name == key or f.name.endswith(f"::{key}")):
                    self._warn(f.pos, f"--range {name} has no effect in the {reading} reading: {key} starts at "
                                      f"{f.value}, RoboTool's default (with --open it starts anywhere in the range)")
        # one instance's constant (`ctrl0::stm_ref0::CC`), by the name given: (the instance's chain,
        # its declaration's key, value)
        self._instance_flags: dict[str, tuple[Chain, str, _ConstEntry]] = {}
        named_by: dict[str, str] = {}  # declaration -> the --set name that gave it a value
        for name, given in (settings or {}).items():
            for v in self.names.constant(name, "--set"):
                value = _value_of_text(given, v.type, name) if isinstance(given, str) else given
                if not isinstance(given, str) and not ast.assignable(v.type, value.type):
                    raise ConfigError(f"{name} is {v.type}: the value given is {value.type}")
                chain = self.names.instance_chain(name)
                if chain is not None:
                    self._instance_flags[name] = (self._one_instance(name, v, chain), declaration_key(v),
                                                  _ConstEntry(value, FLAG_SET))
                    continue
                key = declaration_key(v)
                if key in named_by:
                    raise ConfigError(f"{named_by[key]} and {name} both name constant {key}")
                named_by[key] = name
                self._flags[key] = _ConstEntry(value, FLAG_SET)
        for name in dict.fromkeys(params):  # a name given twice is made a parameter once
            if self.names.instance_chain(name) is not None:
                found = self.names.constant(name, "--param")
                raise ConfigError(f"{name} names one instance's constant, and --param makes a declaration's constant "
                                  "a parameter, each instance's its own: name it by its declaration "
                                  f"({', '.join(declaration_key(v) for v in found)})", "--param")
            for v in self.names.constant(name, "--param"):
                key = declaration_key(v)
                if key in self._flags and self._flags[key].source == FLAG_PARAM:
                    continue  # the same constant by another name
                if key in self._flags:
                    raise ConfigError(f"{name} is given a value with --set and made a parameter with --param",
                                      "--param")
                if v.initial is not None:
                    raise ConfigError(f"{name} has a value in the model ({v.initial.pos.path}:{v.initial.pos.line}); "
                                      "--param is for constants the model leaves open", "--param")
                self._flags[key] = _ConstEntry(None, FLAG_PARAM)
        # by the element's id, the element kept beside its slots so that the id is never another's
        # (an operation checked on its own is a view made per assertion: `ast.operation_machine`)
        self._slots: dict[int, tuple[Checked, list[_Slot]]] = {}
        self._sequences: dict[int, tuple[Checked, bool]] = {}  # as `_slots`: whether it is supplied a sequence
        checked: list[Checked] = [*self.project.controllers, *self.project.modules]
        for e in checked:  # one instance given two values: a usage error
            self._by_instance_flags(e, robotool_slots(self.project, e))

    # --- ranges

    def _core_ranges(self, flags: Ranges | Mapping[str, Range | None] | None) -> dict[str, tuple[Fraction, Fraction]]:
        """The ranges of `core_int`, `core_nat` and `core_real` (RoboTool's default, the instantiation's,
        the command line's), which RoboTool's bounded arithmetic keeps results in."""
        found = {k: e.range for k, e in self._ranges.items() if k in CORE_TYPES}
        found.update({k: r for k, r in _range_items(flags) if k in CORE_TYPES})
        return {k: (r.low, r.high) for k, r in found.items() if r is not None}

    def ranges(self) -> Ranges:
        """The ranges every assertion is checked with."""
        by_type = {k: e.range for k, e in self._ranges.items() if e.range is not None and not is_path(k)}
        by_path = {k: e.range for k, e in self._ranges.items() if e.range is not None and is_path(k)}
        robotool = self.reading == Reading.ROBOTOOL
        return Ranges(by_type, by_path, integral_reals=robotool,
                      sequence_length=ROBOTOOL_SEQUENCE_LENGTH if robotool else None)

    def range_sources(self) -> dict[str, str]:
        return {k: str(e.source) for k, e in self._ranges.items() if e.range is not None}

    # --- per assertion

    def setup(self, a: ast.Assertion | None, element: Checked,
              csp_arguments: Iterable[tuple[str, ast.Expr]] = ()) -> Setup:
        """The ranges and constants an assertion on `element` is checked with.  `csp_arguments`:
        the constants `M::D__(id, c1, …)` sets, by name (`properties.queries.Query.settings`)."""
        if id(element) not in self._slots:
            self._slots[id(element)] = (element, robotool_slots(self.project, element))
        slots = self._slots[id(element)][1]
        declared: dict[str, ast.Variable] = {}
        for s in slots:
            declared.setdefault(declaration_key(s.variable), s.variable)
        entries: dict[str, _ConstEntry] = {}
        for key, v in declared.items():
            if v.initial is not None:
                entries[key] = _ConstEntry(v.initial, Source("model", _at(v.pos)))
            elif self.open_defaults:
                entries[key] = _ConstEntry(None, UNSET_PARAM)
            else:
                entries[key] = _ConstEntry(default_value(v.type, v.pos), ROBOTOOL_DEFAULT)
        for key, (value, source) in self._from_instantiation(slots).items():
            entries[key] = _ConstEntry(value, source)
        for key, entry in self._flags.items():
            if key in declared:
                entries[key] = entry
        self._instance_flags_alone(element, slots, entries)
        for name, value in csp_arguments:
            for key, v in declared.items():
                if v.name == name:
                    entries[key] = _ConstEntry(value, Source("D__ argument", _at(value.pos)))
        for setting in a.settings if a is not None else ():
            if setting.kind == "parameter" and not isinstance(element, ast.OperationMachine):
                continue  # an operation's parameter is its caller's argument unless the operation is checked alone
            if _instances_named(setting.element, setting.constant, element, slots):
                continue  # one instance's value: `_per_instance`
            for key in self._with_constant(setting, declared):
                entries[key] = _ConstEntry(setting.value, Source("with constant", _at(setting.pos)))
        self._bind_required(slots, declared, entries)
        ranges = self.ranges()
        constants = {k: e.value for k, e in entries.items()
                     if e.value is not None and (declared[k].initial is None or e.source.what != "model")}
        described = {k: describe_value(e.value) if e.value is not None else self._parameter(declared[k])
                     for k, e in entries.items()}
        sources = {k: str(e.source) for k, e in entries.items()}
        per_instance = self._per_instance(a, element, slots, entries)
        for key in {k for _, k in per_instance}:  # every instance has its own: the declaration's is unused
            if all((s.instance, key) in per_instance for s in slots if declaration_key(s.variable) == key):
                del described[key], sources[key]
        for (path, key), entry in per_instance.items():
            assert entry.value is not None
            constants[instance_key(path, declared[key])] = entry.value
            shown = instance_name(element.qname, path, declared[key])
            described[shown] = describe_value(entry.value)
            sources[shown] = str(entry.source)
        parameters = tuple(sorted(k for k, e in entries.items() if e.value is None and k in described))
        filled = self._filled_for(element)
        described_ranges, range_sources = ranges.describe(), self.range_sources()
        if ranges.sequence_length is not None and (self._supplied_sequence(element)
                                                   or any(holds_sequence(declared[k].type) for k in parameters)):
            described_ranges[SEQUENCE_LENGTH] = str(ranges.sequence_length)
            range_sources[SEQUENCE_LENGTH] = str(ROBOTOOL_LSEQ)
        return Setup(ranges, constants, described_ranges, described, range_sources, sources, parameters,
                     self.reading, {f.name: f.value for f in filled}, {f.name: f.source for f in filled})

    def _supplied_sequence(self, element: Checked) -> bool:
        """Whether the environment may supply `element` a sequence (`supplied_sequence`), once per element."""
        if id(element) not in self._sequences:
            self._sequences[id(element)] = (element, supplied_sequence(element))
        return self._sequences[id(element)][1]

    def _filled_for(self, element: Checked) -> tuple[Filled, ...]:
        """What the reading filled in that `element` reaches (once per element: a walk of its parts)."""
        if id(element) not in self._reached:
            filled = reached(self.filled, element)
            if isinstance(element, ast.Behaviour):  # its required variables start anywhere (docs/semantics.md §5.5)
                own = (*element.provided_interfaces, *element.used_interfaces)
                filled = tuple(f for f in filled if not (isinstance(f.target, ast.Variable)
                                                         and f.target.kind == "interface"
                                                         and not ast.in_interfaces(f.target, own)))
            # A required variable that a variable of the element declares (a controller's, the
            # platform's, the calling machine's for an operation) starts at that one's value.
            declared = {v.name for v in ast.parts(element) if isinstance(v, ast.Variable) and v.kind == "local"
                        and not v.constant}
            filled = tuple(f for f in filled if not (isinstance(f.target, ast.Variable) and f.target.kind == "interface"
                                                     and f.target.name in declared))
            self._reached[id(element)] = (element, filled)
        return self._reached[id(element)][1]

    def _per_instance(self, a: ast.Assertion | None, element: Checked, slots: list[_Slot],
                      entries: dict[str, _ConstEntry]) -> dict[tuple[tuple[str, ...], str], _ConstEntry]:
        """Values that one instance of a machine gets and another of the same declaration need not:
        from the instantiation under the instance's own name (`const_test12_ctrl0_stm_ref0_CC`), and
        from `--set ctrl0::stm_ref0::CC=…` and from `with constant CC of ctrl0::stm_ref0`, which name
        the instance, each stronger than the one before.  A value the command line or a `D__`
        argument gives the declaration applies to every instance and wins over the instantiation's;
        one the assertion gives it, over the command line's too."""
        out: dict[tuple[tuple[str, ...], str], _ConstEntry] = {}
        for s in slots:
            key = declaration_key(s.variable)
            if not s.instance or s.variable.initial is not None or _RANK.get(entries[key].source.what, 0) > 2:
                continue
            for n in s.names[:-1]:  # the last is the definition's name, the same for every instance
                found = self._instantiated.get(n)
                if found is not None and ast.assignable(s.variable.type, found[0].type):
                    out[(s.instance, key)] = _ConstEntry(*found)
                    break
        for at, (_name, entry) in self._by_instance_flags(element, slots).items():  # `--set ctrl0::stm_ref0::CC=…`
            key = at[1]
            if not (key in entries and _RANK.get(entries[key].source.what, 0) > _RANK[FLAG_SET.what]):
                out[at] = entry  # unless the assertion sets the declaration (`with constant`, `D__`)
        for setting in a.settings if a is not None else ():
            if setting.kind == "constant":
                for s in _instances_named(setting.element, setting.constant, element, slots):
                    out[(s.instance, declaration_key(s.variable))] = _ConstEntry(
                        setting.value, Source("with constant", _at(setting.pos)))
        return out

    def _one_instance(self, name: str, v: ast.Variable, chain: Chain) -> Chain:
        """`--set` through a path of instances names one machine instance's constant: one without
        a value in the model (which every instance shares), of a machine's (a controller's
        constants are one for every instance of the controller)."""
        if v.initial is not None:
            raise ConfigError(f"{name} names one instance's constant, and {declaration_key(v)} has a value in the "
                              f"model, which every instance shares: name it {declaration_key(v)} to set it",
                              "--set")
        if not isinstance(chain[-1][0], (ast.StateMachine, ast.OperationDef)):
            raise ConfigError(f"{name} names an instance of {getattr(chain[-1][0], 'qname', '?')}, whose constants are "
                              f"one for every instance: name it {declaration_key(v)}", "--set")
        return chain

    def _by_instance_flags(self, element: Checked, slots: list[_Slot]
                           ) -> dict[tuple[tuple[str, ...], str], tuple[str, _ConstEntry]]:
        """The values `--set` gives instances' constants in `element`, by (instance, declaration
        key). Two names of one instance with two values are a usage error."""
        out: dict[tuple[tuple[str, ...], str], tuple[str, _ConstEntry]] = {}
        for s in slots:
            if not s.instance or s.variable.initial is not None:
                continue
            key = declaration_key(s.variable)
            chain = instance_chain(element, s.instance)
            for name, (flag, fkey, entry) in self._instance_flags.items():
                if fkey != key or chain is None or not _same_instance(flag, chain):
                    continue
                at = (s.instance, key)
                if at in out and _text(out[at][1]) != _text(entry):
                    raise ConfigError(f"{out[at][0]} and {name} give one instance's constant two values", "--set")
                out[at] = (name, entry)
        return out

    def _instance_flags_alone(self, element: Checked, slots: list[_Slot], entries: dict[str, _ConstEntry]) -> None:
        """`--set ctrl0::stm_ref0::CC=…` where the element checked holds the declaration itself,
        not through instances (the machine checked on its own, or a constant the machine requires
        and its controller provides): the instance's value is the declaration's there, unless two
        instances' values differ (then neither is)."""
        found: dict[str, list[_ConstEntry]] = {}
        for s in slots:
            key = declaration_key(s.variable)
            if s.instance or key in found:
                continue
            for flag, fkey, entry in self._instance_flags.values():
                if fkey == key and any(f is element for f, _rest in flag):
                    found.setdefault(key, []).append(entry)
        for key, given in found.items():
            if len({_text(g) for g in given}) == 1:
                entries[key] = given[0]

    @staticmethod
    def _bind_required(slots: list[_Slot], declared: dict[str, ast.Variable], entries: dict[str, _ConstEntry]) -> None:
        """A constant an operation requires (through an interface) is its caller's constant of that
        name: it takes that constant's value, unless it was given one more directly."""
        for key in dict.fromkeys(declaration_key(s.variable) for s in slots if s.in_operation):
            v = declared[key]
            if v.kind != "interface":
                continue
            providers = [k for k, w in declared.items()
                         if w.name == v.name and w.kind != "interface" and ast.assignable(v.type, w.type)]
            if len(providers) != 1:
                continue
            provider = entries[providers[0]]
            if _RANK.get(provider.source.what, 0) >= _RANK.get(entries[key].source.what, 0):
                entries[key] = _ConstEntry(provider.value, Source(f"as {providers[0]}:", str(provider.source)))

    def _from_instantiation(self, slots: list[_Slot]) -> dict[str, tuple[ast.Expr, Source]]:
        """The instantiation's value for each constant without one in the model: the first of
        RoboTool's names for it that the instantiation defines (an instance's before the
        definition's; the first instance's when two instances share the declaration, each of which
        may have its own value too: `_per_instance`)."""
        out: dict[str, tuple[ast.Expr, Source]] = {}
        for s in slots:
            key = declaration_key(s.variable)
            if s.variable.initial is not None or key in out:
                continue
            for n in s.names:
                found = self._instantiated.get(n)
                if found is not None and ast.assignable(s.variable.type, found[0].type):
                    out[key] = found
                    break
        return out

    def _parameter(self, v: ast.Variable) -> str:
        r = self.ranges()
        t = v.type
        name = {"int": "core_int", "nat": "core_nat", "real": "core_real"}.get(t.name, t.name)
        bound = r.by_path.get(declaration_key(v)) or r.by_type.get(name)
        return f"parameter ({bound if bound is not None else 'unbounded'})"

    def _with_constant(self, s: ast.ConstantSetting, declared: dict[str, ast.Variable]) -> list[str]:
        found = [declaration_key(v) for e in self.names.elements.get(s.element, [])
                 for v in constants_of(self.project, e) if v.name == s.constant]
        keys = [k for k in found if k in declared]
        return keys or [k for k, v in declared.items() if v.name == s.constant]

    # --- the instantiation

    def _read_instantiation(self, project: ast.Project) -> ast.Project:
        slots, functions, types = _instantiable(project)
        helpers: set[str] = set()  # named by a definition read, in the file or a block: read wherever defined

        def wanted(name: str) -> bool:  # a definition of anything else is not parsed (`inst.read`)
            return name in CORE_TYPES or name in types or name in slots or name in functions or name in helpers

        while True:
            read, warnings = self._instantiations(project, wanted)
            named = {n for i in read for d in i.definitions if not d.skipped for n in inst.names_in(d.body)}
            if not {d.name for i in read for d in i.definitions if d.skipped} & (named - helpers):
                break
            helpers |= named
        self.warnings += warnings
        clauses: dict[str, list[inst.Definition]] = {}
        for i in read:
            self.warnings += i.problems
            own: dict[str, list[inst.Definition]] = defaultdict(list)
            for d in i.definitions:
                own[d.name].append(d)
            for name, ds in own.items():
                if name in clauses:
                    first = clauses[name][0]
                    self.warnings.append(Diagnostic(ds[0].pos, f"'{name}' is also defined at {_at(first.pos)}; "
                                                    "this definition is the one used", "warning"))
                clauses[name] = ds
        return self._interpret(project, clauses)

    def _instantiations(self, project: ast.Project, wanted: Callable[[str], bool]
                        ) -> tuple[list[inst.Instantiation], list[Diagnostic]]:
        """The project's instantiation file and `Instantiations` blocks, read (`inst.read`), with the
        warnings of a file that cannot be read."""
        read: list[inst.Instantiation] = []
        warnings: list[Diagnostic] = []
        path = inst.project_file(project.root)
        if path is not None:
            try:
                found, text = inst.read_file(path, wanted)
            except OSError as exc:
                warnings.append(Diagnostic(ast.Pos(str(path), 1, 1), f"cannot read: {exc}", "warning"))
            else:
                read.append(found)
                self.texts[str(path)] = text
        read += [inst.read_block(b, wanted) for b in project.csp_blocks if inst.is_instantiation_block(b)]
        return read, warnings

    def _interpret(self, project: ast.Project, clauses: dict[str, list[inst.Definition]]) -> ast.Project:
        slots_by_name, functions, types = _instantiable(project)
        enums = [t for t in project.types if isinstance(t, ast.EnumType)]
        records = [t for t in project.types if isinstance(t, ast.RecordType)]
        referenced = _referenced(clauses)
        helpers = {n: ds for n, ds in clauses.items() if n not in functions}
        body = inst.FunctionBody(functions, helpers, enums, records)
        defined: dict[int, ast.Function] = {}
        named = {n: ds[-1] for n, ds in clauses.items()}
        for name, ds in clauses.items():
            d = ds[-1]
            try:
                if d.nametype:
                    self._nametype(name, d, types, named)
                elif name in slots_by_name:
                    self._constant(name, d, slots_by_name[name])
                elif name in functions:
                    f = functions[name]
                    if f.definition is not None:
                        self._warn(d.pos, f"the model defines {f.name} (postcondition result == …); this body "
                                          "is not used")
                    else:
                        defined[id(f)] = body.define(f, ds)
                        self._written.add(f.qname)
                elif name.startswith("const_"):
                    self._warn(d.pos, f"no constant of the model is named '{name}' by RoboTool, so it is not "
                                      f"used{suggestion(name, list(slots_by_name))}")
                elif name in _ROBOTOOL_HELPERS or name.endswith("_BOUND") or name in referenced:
                    continue
                else:
                    known = [*functions, *types, *CORE_TYPES]
                    self._warn(d.pos, f"'{name}' is not a constant, type or function of the model, so it is "
                                      f"not used{suggestion(name, known)}")
            except inst.NotUnderstood as exc:
                if name in functions:
                    self._unread[functions[name].qname] = exc.pos
                    self._warn(exc.pos, f"unsupported: {exc.what}; function {functions[name].name} stays "
                                        "uninterpreted (docs/semantics.md §6.4)")
                else:
                    self._warn(exc.pos, f"unsupported: {exc.what}; '{name}' is not used")
        return inst.with_functions(project, defined)

    def _warn(self, pos: ast.Pos, message: str) -> None:
        self.warnings.append(Diagnostic(pos, message, "warning"))

    def _nametype(self, name: str, d: inst.Definition, types: dict[str, ast.Type],
                  named: Mapping[str, inst.Definition]) -> None:
        if name in _IGNORED_TYPES:
            return
        t = CORE_TYPES.get(name) or types.get(name)
        if t is None:
            self._warn(d.pos, f"no type '{name}' in the model{suggestion(name, [*CORE_TYPES, *types])}; "
                              "this range is not used")
            return
        if not (t in ast.NUMERIC or isinstance(t, ast.GivenType)):
            raise inst.NotUnderstood(d.pos, f"'{name}' is not a numeric type or a type declared with 'type'")
        low, high = inst.interval(d, d.body, named)
        key = name if name in CORE_TYPES else t.name
        r = Range(low, high)
        try:
            check_range(name, t, r)
        except ConfigError as exc:
            raise inst.NotUnderstood(d.at(d.body), str(exc)) from None
        self._ranges[key] = _RangeEntry(r, Source("instantiation", _at(d.pos)))

    def _constant(self, name: str, d: inst.Definition, variables: list[ast.Variable]) -> None:
        if d.params is not None:
            raise inst.NotUnderstood(d.pos, f"'{name}' is a constant; it takes no arguments")
        given = [v for v in variables if v.initial is not None]
        if given and len(given) == len(variables):
            v = given[0]
            self._warn(d.pos, f"the model gives {declaration_key(v)} the value it has "
                              f"({_at(v.initial.pos) if v.initial is not None else ''}); '{name}' is not used")
            return
        values = []
        for t in dict.fromkeys(v.type for v in variables):
            values.append(inst.value(d, d.body, t))
        self._instantiated[name] = (values[0], Source("instantiation", _at(d.pos)))


def _range_items(ranges: Ranges | Mapping[str, Range | None] | None) -> list[tuple[str, Range | None]]:
    if ranges is None:
        return []
    if isinstance(ranges, Ranges):
        return [*ranges.by_type.items(), *ranges.by_path.items()]
    return list(ranges.items())


def _referenced(clauses: dict[str, list[inst.Definition]]) -> set[str]:
    """Names used in the bodies of the definitions (helpers such as `abs` are used this way)."""
    return {n for ds in clauses.values() for d in ds for part in (d.body, *(d.params or ())) for n in inst.names_in(part)}


def _instantiable(project: ast.Project) -> tuple[dict[str, list[ast.Variable]], dict[str, ast.Function],
                                                 dict[str, ast.Type]]:
    """What an instantiation can give a value, by the name RoboTool gives it there: the constants
    (each name's variables), the functions and the types."""
    slots_by_name: dict[str, list[ast.Variable]] = defaultdict(list)
    elements: list[Checked] = [*project.machines, *project.operations, *project.controllers, *project.modules]
    for e in elements:
        for s in robotool_slots(project, e):
            for n in s.names:
                if not any(v is s.variable for v in slots_by_name[n]):
                    slots_by_name[n].append(s.variable)
    functions: dict[str, ast.Function] = {}
    for f in project.functions:
        functions.setdefault(inst.mangle(f.qname), f)
    types: dict[str, ast.Type] = {}
    for t in project.types:
        if isinstance(t, (ast.GivenType, ast.EnumType, ast.RecordType)):
            types.setdefault(inst.mangle(t.qname), t)
            types.setdefault(t.name, t)
    return slots_by_name, functions, types


def configure(project: ast.Project, ranges: Ranges | Mapping[str, Range | None] | None = None,
              settings: Mapping[str, ast.Expr | str] | None = None, params: Iterable[str] = (),
              default_ranges: Ranges | None = None, instantiation: bool = True,
              open_defaults: bool | None = None, reading: Reading = Reading.DEFAULT) -> Configuration:
    """The configuration of a project's checks (see `Configuration`)."""
    return Configuration(project, ranges, settings, params, default_ranges, instantiation, open_defaults, reading)

