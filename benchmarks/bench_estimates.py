"""`poinsot check`'s time estimate against the measured solve, for every shipped example.

For each example and each of its methods (the method and the reference, run alone),
the solve (``simulate_scenario``, no files) is timed (min of 3, after a warm-up that
compiles) and compared with the estimate of ``estimate_cost`` for that method, which
is ``overhead + seconds_per_step * steps`` with each kind's table. ``--fit`` prints the
per-step times measured, to refresh the tables. docs/cli.md promises the estimate
within 3x of the solve on one core; this script is how that is checked (not a timed
test: timing varies with the machine's load).

The second table is what `poinsot check` prints (``estimate_cost(measure=True,
outputs=True)``: an adaptive method timed on a short first piece, the outputs added)
against the whole `poinsot run` (``run_scenario``: both methods, tables, figures and
report; warm: numba's compile time is reported apart by the run itself,
``summary.json`` ``run.compile_time_s``, and not counted).

Usage: python benchmarks/bench_estimates.py [--fit] [--runs-only]
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
    examples = sorted((ROOT / "examples").glob("*.toml"))
    for f in [] if "--runs-only" in sys.argv else examples:
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
    worst_run = _check_against_run(examples)
    print(f"check vs run: worst factor {worst_run:.2f} (promise: 3)")
    return 0 if max(worst, worst_run) <= 3.0 else 1


def _check_against_run(examples: list[Path]) -> float:
    import tempfile

    from poinsot.scenarios import estimate_cost, load_scenario, run_scenario

    worst = 1.0
    with tempfile.TemporaryDirectory() as tmp:
        for k, f in enumerate(examples):
            if "ensemble" in f.name:
                continue
            s = load_scenario(f)
            est = estimate_cost(s, measure=True, outputs=True)  # compiles what it runs
            run_scenario(s, Path(tmp) / f"warm{k}", duration=s.simulation.spacing() * 3)
            t0 = time.perf_counter()
            res, _ = run_scenario(s, Path(tmp) / f"run{k}")
            dt = time.perf_counter() - t0 - res.compile_time
            ratio = est.seconds / dt
            worst = max(worst, ratio, 1 / ratio)
            print(f"{f.stem:22s} check {est.seconds:8.3g} s  run {dt:8.3g} s  "
                  f"check/run {ratio:6.2f}", flush=True)  # fmt: skip
    return worst


if __name__ == "__main__":
    raise SystemExit(main())
