"""Benchmark: Monte-Carlo ensembles (poinsot.ensemble) on a local Dask cluster.

Measures, on this machine (medians are not taken: each configuration is run
once after a warm-up run that compiles the kernels in every worker):

1. samples per second for a torque-free and a torque-driven (heavy top)
   ensemble on 1 and 2 worker processes, and the scaling ratio;
2. the overhead per chunk (time of an ensemble of empty-ish chunks: 1 sample each);
3. peak resident memory per worker for N = 1e4 and N = 1e6 (``--big``) samples
   with the same chunk size: bounded by the chunk, not by N;
4. the practice it replaces: a ``multiprocessing.Pool`` of 2 processes calling
   ``scipy.integrate.solve_ivp(DOP853)`` once per sample, same tolerance.

Run: ``.venv/bin/python benchmarks/bench_ensemble.py [--n 20000] [--big]``.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import time

import numpy as np
from scipy.integrate import solve_ivp

from poinsot.ensemble import EnsembleProblem, Metric, Normal, SmallRotation, run

T = np.linspace(0.0, 10.0, 101)


def problem(torque: bool) -> EnsembleProblem:
    kw = {}
    if torque:
        kw = dict(torque_model="gravity", mass=1.0, center_of_mass=np.array([0.0, 0.0, 0.1]))
    return EnsembleProblem(
        "bench",
        np.diag([1.0, 2.0, 3.0]) if not torque else np.diag([1.2, 1.2, 0.5]),
        np.array([0.9, 0.3, 0.1, 0.3]) / np.linalg.norm([0.9, 0.3, 0.1, 0.3]),
        np.array([0.01, 2.0, 0.01]) if not torque else np.array([0.5, 0.0, 15.0]),
        T,
        dispersions=(
            ("omega0", Normal(sigma=[0.01, 0.05, 0.01])),
            ("attitude", SmallRotation(1.0)),
        ),
        metrics=(
            Metric("flip", "first_flip_time"),
            Metric("nmax", "nutation_max"),
            Metric("drift", "energy_drift"),
        ),
        **kw,
    )


def rss_peak(client) -> list[float]:
    import resource

    peaks = client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    return list(peaks.values())


def with_cluster(n_workers, fn):
    from dask.distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=n_workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            host="127.0.0.1",
        ) as cluster,
        Client(cluster) as client,
    ):
        return fn(client)


def _one_sample(args):
    j, q0, w0 = args

    def rhs(_t, y):
        q, w = y[:4], y[4:]
        f = np.empty(7)
        f[0] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2])
        f[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
        f[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2])
        f[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])
        f[4:] = np.cross(j * w, w) / j
        return f

    sol = solve_ivp(
        rhs,
        (T[0], T[-1]),
        np.concatenate([q0, w0]),
        method="DOP853",
        t_eval=T,
        rtol=1e-10,
        atol=1e-12,
    )
    return float(np.max(sol.y[5]))


def pool_baseline(n):
    rng = np.random.default_rng(0)
    j = np.array([1.0, 2.0, 3.0])
    tasks = [
        (j, np.array([1.0, 0, 0, 0]), np.array([0.01, 2.0, 0.01]) + 0.01 * rng.normal(size=3))
        for _ in range(n)
    ]
    with mp.Pool(2) as pool:
        t0 = time.perf_counter()
        pool.map(_one_sample, tasks, chunksize=max(1, n // 20))
        return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20_000)
    ap.add_argument("--chunk", type=int, default=10_000)
    ap.add_argument("--big", action="store_true", help="also N = 1e6 for the memory bound")
    args = ap.parse_args()
    rows = []
    for torque in (False, True):
        p = problem(torque)
        rates = {}
        for k in (1, 2):

            def go(client, p=p):
                run(p, 2 * args.chunk, chunk_size=args.chunk, client=client, seed=1)  # warm-up
                t0 = time.perf_counter()
                run(p, args.n, chunk_size=args.chunk, client=client, seed=2)
                return time.perf_counter() - t0, rss_peak(client)

            print(
                f"  running {'heavy top' if torque else 'free body'} on {k} worker(s)...",
                flush=True,
            )
            dt, rss = with_cluster(k, go)
            rates[k] = args.n / dt
            rows.append((("heavy top" if torque else "free body"), k, args.n / dt, max(rss)))
        print(
            f"{'heavy top' if torque else 'free body'}: {rates[1]:.0f} samples/s on 1 worker, "
            f"{rates[2]:.0f} on 2: scaling {rates[2] / rates[1]:.2f}",
            flush=True,
        )
    for name, k, rate, rss in rows:
        print(f"  {name:10s} workers={k}  {rate:9.0f} samples/s  peak RSS/worker {rss:.0f} MiB")

    def overhead(client):
        p = problem(False)
        run(p, 20, chunk_size=1, client=client, seed=1)
        t0 = time.perf_counter()
        run(p, 200, chunk_size=1, client=client, seed=3)
        return (time.perf_counter() - t0) / 200

    print(
        f"overhead per chunk (1-sample chunks, 1 worker): {with_cluster(1, overhead) * 1e3:.1f} ms"
    )
    nb = min(args.n, 4000)
    dt_pool = pool_baseline(nb)
    print(
        f"multiprocessing.Pool(2) + solve_ivp per sample: {nb / dt_pool:.0f} samples/s "
        f"(free body; poinsot on 2 workers: {rows[1][2]:.0f}, ratio "
        f"{rows[1][2] / (nb / dt_pool):.0f}x)"
    )
    if args.big:
        for n in (10_000, 1_000_000):

            def mem(client, n=n):
                run(problem(False), n, chunk_size=args.chunk, client=client, seed=4)
                return rss_peak(client)

            print(
                f"N = {n}: peak RSS per worker {max(with_cluster(2, mem)):.0f} MiB "
                f"(chunk {args.chunk})"
            )


if __name__ == "__main__":
    main()
