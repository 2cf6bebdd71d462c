"""SciPy parity audit of the rotation core: SciPy's ``Rotation`` is the oracle.

poinsot is scalar-first; SciPy is scalar-last unless ``scalar_first=True``.
Deliberate differences are asserted as such (and documented in the docstrings).
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation
from scipy.spatial.transform import Slerp

from poinsot import GimbalLockWarning, InvalidInputError, Rotation, compose, slerp
from rotation_cases import SCIPY_ND, all_quaternions, assert_same_rotation, quat_distance

SEQS = [a + b + c for a, b, c in itertools.product("xyz", repeat=3) if a != b and b != c]
SEQS += [s.upper() for s in SEQS]
Q = all_quaternions()


def scipy(q) -> SciPyRotation:
    return SciPyRotation.from_quat(np.asarray(q), scalar_first=True)


def sq(r: SciPyRotation) -> np.ndarray:
    return r.as_quat(scalar_first=True)


# ------------------------------------------------------------------ Euler angles
_EDGE = [0.0, np.pi, -np.pi, np.pi / 2, -np.pi / 2, np.pi - 1e-9, -np.pi + 1e-9, 1e-9, 1.0]
_GRID = np.array(list(itertools.product(_EDGE, repeat=3)))


def _distance_from_singular(seq: str, mid: np.ndarray) -> np.ndarray:
    if seq[0].lower() == seq[2].lower():  # proper Euler: singular at 0 and pi
        return np.minimum(np.abs(mid), np.abs(np.pi - mid))
    return np.abs(np.pi / 2 - np.abs(mid))  # Tait-Bryan: singular at +-pi/2


@pytest.mark.parametrize("seq", SEQS)
def test_euler_matches_scipy_on_edges_and_gimbal_lock(seq):
    q = np.vstack([Q, Rotation.from_euler(seq, _GRID).as_quat()])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # both warn at gimbal lock
        angles = Rotation.from_quat(q).as_euler(seq)
        ref = scipy(q).as_euler(seq)
    # same outer angles, same branch (even at +-pi and in gimbal lock) ...
    np.testing.assert_allclose(angles[:, [0, 2]], ref[:, [0, 2]], rtol=0, atol=5e-14)
    # ... and the same middle angle, except that in gimbal lock poinsot snaps it to
    # the singular value (SciPy keeps the computed one, up to 1e-7 rad away)
    locked = _distance_from_singular(seq, ref[:, 1]) <= 1e-7
    assert np.any(locked) and np.any(~locked)
    np.testing.assert_allclose(angles[~locked, 1], ref[~locked, 1], rtol=0, atol=5e-14)
    np.testing.assert_allclose(angles[locked, 1], ref[locked, 1], rtol=0, atol=1e-7)
    assert np.all(_distance_from_singular(seq, angles[locked, 1]) <= 1e-15)
    assert np.all(np.abs(angles) <= np.pi)
    assert_same_rotation(
        Rotation.from_euler(seq, _GRID).as_quat(), sq(SciPyRotation.from_euler(seq, _GRID)), 2e-14
    )


@pytest.mark.parametrize("seq", SEQS)
def test_euler_round_trip_near_gimbal_lock_loses_at_most_the_threshold(seq):
    # Issue 2: inside the 1e-7 rad lock zone the round trip may lose accuracy, but no
    # more than the threshold (it loses exactly the distance d from the singular
    # middle angle; keeping the computed middle angle, as SciPy does, loses up to 2 d).
    rng = np.random.default_rng(11)
    proper = seq[0].lower() == seq[2].lower()
    for singular in (0.0, np.pi) if proper else (np.pi / 2, -np.pi / 2):
        for d in (0.0, 1e-12, 1e-9, 9.9e-8, 1.01e-7, 1e-6):
            mid = singular + d if singular in (0.0, -np.pi / 2) else singular - d
            outer = rng.uniform(-np.pi, np.pi, (40, 2))
            angles = np.column_stack([outer[:, 0], np.full(40, mid), outer[:, 1]])
            r = Rotation.from_euler(seq, angles)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", GimbalLockWarning)
                back = r.as_euler(seq)
            err = (Rotation.from_euler(seq, back).inv() * r).magnitude()
            # round-off beyond d: 1.6e-15 observed (6.9e-16 outside the lock zone)
            assert np.all(err <= (d + 2e-14 if d <= 1e-7 else 2e-14)), (d, err.max())


def test_one_axis_angle_shapes_follow_scipy():
    a = np.array([0.1, -0.2, 0.3, 2.0])
    for angles, shape in [(0.3, ()), (a, (4,)), (a[:, None], (4,)), (a.reshape(2, 2, 1), (2, 2))]:
        r = Rotation.from_euler("y", angles)
        assert r.shape == shape
        want = np.ravel(angles)
        np.testing.assert_allclose(r.as_rotvec().reshape(-1, 3)[:, 1], want, atol=1e-15)
    # SciPy agrees wherever it accepts the input
    for angles in (0.3, a[:, None], [[0.3]]):
        assert_same_rotation(
            Rotation.from_euler("y", angles).as_quat().reshape(-1, 4),
            sq(SciPyRotation.from_euler("y", angles)).reshape(-1, 4),
            1e-16,
        )
    # deliberate extension: a (N,) array is N angles, also for N = 1 (SciPy: single)
    assert Rotation.from_euler("y", [0.3]).shape == (1,)
    assert Rotation.from_euler("y", np.zeros((2, 3))).shape == (2, 3)


# ---------------------------------------------------- rotation vectors at pi
def _at_pi() -> np.ndarray:
    q = [[0, 0, -1, 0], [0, 0, 0, -1], [0, -1, 1, 0], [-0.0, -1, 0, 0], [0, 0, -0.0, -1]]
    return np.vstack([np.array(q, float), Q[Q[:, 0] == 0]])


def test_rotvec_axis_angle_and_power_at_exactly_pi_match_scipy():
    q = _at_pi()
    r = Rotation.from_quat(q)
    np.testing.assert_allclose(r.as_rotvec(), scipy(q).as_rotvec(), rtol=0, atol=1e-15)
    axis, angle = r.as_axis_angle()
    np.testing.assert_allclose(axis * angle[:, None], r.as_rotvec(), atol=1e-15)
    np.testing.assert_allclose(r.as_mrp(), axis * np.tan(angle / 4)[:, None], atol=1e-15)
    for n in (0.5, -0.5, 3):
        assert_same_rotation((r**n).as_quat(), sq(scipy(q) ** n), 2e-14)


def test_canonical_quaternion_matches_scipy():
    # same sign choice everywhere (w > 0, else first non-zero > 0), values to an ulp
    q = np.vstack([Q, _at_pi()])
    r = Rotation.from_quat(q)
    for first in (True, False):
        ref = scipy(q).as_quat(canonical=True, scalar_first=first)
        got = r.as_quat(canonical=True, scalar_first=first)
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-14)


def test_representations_match_scipy_on_edge_set():
    r, s = Rotation.from_quat(Q), scipy(Q)
    # SciPy is a double-precision reference (a few ulp): bounds of ~100 ulp
    np.testing.assert_allclose(r.as_matrix(), s.as_matrix(), rtol=0, atol=2e-14)
    np.testing.assert_allclose(r.as_rotvec(), s.as_rotvec(), rtol=0, atol=5e-14)
    np.testing.assert_allclose(r.magnitude(), s.magnitude(), rtol=0, atol=2e-14)
    assert_same_rotation(Rotation.from_matrix(s.as_matrix()).as_quat(), Q, 2e-14)
    assert_same_rotation(Rotation.from_rotvec(s.as_rotvec()).as_quat(), Q, 2e-14)
    # float32 input: orthogonal only to ~1e-7, so projected onto the nearest rotation
    m32 = s.as_matrix().astype(np.float32)
    u, _, vt = np.linalg.svd(m32.astype(float))
    nearest = u @ vt  # det > 0 here: the polar factor is the nearest rotation
    np.testing.assert_allclose(Rotation.from_matrix(m32).as_matrix(), nearest, atol=2e-14)
    assert np.all(quat_distance(Rotation.from_matrix(m32).as_quat(), Q) < 1e-6)


# ------------------------------------------------------------ operations
def test_apply_and_compose_broadcast_like_scipy():
    rng = np.random.default_rng(3)
    q5 = rng.standard_normal((5, 4))
    r5, s5 = Rotation.from_quat(q5), scipy(q5)
    v5 = rng.standard_normal((5, 3))
    for r, s, v in [(r5[0], s5[0], v5), (r5, s5, v5[0]), (r5, s5, v5), (r5[:1], s5[:1], v5[0])]:
        np.testing.assert_allclose(r.apply(v), s.apply(v), atol=1e-15)
        np.testing.assert_allclose(r.apply(v, inverse=True), s.apply(v, inverse=True), atol=1e-15)
    for a, b, sa, sb in [(r5, r5[0], s5, s5[0]), (r5[0], r5, s5[0], s5), (r5[:1], r5, s5[:1], s5)]:
        assert_same_rotation((a * b).as_quat(), sq(sa * sb), 2e-14)
    for n in (0, 1, -1, 2, -3, 0.5, -0.25, 2.5):
        assert_same_rotation((r5**n).as_quat(), sq(s5**n), 2e-14)


def test_slerp_matches_scipy_including_near_pi():
    r0 = Rotation.random(rng=1)
    t = np.linspace(0.0, 1.0, 11)
    for r1 in (Rotation.random(rng=2), r0 * Rotation.from_rotvec([0, 0, np.pi - 1e-12])):
        ref = Slerp([0, 1], scipy(np.stack([r0.as_quat(), r1.as_quat()])))(t)
        assert_same_rotation(slerp(r0, r1, t).as_quat(), sq(ref), 2e-14)
    with pytest.raises(InvalidInputError, match="to broadcast"):
        slerp(Rotation.random(4, rng=0), Rotation.random(4, rng=1), np.zeros(3))


@pytest.mark.skipif(not SCIPY_ND, reason="this SciPy has no N-D Rotation to compare with")
def test_mean_matches_scipy_with_weights_and_axis():
    rng = np.random.default_rng(4)
    q = rng.standard_normal((5, 3, 4))
    r, s = Rotation.from_quat(q), scipy(q)
    w = rng.random((5, 3))
    assert_same_rotation(r.mean().as_quat(), sq(s.mean()), 1e-14)
    assert_same_rotation(r.mean(w).as_quat(), sq(s.mean(w)), 1e-14)
    for axis in (0, 1, -1, (0, 1)):
        assert_same_rotation(r.mean(w, axis=axis).as_quat(), sq(s.mean(w, axis=axis)), 1e-14)
    # q and -q are the same rotation
    mixed = Rotation.from_quat(np.vstack([q[0], -q[0]]))
    assert_same_rotation(mixed.mean().as_quat(), sq(scipy(q[0]).mean()), 1e-14)
    assert_same_rotation(r[0, 0].mean().as_quat(), r[0, 0].as_quat(), 2e-14)


def test_align_vectors_matches_scipy_and_is_scale_free():
    rng = np.random.default_rng(5)
    b = rng.standard_normal((6, 3))
    truth = Rotation.random(rng=1)
    a = truth.apply(b) + 0.01 * rng.standard_normal((6, 3))
    w = rng.random(6)
    r, rssd, sens = Rotation.align_vectors(a, b, w, return_sensitivity=True)
    s, s_rssd, s_sens = SciPyRotation.align_vectors(a, b, w, return_sensitivity=True)
    assert_same_rotation(r.as_quat(), sq(s), 1e-14)
    np.testing.assert_allclose(rssd, s_rssd, rtol=1e-9)
    np.testing.assert_allclose(sens, s_sens, rtol=1e-12)
    # 1e200 vectors used to hang LAPACK (inf in B); 1e-200 ones underflowed to "degenerate"
    for scale in (1e200, 1e-200, 1e150):
        rs, rssd_s = Rotation.align_vectors(a * scale, b * scale, w)
        assert_same_rotation(rs.as_quat(), r.as_quat(), 1e-14)
        np.testing.assert_allclose(rssd_s, rssd * scale, rtol=1e-12)
    rs = Rotation.align_vectors(a * 1e200, b * 1e-200, w * 1e-300)[0]  # different scales
    assert_same_rotation(rs.as_quat(), r.as_quat(), 1e-14)


def test_compose_matches_products_and_accepts_a_single_rotation():
    a, b, c = (Rotation.random(rng=k) for k in (1, 2, 3))
    sa, sb, sc = (scipy(r.as_quat()) for r in (a, b, c))
    assert_same_rotation(compose([a, b, c]).as_quat(), sq(sc * sb * sa), 2e-14)
    assert_same_rotation(compose([a, b, c], axes="body").as_quat(), sq(sa * sb * sc), 2e-14)
    assert compose(a) is a
