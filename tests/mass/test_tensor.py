"""Inertia tensor operations: validation, points, Huygens-Steiner, rotation, principal axes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import Rotation
from poinsot.errors import InvalidInputError
from poinsot.mass import (
    box,
    check_inertia,
    check_principal_moments,
    cylinder,
    disc,
    inertia_ellipsoid,
    moment_about,
    parallel_axis,
    points,
    principal_axes,
    rod,
    rotate_inertia,
    sphere,
    to_center_of_mass,
)


def _random_cloud(rng, n=7):
    return rng.uniform(0.1, 2.0, n), rng.normal(size=(n, 3))


def _brute_force(masses, positions):
    """J_O = sum m (|r|^2 E - r r^T), entry by entry (SPEC S8), with plain loops."""
    j = np.zeros((3, 3))
    for m, r in zip(masses, positions, strict=True):
        for i in range(3):
            for k in range(3):
                j[i, k] += m * ((r @ r if i == k else 0.0) - r[i] * r[k])
    return j


def _random_inertia(rng, shape=()):
    """Physical tensors of random point clouds (always valid by construction)."""
    m = rng.uniform(0.1, 2.0, shape + (6,))
    r = rng.normal(size=shape + (6, 3))
    return points(m, r)


# -- points -------------------------------------------------------------------


def test_points_against_brute_force():
    rng = np.random.default_rng(0)
    for _ in range(5):
        m, r = _random_cloud(rng)
        np.testing.assert_allclose(points(m, r), _brute_force(m, r), rtol=1e-13, atol=1e-14)
    # textbook entries: diagonal int (y^2 + z^2) dm, off-diagonal -int x y dm
    j = points([2.0], [[1.0, 2.0, 3.0]])
    np.testing.assert_allclose(j[0], [2 * 13, -2 * 2, -2 * 3])
    np.testing.assert_allclose(j[1, 2], -2 * 6)


def test_points_batch():
    rng = np.random.default_rng(1)
    m = rng.uniform(0.1, 1.0, (4, 5))
    r = rng.normal(size=(4, 5, 3))
    j = points(m, r)
    assert j.shape == (4, 3, 3)
    np.testing.assert_allclose(j[2], _brute_force(m[2], r[2]), rtol=1e-13)


def test_points_errors():
    with pytest.raises(InvalidInputError, match=r"`positions` to have shape \(\.\.\., n, 3\)"):
        points([1.0], [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match="same n, got 2 and 3"):
        points([1.0, 1.0], np.zeros((3, 3)))
    with pytest.raises(InvalidInputError, match=r"`masses` to have shape \(\.\.\., n\)"):
        points(1.0, np.zeros((1, 3)))
    with pytest.raises(InvalidInputError, match="`masses` to be positive"):
        points([1.0, 0.0], np.zeros((2, 3)))


# -- check_inertia ------------------------------------------------------------------


def test_check_inertia_accepts_physical_and_symmetrises():
    j = box(1.0, 1.0, 2.0, 3.0)
    np.testing.assert_array_equal(check_inertia(j), j)
    slightly = j + np.array([[0, 1e-12, 0], [0, 0, 0], [0, 0, 0]])
    out = check_inertia(slightly)
    np.testing.assert_array_equal(out, out.T)
    # equality cases of the triangle inequality (plane figures) pass
    check_inertia(disc(1.0, 1.0))
    # a rod is only positive semi-definite
    check_inertia(rod(1.0, 1.0), allow_singular=True)
    assert check_inertia(np.zeros((3, 3)), allow_singular=True).shape == (3, 3)


def test_check_inertia_errors():
    with pytest.raises(InvalidInputError, match=r"`J` to have shape \(\.\.\., 3, 3\), got \(3,\)"):
        check_inertia([1.0, 2.0, 3.0], "J")
    with pytest.raises(InvalidInputError, match="`inertia` to contain only finite"):
        check_inertia(np.diag([1.0, np.nan, 1.0]))
    asym = np.diag([2.0, 2.0, 2.0])
    asym[0, 1] = 0.1
    with pytest.raises(InvalidInputError, match=r"`inertia` to be symmetric, got max \|J - J\^T\|"):
        check_inertia(asym)
    with pytest.raises(InvalidInputError, match="to be positive definite .* smallest principal"):
        check_inertia(rod(1.0, 1.0))
    with pytest.raises(InvalidInputError, match="to be positive semi-definite"):
        check_inertia(np.diag([-1.0, 2.0, 2.0]), allow_singular=True)
    with pytest.raises(InvalidInputError, match=r"violates the triangle inequality A \+ B >= C"):
        check_inertia(np.diag([1.0, 1.0, 2.5]))
    # a positive definite but non-physical tensor, off the axes
    r = SciRotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()
    with pytest.raises(InvalidInputError, match=r"A \+ B = 3 < C = 4"):
        check_inertia(r @ np.diag([1.0, 2.0, 4.0]) @ r.T)
    with pytest.raises(InvalidInputError, match="`rtol` and `atol` to be >= 0"):
        check_inertia(np.eye(3), rtol=-1.0)


def test_check_inertia_tolerance_and_batch_index():
    j = np.diag([1.0, 1.0, 2.0 + 1e-7])
    with pytest.raises(InvalidInputError, match="triangle"):
        check_inertia(j)
    check_inertia(j, rtol=1e-6)
    check_inertia(j, atol=1e-6)
    batch = np.stack([np.eye(3), np.eye(3), np.diag([1.0, 1.0, 3.0])])
    with pytest.raises(InvalidInputError, match=r"at batch index \(2,\)"):
        check_inertia(batch)


def test_check_principal_moments():
    np.testing.assert_array_equal(check_principal_moments([3.0, 1.0, 2.0]), [3.0, 1.0, 2.0])
    with pytest.raises(InvalidInputError, match=r"`moments` is not a physical .*A \+ B >= C"):
        check_principal_moments([5.0, 1.0, 2.0])
    with pytest.raises(InvalidInputError, match="`moments` to be positive definite"):
        check_principal_moments([1.0, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match=r"`I` to have shape \(\.\.\., 3\)"):
        check_principal_moments([1.0, 1.0], "I")


# -- parallel axis ------------------------------------------------------------------


def test_parallel_axis_textbook_and_points():
    # thin rod about its end: m L^2 / 3 (e.g. Landau-Lifshitz Sec. 32)
    np.testing.assert_allclose(parallel_axis(rod(3.0, 2.0), 3.0, [0, 0, 1.0])[0, 0], 3.0 * 4 / 3)
    # solid sphere about a tangent line: 7/5 m r^2
    np.testing.assert_allclose(parallel_axis(sphere(1.0, 1.0), 1.0, [0, 1.0, 0])[0, 0], 1.4)
    # against point masses: a cloud's J about O = J about C + Steiner
    rng = np.random.default_rng(2)
    m, r = _random_cloud(rng)
    c = m @ r / m.sum()
    j_c = _brute_force(m, r - c)
    np.testing.assert_allclose(parallel_axis(j_c, m.sum(), -c), _brute_force(m, r), rtol=1e-12)


def test_parallel_axis_round_trip_and_axis_form():
    rng = np.random.default_rng(3)
    j_c = _random_inertia(rng, (5,))
    m = rng.uniform(0.5, 2.0, 5)
    a = rng.normal(size=(5, 3))
    j_o = parallel_axis(j_c, m, a)
    np.testing.assert_allclose(to_center_of_mass(j_o, m, a), j_c, atol=1e-12)
    # J_Oe = J_Ce + m d^2, d the distance between the parallel axes along e
    e = rng.normal(size=(5, 3))
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    d2 = np.sum(a * a, -1) - np.sum(a * e, -1) ** 2
    np.testing.assert_allclose(moment_about(j_o, e), moment_about(j_c, e) + m * d2, rtol=1e-12)


def test_to_center_of_mass_inconsistent():
    with pytest.raises(
        InvalidInputError, match="`inertia_o`, `mass` and `offset` are inconsistent"
    ):
        to_center_of_mass(sphere(1.0, 1.0), 1.0, [0, 0, 2.0])
    with pytest.raises(InvalidInputError, match="`mass` to be positive"):
        parallel_axis(sphere(1.0, 1.0), 0.0, [0, 0, 1.0])
    with pytest.raises(InvalidInputError, match=r"`offset` to have shape \(\.\.\., 3\)"):
        parallel_axis(sphere(1.0, 1.0), 1.0, [0, 1.0])
    with pytest.raises(InvalidInputError, match="`inertia_cm` is not a physical"):
        parallel_axis(np.diag([1.0, 1.0, 3.0]), 1.0, [0, 0, 1.0])


# -- rotate_inertia ------------------------------------------------------------------


def test_rotate_inertia_convention_against_points():
    """J_b = S^T J_a S with S = C_ab: compare with the points' coordinates in both frames."""
    rng = np.random.default_rng(4)
    m, r_a = _random_cloud(rng)
    c_ab = SciRotation.random(random_state=5).as_matrix()
    r_b = r_a @ c_ab  # v_b = C_ab^T v_a, row-wise
    j_a, j_b = points(m, r_a), points(m, r_b)
    np.testing.assert_allclose(rotate_inertia(j_a, c_ab), j_b, atol=1e-12)
    np.testing.assert_allclose(rotate_inertia(j_b, c_ab.T), j_a, atol=1e-12)
    rot = Rotation.from_matrix(c_ab)
    np.testing.assert_allclose(rotate_inertia(j_a, rot), j_b, atol=1e-12)
    np.testing.assert_allclose(rotate_inertia(j_b, rot.inv()), j_a, atol=1e-12)


def test_rotate_inertia_batch_and_invariants():
    rng = np.random.default_rng(6)
    j = _random_inertia(rng, (4,))
    s = SciRotation.random(4, random_state=7).as_matrix()
    out = rotate_inertia(j, s)
    assert out.shape == (4, 3, 3)
    np.testing.assert_allclose(np.linalg.eigvalsh(out), np.linalg.eigvalsh(j), rtol=1e-12)
    np.testing.assert_allclose(np.trace(out, axis1=-2, axis2=-1), np.trace(j, axis1=-2, axis2=-1))
    # one rotation broadcast against a batch of tensors
    out1 = rotate_inertia(j, s[0])
    np.testing.assert_allclose(out1[3], s[0].T @ j[3] @ s[0], atol=1e-12)


def test_rotate_inertia_errors():
    with pytest.raises(
        InvalidInputError, match=r"`rotation` to be a rotation matrix \(S\^T S = E within 1e-06\)"
    ):
        rotate_inertia(np.eye(3), 2 * np.eye(3))
    with pytest.raises(InvalidInputError, match=r"proper rotation matrix \(det \+1\)"):
        rotate_inertia(np.eye(3), np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidInputError, match=r"`rotation` to have shape \(\.\.\., 3, 3\)"):
        rotate_inertia(np.eye(3), [1.0, 0, 0, 0])


# -- moment_about ------------------------------------------------------------------


def test_moment_about_against_distances():
    """J_e = sum m d^2 with d the distance to the axis (computed from the cross product)."""
    rng = np.random.default_rng(8)
    m, r = _random_cloud(rng)
    axis = rng.normal(size=3) * 7.0  # not normalised on purpose
    e = axis / np.linalg.norm(axis)
    d2 = np.sum(np.cross(r, e) ** 2, axis=-1)
    np.testing.assert_allclose(moment_about(points(m, r), axis), m @ d2, rtol=1e-12)
    # batch of axes against one tensor
    out = moment_about(cylinder(1.0, 1.0, 2.0), np.eye(3))
    np.testing.assert_allclose(out, cylinder(1.0, 1.0, 2.0).diagonal())


def test_moment_about_zero_axis():
    with pytest.raises(InvalidInputError, match="`axis` to be a non-zero vector"):
        moment_about(np.eye(3), [0.0, 0.0, 0.0])


# -- principal axes ------------------------------------------------------------------


def _assert_principal(j, moments, rot):
    s = rot.as_matrix()
    np.testing.assert_allclose(np.linalg.det(s), 1.0, atol=1e-12)
    np.testing.assert_allclose(
        np.swapaxes(s, -1, -2) @ s, np.broadcast_to(np.eye(3), s.shape), atol=1e-12
    )
    assert np.all(np.diff(moments, axis=-1) >= 0)
    scale = np.max(np.abs(j))
    diag = np.swapaxes(s, -1, -2) @ j @ s
    expected = moments[..., :, None] * np.eye(3)
    np.testing.assert_allclose(diag, expected, atol=1e-12 * scale)


def test_principal_axes_random_batch():
    rng = np.random.default_rng(9)
    j = _random_inertia(rng, (50,))
    moments, rot = principal_axes(j)
    assert moments.shape == (50, 3)
    _assert_principal(j, moments, rot)
    np.testing.assert_allclose(rotate_inertia(j, rot), moments[..., None] * np.eye(3), atol=1e-12)


def test_principal_axes_recovers_rotated_box():
    """A box rotated by a known S has moments = sorted box diagonal, axes = columns of S."""
    s = SciRotation.from_rotvec([0.4, -1.1, 0.7]).as_matrix()
    j_b = box(1.0, 1.0, 2.0, 3.0)  # moments 13/12 > 10/12 > 5/12 along x, y, z
    j_a = s @ j_b @ s.T
    moments, rot = principal_axes(j_a)
    np.testing.assert_allclose(moments, [5 / 12, 10 / 12, 13 / 12], rtol=1e-13)
    axes = rot.as_matrix()
    for k, col in enumerate([2, 1, 0]):  # smallest moment along box z ...
        assert abs(abs(axes[:, k] @ s[:, col]) - 1.0) < 1e-12


@pytest.mark.parametrize(
    "j_b",
    [sphere(2.0, 1.0), box(1.0, 1.0, 1.0, 1.0), cylinder(1.0, 1.0, 0.5), np.diag([1.0, 2.0, 2.0])],
    ids=["sphere", "cube", "symmetric top", "prolate"],
)
def test_principal_axes_repeated_moments(j_b):
    s = SciRotation.from_rotvec([0.9, 0.2, -0.4]).as_matrix()
    j = s @ j_b @ s.T
    moments, rot = principal_axes(j)
    np.testing.assert_allclose(moments, np.sort(j_b.diagonal()), rtol=1e-12)
    _assert_principal(j, moments, rot)


def test_principal_axes_singular_and_deterministic():
    moments, rot = principal_axes(rod(3.0, 2.0))
    np.testing.assert_allclose(moments, [0.0, 1.0, 1.0], atol=3e-15)
    np.testing.assert_allclose(abs(rot.as_matrix()[:, 0]), [0, 0, 1.0], atol=3e-15)
    # diagonal input with distinct moments: a signed permutation, det +1
    _, rot = principal_axes(np.diag([3.0, 1.0, 2.0]))
    np.testing.assert_allclose(rot.as_matrix(), [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.05, 10.0), min_size=3, max_size=3),
    st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3),
    st.integers(0, 3),
)
def test_principal_axes_property(moments_b, rotvec, n_equal):
    """Any physical tensor (possibly with repeated moments) is diagonalised by a proper S."""
    a, b, c = sorted(moments_b)
    if n_equal == 1:
        b = a
    elif n_equal == 2:
        c = b
    elif n_equal == 3:
        b = c = a
    c = min(c, a + b)  # stay physical
    s = SciRotation.from_rotvec(rotvec).as_matrix()
    j = s @ np.diag([a, b, c]) @ s.T
    moments, rot = principal_axes(j)
    np.testing.assert_allclose(moments, sorted([a, b, c]), atol=1e-12 * c)
    _assert_principal(j, moments, rot)


# -- inertia ellipsoid -----------------------------------------------------------------


def test_inertia_ellipsoid_points_on_surface():
    """Semi-axis k times axis k lies on r^T J r = 1; r = e / sqrt(J_e) for any e (SPEC S8)."""
    rng = np.random.default_rng(10)
    j = _random_inertia(rng)
    semi, rot = inertia_ellipsoid(j)
    axes = rot.as_matrix()
    assert np.all(np.diff(semi) <= 0)
    for k in range(3):
        r = semi[k] * axes[:, k]
        np.testing.assert_allclose(r @ j @ r, 1.0, rtol=1e-12)
    e = rng.normal(size=3)
    r = e / np.linalg.norm(e) / np.sqrt(moment_about(j, e))
    np.testing.assert_allclose(r @ j @ r, 1.0, rtol=1e-12)


def test_inertia_ellipsoid_needs_definite():
    with pytest.raises(InvalidInputError, match="`inertia` to be positive definite"):
        inertia_ellipsoid(rod(1.0, 1.0))
