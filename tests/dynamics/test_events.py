"""Events in every integrator (theory §11.1), against closed forms and SciPy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipk

from poinsot.dynamics import (
    Event,
    FreeRigidBody,
    HeavyRigidBody,
    LagrangeTop,
    simulate,
    simulate_particle,
)
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.kinematics import FrameMotion

G = 9.81


def _ground(**kw):
    return Event(lambda t, y: y[..., 2], name="ground", **kw)


def test_projectile_lands_at_the_closed_form_time_and_stops_there():
    v0 = np.array([[3.0, 0.0, 10.0], [1.0, 0.0, 5.0]])
    tr = simulate_particle(FrameMotion(), [0, 0, -G], [0, 0, 0], v0, np.linspace(0, 5, 51),
                           events=_ground(terminal=True, direction=-1))  # fmt: skip
    log = tr.info["events"]
    exact = 2 * v0[:, 2] / G
    np.testing.assert_allclose(log.t_stop, exact, rtol=1e-12)
    np.testing.assert_allclose([log.times(body=b)[0] for b in range(2)], exact, rtol=1e-12)
    # the run goes on to the last stop; a stopped particle is held at its landing point
    assert exact[0] <= tr.t[-1] < exact[0] + 0.1 + 1e-12
    np.testing.assert_allclose(tr.position[-1, 1], [v0[1, 0] * exact[1], 0, 0], atol=1e-12)
    np.testing.assert_allclose(tr.position[-1, 0, 2], 0.0, atol=1e-11)
    # one particle alone: the landing is its last sample
    one = simulate_particle(FrameMotion(), [0, 0, -G], [0, 0, 0], v0[0], np.linspace(0, 5, 51),
                            events=_ground(terminal=True))  # fmt: skip
    assert one.t[-1] == one.info["events"].t_events[0][0]
    assert np.all(np.diff(one.t) > 0) and one.t.size == 22
    np.testing.assert_allclose(one.position[-1], [v0[0, 0] * exact[0], 0, 0], atol=1e-11)


def test_particle_events_match_scipy_solve_ivp_events():
    # a particle in a rotating frame crossing the plane x = 0.3 (both directions)
    frame = FrameMotion(omega=[0, 0, 0.7])

    def plane(t, y):
        return y[..., 0] - 0.3

    t = np.linspace(0, 12, 241)
    tr = simulate_particle(frame, None, [1.0, 0, 0], [0, 0.2, 0], t, rtol=1e-12, atol=1e-14,
                           events=plane)  # fmt: skip
    w = np.array([0, 0, 0.7])

    def rhs(_, y):
        r, v = y[:3], y[3:]
        return np.concatenate([v, -np.cross(w, np.cross(w, r)) - 2 * np.cross(w, v)])

    ref = solve_ivp(rhs, (0, 12), [1, 0, 0, 0, 0.2, 0], method="DOP853", rtol=1e-13,
                    atol=1e-15, events=lambda t, y: y[0] - 0.3)  # fmt: skip
    ours = tr.info["events"].t_events[0]
    assert ours.size == ref.t_events[0].size >= 2
    np.testing.assert_allclose(ours, ref.t_events[0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(tr.info["events"].states("plane")[:, 0], 0.3, atol=1e-11)


@pytest.mark.parametrize("method", ["dop853", "adaptive", "rk4", "midpoint", "splitting"])
def test_racket_flip_times_from_the_exact_free_body(method):
    moments, w0 = [1.0, 2.0, 3.0], [0.1, 4.0, 0.1]
    exact = FreeRigidBody(moments, omega0=w0)
    t = np.linspace(0.0, 10.0, 201)
    if method in ("dop853", "adaptive"):
        kw, tol = {"rtol": 1e-12, "atol": 1e-14}, 1e-9
    else:
        kw, tol = {"max_step": 1e-3}, {"rk4": 1e-9, "midpoint": 1e-5, "splitting": 1e-5}[method]
    flips = Event(lambda t, y: y[..., 4], name="flip")
    tr = simulate(moments, [1, 0, 0, 0], w0, t, method=method, events=flips, **kw)
    got = tr.info["events"].times("flip")

    def w1(s):
        return float(exact.omega(s)[0])

    grid = np.linspace(0, 10, 2001)
    v = exact.omega(grid)[:, 0]
    ref = [brentq(w1, grid[i], grid[i + 1], xtol=1e-15) for i in np.flatnonzero(v[:-1] * v[1:] < 0)]
    assert got.size == len(ref) == 3
    np.testing.assert_allclose(got, ref, rtol=0, atol=tol)
    # the states at the events are the motion's: omega_1 = 0 there
    np.testing.assert_allclose(tr.info["events"].states("flip")[:, 4], 0.0, atol=1e-12)


def test_top_nutation_extremes_at_half_nutation_periods():
    # A = 0.06, C = 0.02 kg m^2 about O, m g l = 0.980665 N m; released from rest at 40 deg:
    # theta is extreme at every half nutation period
    body = HeavyRigidBody([0.06, 0.06, 0.02], 1.0, [0.0, 0.0, 0.1], g=9.80665)
    theta0, spin = math.radians(40.0), 60.0
    top = LagrangeTop(0.06, 0.02, 0.980665, theta=theta0, spin=spin)
    q0 = top.rotation(0.0).as_quat()

    def tilt_rate(t, y):
        # d/dt (e_z . R e_3) = e_z . R (w x e_3): zero at the extremes of theta
        q, w = y[..., :4], y[..., 4:]
        a = np.stack([w[..., 1], -w[..., 0], np.zeros_like(w[..., 0])], axis=-1)
        qw, qv = q[..., :1], q[..., 1:]
        rv = a + 2 * np.cross(qv, np.cross(qv, a) + qw * a)
        return rv[..., 2]

    t = np.linspace(0.0, 2.0, 401)
    tr = body.simulate(q0, [0, 0, spin], t, rtol=1e-12, atol=1e-14, events=tilt_rate)
    got = tr.info["events"].t_events[0]
    half = top.nutation_period / 2
    expected = half * np.arange(1, got.size + 1)
    assert got.size == int(2.0 / half)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)


def test_pendulum_crossings_from_the_exact_period():
    sympy = pytest.importorskip("sympy")
    from poinsot.symbolic import LagrangeSystem

    t_ = sympy.Symbol("t")
    th = sympy.Function("theta")(t_)
    pend = LagrangeSystem([th], th.diff() ** 2 / 2, -G * sympy.cos(th))
    th0 = np.array([[0.3], [2.5]])
    down = Event(lambda t, y: y[..., 0], direction=-1, name="down")
    up = Event(lambda t, y: y[..., 0], direction=1, name="up")
    tr = pend.simulate(th0, np.zeros_like(th0), np.linspace(0, 12, 241), rtol=1e-13,
                       atol=1e-14, events=[down, up])  # fmt: skip
    log = tr.info["events"]
    for b in range(2):
        period = 4 * ellipk(math.sin(th0[b, 0] / 2) ** 2) / math.sqrt(G)
        d, u = log.times("down", b), log.times("up", b)
        np.testing.assert_allclose(d, period / 4 + period * np.arange(d.size), atol=1e-9)
        np.testing.assert_allclose(u, 3 * period / 4 + period * np.arange(u.size), atol=1e-9)
        assert d.size >= 3 and u.size >= 3


def test_terminal_count_stops_at_that_occurrence():
    def bottom(t, y):
        return y[..., 4]

    bottom.terminal = 2  # SciPy's attribute form
    t = np.linspace(0, 10, 201)
    tr = simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0.1, 4.0, 0.1], t, rtol=1e-12, atol=1e-14,
                  events=bottom)  # fmt: skip
    log = tr.info["events"]
    assert len(log) == 2 and tr.t[-1] == log.t[-1] and float(log.t_stop) == log.t[-1]
    # the held state is the event's, and the trajectory's last sample is unit
    np.testing.assert_allclose(tr.omega[-1, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(tr.quat[-1]), 1.0, atol=1e-15)


def test_bad_events_are_refused_by_name():
    t = np.linspace(0, 1, 5)
    with pytest.raises(InvalidTypeError, match="events"):
        simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0, 0, 1.0], t, events=3)
    with pytest.raises(InvalidInputError, match="terminal"):
        Event(lambda t, y: 0.0, terminal=-1)
    with pytest.raises(InvalidInputError, match="distinct names"):
        simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0, 0, 1.0], t,
                 events=[Event(lambda t, y: y[..., 0], name="a")] * 2)  # fmt: skip
    log = simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [[0, 0, 1.0]] * 2, t,
                   events=Event(lambda t, y: y[..., 0] - 2, name="a")).info["events"]  # fmt: skip
    with pytest.raises(InvalidInputError, match="body"):
        log.times("a")
    with pytest.raises(InvalidInputError, match="event"):
        log.times("b", 0)
