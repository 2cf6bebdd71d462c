"""Attitude control laws (docs/theory.md §10.3): closed loops run with ``simulate`` and
``simulate_wheels``, each checked against an independent truth (a Lyapunov function, the
analytic second-order response, the planned profile, the energy theorem, the external
torque run)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from poinsot import Rotation
from poinsot.dynamics import (
    BDot,
    EigenaxisSlew,
    MRPFeedback,
    QuaternionPD,
    pyramid,
    simulate,
    simulate_wheels,
)
from poinsot.errors import InvalidInputError, InvalidTypeError

TIGHT = {"method": "dop853", "rtol": 1e-10, "atol": 1e-12}
J_TENSOR = np.array([[10.0, 0.5, -0.3], [0.5, 12.0, 0.4], [-0.3, 0.4, 8.0]])


def _angle(q_ref, q):
    """Angle (rad) between attitudes, the short way."""
    a, b = np.broadcast_arrays(np.asarray(q_ref, float), np.asarray(q, float))
    d = (Rotation.from_quat(a).inv() * Rotation.from_quat(b)).as_quat()
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def _non_increasing(v, tol):
    assert np.all(np.diff(v) <= tol), float(np.max(np.diff(v)))


def test_quaternion_pd_rest_to_rest_lyapunov_and_convergence():
    """Wie, Weiss & Arapostathis (1989): V = w.Jw/2 + 2 kp (1 - |dq0|), V' = -kd |w|^2,
    from a 170 deg error (the short way) with a large initial rate."""
    target = Rotation.from_rotvec([0.3, -1.0, 0.5])
    q0 = target * Rotation.from_rotvec(np.radians(170.0) * np.array([1.0, 2.0, -1.0]) / 6**0.5)
    law = QuaternionPD(4.0, 8.0, target=target)
    t = np.linspace(0.0, 60.0, 601)
    tr = simulate(J_TENSOR, q0, [0.2, -0.1, 0.15], t, torque=law, **TIGHT)
    q = tr.rotation.as_quat()
    v = law.lyapunov(t[:, None], q, tr.omega, J_TENSOR)  # target at rest: t unused
    _non_increasing(v, 1e-9 * v[0])
    # V' = -kd |w|^2 integrated by the trapezoid rule on the samples
    dv = -8.0 * np.sum(tr.omega**2, axis=1)
    assert np.allclose(np.diff(v), 0.5 * (dv[1:] + dv[:-1]) * np.diff(t), atol=2e-3 * v[0])
    assert _angle(target.as_quat(), q[-1]) < 1e-5 and np.linalg.norm(tr.omega[-1]) < 1e-5


def test_quaternion_pd_small_angle_matches_the_second_order_response():
    """About principal axis z (moment C), dq_v ~ theta / 2: C theta'' + kd theta' +
    (kp / 2) theta = 0, so w_n = sqrt(kp / (2 C)), zeta = kd / sqrt(2 kp C); the
    closed-form underdamped response from theta0 at rest."""
    c, kp, kd, th0 = 3.0, 6.0, 1.2, 1e-4
    wn, zeta = math.sqrt(kp / (2 * c)), kd / math.sqrt(2 * kp * c)
    assert (wn, zeta) == pytest.approx((1.0, 0.2))
    law = QuaternionPD(kp, kd, target=[1.0, 0, 0, 0])
    t = np.linspace(0.0, 20.0, 401)
    q0 = Rotation.from_rotvec([0.0, 0.0, th0])
    tr = simulate([1.0, 2.0, c], q0, [0.0, 0.0, 0.0], t, torque=law, **TIGHT)
    q = tr.rotation.as_quat()
    theta = 2.0 * np.arctan2(q[:, 3], q[:, 0])
    wd = wn * math.sqrt(1 - zeta**2)
    exact = th0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))
    assert np.max(np.abs(theta - exact)) < 1e-7 * th0  # measured 3.5e-8 th0 (atol 1e-12)
    assert np.max(np.abs(tr.omega[:, :2])) == 0.0


def test_quaternion_pd_shortest_way_and_sign_of_q():
    law = QuaternionPD(1.0, 1.0, target=[1.0, 0, 0, 0])
    q = Rotation.from_rotvec([np.radians(190.0), 0.0, 0.0]).as_quat()
    m1, m2 = law.body_torque(0.0, q, np.zeros(3)), law.body_torque(0.0, -q, np.zeros(3))
    assert np.array_equal(m1, m2) and m1[0] > 0.0  # back the 170 deg way, not 190


def _moving_target(t):
    """R turns about a fixed non-principal axis e with theta = 0.05 t + 0.002 t^2."""
    e = np.array([1.0, 2.0, 2.0]) / 3.0
    th, rate = 0.05 * t + 0.002 * t**2, 0.05 + 0.004 * t
    q_r = Rotation.from_rotvec([0.4, 0.1, -0.2]) * Rotation.from_rotvec(th * e)
    return q_r, rate * e, 0.004 * e


def test_mrp_feedback_tracks_a_moving_target_with_lyapunov_decrease():
    """Schaub & Junkins: V = dw.J dw/2 + 2 K ln(1 + |sigma|^2), V' = -P |dw|^2, from an
    error beyond 180 deg (the shadow set is taken)."""
    law = MRPFeedback(6.0, 6.0, J_TENSOR, target=_moving_target)
    q0 = _moving_target(0.0)[0] * Rotation.from_rotvec([0.0, np.radians(200.0), 0.0])
    t = np.linspace(0.0, 60.0, 601)
    tr = simulate(J_TENSOR, q0, [0.1, 0.0, -0.1], t, torque=law, **TIGHT)
    q = tr.rotation.as_quat()
    v = np.array([law.lyapunov(tk, q[k], tr.omega[k]) for k, tk in enumerate(t)])
    _non_increasing(v, 1e-9 * v[0])
    assert v[-1] < 1e-9 * v[0]
    err = _angle(_moving_target(60.0)[0].as_quat(), q[-1])
    dw = tr.omega[-1] - _moving_target(60.0)[1]  # on track: R axes = body axes
    assert err < 1e-4 and np.linalg.norm(dw) < 1e-4


def test_mrp_sigma_stays_in_the_unit_ball():
    law = MRPFeedback(1.0, 1.0, [1.0, 1.0, 1.0], target=[1.0, 0, 0, 0])
    q = Rotation.from_rotvec([0.0, 0.0, np.radians(270.0)]).as_quat()  # = -90 deg
    m = law.body_torque(0.0, q, np.zeros(3))
    assert m == pytest.approx([0.0, 0.0, math.tan(math.radians(90.0) / 4)])
    assert float(law.lyapunov(0.0, q, np.zeros(3))) == pytest.approx(
        2.0 * math.log1p(math.tan(math.pi / 8) ** 2)
    )


def _slew(**kw):
    r0 = Rotation.from_rotvec([0.2, 0.4, -0.1])
    target = r0 * Rotation.from_rotvec(np.radians(120.0) * np.array([2.0, -1.0, 2.0]) / 3.0)
    return EigenaxisSlew(
        J_TENSOR, target, rotation0=r0, max_rate=0.05, max_torque=0.02, kp=2.0, kd=5.0, **kw
    )


def test_eigenaxis_slew_duration_profile_and_limits():
    slew = _slew()
    e, je = slew.axis, J_TENSOR @ slew.axis
    alpha = 0.8 * (0.02 - 0.05**2 * np.linalg.norm(np.cross(e, je))) / np.linalg.norm(je)
    assert slew.max_accel == pytest.approx(alpha, rel=1e-14)
    phi = np.radians(120.0)
    assert slew.angle == pytest.approx(phi, rel=1e-13)
    assert slew.duration == pytest.approx(phi / 0.05 + 0.05 / alpha, rel=1e-13)
    # the profile integrates its own rate and acceleration (trapezoid, bang-coast-bang)
    t = np.linspace(-5.0, slew.duration + 5.0, 20001)
    p = slew.profile(t)
    assert np.max(p.rate) == pytest.approx(0.05, rel=1e-12)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (p.rate[1:] + p.rate[:-1]) * np.diff(t))])
    assert np.max(np.abs(cum - p.angle)) < 1e-6
    assert p.angle[-1] == pytest.approx(phi, rel=1e-14)

    # closed loop from rest at rotation0: the body follows the profile (exact feedforward)
    ts = np.linspace(0.0, slew.duration + 20.0, 801)
    tr = simulate(J_TENSOR, slew.rotation0, [0.0, 0.0, 0.0], ts, torque=slew, **TIGHT)
    q = tr.rotation.as_quat()
    torques = np.array([slew.body_torque(tk, q[k], tr.omega[k]) for k, tk in enumerate(ts)])
    assert np.max(np.linalg.norm(torques, axis=1)) <= 0.02 * (1 + 1e-12)
    assert np.max(np.linalg.norm(tr.omega, axis=1)) <= 0.05 * (1 + 1e-7)
    ref = np.array([slew.reference(tk)[0] for tk in ts])
    assert np.max(_angle(ref, q)) < 1e-7
    done = ts >= slew.duration
    assert np.max(_angle(slew.target, q[done])) < 1e-7


def test_eigenaxis_slew_short_angle_is_bang_bang():
    """phi < max_rate^2 / alpha: triangular profile, duration 2 sqrt(phi / alpha), peak
    rate sqrt(phi alpha) < max_rate (principal axis: alpha = f max_torque / J_e)."""
    slew = EigenaxisSlew([2.0, 3.0, 4.0], Rotation.from_rotvec([0.0, 0.01, 0.0]),
                         rotation0=[1.0, 0, 0, 0], max_rate=0.1, max_torque=0.03, kp=1.0,
                         kd=1.0, accel_fraction=0.5)  # fmt: skip
    alpha = 0.5 * 0.03 / 3.0
    assert slew.max_accel == pytest.approx(alpha, rel=1e-14)
    assert slew.duration == pytest.approx(2 * math.sqrt(0.01 / alpha), rel=1e-14)
    p = slew.profile(np.linspace(0.0, slew.duration, 1001))
    assert np.max(p.rate) == pytest.approx(math.sqrt(0.01 * alpha), rel=1e-6)
    assert p.angle[-1] == pytest.approx(0.01, rel=1e-14)
    assert np.array_equal(slew.axis, [0.0, 1.0, 0.0])


def test_eigenaxis_slew_settles_within_the_derived_time():
    """A small initial rate error e0' decays like the linear loop J e'' + kd e' +
    (kp/2) e = 0: every mode underdamped (kd^2 < 2 kp J_min), |e| <= |e0'| / w_d e^{-s t}
    with s = kd / (2 J_max), w_d the smallest damped frequency; settle to eps at
    t_s = ln(|e0'| / (w_d eps)) / s."""
    slew = _slew(accel_fraction=0.6)
    lam = np.linalg.eigvalsh(J_TENSOR)
    kp, kd = slew.kp, slew.kd
    assert kd**2 < 2 * kp * lam[0]
    s = kd / (2 * lam[-1])
    wd = min(math.sqrt(kp / (2 * j) - (kd / (2 * j)) ** 2) for j in lam)
    de, eps = 2e-3, 1e-6
    ts_ = math.log(de / (wd * eps)) / s
    t = np.linspace(0.0, slew.duration + ts_, 400)
    w0 = de * np.array([1.0, -1.0, 0.0]) / 2**0.5
    tr = simulate(J_TENSOR, slew.rotation0, w0, t, torque=slew, **TIGHT)
    q = tr.rotation.as_quat()
    assert _angle(slew.target, q[-1]) < 2 * eps  # measured 2.7e-14: the bound is loose
    torques = np.array([slew.body_torque(tk, q[k], tr.omega[k]) for k, tk in enumerate(t)])
    assert np.max(np.linalg.norm(torques, axis=1)) <= slew.max_torque * (1 + 1e-12)
    assert np.max(np.linalg.norm(tr.omega, axis=1)) <= 0.05 + de


def _dipole_field(t, b0=-3.12e-5, radius=6378.137e3, a=6778.137e3, mu=3.986004418e14):
    """Aligned dipole (moment along -z for b0 < 0) on a polar circular orbit:
    B_i = b0 (R/r)^3 (3 (z.rhat) rhat - z), r(t) = a (cos nt, 0, sin nt)."""
    n = math.sqrt(mu / a**3)
    rhat = np.array([math.cos(n * t), 0.0, math.sin(n * t)])
    z = np.array([0.0, 0.0, 1.0])
    return b0 * (radius / a) ** 3 * (3.0 * rhat[2] * rhat - z)


J_SAT = np.array([0.02, 0.025, 0.03])


def test_bdot_energy_identity_and_detumbling():
    """dT/dt = w . (m x B_b); unsaturated, = -k |w x B_b|^2 + k (w x B_b) . R^T dB_i/dt,
    negative while the tumble is fast; T drops sample by sample."""
    k = 2e5
    law = BDot(k, math.inf, field=_dipole_field)
    t = np.linspace(0.0, 300.0, 301)
    w0 = np.array([0.05, -0.04, 0.06])
    tr = simulate(J_SAT, Rotation.from_rotvec([0.3, 0.2, 0.1]), w0, t, torque=law, **TIGHT)
    q, w = tr.rotation.as_quat(), tr.omega
    energy = 0.5 * np.sum(J_SAT * w**2, axis=1)
    power = np.empty(t.size)
    for i, ti in enumerate(t):
        b_b, db_b = law.field_body(ti, q[i], w[i])
        m = law.dipole(ti, q[i], w[i])
        power[i] = w[i] @ np.cross(m, b_b)
        db_i = (_dipole_field(ti + 0.5) - _dipole_field(ti - 0.5)) / 1.0
        wxb = np.cross(w[i], b_b)
        closed = -k * wxb @ wxb + k * wxb @ Rotation.from_quat(q[i]).inv().apply(db_i)
        assert power[i] == pytest.approx(closed, rel=1e-9, abs=1e-14 * abs(power).max())
        assert power[i] <= k * np.linalg.norm(wxb) * (np.linalg.norm(db_i) - np.linalg.norm(wxb))
    # the energy theorem: T(t_k+1) - T(t_k) = integral of w.L (Simpson on a finer run)
    assert np.all(np.diff(energy) < 0.0)
    tf = np.linspace(0.0, 10.0, 201)
    trf = simulate(J_SAT, tr.rotation[0], w0, tf, torque=law, **TIGHT)
    pf = np.array(
        [trf.omega[i] @ law.body_torque(x, trf.rotation.as_quat()[i], trf.omega[i]) for i, x in
         enumerate(tf)]
    )  # fmt: skip
    h = tf[1] - tf[0]
    simpson = h / 3 * (pf[0] + pf[-1] + 4 * pf[1:-1:2].sum() + 2 * pf[2:-1:2].sum())
    ef = 0.5 * np.sum(J_SAT * trf.omega**2, axis=1)
    assert ef[-1] - ef[0] == pytest.approx(simpson, rel=1e-7)
    assert energy[-1] < 0.1 * energy[0]  # measured 0.083


def test_bdot_saturated_still_detumbles_and_respects_the_limit():
    law = BDot(2e5, 0.05, field=_dipole_field)
    t = np.linspace(0.0, 300.0, 151)
    # rtol 1e-8: the saturation kinks make the tight run slow, and this check is coarse
    tr = simulate(J_SAT, [1.0, 0, 0, 0], [0.05, -0.04, 0.06], t, torque=law, method="dop853",
                  rtol=1e-8, atol=1e-12)  # fmt: skip
    q = tr.rotation.as_quat()
    m = np.array([law.dipole(x, q[i], tr.omega[i]) for i, x in enumerate(t)])
    assert np.max(np.abs(m)) == 0.05  # saturated at the start
    energy = 0.5 * np.sum(J_SAT * tr.omega**2, axis=1)
    assert np.all(np.diff(energy) < 0.0) and energy[-1] < 0.65 * energy[0]  # measured 0.60


def test_bdot_field_rate_option_and_difference_step():
    """The central difference of a field linear in t is exact; a field_rate callable is used."""
    f = lambda t: np.array([1e-5 + 2e-7 * t, -3e-5, 1e-6 * t])  # noqa: E731
    a = BDot(1.0, 1.0, field=f)
    b = BDot(1.0, 1.0, field=f, field_rate=lambda t: np.array([2e-7, 0.0, 1e-6]))
    q, w = Rotation.from_rotvec([0.1, 0.2, 0.3]).as_quat(), np.array([0.01, 0.02, -0.03])
    assert np.allclose(a.field_body(3.0, q, w)[1], b.field_body(3.0, q, w)[1], rtol=1e-9)


def test_quaternion_pd_through_wheels_gives_the_external_torque_motion():
    """``wheel_command`` makes the body see L: the same (q, w) as simulate(torque=law),
    while the total angular momentum is conserved (the motors are internal)."""
    target = Rotation.from_rotvec([0.5, -0.3, 0.8])
    law = QuaternionPD(0.5, 2.0, target=target, inertia=J_TENSOR)
    rw = pyramid(math.acos(3**-0.5), 0.05)
    t = np.linspace(0.0, 20.0, 201)
    w0 = np.array([0.02, -0.01, 0.03])
    ext = simulate(J_TENSOR, [1.0, 0, 0, 0], w0, t, torque=law, **TIGHT)
    whl = simulate_wheels(
        J_TENSOR, rw, [1.0, 0, 0, 0], w0, np.zeros(4), t,
        command=law.wheel_command(rw, J_TENSOR), rtol=1e-10, atol=1e-12,
    )  # fmt: skip
    assert np.max(_angle(ext.rotation.as_quat(), whl.rotation.as_quat())) < 1e-8
    assert np.max(np.abs(ext.omega - whl.omega)) < 1e-9
    assert whl.momentum_vector_drift < 1e-9
    assert np.max(np.abs(whl.wheel_speed)) > 1.0  # the wheels did the work


@pytest.mark.parametrize(
    ("make", "error", "match"),
    [
        (lambda: QuaternionPD(0.0, 1.0, target=[1.0, 0, 0, 0]), InvalidInputError, "`kp`"),
        (lambda: QuaternionPD(1.0, -1.0, target=[1.0, 0, 0, 0]), InvalidInputError, "`kd`"),
        (lambda: QuaternionPD(1.0, 1.0, target="x"), InvalidTypeError, "`target`"),
        (lambda: QuaternionPD(1.0, 1.0, target=None), InvalidTypeError, "`target`"),
        (lambda: QuaternionPD(1.0, 1.0, target=[1.0, 0, 0]), InvalidInputError, "`target`"),
        (lambda: QuaternionPD(1.0, 1.0, target=np.eye(4)), InvalidInputError, "`target`"),
        (lambda: QuaternionPD([1.0, 2.0], 1.0, target=[1, 0, 0, 0]), InvalidInputError, "`kp`"),
        (lambda: MRPFeedback(1.0, 0.0, [1.0, 1, 1], target=[1.0, 0, 0, 0]), InvalidInputError,
         "`P`"),
        (lambda: MRPFeedback(1.0, 1.0, [1.0, 1], target=[1.0, 0, 0, 0]), InvalidInputError,
         "`inertia`"),
        (lambda: MRPFeedback(1.0, 1.0, np.ones((2, 3)), target=[1.0, 0, 0, 0]),
         InvalidInputError, "`inertia`"),
        (lambda: _slew(accel_fraction=1.5), InvalidInputError, "`accel_fraction`"),
        (lambda: _slew(start_time=[0.0, 1.0]), InvalidInputError, "`start_time`"),
        (lambda: EigenaxisSlew([1.0, 1, 1], _moving_target, rotation0=[1.0, 0, 0, 0],
                               max_rate=1.0, max_torque=1.0, kp=1.0, kd=1.0),
         InvalidTypeError, "`target`"),
        (lambda: EigenaxisSlew([1.0, 1, 1], [1.0, 0, 0, 0], rotation0=np.ones((2, 4)),
                               max_rate=1.0, max_torque=1.0, kp=1.0, kd=1.0),
         InvalidInputError, "`rotation0`"),
        (lambda: EigenaxisSlew([1.0, 1, 1], [1.0, 0, 0, 0], rotation0=[1.0, 0, 0, 0],
                               max_rate=0.0, max_torque=1.0, kp=1.0, kd=1.0),
         InvalidInputError, "`max_rate`"),
        (lambda: EigenaxisSlew([1.0, 2, 3], [0.0, 1, 1, 1], rotation0=[1.0, 0, 0, 0],
                               max_rate=10.0, max_torque=1.0, kp=1.0, kd=1.0),
         InvalidInputError, "`max_torque`"),
        (lambda: BDot(0.0, 1.0, field=_dipole_field), InvalidInputError, "`gain`"),
        (lambda: BDot(1.0, -1.0, field=_dipole_field), InvalidInputError, "`max_dipole`"),
        (lambda: BDot(1.0, math.nan, field=_dipole_field), InvalidInputError, "`max_dipole`"),
        (lambda: BDot(1.0, [1.0, 2.0], field=_dipole_field), InvalidInputError,
         "`max_dipole`"),
        (lambda: BDot(1.0, "a", field=_dipole_field), InvalidTypeError, "`max_dipole`"),
        (lambda: BDot(1.0, 1.0, field=[0.0, 0, 1]), InvalidTypeError, "`field`"),
        (lambda: BDot(1.0, 1.0, field=_dipole_field, field_rate=3.0), InvalidTypeError,
         "`field_rate`"),
        (lambda: BDot(1.0, 1.0, field=_dipole_field, step=0.0), InvalidInputError, "`step`"),
    ],
)  # fmt: skip
def test_bad_parameters_name_the_argument(make, error, match):
    with pytest.raises(error, match=match):
        make()


def test_bad_callables_and_wheels_name_the_argument():
    bad_target = QuaternionPD(1.0, 1.0, target=lambda t: ([1.0, 0, 0, 0], [0.0, 0.0], [0, 0, 0]))
    with pytest.raises(InvalidInputError, match="`target` to return shapes"):
        bad_target.body_torque(0.0, [1.0, 0, 0, 0], [0.0, 0, 0])
    not_tuple = QuaternionPD(1.0, 1.0, target=lambda t: [1.0, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="`target` to return"):
        not_tuple.body_torque(0.0, [1.0, 0, 0, 0], [0.0, 0, 0])
    bad_field = BDot(1.0, 1.0, field=lambda t: np.zeros(4))
    with pytest.raises(InvalidInputError, match="`field` to return shape"):
        bad_field.body_torque(0.0, [1.0, 0, 0, 0], [0.0, 0, 0])
    law = QuaternionPD(1.0, 1.0, target=[1.0, 0, 0, 0])
    with pytest.raises(InvalidTypeError, match="`wheels`"):
        law.wheel_command("rw", [1.0, 1, 1])
    from poinsot.dynamics import ReactionWheels

    flat = ReactionWheels([[1.0, 0, 0], [0, 1.0, 0]], 0.01)
    with pytest.raises(InvalidInputError, match="`wheels`"):
        law.wheel_command(flat, [1.0, 1, 1])


def test_laws_broadcast_over_a_batch_of_bodies():
    """simulate with two bodies at once gives each body's own run (the laws broadcast)."""
    law = MRPFeedback(1.0, 2.0, [1.0, 2.0, 3.0], target=_moving_target)
    q0 = Rotation.from_rotvec([[0.3, 0.0, 0.0], [0.0, 2.5, 1.0]])
    w0 = np.array([[0.0, 0.1, 0.0], [0.05, 0.0, -0.02]])
    t = np.linspace(0.0, 5.0, 11)
    both = simulate([1.0, 2.0, 3.0], q0, w0, t, torque=law, **TIGHT)
    for k in range(2):
        one = simulate([1.0, 2.0, 3.0], q0[k], w0[k], t, torque=law, **TIGHT)
        assert np.allclose(both.omega[:, k], one.omega, rtol=0, atol=1e-9)


def test_lyapunov_needs_an_inertia():
    law = QuaternionPD(1.0, 1.0, target=[1.0, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="`inertia`"):
        law.lyapunov(0.0, [1.0, 0, 0, 0], [0.0, 0, 0])
    fed = QuaternionPD(1.0, 1.0, target=[1.0, 0, 0, 0], inertia=[1.0, 2.0, 3.0])
    assert float(fed.lyapunov(0.0, [1.0, 0, 0, 0], [1.0, 1.0, 1.0])) == pytest.approx(3.0)
