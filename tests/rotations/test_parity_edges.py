"""Edge-case audit of the rotation core: extreme magnitudes, empty batches, and
every bad input raising a named poinsot error (never a raw NumPy error or NaN)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot import quaternion as Q

HUGE, TINY = 1e200, 1e-200


# ------------------------------------------------------- extreme magnitudes
@pytest.mark.parametrize("scale", [HUGE, TINY, 1e300, 1e-300])
def test_quaternions_of_any_magnitude_keep_their_direction(scale):
    q = np.array([3.0, 0.0, -4.0, 0.0])  # |q| = 5
    unit = q / 5.0
    np.testing.assert_allclose(Q.normalize(q * scale), unit, rtol=0, atol=5e-15)
    np.testing.assert_allclose(Rotation.from_quat(q * scale).as_quat(), unit, atol=5e-15)
    np.testing.assert_allclose(Rotation(q * scale).as_quat(), unit, atol=3e-16)
    np.testing.assert_allclose(Q.norm(q * scale), 5.0 * scale, rtol=1e-15)
    # inverse = conj / |q|^2, here ~ 1/scale: representable even when |q|^2 is not
    np.testing.assert_allclose(Q.inverse(q * scale) * scale, [0.12, 0.0, 0.16, 0.0], rtol=1e-14)
    # log q = log|q| + e f, f = atan2(|l|, l0)
    want = [np.log(5.0) + np.log(scale), 0.0, -np.arctan2(4.0, 3.0), 0.0]
    # `want` is itself rounded (1 ulp of log(1e300) = 1.1e-13): 100x that
    np.testing.assert_allclose(Q.log(q * scale), want, rtol=2e-14, atol=1e-14)
    np.testing.assert_allclose(
        Q.power(q * scale, 0.5), Q.power(q, 0.5) * np.sqrt(scale), rtol=1e-12
    )  # exp(t log|q|): relative error ~ |t log|q|| eps (~3e-14 here), inherent


def test_exp_of_a_huge_pure_quaternion_is_unit():
    v = np.array([0.0, 1e300, 0.0, 0.0])
    np.testing.assert_allclose(Q.exp(v), [np.cos(1e300), np.sin(1e300), 0, 0], atol=1e-15)


def test_overflowing_quaternion_results_raise_named_errors():
    big = [1e200, 1e200, 0.0, 0.0]
    with pytest.raises(InvalidInputError, match="scalar part of `q`"):
        Q.exp([800.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"`t` log\|q\|"):
        Q.power(big, 2)
    with pytest.raises(InvalidInputError, match="`t` times the angle"):
        Q.power([-1.0, 0.0, 0.0, 0.0], 1e308)  # pi * 1e308 overflows
    with pytest.raises(InvalidInputError, match="product of `p` and `q`"):
        Q.multiply(big, big)
    with pytest.raises(InvalidInputError, match=r"rotate\(q, v\)"):
        Q.rotate(big, [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match="non-zero"):
        Q.normalize([0.0, 0.0, 0.0, 0.0])


@pytest.mark.parametrize("f", [1e155, 1e200, 1e300, 1.7e308])
def test_rotvec_with_a_huge_angle_is_a_unit_quaternion_without_warnings(f):
    q = Rotation.from_rotvec([0.0, f, 0.0]).as_quat()  # RuntimeWarning would be an error
    np.testing.assert_allclose(q, [np.cos(f / 2), 0.0, np.sin(f / 2), 0.0], atol=1e-15)


def test_rotvec_tiny_and_multi_turn_angles_match_scipy():
    v = np.array([[1e-300, 0, 0], [1e-20, 2e-20, 0], [np.pi, 0, 0], [2 * np.pi, 0, 0], [0, 0, 7.0]])
    got = Rotation.from_rotvec(v).as_quat()
    ref = SciPyRotation.from_rotvec(v).as_quat(scalar_first=True)
    np.testing.assert_allclose(got, ref, atol=1e-14)  # + the default rtol for tiny parts


# ------------------------------------------------------------ empty batches
def test_empty_batches_flow_through_and_mean_of_nothing_raises():
    r = Rotation.identity(0)
    assert r.shape == (0,) and len(r) == 0
    assert Rotation.from_quat(np.zeros((0, 4))).shape == (0,)
    assert Rotation.from_matrix(np.zeros((0, 3, 3))).shape == (0,)
    assert Rotation.from_euler("xyz", np.zeros((0, 3))).as_euler("zxz").shape == (0, 3)
    assert r.apply([1.0, 2.0, 3.0]).shape == (0, 3)
    assert (r * Rotation.identity()).shape == (0,)
    assert r.as_matrix().shape == (0, 3, 3) and r.magnitude().shape == (0,)
    with pytest.raises(InvalidInputError, match="at least one rotation to average"):
        r.mean()
    with pytest.raises(InvalidInputError, match="at least one rotation to average"):
        Rotation.identity((2, 0)).mean(axis=1)


# ----------------------------------------------------- argument validation
def test_shapes_for_identity_and_random():
    assert Rotation.identity(None).shape == ()  # as SciPy
    assert Rotation.random(np.int64(2), rng=0).shape == (2,)
    with pytest.raises(InvalidInputError, match="`shape` to have no negative sizes"):
        Rotation.identity(-1)
    with pytest.raises(InvalidTypeError, match="`shape` to be an int or a tuple of ints"):
        Rotation.random(2.5)
    with pytest.raises(InvalidTypeError, match="`shape` to be an int"):
        Rotation.identity("3")


def test_approx_equal_tolerance_in_degrees_and_its_validation():
    r = Rotation.random(4, rng=0)
    s = r * Rotation.from_rotvec([0.0, 0.0, np.deg2rad(0.5)])
    assert not np.any(r.approx_equal(s))  # default 1e-8 rad, as SciPy
    assert np.all(r.approx_equal(s, atol=0.6, degrees=True))
    assert not np.any(r.approx_equal(s, atol=0.4, degrees=True))
    with pytest.raises(InvalidInputError, match="`atol` to be non-negative"):
        r.approx_equal(s, atol=-1.0)
    with pytest.raises(InvalidInputError, match="`atol` to contain only finite"):
        r.approx_equal(s, atol=np.nan)
    with pytest.raises(InvalidTypeError, match="`atol`"):
        r.approx_equal(s, atol="x")
    with pytest.raises(InvalidTypeError, match=r"poinsot.Rotation, got scipy.*from_scipy"):
        r.approx_equal(SciPyRotation.identity())


def test_mean_argument_errors():
    r = Rotation.random((3, 2), rng=1)
    with pytest.raises(InvalidInputError, match="`weights` to broadcast"):
        r.mean(np.ones(4))
    with pytest.raises(InvalidInputError, match="`weights` to be non-negative"):
        r.mean(-np.ones((3, 2)))
    with pytest.raises(InvalidInputError, match="`weights` not to be all zero"):
        r.mean(np.zeros((3, 2)))
    with pytest.raises(InvalidInputError, match="`axis` within"):
        r.mean(axis=2)
    with pytest.raises(InvalidTypeError, match="`axis` to be an int"):
        r.mean(axis=0.5)


def test_concatenate_reshape_and_align_vectors_errors():
    with pytest.raises(InvalidInputError, match="same shape after the first axis"):
        Rotation.concatenate([Rotation.random((2, 3), rng=0), Rotation.random((1, 2), rng=0)])
    with pytest.raises(InvalidInputError, match="same shape after the first axis"):
        Rotation.concatenate([Rotation.random((2, 3), rng=0), Rotation.identity()])
    assert Rotation.concatenate(Rotation.random(3, rng=0)).shape == (3,)
    with pytest.raises(InvalidInputError, match="shape with 12 rotations"):
        Rotation.random((4, 3), rng=0).reshape(5)
    # fewer than two independent pairs (the issue: raise, where SciPy only warns)
    with pytest.raises(InvalidInputError, match=r"shape \(n, 3\) with n >= 2"):
        Rotation.align_vectors([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    with pytest.raises(InvalidInputError, match="two linearly independent"):
        Rotation.align_vectors([[1, 0, 0], [-2, 0, 0]], [[0, 1, 0], [0, -3, 0]])
    with pytest.raises(InvalidInputError, match="two linearly independent"):
        Rotation.align_vectors([[1, 0, 0], [0, 1, 0]], [[0, 1, 0], [1, 0, 0]], [1.0, 0.0])
    with pytest.raises(InvalidInputError, match="`weights` to contain only finite"):
        Rotation.align_vectors([[1, 0, 0], [0, 1, 0]], [[0, 1, 0], [1, 0, 0]], [np.inf, 1.0])


@pytest.mark.parametrize(
    ("bad", "error", "match"),
    [
        (np.nan, InvalidInputError, "finite"),
        ("abc", InvalidTypeError, "string"),
        ([["a", "b", "c"]], InvalidTypeError, "real numbers"),
        ([[1, 0, 0], [1, 0]], InvalidTypeError, "real numbers"),
        ([1j, 0, 0], InvalidTypeError, "real numbers"),
        ([1.0, 0.0], InvalidInputError, r"shape \(\.\.\., 3\)"),
        (1.0, InvalidInputError, r"shape \(\.\.\., 3\)"),
    ],
)
def test_bad_vectors_raise_named_errors(bad, error, match):
    for fn, name in [
        (Rotation.from_rotvec, "rotvec"),
        (Rotation.from_mrp, "mrp"),
        (Rotation.from_gibbs, "gibbs"),
        (Rotation.identity().apply, "vectors"),
    ]:
        with pytest.raises(error, match=match) as info:
            fn(bad)
        assert f"`{name}`" in str(info.value)


@pytest.mark.parametrize("scale", [1e-200, 1e200, 1e300])
def test_axis_gibbs_and_mrp_of_extreme_length(scale):
    # axis-angle: only the direction of the axis matters
    got = Rotation.from_axis_angle([scale, scale, 0.0], 1.0).as_quat()
    want = [np.cos(0.5), np.sin(0.5) / np.sqrt(2), np.sin(0.5) / np.sqrt(2), 0.0]
    np.testing.assert_allclose(got, want, atol=2e-16)
    if scale > 1:
        # Gibbs g = e tan(f/2): |g| -> inf is f -> pi, L -> (1/|g|, e)
        np.testing.assert_allclose(
            Rotation.from_gibbs([0.0, scale, 0.0]).as_quat(), [1 / scale, 0, 1, 0], rtol=1e-15
        )
        # MRP p = e tan(f/4): |p| -> inf is f -> 2 pi, L -> (-1, 2 e / |p|) (SciPy: NaN)
        np.testing.assert_allclose(
            Rotation.from_mrp([0.0, 0.0, scale]).as_quat(), [-1, 0, 0, 2 / scale], rtol=1e-15
        )


def test_mrp_beyond_one_keeps_scipys_quaternion():
    p = np.array([[2.0, 0.0, 0.0], [0.3, -4.0, 1e3], [0.1, 0.2, 0.3]])
    np.testing.assert_allclose(
        Rotation.from_mrp(p).as_quat(),
        SciPyRotation.from_mrp(p).as_quat(scalar_first=True),
        rtol=0,
        atol=1e-14,
    )


def test_from_matrix_tolerance_and_from_basis_messages():
    with pytest.raises(InvalidInputError, match="`atol` to be non-negative"):
        Rotation.from_matrix(np.eye(3), atol=-1.0)
    with pytest.raises(InvalidInputError, match="`atol` to contain only finite"):
        Rotation.from_matrix(np.eye(3), atol=np.nan)
    # far from orthogonal: rejected (SciPy would silently orthogonalise 2 I)
    with pytest.raises(InvalidInputError, match="orthogonal within 1e-06"):
        Rotation.from_matrix(2.0 * np.eye(3))
    with pytest.raises(InvalidInputError, match="orthonormal"):
        Rotation.from_basis([1e-200, 0, 0], [0, 1e-200, 0], [0, 0, 1e-200])
    with pytest.raises(InvalidInputError, match="right-handed"):
        Rotation.from_basis([1, 0, 0], [0, 1, 0], [0, 0, -1])


def test_power_shapes_must_broadcast():
    r = Rotation.random(5, rng=0)
    assert (r ** np.ones((3, 1))).shape == (3, 5)  # an extension: SciPy takes scalars only
    with pytest.raises(InvalidInputError, match="the rotations and `n` to broadcast"):
        r ** np.ones(3)
    with pytest.raises(InvalidInputError, match="shape of `t` .* to broadcast"):
        Q.power(np.ones((5, 4)), np.ones(3))


def test_repr_round_trips_including_empty_batches():
    for r in (Rotation.identity(), Rotation.identity((0, 2)), Rotation.from_rotvec([0, 0, 0.5])):
        back = eval(repr(r), {"Rotation": Rotation, "np": np})
        assert back.shape == r.shape
        assert np.all(back.approx_equal(r, atol=1e-6))
