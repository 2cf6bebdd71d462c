"""Compiled stepping kernels for :func:`poinsot.dynamics.simulate` (private).

This module imports numba at the top, so it is only imported lazily, from inside
``simulate``; ``import poinsot`` never loads it. Each kernel loops over bodies
and steps with scalar arithmetic only (no allocation inside the loops).

State per body: the attitude ``q`` (body -> space, scalar-first unit
quaternion) and the body angular momentum ``m = J w``; ``W = J^-1`` is the
inverse inertia tensor in body axes and ``M`` a constant body torque.

Status codes returned by the kernels: 0 = ok, 1 = the implicit step did not
converge, 2 = the state became non-finite.

The small formulas (Euler's momentum rate, quaternion products, normalisation)
come from :mod:`poinsot._numba_helpers`, inlined; the cache stamp includes that
file (:func:`poinsot._numba_cache.depends_on`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _numba_helpers as nh
from .._jit import njit
from .._numba_cache import depends_on

# the kernels inline helpers of another file: let their cache see its edits
depends_on(__file__, nh)


@njit(cache=True, nogil=True)
def midpoint(q, m, W, M, t, nsub, coef, cancel, progress):
    """Implicit midpoint (Lie-Poisson) + Cayley attitude for N bodies.

    q (N, 4), m (N, 3), W (NW, 3, 3), M (NM, 3) with NW, NM in {1, N};
    t (n,), nsub (n-1,) substeps per interval, coef the composition
    coefficients of one step (``[1.0]`` for the plain midpoint rule). Returns (Q, MO, status, body,
    k, iters): outputs (n, N, 4), (n, N, 3), the status code, and where it
    failed (body index, last output index reached) or the most Newton
    iterations taken by any step. The helpers it calls are inlined and its
    cache stamp covers their file (see the module notes). ``cancel[0] != 0`` (Ctrl-C,
    from another thread) stops it with status 3; ``progress[0]`` counts the output
    intervals done (progress). Without the GIL (``poinsot._progress.run_compiled``).
    """
    n = t.shape[0]
    N = q.shape[0]
    Q = np.empty((n, N, 4))
    MO = np.empty((n, N, 3))
    worst = 0
    nc = coef.shape[0]
    for i in range(N):
        iw = i if W.shape[0] > 1 else 0
        im = i if M.shape[0] > 1 else 0
        w00, w01, w02 = W[iw, 0, 0], W[iw, 0, 1], W[iw, 0, 2]
        w10, w11, w12 = W[iw, 1, 0], W[iw, 1, 1], W[iw, 1, 2]
        w20, w21, w22 = W[iw, 2, 0], W[iw, 2, 1], W[iw, 2, 2]
        M0, M1, M2 = M[im, 0], M[im, 1], M[im, 2]
        q0, q1, q2, q3 = q[i, 0], q[i, 1], q[i, 2], q[i, 3]
        m0, m1, m2 = m[i, 0], m[i, 1], m[i, 2]
        Q[0, i, 0] = q0
        Q[0, i, 1] = q1
        Q[0, i, 2] = q2
        Q[0, i, 3] = q3
        MO[0, i, 0] = m0
        MO[0, i, 1] = m1
        MO[0, i, 2] = m2
        for k in range(t.shape[0] - 1):
            progress[0] = i * (n - 1) + k
            ns = nsub[k]
            hk = (t[k + 1] - t[k]) / ns
            for s_ in range(ns * nc):
                if nh.cancelled(cancel):
                    return Q, MO, 3, i, k, worst
                # a composition stage of length coef[j] * hk (one stage for order 2)
                h = hk * coef[s_ % nc]
                h2 = 0.5 * h
                # first guess of the midpoint momentum m(t + h/2), error O(h^3):
                # y = m + h/4 f(m), x = m + h/2 f(y), f(m) = m x W m + M
                o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, m0, m1, m2)
                h4 = 0.5 * h2
                f0, f1, f2 = nh.euler_momentum_rate(m0, m1, m2, o0, o1, o2, M0, M1, M2)
                y0 = m0 + h4 * f0
                y1 = m1 + h4 * f1
                y2 = m2 + h4 * f2
                o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, y0, y1, y2)
                f0, f1, f2 = nh.euler_momentum_rate(y0, y1, y2, o0, o1, o2, M0, M1, M2)
                x0 = m0 + h2 * f0
                x1 = m1 + h2 * f1
                x2 = m2 + h2 * f2
                # Newton on the midpoint momentum, stopped by the one rule of every
                # midpoint path (poinsot._numba_helpers.midpoint_newton_done)
                prev = math.inf
                it = 0
                while True:
                    it += 1
                    o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, x0, x1, x2)
                    # residual F(x) = x - m - h/2 (x cross W x + M)
                    f0, f1, f2 = nh.euler_momentum_rate(x0, x1, x2, o0, o1, o2, M0, M1, M2)
                    r0 = x0 - m0 - h2 * f0
                    r1 = x1 - m1 - h2 * f1
                    r2 = x2 - m2 - h2 * f2
                    d0, d1, d2 = nh.midpoint_newton_step(
                        x0, x1, x2, o0, o1, o2, w00, w01, w02, w10, w11, w12, w20, w21, w22,
                        h2, r0, r1, r2,
                    )  # fmt: skip
                    x0 -= d0
                    x1 -= d1
                    x2 -= d2
                    nd = max(abs(d0), abs(d1), abs(d2))
                    nx = max(abs(x0), abs(x1), abs(x2))
                    if not (nd == nd and nx == nx and nx < math.inf):
                        return Q, MO, 2, i, k, it
                    rel = 0.0 if nd == 0.0 else nd / (nx if nx != 0.0 else 1.0)
                    stop = nh.midpoint_newton_done(rel, prev, it)
                    if stop > 0:
                        break
                    if stop < 0:
                        return Q, MO, 1, i, k, it
                    prev = rel
                if it > worst:
                    worst = it
                # midpoint angular velocity; a = h w / 2 is the Gibbs vector of the step
                o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, x0, x1, x2)
                a0 = h2 * o0
                a1 = h2 * o1
                a2 = h2 * o2
                # m+ = (I + a^)^-1 [(I - a^) m + h M]: an exact rotation of m when M = 0
                m0, m1, m2 = nh.midpoint_momentum(m0, m1, m2, a0, a1, a2, h, M0, M1, M2)
                # q+ = q o (1, a) / sqrt(1 + |a|^2)  (Cayley map of h w^)
                p0, p1, p2, p3 = nh.qmul_gibbs(q0, q1, q2, q3, a0, a1, a2)
                q0, q1, q2, q3 = nh.qnormalize(p0, p1, p2, p3)
            Q[k + 1, i, 0] = q0
            Q[k + 1, i, 1] = q1
            Q[k + 1, i, 2] = q2
            Q[k + 1, i, 3] = q3
            MO[k + 1, i, 0] = m0
            MO[k + 1, i, 1] = m1
            MO[k + 1, i, 2] = m2
    return Q, MO, 0, -1, n - 1, worst


@njit(cache=True, nogil=True)
def splitting(q, m, inv_i, M, t, nsub, coef, cancel, progress, G=None):
    """Lie-Poisson splitting in principal axes for N bodies (see ``_run_splitting``).

    q (N, 4) attitudes of the principal frame, m (N, 3) principal-axes momenta,
    inv_i (NI, 3) inverse principal moments (ascending moments), M (NM, 3)
    constant principal-axes torques, NI, NM in {1, N}; t, nsub, coef as in
    :func:`midpoint`. Step: kick h/2, F0 h/2, F2 h/2, F_iso h, F2 h/2, F0 h/2,
    kick h/2. Returns (Q, MO, status, body, k): status 2 if non-finite, 3 if
    cancelled (``cancel``, ``progress`` as in :func:`midpoint`).

    ``G`` (NG, 3), optional: a gravity moment ``m g c`` (principal axes) about the
    fixed point; the kicks then add ``gamma x G`` with ``gamma = R^T e_z`` the upward
    vertical in principal axes, frozen during the kick (the exact flow of the
    potential ``V = G . gamma``), as used by :class:`poinsot.dynamics.HeavyRigidBody`.
    """
    n = t.shape[0]
    N = q.shape[0]
    Q = np.empty((n, N, 4))
    MO = np.empty((n, N, 3))
    nc = coef.shape[0]
    for i in range(N):
        ii = i if inv_i.shape[0] > 1 else 0
        im = i if M.shape[0] > 1 else 0
        g1 = inv_i[ii, 1]
        c0 = inv_i[ii, 0] - g1
        c2 = inv_i[ii, 2] - g1
        M0, M1, M2 = M[im, 0], M[im, 1], M[im, 2]
        G0, G1, G2 = 0.0, 0.0, 0.0
        if G is not None:
            ig = i if G.shape[0] > 1 else 0
            G0, G1, G2 = G[ig, 0], G[ig, 1], G[ig, 2]
        q0, q1, q2, q3 = q[i, 0], q[i, 1], q[i, 2], q[i, 3]
        m0, m1, m2 = m[i, 0], m[i, 1], m[i, 2]
        Q[0, i, 0] = q0
        Q[0, i, 1] = q1
        Q[0, i, 2] = q2
        Q[0, i, 3] = q3
        MO[0, i, 0] = m0
        MO[0, i, 1] = m1
        MO[0, i, 2] = m2
        for k in range(n - 1):
            progress[0] = i * (n - 1) + k
            hk = (t[k + 1] - t[k]) / nsub[k]
            for s_ in range(nsub[k] * nc):
                if nh.cancelled(cancel):
                    return Q, MO, 3, i, k
                h = hk * coef[s_ % nc]
                hh = 0.5 * h
                # kick h/2
                m0 += hh * M0
                m1 += hh * M1
                m2 += hh * M2
                if G is not None:
                    m0, m1, m2 = nh.gravity_kick(q0, q1, q2, q3, m0, m1, m2, G0, G1, G2, hh)
                for stage in range(5):
                    if stage == 0 or stage == 4:  # F0, h/2: about principal axis 0
                        th = hh * c0 * m0
                        ch = math.cos(0.5 * th)
                        sh = math.sin(0.5 * th)
                        c = 1.0 - 2.0 * sh * sh  # cos th
                        s = 2.0 * sh * ch  # sin th
                        m1, m2 = c * m1 + s * m2, c * m2 - s * m1
                        q0, q1, q2, q3 = nh.qaxis(q0, q1, q2, q3, ch, sh, 0)
                    elif stage == 1 or stage == 3:  # F2, h/2: about principal axis 2
                        th = hh * c2 * m2
                        ch = math.cos(0.5 * th)
                        sh = math.sin(0.5 * th)
                        c = 1.0 - 2.0 * sh * sh  # cos th
                        s = 2.0 * sh * ch  # sin th
                        m0, m1 = c * m0 + s * m1, c * m1 - s * m0
                        q0, q1, q2, q3 = nh.qaxis(q0, q1, q2, q3, ch, sh, 2)
                    else:  # F_iso, h: the body turns about the constant m by h |m| / I1
                        v0 = h * g1 * m0
                        v1 = h * g1 * m1
                        v2 = h * g1 * m2
                        ang = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
                        c = math.cos(0.5 * ang)
                        if ang < 1e-4:
                            sc = 0.5 - ang * ang / 48.0  # sin(ang/2)/ang
                        else:
                            sc = math.sin(0.5 * ang) / ang
                        q0, q1, q2, q3 = nh.qmul(q0, q1, q2, q3, c, sc * v0, sc * v1, sc * v2)
                q0, q1, q2, q3 = nh.qnormalize(q0, q1, q2, q3)
                # kick h/2
                m0 += hh * M0
                m1 += hh * M1
                m2 += hh * M2
                if G is not None:
                    m0, m1, m2 = nh.gravity_kick(q0, q1, q2, q3, m0, m1, m2, G0, G1, G2, hh)
            if not (math.isfinite(m0 + m1 + m2) and math.isfinite(q0 + q1 + q2 + q3)):
                return Q, MO, 2, i, k
            Q[k + 1, i, 0] = q0
            Q[k + 1, i, 1] = q1
            Q[k + 1, i, 2] = q2
            Q[k + 1, i, 3] = q3
            MO[k + 1, i, 0] = m0
            MO[k + 1, i, 1] = m1
            MO[k + 1, i, 2] = m2
    return Q, MO, 0, -1, n - 1
