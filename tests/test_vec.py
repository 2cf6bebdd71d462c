"""The small shared kernels of ``poinsot._vec`` against NumPy's own."""

from __future__ import annotations

import numpy as np

from poinsot._vec import inverse3


def test_inverse3_of_diagonal_batches_is_lapacks_bit_for_bit():
    # the principal-axes fast path must not change any integrator's result
    rng = np.random.default_rng(3)
    d = rng.uniform(1e-3, 1e3, (500, 3))
    a = d[..., :, None] * np.eye(3)
    got = inverse3(a)
    assert np.array_equal(got, np.linalg.inv(a))
    assert np.allclose(got @ a, np.eye(3), rtol=2e-15, atol=2e-15)


def test_inverse3_of_full_tensors_inverts():
    rng = np.random.default_rng(4)
    m = rng.normal(size=(2, 50, 3, 3))
    a = m @ np.swapaxes(m, -1, -2) + 0.5 * np.eye(3)  # symmetric positive definite
    a[0, 0] = np.diag([1.0, 2.0, 3.0])  # one diagonal entry in a full batch
    got = inverse3(a)
    assert got.shape == a.shape
    assert np.allclose(got @ a, np.eye(3), rtol=0, atol=1e-10)
    assert np.array_equal(inverse3(a[0, 0]), np.diag([1.0, 1 / 2.0, 1 / 3.0]))


def test_diagonal3_is_moments_times_the_identity():
    from poinsot._vec import all_diagonal3, diagonal3

    rng = np.random.default_rng(5)
    for shape in [(3,), (40, 3), (2, 5, 3)]:
        d = rng.uniform(0.1, 10.0, shape)
        got = diagonal3(d)
        assert np.array_equal(got, d[..., :, None] * np.eye(3))
        assert all_diagonal3(got)
    full = diagonal3(rng.uniform(1.0, 2.0, (10, 3)))
    full[7, 2, 0] = 1e-300  # one tiny off-diagonal entry anywhere in the batch
    assert not all_diagonal3(full)
    assert not all_diagonal3(np.zeros((0, 3, 3)))


def test_sort3_is_numpys_sort_with_ties():
    from poinsot.mass.tensor import _sort3

    rng = np.random.default_rng(6)
    for shape in [(3,), (1000, 3), (4, 7, 3)]:
        m = rng.integers(0, 3, shape).astype(float)  # many ties
        assert np.array_equal(_sort3(m), np.sort(m, axis=-1))
        m = rng.normal(size=shape)
        assert np.array_equal(_sort3(m), np.sort(m, axis=-1))


def test_out_arrays_get_the_same_values_and_are_returned():
    # the compiled DOP853 packs J and J^-1 into reused arrays: `out=` must change nothing
    from poinsot._vec import diagonal3

    rng = np.random.default_rng(7)
    d = rng.uniform(0.1, 10.0, (30, 3))
    dirty = np.full((30, 3, 3), np.nan)  # a reused array holds the last call's values
    assert diagonal3(d, out=dirty) is dirty
    assert np.array_equal(dirty, d[..., :, None] * np.eye(3))
    dirty2 = np.full((30, 3, 3), -7.0)
    assert inverse3(dirty, True, out=dirty2) is dirty2
    assert np.array_equal(dirty2, np.linalg.inv(dirty))
    m = rng.normal(size=(30, 3, 3))
    a = m @ np.swapaxes(m, -1, -2) + np.eye(3)
    out = np.empty_like(a)
    assert inverse3(a, out=out) is out
    assert np.array_equal(out, inverse3(a))
