"""Work-precision of MuJoCo on poinsot verify's racket flip and Lagrange top (issue 22).

Run by hand: ``python benchmarks/bench_mujoco_verify.py``. For each MuJoCo integrator
and timestep: the largest geodesic attitude error against the exact solution (rad)
over the case (10 s racket flip; 5 s top with loops), the wall time (median of 3) and
the step count. Also the timestep each integrator needs for 1e-6 rad, from the measured
order of convergence where it is out of reach. The figures are in docs/verify.md.
"""

from __future__ import annotations

import math
import os
import statistics

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from poinsot.verify import cases, make, run  # noqa: E402

STEPS = {
    "RK4": (1e-2, 5e-3, 2e-3, 1e-3, 5e-4),
    "Euler": (1e-3, 1e-4, 1e-5),
    "implicitfast": (1e-3, 1e-4, 1e-5),
}


def main() -> None:
    print(f"load average: {os.getloadavg()}")
    for name in ("racket-flip", "top-loops"):
        case = cases(name)[0]
        print(f"\n{name} ({case.t[-1]:g} s): integrator, timestep (s), attitude error (rad), "
              "median wall time (s), steps")  # fmt: skip
        for integ, steps in STEPS.items():
            rows = []
            for h in steps:
                eng = make("mujoco", integrator=integ, timestep=h)
                if eng.skip_reason(case):
                    continue
                times, res = [], None
                for _ in range(3):
                    res = run(eng, case)
                    times.append(res.seconds)
                assert res is not None
                err = res.metrics["attitude"]["value"]
                rows.append((h, err))
                print(
                    f"  {integ:12s} {h:8.0e} {err:10.2e} {statistics.median(times):8.3f} {res.work}"
                )
            # the order from the two largest steps (the smaller ones reach round-off)
            (h1, e1), (h2, e2) = rows[0], rows[1]
            p = math.log(e1 / e2) / math.log(h1 / h2) if e2 > 0 and e1 != e2 else float("nan")
            need = h2 * (1e-6 / e2) ** (1.0 / p) if p > 0 else float("nan")
            print(f"  {integ}: observed order {p:.2f}; timestep for 1e-6 rad ~ {need:.1e} s")


if __name__ == "__main__":
    main()
