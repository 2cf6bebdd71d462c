"""Work-precision benchmark: batch rigid-body dynamics against SciPy's DOP853.

For each case (a batch of torque-free asymmetric bodies; the same bodies under a
constant body torque; heavy tops about a fixed point) every method is run over a
sweep of tolerances or step sizes; the error of each run is the largest error of
the final attitude (rad, ``2 |q - q_ref|`` with the sign of ``q`` chosen) or body
angular velocity (rad/s) over the batch, against

* the exact Euler-Poinsot solution (``FreeRigidBody``) for the free bodies;
* SciPy ``solve_ivp(DOP853)`` at ``rtol = 1e-13`` for the torqued cases, whose own
  error is measured by comparing it with ``rtol = 5e-14`` (printed).

The time to reach a given error is interpolated (log-log) between the sweep
points, and the ratio ``SciPy time / poinsot time`` at the same error is printed
for 1e-6, 1e-9 and 1e-12. SciPy integrates the whole batch as one vectorised
``7 N`` system (its fastest use), its BLAS pinned to one thread (threadpoolctl,
when installed: see ``blas_one_thread``). A work-precision figure (error against time,
every method) is written to ``docs/_static/work_precision.png`` with ``--figure``.

Run: ``.venv/bin/python benchmarks/bench_fused.py [--n 100000] [--figure]``.
Single body over many periods: ``--one``.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import time

import numpy as np
from scipy.integrate import solve_ivp

from poinsot.dynamics import FreeRigidBody, simulate
from poinsot.dynamics.torques import ConstantBodyTorque, GravityTorque

DURATION = 10.0
TARGETS = (1e-6, 1e-9, 1e-12)


def bodies(n, seed=0):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))
    omega = rng.normal(size=(n, 3))
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return moments, quat, omega


def blas_one_thread():
    """SciPy's BLAS on one thread: solve_ivp takes norms of the long state through BLAS,
    and on a shared machine each call waits for its second thread (about 10x slower for
    the same evaluations; issue 24). Without threadpoolctl: not pinned (printed)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


def scipy_batch(moments, quat, omega, t_end, rtol, torque=None):
    """SciPy DOP853 on the whole batch as one vectorised 7N system."""
    n = len(moments)
    inv = 1.0 / moments.T

    def rhs(_t, y):
        y = y.reshape(7, n)
        q, w = y[:4], y[4:]
        f = np.empty_like(y)
        f[0] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2])
        f[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
        f[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2])
        f[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])
        m = np.cross(moments.T * w, w, axis=0)
        if torque is not None:
            m = m + torque(q)
        f[4:] = m * inv
        return f.ravel()

    y0 = np.concatenate([quat.T, omega.T]).ravel()
    with blas_one_thread():
        sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    y = sol.y[:, -1].reshape(7, n).T
    return y[:, :4] / np.linalg.norm(y[:, :4], axis=1, keepdims=True), y[:, 4:]


def gravity_numpy(moment):
    """Body torque ``gamma x (m g c)`` with ``gamma = R^T e_z`` (the fused kernel's kind 3)."""

    def torque(q):
        w, x, y, z = q
        n2 = w * w + x * x + y * y + z * z
        gamma = np.array([2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z])
        return np.cross(gamma / n2, moment.T, axis=0)

    return torque


def error(result, ref):
    q, w = result
    dq = np.minimum(np.linalg.norm(q - ref[0], axis=-1), np.linalg.norm(q + ref[0], axis=-1))
    return float(max(np.max(2 * dq), np.max(np.abs(w - ref[1]))))


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def at_error(points, target):
    """Time to reach ``target`` error, interpolated log-log between sweep points."""
    pts = sorted((e, t) for t, e in points if e > 0)
    errs = np.log10([p[0] for p in pts])
    times = np.log10([p[1] for p in pts])
    lt = np.log10(target)
    if lt < errs.min() or lt > errs.max():
        return float("nan")
    order = np.argsort(errs)
    return float(10 ** np.interp(lt, errs[order], times[order]))


def run_case(
    name,
    moments,
    quat,
    omega,
    torque_model,
    torque_np,
    ref,
    sweep_extra,
    scipy_tols=(1e-5, 1e-7, 1e-9, 1e-11, 1e-13),
):
    t = np.array([0.0, DURATION])
    curves = {}

    def poinsot_run(method, **kw):
        tr = simulate(moments, quat, omega, t, torque=torque_model, method=method, **kw)
        return tr.quat[-1], tr.omega[-1]

    simulate(
        moments[:2], quat[:2], omega[:2], t, torque=torque_model, method="dop853", rtol=1e-6
    )  # compile outside the timings

    def point(fn):
        dt, res = timed(fn)
        return dt, error(res, ref)

    tols = (1e-5, 1e-7, 1e-9, 1e-11, 1e-13)
    curves["poinsot dop853 (fused)"] = [
        point(lambda rt=rt: poinsot_run("dop853", rtol=rt, atol=rt * 1e-2)) for rt in tols
    ]
    curves["SciPy DOP853 (vectorised 7N)"] = [
        point(lambda rt=rt: scipy_batch(moments, quat, omega, DURATION, rt, torque_np))
        for rt in scipy_tols
    ]
    for label, method, kws in sweep_extra:
        curves[label] = [point(lambda kw=kw, m=method: poinsot_run(m, **kw)) for kw in kws]
    print(f"\n{name}: N = {len(moments)}, {DURATION} s")
    for label, pts in curves.items():
        print(f"  {label:32s} " + "  ".join(f"{e:.1e}@{s:.2f}s" for s, e in pts))
    sci = curves["SciPy DOP853 (vectorised 7N)"]
    fused = curves["poinsot dop853 (fused)"]
    for target in TARGETS:
        ts, tf = at_error(sci, target), at_error(fused, target)
        print(f"  error {target:.0e}: SciPy {ts:.3f} s, fused {tf:.3f} s, ratio {ts / tf:.1f}x")
    return curves


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--figure", action="store_true")
    ap.add_argument("--one", action="store_true", help="one body over 1e4 periods")
    args = ap.parse_args()
    pinned = importlib.util.find_spec("threadpoolctl") is not None
    print(f"SciPy's BLAS {'pinned to 1 thread' if pinned else 'NOT pinned (no threadpoolctl)'}")
    if args.one:
        one_body()
        return
    moments, quat, omega = bodies(args.n)
    t = np.array([0.0, DURATION])
    exact = FreeRigidBody(moments, rotation0=quat, omega0=omega)
    ref_free = (exact.rotation(t).as_quat()[:, -1], exact.omega(t)[:, -1])  # batch first
    extra = [
        (
            "poinsot splitting order 6",
            "splitting",
            [dict(order=6, max_step=h) for h in (0.05, 0.02, 0.01)],
        ),
        ("poinsot midpoint order 6", "midpoint", [dict(order=6, max_step=h) for h in (0.05, 0.02)]),
        ("poinsot rk4", "rk4", [dict(max_step=h) for h in (0.01, 0.003)]),
    ]
    all_curves = {}
    all_curves["free"] = run_case(
        "torque-free bodies",
        moments,
        quat,
        omega,
        None,
        None,
        ref_free,
        extra if args.n <= 10_000 else [],
    )
    # exact solution, same error axis: its error is round-off
    dt, res = timed(lambda: (exact.rotation(t).as_quat()[:, -1], exact.omega(t)[:, -1]))
    print(f"  exact FreeRigidBody: {dt:.3f} s (the fastest and most accurate route)")
    all_curves["free"]["poinsot exact (Jacobi)"] = [(dt, 1e-15)]

    # Torqued cases: the reference is SciPy's DOP853 at rtol = 1e-13 (so SciPy's own sweep
    # stops at 1e-12); its error is estimated against rtol = 5e-14 on the first 1000 bodies.
    sub = slice(0, min(args.n, 1000))
    torque = np.array([0.05, -0.02, 0.03])
    tq = ConstantBodyTorque(torque)
    tq_np = lambda q: torque[:, None]  # noqa: E731
    com = np.array([0.0, 0.0, 0.1])
    grav = GravityTorque(1.0, com)
    for key, title, model, fn in (
        ("torque", "constant body torque", tq, lambda m: tq_np),
        (
            "heavy",
            "heavy top (gravity about a fixed point)",
            grav,
            lambda m: gravity_numpy(np.broadcast_to(grav.moment, m.shape)),
        ),
    ):
        ref = scipy_batch(moments, quat, omega, DURATION, 1e-13, fn(moments))
        ref_a = (ref[0][sub], ref[1][sub])
        ref2 = scipy_batch(moments[sub], quat[sub], omega[sub], DURATION, 5e-14, fn(moments[sub]))
        print(f"\nDOP853 reference ({key}) self-error: {error(ref_a, ref2):.1e}")
        all_curves[key] = run_case(
            title,
            moments,
            quat,
            omega,
            model,
            fn(moments),
            ref,
            [],
            scipy_tols=(1e-5, 1e-7, 1e-9, 1e-11, 1e-12),
        )
    if args.figure:
        figure(all_curves, args.n)


def one_body():
    """One asymmetric body over ~1e4 periods: fused DOP853 vs solve_ivp(DOP853)."""
    moments = np.array([[1.0, 2.0, 3.0]])
    quat = np.array([[1.0, 0.0, 0.0, 0.0]])
    omega = np.array([[0.3, 2.0, 0.2]])
    exact = FreeRigidBody(moments, rotation0=quat, omega0=omega)
    t_end = 1e4 * 2 * np.pi / 2.0
    t = np.array([0.0, t_end])
    ref = (exact.rotation(t).as_quat()[:, -1], exact.omega(t)[:, -1])
    simulate(moments, quat, omega, t[:1].tolist() + [1.0], method="dop853", rtol=1e-6)
    print(f"\none body, {t_end:.0f} s (~1e4 periods)")
    pts_f, pts_s = [], []
    for rt in (1e-7, 1e-9, 1e-11):
        dt, tr = timed(
            lambda rt=rt: simulate(
                moments, quat, omega, t, method="dop853", rtol=rt, atol=rt * 1e-2
            )
        )
        pts_f.append((dt, error((tr.quat[-1], tr.omega[-1]), ref)))
        dt, r = timed(lambda rt=rt: scipy_batch(moments, quat, omega, t_end, rt))
        pts_s.append((dt, error(r, ref)))
    print("  fused " + "  ".join(f"{e:.1e}@{s:.3f}s" for s, e in pts_f))
    print("  SciPy " + "  ".join(f"{e:.1e}@{s:.3f}s" for s, e in pts_s))
    for ts, target in pts_s:  # at each error SciPy reached, the fused time to reach it
        tf = at_error(pts_f, target)
        print(f"  error {target:.1e}: SciPy {ts:.3f} s, fused {tf:.4f} s, ratio {ts / tf:.0f}x")


def figure(all_curves, n):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    titles = {
        "free": f"torque-free, N = {n}",
        "torque": "constant body torque",
        "heavy": "heavy top",
    }
    for ax, (key, curves) in zip(axes, all_curves.items(), strict=False):
        for label, pts in curves.items():
            pts = sorted(pts, key=lambda p: -p[1])  # along the sweep (noisy times zigzag)
            ax.loglog([p[0] for p in pts], [max(p[1], 1e-16) for p in pts], "o-", label=label)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("max final error (rad, rad/s)")
        ax.set_title(titles[key])
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right")
    fig.savefig("docs/_static/work_precision.png", dpi=110)
    print("wrote docs/_static/work_precision.png")


if __name__ == "__main__":
    main()
