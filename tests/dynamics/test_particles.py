"""Particles in moving frames (theory §9): inertial forces, relative motion, the Earth.

Truths used: the inertial forces are -m times the transport and Coriolis
accelerations of poinsot.kinematics.point_motion (Rivals' formula, checked
separately) and also a hand-written expansion; a free particle moves on a straight
line at constant speed in the inertial frame; the Coriolis force does no work;
Jacobi's integral; the first-order eastward deflection (1/3) Omega g t^3 cos(lat)
whose relative error is O((Omega t)^2); the Foucault rate -Omega sin(lat);
WGS 84 normal gravity at the equator and pole (NIMA TR8350.2).
"""

from __future__ import annotations

import numpy as np
import pytest

from poinsot.dynamics import (
    EARTH_ROTATION_RATE,
    earth_frame,
    eastward_deflection,
    foucault_pendulum,
    foucault_period,
    foucault_precession_rate,
    inertial_forces,
    jacobi_integral,
    normal_gravity,
    simulate_particle,
    swing_plane_angles,
)
from poinsot.errors import IntegrationError, InvalidInputError, InvalidTypeError
from poinsot.kinematics import FrameMotion, point_motion

RNG = np.random.default_rng(12)


def _frame():
    return FrameMotion(
        origin_acceleration=[0.3, -0.1, 0.2], omega=[0.4, -0.7, 1.1], eps=[0.05, 0.2, -0.3]
    )


@pytest.mark.parametrize("shape", [(), (1,), (5, 3)])
def test_inertial_forces_match_point_motion_and_hand_expansion(shape):
    fr = _frame()
    r = RNG.standard_normal(shape + (3,))
    v = RNG.standard_normal(shape + (3,))
    m = RNG.uniform(0.5, 2.0, shape)
    f = inertial_forces(fr, r, v, mass=m)
    pm = point_motion(fr, r, v)
    mm = np.asarray(m)[..., None]
    np.testing.assert_allclose(f.origin, -mm * pm.origin_acceleration, atol=1e-14)
    np.testing.assert_allclose(f.euler, -mm * pm.rotational_acceleration, atol=1e-14)
    np.testing.assert_allclose(f.centrifugal, -mm * pm.centripetal_acceleration, atol=1e-14)
    np.testing.assert_allclose(f.coriolis, -mm * pm.coriolis_acceleration, atol=1e-14)
    np.testing.assert_allclose(f.transport, f.origin + f.euler + f.centrifugal, atol=1e-14)
    # independent expansion: w x (w x r) = w (w.r) - r |w|^2
    w = fr.omega
    cen = -mm * (w * np.sum(w * r, -1, keepdims=True) - r * np.dot(w, w))
    np.testing.assert_allclose(f.centrifugal, cen, atol=1e-13)
    assert f.total.shape == shape + (3,)


def test_coriolis_power_is_zero_and_centrifugal_points_outwards():
    fr = earth_frame(0.7, omega=0.5)
    r = RNG.standard_normal((200, 3))
    v = RNG.standard_normal((200, 3))
    f = inertial_forces(fr, r, v, mass=3.0)
    power = np.sum(f.coriolis * v, -1)
    assert np.max(np.abs(power)) <= 1e-15 * np.max(np.abs(f.coriolis) * np.abs(v)) * 10
    # centrifugal is perpendicular to w and points away from the axis
    w = fr.omega / np.linalg.norm(fr.omega)
    assert np.max(np.abs(f.centrifugal @ w)) < 1e-14
    radial = r - np.outer(r @ w, w)
    assert np.all(np.sum(f.centrifugal * radial, -1) >= 0)


def test_free_particle_moves_uniformly_in_the_inertial_frame():
    """No real force: the inertial path is a straight line at constant speed, for a
    constant rotating+accelerating frame and a time-dependent one."""
    t = np.linspace(0.0, 6.0, 61)
    r0 = np.array([[1.0, 0.5, -0.2], [0.0, 2.0, 1.0]])
    v0 = np.array([[0.3, -0.4, 0.1], [-1.0, 0.0, 0.5]])
    frames = [
        FrameMotion(
            origin_velocity=[0.2, 0, 0],
            origin_acceleration=[0.1, 0.3, -0.2],
            omega=[0.2, -0.5, 0.8],
        ),
        lambda tt: FrameMotion(
            omega=[0.3 * np.sin(tt), 0.2, 0.5 + 0.1 * tt],
            eps=[0.3 * np.cos(tt), 0.0, 0.1],
            origin_acceleration=[0.0, 0.2 * tt, 0.0],
        ),
    ]
    for fr in frames:
        tr = simulate_particle(fr, None, r0, v0, t, inertial=True, rtol=1e-11, atol=1e-13)
        x = tr.inertial_position
        u = tr.inertial_velocity
        # velocity constant, position linear in time
        np.testing.assert_allclose(u, np.broadcast_to(u[0], u.shape), atol=2e-8)
        np.testing.assert_allclose(x, x[0] + (t - t[0])[:, None, None] * u[0], atol=2e-8)
        np.testing.assert_allclose(x[0], r0, atol=1e-15)


def test_jacobi_integral_conserved_in_uniformly_rotating_frame():
    fr = FrameMotion(omega=[0.3, -0.2, 1.0], origin_acceleration=[0.1, 0.0, -1.0])
    k = 2.0

    def U(r):
        return 0.5 * k * np.sum(r * r, -1)

    t = np.linspace(0.0, 50.0, 501)
    tr = simulate_particle(
        fr,
        lambda tt, r, v: -k * r,
        [[1, 0, 0], [0, 1, 0.5]],
        [[0, 1, 0], [0.2, 0, 0]],
        t,
        mass=[1.0, 3.0],
    )
    h = jacobi_integral(fr, tr.position, tr.velocity, mass=tr.mass, potential=U)
    drift = np.max(np.abs(h - h[0]), axis=0) / np.abs(h[0])
    assert np.all(drift < 3e-9), drift  # observed 1.5e-10 at rtol 1e-10
    # ... while the relative kinetic energy alone changes a lot
    assert np.ptp(tr.kinetic_energy) > 0.1


def test_jacobi_integral_needs_uniform_rotation():
    with pytest.raises(InvalidInputError, match="eps = 0"):
        jacobi_integral(FrameMotion(eps=[0, 0, 1]), [1, 0, 0], [0, 0, 0])


def test_constant_force_per_particle_and_batch_independence():
    fr = FrameMotion(omega=[0, 0, 0.5])
    t = np.linspace(0, 3, 7)
    force = [[0, 0, -1.0], [1.0, 0, 0]]
    both = simulate_particle(fr, force, [[1, 0, 0], [0, 1, 0]], [[0, 0, 0], [0, 0, 0]], t)
    one = simulate_particle(fr, force[1], [0, 1, 0], [0, 0, 0], t)
    np.testing.assert_array_equal(both.position[:, 1], one.position)


def test_eastward_deflection_error_is_second_order_in_omega():
    """The simulated fall (from rest, to the first-order fall time) against the
    first-order deflection: the relative error scales as Omega^2 (ratio 4 when
    Omega doubles), and is ~1e-7 for the real Earth."""
    g, h, lat = 9.81, 100.0, np.deg2rad(40.0)
    fall = np.sqrt(2 * h / g)
    errs = []
    for om in (1e-3, 2e-3, 4e-3):
        tr = simulate_particle(
            earth_frame(lat, om),
            [0, 0, -g],
            [0, 0, h],
            [0, 0, 0],
            [0.0, fall],
            rtol=1e-13,
            atol=1e-15,
        )
        d = eastward_deflection(h, lat, g, om)
        errs.append((tr.position[-1, 0] - d) / d)
    errs = np.abs(errs)
    np.testing.assert_allclose(errs[1:] / errs[:-1], 4.0, rtol=0.01)  # observed 4.000
    assert errs[0] < 2e-5  # (Omega t)^2 = 2e-5
    tr = simulate_particle(
        earth_frame(lat), [0, 0, -g], [0, 0, h], [0, 0, 0], [0.0, fall], rtol=1e-13, atol=1e-15
    )
    d = eastward_deflection(h, lat, g)
    assert abs(tr.position[-1, 0] / d - 1) < 1e-6  # observed 6.5e-8


def test_eastward_deflection_closed_form_values():
    # (1/3) Omega g t^3 cos(lat) with t = sqrt(2h/g), written out
    g, h = 9.80665, 158.0
    t = np.sqrt(2 * h / g)
    lat = np.deg2rad(50.9)
    ref = EARTH_ROTATION_RATE * g * t**3 * np.cos(lat) / 3
    assert eastward_deflection(h, 50.9, degrees=True) == pytest.approx(ref, rel=1e-14)
    np.testing.assert_allclose(
        eastward_deflection([0.0, 10.0], [0.0, np.pi / 2]), [0, 0], atol=1e-18
    )


def test_foucault_pendulum_plane_turns_at_minus_omega_sin_latitude():
    lat, om, ell = np.deg2rad(50.0), 2e-2, 10.0
    t = np.linspace(0, 300, 30001)
    tr = foucault_pendulum(ell, lat, t, omega=om)
    tt, ang = swing_plane_angles(t, tr.position, tr.velocity)
    slope = np.polyfit(tt, ang, 1)[0]
    expected = -om * np.sin(lat)
    assert foucault_precession_rate(lat, om) == pytest.approx(expected, rel=1e-15)
    assert slope == pytest.approx(expected, rel=1e-7)  # observed 6e-11
    assert np.max(np.abs(tr.position[:, 2])) == 0.0


def test_foucault_period_and_rate_values():
    # at the pole one sidereal day; clockwise (negative) in the north
    assert foucault_period(np.pi / 2) == pytest.approx(2 * np.pi / EARTH_ROTATION_RATE)
    assert foucault_period(90, degrees=True) == pytest.approx(86164.09, abs=0.01)
    assert (
        foucault_precession_rate(30, degrees=True) < 0 < foucault_precession_rate(-30, degrees=True)
    )
    assert np.isinf(foucault_period(0.0))


def test_earth_frame_and_normal_gravity():
    fr = earth_frame(30, degrees=True)
    np.testing.assert_allclose(
        fr.omega, EARTH_ROTATION_RATE * np.array([0, np.sqrt(3) / 2, 0.5]), rtol=1e-15
    )
    assert np.all(fr.origin_acceleration == 0) and np.all(fr.eps == 0)
    # WGS 84 (NIMA TR8350.2): equator 9.7803253359, pole 9.8321849378 m/s^2
    assert normal_gravity(0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert normal_gravity(-90, degrees=True) == pytest.approx(9.8321849378, abs=2e-10)


def test_inertial_output_of_rotating_frame_matches_rotation():
    """A particle at rest in a frame turning at w: inertial position R(t) r0 with R
    the rotation by w t (SciPy), velocity w x (R r0)."""
    from scipy.spatial.transform import Rotation as R

    w = np.array([0.1, 0.2, 0.9])
    t = np.linspace(0, 4, 9)
    r0 = np.array([1.0, -0.5, 0.3])
    # force cancelling the centrifugal force keeps it at rest
    f = np.cross(w, np.cross(w, r0))
    tr = simulate_particle(FrameMotion(omega=w), f, r0, [0, 0, 0], t, inertial=True)
    np.testing.assert_allclose(tr.position, np.broadcast_to(r0, (9, 3)), atol=1e-12)
    ref = R.from_rotvec(t[:, None] * w).apply(r0)
    np.testing.assert_allclose(tr.inertial_position, ref, atol=1e-12)
    np.testing.assert_allclose(tr.inertial_velocity, np.cross(w, ref), atol=1e-12)


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "err", "match"),
    [
        ({"position0": [np.nan, 0, 0]}, InvalidInputError, "position0"),
        ({"mass": -1.0}, InvalidInputError, "mass"),
        ({"mass": 0.0}, InvalidInputError, "mass"),
        ({"t": [0.0, 0.0]}, InvalidInputError, "increasing"),
        ({"method": "euler"}, InvalidInputError, "method"),
        ({"rtol": -1.0}, InvalidInputError, "rtol"),
        ({"frame": "rotating"}, InvalidTypeError, "frame"),
        ({"force": lambda t, r, v: [np.nan, 0, 0]}, IntegrationError, "non-finite"),
        ({"force": lambda t, r, v: [1.0, 0.0]}, InvalidInputError, "shape"),
        ({"velocity0": [0, 0]}, InvalidInputError, "velocity0"),
    ],
)
def test_simulate_particle_bad_input(kwargs, err, match):
    args = {
        "frame": FrameMotion(omega=[0, 0, 1]),
        "force": None,
        "position0": [1, 0, 0],
        "velocity0": [0, 0, 0],
        "t": [0.0, 1.0],
    }
    args.update(kwargs)
    with pytest.raises(err, match=match):
        simulate_particle(
            args.pop("frame"),
            args.pop("force"),
            args.pop("position0"),
            args.pop("velocity0"),
            args.pop("t"),
            **args,
        )


def test_other_bad_input():
    with pytest.raises(InvalidInputError, match="latitude"):
        earth_frame(100, degrees=True)
    with pytest.raises(InvalidInputError, match="height"):
        eastward_deflection(-1.0, 0.3)
    with pytest.raises(InvalidInputError, match="mass"):
        inertial_forces(FrameMotion(), [1, 0, 0], [0, 0, 0], mass=-2.0)
    with pytest.raises(InvalidInputError, match="r"):
        inertial_forces(FrameMotion(), [np.inf, 0, 0], [0, 0, 0])
    with pytest.raises(InvalidInputError, match="length"):
        foucault_pendulum(-1.0, 0.5, [0.0, 1.0])
    with pytest.raises(InvalidInputError, match="g"):
        eastward_deflection(10.0, 0.3, g=0.0)


def test_forces_with_potentials_and_relative_motion_round_trip():
    from poinsot.dynamics import PendulumForce, UniformGravity, foucault_frame, relative_motion

    r = RNG.standard_normal((20, 3))
    for force in (UniformGravity(2.0, 9.81), PendulumForce(1.5, 9.81, 3.0)):
        # F = -grad U by central differences
        h = 1e-6
        for k in range(3):
            e = np.zeros(3)
            e[k] = h
            grad = (force.potential(r + e) - force.potential(r - e)) / (2 * h)
            f = np.array([force(0.0, ri, ri) for ri in r])
            np.testing.assert_allclose(-grad, f[:, k], atol=1e-7)
    np.testing.assert_allclose(
        foucault_frame(0.7, 2.0).omega, [0, 0, 2.0 * np.sin(0.7)], rtol=1e-15
    )
    fr = FrameMotion(omega=[0.2, -0.3, 0.9])
    t = np.linspace(0, 3, 13)
    tr = simulate_particle(fr, PendulumForce(), [1, 0.5, 0], [0, 0.3, 0.1], t, inertial=True)
    traj = tr.to_trajectory("adaptive")
    assert traj.method == "adaptive"
    rr, vv = relative_motion(traj)
    np.testing.assert_allclose(rr, tr.position, atol=1e-13)
    np.testing.assert_allclose(vv, tr.velocity, atol=1e-13)
