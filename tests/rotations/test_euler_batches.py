"""Quaternion -> Euler angles on large batches (the fused SIMD kernel, issue 40).

Batches of at least ``PARALLEL_MIN_SIZE`` take ``_kernels.to_euler_flat``, which runs
the formula of ``_scalar.to_euler`` with ``_scalar.atan2_poly`` (arithmetic only, so
that the loop vectorises) in place of libm's ``atan2``. The truths: libm's
``math.atan2`` for the arctangent (to within 2 ulp, signed zeros exactly), SciPy's
``as_euler`` and the small-batch path (libm) for the angles.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import GimbalLockWarning, Rotation
from poinsot.rotations import PARALLEL_MIN_SIZE
from poinsot.rotations import _scalar as S

N_BIG = PARALLEL_MIN_SIZE + 77  # not a multiple of the 256-rotation block


def _atan2_cases() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(5)
    n = 200_000
    y = rng.standard_normal(n) * np.exp(rng.uniform(-30, 30, n))
    x = rng.standard_normal(n) * np.exp(rng.uniform(-30, 30, n))
    # the band edges (|y|/|x| = 0.66 and 1/0.66, 1), signed zeros, the axes
    t = np.array([0.66, 1 / 0.66, 1.0, 0.66 * (1 + 1e-16), 1e-300, 1e300])
    edge_y = np.concatenate([t, -t, [0.0, -0.0, 0.0, -0.0, 1.0, -1.0, 0.0, -0.0]])
    edge_x = np.concatenate([np.ones(6), -np.ones(6), [1.0, 1.0, -1.0, -1.0, 0.0, 0.0, -0.0, -0.0]])
    return np.concatenate([y, edge_y]), np.concatenate([x, edge_x])


def test_atan2_poly_is_within_2_ulp_of_libm_with_its_signed_zeros():
    numba = pytest.importorskip("numba")
    f = numba.njit(S.atan2_poly)
    y, x = _atan2_cases()
    got = np.array([f(a, b) for a, b in zip(y.tolist(), x.tolist(), strict=True)])
    want = np.array([math.atan2(a, b) for a, b in zip(y.tolist(), x.tolist(), strict=True)])
    ulp = np.abs(got - want) / np.spacing(np.abs(want))
    assert ulp.max() <= 2.0, ulp.max()
    assert np.mean(got == want) > 0.85  # mostly libm's own bits
    np.testing.assert_array_equal(np.signbit(got), np.signbit(want))
    # the plain-Python run (the formula as written) gives the same numbers
    some = slice(0, None, 997)
    np.testing.assert_array_equal(
        [S.atan2_poly(a, b) for a, b in zip(y[some].tolist(), x[some].tolist(), strict=True)],
        got[some],
    )


@pytest.mark.parametrize("seq", ["xyz", "ZYX", "ZXZ", "zxz", "XZY", "yxy"])
def test_large_batches_match_scipy_and_the_small_batch_path(seq):
    rng = np.random.default_rng(7)
    q = rng.standard_normal((N_BIG, 4))
    # gimbal lock, exactly and within / beyond 1e-7 rad, in the middle of the batch
    lock = Rotation.from_euler(seq, [[0.3, 0.0, 0.2], [0.3, np.pi / 2, 0.2]] * 5).as_quat()
    near = Rotation.from_euler(seq, [[0.3, 1e-8, 0.2], [0.3, np.pi / 2 - 2e-7, 0.2]]).as_quat()
    q[1000 : 1000 + 12] = np.vstack([lock, near])
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # both warn in gimbal lock
        big = Rotation.from_quat(q).as_euler(seq)
        parts = np.vstack(
            [Rotation.from_quat(q[i : i + 5000]).as_euler(seq) for i in range(0, N_BIG, 5000)]
        )
        ref = SciPyRotation.from_quat(q, scalar_first=True).as_euler(seq)
    np.testing.assert_allclose(big, parts, rtol=0, atol=4e-15)
    assert np.mean(big == parts) > 0.75  # mostly the same bits as libm's path
    free = np.ones(N_BIG, dtype=bool)
    free[1000 : 1000 + 12] = False  # SciPy keeps the computed middle angle in the lock
    np.testing.assert_allclose(big[free], ref[free], rtol=0, atol=4e-15)
    assert np.all(np.abs(big) <= np.pi)


def test_large_batches_warn_exactly_when_a_rotation_is_in_gimbal_lock():
    rng = np.random.default_rng(8)
    angles = rng.uniform(-1.0, 1.0, (N_BIG, 3))
    r = Rotation.from_euler("ZXZ", angles + [0.0, 2.0, 0.0])  # middle angle in [1, 3]
    with warnings.catch_warnings():
        warnings.simplefilter("error", GimbalLockWarning)
        r.as_euler("ZXZ")
    angles[N_BIG - 1, 1] = -2.0  # the last rotation, in the last, partial block: nutation 0
    r = Rotation.from_euler("ZXZ", angles + [0.0, 2.0, 0.0])
    with pytest.warns(GimbalLockWarning, match="Gimbal lock"):
        a = r.as_euler("ZXZ")
    assert a[-1, 1] == 0.0 and a[-1, 2] == 0.0
    np.testing.assert_allclose(a[-1, 0], angles[-1, 0] + angles[-1, 2], rtol=0, atol=1e-15)
