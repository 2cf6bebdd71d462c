"""``report.html`` of a scenario run: the kind says what to show, plotting draws it.

:func:`write_scenario_report` asks the scenario's kind for a
:class:`~poinsot.scenarios.kind.ReportSpec` (:meth:`ScenarioKind.report
<poinsot.scenarios.kind.ScenarioKind.report>`: the scene, the charts, extra
sections), adds what every run shares (the title, the summary with its accuracy
warnings, the differences from the reference run on the result's own state) and
passes that spec to the generic renderer :func:`poinsot.plotting.write_report`,
which never asks what kind of scenario it draws. The helpers here (:func:`unit_charts`,
:func:`difference_charts`, :func:`figure_sections`) are shared by the kinds.
"""

from __future__ import annotations

import dataclasses
import html
import io
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..plotting import report as renderer
from ..trajectory import quantity_label
from .kind import Chart, FigureSpec

if TYPE_CHECKING:
    from .summary import ScenarioResult

__all__ = ["write_scenario_report", "unit_charts", "difference_charts", "figure_sections"]

#: Names of the quantities of a unit, for the titles of :func:`unit_charts`.
_WHAT = {"m": "position", "m/s": "velocity", "J": "energy"}


def write_scenario_report(
    path: str | os.PathLike[str],
    result: ScenarioResult,
    summary: Mapping[str, Any] | None = None,
    *,
    title: str | None = None,
) -> Path:
    """Write ``report.html`` for a scenario run (as :func:`poinsot.scenarios.write_outputs`).

    The scenario's kind chooses the scene and the charts
    (:meth:`~poinsot.scenarios.ScenarioKind.report`); the page starts with the
    run's accuracy warnings, if any (a conserved quantity that drifts, or two
    methods that disagree beyond the thresholds of ``docs/cli.md``), and, for a
    motion other than a rigid body's, charts the difference of each state
    quantity from the reference run in its units.

    Parameters
    ----------
    path : str or os.PathLike
        Output file (its directory must exist).
    result : ScenarioResult
        The run (from :func:`poinsot.scenarios.simulate_scenario`).
    summary : mapping, optional
        The summary to show (default ``result.summary``).
    title : str, optional
        Page title (default: the scenario's name and description).

    Returns
    -------
    pathlib.Path
        The path written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from poinsot.scenarios import demo_scenario, simulate_scenario
    >>> from poinsot.scenarios import write_scenario_report
    >>> res = simulate_scenario(demo_scenario(), duration=1.0)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "report.html"
    >>> write_scenario_report(out, res).name
    'report.html'
    """

    s = result.scenario
    spec = s.adapter.report(result)
    charts = tuple(spec.charts)
    if spec.reference is None:  # a rigid body's reference is drawn by the renderer
        charts += tuple(difference_charts(result))
    if title is None:
        title = f"poinsot: {s.name}" + (f" ({s.description})" if s.description else "")
    # the accuracy mark and warnings are in the page's header (from summary["accuracy"])
    summary = result.summary if summary is None else summary
    spec = dataclasses.replace(spec, charts=charts, title=title, summary=summary)
    return renderer.write_report(path, spec)


def unit_charts(columns: Mapping[str, tuple[np.ndarray, str]]) -> list[Chart]:
    """Series ``name -> (values (n,), units)`` grouped in one chart per unit, titled
    by the quantity (``"position: x, y, z"`` in m, ``"velocity: vx, vy, vz"`` in m/s).

    Examples
    --------
    >>> z = np.zeros(2)
    >>> [c.title for c in unit_charts({"x": (z, "m"), "y": (z, "m"), "vx": (z, "m/s")})]
    ['position: x, y', 'velocity: vx']
    """
    by_unit: dict[str, dict[str, np.ndarray]] = {}
    for name, (values, units) in columns.items():
        by_unit.setdefault(units or "1", {})[name] = np.asarray(values, dtype=float)
    out = []
    for units, d in by_unit.items():
        head = f"{_WHAT[units]}: " if units in _WHAT else ""
        out.append(Chart(head + ", ".join(d), units, d))
    return out


def difference_charts(result: Any) -> list[Chart]:
    """The difference of each state quantity of ``result.trajectory`` from
    ``result.reference`` at every output time, in its own units (one chart per unit;
    vectors by the norm of the difference), or none without a reference.

    Examples
    --------
    >>> from poinsot.scenarios import parse_scenario, simulate_scenario
    >>> r = simulate_scenario(parse_scenario('''
    ... [orbit]
    ... mu = 1.0
    ... position = [1.0, 0.0, 0.0]
    ... velocity = [0.0, 1.1, 0.0]
    ... [simulation]
    ... duration = 1.0
    ... samples = 11
    ... method = "exact"
    ... reference = "adaptive"
    ... '''))
    >>> [(c.units, list(c.series)) for c in difference_charts(r)]  # doctest: +NORMALIZE_WHITESPACE
    [('m', ['|position - position (adaptive)|']),
     ('m/s', ['|velocity - velocity (adaptive)|'])]
    """
    a, b = result.trajectory, result.reference
    if b is None:
        return []
    ca, cb = a.state_channels(), b.state_channels()
    groups: dict[str, dict[str, np.ndarray]] = {}
    for name, ch in ca.items():
        if name not in cb:
            continue
        d = np.asarray(ch.values, dtype=float) - np.asarray(cb[name].values, dtype=float)
        d = np.linalg.norm(d, axis=-1) if d.ndim == 2 else np.abs(d)
        shown = quantity_label(name)
        label = f"|{shown} - {shown} ({b.method})|"
        groups.setdefault(ch.units, {})[label] = d
    return [
        Chart(f"difference from the reference run ({b.method}), {units}", units, d)
        for units, d in groups.items()
    ]


def figure_sections(specs: Sequence[FigureSpec], titles: Sequence[str]) -> list[tuple[str, str]]:
    """``report.html`` sections: a kind's figures as inline SVG (offline, no files).

    ``specs`` are :class:`~poinsot.scenarios.kind.FigureSpec` objects, ``titles``
    their headings; each is drawn on a new :class:`matplotlib.figure.Figure` (no
    pyplot state). A figure that fails is replaced by a line saying why.
    """
    try:
        from matplotlib.figure import Figure
    except ImportError:  # optional dependency: the report is written without them
        why = "<p>figure skipped: matplotlib is not installed (pip install 'poinsot[plot]')</p>"
        return [(title, why) for title in titles]
    out = []
    for spec, title in zip(specs, titles, strict=True):
        fig = Figure(figsize=spec.size, layout="constrained")
        try:
            spec.draw(fig.add_subplot(projection=spec.projection))
            buf = io.StringIO()
            fig.savefig(buf, format="svg")
        except Exception as exc:  # a figure that fails never sinks the report
            msg = html.escape(f"{spec.name} skipped: {type(exc).__name__}: {exc}")
            out.append((title, f"<p>{msg}</p>"))
            continue
        svg = buf.getvalue()
        out.append((title, svg[svg.index("<svg") :]))
    return out
