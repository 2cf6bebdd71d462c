"""progress= and Ctrl-C in the other long calls (issue 21): particles, Lagrangian
systems, exact solutions on large grids.

As tests/dynamics/test_interrupt.py: a real subprocess gets a real SIGINT 2 s into a
run that would last much longer; it must raise ``KeyboardInterrupt`` within 1.5 s and
leave no thread. Progress callables see increasing fractions ending at 1; the results
are bit-identical with and without progress (and chunked or not).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from poinsot.dynamics import CentralOrbit, FreeRigidBody, LagrangeTop, kepler, simulate_particle
from poinsot.kinematics import FrameMotion

SRC = str(Path(__file__).parents[2] / "src")

_SCRIPT = textwrap.dedent(
    """
    import signal, sys, threading, time
    import numpy as np
    signal.signal(signal.SIGINT, signal.default_int_handler)  # see test_interrupt.py
    from poinsot.dynamics import FreeRigidBody, simulate_particle
    from poinsot.kinematics import FrameMotion

    def main():
        # a guard: Dask's worker processes are spawned and import this file
        which = sys.argv[1]
        if which == "particle":
            def run(n):
                return simulate_particle(FrameMotion(omega=[0, 0, 1.0]), lambda t, r, v: -r,
                                         [1.0, 0, 0], [0, 0.5, 0], np.linspace(0, n, 11),
                                         rtol=1e-13, atol=1e-15)
            small, big = 1.0, 1e6
        elif which == "lagrangian":
            import sympy
            x = sympy.Function("x")(sympy.Symbol("t"))
            from poinsot.symbolic import LagrangeSystem
            osc = LagrangeSystem([x], x.diff() ** 2 / 2, x**4 / 4)
            def run(n):
                return osc.simulate([1.0], [0.0], np.linspace(0, n, 11), rtol=1e-13, atol=1e-15)
            small, big = 1.0, 1e7
        elif which == "midpoint-torque":
            from poinsot.dynamics import GravityTorque, simulate
            grav = GravityTorque(1.0, [0.0, 0.0, 0.4], g=10.0)   # depends on the attitude
            w0 = np.random.default_rng(0).normal(size=(2000, 3)) * 5.0
            def run(n):
                return simulate([2.0, 2.0, 1.0], [1, 0, 0, 0], w0[: int(min(n, 2000))],
                                np.linspace(0, n, 201), torque=grav, max_step=1e-3)
            small, big = 2, 4000.0
        elif which.startswith("one-interval"):
            # issue 38: a SciPy user's [0, T], two output times: the step loops read the
            # cancel flag once per output interval (a hoisted load), so Ctrl-C waited
            # for the end of the whole run (30 s and more)
            from poinsot.dynamics import simulate
            method = which.split(":")[1]
            w0 = np.random.default_rng(0).normal(size=(20000, 3)) * 3.0
            def run(n):
                if method == "dop853":  # many bodies, each many adaptive steps
                    return simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], w0, [0.0, n],
                                    method="dop853", rtol=1e-12, atol=1e-14)
                return simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [1.0, 2.0, 3.0], [0.0, n],
                                method=method, max_step=1e-3)
            small, big = 1.0, 1e6
        elif which == "free-body":
            body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 1.0, 0.2])
            def run(n):
                return body.trajectory(np.linspace(0, 100, int(n)))
            small, big = 10, 6e6  # ~10 s at ~1.9 us per sample (0.5 GB)
        elif which.startswith("ensemble"):
            from poinsot.ensemble import EnsembleProblem, Metric, Normal, run as ens_run
            p = EnsembleProblem("racket", np.diag([1.0, 2.0, 3.0]), np.array([1.0, 0, 0, 0]),
                                np.array([0.01, 2.0, 0.01]), np.linspace(0, 15, 301),
                                dispersions=(("omega0", Normal(sigma=[0.005, 0.05, 0.005])),),
                                metrics=(Metric("flip", "first_flip_time"),))
            client = "serial"
            if which == "ensemble-dask":
                from dask.distributed import Client, LocalCluster
                cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                       dashboard_address=None, host="127.0.0.1")
                client = Client(cluster)
            def run(n):
                return ens_run(p, int(n), chunk_size=100, client=client, seed=1)
            small, big = 200, 2e6  # ~20 ms a chunk: minutes for 20000 chunks
        run(small)  # compile before the clock starts
        print("ready", flush=True)
        try:
            run(big)
            print("finished", flush=True)
        except KeyboardInterrupt:
            print("caught", flush=True)  # the latency ends here (not at the exit)
            if which == "ensemble-dask":  # nothing of ours may still run on the cluster
                time.sleep(0.5)
                busy = sum(len(v) for v in client.processing().values())
                client.close()
                cluster.close()
                print(f"interrupted {1 + busy}", flush=True)
            else:
                print(f"interrupted {len(threading.enumerate())}", flush=True)
        except MemoryError:
            print("memory", flush=True)

    if __name__ == "__main__":
        main()
    """
)


@pytest.mark.parametrize(
    "which",
    [
        "particle",
        "lagrangian",
        "free-body",
        "midpoint-torque",
        "ensemble-serial",
        "ensemble-dask",
        "one-interval:midpoint",
        "one-interval:rk4",
        "one-interval:splitting",
        "one-interval:dop853",
    ],
)
def test_ctrl_c_stops_long_calls(which, tmp_path):
    if which == "lagrangian":
        pytest.importorskip("sympy", reason="the symbolic extra")
    if which.startswith("ensemble"):
        pytest.importorskip("pyarrow", reason="the ensemble extra")
    if which == "ensemble-dask":
        pytest.importorskip("dask.distributed", reason="the ensemble extra")
    script = tmp_path / "long_call.py"
    script.write_text(_SCRIPT)
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen([sys.executable, str(script), which], stdout=subprocess.PIPE,
                            text=True, env=env)  # fmt: skip
    watchdog = threading.Timer(120.0, proc.kill)  # a hung child fails, never hangs
    watchdog.start()
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(2.0)
        t0 = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        first = proc.stdout.readline().strip()
        latency = time.perf_counter() - t0
        # the rest from the same buffered reader (communicate() would read the pipe
        # itself and miss what readline() already buffered); the watchdog bounds it
        out = proc.stdout.read()
        proc.wait()
    finally:
        watchdog.cancel()
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert (first, out.strip()) == ("caught", "interrupted 1"), (first, out)
    assert latency < 1.5, latency


def _check(seen):
    assert seen and seen[-1] == 1.0
    assert all(x < y for x, y in zip(seen, seen[1:], strict=False))
    assert all(0.0 <= x <= 1.0 for x in seen)


def test_exact_solutions_in_chunks_are_bit_identical_and_report():
    t = np.linspace(0.0, 50.0, 200_001)  # > 65536 samples: chunked
    body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 1.0, 0.2])
    seen: list[float] = []
    a = body.trajectory(t, progress=seen.append)
    w, rot = body.state(t)  # one call on the whole grid
    assert np.array_equal(np.asarray(a.omega), w) and np.array_equal(a.quat, rot.as_quat())
    _check(seen)
    assert len(seen) == 4  # 200001 / 65536 -> 4 chunks
    top = LagrangeTop(2.0, 1.0, 4.0, theta=0.6, spin=6.0, precession_rate=-0.8)
    seen = []
    b = top.trajectory(t, progress=seen.append)
    w, rot = top.state(t)
    assert np.array_equal(np.asarray(b.omega), w) and np.array_equal(b.quat, rot.as_quat())
    _check(seen)
    orbit = CentralOrbit.from_state(kepler(1.0), [1.0, 0, 0], [0, 1.2, 0])
    seen = []
    c = orbit.trajectory(t, progress=seen.append)
    x, v = orbit.state(t)
    # Kepler's equation is iterated to round-off over each chunk: equal to round-off
    assert np.max(np.abs(np.asarray(c.position) - x)) < 1e-13  # observed 7.5e-15
    assert np.max(np.abs(np.asarray(c.velocity) - v)) < 1e-13  # observed 4.0e-15
    _check(seen)


def test_midpoint_under_attitude_torque_reports_and_changes_nothing():
    from poinsot.dynamics import GravityTorque, simulate

    grav = GravityTorque(1.0, [0.0, 0.0, 0.4], g=10.0)
    w0 = np.random.default_rng(1).normal(size=(3000, 3))
    t = np.linspace(0.0, 2.0, 21)
    seen: list[float] = []
    a = simulate([2.0, 2.0, 1.0], [1, 0, 0, 0], w0, t, torque=grav, max_step=0.01,
                 progress=seen.append)  # fmt: skip
    b = simulate([2.0, 2.0, 1.0], [1, 0, 0, 0], w0, t, torque=grav, max_step=0.01)
    assert a.method == "midpoint" and np.array_equal(a.quat, b.quat)
    _check(seen)


def test_particle_progress_changes_nothing():
    t = np.linspace(0.0, 10.0, 101)
    args = (FrameMotion(omega=[0, 0, 1.0]), lambda t, r, v: -r, [[1.0, 0, 0], [0.5, 0, 0]],
            [0, 0.5, 0], t)  # fmt: skip
    seen: list[float] = []
    a = simulate_particle(*args, progress=seen.append)
    b = simulate_particle(*args)
    assert np.array_equal(np.asarray(a.position), np.asarray(b.position))
    _check(seen)


def test_lagrangian_progress_changes_nothing():
    sympy = pytest.importorskip("sympy", reason="the symbolic extra")
    from poinsot.symbolic import LagrangeSystem

    x = sympy.Function("x")(sympy.Symbol("t"))
    osc = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2)
    t = np.linspace(0.0, 30.0, 31)
    seen: list[float] = []
    a = osc.simulate([1.0], [0.0], t, progress=seen.append)
    b = osc.simulate([1.0], [0.0], t)
    assert np.array_equal(a.q, b.q)
    _check(seen)
    assert np.allclose(a.q[:, 0], np.cos(t), atol=1e-8)  # and it is the oscillator


def test_ensemble_progress_is_a_fraction_and_on_chunk_counts():
    pytest.importorskip("pyarrow", reason="the ensemble extra")
    from poinsot.ensemble import EnsembleProblem, Metric, Normal, run

    p = EnsembleProblem(
        "racket",
        np.diag([1.0, 2.0, 3.0]),
        np.array([1.0, 0, 0, 0]),
        np.array([0.01, 2.0, 0.01]),
        np.linspace(0, 15, 301),
        dispersions=(("omega0", Normal(sigma=[0.005, 0.05, 0.005])),),
        metrics=(Metric("flip", "first_flip_time"),),
    )
    seen: list[float] = []
    counts: list[tuple[int, int]] = []
    a = run(p, 50, chunk_size=10, client="serial", seed=3, progress=seen.append,
            on_chunk=lambda d, n: counts.append((d, n)))  # fmt: skip
    b = run(p, 50, chunk_size=10, client="serial", seed=3)
    assert a.table.equals(b.table)
    _check(seen)
    assert seen == [k / 5 for k in range(1, 6)]
    assert counts == [(k, 5) for k in range(1, 6)]
