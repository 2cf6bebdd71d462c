"""SciPy interop: the scalar-first/scalar-last trap, from_scipy / to_scipy, checked
against SciPy's own quaternions and rotated vectors (SciPy as the oracle)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation

RNG = np.random.default_rng(11)
SR = SciPyRotation.random(50, random_state=3)
V = RNG.normal(size=(50, 3))


def test_from_scipy_applies_like_scipy():
    r = Rotation.from_scipy(SR)
    assert r.shape == (50,)
    np.testing.assert_allclose(r.apply(V), SR.apply(V), atol=1e-14)
    np.testing.assert_allclose(r.as_quat(scalar_first=False), SR.as_quat(), atol=1e-15)
    one = Rotation.from_scipy(SR[3])
    assert one.shape == ()
    np.testing.assert_allclose(one.apply(V[0]), SR[3].apply(V[0]), atol=1e-14)


def test_to_scipy_round_trip_and_batches():
    r = Rotation.from_scipy(SR)
    back = r.to_scipy()
    np.testing.assert_allclose(back.as_matrix(), SR.as_matrix(), atol=1e-15)
    grid = (
        r.reshape(5, 10)
        if hasattr(r, "reshape")
        else Rotation.from_quat(r.as_quat().reshape(5, 10, 4))
    )
    np.testing.assert_allclose(grid.to_scipy().as_matrix(), SR.as_matrix(), atol=1e-15)
    np.testing.assert_allclose(r[7].to_scipy().apply(V[7]), SR[7].apply(V[7]), atol=1e-14)


def test_scalar_first_keyword_matches_scipy_both_ways():
    q_last = SR.as_quat()
    a = Rotation.from_quat(q_last, scalar_first=False)
    b = Rotation.from_quat(SR.as_quat(scalar_first=True), scalar_first=True)
    np.testing.assert_allclose(a.as_quat(), b.as_quat(), atol=1e-15)
    np.testing.assert_allclose(a.as_quat(scalar_first=False), q_last, atol=1e-15)
    # one rotation through the fast path
    np.testing.assert_allclose(
        Rotation.from_quat(q_last[0], scalar_first=False).apply(V[0]), SR[0].apply(V[0]), atol=1e-14
    )


def test_the_trap_is_documented_and_real():
    """Reading SciPy's scalar-last quaternion as scalar first gives another rotation:
    the docstring of from_quat warns about it."""
    wrong = Rotation.from_quat(SR[0].as_quat())
    assert not np.allclose(wrong.apply(V[0]), SR[0].apply(V[0]), atol=1e-6)
    assert "scalar last" in Rotation.from_quat.__doc__
    assert "from_scipy" in Rotation.from_quat.__doc__


def test_bad_inputs_name_the_argument():
    with pytest.raises(InvalidTypeError, match="`rotation` to be a scipy"):
        Rotation.from_scipy(np.eye(3))
    with pytest.raises(InvalidTypeError, match="scalar_first"):
        Rotation.from_quat([1.0, 0, 0, 0], scalar_first="no")
    with pytest.raises(InvalidInputError):
        Rotation.from_quat([0.0, 0, 0, 0], scalar_first=False)


def test_scipy_rotation_where_a_poinsot_one_is_expected_says_how_to_convert():
    with pytest.raises(InvalidTypeError, match="from_scipy"):
        Rotation.identity() * SR[0]
