"""Unilateral constraints (theory §11.2) against closed forms: the particle leaving a
smooth sphere, a ball bouncing to rest, a pendulum whose string goes slack."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from poinsot.dynamics import Plane, Sphere, simulate_unilateral
from poinsot.errors import InvalidInputError, InvalidTypeError

G = 9.81


@pytest.mark.parametrize("v0", [1e-3, 0.5, 1.5])
def test_particle_leaves_a_smooth_sphere_where_the_reaction_vanishes(v0):
    radius, m = 2.0, 0.3
    t = np.linspace(0, 6, 1201)
    tr = simulate_unilateral(Sphere(radius=radius), [0, 0, -m * G], [0, 0, radius], [v0, 0, 0],
                             t, mass=m)  # fmt: skip
    leave = tr.info["events"].states("leave")
    assert leave.shape == (1, 6)
    cos_leave = (2 + v0**2 / (G * radius)) / 3  # cos(theta) = 2/3 from rest
    np.testing.assert_allclose(leave[0, 2] / radius, cos_leave, atol=1e-10)
    # the time it takes, from energy: theta' = sqrt(v0^2 + 2 g R (1 - cos)) / R
    t_leave = quad(lambda th: radius / math.sqrt(v0**2 + 2 * G * radius * (1 - math.cos(th))),
                   0, math.acos(cos_leave), epsabs=1e-11, epsrel=1e-11, limit=500,
                   points=[1e-4, 1e-2])[0]  # fmt: skip
    np.testing.assert_allclose(tr.info["events"].times("leave"), [t_leave], atol=1e-8)
    # the reaction on the sphere: N = m (g cos - v^2 / R), along the outward radius
    on = tr.in_contact
    assert on[0] and not on[-1]
    r = tr.position[on]
    cos = r[:, 2] / radius
    speed2 = v0**2 + 2 * G * radius * (1 - cos)
    n_exact = m * (G * cos - speed2 / radius)
    np.testing.assert_allclose(np.sum(tr.reaction[on] * r, axis=1) / radius, n_exact, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(r, axis=1), radius, atol=1e-9)
    # then a parabola from the leaving state
    fly = ~on & (t > t_leave)
    dt = t[fly] - t_leave
    parabola = leave[0, :3] + leave[0, 3:] * dt[:, None] - [0, 0, G / 2] * dt[:, None] ** 2
    np.testing.assert_allclose(tr.position[fly], parabola, atol=1e-9)
    assert np.all(tr.reaction[fly] == 0.0)


def test_ball_bounces_to_rest_at_the_zeno_time():
    h, e = 1.0, 0.5
    tr = simulate_unilateral(Plane(), [0, 0, -G], [0, 0, h], [0, 0, 0],
                             np.linspace(0, 2, 401), restitution=e)  # fmt: skip
    log = tr.info["events"]
    t1 = math.sqrt(2 * h / G)
    v1 = G * t1
    impacts = log.times("impact")
    expected = t1 + np.concatenate([[0.0], np.cumsum(2 * v1 * e ** np.arange(1, 6) / G)])
    np.testing.assert_allclose(impacts[:6], expected, atol=1e-10)
    # apex heights e^(2k) h
    apex = tr.position[(tr.t > impacts[0]) & (tr.t < impacts[1]), 2].max()
    assert apex == pytest.approx(e**2 * h, abs=2e-3)  # sampled every 5 ms
    # the bounces accumulate at t1 (1 + e) / (1 - e); it rests there on a reaction m g
    (land,) = log.times("land")
    assert land == pytest.approx(t1 * (1 + e) / (1 - e), abs=1e-6)
    rest = tr.t > land
    np.testing.assert_allclose(tr.reaction[rest], [[0, 0, G]] * rest.sum(), atol=1e-12)
    np.testing.assert_allclose(tr.position[rest, 2], 0.0, atol=1e-12)
    assert tr.channels()["reaction"].units == "N"


def test_pendulum_string_goes_slack_and_catches_at_the_bottom():
    # v0^2 = 3.5 g L: the tension vanishes at 120 degrees from the bottom, and the
    # parabola from there passes through the lowest point (a textbook closed form)
    length = 1.0
    v0 = math.sqrt(3.5 * G * length)
    string = Sphere(radius=length, side="inside")
    tr = simulate_unilateral(string, [0, 0, -G], [0, 0, -length], [v0, 0, 0],
                             np.linspace(0, 2.5, 501))  # fmt: skip
    log = tr.info["events"]
    (t_slack,) = log.times("leave")
    slack = log.states("leave")[0]
    theta = math.radians(120)
    np.testing.assert_allclose(slack[:3], length * np.array([math.sin(theta), 0, -math.cos(theta)]),
                               atol=1e-9)  # fmt: skip
    t_up = quad(lambda th: length / math.sqrt(v0**2 - 2 * G * length * (1 - math.cos(th))),
                0, theta, epsabs=1e-13, epsrel=1e-13)[0]  # fmt: skip
    assert t_slack == pytest.approx(t_up, abs=1e-8)
    speed = math.sqrt(0.5 * G * length)
    t_catch = t_slack + math.sin(theta) * length / (speed * -math.cos(theta))
    (t_hit,) = log.times("impact")
    assert t_hit == pytest.approx(t_catch, abs=1e-9)
    np.testing.assert_allclose(log.states("impact")[0, :3], [0, 0, -length], atol=1e-9)
    # the jerk of the string (e = 0) keeps only the tangential velocity; it swings on
    assert log.times("land")[0] == t_hit
    after = tr.t > t_hit
    np.testing.assert_allclose(np.linalg.norm(tr.position[after], axis=1), length, atol=1e-9)
    assert np.all(tr.in_contact[after])


def test_bad_unilateral_inputs():
    with pytest.raises(InvalidTypeError, match="surface"):
        simulate_unilateral("plane", None, [0, 0, 1.0], [0, 0, 0], [0, 1.0])
    with pytest.raises(InvalidInputError, match="position0"):
        simulate_unilateral(Plane(), None, [0, 0, -1.0], [0, 0, 0], [0, 1.0])
    with pytest.raises(InvalidInputError, match="restitution"):
        simulate_unilateral(Plane(), None, [0, 0, 1.0], [0, 0, 0], [0, 1.0], restitution=2)
    with pytest.raises(InvalidInputError, match="side"):
        Sphere(radius=1.0, side="above")
