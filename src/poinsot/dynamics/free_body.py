"""The exact free rigid body (Euler-Poinsot case) and its MacCullagh/Poinsot geometry.

A rigid body turning about its fixed centre of mass with no torque (docs/theory.md
§10, Euler case) has the integrals ``2T = A p^2 + B q^2 + C r^2`` and
``K^2 = A^2 p^2 + B^2 q^2 + C^2 r^2``. :class:`FreeRigidBody` evaluates the
exact motion of one body or of a batch of bodies at any times: the body angular
velocity by Jacobi elliptic functions and the attitude through the precession
angle about the (constant) angular momentum, an elliptic integral of the third
kind written with Carlson's symmetric integral ``R_J``.

Everything numerical is compiled (:mod:`poinsot.dynamics._free_body_numba`, on
the shared kernels of :mod:`poinsot.dynamics._elliptic`): one pass computes the
constants of every body of a batch (each may be in a different regime), one
pass evaluates every body at every time. The regime discriminant
``D = K^2 - 2 T B`` is formed in double-double arithmetic from error-free
transformations, so ``1 - k^2`` is correct to a few ulp however close the state
is to the separatrix; the Jacobi functions use the descending Landen
transformation fed ``1 - k^2`` directly. The motion is computed for ``|w0| ~ 1``
and ``max(I) ~ 1`` (exact power-of-two scaling; ``w(t; s w0) = s w(s t; w0)``), so
no magnitude under- or overflows.

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
      1 - k^2 = (I_i - I_j) (K^2 - 2 T I_m) / ((I_i - I_m) (K^2 - 2 T I_j)),

  the period of the angular velocity is ``4 K(k^2) / lam`` (Landau & Lifshitz,
  *Mechanics*, §37, with ``I_i = I_3``).
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
``psi' = K (I_x w_x^2 + I_y w_y^2) / (I_x^2 w_x^2 + I_y^2 w_y^2)`` (docs/theory.md
§10) in closed form.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _display
from .._jit import first_call
from .._progress import Progress, in_chunks
from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_rotation_quat, as_vec3, batch_shape, is_integer
from ..errors import InvalidInputError, InvalidTypeError, SingularityWarning
from ..mass import RigidBody, principal_axes
from ..mass.tensor import _kinetic, _momentum, as_inertia
from ..rotations import quaternion as _quaternion
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory
from .invariants import angular_momentum, invariants

if TYPE_CHECKING:
    from ..mass.body import RigidBody

__all__ = [
    "FreeRigidBody",
    "RegularPrecession",
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

#: ``D = K^2 - 2 T B`` is computed in double-double arithmetic (error-free
#: transformations): a ``|D|`` at most ``SEPARATRIX_RTOL = 2^-100`` (7.9e-31) times
#: the size of its two terms ``A (A - B) p^2`` and ``C (B - C) r^2`` is the rounding
#: of that computation, and the state is taken as exactly on the separatrix
#: (silently if ``D`` is exactly zero, else with a :class:`~poinsot.SingularityWarning`).
SEPARATRIX_RTOL = 2.0**-100

#: Below this complementary parameter ``1 - k^2`` (relative distance to the
#: separatrix) a :class:`~poinsot.SingularityWarning` is issued: the motion itself
#: is ill-conditioned there (a relative perturbation ``eps`` of the initial state
#: shifts the phase by about ``2 eps / (1 - k^2)`` per period), although the
#: solution is exact for the given double inputs.
NEAR_SEPARATRIX = 1e-6

_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def _kernels() -> Any:
    from . import _free_body_numba

    return _free_body_numba


def _snap_symmetric(moments: np.ndarray) -> np.ndarray:
    """Moments (..., 3) with pairs closer than ``SYMMETRY_RTOL * max`` made equal (their
    mean; pairs in the order 01, 12, 20). Written with ``np.where``: ``poinsot.jax``
    runs it on JAX arrays."""
    cols = [moments[..., 0], moments[..., 1], moments[..., 2]]
    tol = SYMMETRY_RTOL * np.max(moments, axis=-1)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        snap = (cols[a] != cols[b]) & (np.abs(cols[a] - cols[b]) <= tol)
        mean = 0.5 * (cols[a] + cols[b])
        cols[a] = np.where(snap, mean, cols[a])
        cols[b] = np.where(snap, mean, cols[b])
    return np.stack(cols, axis=-1)


def _pow2(x: np.ndarray) -> np.ndarray:
    """The power of two ``2^e`` with ``x = f 2^e``, ``0.5 <= f < 1`` (1 for x = 0)."""
    _, e = np.frexp(x)
    return np.where(x > 0.0, np.ldexp(1.0, e), 1.0)


def _samples(n: Any) -> int:
    """A number of curve samples: an integer >= 2."""
    if not (is_integer(n) or isinstance(n, np.integer)) or n < 2:
        raise InvalidInputError(f"Expected `n` to be an integer >= 2, got {n!r}.")
    return int(n)


@dataclass(frozen=True, eq=False)
class RegularPrecession:
    """The regular precession of a free symmetric body (docs/theory.md §10).

    Attributes
    ----------
    precession_rate : float or ndarray
        ``psi' = K / A`` (rad/s): the symmetry axis turns about ``K`` at this rate.
    spin_rate : float or ndarray
        ``phi' = r (A - C) / A`` (rad/s): the body turns about its symmetry axis
        relative to the precessing frame (Euler angles with ``z`` along ``K``).
    nutation : float or ndarray
        ``theta`` with ``cos theta = C r / K`` (rad): the constant angle between the
        symmetry axis and ``K``.
    axis : int or ndarray
        Index of the symmetry axis among the principal axes (moment ``C``).
    """

    precession_rate: Any
    spin_rate: Any
    nutation: Any
    axis: Any


@dataclass(frozen=True, eq=False)
class MacCullaghGeometry:
    """The MacCullagh picture in the space of body angular momenta (docs/theory.md §10).

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
        along the principal axes (docs/theory.md §8).
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


class FreeRigidBody:
    """Exact torque-free motion of a rigid body (or a batch of bodies) about its
    fixed centre of mass.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3), or RigidBody
        Principal moments ``(A, B, C)`` in any order (the body axes are then the
        principal axes, in that order), or inertia tensors in some body axes, or a
        :class:`poinsot.mass.RigidBody` (its inertia about the centre of mass), read
        by ``poinsot.mass.tensor.as_inertia``. A non-diagonal tensor is diagonalised
        with :func:`poinsot.mass.principal_axes`; ``omega0``, :meth:`omega`,
        :meth:`momentum_body` and :meth:`rotation` still refer to the axes of the
        given tensor. A diagonal tensor keeps its axes and order. (A batch of three
        bodies' moments, shape ``(3, 3)``, reads as one tensor: pass tensors.)
    rotation0 : Rotation, SciPy Rotation or array_like (..., 4), optional
        Attitude (body -> space) at ``t = 0``: a poinsot or SciPy ``Rotation`` or
        scalar-first quaternions; identity by default.
    omega0 : array_like, shape (..., 3)
        Angular velocity at ``t = 0`` in those body axes (rad/s). Keyword only.

    Attributes
    ----------
    shape : tuple
        The batch shape: the broadcast leading shape of ``inertia``, ``rotation0``
        and ``omega0`` (``()`` for one body).
    principal_moments : ndarray, shape (..., 3)
        The moments used (in the given order, or ascending for a tensor);
        moments within :data:`SYMMETRY_RTOL` are made equal.

    Raises
    ------
    InvalidInputError
        For a non-physical inertia (shape, not positive definite, triangle
        inequality), a non-finite ``omega0``, or batch shapes that do not broadcast.
    InvalidTypeError
        If ``rotation0`` is not a rotation or an array of quaternions.

    Warns
    -----
    SingularityWarning
        When a state is within :data:`NEAR_SEPARATRIX` of the separatrix (the motion
        is ill-conditioned; the result is still exact for the given inputs).

    Notes
    -----
    Jacobi elliptic solution with the case analysis of the module docstring
    (docs/theory.md §10; Landau & Lifshitz, *Mechanics*, §37). The attitude
    satisfies ``R(t) J w(t) = K`` (constant) and ``R' = R w^``. Each body of a batch
    may be in its own regime (major, minor, separatrix, symmetric, spherical, rest);
    evaluations return arrays of shape ``shape + t.shape + (3,)`` (angular velocity)
    or Rotations of shape ``shape + t.shape``.

    **Convention:** ``rotation(t)`` maps body components to space components,
    ``omega`` is in body axes (rad/s), ``momentum`` in space axes; quaternions are
    scalar first.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody
    >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 1.0, 0.1])   # near the middle axis
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
    >>> batch = FreeRigidBody([[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]], omega0=[0.3, 0.2, 1.0])
    >>> batch.shape, batch.regime.tolist(), batch.omega(np.zeros(4)).shape
    ((2,), ['major', 'symmetric'], (2, 4, 3))
    """

    def __init__(
        self,
        inertia: ArrayLike | RigidBody,
        *,
        rotation0: Rotation | ArrayLike | None = None,
        omega0: ArrayLike,
    ) -> None:
        if isinstance(inertia, RigidBody):
            inertia = inertia.inertia  # about the centre of mass, in body axes
        j, principal = as_inertia(inertia, "inertia")
        w0 = as_vec3(omega0, "omega0")
        q0 = _IDENTITY if rotation0 is None else as_rotation_quat(rotation0, "rotation0")
        shape = batch_shape(inertia=(j, 1 if principal else 2), rotation0=(q0, 1), omega0=(w0, 1))
        n = math.prod(shape)
        jb = np.broadcast_to(j, shape + j.shape[j.ndim - (1 if principal else 2) :])
        jb = jb.reshape((n,) + jb.shape[len(shape) :])
        if principal:
            moments = jb.copy()
            qv = np.broadcast_to(_IDENTITY, (n, 4)).copy()
        else:
            moments = np.diagonal(jb, axis1=-2, axis2=-1).copy()
            qv = np.broadcast_to(_IDENTITY, (n, 4)).copy()
            full = np.any(jb != moments[:, :, None] * np.eye(3), axis=(-2, -1))
            if np.any(full):
                mom_f, rot_f = principal_axes(jb[full])
                moments[full] = mom_f
                qv[full] = np.reshape(rot_f.as_quat(), (-1, 4))
        self._shape = shape
        self._n = n
        self._j = j
        self._principal_input = principal
        self._moments = _snap_symmetric(moments)
        self._qv = qv
        self._omega0 = np.broadcast_to(w0, shape + (3,)).reshape(n, 3).copy()
        self._q0 = np.broadcast_to(q0, shape + (4,)).reshape(n, 4).copy()
        self._setup()

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: moments, initial state, integrals, regime and period (SI units)."""
        d = _display
        note = (
            "omega in body axes, K in space axes; exact Euler-Poinsot motion (docs/theory.md §10)"
        )
        if self._shape != ():
            k = min(5, self._n)
            regime = np.ravel(np.asarray(self.regime))[:k]
            period = np.ravel(np.asarray(self.period))[:k]
            cells = [[d.esc(i), d.esc(d.num(self._moments[i])), d.esc(regime[i]),
                      d.esc(d.num(period[i]))] for i in range(k)]  # fmt: skip
            grid = d.grid(["#", "moments kg m^2", "regime", "period s"], cells)
            rows = [
                ("batch shape", d.esc(self._shape)),
                ("bodies shown", d.esc(f"{k} of {self._n}")),
            ]
            return d.table("FreeRigidBody batch", rows, note, grid)
        rows = [
            ("principal moments", d.value(self.principal_moments, "kg m^2")),
            ("omega0", d.value(self.omega0, "rad/s")),
            ("energy T", d.value(self.energy, "J")),
            ("|K|", d.value(self.momentum_norm, "kg m^2/s")),
            ("K (space)", d.value(self.momentum, "kg m^2/s")),
            ("regime", d.esc(self.regime)),
            ("period of omega", d.value(self.period, "s")),
        ]
        return d.table("FreeRigidBody", rows, note)

    # -- constants of the motion (one compiled pass over the bodies) -------------
    def _setup(self) -> None:
        kern = _kernels()
        n = self._n
        wp = _quaternion.rotate(_quaternion.conjugate(self._qv), self._omega0)
        qp0 = _quaternion.multiply(self._q0, self._qv)
        # |w0| ~ 1 and max(I) ~ 1 by exact powers of two (an exact separatrix stays one)
        self._wscale = _pow2(np.linalg.norm(wp, axis=-1))
        iscale = _pow2(np.max(self._moments, axis=-1))
        mom_s = np.ascontiguousarray(self._moments / iscale[:, None])
        w_s = np.ascontiguousarray(wp / self._wscale[:, None])
        self._mom_s = mom_s
        self._par = np.zeros((n, kern.N_PAR))
        self._idx = np.zeros((n, 3), dtype=np.int64)
        self._amp = np.zeros((n, 3))
        self._vec = np.zeros((n, 3))
        self._qa = np.zeros((n, 4))
        self._qb = np.zeros((n, 4))
        self._ks = np.zeros((n, kern.LMAX))
        self._kps = np.zeros((n, kern.LMAX))
        self._info = np.zeros((n, 5))
        first_call(kern.setup, n * 2e-3)(
            mom_s,
            w_s,
            np.ascontiguousarray(qp0),
            self._par,
            self._idx,
            self._amp,
            self._vec,
            self._qa,
            self._qb,
            self._ks,
            self._kps,
            self._info,
        )
        self._par[:, kern.P_WS] = self._wscale
        self._code = self._info[:, 0].astype(np.int64)
        m1 = self._info[:, 3]
        near = (m1 > 0.0) & (m1 < NEAR_SEPARATRIX)
        if np.any(near):
            worst = float(np.min(m1[near]))
            which = "" if self._shape == () else f" ({int(np.sum(near))} of {n} bodies)"
            warnings.warn(
                f"The motion is close to the separatrix (1 - k^2 = {worst:.3g}){which}: it is "
                f"ill-conditioned; a relative change eps of the initial state moves the phase "
                f"by ~2 eps / (1 - k^2) = {2 * _EPS / worst:.1g} per period (the solution is "
                "exact for the given inputs).",
                SingularityWarning,
                stacklevel=3,
            )
        rounded = (self._code == kern.R_SEPARATRIX) & (self._info[:, 4] != 0.0)
        if np.any(rounded):
            warnings.warn(
                "An initial state is within double-double round-off (2^-100) of the "
                "separatrix K^2 = 2 B T and is treated as exactly on it (infinite period).",
                SingularityWarning,
                stacklevel=3,
            )

        k_body = _momentum(self._moments, True, wp)
        self._energy = _kinetic(self._moments, True, wp)
        self._momentum = _quaternion.rotate(qp0, k_body)
        self._kmom = np.linalg.norm(k_body, axis=-1)

    def _out(self, x: np.ndarray, tail: tuple[int, ...] = ()) -> Any:
        """Per-body values (n, *tail) as the batch shape: a float for one body."""
        x = x.reshape(self._shape + tail)
        if self._shape == () and tail == ():
            return x.item()
        return x

    # -- properties ---------------------------------------------------------
    @property
    def shape(self) -> tuple[int, ...]:
        """Batch shape (``()`` for one body)."""
        return self._shape

    @property
    def principal_moments(self) -> np.ndarray:
        """Principal moments ``I_k`` (order: given, or ascending for a tensor), ``(..., 3)``."""
        return self._moments.reshape(self._shape + (3,)).copy()

    def principal_axes(self) -> tuple[np.ndarray, Rotation]:
        """Principal moments and axes, as :meth:`poinsot.mass.RigidBody.principal_axes`.

        Returns
        -------
        moments : ndarray, shape (..., 3)
            :attr:`principal_moments` (the order used for the geometry).
        rotation : Rotation, shape (...)
            ``S`` from the principal axes to the given body axes (``v_body = S v_p``;
            the columns of ``S.as_matrix()`` are the principal axes written in the
            body axes; the identity for principal moments or a diagonal tensor).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> m, s = FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 0.0, 0.0]).principal_axes()
        >>> m.tolist(), float(s.magnitude())
        ([1.0, 2.0, 3.0], 0.0)
        """
        rot = Rotation.from_quat(self._qv.reshape(self._shape + (4,)))
        return self.principal_moments, rot

    @property
    def inertia(self) -> np.ndarray:
        """Inertia tensor in the given body axes, ``S diag(I) S^T``, shape ``(..., 3, 3)``."""
        s = Rotation.from_quat(self._qv).as_matrix()
        j = np.einsum("nik,nk,njk->nij", s, self._moments, s)
        return j.reshape(self._shape + (3, 3))

    @property
    def omega0(self) -> np.ndarray:
        """Initial body angular velocity (rad/s), ``(..., 3)``."""
        return self._omega0.reshape(self._shape + (3,)).copy()

    @property
    def rotation0(self) -> Rotation:
        """Initial attitude (body -> space), shape :attr:`shape`."""
        return Rotation.from_quat(self._q0.reshape(self._shape + (4,)))

    @property
    def energy(self) -> float | FloatArray:
        """Kinetic energy ``T = w^T J w / 2`` (J; constant), float or ``(...)``."""
        return self._out(self._energy)

    @property
    def momentum(self) -> np.ndarray:
        """Angular momentum ``K = R J w`` in space axes (kg m^2/s; constant), ``(..., 3)``."""
        return self._momentum.reshape(self._shape + (3,)).copy()

    @property
    def momentum_norm(self) -> float | FloatArray:
        """``|K|`` (kg m^2/s), float or ``(...)``."""
        return self._out(self._kmom)

    @property
    def regime(self) -> str | np.ndarray:
        """``"major"``/``"minor"`` (the polhode encircles that axis), ``"separatrix"``,
        ``"symmetric"``, ``"spherical"`` or ``"rest"``; a str, or an array of str for
        a batch."""
        names = np.array(_kernels().REGIMES)[self._code]
        return str(names[0]) if self._shape == () else names.reshape(self._shape)

    @property
    def polhode_axis(self) -> int | None | np.ndarray:
        """Index (into :attr:`principal_moments`) of the axis the polhode encircles.

        ``None`` (``-1`` in a batch's int array) on the separatrix, for a spherical
        body, at rest, and for a symmetric body spinning in its equatorial plane.
        """
        kern = _kernels()
        code = self._code
        ax = np.full(self._n, -1, dtype=np.int64)
        ell = (code == kern.R_MAJOR) | (code == kern.R_MINOR)
        ax[ell] = self._idx[ell, 0]
        sym = (code == kern.R_SYMMETRIC) & (
            self._omega0_p()[np.arange(self._n), self._idx[:, 0]] != 0.0
        )
        ax[sym] = self._idx[sym, 0]
        if self._shape == ():
            return None if ax[0] < 0 else int(ax[0])
        return ax.reshape(self._shape)

    def _omega0_p(self) -> np.ndarray:
        return _quaternion.rotate(_quaternion.conjugate(self._qv), self._omega0)

    @property
    def stable_axes(self) -> tuple[bool, ...] | np.ndarray:
        """Stability of permanent rotation about each principal axis.

        Distinct moments: the major and minor axes are stable, the middle one is not
        (docs/theory.md §10). Symmetric body: the symmetry axis is stable, the
        equatorial ones are not (a perturbation makes ``w`` precess away). Spherical
        body: all stable. A tuple of three bools, or a bool array ``(..., 3)``.
        """
        mom = self._moments
        out = np.ones((self._n, 3), dtype=bool)
        e = np.stack([mom[:, 0] == mom[:, 1], mom[:, 1] == mom[:, 2], mom[:, 2] == mom[:, 0]], -1)
        sym = np.any(e, axis=-1) & ~np.all(e, axis=-1)
        s = np.select([e[:, 0], e[:, 1]], [2, 0], 1)
        out[sym] = np.arange(3)[None, :] == s[sym, None]
        dist = ~np.any(e, axis=-1)
        mid = 3 - np.argmax(mom, axis=-1) - np.argmin(mom, axis=-1)
        out[dist] = np.arange(3)[None, :] != mid[dist, None]
        if self._shape == ():
            return tuple(bool(x) for x in out[0])
        return out.reshape(self._shape + (3,))

    @property
    def period(self) -> float | FloatArray:
        """Period of ``omega(t)`` (s), float or ``(...)``.

        ``4 K(k^2) / lam``; ``2 pi / |(C - A) r / A|`` for a symmetric body; the
        small-oscillation limit for a rotation exactly about the major or minor
        axis; ``inf`` on the separatrix, for a spherical body, at rest, and for a
        symmetric body spinning in its equatorial plane.
        """
        return self._out(self._info[:, 1] / self._wscale)

    @property
    def precession_per_period(self) -> float | FloatArray:
        """Angle (rad) the body turns about ``K`` per period of ``omega``.

        ``R(t + period) = Rot(K, angle) R(t)``; the angle is the increase of the
        precession angle ``psi`` with Landau's choice of Euler angles (the
        Euler ``z``-axis along the axis the polhode encircles), e.g.
        ``K / A * period`` for a symmetric body. ``nan`` if the period is
        infinite.
        """
        return self._out(self._info[:, 2].copy())

    def regular_precession(self) -> RegularPrecession:
        """Precession rate, spin rate and nutation angle of a symmetric body (theory §10).

        With ``A = B != C`` (``C`` about the symmetry axis, ``r`` the angular velocity
        about it), ``K = |K|``: ``psi' = K / A``, ``phi' = r (A - C) / A``,
        ``cos theta = C r / K``. Raises :class:`~poinsot.InvalidInputError` for a body
        without exactly two equal moments (asymmetric or spherical); ``nan`` at rest.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> p = FreeRigidBody([2.0, 2.0, 1.0], omega0=[0.0, 0.5, 2.0]).regular_precession()
        >>> round(float(p.precession_rate), 12), float(p.spin_rate), p.axis
        (1.11803398875, 1.0, 2)
        """
        m = self._moments
        eq01, eq12, eq02 = m[:, 0] == m[:, 1], m[:, 1] == m[:, 2], m[:, 0] == m[:, 2]
        pairs = eq01.astype(int) + eq12 + eq02
        if np.any(pairs != 1):
            bad = int(np.flatnonzero(pairs != 1)[0])
            raise InvalidInputError(
                "Expected a symmetric body (exactly two equal principal moments) for a "
                f"regular precession, got moments {m[bad].tolist()}."
            )
        k = np.where(eq01, 2, np.where(eq12, 0, 1))
        rows = np.arange(m.shape[0])
        c = m[rows, k]
        a = m[rows, (k + 1) % 3]
        wp = _quaternion.rotate(_quaternion.conjugate(self._qv), self._omega0)
        r = wp[rows, k]
        kk = self._kmom
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = np.clip(c * r / kk, -1.0, 1.0)
        axis = int(k[0]) if self._shape == () else k.reshape(self._shape)
        return RegularPrecession(
            self._out(kk / a), self._out(r * (a - c) / a), self._out(np.arccos(cos)), axis
        )

    @property
    def complementary_parameter(self) -> float | FloatArray:
        """``1 - k^2``: the relative distance to the separatrix (``0`` on it, ``nan``
        if the motion is not elliptic), correct to a few ulp for the given inputs."""
        return self._out(self._info[:, 3].copy())

    # -- evaluation ---------------------------------------------------------
    def _eval(
        self, t: np.ndarray, want_q: bool, *, principal: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """``w`` (n, nt, 3) and ``q`` (n, nt, 4) at flat times ``t`` (nt,)."""
        kern = _kernels()
        nt = t.shape[0]
        w = np.empty((self._n, nt, 3))
        q = np.empty((self._n, nt if want_q else 0, 4))
        qv = np.broadcast_to(_IDENTITY, (self._n, 4)).copy() if principal else self._qv
        first_call(kern.evaluate, self._n * nt * 1e-4)(
            np.ascontiguousarray(t, dtype=np.float64),
            self._par,
            self._idx,
            self._mom_s,
            self._amp,
            self._vec,
            self._qa,
            self._qb,
            qv,
            self._ks,
            self._kps,
            want_q,
            w,
            q,
        )
        return w, q

    def _times(self, t: ArrayLike) -> tuple[np.ndarray, tuple[int, ...]]:
        ta = as_float_array(t, "t")
        return ta.reshape(-1), ta.shape

    def omega(self, t: ArrayLike) -> FloatArray:
        """Body angular velocity at times ``t`` (rad/s).

        Parameters
        ----------
        t : array_like, any shape
            Times (s) since the initial state.

        Returns
        -------
        ndarray, shape ``shape + t.shape + (3,)``

        Notes
        -----
        ``w_i = a_i dn(u)``, ``w_m = a_m sn(u)``, ``w_j = a_j cn(u)``,
        ``u = lam t + u0`` (module notes, docs/theory.md §10).

        **Convention:** body axes of the given inertia, rad/s.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> FreeRigidBody([2.0, 2.0, 1.0], omega0=[1.0, 0.0, 2.0]).omega([0.0, 1.0]).round(6)
        array([[ 1.      ,  0.      ,  2.      ],
               [ 0.540302, -0.841471,  2.      ]])
        """
        tf, tshape = self._times(t)
        w, _ = self._eval(tf, False)
        return w.reshape(self._shape + tshape + (3,))

    def momentum_body(self, t: ArrayLike) -> FloatArray:
        """Angular momentum ``J w(t)`` in body axes, shape ``shape + t.shape + (3,)``.

        **Convention:** body axes of the given inertia (kg m^2/s).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 1.0, 1.0]).momentum_body(0.0)
        array([1., 2., 3.])
        """

        tf, tshape = self._times(t)
        w, _ = self._eval(tf, False)
        k = angular_momentum(self.inertia.reshape(self._n, 1, 3, 3), w)
        return k.reshape(self._shape + tshape + (3,))

    def _state(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        tf, tshape = self._times(t)
        w, q = self._eval(tf, True)
        return w.reshape(self._shape + tshape + (3,)), q.reshape(self._shape + tshape + (4,))

    def rotation(self, t: ArrayLike) -> Rotation:
        """Attitude (body -> space) at times ``t``, a Rotation of shape ``shape + t.shape``.

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
        >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0])   # the major axis
        >>> body.rotation(np.pi / 2).as_rotvec().round(12) + 0.0
        array([0.        , 0.        , 1.57079633])
        """
        return Rotation.from_quat(self._state(t)[1])

    def state(self, t: ArrayLike) -> tuple[FloatArray, Rotation]:
        """``(omega(t), rotation(t))`` in one pass (cheaper than two calls).

        **Convention:** as :meth:`omega` and :meth:`rotation`.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> w, r = FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 0.5, 0.2]).state([0.0, 1.0, 2.0])
        >>> w.shape, r.shape
        ((3, 3), (3,))
        """
        w, q = self._state(t)
        return w, Rotation.from_quat(q)

    def trajectory(self, t: ArrayLike, *, progress: Progress = None) -> Trajectory:
        """The exact motion sampled at 1-D times ``t`` as a :class:`~poinsot.Trajectory`.

        Time is the first axis: ``omega`` has shape ``(n,) + shape + (3,)``.
        ``energy`` and ``momentum`` are evaluated from the samples
        (``T = w^T J w / 2``, ``K = R J w``, :mod:`poinsot.dynamics.invariants`), so
        their drifts measure round-off. ``info``: ``regime`` (a str, or a tuple of
        str for a batch), ``closed_form`` (``"jacobi"``).

        **Convention:** as :class:`~poinsot.Trajectory` (body ``omega``, space ``momentum``).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 0.5, 0.2])
        >>> tr = body.trajectory([0.0, 5.0, 10.0])
        >>> tr.method, tr.energy_drift < 1e-14
        ('exact', True)

        ``progress``: True (a bar), a callable receiving the fraction done, or None. A grid
        of more than 65536 times is evaluated in chunks, between which Ctrl-C stops it
        (``KeyboardInterrupt``).
        """

        ta = as_float_array(t, "t")
        if ta.ndim != 1:
            raise InvalidInputError(f"Expected `t` to have shape (n,), got {ta.shape}.")
        # a large grid in chunks: Ctrl-C between them, progress (bit-identical results)
        w, q = in_chunks(lambda tc: self._eval(tc, True), ta, progress, "FreeRigidBody", axis=1)
        w = np.moveaxis(w, 1, 0)
        q = np.moveaxis(q, 1, 0)
        inv = invariants(self.inertia.reshape(1, self._n, 3, 3), q, w)
        lead = (ta.shape[0],) + self._shape
        regime = (
            self.regime
            if self._shape == ()
            else tuple(np.asarray(self.regime).reshape(-1).tolist())
        )
        return Trajectory(
            ta,
            Rotation.from_quat(q.reshape(lead + (4,))),
            w.reshape(lead + (3,)),
            "exact",
            energy=inv.kinetic.reshape(lead),
            momentum=inv.momentum_space.reshape(lead + (3,)),
            info={
                "regime": regime,
                "closed_form": "jacobi",
                "torque": "none",
                "conserved": ("energy", "momentum"),
            },
        )

    def __getitem__(self, key: int | slice | tuple[Any, ...]) -> FreeRigidBody:
        """One body (or a sub-batch) of a batch, e.g. ``bodies[3]``.

        >>> from poinsot.dynamics import FreeRigidBody
        >>> FreeRigidBody([[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]], omega0=[0.3, 0.2, 1.0])[1].regime
        'symmetric'
        """
        if self._shape == ():
            raise InvalidTypeError("Expected a batch of bodies to index, got a single body.")
        sel = np.arange(self._n).reshape(self._shape)[key]
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        flat = np.asarray(sel).reshape(-1)
        new._shape = np.shape(sel)
        new._n = flat.size
        for name in (
            "_moments", "_qv", "_omega0", "_q0", "_wscale", "_mom_s", "_par", "_idx", "_amp",
            "_vec", "_qa", "_qb", "_ks", "_kps", "_info", "_code", "_energy", "_momentum",
            "_kmom",
        ):  # fmt: skip
            setattr(new, name, np.ascontiguousarray(getattr(self, name)[flat]))
        return new

    def __len__(self) -> int:
        if self._shape == ():
            raise InvalidTypeError("Expected a batch of bodies for len(), got a single body.")
        return self._shape[0]

    # -- geometry (one body) --------------------------------------------------
    def _single(self, what: str) -> None:
        if self._shape != ():
            raise InvalidInputError(
                f"The {what} picture is drawn for one body: select one of the batch of "
                f"shape {self._shape}, e.g. `bodies[0].{what.lower()}()`."
            )
        if self._kmom[0] == 0.0:
            raise InvalidInputError(
                f"The {what} picture needs a moving body: `omega0` is zero (T = K = 0)."
            )

    def _window(self, n_periods: float) -> float:
        kern = _kernels()
        period = self._info[0, 1]
        ws = self._wscale[0]
        if math.isfinite(period):
            return n_periods * period / ws
        if self._par[0, kern.P_MODE] == kern.SEPARATRIX:
            u0, lam = self._par[0, kern.P_U0], self._par[0, kern.P_LAM]
            return max(10.0 - u0, 1.0) / (lam * ws)
        return 2.0 * math.pi * n_periods / ws

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
        ``K_A^2 (1/B - 1/A) = K_C^2 (1/C - 1/B)`` (docs/theory.md §10). One body only.

        **Convention:** principal body axes (order of :attr:`principal_moments`).

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> g = FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 1.0, 1.0]).maccullagh(50)
        >>> g.ellipsoid_semi_axes.round(4), g.track.shape, g.separatrices.shape
        (array([2.4495, 3.4641, 4.2426]), (50, 3), (2, 50, 3))
        """
        n = _samples(n)
        self._single("MacCullagh")
        kern = _kernels()
        mom = self._moments[0]
        two_t = 2.0 * float(self._energy[0])
        ws = self._wscale[0]
        if self._par[0, kern.P_MODE] == kern.SEPARATRIX:
            u0, lam = self._par[0, kern.P_U0], self._par[0, kern.P_LAM]
            t = (np.linspace(-10.0, 10.0, n) - u0) / (lam * ws)
        else:
            t = np.linspace(0.0, self._window(1.0), n)
        track = self._eval(t, False, principal=True)[0][0] * mom
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
            momentum_radius=float(self._kmom[0]),
            ellipsoid_semi_axes=np.sqrt(two_t * mom),
            track=track,
            separatrices=seps,
        )

    def poinsot(self, t: ArrayLike | None = None, n: int = 400) -> PoinsotGeometry:
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
        (docs/theory.md §10): the invariable plane. One body only.

        **Convention:** polhode in principal body axes, herpolhode and plane in
        space axes.

        Examples
        --------
        >>> from poinsot.dynamics import FreeRigidBody
        >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[1.0, 1.0, 1.0])
        >>> g = body.poinsot(n=100)
        >>> round(g.plane_distance, 6), round((2 * body.energy) ** 0.5 / body.momentum_norm, 6)
        (0.654654, 0.654654)
        """
        n = _samples(n)
        self._single("Poinsot")
        if t is None:
            ta = np.linspace(0.0, self._window(3.0), n)
        else:
            ta = as_float_array(t, "t")
            if ta.ndim != 1 or ta.size == 0:
                raise InvalidInputError(
                    f"Expected `t` to have shape (n,) with n >= 1, got {ta.shape}."
                )
        w, q = self._eval(ta, True, principal=True)
        two_t = 2.0 * float(self._energy[0])
        r = w[0] / math.sqrt(two_t)
        kmom = float(self._kmom[0])
        return PoinsotGeometry(
            ellipsoid_semi_axes=1.0 / np.sqrt(self._moments[0]),
            plane_normal=self._momentum[0] / kmom,
            plane_distance=math.sqrt(two_t) / kmom,
            t=ta,
            polhode=r,
            herpolhode=_quaternion.rotate(q[0], r),
            rotation=Rotation.from_quat(q[0]),
        )

    def __repr__(self) -> str:
        if self._shape != ():
            return f"FreeRigidBody(shape={self._shape})"
        return (
            f"FreeRigidBody(principal_moments={self._moments[0].tolist()}, "
            f"omega0={self._omega0[0].tolist()}, regime={self.regime!r})"
        )
