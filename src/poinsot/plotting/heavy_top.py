"""Figures of the heavy top (docs/theory.md §10, docs/heavy-top.md).

The track of the symmetry axis on the unit sphere inside the nutation band
(waves, cusps, loops), the cubic ``P(u)`` with its roots, ``theta(t)`` exact
against a numerical trajectory, the drift of the invariants of a heavy body, and
the Kovalevskaya integral along trajectories.

matplotlib is imported here only (a leaf module; ``import poinsot`` never loads
it). Each function draws on ``ax`` (a new figure if ``None``) and returns it; it
never changes the backend or closes a figure.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .._drift import relative_change
from .._typing import ArrayLike
from ..dynamics.heavy import HeavyRigidBody
from ..dynamics.lagrange_top import LagrangeTop
from ..errors import InvalidInputError, InvalidTypeError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..dynamics.heavy import HeavyRigidBody
    from ..dynamics.lagrange_top import LagrangeTop
    from ..trajectory import Trajectory

__all__ = [
    "plot_axis_track",
    "plot_cubic",
    "plot_nutation",
    "plot_invariant_drift",
    "plot_kovalevskaya",
]


def _top(top: object) -> Any:
    if not isinstance(top, LagrangeTop):
        raise InvalidTypeError(
            f"Expected `top` to be a poinsot.dynamics.LagrangeTop, got {type(top).__name__}."
        )
    return top


def _axes(ax: Axes | None, projection: str | None = None) -> Any:
    if ax is not None:
        if projection == "3d" and getattr(ax, "name", "") != "3d":
            raise InvalidInputError("Expected `ax` to be a 3D axes (projection='3d').")
        return ax
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(6, 6) if projection else (7, 3.6))
    return fig.add_subplot(projection=projection)


def _window(top: Any, periods: float) -> float:
    period = top.nutation_period
    return periods * period if np.isfinite(period) and period > 0 else 10.0


def plot_axis_track(
    top: LagrangeTop,
    t: ArrayLike | None = None,
    *,
    periods: float = 3.0,
    n: int = 1500,
    ax: Any = None,  # 3D axes: mpl_toolkits.mplot3d is untyped
) -> Axes:
    """The track of the symmetry axis ``e_3`` on the unit sphere, inside the nutation band.

    Parameters
    ----------
    top : LagrangeTop
    t : array_like, optional
        Times (s); default ``n`` samples over ``periods`` nutation periods.
    periods : float, optional
    n : int, optional
    ax : Axes3D, optional
        3D axes; a new figure if ``None``.

    Returns
    -------
    Axes3D
        With the sphere (wireframe), the circles ``theta_min`` and ``theta_max``
        (dashed), the vertical, and the track (waves, cusps or loops are visible).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import LagrangeTop
    >>> from poinsot.plotting.heavy_top import plot_axis_track
    >>> ax = plot_axis_track(LagrangeTop(2.0, 1.0, 4.0, theta=0.5, spin=20.0))
    >>> ax.name
    '3d'
    """
    top = _top(top)
    ax = _axes(ax, "3d")
    tt = np.linspace(0.0, _window(top, periods), n) if t is None else np.asarray(t, float)
    axis = top.rotation(tt).apply(np.array([0.0, 0.0, 1.0]))
    u = np.linspace(0.0, 2.0 * np.pi, 40)
    v = np.linspace(0.0, np.pi, 21)
    ax.plot_wireframe(
        np.outer(np.cos(u), np.sin(v)),
        np.outer(np.sin(u), np.sin(v)),
        np.outer(np.ones_like(u), np.cos(v)),
        color="0.85",
        linewidth=0.4,
    )
    s = np.linspace(0.0, 2.0 * np.pi, 200)
    for th, lab in zip(top.nutation_bounds, ("theta_min", "theta_max"), strict=True):
        ax.plot(
            np.sin(th) * np.cos(s),
            np.sin(th) * np.sin(s),
            np.full_like(s, np.cos(th)),
            "--",
            color="0.4",
            linewidth=0.8,
            label=lab,
        )
    ax.plot([0, 0], [0, 0], [-1.1, 1.1], color="0.6", linewidth=0.6)
    ax.plot(
        axis[:, 0],
        axis[:, 1],
        axis[:, 2],
        color="C3",
        linewidth=1.2,
        label=f"symmetry axis ({top.motion_type})",
    )
    for set_lim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        set_lim(-1.0, 1.0)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (up)")
    ax.set_title("symmetry axis on the unit sphere (docs/theory.md §10)")
    ax.legend(loc="upper left", fontsize=7)
    return ax


def plot_cubic(top: LagrangeTop, *, n: int = 400, ax: Axes | None = None) -> Axes:
    """The cubic ``P(u) = u'^2`` over ``u = cos(theta)`` with its roots and the band.

    Parameters
    ----------
    top : LagrangeTop
    n : int, optional
    ax : Axes, optional

    Returns
    -------
    Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import LagrangeTop
    >>> from poinsot.plotting.heavy_top import plot_cubic
    >>> ax = plot_cubic(LagrangeTop(2.0, 1.0, 4.0, theta=0.5, spin=20.0))
    >>> ax.get_xlabel()
    'u = cos(theta)'
    """
    top = _top(top)
    ax = _axes(ax)
    roots = [r for r in top.cos_theta_roots if np.isfinite(r)]
    lo = min(-1.0, min(roots))
    hi = max(1.0, max(roots))
    pad = 0.05 * (hi - lo)
    u = np.linspace(lo - pad, hi + pad, n)
    p = np.asarray(top.P(u))
    ax.plot(u, p, color="C0", label="P(u)")
    ax.axhline(0.0, color="0.5", linewidth=0.6)
    for x in (-1.0, 1.0):
        ax.axvline(x, color="0.7", linewidth=0.6, linestyle=":")
    ax.plot(roots, np.zeros(len(roots)), "o", color="C3", label="roots u1 <= u2 <= u3")
    a, b = np.cos(top.nutation_bounds[1]), np.cos(top.nutation_bounds[0])
    ax.axvspan(a, b, color="C2", alpha=0.2, label="nutation band")
    band = (u >= -1.0) & (u <= 1.0)
    top_p = np.max(np.abs(p[band])) if np.any(band) else 1.0
    ax.set_ylim(-1.2 * top_p, 1.2 * top_p)
    u1, u2 = roots[0], roots[1]
    if 0.0 < u2 - u1 < 0.05 * (hi - lo):  # a narrow band: zoom on it
        ins = ax.inset_axes((0.62, 0.1, 0.35, 0.35))
        d = u2 - u1
        uz = np.linspace(u1 - 0.3 * d, u2 + 0.3 * d, 200)
        ins.plot(uz, top.P(uz), color="C0")
        ins.axhline(0.0, color="0.5", linewidth=0.6)
        ins.axvspan(u1, u2, color="C2", alpha=0.2)
        ins.plot([u1, u2], [0.0, 0.0], "o", color="C3", markersize=3)
        ins.tick_params(labelsize=6)
        ins.set_title("band (zoom)", fontsize=7)
    ax.set_xlabel("u = cos(theta)")
    ax.set_ylabel("P(u) = u'^2 (1/s^2)")
    ax.set_title("the cubic of the Lagrange top (docs/theory.md §10)")
    ax.legend(fontsize=7)
    return ax


def plot_nutation(
    top: LagrangeTop,
    trajectory: Trajectory | None = None,
    *,
    periods: float = 3.0,
    n: int = 1000,
    ax: Axes | None = None,
) -> Axes:
    """``theta(t)`` exact, with a numerical trajectory's tilt if given, and the bounds.

    Parameters
    ----------
    top : LagrangeTop
    trajectory : Trajectory, optional
        A numerical run of the same top (its tilt ``acos((R e_3)_z)`` is drawn).
    periods, n : optional
        Window of the exact curve when no trajectory is given.
    ax : Axes, optional

    Returns
    -------
    Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import LagrangeTop
    >>> from poinsot.plotting.heavy_top import plot_nutation
    >>> len(plot_nutation(LagrangeTop(2.0, 1.0, 4.0, theta=0.5, spin=20.0)).lines) >= 3
    True
    """
    top = _top(top)
    ax = _axes(ax)
    if trajectory is not None:
        t = np.asarray(trajectory.t, dtype=float)
        tt = np.linspace(t[0], t[-1], max(n, 4 * t.size))
    else:
        tt = np.linspace(0.0, _window(top, periods), n)
    ax.plot(tt, np.degrees(top.theta(tt)), color="C0", label="exact (elliptic functions)")
    if trajectory is not None:
        axis = trajectory.rotation.apply(np.array([0.0, 0.0, 1.0]))
        if axis.ndim != 2:
            raise InvalidInputError("Expected `trajectory` of one body.")
        tilt = np.degrees(np.arccos(np.clip(axis[:, 2], -1.0, 1.0)))
        step = max(1, t.size // 200)
        ax.plot(
            t[::step],
            tilt[::step],
            ".",
            color="C1",
            markersize=3,
            label=f"numerical ({trajectory.method})",
        )
    for th in top.nutation_bounds:
        ax.axhline(np.degrees(th), color="0.5", linestyle="--", linewidth=0.7)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("theta (deg)")
    ax.set_title(f"nutation: {top.motion_type} (docs/theory.md §10)")
    ax.legend(fontsize=7)
    return ax


def plot_invariant_drift(
    body: HeavyRigidBody, trajectory: Trajectory, *, ax: Axes | None = None
) -> Axes:
    """Relative drift of ``E``, ``K_z`` and ``|gamma| - 1`` of a heavy body along a run.

    Parameters
    ----------
    body : HeavyRigidBody
    trajectory : Trajectory
        A run of ``body`` (one body).
    ax : Axes, optional

    Returns
    -------
    Axes
        ``|E - E0| / |E0|``, ``|K_z - K_z0| / |K|`` and ``||gamma| - 1|`` on a log scale.

    Examples
    --------
    >>> import matplotlib, numpy as np
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import HeavyRigidBody
    >>> from poinsot.plotting.heavy_top import plot_invariant_drift
    >>> b = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.1, 0.0, 0.4])
    >>> tr = b.simulate([1.0, 0, 0, 0], [0.2, 0.0, 20.0], np.linspace(0, 1, 11), max_step=1e-3)
    >>> plot_invariant_drift(b, tr).get_yscale()
    'log'
    """

    if not isinstance(body, HeavyRigidBody):
        raise InvalidTypeError(
            f"Expected `body` to be a poinsot.dynamics.HeavyRigidBody, got {type(body).__name__}."
        )
    ax = _axes(ax)
    t = np.asarray(trajectory.t)
    e = np.asarray(body.energy(trajectory.rotation, trajectory.omega))
    kz = np.asarray(body.momentum_z(trajectory.rotation, trajectory.omega))
    k = np.linalg.norm(trajectory.omega @ body.inertia_tensor.T, axis=-1)
    gam = np.linalg.norm(body.gamma(trajectory.rotation), axis=-1)
    tiny = 1e-17
    ax.plot(t, np.abs(relative_change(e, floor=tiny)) + tiny, label="|E - E0| / |E0|")
    ax.plot(t, np.abs(relative_change(kz, k[0], floor=tiny)) + tiny, label="|K_z - K_z0| / |K|")
    ax.plot(t, np.abs(gam - 1.0) + tiny, label="| |gamma| - 1 |")
    ax.set_yscale("log")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("relative drift")
    ax.set_title(f"invariants of the heavy body ({trajectory.method})")
    ax.legend(fontsize=7)
    return ax


def plot_kovalevskaya(
    runs: Sequence[tuple[str, HeavyRigidBody, Trajectory]], *, ax: Axes | None = None
) -> Axes:
    """The Kovalevskaya integral ``k(t) / k(0) - 1`` along one or more runs.

    Parameters
    ----------
    runs : sequence of (label, HeavyRigidBody, Trajectory)
        E.g. a Kovalevskaya top (``A = B = 2 C``) and a perturbed one.
    ax : Axes, optional

    Returns
    -------
    Axes

    Examples
    --------
    >>> import matplotlib, numpy as np
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import HeavyRigidBody
    >>> from poinsot.plotting.heavy_top import plot_kovalevskaya
    >>> b = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.3, 0.0, 0.0])
    >>> tr = b.simulate([1.0, 0, 0, 0], [1.0, 0.5, 2.0], np.linspace(0, 1, 11), max_step=1e-3)
    >>> plot_kovalevskaya([("A = B = 2C", b, tr)]).get_ylabel()
    'k(t) / k(0) - 1'
    """
    ax = _axes(ax)
    for label, body, tr in runs:
        k = np.asarray(body.kovalevskaya_integral(tr.rotation, tr.omega))
        ax.plot(tr.t, k / k[0] - 1.0, label=label)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("k(t) / k(0) - 1")
    ax.set_title("Kovalevskaya integral (docs/theory.md §10)")
    ax.legend(fontsize=7)
    return ax
