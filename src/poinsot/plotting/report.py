"""A self-contained interactive HTML report of a rigid body's motion.

:func:`write_report` writes ONE HTML file that works offline: Plotly's
JavaScript is embedded once (no CDN, no network access), followed by a single
figure holding

- an animated 3-D scene in space axes: the body (its shape, or else its
  inertia ellipsoid ``r^T J r = 1``, theory §8), the body axes as three coloured
  lines, the angular velocity ``w`` and angular momentum ``K`` vectors, the
  polhode (the track of ``w`` fixed in the body, drawn on the moving body) and
  the herpolhode (the track of the same point in space, theory §10), with
  play/pause buttons and a time slider;
- the time series of ``w`` (body axes) and of the relative change of the
  invariants ``T`` and ``|K|`` (their drift for a free body), with a cursor
  that follows the animation; with a ``reference`` trajectory, its ``w`` is
  overlaid and the attitude error between the two is plotted;

and the run's summary as an HTML table. Plotly is imported inside this module
only (``plotting`` is a leaf package; ``import poinsot`` never loads it).
"""

from __future__ import annotations

import html
import math
import os
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import as_float_array, is_integer
from ..errors import InvalidInputError, InvalidTypeError
from ..trajectory import Trajectory

__all__ = ["write_report"]

#: Shapes :func:`write_report` can draw, with the meaning of their ``dims``.
SHAPES = {
    "box": "full edge lengths (a, b, c) along body x, y, z",
    "ellipsoid": "semi-axes (a, b, c) along body x, y, z",
    "sphere": "radius (r,)",
    "cylinder": "radius and height (r, h), axis along body z",
}
_SHAPE_NDIMS = {"box": 3, "ellipsoid": 3, "sphere": 1, "cylinder": 2}

_DIV_ID = "poinsot-figure"
_AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # body x, y, z: red, green, blue
_OMEGA_COLOUR = "#ff7f0e"
_MOMENTUM_COLOUR = "#9467bd"
_POLHODE_COLOUR = "#e377c2"
_HERPOLHODE_COLOUR = "#17becf"
_MAX_TRACK = 300  # points kept for the polhode / herpolhode tracks
_MAX_SERIES = 4000  # points kept per time series (min/max envelope beyond that)


def write_report(
    path: str | os.PathLike,
    *,
    trajectory: Trajectory,
    summary: Mapping[str, Any] | None = None,
    title: str = "poinsot report",
    shape: Mapping[str, Any] | None = None,
    inertia=None,
    reference: Trajectory | None = None,
    max_frames: int = 150,
    sections=(),
) -> Path:
    """Write a self-contained interactive HTML report of a trajectory.

    Parameters
    ----------
    path : str or os.PathLike
        Output file (conventionally ``report.html``). Its directory must exist.
        The file is written atomically: to a temporary name in the same
        directory, then renamed, so an interrupted call never leaves a file
        that looks complete.
    trajectory : Trajectory
        Motion of ONE body: ``rotation`` of shape ``(n,)``, ``omega`` of shape
        ``(n, 3)`` (body axes); ``energy`` and ``momentum`` are plotted when
        present.
    summary : mapping, optional
        Key/value pairs shown as a table (nested mappings are flattened into
        dotted keys), e.g. the content of ``summary.json``.
    title : str, optional
        Title of the page.
    shape : mapping, optional
        Body shape to draw, ``{"kind": KIND, "dims": DIMS}`` with KIND one of
        ``"box"`` (full edge lengths ``(a, b, c)``), ``"ellipsoid"``
        (semi-axes ``(a, b, c)``), ``"sphere"`` (``(r,)``) or ``"cylinder"``
        (``(r, h)``, axis along body z), dimensions in body axes, centred on
        the origin. Default: the inertia ellipsoid.
    inertia : array_like, shape (3,) or (3, 3), optional
        Inertia tensor in body axes (or its principal moments). Without a
        ``shape`` the inertia ellipsoid ``r^T J r = 1`` is drawn and the
        polhode lies on it; without either a unit sphere stands for the body.
    reference : Trajectory, optional
        A second motion (e.g. the exact solution) to compare with: its body
        axes are drawn dashed, its ``w`` overlaid, and the attitude error
        ``|log(R_ref^-1 R)|`` plotted when both share the same times.
    max_frames : int, optional
        Largest number of animation frames (the samples are subsampled
        evenly); between 2 and 1000. Default 150.

    sections : sequence of (str, str), optional
        Extra sections ``(heading, html)`` shown above the summary, e.g. a kind's
        typeset equations as inline SVG (trusted HTML made by poinsot, not user text).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InvalidTypeError
        If ``trajectory``/``reference`` is not a :class:`~poinsot.Trajectory`,
        ``summary``/``shape`` not a mapping, ``title`` not a string or
        ``max_frames`` not an integer.
    InvalidInputError
        If a trajectory holds a batch of bodies, ``shape`` or ``inertia`` is
        malformed, ``max_frames`` is out of range, or the directory of
        ``path`` does not exist.

    Notes
    -----
    The polhode point is ``r = e / sqrt(e^T J e)`` with ``e = w / |w|`` (the
    point of the inertia ellipsoid on the instantaneous axis, theory §8, §10);
    for a free body the herpolhode then lies in the invariable plane at
    distance ``sqrt(2T)/|K|`` from the fixed point. Drawn with a ``shape`` or
    without ``inertia``, the track is the tip of the scaled ``w`` instead.
    The vectors ``w`` and ``K`` are scaled to the size of the body (each
    with its own scale, constant over the animation). The inertia ellipsoid,
    the polhode and the herpolhode are drawn with one common scale, making the
    longest semi-axis 1 (the ellipsoid's size is in ``1/sqrt(kg m^2)``).

    **Convention:** the scene is in space axes, ``v_space = R v_body``
    (theory §2); ``w`` is read in body axes and drawn in space axes; times in s,
    angular velocities in rad/s.

    Examples
    --------
    >>> import numpy as np, poinsot, tempfile, pathlib
    >>> from poinsot.plotting.report import write_report
    >>> t = np.linspace(0.0, 2.0, 21)
    >>> rot = poinsot.Rotation.from_rotvec(np.outer(t, [0.0, 0.0, 1.5]))
    >>> tr = poinsot.Trajectory(t, rot, np.tile([0.0, 0.0, 1.5], (21, 1)), "spin")
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "report.html"
    >>> p = write_report(out, trajectory=tr, summary={"method": "spin"},
    ...                  shape={"kind": "box", "dims": [1.0, 0.6, 0.2]})
    >>> p == out, "<script src=" in p.read_text()  # plotly.js inlined, nothing fetched
    (True, False)
    """
    tr = _check_trajectory(trajectory, "trajectory")
    ref = None if reference is None else _check_trajectory(reference, "reference")
    if summary is not None and not isinstance(summary, Mapping):
        raise InvalidTypeError(
            f"Expected `summary` to be a mapping or None, got {type(summary).__name__}."
        )
    if not isinstance(title, str):
        raise InvalidTypeError(f"Expected `title` to be a string, got {type(title).__name__}.")
    if not is_integer(max_frames):
        raise InvalidTypeError(
            f"Expected `max_frames` to be an integer, got {type(max_frames).__name__}."
        )
    if not 2 <= max_frames <= 1000:
        raise InvalidInputError(f"Expected `max_frames` to be in [2, 1000], got {max_frames}.")
    body = _check_shape(shape)
    J = _check_inertia(inertia)
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

    fig = _figure(tr, ref, body, J, max_frames)
    page = _page(fig, title=title, tr=tr, summary=summary, sections=sections)
    _write_atomic(path, page)
    return path


# --------------------------------------------------------------------------- checks


def _check_trajectory(tr, name: str) -> Trajectory:
    if not isinstance(tr, Trajectory):
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot.Trajectory, got {type(tr).__name__}."
        )
    if tr.rotation.shape != tr.t.shape or tr.omega.shape != tr.t.shape + (3,):
        raise InvalidInputError(
            f"Expected `{name}` to hold one body (rotation shape (n,), omega shape (n, 3)), "
            f"got rotation shape {tr.rotation.shape} and omega shape {tr.omega.shape}; "
            f"select one body of a batch first."
        )
    return tr


def _check_shape(shape) -> tuple[str, np.ndarray] | None:
    if shape is None:
        return None
    if not isinstance(shape, Mapping):
        raise InvalidTypeError(
            f"Expected `shape` to be a mapping {{'kind': ..., 'dims': ...}} or None, "
            f"got {type(shape).__name__}."
        )
    unknown = set(shape) - {"kind", "dims"}
    if unknown or "kind" not in shape or "dims" not in shape:
        raise InvalidInputError(
            f"Expected `shape` to have exactly the keys 'kind' and 'dims', got {sorted(shape)}."
        )
    kind = shape["kind"]
    if kind not in SHAPES:
        opts = ", ".join(repr(k) for k in SHAPES)
        raise InvalidInputError(f"Expected `shape['kind']` to be one of {opts}, got {kind!r}.")
    dims = np.atleast_1d(as_float_array(shape["dims"], "shape['dims']"))
    n = _SHAPE_NDIMS[kind]
    if dims.shape != (n,):
        raise InvalidInputError(
            f"Expected `shape['dims']` for a {kind} to have shape ({n},) ({SHAPES[kind]}), "
            f"got {dims.shape}."
        )
    if np.any(dims <= 0):
        raise InvalidInputError(f"Expected `shape['dims']` to be positive, got {dims.tolist()}.")
    return kind, dims


def _check_inertia(inertia) -> np.ndarray | None:
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


# --------------------------------------------------------------------------- geometry


def _sphere_grid(n_lat: int = 11, n_lon: int = 20):
    """Unit-sphere vertices and triangles (latitude-longitude grid)."""
    th = np.linspace(0.0, np.pi, n_lat)
    ph = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False)
    th, ph = np.meshgrid(th, ph, indexing="ij")
    v = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1)
    tri = []
    for a in range(n_lat - 1):
        for b in range(n_lon):
            p, q = a * n_lon + b, a * n_lon + (b + 1) % n_lon
            tri += [(p, q, p + n_lon), (q, q + n_lon, p + n_lon)]
    return v.reshape(-1, 3), np.array(tri)


def _box(a: float, b: float, c: float):
    s = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    v = 0.5 * s * [a, b, c]
    tri = np.array(
        [
            (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5),  # x = -a/2, +a/2
            (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),  # y
            (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),  # z
        ]
    )  # fmt: skip
    return v, tri


def _cylinder(r: float, h: float, n: int = 32):
    ph = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ring = np.stack([r * np.cos(ph), r * np.sin(ph)], -1)
    v = np.concatenate(
        [
            np.column_stack([ring, np.full(n, -h / 2)]),
            np.column_stack([ring, np.full(n, h / 2)]),
            [[0.0, 0.0, -h / 2], [0.0, 0.0, h / 2]],
        ]
    )
    tri = []
    for k in range(n):
        k1 = (k + 1) % n
        tri += [(k, k1, n + k), (k1, n + k1, n + k), (2 * n, k1, k), (2 * n + 1, n + k, n + k1)]
    return v, np.array(tri)


def _body_mesh(body, J):
    """Vertices (body axes), triangles and a legend label for the body."""
    if body is not None:
        kind, d = body
        if kind == "box":
            v, tri = _box(*d)
        elif kind == "cylinder":
            v, tri = _cylinder(*d)
        else:
            v, tri = _sphere_grid()
            v = v * (d if kind == "ellipsoid" else d[0])
        return v, tri, f"body ({kind})"
    v, tri = _sphere_grid()
    if J is None:
        return v, tri, "body (inertia not given: unit sphere)"
    lam, S = np.linalg.eigh(J)
    # r^T J r = 1 in principal axes: semi-axes 1/sqrt(lambda_k) along S[:, k] (theory §8),
    # drawn scaled by sqrt(lambda_min) (longest semi-axis 1): r^T J r = lambda_min.
    v = (v * np.sqrt(lam[0] / lam)) @ S.T
    return v, tri, "inertia ellipsoid (scaled)"


def _ellipsoid_scale(J) -> float:
    """Scale ``s`` of the drawn inertia ellipsoid ``r^T J r = s^2`` (longest semi-axis 1)."""
    return float(np.sqrt(np.linalg.eigvalsh(J)[0]))


def _frame_indices(n: int, max_frames: int) -> np.ndarray:
    return np.unique(np.round(np.linspace(0, n - 1, min(n, max_frames))).astype(int))


def _track_indices(t: np.ndarray, *curves: np.ndarray, m: int) -> np.ndarray:
    """At most ``m`` sample indices, even in time plus the arc length of the curves.

    Fast stretches of a track (a flip of the tennis racket) get as many points as
    slow ones of the same length, so the drawn curves stay smooth.
    """
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


# --------------------------------------------------------------------------- figure


def _figure(tr: Trajectory, ref: Trajectory | None, body, J, max_frames: int):
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    t = tr.t
    n = t.size
    C = tr.rotation.as_matrix()  # (n, 3, 3), body -> space
    w_b = tr.omega
    w_s = np.einsum("nij,nj->ni", C, w_b)
    K_s = tr.momentum
    verts, tri, body_label = _body_mesh(body, J)
    L = float(np.max(np.linalg.norm(verts, axis=-1)))
    c_w = _scale(w_s, 1.6 * L)
    c_K = _scale(K_s, 1.9 * L) if K_s is not None else 0.0

    # Polhode point in body axes: e / sqrt(e^T J e) on the inertia ellipsoid, or the w tip.
    if body is None and J is not None:
        wJw = np.einsum("ni,ij,nj->n", w_b, J, w_b)
        with np.errstate(divide="ignore", invalid="ignore"):
            pol_b = np.where(wJw[:, None] > 0, w_b / np.sqrt(wJw)[:, None], 0.0)
        pol_b = _ellipsoid_scale(J) * pol_b  # on the drawn (scaled) ellipsoid
        pol_label = "polhode (on the ellipsoid)"
    else:
        pol_b = c_w * w_b
        pol_label = "polhode (w tip, body-fixed)"
    her_s = np.einsum("nij,nj->ni", C, pol_b)
    track = _track_indices(t, pol_b, her_s, m=_MAX_TRACK)
    pol_b, her_s = pol_b[track], her_s[track]

    C_ref = None
    if ref is not None:
        idx = np.clip(np.searchsorted(ref.t, t), 0, ref.t.size - 1)
        prev = np.clip(idx - 1, 0, ref.t.size - 1)
        idx = np.where(np.abs(ref.t[prev] - t) < np.abs(ref.t[idx] - t), prev, idx)
        C_ref = ref.rotation.as_matrix()[idx]  # nearest reference sample
    same_grid = ref is not None and ref.t.shape == t.shape and np.allclose(ref.t, t)

    rows = 3 if same_grid else 2
    titles = ["", "angular velocity, body axes (rad/s)", "relative change of T and |K|"]
    if same_grid:
        titles.append("attitude error vs reference (rad)")
    specs = [[{"type": "scene", "rowspan": rows}, {"type": "xy"}]] + [
        [None, {"type": "xy"}] for _ in range(rows - 1)
    ]
    fig = make_subplots(
        rows=rows,
        cols=2,
        specs=specs,
        column_widths=[0.58, 0.42],
        horizontal_spacing=0.07,
        vertical_spacing=0.1,
        subplot_titles=titles,
    )

    f32 = lambda a: np.asarray(a, dtype=np.float32)  # noqa: E731  (halves the page size)

    # ---- animated 3-D traces: full traces for the first frame, then only x, y, z per frame
    def scene_traces(k: int, i_her: int, full: bool) -> list:
        R = C[k]
        segs = [1.35 * L * R[:, a] for a in range(3)]
        segs.append(c_w * w_s[k])
        if K_s is not None:
            segs.append(c_K * K_s[k])
        if C_ref is not None:
            segs += [1.35 * L * C_ref[k][:, a] for a in range(3)]
        clouds = [verts @ R.T, pol_b @ R.T, her_s[: i_her + 1]]
        if not full:
            xyz = [_xyz(v, go.Mesh3d) for v in clouds[:1]]
            xyz += [_xyz(np.stack([np.zeros(3), e]), go.Scatter3d) for e in segs]
            xyz += [_xyz(v, go.Scatter3d) for v in clouds[1:]]
            return xyz
        v = clouds[0]
        out = [
            go.Mesh3d(
                x=f32(v[:, 0]), y=f32(v[:, 1]), z=f32(v[:, 2]),
                i=tri[:, 0], j=tri[:, 1], k=tri[:, 2],
                color="#b0b7c3", opacity=0.7 if body else 0.45 if J is not None else 0.25,
                flatshading=body is not None and body[0] in ("box", "cylinder"),
                name=body_label, showlegend=True, hoverinfo="skip",
            )
        ]  # fmt: skip
        for a, lab in enumerate("xyz"):
            out.append(_line3d(go, segs[a], _AXIS_COLOURS[a], f"body {lab} axis", width=6))
        out.append(_line3d(go, segs[3], _OMEGA_COLOUR, "w (scaled)", width=5, marker_tip=True))
        if K_s is not None:
            out.append(
                _line3d(go, segs[4], _MOMENTUM_COLOUR, "K (scaled)", width=5, marker_tip=True)
            )
        if C_ref is not None:
            for a in range(3):
                out.append(
                    _line3d(go, segs[-3 + a], _AXIS_COLOURS[a], "reference axes", width=3,
                            dash="dash", legend=a == 0)
                )  # fmt: skip
        for v, colour, width, name in (
            (clouds[1], _POLHODE_COLOUR, 4, pol_label),
            (clouds[2], _HERPOLHODE_COLOUR, 3, "herpolhode (space)"),
        ):
            out.append(
                go.Scatter3d(
                    x=f32(v[:, 0]), y=f32(v[:, 1]), z=f32(v[:, 2]), mode="lines",
                    line={"color": colour, "width": width}, name=name, hoverinfo="skip",
                )
            )  # fmt: skip
        return out

    frames_k = _frame_indices(n, max_frames)
    i_her = np.searchsorted(t[track], t[frames_k], side="right") - 1
    first = scene_traces(int(frames_k[0]), int(i_her[0]), full=True)
    for tr3 in first:
        fig.add_trace(tr3, row=1, col=1)
    n3 = len(first)

    # ---- time series (static) and their time cursors (animated)
    comp = ("w1 (x)", "w2 (y)", "w3 (z)")
    for a in range(3):
        fig.add_trace(
            go.Scatter(
                **_series(t, w_b[:, a]), mode="lines", name=comp[a], legendgroup="ts",
                line={"color": _AXIS_COLOURS[a], "width": 2},
            ),
            row=1, col=2,
        )  # fmt: skip
        if ref is not None:
            fig.add_trace(
                go.Scatter(
                    **_series(ref.t, ref.omega[:, a]), mode="lines",
                    name="reference w" if a == 0 else comp[a] + " ref", showlegend=a == 0,
                    line={"color": _AXIS_COLOURS[a], "width": 2, "dash": "dot"},
                    legendgroup="ref",
                ),
                row=1, col=2,
            )  # fmt: skip
    ranges = [_yrange(w_b)]
    drift = []
    if tr.energy is not None and tr.energy[0] != 0:
        drift.append(("T/T0 - 1", tr.energy / tr.energy[0] - 1.0, "#8c564b"))
    if tr.momentum_norm is not None and tr.momentum_norm[0] != 0:
        drift.append(("|K|/|K0| - 1", tr.momentum_norm / tr.momentum_norm[0] - 1.0, "#7f7f7f"))
    for name, y, colour in drift:
        fig.add_trace(
            go.Scatter(**_series(t, y), mode="lines", name=name, line={"color": colour}),
            row=2, col=2,
        )  # fmt: skip
    if not drift:
        fig.add_annotation(
            text="no invariants recorded (energy, momentum)", showarrow=False,
            xref="x2 domain", yref="y2 domain", x=0.5, y=0.5,
        )  # fmt: skip
    ranges.append(_yrange(np.stack([d[1] for d in drift], -1) if drift else np.zeros(1)))
    if same_grid:
        err = (ref.rotation.inv() * tr.rotation).magnitude()
        fig.add_trace(
            go.Scatter(
                **_series(t, err), mode="lines", name="attitude error",
                line={"color": "#222222"},
            ),
            row=3, col=2,
        )  # fmt: skip
        ranges.append(_yrange(err))
    n_static = len(fig.data) - n3
    for r, (lo, hi) in enumerate(ranges, start=1):
        fig.add_trace(
            go.Scatter(
                x=[t[0], t[0]], y=[lo, hi], mode="lines", showlegend=False, hoverinfo="skip",
                line={"color": "rgba(0,0,0,0.45)", "width": 1.5, "dash": "dot"},
            ),
            row=r, col=2,
        )  # fmt: skip
        fig.update_yaxes(range=[lo, hi], exponentformat="e", row=r, col=2)
    cursor_ids = list(range(n3 + n_static, len(fig.data)))
    fig.update_xaxes(range=[float(t[0]), float(t[-1])] if n > 1 else None, col=2)
    fig.update_xaxes(title_text="t (s)", row=rows, col=2)

    # ---- animation frames, buttons and slider
    frames = []
    for f, (k, ih) in enumerate(zip(frames_k, i_her, strict=True)):
        tk = float(t[k])
        cursors = [go.Scatter(x=[tk, tk]) for _ in cursor_ids]
        frames.append(
            go.Frame(
                name=str(f),
                data=scene_traces(int(k), int(ih), full=False) + cursors,
                traces=list(range(n3)) + cursor_ids,
            )
        )
    fig.frames = frames
    duration = int(max(40, min(200, 12000 / len(frames))))
    play = {
        "frame": {"duration": duration, "redraw": True},
        "fromcurrent": True,
        "transition": {"duration": 0},
        "mode": "immediate",
    }
    pause = {"frame": {"duration": 0, "redraw": False}, "mode": "immediate"}
    fig.update_layout(
        updatemenus=[
            {
                "type": "buttons",
                "direction": "left",
                "showactive": False,
                "x": 0.0,
                "y": 0.0,
                "xanchor": "left",
                "yanchor": "top",
                "pad": {"t": 40, "r": 10},
                "buttons": [
                    {"label": "\u25b6 Play", "method": "animate", "args": [None, play]},
                    {"label": "\u275a\u275a Pause", "method": "animate", "args": [[None], pause]},
                ],
            }
        ],
        sliders=[
            {
                "active": 0,
                "x": 0.15,
                "y": 0.0,
                "len": 0.42,
                "xanchor": "left",
                "yanchor": "top",
                "pad": {"t": 30},
                "currentvalue": {"prefix": "t = ", "suffix": " s", "visible": True},
                "steps": [
                    {
                        "label": f"{float(t[k]):.4g}",
                        "method": "animate",
                        "args": [
                            [str(f)],
                            {
                                "mode": "immediate",
                                "frame": {"duration": 0, "redraw": True},
                                "transition": {"duration": 0},
                            },
                        ],
                    }
                    for f, k in enumerate(frames_k)
                ],
            }
        ],
    )
    extent = max(
        1.45 * L,
        float(np.max(np.abs(c_w * w_s))) if n else 0.0,
        float(np.max(np.abs(c_K * K_s))) if K_s is not None else 0.0,
        float(np.max(np.abs(her_s))),
    )
    ax = {"range": [-1.08 * extent, 1.08 * extent], "autorange": False, "zeroline": False}
    fig.update_layout(
        height=760,
        margin={"l": 10, "r": 10, "t": 40, "b": 110},
        legend={
            "x": 0.0,
            "y": 1.0,
            "xanchor": "left",
            "yanchor": "top",
            "font": {"size": 10},
            "bgcolor": "rgba(255,255,255,0.6)",
            "tracegroupgap": 2,
        },
        scene={
            "xaxis": {**ax, "title": {"text": "x (space)"}},
            "yaxis": {**ax, "title": {"text": "y (space)"}},
            "zaxis": {**ax, "title": {"text": "z (space)"}},
            "aspectmode": "cube",
            "domain": {"x": [0.14, 0.58], "y": [0.0, 1.0]},
            "camera": {"eye": {"x": 1.5, "y": 1.3, "z": 0.9}},
            "uirevision": "keep",
        },
        template="plotly_white",
    )
    return fig


def _line3d(go, end, colour, name, *, width, marker_tip=False, dash=None, legend=True):
    """A segment from the origin to ``end`` (a vector or an axis)."""
    return go.Scatter3d(
        x=[0.0, float(end[0])],
        y=[0.0, float(end[1])],
        z=[0.0, float(end[2])],
        mode="lines+markers" if marker_tip else "lines",
        line={"color": colour, "width": width, **({"dash": dash} if dash else {})},
        marker={"size": [0, 5], "color": colour},
        name=name,
        legendgroup=name,
        showlegend=legend,
        hoverinfo="skip",
    )


def _xyz(v: np.ndarray, cls):
    """A trace of type ``cls`` holding only coordinates (an animation frame's update)."""
    if len(v) <= 4:  # a segment: short lists are smaller than base64 blocks
        v = np.round(np.asarray(v, dtype=float), 5)
        return cls(x=v[:, 0].tolist(), y=v[:, 1].tolist(), z=v[:, 2].tolist())
    v = np.asarray(v, dtype=np.float32)
    return cls(x=v[:, 0], y=v[:, 1], z=v[:, 2])


def _series(t: np.ndarray, y: np.ndarray, m: int = _MAX_SERIES) -> dict:
    """``x``, ``y`` of a time series, at most about ``m`` points (float32).

    Longer series keep the first and last samples and the minimum and maximum of
    each of ``m/2`` bins, so the envelope of fast oscillations or noise survives.
    """
    n = t.size
    if n > m:
        edges = np.linspace(0, n, m // 2 + 1).astype(int)
        idx = [0, n - 1]
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            seg = y[a:b]
            idx += [a + int(np.argmin(seg)), a + int(np.argmax(seg))]
        idx = np.unique(idx)
        t, y = t[idx], y[idx]
    return {"x": np.asarray(t, dtype=np.float32), "y": np.asarray(y, dtype=np.float32)}


def _yrange(y: np.ndarray) -> tuple[float, float]:
    lo, hi = float(np.min(y)), float(np.max(y))
    pad = 0.08 * (hi - lo) if hi > lo else max(1e-12, 0.1 * abs(hi)) + 1e-9
    return lo - pad, hi + pad


# --------------------------------------------------------------------------- page


def _fmt(v: Any) -> str:
    if isinstance(v, bool) or v is None:
        return str(v)
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        return f"{float(v):.6g}" if math.isfinite(v) else str(float(v))
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, Sequence) and not isinstance(v, str):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    return str(v)


def _flatten(d: Mapping[str, Any], prefix: str = "") -> list[tuple[str, str]]:
    rows = []
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            rows += _flatten(v, key + ".") or [(key, "{}")]
        else:
            rows.append((key, _fmt(v)))
    return rows


# Plotly.animate rejects its promise WITHOUT a reason when a newer call (Pause, the
# slider) interrupts a running animation: a signal, not an error (plotly.js #2438).
# Only those reason-less rejections are silenced; every other error still surfaces.
_GUARD_JS = """window.addEventListener("unhandledrejection", function (e) {
  if (e.reason === undefined) { e.preventDefault(); }
});"""

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 1.2em 2em;
       color: #222; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
p.meta { color: #555; margin-top: 0; }
table.summary { border-collapse: collapse; font-size: 0.92em; margin-top: 1em; }
table.summary th, table.summary td { border: 1px solid #ccc; padding: 3px 10px;
       text-align: left; vertical-align: top; }
table.summary th { background: #f1f3f6; font-weight: 600; font-family: monospace; }
table.summary td { font-family: monospace; white-space: pre-wrap; }
"""


def _page(fig, *, title: str, tr: Trajectory, summary, sections=()) -> str:
    import plotly.offline

    js = plotly.offline.get_plotlyjs().replace("</script", "<\\/script")
    div = fig.to_html(
        full_html=False,
        include_plotlyjs=False,
        include_mathjax=False,
        div_id=_DIV_ID,
        auto_play=False,
        config={"displaylogo": False, "responsive": True},
    )
    esc = html.escape
    meta = (
        f"method: <b>{esc(str(tr.method))}</b> &middot; {tr.t.size} samples, "
        f"t = {_fmt(float(tr.t[0]))} .. {_fmt(float(tr.t[-1]))} s &middot; scene in space "
        "axes (v_space = R v_body); body axes x, y, z in red, green, blue"
    )
    table = ""
    if summary is not None:
        body = "\n".join(
            f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in _flatten(summary)
        )
        table = f'<h2>Summary</h2>\n<table class="summary">\n{body}\n</table>'
    extra = "".join(f"<h2>{esc(head)}</h2>\n<div>{content}</div>\n" for head, content in sections)
    table = extra + table
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{esc(title)}</title>\n<style>{_CSS}</style>\n"
        f'<script type="text/javascript">{_GUARD_JS}</script>\n'
        f'<script type="text/javascript">{js}</script>\n</head>\n<body>\n'
        f'<h1>{esc(title)}</h1>\n<p class="meta">{meta}</p>\n{div}\n{table}\n'
        "</body>\n</html>\n"
    )


def _write_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; a report is meant to be shared
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
