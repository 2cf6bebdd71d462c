"""Impacts on a plane (theory §11.3): balance laws, the (1 - e^2) energy formula, stick
and slide against hand-derived closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from poinsot.dynamics.impacts import particle_impact, rigid_impact
from poinsot.errors import InvalidInputError
from poinsot.rotations import Rotation


def _skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _case(seed):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 3.0, 3)  # A + B >= C
    mass = rng.uniform(0.5, 4.0)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    r = rng.normal(size=3) * 0.5
    r[2] = -abs(r[2]) - 0.2  # the contact point below the centre of mass
    v = rng.normal(size=3)
    w = rng.normal(size=3) * 2
    rot = Rotation.from_quat(q).as_matrix()
    u_n = v[2] + np.cross(rot @ w, r)[2]
    if u_n >= -0.1:  # make it approach
        v[2] -= u_n + 0.5
    return moments, mass, q, v, w, r, rot


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("law", ["newton", "poisson"])
@pytest.mark.parametrize("mu", [0.0, 0.1, 0.5, 5.0])
def test_momentum_and_angular_momentum_about_the_contact_point(seed, law, mu):
    moments, m, q, v, w, r, rot = _case(seed)
    e = 0.6
    out = rigid_impact(moments, m, q, v, w, r, restitution=e, friction=mu, law=law)
    js = rot @ np.diag(moments) @ rot.T
    # linear momentum: m (v+ - v-) = P
    np.testing.assert_allclose(m * (out.velocity - v), out.impulse, atol=1e-12)
    # angular momentum about the contact point A, J w + (C - A) x m v = J w - r x m v
    k_before = js @ rot @ w - np.cross(r, m * v)
    k_after = js @ rot @ out.omega - np.cross(r, m * out.velocity)
    np.testing.assert_allclose(k_after, k_before, atol=1e-11 * (1 + np.abs(k_before).max()))
    # Coulomb's cone and a non-negative normal impulse
    pn = out.impulse[2]
    assert pn > 0 and np.hypot(*out.impulse[:2]) <= mu * pn * (1 + 1e-9) + 1e-12
    # the contact leaves the plane (or slides on it), never into it
    u_after = out.velocity + np.cross(rot @ out.omega, r)
    np.testing.assert_allclose(out.contact_velocity[1], u_after, atol=1e-11)
    assert u_after[2] >= -1e-12
    if law == "newton" or mu == 0.0:
        np.testing.assert_allclose(u_after[2], -e * out.contact_velocity[0, 2], atol=1e-11)
    if law == "poisson":  # Poisson's impacts never create energy
        assert out.energy_loss >= -1e-12


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_smooth_impacts_lose_one_minus_e_squared(seed, e):
    moments, m, q, v, w, r, rot = _case(seed)
    js = rot @ np.diag(moments) @ rot.T
    # K = E/m - [r]x J^-1 [r]x, written out here independently of the library's
    k = np.eye(3) / m - _skew(r) @ np.linalg.inv(js) @ _skew(r)
    n = np.array([0.0, 0.0, 1.0])
    u_n = v[2] + np.cross(rot @ w, r)[2]
    out = rigid_impact(moments, m, q, v, w, r, restitution=e)
    expected = (1 - e**2) * u_n**2 / (2 * n @ k @ n)
    t = 0.5 * m * v @ v + 0.5 * (rot @ w) @ js @ (rot @ w)
    np.testing.assert_allclose(out.energy_loss, expected, rtol=1e-10, atol=1e-12 * t)
    assert out.mode == "frictionless"
    # and Newton's and Poisson's laws agree without friction
    other = rigid_impact(moments, m, q, v, w, r, restitution=e, law="poisson")
    np.testing.assert_allclose(other.impulse, out.impulse, atol=1e-12)


def test_ball_with_backspin_grips_and_rolls_back():
    # solid ball R = 0.1 m, m = 0.2 kg: J = 2/5 m R^2; the slip stops during the impact,
    # then v_x+ = (5 v_x + 2 R w_y) / 7 and the ball rolls (u_t+ = 0), w_y+ = v_x+ / R
    m, radius = 0.2, 0.1
    j = 0.4 * m * radius**2
    vx, vz, wy = 1.0, -4.0, -40.0
    out = rigid_impact([j] * 3, m, [1, 0, 0, 0], [vx, 0, vz], [0, wy, 0], [0, 0, -radius],
                       restitution=0.7, friction=0.6)  # fmt: skip
    vx1 = (5 * vx + 2 * radius * wy) / 7
    assert out.mode == "slide-stick" and vx1 < 0 < vx  # it comes back
    np.testing.assert_allclose(out.velocity, [vx1, 0, 0.7 * 4.0], atol=1e-10)
    np.testing.assert_allclose(out.omega, [0, vx1 / radius, 0], atol=1e-9)


def test_topspin_ball_that_slides_throughout():
    # small mu: sliding all through, P_t = -mu P_n, P_n = (1 + e) m |v_z| (2D: exact)
    m, radius, e, mu = 0.2, 0.1, 0.8, 0.05
    j = 0.4 * m * radius**2
    out = rigid_impact([j] * 3, m, [1, 0, 0, 0], [2.0, 0, -3.0], [0, -30.0, 0],
                       [0, 0, -radius], restitution=e, friction=mu)  # fmt: skip
    pn = (1 + e) * m * 3.0
    assert out.mode == "slide"
    np.testing.assert_allclose(out.impulse, [-mu * pn, 0, pn], rtol=1e-12)
    np.testing.assert_allclose(out.omega[1], -30.0 + radius * mu * pn / j, rtol=1e-12)


def test_particle_impacts():
    out = particle_impact([3.0, 0.0, -4.0], restitution=0.5, friction=0.2, mass=2.0)
    # P_n = (1 + e) m |v_n| = 12 N s; the tangential speed drops by mu P_n / m = 1.2 m/s
    np.testing.assert_allclose(out.velocity, [1.8, 0.0, 2.0], atol=1e-14)
    np.testing.assert_allclose(out.impulse, [-2.4, 0.0, 12.0], atol=1e-13)
    assert out.mode == "slide"
    grip = particle_impact([1.0, 1.0, -4.0], restitution=0.0, friction=1.0)
    assert grip.mode == "slide-stick" and np.allclose(grip.velocity, 0.0)
    smooth = particle_impact([1.0, 0.0, -2.0], restitution=0.3)
    np.testing.assert_allclose(smooth.energy_loss, 0.5 * (1 - 0.3**2) * 4.0, rtol=1e-14)


def test_bad_impacts_are_refused_by_name():
    with pytest.raises(InvalidInputError, match="restitution"):
        particle_impact([0, 0, -1.0], restitution=1.5)
    with pytest.raises(InvalidInputError, match="approach"):
        particle_impact([0, 0, 1.0])
    with pytest.raises(InvalidInputError, match="law"):
        rigid_impact([1, 1, 1.0], 1.0, [1, 0, 0, 0], [0, 0, -1.0], [0, 0, 0], [0, 0, -1.0],
                     law="routh")  # fmt: skip
    with pytest.raises(InvalidInputError, match="friction"):
        rigid_impact([1, 1, 1.0], 1.0, [1, 0, 0, 0], [0, 0, -1.0], [0, 0, 0], [0, 0, -1.0],
                     friction=-0.1)  # fmt: skip
    with pytest.raises(InvalidInputError, match="normal"):
        particle_impact([0, 0, -1.0], normal=[0, 0, 0])


def test_ball_with_backspin_bounces_at_the_closed_form_times():
    from poinsot.dynamics import simulate_bounces
    from poinsot.mass import RigidBody

    m, radius, e, g = 0.2, 0.1, 0.5, 9.80665
    ball = RigidBody.sphere(m, radius)
    tr = simulate_bounces(ball, [0, 0, 1.0], [1.0, 0, 0], [1, 0, 0, 0], [0, -60.0, 0],
                          np.linspace(0, 2, 201), radius=radius, restitution=e,
                          friction=0.5, g=g)  # fmt: skip
    t1 = np.sqrt(2 * (1.0 - radius) / g)
    v1 = g * t1
    hits = tr.info["events"].times("impact")
    expected = t1 + np.concatenate([[0.0], np.cumsum(2 * v1 * e ** np.arange(1, 6) / g)])
    np.testing.assert_allclose(hits[:6], expected, atol=1e-12)
    first = tr.info["impacts"][0]
    vx1 = (5 * 1.0 + 2 * radius * -60.0) / 7  # grips: rolls back
    np.testing.assert_allclose(first.velocity, [vx1, 0, e * v1], atol=1e-9)
    # it rests at the accumulation of the bounces (the last rebound below rest_speed)
    assert tr.info["stopped"] and abs(tr.t[-1] - t1 * (1 + e) / (1 - e)) < 1e-3


@pytest.mark.parametrize("law", ["newton", "poisson"])
def test_tumbling_box_never_enters_the_floor_and_loses_energy_only_at_impacts(law):
    from poinsot.dynamics import simulate_bounces
    from poinsot.mass import RigidBody

    a, b, c, m, g = 0.3, 0.2, 0.1, 1.0, 9.80665
    box = RigidBody.box(m, a, b, c)
    corners = np.array([[sx * a / 2, sy * b / 2, sz * c / 2]
                        for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])  # fmt: skip
    q0 = np.array([0.9, 0.3, 0.2, 0.1]) / np.linalg.norm([0.9, 0.3, 0.2, 0.1])
    tr = simulate_bounces(box, [0, 0, 1.0], [0.5, 0, 0], q0, [3.0, 5.0, 1.0],
                          np.linspace(0, 3, 1501), corners=corners, friction=0.3,
                          restitution=0.5, law=law, g=g)  # fmt: skip
    log = tr.info["events"]
    assert len(log) >= 5
    # no corner below the floor at any sample; the impacting corner at 0 at each impact
    low = tr.position[:, None, 2] + tr.rotation[:, None].apply(corners)[..., 2]
    assert low.min() > -1e-9
    for state in log.state:
        z = state[2] + Rotation.from_quat(state[6:10]).apply(corners)[:, 2]
        assert abs(z.min()) < 1e-10
    # mechanical energy: constant in flight (exact), never up at an impact
    end = -1 if tr.info["stopped"] else None  # the last sample is then after an impact
    energy = (tr.energy + m * g * tr.position[:, 2])[:end]
    seg = np.searchsorted(log.t, tr.t[:end], side="left")
    for k in np.unique(seg):
        part = energy[seg == k]
        np.testing.assert_allclose(part, part[0], rtol=1e-12, atol=1e-12)
    if law == "poisson":
        assert all(out.energy_loss >= -1e-12 for out in tr.info["impacts"])
    # the angular momentum about the centre of mass is constant in flight
    for k in np.unique(seg):
        mom = tr.momentum[:end][seg == k]
        np.testing.assert_allclose(mom, np.broadcast_to(mom[0], mom.shape), atol=1e-11)
