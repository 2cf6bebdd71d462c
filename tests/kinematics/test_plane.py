"""Plane motion (theory §6): the centres of velocities and accelerations have zero
velocity / acceleration by the fields v_B = v_A + w k x AB, a_B = a_A + e k x AB - w^2 AB
(computed here independently); the rolling wheel's contact point, its centre at
constant speed, and its centrodes (the ground and the rim)."""

import numpy as np
import pytest

from poinsot.errors import InvalidInputError
from poinsot.kinematics import acceleration_center, centrodes, velocity_center

RNG = np.random.default_rng(9)


def _perp(v):
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def test_centres_have_zero_velocity_and_acceleration():
    a, v, acc = RNG.normal(size=(3, 50, 2))
    w, e = RNG.normal(size=(2, 50))
    p = velocity_center(a, v, w)
    np.testing.assert_allclose(v + w[:, None] * _perp(p - a), 0.0, atol=1e-12)
    q = acceleration_center(a, acc, w, e)
    r = q - a
    np.testing.assert_allclose(acc + e[:, None] * _perp(r) - (w * w)[:, None] * r, 0.0,
                               atol=1e-11)  # fmt: skip


def test_rolling_wheel():
    """Radius 0.3 m, angle th(t) = 2 t + 0.5 t^2 clockwise: centre (0.3 th, 0.3)."""
    rho, t = 0.3, np.linspace(0.0, 2.0, 9)
    th, thd, thdd = 2 * t + 0.5 * t * t, 2 + t, np.ones_like(t)
    centre = np.stack([rho * th, np.full_like(t, rho)], -1)
    v_c = np.stack([rho * thd, 0 * t], -1)
    a_c = np.stack([rho * thdd, 0 * t], -1)
    contact = np.stack([rho * th, 0 * t], -1)
    np.testing.assert_allclose(velocity_center(centre, v_c, -thd), contact, atol=1e-15)
    # at constant speed the centre of the wheel is the centre of accelerations
    np.testing.assert_allclose(acceleration_center(centre, 0 * a_c, -thd, 0.0), centre, atol=0)
    # accelerating: Q is where a_Q = 0 (closed form of the test above)
    q = acceleration_center(centre, a_c, -thd, -thdd)
    r = q - centre
    np.testing.assert_allclose(a_c - thdd[:, None] * _perp(r) - (thd**2)[:, None] * r, 0.0,
                               atol=1e-14)  # fmt: skip
    c = centrodes(centre, v_c, -th, -thd)
    np.testing.assert_allclose(c.fixed, contact, atol=1e-15)  # the ground
    np.testing.assert_allclose(np.linalg.norm(c.moving, axis=-1), rho, rtol=1e-14)  # the rim
    ang = np.unwrap(np.arctan2(c.moving[:, 1], c.moving[:, 0]))
    np.testing.assert_allclose(ang - ang[0], th - th[0], atol=1e-13)  # rim point turns with th


def test_translation_has_its_centre_at_infinity_and_bad_input_is_named():
    assert np.all(np.isinf(velocity_center([0.0, 0.0], [1.0, 0.0], 0.0))[1])
    with pytest.raises(InvalidInputError, match="velocity"):
        velocity_center([0.0, 0.0], [1.0, 0.0, 0.0], 1.0)
