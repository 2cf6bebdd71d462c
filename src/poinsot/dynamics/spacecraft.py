"""A spacecraft in orbit: environment torques, a control law and reaction wheels
(theory §10.2, §10.3).

:class:`Spacecraft` puts together what :mod:`poinsot.dynamics.orbit`,
:mod:`poinsot.dynamics.torques`, :mod:`poinsot.dynamics.control` and
:mod:`poinsot.dynamics.wheels` define one by one: the orbit (a
:class:`~poinsot.dynamics.KeplerOrbit`) gives the position, hence the
gravity-gradient torque and the magnetic field along the way; the orbit frame
(``"lvlh"`` or ``"rtn"``) gives the attitude the satellite is judged against
(:meth:`Spacecraft.orbit_reference`, :meth:`Spacecraft.relative`,
:meth:`Spacecraft.pointing_error`); a control law acts as an external torque
(thrusters, magnetorquers) or through reaction wheels.

**Convention:** attitude maps body to inertial components (scalar-first
quaternions, ``v_i = R_ib v_b``), the orbit frame's attitude ``R_io`` maps its
components to inertial ones, so the attitude relative to the orbit frame is
``R_ob = R_io^T R_ib``; ``omega`` in body axes (rad/s); torques N m, body axes;
times s from the orbit's time origin.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_choice, as_times, as_vec3
from ..errors import InvalidInputError, InvalidTypeError
from ..mass.tensor import as_inertia
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory
from .control import BDot
from .euler_equations import simulate
from .orbit import ORBIT_FRAMES, orbit_frame, orbit_frame_rates
from .torques import MagneticTorque, OrbitGravityGradientTorque, TorqueModel
from .wheels import ReactionWheels, WheelTrajectory, simulate_wheels

__all__ = ["Spacecraft"]


def _as_rotation(x: Any, name: str) -> Rotation:
    if isinstance(x, Rotation):
        return x
    return Rotation.from_quat(np.asarray(x, dtype=float))


@dataclass(frozen=True, eq=False)
class Spacecraft:
    """A rigid satellite on a Kepler orbit, with its environment torques, an attitude
    control law and optional reaction wheels (theory §10.2, §10.3).

    The body obeys Euler's equations (theory §10; with wheels, theory §10.1) under

    ``M = M_gg + M_mag + L``,  ``M_gg = 3 mu / r^3 n_b x (J n_b)`` (``n_b = R^T r /
    |r|``),  ``M_mag = m_b x R^T B(t, r)``,

    where ``r(t)`` is the orbit's position, ``B`` the Earth's field
    (:func:`~poinsot.dynamics.dipole_field` unless ``field`` is given) and ``L`` the
    control torque. With ``wheels``, a law that has ``wheel_command`` (quaternion
    PD, MRP feedback, eigenaxis slew) drives the motors so that the body feels ``L``
    (the wheels' momentum absorbs it); B-dot always acts through magnetorquers.

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3)
        ``J`` about the centre of mass, body axes (kg m^2), wheels locked when there
        are wheels.
    orbit : KeplerOrbit
        The orbit (or any object with ``state(t) -> (r, v)``, ``position(t)`` and
        ``mu``).
    frame : {"lvlh", "rtn"}, optional
        The orbit frame of the reference attitude (:func:`~poinsot.dynamics.orbit_frame`);
        default ``"lvlh"`` (``z`` nadir, ``y`` minus the orbit normal).
    gravity_gradient : bool, optional
        Include the gravity-gradient torque (default ``True``).
    dipole : array_like, shape (3,), optional
        A residual magnetic dipole of the body (A m^2, body axes); default none.
    field : callable, optional
        ``field(t, r) -> (3,)`` (T, inertial axes) for ``dipole``; default the
        tilted dipole :func:`~poinsot.dynamics.dipole_field`.
    control : TorqueModel, optional
        The control law (:class:`~poinsot.dynamics.QuaternionPD`,
        :class:`~poinsot.dynamics.MRPFeedback`, :class:`~poinsot.dynamics.EigenaxisSlew`,
        :class:`~poinsot.dynamics.BDot` or any torque model); for pointing in the
        orbit frame give it ``target=spacecraft.orbit_reference()``.
    wheels : ReactionWheels, optional
        Reaction wheels that carry out ``control`` (see above).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import KeplerOrbit, Spacecraft
    >>> orbit = KeplerOrbit(7.0e6, 0.0, 0.9, 0.0, 0.0, 0.0)
    >>> sat = Spacecraft([10.0, 12.0, 8.0], orbit)       # gravity gradient only
    >>> t = np.linspace(0.0, 600.0, 3)
    >>> q0 = sat.orbit_attitude(0.0)                     # aligned with LVLH ...
    >>> w0 = sat.orbit_rate(q0, 0.0)                     # ... and turning with it
    >>> tr = sat.simulate(q0, w0, t)
    >>> float(np.degrees(sat.pointing_error(tr)).max()) < 1e-6   # an equilibrium
    True
    """

    inertia: Any
    orbit: Any
    frame: str = "lvlh"
    gravity_gradient: bool = True
    dipole: Any = None
    field: Callable[..., Any] | None = None
    control: TorqueModel | None = None
    wheels: ReactionWheels | None = None

    def __post_init__(self) -> None:
        j, principal = as_inertia(self.inertia, "inertia")
        if np.ndim(j) != (1 if principal else 2):
            raise InvalidInputError("Expected `inertia` of one body, (3,) or (3, 3).")
        object.__setattr__(self, "inertia", np.diag(j) if principal else np.asarray(j))
        for attr in ("state", "position"):
            if not callable(getattr(self.orbit, attr, None)):
                raise InvalidTypeError(
                    "Expected `orbit` to be a KeplerOrbit (or have state(t) and "
                    f"position(t)), got {type(self.orbit).__name__}."
                )
        as_choice(self.frame, "frame", ORBIT_FRAMES)
        as_bool(self.gravity_gradient, "gravity_gradient")
        if self.dipole is not None:
            object.__setattr__(self, "dipole", as_vec3(self.dipole, "dipole"))
        if self.control is not None and not isinstance(self.control, TorqueModel):
            raise InvalidTypeError(
                f"Expected `control` to be a TorqueModel, got {type(self.control).__name__}."
            )
        if self.wheels is not None and not isinstance(self.wheels, ReactionWheels):
            raise InvalidTypeError(
                f"Expected `wheels` to be ReactionWheels, got {type(self.wheels).__name__}."
            )

    # -- the orbit frame ------------------------------------------------------------
    def orbit_attitude(self, t: ArrayLike) -> Rotation:
        """``R_io(t)``: the orbit frame's attitude (its axes to inertial) at ``t`` (s)."""
        r, v = self.orbit.state(np.asarray(t, dtype=float))
        return orbit_frame(r, v, frame=self.frame)

    def orbit_reference(
        self, offset: Rotation | ArrayLike | None = None
    ) -> Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The target ``t -> (q_r, w_r, w_r')`` of a body held at ``offset`` (``R_or``,
        default the identity) in the orbit frame, as the control laws take it:
        ``q_r = q_io o q_or`` and the frame's rate and acceleration in ``R`` axes
        (rad/s, rad/s^2; theory §10.2: ``w_o = |h| / r^2`` about the orbit normal)."""
        off = Rotation.identity() if offset is None else _as_rotation(offset, "offset")
        q_or = off.as_quat()

        def reference(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            r, v = self.orbit.state(float(t))
            q_io = orbit_frame(r, v, frame=self.frame)
            w, dw = orbit_frame_rates(r, v, frame=self.frame)
            q_r = (q_io * Rotation.from_quat(q_or)).as_quat()
            return q_r, off.inv().apply(w), off.inv().apply(dw)

        return reference

    def orbit_rate(self, rotation: Rotation | ArrayLike, t: float) -> FloatArray:
        """The body rate (rad/s, body axes) of a body at ``rotation`` (body -> inertial)
        that turns with the orbit frame at ``t``: ``R_ib^T R_io w_o``."""
        r, v = self.orbit.state(float(t))
        w, _ = orbit_frame_rates(r, v, frame=self.frame)
        w_i = orbit_frame(r, v, frame=self.frame).apply(w)
        return _as_rotation(rotation, "rotation").inv().apply(w_i)

    def relative(self, trajectory: Trajectory) -> Rotation:
        """``R_ob(t) = R_io(t)^T R_ib(t)``: the attitude relative to the orbit frame
        along ``trajectory`` (time first; a batch of bodies after time, shape (n, M),
        is judged against the one orbit frame at each time)."""
        ref = self.orbit_attitude(trajectory.t)
        rot = trajectory.rotation
        extra = len(rot.shape) - len(ref.shape)  # the batch axes after time
        if extra > 0:
            ref = ref.reshape(*ref.shape, *(1,) * extra)
        return ref.inv() * rot

    def pointing_error(
        self, trajectory: Trajectory, offset: Rotation | ArrayLike | None = None
    ) -> FloatArray:
        """The angle (rad) of the rotation from the target ``R_io R_or`` to the body,
        at each time of ``trajectory`` (``offset`` ``R_or`` as in
        :meth:`orbit_reference`)."""
        rel = self.relative(trajectory)
        if offset is not None:
            rel = _as_rotation(offset, "offset").inv() * rel
        return np.asarray(rel.magnitude())

    # -- torques ------------------------------------------------------------------------
    def environment(self) -> TorqueModel | None:
        """The environment torques (gravity gradient, residual dipole) as one model, or
        ``None``."""
        parts: list[TorqueModel] = []
        if self.gravity_gradient:
            parts.append(OrbitGravityGradientTorque(self.inertia, self.orbit))
        if self.dipole is not None:
            parts.append(MagneticTorque(self.dipole, self.orbit, field=self.field))
        if not parts:
            return None
        total = parts[0]
        for p in parts[1:]:
            total = total + p
        return total

    def _through_wheels(self) -> bool:
        return (
            self.wheels is not None
            and self.control is not None
            and hasattr(self.control, "wheel_command")
            and not isinstance(self.control, BDot)
        )

    def external_torque(self) -> TorqueModel | None:
        """Everything that acts on the body from outside: :meth:`environment` plus the
        control law unless wheels carry it out."""
        total = self.environment()
        if self.control is not None and not self._through_wheels():
            total = self.control if total is None else total + self.control
        return total

    # -- motion -----------------------------------------------------------------------------
    def simulate(
        self,
        rotation0: Rotation | ArrayLike,
        omega0: ArrayLike,
        t: ArrayLike,
        *,
        wheel_speed0: ArrayLike | None = None,
        method: str = "dop853",
        rtol: float | None = None,
        atol: float | None = None,
        max_step: float | None = None,
    ) -> Trajectory | WheelTrajectory:
        """Integrate the attitude from ``rotation0`` (body -> inertial) and ``omega0``
        (rad/s, body axes) at ``t[0]`` over the times ``t`` (s).

        Without wheels, :func:`~poinsot.dynamics.simulate` under
        :meth:`external_torque`; with wheels, :func:`~poinsot.dynamics.simulate_wheels`
        (``wheel_speed0`` (N,) rad/s, default at rest) with the control law's
        ``wheel_command``. ``method``, ``rtol``, ``atol``, ``max_step`` as those
        functions take them (defaults: DOP853, rtol 1e-10).

        Returns
        -------
        Trajectory or WheelTrajectory
        """
        times = as_times(t, "t")
        rtol = 1e-10 if rtol is None and method == "dop853" else rtol
        atol = 1e-12 if atol is None and method == "dop853" else atol
        if self.wheels is None:
            if wheel_speed0 is not None:
                raise InvalidInputError("`wheel_speed0` needs `wheels`.")
            return simulate(
                self.inertia, rotation0, omega0, times, torque=self.external_torque(),
                method=method, rtol=rtol, atol=atol, max_step=max_step,
            )  # fmt: skip
        n = self.wheels.axes.shape[0]
        speed0 = np.zeros(n) if wheel_speed0 is None else wheel_speed0
        command = None
        if self._through_wheels():
            command = self.control.wheel_command(self.wheels, self.inertia)  # type: ignore[union-attr]
        return simulate_wheels(
            self.inertia, self.wheels, rotation0, omega0, speed0, times, command=command,
            torque=self.external_torque(), method=method, rtol=rtol, atol=atol,
            max_step=max_step,
        )  # fmt: skip
