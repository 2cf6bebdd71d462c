"""Time to first result (issue 40): each figure in a fresh process.

    python benchmarks/bench_cold_start.py [--only NAME ...] [--repeat N] [--before]
    python benchmarks/bench_cold_start.py --examples [EXAMPLE ...]

Columns: **cold** (an empty ``NUMBA_CACHE_DIR``: first use after an install; small
calls interpreted, no background build), **before** (with ``--before``: cold with
``POINSOT_INTERPRET_FIRST=0``, every first call compiles, as before issue 40) and
**warm** (the cache ``poinsot warmup`` filled, timed once at the start). Each figure is
the wall time of one ``python -c`` process from start to exit (import included), the
median of ``--repeat`` runs (each cold run with a new empty cache). The machine's load
is printed first (``os.getloadavg``): quote it with the figures.

``--examples`` runs each shipped example (``examples/*.toml``, or those named) once
with an empty cache instead: ``poinsot run`` from start to exit, and the seconds its
``summary.json`` reports compiling (``run.compile_time_s``; target <= 10 s each).
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
        "e = np.random.default_rng(0).uniform(-3, 3, (1000, 3))\n"
        "r = poinsot.Rotation.from_euler('ZXZ', e)\n"
        "r.apply([1.0, 0.0, 0.0]); r.as_euler('ZYX'); r.as_matrix(); (r * r.inv()).as_quat()",
        3.0,
    ),
    "simulate-rtol": (
        "from poinsot.dynamics import simulate\n"
        "t = np.linspace(0, 10, 101)\n"
        "simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], t, rtol=1e-10)",
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
        "body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1])\n"
        "body.trajectory(np.linspace(0, 10, 101))",
        3.0,
    ),
    "demo": (
        "import sys, tempfile\nfrom poinsot.cli import main\n"
        "sys.exit(main(['demo', '--out', tempfile.mkdtemp(), '--quiet']))",
        15.0,
    ),
}


def run_once(code: str, cache: str, interpret: str = "1") -> float:
    env = dict(
        os.environ,
        NUMBA_CACHE_DIR=cache,
        POINSOT_COMPILE_NOTICE="0",
        POINSOT_INTERPRET_FIRST=interpret,
        POINSOT_BACKGROUND_BUILD="0",
    )
    t0 = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", SETUP + code], env=env, capture_output=True, text=True
    )
    dt = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(f"failed:\n{code}\n{out.stderr[-2000:]}")
    return dt


def examples(names: list[str]) -> None:
    """Each example's first run with an empty cache: wall seconds and compile seconds."""
    import json

    paths = sorted((ROOT / "examples").glob("*.toml"))
    if names:
        paths = [p for p in paths if p.stem in names or p.name in names]
    print(f"{'example':32s} {'wall s':>8s} {'compile s':>10s}")
    worst = 0.0
    for path in paths:
        cache = tempfile.mkdtemp(prefix="poinsot-cold-")
        out = tempfile.mkdtemp(prefix="poinsot-out-")
        try:
            code = (
                "import sys\nfrom poinsot.cli import main\n"
                f"sys.exit(main(['run', {str(path)!r}, '--out', {out!r}, '--quiet']))"
            )
            wall = run_once(code, cache)
            run = json.loads((Path(out) / "summary.json").read_text())["run"]
            comp = float(run.get("compile_time_s", float("nan")))
        finally:
            shutil.rmtree(cache, ignore_errors=True)
            shutil.rmtree(out, ignore_errors=True)
        worst = max(worst, comp)
        flag = "" if comp <= 10.0 else "  (over 10 s)"
        print(f"{path.stem:32s} {wall:8.2f} {comp:10.2f}{flag}", flush=True)
    print(f"most compiling in one example: {worst:.2f} s (target 10 s)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--before", action="store_true", help="also cold with interpreting off")
    ap.add_argument("--examples", nargs="*", default=None, help="each example's first run")
    args = ap.parse_args()
    print(f"load average (1, 5, 15 min): {os.getloadavg()}; {os.cpu_count()} CPUs")
    if args.examples is not None:
        examples(args.examples)
        return
    warm_cache = tempfile.mkdtemp(prefix="poinsot-warm-")
    t0 = time.perf_counter()
    code = "import sys\nfrom poinsot.cli import main\nsys.exit(main(['warmup', '--quiet']))"
    run_once(code, warm_cache, interpret="0")
    print(f"poinsot warmup (all kernels into an empty cache): {time.perf_counter() - t0:.1f} s")
    print(f"{'figure':24s} {'cold s':>8s} {'before s':>9s} {'warm s':>8s} {'target s':>9s}")
    for name, (code, target) in FIGURES.items():
        if args.only and name not in args.only:
            continue
        cold, before, warm = [], [], []
        for _ in range(args.repeat):
            for interpret, into in (("1", cold), ("0", before)):
                if interpret == "0" and not args.before:
                    continue
                cache = tempfile.mkdtemp(prefix="poinsot-cold-")
                try:
                    into.append(run_once(code, cache, interpret))
                finally:
                    shutil.rmtree(cache, ignore_errors=True)
            warm.append(run_once(code, warm_cache))
        c, w = float(np.median(cold)), float(np.median(warm))
        b = f"{float(np.median(before)):9.2f}" if before else f"{'-':>9s}"
        flag = "" if c <= target else "  (over)"
        print(f"{name:24s} {c:8.2f} {b} {w:8.2f} {target:9.1f}{flag}")
    shutil.rmtree(warm_cache, ignore_errors=True)


if __name__ == "__main__":
    main()
