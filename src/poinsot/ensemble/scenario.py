"""Ensembles from scenario files: ``[dispersion]``, ``[[metric]]`` and the outputs.

A rigid-body scenario file (kinds ``free-body``, ``torqued-body``, ``heavy-top``: a
free body, a constant body/space torque, or gravity about a fixed point; or kind
``spacecraft`` with the gravity gradient alone along its ``[orbit]``, read by that
kind's own reader, the attitude and rates relative to LVLH) gains two tables that
``poinsot run`` passes over::

    [dispersion.omega0]            # one table per dispersed quantity
    distribution = "normal"        # about the nominal value of the file
    sigma = [0.01, 0.0, 0.01]      # rad/s

    [dispersion.attitude]
    distribution = "small_rotation"
    sigma = 2.0                    # deg

    [[metric]]
    name = "flip"                  # column name
    kind = "first_flip_time"       # see poinsot.ensemble.metrics
    component = "omega_y"

:func:`run_scenario_ensemble` writes ``chunks/*.parquet`` (one file per chunk,
atomically; together a Parquet dataset), ``summary.json`` (statistics of every
metric, failures) and a self-contained ``report.html`` (the metrics table,
histograms and metric-vs-parameter scatter charts drawn by the report viewer of
:mod:`poinsot.plotting.report`, offline, and the summary in sections).
"""

from __future__ import annotations

import html
import json
import os
import re
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._files import atomic_write
from .._progress import Progress
from ..errors import InvalidInputError
from ..plotting._report_page import chart, page_html
from ..rotations.rotation import Rotation
from ..scenarios import load_scenario
from ..scenarios._toml import locate_keys
from ..scenarios.solve import MAX_MEMORY_BYTES, _bytes, _seconds, estimate_cost
from . import dispersion as _disp
from . import metrics as _metrics
from .engine import (
    QUANTITIES,
    EnsembleError,
    EnsembleProblem,
    EnsembleResult,
    _draw,
    _nominal,
    orbit_elements,
    run,
)

if TYPE_CHECKING:
    from ..scenarios.schema import Scenario

__all__ = [
    "load_ensemble",
    "problem_from_scenario",
    "run_scenario_ensemble",
    "physical_inputs",
    "sensitivity",
]

_KINDS = ("free-body", "torqued-body", "heavy-top", "spacecraft")


def problem_from_scenario(
    scenario: Scenario, *, rtol: float = 1e-10, atol: float = 1e-12
) -> EnsembleProblem:
    """The :class:`EnsembleProblem` of a loaded scenario (its ``data`` holds the tables)."""
    where = scenario.source
    lines = _key_lines(where)

    def at(key: str, msg: str, table: Any = None) -> EnsembleError:
        """``file:line: `key` msg`` (as the scenario errors of ``run``), at the line of
        the most specific key the message names (or, for a shape that does not fit, the
        first array-valued key of ``table``)."""
        msg = msg.removeprefix(f"`{key}`: ")
        found = None
        for token in re.findall(r"`([A-Za-z_.\[\]0-9]+)`", msg):
            for cand in (token, f"{key}.{token}"):
                if cand in lines and cand.startswith(key):
                    found = cand
                    break
            if found:
                break
        if found is None and isinstance(table, dict) and "shape" in msg:
            arrays = [k for k, v in table.items() if isinstance(v, list)]
            if arrays and f"{key}.{arrays[0]}" in lines:
                found = f"{key}.{arrays[0]}"
        key = found or key
        line = lines.get(key)
        loc = f"{where}:{line}" if line else where
        return EnsembleError(f"{loc}: `{key}` {msg}")

    if scenario.kind not in _KINDS:
        raise EnsembleError(
            f"{where}: ensembles run rigid-body scenarios ({', '.join(_KINDS)}), "
            f"this one is {scenario.kind!r}."
        )
    data = scenario.data or {}
    table = data.get("dispersion", {})
    if not isinstance(table, dict):
        raise EnsembleError(f"{where}: [dispersion] must be a table of tables.")
    disps = []
    for name, sub in sorted(table.items()):
        if name not in QUANTITIES:
            raise at(
                f"dispersion.{name}",
                "unknown quantity; expected one of " + ", ".join(QUANTITIES) + ".",
            )
        try:
            disps.append((name, _disp.from_table(sub, name)))
        except InvalidInputError as exc:
            raise at(f"dispersion.{name}", str(exc)) from None
    if not disps:  # N copies of one run: refused, not run silently
        raise EnsembleError(
            f"{where}: no [dispersion] table: every sample would be the same run. An "
            f"ensemble draws its inputs from [dispersion.<quantity>] tables (quantities: "
            f"{', '.join(QUANTITIES)}; docs/ensembles.md); for one run use `poinsot run`."
        )
    mtables = data.get("metric", [])
    if not isinstance(mtables, list) or not mtables:
        raise EnsembleError(
            f"{where}: an ensemble needs at least one [[metric]] table "
            f"(kinds: {', '.join(_metrics.METRICS)})."
        )
    metric_list = []
    for i, m in enumerate(mtables):
        try:
            metric_list.append(_metrics.from_table(m, i))
        except InvalidInputError as exc:
            raise at(f"metric[{i}]", str(exc)) from None
    metrics = tuple(metric_list)
    tq = scenario.torque
    model = "none" if tq is None else tq.model
    body, spin = scenario.body, scenario.angular_velocity
    if body is None or spin is None:  # the rigid-body kinds always read both
        raise EnsembleError(f"{where}: an ensemble needs a [body] and an [angular_velocity].")
    orbit = None
    if scenario.kind == "spacecraft":
        # the [orbit] as the spacecraft kind read it (one reader of the orbit keys); the
        # attitude and rate relative to LVLH, as that kind reads them
        model, orbit = "gravity-gradient", _gravity_gradient_orbit(scenario, at)
    try:
        problem = EnsembleProblem(
            name=scenario.name,
            inertia=np.asarray(body.inertia, dtype=float),
            rotation0=np.asarray(scenario.attitude.quat, dtype=float),
            omega0=np.asarray(spin.omega_body, dtype=float),
            t=np.asarray(scenario.simulation.times(), dtype=float),
            mass=float(body.mass),
            center_of_mass=np.asarray(body.center_of_mass, dtype=float),
            torque_model=model,
            torque=np.zeros(3)
            if tq is None or tq.vector is None
            else np.asarray(tq.vector, dtype=float),
            g=9.80665 if tq is None or tq.g is None else float(tq.g),
            rtol=rtol,
            atol=atol,
            dispersions=tuple(disps),
            metrics=metrics,
            orbit=orbit,
        )
    except InvalidInputError as exc:
        raise EnsembleError(f"{where}: {exc}") from None
    # every dispersion is drawn once here, so bad parameters fail before any work

    for name, d in disps:
        try:
            _draw(replace(problem, dispersions=((name, d),)), np.random.default_rng(0), 2)
        except InvalidInputError as exc:
            raise at(f"dispersion.{name}", str(exc), table.get(name)) from None
    # dispersions of zero spread (sigma = 0, one choice...): the samples would all be equal
    drawn = _draw(problem, np.random.default_rng(0), 8)
    if not any(np.ptp(drawn[name], axis=0).max() > 0 for name, _ in disps):
        raise EnsembleError(
            f"{where}: zero spread in "
            f"{', '.join(f'[dispersion.{n}]' for n, _ in disps)}: every sample would be "
            f"the same run. Give a spread (docs/ensembles.md); for one run use `poinsot run`."
        )
    return problem


def _gravity_gradient_orbit(scenario: Scenario, at: Callable[..., EnsembleError]) -> Any:
    """The orbit elements of a ``spacecraft`` scenario an ensemble runs: the gravity
    gradient alone, judged in LVLH (what else the kind reads is refused, by key)."""
    spec = scenario.spec
    if spec.frame != "lvlh":
        raise at("orbit.frame", 'ensembles judge the pointing in "lvlh" only.')
    if not spec.gravity_gradient:
        raise at("environment.gravity_gradient", "ensembles of a spacecraft run the gravity "
                 "gradient: it must be true.")  # fmt: skip
    if spec.dipole is not None:
        raise at("environment.dipole", "ensembles of a spacecraft run the gravity gradient "
                 "alone (no magnetic dipole).")  # fmt: skip
    if spec.law != "none" or spec.wheels is not None:
        raise at("control", "ensembles of a spacecraft run the free attitude under the "
                 "gravity gradient (no control law, no wheels).")  # fmt: skip
    return orbit_elements(spec.orbit)


#: Most samples of one ensemble (a hard limit, as ``run``'s output samples).
MAX_ENSEMBLE_SAMPLES = 100_000_000
#: Longest estimated wall time without ``--allow-large`` (s).
MAX_ENSEMBLE_SECONDS = 3600.0


def ensemble_problems(
    scenario: Scenario,
    problem: EnsembleProblem,
    samples: int,
    chunk_size: int,
    out: str | os.PathLike[str] | None,
    allow_large: bool = False,
) -> list[str]:
    """What makes an ensemble too large to start (empty: it may go ahead).

    The same limits as ``poinsot run`` (docs/cli.md, "Limits"), per ensemble:
    ``samples`` <= :data:`MAX_ENSEMBLE_SAMPLES` always; unless ``allow_large``, the
    memory (the per-sample table held at the end, twice, and one chunk's states)
    <= 2 GiB, the Parquet files <= 2 GiB, and the estimated time (the scenario's cost
    estimate per sample, on the cores there are) <= one hour. Never more disk than
    is free where ``out`` goes.
    """
    import shutil

    if samples > MAX_ENSEMBLE_SAMPLES:
        return [f"{samples:.3g} samples exceed the limit of {MAX_ENSEMBLE_SAMPLES:.3g}"]
    columns = (
        4
        + len(problem.metrics)
        + sum(
            int(np.size(np.asarray(_nominal_of(problem, name)))) for name, _ in problem.dispersions
        )
    )
    n_t = int(problem.t.size)
    table_bytes = samples * columns * 8
    memory = 2 * table_bytes + 2 * min(chunk_size, samples) * n_t * 7 * 8
    per_sample = estimate_cost(scenario).seconds
    seconds = samples * per_sample / max(os.cpu_count() or 1, 1)
    out_dir = Path(out) if out is not None else Path.cwd()
    probe = next((p for p in (out_dir, *out_dir.parents) if p.exists()), Path.cwd())
    problems = []
    free = shutil.disk_usage(probe).free
    if table_bytes > free:
        problems.append(
            f"its files need ~{_bytes(table_bytes)}, more than the {_bytes(free)} free there"
        )
    if allow_large:
        return problems
    if memory > MAX_MEMORY_BYTES:
        problems.append(
            f"it needs ~{_bytes(memory)} of memory, more than the limit of "
            f"{_bytes(MAX_MEMORY_BYTES)} (--allow-large to run it anyway)"
        )
    if table_bytes > MAX_MEMORY_BYTES:
        problems.append(
            f"its files need ~{_bytes(table_bytes)} of disk, more than the limit of "
            f"{_bytes(MAX_MEMORY_BYTES)} (--allow-large to run it anyway)"
        )
    if seconds > MAX_ENSEMBLE_SECONDS:
        problems.append(
            f"it would take ~{_seconds(seconds)} (estimated), more than the limit of "
            f"{_seconds(MAX_ENSEMBLE_SECONDS)} (fewer --samples, or --allow-large)"
        )
    return problems


def _nominal_of(problem: EnsembleProblem, name: str) -> Any:
    return _nominal(problem, name)


def _key_lines(source: str) -> dict[str, int]:
    """Lines of the keys of the scenario file ``source`` (empty if it is not a file)."""

    try:
        return locate_keys(Path(source).read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError):
        return {}


def load_ensemble(
    path: str | os.PathLike[str], *, allow_paths: bool = False
) -> tuple[Scenario, EnsembleProblem]:
    """``(scenario, problem)`` of a scenario file with ``[dispersion]`` and ``[[metric]]``."""

    scenario = load_scenario(path, allow_paths=allow_paths)
    return scenario, problem_from_scenario(scenario)


_MAX_POINTS = 4000  # points kept per scatter chart (an even subset beyond that)


def physical_inputs(problem: EnsembleProblem, result: EnsembleResult) -> dict[str, Any]:
    """The dispersed inputs of every sample as physical quantities:
    ``{name: (values (n,), unit, what)}``. Vectors by component (``omega0_x``, rad/s);
    the attitude as ``attitude_offset``, the rotation angle (deg) from the nominal
    attitude, ``|log(R_nominal^-1 R)|``, not as quaternion components. Only inputs
    that vary are listed."""

    out: dict[str, Any] = {}
    for name, _d in problem.dispersions:
        unit, _shape, what = QUANTITIES[name]
        if name == "attitude":
            q = np.column_stack([result.column(f"attitude_{c}") for c in "wxyz"])
            nominal = Rotation.from_quat(np.asarray(problem.rotation0, dtype=float))
            angle = (nominal.inv() * Rotation.from_quat(q)).magnitude()
            out["attitude_offset"] = (np.degrees(np.asarray(angle)), "deg",
                                      "rotation angle from the nominal attitude")  # fmt: skip
            continue
        cols = [c for c in result.table.column_names if c == name or c.startswith(name + "_")]
        for c in cols:
            v = np.asarray(result.column(c), dtype=float)
            if np.ptp(v) > 0:
                out[c] = (v, unit, what)
    return out


def sensitivity(
    problem: EnsembleProblem, result: EnsembleResult, inputs: dict[str, Any]
) -> dict[str, list[tuple[str, float]]]:
    """For each metric, the inputs ranked by ``|rho|``, Spearman's rank correlation of
    the metric with the input over the samples that did not fail and have a finite
    metric: ``rho = 1 - 6 sum d_i^2 / (n (n^2 - 1))`` for ranks without ties
    (``scipy.stats.spearmanr``, ties averaged). It measures a monotonic influence:
    ``|rho|`` near 1, the metric follows the input; near 0, no monotonic link."""
    from scipy.stats import spearmanr

    failed = result.column("failed")
    out: dict[str, list[tuple[str, float]]] = {}
    for m in problem.metrics:
        v = np.asarray(result.column(m.name), dtype=float)
        good = ~failed & np.isfinite(v)
        ranked = []
        for name, (x, _unit, _what) in inputs.items():
            if good.sum() < 3 or np.ptp(x[good]) == 0 or np.ptp(v[good]) == 0:
                continue
            rho = float(spearmanr(x[good], v[good]).statistic)
            if np.isfinite(rho):
                ranked.append((name, rho))
        out[m.name] = sorted(ranked, key=lambda p: -abs(p[1]))
    return out


def _dispersion_rows(problem: EnsembleProblem, inputs: dict[str, Any]) -> str:
    """HTML rows: each input's distribution as given and its spread over the samples."""

    given = {}
    for name, d in problem.dispersions:
        params = ", ".join(
            f"{key} = {np.asarray(value).tolist()}"
            for key, value in vars(d).items()
            if value is not None
        )
        given[name] = f"{type(d).__name__}({params})"
    rows = []
    for col, (v, unit, _what) in inputs.items():
        base = "attitude" if col == "attitude_offset" else col.rsplit("_", 1)[0]
        base = col if col in given else base
        nominal = np.asarray(_nominal(problem, base), dtype=float)
        k = "xyz".find(col[-1]) if nominal.ndim == 1 and col != base else -1
        nom = "0" if col == "attitude_offset" else f"{float(nominal[k] if k >= 0 else nominal):.6g}"
        rows.append(
            f"<tr><td>{html.escape(col)}</td><td>{html.escape(unit)}</td>"
            f"<td>{html.escape(given.get(base, ''))}</td><td>{nom}</td>"
            f"<td>{np.mean(v):.6g}</td><td>{np.std(v):.3g}</td>"
            f"<td>{np.min(v):.6g}</td><td>{np.max(v):.6g}</td></tr>"
        )
    return ('<table class="summary"><tr><th>input</th><th>unit</th><th>dispersion</th>'
            "<th>nominal</th><th>mean</th><th>std</th><th>min</th><th>max</th></tr>"
            + "".join(rows) + "</table>")  # fmt: skip


def _charts(
    problem: EnsembleProblem, result: EnsembleResult, inputs: dict[str, Any] | None = None
) -> list[dict[str, Any]]:
    """Charts of the report viewer: a histogram of every metric and every metric
    against every dispersed physical input (:func:`physical_inputs`)."""

    failed = result.column("failed")
    inputs = physical_inputs(problem, result) if inputs is None else inputs
    out = []
    for m in problem.metrics:
        v = result.column(m.name)
        good = ~failed & np.isfinite(v)
        never = int((~failed & ~np.isfinite(v)).sum())
        title = f"Histogram of {m.name}: {int(good.sum())} samples" + (
            f", {never} never" if never else ""
        )
        if good.any():
            bins = min(50, max(5, int(np.sqrt(good.sum()))))
            lo, hi = float(v[good].min()), float(v[good].max())
            if hi <= lo:
                lo, hi = lo - 0.5 * (abs(lo) or 1.0), hi + 0.5 * (abs(hi) or 1.0)
            counts, edges = np.histogram(v[good], bins=bins, range=(lo, hi))
            out.append(chart(title, "samples", [(m.name, edges, counts, "#4477aa", "bars")],
                             x_name=m.name, x_units=m.unit))  # fmt: skip
        idx = np.flatnonzero(good)
        if idx.size > _MAX_POINTS:
            idx = idx[np.linspace(0, idx.size - 1, _MAX_POINTS).astype(int)]
        for p, (x, unit, _what) in inputs.items():
            if idx.size == 0:
                continue
            out.append(chart(f"{m.name} against {p}", m.unit,
                             [(f"{m.name} ({idx.size} samples)", x[idx], v[idx], "#aa3377",
                               "markers")], x_name=p,
                             x_units="" if unit == "1" else unit))  # fmt: skip
    return out


def _report(problem: EnsembleProblem, result: EnsembleResult, path: Path) -> None:
    """``report.html``: the metrics table, the charts (drawn by the report viewer of
    poinsot.plotting, offline) and the summary in sections with the raw JSON."""

    rows = []
    for name, s in result.summary["metrics"].items():
        q = s["quantiles"]
        rows.append(
            f"<tr><td>{html.escape(name)}</td><td>{s['unit']}</td><td>{s['count']}</td>"
            f"<td>{s['never']}</td><td>{s['mean']:.6g}</td><td>{s['std']:.3g}</td>"
            + "".join(f"<td>{q[k]:.6g}</td>" for k in ("5%", "50%", "95%"))
            + "</tr>"
        )
    s = result.summary
    inputs = physical_inputs(problem, result)
    ranking = sensitivity(problem, result, inputs)
    table = ('<table class="summary"><tr><th>metric</th><th>unit</th><th>samples</th>'
             "<th>never</th><th>mean</th><th>std</th><th>5%</th><th>median</th><th>95%</th>"
             f"</tr>{''.join(rows)}</table>")  # fmt: skip
    table += "<h2>Dispersed inputs</h2>" + _dispersion_rows(problem, inputs)
    rank_rows = "".join(
        f"<tr><td>{html.escape(metric)}</td><td>"
        + ", ".join(f"{html.escape(name)} ({rho:+.2f})" for name, rho in ranked)
        + "</td></tr>"
        for metric, ranked in ranking.items()
    )
    table += (
        "<h2>Which input matters most</h2><p>Inputs ranked by |rho|, Spearman's rank "
        "correlation of the metric with the input over the samples that did not fail "
        "(+1: the metric rises with the input, -1: falls, 0: no monotonic link; an "
        "influence that is symmetric about the nominal value, such as a tilt either way, "
        "shows as rho near 0: read it in the scatter charts below).</p>"
        '<table class="summary"><tr><th>metric</th><th>inputs, most influential first '
        f"(rho)</th></tr>{rank_rows}</table>"
    )
    reasons = s.get("failure_reasons") or {}
    table += f"<h2>Failed samples: {s['failures']} of {s['samples']}</h2>" + (
        "<ul>" + "".join(f"<li>{n} x {html.escape(r)}</li>" for r, n in reasons.items()) + "</ul>"
        if reasons
        else "<p>None: every sample ran to the end with finite metrics or a stated 'never'.</p>"
    )
    meta = (f"{s['samples']} samples in chunks of {s['chunk_size']}, seed {s['seed']}; "
            f"{s['failures']} failed; integrator: {html.escape(s['integrator'])}. Metrics "
            "are defined in the poinsot documentation (ensembles page); attitude angles in "
            "degrees, times in seconds, theory in docs/theory.md §10.")  # fmt: skip
    payload = {"t": "", "q": "", "qref": None, "t0": 0.0, "t1": 1.0, "scene": None,
               "panels": _charts(problem, result, inputs), "interval": 40}  # fmt: skip
    page = page_html(
        title=f"poinsot ensemble: {problem.name}",
        meta=meta,
        lead=table,
        notes=["Hover a chart to read its values; click a legend item to hide a series."],
        payload=payload,
        summary=s,
        animated=False,
    )
    atomic_write(path, lambda fh: fh.write(page))


def run_scenario_ensemble(
    path: str | os.PathLike[str],
    samples: int,
    out: str | os.PathLike[str],
    *,
    chunk_size: int = 1000,
    scheduler: str | None = None,
    workers: int | None = None,
    seed: int = 0,
    resume: bool = False,
    client: Any = None,
    timeout: float = 10.0,
    progress: Progress = None,
    on_chunk: Callable[[int, int], object] | None = None,
    allow_paths: bool = False,
    allow_large: bool = False,
) -> EnsembleResult:
    """Run the ensemble of a scenario file and write its outputs into ``out``
    (``allow_paths`` as in :func:`poinsot.scenarios.load_scenario`; ``progress``,
    ``on_chunk`` and Ctrl-C as in :func:`run`).

    Refused up front (:class:`EnsembleError`, before anything is written) when it
    exceeds the limits of :func:`ensemble_problems`, unless ``allow_large``.
    """
    scenario, problem = load_ensemble(path, allow_paths=allow_paths)
    problems = ensemble_problems(scenario, problem, samples, chunk_size, out, allow_large)
    if problems:
        raise EnsembleError(f"{scenario.source}: the ensemble is too large: " + "; ".join(problems))
    result = run(
        problem,
        samples,
        chunk_size=chunk_size,
        client=client,
        scheduler=scheduler,
        workers=workers,
        seed=seed,
        out=out,
        resume=resume,
        timeout=timeout,
        progress=progress,
        on_chunk=on_chunk,
    )
    outp = Path(out)
    _report(problem, result, outp / "report.html")
    summary = json.dumps(result.summary, indent=2, allow_nan=True)
    atomic_write(outp / "summary.json", lambda fh: fh.write(summary))
    return result
