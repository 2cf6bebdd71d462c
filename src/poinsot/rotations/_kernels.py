"""Compiled kernels: each quaternion formula of SPEC S1-S3 written once.

These are numba ``guvectorize`` kernels: they broadcast over leading dimensions
like NumPy ufuncs and allocate their outputs. They trust their inputs (shapes,
finiteness, unit norm where stated); validation happens at the public entry
points. This module is imported lazily (on first use) so that ``import
poinsot`` does not pay for numba.

Numba cannot size an output from a literal dimension, so kernels whose output
size does not appear among their inputs take a small ``dummy`` array of that
size (``_D3``/``_D4``); the wrappers in the representation modules hide it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import guvectorize, njit

_D3 = np.zeros(3)
_D4 = np.zeros(4)

_OPTS = {"nopython": True, "cache": True}


@njit(inline="always", cache=True)
def _hamilton(p0, p1, p2, p3, q0, q1, q2, q3):  # pragma: no cover - compiled
    # SPEC S1: L o M = l0 m0 - l.m + l0 m + m0 l + l x m
    return (
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + q0 * p1 + p2 * q3 - p3 * q2,
        p0 * q2 + q0 * p2 + p3 * q1 - p1 * q3,
        p0 * q3 + q0 * p3 + p1 * q2 - p2 * q1,
    )


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(n)->(n)", **_OPTS)
def qmul(p, q, r):  # pragma: no cover - compiled
    r[0], r[1], r[2], r[3] = _hamilton(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])


@njit(cache=True)
def qmul1(p, q):  # pragma: no cover - compiled
    # One product of two single quaternions: a plain jitted call costs ~0.4 us less
    # than a gufunc call, which matters when composing single rotations in a loop.
    r = np.empty(4)
    r[0], r[1], r[2], r[3] = _hamilton(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])
    return r


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(m)->(m)", **_OPTS)
def qrot(q, v, out):  # pragma: no cover - compiled
    # The sandwich q o v o q~ expanded (SPEC S2):
    # v' = (w^2 - |u|^2) v + 2 (u.v) u + 2 w (u x v); for |q| != 1 it scales by |q|^2.
    w, x, y, z = q[0], q[1], q[2], q[3]
    a, b, c = v[0], v[1], v[2]
    s = w * w - (x * x + y * y + z * z)
    d = 2.0 * (x * a + y * b + z * c)
    w2 = 2.0 * w
    out[0] = s * a + d * x + w2 * (y * c - z * b)
    out[1] = s * b + d * y + w2 * (z * a - x * c)
    out[2] = s * c + d * z + w2 * (x * b - y * a)


@guvectorize(["void(float64[:], float64[:], float64[:,:])"], "(n),(m)->(m,m)", **_OPTS)
def quat_to_matrix(q, dummy, m):  # pragma: no cover - compiled
    # SPEC S2: A = (2 l0^2 - 1) E + 2 l0 l^ + 2 l l^T, for a unit quaternion.
    w, x, y, z = q[0], q[1], q[2], q[3]
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    m[0, 0] = 1.0 - 2.0 * (yy + zz)
    m[0, 1] = 2.0 * (xy - wz)
    m[0, 2] = 2.0 * (xz + wy)
    m[1, 0] = 2.0 * (xy + wz)
    m[1, 1] = 1.0 - 2.0 * (xx + zz)
    m[1, 2] = 2.0 * (yz - wx)
    m[2, 0] = 2.0 * (xz - wy)
    m[2, 1] = 2.0 * (yz + wx)
    m[2, 2] = 1.0 - 2.0 * (xx + yy)


@guvectorize(
    ["void(float64[:,:], float64[:], float64[:], float64[:], float64[:])"],
    "(m,m),(n)->(n),(),()",
    **_OPTS,
)
def matrix_to_quat(a, dummy, q, err, det):  # pragma: no cover - compiled
    # SPEC S2: 4 l0^2 = 1 + tr A, 4 l1^2 = 1 + a11 - a22 - a33 (cyclic); take the
    # largest square first (no singular case), signs from off-diagonal sums.
    # Also reports max |A^T A - E| and det A so the caller can reject or project.
    e = 0.0
    for i in range(3):
        for j in range(3):
            s = a[0, i] * a[0, j] + a[1, i] * a[1, j] + a[2, i] * a[2, j]
            if i == j:
                s -= 1.0
            e = max(e, abs(s))
    err[0] = e
    det[0] = (
        a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
        - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
        + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0])
    )
    tr = a[0, 0] + a[1, 1] + a[2, 2]
    d0, d1, d2 = a[0, 0], a[1, 1], a[2, 2]
    if tr >= d0 and tr >= d1 and tr >= d2:
        q[0] = 1.0 + tr
        q[1] = a[2, 1] - a[1, 2]
        q[2] = a[0, 2] - a[2, 0]
        q[3] = a[1, 0] - a[0, 1]
    elif d0 >= d1 and d0 >= d2:
        q[0] = a[2, 1] - a[1, 2]
        q[1] = 1.0 + d0 - d1 - d2
        q[2] = a[0, 1] + a[1, 0]
        q[3] = a[0, 2] + a[2, 0]
    elif d1 >= d2:
        q[0] = a[0, 2] - a[2, 0]
        q[1] = a[0, 1] + a[1, 0]
        q[2] = 1.0 + d1 - d0 - d2
        q[3] = a[1, 2] + a[2, 1]
    else:
        q[0] = a[1, 0] - a[0, 1]
        q[1] = a[0, 2] + a[2, 0]
        q[2] = a[1, 2] + a[2, 1]
        q[3] = 1.0 + d2 - d0 - d1
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    for i in range(4):
        q[i] /= n


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(m),(n)->(n)", **_OPTS)
def rotvec_to_quat(v, dummy, q):  # pragma: no cover - compiled
    # L = cos(f/2) + e sin(f/2) with phi = f e.
    m = max(abs(v[0]), abs(v[1]), abs(v[2]))
    if m > 1e150:  # |phi|^2 would overflow: take the length scaled
        f = m * math.sqrt((v[0] / m) ** 2 + (v[1] / m) ** 2 + (v[2] / m) ** 2)
    else:
        f = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if f == 0.0:
        c, s = 1.0, 0.5
    elif f <= math.pi:
        # Half-angle tangent t = tan(f/4): cos(f/2) = (1 - t^2)/(1 + t^2),
        # sin(f/2) = 2 t/(1 + t^2). One tan instead of sin + cos (1.4x faster);
        # t/f stays accurate for tiny f (no series needed) and (1 - t)(1 + t)
        # avoids cancellation near f = pi (1 - t is exact there).
        t = math.tan(0.25 * f)
        d = 1.0 / (1.0 + t * t)
        c = (1.0 - t) * (1.0 + t) * d
        s = 2.0 * (t / f) * d
    else:
        c = math.cos(0.5 * f)
        s = math.sin(0.5 * f) / f
    q[0] = c
    q[1] = s * v[0]
    q[2] = s * v[1]
    q[3] = s * v[2]


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(m)->(m)", **_OPTS)
def quat_to_rotvec(q, dummy, v):  # pragma: no cover - compiled
    # f = 2 atan2(|l|, l0) with l0 >= 0 (shortest rotation, f in [0, pi]);
    # phi = f l / |l|, accurate at every angle because atan2 is.
    w, x, y, z = q[0], q[1], q[2], q[3]
    # Canonical sign (as SciPy): w > 0, or at exactly pi (w = 0) the first
    # non-zero vector component positive, so that f e is unique there too.
    if w < 0.0 or (w == 0.0 and (x < 0.0 or (x == 0.0 and (y < 0.0 or (y == 0.0 and z < 0.0))))):
        w, x, y, z = -w, -x, -y, -z
    n = math.sqrt(x * x + y * y + z * z)
    if n == 0.0:
        s = 2.0 / w
    else:
        s = 2.0 * math.atan2(n, w) / n
    v[0] = s * x
    v[1] = s * y
    v[2] = s * z


@guvectorize(["void(int64[:], float64[:], float64[:], float64[:])"], "(k),(k),(n)->(n)", **_OPTS)
def euler_to_quat(axes, angles, dummy, q):  # pragma: no cover - compiled
    # Intrinsic sequence: L = L_a1(f1) o L_a2(f2) o L_a3(f3) with L_a(f) = cos(f/2) + i_a sin(f/2).
    q[0], q[1], q[2], q[3] = 1.0, 0.0, 0.0, 0.0
    for n in range(axes.shape[0]):
        h = 0.5 * angles[n]
        c, s = math.cos(h), math.sin(h)
        a = axes[n] + 1
        # q <- q o (c + s i_a); with i_a o i_b = i_d (cyclic) only these terms survive.
        b = 1 + (a % 3)
        d = 1 + (b % 3)
        w, ua, ub, ud = q[0], q[a], q[b], q[d]
        q[0] = c * w - s * ua
        q[a] = c * ua + s * w
        q[b] = c * ub + s * ud
        q[d] = c * ud - s * ub


@njit(cache=True)
def quat_to_euler(q, seq, angles, singular):  # pragma: no cover - compiled
    # Bernardes & Viollet (2022), "Quaternion to Euler angles conversion: a direct,
    # general and computationally efficient method", PLoS ONE 17(11): e0276302 --
    # the algorithm SciPy uses. q (N, 4) unit; seq = (i, j, k, extrinsic) with i, j, k
    # the axes in *extrinsic* order (the caller reverses intrinsic sequences).
    # A plain loop (not a gufunc): per-element gufunc overhead doubled its cost.
    i, j, k, extrinsic = seq[0], seq[1], seq[2], seq[3]
    symmetric = i == k
    if symmetric:
        k = 3 - i - j
    sign = float((i - j) * (j - k) * (k - i) // 2)
    first = 0 if extrinsic else 2
    third = 2 if extrinsic else 0
    tb_sign = 1.0 if symmetric else sign
    eps = 1e-7  # documented gimbal-lock threshold (rad)
    for n in range(q.shape[0]):
        w = q[n, 0]
        qi, qj, qk = q[n, 1 + i], q[n, 1 + j], q[n, 1 + k]
        if symmetric:
            a, b, c, d = w, qi, qj, qk * sign
        else:
            a, b, c, d = w - qj, qi + qk * sign, qj + w, qk * sign - qi
        # |a|, |b|, |c|, |d| <= 2: sqrt(x^2 + y^2) cannot overflow, no need for hypot
        mid = 2.0 * math.atan2(math.sqrt(c * c + d * d), math.sqrt(a * a + b * b))
        half_sum = math.atan2(b, a)
        half_diff = math.atan2(d, c)
        case1 = abs(mid) <= eps
        case2 = abs(mid - math.pi) <= eps
        if case1 or case2:
            # Only the sum (case 1) or difference (case 2) of the outer angles is
            # determined: the user's third angle is set to 0, the first holds it.
            singular[n] = True
            if case1:
                combined = 2.0 * half_sum
            else:
                combined = 2.0 * half_diff * (-1.0 if extrinsic else 1.0)
            angles[n, 0] = combined if extrinsic else combined * tb_sign
            angles[n, 2] = 0.0
            # The middle angle snaps to its singular value: the returned angles then
            # reproduce the rotation to within |mid - singular| <= eps exactly (keeping
            # the computed middle angle, as SciPy does, could be off by up to 2 eps).
            mid = 0.0 if case1 else math.pi
        else:
            singular[n] = False
            angles[n, first] = half_sum - half_diff
            angles[n, third] = (half_sum + half_diff) * tb_sign
        if not symmetric:
            mid -= 0.5 * math.pi
        angles[n, 1] = mid
        for m in (0, 2):
            a_m = angles[n, m]
            if a_m > math.pi or a_m < -math.pi:  # wrap to [-pi, pi]
                angles[n, m] = (a_m + math.pi) % (2.0 * math.pi) - math.pi
