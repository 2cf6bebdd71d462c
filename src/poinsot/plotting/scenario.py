"""Time-series plots of a run: angular velocity, and relative change of invariants.

Used by ``poinsot run`` (``omega.png``, ``invariants.png``) and usable directly.
matplotlib is imported here only (a leaf module; ``import poinsot`` never loads it).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import TYPE_CHECKING, Any

from .._typing import ArrayLike
from .._validate import as_float_array, as_times
from ..errors import InvalidInputError, InvalidTypeError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..trajectory import Trajectory

__all__ = ["plot_angular_velocity", "plot_relative_change"]

_COLOURS = ("C3", "C2", "C0")  # x, y, z


def _new_axes(ax: Axes | None, size: tuple[float, float] = (7, 3.6)) -> Axes:
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def _trajectory(tr: object, name: str) -> Any:
    if not all(hasattr(tr, a) for a in ("t", "omega", "method")):
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot Trajectory, got {type(tr).__name__}."
        )
    return tr


def plot_angular_velocity(
    trajectory: Trajectory,
    reference: Trajectory | None = None,
    *,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Plot the body angular velocity ``w_x, w_y, w_z`` against time.

    Parameters
    ----------
    trajectory : Trajectory
        The motion (``omega`` in body axes, rad/s).
    reference : Trajectory, optional
        A second solution, drawn dashed in the same colours.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    **Convention:** body axes, rad/s, time in s.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.dynamics import simulate
    >>> from poinsot.plotting import plot_angular_velocity
    >>> tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 1, 11))
    >>> len(plot_angular_velocity(tr).lines)
    3
    """
    tr = _trajectory(trajectory, "trajectory")
    ref = None if reference is None else _trajectory(reference, "reference")
    ax = _new_axes(ax)
    for k, (label, colour) in enumerate(zip("xyz", _COLOURS, strict=True)):
        ax.plot(tr.t, tr.omega[:, k], color=colour, label=f"$\\omega_{label}$ ({tr.method})")
        if ref is not None:
            ax.plot(
                ref.t,
                ref.omega[:, k],
                color=colour,
                ls="--",
                lw=1,
                label=f"$\\omega_{label}$ ({ref.method})",
            )
    ax.set(xlabel="t (s)", ylabel="angular velocity, body axes (rad/s)")
    if title:
        ax.set_title(title)
    ax.legend(fontsize=7, ncol=2 if ref is not None else 1)
    ax.grid(alpha=0.3)
    return ax


def plot_relative_change(
    t: ArrayLike,
    curves: Mapping[str, ArrayLike],
    *,
    dashed: Collection[str] = (),
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Plot relative changes (``(q(t) - q(0)) / scale``) of quantities against time.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (s).
    curves : mapping of str to array_like, shape (n,)
        Label -> relative change at each time (dimensionless).
    dashed : collection of str, optional
        Labels drawn dashed (e.g. those of a reference solution).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.plotting import plot_relative_change
    >>> ax = plot_relative_change([0.0, 1.0], {"T": [0.0, 1e-9]})
    >>> ax.lines[0].get_ydata().tolist()
    [0.0, 1e-09]
    """
    tt = as_times(t, "t")
    if not isinstance(curves, Mapping) or not curves:
        raise InvalidInputError(
            "Expected `curves` to be a non-empty mapping of label -> relative changes, "
            f"got {curves!r:.60}."
        )
    ax = _new_axes(ax)
    for label, y in curves.items():
        ya = as_float_array(y, f"curves[{label!r}]")
        if ya.shape != tt.shape:
            raise InvalidInputError(
                f"Expected `curves[{label!r}]` to have shape {tt.shape} to match `t`, "
                f"got {ya.shape}."
            )
        style: dict[str, Any] = {"ls": "--", "lw": 1} if label in dashed else {}
        ax.plot(tt, ya, label=label, **style)
    ax.set(xlabel="t (s)", ylabel="relative change")
    if title:
        ax.set_title(title)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax
