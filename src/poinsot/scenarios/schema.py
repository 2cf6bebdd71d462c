"""The scenario, as frozen dataclasses (what a TOML scenario file describes).

A scenario is either a **dynamics** scenario (a rigid body, its initial attitude and
angular velocity, a torque model: Euler's equations, SPEC S10) or a
**kinematics** scenario (an attitude propagated from a given angular-velocity
profile: Poisson's equation, SPEC S5). :func:`poinsot.scenarios.load_scenario`
builds one from a file; the format is documented in ``docs/cli.md``.

Convention: SI units (kg, m, s, N m); the attitude maps body components to space
components (``v_space = R v_body``); quaternions scalar first; the inertia tensor is
about the centre of mass, in body axes; the fixed point of a gravity scenario is
the origin of the body axes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "PartSpec",
    "BodySpec",
    "AttitudeSpec",
    "AngularVelocitySpec",
    "TorqueSpec",
    "OmegaProfileSpec",
    "SimulationSpec",
    "Scenario",
    "DYNAMICS_METHODS",
    "KINEMATICS_METHODS",
    "TORQUE_MODELS",
    "OMEGA_UNITS",
    "STANDARD_GRAVITY",
]

#: Integrators of Euler's equations accepted in ``[simulation] method`` (plus ``"exact"``).
DYNAMICS_METHODS = ("exact", "midpoint", "splitting", "rk4", "adaptive")
#: Attitude-propagation methods accepted for ``[omega_profile]`` scenarios.
KINEMATICS_METHODS = ("exact", "magnus4", "rk4", "adaptive")
TORQUE_MODELS = ("none", "body", "space", "gravity")
#: Angular velocity units and their factor to rad/s.
OMEGA_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0, "rpm": 2.0 * np.pi / 60.0, "Hz": 2.0 * np.pi}
STANDARD_GRAVITY = 9.80665


def _frozen_array(a) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class PartSpec:
    """One part of a composite body (``[[body.parts]]``).

    ``inertia`` is the part's inertia tensor about its own centre of mass in body
    axes; ``position`` is its centre of mass in body axes (m).
    """

    name: str
    mass: float
    inertia: np.ndarray
    position: np.ndarray
    shape: str | None = None
    dims: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _frozen_array(self.inertia))
        object.__setattr__(self, "position", _frozen_array(self.position))


@dataclass(frozen=True, eq=False)
class BodySpec:
    """The rigid body: total mass (kg), inertia tensor about the centre of mass in body
    axes (kg m^2), centre of mass in body axes (m) and how it was described."""

    mass: float
    inertia: np.ndarray
    center_of_mass: np.ndarray
    shape: str | None = None
    dims: tuple[float, ...] | None = None
    parts: tuple[PartSpec, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _frozen_array(self.inertia))
        object.__setattr__(self, "center_of_mass", _frozen_array(self.center_of_mass))

    def inertia_about_origin(self) -> np.ndarray:
        """Inertia tensor about the origin of the body axes (Huygens-Steiner, SPEC S8)."""
        from ..mass import parallel_axis

        return np.asarray(parallel_axis(self.inertia, self.mass, self.center_of_mass))


@dataclass(frozen=True, eq=False)
class AttitudeSpec:
    """Initial attitude as written (``representation``, ``values`` and convention) and
    resolved (``quat``, scalar-first unit quaternion, body -> space)."""

    representation: str
    values: tuple
    quat: np.ndarray
    sequence: str | None = None
    degrees: bool | None = None
    scalar_first: bool | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "quat", _frozen_array(self.quat))

    @property
    def rotation(self):
        from ..rotations.rotation import Rotation

        return Rotation.from_quat(self.quat)


@dataclass(frozen=True, eq=False)
class AngularVelocitySpec:
    """Initial angular velocity as written and resolved to body axes in rad/s."""

    vector: tuple[float, float, float]
    frame: str
    units: str
    omega_body: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "omega_body", _frozen_array(self.omega_body))


@dataclass(frozen=True, eq=False)
class TorqueSpec:
    """Torque model: ``"none"``, constant ``"body"`` or ``"space"`` vector (N m), or
    ``"gravity"`` about the fixed point (the origin of the body axes), with gravity
    ``g`` (m/s^2) along ``-z`` of space."""

    model: str = "none"
    vector: np.ndarray | None = None
    g: float | None = None

    def __post_init__(self) -> None:
        if self.vector is not None:
            object.__setattr__(self, "vector", _frozen_array(self.vector))


@dataclass(frozen=True, eq=False)
class OmegaProfileSpec:
    """A prescribed angular velocity ``omega(t)`` (rad/s) for attitude propagation.

    kinds: ``"constant"`` (``vector``), ``"coning"`` (classical coning motion of
    half-angle ``half_angle`` (rad) at rate ``rate`` (rad/s)), ``"samples"`` (``t``,
    ``omega`` tabulated, linearly interpolated); ``frame`` is ``"body"`` or ``"space"``.
    """

    kind: str
    frame: str
    vector: np.ndarray | None = None
    half_angle: float | None = None
    rate: float | None = None
    t: np.ndarray | None = None
    omega: np.ndarray | None = None

    def __post_init__(self) -> None:
        for name in ("vector", "t", "omega"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _frozen_array(getattr(self, name)))


@dataclass(frozen=True)
class SimulationSpec:
    """Output times and method: ``duration`` (s) and either ``step`` (s) or ``samples``;
    ``reference`` is an optional second method run on the same times for comparison;
    ``max_step`` (s) bounds the integration step (default: the output spacing)."""

    duration: float
    method: str
    step: float | None = None
    samples: int | None = None
    reference: str | None = None
    max_step: float | None = None

    def times(self) -> np.ndarray:
        """The output times ``0 .. duration`` (s)."""
        if self.samples is not None:
            return np.linspace(0.0, self.duration, self.samples)
        n = int(np.floor(self.duration / self.step + 1e-9))
        t = self.step * np.arange(n + 1)
        if self.duration - t[-1] > 1e-9 * self.duration:
            t = np.append(t, self.duration)
        return t


@dataclass(frozen=True, eq=False)
class Scenario:
    """A parsed scenario file.

    ``kind`` is ``"dynamics"`` (``body`` and ``angular_velocity`` set) or
    ``"kinematics"`` (``omega_profile`` set; ``body`` optional, used only to report
    energy and angular momentum). ``data`` is the file's content, echoed in outputs.
    """

    name: str
    source: str
    attitude: AttitudeSpec
    simulation: SimulationSpec
    description: str = ""
    body: BodySpec | None = None
    angular_velocity: AngularVelocitySpec | None = None
    torque: TorqueSpec = field(default_factory=TorqueSpec)
    omega_profile: OmegaProfileSpec | None = None
    data: dict[str, Any] = field(default_factory=dict)

    @property
    def kind(self) -> str:
        return "kinematics" if self.omega_profile is not None else "dynamics"
