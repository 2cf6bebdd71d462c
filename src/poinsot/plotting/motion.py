"""Plots of point kinematics: the contributions to a point's acceleration.

matplotlib is imported here only (a leaf module; ``import poinsot`` never loads it).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array, as_times, is_integer
from ..errors import InvalidInputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..kinematics.fields import CompositeMotion

__all__ = ["plot_acceleration_terms"]

_COMPONENTS = {"norm": None, "x": 0, "y": 1, "z": 2, 0: 0, 1: 1, 2: 2}


def _composite_terms(m: Any) -> dict[str, np.ndarray]:
    return {
        r"transport $W_e = W_0 + \varepsilon\times s + \omega\times(\omega\times s)$": (
            m.transport_acceleration
        ),
        r"relative $W_r$": m.relative_acceleration,
        r"Coriolis $W_c = 2\,\omega\times V_r$": m.coriolis_acceleration,
        r"total $W$": m.acceleration,
    }


def _parse_component(component: Any, n: int) -> tuple[int | None, np.ndarray | None]:
    """(index, direction): index None = norm; direction an (n, 3) or (3,) array."""
    if isinstance(component, str) or is_integer(component):
        key = component if isinstance(component, str) else int(component)
        if key in _COMPONENTS:
            return _COMPONENTS[key], None
    elif not isinstance(component, bool):
        d = as_float_array(component, "component")
        if d.shape in ((3,), (n, 3)):
            return None, d
    raise InvalidInputError(
        "Expected `component` to be one of 'norm', 'x', 'y', 'z', 0, 1, 2 or a direction "
        f"of shape (3,) or ({n}, 3), got {component!r}."
    )


def plot_acceleration_terms(
    t: ArrayLike,
    terms: CompositeMotion | Mapping[str, ArrayLike],
    ax: Axes | None = None,
    *,
    component: str | int | ArrayLike = "norm",
) -> Axes:
    """Plot the contributions to a point's acceleration against time.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (strictly increasing).
    terms : CompositeMotion or mapping of str to array_like (n, 3)
        A :class:`~poinsot.kinematics.CompositeMotion` computed on the times
        ``t`` (batch shape ``(n,)``): plots the transport, relative and Coriolis
        accelerations and their sum (dashed); or any mapping label -> vectors.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    component : {"norm", "x", "y", "z", 0, 1, 2} or array_like, optional
        What to plot of each vector: its magnitude (default), one Cartesian
        component, or its projection ``W . d`` on a direction ``d`` of shape
        (3,) or (n, 3) (e.g. a moving unit vector; not normalised here).

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    **Convention:** vectors in fixed-frame components (theory §6); units those of
    the data (m/s^2 with SI input).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.kinematics import FrameMotion, point_motion
    >>> from poinsot.plotting.motion import plot_acceleration_terms
    >>> t = np.linspace(0, 1, 5)
    >>> m = point_motion(FrameMotion(omega=[0, 0, 1]), [1, 0, 0], v_rel=[1, 0, 0])
    >>> ax = plot_acceleration_terms(t, {"Coriolis": np.tile(m.coriolis_acceleration, (5, 1))})
    >>> ax.get_lines()[0].get_ydata().round(3)
    array([2., 2., 2., 2., 2.])
    """
    t = as_times(t, "t")
    index, direction = _parse_component(component, t.size)
    if isinstance(terms, Mapping):
        named: dict[str, Any] = dict(terms)
    elif all(hasattr(terms, a) for a in ("transport_acceleration", "coriolis_acceleration")):
        named = _composite_terms(terms)
    else:
        raise InvalidInputError(
            "Expected `terms` to be a CompositeMotion or a mapping of label -> (n, 3) "
            f"vectors, got {type(terms).__name__}."
        )
    if not named:
        raise InvalidInputError("Expected `terms` to hold at least one term, got none.")
    series = {}
    for label, v in named.items():
        a = as_float_array(v, f"terms[{label!r}]")
        if a.shape != (t.size, 3):
            raise InvalidInputError(
                f"Expected `terms[{label!r}]` to have shape ({t.size}, 3) to match `t`, "
                f"got {a.shape}."
            )
        if direction is not None:
            series[label] = np.einsum("ni,ni->n", a, np.broadcast_to(direction, a.shape))
        elif index is None:
            series[label] = np.linalg.norm(a, axis=-1)
        else:
            series[label] = a[:, index]

    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4))
    for label, y in series.items():
        dashed = label.startswith("total")
        ax.plot(t, y, label=label, ls="--" if dashed else "-", lw=1.2 if dashed else 1.8)
    if direction is not None:
        what = "projection on the given direction"
    else:
        what = "magnitude" if index is None else "xyz"[index] + " component"
    ax.set_xlabel("t")
    ax.set_ylabel(f"acceleration ({what})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    return ax
