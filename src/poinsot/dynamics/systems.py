"""Forces and the general theorems for systems of particles (theory §9).

:func:`classify_force` sorts a force field ``F(t, r, v)`` by its power and its
Jacobian: *potential* (velocity- and time-independent with
``dF_i/dx_j = dF_j/dx_i``; a potential ``U`` with ``F = -grad U`` is returned),
*gyroscopic* (power ``F . v = 0`` for every motion: Lorentz, Coriolis),
*dissipative* (``F . v <= 0``) or none of these.

:class:`ParticleSystem` holds masses, positions and velocities and gives the
quantities of the general theorems: momentum ``p = sum m v`` (``p' = R^e``),
angular momentum about any point ``K_O = sum (r - O) x m v``
(``K_O' = M_O^e - m V_O x V_c``), kinetic energy with Koenig's split
``T = m V_c^2 / 2 + T_rel`` (``T' = N^e + N^i``).

**Convention:** one inertial frame, Cartesian components; velocities are
absolute; SI units (kg, m, m/s, N). A force callable takes
``force(t, r, v)`` with ``r`` and ``v`` of shape (3,), like
:func:`~poinsot.dynamics.simulate_particle`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_vec3
from .._vec import cross, dot, length
from ..errors import InvalidInputError, InvalidTypeError
from ..kinematics.screw import reduce_motions

__all__ = [
    "FORCE_KINDS",
    "ForceClassification",
    "LinePotential",
    "classify_force",
    "ParticleSystem",
    "KoenigSplit",
    "shift_angular_momentum",
    "ForceSystem",
    "reduce_forces",
]

#: The kinds :func:`classify_force` reports.
FORCE_KINDS = ("potential", "gyroscopic", "dissipative", "none")


# ---------------------------------------------------------------------------
# Forces
# ---------------------------------------------------------------------------


def _call_force(
    force: Callable[..., Any],
    t: float,
    r: np.ndarray,
    v: np.ndarray,
    *,
    nonfinite: type[Exception] = InvalidInputError,
) -> np.ndarray:
    """``force(t, r, v)`` as a checked (3,) array (the ONE force-call validator,
    also used by :func:`~poinsot.dynamics.simulate_particle`, which passes
    ``nonfinite=IntegrationError``)."""
    try:
        out = np.asarray(force(t, r, v), dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(
            f"Expected `force(t, r, v)` to return a 3-vector (N), calling it failed: "
            f"{type(exc).__name__}: {exc}"
        ) from None
    if out.shape != (3,):
        raise InvalidInputError(
            f"Expected `force(t, r, v)` to return shape (3,) for one point, got {out.shape}."
        )
    if not np.all(np.isfinite(out)):
        raise nonfinite(
            f"Expected `force` to return finite values, got {out.tolist()} (non-finite) at "
            f"t = {float(t):g}, r = {np.asarray(r).tolist()}, v = {np.asarray(v).tolist()}."
        )
    return out


@dataclass(frozen=True, eq=False)
class LinePotential:
    """The potential of a curl-free force, zero at ``reference`` (J).

    ``U(r) = -int_0^1 F(r_ref + s (r - r_ref)) . (r - r_ref) ds``: minus the work
    of a curl-free stationary force ``F(r)`` along the straight path from
    ``reference`` to ``r`` (16-point Gauss-Legendre), so that ``F = -grad U``.
    Call with ``r`` of shape (..., 3).

    >>> import numpy as np
    >>> from poinsot.dynamics import LinePotential
    >>> U = LinePotential(lambda t, r, v: -2.0 * r, np.zeros(3))   # U = |r|^2
    >>> U([[1.0, 1.0, 0.0]]).round(12)
    array([2.])
    """

    force: Callable[..., Any]
    reference: np.ndarray
    time: float = 0.0

    def __call__(self, r: ArrayLike) -> FloatArray:
        r = as_vec3(r, "r")
        x, w = np.polynomial.legendre.leggauss(16)
        s = 0.5 * (x + 1.0)
        d = r - self.reference
        flat = d.reshape(-1, 3)
        out = np.empty(flat.shape[0])
        zero = np.zeros(3)
        for i, di in enumerate(flat):
            f = np.array(
                [_call_force(self.force, self.time, self.reference + sk * di, zero) for sk in s]
            )
            out[i] = -0.5 * float(w @ (f @ di))
        return out.reshape(d.shape[:-1])


@dataclass(frozen=True, eq=False)
class ForceClassification:
    """What :func:`classify_force` found on its samples.

    Attributes
    ----------
    kind : str
        ``"potential"``, ``"gyroscopic"``, ``"dissipative"`` or ``"none"``.
    potential : LinePotential or None
        ``U`` with ``F = -grad U`` (J) when ``kind == "potential"``.
    velocity_dependent, time_dependent : bool
        Whether ``F`` changed with ``v`` (or ``t``) on the samples.
    curl_free : bool
        Whether ``F(t, r, 0)`` has a symmetric Jacobian ``dF_i/dx_j = dF_j/dx_i``.
    asymmetry : float
        ``max |J - J^T| / max |J|`` over the samples (0 for a gradient).
    power_range : tuple of float
        Smallest and largest ``F . v / (|F| |v|)`` over the samples.
    potential_residual : float or None
        ``max |F + grad U| / max |F|`` on the samples (central differences).
    fully_dissipative : bool
        For a dissipative force: ``F . v < 0`` for **every** ``v != 0`` (tested along
        26 directions of the cube's axes and diagonals and the softest direction of
        the velocity Jacobian, at every sample point), e.g. ``-beta v``; False for
        a merely dissipative force that damps some velocities only (``F . v = 0``
        for others, e.g. a force damping ``v_x`` alone).
    """

    kind: str
    potential: LinePotential | None
    velocity_dependent: bool
    time_dependent: bool
    curl_free: bool
    asymmetry: float
    power_range: tuple[float, float]
    potential_residual: float | None
    fully_dissipative: bool = False


def classify_force(
    force: Callable[..., Any],
    *,
    center: ArrayLike = (0.0, 0.0, 0.0),
    size: float = 1.0,
    speed: float = 1.0,
    times: ArrayLike = (0.0, 1.0),
    samples: int = 24,
    rtol: float = 1e-6,
    seed: int = 0,
) -> ForceClassification:
    """Classify a force field ``F(t, r, v)`` by its power and Jacobian (theory §9).

    Parameters
    ----------
    force : callable
        ``force(t, r, v) -> (3,)`` (N), ``r`` and ``v`` of shape (3,).
    center : array_like, shape (3,), optional
        Centre of the cube of side ``2 size`` where positions are sampled; the
        returned potential is zero there. Keep singular points (e.g. the
        attracting centre of a Kepler field) out of the cube.
    size : float, optional
        Half side of the sampling cube (m), default 1.
    speed : float, optional
        Scale of the sampled velocities (m/s), default 1.
    times : sequence of float, optional
        Times at which ``F`` is sampled (stationarity test), default (0, 1).
    samples : int, optional
        Number of random sample points (default 24).
    rtol : float, optional
        Relative tolerance of every test (default 1e-6, well above the
        ~1e-10 error of the 4th-order differences with step ``1e-3 size``).
    seed : int, optional
        Seed of the sample points (reproducible).

    Returns
    -------
    ForceClassification
        ``kind``: ``"potential"`` when ``F`` depends on neither ``v`` nor
        ``t`` and its Jacobian is symmetric (then ``potential`` is
        ``U(r) = -int F . dr`` from ``center``, checked: ``F = -grad U``);
        ``"gyroscopic"`` when ``F . v = 0`` on every sample (velocity
        dependent); ``"dissipative"`` when ``F . v <= 0`` on every sample
        and ``< 0`` on some; ``"none"`` otherwise.

    Notes
    -----
    A numerical test on samples, not a proof: a field can pass it and fail
    elsewhere. The symmetric-Jacobian test is ``curl F = 0`` (theory §9); on a
    cube (simply connected) it makes the line integral path-independent.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import classify_force
    >>> classify_force(lambda t, r, v: -2.0 * r).kind
    'potential'
    >>> classify_force(lambda t, r, v: np.cross(v, [0.0, 0.0, 1.5])).kind
    'gyroscopic'
    >>> classify_force(lambda t, r, v: -0.3 * v).kind
    'dissipative'
    >>> classify_force(lambda t, r, v: np.array([-r[1], r[0], 0.0])).kind
    'none'
    """
    if not callable(force):
        raise InvalidTypeError(f"Expected `force` to be callable, got {type(force).__name__}.")
    c = as_vec3(center, "center")
    if c.shape != (3,):
        raise InvalidInputError(f"Expected `center` of shape (3,), got {c.shape}.")
    size, speed, rtol = (
        _positive(size, "size"),
        _positive(speed, "speed"),
        _positive(rtol, "rtol"),
    )
    ts = as_float_array(times, "times").ravel()
    if ts.size < 1:
        raise InvalidInputError("Expected at least one time in `times`.")
    if not isinstance(samples, int | np.integer) or samples < 2:
        raise InvalidInputError(f"Expected `samples` to be an integer >= 2, got {samples!r}.")
    rng = np.random.default_rng(seed)
    R = c + size * rng.uniform(-1.0, 1.0, (samples, 3))
    V = speed * rng.standard_normal((samples, 3))
    V2 = speed * rng.standard_normal((samples, 3))
    t0 = float(ts[0])
    zero = np.zeros(3)

    F = np.array([_call_force(force, t0, r, v) for r, v in zip(R, V, strict=True)])
    F0 = np.array([_call_force(force, t0, r, zero) for r in R])
    F2 = np.array([_call_force(force, t0, r, v) for r, v in zip(R, V2, strict=True)])
    scale = max(float(np.max(length(F))), float(np.max(length(F0))), float(np.max(length(F2))))
    if scale == 0.0:  # the zero force: potential U = 0
        zero_pot = LinePotential(force, c, t0)
        return ForceClassification("potential", zero_pot, False, False, True, 0.0, (0.0, 0.0), 0.0)
    tol = rtol * scale
    vel_dep = bool(np.max(np.abs(F - F0)) > tol or np.max(np.abs(F2 - F0)) > tol)
    time_dep = False
    for tk in ts[1:]:
        Fk = np.array([_call_force(force, float(tk), r, v) for r, v in zip(R, V, strict=True)])
        time_dep |= bool(np.max(np.abs(Fk - F)) > tol)

    # Jacobian of F(t0, r, 0): 4th-order central differences
    h = 1e-3 * size
    J = np.empty((samples, 3, 3))
    for k, r in enumerate(R):
        for j in range(3):
            e = np.zeros(3)
            e[j] = h

            def f(x: np.ndarray, r: np.ndarray = r) -> np.ndarray:
                return _call_force(force, t0, x, zero)

            J[k, :, j] = (8 * (f(r + e) - f(r - e)) - (f(r + 2 * e) - f(r - 2 * e))) / (12 * h)
    jmax = float(np.max(np.abs(J)))
    asym = float(np.max(np.abs(J - np.swapaxes(J, -1, -2)))) / jmax if jmax > 0 else 0.0
    curl_free = asym <= rtol

    cosines = []
    for Fv, v in ((F, V), (F2, V2)):
        nf, nv = length(Fv), length(v)
        ok = nf > 0
        cosines.append(dot(Fv[ok], v[ok]) / (nf[ok] * nv[ok]))
    cos = np.concatenate(cosines) if cosines else np.zeros(1)
    prange = (float(cos.min()), float(cos.max())) if cos.size else (0.0, 0.0)

    pot = None
    residual = None
    if not vel_dep and not time_dep and curl_free:
        kind = "potential"
        pot = LinePotential(force, c, t0)
        # check F = -grad U on a few samples
        idx = np.arange(min(samples, 6))
        err = 0.0
        for k in idx.tolist():
            g = np.empty(3)
            for j in range(3):
                e = np.zeros(3)
                e[j] = h
                u = pot(np.stack([R[k] + 2 * e, R[k] + e, R[k] - e, R[k] - 2 * e]))
                g[j] = (8 * (u[1] - u[2]) - (u[0] - u[3])) / (12 * h)
            err = max(err, float(np.max(np.abs(F0[k] + g))))
        residual = err / scale
        if residual > rtol:
            kind = "none"
    elif vel_dep and np.all(np.abs(cos) <= rtol):
        kind = "gyroscopic"
    elif vel_dep and np.all(cos <= rtol) and np.any(cos < -rtol):
        kind = "dissipative"
    else:
        kind = "none"
    fully = kind == "dissipative" and _strictly_dissipative(force, t0, R, speed, rtol, scale)
    return ForceClassification(
        kind, pot, vel_dep, time_dep, bool(curl_free), asym, prange, residual, fully
    )


def _directions() -> FloatArray:
    """26 unit directions: the cube's 3 axes, 4 body and 6 face diagonals, both signs."""
    pts = np.array(
        [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)], dtype=float
    )
    pts = pts[np.any(pts != 0, axis=1)]
    return pts / np.linalg.norm(pts, axis=1, keepdims=True)


def _strictly_dissipative(
    force: Callable[..., Any], t0: float, R: FloatArray, speed: float, rtol: float, scale: float
) -> bool:
    """``F . v < 0`` along every test direction at every sample point (see
    :class:`ForceClassification`): also along the softest direction of the symmetric
    part of ``-dF/dv`` at ``v = 0``, which a linear damping leaves undamped."""
    dirs = _directions()
    h = 1e-3 * speed
    for r in R:
        jv = np.empty((3, 3))
        for j in range(3):
            e = np.zeros(3)
            e[j] = h
            jv[:, j] = (_call_force(force, t0, r, e) - _call_force(force, t0, r, -e)) / (2 * h)
        sym = -0.5 * (jv + jv.T)
        soft = np.linalg.eigh(sym)[1][:, 0]
        for d in (*dirs, soft, -soft):
            v = speed * d
            if float(_call_force(force, t0, r, v) @ v) >= -rtol * scale * speed:
                return False
    return True


def _positive(x: ArrayLike, name: str) -> float:
    a = as_float_array(x, name)
    if a.ndim or not a > 0:
        raise InvalidInputError(f"Expected `{name}` to be a positive scalar, got {x!r}.")
    return float(a)


# ---------------------------------------------------------------------------
# Systems of particles
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class KoenigSplit:
    """Koenig's theorem ``T = M V_c^2 / 2 + T_rel`` (J).

    Attributes
    ----------
    total : ndarray
        ``T = sum m v^2 / 2``.
    center : ndarray
        ``M |V_c|^2 / 2``, the energy of the centre of mass carrying the total mass.
    relative : ndarray
        ``T_rel = sum m |v - V_c|^2 / 2``, the motion relative to the centre of mass.
    """

    total: np.ndarray
    center: np.ndarray
    relative: np.ndarray


def shift_angular_momentum(
    k_o: ArrayLike, momentum: ArrayLike, o: ArrayLike, o_prime: ArrayLike
) -> FloatArray:
    """Angular momentum about another point: ``K_O' = K_O + O'O x p`` (theory §9).

    Parameters
    ----------
    k_o : array_like, shape (..., 3)
        ``K_O`` about the point ``O`` (kg m^2/s).
    momentum : array_like, shape (..., 3)
        Total momentum ``p`` (kg m/s).
    o, o_prime : array_like, shape (..., 3)
        Positions of ``O`` and ``O'`` (m); ``O'O = O - O'``.

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> from poinsot.dynamics import shift_angular_momentum
    >>> shift_angular_momentum([0, 0, 0], [0, 2, 0], [1, 0, 0], [0, 0, 0]) + 0.0
    array([0., 0., 2.])
    """
    k, p = as_vec3(k_o, "k_o"), as_vec3(momentum, "momentum")
    a, b = as_vec3(o, "o"), as_vec3(o_prime, "o_prime")
    return k + cross(a - b, p)


@dataclass(frozen=True, eq=False)
class ParticleSystem:
    """A system of point masses at one instant (or a batch of instants).

    Parameters
    ----------
    masses : array_like, shape (..., N)
        Masses (kg, >= 0, total > 0).
    positions, velocities : array_like, shape (..., N, 3)
        Positions (m) and absolute velocities (m/s), inertial axes.

    Examples
    --------
    Two unit masses on a rod spinning at 1 rad/s about z through its middle:

    >>> from poinsot.dynamics import ParticleSystem
    >>> s = ParticleSystem([1, 1], [[1, 0, 0], [-1, 0, 0]], [[0, 1, 0], [0, -1, 0]])
    >>> s.momentum + 0.0, s.angular_momentum() + 0.0
    (array([0., 0., 0.]), array([0., 0., 2.]))
    >>> s.angular_momentum(point=[5, 0, 0]) + 0.0
    array([0., 0., 2.])
    >>> float(s.koenig().relative), float(s.koenig().center)
    (1.0, 0.0)
    """

    masses: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray

    def __post_init__(self) -> None:
        m = as_float_array(self.masses, "masses")
        r = as_float_array(self.positions, "positions")
        v = as_float_array(self.velocities, "velocities")
        if m.ndim < 1:
            raise InvalidInputError(f"Expected `masses` to have shape (..., N), got {m.shape}.")
        if np.any(m < 0):
            raise InvalidInputError(
                f"Expected `masses` to be non-negative (kg), got {float(m[m < 0].ravel()[0])!r}."
            )
        if np.any(np.sum(m, axis=-1) <= 0):
            raise InvalidInputError("Expected the total mass to be positive, got 0.")
        for name, a in (("positions", r), ("velocities", v)):
            if a.ndim < 2 or a.shape[-1] != 3 or a.shape[-2] != m.shape[-1]:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape (..., N, 3) with N = {m.shape[-1]} "
                    f"(the number of masses), got {a.shape}."
                )
        try:
            shape = np.broadcast_shapes(m.shape, r.shape[:-1], v.shape[:-1])
        except ValueError:
            raise InvalidInputError(
                f"Expected the batch shapes of `masses` {m.shape}, `positions` {r.shape}, "
                f"`velocities` {v.shape} to broadcast."
            ) from None
        for name, a, tail in (("masses", m, ()), ("positions", r, (3,)), ("velocities", v, (3,))):
            a = np.broadcast_to(a, shape + tail).copy()
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def total_mass(self) -> np.ndarray:
        """``M = sum m`` (kg)."""
        return np.sum(self.masses, axis=-1)

    @property
    def momentum(self) -> np.ndarray:
        """``p = sum m v = M V_c`` (kg m/s)."""
        return np.einsum("...n,...ni->...i", self.masses, self.velocities)

    @property
    def center_of_mass(self) -> np.ndarray:
        """``r_c = sum m r / M`` (m)."""
        return (
            np.einsum("...n,...ni->...i", self.masses, self.positions) / self.total_mass[..., None]
        )

    @property
    def center_velocity(self) -> np.ndarray:
        """``V_c = p / M`` (m/s)."""
        return self.momentum / self.total_mass[..., None]

    def angular_momentum(self, point: ArrayLike = (0.0, 0.0, 0.0)) -> FloatArray:
        """``K_O = sum (r - O) x m v`` about ``point`` (kg m^2/s), absolute velocities."""
        o = as_vec3(point, "point")
        rel = self.positions - o[..., None, :]
        return np.einsum("...n,...ni->...i", self.masses, cross(rel, self.velocities))

    @property
    def kinetic_energy(self) -> np.ndarray:
        """``T = sum m |v|^2 / 2`` (J)."""
        return 0.5 * np.einsum("...n,...n->...", self.masses, dot(self.velocities, self.velocities))

    def koenig(self) -> KoenigSplit:
        """Koenig's split of the kinetic energy (see :class:`KoenigSplit`)."""
        vc = self.center_velocity
        rel = self.velocities - vc[..., None, :]
        t_rel = 0.5 * np.einsum("...n,...n->...", self.masses, dot(rel, rel))
        t_c = 0.5 * self.total_mass * dot(vc, vc)
        return KoenigSplit(total=self.kinetic_energy, center=t_c, relative=t_rel)

    def resultant(self, forces: ArrayLike) -> FloatArray:
        """``R = sum F`` of forces ``(..., N, 3)`` acting on the particles (N)."""
        return np.sum(self._forces(forces), axis=-2)

    def moment(self, forces: ArrayLike, point: ArrayLike = (0.0, 0.0, 0.0)) -> FloatArray:
        """``M_O = sum (r - O) x F`` (N m)."""
        o = as_vec3(point, "point")
        return np.sum(cross(self.positions - o[..., None, :], self._forces(forces)), axis=-2)

    def power(self, forces: ArrayLike) -> FloatArray:
        """``N = sum F . v`` (W)."""
        return np.sum(dot(self._forces(forces), self.velocities), axis=-1)

    def _forces(self, forces: ArrayLike) -> np.ndarray:
        f = as_float_array(forces, "forces")
        if f.shape[-2:] != self.positions.shape[-2:]:
            raise InvalidInputError(
                f"Expected `forces` to have shape (..., {self.positions.shape[-2]}, 3), "
                f"got {f.shape}."
            )
        return f


# ---------------------------------------------------------------------------
# Systems of forces on a rigid body
# ---------------------------------------------------------------------------

#: The simplest equivalent of a force system (:func:`reduce_forces`), by the kind of
#: the kinematic reduction with the same algebra (:func:`poinsot.kinematics.reduce_motions`).
_FORCE_KIND = {
    "screw": "wrench",
    "rotation": "resultant",
    "translation": "couple",
    "rest": "equilibrium",
}


@dataclass(frozen=True, eq=False)
class ForceSystem:
    """A system of forces and couples on a rigid body, reduced at a pole (theory §9).

    Attributes
    ----------
    resultant : ndarray, shape (3,)
        The principal vector ``R = sum F_i`` (N).
    moment : ndarray, shape (3,)
        The principal moment about the pole, ``M_O = sum OP_i x F_i + sum C_k`` (N m).
    pole : ndarray, shape (3,)
        The pole ``O`` (m).
    invariant : float
        ``R . M_O``, the same for every pole (N^2 m).
    kind : str
        The simplest equivalent: ``"wrench"`` (a force along the central axis and a
        couple about it, ``R . M != 0``), ``"resultant"`` (a single force on the
        central axis), ``"couple"`` (``R = 0``, ``M != 0``) or ``"equilibrium"``.
    central_axis : Screw or None
        For a wrench or a resultant: the central axis (``point``: its point nearest
        the pole, ``direction`` along ``R``, ``parameter`` the pitch
        ``p = R . M / |R|^2`` in m, ``min_speed`` the smallest moment
        ``|R . M| / |R|`` in N m, reached on the axis); else ``None``.
    """

    resultant: FloatArray
    moment: FloatArray
    pole: FloatArray
    invariant: float
    kind: str
    central_axis: Any

    def moment_about(self, point: ArrayLike) -> FloatArray:
        """``M_O' = M_O + O'O x R`` (N m), the principal moment about ``point``."""
        r = as_vec3(point, "point")
        return self.moment + cross(self.resultant, r - self.pole)


def reduce_forces(
    forces: Any = (),
    couples: Any = (),
    *,
    pole: ArrayLike = (0.0, 0.0, 0.0),
    rtol: float = 1e-10,
    atol: float = 0.0,
) -> ForceSystem:
    """Reduce forces at points and couples to the simplest equivalent system (theory §9).

    ``R = sum F_i``, ``M_O = sum OP_i x F_i + sum C_k``; ``M_O' = M_O + O'O x R``; the
    invariant ``R . M_O``; then a wrench on the central axis, a single resultant, a
    couple, or equilibrium. This is the algebra of the kinematic screw (a force at
    ``P_i`` like a rotation about an axis through ``P_i``, a couple like a
    translation): it is computed by :func:`poinsot.kinematics.reduce_motions`, one
    implementation for both.

    Parameters
    ----------
    forces : sequence of (F_i, P_i)
        Forces (N, shape (3,)) applied at points (m, shape (3,)).
    couples : sequence of array_like, shape (3,)
        Couples (N m).
    pole : array_like, shape (3,), optional
        The reduction point ``O`` (default the origin).
    rtol, atol : float, optional
        Classification tolerances (as :func:`poinsot.kinematics.reduce_motions`).

    Returns
    -------
    ForceSystem

    Examples
    --------
    Two equal and opposite parallel forces are a couple; a force and a couple about
    its line are a wrench:

    >>> from poinsot.dynamics import reduce_forces
    >>> s = reduce_forces([([0, 1.0, 0], [0, 0, 0]), ([0, -1.0, 0], [2.0, 0, 0])])
    >>> s.kind, s.moment + 0.0
    ('couple', array([ 0.,  0., -2.]))
    >>> w = reduce_forces([([0, 0, 2.0], [1.0, 0, 0])], [[0, 0, 1.0]])
    >>> w.kind, w.central_axis.point + 0.0, float(w.central_axis.parameter)
    ('wrench', array([1., 0., 0.]), 0.5)
    """

    pairs = []
    for i, item in enumerate(_sequence(forces, "forces")):
        try:
            f_i, p_i = item
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"Expected `forces[{i}]` to be a pair (force, point), got {item!r}."
            ) from None
        pairs.append((_vector(f_i, f"forces[{i}][0]"), _vector(p_i, f"forces[{i}][1]")))
    cs = [_vector(c, f"couples[{k}]") for k, c in enumerate(_sequence(couples, "couples"))]
    m = reduce_motions(pairs, cs, pole=_vector(pole, "pole"), rtol=rtol, atol=atol)
    return ForceSystem(
        resultant=m.omega,
        moment=m.velocity,
        pole=m.pole,
        invariant=float(m.omega @ m.velocity),
        kind=_FORCE_KIND[m.kind],
        central_axis=m.screw,
    )


def _sequence(x: Any, name: str) -> list[Any]:
    if isinstance(x, str | bytes) or not hasattr(x, "__iter__"):
        raise InvalidTypeError(f"Expected `{name}` to be a sequence, got {type(x).__name__}.")
    return list(x)


def _vector(x: Any, name: str) -> FloatArray:
    a = as_float_array(x, name)
    if a.shape != (3,):
        raise InvalidInputError(f"Expected `{name}` to have shape (3,), got {a.shape}.")
    return a
