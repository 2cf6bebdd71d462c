"""A particle with a unilateral constraint ``f(r) <= 0`` (theory §11.2): it slides on
the surface while the normal reaction pushes, leaves it when the reaction vanishes,
and hits it again by an impact (Newton's restitution, theory §11.3).

On the surface (``f = 0``, "in contact") the reaction is ``N = -lambda grad f`` with the
multiplier that keeps ``f'' = 0``,

``lambda = (grad f . F + m v.H v) / |grad f|^2``,

(``H`` the Hessian of ``f``, ``F`` the applied force): a unilateral constraint can only
push, ``lambda >= 0``, so the particle leaves the surface at the event ``lambda = 0``
(decreasing). Off the surface (``f < 0``) it moves under ``F`` alone until the event
``f = 0`` (increasing): an impact, ``v_n+ = -e v_n-`` along the normal ``grad f / |grad
f|``; with ``e = 0``, or a rebound slower than ``landing_speed``, it stays on the
surface (if the reaction then pushes). Each phase is integrated by DOP853 and each
switch located by :mod:`poinsot.events`.

Examples
--------
A particle released at the top of a smooth sphere of radius 1 m leaves it where
``cos theta = 2/3`` (and the reaction is zero there):

>>> import numpy as np
>>> sphere = Sphere(radius=1.0)
>>> tr = simulate_unilateral(sphere, [0, 0, -9.81], [0, 0, 1.0], [1e-3, 0, 0],
...                          np.linspace(0.0, 3.0, 301))
>>> leave = tr.info["events"].states("leave")[0]
>>> round(float(leave[2]), 6)
0.666667
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_times, as_vec3
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError
from ..events import EventLog
from ..trajectory import Channel, PointTrajectory

__all__ = ["Surface", "Plane", "Sphere", "ContactTrajectory", "simulate_unilateral"]

_XYZ = ("x", "y", "z")


class Surface:
    """A unilateral constraint ``f(r) <= 0`` on a particle (theory §11.2): subclasses give
    ``value(r)`` (m), ``gradient(r)`` and ``curvature(r, v) = v.H v`` (the Hessian's
    quadratic form, 1/s^2 m), each for ``r``, ``v`` of shape (3,).

    Examples
    --------
    A paraboloid bowl ``z >= (x^2 + y^2) / 2`` (``f = (x^2 + y^2) / 2 - z``):

    >>> import numpy as np
    >>> class Bowl(Surface):
    ...     def value(self, r): return 0.5 * (r[0] ** 2 + r[1] ** 2) - r[2]
    ...     def gradient(self, r): return np.array([r[0], r[1], -1.0])
    ...     def curvature(self, r, v): return v[0] ** 2 + v[1] ** 2
    >>> tr = simulate_unilateral(Bowl(), [0, 0, -9.81], [0.5, 0, 0.125], [0, 0, 0],
    ...                          np.linspace(0, 1, 11))
    >>> bool(np.all(tr.in_contact)), bool(abs(Bowl().value(tr.position[-1])) < 1e-9)
    (True, True)
    """

    def value(self, r: FloatArray) -> float:
        raise NotImplementedError

    def gradient(self, r: FloatArray) -> FloatArray:
        raise NotImplementedError

    def curvature(self, r: FloatArray, v: FloatArray) -> float:
        raise NotImplementedError


@dataclass(frozen=True)
class Plane(Surface):
    """The half-space on the side of ``normal``: ``f = -n.(r - point) <= 0``.

    >>> Plane().value(np.array([0.0, 0.0, 2.0]))
    -2.0
    """

    point: Any = (0.0, 0.0, 0.0)
    normal: Any = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        p = as_vec3(self.point, "point").reshape(3)
        n = as_vec3(self.normal, "normal").reshape(3)
        if not np.linalg.norm(n) > 0:
            raise InvalidInputError("Expected `normal` to be a non-zero vector (3,).")
        object.__setattr__(self, "point", p)
        object.__setattr__(self, "normal", n / np.linalg.norm(n))

    def value(self, r: FloatArray) -> float:
        return -float(self.normal @ (r - self.point))

    def gradient(self, r: FloatArray) -> FloatArray:
        return -np.asarray(self.normal)

    def curvature(self, r: FloatArray, v: FloatArray) -> float:
        return 0.0


@dataclass(frozen=True)
class Sphere(Surface):
    """A sphere of ``radius`` about ``center``; ``side="outside"`` (default): the
    particle stays outside (a ball on a dome), ``f = R - |r - c|``; ``"inside"``: it
    stays inside (a string of length ``R``, a bowl), ``f = |r - c| - R``.

    >>> Sphere(radius=2.0, side="inside").value(np.array([0.0, 0.0, 1.0]))
    -1.0
    """

    radius: float = 1.0
    center: Any = (0.0, 0.0, 0.0)
    side: str = "outside"

    def __post_init__(self) -> None:
        r = float(as_float_array(self.radius, "radius"))
        if not r > 0:
            raise InvalidInputError(f"Expected `radius` > 0 (m), got {r!r}.")
        if self.side not in ("outside", "inside"):
            raise InvalidInputError(
                f"Expected `side` to be 'outside' or 'inside', got {self.side!r}."
            )
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "center", as_vec3(self.center, "center").reshape(3))

    @property
    def _sign(self) -> float:
        return 1.0 if self.side == "inside" else -1.0

    def value(self, r: FloatArray) -> float:
        return self._sign * (float(np.linalg.norm(r - self.center)) - self.radius)

    def gradient(self, r: FloatArray) -> FloatArray:
        d = r - self.center
        return self._sign * d / float(np.linalg.norm(d))

    def curvature(self, r: FloatArray, v: FloatArray) -> float:
        # the Hessian of |d| is (E - d d^T / |d|^2) / |d|
        d = r - self.center
        s = float(np.linalg.norm(d))
        vr = float(v @ d) / s
        return self._sign * (float(v @ v) - vr * vr) / s


@dataclass(frozen=True, eq=False, repr=False)
class ContactTrajectory(PointTrajectory):
    """A :class:`~poinsot.trajectory.PointTrajectory` with the constraint's reaction.

    Attributes (beyond the point result's)
    --------------------------------------
    reaction : ndarray, shape (n, 3)
        The normal reaction ``N = -lambda grad f`` of the surface (N, inertial axes);
        zero off the surface.
    in_contact : ndarray of bool, shape (n,)
        Whether the particle is on the surface at each sample.
    """

    reaction: Any = None
    in_contact: Any = None

    def channels(self) -> dict[str, Channel]:
        """The point's channels and ``reaction`` (N)."""
        out = super().channels()
        if self.reaction is not None:
            out["reaction"] = Channel(
                "reaction", np.asarray(self.reaction), "N", _XYZ, "normal reaction, inertial axes"
            )
        return out


def _force(force: Any) -> Callable[[float, FloatArray, FloatArray], FloatArray]:
    if force is None:
        return lambda t, r, v: np.zeros(3)
    if callable(force):

        def call(t: float, r: FloatArray, v: FloatArray) -> FloatArray:
            f = np.asarray(force(t, r, v), dtype=float)
            if f.shape != (3,) or not np.all(np.isfinite(f)):
                raise IntegrationError(
                    f"Expected `force(t, r, v)` to return 3 finite values (N), got {f!r} at "
                    f"t = {t:.6g} s."
                )
            return f

        return call
    const = as_vec3(force, "force").reshape(3)
    return lambda t, r, v: const


def simulate_unilateral(
    surface: Surface,
    force: ArrayLike | Callable[..., ArrayLike] | None,
    position0: ArrayLike,
    velocity0: ArrayLike,
    t: ArrayLike,
    *,
    mass: float = 1.0,
    restitution: float = 0.0,
    landing_speed: float = 1e-6,
    rtol: float = 1e-12,
    atol: float = 1e-14,
    max_switches: int = 1000,
) -> ContactTrajectory:
    """Integrate a particle with the unilateral constraint ``surface`` (theory §11.2).

    Parameters
    ----------
    surface : Surface
        :class:`Plane`, :class:`Sphere` or a :class:`Surface` of your own.
    force : None, array_like (3,) or callable
        The applied force (N, inertial axes): ``None``, a constant vector, or
        ``force(t, r, v) -> (3,)``. ``[0, 0, -m g]`` is gravity.
    position0, velocity0 : array_like, shape (3,)
        Initial position (m) and velocity (m/s); ``f(position0) <= 0``.
    t : array_like, shape (n,)
        Output times (s), increasing.
    mass : float, optional
        ``m`` (kg), default 1.
    restitution : float, optional
        Newton's ``e`` in [0, 1] for the impacts on the surface (default 0: it lands).
    landing_speed : float, optional
        A rebound slower than this (m/s) lands instead: the bounces of ``e < 1``
        accumulate in finite time (a Zeno point), default 1e-6 m/s.
    rtol, atol : float, optional
        DOP853's tolerances in each phase (defaults 1e-12, 1e-14).
    max_switches : int, optional
        At most this many phase changes (default 1000).

    Returns
    -------
    ContactTrajectory
        ``position``, ``velocity`` (n, 3), ``reaction`` (n, 3) in N, ``in_contact``
        (n,); ``info["events"]`` an :class:`~poinsot.events.EventLog` of ``"leave"``
        (the reaction reached 0), ``"impact"`` (hit the surface; its state is the one
        before) and ``"land"`` (stays on it).

    Raises
    ------
    InvalidInputError
        A start in the forbidden region (``f > 0``), bad coefficients or shapes.
    IntegrationError
        A phase failed, or ``max_switches`` was reached.

    Examples
    --------
    A ball dropped from 1 m with ``e = 0.5`` comes to rest after ``3 sqrt(2 h / g)``:

    >>> import numpy as np
    >>> tr = simulate_unilateral(Plane(), [0, 0, -9.81], [0, 0, 1.0], [0, 0, 0],
    ...                          np.linspace(0.0, 2.0, 201), restitution=0.5)
    >>> rest = tr.info["events"].times("land")[0]
    >>> bool(abs(rest - 3 * np.sqrt(2 / 9.81)) < 1e-5), tr.reaction[-1].round(6).tolist()
    (True, [0.0, 0.0, 9.81])
    """
    from scipy.integrate import solve_ivp

    if not isinstance(surface, Surface):
        raise InvalidTypeError(
            f"Expected `surface` to be a poinsot.dynamics.Surface (Plane, Sphere...), got "
            f"{type(surface).__name__}."
        )
    f_app = _force(force)
    r0 = as_vec3(position0, "position0").reshape(3)
    v0 = as_vec3(velocity0, "velocity0").reshape(3)
    tt = as_times(t, "t")
    m = float(as_float_array(mass, "mass"))
    e = float(as_float_array(restitution, "restitution"))
    if not m > 0:
        raise InvalidInputError(f"Expected `mass` > 0 (kg), got {m!r}.")
    if not 0.0 <= e <= 1.0:
        raise InvalidInputError(f"Expected `restitution` in [0, 1], got {e!r}.")
    scale = max(1.0, float(np.linalg.norm(r0)))
    tol_f = 1e-9 * scale
    if surface.value(r0) > tol_f:
        raise InvalidInputError(
            f"Expected `position0` on the allowed side of the surface (f <= 0), got f = "
            f"{surface.value(r0)!r} m."
        )

    def multiplier(tn: float, r: FloatArray, v: FloatArray) -> float:
        g = surface.gradient(r)
        return (float(g @ f_app(tn, r, v)) + m * surface.curvature(r, v)) / float(g @ g)

    def contact_rhs(tn: float, y: FloatArray) -> FloatArray:
        r, v = y[:3], y[3:]
        g = surface.gradient(r)
        lam = multiplier(tn, r, v)
        return np.concatenate([v, (f_app(tn, r, v) - lam * g) / m])

    def free_rhs(tn: float, y: FloatArray) -> FloatArray:
        return np.concatenate([y[3:], f_app(tn, y[:3], y[3:]) / m])

    def leave(tn: float, y: FloatArray) -> float:
        return multiplier(tn, y[:3], y[3:])

    def hit(tn: float, y: FloatArray) -> float:
        return surface.value(y[:3])

    leave.terminal, leave.direction = True, -1  # type: ignore[attr-defined]
    hit.terminal, hit.direction = True, 1  # type: ignore[attr-defined]

    def normal_speed(r: FloatArray, v: FloatArray) -> float:
        g = surface.gradient(r)
        return float(g @ v) / float(np.linalg.norm(g))

    # the phase at the start: on the surface, not moving off it, pushed onto it
    contact = (
        abs(surface.value(r0)) <= tol_f
        and normal_speed(r0, v0) <= 1e-12 * max(1.0, float(np.linalg.norm(v0)))
        and multiplier(float(tt[0]), r0, v0) > 0.0
    )
    n = tt.size
    pos, vel = np.empty((n, 3)), np.empty((n, 3))
    react, on = np.zeros((n, 3)), np.zeros(n, dtype=bool)
    rows: list[tuple[float, int, FloatArray, float]] = []  # (t, event, state, direction)
    names = ("leave", "impact", "land")
    y = np.concatenate([r0, v0])
    t_now = float(tt[0])
    pos[0], vel[0], on[0] = r0, v0, contact
    if contact:
        react[0] = -multiplier(t_now, r0, v0) * surface.gradient(r0)
    k = 1  # the next sample to fill
    for _ in range(max_switches):
        if t_now >= tt[-1]:
            break
        rhs, ev = (contact_rhs, leave) if contact else (free_rhs, hit)
        sol = solve_ivp(rhs, (t_now, float(tt[-1])), y, method="DOP853", rtol=rtol, atol=atol,
                        events=ev, dense_output=True)  # fmt: skip
        if sol.status < 0:
            raise IntegrationError(f"simulate_unilateral failed after t = {t_now:.6g} s: "
                                   f"{sol.message}")  # fmt: skip
        t_end = float(sol.t[-1])
        while k < n and tt[k] <= t_end:
            yk = sol.sol(tt[k])
            pos[k], vel[k], on[k] = yk[:3], yk[3:], contact
            if contact:
                react[k] = -multiplier(float(tt[k]), yk[:3], yk[3:]) * surface.gradient(yk[:3])
            k += 1
        if sol.status == 0:
            break
        t_now, y = t_end, sol.y[:, -1].copy()
        if contact:  # the reaction reached 0: it flies
            rows.append((t_now, 0, y.copy(), -1.0))
            contact = False
            continue
        # an impact: Newton's law along the normal
        rows.append((t_now, 1, y.copy(), 1.0))
        r, v = y[:3], y[3:]
        g = surface.gradient(r)
        nrm = g / float(np.linalg.norm(g))  # out of the allowed region
        vn = float(v @ nrm)
        v = v - (1.0 + e) * vn * nrm
        if e * vn <= landing_speed and multiplier(t_now, r, v - float(v @ nrm) * nrm) > 0.0:
            v = v - float(v @ nrm) * nrm  # lands: the normal speed is taken away
            contact = True
            rows.append((t_now, 2, np.concatenate([r, v]), 1.0))
        y = np.concatenate([r, v])
    else:
        raise IntegrationError(
            f"simulate_unilateral: more than max_switches = {max_switches} phase changes "
            f"before t = {float(tt[-1]):.6g} s (chattering?)."
        )
    log = EventLog.of_one_body(names, rows, 6)
    return ContactTrajectory(
        t=tt,
        position=pos,
        velocity=vel,
        method="DOP853 (phases)",
        frame_name="inertial",
        mass=np.array(m),
        reaction=react,
        in_contact=on,
        info={"solver": "DOP853", "rtol": rtol, "atol": atol, "events": log},
    )
