"""The scenario, as frozen dataclasses (what a TOML scenario file describes).

Every scenario has a ``kind``: the name of the adapter in
:data:`poinsot.scenarios.registry.KINDS` that reads its tables, solves it and
summarises it (``docs/adding-a-motion.md``). The built-in kinds are rigid-body
motions (``"free-body"``: Euler's case, docs/theory.md §10; ``"torqued-body"``: a
body torque, a space torque or gravity about a fixed point) and attitude
propagation from a prescribed angular velocity (``"attitude"`` and ``"coning"``:
Poisson's equation, docs/theory.md §5). :func:`poinsot.scenarios.load_scenario`
builds one from a file; the format is documented in ``docs/cli.md``.

Convention: SI units (kg, m, s, N m); the attitude maps body components to space
components (``v_space = R v_body``); quaternions scalar first; the inertia tensor is
about the centre of mass, in body axes; the fixed point of a gravity scenario is
the origin of the body axes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import integrators
from ..dynamics.torques import STANDARD_GRAVITY  # the one value (m/s^2)
from ..errors import InvalidInputError
from ..mass import parallel_axis
from ..rotations.rotation import Rotation

if TYPE_CHECKING:
    from ..rotations.rotation import Rotation

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
    "MAX_SAMPLES",
]

#: Integrators of Euler's equations accepted in ``[simulation] method`` (plus ``"exact"``),
#: from the one table :data:`poinsot.integrators.INTEGRATORS`.
DYNAMICS_METHODS = integrators.names("rigid", exact=True)
#: Attitude-propagation methods accepted for ``[omega_profile]`` scenarios.
KINEMATICS_METHODS = integrators.names("attitude", exact=True)
TORQUE_MODELS = ("none", "body", "space", "gravity")
#: Angular velocity units and their factor to rad/s.
OMEGA_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0, "rpm": 2.0 * np.pi / 60.0, "Hz": 2.0 * np.pi}
#: Most output samples a scenario may have, after every override (``--duration``).
MAX_SAMPLES = 5_000_000


def _frozen_array(a: Any) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class PartSpec:
    """One part of a composite body (``[[body.parts]]``).

    ``inertia`` is the part's inertia tensor about its own centre of mass in body
    axes; ``position`` is its centre of mass in body axes (m). A ``shape = "mesh"``
    part keeps its triangle mesh placed in body axes: ``vertices`` (m) and
    ``faces`` (0-based indices, counter-clockwise seen from outside).
    """

    name: str
    mass: float
    inertia: np.ndarray
    position: np.ndarray
    shape: str | None = None
    dims: tuple[float, ...] | None = None
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _frozen_array(self.inertia))
        object.__setattr__(self, "position", _frozen_array(self.position))
        _freeze_mesh(self)


def _freeze_mesh(spec: Any) -> None:
    if spec.vertices is not None:
        object.__setattr__(spec, "vertices", _frozen_array(spec.vertices))
    if spec.faces is not None:
        f = np.array(spec.faces, dtype=np.int64)
        f.setflags(write=False)
        object.__setattr__(spec, "faces", f)


@dataclass(frozen=True, eq=False)
class BodySpec:
    """The rigid body: total mass (kg), inertia tensor about the centre of mass in body
    axes (kg m^2), centre of mass in body axes (m) and how it was described (a
    ``shape = "mesh"`` body keeps its ``vertices`` (m, body axes) and ``faces``)."""

    mass: float
    inertia: np.ndarray
    center_of_mass: np.ndarray
    shape: str | None = None
    dims: tuple[float, ...] | None = None
    parts: tuple[PartSpec, ...] = ()
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _frozen_array(self.inertia))
        object.__setattr__(self, "center_of_mass", _frozen_array(self.center_of_mass))
        _freeze_mesh(self)

    def inertia_about_origin(self) -> np.ndarray:
        """Inertia tensor about the origin of the body axes (Huygens-Steiner,
        docs/theory.md §8)."""

        return np.asarray(parallel_axis(self.inertia, self.mass, self.center_of_mass))


@dataclass(frozen=True, eq=False)
class AttitudeSpec:
    """Initial attitude as written (``representation``, ``values`` and convention) and
    resolved (``quat``, scalar-first unit quaternion, body -> space)."""

    representation: str
    values: tuple[Any, ...]
    quat: np.ndarray
    sequence: str | None = None
    degrees: bool | None = None
    scalar_first: bool | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "quat", _frozen_array(self.quat))

    @property
    def rotation(self) -> Rotation:
        return Rotation.from_quat(self.quat)


@dataclass(frozen=True, eq=False)
class AngularVelocitySpec:
    """Initial angular velocity as written and resolved to body axes in rad/s."""

    vector: tuple[float, ...]
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
    ``max_step`` (s) bounds the integration step (default: the output spacing);
    ``drift_threshold`` (relative), ``attitude_threshold`` (rad) and
    ``agreement_threshold`` (relative to each quantity's scale) replace the default
    accuracy thresholds of :mod:`poinsot.scenarios.summary`."""

    def n_samples(self) -> int:
        """The number of output times, computed without building them."""
        if self.samples is not None:
            return int(self.samples)
        step = self.step
        assert step is not None  # exactly one of `step` and `samples` is given
        ratio = self.duration / step
        if not ratio < 1e15:
            return 10**15  # beyond any limit: refused before anything is allocated
        n = int(np.floor(ratio + 1e-9))
        last = step * n
        return n + 1 + (1 if self.duration - last > 1e-9 * self.duration else 0)

    def spacing(self) -> float:
        """The output spacing (s): ``step``, or ``duration / (samples - 1)``."""
        if self.step is not None:
            return float(self.step)
        assert self.samples is not None  # exactly one of `step` and `samples` is given
        return self.duration / (self.samples - 1)

    def integration_step(self) -> float:
        """The longest integration step of a fixed-step method (s): ``max_step`` when
        given and shorter than the output spacing, else the output spacing."""
        h = self.spacing()
        return min(h, self.max_step) if self.max_step is not None else h

    duration: float
    method: str
    step: float | None = None
    samples: int | None = None
    reference: str | None = None
    max_step: float | None = None
    drift_threshold: float | None = None
    attitude_threshold: float | None = None
    agreement_threshold: float | None = None

    def times(self) -> np.ndarray:
        """The output times ``0 .. duration`` (s)."""
        if self.samples is not None:
            return np.linspace(0.0, self.duration, self.samples)
        step = self.step
        assert step is not None  # exactly one of `step` and `samples` is given
        n = int(np.floor(self.duration / step + 1e-9))
        t = step * np.arange(n + 1)
        if self.duration - t[-1] > 1e-9 * self.duration:
            t = np.append(t, self.duration)
        return t


#: Largest maximum relative drift of a conserved quantity accepted without a warning.
DRIFT_THRESHOLD = 1e-6
#: Largest attitude difference from the reference (rad) accepted without a warning.
ATTITUDE_THRESHOLD = 1e-2
#: Largest difference from the reference of any other state quantity accepted without
#: a warning, relative to the quantity's scale (its largest magnitude along the
#: reference run).
AGREEMENT_THRESHOLD = 1e-2


def agreement_thresholds(scenario: Scenario) -> tuple[float, float]:
    """``(attitude_threshold (rad), agreement_threshold (relative))`` of a scenario:
    its ``[simulation]`` values, else :data:`ATTITUDE_THRESHOLD` and
    :data:`AGREEMENT_THRESHOLD`.

    Examples
    --------
    >>> from poinsot.scenarios import demo_scenario
    >>> agreement_thresholds(demo_scenario())
    (0.01, 0.01)
    """
    sim = scenario.simulation
    att = getattr(sim, "attitude_threshold", None) or ATTITUDE_THRESHOLD
    rel = getattr(sim, "agreement_threshold", None) or AGREEMENT_THRESHOLD
    return float(att), float(rel)


@dataclass(frozen=True, eq=False)
class Scenario:
    """A parsed scenario file.

    ``kind`` names the adapter that solves it (a key of
    :data:`poinsot.scenarios.registry.KINDS`): ``"free-body"`` and
    ``"torqued-body"`` (``body`` and ``angular_velocity`` set), ``"attitude"`` and
    ``"coning"`` (``omega_profile`` set; ``body`` optional, used only to report
    energy and angular momentum). A kind added later keeps what it reads from its
    own tables in ``spec`` (its own frozen dataclass). ``data`` is the file's
    content, echoed in outputs.
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
    kind: str = "free-body"
    spec: Any = None
    #: The :class:`~poinsot.scenarios.kind.ScenarioKind` that solves this scenario (the
    #: reader sets it: :func:`~poinsot.scenarios.load_scenario`); its ``name`` is ``kind``.
    adapter: Any = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.adapter is not None and getattr(self.adapter, "name", self.kind) != self.kind:
            raise InvalidInputError(
                f"Expected `adapter` to solve kind {self.kind!r}, got one of kind "
                f"{self.adapter.name!r}."
            )
