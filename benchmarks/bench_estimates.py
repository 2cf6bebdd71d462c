"""`poinsot check`'s time estimate against the measured solve, for every shipped example.

For each example and each of its methods (the method and the reference, run alone),
the solve (``simulate_scenario``, no files) is timed (min of 3, after a warm-up that
compiles) and compared with the estimate of ``estimate_cost`` for that method, which
is ``overhead + seconds_per_step * steps`` with each kind's table. ``--fit`` prints the
per-step times measured, to refresh the tables. docs/cli.md promises the estimate
within 3x of the solve on one core; this script is how that is checked (not a timed
test: timing varies with the machine's load).

Usage: python benchmarks/bench_estimates.py [--fit]
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")  # the estimate is for one core
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    from poinsot.scenarios import estimate_cost, load_scenario, simulate_scenario
    from poinsot.scenarios.solve import _steps

    fit = "--fit" in sys.argv
    print(f"load {os.getloadavg()[0]:.2f}; NUMBA_NUM_THREADS={os.environ['NUMBA_NUM_THREADS']}")
    worst = 1.0
    for f in sorted((ROOT / "examples").glob("*.toml")):
        if "ensemble" in f.name:
            continue
        s = load_scenario(f)
        sim = s.simulation
        for m in [sim.method] + ([sim.reference] if sim.reference else []):
            one = dataclasses.replace(
                s, simulation=dataclasses.replace(sim, method=m, reference=None)
            )
            est = estimate_cost(one).seconds
            simulate_scenario(one, duration=min(sim.duration, sim.spacing() * 3))  # compile
            runs = []
            for _ in range(3):
                t0 = time.perf_counter()
                simulate_scenario(one)
                runs.append(time.perf_counter() - t0)
            dt = min(runs)
            ratio = est / dt
            worst = max(worst, ratio, 1 / ratio)
            steps = _steps(one, m, sim.n_samples())
            extra = f"  per step {dt / steps:.3g} s ({steps} steps)" if fit else ""
            print(f"{f.stem:22s} {s.kind:14s} {m:10s} est {est:8.3g} s  solve {dt:8.3g} s  "
                  f"est/solve {ratio:6.2f}{extra}", flush=True)  # fmt: skip
    print(f"worst factor {worst:.2f} (promise: 3)")
    return 0 if worst <= 3.0 else 1


if __name__ == "__main__":
    raise SystemExit(main())
