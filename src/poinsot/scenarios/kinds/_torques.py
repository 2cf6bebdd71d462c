"""Torque models of the torqued-body kind (until poinsot.dynamics.torques replaces them)."""

from __future__ import annotations

import numpy as np


def _rotation_of(rotation):
    from ...rotations.rotation import Rotation

    return rotation if isinstance(rotation, Rotation) else Rotation.from_quat(rotation)


def space_torque(vector):
    m_n = np.asarray(vector, dtype=float)

    def torque(t, rotation, omega):
        return _rotation_of(rotation).apply(m_n, inverse=True)

    return torque


def gravity_torque(mass, center_of_mass, g):
    weight_n = mass * np.array([0.0, 0.0, -g])
    r_c = np.asarray(center_of_mass, dtype=float)

    def torque(t, rotation, omega):
        return np.cross(r_c, _rotation_of(rotation).apply(weight_n, inverse=True))

    return torque


def gravity_potential(mass, center_of_mass, g, rotation):
    return mass * g * rotation.apply(np.asarray(center_of_mass))[..., 2]
