"""Trajectory invariant monitoring (drifts), including a body at rest."""

from __future__ import annotations

import numpy as np

from poinsot import Rotation, Trajectory


def test_drifts_relative_and_at_rest():
    t = np.linspace(0, 1, 3)
    e = np.array([2.0, 2.002, 1.999])
    k = np.array([[0, 0, 1.0], [0, 0.001, 1.0], [0, 0, 1.002]])
    tr = Trajectory(t, Rotation.identity(3), np.zeros((3, 3)), "test", energy=e, momentum=k)
    assert np.isclose(tr.energy_drift, 0.001)
    assert np.isclose(tr.momentum_drift, 0.002)
    assert np.isclose(tr.momentum_vector_drift, 0.002)
    rest = Trajectory(
        t,
        Rotation.identity(3),
        np.zeros((3, 3)),
        "rest",
        energy=np.zeros(3),
        momentum=np.zeros((3, 3)),
    )
    assert rest.energy_drift == 0.0 and rest.momentum_drift == 0.0
    assert rest.momentum_vector_drift == 0.0
    assert tr.quat.shape == (3, 4) and tr.omega_space.shape == (3, 3)
    assert not tr.t.flags.writeable


def test_bad_construction_is_named():
    import pytest

    from poinsot import InvalidInputError, InvalidTypeError

    t = np.linspace(0, 1, 3)
    with pytest.raises(InvalidTypeError, match="`rotation`"):
        Trajectory(t, np.zeros((3, 4)), np.zeros((3, 3)), "x")
    with pytest.raises(InvalidTypeError, match="`t`"):
        Trajectory("abc", Rotation.identity(3), np.zeros((3, 3)), "x")
    with pytest.raises(InvalidInputError, match=r"`omega` to have shape \(3, 3\)"):
        Trajectory(t, Rotation.identity(3), np.zeros((3, 2)), "x")
    with pytest.raises(InvalidInputError, match="`t` to have shape"):
        Trajectory(t[:2], Rotation.identity(3), np.zeros((3, 3)), "x")


def test_pickles_with_info_and_translational_part():
    import pickle

    import pytest

    from poinsot import InvalidInputError
    from poinsot.dynamics import simulate

    t = np.linspace(0.0, 1.0, 4)
    tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 1.0, 0.1], t, method="rk4")
    back = pickle.loads(pickle.dumps(tr))
    np.testing.assert_array_equal(back.quat, tr.quat)
    np.testing.assert_array_equal(back.omega, tr.omega)
    np.testing.assert_array_equal(back.momentum, tr.momentum)
    assert dict(back.info) == dict(tr.info) and back.info["steps"] == 3
    with pytest.raises(TypeError):
        back.info["steps"] = 1  # read-only mapping
    pos = np.arange(12.0).reshape(4, 3)
    moving = Trajectory(t, tr.rotation, tr.omega, "x", position=pos, velocity=np.ones((4, 3)))
    again = pickle.loads(pickle.dumps(moving))
    np.testing.assert_array_equal(again.position, pos)
    assert not again.position.flags.writeable and again.velocity.shape == (4, 3)
    with pytest.raises(InvalidInputError, match=r"`position` to have shape \(4, 3\)"):
        Trajectory(t, tr.rotation, tr.omega, "x", position=np.ones((3, 3)))


def test_info_keys_used_by_the_library_are_documented():
    from poinsot.dynamics import simulate
    from poinsot.kinematics import propagate
    from poinsot.trajectory import INFO_KEYS

    t = np.linspace(0.0, 1.0, 3)
    runs = [
        simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 1.0, 0.1], t, method=m)
        for m in ("midpoint", "splitting", "rk4", "adaptive")
    ]
    runs.append(
        simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 1.0, 0.1], t, torque=lambda tn, r, w: -w)
    )
    t4 = np.linspace(0.0, 1.0, 4)
    w = np.tile([0.0, 0.0, 1.0], (4, 1))
    runs.append(propagate([1.0, 0, 0, 0], w, t4))
    runs.append(propagate([1.0, 0, 0, 0], w, t4, method="adaptive"))
    for tr in runs:
        assert set(tr.info) <= set(INFO_KEYS), (tr.method, set(tr.info) - set(INFO_KEYS))


def test_info_keys_of_the_exact_solutions_are_documented():
    from poinsot.dynamics import FreeRigidBody
    from poinsot.trajectory import INFO_KEYS

    t = np.linspace(0.0, 1.0, 3)
    tr = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 1.0, 0.1]).trajectory(t)
    assert set(tr.info) <= set(INFO_KEYS), set(tr.info) - set(INFO_KEYS)
