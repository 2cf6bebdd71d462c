"""Dynamics (theory §8-§10): Euler's equations and their integrators, torque models
and invariants, exact solutions (free body, gyrostat, Lagrange top), the heavy body, attitude
control and estimation (sensors, the MEKF), particles in moving frames and central forces.

A new kind of motion is one module here plus one scenario adapter
(``docs/adding-a-motion.md``); it follows the contract of ``docs/conventions.md``
("One contract for the things that move").

**Convention:** angular velocity in body axes, angular momentum in space axes,
attitude maps body to space components. See ``docs/dynamics.md`` and
``docs/free-body.md``.

>>> from poinsot.dynamics import FreeRigidBody
>>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0])
>>> float(body.energy)
1.5
"""

from __future__ import annotations

from ..events import Event, EventLog
from .central import (
    Apsides,
    CentralOrbit,
    KeplerConic,
    Potential,
    harmonic,
    inverse_square,
    kepler,
    power_law,
)
from .charts import (
    ChartTrajectory,
    CoordinateChart,
    simulate_charts,
    spherical_pendulum_charts,
)
from .control import BDot, EigenaxisSlew, MRPFeedback, QuaternionPD, SlewProfile
from .earth import (
    EARTH_ROTATION_RATE,
    PendulumForce,
    UniformGravity,
    earth_frame,
    eastward_deflection,
    foucault_frame,
    foucault_pendulum,
    foucault_period,
    foucault_precession_rate,
    normal_gravity,
    swing_plane_angles,
)
from .estimation import (
    GYRO_KINDS,
    MEKF,
    AttitudeSamples,
    EstimationResult,
    Gyro,
    GyroSamples,
    StarTracker,
    VectorSamples,
    VectorSensor,
    attitude_error,
    nees,
    nis,
    run_mekf,
)
from .euler_equations import (
    METHODS,
    euler_rhs,
    simulate,
)
from .free_body import (
    NEAR_SEPARATRIX,
    SEPARATRIX_RTOL,
    SYMMETRY_RTOL,
    FreeRigidBody,
    MacCullaghGeometry,
    PoinsotGeometry,
    RegularPrecession,
)
from .free_motion import simulate_free_motion
from .gyroscope import (
    GyroscopicMoment,
    critical_spin,
    gyroscope_precession_rate,
    gyroscopic_moment,
    regular_precession_rates,
    sleeping_top_stable,
)
from .gyrostat import GYROSTAT_REGIMES, FreeGyrostat, gyrostat_rhs, gyrostat_spin_stable
from .heavy import HEAVY_METHODS, HeavyRigidBody, kovalevskaya_integral
from .impacts import (
    ImpactResult,
    collision_matrix,
    particle_impact,
    rigid_impact,
    simulate_bounces,
)
from .invariants import Invariants, angular_momentum, invariants, kinetic_energy
from .lagrange_top import MOTION_TYPES, LagrangeTop
from .orbit import (
    EARTH_MAGNETIC_RADIUS,
    EARTH_MU,
    IGRF2020_DIPOLE,
    ORBIT_FRAMES,
    GravityGradientStability,
    KeplerOrbit,
    PitchLibration,
    dipole_field,
    gravity_gradient_stability,
    linearized_gravity_gradient,
    orbit_frame,
    orbit_frame_rates,
)
from .particles import (
    PARTICLE_SOLVERS,
    BodyInertialForces,
    InertialForces,
    ParticleTrajectory,
    body_inertial_forces,
    inertial_forces,
    jacobi_integral,
    relative_motion,
    simulate_particle,
)
from .spacecraft import Spacecraft
from .systems import (
    FORCE_KINDS,
    ForceClassification,
    ForceSystem,
    KoenigSplit,
    LinePotential,
    ParticleSystem,
    classify_force,
    reduce_forces,
    shift_angular_momentum,
)
from .torques import (
    STANDARD_GRAVITY,
    CallableTorque,
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityGradientTorque,
    GravityTorque,
    GyrostaticTorque,
    MagneticTorque,
    OrbitGravityGradientTorque,
    TorqueModel,
    TorqueSum,
    as_torque,
)
from .unilateral import ContactTrajectory, Plane, Sphere, Surface, simulate_unilateral
from .wheels import WHEEL_METHODS, ReactionWheels, WheelTrajectory, pyramid, simulate_wheels

__all__ = [
    "simulate_free_motion",
    "BodyInertialForces",
    "body_inertial_forces",
    "ForceSystem",
    "reduce_forces",
    # heavy body about a fixed point, Lagrange and Kovalevskaya tops (theory §10)
    "HeavyRigidBody",
    "HEAVY_METHODS",
    "kovalevskaya_integral",
    "LagrangeTop",
    "MOTION_TYPES",
    "regular_precession_rates",
    "gyroscope_precession_rate",
    "critical_spin",
    "sleeping_top_stable",
    "gyroscopic_moment",
    "GyroscopicMoment",
    "euler_rhs",
    "simulate",
    "METHODS",
    "FreeRigidBody",
    # the gyrostat (theory §10.1)
    "FreeGyrostat",
    "gyrostat_rhs",
    "gyrostat_spin_stable",
    "GYROSTAT_REGIMES",
    # reaction wheels (theory §10.1)
    "ReactionWheels",
    "pyramid",
    "simulate_wheels",
    "WheelTrajectory",
    "WHEEL_METHODS",
    # attitude control laws (theory §10.3)
    "QuaternionPD",
    "MRPFeedback",
    "EigenaxisSlew",
    "SlewProfile",
    "BDot",
    # attitude estimation (theory §10.4)
    "Gyro",
    "GYRO_KINDS",
    "GyroSamples",
    "StarTracker",
    "AttitudeSamples",
    "VectorSensor",
    "VectorSamples",
    "MEKF",
    "EstimationResult",
    "Event",
    "EventLog",
    "ImpactResult",
    "collision_matrix",
    "particle_impact",
    "rigid_impact",
    "simulate_bounces",
    "ContactTrajectory",
    "Plane",
    "Sphere",
    "Surface",
    "simulate_unilateral",
    "ChartTrajectory",
    "CoordinateChart",
    "simulate_charts",
    "spherical_pendulum_charts",
    "run_mekf",
    "attitude_error",
    "nees",
    "nis",
    "RegularPrecession",
    "MacCullaghGeometry",
    "PoinsotGeometry",
    "SYMMETRY_RTOL",
    "SEPARATRIX_RTOL",
    "NEAR_SEPARATRIX",
    "kinetic_energy",
    "angular_momentum",
    "invariants",
    "Invariants",
    "TorqueModel",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "GravityTorque",
    "GravityGradientTorque",
    "GyrostaticTorque",
    "CallableTorque",
    "TorqueSum",
    "as_torque",
    # attitude in orbit (theory §10.2)
    "OrbitGravityGradientTorque",
    "MagneticTorque",
    "KeplerOrbit",
    "Spacecraft",
    "orbit_frame",
    "orbit_frame_rates",
    "dipole_field",
    "PitchLibration",
    "GravityGradientStability",
    "gravity_gradient_stability",
    "linearized_gravity_gradient",
    "ORBIT_FRAMES",
    "EARTH_MU",
    "EARTH_MAGNETIC_RADIUS",
    "IGRF2020_DIPOLE",
    "STANDARD_GRAVITY",
    # particles in moving frames (theory §9)
    "inertial_forces",
    "InertialForces",
    "simulate_particle",
    "ParticleTrajectory",
    "jacobi_integral",
    "earth_frame",
    "normal_gravity",
    "eastward_deflection",
    "foucault_precession_rate",
    "foucault_period",
    "foucault_pendulum",
    "swing_plane_angles",
    "relative_motion",
    "UniformGravity",
    "PendulumForce",
    "foucault_frame",
    "EARTH_ROTATION_RATE",
    "PARTICLE_SOLVERS",
    # central forces (theory §9)
    "CentralOrbit",
    "Apsides",
    "KeplerConic",
    "Potential",
    "kepler",
    "inverse_square",
    "harmonic",
    "power_law",
    # forces and systems of particles (theory §9)
    "classify_force",
    "ForceClassification",
    "LinePotential",
    "FORCE_KINDS",
    "ParticleSystem",
    "KoenigSplit",
    "shift_angular_momentum",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
