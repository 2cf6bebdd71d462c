"""Compiled kernel of :class:`poinsot.dynamics.LagrangeTop` (private).

Imported lazily (numba loads on first use). Per time point: the Jacobi elliptic
functions of the nutation argument ``tau = tau' t + tau0`` and the two
incomplete integrals of the third kind of the Cayley-Klein angles, all from the
scalar kernels of :mod:`poinsot.dynamics._elliptic` (declared with
``depends_on`` so that editing them invalidates this file's cache). The
formulas are derived in the docstring of :mod:`poinsot.dynamics.lagrange_top`.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit
from .._numba_cache import depends_on
from . import _elliptic as el

depends_on(__file__, el)

# Layout of the parameter vector (see lagrange_top._Elliptic).
(
    P_RATE,  # tau'
    P_TAU0,
    P_M,
    P_M1,
    P_K,  # K(m)
    P_DX,  # x2 - x1 = u2 - u1
    P_OM1,  # 1 - u1
    P_OP1,  # 1 + u1
    P_NP,  # n+ = (u2 - u1) / (1 - u1)
    P_NM,  # n- = -(u2 - u1) / (1 + u1)
    P_CP,  # (K_z - H) / (A (1 - u1) tau')   (0: term absent)
    P_CM,  # (K_z + H) / (A (1 + u1) tau')
    P_PIP,  # Pi(n+ | m) complete
    P_PIM,  # Pi(n- | m)
    P_PIP0,  # Pi(n+; tau0)
    P_PIM0,  # Pi(n-; tau0)
    P_WS,  # H/C - H/A: linear part of sigma' (and -delta')
    P_SIG0,
    P_DEL0,
    P_SPS,  # 1: u2 = 1 reached (K_z = H): sin(theta/2) signed, proportional to cn
    P_SPC,  # 1: u1 = -1 reached (K_z = -H): cos(theta/2) signed, proportional to sn
    P_KMH,  # K_z - H
    P_KPH,  # K_z + H
    P_A,
    P_H,
    P_R,  # spin r = H / C
    P_NP1,  # 1 - n+ = (1 - u2) / (1 - u1), exact near the upright
    P_Y2,  # 1 - u2
    P_PSI,  # 1: psi - psi0 = F(tau) - F(tau0) (see psi_sum), else (Delta sigma + Delta delta)/2
    P_Q1P,  # (K_z - H u1) / (2 A (1 - u1) tau')   times G+
    P_Q1M,  # (K_z - H u1) / (2 A (1 + u1) tau')   times G-
    P_Q2P,  # (K_z - H u2) / (2 A (1 - u1) tau')   times S+
    P_Q2M,  # (K_z - H u2) / (2 A (1 + u1) tau')   times S-
    P_FC,  # F over [0, K]
    P_F0,  # F(tau0)
) = range(35)
N_PAR = 35


@njit(cache=True, inline="always")
def _pi_reduced(f, n, p, r, theta, s, s2, c2, d2):  # pragma: no cover - compiled
    """``Pi(n; am r)`` on the reduced argument ``r``: the precomputed Fourier series
    ``f`` when there is one, else ``r + n s^3 R_J(c^2, d^2, 1, p) / 3`` with
    ``p = 1 - n s^2`` given by the caller (without cancellation)."""
    if f.shape[0] > 0:
        return f[0] * r + _sine_series(f, theta)
    if s2 > 0.0:
        return r + n * s * s2 * el.carlson_rj(c2, d2, 1.0, p) / 3.0
    return r


@njit(cache=True)
def _sine_series(c, theta):  # pragma: no cover - compiled
    """``sum_{j=1}^{J} c[j] sin(j theta)`` by Clenshaw's recurrence (``c[0]`` unused)."""
    nj = c.shape[0] - 1
    if nj < 1:
        return 0.0
    x2 = 2.0 * math.cos(theta)
    b1 = 0.0
    b2 = 0.0
    for j in range(nj, 0, -1):
        b1, b2 = c[j] + x2 * b1 - b2, b1
    return b1 * math.sin(theta)


@njit(cache=True)
def psi_sum(r, s, c, d, par):  # pragma: no cover - compiled
    """``F(r) = Q1+ G+ + Q1- G- + Q2+ S+ + Q2- S-`` on the reduced argument ``|r| <= K``
    (``s, c, d`` its ``sn, cn, dn``): ``psi - psi0 = F(tau) - F(tau0)``.

    ``K_z - H u = (K_z - H u1) cn^2 + (K_z - H u2) sn^2`` and
    ``2 / (1 - u^2) = 1 / (1 - u) + 1 / (1 + u)``, ``1 -+ u = (1 -+ u1)(1 - n+- sn^2)``
    give ``2 A tau' psi' = (K_z - H u1) (g+ / (1 - u1) + g- / (1 + u1)) + (K_z - H u2)
    (s+ / (1 - u1) + s- / (1 + u1))`` with ``g = cn^2 / (1 - n sn^2)``,
    ``s = sn^2 / (1 - n sn^2)`` (docs/theory.md §10). Their integrals
    ``S(n; r) = s^3 R_J(c^2, d^2, 1, 1 - n s^2) / 3`` and ``G = r - (1 - n) S`` (no
    division by ``n``; ``1 - n+ s^2`` as ``(1 - n+) + n+ c^2``, exact near the upright)
    are positive, the coefficients small for a fast top (``~ m g l / H``): a sum of
    terms of one sign unless ``psi'`` changes sign (loops), so ``psi`` keeps full
    relative precision, where ``(Delta sigma + Delta delta) / 2`` cancels the parts
    ``+-H / A`` of ``sigma'``, ``delta'`` (``ulp(r t)`` absolute).
    """
    np1 = par[P_NP1]
    nm = par[P_NM]
    sp = 0.0
    sm = 0.0
    s2 = s * s
    if s2 > 0.0:
        c2 = c * c
        d2 = d * d
        s3 = s * s2 / 3.0
        sp = s3 * el.carlson_rj(c2, d2, 1.0, np1 + par[P_NP] * c2)
        sm = s3 * el.carlson_rj(c2, d2, 1.0, 1.0 - nm * s2)
    gp = r - np1 * sp
    gm = r - (1.0 - nm) * sm
    return par[P_Q1P] * gp + par[P_Q1M] * gm + par[P_Q2P] * sp + par[P_Q2M] * sm


@njit(cache=True)
def _pi_pair(tau, par, ks, kps, lv, scale, fp, fm, want_pi, want_psi):  # pragma: no cover
    """``(sn, cn, dn, Pi(n+; tau), Pi(n-; tau), F(tau))`` for the argument ``tau`` (any
    real); ``F`` of :func:`psi_sum` (plus ``2 j`` times its value over ``[0, K]``) only
    with ``want_psi``, else 0.

    ``Pi(n; tau) = int_0^tau dv / (1 - n sn^2 v)``. With ``tau = 2 j K + r``,
    ``|r| <= K``: by Fourier series when the coefficients ``fp``/``fm`` are given
    (``f[0]`` the mean ``Pi(n | m) / K``, ``f[k] = K a_k / (k pi)`` for the cosine
    coefficients ``a_k`` of ``1 / (1 - n sn^2)``), else
    ``r + n s^3 R_J(c^2, d^2, 1, 1 - n s^2) / 3`` (``s R_F(c^2, d^2, 1) = r``); plus
    ``2 j Pi(n | m)``. On the separatrix (``m = 1``) the elementary form
    ``(tau + sqrt(-n) atan(sqrt(-n) tanh tau)) / (1 - n)`` (``n <= 0``).
    """
    m, m1 = par[P_M], par[P_M1]
    np_, nm = par[P_NP], par[P_NM]
    if lv < 0:  # m = 1
        sn, cn, dn = el.jacobi_reduced(tau, ks, kps, lv, scale, m, m1)
        pim = 0.0
        if want_pi:
            a = math.sqrt(-nm)
            pim = (tau + a * math.atan(a * sn)) / (1.0 - nm)
        return sn, cn, dn, 0.0, pim, 0.0  # on the separatrix K_z = H: no n+ term
    kq = par[P_K]
    j, r = el.reduce_argument(tau, kq)
    s, c, d = el.jacobi_reduced(r, ks, kps, lv, scale, m, m1)
    pip = 0.0
    pim = 0.0
    if want_pi:
        s2 = s * s
        c2 = c * c
        d2 = d * d
        theta = math.pi * r / kq
        if par[P_CP] != 0.0:
            # 1 - n+ s^2 = (1 - n+) + n+ c^2: exact as n+ -> 1 (released near the upright)
            p = par[P_NP1] + np_ * c2
            pip = _pi_reduced(fp, np_, p, r, theta, s, s2, c2, d2) + 2.0 * j * par[P_PIP]
        if par[P_CM] != 0.0:
            p = 1.0 - nm * s2
            pim = _pi_reduced(fm, nm, p, r, theta, s, s2, c2, d2) + 2.0 * j * par[P_PIM]
    f = 0.0
    if want_psi:
        f = psi_sum(r, s, c, d, par) + 2.0 * j * par[P_FC]
    if j - 2.0 * math.floor(0.5 * j) != 0.0:
        s, c = -s, -c
    return s, c, d, pip, pim, f


@njit(cache=True)
def motion(t, par, fp, fm, want_q, want_w, out_q, out_w, out_x):  # pragma: no cover
    """Attitude ``out_q`` (n, 4), body angular velocity ``out_w`` (n, 3) and
    ``out_x`` (n, 2|4|5) = ``(sin(theta/2), cos(theta/2), sigma, delta, psi - psi0)``
    (signed half-angle functions, continuous Cayley-Klein angles, and with 5 columns
    the precession of :func:`psi_sum`, which needs ``par[P_PSI]`` set) at the times
    ``t`` (n,), ``m g l > 0``.

    The attitude is ``(c cos(sigma/2), s cos(delta/2), s sin(delta/2), c sin(sigma/2))``
    with ``sigma = psi + phi``, ``delta = psi - phi`` (z-x-z Euler angles).
    """
    ks = np.empty(el.LMAX)
    kps = np.empty(el.LMAX)
    lv, scale = el.landen_fill(par[P_M], par[P_M1], ks, kps)
    rate, tau0, dx = par[P_RATE], par[P_TAU0], par[P_DX]
    om1, op1 = par[P_OM1], par[P_OP1]
    cp, cm, ws = par[P_CP], par[P_CM], par[P_WS]
    y2 = par[P_Y2]
    sps = par[P_SPS] > 0.5
    spc = par[P_SPC] > 0.5
    a_s = math.sqrt(0.5 * om1)
    a_c = math.sqrt(0.5 * dx)
    big_a, big_h = par[P_A], par[P_H]
    want_psi = out_x.shape[1] > 4 and par[P_PSI] > 0.5
    for p in range(t.shape[0]):
        tp = t[p]
        tau = rate * tp + tau0
        want_pi = want_q or want_w or out_x.shape[1] > 2
        sn, cn, dn, pip, pim, f = _pi_pair(tau, par, ks, kps, lv, scale, fp, fm, want_pi, want_psi)
        sn2 = sn * sn
        if sps:
            s = a_s * cn
        else:  # 1 - u = (1 - u2) + (u2 - u1) cn^2: no cancellation near the upright
            s = math.sqrt(0.5 * (y2 + dx * cn * cn))
        if spc:
            c = a_c * sn
        else:
            c = math.sqrt(max(0.5 * (op1 + dx * sn2), 0.0))
        sig = par[P_SIG0] + ws * tp
        dlt = par[P_DEL0] - ws * tp
        if cm != 0.0:
            sig += cm * (pim - par[P_PIM0])
        if cp != 0.0:
            dlt += cp * (pip - par[P_PIP0])
        out_x[p, 0] = s
        out_x[p, 1] = c
        if out_x.shape[1] > 2:
            out_x[p, 2] = sig
            out_x[p, 3] = dlt
        if want_psi:
            out_x[p, 4] = f - par[P_F0]
        if want_q:
            out_q[p, 0] = c * math.cos(0.5 * sig)
            out_q[p, 1] = s * math.cos(0.5 * dlt)
            out_q[p, 2] = s * math.sin(0.5 * dlt)
            out_q[p, 3] = c * math.sin(0.5 * sig)
        if want_w:
            # q_b + i p_b = (psi' sin(theta) + i theta') e^{i phi}, phi = (sigma - delta)/2
            if big_h == 0.0 and par[P_KMH] == 0.0:
                wps = 0.0
            elif spc:
                # K_z - H u = (K_z + H) - 2 H c^2, K_z + H = 0
                wps = -big_h * c / (big_a * s)
            else:
                # K_z - H u = (K_z - H) + 2 H s^2
                wps = big_h * s / (big_a * c)
                if par[P_KMH] != 0.0:
                    wps += par[P_KMH] / (2.0 * big_a * s * c)
            # theta' = -u' / sin(theta), u' = 2 (u2 - u1) tau' sn cn dn, sin(theta) = 2 s c
            rs = 1.0 / a_s if sps else cn / s
            rc = 1.0 / a_c if spc else sn / c
            wth = -dx * rate * dn * rs * rc
            ph = 0.5 * (sig - dlt)
            cph = math.cos(ph)
            sph = math.sin(ph)
            out_w[p, 0] = wps * sph + wth * cph
            out_w[p, 1] = wps * cph - wth * sph
            out_w[p, 2] = par[P_R]


@njit(cache=True)
def pi_at(tau, par, fp, fm):  # pragma: no cover - compiled
    """``(sn, cn, dn, Pi(n+; tau), Pi(n-; tau), F(tau))`` at one argument (for the
    constants)."""
    ks = np.empty(el.LMAX)
    kps = np.empty(el.LMAX)
    lv, scale = el.landen_fill(par[P_M], par[P_M1], ks, kps)
    return _pi_pair(tau, par, ks, kps, lv, scale, fp, fm, True, par[P_PSI] > 0.5)
