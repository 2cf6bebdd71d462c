"""Tests of the shared elliptic kernels ``poinsot.dynamics._elliptic``.

Oracles: mpmath at 40 digits (``ellipfun``, ``ellipk``, ``ellipe``, ``ellipf``,
``ellippi``, Carlson ``elliprf/rd/rj/rc``) evaluated on the same double inputs,
and ``scipy.special`` where its inputs are exact (``m`` not near 1).
Tolerances: observed errors are a few 1e-16 (relative for integrals, absolute
for the bounded Jacobi functions); tolerances are >= 10x above the worst observed
(also with ``NUMBA_CPU_NAME=generic``), and the 40-digit references are ~1e-40
accurate (scipy's ``ellipj`` is not: it is only compared at 100x its own error).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from poinsot.dynamics import _elliptic as E

mp = pytest.importorskip("mpmath")
mp.mp.dps = 40

M1_NEAR_1 = [1e-3, 1e-6, 1e-9, 1e-13, 1e-16, 1e-30, 1e-300]


def _rel(a, b):
    return abs(a - b) / abs(b)


def _mp_m(m1):
    """The exact parameter 1 - m1 (enough digits that 1 - 1e-300 is not 1)."""
    return 1 - mp.mpf(m1)


def _dps(m1):
    return max(40, int(-math.log10(m1)) + 40) if m1 > 0 else 40


# ---------------------------------------------------------------------------
# Jacobi functions
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("m1", [1.0, 0.999999, 0.7, 0.3, *M1_NEAR_1])
def test_ellipj_against_mpmath(m1):
    """sn, cn, dn, am on [-3K, 3K] from the exact parameter 1 - m1 (m1 passed
    directly): absolute error < 4e-15 * max(1, |u|) (observed <= 1.7 ulp = 4e-16
    on [-K, K]; beyond, the rounding of u itself, |u| eps)."""
    m = 1.0 - m1
    mp.mp.dps = _dps(m1)
    mm = _mp_m(m1)
    kq = float(mp.ellipk(mm))
    u = np.concatenate([np.linspace(-3 * kq, 3 * kq, 13), [0.123, kq - 1e-9, -kq + 1e-3]])
    sn, cn, dn, am = E.ellipj(u, m, m1=m1)
    for k, uk in enumerate(u):
        uu = mp.mpf(float(uk))
        ref = [mp.ellipfun(f, uu, m=mm) for f in ("sn", "cn", "dn")]
        ref.append(mp.asin(ref[0]) if abs(uk) <= kq else None)
        tol = 4e-15 * max(1.0, abs(uk))
        assert abs(sn[k] - float(ref[0])) < tol
        assert abs(cn[k] - float(ref[1])) < tol
        assert abs(dn[k] - float(ref[2])) < tol
        if ref[3] is not None:
            assert abs(am[k] - float(ref[3])) < tol
    mp.mp.dps = 40


def test_ellipj_matches_scipy_and_am_is_continuous():
    """Same outputs as scipy.special.ellipj (m exact): 2e-12 absolute over |u| <= 20,
    100x scipy's own error there (2e-14, e.g. dn(17.84 | 0.1), where ours is 1e-16 from
    mpmath); am(u + 2K) = am(u) + pi."""
    u = np.linspace(-20.0, 20.0, 2001)
    for m in (0.0, 1e-20, 0.1, 0.5, 0.9):
        ours = np.array(E.ellipj(u, m))
        ref = np.array(special.ellipj(u, m))
        np.testing.assert_allclose(ours, ref, rtol=0, atol=2e-12)
    kq = float(special.ellipk(0.6))
    a = E.ellipj(np.array([0.3, 0.3 + 2 * kq, 0.3 - 4 * kq]), 0.6)[3]
    np.testing.assert_allclose(a - a[0], [0.0, math.pi, -2 * math.pi], atol=1e-14)


def test_ellipj_limits_and_broadcast():
    """m = 0: sin, cos, 1, u; m = 1: tanh, sech, sech, gd; m > 1 or NaN: NaN; shapes broadcast."""
    u = np.linspace(-5, 5, 11)
    sn, cn, dn, am = E.ellipj(u, 0.0)
    np.testing.assert_allclose(sn, np.sin(u), atol=1e-15)
    np.testing.assert_allclose(cn, np.cos(u), atol=1e-15)
    np.testing.assert_allclose(dn, 1.0, atol=0)
    np.testing.assert_allclose(am, u, atol=4e-15)
    sn, cn, dn, am = E.ellipj(u, 1.0)
    # NumPy's tanh/cosh/arctan are good to ~1e-16: tolerance 1e-14 (ours <= 2.2e-16)
    np.testing.assert_allclose(sn, np.tanh(u), rtol=1e-14)
    np.testing.assert_allclose(cn, 1 / np.cosh(u), rtol=1e-14)
    np.testing.assert_allclose(am, 2 * np.arctan(np.tanh(u / 2)), rtol=1e-14)
    assert np.all(np.isnan(E.ellipj(u, 1.5)))
    assert np.all(np.isnan(E.ellipj(u, np.nan)))
    out = E.ellipj(np.zeros((2, 1)), np.array([0.1, 0.2, 0.3]))
    assert all(x.shape == (2, 3) for x in out)
    assert isinstance(E.ellipj(0.5, 0.5)[0], np.float64)


# ---------------------------------------------------------------------------
# Complete integrals
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("m1", [1.5, 1.0, 0.75, 0.5, 0.1, *M1_NEAR_1])
def test_complete_k_e_against_mpmath(m1):
    """K(m), E(m) from m1 to 4e-15 relative (observed <= 4e-16), also m < 0."""
    m = 1.0 - m1
    with mp.workdps(_dps(m1)):
        mm = _mp_m(m1)
        assert _rel(E.ellipk(m, m1=m1), float(mp.ellipk(mm))) < 4e-15
        assert _rel(E.ellipe(m, m1=m1), float(mp.ellipe(mm))) < 4e-15


def test_complete_against_scipy_and_limits():
    m = np.linspace(-3.0, 1.0, 41)[:-1]
    assert abs(E.ellipj(17.84, 0.1)[2] - float(mp.ellipfun("dn", 17.84, m=0.1))) < 2e-16
    np.testing.assert_allclose(E.ellipk(m), special.ellipk(m), rtol=1e-14)  # observed 4.4e-16
    np.testing.assert_allclose(E.ellipe(m), special.ellipe(m), rtol=1e-14)
    assert E.ellipk(1.0) == math.inf and E.ellipe(1.0) == 1.0
    assert math.isnan(E.ellipk(1.2)) and math.isnan(E.ellippi(1.5, 0.3))
    assert E.ellippi(1.0, 0.3) == math.inf


@pytest.mark.parametrize("m1", [1.0, 0.6, 1e-3, 1e-9, 1e-13])
@pytest.mark.parametrize(
    "n", [-1e12, -30.0, -1.0, -1e-9, 0.0, 1e-9, 0.25, 0.7, 1 - 1e-6, 1 - 1e-12, 1 - 2**-52]
)
def test_complete_pi_against_mpmath(n, m1):
    """Pi(n | m) to 5e-15 relative (observed <= 4.5e-16), n near 1 (pole), n -> -inf, n = m."""
    m = 1.0 - m1
    ref = mp.ellippi(mp.mpf(n), 1 - mp.mpf(m1))
    assert _rel(E.ellippi(n, m, m1=m1), float(ref)) < 5e-15
    # n = m: Pi(m | m) = E(m) / (1 - m) (DLMF 19.6.1), with m and 1 - m both exact doubles
    if m >= 0.5:
        e_ref = mp.ellipe(mp.mpf(m)) / (1 - mp.mpf(m))
        assert _rel(E.ellippi(m, m, m1=1.0 - m), float(e_ref)) < 5e-15


# ---------------------------------------------------------------------------
# Incomplete integrals
# ---------------------------------------------------------------------------

PHI = [1e-8, 0.3, 1.0, math.pi / 2 - 1e-7, math.pi / 2, 2.0, 3.0, -2.5, 7.9, -12.0]


@pytest.mark.parametrize("m1", [1.7, 1.0, 0.8, 0.2, *M1_NEAR_1[:5]])
def test_incomplete_f_e_against_mpmath(m1):
    """F(phi | m), E(phi | m) for phi over several half periods: 5e-15 relative
    (observed <= 4.5e-16 relative to max(|value|, |phi|))."""
    m = 1.0 - m1
    mm = 1 - mp.mpf(m1)
    for phi in PHI:
        pp = mp.mpf(phi)
        f_ref, e_ref = float(mp.ellipf(pp, mm)), float(mp.ellipe(pp, mm))
        scale = max(abs(phi), 1.0)
        assert abs(E.ellipkinc(phi, m, m1=m1) - f_ref) < 5e-15 * max(abs(f_ref), scale)
        assert abs(E.ellipeinc(phi, m, m1=m1) - e_ref) < 5e-15 * max(abs(e_ref), scale)


def test_incomplete_against_scipy():
    phi = np.linspace(-10.0, 10.0, 201)
    for m in (-2.0, 0.0, 0.3, 0.9, 0.999):
        np.testing.assert_allclose(E.ellipkinc(phi, m), special.ellipkinc(phi, m), rtol=1e-14)
        np.testing.assert_allclose(
            E.ellipeinc(phi, m), special.ellipeinc(phi, m), rtol=1e-14, atol=3e-15
        )
    assert E.ellipkinc(math.pi / 2, 1.0) == math.inf or E.ellipkinc(math.pi / 2, 1.0) > 30
    assert E.ellipeinc(1.0, 1.0) == pytest.approx(math.sin(1.0), rel=1e-15)


@pytest.mark.parametrize("m1", [1.0, 0.5, 1e-4, 1e-13])
@pytest.mark.parametrize("n", [-50.0, -0.5, 0.0, 0.5, 0.9, 1 - 1e-10])
def test_incomplete_pi_against_mpmath(n, m1):
    """Pi(n; phi | m) over several half periods: 1e-14 relative (observed <= 1e-15),
    times 1 + |n| for n < 0 (documented cancellation; observed 2e-14 at n = -50)."""
    m = 1.0 - m1
    mm = 1 - mp.mpf(m1)
    for phi in PHI:
        ref = float(mp.ellippi(mp.mpf(n), mp.mpf(phi), mm))
        val = E.ellippiinc(n, phi, m, m1=m1)
        tol = 1e-14 * max(abs(ref), abs(phi), 1.0) * (1.0 + max(-n, 0.0))
        assert abs(val - ref) < tol, (phi, val, ref)


def test_incomplete_pi_beyond_pole_is_nan():
    """n > 1: the principal value is not implemented: NaN past sin^2 phi = 1/n."""
    assert math.isnan(E.ellippiinc(4.0, 1.0, 0.5))
    ref = float(mp.ellippi(4, 0.4, 0.5))
    assert _rel(E.ellippiinc(4.0, 0.4, 0.5), ref) < 1e-14


# ---------------------------------------------------------------------------
# Carlson
# ---------------------------------------------------------------------------


def test_carlson_against_scipy():
    rng = np.random.default_rng(3)
    x, y, z, p = (10.0 ** rng.uniform(-8, 3, 500) for _ in range(4))
    x[:50] = 0.0
    # observed <= 6.7e-16 (R_F, R_D), 4.4e-16 (R_C), 2.2e-15 (R_J)
    np.testing.assert_allclose(E.elliprf(x, y, z), special.elliprf(x, y, z), rtol=7e-15)
    np.testing.assert_allclose(E.elliprd(x, y, z), special.elliprd(x, y, z), rtol=7e-15)
    # R_J against mpmath (scipy's own error reaches 8e-15 here; ours 4e-15, notably
    # for p << x, y, z where the R_C terms approach their logarithmic limit)
    ref = np.array(
        [float(mp.elliprj(*v)) for v in zip(x[::3], y[::3], z[::3], p[::3], strict=True)]
    )
    np.testing.assert_allclose(E.elliprj(x[::3], y[::3], z[::3], p[::3]), ref, rtol=5e-14)
    np.testing.assert_allclose(E.elliprc(x, y), special.elliprc(x, y), rtol=5e-15)
    assert math.isnan(E.elliprj(1.0, 2.0, 3.0, -1.0)) and math.isnan(E.elliprf(-1.0, 1, 1))
