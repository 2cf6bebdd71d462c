"""Plots of a gyrostat's momentum exchange and of reaction-wheel speeds against their
limits (docs/theory.md §10.1).

Used by the scenario kind ``gyrostat`` (``momentum.png``, ``wheel_speed.png``) and
usable directly with the arrays of a :class:`poinsot.dynamics.WheelTrajectory` or a
:class:`poinsot.dynamics.FreeGyrostat` run. matplotlib is imported here only.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._typing import ArrayLike
from ..errors import InvalidInputError
from .scenario import _new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_momentum_exchange", "plot_wheel_speeds"]

_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")


def _series(t: ArrayLike, x: ArrayLike, name: str, cols: int | None) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    n = np.asarray(t).shape[0]
    if a.ndim != 2 or a.shape[0] != n or (cols is not None and a.shape[1] != cols):
        want = f"({n}, {cols})" if cols is not None else f"({n}, N)"
        raise InvalidInputError(f"Expected `{name}` of shape {want}, got {a.shape}.")
    return a


def plot_momentum_exchange(
    t: ArrayLike,
    body: ArrayLike,
    rotor: ArrayLike,
    *,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Plot the body's momentum ``J w``, the rotors' ``h`` and their sum ``J w + h``
    against time, component by component in body axes.

    ``K = R (J w + h)`` is constant in space without an external torque
    (docs/theory.md §10.1): what the body loses on an axis the rotors gain, up to
    the turning of the body axes.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (s).
    body : array_like, shape (n, 3)
        ``J w``, body axes (kg m^2/s).
    rotor : array_like, shape (n, 3)
        ``h``, the rotors' momentum relative to the body, body axes (kg m^2/s).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes
        Solid ``J w``, dashed ``h``, dotted ``J w + h``, one colour per body axis.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> jw = np.outer(t, [0.0, 0.0, -1.0])
    >>> ax = plot_momentum_exchange(t, jw, -jw, ax=Figure().add_subplot())
    >>> len(ax.lines)
    9
    """
    jw = _series(t, body, "body", 3)
    h = _series(t, rotor, "rotor", 3)
    ax = _new_axes(ax)
    for c, name in enumerate("xyz"):
        colour = _COLOURS[c]
        ax.plot(t, jw[:, c], color=colour, label=f"(J w)_{name}")
        ax.plot(t, h[:, c], color=colour, ls="--", label=f"h_{name}")
        ax.plot(t, jw[:, c] + h[:, c], color=colour, ls=":", label=f"(J w + h)_{name}")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("momentum, body axes (kg m^2/s)")
    ax.legend(loc="best", fontsize="small", ncol=3)
    ax.grid(True, alpha=0.3)
    ax.set_title(title or "momentum exchange: J w (solid), h (dashed), J w + h (dotted)")
    return ax


def plot_wheel_speeds(
    t: ArrayLike,
    speed: ArrayLike,
    max_speed: ArrayLike | None = None,
    *,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Plot each wheel's speed relative to the body against time, with its limits
    ``+-max_speed`` dashed in the same colour (docs/theory.md §10.1).

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (s).
    speed : array_like, shape (n, N)
        Wheel speeds ``Omega_i`` (rad/s).
    max_speed : float or array_like, shape (N,), optional
        Speed limits (rad/s); infinite ones are not drawn. Default: none.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> ax = plot_wheel_speeds(t, np.c_[t, -t], [2.0, np.inf], ax=Figure().add_subplot())
    >>> len(ax.lines)   # two wheels, the two limits of the first
    4
    """
    om = _series(t, speed, "speed", None)
    n = om.shape[1]
    limit = np.broadcast_to(
        np.inf if max_speed is None else np.asarray(max_speed, dtype=float), (n,)
    )
    ax = _new_axes(ax)
    for i in range(n):
        colour = _COLOURS[i % len(_COLOURS)]
        ax.plot(t, om[:, i], color=colour, label=f"wheel {i}")
        if np.isfinite(limit[i]):
            for sign in (1.0, -1.0):
                ax.axhline(sign * limit[i], color=colour, ls="--", lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("wheel speed (rad/s)")
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    ax.set_title(title or "wheel speeds and their limits (dashed)")
    return ax
