"""Rotation core vs SciPy's Rotation (and numpy-quaternion / quaternionic if installed).

For N = 1,000,000 rotations: nanoseconds per rotation, the ratio to SciPy, and for
the memory-bound operations the ratio to the memory-bandwidth floor measured in
the same run (time of ``q.copy()`` per byte moved, times the bytes the operation
reads and writes). Also the time of one composition of two single rotations.

Run: ``python benchmarks/bench_rotations.py [N]`` (``make bench`` runs all).
"""

from __future__ import annotations

import sys
import warnings

import numpy as np
from _timing import median_time, table
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import Rotation


def main(n: int = 1_000_000) -> None:
    rng = np.random.default_rng(0)
    q = rng.standard_normal((n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    v = rng.standard_normal((n, 3))
    ang = rng.uniform(-3, 3, (n, 3))
    r, r2 = Rotation.from_quat(q), Rotation.random(n, rng=1)
    s, s2 = (
        SciPyRotation.from_quat(q, scalar_first=True),
        SciPyRotation.from_quat(r2.as_quat(), scalar_first=True),
    )
    m, rv = r.as_matrix(), r.as_rotvec()
    warnings.simplefilter("ignore")

    floor_s = median_time(lambda: q.copy(), repeat=15)
    per_byte = floor_s / (2 * q.nbytes)
    f8 = 8 * n
    ops = [
        # name, poinsot, scipy, bytes moved (None: not memory-bound)
        ("quat->matrix", lambda: r.as_matrix(), lambda: s.as_matrix(), f8 * (4 + 9)),
        (
            "matrix->quat",
            lambda: Rotation.from_matrix(m),
            lambda: SciPyRotation.from_matrix(m),
            None,
        ),
        (
            "rotvec->quat",
            lambda: Rotation.from_rotvec(rv),
            lambda: SciPyRotation.from_rotvec(rv),
            None,
        ),
        ("quat->rotvec", lambda: r.as_rotvec(), lambda: s.as_rotvec(), None),
        (
            "euler->quat",
            lambda: Rotation.from_euler("ZXZ", ang),
            lambda: SciPyRotation.from_euler("ZXZ", ang),
            None,
        ),
        ("quat->euler", lambda: r.as_euler("ZXZ"), lambda: s.as_euler("ZXZ"), None),
        ("compose", lambda: r * r2, lambda: s * s2, f8 * 12),
        ("apply", lambda: r.apply(v), lambda: s.apply(v), f8 * (4 + 3 + 3)),
        ("inverse", lambda: r.inv(), lambda: s.inv(), f8 * 8),
    ]
    rows, ratios = [], []
    for name, ours, theirs, nbytes in ops:
        t_ours = median_time(ours, repeat=5)
        t_scipy = median_time(theirs, repeat=5)
        ratio = t_scipy / t_ours
        ratios.append(ratio)
        floor = f"{t_ours / (per_byte * nbytes):.2f}x" if nbytes else "-"
        rows.append(
            [name, f"{1e9 * t_ours / n:.1f}", f"{1e9 * t_scipy / n:.1f}", f"{ratio:.2f}x", floor]
        )
    print(
        f"N = {n:,} rotations; memory floor from q.copy(): {2 * q.nbytes / floor_s / 1e9:.1f} GB/s"
    )
    print(table(rows, ["operation", "poinsot ns/rot", "scipy ns/rot", "speed-up", "vs floor"]))
    print(f"geometric-mean speed-up over SciPy: {np.exp(np.mean(np.log(ratios))):.2f}x")

    a, b = Rotation.random(rng=2), Rotation.random(rng=3)
    sa, sb = SciPyRotation.random(rng=2), SciPyRotation.random(rng=3)
    t1 = median_time(lambda: a * b, repeat=7, number=20000)
    t1s = median_time(lambda: sa * sb, repeat=7, number=20000)
    print(f"one composition of two single rotations: {1e6 * t1:.2f} us (SciPy {1e6 * t1s:.2f} us)")
    _peers(q, n)


def _peers(q: np.ndarray, n: int) -> None:
    try:
        import quaternion  # numpy-quaternion
    except ImportError:
        print("numpy-quaternion not installed: skipped")
    else:
        qq = quaternion.as_quat_array(q)
        t = median_time(lambda: quaternion.as_rotation_matrix(qq), repeat=5)
        print(f"numpy-quaternion quat->matrix: {1e9 * t / n:.1f} ns/rot")
    try:
        import quaternionic
    except ImportError:
        print("quaternionic not installed: skipped")
    else:
        qa = quaternionic.array(q)
        t = median_time(lambda: qa.to_rotation_matrix, repeat=5)
        print(f"quaternionic quat->matrix: {1e9 * t / n:.1f} ns/rot")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
