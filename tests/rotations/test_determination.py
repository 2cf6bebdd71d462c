"""Attitude determination (Wahba's problem, docs/theory.md §2.4), each check against an
independent truth: the true rotation of noise-free data, SciPy's ``align_vectors``
(SVD), SciPy's exact-primary-vector alignment for TRIAD, a Monte-Carlo covariance, and
SciPy's documented example."""

from __future__ import annotations

import importlib
import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.rotations import ATTITUDE_METHODS, AttitudeSolution, determine_attitude
from poinsot.rotations.determination import QUEST_ROTATION_THRESHOLD

OPTIMAL = ("svd", "q-method", "quest", "esoq2")
SHAPES = [(), (5,), (2, 3), (1000,)]


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _canon(q):
    return np.where(q[..., :1] < 0, -q, q)


def _qdist(q1, q2):
    """Max-abs difference of two quaternion arrays up to sign (q and -q are one rotation)."""
    return np.max(np.minimum(np.abs(q1 - q2).max(-1), np.abs(q1 + q2).max(-1)))


def _problem(shape, n=4, *, seed=0, noise=0.0, rotvec=None):
    """True quaternions (body -> reference), references r and body observations b = C^T r."""
    rng = np.random.default_rng(seed)
    m = int(np.prod(shape, dtype=int))
    truth = (
        SciRotation.random(m, random_state=seed)
        if rotvec is None
        else SciRotation.from_rotvec(rotvec)
    )
    r = _unit(rng.normal(size=(m, n, 3)))
    b = np.einsum("mji,mkj->mki", truth.as_matrix(), r)  # b_i = C^T r_i
    if noise:
        b = _unit(b + noise * rng.normal(size=b.shape))
    q = _canon(truth.as_quat(scalar_first=True))
    return q.reshape(shape + (4,)), b.reshape(shape + (n, 3)), r.reshape(shape + (n, 3))


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("method", OPTIMAL)
def test_noise_free_sets_give_the_true_rotation(shape, method):
    q, b, r = _problem(shape)
    sol = determine_attitude(b, r, method=method)
    assert sol.quat.shape == shape + (4,) and sol.loss.shape == shape
    assert sol.covariance.shape == shape + (3, 3)
    assert _qdist(sol.quat, q) < 1e-12
    assert np.all(sol.quat[..., 0] >= 0)
    assert np.all(sol.loss < 1e-25)


@pytest.mark.parametrize("shape", SHAPES)
def test_triad_gives_the_true_rotation_of_noise_free_pairs(shape):
    q, b, r = _problem(shape, n=2, seed=1)
    assert _qdist(determine_attitude(b, r, method="triad").quat, q) < 1e-12


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("method", OPTIMAL)
def test_noisy_weighted_sets_match_scipy_svd(shape, method):
    """Against SciPy's ``align_vectors`` (an independent SVD), reference ~ C observed."""
    _, b, r = _problem(shape, n=4, seed=2, noise=1e-2)
    w = np.random.default_rng(3).uniform(0.5, 2.0, size=shape + (4,))
    sol = determine_attitude(b, r, w, method=method)
    flat_b, flat_r, flat_w = b.reshape(-1, 4, 3), r.reshape(-1, 4, 3), w.reshape(-1, 4)
    want = np.array(
        [
            _canon(
                SciRotation.align_vectors(flat_r[k], flat_b[k], flat_w[k])[0].as_quat(
                    scalar_first=True
                )
            )
            for k in range(len(flat_b))
        ]
    ).reshape(shape + (4,))
    assert _qdist(sol.quat, want) < 1e-12
    # the loss at the solution is Wahba's, recomputed by hand with SciPy's rotation
    c = SciRotation.from_quat(want.reshape(-1, 4), scalar_first=True).as_matrix()
    resid = flat_r - np.einsum("mjk,mik->mij", c, flat_b)
    loss = 0.5 * np.sum(flat_w * np.sum(resid**2, axis=-1), axis=-1)
    np.testing.assert_allclose(sol.loss.reshape(-1), loss, rtol=1e-9)


@pytest.mark.parametrize("method", OPTIMAL)
def test_near_half_turns_match_svd(method):
    """Angles pi - 10^U(-16, -1): QUEST's Gibbs vector is infinite at pi, so its
    sequential rotations must run (every solution has |l0| below the threshold)."""
    m = 1000
    rng = np.random.default_rng(4)
    axis = _unit(rng.normal(size=(m, 3)))
    angle = np.pi - 10.0 ** rng.uniform(-16, -1, m)
    q, b, r = _problem((m,), seed=5, noise=1e-3, rotvec=axis * angle[:, None])
    svd = determine_attitude(b, r, method="svd").quat
    sol = determine_attitude(b, r, method=method)
    assert np.all(np.abs(svd[:, 0]) < QUEST_ROTATION_THRESHOLD)
    assert _qdist(sol.quat, svd) < 1e-12
    q_free, b_free, r_free = _problem((m,), seed=5, rotvec=axis * angle[:, None])
    assert _qdist(determine_attitude(b_free, r_free, method=method).quat, q_free) < 1e-12


@pytest.mark.parametrize("method", OPTIMAL)
def test_near_identity_matches_svd(method):
    """ESOQ2's axis is undetermined at the identity: its frame turn must handle it."""
    m = 1000
    rng = np.random.default_rng(6)
    rotvec = _unit(rng.normal(size=(m, 3))) * 10.0 ** rng.uniform(-16, -1, m)[:, None]
    rotvec[:10] = 0.0
    q, b, r = _problem((m,), seed=7, rotvec=rotvec)
    assert _qdist(determine_attitude(b, r, method=method).quat, q) < 1e-12


def test_triad_is_the_exact_two_vector_construction():
    """TRIAD matches the first pair exactly and the plane of the two: SciPy's
    ``align_vectors`` with an infinite primary weight (an independent construction)."""
    _, b, r = _problem((200,), n=2, seed=8, noise=5e-2)
    sol = determine_attitude(b, r, [1.0, 100.0], method="triad")  # weights ignored
    c = sol.rotation.as_matrix()
    np.testing.assert_allclose(np.einsum("mij,mj->mi", c, b[:, 0]), r[:, 0], atol=1e-15)
    want = np.array(
        [
            _canon(
                SciRotation.align_vectors(r[k], b[k], [np.inf, 1.0])[0].as_quat(scalar_first=True)
            )
            for k in range(200)
        ]
    )
    assert _qdist(sol.quat, want) < 1e-12
    normal_b = _unit(np.cross(b[:, 0], b[:, 1]))
    normal_r = _unit(np.cross(r[:, 0], r[:, 1]))
    np.testing.assert_allclose(np.einsum("mij,mj->mi", c, normal_b), normal_r, atol=1e-14)


def test_scipy_documented_example():
    """SciPy ``Rotation.align_vectors`` docstring: a = [[0, 1, 0], [0, 0, 1]] ~ C b for
    b = [[1, 0, 0], [0, 0, 1]] gives C = [[0, -1, 0], [1, 0, 0], [0, 0, 1]] (a quarter
    turn about z, checked by hand: C (1, 0, 0) = (0, 1, 0), C (0, 0, 1) = (0, 0, 1)).
    The published QUEST test cases (Shuster & Oh 1981; Markley & Mortari 2000) were not
    available to this test, so their numbers are not used."""
    for method in ATTITUDE_METHODS:
        sol = determine_attitude([[1, 0, 0], [0, 0, 1]], [[0, 1, 0], [0, 0, 1]], method=method)
        np.testing.assert_allclose(sol.quat, [0.5**0.5, 0, 0, 0.5**0.5], atol=1e-15)
        np.testing.assert_allclose(
            sol.rotation.as_matrix(), [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15
        )
        np.testing.assert_allclose(sol.covariance, np.diag([1.0, 0.5, 1.0]), atol=1e-15)


def test_covariance_matches_monte_carlo():
    """20000 draws, noise perpendicular to each body vector with sigma = 1e-3 rad per
    axis (Shuster's QUEST model): the sample covariance of dtheta, L_est = L_true o
    exp(dtheta/2) (body axes), equals P = (sum w_i (E - b_i b_i^T))^-1 for w = 1/sigma^2:
    5% on the diagonal (sampling error ~1%), 0.03 on the correlations."""
    m = 20000
    rng = np.random.default_rng(9)
    sig = np.array([1e-3, 2e-3, 1.5e-3])
    r = _unit(np.array([[1.0, 0.2, 0.0], [0.1, 1.0, 0.3], [0.0, 0.4, 1.0]]))
    truth = SciRotation.from_rotvec([0.3, -1.2, 2.0])
    b_true = truth.inv().apply(r)  # b_i = C^T r_i
    # two unit vectors perpendicular to each b_i
    u1 = _unit(np.cross(b_true, [0.0, 0.0, 1.0]))
    u2 = np.cross(b_true, u1)
    n1, n2 = rng.normal(size=(2, m, 3, 1))
    b = _unit(b_true + sig[:, None] * (n1 * u1 + n2 * u2))
    sol = determine_attitude(b, r, 1.0 / sig**2)
    q_true = truth.as_quat(scalar_first=True)
    err = (SciRotation.from_quat(q_true, scalar_first=True).inv()
           * SciRotation.from_quat(sol.quat, scalar_first=True)).as_rotvec()  # fmt: skip
    sample = np.cov(err.T)
    p_exact = np.linalg.inv(
        sum((np.eye(3) - np.outer(v, v)) / s**2 for v, s in zip(b_true, sig, strict=True))
    )
    # P from the measured b_i: equal to first order (relative ~ the noise, 1e-3 rad)
    np.testing.assert_allclose(sol.covariance, np.broadcast_to(p_exact, (m, 3, 3)), rtol=0,
                               atol=0.03 * p_exact.diagonal().max())  # fmt: skip
    np.testing.assert_allclose(np.diag(sample), np.diag(p_exact), rtol=0.05)
    d = np.sqrt(np.diag(p_exact))
    np.testing.assert_allclose(sample / np.outer(d, d), p_exact / np.outer(d, d), atol=0.03)
    assert np.abs(err.mean(axis=0)).max() < 4 * d.max() / np.sqrt(m)  # unbiased


def test_broadcasting_catalogue_and_weights():
    q, b, r = _problem((6,), seed=10)
    sol = determine_attitude(b[None], r, [1.0, 2.0, 3.0, 4.0])  # (1, 6, n, 3) with (6, n, 3)
    assert sol.shape == (1, 6) and _qdist(sol.quat[0], q) < 1e-12
    one = determine_attitude(b[:, None] @ np.eye(3), r[0], method="q-method")
    assert one.quat.shape == (6, 1, 4)


def test_solution_object():
    _, b, r = _problem((3,), seed=11)
    sol = determine_attitude(b, r, method="esoq2")
    assert isinstance(sol, AttitudeSolution) and sol.method == "esoq2"
    assert repr(sol) == "AttitudeSolution(method='esoq2', shape=(3,))"
    assert isinstance(sol.rotation, Rotation)
    np.testing.assert_allclose(sol.rotation.apply(b[:, 0]), r[:, 0], atol=1e-14)
    with pytest.raises(ValueError, match="read-only"):
        sol.quat[0, 0] = 2.0
    # the module as pickle finds it (a --doctest-modules run may import it a second time)
    mod = importlib.import_module("poinsot.rotations.determination")
    sol = mod.determine_attitude(b, r, method="esoq2")
    back = pickle.loads(pickle.dumps(sol))
    np.testing.assert_array_equal(back.quat, sol.quat)


def test_magnitudes_are_ignored():
    q, b, r = _problem((), seed=12)
    scale = np.array([1e-200, 1.0, 1e200, 3.0])[:, None]
    sol = determine_attitude(b * scale, r / scale)
    assert _qdist(sol.quat, q) < 1e-12


# -------------------------------------------------------------------------- errors
GOOD_B = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"observed": [[1.0, 0.0, 0.0]], "reference": [[0.0, 1.0, 0.0]]}, InvalidInputError,
         r"at least two observations .*got n = 1"),
        ({"observed": [[1.0, 0, 0], [2.0, 0, 0]], "reference": GOOD_B}, InvalidInputError,
         r"`observed` to contain at least two non-parallel directions"),
        ({"observed": GOOD_B, "reference": [[0, 0, 1.0], [0, 0, -3.0]]}, InvalidInputError,
         r"`reference` to contain at least two non-parallel"),
        ({"observed": [GOOD_B, [[1.0, 0, 0], [1.0, 1e-9, 0]]], "reference": GOOD_B},
         InvalidInputError, r"non-parallel directions with non-zero weight at index \(1,\)"),
        ({"observed": GOOD_B + [[0, 0, 1.0]], "reference": GOOD_B + [[0, 0, 1.0]],
          "weights": [1.0, 0.0, 0.0]}, InvalidInputError, r"non-parallel .*non-zero weight"),
        ({"observed": [[0.0, 0, 0], [0, 1.0, 0]], "reference": GOOD_B}, InvalidInputError,
         r"`observed` to contain non-zero vectors, got a zero vector at index \(0,\)"),
        ({"observed": GOOD_B, "reference": [[1.0, 0, 0], [0, 0, 0]]}, InvalidInputError,
         r"`reference` to contain non-zero vectors"),
        ({"observed": GOOD_B, "reference": GOOD_B + [[0, 0, 1.0]]}, InvalidInputError,
         r"same number of observations .*\(2, 3\) and \(3, 3\)"),
        ({"observed": [[1.0, 0], [0, 1.0]], "reference": GOOD_B}, InvalidInputError,
         r"Expected `observed` to have shape \(\.\.\., n, 3\), got \(2, 2\)"),
        ({"observed": [1.0, 0, 0], "reference": GOOD_B}, InvalidInputError,
         r"`observed` to have shape \(\.\.\., n, 3\)"),
        ({"observed": [GOOD_B] * 2, "reference": [GOOD_B] * 3}, InvalidInputError,
         r"batch \(leading\) shapes of `observed` \(2,\), `reference` \(3,\)"),
        ({"observed": GOOD_B, "reference": GOOD_B, "weights": [1.0, 1.0, 1.0]},
         InvalidInputError, r"`weights` to have shape \(\.\.\., 2\) or \(2,\), got \(3,\)"),
        ({"observed": GOOD_B, "reference": GOOD_B, "weights": [1.0, -1.0]},
         InvalidInputError, r"`weights` to be non-negative, got -1.0"),
        ({"observed": GOOD_B, "reference": GOOD_B, "weights": [1.0, np.nan]},
         InvalidInputError, r"`weights` to contain only finite"),
        ({"observed": GOOD_B, "reference": GOOD_B, "method": "davenport"}, InvalidInputError,
         r"`method` to be one of 'quest', 'svd', 'q-method', 'esoq2', 'triad', got 'davenport'"),
        ({"observed": GOOD_B, "reference": GOOD_B, "method": 3}, InvalidTypeError,
         r"`method` to be one of"),
        ({"observed": GOOD_B + [[0, 0, 1.0]], "reference": GOOD_B + [[0, 0, 1.0]],
          "method": "triad"}, InvalidInputError, r"exactly two observations for method='triad'"),
        ({"observed": "ab", "reference": GOOD_B}, InvalidTypeError, r"`observed` to be array-like"),
    ],
)  # fmt: skip
def test_errors_name_the_argument(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        determine_attitude(**kwargs)
