"""The exact free rigid body (Euler-Poinsot case) and its MacCullagh/Poinsot geometry.

A rigid body turning about its fixed centre of mass with no torque (SPEC S10,
Euler case) has the integrals ``2T = A p^2 + B q^2 + C r^2`` and
``K^2 = A^2 p^2 + B^2 q^2 + C^2 r^2``. :class:`FreeRigidBody` evaluates the
exact motion at any times: the body angular velocity by Jacobi elliptic
functions and the attitude through the precession angle about the (constant)
angular momentum, an elliptic integral of the third kind written with
Carlson's symmetric integral ``R_J``.

Per-body constants come from ``scipy.special`` (``ellipkm1``, ``elliprf``,
``elliprj``). The per-time-point work is one compiled kernel
(:mod:`poinsot.dynamics._free_body_numba`): Jacobi functions by the descending
Landen transformation fed ``1 - k^2`` directly (``scipy.special.ellipj`` only
takes ``k^2``, which loses ``1 - k^2`` near the separatrix, and is 3x slower),
Carlson's duplication algorithm for ``R_J``, and the attitude quaternion. The
motion is computed for ``|w0| ~ 1`` and ``max(I) ~ 1`` (exact power-of-two
scaling; ``w(t; s w0) = s w(s t; w0)``), so no magnitude under- or overflows.

Case analysis (moments relabelled ``A > B > C`` here; the code works in the
axes as given). Put ``D = K^2 - 2 T B``:

* ``D > 0``: the polhode encircles the major axis ``A``; ``D < 0``: the minor
  axis ``C``. With ``i`` the encircled axis, ``j`` the other extreme one and
  ``m`` the middle one (``B``)::

      w_i = a_i dn(u | k^2),  w_m = a_m sn(u | k^2),  w_j = a_j cn(u | k^2),
      u = lam t + u0,
      a_i^2 = (K^2 - 2 T I_j) / (I_i (I_i - I_j)),
      a_j^2 = (2 T I_i - K^2) / (I_j (I_i - I_j)),
      a_m^2 = (2 T I_i - K^2) / (I_m (I_i - I_m)),
      lam^2 = (I_i - I_m) (K^2 - 2 T I_j) / (I_i I_m I_j),
      k^2 = (I_m - I_j) (2 T I_i - K^2) / ((I_i - I_m) (K^2 - 2 T I_j)),

  the period of the angular velocity is ``4 K(k^2) / lam`` (Landau & Lifshitz,
  *Mechanics*, S37, with ``I_i = I_3``).
* ``D = 0`` (the separatrix ``K^2 = 2 B T``): ``k = 1``, ``sn = tanh``,
  ``cn = dn = sech``; the period is infinite.
* Two equal moments (symmetric body): regular precession, ``psi' = K / A``,
  ``phi' = (A - C) r / A``, ``cos theta = C r / K`` (``A = B`` the equatorial
  moment, ``C`` the symmetry one).
* Three equal moments, or ``omega0 = 0``, or a rotation exactly about the
  middle axis: uniform rotation about a fixed axis.

The attitude is ``R(t) = S Rz(psi(t)) Rx(theta(t)) Rz(phi(t))`` with
``(theta, phi)`` the z-x-z angles of the body momentum direction about the
extreme axis ``j`` that the polhode does not encircle (so they are never
singular) and ``psi`` the precession angle about ``K``, obtained from
``psi' = K (I_x w_x^2 + I_y w_y^2) / (I_x^2 w_x^2 + I_y^2 w_y^2)`` (SPEC S10)
in closed form.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .._validate import as_float_array, as_vec3, is_integer
from ..errors import InvalidInputError, InvalidTypeError, SingularityWarning
from ..rotations import quaternion as _quaternion
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory

__all__ = [
    "FreeRigidBody",
    "MacCullaghGeometry",
    "PoinsotGeometry",
    "SYMMETRY_RTOL",
    "SEPARATRIX_RTOL",
    "NEAR_SEPARATRIX",
]

_EPS = float(np.finfo(float).eps)

#: Two principal moments closer than ``SYMMETRY_RTOL * max(moments)`` are taken
#: as equal (a symmetric body). ``16 eps`` (3.6e-15) is the level at which
#: ``numpy.linalg.eigh`` splits a repeated moment of a rotated symmetric tensor;
#: bodies farther from symmetry use the general (elliptic) formulas, which stay
#: accurate for nearly equal moments.
SYMMETRY_RTOL = 16.0 * _EPS

#: ``K^2 - 2 T B`` smaller than ``SEPARATRIX_RTOL`` times the size of its two
#: terms (``A (A - B) p^2`` and ``C (B - C) r^2``) is round-off: the motion is
#: taken as exactly on the separatrix (and a :class:`~poinsot.SingularityWarning`
#: says so unless the difference is exactly zero).
SEPARATRIX_RTOL = 8.0 * _EPS

#: Below this complementary parameter ``1 - k^2`` (relative distance to the
#: separatrix) a :class:`~poinsot.SingularityWarning` is issued: the motion itself
#: is ill-conditioned there, and a relative perturbation ``eps`` of the initial
#: state shifts the phase by about ``2 eps / (1 - k^2)`` per period.
NEAR_SEPARATRIX = 1e-6


# ---------------------------------------------------------------------------
# Kernels (pure numpy / scipy.special; no validation)
# ---------------------------------------------------------------------------


def _special():
    from scipy import special

    return special


def _axis_quat(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Unit quaternion (..., 4) of a rotation by ``angle`` (...) about unit ``axis`` (3,)."""
    h = 0.5 * np.asarray(angle, dtype=float)
    s = np.sin(h)
    return np.concatenate([np.cos(h)[..., None], s[..., None] * axis], axis=-1)


#: Quaternions of the cyclic relabellings ``(x, y, z) = (e_{j+1}, e_{j+2}, e_j)``
#: (rotations by -120, +120 and 0 degrees about ``(1, 1, 1)``).
_PERM_QUAT = (
    np.array([0.5, -0.5, -0.5, -0.5]),
    np.array([0.5, 0.5, 0.5, 0.5]),
    np.array([1.0, 0.0, 0.0, 0.0]),
)


def _conj(q: np.ndarray) -> np.ndarray:
    return q * np.array([1.0, -1.0, -1.0, -1.0])


class _Motion:
    """Exact torque-free motion in principal axes (moments ``I`` in any order).

    ``mode`` is one of ``"uniform"``, ``"symmetric"``, ``"elliptic"``,
    ``"separatrix"``. Evaluation methods take a flat float array of times.
    """

    def __init__(self, moments: np.ndarray, w0: np.ndarray, q0: np.ndarray):
        self.I = moments
        self.w0 = w0
        self.q0 = q0
        jw = moments * w0
        self.energy = 0.5 * float(np.dot(w0, jw))
        self.kmom = float(np.linalg.norm(jw))
        self.momentum = _quaternion.rotate(q0, jw)
        self.khat = self.momentum / self.kmom if self.kmom > 0 else np.array([0.0, 0.0, 1.0])
        self.period = math.inf
        self.precession = math.nan
        self.polhode_axis: int | None = None
        self.m1 = math.nan
        imax, imin = int(np.argmax(moments)), int(np.argmin(moments))
        equal = [moments[a] == moments[b] for a, b in ((0, 1), (1, 2), (2, 0))]
        if all(equal) or self.kmom == 0.0:
            self.regime = "rest" if self.kmom == 0.0 else "spherical"
            self._setup_uniform()
        elif any(equal):
            self.regime = "symmetric"
            self._setup_symmetric(equal)
        else:
            mid = 3 - imax - imin
            t_a = moments[imax] * (moments[imax] - moments[mid]) * w0[imax] ** 2
            t_c = moments[imin] * (moments[mid] - moments[imin]) * w0[imin] ** 2
            d = t_a - t_c
            if abs(d) <= SEPARATRIX_RTOL * (t_a + t_c):
                self.regime = "separatrix"
                if t_a == 0.0 and t_c == 0.0:
                    self._setup_uniform()  # permanent rotation about the middle axis
                else:
                    if d != 0.0:
                        warnings.warn(
                            "The initial state is within round-off of the separatrix "
                            "K^2 = 2 B T and is treated as exactly on it (infinite period); "
                            "the true motion may flip back after t ~ 36 / lam.",
                            SingularityWarning,
                            stacklevel=3,
                        )
                    self._setup_elliptic(imax, mid, imin, d, separatrix=True)
            elif d > 0:
                self.regime = "major"
                self._setup_elliptic(imax, mid, imin, d, separatrix=False)
            else:
                self.regime = "minor"
                self._setup_elliptic(imin, mid, imax, d, separatrix=False)

    # -- uniform rotation ---------------------------------------------------
    def _setup_uniform(self) -> None:
        self.mode = "uniform"
        wn = float(np.linalg.norm(self.w0))
        self.rate = wn
        self.axis = self.w0 / wn if wn > 0 else np.array([0.0, 0.0, 1.0])

    # -- symmetric body: regular precession ---------------------------------
    def _setup_symmetric(self, equal: list[bool]) -> None:
        self.mode = "symmetric"
        s = {0: 2, 1: 0, 2: 1}[equal.index(True)]  # the axis not in the equal pair
        i_s, i_p = self.I[s], self.I[(s + 1) % 3]
        self.s = s
        self.es = np.eye(3)[s]
        self.spin = (i_s - i_p) * self.w0[s] / i_p  # rate of w_perp about e_s in the body
        self.psi_dot = self.kmom / i_p
        self.phi_dot = -self.spin
        if self.spin != 0.0:
            self.period = 2.0 * math.pi / abs(self.spin)
            self.precession = self.psi_dot * self.period
        if self.w0[s] != 0.0:
            self.polhode_axis = s

    # -- general body: Jacobi elliptic functions ----------------------------
    def _setup_elliptic(self, i: int, m: int, j: int, d: float, *, separatrix: bool) -> None:
        sp = _special()
        mom, w = self.I, self.w0
        ii, im, ij = mom[i], mom[m], mom[j]
        self.mode = "separatrix" if separatrix else "elliptic"
        self.i, self.m, self.j = i, m, j
        # 2 T I_i - K^2 and K^2 - 2 T I_j as sums of same-sign terms (no cancellation).
        g_i = sum(mom[k] * (ii - mom[k]) * w[k] ** 2 for k in (m, j))
        mg_j = sum(mom[k] * (mom[k] - ij) * w[k] ** 2 for k in (i, m))
        ai2 = mg_j / (ii * (ii - ij))
        aj2 = g_i / (ij * (ii - ij))
        am2 = g_i / (im * (ii - im))
        lam = math.sqrt((ii - im) * mg_j / (ii * im * ij))
        sigma = 1.0 if i == (m + 1) % 3 else -1.0
        s_i = math.copysign(1.0, w[i])
        s_j = math.copysign(1.0, w[j]) if separatrix else 1.0
        s_m = sigma * math.copysign(1.0, ii - ij) * s_i * s_j
        a = np.zeros(3)
        a[i], a[m], a[j] = s_i * math.sqrt(ai2), s_m * math.sqrt(am2), s_j * math.sqrt(aj2)
        self.a, self.lam = a, lam
        self.n2 = ij * g_i / (ii * mg_j)
        self.beta = (im * im * am2) / (ii * ii * ai2)
        self.major = ii > ij
        self.kappa = self.kmom * ((1.0 / im - 1.0 / ii) if self.major else (1.0 / ii - 1.0 / im))
        self.rate0 = self.kmom / (ii if self.major else im)
        self.polhode_axis = None if separatrix else i
        if separatrix:
            self.m1 = 0.0
            self.k2 = 1.0
            self.u0 = math.asinh((w[m] / a[m]) / (w[i] / a[i]))
            self.Jh = 0.0
            self.Kq = math.inf
        else:
            m1 = (ii - ij) * d / ((ii - im) * mg_j)
            k2 = (im - ij) * g_i / ((ii - im) * mg_j)
            self.m1, self.k2 = m1, k2
            self.Kq = float(sp.ellipkm1(m1))
            if 0.0 < m1 < NEAR_SEPARATRIX:
                warnings.warn(
                    f"The motion is close to the separatrix (1 - k^2 = {m1:.3g}): it is "
                    f"ill-conditioned, and relative errors ~{2 * _EPS / m1:.1g} per period in "
                    "the phase are unavoidable.",
                    SingularityWarning,
                    stacklevel=4,
                )
            if am2 == 0.0:
                self.u0 = 0.0
            else:
                sn0, cn0 = w[m] / a[m], w[j] / a[j]
                rho = math.hypot(sn0, cn0)
                sn0, cn0 = sn0 / rho, cn0 / rho
                dn0 = w[i] / a[i]
                f = sn0 * float(sp.elliprf(cn0 * cn0, dn0 * dn0, 1.0))
                self.u0 = f if cn0 >= 0.0 else math.copysign(2.0 * self.Kq, sn0) - f
            self.Jh = (2.0 / 3.0) * float(sp.elliprj(0.0, m1, 1.0, 1.0 + self.n2))
            self.period = 4.0 * self.Kq / lam
            dpsi_j = self.rate0 * self.period + self._psi_extra(self.period, 2.0 * self.Jh)
            # Landau's convention (Euler z-axis = the encircled axis i): differs by 2 pi.
            self.precession = dpsi_j + 2.0 * math.pi * math.copysign(1.0, ii - ij)
        self.qp = _PERM_QUAT[j]
        self.par = np.array(
            [
                lam,
                self.u0,
                self.Kq,
                self.k2,
                self.m1,
                self.n2,
                self.Jh,
                0.0,
                self.kmom,
                self.rate0,
                self.kappa,
                self.beta,
                float(self.major),
                float(separatrix),
            ]
        )
        self.idx = np.array([i, m, j], dtype=np.int64)
        from ._free_body_numba import landen_table

        self.landen = landen_table(self.k2, self.m1) if not separatrix else np.zeros((3, 1))
        one = np.array([1.0, 0.0, 0.0, 0.0])
        zero = np.zeros(1)
        _, _, j0 = self._kernel(zero, one, one, True)
        self.par[7] = j0[0]
        _, qz0, _ = self._kernel(zero, one, one, True)
        self.qs = _quaternion.multiply(self.q0, _quaternion.multiply(_conj(self.qp), _conj(qz0[0])))

    def _kernel(self, t: np.ndarray, qs: np.ndarray, qp: np.ndarray, want_q: bool):
        from . import _free_body_numba

        t = np.ascontiguousarray(t, dtype=np.float64)
        return _free_body_numba.elliptic_state(
            t, self.par, self.idx, self.I, self.a, qs, qp, want_q, self.landen
        )

    def _psi_extra(self, t, dj):
        """``psi - rate0 t`` given the time ``t`` and the increase ``dj`` of ``J``."""
        if self.major:
            return self.kappa * self.beta * dj / self.lam
        return self.kappa * (t - self.beta * dj / self.lam)

    # -- evaluation ---------------------------------------------------------
    def omega(self, t: np.ndarray) -> np.ndarray:
        if self.mode == "uniform":
            return np.broadcast_to(self.w0, t.shape + (3,)).copy()
        if self.mode == "symmetric":
            return self._omega_symmetric(t)
        return self._kernel(t, self.qs, self.qp, False)[0]

    def _omega_symmetric(self, t: np.ndarray) -> np.ndarray:
        s = self.s
        x, y = (s + 1) % 3, (s + 2) % 3
        ang = self.spin * t
        c, sn = np.cos(ang), np.sin(ang)
        w = np.empty(t.shape + (3,))
        w[..., s] = self.w0[s]
        w[..., x] = self.w0[x] * c - self.w0[y] * sn
        w[..., y] = self.w0[x] * sn + self.w0[y] * c
        return w

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Body angular velocity (n, 3) and attitude quaternion (n, 4) at times ``t``."""
        if self.mode == "uniform":
            q = _quaternion.multiply(self.q0, _axis_quat(self.axis, self.rate * t))
            return self.omega(t), q
        if self.mode == "symmetric":
            q = _quaternion.multiply(
                _axis_quat(self.khat, self.psi_dot * t),
                _quaternion.multiply(self.q0, _axis_quat(self.es, self.phi_dot * t)),
            )
            return self._omega_symmetric(t), q
        w, q, _ = self._kernel(t, self.qs, self.qp, True)
        return w, q


# ---------------------------------------------------------------------------
# Geometry results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MacCullaghGeometry:
    """The MacCullagh picture in the space of body angular momenta (SPEC S10).

    All vectors are in the body's principal axes, in the order of
    :attr:`FreeRigidBody.principal_moments`.

    Attributes
    ----------
    momentum_radius : float
        ``|K|``, radius of the momentum sphere ``|K|^2 = K^2``.
    ellipsoid_semi_axes : ndarray, shape (3,)
        ``sqrt(2 T I_k)``: semi-axes of the energy ellipsoid
        ``K1^2/A + K2^2/B + K3^2/C = 2T``.
    track : ndarray, shape (n, 3)
        The body angular momentum ``J w(t)`` over one period (over a finite
        window ``|lam t + u0| <= 10`` on the separatrix; a point when ``w`` is
        constant): the intersection of sphere and ellipsoid.
    separatrices : ndarray, shape (2, n, 3) or (0, n, 3)
        The two great circles ``|K|^2 = 2 B T`` on the energy ellipsoid (planes
        through the middle axis); empty for a body with equal moments.
    """

    momentum_radius: float
    ellipsoid_semi_axes: np.ndarray
    track: np.ndarray
    separatrices: np.ndarray


@dataclass(frozen=True, eq=False)
class PoinsotGeometry:
    """Poinsot's picture: the inertia ellipsoid rolling on the invariable plane.

    Attributes
    ----------
    ellipsoid_semi_axes : ndarray, shape (3,)
        ``1 / sqrt(I_k)``: semi-axes of the inertia ellipsoid ``r^T J r = 1``
        along the principal axes (SPEC S8).
    plane_normal : ndarray, shape (3,)
        ``K / |K|`` in space axes.
    plane_distance : float
        ``sqrt(2T) / |K|``: distance of the invariable plane from the fixed point.
    t : ndarray, shape (n,)
        Sample times.
    polhode : ndarray, shape (n, 3)
        Contact point ``r = w / sqrt(2T)`` in principal body axes.
    herpolhode : ndarray, shape (n, 3)
        Contact point in space axes, ``R r``; it lies in the invariable plane.
    rotation : Rotation, shape (n,)
        Attitude of the principal axes (principal body -> space) at ``t``.
    """

    ellipsoid_semi_axes: np.ndarray
    plane_normal: np.ndarray
    plane_distance: float
    t: np.ndarray
    polhode: np.ndarray
    herpolhode: np.ndarray
    rotation: Rotation


# ---------------------------------------------------------------------------
# Public class
# ---------------------------------------------------------------------------


def _snap_symmetric(moments: np.ndarray) -> np.ndarray:
    mom = moments.copy()
    tol = SYMMETRY_RTOL * float(np.max(mom))
    for a, b in ((0, 1), (1, 2), (2, 0)):
        if mom[a] != mom[b] and abs(mom[a] - mom[b]) <= tol:
            mom[a] = mom[b] = 0.5 * (mom[a] + mom[b])
    return mom


def _samples(n) -> int:
    """A number of curve samples: an integer >= 2."""
    if not (is_integer(n) or isinstance(n, np.integer)) or n < 2:
        raise InvalidInputError(f"Expected `n` to be an integer >= 2, got {n!r}.")
    return int(n)


class FreeRigidBody:
    """Exact torque-free motion of a rigid body about its fixed centre of mass.

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3), or RigidBody
        Principal moments ``(A, B, C)`` in any order (the body axes are then the
        principal axes, in that order), or an inertia tensor in some body axes,
        or a :class:`poinsot.mass.RigidBody` (its inertia about the centre of mass).
        A non-diagonal tensor is diagonalised with
        :func:`poinsot.mass.principal_axes`; ``omega0``, :meth:`omega`,
        :meth:`momentum_body` and :meth:`rotation` still refer to the axes of the
        given tensor. A diagonal tensor keeps its axes and order.
    omega0 : array_like, shape (3,)
        Angular velocity at ``t = 0`` in those body axes (rad/s).
    rotation0 : Rotation, optional
        Attitude (body -> space) at ``t = 0``; identity by default.

    Attributes
    ----------
    principal_moments : ndarray, shape (3,)
        The moments used (in the given order, or ascending for a tensor);
        moments within :data:`SYMMETRY_RTOL` are made equal.
    principal_axes : ndarray, shape (3, 3)
        Columns: the principal axes in the given body axes (identity for moments).

    Raises
    ------
    InvalidInputError
        For a non-physical inertia (shape, not positive definite, triangle
        inequality), a non-finite ``omega0`` or a ``rotation0`` of wrong shape.
    InvalidTypeError
        If ``rotation0`` is not a :class:`~poinsot.Rotation`.

    Warns
    -----
    SingularityWarning
        When the state is within :data:`NEAR_SEPARATRIX` of the separatrix or
        on it only up to round-off (see the module notes).

    Notes
    -----
    Jacobi elliptic solution with the case analysis of the module docstring
    (SPEC S10; Landau & Lifshitz, *Mechanics*, S37). The attitude satisfies
    ``R(t) J w(t) = K`` (constant) and ``R' = R w^``.

    **Convention:** ``rotation(t)`` maps body components to space components,
    ``omega`` is in body axes (rad/s), ``momentum`` in space axes.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody
    >>> body = FreeRigidBody([1.0, 2.0, 3.0], [0.1, 1.0, 0.1])   # near the middle axis
    >>> body.regime, body.polhode_axis
    ('major', 2)
    >>> round(body.period, 4)
    22.9963
    >>> w = body.omega([0.0, body.period])
    >>> bool(np.allclose(w[0], w[1]))
    True
    >>> K = body.rotation(2.5).apply(body.momentum_body(2.5))
    >>> bool(np.allclose(K, body.momentum))
    True
    """

    def __init__(self, inertia, omega0, rotation0=None):
        from ..mass import RigidBody, check_inertia, check_principal_moments, principal_axes

        if isinstance(inertia, RigidBody):
            if inertia.shape != ():
                raise InvalidInputError(
                    f"Expected `inertia` to be a single RigidBody, got shape {inertia.shape}."
                )
            inertia = inertia.inertia  # about the centre of mass, in body axes
        j = as_float_array(inertia, "inertia")
        if j.shape == (3,):
            moments = check_principal_moments(j, "inertia")
            axes, qv = np.eye(3), _PERM_QUAT[2]
        elif j.shape == (3, 3):
            js = check_inertia(j, "inertia")
            if np.all(js == np.diag(np.diagonal(js))):
                moments, axes, qv = np.diagonal(js).copy(), np.eye(3), _PERM_QUAT[2]
            else:
                moments, rot = principal_axes(js)
                axes, qv = rot.as_matrix(), rot.as_quat()
        else:
            raise InvalidInputError(
                f"Expected `inertia` to have shape (3,) (principal moments) or (3, 3) "
                f"(an inertia tensor), got {j.shape}."
            )
        w0 = as_vec3(omega0, "omega0")
        if w0.shape != (3,):
            raise InvalidInputError(f"Expected `omega0` to have shape (3,), got {w0.shape}.")
        if rotation0 is None:
            q0 = np.array([1.0, 0.0, 0.0, 0.0])
        elif isinstance(rotation0, Rotation):
            if rotation0.shape != ():
                raise InvalidInputError(
                    f"Expected `rotation0` to be a single rotation, got shape {rotation0.shape}."
                )
            q0 = rotation0.as_quat()
        else:
            raise InvalidTypeError(
                f"Expected `rotation0` to be a poinsot.Rotation or None, got "
                f"{type(rotation0).__name__}."
            )
        self._moments = _snap_symmetric(np.asarray(moments, dtype=float))
        self._axes = np.asarray(axes, dtype=float)
        self._identity_axes = bool(np.all(self._axes == np.eye(3)))
        self._qv = np.asarray(qv, dtype=float)  # principal -> given body axes
        self._omega0 = w0.copy()
        self._q0 = q0
        wp = self._axes.T @ w0
        qp0 = _quaternion.multiply(q0, self._qv)
        jw = self._moments * wp
        self._energy = 0.5 * float(np.dot(wp, jw))
        self._kmom = float(np.linalg.norm(jw))
        self._momentum = _quaternion.rotate(qp0, jw)
        # The motion is computed for |w0| ~ 1 and max(I) ~ 1 (w(t; s w0) = s w(s t; w0),
        # and J -> c J leaves w(t) unchanged), so that no magnitude can under/overflow.
        # Powers of two keep the scaled data exact (e.g. an exact separatrix stays one).
        wn = float(np.linalg.norm(wp))
        self._wscale = math.ldexp(1.0, math.frexp(wn)[1]) if wn > 0.0 else 1.0
        iscale = math.ldexp(1.0, math.frexp(float(np.max(self._moments)))[1])
        self._motion = _Motion(self._moments / iscale, wp / self._wscale, qp0)

    # -- properties ---------------------------------------------------------
    @property
    def principal_moments(self) -> np.ndarray:
        """Principal moments ``I_k`` (order: given, or ascending for a tensor)."""
        return self._moments.copy()

    @property
    def principal_axes(self) -> np.ndarray:
        """Columns: principal axes in the given body axes (a proper rotation matrix)."""
        return self._axes.copy()

    @property
    def inertia(self) -> np.ndarray:
        """Inertia tensor in the given body axes, ``V diag(I) V^T``."""
        return (self._axes * self._moments) @ self._axes.T

    @property
    def omega0(self) -> np.ndarray:
        """Initial body angular velocity (rad/s)."""
        return self._omega0.copy()

    @property
    def energy(self) -> float:
        """Kinetic energy ``T = w^T J w / 2`` (constant)."""
        return self._energy

    @property
    def momentum(self) -> np.ndarray:
        """Angular momentum ``K = R J w`` in space axes (constant)."""
        return self._momentum.copy()

    @property
    def momentum_norm(self) -> float:
        """``|K|``."""
        return self._kmom

    @property
    def regime(self) -> str:
        """``"major"``/``"minor"`` (the polhode encircles that axis), ``"separatrix"``,
        ``"symmetric"``, ``"spherical"`` or ``"rest"``."""
        return self._motion.regime

    @property
    def polhode_axis(self) -> int | None:
        """Index (into :attr:`principal_moments`) of the axis the polhode encircles.

        ``None`` on the separatrix, for a spherical body, at rest, and for a
        symmetric body spinning in its equatorial plane.
        """
        return self._motion.polhode_axis

    @property
    def stable_axes(self) -> tuple[bool, bool, bool]:
        """Stability of permanent rotation about each principal axis.

        Distinct moments: the major and minor axes are stable, the middle one
        is not (SPEC S10). Symmetric body: the symmetry axis is stable, the
        equatorial ones are not (a perturbation makes ``w`` precess away).
        Spherical body: all stable.
        """
        mom = self._moments
        equal = [mom[a] == mom[b] for a, b in ((0, 1), (1, 2), (2, 0))]
        if all(equal):
            return (True, True, True)
        if any(equal):
            s = {0: 2, 1: 0, 2: 1}[equal.index(True)]
            return tuple(k == s for k in range(3))  # type: ignore[return-value]
        mid = 3 - int(np.argmax(mom)) - int(np.argmin(mom))
        return tuple(k != mid for k in range(3))  # type: ignore[return-value]

    @property
    def period(self) -> float:
        """Period of ``omega(t)`` (s).

        ``4 K(k^2) / lam``; ``2 pi / |(C - A) r / A|`` for a symmetric body; the
        small-oscillation limit for a rotation exactly about the major or minor
        axis; ``inf`` on the separatrix, for a spherical body, at rest, and for a
        symmetric body spinning in its equatorial plane.
        """
        return float(self._motion.period) / self._wscale

    @property
    def precession_per_period(self) -> float:
        """Angle (rad) the body turns about ``K`` per period of ``omega``.

        ``R(t + period) = Rot(K, angle) R(t)``; the angle is the increase of the
        precession angle ``psi`` with Landau's choice of Euler angles (the
        Euler ``z``-axis along the axis the polhode encircles), e.g.
        ``K / A * period`` for a symmetric body. ``nan`` if the period is
        infinite.
        """
        return float(self._motion.precession)

    @property
    def complementary_parameter(self) -> float:
        """``1 - k^2``: the relative distance to the separatrix (``nan`` if not elliptic)."""
        return float(self._motion.m1)

    # -- evaluation ---------------------------------------------------------
    def _omega_p(self, t: np.ndarray) -> np.ndarray:
        """Angular velocity in principal axes at flat times ``t``."""
        return self._wscale * self._motion.omega(self._wscale * t)

    def _state_p(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Angular velocity (principal axes) and principal-axes attitude quaternions."""
        w, q = self._motion.state(self._wscale * t)
        return self._wscale * w, q

    def _times(self, t) -> tuple[np.ndarray, tuple[int, ...]]:
        ta = as_float_array(t, "t")
        return ta.reshape(-1), ta.shape

    def omega(self, t) -> np.ndarray:
        """Body angular velocity at times ``t`` (rad/s).

        Parameters
        ----------
        t : array_like, any shape
            Times (s) since the initial state.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``

        Notes
        -----
        ``w_i = a_i dn(u)``, ``w_m = a_m sn(u)``, ``w_j = a_j cn(u)``,
        ``u = lam t + u0`` (module notes, SPEC S10).

        **Convention:** body axes of the given inertia, rad/s.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> FreeRigidBody([2.0, 2.0, 1.0], [1.0, 0.0, 2.0]).omega([0.0, 1.0]).round(6)
        array([[ 1.      ,  0.      ,  2.      ],
               [ 0.540302, -0.841471,  2.      ]])
        """
        tf, shape = self._times(t)
        w = self._omega_p(tf)
        if not self._identity_axes:
            w = w @ self._axes.T
        return w.reshape(shape + (3,))

    def momentum_body(self, t) -> np.ndarray:
        """Angular momentum ``J w(t)`` in body axes, shape ``t.shape + (3,)``.

        **Convention:** body axes of the given inertia.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> FreeRigidBody([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]).momentum_body(0.0)
        array([1., 2., 3.])
        """
        tf, shape = self._times(t)
        w = self._omega_p(tf) * self._moments
        if not self._identity_axes:
            w = w @ self._axes.T
        return w.reshape(shape + (3,))

    def _state(self, t):
        tf, shape = self._times(t)
        w, q = self._state_p(tf)
        if not self._identity_axes:
            w = w @ self._axes.T
            q = _quaternion.multiply(q, _conj(self._qv))
        return w.reshape(shape + (3,)), q.reshape(shape + (4,))

    def rotation(self, t) -> Rotation:
        """Attitude (body -> space) at times ``t``, a Rotation of shape ``t.shape``.

        Notes
        -----
        ``R(t) = S Rz(psi) Rx(theta) Rz(phi)`` (module notes) with the
        precession angle ``psi`` in closed form through Carlson's ``R_J``; whole
        periods are added by quasi-periodicity.

        **Convention:** ``v_space = R(t) v_body``; ``R(0) = rotation0``.

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import FreeRigidBody
        >>> body = FreeRigidBody([1.0, 2.0, 3.0], [0.0, 0.0, 1.0])   # about the major axis
        >>> body.rotation(np.pi / 2).as_rotvec().round(12) + 0.0
        array([0.        , 0.        , 1.57079633])
        """
        return Rotation.from_quat(self._state(t)[1])

    def state(self, t) -> tuple[np.ndarray, Rotation]:
        """``(omega(t), rotation(t))`` in one pass (cheaper than two calls).

        **Convention:** as :meth:`omega` and :meth:`rotation`.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> w, r = FreeRigidBody([1.0, 2.0, 3.0], [1.0, 0.5, 0.2]).state([0.0, 1.0, 2.0])
        >>> w.shape, r.shape
        ((3, 3), (3,))
        """
        w, q = self._state(t)
        return w, Rotation.from_quat(q)

    def trajectory(self, t) -> Trajectory:
        """The exact motion sampled at 1-D times ``t`` as a :class:`~poinsot.Trajectory`.

        ``energy`` and ``momentum`` are evaluated from the samples
        (``T = w^T J w / 2``, ``K = R J w``), so their drifts measure round-off.

        **Convention:** as :class:`~poinsot.Trajectory` (body ``omega``, space ``momentum``).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> tr = FreeRigidBody([1.0, 2.0, 3.0], [1.0, 0.5, 0.2]).trajectory([0.0, 5.0, 10.0])
        >>> tr.method, tr.energy_drift < 1e-14
        ('exact', True)
        """
        ta = as_float_array(t, "t")
        if ta.ndim != 1:
            raise InvalidInputError(f"Expected `t` to have shape (n,), got {ta.shape}.")
        w, q = self._state(ta)
        rot = Rotation.from_quat(q)
        jw = w @ self.inertia.T
        energy = 0.5 * np.einsum("...i,...i->...", w, jw)
        momentum = rot.apply(jw)
        return Trajectory(
            ta, rot, w, "exact", energy=energy, momentum=momentum, info={"regime": self.regime}
        )

    # -- geometry -----------------------------------------------------------
    def _window(self, n_periods: float) -> float:
        mo = self._motion
        if math.isfinite(mo.period):
            return n_periods * mo.period / self._wscale
        if mo.mode == "separatrix":
            return max(10.0 - mo.u0, 1.0) / (mo.lam * self._wscale)
        return 2.0 * math.pi * n_periods / self._wscale

    def _require_motion(self, what: str) -> None:
        if self._kmom == 0.0:
            raise InvalidInputError(
                f"The {what} picture needs a moving body: `omega0` is zero (T = K = 0)."
            )

    def maccullagh(self, n: int = 200) -> MacCullaghGeometry:
        """The MacCullagh picture: momentum sphere, energy ellipsoid, track, separatrices.

        Parameters
        ----------
        n : int, optional
            Samples per curve.

        Returns
        -------
        MacCullaghGeometry

        Notes
        -----
        Body ``K`` lies on ``|K|^2 = K^2`` and on ``K1^2/A + K2^2/B + K3^2/C = 2T``;
        the separatrices are the great circles ``|K|^2 = 2 B T`` of the ellipsoid,
        ``K_A^2 (1/B - 1/A) = K_C^2 (1/C - 1/B)`` (SPEC S10).

        **Convention:** principal body axes (order of :attr:`principal_moments`).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> g = FreeRigidBody([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]).maccullagh(50)
        >>> g.ellipsoid_semi_axes.round(4), g.track.shape, g.separatrices.shape
        (array([2.4495, 3.4641, 4.2426]), (50, 3), (2, 50, 3))
        """
        n = _samples(n)
        self._require_motion("MacCullagh")
        mo = self._motion
        mom = self._moments
        two_t = 2.0 * self._energy
        if mo.mode == "separatrix":
            t = (np.linspace(-10.0, 10.0, n) - mo.u0) / (mo.lam * self._wscale)
        else:
            t = np.linspace(0.0, self._window(1.0), n)
        track = self._omega_p(t) * mom
        equal = [mom[a] == mom[b] for a, b in ((0, 1), (1, 2), (2, 0))]
        if any(equal):
            seps = np.zeros((0, n, 3))
        else:
            ia, ic = int(np.argmax(mom)), int(np.argmin(mom))
            ib = 3 - ia - ic
            a, b, c = mom[ia], mom[ib], mom[ic]
            alpha = math.atan(math.sqrt((1.0 / b - 1.0 / a) / (1.0 / c - 1.0 / b)))
            s = np.linspace(0.0, 2.0 * math.pi, n)
            rad = math.sqrt(two_t * b)
            seps = np.zeros((2, n, 3))
            for k, sgn in enumerate((1.0, -1.0)):
                seps[k, :, ib] = rad * np.cos(s)
                seps[k, :, ia] = rad * np.sin(s) * math.cos(alpha)
                seps[k, :, ic] = sgn * rad * np.sin(s) * math.sin(alpha)
        return MacCullaghGeometry(
            momentum_radius=self._kmom,
            ellipsoid_semi_axes=np.sqrt(two_t * mom),
            track=track,
            separatrices=seps,
        )

    def poinsot(self, t=None, n: int = 400) -> PoinsotGeometry:
        """Poinsot's picture: inertia ellipsoid, invariable plane, polhode, herpolhode.

        Parameters
        ----------
        t : array_like, shape (n,), optional
            Sample times; default ``n`` samples over three periods (over a window
            of the flip on the separatrix).
        n : int, optional
            Number of samples when ``t`` is not given.

        Returns
        -------
        PoinsotGeometry

        Notes
        -----
        With the inertia ellipsoid ``r^T J r = 1`` the contact point is
        ``r = w / sqrt(2T)``; the tangent plane there is normal to ``J w = K``
        and at distance ``r . K / |K| = sqrt(2T) / |K|`` from the fixed point
        (SPEC S10): the invariable plane.

        **Convention:** polhode in principal body axes, herpolhode and plane in
        space axes.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> body = FreeRigidBody([1.0, 2.0, 3.0], [1.0, 1.0, 1.0])
        >>> g = body.poinsot(n=100)
        >>> round(g.plane_distance, 6), round((2 * body.energy) ** 0.5 / body.momentum_norm, 6)
        (0.654654, 0.654654)
        """
        n = _samples(n)
        self._require_motion("Poinsot")
        mo = self._motion
        if t is None:
            ta = np.linspace(0.0, self._window(3.0), n)
        else:
            ta = as_float_array(t, "t")
            if ta.ndim != 1 or ta.size == 0:
                raise InvalidInputError(
                    f"Expected `t` to have shape (n,) with n >= 1, got {ta.shape}."
                )
        w, q = self._state_p(ta)
        r = w / math.sqrt(2.0 * self._energy)
        herp = _quaternion.rotate(q, r)
        return PoinsotGeometry(
            ellipsoid_semi_axes=1.0 / np.sqrt(self._moments),
            plane_normal=mo.khat.copy(),
            plane_distance=math.sqrt(2.0 * self._energy) / self._kmom,
            t=ta,
            polhode=r,
            herpolhode=herp,
            rotation=Rotation.from_quat(q),
        )

    def __repr__(self) -> str:
        return (
            f"FreeRigidBody(principal_moments={self._moments.tolist()}, "
            f"omega0={self._omega0.tolist()}, regime={self.regime!r})"
        )
