"""Attitude in orbit (docs/theory.md §10.2): Kepler orbits against solve_ivp and the
conservation laws, orbit-frame rates against finite differences, the dipole field
against the textbook, pitch libration against mpmath and a 3-D integration, and the
stability regions against eigenvalues of a numerically differentiated model."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from poinsot import Rotation
from poinsot.dynamics import (
    GravityGradientTorque,
    KeplerOrbit,
    MagneticTorque,
    OrbitGravityGradientTorque,
    PitchLibration,
    dipole_field,
    gravity_gradient_stability,
    linearized_gravity_gradient,
    orbit_frame,
    orbit_frame_rates,
    simulate,
)
from poinsot.errors import InvalidInputError, InvalidTypeError

MU = 3.986004418e14


# ------------------------------------------------------------------ Kepler orbits
@pytest.mark.parametrize("e", [0.0, 0.1, 0.7, 0.99])
def test_kepler_equation_converges_to_a_few_ulp(e):
    orbit = KeplerOrbit(7.0e6, e, 0.3, 0.0, 0.0, 0.0)
    t = np.linspace(-3.0, 3.0, 20001) * orbit.period
    E = orbit.eccentric_anomaly(t)
    mean = np.remainder(orbit.mean_motion * t + np.pi, 2 * np.pi) - np.pi
    # residual of Kepler's equation, in units of the spacing of doubles at pi
    resid = np.abs(E - e * np.sin(E) - mean)
    assert np.max(resid) <= 4 * np.spacing(np.pi)  # observed <= 1 ulp(pi)


@pytest.mark.parametrize(
    ("e", "tol_r", "tol_v"),
    [(0.0, 1e-10, 1e-10), (0.3, 1e-10, 1e-10), (0.9, 2e-10, 1e-9), (0.99, 1e-8, 5e-7)],
)
def test_orbit_agrees_with_a_tight_integration(e, tol_r, tol_v):
    """r'' = -mu r / |r|^3 by DOP853 at rtol 1e-13 over two periods; the difference is
    the integration's (it shrinks with rtol: e = 0.99 gives 3e-9, 7e-10, 6e-10 at rtol
    1e-12, 1e-13, 3e-14)."""
    orbit = KeplerOrbit(8.0e6, e, 0.7, 1.1, -0.4, 0.5, epoch=10.0)
    t = np.linspace(10.0, 10.0 + 2 * orbit.period, 41)
    r0, v0 = orbit.state(10.0)

    def rhs(_, y):
        r = y[:3]
        return np.concatenate([y[3:], -MU * r / np.linalg.norm(r) ** 3])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([r0, v0]), method="DOP853",
                    t_eval=t, rtol=1e-13, atol=1e-9)  # fmt: skip
    r, v = orbit.state(t)
    err_r = np.max(np.abs(r - sol.y[:3].T)) / orbit.a
    err_v = np.max(np.abs(v - sol.y[3:].T)) / np.max(np.linalg.norm(v, axis=-1))
    # observed: r 1e-11 (e <= 0.9), 7e-10 (e = 0.99); v (relative to the largest |v|)
    # up to 5e-8 at e = 0.99, where the integration's time error meets the periapsis
    assert err_r < tol_r and err_v < tol_v


def test_energy_and_angular_momentum_are_conserved():
    orbit = KeplerOrbit(2.4e7, 0.73, 0.5, 0.2, 2.0, -1.0)
    r, v = orbit.state(np.linspace(0, 3 * orbit.period, 1001))
    energy = 0.5 * np.sum(v * v, -1) - MU / np.linalg.norm(r, axis=-1)
    h = np.cross(r, v)
    assert np.max(np.abs(energy / (-MU / (2 * orbit.a)) - 1)) < 1e-13  # observed 8e-15
    h0 = math.sqrt(MU * orbit.a * (1 - orbit.e**2))
    assert np.max(np.abs(h - h[0])) / h0 < 1e-13
    assert np.max(np.abs(np.linalg.norm(h, axis=-1) / h0 - 1)) < 1e-13


@pytest.mark.parametrize(
    "elements",
    [
        (7.0e6, 0.2, 0.5, 0.3, 1.2, 2.0),
        (9.0e6, 0.0, 0.9, 2.0, 0.0, -2.5),
        (7.5e6, 0.6, 0.0, 0.0, 0.7, 1.0),
        (7.5e6, 0.01, math.pi, 0.0, 0.7, 0.4),
        (4.2e7, 0.95, 1.2, -2.0, 3.0, 3.1),
    ],  # fmt: skip
)
def test_from_state_round_trip(elements):
    orbit = KeplerOrbit(*elements, epoch=5.0)
    r, v = orbit.state(5.0)
    back = KeplerOrbit.from_state(r, v, epoch=5.0)
    t = np.linspace(0, 2 * orbit.period, 50)
    assert np.max(np.abs(back.position(t) - orbit.position(t))) / orbit.a < 1e-11  # obs 1e-14
    assert abs(back.a / orbit.a - 1) < 1e-12 and abs(back.e - orbit.e) < 1e-12
    if 1e-6 < orbit.e and 1e-6 < orbit.inclination < 3.14:
        got = np.array([back.inclination, back.raan, back.argp, back.anomaly0])
        want = np.array(elements[2:])
        assert np.max(np.abs(np.angle(np.exp(1j * (got - want))))) < 1e-10


def test_kepler_degrees_and_shapes():
    a = KeplerOrbit(7e6, 0.1, 30.0, 40.0, 50.0, 60.0, degrees=True)
    b = KeplerOrbit(7e6, 0.1, *np.radians([30.0, 40.0, 50.0, 60.0]))
    t = np.linspace(0, 1e4, 12).reshape(3, 4)
    assert a.position(t).shape == (3, 4, 3)
    np.testing.assert_allclose(a.velocity(t), b.velocity(t), rtol=1e-14)
    assert a.state(0.0)[0].shape == (3,)


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"e": 1.0}, InvalidInputError, "`e`"),
        ({"e": -0.1}, InvalidInputError, "`e`"),
        ({"a": -1.0}, InvalidInputError, "`a`"),
        ({"a": [1.0, 2.0]}, InvalidInputError, "`a`"),
        ({"raan": "x"}, InvalidTypeError, "`raan`"),
        ({"degrees": 1}, InvalidTypeError, "degrees"),
        ({"mu": 0.0}, InvalidInputError, "`mu`"),
    ],  # fmt: skip
)
def test_kepler_errors(kwargs, exc, match):
    args = {"a": 7e6, "e": 0.1, "inclination": 0.0, "raan": 0.0, "argp": 0.0, "anomaly0": 0.0}
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        KeplerOrbit(**args)


def test_from_state_errors():
    with pytest.raises(InvalidInputError, match="elliptic"):
        KeplerOrbit.from_state([7e6, 0, 0], [0, 2e4, 0])
    with pytest.raises(InvalidInputError, match="rectilinear"):
        KeplerOrbit.from_state([7e6, 0, 0], [1e3, 0, 0])


# ------------------------------------------------------------------ orbit frames
def test_orbit_frames_axes():
    r, v = np.array([7e6, 1e6, 2e6]), np.array([-1e3, 7e3, 1e3])
    h = np.cross(r, v)
    rtn = orbit_frame(r, v).as_matrix()
    lvlh = orbit_frame(r, v, frame="lvlh").as_matrix()
    unit = lambda x: x / np.linalg.norm(x)  # noqa: E731
    np.testing.assert_allclose(rtn[:, 0], unit(r), atol=1e-15)
    np.testing.assert_allclose(rtn[:, 2], unit(h), atol=1e-15)
    np.testing.assert_allclose(lvlh[:, 2], -unit(r), atol=1e-15)
    np.testing.assert_allclose(lvlh[:, 1], -unit(h), atol=1e-15)
    np.testing.assert_allclose(lvlh[:, 0], rtn[:, 1], atol=1e-15)
    assert rtn[:, 1] @ v > 0
    batch = orbit_frame(np.broadcast_to(r, (4, 2, 3)), v)
    assert batch.shape == (4, 2)


@pytest.mark.parametrize("frame", ["rtn", "lvlh"])
def test_orbit_frame_rates_against_finite_differences(frame):
    """w (frame axes) = log(R(t)^-1 R(t + h)) / h, central; w' from w(t +- h)."""
    orbit = KeplerOrbit(1.2e7, 0.6, 0.8, 0.3, 1.0, 0.2)
    t = np.linspace(0, orbit.period, 17)
    step = 1e-2

    def frame_at(tt):
        return orbit_frame(*orbit.state(tt), frame=frame)

    fr = frame_at(t)
    plus = (fr.inv() * frame_at(t + step)).as_rotvec()
    minus = (fr.inv() * frame_at(t - step)).as_rotvec()
    w_fd = (plus - minus) / (2 * step)
    w, eps = orbit_frame_rates(*orbit.state(t), frame=frame)
    scale = np.max(np.abs(w))
    assert np.max(np.abs(w - w_fd)) / scale < 1e-8  # observed 1e-10
    wp, _ = orbit_frame_rates(*orbit.state(t + step), frame=frame)
    wm, _ = orbit_frame_rates(*orbit.state(t - step), frame=frame)
    eps_fd = (wp - wm) / (2 * step)
    assert np.max(np.abs(eps - eps_fd)) / np.max(np.abs(eps)) < 1e-6  # observed 3e-10


def test_orbit_frame_errors():
    with pytest.raises(InvalidInputError, match="frame"):
        orbit_frame([1.0, 0, 0], [0, 1.0, 0], frame="ned")
    with pytest.raises(InvalidInputError, match="parallel"):
        orbit_frame([1.0, 0, 0], [2.0, 0, 0])
    with pytest.raises(InvalidInputError, match=r"`v`.*\(\.\.\., 3\)"):
        orbit_frame_rates([1.0, 0, 0], [2.0, 0])


# ------------------------------------------------------------------ the dipole field
def _b0():
    g10, g11, h11 = -29404.8e-9, -1450.9e-9, 4652.5e-9
    return math.sqrt(g10**2 + g11**2 + h11**2), np.array([g11, h11, g10])


def _axis_inertial(t, greenwich=0.0):
    b0, g = _b0()
    a = greenwich + 7.2921159e-5 * t
    return Rotation.from_euler("z", a).apply(g / b0)


@pytest.mark.parametrize("t", [0.0, 1234.5])
def test_dipole_on_the_magnetic_equator_and_pole(t):
    """|B| = B0 (R/r)^3 on the magnetic equator, 2 B0 (R/r)^3 on the axis (textbook)."""
    b0, _ = _b0()
    m = _axis_inertial(t, 0.4)
    rad = 7.1e6
    eq = np.cross(m, [0.3, 0.5, 0.8])
    eq = rad * eq / np.linalg.norm(eq)
    pole = rad * m
    k = b0 * (6371.2e3 / rad) ** 3
    b_eq = dipole_field(t, eq, greenwich_angle=0.4)
    b_pole = dipole_field(t, -pole, greenwich_angle=0.4)
    assert abs(np.linalg.norm(b_eq) / k - 1) < 1e-14
    np.testing.assert_allclose(b_eq, -k * m, rtol=1e-14, atol=1e-14 * k)
    np.testing.assert_allclose(b_pole, 2 * k * m, rtol=1e-14, atol=1e-14 * k)


def test_dipole_is_divergence_and_curl_free():
    r = np.array([[5.0e6, -3.1e6, 2.2e6], [-7.0e6, 1.0e6, -0.5e6]])
    h = 1.0
    jac = np.empty((2, 3, 3))  # d B_i / d x_j
    for j in range(3):
        d = np.zeros(3)
        d[j] = h
        jac[:, :, j] = (dipole_field(100.0, r + d) - dipole_field(100.0, r - d)) / (2 * h)
    scale = np.max(np.abs(jac))
    div = np.trace(jac, axis1=1, axis2=2)
    curl = jac - np.swapaxes(jac, 1, 2)
    assert np.max(np.abs(div)) / scale < 1e-7  # observed 5e-10 (differencing)
    assert np.max(np.abs(curl)) / scale < 1e-7  # observed 1e-9


def test_untilted_dipole_and_rotation():
    """g11 = h11 = 0: B = B0 (R/r)^3 (3 cos(th) rhat - z_m), axis -z (g10 < 0), not turning."""
    g10 = -3.0e-5
    r = np.array([[7e6, 0, 0], [0, 0, 7e6], [4e6, 3e6, 5e6]])
    b = dipole_field(np.array([0.0, 500.0, 9000.0]), r, coefficients=(g10, 0.0, 0.0))
    k = 3.0e-5 * (6371.2e3 / np.linalg.norm(r, axis=-1)) ** 3
    rhat = r / np.linalg.norm(r, axis=-1)[:, None]
    m = np.array([0.0, 0.0, -1.0])
    want = k[:, None] * (3 * (rhat @ m)[:, None] * rhat - m)
    np.testing.assert_allclose(b, want, rtol=1e-14, atol=1e-20)
    # a tilted axis turns with the Earth: one sidereal day later the field repeats
    day = 2 * np.pi / 7.2921159e-5
    np.testing.assert_allclose(dipole_field(day, r), dipole_field(0.0, r), rtol=1e-9)


def test_dipole_errors():
    with pytest.raises(InvalidInputError, match="`r`"):
        dipole_field(0.0, [0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="`coefficients`"):
        dipole_field(0.0, [7e6, 0, 0], coefficients=(1.0, 2.0))


# ------------------------------------------------------------------ orbit torques
def test_orbit_gravity_gradient_matches_the_fixed_direction_model():
    orbit = KeplerOrbit(7.3e6, 0.2, 0.5, 0.1, 0.2, 0.3)
    j = np.array([[3.0, 0.1, 0.2], [0.1, 4.0, -0.3], [0.2, -0.3, 5.0]])
    q = Rotation.random((5,), rng=1).as_quat()
    t = 777.0
    r = orbit.position(t)
    fixed = GravityGradientTorque(j, np.linalg.norm(r), r)
    moving = OrbitGravityGradientTorque(j, orbit)
    np.testing.assert_allclose(
        moving.body_torque(t, q, np.zeros(3)), fixed.body_torque(t, q, np.zeros(3)), rtol=1e-14
    )
    assert not moving.conservative


def test_gravity_gradient_by_hand():
    """Independent formula: M = 3 mu / r^3 n_b x J n_b written out with numpy."""
    orbit = KeplerOrbit(7.3e6, 0.1, 0.5, 0.1, 0.2, 0.3)
    j = np.diag([1.0, 2.0, 2.5])
    rot = Rotation.from_rotvec([0.3, -0.2, 0.9])
    t = 55.0
    r = orbit.position(t)
    nb = rot.as_matrix().T @ (r / np.linalg.norm(r))
    want = 3 * MU / np.linalg.norm(r) ** 3 * np.cross(nb, j @ nb)
    got = OrbitGravityGradientTorque([1.0, 2.0, 2.5], orbit).body_torque(t, rot.as_quat(), 0.0)
    np.testing.assert_allclose(got, want, rtol=1e-13)


def test_magnetic_torque_by_hand():
    orbit = KeplerOrbit(7.0e6, 0.01, 1.0, 0.1, 0.2, 0.3)
    rot = Rotation.from_rotvec([[0.3, -0.2, 0.9], [0.0, 0.0, 0.0]])
    t = 300.0
    b_i = dipole_field(t, orbit.position(t))
    m_b = np.array([0.5, -1.0, 2.0])
    want = np.cross(m_b, rot.apply(b_i, inverse=True))
    got = MagneticTorque(m_b, orbit).body_torque(t, rot.as_quat(), np.zeros(3))
    np.testing.assert_allclose(got, want, rtol=1e-13)


def test_orbit_torques_batch_over_bodies():
    orbit = KeplerOrbit(7.0e6, 0.05, 1.0, 0.1, 0.2, 0.3)
    q = Rotation.random((4, 2), rng=3).as_quat()
    dipoles = np.arange(24.0).reshape(4, 2, 3) - 10.0
    got = MagneticTorque(dipoles, orbit).body_torque(10.0, q[0, 0], np.zeros(3))
    assert got.shape == (4, 2, 3)
    one = MagneticTorque(dipoles[2, 1], orbit).body_torque(10.0, q[0, 0], np.zeros(3))
    np.testing.assert_allclose(got[2, 1], one, rtol=1e-15)
    gg = OrbitGravityGradientTorque([1.0, 2.0, 2.5], orbit).body_torque(10.0, q, np.zeros(3))
    assert gg.shape == (4, 2, 3)


def test_torque_errors():
    with pytest.raises(InvalidTypeError, match="`orbit`"):
        OrbitGravityGradientTorque([1.0, 2.0, 3.0], 7e6)
    with pytest.raises(InvalidTypeError, match="`field`"):
        MagneticTorque([1.0, 0, 0], KeplerOrbit(7e6, 0, 0, 0, 0, 0), field=3.0)
    with pytest.raises(InvalidInputError, match="`dipole`"):
        MagneticTorque([1.0, 0], KeplerOrbit(7e6, 0, 0, 0, 0, 0))


# ------------------------------------------------------------------ pitch libration
def _mp_pendulum(w2, phi0, dphi0, times):
    """phi'' = -w2 sin(phi) by mpmath's Taylor integrator at 20 digits, in the scaled
    time tau = sqrt(|w2|) t (phi_tautau = -sign(w2) sin(phi))."""
    sign = 1 if w2 > 0 else -1
    with mpmath.workdps(20):
        w = mpmath.sqrt(abs(mpmath.mpf(w2)))
        f = mpmath.odefun(lambda _, y: [y[1], -sign * mpmath.sin(y[0])], 0,
                          [mpmath.mpf(phi0), mpmath.mpf(dphi0) / w])  # fmt: skip
        out = [f(w * mpmath.mpf(x)) for x in times]
        return np.array([[float(y[0]) for y in out], [float(y[1] * w) for y in out]])


@pytest.mark.parametrize(
    ("inertia", "theta0", "rate0"),
    [([2.0, 3.0, 1.0], 0.4, 0.0),  # libration, I1 > I3
     ([2.0, 3.0, 1.0], -0.2, -1.4e-3),  # libration, moving backwards
     ([2.0, 3.0, 1.0], 0.1, 3.0e-3),  # circulation
     ([2.0, 3.0, 1.0], 0.1, -3.0e-3),  # circulation backwards
     ([1.0, 3.0, 2.0], 1.2, 4e-4),  # I1 < I3: stable at theta = pi/2
     ([2.0, 3.0, 1.0], 1.5707, 0.0)],  # near the top: k ~ 1 - 1e-8
)  # fmt: skip
def test_pitch_libration_against_mpmath(inertia, theta0, rate0):
    n = 1.1e-3
    lib = PitchLibration(inertia, n, theta0=theta0, rate0=rate0)
    i1, i2, i3 = inertia
    w2 = 3 * n * n * (i1 - i3) / i2
    times = np.linspace(0.0, 4000.0, 5)
    phi, dphi = _mp_pendulum(w2, 2 * theta0, 2 * rate0, times)
    err = np.max(np.abs(lib.theta(times) - phi / 2))
    err_rate = np.max(np.abs(lib.rate(times) - dphi / 2)) / n
    assert err < 1e-12 and err_rate < 1e-12  # observed <= 2.5e-15 rad, 2.5e-15 n


def test_pitch_libration_period_and_small_oscillation():
    """Period = 4 K(k^2) / w0 (mpmath) and -> 2 pi / w0 for small amplitudes."""
    n = 1e-3
    for theta0, rate0 in [(0.5, 0.0), (0.0, 5e-4), (1e-6, 0.0)]:
        lib = PitchLibration([2.0, 3.0, 1.0], n, theta0=theta0, rate0=rate0)
        w0 = math.sqrt(3 * n * n * (2.0 - 1.0) / 3.0)
        m = (2 * rate0 / (2 * w0)) ** 2 + math.sin(theta0) ** 2
        want = 4 * float(mpmath.ellipk(m)) / w0
        assert abs(lib.period / want - 1) < 1e-13
        assert abs(lib.theta(lib.period) - theta0) < 1e-12
    assert lib.regime == "libration"
    assert abs(lib.period * w0 / (2 * math.pi) - 1) < 1e-11


def test_pitch_circulation_period_and_separatrix():
    n = 1e-3
    w0 = math.sqrt(3 * n * n / 3.0)
    lib = PitchLibration([2.0, 3.0, 1.0], n, theta0=0.0, rate0=2 * w0)
    assert lib.regime == "circulation"
    # one turn of phi = 2 theta: theta advances by pi
    assert abs(lib.theta(lib.period) - math.pi) < 1e-12
    k = lib.modulus
    assert abs(lib.period - 2 * float(mpmath.ellipk(1 / k**2)) / (k * w0)) < 1e-9 * lib.period
    # the separatrix, exactly: phi / 2 = gd(w0 t)  (phi(0) = 0, phi'(0) = 2 w0)
    sep = PitchLibration([2.0, 3.0, 1.0], n, theta0=0.0, rate0=w0)
    assert sep.regime == "separatrix" and sep.period == math.inf
    t = np.linspace(0, 2e4, 9)
    gd = 2 * np.arctan(np.tanh(w0 * t / 2))
    np.testing.assert_allclose(sep.theta(t), gd, rtol=0, atol=1e-14)
    np.testing.assert_allclose(sep.rate(t), w0 / np.cosh(w0 * t), rtol=1e-13, atol=0)


def test_pitch_libration_follows_the_3d_integration():
    """simulate (dop853, rtol 1e-12) with OrbitGravityGradientTorque in a circular orbit,
    started in-plane: the pitch angle relative to the LVLH frame follows theta(t)."""
    orbit = KeplerOrbit(7.0e6, 0.0, 0.9, 0.4, 0.0, 0.3)
    n = orbit.mean_motion
    inertia = np.array([2.0, 3.0, 1.0])
    theta0, rate0 = 0.6, 0.5 * n
    lib = PitchLibration(inertia, n, theta0=theta0, rate0=rate0)
    t = np.linspace(0.0, 1.5 * orbit.period, 31)
    frame0 = orbit_frame(*orbit.state(0.0), frame="lvlh")
    rot0 = frame0 * Rotation.from_euler("y", theta0)
    omega0 = np.array([0.0, rate0 - n, 0.0])  # body rate = relative rate + frame rate
    tr = simulate(inertia, rot0, omega0, t, torque=OrbitGravityGradientTorque(inertia, orbit),
                  method="dop853", rtol=1e-12, atol=1e-14)  # fmt: skip
    rel = orbit_frame(*orbit.state(t), frame="lvlh").inv() * Rotation.from_quat(tr.quat)
    rv = rel.as_rotvec()
    assert np.max(np.abs(rv[:, [0, 2]])) < 1e-9  # stays in the plane
    err = np.max(np.abs(np.angle(np.exp(1j * (rv[:, 1] - lib.theta(t))))))
    assert err < 1e-8  # observed 1.2e-11
    err_rate = np.max(np.abs(tr.omega[:, 1] + n - lib.rate(t))) / n
    assert err_rate < 1e-8


def test_pitch_libration_errors():
    with pytest.raises(InvalidInputError, match="`mean_motion`"):
        PitchLibration([2.0, 3.0, 1.0], -1.0, theta0=0.0, rate0=0.0)
    with pytest.raises(InvalidInputError, match="products of inertia"):
        PitchLibration(np.diag([2.0, 3.0, 1.5]) + 0.1 * (1 - np.eye(3)), 1e-3, theta0=0, rate0=0)
    assert PitchLibration([2.0, 3.0, 2.0], 1e-3, theta0=0.1, rate0=1e-4).regime == "uniform"


# ------------------------------------------------------------------ stability
def _numeric_jacobian(inertia, n):
    """6x6 Jacobian of the full nonlinear equations (relative rotation vector, body
    rate) at the LVLH equilibrium, by central differences: independent of the
    linearised formulas."""
    j = np.diag(inertia)
    w_frame = np.array([0.0, -n, 0.0])
    up = np.array([0.0, 0.0, -1.0])  # direction to the body from the centre, LVLH axes

    def f(x):
        rot = Rotation.from_rotvec(x[:3])
        w = x[3:]
        w_rel = w - rot.apply(w_frame, inverse=True)
        nb = rot.apply(up, inverse=True)
        torque = 3 * n * n * np.cross(nb, j @ nb)
        return np.concatenate([w_rel, np.linalg.solve(j, torque - np.cross(w, j @ w))])

    x0 = np.concatenate([np.zeros(3), w_frame])
    h = 1e-6
    cols = []
    for k in range(6):
        d = np.zeros(6)
        d[k] = h * (1 if k < 3 else n)
        cols.append((f(x0 + d) - f(x0 - d)) / (2 * d[k]))
    return np.array(cols).T


@pytest.mark.parametrize("inertia", [[3.0, 4.0, 2.0], [2.0, 2.5, 4.0], [4.0, 3.0, 2.0],
                                     [1.5, 1.0, 2.2], [3.0, 1.2, 2.0]])  # fmt: skip
def test_linearized_matrix_has_the_eigenvalues_of_the_full_model(inertia):
    n = 1.0
    ev = np.sort_complex(np.round(np.linalg.eigvals(linearized_gravity_gradient(inertia, n)), 6))
    ref = np.sort_complex(np.round(np.linalg.eigvals(_numeric_jacobian(inertia, n)), 6))
    np.testing.assert_allclose(ev, ref, atol=1e-5)  # equal to the 6 digits kept (raw 2e-11)


def test_classification_agrees_with_the_eigenvalues():
    """On a (k1, k3) grid of physical bodies, stable <-> purely imaginary distinct roots."""
    n = 0.7
    k = np.linspace(-0.98, 0.98, 50)
    checked = {"lagrange": 0, "debra-delp": 0, "unstable": 0}
    for k1 in k:
        for k3 in k:
            # a body with these ratios: I2 = 1, I1 = (1 - k3)/(1 - k1 k3), I3 = (1 - k1)/(1 - k1 k3)
            d = 1 - k1 * k3
            inertia = np.array([(1 - k3) / d, 1.0, (1 - k1) / d])
            s = gravity_gradient_stability(inertia)
            assert abs(s.k1 - k1) < 1e-12 and abs(s.k3 - k3) < 1e-12
            a = linearized_gravity_gradient(inertia, n)
            ev_p = np.linalg.eigvals(a[np.ix_([1, 4], [1, 4])])
            ev_ry = np.linalg.eigvals(a[np.ix_([0, 2, 3, 5], [0, 2, 3, 5])])
            tol = 1e-9 * n
            pitch_ok = np.all(np.abs(ev_p.real) < tol) and np.min(np.abs(ev_p.imag)) > tol
            im = np.sort(ev_ry.imag)
            ry_ok = (np.all(np.abs(ev_ry.real) < tol) and np.min(np.abs(im)) > tol
                     and np.min(np.diff(im)) > 1e-6 * n)  # fmt: skip
            if min(abs(k1 * k3), abs(k1 - k3)) < 1e-3:
                continue  # on a boundary: marginal, not classified
            assert bool(s.pitch_stable) == pitch_ok, (k1, k3)
            assert bool(s.roll_yaw_stable) == ry_ok, (k1, k3)
            # linearly stable in every axis: the Lagrange region (k3 > 0, a minimum of the
            # potential) or the DeBra-Delp region (k1 < 0: gyroscopic stability)
            want = "unstable"
            if pitch_ok and ry_ok:
                want = "lagrange" if k3 > 0 else "debra-delp"
            assert str(s.region) == want, (k1, k3)
            checked[str(s.region)] += 1
            if pitch_ok:  # the pitch frequency sqrt(3 k2) n
                assert abs(np.max(ev_p.imag) / (math.sqrt(3 * s.k2) * n) - 1) < 1e-12
    assert min(checked.values()) > 10


def test_stability_from_ratios_and_errors():
    s = gravity_gradient_stability(k1=np.array([0.5, -0.05, 0.2]), k3=np.array([0.2, -0.95, 0.5]))
    assert s.region.tolist() == ["lagrange", "debra-delp", "unstable"]
    with pytest.raises(InvalidInputError, match="`k1`"):
        gravity_gradient_stability(k1=1.5, k3=0.0)
    with pytest.raises(InvalidInputError, match="both"):
        gravity_gradient_stability([1.0, 2.0, 2.5], k1=0.1, k3=0.1)
    with pytest.raises(InvalidInputError, match="`k1` and `k3`"):
        gravity_gradient_stability(k1=0.1)


def test_plot_gravity_gradient_stability():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from poinsot.plotting import plot_gravity_gradient_stability

    fig, ax = plt.subplots()
    assert plot_gravity_gradient_stability(ax=ax) is ax
    assert ax.get_xlabel().startswith("k1")
    plt.close(fig)
