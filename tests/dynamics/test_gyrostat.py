"""Tests of the gyrostat (docs/theory.md §10.1): the Euler-Zhukovsky
right-hand side, the exact dual-spin solution and its numeric fallback.

Oracles: a Taylor-series integration of ``J w' = (J w + h) x w`` (and of
``q' = q o w / 2`` for the attitude) from the same double inputs, with the series
coefficients from the exact Cauchy-product recurrence of these quadratic equations in
112-bit fixed point (128 for one separatrix case; Python integers, order 30, each
step shortened until its last two terms are below 2^(6 - bits)): :func:`_taylor`. It
is checked against 30-digit ``mpmath.odefun`` (to 1e-28) and against itself at 32 more
bits on the case that amplifies its errors most (:func:`test_reference_is_converged`),
so its error is >= 100x below every tolerance here; each reference is computed once
(:func:`_reference`, cached) and shared by the tests that use it. Further oracles:
:class:`poinsot.dynamics.FreeRigidBody` for ``h = 0``; the eigenvalues of the
finite-difference Jacobian of :func:`gyrostat_rhs` for the stability of permanent
rotations (Wittenburg, *Dynamics of Multibody Systems*, ch. 4; Cochran, Shu & Rew
1982). Every tolerance is >= 10x the error observed (noted at each).
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction
from operator import mul

import numpy as np
import pytest

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.dynamics import (
    FreeGyrostat,
    FreeRigidBody,
    euler_rhs,
    gyrostat_rhs,
    gyrostat_spin_stable,
)

mpmath = pytest.importorskip("mpmath")

#: omega against the reference, max |w - w_ref| / max |w_ref|: observed <= 6.1e-16
#: (random cases, t in [-3, 6]) and <= 9.2e-15 next to a separatrix (1 - k^2 from
#: 5.7e-9 down to 1.0e-12, SEPARATRIX_CASES; before the quartic was solved in exact
#: arithmetic: up to 5.8e-11 there).
TOL_REF_W = 1e-12
#: attitude against the reference (angle of R_ref^T R, rad) over 1.5 periods:
#: observed <= 1.6e-14.
TOL_REF_R = 1e-12

_CROSS = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


def _taylor(inertia, h, w0, q0, ts, *, bits=112, order=30, exact=False):
    """``w`` (and ``q`` if ``q0`` is given) at times ``ts`` (any signs): Taylor series of
    ``J w' = (J w + h) x w``, ``q' = q o (0, w) / 2`` in ``bits``-bit fixed point.

    With ``W_n = w_n s^n`` the scaled coefficients of a step ``s`` and
    ``M_n = J W_n (+ h for n = 0)``: ``W_{n+1} = s / ((n + 1) J) sum_j M_j x W_{n-j}``,
    ``Q_{n+1} = s / (2 (n + 1)) sum_j Q_j o (0, W_{n-j})``, exact integer Cauchy
    products rounded once per coefficient. The step shrinks (x 3/4) until the last two
    coefficients are below ``2^(6 - bits)`` and grows (x 5/4) when far below. Returns
    floats (n, 3 or 7), or with ``exact`` the fixed-point integers and the scale."""
    one = 1 << bits

    def fx(x):  # fixed point of an exact double (exact for the inputs used here)
        return round(Fraction(float(x)) * one)

    i_fx = [fx(x) for x in inertia]
    inv_fx = [round(one / Fraction(float(x)) * one) >> bits for x in inertia]  # 1 / I_k
    h_fx = [fx(x) for x in h]
    att = q0 is not None
    y0 = [fx(x) for x in (list(w0) + (list(q0) if att else []))]
    tq = [fx(t) for t in ts]
    out = [list(y0) if t == 0 else None for t in tq]
    tail_tol = 1 << 6
    for sign in (1, -1):
        todo = sorted((i for i, t in enumerate(tq) if sign * t > 0), key=lambda i: sign * tq[i])
        y, tc, step, pos = list(y0), 0, one >> 3, 0
        while pos < len(todo):
            while True:
                s = sign * step
                ser = [[v] for v in y]  # 3 (+ 4) coefficient lists
                mm = [[(i_fx[k] * y[k] >> bits) + h_fx[k]] for k in range(3)]
                coef = [s * inv_fx[k] >> bits for k in range(3)]  # s / I_k
                for n in range(order):
                    ww = ser[:3]
                    new = []
                    for k, a, b in _CROSS:
                        acc = sum(map(mul, mm[a], reversed(ww[b])))
                        acc -= sum(map(mul, mm[b], reversed(ww[a])))
                        new.append((acc * coef[k] >> 2 * bits) // (n + 1))
                    if att:
                        rw = [ww[k][::-1] for k in range(3)]
                        qq = ser[3:]

                        def cp(x, k, qq=qq, rw=rw):
                            return sum(map(mul, qq[x], rw[k]))

                        dq = (
                            -(cp(1, 0) + cp(2, 1) + cp(3, 2)),
                            cp(0, 0) + cp(2, 2) - cp(3, 1),
                            cp(0, 1) + cp(3, 0) - cp(1, 2),
                            cp(0, 2) + cp(1, 1) - cp(2, 0),
                        )
                        for x in range(4):
                            qq[x].append((dq[x] * s >> 2 * bits) // (2 * (n + 1)))
                    for k in range(3):
                        ww[k].append(new[k])
                        mm[k].append(i_fx[k] * new[k] >> bits)
                tail = max(abs(c[j]) for c in ser for j in (-1, -2))
                if tail < tail_tol:
                    break
                step = step * 3 // 4
            tn = tc + s
            while pos < len(todo) and sign * tq[todo[pos]] <= sign * tn:
                th = ((tq[todo[pos]] - tc) << bits) // s
                vals = []
                for c in ser:
                    acc = 0
                    for cf in reversed(c):
                        acc = (acc * th >> bits) + cf
                    vals.append(acc)
                out[todo[pos]] = vals
                pos += 1
            y, tc = [sum(c) for c in ser], tn
            if tail < tail_tol >> 8:
                step = step * 5 // 4
    if exact:
        return out, one
    return np.array([[v / one for v in row] for row in out])


@functools.cache
def _cached(inertia, h, w0, q0, ts, bits):
    ref = _taylor(inertia, h, w0, q0, ts, bits=bits)
    ref.flags.writeable = False
    return ref


def _reference(inertia, h, w0, q0, ts, bits=112):
    """The Taylor reference, computed once per distinct case and shared."""

    def key(x):
        return None if x is None else tuple(float(v) for v in np.ravel(x))

    return _cached(key(inertia), key(h), key(w0), key(q0), key(ts), bits)


def _rel(w, ref):
    return float(np.max(np.abs(w - ref)) / np.max(np.abs(ref)))


def _random_cases(n, seed):
    rng = np.random.default_rng(seed)
    cases = []
    while len(cases) < n:
        inertia = rng.uniform(0.5, 3.0, 3)
        if 2.0 * inertia.max() > inertia.sum():
            continue
        h = np.zeros(3)
        h[rng.integers(3)] = rng.normal() * rng.choice([0.2, 1.0, 3.0])
        cases.append((inertia, h, rng.normal(size=3)))
    return cases


@pytest.mark.parametrize("case", _random_cases(4, 41), ids=lambda c: "")
def test_omega_matches_reference_random(case):
    inertia, h, w0 = case
    g = FreeGyrostat(inertia, h, omega0=w0)
    assert g.regime in ("four_roots", "two_roots")
    t = np.linspace(-3.0, 6.0, 10)
    err = _rel(g.omega(t), _reference(inertia, h, w0, None, t))
    assert err < TOL_REF_W, (g.regime, err)


#: Next to the two kinds of separatrix, on both sides (the sides differ in which roots of
#: the quartic belong to which quadratic, or in the number of real roots):
#: (b) a spin about the rotor axis 3 of moments (1, 3, 2) (axis 3 intermediate) with
#: h e3, unstable for |h| < |W| (a near-common root of the two quadratics) and a small
#: transverse omega; (a) the unstable permanent rotation (0, 1, h / (I2 - I3)) of moments
#: (1, 2, 3) with h e3 (a near-double root of one quadratic: its discriminant is
#: ~ (1 - k^2)^2). Values: (inertia, h, omega0, 1 - k^2 range from the exact inputs).
SEPARATRIX_CASES = {
    "b-side1-1e-12": ([1.0, 3.0, 2.0], [0.0, 0.0, 0.2], [3e-6, 3e-7, 1.0], (1e-12, 2e-12)),
    "b-side2-2e-12": ([1.0, 3.0, 2.0], [0.0, 0.0, 0.2], [3e-7, 3e-6, 1.0], (2e-12, 3e-12)),
    "b-4e-9": ([1.0, 3.0, 2.0], [0.0, 0.0, 0.5], [1e-2, 1e-2, 1.0], (4e-9, 5e-9)),
    "a-two-roots-1e-12": ([1.0, 2.0, 3.0], [0.0, 0.0, 0.1], [1e-6, 1.0, -0.1], (1e-12, 2e-12)),
    "a-four-roots-6e-9": ([1.0, 2.0, 3.0], [0.0, 0.0, 0.1], [1e-9, 1.0, -0.1 + 1e-9], (5e-9, 7e-9)),
}
#: Fixed-point bits of the reference per case: on the four-roots side of (a) its error is
#: amplified ~ 1 / (1 - k^2)^2 (2.6e-13 at 112 bits for 6e-9), elsewhere ~ 1 / (1 - k^2).
SEPARATRIX_BITS = {"a-four-roots-6e-9": 128}


def _mp_one_minus_k2(inertia, h, w0):
    """``1 - k^2`` at 50 digits from the exact inputs, independently of the module's
    formulas: ``m1^2`` and ``m2^2`` as quadratics in ``z = m3`` from the two integrals
    ``|m|^2 = K^2``, ``sum (m_i - h_i)^2 / I_i = 2 T`` (rotor axis last), their roots,
    and the textbook moduli (Byrd & Friedman 1971, 251-259): four real roots
    ``e1 > e2 > e3 > e4``, ``k^2 = (e1 - e2)(e3 - e4) / ((e1 - e3)(e2 - e4))`` on
    ``[e4, e3]`` or ``[e2, e1]``, ``(e2 - e3)(e1 - e4) / ((e1 - e3)(e2 - e4))`` on
    ``[e3, e2]``; two, ``((e1 - e2)^2 - (A - B)^2) / (4 A B)``."""
    mp = mpmath.mp
    with mpmath.workdps(50):
        ax = int(np.flatnonzero(h)[0])
        idx = ((ax + 1) % 3, (ax + 2) % 3, ax)
        i1, i2, i3 = (mp.mpf(float(inertia[k])) for k in idx)
        p, q, r = (mp.mpf(float(w0[k])) for k in idx)
        hh = mp.mpf(float(h[ax]))
        z0 = i3 * r + hh
        k2m = (i1 * p) ** 2 + (i2 * q) ** 2 + z0**2
        two_t = i1 * p * p + i2 * q * q + i3 * r * r
        # m1^2 (1/I1 - 1/I2) = 2T - (z - h)^2 / I3 - (K^2 - z^2) / I2, and 1 <-> 2
        quads = []
        for ia, ib in ((i1, i2), (i2, i1)):
            s = 1 / ia - 1 / ib
            quads.append(
                [(1 / ib - 1 / i3) / s, 2 * hh / i3 / s, (two_t - hh * hh / i3 - k2m / ib) / s]
            )
        real, cplx = [], []
        for c2, c1, c0 in quads:
            disc = c1 * c1 - 4 * c2 * c0
            if disc >= 0:
                real += [(-c1 + sg * mp.sqrt(disc)) / (2 * c2) for sg in (1, -1)]
            else:
                cplx.append((-c1 / (2 * c2), mp.sqrt(-disc) / (2 * abs(c2))))

        def positive(z):
            return all(c2 * z * z + c1 * z + c0 > 0 for c2, c1, c0 in quads)

        e = sorted(real, reverse=True)  # e1 > e2 > ...
        if len(e) == 4:
            e1, e2, e3, e4 = e
            assert e3 <= z0 <= e2 or e4 <= z0 <= e3 or e2 <= z0 <= e1
            if e3 < z0 < e2 or (z0 in (e2, e3) and positive((e2 + e3) / 2)):
                k2 = (e2 - e3) * (e1 - e4) / ((e1 - e3) * (e2 - e4))
            else:
                k2 = (e1 - e2) * (e3 - e4) / ((e1 - e3) * (e2 - e4))
        else:
            (e1, e2), (b1, a1) = e, cplx[0]
            big_a = mp.sqrt((e1 - b1) ** 2 + a1**2)
            big_b = mp.sqrt((e2 - b1) ** 2 + a1**2)
            k2 = ((e1 - e2) ** 2 - (big_a - big_b) ** 2) / (4 * big_a * big_b)
        return float(1 - k2)


@pytest.mark.parametrize("name", list(SEPARATRIX_CASES))
def test_omega_matches_reference_near_separatrix(name):
    """omega over 1.2 periods (1 - k^2 down to 1e-12; observed 8.9e-16 .. 9.2e-15, the
    largest at u ~ 50 where the argument's rounding shows) and ``1 - k^2`` itself to
    1e-14 relative (observed 0: correctly rounded): the quartic is solved in exact
    arithmetic on the double inputs. Before, in double: 1 - k^2 off by up to 7.8e-14
    relative and the phase u0 by 1.7e-13; omega errors 4.4e-12 (b-side1), 5.8e-11
    (b-side2), 4.9e-14 (b-4e-9), 4.6e-11 (a-two-roots)."""
    inertia, hv, w0, (lo, hi) = SEPARATRIX_CASES[name]
    g = FreeGyrostat(inertia, hv, omega0=w0)
    m1_exact = _mp_one_minus_k2(inertia, hv, w0)
    assert lo < m1_exact < hi
    m1 = g._bodies[0].plan.m1
    assert abs(m1 - m1_exact) < 1e-14 * m1_exact, (m1, m1_exact)
    t = np.linspace(0.0, 1.2 * g.period, 9)
    ref = _reference(inertia, hv, w0, None, t, bits=SEPARATRIX_BITS.get(name, 112))
    err = _rel(g.omega(t), ref)
    assert err < TOL_REF_W, (m1, err)


@pytest.mark.parametrize("case", _random_cases(2, 7), ids=lambda c: "")
def test_attitude_matches_reference(case):
    inertia, h, w0 = case
    q0 = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_quat()
    g = FreeGyrostat(inertia, h, rotation0=q0, omega0=w0)
    t = np.linspace(0.0, 1.5 * g.period, 6)
    ref = _reference(inertia, h, w0, q0, t)
    w, r = g.state(t)
    assert _rel(w, ref[:, :3]) < TOL_REF_W
    angle = (r.inv() * Rotation.from_quat(ref[:, 3:])).magnitude()
    assert float(np.max(angle)) < TOL_REF_R


def test_integrals_are_conserved():
    cases = _random_cases(8, 3)
    for inertia, h, w0 in cases:
        g = FreeGyrostat(inertia, h, rotation0=Rotation.from_rotvec([1.0, 2.0, 0.5]), omega0=w0)
        tr = g.trajectory(np.linspace(-20.0, 40.0, 301))
        e = tr.energy
        assert np.max(np.abs(e - g.energy)) < 1e-13 * g.energy  # observed <= 1.1e-15
        k = tr.momentum
        assert np.max(np.abs(k - g.momentum)) < 1e-12 * g.momentum_norm  # observed <= 1.3e-15
        mb = g.momentum_body(tr.t)
        assert np.allclose(np.linalg.norm(mb, axis=-1), g.momentum_norm, rtol=1e-14, atol=0)
        assert tr.info["conserved"] == ("energy", "momentum")


def test_h_zero_is_the_free_rigid_body():
    for inertia, _, w0 in _random_cases(6, 11):
        q0 = Rotation.from_rotvec([0.2, 0.1, -0.4])
        g = FreeGyrostat(inertia, [0.0, 0.0, 0.0], rotation0=q0, omega0=w0)
        b = FreeRigidBody(inertia, rotation0=q0, omega0=w0)
        t = np.linspace(-5.0, 15.0, 41)
        wg, rg = g.state(t)
        wb, rb = b.state(t)
        assert _rel(wg, wb) < 1e-13  # observed <= 5.2e-15
        assert float(np.max((rg.inv() * rb).magnitude())) < 1e-12  # observed <= 1.1e-14
        assert math.isclose(g.period, b.period, rel_tol=1e-13)
        assert math.isclose(g.energy, b.energy, rel_tol=1e-15)


def _jacobian(inertia, h, w, step=1e-6):
    cols = []
    for k in range(3):
        d = np.zeros(3)
        d[k] = step
        cols.append(
            (gyrostat_rhs(inertia, w + d, h) - gyrostat_rhs(inertia, w - d, h)) / (2 * step)
        )
    return np.stack(cols, -1)


@pytest.mark.parametrize("axis", [0, 1, 2])
@pytest.mark.parametrize("h", [-3.0, -1.2, -0.8, -0.3, 0.0, 0.3, 0.8, 1.2, 3.0])
def test_spin_stability_against_linearised_rhs(axis, h):
    """Stable iff the Jacobian at the permanent rotation has no eigenvalue with a
    positive real part (the others are purely imaginary pairs and a zero)."""
    inertia = np.array([1.0, 2.0, 3.0])
    w = np.zeros(3)
    w[axis] = 1.0
    hv = np.zeros(3)
    hv[axis] = h
    assert np.allclose(gyrostat_rhs(inertia, w, hv), 0.0)  # a permanent rotation
    ev = np.linalg.eigvals(_jacobian(inertia, hv, w))
    unstable = np.max(ev.real) > 1e-6
    assert gyrostat_spin_stable(inertia, hv, w) == (not unstable)
    g = FreeGyrostat(inertia, hv, omega0=w)
    assert g.regime == "permanent"
    assert np.allclose(g.omega([0.0, 3.0]), w, rtol=0, atol=0)


def test_intermediate_axis_is_stabilised_by_the_rotor():
    """Dual spin: spin W = 1 about the intermediate axis of (1, 2, 3): unstable for
    -1 < h < 1 ((m - I1 W)(m - I3 W) < 0 with m = 2 + h), stable beyond."""
    inertia, w = [1.0, 2.0, 3.0], [0.0, 1.0, 0.0]
    hs = np.array([-1.5, -0.99, 0.0, 0.99, 1.5])
    got = gyrostat_spin_stable(inertia, np.outer(hs, [0.0, 1.0, 0.0]), w)
    assert got.tolist() == [True, False, False, False, True]
    # the perturbed motion stays close (stable) or leaves (unstable)
    for h, bounded in ((1.5, True), (0.5, False)):
        g = FreeGyrostat(inertia, [0.0, h, 0.0], omega0=[1e-4, 1.0, 1e-4])
        dev = np.max(np.abs(g.omega(np.linspace(0.0, 60.0, 601))[:, [0, 2]]))
        assert (dev < 1e-3) == bounded


def test_rhs_reduces_to_euler_and_has_the_rotor_terms():
    rng = np.random.default_rng(5)
    w = rng.normal(size=(4, 3))
    jt = np.array([[2.0, 0.1, 0.0], [0.1, 3.0, 0.2], [0.0, 0.2, 4.0]])
    m = rng.normal(size=3)
    assert np.allclose(gyrostat_rhs(jt, w, np.zeros(3), m), euler_rhs(jt, w, m), rtol=1e-15)
    h, hd = rng.normal(size=3), rng.normal(size=3)
    lhs = jt @ gyrostat_rhs(jt, w[0], h, m, h_rate=hd) + np.cross(w[0], jt @ w[0] + h)
    assert np.allclose(lhs, m - hd, rtol=1e-14, atol=1e-14)


def test_regimes_and_fallback():
    # rotor along the symmetry axis: r constant, (p + i q) turns at ((I3 - I1) r + h) / I1
    g = FreeGyrostat([2.0, 2.0, 1.0], [0.0, 0.0, 2.0], omega0=[0.3, 0.4, 1.0])
    assert g.regime == "axisymmetric"
    t = np.linspace(0.0, 10.0, 11)
    ang = 0.5 * t
    w = g.omega(t)
    assert np.allclose(w[:, 0], 0.3 * np.cos(ang) - 0.4 * np.sin(ang), rtol=0, atol=1e-15)
    assert np.allclose(w[:, 2], 1.0, rtol=0, atol=0)
    r = g.rotation(t)
    assert np.allclose(r.apply(g.momentum_body(t)), g.momentum, rtol=0, atol=1e-14)
    assert FreeGyrostat([1.0, 2.0, 3.0], [0.0, 1.0, 0.0], omega0=[0.0, 0.0, 0.0]).regime == "rest"
    # h off the principal axes, a full tensor, a rotor on a symmetric body's equator
    for inertia, h in (
        ([1.0, 2.0, 3.0], [0.3, 0.0, 0.4]),
        ([[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]], [0.0, 0.0, 0.5]),
        ([1.0, 2.0, 2.0], [0.0, 0.0, 0.5]),
    ):
        g = FreeGyrostat(inertia, h, omega0=[0.3, 0.5, 0.7])
        assert g.regime == "numeric" and math.isnan(g.period)
        if np.ndim(inertia) == 1:
            t = np.array([0.0, 1.5, 3.0])
            ref = _reference(inertia, h, [0.3, 0.5, 0.7], None, t)
            assert _rel(g.omega(t), ref) < 1e-9  # DOP853 at rtol 1e-12; observed <= 1.4e-13
            # backwards in time: the forward run from the state reached at t = -2
            back = g.omega([-2.0])[0]
            fwd = FreeGyrostat(inertia, h, omega0=back).omega([2.0])[0]
            assert np.allclose(fwd, [0.3, 0.5, 0.7], rtol=0, atol=1e-10)
        tr = g.trajectory(np.linspace(0.0, 5.0, 11))
        assert tr.info["path"] == "solve_ivp DOP853 fallback"
        assert np.max(np.abs(tr.momentum - g.momentum)) < 1e-9


def test_batches_index_and_shapes():
    g = FreeGyrostat(
        [[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]], [0.0, 0.0, 2.0], omega0=[[0.3, 0.2, 1.0]] * 2
    )
    assert g.shape == (2,) and len(g) == 2
    assert g.regime.tolist() == ["four_roots", "axisymmetric"]
    assert g.omega(np.zeros((4, 5))).shape == (2, 4, 5, 3)
    assert g.rotation([0.0, 1.0]).shape == (2, 2)
    w1 = g[1].omega([0.5, 1.5])
    assert np.array_equal(w1, g.omega([0.5, 1.5])[1])
    tr = g.trajectory([0.0, 1.0, 2.0])
    assert tr.omega.shape == (3, 2, 3)
    assert "FreeGyrostat" in repr(g) and "FreeGyrostat" in repr(g[0])


@pytest.mark.parametrize(
    ("kwargs", "err", "match"),
    [
        ({"inertia": [1.0, 1.0, 3.0]}, InvalidInputError, "triangle inequality"),
        ({"inertia": [1.0, 2.0]}, InvalidInputError, r"`inertia` to have shape"),
        ({"h": [0.0, 1.0]}, InvalidInputError, r"`h` to have shape \(\.\.\., 3\)"),
        ({"h": [0.0, np.nan, 1.0]}, InvalidInputError, "`h` to contain only finite"),
        ({"h": "abc"}, InvalidTypeError, "`h` to be array-like"),
        ({"omega0": [1.0, 2.0]}, InvalidInputError, r"`omega0` to have shape"),
        ({"omega0": [np.inf, 0, 0]}, InvalidInputError, "`omega0` to contain only finite"),
        ({"rotation0": {"w": 1}}, InvalidTypeError, "`rotation0` to be a poinsot Rotation"),
        ({"h": np.zeros((3, 3))}, InvalidInputError, r"batch \(leading\) shapes"),
    ],
)
def test_bad_inputs(kwargs, err, match):
    args = {"inertia": [1.0, 2.0, 3.0], "h": [0.0, 0.0, 1.0], "omega0": [0.0, 0.0, 1.0]}
    args.update(kwargs)
    inertia, h = args.pop("inertia"), args.pop("h")
    if kwargs.get("h") is not None and np.shape(kwargs["h"]) == (3, 3):
        args["omega0"] = np.zeros((2, 3))
    with pytest.raises(err, match=match):
        FreeGyrostat(inertia, h, **args)


def test_bad_inputs_of_the_functions():
    with pytest.raises(TypeError, match="positional"):
        FreeGyrostat([1, 2, 3], [0, 0, 1], [1, 2, 3])  # omega0 is keyword-only
    with pytest.raises(InvalidInputError, match="`h_rate` to have shape"):
        gyrostat_rhs([1, 2, 3], [1, 2, 3], [0, 0, 1], h_rate=[1, 2])
    with pytest.raises(InvalidInputError, match="`torque` to contain only finite"):
        gyrostat_rhs([1, 2, 3], [1, 2, 3], [0, 0, 1], [np.nan, 0, 0])
    with pytest.raises(InvalidInputError, match="`h` to be along one principal axis"):
        gyrostat_spin_stable([1, 2, 3], [1, 1, 0], [1, 0, 0])
    with pytest.raises(InvalidInputError, match="`omega` to be along one principal axis"):
        gyrostat_spin_stable([1, 2, 3], [1, 0, 0], [1, 1, 0])
    with pytest.raises(InvalidInputError, match="same principal axis"):
        gyrostat_spin_stable([1, 2, 3], [0, 1, 0], [1, 0, 0])
    with pytest.raises(InvalidInputError, match="principal moments of shape"):
        gyrostat_spin_stable(np.eye(3), [0, 1, 0], [0, 1, 0])
    g = FreeGyrostat([1, 2, 3], [0, 0, 1], omega0=[1, 2, 3])
    with pytest.raises(InvalidInputError, match="`t` to contain only finite"):
        g.omega([0.0, np.inf])
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\)"):
        g.trajectory([[0.0, 1.0]])
    with pytest.raises(InvalidTypeError, match="a single one"):
        g[0]
    with pytest.raises(InvalidTypeError, match="a single one"):
        len(g)


def _exact_diff(a, b):
    """max |a - b| of two exact ``_taylor`` outputs (rows of fixed-point integers)."""
    (ra, oa), (rb, ob) = a, b
    return max(
        abs(Fraction(x, oa) - Fraction(y, ob))
        for row_a, row_b in zip(ra, rb, strict=True)
        for x, y in zip(row_a, row_b, strict=True)
    )


def test_reference_is_converged():
    """The Taylor reference (a) against 30-digit ``mpmath.odefun`` with the attitude at
    t = 0.5, 1: observed 9.9e-32; (b) for t < 0 by time reversal, ``w(-t; h, w0) =
    -w(t; -h, -w0)``: observed 1.9e-31; (c) against itself at 32 more bits (order 40)
    over 1.2 periods of the separatrix case where integration errors are amplified most
    (~ 1 / (1 - k^2)^2): observed 3.9e-18 (|w| ~ 1; 3.5e-23 for b-side2-2e-12 at 112
    bits, amplification ~ 1 / (1 - k^2))."""
    inertia, h, w0 = [1.3, 2.1, 2.9], [0.0, 0.7, 0.0], [0.4, -0.6, 0.9]
    q0 = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_quat()
    ts = [0.5, 1.0]
    rows, one = _taylor(inertia, h, w0, q0, ts, exact=True)
    with mpmath.workdps(30):
        i = [mpmath.mpf(float(x)) for x in inertia]
        hv = [mpmath.mpf(float(x)) for x in h]

        def f(_, y):
            w, q = y[:3], y[3:]
            m = [i[k] * w[k] + hv[k] for k in range(3)]
            dw = [(m[a] * w[b] - m[b] * w[a]) / i[k] for k, a, b in _CROSS]
            dq = [
                -(q[1] * w[0] + q[2] * w[1] + q[3] * w[2]) / 2,
                (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]) / 2,
                (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]) / 2,
                (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]) / 2,
            ]
            return dw + dq

        sol = mpmath.odefun(f, 0, [mpmath.mpf(float(x)) for x in [*w0, *q0]])
        for t, row in zip(ts, rows, strict=True):
            ref = sol(mpmath.mpf(t))
            err = max(abs(mpmath.mpf(v) / one - r) for v, r in zip(row, ref, strict=True))
            assert err < 1e-28, err
    # (b) negative times
    back = _taylor(inertia, h, w0, None, [-0.7, -2.5], exact=True)
    fwd = _taylor(inertia, [-x for x in h], [-x for x in w0], None, [0.7, 2.5], exact=True)
    fwd = ([[-v for v in row] for row in fwd[0]], fwd[1])
    assert _exact_diff(back, fwd) < 1e-28
    # (c) the reference's own error next to a separatrix
    name = "a-four-roots-6e-9"
    inertia, hv, w0, _ = SEPARATRIX_CASES[name]
    bits = SEPARATRIX_BITS[name]
    g = FreeGyrostat(inertia, hv, omega0=w0)
    ts = np.linspace(0.0, 1.2 * g.period, 9)
    lo = _taylor(inertia, hv, w0, None, ts, bits=bits, exact=True)
    hi = _taylor(inertia, hv, w0, None, ts, bits=bits + 32, order=40, exact=True)
    assert _exact_diff(lo, hi) < 1e-15
