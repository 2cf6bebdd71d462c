"""Attitude control laws as torque models (docs/theory.md §10.3).

Each law is a :class:`~poinsot.dynamics.TorqueModel`: ``simulate(..., torque=law)``
closes the loop with an ideal external torque, and ``law.wheel_command(wheels,
inertia)`` gives the motor command of :func:`~poinsot.dynamics.simulate_wheels` that
makes the body see the same torque through reaction wheels.

Laws
----
:class:`QuaternionPD`
    ``L = -kp sign(dq0) dq_v - kd dw`` (+ feedforward), Wie, Weiss & Arapostathis 1989.
:class:`MRPFeedback`
    ``L = -K sigma - P dw + J (w_r' - w x w_r) + w x J w`` (Schaub & Junkins;
    Basilisk ``mrpFeedback`` without the integral term).
:class:`EigenaxisSlew`
    A rest-to-rest slew about the eigenaxis with a bang-coast-bang rate profile,
    tracked by a quaternion PD with feedforward.
:class:`BDot`
    Magnetorquer detumbling ``m = -k dB_b/dt`` (saturated), torque ``m x B_b``.

**Targets and frames.** A target is the attitude of a reference frame ``R``: an
inertial attitude (a :class:`~poinsot.Rotation`, scalar-first quaternion ``(4,)`` or
SciPy ``Rotation``; then ``R`` is at rest), or a callable ``target(t) -> (q_r, w_r,
w_r_dot)`` with ``q_r`` the attitude of ``R`` (R -> space, ``(4,)`` or a Rotation),
``w_r`` the angular velocity of ``R`` in **R axes** (rad/s) and ``w_r_dot`` its
derivative, in R axes (rad/s^2). The error quaternion is ``dq = q_r^* o q`` (attitude
of the body relative to ``R``, body -> R), the rate error ``dw = w - w_r_B`` with
``w_r_B = C(dq)^T w_r`` (body axes).

**Convention:** scalar-first Hamilton quaternions body -> space; ``omega`` in body axes
(rad/s); torques in N m, body axes; magnetic fields in tesla, dipoles in A m^2.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _quat
from .._validate import as_float_array, as_positive, as_rotation_quat
from .._vec import cross, diagonal3
from ..errors import InvalidInputError, InvalidTypeError
from ..mass.tensor import as_inertia
from ..rotations.rodrigues import mrp_from_quat
from .torques import TorqueModel
from .wheels import ReactionWheels, _tensor

__all__ = ["QuaternionPD", "MRPFeedback", "EigenaxisSlew", "SlewProfile", "BDot"]

_ZERO3 = np.zeros(3)
_ZERO3.setflags(write=False)


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64)
    a.setflags(write=False)
    return a


def _scalar(x: object, name: str) -> float:
    """A positive finite scalar parameter."""
    a = as_positive(x, name)
    if a.ndim != 0:
        raise InvalidInputError(f"Expected `{name}` to be a scalar, got shape {a.shape}.")
    return float(a)


def _inertia3(inertia: object, name: str = "inertia") -> np.ndarray:
    """One body's inertia as a (3, 3) tensor in body axes."""
    j, principal = as_inertia(inertia, name)
    if j.shape != ((3,) if principal else (3, 3)):
        raise InvalidInputError(
            f"Expected `{name}` for one body, (3,) or (3, 3), got {j.shape} (no batches)."
        )
    return _ro(diagonal3(j) if principal else j)


def _matvec(j: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.einsum("ij,...j->...i", j, v)


def _as_target(target: object) -> Any:
    """A constant unit quaternion (4,) (read-only) or a callable."""
    if callable(target) and not hasattr(target, "as_quat"):
        return target
    if target is None:
        raise InvalidTypeError(
            "Expected `target` to be an attitude (Rotation or quaternion (4,)) or a callable "
            "t -> (q_r, w_r, w_r_dot), got None."
        )
    q = as_rotation_quat(target, "target")
    if q.shape != (4,):
        raise InvalidInputError(f"Expected `target` to have shape (4,), got {q.shape}.")
    return _ro(q)


def _reference(target: Any, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q_r, w_r, w_r_dot)`` of the target at ``t`` (R axes), checked."""
    if isinstance(target, np.ndarray):
        return target, _ZERO3, _ZERO3
    out = target(t)
    if not isinstance(out, tuple | list) or len(out) != 3:
        raise InvalidInputError(
            f"Expected `target` to return (q_r, w_r, w_r_dot), got {type(out).__name__}."
        )
    q = as_rotation_quat(out[0], "target")
    w = as_float_array(out[1], "target")
    a = as_float_array(out[2], "target")
    if q.shape != (4,) or w.shape != (3,) or a.shape != (3,):
        raise InvalidInputError(
            "Expected `target` to return shapes (4,), (3,), (3,), got "
            f"{q.shape}, {w.shape}, {a.shape}."
        )
    return q, w, a


def _errors(
    target: Any, t: float, quat: np.ndarray, omega: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(dq, dw, w_r_B, w_r_dot_B)``: ``dq = q_r^* o q`` with ``dq0 >= 0`` (shortest way),
    ``dw = w - w_r_B``, the reference rate and acceleration in body axes."""
    q_r, w_r, a_r = _reference(target, t)
    q = np.asarray(quat, dtype=np.float64)
    w = np.asarray(omega, dtype=np.float64)
    dq = _quat.mul(_quat.conj(q_r), q)
    dq = np.where(dq[..., :1] < 0.0, -dq, dq)
    w_rb = _quat.to_body(dq, np.broadcast_to(w_r, dq.shape[:-1] + (3,)))
    a_rb = _quat.to_body(dq, np.broadcast_to(a_r, dq.shape[:-1] + (3,)))
    return dq, w - w_rb, w_rb, a_rb


def _feedforward(j: np.ndarray, w: np.ndarray, w_rb: np.ndarray, a_rb: np.ndarray) -> np.ndarray:
    """``J (w_r' - w x w_r) + w x J w`` (body axes)."""
    return _matvec(j, a_rb - cross(w, w_rb)) + cross(w, _matvec(j, w))


class _ControlLaw(TorqueModel):
    """A torque model that can also drive reaction wheels."""

    def wheel_command(
        self, wheels: ReactionWheels, inertia: object
    ) -> Callable[[float, np.ndarray, np.ndarray, np.ndarray], np.ndarray]:
        """The motor command of :func:`~poinsot.dynamics.simulate_wheels` that gives the
        body this law's torque ``L`` (docs/theory.md §10.3).

        With ``G = [a_1 ... a_N]`` (3, N), ``h = sum_i I_i Omega_i a_i`` (relative wheel
        momentum) and ``J_a = sum_i I_i a_i a_i^T``,

        ``u = -pinv(G) (L + w x h - J_a w_d')``,  ``w_d' = J^{-1} (L - w x J w)``:

        the motors' reaction ``-G u`` on the body then makes ``J w' + w x J w = L``
        exactly (the body moves as under the external torque ``L``) while ``G`` has
        rank 3 and no motor saturates (``max_torque``, ``max_speed``).

        Parameters
        ----------
        wheels : ReactionWheels
            The wheel set (axes span the body axes).
        inertia : array_like, shape (3,) or (3, 3)
            ``J`` of body and locked wheels (kg m^2), the one given to
            ``simulate_wheels``.

        Returns
        -------
        callable
            ``command(t, q, w, Omega) -> (N,)`` motor torques (N m).

        Notes
        -----
        **Convention:** scalar-first quaternions body -> space, ``w`` body axes (rad/s),
        torques N m (body axes for ``L``, about the wheel axes for ``u``).

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import QuaternionPD, ReactionWheels
        >>> rw = ReactionWheels(np.eye(3), 0.01)
        >>> cmd = QuaternionPD(1.0, 2.0, target=[1.0, 0, 0, 0]).wheel_command(rw, [1.0, 1, 1])
        >>> cmd(0.0, np.array([1.0, 0, 0, 0]), np.array([0.0, 0, 0.1]), np.zeros(3)).round(6)
        array([0.   , 0.   , 0.198])
        """
        if not isinstance(wheels, ReactionWheels):
            raise InvalidTypeError(
                f"Expected `wheels` to be a ReactionWheels, got {type(wheels).__name__}."
            )
        j = _tensor(inertia)
        j_inv = np.linalg.inv(j)
        g = wheels.axes.T
        if np.linalg.matrix_rank(g) < 3:
            raise InvalidInputError("Expected `wheels` axes to span the three body axes.")
        g_pinv = np.linalg.pinv(g)
        j_ax = wheels.axial_inertia
        law = self

        def command(t: float, q: np.ndarray, w: np.ndarray, om: np.ndarray) -> np.ndarray:
            torque = law.body_torque(t, q, w)
            h = wheels.momentum(om)
            w_dot = j_inv @ (torque - np.cross(w, j @ w))
            return -g_pinv @ (torque + np.cross(w, h) - j_ax @ w_dot)

        return command


@dataclass(frozen=True, eq=False)
class QuaternionPD(_ControlLaw):
    """Quaternion PD attitude control (docs/theory.md §10.3).

    ``L = -kp sign(dq0) dq_v - kd dw`` (+ ``J (w_r' - w x w_r) + w x J w`` when
    ``inertia`` is given), with ``dq = q_r^* o q = (dq0, dq_v)`` and
    ``dw = w - w_r_B`` (module notes); ``sign(dq0)`` turns the body the short way.

    Parameters
    ----------
    kp : float
        Attitude gain (N m), > 0.
    kd : float
        Rate gain (N m s), > 0.
    target : Rotation, array_like (4,) or callable
        The reference attitude, or ``target(t) -> (q_r, w_r, w_r_dot)`` (R axes).
    inertia : array_like (3,) or (3, 3), optional
        ``J`` (kg m^2, body axes): adds the feedforward ``J (w_r' - w x w_r) + w x J w``.
        Default: none (the plain PD).

    Raises
    ------
    InvalidInputError
        A non-positive gain, a target of the wrong shape.
    InvalidTypeError
        A target that is neither an attitude nor a callable.

    Notes
    -----
    Stability (Wie, Weiss & Arapostathis 1989): for a target at rest and ``kp, kd > 0``,
    ``V = 1/2 w . J w + 2 kp (1 - |dq0|)`` has ``V' = -kd |w|^2`` (with or without the
    feedforward), and the rest attitude ``dq = (+-1, 0)`` is globally asymptotically
    stable (LaSalle). With the feedforward and a moving target,
    ``V = 1/2 dw . J dw + 2 kp (1 - |dq0|)``, ``V' = -kd |dw|^2``. About a principal
    axis of moment ``J`` at small angles ``dq_v ~ theta / 2``: ``J theta'' + kd theta'
    + (kp / 2) theta = 0``, natural frequency ``sqrt(kp / (2 J))`` and damping ratio
    ``kd / sqrt(2 kp J)``.

    **Convention:** scalar-first Hamilton quaternions body -> space, ``omega`` body
    axes (rad/s), torques N m body axes.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.dynamics import QuaternionPD
    >>> law = QuaternionPD(2.0, 1.0, target=Rotation.identity())
    >>> q = Rotation.from_rotvec([0.0, 0.0, 0.2]).as_quat()
    >>> law.body_torque(0.0, q, np.zeros(3)).round(6)     # -2 sin(0.1) e_z
    array([-0.      , -0.      , -0.199667])
    """

    kp: Any
    kd: Any
    target: Any
    inertia: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "kp", _scalar(self.kp, "kp"))
        object.__setattr__(self, "kd", _scalar(self.kd, "kd"))
        object.__setattr__(self, "target", _as_target(self.target))
        if self.inertia is not None:
            object.__setattr__(self, "inertia", _inertia3(self.inertia))

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        dq, dw, w_rb, a_rb = _errors(self.target, t, quat, omega)
        torque = -self.kp * dq[..., 1:] - self.kd * dw
        if self.inertia is not None:
            torque = torque + _feedforward(self.inertia, np.asarray(omega, float), w_rb, a_rb)
        return torque

    def lyapunov(
        self, t: float, quat: np.ndarray, omega: np.ndarray, inertia: object = None
    ) -> Any:
        """``V = 1/2 dw . J dw + 2 kp (1 - |dq0|)`` (J), non-increasing in closed loop.

        ``inertia`` is the body's ``J`` (kg m^2); default the law's ``inertia``. Shape
        of the state's batch.

        >>> from poinsot.dynamics import QuaternionPD
        >>> law = QuaternionPD(2.0, 1.0, target=[1.0, 0, 0, 0])
        >>> float(law.lyapunov(0.0, [0.0, 1.0, 0, 0], [0.0, 0, 0], [1.0, 1, 1]))
        4.0
        """
        if inertia is None and self.inertia is None:
            raise InvalidInputError("Expected `inertia` (the law has none), got None.")
        j = self.inertia if inertia is None else _inertia3(inertia)
        dq, dw, _, _ = _errors(self.target, t, quat, omega)
        return 0.5 * np.einsum("...i,...i->...", dw, _matvec(j, dw)) + 2.0 * self.kp * (
            1.0 - dq[..., 0]
        )


@dataclass(frozen=True, eq=False)
class MRPFeedback(_ControlLaw):
    """MRP feedback with feedforward (docs/theory.md §10.3; Schaub & Junkins).

    ``L = -K sigma - P dw + J (w_r' - w x w_r) + w x J w``,

    ``sigma`` the MRPs of ``dq = q_r^* o q`` taken with ``|sigma| <= 1`` (switched to
    the shadow set ``-sigma / |sigma|^2`` beyond 1), ``dw = w - w_r`` and ``w_r``,
    ``w_r'`` the reference rate and acceleration in body axes (module notes). These are
    the terms of Basilisk's ``mrpFeedback`` (its control-law option 0) without the
    integral feedback and without wheel terms (those are in :meth:`wheel_command`).

    Parameters
    ----------
    K : float
        Attitude gain (N m), > 0.
    P : float
        Rate gain (N m s), > 0.
    inertia : array_like (3,) or (3, 3)
        ``J`` (kg m^2, body axes), used in the feedforward.
    target : Rotation, array_like (4,) or callable
        The reference (module notes).

    Raises
    ------
    InvalidInputError
        A non-positive gain, a bad inertia or target shape.
    InvalidTypeError
        A target that is neither an attitude nor a callable.

    Notes
    -----
    The closed loop is ``J dw' = -K sigma - P dw`` (body derivative of ``dw``), and
    ``V = 1/2 dw . J dw + 2 K ln(1 + |sigma|^2)`` has ``V' = -P |dw|^2``
    (``sigma . sigma' = (1 + |sigma|^2) sigma . dw / 4``); ``V`` is continuous at the
    switch ``|sigma| = 1``. Global asymptotic stability for any ``K, P > 0``.

    **Convention:** scalar-first Hamilton quaternions body -> space, ``omega`` body
    axes (rad/s), torques N m body axes.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.dynamics import MRPFeedback
    >>> law = MRPFeedback(1.0, 3.0, [1.0, 1.0, 1.0], target=Rotation.identity())
    >>> q = Rotation.from_rotvec([0.4, 0.0, 0.0]).as_quat()
    >>> law.body_torque(0.0, q, np.zeros(3)).round(6)    # -tan(0.1) e_x
    array([-0.100335, -0.      , -0.      ])
    """

    K: Any
    P: Any
    inertia: Any
    target: Any

    def __post_init__(self) -> None:
        object.__setattr__(self, "K", _scalar(self.K, "K"))
        object.__setattr__(self, "P", _scalar(self.P, "P"))
        object.__setattr__(self, "inertia", _inertia3(self.inertia))
        object.__setattr__(self, "target", _as_target(self.target))

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        dq, dw, w_rb, a_rb = _errors(self.target, t, quat, omega)
        sigma = mrp_from_quat(dq)
        w = np.asarray(omega, dtype=np.float64)
        return -self.K * sigma - self.P * dw + _feedforward(self.inertia, w, w_rb, a_rb)

    def lyapunov(self, t: float, quat: np.ndarray, omega: np.ndarray) -> Any:
        """``V = 1/2 dw . J dw + 2 K ln(1 + |sigma|^2)`` (J), non-increasing in closed loop.

        >>> from poinsot.dynamics import MRPFeedback
        >>> law = MRPFeedback(1.0, 3.0, [1.0, 1.0, 1.0], target=[1.0, 0, 0, 0])
        >>> round(float(law.lyapunov(0.0, [0.0, 1.0, 0, 0], [0.0, 0, 0])), 12)   # 2 ln 2
        1.386294361120
        """
        dq, dw, _, _ = _errors(self.target, t, quat, omega)
        s2 = np.einsum("...i,...i->...", *(2 * (mrp_from_quat(dq),)))
        kin = 0.5 * np.einsum("...i,...i->...", dw, _matvec(self.inertia, dw))
        return kin + 2.0 * self.K * np.log1p(s2)


@dataclass(frozen=True)
class SlewProfile:
    """The planned eigenaxis rotation of :class:`EigenaxisSlew` at given times.

    Attributes
    ----------
    angle : ndarray
        Angle turned about the eigenaxis (rad).
    rate : ndarray
        Its rate (rad/s).
    acceleration : ndarray
        Its second derivative (rad/s^2).

    Notes
    -----
    **Convention:** angles about the eigenaxis ``e`` (body axes), right-handed.

    Examples
    --------
    >>> from poinsot.dynamics import SlewProfile
    >>> SlewProfile(0.0, 0.0, 0.0).rate
    0.0
    """

    angle: Any
    rate: Any
    acceleration: Any


@dataclass(frozen=True, eq=False, init=False)
class EigenaxisSlew(_ControlLaw):
    """Rest-to-rest eigenaxis slew with a bang-coast-bang profile (docs/theory.md §10.3).

    From rest at ``rotation0`` (at time ``start_time``) to rest at ``target``: the
    reference turns by ``theta(t)`` about the fixed eigenaxis ``e`` of
    ``dq_total = q0^* o q_target`` (angle ``phi`` in [0, pi], the short way),
    ``q_r(t) = q0 o (cos(theta/2), sin(theta/2) e)``, ``w_r = theta' e``,
    ``w_r' = theta'' e``, with ``theta''`` equal to ``+alpha``, ``0``, ``-alpha``
    (trapezoidal rate, ``|theta'| <= max_rate``). The body tracks it with

    ``L = -kp dq_v - kd dw + J (w_r' - w x w_r) + w x J w``,

    ``dq = q_r^* o q`` (``dq0 >= 0``), scaled down to ``|L| = max_torque`` if larger.

    Parameters
    ----------
    inertia : array_like (3,) or (3, 3)
        ``J`` (kg m^2, body axes).
    target : Rotation or array_like (4,)
        Final attitude (body -> space).
    rotation0 : Rotation or array_like (4,)
        Attitude at the start, at rest.
    max_rate : float
        Largest planned rate ``|theta'|`` (rad/s), > 0.
    max_torque : float
        Largest ``|L|`` (N m), > 0.
    kp, kd : float
        Tracking gains (N m, N m s), > 0.
    start_time : float, optional
        When the slew starts (s); default 0.
    accel_fraction : float, optional
        Share of the torque left after the gyroscopic term that the profile uses,
        in (0, 1]; the rest is margin for the feedback. Default 0.8.

    Raises
    ------
    InvalidInputError
        Non-positive limits or gains, ``accel_fraction`` outside (0, 1], a torque
        limit that cannot hold the gyroscopic torque at ``max_rate``.

    Notes
    -----
    The feedforward of the profile needs ``|J e| alpha + theta'^2 |e x J e|``; the
    planned acceleration is

    ``alpha = accel_fraction (max_torque - max_rate^2 |e x J e|) / |J e|``

    (``= accel_fraction max_torque / J_e`` about a principal axis). With
    ``t_a = max_rate / alpha``: if ``phi >= max_rate t_a`` the profile accelerates for
    ``t_a``, coasts for ``phi / max_rate - t_a`` and brakes for ``t_a``,
    ``duration = phi / max_rate + max_rate / alpha``; otherwise it is triangular,
    ``duration = 2 sqrt(phi / alpha)`` with peak rate ``sqrt(phi alpha)``. Starting on
    the profile, the tracking error stays zero (the feedforward is exact), so the body
    reaches the target at ``start_time + duration``; an initial error decays like the
    :class:`QuaternionPD` loop, ``exp(-kd t / (2 J_e))`` for ``J_e = e . J e``.

    **Convention:** scalar-first Hamilton quaternions body -> space, ``omega`` body
    axes (rad/s), torques N m body axes.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.dynamics import EigenaxisSlew
    >>> slew = EigenaxisSlew([2.0, 2.0, 2.0], Rotation.from_rotvec([0.0, 0.0, 1.0]),
    ...                      rotation0=Rotation.identity(), max_rate=0.1, max_torque=0.1,
    ...                      kp=1.0, kd=2.0, accel_fraction=1.0)
    >>> round(slew.duration, 12)    # 1 / 0.1 + 0.1 / 0.05
    12.0
    >>> slew.profile([0.0, 6.0, 12.0]).angle.round(12) + 0.0
    array([0. , 0.5, 1. ])
    """

    inertia: Any
    target: Any
    rotation0: Any
    max_rate: float
    max_torque: float
    kp: float
    kd: float
    start_time: float
    accel_fraction: float
    axis: Any
    angle: float
    max_accel: float

    def __init__(
        self,
        inertia: object,
        target: object,
        *,
        rotation0: object,
        max_rate: float,
        max_torque: float,
        kp: float,
        kd: float,
        start_time: float = 0.0,
        accel_fraction: float = 0.8,
    ) -> None:
        set_ = object.__setattr__
        j = _inertia3(inertia)
        qf = _as_target(target)
        if not isinstance(qf, np.ndarray):
            raise InvalidTypeError(
                "Expected `target` to be an attitude (Rotation or quaternion (4,)), "
                f"got {type(target).__name__}."
            )
        q0 = as_rotation_quat(rotation0, "rotation0")
        if q0.shape != (4,):
            raise InvalidInputError(f"Expected `rotation0` to have shape (4,), got {q0.shape}.")
        rate = _scalar(max_rate, "max_rate")
        tmax = _scalar(max_torque, "max_torque")
        frac = _scalar(accel_fraction, "accel_fraction")
        if frac > 1.0:
            raise InvalidInputError(f"Expected `accel_fraction` in (0, 1], got {frac!r}.")
        t0 = as_float_array(start_time, "start_time")
        if t0.ndim != 0:
            raise InvalidInputError(f"Expected `start_time` to be a scalar, got {t0.shape}.")
        dq = _quat.mul(_quat.conj(q0), qf)
        if dq[0] < 0.0:
            dq = -dq
        s = float(np.linalg.norm(dq[1:]))
        phi = 2.0 * math.atan2(s, float(dq[0]))
        e = dq[1:] / s if s > 0.0 else np.array([1.0, 0.0, 0.0])
        je = j @ e
        spare = tmax - rate**2 * float(np.linalg.norm(np.cross(e, je)))
        if spare <= 0.0:
            raise InvalidInputError(
                f"Expected `max_torque` above the gyroscopic torque at `max_rate` about the "
                f"eigenaxis, {tmax - spare!r} N m, got {tmax!r}."
            )
        for name, value in (
            ("inertia", j),
            ("target", qf),
            ("rotation0", _ro(q0)),
            ("max_rate", rate),
            ("max_torque", tmax),
            ("kp", _scalar(kp, "kp")),
            ("kd", _scalar(kd, "kd")),
            ("start_time", float(t0)),
            ("accel_fraction", frac),
            ("axis", _ro(e)),
            ("angle", phi),
            ("max_accel", frac * spare / float(np.linalg.norm(je))),
        ):
            set_(self, name, value)

    @property
    def duration(self) -> float:
        """Planned slew time (s): ``phi / max_rate + max_rate / alpha`` (bang-coast-bang)
        or ``2 sqrt(phi / alpha)`` (bang-bang, when ``phi < max_rate^2 / alpha``)."""
        r, a, phi = self.max_rate, self.max_accel, self.angle
        if phi >= r * r / a:
            return phi / r + r / a
        return 2.0 * math.sqrt(phi / a)

    def profile(self, t: object) -> SlewProfile:
        """The planned ``theta``, ``theta'``, ``theta''`` at times ``t`` (s), any shape.

        >>> from poinsot.dynamics import EigenaxisSlew
        >>> slew = EigenaxisSlew([1.0, 1, 1], [0.0, 0, 0, 1], rotation0=[1.0, 0, 0, 0],
        ...                      max_rate=1.0, max_torque=1.0, kp=1.0, kd=1.0)
        >>> float(slew.profile(slew.duration).angle) == slew.angle
        True
        """
        tt = as_float_array(t, "t") - self.start_time
        a, phi, total = self.max_accel, self.angle, self.duration
        peak = min(self.max_rate, math.sqrt(phi * a))
        ta = peak / a
        tau = np.clip(tt, 0.0, total)
        back = total - tau
        acc_phase = tau < ta
        dec_phase = back < ta
        angle = np.where(
            acc_phase,
            0.5 * a * tau**2,
            np.where(dec_phase, phi - 0.5 * a * back**2, 0.5 * a * ta**2 + peak * (tau - ta)),
        )
        rate = np.where(acc_phase, a * tau, np.where(dec_phase, a * back, peak))
        accel = np.where(acc_phase, a, np.where(dec_phase, -a, 0.0))
        outside = (tt < 0.0) | (tt > total)
        rate = np.where(outside, 0.0, rate)
        accel = np.where(outside, 0.0, accel)
        return SlewProfile(angle, rate, accel)

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q_r, w_r, w_r_dot)`` of the profile at ``t`` (R axes = body axes on track).

        >>> from poinsot.dynamics import EigenaxisSlew
        >>> slew = EigenaxisSlew([1.0, 1, 1], [0.0, 0, 0, 1], rotation0=[1.0, 0, 0, 0],
        ...                      max_rate=1.0, max_torque=1.0, kp=1.0, kd=1.0)
        >>> slew.reference(1e9)[0].round(12) + 0.0
        array([0., 0., 0., 1.])
        """
        p = self.profile(float(t))
        th = float(p.angle)
        q_r = _quat.mul(self.rotation0, _quat.axis_angle(self.axis, np.asarray(th)))
        return q_r, float(p.rate) * self.axis, float(p.acceleration) * self.axis

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        ref = self.reference(t)
        dq, dw, w_rb, a_rb = _errors(lambda _t: ref, t, quat, omega)
        w = np.asarray(omega, dtype=np.float64)
        torque = -self.kp * dq[..., 1:] - self.kd * dw + _feedforward(self.inertia, w, w_rb, a_rb)
        size = np.linalg.norm(torque, axis=-1, keepdims=True)
        scale = np.where(size > self.max_torque, self.max_torque / np.maximum(size, 1e-300), 1.0)
        return torque * scale


@dataclass(frozen=True, eq=False)
class BDot(TorqueModel):
    """Magnetorquer B-dot detumbling (docs/theory.md §10.3).

    ``m = sat(-gain dB_b/dt)`` (each component clipped to ``[-max_dipole, max_dipole]``)
    and the torque ``L = m x B_b``, with ``B_b = R^T B_i(t)`` and

    ``dB_b/dt = R^T dB_i/dt - w x B_b``.

    Parameters
    ----------
    gain : float
        ``k`` (A m^2 s / T), > 0.
    max_dipole : float
        Per-axis dipole limit (A m^2), > 0 (``inf`` for none).
    field : callable
        ``field(t) -> (3,)``: the geomagnetic field in **inertial** axes (T) at time
        ``t`` (s), e.g. along an orbit.
    field_rate : callable, optional
        ``field_rate(t) -> (3,)``, ``dB_i/dt`` (T/s). Default: the central difference
        ``(B_i(t + step) - B_i(t - step)) / (2 step)``.
    step : float, optional
        The difference step (s), > 0; default 0.5 (error ~ ``step^2 |B_i'''| / 6``).

    Raises
    ------
    InvalidInputError
        A non-positive gain, limit or step; a field of the wrong shape.
    InvalidTypeError
        ``field`` or ``field_rate`` not callable.

    Notes
    -----
    The power of the torque is ``dT/dt = w . (m x B_b)``. Unsaturated,
    ``dT/dt = -k |w x B_b|^2 + k (w x B_b) . R^T dB_i/dt``: negative whenever the body
    turns fast against the field's own rotation (``|w x B_b| > |dB_i/dt|``), so a fast
    tumble is damped down to about the orbit rate. Saturated per axis, each
    ``m_j = -c_j dB_j`` with ``0 < c_j <= k``.

    **Convention:** scalar-first Hamilton quaternions body -> space, ``omega`` body
    axes (rad/s), torques N m body axes, fields T, dipoles A m^2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import BDot
    >>> law = BDot(1e4, 0.1, field=lambda t: np.array([0.0, 0.0, 3e-5]))
    >>> law.dipole(0.0, [1.0, 0, 0, 0], [0.1, 0.0, 0.0]).round(6) + 0.0   # -k (-w x B)
    array([ 0.  , -0.03,  0.  ])
    """

    gain: Any
    max_dipole: Any
    field: Callable[[float], Any]
    field_rate: Callable[[float], Any] | None = None
    step: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "gain", _scalar(self.gain, "gain"))
        m = as_float_array(self.max_dipole, "max_dipole", finite=False)
        if m.ndim != 0:
            raise InvalidInputError(f"Expected `max_dipole` to be a scalar, got {m.shape}.")
        if not m > 0.0:  # NaN too
            raise InvalidInputError(f"Expected `max_dipole` to be positive, got {float(m)!r}.")
        object.__setattr__(self, "max_dipole", float(m))
        object.__setattr__(self, "step", _scalar(self.step, "step"))
        for name in ("field", "field_rate"):
            f = getattr(self, name)
            if not callable(f) and not (name == "field_rate" and f is None):
                raise InvalidTypeError(
                    f"Expected `{name}` to be callable t -> (3,), got {type(f).__name__}."
                )

    def _inertial(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        b = self._vec(self.field, t, "field")
        if self.field_rate is not None:
            return b, self._vec(self.field_rate, t, "field_rate")
        h = self.step
        ahead = self._vec(self.field, t + h, "field")
        return b, (ahead - self._vec(self.field, t - h, "field")) / (2.0 * h)

    @staticmethod
    def _vec(f: Callable[[float], Any], t: float, name: str) -> np.ndarray:
        v = as_float_array(f(t), name)
        if v.shape != (3,):
            raise InvalidInputError(f"Expected `{name}` to return shape (3,), got {v.shape}.")
        return v

    def field_body(self, t: float, quat: np.ndarray, omega: np.ndarray) -> tuple[Any, Any]:
        """``(B_b, dB_b/dt)`` in body axes (T, T/s).

        >>> import numpy as np
        >>> from poinsot.dynamics import BDot
        >>> law = BDot(1.0, 1.0, field=lambda t: np.array([1e-5 * t, 0.0, 0.0]))
        >>> law.field_body(2.0, [1.0, 0, 0, 0], [0.0, 0, 0])[1].round(12)
        array([1.e-05, 0.e+00, 0.e+00])
        """
        q = np.asarray(quat, dtype=np.float64)
        w = np.asarray(omega, dtype=np.float64)
        b_i, db_i = self._inertial(float(t))
        b_b = _quat.to_body(q, b_i)
        return b_b, _quat.to_body(q, db_i) - cross(w, b_b)

    def dipole(self, t: float, quat: np.ndarray, omega: np.ndarray) -> Any:
        """The commanded dipole ``m`` (A m^2, body axes), saturated per axis."""
        _, db = self.field_body(t, quat, omega)
        return np.clip(-self.gain * db, -self.max_dipole, self.max_dipole)

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        b_b, db = self.field_body(t, quat, omega)
        m = np.clip(-self.gain * db, -self.max_dipole, self.max_dipole)
        return cross(m, b_b)
