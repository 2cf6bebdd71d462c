"""1e4 heterogeneous gyrostats (issue 41): poinsot's fused DOP853 lanes against diffrax.

Each body is a gyrostat with constant rotor momentum ``h`` (body axes): ``J w' + w x
(J w + h) = 0`` (docs/theory.md §10.1), integrated by ``simulate(..., torque=
GyrostaticTorque(h), method="dop853")`` (the torque ``h x w`` fused into the compiled
lane kernel) and by diffrax (``Dopri8``, ``PIDController`` at the same ``rtol`` and
``atol = rtol / 100``, one ``diffeqsolve`` per body ``jax.vmap``-ed over the batch, so
that every body has its own step control as in poinsot; ``jax.jit``-compiled, the
compile excluded: a warm-up call first). The batch: random principal moments obeying
the triangle inequality, ``h`` along a random principal axis with a random magnitude
and sign (the dual-spin gyrostat, whose exact motion :class:`~poinsot.dynamics.
FreeGyrostat` gives), random ``w0`` and attitudes; the span is ``--periods`` times the
median period of ``w`` over the batch.

Accuracy: the largest final attitude error (rad, angle of ``R_ref^T R``) and angular
velocity error (rad/s) over the batch against FreeGyrostat's exact solution (set up
once, ~27 ms per body in exact rational arithmetic; cached in the temporary directory).
The ratio is taken at equal accuracy too: diffrax's ``rtol`` is searched on a
half-decade grid (then refined, as ``bench_peers.tolerance_for``) for the loosest one
whose attitude error is at most poinsot's at ``--rtol``.

Timing: the median of ``--repeat`` rounds, interleaved (each round runs every solver
once, in turn, so that a slow spell of the shared machine falls on all alike); BLAS
pinned to one thread (``OPENBLAS_NUM_THREADS``/``MKL_NUM_THREADS`` set before NumPy
loads; nothing here calls BLAS in the timed runs); poinsot on 1 and on all cores
(``set_num_threads``); XLA on all cores (its default, as in ``bench_peers.py``) or, with
``--xla-one-thread``, on one (``XLA_FLAGS``, set before JAX loads). The machine load is
printed at the start and the end.

Run: ``python benchmarks/bench_gyrostat.py [--n 10000] [--periods 20] [--rtol 1e-10]
[--repeat 5] [--xla-one-thread]``.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from collections.abc import Callable

# before NumPy and JAX load
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
if "--xla-one-thread" in sys.argv:
    os.environ["XLA_FLAGS"] = (
        os.environ.get("XLA_FLAGS", "")
        + " --xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
    ).strip()

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from _timing import table  # noqa: E402


def load() -> str:
    a, b, c = os.getloadavg()
    return f"load average {a:.2f} / {b:.2f} / {c:.2f} (1/5/15 min) on {os.cpu_count()} cores"


def gyrostats(n: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    """``(moments, h, quat, omega)`` of ``n`` random dual-spin gyrostats."""
    rng = np.random.default_rng(seed)
    moments = np.empty((0, 3))
    while len(moments) < n:  # principal moments in [0.5, 3] obeying A + B >= C
        m = rng.uniform(0.5, 3.0, (2 * n, 3))
        s = np.sort(m, axis=1)
        moments = np.concatenate([moments, m[s[:, 0] + s[:, 1] > 1.02 * s[:, 2]]])
    moments = moments[:n]
    h = np.zeros((n, 3))
    h[np.arange(n), rng.integers(0, 3, n)] = rng.uniform(-1.5, 1.5, n)  # kg m^2/s
    omega = rng.normal(size=(n, 3))
    omega *= (rng.uniform(0.5, 2.0, n) / np.linalg.norm(omega, axis=1))[:, None]
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return moments, h, quat, omega


def reference(moments, h, quat, omega, periods, seed):
    """``(t_end, q_ref, w_ref)``: FreeGyrostat's exact final state, cached on disk."""
    path = os.path.join(
        tempfile.gettempdir(), f"poinsot-bench-gyrostat-{len(moments)}-{seed}-{periods}.npz"
    )
    if os.path.exists(path):
        z = np.load(path)
        if np.array_equal(z["omega0"], omega) and np.array_equal(z["h"], h):
            print(f"  (exact reference from the cache {path})")
            return float(z["t_end"]), z["q"], z["w"]
    from poinsot.dynamics import FreeGyrostat

    t0 = time.perf_counter()
    exact = FreeGyrostat(moments, h, rotation0=quat, omega0=omega)
    period = np.asarray(exact.period)
    t_end = float(periods * np.median(period[np.isfinite(period)]))
    q = exact.rotation(t_end).as_quat()
    w = exact.omega(t_end)
    print(f"  (exact reference: FreeGyrostat, {time.perf_counter() - t0:.0f} s for the batch)")
    np.savez(path, omega0=omega, h=h, t_end=t_end, q=q, w=w)
    return t_end, q, w


def errors(q, w, q_ref, w_ref) -> tuple[float, float]:
    """Largest attitude error (rad) and angular velocity error (rad/s) over the batch."""
    dq = np.minimum(np.linalg.norm(q - q_ref, axis=-1), np.linalg.norm(q + q_ref, axis=-1))
    angle = 4.0 * np.arcsin(np.clip(dq / 2.0, 0.0, 1.0))  # |q - p| = 2 sin(angle / 4)
    return float(angle.max()), float(np.abs(w - w_ref).max())


def poinsot_solver(moments, h, quat, omega, t_end, threads):
    from poinsot.dynamics import GyrostaticTorque, simulate
    from poinsot.rotations import set_num_threads

    torque = GyrostaticTorque(h)
    t = np.array([0.0, t_end])

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        set_num_threads(threads)  # pinned: the default follows the load average
        try:
            tr = simulate(moments, quat, omega, t, torque=torque, method="dop853",
                          rtol=rtol, atol=rtol * 1e-2)  # fmt: skip
        finally:
            set_num_threads(None)
        run.steps = tr.info["steps"]  # type: ignore[attr-defined]
        return tr.quat[-1], tr.omega[-1]

    return run


def diffrax_solver(moments, h, quat, omega, t_end):
    """diffrax Dopri8 + PIDController, one solve per body vmapped over the batch."""
    import diffrax
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    def rhs(_t, y, args):
        jm, hv = args
        q, w = y[:4], y[4:]
        dq = 0.5 * jnp.stack(
            [
                -(q[1] * w[0] + q[2] * w[1] + q[3] * w[2]),
                q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                q[0] * w[1] + q[3] * w[0] - q[1] * w[2],
                q[0] * w[2] + q[1] * w[1] - q[2] * w[0],
            ]
        )
        dw = jnp.cross(jm * w + hv, w) / jm  # J w' = (J w + h) x w
        return jnp.concatenate([dq, dw])

    term = diffrax.ODETerm(rhs)
    solver = diffrax.Dopri8()

    def one(y0, jm, hv, rtol):
        ctrl = diffrax.PIDController(rtol=rtol, atol=rtol * 1e-2)
        sol = diffrax.diffeqsolve(
            term, solver, 0.0, t_end, None, y0, args=(jm, hv), stepsize_controller=ctrl,
            max_steps=1_000_000, saveat=diffrax.SaveAt(t1=True),
        )  # fmt: skip
        return sol.ys[-1], sol.stats["num_steps"]

    solve = jax.jit(jax.vmap(one, in_axes=(0, 0, 0, None)))
    y0 = jnp.asarray(np.concatenate([quat, omega], axis=1))
    jm, hv = jnp.asarray(moments), jnp.asarray(h)
    steps: list[np.ndarray] = []

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        y, ns = solve(y0, jm, hv, jnp.float64(rtol))
        y = np.asarray(y.block_until_ready())
        steps[:] = [np.asarray(ns)]
        q = y[:, :4] / np.linalg.norm(y[:, :4], axis=1, keepdims=True)
        return q, y[:, 4:]

    run.steps = steps  # type: ignore[attr-defined]
    return run


def equal_accuracy(run, q_ref, w_ref, target, start, measure=None):
    """The loosest ``rtol`` on a half-decade grid from ``start`` (refined once, log-log)
    whose attitude error is at most ``target``: ``(rtol, errors)``; ``measure(q, w, q_ref,
    w_ref)`` the errors (default :func:`errors`, the largest over the batch)."""
    errors = globals()["errors"] if measure is None else measure
    tol = start
    err = errors(*run(tol), q_ref, w_ref)
    if err[0] <= target:  # looser while it stays within the target
        while True:
            e = errors(*run(tol * math.sqrt(10.0)), q_ref, w_ref)
            if e[0] > target:
                bracket = (tol * math.sqrt(10.0), e[0])
                break
            tol, err = tol * math.sqrt(10.0), e
    else:
        while err[0] > target:
            if tol < 1e-14:
                return math.nan, (math.nan, math.nan)
            bracket = (tol, err[0])
            tol /= math.sqrt(10.0)
            err = errors(*run(tol), q_ref, w_ref)
    (t1, e1), (t2, e2) = bracket, (tol, err[0])
    if e1 > e2 > 0:  # refine between the grid points: error ~ rtol^p
        p = math.log(e1 / e2) / math.log(t1 / t2)
        cand = min(t2 * (target / e2) ** (1.0 / p) * 0.9, t1 / 1.05)
        if cand > t2:
            e = errors(*run(cand), q_ref, w_ref)
            if e[0] <= target:
                tol, err = cand, e
    return tol, err


def interleaved(fns: dict[str, Callable[[], object]], repeat: int) -> dict[str, float]:
    """Per name, the median over ``repeat`` rounds (after a warm-up round) of one call;
    each round calls every function once, in turn."""
    times: dict[str, list[float]] = {name: [] for name in fns}
    for r in range(repeat + 1):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            if r:
                times[name].append(time.perf_counter() - t0)
    return {name: float(np.median(ts)) for name, ts in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--periods", type=float, default=20.0)
    ap.add_argument("--rtol", type=float, default=1e-10)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--xla-one-thread", action="store_true")
    args = ap.parse_args()
    print(load())
    cores = os.cpu_count() or 1
    xla = "1 thread (XLA_FLAGS)" if args.xla_one_thread else f"all {cores} cores"
    print(f"BLAS pinned to 1 thread (environment); XLA on {xla}")
    moments, h, quat, omega = gyrostats(args.n, args.seed)
    t_end, q_ref, w_ref = reference(moments, h, quat, omega, args.periods, args.seed)
    print(f"{args.n} dual-spin gyrostats, {args.periods:g} median periods = {t_end:.1f} s, "
          f"rtol {args.rtol:g}, atol rtol/100")  # fmt: skip

    runs = {
        f"poinsot dop853 lanes ({cores} threads)": poinsot_solver(
            moments, h, quat, omega, t_end, cores
        ),
        "poinsot dop853 lanes (1 thread)": poinsot_solver(moments, h, quat, omega, t_end, 1),
    }
    dfx = diffrax_solver(moments, h, quat, omega, t_end)
    runs[f"diffrax Dopri8 vmap (jit; XLA {xla})"] = dfx
    t0 = time.perf_counter()
    dfx(args.rtol)
    print(f"  (diffrax compile + first run: {time.perf_counter() - t0:.1f} s, excluded)")
    errs = {name: errors(*run(args.rtol), q_ref, w_ref) for name, run in runs.items()}
    dfx_steps = dfx.steps[0]
    for name, (ea, ew) in errs.items():
        print(f"  {name}: attitude error {ea:.1e} rad, omega error {ew:.1e} rad/s", flush=True)
    target = errs[next(iter(runs))][0]
    tol_eq, err_eq = equal_accuracy(dfx, q_ref, w_ref, target, args.rtol)
    eq_name = f"diffrax at equal accuracy (rtol {tol_eq:.2e})"
    print(f"  (equal accuracy: diffrax at rtol {tol_eq:.2e}, errors {err_eq[0]:.1e} rad, "
          f"{err_eq[1]:.1e} rad/s)", flush=True)  # fmt: skip
    fns: dict[str, Callable[[], object]] = {
        name: (lambda run=run: run(args.rtol)) for name, run in runs.items()
    }
    if not math.isnan(tol_eq):
        fns[eq_name] = lambda: dfx(tol_eq)
        errs[eq_name] = err_eq
    times = interleaved(fns, args.repeat)
    ours = times[next(iter(runs))]
    rows = [
        [name, f"{times[name]:.3f} s", f"{errs[name][0]:.1e}", f"{errs[name][1]:.1e}",
         f"{times[name] / ours:.2f}x"]
        for name in fns
    ]  # fmt: skip
    print(table(rows, ["solver", f"median of {args.repeat}", "attitude err (rad)",
                       "omega err (rad/s)", "time / poinsot"]))  # fmt: skip
    ps = runs[next(iter(runs))].steps  # type: ignore[attr-defined]
    print(
        f"  (accepted steps per body at rtol {args.rtol:g}: poinsot median "
        f"{np.median(ps):.0f}, max {ps.max()}; diffrax median {np.median(dfx_steps):.0f}, "
        f"max {dfx_steps.max()}: a vmapped while loop runs until its slowest body ends)"
    )
    print(load())


if __name__ == "__main__":
    main()
