"""The shared compiled helpers (``poinsot._numba_helpers``) against independent truths:
SciPy's rotations for the quaternion formulas, ``numpy.cross`` / ``@`` for the vector
ones, the torque models for the gravity kick."""

from __future__ import annotations

import platform

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

numba = pytest.importorskip("numba")

from poinsot import _numba_helpers as nh  # noqa: E402
from poinsot.dynamics import GravityTorque  # noqa: E402

RNG = np.random.default_rng(12)


@numba.njit
def _all(p, q, v, w9, t3, c, s, i, h):
    out = np.empty(4 * 4 + 3 * 6)
    out[0:4] = nh.qmul(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])
    out[4:8] = nh.qmul_gibbs(p[0], p[1], p[2], p[3], v[0], v[1], v[2])
    out[8:12] = nh.qnormalize(q[0], q[1], q[2], q[3])
    out[12:16] = nh.qaxis(p[0], p[1], p[2], p[3], c, s, i)
    out[16:19] = nh.qrot_inverse(q[0], q[1], q[2], q[3], v[0], v[1], v[2])
    out[19:22] = nh.cross(v[0], v[1], v[2], t3[0], t3[1], t3[2])
    out[22:25] = nh.matvec(
        w9[0], w9[1], w9[2], w9[3], w9[4], w9[5], w9[6], w9[7], w9[8], v[0], v[1], v[2]
    )
    out[25:28] = nh.euler_momentum_rate(v[0], v[1], v[2], t3[0], t3[1], t3[2], 1.0, 2.0, 3.0)
    out[28:31] = nh.gravity_kick(p[0], p[1], p[2], p[3], v[0], v[1], v[2], t3[0], t3[1], t3[2], h)
    return out


def _sci(q):
    return SciRotation.from_quat(q, scalar_first=True)


@pytest.mark.parametrize("i", [0, 1, 2])
def test_helpers_against_scipy_and_numpy(i):
    for _ in range(20):
        p, q = RNG.normal(size=4), RNG.normal(size=4)
        p /= np.linalg.norm(p)
        v, t3 = RNG.normal(size=3), RNG.normal(size=3)
        w9 = RNG.normal(size=9)
        f = RNG.uniform(-3, 3)
        h = 0.01
        out = _all(p, q, v, w9, t3, np.cos(f / 2), np.sin(f / 2), i, h)
        qn = q / np.linalg.norm(q)
        # P o Q composes rotations: apply Q first, then P
        prod = out[0:4] / np.linalg.norm(out[0:4])
        want = (_sci(p) * _sci(qn)).as_quat(scalar_first=True)
        assert min(np.abs(prod - want).max(), np.abs(prod + want).max()) < 1e-14
        np.testing.assert_allclose(np.linalg.norm(out[0:4]), np.linalg.norm(q), rtol=1e-14)
        gib = (_sci(p) * _sci(np.r_[1.0, v] / np.linalg.norm(np.r_[1.0, v]))).as_quat(
            scalar_first=True
        )
        got = out[4:8] / np.linalg.norm(out[4:8])
        assert min(np.abs(got - gib).max(), np.abs(got + gib).max()) < 1e-14
        np.testing.assert_allclose(out[8:12], qn, atol=1e-15)
        axis = np.eye(3)[i]
        turn = (_sci(p) * SciRotation.from_rotvec(f * axis)).as_quat(scalar_first=True)
        assert min(np.abs(out[12:16] - turn).max(), np.abs(out[12:16] + turn).max()) < 1e-14
        np.testing.assert_allclose(out[16:19], _sci(qn).apply(v, inverse=True), atol=1e-14)
        np.testing.assert_allclose(out[19:22], np.cross(v, t3), atol=1e-15)
        np.testing.assert_allclose(out[22:25], w9.reshape(3, 3) @ v, atol=1e-14)
        np.testing.assert_allclose(out[25:28], np.cross(v, t3) + [1.0, 2.0, 3.0], atol=1e-14)
        # the gravity kick is h times the torque of GravityTorque with m g c = t3
        kick = GravityTorque(1.0, t3, g=1.0).body_torque(0.0, p, np.zeros(3))
        np.testing.assert_allclose(out[28:31], v + h * kick, atol=1e-15)


@numba.njit
def _fma_vertical(a, b, c, q):
    out = np.empty((a.shape[0], 4))
    for k in range(a.shape[0]):
        out[k, 0] = nh.fma(a[k], b[k], c[k])
        out[k, 1:] = nh.vertical(q[k, 0], q[k, 1], q[k, 2], q[k, 3])
    return out


def test_fma_rounds_once_and_vertical_is_the_third_row():
    """``fma`` against exact rational arithmetic rounded once (``float(Fraction)``), on
    cases where ``a b + c`` rounds twice; ``vertical`` against SciPy's matrix row."""
    from fractions import Fraction

    n = 200
    a = 1.0 + RNG.uniform(-1, 1, n) * 2.0**-26
    b = 1.0 + RNG.uniform(-1, 1, n) * 2.0**-26
    c = -(a * b)  # the product's rounding error is all that is left
    c[: n // 2] = RNG.normal(size=n // 2) * 10.0 ** RNG.uniform(-5, 5, n // 2)
    q = RNG.normal(size=(n, 4)) * RNG.uniform(0.5, 2.0, (n, 1))
    out = _fma_vertical(a, b, c, q)
    abc = zip(a, b, c, strict=True)
    exact = [float(Fraction(x) * Fraction(y) + Fraction(z)) for x, y, z in abc]
    np.testing.assert_array_equal(out[:, 0], exact)
    assert np.any(out[n // 2 :, 0] != (a * b + c)[n // 2 :])  # two roundings differ
    n2 = np.sum(q * q, axis=1)
    row = _sci(q).as_matrix()[:, 2, :]  # R^T e_z = third row of R
    np.testing.assert_allclose(out[:, 1:] / n2[:, None], row, rtol=0, atol=1e-15)


@numba.njit
def _sum_prefetching(a, ahead):
    s = 0.0
    for i in range(a.size):
        nh.prefetch(a, i + ahead)  # far out of bounds on either side: never faults
        s += a[i]
    return s


def test_prefetch_emits_the_instruction_and_changes_no_value():
    """``prefetch`` compiles to x86's ``prefetcht0`` (the hint is really there), does not
    fault for indices far outside the array, and the loop's value is NumPy's."""
    a = RNG.normal(size=1000)
    expected = float(np.cumsum(a)[-1])  # summed in order, as the loop does
    for ahead in (0, 64, 10**9, -(10**9)):
        assert _sum_prefetching(a, ahead) == expected
    if platform.machine().lower() in ("x86_64", "amd64"):
        asm = _sum_prefetching.inspect_asm(_sum_prefetching.signatures[0])
        assert "prefetcht0" in asm


@numba.njit
def _stream(dst, src, neg):
    for i in range(src.shape[0]):
        nh.store_nt(dst, i, -src[i] if neg else src[i])
    nh.fence()


def test_streaming_stores_write_the_same_bits_and_stream_on_x86():
    """``store_nt`` writes a float's bits exactly (signed zeros, infinities, NaN
    payloads, float32 and int64 arrays); on x86 every store of the compiled loop is a
    streaming one (``movnti``: a float goes through its integer bits). Before, a float
    taken from a vector register was stored plainly on Intel (x86 has no streaming
    store for it there): mixed with streamed stores into the same lines, 10^6 inverses
    took 600 ns per rotation instead of 5."""
    bits = np.array([0, 1 << 63, 0x7FF0000000000000, 0x7FF8000000000123, 0x3FF0000000000001])
    for src in (bits.view(np.float64), RNG.normal(size=37), RNG.normal(size=5).astype(np.float32)):
        for neg in (False, True):
            dst = np.full_like(src, 7.0)
            _stream(dst, src, neg)
            want = -src if neg else src
            assert dst.tobytes() == want.tobytes()
    ints = np.arange(-3, 9, dtype=np.int64)
    dst_i = np.zeros_like(ints)
    _stream(dst_i, ints, False)
    assert dst_i.tolist() == ints.tolist()
    if platform.machine().lower() in ("x86_64", "amd64"):
        from llvmlite import binding

        for sig in _stream.signatures:
            if sig[0].dtype == numba.float32 and binding.llvm_version_info < (15,):
                # LLVM 14 (numba 0.60) folds a float32's bit cast back into a plain
                # vmovss store: the same bits, not streamed (float64 streams there too)
                continue
            asm = _stream.inspect_asm(sig)
            # stores: a mov whose destination (after the first comma) is in memory,
            # the stack excepted
            stores = [
                ln.split()[0]
                for ln in asm.splitlines()
                if ln.strip().startswith(("mov", "vmov"))
                and "(" in ln.split(",", 1)[-1]
                and "%rsp" not in ln.split(",", 1)[-1]
            ]
            assert any(op.startswith("movnti") for op in stores), (sig, stores)
            # no plain store of a float alongside the streamed ones
            assert not [op for op in stores if op in ("vmovsd", "vmovss", "movsd", "movss")], (
                sig,
                stores,
            )
