"""Every constructor that takes a RigidBody uses the inertia about the point its
docstring names; checked against the parallel-axis theorem computed here,
J_O = J_C + m (|c|^2 E - c c^T) (Huygens-Steiner, theory §8)."""

import numpy as np
import pytest

from poinsot.dynamics import FreeRigidBody, HeavyRigidBody, simulate
from poinsot.errors import InvalidInputError
from poinsot.mass import RigidBody


def _steiner(j_c, m, c):
    c = np.asarray(c, dtype=float)
    return np.asarray(j_c, dtype=float) + m * (c @ c * np.eye(3) - np.outer(c, c))


def test_heavy_body_takes_the_inertia_about_the_fixed_point():
    """The issue's case: moments (2, 2, 1) about the centre of mass, m = 1,
    c = (0, 0, 0.5) -> (2.25, 2.25, 1) about the fixed point O."""
    body = RigidBody(1.0, [2.0, 2.0, 1.0], center_of_mass=[0.0, 0.0, 0.5])
    top = HeavyRigidBody(body)
    np.testing.assert_allclose(np.diag(top.inertia_tensor), [2.25, 2.25, 1.0], rtol=1e-15)
    assert top.mass == 1.0
    np.testing.assert_array_equal(top.center_of_mass, [0.0, 0.0, 0.5])


def test_heavy_body_general_offset_matches_parallel_axis():
    rng = np.random.default_rng(7)
    a = rng.normal(size=(3, 3))
    j_c = a @ a.T + 3 * np.eye(3)
    c = rng.normal(size=3)
    body = RigidBody(2.5, j_c, center_of_mass=c)
    top = HeavyRigidBody(body, 2.5, c)  # explicit mass and centre agreeing with the body
    np.testing.assert_allclose(top.inertia_tensor, _steiner(j_c, 2.5, c), rtol=1e-14)


def test_heavy_body_refuses_disagreeing_mass_or_centre():
    body = RigidBody(1.0, [2.0, 2.0, 1.0], center_of_mass=[0.0, 0.0, 0.5])
    with pytest.raises(InvalidInputError, match="`mass` to agree"):
        HeavyRigidBody(body, 2.0)
    with pytest.raises(InvalidInputError, match="`center_of_mass` to agree"):
        HeavyRigidBody(body, 1.0, [0.0, 0.0, 0.4])
    with pytest.raises(InvalidInputError, match="`mass` and `center_of_mass`"):
        HeavyRigidBody([1.0, 1.0, 1.0])


def test_heavy_body_from_rigid_body_moves_as_the_explicit_fixed_point_inertia():
    """Same motion as the same top given by its inertia about O (an independent input)."""
    body = RigidBody(1.0, [2.0, 2.0, 1.0], center_of_mass=[0.0, 0.0, 0.5])
    t = np.linspace(0.0, 1.0, 5)
    a = HeavyRigidBody(body).simulate([1.0, 0, 0, 0], [0.3, 0.0, 5.0], t, max_step=1e-3)
    b = HeavyRigidBody([2.25, 2.25, 1.0], 1.0, [0.0, 0.0, 0.5]).simulate(
        [1.0, 0, 0, 0], [0.3, 0.0, 5.0], t, max_step=1e-3
    )
    np.testing.assert_array_equal(a.quat, b.quat)


@pytest.mark.parametrize("offset", [[0.0, 0.0, 0.0], [0.3, -0.2, 0.5]])
def test_free_body_and_simulate_take_the_inertia_about_the_centre_of_mass(offset):
    """A free body turns about its centre of mass: FreeRigidBody and simulate use J_C
    whatever the body's reference point (their docstrings say so)."""
    body = RigidBody(1.5, [1.0, 2.0, 3.0], center_of_mass=offset)
    w0 = [0.1, 1.0, 0.2]
    t = np.linspace(0.0, 1.0, 5)
    exact = FreeRigidBody(body, omega0=w0).trajectory(t)
    ref = FreeRigidBody([1.0, 2.0, 3.0], omega0=w0).trajectory(t)
    np.testing.assert_array_equal(exact.omega, ref.omega)
    sim = simulate(body, [1.0, 0, 0, 0], w0, t, method="rk4")
    sim_ref = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], w0, t, method="rk4")
    np.testing.assert_array_equal(sim.omega, sim_ref.omega)
