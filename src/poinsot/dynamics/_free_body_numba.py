"""Compiled kernels of :class:`poinsot.dynamics.FreeRigidBody` (private).

Imported lazily (numba loads on first use). Two kernels over a batch of bodies:

* :func:`setup` computes, per body, the regime and the constants of the exact
  solution (docs/theory.md §10, docs/free-body.md): the regime discriminant
  ``D = K^2 - 2 T B = I_a (I_a - I_b) w_a^2 - I_c (I_b - I_c) w_c^2`` in double-double
  arithmetic from error-free transformations (Dekker's two-product, Knuth's
  two-sum), so ``D`` and ``1 - k^2`` are correct to a few ulp however close the
  state is to the separatrix; then the amplitudes, ``K(k)`` by the AGM, the phase
  by Carlson's ``R_F``, ``R_J`` of the half period and the attitude offset.
* :func:`evaluate` evaluates ``omega`` and the attitude of every body at every
  time: argument reduction, Jacobi functions by the descending Landen
  transformation fed ``1 - k^2`` directly, Carlson's ``R_J`` for the precession
  angle, and the quaternion.

The elliptic helpers come from :mod:`poinsot.dynamics._elliptic` and the
quaternion product from :mod:`poinsot._numba_helpers`; the cache stamps of these
kernels include both files (:func:`poinsot._numba_cache.depends_on`), so editing a
shared helper rebuilds them.
"""

from __future__ import annotations

import math

from .. import _numba_helpers as nh
from .._jit import njit, pick
from .._numba_cache import depends_on
from . import _elliptic

depends_on(__file__, nh, _elliptic)  # before the kernels: editing a helper rebuilds them

from .._numba_helpers import qaxis, qmul  # noqa: E402  # by name: poinsot.jax re-binds them
from ._elliptic import (  # noqa: E402
    LMAX,
    carlson_rf,
    carlson_rj,
    complete_k,
    jacobi_reduced,
    landen_fill,
    landen_table,
    reduce_argument,
)

# Modes
UNIFORM, SYMMETRIC, ELLIPTIC, SEPARATRIX = 0, 1, 2, 3
# Regime codes (FreeRigidBody.regime)
REGIMES = ("rest", "spherical", "separatrix", "symmetric", "major", "minor", "separatrix")
R_REST, R_SPHERICAL, R_MIDDLE, R_SYMMETRIC, R_MAJOR, R_MINOR, R_SEPARATRIX = range(7)

# Parameter vector layout, per body
P_MODE, P_WS, P_LAM, P_U0, P_KQ, P_K2, P_M1, P_N2, P_JH, P_J0 = range(10)
P_KMOM, P_RATE0, P_KAPPA, P_BETA, P_MAJOR, P_LEVELS, P_LSCALE = range(10, 17)
N_PAR = 17
# symmetric / uniform bodies reuse slots
P_SPIN, P_PSIDOT, P_PHIDOT = P_LAM, P_U0, P_KQ
P_RATE = P_LAM

#: ``|D|`` at most this times its two terms is the double-double rounding level:
#: the state is exactly on the separatrix (``FreeRigidBody.SEPARATRIX_RTOL``).
SEP_RTOL = 2.0**-100

_SPLIT = 134217729.0  # 2^27 + 1 (Dekker)


# ---------------------------------------------------------------------------
# Error-free transformations and double-double arithmetic
# ---------------------------------------------------------------------------


@njit(cache=True)
def two_sum(a, b):  # pragma: no cover - compiled
    """``(s, e)`` with ``s = fl(a + b)`` and ``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(cache=True)
def two_prod(a, b):  # pragma: no cover - compiled
    """``(p, e)`` with ``p = fl(a b)`` and ``a b = p + e`` exactly (Dekker's split;
    no FMA needed, no over/underflow for the scaled data used here)."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@njit(cache=True)
def _dd_norm(h, lo):  # pragma: no cover - compiled
    s = h + lo
    return s, lo - (s - h)


@njit(cache=True)
def dd_mul(ah, al, bh, bl):  # pragma: no cover - compiled
    """Double-double product (relative error ~ 2^-104)."""
    p, e = two_prod(ah, bh)
    e += ah * bl + al * bh
    return _dd_norm(p, e)


@njit(cache=True)
def dd_add(ah, al, bh, bl):  # pragma: no cover - compiled
    """Double-double sum (relative error ~ 2^-104 of ``|a| + |b|``)."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    e += t
    s, e = _dd_norm(s, e)
    e += f
    return _dd_norm(s, e)


@njit(cache=True)
def discriminant_term(ia, ib, w):  # pragma: no cover - compiled
    """``I_a (I_a - I_b) w^2`` as a double-double ``(hi, lo)``: the difference by
    two-sum and ``w^2`` by two-product are exact, the two products are double-double."""
    dh, dl = two_sum(ia, -ib)
    ph, pl = dd_mul(ia, 0.0, dh, dl)
    sh, sl = two_prod(w, w)
    return dd_mul(ph, pl, sh, sl)


# ---------------------------------------------------------------------------
# Per point: elliptic state
# ---------------------------------------------------------------------------


@njit(cache=True, inline="always")
def elliptic_omega(
    tau, lam, u0, kq, k2, m1, n2, levels, lscale, ks, kps, separatrix, ai, am, aj, want_j
):  # pragma: no cover - compiled
    """``(w_i, w_m, w_j, kk, J(r))`` at scaled time ``tau``: ``w_i = a_i dn(u)``,
    ``w_m = a_m sn(u)``, ``w_j = a_j cn(u)``, ``u = lam tau + u0 = 2 kk K + r``, and
    ``J(r) = int_0^r sn^2 / (1 + n sn^2)`` when ``want_j`` (else 0); the Landen table
    ``ks, kps, levels, lscale`` of ``k2``, ``m1 = 1 - k2`` from :func:`landen_fill`."""
    u = lam * tau + u0
    if separatrix:
        # k = 1: sn = tanh, cn = dn = sech; J(u) in closed form.
        kk = 0.0
        sn = math.tanh(u)
        e = math.exp(-abs(u))
        cn = 2.0 * e / (1.0 + e * e)
        dn = cn
        sgn = 1.0
        if n2 > 0.0:
            sq = math.sqrt(n2)
            jr = (u - math.atan(sq * sn) / sq) / (1.0 + n2)
        else:
            jr = u - sn
    else:
        kk, r = reduce_argument(u, kq)
        sgn = 1.0 - 2.0 * (kk - 2.0 * math.floor(0.5 * kk))
        sn, cn, dn = jacobi_reduced(r, ks, kps, levels, lscale, k2, m1)
        # J(r) = int_0^r sn^2 / (1 + n sn^2) = sn^3 R_J(cn^2, dn^2, 1, 1 + n sn^2) / 3
        sn2 = sn * sn
        if sn2 == 0.0 or not want_j:
            jr = 0.0
        else:
            jr = sn * sn2 * carlson_rj(cn * cn, dn * dn, 1.0, 1.0 + n2 * sn2) / 3.0
    return ai * dn, am * sgn * sn, aj * sgn * cn, kk, jr


@njit(cache=True, inline="always")
def _elliptic_point(tau, par, idx, inertia, amp, qs, qp, ks, kps, want_q):  # pragma: no cover
    """Principal-axes ``w`` (3 floats), attitude ``q`` (4 floats), ``J(u)`` at scaled ``tau``."""
    i, m, j = idx[0], idx[1], idx[2]
    wi, wm, wj, kk, jr = elliptic_omega(
        tau, par[P_LAM], par[P_U0], par[P_KQ], par[P_K2], par[P_M1], par[P_N2],
        int(par[P_LEVELS]), par[P_LSCALE], ks, kps, par[P_MODE] == SEPARATRIX, amp[i], amp[m],
        amp[j], want_q,
    )  # fmt: skip
    w0, w1, w2 = _place(i, m, wi, wm, wj)
    if not want_q:
        return w0, w1, w2, 1.0, 0.0, 0.0, 0.0, 0.0
    q0, q1, q2, q3, jval = elliptic_attitude(
        tau, wi, wm, wj, kk, jr, i, m, j, inertia, par[P_KMOM], par[P_RATE0], par[P_KAPPA],
        par[P_BETA], par[P_LAM], par[P_MAJOR] > 0.5, par[P_JH], par[P_J0], qs, qp,
    )  # fmt: skip
    return w0, w1, w2, q0, q1, q2, q3, jval


@njit(cache=True, inline="always")
def elliptic_attitude(
    tau, wi, wm, wj, kk, jr, i, m, j, inertia, kmom, rate0, kappa, beta, lam, major, jh, j0, qs, qp
):  # pragma: no cover - compiled
    """``(q_0, q_1, q_2, q_3, J(u))``: the attitude ``q = qs o Rzxz o qp`` (principal
    body -> space) at scaled ``tau`` of an elliptic motion (theory §10), from the
    point ``wi, wm, wj, kk, jr`` of :func:`elliptic_omega` (``want_j``) and the
    constants of :func:`elliptic_constants`; ``J(u) = kk J_h + J(r)``."""
    jval = kk * jh + jr
    # the two precession angles are cheap and finite: a select, not a branch (on JAX a
    # branch doubles the traced paths)
    psi = pick(
        major,
        rate0 * tau + kappa * beta * (jval - j0) / lam,
        rate0 * tau + kappa * (tau - beta * (jval - j0) / lam),
    )
    # z-x-z Euler angles (about axis j) of the body unit momentum; q = qs o Rzxz o qp.
    # (jx, jy) = (j + 1, j + 2) mod 3 is (i, m) or (m, i).
    xi, xm = inertia[i] * wi / kmom, inertia[m] * wm / kmom
    first = (j + 1) % 3 == i
    x = pick(first, xi, xm)
    y = pick(first, xm, xi)
    z = inertia[j] * wj / kmom
    st = math.hypot(x, y)
    big = math.sqrt(0.5 * (1.0 + abs(z)))
    small = st / (2.0 * big)
    ch = pick(z >= 0.0, big, small)
    sh = pick(z >= 0.0, small, big)
    ph = math.atan2(x, y)
    ha = 0.5 * (psi + ph)
    hb = 0.5 * (psi - ph)
    z0, z1, z2, z3 = ch * math.cos(ha), sh * math.cos(hb), sh * math.sin(hb), ch * math.sin(ha)
    r0, r1, r2, r3 = qmul(qs[0], qs[1], qs[2], qs[3], z0, z1, z2, z3)
    q0, q1, q2, q3 = qmul(r0, r1, r2, r3, qp[0], qp[1], qp[2], qp[3])
    return q0, q1, q2, q3, jval


@njit(cache=True, inline="always")
def elliptic_offset(
    wi, wm, wj, kk, jr, i, m, j, inertia, kmom, rate0, kappa, beta, lam, major, jh, q0
):  # pragma: no cover - compiled
    """``(qs_0, qs_1, qs_2, qs_3, J0, qp_0, qp_1, qp_2, qp_3)``: the constants of
    :func:`elliptic_attitude` with ``q(0) = q0``, from the point of
    :func:`elliptic_omega` at ``tau = 0``."""
    p0, p1, p2, p3 = axis_permutation(j)
    # J(u0) and the Euler quaternion Rz(psi0) Rx(theta0) Rz(phi0) at t = 0 (with J0 = 0,
    # psi0 = +-kappa beta J(u0) / lam); then J0 = J(u0) and psi0 -> 0.
    one = (1.0, 0.0, 0.0, 0.0)
    z0, z1, z2, z3, j0 = elliptic_attitude(
        0.0, wi, wm, wj, kk, jr, i, m, j, inertia, kmom, rate0, kappa, beta, lam, major, jh,
        0.0, one, one,
    )  # fmt: skip
    psi0 = kappa * beta * j0 / lam
    psi0 = pick(major, psi0, -psi0)
    z0, z1, z2, z3 = qmul(math.cos(0.5 * psi0), 0.0, 0.0, -math.sin(0.5 * psi0), z0, z1, z2, z3)
    # qs = q0 o qp~ o qz0~
    r0, r1, r2, r3 = qmul(q0[0], q0[1], q0[2], q0[3], p0, -p1, -p2, -p3)
    s0, s1, s2, s3 = qmul(r0, r1, r2, r3, z0, -z1, -z2, -z3)
    return s0, s1, s2, s3, j0, p0, p1, p2, p3


@njit(cache=True, inline="always")
def axis_permutation(j):  # pragma: no cover - compiled
    """The quaternion taking ``(x, y, z) = (e_{j+1}, e_{j+2}, e_j)``: a rotation by -120,
    +120, 0 deg about ``(1, 1, 1)`` for ``j = 0, 1, 2``."""
    c = pick(j == 2, 1.0, 0.5)
    s = pick(j == 0, -0.5, pick(j == 1, 0.5, 0.0))
    return c, s, s, s


@njit(cache=True, inline="always")
def _place(i, m, wi, wm, wj):  # pragma: no cover - compiled
    """``(w_0, w_1, w_2)`` from the components along axes ``i``, ``m`` and the third."""
    # selects (cheap, all defined): on JAX branches would make 27 traced paths
    out0 = pick(i == 0, wi, pick(m == 0, wm, wj))
    out1 = pick(i == 1, wi, pick(m == 1, wm, wj))
    out2 = pick(i == 2, wi, pick(m == 2, wm, wj))
    return out0, out1, out2


@njit(cache=True, inline="always")
def _axis_q(ax, angle):  # pragma: no cover - compiled
    h = 0.5 * angle
    s = math.sin(h)
    return math.cos(h), s * ax[0], s * ax[1], s * ax[2]


@njit(cache=True, inline="always")
def symmetric_spin(i_s, i_p, w_s):  # pragma: no cover - compiled
    """``phi' = (I_s - I_p) w_s / I_p``: the rate at which ``w`` turns about the symmetry
    axis ``s`` of a symmetric body (equatorial moment ``I_p``) in body axes."""
    return (i_s - i_p) * w_s / i_p


@njit(cache=True, inline="always")
def symmetric_omega(ax, ay, spin, tau):  # pragma: no cover - compiled
    """The equatorial components ``(w_x, w_y)`` of a symmetric body at scaled ``tau``:
    ``(a_x, a_y)`` turned by ``spin tau`` (``x, y`` the axes after ``s``, cyclically)."""
    ang = spin * tau
    c, sn = math.cos(ang), math.sin(ang)
    return ax * c - ay * sn, ax * sn + ay * c


# ---------------------------------------------------------------------------
# Setup (per body)
# ---------------------------------------------------------------------------


@njit(cache=True)
def setup(mom, w0, q0, par, idx, amp, vec, qa, qb, ks, kps, info):  # pragma: no cover
    """Constants of the exact motion of each body (scaled data, principal axes).

    Inputs ``mom`` (N, 3) moments (max ~ 1), ``w0`` (N, 3) (``|w0| ~ 1``), ``q0``
    (N, 4) principal-axes attitude. Fills ``par`` (N, N_PAR), ``idx`` (N, 3),
    ``amp`` (N, 3), ``vec`` (N, 3), ``qa``, ``qb`` (N, 4), the Landen tables and
    ``info`` (N, 5): regime code, period, precession per period, ``1 - k^2``, and
    ``|D| / (|t_a| + |t_c|)`` (the relative size of the discriminant).
    """
    n = mom.shape[0]
    for b in range(n):
        im = mom[b]
        w = w0[b]
        code, i, m, j, d, rel, kmom = classify(im, w)
        pb = par[b]
        pb[:] = 0.0
        info[b, 0] = code
        info[b, 1] = math.inf
        info[b, 2] = math.nan
        info[b, 3] = math.nan
        info[b, 4] = rel
        if code == R_REST or code == R_SPHERICAL or code == R_MIDDLE:
            # uniform rotation about a fixed axis
            _setup_uniform(b, w, q0[b], pb, amp, vec, qa)
        elif code == R_SYMMETRIC:
            s, ip = i, im[m]
            idx[b, 0] = s
            pb[P_MODE] = SYMMETRIC
            spin = symmetric_spin(im[s], ip, w[s])
            pb[P_SPIN] = spin
            pb[P_PSIDOT] = kmom / ip
            pb[P_PHIDOT] = -spin
            amp[b, :] = w
            vec[b, 0], vec[b, 1], vec[b, 2] = momentum_direction(im, w, q0[b], kmom)
            qa[b, :] = q0[b]
            if spin != 0.0:
                info[b, 1] = 2.0 * math.pi / abs(spin)
                info[b, 2] = pb[P_PSIDOT] * info[b, 1]
        else:
            sep = code == R_SEPARATRIX
            _setup_elliptic(
                b, i, m, j, d, sep, im, w, q0[b], kmom, pb, idx, amp, qa, qb, ks, kps, info
            )


@njit(cache=True)
def classify(im, w):  # pragma: no cover - compiled
    """``(code, i, m, j, D, |D| / size, |K|)`` of a body with (scaled) moments ``im`` and
    angular velocity ``w`` (indexable by 0, 1, 2): the regime code ``R_*``; for an
    elliptic motion (major, minor, separatrix) the encircled axis ``i``, the middle
    one ``m`` and the other extreme ``j``; for a symmetric body ``i`` the symmetry
    axis and ``(m, j)`` the next two cyclically. ``D = K^2 - 2 T B`` in double-double
    arithmetic (its leading part; 0 on the separatrix), and ``|D| / (|t_a| + |t_c|)``
    (NaN for equal moments)."""
    ka0, ka1, ka2 = im[0] * w[0], im[1] * w[1], im[2] * w[2]
    kmom = math.sqrt(ka0 * ka0 + ka1 * ka1 + ka2 * ka2)
    e01, e12, e20 = im[0] == im[1], im[1] == im[2], im[2] == im[0]
    # | and &, not or/and: one decision each (on JAX each operand would be a branch)
    if (kmom == 0.0) | (e01 & e12):
        return pick(kmom == 0.0, R_REST, R_SPHERICAL), 0, 1, 2, 0.0, math.nan, kmom
    if e01 | e12 | e20:
        s = pick(e01, 2, pick(e12, 0, 1))
        return R_SYMMETRIC, s, (s + 1) % 3, (s + 2) % 3, 0.0, math.nan, kmom
    # distinct moments: a = major, c = minor, bm = middle axis
    ia, ic = _extremes(im[0], im[1], im[2])
    ibm = 3 - ia - ic
    # D = K^2 - 2 T B = I_a (I_a - I_b) w_a^2 + I_c (I_c - I_b) w_c^2 (double-double)
    tah, tal = discriminant_term(im[ia], im[ibm], w[ia])
    tch, tcl = discriminant_term(im[ic], im[ibm], w[ic])
    dh, dl = dd_add(tah, tal, tch, tcl)
    size = abs(tah) + abs(tch)
    rel = abs(dh) / pick(size > 0.0, size, 1.0)  # (dh = 0 if size = 0)
    if abs(dh) <= SEP_RTOL * size:
        if size == 0.0:  # permanent rotation about the middle axis
            return R_MIDDLE, ia, ibm, ic, dh, rel, kmom
        return R_SEPARATRIX, ia, ibm, ic, 0.0, rel, kmom
    if dh > 0.0:
        return R_MAJOR, ia, ibm, ic, dh, rel, kmom
    return R_MINOR, ic, ibm, ia, dh, rel, kmom


@njit(cache=True)
def _extremes(a0, a1, a2):  # pragma: no cover - compiled
    """``(argmax, argmin)`` of three distinct numbers."""
    # selects, not branches: on JAX each branch would double the traced paths
    ia = pick((a0 > a1) & (a0 > a2), 0, pick(a1 > a2, 1, 2))
    ic = pick((a0 < a1) & (a0 < a2), 0, pick(a1 < a2, 1, 2))
    return ia, ic


@njit(cache=True)
def _setup_uniform(b, w, q0, pb, amp, vec, qa):  # pragma: no cover - compiled
    pb[P_MODE] = UNIFORM
    amp[b, :] = w
    pb[P_RATE], vec[b, 0], vec[b, 1], vec[b, 2] = spin_axis(w)
    qa[b, :] = q0


@njit(cache=True, inline="always")
def spin_axis(w):  # pragma: no cover - compiled
    """``(|w|, e_0, e_1, e_2)``: the rate and axis of a uniform rotation (``e_z`` at rest)."""
    wn = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    # a select: the division by zero of the resting lane is discarded
    on = wn > 0.0
    d = pick(on, wn, 1.0)
    return wn, pick(on, w[0] / d, 0.0), pick(on, w[1] / d, 0.0), pick(on, w[2] / d, 1.0)


@njit(cache=True, inline="always")
def momentum_direction(im, w, q, kmom):  # pragma: no cover - compiled
    """``khat = q (J w) q~ / K``: the fixed direction of the angular momentum in space."""
    ka0, ka1, ka2 = im[0] * w[0], im[1] * w[1], im[2] * w[2]
    a0, a1, a2, a3 = qmul(q[0], q[1], q[2], q[3], 0.0, ka0, ka1, ka2)
    _, v1, v2, v3 = qmul(a0, a1, a2, a3, q[0], -q[1], -q[2], -q[3])
    return v1 / kmom, v2 / kmom, v3 / kmom


@njit(cache=True, inline="always")
def uniform_attitude(vec, rate, qa, tau):  # pragma: no cover - compiled
    """``q = qa o Rot(e, |w| tau)``: a uniform rotation about the body axis ``e``."""
    c0, c1, c2, c3 = _axis_q(vec, rate * tau)
    return qmul(qa[0], qa[1], qa[2], qa[3], c0, c1, c2, c3)


@njit(cache=True, inline="always")
def symmetric_attitude(vec, psidot, phidot, qa, s, tau):  # pragma: no cover - compiled
    """``q = Rot(khat, psi' tau) qa Rot(e_s, phi' tau)``: regular precession about the
    momentum ``khat`` (space) and spin about the symmetry axis ``s`` (body)."""
    a0, a1, a2, a3 = _axis_q(vec, psidot * tau)
    hp = 0.5 * phidot * tau
    r0, r1, r2, r3 = qmul(a0, a1, a2, a3, qa[0], qa[1], qa[2], qa[3])
    return qaxis(r0, r1, r2, r3, math.cos(hp), math.sin(hp), s)


@njit(cache=True)
def elliptic_constants(i, m, j, d, separatrix, mom, w, kmom):  # pragma: no cover - compiled
    """Constants of the elliptic motion about axis ``i`` (``m`` middle, ``j`` the other
    extreme; ``d = D`` the discriminant, ``separatrix`` when ``k = 1``) for scaled
    moments ``mom`` and ``w`` (indexable by ``i, m, j``) and ``kmom = |K|``:
    ``(a_i, a_m, a_j, lam, n, beta, major, kappa, rate0, 1 - k^2, k^2, K, u0, J_h)``
    (module notes of :mod:`poinsot.dynamics.free_body`; ``J_h = 2 R_J(0, m1, 1, 1 + n)
    / 3`` is 0 and ``K`` infinite on the separatrix)."""
    ii, im, ij = mom[i], mom[m], mom[j]
    # 2 T I_i - K^2 and K^2 - 2 T I_j as sums of same-sign terms (no cancellation)
    g_i = mom[m] * (ii - mom[m]) * w[m] ** 2 + mom[j] * (ii - mom[j]) * w[j] ** 2
    mg_j = mom[i] * (mom[i] - ij) * w[i] ** 2 + mom[m] * (mom[m] - ij) * w[m] ** 2
    ai2 = mg_j / (ii * (ii - ij))
    aj2 = g_i / (ij * (ii - ij))
    am2 = g_i / (im * (ii - im))
    lam = math.sqrt((ii - im) * mg_j / (ii * im * ij))
    n2 = ij * g_i / (ii * mg_j)
    beta = (im * im * am2) / (ii * ii * ai2)
    # the elliptic integrals first, then the signs (on JAX, the paths of the signs
    # then share one trace of the integrals: poinsot.jax notes)
    if separatrix:
        m1, k2, kq, jh, rf0 = 0.0, 1.0, math.inf, 0.0, 0.0
    else:
        # 1 - k^2 = (I_i - I_j) D / ((I_i - I_m)(K^2 - 2 T I_j)), D exact to a few ulp
        m1 = (ii - ij) * d / ((ii - im) * mg_j)
        k2 = min((im - ij) * g_i / ((ii - im) * mg_j), 1.0)  # an ulp above 1 by rounding
        kq = complete_k(m1)
        jh = (2.0 / 3.0) * carlson_rj(0.0, m1, 1.0, 1.0 + n2)
        # the phase u0 = F(am0): R_F of (cn0^2, dn0^2) (the signs do not enter)
        rf0 = 0.0
        if am2 != 0.0:
            sn0, cn0 = w[m] / math.sqrt(am2), w[j] / math.sqrt(aj2)
            cn0 = cn0 / math.hypot(sn0, cn0)
            dn0 = w[i] / math.sqrt(ai2)
            rf0 = carlson_rf(cn0 * cn0, dn0 * dn0, 1.0)
    sigma = pick(i == (m + 1) % 3, 1.0, -1.0)
    s_i = math.copysign(1.0, w[i])
    s_j = pick(separatrix, math.copysign(1.0, w[j]), 1.0)
    s_m = sigma * math.copysign(1.0, ii - ij) * s_i * s_j
    ai = s_i * math.sqrt(ai2)
    am = s_m * math.sqrt(am2)
    aj = s_j * math.sqrt(aj2)
    major = ii > ij
    kappa = kmom * pick(major, 1.0 / im - 1.0 / ii, 1.0 / ii - 1.0 / im)
    rate0 = kmom / pick(major, ii, im)
    if separatrix:
        u0 = math.asinh((w[m] / am) / (w[i] / ai))
    elif am2 == 0.0:
        u0 = 0.0
    else:
        sn0, cn0 = w[m] / am, w[j] / aj
        rho = math.hypot(sn0, cn0)
        sn0, cn0 = sn0 / rho, cn0 / rho
        f = sn0 * rf0
        u0 = f if cn0 >= 0.0 else math.copysign(2.0 * kq, sn0) - f
    return ai, am, aj, lam, n2, beta, major, kappa, rate0, m1, k2, kq, u0, jh


@njit(cache=True)
def _setup_elliptic(
    b, i, m, j, d, separatrix, mom, w, q0, kmom, pb, idx, amp, qa, qb, ks, kps, info
):  # pragma: no cover - compiled
    ii, ij = mom[i], mom[j]
    idx[b, 0], idx[b, 1], idx[b, 2] = i, m, j
    pb[P_MODE] = SEPARATRIX if separatrix else ELLIPTIC
    ai, am, aj, lam, n2, beta, major, kappa, rate0, m1, k2, kq, u0, jh = elliptic_constants(
        i, m, j, d, separatrix, mom, w, kmom
    )
    amp[b, i], amp[b, m], amp[b, j] = ai, am, aj
    pb[P_LAM] = lam
    pb[P_N2] = n2
    pb[P_BETA] = beta
    pb[P_MAJOR] = 1.0 if major else 0.0
    pb[P_KMOM] = kmom
    pb[P_KAPPA] = kappa
    pb[P_RATE0] = rate0
    pb[P_M1], pb[P_K2], pb[P_KQ], pb[P_U0] = m1, k2, kq, u0
    if separatrix:
        pb[P_LEVELS] = -1.0
        info[b, 3] = 0.0
    else:
        lv, sc = landen_fill(k2, m1, ks[b], kps[b])
        pb[P_LEVELS] = lv
        pb[P_LSCALE] = sc
        info[b, 3] = m1
        pb[P_JH] = jh
        period = 4.0 * kq / lam
        dj = 2.0 * jh
        if major:
            extra = pb[P_KAPPA] * pb[P_BETA] * dj / lam
        else:
            extra = pb[P_KAPPA] * (period - pb[P_BETA] * dj / lam)
        info[b, 1] = period
        # Landau's convention (Euler z-axis = the encircled axis i): differs by 2 pi
        info[b, 2] = pb[P_RATE0] * period + extra + 2.0 * math.pi * math.copysign(1.0, ii - ij)
    wi, wm, wj, kk, jr = elliptic_omega(
        0.0, lam, u0, kq, k2, m1, n2, int(pb[P_LEVELS]), pb[P_LSCALE], ks[b], kps[b], separatrix,
        ai, am, aj, True,
    )  # fmt: skip
    s0, s1, s2, s3, j0, p0, p1, p2, p3 = elliptic_offset(
        wi, wm, wj, kk, jr, i, m, j, mom, kmom, rate0, kappa, beta, lam, major, pb[P_JH], q0
    )
    pb[P_J0] = j0
    qa[b, 0], qa[b, 1], qa[b, 2], qa[b, 3] = s0, s1, s2, s3
    qb[b, 0], qb[b, 1], qb[b, 2], qb[b, 3] = p0, p1, p2, p3


# ---------------------------------------------------------------------------
# The same steps per lane, for the array executors that trace them (poinsot.jax)
# ---------------------------------------------------------------------------


def setup_lanes(im, w):  # plain Python: run by poinsot.jax with branches as selects
    """Per body, the constants :func:`state_lanes` needs: :func:`setup` without the
    attitude, returned instead of stored (``im``, ``w`` scaled moments and angular
    velocity, indexable by 0, 1, 2). ``(code, i, m, j, a_i, a_m, a_j, lam, u0, K, k^2,
    1 - k^2, n, L, scale, ks, kps, spin, |K|, beta, major, kappa, rate0, J_h)``. Every
    regime's constants are computed before the regime is chosen (on JAX each is then
    traced once)."""
    code, i, m, j, d, rel, kmom = classify(im, w)
    ell = elliptic_constants(i, m, j, d, code == R_SEPARATRIX, im, w, kmom)
    ai, am, aj, lam, n2, beta, major, kappa, rate0, m1, k2, kq, u0, jh = ell
    lv, sc, ks, kps = landen_table(k2, m1)
    spin = symmetric_spin(im[i], im[m], w[i])
    att = (kmom, beta, major, kappa, rate0, jh)  # of the attitude (attitude_setup_lanes)
    if code == R_MAJOR or code == R_MINOR or code == R_SEPARATRIX:
        return (code, i, m, j, ai, am, aj, lam, u0, kq, k2, m1, n2, lv, sc, ks, kps, 0.0) + att
    if code == R_SYMMETRIC:
        return (
            code, i, m, j, w[i], w[m], w[j], 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0, 1.0, ks, kps, spin
        ) + att  # fmt: skip
    return (
        code, 0, 1, 2, w[0], w[1], w[2], 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0, 1.0, ks, kps, 0.0
    ) + att  # fmt: skip


def attitude_setup_lanes(im, w, q, c):  # plain Python: run by poinsot.jax as selects
    """Per body, the attitude constants :func:`state_lanes` needs, from the constants
    ``c`` of :func:`setup_lanes` and the initial attitude ``q`` (principal body ->
    space, 4 lanes): :func:`setup`'s ``qa`` and ``qb`` (elliptic: the offsets ``qs``,
    ``qp`` of :func:`elliptic_attitude`; else ``q`` and the identity), ``vec`` (the
    momentum direction, or the spin axis), ``J0`` and the rate of the turn about
    ``vec`` (``psi'`` or ``|w|``): 13 lanes."""
    code, i, m, j, ai, am, aj, lam, u0, kq, k2, m1, n2, lv, sc, ks, kps, spin = c[:18]
    kmom, beta, major, kappa, rate0, jh = c[18:]
    sep = code == R_SEPARATRIX
    wi, wm, wj, kk, jr = elliptic_omega(
        0.0, lam, u0, kq, k2, m1, n2, lv, sc, ks, kps, sep, ai, am, aj, True
    )
    ell = elliptic_offset(
        wi, wm, wj, kk, jr, i, m, j, im, kmom, rate0, kappa, beta, lam, major, jh, q
    )
    k0, k1, k2_ = momentum_direction(im, w, q, kmom)
    wn, e0, e1, e2 = spin_axis(w)
    if code == R_MAJOR or code == R_MINOR or code == R_SEPARATRIX:
        return ell[:4] + ell[5:] + (0.0, 0.0, 1.0, ell[4], 0.0)
    one = (1.0, 0.0, 0.0, 0.0)
    if code == R_SYMMETRIC:
        return (q[0], q[1], q[2], q[3]) + one + (k0, k1, k2_, 0.0, kmom / im[m])
    return (q[0], q[1], q[2], q[3]) + one + (e0, e1, e2, 0.0, wn)


def state_lanes(tau, c, a, im, want_q):  # plain Python: run by poinsot.jax as selects
    """``(w_0, w_1, w_2)`` and, if ``want_q``, ``(q_0, q_1, q_2, q_3)`` at scaled time
    ``tau`` of a body with the constants ``c`` of :func:`setup_lanes` and ``a`` of
    :func:`attitude_setup_lanes` (``None`` without ``want_q``), scaled moments ``im``:
    :func:`evaluate` in principal axes, the attitude principal body -> space."""
    code, i, m, j, ai, am, aj, lam, u0, kq, k2, m1, n2, lv, sc, ks, kps, spin = c[:18]
    kmom, beta, major, kappa, rate0, jh = c[18:]
    sep = code == R_SEPARATRIX
    wi, wm, wj, kk, jr = elliptic_omega(
        tau, lam, u0, kq, k2, m1, n2, lv, sc, ks, kps, sep, ai, am, aj, want_q
    )
    wxx, wyy = symmetric_omega(am, aj, spin, tau)
    qe = qs = qu = ()
    if want_q:
        qa, qb, vec, j0, rate = a[0:4], a[4:8], a[8:11], a[11], a[12]
        qe = elliptic_attitude(
            tau, wi, wm, wj, kk, jr, i, m, j, im, kmom, rate0, kappa, beta, lam, major, jh, j0,
            qa, qb,
        )[:4]  # fmt: skip
        qs = symmetric_attitude(vec, rate, -spin, qa, i, tau)
        qu = uniform_attitude(vec, rate, qa, tau)
    if code == R_MAJOR or code == R_MINOR or code == R_SEPARATRIX:
        return _place(i, m, wi, wm, wj) + qe
    if code == R_SYMMETRIC:
        return _place(i, m, ai, wxx, wyy) + qs
    return (ai, am, aj) + qu


# ---------------------------------------------------------------------------
# Evaluation (bodies x times)
# ---------------------------------------------------------------------------


@njit(cache=True)
def evaluate(
    t, par, idx, mom, amp, vec, qa, qb, qv, ks, kps, want_q, w_out, q_out
):  # pragma: no cover
    """``w_out[b, p]`` (given body axes, rad/s) and ``q_out[b, p]`` (body -> space) for
    bodies ``b`` at times ``t[p]`` (s). ``qv`` (N, 4): principal -> given body axes.
    If ``want_q`` is false only ``w_out`` is filled."""
    nb = par.shape[0]
    nt = t.shape[0]
    for b in range(nb):
        pb = par[b]
        ws = pb[P_WS]
        mode = pb[P_MODE]
        v = qv[b]
        for p in range(nt):
            tau = ws * t[p]
            q0 = q1 = q2 = q3 = 0.0
            if mode == ELLIPTIC or mode == SEPARATRIX:
                wx, wy, wz, q0, q1, q2, q3, _ = _elliptic_point(
                    tau, pb, idx[b], mom[b], amp[b], qa[b], qb[b], ks[b], kps[b], want_q
                )
            elif mode == SYMMETRIC:
                # w_perp turns about e_s at the rate spin; R = Rot(K, psi' t) R0 Rot(e_s, phi' t)
                s = idx[b, 0]
                x, y = (s + 1) % 3, (s + 2) % 3
                wxx, wyy = symmetric_omega(amp[b, x], amp[b, y], pb[P_SPIN], tau)
                wx, wy, wz = _place(s, x, amp[b, s], wxx, wyy)
                if want_q:
                    q0, q1, q2, q3 = symmetric_attitude(
                        vec[b], pb[P_PSIDOT], pb[P_PHIDOT], qa[b], s, tau
                    )
            else:
                wx, wy, wz = amp[b, 0], amp[b, 1], amp[b, 2]
                if want_q:
                    q0, q1, q2, q3 = uniform_attitude(vec[b], pb[P_RATE], qa[b], tau)
            # to the given body axes: w_given = qv w qv~, q_given = q o qv~
            if v[0] == 1.0:
                w_out[b, p, 0], w_out[b, p, 1], w_out[b, p, 2] = ws * wx, ws * wy, ws * wz
                if want_q:
                    q_out[b, p, 0], q_out[b, p, 1], q_out[b, p, 2], q_out[b, p, 3] = q0, q1, q2, q3
            else:
                a0, a1, a2, a3 = qmul(v[0], v[1], v[2], v[3], 0.0, wx, wy, wz)
                _, r1, r2, r3 = qmul(a0, a1, a2, a3, v[0], -v[1], -v[2], -v[3])
                w_out[b, p, 0], w_out[b, p, 1], w_out[b, p, 2] = ws * r1, ws * r2, ws * r3
                if want_q:
                    r0, r1, r2, r3 = qmul(q0, q1, q2, q3, v[0], -v[1], -v[2], -v[3])
                    q_out[b, p, 0], q_out[b, p, 1], q_out[b, p, 2], q_out[b, p, 3] = r0, r1, r2, r3


__all__ = [
    "setup",
    "evaluate",
    "elliptic_constants",
    "elliptic_omega",
    "classify",
    "setup_lanes",
    "attitude_setup_lanes",
    "state_lanes",
    "elliptic_attitude",
    "symmetric_spin",
    "symmetric_omega",
    "LMAX",
    "N_PAR",
    "REGIMES",
    "two_sum",
    "two_prod",
]
