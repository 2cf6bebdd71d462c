"""Quaternion algebra (SPEC S1) against its defining formulas."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import poinsot
from poinsot import quaternion as Q
from rotation_cases import random_quaternions

# magnitudes kept away from the subnormal range, where relative tolerances mean nothing
finite = st.one_of(st.just(0.0), st.floats(1e-6, 10), st.floats(-10, -1e-6))
quats = arrays(np.float64, (4,), elements=finite)
vecs = arrays(np.float64, (3,), elements=finite)


def spec_product(p, q):
    """SPEC S1: L o M = l0 m0 - l.m + l0 m + m0 l + l x m, written independently."""
    p0, pv, q0, qv = p[..., 0], p[..., 1:], q[..., 0], q[..., 1:]
    s = p0 * q0 - np.sum(pv * qv, axis=-1)
    v = p0[..., None] * qv + q0[..., None] * pv + np.cross(pv, qv)
    return np.concatenate([s[..., None], v], axis=-1)


def test_hamilton_units():
    """i_k o i_k = -1, i1 o i2 = i3, i2 o i3 = i1, i3 o i1 = i2, anticommuting."""
    one, i1, i2, i3 = np.eye(4)
    for u in (i1, i2, i3):
        np.testing.assert_array_equal(Q.multiply(u, u), -one)
    np.testing.assert_array_equal(Q.multiply(i1, i2), i3)
    np.testing.assert_array_equal(Q.multiply(i2, i3), i1)
    np.testing.assert_array_equal(Q.multiply(i3, i1), i2)
    np.testing.assert_array_equal(Q.multiply(i2, i1), -i3)


@settings(max_examples=200, deadline=None)
@given(quats, quats)
def test_product_formula_and_commutator(p, q):
    pq = Q.multiply(p, q)
    np.testing.assert_allclose(pq, spec_product(p, q), rtol=1e-13, atol=1e-12)
    # L o M - M o L = 2 l x m
    comm = pq - Q.multiply(q, p)
    np.testing.assert_allclose(comm[0], 0.0, atol=1e-11)
    np.testing.assert_allclose(comm[1:], 2 * np.cross(p[1:], q[1:]), rtol=1e-12, atol=1e-11)
    # ||L o M|| = ||L|| ||M||; (L o M)~ = M~ o L~
    np.testing.assert_allclose(
        Q.norm_squared(pq), Q.norm_squared(p) * Q.norm_squared(q), rtol=1e-12
    )
    np.testing.assert_allclose(
        Q.conjugate(pq), Q.multiply(Q.conjugate(q), Q.conjugate(p)), rtol=1e-12, atol=1e-11
    )


def test_broadcasting_and_batches():
    p = random_quaternions(15, seed=1).reshape(5, 3, 4)
    q = random_quaternions(3, seed=2)
    out = Q.multiply(p, q)
    assert out.shape == (5, 3, 4)
    np.testing.assert_allclose(out, spec_product(p, q[None]), atol=1e-15)
    v = np.random.default_rng(0).standard_normal((5, 3, 3))
    assert Q.rotate(p, v).shape == (5, 3, 3)


def test_inverse_exp_log_power():
    q = random_quaternions(50, seed=3) * np.linspace(0.5, 3, 50)[:, None]
    np.testing.assert_allclose(Q.multiply(q, Q.inverse(q)), [[1, 0, 0, 0]] * 50, atol=5e-15)
    np.testing.assert_allclose(Q.exp(Q.log(q)), q, rtol=1e-13, atol=1e-14)
    # de Moivre: L^n = |L|^n (cos nf + e sin nf); integer powers are repeated products
    np.testing.assert_allclose(Q.power(q, 3), Q.multiply(q, Q.multiply(q, q)), rtol=1e-12)
    np.testing.assert_allclose(Q.power(q, 0.5), Q.exp(0.5 * Q.log(q)), rtol=1e-14)
    sq = Q.power(q, 0.5)
    np.testing.assert_allclose(Q.multiply(sq, sq), q, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(Q.norm(q), np.sqrt(np.sum(q * q, axis=1)), rtol=2e-14)


def test_exp_log_small_and_negative_real():
    tiny = np.array([0.0, 1e-12, -2e-12, 3e-12])
    np.testing.assert_allclose(Q.exp(tiny), [1.0, 1e-12, -2e-12, 3e-12], rtol=0, atol=1e-28)
    # log of -1: a valid logarithm with exp(log(-1)) = -1
    np.testing.assert_allclose(Q.exp(Q.log([-1.0, 0, 0, 0])), [-1.0, 0, 0, 0], atol=5e-15)


@settings(max_examples=200, deadline=None)
@given(quats.filter(lambda q: np.linalg.norm(q) > 1e-3), vecs)
def test_rotate_is_the_sandwich(q, v):
    vq = np.concatenate([[0.0], v])
    sandwich = spec_product(spec_product(q, vq), np.array([1, -1, -1, -1]) * q)
    np.testing.assert_allclose(Q.rotate(q, v), sandwich[1:], rtol=1e-12, atol=1e-9)
    # the action keeps the scalar part (SPEC S2)
    assert abs(sandwich[0]) <= 1e-9 * (1 + np.linalg.norm(q) ** 2 * np.linalg.norm(v))


def test_orthogonal_transform_commutes_with_product():
    """SPEC S1: (l0 + A l) o (m0 + A m) = n0 + A n for orthogonal A (det +1)."""
    rng = np.random.default_rng(5)
    a = poinsot.Rotation.random(rng=rng).as_matrix()
    p, q = rng.standard_normal(4), rng.standard_normal(4)
    n = Q.multiply(p, q)
    lhs = Q.multiply(np.r_[p[0], a @ p[1:]], np.r_[q[0], a @ q[1:]])
    np.testing.assert_allclose(lhs, np.r_[n[0], a @ n[1:]], atol=1e-14)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (
            lambda: Q.multiply([1, 0, 0], [1, 0, 0, 0]),
            r"Expected `p` to have shape \(\.\.\., 4\), got \(3,\)",
        ),
        (lambda: Q.multiply(np.ones((2, 4)), np.ones((3, 4))), "broadcast"),
        (lambda: Q.inverse([0, 0, 0, 0]), "non-zero"),
        (lambda: Q.log([0, 0, 0, 0]), "non-zero"),
        (lambda: Q.normalize([0, 0, 0, 0]), "non-zero"),
        (lambda: Q.rotate([1, 0, 0, 0], [1, 2]), r"`v` to have shape \(\.\.\., 3\)"),
        (lambda: Q.conjugate([np.nan, 0, 0, 0]), "finite"),
        (lambda: Q.multiply("abcd", [1, 0, 0, 0]), "string"),
    ],
)
def test_errors(call, match):
    exc = poinsot.InvalidTypeError if match == "string" else poinsot.InvalidInputError
    with pytest.raises(exc, match=match):
        call()
