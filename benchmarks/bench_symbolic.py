"""Benchmark: ``poinsot.symbolic`` against SymPy's ``LagrangesMethod`` / ``KanesMethod``
+ ``lambdify`` on an n-link planar pendulum (n = 1, 2, 3, 5, 8, 12).

Measured for each n (medians of several runs, same process):

1. derivation time: poinsot ``LagrangeSystem(q, T, P)`` -> ``mass_matrix``, ``forcing``
   against SymPy ``LagrangesMethod(L, q).form_lagranges_equations()`` and
   ``KanesMethod.kanes_equations`` (from the same particles), and the time of
   SymPy's ``rhs()`` (a symbolic solve) where it finishes (capped, see ``--rhs-cap``);
2. the time to build the numeric function: ``to_numeric().compile()`` (cse + numba,
   cold: a fresh cache directory) against ``lambdify``;
3. right-hand-side evaluations per second for one state and for a batch of 10^4
   states: poinsot's compiled ``f(t, y)`` against ``lambdify(rhs())`` (NumPy,
   vectorised over the batch) and, for every n, ``lambdify(M), lambdify(F)`` +
   ``numpy.linalg.solve`` (what a SymPy user does when ``rhs()`` is too slow);
4. the time of a 10 s simulation with ``solve_ivp(DOP853, rtol=1e-10, atol=1e-12)``
   driven by each right-hand side.

Run: ``.venv/bin/python benchmarks/bench_symbolic.py [--quick] [--n 1 2 3]``.
The machine may be shared and loaded: ratios measured in the same run matter, not
absolute times.
"""

# ruff: noqa: B023  (the closures timed in each loop iteration run within it)
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_time, table  # noqa: E402


def pendulum(n):
    """Points, particles and coordinates of an n-link pendulum (unit masses and lengths
    as symbols ``m``, ``l``; gravity ``g`` along -y)."""
    import sympy
    from sympy.physics import mechanics as me

    q = me.dynamicsymbols(f"q1:{n + 1}")
    u = me.dynamicsymbols(f"u1:{n + 1}")
    m, l, g = sympy.symbols("m l g", positive=True)
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    frames, points, parts = [], [], []
    prev = O
    for i in range(n):
        Fi = N.orientnew(f"A{i}", "Axis", [q[i], N.z])
        Pi = prev.locatenew(f"P{i}", -l * Fi.y)
        Pi.v2pt_theory(prev, N, Fi)
        pa = me.Particle(f"pa{i}", Pi, m)
        pa.potential_energy = m * g * Pi.pos_from(O).dot(N.y)
        frames.append(Fi)
        points.append(Pi)
        parts.append(pa)
        prev = Pi
    return q, u, (m, l, g), N, O, frames, points, parts


def kane_setup(n):
    import sympy  # noqa: F401
    from sympy.physics import mechanics as me

    q, u, (m, l, g), N, O, frames, points, parts = pendulum(n)
    prev = O
    for i in range(n):
        frames[i].set_ang_vel(N, u[i] * N.z)
        points[i].v2pt_theory(prev, N, frames[i])
        prev = points[i]
    kd = [q[i].diff() - u[i] for i in range(n)]
    kane = me.KanesMethod(N, q, u, kd_eqs=kd)
    loads = [(points[i], -m * g * N.y) for i in range(n)]
    return kane, parts, loads


def _solve_batch(M, F):
    return np.linalg.solve(M, F[..., None])[..., 0]


def _stack(entries, shape, nb):
    arr = np.empty((nb, *shape))
    flat = arr.reshape(nb, -1)
    for k, e in enumerate(entries):
        flat[:, k] = e
    return arr


def run(ns, rhs_cap, quick):
    import sympy
    from sympy.physics import mechanics as me

    from poinsot.symbolic import LagrangeSystem

    reps = 3 if quick else 5
    rows_d, rows_e, rows_s = [], [], []
    params = {"m": 1.0, "l": 1.0, "g": 9.81}
    for n in ns:
        q, u, (m, l, g), N, *_, parts = pendulum(n)
        T = me.kinetic_energy(N, *parts)
        P = sum(p.potential_energy for p in parts)
        L = T - P

        # ---- derivation
        def ours():
            s = LagrangeSystem(q, T, P)
            s._MF  # noqa: B018  (M and F, in the plain symbols used by to_numeric)
            return s

        def sympy_lagrange():
            lm = me.LagrangesMethod(L, q)
            lm.form_lagranges_equations()
            return lm

        t_ours = median_time(ours, repeat=reps)
        t_lm = median_time(sympy_lagrange, repeat=reps)

        def sympy_kane():
            kane, parts_k, loads = kane_setup(n)
            kane.kanes_equations(parts_k, loads)
            return kane

        t_km = median_time(sympy_kane, repeat=max(1, reps - 2))
        system = ours()
        lm = sympy_lagrange()
        t_rhs = None
        rhs_expr = None
        if n <= rhs_cap:
            t0 = time.perf_counter()
            rhs_expr = lm.rhs()
            t_rhs = time.perf_counter() - t0
        # ---- numeric functions
        with tempfile.TemporaryDirectory() as cache:
            os.environ["POINSOT_CACHE_DIR"] = cache
            t0 = time.perf_counter()
            f = system.to_numeric(params).compile()
            t_num = time.perf_counter() - t0
            del os.environ["POINSOT_CACHE_DIR"]
        qd = [qi.diff() for qi in q]
        args = [*q, *qd, m, l, g]
        t0 = time.perf_counter()
        mf = (sympy.lambdify(args, lm.mass_matrix), sympy.lambdify(args, lm.forcing))
        mf_flat = (
            sympy.lambdify(args, list(lm.mass_matrix)),
            sympy.lambdify(args, list(lm.forcing)),
        )
        t_lmf = time.perf_counter() - t0
        lam_rhs = lam_rhs_flat = None
        if rhs_expr is not None:
            t0 = time.perf_counter()
            lam_rhs = sympy.lambdify(args, rhs_expr)
            lam_rhs_flat = sympy.lambdify(args, list(rhs_expr))
            t_lrhs = time.perf_counter() - t0
        rows_d.append(
            [
                n,
                f"{t_ours:.3g}",
                f"{t_lm:.3g}",
                f"{t_km:.3g}",
                f"{t_lm / t_ours:.1f}x",
                "-" if t_rhs is None else f"{t_rhs:.3g}",
                f"{t_num:.3g}",
                f"{t_lmf:.3g}" + ("" if lam_rhs is None else f" / {t_lrhs:.3g}"),
            ]
        )
        # ---- evaluations
        rng = np.random.default_rng(n)
        y1 = rng.normal(size=2 * n)
        pv = (1.0, 1.0, 9.81)

        def sym_mf_one(y=y1):
            M = np.asarray(mf[0](*y, *pv), dtype=float)
            F = np.asarray(mf[1](*y, *pv), dtype=float).ravel()
            return np.concatenate([y[n:], np.linalg.solve(M, F)])

        def sym_rhs_one(y=y1):
            return np.asarray(lam_rhs(*y, *pv), dtype=float).ravel()

        ref = sym_mf_one()
        assert np.allclose(f(0.0, y1), ref, rtol=1e-9, atol=1e-9), "rhs mismatch"
        number = 200 if quick else 1000
        t_one = median_time(lambda: f(0.0, y1), repeat=reps, number=number)
        t_one_mf = median_time(sym_mf_one, repeat=reps, number=max(10, number // 10))
        t_one_rhs = (
            median_time(sym_rhs_one, repeat=reps, number=max(10, number // 10)) if lam_rhs else None
        )
        nb = 10_000
        yb = rng.normal(size=(nb, 2 * n))
        cols = [yb[:, k] for k in range(2 * n)]

        def sym_mf_batch():
            Ms = _stack(mf_flat[0](*cols, *pv), (n, n), nb)
            Fs = _stack(mf_flat[1](*cols, *pv), (n,), nb)
            return np.concatenate([yb[:, n:], _solve_batch(Ms, Fs)], axis=1)

        def sym_rhs_batch():
            return _stack(lam_rhs_flat(*cols, *pv), (2 * n,), nb)

        assert np.allclose(f(0.0, yb[:5]), sym_mf_batch()[:5], rtol=1e-9, atol=1e-9)
        if lam_rhs:
            assert np.allclose(f(0.0, yb[:5]), sym_rhs_batch()[:5], rtol=1e-9, atol=1e-9)
        t_b = median_time(lambda: f(0.0, yb), repeat=reps)
        t_b_mf = median_time(sym_mf_batch, repeat=reps)
        t_b_rhs = median_time(sym_rhs_batch, repeat=reps) if lam_rhs else None
        best_one = t_one_rhs if t_one_rhs else t_one_mf
        best_b = t_b_rhs if t_b_rhs else t_b_mf
        rows_e.append(
            [
                n,
                f"{1 / t_one:.3g}",
                "-" if t_one_rhs is None else f"{1 / t_one_rhs:.3g}",
                f"{1 / t_one_mf:.3g}",
                f"{t_one_rhs / t_one:.0f}x" if t_one_rhs else "-",
                f"{t_one_mf / t_one:.0f}x",
                f"{nb / t_b:.3g}",
                "-" if t_b_rhs is None else f"{nb / t_b_rhs:.3g}",
                f"{nb / t_b_mf:.3g}",
                f"{t_b_rhs / t_b:.0f}x" if t_b_rhs else "-",
                f"{t_b_mf / t_b:.0f}x",
            ]
        )
        del best_one, best_b
        # ---- 10 s simulation
        y0 = np.concatenate([np.full(n, 0.5), np.zeros(n)])
        opts = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-12}

        def sim_ours():
            return solve_ivp(f, (0.0, 10.0), y0, **opts)

        def sim_mf():
            return solve_ivp(lambda _t, y: sym_mf_one(y), (0.0, 10.0), y0, **opts)

        s_ours = sim_ours()
        t_sim = median_time(sim_ours, repeat=max(1, reps - 2))
        t_sim_mf = median_time(sim_mf, repeat=1)
        t_sim_rhs = None
        if lam_rhs:
            t_sim_rhs = median_time(
                lambda: solve_ivp(lambda _t, y: sym_rhs_one(y), (0.0, 10.0), y0, **opts),
                repeat=1,
            )
        rows_s.append(
            [
                n,
                s_ours.nfev,
                f"{t_sim:.3g}",
                "-" if t_sim_rhs is None else f"{t_sim_rhs:.3g}",
                f"{t_sim_mf:.3g}",
                f"{(t_sim_rhs or t_sim_mf) / t_sim:.0f}x",
            ]
        )
        print(f"n = {n}: derivation {rows_d[-1][1:]}, evaluations/s {rows_e[-1][1:]}, "
              f"simulation {rows_s[-1][1:]}", flush=True)  # fmt: skip
    print("\nDerivation (s; ratio = LagrangesMethod / poinsot) and numeric build (s)")
    print(
        table(
            rows_d,
            ["n", "poinsot", "LagrangesMethod", "KanesMethod", "ratio", "LM.rhs()",
             "to_numeric+numba", "lambdify M,F / rhs"],
        )
    )  # fmt: skip
    print("\nRight-hand side evaluations per second (one state; batch of 10^4 states)")
    print(
        table(
            rows_e,
            ["n", "poinsot 1", "lambdify rhs 1", "lambdify M,F+solve 1", "x rhs", "x M,F",
             "poinsot batch", "lambdify rhs batch", "M,F+solve batch", "x rhs", "x M,F"],
        )
    )  # fmt: skip
    print("\n10 s simulation, solve_ivp DOP853 rtol 1e-10 (s)")
    print(table(rows_s, ["n", "nfev", "poinsot", "lambdify rhs", "lambdify M,F+solve", "speed-up"]))
    print(f"\n(LM.rhs() = SymPy's symbolic solve, attempted for n <= {rhs_cap}.)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--n", type=int, nargs="*", default=[1, 2, 3, 5, 8, 12])
    ap.add_argument("--rhs-cap", type=int, default=5)
    a = ap.parse_args()
    run(a.n, a.rhs_cap, a.quick)
