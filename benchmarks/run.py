"""Run every ``benchmarks/bench_*.py`` script in turn (``make bench``)."""

from __future__ import annotations

import pathlib
import runpy
import sys

here = pathlib.Path(__file__).parent
sys.path.insert(0, str(here))
only = sys.argv[1:]
for path in sorted(here.glob("bench_*.py")):
    if only and not any(o in path.name for o in only):
        continue
    print(f"\n=== {path.name} ===", flush=True)
    runpy.run_path(str(path), run_name="__main__")
