"""RigidTransform (SE(3)) and Chasles' finite screw (theory §4, §6): SciPy's
RigidTransform as the oracle where the installed SciPy has it (>= 1.16), closed
forms and invariants otherwise."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import InvalidInputError, Rotation
from poinsot.rotations import RigidTransform, sclerp

RNG = np.random.default_rng(5)
N = 40
SR = SciPyRotation.random(N, random_state=7)
T = RNG.normal(size=(N, 3))
X = RNG.normal(size=(N, 3))

scipy_tf = pytest.importorskip("scipy.spatial.transform")
SciPyTF = getattr(scipy_tf, "RigidTransform", None)
needs_scipy_tf = pytest.mark.skipif(SciPyTF is None, reason="SciPy < 1.16 has no RigidTransform")


def _ours():
    return RigidTransform.from_components(T, Rotation.from_scipy(SR))


@needs_scipy_tf
def test_matrix_apply_compose_inverse_match_scipy():
    ours = _ours()
    ref = SciPyTF.from_components(T, SR)
    np.testing.assert_allclose(ours.as_matrix(), ref.as_matrix(), atol=1e-15)
    np.testing.assert_allclose(ours.apply(X), ref.apply(X), atol=1e-14)
    np.testing.assert_allclose(ours.apply(X, inverse=True), ref.apply(X, inverse=True), atol=1e-14)
    other, other_ref = ours[::-1], ref[::-1]
    np.testing.assert_allclose(
        (ours * other).as_matrix(), (ref * other_ref).as_matrix(), atol=1e-14
    )
    np.testing.assert_allclose(ours.inv().as_matrix(), ref.inv().as_matrix(), atol=1e-14)


@needs_scipy_tf
def test_exp_coords_and_dual_quat_match_scipy():
    ours, ref = _ours(), SciPyTF.from_components(T, SR)
    np.testing.assert_allclose(ours.as_exp_coords(), ref.as_exp_coords(), atol=1e-12)
    x = RNG.normal(size=(N, 6))
    np.testing.assert_allclose(
        RigidTransform.from_exp_coords(x).as_matrix(),
        SciPyTF.from_exp_coords(x).as_matrix(),
        atol=1e-13,
    )
    dq = ours.as_dual_quat(scalar_first=False)
    ref_dq = ref.as_dual_quat()
    sign = np.sign(np.sum(dq[:, :4] * ref_dq[:, :4], axis=-1))[:, None]  # q and -q: one pose
    np.testing.assert_allclose(dq, sign * ref_dq, atol=1e-14)
    back = RigidTransform.from_dual_quat(ref.as_dual_quat(scalar_first=True))
    np.testing.assert_allclose(back.as_matrix(), ref.as_matrix(), atol=1e-14)


def test_composition_reads_like_rotation_and_round_trips():
    a, b = _ours(), _ours()[::-1]
    np.testing.assert_allclose((a * b).apply(X), a.apply(b.apply(X)), atol=1e-13)
    np.testing.assert_allclose((a * a.inv()).as_matrix(), np.broadcast_to(np.eye(4), (N, 4, 4)),
                               atol=1e-14)  # fmt: skip
    m = a.as_matrix()
    np.testing.assert_allclose(RigidTransform.from_matrix(m).as_matrix(), m, atol=1e-15)
    np.testing.assert_allclose(
        RigidTransform.from_exp_coords(a.as_exp_coords()).as_matrix(), m, atol=1e-13
    )
    np.testing.assert_allclose(RigidTransform.from_dual_quat(a.as_dual_quat()).as_matrix(), m,
                               atol=1e-14)  # fmt: skip


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-8, 1e-3, 1.0, np.pi - 1e-8, np.pi])
def test_exp_coords_near_zero_and_pi(angle):
    """log(exp(x)) = x with t = V(phi) rho in closed form: at the two ends the series
    and the cotangent form keep the round trip to ~1e-15 (rad, m)."""
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    x = np.concatenate([angle * axis, [1.0, -2.0, 0.5]])
    tf = RigidTransform.from_exp_coords(x)
    # independent: V applied as the series E + phi^/2! + phi^^2/3! + ... (exact enough)
    ph = np.array([[0, -x[2], x[1]], [x[2], 0, -x[0]], [-x[1], x[0], 0]])
    v, term = np.eye(3), np.eye(3)
    for k in range(2, 40):
        term = term @ ph / k
        v = v + term
    np.testing.assert_allclose(tf.as_components()[0], v @ x[3:], atol=1e-13)
    np.testing.assert_allclose(tf.as_exp_coords(), x, atol=1e-12)


def test_screw_slide_is_the_projection_of_every_displacement():
    """Chasles: the displacement of ANY point has the same projection on the axis (the
    slide); points on the axis move only along it; the screw rebuilds the transform."""
    tf = _ours()
    s = tf.screw()
    pts = RNG.normal(size=(7, N, 3)) * 3
    disp = tf.apply(pts) - pts
    slides = np.sum(disp * s.direction, axis=-1)
    np.testing.assert_allclose(slides, np.broadcast_to(s.slide, (7, N)), atol=1e-12)
    on_axis = s.point + 0.7 * s.direction
    np.testing.assert_allclose(tf.apply(on_axis) - on_axis, s.slide[:, None] * s.direction,
                               atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(np.sum(s.point * s.direction, axis=-1), 0.0, atol=1e-12)
    rebuilt = RigidTransform.from_translation(s.point + s.slide[:, None] * s.direction) * (
        RigidTransform.from_rotation(Rotation.from_rotvec(s.angle[:, None] * s.direction))
        * RigidTransform.from_translation(-s.point)
    )
    np.testing.assert_allclose(rebuilt.as_matrix(), tf.as_matrix(), atol=1e-12)


def test_screw_pure_translation_and_pure_rotation_exact():
    s = RigidTransform.from_translation([0.0, 3.0, 4.0]).screw()
    assert s.angle == 0 and s.slide == 5.0 and s.pitch == np.inf
    np.testing.assert_array_equal(s.direction, [0.0, 0.6, 0.8])
    np.testing.assert_array_equal(s.point, [0.0, 0.0, 0.0])
    r = Rotation.from_rotvec([0.0, 0.0, 0.5])
    about = RigidTransform.from_translation([1.0, 2.0, 0.0])
    pure = about * RigidTransform.from_rotation(r) * about.inv()  # about the line x=1, y=2
    s = pure.screw()
    assert abs(float(s.slide)) < 1e-15 and abs(float(s.pitch)) < 1e-14
    np.testing.assert_allclose(s.point, [1.0, 2.0, 0.0], atol=1e-14)
    ident = RigidTransform.identity().screw()
    assert np.isnan(ident.pitch) and ident.angle == 0


def test_sclerp_endpoints_constant_screw_and_special_cases():
    a, b = _ours()[0], _ours()[1]
    np.testing.assert_allclose(sclerp(a, b, 0.0).as_matrix(), a.as_matrix(), atol=1e-14)
    np.testing.assert_allclose(sclerp(a, b, 1.0).as_matrix(), b.as_matrix(), atol=1e-13)
    half = sclerp(a, b, 0.5)
    step = a.inv() * half
    np.testing.assert_allclose((a * step * step).as_matrix(), b.as_matrix(), atol=1e-13)
    s = np.linspace(0, 1, 5)
    rot_a, rot_b = (
        RigidTransform.from_rotation(a.rotation),
        RigidTransform.from_rotation(b.rotation),
    )
    from poinsot import slerp

    np.testing.assert_allclose(
        sclerp(rot_a, rot_b, s).rotation.as_matrix(),
        slerp(a.rotation, b.rotation, s).as_matrix(),
        atol=1e-13,
    )
    ta, tb = RigidTransform.from_translation(T[0]), RigidTransform.from_translation(T[1])
    np.testing.assert_allclose(sclerp(ta, tb, s).as_components()[0],
                               T[0] + s[:, None] * (T[1] - T[0]), atol=1e-14)  # fmt: skip


def test_bad_inputs_are_named():
    m = np.eye(4)
    m[3, 0] = 0.5
    with pytest.raises(InvalidInputError, match="bottom row"):
        RigidTransform.from_matrix(m)
    with pytest.raises(InvalidInputError, match="matrix"):
        RigidTransform.from_matrix(np.eye(3))
    with pytest.raises(InvalidInputError, match="real part"):
        RigidTransform.from_dual_quat(np.zeros(8))
    with pytest.raises(InvalidInputError, match="translation"):
        RigidTransform.from_components([1.0, 2.0], Rotation.identity())
    # the argument is `rotation` (it named `quat`, the argument of from_quat: issue 38)
    for bad in (np.ones((2, 5)), [1.0, 0.0, 0.0]):
        with pytest.raises(InvalidInputError, match="`rotation`.*got shape"):
            RigidTransform.from_components([1.0, 2.0, 3.0], bad)
        with pytest.raises(InvalidInputError, match="`rotation`"):
            RigidTransform.from_rotation(bad)


@pytest.mark.parametrize("streamed", [False, True])
def test_large_batch_matrices_equal_small_batches_on_any_thread_count(streamed):
    """A large batch's homogeneous matrices (one compiled pass; with streaming stores
    once the result reaches ``_kernels.STREAM_MIN_BYTES``) are, bit for bit on 1 and on
    every thread, those of small batches (NumPy assembly of ``Rotation.as_matrix``),
    with the last row ``(0, 0, 0, 1)``, the translations as given and ``R`` orthonormal
    to round-off; one translation given for every rotation too."""
    from poinsot.rotations import PARALLEL_MIN_SIZE
    from poinsot.rotations._kernels import STREAM_MIN_BYTES
    from rotation_cases import on_one_and_every_thread

    n = (STREAM_MIN_BYTES // 128 if streamed else PARALLEL_MIN_SIZE) + 1001
    rng = np.random.default_rng(13)
    r = Rotation.from_quat(rng.normal(size=(n, 4)))
    t = rng.normal(size=(n, 3))
    t[: n // 2] = [1.0, -2.0, 3.0]
    tf = RigidTransform.from_components(t, r)
    want = np.concatenate([tf[i : i + 5000].as_matrix() for i in range(0, n, 5000)])
    for got in on_one_and_every_thread(tf.as_matrix):
        assert got.tobytes() == want.tobytes()
    np.testing.assert_array_equal(got[:, 3], np.broadcast_to([0.0, 0.0, 0.0, 1.0], (n, 4)))
    np.testing.assert_array_equal(got[:, :3, 3], t)
    rt = got[:, :3, :3]
    np.testing.assert_allclose(
        rt @ rt.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (n, 3, 3)), atol=1e-14
    )
    single = RigidTransform.from_components(t[7], r[7]).as_matrix()
    np.testing.assert_array_equal(got[7], single)
    one_t = RigidTransform.from_components([1.0, 2.0, 3.0], r)  # broadcast to every rotation
    np.testing.assert_array_equal(
        one_t.as_matrix()[:, :3, 3], np.broadcast_to([1.0, 2.0, 3.0], (n, 3))
    )
