"""A diverging compiled run raises the documented IntegrationError (not a raw
SystemError from the parallel kernel), and HeavyRigidBody.simulate reads tolerances
as poinsot.dynamics.simulate does."""

import warnings

import numpy as np
import pytest

import poinsot
from poinsot.dynamics import GravityTorque, HeavyRigidBody, simulate
from poinsot.errors import IntegrationError

T = np.linspace(0.0, 100.0, 3)


@pytest.mark.parametrize("batch", [False, True])
def test_compiled_rk4_blow_up_is_an_integration_error(batch):
    """Steps of 10 s on a top spinning at 5e3 rad/s overflow: the quaternion's norm
    becomes inf/0 (this raised SystemError before)."""
    top = HeavyRigidBody([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.3])
    q0 = [[1.0, 0, 0, 0]] * 2 if batch else [1.0, 0, 0, 0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        with pytest.raises(IntegrationError, match="rk4 integration diverged"):
            top.simulate(q0, [1e3, 0.0, 5e3], T, method="rk4", max_step=10.0)


def test_rk4_with_gravity_torque_blow_up_is_an_integration_error():
    with pytest.raises(IntegrationError, match="diverged"):
        simulate(
            [1.0, 2.0, 3.0],
            [1.0, 0, 0, 0],
            [1e3, 2e3, 1e3],
            T,
            method="rk4",
            max_step=10.0,
            torque=GravityTorque(1.0, [0.0, 0.0, 1e3]),
        )


def test_heavy_simulate_with_tolerances_and_no_method_matches_simulate():
    """simulate(rtol=...) picks the compiled dop853; HeavyRigidBody.simulate does the
    same instead of refusing the call; the two give the same samples."""
    top = HeavyRigidBody([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.3])
    t = np.linspace(0.0, 2.0, 5)
    a = top.simulate([1.0, 0, 0, 0], [0.1, 0.0, 5.0], t, rtol=1e-9)
    b = simulate(top.inertia_tensor, [1.0, 0, 0, 0], [0.1, 0.0, 5.0], t, rtol=1e-9,
                 torque=top.torque)  # fmt: skip
    assert a.method == b.method == "dop853"
    np.testing.assert_array_equal(a.quat, b.quat)
    # and the default without tolerances stays the structure-preserving splitting
    assert top.simulate([1.0, 0, 0, 0], [0.1, 0.0, 5.0], t, max_step=1e-2).method == "splitting"


def test_failures_mark_keeps_the_batch_and_names_the_failed_body():
    """failures='mark' (the ensembles' mode): a diverging body of a dop853 batch is held
    at its last finite state and named in info['failed']; the others equal a run of
    their own (independent: the same body alone)."""
    w0 = np.array([[0.1, 2.0, 0.1], [1e300, 1e300, 1e300]])
    t = np.linspace(0.0, 1.0, 11)
    with np.errstate(all="ignore"):
        tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], w0, t, method="dop853", failures="mark")
    assert list(tr.info["failed"]) == ["", "the state became non-finite"]
    alone = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], w0[0], t, method="dop853")
    np.testing.assert_array_equal(tr.quat[:, 0], alone.quat)
    assert np.isfinite(tr.quat).all() and np.isfinite(tr.omega).all()
    with pytest.raises(IntegrationError, match="1 of 2 bodies"):
        with np.errstate(all="ignore"):
            simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], w0, t, method="dop853")
    with pytest.raises(poinsot.InvalidInputError, match="failures='mark'"):
        simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], w0[0], t, method="rk4", failures="mark")
