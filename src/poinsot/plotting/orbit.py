"""Figures of attitude in orbit: the gravity-gradient stability regions in the
``(k1, k3)`` plane (docs/theory.md §10.2). matplotlib is imported inside the functions.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._validate import as_int
from ..dynamics.orbit import gravity_gradient_stability
from .scenario import _new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_gravity_gradient_stability"]


def plot_gravity_gradient_stability(*, ax: Axes | None = None, resolution: int = 401) -> Axes:
    """Shade the Lagrange and DeBra-Delp regions of a gravity-gradient satellite in the
    ``(k1, k3)`` plane (theory §10.2).

    ``k1 = (I2 - I3) / I1``, ``k3 = (I2 - I1) / I3`` (roll 1 along-track, pitch 2 along
    the orbit normal, yaw 3 radial). Pitch is stable for
    ``k1 > k3``; roll-yaw for ``k1 k3 > 0`` and ``1 + 3 k1 + k1 k3 > 4 sqrt(k1 k3)``
    (:func:`poinsot.dynamics.gravity_gradient_stability`). Green: Lagrange region
    (all stable, a potential minimum); orange: DeBra-Delp region (all stable by
    gyroscopic coupling, ``0 > k1 > k3``); the dashed line ``k1 = k3`` and
    the boundary curve of roll-yaw stability are drawn.

    Parameters
    ----------
    ax : matplotlib Axes, optional
        Axes to draw on; a new figure if ``None``.
    resolution : int, optional
        Grid points per axis. Default 401.

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    **Convention:** body axes along the ``"lvlh"`` axes at the equilibrium; see
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.plotting import plot_gravity_gradient_stability
    >>> ax = plot_gravity_gradient_stability(resolution=41)
    >>> ax.get_xlabel()
    'k1 = (I2 - I3) / I1'
    """
    from matplotlib.colors import ListedColormap

    n = as_int(resolution, "resolution", minimum=3)
    ax = _new_axes(ax, (5.5, 5.0))
    k = np.linspace(-1.0, 1.0, n)
    k1, k3 = np.meshgrid(k, k)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = gravity_gradient_stability(k1=k1, k3=k3)
    code = np.where(s.region == "lagrange", 2.0, np.where(s.region == "debra-delp", 1.0, 0.0))
    cmap = ListedColormap(["white", "tab:orange", "tab:green"])
    ax.pcolormesh(k1, k3, code, cmap=cmap, vmin=-0.5, vmax=2.5, shading="nearest", alpha=0.6)
    ax.plot([-1, 1], [-1, 1], "k--", lw=0.8, label="k1 = k3 (pitch)")
    with np.errstate(invalid="ignore"):
        ry = 1.0 + 3.0 * k1 + k1 * k3 - 4.0 * np.sqrt(np.maximum(k1 * k3, 0.0))
    ax.contour(k1, k3, ry, levels=[0.0], colors="k", linewidths=0.8)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.axvline(0.0, color="k", lw=0.5)
    ax.text(0.5, 0.2, "Lagrange", ha="center")
    ax.text(-0.2, -0.9, "DeBra-Delp", ha="center", fontsize=8)
    ax.set_xlabel("k1 = (I2 - I3) / I1")
    ax.set_ylabel("k3 = (I2 - I1) / I3")
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_aspect("equal")
    ax.set_title("Gravity-gradient stability")
    return ax
