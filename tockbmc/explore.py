"""`explore`: which ranges, constants and inputs break each assertion (the API behind `tockbmc explore`).

A check answers at one point: these ranges, these constants.  Exploration makes the bounds of
ranges and the constants without a value parameters (symbols every step shares,
`encodings.values.range_bounds`) and computes, for each assertion, the exact set of parameter
values for which a run violates it (`bmc.regions.region`: find, generalise by model-based
projection, block, until BMC, k-induction or PDR shows nothing is left outside).  The region is
printed in the model's names, with the parameters it does not depend on, one counterexample
replayed by the interpreter at a point inside it, and, for each input event of a shortest
counterexample, the values of its fields that such a counterexample can carry.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction

import z3

from tockbmc.bmc.engine import SPENT
from tockbmc.bmc.regions import Region, Witness, carried, condition_text, region, simplified
from tockbmc.bmc.witness import decode, initial_choices, python_value, scalar_text
from tockbmc.check import DEFAULT_BOUND, own_z3_context, replay_trace
from tockbmc.encodings.composition import Network, network_of
from tockbmc.encodings.system import TransitionSystem, check_encodable
from tockbmc.encodings.terms import constants, quantified
from tockbmc.encodings.values import leaves
from tockbmc.model import ast
from tockbmc.model.config import ConfigError, Configuration, Names, Setup, configure
from tockbmc.model.errors import Unsupported
from tockbmc.model.exploration import Carried, Exploration
from tockbmc.model.ranges import Range, Ranges, is_path
from tockbmc.model.readings import Reading
from tockbmc.model.result import Verdict
from tockbmc.properties.goals import Goal, Query
from tockbmc.properties.queries import query

CORE_RANGES = ("core_int", "core_nat", "core_real")


@dataclass(frozen=True)
class Plan:
    """What an exploration varies: the configuration (constants made parameters in it) and the
    ranges whose bounds are parameters."""

    config: Configuration
    ranges: tuple[str, ...]


def plan(project: ast.Project, ranges: Mapping[str, Range | None] | None = None,
         settings: Mapping[str, ast.Expr | str] | None = None, params: Sequence[str] = ()) -> Plan:
    """Resolve what varies.  Each of `params` is a constant (made a parameter) or a range: `core_int`,
    a type, or a path (its bounds made parameters).  With none, every core range the command line
    does not fix and every constant left without a value are parameters.  Raises `ConfigError`."""
    names = Names(project)
    constants: list[str] = []
    bounded: list[str] = []
    for p in params:
        try:
            names.constant(p, "--param")
            constants.append(p)
        except ConfigError as as_constant:
            try:
                key, _t = names.range_type(p)
            except ConfigError as as_range:
                raise ConfigError(f"'{p}' is neither a constant nor a range: {as_constant}; {as_range}",
                                  "--param") from None
            bounded.append(key)
    if not params:
        bounded = [r for r in CORE_RANGES if r not in (ranges or {})]
    config = configure(project, ranges, settings, constants, open_defaults=not params, reading=Reading.OPEN)
    return Plan(config, tuple(bounded))


def explore(project: ast.Project, names: Iterable[str] | None = None, bound: int = DEFAULT_BOUND,
            ranges: Mapping[str, Range | None] | None = None, settings: Mapping[str, ast.Expr | str] | None = None,
            params: Sequence[str] = (), timeout: float | None = None) -> Iterator[Exploration]:
    """One `Exploration` per selected assertion (all by default), in file order, each as it is found."""
    p = plan(project, ranges, settings, params)
    wanted = set(names) if names is not None else None
    for a in p.config.project.assertions:
        if wanted is None or any(a.selected_by(n) for n in wanted):
            with own_z3_context():
                yield _Explore(a, bound, p, timeout).run()


class _Explore:
    """The exploration of one assertion."""

    def __init__(self, a: ast.Assertion, bound: int, p: Plan, timeout: float | None):
        self.a, self.bound, self.plan, self.timeout = a, bound, p, timeout
        self.start = time.perf_counter()

    def left(self) -> float | None:
        return None if self.timeout is None else max(SPENT, self.timeout - (time.perf_counter() - self.start))

    def out(self, status: str, **fields: object) -> Exploration:
        return Exploration(assertion=self.a.label, text=self.a.text, pos=str(self.a.pos), status=status,
                           bound=self.bound, seconds=time.perf_counter() - self.start, **fields)  # type: ignore[arg-type]

    def run(self) -> Exploration:
        try:
            q = query(self.plan.config.project, self.a)
            if q.spec_element is not None:
                raise Unsupported(self.a.pos, "explore's ranges are parameters, and a model element on the "
                                  "specification's side is listed by the interpreter within fixed ranges")
            if q.determinism or q.inclusion is not None:
                what = "determinism" if q.determinism else "a specification's traces on the model's right"
                raise Unsupported(self.a.pos, f"explore decides assertions whose violation is one run to a "
                                  f"configuration; {what} needs two runs or trace listing")
            kinds = {g.found for g in q.goals}
            if len(kinds) > 1 or (kinds == {Verdict.HOLDS} and len(q.goals) > 1):
                raise Unsupported(self.a.pos, "explore decides assertions that one kind of run decides; this one "
                                  "needs a witness and the absence of a violation together")
            free = ast.free_functions(q.element, q.defined)
            if free:
                raise Unsupported(self.a.pos, "explore's regions are sets of values of the parameters; this model "
                                  f"calls functions without a body ({', '.join(f.qname for f in free)}), whose "
                                  "results a region would have to name")
            setup = self.plan.config.setup(self.a, q.element, q.settings)
            network = network_of(q.element, dict(q.defined), timed=q.timed)
            check_encodable(network)
            return self.regions(q, setup, network)
        except Unsupported as exc:
            return self.out("unsupported", reason=exc.reason)
        except RecursionError:
            return self.out("unsupported", reason="the model is nested too deeply to check")

    def system(self, q: Query, goal: Goal, setup: Setup, network: Network) -> Callable[[Sequence[z3.BoolRef]], TransitionSystem]:
        ranges = replace(setup.ranges, parametric=self.plan.ranges)

        def build(outside: Sequence[z3.BoolRef]) -> TransitionSystem:
            s = TransitionSystem(network, ranges, setup.constants, context=q.context)
            s.constraints += outside
            if goal.prepare is not None:
                goal.prepare(s)
            return s

        return build

    def regions(self, q: Query, setup: Setup, network: Network) -> Exploration:
        witness = q.goals[0].found == Verdict.HOLDS if q.goals else False
        found: list[tuple[Goal, Region]] = []
        params: dict[str, z3.ExprRef] = {}  # symbol name -> symbol
        display: dict[str, str] = {}
        assume: list[z3.BoolRef] = []
        builds = []
        for goal in q.goals:
            build = self.system(q, goal, setup, network)
            probe = build([])
            if quantified(probe.init()) or quantified(probe.trans()):
                raise Unsupported(self.a.pos, "explore projects runs onto the parameters without quantifiers; this "
                                  "model's formulas quantify (a sequence's or set's elements, forall/exists)")
            if not goal.applies(probe):  # unreachable whatever the data (abstraction)
                continue
            named, facts = _parameters(probe, self.plan.ranges)
            for name, (symbol, shown) in named.items():
                if name not in params:
                    params[name], display[name] = symbol, shown
            assume += [f for f in facts if not any(f.eq(g) for g in assume)]
            builds.append((goal, build, probe))
        cubes: list[z3.BoolRef] = []
        for goal, build, probe in builds:
            why_not = goal.unprovable(probe) if goal.unprovable is not None else None
            r = region(build, goal.target, self.bound, list(params.values()),
                       [*assume, *(z3.Not(c) for c in cubes)], self.left(),
                       induction=goal.stateless and why_not is None)
            found.append((goal, r))
            cubes += r.cubes
        pieces = simplified(cubes, assume)
        integers = {n for n, s in params.items() if s.sort() == z3.IntSort()}
        condition = condition_text(pieces, display, integers)
        mentioned = {v.decl().name() for c in pieces for v in constants(*c)}
        complete = all(r.complete for _, r in found)
        reasons = [r.reason for _, r in found if r.reason]
        proved = [r.proof for _, r in found if r.proof]
        reach = ("every length" if complete and len(proved) == len(found) else "bound" if complete else "partial")
        if complete and condition == "true":  # nothing is outside
            reach, proved = "every length", [f"every point has a {'witness' if witness else 'counterexample'}"]
        elif witness and reach == "bound":
            # No witness within the bound decides nothing (`Goal.witness`: unknown), so outside the
            # region nothing is known, as when the search is cut short.
            reach, complete = "partial", False
            reasons.append(f"no witness within {self.bound} steps decides nothing")
        fields: dict[str, object] = dict(
            parameters=tuple(display[n] for n in params), fixed=self.fixed(setup),
            fixed_here={k: v for k, v in self.fixed(setup).items()
                        if setup.constant_sources.get(k, "").startswith(("D__ argument", "with constant"))},
            assumed=tuple(condition_text([[f]], display, integers) for f in assume),
            inside="holds" if witness else "violated", condition=condition,
            independent=tuple(display[n] for n in params if n not in mentioned), reach=reach,
            proof="; ".join(proved), reason="; ".join(reasons))
        witnesses = [(goal, w) for goal, r in found for w in r.witnesses]
        if witnesses:
            goal, w = min(witnesses, key=lambda gw: gw[1].depth)
            fields.update(self.example(q, goal, w, setup, params, display))
            fields["carried"] = self.inputs(goal, w, setup, network, q, [*assume, z3.Or(cubes)])
        return self.out("region" if complete else "unknown", **fields)

    def fixed(self, setup: Setup) -> dict[str, str]:
        """The ranges and constants that do not vary, with their values."""
        out = {k: v for k, v in setup.described_ranges.items() if k not in self.plan.ranges}
        out.update({k: v for k, v in setup.described_constants.items() if not v.startswith("parameter")})
        return out

    def example(self, q: Query, goal: Goal, w: Witness, setup: Setup, params: dict[str, z3.ExprRef],
                display: dict[str, str]) -> dict[str, object]:
        """A counterexample at a point of the region, decoded and replayed at that point's ranges."""
        u, model = w.unroller, w.model
        trace = decode(u, model, w.depth)
        point = {display[n]: scalar_text(s, model, ast.REAL if s.sort() == z3.RealSort() else ast.INT)
                 for n, s in params.items()}
        by_type, by_path = dict(setup.ranges.by_type), dict(setup.ranges.by_path)
        for name in self.plan.ranges:
            low, high = params.get(f"range[{name}].low"), params.get(f"range[{name}].high")
            if low is not None and high is not None:  # a range the formulas use: its bounds at this point
                t = ast.REAL if low.sort() == z3.RealSort() else ast.INT
                lo, hi = python_value(low, model, t), python_value(high, model, t)
                assert isinstance(lo, (int, Fraction)) and isinstance(hi, (int, Fraction))
                (by_path if is_path(name) else by_type)[name] = Range(Fraction(lo), Fraction(hi))
        replayed = replay_trace(q, self.a, goal, trace, initial_choices(u, model), Ranges(by_type, by_path),
                                setup.constants)
        return {"depth": w.depth, "point": point, "trace": trace, "replayed": replayed}

    def inputs(self, goal: Goal, w: Witness, setup: Setup, network: Network, q: Query,
               inside: list[z3.BoolRef]) -> tuple[Carried, ...]:
        """For each input event of the example, the values of each field a run of as many steps
        (inside the region) can carry where it takes that event."""
        system = self.system(q, goal, setup, network)([])
        u, model = w.unroller, w.model
        taken = [system.moves[model.eval(u.action(i), model_completion=True).as_long()] for i in range(w.depth)]
        out: list[Carried] = []
        seen: set[tuple] = set()
        for m in taken:
            if not system.effect(m).chosen or m.kind in ("tock", "internal"):
                continue
            channel, _ = system.label(m)
            if channel in seen:
                continue
            seen.add(channel)
            moves = [x for x in system.moves if x.kind not in ("tock", "internal") and system.label(x)[0] == channel
                     and system.effect(x).chosen]
            event = ".".join(str(c) for c in channel)
            for path, field_type, templates in _fields(system, moves):
                def choices(unroller, i, templates=templates):  # type: ignore[no-untyped-def]
                    return [(unroller.action(i) == x.index, unroller.at(t, i)) for x, t in templates]

                r = carried(system, goal.target, w.depth, choices, inside, self.left())
                name = path or "value"
                ints = {"value"} if field_type in (ast.INT, ast.NAT) else set()
                text = condition_text(simplified(r.cubes, []), {"value": name}, ints)
                if r.complete and _any(system, templates, r, inside):
                    text = "any"
                out.append(Carried(event, path, text if path == "" or text == "any" else text, r.complete))
        return tuple(out)


def _fields(system: TransitionSystem, moves: list) -> list[tuple[str, ast.Type, list[tuple[object, z3.ExprRef]]]]:
    """Each field (leaf) of the value the moves carry: its path, type, and each move's term for it."""
    by_path: dict[str, tuple[ast.Type, list]] = {}
    for m in moves:
        for value, t in system.label_values(m):
            for path, term in leaves(value):
                leaf = _leaf_type(t, path)
                by_path.setdefault(path.lstrip("."), (leaf, []))[1].append((m, term))
    return [(p, t, ts) for p, (t, ts) in by_path.items()]


def _leaf_type(t: ast.Type, path: str) -> ast.Type:
    for name in [x for x in path.split(".") if x]:
        assert isinstance(t, ast.RecordType)
        ft = t.field_type(name)
        assert ft is not None
        t = ft
    return t


def _any(system: TransitionSystem, templates: list, r: Region, inside: list[z3.BoolRef]) -> bool:
    """Whether the region allows every value the field's type and range allow (inside the region)."""
    solver = z3.Solver()
    solver.set("timeout", 5000)
    for m, term in templates:
        v = z3.Const("value", term.sort())
        region_here = z3.substitute(r.formula(), (v, term))
        solver.push()
        solver.add(*inside, *system.effect(m).choose, z3.Not(region_here))
        result = solver.check()
        solver.pop()
        if result != z3.unsat:
            return False
    return True


def _parameters(system: TransitionSystem, ranges: Sequence[str]) -> tuple[dict[str, tuple[z3.ExprRef, str]], list[z3.BoolRef]]:
    """The parameters a system's formulas name, by symbol name with the name to print: the bounds
    of the parametric ranges and the constants without a value; and what every point satisfies
    (a low bound at most its high one, naturals not negative, a constant in its type and range)."""
    used = {v.decl().name(): v for v in constants(system.init(), system.trans())}
    out: dict[str, tuple[z3.ExprRef, str]] = {}
    facts: list[z3.BoolRef] = []
    for name in ranges:
        low, high = used.get(f"range[{name}].low"), used.get(f"range[{name}].high")
        if low is None or high is None:
            continue
        facts.append(low <= high)  # type: ignore[arg-type, operator]
        if name == "core_nat":
            facts.append(low >= 0)  # type: ignore[arg-type, operator]
        out[f"range[{name}].low"] = (low, f"{name}.low")
        out[f"range[{name}].high"] = (high, f"{name}.high")
    for key, value in system.open_constants.items():
        for path, term in leaves(value):
            out[term.decl().name()] = (term, f"{key}{path}")
    facts += [c for c in system.constraints if all(v.decl().name() in out for v in constants(c))]
    return out, facts
