"""Matrix -> quaternion on large batches (the blocked SIMD kernel) near 180 degrees.

The truths are independent of poinsot: the matrices are built with NumPy from
Rodrigues' formula ``A = cos f E + (1 - cos f) e e^T + sin f e^`` (theory §2) and
compared with the exact quaternion ``(cos f/2, e sin f/2)`` and with SciPy's
``Rotation.from_matrix``. Batches of at least ``PARALLEL_MIN_SIZE`` take the
blocked kernel (blocks of 256 rotations), smaller ones the broadcasting gufunc;
a size that is not a multiple of the block checks the last, partial block.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.rotations import PARALLEL_MIN_SIZE

N_BIG = PARALLEL_MIN_SIZE + 77


def _axis_angle_batch(n: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, 3))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    near_pi = np.array([np.pi - 1e-8, np.pi, np.pi - 1e-12, np.pi - 1e-4, 1e-9, 0.0])
    f = np.where(
        np.arange(n) % 2 == 0, near_pi[np.arange(n) % near_pi.size], rng.uniform(0, np.pi, n)
    )
    return e, f


def _rodrigues(e: np.ndarray, f: np.ndarray) -> np.ndarray:
    c, s = np.cos(f)[:, None, None], np.sin(f)[:, None, None]
    hat = np.zeros(e.shape[:-1] + (3, 3))
    hat[:, 0, 1], hat[:, 0, 2], hat[:, 1, 2] = -e[:, 2], e[:, 1], -e[:, 0]
    hat -= np.swapaxes(hat, -1, -2)
    return c * np.eye(3) + (1.0 - c) * e[:, :, None] * e[:, None, :] + s * hat


def _exact_quat(e: np.ndarray, f: np.ndarray) -> np.ndarray:
    return np.concatenate([np.cos(f / 2)[:, None], e * np.sin(f / 2)[:, None]], axis=1)


def _sign_free_distance(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return np.minimum(np.linalg.norm(p - q, axis=-1), np.linalg.norm(p + q, axis=-1))


@pytest.mark.parametrize("n", [N_BIG, 500])
def test_near_pi_matrices_give_the_exact_quaternion(n):
    e, f = _axis_angle_batch(n)
    q = Rotation.from_matrix(_rodrigues(e, f)).as_quat()
    # observed: <= 4.5e-16 (a few ulp: the matrix entries carry their own rounding),
    # also at pi - 1e-8 where the scalar part (5e-9) is far smaller than the others
    err = _sign_free_distance(q, _exact_quat(e, f))
    assert err.max() < 5e-15
    # the tiny scalar part near pi comes from an off-diagonal difference (a21 - a12 =
    # 2 e1 sin f ~ 1e-8), not from 1 + tr (which would cancel to nothing): its relative
    # error is the matrix entries' rounding (1e-16) over 1e-8. Observed 1.5e-8.
    at = np.isclose(f, np.pi - 1e-8, rtol=0, atol=1e-15)
    w = np.abs(q[at, 0])
    np.testing.assert_allclose(w, np.sin(1e-8 / 2), rtol=2e-7)


@pytest.mark.parametrize("n", [N_BIG, 500])
def test_large_and_small_batches_agree_with_scipy(n):
    e, f = _axis_angle_batch(n, seed=4)
    m = _rodrigues(e, f)
    ours = Rotation.from_matrix(m).as_quat()
    theirs = SciPyRotation.from_matrix(m).as_quat(scalar_first=True)
    assert _sign_free_distance(ours, theirs).max() < 5e-15  # observed 3.0e-16


def test_blocked_kernel_equals_the_one_rotation_path_bit_for_bit():
    e, f = _axis_angle_batch(N_BIG, seed=5)
    m = _rodrigues(e, f)
    big = Rotation.from_matrix(m).as_quat()
    rows = np.r_[0:300, N_BIG - 300 : N_BIG]  # first blocks and the partial last one
    singles = np.array([Rotation.from_matrix(m[i]).as_quat() for i in rows])
    np.testing.assert_array_equal(big[rows], singles)


@pytest.mark.parametrize("n", [N_BIG, 50])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_matrices_are_rejected_in_batches(n, bad):
    m = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    m[n - 1, 1, 2] = bad  # one entry of the last matrix (in the partial block)
    with pytest.raises(InvalidInputError, match="`matrix` to contain only finite values"):
        Rotation.from_matrix(m)


@pytest.mark.parametrize("n", [N_BIG, 50])
def test_improper_and_non_orthogonal_batches_are_rejected(n):
    m = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    m[n // 2] = np.diag([1.0, 1.0, -1.0])
    with pytest.raises(InvalidInputError, match=r"determinant > 0\), got det = -1"):
        Rotation.from_matrix(m)
    m[n // 2] = np.diag([1.0, 1.0, 1.001])
    with pytest.raises(InvalidInputError, match="orthogonal within 1e-06"):
        Rotation.from_matrix(m)
    # slightly off (1e-10): projected onto the nearest rotation, then converted
    m[n // 2] = np.diag([1.0, 1.0, 1.0 + 1e-10])
    q = Rotation.from_matrix(m).as_quat()
    np.testing.assert_allclose(_sign_free_distance(q, np.array([1.0, 0, 0, 0])), 0, atol=1e-15)


def _streamed_batch() -> tuple[np.ndarray, np.ndarray]:
    # a result of at least STREAM_MIN_BYTES (the kernel's streaming stores), a row count
    # that is not a multiple of the block: the last, partial block of the last part
    from poinsot.rotations._kernels import STREAM_MIN_BYTES

    n = STREAM_MIN_BYTES // 32 + 1001
    e, f = _axis_angle_batch(n, seed=6)
    return _rodrigues(e, f), _exact_quat(e, f)


def test_streamed_batch_equals_sub_batches_bit_for_bit_on_any_thread_count():
    """The streamed result (the check reduced to a count per part, no per-matrix
    arrays) is, bit for bit, what sub-batches of the plain-store kernel and the
    one-rotation path give, on one and on every thread; and the exact quaternion
    to round-off."""
    from rotation_cases import on_one_and_every_thread

    m, exact = _streamed_batch()
    n = len(m)
    parts = [Rotation.from_matrix(m[i : i + N_BIG]).as_quat() for i in range(0, n, N_BIG)]
    want = np.concatenate(parts)
    assert want.nbytes // len(parts) < 1 << 24  # the sub-batches store plainly
    rows = np.r_[0:5, n - 5 : n]
    singles = np.array([Rotation.from_matrix(m[i]).as_quat() for i in rows])
    np.testing.assert_array_equal(want[rows], singles)
    for got in on_one_and_every_thread(lambda: Rotation.from_matrix(m).as_quat()):
        assert got.tobytes() == want.tobytes()
    assert _sign_free_distance(got, exact).max() < 5e-15  # observed 4.7e-16


@pytest.mark.parametrize("where", ["first", "last"])
def test_one_bad_matrix_in_a_streamed_batch_is_found(where):
    """The count per part finds a single bad matrix anywhere (the first row, the last
    row of the partial block), and the batch then gets the per-matrix messages and
    projection."""
    m, exact = _streamed_batch()
    i = 0 if where == "first" else len(m) - 1
    keep = m[i].copy()
    m[i, 2, 1] = np.nan
    with pytest.raises(InvalidInputError, match="only finite values"):
        Rotation.from_matrix(m)
    m[i] = keep * np.array([1.0, 1.0, -1.0])  # a reflection: det = -1
    with pytest.raises(InvalidInputError, match=r"determinant > 0\), got det = -1"):
        Rotation.from_matrix(m)
    m[i] = keep @ np.diag([1.0, 1.0, 1.0 + 1e-9])  # off by 2e-9: projected
    q = Rotation.from_matrix(m).as_quat()
    assert _sign_free_distance(q[i], exact[i]) < 5e-15  # observed 1.7e-16
    with pytest.raises(InvalidInputError, match="orthogonal within 1e-10"):
        Rotation.from_matrix(m, atol=1e-10)
    # a user tolerance below the exact one (1e-14) is the one applied: the Rodrigues
    # matrices' round-off (observed max |A^T A - E| = 2e-15) fails 1e-15, and exact
    # identities pass atol = 0
    m[i] = keep
    with pytest.raises(InvalidInputError, match="orthogonal within 1e-15"):
        Rotation.from_matrix(m, atol=1e-15)
    m[:] = np.eye(3)
    q = Rotation.from_matrix(m, atol=0.0).as_quat()
    assert q.tobytes() == np.broadcast_to([1.0, 0.0, 0.0, 0.0], q.shape).tobytes()


# ------------------------------------------------------- as_matrix(out=...) (issue 40)
@pytest.mark.parametrize("shape", [(), (7,), (5, 3), (N_BIG,), (2, N_BIG // 2)])
def test_as_matrix_into_out_returns_out_with_the_fresh_result(shape):
    r = Rotation.random(shape, rng=4)
    want = r.as_matrix()
    out = np.full(shape + (3, 3), np.nan)
    got = r.as_matrix(out=out)
    assert got is out
    np.testing.assert_array_equal(out, want)
    # reused: overwritten, not accumulated
    r2 = Rotation.random(shape, rng=5)
    assert r2.as_matrix(out=out) is out
    np.testing.assert_array_equal(out, r2.as_matrix())


def test_as_matrix_into_out_streamed_batch():
    # a result of at least STREAM_MIN_BYTES is written with streaming stores
    m, _ = _streamed_batch()
    r = Rotation.from_matrix(m)
    out = np.empty(m.shape)
    assert r.as_matrix(out=out) is out
    assert out.tobytes() == r.as_matrix().tobytes()


@pytest.mark.parametrize(
    "out, error, match",
    [
        (
            np.empty((4, 3, 3)),
            InvalidInputError,
            r"`out` to have shape \(3, 3, 3\), got \(4, 3, 3\)",
        ),
        (np.empty((3, 9)), InvalidInputError, r"`out` to have shape \(3, 3, 3\), got \(3, 9\)"),
        (
            np.empty((3, 3, 3), np.float32),
            InvalidTypeError,
            "`out` to be a float64 array, got dtype float32",
        ),
        (
            np.empty((3, 3, 3), np.int64),
            InvalidTypeError,
            "`out` to be a float64 array, got dtype int64",
        ),
        (np.empty((3, 3, 6))[..., ::2], InvalidInputError, "`out` to be a C-contiguous array"),
        (
            np.empty((3, 3, 3)).transpose(0, 2, 1),
            InvalidInputError,
            "`out` to be a C-contiguous array",
        ),
        ([[0.0] * 3] * 3, InvalidTypeError, "`out` to be a NumPy array, got list"),
    ],
)
def test_as_matrix_rejects_a_wrong_out(out, error, match):
    with pytest.raises(error, match=match):
        Rotation.random(3, rng=0).as_matrix(out=out)


def test_as_matrix_rejects_a_read_only_out_and_a_wrong_single_out():
    out = np.empty((3, 3, 3))
    out.setflags(write=False)
    with pytest.raises(InvalidInputError, match="`out` to be a writeable array"):
        Rotation.random(3, rng=0).as_matrix(out=out)
    with pytest.raises(InvalidInputError, match=r"`out` to have shape \(3, 3\), got \(1, 3, 3\)"):
        Rotation.identity().as_matrix(out=np.empty((1, 3, 3)))
