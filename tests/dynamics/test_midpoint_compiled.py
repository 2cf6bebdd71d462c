"""``method="midpoint"`` under attitude-dependent built-in torques runs compiled.

The compiled path (``_fused.midpoint_batch``) must give the NumPy path's results
(the same step, taken when the torque is a Python callable) to round-off, the
exact Lagrange top (theory §10) to the method's accuracy, and bit-identical
results for any number of threads.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest

from poinsot import Rotation
from poinsot.dynamics import (
    ConstantSpaceTorque,
    GravityGradientTorque,
    GravityTorque,
    HeavyRigidBody,
    LagrangeTop,
    simulate,
)
from poinsot.rotations import set_num_threads

J = np.array([[1.2, 0.1, -0.05], [0.1, 1.6, 0.02], [-0.05, 0.02, 2.1]])
Q0 = Rotation.from_euler("ZXZ", [0.3, 0.8, -0.2]).as_quat()
W0 = np.array([1.0, -2.0, 6.0])

MODELS = {
    "space": ConstantSpaceTorque([0.3, -0.2, 0.5]),
    "gravity": GravityTorque(2.0, [0.05, -0.02, 0.3], g=9.81),
    "gradient": GravityGradientTorque(J, 7.0e6, [0.6, 0.0, 0.8]),
}


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("order", [2, 4])
def test_compiled_midpoint_equals_the_numpy_step(name, order):
    model = MODELS[name]
    t = np.linspace(0.0, 2.0, 21)

    def as_python(tt, r, w):
        return model.body_torque(tt, r.as_quat(), w)

    fast = simulate(J, Q0, W0, t, torque=model, method="midpoint", order=order, max_step=2e-3)
    slow = simulate(J, Q0, W0, t, torque=as_python, method="midpoint", order=order, max_step=2e-3)
    assert "path" not in fast.info and slow.info["path"].startswith("NumPy")
    # observed <= 8.4e-14 over 1000 steps (the Newton iterations stop per body here, for
    # the whole batch in NumPy: both at round-off)
    np.testing.assert_allclose(fast.omega, slow.omega, rtol=0, atol=1e-12)
    dq = np.minimum(
        np.abs(fast.rotation.as_quat() - slow.rotation.as_quat()).max(-1),
        np.abs(fast.rotation.as_quat() + slow.rotation.as_quat()).max(-1),
    )
    assert dq.max() < 1e-12  # observed 2.5e-14
    assert fast.info["max_newton_iterations"] >= 1


def test_compiled_midpoint_follows_the_exact_lagrange_top():
    body = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.4], g=10.0)
    r0 = Rotation.from_euler("ZXZ", [0.0, 0.5, 0.0])
    w0 = [0.3, 0.0, 20.0]
    top = LagrangeTop.from_state(body, None, r0, w0)
    t = np.linspace(0.0, 2.0, 5)
    exact = top.rotation(t).as_quat()
    errors = []
    for h in (4e-3, 2e-3):  # max_step: 500 and 1000 steps
        tr = body.simulate(r0, w0, t, method="midpoint", order=4, max_step=h)
        q = tr.rotation.as_quat()
        errors.append(np.minimum(np.abs(q - exact), np.abs(q + exact)).max())
    # fourth order: halving the step divides the error by about 16 (observed 15.9 and,
    # at 1e-3, 16.0); observed errors 4.9e-5 and 3.0e-6
    assert 14.0 < errors[0] / errors[1] < 18.0
    assert errors[1] < 3e-5


def test_compiled_midpoint_is_bit_identical_for_any_thread_count():
    rng = np.random.default_rng(2)
    q0 = rng.normal(size=(7, 4))
    q0 /= np.linalg.norm(q0, axis=1, keepdims=True)
    w0 = rng.normal(size=(7, 3)) + [0.0, 0.0, 5.0]
    body = HeavyRigidBody(J, 2.0, [0.05, -0.02, 0.3], g=9.81)
    t = np.linspace(0.0, 1.0, 11)
    before = numba.get_num_threads()
    try:  # poinsot's setting: exactly n threads (the default would take the idle cores)
        set_num_threads(1)
        one = body.simulate(q0, w0, t, method="midpoint", max_step=1e-2)
        set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = body.simulate(q0, w0, t, method="midpoint", max_step=1e-2)
    finally:
        set_num_threads(before)
        set_num_threads(None)
    np.testing.assert_array_equal(one.omega, many.omega)
    np.testing.assert_array_equal(one.rotation.as_quat(), many.rotation.as_quat())
    # each body of the batch as if alone
    alone = body.simulate(q0[3], w0[3], t, method="midpoint", max_step=1e-2)
    np.testing.assert_array_equal(alone.omega, one.omega[:, 3])
