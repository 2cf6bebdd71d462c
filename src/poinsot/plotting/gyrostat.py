"""Figures of the gyrostat: its polhodes on the momentum sphere (docs/gyrostat.md), the
momentum exchange between body and rotors, and reaction-wheel speeds against their limits
(the scenario kind ``gyrostat``: ``momentum.png``, ``wheel_speed.png``).

See docs/theory.md §10.1. matplotlib (and contourpy, which it ships with) is imported
inside the functions only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array
from ..errors import InvalidInputError, InvalidTypeError
from ..mass.tensor import as_inertia
from .free_body import _ellipsoid_mesh, _equal_aspect
from .scenario import _new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_gyrostat_polhodes", "plot_momentum_exchange", "plot_wheel_speeds"]

#: Markers of the permanent rotations (equilibria of the polhode flow).
_STABLE = dict(color="tab:green", marker="o", ms=7, ls="none")
_UNSTABLE = dict(color="tab:red", marker="X", ms=8, ls="none")


@dataclass(frozen=True)
class _Equilibria:
    """Permanent rotations on the sphere: body momenta ``m`` (k, 3), their ``stable`` flags,
    and ``saddle`` (unstable with a non-degenerate Hessian: separatrix levels)."""

    m: np.ndarray
    stable: np.ndarray
    saddle: np.ndarray


def _energy(moments: np.ndarray, h: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``T = (m - h) . J^-1 (m - h) / 2`` (principal axes)."""
    d = m - h
    return 0.5 * np.sum(d * d / moments, axis=-1)


def _equilibria(moments: np.ndarray, h: np.ndarray, k: float) -> _Equilibria:
    """Critical points of ``T`` on ``|m| = k``: ``J^-1 (m - h) = lam m``, i.e. ``w || m``
    (``w x (J w + h) = 0``, the permanent rotations).

    ``m_i = h_i / (1 - lam I_i)`` with ``sum_i m_i^2 = k^2`` (a degree-6 polynomial in
    ``lam``, roots polished by Newton), plus for each ``h_i = 0`` the branch
    ``lam = 1 / I_i`` (``m_i`` free, fixed by the sphere).
    """
    from numpy.polynomial import polynomial as npoly

    found: list[tuple[np.ndarray, float]] = []
    # the generic branch: k^2 prod (1 - lam I)^2 - sum_i h_i^2 prod_{j != i} (1 - lam I_j)^2
    lin = [np.array([1.0, -moments[i]]) for i in range(3)]
    sq = [npoly.polymul(p, p) for p in lin]
    poly = k * k * npoly.polymul(npoly.polymul(sq[0], sq[1]), sq[2])
    for i in range(3):
        j, l = (i + 1) % 3, (i + 2) % 3
        poly = npoly.polysub(poly, h[i] ** 2 * npoly.polymul(sq[j], sq[l]))
    scale = 1.0 / float(np.min(moments))
    for root in npoly.polyroots(poly):
        if abs(root.imag) > 1e-6 * scale:
            continue
        lam = float(root.real)
        for _ in range(50):  # Newton on f(lam) = sum h^2 / (1 - lam I)^2 - k^2
            den = 1.0 - lam * moments
            if np.any(np.abs(den) < 1e-6):
                break  # near a pole (a degenerate root): left to the branches below
            f = float(np.sum(h * h / den**2)) - k * k
            df = float(np.sum(2.0 * h * h * moments / den**3))
            if df == 0.0:
                break
            step = f / df
            lam -= step
            if abs(step) <= 1e-16 * max(abs(lam), scale):
                break
        den = 1.0 - lam * moments
        if np.any((np.abs(den) < 1e-9) & (h != 0.0)) or np.any((np.abs(den) < 1e-9) & (h == 0.0)):
            continue  # a pole, or a degenerate root handled by the branches below
        m = h / den
        if abs(float(np.linalg.norm(m)) - k) <= 1e-8 * k:
            found.append((m * (k / np.linalg.norm(m)), lam))
    # the branches lam = 1 / I_i where h_i = 0
    for i in range(3):
        if h[i] != 0.0:
            continue
        lam = 1.0 / moments[i]
        den = 1.0 - lam * moments
        others = [j for j in range(3) if j != i]
        if any(abs(den[j]) < 1e-12 for j in others):
            continue  # equal moments and h_j = 0 too: a circle of equilibria, not marked
        m = np.zeros(3)
        for j in others:
            m[j] = h[j] / den[j]
        rest = k * k - float(np.sum(m * m))
        if rest < -1e-12 * k * k:
            continue
        for s in (1.0, -1.0):
            mm = m.copy()
            mm[i] = s * math.sqrt(max(rest, 0.0))
            found.append((mm, lam))
    # merge duplicates
    pts: list[np.ndarray] = []
    lams: list[float] = []
    for m, lam in found:
        if all(np.linalg.norm(m - p) > 1e-7 * k for p in pts):
            pts.append(m)
            lams.append(lam)
    stable, saddle = [], []
    for m, lam in zip(pts, lams, strict=True):
        # Hessian of T - lam |m|^2 / 2 on the tangent plane: diag(1/I - lam) projected
        u = m / k
        a = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        b = np.cross(u, a)
        d = 1.0 / moments - lam
        e = np.array([a, b])
        hess = (e * d) @ e.T
        det = float(np.linalg.det(hess))
        tol = 1e-9 * float(np.max(np.abs(d))) ** 2
        stable.append(det > tol)
        saddle.append(det < -tol)
    return _Equilibria(
        np.array(pts).reshape(-1, 3), np.array(stable, dtype=bool), np.array(saddle, dtype=bool)
    )


def _frame(saddles: np.ndarray) -> np.ndarray:
    """Orthonormal frame (rows e1, e2, pole) with the pole far from every saddle (the
    sphere's (theta, phi) grid is singular at its poles)."""
    cands = [np.eye(3)[i] for i in (2, 0, 1)]
    cands += [np.array(v) / math.sqrt(3.0) for v in ([1, 1, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1])]
    u = saddles / np.linalg.norm(saddles, axis=-1, keepdims=True) if len(saddles) else saddles
    best = min(cands, key=lambda c: float(np.max(np.abs(u @ c))) if len(u) else 0.0)
    e1 = np.cross(best, [1.0, 0.0, 0.0] if abs(best[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return np.array([e1, np.cross(best, e1), best])


def _project(
    moments: np.ndarray, h: np.ndarray, k: float, level: float, m: np.ndarray
) -> np.ndarray:
    """Newton (minimum-norm steps) onto ``|m| = k`` and ``T(m) = level``; points (n, 3)."""
    for _ in range(30):
        g = np.stack([np.sum(m * m, -1) - k * k, 2.0 * (_energy(moments, h, m) - level)], -1)
        jac = np.stack([2.0 * m, 2.0 * (m - h) / moments], -2)  # (n, 2, 3)
        gram = jac @ np.swapaxes(jac, -1, -2)
        # minimum-norm step (gram singular only at a saddle, where g is already ~0)
        y = np.linalg.pinv(gram, rcond=1e-13) @ g[..., None]
        step = (np.swapaxes(jac, -1, -2) @ y)[..., 0]
        m = m - step
        if float(np.max(np.abs(step))) <= 1e-15 * k:
            break
    return m


def _polhodes(
    moments: np.ndarray,
    h: np.ndarray,
    k: float,
    levels: list[float],
    frame: np.ndarray,
    n: int,
) -> list[list[np.ndarray]]:
    """For each energy level the pieces (arrays (p, 3)) of its curve on the sphere."""
    import contourpy

    theta = np.linspace(0.0, math.pi, n + 1)
    phi = np.linspace(-math.pi, math.pi, 2 * n + 1)
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    local = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], -1)
    m = k * (local @ frame)
    gen = contourpy.contour_generator(x=phi, y=theta, z=_energy(moments, h, m))
    out = []
    for level in levels:
        pieces = []
        for line in gen.lines(level):
            line = np.asarray(line, dtype=np.float64)
            if len(line) < 2:
                continue
            p, t = line[:, 0], line[:, 1]
            loc = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
            pieces.append(_project(moments, h, k, level, k * (loc @ frame)))
        out.append(pieces)
    return out


def _draw_one(
    ax: Any, moments: np.ndarray, h: np.ndarray, k: float, levels: int, n: int, title: bool
) -> None:
    eq = _equilibria(moments, h, k)
    tvals = _energy(moments, h, eq.m) if len(eq.m) else np.zeros(0)
    # the range of T on the sphere: its extremes are at the stable equilibria (or any)
    tmin, tmax = (float(np.min(tvals)), float(np.max(tvals))) if len(tvals) else (0.0, 0.0)
    inner = list(np.linspace(tmin, tmax, levels + 2)[1:-1]) if tmax > tmin else []
    seps = sorted({float(x) for x in tvals[eq.saddle]})
    frame = _frame(eq.m[eq.saddle])
    x, y, z = _ellipsoid_mesh(np.full(3, k))
    ax.plot_wireframe(x, y, z, color="tab:blue", alpha=0.12, linewidth=0.5)
    curves = _polhodes(moments, h, k, inner + seps, frame, n)
    first = True
    for pieces in curves[: len(inner)]:
        for c in pieces:
            (line,) = ax.plot(*c.T, color="tab:red", lw=1.2, label="polhode" if first else None)
            line.set_gid("polhode")
            first = False
    first = True
    for pieces in curves[len(inner) :]:
        for c in pieces:
            (line,) = ax.plot(
                *c.T, color="k", lw=1.2, ls="--", label="separatrix" if first else None
            )
            line.set_gid("separatrix")
            first = False
    for flag, style, name in ((True, _STABLE, "stable"), (False, _UNSTABLE, "unstable")):
        pts = eq.m[eq.stable == flag]
        if len(pts):
            (line,) = ax.plot(*pts.T, label=f"{name} permanent rotation", **style)
            line.set_gid(f"equilibrium-{name}")
    ax.set_xlabel("$m_1$")
    ax.set_ylabel("$m_2$")
    ax.set_zlabel("$m_3$")
    _equal_aspect(ax, k)
    if title:
        hs = ", ".join(f"{v:g}" for v in h)
        ax.set_title(f"h = ({hs}), |K| = {k:g}")


def plot_gyrostat_polhodes(
    inertia: ArrayLike,
    h: ArrayLike,
    *,
    momentum: float,
    levels: int = 10,
    n: int = 60,
    ax: Any = None,
) -> Axes | list[Axes]:
    """Polhodes of a free gyrostat on the momentum sphere ``|J w + h| = |K|``.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments ``(I1, I2, I3)`` of the whole gyrostat (kg m^2); ``h`` and the
        drawing in these principal axes.
    h : array_like, shape (3,) or (p, 3)
        Rotor momentum relative to the body (kg m^2/s, body axes, any direction); ``p``
        values give ``p`` panels side by side.
    momentum : float
        ``|K|``, the radius of the sphere (kg m^2/s, > 0). Keyword only.
    levels : int, optional
        Number of polhodes (energies evenly spaced strictly between the least and the
        greatest energy on the sphere), drawn besides the separatrices.
    n : int, optional
        Resolution of the sphere's (theta, phi) grid on which the curves are found
        (``n x 2n`` cells) before each point is put on both surfaces by Newton.
    ax : Axes3D or sequence of p Axes3D, optional
        3D axes to draw on (one per value of ``h``); a new figure if ``None``.

    Returns
    -------
    Axes3D, or a list of p Axes3D when ``h`` has shape (p, 3)

    Raises
    ------
    InvalidInputError
        ``inertia`` not principal moments (3,), ``h`` not (3,) or (p, 3) or not
        finite, ``momentum`` not positive and finite, ``levels`` < 0, ``n`` < 8, or
        ``ax`` not 3D axes (or not ``p`` of them).
    InvalidTypeError
        A non-integer ``levels`` or ``n``.

    Notes
    -----
    docs/theory.md §10.1, docs/gyrostat.md. With ``h`` constant and no torque the body
    momentum ``m = J w + h`` keeps ``|m| = |K|`` and the energy
    ``T = (m - h) . J^-1 (m - h) / 2``: the polhodes are the level curves of ``T`` on
    the sphere (red). The permanent rotations are the critical points of ``T`` there,
    ``w = J^-1 (m - h)`` parallel to ``m`` (so ``w x (J w + h) = 0``): ``m_i = h_i / (1 -
    lam I_i)`` with ``|m| = |K|`` (a degree-6 polynomial in ``lam``, and for ``h_i = 0``
    the branch ``lam = 1 / I_i``). Each is stable (green dot, a centre: the Hessian of
    ``T - lam |m|^2 / 2`` on the tangent plane is definite) or unstable (red cross);
    the level curves through the saddles are the separatrices (black, dashed). Line
    ``gid`` s: ``"polhode"``, ``"separatrix"``, ``"equilibrium-stable"``,
    ``"equilibrium-unstable"``.

    **Convention:** principal body axes (``m_1, m_2, m_3``), momentum units.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from poinsot.plotting import plot_gyrostat_polhodes
    >>> axes = plot_gyrostat_polhodes([1.0, 2.0, 3.0], [[0, 0, 0], [0, 1.2, 0]],
    ...                               momentum=2.0, levels=4, n=24)
    >>> len(axes), axes[0].name
    (2, '3d')
    """
    import matplotlib.pyplot as plt

    moments, principal = as_inertia(inertia, "inertia")
    if not principal or moments.shape != (3,):
        raise InvalidInputError(
            f"Expected `inertia` to be principal moments of shape (3,), got {moments.shape}."
        )
    hv = as_float_array(h, "h")
    if hv.ndim not in (1, 2) or hv.shape[-1] != 3:
        raise InvalidInputError(f"Expected `h` to have shape (3,) or (p, 3), got {hv.shape}.")
    if not np.all(np.isfinite(hv)):
        raise InvalidInputError("Expected `h` to be finite, got a non-finite value.")
    k = as_float_array(momentum, "momentum")
    if k.shape != () or not (math.isfinite(float(k)) and float(k) > 0.0):
        raise InvalidInputError(
            f"Expected `momentum` to be a positive finite number, got {momentum!r}."
        )
    for name, val, low in (("levels", levels, 0), ("n", n, 8)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)):
            raise InvalidTypeError(f"Expected `{name}` to be an int, got {type(val).__name__}.")
        if val < low:
            raise InvalidInputError(f"Expected `{name}` to be >= {low}, got {val}.")
    hs = hv.reshape(-1, 3)
    p = hs.shape[0]
    if ax is None:
        fig = plt.figure(figsize=(4.5 * p, 4.5))
        axes = [fig.add_subplot(1, p, i + 1, projection="3d") for i in range(p)]
    else:
        axes = list(ax) if hv.ndim == 2 else [ax]
        if len(axes) != p:
            raise InvalidInputError(f"Expected `ax` to hold {p} axes (one per h), got {len(axes)}.")
        if any(getattr(a, "name", "") != "3d" for a in axes):
            raise InvalidInputError("Expected `ax` to be 3D axes (projection='3d').")
    for a, hh in zip(axes, hs, strict=True):
        _draw_one(a, moments, hh, float(k), int(levels), int(n), True)
    axes[0].legend(loc="upper left", fontsize="small")
    return axes if hv.ndim == 2 else axes[0]


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
