"""Figures of the exact free rigid body: MacCullagh's and Poinsot's pictures.

See docs/theory.md §10 and docs/free-body.md.

matplotlib is imported here only (a leaf module; ``import poinsot`` never loads
it). Each function draws on ``ax`` (a new figure if ``None``) and returns it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validate import as_times
from ..errors import InvalidInputError, InvalidTypeError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..dynamics.free_body import FreeRigidBody

__all__ = ["plot_maccullagh", "plot_poinsot", "plot_omega"]


def _body(body: object) -> Any:
    # Duck typing (a FreeRigidBody or anything with its geometry methods).
    if not all(hasattr(body, a) for a in ("maccullagh", "poinsot", "omega", "regime")):
        raise InvalidTypeError(
            f"Expected `body` to be a poinsot.dynamics.FreeRigidBody, got {type(body).__name__}."
        )
    shape = getattr(body, "shape", ())
    if shape != ():
        raise InvalidInputError(
            f"Expected `body` to be one body, got a batch of shape {shape}: plot `body[i]`."
        )
    return body


def _axes3d(ax: Any) -> Any:
    import matplotlib.pyplot as plt

    if ax is None:
        fig = plt.figure(figsize=(6, 6))
        ax = fig.add_subplot(projection="3d")
    elif getattr(ax, "name", "") != "3d":
        raise InvalidInputError("Expected `ax` to be a 3D axes (projection='3d').")
    return ax


def _ellipsoid_mesh(
    semi_axes: np.ndarray, rotation: np.ndarray | None = None, n: int = 30
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Surface (x, y, z) of the ellipsoid with principal semi-axes; rotated by a 3x3 matrix."""
    u = np.linspace(0.0, 2.0 * np.pi, n)
    v = np.linspace(0.0, np.pi, n // 2 + 1)
    pts = np.stack(
        [
            semi_axes[0] * np.outer(np.cos(u), np.sin(v)),
            semi_axes[1] * np.outer(np.sin(u), np.sin(v)),
            semi_axes[2] * np.outer(np.ones_like(u), np.cos(v)),
        ],
        axis=-1,
    )
    if rotation is not None:
        pts = pts @ np.asarray(rotation).T
    return pts[..., 0], pts[..., 1], pts[..., 2]


def _equal_aspect(ax: Any, radius: float) -> None:
    for set_lim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        set_lim(-radius, radius)
    ax.set_box_aspect((1, 1, 1))


def plot_maccullagh(body: FreeRigidBody, *, n: int = 200, ax: Any = None) -> Axes:
    """MacCullagh's picture: momentum sphere, energy ellipsoid, the track of ``K``, separatrices.

    Parameters
    ----------
    body : FreeRigidBody
        The body (not at rest).
    ax : mpl_toolkits.mplot3d.Axes3D, optional
        3D axes to draw on; a new figure if ``None``.
    n : int, optional
        Samples per curve.

    Returns
    -------
    Axes3D

    Notes
    -----
    Data from :meth:`FreeRigidBody.maccullagh`: the sphere ``|K| = K``, the
    ellipsoid ``K1^2/A + K2^2/B + K3^2/C = 2T`` (semi-axes ``sqrt(2 T I_k)``),
    their intersection (the body's track) and the separatrices ``|K|^2 = 2 B T``.

    **Convention:** principal body axes, momentum units.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import FreeRigidBody
    >>> from poinsot.plotting import plot_maccullagh
    >>> ax = plot_maccullagh(FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.3, 1.0, 0.2]))
    >>> ax.name
    '3d'
    """
    g = _body(body).maccullagh(n)
    ax = _axes3d(ax)
    x, y, z = _ellipsoid_mesh(g.ellipsoid_semi_axes)
    ax.plot_surface(x, y, z, color="tab:orange", alpha=0.15, linewidth=0)
    x, y, z = _ellipsoid_mesh(np.full(3, g.momentum_radius))
    ax.plot_wireframe(x, y, z, color="tab:blue", alpha=0.15, linewidth=0.5)
    for k, sep in enumerate(g.separatrices):
        ax.plot(*sep.T, color="k", lw=1.0, ls="--", label="separatrix" if k == 0 else None)
    ax.plot(*g.track.T, color="tab:red", lw=2.0, label="track of K (body)")
    ax.set_xlabel("$K_1$")
    ax.set_ylabel("$K_2$")
    ax.set_zlabel("$K_3$")
    _equal_aspect(ax, float(np.max(g.ellipsoid_semi_axes)))
    ax.set_title("MacCullagh: momentum sphere and energy ellipsoid")
    ax.legend(loc="upper left")
    return ax


def plot_poinsot(
    body: FreeRigidBody, t: ArrayLike | None = None, *, n: int = 400, ax: Any = None
) -> Axes:
    """Poinsot's picture: the inertia ellipsoid rolling on the invariable plane.

    Parameters
    ----------
    body : FreeRigidBody
        The body (not at rest).
    t : array_like, shape (n,), optional
        Times for the herpolhode (default: three periods); the ellipsoid is drawn
        at ``t[0]``.
    ax : mpl_toolkits.mplot3d.Axes3D, optional
        3D axes to draw on; a new figure if ``None``.
    n : int, optional
        Number of samples when ``t`` is not given.

    Returns
    -------
    Axes3D

    Notes
    -----
    Data from :meth:`FreeRigidBody.poinsot`: ellipsoid ``r^T J r = 1``, plane
    normal to ``K`` at distance ``sqrt(2T) / K``, polhode (drawn on the ellipsoid
    at ``t[0]``) and herpolhode (in the plane).

    **Convention:** space axes.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.dynamics import FreeRigidBody
    >>> from poinsot.plotting import plot_poinsot
    >>> ax = plot_poinsot(FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.3, 1.0, 0.2]))
    >>> ax.name
    '3d'
    """
    g = _body(body).poinsot(t, n)
    ax = _axes3d(ax)
    c0 = g.rotation[0].as_matrix()
    x, y, z = _ellipsoid_mesh(g.ellipsoid_semi_axes, c0)
    ax.plot_surface(x, y, z, color="tab:orange", alpha=0.2, linewidth=0)
    ax.plot(*(g.polhode @ c0.T).T, color="tab:red", lw=1.5, label="polhode (on the body)")
    ax.plot(*g.herpolhode.T, color="tab:green", lw=1.5, label="herpolhode (in the plane)")
    # The invariable plane: a square patch around the foot of the normal.
    nrm = g.plane_normal
    e1 = np.cross(nrm, [1.0, 0.0, 0.0] if abs(nrm[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(nrm, e1)
    half = 1.2 * float(np.max(g.ellipsoid_semi_axes))
    s = np.linspace(-half, half, 2)
    a, b = np.meshgrid(s, s)
    patch = g.plane_distance * nrm + a[..., None] * e1 + b[..., None] * e2
    ax.plot_surface(patch[..., 0], patch[..., 1], patch[..., 2], color="tab:gray", alpha=0.25)
    ax.plot(*np.stack([np.zeros(3), g.plane_distance * nrm]).T, color="k", lw=1.0, label="K")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    _equal_aspect(ax, half)
    ax.set_title("Poinsot: inertia ellipsoid on the invariable plane")
    ax.legend(loc="upper left")
    return ax


def plot_omega(body: FreeRigidBody, t: ArrayLike, *, ax: Axes | None = None) -> Axes:
    """Body angular velocity components ``w_k(t)`` of the exact solution.

    Parameters
    ----------
    body : FreeRigidBody
        The body.
    t : array_like, shape (n,)
        Times (s).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure if ``None``.

    Returns
    -------
    Axes

    Notes
    -----
    **Convention:** body axes of the given inertia, rad/s.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody
    >>> from poinsot.plotting import plot_omega
    >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.05, 1.0, 0.05])
    >>> ax = plot_omega(body, np.linspace(0, 60, 600))
    >>> len(ax.lines)
    3
    """
    import matplotlib.pyplot as plt

    body = _body(body)
    ta = as_times(t, "t", min_len=2)
    w = body.omega(ta)
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5))
    for k in range(3):
        ax.plot(ta, w[:, k], label=rf"$\omega_{k + 1}$")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\omega$ (rad/s, body)")
    ax.set_title(f"Exact free rigid body ({body.regime})")
    ax.legend()
    return ax
