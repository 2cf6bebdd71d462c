"""Figures of particle motion: paths in a moving frame, orbits, the Foucault plane.

Every function takes ``ax=None`` (a new figure) and returns the axes it drew on;
matplotlib is imported inside the functions. See ``docs/particles.md``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, SupportsFloat

import numpy as np

from .._typing import ArrayLike
from ..dynamics.earth import swing_plane_angles
from ..errors import InvalidInputError, InvalidTypeError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..dynamics.central import CentralOrbit
    from ..dynamics.particles import ParticleTrajectory

__all__ = [
    "plot_path",
    "plot_particle_path",
    "plot_orbit",
    "plot_effective_potential",
    "plot_swing_plane",
]


def _new_axes(ax: Axes | None, size: tuple[float, float] = (6.0, 4.5)) -> Axes:
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def _components(components: object) -> tuple[int, int]:
    if (
        not isinstance(components, tuple | list)
        or len(components) != 2
        or any(c not in (0, 1, 2) for c in components)
    ):
        raise InvalidInputError(
            f"Expected `components` to be two axis indices from 0, 1, 2, got {components!r}."
        )
    return tuple(components)


def plot_path(
    position: ArrayLike,
    *,
    components: tuple[int, int] = (0, 1),
    ax: Axes | None = None,
    title: str | None = None,
    label: str | None = None,
    axis_names: tuple[str, str, str] = ("x", "y", "z"),
) -> Axes:
    """A path projected on two axes, its start marked.

    Parameters
    ----------
    position : array_like, shape (n, 3) or (n, N, 3)
        Positions (m); a batch draws one line per path.
    components : pair of int, optional
        Axes projected on (default ``(0, 1)``).
    title, label : str, optional
    axis_names : tuple of 3 str, optional
        Names of the axes for the labels (e.g. ``("east", "north", "up")``).

    Returns
    -------
    Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.plotting import plot_path
    >>> t = np.linspace(0, 6, 50)
    >>> ax = plot_path(np.stack([np.cos(t), np.sin(t), t], -1), components=(0, 2))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('x (m)', 'z (m)')
    """
    i, j = _components(components)
    p = np.asarray(position, dtype=float)
    if p.ndim < 2 or p.shape[-1] != 3:
        raise InvalidInputError(f"Expected `position` of shape (n, 3) or (n, N, 3), got {p.shape}.")
    ax = _new_axes(ax)
    p = p.reshape(p.shape[0], -1, 3)
    for k in range(p.shape[1]):
        ax.plot(p[:, k, i], p[:, k, j], label=label if k == 0 else None)
    ax.plot(p[0, :, i], p[0, :, j], "ko", ms=4, label="start")
    ax.set_xlabel(f"{axis_names[i]} (m)")
    ax.set_ylabel(f"{axis_names[j]} (m)")
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_particle_path(
    trajectory: ParticleTrajectory,
    *,
    frame: str = "relative",
    components: tuple[int, int] = (0, 1),
    ax: Axes | None = None,
    label: str | None = None,
) -> Axes:
    """The path of a particle: relative to the moving frame or in the inertial frame.

    Parameters
    ----------
    trajectory : ParticleTrajectory
        From :func:`poinsot.dynamics.simulate_particle` (``inertial=True`` for
        ``frame="inertial"``); a batch draws one line per particle.
    frame : {"relative", "inertial"}
        Which path to draw.
    components : pair of int, optional
        Axes projected on (default ``(0, 1)``: x and y, e.g. east and north).
    ax : Axes, optional
    label : str, optional
        Legend label.

    Returns
    -------
    Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.kinematics import FrameMotion
    >>> from poinsot.dynamics import simulate_particle
    >>> from poinsot.plotting import plot_particle_path
    >>> tr = simulate_particle(FrameMotion(omega=[0, 0, 1]), None, [1, 0, 0], [0, 0, 0],
    ...                        np.linspace(0, 3, 50), inertial=True)
    >>> ax = plot_particle_path(tr, frame="inertial")
    >>> len(ax.lines)
    2
    """
    if not hasattr(trajectory, "position") or not hasattr(trajectory, "inertial_position"):
        raise InvalidTypeError(
            f"Expected `trajectory` to be a ParticleTrajectory, got {type(trajectory).__name__}."
        )
    i, j = _components(components)
    p: np.ndarray | None
    if frame == "relative":
        p = trajectory.position
        words = "relative to the moving frame"
    elif frame == "inertial":
        p = trajectory.inertial_position
        if p is None:
            raise InvalidInputError(
                "Expected a trajectory simulated with inertial=True for frame='inertial'."
            )
        words = "in the inertial frame"
    else:
        raise InvalidInputError(f"Expected `frame` 'relative' or 'inertial', got {frame!r}.")
    return plot_path(p, components=(i, j), ax=ax, title=f"Particle path {words}", label=label)


def plot_orbit(
    orbit: CentralOrbit, t: ArrayLike | None = None, *, samples: int = 600, ax: Axes | None = None
) -> Axes:
    """An orbit in its plane, with the centre, the apsides and the pericentre marked.

    Parameters
    ----------
    orbit : CentralOrbit
    t : array_like, optional
        Times to draw (s). Default: three radial periods (bound orbits) or the
        time to go out to ~5 pericentre distances and back (unbound).
    samples : int, optional
        Number of points when ``t`` is not given.
    ax : Axes, optional

    Returns
    -------
    Axes
        In the plane axes ``(e1, e2)`` of the orbit (m); dashed circles at
        ``r_min`` and ``r_max``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import CentralOrbit, kepler, inverse_square
    >>> from poinsot.plotting import plot_orbit
    >>> ax = plot_orbit(CentralOrbit(kepler(1) + inverse_square(0.05), energy=-0.3,
    ...                              angular_momentum=0.9))
    >>> ax.get_title()
    'Central-force orbit: apsidal angle 0.9435 pi'
    """
    if not hasattr(orbit, "apsides") or not hasattr(orbit, "polar"):
        raise InvalidTypeError(f"Expected a CentralOrbit, got {type(orbit).__name__}.")
    r1, r2 = orbit.apsides
    if t is None:
        if orbit.unbound:
            span = 4.0 * r1 / max(1e-300, abs(orbit.angular_momentum) / (orbit.mass * r1))
            span = max(span, _escape_time(orbit))
            t = orbit.pericentre_time + np.linspace(-span, span, samples)
        else:
            t = orbit.pericentre_time + np.linspace(0.0, 3.0 * orbit.radial_period, samples)
    r, phi = orbit.polar(t)
    ax = _new_axes(ax, (5.5, 5.5))
    ax.plot(r * np.cos(phi), r * np.sin(phi), lw=1.2, label="orbit")
    ax.plot([0], [0], "k+", ms=10, label="centre")
    th = np.linspace(0, 2 * np.pi, 361)
    ax.plot(r1 * np.cos(th), r1 * np.sin(th), "g--", lw=0.7, label=f"r_min = {r1:.4g} m")
    if math.isfinite(r2):
        ax.plot(r2 * np.cos(th), r2 * np.sin(th), "r--", lw=0.7, label=f"r_max = {r2:.4g} m")
    a = orbit.pericentre_angle
    ax.plot([r1 * math.cos(a)], [r1 * math.sin(a)], "go", label="pericentre")
    if math.isfinite(r2) and not orbit.is_circular:
        b = a + math.copysign(orbit.apsidal_angle, orbit.angular_momentum)
        ax.plot([r2 * math.cos(b)], [r2 * math.sin(b)], "ro", label="next apocentre")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("e1 (m)")
    ax.set_ylabel("e2 (m)")
    ax.set_title(f"Central-force orbit: apsidal angle {orbit.apsidal_angle / math.pi:.4f} pi")
    ax.legend(loc="upper right", fontsize="small")
    return ax


def _escape_time(orbit: Any) -> float:
    v = math.sqrt(max(2.0 * orbit.energy / orbit.mass, 1e-300))
    return 5.0 * orbit.apsides.pericentre / v


def plot_effective_potential(
    orbit: CentralOrbit, *, ax: Axes | None = None, span: float = 4.0
) -> Axes:
    """``U_eff(r) = U(r) + L^2/(2 m r^2)``, the energy level and the apsides.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import CentralOrbit, kepler
    >>> from poinsot.plotting import plot_effective_potential
    >>> ax = plot_effective_potential(CentralOrbit(kepler(1), energy=-0.5, angular_momentum=0.8))
    >>> ax.get_xlabel()
    'r (m)'
    """
    r1, r2 = orbit.apsides
    top = r2 if math.isfinite(r2) else span * r1
    r = np.linspace(0.4 * r1, 1.3 * top, 500)
    ax = _new_axes(ax)
    u = orbit.effective_potential(r)
    ax.plot(r, u, label=r"$U_{eff}(r)$")
    ax.axhline(orbit.energy, color="k", lw=0.8, label=f"E = {orbit.energy:.4g} J")
    ax.plot([r1], [orbit.energy], "go")
    if math.isfinite(r2):
        ax.plot([r2], [orbit.energy], "ro")
    lo = min(float(np.min(u)), orbit.energy)
    hi = orbit.energy + 2.0 * (orbit.energy - lo + 1e-300)
    ax.set_ylim(lo - 0.1 * (hi - lo), hi)
    ax.set_xlabel("r (m)")
    ax.set_ylabel("energy (J)")
    ax.set_title("Effective potential (docs/theory.md §9)")
    ax.legend(fontsize="small")
    return ax


def plot_swing_plane(
    trajectory: ParticleTrajectory, *, rate: SupportsFloat | None = None, ax: Axes | None = None
) -> Axes:
    """Azimuth of a pendulum's swing plane against time, with a predicted rate.

    Parameters
    ----------
    trajectory : ParticleTrajectory
        A pendulum (e.g. :func:`poinsot.dynamics.foucault_pendulum`).
    rate : float, optional
        Predicted turning rate (rad/s), e.g.
        :func:`~poinsot.dynamics.foucault_precession_rate`, drawn as a line.
    ax : Axes, optional

    Returns
    -------
    Axes
        Azimuth in degrees (counter-clockwise from x, east) at each extreme of
        the swing (:func:`poinsot.dynamics.swing_plane_angles`).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.dynamics import foucault_pendulum, foucault_precession_rate
    >>> from poinsot.plotting import plot_swing_plane
    >>> tr = foucault_pendulum(10.0, 0.8, np.linspace(0, 100, 5001), omega=1e-2)
    >>> ax = plot_swing_plane(tr, rate=foucault_precession_rate(0.8, 1e-2))
    >>> len(ax.lines)
    2
    """

    p = np.asarray(trajectory.position)
    v = np.asarray(trajectory.velocity)
    if p.ndim != 2:
        raise InvalidInputError(f"Expected one particle (position (n, 3)), got {p.shape}.")
    tt, ang = swing_plane_angles(trajectory.t, p, v)
    ax = _new_axes(ax, (7.0, 3.6))
    ax.plot(tt, np.degrees(ang), ".", ms=3, label="swing plane (simulated)")
    if rate is not None and tt.size:
        ax.plot(
            tt,
            np.degrees(ang[0] + float(rate) * (tt - tt[0])),
            "k-",
            lw=0.8,
            label=f"predicted {float(rate):.4g} rad/s",
        )
    ax.set_xlabel("t (s)")
    ax.set_ylabel("azimuth of the plane (deg)")
    ax.set_title("Foucault pendulum: the swing plane turns (docs/theory.md §9)")
    ax.legend(fontsize="small")
    return ax
