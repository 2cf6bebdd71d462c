"""1e4 satellites on one Kepler orbit under its gravity gradient: poinsot against diffrax.

Each satellite is a rigid body on the same LEO orbit (``KeplerOrbit``: ``a = 7000 km``,
``e = 0.01``, ``i = 50 deg`` by default) under the orbit-coupled gravity-gradient torque
``M_b = 3 mu / r^3 n_b x J n_b``, ``n_b = R^T r / |r|`` with ``r`` on the orbit at each
time (docs/theory.md §10.2): ``simulate(..., torque=OrbitGravityGradientTorque(J,
orbit), method="dop853")`` runs it as torque kind 6 of the compiled lane kernels
(Kepler's equation solved at every evaluation of the right-hand side). The batch: random
principal moments obeying the triangle inequality, attitudes within ~0.1 rad of the
LVLH frame, body rates the LVLH rate plus random rates of the order of the orbit rate.
The span is ``--orbits`` orbital periods.

The peer: diffrax (``Dopri8`` and ``Tsit5``, ``PIDController`` at ``rtol`` and ``atol =
rtol * n``; one ``diffeqsolve`` per body, ``jax.vmap``-ed over the batch so that every
body has its own step control as in poinsot; ``jax.jit``-compiled, the compile
excluded), with the same right-hand side written in JAX (Kepler's equation by 3 Newton
steps from ``M + e sin M``, a fixed count that is exact to rounding at ``e = 0.01``: a
loop to convergence would cost diffrax a batched while loop). diffrax runs ``--n-peer``
bodies (default 2000) and its time is scaled by ``n / n_peer`` (its vmapped steps cost
in proportion to the batch; the scaling is stated in the output).

Accuracy: the median over the first ``--n-ref`` bodies of the final attitude error (rad)
and angular velocity error (rad/s) against poinsot at ``rtol 1e-12`` (``atol 1e-12 n``);
the median, as the tumbling bodies' motion is chaotic (:func:`errors`). At each
``--rtol``, each diffrax solver's ``rtol`` is searched (half-decade grid, then refined,
as ``bench_gyrostat.equal_accuracy``) for the loosest one whose attitude error is at
most poinsot's; the faster of the two solvers at equal accuracy is the ratio's peer.

Timing: the median of ``--repeat`` rounds, interleaved (``bench_gyrostat.interleaved``);
BLAS pinned to one thread (``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``,
``MKL_NUM_THREADS`` set before NumPy loads); poinsot on all cores; XLA on all cores (its
default). The machine load is printed at the start and the end.

Run: ``python benchmarks/bench_orbit.py [--n 10000] [--n-peer 2000] [--orbits 10]
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


def errors(q, w, q_ref, w_ref) -> tuple[float, float]:
    """Median over the bodies of the final attitude error (rad) and of the largest
    component of the angular velocity error (rad/s). The median, not the largest: a
    tumbling body's motion here is chaotic (errors grow exponentially), so that the
    tail of the batch measures chaos, not the integrators (the reference at rtol 1e-12
    itself differs from one at 1e-13 by up to ~2 rad on a few bodies, by 1e-9 rad on
    the median one)."""
    dq = np.minimum(np.linalg.norm(q - q_ref, axis=-1), np.linalg.norm(q + q_ref, axis=-1))
    angle = 4.0 * np.arcsin(np.clip(dq / 2.0, 0.0, 1.0))  # |q - p| = 2 sin(angle / 4)
    return float(np.median(angle)), float(np.median(np.abs(w - w_ref).max(axis=-1)))


def leo_orbit(a_km: float = 7000.0, e: float = 0.01, inc_deg: float = 50.0):
    from poinsot.dynamics import KeplerOrbit

    return KeplerOrbit(a_km * 1e3, e, math.radians(inc_deg), math.radians(30.0),
                       math.radians(40.0), 0.0)  # fmt: skip


def satellites(n: int, orbit, seed: int = 0) -> tuple[np.ndarray, ...]:
    """``(moments, quat, omega)`` of ``n`` random satellites near the LVLH attitude."""
    from poinsot import Rotation
    from poinsot.dynamics import orbit_frame

    rng = np.random.default_rng(seed)
    moments = np.empty((0, 3))
    while len(moments) < n:  # principal moments in [100, 1000] kg m^2 obeying A + B >= C
        m = rng.uniform(100.0, 1000.0, (2 * n, 3))
        s = np.sort(m, axis=1)
        moments = np.concatenate([moments, m[s[:, 0] + s[:, 1] > 1.02 * s[:, 2]]])
    moments = moments[:n]
    nn = orbit.mean_motion
    off = Rotation.from_rotvec(rng.normal(scale=0.1, size=(n, 3)))  # body from LVLH
    rot = orbit_frame(*orbit.state(0.0), frame="lvlh") * off
    # the LVLH frame turns at -n about its y axis; body rate = that + a random rate ~ n
    omega = off.inv().apply([0.0, -nn, 0.0]) + rng.normal(scale=nn, size=(n, 3))
    return moments, rot.as_quat(), omega


def poinsot_solver(moments, quat, omega, orbit, t_end):
    from poinsot.dynamics import OrbitGravityGradientTorque, simulate

    torque = OrbitGravityGradientTorque(moments, orbit)
    t = np.array([0.0, t_end])
    nn = orbit.mean_motion

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        tr = simulate(moments, quat, omega, t, torque=torque, method="dop853", rtol=rtol,
                      atol=rtol * nn)  # fmt: skip
        assert tr.info["solver"].startswith("DOP853 (compiled") and "path" not in tr.info
        run.steps = tr.info["steps"]  # type: ignore[attr-defined]
        return tr.quat[-1], tr.omega[-1]

    return run


def diffrax_solver(moments, quat, omega, orbit, t_end, name):
    """diffrax ``name`` (Dopri8, Tsit5) + PIDController, vmapped over the batch."""
    import diffrax
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    nn, e = orbit.mean_motion, orbit.e
    m0 = orbit._mean0 - nn * orbit.epoch
    b = math.sqrt((1.0 - e) * (1.0 + e))
    pp, qq = (jnp.asarray(orbit.perifocal[:, k]) for k in (0, 1))

    def rhs(t, y, jm):
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
        mean = m0 + nn * t
        mean = mean - 2.0 * jnp.pi * jnp.floor((mean + jnp.pi) / (2.0 * jnp.pi))
        ea = mean + e * jnp.sin(mean)
        for _ in range(3):  # Newton: error e^2 -> e^5 -> e^11 -> below rounding
            ea = ea - (ea - e * jnp.sin(ea) - mean) / (1.0 - e * jnp.cos(ea))
        c, s = jnp.cos(ea), jnp.sin(ea)
        g = 1.0 - e * c
        v = pp * ((c - e) / g) + qq * (b * s / g)  # unit direction, inertial axes
        # n_b = R^T v / |q|^2 (the rotation matrix of q, transposed)
        rt = jnp.stack(
            [
                jnp.stack([q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 + q0 * q3),
                           2 * (q1 * q3 - q0 * q2)]),
                jnp.stack([2 * (q1 * q2 - q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3,
                           2 * (q2 * q3 + q0 * q1)]),
                jnp.stack([2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1),
                           q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3]),
            ]
        )  # fmt: skip
        nb = rt @ v / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        torque = (3.0 * nn * nn / (g * g * g)) * jnp.cross(nb, jm * nb)
        dw = (jnp.cross(jm * w, w) + torque) / jm  # J w' = J w x w + M
        return jnp.concatenate([dq, dw])

    term = diffrax.ODETerm(rhs)
    solver = {"Dopri8": diffrax.Dopri8, "Tsit5": diffrax.Tsit5}[name]()

    def one(y0, jm, rtol):
        ctrl = diffrax.PIDController(rtol=rtol, atol=rtol * nn)
        sol = diffrax.diffeqsolve(
            term, solver, 0.0, t_end, None, y0, args=jm, stepsize_controller=ctrl,
            max_steps=1_000_000, saveat=diffrax.SaveAt(t1=True),
        )  # fmt: skip
        return sol.ys[-1], sol.stats["num_steps"]

    solve = jax.jit(jax.vmap(one, in_axes=(0, 0, None)))
    y0 = jnp.asarray(np.concatenate([quat, omega], axis=1))
    jm = jnp.asarray(moments)
    steps: list[np.ndarray] = []

    def run(rtol: float) -> tuple[np.ndarray, np.ndarray]:
        y, ns = solve(y0, jm, jnp.float64(rtol))
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
    ap.add_argument("--orbits", type=float, default=10.0)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-6, 1e-9])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--solvers", nargs="+", default=["Tsit5", "Dopri8"])
    args = ap.parse_args()
    print(load())
    cores = os.cpu_count() or 1
    print(f"BLAS pinned to 1 thread (environment); poinsot and XLA on all {cores} cores")
    orbit = leo_orbit()
    t_end = args.orbits * orbit.period
    moments, quat, omega = satellites(args.n, orbit, args.seed)
    n_peer = min(args.n_peer, args.n)
    scale = args.n / n_peer
    print(f"{args.n} satellites on {orbit!r}, {args.orbits:g} orbits = {t_end:.0f} s; "
          f"diffrax on the first {n_peer} (times scaled by {scale:g}); errors on the first "
          f"{args.n_ref} against poinsot at rtol 1e-12")  # fmt: skip

    ours = poinsot_solver(moments, quat, omega, orbit, t_end)
    ref_run = poinsot_solver(moments[: args.n_ref], quat[: args.n_ref], omega[: args.n_ref],
                             orbit, t_end)  # fmt: skip
    t0 = time.perf_counter()
    q_ref, w_ref = ref_run(1e-12)
    print(f"  (reference: poinsot rtol 1e-12 on {args.n_ref} bodies, "
          f"{time.perf_counter() - t0:.1f} s)")  # fmt: skip
    sub = slice(0, args.n_ref)

    def on_subset(run):
        def r(rtol):
            q, w = run(rtol)
            return q[sub], w[sub]

        return r

    peers = {}
    for name in args.solvers:
        run = diffrax_solver(moments[:n_peer], quat[:n_peer], omega[:n_peer], orbit, t_end,
                             name)  # fmt: skip
        t0 = time.perf_counter()
        run(args.rtol[0])
        print(f"  (diffrax {name} compile + first run: {time.perf_counter() - t0:.1f} s, "
              "excluded)")  # fmt: skip
        peers[name] = run

    for rtol in args.rtol:
        print(f"\nrtol {rtol:g} (atol rtol * n):")
        err = errors(*on_subset(ours)(rtol), q_ref, w_ref)
        print(f"  poinsot: attitude error {err[0]:.1e} rad, omega error {err[1]:.1e} rad/s")
        fns: dict[str, Callable[[], object]] = {
            "poinsot dop853 (kind 6, lanes)": lambda rtol=rtol: ours(rtol)
        }
        errs = {"poinsot dop853 (kind 6, lanes)": err}
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
        base = times["poinsot dop853 (kind 6, lanes)"]
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
