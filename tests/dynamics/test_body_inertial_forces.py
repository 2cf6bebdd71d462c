"""Inertial forces over a whole rigid body (theory §9): the tensor formulas against the
direct sum of the particle inertial forces over a cloud of point masses (the body's
mass, centre and inertia from RigidBody.from_points: an independent route), and the
course's rotating rod (R^e = -m w x (w x r_c); M_O^e not r_c x R^e when inclined)."""

import numpy as np
import pytest

from poinsot.dynamics import body_inertial_forces, inertial_forces
from poinsot.errors import InvalidTypeError
from poinsot.kinematics import FrameMotion
from poinsot.mass import RigidBody

RNG = np.random.default_rng(12)


def test_tensor_formulas_equal_the_sum_over_points():
    m = RNG.uniform(0.5, 2.0, 12)
    x = RNG.normal(size=(12, 3)) + [1.0, -0.5, 0.3]
    body = RigidBody.from_points(m, x)
    frame = FrameMotion(omega=RNG.normal(size=3), eps=RNG.normal(size=3),
                        origin_acceleration=RNG.normal(size=3))  # fmt: skip
    u, big_w = RNG.normal(size=(2, 3))
    rc = body.center_of_mass
    v_r = u + np.cross(big_w, x - rc)  # relative velocity of each point of the body
    pts = inertial_forces(frame, x, v_r, mass=m)
    f = body_inertial_forces(frame, body, velocity=u, angular_velocity=big_w)
    np.testing.assert_allclose(f.transport_force, pts.transport.sum(0), atol=1e-12)
    np.testing.assert_allclose(f.coriolis_force, pts.coriolis.sum(0), atol=1e-12)
    np.testing.assert_allclose(f.transport_moment, np.cross(x, pts.transport).sum(0), atol=1e-11)
    np.testing.assert_allclose(f.coriolis_moment, np.cross(x, pts.coriolis).sum(0), atol=1e-11)
    p = RNG.normal(size=3)
    np.testing.assert_allclose(f.moment_about(p), np.cross(x - p, pts.total).sum(0), atol=1e-11)


def test_rotating_inclined_rod():
    """A thin rod (mass m, length L) from O at 30 degrees to the axis of rotation z: the
    resultant is -m w x (w x r_c), but its moment about O is -w x J_O w, not r_c x R^e."""
    m, length, w = 2.0, 1.5, 3.0
    d = np.array([np.sin(np.pi / 6), 0.0, np.cos(np.pi / 6)])
    rc = 0.5 * length * d
    j_c = m * length**2 / 12 * (np.eye(3) - np.outer(d, d))
    rod = RigidBody(m, j_c, center_of_mass=rc)
    f = body_inertial_forces(FrameMotion(omega=[0.0, 0.0, w]), rod)
    om = np.array([0.0, 0.0, w])
    np.testing.assert_allclose(f.transport_force, -m * np.cross(om, np.cross(om, rc)), atol=1e-14)
    # J_O of the rod about its end: m L^2 / 3 (E - d d^T)
    j_o = m * length**2 / 3 * (np.eye(3) - np.outer(d, d))
    np.testing.assert_allclose(f.transport_moment, -np.cross(om, j_o @ om), atol=1e-13)
    assert np.linalg.norm(f.transport_moment - np.cross(rc, f.transport_force)) > 0.1


def test_body_must_be_one_rigid_body():
    with pytest.raises(InvalidTypeError, match="RigidBody"):
        body_inertial_forces(FrameMotion(omega=[0, 0, 1.0]), [1.0, 2.0, 3.0])
