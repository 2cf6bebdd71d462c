"""Poisson's matrix equations integrated directly (theory §5): against the exact
C0 exp(w^ t) for constant omega (body form) and exp(w^ t) C0 (space form), in 9 and in
the course's 6 equations; against poinsot's quaternion propagation for a varying
omega; the orthonormality drift is reported and small at tight tolerance."""

import numpy as np
import pytest
from scipy.linalg import expm

from poinsot import Rotation
from poinsot.errors import InvalidInputError
from poinsot.kinematics import integrate_poisson_matrix, propagate
from poinsot.rotations import hat

R0 = Rotation.from_rotvec([0.3, -0.2, 0.5])
W = np.array([0.4, -1.1, 0.7])
T = np.linspace(0.0, 3.0, 13)


@pytest.mark.parametrize("equations", [9, 6])
@pytest.mark.parametrize("frame", ["body", "space"])
def test_constant_omega_matches_the_exponential(frame, equations):
    run = integrate_poisson_matrix(R0, W, T, frame=frame, equations=equations, rtol=1e-12,
                                   atol=1e-14)  # fmt: skip
    c0 = R0.as_matrix()
    exact = np.stack(
        [c0 @ expm(hat(W) * tk) if frame == "body" else expm(hat(W) * tk) @ c0 for tk in T]
    )
    np.testing.assert_allclose(run.matrix, exact, atol=1e-10)
    assert run.orthonormality_drift.max() < 1e-10
    if equations == 6:  # the third column/row is the cross product: orthogonal to the others
        c = run.matrix[-1]
        third = c[:, 2] if frame == "body" else c[2]
        first = c[:, 0] if frame == "body" else c[0]
        assert abs(third @ first) < 1e-12


def test_varying_omega_matches_quaternion_propagation():
    def w(t):
        return np.array([np.sin(t), 0.5, np.cos(2 * t)])

    run = integrate_poisson_matrix(R0, w, T, rtol=1e-12, atol=1e-14)
    q = propagate(R0, w, T, method="adaptive", rtol=1e-12, atol=1e-14)
    ang = (q.rotation.inv() * run.rotation).magnitude()
    assert np.max(ang) < 1e-9


def test_loose_tolerance_shows_the_drift_and_bad_input_is_named():
    run = integrate_poisson_matrix(R0, W, np.linspace(0, 30, 4), rtol=1e-3, atol=1e-3)
    assert run.orthonormality_drift[-1] > 1e-6  # a matrix integration is not orthogonal
    with pytest.raises(InvalidInputError, match="equations"):
        integrate_poisson_matrix(R0, W, T, equations=4)


@pytest.mark.parametrize("representation", ["dcm", "dcm6"])
def test_propagate_with_the_matrix_representation(representation):
    """propagate(..., representation="dcm"/"dcm6") runs the matrix equation and agrees
    with the quaternion propagation; the drift is in info."""
    q = propagate(R0, lambda t: W, T, method="adaptive", rtol=1e-12, atol=1e-14)
    m = propagate(R0, W, T, method="adaptive", rtol=1e-12, atol=1e-14,
                  representation=representation)  # fmt: skip
    assert np.max((q.rotation.inv() * m.rotation).magnitude()) < 1e-9
    assert 0 <= m.info["orthonormality_drift"] < 1e-9
    np.testing.assert_allclose(m.omega, np.broadcast_to(W, (T.size, 3)))
    with pytest.raises(InvalidInputError, match="method='adaptive'"):
        propagate(R0, W, T, representation=representation)
