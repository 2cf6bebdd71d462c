"""Where the microseconds of a one-rotation call go (issue 9: "profile, then give
scalars a short path").

Times, in the same process, the building blocks a one-rotation call is made of
(Python call, input checks, array creation, numba call through the dispatcher or
through the compiled entry point) and the whole calls they add up to, next to
SciPy's equivalents. Medians of interleaved rounds, each the best of 5 x 2000 calls.

Run: ``python benchmarks/profile_one_rotation.py``.
"""

from __future__ import annotations

import os
import timeit

import numpy as np
from _timing import table
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import Rotation
from poinsot._validate import plain_floats
from poinsot.rotations._lazy import kernels, one


def _us(fn, number=2000, repeat=5) -> float:
    return min(timeit.repeat(fn, number=number, repeat=repeat)) / number * 1e6


def main() -> None:
    r = Rotation.from_quat([0.9, 0.1, -0.3, 0.2])
    s = SciPyRotation.from_quat(r.as_quat(), scalar_first=True)
    q, m = r._q, np.empty((3, 3))
    k = kernels()
    one.to_matrix1(q, m)
    k.to_matrix1(q, m)

    class _C:
        def method(self):
            return None

    c = _C()
    blocks = [
        ("a Python method call (nothing inside)", lambda: c.method()),
        ("q.tolist() (4 Python floats)", lambda: q.tolist()),
        (
            "plain_floats(list of 4) (type + finite check)",
            lambda: plain_floats([0.9, 0.1, -0.3, 0.2], 4),
        ),
        ("np.array(4 floats)", lambda: np.array((0.9, 0.1, -0.3, 0.2))),
        ("np.empty((3, 3))", lambda: np.empty((3, 3))),
        ("a.setflags(write=False)", lambda: m.setflags(write=True)),
        ("object.__new__(Rotation)", lambda: object.__new__(Rotation)),
        ("numba call through the dispatcher (to_matrix1)", lambda: k.to_matrix1(q, m)),
        ("numba call through the entry point (to_matrix1)", lambda: one.to_matrix1(q, m)),
    ]
    calls = [
        ("r.as_matrix()", lambda: r.as_matrix(), lambda: s.as_matrix()),
        ("r.as_rotvec()", lambda: r.as_rotvec(), lambda: s.as_rotvec()),
        ("r.magnitude()", lambda: r.magnitude(), lambda: s.magnitude()),
        ("r.inv()", lambda: r.inv(), lambda: s.inv()),
        (
            "Rotation.from_quat(list)",
            lambda: Rotation.from_quat([0.9, 0.1, -0.3, 0.2]),
            lambda: SciPyRotation.from_quat([0.9, 0.1, -0.3, 0.2], scalar_first=True),
        ),
        ("r.apply(list)", lambda: r.apply([1.0, 2.0, 3.0]), lambda: s.apply([1.0, 2.0, 3.0])),
    ]
    rounds = 5
    b = np.array([[_us(f) for _, f in blocks] for _ in range(rounds)])
    cc = np.array([[[_us(f), _us(g)] for _, f, g in calls] for _ in range(rounds)])
    b, cc = np.median(b, axis=0), np.median(cc, axis=0)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"Building blocks of one-rotation calls (us per call; load average {load:.1f})")
    print(
        table([[name, f"{t:.3f}"] for (name, _), t in zip(blocks, b, strict=True)], ["block", "us"])
    )
    print()
    print("Whole calls (us per call), same run")
    rows = [
        [name, f"{p:.3f}", f"{sp:.3f}", f"{sp / p:.1f}x"]
        for (name, _, _), (p, sp) in zip(calls, cc, strict=True)
    ]
    print(table(rows, ["call", "poinsot", "SciPy", "SciPy/poinsot"]))
    print(
        "\nA one-rotation conversion is: method call + output array (np.empty) + one numba\n"
        "call through its compiled entry point (the dispatcher's type matching skipped);\n"
        "a constructor from a list: type/finite check on Python floats + the formula in\n"
        "plain Python + np.array + object.__new__ (no setflags: a single rotation's array\n"
        "is private and unshared)."
    )


if __name__ == "__main__":
    main()
