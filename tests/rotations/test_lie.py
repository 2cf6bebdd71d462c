"""so(3) helpers (theory §1, §2): exp/log against SciPy's expm/logm and exact closed
forms at the ends (angle 1e-12 and pi - 1e-8, pi), the quaternion product matrices
against the product itself, and the eigen-structure against numpy.linalg.eig."""

import numpy as np
import pytest
from scipy.linalg import expm

from poinsot import InvalidInputError
from poinsot.rotations import (
    expm_so3,
    hat,
    logm_so3,
    quat_left_matrix,
    quat_right_matrix,
    rotation_eigen,
    vee,
)
from poinsot.rotations.quaternion import multiply

RNG = np.random.default_rng(3)
AXIS = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])


def test_hat_vee_round_trip_and_cross_product():
    v, u = RNG.normal(size=(5, 3)), RNG.normal(size=(5, 3))
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", hat(v), u), np.cross(v, u), atol=1e-15)
    np.testing.assert_array_equal(vee(hat(v)), v)
    with pytest.raises(InvalidInputError, match="skew-symmetric"):
        vee(np.eye(3))


def test_expm_matches_scipy_expm():
    for phi in RNG.normal(size=(6, 3)):
        np.testing.assert_allclose(expm_so3(hat(phi)), expm(hat(phi)), atol=1e-13)


@pytest.mark.parametrize("angle", [1e-12, 1e-8, 1.0, np.pi - 1e-8])
def test_logm_is_exact_near_zero_and_pi(angle):
    """R = E + sin f e^ + (1 - cos f) e^^2 built here in closed form; log(R) = f e^."""
    e = hat(AXIS)
    r = np.eye(3) + np.sin(angle) * e + (1.0 - np.cos(angle)) * (e @ e)
    np.testing.assert_allclose(vee(logm_so3(r)), angle * AXIS, rtol=1e-12, atol=1e-20)


def test_logm_at_pi_gives_a_logarithm():
    r = np.eye(3) + 2.0 * (hat(AXIS) @ hat(AXIS))  # a half turn
    phi = vee(logm_so3(r))
    assert abs(np.linalg.norm(phi) - np.pi) < 1e-14
    np.testing.assert_allclose(expm_so3(hat(phi)), r, atol=1e-15)


def test_quaternion_product_matrices():
    q, p = RNG.normal(size=(4, 4)), RNG.normal(size=(4, 4))
    np.testing.assert_allclose(quat_left_matrix(q) @ p[..., None], multiply(q, p)[..., None],
                               atol=1e-14)  # fmt: skip
    np.testing.assert_allclose(quat_right_matrix(q) @ p[..., None], multiply(p, q)[..., None],
                               atol=1e-14)  # fmt: skip
    a, b = quat_left_matrix(p[0]), quat_right_matrix(q[0])
    np.testing.assert_allclose(a @ b, b @ a, atol=1e-14)  # associativity of the product


@pytest.mark.parametrize("angle", [0.0, 1e-9, 0.7, np.pi])
def test_rotation_eigen_against_numpy(angle):
    r = expm(hat(angle * AXIS))
    e = rotation_eigen(r)
    ref = np.sort_complex(np.linalg.eigvals(r))
    np.testing.assert_allclose(np.sort_complex(e.eigenvalues), ref, atol=1e-8)
    if angle > 0:
        sign = np.sign(e.axis @ AXIS) if angle == np.pi else 1.0  # at pi, -axis is as good
        np.testing.assert_allclose(sign * e.axis, AXIS, atol=1e-12)
        assert e.angle == pytest.approx(angle, rel=1e-12)
    np.testing.assert_allclose(r @ e.axis, e.axis, atol=1e-15)
    u, v = e.plane
    np.testing.assert_allclose([u @ e.axis, v @ e.axis, u @ v, u @ u, v @ v], [0, 0, 0, 1, 1],
                               atol=1e-15)  # fmt: skip
    np.testing.assert_allclose(r @ u, np.cos(e.angle) * u + np.sin(e.angle) * v, atol=1e-14)
