"""Euler's dynamic equations ``J w' = M - w x J w`` (SPEC S10): ``euler_rhs``."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError, InvalidTypeError
from poinsot.dynamics import euler_rhs

RNG = np.random.default_rng(20261122)


def _physical_moments(n):
    """Random principal moments obeying the triangle inequality."""
    return RNG.uniform(1.5, 2.9, size=(n, 3))  # any two sum to >= 3 > the third


def test_principal_axes_match_spec_component_form():
    """SPEC S10: A p' + (C - B) q r = M1, B q' + (A - C) r p = M2, C r' + (B - A) p q = M3."""
    moments = _physical_moments(20)
    w = RNG.normal(size=(20, 3))
    m = RNG.normal(size=(20, 3))
    a, b, c = moments.T
    p, q, r = w.T
    expected = np.stack(
        [
            (m[:, 0] - (c - b) * q * r) / a,
            (m[:, 1] - (a - c) * r * p) / b,
            (m[:, 2] - (b - a) * p * q) / c,
        ],
        axis=-1,
    )
    np.testing.assert_allclose(euler_rhs(moments, w, m), expected, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(
        euler_rhs(moments, w), euler_rhs(moments, w, np.zeros(3)), rtol=0, atol=0
    )


def test_general_tensor_is_principal_result_rotated():
    """``J_b = S diag(I) S^T``, ``w_b = S w_p``  =>  ``w_b' = S w_p'`` (SPEC S8 change of axes)."""
    moments = _physical_moments(10)
    s = SciRotation.random(10, 1).as_matrix()
    j_b = s @ (moments[:, :, None] * np.eye(3)) @ np.swapaxes(s, -1, -2)
    w_p = RNG.normal(size=(10, 3))
    m_p = RNG.normal(size=(10, 3))
    w_b = np.einsum("nij,nj->ni", s, w_p)
    m_b = np.einsum("nij,nj->ni", s, m_p)
    expected = np.einsum("nij,nj->ni", s, euler_rhs(moments, w_p, m_p))
    np.testing.assert_allclose(euler_rhs(j_b, w_b, m_b), expected, rtol=1e-11, atol=1e-12)


def test_diagonal_tensor_equals_moments_and_broadcasts():
    moments = np.array([1.0, 2.0, 2.5])
    w = RNG.normal(size=(4, 5, 3))
    out = euler_rhs(np.diag(moments), w)
    assert out.shape == (4, 5, 3)
    np.testing.assert_allclose(out, euler_rhs(moments, w), rtol=1e-14, atol=1e-15)


def test_rotation_about_principal_axis_is_steady_and_energy_rate_is_power():
    """Free rotation about a principal axis is a steady state; ``dT/dt = w . M``."""
    for axis in range(3):
        w = np.zeros(3)
        w[axis] = 2.0
        np.testing.assert_array_equal(euler_rhs([1.0, 2.0, 3.0], w), np.zeros(3))
    moments = np.array([1.0, 2.0, 3.0])
    w = RNG.normal(size=(50, 3))
    m = RNG.normal(size=(50, 3))
    dt = np.sum(moments * w * euler_rhs(moments, w, m), axis=-1)  # d/dt (w.Jw/2)
    np.testing.assert_allclose(dt, np.sum(w * m, axis=-1), rtol=1e-12, atol=1e-12)
    # |K|^2 changes at 2 K.M only
    dk2 = 2 * np.sum(moments * w * moments * euler_rhs(moments, w, m), axis=-1)
    np.testing.assert_allclose(dk2, 2 * np.sum(moments * w * m, axis=-1), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    ("inertia", "match"),
    [
        ([1.0, 1.0, 3.0], "triangle inequality"),
        ([1.0, -2.0, 2.0], "positive definite"),
        (np.diag([1.0, 1.0, 3.0]), "triangle inequality"),
        ([[1.0, 0.5, 0], [0, 1.0, 0], [0, 0, 1.0]], "symmetric"),
        ([1.0, 2.0], r"shape \(\.\.\., 3\)"),
        ([1.0, np.nan, 2.0], "finite"),
    ],
)
def test_non_physical_inertia_is_rejected(inertia, match):
    with pytest.raises(InvalidInputError, match=match) as info:
        euler_rhs(inertia, [1.0, 0.0, 0.0])
    assert "`inertia`" in str(info.value)


def test_bad_omega_and_torque():
    with pytest.raises(InvalidInputError, match="`omega`.*finite"):
        euler_rhs([1.0, 2.0, 3.0], [np.nan, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"`omega` to have shape \(\.\.\., 3\)"):
        euler_rhs([1.0, 2.0, 3.0], [1.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"`torque` to have shape"):
        euler_rhs([1.0, 2.0, 3.0], [1.0, 0.0, 0.0], torque=[1.0])
    with pytest.raises(InvalidTypeError, match="`omega`"):
        euler_rhs([1.0, 2.0, 3.0], "abc")
    with pytest.raises(InvalidInputError, match="to broadcast"):
        euler_rhs(np.ones((2, 3)) + [0, 1, 1], np.ones((5, 3)))


def test_single_state_short_path_matches_the_batch_path_bit_for_bit():
    """The scalar short path (issue 9: one state within 2x of hand NumPy) computes the
    same floating-point operations as the vectorised path and keeps its checks."""
    rng = np.random.default_rng(9)
    for _ in range(200):
        j = np.sort(rng.uniform(0.5, 3.0, 3))
        j[2] = min(j[2], j[0] + j[1])
        w, m = rng.normal(size=3), rng.normal(size=3)
        for inertia, omega, torque in ((j, w, None), (list(j), tuple(w), list(m)), (j, w, m)):
            fast = euler_rhs(inertia, omega, torque)
            slow = euler_rhs(
                np.asarray(inertia)[None],
                np.asarray(omega)[None],
                None if torque is None else np.asarray(torque)[None],
            )[0]
            np.testing.assert_array_equal(fast, slow)
            assert fast.shape == (3,) and fast.dtype == np.float64
    # the checks are the general path's: same errors, same messages
    with pytest.raises(InvalidInputError, match="triangle inequality"):
        euler_rhs([1.0, 1.0, 2.5], [0.0, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match="positive definite"):
        euler_rhs([0.0, 1.0, 1.0], [0.0, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        euler_rhs([1.0, 2.0, 3.0], [np.nan, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match="`torque` to contain only finite"):
        euler_rhs([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], [np.inf, 0.0, 0.0])
    with pytest.raises(InvalidTypeError, match="`omega`"):
        euler_rhs([1.0, 2.0, 3.0], ["a", "b", "c"])
    # integers are numbers, booleans and tensors take the general path
    np.testing.assert_array_equal(
        euler_rhs([1, 2, 3], [1, 1, 1]), euler_rhs([1.0, 2.0, 3.0], [1.0, 1.0, 1.0])
    )
    np.testing.assert_allclose(
        euler_rhs(np.diag([1.0, 2.0, 3.0]), [1.0, 1.0, 1.0]),
        euler_rhs([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]),
        rtol=1e-15,
    )
