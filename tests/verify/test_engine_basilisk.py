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

from poinsot.verify._basilisk import mrp_to_quat, quat_to_mrp, run_basilisk  # noqa: E402

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
    assert eng.skip_reason(cases("body-torque")[0])
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
