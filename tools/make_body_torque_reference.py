"""Regenerate the stored 32-digit reference of the ``body-torque`` verify case.

A free axisymmetric body (``A = B``) under a constant body-axes torque ``M e_3``:
``w_3 = w_30 + M t / C`` and the transverse rate turns in body axes by
``(C - A) / A`` times the integral of ``w_3``, but the attitude has no elementary
closed form (it is a Landau-Zener problem: parabolic cylinder functions). Its exact
states on the case's grid are a Taylor-series integration (``mpmath.odefun``,
``mp.dps = 32``) of Euler's equations with the quaternion
(:func:`make_kovalevskaya_reference.integrate`), written to
``src/poinsot/verify/data/body_torque.npz`` with the inputs they came from.

Usage (from the repository root)::

    PYTHONPATH=src .venv/bin/python tools/make_body_torque_reference.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import mpmath as mp

sys.path.insert(0, str(Path(__file__).resolve().parent))

from make_kovalevskaya_reference import integrate, save  # noqa: E402


def main() -> None:
    from poinsot.verify.cases import body_torque_case

    case = body_torque_case()
    m = [mp.mpf(float(x)) for x in case.inputs["body_torque"]]

    def torque(tt: Any, q: list[Any], w: list[Any]) -> list[Any]:
        return m

    start = time.perf_counter()
    quat, omega = integrate(case.inputs, case.t, torque)
    seconds = time.perf_counter() - start
    path = save("body_torque", case, quat, omega, seconds)
    print(f"wrote {path} ({case.t.size} samples, {seconds:.0f} s)")


if __name__ == "__main__":
    main()
