"""The rotating Earth: the local frame, free fall and the Foucault pendulum (theory §9).

:func:`earth_frame` is the local east-north-up frame on the rotating Earth (a
:class:`~poinsot.kinematics.FrameMotion` for :func:`~poinsot.dynamics.simulate_particle`),
with :func:`normal_gravity` and the closed forms :func:`eastward_deflection` (free
fall), :func:`foucault_precession_rate` and :func:`foucault_period` beside it;
:func:`foucault_pendulum` integrates the linearised Foucault pendulum and
:func:`swing_plane_angles` measures its swing plane. The particle dynamics they rest
on is :mod:`poinsot.dynamics.particles`.

**Convention:** as in :mod:`poinsot.dynamics.particles`: vectors in the moving
frame's own axes (x east, y north, z up); positions in m, velocities in m/s, forces
in N, masses in kg, angles in rad (or degrees with ``degrees=True``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_choice, as_float_array, as_times
from .._vec import dot
from ..errors import InvalidInputError
from ..kinematics.fields import FrameMotion
from .particles import ParticleTrajectory, simulate_particle
from .torques import STANDARD_GRAVITY

# in the order of the file
__all__ = [
    "EARTH_ROTATION_RATE",
    "earth_frame",
    "normal_gravity",
    "eastward_deflection",
    "foucault_precession_rate",
    "foucault_period",
    "UniformGravity",
    "PendulumForce",
    "foucault_frame",
    "foucault_pendulum",
    "swing_plane_angles",
]


def _as_latitude(latitude: ArrayLike, degrees: object) -> np.ndarray:
    degrees = as_bool(degrees, "degrees")
    lat = as_float_array(latitude, "latitude")
    if degrees:
        lat = np.deg2rad(lat)
    if np.any(np.abs(lat) > np.pi / 2 * (1 + 1e-15)):
        unit = "deg" if degrees else "rad"
        bad = float(np.asarray(latitude, dtype=float)[np.abs(lat) > np.pi / 2].ravel()[0])
        raise InvalidInputError(
            f"Expected `latitude` within [-90, 90] deg (|latitude| <= pi/2 rad), "
            f"got {bad!r} {unit}."
        )
    return np.clip(lat, -np.pi / 2, np.pi / 2)


def _real(x: ArrayLike, name: str) -> np.ndarray:
    return as_float_array(x, name)


# ---------------------------------------------------------------------------
# The rotating Earth
# ---------------------------------------------------------------------------

#: Rotation rate of the Earth relative to the stars (rad/s), IERS nominal value
#: (one sidereal day of 86164.0989 s).
EARTH_ROTATION_RATE = 7.2921159e-5


def earth_frame(
    latitude: ArrayLike, omega: float = EARTH_ROTATION_RATE, *, degrees: bool = False
) -> FrameMotion:
    """Local east-north-up frame on the rotating Earth (theory §9).

    Axes ``x`` east, ``y`` north, ``z`` up (along the plumb line); the frame
    turns with the Earth at ``w = Omega (0, cos(latitude), sin(latitude))``
    (frame axes), with ``eps = 0`` and ``W0 = 0``.

    The acceleration of the origin (a point of the ground, ``-Omega^2`` times
    its distance from the axis) is *not* put into ``W0``: it is absorbed, with
    the gravitational attraction, into the effective gravity
    ``g = g_grav - Omega x (Omega x R)`` that a plumb line shows and that
    defines "up". Give the force as ``m g (0, 0, -1)`` with that ``g``
    (e.g. :func:`normal_gravity`, or 9.80665 m/s^2); the remaining centrifugal
    term ``-m w x (w x r)`` is then only the tiny correction for the distance
    ``r`` from the origin (the change of ``g`` with height is neglected).

    Parameters
    ----------
    latitude : float
        Geodetic (plumb-line) latitude, positive north (rad, or deg with
        ``degrees=True``).
    omega : float, optional
        Rotation rate ``Omega`` (rad/s), default :data:`EARTH_ROTATION_RATE`.
    degrees : bool, optional
        Latitude in degrees.

    Returns
    -------
    FrameMotion
        ``omega = Omega (0, cos(lat), sin(lat))``, zero ``W0``, ``V0`` and ``eps``.

    Examples
    --------
    >>> from poinsot.dynamics import earth_frame
    >>> (earth_frame(90, degrees=True).omega * 1e5).round(5) + 0.0
    array([0.     , 0.     , 7.29212])
    """
    lat = _as_latitude(latitude, degrees)
    om = _real(omega, "omega")
    if lat.ndim or om.ndim:
        raise InvalidInputError(
            f"Expected `latitude` and `omega` to be scalars, got shapes {lat.shape} and {om.shape}."
        )
    return FrameMotion(omega=float(om) * np.array([0.0, math.cos(lat), math.sin(lat)]))


def normal_gravity(latitude: ArrayLike, *, degrees: bool = False) -> FloatArray:
    """Effective gravity on the WGS 84 ellipsoid (Somigliana's formula), m/s^2.

    ``g = g_e (1 + k sin^2 lat) / sqrt(1 - e^2 sin^2 lat)`` with
    ``g_e = 9.7803253359``, ``k = 0.00193185265241``, ``e^2 = 0.00669437999013``
    (NIMA TR8350.2, 2000): attraction plus centrifugal, at sea level.

    >>> from poinsot.dynamics import normal_gravity
    >>> float(normal_gravity(0.0)), round(float(normal_gravity(90, degrees=True)), 9)
    (9.7803253359, 9.832184938)
    """
    lat = _as_latitude(latitude, degrees)
    s2 = np.sin(lat) ** 2
    return 9.7803253359 * (1.0 + 0.00193185265241 * s2) / np.sqrt(1.0 - 0.00669437999013 * s2)


def eastward_deflection(
    height: ArrayLike,
    latitude: ArrayLike,
    g: float = STANDARD_GRAVITY,
    omega: float = EARTH_ROTATION_RATE,
    *,
    degrees: bool = False,
) -> FloatArray:
    """Eastward deflection of a body dropped from rest (first order in ``Omega``).

    ``d = (1/3) Omega g t^3 cos(lat)`` with ``t = sqrt(2 h / g)`` the fall time,
    i.e. ``d = (1/3) Omega cos(lat) sqrt(8 h^3 / g)`` (theory §9: the Coriolis
    force ``-2 m w x v`` on the falling body). The neglected terms are of
    relative order ``(Omega t)^2``; air resistance is ignored.

    Parameters
    ----------
    height : array_like
        Drop height ``h`` (m, >= 0).
    latitude : array_like
        Latitude (rad, or deg with ``degrees=True``).
    g : array_like, optional
        Effective gravity (m/s^2, > 0), default 9.80665.
    omega : array_like, optional
        Rotation rate (rad/s), default :data:`EARTH_ROTATION_RATE`.

    Returns
    -------
    ndarray
        Deflection to the east (m); negative for ``omega < 0``.

    Examples
    --------
    Reich's 158 m mine shaft at Freiberg (50.9 deg N):

    >>> from poinsot.dynamics import eastward_deflection
    >>> round(float(eastward_deflection(158.0, 50.9, degrees=True)) * 1000, 1)
    27.5
    """
    h = as_float_array(height, "height")
    if np.any(h < 0):
        raise InvalidInputError(f"Expected `height` to be >= 0 (m), got {float(h.min())!r}.")
    gg = as_float_array(g, "g")
    if np.any(gg <= 0):
        raise InvalidInputError(f"Expected `g` to be positive (m/s^2), got {float(gg.min())!r}.")
    lat = _as_latitude(latitude, degrees)
    om = _real(omega, "omega")
    return om * np.cos(lat) * np.sqrt(8.0 * h**3 / gg) / 3.0


def foucault_precession_rate(
    latitude: ArrayLike, omega: float = EARTH_ROTATION_RATE, *, degrees: bool = False
) -> FloatArray | float:
    """Turning rate of a Foucault pendulum's swing plane, ``-Omega sin(lat)`` (rad/s).

    Positive counter-clockwise seen from above (about the local up axis): the
    plane turns clockwise in the northern hemisphere. Linearised (small
    swings) and to first order in ``Omega`` (theory §9).

    >>> from poinsot.dynamics import foucault_precession_rate
    >>> round(float(foucault_precession_rate(30, degrees=True)) * 1e5, 6)
    -3.646058
    """
    lat = _as_latitude(latitude, degrees)
    return -_real(omega, "omega") * np.sin(lat)


def foucault_period(
    latitude: ArrayLike, omega: float = EARTH_ROTATION_RATE, *, degrees: bool = False
) -> FloatArray | float:
    """Time for a Foucault pendulum's plane to turn a full circle: ``2 pi / (Omega |sin lat|)``.

    In s; ``inf`` at the equator. At the pole it is one sidereal day
    (86164.1 s); at Paris (48.85 deg N) about 31.8 h.

    >>> from poinsot.dynamics import foucault_period
    >>> round(float(foucault_period(48.85, degrees=True)) / 3600, 1)
    31.8
    """
    rate = np.abs(foucault_precession_rate(latitude, omega, degrees=degrees))
    with np.errstate(divide="ignore"):
        return np.where(rate > 0, 2.0 * np.pi / np.where(rate > 0, rate, 1.0), np.inf)


@dataclass(frozen=True)
class UniformGravity:
    """Weight ``F = (0, 0, -m g)`` in an east-north-up frame, potential ``U = m g z``.

    A force callable ``force(t, r, v)`` for :func:`simulate_particle`, with its
    potential energy (J) for :func:`jacobi_integral`.

    >>> from poinsot.dynamics import UniformGravity
    >>> w = UniformGravity(mass=2.0, g=9.81)
    >>> w(0.0, [0, 0, 5.0], [0, 0, 0]).tolist(), round(float(w.potential([0, 0, 5.0])), 9)
    ([0.0, 0.0, -19.62], 98.1)
    """

    mass: float = 1.0
    g: float = STANDARD_GRAVITY

    def __call__(self, _t: float, _r: np.ndarray, _v: np.ndarray) -> np.ndarray:
        return np.array([0.0, 0.0, -self.mass * self.g])

    def potential(self, r: np.ndarray) -> np.ndarray:
        """``m g z`` (J)."""
        return self.mass * self.g * np.asarray(r, dtype=float)[..., 2]


@dataclass(frozen=True)
class PendulumForce:
    """The linearised pendulum's restoring force ``F = -m (g/l) (x, y, 0)``.

    Horizontal, towards the point below the suspension; potential
    ``U = m g (x^2 + y^2) / (2 l)`` (J).

    >>> from poinsot.dynamics import PendulumForce
    >>> f = PendulumForce(mass=1.0, g=9.8, length=9.8)
    >>> f(0.0, [0.5, 0, 0], [0, 0, 0]).tolist(), float(f.potential([0.5, 0, 0]))
    ([-0.5, -0.0, 0.0], 0.125)
    """

    mass: float = 1.0
    g: float = STANDARD_GRAVITY
    length: float = 1.0

    def __call__(self, _t: float, r: np.ndarray, _v: np.ndarray) -> np.ndarray:
        k = self.mass * self.g / self.length
        return np.array([-k * r[0], -k * r[1], 0.0])

    def potential(self, r: np.ndarray) -> np.ndarray:
        """``m g (x^2 + y^2) / (2 l)`` (J)."""
        r = np.asarray(r, dtype=float)
        return 0.5 * self.mass * self.g / self.length * (r[..., 0] ** 2 + r[..., 1] ** 2)


def foucault_frame(
    latitude: ArrayLike, omega: float = EARTH_ROTATION_RATE, *, degrees: bool = False
) -> FrameMotion:
    """The frame of the linearised Foucault pendulum: east-north-up turning at the
    vertical component ``Omega sin(lat)`` of the Earth's rotation only.

    >>> from poinsot.dynamics import foucault_frame
    >>> foucault_frame(30, 2.0, degrees=True).omega.round(12) + 0.0
    array([0., 0., 1.])
    """
    lat = _as_latitude(latitude, degrees)
    om = float(_real(omega, "omega"))
    return FrameMotion(omega=[0.0, 0.0, om * math.sin(float(lat))])


def foucault_pendulum(
    length: float,
    latitude: float,
    t: ArrayLike,
    *,
    amplitude: float = 1.0,
    g: float = STANDARD_GRAVITY,
    omega: float = EARTH_ROTATION_RATE,
    mass: float = 1.0,
    degrees: bool = False,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_step: float = math.inf,
    inertial: bool = False,
    model: str = "full",
) -> ParticleTrajectory:
    """The linearised Foucault pendulum, integrated in the Earth's frame (theory §9).

    The bob moves in the horizontal plane under ``F = -m (g / l) (x, y, 0)``
    in the east-north-up frame turning at the vertical component
    ``Omega_z = Omega sin(lat)`` of the Earth's rotation (the horizontal
    component's Coriolis force is vertical, taken up by the wire in the linear
    theory). It is released at rest relative to the Earth at
    ``(amplitude, 0, 0)`` (east).

    Two models (``model=``), in ``w = x + i y``:

    - ``"full"`` (default): every inertial force of the turning frame, the
      centrifugal ``m Omega_z^2 (x, y)`` included:
      ``w'' + 2 i Omega_z w' + (omega0^2 - Omega_z^2) w = 0``, solved by
      ``w = e^{-i Omega_z t} (A e^{i omega0 t} + B e^{-i omega0 t})``;
    - ``"textbook"``: the classical linearisation, which drops the centrifugal
      term: ``w'' + 2 i Omega_z w' + omega0^2 w = 0``, solved by
      ``w = e^{-i Omega_z t} (A e^{i w1 t} + B e^{-i w1 t})`` with
      ``w1 = sqrt(omega0^2 + Omega_z^2)``.

    Both turn the swing plane at ``-Omega_z``; they differ in the swing
    frequency by ``w1 - omega0 ~ Omega_z^2 / (2 omega0)``, a relative
    ``(Omega_z / omega0)^2 / 2``: about 1e-8 for a pendulum on the Earth,
    but a phase difference of 5e-3 rad per swing at ``Omega_z / omega0 = 0.05``.

    Parameters
    ----------
    length : float
        Wire length ``l`` (m, > 0).
    latitude : float
        Latitude (rad, or deg with ``degrees=True``).
    t : array_like, shape (n,)
        Output times (s).
    amplitude : float, optional
        Initial displacement (m), default 1.
    g, omega, mass : float, optional
        Gravity (m/s^2), rotation rate (rad/s), bob mass (kg).
    rtol, atol, max_step, inertial : optional
        As in :func:`simulate_particle`.
    model : {"full", "textbook"}, optional
        Keep the centrifugal force of the turning frame (``"full"``, default) or
        drop it as the textbook linearisation does (``"textbook"``).

    Returns
    -------
    ParticleTrajectory
        Positions east/north/up of the bob (``z = 0``); the swing plane turns
        at :func:`foucault_precession_rate` (see :func:`swing_plane_angles`).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import foucault_pendulum
    >>> tr = foucault_pendulum(67.0, 48.85, np.linspace(0, 60, 7), degrees=True)
    >>> tr.position.shape
    (7, 3)
    """
    lat = _as_latitude(latitude, degrees)
    ell = as_float_array(length, "length")
    if ell.ndim or ell <= 0:
        raise InvalidInputError(f"Expected `length` to be a positive scalar (m), got {length!r}.")
    gg = as_float_array(g, "g")
    if gg.ndim or gg <= 0:
        raise InvalidInputError(f"Expected `g` to be a positive scalar (m/s^2), got {g!r}.")
    a = as_float_array(amplitude, "amplitude")
    if a.ndim:
        raise InvalidInputError(f"Expected `amplitude` to be a scalar (m), got shape {a.shape}.")
    m = float(as_float_array(mass, "mass"))
    model = as_choice(model, "model", ("full", "textbook"))
    frame = foucault_frame(lat, omega)
    g_eff = float(gg)
    if model == "textbook":
        # a restoring force stiffer by m Omega_z^2 cancels the frame's centrifugal force
        g_eff += float(frame.omega[2]) ** 2 * float(ell)
    force = PendulumForce(m, g_eff, float(ell))
    return simulate_particle(
        frame,
        force,
        [float(a), 0.0, 0.0],
        [0.0, 0.0, 0.0],
        t,
        mass=m,
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        inertial=inertial,
    )


def swing_plane_angles(
    t: ArrayLike, position: ArrayLike, velocity: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Azimuth of a pendulum's swing plane at each extreme of the swing.

    At each maximum of the horizontal distance (``r . v`` changing sign from
    + to -, located by linear interpolation) the azimuth
    ``atan2(y, x)`` of the bob, reduced modulo ``pi`` (a plane has no
    direction) and unwrapped. Used to measure the Foucault precession.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (s).
    position, velocity : array_like, shape (n, 3) or (n, 2)
        Horizontal position (m) and velocity (m/s), x east and y north.

    Returns
    -------
    times, angles : ndarray, shape (k,)
        Times of the extremes (s) and the plane's azimuth (rad,
        counter-clockwise from east, continuous).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import swing_plane_angles
    >>> t = np.linspace(0, 10, 2001)
    >>> r = np.stack([np.cos(2 * np.pi * t), 0 * t], -1)
    >>> v = np.stack([-2 * np.pi * np.sin(2 * np.pi * t), 0 * t], -1)
    >>> tt, ang = swing_plane_angles(t, r, v)
    >>> tt[:3].round(3), ang[:3] + 0.0
    (array([0.5, 1. , 1.5]), array([0., 0., 0.]))
    """
    t = as_times(t, "t", min_len=2)
    r = as_float_array(position, "position")[..., :2]
    v = as_float_array(velocity, "velocity")[..., :2]
    if r.shape != (t.size, 2) or v.shape != (t.size, 2):
        raise InvalidInputError(
            f"Expected `position` and `velocity` of shape ({t.size}, 2 or 3), "
            f"got {np.shape(position)} and {np.shape(velocity)}."
        )
    f = dot(r, v)
    k = np.nonzero((f[:-1] > 0) & (f[1:] <= 0) | (f[:-1] < 0) & (f[1:] >= 0))[0]
    # keep maxima of |r| only (the product goes from + to -) and minima skipped
    k = k[f[k] > 0]
    s = f[k] / (f[k] - f[k + 1])
    tt = t[k] + s * (t[k + 1] - t[k])
    p = r[k] + s[:, None] * (r[k + 1] - r[k])
    doubled = np.unwrap(np.arctan2(2.0 * p[:, 0] * p[:, 1], p[:, 0] ** 2 - p[:, 1] ** 2))
    return tt, 0.5 * doubled
