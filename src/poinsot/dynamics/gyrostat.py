"""The gyrostat: a rigid body carrying rotors of constant relative momentum (theory §10.1).

A gyrostat is a rigid body with rotors (wheels) that spin relative to it about axes
fixed in it, without changing its mass distribution. With ``h`` the rotors' angular
momentum relative to the body (body axes) and ``J`` the inertia of the whole system
with the rotors locked, the Euler-Zhukovsky equations (docs/theory.md §10.1) are

    J w' + w x (J w + h) = M - h'.

:func:`gyrostat_rhs` evaluates ``w'``. :class:`FreeGyrostat` is the motion for a
constant ``h`` and no torque: the total angular momentum ``K = R (J w + h)`` is
constant in space and the energy ``T = w . J w / 2`` is conserved.

**Exact solution (h along a principal axis, the dual-spin spacecraft).** Label the
rotor axis 3 (any principal axis is brought there by a cyclic permutation),
``h = h e3``, moments ``I1, I2, I3``, body momentum ``m = J w + h`` and ``z = m3``.
The two integrals give ``m1^2`` and ``m2^2`` as quadratics in ``z``, written about
the initial value ``z0`` (``d = z - z0``)::

    m1^2 = f1(d) = m10^2 + g1 d + a1 d^2,   a1 = I1 (I3 - I2) / (I3 (I2 - I1)),
    m2^2 = f2(d) = m20^2 + g2 d + a2 d^2,   a2 = -1 - a1,
    g1 = 2 I1 ((I3 - I2) r0 + h) / (I2 - I1),  g2 = -2 z0 - g1,

and ``z' = (1/I2 - 1/I1) m1 m2`` makes ``z'^2 = (1/I1 - 1/I2)^2 f1 f2`` a quartic
that is the product of two quadratics: its roots are in closed form. ``z`` moves
between two adjacent real roots ``y1, y2`` (where ``f1 >= 0`` and ``f2 >= 0``):

* four real roots (``y3`` the root next to ``y1`` beyond it, ``y4`` the last): the
  Moebius substitution ``sn^2 u = (y2 - y3)(z - y1) / ((y2 - y1)(z - y3))`` gives
  ``z - y = kappa_y phi_y^2 / D`` for each root ``y``, with ``phi = sn, cn, 1, dn``
  for ``y1, y2, y3, y4``, ``D = (y1 - y3) + (y2 - y1) cn^2``, so ``m1, m2`` are
  ``+- sqrt(a kappa kappa') phi phi' / D`` (signs carried by the functions);
  ``k^2 = (y2 - y1)(y4 - y3) / ((y2 - y3)(y4 - y1))``,
  ``lam^2 = -L (y1 - y4)(y2 - y3) / 4`` with ``L = (1/I1 - 1/I2)^2 a1 a2``;
* two real roots (the other quadratic positive definite, complex roots ``zeta``):
  ``cn u = ((y2 - z) B - (z - y1) A) / ((y2 - z) B + (z - y1) A)``,
  ``A = |y2 - zeta|``, ``B = |y1 - zeta|``, ``k^2 = ((y2 - y1)^2 - (A - B)^2) / (4 A B)``,
  ``lam^2 = -L A B``; the real-root momentum is ``~ sn / D``, the other ``~ dn / D``.

with ``u = lam t + u0`` (Byrd & Friedman 1971, 257-259; the case analysis of
Cochran, Shu & Rew 1982 and Wittenburg, *Dynamics of Multibody Systems*, ch. 4).
A double root at an end of the interval is a separatrix (``k = 1``, infinite
period); a double root at ``z0`` a permanent rotation. **Next to a separatrix**
``1 - k^2`` is a small difference of roots: of a near-double root of one quadratic
(whose discriminant can be ``~ (1 - k^2)^2``, beyond double-double) or of near-common
roots of the two.
The quadratics (from the exact double inputs), their roots and every difference of
roots are therefore formed in exact rational arithmetic (square roots to 2^-128) and
rounded once, and ``u0 = F(phi0 | k^2)`` is evaluated from ``sn^2 u0, cn u0`` by
Carlson's ``R_F`` rather than through ``phi0`` (steep near ``pi/2``): omega to ~1e-14
relative at ``1 - k^2 = 1e-12`` (tests/dynamics/test_gyrostat.py).

``I1 = I2`` (the rotor along the symmetry axis): ``r`` is constant and ``(p + i q)`` turns at
``((I3 - I1) r + h) / I1``.

**Attitude.** As for the free body, ``R(t) = S Rz(psi) Rx(theta) Rz(phi) P`` with
``(theta, phi)`` the z-x-z angles of the body momentum ``m`` about the body axis
``P^T e_z`` farthest from ``m`` over the motion, ``S`` fixed by ``R(0)``, and the
precession angle about ``K``, ``psi' = |K| (w_x m_x + w_y m_y) / (m_x^2 + m_y^2)``,
integrated **numerically** (Gauss-Legendre, 20 nodes on panels of at most 1/32 of
a period and ``0.5 / lam``, about 1e-15 relative per period) over one period and
continued by quasi-periodicity (``R(t + P) = Rot(K, Delta psi) R(t)``).

**Numeric fallback.** ``h`` not along a principal axis, a non-diagonal inertia
tensor, or a rotor on the equatorial axis of a body whose symmetry axis is another
(``I3 = I1`` or ``I3 = I2`` exactly, where the quartic degenerates to a cubic):
``scipy.integrate.solve_ivp`` (``DOP853``, ``rtol = 1e-12``, ``atol = 1e-14`` in
units of ``|w0|`` and of the quaternion) on ``(w, q)``; ``regime == "numeric"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_rotation_quat, as_vec3, batch_shape
from .._vec import cross, inverse3
from ..errors import InvalidInputError, InvalidTypeError
from ..kinematics.rates import _quat_rate
from ..mass import RigidBody
from ..mass.tensor import _kinetic, _momentum, as_inertia
from ..rotations import quaternion as _quaternion
from ..rotations.euler import quat_from_euler
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory
from .integrators._common import _rhs
from .torques import GyrostaticTorque

__all__ = ["gyrostat_rhs", "gyrostat_spin_stable", "FreeGyrostat", "GYROSTAT_REGIMES"]

#: The regimes of :attr:`FreeGyrostat.regime`: ``"four_roots"`` / ``"two_roots"`` (the
#: quartic ``z'^2`` has four or two real roots; Jacobi functions), ``"separatrix"``
#: (a double root at an end of the motion: asymptotic motion, infinite period),
#: ``"axisymmetric"`` (rotor along the symmetry axis, ``I1 = I2``), ``"permanent"``
#: (a permanent rotation: ``w`` constant), ``"rest"``, ``"numeric"`` (the DOP853
#: fallback of the module notes).
GYROSTAT_REGIMES = (
    "four_roots",
    "two_roots",
    "separatrix",
    "axisymmetric",
    "permanent",
    "rest",
    "numeric",
)

#: Numeric fallback: solve_ivp DOP853 relative tolerance (absolute: 1e-2 of it, scaled).
FALLBACK_RTOL = 1e-12

_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])
# Gauss-Legendre nodes and weights on [0, 1] for the precession quadrature
_GL_X, _GL_W = np.polynomial.legendre.leggauss(20)
_GL_X = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W
_PANELS = 32  # panels per period of omega


# ---------------------------------------------------------------------------
# Right-hand side (kernel and public wrapper)
# ---------------------------------------------------------------------------


def _gyro_rhs(
    j: np.ndarray,
    j_inv: Any,
    w: np.ndarray,
    h: np.ndarray,
    torque: np.ndarray | None,
    h_rate: np.ndarray | None,
    principal: bool,
) -> np.ndarray:
    """``w' = J^-1 (M - h' - w x (J w + h))`` (no validation): Euler's right-hand side
    (:func:`poinsot.dynamics.integrators._common._rhs`) with the rotor terms as a torque."""
    extra = -cross(w, h)
    if torque is not None:
        extra = extra + torque
    if h_rate is not None:
        extra = extra - h_rate
    return _rhs(j, j_inv, w, extra, principal)


def gyrostat_rhs(
    inertia: ArrayLike,
    omega: ArrayLike,
    h: ArrayLike,
    torque: ArrayLike | None = None,
    *,
    h_rate: ArrayLike | None = None,
) -> FloatArray:
    """Angular acceleration of a gyrostat from the Euler-Zhukovsky equations.

    ``J w' + w x (J w + h) = M - h'``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3)
        Principal moments (``omega`` and ``h`` then in principal axes) or the inertia
        tensor in body axes of the whole gyrostat, rotors included (kg m^2), as in
        :func:`poinsot.dynamics.euler_rhs`.
    omega : array_like, shape (..., 3)
        Angular velocity of the carrier body in body axes (rad/s).
    h : array_like, shape (..., 3)
        Angular momentum of the rotors relative to the body, in body axes (kg m^2/s).
    torque : array_like, shape (..., 3), optional
        External torque in body axes (N m). Default zero.
    h_rate : array_like, shape (..., 3), optional
        ``h'``, the rate of the rotors' relative momentum in body axes (N m; the
        negative of the torque the motors exert on the body). Default zero.

    Returns
    -------
    ndarray, shape (..., 3)
        ``w'`` in body axes (rad/s^2); leading shapes broadcast.

    Raises
    ------
    InvalidInputError
        For a non-physical inertia, a wrong shape or a non-finite value (the message
        names the argument).

    Notes
    -----
    docs/theory.md §10.1: the body-frame derivative of the total
    angular momentum ``K = J w + h`` is ``K' + w x K = M``. With ``h = 0`` this is
    :func:`~poinsot.dynamics.euler_rhs`.

    **Convention:** body axes throughout; SI units (kg m^2, rad/s, kg m^2/s, N m).

    Examples
    --------
    >>> from poinsot.dynamics import gyrostat_rhs
    >>> gyrostat_rhs([1.0, 2.0, 3.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0]) + 0.0  # -(w x h) / J
    array([0., 1., 0.])
    """
    j, principal = as_inertia(inertia, "inertia")
    w = as_vec3(omega, "omega")
    hv = as_vec3(h, "h")
    m = None if torque is None else as_vec3(torque, "torque")
    hd = None if h_rate is None else as_vec3(h_rate, "h_rate")
    shapes: dict[str, tuple[Any, int]] = {
        "inertia": (j, 1 if principal else 2),
        "omega": (w, 1),
        "h": (hv, 1),
    }
    if m is not None:
        shapes["torque"] = (m, 1)
    if hd is not None:
        shapes["h_rate"] = (hd, 1)
    batch_shape(**shapes)
    return _gyro_rhs(j, None if principal else inverse3(j), w, hv, m, hd, principal)


def gyrostat_spin_stable(inertia: ArrayLike, h: ArrayLike, omega: ArrayLike) -> Any:
    """Linear stability of a permanent rotation of a free gyrostat about its rotor axis.

    Parameters
    ----------
    inertia : array_like, shape (..., 3)
        Principal moments ``(I1, I2, I3)`` (kg m^2).
    h : array_like, shape (..., 3)
        Rotor momentum relative to the body (principal axes, kg m^2/s), along one
        principal axis (or zero).
    omega : array_like, shape (..., 3)
        The spin: an angular velocity along the same principal axis (rad/s).

    Returns
    -------
    bool or ndarray of bool
        True where the linearised equations have purely imaginary eigenvalues
        (``(m3 - I1 W)(m3 - I2 W) > 0``; Lyapunov stable, the two integrals then
        bounding the motion), False where one is real and positive or at the
        boundary.

    Raises
    ------
    InvalidInputError
        If ``h`` or ``omega`` is not along one principal axis, or they are along
        different axes, or for a bad shape or value.

    Notes
    -----
    docs/theory.md §10.1. For a spin ``W`` about axis 3 with
    ``h = h e3`` (``m3 = I3 W + h``), small ``p, q`` obey
    ``I1 p' = -(m3 - I2 W) q``, ``I2 q' = (m3 - I1 W) p``: stable iff
    ``(m3 - I1 W)(m3 - I2 W) > 0``, i.e. the effective moment ``I3 + h / W`` is the
    largest or the smallest. With ``h = 0`` the major and minor axes are stable, the
    intermediate one not; a large enough ``h`` along it (``|h| > (I_max - I2) |W|``
    or ``> (I2 - I_min) |W|`` with the right sign) stabilises it (dual spin).

    **Convention:** principal body axes, SI units.

    Examples
    --------
    >>> from poinsot.dynamics import gyrostat_spin_stable
    >>> gyrostat_spin_stable([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    False
    >>> gyrostat_spin_stable([1.0, 2.0, 3.0], [0.0, 1.5, 0.0], [0.0, 1.0, 0.0])
    True
    """
    mom, principal = as_inertia(inertia, "inertia")
    if not principal:
        raise InvalidInputError(
            f"Expected `inertia` to be principal moments of shape (..., 3), got {mom.shape}."
        )
    hv = as_vec3(h, "h")
    w = as_vec3(omega, "omega")
    shape = batch_shape(inertia=(mom, 1), h=(hv, 1), omega=(w, 1))
    mom, hv, w = (np.broadcast_to(x, shape + (3,)) for x in (mom, hv, w))
    nz_w = w != 0.0
    nz_h = hv != 0.0
    if np.any(np.sum(nz_w, axis=-1) > 1):
        raise InvalidInputError(
            "Expected `omega` to be along one principal axis (one non-zero component)."
        )
    if np.any(np.sum(nz_h, axis=-1) > 1):
        raise InvalidInputError(
            "Expected `h` to be along one principal axis (one non-zero component)."
        )
    both = np.any(nz_w, -1) & np.any(nz_h, -1)
    if np.any(both & (np.argmax(nz_w, -1) != np.argmax(nz_h, -1))):
        raise InvalidInputError(
            "Expected `h` and `omega` to be along the same principal axis, got different ones."
        )
    ax = np.where(np.any(nz_w, -1), np.argmax(nz_w, -1), np.argmax(nz_h, -1))
    spin = np.take_along_axis(w, ax[..., None], -1)[..., 0]
    hs = np.take_along_axis(hv, ax[..., None], -1)[..., 0]
    i3 = np.take_along_axis(mom, ax[..., None], -1)[..., 0]
    i1 = np.take_along_axis(mom, ((ax + 1) % 3)[..., None], -1)[..., 0]
    i2 = np.take_along_axis(mom, ((ax + 2) % 3)[..., None], -1)[..., 0]
    m3 = i3 * spin + hs
    stable = (m3 - i1 * spin) * (m3 - i2 * spin) > 0.0
    return bool(stable) if shape == () else stable


# ---------------------------------------------------------------------------
# Closed form: one body with the rotor along internal axis 3
# ---------------------------------------------------------------------------


def _fsqrt(x: Fraction, bits: int = 128) -> Fraction:
    """``sqrt(x)`` of an exact ``x >= 0`` to a relative ``2^-bits`` (integer square root)."""
    if x <= 0:
        return Fraction(0)
    n, d = x.numerator, x.denominator
    shift = max(0, 2 * bits + 2 - (n.bit_length() - d.bit_length()))
    shift += shift & 1
    return Fraction(math.isqrt((n << shift) // d), 1 << (shift // 2))


def _roots(
    c0: Fraction, c1: Fraction, c2: Fraction
) -> tuple[list[Fraction], tuple[Fraction, Fraction] | None]:
    """Roots of ``c0 + c1 d + c2 d^2`` (``c2 != 0``, exact coefficients): the real ones
    (stable formula, square root to 2^-128) or ``([], (re, im^2))`` of the complex pair."""
    disc = c1 * c1 - 4 * c2 * c0
    if disc < 0:
        return [], (-c1 / (2 * c2), -disc / (4 * c2 * c2))
    sq = _fsqrt(disc)
    qq = -(c1 + sq) / 2 if c1 >= 0 else -(c1 - sq) / 2
    if qq == 0:
        return [Fraction(0), Fraction(0)], None
    return sorted([qq / c2, c0 / qq]), None


def _sign(x: float) -> float:
    return -1.0 if x < 0.0 else 1.0


def _one_minus_cos_pair(cn: np.ndarray, sn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``1 + cn`` and ``1 - cn`` without cancellation (``sn^2 + cn^2 = 1``)."""
    s2 = sn * sn
    pos = cn >= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        one_p = np.where(pos, 1.0 + cn, s2 / (1.0 - cn))
        one_m = np.where(pos, s2 / (1.0 + cn), 1.0 - cn)
    return one_p, one_m


@dataclass
class _Plan:
    """The closed form of one body (internal axes: rotor along index 2)."""

    regime: str
    moments: np.ndarray  # (3,) internal order
    h: float
    w0: np.ndarray  # (3,) internal
    z0: float = 0.0
    lam: float = 0.0
    u0: float = 0.0
    m: float = 0.0
    m1: float = 1.0
    period: float = math.inf
    kind: int = 0  # 4: four roots, 2: two roots
    y: tuple[float, ...] = ()  # (d1, d2, d3, d4) or (d1, d2)
    amp: tuple[float, float] = (0.0, 0.0)  # signed amplitudes of m1, m2
    fac: tuple[tuple[int, int], tuple[int, int]] = ((0, 0), (0, 0))
    ab: tuple[float, float] = (0.0, 0.0)  # (A, B) of the two-roots case
    diffs: tuple[float, float] = (0.0, 0.0)  # (d1 - d3, d2 - d1) of the four-roots case
    omega_rate: float = 0.0  # axisymmetric: rate of (p + i q)
    extra: dict[str, Any] = field(default_factory=dict)

    # -- omega --------------------------------------------------------------
    def omega(self, t: np.ndarray) -> np.ndarray:
        """``w`` (nt, 3) in internal axes at times ``t`` (nt,)."""
        i1, i2, i3 = self.moments
        nt = t.shape[0]
        if self.regime in ("permanent", "rest"):
            return np.broadcast_to(self.w0, (nt, 3)).copy()
        if self.regime == "axisymmetric":
            ang = self.omega_rate * t
            c, s = np.cos(ang), np.sin(ang)
            p0, q0, r0 = self.w0
            return np.stack([p0 * c - q0 * s, p0 * s + q0 * c, np.full(nt, r0)], -1)
        from . import _elliptic

        u = self.lam * t + self.u0
        sn, cn, dn, _ = _elliptic.ellipj(u, np.full_like(u, self.m), m1=np.full_like(u, self.m1))
        sn, cn, dn = (np.atleast_1d(np.asarray(x, dtype=np.float64)) for x in (sn, cn, dn))
        if self.kind == 4:
            d1 = self.y[0]
            e13, e21 = self.diffs  # d1 - d3, d2 - d1 (rounded once from exact values)
            den = e13 + e21 * cn * cn
            delta = d1 + e21 * e13 * sn * sn / den
            phis = (sn, cn, np.ones_like(sn), dn)
            mm = [self.amp[k] * phis[self.fac[k][0]] * phis[self.fac[k][1]] / den for k in range(2)]
        else:
            d1, d2 = self.y[0], self.y[1]
            a, b = self.ab
            one_p, one_m = _one_minus_cos_pair(cn, sn)
            den = a * one_p + b * one_m
            delta = (b * d2 * one_m + a * d1 * one_p) / den
            real_axis = self.fac[0][0]
            mm = [np.empty(0), np.empty(0)]
            mm[real_axis] = self.amp[real_axis] * sn / den
            mm[1 - real_axis] = self.amp[1 - real_axis] * dn / den
        w = np.empty((nt, 3))
        w[:, 0] = mm[0] / i1
        w[:, 1] = mm[1] / i2
        w[:, 2] = self.w0[2] + delta / i3
        return w


def _plan(moments: np.ndarray, h: float, w0: np.ndarray) -> _Plan:
    """The closed form of one body: moments (3,), rotor momentum ``h e3``, ``w0`` (3,)."""
    i1, i2, i3 = (float(x) for x in moments)
    p0, q0, r0 = (float(x) for x in w0)
    base: dict[str, Any] = {"moments": np.array([i1, i2, i3]), "h": h, "w0": np.array([p0, q0, r0])}
    m10, m20, z0 = i1 * p0, i2 * q0, i3 * r0 + h
    if p0 == 0.0 and q0 == 0.0 and r0 == 0.0:
        return _Plan("rest", **base)
    if m10 == 0.0 and m20 == 0.0:
        return _Plan("permanent", **base)  # spin about the rotor axis
    if i1 == i2:
        rate = ((i3 - i1) * r0 + h) / i1
        if rate == 0.0:
            return _Plan("permanent", **base)
        per = 2.0 * math.pi / abs(rate)
        return _Plan("axisymmetric", omega_rate=rate, period=per, z0=z0, **base)
    if i3 == i1 or i3 == i2:
        return _Plan("numeric", **base)
    # The quadratics, their roots and every difference of roots in exact rational
    # arithmetic on the double inputs (square roots to 2^-128 relative), rounded once:
    # next to a separatrix 1 - k^2 is a small difference of roots (a double root of one
    # quadratic, where the discriminant is ~ (1 - k^2)^2, or a near-common root of both),
    # which double or double-double arithmetic leaves with too few correct digits.
    fi1, fi2, fi3, fh = Fraction(i1), Fraction(i2), Fraction(i3), Fraction(h)
    fr0 = Fraction(r0)
    fm10, fm20 = fi1 * Fraction(p0), fi2 * Fraction(q0)
    a1 = fi1 * (fi3 - fi2) / (fi3 * (fi2 - fi1))
    a2 = -1 - a1
    g1 = 2 * fi1 * ((fi3 - fi2) * fr0 + fh) / (fi2 - fi1)
    g2 = -2 * (fi3 * fr0 + fh) - g1
    ddf = 1 / fi1 - 1 / fi2
    dd = float(ddf)
    lead = ddf * ddf * a1 * a2
    quads = ((fm10 * fm10, g1, a1), (fm20 * fm20, g2, a2))
    if (m10 == 0.0 and g1 == 0) or (m20 == 0.0 and g2 == 0):
        return _Plan("permanent", **base)  # z0 a double root: m1 (or m2) and z' stay 0
    real: list[tuple[Fraction, int]] = []
    cplx: tuple[Fraction, Fraction, int] | None = None
    for k, (c0, c1, c2) in enumerate(quads):
        rr, zeta = _roots(c0, c1, c2)
        real += [(x, k) for x in rr]
        if zeta is not None:
            cplx = (*zeta, k)
    real.sort()

    def f(k: int, d: Fraction) -> Fraction:
        c0, c1, c2 = quads[k]
        return c0 + d * (c1 + d * c2)

    # the interval [R_i, R_i+1] holding d = 0 where both quadratics are >= 0
    pick = None
    for i in range(len(real) - 1):
        lo, hi = real[i][0], real[i + 1][0]
        if lo <= 0 <= hi and lo < hi:
            mid = (lo + hi) / 2
            if f(0, mid) > 0 and f(1, mid) > 0:
                pick = i
                break
    if pick is None:
        return _Plan("permanent", **base)
    zdot0 = -dd * m10 * m20  # z' at t = 0
    plan = _Plan("four_roots", z0=z0, **base)
    if len(real) == 4:
        order = {0: (0, 1, 3, 2), 1: (1, 2, 0, 3), 2: (2, 3, 1, 0)}[pick]
        ys = [real[k][0] for k in order]
        owner = [real[k][1] for k in order]
        d1, d2, d3, d4 = ys
        k2x = (d2 - d1) * (d4 - d3) / ((d2 - d3) * (d4 - d1))
        m1x = (d2 - d4) * (d1 - d3) / ((d2 - d3) * (d1 - d4))
        lam = math.sqrt(float(-lead * (d1 - d4) * (d2 - d3) / 4))
        kap = (
            (d2 - d1) * (d1 - d3),
            (d2 - d3) * (d1 - d2),
            (d2 - d3) * (d1 - d3),
            (d2 - d3) * (d1 - d4),
        )
        fac = [[k for k in range(4) if owner[k] == ax] for ax in (0, 1)]
        mag = [
            math.sqrt(max(float(quads[ax][2] * kap[fac[ax][0]] * kap[fac[ax][1]]), 0.0))
            for ax in (0, 1)
        ]
        # sn^2 u0 and cn^2 u0 of the Moebius substitution at z = z0 (d = 0)
        s2 = (d2 - d3) * (-d1) / ((d2 - d1) * (-d3))
        c2 = (d3 - d1) * (-d2) / ((d2 - d1) * (-d3))
        cos0 = _fsqrt(max(c2, Fraction(0)))
        up = zdot0 == 0.0 or _sign(zdot0) == _sign(float(d2 - d1))
        plan.kind, plan.y = 4, tuple(float(x) for x in ys)
        plan.diffs = (float(d1 - d3), float(d2 - d1))
        plan.fac = ((fac[0][0], fac[0][1]), (fac[1][0], fac[1][1]))
        per_factor = 2.0 if set(fac[0]) in ({0, 1}, {2, 3}) else 4.0
    else:
        assert cplx is not None
        zr, zi2, kc = cplx  # zeta = zr + i sqrt(zi2)
        kr = 1 - kc
        d1, d2 = real[0][0], real[1][0]
        a = _fsqrt((d2 - zr) ** 2 + zi2)
        b = _fsqrt((d1 - zr) ** 2 + zi2)
        m1x = ((a + b) - (d2 - d1)) * ((a + b) + (d2 - d1)) / (4 * a * b)
        k2x = ((d2 - d1) - (a - b)) * ((d2 - d1) + (a - b)) / (4 * a * b)
        lam = math.sqrt(float(-lead * a * b))
        amp_r = math.sqrt(float(-quads[kr][2] * a * b)) * float(d2 - d1)
        amp_c = math.sqrt(float(quads[kc][2])) * float(2 * a * b)
        mag = [0.0, 0.0]
        mag[kr], mag[kc] = amp_r, amp_c
        # cn u0 = (d2 B + d1 A) / (d2 B - d1 A) at d = 0, sn^2 u0 = 1 - cn^2 u0
        cos0 = (d2 * b + d1 * a) / (d2 * b - d1 * a)
        s2 = -4 * d1 * d2 * a * b / (d2 * b - d1 * a) ** 2
        up = zdot0 >= 0.0
        plan.kind, plan.y, plan.ab = 2, (float(d1), float(d2)), (float(a), float(b))
        plan.fac = ((kr, kr), (kr, kr))
        per_factor = 4.0
        plan.regime = "two_roots"
    from . import _elliptic

    m1c = min(max(float(m1x), 0.0), 1.0)
    k2 = min(max(float(k2x), 0.0), 1.0)
    # u0 = F(phi0 | k^2) from sn^2, cn of phi0 directly (no phi0: near a separatrix phi0
    # is close to pi/2 and F steep there): sin R_F(cos^2, 1 - k^2 sin^2, 1), reflected
    # about K when cos < 0
    s2f = min(max(float(s2), 0.0), 1.0)
    dn2 = float(cos0 * cos0 + max(m1x, Fraction(0)) * max(s2, Fraction(0)))
    uabs = math.sqrt(s2f) * float(_elliptic.elliprf(float(cos0 * cos0), dn2, 1.0))
    kq = float(_elliptic.ellipk(k2, m1=m1c)) if m1c > 0.0 else math.inf
    if cos0 < 0:
        uabs = 2.0 * kq - uabs
    plan.lam, plan.m, plan.m1 = lam, k2, m1c
    plan.u0 = uabs if up else -uabs
    if m1c == 0.0:
        plan.regime = "separatrix"
        plan.period = math.inf
    else:
        plan.period = per_factor * kq / lam
    # signs of m1, m2 from the initial values (a zero one from z' = -(1/I1 - 1/I2) m1 m2)
    plan.amp = (mag[0], mag[1])
    wv = plan.omega(np.zeros(1))[0]
    v1, v2 = wv[0] * i1, wv[1] * i2
    e1 = _sign(m10 * v1) if m10 != 0.0 and v1 != 0.0 else 0.0
    e2 = _sign(m20 * v2) if m20 != 0.0 and v2 != 0.0 else 0.0
    # the product m1 m2 of the formulas has a fixed sign relative to -z' / (1/I1 - 1/I2)
    # (dz/du is written without its positive denominator D^2)
    yv: tuple[float, ...] = plan.y
    prod_sign = 1.0
    for frac in (0.37, 0.61, 0.23, 0.83):
        t_probe = np.array([frac * (plan.period if math.isfinite(plan.period) else 1.0 / lam)])
        wp = plan.omega(t_probe)[0]
        u = lam * t_probe[0] + plan.u0
        sn, cn, dn, _ = (float(np.asarray(x)) for x in _elliptic.ellipj(u, k2, m1=m1c))
        if plan.kind == 4:
            e13, e21 = plan.diffs
            dzdu = e21 * e13 * (e21 + e13) * 2.0 * sn * cn * dn
        else:
            fa, fb = plan.ab
            dzdu = 2.0 * fa * fb * (yv[1] - yv[0]) * sn * dn
        prod = wp[0] * wp[1] * dzdu
        if prod != 0.0:
            prod_sign = _sign(-(lam * dzdu) / dd) * _sign(wp[0] * i1 * wp[1] * i2)
            break
    if e1 == 0.0:
        e1 = e2 * prod_sign
    if e2 == 0.0:
        e2 = e1 * prod_sign
    plan.amp = (e1 * mag[0], e2 * mag[1])
    return plan


# ---------------------------------------------------------------------------
# Attitude of one body (closed-form omega, numeric precession angle)
# ---------------------------------------------------------------------------


def _perm_quat(tidx: tuple[int, ...]) -> np.ndarray:
    """Quaternion of ``C`` with ``(C v)[k] = v[tidx[k]]`` (a cyclic permutation)."""
    c = np.zeros((3, 3))
    c[np.arange(3), list(tidx)] = 1.0
    return Rotation.from_matrix(c).as_quat()


class _Body:
    """One gyrostat: closed form (``plan``) or the numeric fallback, in user axes."""

    def __init__(
        self, j: np.ndarray, principal: bool, h: np.ndarray, w0: np.ndarray, q0: np.ndarray
    ):
        self.j, self.principal, self.hv, self.w0, self.q0 = j, principal, h, w0, q0
        moments = j if principal else np.diagonal(j).copy()
        diagonal = principal or bool(np.all(j == np.diag(moments)))
        nz = np.flatnonzero(h != 0.0)
        self.plan: _Plan | None = None
        if diagonal and nz.size <= 1:
            a = int(nz[0]) if nz.size else 2
            self.idx = ((a + 1) % 3, (a + 2) % 3, a)
            plan = _plan(moments[list(self.idx)], float(h[a]), w0[list(self.idx)])
            if plan.regime != "numeric":
                self.plan = plan
        self.regime = "numeric" if self.plan is None else self.plan.regime
        self.period = math.inf if self.plan is None else self.plan.period
        if self.plan is not None and self.regime not in ("rest", "permanent"):
            self._attitude_setup()

    # -- closed form ---------------------------------------------------------
    def _internal_omega(self, t: np.ndarray) -> np.ndarray:
        assert self.plan is not None
        return self.plan.omega(t)

    def _m_int(self, w: np.ndarray) -> np.ndarray:
        assert self.plan is not None
        m = w * self.plan.moments
        m[..., 2] += self.plan.h
        return m

    def _window(self) -> float:
        assert self.plan is not None
        if math.isfinite(self.period):
            return self.period
        return 20.0 / self.plan.lam

    def _attitude_setup(self) -> None:
        plan = self.plan
        assert plan is not None
        ts = np.linspace(0.0, self._window(), 65)
        m = self._m_int(self._internal_omega(ts))
        self.kmom = float(np.linalg.norm(self._m_int(plan.w0[None, :])[0]))
        # the reference axis: the body axis farthest from m over the motion
        jref = int(np.argmax(np.min(self.kmom**2 - m**2, axis=0)))
        self.pj = ((jref + 1) % 3, (jref + 2) % 3, jref)
        tidx = tuple(self.idx[k] for k in self.pj)
        q_c = _perm_quat(tidx)  # user body axes -> xyz
        m0 = self._m_int(plan.w0[None, :])[0][list(self.pj)]
        e0 = quat_from_euler("ZXZ", np.array([0.0, *self._angles(m0[None, :])[0]]))
        self.q_c = q_c
        self.q_s = _quaternion.multiply(
            self.q0, _quaternion.conjugate(_quaternion.multiply(e0, q_c))
        )
        width = self._window() / _PANELS
        if plan.lam > 0.0:
            width = min(width, 0.5 / plan.lam)
        self.npan = max(int(math.ceil(self._window() / width)), 1)
        if math.isfinite(self.period):
            self.wpan = self.period / self.npan
            self.cum = self._cumulative(self.npan, self.wpan, 1.0)
            self.dpsi = float(self.cum[-1])
        else:
            self.wpan = 0.5 / plan.lam

    def _angles(self, m_xyz: np.ndarray) -> np.ndarray:
        """``(theta, phi)`` (..., 2) of ``m = K (sin th sin ph, sin th cos ph, cos th)``."""
        th = np.arctan2(np.hypot(m_xyz[..., 0], m_xyz[..., 1]), m_xyz[..., 2])
        ph = np.arctan2(m_xyz[..., 0], m_xyz[..., 1])
        return np.stack([th, ph], -1)

    def _psidot(self, t: np.ndarray) -> np.ndarray:
        w = self._internal_omega(t)
        m = self._m_int(w)
        x, y = self.pj[0], self.pj[1]
        num = w[:, x] * m[:, x] + w[:, y] * m[:, y]
        return self.kmom * num / (m[:, x] ** 2 + m[:, y] ** 2)

    def _cumulative(self, n: int, width: float, sign: float) -> np.ndarray:
        """psi at the breakpoints ``sign * k * width``, k = 0..n."""
        nodes = sign * width * (np.arange(n)[:, None] + _GL_X[None, :])
        vals = self._psidot(nodes.reshape(-1)).reshape(n, -1)
        return np.concatenate([[0.0], np.cumsum(sign * width * (vals @ _GL_W))])

    def _psi(self, t: np.ndarray) -> np.ndarray:
        if math.isfinite(self.period):
            nper = np.floor(t / self.period)
            tau = t - nper * self.period
            k = np.minimum(np.floor(tau / self.wpan), self.npan - 1).astype(np.int64)
            k = np.maximum(k, 0)
            base = nper * self.dpsi + self.cum[k]
            start = k * self.wpan
            offset = nper * self.period
        else:  # separatrix: panels from 0 out to the largest |t|
            base = np.zeros_like(t)
            start = np.zeros_like(t)
            for sign in (1.0, -1.0):
                sel = sign * t > 0.0
                if not np.any(sel):
                    continue
                n = int(math.ceil(float(np.max(sign * t[sel])) / self.wpan)) + 1
                cum = self._cumulative(n, self.wpan, sign)
                k = np.floor(sign * t[sel] / self.wpan).astype(np.int64)
                base[sel] = cum[k]
                start[sel] = sign * k * self.wpan
            offset = np.zeros_like(t)
        span = t - offset - start
        nodes = start[:, None] + span[:, None] * _GL_X[None, :]
        vals = self._psidot(nodes.reshape(-1)).reshape(t.shape[0], -1)
        return base + span * (vals @ _GL_W)

    def _closed_state(self, t: np.ndarray, want_q: bool) -> tuple[np.ndarray, np.ndarray]:
        plan = self.plan
        assert plan is not None
        w_int = self._internal_omega(t)
        w = np.empty_like(w_int)
        w[:, list(self.idx)] = w_int
        if not want_q:
            return w, np.empty((t.shape[0], 0))
        if self.regime in ("rest", "permanent"):
            rot = Rotation.from_rotvec(self.w0[None, :] * t[:, None]).as_quat()
            return w, _quaternion.multiply(self.q0, rot)
        m_xyz = self._m_int(w_int)[:, list(self.pj)]
        ang = np.concatenate([self._psi(t)[:, None], self._angles(m_xyz)], -1)
        e = quat_from_euler("ZXZ", ang)
        q = _quaternion.multiply(self.q_s, _quaternion.multiply(e, self.q_c))
        return w, q

    # -- numeric fallback ------------------------------------------------------
    def _numeric_state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        from scipy.integrate import solve_ivp

        j, principal = self.j, self.principal
        j_inv = None if principal else inverse3(j)
        scale = max(float(np.linalg.norm(self.w0)), 1e-300)

        def f(_: float, y: np.ndarray) -> np.ndarray:
            w, q = y[:3], y[3:]
            dw = _gyro_rhs(j, j_inv, w, self.hv, None, None, principal)
            return np.concatenate([dw, _quat_rate(q, w, "body")])

        y0 = np.concatenate([self.w0, self.q0])
        atol = np.array([scale] * 3 + [1.0] * 4) * 1e-2 * FALLBACK_RTOL
        out = np.empty((t.shape[0], 7))
        for sign in (1.0, -1.0):
            sel = np.flatnonzero(sign * t > 0.0)
            if sel.size == 0:
                continue
            order = sel[np.argsort(sign * t[sel])]
            sol = solve_ivp(
                f, (0.0, float(t[order[-1]])), y0, method="DOP853", rtol=FALLBACK_RTOL,
                atol=atol, t_eval=t[order],
            )  # fmt: skip
            out[order] = sol.y.T
        out[t == 0.0] = y0
        q = out[:, 3:] / np.linalg.norm(out[:, 3:], axis=-1, keepdims=True)
        return out[:, :3].copy(), q

    def state(self, t: np.ndarray, want_q: bool) -> tuple[np.ndarray, np.ndarray]:
        if self.plan is None:
            return self._numeric_state(t)
        return self._closed_state(t, want_q)


# ---------------------------------------------------------------------------
# Public class
# ---------------------------------------------------------------------------


class FreeGyrostat:
    """Torque-free motion of a gyrostat (or a batch) with constant rotor momentum.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3), or RigidBody
        Principal moments ``(I1, I2, I3)`` of the whole gyrostat (rotors included;
        body axes then principal axes) or its inertia tensor in body axes (a
        non-diagonal one takes the numeric fallback), or a
        :class:`poinsot.mass.RigidBody` (its inertia about the centre of mass).
    h : array_like, shape (..., 3)
        Angular momentum of the rotors relative to the body, in body axes
        (kg m^2/s), constant. Along a principal axis (or zero) for the closed form.
    rotation0 : Rotation, SciPy Rotation or array_like (..., 4), optional
        Attitude (body -> space) at ``t = 0``; identity by default.
    omega0 : array_like, shape (..., 3)
        Angular velocity of the body at ``t = 0`` in body axes (rad/s). Keyword only.

    Attributes
    ----------
    shape : tuple
        Batch shape (the broadcast leading shape of the inputs; ``()`` for one body).

    Raises
    ------
    InvalidInputError
        For a non-physical inertia, a non-finite or wrongly shaped ``h`` or
        ``omega0``, or batch shapes that do not broadcast.
    InvalidTypeError
        If ``rotation0`` is not a rotation or an array of quaternions.

    Notes
    -----
    Euler-Zhukovsky equations ``J w' + w x (J w + h) = 0`` (docs/theory.md §10.1);
    integrals ``T = w . J w / 2`` and ``K = R (J w + h)`` (constant in
    space). For ``h`` along a principal axis ``omega(t)`` is exact (Jacobi elliptic
    functions of a Moebius transformation of the roots of the quartic
    ``z'^2 = (1/I1 - 1/I2)^2 f1(z) f2(z)``, module notes); the attitude is exact up
    to the precession angle about ``K``, a numerical quadrature (Gauss-Legendre,
    ~1e-15 relative per period). Other cases: ``solve_ivp`` DOP853 at
    ``rtol = 1e-12`` (``regime == "numeric"``). Each body of a batch is set up and
    evaluated in its own NumPy pass (no compiled batch loop).

    **Convention:** ``rotation(t)`` maps body to space components; ``omega`` and
    ``h`` in body axes (rad/s, kg m^2/s); ``momentum`` in space axes; quaternions
    scalar first.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeGyrostat
    >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.0, 0.5, 0.0], omega0=[0.1, 1.0, 0.1])
    >>> g.regime, round(g.period, 6)
    ('four_roots', 25.357711)
    >>> w = g.omega([0.0, g.period])
    >>> bool(np.allclose(w[0], w[1]))
    True
    >>> K = g.rotation(2.5).apply(g.momentum_body(2.5))
    >>> bool(np.allclose(K, g.momentum))
    True
    """

    def __init__(
        self,
        inertia: ArrayLike | RigidBody,
        h: ArrayLike,
        *,
        rotation0: Rotation | ArrayLike | None = None,
        omega0: ArrayLike,
    ) -> None:
        if isinstance(inertia, RigidBody):
            inertia = inertia.inertia
        j, principal = as_inertia(inertia, "inertia")
        hv = as_vec3(h, "h")
        w0 = as_vec3(omega0, "omega0")
        q0 = _IDENTITY if rotation0 is None else as_rotation_quat(rotation0, "rotation0")
        core = 1 if principal else 2
        shape = batch_shape(inertia=(j, core), h=(hv, 1), rotation0=(q0, 1), omega0=(w0, 1))
        n = math.prod(shape)
        jb = np.broadcast_to(j, shape + j.shape[j.ndim - core :]).reshape(
            (n,) + j.shape[j.ndim - core :]
        )
        self._shape = shape
        self._n = n
        self._principal = principal
        self._j = np.ascontiguousarray(jb)
        self._h = np.broadcast_to(hv, shape + (3,)).reshape(n, 3).copy()
        self._omega0 = np.broadcast_to(w0, shape + (3,)).reshape(n, 3).copy()
        self._q0 = np.broadcast_to(q0, shape + (4,)).reshape(n, 4).copy()
        self._bodies = [
            _Body(self._j[i], principal, self._h[i], self._omega0[i], self._q0[i]) for i in range(n)
        ]
        mb = _momentum(self._j, principal, self._omega0) + self._h
        self._energy = _kinetic(self._j, principal, self._omega0)
        self._momentum = _quaternion.rotate(self._q0, mb)
        self._kmom = np.linalg.norm(mb, axis=-1)

    # -- helpers ------------------------------------------------------------
    def _out(self, x: np.ndarray) -> Any:
        x = np.asarray(x).reshape(self._shape)
        return x.item() if self._shape == () else x

    def _eval(self, t: np.ndarray, want_q: bool) -> tuple[np.ndarray, np.ndarray]:
        """``w`` (n, nt, 3), ``q`` (n, nt, 4) at flat times ``t``."""
        nt = t.shape[0]
        w = np.empty((self._n, nt, 3))
        q = np.empty((self._n, nt if want_q else 0, 4))
        for i, body in enumerate(self._bodies):
            wi, qi = body.state(t, want_q)
            w[i] = wi
            if want_q:
                q[i] = qi
        return w, q

    def _times(self, t: ArrayLike) -> tuple[np.ndarray, tuple[int, ...]]:
        ta = as_float_array(t, "t")
        return ta.reshape(-1), ta.shape

    # -- properties -----------------------------------------------------------
    @property
    def shape(self) -> tuple[int, ...]:
        """Batch shape (``()`` for one body)."""
        return self._shape

    @property
    def inertia(self) -> np.ndarray:
        """Principal moments ``(..., 3)`` or the tensor ``(..., 3, 3)`` as given (kg m^2)."""
        return self._j.reshape(self._shape + self._j.shape[1:]).copy()

    @property
    def h(self) -> np.ndarray:
        """Rotor momentum relative to the body, body axes (kg m^2/s; constant), ``(..., 3)``."""
        return self._h.reshape(self._shape + (3,)).copy()

    @property
    def omega0(self) -> np.ndarray:
        """Initial body angular velocity (rad/s), ``(..., 3)``."""
        return self._omega0.reshape(self._shape + (3,)).copy()

    @property
    def rotation0(self) -> Rotation:
        """Initial attitude (body -> space), shape :attr:`shape`."""
        return Rotation.from_quat(self._q0.reshape(self._shape + (4,)))

    @property
    def torque(self) -> GyrostaticTorque:
        """The rotors as a torque model, :class:`~poinsot.dynamics.GyrostaticTorque` of
        :attr:`h` (``M_b = h x w``, docs/theory.md §10.1): with it,
        ``simulate(g.inertia, g.rotation0, g.omega0, t, torque=g.torque)`` integrates
        the same gyrostats numerically, in the compiled loops (any ``h``, any regime; a
        batch in the SIMD lanes of ``method="dop853"``).

        **Convention:** ``h`` in body axes (kg m^2/s).

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import FreeGyrostat, simulate
        >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.3, 0.0, 0.4], omega0=[0.3, 0.5, 0.7])
        >>> t = np.linspace(0.0, 5.0, 6)
        >>> tr = simulate(g.inertia, g.rotation0, g.omega0, t, torque=g.torque, rtol=1e-12)
        >>> g.regime, bool(np.abs(tr.omega - g.omega(t)).max() < 1e-10)
        ('numeric', True)
        """
        return GyrostaticTorque(self.h)

    @property
    def energy(self) -> float | FloatArray:
        """Kinetic energy of the carrier motion ``T = w . J w / 2`` (J; constant)."""
        return self._out(self._energy)

    @property
    def momentum(self) -> np.ndarray:
        """Total angular momentum ``K = R (J w + h)`` in space axes (kg m^2/s; constant)."""
        return self._momentum.reshape(self._shape + (3,)).copy()

    @property
    def momentum_norm(self) -> float | FloatArray:
        """``|K| = |J w + h|`` (kg m^2/s; constant)."""
        return self._out(self._kmom)

    @property
    def regime(self) -> str | np.ndarray:
        """One of :data:`GYROSTAT_REGIMES`; a str, or an array of str for a batch."""
        names = np.array([b.regime for b in self._bodies])
        return str(names[0]) if self._shape == () else names.reshape(self._shape)

    @property
    def period(self) -> float | FloatArray:
        """Period of ``omega(t)`` (s): ``4 K(k^2) / lam`` (``2 K / lam`` when one momentum
        component is ``~ sn cn``), ``2 pi I1 / |(I3 - I1) r + h|`` (axisymmetric);
        ``inf`` on a separatrix, for a permanent rotation, at rest, and ``nan`` for the
        numeric fallback."""
        vals = [math.nan if b.regime == "numeric" else b.period for b in self._bodies]
        return self._out(np.array(vals))

    @property
    def precession_per_period(self) -> float | FloatArray:
        """Angle (rad) the body turns about ``K`` per period of ``omega``:
        ``R(t + period) = Rot(K, angle) R(t)`` (``nan`` where the period is not finite)."""
        vals = [
            b.dpsi if b.plan is not None and hasattr(b, "dpsi") else math.nan for b in self._bodies
        ]
        return self._out(np.array(vals))

    # -- evaluation -------------------------------------------------------------
    def omega(self, t: ArrayLike) -> FloatArray:
        """Body angular velocity at times ``t`` (rad/s), shape ``shape + t.shape + (3,)``.

        Notes
        -----
        Jacobi elliptic closed form of the module notes (docs/theory.md §10.1);
        the DOP853 fallback where it does not apply.

        **Convention:** body axes, rad/s.

        Examples
        --------
        >>> from poinsot.dynamics import FreeGyrostat
        >>> g = FreeGyrostat([2.0, 2.0, 1.0], [0.0, 0.0, 1.0], omega0=[1.0, 0.0, 2.0])
        >>> g.omega([0.0, 1.0]).round(6)   # (p + i q) turns at ((I3 - I1) r + h) / I1 = -0.5
        array([[ 1.      ,  0.      ,  2.      ],
               [ 0.877583, -0.479426,  2.      ]])
        """
        tf, tshape = self._times(t)
        w, _ = self._eval(tf, False)
        return w.reshape(self._shape + tshape + (3,))

    def momentum_body(self, t: ArrayLike) -> FloatArray:
        """Total angular momentum ``J w(t) + h`` in body axes, ``shape + t.shape + (3,)``.

        **Convention:** body axes (kg m^2/s); ``|J w + h| = |K|`` at every time.

        Examples
        --------
        >>> from poinsot.dynamics import FreeGyrostat
        >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], omega0=[1.0, 1.0, 1.0])
        >>> g.momentum_body(0.0)
        array([1., 2., 4.])
        """
        tf, tshape = self._times(t)
        w, _ = self._eval(tf, False)
        jj = self._j.reshape((self._n, 1) + self._j.shape[1:])
        k = _momentum(jj, self._principal, w) + self._h[:, None, :]
        return k.reshape(self._shape + tshape + (3,))

    def _state(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        tf, tshape = self._times(t)
        w, q = self._eval(tf, True)
        return w.reshape(self._shape + tshape + (3,)), q.reshape(self._shape + tshape + (4,))

    def rotation(self, t: ArrayLike) -> Rotation:
        """Attitude (body -> space) at times ``t``, a Rotation of shape ``shape + t.shape``.

        Notes
        -----
        ``R(t) = S Rz(psi) Rx(theta) Rz(phi) P`` (module notes, docs/theory.md §10.1):
        ``theta, phi`` from the body momentum in closed form, ``psi`` by quadrature;
        ``R(t) (J w + h) = K`` at every time.

        **Convention:** ``v_space = R(t) v_body``; ``R(0) = rotation0``.

        Examples
        --------
        >>> from poinsot.dynamics import FreeGyrostat
        >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], omega0=[0.0, 0.0, 1.0])
        >>> g.regime, g.rotation(1.0).as_rotvec().round(12) + 0.0
        ('permanent', array([0., 0., 1.]))
        """
        return Rotation.from_quat(self._state(t)[1])

    def state(self, t: ArrayLike) -> tuple[FloatArray, Rotation]:
        """``(omega(t), rotation(t))`` in one pass.

        **Convention:** as :meth:`omega` and :meth:`rotation`.

        Examples
        --------
        >>> from poinsot.dynamics import FreeGyrostat
        >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], omega0=[1.0, 0.5, 0.2])
        >>> w, r = g.state([0.0, 1.0])
        >>> w.shape, r.shape
        ((2, 3), (2,))
        """
        w, q = self._state(t)
        return w, Rotation.from_quat(q)

    def trajectory(self, t: ArrayLike) -> Trajectory:
        """The motion sampled at 1-D times ``t`` as a :class:`~poinsot.Trajectory`.

        Time is the first axis. ``energy`` (``T = w . J w / 2``) and ``momentum``
        (``K = R (J w + h)``, space axes) are evaluated from the samples, so their
        drifts measure the error. ``info``: ``regime``, ``closed_form``
        (``"jacobi"`` or ``"none"``), ``path``, ``torque`` (``"none"``), ``conserved``.

        **Convention:** as :class:`~poinsot.Trajectory`.

        Examples
        --------
        >>> from poinsot.dynamics import FreeGyrostat
        >>> g = FreeGyrostat([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], omega0=[1.0, 0.5, 0.2])
        >>> tr = g.trajectory([0.0, 5.0, 10.0])
        >>> tr.method, tr.energy_drift < 1e-13
        ('exact', True)
        """
        ta = as_float_array(t, "t")
        if ta.ndim != 1:
            raise InvalidInputError(f"Expected `t` to have shape (n,), got {ta.shape}.")
        w, q = self._eval(ta, True)
        w = np.moveaxis(w, 1, 0)
        q = np.moveaxis(q, 1, 0)
        jj = self._j.reshape((1, self._n) + self._j.shape[1:])
        energy = _kinetic(jj, self._principal, w)
        momentum = _quaternion.rotate(q, _momentum(jj, self._principal, w) + self._h[None])
        lead = (ta.shape[0],) + self._shape
        regimes = [b.regime for b in self._bodies]
        regime = regimes[0] if self._shape == () else tuple(regimes)
        numeric = any(r == "numeric" for r in regimes)
        return Trajectory(
            ta,
            Rotation.from_quat(q.reshape(lead + (4,))),
            w.reshape(lead + (3,)),
            "exact" if not numeric else "adaptive",
            energy=energy.reshape(lead),
            momentum=momentum.reshape(lead + (3,)),
            info={
                "regime": regime,
                "closed_form": "none" if numeric else "jacobi",
                "path": "solve_ivp DOP853 fallback" if numeric else "closed form",
                "torque": "none",
                "conserved": ("energy", "momentum"),
            },
        )

    def __getitem__(self, key: int | slice | tuple[Any, ...]) -> FreeGyrostat:
        """One gyrostat (or a sub-batch) of a batch.

        >>> from poinsot.dynamics import FreeGyrostat
        >>> moments = [[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]]
        >>> g = FreeGyrostat(moments, [0.0, 0.0, 2.0], omega0=[0.3, 0.2, 1.0])
        >>> g[1].regime
        'axisymmetric'
        """
        if self._shape == ():
            raise InvalidTypeError("Expected a batch of gyrostats to index, got a single one.")
        sel = np.arange(self._n).reshape(self._shape)[key]
        flat = np.asarray(sel).reshape(-1)
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new._shape = np.shape(sel)
        new._n = flat.size
        for name in ("_j", "_h", "_omega0", "_q0", "_energy", "_momentum", "_kmom"):
            setattr(new, name, np.ascontiguousarray(getattr(self, name)[flat]))
        new._bodies = [self._bodies[i] for i in flat]
        return new

    def __len__(self) -> int:
        if self._shape == ():
            raise InvalidTypeError("Expected a batch of gyrostats for len(), got a single one.")
        return self._shape[0]

    def __repr__(self) -> str:
        if self._shape != ():
            return f"FreeGyrostat(shape={self._shape})"
        return (
            f"FreeGyrostat(inertia={self._j[0].tolist()}, h={self._h[0].tolist()}, "
            f"omega0={self._omega0[0].tolist()}, regime={self.regime!r})"
        )
