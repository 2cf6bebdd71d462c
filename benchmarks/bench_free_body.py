"""Benchmark of the exact free rigid body (poinsot.dynamics.FreeRigidBody).

Two workloads (issue 9, "fast for one rotation as for a million"):

1. one generic body at 1,000,000 time points (over 1000 s, ~40 periods): the
   angular velocity alone, and the angular velocity with the attitude (a
   ``Rotation``);
2. a batch of 100,000 random bodies (random moments, states and attitudes:
   major, minor and near-separatrix regimes) evaluated at one time each, in one
   vectorised call: construction (validation + the compiled per-body setup) and
   evaluation.

Peers measured in the same process: the same closed form evaluated with
``scipy.special`` on the same arrays -- special functions only, i.e. a lower
bound of any SciPy-based implementation (no attitude assembly, no case
analysis): ``ellipj`` for omega, plus ``elliprj`` for the precession integral;
for the batch also the per-body constants ``ellipk``, ``ellipkinc`` and the
complete ``elliprj``. And ``solve_ivp(DOP853, rtol=1e-13)`` for workload 1 (with
its error against the exact solution).

Prints medians of several runs, ns per point (or per body) and the ratio
peer / poinsot (> 1 = poinsot faster). The machine is shared: compare ratios.

Run: ``.venv/bin/python benchmarks/bench_free_body.py [--no-dop853]``
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from scipy import integrate, special

from poinsot import Rotation, SingularityWarning
from poinsot.dynamics import FreeRigidBody
from poinsot.dynamics import _free_body_numba as kern

N = 1_000_000
SPAN = 1000.0
N_BODIES = 100_000


def median_time(fn, repeat=5):
    fn()  # warm-up (numba compilation / cache load)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def dop853(moments, w0, t):
    inertia = np.asarray(moments, float)

    def f(_, y):
        w, q = y[:3], y[3:]
        dw = np.cross(inertia * w, w) / inertia
        return np.concatenate([dw, [-0.5 * q[1:] @ w], 0.5 * (q[0] * w + np.cross(q[1:], w))])

    sol = integrate.solve_ivp(
        f, (0.0, t[-1]), np.r_[w0, 1.0, 0, 0, 0], method="DOP853", rtol=1e-13, atol=1e-14,
        t_eval=t,
    )  # fmt: skip
    return sol.y[:3].T, sol.y[3:].T


def table(rows, n, unit):
    header = ["poinsot", "time (s)", f"ns/{unit}", "peer", "peer time (s)", "ratio"]
    rows = [
        [a, f"{t:.3f}", f"{1e9 * t / n:.0f}", p, f"{tp:.3f}", f"{tp / t:.1f}"]
        for a, t, p, tp in rows
    ]
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(6)]
    for r in [header, ["-" * w for w in widths], *rows]:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths, strict=True)))


def one_body(run_dop853: bool):
    moments, w0 = [1.0, 2.0, 3.0], np.array([0.3, 1.0, 0.2])
    body = FreeRigidBody(moments, omega0=w0)
    par = body._par[0]  # the constants of the closed form, for the SciPy peer
    ws = body._wscale[0]
    t = np.linspace(0.0, SPAN, N)
    print(f"1) body {moments}, omega0 {w0.tolist()}, regime {body.regime}, period "
          f"{body.period:.4f} s; {N:,} time points over {SPAN:g} s")  # fmt: skip
    t_omega = median_time(lambda: body.omega(t))
    t_state = median_time(lambda: body.state(t))
    u = par[kern.P_LAM] * ws * t + par[kern.P_U0]
    k2, n2 = par[kern.P_K2], par[kern.P_N2]

    def scipy_attitude_special():
        sn, cn, dn, _ = special.ellipj(u, k2)
        return special.elliprj(cn * cn, dn * dn, 1.0, 1.0 + n2 * sn * sn)

    s_omega = median_time(lambda: special.ellipj(u, k2))
    s_att = median_time(scipy_attitude_special)
    rows = [
        ("omega(t)", t_omega, "scipy.special.ellipj", s_omega),
        ("state(t): omega + Rotation", t_state, "scipy ellipj + elliprj", s_att),
    ]
    if run_dop853:
        t0 = time.perf_counter()
        w_ref, q_ref = dop853(moments, w0, t)
        t_ivp = time.perf_counter() - t0
        rows.append(("state(t): omega + Rotation", t_state, "solve_ivp DOP853 1e-13", t_ivp))
    table(rows, N, "point")
    if run_dop853:
        w, rot = body.state(t)
        err_w = np.max(np.abs(w - w_ref))
        err_r = np.max((rot.inv() * Rotation.from_quat(q_ref)).magnitude())
        print(f"DOP853 vs exact over {SPAN:g} s: max |dw| = {err_w:.2e} rad/s, "
              f"max attitude error = {err_r:.2e} rad")  # fmt: skip


def random_bodies(n, rng):
    """Random physical moments (A + B >= C), states and attitudes."""
    mom = rng.uniform(1.0, 3.0, (2 * n, 3))
    s = np.sort(mom, axis=-1)
    mom = mom[s[:, 0] + s[:, 1] >= s[:, 2]][:n]
    w0 = rng.normal(size=(n, 3))
    q0 = rng.normal(size=(n, 4))
    q0 /= np.linalg.norm(q0, axis=-1, keepdims=True)
    return mom, w0, q0


def batch(n):
    rng = np.random.default_rng(0)
    mom, w0, q0 = random_bodies(n, rng)
    t1 = np.array(7.3)
    print(f"\n2) a batch of {n:,} random bodies, one time each")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        bodies = FreeRigidBody(mom, rotation0=q0, omega0=w0)
        t_make = median_time(lambda: FreeRigidBody(mom, rotation0=q0, omega0=w0), repeat=3)
    t_omega = median_time(lambda: bodies.omega(t1))
    t_state = median_time(lambda: bodies.state(t1))
    regimes, counts = np.unique(bodies.regime, return_counts=True)
    print("   regimes: " + ", ".join(f"{r} {c}" for r, c in zip(regimes, counts, strict=True)))
    # SciPy peer: the special functions of the same closed form for every body
    # (the per-body constants and the evaluation), on the same arrays
    par = bodies._par
    k2 = par[:, kern.P_K2]
    m1 = par[:, kern.P_M1]
    n2 = par[:, kern.P_N2]
    phi0 = np.linspace(0.1, 1.4, n)
    u = par[:, kern.P_LAM] * bodies._wscale * 7.3 + par[:, kern.P_U0]

    def scipy_setup():
        return (
            special.ellipk(k2),
            special.ellipkinc(phi0, k2),
            special.elliprj(0.0, m1, 1.0, 1.0 + n2),
        )

    def scipy_eval():
        sn, cn, dn, _ = special.ellipj(u, k2)
        return special.elliprj(cn * cn, dn * dn, 1.0, 1.0 + n2 * sn * sn)

    s_setup = median_time(scipy_setup, repeat=3)
    s_omega = median_time(lambda: special.ellipj(u, k2))
    s_eval = median_time(scipy_eval)
    table(
        [
            ("FreeRigidBody(...) (setup)", t_make, "ellipk + ellipkinc + elliprj", s_setup),
            ("omega(t)", t_omega, "scipy.special.ellipj", s_omega),
            ("state(t): omega + Rotation", t_state, "ellipj + elliprj", s_eval),
            ("setup + state(t)", t_make + t_state, "all of the above", s_setup + s_eval),
        ],
        n,
        "body",
    )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-dop853", action="store_true", help="skip the 5-10 s DOP853 peer")
    ap.add_argument("--bodies", type=int, default=N_BODIES)
    args = ap.parse_args()
    one_body(not args.no_dop853)
    batch(args.bodies)


if __name__ == "__main__":
    main()
