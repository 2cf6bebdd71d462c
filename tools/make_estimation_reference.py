"""Regenerate the stored sensor data of the ``estimation`` verify case ``mekf-racket``.

The truth is the exact torque-free motion of the case (:class:`FreeRigidBody`,
docs/theory.md §10) on its 10 Hz grid; a rate-integrating gyro (Farrenkopf's model,
:class:`poinsot.dynamics.Gyro`: the case's ARW, RRW and initial bias) samples it on
that grid and a star tracker (:class:`poinsot.dynamics.StarTracker`, the case's
sigmas) at 1 Hz, each from its own PCG64 stream spawned from the case's seed
(``numpy.random.SeedSequence(seed).spawn(2)``: gyro, then star tracker). NumPy does
not promise that ``Generator.standard_normal`` gives the same numbers in every
version, so the samples are drawn once and stored, with the inputs they were drawn
from, in ``src/poinsot/verify/data/mekf_racket.npz``; the case checks the inputs on
load, and ``tests/verify/test_verify_estimation.py`` that this script's draw with the
installed NumPy still reproduces the file.

Usage (from the repository root; a second)::

    PYTHONPATH=src .venv/bin/python tools/make_estimation_reference.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "src" / "poinsot" / "verify" / "data"


def main() -> None:
    from poinsot.verify.cases import mekf_racket_case
    from poinsot.verify.groups import draw_sensors

    case = mekf_racket_case()
    data = draw_sensors(case)
    inputs = {f"input_{k}": np.asarray(v, dtype=float) for k, v in case.inputs.items()}
    np.savez_compressed(DATA / "mekf_racket.npz", t=case.t, **data, **inputs)
    print(
        f"wrote {DATA / 'mekf_racket.npz'}: " + ", ".join(f"{k} {v.shape}" for k, v in data.items())
    )


if __name__ == "__main__":
    main()
