"""Saved outputs of poinsot's integrators on benchmark cases, to show that a refactor
changes no bit (issue 39: "results are bit-identical before/after").

``python tools/golden_outputs.py OUT.npz`` computes every case with the poinsot on
``sys.path`` and writes the arrays; ``tests/test_golden_outputs.py`` recomputes them
with the current code and compares with the file saved from the release before the
redesign (``tests/data/golden_outputs.npz``). Only positional arguments and names that
every version since 0.3 accepts are used.
"""

from __future__ import annotations

import sys

import numpy as np


def bodies() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Five heterogeneous bodies: moments (kg m^2), attitudes, angular velocities (rad/s)."""
    rng = np.random.default_rng(20261129)
    moments = np.sort(rng.uniform(1.0, 2.0, (5, 3)), axis=1)  # A + B >= C
    moments[1] = [1.0, 1.0, 2.0]  # symmetric
    moments[2] = [0.5, 1.0, 1.5 - 1e-9]  # near the separatrix's inertia ratios
    q = rng.normal(size=(5, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w = rng.normal(size=(5, 3)) * [[1.0], [3.0], [0.5], [8.0], [2.0]]
    return moments, q, w


def compute() -> dict[str, np.ndarray]:
    from poinsot import dynamics as d

    j, q, w = bodies()
    t = np.linspace(0.0, 3.0, 31)
    out: dict[str, np.ndarray] = {}

    def keep(name: str, tr) -> None:  # noqa: ANN001
        out[f"{name}/quat"] = np.asarray(tr.rotation.as_quat(scalar_first=True))
        out[f"{name}/omega"] = np.asarray(tr.omega)

    def py_torque(tt, rotation, omega):  # noqa: ANN001, ANN202
        return -0.1 * np.asarray(omega)

    torques = {
        "free": None,
        "body": d.ConstantBodyTorque([0.1, -0.2, 0.05]),
        "space": d.ConstantSpaceTorque([0.0, 0.3, 0.0]),
        "gravity": d.GravityTorque(2.0, [0.0, 0.0, 0.2]),
        "python": py_torque,
    }
    for tname, torque in torques.items():
        for method, kw in (
            ("midpoint", {"max_step": 1e-2}),
            ("splitting", {"max_step": 1e-2}),
            ("rk4", {"max_step": 1e-2}),
            ("dop853", {"rtol": 1e-10, "atol": 1e-12}),
            ("adaptive", {"rtol": 1e-10, "atol": 1e-12}),
        ):
            if tname == "python" and method in ("splitting", "dop853"):
                continue  # not offered for a Python torque
            try:
                tr = d.simulate(j, q, w, t, torque=torque, method=method, **kw)
            except Exception as exc:  # a combination a version refuses: not compared
                print(f"skip {tname}/{method}: {exc}", file=sys.stderr)
                continue
            keep(f"simulate/{tname}/{method}", tr)
    top = d.HeavyRigidBody([1.0, 1.0, 0.4], 2.0, [0.0, 0.0, 0.3])
    for method, kw in (("splitting", {"max_step": 1e-3}), ("dop853", {"rtol": 1e-11})):
        keep(f"heavy/{method}", top.simulate(q[:2], w[:2] + [0, 0, 15.0], t, method=method, **kw))
    keep("free_body_exact", d.FreeRigidBody(j, rotation0=q, omega0=w).trajectory(t))
    return out


def machine() -> dict[str, str]:
    """What bit-identity depends on: the executor, the CPU target numba compiles for, and
    the versions of numba and NumPy."""
    import os
    import platform

    from poinsot import _jit

    rec = {"executor": "numba" if _jit.NUMBA else "numpy", "numpy": np.__version__}
    rec["machine"] = platform.machine()
    if _jit.NUMBA:
        import llvmlite.binding as llvm
        import numba

        rec["numba"] = numba.__version__
        rec["cpu"] = os.environ.get("NUMBA_CPU_NAME") or llvm.get_host_cpu_name()
    return rec


if __name__ == "__main__":
    import json

    np.savez_compressed(sys.argv[1], meta=json.dumps(machine(), sort_keys=True), **compute())
