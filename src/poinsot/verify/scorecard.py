"""The scorecard of ``poinsot verify``: every installed engine, every integrator, every
case, over a sweep of steps or tolerances (docs/verify.md, "Scorecard").

:func:`scorecard` runs the sweeps of :data:`SWEEPS` (or those given) and returns a
:class:`Scorecard`: per engine its version, and per (integrator, setting, case) the
verdict, each metric against its threshold, the energy and momentum drift per
revolution (per second when the case has no period), the work and the seconds.
:func:`first_passing` gives the coarsest setting from which an integrator passes a
case, :func:`observed_order` the slope of the error against the step (or the
tolerance) and :func:`diagnose` a plain reason for a failure derived from those data
("a first-order method", "energy growth", "does not converge: wrong physics?").
:meth:`Scorecard.write` writes ``scorecard.json``, one Markdown page per engine
version and work-precision charts (PNG); :meth:`Scorecard.from_json` reads the JSON
back, so the pages are regenerated without any engine (``poinsot verify scorecard
--from-json``).
"""

from __future__ import annotations

import functools
import math
import os
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from .._files import atomic_write
from ..errors import InvalidInputError
from .cases import CASES_VERSION, cases
from .cases import cases as _all_cases  # `scorecard(cases=...)` shadows the name
from .engines import make, run
from .metrics import METRICS, integrals

__all__ = [
    "QUICK_SWEEPS",
    "SWEEPS",
    "EngineCard",
    "Scorecard",
    "Sweep",
    "diagnose",
    "first_passing",
    "observed_order",
    "scorecard",
]

#: the engines of the scorecard, in the order of the pages
ENGINES = ("poinsot", "scipy", "mujoco", "pybullet", "drake", "basilisk")

#: settings that are a step (s): the error against them is an order of convergence
STEP_SETTINGS = ("timestep", "step")

#: an error at or under this (1e-4 of the thresholds) is near round-off, left out of
#: the fitted order
ROUNDOFF = 1e-10
#: an error at or over this is saturated (an attitude error is at most pi rad)
SATURATED = 0.1


@dataclass(frozen=True)
class Sweep:
    """One integrator of one engine over a sweep of one setting.

    Attributes
    ----------
    engine : str
        An engine of :data:`poinsot.verify.engines.ENGINES`.
    integrator : str
        The integrator's name on the pages (e.g. ``"implicitfast"``).
    options : dict
        The engine's fixed options (:func:`poinsot.verify.make`), e.g.
        ``{"integrator": "implicitfast"}``.
    setting : str
        The option swept: ``"timestep"``, ``"step"`` (s), ``"rtol"`` or ``"accuracy"``.
    values : tuple of float
        Its values, coarsest first.
    default : float
        The engine adapter's default value of the setting (its verdict at this value
        is the "default" column of the pages).
    """

    engine: str
    integrator: str
    options: Mapping[str, Any]
    setting: str
    values: tuple[float, ...]
    default: float

    def to_json(self) -> dict[str, Any]:
        return {"engine": self.engine, "integrator": self.integrator,
                "options": dict(self.options), "setting": self.setting,
                "values": list(self.values), "default": self.default}  # fmt: skip


def _steps(*v: float) -> tuple[float, ...]:
    return tuple(float(x) for x in v)


_DECADES = _steps(1e-2, 1e-3, 1e-4)
_TOLS = _steps(1e-6, 1e-8, 1e-10, 1e-12)

#: the default sweeps, per engine (coarsest value first)
SWEEPS: dict[str, tuple[Sweep, ...]] = {
    "poinsot": (
        Sweep("poinsot", "dop853", {"method": "dop853"}, "rtol", _TOLS, 1e-10),
        Sweep("poinsot", "DOP853 (points)", {"method": "DOP853"}, "rtol", _TOLS, 1e-10),
        Sweep("poinsot", "rk4", {"method": "rk4"}, "step", _DECADES, 1e-3),
        Sweep("poinsot", "midpoint", {"method": "midpoint"}, "step", _DECADES, 1e-3),
    ),
    "scipy": (
        Sweep("scipy", "DOP853", {"method": "DOP853"}, "rtol", _TOLS, 1e-12),
        Sweep("scipy", "RK45", {"method": "RK45"}, "rtol", _TOLS[:2], 1e-8),
        Sweep("scipy", "Radau", {"method": "Radau"}, "rtol", _steps(1e-5, 1e-6), 1e-6),
    ),
    "mujoco": tuple(
        Sweep(
            "mujoco",
            name,
            {"integrator": name},
            "timestep",
            _steps(1e-2, 3e-3, 1e-3, 3e-4, 1e-4),
            1e-3,
        )  # fmt: skip
        for name in ("Euler", "implicit", "implicitfast", "RK4")
    ),
    "pybullet": tuple(
        Sweep("pybullet", name, {"coordinates": name}, "timestep", _DECADES, 1e-3)
        for name in ("reduced", "maximal")
    ),
    "drake": (
        Sweep(
            "drake", "runge_kutta3", {"integrator": "runge_kutta3"}, "accuracy", _TOLS[:3], 1e-13
        ),  # fmt: skip
        Sweep(
            "drake",
            "runge_kutta5",
            {"integrator": "runge_kutta5"},
            "accuracy",
            _TOLS + (1e-13,),
            1e-13,
        ),  # fmt: skip
        Sweep(
            "drake",
            "runge_kutta5 fixed",
            {"integrator": "runge_kutta5"},
            "step",
            _steps(1e-2, 3e-3, 1e-3),
            1e-3,
        ),  # fmt: skip
        Sweep("drake", "radau3", {"integrator": "radau3"}, "accuracy", _TOLS[:3], 1e-13),
        Sweep(
            "drake", "implicit_euler", {"integrator": "implicit_euler"}, "step", _DECADES, 1e-3
        ),  # fmt: skip
        Sweep(
            "drake",
            "semi_explicit_euler",
            {"integrator": "semi_explicit_euler"},
            "step",
            _DECADES,
            1e-3,
        ),  # fmt: skip
    ),
    "basilisk": tuple(
        Sweep("basilisk", name, {"integrator": name}, "timestep", _DECADES, 1e-3)
        for name in ("Euler", "RK2", "RK4")
    )
    + tuple(
        Sweep(
            "basilisk", name, {"integrator": name, "timestep": 1e-2}, "rtol", (1e-4, *_TOLS), 1e-4
        )
        for name in ("RKF45", "RKF78")
    ),
}

#: a shorter scorecard (``--quick``): two settings a decade apart per integrator
QUICK_SWEEPS: dict[str, tuple[Sweep, ...]] = {
    name: tuple(
        Sweep(
            s.engine,
            s.integrator,
            s.options,
            s.setting,
            s.values[:2] if s.setting in STEP_SETTINGS else s.values[:3:2],
            s.default,
        )
        for s in sweeps
    )  # fmt: skip
    for name, sweeps in SWEEPS.items()
}

#: the cases of the work-precision charts (the first ones an engine scores)
CHART_CASES = ("racket-flip", "top-loops", "kepler-e0.95", "free-minor-axis")

#: the largest number of fixed steps one run of the scorecard takes (more: skipped)
MAX_STEPS = 400_000
#: the longest predicted CPU time (s) of one run (more: skipped, the finer ones too)
RUN_SECONDS = 60.0
#: the growth of a run's time per step of a tolerance sweep, for the prediction
TOL_GROWTH = 2.0


def engine_version(engine: str) -> str | None:
    """The installed version of ``engine`` (None when it is not installed)."""
    dist = {
        "mujoco": "mujoco",
        "pybullet": "pybullet",
        "drake": "drake",
        "scipy": "scipy",
        "basilisk": "bsk",
    }
    if engine == "poinsot":
        return __version__
    try:
        v = version(dist[engine])
    except PackageNotFoundError:
        return None
    if engine == "pybullet":
        try:
            import pybullet

            v += f" (API {pybullet.getAPIVersion()})"
        except ImportError:
            return None
    return v


def drift_period(case: Any) -> tuple[float, str]:
    """``(seconds, unit)``: the case's period (``"rev"``) or 1 s (``"s"``) when none."""
    f = case.facts
    for key in ("period_s", "nutation_period_s", "libration_period_s"):
        if key in f:
            return float(f[key]), "rev"
    if "swing_frequency_rad_per_s" in f:
        return 2.0 * math.pi / float(f["swing_frequency_rad_per_s"]), "rev"
    return 1.0, "s"


def _run_case(sweep: Sweep, name: str) -> list[dict[str, Any]]:
    """The rows of one sweep on one case, coarsest setting first (in a worker process).

    A setting whose run would take more than :data:`MAX_STEPS` fixed steps, or more
    than :data:`RUN_SECONDS` predicted from the previous setting's CPU time (the work
    of a fixed step grows as 1 / step; a tolerance's by :data:`TOL_GROWTH` per step of
    the sweep), is a ``"skip"`` row with the reason.
    """
    rows: list[dict[str, Any]] = []
    case = cases(name)[0]
    duration = float(case.t[-1] - case.t[0])
    last: tuple[float, float] | None = None  # (value, seconds) of the previous run
    for value in sweep.values:
        row: dict[str, Any] = {"integrator": sweep.integrator, "setting": sweep.setting,
                               "value": value, "case": case.name}  # fmt: skip
        fixed = sweep.setting in STEP_SETTINGS
        if fixed:
            row["step"] = _effective_step(sweep.engine, value, float(case.t[1] - case.t[0]))
        eng = make(sweep.engine, **{**sweep.options, sweep.setting: value})
        why = eng.skip_reason(case) or ""
        if not why and fixed and duration / value > MAX_STEPS:
            why = (f"{duration / value:.3g} steps over the case's {duration:g} s: more "
                   f"than the scorecard's {MAX_STEPS}")  # fmt: skip
        elif not why and last is not None:
            grow = last[0] / value if fixed else TOL_GROWTH
            predicted = last[1] * grow
            if predicted > RUN_SECONDS:
                why = (f"predicted {predicted:.0f} s of CPU from {last[1]:.1f} s at "
                       f"{fmt_setting(sweep.setting, last[0])}: over the scorecard's "
                       f"{RUN_SECONDS:g} s per run")  # fmt: skip
        if why:  # this setting and every finer one: over the budget
            k = sweep.values.index(value)
            row.pop("step", None)
            rows += [{**row, "value": v, "status": "skip", "reason": why} for v in sweep.values[k:]]
            break
        t0, cpu0 = time.perf_counter(), time.process_time()
        res = run(eng, case)
        cpu = time.process_time() - cpu0
        if res.status in ("skip", "missing"):
            rows.append({**row, "status": res.status, "reason": res.reason})
            continue
        period, unit = drift_period(case)
        revs = duration / period
        change = math.nan
        if res.states and all(np.all(np.isfinite(a)) for a in res.states.values()):
            e = integrals(case, res.states)["energy"]
            e0 = abs(float(integrals(case, case.exact())["energy"][0])) or 1.0
            change = float((e[-1] - e[0]) / e0)
        metrics = {k: {"value": _num(m["value"]), "threshold": m["threshold"],
                       "passed": m["passed"]} for k, m in res.metrics.items()}  # fmt: skip
        seconds = res.seconds or time.perf_counter() - t0
        last = (value, cpu)  # CPU time: the prediction does not depend on the load
        rows.append({
            **row, "status": res.status, "reason": res.reason, "metrics": metrics,
            "energy_change": _num(change),
            "drift_unit": unit,
            "energy_per": _num(res.metrics["energy"]["value"] / revs),
            "momentum_per": _num(res.metrics["momentum"]["value"] / revs)
            if "momentum" in res.metrics else None,
            "work": res.work, "seconds": round(seconds, 4),
        })  # fmt: skip
    return rows


def _effective_step(engine: str, value: float, spacing: float) -> float:
    """The step an engine takes: poinsot's ``max_step`` and Drake's fixed step are
    cut at the case's grid (a step of 20 ms on a 10 ms grid is 10 ms); MuJoCo and
    PyBullet go on with whole steps and read a time between them by a shorter one."""
    return min(value, spacing) if engine in ("poinsot", "drake") else value


def _num(x: float) -> float | str:
    x = float(x)
    return x if math.isfinite(x) else "inf" if x > 0 else "nan" if math.isnan(x) else "-inf"


@dataclass
class EngineCard:
    """One engine's part of the scorecard.

    Attributes
    ----------
    engine : str
    version : str or None
        The installed version (None: not installed, ``reason`` says so).
    reason : str
        Why the engine was not run ("" when it was).
    sweeps : list of Sweep
    rows : list of dict
        One per (integrator, setting value, case): ``integrator``, ``setting``,
        ``value``, ``case``, ``status``, ``reason``, and for a scored case
        ``metrics`` (``name -> {"value", "threshold", "passed"}``), ``energy_change``
        (the signed relative energy change over the run), ``drift_unit`` (``"rev"``
        or ``"s"``), ``energy_per`` and ``momentum_per`` (the drift per revolution
        or per second), ``work`` and ``seconds``.
    seconds : float
        Wall time of the engine's sweeps.
    """

    engine: str
    version: str | None
    reason: str = ""
    sweeps: list[Sweep] = field(default_factory=list)
    rows: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def slug(self) -> str:
        """The file name of the engine's page: ``engine-version``."""
        v = (self.version or "missing").split(" ")[0]
        return f"{self.engine}-{v}"

    def to_json(self) -> dict[str, Any]:
        return {"engine": self.engine, "version": self.version, "reason": self.reason,
                "seconds": round(self.seconds, 2), "sweeps": [s.to_json() for s in self.sweeps],
                "rows": self.rows}  # fmt: skip

    @classmethod
    def from_json(cls, d: Mapping[str, Any]) -> EngineCard:
        sweeps = [Sweep(s["engine"], s["integrator"], s["options"], s["setting"],
                        tuple(s["values"]), s["default"]) for s in d["sweeps"]]  # fmt: skip
        return cls(d["engine"], d["version"], d.get("reason", ""), sweeps, list(d["rows"]),
                   d.get("seconds", 0.0))  # fmt: skip

    def cases(self) -> list[str]:
        """The cases the engine scored (in the order of the rows)."""
        return list(dict.fromkeys(r["case"] for r in self.rows if "metrics" in r))

    def skipped(self) -> dict[str, str]:
        """Cases the engine never scored -> the reason."""
        scored = set(self.cases())
        out: dict[str, str] = {}
        for r in self.rows:
            if r["case"] not in scored and r["status"] in ("skip", "missing"):
                out.setdefault(r["case"], r["reason"])
        return out

    def series(self, sweep: Sweep, case: str) -> list[dict[str, Any]]:
        """The scored rows of ``sweep`` on ``case``, coarsest setting first."""
        rows = [r for r in self.rows if r["integrator"] == sweep.integrator
                and r["case"] == case and "metrics" in r]  # fmt: skip
        return sorted(rows, key=lambda r: -r["value"])


@dataclass
class Scorecard:
    """The results of :func:`scorecard`: one :class:`EngineCard` per engine."""

    cards: list[EngineCard]
    cases_version: str = CASES_VERSION

    def to_dict(self) -> dict[str, Any]:
        return {"cases_version": self.cases_version, "metrics": {k: {"units": u, "meaning": m}
                for k, (u, m) in METRICS.items()},
                "engines": [c.to_json() for c in self.cards], "docs": "docs/verify.md"}  # fmt: skip

    def to_json(self, path: str | Path) -> Path:
        """Write the scorecard as JSON (what :meth:`from_json` reads)."""
        import json

        path = Path(path)
        d = self.to_dict()  # one line per row: a diff of two runs reads row by row
        head = json.dumps({k: v for k, v in d.items() if k != "engines"}, indent=1)
        cards = []
        for c in d["engines"]:
            rows = ",\n".join(json.dumps(r, allow_nan=False) for r in c["rows"])
            rest = json.dumps({k: v for k, v in c.items() if k != "rows"}, allow_nan=False)
            cards.append(rest[:-1] + ', "rows": [\n' + rows + "\n]}")
        text = head[:-2] + ',\n "engines": [\n' + ",\n".join(cards) + "\n]\n}\n"
        atomic_write(path, lambda fh: fh.write(text))
        return path

    @classmethod
    def from_json(cls, path: str | Path) -> Scorecard:
        """The scorecard stored by :meth:`to_json`."""
        import json

        d = json.loads(Path(path).read_text(encoding="utf-8"))
        return cls([EngineCard.from_json(c) for c in d["engines"]], d["cases_version"])

    def to_markdown(self, engine: str | None = None) -> str:
        """The Markdown page of ``engine`` (default: the index of every engine)."""

        if engine is None:
            return index_page(self)
        for card in self.cards:
            if card.engine == engine:
                return engine_page(card, self.cases_version)
        raise InvalidInputError(f"Expected an engine of the scorecard, got {engine!r}.")

    def write(self, out: str | Path, *, charts: bool = True) -> list[Path]:
        """Write ``scorecard.json``, ``index.md``, one page per engine version
        (``ENGINE-VERSION.md``) and (``charts``) its work-precision charts (PNG)."""
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        return [self.to_json(out / "scorecard.json"), *self.write_pages(out, charts=charts)]

    def write_pages(self, out: str | Path, *, charts: bool = True) -> list[Path]:
        """Write the Markdown pages (and charts) only, e.g. from a stored JSON."""

        return write_pages(self, Path(out), charts=charts)


def scorecard(engines_settings: Sequence[str] | Mapping[str, Sequence[Sweep]] | None = None,
              cases: str | Iterable[str] | None = None, *, quick: bool = False,
              jobs: int | None = None,
              progress: Callable[[str], object] | None = None) -> Scorecard:  # fmt: skip
    """Run every engine's integrators on every case over a sweep of its setting.

    Parameters
    ----------
    engines_settings : sequence of str or mapping, optional
        Engine names (their sweeps from :data:`SWEEPS`, or :data:`QUICK_SWEEPS` with
        ``quick``) or ``engine -> [Sweep, ...]``; default every engine of
        :data:`ENGINES`. An engine that is not installed is listed with the reason.
    cases : str or iterable of str, optional
        Case names or groups (:func:`poinsot.verify.cases`); default all.
    quick : bool, optional
        Two settings per integrator (:data:`QUICK_SWEEPS`).
    jobs : int, optional
        Worker processes (default: up to 2, one per CPU); 1 runs in this process.
    progress : callable, optional
        Called with a line of text after each sweep.

    Returns
    -------
    Scorecard

    Examples
    --------
    >>> from poinsot.verify.scorecard import Sweep, scorecard
    >>> s = Sweep("scipy", "DOP853", {"method": "DOP853"}, "rtol", (1e-6, 1e-12), 1e-12)
    >>> card = scorecard({"scipy": [s]}, "free-symmetric", jobs=1).cards[0]
    >>> [(r["value"], r["status"]) for r in card.rows]
    [(1e-06, 'fail'), (1e-12, 'pass')]
    """

    names = [c.name for c in _all_cases(cases)]
    table = QUICK_SWEEPS if quick else SWEEPS
    if engines_settings is None:
        plan = {e: list(table[e]) for e in ENGINES}
    elif isinstance(engines_settings, Mapping):
        plan = {e: list(s) for e, s in engines_settings.items()}
    else:
        plan = {}
        for e in engines_settings:
            if e not in table:
                raise InvalidInputError(f"Expected engines among {', '.join(ENGINES)}, got {e!r}.")
            plan[e] = list(table[e])
    cards: list[EngineCard] = []
    tasks: list[tuple[EngineCard, Sweep, str]] = []
    for engine, sweeps in plan.items():
        version = engine_version(engine)
        reason = "" if version else (
            f"the {engine} package is not installed: pip install 'poinsot[verify]'")  # fmt: skip
        card = EngineCard(engine, version, reason, list(sweeps))
        cards.append(card)
        if version:
            tasks += [(card, s, n) for s in sweeps for n in names]
    jobs = min(2, os.cpu_count() or 1) if jobs is None else max(1, int(jobs))
    t0 = time.perf_counter()
    results: dict[int, list[dict[str, Any]]] = {}

    def done(k: int, rows: list[dict[str, Any]]) -> None:
        results[k] = rows
        if progress is not None:
            card, s, n = tasks[k]
            got = ", ".join(f"{fmt_setting(r['setting'], r['value'])} {r['status']}"
                            for r in rows)  # fmt: skip
            progress(f"{card.engine} {s.integrator} {n}: {got} ({time.perf_counter() - t0:.0f} s)")

    if jobs == 1 or len(tasks) < 2:
        for k, (_, s, n) in enumerate(tasks):
            done(k, _run_case(s, n))
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            futures = {pool.submit(_run_case, s, n): k for k, (_, s, n) in enumerate(tasks)}
            for fut in as_completed(futures):
                done(futures[fut], fut.result())
    for card in cards:  # the rows of each sweep by setting, then case
        mine = [k for k in range(len(tasks)) if tasks[k][0] is card]
        for s in card.sweeps:
            for v in s.values:
                for k in mine:
                    if tasks[k][1] is s:
                        card.rows += [r for r in results[k] if r["value"] == v]
        # rounded as the JSON stores it, so that the pages of a fresh run and of its JSON
        # agree (0.5012 s printed "1" here and "0" from the stored 0.50)
        card.seconds = round(sum(r.get("seconds", 0.0) for r in card.rows), 2)
    return Scorecard(cards)


# ---- analysis: derived from the rows only (so the pages come from the JSON alone)


def first_passing(values: Sequence[float], passed: Sequence[bool]) -> float | None:
    """The coarsest setting from which every finer one passes (None: the finest fails).

    ``values`` coarsest first. A pass at a coarse setting followed by a failure at a
    finer one (a lucky cancellation) does not count.

    >>> first_passing([1e-2, 1e-3, 1e-4], [False, True, True])
    0.001
    >>> first_passing([1e-2, 1e-3, 1e-4], [True, False, True])
    0.0001
    >>> first_passing([1e-2, 1e-3], [True, False]) is None
    True
    """
    out = None
    for v, p in zip(reversed(list(values)), reversed(list(passed)), strict=True):
        if not p:
            break
        out = v
    return out


def observed_order(values: Sequence[float], errors: Sequence[float]) -> float | None:
    """The slope of ``log(error)`` against ``log(value)`` (least squares).

    Errors at round-off (<= :data:`ROUNDOFF`), saturated (>= :data:`SATURATED`) or not
    finite are left out; None with fewer than two left. Against a step it is the
    observed order of convergence (1 for a first-order method); against a tolerance,
    how the error follows it.

    >>> round(observed_order([1e-2, 1e-3, 1e-4], [1e-2, 1e-3, 1e-4]), 6)
    1.0
    >>> round(observed_order([1e-2, 1e-3, 1e-4], [1e-3, 1e-7, 1e-11]), 6)
    4.0
    """
    pts = [
        (math.log10(v), math.log10(e))
        for v, e in zip(values, errors, strict=True)
        if isinstance(e, (int, float)) and math.isfinite(e) and ROUNDOFF < e < SATURATED
    ]
    if len(pts) < 2 or len({x for x, _ in pts}) < 2:
        return None
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def _main_error(row: Mapping[str, Any]) -> tuple[str, float]:
    key = "attitude" if "attitude" in row["metrics"] else "position"
    return key, _value(row["metrics"][key]["value"])


def _value(x: Any) -> float:
    return float(x) if not isinstance(x, str) else float(x)


def _write_text(fh: Any, text: str) -> None:
    fh.write(text)


def fmt_setting(setting: str, value: float) -> str:
    """``1 ms``, ``0.1 ms``, ``10 ms`` for a step; ``rtol=1e-08`` for a tolerance."""
    if setting in STEP_SETTINGS:
        return f"{value * 1e3:.2g} ms" if value >= 1e-5 else f"{value:.1e} s"
    return f"{setting}={value:.0e}"


def diagnose(setting: str, rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Why an integrator fails a case, from its rows over the sweep (coarsest first).

    Returns
    -------
    dict
        ``first`` (the first passing setting, :func:`first_passing`), ``order``
        (:func:`observed_order` of the attitude or position error against the step
        taken, ``row["step"]``, or the setting), ``kind``: one of
        ``"pass"``, ``"first-order"``, ``"order N"``, ``"tolerance"``, ``"unstable"``
        (the attitude stays wrong while the energy drift converges), ``"error
        control"`` (a tolerance sweep whose error does not fall while the energy is
        kept), ``"no convergence"``, ``"saturated"``, ``"other metric"``, and ``text``: the
        plain sentence (e.g. ``"a first-order method"``), ``energy_growth`` (True
        when the energy grows past its threshold at a setting where the attitude is
        within 10x its threshold).

    >>> rows = [{"value": h, "status": "fail", "energy_change": 0.0, "metrics": {
    ...     "attitude": {"value": 10 * h, "threshold": 1e-6, "passed": False},
    ...     "energy": {"value": 0.0, "threshold": 1e-8, "passed": True}}}
    ...     for h in (1e-2, 1e-3, 1e-4)]
    >>> diagnose("timestep", rows)["text"]
    'a first-order method (error ~ step^1.0); would pass near 1.0e-07 s'
    """
    values = [r["value"] for r in rows]
    passed = [r["status"] == "pass" for r in rows]
    first = first_passing(values, passed)
    errs = [_main_error(r)[1] for r in rows]
    # the order against the step taken (a setting over the grid's spacing is cut to it)
    taken: dict[float, float] = {}
    for r, e in zip(rows, errs, strict=True):
        taken[float(r.get("step", r["value"]))] = e
    order = observed_order(list(taken), list(taken.values()))
    out: dict[str, Any] = {"first": first, "order": order, "energy_growth": False}
    for r in rows:
        key, err = _main_error(r)
        thr = r["metrics"][key]["threshold"]
        e = r["metrics"].get("energy")
        if (err <= 10 * thr and e is not None and not e["passed"]
                and isinstance(r.get("energy_change"), (int, float))
                and r["energy_change"] > 0):  # fmt: skip
            out["energy_growth"] = True
    if first is not None and all(passed[values.index(first) :]):
        out.update(kind="pass", text="passes")
        return out
    last = rows[-1]
    key, err = _main_error(last)
    if len(rows) < 2:
        out.update(kind="one setting", text=(
            f"only {fmt_setting(setting, last['value'])} was run (the finer settings are over "
            "the scorecard's budget): no order measured"))  # fmt: skip
        return out
    thr = last["metrics"][key]["threshold"]
    if err <= thr:  # the main error passes at the finest: another metric fails
        bad = [k for k, m in last["metrics"].items() if not m["passed"]]
        out.update(kind="other metric", text=f"the {', '.join(bad)} fail(s) at the finest "
                   f"setting while the {key} passes")  # fmt: skip
        return out
    usable = [e for e in errs if math.isfinite(e) and ROUNDOFF < e < SATURATED]
    finite = [e for e in errs if math.isfinite(e)]
    falls = len(finite) >= 2 and finite[-1] < 0.5 * finite[0]
    # the order of the energy drift: a drift that converges while the attitude does not
    # is a motion that is right to that order but unstable at these steps (a flip lost)
    drifts = {float(r.get("step", r["value"])): _value(r["metrics"]["energy"]["value"])
              for r in rows if "energy" in r["metrics"]}  # fmt: skip
    e_order = observed_order(list(drifts), list(drifts.values())) if len(drifts) > 1 else None
    e_last = _value(last["metrics"]["energy"]["value"]) if "energy" in last["metrics"] else None
    stuck = order is None and not falls or (order is not None and order < 0.3 and len(usable) > 1)
    if stuck:
        head = (f"the {key} error stays over {SATURATED:g} at every setting"
                if all(math.isfinite(e) and e >= SATURATED for e in errs)
                else f"the {key} error does not fall with the setting")  # fmt: skip
        if setting in STEP_SETTINGS and e_order is not None and e_order > 0.6:
            out.update(kind="unstable", text=(
                f"{head} while the energy drift falls as step^{_f1(e_order)}: the motion is "
                "unstable and the steps swept are too coarse for it (flips gained or lost), "
                "not wrong physics"))  # fmt: skip
        elif setting not in STEP_SETTINGS and e_last is not None and e_last < 1e-10:
            out.update(kind="error control", text=(
                f"{head} while the energy is kept to {e_last:.1e}: the error control, not "
                "the physics"))  # fmt: skip
        elif setting not in STEP_SETTINGS and e_order is not None and e_order > 0.3:
            out.update(kind="error control", text=(
                f"{head} while the energy drift falls as {setting}^{_f1(e_order)}: the error "
                "control on an unstable motion, not the physics"))  # fmt: skip
        else:
            out.update(kind="no convergence", text=f"does not converge: {head} (wrong physics?)")
        return out
    if order is None:
        out.update(kind="saturated", text=(
            f"the error falls but stays over {SATURATED:g} until the finest setting "
            "(too coarse to measure an order)"))  # fmt: skip
        return out
    if setting in STEP_SETTINGS:
        p = order
        if 0.6 <= p < 1.5:
            kind, text = "first-order", f"a first-order method (error ~ step^{_f1(p)})"
        else:
            kind, text = f"order {round(p)}", f"converges at order {_f1(p)} here"
        need = (
            float(last.get("step", last["value"])) * (thr / err) ** (1.0 / p) if p > 0 else math.nan
        )
        if math.isfinite(need):
            text += f"; would pass near {fmt_setting(setting, need)}"
    else:
        kind = "tolerance"
        text = (f"error ~ {setting}^{_f1(order)}; the finest {setting} swept is not tight "
                "enough")  # fmt: skip
    out.update(kind=kind, text=text)
    return out


# ---------------------------------------------------------------- the pages
# The Markdown pages and work-precision charts, written from the stored rows alone, so
# that ``poinsot verify scorecard --from-json`` regenerates them without any engine.

COMMAND = (
    "poinsot verify scorecard --out docs/verify/scorecard   "
    "# runs every installed engine (< 10 min on 2 cores)\n"
    "poinsot verify scorecard --from-json docs/verify/scorecard/scorecard.json "
    "--out docs/verify/scorecard   # the pages only, no engine"
)


def _f1(x: float) -> str:
    """A fitted order or slope to one decimal, never ``-0.0``: a slope that is zero up to
    rounding comes out of the least-squares fit as +-1e-17 with a sign that depends on
    the machine's LAPACK, and the pages must not."""
    return f"{round(float(x), 1) + 0.0:.1f}"


def _e(x: Any) -> str:
    """A number as the pages write it (``1.04e-02``; ``inf``; ``-`` for none)."""
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    return f"{x:.2e}" if x != 0 else "0"


def _err(row: dict[str, Any]) -> tuple[str, float, float]:
    key = "attitude" if "attitude" in row["metrics"] else "position"
    m = row["metrics"][key]
    return key, float(m["value"]), float(m["threshold"])


def _unit(key: str) -> str:
    return " rad" if key == "attitude" else " (relative)"


def _chart_cases(card: EngineCard) -> list[str]:
    scored = card.cases()
    out = [c for c in CHART_CASES if c in scored][:3]
    return out or scored[:1]


def _default_row(card: EngineCard, sweep: Sweep, case: str) -> dict[str, Any] | None:
    for r in card.series(sweep, case):
        if math.isclose(r["value"], sweep.default, rel_tol=1e-9):
            return r
    return None


def engine_page(card: EngineCard, cases_version: str) -> str:
    """The Markdown page of one engine version."""
    title = f"{card.engine} {card.version or '(not installed)'}"
    lines = [f"# Scorecard: {title}", ""]
    lines += [
        f"Cases version {cases_version}. Every integrator of the engine on every case "
        "it models, over a sweep of its step or tolerance, against the exact "
        "solutions ([poinsot verify](../../verify.md)). Regenerate:",
        "",
        "```console",
        COMMAND,
        "```",
        "",
    ]
    if card.reason:
        return "\n".join(lines + [f"Not run: {card.reason}.", ""])
    lines += ["| integrator | setting | values (coarsest first) | default |",
              "|---|---|---|---|"]  # fmt: skip
    for s in card.sweeps:
        vals = ", ".join(fmt_setting(s.setting, v) for v in s.values)
        lines.append(f"| {s.integrator} | {s.setting} | {vals} | "
                     f"{fmt_setting(s.setting, s.default)} |")  # fmt: skip
    scored = card.cases()
    sweeps = [s for s in card.sweeps if any(card.series(s, c) for c in scored)]
    lines += ["", "## Cases x integrators", "",
              "Each cell: the first (coarsest) setting from which the integrator passes "
              "every metric of the case (`-`: none swept); the verdict at the adapter's "
              "default setting (`-`: not run there); the energy drift per revolution "
              "(`/rev`, the case's period) or per second (`/s`) at the finest setting.",
              "",
              "| case | " + " | ".join(s.integrator for s in sweeps) + " |",
              "|---" * (len(sweeps) + 1) + "|"]  # fmt: skip
    diags: dict[tuple[str, str], dict[str, Any]] = {}
    for case in scored:
        cells = [case]
        for s in sweeps:
            rows = card.series(s, case)
            if not rows:
                cells.append("skip")
                continue
            d = diagnose(s.setting, rows)
            diags[s.integrator, case] = d
            first = "-" if d["first"] is None else fmt_setting(s.setting, d["first"])
            dr = _default_row(card, s, case)
            default = "-" if dr is None else dr["status"]
            fin = rows[-1]
            cells.append(f"{first}; {default}; {_e(fin['energy_per'])}/{fin['drift_unit']}")
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "## What fails and why", ""]
    lines += _findings(card, sweeps, scored, diags)
    skipped = card.skipped()
    if skipped:
        lines += ["", "## Cases not run", ""]
        for case, why in skipped.items():
            lines.append(f"- {case}: {why}")
    charts = _chart_cases(card)
    if charts:
        lines += ["", "## Work-precision", "",
                  "The largest attitude error (rad; relative position error for a point) "
                  "against the engine's own count of work (steps for MuJoCo, PyBullet and "
                  "poinsot's fixed-step methods, task updates for Basilisk, derivative "
                  "evaluations otherwise), "
                  "log-log, the dashed line the threshold.", ""]  # fmt: skip
        for c in charts:
            lines += [f"![{c}]({card.slug}-{c}.png)", ""]
    lines += ["## Every run", "",
              "| integrator | setting | case | status | error | energy drift | "
              "momentum drift | work | seconds |",
              "|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in card.rows:
        if "metrics" not in r:
            continue
        key, err, _ = _err(r)
        u = r["drift_unit"]
        lines.append(
            f"| {r['integrator']} | {fmt_setting(r['setting'], r['value'])} | {r['case']} | "
            f"{r['status']} | {_e(err)}{_unit(key)} | {_e(r['energy_per'])}/{u} | "
            f"{_e(r['momentum_per'])}/{u} | {r['work'] if r['work'] is not None else '-'} | "
            f"{r['seconds']:.2f} |"
        )
    return "\n".join(lines) + "\n"


def _findings(card: EngineCard, sweeps: list[Sweep], scored: list[str],
              diags: dict[tuple[str, str], dict[str, Any]]) -> list[str]:  # fmt: skip
    """The plain summary: per integrator, which cases fail and why (from the data)."""
    out: list[str] = []
    for s in sweeps:
        mine = {c: diags[s.integrator, c] for c in scored if (s.integrator, c) in diags}
        if not mine:
            continue
        fails = {c: d for c, d in mine.items() if d["kind"] != "pass"}
        orders = [d["order"] for d in mine.values() if d["order"] is not None]
        order_text = ""
        if orders:
            what = "order" if s.setting in STEP_SETTINGS else f"slope against {s.setting}"
            order_text = f" Observed {what}: {_f1(min(orders))} to {_f1(max(orders))}."
        if not fails:
            worst = min(d["first"] for d in mine.values())  # `mine` is not empty
            out.append(f"- **{s.integrator}** passes all {len(mine)} cases, each from the "
                       f"setting of the table on, all of them from "
                       f"{fmt_setting(s.setting, worst)}.{order_text}")  # fmt: skip
            continue
        out.append(f"- **{s.integrator}** fails {len(fails)} of {len(mine)} cases at the "
                   f"finest setting swept.{order_text}")  # fmt: skip
        for case, d in fails.items():
            rows = card.series(s, case)
            dr = _default_row(card, s, case) or rows[-1]
            key, err, thr = _err(dr)
            where = fmt_setting(s.setting, dr["value"])
            text = f"{s.integrator} at {where}: {_e(err)}{_unit(key)} on {case} - {d['text']}"
            fixed = _fixed_pass(card, s, case)
            if fixed:
                text += f"; the same integrator at a fixed step passes from {fixed}"
            if d["energy_growth"]:
                text += (
                    "; energy growth (the energy grows past its threshold where the "
                    "attitude is within 10x of its own)"
                )
            bad = [k for k, m in rows[-1]["metrics"].items() if not m["passed"]]
            text += f" (failing at {fmt_setting(s.setting, rows[-1]['value'])}: {', '.join(bad)})"
            out.append(f"  - {text}")
    return out or ["Nothing was scored."]


def _fixed_pass(card: EngineCard, sweep: Sweep, case: str) -> str:
    """The first passing fixed step of the same integrator on ``case`` ("" if none)."""
    if sweep.setting in STEP_SETTINGS:
        return ""
    for s in card.sweeps:
        if s.setting in STEP_SETTINGS and dict(s.options) == dict(sweep.options):
            rows = card.series(s, case)
            if rows:
                d = diagnose(s.setting, rows)
                if d["first"] is not None:
                    return fmt_setting(s.setting, d["first"])
    return ""


def index_page(sc: Scorecard) -> str:
    """The index of the scorecard: one line per engine, links to the pages."""
    lines = ["# Scorecard of the engines", "",
             f"Cases version {sc.cases_version}: every installed engine's integrators on "
             "every case over a sweep of steps or tolerances, scored against the exact "
             "solutions ([poinsot verify](../../verify.md)). Regenerate:", "",
             "```console", COMMAND, "```", "",
             "| engine | version | integrators | cases scored | passing at the finest "
             "setting | seconds |", "|---|---|---|---|---|---|"]  # fmt: skip
    for card in sc.cards:
        if card.reason:
            lines.append(f"| {card.engine} | - | - | - | not run: {card.reason} | - |")
            continue
        scored = card.cases()
        per = []
        for s in card.sweeps:
            rows = [card.series(s, c) for c in scored]
            rows = [r for r in rows if r]
            if rows:
                ok = sum(r[-1]["status"] == "pass" for r in rows)
                per.append(f"{s.integrator} {ok}/{len(rows)}")
        link = f"[{card.engine}]({card.slug}.md)"
        lines.append(f"| {link} | {card.version} | {len(card.sweeps)} | {len(scored)} | "
                     f"{', '.join(per)} | {card.seconds:.0f} |")  # fmt: skip
    lines += ["", "```{toctree}", ":hidden:", ""]
    lines += [f"{c.slug}" for c in sc.cards if not c.reason]
    lines += ["```", ""]
    return "\n".join(lines)


def chart(card: EngineCard, case: str, path: Path) -> Path:
    """The work-precision chart (PNG) of ``case``: error vs work per integrator."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.6, 3.6), dpi=80)
    ax = fig.add_subplot()
    thr = None
    key = "attitude"
    for s in card.sweeps:
        rows = [r for r in card.series(s, case) if r["work"]]
        if not rows:
            continue
        key, _, thr = _err(rows[0])
        pts = sorted((r["work"], max(_err(r)[1], 1e-17)) for r in rows
                     if math.isfinite(_err(r)[1]))  # fmt: skip
        if pts:
            x, y = zip(*pts, strict=True)
            ax.loglog(x, y, marker="o", ms=3, lw=1, label=s.integrator)
    if thr is not None:
        ax.axhline(thr, color="k", ls="--", lw=0.8, label=f"threshold {thr:g}")
    ax.set_xlabel("work (steps or evaluations)")
    ax.set_ylabel("largest attitude error (rad)" if key == "attitude" else
                  "largest position error (rel.)")  # fmt: skip
    ax.set_title(f"{card.engine} {card.version}: {case}", fontsize=9)
    ax.legend(fontsize=7, frameon=False)
    ax.grid(True, which="major", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, format="png", metadata={"Software": None})
    return path


def write_pages(sc: Scorecard, out: Path, *, charts: bool = True) -> list[Path]:
    """Write ``index.md``, ``ENGINE-VERSION.md`` and the charts to ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    files = []
    index = index_page(sc)
    atomic_write(out / "index.md", lambda fh: fh.write(index))
    files.append(out / "index.md")
    for card in sc.cards:
        if card.reason:
            continue
        page = engine_page(card, sc.cases_version)
        atomic_write(out / f"{card.slug}.md", functools.partial(_write_text, text=page))
        files.append(out / f"{card.slug}.md")
        if charts:
            for c in _chart_cases(card):
                files.append(chart(card, c, out / f"{card.slug}-{c}.png"))
    return files
