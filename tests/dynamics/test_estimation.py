"""Attitude estimation (docs/theory.md §10.4): the sensor models and the MEKF, each
against an independent truth: the gyro's sample statistics against a fine-grid
simulation of Farrenkopf's continuous model and the stated variances; the propagation
against the exact torque-free motion (``FreeRigidBody``); the filter's consistency
(3-sigma bounds, bias convergence, NEES and NIS in their chi-square bands over seeded
Monte-Carlo runs) on the exact tennis-racket flip and on an exact Lagrange top; a
mistuned filter reports its divergence."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.stats import chi2

from poinsot import _quat
from poinsot.dynamics import (
    MEKF,
    EstimationResult,
    FreeRigidBody,
    Gyro,
    LagrangeTop,
    StarTracker,
    VectorSensor,
    attitude_error,
    dipole_field,
    nees,
    nis,
    run_mekf,
)
from poinsot.errors import InvalidInputError, InvalidTypeError

#: the tennis-racket flip: moments 1, 2, 3, spin mostly about the intermediate axis;
#: omega_y goes from +1.5 to -1.5 rad/s and back within 30 s
RACKET = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.05, 1.5, 0.05])
DT = 0.1  # gyro interval (s)
T = np.arange(0.0, 30.0 + 1e-9, DT)
T_VEC = T[::10]  # vector sensors at 1 Hz
ARW, RRW = 1e-4, 1e-6  # rad/s^0.5, rad/s^1.5
SIGMA_VEC = 2e-3  # rad
SIGMA_ATT0, SIGMA_BIAS0 = 1e-2, 2e-3  # prior: rad, rad/s
P0 = np.r_[[SIGMA_ATT0**2] * 3, [SIGMA_BIAS0**2] * 3]
SUN, MAG = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.6, 0.8])


@pytest.fixture(scope="module")
def racket():
    return RACKET.trajectory(T), RACKET.trajectory(T_VEC)


def _run(truth, truth_vec, seed, *, bias0=None, gyro=None, sigma_filter=None):
    """One seeded run: truth bias and initial error drawn from the prior."""
    rng = np.random.default_rng(seed)
    b0 = SIGMA_BIAS0 * rng.standard_normal(3) if bias0 is None else np.asarray(bias0)
    g = (gyro or Gyro(ARW, RRW, bias0=b0)).sample(truth, rng=rng)
    sun = VectorSensor(SUN, SIGMA_VEC).sample(truth_vec, rng=rng)
    mag = VectorSensor(MAG, SIGMA_VEC).sample(truth_vec, rng=rng)
    if sigma_filter is not None:
        sun = dataclasses.replace(sun, sigma=sigma_filter)
        mag = dataclasses.replace(mag, sigma=sigma_filter)
    q0 = _quat.mul(truth.quat[0], _quat.from_rotvec(SIGMA_ATT0 * rng.standard_normal(3)))
    p0 = P0 if bias0 is None else np.r_[P0[:3], [max(np.max(np.abs(b0)), SIGMA_BIAS0) ** 2] * 3]
    return g, run_mekf(g, [sun, mag], q0, p0)


# ----------------------------------------------------------------------------- gyro
def _spin(n, dt):
    """A pure spin about the major axis: omega = (0, 0, 1) rad/s exactly, at n times."""
    return FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory(dt * np.arange(n))


def test_gyro_bias_increments_and_rate_noise_have_the_stated_variances():
    """Over 60 000 seeded samples (3 axes): bias increments ``b_{k+1} - b_k`` have
    variance ``sigma_u^2 dt`` and no lag-1 correlation; the rate noise ``w_m - w -
    (b_{k+1} + b_k)/2`` has variance ``sigma_v^2/dt + sigma_u^2 dt/12`` (Crassidis &
    Junkins, §7.2). Relative sampling error of a variance from N = 180 000 normals:
    ``sqrt(2/N) = 0.33 %``; tolerance 1.5 %."""
    dt, arw, rrw = 0.5, 3e-3, 2e-3  # sigma_u^2 dt/12 is 1/11 of sigma_v^2/dt here
    g = Gyro(arw, rrw, bias0=[1e-2, 0.0, -1e-2]).sample(_spin(60_001, dt), rng=7)
    db = np.diff(g.bias, axis=0)
    assert np.var(db) == pytest.approx(rrw**2 * dt, rel=0.015)
    lag1 = np.mean(db[1:] * db[:-1]) / np.var(db)
    assert abs(lag1) < 0.01  # 4 / sqrt(180 000) = 0.0094
    noise = g.rate[1:] - g.omega[1:] - 0.5 * (g.bias[1:] + g.bias[:-1])
    expected = arw**2 / dt + rrw**2 * dt / 12.0
    assert np.var(noise) == pytest.approx(expected, rel=0.015)
    assert abs(np.mean(noise)) < 4.0 * np.sqrt(expected / noise.size)
    assert np.array_equal(g.bias[0], [1e-2, 0.0, -1e-2])


def test_gyro_averaged_noise_agrees_with_a_fine_simulation_of_the_continuous_model():
    """Independent truth for the ``sigma_u^2 dt / 12`` term: Farrenkopf's continuous
    model simulated on 40 sub-steps per interval (Euler-Maruyama, exact for a random
    walk), measured rate = the interval mean of ``b(t) + eta_v``; its residual about
    ``(b_k + b_{k+1})/2`` has the variance of the discrete model within sampling error
    (both from 60 000 intervals: relative error 0.6 % each; tolerance 3 %)."""
    dt, arw, rrw, n, sub = 1.0, 0.01, 0.1, 20_000, 40
    rng = np.random.default_rng(3)
    h = dt / sub
    b = np.concatenate(
        [np.zeros((1, 3)), np.cumsum(rrw * np.sqrt(h) * rng.standard_normal((n * sub, 3)), 0)]
    )
    # the mean of the piecewise-linear b over each interval (trapezoid on the fine grid)
    fine = 0.5 * (b[1:] + b[:-1]).reshape(n, sub, 3).mean(1)
    white = arw * np.sqrt(h) * rng.standard_normal((n, sub, 3))
    measured = fine + white.sum(1) / dt
    ends = b[::sub]
    fine_res = measured - 0.5 * (ends[1:] + ends[:-1])
    g = Gyro(arw, rrw).sample(_spin(n + 1, dt), rng=4)
    res = g.rate[1:] - g.omega[1:] - 0.5 * (g.bias[1:] + g.bias[:-1])
    assert np.var(res) == pytest.approx(np.var(fine_res), rel=0.03)
    assert np.var(fine_res) == pytest.approx(arw**2 / dt + rrw**2 * dt / 12.0, rel=0.03)


def test_gyro_is_reproducible_from_its_seed_and_applies_the_scale_factor():
    truth = _spin(50, 0.1)
    a = Gyro(1e-3, 1e-4).sample(truth, rng=11)
    b = Gyro(1e-3, 1e-4).sample(truth, rng=np.random.default_rng(11))
    assert np.array_equal(a.rate, b.rate) and np.array_equal(a.bias, b.bias)
    s = Gyro(0.0, 0.0, scale_factor=0.01, kind="rate").sample(truth, rng=0)
    assert np.allclose(s.rate, 1.01 * s.omega, rtol=0, atol=1e-15)
    assert "GyroSamples(50 samples" in repr(a) and "kind='integrating'" in repr(Gyro(0, 0))


def test_star_tracker_and_vector_sensor_noise_statistics():
    """Star tracker: ``attitude_error(L_m, L)`` has the standard deviation ``sigma``
    across and ``boresight_sigma`` about z; a direction sensor: the angle between the
    measured and true directions has mean square ``2 sigma^2`` (two perpendicular
    axes), the noise perpendicular to the truth. 20 000 samples; tolerance 3 %."""
    truth = RACKET.trajectory(np.linspace(0.0, 30.0, 20_000))
    st = StarTracker(1e-4, boresight_sigma=6e-4).sample(truth, rng=5)
    err = attitude_error(st.quat, st.true_quat)
    assert np.std(err, axis=0) == pytest.approx([1e-4, 1e-4, 6e-4], rel=0.03)

    def field(t):  # a circular equatorial orbit of radius 7000 km, period 5655 s
        r = 7e6 * np.stack([np.cos(t / 900), np.sin(t / 900), np.zeros_like(t)], -1)
        return dipole_field(t, r)

    vs = VectorSensor(field, 1e-3).sample(truth, rng=6)
    r = vs.reference
    assert np.allclose(np.linalg.norm(r, axis=-1), 1.0)
    assert np.allclose(_quat.to_body(truth.quat, r), vs.true, atol=1e-14)
    ang = np.arccos(np.clip(np.einsum("ni,ni->n", vs.observed, vs.true), -1, 1))
    assert np.mean(ang**2) == pytest.approx(2e-6, rel=0.03)


# ---------------------------------------------------------------------- propagation
def test_perfect_integrating_gyro_reproduces_the_exact_motion(racket):
    """A noise-free integrating gyro (the constant rate carrying ``L_{k-1}`` to ``L_k``)
    and the exact constant-rate propagation give the exact ``FreeRigidBody`` attitude
    across the flip to rounding: measured 3.3e-15 rad over 300 steps."""
    truth, _ = racket
    g = Gyro(0.0, 0.0).sample(truth, rng=0)
    r = run_mekf(g, [], truth.quat[0], np.full(6, 1e-8))
    assert np.abs(attitude_error(r.quat, truth.quat)).max() < 1e-12


def test_zero_order_hold_of_rate_samples_is_first_order():
    """A noise-free ``"rate"`` gyro held over each step: local error ``O(dt^2)``, so
    the error against the exact flip after 10 s is ``O(dt)``: measured 1.30e-3 rad
    (dt = 0.04 s), 6.46e-4 (0.02 s), 3.22e-4 (0.01 s), ratios 2.02, 2.01."""
    errs = []
    for dt in (0.04, 0.02, 0.01):
        truth = RACKET.trajectory(np.arange(0.0, 10.0 + 1e-9, dt))
        g = Gyro(0.0, 0.0, kind="rate").sample(truth, rng=0)
        r = run_mekf(g, [], truth.quat[0], np.full(6, 1e-8))
        errs.append(np.linalg.norm(attitude_error(r.quat[-1], truth.quat[-1])))
    assert errs[0] / errs[1] == pytest.approx(2.0, rel=0.1)
    assert errs[1] / errs[2] == pytest.approx(2.0, rel=0.1)


def test_transition_matrix_matches_finite_differences_of_the_propagation():
    """``Phi`` against the propagation itself: perturb the attitude (in body axes) and
    the bias of the estimate, propagate both with the same measured rate, read the
    error ``log(L~ o L')``: central differences agree to 1e-8, at a large rotation
    (1.2 rad per step) and in the series branch (1e-5 rad)."""
    from poinsot.dynamics.estimation import _transition

    for rate in ([0.3, -1.0, 0.5], [1e-5, 0.0, 0.0]):
        w, dt, q = np.array(rate), 1.0, _quat.normalize(np.array([0.9, 0.1, -0.3, 0.2]))
        num = np.zeros((6, 6))
        for j in range(6):
            out = []
            for sgn in (1.0, -1.0):
                dx = np.zeros(6)
                dx[j] = sgn * 1e-6
                qp = _quat.mul(q, _quat.from_rotvec(dx[:3]))
                a = _quat.mul(q, _quat.from_rotvec(w * dt))  # nominal, bias b
                b = _quat.mul(qp, _quat.from_rotvec((w - dx[3:]) * dt))  # true bias b + db
                out.append(np.r_[attitude_error(b, a), dx[3:]])
            num[:, j] = (out[0] - out[1]) / 2e-6
        assert np.allclose(_transition(w, dt), num, atol=1e-8)


# --------------------------------------------------------------------------- filter
def test_one_run_stays_inside_three_sigma_and_finds_the_bias(racket):
    """Gyro + Sun sensor + magnetometer on the exact flip, a large initial bias
    (0.5, -0.3, 0.4 deg/s) and a 1e-2 rad initial error: the attitude error lies
    within +-3 sigma for >= 99 % of the 301 samples per axis (measured 100 %), the
    final bias error is below 3 sigma and below 5 % of the initial bias (measured
    1.0e-4 rad/s max, 3 sigma = 9.4e-4, vs |b0| = 1.2e-2 rad/s); no divergence."""
    truth, tv = racket
    b0 = np.deg2rad([0.5, -0.3, 0.4])
    g, r = _run(truth, tv, 1, bias0=b0)
    e = attitude_error(r.quat, truth.quat)
    inside = (np.abs(e) <= 3.0 * r.sigma[:, :3]).mean(0)
    assert np.all(inside >= 0.99), inside
    db = np.abs(r.bias[-1] - g.bias[-1])
    assert np.all(db < 3.0 * r.sigma[-1, 3:])
    assert db.max() < 0.05 * np.linalg.norm(b0)
    assert not r.diverged and r.message == ""
    assert "converged" in repr(r) and isinstance(r, EstimationResult)


def test_monte_carlo_nees_and_nis_lie_in_their_chi_square_bands(racket):
    """M = 50 seeded runs (30 s, 301 gyro samples, 2 x 31 vector updates each; truth
    bias and initial error drawn from the prior). Average NEES per time: chi2(6M)/M,
    99 % band [4.81, 7.34]; measured inside at 100 % of times, grand mean 6.19. Average
    NIS per update: chi2(2M)/M, band [1.35, 2.80]; measured inside at 98 % of updates,
    mean 1.99. Pooled over the runs, >= 99 % of the attitude errors lie within 3 sigma
    per axis (measured 99.6, 99.7, 99.7 %)."""
    truth, tv = racket
    m_runs = 50
    all_nees, all_nis, inside = [], [], []
    for seed in range(100, 100 + m_runs):
        g, r = _run(truth, tv, seed)
        all_nees.append(nees(r, g))
        all_nis.append(nis(r))
        e = attitude_error(r.quat, truth.quat)
        inside.append(np.abs(e) <= 3.0 * r.sigma[:, :3])
    mean_nees = np.mean(all_nees, axis=0)
    lo, hi = chi2.ppf([0.005, 0.995], 6 * m_runs) / m_runs
    assert np.mean((mean_nees >= lo) & (mean_nees <= hi)) >= 0.95
    assert lo < mean_nees.mean() < hi
    mean_nis = np.mean(all_nis, axis=0)
    lo2, hi2 = chi2.ppf([0.005, 0.995], 2 * m_runs) / m_runs
    assert np.mean((mean_nis >= lo2) & (mean_nis <= hi2)) >= 0.95
    assert np.all(np.mean(np.concatenate(inside), axis=0) >= 0.99)


def test_star_tracker_on_an_exact_lagrange_top():
    """Gyro + star tracker (boresight 5x worse) on an exact Lagrange top (spin 8 rad/s,
    nutating between theta = 0.50 and 0.68 rad, measured): M = 20 runs, average NEES in
    the chi2(6M)/M 99 % band at >= 95 % of times, average NIS (3 dof) in chi2(3M)/M's
    band at >= 95 % of updates; >= 95 % of the 60 final bias errors within 3 sigma
    (measured: NEES inside at 100 % of times, mean 6.09; NIS at 100 %, mean 2.91; bias
    59 of 60)."""
    top = LagrangeTop(1.0, 0.5, 2.0, theta=0.5, spin=8.0)
    t = np.arange(0.0, 10.0 + 1e-9, 0.05)
    truth, tst = top.trajectory(t), top.trajectory(t[::4])
    m_runs, nn, ns, final = 20, [], [], []
    for seed in range(m_runs):
        rng = np.random.default_rng(seed)
        g = Gyro(ARW, RRW, bias0=SIGMA_BIAS0 * rng.standard_normal(3)).sample(truth, rng=rng)
        st = StarTracker(5e-5, boresight_sigma=2.5e-4).sample(tst, rng=rng)
        q0 = _quat.mul(truth.quat[0], _quat.from_rotvec(SIGMA_ATT0 * rng.standard_normal(3)))
        r = run_mekf(g, [st], q0, P0)
        assert not r.diverged
        final.append(np.abs(r.bias[-1] - g.bias[-1]) < 3.0 * r.sigma[-1, 3:])
        nn.append(nees(r, g))
        ns.append(nis(r))
    lo, hi = chi2.ppf([0.005, 0.995], 6 * m_runs) / m_runs
    mean_nees = np.mean(nn, axis=0)
    assert np.mean((mean_nees >= lo) & (mean_nees <= hi)) >= 0.95
    lo3, hi3 = chi2.ppf([0.005, 0.995], 3 * m_runs) / m_runs
    mean_nis = np.mean(ns, axis=0)
    assert np.mean((mean_nis >= lo3) & (mean_nis <= hi3)) >= 0.95
    assert np.mean(final) >= 0.95


def test_a_mistuned_filter_reports_its_divergence(racket):
    """Sensor sigma 100x too small in the filter, or a 5 % unmodelled scale factor on
    the flip (rates up to 1.5 rad/s): NIS stays above its 99.9 % gate for 10 updates
    (measured: declared at t = 6 s and t = 5 s) and the result says so; the well-tuned
    run of the same seed does not."""
    truth, tv = racket
    _, good = _run(truth, tv, 2)
    assert not good.diverged
    _, tight = _run(truth, tv, 2, sigma_filter=SIGMA_VEC / 100)
    assert tight.diverged and "NIS above the chi-square 0.999 gate" in tight.message
    assert "diverged" in repr(tight)
    _, scaled = _run(truth, tv, 2, gyro=Gyro(ARW, RRW, scale_factor=0.05))
    assert scaled.diverged and "consecutive" in scaled.message


def test_updates_in_between_gyro_samples_and_the_filter_object():
    """A measurement between gyro times is applied at its own time (the filter
    propagates to it); MEKF's vector update of an exact observation leaves a zero
    innovation, and the covariance shrinks."""
    truth = RACKET.trajectory(np.arange(0.0, 2.0 + 1e-9, 0.1))
    tmid = RACKET.trajectory([0.55, 1.05])
    g = Gyro(0.0, 0.0).sample(truth, rng=0)
    st = StarTracker(1e-4).sample(tmid, rng=0)
    r = run_mekf(g, [st], truth.quat[0], np.full(6, 1e-6))
    assert np.allclose(r.update_t, [0.55, 1.05]) and r.dof.tolist() == [3, 3]
    assert np.all(nis(r) < 20.0)
    f = MEKF(truth.quat[0], np.full(6, 1e-4), arw=1e-4, rrw=1e-6)
    b = _quat.to_body(truth.quat[0], SUN)
    y, s = f.update_vector(b, SUN, 1e-3)
    assert np.allclose(y, 0.0, atol=1e-15) and s.shape == (2, 2)
    assert np.trace(f.covariance) < 6e-4 and "MEKF(" in repr(f)
    y2, _ = f.update_attitude(-f.quat, [1e-3] * 3)  # -L is the same attitude
    assert np.allclose(y2, 0.0, atol=1e-15)
    with pytest.raises(InvalidInputError, match=r"`dt` to be >= 0, got -1.0"):
        f.propagate([0.0, 0.0, 1.0], -1.0)


def test_results_are_frozen_read_only_and_picklable(racket):
    import importlib
    import pickle

    truth, tv = racket
    g, r = _run(truth, tv, 3)
    for obj in (g, r):
        with pytest.raises(dataclasses.FrozenInstanceError):
            obj.t = None
    # the module as pickle finds it (a --doctest-modules run may import it a second time)
    mod = importlib.import_module("poinsot.dynamics.estimation")
    g2 = mod.Gyro(ARW, RRW).sample(truth, rng=3)
    r2 = mod.run_mekf(g2, [mod.StarTracker(1e-4).sample(tv, rng=3)], truth.quat[0], P0)
    for obj in (g2, r2):
        back = pickle.loads(pickle.dumps(obj))
        assert np.array_equal(back.t, obj.t) and np.array_equal(back.quat, obj.quat)
    with pytest.raises(ValueError, match="read-only"):
        r.quat[0, 0] = 2.0
    assert r.sigma.shape == (301, 6) and r.innovation.shape == (62, 3)
    assert np.isnan(r.innovation[:, 2]).all() and set(r.sensor.tolist()) == {0, 1}


def test_attitude_error_is_the_body_axis_rotation_vector():
    q = _quat.normalize(np.array([0.3, -0.5, 0.2, 0.7]))
    d = np.array([1e-3, -2e-3, 5e-4])
    est = _quat.mul(q, _quat.from_rotvec(d))
    assert np.allclose(attitude_error(est, q), d, atol=1e-15)
    assert np.allclose(attitude_error(-est, q), d, atol=1e-15)  # L and -L alike
    assert attitude_error(np.tile(est, (4, 1)), q).shape == (4, 3)


# --------------------------------------------------------------------------- errors
def test_errors():
    truth = _spin(5, 0.1)
    with pytest.raises(InvalidInputError, match=r"`arw` to be >= 0, got -1.0"):
        Gyro(-1.0, 0.0)
    with pytest.raises(InvalidInputError, match=r"`rrw` to be >= 0"):
        Gyro(0.0, -1e-3)
    with pytest.raises(InvalidInputError, match=r"`arw` to be a scalar"):
        Gyro([1.0, 2.0], 0.0)
    with pytest.raises(InvalidInputError, match=r"`bias0` to have shape \(3,\)"):
        Gyro(0.0, 0.0, bias0=[1.0, 2.0])
    with pytest.raises(InvalidInputError, match=r"`bias0` to have shape \(3,\), got \(2, 3\)"):
        Gyro(0.0, 0.0, bias0=np.zeros((2, 3)))
    with pytest.raises(InvalidInputError, match=r"`scale_factor` to be a scalar"):
        Gyro(0.0, 0.0, scale_factor=[0.1])
    with pytest.raises(InvalidInputError, match=r"`kind` to be one of 'integrating', 'rate'"):
        Gyro(0.0, 0.0, kind="optical")
    with pytest.raises(InvalidTypeError, match=r"`truth` to be a poinsot Trajectory"):
        Gyro(0.0, 0.0).sample(truth.quat)
    with pytest.raises(InvalidInputError, match=r"`truth` to have >= 2 samples, got 1"):
        Gyro(0.0, 0.0).sample(_spin(1, 0.1))
    batch = FreeRigidBody([1.0, 2.0, 3.0], omega0=[[0.0, 0.0, 1.0]] * 2).trajectory([0.0, 1.0])
    with pytest.raises(InvalidInputError, match=r"`truth` to hold one body"):
        StarTracker(1e-4).sample(batch)
    with pytest.raises(InvalidTypeError, match=r"`rng` to be a numpy Generator"):
        Gyro(0.0, 0.0).sample(truth, rng="seed")
    with pytest.raises(InvalidInputError, match=r"`sigma` to be >= 0"):
        StarTracker(-1e-4)
    with pytest.raises(InvalidInputError, match=r"`boresight_sigma` to be >= 0"):
        StarTracker(1e-4, boresight_sigma=-1.0)
    with pytest.raises(InvalidInputError, match=r"`reference` to be a non-zero vector"):
        VectorSensor([0.0, 0.0, 0.0], 1e-3)
    with pytest.raises(InvalidInputError, match=r"`reference` to be a non-zero vector"):
        VectorSensor([1.0, 0.0], 1e-3)
    with pytest.raises(InvalidInputError, match=r"`sigma` to be >= 0"):
        VectorSensor([1.0, 0.0, 0.0], -1.0)
    with pytest.raises(InvalidInputError, match=r"`reference\(t\)` to have shape \(5, 3\)"):
        VectorSensor(lambda t: np.zeros(3), 1e-3).sample(truth)
    with pytest.raises(InvalidInputError, match=r"`reference\(t\)` to be non-zero"):
        VectorSensor(lambda t: np.zeros(t.shape + (3,)), 1e-3).sample(truth)
    g = Gyro(0.0, 0.0).sample(truth)
    q0 = truth.quat[0]
    with pytest.raises(InvalidTypeError, match=r"`gyro_data` to be GyroSamples"):
        run_mekf(truth, [], q0, np.ones(6))
    with pytest.raises(InvalidTypeError, match=r"`measurements` to be a sequence"):
        run_mekf(g, 3, q0, np.ones(6))
    with pytest.raises(InvalidTypeError, match=r"`measurements\[0\]` to be AttitudeSamples"):
        run_mekf(g, [truth], q0, np.ones(6))
    late = StarTracker(1e-4).sample(_spin(20, 0.1))
    with pytest.raises(InvalidInputError, match=r"`measurements\[0\]` to lie within"):
        run_mekf(g, late, q0, np.ones(6))
    with pytest.raises(InvalidInputError, match=r"`gate` to be in \(0, 1\)"):
        run_mekf(g, [], q0, np.ones(6), gate=1.0)
    with pytest.raises(InvalidTypeError, match=r"`consecutive` to be an int"):
        run_mekf(g, [], q0, np.ones(6), consecutive=True)
    with pytest.raises(InvalidInputError, match=r"`consecutive` to be >= 1"):
        run_mekf(g, [], q0, np.ones(6), consecutive=0)
    with pytest.raises(InvalidInputError, match=r"`covariance0` to have shape \(6, 6\) or"):
        run_mekf(g, [], q0, np.ones(5))
    with pytest.raises(InvalidInputError, match=r"`covariance0` to be symmetric positive"):
        MEKF(q0, -np.ones(6), arw=0.0, rrw=0.0)
    with pytest.raises(InvalidInputError, match=r"`rotation0` to be one attitude"):
        MEKF(np.tile(q0, (2, 1)), np.ones(6), arw=0.0, rrw=0.0)
    with pytest.raises(InvalidInputError, match=r"`bias0` to have shape \(3,\)"):
        MEKF(q0, np.ones(6), bias0=[0.0], arw=0.0, rrw=0.0)
    with pytest.raises(InvalidInputError, match=r"`arw` to be >= 0"):
        run_mekf(g, [], q0, np.ones(6), arw=-1.0)
    r = run_mekf(g, [], q0, np.ones(6))
    with pytest.raises(InvalidTypeError, match=r"`result` to be an EstimationResult"):
        nees(g, g)
    with pytest.raises(InvalidTypeError, match=r"`truth` to be GyroSamples"):
        nees(r, truth)
    with pytest.raises(InvalidInputError, match=r"`truth` at the times of `result`"):
        nees(r, Gyro(0.0, 0.0).sample(_spin(6, 0.1)))
    with pytest.raises(InvalidTypeError, match=r"`result` to be an EstimationResult"):
        nis(g)
    with pytest.raises(InvalidInputError, match=r"`estimate_quat` to have shape"):
        attitude_error([1.0, 0.0, 0.0], q0)
    with pytest.raises(InvalidInputError, match=r"Expected the times of `truth` to be"):
        Gyro(0.0, 0.0).sample(RACKET.trajectory([1.0, 0.0]))
