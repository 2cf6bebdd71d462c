"""Impacts of a particle or a rigid body on a plane at one point (theory §11.3).

An impact lasts no time: the velocities jump, the positions do not, and finite forces
(gravity) give no impulse. With ``P`` the impulse of the plane on the body at the
contact point ``A`` (offset ``r = A - C`` from the centre of mass ``C``), the theorems
of momentum and angular momentum about ``C`` give

``m (v+ - v-) = P``,  ``J (w+ - w-) = r x P``,

so the angular momentum about the contact point, ``K_A = J w - r x m v``, is the same
before and after. The velocity of the contact point ``u = v + w x r`` jumps by
``u+ - u- = K P`` with the **collision matrix** ``K = E/m - [r]x J^-1 [r]x``
(symmetric, positive definite).

Laws (``n`` the plane's normal pointing out of the plane, into the body's side;
``u_n = u . n < 0`` approaching):

- **Newton**: ``u_n+ = -e u_n-`` (kinematic restitution, ``0 <= e <= 1``).
- **Poisson**: the impulse of restitution is ``e`` times the impulse of compression,
  ``P_n = (1 + e) P_c`` (``P_c``: the normal impulse at which ``u_n`` reaches 0).
- **Coulomb friction** ``|P_t| <= mu P_n``: while the contact slides, the tangential
  impulse opposes the slip, ``dP_t = -mu (u_t / |u_t|) dP_n``; once ``u_t = 0`` it
  sticks if ``mu`` allows it, or slides on in the direction the dynamics gives. The
  velocities follow Routh's method: ``du/dP_n = K (n + dP_t/dP_n)``, integrated in the
  normal impulse ``P_n`` (exact for each stage; the slip direction may turn in 3D).

Without friction both laws give ``P = -(1 + e) u_n- / (n.K n) n`` and the energy lost is
``(1 - e^2) u_n-^2 / (2 n.K n)``.

**Conventions:** vectors in space axes except ``omega`` (body axes, rad/s), as
everywhere in poinsot; the attitude maps body to space components; SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _quat
from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_rotation_quat, as_times, as_vec3
from ..errors import InvalidInputError
from ..events import EventLog
from ..mass import RigidBody
from ..rotations.quaternion import rotate
from ..rotations.rotation import Rotation
from ..trajectory import PoseTrajectory
from .euler_equations import _as_inertia
from .free_body import FreeRigidBody

__all__ = [
    "ImpactResult",
    "collision_matrix",
    "particle_impact",
    "rigid_impact",
    "simulate_bounces",
]

_LAWS = ("newton", "poisson")


@dataclass(frozen=True, eq=False)
class ImpactResult:
    """The outcome of an impact.

    Attributes
    ----------
    impulse : ndarray, shape (3,)
        ``P``, the plane's impulse on the body at the contact point (N s, space axes).
    velocity : ndarray, shape (3,)
        ``v+``, the velocity of the centre of mass (or the particle) after (m/s).
    omega : ndarray, shape (3,) or None
        ``w+`` in body axes (rad/s); None for a particle.
    contact_velocity : ndarray, shape (2, 3)
        ``u-`` and ``u+``, the velocity of the contact point before and after (m/s).
    energy_loss : float
        Kinetic energy lost, ``T- - T+ >= 0`` (J).
    compression_impulse : float
        ``P_c``, the normal impulse at the end of compression (N s).
    mode : str
        ``"frictionless"``, ``"stick"`` (the contact stops sliding and stays),
        ``"slide"`` (it slides throughout) or ``"slide-stick"`` (slides, then sticks).
    """

    impulse: FloatArray
    velocity: FloatArray
    omega: FloatArray | None
    contact_velocity: FloatArray
    energy_loss: float
    compression_impulse: float
    mode: str


def collision_matrix(mass: float, inertia_space: ArrayLike, offset: ArrayLike) -> FloatArray:
    """``K = E/m - [r]x J^-1 [r]x``: the jump of the contact point's velocity per unit
    impulse, ``u+ - u- = K P`` (theory §11.3).

    Parameters
    ----------
    mass : float
        ``m`` (kg).
    inertia_space : array_like, shape (3, 3)
        ``J``, the inertia about the centre of mass in **space** axes (kg m^2),
        ``R J_body R^T``.
    offset : array_like, shape (3,)
        ``r``, the contact point from the centre of mass (m, space axes).

    Examples
    --------
    A solid ball of radius 1 m and mass 1 kg touching at its bottom: the tangential
    entries are ``1/m + R^2 / (2/5 m R^2) = 3.5`` kg^-1.

    >>> import numpy as np
    >>> np.round(collision_matrix(1.0, 0.4 * np.eye(3), [0, 0, -1.0]), 6)
    array([[3.5, 0. , 0. ],
           [0. , 3.5, 0. ],
           [0. , 0. , 1. ]])
    """
    m = float(mass)
    r = np.asarray(offset, dtype=float)
    rx = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    return np.eye(3) / m - rx @ np.linalg.solve(np.asarray(inertia_space, dtype=float), rx)


def _law(law: Any) -> str:
    if law not in _LAWS:
        raise InvalidInputError(f"Expected `law` to be one of {_LAWS}, got {law!r}.")
    return str(law)


def _coefficient(x: Any, name: str, hi: float | None) -> float:
    v = float(as_float_array(x, name))
    if not (v >= 0.0 and (hi is None or v <= hi)):
        bound = f"in [0, {hi:g}]" if hi is not None else ">= 0"
        raise InvalidInputError(f"Expected `{name}` {bound}, got {v!r}.")
    return v


def _unit_normal(normal: ArrayLike) -> FloatArray:
    n = as_vec3(normal, "normal").reshape(3)
    s = float(np.linalg.norm(n))
    if not s > 0.0:
        raise InvalidInputError("Expected `normal` to be a non-zero vector (3,), got zero.")
    return n / s


def _routh(
    k: FloatArray, n: FloatArray, u0: FloatArray, e: float, mu: float, law: str
) -> tuple[FloatArray, float, str]:
    """The impulse ``P`` of an impact with contact velocity ``u0`` (approaching), by
    Routh's method: ``u`` as a function of the normal impulse ``p`` (theory §11.3).
    Returns ``(P, P_c, mode)``."""
    from scipy.integrate import solve_ivp

    knn = float(n @ k @ n)
    un0 = float(u0 @ n)
    scale = float(np.linalg.norm(u0))
    if mu == 0.0:
        return -(1.0 + e) * un0 / knn * n, -un0 / knn, "frictionless"
    basis = _tangent_basis(n)
    tiny = 1e-12 * scale
    u = u0.astype(float).copy()
    p_vec = np.zeros(3)
    pn = 0.0
    pc: float | None = None
    slid = stuck = False

    def end_reached() -> bool:
        if pc is None:
            return False
        if law == "poisson":
            return pn >= (1.0 + e) * pc * (1.0 - 1e-14)
        return float(u @ n) >= -e * un0 * (1.0 - 1e-14)

    for _ in range(64):  # stages: slide, stick (or slide on), each to its boundary
        if pc is None and float(u @ n) >= -1e-15 * scale:
            pc = pn
        if end_reached():
            break
        ut = u - float(u @ n) * n
        if float(np.linalg.norm(ut)) > 10.0 * tiny:  # the slip event ends at `tiny`
            slid = True

            def rhs(_: float, y: FloatArray) -> FloatArray:
                uu = y[:3]
                vt = uu - float(uu @ n) * n
                d = n - mu * vt / max(float(np.linalg.norm(vt)), 1e-300)
                return np.concatenate([k @ d, d])

            def slip(_: float, y: FloatArray) -> float:
                vt = y[:3] - float(y[:3] @ n) * n
                return float(np.linalg.norm(vt)) - tiny

            def compressed(_: float, y: FloatArray) -> float:
                return float(y[:3] @ n)

            def done(s: float, y: FloatArray, pc: float | None = pc) -> float:
                if pc is None:
                    return -1.0
                if law == "poisson":
                    return s - (1.0 + e) * pc
                return float(y[:3] @ n) + e * un0

            slip.terminal = True  # type: ignore[attr-defined]
            compressed.terminal = True  # type: ignore[attr-defined]
            done.terminal = True  # type: ignore[attr-defined]
            slip.direction = -1  # type: ignore[attr-defined]
            compressed.direction = 1  # type: ignore[attr-defined]
            done.direction = 1  # type: ignore[attr-defined]
            span = 10.0 * (1.0 + e) * (abs(un0) + scale) / knn + 1e-300
            events = [slip, done] if pc is not None else [slip, compressed]
            sol = solve_ivp(rhs, (pn, pn + span), np.concatenate([u, p_vec]), method="DOP853",
                            rtol=1e-13, atol=1e-15 * max(scale, 1e-300), events=events)  # fmt: skip
            pn, u, p_vec = float(sol.t[-1]), sol.y[:3, -1], sol.y[3:, -1]
            if sol.status != 1:
                raise InvalidInputError(
                    "The impact does not end (Painleve's paradox): with friction `mu` the "
                    "normal velocity of the contact does not grow with the impulse."
                )
            continue
        # no slip: can it stay so? the tangential impulse rate that keeps u_t = 0
        ktt = basis @ k @ basis.T
        d = -np.linalg.solve(ktt, basis @ k @ n)
        if float(np.linalg.norm(d)) <= mu:
            stuck = True
            direction = n + basis.T @ d
        else:  # it cannot: it slides on, friction at its limit, along the slip it starts
            # (u_t' = K_tn + K_tt f with f = -mu s/|s| for the slip direction s; taking s
            # along -d, the direction of the unresisted tangential acceleration)
            s_dir = -(basis.T @ d) / float(np.linalg.norm(d))
            direction = n - mu * s_dir
        rate = k @ direction
        dun = float(rate @ n)
        if dun <= 0.0:
            raise InvalidInputError(
                "The impact does not end (Painleve's paradox): with friction `mu` the "
                "normal velocity of the contact does not grow with the impulse."
            )
        un = float(u @ n)
        if pc is None:
            step = -un / dun
        elif law == "poisson":
            step = (1.0 + e) * pc - pn
        else:
            step = (-e * un0 - un) / dun
        step = max(step, 0.0)
        u = u + step * rate
        p_vec = p_vec + step * direction
        pn += step
        if pc is None:
            pc = pn
    mode = "slide-stick" if (slid and stuck) else "stick" if stuck else "slide"
    return p_vec, float(pc if pc is not None else pn), mode


def _tangent_basis(n: FloatArray) -> FloatArray:
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return np.stack([t1, np.cross(n, t1)])


def rigid_impact(
    inertia: ArrayLike,
    mass: float,
    rotation: ArrayLike,
    velocity: ArrayLike,
    omega: ArrayLike,
    offset: ArrayLike,
    normal: ArrayLike = (0.0, 0.0, 1.0),
    *,
    restitution: float = 1.0,
    friction: float = 0.0,
    law: str = "newton",
) -> ImpactResult:
    """A rigid body hits a plane at one point: the impulse and the velocity jump
    (theory §11.3).

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3)
        Inertia about the centre of mass in body axes (kg m^2): principal moments or
        a tensor.
    mass : float
        ``m`` (kg).
    rotation : array_like, shape (4,)
        Attitude at the impact, body -> space (scalar-first quaternion).
    velocity : array_like, shape (3,)
        ``v-``, the centre of mass's velocity before (m/s, space axes).
    omega : array_like, shape (3,)
        ``w-`` in body axes (rad/s).
    offset : array_like, shape (3,)
        ``r``, the contact point from the centre of mass (m, space axes).
    normal : array_like, shape (3,), optional
        The plane's normal, pointing to the body's side (default ``+z``).
    restitution : float, optional
        ``e`` in [0, 1] (default 1, elastic).
    friction : float, optional
        Coulomb's ``mu >= 0`` (default 0, smooth).
    law : {"newton", "poisson"}, optional
        The restitution law (equal without friction, and for a contact that sticks
        throughout).

    Returns
    -------
    ImpactResult
        ``omega`` in body axes; the other vectors in space axes.

    Raises
    ------
    InvalidInputError
        The contact point not approaching the plane (``u_n >= 0``), coefficients out of
        range, a non-physical inertia, Painleve's paradox (no impulsive solution).

    Examples
    --------
    A solid ball (``J = 2/5 m R^2``, ``R = 1`` m) with backspin (``w_y < 0`` while
    ``v_x > 0``) lands with ``mu`` large enough for the slip to stop: it leaves rolling
    backwards, ``v_x+ = (5 v_x + 2 R w_y) / 7`` (the angular momentum about the
    contact point is kept).

    >>> import numpy as np
    >>> out = rigid_impact([0.4] * 3, 1.0, [1, 0, 0, 0], [2.0, 0, -3.0], [0, -10.0, 0],
    ...                    [0, 0, -1.0], restitution=0.5, friction=10.0)
    >>> out.mode, np.round(out.velocity, 6).tolist(), np.round(out.omega, 6).tolist()
    ('slide-stick', [-1.428571, 0.0, 1.5], [0.0, -1.428571, 0.0])
    """
    j, principal = _as_inertia(inertia, "inertia")
    jb = np.diag(j) if principal else np.asarray(j, dtype=float)
    if jb.shape != (3, 3):
        raise InvalidInputError(f"Expected `inertia` of one body, got shape {np.shape(j)}.")
    m = _coefficient(mass, "mass", None)
    if m <= 0:
        raise InvalidInputError(f"Expected `mass` > 0 (kg), got {m!r}.")
    q = as_rotation_quat(rotation, "rotation").reshape(4)
    v = as_vec3(velocity, "velocity").reshape(3)
    wb = as_vec3(omega, "omega").reshape(3)
    r = as_vec3(offset, "offset").reshape(3)
    n = _unit_normal(normal)
    e = _coefficient(restitution, "restitution", 1.0)
    mu = _coefficient(friction, "friction", None)
    law = _law(law)
    rot = _rotation_matrix(q)
    js = rot @ jb @ rot.T
    w = rot @ wb
    u0 = v + np.cross(w, r)
    if not float(u0 @ n) < 0.0:
        raise InvalidInputError(
            f"Expected the contact point to approach the plane (u . n < 0), got u . n = "
            f"{float(u0 @ n)!r} m/s."
        )
    k = collision_matrix(m, js, r)
    p, pc, mode = _routh(k, n, u0, e, mu, law)
    v1 = v + p / m
    w1 = w + np.linalg.solve(js, np.cross(r, p))
    t0 = 0.5 * m * float(v @ v) + 0.5 * float(w @ js @ w)
    t1 = 0.5 * m * float(v1 @ v1) + 0.5 * float(w1 @ js @ w1)
    u1 = v1 + np.cross(w1, r)
    return ImpactResult(
        impulse=p,
        velocity=v1,
        omega=rot.T @ w1,
        contact_velocity=np.stack([u0, u1]),
        energy_loss=t0 - t1,
        compression_impulse=pc,
        mode=mode,
    )


def particle_impact(
    velocity: ArrayLike,
    normal: ArrayLike = (0.0, 0.0, 1.0),
    *,
    restitution: float = 1.0,
    friction: float = 0.0,
    mass: float = 1.0,
) -> ImpactResult:
    """A particle hits a plane: ``v_n+ = -e v_n-``; Coulomb friction takes at most
    ``mu (1 + e) |v_n-|`` off the tangential speed (theory §11.3).

    Parameters
    ----------
    velocity : array_like, shape (3,)
        ``v-`` (m/s), approaching the plane.
    normal : array_like, shape (3,), optional
        The plane's normal, towards the particle (default ``+z``).
    restitution, friction : float, optional
        ``e`` in [0, 1] (default 1) and Coulomb's ``mu >= 0`` (default 0).
    mass : float, optional
        ``m`` (kg), for the impulse and the energy (default 1).

    Examples
    --------
    >>> out = particle_impact([3.0, 0.0, -4.0], restitution=0.5, friction=0.2)
    >>> out.velocity.tolist(), out.mode, round(out.energy_loss, 12)
    ([1.8, 0.0, 2.0], 'slide', 8.88)
    """
    v = as_vec3(velocity, "velocity").reshape(3)
    n = _unit_normal(normal)
    e = _coefficient(restitution, "restitution", 1.0)
    mu = _coefficient(friction, "friction", None)
    m = _coefficient(mass, "mass", None)
    if m <= 0:
        raise InvalidInputError(f"Expected `mass` > 0 (kg), got {m!r}.")
    vn = float(v @ n)
    if not vn < 0.0:
        raise InvalidInputError(
            f"Expected the particle to approach the plane (v . n < 0), got v . n = {vn!r} m/s."
        )
    vt = v - vn * n
    slip = float(np.linalg.norm(vt))
    pn = -(1.0 + e) * m * vn
    if mu == 0.0:
        mode, vt1 = "frictionless", vt
    elif mu * pn >= m * slip:
        mode, vt1 = "stick", np.zeros(3)
    else:
        mode, vt1 = "slide", vt * (1.0 - mu * pn / (m * slip))
    v1 = vt1 - e * vn * n
    p = m * (v1 - v)
    return ImpactResult(
        impulse=p,
        velocity=v1,
        omega=None,
        contact_velocity=np.stack([v, v1]),
        energy_loss=0.5 * m * (float(v @ v) - float(v1 @ v1)),
        compression_impulse=-m * vn,
        mode=mode if mu == 0.0 or mode == "slide" or slip == 0.0 else "slide-stick",
    )


def _rotation_matrix(q: FloatArray) -> FloatArray:
    return np.stack([rotate(q, e) for e in np.eye(3)], axis=1)


def simulate_bounces(
    body: Any,
    position0: ArrayLike,
    velocity0: ArrayLike,
    rotation0: ArrayLike,
    omega0: ArrayLike,
    t: ArrayLike,
    *,
    corners: ArrayLike | None = None,
    radius: float | None = None,
    g: float = 9.80665,
    restitution: float = 0.5,
    friction: float = 0.0,
    law: str = "newton",
    rest_speed: float = 1e-3,
    max_impacts: int = 500,
) -> Any:
    """A rigid body thrown onto the floor ``z = 0`` in uniform gravity, bouncing on its
    corners (a box) or on its surface (a ball): exact flights between impacts, each
    impact by :func:`rigid_impact` (theory §11.3).

    Between impacts the centre of mass follows the parabola ``r0 + v0 s - g s^2 e_z / 2``
    and the body turns by the exact Euler-Poinsot motion
    (:class:`~poinsot.dynamics.FreeRigidBody`); an impact is the first time a corner's
    height ``z_c(s) + (R(s) p_i)_z`` reaches 0 (Brent's method on the exact motion) or,
    for a ball, ``z_c(s) = radius`` (a quadratic). The motion ends when a rebound's
    normal contact speed is below ``rest_speed``: resting contact on several points is
    not a sequence of single-point impacts (``info["stopped"]`` says so).

    Parameters
    ----------
    body : RigidBody
        Mass and inertia about the centre of mass (body axes).
    position0, velocity0 : array_like, shape (3,)
        The centre of mass (m, m/s, space axes; ``z`` up), above the floor.
    rotation0 : array_like, shape (4,)
        Initial attitude, body -> space (scalar-first quaternion).
    omega0 : array_like, shape (3,)
        Initial angular velocity in body axes (rad/s).
    t : array_like, shape (n,)
        Output times (s), increasing, from the initial state.
    corners : array_like, shape (k, 3), optional
        The body points that can touch the floor (m, body axes, from the centre of mass).
    radius : float, optional
        A ball's radius (m), instead of ``corners``.
    g : float, optional
        Gravity (m/s^2) along ``-z``.
    restitution, friction, law : optional
        As :func:`rigid_impact` (defaults 0.5, 0, ``"newton"``).
    rest_speed : float, optional
        A rebound slower than this (m/s) ends the motion (default 1 mm/s).
    max_impacts : int, optional
        At most this many impacts (default 500).

    Returns
    -------
    PoseTrajectory
        ``position``, ``velocity`` (space), ``rotation``, ``omega`` (body) at the output
        times up to the end; ``info["events"]`` an :class:`~poinsot.events.EventLog` of
        the impacts (state: position, velocity, quaternion, omega before the impact,
        13 values), ``info["impacts"]`` a list of :class:`ImpactResult`.

    Examples
    --------
    A ball (``J = 2/5 m R^2``) dropped with backspin bounces back towards where it
    came from:

    >>> import numpy as np
    >>> from poinsot.mass import RigidBody
    >>> ball = RigidBody.sphere(0.2, 0.1)
    >>> tr = simulate_bounces(ball, [0, 0, 1.0], [1.0, 0, 0], [1, 0, 0, 0], [0, -60.0, 0],
    ...                       np.linspace(0, 1.5, 151), radius=0.1, friction=0.5)
    >>> first = tr.info["impacts"][0]
    >>> bool(first.velocity[0] < 0), first.mode
    (True, 'slide-stick')
    """
    from scipy.optimize import brentq

    if not isinstance(body, RigidBody) or body.shape != ():
        raise InvalidInputError(
            f"Expected `body` to be one poinsot.mass.RigidBody, got {type(body).__name__}."
        )
    if (corners is None) == (radius is None):
        raise InvalidInputError("Expected exactly one of `corners` (a box) and `radius` (a ball).")
    pts = None
    rad = 0.0
    if corners is not None:
        pts = as_float_array(corners, "corners")
        if pts.ndim != 2 or pts.shape[-1] != 3 or pts.shape[0] < 1:
            raise InvalidInputError(f"Expected `corners` of shape (k, 3), got {pts.shape}.")
    else:
        rad = _coefficient(radius, "radius", None)
        if rad <= 0:
            raise InvalidInputError(f"Expected `radius` > 0 (m), got {rad!r}.")
    m = float(body.mass)
    inertia = np.asarray(body.inertia, dtype=float)
    r = as_vec3(position0, "position0").reshape(3).copy()
    v = as_vec3(velocity0, "velocity0").reshape(3).copy()
    q = as_rotation_quat(rotation0, "rotation0").reshape(4).copy()
    w = as_vec3(omega0, "omega0").reshape(3).copy()
    tt = as_times(t, "t")
    grav = _coefficient(g, "g", None)
    e = _coefficient(restitution, "restitution", 1.0)
    mu = _coefficient(friction, "friction", None)
    law = _law(law)
    down = np.array([0.0, 0.0, grav])

    def heights(fb: Any, s: np.ndarray, r_a: np.ndarray, v_a: np.ndarray) -> np.ndarray:
        z = r_a[2] + v_a[2] * s - 0.5 * grav * s * s
        if pts is None:
            return (z - rad)[:, None]
        qs = fb.rotation(s).as_quat()
        return z[:, None] + _quat.rotate(qs[:, None, :], pts[None])[..., 2]

    if np.any(heights(FreeRigidBody(inertia, rotation0=q, omega0=w), np.zeros(1), r, v) < -1e-12):
        raise InvalidInputError("Expected the body to start above the floor z = 0.")
    n_out = tt.size
    pos, vel = np.empty((n_out, 3)), np.empty((n_out, 3))
    quat, omg = np.empty((n_out, 4)), np.empty((n_out, 3))
    rows: list[tuple[float, int, FloatArray, float]] = []
    impacts: list[ImpactResult] = []
    t_a = float(tt[0])
    k = 0
    stopped = ""
    n_hat = np.array([0.0, 0.0, 1.0])
    while True:
        fb = FreeRigidBody(inertia, rotation0=q, omega0=w)
        horizon = float(tt[-1]) - t_a
        # the first impact of this flight: scan, then Brent on the exact motion
        spin = float(np.linalg.norm(w))
        ds = min(0.01, 0.02 / max(spin, 1e-12))
        found: tuple[float, int] | None = None
        s0 = 0.0
        h_prev = heights(fb, np.zeros(1), r, v)[0]
        h_prev = np.where(h_prev <= 1e-12, np.inf, h_prev)  # touching now: leaving
        while s0 < horizon and found is None:
            grid = s0 + ds * np.arange(1, 257)
            grid = grid[grid <= horizon + ds]
            grid[-1] = min(grid[-1], horizon) if grid[-1] > horizon else grid[-1]
            h = heights(fb, grid, r, v)
            prev = np.vstack([h_prev[None], h[:-1]])
            hit = (prev > 0) & (h <= 0)
            if s0 == 0.0:  # a corner touching at the start that goes down: hit now
                hit[0] |= (np.isinf(h_prev)) & (h[0] <= 0)
            if hit.any():
                row = int(np.flatnonzero(hit.any(axis=1))[0])
                a = float(grid[row - 1]) if row else s0
                best = None
                for i in np.flatnonzero(hit[row]):

                    def hi(
                        s: float, i: int = int(i), fb: Any = fb, r: Any = r, v: Any = v
                    ) -> float:
                        return float(heights(fb, np.array([s]), r, v)[0, i])

                    b_end = float(grid[row])
                    if hi(a) <= 0:  # the corner that touches at the start: find it above
                        for j in range(1, 60):
                            if hi(a + (b_end - a) * 2.0**-j) > 0:
                                a = a + (b_end - a) * 2.0**-j
                                break
                        else:
                            continue  # it never rises: a resting contact, below
                    root = float(brentq(hi, a, b_end, xtol=1e-15))
                    if best is None or root < best[0]:
                        best = (root, int(i))
                found = best
            h_prev = h[-1]
            s0 = float(grid[-1])
        s_end = found[0] if found is not None else horizon
        # the samples of this flight
        while k < n_out and tt[k] <= t_a + s_end:
            s = np.array([float(tt[k]) - t_a])
            pos[k] = r + v * s - 0.5 * down * s * s
            vel[k] = v - down * s
            quat[k] = fb.rotation(s).as_quat()[0]
            omg[k] = fb.omega(s)[0]
            k += 1
        if found is None:
            break
        s_hit, i_hit = found
        t_a += s_hit
        r = r + v * s_hit - 0.5 * down * s_hit * s_hit
        v = v - down * s_hit
        q = fb.rotation(np.array([s_hit])).as_quat()[0]
        w = fb.omega(np.array([s_hit]))[0]
        rows.append((t_a, 0, np.concatenate([r, v, q, w]), -1.0))
        offset = -rad * n_hat if pts is None else _quat.rotate(q, pts[i_hit])
        u_n = float(v[2] + np.cross(_rotation_matrix(q) @ w, offset)[2])
        if u_n >= 0.0:  # grazing, or a contact that never rises: it rests
            stopped = f"at t = {t_a:.6g} s a corner grazes the floor: resting contact"
            break
        out = rigid_impact(inertia, m, q, v, w, offset, n_hat, restitution=e, friction=mu,
                           law=law)  # fmt: skip
        impacts.append(out)
        assert out.omega is not None  # a rigid body's impact
        v, w = out.velocity, out.omega
        if float(out.contact_velocity[1] @ n_hat) < rest_speed:
            stopped = (
                f"at t = {t_a:.6g} s the rebound ({float(out.contact_velocity[1] @ n_hat):.3g} "
                f"m/s) was slower than rest_speed: resting contact is not modelled"
            )
            break
        if len(impacts) >= max_impacts:
            stopped = f"max_impacts = {max_impacts} reached at t = {t_a:.6g} s"
            break
    if stopped:  # the motion ends at the last impact: its state after is the last sample
        keep = int(np.searchsorted(tt, t_a, side="left"))
        tt = np.concatenate([tt[:keep], [t_a]])
        pos = np.concatenate([pos[:keep], r[None]])
        vel = np.concatenate([vel[:keep], v[None]])
        quat = np.concatenate([quat[:keep], q[None]])
        omg = np.concatenate([omg[:keep], w[None]])
    log = EventLog.of_one_body(("impact",), rows, 13, t_a if stopped else math.inf)
    rot = Rotation.from_quat(quat)
    js = np.einsum("nij,jk,nlk->nil", rot.as_matrix(), inertia, rot.as_matrix())
    w_space = np.einsum("nij,nj->ni", rot.as_matrix(), omg)
    energy = 0.5 * m * np.sum(vel * vel, axis=1) + 0.5 * np.einsum("ni,nij,nj->n", w_space, js,
                                                                   w_space)  # fmt: skip
    return PoseTrajectory(
        t=tt,
        rotation=rot,
        omega=omg,
        method="exact",
        energy=energy,
        momentum=np.einsum("nij,nj->ni", js, w_space),
        position=pos,
        velocity=vel,
        info={"events": log, "impacts": impacts, "stopped": stopped},
    )
