"""QUEST and ESOQ2 of ``determine_attitude`` run one source (``poinsot.rotations._wahba``)
two ways: compiled (a parallel loop over the batch) and on NumPy columns (the executor
of ``POINSOT_NUMBA=0``). Both against each other and against the SVD (SciPy's
``align_vectors`` method, an independent algorithm) at 1e-12, and the degenerate sets
named by the same errors as the NumPy path's."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError, _jit
from poinsot.rotations import PARALLEL_MIN_SIZE, determine_attitude, set_num_threads

FAST = ("quest", "esoq2")


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _sets(m, n, *, seed=0, noise=1e-3, rotvec=None):
    """``m`` well-conditioned sets of ``n`` observations (random directions, noise in rad)."""
    rng = np.random.default_rng(seed)
    truth = SciRotation.random(m, random_state=seed) if rotvec is None else rotvec
    r = _unit(rng.normal(size=(m, n, 3)))
    close = np.abs(np.einsum("mi,mi->m", r[:, 0], r[:, 1])) > 0.9  # well-conditioned:
    r[close, 1] = _unit(np.cross(r[close, 0], r[close, 1]))  # the first two >= 25 deg apart
    b = np.einsum("mji,mkj->mki", truth.as_matrix(), r)  # b_i = C^T r_i
    b = _unit(b + noise * rng.normal(size=b.shape))
    w = rng.uniform(0.5, 2.0, size=(m, n))
    return b, r, w


def _numpy(monkeypatch, *args, **kwargs):
    """The NumPy executor's answer (the path of POINSOT_NUMBA=0), in this process."""
    with monkeypatch.context() as mp:
        mp.setattr(_jit, "NUMBA", False)
        return determine_attitude(*args, **kwargs)


def _qdist(q1, q2):
    return float(np.max(np.minimum(np.abs(q1 - q2).max(-1), np.abs(q1 + q2).max(-1))))


def _agree(a, b, tol=1e-12):
    assert _qdist(a.quat, b.quat) <= tol
    np.testing.assert_allclose(a.loss, b.loss, rtol=1e-9, atol=1e-15)
    if a.covariance is not None and b.covariance is not None:
        np.testing.assert_allclose(a.covariance, b.covariance, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("method", FAST)
@pytest.mark.parametrize("n", [2, 3, 5])
@pytest.mark.parametrize("m", [7, PARALLEL_MIN_SIZE + 3])  # serial and threaded loops
def test_compiled_numpy_and_svd_agree(monkeypatch, method, n, m):
    b, r, w = _sets(m, n, seed=n)
    fast = determine_attitude(b, r, w, method=method)
    ref = determine_attitude(b, r, w, method="svd")
    _agree(fast, ref)
    if m < 1000 or n == 3:  # the NumPy executor on the large batch once per method
        _agree(_numpy(monkeypatch, b, r, w, method=method), fast)
    assert np.all(fast.quat[..., 0] >= 0.0)


def _turn_sets(m, n, seed, rng):
    """``m`` sets of ``n`` observations: half of them within 1e-9 to 1 rad of a half
    turn, half within 1e-9 to 1 rad of the identity, about random axes."""
    axes = _unit(rng.normal(size=(m, 3)))
    k = m // 2
    angles = np.concatenate([np.pi - np.geomspace(1e-9, 1.0, k), np.geomspace(1e-9, 1.0, m - k)])
    return _sets(
        m, n, seed=seed, noise=1e-4, rotvec=SciRotation.from_rotvec(axes * angles[:, None])
    )


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("method", FAST)
def test_near_half_turns_and_identity(monkeypatch, method, n):
    # QUEST's frame turns (|l0| < 0.3) and ESOQ2's (near the identity): every branch;
    # (choosing the turn by the largest diagonal of K left 1.9e-9 rad on 1e6 sets of
    # two observations, benchmarks/bench_determination.py; the largest l0': 8e-15)
    b, r, w = _turn_sets(400, n, seed=4, rng=np.random.default_rng(4))
    fast = determine_attitude(b, r, w, method=method)
    _agree(fast, determine_attitude(b, r, w, method="svd"), tol=1e-11)
    _agree(_numpy(monkeypatch, b, r, w, method=method), fast)


@pytest.mark.parametrize("method", FAST)
def test_broadcast_catalogue_and_batch_shape(monkeypatch, method):
    b, r, w = _sets(24, 3, seed=9)
    cat = r[0]  # one catalogue (n, 3) for the batch, one weight vector (n,)
    b = b.reshape(2, 3, 4, 3, 3)
    fast = determine_attitude(b, cat, w[0], method=method)
    assert fast.quat.shape == (2, 3, 4, 4) and fast.covariance.shape == (2, 3, 4, 3, 3)
    ref = determine_attitude(b, np.broadcast_to(cat, b.shape), np.broadcast_to(w[0], b.shape[:-1]),
                             method="svd")  # fmt: skip
    _agree(fast, ref)
    _agree(_numpy(monkeypatch, b, cat, w[0], method=method), fast)


@pytest.mark.parametrize("method", FAST)
def test_covariance_is_optional(monkeypatch, method):
    b, r, w = _sets(50, 3, seed=2)
    full = determine_attitude(b, r, w, method=method)
    lean = determine_attitude(b, r, w, method=method, covariance=False)
    assert lean.covariance is None
    np.testing.assert_array_equal(lean.quat, full.quat)
    np.testing.assert_array_equal(lean.loss, full.loss)
    assert _numpy(monkeypatch, b, r, w, method=method, covariance=False).covariance is None
    assert determine_attitude(b, r, w, method="svd", covariance=False).covariance is None


@pytest.mark.skipif(not _jit.NUMBA, reason="threads: numba only")
def test_threads_give_identical_results():
    b, r, w = _sets(PARALLEL_MIN_SIZE * 2, 3, seed=5)
    out = []
    try:
        for k in (1, 2):
            set_num_threads(k)
            out.append(determine_attitude(b, r, w).quat)
    finally:
        set_num_threads(None)
    np.testing.assert_array_equal(out[0], out[1])


def _bad_sets():
    good = _sets(6, 3, seed=1)[:2]
    cases = []
    for name, idx, value in [
        ("observed", (4, 1), np.nan),
        ("reference", (2, 0), np.inf),
        ("observed", (3, 2), 0.0),
        ("reference", (5, 1), 0.0),
    ]:
        b, r = (x.copy() for x in good)
        (b if name == "observed" else r)[idx] = value
        cases.append((b, r, None))
    b, r = (x.copy() for x in good)
    b[2, 1] = b[2, 0] * 3.0  # parallel observed, the third weighted 0
    cases.append((b, r, np.array([1.0, 1.0, 0.0])))
    b, r = (x.copy() for x in good)
    r[1, :] = r[1, 0]  # all three references of set 1 parallel
    cases.append((b, r, None))
    b, r = (x.copy() for x in good)
    b[4, 0] = 0.0  # a zero observation after a non-finite reference: finiteness first
    r[5, 2] = np.nan
    cases.append((b, r, None))
    return cases


@pytest.mark.parametrize("case", range(7))
@pytest.mark.parametrize("method", FAST)
def test_degenerate_sets_raise_the_numpy_paths_errors(monkeypatch, case, method):
    b, r, w = _bad_sets()[case]
    with pytest.raises(InvalidInputError) as expected:
        determine_attitude(b, r, w, method="svd")
    with pytest.raises(InvalidInputError) as got:
        determine_attitude(b, r, w, method=method)
    assert str(got.value) == str(expected.value)
    with pytest.raises(InvalidInputError) as got_np:
        _numpy(monkeypatch, b, r, w, method=method)
    assert str(got_np.value) == str(expected.value)


def test_empty_batch():
    sol = determine_attitude(np.zeros((0, 3, 3)), np.zeros((0, 3, 3)))
    assert sol.quat.shape == (0, 4) and sol.covariance.shape == (0, 3, 3)


@pytest.mark.skipif(not _jit.NUMBA, reason="the block pass: numba only")
@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("method", FAST)
def test_block_pass_is_solve_bit_for_bit(monkeypatch, method, n):
    # the compiled loops solve sets of 2 and 3 observations a block at a time without a
    # branch (_wahba.solve_fast), the NumPy executor set by set with branches
    # (solve_slow): the same operations, so the same bits; near half-turns, near the
    # identity, noise as large as the signal (Newton past the block's fixed steps, the
    # sets solved again) and a set in a block that fails
    rng = np.random.default_rng(11)
    b, r, w = _turn_sets(300, n, seed=5, rng=rng)
    b[::3] = _unit(b[::3] + rng.normal(size=b[::3].shape))
    fast = determine_attitude(b, r, w, method=method)
    slow = _numpy(monkeypatch, b, r, w, method=method)
    np.testing.assert_array_equal(fast.quat, slow.quat)
    np.testing.assert_array_equal(fast.loss, slow.loss)
    np.testing.assert_array_equal(fast.covariance, slow.covariance)
    b[7, :] = b[7, 0]  # all parallel: the same error from either path
    with pytest.raises(InvalidInputError, match=r"observed.*non-parallel"):
        determine_attitude(b, r, w, method=method)
