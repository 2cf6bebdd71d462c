"""Switching charts where generalized coordinates become singular (theory §11.4).

Spherical coordinates ``(theta, phi)`` cover the sphere except its two poles, where
``phi`` is undefined and Lagrange's equations divide by ``sin theta``: a spherical
pendulum swinging through the bottom point cannot be integrated in the chart whose
pole is there. An *atlas* of charts whose singular sets are disjoint covers it: the
motion is integrated in one chart until the event "too close to this chart's
singularity" (:class:`poinsot.events.Event`, located to round-off), then the state is
carried to the chart that is farthest from its own singularity, through the space
position and velocity, and the integration goes on there.

Examples
--------
A spherical pendulum released in a vertical plane swings through the bottom point,
where the chart with its pole there is singular; the atlas hands over to the chart
with poles at ``+-x``:

>>> import numpy as np
>>> atlas = spherical_pendulum_charts(1.0, g=9.81)
>>> r0 = [np.sin(1.0), 0.0, -np.cos(1.0)]
>>> tr = simulate_charts(atlas, r0, [0.0, 0.0, 0.0], np.linspace(0, 2.0, 201))
>>> sorted(set(tr.chart.tolist())), bool(np.allclose(np.linalg.norm(tr.position, axis=1), 1.0))
([0, 1], True)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_times, as_vec3
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError
from ..events import EventLog
from ..trajectory import Channel, PointTrajectory

__all__ = ["CoordinateChart", "ChartTrajectory", "simulate_charts", "spherical_pendulum_charts"]


@dataclass(frozen=True)
class CoordinateChart:
    """One chart of an atlas: its equations of motion in its coordinates and the maps
    to and from the space state.

    Attributes
    ----------
    name : str
    rhs : callable
        ``rhs(t, y) -> y'`` with ``y = (q, q')`` in this chart.
    to_space : callable
        ``to_space(y) -> (r, v)``: the position (m) and velocity (m/s), space axes.
    from_space : callable
        ``from_space(r, v) -> y``.
    quality : callable
        ``quality(y) -> float``: how far from this chart's singularity (1 far, 0 on
        it; e.g. ``sin theta``).
    """

    name: str
    rhs: Callable[[float, FloatArray], FloatArray]
    to_space: Callable[[FloatArray], tuple[FloatArray, FloatArray]]
    from_space: Callable[[FloatArray, FloatArray], FloatArray]
    quality: Callable[[FloatArray], float]


@dataclass(frozen=True, eq=False, repr=False)
class ChartTrajectory(PointTrajectory):
    """A :class:`~poinsot.trajectory.PointTrajectory` integrated in an atlas of charts:
    also ``chart`` (n,), the chart of each sample, and ``coordinates`` (n, 2k), its
    ``(q, q')`` in that chart."""

    chart: Any = None
    coordinates: Any = None

    def channels(self) -> dict[str, Channel]:
        """The point's channels and ``chart`` (the index of the chart in use)."""
        out = super().channels()
        if self.chart is not None:
            out["chart"] = Channel("chart", np.asarray(self.chart, dtype=float), "1", (),
                                   "index of the chart in use")  # fmt: skip
        return out


def simulate_charts(
    charts: Sequence[CoordinateChart],
    position0: ArrayLike,
    velocity0: ArrayLike,
    t: ArrayLike,
    *,
    switch_below: float = 0.5,
    rtol: float = 1e-12,
    atol: float = 1e-14,
    max_switches: int = 10000,
) -> ChartTrajectory:
    """Integrate in an atlas of charts, switching charts near their singularities
    (theory §11.4).

    Parameters
    ----------
    charts : sequence of CoordinateChart
        The atlas (at least two charts whose singular sets are disjoint).
    position0, velocity0 : array_like, shape (3,)
        The initial state in space (m, m/s).
    t : array_like, shape (n,)
        Output times (s).
    switch_below : float, optional
        A chart is left when its ``quality`` falls to this (default 0.5: for spherical
        coordinates, 30 degrees from a pole); the next chart is the one of highest
        quality there.
    rtol, atol : float, optional
        DOP853's tolerances in each chart.
    max_switches : int, optional
        At most this many switches.

    Returns
    -------
    ChartTrajectory
        ``position``, ``velocity`` (space axes), ``chart`` and ``coordinates`` per
        sample; ``info["events"]`` the switches (``"switch"``, state ``(r, v)``).

    Examples
    --------
    A pendulum released at 1 rad nears the bottom point (the first chart's pole) and is
    handed to the second chart:

    >>> import numpy as np
    >>> atlas = spherical_pendulum_charts(1.0, g=9.81)
    >>> tr = simulate_charts(atlas, [np.sin(1.0), 0, -np.cos(1.0)], [0, 0, 0],
    ...                      np.linspace(0, 1.0, 101))
    >>> len(tr.info["events"]), int(tr.chart[0]), int(tr.chart[-1])
    (1, 0, 1)
    """
    from scipy.integrate import solve_ivp

    atlas = list(charts)
    if len(atlas) < 2 or not all(isinstance(c, CoordinateChart) for c in atlas):
        raise InvalidTypeError("Expected `charts` to be two or more CoordinateChart objects.")
    if not 0.0 < float(switch_below) < 1.0:
        raise InvalidInputError(f"Expected `switch_below` in (0, 1), got {switch_below!r}.")
    r = as_vec3(position0, "position0").reshape(3)
    v = as_vec3(velocity0, "velocity0").reshape(3)
    tt = as_times(t, "t")

    def best(r: FloatArray, v: FloatArray) -> tuple[int, FloatArray]:
        ys = [c.from_space(r, v) for c in atlas]
        k = int(np.argmax([c.quality(y) for c, y in zip(atlas, ys, strict=True)]))
        return k, ys[k]

    k_chart, y = best(r, v)
    n = tt.size
    width = y.size
    pos, vel = np.empty((n, 3)), np.empty((n, 3))
    chart_of, coords = np.empty(n, dtype=np.int64), np.empty((n, width))
    pos[0], vel[0] = r, v
    chart_of[0], coords[0] = k_chart, y
    switches: list[tuple[float, int, FloatArray, float]] = []
    t_now, k = float(tt[0]), 1
    for _ in range(max_switches):
        if t_now >= tt[-1]:
            break
        c = atlas[k_chart]

        def near(_: float, yy: FloatArray, c: CoordinateChart = c) -> float:
            return c.quality(yy) - switch_below

        near.terminal, near.direction = True, -1  # type: ignore[attr-defined]
        sol = solve_ivp(c.rhs, (t_now, float(tt[-1])), y, method="DOP853", rtol=rtol,
                        atol=atol, events=near, dense_output=True)  # fmt: skip
        if sol.status < 0:
            raise IntegrationError(f"chart {c.name!r} failed after t = {t_now:.6g} s: "
                                   f"{sol.message}")  # fmt: skip
        t_end = float(sol.t[-1])
        while k < n and tt[k] <= t_end:
            yk = sol.sol(tt[k])
            pos[k], vel[k] = c.to_space(yk)
            chart_of[k], coords[k] = k_chart, yk
            k += 1
        if sol.status == 0:
            break
        t_now = t_end
        r, v = c.to_space(sol.y[:, -1])
        switches.append((t_now, 0, np.concatenate([r, v]), -1.0))
        k_new, y = best(r, v)
        if k_new == k_chart:
            raise IntegrationError(
                f"no chart of the atlas is better than {c.name!r} at t = {t_now:.6g} s: "
                "the charts' singular sets overlap"
            )
        k_chart = k_new
    else:
        raise IntegrationError(f"more than max_switches = {max_switches} chart switches")
    log = EventLog.of_one_body(("switch",), switches, 6)
    return ChartTrajectory(
        t=tt, position=pos, velocity=vel, method="DOP853 (atlas)", frame_name="inertial",
        chart=chart_of, coordinates=coords,
        info={"solver": "DOP853", "rtol": rtol, "atol": atol, "events": log},
    )  # fmt: skip


def spherical_pendulum_charts(
    length: float, g: float = 9.80665
) -> tuple[CoordinateChart, CoordinateChart]:
    """Two spherical-coordinate charts of a spherical pendulum (length ``L``, gravity
    ``-g e_z``): poles at ``+-z`` and at ``+-x`` (theory §11.4).

    In a chart with axes ``M`` (columns in space), ``r = L M u`` with ``u = (sin theta
    cos phi, sin theta sin phi, -cos theta)``; Lagrange's equations with ``a = M^T g /
    L`` are

    ``theta'' = sin theta cos theta phi'^2 + a . du/dtheta``,
    ``phi'' = -2 cot theta theta' phi' + a . (-sin phi, cos phi, 0) / sin theta``,

    singular where ``sin theta = 0``; ``quality = |sin theta|``.

    >>> a, b = spherical_pendulum_charts(1.0)
    >>> y = a.from_space(np.array([0.0, 0.0, -1.0]), np.zeros(3))
    >>> float(a.quality(y)), float(b.quality(b.from_space(np.array([0.0, 0.0, -1.0]), np.zeros(3))))
    (0.0, 1.0)
    """
    lg = float(length)
    if not lg > 0:
        raise InvalidInputError(f"Expected `length` > 0 (m), got {length!r}.")
    gravity = np.array([0.0, 0.0, -float(g)])

    def chart(name: str, m: FloatArray) -> CoordinateChart:
        a = m.T @ gravity / lg

        def rhs(_: float, y: FloatArray) -> FloatArray:
            th, ph, thd, phd = y
            s, c = math.sin(th), math.cos(th)
            sp, cp = math.sin(ph), math.cos(ph)
            du_th = np.array([c * cp, c * sp, s])
            thdd = s * c * phd * phd + float(a @ du_th)
            phdd = -2.0 * c / s * thd * phd + float(a @ np.array([-sp, cp, 0.0])) / s
            return np.array([thd, phd, thdd, phdd])

        def to_space(y: FloatArray) -> tuple[FloatArray, FloatArray]:
            th, ph, thd, phd = y
            s, c = math.sin(th), math.cos(th)
            sp, cp = math.sin(ph), math.cos(ph)
            u = np.array([s * cp, s * sp, -c])
            ud = np.array([c * cp, c * sp, s]) * thd + np.array([-s * sp, s * cp, 0.0]) * phd
            return lg * (m @ u), lg * (m @ ud)

        def from_space(r: FloatArray, v: FloatArray) -> FloatArray:
            u, ud = m.T @ r / lg, m.T @ v / lg
            th = math.atan2(math.hypot(u[0], u[1]), -u[2])
            ph = math.atan2(u[1], u[0])
            s, c = math.sin(th), math.cos(th)
            sp, cp = math.sin(ph), math.cos(ph)
            thd = float(ud @ np.array([c * cp, c * sp, s]))
            phd = float(ud @ np.array([-sp, cp, 0.0])) / s if s > 0 else 0.0
            return np.array([th, ph, thd, phd])

        return CoordinateChart(name, rhs, to_space, from_space, lambda y: abs(math.sin(y[0])))

    z_poles = chart("poles at +-z", np.eye(3))
    # the second chart's -z axis is space +x: columns (x', y', z') = (e_z, e_y, -e_x)
    x_poles = chart("poles at +-x", np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]))
    return z_poles, x_poles
