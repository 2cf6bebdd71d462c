"""Regenerate the stored 32-digit reference of the ``kovalevskaya`` verify case.

The Kovalevskaya top has no closed form in poinsot; its exact states on the case's
grid are a Taylor-series integration (``mpmath.odefun``, ``mp.dps = 32``) of the
Euler-Poisson equations with the attitude quaternion,

    J_O w' + w x J_O w = m g gamma x c,    q' = q (0, w) / 2,

``gamma = R^T e_z`` (the upward vertical in body axes), from the case's double
inputs read exactly (``J_O`` of the case's inertia about the centre of mass by the
parallel-axis theorem, in 32-digit arithmetic). The result is rounded to doubles
and written, with the inputs it was computed from, to
``src/poinsot/verify/data/kovalevskaya.npz``; the case checks the inputs on load.

Usage (from the repository root; about a minute on one core)::

    PYTHONPATH=src .venv/bin/python tools/make_kovalevskaya_reference.py

:func:`integrate` is shared with ``tools/make_body_torque_reference.py``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mpmath as mp
import numpy as np

DATA = Path(__file__).resolve().parents[1] / "src" / "poinsot" / "verify" / "data"
DPS = 32


def inertia_about_origin(inputs: dict[str, Any]) -> list[list[Any]]:
    """``J_O = J_C + m (|c|^2 E - c c^T)`` in mpmath numbers, from the exact doubles."""
    jc = [[mp.mpf(float(x)) for x in row] for row in inputs["inertia"]]
    m = mp.mpf(float(inputs["mass"]))
    c = [mp.mpf(float(x)) for x in inputs["com"]]
    c2 = sum(x * x for x in c)
    return [[jc[i][j] + m * ((c2 if i == j else 0) - c[i] * c[j]) for j in range(3)]
            for i in range(3)]  # fmt: skip


def integrate(
    inputs: dict[str, Any],
    t: np.ndarray,
    torque: Callable[[Any, list[Any], list[Any]], list[Any]],
) -> tuple[np.ndarray, np.ndarray]:
    """Euler's equations with the quaternion at ``DPS`` digits on the grid ``t``.

    ``torque(t, q, w)`` (mpmath numbers; body axes) is the external torque about the
    fixed point (or the centre of mass). Returns ``(quat (n, 4), omega (n, 3))``
    rounded to doubles.
    """
    mp.mp.dps = DPS
    jo = inertia_about_origin(inputs)
    for i in range(3):
        for j in range(3):
            if i != j and jo[i][j] != 0:
                raise ValueError("principal axes only")
    a, b, c = jo[0][0], jo[1][1], jo[2][2]

    def rhs(tt: Any, y: list[Any]) -> list[Any]:
        w1, w2, w3, q0, q1, q2, q3 = y
        m = torque(tt, [q0, q1, q2, q3], [w1, w2, w3])
        return [
            (m[0] - (c - b) * w2 * w3) / a,
            (m[1] - (a - c) * w3 * w1) / b,
            (m[2] - (b - a) * w1 * w2) / c,
            (-q1 * w1 - q2 * w2 - q3 * w3) / 2,
            (q0 * w1 + q2 * w3 - q3 * w2) / 2,
            (q0 * w2 + q3 * w1 - q1 * w3) / 2,
            (q0 * w3 + q1 * w2 - q2 * w1) / 2,
        ]

    y0 = [mp.mpf(float(x)) for x in inputs["omega0"]] + [mp.mpf(float(x)) for x in inputs["q0"]]
    sol = mp.odefun(rhs, 0, y0)
    out = np.empty((t.size, 7))
    start = time.perf_counter()
    for k, tk in enumerate(t):
        out[k] = [float(v) for v in sol(mp.mpf(float(tk)))]
        if k % 50 == 0:
            print(f"  t = {tk:g} s ({time.perf_counter() - start:.0f} s)", file=sys.stderr)
    return out[:, 3:], out[:, :3]


def gravity_torque(inputs: dict[str, Any]) -> Callable[[Any, list[Any], list[Any]], list[Any]]:
    """``m g gamma x c`` with ``gamma = R^T e_z`` (gravity ``(0, 0, -g)``)."""
    g = -mp.mpf(float(inputs["gravity"][2]))
    if any(float(x) for x in inputs["gravity"][:2]):
        raise ValueError("vertical gravity only")
    m = mp.mpf(float(inputs["mass"]))
    cx, cy, cz = (mp.mpf(float(x)) for x in inputs["com"])

    def torque(tt: Any, q: list[Any], w: list[Any]) -> list[Any]:
        q0, q1, q2, q3 = q
        g1 = 2 * (q1 * q3 - q0 * q2)
        g2 = 2 * (q2 * q3 + q0 * q1)
        g3 = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
        return [m * g * (g2 * cz - g3 * cy), m * g * (g3 * cx - g1 * cz),
                m * g * (g1 * cy - g2 * cx)]  # fmt: skip

    return torque


def save(name: str, case: Any, quat: np.ndarray, omega: np.ndarray, seconds: float) -> Path:
    """Write ``DATA/NAME.npz``: the grid, the states and the inputs they came from."""
    DATA.mkdir(parents=True, exist_ok=True)
    path = DATA / f"{name}.npz"
    inputs = {f"input_{k}": np.asarray(v, dtype=float) for k, v in case.inputs.items()}
    np.savez_compressed(path, t=case.t, quat=quat, omega=omega, digits=np.array(DPS),
                        seconds=np.array(seconds), **inputs)  # fmt: skip
    return path


def main() -> None:
    from poinsot.verify.cases import kovalevskaya_case

    case = kovalevskaya_case()
    start = time.perf_counter()
    quat, omega = integrate(case.inputs, case.t, gravity_torque(case.inputs))
    seconds = time.perf_counter() - start
    path = save("kovalevskaya", case, quat, omega, seconds)
    print(f"wrote {path} ({case.t.size} samples, {seconds:.0f} s)")


if __name__ == "__main__":
    main()
