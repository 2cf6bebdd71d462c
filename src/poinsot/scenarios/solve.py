"""Solving a scenario: overrides, the cost estimate and its limits, the run itself.

:func:`simulate_scenario` applies the overrides (``--duration``), estimates the
cost (:func:`estimate_cost`) and refuses a run beyond the limits *before any
work*, then asks the scenario's kind (its adapter, ``docs/adding-a-motion.md``) to
solve it with ``simulation.method`` and, when one is named, with
``simulation.reference`` on the same times. The result is a
:class:`~poinsot.scenarios.summary.ScenarioResult`; no file is written here.

Limits (documented in ``docs/cli.md``): at most :data:`MAX_SAMPLES` output samples
(always), and by default at most :data:`MAX_MEMORY_BYTES` of estimated memory and
:data:`MAX_STEPS` integration steps (``allow_large=True``, the command's
``--allow-large``, lifts these two).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .._jit import compile_seconds
from ..errors import InvalidInputError, InvalidTypeError
from ..integrators import INTEGRATORS
from ..rotations.rotation import Rotation
from ..trajectory import PER_SAMPLE_INFO, Trajectory
from .facts import Progress
from .schema import MAX_SAMPLES, Scenario
from .summary import ScenarioResult

if TYPE_CHECKING:
    from .summary import ScenarioResult

__all__ = [
    "simulate_scenario",
    "estimate_cost",
    "Cost",
    "MAX_SAMPLES",
    "MAX_MEMORY_BYTES",
    "MAX_STEPS",
    "chunked",
    "quiet_progress",
    "span",
]

#: Default limit of the estimated memory of a run (bytes): 2 GiB.
MAX_MEMORY_BYTES = 2 * 1024**3
#: Default limit of the number of integration steps (all methods of a run together).
MAX_STEPS = 50_000_000

#: Bytes held per output sample of one trajectory while a run is summarised and
#: written (t, quaternion, omega, K, T, V, their derived series and the rows being
#: formatted), measured with tracemalloc on the shipped examples and rounded up.
_BYTES_PER_SAMPLE = 600
#: Rough cost of one integration step or closed-form sample (seconds) when a kind
#: gives none for a method (:attr:`ScenarioKind.seconds_per_step`).
_DEFAULT_SECONDS_PER_STEP = 1e-4
_DEFAULT_SECONDS_PER_RUN = 2e-3
#: Above this many output samples a run is done in chunks (progress reports).
_CHUNK_SAMPLES = 1000
_N_CHUNKS = 40


def quiet_progress(fraction: float, stage: str) -> None:
    """A progress callback that does nothing."""


def span(progress: Progress, lo: float, hi: float) -> Progress:
    """Map the fractions ``[0, 1]`` of one stage onto ``[lo, hi]`` of the whole run."""
    return lambda fraction, stage: progress(lo + (hi - lo) * fraction, stage)


# ----------------------------------------------------------------------------- cost
@dataclass(frozen=True)
class Cost:
    """The estimated cost of a run, computed from the scenario alone.

    Attributes
    ----------
    samples : int
        Output samples (per method).
    steps : int
        Integration steps of every method together (closed forms count one per
        sample; ``"adaptive"`` counts its output samples: its own steps are not
        known in advance).
    memory_bytes : int
        Peak memory, estimated (bytes).
    seconds : float
        Rough wall time (s), from the seconds per step each kind measured
        (:attr:`~poinsot.scenarios.ScenarioKind.seconds_per_step`); a machine may
        differ by 3x either way.
    """

    samples: int
    steps: int
    memory_bytes: int
    seconds: float
    #: seconds of each method (the method, then the reference), solving only
    methods: tuple[tuple[str, float], ...] = ()
    #: seconds to write the outputs (tables, figures, report.html), rough
    outputs_seconds: float = 0.0
    #: seconds numba spent compiling during a measured estimate (first run only)
    compile_seconds: float = 0.0
    #: the methods whose time was measured on a short piece of the run (``measure=True``)
    measured: tuple[str, ...] = ()

    def describe(self) -> str:
        """One line: ``"cost: 3001 samples, 6002 steps, ~2 MB, ~0.02 s"``, and what the
        time is made of when it has more than one part."""
        line = (
            f"cost: {self.samples} samples, {self.steps} integration steps, "
            f"~{_bytes(self.memory_bytes)} memory, ~{_seconds(self.seconds)}"
        )
        parts = [
            f"{m} ~{_seconds(sec)}" + (" (measured on a piece)" if m in self.measured else "")
            for m, sec in self.methods
        ]
        if self.outputs_seconds:
            parts.append(f"outputs ~{_seconds(self.outputs_seconds)}")
        if len(parts) > 1:
            line += " (" + ", ".join(parts) + ")"
        if self.compile_seconds >= 0.5:
            line += f"; compiling took {_seconds(self.compile_seconds)} (first run only)"
        return line

    def problems(self, *, allow_large: bool = False) -> list[str]:
        """What exceeds the limits (empty when the run may go ahead)."""
        out = []
        if self.samples > MAX_SAMPLES:
            out.append(
                f"{self.samples:.3g} output samples exceed the limit of {MAX_SAMPLES} "
                "(use a longer `step`, fewer `samples` or a shorter duration)"
            )
            return out  # a hard limit: the others follow from it
        if allow_large:
            return out
        if self.memory_bytes > MAX_MEMORY_BYTES:
            out.append(
                f"the run needs ~{_bytes(self.memory_bytes)} of memory, more than the limit "
                f"of {_bytes(MAX_MEMORY_BYTES)} (--allow-large to run it anyway)"
            )
        if self.steps > MAX_STEPS:
            out.append(
                f"{self.steps:.3g} integration steps exceed the limit of {MAX_STEPS:.3g} "
                "(a longer `max_step`, or --allow-large to run it anyway)"
            )
        return out


def _bytes(n: float) -> str:
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def _seconds(s: float) -> str:
    if s >= 3600:
        return f"{s / 3600:.3g} h"
    if s >= 60:
        return f"{s / 60:.3g} min"
    return f"{s:.2g} s"


def _steps(scenario: Scenario, method: str, samples: int) -> int:
    sim = scenario.simulation
    if method == "exact":
        return samples
    if method == "adaptive":  # its own steps, at least one per output interval and max_step
        floor = 0 if sim.max_step is None else math.ceil(sim.duration / sim.max_step)
        return max(samples, min(floor, 10**15))
    # fixed-step methods: the fewest equal steps no longer than max_step per interval
    per_interval = 1 if sim.max_step is None else max(1, math.ceil(sim.spacing() / sim.max_step))
    return (samples - 1) * per_interval


def estimate_cost(
    scenario: Scenario,
    *,
    duration: float | None = None,
    measure: bool = False,
    outputs: bool = False,
) -> Cost:
    """Estimate the cost of running ``scenario`` (after the ``duration`` override).

    The time is ``seconds_per_run + seconds_per_step * steps`` of each method (the
    method and the reference), from each kind's table. Nothing is allocated: a
    scenario of ``1e12`` seconds is estimated as fast as one of a second. An adaptive
    method's steps are not known in advance (they follow the motion): with
    ``measure=True`` (``poinsot check``) each adaptive method is run on a short first
    piece of the motion (~2 %, at most ~0.3 s of work) and its time scaled to the
    whole duration; a compilation this triggers (a cold cache) is counted apart
    (:attr:`Cost.compile_seconds`). ``outputs=True`` adds the rough time of writing
    the tables, figures and report of ``poinsot run``.

    Examples
    --------
    >>> from poinsot.scenarios import demo_scenario, estimate_cost
    >>> c = estimate_cost(demo_scenario())
    >>> c.samples, c.steps
    (4001, 24001)
    >>> print(estimate_cost(demo_scenario(), duration=1e12).problems()[0])  # doctest: +ELLIPSIS
    2e+14 output samples exceed the limit of 5000000 ...
    """
    _expect(scenario, Scenario, "scenario", "a Scenario (from load_scenario/parse_scenario)")
    scenario = _override(scenario, duration)
    sim = scenario.simulation
    n = sim.n_samples()
    methods = [sim.method] + ([sim.reference] if sim.reference else [])
    steps = sum(_steps(scenario, m, n) for m in methods)
    per_step = scenario.adapter.seconds_per_step
    per_run = scenario.adapter.seconds_per_run
    each = []
    measured = []
    compiled = 0.0
    for m in methods:
        sec = per_run.get(m, _DEFAULT_SECONDS_PER_RUN) + per_step.get(
            m, _DEFAULT_SECONDS_PER_STEP
        ) * _steps(scenario, m, n)
        if measure and _adaptive(m) and n * len(methods) <= MAX_SAMPLES:
            piece = _measure(scenario, m, sec)
            if piece is not None:
                sec, comp = piece
                compiled += comp
                measured.append(m)
        each.append((m, sec))
    out_s = _outputs_seconds(scenario, n, measure) if outputs else 0.0
    memory = _BYTES_PER_SAMPLE * n * len(methods)
    return Cost(
        samples=n,
        steps=steps,
        memory_bytes=memory,
        seconds=sum(sec for _, sec in each) + out_s,
        methods=tuple(each),
        outputs_seconds=out_s,
        compile_seconds=compiled,
        measured=tuple(measured),
    )


#: Rough seconds to write a run's outputs: a fixed part, each figure (matplotlib draws
#: it as a PNG and again in report.html: most of the time), and per sample the tables;
#: measured on the shipped examples by benchmarks/bench_estimates.py.
_OUTPUT_SECONDS = 0.2
_SECONDS_PER_FIGURE = 0.6
_OUTPUT_SECONDS_PER_SAMPLE = 2e-5
_TYPICAL_FIGURES = 4


def _outputs_seconds(scenario: Scenario, samples: int, measure: bool) -> float:
    figures = _TYPICAL_FIGURES
    if measure:  # the figures this kind draws for this scenario, from a run of 3 samples
        sim = scenario.simulation
        tiny = simulate_scenario(
            scenario, duration=min(sim.duration, 2 * sim.spacing()), allow_large=True
        )
        figures = len(tiny.figures())
    return _OUTPUT_SECONDS + _SECONDS_PER_FIGURE * figures + _OUTPUT_SECONDS_PER_SAMPLE * samples


def _adaptive(method: str) -> bool:
    entry = INTEGRATORS.get(method)
    return bool(entry is not None and entry.adaptive)


#: Target work of the measured piece of an adaptive run (s) and its largest fraction.
_PIECE_SECONDS = 0.3
_PIECE_FRACTION = 0.02


def _measure(scenario: Scenario, method: str, guess: float) -> tuple[float, float] | None:
    """``(seconds of the whole run, seconds compiling)`` of ``method`` from a run of a
    short first piece (after a tiny one that compiles and warms up), or None when the
    run is too short to need it."""

    sim = scenario.simulation
    frac = min(_PIECE_FRACTION, _PIECE_SECONDS / max(guess, 1e-9))
    piece = sim.duration * frac
    warm = min(piece, 2 * sim.spacing())
    if piece < 4 * sim.spacing() or piece >= sim.duration:
        return None
    kind = scenario.adapter
    one = dataclasses.replace(
        scenario, simulation=dataclasses.replace(sim, method=method, reference=None)
    )
    c0 = compile_seconds()
    w = _override(one, warm)
    kind.solve(w, method, w.simulation.times(), quiet_progress)  # compiles, warms up
    compiled = compile_seconds() - c0
    timed = []
    for span_ in (warm, piece):  # time = fixed + rate * duration, from two spans
        r = _override(one, span_)
        start = time.perf_counter()
        kind.solve(r, method, r.simulation.times(), quiet_progress)
        timed.append(time.perf_counter() - start)
    rate = max(timed[1] - timed[0], 0.0) / (piece - warm)
    return timed[0] + rate * (sim.duration - warm), compiled


# ----------------------------------------------------------------------------- solving
def chunked(
    solve: Any,
    r0: Any,
    w0: Any,
    t: np.ndarray,
    progress: Progress,
    stage: str,
    *,
    resume: Any = None,
) -> Any:
    """Run ``solve(r0, w0, t)`` in consecutive chunks of ``t`` to report progress.

    Each chunk starts from the last state of the previous one, so a fixed-step method
    advances exactly as in one call (the step is tied to the output spacing).
    ``resume(result) -> (r0, w0)`` gives that state; by default, for a
    :class:`~poinsot.trajectory.Trajectory`, its last attitude and angular
    velocity (``w0`` may be ``None``: attitude propagation carries no angular
    velocity). A solve returning another result must pass ``resume``. The chunks
    are joined field by field (:func:`_concatenate`), whatever the result type.
    """
    n = t.size
    if n <= _CHUNK_SAMPLES:
        progress(0.0, stage)
        tr = solve(r0, w0, t)
        progress(1.0, stage)
        return tr
    edges = np.unique(np.linspace(0, n - 1, _N_CHUNKS + 1).round().astype(int))
    parts: list[Any] = []
    state = (r0, w0)
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        progress(k / (len(edges) - 1), stage)
        tr = solve(*state, t[a : b + 1])
        parts.append(tr)
        state = _last_state(tr) if resume is None else resume(tr)
    progress(1.0, stage)
    return _concatenate(parts)


def _last_state(tr: Any) -> tuple[Any, ...]:
    if not isinstance(tr, Trajectory):
        raise InvalidTypeError(
            f"Expected `resume` for a chunked run returning {type(tr).__name__} (only a "
            "Trajectory resumes from its last attitude and angular velocity)."
        )
    return tr.rotation[-1], np.asarray(tr.omega[-1])


def _concatenate(parts: list[Any]) -> Any:
    """One result from consecutive chunks that share their boundary samples: every
    per-sample field (an array or a Rotation whose first axis runs over the times)
    joined without the repeated samples, the others from the first chunk;
    ``info`` from the last, with ``chunks``, its counts (steps, evaluations...)
    summed over the chunks and its step sizes the extremes of all chunks."""

    first = parts[0]
    n0 = first.t.shape[0]
    kwargs: dict[str, Any] = {}
    for f in dataclasses.fields(first):
        if not f.init:
            continue
        values = [getattr(p, f.name) for p in parts]
        v0 = values[0]
        if isinstance(v0, Rotation) and v0.shape[:1] == (n0,):
            kwargs[f.name] = Rotation.concatenate([v0] + [v[1:] for v in values[1:]])
        elif isinstance(v0, np.ndarray) and v0.ndim >= 1 and v0.shape[0] == n0:
            kwargs[f.name] = np.concatenate([v0] + [np.asarray(v)[1:] for v in values[1:]])
        else:
            kwargs[f.name] = v0
    info = dict(parts[-1].info)
    for key in PER_SAMPLE_INFO:  # one value per sample (V, T + V): joined as the samples
        if all(key in p.info for p in parts):
            values = [np.asarray(p.info[key]) for p in parts]
            info[key] = np.concatenate([values[0]] + [v[1:] for v in values[1:]])
    for key in _COUNTS:  # one count for the whole run, not the last chunk's
        values = [p.info.get(key) for p in parts]
        if all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in values):
            info[key] = int(sum(values))
    for key, pick in (("step_size", max), ("min_step_size", min)):
        values = [p.info[key] for p in parts if isinstance(p.info.get(key), float | int)]
        if values:
            info[key] = float(pick(values))
    info["chunks"] = len(parts)
    kwargs["info"] = info
    return type(first)(**kwargs)


#: ``info`` counts that add up over the chunks of a run (poinsot.trajectory.INFO_KEYS).
_COUNTS = ("steps", "evaluations", "rejected", "torque_calls")


def _override(scenario: Scenario, duration: float | None) -> Scenario:
    if duration is None:
        return scenario
    if isinstance(duration, bool) or not (
        isinstance(duration, int | float | np.integer | np.floating)
        and np.isfinite(duration)
        and duration > 0
    ):
        raise InvalidInputError(
            f"Expected `duration` (--duration) to be a positive number of seconds, "
            f"got {duration!r}."
        )
    sim = scenario.simulation
    step = sim.step if sim.step is None else min(sim.step, float(duration))
    new = dataclasses.replace(sim, duration=float(duration), step=step)
    bad = scenario.adapter.check_simulation(new, vars(scenario))
    if bad is not None:
        key, why = bad
        raise InvalidInputError(f"Expected `duration` (--duration) {why.removeprefix('expected ')}")
    return dataclasses.replace(scenario, simulation=new)


def _expect(value: Any, kind: Any, name: str, what: str) -> None:
    if not isinstance(value, kind):
        raise InvalidTypeError(f"Expected `{name}` to be {what}, got {type(value).__name__}.")


def check_cost(scenario: Scenario, *, duration: Any = None, allow_large: bool = False) -> Cost:
    """The cost of a run, or an :class:`~poinsot.InvalidInputError` listing what
    exceeds the limits (raised before any work)."""
    cost = estimate_cost(scenario, duration=duration)
    problems = cost.problems(allow_large=allow_large)
    if problems:
        raise InvalidInputError(
            f"scenario {scenario.name!r} is refused before running: " + "; ".join(problems) + "."
        )
    return cost


def simulate_scenario(
    scenario: Scenario,
    *,
    duration: float | None = None,
    progress: Progress | None = None,
    allow_large: bool = False,
) -> ScenarioResult:
    """Solve a scenario with the library (no files written).

    Parameters
    ----------
    scenario : Scenario
        From :func:`poinsot.scenarios.load_scenario`.
    duration : float, optional
        Override of ``[simulation] duration`` (s), e.g. for a quick look.
    progress : callable, optional
        ``progress(fraction, stage)`` called as the computation advances.
    allow_large : bool, optional
        Run even when the estimated memory or number of steps exceeds
        :data:`MAX_MEMORY_BYTES` / :data:`MAX_STEPS` (the sample limit
        :data:`MAX_SAMPLES` always holds).

    Returns
    -------
    ScenarioResult

    Raises
    ------
    InvalidInputError
        A bad override, or a run beyond the limits (before any work).
    IntegrationError
        The integrator diverged (a shorter ``max_step`` usually helps).

    Notes
    -----
    **Convention:** see :data:`poinsot.scenarios.CONVENTIONS`.

    Examples
    --------
    >>> from poinsot.scenarios import parse_scenario, simulate_scenario
    >>> s = parse_scenario('''
    ... [body]
    ... mass = 1.0
    ... inertia = [1.0, 2.0, 3.0]
    ... [angular_velocity]
    ... vector = [0.0, 0.0, 1.0]
    ... frame = "body"
    ... [simulation]
    ... duration = 1.0
    ... samples = 11
    ... method = "exact"
    ... ''')
    >>> r = simulate_scenario(s)
    >>> r.summary["results"]["energy"], r.summary["results"]["units"]["energy"]
    (1.5, 'J')
    """

    _expect(scenario, Scenario, "scenario", "a Scenario (from load_scenario/parse_scenario)")
    cost = check_cost(scenario, duration=duration, allow_large=bool(allow_large))
    scenario = _override(scenario, duration)
    progress = progress or quiet_progress
    kind = scenario.adapter
    t = scenario.simulation.times()
    has_ref = scenario.simulation.reference is not None

    # numba's compile time (a cold cache) is counted apart from each method's time
    c0 = compile_seconds()
    start = time.perf_counter()
    tr = kind.solve(
        scenario, scenario.simulation.method, t, span(progress, 0.0, 0.5 if has_ref else 1.0)
    )
    c1 = compile_seconds()
    wall = time.perf_counter() - start - (c1 - c0)
    ref = None
    ref_wall = None
    if has_ref:
        start = time.perf_counter()
        ref = kind.solve(scenario, scenario.simulation.reference, t, span(progress, 0.5, 1.0))
        ref_wall = time.perf_counter() - start - (compile_seconds() - c1)
    return ScenarioResult.build(
        scenario,
        tr,
        ref,
        wall_time=wall,
        cost=cost,
        reference_time=ref_wall,
        compile_time=compile_seconds() - c0,
    )
