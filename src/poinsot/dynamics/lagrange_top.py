"""The Lagrange top (heavy symmetric top) in closed form.

A body with one fixed point ``O`` in uniform gravity ``g`` (along ``-z`` of space),
symmetric about its body axis ``e_3`` (equatorial moment ``A``, axial moment ``C``,
both about ``O``), with its centre of mass on that axis at the signed distance
``l`` from ``O`` (docs/theory.md §10). With the z-x-z Euler angles (precession
``psi``, nutation ``theta`` = tilt of ``e_3`` from the upward vertical, spin
``phi``) and ``u = cos(theta)`` the first integrals are

    H = C r,   K_z = A psi' sin^2(theta) + H u,
    E = A (theta'^2 + psi'^2 sin^2(theta)) / 2 + m g l u   (the spin energy C r^2/2 left out),

and ``u`` obeys ``u'^2 = P(u) = (2/A)(E - m g l u)(1 - u^2) - (K_z - H u)^2 / A^2``,
a cubic with roots ``u1 <= u2 <= 1 <= u3`` (``m g l > 0``); ``u`` oscillates in
``[u1, u2]`` (nutation) and

    psi' = (K_z - H u) / (A (1 - u^2)),   phi' = H / C - psi' u.

**Roots to full precision.** ``P`` is expanded about the initial ``u0``:
``P(u0 + x) = c3 x^3 + c2 x^2 + c1 x + c0`` with ``c3 = 2 m g l / A``,
``c2 = -w^2 + 2 c3 u0 - H^2/A^2``, ``c1 = -2 u0 w^2 - c3 s^2 + 2 H L / A``,
``c0 = V^2``, where ``w^2 = p^2 + q^2`` (transverse rate), ``s^2 = sin^2 theta0``,
``L = psi' s^2 = p gamma_1 + q gamma_2`` and ``V = u0' = gamma_1 q - gamma_2 p``
(``gamma = R^T e_z``) are taken from the initial state without cancellation.
``P(-1) <= 0 <= P(u0) = c0`` and ``P(1) <= 0`` bracket ``x1`` in ``[-(1 + u0), 0]``
and ``x2`` in ``[0, 1 - u0]`` (``1 +- u0`` from the half-angles of the
quaternion); safeguarded Newton brings them to round-off, ``x3`` follows by Vieta
and is polished. When ``V = 0`` (``theta' = 0``: released from rest, regular
precession, sleeping) ``x = 0`` is an exact root and the cubic is deflated.

**Exact motion.** ``u = u1 + (u2 - u1) sn^2(tau | m)``, ``tau = tau' t + tau0``,
``m = (u2 - u1)/(u3 - u1)``, ``tau' = sqrt(m g l (u3 - u1) / (2 A))``; the nutation
period is ``2 K(m) / tau'``. The attitude is written with the Cayley-Klein
angles ``sigma = psi + phi``, ``delta = psi - phi``:

    q = (cos(theta/2) cos(sigma/2), sin(theta/2) cos(delta/2),
         sin(theta/2) sin(delta/2), cos(theta/2) sin(sigma/2)),
    sigma' = (K_z + H) / (A (1 + u)) + H/C - H/A,
    delta' = (K_z - H) / (A (1 - u)) - H/C + H/A,

each with a single pole (``u = -1`` resp. ``u = 1``) that is harmless: where
``u`` reaches ``1`` the coefficient ``K_z - H`` vanishes. With
``1 -+ u = (1 -+ u1)(1 - n_+- sn^2)``, ``n_+ = (u2 - u1)/(1 - u1)``,
``n_- = -(u2 - u1)/(1 + u1)``, both integrate to incomplete elliptic integrals of
the third kind ``Pi(n; tau) = int_0^tau dv / (1 - n sn^2 v)`` (Carlson's ``R_J``,
:mod:`poinsot.dynamics._elliptic`), so ``psi(t)`` and ``phi(t)`` are exact; the
precession over one nutation period is
``Delta psi = (K_z - H) Pi(n_+ | m) / (A (1 - u1) tau')
+ (K_z + H) Pi(n_- | m) / (A (1 + u1) tau')``.

**Precession to full relative precision.** ``psi = (sigma + delta) / 2`` cancels the
parts ``+-H/A`` of ``sigma'``, ``delta'``: a fast top's slow ``psi ~ m g l t / H``
would keep only ``ulp(r t)`` absolute. ``psi(t)`` is integrated directly instead, with
``K_z - H u = (K_z - H u1) cn^2 + (K_z - H u2) sn^2`` and ``2 / (1 - u^2) = 1 / (1 - u)
+ 1 / (1 + u)``: small coefficients (``K_z - H u1,2 = A L - H x1,2`` from the initial
state, ``0`` at a cusp) times the positive integrals ``int sn^2 / (1 - n sn^2)
= s^3 R_J(c^2, d^2, 1, 1 - n s^2) / 3`` and ``int cn^2 / (1 - n sn^2)``; no
cancellation unless ``psi'`` changes sign (loops).

Degenerate cases are exact, not limits: regular precession (``u1 = u2``) and the
sleeping top (``u = 1``) turn uniformly; where the band reaches a pole
(``K_z = +-H``) ``sin(theta/2)`` (``cos``) is taken signed (``~ cn``, ``~ sn``) so
that the attitude passes smoothly through the vertical; the separatrix
(``u2 = u3 = 1``, ``m = 1``) uses the hyperbolic forms; ``m g l < 0`` (centre of
mass below ``O``) is the same motion with the body axis reversed
(``R -> R Rx(pi)``); ``m g l = 0`` is the free symmetric top and delegates to
:class:`poinsot.dynamics.FreeRigidBody`.

The array functions of regular precession, the sleeping top and the gyroscope are
in :mod:`poinsot.dynamics.gyroscope` (re-exported here), the bracketed Newton
iteration for the roots in :mod:`poinsot.dynamics._lagrange_roots`.

**Convention:** ``rotation(t)`` maps body components to space components
(``v_s = R v_b``), body axes with ``e_3`` the symmetry axis; Euler angles z-x-z
intrinsic (``R = Rz(psi) Rx(theta) Rz(phi)``, docs/theory.md §3); ``omega`` in
body axes (rad/s); ``theta`` from the *upward* vertical; SI units.
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _display
from .._jit import first_call
from .._progress import Progress, in_chunks
from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_float_array, as_rotation_quat, as_vec3
from ..errors import GimbalLockWarning, InvalidInputError
from ..rotations import quaternion
from ..rotations._scalar import vertical
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory
from ._lagrange_roots import _cubic, _polish, _rtsafe
from .free_body import FreeRigidBody
from .gyroscope import (
    GyroscopicMoment,
    _angle,
    critical_spin,
    gyroscope_precession_rate,
    gyroscopic_moment,
    regular_precession_rates,
    sleeping_top_stable,
)
from .heavy import HeavyRigidBody
from .invariants import invariants
from .torques import GravityTorque

if TYPE_CHECKING:
    from .free_body import FreeRigidBody
    from .heavy import HeavyRigidBody

__all__ = [
    "LagrangeTop",
    "MOTION_TYPES",
    "regular_precession_rates",
    "gyroscope_precession_rate",
    "critical_spin",
    "sleeping_top_stable",
    "gyroscopic_moment",
    "GyroscopicMoment",
]

#: The values of :attr:`LagrangeTop.motion_type`.
MOTION_TYPES = (
    "regular precession",
    "waves",
    "cusps",
    "loops",
    "sleeping",
    "asymptotic",
    "pendulum",
)

_EPS = float(np.finfo(float).eps)
#: psi' at a band edge within this fraction of the largest psi' scale counts as zero (cusps).
CUSP_RTOL = 1e-10
#: ``|c1|`` within this many eps of its terms: the double root of regular precession.
_DOUBLE_ROOT_EPS = 64.0
_PI_X = np.array([0.0, 1.0, 0.0, 0.0])  # Rx(pi)


# ---------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------


def _scalar(x: ArrayLike, name: str) -> float:
    a = as_float_array(x, name)
    if a.ndim != 0:
        raise InvalidInputError(f"Expected `{name}` to be a scalar, got shape {a.shape}.")
    return float(a)


def _moments(
    a: ArrayLike, c: ArrayLike, names: tuple[str, str] = ("A", "C")
) -> tuple[float, float]:
    """``A > 0``, ``C > 0`` and ``C <= 2 A`` (the triangle inequality ``A + B >= C``)."""
    av = _scalar(a, names[0])
    cv = _scalar(c, names[1])
    for n, v in zip(names, (av, cv), strict=True):
        if not v > 0:
            raise InvalidInputError(f"Expected `{n}` to be positive (kg m^2), got {v!r}.")
    if cv > 2.0 * av * (1.0 + 4 * _EPS):
        raise InvalidInputError(
            f"Expected `{names[1]}` <= 2 `{names[0]}` (triangle inequality A + B >= C of a "
            f"rigid body), got {names[0]}={av!r}, {names[1]}={cv!r}."
        )
    return av, cv


# ---------------------------------------------------------------------------
# The top
# ---------------------------------------------------------------------------


class _State:
    """Constants of one top in the frame where ``m g l >= 0`` (internal)."""

    # Set by LagrangeTop._setup and the steps it calls (_roots, _classify,
    # _motion_constants); declared for the type checker (no class attributes).
    q: np.ndarray
    om: float
    op: float
    u0: float
    s2: float
    L: float
    V: float
    w2: float
    H: float
    r: float
    g: float
    p: float
    qq: float
    kmh: float
    kph: float
    y2: float
    y3: float
    coef: tuple[float, float, float, float]
    double: bool
    x: tuple[float, float, float]
    sorted: tuple[float, ...]
    unstable_vertical: bool
    kind: str
    ws: float
    free: bool
    body: FreeRigidBody
    period: float
    sig_rate: float
    del_rate: float
    sig0: float
    del0: float
    wps: float
    sign0: tuple[float, float]
    par: np.ndarray
    fp: np.ndarray
    fm: np.ndarray


def _zxz_quat(psi: float, theta: float, phi: float) -> np.ndarray:
    """``Rz(psi) Rx(theta) Rz(phi)``; ``theta = pi`` gives ``cos(theta/2) = 0`` exactly."""
    s, c = math.sin, math.cos
    ch = 0.0 if theta == math.pi else c(0.5 * theta)
    sh = s(0.5 * theta)
    return np.array(
        [
            ch * c(0.5 * (psi + phi)),
            sh * c(0.5 * (psi - phi)),
            sh * s(0.5 * (psi - phi)),
            ch * s(0.5 * (psi + phi)),
        ]
    )


def _flip(q: np.ndarray) -> np.ndarray:
    """``q o (0, 1, 0, 0)``: the attitude with the body axes ``e_2, e_3`` reversed."""

    return quaternion.multiply(q, _PI_X)


class LagrangeTop:
    """The exact motion of the heavy symmetric (Lagrange) top (docs/theory.md §10).

    Parameters
    ----------
    A, C : float
        Equatorial and axial moments of inertia about the fixed point (kg m^2);
        ``A > 0``, ``C > 0``, ``C <= 2 A``.
    mgl : float
        ``m g l`` (N m): ``l`` is the signed distance from the fixed point to the
        centre of mass along the symmetry axis ``e_3``; ``mgl < 0`` (centre of mass
        below the point: a hanging top) and ``mgl = 0`` (free symmetric top) are valid.
    theta : float
        Initial tilt of the symmetry axis from the upward vertical, in ``[0, pi]``.
    theta_rate : float, optional
        ``theta'`` at ``t = 0`` (rad/s). Default 0.
    precession_rate : float, optional
        ``psi'`` at ``t = 0`` (rad/s). Default 0.
    spin : float
        ``r``, the axial component of the angular velocity in body axes (rad/s),
        constant (``H = C r``).
    psi, phi : float, optional
        Initial precession and spin angles (z-x-z); default 0.
    degrees : bool, optional
        ``theta``, ``psi`` and ``phi`` in degrees (the rates stay in rad/s).

    Attributes
    ----------
    A, C, mgl : float
    H, K_z, E : float
        The integrals ``C r``, ``K . e_z`` (kg m^2/s) and the reduced energy
        ``A (theta'^2 + psi'^2 sin^2 theta)/2 + m g l cos theta`` (J) of
        docs/theory.md §10 (without the constant ``C r^2 / 2``; :attr:`energy`
        is the total).

    Notes
    -----
    The formulas and the treatment of the degenerate cases are in the module
    docstring of :mod:`poinsot.dynamics.lagrange_top`. Evaluate with
    :meth:`theta`, :meth:`psi`, :meth:`phi`, :meth:`rotation`, :meth:`omega`,
    :meth:`state`, :meth:`trajectory` at times ``t`` of any shape (s, from the
    initial state at ``t = 0``). One top per object.

    **Convention:** ``rotation(t)`` body -> space; body ``e_3`` the symmetry axis;
    z-x-z Euler angles; gravity along ``-z`` of space; ``omega`` in body axes.

    **Accuracy:** periods, bounds and precession to ~1e-14 relative and attitudes to
    ~1e-13 rad against 60-digit references, also released within 1e-8 rad of the
    upright, near the separatrix and for fast tops; the attitude of a very fast top
    carries ~30 ulps of the spin angle ``r t`` (7e-9 rad at ``r = 1e6`` rad/s,
    ``t = 0.5`` s), while ``psi(t)`` keeps full relative precision (4e-16 at
    ``r = 1e6``, ``t = 7`` s). Table and method: docs/heavy-top.md ("Numerical notes").

    Examples
    --------
    A top released from rest at 30 degrees with a fast spin: cusps at the start.

    >>> import numpy as np
    >>> from poinsot.dynamics import LagrangeTop
    >>> top = LagrangeTop(2.0, 1.0, 4.0, theta=30.0, spin=20.0, degrees=True)
    >>> top.motion_type
    'cusps'
    >>> [round(float(np.degrees(b)), 4) for b in top.nutation_bounds]
    [30.0, 31.2087]
    >>> bool(top.theta(0.0) == np.radians(30.0)), round(top.nutation_period, 6)
    (True, 0.651059)
    >>> bool(np.isclose(top.theta(top.nutation_period / 2), top.nutation_bounds[1]))
    True
    """

    def __init__(
        self,
        A: ArrayLike,
        C: ArrayLike,
        mgl: ArrayLike,
        *,
        theta: ArrayLike,
        theta_rate: ArrayLike = 0.0,
        precession_rate: ArrayLike = 0.0,
        spin: ArrayLike,
        psi: ArrayLike = 0.0,
        phi: ArrayLike = 0.0,
        degrees: bool = False,
    ) -> None:
        a, c = _moments(A, C)
        g = _scalar(mgl, "mgl")
        deg = as_bool(degrees, "degrees")
        th = float(_angle(_scalar(theta, "theta"), "theta", deg, lo=0.0, hi=math.pi))
        ps = float(_angle(_scalar(psi, "psi"), "psi", deg))
        ph = float(_angle(_scalar(phi, "phi"), "phi", deg))
        thd = _scalar(theta_rate, "theta_rate")
        psd = _scalar(precession_rate, "precession_rate")
        r = _scalar(spin, "spin")
        q0 = _zxz_quat(ps, th, ph)
        st = math.sin(th)
        w0 = np.array(
            [
                psd * st * math.sin(ph) + thd * math.cos(ph),
                psd * st * math.cos(ph) - thd * math.sin(ph),
                r,
            ]
        )
        self._setup(a, c, g, q0, w0, ps, ph, th)

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: parameters, integrals, motion type, nutation bounds and periods."""
        d = _display
        lo, hi = self.nutation_bounds
        rows = [
            ("A, C (about O)", d.value([self.A, self.C], "kg m^2")),
            ("m g l", d.value(self.mgl, "N m")),
            ("spin r", d.value(self.spin, "rad/s")),
            ("H = C r, K_z", d.value([self.H, self.K_z], "kg m^2/s")),
            ("energy", d.value(self.energy, "J")),
            ("motion", d.esc(self.motion_type)),
            ("nutation theta", d.value(np.degrees([lo, hi]), "deg")),
            ("nutation period", d.value(self.nutation_period, "s")),
            ("mean precession rate", d.value(self.mean_precession_rate, "rad/s")),
        ]
        note = "z-x-z Euler angles, gravity along -z, omega in body axes (docs/theory.md §10)"
        return d.table("LagrangeTop", rows, note)

    # -- construction --------------------------------------------------------
    @classmethod
    def from_state(
        cls,
        body_or_moments: HeavyRigidBody | ArrayLike,
        mgl: ArrayLike | None = None,
        rotation: Rotation | ArrayLike | None = None,
        omega: ArrayLike | None = None,
    ) -> LagrangeTop:
        """A Lagrange top from an attitude and a body angular velocity.

        Parameters
        ----------
        body_or_moments : HeavyRigidBody or array_like, shape (3,) or (3, 3)
            A :class:`~poinsot.dynamics.HeavyRigidBody` (``mgl`` is then taken from
            its mass, ``g`` and centre of mass), or the principal moments
            ``(A, A, C)`` / the inertia tensor about the fixed point in body axes.
            The symmetry axis must be the body ``z`` axis.
        mgl : float, optional
            ``m g l`` (N m); required unless a ``HeavyRigidBody`` is given.
        rotation : Rotation, scipy Rotation or array_like (4,)
            Attitude, body -> space (scalar-first quaternion).
        omega : array_like, shape (3,)
            Angular velocity in body axes (rad/s).

        Raises
        ------
        InvalidInputError
            If the body is not a Lagrange top (``A != B``, the body ``z`` axis not
            principal, the centre of mass off the symmetry axis), naming the
            condition; unphysical moments; NaN/inf.

        Examples
        --------
        >>> from poinsot.dynamics import LagrangeTop
        >>> from poinsot import Rotation
        >>> r = Rotation.from_euler("ZXZ", [0.0, 0.5, 0.0])
        >>> top = LagrangeTop.from_state([2.0, 2.0, 1.0], 4.0, r, [0.0, 0.0, 20.0])
        >>> top.motion_type, round(top.H, 12)
        ('cusps', 20.0)
        """

        rtol = 1e-12
        if isinstance(body_or_moments, HeavyRigidBody):
            body = body_or_moments
            j = body.inertia_tensor
            cvec = body.center_of_mass
            lc = float(np.hypot(cvec[0], cvec[1]))
            if lc > rtol * float(np.linalg.norm(cvec)):
                raise InvalidInputError(
                    "Expected the centre of mass on the symmetry (body z) axis for a Lagrange "
                    f"top, got center_of_mass = {cvec.tolist()} (off the axis by {lc:.3g} m)."
                )
            g_mgl = float(body.mass * body.g * cvec[2])
            if mgl is not None and not math.isclose(_scalar(mgl, "mgl"), g_mgl, rel_tol=1e-12):
                raise InvalidInputError(
                    f"Expected `mgl` to be None or the body's m g l = {g_mgl!r}, got {mgl!r}."
                )
            mgl = g_mgl
        else:
            j = as_float_array(body_or_moments, "body_or_moments")
            if j.shape == (3,):
                j = np.diag(j)
            elif j.shape != (3, 3):
                raise InvalidInputError(
                    "Expected `body_or_moments` to be a HeavyRigidBody, principal moments (3,) "
                    f"or an inertia tensor (3, 3), got shape {j.shape}."
                )
            if mgl is None:
                raise InvalidInputError("Expected `mgl` (N m) with moments or a tensor, got None.")
        scale = float(np.max(np.abs(j)))
        if not scale > 0:
            raise InvalidInputError("Expected positive moments of inertia, got zeros.")
        if abs(j[0, 2]) + abs(j[1, 2]) > rtol * scale:
            raise InvalidInputError(
                "Expected the body z axis to be a principal axis (the symmetry axis of a "
                f"Lagrange top), got J13 = {j[0, 2]!r}, J23 = {j[1, 2]!r}."
            )
        if abs(j[0, 0] - j[1, 1]) > rtol * scale or abs(j[0, 1]) > rtol * scale:
            raise InvalidInputError(
                "Expected A = B (a body symmetric about its z axis) for a Lagrange top, got "
                f"equatorial moments J11 = {j[0, 0]!r}, J22 = {j[1, 1]!r}, J12 = {j[0, 1]!r}."
            )
        a, c = _moments(0.5 * (j[0, 0] + j[1, 1]), j[2, 2], names=("A", "C"))
        g = _scalar(mgl, "mgl")
        if rotation is None or omega is None:
            raise InvalidInputError(
                "Expected `rotation` and `omega` (the initial state), got None."
            )
        q0 = as_rotation_quat(rotation, "rotation")
        if q0.shape != (4,):
            raise InvalidInputError(f"Expected one `rotation`, got shape {q0.shape[:-1]}.")
        w0 = as_vec3(omega, "omega")
        if w0.shape != (3,):
            raise InvalidInputError(f"Expected `omega` to have shape (3,), got {w0.shape}.")
        with warnings.catch_warnings():  # at theta = 0 or pi the split psi/phi is a convention
            warnings.simplefilter("ignore", GimbalLockWarning)
            ps, th, ph = Rotation.from_quat(q0).as_euler("ZXZ")
        self = cls.__new__(cls)
        self._setup(a, c, g, np.array(q0, dtype=float), np.array(w0, dtype=float), ps, ph, th)
        return self

    def _setup(
        self,
        a: float,
        c: float,
        mgl: float,
        q0: np.ndarray,
        w0: np.ndarray,
        psi0: float,
        phi0: float,
        theta0: float,
    ) -> None:
        self._a, self._c, self._mgl = a, c, mgl
        self._q0 = q0
        self._w0 = w0
        self._psi0, self._phi0 = float(psi0), float(phi0)
        flip = mgl < 0
        self._flip = flip
        if flip:
            qf = _flip(q0)
            wf = np.array([w0[0], -w0[1], -w0[2]])
            g = -mgl
        else:
            qf, wf, g = q0, w0, mgl
        qf = qf / math.sqrt(float(qf @ qf))
        s = _State()
        self._s = s
        q_0, q_1, q_2, q_3 = (float(x) for x in qf)
        p, qq, r = (float(x) for x in wf)
        s.q = qf
        s.om = 2.0 * (q_1 * q_1 + q_2 * q_2)  # 1 - u0 = 2 sin^2(theta/2)
        s.op = 2.0 * (q_0 * q_0 + q_3 * q_3)  # 1 + u0
        s.u0 = 0.5 * (s.op - s.om)
        gam1, gam2, _ = vertical(q_0, q_1, q_2, q_3)  # gamma_1, gamma_2 (R^T e_z)
        s.s2 = s.om * s.op  # sin^2(theta0)
        s.L = p * gam1 + qq * gam2  # psi' sin^2 theta
        s.V = gam1 * qq - gam2 * p  # u0'
        s.w2 = p * p + qq * qq
        s.H = c * r
        s.r = r
        s.g = g
        s.p, s.qq = p, qq
        big_h = s.H
        # integrals (the original frame: K_z, E unchanged by the flip; H -> -H)
        self._H = -big_h if flip else big_h
        self._Kz = a * s.L + big_h * s.u0
        self._E = 0.5 * a * s.w2 + g * s.u0
        s.kmh = a * s.L - big_h * s.om  # K_z - H
        s.kph = a * s.L + big_h * s.op  # K_z + H
        if abs(s.kmh) <= 16 * _EPS * (abs(a * s.L) + abs(big_h * s.om)):
            s.kmh = 0.0
        if abs(s.kph) <= 16 * _EPS * (abs(a * s.L) + abs(big_h * s.op)):
            s.kph = 0.0
        c3 = 2.0 * g / a
        c2 = -s.w2 + 2.0 * c3 * s.u0 - (big_h / a) ** 2
        c1 = -2.0 * s.u0 * s.w2 - c3 * s.s2 + 2.0 * big_h * s.L / a
        c0 = s.V * s.V
        s.coef = (c3, c2, c1, c0)
        c1_scale = 2.0 * abs(s.u0) * s.w2 + c3 * s.s2 + 2.0 * abs(big_h * s.L) / a
        if c0 == 0.0 and abs(c1) <= _DOUBLE_ROOT_EPS * _EPS * c1_scale:
            c1 = 0.0
            s.coef = (c3, c2, c1, c0)
        self._roots(s)
        self._classify(s)
        self._motion_constants(s)

    def _roots(self, s: _State) -> None:
        c3, c2, c1, c0 = s.coef
        om, op = s.om, s.op
        f, df = _cubic(c3, c2, c1, c0)
        s.double = False
        if c3 == 0.0:  # free top: a quadratic (c2 = -|K|^2/A^2 <= 0)
            if c2 == 0.0:
                x1 = x2 = 0.0
            elif c0 == 0.0 and c1 == 0.0:
                x1 = x2 = 0.0
            else:
                disc = max(c1 * c1 - 4.0 * c2 * c0, 0.0)
                qd = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
                ra = qd / c2 if c2 != 0 else 0.0
                rb = c0 / qd if qd != 0 else 0.0
                x1, x2 = min(ra, rb), max(ra, rb)
                x1 = _polish(f, df, x1, -op, min(0.0, x2))
                x2 = _polish(f, df, x2, max(0.0, x1), om)
            s.x = (x1, x2, math.inf)
            s.double = x1 == x2
            return
        if c0 > 0.0:
            x1 = _rtsafe(f, df, -op, 0.0)
            x2 = _rtsafe(f, df, 0.0, om)
            x3 = -c2 / c3 - x1 - x2
            hi = max(x3, om)
            step = max(1.0, abs(hi))
            while f(hi) <= 0.0:
                hi += step
                step *= 2.0
            x3 = _rtsafe(f, df, om, hi) if f(om) < 0.0 else om
        else:
            g2, dg2 = _cubic(0.0, c3, c2, c1)  # P(x) / x
            if c1 == 0.0:
                x1 = x2 = 0.0
                x3 = -c2 / c3
                s.double = True
            elif c1 > 0.0:
                x1 = 0.0
                x2 = _rtsafe(g2, dg2, 0.0, om)
                x3 = c1 / (c3 * x2) if x2 != 0.0 else -c2 / c3
            else:
                x2 = 0.0
                x1 = _rtsafe(g2, dg2, -op, 0.0)
                x3 = c1 / (c3 * x1) if x1 != 0.0 else -c2 / c3
            if not s.double:
                hi = max(x3, om)
                lo = om
                if g2(lo) < 0.0 < g2(hi):
                    x3 = _rtsafe(g2, dg2, lo, hi)
        # the lower pole: K_z = -H makes u = -1 a root (and a root there means K_z = -H)
        if not s.double and c3 != 0.0 and x1 <= -op:
            s.kph = 0.0
        if s.kph == 0.0 and not s.double:
            x1 = -op
        s.y2, s.y3 = om - x2, om - x3
        if not s.double and c3 != 0.0:
            x2, x3 = self._upper_roots(s, x1, x2, x3)
        xs = sorted((x1, x2, x3))
        if s.double and x3 < 0.0:
            # upright with a slow spin: roots (x3, 0, 0), u2 = u3 = 1
            s.x = (x1, x2, x3)
            s.unstable_vertical = True
        else:
            s.x = (x1, x2, x3) if not s.double else (0.0, 0.0, x3)
            s.unstable_vertical = False
        s.sorted = tuple(xs)

    def _upper_roots(self, s: _State, x1: float, x2: float, x3: float) -> tuple[float, float]:
        """``y2 = 1 - u2 >= 0`` and ``y3 = 1 - u3 <= 0`` (into ``s``) from ``P`` written in
        ``y = 1 - u``; returns ``(x2, x3)`` with the upper pole and the separatrix exact.

        ``x = u - u0`` keeps the band accurate relative to ``u0``; near the upright
        (``u2``, ``u3`` within round-off of 1) it cannot tell ``u2`` from 1, and
        ``1 - u2`` is what the half-angle ``sin(theta/2)``, the modulus
        ``m1 = (u3 - u2) / (u3 - u1)`` and the parameter ``1 - n+`` of the precession
        integral need. In ``y``, with ``k = (K_z - H)/A``, ``h = H/A``,
        ``e = 2 (E - m g l)/A = w2 - c3 (1 - u0)`` (each from the initial state without
        cancellation), ``P = -c3 y^3 + (2 c3 - e - h^2) y^2 + 2 (e - k h) y - k^2``:
        its roots near ``y = 0`` are as accurate as the problem allows.
        """
        a = self._a
        om, c3 = s.om, s.coef[0]
        h = s.H / a
        k = s.kmh / a
        e = s.w2 - c3 * om
        d3, d2, d1, d0 = -c3, 2.0 * c3 - e - h * h, 2.0 * (e - k * h), -k * k
        fy, dfy = _cubic(d3, d2, d1, d0)
        y1 = om - x1
        if k == 0.0:  # u = 1 a root: the other root of the quadratic P / y (Vieta)
            other = -d1 / (c3 * y1)
            y2, y3 = (other, 0.0) if other >= 0.0 else (0.0, other)
        else:
            if s.coef[3] == 0.0 and x2 == 0.0:  # released at the top of the band
                y2 = om
            else:  # f(0) = -k^2 < 0 < f(middle of the band)
                y2 = _rtsafe(fy, dfy, 0.0, om - 0.5 * (x1 + x2))
            y3 = -k * k / (c3 * y1 * y2)
        # no snapping onto the separatrix u2 = u3 = 1: a band a few ulps of input below
        # it has a finite period (1 - m ~ 1e-15), and y2, y3 from P in y are as accurate
        # as the inputs make them (issue 38: a snap at 64 eps put such a top 2.9 rad off)
        s.y2, s.y3 = y2, y3
        if y2 == 0.0 or y3 == 0.0:
            s.kmh = 0.0
        # near the pole the y-roots are the accurate ones (x2 > om by round-off was a
        # root above the pole); elsewhere x keeps the band accurate relative to u0, and
        # y = om - x without cancellation: a fast top's y1, y2 are a nearly double root
        # of P in y, ~1e-11 off (m1 = (y2 - y3) / (x3 - x1) then missed 1 - m by 3e-12:
        # K(m), 1 - n+ and psi of a nutating top with r = 1e5 ~1e-8 off)
        if y2 < 0.5 * om:
            x2 = om - y2
        else:
            s.y2 = om - x2
        if -y3 < 0.5 * om:
            x3 = om - y3
        else:
            s.y3 = om - x3
        return x2, x3

    def _classify(self, s: _State) -> None:
        x1, x2, x3 = s.x
        a, big_h = self._a, s.H
        if s.double:
            if s.s2 == 0.0:
                s.kind = "asymptotic" if s.unstable_vertical else "sleeping"
            else:
                s.kind = "regular precession"
            return
        if x2 == x3 == s.om and s.g > 0:
            s.kind = "asymptotic"
            return
        if big_h == 0.0 and a * s.L == 0.0:
            # no spin and no momentum about the vertical: psi' = 0 for ever, the axis
            # swings in a vertical plane (a spherical pendulum reduced to a plane one)
            s.kind = "pendulum"
            return
        n1 = a * s.L - big_h * x1  # K_z - H u at u1 (times 1)
        n2 = a * s.L - big_h * x2
        # at a pole the limit of psi' = (K_z - H u) / (A (1 - u^2)) is +-H / (2 A)
        if x2 == s.om and s.kmh == 0.0:
            n2 = big_h
        if x1 == -s.op and s.kph == 0.0:
            n1 = -big_h
        scale = max(abs(a * s.L), abs(big_h) * (x2 - x1), abs(n1), abs(n2))
        tol = CUSP_RTOL * scale
        z1, z2 = abs(n1) <= tol, abs(n2) <= tol
        if z1 or z2:
            s.kind = "cusps"
        elif (n1 > 0) == (n2 > 0):
            s.kind = "waves"
        else:
            s.kind = "loops"

    def _motion_constants(self, s: _State) -> None:
        from . import _elliptic as el

        a, c = self._a, self._c
        big_h = s.H
        s.ws = big_h / c - big_h / a
        x1, x2, x3 = s.x
        qf = s.q
        s.free = s.g == 0.0
        if s.free:
            s.body = FreeRigidBody(
                [a, a, c], omega0=self._w0, rotation0=Rotation.from_quat(self._q0)
            )
            c2 = s.coef[1]
            s.period = 2.0 * math.pi / math.sqrt(-c2) if c2 < 0 else math.inf
            return
        if s.double:
            # uniform: u = u0, sigma and delta linear in t
            s.sig_rate = s.kph / (a * s.op) + s.ws if s.op > 0 else 0.0
            s.del_rate = s.kmh / (a * s.om) - s.ws if s.om > 0 else 0.0
            s.sig0 = 2.0 * math.atan2(qf[3], qf[0])
            s.del0 = 2.0 * math.atan2(qf[2], qf[1])
            s.wps = s.L / math.sqrt(s.s2) if s.s2 > 0 else 0.0
            s.sign0 = (1.0, 1.0)
            s.period = 2.0 * math.pi / math.sqrt(s.g * 2.0 / a * x3) if x3 > 0 else math.inf
            return
        from . import _lagrange_numba as kn

        dx = x2 - x1
        x31 = x3 - x1
        m = dx / x31
        m1 = (s.y2 - s.y3) / x31  # y2 >= 0 >= y3: no cancellation near the upright
        rate = 0.5 * math.sqrt(2.0 * s.g / a * x31)
        om1 = s.om - x1
        op1 = s.op + x1
        par = np.zeros(kn.N_PAR)
        par[kn.P_RATE] = rate
        par[kn.P_M] = m
        par[kn.P_M1] = m1
        kq = float(el.ellipk(m, m1=m1))
        par[kn.P_K] = kq
        par[kn.P_DX] = dx
        par[kn.P_OM1] = om1
        par[kn.P_OP1] = op1
        par[kn.P_NP] = dx / om1
        par[kn.P_NP1] = s.y2 / om1  # 1 - n+, not rounded to 0 near the upright
        par[kn.P_Y2] = s.y2
        par[kn.P_NM] = -dx / op1 if op1 > 0 else -math.inf
        sps = x2 == s.om and s.kmh == 0.0
        spc = x1 == -s.op and s.kph == 0.0
        par[kn.P_CP] = 0.0 if s.kmh == 0.0 else s.kmh / (a * om1 * rate)
        par[kn.P_CM] = 0.0 if s.kph == 0.0 else s.kph / (a * op1 * rate)
        if m1 > 0.0:
            if par[kn.P_CP]:
                par[kn.P_PIP] = _complete_pi(par[kn.P_NP], par[kn.P_NP1], kq, m1)
            if par[kn.P_CM]:
                par[kn.P_PIM] = _complete_pi(par[kn.P_NM], 1.0 - par[kn.P_NM], kq, m1)
        par[kn.P_WS] = s.ws
        par[kn.P_SPS] = 1.0 if sps else 0.0
        par[kn.P_SPC] = 1.0 if spc else 0.0
        par[kn.P_KMH] = s.kmh
        par[kn.P_KPH] = s.kph
        par[kn.P_A] = a
        par[kn.P_H] = big_h
        par[kn.P_R] = s.r
        # tau0: sn^2(tau0) = -x1 / dx, cn^2 = x2 / dx, dn^2 = x3 / x31; sign of u0' = V
        rho = -x1 / dx
        if m1 == 0.0 and rho >= 1.0:  # pragma: no cover - the equilibrium is 'double'
            tau0 = math.inf
        else:
            tau0 = math.sqrt(rho) * float(el.elliprf(max(x2, 0.0) / dx, x3 / x31, 1.0))
        if s.V < 0.0:
            tau0 = -tau0
        par[kn.P_TAU0] = tau0
        s.fp = (
            _fourier(par[kn.P_NP], par[kn.P_NP1], m, m1, kq, par[kn.P_PIP])
            if par[kn.P_CP]
            else _EMPTY
        )
        s.fm = (
            _fourier(par[kn.P_NM], 1.0 - par[kn.P_NM], m, m1, kq, par[kn.P_PIM])
            if par[kn.P_CM]
            else _EMPTY
        )
        if not (sps or spc) and m1 > 0.0 and s.y2 > 0.0 and op1 > 0.0 and dx <= op1:
            # psi without the cancellation of sigma and delta (kernel psi_sum), where no
            # pole is reached (no jump of pi: js = jc = 0 in _angles) and 1 + u1 >=
            # u2 - u1 (G- = r - (1 - n-) S- keeps its digits); K_z - H u1,2 =
            # A L - H x1,2 from the initial state, exact at a cusp (from rest: L = x2 = 0)
            par[kn.P_PSI] = 1.0
            den = 2.0 * a * rate
            n1 = (a * s.L - big_h * x1) / den
            n2 = (a * s.L - big_h * x2) / den
            par[kn.P_Q1P], par[kn.P_Q1M] = n1 / om1, n1 / op1
            par[kn.P_Q2P], par[kn.P_Q2M] = n2 / om1, n2 / op1
            np1, nm1 = par[kn.P_NP1], 1.0 - par[kn.P_NM]
            sp = float(el.elliprj(0.0, m1, 1.0, np1)) / 3.0
            sm = float(el.elliprj(0.0, m1, 1.0, nm1)) / 3.0
            par[kn.P_FC] = (
                par[kn.P_Q1P] * (kq - np1 * sp)
                + par[kn.P_Q1M] * (kq - nm1 * sm)
                + par[kn.P_Q2P] * sp
                + par[kn.P_Q2M] * sm
            )
        sn0, cn0, dn0, pip0, pim0, f0 = first_call(kn.pi_at, 1e-3)(tau0, par, s.fp, s.fm)
        par[kn.P_PIP0] = pip0
        par[kn.P_PIM0] = pim0
        par[kn.P_F0] = f0
        # signed half-angle functions at t = 0 and the Cayley-Klein angles
        s_0 = math.sqrt(0.5 * om1) * cn0 if sps else math.sqrt(0.5 * (s.y2 + dx * cn0 * cn0))
        c_0 = (
            math.sqrt(0.5 * dx) * sn0 if spc else math.sqrt(max(0.5 * (op1 + dx * sn0 * sn0), 0.0))
        )
        if c_0 != 0.0:
            sg = 1.0 if c_0 > 0 else -1.0
            sig0 = 2.0 * math.atan2(sg * qf[3], sg * qf[0])
        if s_0 != 0.0:
            sg = 1.0 if s_0 > 0 else -1.0
            del0 = 2.0 * math.atan2(sg * qf[2], sg * qf[1])
        if c_0 == 0.0 or s_0 == 0.0:
            # at a pole: phi0 from the transverse angular velocity, q + i p = i theta' e^{i phi}
            rs = 1.0 / math.sqrt(0.5 * om1) if sps else cn0 / s_0
            rc = 1.0 / math.sqrt(0.5 * dx) if spc else sn0 / c_0
            wth = -dx * rate * dn0 * rs * rc
            sg = 1.0 if wth > 0 else -1.0
            ph0 = math.atan2(-sg * s.qq, sg * s.p)  # e^{i phi} = (p - i q) / theta'
            if c_0 == 0.0:
                sig0 = del0 + 2.0 * ph0
            else:
                del0 = sig0 - 2.0 * ph0
        par[kn.P_SIG0] = sig0
        par[kn.P_DEL0] = del0
        s.sign0 = (s_0, c_0)
        s.par = par
        s.period = 2.0 * kq / rate

    # -- integrals and properties -----------------------------------------------
    @property
    def A(self) -> float:
        """Equatorial moment about the fixed point (kg m^2)."""
        return self._a

    @property
    def C(self) -> float:
        """Axial moment about the fixed point (kg m^2)."""
        return self._c

    @property
    def mgl(self) -> float:
        """``m g l`` (N m)."""
        return self._mgl

    @property
    def H(self) -> float:
        """``H = C r``, the axial angular momentum (kg m^2/s), constant."""
        return self._H

    @property
    def spin(self) -> float:
        """``r`` (rad/s), the axial component of the angular velocity, constant."""
        return self._H / self._c

    @property
    def K_z(self) -> float:
        """The area integral ``K_z = A psi' sin^2(theta) + H cos(theta)`` (kg m^2/s)."""
        return self._Kz

    @property
    def E(self) -> float:
        """Reduced energy ``A (theta'^2 + psi'^2 sin^2 theta) / 2 + m g l cos theta`` (J)."""
        return self._E

    @property
    def energy(self) -> float:
        """Total mechanical energy ``T + V = E + C r^2 / 2`` (J)."""
        return self._E + 0.5 * self._c * self.spin**2

    def P(self, u: ArrayLike) -> FloatArray | float:
        """The cubic ``P(u) = (2/A)(E - m g l u)(1 - u^2) - (K_z - H u)^2 / A^2`` (1/s^2).

        ``u'^2 = P(u)`` with ``u = cos(theta)``; evaluated as the polynomial in
        ``x = u - u0`` (module notes), accurate near the roots.

        Examples
        --------
        >>> from poinsot.dynamics import LagrangeTop
        >>> top = LagrangeTop(2.0, 1.0, 4.0, theta=1.0, spin=20.0)
        >>> [abs(float(top.P(u))) < 1e-12 for u in top.cos_theta_roots[:2]]
        [True, True]
        """
        u = as_float_array(u, "u")
        c3, c2, c1, c0 = self._s.coef
        x = (-u if self._flip else u) - self._s.u0
        return (((c3 * x + c2) * x + c1) * x + c0)[()]

    def _u_roots(self) -> tuple[float, float, float]:
        s = self._s
        if s.free:
            x1, x2, _ = s.x
            us = [s.u0 + x1, s.u0 + x2, math.inf]
        else:
            us = [s.u0 + x for x in s.sorted]
        if self._flip:
            us = sorted(-u for u in us)
        u1, u2, u3 = us
        return u1, u2, u3

    @property
    def cos_theta_roots(self) -> tuple[float, float, float]:
        """The roots ``u1 <= u2 <= u3`` of ``P`` (``u = cos theta``).

        For ``m g l > 0`` the band is ``[u1, u2]`` and ``u3 >= 1``; for ``m g l < 0``
        the band is ``[u2, u3]`` and ``u1 <= -1``; for ``m g l = 0`` (``P`` is a
        quadratic) ``u3 = inf``.
        """
        return self._u_roots()

    def _theta_of_x(self, x: float) -> float:
        s = self._s
        th = 2.0 * math.atan2(
            math.sqrt(max(0.5 * (s.om - x), 0.0)), math.sqrt(max(0.5 * (s.op + x), 0.0))
        )
        return math.pi - th if self._flip else th

    @property
    def nutation_bounds(self) -> tuple[float, float]:
        """``(theta_min, theta_max)`` (rad), the band the symmetry axis nutates in."""
        s = self._s
        x1, x2 = s.x[0], s.x[1]
        ta, tb = self._theta_of_x(x2), self._theta_of_x(x1)
        return (min(ta, tb), max(ta, tb))

    @property
    def nutation_period(self) -> float:
        """Period of ``theta(t)``, ``2 K(m) / tau'`` (s); for regular precession the
        period of small nutations about it; ``inf`` on the separatrix."""
        return float(self._s.period)

    @property
    def motion_type(self) -> str:
        """One of :data:`MOTION_TYPES`, from the sign of ``psi'`` at the two bounds.

        ``"regular precession"`` (``u1 = u2``), ``"sleeping"`` (vertical axis,
        stable), ``"asymptotic"`` (on the separatrix ``u2 = u3 = 1``, including the
        unstable upright equilibrium), ``"cusps"`` (``psi' = 0`` at a bound, e.g.
        released from rest), ``"waves"`` (same sign), ``"loops"`` (opposite signs),
        ``"pendulum"`` (``H = K_z = 0``: no spin and no momentum about the vertical,
        the axis swings in a vertical plane with ``psi'`` identically 0).
        """
        return self._s.kind

    @property
    def maievskii_ratio(self) -> float:
        """``C^2 r^2 / (4 A m g l)``: the sleeping top is stable above 1 (``inf`` if
        ``m g l <= 0``)."""
        if self._mgl <= 0:
            return math.inf
        return self._H**2 / (4.0 * self._a * self._mgl)

    def psi_rate_at_bounds(self) -> tuple[float, float]:
        """``psi'`` at ``theta_min`` and ``theta_max`` (rad/s); at a pole the limit ``+-H/(2A)``."""
        s = self._s
        a = self._a
        out = []
        for x in (s.x[1], s.x[0]):
            num = a * s.L - s.H * x
            den = a * (s.om - x) * (s.op + x)
            if den == 0.0:
                v = s.H / (2.0 * a) if x == s.om else -s.H / (2.0 * a)
            else:
                v = num / den
            out.append(v)
        if self._flip:
            out = out[::-1]
        return (float(out[0]), float(out[1]))

    @property
    def precession_per_nutation(self) -> float:
        """The precession angle gained over one nutation period (rad)."""
        s = self._s
        if s.free:
            return float("nan")
        if s.double:
            return 0.5 * (s.sig_rate + s.del_rate) * s.period if s.s2 > 0 else float("nan")
        if not math.isfinite(s.period):
            return float("nan")
        from . import _lagrange_numba as kn

        par = s.par
        om1, op1 = par[kn.P_OM1], par[kn.P_OP1]
        if op1 == 0.0 or par[kn.P_M1] == 0.0:  # the lower pole reached / the separatrix
            return float(par[kn.P_CP] * par[kn.P_PIP] + par[kn.P_CM] * par[kn.P_PIM])
        # K_z - H u = (K_z - H u2) + H (u2 - u1) cn^2 splits psi' into two sums of
        # positive terms when the band is narrow (a fast top, K_z - H u2 ~ 0), where the
        # partial fractions (K_z -+ H) / (1 -+ u) cancel to ~ eps (C r)^2 / (A m g l)
        kq, m1 = par[kn.P_K], par[kn.P_M1]
        npl, npl1, nmi = par[kn.P_NP], par[kn.P_NP1], par[kn.P_NM]
        top_bound = self._a * s.L - s.H * s.x[1]  # K_z - H u2
        inv = 0.0
        if top_bound != 0.0:
            pi_p = par[kn.P_PIP] if par[kn.P_CP] else _complete_pi(npl, npl1, kq, m1)
            pi_m = par[kn.P_PIM] if par[kn.P_CM] else _complete_pi(nmi, 1.0 - nmi, kq, m1)
            inv = top_bound * (pi_p / om1 + pi_m / op1)
        band = s.H * par[kn.P_DX]
        if band != 0.0:
            g_p = _complete_g(npl, npl1, kq, m1)
            g_m = _complete_g(nmi, 1.0 - nmi, kq, m1)
            inv += band * (g_p / om1 + g_m / op1)
        return float(inv / (self._a * par[kn.P_RATE]))

    @property
    def mean_precession_rate(self) -> float:
        """Mean ``psi'`` over a nutation period (rad/s); on the separatrix the limit ``H/(2A)``."""
        s = self._s
        if s.double:
            return 0.5 * (s.sig_rate + s.del_rate) if s.s2 > 0 else float("nan")
        if not s.free and not math.isfinite(s.period):
            return s.H / (2.0 * self._a)
        return self.precession_per_nutation / s.period

    # -- evaluation ----------------------------------------------------------------
    def _eval(
        self, t: np.ndarray, want_q: bool = True, want_w: bool = True, angles: bool = True
    ) -> tuple[Any, ...]:
        """Flattened ``(q (n, 4), w (n, 3), s, c, sigma_increment, delta_increment,
        psi_increment)`` in the internal frame (``m g l >= 0``); ``psi_increment`` is
        None where ``psi`` is to be taken from ``(sigma + delta) / 2``."""
        s = self._s
        ta = np.ascontiguousarray(np.asarray(t, dtype=float).reshape(-1))
        n = ta.shape[0]
        if s.double:
            sig = s.sig0 + s.sig_rate * ta
            dlt = s.del0 + s.del_rate * ta
            sh = math.sqrt(0.5 * s.om)
            ch = math.sqrt(0.5 * s.op)
            q = np.empty((n, 4))
            q[:, 0] = ch * np.cos(0.5 * sig)
            q[:, 1] = sh * np.cos(0.5 * dlt)
            q[:, 2] = sh * np.sin(0.5 * dlt)
            q[:, 3] = ch * np.sin(0.5 * sig)
            ph = 0.5 * (sig - dlt)
            w = np.empty((n, 3))
            w[:, 0] = s.wps * np.sin(ph)
            w[:, 1] = s.wps * np.cos(ph)
            w[:, 2] = s.r
            # psi' = (K_z - H u0) / (A sin^2 theta0) = L / s2, not (sigma' + delta') / 2
            # whose parts +-(H/C - H/A) cancel (a fast top's slow precession)
            dpsi = (s.L / s.s2) * ta if s.s2 > 0 else None
            return q, w, np.full(n, sh), np.full(n, ch), sig - s.sig0, dlt - s.del0, dpsi
        from . import _lagrange_numba as kn

        direct = angles and s.par[kn.P_PSI] > 0.5
        q = np.empty((n if want_q else 0, 4))
        w = np.empty((n if want_w else 0, 3))
        xs = np.empty((n, (5 if direct else 4) if angles else 2))
        first_call(kn.motion, n * 2e-4)(ta, s.par, s.fp, s.fm, want_q, want_w, q, w, xs)
        if not angles:
            return q, w, xs[:, 0], xs[:, 1], None, None, None
        return (
            q,
            w,
            xs[:, 0],
            xs[:, 1],
            xs[:, 2] - s.par[kn.P_SIG0],
            xs[:, 3] - s.par[kn.P_DEL0],
            xs[:, 4] if direct else None,
        )

    def _times(self, t: ArrayLike) -> tuple[np.ndarray, tuple[int, ...]]:
        ta = as_float_array(t, "t")
        return ta, ta.shape

    def rotation(self, t: ArrayLike) -> Rotation:
        """Attitude (body -> space) at times ``t`` (any shape), a :class:`~poinsot.Rotation`.

        Examples
        --------
        >>> from poinsot.dynamics import LagrangeTop
        >>> top = LagrangeTop(2.0, 1.0, 4.0, theta=0.5, spin=20.0)
        >>> top.rotation([0.0, 1.0, 2.0]).shape
        (3,)
        """
        ta, shape = self._times(t)
        return Rotation.from_quat(self._quat(ta).reshape(shape + (4,)))

    def _quat(self, ta: np.ndarray) -> np.ndarray:
        s = self._s
        if s.free:
            return s.body.rotation(ta.reshape(-1)).as_quat().reshape(-1, 4)
        q = self._eval(ta, True, False)[0]
        if self._flip:
            q = _flip_back(q)
        return q

    def omega(self, t: ArrayLike) -> FloatArray:
        """Angular velocity in body axes at times ``t`` (rad/s), shape ``t.shape + (3,)``.

        ``p = psi' sin(theta) sin(phi) + theta' cos(phi)``,
        ``q = psi' sin(theta) cos(phi) - theta' sin(phi)``, ``r = H / C``.
        """
        ta, shape = self._times(t)
        return self._omega(ta).reshape(shape + (3,))

    def _omega(self, ta: np.ndarray) -> np.ndarray:
        s = self._s
        if s.free:
            return s.body.omega(ta.reshape(-1)).reshape(-1, 3)
        w = self._eval(ta, False, True)[1]
        if self._flip:
            w = w * np.array([1.0, -1.0, -1.0])
        return w

    def state(self, t: ArrayLike) -> tuple[FloatArray, Rotation]:
        """``(omega(t), rotation(t))`` in one pass."""
        ta, shape = self._times(t)
        s = self._s
        if s.free:
            return self._omega(ta).reshape(shape + (3,)), Rotation.from_quat(
                self._quat(ta).reshape(shape + (4,))
            )
        q, w = self._eval(ta, True, True)[:2]
        if self._flip:
            q = _flip_back(q)
            w = w * np.array([1.0, -1.0, -1.0])
        return w.reshape(shape + (3,)), Rotation.from_quat(q.reshape(shape + (4,)))

    def theta(self, t: ArrayLike) -> FloatArray:
        """Nutation angle ``theta(t)`` in ``[0, pi]`` (rad), exact:
        ``cos theta = u1 + (u2 - u1) sn^2(tau' t + tau0 | m)``."""
        ta, shape = self._times(t)
        s = self._s
        if s.free:
            q = self._quat(ta)
            th = 2.0 * np.arctan2(np.hypot(q[:, 1], q[:, 2]), np.hypot(q[:, 0], q[:, 3]))
            return th.reshape(shape)
        if s.double:
            th = np.full(ta.size, self._theta_of_x(0.0))
            return th.reshape(shape)
        sh, ch = self._eval(ta, False, False, angles=False)[2:4]
        th = 2.0 * np.arctan2(np.abs(sh), np.abs(ch))
        if self._flip:
            th = math.pi - th
        return th.reshape(shape)

    def _angles(self, ta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ZXZ ``(psi, phi)`` from the initial ``(psi0, phi0)`` (flattened)."""
        s = self._s
        if s.free:
            # free symmetric top: from the attitude, within pi of the initial angles
            q = self._quat(ta)
            sig = 2.0 * np.arctan2(q[:, 3], q[:, 0])
            dlt = 2.0 * np.arctan2(q[:, 2], q[:, 1])
            q0 = self._q0
            psi_0 = math.atan2(q0[3], q0[0]) + math.atan2(q0[2], q0[1])
            phi_0 = math.atan2(q0[3], q0[0]) - math.atan2(q0[2], q0[1])
            return (
                self._psi0 + _wrap(0.5 * (sig + dlt) - psi_0),
                self._phi0 + _wrap(0.5 * (sig - dlt) - phi_0),
            )
        _, _, sh, ch, dsig, ddlt, direct = self._eval(ta, False, False)
        # a negative sin(theta/2) (cos) is the same attitude with delta (sigma) + 2 pi
        js = np.where(sh < 0, math.pi, 0.0) - (math.pi if s.sign0[0] < 0 else 0.0)
        jc = np.where(ch < 0, math.pi, 0.0) - (math.pi if s.sign0[1] < 0 else 0.0)
        # psi to full relative precision where the kernel integrates it directly (see
        # _lagrange_numba.psi_sum); (sigma + delta) / 2 carries ulp(r t) absolute
        dpsi = 0.5 * (dsig + ddlt) + js + jc if direct is None else direct + js + jc
        dphi = 0.5 * (dsig - ddlt) + jc - js
        if self._flip:
            dphi = -dphi
        return self._psi0 + dpsi, self._phi0 + dphi

    def psi(self, t: ArrayLike) -> FloatArray:
        """Precession angle ``psi(t)`` (rad), z-x-z, from ``psi0`` at ``t = 0``.

        Continuous (not wrapped), to full relative precision: the integral of
        ``psi' = (K_z - H u) / (A (1 - u^2))`` with ``K_z - H u = (K_z - H u1) cn^2 +
        (K_z - H u2) sn^2`` (incomplete integrals of the third kind with the small
        coefficients of a fast top's slow precession ``~ m g l / (C r)``, docs/theory.md
        §10), and ``L / sin^2(theta)`` for a regular precession; where the band reaches
        a pole, or comes within its width of the lower one, ``psi0 + (Delta sigma +
        Delta delta) / 2`` from the exact Cayley-Klein angles (``ulp(r t)`` absolute). It
        jumps by ``pi`` where the axis passes through the vertical (where the angle is
        undefined). For ``m g l = 0`` (free top) it is taken from the attitude, within
        ``pi`` of ``psi0``.

        Examples
        --------
        >>> from poinsot.dynamics import LagrangeTop
        >>> top = LagrangeTop(2.0, 1.0, 4.0, theta=0.5, spin=20.0, psi=0.25)
        >>> T = top.nutation_period
        >>> bool(abs(top.psi(T) - 0.25 - top.precession_per_nutation) < 1e-12)
        True
        """
        ta, shape = self._times(t)
        return self._angles(ta)[0].reshape(shape)

    def phi(self, t: ArrayLike) -> FloatArray:
        """Spin angle ``phi(t)`` (rad), z-x-z, from ``phi0``, continuous like :meth:`psi`."""
        ta, shape = self._times(t)
        return self._angles(ta)[1].reshape(shape)

    def trajectory(self, t: ArrayLike, *, progress: Progress = None) -> Trajectory:
        """The exact motion sampled at times ``t`` (n,), as a :class:`~poinsot.Trajectory`.

        ``energy`` is the kinetic energy ``T`` and ``momentum`` the space angular
        momentum (as :func:`poinsot.dynamics.simulate` returns them);
        ``info["total_energy"]`` is ``T + V`` (J). ``progress``: True (a bar), a callable
        receiving the fraction done, or None; a grid of more than 65536 times is evaluated
        in chunks, between which Ctrl-C stops it (``KeyboardInterrupt``).
        """

        ta = as_float_array(t, "t")
        if ta.ndim != 1:
            raise InvalidInputError(f"Expected `t` to have shape (n,), got {ta.shape}.")

        def chunk(tc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            wc, rc = self.state(tc)
            return wc, np.asarray(rc.as_quat())

        w, q = in_chunks(chunk, ta, progress, "LagrangeTop")
        rot = Rotation.from_quat(q)
        model = None
        if self._mgl != 0:
            model = GravityTorque(1.0, [0.0, 0.0, math.copysign(1.0, self._mgl)], g=abs(self._mgl))
        inv = invariants([self._a, self._a, self._c], rot, w, torque=model)
        return Trajectory(
            ta,
            rot,
            w,
            "exact",
            energy=inv.kinetic,
            momentum=inv.momentum_space,
            info={
                "closed_form": "lagrange",
                "motion_type": self.motion_type,
                "total_energy": inv.energy,
                **(
                    {
                        "torque": "GravityTorque",
                        "conserved": ("total_energy", "momentum_z"),
                        "potential_energy": inv.potential,
                    }
                    if model is not None
                    else {"torque": "none", "conserved": ("energy", "momentum")}
                ),
            },
        )

    def __repr__(self) -> str:
        return (
            f"LagrangeTop(A={self._a!r}, C={self._c!r}, mgl={self._mgl!r}, "
            f"motion_type={self.motion_type!r})"
        )


_EMPTY = np.zeros(0)
#: Largest number of Fourier terms kept for ``Pi(n; tau)``; beyond it (near the
#: separatrix, or a band reaching close to a pole) the kernel uses Carlson's R_J.
FOURIER_MAX_TERMS = 400


def _complete_pi(n: float, n1: float, kq: float, m1: float) -> float:
    """``Pi(n | m) = K(m) + n R_J(0, m1, 1, 1 - n) / 3`` with ``n1 = 1 - n`` given exactly
    (``n`` near 1 near the upright: ``1 - n`` computed from ``n`` would be round-off)."""
    from . import _elliptic as el

    return kq + n * float(el.elliprj(0.0, m1, 1.0, n1)) / 3.0


def _complete_g(n: float, n1: float, kq: float, m1: float) -> float:
    """``int_0^K cn^2 / (1 - n sn^2) dtau = K - (1 - n) R_J(0, m1, 1, 1 - n) / 3``.

    (``cn^2 = ((1 - n sn^2) - (1 - n)) / n`` and the form of :func:`_complete_pi`; no
    division by ``n``, finite at ``n = 1`` where it is ``K``.)
    """
    from . import _elliptic as el

    if n1 == 0.0:
        return kq
    return kq - n1 * float(el.elliprj(0.0, m1, 1.0, n1)) / 3.0


def _fourier(n: float, n1: float, m: float, m1: float, kq: float, pi_complete: float) -> np.ndarray:
    """Coefficients of ``Pi(n; r) = c[0] r + sum_k c[k] sin(k pi r / K)`` (``|r| <= K``).

    ``1 / (1 - n sn^2(tau | m))`` (for ``n > 0`` as ``1 / (n1 + n cn^2)``, ``n1 = 1 - n``,
    free of cancellation as ``n -> 1``) is even and ``2K``-periodic: its cosine coefficients
    ``a_k`` come from the FFT of ``N`` samples over a period (``N`` doubled until the
    upper quarter of the spectrum is round-off), truncated before the first term
    below ``eps max|f| / 2``; ``c[k] = K a_k / (k pi)`` and
    ``c[0] = Pi(n | m) / K`` (the mean). Returns an empty array (use ``R_J``) when
    more than :data:`FOURIER_MAX_TERMS` terms would be needed.
    """
    from . import _elliptic as el

    for big_n in (64, 128, 256, 512, 1024, 2048):
        tau = (2.0 * kq / big_n) * np.arange(big_n)
        sn, cn = el.ellipj(tau, m, m1=m1)[:2]
        f = 1.0 / (n1 + n * cn * cn) if n > 0.0 else 1.0 / (1.0 - n * sn * sn)
        a = np.fft.rfft(f).real * (2.0 / big_n)
        fmax = float(np.max(np.abs(f)))
        tail = np.abs(a[big_n // 4 :])
        # the upper quarter of the spectrum is round-off noise (~eps max|f|): converged;
        # keep the terms before the first one below round-off (they decay geometrically)
        if float(np.max(tail)) <= 4.0 * _EPS * fmax:
            small = np.flatnonzero(np.abs(a[1:]) <= 0.5 * _EPS * fmax)
            nk = int(small[0]) if small.size else big_n // 2
            if nk > FOURIER_MAX_TERMS:
                return _EMPTY
            k = np.arange(1, nk + 1)
            c = np.empty(nk + 1)
            c[0] = pi_complete / kq
            c[1:] = kq * a[1 : nk + 1] / (k * math.pi)
            return c
    return _EMPTY


def _wrap(x: np.ndarray) -> np.ndarray:
    return (x + math.pi) % (2.0 * math.pi) - math.pi


def _flip_back(q: np.ndarray) -> np.ndarray:
    """``q o (0, -1, 0, 0)`` = ``(q1, -q0, -q3, q2)``: undo :func:`_flip`."""
    out = np.empty_like(q)
    out[..., 0] = q[..., 1]
    out[..., 1] = -q[..., 0]
    out[..., 2] = -q[..., 3]
    out[..., 3] = q[..., 2]
    return out
