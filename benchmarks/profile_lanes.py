"""Where the lane-blocked DOP853 (``poinsot.dynamics._fused_lanes``) spends its time.

One thread. For a batch of free bodies and one of heavy (Lagrange-like) tops it prints
the whole kernel's cost per right-hand-side evaluation per body (from the kernel's own
evaluation counts), the cost of one step attempt alone (12 stages of ``L`` lanes,
``y_new``, the error norm: looped on a fixed state) and of the right-hand side alone
(every lane), both per evaluation per body: the rest of the kernel's time is the
per-lane step control, loading bodies and writing outputs.

``--control`` also times the kernel with the attempt replaced by a stub (``y_new = y``,
an error norm that keeps the step): the cost of everything but the attempt, per attempt
per body (it compiles a copy of the chunk loop: a few minutes).

Run: ``python benchmarks/profile_lanes.py [--n 10000] [--repeat 5] [--control]``.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def _best(fn, repeat):
    fn()
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--control", action="store_true")
    a = ap.parse_args()
    from poinsot.dynamics import GravityTorque, simulate
    from poinsot.dynamics import _fused_lanes as FL
    from poinsot.rotations import set_num_threads

    set_num_threads(1)
    rng = np.random.default_rng(0)
    n = a.n
    moments = rng.uniform(1.0, 2.0, (n, 3))
    omega = rng.normal(size=(n, 3))
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    t = np.array([0.0, 10.0])
    loops = 20_000
    print(f"{n} bodies, 10 s, 1 thread, lanes L = {FL.L}; load {os.getloadavg()[0]:.2f}")
    cases = {
        "free, rtol 1.5e-7": (None, 1.5e-7, 0),
        "heavy, rtol 1.3e-8": (GravityTorque(1.0, [0.0, 0.0, 0.3], g=9.81), 1.3e-8, 3),
    }
    for name, (torque, rtol, kind) in cases.items():

        def run(torque=torque, rtol=rtol):
            return simulate(moments, quat, omega, t, torque=torque, method="dop853",
                            rtol=rtol, atol=rtol * 1e-2)  # fmt: skip

        total = _best(run, a.repeat)
        nfev = int(run().info["evaluations"])
        W = np.zeros(FL.N_WORK)
        W[FL.OFF_Y : FL.OFF_Y + 4 * FL.L] = 0.5  # a unit quaternion in every lane
        W[FL.OFF_Y + 4 * FL.L : FL.OFF_Y + 7 * FL.L] = 0.3
        for r in range(3):  # J = diag(1, 1.5, 2), J^-1; gravity parameters
            W[FL.OFF_J + (4 * r) * FL.L : FL.OFF_J + (4 * r + 1) * FL.L] = 1.0 + 0.5 * r
            W[FL.OFF_JI + (4 * r) * FL.L : FL.OFF_JI + (4 * r + 1) * FL.L] = 1.0 / (1 + 0.5 * r)
        W[FL.OFF_P : FL.OFF_P + 4 * FL.L] = [1.0] * FL.L + [0.0] * (2 * FL.L) + [2.9] * FL.L
        W[FL.OFF_H : FL.OFF_H + FL.L] = 1e-3
        W[FL.OFF_K : FL.OFF_K + 7 * FL.L] = 0.1
        att = _best(lambda W=W, kind=kind: _attempts(W, kind, loops), a.repeat)
        att /= loops * FL.L * 12
        rhs = _best(lambda W=W, kind=kind: _rhss(W, kind, loops), a.repeat) / (loops * FL.L)
        per = f", {1e9 * total / nfev:.1f} ns per evaluation per body"
        print(f"  {name}: kernel + Python {total:.3f} s ({nfev} evaluations{per});"
              f" attempt alone {1e9 * att:.1f} ns, right-hand side alone {1e9 * rhs:.1f} ns"
              " per evaluation per body")  # fmt: skip

    if a.control:
        _control(moments, quat, omega, a.repeat)


def _control(moments, quat, omega, repeat):
    """The chunk loop with a stub attempt, and the real one, per attempt per body."""
    import inspect

    from numba import njit

    from poinsot.dynamics import GravityTorque
    from poinsot.dynamics import _fused_lanes as FL
    from poinsot.dynamics._fused import _flat_problem

    L = FL.L
    off_y, off_k, off_yn, off_err = FL.OFF_Y, FL.OFF_K, FL.OFF_YN, FL.OFF_ERR

    @njit
    def stub(W, kind, rtol, atol):
        for l in range(L):
            for c in range(7):
                W[off_yn + c * L + l] = W[off_y + c * L + l]
                W[off_k + 12 * 7 * L + c * L + l] = W[off_k + c * L + l]
            W[off_err + l] = 0.9**8  # SAFETY * err^(-1/8) = 1: the step is kept

    src = inspect.getsource(FL._chunk.py_func).replace("@njit(cache=True)\n", "")
    src = src.replace("def _chunk(", "def _stub_chunk(").replace("_attempt(W,", "_stub(W,")
    ns = dict(vars(FL), _stub=stub)
    exec(src, ns)  # noqa: S102 - the kernel's own source with the attempt swapped
    chunks = {"real": FL._chunk, "stub attempt": njit(ns["_stub_chunk"])}
    n = len(moments)
    tq = GravityTorque(1.0, [0.0, 0.0, 0.3], g=9.81)
    _, kind, par, jj, ji, y0 = _flat_problem(moments, quat, omega, tq)
    t_out = np.array([0.0, 10.0])

    def run(chunk):
        oq, ow = np.empty((2, n, 4)), np.empty((2, n, 3))
        stats = np.zeros((n, 4), np.int64)
        cancel, done = np.zeros(1, np.int64), np.zeros(n, np.int64)
        for lo in range(0, n, FL.CHUNK):
            chunk(lo, min(n, lo + FL.CHUNK), y0, jj, ji, kind, par, t_out, 1.3e-8, 1.3e-10,
                  np.inf, 10**6, oq, ow, stats, cancel, done)  # fmt: skip
        return stats

    for name, chunk in chunks.items():
        stats = run(chunk)
        secs = _best(lambda chunk=chunk: run(chunk), repeat)
        tries = int(stats[:, 0].sum() + stats[:, 1].sum())
        print(f"  heavy, {name}: {secs:.3f} s, {tries} attempts, "
              f"{1e9 * secs / tries:.0f} ns per attempt per body")  # fmt: skip


def _attempts(W, kind, loops):
    from poinsot.dynamics import _fused_lanes as FL

    return _loop_attempt(FL._attempt, W, kind, loops)


def _rhss(W, kind, loops):
    from poinsot.dynamics import _fused_lanes as FL

    return _loop_rhs(FL._rhs_lanes, W, kind, loops)


_CACHE: dict = {}


def _loop_attempt(attempt, W, kind, loops):
    if "a" not in _CACHE:
        from numba import njit

        @njit
        def go(W, kind, loops):
            for _ in range(loops):
                attempt(W, kind, 1e-8, 1e-10)
            return W[0]

        _CACHE["a"] = go
    return _CACHE["a"](W, kind, loops)


def _loop_rhs(rhs, W, kind, loops):
    if "r" not in _CACHE:
        from numba import njit

        @njit
        def go(W, kind, loops):
            for _ in range(loops):
                rhs(W, kind)
            return W[0]

        _CACHE["r"] = go
    return _CACHE["r"](W, kind, loops)


if __name__ == "__main__":
    main()
