"""Bad input (each branch named in the message) and SPEC S4's two points of view."""

from __future__ import annotations

import numpy as np
import pytest

from poinsot import InvalidInputError, InvalidTypeError, PoinsotError, Rotation, compose


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (
            lambda: Rotation.from_quat([1, 0, 0]),
            r"Expected `quat` to have shape \(\.\.\., 4\), got \(3,\)\.",
        ),
        (lambda: Rotation.from_quat([0, 0, 0, 0]), "`quat` to be non-zero"),
        (lambda: Rotation.from_quat([np.nan, 0, 0, 1]), "`quat` to contain only finite"),
        (lambda: Rotation.from_quat([np.inf, 0, 0, 1]), "finite"),
        (lambda: Rotation.from_matrix(np.eye(2)), r"`matrix` to have shape \(\.\.\., 3, 3\)"),
        (lambda: Rotation.from_matrix(np.diag([1.0, 1.0, -1.0])), "determinant > 0"),
        (lambda: Rotation.from_matrix(np.zeros((3, 3))), "determinant > 0"),
        (lambda: Rotation.from_matrix(2 * np.eye(3)), "orthogonal within"),
        (lambda: Rotation.from_matrix(np.eye(3) + 1e-3), "orthogonal within"),
        (lambda: Rotation.from_euler("ZZX", [1, 2, 3]), "consecutive axes"),
        (lambda: Rotation.from_euler("abc", [1, 2, 3]), "Expected `seq`"),
        (lambda: Rotation.from_euler("ZxZ", [1, 2, 3]), "not mixed"),
        (lambda: Rotation.from_euler("XYZX", [1, 2, 3, 4]), "1 to 3 axes"),
        (lambda: Rotation.from_euler("XYZ", [1, 2]), r"`angles` to have shape \(\.\.\., 3\)"),
        (lambda: Rotation.identity().as_euler("xy"), "3 axes"),
        (lambda: Rotation.from_axis_angle([0, 0, 0], 1.0), "`axis` to be non-zero"),
        (lambda: Rotation.from_axis_angle(np.ones((2, 3)), [1.0, 2.0, 3.0]), "broadcast"),
        (lambda: Rotation.from_rotvec([1, 2]), "`rotvec`"),
        (lambda: Rotation.from_basis([1, 0, 0], [0, 1, 0], [0, 0, -1]), "right-handed"),
        (lambda: Rotation.from_basis([1, 0, 0], [0.5, 1, 0], [0, 0, 1]), "orthonormal"),
        (
            lambda: Rotation.align_vectors([[1, 0, 0], [2, 0, 0]], [[0, 1, 0], [0, 2, 0]]),
            "two linearly independent",
        ),
        (lambda: Rotation.align_vectors([[1, 0, 0]], [[0, 1, 0]]), "two linearly independent"),
        (lambda: Rotation.align_vectors(np.eye(3), np.eye(3)[:2]), "same shape"),
        (lambda: Rotation.align_vectors(np.eye(3), np.eye(3), weights=[1, 1]), "`weights`"),
        (lambda: Rotation.random(3) * Rotation.random(4), "broadcast"),
        (lambda: Rotation.random(3).apply(np.ones((4, 3))), "broadcast"),
        (lambda: compose([Rotation.identity()], axes="space"), "`axes` to be one of"),
        (lambda: compose([]), "at least one"),
        (lambda: Rotation.random(3).mean(weights=[1, 2]), "`weights`"),
    ],
)
def test_bad_input_is_named(call, match):
    with pytest.raises(InvalidInputError, match=match):
        call()


def test_type_errors():
    with pytest.raises(InvalidTypeError, match="string"):
        Rotation.from_quat("1, 0, 0, 0")
    with pytest.raises(InvalidTypeError, match="Rotation"):
        compose([Rotation.identity(), np.eye(3)])
    with pytest.raises(InvalidTypeError, match="single rotation is not subscriptable"):
        Rotation.identity()[0]
    with pytest.raises(InvalidTypeError, match=r"poinsot.Rotation in `r \* other`, got int"):
        Rotation.identity() * 3
    assert issubclass(InvalidInputError, PoinsotError) and issubclass(InvalidInputError, ValueError)


def test_non_unit_quaternions_are_normalised():
    r = Rotation.from_quat([[0, 0, 0, 5.0], [3.0, 0, 0, 0]])
    np.testing.assert_allclose(np.linalg.norm(r.as_quat(), axis=1), 1.0, rtol=0, atol=1e-16)


def test_exactly_orthogonal_matrix_passes_through():
    """A matrix computed from a quaternion returns that quaternion to machine precision."""
    q = Rotation.random(1000, rng=8)
    back = Rotation.from_matrix(q.as_matrix())
    d = np.minimum(
        np.abs(back.as_quat() - q.as_quat()).max(axis=1),
        np.abs(back.as_quat() + q.as_quat()).max(axis=1),
    )
    assert d.max() <= 5e-15  # 4.4e-16 (2 ulp) observed


def test_spec_s4_worked_example_both_points_of_view():
    """SPEC S4: A = 90 deg about x, B = 90 deg about y (fixed axes): C = B A."""
    a = Rotation.from_euler("x", 90, degrees=True)
    b = Rotation.from_euler("y", 90, degrees=True)
    expected = np.array([[0, 1, 0], [0, 0, -1], [-1, 0, 0]])
    np.testing.assert_allclose(compose([a, b], axes="fixed").as_matrix(), expected, atol=3e-15)
    np.testing.assert_allclose((b * a).as_matrix(), expected, atol=3e-15)
    # two points of view: the same elementary rotations about body axes give C = A B,
    # which equals the intrinsic sequence "XY" and the reversed extrinsic "yx"
    body = compose([a, b], axes="body")
    np.testing.assert_allclose(body.as_matrix(), a.as_matrix() @ b.as_matrix(), atol=1e-15)
    assert body.approx_equal(Rotation.from_euler("XY", [90, 90], degrees=True))
    assert compose([a, b], axes="fixed").approx_equal(
        Rotation.from_euler("xy", [90, 90], degrees=True)
    )


def test_compose_n_rotations():
    rs = list(Rotation.random(6, rng=2))
    fixed = compose(rs, axes="fixed")
    body = compose(rs, axes="body")
    m_fixed = np.eye(3)
    m_body = np.eye(3)
    for r in rs:
        m_fixed = r.as_matrix() @ m_fixed  # C = A_n ... A_1
        m_body = m_body @ r.as_matrix()  # C = A_1 ... A_n
    np.testing.assert_allclose(fixed.as_matrix(), m_fixed, atol=1e-14)
    np.testing.assert_allclose(body.as_matrix(), m_body, atol=1e-14)
    # a Rotation whose first axis lists them works too
    assert compose(Rotation.concatenate(rs)).approx_equal(fixed)


def test_poisson_identity_quaternion_components_same_in_both_bases():
    """SPEC S4: the axis is fixed by the rotation, so it has the same components in both bases."""
    r = Rotation.random(50, rng=4)
    axis, _ = r.as_axis_angle()
    np.testing.assert_allclose(r.apply(axis), axis, atol=1e-14)
    np.testing.assert_allclose(r.apply(axis, inverse=True), axis, atol=1e-14)


def test_normalising_a_unit_quaternion_is_exact():
    """from_quat(r.as_quat()) reproduces r bit for bit (normalisation is idempotent)."""
    r = Rotation.random(10_000, rng=3)
    np.testing.assert_array_equal(Rotation.from_quat(r.as_quat()).as_quat(), r.as_quat())
    np.testing.assert_array_equal(Rotation(r.as_quat()).as_quat(), r.as_quat())
