"""A point mass in a moving frame: every inertial force by name (theory §9).

Relative to a frame that moves with origin acceleration ``W0``, angular velocity
``w`` and angular acceleration ``eps`` (a :class:`~poinsot.kinematics.FrameMotion`),
a particle of mass ``m`` obeys

``m a_r = F + J_e + J_c``,
``J_e = -m W0 - m eps x r - m w x (w x r)`` (transport: origin, Euler, centrifugal),
``J_c = -2 m w x v_r`` (Coriolis, which does no work).

:func:`inertial_forces` returns each term by name; :func:`simulate_particle`
integrates the equation of relative motion (DOP853 by default) and can also
return the motion seen from the inertial frame. The applications on the rotating
Earth (:func:`earth_frame`, free fall, the Foucault pendulum) are in
:mod:`poinsot.dynamics.earth`; their names are still reachable from here.

**Convention:** for particle dynamics the vectors of a ``FrameMotion`` (``W0``,
``w``, ``eps``, ``V0``), the force and the particle's ``r`` and ``v_r`` are all
components in the **moving frame's own axes** (e.g. east, north, up). Positions
in m, velocities in m/s, forces in N, masses in kg, angles in rad. At the first
output time the inertial axes coincide with the frame's axes and the inertial
origin with the frame's origin.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import integrators
from .._deprecate import renamed
from .._progress import Progress, as_progress, ivp_progress
from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_float_array, as_times, as_vec3, batch_shape
from .._vec import cross, dot, hat
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError
from ..events import as_events, locate, solve_dense
from ..kinematics.fields import FrameMotion, _rivals_terms
from ..kinematics.rates import _quat_rate
from ..mass import RigidBody
from ..rotations.quaternion import rotate
from ..rotations.rotation import Rotation
from ..trajectory import PointTrajectory, Trajectory
from .systems import _call_force

if TYPE_CHECKING:
    from ..trajectory import Trajectory

__all__ = [
    "InertialForces",
    "ParticleTrajectory",
    "inertial_forces",
    "simulate_particle",
    "jacobi_integral",
    "relative_motion",
    "PARTICLE_SOLVERS",
    "BodyInertialForces",
    "body_inertial_forces",
]

#: ``scipy.integrate.solve_ivp`` methods accepted by :func:`simulate_particle`.
#: SciPy's solve_ivp methods (from :data:`poinsot.integrators.INTEGRATORS`).
PARTICLE_SOLVERS = integrators.names("lagrangian")


def __getattr__(name: str) -> Any:
    # the applications on the rotating Earth moved to .earth (issue 39) and are still
    # reachable here; a module-level re-export would be an import circle (earth
    # integrates with simulate_particle), so they are looked up when first asked for
    from . import earth

    if name in earth.__all__:
        return getattr(earth, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# ---------------------------------------------------------------------------
# Validation helpers
# ---------------------------------------------------------------------------


def _as_frame(frame: object, name: str = "frame") -> FrameMotion:
    if not isinstance(frame, FrameMotion):
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot.kinematics.FrameMotion, got {type(frame).__name__}."
        )
    return frame


def _as_mass(mass: ArrayLike, name: str = "mass") -> np.ndarray:
    m = as_float_array(mass, name)
    if np.any(m < 0):
        raise InvalidInputError(
            f"Expected `{name}` to be non-negative (kg), got {float(m[m < 0].ravel()[0])!r}."
        )
    return m


# ---------------------------------------------------------------------------
# Inertial forces
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class InertialForces:
    """The inertial forces on a particle in a moving frame, term by term (theory §9).

    Attributes
    ----------
    origin : ndarray, shape (..., 3)
        ``-m W0`` (acceleration of the frame's origin), N.
    euler : ndarray, shape (..., 3)
        ``-m eps x r`` (angular acceleration of the frame), N.
    centrifugal : ndarray, shape (..., 3)
        ``-m w x (w x r)``, pointing away from the rotation axis, N.
    transport : ndarray, shape (..., 3)
        ``J_e = origin + euler + centrifugal`` (minus ``m`` times the
        acceleration of the frame point the particle occupies), N.
    coriolis : ndarray, shape (..., 3)
        ``J_c = -2 m w x v_r``, perpendicular to ``v_r`` (no power), N.

    All in the frame's axes (the axes of the given vectors).
    """

    origin: np.ndarray
    euler: np.ndarray
    centrifugal: np.ndarray
    transport: np.ndarray
    coriolis: np.ndarray

    @property
    def total(self) -> np.ndarray:
        """``J_e + J_c``, the sum of all inertial forces (N)."""
        return self.transport + self.coriolis


def inertial_forces(
    frame: FrameMotion,
    r: ArrayLike,
    v: ArrayLike,
    mass: ArrayLike = 1.0,
    *legacy: float,
    t: float = 0.0,
) -> InertialForces:
    """Every inertial force on a particle moving in a moving frame (theory §9).

    Parameters
    ----------
    frame : FrameMotion or callable
        Motion of the frame: ``W0`` (``origin_acceleration``), ``w``
        (``omega``) and ``eps``, or a function ``frame(t) -> FrameMotion``.
    r : array_like, shape (..., 3)
        Position of the particle relative to the frame's origin (m).
    v : array_like, shape (..., 3)
        Velocity relative to the frame, ``v_r`` (m/s).
    mass : array_like, shape (...), optional
        Mass ``m`` (kg, >= 0), default 1.
    t : float, optional, keyword-only
        Time (s) at which a callable ``frame`` is evaluated; default 0. (Passing it as
        the fifth positional argument still works, with a ``DeprecationWarning``.)

    Returns
    -------
    InertialForces
        ``origin = -m W0``, ``euler = -m eps x r``,
        ``centrifugal = -m w x (w x r)``, ``transport`` (their sum ``J_e``) and
        ``coriolis = -2 m w x v_r``, broadcast over the batch.

    Notes
    -----
    **Convention:** all vectors in one set of axes (normally the frame's own
    axes); the result is in the same axes. ``-m`` times the transport and
    Coriolis terms of :func:`poinsot.kinematics.point_motion` (Rivals'
    formula, theory §6).

    Examples
    --------
    A 2 kg bead moving outwards at 1 m/s on a turntable spinning at 3 rad/s,
    0.5 m from the axis:

    >>> from poinsot.kinematics import FrameMotion
    >>> from poinsot.dynamics import inertial_forces
    >>> f = inertial_forces(FrameMotion(omega=[0, 0, 3]), [0.5, 0, 0], [1, 0, 0], mass=2.0)
    >>> f.centrifugal + 0.0, f.coriolis + 0.0
    (array([9., 0., 0.]), array([  0., -12.,   0.]))
    """
    if legacy:  # the former positional `t` (docs/conventions.md, "Names")
        if len(legacy) > 1:
            raise InvalidTypeError(
                f"inertial_forces takes 4 positional arguments (frame, r, v, mass) and "
                f"`t` by keyword; got {4 + len(legacy)} positional arguments."
            )
        warnings.warn(
            "inertial_forces(frame, r, v, mass, t): pass the time by keyword, t=...; "
            "a positional t is deprecated (a time with a default is keyword-only).",
            DeprecationWarning,
            stacklevel=2,
        )
        t = legacy[0]
    frame = _frame_at(frame, t)
    r = as_vec3(r, "r")
    v = as_vec3(v, "v")
    m = _as_mass(mass)
    shape = batch_shape(r=(r, 1), v=(v, 1), mass=(m, 0), frame=(frame.omega, 1))
    w0, rot, cen = _rivals_terms(frame.origin_acceleration, frame.omega, frame.eps, r)
    cor = 2.0 * cross(frame.omega, v)
    mm = m[..., None]

    def out(a: np.ndarray) -> np.ndarray:
        return np.broadcast_to(-mm * a, shape + (3,)).copy()

    origin, euler, centrifugal = out(w0), out(rot), out(cen)
    return InertialForces(
        origin=origin,
        euler=euler,
        centrifugal=centrifugal,
        transport=origin + euler + centrifugal,
        coriolis=out(cor),
    )


@dataclass(frozen=True, eq=False)
class BodyInertialForces:
    """The inertial forces on a whole rigid body in a moving frame (theory §9),
    reduced at the frame's origin ``O``.

    Attributes
    ----------
    transport_force, coriolis_force : ndarray, shape (3,)
        Resultants ``R^e = -m (W0 + eps x r_c + w x (w x r_c))`` and
        ``R^c = -2 m w x u_c`` (N).
    transport_moment, coriolis_moment : ndarray, shape (3,)
        Their moments about ``O``: ``M^e = -(m r_c x W0 + J_O eps + w x J_O w)`` and
        ``M^c = r_c x R^c + 2 W x (S w)``, ``S = (tr J_c / 2) E - J_c`` (N m).

    All in the frame's axes.
    """

    transport_force: FloatArray
    transport_moment: FloatArray
    coriolis_force: FloatArray
    coriolis_moment: FloatArray

    def moment_about(self, point: ArrayLike) -> FloatArray:
        """Moment of all the inertial forces about ``point`` (frame axes, m):
        ``M_P = M_O + PO x R`` (N m)."""
        p = as_vec3(point, "point")
        r = self.transport_force + self.coriolis_force
        return self.transport_moment + self.coriolis_moment + cross(r, p)


def body_inertial_forces(
    frame: FrameMotion,
    body: Any,
    *,
    velocity: ArrayLike = (0.0, 0.0, 0.0),
    angular_velocity: ArrayLike = (0.0, 0.0, 0.0),
    t: float = 0.0,
) -> BodyInertialForces:
    """Resultants and moments of the transport and Coriolis forces over a rigid body
    moving in a moving frame (theory §9).

    Parameters
    ----------
    frame : FrameMotion or callable
        The frame's motion (``W0``, ``w``, ``eps``), or ``frame(t)``.
    body : RigidBody
        Mass, centre of mass ``r_c`` and inertia about it, all in the frame's axes
        and relative to the frame's origin ``O`` (the body's reference point is
        ``O``).
    velocity : array_like, shape (3,), optional
        Velocity of the centre of mass relative to the frame, ``u_c`` (m/s).
    angular_velocity : array_like, shape (3,), optional
        Angular velocity of the body relative to the frame, ``W`` (rad/s).
    t : float, optional
        Time at which a callable ``frame`` is evaluated.

    Returns
    -------
    BodyInertialForces
        The sums over the body of :func:`inertial_forces`:
        ``sum r x (eps x r) dm = J_O eps``, ``sum r x (w x (w x r)) dm = w x J_O w``,
        and, with ``v_r = u_c + W x rho``, ``sum rho x (w x (W x rho)) dm = -W x (S w)``.
        The moment of the transport forces is **not** the resultant applied at the
        centre of mass unless ``w`` and ``eps`` are principal directions there.

    Examples
    --------
    A rod of mass 3 kg and length 2 m along x from the axis, the frame turning at
    2 rad/s about z: ``R^e = m w^2 L/2`` outwards, no moment about ``O``.

    >>> from poinsot.kinematics import FrameMotion
    >>> from poinsot.mass import RigidBody
    >>> from poinsot.dynamics import body_inertial_forces
    >>> rod = RigidBody(3.0, [0.0, 1.0, 1.0], center_of_mass=[1.0, 0.0, 0.0])
    >>> f = body_inertial_forces(FrameMotion(omega=[0, 0, 2.0]), rod)
    >>> f.transport_force + 0.0, f.transport_moment + 0.0
    (array([12.,  0.,  0.]), array([0., 0., 0.]))
    """

    if not isinstance(body, RigidBody) or body.shape != ():
        raise InvalidTypeError(
            f"Expected `body` to be one poinsot.mass.RigidBody, got {type(body).__name__}."
        )
    fr = _frame_at(frame, t)
    if fr.omega.shape != (3,):
        raise InvalidInputError("Expected one frame motion (vectors of shape (3,)).")
    u = as_vec3(velocity, "velocity")
    big_w = as_vec3(angular_velocity, "angular_velocity")
    if u.shape != (3,) or big_w.shape != (3,):
        raise InvalidInputError(
            "Expected `velocity` and `angular_velocity` of shape (3,), got "
            f"{u.shape} and {big_w.shape}."
        )
    m = float(body.mass)
    rc = np.asarray(body.center_of_mass, dtype=float)
    j_c = np.asarray(body.inertia, dtype=float)
    j_o = np.asarray(body.inertia_about((0.0, 0.0, 0.0)), dtype=float)
    w, eps, w0 = fr.omega, fr.eps, fr.origin_acceleration
    # the point kernel (Rivals' terms) at the centre of mass gives the resultant
    a0, rot, cen = _rivals_terms(w0, w, eps, rc)
    r_e = -m * (a0 + rot + cen)
    m_e = -(m * cross(rc, w0) + j_o @ eps + cross(w, j_o @ w))
    r_c = -2.0 * m * cross(w, u)
    s = 0.5 * np.trace(j_c) * np.eye(3) - j_c
    m_c = cross(rc, r_c) + 2.0 * cross(big_w, s @ w)
    return BodyInertialForces(r_e, m_e, r_c, m_c)


def _frame_at(frame: Any, t: float) -> FrameMotion:
    """The frame at time ``t``: a FrameMotion as is, a callable evaluated and checked."""
    if isinstance(frame, FrameMotion):
        return frame
    if callable(frame):
        out = frame(float(t))
        if not isinstance(out, FrameMotion):
            raise InvalidTypeError(
                f"Expected `frame(t)` to return a FrameMotion, got {type(out).__name__}."
            )
        return out
    raise InvalidTypeError(
        "Expected `frame` to be a poinsot.kinematics.FrameMotion or a callable "
        f"frame(t) -> FrameMotion, got {type(frame).__name__}."
    )


def jacobi_integral(
    frame: FrameMotion,
    r: ArrayLike,
    v: ArrayLike,
    *,
    mass: ArrayLike = 1.0,
    potential: Callable[[np.ndarray], ArrayLike] | None = None,
) -> FloatArray:
    """Jacobi's integral of relative motion in a uniformly rotating frame (theory §9).

    ``h = m |v_r|^2 / 2 - m |w x r|^2 / 2 + m W0 . r + U(r)``

    is conserved when ``w`` and ``W0`` are constant in the frame's axes
    (``eps = 0``) and the real force is ``-grad U``: the centrifugal and origin
    forces derive from ``-m |w x r|^2 / 2`` and ``m W0 . r``, and the Coriolis
    force does no work.

    Parameters
    ----------
    frame : FrameMotion
        A frame with ``eps = 0`` (one instant; ``omega`` and
        ``origin_acceleration`` constant).
    r, v : array_like, shape (..., 3)
        Relative positions (m) and velocities (m/s), frame axes.
    mass : array_like, shape (...), optional
        Mass (kg), default 1.
    potential : callable or array_like, optional
        ``U(r) -> (...)`` in J (called with ``r`` of shape (..., 3)), or its
        values. Default: no real force (``U = 0``).

    Returns
    -------
    ndarray, shape (...)
        ``h`` in J.

    Raises
    ------
    InvalidInputError
        A frame with ``eps != 0`` (no Jacobi integral exists then).

    Examples
    --------
    A particle at rest in a frame turning at 2 rad/s, 1 m from the axis:

    >>> from poinsot.kinematics import FrameMotion
    >>> from poinsot.dynamics import jacobi_integral
    >>> float(jacobi_integral(FrameMotion(omega=[0, 0, 2]), [1, 0, 0], [0, 0, 0]))
    -2.0
    """
    frame = _as_frame(frame)
    if np.any(frame.eps != 0):
        raise InvalidInputError(
            "Expected `frame` to rotate uniformly (eps = 0) for a Jacobi integral, "
            f"got eps = {np.asarray(frame.eps).tolist()}."
        )
    r = as_vec3(r, "r")
    v = as_vec3(v, "v")
    m = _as_mass(mass)
    batch_shape(r=(r, 1), v=(v, 1), mass=(m, 0), frame=(frame.omega, 1))
    wr = cross(frame.omega, r)
    h = 0.5 * m * dot(v, v) - 0.5 * m * dot(wr, wr) + m * dot(frame.origin_acceleration, r)
    if potential is not None:
        u = potential(r) if callable(potential) else potential
        h = h + as_float_array(u, "potential")
    return h


# ---------------------------------------------------------------------------
# Integration
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False, repr=False)
class ParticleTrajectory(PointTrajectory):
    """Samples of a particle's motion relative to a moving frame: a
    :class:`poinsot.trajectory.PointTrajectory` that knows its frame's motion.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times (s).
    position, velocity : ndarray, shape (n, ..., 3)
        ``r`` and ``v_r`` relative to the frame, frame axes (m, m/s).
    mass : ndarray, shape (...)
        Masses (kg).
    method : str
        Solver name (a ``scipy.integrate.solve_ivp`` method).
    frame : FrameMotion or callable
        The frame the motion was computed in (a callable frame is not pickled:
        it is ``None`` after a round trip through pickle).
    frame_name : str
        ``"frame"``: the vectors are in the moving frame's axes.
    inertial_position, inertial_velocity : ndarray, shape (n, ..., 3) or None
        The same motion seen from the inertial frame (inertial axes), when
        asked for (``inertial=True``).
    frame_rotation : Rotation, shape (n,) or None
        Attitude of the frame (frame -> inertial components) at each time.
    frame_origin : ndarray, shape (n, 3) or None
        Position of the frame's origin in the inertial frame.
    info : mapping
        ``solver``, ``rtol``, ``atol``, ``evaluations`` (right-hand-side
        calls, summed over the batch), ``message`` (keys of :data:`poinsot.trajectory.INFO_KEYS`).
    """

    def _frame_motion(self) -> Any:
        if self.frame is None:
            raise InvalidInputError(
                "This particle trajectory no longer knows its frame (a frame given as a "
                "Python callable is not pickled): recompute it with simulate_particle."
            )
        return self.frame

    @property
    def kinetic_energy(self) -> np.ndarray:
        """Relative kinetic energy ``T_r = m |v_r|^2 / 2`` (J), shape (n, ...)."""
        m = self.mass
        assert m is not None  # simulate_particle always records the mass
        return 0.5 * m * dot(self.velocity, self.velocity)

    def to_trajectory(self, method: str | None = None) -> Trajectory:
        """The motion as a :class:`poinsot.trajectory.Trajectory` (one particle).

        ``rotation`` is the frame's attitude (frame -> inertial), ``omega`` the
        frame's angular velocity in its own axes (rad/s), ``position`` and
        ``velocity`` the particle's *inertial* position and velocity (space axes),
        as the Trajectory's conventions say. Needs ``inertial=True``; recover the
        relative motion with :func:`relative_motion`. ``method`` names the method
        in the result (default: the solver's name, e.g. ``"DOP853"``).
        """

        if (
            self.inertial_position is None
            or self.frame_rotation is None  # set with inertial_position
            or self.position.ndim != 2
        ):
            raise InvalidInputError(
                "Expected one particle simulated with inertial=True for a Trajectory."
            )
        frame = self._frame_motion()
        if isinstance(frame, FrameMotion):
            omega = np.broadcast_to(frame.omega, self.position.shape)
        else:
            omega = np.stack([_frame_at(frame, tk).omega for tk in self.t])
        return Trajectory(
            self.t,
            self.frame_rotation,
            omega,
            self.method if method is None else method,
            info=dict(self.info),
            position=self.inertial_position,
            velocity=self.inertial_velocity,
        )

    def inertial_forces(self) -> InertialForces:
        """:func:`inertial_forces` at every sample, shape (n, ..., 3)."""
        frame = self._frame_motion()
        mass = self.mass
        assert mass is not None  # simulate_particle always records the mass
        if isinstance(frame, FrameMotion):
            return inertial_forces(frame, self.position, self.velocity, mass)
        parts = [
            inertial_forces(frame, self.position[k], self.velocity[k], mass, t=tk)
            for k, tk in enumerate(self.t)
        ]
        return InertialForces(
            *(
                np.stack([getattr(p, f) for p in parts])
                for f in ("origin", "euler", "centrifugal", "transport", "coriolis")
            )
        )


class _Force:
    """A validated force: None (zero), a constant vector or ``force(t, r, v)``."""

    def __init__(self, force: Any) -> None:
        self.calls = 0
        self.const: Any  # a (3,) or (N, 3) array; None when `fn` is the force
        self.fn: Any
        if force is None:
            self.const = np.zeros(3)
            self.fn = None
        elif callable(force):
            self.const = None
            self.fn = force
        else:
            self.const = as_vec3(force, "force")
            self.fn = None

    def __call__(self, t: float, r: np.ndarray, v: np.ndarray, index: Any) -> np.ndarray:
        if self.fn is None:
            c = self.const
            return c if c.ndim == 1 else c[index]
        self.calls += 1
        return _call_force(self.fn, t, r, v, nonfinite=IntegrationError)


def _frame_matrices(fr: FrameMotion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(W0, A, B)``, ``J_e + J_c = -m (W0 + A r + B v)``: ``A = eps^ + w^ w^``, ``B = 2 w^``."""
    wh = hat(fr.omega)
    return fr.origin_acceleration, hat(fr.eps) + wh @ wh, 2.0 * wh


def _tolerance(x: ArrayLike, name: str, strict: bool) -> float:
    a = as_float_array(x, name, finite=False)
    if a.ndim != 0 or np.isnan(a) or not (a > 0 if strict else a >= 0):
        word = "positive" if strict else "non-negative"
        raise InvalidInputError(f"Expected `{name}` to be a {word} scalar, got {x!r}.")
    return float(a)


@renamed(r0="position0", v0="velocity0")
def simulate_particle(
    frame: Any,  # a FrameMotion or frame(t) -> FrameMotion (checked below)
    force: ArrayLike | Callable[..., ArrayLike] | None,
    position0: ArrayLike,
    velocity0: ArrayLike,
    t: ArrayLike,
    *,
    mass: ArrayLike = 1.0,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_step: float = math.inf,
    inertial: bool = False,
    progress: Progress = None,
    events: Any = None,
) -> ParticleTrajectory:
    """Integrate a particle's motion relative to a moving frame (theory §9).

    Solves ``m a_r = F(t, r, v_r) + J_e + J_c`` with
    ``J_e = -m (W0 + eps x r + w x (w x r))`` and ``J_c = -2 m w x v_r``
    (see :func:`inertial_forces`) for one or a batch of initial conditions.

    Parameters
    ----------
    frame : FrameMotion or callable
        The frame's motion: a constant :class:`~poinsot.kinematics.FrameMotion`
        (shape ``()``: ``W0``, ``w``, ``eps`` fixed in the frame's axes), or a
        function ``frame(t) -> FrameMotion``.
    force : None, array_like (3,) or (..., 3), or callable
        The real force in N, frame axes: ``None`` (none), a constant vector
        (per particle if batched), or ``force(t, r, v) -> (3,)`` called with
        one particle's relative ``r`` and ``v_r`` (shape (3,)).
    position0, velocity0 : array_like, shape (..., 3)
        Initial relative position (m) and velocity (m/s); leading dimensions
        are a batch of independent particles.
    t : array_like, shape (n,)
        Output times (s), strictly increasing; ``t[0]`` is the initial time.
    mass : array_like, shape (...), optional
        Mass (kg, > 0), default 1.
    method : str, optional
        ``scipy.integrate.solve_ivp`` method (default ``"DOP853"``, explicit
        Runge-Kutta of order 8 with step control); see :data:`PARTICLE_SOLVERS`.
    rtol, atol : float, optional
        Local error tolerances on the state ``(r, v_r)``: each component's
        error estimate is kept below ``atol + rtol |y|`` (defaults 1e-10 and
        1e-12, in m and m/s). Each particle of a batch is integrated with its
        own step control, so its result does not depend on the others.
    max_step : float, optional
        Longest step (s), default unbounded.
    progress : bool or callable, optional
        ``True``: a progress bar (tqdm when installed); a callable: called with the
        fraction done in ``[0, 1]``; default None. The solver loop is Python: Ctrl-C
        stops it between steps (``KeyboardInterrupt``, nothing partial returned).
    inertial : bool, optional
        Also return the motion seen from the inertial frame, whose axes and
        origin coincide with the frame's at ``t[0]``; the frame's attitude
        follows ``R' = R w^`` and its origin ``X0'' = R W0`` with
        ``X0'(t[0]) = V0`` (``origin_velocity`` of the frame at ``t[0]``).

    Returns
    -------
    ParticleTrajectory
        Positions and velocities relative to the frame (and inertial ones if
        asked for), time first: shape (n, ..., 3).

    Raises
    ------
    InvalidInputError
        Non-finite or badly shaped inputs, a mass <= 0, bad tolerances.
    IntegrationError
        The solver failed or the force returned non-finite values.

    Notes
    -----
    **Convention:** frame axes throughout (see the module docstring); a
    constant frame's vectors are constant *in the frame's axes*.

    Examples
    --------
    A stone dropped from rest 100 m above the ground at 45 deg latitude lands
    east of the plumb line by ``(1/3) Omega g t^3 cos(latitude)``:

    >>> import numpy as np
    >>> from poinsot.dynamics import earth_frame, simulate_particle, eastward_deflection
    >>> g = 9.81
    >>> fall = np.sqrt(2 * 100 / g)
    >>> tr = simulate_particle(earth_frame(45, degrees=True), [0, 0, -g], [0, 0, 100],
    ...                        [0, 0, 0], [0.0, fall])
    >>> east = tr.position[-1, 0]
    >>> round(float(east), 5), round(float(eastward_deflection(100, 45, g=g, degrees=True)), 5)
    (0.01553, 0.01553)
    """
    from scipy.integrate import solve_ivp

    if not (isinstance(frame, FrameMotion) or callable(frame)):
        raise InvalidTypeError(
            "Expected `frame` to be a poinsot.kinematics.FrameMotion or a callable "
            f"frame(t) -> FrameMotion, got {type(frame).__name__}."
        )
    if isinstance(frame, FrameMotion) and frame.shape != ():
        raise InvalidInputError(
            f"Expected `frame` to describe one frame (shape ()), got shape {frame.shape}; "
            "pass a callable frame(t) for a frame that changes with time."
        )
    r0 = as_vec3(position0, "position0")
    v0 = as_vec3(velocity0, "velocity0")
    m = as_float_array(mass, "mass")
    if np.any(m <= 0):
        raise InvalidInputError(
            f"Expected `mass` to be positive (kg), got {float(m[m <= 0].ravel()[0])!r}."
        )
    t = as_times(t, "t")
    method = integrators.check_method(method, PARTICLE_SOLVERS, "a particle")
    rtol = _tolerance(rtol, "rtol", True)
    atol = _tolerance(atol, "atol", False)
    max_step = _tolerance(max_step, "max_step", True)
    if not (np.isfinite(rtol) and np.isfinite(atol)):
        raise InvalidInputError(f"Expected finite `rtol` and `atol`, got {rtol!r} and {atol!r}.")
    inertial = as_bool(inertial, "inertial")
    fmodel = _Force(force)
    fshape = (fmodel.const, 1) if fmodel.const is not None else ((), 0)
    batch = batch_shape(position0=(r0, 1), velocity0=(v0, 1), mass=(m, 0), force=fshape)
    nb = math.prod(batch)
    R0 = np.broadcast_to(r0, batch + (3,)).reshape(nb, 3)
    V0 = np.broadcast_to(v0, batch + (3,)).reshape(nb, 3)
    M = np.broadcast_to(m, batch).reshape(nb)
    if fmodel.const is not None:
        fmodel.const = np.broadcast_to(fmodel.const, batch + (3,)).reshape(nb, 3)

    const = isinstance(frame, FrameMotion)
    if const:
        w0c, Ac, Bc = _frame_matrices(frame)

    n = t.size
    pos = np.empty((n, nb, 3))
    vel = np.empty((n, nb, 3))
    nfev = 0
    message = ""
    report = as_progress(progress, "simulate_particle")
    event_list = as_events(events)

    def particle_rhs(i: int) -> Callable[[float, np.ndarray], np.ndarray]:
        mi = M[i]

        def rhs(tn: float, y: np.ndarray) -> np.ndarray:
            r, v = y[:3], y[3:]
            if const:
                w0, A, B = w0c, Ac, Bc
            else:
                w0, A, B = _frame_matrices(_frame_at(frame, tn))
            a = fmodel(tn, r, v, i) / mi - w0 - A @ r - B @ v
            return np.concatenate((v, a))

        return rhs

    for i in range(nb):
        rhs = particle_rhs(i)

        y0 = np.concatenate((R0[i], V0[i]))
        if n == 1:
            pos[0, i], vel[0, i] = R0[i], V0[i]
            continue
        part = None if report is None else (lambda f, i=i: report((i + f) / nb))
        fun = ivp_progress(rhs, float(t[0]), float(t[-1]), part)
        try:
            sol = solve_ivp(
                fun, (t[0], t[-1]), y0, method=method, t_eval=t, rtol=rtol, atol=atol,
                max_step=max_step,
            )  # fmt: skip
        except BaseException:  # Ctrl-C (between the solver's steps) or a failing force
            if report is not None:
                report.close()
            raise
        if sol.status != 0 or sol.y.shape[1] != n or not np.all(np.isfinite(sol.y)):
            reached = float(sol.t[-1]) if sol.t.size else float(t[0])
            raise IntegrationError(
                f"Particle integration ({method}) failed after t = {reached:.6g} s "
                f"(particle {i}): {sol.message}"
            )
        pos[:, i], vel[:, i] = sol.y[:3].T, sol.y[3:].T
        nfev += int(sol.nfev)
        message = sol.message
    if report is not None:
        report.finish()
    if event_list:

        def flow(bodies: np.ndarray, t0: float, t1: float, y0: np.ndarray) -> Any:
            # each particle alone: its own step control, as in the run itself
            sols = [solve_dense(_one(particle_rhs(int(b))), t0, t1, y0[b][None]) for b in bodies]
            return lambda s: np.concatenate([sol(s) for sol in sols], axis=0)

        y_all = np.concatenate([pos, vel], axis=-1)
        t, y_all, info_events = locate(event_list, t, y_all, flow, batch)
        pos, vel = np.ascontiguousarray(y_all[..., :3]), np.ascontiguousarray(y_all[..., 3:])
        n = t.size
    shape = (n, *batch, 3)
    info = {"solver": method, "rtol": rtol, "atol": atol, "evaluations": nfev, "message": message}
    if event_list:
        info["events"] = info_events
    extra: dict[str, Any] = {}
    if inertial:
        rot, x0, vo = _frame_path(frame, t, rtol, atol, max_step)
        q = rot.as_quat()  # (n, 4)

        p = pos + 0.0
        wr = np.empty_like(p)
        for k in range(n):
            fr = _frame_at(frame, t[k])
            wr[k] = cross(fr.omega, p[k])
        vo_frame = rotate(q * [1.0, -1.0, -1.0, -1.0], vo)  # origin velocity in frame axes
        va = vel + wr + vo_frame[:, None, :]
        extra = {
            "inertial_position": (x0[:, None, :] + rotate(q[:, None, :], p)).reshape(shape),
            "inertial_velocity": rotate(q[:, None, :], va).reshape(shape),
            "frame_rotation": rot,
            "frame_origin": x0,
        }
    return ParticleTrajectory(
        t=t,
        position=pos.reshape(shape),
        velocity=vel.reshape(shape),
        mass=np.broadcast_to(m, batch).copy(),
        method=method,
        frame_name="frame",
        frame=frame,
        info=info,
        **extra,
    )


def _one(rhs: Callable[[float, np.ndarray], np.ndarray]) -> Callable[..., np.ndarray]:
    """A one-particle right-hand side as one of a batch of one: ``(t, Y (1, 6))``."""
    return lambda tn, y: rhs(tn, y[0])[None]


def _frame_path(
    frame: Any, t: np.ndarray, rtol: float, atol: float, max_step: float
) -> tuple[Any, np.ndarray, np.ndarray]:
    """Attitude (frame -> inertial), origin position and velocity (inertial axes) of the frame.

    A constant frame with ``W0 = 0`` moves in closed form (``R = exp((t - t0) w^)``,
    ``X0 = V0 (t - t0)`` with ``V0`` the initial origin velocity); otherwise
    ``q' = q o w / 2``, ``X0' = V0``, ``V0' = R W0`` are integrated (DOP853).
    """
    from scipy.integrate import solve_ivp

    fr0 = _frame_at(frame, t[0])
    dt = t - t[0]
    if isinstance(frame, FrameMotion) and not np.any(frame.origin_acceleration):
        rot = Rotation.from_rotvec(dt[:, None] * frame.omega)
        vo_in = np.broadcast_to(frame.origin_velocity, (t.size, 3)).copy()
        return rot, dt[:, None] * frame.origin_velocity, vo_in

    def rhs(tn: float, y: np.ndarray) -> np.ndarray:
        fr = _frame_at(frame, tn)
        q = y[:4]
        return np.concatenate(
            (_quat_rate(q, fr.omega, "body"), y[7:], rotate(q, fr.origin_acceleration))
        )

    y0 = np.concatenate(([1.0, 0.0, 0.0, 0.0], np.zeros(3), fr0.origin_velocity))
    if t.size == 1:
        ys = y0[:, None]
    else:
        sol = solve_ivp(
            rhs,
            (t[0], t[-1]),
            y0,
            method="DOP853",
            t_eval=t,
            rtol=rtol,
            atol=atol,
            max_step=max_step,
        )
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            raise IntegrationError(f"Integrating the frame's motion failed: {sol.message}")
        ys = sol.y
    return Rotation.from_quat(ys[:4].T), ys[4:7].T.copy(), ys[7:].T.copy()


def relative_motion(trajectory: Any) -> tuple[FloatArray, FloatArray]:
    """Position and velocity relative to a frame turning about a fixed origin.

    ``r = R^T x`` and ``v_r = R^T v - w x r`` from a
    :class:`~poinsot.trajectory.Trajectory` whose ``rotation`` is the frame's
    attitude, ``omega`` its angular velocity in frame axes and ``position``,
    ``velocity`` the inertial motion (see :meth:`ParticleTrajectory.to_trajectory`),
    for a frame whose origin stays at the inertial origin (``V0 = W0 = 0``, as
    :func:`earth_frame`).

    Returns
    -------
    position, velocity : ndarray, shape (n, 3)
        Frame axes (m, m/s).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.kinematics import FrameMotion
    >>> from poinsot.dynamics import simulate_particle, relative_motion
    >>> tr = simulate_particle(FrameMotion(omega=[0, 0, 1]), None, [1, 0, 0], [0, 1, 0],
    ...                        np.linspace(0, 1, 3), inertial=True)
    >>> r, v = relative_motion(tr.to_trajectory())
    >>> bool(np.allclose(r, tr.position) and np.allclose(v, tr.velocity))
    True
    """
    if (
        getattr(trajectory, "position", None) is None
        or getattr(trajectory, "rotation", None) is None
    ):
        raise InvalidTypeError(
            "Expected a Trajectory with a translational part (position, velocity), got "
            f"{type(trajectory).__name__}."
        )
    inv = trajectory.rotation.inv()
    r = inv.apply(trajectory.position)
    v = inv.apply(trajectory.velocity) - cross(trajectory.omega, r)
    return r, v
