"""LagrangeSystem.simulate_unilateral (theory §11.2, §11.3): unilateral constraints in
generalized coordinates against the same closed forms as the particle's."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy
from scipy.integrate import quad

from poinsot.errors import InvalidInputError
from poinsot.symbolic import LagrangeSystem

G = 9.81
T_ = sympy.Symbol("t")


def _polar(potential_sign):
    r, th = sympy.Function("r")(T_), sympy.Function("theta")(T_)
    kinetic = (r.diff() ** 2 + r**2 * th.diff() ** 2) / 2
    return r, th, LagrangeSystem([r, th], kinetic, potential_sign * G * r * sympy.cos(th))


def test_string_goes_slack_at_120_degrees_and_catches_at_the_bottom():
    r, th, pend = _polar(-1)  # theta from the downward vertical: V = -g r cos(theta)
    v0 = math.sqrt(3.5 * G)
    tr = pend.simulate_unilateral(r - 1, [1.0, 0.0], [0.0, v0], np.linspace(0, 2, 401))
    log = tr.info["events"]
    (t_slack,) = log.times("leave")
    np.testing.assert_allclose(log.states("leave")[0, :2], [1.0, 2 * math.pi / 3], atol=1e-9)
    t_up = quad(lambda a: 1 / math.sqrt(v0**2 - 2 * G * (1 - math.cos(a))), 0, 2 * math.pi / 3,
                epsabs=1e-13, epsrel=1e-13)[0]  # fmt: skip
    assert t_slack == pytest.approx(t_up, abs=1e-8)
    (t_hit,) = log.times("impact")
    speed = math.sqrt(0.5 * G)
    t_catch = t_slack + math.sin(2 * math.pi / 3) / (speed * 0.5)
    assert t_hit == pytest.approx(t_catch, abs=1e-9)
    q_hit = log.states("impact")[0]
    np.testing.assert_allclose([q_hit[0], math.remainder(q_hit[1], 2 * math.pi)], [1.0, 0.0],
                               atol=1e-9)  # fmt: skip
    # tension (lambda < 0 pushes into r < 1) while taut, zero while slack
    taut = tr.t < t_slack
    assert np.all(tr.multipliers[taut, 0] < 0) and np.all(
        tr.multipliers[~taut & (tr.t < t_hit)] == 0
    )
    # T = m (v^2 / L + g cos(theta)) on the string: lambda = -T
    th_ = tr.q[taut, 1]
    v2 = v0**2 - 2 * G * (1 - np.cos(th_))
    np.testing.assert_allclose(-tr.multipliers[taut, 0], v2 + G * np.cos(th_), rtol=1e-8)


def test_leaving_a_dome_in_polar_coordinates():
    r, th, dome = _polar(+1)  # theta from the upward vertical: V = g r cos(theta)
    v0 = 0.5
    tr = dome.simulate_unilateral(1 - r, [1.0, 0.0], [0.0, v0], np.linspace(0, 3, 301))
    leave = tr.info["events"].states("leave")
    assert leave.shape == (1, 4)
    assert math.cos(leave[0, 1]) == pytest.approx((2 + v0**2 / G) / 3, abs=1e-9)


def test_bouncing_coordinate_comes_to_rest_at_the_zeno_time():
    z = sympy.Function("z")(T_)
    ball = LagrangeSystem([z], z.diff() ** 2 / 2, G * z)
    e, h = 0.5, 1.0
    tr = ball.simulate_unilateral(-z, [h], [0.0], np.linspace(0, 2, 201), restitution=e)
    log = tr.info["events"]
    t1 = math.sqrt(2 * h / G)
    hits = log.times("impact")
    expected = t1 + np.concatenate([[0.0], np.cumsum(2 * G * t1 * e ** np.arange(1, 4) / G)])
    np.testing.assert_allclose(hits[:4], expected, atol=1e-10)
    assert log.times("land")[0] == pytest.approx(t1 * (1 + e) / (1 - e), abs=1e-6)
    rest = tr.t > log.times("land")[0]
    np.testing.assert_allclose(tr.multipliers[rest, 0], -G, rtol=1e-12)  # the floor holds m g


def test_bad_unilateral_constraints():
    z = sympy.Function("z")(T_)
    ball = LagrangeSystem([z], z.diff() ** 2 / 2, G * z)
    with pytest.raises(InvalidInputError, match="constraint"):
        ball.simulate_unilateral(z.diff(), [1.0], [0.0], [0, 1.0])
    with pytest.raises(InvalidInputError, match="q0"):
        ball.simulate_unilateral(-z, [-1.0], [0.0], [0, 1.0])
    with pytest.raises(InvalidInputError, match="restitution"):
        ball.simulate_unilateral(-z, [1.0], [0.0], [0, 1.0], restitution=-1)


def test_bead_against_the_wall_of_a_spinning_hoop():
    # a bead inside a circular channel of radius R spinning at Omega about its vertical
    # diameter, pressed on the wall (r <= R) by the centrifugal force: on the wall it
    # is the classic bead on a rotating hoop, theta'' = sin(theta) (Omega^2 cos(theta) -
    # g / R), equilibrium cos(theta*) = g / (R Omega^2), the wall pushing with m R Omega^2
    # there and small oscillations at Omega sin(theta*)
    R, omega = 0.5, 7.0
    r, th = sympy.Function("r")(T_), sympy.Function("theta")(T_)
    kinetic = (r.diff() ** 2 + r**2 * th.diff() ** 2 + omega**2 * r**2 * sympy.sin(th) ** 2) / 2
    bead = LagrangeSystem([r, th], kinetic, -G * r * sympy.cos(th))
    eq = math.acos(G / (R * omega**2))
    w_small = omega * math.sin(eq)
    t = np.linspace(0, 4 * 2 * math.pi / w_small, 801)
    amp = 1e-4
    tr = bead.simulate_unilateral(r - R, [R, eq + amp], [0.0, 0.0], t)
    assert len(tr.info["events"]) == 0 and np.all(tr.q[:, 0] == pytest.approx(R, abs=1e-12))
    np.testing.assert_allclose(tr.q[:, 1] - eq, amp * np.cos(w_small * t), atol=6e-8)
    np.testing.assert_allclose(tr.multipliers[:, 0], -R * omega**2, rtol=1e-3)
    # too slow a spin near the top: the wall stops pushing and the bead falls off it
    slow = bead.simulate_unilateral(r - R, [R, 2.6], [0.0, 0.0], np.linspace(0, 1, 101))
    assert slow.info["events"].times("leave").size == 1
