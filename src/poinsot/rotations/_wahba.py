"""QUEST and ESOQ2 on one observation set, written once (docs/conventions.md, "Writing a
formula"): compiled by numba for :func:`poinsot.rotations.determine_attitude` (a
parallel loop over the batch, :mod:`poinsot.rotations._wahba_kernels`) and run by the
NumPy executor (``POINSOT_NUMBA=0``) on whole columns of the batch
(:func:`poinsot._jit.lanes`): the same operations either way.

:func:`solve` takes one set's observations ``ob`` and references ``rf`` (``(n, 3)``,
any non-zero length) and weights ``w`` (``(n,)``), validates them (finite, non-zero,
not all parallel: the status bits below) and returns the quaternion ``L`` of ``C_nb``
(``l0 >= 0``), Wahba's loss and, when asked, the six entries of the QUEST covariance
``(sum_i w_i (E - b_i b_i^T))^-1``. Convention and formulas: the docstring of
:func:`~poinsot.rotations.determine_attitude`, docs/theory.md §2.4.

Two forms of :func:`solve`, from the same helpers and with the same operations, so
the same results bit for bit: :func:`solve_slow` (the checks and Newton's loop with
their branches; what :func:`solve` runs) and :func:`solve_fast` (no branch on the
data: selects, a fixed number of Newton steps, QUEST's four frames all formed), which
the compiled loops run on blocks of sets at once (vectorised by LLVM across the sets),
running :func:`solve_slow` on the sets it flags (a status bit, or Newton not stopped).
"""

from __future__ import annotations

import math
from typing import Any

from .._jit import going, pick
from ._scalar import hamilton, to_matrix
from ._wahba_codes import (  # noqa: F401 - read as W.<NAME> by the callers
    ESOQ2,
    NEWTON_FAST,
    NEWTON_MAX,
    NEWTON_TOL,
    NONFINITE_OBSERVED,
    NONFINITE_REFERENCE,
    PARALLEL_OBSERVED,
    PARALLEL_REFERENCE,
    PARALLEL_RTOL,
    QUEST,
    QUEST_ROTATION_THRESHOLD,
    UNIT_DOWN,
    UNIT_MAX,
    UNIT_MIN,
    UNIT_UP,
    ZERO_OBSERVED,
    ZERO_REFERENCE,
)


def finite3(x: float, y: float, z: float) -> bool:
    """Whether ``x, y, z`` are all finite (``v - v`` is NaN for NaN and inf)."""
    return (x - x) + (y - y) + (z - z) == 0.0


def unit(x: float, y: float, z: float) -> tuple[float, float, float]:
    """``v / |v|`` for a non-zero finite ``v``, scaled first by a power of two (exact)
    where ``|v|^2`` would overflow or lose digits (1e200, 1e-200). No branch and no
    division for the scale: the loss's second pass over the observations repeats
    these same operations, which the compiler then shares with the first."""
    n2 = x * x + y * y + z * z
    t = pick(n2 < UNIT_MIN, UNIT_UP, pick(n2 > UNIT_MAX, UNIT_DOWN, 1.0))
    x, y, z = x * t, y * t, z * t
    n = 1.0 / math.sqrt(x * x + y * y + z * z)
    return x * n, y * n, z * n


def sym_det(m00: float, m01: float, m02: float, m11: float, m12: float, m22: float) -> float:
    """``det`` of the symmetric ``[[m00, m01, m02], [m01, m11, m12], [m02, m12, m22]]``."""
    return (
        m00 * (m11 * m22 - m12 * m12)
        - m01 * (m01 * m22 - m12 * m02)
        + m02 * (m01 * m12 - m11 * m02)
    )


def k_parts(
    b00: float, b01: float, b02: float, b10: float, b11: float, b12: float,
    b20: float, b21: float, b22: float,
) -> tuple[float, ...]:  # fmt: skip
    """``S = B + B^T`` (``s00, s01, s02, s11, s12, s22``), ``sigma = tr B`` and
    ``z = (B12 - B21, B20 - B02, B01 - B10)``: Davenport's
    ``K = [[sigma, z^T], [z, S - sigma E]]``."""
    return (
        2.0 * b00, b01 + b10, b02 + b20, 2.0 * b11, b12 + b21, 2.0 * b22,
        b00 + b11 + b22, b12 - b21, b20 - b02, b01 - b10,
    )  # fmt: skip


def sym_mv(
    s00: float, s01: float, s02: float, s11: float, s12: float, s22: float,
    x: float, y: float, z: float,
) -> tuple[float, float, float]:  # fmt: skip
    """``S v`` for the symmetric ``S``."""
    return (
        s00 * x + s01 * y + s02 * z,
        s01 * x + s11 * y + s12 * z,
        s02 * x + s12 * y + s22 * z,
    )


def lambda_coeffs(
    s00: float, s01: float, s02: float, s11: float, s12: float, s22: float,
    sigma: float, z0: float, z1: float, z2: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """``a, b, c, d`` of ``K``'s characteristic polynomial
    ``f(l) = (l^2 - a)(l^2 - b) - c l + c sigma - d``: ``a = sigma^2 - kappa``,
    ``b = sigma^2 + z.z``, ``c = Delta + z.S z``, ``d = z.S^2 z``, ``kappa = tr adj S``,
    ``Delta = det S`` (Shuster & Oh 1981); the weights sum to 1 here.
    ``f'(lambda_max) = prod_(j != max) (lambda_max - lambda_j)``."""
    sz0, sz1, sz2 = sym_mv(s00, s01, s02, s11, s12, s22, z0, z1, z2)
    kappa = s11 * s22 - s12 * s12 + s00 * s22 - s02 * s02 + s00 * s11 - s01 * s01
    a = sigma * sigma - kappa
    bb = sigma * sigma + z0 * z0 + z1 * z1 + z2 * z2
    c = sym_det(s00, s01, s02, s11, s12, s22) + z0 * sz0 + z1 * sz1 + z2 * sz2
    d = sz0 * sz0 + sz1 * sz1 + sz2 * sz2
    return a, bb, c, d


def fprime(lam: float, a: float, bb: float, c: float) -> float:
    """``f'(lam)`` of :func:`lambda_coeffs`' polynomial."""
    l2 = lam * lam
    return 2.0 * lam * (2.0 * l2 - a - bb) - c


def newton_step(lam: float, a: float, bb: float, c: float, sigma: float, d: float) -> float:
    """Newton's step ``f / f'`` at ``lam`` (0 where ``f' = 0``)."""
    l2 = lam * lam
    f = (l2 - a) * (l2 - bb) - c * lam + c * sigma - d
    fp = fprime(lam, a, bb, c)
    return pick(fp != 0.0, f / fp, 0.0)


def newton_fast(a: float, bb: float, c: float, d: float, sigma: float) -> tuple[float, float]:
    """``NEWTON_FAST`` of :func:`lambda_max`'s steps from 1 with no branch (a lane stops
    moving once a step is within ``NEWTON_TOL``, as the loop stops): ``lam`` and 1.0
    where the loop would go on (0.0 where it stopped)."""
    lam = 1.0
    on = 1.0
    for _ in range(NEWTON_FAST):
        step = newton_step(lam, a, bb, c, sigma, d)
        lam = pick(on != 0.0, lam - step, lam)
        on = pick(abs(step) > NEWTON_TOL, on, 0.0)
    return lam, on


def lambda_max(a: float, bb: float, c: float, d: float, sigma: float) -> float:
    """Largest eigenvalue of ``K`` by Newton on its characteristic polynomial from 1
    (:func:`lambda_coeffs`), until a step is within ``NEWTON_TOL``."""
    lam = 1.0
    for _ in range(NEWTON_MAX):
        step = newton_step(lam, a, bb, c, sigma, d)
        lam = lam - step
        if not going(abs(step) > NEWTON_TOL):
            break
    return lam


def quest_raw(
    s00: float, s01: float, s02: float, s11: float, s12: float, s22: float,
    sigma: float, z0: float, z1: float, z2: float, lam: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """Unnormalised QUEST quaternion ``(gamma, x)`` (Shuster & Oh 1981).

    ``alpha = l^2 - sigma^2 + kappa``, ``beta = l - sigma``,
    ``gamma = (l + sigma) alpha - Delta``, ``x = (alpha E + beta S + S^2) z``: the Gibbs
    vector is ``x / gamma``.
    """
    kappa = s11 * s22 - s12 * s12 + s00 * s22 - s02 * s02 + s00 * s11 - s01 * s01
    alpha = lam * lam - sigma * sigma + kappa
    beta = lam - sigma
    gamma = (lam + sigma) * alpha - sym_det(s00, s01, s02, s11, s12, s22)
    sz0, sz1, sz2 = sym_mv(s00, s01, s02, s11, s12, s22, z0, z1, z2)
    ssz0, ssz1, ssz2 = sym_mv(s00, s01, s02, s11, s12, s22, sz0, sz1, sz2)
    return (
        gamma,
        alpha * z0 + beta * sz0 + ssz0,
        alpha * z1 + beta * sz1 + ssz1,
        alpha * z2 + beta * sz2 + ssz2,
    )


def normalised4(w: float, x: float, y: float, z: float) -> tuple[float, float, float, float]:
    n = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
    return w * n, x * n, y * n, z * n


def turned(
    b00: float, b01: float, b02: float, b10: float, b11: float, b12: float,
    b20: float, b21: float, b22: float, c0: float, c1: float, c2: float,
) -> tuple[float, ...]:  # fmt: skip
    """``B D`` for ``D = diag(c0, c1, c2)``: the half-turn about axis ``k`` has
    ``c_k = 1`` and -1 for the others (``(1, 1, 1)``: ``B``), the reference frame turned
    (Shuster's sequential rotations)."""
    return (
        b00 * c0, b01 * c1, b02 * c2, b10 * c0, b11 * c1, b12 * c2,
        b20 * c0, b21 * c1, b22 * c2,
    )  # fmt: skip


def turned_back(
    i0: float, i1: float, i2: float, i3: float, w: float, x: float, y: float, z: float
) -> tuple[float, float, float, float]:
    """``L = i_k o L'`` for the solution ``L'`` in the frame turned about axis ``k``
    (``i_k`` the basis quaternion, given as its four entries, one of them 1: ``(1, 0,
    0, 0)`` for ``L'`` itself). Entries, not an axis number, so that no table of
    constants is read by index (which would stop LLVM vectorising the batch loop)."""
    return hamilton(i0, i1, i2, i3, w, x, y, z)


def quest(
    b00: float, b01: float, b02: float, b10: float, b11: float, b12: float,
    b20: float, b21: float, b22: float, lam: float, fp: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """QUEST (Shuster & Oh 1981) for ``B = sum_i w_i b_i r_i^T`` with ``sum w_i = 1``,
    ``lam = lambda_max`` and ``fp = f'(lambda_max)`` (:func:`lambda_max`); where
    ``|l0| < 0.3`` (``gamma = f'(lambda_max) l0^2``) the reference frame is turned by the
    half-turn about x, y or z that gives the largest ``|l0'|`` and the result turned
    back. No branch: the four solutions are formed and one picked (the batch loops run
    it on a block of sets at once)."""
    s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2 = k_parts(
        b00, b01, b02, b10, b11, b12, b20, b21, b22
    )
    g, x0, x1, x2 = quest_raw(s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2, lam)
    # sequential rotations: the half-turn whose frame has the largest |l0'|, read from
    # the three turned solutions (l0'^2 = gamma^2 / |(gamma, x)|^2); the largest diagonal
    # of K alone picks a poor one for two observations (1e-9 rad instead of 1e-14)
    g1, a1, b1, c1 = quest_turned(b00, b01, b02, b10, b11, b12, b20, b21, b22, 1, lam)
    g2, a2, b2, c2 = quest_turned(b00, b01, b02, b10, b11, b12, b20, b21, b22, 2, lam)
    g3, a3, b3, c3 = quest_turned(b00, b01, b02, b10, b11, b12, b20, b21, b22, 3, lam)
    f1 = g1 * g1 / (g1 * g1 + a1 * a1 + b1 * b1 + c1 * c1)
    f2 = g2 * g2 / (g2 * g2 + a2 * a2 + b2 * b2 + c2 * c2)
    f3 = g3 * g3 / (g3 * g3 + a3 * a3 + b3 * b3 + c3 * c3)
    one = f1 >= f2 and f1 >= f3
    two = not one and f2 >= f3
    keep = g >= QUEST_ROTATION_THRESHOLD * QUEST_ROTATION_THRESHOLD * fp
    i0 = pick(keep, 1.0, 0.0)
    i1 = pick(keep, 0.0, pick(one, 1.0, 0.0))
    i2 = pick(keep, 0.0, pick(one, 0.0, pick(two, 1.0, 0.0)))
    i3 = 1.0 - i0 - i1 - i2
    g = pick(keep, g, pick(one, g1, pick(two, g2, g3)))
    x0 = pick(keep, x0, pick(one, a1, pick(two, a2, a3)))
    x1 = pick(keep, x1, pick(one, b1, pick(two, b2, b3)))
    x2 = pick(keep, x2, pick(one, c1, pick(two, c2, c3)))
    w, x, y, z = normalised4(g, x0, x1, x2)
    return turned_back(i0, i1, i2, i3, w, x, y, z)


def quest_turned(
    b00: float, b01: float, b02: float, b10: float, b11: float, b12: float,
    b20: float, b21: float, b22: float, turn: int, lam: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """:func:`quest_raw` in the reference frame turned about axis ``turn - 1`` (a
    constant: 1, 2 or 3; same ``lambda``)."""
    t = turned(
        b00, b01, b02, b10, b11, b12, b20, b21, b22,
        1.0 if turn == 1 else -1.0, 1.0 if turn == 2 else -1.0, 1.0 if turn == 3 else -1.0,
    )  # fmt: skip
    s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2 = k_parts(
        t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8]
    )
    return quest_raw(s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2, lam)


def cross(
    ax: float, ay: float, az: float, bx: float, by: float, bz: float
) -> tuple[float, float, float]:
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


def esoq2(
    b00: float, b01: float, b02: float, b10: float, b11: float, b12: float,
    b20: float, b21: float, b22: float, lam: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """ESOQ2 (Mortari 1997) with QUEST's ``lam = lambda_max``; the axis ``e`` is the null
    vector of ``M = (lambda - sigma)(S - (lambda + sigma) E) + z z^T`` (the largest cross
    product of two of its columns), ``L ~ (z.e, (lambda - sigma) e)``, in the frame
    turned by the half-turn of the smallest diagonal of ``K`` (ESOQ2 is singular at the
    identity). No branch (picks), as :func:`quest`."""
    s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2 = k_parts(
        b00, b01, b02, b10, b11, b12, b20, b21, b22
    )
    k0, k1, k2, k3 = sigma, s00 - sigma, s11 - sigma, s22 - sigma
    # the smallest diagonal of K, the first on ties (numpy.argmin)
    t0 = k0 <= k1 and k0 <= k2 and k0 <= k3
    t1 = not t0 and k1 <= k2 and k1 <= k3
    t2 = not t0 and not t1 and k2 <= k3
    i0 = pick(t0, 1.0, 0.0)
    i1 = pick(t1, 1.0, 0.0)
    i2 = pick(t2, 1.0, 0.0)
    i3 = 1.0 - i0 - i1 - i2
    t = turned(
        b00, b01, b02, b10, b11, b12, b20, b21, b22,
        i0 + i1 - i2 - i3, i0 - i1 + i2 - i3, i0 - i1 - i2 + i3,
    )  # fmt: skip
    s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2 = k_parts(
        t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8]
    )
    beta = lam - sigma
    ls = lam + sigma
    m00 = beta * (s00 - ls) + z0 * z0
    m01 = beta * s01 + z0 * z1
    m02 = beta * s02 + z0 * z2
    m11 = beta * (s11 - ls) + z1 * z1
    m12 = beta * s12 + z1 * z2
    m22 = beta * (s22 - ls) + z2 * z2
    # columns of the symmetric M: (m00, m01, m02), (m01, m11, m12), (m02, m12, m22)
    ya = cross(m00, m01, m02, m01, m11, m12)
    yb = cross(m01, m11, m12, m02, m12, m22)
    yc = cross(m02, m12, m22, m00, m01, m02)
    na = ya[0] * ya[0] + ya[1] * ya[1] + ya[2] * ya[2]
    nb = yb[0] * yb[0] + yb[1] * yb[1] + yb[2] * yb[2]
    nc = yc[0] * yc[0] + yc[1] * yc[1] + yc[2] * yc[2]
    pa = na >= nb and na >= nc  # the first of the largest (numpy.argmax)
    pb = not pa and nb >= nc
    e0 = pick(pa, ya[0], pick(pb, yb[0], yc[0]))
    e1 = pick(pa, ya[1], pick(pb, yb[1], yc[1]))
    e2 = pick(pa, ya[2], pick(pb, yb[2], yc[2]))
    ne = pick(pa, na, pick(pb, nb, nc))
    n = 1.0 / math.sqrt(ne)
    e0, e1, e2 = e0 * n, e1 * n, e2 * n
    w, x, y, z = normalised4(z0 * e0 + z1 * e1 + z2 * e2, beta * e0, beta * e1, beta * e2)
    return turned_back(i0, i1, i2, i3, w, x, y, z)


def accumulate(ob: Any, rf: Any, w: Any, n: Any) -> Any:
    """``lambda0 = sum w``, ``sum w b b^T`` (6), ``sum w r r^T`` (6) and ``sum w b r^T``
    (9) of the unit directions."""
    lam0 = 0.0
    pb00 = pb01 = pb02 = pb11 = pb12 = pb22 = 0.0  # sum w b b^T
    pr00 = pr01 = pr02 = pr11 = pr12 = pr22 = 0.0  # sum w r r^T
    b00 = b01 = b02 = b10 = b11 = b12 = b20 = b21 = b22 = 0.0  # sum w b r^T
    for i in range(n):
        wi = w[i]
        bx, by, bz = unit(ob[i][0], ob[i][1], ob[i][2])
        rx, ry, rz = unit(rf[i][0], rf[i][1], rf[i][2])
        lam0 += wi
        pb00 += wi * bx * bx
        pb01 += wi * bx * by
        pb02 += wi * bx * bz
        pb11 += wi * by * by
        pb12 += wi * by * bz
        pb22 += wi * bz * bz
        pr00 += wi * rx * rx
        pr01 += wi * rx * ry
        pr02 += wi * rx * rz
        pr11 += wi * ry * ry
        pr12 += wi * ry * rz
        pr22 += wi * rz * rz
        b00 += wi * bx * rx
        b01 += wi * bx * ry
        b02 += wi * bx * rz
        b10 += wi * by * rx
        b11 += wi * by * ry
        b12 += wi * by * rz
        b20 += wi * bz * rx
        b21 += wi * bz * ry
        b22 += wi * bz * rz
    return (
        lam0, pb00, pb01, pb02, pb11, pb12, pb22, pr00, pr01, pr02, pr11, pr12, pr22,
        b00, b01, b02, b10, b11, b12, b20, b21, b22,
    )  # fmt: skip


def attitude(
    ob: Any, rf: Any, w: Any, n: Any, method: Any, want_cov: Any, p: Any, lam: Any, fp: Any
) -> Any:
    """From the sums ``p`` (:func:`accumulate`) and ``lambda_max``: the 12 results of
    :func:`solve` (``status`` 0.0)."""
    nan = math.nan
    lam0 = p[0]
    s = 1.0 / lam0  # lambda0 = 1 inside: the polynomial's scale is fixed
    b00, b01, b02, b10, b11, b12 = p[13] * s, p[14] * s, p[15] * s, p[16] * s, p[17] * s, p[18] * s
    b20, b21, b22 = p[19] * s, p[20] * s, p[21] * s
    if method == QUEST:
        q0, q1, q2, q3 = quest(b00, b01, b02, b10, b11, b12, b20, b21, b22, lam, fp)
    else:
        q0, q1, q2, q3 = esoq2(b00, b01, b02, b10, b11, b12, b20, b21, b22, lam)
    flip = pick(q0 < 0.0, -1.0, 1.0)
    q0, q1, q2, q3 = q0 * flip, q1 * flip, q2 * flip, q3 * flip
    c = to_matrix(q0, q1, q2, q3)  # C_nb: r ~ C b
    loss = 0.0
    for i in range(n):
        bx, by, bz = unit(ob[i][0], ob[i][1], ob[i][2])
        rx, ry, rz = unit(rf[i][0], rf[i][1], rf[i][2])
        dx = rx - (c[0] * bx + c[1] * by + c[2] * bz)
        dy = ry - (c[3] * bx + c[4] * by + c[5] * bz)
        dz = rz - (c[6] * bx + c[7] * by + c[8] * bz)
        loss += w[i] * (dx * dx + dy * dy + dz * dz)
    loss = 0.5 * loss
    if not want_cov:
        return q0, q1, q2, q3, loss, nan, nan, nan, nan, nan, nan, 0.0
    # (sum w (E - b b^T))^-1 = adj / det: symmetric
    m00, m01, m02, m11, m12, m22 = lam0 - p[1], -p[2], -p[3], lam0 - p[4], -p[5], lam0 - p[6]
    inv = 1.0 / sym_det(m00, m01, m02, m11, m12, m22)
    return (
        q0, q1, q2, q3, loss,
        (m11 * m22 - m12 * m12) * inv,
        (m02 * m12 - m01 * m22) * inv,
        (m01 * m12 - m02 * m11) * inv,
        (m00 * m22 - m02 * m02) * inv,
        (m01 * m02 - m00 * m12) * inv,
        (m00 * m11 - m01 * m01) * inv,
        0.0,
    )  # fmt: skip


def spreads(p: Any) -> Any:
    """``det sum w (E - u u^T)`` for the observations and the references, and the bound
    they must exceed (not all parallel, nor all weight on one direction)."""
    lam0 = p[0]
    det_b = sym_det(lam0 - p[1], -p[2], -p[3], lam0 - p[4], -p[5], lam0 - p[6])
    det_r = sym_det(lam0 - p[7], -p[8], -p[9], lam0 - p[10], -p[11], lam0 - p[12])
    return det_b, det_r, PARALLEL_RTOL * lam0 * lam0 * lam0


def polynomial(p: Any) -> Any:
    """``a, b, c, d, sigma`` of ``K``'s characteristic polynomial for the sums ``p``."""
    s = 1.0 / p[0]
    s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2 = k_parts(
        p[13] * s, p[14] * s, p[15] * s, p[16] * s, p[17] * s, p[18] * s,
        p[19] * s, p[20] * s, p[21] * s,
    )  # fmt: skip
    a, bb, c, d = lambda_coeffs(s00, s01, s02, s11, s12, s22, sigma, z0, z1, z2)
    return a, bb, c, d, sigma


def solve_fast(ob: Any, rf: Any, w: Any, n: Any, method: Any, want_cov: Any) -> Any:
    """:func:`solve` without a branch on the data, for a block of sets at once (the
    compiled batch loops): its 12 results and a 13th value, 0.0 where they are
    :func:`solve`'s, 1.0 where :func:`solve_slow` must be run instead (a status bit, or
    Newton not stopped in ``NEWTON_FAST`` steps; the results are then meaningless)."""
    fin = 0.0  # NaN unless every entry is finite
    least = math.inf  # the smallest largest |entry| of a direction: 0 for a zero vector
    for i in range(n):
        fin += (ob[i][0] - ob[i][0]) + (ob[i][1] - ob[i][1]) + (ob[i][2] - ob[i][2])
        fin += (rf[i][0] - rf[i][0]) + (rf[i][1] - rf[i][1]) + (rf[i][2] - rf[i][2])
        least = min(least, max(abs(ob[i][0]), abs(ob[i][1]), abs(ob[i][2])))
        least = min(least, max(abs(rf[i][0]), abs(rf[i][1]), abs(rf[i][2])))
    p = accumulate(ob, rf, w, n)
    det_b, det_r, bound = spreads(p)
    a, bb, c, d, sigma = polynomial(p)
    lam, on = newton_fast(a, bb, c, d, sigma)
    r = attitude(ob, rf, w, n, method, want_cov, p, lam, fprime(lam, a, bb, c))
    good = fin == 0.0 and least > 0.0 and det_b > bound and det_r > bound and on == 0.0
    return (*r, pick(good, 0.0, 1.0))


def solve_slow(ob: Any, rf: Any, w: Any, n: Any, method: Any, want_cov: Any) -> Any:
    """:func:`solve` one set at a time, with branches: the status checks first, Newton's
    loop until it stops."""
    nan = math.nan
    bad_b = bad_r = 0.0
    zero_b = zero_r = 0.0
    for i in range(n):  # finite, non-zero
        if not finite3(ob[i][0], ob[i][1], ob[i][2]):
            bad_b = 1.0
        if not finite3(rf[i][0], rf[i][1], rf[i][2]):
            bad_r = 1.0
        if max(abs(ob[i][0]), abs(ob[i][1]), abs(ob[i][2])) == 0.0:
            zero_b = 1.0
        if max(abs(rf[i][0]), abs(rf[i][1]), abs(rf[i][2])) == 0.0:
            zero_r = 1.0
    bad = bad_b * NONFINITE_OBSERVED + bad_r * NONFINITE_REFERENCE
    if bad != 0.0:
        return nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, bad
    bad = zero_b * ZERO_OBSERVED + zero_r * ZERO_REFERENCE
    if bad != 0.0:
        return nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, bad
    p = accumulate(ob, rf, w, n)
    det_b, det_r, bound = spreads(p)
    bad_b = 0.0 if det_b > bound else 1.0
    bad_r = 0.0 if det_r > bound else 1.0
    bad = bad_b * PARALLEL_OBSERVED + bad_r * PARALLEL_REFERENCE
    if bad != 0.0:
        return nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, bad
    a, bb, c, d, sigma = polynomial(p)
    lam = lambda_max(a, bb, c, d, sigma)
    return attitude(ob, rf, w, n, method, want_cov, p, lam, fprime(lam, a, bb, c))


def solve(ob: Any, rf: Any, w: Any, n: Any, method: Any, want_cov: Any) -> Any:
    """One observation set, read as ``ob[i][k]``, ``rf[i][k]``, ``w[i]`` (arrays, or
    tuples of floats in the compiled loops: no array, no reference count per set):
    ``(l0, l1, l2, l3, loss, c00, c01, c02, c11, c12, c22, status)``: the quaternion of
    ``C_nb`` with ``l0 >= 0``, Wahba's loss, the covariance entries (NaN unless
    ``want_cov``) and the status bits (``0.0``: solved; else everything else is NaN).
    :func:`solve_slow`; the compiled batch loops run :func:`solve_fast` on blocks of
    sets and :func:`solve_slow` on the sets it flags (the same results)."""
    return solve_slow(ob, rf, w, n, method, want_cov)
