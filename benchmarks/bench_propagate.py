"""Benchmark of attitude propagation (SPEC S5 task (a)) against peer libraries.

Motion: the coning motion ``L(t) = exp(A t/2) o exp(B t/2)`` over ``T = 10 s``,
driven by its closed-form angular velocity in space axes
``w_x(t) = A + R(A t) B`` (both peers integrate ``R' = 1/2 w_x o R``), so the
final error of every method is measured against the exact attitude.

Peers, measured in the same process (skipped if not installed; they are in the
``bench`` extra):

- ``quaternionic.array.from_angular_velocity(omega, t, R0, tolerance)``
  (SciPy ``solve_ivp`` DOP853, ``rtol = 100 eps``, ``atol = tolerance``);
- numpy-quaternion's ``quaternion.integrate_angular_velocity(Omega, t0, t1, R0,
  tolerance)`` (SciPy ``ode`` dop853).

For each peer tolerance we take the peer's final error ``e`` and find the
smallest number of equal steps for which ``propagate(..., method="magnus4")``
has final error <= ``e`` ("equal final error"), then time both. Two poinsot
variants: the same scalar callable the peers get, and ``vectorized=True`` (one
call with all stage times). Ratio = peer time / poinsot time (> 1: poinsot
faster). Then the throughput of each fixed-step method for a batch of N =
100,000 bodies, in body-steps per second.

Run: ``.venv/bin/python benchmarks/bench_propagate.py``
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _timing import median_time, table  # noqa: E402

from poinsot.kinematics.propagation import propagate  # noqa: E402

A = np.array([0.3, -0.2, 1.1])
B = np.array([0.7, 0.5, -0.4])
T = 10.0
_NA = float(np.linalg.norm(A))
_EA = A / _NA
# Rodrigues: R(A t) B = B cos + (e x B) sin + e (e.B)(1 - cos); precomputed terms.
_B_PAR = _EA * (_EA @ B)
_B_PERP = B - _B_PAR
_E_X_B = np.cross(_EA, B)
_A_PLUS = A + _B_PAR


def w_space(t: float) -> np.ndarray:
    """Closed-form space-frame angular velocity of the coning motion (scalar t)."""
    c, s = math.cos(_NA * t), math.sin(_NA * t)
    return _A_PLUS + _B_PERP * c + _E_X_B * s


def w_space_vec(t: np.ndarray) -> np.ndarray:
    """The same, for an array of times (``vectorized=True``)."""
    a = _NA * np.asarray(t)[:, None]
    return _A_PLUS + _B_PERP * np.cos(a) + _E_X_B * np.sin(a)


def exact_final() -> np.ndarray:
    """Exact scalar-first quaternion at T, from SciPy (an independent oracle)."""
    from scipy.spatial.transform import Rotation as SR

    r = SR.from_rotvec(A * T) * SR.from_rotvec(B * T)
    return r.as_quat(scalar_first=True)


Q_T = exact_final()


def qerr(q) -> float:
    q = np.asarray(q, dtype=float)
    return float(min(np.linalg.norm(q - Q_T), np.linalg.norm(q + Q_T)))


def poinsot_final(n: int, vectorized: bool, method: str = "magnus4"):
    f = w_space_vec if vectorized else w_space
    tr = propagate(
        [1, 0, 0, 0],
        f,
        [0.0, T],
        frame="space",
        method=method,
        steps_per_sample=n,
        vectorized=vectorized,
    )
    return tr.quat[-1]


def steps_for(err_target: float, method: str) -> int:
    """Fewest steps with final error <= err_target (error ~ C h^p, then refined)."""
    p = 4 if method == "magnus4" else 6
    n0 = 64
    e0 = qerr(poinsot_final(n0, True, method))
    n = max(1, int(n0 * (e0 / err_target) ** (1.0 / p) * 0.8))
    while qerr(poinsot_final(n, True, method)) > err_target:
        n = int(n * 1.03) + 1
    return n


def peers():
    """(name, run(tolerance) -> final quaternion) for each installed peer."""
    out = []
    try:
        import quaternionic

        def run_quaternionic(tol):
            R = quaternionic.array.from_angular_velocity(
                lambda R, t: w_space(t), np.array([0.0, T]), tolerance=tol
            )
            return R.ndarray[-1]

        out.append(("quaternionic", run_quaternionic))
    except ImportError:
        print("quaternionic not installed: skipped (pip install quaternionic)")
    try:
        import quaternion

        def run_npq(tol):
            _, R = quaternion.integrate_angular_velocity(w_space, 0.0, T, tolerance=tol)
            return quaternion.as_float_array(R[-1])

        out.append(("numpy-quaternion", run_npq))
    except ImportError:
        print("numpy-quaternion not installed: skipped (pip install numpy-quaternion)")
    return out


def one_body():
    rows = []
    for name, run in peers():
        for tol in (1e-8, 1e-10, 1e-12):
            e_peer = qerr(run(tol))
            t_peer = median_time(lambda run=run, tol=tol: run(tol), repeat=5)
            for method in ("magnus4", "magnus6"):
                n = steps_for(e_peer, method)
                e_ours = qerr(poinsot_final(n, True, method))
                t_scalar = median_time(lambda n=n, m=method: poinsot_final(n, False, m), repeat=5)
                t_vec = median_time(lambda n=n, m=method: poinsot_final(n, True, m), repeat=7)
                rows.append(
                    [
                        name,
                        f"{tol:.0e}",
                        f"{e_peer:.1e}",
                        f"{t_peer * 1e3:.2f}",
                        method,
                        f"{n}",
                        f"{e_ours:.1e}",
                        f"{t_scalar * 1e3:.2f} ({t_peer / t_scalar:.1f}x)",
                        f"{t_vec * 1e3:.3f} ({t_peer / t_vec:.0f}x)",
                    ]
                )
    if rows:
        header = [
            "peer",
            "peer tol",
            "peer err",
            "peer ms",
            "method",
            "steps",
            "our err",
            "ours ms, scalar fn (ratio)",
            "ours ms, vectorized (ratio)",
        ]
        print("One body, coning motion, T = 10 s, equal final error (space-frame omega)")
        print(table(rows, header))


def peers_samples():
    """(name, run(t, w) -> final quaternion) integrating the cubic spline through samples."""
    out = []
    try:
        import quaternionic

        def run_quaternionic(t, w):
            return quaternionic.array.from_angular_velocity(w, t).ndarray[-1]

        out.append(("quaternionic", run_quaternionic))
    except ImportError:
        pass
    try:
        import quaternion

        def run_npq(t, w):
            _, R = quaternion.integrate_angular_velocity((t, w), t[0], t[-1])
            return quaternion.as_float_array(R[-1])

        out.append(("numpy-quaternion", run_npq))
    except ImportError:
        pass
    return out


def one_body_samples():
    """Gyro-like input: omega sampled on n points, all three integrate its cubic spline."""
    rows = []
    for n in (101, 1001, 10001):
        t = np.linspace(0.0, T, n)
        w = w_space_vec(t)

        def ours(k, t=t, w=w):
            return propagate([1, 0, 0, 0], w, t, frame="space", steps_per_sample=k).quat[-1]

        for name, run in peers_samples():
            e_peer = qerr(run(t, w))
            t_peer = median_time(lambda run=run, t=t, w=w: run(t, w), repeat=3)
            # both integrate the same spline, whose own error is the floor: "equal" = within 10%
            k = 1
            while qerr(ours(k)) > 1.1 * e_peer and k < 64:
                k += 1
            e_ours = qerr(ours(k))
            t_ours = median_time(lambda k=k: ours(k), repeat=5)
            rows.append(
                [
                    name,
                    f"{n}",
                    f"{e_peer:.1e}",
                    f"{t_peer * 1e3:.2f}",
                    f"{k}",
                    f"{e_ours:.1e}",
                    f"{t_ours * 1e3:.3f}",
                    f"{t_peer / t_ours:.0f}x",
                ]
            )
    if rows:
        print("\nOne body, omega as n samples on [0, 10 s] (cubic spline), equal error (10%)")
        header = ["peer", "n", "peer err", "peer ms", "steps/sample", "our err", "ours ms", "ratio"]
        print(table(rows, header))


def batch(n_bodies=100_000, n_steps=20):
    rng = np.random.default_rng(0)
    q0 = rng.normal(size=(n_bodies, 4))
    amp = rng.uniform(0.5, 2.0, (n_bodies, 3))
    t = np.linspace(0.0, 1.0, n_steps + 1)

    def w_vec(s):  # (m,) -> (m, N, 3)
        s = np.asarray(s)[:, None, None]
        return amp * np.concatenate([np.sin(s), np.cos(2 * s), np.ones_like(s)], axis=-1)

    def w_scalar(s):  # -> (N, 3)
        return amp * np.array([math.sin(s), math.cos(2 * s), 1.0])

    w_samples = w_vec(t)
    rows = []
    for method in ("magnus4", "magnus6", "rk4", "exponential"):
        for label, omega, vec in (
            ("callable (N,3)", w_scalar, False),
            ("vectorized", w_vec, True),
            ("samples", w_samples, False),
        ):

            def every(method=method, omega=omega, vec=vec):
                return propagate(q0, omega, t, method=method, vectorized=vec)

            def ends(method=method, omega=omega, vec=vec):
                # the same steps, output only at both ends (samples: every step is a sample)
                return propagate(
                    q0, omega, t[[0, -1]], method=method, vectorized=vec, steps_per_sample=n_steps
                )

            sec = median_time(every, repeat=3)
            row = [method, label, f"{sec * 1e3:.0f}", f"{n_bodies * n_steps / sec:.2e}"]
            if label == "samples":
                row += ["-", "-"]
            else:
                sec2 = median_time(ends, repeat=3)
                row += [f"{sec2 * 1e3:.0f}", f"{n_bodies * n_steps / sec2:.2e}"]
            rows.append(row)
    print(
        f"\nBatch throughput, N = {n_bodies:,} bodies, {n_steps} steps (omega evaluation included)"
    )
    header = [
        "method",
        "omega",
        "ms (output every step)",
        "body-steps/s",
        "ms (output at ends)",
        "body-steps/s",
    ]
    print(table(rows, header))


if __name__ == "__main__":
    t0 = time.perf_counter()
    one_body()
    one_body_samples()
    batch()
    print(f"\n(total {time.perf_counter() - t0:.1f} s)")
