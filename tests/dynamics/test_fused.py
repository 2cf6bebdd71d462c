"""The compiled adaptive DOP853 (``simulate(method="dop853")``).

References: the exact Euler-Poinsot solution (``FreeRigidBody``, ~1e-14) for free
bodies; for torques, SciPy's ``solve_ivp(DOP853)`` at ``rtol = 1e-13`` driven by
the NumPy torque models (an independent code path for the torque formulas) and
the conserved quantities of the heavy top (energy ``T + V``, ``K . e_z``).
"""

from __future__ import annotations

import numba
import numpy as np
import pytest

from poinsot import Rotation
from poinsot.dynamics import (
    ConstantBodyTorque,
    ConstantSpaceTorque,
    FreeRigidBody,
    GravityGradientTorque,
    GravityTorque,
    GyrostaticTorque,
    invariants,
    simulate,
)
from poinsot.errors import IntegrationError, InvalidInputError
from poinsot.rotations import set_num_threads


def _bodies(n, seed=1):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))  # triangle inequality holds
    omega = rng.normal(size=(n, 3))
    quat = Rotation.random(n, rng=rng).as_quat() if hasattr(Rotation, "random") else None
    if quat is None:
        quat = rng.normal(size=(n, 4))
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return moments, quat, omega


def _attitude_error(q, p):
    """Rotation angle between unit quaternions (either sign), small-angle form."""
    d = np.minimum(np.linalg.norm(q - p, axis=-1), np.linalg.norm(q + p, axis=-1))
    return 2.0 * d


def _exact(moments, quat, omega, t):
    qs, ws = [], []
    for m, q, w in zip(moments, quat, omega, strict=True):
        body = FreeRigidBody(m, rotation0=q, omega0=w)
        qs.append(body.rotation(t).as_quat())
        ws.append(body.omega(t))
    return np.stack(qs, axis=1), np.stack(ws, axis=1)


def test_free_bodies_match_exact_solution():
    moments, quat, omega = _bodies(12)
    t = np.linspace(0.0, 20.0, 41)
    tr = simulate(moments, quat, omega, t, rtol=1e-12, atol=1e-14)
    assert tr.method == "dop853"
    q_ref, w_ref = _exact(moments, quat, omega, t)
    # observed ~3e-12 (also with NUMBA_CPU_NAME=generic); exact solution ~1e-14
    assert _attitude_error(tr.quat, q_ref).max() < 1e-9
    assert np.abs(tr.omega - w_ref).max() < 1e-9
    assert np.allclose(np.linalg.norm(tr.quat, axis=-1), 1.0, rtol=0, atol=3e-15)  # 1 ulp seen


def test_measured_order_is_eight_with_projection():
    """Fixed steps (tolerances so loose that every step is accepted at ``max_step``):
    halving the step divides the error by ~2^8 although |q| is projected each step."""
    moments, quat, omega = _bodies(4, seed=3)
    t = np.array([0.0, 6.0])
    q_ref, w_ref = _exact(moments, quat, omega, t)
    errors = []
    for h in (0.6, 0.3):
        tr = simulate(moments, quat, omega, t, method="dop853", rtol=1e3, atol=1e3, max_step=h)
        assert np.all(tr.info["rejected"] == 0)
        errors.append(
            max(
                _attitude_error(tr.quat[-1], q_ref[-1]).max(),
                np.abs(tr.omega[-1] - w_ref[-1]).max(),
            )
        )
    ratio = errors[0] / errors[1]
    assert errors[1] > 1e-12  # still far above round-off, so the ratio measures the order
    assert ratio > 2.0**6.5, (errors, ratio)  # observed 255 = 2^8


@pytest.mark.parametrize(
    "torque",
    [
        ConstantBodyTorque([0.05, -0.02, 0.03]),
        ConstantSpaceTorque([0.1, 0.0, -0.05]),
        GravityTorque(2.0, [0.01, -0.02, 0.1]),
        "gradient",
        GyrostaticTorque(
            [[0.0, 0.0, 0.8], [0.3, -0.4, 0.2], [0.0, 1.5, 0.0], [0.1, 0.1, 0.1], [-0.6, 0.0, 0.3]]
        ),  # fmt: skip
    ],
    ids=["body", "space", "gravity", "gravity-gradient", "gyrostat"],
)
def test_fused_torques_match_solve_ivp(torque):
    moments, quat, omega = _bodies(5, seed=7)
    if torque == "gradient":  # the field sees the same inertia as the integrator
        moments = np.broadcast_to(moments[0], moments.shape)
        torque = GravityGradientTorque(moments[0], 7.0e6, [0.3, -0.4, 0.8], mu=3.986e14 * 1e5)
    t = np.linspace(0.0, 5.0, 11)
    fused = simulate(
        moments, quat, omega, t, torque=torque, method="dop853", rtol=1e-12, atol=1e-14
    )
    ref = simulate(
        moments, quat, omega, t, torque=torque, method="adaptive", rtol=1e-13, atol=1e-15
    )
    # observed <= 2e-11; the reference's own error ~1e-12
    assert _attitude_error(fused.quat, ref.quat).max() < 1e-9
    assert np.abs(fused.omega - ref.omega).max() < 1e-9


def test_heavy_top_conserves_energy_and_area_integral():
    inertia = np.array([1.2, 1.2, 0.5])
    grav = GravityTorque(1.0, [0.0, 0.0, 0.3], g=9.81)
    q0 = Rotation.from_euler("ZXZ", [0.0, 0.6, 0.0]).as_quat()
    w0 = np.array([0.4, 0.0, 12.0])
    t = np.linspace(0.0, 30.0, 3001)
    tr = simulate(inertia, q0, w0, t, torque=grav, rtol=1e-12, atol=1e-14)
    inv = invariants(inertia, tr.quat, tr.omega, torque=grav)
    e, kz = inv.energy, inv.momentum_z
    # observed ~2e-12 relative over 30 s
    assert np.abs(e - e[0]).max() < 1e-9 * abs(e[0])
    assert np.abs(kz - kz[0]).max() < 1e-9 * np.abs(inv.momentum_space[0]).max()


def test_dense_output_matches_runs_ending_there():
    moments, quat, omega = _bodies(4, seed=11)
    t = np.linspace(0.0, 4.0, 401)
    dense = simulate(moments, quat, omega, t, rtol=1e-12, atol=1e-14)
    for k in (37, 200, 333):
        end = simulate(moments, quat, omega, [0.0, t[k]], rtol=1e-12, atol=1e-14)
        # both ~1e-12 from the truth: their difference bounds the dense-output error
        assert _attitude_error(dense.quat[k], end.quat[-1]).max() < 1e-9
        assert np.abs(dense.omega[k] - end.omega[-1]).max() < 1e-9


def test_results_bit_identical_for_any_thread_count():
    moments, quat, omega = _bodies(64, seed=5)
    t = np.linspace(0.0, 3.0, 7)
    before = numba.get_num_threads()
    try:  # poinsot's setting: exactly n threads (the default would take the idle cores)
        set_num_threads(1)
        one = simulate(moments, quat, omega, t, rtol=1e-10)
        set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = simulate(moments, quat, omega, t, rtol=1e-10)
    finally:
        set_num_threads(before)
        set_num_threads(None)
    assert np.array_equal(one.quat, many.quat)
    assert np.array_equal(one.omega, many.omega)


@pytest.mark.parametrize("torque", [None, GravityTorque(1.0, [0.02, 0.0, 0.1])])
def test_one_body_on_the_calling_thread_equals_it_in_a_batch(monkeypatch, torque):
    # on a cold cache one body runs the serial kernel (no parallel region to compile); it
    # must give the batch kernel's results bit for bit, the body's own step control
    # unchanged
    from poinsot import _jit
    from poinsot.dynamics import _fused, _fused_run

    moments, quat, omega = _bodies(4, seed=7)  # fewer than the lanes take
    t = np.linspace(0.0, 2.0, 9)
    batch = simulate(moments, quat, omega, t, torque=torque, rtol=1e-10)
    monkeypatch.setattr(_fused_run, "ready", lambda fn, match=None: False)  # "cold"
    for b in range(4):
        one = simulate(moments[b], quat[b], omega[b], t, torque=torque, rtol=1e-10)
        assert np.array_equal(one.quat, batch.quat[:, b])
        assert np.array_equal(one.omega, batch.omega[:, b])
        assert one.info["steps"] == batch.info["steps"][b]
        if torque is None:  # and the exact solution (observed <= 2.2e-10 at rtol 1e-10)
            q_ex, w_ex = _exact(moments[b : b + 1], quat[b : b + 1], omega[b : b + 1], t)
            assert _attitude_error(one.quat, q_ex[:, 0]).max() < 1e-8
            assert np.abs(one.omega - w_ex[:, 0]).max() < 1e-8
    if _jit.NUMBA:  # (the NumPy executor runs the same source as Python)
        assert _fused.integrate_serial.signatures  # the serial kernel ran


def test_default_method_follows_the_request():
    args = ([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], [0.0, 1.0])
    assert simulate(*args, rtol=1e-8).method == "dop853"
    assert simulate(*args, atol=1e-10).method == "dop853"
    assert simulate(*args).method == "midpoint"


def test_callable_torque_takes_the_slower_path():
    args = ([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 2, 5))
    m = np.array([0.01, 0.02, -0.01])
    tr = simulate(*args, torque=lambda t, r, w: m, method="dop853", rtol=1e-12, atol=1e-14)
    assert "solve_ivp" in tr.info["path"]
    ref = simulate(*args, torque=ConstantBodyTorque(m), method="dop853", rtol=1e-12, atol=1e-14)
    assert np.abs(tr.omega - ref.omega).max() < 1e-9


def test_bad_options_and_divergence_are_named():
    args = ([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], [0.0, 1.0])
    with pytest.raises(InvalidInputError, match="`solver` applies to method='adaptive'"):
        simulate(*args, method="dop853", solver="RK45")
    with pytest.raises(IntegrationError, match="dop853 integration failed for 1 of 1 bodies"):
        simulate(
            [1.0, 2.0, 3.0], [1.0, 0, 0, 0], [1e300, 1e300, 1e300], [0.0, 1.0], method="dop853"
        )
