"""Attitude in orbit (theory §10.2): Kepler orbits, orbit frames and their rates, the
Earth's tilted-dipole magnetic field, exact planar pitch libration and the linear
stability of a gravity-gradient satellite.

Public names
------------
:class:`KeplerOrbit`
    An elliptic Kepler orbit from its classical elements (or a state), evaluated at
    any times: ``position(t)``, ``velocity(t)``, ``state(t)``.
:func:`orbit_frame`, :func:`orbit_frame_rates`
    The orbit frame ``"rtn"`` (Hill) or ``"lvlh"`` of a state ``(r, v)`` as a
    :class:`~poinsot.Rotation` ``q_io`` (orbit -> inertial components), and its
    angular velocity and acceleration in its own axes.
:func:`dipole_field`
    The Earth's tilted-dipole magnetic field (IGRF-13, epoch 2020), inertial axes.
:class:`PitchLibration`
    The exact planar pitch motion in a circular orbit (a pendulum in ``2 theta``).
:func:`gravity_gradient_stability`, :func:`linearized_gravity_gradient`,
:class:`GravityGradientStability`
    The linear stability of the orbit-frame-aligned equilibrium (Lagrange and
    DeBra-Delp regions) and the linearised equations.

**Convention:** inertial axes are those of the orbit's central body (ECI for the
Earth), metres, seconds, radians; an orbit-frame attitude maps orbit-frame components
to inertial components (``v_i = R_io v_o``); body axes ``1, 2, 3`` = roll, pitch, yaw
coincide with the ``"lvlh"`` axes ``x`` (along-track), ``y`` (minus the orbit
normal), ``z`` (nadir) at the equilibrium.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_choice, as_float_array, as_positive, as_vec3
from .._vec import cross, dot, length
from ..errors import InvalidInputError
from ..mass.tensor import as_inertia
from ..rotations.rotation import Rotation

__all__ = [
    "EARTH_MU",
    "EARTH_MAGNETIC_RADIUS",
    "IGRF2020_DIPOLE",
    "KeplerOrbit",
    "orbit_frame",
    "orbit_frame_rates",
    "dipole_field",
    "PitchLibration",
    "GravityGradientStability",
    "gravity_gradient_stability",
    "linearized_gravity_gradient",
    "ORBIT_FRAMES",
]

#: The Earth's gravitational parameter (m^3/s^2, WGS-84 / EGM-96).
EARTH_MU = 3.986004418e14
#: The reference radius of the IGRF geomagnetic model (m).
EARTH_MAGNETIC_RADIUS = 6371.2e3
#: IGRF-13 dipole (degree-1) Gauss coefficients ``(g10, g11, h11)`` at epoch 2020 (T).
IGRF2020_DIPOLE = (-29404.8e-9, -1450.9e-9, 4652.5e-9)
#: The orbit frames of :func:`orbit_frame`.
ORBIT_FRAMES = ("rtn", "lvlh")

_EARTH_ROTATION_RATE = 7.2921159e-5  # rad/s, as poinsot.dynamics.EARTH_ROTATION_RATE
_TWO_PI = 2.0 * math.pi


def _scalar(x: object, name: str, unit: str) -> float:
    a = as_float_array(x, name)
    if a.ndim != 0:
        raise InvalidInputError(f"Expected `{name}` to be a scalar ({unit}), got shape {a.shape}.")
    return float(a)


def _rot3(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot1(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _solve_kepler(mean: FloatArray, e: float) -> FloatArray:
    """The eccentric anomaly ``E`` of ``E - e sin E = M`` for ``M`` in ``[-pi, pi]``.

    Newton's method from Danby's start ``E = M + 0.85 e sign(M)``, which converges
    monotonically for every ``0 <= e < 1``; iterated (vectorised) until the step is
    below ``4 eps``, then one more step.
    """
    E = mean + 0.85 * e * np.sign(mean)
    for _ in range(60):
        f = E - e * np.sin(E) - mean
        step = f / (1.0 - e * np.cos(E))
        E = E - step
        if np.all(np.abs(step) <= 4e-16 * np.maximum(np.abs(E), 1.0)):
            break
    f = E - e * np.sin(E) - mean
    out: FloatArray = E - f / (1.0 - e * np.cos(E))
    return out


class KeplerOrbit:
    """An elliptic Kepler orbit given by its classical elements (theory §9, §10.2).

    The position at time ``t`` follows from the mean anomaly
    ``M = M0 + n (t - epoch)``, ``n = sqrt(mu / a^3)``, Kepler's equation
    ``E - e sin E = M`` (solved by Newton's method, vectorised, to a few ulp), and
    in the perifocal frame (``P`` to the periapsis, ``Q`` 90 deg ahead, ``W`` the
    orbit normal)

    ``r = a (cos E - e) P + a sqrt(1 - e^2) sin E Q``,
    ``v = (sqrt(mu a) / |r|) (-sin E P + sqrt(1 - e^2) cos E Q)``,

    with ``[P Q W] = R3(raan) R1(inclination) R3(argp)`` in inertial axes.

    Parameters
    ----------
    a : float
        Semi-major axis (m), > 0.
    e : float
        Eccentricity, ``0 <= e < 1``.
    inclination, raan, argp : float
        Inclination, right ascension of the ascending node and argument of periapsis
        (rad, or degrees with ``degrees=True``).
    anomaly0 : float
        True anomaly at ``epoch`` (rad, or degrees).
    mu : float, optional
        Gravitational parameter (m^3/s^2); default the Earth's.
    epoch : float, optional
        Time (s) at which the true anomaly is ``anomaly0``; default 0.
    degrees : bool, optional
        Angles in degrees. Default ``False``.

    Notes
    -----
    **Convention:** inertial axes of the central body; m, m/s, s; the anomaly grows
    in the sense of the angular momentum ``h = r x v`` (along ``W``). See
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import KeplerOrbit
    >>> orbit = KeplerOrbit(7.0e6, 0.1, 0.5, 0.2, 0.3, 0.0)
    >>> bool(np.isclose(orbit.period, 2 * np.pi * np.sqrt(7.0e6**3 / 3.986004418e14)))
    True
    >>> r, v = orbit.state(orbit.period)        # back at the periapsis
    >>> round(float(np.linalg.norm(r)) / 7.0e6, 12)
    0.9
    """

    def __init__(
        self,
        a: float,
        e: float,
        inclination: float,
        raan: float,
        argp: float,
        anomaly0: float,
        *,
        mu: float = EARTH_MU,
        epoch: float = 0.0,
        degrees: bool = False,
    ) -> None:
        deg = as_bool(degrees, "degrees")
        self.a = _scalar(as_positive(a, "a"), "a", "m")
        ecc = _scalar(e, "e", "eccentricity")
        if not 0.0 <= ecc < 1.0:
            raise InvalidInputError(
                f"Expected `e` to be an elliptic eccentricity, 0 <= e < 1, got {ecc!r}."
            )
        self.e = ecc
        k = math.pi / 180.0 if deg else 1.0
        self.inclination = _scalar(inclination, "inclination", "angle") * k
        self.raan = _scalar(raan, "raan", "angle") * k
        self.argp = _scalar(argp, "argp", "angle") * k
        self.anomaly0 = _scalar(anomaly0, "anomaly0", "angle") * k
        self.mu = _scalar(as_positive(mu, "mu"), "mu", "m^3/s^2")
        self.epoch = _scalar(epoch, "epoch", "s")
        pqw = _rot3(self.raan) @ _rot1(self.inclination) @ _rot3(self.argp)
        pqw.setflags(write=False)
        self._pqw = pqw
        half = 0.5 * self.anomaly0
        E0 = 2.0 * math.atan2(
            math.sqrt(1.0 - ecc) * math.sin(half), math.sqrt(1.0 + ecc) * math.cos(half)
        )
        self._mean0 = E0 - ecc * math.sin(E0)

    @classmethod
    def from_state(
        cls, r: ArrayLike, v: ArrayLike, *, mu: float = EARTH_MU, epoch: float = 0.0
    ) -> KeplerOrbit:
        """The orbit through position ``r`` (m) and velocity ``v`` (m/s) at ``epoch``.

        ``h = r x v``, ``e = v x h / mu - r / |r|``, ``1 / a = 2 / |r| - |v|^2 / mu``;
        the perifocal axes ``P = e / |e|`` (the node line, or inertial ``x``
        projected, when ``e = 0``), ``W = h / |h|``, ``Q = W x P`` give the angles
        (theory §10.2). Raises :class:`InvalidInputError` for a state that is not on
        an ellipse (``e >= 1``) or has no angular momentum.

        Examples
        --------
        >>> from poinsot.dynamics import KeplerOrbit
        >>> o = KeplerOrbit.from_state([7.0e6, 0.0, 0.0], [0.0, 8.0e3, 0.0])
        >>> round(o.e, 6), round(o.anomaly0, 12)
        (0.123933, 0.0)
        """
        rr = as_vec3(r, "r")
        vv = as_vec3(v, "v")
        if rr.shape != (3,) or vv.shape != (3,):
            raise InvalidInputError(
                f"Expected `r` and `v` to have shape (3,), got {rr.shape} and {vv.shape}."
            )
        m = _scalar(as_positive(mu, "mu"), "mu", "m^3/s^2")
        h = cross(rr, vv)
        rn, hn = float(length(rr)), float(length(h))
        if rn == 0.0 or hn == 0.0:
            raise InvalidInputError(
                "Expected `r` and `v` to give a non-zero angular momentum r x v, got a "
                "rectilinear state."
            )
        ev = cross(vv, h) / m - rr / rn
        ecc = float(length(ev))
        if ecc >= 1.0:
            raise InvalidInputError(
                f"Expected the state (`r`, `v`) to be on an elliptic orbit, got e = {ecc:.6g}."
            )
        a = 1.0 / (2.0 / rn - float(dot(vv, vv)) / m)
        w = h / hn
        p = ev - float(dot(ev, w)) * w  # in the plane (a round-off e of a circle is not)
        pn = float(length(p))
        if pn > 0.0:
            p = p / pn
        else:  # circular: the periapsis at the ascending node (or inertial x)
            node = np.array([-w[1], w[0], 0.0])
            if float(length(node)) < 1e-12:
                node = np.array([1.0, 0.0, 0.0]) - w[0] * w
            p = node / float(length(node))
        q = cross(w, p)
        inc = math.atan2(math.hypot(w[0], w[1]), w[2])
        if math.hypot(w[0], w[1]) > 1e-15:
            raan = math.atan2(w[0], -w[1])
            argp = math.atan2(p[2], q[2])
        else:  # equatorial: the node is undefined, raan = 0
            raan = 0.0
            argp = math.atan2(p[1], p[0]) if w[2] > 0 else math.atan2(-p[1], p[0])
        nu = math.atan2(float(dot(q, rr)), float(dot(p, rr)))
        return cls(a, ecc, inc, raan, argp, nu, mu=m, epoch=epoch)

    def __repr__(self) -> str:
        return (
            f"KeplerOrbit(a={self.a:.6g}, e={self.e:.6g}, inclination={self.inclination:.6g}, "
            f"raan={self.raan:.6g}, argp={self.argp:.6g}, anomaly0={self.anomaly0:.6g})"
        )

    @property
    def mean_motion(self) -> float:
        """``n = sqrt(mu / a^3)`` (rad/s)."""
        return math.sqrt(self.mu / self.a**3)

    @property
    def period(self) -> float:
        """``2 pi / n`` (s)."""
        return _TWO_PI / self.mean_motion

    @property
    def perifocal(self) -> np.ndarray:
        """``[P Q W]`` (3, 3): the perifocal axes as columns, inertial components."""
        return self._pqw

    def eccentric_anomaly(self, t: ArrayLike) -> FloatArray:
        """``E(t)`` (rad) in ``[-pi, pi]``, the solution of ``E - e sin E = M(t)``."""
        tt = as_float_array(t, "t")
        mean = np.remainder(self._mean0 + self.mean_motion * (tt - self.epoch) + math.pi, _TWO_PI)
        return _solve_kepler(mean - math.pi, self.e)

    def state(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Position (m) and velocity (m/s) at times ``t``, each shape ``t.shape + (3,)``."""
        E = self.eccentric_anomaly(t)
        a, e = self.a, self.e
        s, c = np.sin(E), np.cos(E)
        b = math.sqrt((1.0 - e) * (1.0 + e))
        rad = a * (1.0 - e * c)
        pr = np.stack([a * (c - e), a * b * s], axis=-1)
        k = math.sqrt(self.mu * a) / rad
        pv = np.stack([-k * s, k * b * c], axis=-1)
        pq = self._pqw[:, :2]
        return pr @ pq.T, pv @ pq.T

    def position(self, t: ArrayLike) -> FloatArray:
        """Position (m), inertial axes, shape ``t.shape + (3,)``."""
        return self.state(t)[0]

    def velocity(self, t: ArrayLike) -> FloatArray:
        """Velocity (m/s), inertial axes, shape ``t.shape + (3,)``."""
        return self.state(t)[1]


def _frame_axes(r: FloatArray, v: FloatArray, frame: str) -> FloatArray:
    """The orbit-frame axes as the columns of ``C_io`` (..., 3, 3)."""
    h = cross(r, v)
    rn, hn = length(r), length(h)
    if np.any(rn == 0.0) or np.any(hn == 0.0):
        raise InvalidInputError(
            "Expected `r` and `v` to be non-zero and not parallel (r x v != 0), got a "
            "rectilinear state."
        )
    x = r / rn[..., None]
    z = h / hn[..., None]
    y = cross(z, x)
    if frame == "lvlh":  # z nadir, y minus the normal, x = y x z (along-track)
        x, y, z = y, -z, -x
    return np.stack([x, y, z], axis=-1)


def orbit_frame(r: ArrayLike, v: ArrayLike, *, frame: str = "rtn") -> Rotation:
    """The orbit frame of the state ``(r, v)``: ``R_io`` mapping its components to
    inertial ones (theory §10.2).

    ``"rtn"`` (Hill): ``x = r / |r|`` radial out, ``z = h / |h|`` the orbit normal
    (``h = r x v``), ``y = z x x`` along-track. ``"lvlh"``: ``z = -r / |r|`` (nadir),
    ``y = -h / |h|``, ``x = y x z`` (the velocity direction on a circular orbit).
    ``v_i = R_io v_o``; for the attitude of a body relative to the orbit frame take
    ``R_ob = R_io^-1 R_ib`` (theory §4).

    Parameters
    ----------
    r, v : array_like, shape (..., 3)
        Position (m) and velocity (m/s) in inertial axes; ``r x v != 0``.
    frame : {"rtn", "lvlh"}, optional
        Which frame. Default ``"rtn"``.

    Returns
    -------
    Rotation
        ``R_io`` with the broadcast batch shape of ``r`` and ``v``.

    Notes
    -----
    **Convention:** the rotation maps orbit-frame components to inertial components.
    See ``docs/theory.md`` §10.2 and ``docs/conventions.md``.

    Examples
    --------
    >>> from poinsot.dynamics import orbit_frame
    >>> f = orbit_frame([7.0e6, 0, 0], [0, 7.5e3, 0], frame="lvlh")
    >>> f.apply([1.0, 0.0, 0.0]).round(12) + 0.0    # x: along the velocity
    array([0., 1., 0.])
    >>> f.apply([0.0, 0.0, 1.0]).round(12) + 0.0    # z: nadir
    array([-1.,  0.,  0.])
    """
    as_choice(frame, "frame", ORBIT_FRAMES)
    rr, vv = as_vec3(r, "r"), as_vec3(v, "v")
    shape = np.broadcast_shapes(rr.shape, vv.shape)
    rr, vv = np.broadcast_to(rr, shape), np.broadcast_to(vv, shape)
    return Rotation.from_matrix(_frame_axes(rr, vv, frame))


def orbit_frame_rates(
    r: ArrayLike, v: ArrayLike, *, frame: str = "rtn"
) -> tuple[FloatArray, FloatArray]:
    """Angular velocity and angular acceleration of the orbit frame, in its own axes
    (theory §10.2).

    Under a central force (Kepler's included: ``h = r x v`` constant) the orbit
    plane is fixed and the frame turns about the orbit normal at

    ``w = |h| / |r|^2``,  ``w' = -2 (r . v) / |r|^2 w``

    (rad/s, rad/s^2): ``(0, 0, w)`` and ``(0, 0, w')`` in ``"rtn"`` axes,
    ``(0, -w, 0)`` and ``(0, -w', 0)`` in ``"lvlh"`` axes. With these, the
    kinematics of theory §5-§6 apply to the attitude relative to the orbit frame:
    ``w_body = w_rel + R_ob^T w_frame``. No ``mu`` is needed.

    Parameters
    ----------
    r, v : array_like, shape (..., 3)
        Position (m) and velocity (m/s), inertial axes.
    frame : {"rtn", "lvlh"}, optional
        Default ``"rtn"``.

    Returns
    -------
    omega, eps : ndarray, shape (..., 3)
        Angular velocity (rad/s) and acceleration (rad/s^2) in the frame's axes.

    Notes
    -----
    **Convention:** frame axes as in :func:`orbit_frame`; see ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> from poinsot.dynamics import orbit_frame_rates
    >>> w, dw = orbit_frame_rates([7.0e6, 0, 0], [0, 7.0e3, 0])
    >>> w, dw + 0.0
    (array([0.   , 0.   , 0.001]), array([0., 0., 0.]))
    """
    as_choice(frame, "frame", ORBIT_FRAMES)
    rr, vv = as_vec3(r, "r"), as_vec3(v, "v")
    h = length(cross(rr, vv))
    r2 = dot(rr, rr)
    if np.any(h == 0.0):
        raise InvalidInputError("Expected `r` and `v` to be non-zero and not parallel.")
    w = h / r2
    dw = -2.0 * dot(rr, vv) / r2 * w
    axis = 2 if frame == "rtn" else 1
    sign = 1.0 if frame == "rtn" else -1.0
    omega = np.zeros(w.shape + (3,))
    eps = np.zeros(w.shape + (3,))
    omega[..., axis] = sign * w
    eps[..., axis] = sign * dw
    return omega, eps


def dipole_field(
    t: ArrayLike,
    r: ArrayLike,
    *,
    coefficients: tuple[float, float, float] = IGRF2020_DIPOLE,
    radius: float = EARTH_MAGNETIC_RADIUS,
    rotation_rate: float = _EARTH_ROTATION_RATE,
    greenwich_angle: float = 0.0,
) -> FloatArray:
    """The Earth's tilted-dipole magnetic field ``B`` (T) at ``r``, inertial axes
    (theory §10.2).

    The degree-1 term of the geomagnetic potential,
    ``V = R_E (R_E / r)^2 (g10 cos th + (g11 cos ph + h11 sin ph) sin th)``
    (colatitude ``th``, east longitude ``ph``, Earth-fixed), is
    ``V = R_E^3 (g . r) / r^3`` with ``g = (g11, h11, g10)``; ``B = -grad V`` gives

    ``B = B0 (R_E / r)^3 (3 (m . rhat) rhat - m)``,  ``B0 = |g|``,  ``m = g / |g|``,

    the field of a dipole along the unit axis ``m`` (with IGRF-13 2020 it points
    80.6 deg south, to longitude 107.3 deg E: ``-m`` is the boreal geomagnetic pole
    at 80.6 deg N, 72.7 deg W). ``m`` is fixed in the Earth, which turns about
    inertial ``z`` at ``rotation_rate``: ``m_i = R3(greenwich_angle +
    rotation_rate t) m``. On the magnetic equator ``|B| = B0 (R_E / r)^3``, on its
    axis ``2 B0 (R_E / r)^3``.

    Parameters
    ----------
    t : array_like, shape (...)
        Time (s); broadcast with the batch shape of ``r``.
    r : array_like, shape (..., 3)
        Position from the Earth's centre (m), inertial axes, non-zero.
    coefficients : tuple of 3 floats, optional
        ``(g10, g11, h11)`` (T); default IGRF-13 epoch 2020
        ``(-29404.8, -1450.9, 4652.5)`` nT.
    radius : float, optional
        ``R_E`` (m), default the IGRF reference radius 6371.2 km.
    rotation_rate : float, optional
        The Earth's rotation rate (rad/s), default 7.2921159e-5.
    greenwich_angle : float, optional
        Angle (rad) from inertial ``x`` to the Greenwich meridian at ``t = 0``.

    Returns
    -------
    ndarray, shape (..., 3)
        ``B`` (T), inertial axes.

    Notes
    -----
    **Convention:** inertial axes with ``z`` the Earth's rotation axis, Earth-fixed
    axes equal to them at ``t = -greenwich_angle / rotation_rate``; see
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import dipole_field
    >>> b = dipole_field(0.0, [6371.2e3, 0, 0], coefficients=(-3e-5, 0.0, 0.0))
    >>> (b * 1e5).round(12) + 0.0     # untilted: 30 uT due north on the equator
    array([0., 0., 3.])
    """
    rr = as_vec3(r, "r")
    tt = as_float_array(t, "t")
    g = as_float_array(coefficients, "coefficients")
    if g.shape != (3,):
        raise InvalidInputError(f"Expected `coefficients` to have shape (3,), got {g.shape}.")
    re = _scalar(as_positive(radius, "radius"), "radius", "m")
    rate = _scalar(rotation_rate, "rotation_rate", "rad/s")
    g0 = _scalar(greenwich_angle, "greenwich_angle", "rad")
    rn = length(rr)
    if np.any(rn == 0.0):
        raise InvalidInputError("Expected `r` to be non-zero (the field is singular at 0).")
    b0 = float(np.sqrt(np.sum(g * g)))
    if b0 == 0.0:
        return np.zeros(np.broadcast_shapes(tt.shape, rr.shape[:-1]) + (3,))
    m_e = np.array([g[1], g[2], g[0]]) / b0
    angle = g0 + rate * tt
    c, s = np.cos(angle), np.sin(angle)
    m = np.stack([c * m_e[0] - s * m_e[1], s * m_e[0] + c * m_e[1], np.full_like(c, m_e[2])], -1)
    rhat = rr / rn[..., None]
    scale = b0 * (re / rn) ** 3
    out: FloatArray = scale[..., None] * (3.0 * dot(m, rhat)[..., None] * rhat - m)
    return out


def _principal(inertia: object, name: str = "inertia") -> FloatArray:
    j, principal = as_inertia(inertia, name)
    if principal:
        return j
    off = j - np.einsum("...ii->...i", j)[..., None] * np.eye(3)
    if np.any(off != 0.0):
        raise InvalidInputError(
            f"Expected `{name}` to be principal moments (roll, pitch, yaw) or a diagonal "
            "tensor, got a tensor with products of inertia."
        )
    return np.einsum("...ii->...i", j).copy()


class PitchLibration:
    """Exact planar pitch libration of a rigid body in a circular orbit (theory §10.2).

    Body principal axes ``1, 2, 3`` (moments ``I1, I2, I3``) start along the
    ``"lvlh"`` axes (roll ``x`` along-track, pitch ``y = -h / |h|``, yaw ``z``
    nadir) turned by the pitch angle ``theta`` about ``y``:
    ``R_ob = R2(theta)``. The gravity-gradient torque gives

    ``theta'' + 3 n^2 (I1 - I3) / I2 sin(theta) cos(theta) = 0``,

    a pendulum in ``phi = 2 theta``: ``phi'' + w0^2 sin(phi) = 0``,
    ``w0^2 = 3 n^2 (I1 - I3) / I2`` (for ``I1 < I3`` the same about
    ``phi = pi``). With ``k^2 = phi'(0)^2 / (4 w0^2) + sin^2(phi(0) / 2)``:

    - libration (``k < 1``): ``sin(phi / 2) = k sn(w0 t + u0 | k^2)``,
      ``cos(phi / 2) = dn``, period ``4 K(k^2) / w0``;
    - circulation (``k > 1``): ``phi / 2 = am(k w0 t + u0 | 1 / k^2)``, period
      (one turn of ``phi``) ``2 K(1 / k^2) / (k w0)``;
    - separatrix (``k = 1``): ``phi / 2 = gd(w0 t + u0)`` (``tanh``/``sech``;
      no period: ``inf``).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments ``(I1, I2, I3)`` (roll, pitch, yaw), kg m^2.
    mean_motion : float
        The orbit rate ``n`` (rad/s), > 0.
    theta0 : float
        Pitch angle at ``t = 0`` (rad).
    rate0 : float
        Pitch rate ``theta'(0)`` relative to the orbit frame (rad/s); the body rate
        about its axis 2 is ``theta' - n``.

    Notes
    -----
    **Convention:** ``theta`` is the angle of ``R2`` in ``R_ob`` (``"lvlh"``
    axes); see ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> from poinsot.dynamics import PitchLibration
    >>> lib = PitchLibration([2.0, 3.0, 1.0], 1e-3, theta0=0.3, rate0=0.0)
    >>> lib.regime
    'libration'
    >>> round(float(lib.theta(lib.period)), 12)
    0.3
    """

    def __init__(
        self, inertia: ArrayLike, mean_motion: float, *, theta0: float, rate0: float
    ) -> None:
        moments = _principal(inertia)
        if moments.shape != (3,):
            raise InvalidInputError(f"Expected `inertia` to have shape (3,), got {moments.shape}.")
        self.inertia = moments
        self.mean_motion = _scalar(as_positive(mean_motion, "mean_motion"), "mean_motion", "rad/s")
        self.theta0 = _scalar(theta0, "theta0", "rad")
        self.rate0 = _scalar(rate0, "rate0", "rad/s")
        i1, i2, i3 = (float(x) for x in moments)
        n = self.mean_motion
        w2 = 3.0 * n * n * (i1 - i3) / i2
        self.omega0 = math.sqrt(abs(w2))  # the small-libration rate about the stable point
        # psi = phi - offset swings about 0 with psi'' = -w^2 sin(psi)
        self._offset = 0.0 if w2 >= 0 else math.pi
        psi0 = 2.0 * self.theta0 - self._offset
        dpsi0 = 2.0 * self.rate0
        self._sign = -1.0 if dpsi0 < 0 else 1.0
        psi0, dpsi0 = self._sign * psi0, abs(dpsi0)
        self._psi0, self._dpsi0 = psi0, dpsi0
        if self.omega0 == 0.0:
            self.regime = "uniform"
            self._m = math.inf
            return
        w = self.omega0
        a = dpsi0 / (2.0 * w)
        s, c = math.sin(0.5 * psi0), math.cos(0.5 * psi0)
        m = a * a + s * s
        m1 = (c - a) * (c + a)  # 1 - m without the cancellation of 1 - (a^2 + s^2)
        self._m, self._m1 = m, m1
        if m1 > 0.0:
            self.regime = "libration"
        elif m1 < 0.0:
            self.regime = "circulation"
        else:
            self.regime = "separatrix"
        from ._elliptic import ellipk, ellipkinc

        if self.regime == "circulation":
            k = math.sqrt(m)
            self._k = k
            self._u0 = float(ellipkinc(0.5 * psi0, 1.0 / m, m1=-m1 / m))
            self.period = 2.0 * float(ellipk(1.0 / m, m1=-m1 / m)) / (k * w)
            return
        # libration and separatrix: sin(psi/2) = k sn(u), reduce psi0 to (-pi, pi]
        j = round(psi0 / _TWO_PI)
        self._turns = j * _TWO_PI
        psi0 = psi0 - self._turns
        k = math.sqrt(m)
        self._k = k
        s = math.sin(0.5 * psi0)
        if k == 0.0:
            self._u0 = 0.0
        else:  # sn(u0) = s / k, cn(u0) >= 0 (psi' >= 0)
            x = min(max(s / k, -1.0), 1.0)
            self._u0 = float(ellipkinc(math.asin(x), m, m1=max(m1, 0.0)))
        self.period = 4.0 * float(ellipk(m, m1=m1)) / w if self.regime == "libration" else math.inf

    def __repr__(self) -> str:
        return (
            f"PitchLibration(inertia={self.inertia.tolist()}, mean_motion={self.mean_motion:.6g}, "
            f"theta0={self.theta0:.6g}, rate0={self.rate0:.6g})"
        )

    @property
    def modulus(self) -> float:
        """``k`` with ``k^2 = phi'(0)^2 / (4 w0^2) + sin^2(phi(0) / 2)``: < 1 libration."""
        return math.sqrt(self._m)

    def _psi(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        from ._elliptic import ellipj

        w = self.omega0
        if self.regime == "uniform":
            return self._psi0 + self._dpsi0 * t, np.full_like(t, self._dpsi0)
        if self.regime == "circulation":
            m = 1.0 / self._m
            _, _, dn, am = ellipj(self._k * w * t + self._u0, m, m1=-self._m1 * m)
            return np.asarray(2.0 * am), np.asarray(2.0 * self._k * w * dn)
        sn, cn, dn, _ = ellipj(w * t + self._u0, self._m, m1=max(self._m1, 0.0))
        psi = 2.0 * np.arctan2(self._k * sn, dn) + self._turns
        return np.asarray(psi), np.asarray(2.0 * self._k * w * cn)

    def theta(self, t: ArrayLike) -> FloatArray:
        """The pitch angle ``theta(t)`` (rad), continuous, shape of ``t``."""
        tt = as_float_array(t, "t")
        psi, _ = self._psi(tt)
        out: FloatArray = 0.5 * (self._sign * np.asarray(psi) + self._offset)
        return out

    def rate(self, t: ArrayLike) -> FloatArray:
        """The pitch rate ``theta'(t)`` (rad/s) relative to the orbit frame."""
        tt = as_float_array(t, "t")
        _, dpsi = self._psi(tt)
        out: FloatArray = 0.5 * self._sign * np.asarray(dpsi)
        return out


@dataclass(frozen=True)
class GravityGradientStability:
    """Linear stability of the orbit-frame-aligned attitude (theory §10.2).

    Attributes
    ----------
    k1, k2, k3 : ndarray
        ``k1 = (I2 - I3) / I1``, ``k2 = (I1 - I3) / I2 = (k1 - k3) / (1 - k1 k3)``,
        ``k3 = (I2 - I1) / I3`` (roll 1 along-track, pitch 2 orbit normal, yaw 3
        radial).
    pitch_stable : ndarray of bool
        ``k2 > 0`` (``I1 > I3``), i.e. ``k1 > k3``.
    roll_yaw_stable : ndarray of bool
        ``k1 k3 > 0`` and ``1 + 3 k1 + k1 k3 > 4 sqrt(k1 k3)``.
    region : ndarray of str
        Where every axis is linearly stable: ``"lagrange"`` (``k1 > k3 > 0``, the
        aligned attitude a minimum of the potential) or ``"debra-delp"``
        (``0 > k1 > k3`` with the roll-yaw condition: stable by gyroscopic coupling,
        not a minimum); ``"unstable"`` otherwise (boundaries, where motions are
        marginal, included).
    """

    k1: Any
    k2: Any
    k3: Any
    pitch_stable: Any
    roll_yaw_stable: Any
    region: Any


def gravity_gradient_stability(
    inertia: ArrayLike | None = None, *, k1: ArrayLike | None = None, k3: ArrayLike | None = None
) -> GravityGradientStability:
    """Which stability region the orbit-frame-aligned equilibrium lies in (theory §10.2).

    Linearised in a circular orbit (see :func:`linearized_gravity_gradient`), pitch
    decouples, ``theta'' + 3 n^2 k2 theta = 0``, and roll-yaw has the characteristic
    polynomial ``s^4 + n^2 (1 + 3 k1 + k1 k3) s^2 + 4 n^4 k1 k3``. Pitch is stable
    iff ``k1 > k3`` (``k2 > 0``); roll-yaw iff ``k1 k3 > 0`` and
    ``1 + 3 k1 + k1 k3 > 4 sqrt(k1 k3)``. Both hold in the Lagrange region
    ``k1 > k3 > 0`` (``I2 > I1 > I3``) and in the small DeBra-Delp region
    ``0 > k1 > k3`` beyond the roll-yaw curve (stable by gyroscopic coupling: the
    aligned attitude is not a minimum of the potential there).

    Parameters
    ----------
    inertia : array_like, shape (..., 3), optional
        Principal moments ``(I1, I2, I3)`` (roll along-track, pitch along the orbit
        normal, yaw radial), kg m^2.
    k1, k3 : array_like, shape (...), optional
        The inertia ratios, ``|k| <= 1``, instead of ``inertia`` (give both).

    Returns
    -------
    GravityGradientStability

    Notes
    -----
    **Convention:** body axes ``1, 2, 3`` along the ``"lvlh"`` axes ``x, y, z`` at the
    equilibrium (Hughes, *Spacecraft Attitude Dynamics*, 1986, §9.2; Wie, *Space
    Vehicle Dynamics and Control*, §6.3); see ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> from poinsot.dynamics import gravity_gradient_stability
    >>> str(gravity_gradient_stability([3.0, 4.0, 2.0]).region)    # I2 > I1 > I3
    'lagrange'
    >>> str(gravity_gradient_stability(k1=-0.05, k3=-0.95).region)
    'debra-delp'
    """
    if inertia is not None:
        if k1 is not None or k3 is not None:
            raise InvalidInputError("Expected either `inertia` or (`k1`, `k3`), got both.")
        j = _principal(inertia)
        i1, i2, i3 = j[..., 0], j[..., 1], j[..., 2]
        a1, a2, a3 = (i2 - i3) / i1, (i1 - i3) / i2, (i2 - i1) / i3
    else:
        if k1 is None or k3 is None:
            raise InvalidInputError("Expected `inertia`, or both `k1` and `k3`.")
        a1, a3 = as_float_array(k1, "k1"), as_float_array(k3, "k3")
        for name, val in (("k1", a1), ("k3", a3)):
            if np.any(np.abs(val) > 1.0):
                raise InvalidInputError(
                    f"Expected `{name}` in [-1, 1] (a physical inertia), got "
                    f"{float(val[np.abs(val) > 1].ravel()[0])!r}."
                )
        a1, a3 = np.broadcast_arrays(a1, a3)
        with np.errstate(divide="ignore", invalid="ignore"):  # k1 = k3 = +-1: no body
            a2 = (a1 - a3) / (1.0 - a1 * a3)
    pitch = a1 > a3
    p = a1 * a3
    roll_yaw = (p > 0) & (1.0 + 3.0 * a1 + p > 4.0 * np.sqrt(np.maximum(p, 0.0)))
    region = np.where(
        pitch & roll_yaw & (a3 > 0),
        "lagrange",
        np.where(pitch & roll_yaw & (a1 < 0), "debra-delp", "unstable"),
    )
    return GravityGradientStability(a1, a2, a3, pitch, roll_yaw, region)


def linearized_gravity_gradient(inertia: ArrayLike, mean_motion: float) -> FloatArray:
    """State matrix ``A`` (..., 6, 6) of the linearised attitude about the
    orbit-frame-aligned equilibrium in a circular orbit (theory §10.2).

    State ``x = (phi, theta, psi, phi', theta', psi')`` (roll, pitch, yaw angles of
    ``R_ob`` and their rates, rad and rad/s), ``x' = A x``:

    ``phi'' = -4 n^2 k1 phi + n (1 - k1) psi'``,
    ``theta'' = -3 n^2 k2 theta``,
    ``psi'' = -n^2 k3 psi - n (1 - k3) phi'``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3)
        Principal moments ``(I1, I2, I3)``: roll (along-track), pitch (``-h``), yaw
        (nadir), kg m^2.
    mean_motion : float
        ``n`` (rad/s), > 0.

    Notes
    -----
    **Convention:** axes as in :func:`gravity_gradient_stability`; see
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import linearized_gravity_gradient
    >>> a = linearized_gravity_gradient([2.0, 3.0, 1.0], 1.0)
    >>> float(np.sqrt(-a[4, 1]))        # the pitch rate sqrt(3 k2) n, k2 = 1/3
    1.0
    """
    j = _principal(inertia)
    n = _scalar(as_positive(mean_motion, "mean_motion"), "mean_motion", "rad/s")
    i1, i2, i3 = j[..., 0], j[..., 1], j[..., 2]
    k1, k2, k3 = (i2 - i3) / i1, (i1 - i3) / i2, (i2 - i1) / i3
    a = np.zeros(j.shape[:-1] + (6, 6))
    a[..., 0, 3] = a[..., 1, 4] = a[..., 2, 5] = 1.0
    a[..., 3, 0] = -4.0 * n * n * k1
    a[..., 3, 5] = n * (1.0 - k1)
    a[..., 4, 1] = -3.0 * n * n * k2
    a[..., 5, 2] = -n * n * k3
    a[..., 5, 3] = -n * (1.0 - k3)
    return a
