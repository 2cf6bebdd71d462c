"""A self-contained interactive HTML report of a motion: a rigid body, a particle, or
any poinsot result with named time series.

:func:`write_report` writes ONE HTML file that works offline (a small built-in
viewer, plain JavaScript shipped with poinsot; no plotting library, nothing
fetched; typically 0.1-0.3 MB plus the kind's figures) holding

- an animated 3-D scene in space axes, lengths in metres, drawn on a canvas
  (drag to turn, wheel to zoom, double-click to reset): the body drawn as its
  shape (box, cylinder, disc, cone, sphere, ellipsoid, rod, ring, point masses,
  a triangle mesh, or else the uniform ellipsoid of the same mass and inertia)
  at its centre of mass, the fixed point marked where there is one, the body
  axes, the angular velocity ``w`` and angular momentum ``K`` arrows (their
  scales stated), the inertia ellipsoid as an optional layer and, for a free
  body only, the polhode and herpolhode (theory §10); for a particle, its path
  and position; a legend whose items show or hide the layers;
- time-series charts chosen by what the motion is: ``w`` in body axes, the
  attitude angles (Euler angles of a stated sequence), the conserved quantities
  of the torque model (relative change, with its maximum written: a round-off
  drift shows as "max 3e-15"), the quantities that are not conserved, the
  energy balance ``dT/dt = N . w`` of a torqued body, the torque, the attitude
  error against a reference, and any extra series (e.g. generalised coordinates);
  each chart has a time cursor that follows the animation and a hover read-out;
- Play/Pause, a frame slider and a speed control. Frames are chosen so that the
  body turns by at most ``max_frame_angle`` between two frames (a fast spin does
  not strobe); the page says the largest turn between frames;

and the run's summary in sections (units on numbers, values in words, the raw
JSON collapsible). What it draws is one :class:`~poinsot.plotting.ReportSpec`
(:mod:`poinsot.plotting.spec`; ``write_report(path, spec)``), or its keyword form
(``write_report(path, trajectory=..., inertia=...)``). The function is generic: it
draws what it is given and never asks what kind of scenario produced it
(``poinsot.scenarios.write_scenario_report`` asks the scenario's kind for its spec,
then calls it).
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from .._quat import attitude_distance
from .._validate import as_float_array, is_integer
from ..errors import InvalidInputError, InvalidTypeError
from ..errors import InvalidInputError as _Bad
from ..trajectory import Trajectory
from . import _report_shapes as shapes
from ._report_page import b64, chart, fmt_number, page_html
from .spec import BodyLayer, Chart, Drawing, ReportSpec

__all__ = ["write_report"]

#: Shapes :func:`write_report` can draw, with the meaning of their ``dims`` (m).
SHAPES = shapes.SOLIDS
_AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # body x, y, z: red, green, blue
_OMEGA_COLOUR = "#ff7f0e"
_MOMENTUM_COLOUR = "#9467bd"
_POLHODE_COLOUR = "#e377c2"
_HERPOLHODE_COLOUR = "#17becf"
_SERIES_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf")
_PALETTE = ("#8c564b", "#7f7f7f", "#bcbd22", "#17becf", "#e377c2", "#1f77b4", "#ff7f0e")
_MAX_TRACK = 400  # points kept for the polhode / herpolhode / particle path
_MAX_SERIES = 1200  # points kept per time series (min/max envelope beyond that)
_MIN_FRAMES = 120  # frames even in time, at least (fewer if fewer samples)
_MAX_MESH_FACES = 3000  # a mesh body is decimated to at most this many triangles
_FRAMES_PER_PERIOD = 24  # frames per period of a motion without attitude, at least
_TRAIL_FLOOR = 0.12  # opacity of the oldest part of a trail (the whole path stays legible)
_LINK_COLOUR = "#3a3a3a"
_DOT_COLOUR = "#d62728"
_GUIDE_COLOURS = ("#2ca02c", "#9467bd", "#ff7f0e")


def write_report(
    path: str | os.PathLike[str], spec: ReportSpec | None = None, **keywords: Any
) -> Path:
    """Write a self-contained interactive HTML report of a motion.

    Parameters
    ----------
    path : str or os.PathLike
        Output file (conventionally ``report.html``), written atomically (a
        temporary name in the same directory, then renamed). Its directory must exist.
    spec : ReportSpec
        What the page shows (:class:`~poinsot.plotting.ReportSpec`): the motion, the
        rigid body, the charts, the drawing, the checks, the title and summary.
    **keywords
        The keyword form instead of ``spec``: ``write_report(path, trajectory=tr,
        inertia=..., mass=..., shape=..., reference=..., series=..., drawing=...)``,
        read by :meth:`ReportSpec.from_keywords <poinsot.plotting.ReportSpec.from_keywords>`.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InvalidTypeError
        If ``spec`` is not a ReportSpec (or is given with keywords), its motion is
        not a poinsot result (``reference``: not a :class:`~poinsot.Trajectory`),
        ``summary``/``shape`` of the wrong type, ``title``/``euler_seq`` not a
        string or ``max_frames`` not an integer.
    InvalidInputError
        If a trajectory holds a batch of bodies, ``shape``, ``inertia``,
        ``torque`` or ``mass`` is malformed, ``max_frames`` or
        ``max_frame_angle`` is out of range, or the directory of ``path`` does
        not exist.

    Notes
    -----
    The polhode point is ``r = e / sqrt(e^T J e)`` with ``e = w / |w|`` (the
    point of the inertia ellipsoid ``r^T J r = 1`` on the instantaneous axis,
    theory §8, §10), drawn with the ellipsoid scaled to the body's size; the
    herpolhode, its track in space, then lies in the invariable plane. The
    equivalent ellipsoid has semi-axes ``a^2 = 5 (B + C - A) / (2 m)`` (and
    cyclically). Arrows: ``w`` and ``K`` are drawn from the origin of the body
    axes, each with one scale for the whole animation, written in the legend
    (e.g. "1 rad/s = 0.05 m").

    The time scale of a motion without attitude (a particle, a drawn Lagrangian
    system) is ``P = 2 (t_end - t_0) / c``, with ``c`` the largest number of sign
    changes of one velocity component of one drawn point (components smaller than
    1e-3 of their largest value ignored): a swing, an orbit or a gyration has two
    per period. Frames are then at most ``P/24`` apart (fewer if ``max_frames``
    or the samples do not allow it: the page says so); trails fade with the age
    ``a`` of a point as ``0.12 + 0.88 exp(-a / (1.5 P))``.

    **Convention:** the scene is in space axes, ``v_space = R v_body``
    (theory §2), quaternions scalar first; ``w`` is read in body axes and drawn
    in space axes; SI units, angles plotted in degrees.

    Examples
    --------
    >>> import numpy as np, poinsot, tempfile, pathlib
    >>> from poinsot.plotting import BodyLayer, ReportSpec, write_report
    >>> t = np.linspace(0.0, 2.0, 21)
    >>> rot = poinsot.Rotation.from_rotvec(np.outer(t, [0.0, 0.0, 1.5]))
    >>> tr = poinsot.Trajectory(t, rot, np.tile([0.0, 0.0, 1.5], (21, 1)), "spin")
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "report.html"
    >>> spec = ReportSpec(tr, BodyLayer({"kind": "box", "dims": [1.0, 0.6, 0.2]}),
    ...                   summary={"method": "spin"})
    >>> p = write_report(out, spec)
    >>> text = p.read_text()
    >>> p == out, "<script src=" in text, "plotly" in text  # nothing fetched, no library
    (True, False, False)
    >>> p = write_report(out, trajectory=tr, summary={"method": "spin"},  # keyword form
    ...                  shape={"kind": "box", "dims": [1.0, 0.6, 0.2]})
    """
    if not isinstance(path, str | os.PathLike):
        raise InvalidTypeError(
            f"Expected `path` to be a str or os.PathLike, got {type(path).__name__}."
        )
    path = Path(os.fspath(path))
    if not path.parent.is_dir():
        raise InvalidInputError(
            f"Expected the directory of `path` to exist, got {str(path.parent)!r}."
        )
    if path.is_dir():
        raise InvalidInputError(f"Expected `path` to name a file, got the directory {str(path)!r}.")
    page = report_html(spec, **keywords)
    atomic_write(path, lambda fh: fh.write(page))
    return path


def report_html(spec: ReportSpec | None = None, **keywords: Any) -> str:
    """The self-contained HTML page of :func:`write_report`, as a string.

    Takes the same arguments as :func:`write_report` but ``path``: a
    :class:`~poinsot.plotting.ReportSpec`, or its keyword form. The page embeds the
    viewer's JavaScript and the data (nothing is fetched). Used by
    :func:`poinsot.plotting.show` to draw the same viewer inside a notebook cell.

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> from poinsot.plotting import ReportSpec
    >>> from poinsot.plotting.report import report_html
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> tr = poinsot.Trajectory(t, poinsot.Rotation.from_rotvec(np.outer(t, [0, 0, 1.0])),
    ...                         np.tile([0.0, 0.0, 1.0], (11, 1)), "spin")
    >>> page = report_html(ReportSpec(tr, title="spin"))
    >>> page.startswith("<!DOCTYPE html>"), "<script src=" in page
    (True, False)
    >>> report_html(trajectory=tr, title="spin", free_body=False) == page  # keyword form
    True
    """
    spec = _as_spec(spec, keywords)
    body = BodyLayer() if spec.body is None else spec.body
    if not isinstance(body, BodyLayer):
        raise InvalidTypeError(
            f"Expected `body` to be a poinsot.plotting.BodyLayer or None, got "
            f"{type(body).__name__}."
        )
    tr = _check_trajectory(spec.motion, "trajectory")
    ref = None  # a rigid body's reference only (attitude error, dashed axes)
    if spec.reference is not None and isinstance(tr, Trajectory):
        ref = _check_trajectory(spec.reference, "reference", rigid=True)
    summary, title, euler_seq = spec.summary, spec.title, spec.euler_seq
    max_frames = spec.max_frames
    if summary is not None and not isinstance(summary, Mapping):
        raise InvalidTypeError(
            f"Expected `summary` to be a mapping or None, got {type(summary).__name__}."
        )
    for name, v in (("title", title), ("euler_seq", euler_seq)):
        if not isinstance(v, str):
            raise InvalidTypeError(f"Expected `{name}` to be a string, got {type(v).__name__}.")
    if not is_integer(max_frames):
        raise InvalidTypeError(
            f"Expected `max_frames` to be an integer, got {type(max_frames).__name__}."
        )
    if not 2 <= max_frames <= 20000:
        raise InvalidInputError(f"Expected `max_frames` to be in [2, 20000], got {max_frames}.")
    max_frame_angle = float(spec.max_frame_angle)
    if not 0.0 < max_frame_angle <= 90.0:
        raise InvalidInputError(
            f"Expected `max_frame_angle` to be in (0, 90] degrees, got {max_frame_angle}."
        )
    parts = _check_shape(body.shapes)
    J = _check_inertia(body.inertia)
    mass = body.mass
    if mass is not None:
        mass = float(mass)
        if not (math.isfinite(mass) and mass > 0):
            raise InvalidInputError(f"Expected `mass` to be a positive number (kg), got {mass}.")
    com = (
        np.zeros(3)
        if body.center_of_mass is None
        else as_float_array(body.center_of_mass, "center_of_mass")
    )
    if com.shape != (3,):
        raise InvalidInputError(f"Expected `center_of_mass` to have shape (3,), got {com.shape}.")
    tq = None
    if spec.torque is not None:
        tq = as_float_array(spec.torque, "torque")
        if not isinstance(tr, Trajectory) or tq.shape != tr.omega.shape:
            wanted = tr.omega.shape if isinstance(tr, Trajectory) else "(no rigid body)"
            raise InvalidInputError(
                f"Expected `torque` to have shape {wanted} (one body-axes torque per "
                f"sample, N m), got {tq.shape}."
            )
    extra = _check_series(spec.charts, tr.t.size)
    draw = _check_drawing(spec.drawing, tr.t.size)
    with warnings.catch_warnings():  # gimbal lock of the plotted angles is not the user's
        warnings.simplefilter("ignore")
        payload, notes, meta = _build(
            tr,
            ref,
            parts,
            J,
            mass,
            com,
            bool(body.fixed_point),
            bool(body.polhode),
            tuple(spec.checks),
            tq,
            euler_seq,
            max_frames,
            max_frame_angle,
            extra,
            draw,
        )
    page = page_html(
        title=title, meta=meta, notes=notes, payload=payload, summary=summary,
        sections=spec.sections,
    )  # fmt: skip
    return page


def _as_spec(spec: Any, keywords: Mapping[str, Any]) -> ReportSpec:
    """The one spec of a call: ``spec``, or the spec of the keyword form."""
    if spec is None:
        return ReportSpec.from_keywords(**keywords)
    if not isinstance(spec, ReportSpec):
        raise InvalidTypeError(
            "Expected `spec` to be a poinsot.plotting.ReportSpec (or the keywords "
            f"trajectory=..., ...), got {type(spec).__name__}."
        )
    if keywords:
        raise InvalidTypeError(
            f"Expected a ReportSpec or keywords, not both; got {', '.join(sorted(keywords))} "
            "with a spec (change the spec with dataclasses.replace)."
        )
    return spec


# --------------------------------------------------------------------------- checks


def _check_trajectory(tr: Any, name: str, *, rigid: bool = False) -> Any:
    """A Trajectory of one body, or (``rigid`` False) another result with times ``t``
    and an optional ``position`` of shape (n, 3)."""
    if not isinstance(tr, Trajectory):
        t = getattr(tr, "t", None)
        if rigid or not (isinstance(t, np.ndarray) and t.ndim == 1 and hasattr(tr, "channels")):
            what = "a poinsot.Trajectory" + ("" if rigid else " or another poinsot result")
            raise InvalidTypeError(f"Expected `{name}` to be {what}, got {type(tr).__name__}.")
        pos = getattr(tr, "position", None)
        if pos is not None and np.shape(pos) != t.shape + (3,):
            raise InvalidInputError(
                f"Expected `{name}` to hold one point (position shape {t.shape + (3,)}), got "
                f"position shape {np.shape(pos)}; select one point of a batch first."
            )
        return tr
    if tr.rotation.shape != tr.t.shape or tr.omega.shape != tr.t.shape + (3,):
        raise InvalidInputError(
            f"Expected `{name}` to hold one body (rotation shape (n,), omega shape (n, 3)), "
            f"got rotation shape {tr.rotation.shape} and omega shape {tr.omega.shape}; "
            f"select one body of a batch first."
        )
    return tr


def _check_shape(shape: Any) -> list[dict[str, Any]] | None:
    if shape is None:
        return None
    items = [shape] if isinstance(shape, Mapping) else shape
    if (
        not isinstance(items, Sequence)
        or isinstance(items, str)
        or not all(isinstance(x, Mapping) for x in items)
    ):
        raise InvalidTypeError(
            "Expected `shape` to be a mapping {'kind': ..., 'dims': ...}, a sequence of "
            f"them, or None, got {type(shape).__name__}."
        )
    out = []
    for s in items:
        if s.get("kind") == "mesh":
            out.append(_check_mesh(s))
            continue
        unknown = set(s) - {"kind", "dims", "center", "axes"}
        if unknown or "kind" not in s or "dims" not in s:
            raise InvalidInputError(
                "Expected `shape` to have the keys 'kind' and 'dims' (and optionally 'center', "
                f"'axes'), got {sorted(s)}."
            )
        kind = s["kind"]
        center = (
            np.zeros(3)
            if s.get("center") is None
            else as_float_array(s["center"], "shape['center']")
        )
        if center.shape != (3,):
            raise InvalidInputError(
                f"Expected `shape['center']` to have shape (3,), got {center.shape}."
            )
        if kind == "point":  # a point mass (drawn as a small sphere)
            out.append({"kind": "point", "dims": np.zeros(1), "center": center, "axes": np.eye(3)})
            continue
        if kind not in SHAPES:
            opts = ", ".join(repr(k) for k in (*SHAPES, "point", "mesh"))
            raise InvalidInputError(f"Expected `shape['kind']` to be one of {opts}, got {kind!r}.")
        dims = np.atleast_1d(as_float_array(s["dims"], "shape['dims']"))
        n = shapes.NDIMS[kind]
        if dims.shape != (n,):
            raise InvalidInputError(
                f"Expected `shape['dims']` for a {kind} to have shape ({n},) ({SHAPES[kind]}), "
                f"got {dims.shape}."
            )
        if np.any(dims <= 0):
            raise InvalidInputError(
                f"Expected `shape['dims']` to be positive, got {dims.tolist()}."
            )
        axes = np.eye(3) if s.get("axes") is None else as_float_array(s["axes"], "shape['axes']")
        if axes.shape != (3, 3) or not np.allclose(axes.T @ axes, np.eye(3), atol=1e-6):
            raise InvalidInputError("Expected `shape['axes']` to be a 3x3 rotation matrix.")
        out.append({"kind": kind, "dims": dims, "center": center, "axes": axes})
    return out


def _check_mesh(s: Any) -> dict[str, Any]:
    unknown = set(s) - {"kind", "vertices", "faces", "center", "axes"}
    if unknown or "vertices" not in s or "faces" not in s:
        raise InvalidInputError(
            "Expected a mesh `shape` to have the keys 'kind', 'vertices' and 'faces' (and "
            f"optionally 'center', 'axes'), got {sorted(s)}."
        )
    v = as_float_array(s["vertices"], "shape['vertices']")
    if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3:
        raise InvalidInputError(
            f"Expected `shape['vertices']` to have shape (m, 3) with m >= 3, got {v.shape}."
        )
    f = np.asarray(s["faces"])
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0 or not np.issubdtype(f.dtype, np.integer):
        raise InvalidInputError(
            "Expected `shape['faces']` to be integer vertex indices of shape (k, 3), got "
            f"dtype {f.dtype} and shape {f.shape}."
        )
    if f.min() < 0 or f.max() >= len(v):
        raise InvalidInputError(
            f"Expected `shape['faces']` to index the {len(v)} vertices (0..{len(v) - 1}), got "
            f"indices {int(f.min())}..{int(f.max())}."
        )
    center = np.zeros(3) if s.get("center") is None else as_float_array(s["center"], "center")
    axes = np.eye(3) if s.get("axes") is None else as_float_array(s["axes"], "shape['axes']")
    if center.shape != (3,):
        raise InvalidInputError(
            f"Expected `shape['center']` to have shape (3,), got {center.shape}."
        )
    if axes.shape != (3, 3) or not np.allclose(axes.T @ axes, np.eye(3), atol=1e-6):
        raise InvalidInputError("Expected `shape['axes']` to be a 3x3 rotation matrix.")
    v, f = shapes.decimate(v, f, _MAX_MESH_FACES)
    return {"kind": "mesh", "dims": np.zeros(1), "center": center, "axes": axes,
            "vertices": v, "faces": f}  # fmt: skip


def _check_series(charts: Any, n: int) -> list[Any]:
    """The charts as panels ``(title, units, [(label, y, colour, dash)])``."""
    out = []
    for ch in charts:
        if not isinstance(ch, Chart):
            raise InvalidTypeError(
                f"Expected each of `charts` to be a poinsot.plotting.Chart, got {ch!r:.80}."
            )
        dashed = set(ch.dashed)
        lines: list[tuple[str, np.ndarray, str, str | None]] = []
        for label, y in ch.series.items():
            y = as_float_array(y, f"series[{ch.title!r}][{label!r}]")
            if y.shape != (n,):
                raise InvalidInputError(
                    f"Expected `series` {ch.title!r} / {label!r} to have shape ({n},) (one value "
                    f"per sample), got {y.shape}."
                )
            if label in dashed and lines:  # drawn over the series before it, in its colour
                lines.append((str(label), y, lines[-1][2], "dash"))
                continue
            colour = _SERIES_COLOURS[len({c for _, _, c, _ in lines}) % len(_SERIES_COLOURS)]
            lines.append((str(label), y, colour, None))
        if lines:
            out.append((ch.title, ch.units, lines))
    return out


def _check_drawing(drawing: Any, n: int) -> dict[str, Any] | None:
    """``drawing`` validated: points as float arrays (n, 3), links as index pairs."""
    if drawing is None:
        return None
    if not isinstance(drawing, Drawing):
        raise InvalidTypeError(
            f"Expected `drawing` to be a poinsot.plotting.Drawing or None, got "
            f"{type(drawing).__name__}."
        )
    raw = drawing.points or {}
    if not isinstance(raw, Mapping):
        raise InvalidTypeError(
            f"Expected `drawing['points']` to be a mapping, got {type(raw).__name__}."
        )
    points: dict[str, np.ndarray] = {}
    for name, v in raw.items():
        a = as_float_array(v, f"drawing['points'][{name!r}]")
        if a.shape != (n, 3):
            raise InvalidInputError(
                f"Expected `drawing['points'][{name!r}]` to have shape ({n}, 3) (one position "
                f"per sample, m), got {a.shape}."
            )
        points[str(name)] = a
    names = list(points)

    def index(name: Any, what: Any) -> Any:
        if name not in points:
            raise InvalidInputError(
                f"Expected each name in `drawing[{what!r}]` to be one of the points {names}, "
                f"got {name!r}."
            )
        return names.index(name)

    links = []
    for pair in drawing.links or ():
        if isinstance(pair, str) or not isinstance(pair, Sequence) or len(pair) != 2:
            raise InvalidInputError(
                f"Expected each of `drawing['links']` to be a pair of point names, got {pair!r}."
            )
        links.append((index(pair[0], "links"), index(pair[1], "links")))
    trails = [index(name, "trails") for name in drawing.trails or ()]
    guides: dict[str, np.ndarray] = {}
    for label, v in (drawing.guides or {}).items():
        a = as_float_array(v, f"drawing['guides'][{label!r}]")
        if a.shape != (n, 2, 3):
            raise InvalidInputError(
                f"Expected `drawing['guides'][{label!r}]` to have shape ({n}, 2, 3) (two ends "
                f"per sample, m), got {a.shape}."
            )
        guides[str(label)] = a
    return {"points": points, "links": links, "trails": trails, "guides": guides,
            "face_on": bool(drawing.face_on)}  # fmt: skip


def _time_scale(t: np.ndarray, tracks: Any) -> float | None:
    """Shortest period (s) of the back-and-forth of the tracked points: twice the
    duration over the most sign changes of one velocity component (the sign of the
    difference of consecutive positions; values under 1e-3 of the component's largest
    ignored, so that round-off about zero does not count). None if nothing turns back."""
    most = 0
    for p in tracks:
        for c in np.diff(np.asarray(p, dtype=float), axis=0).T:
            big = float(np.max(np.abs(c), initial=0.0))
            if not big > 0:
                continue
            s = np.sign(c[np.abs(c) > 1e-3 * big])
            most = max(most, int(np.count_nonzero(s[1:] != s[:-1])))
    if most == 0 or t.size < 2:
        return None
    return 2.0 * float(t[-1] - t[0]) / most


def _check_inertia(inertia: Any) -> np.ndarray | None:
    if inertia is None:
        return None
    J = as_float_array(inertia, "inertia")
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3):
        raise InvalidInputError(f"Expected `inertia` to have shape (3,) or (3, 3), got {J.shape}.")
    if not np.allclose(J, J.T, rtol=1e-10, atol=1e-12 * np.max(np.abs(J))):
        raise InvalidInputError("Expected `inertia` to be a symmetric matrix.")
    if np.linalg.eigvalsh(J)[0] <= 0:
        raise InvalidInputError("Expected `inertia` to be positive definite.")
    return J


# --------------------------------------------------------------------------- building


def _body_mesh(parts: Any, J: Any, mass: Any, com: Any) -> Any:
    """Vertices (body axes, from the origin), triangles, label, and whether in metres."""
    if parts:
        vs, ts, n0 = [], [], 0
        size = max(
            (
                float(np.max(np.abs(p["vertices"] if p["kind"] == "mesh" else p["dims"])))
                for p in parts
                if p["kind"] != "point"
            ),
            default=0.1,
        )
        for p in parts:
            if p["kind"] == "point":
                v, tri = shapes.sphere_grid(7, 10)
                v = v * 0.04 * size
            elif p["kind"] == "mesh":
                v, tri = p["vertices"] @ p["axes"].T, p["faces"]
            else:
                v, tri = shapes.solid_mesh(p["kind"], p["dims"])
                v = v @ p["axes"].T
            vs.append(v + p["center"])
            ts.append(tri + n0)
            n0 += len(v)
        kinds = sorted({p["kind"] for p in parts})
        return np.concatenate(vs), np.concatenate(ts), "body: " + ", ".join(kinds), True
    v, tri = shapes.sphere_grid()
    if J is None:
        return v, tri, "body (no inertia given: unit sphere)", False
    if mass is not None:
        semi, S = shapes.equivalent_ellipsoid(mass, J)
        return (v * semi) @ S.T + com, tri, "body: ellipsoid of the same mass and inertia", True
    lam, S = np.linalg.eigh(J)
    return (v * np.sqrt(lam[0] / lam)) @ S.T + com, tri, "inertia ellipsoid (scaled)", False


def _angles_between(rot: Any) -> np.ndarray:
    """Turn (rad) between consecutive attitudes."""
    if len(rot) < 2:
        return np.zeros(0)
    q = rot.as_quat()
    return attitude_distance(q[:-1], q[1:])


def _frame_indices(t: Any, turns: Any, max_frames: int, max_angle: float) -> Any:
    """Frames: each the latest sample within ``max_angle`` of turn and ``1/_MIN_FRAMES``
    of the duration from the previous one (greedy; ``turns`` the turn between
    consecutive samples, zeros for a motion without attitude); if that needs more than
    ``max_frames``, ``max_frames`` frames even in time plus turn. Returns the
    indices and the largest turn between frames (rad)."""
    n = t.size
    if n <= 2:
        return np.arange(n), 0.0
    turn = np.concatenate([[0.0], np.cumsum(turns)])
    dt = float(t[-1] - t[0]) / min(_MIN_FRAMES, n - 1)
    frames, i = [0], 0
    while i < n - 1 and len(frames) <= max_frames:
        j1 = int(np.searchsorted(turn, turn[i] + max_angle, side="right")) - 1
        j2 = int(np.searchsorted(t, t[i] + dt * (1 + 1e-9), side="right")) - 1
        i = max(i + 1, min(j1, j2))
        frames.append(i)
    if len(frames) <= max_frames:
        idx = np.asarray(frames)
    else:
        measure = (t - t[0]) / (float(t[-1] - t[0]) or 1.0) + turn / max(turn[-1], 1e-300)
        idx = np.searchsorted(measure, np.linspace(0.0, measure[-1], max_frames))
        idx = np.unique(np.concatenate([[0], np.clip(idx, 0, n - 1), [n - 1]]))
    worst = float(np.max(np.diff(turn[idx]))) if idx.size > 1 else 0.0
    return idx, worst


def _track_indices(t: np.ndarray, *curves: np.ndarray, m: int) -> np.ndarray:
    """At most ``m`` sample indices, even in time plus the arc length of the curves."""
    n = t.size
    if n <= m:
        return np.arange(n)
    measure = np.zeros(n)
    for y in (t[:, None], *curves):
        steps = np.linalg.norm(np.diff(y, axis=0), axis=-1)
        total = steps.sum()
        if total > 0:
            measure[1:] += np.cumsum(steps) / total
    idx = np.searchsorted(measure, np.linspace(0.0, measure[-1], m))
    return np.unique(np.concatenate([[0], np.clip(idx, 0, n - 1), [n - 1]]))


def _scale(vectors: np.ndarray, length: float) -> float:
    m = float(np.max(np.linalg.norm(vectors, axis=-1))) if vectors.size else 0.0
    return length / m if m > 0 else 0.0


def _series(t: np.ndarray, y: np.ndarray, m: int = _MAX_SERIES) -> tuple[np.ndarray, np.ndarray]:
    """``(x, y)`` of a time series, at most about ``m`` points; longer series keep
    the min and max of each of ``m/2`` bins (the envelope survives)."""
    n = t.size
    if n > m:
        edges = np.linspace(0, n, m // 2 + 1).astype(int)
        idx = [0, n - 1]
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            seg = y[a:b]
            idx += [a + int(np.nanargmin(seg)), a + int(np.nanargmax(seg))]
        keep = np.unique(idx)
        t, y = t[keep], y[keep]
    return t, y


_ANGLE_NAMES = {
    "ZXZ": ("psi, precession", "theta, nutation", "phi, spin"),
    "ZYX": ("yaw", "pitch", "roll"),
}


def _law_label(check: Any) -> str:
    """``"label vs law"``, or the label alone when it already names what it is
    compared with (no "a vs b vs c" legends)."""
    if not check.law or " vs " in check.label or check.law in check.label:
        return str(check.label)
    return f"{check.label} vs {check.law}"


def _panels(tr: Any, ref: Any, checks: Any, tq: Any, euler_seq: Any, free_body: Any) -> Any:
    """Time-series panels: (title, y title, [(name, y, colour, dash)])."""

    t = tr.t
    out: list[Any] = []
    rigid = isinstance(tr, Trajectory)
    w = np.asarray(tr.omega) if rigid else np.zeros((t.size, 3))
    if np.any(w != 0):
        series: list[tuple[str, Any, str, str | None]] = [
            (f"w{a + 1} (body {c})", w[:, a], _AXIS_COLOURS[a], None) for a, c in enumerate("xyz")
        ]
        if ref is not None and ref.t.shape == t.shape:
            series += [
                (f"w{a + 1} reference", ref.omega[:, a], _AXIS_COLOURS[a], "dot") for a in range(3)
            ]
        out.append(("angular velocity w, body axes", "rad/s", series))
    q = tr.rotation if isinstance(tr, Trajectory) else None
    if q is not None and t.size > 1 and float(np.max(_angles_between(q), initial=0.0)) > 0:
        try:
            ang = np.unwrap(np.asarray(q.as_euler(euler_seq)), axis=0)
            # a spin: all three shown in (-180, 180] deg, so that they read alike (one
            # angle unwrapped over many turns would flatten the others on the shared axis)
            spans = np.ptp(ang, axis=0)
            wrapped = np.full(3, bool(np.any(spans > 4.0 * np.pi)))
            ang = np.where(wrapped, np.angle(np.exp(1j * ang)), ang)
        except _Bad:
            ang = None
        if ang is not None:
            names = _ANGLE_NAMES.get(euler_seq, tuple(f"angle {k + 1}" for k in range(3)))
            series = [
                (
                    f"{names[k]} ({euler_seq[k]})",
                    np.degrees(ang[:, k]),
                    _AXIS_COLOURS[k],
                    None,
                )
                for k in range(3)
            ]
            how = " (unwrapped)"
            if wrapped[0]:  # say why not unwrapped, with the turns it would take
                k = int(np.argmax(spans))
                how = (
                    f" (each wrapped to (-180, 180]: unwrapped, {names[k].split(',')[0]} "
                    f"would run over {spans[k] / (2.0 * np.pi):.3g} turns and flatten the others)"
                )
            out.append((f"attitude: Euler angles {euler_seq}{how}", "deg", series))
    laws = [c for c in checks if not c.conserved and c.expected is not None]
    if laws:  # compared with a known law (a closed form): the relative deviation
        series = []
        for k, c in enumerate(laws):
            d = np.asarray(c.relative_change(), dtype=float)
            m = float(np.max(np.abs(d), initial=0.0))
            what = _law_label(c)
            series.append((f"{what}: max {fmt_number(m)}", d, _PALETTE[k % len(_PALETTE)], None))
        out.append(("deviation from the known law (relative)", "relative", series))
    conserved = [c for c in checks if c.conserved]
    if conserved:
        series, worst = [], 0.0
        for k, c in enumerate(conserved):
            d = np.asarray(c.relative_change(), dtype=float)
            m = float(np.max(np.abs(d), initial=0.0))
            worst = max(worst, m)
            what = _law_label(c)
            series.append((f"{what}: max {fmt_number(m)}", d, _PALETTE[k % len(_PALETTE)], None))
        # round-off: a few thousand ulp at most; beyond, the method's error (a drift)
        kindof = "round-off only" if worst < 1e-12 else "drift"
        out.append(
            (
                f"conserved quantities: relative change ({kindof}, max {fmt_number(worst)})",
                "relative",
                series,
            )
        )
    others: dict[str, list[Any]] = {}
    steady: dict[str, bool] = {}  # every quantity of these units constant in this motion
    for c in checks:
        if c.conserved or c.expected is not None:
            continue
        v = np.asarray(c.values, dtype=float)
        lst = others.setdefault(c.units, [])
        # not conserved by the torque model, yet constant along this particular motion
        # (e.g. T of a uniform coning): said, with the size of its change
        span = float(np.max(np.ptp(v.reshape(v.shape[0], -1), axis=0), initial=0.0))
        flat = span <= 1e-9 * max(float(np.max(np.abs(v), initial=0.0)), 1e-300)
        steady[c.units] = steady.get(c.units, True) and flat
        note = f" (constant here: max change {fmt_number(span)})" if flat else ""
        if v.ndim == 1:
            lst.append((c.label + note, v, _PALETTE[len(lst) % len(_PALETTE)], None))
        else:
            for a in range(v.shape[-1]):
                lst.append((f"{c.label} {'xyz'[a]}", v[:, a], _AXIS_COLOURS[a % 3], "dash"))
    for units, series in others.items():
        quantities = ", ".join(
            dict.fromkeys(
                s[0].rsplit(" ", 1)[0] if s[3] else s[0].split(" (constant here")[0] for s in series
            )
        )
        how = (
            "not conserved in general, constant in this motion"
            if steady[units]
            else "changes along this motion"
        )
        out.append((f"{quantities} ({how})", units, series))
    if tq is not None and np.any(tq != 0):
        out.append(
            (
                "torque N, body axes",
                "N m",
                [(f"N{'xyz'[a]}", tq[:, a], _AXIS_COLOURS[a], None) for a in range(3)],
            )
        )
        if rigid and tr.energy is not None and not free_body:
            from scipy.integrate import cumulative_trapezoid

            power = np.einsum("ni,ni->n", tq, w)  # dT/dt = N . w (theory §9)
            work = cumulative_trapezoid(power, t, initial=0.0)
            dT = np.asarray(tr.energy) - tr.energy[0]
            title = "energy balance: T(t) - T(0) = work of the torque"
            big = max(float(np.max(np.abs(dT))), float(np.max(np.abs(work))))
            if big <= 1e-9 * max(abs(float(tr.energy[0])), 1e-300):
                # the torque does no work here (e.g. a top in regular precession): say so
                # rather than show round-off as if it were a balance
                title += f" (T constant here: round-off only, max {fmt_number(big)} J)"
            out.append(
                (
                    title,
                    "J",
                    [
                        ("T(t) - T(0)", dT, "#8c564b", None),
                        ("int N . w dt", work, "#222222", "dot"),
                    ],
                )
            )
    if ref is not None and ref.t.shape == t.shape and np.allclose(ref.t, t):
        err = attitude_distance(ref.rotation.as_quat(), tr.rotation.as_quat())
        worst = float(np.max(err, initial=0.0))
        noise = "round-off only, " if worst < 1e-12 else ""  # 1e-12 rad: ~4e3 ulp of pi
        out.append(
            (
                f"attitude error vs reference ({ref.method}; {noise}max {fmt_number(worst)} rad)",
                "rad",
                [("|log(R_ref^-1 R)|", err, "#222222", None)],
            )
        )
    return [p for p in out if any(np.any(np.isfinite(s[1]) & (s[1] != 0)) for s in p[2])]


def _build(
    tr: Any, ref: Any, parts: Any, J: Any, mass: Any, com: Any, fixed: Any,
    free_body: Any, checks: Any, tq: Any, euler_seq: Any, max_frames: Any,
    max_angle_deg: Any, extra_panels: Any = (), draw: Any = None,
) -> Any:  # fmt: skip
    """The viewer's data (``payload``), the notes under the figure and the meta line."""
    t = tr.t
    n = t.size
    rigid = isinstance(tr, Trajectory)
    rot = tr.rotation if rigid else None
    turns = _angles_between(rot) if rigid else np.zeros(max(n - 1, 0))
    moving = n > 1 and float(np.max(turns, initial=0.0)) > 0
    pos = getattr(tr, "position", None)
    pos = None if pos is None else np.asarray(pos, dtype=float)
    has_body = rigid and (parts is not None or J is not None or moving)
    drawn = draw is not None and bool(draw["points"] or draw["guides"])
    show_scene = has_body or pos is not None or drawn
    panels = list(extra_panels) + _panels(tr, ref, checks, tq, euler_seq, free_body)
    tracks = ([] if pos is None else [pos]) + (
        [] if draw is None else list(draw["points"].values())
    )
    period = _time_scale(t, tracks)
    max_angle = math.radians(max_angle_deg)
    if not moving and period is not None:  # a phase advancing 2 pi per period: the frame rule
        turns, max_angle = 2.0 * np.pi * np.diff(t) / period, 2.0 * np.pi / _FRAMES_PER_PERIOD
    frames_k, worst = _frame_indices(t, turns, max_frames, max_angle)
    fade = 1.5 * period if period is not None else float(t[-1] - t[0]) / 4.0 if n > 1 else 1.0
    sample_turn = float(np.max(turns, initial=0.0))
    qf = tr.quat[frames_k] if rigid else None
    layers: list[dict[str, Any]] = []
    notes: list[str] = []
    has_ref = ref is not None and ref.t.shape == t.shape

    def layer(type_: Any, name: Any, colour: Any, *, legend: Any = True, **kw: Any) -> None:
        layers.append({"type": type_, "name": name, "colour": colour, "legend": legend, **kw})

    unit = "m"
    lo: Any = None  # the scene's box: set with the body or the path
    hi: Any = None
    if show_scene and has_body and rot is not None:
        verts, tri, label, metres = _body_mesh(parts, J, mass, com)
        unit = "m" if metres else "scaled"
        L = float(np.max(np.linalg.norm(verts, axis=-1)))
        layer("mesh", label, "#a9b3c1", v=b64(verts), f=b64(tri, np.uint32), frame="body",
              opacity=1.0, group="body")  # fmt: skip
        s_ell = None
        if J is not None:
            # the inertia ellipsoid r^T J r = 1 about the centre of mass, scaled to the body
            sph, etri = shapes.sphere_grid()
            lam, S = np.linalg.eigh(J)
            size = float(np.max(np.linalg.norm(verts - com, axis=-1))) or 1.0
            s_ell = size * math.sqrt(lam[0])  # r^T J r = s_ell^2: longest semi-axis = size
            ell = (sph * np.sqrt(lam[0] / lam)) @ S.T * size + com
            layer("mesh", f"inertia ellipsoid r.J r = 1 (scaled x{fmt_number(s_ell)})",
                  "#e377c2", v=b64(ell), f=b64(etri, np.uint32), frame="body", opacity=0.25,
                  visible=False)  # fmt: skip
        axis_len = 1.25 * L
        for a, lab in enumerate("xyz"):
            e = np.zeros(3)
            e[a] = axis_len
            layer("seg", f"body {lab} axis", _AXIS_COLOURS[a], b=e.tolist(), frame="body",
                  width=3.5, arrow=True)  # fmt: skip
            if has_ref:
                layer("seg", "reference axes (dashed)", _AXIS_COLOURS[a], b=e.tolist(),
                      frame="ref", width=2, dash=True, group="refaxes",
                      legend=a == 0)  # fmt: skip
        w_s = rot.apply(tr.omega) if n else np.zeros((0, 3))
        vecs = [(w_s, "w, angular velocity", "rad/s", _OMEGA_COLOUR)]
        if tr.momentum is not None:
            vecs.append(
                (np.asarray(tr.momentum), "K, angular momentum", "kg m^2/s", _MOMENTUM_COLOUR)
            )
        arrow_unit = "m" if unit == "m" else "scene units"
        extent = 1.4 * L
        for k, (V, name, vu, colour) in enumerate(vecs):
            c = _scale(V, (1.5 + 0.3 * k) * L)
            if c == 0:
                continue
            Vf = c * V[frames_k]
            layer("vec", f"{name} (arrow: 1 {vu} = {fmt_number(c)} {arrow_unit})", colour,
                  v=b64(Vf), width=3, arrow=True, scale=c)  # fmt: skip
            extent = max(extent, float(np.max(np.abs(c * V))))
        if fixed:
            layer("marker", "fixed point (origin of the body axes)", "#000000", p=[0.0, 0.0, 0.0],
                  symbol="diamond", size=6)  # fmt: skip
        if free_body and J is not None and moving:
            wb = np.asarray(tr.omega)
            wJw = np.einsum("ni,ij,nj->n", wb, J, wb)
            with np.errstate(divide="ignore", invalid="ignore"):
                pol_b = wb / np.sqrt(wJw)[:, None] * s_ell + com
            pol_b = np.where(np.isfinite(pol_b), pol_b, com)
            her = rot.apply(pol_b)
            track = _track_indices(t, pol_b, her, m=_MAX_TRACK)
            layer("line", "polhode (on the inertia ellipsoid, moves with the body)",
                  _POLHODE_COLOUR, v=b64(pol_b[track]), frame="body", width=2.5)  # fmt: skip
            upto = np.searchsorted(t[track], t[frames_k], side="right")
            layer("line", "herpolhode (in the invariable plane, fixed in space)",
                  _HERPOLHODE_COLOUR, v=b64(her[track]), frame="space", upto=upto.tolist(),
                  width=2)  # fmt: skip
            extent = max(extent, float(np.max(np.abs(her))))
        lo, hi = np.full(3, -1.08 * extent), np.full(3, 1.08 * extent)

    def trail(p: Any, name: Any, colour: Any) -> None:
        """The path of ``p`` (n, 3) up to each frame's time, fading with age."""
        keep = np.union1d(_track_indices(t, p, m=_MAX_TRACK * 3), frames_k)
        upto = np.searchsorted(keep, frames_k, side="right")
        layer("trail", name, colour, v=b64(p[keep]), tt=b64(t[keep] - t[0]), upto=upto.tolist(),
              tau=fade, floor=_TRAIL_FLOOR, width=2.2)  # fmt: skip

    if show_scene and pos is not None:
        track = _track_indices(t, pos, m=_MAX_TRACK * 3)
        layer("line", "whole path", "#9bbbd9", v=b64(pos[track]), frame="space", width=1.2,
              visible=False)  # fmt: skip
        trail(pos, "path up to the frame's time (fading with age)", "#1f77b4")
        layer("point", "position r(t)", "#d62728", v=b64(pos[frames_k]), size=6)
        axes = getattr(tr, "frame_name", None) if not rigid else None
        axes = axes if isinstance(axes, str) and axes else "space"
        layer("marker", f"origin of {axes} axes", "#000000", p=[0.0, 0.0, 0.0], symbol="cross")
        plo, phi_ = np.minimum(pos.min(0), 0.0), np.maximum(pos.max(0), 0.0)
        c, r = (plo + phi_) / 2, max(float(np.max(phi_ - plo)) / 2 * 1.1, 1e-9)
        if has_body:
            lo, hi = np.minimum(lo, c - r), np.maximum(hi, c + r)
        else:
            lo, hi, unit = c - r, c + r, "m"
    if show_scene and drawn:
        pts = draw["points"]
        names = list(pts)
        for k in draw["trails"]:
            trail(pts[names[k]], f"trail of {names[k]} (fading with age)",
                  _PALETTE[(k + 5) % len(_PALETTE)])  # fmt: skip
        if names:
            P = np.stack([pts[nm][frames_k] for nm in names], axis=1)  # (frames, m, 3)
            what = "links and points" if draw["links"] else "points"
            # the points with a trail (the ones to follow) large and red, the others small
            layer("rig", f"{what}: {', '.join(names)}", _LINK_COLOUR, v=b64(P), m=len(names),
                  pairs=[list(pr) for pr in draw["links"]], dots=True, dot=_DOT_COLOUR,
                  big=sorted(set(draw["trails"])), width=3.5)  # fmt: skip
        for k, (label, G) in enumerate(draw["guides"].items()):
            layer("rig", label, _GUIDE_COLOURS[k % len(_GUIDE_COLOURS)], v=b64(G[frames_k]), m=2,
                  pairs=[[0, 1]], dots=False, dash=True, width=2.5)  # fmt: skip
        every = np.concatenate(
            [a.reshape(-1, 3) for a in (*pts.values(), *draw["guides"].values())]
        )
        every = every[np.all(np.isfinite(every), axis=-1)]
        if every.size:
            dlo, dhi = every.min(0), every.max(0)
            if lo is None:
                c, r = (dlo + dhi) / 2, max(float(np.max(dhi - dlo)) / 2 * 1.1, 1e-9)
                lo, hi, unit = c - r, c + r, "m"
            else:
                lo, hi = np.minimum(lo, dlo), np.maximum(hi, dhi)
    scene = None
    if show_scene and lo is not None:
        scene = {"unit": unit, "lo": lo.tolist(), "hi": hi.tolist(), "layers": layers}
        if draw is not None and draw["face_on"]:  # a plane drawing in x-z: seen face on
            scene["view"] = {"az": -0.5 * math.pi + 0.12, "el": 0.1}

    if show_scene and has_body and moving:
        deg = math.degrees(worst)
        if deg <= max_angle_deg + 1e-9:
            notes.append(
                f"Animation: {frames_k.size} frames; the body turns at most {deg:.3g} deg between "
                f"two frames (frames are added where it turns fast, so a spin does not strobe)."
            )
        else:
            why = (
                f"the output samples are {math.degrees(sample_turn):.3g} deg apart at most "
                "(use a smaller [simulation] step)"
                if math.degrees(sample_turn) > max_angle_deg
                else f"the number of frames is limited to {max_frames}"
            )
            notes.append(
                f"Animation: {frames_k.size} frames; the body turns up to {deg:.3g} deg between "
                f"two frames because {why}: a fast spin may appear to strobe."
            )
    if show_scene and not moving and n > 2:
        if period is None:
            notes.append(f"Animation: {frames_k.size} frames even in time.")
        else:
            per = period / (float(np.max(np.diff(t[frames_k]))) or period)
            notes.append(
                f"Animation: {frames_k.size} frames, at least {per:.3g} per period of the "
                f"motion ({fmt_number(period)} s, from the turning points of the drawn points)"
                + (
                    "."
                    if per >= _FRAMES_PER_PERIOD * 0.99
                    else f": fewer than {_FRAMES_PER_PERIOD} because of the output samples "
                    f"or the frame limit ({max_frames}); fast motion may look jumpy."
                )
            )
    notes.append(
        "Speed: 1x shows every frame (about 25 per second); faster speeds skip frames. "
        + (
            "Scene in space axes (v_space = R v_body); body axes x, y, z in red, green, blue. "
            if show_scene and has_body
            else "Scene: the path in metres up to the frame's time (older parts fade), the "
            "red dot the position at the frame's time. "
            if show_scene and pos is not None
            else "Scene in metres: the system drawn at the frame's time, trails fading with age. "
            if show_scene
            else ""
        )
        + "The dashed vertical line on every chart is the time of the frame shown; hover a "
        "chart to read its values."
    )
    payload = {
        "t": b64(t[frames_k]),
        "q": None if qf is None else b64(qf),
        "qref": b64(ref.quat[frames_k]) if has_ref else None,
        # a rigid body that also moves (PoseTrajectory): the body is drawn at its centre
        "bp": b64(pos[frames_k]) if rigid and pos is not None else None,
        "t0": float(t[0]) if n else 0.0,
        "t1": float(t[-1]) if n else 1.0,
        "scene": scene,
        "panels": [
            chart(
                title,
                yunits,
                [
                    (name, *_series(t, np.asarray(y, dtype=float)), colour, "line", dash)
                    for name, y, colour, dash in series
                ],  # fmt: skip
            )
            for title, yunits, series in panels
        ],
        "interval": 40,
    }
    meta = (
        f"method: <b>{tr.method}</b> &middot; {n} samples, t = {fmt_number(float(t[0]))} .. "
        f"{fmt_number(float(t[-1]))} s &middot; {frames_k.size} animation frames"
    )
    return payload, notes, meta
