"""Instantaneous screw axis and reduction of rotations and translations (SPEC S6).

Truths: the defining property of the axis (``V(r) = lam w`` on it), the
invariant ``V . w``, the minimal speed found by brute-force sampling, and the
textbook reductions (a couple of rotations is a translation; intersecting
rotations are a rotation about the intersection; parallel rotations of one
sense are a rotation about the axis that divides their distance inversely to
the angular speeds; skew axes give a screw).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.kinematics.screw import ReducedMotion, Screw, reduce_motions, screw_axis

vec = arrays(np.float64, 3, elements=st.floats(-5, 5))


def field(v0, w, origin, r):
    return v0 + np.cross(w, np.asarray(r) - origin)


@settings(max_examples=60, deadline=None)
@given(vec, vec, vec)
def test_axis_points_move_along_omega(v0, w, origin):
    """Every point of the axis has velocity lam * w; point is the foot of the
    perpendicular from `origin`; |direction| = 1 along w."""
    wn = np.linalg.norm(w)
    assume(wn >= 1e-3)
    s = screw_axis(v0, w, pole=origin)
    assert isinstance(s, Screw)
    np.testing.assert_allclose(np.linalg.norm(s.direction), 1.0)
    np.testing.assert_allclose(s.direction, w / wn, atol=1e-12)
    scale = 1 + np.abs(v0).max() + wn * (np.abs(origin).max() + np.linalg.norm(s.point))
    for lam in (-2.0, 0.0, 3.0):
        p = s.point + lam * s.direction
        np.testing.assert_allclose(field(v0, w, origin, p), s.parameter * w, atol=1e-10 * scale)
    assert abs((s.point - origin) @ s.direction) <= 1e-10 * (1 + np.linalg.norm(s.point - origin))


def test_min_speed_is_minimum_and_invariant():
    """V . w is the same at every point; no point moves slower than min_speed,
    and the axis computed from another point's velocity is the same line."""
    rng = np.random.default_rng(0)
    v0, w, origin = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
    s = screw_axis(v0, w, pole=origin)
    pts = rng.normal(scale=3, size=(2000, 3))
    V = field(v0, w, origin, pts)
    np.testing.assert_allclose(V @ w, v0 @ w, atol=1e-12)
    speeds = np.linalg.norm(V, axis=1)
    assert speeds.min() >= s.min_speed - 1e-12
    np.testing.assert_allclose(np.linalg.norm(field(v0, w, origin, s.point)), s.min_speed)
    # the same field described from another pole
    q = pts[7]
    s2 = screw_axis(V[7], w, pole=q)
    np.testing.assert_allclose(s2.parameter, s.parameter, rtol=1e-12)
    np.testing.assert_allclose(s2.closest_point(s.point), s.point, atol=1e-12)
    np.testing.assert_allclose(s2.point, s.closest_point(q), atol=1e-12)


def test_screw_textbook_pitch():
    """Rotation 2 rad/s about the vertical line through (1, 2, 0) plus climb
    0.5 m/s: axis through (1, 2, 0), pitch per radian 0.25, min speed 0.5."""
    w = np.array([0, 0, 2.0])
    P = np.array([1.0, 2.0, 0.0])
    v_origin = np.cross(w, -P) + [0, 0, 0.5]
    s = screw_axis(v_origin, w)
    np.testing.assert_allclose(s.point, P, atol=1e-15)
    np.testing.assert_allclose(s.parameter, 0.25)
    np.testing.assert_allclose(s.min_speed, 0.5)
    # left-handed screw: negative parameter, same min speed
    s = screw_axis(np.cross(w, -P) - [0, 0, 0.5], w)
    np.testing.assert_allclose([s.parameter, s.min_speed], [-0.25, 0.5])


def test_screw_axis_batch():
    rng = np.random.default_rng(1)
    v0, w = rng.normal(size=(4, 5, 3)), rng.normal(size=(5, 3))
    s = screw_axis(v0, w)
    assert s.point.shape == s.direction.shape == (4, 5, 3)
    assert s.parameter.shape == s.min_speed.shape == (4, 5)
    one = screw_axis(v0[2, 3], w[3])
    np.testing.assert_allclose(s.point[2, 3], one.point)
    np.testing.assert_allclose(s.parameter[2, 3], one.parameter)


def test_screw_axis_errors():
    with pytest.raises(InvalidInputError, match="pure translation has no screw axis"):
        screw_axis([1, 0, 0], [0, 0, 0])
    with pytest.raises(InvalidInputError, match="reduce_motions"):
        screw_axis([1, 0, 0], np.array([[0, 0, 1], [0, 0, 1e-14]]))
    with pytest.raises(InvalidInputError, match=r"`v0` to have shape \(\.\.\., 3\)"):
        screw_axis([1, 0], [0, 0, 1])
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        screw_axis([1, 0, 0], [0, np.nan, 1])
    with pytest.raises(InvalidInputError, match="shapes of .* to broadcast"):
        screw_axis(np.zeros((2, 3)), np.ones((3, 3)))
    with pytest.raises(InvalidInputError, match="`pole`"):
        screw_axis([1, 0, 0], [0, 0, 1], pole=[0, 0])
    with pytest.raises(InvalidInputError, match="`point`"):
        screw_axis([1, 0, 0], [0, 0, 1]).closest_point([1, 2])


# ---------------------------------------------------------------------------
# reduce_motions
# ---------------------------------------------------------------------------


def brute_velocity(rotations, translations, r):
    """Velocity at r of the superposed motions, summed point by point."""
    v = np.zeros(3)
    for w, P in rotations:
        v = v + np.cross(w, np.asarray(r, float) - P)
    for vk in translations:
        v = v + np.asarray(vk, float)
    return v


def check_field(red: ReducedMotion, rotations, translations):
    rng = np.random.default_rng(2)
    for r in rng.normal(scale=4, size=(5, 3)):
        np.testing.assert_allclose(
            red.velocity_at(r), brute_velocity(rotations, translations, r), atol=1e-12
        )


def test_couple_of_rotations_is_translation():
    """Equal and opposite rotations about parallel axes a distance d apart:
    a translation with speed w d, perpendicular to both (textbook 'couple')."""
    w = np.array([0, 0, 1.7])
    P1, P2 = np.array([0.3, -1.0, 2.0]), np.array([0.3, 1.5, -4.0])
    rots = [(w, P1), (-w, P2)]
    red = reduce_motions(rots, pole=[5, 6, 7])
    assert red.kind == "translation"
    assert red.screw is None
    np.testing.assert_allclose(red.omega, 0, atol=1e-15)
    # w x (O - P1) - w x (O - P2) = w x (P2 - P1), the same at every pole
    np.testing.assert_allclose(red.velocity, np.cross(w, P2 - P1), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(red.velocity), 1.7 * 2.5)
    check_field(red, rots, [])


def test_intersecting_rotations_are_a_rotation_about_the_intersection():
    rng = np.random.default_rng(3)
    X = rng.normal(size=3)  # the common point
    w1, w2 = rng.normal(size=3), rng.normal(size=3)
    rots = [(w1, X + 2.0 * w1), (w2, X - 0.7 * w2)]  # axes through X
    red = reduce_motions(rots, pole=[1, -2, 0.5])
    assert red.kind == "rotation"
    np.testing.assert_allclose(red.omega, w1 + w2)
    np.testing.assert_allclose(red.screw.closest_point(X), X, atol=1e-12)
    assert red.screw.parameter == 0.0 and red.screw.min_speed == 0.0
    check_field(red, rots, [])


def test_parallel_rotations_same_sense():
    """w1 about P1 and w2 about P2 (parallel): rotation w1 + w2 about the axis
    through (w1 P1 + w2 P2)/(w1 + w2)."""
    e = np.array([0, 0, 1.0])
    P1, P2 = np.array([0.0, 0, 0]), np.array([3.0, 0, 0])
    red = reduce_motions([(2 * e, P1), (1 * e, P2)])
    assert red.kind == "rotation"
    np.testing.assert_allclose(red.screw.point, [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(red.omega, 3 * e)


def test_skew_rotations_give_a_screw():
    """Unit rotations about the z axis and about the skew line (x, 1, 0):
    v(O) = OP2 x w2 = (0, 1, 0) x (1, 0, 0) = (0, 0, -1), w = (1, 0, 1),
    lam = v.w/|w|^2 = -1/2 (left-handed), min speed |v.w|/|w| = 1/sqrt(2)."""
    rots = [([0, 0, 1.0], [0, 0, 0]), ([1.0, 0, 0], [0, 1.0, 0])]
    red = reduce_motions(rots)
    assert red.kind == "screw"
    np.testing.assert_allclose(red.velocity, [0, 0, -1])
    np.testing.assert_allclose(red.screw.parameter, -0.5)
    np.testing.assert_allclose(red.screw.min_speed, 1 / np.sqrt(2))
    # the axis lies between the two lines: it meets the common perpendicular
    # (the y axis) at y = w2^2 / (w1^2 + w2^2) * 1 = 1/2
    np.testing.assert_allclose(red.screw.point, [0, 0.5, 0], atol=1e-15)
    check_field(red, rots, [])
    # intersecting lines (the x-parallel through (0, 0, 1) meets the z axis): rotation
    assert reduce_motions([([0, 0, 1.0], [0, 0, 0]), ([1.0, 0, 0], [0, 0, 1.0])]).kind == (
        "rotation"
    )


def test_skew_rotations_with_slide():
    rots = [([0, 0, 1.0], [0, 0, 0]), ([1.0, 0, 1.0], [0, 2.0, 0])]
    red = reduce_motions(rots)
    w = np.array([1.0, 0, 2.0])
    v_o = np.cross([0, 2.0, 0], [1.0, 0, 1.0])
    assert red.kind == "screw"
    np.testing.assert_allclose(red.screw.parameter, (v_o @ w) / (w @ w))
    check_field(red, rots, [])


def test_rotation_plus_translation():
    w = np.array([0, 0, 2.0])
    # perpendicular translation: a rotation about a shifted parallel axis
    red = reduce_motions([(w, [0, 0, 0])], [[4.0, 0, 0]])
    assert red.kind == "rotation"
    np.testing.assert_allclose(red.screw.point, [0, 2.0, 0])  # w x r = -v there
    # parallel translation: a screw about the same axis with lam = v / w
    red = reduce_motions([(w, [1, 1, 0])], [[0, 0, 3.0]])
    assert red.kind == "screw"
    np.testing.assert_allclose(red.screw.parameter, 1.5)
    np.testing.assert_allclose(red.screw.point, [1, 1, 0], atol=1e-15)
    np.testing.assert_allclose(red.screw.min_speed, 3.0)


def test_rest_and_translation_only():
    red = reduce_motions([([0, 1, 0], [1, 2, 3]), ([0, -1, 0], [1, 5, 3])])  # same axis
    assert red.kind == "rest" and red.screw is None
    assert reduce_motions().kind == "rest"
    red = reduce_motions([], [[1, 0, 0], [0, 1, 0]])
    assert red.kind == "translation"
    np.testing.assert_allclose(red.velocity, [1, 1, 0])
    red = reduce_motions([], [[1, 0, 0], [-1, 0, 0]])
    assert red.kind == "rest"


def test_classification_tolerances():
    """Cancellation at the rounding level of large inputs still classifies;
    a real small slide is a screw; atol widens 'rotation'."""
    w = np.array([0.1, 0.2, 0.3])
    P = np.array([1e3, -2e3, 7e2])
    rots = [(w, P), (w * 3, P + w * 11.0)]  # same axis
    assert reduce_motions(rots).kind == "rotation"
    red = reduce_motions([(w, [0, 0, 0])], [w * 1e-6])
    assert red.kind == "screw"
    assert reduce_motions([(w, [0, 0, 0])], [w * 1e-6], atol=1e-3).kind == "rotation"


def test_reduce_errors():
    with pytest.raises(InvalidInputError, match=r"`rotations\[0\]` to be a pair"):
        reduce_motions([[0, 0, 1]])
    with pytest.raises(InvalidInputError, match=r"`rotations\[1\]\[1\]` to have shape \(3,\)"):
        reduce_motions([([0, 0, 1], [0, 0, 0]), ([0, 0, 1], [0, 0])])
    with pytest.raises(InvalidInputError, match=r"`translations\[0\]` to contain only finite"):
        reduce_motions([], [[np.nan, 0, 0]])
    with pytest.raises(InvalidInputError, match=r"`pole` to have shape \(3,\)"):
        reduce_motions([], [], pole=np.zeros((2, 3)))
    with pytest.raises(InvalidTypeError, match="`rtol`"):
        reduce_motions([], [], rtol="x")
    with pytest.raises(InvalidInputError, match=r"`point` to have shape \(\.\.\., 3\)"):
        reduce_motions([], [[1, 0, 0]]).velocity_at([1, 2])
    with pytest.raises(InvalidInputError, match="`atol` to be a non-negative number"):
        reduce_motions([], [], atol=-1.0)
    with pytest.raises(InvalidInputError, match="`atol` to be a non-negative number"):
        screw_axis([0, 0, 1], [0, 0, 1], atol=[1e-9, 1e-9])
