"""1e4 spacecraft with four reaction wheels each under constant motor torques: poinsot
against diffrax.

Each spacecraft is a rigid body carrying a 4-wheel pyramid (``pyramid(arccos(1/sqrt 3),
0.02 kg m^2)``, 0.05 N m and 600 rad/s limits) whose motors apply constant torques drawn
in ``[-0.01, 0.01]`` N m for ``--span`` seconds (600 s: a slew-like momentum exchange of
up to 6 N m s per wheel; the script checks that no wheel reaches its speed limit). The
batch: principal moments in [5, 50] kg m^2 obeying the triangle inequality (locked
inertia, wheels included), random attitudes, body rates ~ N(0, 0.02) rad/s, wheel speeds
in [-100, 100] rad/s.

poinsot: ``simulate_wheels(..., command=<(n, 4) array>)``, the batched compiled path:
Euler's equations of ``J_f = J - sum_i I_i a_i a_i^T`` under the gyrostatic torque
``(h0 + U t) x w - U`` (torque kind 5 of the compiled lane kernels, ``h_f(t) = h0 + U t``
in closed form, ``U = sum_i u_i a_i``; docs/theory.md §10.1), the wheel speeds, momenta,
energy and total momentum rebuilt after it (all included in its time).

The peer: diffrax (``Dopri8``, ``PIDController`` at ``rtol`` and ``atol = rtol * 0.01``
rad/s, the atol poinsot gets; one ``diffeqsolve`` per body, ``jax.vmap``-ed over the
batch so that every body has its own step control as in poinsot; ``jax.jit``-compiled, the
compile excluded) integrating the SAME reduced 7-state system (quaternion and ``w``, the
wheels' momentum ``h0 + U t`` in closed form, diagonal ``J_f`` as the 3 moments: its
fastest form) and returning the final state only (poinsot also rebuilds the wheel
channels). diffrax runs ``--n-peer`` bodies (default 2000) and its time is scaled by ``n
/ n_peer`` (its vmapped steps cost in proportion to the batch; stated in the output).

Accuracy: the median over the first ``--n-ref`` bodies of the final attitude error (rad)
and angular velocity error (rad/s) against poinsot at ``rtol 1e-12`` (``atol 1e-14``),
as ``bench_orbit.errors``. At each ``--rtol``, diffrax's ``rtol`` is searched
(half-decade grid, then refined, ``bench_gyrostat.equal_accuracy``) for the loosest one
whose attitude error is at most poinsot's.

Timing: the median of ``--repeat`` rounds, interleaved (``bench_gyrostat.interleaved``);
BLAS pinned to one thread (``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``,
``MKL_NUM_THREADS`` set before NumPy loads); poinsot on all cores; XLA on all cores (its
default). The machine load (/proc/loadavg) is printed at the start and the end.

Run: ``python benchmarks/bench_wheels.py [--n 10000] [--n-peer 2000] [--span 600]
[--rtol 1e-6 1e-9] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from collections.abc import Callable

# before NumPy and JAX load
for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from _timing import table  # noqa: E402
from bench_gyrostat import equal_accuracy, interleaved, load  # noqa: E402
from bench_orbit import errors  # noqa: E402

#: atol / rtol (rad/s): the body rates are ~0.01-0.3 rad/s.
ATOL_SCALE = 0.01


def spacecraft(n: int, seed: int = 0) -> tuple[object, tuple[np.ndarray, ...]]:
    """``(wheels, (moments, quat, omega, wheel_speed, command))`` of ``n`` spacecraft."""
    from poinsot.dynamics import pyramid

    rng = np.random.default_rng(seed)
    wheels = pyramid(math.acos(1.0 / math.sqrt(3.0)), 0.02, max_torque=0.05, max_speed=600.0)
    moments = np.empty((0, 3))
    while len(moments) < n:  # principal moments in [5, 50] kg m^2 obeying A + B >= C
        m = rng.uniform(5.0, 50.0, (2 * n, 3))
        s = np.sort(m, axis=1)
        moments = np.concatenate([moments, m[s[:, 0] + s[:, 1] > 1.02 * s[:, 2]]])
    moments = moments[:n]
    quat = _random_quat(rng, n)
    omega = rng.normal(scale=0.02, size=(n, 3))
    speed = rng.uniform(-100.0, 100.0, (n, 4))
    command = rng.uniform(-0.01, 0.01, (n, 4))
    return wheels, (moments, quat, omega, speed, command)


def _random_quat(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` uniformly random unit quaternions, scalar part >= 0."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return q * np.where(q[:, :1] < 0.0, -1.0, 1.0)


def poinsot_solver(wheels, moments, quat, omega, speed, command, t_end):
    from poinsot.dynamics import simulate_wheels

    t = np.array([0.0, t_end])

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        atol = 1e-14 if rtol <= 1e-12 else rtol * ATOL_SCALE
        tr = simulate_wheels(moments, wheels, quat, omega, speed, t, command=command,
                             rtol=rtol, atol=atol)  # fmt: skip
        assert tr.info["solver"].startswith("DOP853 (compiled")
        run.steps = tr.info["steps"]  # type: ignore[attr-defined]
        run.speed = tr.wheel_speed  # type: ignore[attr-defined]
        return tr.quat[-1], tr.omega[-1]

    return run


def diffrax_solver(wheels, moments, quat, omega, speed, command, t_end, name="Dopri8"):
    """diffrax ``name`` + PIDController, vmapped over the batch: the reduced 7-state form
    ``J_f w' = (h0 + U t) x w - U - w x J_f w`` (``J_f`` diagonal here)."""
    import diffrax
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    axes, moments_w = wheels.axes, wheels.inertia
    jf = moments[:, None, :] * np.eye(3) - wheels.axial_inertia
    assert np.allclose(jf, np.eye(3) * np.diagonal(jf, axis1=1, axis2=2)[:, None, :], atol=1e-15)
    jf = np.diagonal(jf, axis1=1, axis2=2).copy()
    h_abs0 = moments_w * (speed + omega @ axes.T)
    h0 = h_abs0 @ axes
    rate = command @ axes

    def rhs(t, y, args):
        jm, h, u = args
        q, w = y[:4], y[4:]
        q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
        dq = 0.5 * jnp.stack(
            [
                -(q1 * w[0] + q2 * w[1] + q3 * w[2]),
                q0 * w[0] + q2 * w[2] - q3 * w[1],
                q0 * w[1] + q3 * w[0] - q1 * w[2],
                q0 * w[2] + q1 * w[1] - q2 * w[0],
            ]
        )
        dw = (jnp.cross(jm * w + h + u * t, w) - u) / jm  # J w' = (J w + h(t)) x w - U
        return jnp.concatenate([dq, dw])

    term = diffrax.ODETerm(rhs)
    solver = {"Dopri8": diffrax.Dopri8, "Tsit5": diffrax.Tsit5}[name]()

    def one(y0, args, rtol):
        ctrl = diffrax.PIDController(rtol=rtol, atol=rtol * ATOL_SCALE)
        sol = diffrax.diffeqsolve(
            term, solver, 0.0, t_end, None, y0, args=args, stepsize_controller=ctrl,
            max_steps=1_000_000, saveat=diffrax.SaveAt(t1=True),
        )  # fmt: skip
        return sol.ys[-1], sol.stats["num_steps"]

    solve = jax.jit(jax.vmap(one, in_axes=(0, 0, None)))
    y0 = jnp.asarray(np.concatenate([quat, omega], axis=1))
    args = (jnp.asarray(jf), jnp.asarray(h0), jnp.asarray(rate))
    steps: list[np.ndarray] = []

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        y, ns = solve(y0, args, jnp.float64(rtol))
        y = np.asarray(y.block_until_ready())
        steps[:] = [np.asarray(ns)]
        q = y[:, :4] / np.linalg.norm(y[:, :4], axis=1, keepdims=True)
        return q, y[:, 4:]

    run.steps = steps  # type: ignore[attr-defined]
    return run


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--n-peer", type=int, default=2000)
    ap.add_argument("--n-ref", type=int, default=1000)
    ap.add_argument("--span", type=float, default=600.0)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-6, 1e-9])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--solvers", nargs="+", default=["Dopri8"])
    args = ap.parse_args()
    print(load())
    cores = os.cpu_count() or 1
    print(f"BLAS pinned to 1 thread (environment); poinsot and XLA on all {cores} cores")
    wheels, (moments, quat, omega, speed, command) = spacecraft(args.n, args.seed)
    t_end = args.span
    n_peer = min(args.n_peer, args.n)
    scale = args.n / n_peer
    print(f"{args.n} spacecraft with a 4-wheel pyramid each, constant motor torques, "
          f"{t_end:g} s; diffrax on the first {n_peer} (times scaled by {scale:g}); errors "
          f"on the first {args.n_ref} against poinsot at rtol 1e-12")  # fmt: skip

    ours = poinsot_solver(wheels, moments, quat, omega, speed, command, t_end)
    nr = slice(0, args.n_ref)
    ref_run = poinsot_solver(wheels, moments[nr], quat[nr], omega[nr], speed[nr], command[nr],
                             t_end)  # fmt: skip
    t0 = time.perf_counter()
    q_ref, w_ref = ref_run(1e-12)
    print(f"  (reference: poinsot rtol 1e-12 on {args.n_ref} bodies, "
          f"{time.perf_counter() - t0:.1f} s)")  # fmt: skip
    t0 = time.perf_counter()
    ours(args.rtol[0])
    top = float(np.abs(ours.speed).max())  # type: ignore[attr-defined]
    print(f"  (poinsot first run {time.perf_counter() - t0:.1f} s; largest wheel speed at the "
          f"ends {top:.0f} rad/s, limit 600: no saturation)")  # fmt: skip
    assert top < 600.0

    def on_subset(run):
        def r(rtol):
            q, w = run(rtol)
            return q[nr], w[nr]

        return r

    peers = {}
    for name in args.solvers:
        run = diffrax_solver(wheels, moments[:n_peer], quat[:n_peer], omega[:n_peer],
                             speed[:n_peer], command[:n_peer], t_end, name)  # fmt: skip
        t0 = time.perf_counter()
        run(args.rtol[0])
        print(f"  (diffrax {name} compile + first run: {time.perf_counter() - t0:.1f} s, "
              "excluded)")  # fmt: skip
        peers[name] = run

    label0 = "poinsot simulate_wheels (kind 5, lanes)"
    for rtol in args.rtol:
        print(f"\nrtol {rtol:g} (atol rtol * {ATOL_SCALE:g}):")
        err = errors(*on_subset(ours)(rtol), q_ref, w_ref)
        print(f"  poinsot: attitude error {err[0]:.1e} rad, omega error {err[1]:.1e} rad/s")
        fns: dict[str, Callable[[], object]] = {label0: lambda rtol=rtol: ours(rtol)}
        errs = {label0: err}
        for name, run in peers.items():
            tol, e = equal_accuracy(on_subset(run), q_ref, w_ref, err[0], rtol, errors)
            print(f"  diffrax {name}: equal accuracy at rtol {tol:.2e}: errors {e[0]:.1e} rad, "
                  f"{e[1]:.1e} rad/s", flush=True)  # fmt: skip
            if math.isnan(tol):
                continue
            label = f"diffrax {name} vmap (rtol {tol:.2e}; x{scale:g})"
            fns[label] = lambda run=run, tol=tol: run(tol)
            errs[label] = e
        times = interleaved(fns, args.repeat)
        for label in times:
            if label.startswith("diffrax"):
                times[label] *= scale
        base = times[label0]
        rows = [
            [label, f"{times[label]:.3f} s", f"{errs[label][0]:.1e}", f"{errs[label][1]:.1e}",
             f"{times[label] / base:.2f}x"]
            for label in fns
        ]  # fmt: skip
        head = [f"solver ({args.n} bodies)", f"median of {args.repeat}"]
        head += ["median attitude err (rad)", "median omega err (rad/s)", "time / poinsot"]
        print(table(rows, head))
        ps = ours.steps  # type: ignore[attr-defined]
        line = f"  (accepted steps per body: poinsot median {np.median(ps):.0f}, max {ps.max()}"
        for name, run in peers.items():
            st = run.steps[0]  # type: ignore[attr-defined]
            line += f"; diffrax {name} (last run) median {np.median(st):.0f}, max {st.max()}"
        print(line + ")")
    print(load())


if __name__ == "__main__":
    main()
