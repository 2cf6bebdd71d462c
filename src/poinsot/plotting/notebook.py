"""poinsot in Jupyter: the report's viewer inside a cell, and live explorers.

:func:`show` draws any result (or a :class:`~poinsot.plotting.ReportSpec`) with the
viewer of ``report.html`` (the same page, the same JavaScript:
:func:`poinsot.plotting.report.report_html`) in an ``<iframe srcdoc>``: offline (the
script and the data are inlined, nothing is fetched), and each cell's viewer is
isolated from the others'. ``result.show()`` is a shorthand.

:func:`explore` (needs ``pip install 'poinsot[notebook]'``: ipywidgets) puts sliders
over one of five classical motions and redraws the viewer from the library's exact
solutions when a slider is released: the tennis-racket flip and the free symmetric
top (Euler-Poinsot), the Lagrange top, the Foucault pendulum (linear theory) and a
Kepler orbit (docs/theory.md §9-§10).
"""

from __future__ import annotations

import dataclasses
import html
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from ..dynamics import (
    CentralOrbit,
    FreeRigidBody,
    LagrangeTop,
    foucault_pendulum,
    foucault_precession_rate,
    kepler,
)
from ..errors import InvalidInputError, InvalidTypeError, PoinsotError
from ..trajectory import CoordinateTrajectory, PointTrajectory, Result, Trajectory
from .report import report_html
from .spec import BodyLayer, Drawing, ReportSpec

PRESETS = ("racket", "symmetric-top", "lagrange-top", "foucault", "kepler")


#: What a blank viewer means (docs/notebook.md, "Untrusted notebooks").
UNTRUSTED_NOTE = (
    "If the view is blank, the notebook is not trusted (Jupyter then shows no frames or "
    "scripts in outputs): trust it (JupyterLab: File > Trust Notebook; Classic: "
    "File > Trust Notebook; `jupyter trust NOTEBOOK`), or save the page with "
    ".save('report.html') and open that in a browser."
)


class Viewer:
    """The report's viewer for a notebook cell (an ``<iframe srcdoc>``).

    Attributes
    ----------
    html : str
        The full, self-contained page (the same as ``report.html``).
    height : int
        Height of the frame in the notebook (pixels).
    """

    def __init__(self, page: str, height: int = 640) -> None:
        self.html = page
        self.height = int(height)

    def _repr_html_(self) -> str:
        # sandboxed, scripts only: the page reaches neither the notebook nor a network.
        # An untrusted notebook strips frames and scripts from its outputs: the note under
        # the frame (plain HTML, kept) then says why the view is blank and what to do
        return (
            f'<iframe class="poinsot-viewer" srcdoc="{html.escape(self.html, quote=True)}" '
            f'style="width:100%;height:{self.height}px;border:1px solid #ddd" '
            'sandbox="allow-scripts"></iframe>'
            f'<p class="poinsot-untrusted" style="font-size:11px;color:#666;margin:2px 0">'
            f"{html.escape(UNTRUSTED_NOTE)}</p>"
        )

    def _repr_mimebundle_(self, **kwargs: Any) -> dict[str, str]:
        """HTML (the viewer) and, where HTML is not shown, text saying what it holds."""
        return {"text/html": self._repr_html_(), "text/plain": repr(self) + ". " + UNTRUSTED_NOTE}

    def save(self, path: str | Path) -> Path:
        """Write the page to ``path`` (an HTML file that opens in any browser)."""
        return atomic_write(Path(path), lambda fh: fh.write(self.html))

    def __repr__(self) -> str:
        return f"Viewer({len(self.html)} characters of HTML; shown in a notebook cell)"


def show(result: Result | ReportSpec, *, height: int = 640, **options: Any) -> Viewer:
    """Draw a result with the report's viewer, inline in a notebook.

    Parameters
    ----------
    result : Result or ReportSpec
        Any poinsot result of ONE motion: a rigid body (:class:`~poinsot.Trajectory`,
        drawn as a turning body), a point (drawn as a path), a pose, or a system in
        generalized coordinates (its coordinates and rates as charts). Or a
        :class:`~poinsot.plotting.ReportSpec`, drawn as it says (no ``options``).
    height : int, optional
        Height of the cell's frame in pixels (default 640).
    **options
        With a result: the keyword form of :func:`poinsot.plotting.report.report_html`
        (``inertia``, ``mass``, ``shape``, ``reference``, ``title``, ``euler_seq``...).

    Returns
    -------
    Viewer
        Displays itself in Jupyter; ``.html`` is the page, ``.save(path)`` writes it.

    Notes
    -----
    **Convention:** as the report: scene in space axes, ``w`` in body axes drawn in
    space axes, SI units, angles plotted in degrees (docs/cli.md, "The report").

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody
    >>> from poinsot.plotting import show
    >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 4.0, 0.1])
    >>> v = show(body.trajectory(np.linspace(0, 5, 201)), inertia=[1.0, 2.0, 3.0], mass=1.0)
    >>> v._repr_html_().startswith('<iframe class="poinsot-viewer"'), "<script src=" in v.html
    (True, False)
    >>> from poinsot.plotting import BodyLayer, ReportSpec
    >>> tr = body.trajectory(np.linspace(0, 5, 201))
    >>> "flip" in show(ReportSpec(tr, BodyLayer(inertia=[1.0, 2.0, 3.0]), title="flip")).html
    True
    """
    if not isinstance(result, Result | ReportSpec):
        raise InvalidTypeError(
            f"Expected `result` to be a poinsot result (Trajectory, PointTrajectory...) or a "
            f"ReportSpec, got {type(result).__name__}."
        )
    if not (isinstance(height, int) and 100 <= height <= 4000):
        raise InvalidInputError(
            f"Expected `height` to be an integer in [100, 4000], got {height!r}."
        )
    if isinstance(result, ReportSpec):
        if options:
            raise InvalidTypeError(
                f"Expected no options with a ReportSpec, got {', '.join(sorted(options))} "
                "(change the spec with dataclasses.replace)."
            )
        return Viewer(report_html(result), height)
    if isinstance(result, Trajectory) and result.rotation.shape[1:] != ():
        raise InvalidInputError(
            f"Expected one body, got a batch of shape {result.rotation.shape[1:]}: "
            "show one, e.g. poinsot.Trajectory(tr.t, tr.rotation[:, 0], tr.omega[:, 0], tr.method)."
        )
    opts = dict(options)
    opts.setdefault("title", f"{type(result).__name__}: {result.method}")
    if isinstance(result, Trajectory) and "free_body" not in opts:
        opts["free_body"] = False  # the polhode only when the caller says it is torque-free
    if isinstance(result, CoordinateTrajectory) and "series" not in opts:
        opts["series"] = _coordinate_series(result)
    if isinstance(result, PointTrajectory) and "series" not in opts:
        if np.ndim(result.position) != 2:
            raise InvalidInputError(
                f"Expected one point, got a batch of shape {np.shape(result.position)[1:-1]}: "
                "show one (index the batch of position and velocity)."
            )
        opts["series"] = _point_series(result)
    return Viewer(report_html(trajectory=result, **opts), height)


def _point_series(result: PointTrajectory) -> list[tuple[str, str, dict[str, Any]]]:
    """Charts of a point's motion: position with the distance ``|r|`` from the origin,
    velocity with the speed, in the result's frame, and the energy where it is given."""
    where = f"{result.frame_name} axes"
    r = np.asarray(result.position, dtype=float)
    v = np.asarray(result.velocity, dtype=float)
    out: list[tuple[str, str, dict[str, Any]]] = [
        (f"position, {where}, and distance |r| (m)", "m",
         {"x": r[:, 0], "y": r[:, 1], "z": r[:, 2], "|r|": np.linalg.norm(r, axis=-1)}),
        (f"velocity, {where}, and speed |v| (m/s)", "m/s",
         {"vx": v[:, 0], "vy": v[:, 1], "vz": v[:, 2], "|v|": np.linalg.norm(v, axis=-1)}),
    ]  # fmt: skip
    if result.energy is not None and np.ndim(result.energy) == 1:
        out.append(("energy (J)", "J", {"energy": np.asarray(result.energy, dtype=float)}))
    return out


def _coordinate_series(result: CoordinateTrajectory) -> list[tuple[str, str, dict[str, Any]]]:
    """Charts of the coordinates and of the rates, one per unit."""
    groups: dict[tuple[str, str], dict[str, Any]] = {}
    for name, ch in result.state_channels().items():
        kind = "rates" if name.endswith("_dot") else "coordinates"
        groups.setdefault((kind, ch.units), {})[name] = np.asarray(ch.values, dtype=float)
    return [(f"{kind} ({units or 'no unit'})", units or "1", series)
            for (kind, units), series in groups.items()]  # fmt: skip


# --------------------------------------------------------------------------- explore


@dataclass(frozen=True)
class Slider:
    """One slider of an explorer: name, label with units, range and start value."""

    name: str
    label: str
    lo: float
    hi: float
    value: float
    step: float


def _free_body(p: Mapping[str, float]) -> ReportSpec:
    moments = [p["A"], p["B"], p["C"]]
    body = FreeRigidBody(moments, omega0=[p["w1"], p["w2"], p["w3"]])
    t = np.linspace(0.0, p["duration"], 601)
    caption = f"{body.regime} regime, period of omega {body.period:.4g} s"
    return ReportSpec(body.trajectory(t), BodyLayer(inertia=moments, mass=1.0, polhode=True),
                      title=caption)  # fmt: skip


def _lagrange_top(p: Mapping[str, float]) -> ReportSpec:
    m, g, l_ = 1.0, 9.80665, p["l"]
    a_cm, c = p["A"], p["C"]
    a_o = a_cm + m * l_ * l_
    top = LagrangeTop(a_o, c, m * g * l_, theta=p["theta"], spin=p["spin"],
                      precession_rate=p["precession"], degrees=True)  # fmt: skip
    t = np.linspace(0.0, p["duration"], 801)
    tr = top.trajectory(t)
    axis = tr.rotation.apply(np.array([0.0, 0.0, 2.0 * l_]))
    drawing = Drawing({"tip": axis, "O": np.zeros_like(axis)}, (("O", "tip"),), ("tip",))
    caption = f"{top.motion_type}, nutation period {top.nutation_period:.4g} s"
    body = BodyLayer(inertia=[a_cm, a_cm, c], mass=m, center_of_mass=[0.0, 0.0, l_],
                     fixed_point=True)  # fmt: skip
    return ReportSpec(tr, body, euler_seq="ZXZ", drawing=drawing, title=caption)


def _foucault(p: Mapping[str, float]) -> ReportSpec:
    t = np.linspace(0.0, p["duration"], 1201)
    tr = foucault_pendulum(p["length"], p["latitude"], t, omega=p["rate"], degrees=True,
                           amplitude=0.1 * p["length"])  # fmt: skip
    rate = float(foucault_precession_rate(p["latitude"], omega=p["rate"], degrees=True))
    drawing = Drawing({"bob": np.asarray(tr.position)}, trails=("bob",))
    return ReportSpec(tr, drawing=drawing, title=f"swing plane turns at {rate:.4g} rad/s")


def _kepler(p: Mapping[str, float]) -> ReportSpec:
    e = p["e"]
    rp = 1.0 - e
    orbit = CentralOrbit.from_state(
        kepler(1.0), [rp, 0.0, 0.0], [0.0, math.sqrt((1 + e) / rp), 0.0]
    )
    t = np.linspace(0.0, p["duration"], 1201)
    return ReportSpec(orbit.trajectory(t), title=f"e = {e:.3g}, period {orbit.radial_period:.4g} s")


#: preset -> (its report from the sliders' values, the sliders)
_PRESETS: dict[str, tuple[Callable[[Mapping[str, float]], ReportSpec], tuple[Slider, ...]]] = {
    "racket": (_free_body, (
        Slider("A", "A (kg m^2)", 0.5, 3.0, 1.0, 0.05),
        Slider("B", "B (kg m^2)", 0.5, 3.0, 2.0, 0.05),
        Slider("C", "C (kg m^2)", 0.5, 3.0, 3.0, 0.05),
        Slider("w1", "w1 (rad/s)", -2.0, 2.0, 0.05, 0.01),
        Slider("w2", "w2 (rad/s)", -6.0, 6.0, 4.0, 0.1),
        Slider("w3", "w3 (rad/s)", -2.0, 2.0, 0.05, 0.01),
        Slider("duration", "duration (s)", 1.0, 40.0, 12.0, 0.5),
    )),
    "symmetric-top": (_free_body, (
        Slider("A", "A = B (kg m^2)", 0.5, 3.0, 2.0, 0.05),
        Slider("B", "B (kg m^2)", 0.5, 3.0, 2.0, 0.05),
        Slider("C", "C (kg m^2)", 0.5, 3.0, 1.0, 0.05),
        Slider("w1", "w1 (rad/s)", -2.0, 2.0, 0.5, 0.01),
        Slider("w2", "w2 (rad/s)", -2.0, 2.0, 0.0, 0.01),
        Slider("w3", "spin w3 (rad/s)", -6.0, 6.0, 3.0, 0.1),
        Slider("duration", "duration (s)", 1.0, 40.0, 10.0, 0.5),
    )),
    "lagrange-top": (_lagrange_top, (
        Slider("A", "A about the centre of mass (kg m^2)", 0.01, 0.2, 0.05, 0.005),
        Slider("C", "C (kg m^2)", 0.01, 0.1, 0.02, 0.005),
        Slider("l", "centre of mass distance l (m)", 0.02, 0.3, 0.1, 0.01),
        Slider("spin", "spin r (rad/s)", 0.0, 150.0, 60.0, 1.0),
        Slider("theta", "initial tilt (deg)", 1.0, 90.0, 40.0, 1.0),
        Slider("precession", "initial precession rate (rad/s)", -5.0, 5.0, 0.0, 0.1),
        Slider("duration", "duration (s)", 0.5, 10.0, 2.0, 0.1),
    )),
    "foucault": (_foucault, (
        Slider("latitude", "latitude (deg)", -90.0, 90.0, 48.85, 0.5),
        Slider("length", "length (m)", 1.0, 100.0, 10.0, 1.0),
        Slider("rate", "frame rotation rate (rad/s, exaggerated)", 0.0, 0.2, 0.05, 0.005),
        Slider("duration", "duration (s)", 10.0, 300.0, 60.0, 5.0),
    )),
    "kepler": (_kepler, (
        Slider("e", "eccentricity", 0.0, 0.97, 0.5, 0.01),
        Slider("duration", "duration (s)", 1.0, 40.0, 12.6, 0.2),
    )),
}  # fmt: skip


class Explorer:
    """Sliders over a classical motion and the viewer, redrawn from the exact solution.

    Attributes
    ----------
    preset : str
    widget : ipywidgets.VBox
        The sliders, the viewer (an ``HTML`` widget holding the ``<iframe>``) and a
        status line (motion type, time to recompute).
    sliders : dict
        ``name -> ipywidgets.FloatSlider``.
    last_seconds : float
        Time of the last recomputation and page build (s).
    """

    def __init__(self, preset: str, values: Mapping[str, float], height: int) -> None:
        try:
            import ipywidgets as w
        except ImportError as exc:
            raise PoinsotError(
                f"explore() needs ipywidgets: pip install 'poinsot[notebook]' ({exc})"
            ) from exc
        self.preset = preset
        self._compute, specs = _PRESETS[preset]
        self.height = height
        self.sliders = {
            s.name: w.FloatSlider(
                value=float(values.get(s.name, s.value)), min=s.lo, max=s.hi, step=s.step,
                description=s.label, continuous_update=False, readout_format=".4g",
                style={"description_width": "16em"}, layout=w.Layout(width="36em"),
            )
            for s in specs
        }  # fmt: skip
        self.view = w.HTML()
        self.status = w.HTML()
        self.widget = w.VBox([*self.sliders.values(), self.status, self.view])
        self.last_seconds = math.nan
        for s in self.sliders.values():
            s.observe(self._changed, names="value")
        self.update()

    def values(self) -> dict[str, float]:
        """The sliders' current values."""
        return {k: float(s.value) for k, s in self.sliders.items()}

    def update(self) -> None:
        """Recompute the motion from the sliders and redraw the viewer."""
        t0 = time.perf_counter()
        try:
            spec = self._compute(self.values())
            title = spec.title
            page = report_html(dataclasses.replace(spec, title=f"{self.preset}: {title}"))
        except PoinsotError as exc:  # a slider combination outside the model: say so
            self.status.value = f"<span style='color:#b00'>{html.escape(str(exc))}</span>"
            return
        self.view.value = Viewer(page, self.height)._repr_html_()
        self.last_seconds = time.perf_counter() - t0
        self.status.value = (
            f"<span class='poinsot-status'>{html.escape(title)}; recomputed in "
            f"{self.last_seconds * 1e3:.0f} ms</span>"
        )

    def _changed(self, change: Any) -> None:
        self.update()

    def _repr_mimebundle_(self, **kwargs: Any) -> Any:
        bundle = self.widget._repr_mimebundle_(**kwargs)
        if isinstance(bundle, dict):  # where widgets cannot run, not 'VBox(children=...)'
            bundle["text/plain"] = (
                f"{self!r}: sliders and a viewer, shown where Jupyter runs widgets in a "
                "trusted notebook (ipywidgets installed, docs/notebook.md). Elsewhere: "
                "show(...) of a result, or report_html(...) saved to a file."
            )
        return bundle

    def __repr__(self) -> str:
        return f"Explorer({self.preset!r}, {self.values()})"


def explore(preset: str = "racket", *, height: int = 560, **values: float) -> Explorer:
    """Sliders over a classical motion, redrawn from the library's exact solutions.

    Parameters
    ----------
    preset : {"racket", "symmetric-top", "lagrange-top", "foucault", "kepler"}
        The tennis-racket flip and the free symmetric top (principal moments, initial
        angular velocity in body axes, duration: :class:`~poinsot.dynamics.FreeRigidBody`);
        the Lagrange top (moments about the centre of mass, its distance ``l`` from the
        fixed point, spin, initial tilt in degrees and precession rate:
        :class:`~poinsot.dynamics.LagrangeTop`, loops, cusps or regular precession); the
        Foucault pendulum (latitude in degrees, length, an exaggerated rotation rate:
        :func:`~poinsot.dynamics.foucault_pendulum`); a Kepler orbit (eccentricity, with
        ``mu = 1 m^3/s^2`` and ``a = 1 m``: :class:`~poinsot.dynamics.CentralOrbit`).
    height : int, optional
        Height of the viewer (pixels).
    **values : float
        Start values of the sliders, by name (``A``, ``w2``, ``spin``, ``e``...).

    Returns
    -------
    Explorer
        Displays itself (the widget); redraws when a slider is released.

    Raises
    ------
    PoinsotError
        Without ipywidgets (``pip install 'poinsot[notebook]'``).
    InvalidInputError
        An unknown preset or slider name, or a value outside its slider's range.

    Examples
    --------
    >>> from poinsot.plotting import explore
    >>> ex = explore("kepler", e=0.3)
    >>> sorted(ex.sliders), ex.values()["e"]
    (['duration', 'e'], 0.3)
    >>> ex.sliders["e"].value = 0.6        # what moving the slider does
    >>> "e = 0.6" in ex.status.value, "<iframe" in ex.view.value
    (True, True)
    """
    if preset not in _PRESETS:
        raise InvalidInputError(f"Expected `preset` in {', '.join(PRESETS)}, got {preset!r}.")
    specs = {s.name: s for s in _PRESETS[preset][1]}
    for name, v in values.items():
        if name not in specs:
            raise InvalidInputError(
                f"Expected slider names of {preset!r} ({', '.join(specs)}), got {name!r}."
            )
        s = specs[name]
        if not (isinstance(v, int | float) and s.lo <= v <= s.hi):
            raise InvalidInputError(
                f"Expected `{name}` in [{s.lo}, {s.hi}] ({s.label}), got {v!r}."
            )
    return Explorer(preset, values, height)
