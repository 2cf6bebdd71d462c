"""Time to first result: each figure in a fresh process, with an empty numba cache
(cold: first use after an install) and then with the cache that run filled (warm).

    python benchmarks/bench_cold_start.py [--only NAME ...] [--repeat N]

Each figure is the wall time of one ``python -c`` process from start to exit (import
included), the median of ``--repeat`` runs (each cold run gets a new empty
``NUMBA_CACHE_DIR``). The machine's load is printed first (``os.getloadavg``): quote
it with the figures (issue 40's targets are for a quiet machine).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).parents[1]

SETUP = "import numpy as np\n"
#: name -> (code run in the fresh process, target of issue 40 in s, cold)
FIGURES = {
    "import": ("import poinsot", 0.5),
    "rotation-batch": (
        "import poinsot\n"
        "r = poinsot.Rotation.from_euler('ZXZ', np.random.default_rng(0).uniform(-3, 3, (1000, 3)))\n"
        "r.apply([1.0, 0.0, 0.0]); r.as_euler('ZYX'); r.as_matrix(); (r * r.inv()).as_quat()",
        3.0,
    ),
    "simulate-rtol": (
        "from poinsot.dynamics import simulate\n"
        "simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 10, 101), rtol=1e-10)",
        5.0,
    ),
    "simulate-default": (
        "from poinsot.dynamics import simulate\n"
        "simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 10, 101))",
        5.0,
    ),
    "heavy-simulate": (
        "from poinsot.dynamics import HeavyRigidBody\n"
        "top = HeavyRigidBody([1.0, 1.0, 0.4], 2.0, [0.0, 0.0, 0.3])\n"
        "top.simulate([1.0, 0, 0, 0], [0.0, 0.5, 15.0], np.linspace(0, 5, 51))",
        3.0,
    ),
    "free-body-trajectory": (
        "from poinsot.dynamics import FreeRigidBody\n"
        "FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1]).trajectory(np.linspace(0, 10, 101))",
        3.0,
    ),
    "demo": (
        "import sys, tempfile\nfrom poinsot.cli import main\n"
        "sys.exit(main(['demo', '--out', tempfile.mkdtemp(), '--quiet']))",
        15.0,
    ),
}


def run_once(code: str, cache: str) -> float:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, POINSOT_COMPILE_NOTICE="0")
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", SETUP + code], env=env, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(f"failed:\n{code}\n{out.stderr[-2000:]}")
    return dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"load average (1, 5, 15 min): {os.getloadavg()}; {os.cpu_count()} CPUs")
    print(f"{'figure':24s} {'cold s':>8s} {'warm s':>8s} {'target s':>9s}")
    for name, (code, target) in FIGURES.items():
        if args.only and name not in args.only:
            continue
        cold, warm = [], []
        for _ in range(args.repeat):
            cache = tempfile.mkdtemp(prefix="poinsot-cold-")
            try:
                cold.append(run_once(code, cache))
                warm.append(run_once(code, cache))
            finally:
                shutil.rmtree(cache, ignore_errors=True)
        c, w = float(np.median(cold)), float(np.median(warm))
        print(f"{name:24s} {c:8.2f} {w:8.2f} {target:9.1f}{'' if c <= target else '  (over)'}")


if __name__ == "__main__":
    main()
