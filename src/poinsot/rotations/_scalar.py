"""The rotation formulas on scalars, written once: plain Python, compiled by numba too.

Each function takes and returns Python floats (tuples for several values) and uses
only ``math`` and arithmetic, so it serves two callers unchanged:

* the short path for *one* rotation in :class:`~poinsot.Rotation` (called as plain
  Python on the floats of ``q.tolist()``: no NumPy dispatch, no numba call);
* the compiled batch kernels of :mod:`poinsot.rotations._kernels`, which wrap them
  with ``numba.njit(inline="always")`` (their cache is stamped with this file, see
  ``docs/conventions.md``, "Compiled kernels").

One rotation and a batch therefore run the same operations in the same order
(bit-identical results for the same libm). Inputs are trusted: validation is done
by the callers. Quaternions are Hamilton, scalar first ``(w, x, y, z)``
(theory §1-§3).

>>> hamilton(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)      # i1 o i2 = i3
(0.0, 0.0, 0.0, 1.0)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = [
    "hamilton",
    "rotate",
    "to_matrix",
    "vertical",
    "matrix_residual",
    "matrix_check",
    "is_rotation_within",
    "from_matrix",
    "from_rotvec",
    "rotvec_angle",
    "from_rotvec_tan",
    "canonical",
    "to_rotvec",
    "to_mrp",
    "from_mrp",
    "axis_angle",
    "from_euler",
    "to_euler",
    "euler_atan2_args",
    "euler_axes",
    "euler_args",
    "euler_from_atan2",
    "atan2_poly",
    "angle",
    "cross",
    "euler_columns",
]


def hamilton(
    p0: float,
    p1: float,
    p2: float,
    p3: float,
    q0: float,
    q1: float,
    q2: float,
    q3: float,
) -> tuple[float, float, float, float]:
    """``P o Q = (p0 q0 - p.q, p0 q + q0 p + p x q)`` (theory §1)."""
    return (
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + q0 * p1 + p2 * q3 - p3 * q2,
        p0 * q2 + q0 * p2 + p3 * q1 - p1 * q3,
        p0 * q3 + q0 * p3 + p1 * q2 - p2 * q1,
    )


def rotate(
    w: float,
    x: float,
    y: float,
    z: float,
    a: float,
    b: float,
    c: float,
) -> tuple[float, float, float]:
    """The sandwich ``q o v o q~`` expanded (theory §2).

    ``v' = (w^2 - |u|^2) v + 2 (u.v) u + 2 w (u x v)``; for ``|q| != 1`` it is
    scaled by ``|q|^2``.
    """
    s = w * w - (x * x + y * y + z * z)
    d = 2.0 * (x * a + y * b + z * c)
    w2 = 2.0 * w
    return (
        s * a + d * x + w2 * (y * c - z * b),
        s * b + d * y + w2 * (z * a - x * c),
        s * c + d * z + w2 * (x * b - y * a),
    )


def to_matrix(w: float, x: float, y: float, z: float) -> tuple[float, ...]:
    """``A = (2 l0^2 - 1) E + 2 l0 l^ + 2 l l^T`` row by row, unit ``q`` (theory §2)."""
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    return (
        1.0 - 2.0 * (yy + zz),
        2.0 * (xy - wz),
        2.0 * (xz + wy),
        2.0 * (xy + wz),
        1.0 - 2.0 * (xx + zz),
        2.0 * (yz - wx),
        2.0 * (xz - wy),
        2.0 * (yz + wx),
        1.0 - 2.0 * (xx + yy),
    )


def vertical(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """``|L|^2 R^T e_z``: the third row of :func:`to_matrix` written for any ``L`` (its
    entries scaled by ``|L|^2``); for a unit ``L`` the vertical ``gamma`` in body axes,
    whose entry ``i`` is the vertical component of body axis ``i`` (theory §2, §10).
    Arithmetic only: also runs on NumPy arrays, element by element.

    >>> vertical(1.0, 0.0, 0.0, 0.0)
    (0.0, 0.0, 1.0)
    """
    return (
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        w * w - x * x - y * y + z * z,
    )


def matrix_residual(
    a00: float,
    a01: float,
    a02: float,
    a10: float,
    a11: float,
    a12: float,
    a20: float,
    a21: float,
    a22: float,
) -> tuple[float, float, float, float, float, float, float]:
    """The six entries of ``A^T A - E`` (diagonal first) and ``det A``, rows given."""
    c00 = a00 * a00 + a10 * a10 + a20 * a20 - 1.0
    c11 = a01 * a01 + a11 * a11 + a21 * a21 - 1.0
    c22 = a02 * a02 + a12 * a12 + a22 * a22 - 1.0
    c01 = a00 * a01 + a10 * a11 + a20 * a21
    c02 = a00 * a02 + a10 * a12 + a20 * a22
    c12 = a01 * a02 + a11 * a12 + a21 * a22
    det = (
        a00 * (a11 * a22 - a12 * a21)
        - a01 * (a10 * a22 - a12 * a20)
        + a02 * (a10 * a21 - a11 * a20)
    )
    return c00, c11, c22, c01, c02, c12, det


def matrix_check(
    a00: float,
    a01: float,
    a02: float,
    a10: float,
    a11: float,
    a12: float,
    a20: float,
    a21: float,
    a22: float,
) -> tuple[float, float]:
    """``(max |A^T A - E|, det A)`` of a 3x3 matrix given by rows."""
    c00, c11, c22, c01, c02, c12, det = matrix_residual(a00, a01, a02, a10, a11, a12, a20, a21, a22)
    return max(abs(c00), abs(c11), abs(c22), abs(c01), abs(c02), abs(c12)), det


def is_rotation_within(
    a00: float,
    a01: float,
    a02: float,
    a10: float,
    a11: float,
    a12: float,
    a20: float,
    a21: float,
    a22: float,
    tol: float,
) -> bool:
    """``max |A^T A - E| <= tol`` and ``det A > 0``, False for any NaN or inf entry.

    Each comparison is made on its own (a NaN fails it), so no ``max`` that could
    drop a NaN; ``&`` rather than ``and``: no branch, and the compiled batch loop
    stays vectorised.
    """
    c00, c11, c22, c01, c02, c12, det = matrix_residual(a00, a01, a02, a10, a11, a12, a20, a21, a22)
    near = (abs(c00) <= tol) & (abs(c11) <= tol) & (abs(c22) <= tol) & (abs(c01) <= tol)
    return near & (abs(c02) <= tol) & (abs(c12) <= tol) & (det > 0.0)


def from_matrix(
    a00: float,
    a01: float,
    a02: float,
    a10: float,
    a11: float,
    a12: float,
    a20: float,
    a21: float,
    a22: float,
) -> tuple[float, float, float, float]:
    """Unit quaternion of a rotation matrix, largest square first (theory §2).

    ``4 l0^2 = 1 + tr A``, ``4 l1^2 = 1 + a11 - a22 - a33`` (cyclic): the largest
    one is taken first (no singular case), the others from off-diagonal sums.
    """
    tr = a00 + a11 + a22
    if tr >= a00 and tr >= a11 and tr >= a22:
        q0, q1, q2, q3 = 1.0 + tr, a21 - a12, a02 - a20, a10 - a01
    elif a00 >= a11 and a00 >= a22:
        q0, q1, q2, q3 = a21 - a12, 1.0 + a00 - a11 - a22, a01 + a10, a02 + a20
    elif a11 >= a22:
        q0, q1, q2, q3 = a02 - a20, a01 + a10, 1.0 + a11 - a00 - a22, a12 + a21
    else:
        q0, q1, q2, q3 = a10 - a01, a02 + a20, a12 + a21, 1.0 + a22 - a00 - a11
    n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return q0 / n, q1 / n, q2 / n, q3 / n


def from_rotvec(a: float, b: float, c: float) -> tuple[float, float, float, float]:
    """``L = cos(f/2) + e sin(f/2)`` from ``phi = f e`` (theory §2).

    Up to ``f = pi`` through the half-angle tangent ``t = tan(f/4)``:
    ``cos(f/2) = (1 - t)(1 + t)/(1 + t^2)``, ``sin(f/2)/f = 2 (t/f)/(1 + t^2)``,
    one ``tan`` instead of ``sin`` and ``cos``, accurate for tiny ``f`` (no series)
    and near pi (``1 - t`` is exact there). The length is taken scaled when
    ``|phi|^2`` would overflow.

    Written as :func:`rotvec_angle`, ``tan``, :func:`from_rotvec_tan`: large
    batches take the ``tan`` from NumPy's vectorised loop in between.
    """
    f = rotvec_angle(a, b, c)
    return from_rotvec_tan(a, b, c, f, math.tan(0.25 * f) if f <= math.pi else 0.0)


def rotvec_angle(a: float, b: float, c: float) -> float:
    """``f = |phi|``, scaled when ``|phi|^2`` would overflow."""
    m = max(abs(a), abs(b), abs(c))
    if m > 1e150:
        return m * math.sqrt((a / m) * (a / m) + (b / m) * (b / m) + (c / m) * (c / m))
    return math.sqrt(a * a + b * b + c * c)


def from_rotvec_tan(
    a: float,
    b: float,
    c: float,
    f: float,
    t: float,
) -> tuple[float, float, float, float]:
    """:func:`from_rotvec` given ``f = |phi|`` and ``t = tan(f/4)`` (ignored unless
    ``0 < f <= pi``)."""
    if f == 0.0:
        co, s = 1.0, 0.5
    elif f <= math.pi:
        d = 1.0 / (1.0 + t * t)
        co = (1.0 - t) * (1.0 + t) * d
        s = 2.0 * (t / f) * d
    else:
        co = math.cos(0.5 * f)
        s = math.sin(0.5 * f) / f
    return co, s * a, s * b, s * c


def canonical(w: float, x: float, y: float, z: float) -> tuple[float, float, float, float]:
    """``q`` or ``-q``, whichever has ``w > 0`` (at ``w = 0``: the first non-zero
    component positive): the sign SciPy calls canonical (theory §2)."""
    if w < 0.0 or (w == 0.0 and (x < 0.0 or (x == 0.0 and (y < 0.0 or (y == 0.0 and z < 0.0))))):
        return -w, -x, -y, -z
    return w, x, y, z


def to_mrp(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """Modified Rodrigues parameters ``p = l / (1 + l0)``, ``|p| <= 1`` (theory §2), of a
    quaternion of :func:`canonical` sign (callers take it first: numba inlines calls)."""
    d = 1.0 + w
    return x / d, y / d, z / d


def from_mrp(a: float, b: float, c: float) -> tuple[float, float, float, float]:
    """``L = ((1 - |p|^2) + 2 p) / (1 + |p|^2)`` from modified Rodrigues parameters
    (theory §2), for ``|p|^2`` that does not overflow (callers check)."""
    n2 = a * a + b * b + c * c
    d = 1.0 + n2
    return (1.0 - n2) / d, 2.0 * a / d, 2.0 * b / d, 2.0 * c / d


def axis_angle(w: float, x: float, y: float, z: float) -> tuple[float, float, float, float]:
    """Unit axis and angle in ``[0, pi]`` of a quaternion of :func:`canonical` sign
    (theory §2): ``f = 2 atan2(|l|, l0)``, ``e = l / |l|`` (``(1, 0, 0)`` for ``f = 0``)."""
    n = math.sqrt(x * x + y * y + z * z)
    if n > 0.0:
        return x / n, y / n, z / n, 2.0 * math.atan2(n, w)
    return 1.0, 0.0, 0.0, 2.0 * math.atan2(n, w)


def to_rotvec(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """``phi = 2 atan2(|l|, l0) l / |l|`` of a quaternion of :func:`canonical` sign
    (theory §2; callers take it first).

    The sign is SciPy's canonical one: ``w > 0``, or at exactly pi (``w = 0``) the
    first non-zero vector component positive, so that ``f e`` (``f in [0, pi]``)
    is unique there too. Accurate at every angle because ``atan2`` is.
    """
    n = math.sqrt(x * x + y * y + z * z)
    if n == 0.0:
        s = 2.0 / w
    else:
        s = 2.0 * math.atan2(n, w) / n
    return s * x, s * y, s * z


def from_euler(
    axes: Sequence[int],
    a0: float,
    a1: float,
    a2: float,
) -> tuple[float, float, float, float]:
    """``L = L_a1(f1) o L_a2(f2) o L_a3(f3)`` for an intrinsic sequence (theory §3).

    ``axes`` lists the axes (0, 1, 2) of the sequence (1 to 3 of them; the unused
    angles are ignored), ``L_a(f) = cos(f/2) + i_a sin(f/2)``. Each factor is
    ``q o (c + s i_a)``; with ``i_a o i_b = i_d`` (cyclic) only these terms survive.
    """
    w, x, y, z = 1.0, 0.0, 0.0, 0.0
    angles = (a0, a1, a2)
    for n in range(len(axes)):
        h = 0.5 * angles[n]
        c, s = math.cos(h), math.sin(h)
        a = axes[n]
        if a == 0:
            w, x, y, z = c * w - s * x, c * x + s * w, c * y + s * z, c * z - s * y
        elif a == 1:
            w, x, y, z = c * w - s * y, c * x - s * z, c * y + s * w, c * z + s * x
        else:
            w, x, y, z = c * w - s * z, c * x + s * y, c * y - s * x, c * z + s * w
    return w, x, y, z


def to_euler(
    w: float,
    x: float,
    y: float,
    z: float,
    i: int,
    j: int,
    k: int,
    extrinsic: bool,
    eps: float,
) -> tuple[float, float, float, bool]:
    """Euler angles ``(a1, a2, a3, singular)`` of a unit quaternion (theory §3).

    Bernardes & Viollet (2022), "Quaternion to Euler angles conversion: a direct,
    general and computationally efficient method", PLoS ONE 17(11): e0276302 (the
    algorithm SciPy uses). ``i, j, k`` are the axes (0, 1, 2) of the sequence in
    *extrinsic* order (the caller reverses intrinsic ones); ``extrinsic`` is a
    bool. Within ``eps`` of gimbal lock only the sum (or difference) of the outer
    angles is determined: the user's third angle is set to 0, the first holds it,
    and the middle one snaps to its singular value (the angles then reproduce the
    rotation to within ``eps``).

    Written as :func:`euler_atan2_args`, three ``atan2``, :func:`euler_from_atan2`:
    large batches take the ``atan2`` from NumPy's vectorised loop in between.
    """
    y1, x1, y2, x2, y3, x3 = euler_atan2_args(w, x, y, z, i, j, k)
    return euler_from_atan2(
        math.atan2(y1, x1), math.atan2(y2, x2), math.atan2(y3, x3), i, j, k, extrinsic, eps
    )


def euler_atan2_args(
    w: float,
    x: float,
    y: float,
    z: float,
    i: int,
    j: int,
    k: int,
) -> tuple[float, float, float, float, float, float]:
    """The arguments ``(y, x)`` of the three ``atan2`` of :func:`to_euler`: half the
    middle angle, the half sum and the half difference of the outer ones."""
    k, sign, symmetric = euler_axes(i, j, k)
    v = (x, y, z)
    return euler_args(w, v[i], v[j], v[k], sign, symmetric)


def euler_axes(i: int, j: int, k: int) -> tuple[int, float, bool]:
    """``(k, sign, symmetric)`` of a sequence ``i, j, k`` (extrinsic order) in the
    algorithm of :func:`to_euler`: for a proper sequence (``i == k``) the third axis
    is the one not listed; ``sign`` is that of the permutation ``(i, j, k)``.

    >>> euler_axes(2, 0, 2), euler_axes(0, 1, 2)
    ((1, 1.0, True), (2, 1.0, False))
    """
    symmetric = i == k
    if symmetric:
        k = 3 - i - j
    return k, float((i - j) * (j - k) * (k - i) // 2), symmetric


def euler_args(
    w: float,
    qi: float,
    qj: float,
    qk: float,
    sign: float,
    symmetric: bool,
) -> tuple[float, float, float, float, float, float]:
    """:func:`euler_atan2_args` given the components ``qi, qj, qk`` of the axes and
    ``sign, symmetric`` of :func:`euler_axes` (the compiled batch loop picks the
    components once per block, so that this runs on unit-stride rows)."""
    if symmetric:
        a, b, c, d = w, qi, qj, qk * sign
    else:
        a, b, c, d = w - qj, qi + qk * sign, qj + w, qk * sign - qi
    # |a|, |b|, |c|, |d| <= 2: sqrt(x^2 + y^2) cannot overflow, no need for hypot
    return math.sqrt(c * c + d * d), math.sqrt(a * a + b * b), b, a, d, c


#: ``2 pi`` rounded: the outer angles (sums of two ``atan2``, in ``[-2 pi, 2 pi]``)
#: are brought to ``[-pi, pi]`` by adding or subtracting it once, as SciPy does.
_TWO_PI = 2.0 * math.pi


def euler_from_atan2(
    half_mid: float,
    half_sum: float,
    half_diff: float,
    i: int,
    j: int,
    k: int,
    extrinsic: bool,
    eps: float,
) -> tuple[float, float, float, bool]:
    """The angles of :func:`to_euler` from its three ``atan2`` values.

    Arithmetic and selects only (no call), so that a compiled loop over a batch
    vectorises.
    """
    k, sign, symmetric = euler_axes(i, j, k)
    mid = 2.0 * half_mid
    tb_sign = 1.0 if symmetric else sign
    case1 = abs(mid) <= eps
    case2 = abs(mid - math.pi) <= eps
    singular = case1 | case2
    if singular:
        combined = 2.0 * half_sum if case1 else 2.0 * half_diff * (-1.0 if extrinsic else 1.0)
        first = combined if extrinsic else combined * tb_sign
        third = 0.0
        mid = 0.0 if case1 else math.pi
    else:
        lo = half_sum - half_diff
        hi = (half_sum + half_diff) * tb_sign
        first, third = (lo, hi) if extrinsic else (hi, lo)
    if not symmetric:
        mid -= 0.5 * math.pi
    # each in [-2 pi, 2 pi]: one turn added or taken brings it to [-pi, pi]
    first = first - _TWO_PI if first > math.pi else (first + _TWO_PI if first < -math.pi else first)
    third = third - _TWO_PI if third > math.pi else (third + _TWO_PI if third < -math.pi else third)
    return first, mid, third, singular


def atan2_poly(y: float, x: float) -> float:
    """``atan2(y, x)`` by arithmetic and selects only (no libm call), within 2 ulp of
    libm's, for the compiled batch loops: LLVM vectorises a loop of these (libm's
    ``atan2``, about 20 ns a call, does not vectorise; NumPy's ``arctan2`` is SIMD
    only on AVX-512 CPUs).

    The first quadrant is ``atan(t)`` for ``t = min/max`` of ``|x|, |y|`` up to 0.66,
    ``pi/4 + atan((|y| - |x|) / (|y| + |x|))`` beyond (the numerator exact there,
    Sterbenz), taken from ``pi/2`` when ``|y| > |x|`` and from ``pi`` when ``x < 0``;
    ``atan`` on ``|u| <= 0.66`` is Cephes' rational approximation
    ``u + u z P(z) / Q(z)``, ``z = u^2`` (relative error 1.8e-16; Moshier, *Methods
    and Programs for Mathematical Functions*, 1989), the multiples of ``pi/4`` added
    in two parts. Signed zeros as libm: ``atan2(+-0, -0) = +-pi``; finite arguments.

    >>> atan2_poly(1.0, 1.0) == math.pi / 4, atan2_poly(-0.0, -1.0) == -math.pi
    (True, True)
    >>> abs(atan2_poly(0.3, -2.0) - math.atan2(0.3, -2.0)) <= 4.5e-16
    True
    """
    ax, ay = abs(x), abs(y)
    mx, mn = max(ax, ay), min(ax, ay)
    band = mn > 0.66 * mx
    swap = ay > ax
    num = ay - ax if band else mn
    den = ay + ax if band else mx
    u = num / den if den > 0.0 else 0.0
    z = u * u
    p = -8.750608600031904122785e-1 * z - 1.615753718733365076637e1
    p = (p * z - 7.500855792314704667340e1) * z - 1.228866684490136173410e2
    p = p * z - 6.485021904942025371773e1
    q = (z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2
    q = ((q * z + 4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z
    q = q + 1.945506571482613964425e2
    a = u + u * (z * p / q)
    # the base angle k pi/4 in two parts (hi rounded, lo the rest) and the sign of a:
    # 0 + a, pi/4 + a, pi/2 - a in the first quadrant, pi minus these for x < 0
    hi = 0.7853981633974483 if band else (1.5707963267948966 if swap else 0.0)
    lo = 3.061616997868383e-17 if band else (6.123233995736766e-17 if swap else 0.0)
    s = 1.0 if band or not swap else -1.0
    if math.copysign(1.0, x) < 0.0:
        hi, lo, s = math.pi - hi, 1.2246467991473532e-16 - lo, -s
    return math.copysign(hi + (s * a + lo), y)


def angle(w: float, x: float, y: float, z: float) -> float:
    """Rotation angle in ``[0, pi]``: ``2 atan2(|l|, |l0|)`` (theory §2).

    Written as :func:`angle_atan2_args` and ``atan2``: large batches take the
    ``atan2`` from NumPy's vectorised loop in between.
    """
    s, c = angle_atan2_args(w, x, y, z)
    return 2.0 * math.atan2(s, c)


def angle_atan2_args(w: float, x: float, y: float, z: float) -> tuple[float, float]:
    """The ``(|l|, |l0|)`` whose ``2 atan2`` is :func:`angle`."""
    return math.sqrt(x * x + y * y + z * z), abs(w)


def cross(
    a0: float,
    a1: float,
    a2: float,
    b0: float,
    b1: float,
    b2: float,
) -> tuple[float, float, float]:
    """``a x b``."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


def euler_columns(
    ax0: int,
    ax1: int,
    ax2: int,
    c0: float,
    s0: float,
    c1: float,
    s1: float,
    c2: float,
    s2: float,
    space: bool,
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """Columns of the Euler rate matrix ``M`` (``omega = M angles'``, theory §3), in
    factor order, for ``C = F0 F1 F2`` with ``F_m`` the turn about coordinate axis
    ``ax_m`` (0, 1, 2) by the angle of cosine ``c_m`` and sine ``s_m``.

    The column of factor ``m`` is its axis turned by the factors before it
    (``space=True``: ``F0 .. F(m-1) e``) or by the transposes of those after it
    (body frame: ``(F(m+1) .. F2)^T e``). Returns 9 floats, column after column.
    """

    def turn(
        v0: float,
        v1: float,
        v2: float,
        axis: int,
        c: float,
        s: float,
    ) -> tuple[float, float, float]:  # A_axis v, right-handed (s -> -s: transpose)
        if axis == 0:
            return v0, c * v1 - s * v2, s * v1 + c * v2
        if axis == 1:
            return c * v0 + s * v2, v1, c * v2 - s * v0
        return c * v0 - s * v1, s * v0 + c * v1, v2

    e0 = (1.0 if ax0 == 0 else 0.0, 1.0 if ax0 == 1 else 0.0, 1.0 if ax0 == 2 else 0.0)
    e1 = (1.0 if ax1 == 0 else 0.0, 1.0 if ax1 == 1 else 0.0, 1.0 if ax1 == 2 else 0.0)
    e2 = (1.0 if ax2 == 0 else 0.0, 1.0 if ax2 == 1 else 0.0, 1.0 if ax2 == 2 else 0.0)
    if space:
        a = e0
        b = turn(e1[0], e1[1], e1[2], ax0, c0, s0)
        d = turn(e2[0], e2[1], e2[2], ax1, c1, s1)
        d = turn(d[0], d[1], d[2], ax0, c0, s0)
    else:
        a = turn(e0[0], e0[1], e0[2], ax1, c1, -s1)
        a = turn(a[0], a[1], a[2], ax2, c2, -s2)
        b = turn(e1[0], e1[1], e1[2], ax2, c2, -s2)
        d = e2
    return a[0], a[1], a[2], b[0], b[1], b[2], d[0], d[1], d[2]
