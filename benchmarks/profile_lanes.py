"""Where the lane-blocked DOP853 (``poinsot.dynamics._fused_lanes``) spends its time.

One thread. For a batch of free bodies and one of heavy (Lagrange-like) tops it prints
the whole kernel's cost per right-hand-side evaluation per body (from the kernel's own
evaluation counts), the cost of one step attempt alone (12 stages of ``L`` lanes,
``y_new``, the error norm: looped on a fixed state) and of the right-hand side alone
(every lane), both per evaluation per body: the rest of the kernel's time is the
per-lane step control, loading bodies and writing outputs.

``--control`` also splits the chunk loop's time by phase (refilling and checking the
lanes, the attempt, accept/reject, dense output, accepting) with the CPU's cycle
counter, per lane-attempt (one body's step attempt); the parts add up to the whole.

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
        kind = FL.Kind(kind)  # the lane kernels are compiled per kind
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
    """The chunk loop's time split by phase with the CPU's cycle counter.

    A copy of ``_fused_lanes._chunk`` whose phases (refilling and checking the lanes,
    the attempt, accept/reject, dense output, accepting) are bracketed by
    ``lfence`` + ``llvm.readcyclecounter``: the parts add up to the whole by construction
    (the fence and the counter's own cost land in the phases)."""
    from numba import njit
    from numba.core import types
    from numba.extending import intrinsic

    from poinsot.dynamics import GravityTorque
    from poinsot.dynamics import _fused_lanes as FL
    from poinsot.dynamics._fused_run import _flat_problem

    @intrinsic
    def cycles(typingctx):
        def codegen(context, builder, signature, args):
            from llvmlite import ir

            # lfence first: the counter is read once the phase's instructions are done,
            # not while the out-of-order core still works on them
            fence = builder.module.declare_intrinsic(
                "llvm.x86.sse2.lfence", fnty=ir.FunctionType(ir.VoidType(), [])
            )
            builder.call(fence, [])
            fnty = ir.FunctionType(ir.IntType(64), [])
            fn = builder.module.declare_intrinsic("llvm.readcyclecounter", fnty=fnty)
            return builder.call(fn, [])

        return types.int64(), codegen

    L = FL.L

    @njit
    def chunk(lo, hi, y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow,
              stats, cancel, done, acc):  # fmt: skip
        W = np.zeros(FL.N_WORK)
        scratch = np.empty((1, 7))
        t_end = t_out[-1]
        c0 = cycles()
        first = np.empty((hi - lo, 8))
        FL._first_steps(lo, hi, W, y0, J, Ji, kind, par, t_end - t_out[0], rtol, atol,
                        max_step, first)  # fmt: skip
        W[:] = 0.0
        W[FL.S_BODY : FL.S_BODY + L] = -1.0
        W[FL.S_END : FL.S_END + L] = -1.0
        acc[0] += cycles() - c0
        nxt = lo
        while True:
            c0 = cycles()
            n_busy, n_end = FL.lane_prepare(W, t_end, max_step, max_steps, cancel[0] != 0)
            while n_end > 0 or (n_busy < L and nxt < hi):
                nxt = FL.lane_service(nxt, lo, hi, W, y0, J, Ji, par, t_out, first,
                                      oq, ow, stats, done)  # fmt: skip
                n_busy, n_end = FL.lane_prepare(W, t_end, max_step, max_steps, cancel[0] != 0)
            c1 = cycles()
            acc[0] += c1 - c0
            if n_busy == 0:
                break
            acc[5] += n_busy
            FL._attempt(W, kind, rtol, atol)
            c2 = cycles()
            n_dense = FL.lane_control(W)
            c3 = cycles()
            if n_dense > 0:
                FL._dense(W, kind)
                FL.lane_dense_out(W, scratch, t_out, oq, ow, done)
            c4 = cycles()
            if FL.lane_accept(W) > 0:
                FL.lane_events(W, scratch, t_out, oq, ow, stats, done)
            c5 = cycles()
            acc[1] += c2 - c1
            acc[2] += c3 - c2
            acc[3] += c4 - c3
            acc[4] += c5 - c4

    n = len(moments)
    t_out = np.array([0.0, 10.0])
    cases = {
        "free, rtol 1.5e-7": (None, 1.5e-7),
        "heavy, rtol 1.3e-8": (GravityTorque(1.0, [0.0, 0.0, 0.3], g=9.81), 1.3e-8),
    }
    names = ["first steps, prepare + refill", "attempt (12 stages)", "accept/reject",
             "dense output", "accept: project, outputs"]  # fmt: skip
    print("  split of the chunk loop (cycle counter, 1 thread; per lane-attempt, i.e. one "
          "body's step attempt):")  # fmt: skip
    for name, (tq, rtol) in cases.items():
        _, kind, par, jj, ji, y0 = _flat_problem(moments, quat, omega, tq)
        kind = FL.Kind(kind)  # the lane kernels are compiled per kind
        best = None
        for _ in range(repeat + 1):
            oq, ow = np.empty((2, n, 4)), np.empty((2, n, 3))
            stats = np.zeros((n, 4), np.int64)
            cancel, done = np.zeros(1, np.int64), np.zeros(n, np.int64)
            acc = np.zeros(6, np.int64)
            t0 = time.perf_counter()
            for lo in range(0, n, FL.CHUNK):
                chunk(lo, min(n, lo + FL.CHUNK), y0, jj, ji, kind, par, t_out, rtol,
                      rtol * 1e-2, np.inf, 10**6, oq, ow, stats, cancel, done, acc)  # fmt: skip
            secs = time.perf_counter() - t0
            if best is None or secs < best[0]:
                best = (secs, acc)
        secs, acc = best
        per_cycle = secs / acc[:5].sum()  # seconds per counter tick
        lanes = acc[5]
        parts = ", ".join(
            f"{k} {1e9 * per_cycle * acc[i] / lanes:.0f} ns ({100 * acc[i] / acc[:5].sum():.0f}%)"
            for i, k in enumerate(names)
        )
        print(f"  {name}: {1e9 * secs / lanes:.0f} ns per lane-attempt = {parts}")


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
