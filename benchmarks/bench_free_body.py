"""Benchmark of the exact free rigid body (poinsot.dynamics.FreeRigidBody).

1,000,000 time points (over 1000 s, ~40 periods) of a generic body: the angular
velocity alone, and the angular velocity with the attitude (a ``Rotation``).
Peers measured in the same process:

* the same closed form evaluated with ``scipy.special`` (``ellipj`` for omega,
  plus ``elliprj`` for the precession integral): the obvious vectorised
  implementation, special functions only (no attitude assembly);
* ``scipy.integrate.solve_ivp(DOP853, rtol=1e-13, atol=1e-14)`` of Euler's
  equations + quaternion kinematics with the same 10^6 output times (and its
  error against the exact solution).

Prints the median of several runs and the ratio peer / poinsot (> 1 = poinsot
faster). Target (issue 4): omega and attitude for 10^6 points under 1 s.

Run: ``.venv/bin/python benchmarks/bench_free_body.py``
"""

from __future__ import annotations

import time

import numpy as np
from scipy import integrate, special

from poinsot import Rotation
from poinsot.dynamics import FreeRigidBody

N = 1_000_000
SPAN = 1000.0


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


def main():
    moments, w0 = [1.0, 2.0, 3.0], np.array([0.3, 1.0, 0.2])
    body = FreeRigidBody(moments, omega0=w0)
    mo = body._motion  # the constants of the closed form, for the SciPy peer
    t = np.linspace(0.0, SPAN, N)
    print(f"body {moments}, omega0 {w0.tolist()}, regime {body.regime}, period "
          f"{body.period:.4f} s; {N:,} time points over {SPAN:g} s")  # fmt: skip

    t_omega = median_time(lambda: body.omega(t))
    t_state = median_time(lambda: body.state(t))

    u = mo.lam * t + mo.u0

    def scipy_omega():
        return special.ellipj(u, mo.k2)

    def scipy_attitude_special():
        sn, cn, dn, _ = special.ellipj(u, mo.k2)
        return special.elliprj(cn * cn, dn * dn, 1.0, 1.0 + mo.n2 * sn * sn)

    s_omega = median_time(scipy_omega)
    s_att = median_time(scipy_attitude_special)

    t0 = time.perf_counter()
    w_ref, q_ref = dop853(moments, w0, t)
    t_ivp = time.perf_counter() - t0
    w, rot = body.state(t)
    err_w = np.max(np.abs(w - w_ref))
    err_r = np.max((rot.inv() * Rotation.from_quat(q_ref)).magnitude())

    rows = [
        ["omega(t)", f"{t_omega:.3f}", "scipy.special.ellipj", f"{s_omega:.3f}",
         f"{s_omega / t_omega:.1f}"],
        ["state(t): omega + Rotation", f"{t_state:.3f}", "scipy ellipj + elliprj",
         f"{s_att:.3f}", f"{s_att / t_state:.1f}"],
        ["state(t): omega + Rotation", f"{t_state:.3f}", "solve_ivp DOP853 rtol 1e-13",
         f"{t_ivp:.3f}", f"{t_ivp / t_state:.1f}"],
    ]  # fmt: skip
    header = ["poinsot", "time (s)", "peer", "peer time (s)", "ratio"]
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(5)]
    for r in [header, ["-" * w for w in widths], *rows]:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths, strict=True)))
    print(f"\ntarget: omega + attitude for 1e6 points < 1 s: "
          f"{'met' if t_state < 1.0 else 'NOT met'} ({t_state:.3f} s)")  # fmt: skip
    print(f"DOP853 vs exact over {SPAN:g} s: max |dw| = {err_w:.2e} rad/s, "
          f"max attitude error = {err_r:.2e} rad")  # fmt: skip

    print("\nstate(t) for 10^6 points by regime:")
    others = {
        "near separatrix (1 - k^2 ~ 2e-4)": ([1.0, 2.0, 3.0], [0.01, 1.0, 0.01]),
        "separatrix": ([6.0, 5.0, 2.0], [1.0, 0.5, 1.0]),
        "symmetric": ([2.0, 2.0, 1.0], [0.3, 0.4, 1.0]),
        "inertia tensor (non-diagonal)": (
            Rotation.from_rotvec([0.3, 0.2, 0.1]).as_matrix() @ np.diag([1.0, 2.0, 3.0])
            @ Rotation.from_rotvec([0.3, 0.2, 0.1]).as_matrix().T,
            [0.3, 1.0, 0.2],
        ),
    }  # fmt: skip
    for name, (inertia, omega0) in others.items():
        b = FreeRigidBody(inertia, omega0)
        print(f"  {name:34s} {median_time(lambda b=b: b.state(t), repeat=3):.3f} s")


if __name__ == "__main__":
    main()
