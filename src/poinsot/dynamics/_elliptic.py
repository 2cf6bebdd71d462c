"""Jacobi elliptic functions and elliptic integrals: compiled, vectorised kernels (private).

Shared by :class:`poinsot.dynamics.FreeRigidBody` and the Lagrange top (docs/theory.md
§10). Imported lazily (numba loads on first use), never by ``import poinsot``.

**Parameter convention.** Everything takes the *parameter* ``m = k^2`` exactly as
``scipy.special.ellipj`` / ``ellipk`` / ``ellipkinc`` and mpmath do (not the modulus
``k``), with ``m <= 1``. Every function also accepts the *complementary parameter*
``m1 = 1 - m`` by keyword: near ``m = 1`` (the separatrix of the free body) pass it
when it is known more accurately than ``1 - m`` can be rounded; it is then used
wherever ``1 - m`` appears (``m`` is only used where ``m`` itself appears). The
third kind uses the characteristic ``n`` with mpmath's / DLMF 19.2.7's sign,
``Pi(n; phi | m) = int_0^phi dt / ((1 - n sin^2 t) sqrt(1 - m sin^2 t))``.

**Algorithms.**

* Jacobi ``sn, cn, dn, am``: argument reduction by the quarter period to
  ``|r| <= K`` (``sn(r + 2K) = -sn r``, ``am(r + 2K) = am r + pi``), then the
  descending Landen (Gauss) transformation (DLMF 22.7.1-2, A&S 16.12) whose moduli
  ``k_{l+1} = (1 - k'_l) / (1 + k'_l)``, ``k'_{l+1} = 2 sqrt(k'_l) / (1 + k'_l)``
  are computed once per parameter from ``k = sqrt(m)`` and ``k' = sqrt(m1)``
  without cancellation (:func:`landen_fill`), until ``k_L < 1e-9`` where
  ``sn = sin`` to ``O(k_L^2) = 1e-18``; ``dn = sqrt(m1 + m cn^2)``. ``m1 = 0``:
  ``sn = tanh``, ``cn = dn = sech``, ``am = gd``.
* Complete integrals: ``K = pi / (2 AGM(1, k'))``;
  ``E = k'^2 (R_D(0, k'^2, 1) + R_D(0, 1, k'^2)) / 3`` (DLMF 19.25.1, all terms
  positive); ``Pi(n | m) = R_F(0, m1, 1) + n R_J(0, m1, 1, 1 - n) / 3``
  (DLMF 19.25.2), for ``n < 0`` after the transformation to ``N = (m - n) / (1 - n)``
  (A&S 17.7.15; terms of one sign).
* Incomplete integrals (``phi = j pi + r``, ``|r| <= pi/2``, ``s = sin r``,
  ``c = cos r``, ``D^2 = c^2 + m1 s^2`` written without cancellation):
  ``F = s R_F(c^2, D^2, 1) + 2 j K``;
  ``E = m1 s R_F(c^2, D^2, 1) + m m1 s^3 R_D(c^2, 1, D^2) / 3 + m s c / D + 2 j E``
  (DLMF 19.25.11 with ``c -> csc^2``, all terms of one sign);
  ``Pi = s R_F(c^2, D^2, 1) + n s^3 R_J(c^2, D^2, 1, c^2 + (1 - n) s^2) / 3
  + 2 j Pi(n | m)`` (DLMF 19.25.14).
* Carlson's symmetric integrals ``R_F, R_D, R_J, R_C`` by duplication with the
  stopping rules and series of Carlson (1995), Numer. Algorithms 10, 13-26
  (truncation error below ``eps``).

**Accuracy** (tests in ``tests/dynamics/test_elliptic.py``, against 40-digit mpmath
and scipy.special): ``sn, cn, dn`` to a few ``1e-16`` absolute for ``|u| <= K``
(and ``|u| eps`` beyond, the rounding of the argument), ``am`` likewise; ``K, E,
Pi`` and the incomplete integrals to a few ulp relative for ``0 <= m <= 1``,
including ``m1 = 1e-300 .. 1e-13`` when ``m1`` is passed, ``m < 0``, and
``n -> 1`` (``Pi`` grows like ``1 / sqrt(1 - n)``), ``n -> -inf`` for the complete
``Pi``. The incomplete ``Pi`` with ``n < 0`` loses about ``log10(1 + |n| sin^2 phi)``
digits to cancellation (fine for ``|n| <~ 100``).

**Limits.** ``m > 1`` is not supported (NaN). For ``n > 1`` the integral of the
third kind has a pole at ``sin^2 phi = 1 / n``: the Cauchy principal value is not
implemented and the result is NaN wherever ``1 - n sin^2 t`` changes sign on the
path (so ``Pi(n | m)`` is NaN for ``n > 1``, ``inf`` for ``n = 1``).

**Sharing compiled helpers.** The scalar kernels here (``@njit(cache=True)``) are
meant to be called from other compiled kernels. Numba's on-disk cache of a calling
kernel is keyed only on its *own* file, so a caller module declares this file with
``poinsot._numba_cache.depends_on(__file__, _elliptic)`` before its kernels (its
cached machine code is then rebuilt whenever this file changes).

>>> import numpy as np
>>> from poinsot.dynamics import _elliptic
>>> sn, cn, dn, am = _elliptic.ellipj(np.array([0.0, 0.5]), 0.3)
>>> bool(np.allclose(sn**2 + cn**2, 1.0) and np.allclose(dn**2 + 0.3 * sn**2, 1.0))
True
>>> round(float(_elliptic.ellipk(0.0)), 15) == round(np.pi / 2, 15)
True
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import first_call, going, njit, upto
from .._typing import ArrayLike, FloatArray

__all__ = [
    "LMAX",
    "landen_fill",
    "landen_table",
    "reduce_argument",
    "jacobi_reduced",
    "jacobi_point",
    "complete_k",
    "complete_e",
    "complete_pi",
    "incomplete_f",
    "incomplete_e",
    "incomplete_pi",
    "carlson_rf",
    "carlson_rd",
    "carlson_rj",
    "carlson_rc",
    "ellipj",
    "ellipk",
    "ellipe",
    "ellippi",
    "ellipkinc",
    "ellipeinc",
    "ellippiinc",
    "elliprf",
    "elliprd",
    "elliprj",
    "elliprc",
]

#: Length of the Landen tables (the descending sequence needs at most 8 levels
#: for ``m1 >= 1e-300``: ``k'`` goes 1e-150 -> 2e-75 -> ... -> 1 quadratically).
LMAX = 16

_EPS = 2.220446049250313e-16
_QRF = (3.0 * _EPS) ** (-1.0 / 6.0)  # Carlson (1995): R_F, R_J/R_D stopping rules
_QRD = (0.25 * _EPS) ** (-1.0 / 6.0)
_QRC = (3.0 * _EPS) ** (-1.0 / 8.0)
#: Steps of Carlson's duplication on JAX, which runs a fixed number of them (the
#: stopping rule is met within 20 steps for every argument of the elliptic integrals
#: here, ``z = 1``, ``x, y`` in ``[0, 1]`` down to ``1e-300``, ``p <= 1e4``; steps after
#: it leave the value unchanged to rounding). Compiled and plain runs stop by the
#: rule: ``fac = 4^-n`` reaches 0 (and the rule holds) by ``n = 538``, below ``_NOCAP``.
NDUP = 24
_NOCAP = 1100


# ---------------------------------------------------------------------------
# Carlson's symmetric integrals (scalar kernels)
# ---------------------------------------------------------------------------


@njit(cache=True)
def carlson_rc(x, y):  # pragma: no cover - compiled
    """``R_C(x, y) = R_F(x, y, y)`` for ``x >= 0``, ``y > 0`` (DLMF 19.2.17), by duplication."""
    if not (x >= 0.0 and y > 0.0):
        return math.nan
    a0 = (x + 2.0 * y) / 3.0
    q = _QRC * abs(a0 - x)
    am, xm, ym, fac = a0, x, y, 1.0
    for _ in range(upto(_NOCAP, NDUP)):
        if not going(fac * q > abs(am)):
            break
        lam = 2.0 * math.sqrt(xm) * math.sqrt(ym) + ym
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        fac *= 0.25
    s = (y - a0) * fac / am
    poly = 1.0 + s * s * (
        0.3 + s * (1.0 / 7.0 + s * (0.375 + s * (9.0 / 22.0 + s * (159.0 / 208.0 + s * 9.0 / 8.0))))
    )
    return poly / math.sqrt(am)


@njit(cache=True)
def carlson_rf(x, y, z):  # pragma: no cover - compiled
    """``R_F(x, y, z)`` (DLMF 19.16.1) for ``x, y, z >= 0``, at most one zero; by duplication."""
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0):
        return math.nan
    a0 = (x + y + z) / 3.0
    q = _QRF * max(abs(a0 - x), abs(a0 - y), abs(a0 - z))
    am, xm, ym, zm, fac = a0, x, y, z, 1.0
    for _ in range(upto(_NOCAP, NDUP)):
        if not going(fac * q > abs(am)):
            break
        sx, sy, sz = math.sqrt(xm), math.sqrt(ym), math.sqrt(zm)
        lam = sx * sy + sy * sz + sz * sx
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        zm = 0.25 * (zm + lam)
        fac *= 0.25
    if am == 0.0:
        return math.inf
    xx = (a0 - x) * fac / am
    yy = (a0 - y) * fac / am
    zz = -(xx + yy)
    e2 = xx * yy - zz * zz
    e3 = xx * yy * zz
    poly = 1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0
    return poly / math.sqrt(am)


@njit(cache=True)
def _rj_series(e2, e3, e4, e5):  # pragma: no cover - compiled
    """Carlson's (1995) fifth-order series of ``R_D`` and ``R_J`` in the elementary
    symmetric functions ``E_2 .. E_5`` of the scaled deviations."""
    return (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
    )


@njit(cache=True)
def carlson_rd(x, y, z):  # pragma: no cover - compiled
    """``R_D(x, y, z) = R_J(x, y, z, z)`` (DLMF 19.16.5) for ``x, y >= 0``, ``z > 0``."""
    if not (x >= 0.0 and y >= 0.0 and z > 0.0):
        return math.nan
    a0 = (x + y + 3.0 * z) / 5.0
    q = _QRD * max(abs(a0 - x), abs(a0 - y), abs(a0 - z))
    am, xm, ym, zm, fac, ssum = a0, x, y, z, 1.0, 0.0
    for _ in range(upto(_NOCAP, NDUP)):
        if not going(fac * q > abs(am)):
            break
        sx, sy, sz = math.sqrt(xm), math.sqrt(ym), math.sqrt(zm)
        lam = sx * sy + sy * sz + sz * sx
        ssum += fac / (sz * (zm + lam))
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        zm = 0.25 * (zm + lam)
        fac *= 0.25
    if am == 0.0:
        return math.inf
    xx = (a0 - x) * fac / am
    yy = (a0 - y) * fac / am
    zz = -(xx + yy) / 3.0
    xy = xx * yy
    z2 = zz * zz
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * zz
    e4 = 3.0 * (xy - z2) * z2
    e5 = xy * z2 * zz
    poly = _rj_series(e2, e3, e4, e5)
    return fac * poly / (am * math.sqrt(am)) + 3.0 * ssum


@njit(cache=True, inline="always")
def _rj_rc(ee, sp, pm, lam, d):  # pragma: no cover - compiled
    """``R_C(1, 1 + ee)`` of a duplication step of :func:`carlson_rj` (closed forms)."""
    if abs(ee) < 1e-4:
        return 1.0 - ee * (1.0 / 3.0 - ee * (0.2 - ee * (1.0 / 7.0 - ee / 9.0)))
    if ee > 0.0:
        se = math.sqrt(ee)
        return math.atan(se) / se
    # ee = prod(sp - s_i) / d, so 1 + ee = 2 sp (p + lam) / d (positive terms, no
    # cancellation when ee -> -1, i.e. p << x, y, z);
    # atanh(se) = log((1 + se)^2 / (1 + ee)) / 2.
    tt = 2.0 * sp * (pm + lam) / d
    se = math.sqrt(-ee)
    return 0.5 * math.log((1.0 + se) ** 2 / tt) / se


@njit(cache=True)
def carlson_rj(x, y, z, p):  # pragma: no cover - compiled
    """``R_J(x, y, z, p)`` (DLMF 19.16.2) for ``x, y, z >= 0`` (at most one zero), ``p > 0``.

    Duplication with the ``R_C(1, 1 + e)`` terms in closed form (``atan``/``atanh``,
    series for ``|e| < 1e-4``). ``p <= 0`` (principal value) is not implemented: NaN.
    """
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0 and p > 0.0):
        return math.nan
    a0 = (x + y + z + 2.0 * p) / 5.0
    delta = (p - x) * (p - y) * (p - z)
    q = _QRD * max(abs(a0 - x), abs(a0 - y), abs(a0 - z), abs(a0 - p))
    am, xm, ym, zm, pm, fac, ssum = a0, x, y, z, p, 1.0, 0.0
    for _ in range(upto(_NOCAP, NDUP)):
        if not going(fac * q > abs(am)):
            break
        sx, sy, sz, sp = math.sqrt(xm), math.sqrt(ym), math.sqrt(zm), math.sqrt(pm)
        lam = sx * sy + sy * sz + sz * sx
        d = (sp + sx) * (sp + sy) * (sp + sz)
        ee = delta * fac * fac * fac / (d * d)
        ssum += fac * _rj_rc(ee, sp, pm, lam, d) / d
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        zm = 0.25 * (zm + lam)
        pm = 0.25 * (pm + lam)
        fac *= 0.25
    if am == 0.0:
        return math.inf
    xx = (a0 - x) * fac / am
    yy = (a0 - y) * fac / am
    zz = (a0 - z) * fac / am
    pp = -0.5 * (xx + yy + zz)
    e2 = xx * yy + xx * zz + yy * zz - 3.0 * pp * pp
    e3 = xx * yy * zz + 2.0 * e2 * pp + 4.0 * pp * pp * pp
    e4 = (2.0 * xx * yy * zz + e2 * pp + 3.0 * pp * pp * pp) * pp
    e5 = xx * yy * zz * pp * pp
    poly = _rj_series(e2, e3, e4, e5)
    return fac * poly / (am * math.sqrt(am)) + 6.0 * ssum


# ---------------------------------------------------------------------------
# Jacobi elliptic functions (scalar kernels)
# ---------------------------------------------------------------------------


@njit(cache=True, inline="always")
def _landen_down(k, kp):  # pragma: no cover - compiled
    """One descending Landen step ``(k, k') -> (k_{l+1}, k'_{l+1})``."""
    # k_{l+1} = (1 - k') / (1 + k') = k^2 / (1 + k')^2 (the latter without cancellation)
    k1 = (1.0 - kp) / (1.0 + kp) if kp < 0.5 else (k / (1.0 + kp)) ** 2
    return k1, 2.0 * math.sqrt(kp) / (1.0 + kp)


@njit(cache=True)
def landen_fill(m, m1, ks, kps):  # pragma: no cover - compiled
    """Descending Landen moduli of parameter ``m`` (``m1 = 1 - m``) into ``ks``, ``kps``.

    Writes ``k_l`` and ``k'_l`` (``l = 0..L``) into the first ``L + 1`` entries of
    the arrays (length >= :data:`LMAX`) and returns ``(L, scale)`` with
    ``scale = prod_{l >= 1} 1 / (1 + k_l)``. ``L = -1`` flags ``m1 = 0`` (``k = 1``,
    hyperbolic functions), NaN inputs or ``m > 1`` (then ``scale`` is NaN).
    """
    if not (m1 > 0.0 and 0.0 <= m <= 1.0):
        return -1, (1.0 if m1 == 0.0 else math.nan)
    kp = math.sqrt(m1)
    k = math.sqrt(m)  # m >= 0 here (one path: the table is written on every one)
    ks[0] = k
    kps[0] = kp
    lv = 0
    scale = 1.0
    # a table loop (on JAX one rolled loop: poinsot._rolled), at most len(ks) - 1 levels
    for _ in range(upto(len(ks) - 1, len(ks) - 1)):
        if not going(k >= 1e-9):
            break
        k, kp = _landen_down(k, kp)
        lv += 1
        ks[lv] = k
        kps[lv] = kp
        scale /= 1.0 + k
    return lv, scale


def landen_table(m, m1):  # plain Python: for the array executors that trace it (poinsot.jax)
    """``(L, scale, ks, kps)`` of :func:`landen_fill` with the tables returned as tuples of
    length :data:`LMAX` (entries past ``L``: ``k = 0``, ``k' = 1``, identity steps)."""
    ks = [0.0] * LMAX
    kps = [1.0] * LMAX
    lv, scale = landen_fill(m, m1, ks, kps)
    return lv, scale, tuple(ks), tuple(kps)


@njit(cache=True)
def reduce_argument(u, kq):  # pragma: no cover - compiled
    """``(j, r)`` with ``u = 2 j K + r``, ``|r| <= K`` (``j`` a float integer; ``kq = K``)."""
    j = math.floor((u + kq) / (2.0 * kq))
    return j, u - 2.0 * kq * j


@njit(cache=True)
def jacobi_reduced(r, ks, kps, levels, scale, m, m1):  # pragma: no cover - compiled
    """``(sn, cn, dn)(r | m)`` for ``|r| <= K`` from the table of :func:`landen_fill`.

    ``levels = -1`` means ``m1 = 0``: ``(tanh r, sech r, sech r)``.
    """
    if levels < 0:
        if m1 == 0.0:
            e = math.exp(-abs(r))
            sech = 2.0 * e / (1.0 + e * e)
            return math.tanh(r), sech, sech
        return math.nan, math.nan, math.nan
    z = r * scale
    s = math.sin(z)
    c = math.cos(z)
    # levels .. 1 (on JAX all the table: its entries past `levels` are k = 0, k' = 1,
    # or k below 1e-9 still descending, steps that leave (s, c) unchanged to rounding)
    for lv in range(upto(levels, len(ks) - 1), 0, -1):
        s, c = _landen_up(s, c, ks[lv], kps[lv])
    return s, c, math.sqrt(m1 + m * c * c)


@njit(cache=True, inline="always")
def _landen_up(s, c, k1, kp1):  # pragma: no cover - compiled
    """One ascending Landen step of ``(sin, cos)`` with the level's ``k``, ``k'``."""
    ss = s * s
    den = 1.0 + k1 * ss
    # dn(z_l | k_l^2) = sqrt(1 - k_l^2 s^2) = sqrt(k'_l^2 + k_l^2 c^2): the form
    # without cancellation (and with the smaller rounding) on each side.
    if ss < 0.5:
        d = math.sqrt(1.0 - k1 * k1 * ss)
    else:
        d = math.sqrt(kp1 * kp1 + k1 * k1 * c * c)
    return (1.0 + k1) * s / den, c * d / den


@njit(cache=True)
def jacobi_point(u, kq, ks, kps, levels, scale, m, m1):  # pragma: no cover - compiled
    """``(sn, cn, dn, am)(u | m)`` for any real ``u``.

    ``kq = K(m)``; ``ks, kps, levels, scale`` from :func:`landen_fill`.
    """
    if levels < 0:
        sn, cn, dn = jacobi_reduced(u, ks, kps, levels, scale, m, m1)
        return sn, cn, dn, math.atan2(sn, cn)  # gd(u) for m = 1
    j, r = reduce_argument(u, kq)
    sn, cn, dn = jacobi_reduced(r, ks, kps, levels, scale, m, m1)
    am = math.atan2(sn, cn) + j * math.pi
    if j - 2.0 * math.floor(0.5 * j) != 0.0:
        sn, cn = -sn, -cn
    return sn, cn, dn, am


# ---------------------------------------------------------------------------
# Complete and incomplete integrals (scalar kernels)
# ---------------------------------------------------------------------------


@njit(cache=True)
def complete_k(m1):  # pragma: no cover - compiled
    """``K(m) = pi / (2 AGM(1, sqrt(m1)))`` from the complementary parameter ``m1 = 1 - m``."""
    if m1 == 0.0:
        return math.inf
    if not (m1 > 0.0):
        return math.nan
    a, b = 1.0, math.sqrt(m1)
    # 12 steps at most for m1 >= 1e-300 (quadratic convergence); 16 on JAX
    for _ in range(upto(64, 16)):
        if not going(abs(a - b) > 4.0 * _EPS * a):  # (a NaN stops: it stays NaN)
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (a + b)


@njit(cache=True)
def complete_e(m, m1):  # pragma: no cover - compiled
    """``E(m) = m1 (R_D(0, m1, 1) + R_D(0, 1, m1)) / 3`` (DLMF 19.25.1; ``E(1) = 1``)."""
    if m1 == 0.0:
        return 1.0
    if m <= 0.0:  # R_F - m R_D / 3 with both terms positive
        return carlson_rf(0.0, m1, 1.0) - m * carlson_rd(0.0, m1, 1.0) / 3.0
    return m1 * (carlson_rd(0.0, m1, 1.0) + carlson_rd(0.0, 1.0, m1)) / 3.0


@njit(cache=True)
def complete_pi(n, m, m1):  # pragma: no cover - compiled
    """``Pi(n | m) = R_F(0, m1, 1) + n R_J(0, m1, 1, 1 - n) / 3`` (DLMF 19.25.2), ``n < 1``."""
    if n == 1.0 or m1 == 0.0:
        return math.inf
    if n > 1.0:
        return math.nan
    if n == 0.0:
        return complete_k(m1)
    if m == 0.0:
        return 0.5 * math.pi / math.sqrt(1.0 - n)
    if n < 0.0:
        # A&S 17.7.15 / DLMF 19.7.9 to N = (m - n) / (1 - n) in (m, 1): both terms
        # positive (the direct form cancels for n -> -inf); 1 - N = m1 / (1 - n).
        nn = (m - n) / (1.0 - n)
        pn = m1 / (1.0 - n)
        pi_n = carlson_rf(0.0, m1, 1.0) + nn * carlson_rj(0.0, m1, 1.0, pn) / 3.0
        return m / (m - n) * complete_k(m1) - n * m1 / ((1.0 - n) * (m - n)) * pi_n
    return carlson_rf(0.0, m1, 1.0) + n * carlson_rj(0.0, m1, 1.0, 1.0 - n) / 3.0


_PI1 = 3.141592653589793  # pi = _PI1 + _PI2 (Cody-Waite)
_PI2 = 1.2246467991473532e-16


@njit(cache=True)
def _reduce_phi(phi):  # pragma: no cover - compiled
    """``(j, s, c)``: ``phi = j pi + r``, ``|r| <= pi/2``, ``s = sin r``, ``c = cos r >= 0``.

    ``r`` is formed with ``pi`` in two parts, and near ``|r| = pi/2`` the distance
    ``d = pi/2 - |r|`` is formed exactly (Sterbenz) before ``c = sin d``: ``c`` keeps
    its relative accuracy where the integrands ``1 / sqrt(c^2 + m1 s^2)`` are largest.
    """
    j = math.floor(phi / _PI1 + 0.5)
    a = phi - j * _PI1
    r = a - j * _PI2
    if abs(r) <= 0.78:
        return j, math.sin(r), math.cos(r)
    sg = math.copysign(1.0, r)
    d = (sg * 0.5 * _PI1 - a) + (sg * 0.5 * _PI2 + j * _PI2)  # sg pi/2 - r, r = sg pi/2 - d
    if sg * d < 0.0:  # |r| > pi/2 by rounding: r - sg pi = -sg pi/2 - d, same d
        j += sg
        sg = -sg
    return j, sg * math.cos(d), sg * math.sin(d)


@njit(cache=True)
def incomplete_f(phi, m, m1):  # pragma: no cover - compiled
    """``F(phi | m) = s R_F(c^2, c^2 + m1 s^2, 1) + 2 j K`` (DLMF 19.25.5)."""
    j, s, c = _reduce_phi(phi)
    c2 = c * c
    d2 = c2 + m1 * s * s
    f = s * carlson_rf(c2, d2, 1.0) if s != 0.0 else 0.0
    if j != 0.0:
        f += 2.0 * j * complete_k(m1)
    return f


@njit(cache=True)
def incomplete_e(phi, m, m1):  # pragma: no cover - compiled
    """``E(phi | m)`` by DLMF 19.25.11 (terms of one sign for ``0 <= m <= 1``), ``+ 2 j E``."""
    j, s, c = _reduce_phi(phi)
    c2 = c * c
    if m1 == 0.0:
        e = s
    elif m < 0.0:  # 19.25.9, both terms positive
        d2 = c2 + m1 * s * s
        e = s * carlson_rf(c2, d2, 1.0) - m * s * s * s * carlson_rd(c2, d2, 1.0) / 3.0
    else:
        d2 = c2 + m1 * s * s
        e = m1 * s * carlson_rf(c2, d2, 1.0)
        e += m * m1 * s * s * s * carlson_rd(c2, 1.0, d2) / 3.0
        e += m * s * c / math.sqrt(d2)
    if j != 0.0:
        e += 2.0 * j * complete_e(m, m1)
    return e


@njit(cache=True)
def incomplete_pi(n, phi, m, m1):  # pragma: no cover - compiled
    """``Pi(n; phi | m) = s R_F + n s^3 R_J(c^2, D^2, 1, c^2 + (1 - n) s^2) / 3 + 2 j Pi(n|m)``."""
    j, s, c = _reduce_phi(phi)
    c2 = c * c
    s2 = s * s
    d2 = c2 + m1 * s2
    p = c2 + (1.0 - n) * s2
    if s == 0.0:
        v = 0.0
    else:
        v = s * carlson_rf(c2, d2, 1.0) + n * s * s2 * carlson_rj(c2, d2, 1.0, p) / 3.0
    if j != 0.0:
        v += 2.0 * j * complete_pi(n, m, m1)
    return v


# ---------------------------------------------------------------------------
# Vectorised wrappers (NumPy broadcasting; loops over flat arrays)
# ---------------------------------------------------------------------------


@njit(cache=True)
def _ellipj_loop(u, m, m1, sn, cn, dn, am):  # pragma: no cover - compiled
    ks = np.empty(LMAX)
    kps = np.empty(LMAX)
    mprev, m1prev = math.nan, math.nan
    lv, scale, kq = -1, math.nan, math.nan
    for p in range(u.shape[0]):
        if not (m[p] == mprev and m1[p] == m1prev):  # rebuild the table when m changes
            mprev, m1prev = m[p], m1[p]
            lv, scale = landen_fill(mprev, m1prev, ks, kps)
            kq = complete_k(m1prev)
        sn[p], cn[p], dn[p], am[p] = jacobi_point(u[p], kq, ks, kps, lv, scale, mprev, m1prev)


@njit(cache=True)
def _complete_loop(kind, n, m, m1, out):  # pragma: no cover - compiled
    for p in range(out.shape[0]):
        if not (m[p] <= 1.0 and m1[p] >= 0.0):
            out[p] = math.nan
        elif kind == 0:
            out[p] = complete_k(m1[p])
        elif kind == 1:
            out[p] = complete_e(m[p], m1[p])
        else:
            out[p] = complete_pi(n[p], m[p], m1[p])


@njit(cache=True)
def _incomplete_loop(kind, n, phi, m, m1, out):  # pragma: no cover - compiled
    for p in range(out.shape[0]):
        if not (m[p] <= 1.0 and m1[p] >= 0.0):
            out[p] = math.nan
        elif kind == 0:
            out[p] = incomplete_f(phi[p], m[p], m1[p])
        elif kind == 1:
            out[p] = incomplete_e(phi[p], m[p], m1[p])
        else:
            out[p] = incomplete_pi(n[p], phi[p], m[p], m1[p])


@njit(cache=True)
def _carlson_loop(kind, x, y, z, p, out):  # pragma: no cover - compiled
    for i in range(out.shape[0]):
        if kind == 0:
            out[i] = carlson_rf(x[i], y[i], z[i])
        elif kind == 1:
            out[i] = carlson_rd(x[i], y[i], z[i])
        elif kind == 2:
            out[i] = carlson_rj(x[i], y[i], z[i], p[i])
        else:
            out[i] = carlson_rc(x[i], y[i])


def _flat(*arrays: ArrayLike) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """Broadcast float arrays; return the shape and contiguous flat copies."""
    b = np.broadcast_arrays(*[np.asarray(a, dtype=np.float64) for a in arrays])
    shape = b[0].shape
    return shape, [np.ascontiguousarray(x).reshape(-1) for x in b]


def _m_m1(m, m1):
    m = np.asarray(m, dtype=np.float64)
    return m, (1.0 - m) if m1 is None else np.asarray(m1, dtype=np.float64)


def _out(shape, *arrays):
    res = tuple(a.reshape(shape) for a in arrays)
    if shape == ():
        res = tuple(np.float64(a[()]) for a in res)
    return res if len(res) > 1 else res[0]


def ellipj(
    u: ArrayLike, m: ArrayLike, *, m1: ArrayLike | None = None
) -> tuple[
    FloatArray | np.float64,
    FloatArray | np.float64,
    FloatArray | np.float64,
    FloatArray | np.float64,
]:
    """Jacobi elliptic functions ``sn, cn, dn`` and the amplitude ``am`` of ``u`` and ``m``.

    Same convention and outputs as ``scipy.special.ellipj(u, m)`` (parameter
    ``m = k^2 <= 1``; ``am`` continuous, ``am(u + 2K) = am(u) + pi``); ``m1 = 1 - m``
    may be given for accuracy near ``m = 1`` (module notes). Broadcasts.

    >>> import numpy as np
    >>> from poinsot.dynamics._elliptic import ellipj
    >>> [round(float(x), 12) for x in ellipj(1.0, 1.0)]   # m = 1: tanh, sech, sech, gd
    [0.761594155956, 0.648054273664, 0.648054273664, 0.865769483239]
    """
    m, m1 = _m_m1(m, m1)
    shape, (u, m, m1) = _flat(u, m, m1)
    sn, cn, dn, am = (np.empty(u.shape[0]) for _ in range(4))
    first_call(_ellipj_loop, u.shape[0] * 1e-4)(u, m, m1, sn, cn, dn, am)
    return _out(shape, sn, cn, dn, am)


def _complete(kind, n, m, m1):
    m, m1 = _m_m1(m, m1)
    shape, (n, m, m1) = _flat(n, m, m1)
    out = np.empty(m.shape[0])
    first_call(_complete_loop, m.shape[0] * 1e-4)(kind, n, m, m1, out)
    return _out(shape, out)


def ellipk(m: ArrayLike, *, m1: ArrayLike | None = None) -> FloatArray | np.float64:
    """Complete integral of the first kind ``K(m)``, as ``scipy.special.ellipk``.

    >>> from poinsot.dynamics._elliptic import ellipk
    >>> round(float(ellipk(0.5)), 14)
    1.85407467730137
    """
    return _complete(0, 0.0, m, m1)


def ellipe(m: ArrayLike, *, m1: ArrayLike | None = None) -> FloatArray | np.float64:
    """Complete integral of the second kind ``E(m)``, as ``scipy.special.ellipe``.

    >>> from poinsot.dynamics._elliptic import ellipe
    >>> round(float(ellipe(0.5)), 14)
    1.35064388104768
    """
    return _complete(1, 0.0, m, m1)


def ellippi(n: ArrayLike, m: ArrayLike, *, m1: ArrayLike | None = None) -> FloatArray | np.float64:
    """Complete integral of the third kind ``Pi(n | m)`` (mpmath ``ellippi(n, m)``), ``n < 1``.

    >>> from poinsot.dynamics._elliptic import ellippi
    >>> round(float(ellippi(0.0, 0.5)), 14), round(float(ellippi(-1.0, 0.0)), 14)
    (1.85407467730137, 1.11072073453959)
    """
    return _complete(2, n, m, m1)


def _incomplete(kind, n, phi, m, m1):
    m, m1 = _m_m1(m, m1)
    shape, (n, phi, m, m1) = _flat(n, phi, m, m1)
    out = np.empty(m.shape[0])
    first_call(_incomplete_loop, out.shape[0] * 1e-4)(kind, n, phi, m, m1, out)
    return _out(shape, out)


def ellipkinc(
    phi: ArrayLike, m: ArrayLike, *, m1: ArrayLike | None = None
) -> FloatArray | np.float64:
    """Incomplete integral of the first kind ``F(phi | m)``, as ``scipy.special.ellipkinc``.

    >>> from poinsot.dynamics._elliptic import ellipkinc
    >>> round(float(ellipkinc(1.0, 0.5)), 14)
    1.08321677284517
    """
    return _incomplete(0, 0.0, phi, m, m1)


def ellipeinc(
    phi: ArrayLike, m: ArrayLike, *, m1: ArrayLike | None = None
) -> FloatArray | np.float64:
    """Incomplete integral of the second kind ``E(phi | m)``, as ``scipy.special.ellipeinc``.

    >>> from poinsot.dynamics._elliptic import ellipeinc
    >>> round(float(ellipeinc(1.0, 0.5)), 14)
    0.92732988362444
    """
    return _incomplete(1, 0.0, phi, m, m1)


def ellippiinc(
    n: ArrayLike, phi: ArrayLike, m: ArrayLike, *, m1: ArrayLike | None = None
) -> FloatArray | np.float64:
    """Incomplete integral of the third kind ``Pi(n; phi | m)`` (mpmath ``ellippi(n, phi, m)``).

    >>> from poinsot.dynamics._elliptic import ellippiinc
    >>> round(float(ellippiinc(0.3, 1.0, 0.5)), 14)
    1.19232543693456
    """
    return _incomplete(2, n, phi, m, m1)


def _carlson(kind, x, y, z, p):
    shape, (x, y, z, p) = _flat(x, y, z, p)
    out = np.empty(x.shape[0])
    first_call(_carlson_loop, out.shape[0] * 1e-4)(kind, x, y, z, p, out)
    return _out(shape, out)


def elliprf(x: ArrayLike, y: ArrayLike, z: ArrayLike) -> FloatArray | np.float64:
    """Carlson's ``R_F(x, y, z)``, as ``scipy.special.elliprf`` (real arguments)."""
    return _carlson(0, x, y, z, 0.0)


def elliprd(x: ArrayLike, y: ArrayLike, z: ArrayLike) -> FloatArray | np.float64:
    """Carlson's ``R_D(x, y, z)``, as ``scipy.special.elliprd`` (real arguments)."""
    return _carlson(1, x, y, z, 0.0)


def elliprj(x: ArrayLike, y: ArrayLike, z: ArrayLike, p: ArrayLike) -> FloatArray | np.float64:
    """Carlson's ``R_J(x, y, z, p)``, as ``scipy.special.elliprj`` (real, ``p > 0``)."""
    return _carlson(2, x, y, z, p)


def elliprc(x: ArrayLike, y: ArrayLike) -> FloatArray | np.float64:
    """Carlson's ``R_C(x, y)``, as ``scipy.special.elliprc`` (real, ``y > 0``)."""
    return _carlson(3, x, y, 1.0, 0.0)
