"""Compiled kernel of :class:`poinsot.dynamics.FreeRigidBody` (private).

Imported lazily (numba loads on first use). One function, no calls to other
cached functions (numba's cache is then safe across processes). Per time point:
argument reduction by quasi-periodicity, Jacobi elliptic functions by the
arithmetic-geometric mean (descending Landen transformation, Abramowitz &
Stegun 16.12, DLMF 22.7: the sequence of moduli is computed once per body from
``k`` and ``k' = sqrt(1 - k^2)`` without cancellation, so nothing is lost near
the separatrix; per point one ``sin``/``cos`` and rational steps),
Carlson's ``R_J`` by duplication (Carlson 1995, Numer. Algorithms 10, 13-26),
the angular velocity, the precession angle and the attitude quaternion.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# Parameter vector layout (see free_body._Motion._setup_elliptic).
P_LAM, P_U0, P_KQ, P_K2, P_M1, P_N2, P_JH, P_J0 = 0, 1, 2, 3, 4, 5, 6, 7
P_KMOM, P_RATE0, P_KAPPA, P_BETA, P_MAJOR, P_SEP = 8, 9, 10, 11, 12, 13
N_PAR = 14


def landen_table(k2: float, m1: float) -> np.ndarray:
    """Descending Landen moduli for parameter ``k2`` (``m1 = 1 - k2``), shape (3, L+1).

    ``k_{l+1} = (1 - k'_l) / (1 + k'_l)``, ``k'_{l+1} = 2 sqrt(k'_l) / (1 + k'_l)``
    until ``k_L < 1e-9`` (then ``sn = sin`` to O(k_L^2) = 1e-18).
    """
    ks = [math.sqrt(k2)]
    kps = [math.sqrt(m1)]
    while ks[-1] >= 1e-9:
        kp = kps[-1]
        ks.append((1.0 - kp) / (1.0 + kp) if kp < 0.5 else ks[-1] ** 2 / (1.0 + kp) ** 2)
        kps.append(2.0 * math.sqrt(kp) / (1.0 + kp))
    scale = 1.0
    for k1 in ks[1:]:
        scale /= 1.0 + k1
    out = np.zeros((3, len(ks)))
    out[0], out[1], out[2, 0] = ks, kps, scale
    return out


@njit(cache=True)
def elliptic_state(
    t, par, idx, inertia, amp, qs, qp, want_q, landen
):  # pragma: no cover - compiled
    """Angular velocity w (n, 3), attitude q (n, 4) and J(u) (n,) at times t (n,).

    ``idx = (i, m, j)``: encircled, middle and other axis; ``amp`` the signed
    amplitudes; ``q = qs o Rzxz(psi, theta, phi) o qp``; ``landen`` (3, L+1):
    moduli ``k_l``, complementary moduli ``k'_l`` and (in ``[2, 0]``) the
    scale ``prod 1 / (1 + k_l)`` of :func:`landen_table`. If ``want_q`` is false
    only ``w`` is computed (``q`` and ``J`` are left empty).
    """
    n = t.shape[0]
    lam, u0, kq, k2, m1, n2 = par[0], par[1], par[2], par[3], par[4], par[5]
    jh, j0, kmom, rate0, kappa, beta = par[6], par[7], par[8], par[9], par[10], par[11]
    major = par[12] > 0.5
    sep = par[13] > 0.5
    i, m, j = idx[0], idx[1], idx[2]
    jx, jy = (j + 1) % 3, (j + 2) % 3
    w = np.empty((n, 3))
    nq = n if want_q else 0
    q = np.empty((nq, 4))
    jv = np.empty(nq)
    eps = 2.220446049250313e-16
    sqn2 = math.sqrt(n2)
    qfac = (0.25 * eps) ** (-1.0 / 6.0)
    ks = landen[0]
    kps = landen[1]
    nl = ks.shape[0] - 1
    scale = landen[2, 0]
    for p in range(n):
        u = lam * t[p] + u0
        if sep:
            # k = 1: sn = tanh, cn = dn = sech; J(v) in closed form.
            kk = 0.0
            sn = math.tanh(u)
            e = math.exp(-abs(u))
            cn = 2.0 * e / (1.0 + e * e)
            dn = cn
            sgn = 1.0
            if want_q:
                if n2 > 0.0:
                    jr = (u - math.atan(sqn2 * sn) / sqn2) / (1.0 + n2)
                else:
                    jr = u - sn
        else:
            kk = math.floor((u + kq) / (2.0 * kq))
            r = u - 2.0 * kq * kk
            sgn = 1.0 - 2.0 * (kk - 2.0 * math.floor(0.5 * kk))
            # Descending Landen (Gauss) transformation, DLMF 22.7.1-2: the moduli
            # ks[0] = k > ks[1] > ... > ks[nl] ~ 0 and the scale are precomputed;
            # at the bottom sn = sin, cn = cos; climb back with rational formulas.
            zb = r * scale
            s = math.sin(zb)
            c = math.cos(zb)
            for lv in range(nl, 0, -1):
                k1 = ks[lv]
                den = 1.0 + k1 * s * s
                d = math.sqrt(kps[lv] * kps[lv] + k1 * k1 * c * c)
                s, c = (1.0 + k1) * s / den, c * d / den
            sn = s
            cn = c
            dn = math.sqrt(m1 + k2 * cn * cn)
            if want_q:
                # J(r) = sn^3 R_J(cn^2, dn^2, 1, 1 + n2 sn^2) / 3 (Carlson duplication).
                sn2 = sn * sn
                if sn2 == 0.0:
                    jr = 0.0
                else:
                    x0, y0, z0, p0 = cn * cn, dn * dn, 1.0, 1.0 + n2 * sn2
                    xt, yt, zt, pt = x0, y0, z0, p0
                    a0 = (x0 + y0 + z0 + 2.0 * p0) / 5.0
                    am = a0
                    delta = (p0 - x0) * (p0 - y0) * (p0 - z0)
                    qq = qfac * max(abs(a0 - x0), abs(a0 - y0), abs(a0 - z0), abs(a0 - p0))
                    fac = 1.0
                    ssum = 0.0
                    while fac * qq >= abs(am):
                        sx = math.sqrt(xt)
                        sy = math.sqrt(yt)
                        sz = math.sqrt(zt)
                        sp = math.sqrt(pt)
                        lm = sx * sy + sy * sz + sz * sx
                        d = (sp + sx) * (sp + sy) * (sp + sz)
                        ee = delta * fac * fac * fac / (d * d)
                        if ee < 1e-4:
                            rc = 1.0 - ee * (1.0 / 3.0 - ee * (0.2 - ee / 7.0))
                        else:
                            se = math.sqrt(ee)
                            rc = math.atan(se) / se
                        ssum += fac * rc / d
                        fac *= 0.25
                        xt = 0.25 * (xt + lm)
                        yt = 0.25 * (yt + lm)
                        zt = 0.25 * (zt + lm)
                        pt = 0.25 * (pt + lm)
                        am = 0.25 * (am + lm)
                    xx = (a0 - x0) * fac / am
                    yy = (a0 - y0) * fac / am
                    zz = (a0 - z0) * fac / am
                    pp = -0.5 * (xx + yy + zz)
                    e2 = xx * yy + xx * zz + yy * zz - 3.0 * pp * pp
                    e3 = xx * yy * zz + 2.0 * e2 * pp + 4.0 * pp * pp * pp
                    e4 = (2.0 * xx * yy * zz + e2 * pp + 3.0 * pp * pp * pp) * pp
                    e5 = xx * yy * zz * pp * pp
                    poly = (
                        1.0
                        - 3.0 * e2 / 14.0
                        + e3 / 6.0
                        + 9.0 * e2 * e2 / 88.0
                        - 3.0 * e4 / 22.0
                        - 9.0 * e2 * e3 / 52.0
                        + 3.0 * e5 / 26.0
                    )
                    rj = fac * poly / (am * math.sqrt(am)) + 6.0 * ssum
                    jr = sn * sn2 * rj / 3.0
        wi = amp[i] * dn
        wm = amp[m] * sgn * sn
        wj = amp[j] * sgn * cn
        w[p, i] = wi
        w[p, m] = wm
        w[p, j] = wj
        if not want_q:
            continue
        jval = kk * jh + jr
        jv[p] = jval
        tp = t[p]
        if major:
            psi = rate0 * tp + kappa * beta * (jval - j0) / lam
        else:
            psi = rate0 * tp + kappa * (tp - beta * (jval - j0) / lam)
        # Euler angles (z-x-z about axis j) of the body unit momentum.
        x = inertia[jx] * w[p, jx] / kmom
        y = inertia[jy] * w[p, jy] / kmom
        z = inertia[j] * w[p, j] / kmom
        st = math.hypot(x, y)
        big = math.sqrt(0.5 * (1.0 + abs(z)))
        small = st / (2.0 * big)
        if z >= 0.0:
            ch, sh = big, small
        else:
            ch, sh = small, big
        ph = math.atan2(x, y)
        ha = 0.5 * (psi + ph)
        hb = 0.5 * (psi - ph)
        z0_ = ch * math.cos(ha)
        z1_ = sh * math.cos(hb)
        z2_ = sh * math.sin(hb)
        z3_ = ch * math.sin(ha)
        # r = qs o z
        r0 = qs[0] * z0_ - qs[1] * z1_ - qs[2] * z2_ - qs[3] * z3_
        r1 = qs[0] * z1_ + qs[1] * z0_ + qs[2] * z3_ - qs[3] * z2_
        r2 = qs[0] * z2_ - qs[1] * z3_ + qs[2] * z0_ + qs[3] * z1_
        r3 = qs[0] * z3_ + qs[1] * z2_ - qs[2] * z1_ + qs[3] * z0_
        # q = r o qp
        q[p, 0] = r0 * qp[0] - r1 * qp[1] - r2 * qp[2] - r3 * qp[3]
        q[p, 1] = r0 * qp[1] + r1 * qp[0] + r2 * qp[3] - r3 * qp[2]
        q[p, 2] = r0 * qp[2] - r1 * qp[3] + r2 * qp[0] + r3 * qp[1]
        q[p, 3] = r0 * qp[3] + r1 * qp[2] - r2 * qp[1] + r3 * qp[0]
    return w, q, jv
