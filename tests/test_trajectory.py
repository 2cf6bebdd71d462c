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
