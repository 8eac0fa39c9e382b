"""Replay: the independent interpreter follows a counterexample that BMC found.

The interpreter starts from the values the trace starts from (constants and
variables the model leaves open) and must perform the trace's visible steps,
events and tocks, in order, with any internal steps between them (the two
engines cut internal work into steps differently), and end in a configuration
where the claimed condition holds (terminated, refusing tock, in the state…).
If it cannot, `ReplayFailure` says where, with both views: that is a bug in
tockbmc, never a user error.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Hashable, Iterator, Mapping

from tockbmc.explicit.interpreter import Config, Interpreter, Step
from tockbmc.model.result import TraceStep
from tockbmc.properties.process import Context

LIMIT = 200_000  # configurations explored before replay gives up (reported as a failure to follow)


class ReplayFailure(Exception):
    """The interpreter cannot follow a BMC trace: at which step, and what each engine does there."""

    def __init__(self, step: int, bmc: str, interpreter: str):
        super().__init__(f"the interpreter cannot follow BMC's trace at step {step}: BMC does {bmc}; "
                         f"the interpreter can do {interpreter}")
        self.step, self.bmc, self.interpreter = step, bmc, interpreter

    def __reduce__(self) -> tuple[type[ReplayFailure], tuple[int, str, str]]:
        """Rebuilt from its parts (a worker process of `check -j` raises it in the parent)."""
        return type(self), (self.step, self.bmc, self.interpreter)


class ReplayGaveUp(ReplayFailure):
    """The interpreter did not follow a BMC trace within `LIMIT` configurations: not a disagreement
    of the engines, but no confirmation either (the check reports the trace as not replayed)."""


class _Inputs(Mapping[tuple, tuple]):
    """The values to offer on input channels: the trace's next event's, and none on any other."""

    def __init__(self, channel: tuple | None, given: tuple):
        self.channel, self.given = channel, given

    def __getitem__(self, channel: tuple) -> tuple:
        if channel == self.channel:
            return self.given
        raise KeyError(channel)

    def __iter__(self) -> Iterator[tuple]:
        return iter([self.channel] if self.channel is not None else [])

    def __len__(self) -> int:
        return 1 if self.channel is not None else 0


def replay(interp: Interpreter, trace: tuple[TraceStep, ...], choices: dict[str, object],
           context: Context | None, final: Callable[[Config, list[Step]], bool]) -> None:
    """Follow `trace` (its visible steps) with the interpreter, or raise `ReplayFailure`."""
    replay_watched(interp, trace, choices, context, None, lambda w, config, steps, s: None,
                   lambda config, steps, w: final(config, steps))


Watch = Callable[[Hashable, Config, list[Step], Step], Hashable]  # (watched, configuration, its steps, step) -> next


def replay_watched(interp: Interpreter, trace: tuple[TraceStep, ...], choices: dict[str, object],
                   context: Context | None, start: Hashable, watch: Watch,
                   final: Callable[[Config, list[Step], Hashable], bool]) -> None:
    """`replay`, carrying a value along each run (`watch` gives it after each visible step, from
    the configuration the step leaves and every step it offers): the tick-tock model's monitor,
    whose tocks depend on what the configuration refuses.  `final` reads the value at the end."""
    visible = [s for s in trace if s.kind in ("event", "tock") and s.note not in _OUTSIDE]
    seen: set[Hashable] = set()
    todo: deque[tuple[Config, int, Hashable]] = deque()
    for c in interp.initial(choices):
        if (c, 0, start) not in seen:
            seen.add((c, 0, start))
            todo.append((c, 0, start))
    best, offered, gave_up = 0, set[str](), False
    while todo:
        config, i, watched = todo.popleft()
        expected = visible[i] if i < len(visible) else None
        inputs = _Inputs(expected.channel if expected is not None and expected.kind == "event" else None,
                         expected.values if expected is not None else ())
        steps = interp.steps(config, inputs)
        statuses = [_status(context, s) for s in steps]
        hidden_possible = any(st == "hidden" and s.kind == "event" for s, st in zip(steps, statuses, strict=True))
        allowed = [s for s, st in zip(steps, statuses, strict=True)
                   if st != "blocked" and not (s.kind == "tock" and hidden_possible)]
        if expected is None and final(config, allowed, watched):
            return
        if i > best:
            best, offered = i, set()
        for s, st in zip(steps, statuses, strict=True):
            if s not in allowed:
                continue
            if s.kind == "internal" or st == "hidden":
                nxt = (s.target, i, watched)
            elif expected is not None and s.kind == expected.kind and (
                    s.kind == "tock" or (s.event is not None and s.event.name == expected.event)):
                nxt = (s.target, i + 1, watch(watched, config, allowed, s))
            else:
                if i == best:
                    offered.add("tock" if s.kind == "tock" else s.event.name if s.event else "?")
                continue
            if nxt not in seen:
                if len(seen) >= LIMIT:
                    gave_up = True
                    break
                seen.add(nxt)
                todo.append(nxt)
    short = f" (the replay gave up after {LIMIT:,} configurations)" if gave_up else ""
    failure = ReplayGaveUp if gave_up else ReplayFailure
    if best < len(visible):
        step = visible[best]
        raise failure(step.step, f"{step.event}", (", ".join(sorted(offered)[:8]) or "nothing") + short)
    raise failure(visible[-1].step if visible else 0, "the end of its trace, where the assertion fails",
                  "every step of the trace, but the assertion does not fail where it ends" + short)


_OUTSIDE = ("before the model starts", "after the model terminates")


def can_diverge(interp: Interpreter, config: Config, context: Context | None = None) -> bool:
    """Whether internal steps alone (hidden events included) lead from `config` into a cycle: the
    end of a divergence BMC shows as a lasso (the engines cut internal work into steps
    differently, so the cycle is looked for afresh, not matched step by step).  Raises
    `ReplayGaveUp` when no cycle is found among the first `LIMIT` configurations."""
    def internal(c: Config) -> list[Config]:
        return [s.target for s in interp.steps(c)
                if s.kind == "internal" or (s.kind == "event" and _status(context, s) == "hidden")]

    # Depth-first, with the configurations on the current path ("grey") told from finished ones.
    on_path, done = {config}, set[Config]()
    stack = [(config, iter(internal(config)))]
    while stack:
        c, nexts = stack[-1]
        nxt = next(nexts, None)
        if nxt is None:
            stack.pop()
            on_path.discard(c)
            done.add(c)
        elif nxt in on_path:
            return True
        elif nxt not in done:
            if len(done) + len(on_path) >= LIMIT:
                raise ReplayGaveUp(0, "a divergence", f"no cycle of internal steps among {LIMIT:,} configurations")
            on_path.add(nxt)
            stack.append((nxt, iter(internal(nxt))))
    return False


def _status(context: Context | None, s: Step) -> str:
    if context is None or s.event is None:
        return "visible"
    return context.status(s.event.channel, len(s.event.values))
