"""The Basilisk adapter of poinsot verify against the real engine (issue 44).

Basilisk (``pip install bsk``) is not in poinsot's extras: it caps pandas and
matplotlib, so it lives in an environment of its own; without it this module is
skipped, loudly. Truths: poinsot's exact Euler-Poinsot solutions, and a steady spin
about a principal axis with a turned attitude and a non-diagonal inertia, which checks
the MRP <-> quaternion conversion, its frame (``[BN]`` inertial -> body) and the
frame of the angular velocity on their own.

Observed (bsk 2.12.1): RK4 at a 1 ms task period passes every free body (attitude
<= 1.4e-11 rad on the version-1 cases); RK4 at 10 ms fails the racket flip (attitude
9.0e-8 rad, within its 1e-6, but the momentum drifts 5.8e-8, over 1e-8); Euler is
first order (0.10 rad on the racket flip at 1 ms), RK2 second, RK4 fourth.

The dual-spin gyrostat (a balanced ``reactionWheelStateEffector``, no motor torque,
the hub holding the wheel's spin inertia; docs/verify.md) and the constant body
torque (an ``extForceTorque`` effector), attitude errors (rad): dual-spin RK4 1.50e-9
at 10 ms, 9.38e-11 at 5 ms (ratio 16.0), 1.51e-13 at 1 ms; Euler 2.68e-3 at 1 ms,
1.33e-3 at 0.5 ms (ratio 2.01); RK2 1.13e-6 at 1 ms (fail); RKF78 rtol 1e-10 2.7e-14.
body-torque RK4 1.02e-7 at 10 ms, 6.41e-9 at 5 ms (ratio 15.9), 1.02e-11 at 1 ms;
Euler 2.87e-2 at 1 ms, 1.43e-2 at 0.5 ms (ratio 2.01). A wrong wheel mapping at RK4
1 ms: the hub given ``J`` alone (the wheel's ``Js`` left out) 0.162 rad, the wheel
speed ``|h| / Js`` (absolute, not relative to the hub) 0.146 rad.
"""

from __future__ import annotations

import numpy as np
import pytest

from poinsot import Rotation
from poinsot.dynamics import FreeRigidBody
from poinsot.errors import InvalidInputError
from poinsot.verify import cases, make, run

pytest.importorskip(
    "Basilisk",
    reason="THE BASILISK ADAPTER IS NOT TESTED: Basilisk is not installed; pip install bsk "
    "(not in poinsot's extras: it caps pandas/matplotlib; use an environment of its own)",
)

import poinsot.verify._basilisk as bsk  # noqa: E402
from poinsot.verify._basilisk import (  # noqa: E402
    build_basilisk,
    mrp_to_quat,
    quat_to_mrp,
    run_basilisk,
)
from poinsot.verify._mujoco import ROTOR_AXIAL, rotor_axis  # noqa: E402

#: the free bodies of cases version 1
FREE4 = "free-minor-axis,free-major-axis,racket-flip,free-symmetric"


def attitude_error(q: np.ndarray, exact: np.ndarray) -> float:
    return float(np.max((Rotation.from_quat(exact).inv() * Rotation.from_quat(q)).magnitude()))


def test_mrp_conversion_round_trip_and_basilisk_dcm():
    from Basilisk.utilities import RigidBodyKinematics as rbk

    rng = np.random.default_rng(4)
    for _ in range(20):
        q = np.asarray(Rotation.from_rotvec(rng.normal(size=3) * 1.5).as_quat(), dtype=float)
        s = quat_to_mrp(q)
        assert np.linalg.norm(s) <= 1.0 + 1e-15
        # Basilisk's own: the MRPs of [BN] = R_ib^T
        np.testing.assert_allclose(s, rbk.C2MRP(Rotation.from_quat(q).as_matrix().T),
                                   atol=1e-14)  # fmt: skip
        back = mrp_to_quat(s)
        assert min(np.abs(back - q).max(), np.abs(back + q).max()) < 1e-14
        np.testing.assert_allclose(rbk.MRP2C(s).T, Rotation.from_quat(q).as_matrix(), atol=1e-14)


def test_rk4_passes_the_free_bodies():
    for case in cases(FREE4):
        res = run(make("basilisk", integrator="RK4", timestep=1e-3), case)
        assert res.status == "pass", (case.name, res.reason)
        assert res.metrics["attitude"]["value"] < 1e-9  # observed <= 1.4e-11 rad
        assert res.work == 10_000


def test_coarse_steps_fail():
    flip = cases("racket-flip")[0]
    res = run(make("basilisk", integrator="RK4", timestep=1e-2), flip)
    assert res.status == "fail" and res.metrics["attitude"]["value"] > 1e-8  # observed 9.0e-8
    assert not res.metrics["momentum"]["passed"]  # observed 5.8e-8 > 1e-8
    res = run(make("basilisk", integrator="Euler", timestep=1e-3), flip)
    assert res.status == "fail" and res.metrics["attitude"]["value"] > 1e-2  # observed 0.10


def test_euler_is_first_order_and_rk4_fourth():
    case = cases("free-symmetric")[0]
    e = [run(make("basilisk", integrator="Euler", timestep=h), case).metrics["attitude"]
         ["value"] for h in (1e-2, 1e-3)]  # fmt: skip
    assert 7.0 < e[0] / e[1] < 13.0, e  # first order
    e = [run(make("basilisk", integrator="RK4", timestep=h), case).metrics["attitude"]["value"]
         for h in (1e-2, 5e-3)]  # fmt: skip
    assert 12.0 < e[0] / e[1] < 20.0, e  # fourth order: 16 per halving


def test_adaptive_rkf78_with_a_tolerance_passes():
    res = run(make("basilisk", integrator="RKF78", timestep=1e-2, rtol=1e-10),
              cases("racket-flip")[0])  # fmt: skip
    assert res.status == "pass", res.reason


def test_conventions_steady_spin_and_general_axes():
    """A steady spin about a principal axis (the greatest) of a non-diagonal inertia
    from a turned attitude: omega constant in body axes, the attitude
    ``q0 * exp(w t n / 2)``; a swapped order or frame would be far off."""
    t = np.linspace(0.0, 2.0, 21)
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8])
    inertia = turn.as_matrix() @ np.diag([1.0, 2.0, 3.0]) @ turn.as_matrix().T
    axis = turn.as_matrix()[:, 2]
    q0 = np.asarray(Rotation.from_rotvec([0.7, 0.2, -0.4]).as_quat(), dtype=float)
    w0 = 1.5 * axis
    exact_q = np.asarray(
        (Rotation.from_quat(q0) * Rotation.from_rotvec(1.5 * t[:, None] * axis)).as_quat(),
        dtype=float,
    )
    q, w, steps = run_basilisk(inertia=inertia, mass=2.0, q0=q0, omega0=w0, t=t,
                               timestep=1e-3)  # fmt: skip
    assert steps == 2000
    assert np.max(np.abs(w - w0)) < 1e-9  # body-axes omega, constant
    assert attitude_error(q, exact_q) < 1e-9
    assert np.max(np.abs(Rotation.from_quat(q).apply(w) - w0)) > 0.1  # not space axes
    assert attitude_error(np.roll(q, -1, axis=1), exact_q) > 0.1  # not scalar last
    conj = q * np.array([1.0, -1.0, -1.0, -1.0])
    assert attitude_error(conj, exact_q) > 0.1  # not [BN] read as body -> inertial
    # a general motion: not a principal axis, so the products of inertia count
    w1 = np.array([0.4, 1.5, -0.6])
    t = np.linspace(0.0, 5.0, 51)
    q, w, _ = run_basilisk(inertia=inertia, mass=2.0, q0=q0, omega0=w1, t=t, timestep=1e-3)
    we, re = FreeRigidBody(inertia, rotation0=q0, omega0=w1).state(t)
    assert np.max(np.abs(w - we)) < 1e-9
    assert np.max((re.inv() * Rotation.from_quat(q)).magnitude()) < 1e-9


def test_skips_and_bad_options():
    eng = make("basilisk")
    assert "fixed point" in eng.skip_reason(cases("top-loops")[0])
    assert "turning frame" in eng.skip_reason(cases("foucault")[0])
    assert eng.skip_reason(cases("body-torque")[0]) is None
    assert eng.skip_reason(cases("dual-spin")[0]) is None
    assert "gravity-gradient" in eng.skip_reason(cases("pitch-libration")[0])
    assert eng.skip_reason(cases("racket-flip")[0]) is None
    for opts, word in (({"integrator": "rk4"}, "integrator"), ({"timestep": 0.0}, "timestep"),
                       ({"rtol": 1e-8}, "adaptive")):  # fmt: skip
        with pytest.raises(InvalidInputError, match=word):
            make("basilisk", **opts)
    with pytest.raises(InvalidInputError, match="multiples"):
        run_basilisk(inertia=np.eye(3), mass=1.0, q0=[1.0, 0.0, 0.0, 0.0],
                     omega0=[0.0, 0.0, 1.0], t=[0.0, 0.005], timestep=0.002)  # fmt: skip


def test_cli_verdicts(capsys):
    from poinsot.cli import main

    assert main(["verify", "basilisk", "--cases", FREE4, "--quiet"]) == 0
    assert "4 passed" in capsys.readouterr().out
    assert main(["verify", "basilisk", "--method", "Euler", "--step", "0.01", "--cases",
                 "racket-flip,top-loops", "--quiet"]) == 1  # fmt: skip
    assert "verdict: FAIL (0 passed, 1 failed, 0 missing, 1 skipped)" in capsys.readouterr().out


# --- the gyrostat's reaction wheel and the constant body torque ----------------------


def attitude(res) -> float:
    return float(res.metrics["attitude"]["value"])


def test_wheel_mapping_total_momentum_at_the_start():
    """Basilisk's own total angular momentum at ``t = 0`` (``computeEnergyMomentum``)
    is the case's ``R (J w + h)``: on dual-spin and on a general gyrostat (turned
    inertia not flat, so that ``J_L`` passes Basilisk's check of the hub's inertia;
    wheel axis off the principal axes, turned attitude). The hub holds
    ``J + Js a a^T``, the wheel's ``Omega`` the speed relative to the hub."""
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8])
    general = (
        turn.as_matrix() @ np.diag([2.0, 3.0, 4.0]) @ turn.as_matrix().T,
        np.array([0.6, -1.2, 2.0]),
        np.array([0.4, 1.5, -0.6]),
        np.asarray(Rotation.from_rotvec([0.7, 0.2, -0.4]).as_quat(), dtype=float),
    )
    i = cases("dual-spin")[0].inputs
    for j, h, w0, q0 in ((i["inertia"], i["rotor_momentum"], i["omega0"], i["q0"]), general):
        sim, sc, eff = build_basilisk(inertia=j, mass=1.0, q0=q0, omega0=w0,
                                      rotor_momentum=h)  # fmt: skip
        sc.computeEnergyMomentum(0.0)
        k = np.ravel(sc.totRotAngMomPntC_N)
        want = Rotation.from_quat(q0).apply(j @ w0 + h)
        np.testing.assert_allclose(k, want, atol=1e-13)
        a = h / np.linalg.norm(h)
        np.testing.assert_allclose(np.asarray(sc.hub.IHubPntBc_B),
                                   j + ROTOR_AXIAL * np.outer(a, a), atol=1e-15)  # fmt: skip
        wheel = eff[0].ReactionWheelData[0]
        assert wheel.Js == ROTOR_AXIAL
        assert abs(wheel.Omega - (np.linalg.norm(h) / ROTOR_AXIAL - a @ w0)) < 1e-14
        assert wheel.Omega == rotor_axis(j, h, w0)[2]


def test_general_gyrostat_matches_dop853():
    """A general gyrostat (turned inertia, oblique wheel) against DOP853 on
    ``J w' + w x (J w + h) = 0``, 5 s at RK4 1 ms."""
    from scipy.integrate import solve_ivp

    from poinsot.kinematics import quat_rate

    turn = Rotation.from_rotvec([0.3, -0.5, 0.8])
    j = turn.as_matrix() @ np.diag([2.0, 3.0, 4.0]) @ turn.as_matrix().T
    h, w0 = np.array([0.6, -1.2, 2.0]), np.array([0.4, 1.5, -0.6])
    q0 = np.asarray(Rotation.from_rotvec([0.7, 0.2, -0.4]).as_quat(), dtype=float)
    t = np.linspace(0.0, 5.0, 51)

    def rhs(_, y):
        w = y[4:]
        return np.concatenate([quat_rate(y[:4], w), np.linalg.solve(j, -np.cross(w, j @ w + h))])

    ref = solve_ivp(rhs, (0.0, 5.0), np.concatenate([q0, w0]), method="DOP853", t_eval=t,
                    rtol=1e-12, atol=1e-14).y.T  # fmt: skip
    q, w, _ = run_basilisk(inertia=j, mass=1.0, q0=q0, omega0=w0, t=t, timestep=1e-3,
                           rotor_momentum=h)  # fmt: skip
    assert np.max(np.abs(w - ref[:, 4:])) < 1e-9
    assert attitude_error(q, ref[:, :4] / np.linalg.norm(ref[:, :4], axis=1)[:, None]) < 1e-9


def test_rk4_passes_dual_spin_at_fourth_order():
    case = cases("dual-spin")[0]
    res = [run(make("basilisk", integrator="RK4", timestep=h), case) for h in (1e-2, 5e-3)]
    assert all(r.status == "pass" for r in res), [r.reason for r in res]
    e = [attitude(r) for r in res]  # observed 1.50e-9, 9.38e-11
    assert 12.0 < e[0] / e[1] < 20.0, e
    res = run(make("basilisk", integrator="RK4", timestep=1e-3), case)
    assert res.status == "pass" and attitude(res) < 1.5e-12  # observed 1.51e-13
    assert res.work == 20_000


def test_euler_fails_dual_spin_at_first_order():
    case = cases("dual-spin")[0]
    res = [run(make("basilisk", integrator="Euler", timestep=h), case) for h in (1e-3, 5e-4)]
    assert all(r.status == "fail" for r in res)
    e = [attitude(r) for r in res]  # observed 2.68e-3, 1.33e-3
    assert e[1] > 1e-4 and 1.7 < e[0] / e[1] < 2.3, e


@pytest.mark.parametrize("wrong", ["hub without the wheel's Js", "absolute wheel speed"])
def test_a_wrong_wheel_mapping_fails(monkeypatch, wrong):
    """The hub given ``J`` alone (Basilisk's balanced wheel adds no inertia, so its
    ``Js`` must be in the hub) or the wheel's ``Omega`` read as its absolute speed
    ``|h| / Js`` fails dual-spin far over the threshold; the right mapping 1.5e-13 rad."""
    right = bsk.rotor_axis

    def mapped(inertia, h, w0, *args):
        jl, a, rate0 = right(inertia, h, w0, *args)
        if wrong == "absolute wheel speed":
            return jl, a, rate0 + float(a @ np.asarray(w0))
        return np.asarray(inertia, dtype=float), a, rate0

    monkeypatch.setattr(bsk, "rotor_axis", mapped)
    res = run(make("basilisk", integrator="RK4", timestep=1e-3), cases("dual-spin")[0])
    assert res.status == "fail"
    assert attitude(res) > 1e-2, attitude(res)  # observed 0.162 and 0.146 rad


def test_rk4_passes_body_torque_at_fourth_order_and_euler_fails():
    """The constant body-axes torque as an ``extForceTorque`` effector."""
    case = cases("body-torque")[0]
    res = [run(make("basilisk", integrator="RK4", timestep=h), case) for h in (1e-2, 5e-3, 1e-3)]
    assert all(r.status == "pass" for r in res), [r.reason for r in res]
    e = [attitude(r) for r in res]  # observed 1.02e-7, 6.41e-9, 1.02e-11
    assert 12.0 < e[0] / e[1] < 20.0 and e[2] < 1e-10, e
    res = [run(make("basilisk", integrator="Euler", timestep=h), case) for h in (1e-3, 5e-4)]
    assert all(r.status == "fail" for r in res)
    e = [attitude(r) for r in res]  # observed 2.87e-2, 1.43e-2
    assert e[1] > 1e-3 and 1.7 < e[0] / e[1] < 2.3, e


def test_torque_and_wheel_inputs_are_checked():
    with pytest.raises(InvalidInputError, match="torque"):
        build_basilisk(inertia=np.eye(3), mass=1.0, q0=[1.0, 0.0, 0.0, 0.0],
                       omega0=[0.0, 0.0, 1.0], torque=[1.0, 2.0])  # fmt: skip
    with pytest.raises(InvalidInputError, match="rotor_momentum"):
        build_basilisk(inertia=np.eye(3), mass=1.0, q0=[1.0, 0.0, 0.0, 0.0],
                       omega0=[0.0, 0.0, 1.0], rotor_momentum=[0.0, 0.0, 0.0])  # fmt: skip
