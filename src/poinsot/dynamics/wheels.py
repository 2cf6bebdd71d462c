"""Reaction wheels: a rigid body carrying N wheels on fixed body axes (theory §10.1).

A set of :class:`ReactionWheels` (unit axes ``a_i`` in body axes, axial moments of
inertia ``I_i``, motor torque and speed limits, bearing friction) turns a rigid body
into a gyrostat whose rotor momentum is driven by the motors.
:func:`simulate_wheels` integrates the attitude ``q``, the body angular velocity ``w``
and the wheel speeds ``Omega`` (each relative to the body) together.

**Inertia convention.** ``J`` (the ``inertia`` the caller gives) is the inertia of the
*whole* spacecraft, wheels included, with the wheels **locked** (their masses and
their full inertia, axial moments included), about the centre of mass, in body axes:
the ``J`` of the gyrostat, docs/theory.md §10.1. The wheels' angular momentum relative
to the body is then

    h = sum_i I_i Omega_i a_i                  (body axes, N m s = kg m^2/s),

and the total angular momentum ``K = R (J w + h)`` (space axes). The same ``K`` reads
``K = R (J_f w + h_f)`` with ``J_f = J - sum_i I_i a_i a_i^T`` (the wheels' axial
inertia taken out) and ``h_f = sum_i I_i (Omega_i + a_i . w) a_i``, the wheels' *absolute*
axial momenta; ``h_f`` belongs to ``J_f``, not to ``J``.

**Equations** (docs/theory.md §10.1, "Reaction wheels"). The torque on wheel ``i``
about its axis is ``u_i + f_i`` (motor torque ``u_i``, friction
``f_i = -c_v Omega_i - c_c sign(Omega_i)``) and the body gets ``-(u_i + f_i) a_i``:

    I_i (a_i . w' + Omega_i') = u_i + f_i,
    J_f w' + w x (J_f w + h_f) = M - h_f',   h_f' = sum_i (u_i + f_i) a_i,

the Euler-Zhukovsky equations with ``(J_f, h_f)``, whose ``h_f'`` is explicit: ``w'`` is
:func:`~poinsot.dynamics.gyrostat_rhs` of ``(J_f, w, h_f, M, h_rate=h_f')``, then
``Omega_i' = (u_i + f_i) / I_i - a_i . w'``.

**Saturation.** The motor torque is the command clipped to ``[-u_max, u_max]``. A
wheel at ``|Omega_i| >= Omega_max`` whose speed would grow is **held**: its motor gives
the torque that keeps ``Omega_i' = 0`` (zero when nothing else acts: the torque is
cut), which makes the wheel part of the body (locked: ``I_i a_i a_i^T`` back in
``J_f``, its momentum ``I_i Omega_i a_i`` in ``h_f``), ``u_i = I_i a_i . w' - f_i``.
Only cutting the torque would let the body's acceleration drive the wheel past the
limit (``Omega_i' = -a_i . w'``). If holding needs more than ``u_max`` the motor gives
``u_max`` in that direction and the wheel moves on.

**Energy.** The kinetic energy of body and wheels,
``T = w . J w / 2 + sum_i I_i Omega_i (a_i . w + Omega_i / 2)``, changes by the power
of the external torque and of the torques between body and wheels on the *relative*
speeds: ``T' = w . M + sum_i (u_i + f_i) Omega_i``.

**Convention:** ``rotation`` maps body to space components; ``omega``, ``h`` and the
torques in body axes, ``K`` in space axes; SI units (kg m^2, rad/s, N m, N m s).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _quat
from .._typing import ArrayLike, FloatArray
from .._validate import (
    as_choice,
    as_float_array,
    as_rotation_quat,
    as_times,
    as_vec3,
    batch_shape,
)
from .._vec import diagonal3, inverse3
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError
from ..mass.tensor import _kinetic
from ..rotations.rotation import Rotation
from ..trajectory import Channel, Trajectory, _readonly
from .euler_equations import _body_inertia, _max_step, _tolerances, simulate
from .gyrostat import _gyro_rhs
from .integrators._common import _fixed_step_info, _normalize, _stages, _substeps
from .torques import GyrostaticTorque, TorqueModel, as_torque

__all__ = ["ReactionWheels", "pyramid", "simulate_wheels", "WheelTrajectory", "WHEEL_METHODS"]

#: Names accepted by ``simulate_wheels(method=...)``.
WHEEL_METHODS = ("dop853", "rk4")

#: ``|a_i|`` may differ from 1 by this much (the axes are then normalised).
AXIS_ATOL = 1e-6


def _along(axes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``sum_i x_i a_i`` (body axes) for per-wheel scalars ``x`` (..., N)."""
    return x @ axes


def _per_wheel(x: object, name: str, n: int, *, positive: bool, finite: bool) -> np.ndarray:
    """A per-wheel parameter: a scalar or shape (N,), > 0 (``positive``) or >= 0."""
    a = as_float_array(x, name, finite=False)
    if a.ndim > 1 or (a.ndim == 1 and a.shape[0] != n):
        raise InvalidInputError(
            f"Expected `{name}` to be a scalar or of shape ({n},), got {a.shape}."
        )
    a = np.array(np.broadcast_to(a, (n,)), dtype=float)
    bad = np.isnan(a) | (~np.isfinite(a) if finite else np.isneginf(a))
    bad |= (a <= 0.0) if positive else (a < 0.0)
    if np.any(bad):
        word = "positive" if positive else "non-negative"
        kind = " finite" if finite else ""
        raise InvalidInputError(
            f"Expected `{name}` to be{kind} {word}, got {float(a[bad][0])!r} "
            f"(wheel {int(np.flatnonzero(bad)[0])})."
        )
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ReactionWheels:
    """N reaction wheels on fixed body axes (docs/theory.md §10.1, "Reaction wheels").

    Parameters
    ----------
    axes : array_like, shape (N, 3)
        Unit spin axes ``a_i`` in body axes (normalised; ``| |a_i| - 1 |`` at most
        :data:`AXIS_ATOL`).
    inertia : float or array_like, shape (N,)
        Axial moments of inertia ``I_i`` of the wheels about their axes (kg m^2). The
        body inertia given to :func:`simulate_wheels` already contains them (wheels
        locked, module notes).
    max_torque : float or array_like, shape (N,), optional
        Motor torque limit ``u_max`` (N m, > 0); default ``inf``.
    max_speed : float or array_like, shape (N,), optional
        Wheel speed limit ``Omega_max`` relative to the body (rad/s, > 0); default ``inf``.
    viscous : float or array_like, shape (N,), optional
        Viscous friction coefficient ``c_v`` (N m s, >= 0); default 0.
    coulomb : float or array_like, shape (N,), optional
        Coulomb friction torque ``c_c`` (N m, >= 0); default 0.

    Raises
    ------
    InvalidInputError
        A wrong shape, a zero or non-unit axis, a non-positive inertia or limit, a
        negative friction coefficient, NaN (the message names the argument).
    InvalidTypeError
        A string or another non-numeric value.

    Notes
    -----
    Wheel ``i`` spins at ``Omega_i`` about ``a_i`` relative to the body; its momentum
    relative to the body is ``I_i Omega_i a_i``, so ``h = sum_i I_i Omega_i a_i``
    (:meth:`momentum`). The friction torque on the wheel is
    ``f_i = -c_v Omega_i - c_c sign(Omega_i)`` (:meth:`friction`, ``sign(0) = 0``).

    **Convention:** axes and ``h`` in body axes; SI units.

    Examples
    --------
    >>> from poinsot.dynamics import ReactionWheels
    >>> rw = ReactionWheels([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]], 0.02, max_torque=0.1)
    >>> rw.n, rw.momentum([100.0, 0.0, -50.0])
    (3, array([ 2.,  0., -1.]))
    """

    # each an array (N, 3) or (N,) after the checks (read-only)
    axes: Any
    inertia: Any
    max_torque: Any = math.inf
    max_speed: Any = math.inf
    viscous: Any = 0.0
    coulomb: Any = 0.0

    def __post_init__(self) -> None:
        a = as_float_array(self.axes, "axes")
        if a.ndim != 2 or a.shape[1] != 3 or a.shape[0] == 0:
            raise InvalidInputError(f"Expected `axes` to have shape (N, 3), N >= 1, got {a.shape}.")
        norm = np.linalg.norm(a, axis=1)
        bad = np.abs(norm - 1.0) > AXIS_ATOL
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise InvalidInputError(
                f"Expected `axes` to be unit vectors, got |a_{i}| = {float(norm[i])!r}."
            )
        a = a / norm[:, None]
        a.setflags(write=False)
        n = a.shape[0]
        set_ = object.__setattr__
        set_(self, "axes", a)
        set_(self, "inertia", _per_wheel(self.inertia, "inertia", n, positive=True, finite=True))
        for name in ("max_torque", "max_speed"):
            set_(self, name, _per_wheel(getattr(self, name), name, n, positive=True, finite=False))
        for name in ("viscous", "coulomb"):
            set_(self, name, _per_wheel(getattr(self, name), name, n, positive=False, finite=True))

    @property
    def n(self) -> int:
        """Number of wheels."""
        return int(self.axes.shape[0])

    @property
    def axial_inertia(self) -> FloatArray:
        """``sum_i I_i a_i a_i^T`` (3, 3), body axes (kg m^2): the part of the locked
        inertia ``J`` that spins with the wheels; ``J_f = J - axial_inertia``."""
        return np.einsum("i,ij,ik->jk", self.inertia, self.axes, self.axes)

    def _wheel_array(self, x: ArrayLike, name: str) -> np.ndarray:
        a = as_float_array(x, name)
        if a.ndim == 0 or a.shape[-1] != self.n:
            raise InvalidInputError(
                f"Expected `{name}` to have shape (..., {self.n}), got {a.shape}."
            )
        return a

    def momentum(self, wheel_speed: ArrayLike) -> FloatArray:
        """Wheel momentum relative to the body, ``h = sum_i I_i Omega_i a_i``.

        Parameters
        ----------
        wheel_speed : array_like, shape (..., N)
            Wheel speeds ``Omega_i`` relative to the body (rad/s).

        Returns
        -------
        ndarray, shape (..., 3)
            ``h`` in body axes (N m s); the ``h`` of docs/theory.md §10.1 for the
            locked inertia ``J``.

        **Convention:** body axes, SI units.

        Examples
        --------
        >>> from poinsot.dynamics import pyramid
        >>> pyramid(0.5, 0.01).momentum([10.0, 10.0, 10.0, 10.0]).round(12) + 0.0
        array([0.        , 0.        , 0.35103302])
        """
        om = self._wheel_array(wheel_speed, "wheel_speed")
        return _along(self.axes, self.inertia * om)

    def friction(self, wheel_speed: ArrayLike) -> FloatArray:
        """Friction torque on each wheel, ``f_i = -c_v Omega_i - c_c sign(Omega_i)`` (N m).

        **Convention:** about ``a_i``, acting on the wheel (the body gets ``-f_i a_i``).

        Examples
        --------
        >>> from poinsot.dynamics import ReactionWheels
        >>> rw = ReactionWheels([[0.0, 0.0, 1.0]], 0.01, viscous=1e-4, coulomb=1e-3)
        >>> rw.friction([100.0])
        array([-0.011])
        """
        return self._friction(self._wheel_array(wheel_speed, "wheel_speed"))

    def _friction(self, om: np.ndarray) -> np.ndarray:
        return -self.viscous * om - self.coulomb * np.sign(om)

    def kinetic_energy(
        self, inertia: ArrayLike, omega: ArrayLike, wheel_speed: ArrayLike
    ) -> FloatArray:
        """Kinetic energy of body and wheels (J).

        ``T = w . J w / 2 + sum_i I_i Omega_i (a_i . w + Omega_i / 2)``, ``J`` locked.

        Parameters
        ----------
        inertia : array_like, shape (3,) or (3, 3), or RigidBody
            Locked inertia ``J`` (module notes), body axes (kg m^2).
        omega : array_like, shape (..., 3)
            Body angular velocity (rad/s, body axes).
        wheel_speed : array_like, shape (..., N)
            Wheel speeds relative to the body (rad/s).

        Notes
        -----
        docs/theory.md §10.1: each wheel adds ``I_i Omega_i a_i . w + I_i Omega_i^2 / 2``
        to the locked body's ``w . J w / 2``. ``T' = w . M + sum_i (u_i + f_i) Omega_i``.

        **Convention:** body axes, SI units.

        Examples
        --------
        >>> from poinsot.dynamics import ReactionWheels
        >>> rw = ReactionWheels([[0.0, 0.0, 1.0]], 0.1)
        >>> float(rw.kinetic_energy([1.0, 1.0, 2.0], [0.0, 0.0, 1.0], [10.0]))
        7.0
        """
        j = _tensor(inertia)
        w = as_vec3(omega, "omega")
        om = self._wheel_array(wheel_speed, "wheel_speed")
        return _energy(self, j, w, om)

    def simulate(
        self,
        inertia: ArrayLike,
        rotation0: Rotation | ArrayLike,
        omega0: ArrayLike,
        wheel_speed0: ArrayLike,
        t: ArrayLike,
        **options: Any,
    ) -> WheelTrajectory:
        """:func:`simulate_wheels` with these wheels (same arguments and options).

        Examples
        --------
        >>> from poinsot.dynamics import ReactionWheels
        >>> rw = ReactionWheels([[0.0, 0.0, 1.0]], 0.1)
        >>> tr = rw.simulate([2.0, 2.0, 1.0], [1.0, 0, 0, 0], [0, 0, 0], [0.0], [0.0, 1.0],
        ...                  command=lambda t, q, w, om: [0.1])
        >>> round(float(tr.wheel_speed[-1, 0]), 9)   # Omega' = u J3 / (I_w (J3 - I_w))
        1.111111111
        """
        return simulate_wheels(inertia, self, rotation0, omega0, wheel_speed0, t, **options)


def pyramid(
    beta: float,
    inertia: ArrayLike,
    *,
    degrees: bool = False,
    max_torque: ArrayLike = math.inf,
    max_speed: ArrayLike = math.inf,
    viscous: ArrayLike = 0.0,
    coulomb: ArrayLike = 0.0,
) -> ReactionWheels:
    """The standard four-wheel pyramid about the body z axis.

    ``a_i = (sin(beta) cos(alpha_i), sin(beta) sin(alpha_i), cos(beta))``,
    ``alpha_i = 0, 90, 180, 270 deg``: each axis makes the angle ``beta`` with ``+z``.

    Parameters
    ----------
    beta : float
        Angle between each wheel axis and the body z axis (rad, or degrees with
        ``degrees=True``); ``arccos(1/sqrt(3)) = 54.7356 deg`` gives the same momentum
        capacity about x, y and z.
    inertia, max_torque, max_speed, viscous, coulomb
        As :class:`ReactionWheels` (a scalar for all four or shape (4,)).
    degrees : bool, optional
        ``beta`` in degrees.

    Returns
    -------
    ReactionWheels

    Notes
    -----
    docs/theory.md §10.1. ``sum_i a_i a_i^T = diag(2 s^2, 2 s^2, 4 c^2)`` (``s, c`` of
    ``beta``): with equal wheels the pyramid adds a diagonal ``axial_inertia``.

    **Convention:** body axes.

    Examples
    --------
    >>> from poinsot.dynamics import pyramid
    >>> pyramid(90.0, 0.01, degrees=True).axes.round(12) + 0.0
    array([[ 1.,  0.,  0.],
           [ 0.,  1.,  0.],
           [-1.,  0.,  0.],
           [ 0., -1.,  0.]])
    """
    if not isinstance(degrees, bool | np.bool_):
        raise InvalidTypeError(f"Expected `degrees` to be a bool, got {type(degrees).__name__}.")
    b_arr = as_float_array(beta, "beta")
    if b_arr.ndim != 0:
        raise InvalidInputError(f"Expected `beta` to be a scalar, got shape {b_arr.shape}.")
    b = math.radians(float(b_arr)) if degrees else float(b_arr)
    alpha = np.arange(4) * (math.pi / 2.0)
    s, c = math.sin(b), math.cos(b)
    axes = np.stack([s * np.cos(alpha), s * np.sin(alpha), np.full(4, c)], axis=1)
    return ReactionWheels(
        axes, inertia, max_torque=max_torque, max_speed=max_speed, viscous=viscous,
        coulomb=coulomb,
    )  # fmt: skip


# ---------------------------------------------------------------------------
# Result
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False, repr=False)
class WheelTrajectory(Trajectory):
    """Samples of a rigid body with reaction wheels: a :class:`~poinsot.Trajectory`
    whose wheel speeds are part of the state.

    Attributes (beyond :class:`~poinsot.Trajectory`)
    ------------------------------------------------
    wheel_speed : ndarray, shape (n, N)
        Wheel speeds ``Omega_i`` relative to the body (rad/s).
    wheel_momentum : ndarray, shape (n, 3)
        ``h = sum_i I_i Omega_i a_i``, body axes (N m s = kg m^2/s).
    motor_torque : ndarray, shape (n, N)
        Motor torque applied at each sample (N m, after the limits), on wheel ``i``
        about ``a_i``.

    ``energy`` is the whole kinetic energy of body and wheels,
    ``T = w . J w / 2 + sum_i I_i Omega_i (a_i . w + Omega_i / 2)`` (J), and
    ``momentum`` the total angular momentum ``K = R (J w + h)`` in space axes
    (``J`` locked, docs/theory.md §10.1).

    Notes
    -----
    The state compared by :func:`~poinsot.compare` is ``"attitude"`` (rad),
    ``"omega"`` (rad/s) and ``"wheel_speed"`` (rad/s).

    **Convention:** as :class:`~poinsot.Trajectory`.

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> w = WheelTrajectory(t, poinsot.Rotation.identity((3,)), np.zeros((3, 3)), "x",
    ...                     wheel_speed=np.zeros((3, 2)), wheel_momentum=np.zeros((3, 3)),
    ...                     motor_torque=np.zeros((3, 2)))
    >>> list(w.state_channels()), w.channels()["wheel_speed"].units
    (['attitude', 'omega', 'wheel_speed'], 'rad/s')
    """

    wheel_speed: FloatArray | None = None
    wheel_momentum: FloatArray | None = None
    motor_torque: FloatArray | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.wheel_speed is None or self.wheel_momentum is None or self.motor_torque is None:
            raise InvalidInputError(
                "Expected `wheel_speed`, `wheel_momentum` and `motor_torque` for a WheelTrajectory."
            )
        speed = _readonly(self.wheel_speed, "wheel_speed")
        lead = self.rotation.shape
        if speed.shape[:-1] != lead or speed.ndim != len(lead) + 1:
            raise InvalidInputError(
                f"Expected `wheel_speed` to have shape {lead} + (N,), got {speed.shape}."
            )
        object.__setattr__(self, "wheel_speed", speed)
        for name, shape in (("wheel_momentum", lead + (3,)), ("motor_torque", speed.shape)):
            arr = _readonly(getattr(self, name), name)
            if arr.shape != shape:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape {shape}, got {arr.shape}."
                )
            object.__setattr__(self, name, arr)

    def channels(self) -> dict[str, Channel]:
        """Those of :class:`~poinsot.Trajectory` (``energy`` the whole kinetic energy,
        ``momentum`` the total ``K``), ``wheel_speed`` (rad/s), ``wheel_momentum``
        (kg m^2/s, body axes) and ``motor_torque`` (N m)."""
        out = super().channels()
        assert self.wheel_speed is not None and self.wheel_momentum is not None
        assert self.motor_torque is not None
        labels = tuple(str(i) for i in range(self.wheel_speed.shape[-1]))
        out["wheel_speed"] = Channel(
            "wheel_speed", self.wheel_speed, "rad/s", labels, "wheel speeds relative to the body"
        )
        out["wheel_momentum"] = Channel(
            "wheel_momentum", self.wheel_momentum, "kg m^2/s", ("x", "y", "z"),
            "wheel momentum h relative to the body, body axes",
        )  # fmt: skip
        out["motor_torque"] = Channel(
            "motor_torque", self.motor_torque, "N m", labels, "motor torque on each wheel"
        )
        return out

    def state_channels(self) -> dict[str, Channel]:
        """``attitude`` (rad), ``omega`` (rad/s) and ``wheel_speed`` (rad/s)."""
        return {**super().state_channels(), "wheel_speed": self.channels()["wheel_speed"]}


# ---------------------------------------------------------------------------
# The motion
# ---------------------------------------------------------------------------


def _tensor(inertia: object) -> np.ndarray:
    """The locked inertia ``J`` as a (3, 3) tensor in body axes (one body)."""
    j, principal = _body_inertia(inertia)
    if j.shape != ((3,) if principal else (3, 3)):
        raise InvalidInputError(
            f"Expected `inertia` for one body, (3,) or (3, 3), got {j.shape} (batches run only "
            "with a constant `command` array, no friction, no `torque` and method='dop853')."
        )
    return diagonal3(j) if principal else j


def _energy(wheels: ReactionWheels, j: np.ndarray, w: np.ndarray, om: np.ndarray) -> np.ndarray:
    """``T = w . J w / 2 + sum_i I_i Omega_i (a_i . w + Omega_i / 2)`` (no validation)."""
    aw = np.einsum("...j,ij->...i", w, wheels.axes)
    return _kinetic(j, False, w) + np.sum(wheels.inertia * om * (aw + 0.5 * om), axis=-1)


def _returned(value: object, name: str, n: int, t: float) -> np.ndarray:
    """What a user's ``command`` (N,) or ``torque`` (3,) returned, checked: shape ``(n,)``
    (a scalar is broadcast) and finite."""
    a = np.asarray(value, dtype=float)
    if a.shape not in ((n,), ()):
        raise InvalidInputError(f"Expected `{name}` to return shape ({n},), got {a.shape}.")
    if not np.all(np.isfinite(a)):
        raise IntegrationError(f"`{name}` returned NaN/inf at t = {t:.6g}.")
    return np.broadcast_to(a, (n,))


class _WheelSystem:
    """The right-hand side of ``(q, w, Omega)`` (module notes), checked arguments."""

    def __init__(
        self,
        j: np.ndarray,
        wheels: ReactionWheels,
        command: Callable[..., ArrayLike] | None,
        model: TorqueModel | None,
    ) -> None:
        self.j, self.wheels, self.command, self.model = j, wheels, command, model
        self.n = wheels.n
        self.outer = wheels.inertia[:, None, None] * np.einsum(
            "ij,ik->ijk", wheels.axes, wheels.axes
        )  # I_i a_i a_i^T, summed: ReactionWheels.axial_inertia
        self.j_free = j - wheels.axial_inertia
        self.j_free_inv = inverse3(self.j_free)

    def motor(self, t: float, q: np.ndarray, w: np.ndarray, om: np.ndarray) -> np.ndarray:
        """The commanded torques clipped to ``[-u_max, u_max]`` (N,)."""
        if self.command is None:
            return np.zeros(self.n)
        c = _returned(self.command(t, q.copy(), w.copy(), om.copy()), "command", self.n, t)
        mx = self.wheels.max_torque
        return np.clip(c, -mx, mx)

    def external(self, t: float, q: np.ndarray, w: np.ndarray) -> np.ndarray | None:
        """The external torque (3,) in body axes, or None."""
        if self.model is None:
            return None
        return _returned(self.model.body_torque(t, q, w), "torque", 3, t)

    def accel(
        self,
        w: np.ndarray,
        om: np.ndarray,
        u: np.ndarray,
        f: np.ndarray,
        m: np.ndarray | None,
        held: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(w', Omega')``: the gyrostat ``(J_f, h_f)`` of the module notes, the held
        wheels locked into ``J_f``."""
        ws = self.wheels
        free = ~held
        if held.any():
            jf = self.j - self.outer[free].sum(axis=0)
            jf_inv = inverse3(jf)
        else:
            jf, jf_inv = self.j_free, self.j_free_inv
        aw = ws.axes @ w
        h = _along(ws.axes, ws.inertia * (om + np.where(free, aw, 0.0)))
        drive = np.where(free, u + f, 0.0)
        wdot = _gyro_rhs(jf, jf_inv, w, h, m, _along(ws.axes, drive), False)
        omdot = np.where(free, drive / ws.inertia - ws.axes @ wdot, 0.0)
        return wdot, omdot

    def motion(
        self, t: float, q: np.ndarray, w: np.ndarray, om: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(w', Omega', u)`` with the limits of the module notes (``u`` applied)."""
        ws = self.wheels
        u = self.motor(t, q, w, om)
        f = ws._friction(om)
        m = self.external(t, q, w)
        held = np.zeros(self.n, dtype=bool)
        wdot, omdot = self.accel(w, om, u, f, m, held)
        at_limit = np.abs(om) >= ws.max_speed
        if not at_limit.any():
            return wdot, omdot, u
        held = at_limit & (omdot * om > 0.0)  # the speed would grow past the limit
        if not held.any():
            return wdot, omdot, u
        wdot, omdot = self.accel(w, om, u, f, m, held)
        hold = ws.inertia * (ws.axes @ wdot) - f  # the torque that keeps Omega' = 0
        u = np.where(held, hold, u)
        over = held & (np.abs(hold) > ws.max_torque)
        if over.any():  # the motor cannot hold: full torque against the drift
            u = np.where(over, np.sign(hold) * ws.max_torque, u)
            wdot, omdot = self.accel(w, om, u, f, m, held & ~over)
        return wdot, omdot, u

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        q, w, om = y[:4], y[4:7], y[7:]
        wdot, omdot, _ = self.motion(t, q, w, om)
        return np.concatenate([0.5 * _quat.mul(q, _quat.pure(w)), wdot, omdot])  # theory §5


def _run_dop853(
    sys_: _WheelSystem, y0: np.ndarray, t: np.ndarray, rtol: float, atol: float, h_max: float
) -> tuple[np.ndarray, dict[str, Any]]:
    from scipy.integrate import solve_ivp

    info: dict[str, Any] = {"solver": "DOP853", "rtol": rtol, "atol": atol}
    if t.size == 1:
        info.update(evaluations=0, message="")
        return y0[None].copy(), info
    sol = solve_ivp(
        sys_.rhs, (t[0], t[-1]), y0, method="DOP853", t_eval=t, rtol=rtol, atol=atol,
        max_step=h_max,
    )  # fmt: skip
    if sol.status != 0 or sol.y.shape[1] != t.size or not np.all(np.isfinite(sol.y)):
        reached = float(sol.t[-1]) if sol.t.size else float(t[0])
        raise IntegrationError(
            f"dop853 integration of the wheels failed after t = {reached:.6g}: {sol.message} "
            f"Try method='rk4' with a small `max_step`."
        )
    info.update(evaluations=int(sol.nfev), message=sol.message)
    return np.ascontiguousarray(sol.y.T), info


def _run_rk4(
    sys_: _WheelSystem, y0: np.ndarray, t: np.ndarray, h_max: float
) -> tuple[np.ndarray, dict[str, Any]]:
    nsub = _substeps(t, h_max)
    ys = np.empty((t.size, y0.size))
    ys[0] = y = y0
    f = sys_.rhs
    for k, tn, h, last in _stages(t, nsub, (1.0,)):
        k1 = f(tn, y)
        k2 = f(tn + h / 2, y + h / 2 * k1)
        k3 = f(tn + h / 2, y + h / 2 * k2)
        k4 = f(tn + h, y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        y[:4] = _normalize(y[:4])
        if last:
            if not np.all(np.isfinite(y)):
                raise IntegrationError(
                    f"rk4 integration of the wheels diverged after t = {float(t[k]):.6g}: "
                    f"reduce `max_step`."
                )
            ys[k + 1] = y
    info = _fixed_step_info(t, nsub)
    info["order"] = 4
    return ys, info


#: The end of the messages refusing a batch on the Python path.
_BATCH_ONLY = (
    " (batches run only with a constant `command` array, no friction, no `torque` and "
    "method='dop853')"
)


def _constant_command(command: object, wheels: ReactionWheels) -> np.ndarray:
    """A constant ``command`` (..., N), clipped to ``[-u_max, u_max]``."""
    c = as_float_array(command, "command")
    if c.ndim == 0 or c.shape[-1] != wheels.n:
        error = InvalidTypeError if c.ndim == 0 else InvalidInputError
        raise error(
            f"Expected `command` to be callable or an array of shape (..., {wheels.n}) "
            f"(constant motor torques), got shape {c.shape}."
        )
    return np.clip(c, -wheels.max_torque, wheels.max_torque)


def _run_constant(
    inertia: ArrayLike,
    wheels: ReactionWheels,
    rotation0: Rotation | ArrayLike,
    omega0: ArrayLike,
    wheel_speed0: ArrayLike,
    tt: np.ndarray,
    u: np.ndarray,
    rtol: float,
    atol: float,
    max_step: float | None,
) -> WheelTrajectory | None:
    """Constant motor torques ``u`` (..., N), no friction, no external torque: Euler's
    equations of ``J_f`` under :class:`GyrostaticTorque` ``(h_f(0), rate=U)`` in the
    compiled DOP853 (:func:`simulate`), ``h_i(t) = h_i(t0) + u_i (t - t0)`` and
    ``Omega_i = h_i / I_i - a_i . w`` after it (module notes). ``None`` when one body's
    wheel passes ``max_speed`` on the output grid (the caller takes the Python path);
    a batch's raises."""
    j, principal = _body_inertia(inertia)
    jt = diagonal3(j) if principal else j
    q0 = as_rotation_quat(rotation0, "rotation0")
    w0 = as_vec3(omega0, "omega0")
    om0 = wheels._wheel_array(wheel_speed0, "wheel_speed0")
    batch = batch_shape(
        inertia=(jt, 2), rotation0=(q0, 1), omega0=(w0, 1), wheel_speed0=(om0, 1),
        command=(u, 1),
    )  # fmt: skip
    n = wheels.n
    om0 = np.broadcast_to(om0, batch + (n,))
    _check_start(om0, wheels)
    jf = jt - wheels.axial_inertia
    _check_free(jf)
    jf = np.broadcast_to(jf, batch + (3, 3))
    q0 = np.broadcast_to(q0, batch + (4,))
    w0 = np.broadcast_to(w0, batch + (3,))
    u = np.broadcast_to(u, batch + (n,))
    axes, moments = wheels.axes, wheels.inertia
    h_abs0 = moments * (om0 + w0 @ axes.T)  # the wheels' absolute axial momenta at t0
    rate = u @ axes  # U = sum_i u_i a_i
    t0 = float(tt[0])
    h0 = h_abs0 @ axes - rate * t0  # h_f(t) = h0 + U t
    tr = simulate(
        jf, q0, w0, tt, torque=GyrostaticTorque(h0, rate=rate), method="dop853", rtol=rtol,
        atol=atol, max_step=max_step,
    )  # fmt: skip
    q = tr.rotation.as_quat()
    w = tr.omega
    dt = (tt - t0).reshape((-1,) + (1,) * (len(batch) + 1))
    om = (h_abs0 + u * dt) / moments - w @ axes.T
    over = np.abs(om) > wheels.max_speed
    if np.any(over):
        if batch == ():
            return None
        k, *b, i = (int(x[0]) for x in np.nonzero(over))
        raise InvalidInputError(
            f"Expected the constant `command` to keep every wheel within `max_speed` on the "
            f"output grid (a batch has no speed hold), got wheel {i} of body {tuple(b)} at "
            f"{float(om[(k, *b, i)])!r} rad/s at t = {float(tt[k]):.6g} (limit "
            f"{float(wheels.max_speed[i])!r}): reduce `command` or integrate that body alone."
        )
    h = (moments * om) @ axes
    k_space = _quat.rotate(q, np.einsum("...ij,...j->...i", jt, w) + h)
    info = dict(tr.info)
    info.update(_conserved(None, u, wheels))
    return WheelTrajectory(
        tt,
        tr.rotation,
        tr.omega,
        "dop853",
        energy=_energy(wheels, jt, w, om),
        momentum=k_space,
        info=info,
        wheel_speed=np.ascontiguousarray(om),
        wheel_momentum=h,
        motor_torque=np.ascontiguousarray(np.broadcast_to(u, om.shape)),
    )


def _check_start(om0: np.ndarray, wheels: ReactionWheels) -> None:
    """Every initial wheel speed within its limit."""
    over = np.abs(om0) > wheels.max_speed
    if np.any(over):
        *b, i = (int(x[0]) for x in np.nonzero(over))
        where = f" of body {tuple(b)}" if b else ""
        raise InvalidInputError(
            f"Expected `wheel_speed0` within `max_speed`, got {float(om0[(*b, i)])!r} for "
            f"wheel {i}{where} (limit {float(wheels.max_speed[i])!r})."
        )


def _check_free(jf: np.ndarray) -> None:
    """``J_f = J - sum_i I_i a_i a_i^T`` positive definite (every body)."""
    eig = np.linalg.eigvalsh(jf)
    if np.any(eig <= 0.0):
        bad = eig.reshape(-1, 3)[np.flatnonzero(np.any(eig.reshape(-1, 3) <= 0.0, axis=1))[0]]
        raise InvalidInputError(
            "Expected `inertia` to contain the wheels locked: J - sum_i I_i a_i a_i^T must be "
            f"positive definite, got eigenvalues {bad.tolist()} (`wheels` inertia too large "
            "for `inertia`?)."
        )


def simulate_wheels(
    inertia: ArrayLike,
    wheels: ReactionWheels,
    rotation0: Rotation | ArrayLike,
    omega0: ArrayLike,
    wheel_speed0: ArrayLike,
    t: ArrayLike,
    *,
    command: Callable[..., ArrayLike] | ArrayLike | None = None,
    torque: TorqueModel | ArrayLike | Callable[..., ArrayLike] | None = None,
    method: str = "dop853",
    rtol: float | None = None,
    atol: float | None = None,
    max_step: float | None = None,
) -> WheelTrajectory:
    """Integrate a rigid body with reaction wheels (docs/theory.md §10.1).

    State ``(q, w, Omega)``: ``q' = q o w / 2`` (theory §5) and the equations of the
    module notes,

    ``J_f w' + w x (J_f w + h_f) = M - sum_i (u_i + f_i) a_i``,
    ``I_i (a_i . w' + Omega_i') = u_i + f_i``,

    ``J_f = J - sum_i I_i a_i a_i^T``, ``h_f = sum_i I_i (Omega_i + a_i . w) a_i``.

    **Constant motor torques (the compiled, batched path).** When ``command`` is an
    array (constant torques ``u_i``, clipped at ``max_torque``), the wheels have no
    friction (``viscous`` and ``coulomb`` zero), ``torque`` is ``None`` and ``method`` is
    ``"dop853"``, the wheels' absolute momenta are known in closed form,
    ``h_i(t) = h_i(t0) + u_i (t - t0)``, so ``h_f(t) = h_f(t0) + U (t - t0)`` with
    ``U = sum_i u_i a_i``, and the body obeys Euler's equations of ``J_f`` under

    ``M_b = h_f(t) x w - U``,

    integrated by the compiled DOP853 (:func:`~poinsot.dynamics.simulate` with
    :class:`~poinsot.dynamics.GyrostaticTorque` ``(h_f(t0) - U t0, rate=U)``, torque
    kind 5) for a whole batch at once; then ``Omega_i(t) = h_i(t) / I_i - a_i . w(t)``
    exactly. The step control then sees ``(q, w)`` only (not ``Omega``). If a wheel's
    ``|Omega_i|`` exceeds ``max_speed`` at an output time (the hold makes the torque
    piecewise), one body is integrated again on the Python path and a batch raises
    :class:`~poinsot.InvalidInputError`; between output times the speeds are not
    checked (``h_i`` is linear in ``t``, so the speeds move monotonically but for
    ``a_i . w``). Everything else (a callable ``command``, friction, ``torque``,
    ``"rk4"``) takes the Python path: one body, the state ``(q, w, Omega)`` in SciPy's
    DOP853 (``info["solver"] == "DOP853"``) or the RK4 here.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3), or RigidBody
        Inertia ``J`` of body and wheels with the wheels **locked** (axial moments
        included), about the centre of mass in body axes (kg m^2); principal moments
        when the body axes are principal. A leading shape (a batch) only on the
        compiled path.
    wheels : ReactionWheels
        The wheels (axes, axial inertias, limits, friction), shared by the batch.
    rotation0 : Rotation or array_like, shape (..., 4)
        Initial attitude, body -> space.
    omega0 : array_like, shape (..., 3)
        Initial body angular velocity in body axes (rad/s).
    wheel_speed0 : array_like, shape (..., N)
        Initial wheel speeds relative to the body (rad/s), ``|Omega_i| <= Omega_max``.
    t : array_like, shape (n,)
        Output times, strictly increasing; the motion starts at ``t[0]``.
    command : callable or array_like, shape (..., N), optional
        ``command(t, q, w, Omega) -> (N,)``: the motor torques (N m) asked for, from
        the time (s), the scalar-first quaternion ``q`` (4,), ``w`` (3,) (rad/s, body
        axes) and the wheel speeds (N,) (rad/s); or an array: constant motor torques
        (N m), one row per body of a batch. Clipped at ``max_torque``. Default: no
        motor torque.
    torque : None, TorqueModel, array_like (3,) or callable, optional
        External torque in body axes (N m), as :func:`~poinsot.dynamics.simulate`
        takes it (a callable gets ``(t, rotation, omega)``).
    method : {"dop853", "rk4"}, optional
        ``"dop853"`` (default): :func:`scipy.integrate.solve_ivp` DOP853 (poinsot's
        compiled DOP853 runs Euler's equations only); ``"rk4"``: classical Runge-Kutta
        with equal steps no longer than ``max_step`` in each output interval, the
        quaternion renormalised after each step.
    rtol, atol : float, optional
        Tolerances of ``"dop853"`` (defaults ``1e-10``, ``1e-12``); refused by ``"rk4"``.
    max_step : float, optional
        Longest step (s).

    Returns
    -------
    WheelTrajectory
        ``rotation`` (n, ...), ``omega`` (n, ..., 3), ``wheel_speed`` (n, ..., N)
        (rad/s), ``wheel_momentum`` ``h`` (n, ..., 3) (N m s, body axes),
        ``motor_torque`` (n, ..., N) (N m, applied), ``energy`` (n, ...) the kinetic
        energy of body and wheels (J), ``momentum`` ``K = R (J w + h)`` (n, ..., 3,
        space axes): the batch axes after the time axis, as
        :func:`~poinsot.dynamics.simulate`'s. ``info``: ``solver``, ``rtol``, ``atol``,
        ``evaluations``, ``message`` (SciPy's dop853), ``steps`` (per body), ``rejected``
        (compiled dop853) or ``steps``, ``step_size``, ``order`` (rk4), and ``torque``,
        ``conserved``.

    Raises
    ------
    InvalidInputError
        Bad values or shapes (the message names the argument); a ``J`` that does not
        contain the wheels (``J - sum_i I_i a_i a_i^T`` not positive definite); a wheel
        speed beyond its limit; a command of the wrong shape; a batch off the compiled
        path; a batch whose constant ``command`` drives a wheel past ``max_speed``.
    InvalidTypeError
        ``wheels`` not a :class:`ReactionWheels`, ``command`` neither callable nor an
        array, a bad type.
    IntegrationError
        A non-finite state or command.

    Notes
    -----
    docs/theory.md §10.1 ("Reaction wheels"). ``w'`` is
    :func:`~poinsot.dynamics.gyrostat_rhs` of ``(J_f, w, h_f, M, h_rate=h_f')``. With no
    external torque ``K`` is constant; ``T' = w . M + sum_i (u_i + f_i) Omega_i``. The
    motor torque and the speed hold are discontinuous (and so is Coulomb friction at
    ``Omega_i = 0``): the adaptive steps shorten there, and a wheel stuck at
    ``Omega_i = 0`` by Coulomb friction chatters (many short steps). The step that
    reaches a speed limit is not cut at it: a held wheel may sit above ``max_speed`` by
    that step's error (measured up to 3.7e-9 relative at ``rtol=1e-10``).

    **Convention:** body -> space attitude; ``omega``, ``h``, torques in body axes,
    ``K`` in space axes; SI units.

    Examples
    --------
    A body spinning up its single wheel: the momentum moves from the body to the wheel.

    >>> import numpy as np
    >>> from poinsot.dynamics import ReactionWheels, simulate_wheels
    >>> rw = ReactionWheels([[0.0, 0.0, 1.0]], 0.1, max_torque=0.05)
    >>> tr = simulate_wheels([2.0, 2.0, 1.0], rw, [1.0, 0, 0, 0], [0.0, 0.0, 0.5], [0.0],
    ...                      np.linspace(0.0, 2.0, 5), command=lambda t, q, w, om: [0.2])
    >>> tr.motor_torque[0], round(float(tr.omega[-1, 2]), 10)   # clipped; w3' = -u / (1 - 0.1)
    (array([0.05]), 0.3888888889)
    >>> bool(tr.momentum_vector_drift < 1e-12)
    True

    A batch of two bodies (principal moments, shape (2, 3); a (3, 3) array would be one
    tensor) with a four-wheel pyramid under constant motor torques (the compiled path);
    the total momentum ``K`` stays put, the motors being internal:

    >>> from poinsot.dynamics import pyramid
    >>> rw4 = pyramid(np.arccos(1 / np.sqrt(3)), 0.02, max_torque=0.05, max_speed=600.0)
    >>> J = [[10.0, 12.0, 8.0], [20.0, 15.0, 9.0]]
    >>> u = [[0.01, -0.01, 0.0, 0.02], [0.0, 0.0, 0.05, 0.0]]
    >>> tr = simulate_wheels(J, rw4, [1.0, 0, 0, 0], [0.01, 0.0, -0.02], [50.0, 0, 0, -50.0],
    ...                      np.linspace(0.0, 60.0, 7), command=u)
    >>> tr.wheel_speed.shape, tr.info["solver"].startswith("DOP853 (compiled")
    ((7, 2, 4), True)
    >>> bool(np.abs(tr.momentum - tr.momentum[0]).max() < 1e-8)   # |K| ~ 1, rtol 1e-10
    True
    """
    if not isinstance(wheels, ReactionWheels):
        raise InvalidTypeError(
            f"Expected `wheels` to be a ReactionWheels, got {type(wheels).__name__}."
        )
    method = as_choice(method, "method", WHEEL_METHODS)
    if method == "rk4" and (rtol is not None or atol is not None):
        raise InvalidInputError(
            "Expected no `rtol`/`atol` with method='rk4' (a fixed-step method); use `max_step`."
        )
    tt = as_times(t, "t")
    model = as_torque(torque)
    h_max = _max_step(max_step)
    rt, at = _tolerances(1e-10 if rtol is None else rtol, 1e-12 if atol is None else atol)
    law: Callable[..., ArrayLike] | None
    if command is None or callable(command):
        law = command
    else:  # constant motor torques
        u = _constant_command(command, wheels)
        friction = bool(np.any(wheels.viscous) or np.any(wheels.coulomb))
        if model is None and method == "dop853" and not friction:
            out = _run_constant(
                inertia, wheels, rotation0, omega0, wheel_speed0, tt, u, rt, at, max_step
            )
            if out is not None:
                return out
        if u.shape != (wheels.n,):
            raise InvalidInputError(
                f"Expected `command` of shape ({wheels.n},) (one body), got {u.shape}"
                + _BATCH_ONLY
                + "."
            )
        u.setflags(write=False)
        law = lambda t, q, w, om: u  # noqa: E731
    j = _tensor(inertia)
    q0 = as_rotation_quat(rotation0, "rotation0")
    if q0.shape != (4,):
        raise InvalidInputError(
            f"Expected `rotation0` to have shape (4,) (one body), got {q0.shape}"
            + _BATCH_ONLY
            + "."
        )
    w0 = as_vec3(omega0, "omega0")
    if w0.shape != (3,):
        raise InvalidInputError(
            f"Expected `omega0` to have shape (3,) (one body), got {w0.shape}" + _BATCH_ONLY + "."
        )
    om0 = as_float_array(wheel_speed0, "wheel_speed0")
    if om0.shape != (wheels.n,):
        raise InvalidInputError(
            f"Expected `wheel_speed0` to have shape ({wheels.n},) (one body), got {om0.shape}"
            + _BATCH_ONLY
            + "."
        )
    _check_start(om0, wheels)
    _check_free(j - wheels.axial_inertia)
    sys_ = _WheelSystem(j, wheels, law, model)
    y0 = np.concatenate([q0, w0, om0])
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if method == "dop853":
            ys, info = _run_dop853(sys_, y0, tt, rt, at, h_max)
        else:
            ys, info = _run_rk4(sys_, y0, tt, h_max)
    q = _normalize(ys[:, :4])
    w, om = ys[:, 4:7], np.ascontiguousarray(ys[:, 7:])
    u = np.array([sys_.motion(float(tk), q[k], w[k], om[k])[2] for k, tk in enumerate(tt)])
    h = _along(wheels.axes, wheels.inertia * om)
    k_space = _quat.rotate(q, np.einsum("ij,nj->ni", j, w) + h)
    info.update(_conserved(model, law, wheels))
    return WheelTrajectory(
        tt,
        Rotation.from_quat(q),
        np.ascontiguousarray(w),
        method,
        energy=_energy(wheels, j, w, om),
        momentum=k_space,
        info=info,
        wheel_speed=om,
        wheel_momentum=h,
        motor_torque=u.reshape(tt.size, wheels.n),
    )


def _conserved(
    model: TorqueModel | None, command: object, wheels: ReactionWheels
) -> Mapping[str, Any]:
    """``torque`` and ``conserved`` of ``info``: ``K`` without external torque; ``T`` too
    when no motor torque, friction or speed hold can act."""
    if model is not None:
        return {"torque": type(model).__name__, "conserved": ()}
    quiet = (
        (command is None or (isinstance(command, np.ndarray) and not np.any(command)))
        and not np.any(wheels.viscous)
        and not np.any(wheels.coulomb)
        and np.all(np.isinf(wheels.max_speed))
    )
    return {"torque": "none", "conserved": ("energy", "momentum") if quiet else ("momentum",)}
