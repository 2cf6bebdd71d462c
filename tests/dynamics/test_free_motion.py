"""Six degrees of freedom (theory §9, §10): a spinning body thrown in uniform gravity
follows the parabola exactly (centre of mass) and turns as the exact Euler-Poinsot
motion; a force off the centre of mass gives the torque p x F; a force through the
centre none."""

import numpy as np
import pytest

from poinsot import PoseTrajectory, compare
from poinsot.dynamics import FreeRigidBody, simulate_free_motion
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.mass import RigidBody

BOX = RigidBody.box(2.0, 0.4, 0.25, 0.1)
G = np.array([0.0, 0.0, -9.81])


def test_thrown_spinning_box_parabola_and_euler_poinsot():
    t = np.linspace(0.0, 2.0, 41)
    r0, v0, w0 = np.array([1.0, 2.0, 0.0]), np.array([3.0, -1.0, 8.0]), np.array([0.3, 6.0, 0.2])
    tr = simulate_free_motion(BOX, r0, v0, [1.0, 0, 0, 0], w0, t, force=2.0 * G,
                              rtol=1e-12, atol=1e-14)  # fmt: skip
    assert isinstance(tr, PoseTrajectory)
    parabola = r0 + v0 * t[:, None] + 0.5 * G * t[:, None] ** 2
    np.testing.assert_allclose(tr.position, parabola, atol=1e-11)
    np.testing.assert_allclose(tr.velocity, v0 + G * t[:, None], atol=1e-11)
    exact = FreeRigidBody(BOX, omega0=w0).trajectory(t)
    ang = (exact.rotation.inv() * tr.rotation).magnitude()
    assert np.max(ang) < 1e-9  # observed ~1e-11 at rtol 1e-12
    np.testing.assert_allclose(tr.omega, exact.omega, atol=1e-9)
    assert np.ptp(tr.energy - 2.0 * G @ np.zeros(3)) > 0  # kinetic energy changes (gravity)


def test_force_off_the_centre_of_mass_gives_the_torque_p_x_f():
    """A sphere (J = I E) at rest, a constant space force F at the body point p:
    w' = p x F / I at the start, so w(t) ~ (p x F) t / I for small t, and the centre
    of mass accelerates as F/m whatever the point."""
    ball = RigidBody.sphere(3.0, 0.5)
    i = float(ball.inertia[0, 0])
    f, p = np.array([0.0, 2.0, 0.0]), np.array([0.5, 0.0, 0.0])
    t = np.array([0.0, 1e-3])
    tr = simulate_free_motion(ball, [0, 0, 0], [0, 0, 0], [1.0, 0, 0, 0], [0, 0, 0], t,
                              point_forces=[(f, p)], rtol=1e-12, atol=1e-16)  # fmt: skip
    np.testing.assert_allclose(tr.omega[-1], np.cross(p, f) * t[-1] / i, rtol=1e-6)
    np.testing.assert_allclose(tr.velocity[-1], f / 3.0 * t[-1], rtol=1e-9)
    through = simulate_free_motion(ball, [0, 0, 0], [0, 0, 0], [1.0, 0, 0, 0], [0, 0, 0],
                                   t, point_forces=[(f, [0.0, 0.3, 0.0])])  # fmt: skip
    np.testing.assert_allclose(through.omega, 0.0, atol=1e-15)


def test_compare_and_bad_inputs():
    t = np.linspace(0.0, 0.5, 6)
    a = simulate_free_motion(BOX, [0, 0, 0], [1.0, 0, 0], [1.0, 0, 0, 0], [0, 1.0, 0], t)
    c = compare(a, a)
    assert c.names() == ("position", "velocity", "attitude", "omega")
    with pytest.raises(InvalidTypeError, match="RigidBody"):
        simulate_free_motion([1.0, 2, 3], [0, 0, 0], [0, 0, 0], [1.0, 0, 0, 0], [0, 0, 0], t)
    with pytest.raises(InvalidInputError, match="point_forces"):
        simulate_free_motion(BOX, [0, 0, 0], [0, 0, 0], [1.0, 0, 0, 0], [0, 0, 0], t,
                             point_forces=[[1.0, 2.0, 3.0]])  # fmt: skip
