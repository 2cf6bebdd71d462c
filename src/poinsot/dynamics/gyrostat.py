"""The gyrostat: a rigid body carrying rotors of constant relative momentum (theory §10).

A gyrostat is a rigid body with rotors (wheels) that spin relative to it about axes
fixed in it, without changing its mass distribution. With ``h`` the rotors' angular
momentum relative to the body (body axes) and ``J`` the inertia of the whole system
with the rotors locked, the Euler-Zhukovsky equations (docs/theory.md §10, "The
gyrostat") are

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
period); a double root at ``z0`` a permanent rotation. ``I1 = I2`` (the rotor
along the symmetry axis): ``r`` is constant and ``(p + i q)`` turns at
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
from .invariants import invariants

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
    docs/theory.md §10, "The gyrostat": the body-frame derivative of the total
    angular momentum ``K = J w + h`` is ``K' + w x K = M``. With ``h = 0`` this is
    :func:`~poinsot.dynamics.euler_rhs`.

    **Convention:** body axes throughout; SI units (kg m^2, rad/s, kg m^2/s, N m).

    Examples
    --------
    >>> from poinsot.dynamics import gyrostat_rhs
    >>> gyrostat_rhs([1.0, 2.0, 3.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0])   # -(w x h) / J
    array([ 0.,  1.,  0.])
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
    docs/theory.md §10, "The gyrostat". For a spin ``W`` about axis 3 with
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


def _roots(c0: float, c1: float, c2: float) -> tuple[list[float], complex | None]:
    """Roots of ``c0 + c1 d + c2 d^2`` (``c2 != 0``): the real ones (stable formula) or
    ``([], zeta)`` with ``zeta`` one of the complex pair."""
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return [], complex(-c1 / (2.0 * c2), math.sqrt(-disc) / (2.0 * abs(c2)))
    sq = math.sqrt(disc)
    qq = -0.5 * (c1 + math.copysign(sq, c1))
    if qq == 0.0:
        return [0.0, 0.0], None
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
        sn, cn, dn, _ = _elliptic.ellipj(u, self.m, m1=self.m1)
        sn, cn, dn = (np.atleast_1d(np.asarray(x, dtype=np.float64)) for x in (sn, cn, dn))
        if self.kind == 4:
            d1, d2, d3, _ = self.y
            den = (d1 - d3) + (d2 - d1) * cn * cn
            delta = d1 + (d2 - d1) * (d1 - d3) * sn * sn / den
            phis = (sn, cn, np.ones_like(sn), dn)
            mm = [
                self.amp[k] * phis[self.fac[k][0]] * phis[self.fac[k][1]] / den for k in range(2)
            ]
        else:
            d1, d2 = self.y
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
    base = {"moments": np.array([i1, i2, i3]), "h": h, "w0": np.array([p0, q0, r0])}
    m10, m20, z0 = i1 * p0, i2 * q0, i3 * r0 + h
    if p0 == 0.0 and q0 == 0.0 and r0 == 0.0:
        return _Plan("rest", **base)
    if m10 == 0.0 and m20 == 0.0:
        return _Plan("permanent", **base)  # spin about the rotor axis
    if i1 == i2:
        rate = ((i3 - i1) * r0 + h) / i1
        per = 2.0 * math.pi / abs(rate) if rate != 0.0 else math.inf
        return _Plan("axisymmetric", omega_rate=rate, period=per, z0=z0, **base)
    if i3 == i1 or i3 == i2:
        return _Plan("numeric", **base)
    a1 = i1 * (i3 - i2) / (i3 * (i2 - i1))
    a2 = i2 * (i1 - i3) / (i3 * (i2 - i1))
    g1 = 2.0 * i1 * ((i3 - i2) * r0 + h) / (i2 - i1)
    g2 = -2.0 * z0 - g1
    dd = 1.0 / i1 - 1.0 / i2
    lead = dd * dd * a1 * a2
    quads = ((m10 * m10, g1, a1), (m20 * m20, g2, a2))
    real: list[tuple[float, int]] = []
    cplx: tuple[complex, int] | None = None
    for k, (c0, c1, c2) in enumerate(quads):
        rr, zeta = _roots(c0, c1, c2)
        real += [(x, k) for x in rr]
        if zeta is not None:
            cplx = (zeta, k)
    real.sort()

    def f(k: int, d: float) -> float:
        c0, c1, c2 = quads[k]
        return c0 + d * (c1 + d * c2)

    # the interval [R_i, R_i+1] holding d = 0 where both quadratics are >= 0
    pick = None
    for i in range(len(real) - 1):
        lo, hi = real[i][0], real[i + 1][0]
        if lo <= 0.0 <= hi and lo < hi:
            mid = 0.5 * (lo + hi)
            if f(0, mid) > 0.0 and f(1, mid) > 0.0:
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
        k2 = (d2 - d1) * (d4 - d3) / ((d2 - d3) * (d4 - d1))
        m1c = (d2 - d4) * (d1 - d3) / ((d2 - d3) * (d1 - d4))
        lam = math.sqrt(-lead * (d1 - d4) * (d2 - d3) / 4.0)
        kap = (
            (d2 - d1) * (d1 - d3),
            (d2 - d3) * (d1 - d2),
            (d2 - d3) * (d1 - d3),
            (d2 - d3) * (d1 - d4),
        )
        fac = [[k for k in range(4) if owner[k] == ax] for ax in (0, 1)]
        mag = [math.sqrt(max(quads[ax][2] * kap[fac[ax][0]] * kap[fac[ax][1]], 0.0)) for ax in (0, 1)]
        s0 = max((d2 - d3) * (-d1) / ((d2 - d1) * (-d3)), 0.0)
        c0 = max((d3 - d1) * (-d2) / ((d2 - d1) * (-d3)), 0.0)
        phi0 = math.atan2(math.sqrt(s0), math.sqrt(c0))
        up = zdot0 == 0.0 or _sign(zdot0) == _sign(d2 - d1)
        plan.kind, plan.y = 4, (d1, d2, d3, d4)
        plan.fac = ((fac[0][0], fac[0][1]), (fac[1][0], fac[1][1]))
        per_factor = 2.0 if set(fac[0]) in ({0, 1}, {2, 3}) else 4.0
    else:
        assert cplx is not None
        zeta, kc = cplx
        kr = 1 - kc
        d1, d2 = real[0][0], real[1][0]
        a = abs(d2 - zeta)
        b = abs(d1 - zeta)
        zr, zi2 = zeta.real, zeta.imag**2
        # A + B - (d2 - d1) without cancellation
        ea = zi2 / (a + (d2 - zr)) if d2 - zr > 0.0 else a + (zr - d2)
        eb = zi2 / (b + (zr - d1)) if zr - d1 > 0.0 else b + (d1 - zr)
        m1c = (ea + eb) * ((a + b) + (d2 - d1)) / (4.0 * a * b)
        k2 = ((d2 - d1) - (a - b)) * ((d2 - d1) + (a - b)) / (4.0 * a * b)
        lam = math.sqrt(-lead * a * b)
        amp_r = math.sqrt(-quads[kr][2] * a * b) * (d2 - d1)
        amp_c = math.sqrt(quads[kc][2]) * 2.0 * a * b
        mag = [0.0, 0.0]
        mag[kr], mag[kc] = amp_r, amp_c
        phi0 = math.atan2(2.0 * math.sqrt(max(a * b * d2 * (-d1), 0.0)), d2 * b + d1 * a)
        up = zdot0 >= 0.0
        plan.kind, plan.y, plan.ab = 2, (d1, d2), (a, b)
        plan.fac = ((kr, kr), (kr, kr))
        per_factor = 4.0
        plan.regime = "two_roots"
    from . import _elliptic

    m1c = min(max(m1c, 0.0), 1.0)
    k2 = 1.0 - m1c if m1c > 0.5 else min(max(k2, 0.0), 1.0)
    uabs = float(_elliptic.ellipkinc(phi0, k2, m1=m1c))
    plan.lam, plan.m, plan.m1 = lam, k2, m1c
    plan.u0 = uabs if up else -uabs
    if m1c == 0.0:
        plan.regime = "separatrix"
        plan.period = math.inf
    else:
        plan.period = per_factor * float(_elliptic.ellipk(k2, m1=m1c)) / lam
    # signs of m1, m2 from the initial values (a zero one from z' = -(1/I1 - 1/I2) m1 m2)
    plan.amp = (mag[0], mag[1])
    wv = plan.omega(np.zeros(1))[0]
    v1, v2 = wv[0] * i1, wv[1] * i2
    e1 = _sign(m10 * v1) if m10 != 0.0 and v1 != 0.0 else 0.0
    e2 = _sign(m20 * v2) if m20 != 0.0 and v2 != 0.0 else 0.0
    # the product m1 m2 of the formulas has a fixed sign relative to -z'/dd:
    t_probe = np.array([0.37 * (plan.period if math.isfinite(plan.period) else 1.0 / lam)])
    wp = plan.omega(t_probe)[0]
    u = lam * t_probe[0] + plan.u0
    sn, cn, dn, _ = (float(np.asarray(x)) for x in _elliptic.ellipj(u, k2, m1=m1c))
    if plan.kind == 4:
        d1, d2, d3, _ = plan.y
        den = (d1 - d3) + (d2 - d1) * cn * cn
        dzdu = (d2 - d1) * (d1 - d3) * (d2 - d3) * 2.0 * sn * cn * dn / (den * den)
    else:
        d1, d2 = plan.y
        a, b = plan.ab
        den = a * (1.0 + cn) + b * (1.0 - cn)
        dzdu = 2.0 * a * b * (d2 - d1) * sn * dn / (den * den)
    prod_sign = _sign(-(lam * dzdu) / dd) * _sign(wp[0] * i1 * wp[1] * i2)
    if e1 == 0.0:
        e1 = e2 * prod_sign
    if e2 == 0.0:
        e2 = e1 * prod_sign
    plan.amp = (e1 * mag[0], e2 * mag[1])
    return plan
