"""Angle presets (theory §3): "ship" (the course's sign: first a turn by MINUS psi about
axis 3, then theta about 1', then phi about 2'') and "bryant" = "cardan" (XYZ about the
moving axes), against explicit products of elementary rotation matrices."""

import numpy as np
import pytest

from poinsot import Rotation


def _a(axis, f):
    c, s = np.cos(f), np.sin(f)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m = np.eye(3)
    m[i, i] = m[j, j] = c
    m[i, j], m[j, i] = -s, s
    return m


ANGLES = np.array([[0.3, 0.2, -0.4], [-1.2, 0.7, 2.5], [2.9, -1.1, 0.05]])


@pytest.mark.parametrize("angles", ANGLES)
def test_ship_is_minus_psi_then_theta_then_phi(angles):
    psi, theta, phi = angles
    ref = _a(2, -psi) @ _a(0, theta) @ _a(1, phi)  # intrinsic: C = A_3(-psi) A_1' A_2''
    r = Rotation.from_euler("ship", angles)
    np.testing.assert_allclose(r.as_matrix(), ref, atol=1e-15)
    np.testing.assert_allclose(r.as_euler("ship"), angles, atol=1e-14)
    krylov = Rotation.from_euler("krylov", [-psi, theta, phi])
    np.testing.assert_allclose(krylov.as_matrix(), ref, atol=1e-15)


def test_ship_batches_and_degrees():
    r = Rotation.from_euler("ship", np.rad2deg(ANGLES), degrees=True)
    np.testing.assert_allclose(r.as_euler("ship", degrees=True), np.rad2deg(ANGLES), atol=1e-12)
    one = Rotation.from_euler("ship", ANGLES[1])
    np.testing.assert_allclose(r[1].as_matrix(), one.as_matrix(), atol=1e-15)


@pytest.mark.parametrize("name", ["bryant", "cardan", "Bryant"])
def test_bryant_is_xyz_about_the_moving_axes(name):
    f = ANGLES[0]
    ref = _a(0, f[0]) @ _a(1, f[1]) @ _a(2, f[2])
    np.testing.assert_allclose(Rotation.from_euler(name, f).as_matrix(), ref, atol=1e-15)
    np.testing.assert_allclose(Rotation.from_euler(name, f).as_euler(name), f, atol=1e-14)
