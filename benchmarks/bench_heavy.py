"""Benchmark of the heavy body (HeavyRigidBody) and the exact Lagrange top (LagrangeTop).

Workloads (issue 11):

1. exact Lagrange top: ``rotation(t)`` and ``theta(t)`` at 1,000,000 times (about
   870 nutation periods), against ``scipy.integrate.solve_ivp(DOP853)`` integrating
   the same motion with a tolerance chosen so that its error is at least as large
   as the closed form's (errors measured against the closed form);
2. drift over 1,000,000 steps of the default integrator (free-body Lie-Poisson
   splitting with exact gravity kicks, order 2, and its 4th-order composition) for
   an asymmetric heavy body: relative energy drift, ``K_z`` drift relative to
   ``|K|``, ``| |gamma| - 1 |``;
3. work-precision against ``solve_ivp(DOP853)`` on one asymmetric body and on a
   batch of 10,000 bodies integrated as one vectorised system (the errors of both
   measured against a tight reference): the time each needs for a given error.

Prints medians of several runs and the ratios peer / poinsot (> 1 = poinsot
faster). The machine is shared and loaded: compare ratios, not absolute times.

Run: ``.venv/bin/python benchmarks/bench_heavy.py [--quick]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

from poinsot import Rotation
from poinsot.dynamics import HeavyRigidBody, LagrangeTop

A, C, MGL = 2.0, 1.0, 4.0
J_ASYM = np.array([[1.2, 0.1, -0.05], [0.1, 1.6, 0.02], [-0.05, 0.02, 2.1]])
COM = np.array([0.05, -0.02, 0.3])


def median_time(fn, repeat=3):
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _f_batch(j, ji, mgc):
    """Euler-Poisson in (quaternion, omega) for N bodies, one vectorised NumPy rhs."""

    def f(_, y):
        y = y.reshape(-1, 7)
        q, w = y[:, :4], y[:, 4:]
        g = np.stack(
            [
                2.0 * (q[:, 1] * q[:, 3] - q[:, 0] * q[:, 2]),
                2.0 * (q[:, 2] * q[:, 3] + q[:, 0] * q[:, 1]),
                q[:, 0] ** 2 - q[:, 1] ** 2 - q[:, 2] ** 2 + q[:, 3] ** 2,
            ],
            axis=1,
        )
        jw = w @ j.T
        dw = (np.cross(g, mgc) - np.cross(w, jw)) @ ji.T
        dq = 0.5 * np.stack(
            [
                -(q[:, 1] * w[:, 0] + q[:, 2] * w[:, 1] + q[:, 3] * w[:, 2]),
                q[:, 0] * w[:, 0] + q[:, 2] * w[:, 2] - q[:, 3] * w[:, 1],
                q[:, 0] * w[:, 1] + q[:, 3] * w[:, 0] - q[:, 1] * w[:, 2],
                q[:, 0] * w[:, 2] + q[:, 1] * w[:, 1] - q[:, 2] * w[:, 0],
            ],
            axis=1,
        )
        return np.concatenate([dq, dw], axis=1).ravel()

    return f


def exact_top(n):
    top = LagrangeTop(A, C, MGL, theta=0.6, spin=15.0, precession_rate=0.4, theta_rate=0.3)
    span = 1000.0
    t = np.linspace(0.0, span, n)
    top.rotation(t[:10])  # compile
    top.theta(t[:10])
    t_rot = median_time(lambda: top.rotation(t))
    t_theta = median_time(lambda: top.theta(t))
    t_state = median_time(lambda: top.state(t))
    t_sin = median_time(lambda: np.sin(t))
    print(
        f"exact Lagrange top, {n} times over {span:g} s "
        f"({span / top.nutation_period:.0f} nutation periods):"
    )
    print(
        f"  rotation(t) {t_rot:.3f} s ({t_rot / n * 1e9:.0f} ns/point), theta(t) {t_theta:.3f} s, "
        f"state(t) (rotation + omega) {t_state:.3f} s; np.sin of the same array {t_sin:.4f} s "
        f"(machine yardstick: rotation(t) = {t_rot / t_sin:.0f} x np.sin)"
    )
    # the same motion by solve_ivp(DOP853) over a tenth of the span (n / 10 outputs)
    span2 = span / 10.0
    t2 = t[t <= span2]
    w_ex, r_ex = top.state(t2)
    q_ex = r_ex.as_quat()
    t_rot2 = median_time(lambda: top.rotation(t2))
    f = _f_batch(np.diag([A, A, C]), np.diag([1 / A, 1 / A, 1 / C]), np.array([0, 0, MGL]))
    y0 = np.concatenate([q_ex[0], w_ex[0]])
    for rtol in (1e-10, 1e-13):
        t0 = time.perf_counter()
        sol = solve_ivp(f, (0, span2), y0, method="DOP853", t_eval=t2, rtol=rtol, atol=rtol)
        el = time.perf_counter() - t0
        q = sol.y[:4].T
        err_q = np.max(
            np.minimum(np.linalg.norm(q - q_ex, axis=1), np.linalg.norm(q + q_ex, axis=1))
        )
        err_w = np.abs(sol.y[4:].T - w_ex).max()
        print(
            f"  {t2.size} times over {span2:g} s: exact rotation(t) {t_rot2:.4f} s; "
            f"solve_ivp DOP853 rtol={rtol:g}: {el:.2f} s ({sol.nfev} evaluations), "
            f"differences: attitude {err_q:.1e}, omega {err_w:.1e} rad/s; "
            f"ratio DOP853 / exact = {el / t_rot2:.0f}x"
        )


def drift(steps):
    body = HeavyRigidBody(J_ASYM, 2.0, COM, g=9.81)
    q0 = Rotation.from_euler("ZXZ", [0.3, 0.8, -0.2]).as_quat()
    w0 = [1.0, -2.0, 6.0]
    h = 1e-3
    t = np.linspace(0.0, steps * h, 1001)
    for order in (2, 4, 6):
        t0 = time.perf_counter()
        tr = body.simulate(q0, w0, t, order=order, max_step=h * (1 + 1e-9))
        el = time.perf_counter() - t0
        e = body.energy(tr.rotation, tr.omega)
        kz = body.momentum_z(tr.rotation, tr.omega)
        k = np.linalg.norm(J_ASYM @ np.asarray(w0))
        g = np.linalg.norm(body.gamma(tr.rotation), axis=-1)
        de = np.abs(e - e[0]) / abs(e[0])
        print(
            f"  splitting order {order}, {tr.info['steps']} steps of {h:g} s ({el:.1f} s): "
            f"energy max {de.max():.1e} (first half {de[:500].max():.1e}, second half "
            f"{de[500:].max():.1e}), K_z {np.abs(kz - kz[0]).max() / k:.1e}, "
            f"|gamma|-1 {np.abs(g - 1).max():.1e}"
        )


def _reference(body, q0, w0, t):
    return body.simulate(q0, w0, t, method="dop853", rtol=1e-13, atol=1e-13).omega


def work_precision(n_bodies, span):
    body = HeavyRigidBody(J_ASYM, 2.0, COM, g=9.81)
    rng = np.random.default_rng(1)
    q0 = rng.normal(size=(n_bodies, 4))
    q0 /= np.linalg.norm(q0, axis=1)[:, None]
    w0 = rng.normal(size=(n_bodies, 3)) * 2 + np.array([0, 0, 5.0])
    t = np.array([0.0, span])
    ref = _reference(body, q0, w0, t)[-1]
    f = _f_batch(J_ASYM, np.linalg.inv(J_ASYM), 2.0 * 9.81 * COM)
    y0 = np.concatenate([q0, w0], axis=1).ravel()
    rows = []
    for order, hs in ((4, (1e-2, 5e-3, 2.5e-3, 1.25e-3)), (6, (2e-2, 1e-2, 5e-3))):
        for h in hs:
            el = median_time(
                lambda h=h, o=order: body.simulate(q0, w0, t, order=o, max_step=h), repeat=3
            )
            tr = body.simulate(q0, w0, t, order=order, max_step=h)
            err = np.abs(tr.omega[-1] - ref).max()
            rows.append((f"splitting-{order}", h, el, err))
    for rtol in (1e-6, 1e-8, 1e-10):

        def run(rtol=rtol):
            return solve_ivp(f, (0, span), y0, method="DOP853", rtol=rtol, atol=rtol)

        el = median_time(run, repeat=1 if n_bodies > 1 else 3)
        sol = run()
        err = np.abs(sol.y[:, -1].reshape(-1, 7)[:, 4:] - ref).max()
        rows.append(("DOP853", rtol, el, err))
    print(
        f"work-precision, {n_bodies} bod{'y' if n_bodies == 1 else 'ies'} over {span:g} s "
        f"(max omega error vs compiled DOP853 rtol 1e-13):"
    )
    for name, par, el, err in rows:
        print(f"  {name:12s} {par:9.3g}  {el:8.4f} s  error {err:.1e}")

    # time at equal accuracy: log-log interpolation of each method's curve
    def time_at(name, target):
        pts = sorted((r[3], r[2]) for r in rows if r[0] == name)
        e = np.log([p[0] for p in pts])
        tm = np.log([p[1] for p in pts])
        return float(np.exp(np.interp(np.log(target), e, tm)))

    for target in (1e-6, 1e-8):
        td = time_at("DOP853", target)
        for name in ("splitting-4", "splitting-6"):
            ts = time_at(name, target)
            print(
                f"  at error {target:g}: {name} {ts:.4f} s, DOP853 {td:.4f} s, "
                f"ratio DOP853 / {name} = {td / ts:.2f}x"
            )


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true")
    a = p.parse_args()
    exact_top(100_000 if a.quick else 1_000_000)
    print("drift of the default integrator (asymmetric body):")
    drift(100_000 if a.quick else 1_000_000)
    work_precision(1, 10.0)
    work_precision(1000 if a.quick else 10_000, 1.0)
    print("(machine shared and loaded: compare ratios)")


if __name__ == "__main__":
    main()
