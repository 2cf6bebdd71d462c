"""poinsot against the fastest peers, every table of issue 24 in one run.

Peers (each optional: a peer that is not installed is skipped with a message;
this script installs nothing; ``pip install poinsot[bench]`` brings them all):
SciPy, diffrax/JAX, jaxlie, numpy-quaternion, quaternionic, MuJoCo, Pinocchio,
SymPy.

Rules followed by every table:

* same process, same run; each time is the **minimum** of ``--repeat`` runs
  (after a warm-up that also compiles), and the runs are **interleaved**: each
  round times poinsot and every peer of a row once, in turn, so that a slow spell
  of the shared machine falls on all of them alike;
* SciPy's OpenBLAS is pinned to one thread (threadpoolctl) for SciPy's runs:
  ``solve_ivp`` takes norms of the long state through BLAS, and on a shared
  machine a BLAS call waits for its second thread (about 10x slower for the same
  evaluations). Without threadpoolctl the tables say so;
* integrators are compared at **equal final accuracy**: for each method the
  tolerance is searched (``rtol`` on a half-decade grid, then refined by log-log
  interpolation and checked) until the largest final attitude error over the
  batch, against the exact solution, is at most the target (1e-6, 1e-9 rad);
  the time printed is that run's (``atol = rtol / 100`` for every method);
* the machine load (``os.getloadavg``) is printed at the start and the end.

Run: ``python benchmarks/bench_peers.py [--repeat 5] [--only rot,free,heavy,pend,derive]``.
"""

# ruff: noqa: B023  (the closures timed in each loop iteration run within it)
from __future__ import annotations

import argparse
import contextlib
import math
import os
import platform
import sys
import time
from collections.abc import Callable, Iterator

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _timing import table  # noqa: E402

DURATION = 10.0
TARGETS = (1e-6, 1e-9)
REPEAT = 5
SMALL = 10_000


def best(fn: Callable[[], object], repeat: int | None = None) -> float:
    """Minimum wall time of ``fn()`` over ``repeat`` runs (after one warm-up run)."""
    fn()
    times = []
    for _ in range(repeat or REPEAT):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def interleaved(
    fns: dict[str, Callable[[], object]],
    number: int = 1,
    repeat: int | None = None,
    before: dict[str, Callable[[], object]] | None = None,
) -> dict[str, float]:
    """Per name, the minimum over ``repeat`` rounds of the mean time of ``number`` calls.

    Each round times every function once, in turn (after one warm-up round), so that a
    slow spell of the shared machine falls on poinsot and its peers alike: timed one
    after the other, the same n = 2 pendulum call took 0.80 us in one process and
    1.35-1.55 us in the next, the interpreter's empty loop 1.7x slower with it.
    ``before[name]``, if given, runs untimed before each of that name's timings."""
    before = before or {}
    times: dict[str, list[float]] = {name: [] for name in fns}
    for r in range((repeat or REPEAT) + 1):
        for name, fn in fns.items():
            if name in before:
                before[name]()
            t0 = time.perf_counter()
            for _ in range(number):
                fn()
            if r:
                times[name].append((time.perf_counter() - t0) / number)
    return {name: min(ts) for name, ts in times.items()}


def missing(name: str, exc: Exception) -> None:
    print(f"  [{name} not installed: skipped ({type(exc).__name__}: {exc})]")


@contextlib.contextmanager
def blas_one_thread() -> Iterator[str]:
    """SciPy's BLAS on one thread (threadpoolctl), or a note that it could not be pinned."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        yield "BLAS threads NOT pinned (threadpoolctl not installed)"
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield "BLAS pinned to 1 thread"


def load() -> str:
    a, b, c = os.getloadavg()
    return f"load average {a:.2f} / {b:.2f} / {c:.2f} (1/5/15 min) on {os.cpu_count()} cores"


def set_threads(n: int | None) -> None:
    from poinsot.rotations import set_num_threads

    set_num_threads(n)


# ----------------------------------------------------------------- rotations
def rotations(n: int) -> None:
    from scipy.spatial.transform import Rotation as SciPyRotation

    from poinsot import Rotation

    rng = np.random.default_rng(0)
    q = rng.standard_normal((n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    r = Rotation.from_quat(q)
    s = SciPyRotation.from_quat(q, scalar_first=True)
    m = r.as_matrix()
    # the two slow matrix -> quaternion peers (~17 us per rotation: an eigen/linear
    # solve each) are timed on the first SMALL rotations, per rotation
    m_small = m[:SMALL]
    # The memory floor: the time per byte of copying an array as large as a matrix batch
    # (a fresh result array, its pages faulted in as any new NumPy result's are), times
    # the bytes each operation must read and write; timed in each row's rounds.
    f8 = 8 * n
    into = np.empty_like(m)  # as_matrix(out=into): a result array reused from call to call
    into_copy = np.empty_like(m)
    # Euler angles: roll, pitch, yaw about the fixed x, y, z (extrinsic "xyz"), jaxlie's
    # as_rpy_radians; numpy-quaternion and quaternionic offer only z-y-z (marked †)
    ops: list[tuple[str, int, Callable[[], object], Callable[[], object]]] = [
        ("matrix -> quaternion", f8 * 13, lambda: Rotation.from_matrix(m), lambda: None),
        ("inverse", f8 * 8, lambda: r.inv(), lambda: None),
        ("quaternion -> matrix", f8 * 13, lambda: r.as_matrix(), lambda: None),
        ("quaternion -> matrix, out=", f8 * 13, lambda: r.as_matrix(out=into), lambda: None),
        ("quaternion -> Euler xyz", f8 * 7, lambda: r.as_euler("xyz"), lambda: None),
    ]
    peers: dict[str, list[Callable[[], object] | None]] = {
        "SciPy": [
            lambda: SciPyRotation.from_matrix(m),
            lambda: s.inv(),
            lambda: s.as_matrix(),
            lambda: s.as_matrix(),
            lambda: s.as_euler("xyz"),
        ]
    }
    try:
        import jax

        jax.config.update("jax_enable_x64", True)
        import jax.numpy as jnp
        import jaxlie

        jm, jq = jnp.asarray(m), jnp.asarray(q)
        f_m2q = jax.jit(lambda a: jaxlie.SO3.from_matrix(a).wxyz)
        f_inv = jax.jit(lambda a: jaxlie.SO3(a).inverse().wxyz)
        f_q2m = jax.jit(lambda a: jaxlie.SO3(a).as_matrix())
        f_rpy = jax.jit(lambda a: jnp.stack(jaxlie.SO3(a).as_rpy_radians(), axis=-1))
        assert np.allclose(np.abs(np.sum(np.asarray(f_m2q(jm)) * q, axis=1)), 1.0, atol=1e-12)
        assert np.allclose(np.asarray(f_rpy(jq)), s.as_euler("xyz"), rtol=0, atol=1e-12)
        peers["jaxlie (XLA)"] = [
            lambda: f_m2q(jm).block_until_ready(),
            lambda: f_inv(jq).block_until_ready(),
            lambda: f_q2m(jq).block_until_ready(),
            lambda: f_q2m(jq).block_until_ready(),
            lambda: f_rpy(jq).block_until_ready(),
        ]
    except ImportError as e:
        missing("jaxlie", e)
    try:
        import quaternion as npq

        qq = npq.as_quat_array(q)
        peers["numpy-quaternion"] = [
            lambda: npq.from_rotation_matrix(m_small),
            lambda: np.reciprocal(qq),
            lambda: npq.as_rotation_matrix(qq),
            lambda: npq.as_rotation_matrix(qq),
            lambda: npq.as_euler_angles(qq),
        ]
    except ImportError as e:
        missing("numpy-quaternion", e)
    try:
        import quaternionic

        qa = quaternionic.array(q)
        peers["quaternionic"] = [
            lambda: quaternionic.array.from_rotation_matrix(m_small),
            lambda: qa.inverse,
            lambda: qa.to_rotation_matrix,
            lambda: qa.to_rotation_matrix,
            lambda: qa.to_euler_angles,
        ]
    except ImportError as e:
        missing("quaternionic", e)

    rows = []
    cores = os.cpu_count() or 1
    per_bytes = []
    for k, (name, nbytes, ours, _) in enumerate(ops):
        # poinsot pinned to every core, as the integrators below and as XLA runs (the
        # default follows the load average, which this script's own runs raise), and to
        # one thread; every function of the row timed in the same interleaved rounds
        fns: dict[str, Callable[[], object]] = {"auto": ours, "one": ours, "floor": m.copy}
        fns.update((pname, fs[k]) for pname, fs in peers.items() if fs[k] is not None)
        before = {"auto": lambda: set_threads(cores), "one": lambda: set_threads(1)}
        if name == "quaternion -> matrix":  # what bounds it: writing its result alone
            fns["write"], before["write"] = lambda: write_fresh(m.size), before["auto"]
        if name.endswith("out="):  # the floor of a reused result: copying into one
            fns["copyto"] = lambda: np.copyto(into_copy, m)
        t = interleaved(fns, before=before)
        set_threads(None)
        t_auto, t_one = t["auto"], t["one"]
        per_byte = t["floor"] / (2 * m.nbytes)
        per_bytes.append(per_byte)
        floor = per_byte * nbytes
        row = [name, f"{1e9 * t_auto / n:.1f}", f"{1e9 * t_one / n:.1f}", f"{1e9 * floor / n:.1f}"]
        best_peer, best_name = math.inf, "-"
        for pname in peers:
            if pname not in t:
                row.append("-")
                continue
            slow = k == 0 and pname in ("numpy-quaternion", "quaternionic")
            tp = t[pname] * (n / SMALL if slow else 1.0)
            zyz = name.endswith("Euler xyz") and pname in ("numpy-quaternion", "quaternionic")
            row.append(f"{1e9 * tp / n:.1f}" + ("*" if slow else "") + ("†" if zyz else ""))
            if pname != "SciPy" and tp < best_peer:
                best_peer, best_name = tp, pname
        row += [f"{best_peer / t_auto:.2f}x ({best_name})", f"{t_auto / floor:.2f}x"]
        rows.append(row)
        if "write" in t:
            t_write, floor_q2m = t["write"], floor
        if "copyto" in t:
            t_copyto, t_out = t["copyto"] * nbytes / (2 * m.nbytes), t_auto
    head = [f"N = {n:.0e}, ns per rotation", f"poinsot ({cores} thr)", "poinsot 1 thr"]
    head.append("copy floor")
    head += list(peers) + ["best non-SciPy peer / poinsot", "poinsot / floor"]
    print(table(rows, head))
    print(
        f"  (* timed on {SMALL} rotations; † their only Euler sequence, z-y-z; the out= row "
        "writes into one (N, 3, 3) array reused from call to call, the peers (none offers "
        "out=) their fresh result)"
    )
    print(
        f"  (poinsot's default would take {_threads()} thread(s) now: the idle cores; copy floor = "
        f"{1e-9 / max(per_bytes):.1f}-{1e-9 / min(per_bytes):.1f} GB/s from copying the (N, 3, 3) "
        f"batch in each row's rounds; copying the (N, 4) "
        f"quaternions, small enough for malloc to reuse its pages: "
        f"{1e9 * best(lambda: q.copy()) / n:.1f} ns per rotation)"
    )
    print(
        f"  (writing a fresh (N, 3, 3) result alone, streaming stores of one value on "
        f"{cores} threads, in the quaternion -> matrix rounds: {1e9 * t_write / n:.1f} ns "
        f"per rotation, {t_write / floor_q2m:.2f}x the floor)"
    )
    print(
        f"  (the floor of a reused result: copying the (N, 3, 3) batch into an existing array, "
        f"times the bytes of quaternion -> matrix, {1e9 * t_copyto / n:.1f} ns per rotation; "
        f"out= takes {t_out / t_copyto:.2f}x that)"
    )


def write_fresh(size: int) -> np.ndarray:
    """A new float64 array of ``size`` values, each written once by a streaming store
    spread over numba's threads: the least a function returning a fresh array that
    large can do (its pages faulted in, every line written, nothing read)."""
    global _WRITE
    if _WRITE is None:
        from numba import njit, prange

        from poinsot import _numba_helpers as nh

        @njit(parallel=True)
        def fill(d):
            parts = 64
            per = -(-d.size // parts)
            for p in prange(parts):
                for i in range(p * per, min(d.size, (p + 1) * per)):
                    nh.store_nt(d, i, 1.0)
                nh.fence()

        _WRITE = fill
    d = np.empty(size)
    _WRITE(d)
    return d


_WRITE: Callable[[np.ndarray], None] | None = None


def _threads() -> int:
    from poinsot.rotations._lazy import thread_count

    return thread_count()


# ----------------------------------------------------------- batch integration
def attitude_error(q: np.ndarray, ref: np.ndarray) -> float:
    """Largest angle (rad) between the final attitudes and the exact ones."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    d = np.minimum(np.linalg.norm(q - ref, axis=-1), np.linalg.norm(q + ref, axis=-1))
    return float(np.max(4.0 * np.arcsin(np.minimum(d / 2.0, 1.0))))


def tolerance_for(
    run: Callable[[float], np.ndarray], ref: np.ndarray, target: float, start: float
) -> tuple[float, float, float]:
    """The loosest ``rtol`` (searched, see the module notes) whose final attitude error is at
    most ``target``: ``(rtol, error, seconds of that run)``."""
    from poinsot import IntegrationError

    tol, prev = start, None
    while True:
        if tol < 1e-14:  # the method (or the reference) cannot reach the target
            return math.nan, math.nan, math.nan
        t0 = time.perf_counter()
        try:
            err = attitude_error(run(tol), ref)
        except IntegrationError:
            return math.nan, math.nan, math.nan
        dt = time.perf_counter() - t0
        if err <= target:
            break
        prev = (tol, err)
        tol /= math.sqrt(10.0)
    if prev is not None and err > 0:
        # refine between the bracketing grid points (error ~ tol^p, log-log)
        (t1, e1), (t2, e2) = prev, (tol, err)
        p = math.log(e1 / e2) / math.log(t1 / t2) if e1 > e2 else 1.0
        cand = t2 * (target / e2) ** (1.0 / p) * 0.9
        # strictly inside the bracket: a flat error curve (small p) would send it far
        # beyond t1, to tolerances no method can use
        cand = min(cand, t1 / 1.05)
        for _ in range(6):
            if cand <= t2:
                break
            e = attitude_error(run(cand), ref)
            if e <= target:
                tol, err = cand, e
                break
            cand = math.sqrt(cand * t2)
    return tol, err, dt


def scipy_run(moments, quat, omega, torque=None):
    """SciPy's DOP853 on the batch as one vectorised 7N system (bench_fused's, which pins
    SciPy's BLAS to one thread when threadpoolctl is installed)."""
    from bench_fused import scipy_batch

    def run(rtol: float) -> np.ndarray:
        return scipy_batch(moments, quat, omega, DURATION, rtol, torque)[0]

    return run


def diffrax_run(moments, quat, omega, mgc=None):
    import diffrax
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    n = len(moments)
    inv = jnp.asarray(1.0 / moments.T)
    mom = jnp.asarray(moments.T)
    mg = None if mgc is None else jnp.asarray(mgc.T)

    def rhs(_t, y, _args):
        y = y.reshape(7, n)
        q, w = y[:4], y[4:]
        dq = 0.5 * jnp.stack(
            [
                -(q[1] * w[0] + q[2] * w[1] + q[3] * w[2]),
                q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                q[0] * w[1] + q[3] * w[0] - q[1] * w[2],
                q[0] * w[2] + q[1] * w[1] - q[2] * w[0],
            ]
        )
        mm = jnp.cross(mom * w, w, axis=0)
        if mg is not None:
            a, b, c, d = q
            n2 = a * a + b * b + c * c + d * d
            gamma = jnp.stack(
                [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]
            )
            mm = mm + jnp.cross(gamma / n2, mg, axis=0)
        return jnp.concatenate([dq, mm * inv]).ravel()

    term = diffrax.ODETerm(rhs)
    solver = diffrax.Dopri8()

    @jax.jit
    def solve(y0, rtol):
        ctrl = diffrax.PIDController(rtol=rtol, atol=rtol * 1e-2)
        sol = diffrax.diffeqsolve(
            term,
            solver,
            0.0,
            DURATION,
            None,
            y0,
            stepsize_controller=ctrl,
            max_steps=1_000_000,
            saveat=diffrax.SaveAt(t1=True),
        )
        return sol.ys[-1]

    y0 = jnp.asarray(np.concatenate([quat.T, omega.T]).ravel())

    def run(rtol: float) -> np.ndarray:
        y = np.asarray(solve(y0, jnp.float64(rtol)).block_until_ready())
        return y.reshape(7, n)[:4].T

    return run


def poinsot_run(moments, quat, omega, torque=None):
    from poinsot.dynamics import simulate

    t = np.array([0.0, DURATION])

    def run(rtol: float) -> np.ndarray:
        tr = simulate(moments, quat, omega, t, torque=torque, method="dop853", rtol=rtol,
                      atol=rtol * 1e-2)  # fmt: skip
        return tr.quat[-1]

    return run


def integrate_table(title: str, ref: np.ndarray, runs: dict[str, Callable[[float], np.ndarray]]):
    """Find each run's tolerance for each target, then time all of them round-robin.

    The repeats are interleaved (one run of every solver per round, min over the rounds)
    so that a slow spell of a shared machine falls on every solver alike: timed one
    solver after the other, min of 5, the ratios on this VM moved by up to 1.5x."""
    tols: dict[str, list[tuple[float, float]]] = {}
    for name, run in runs.items():
        start, found = 1e-3, []
        for target in TARGETS:
            tol, err, _ = tolerance_for(run, ref, target, start)
            found.append((tol, err))
            if not math.isnan(tol):
                start = tol
        tols[name] = found
    times: dict[tuple[str, int], list[float]] = {}
    for _ in range(REPEAT + 1):  # the first round warms up, like best()
        for name, run in runs.items():
            for i, (tol, _err) in enumerate(tols[name]):
                if math.isnan(tol):
                    continue
                t0 = time.perf_counter()
                run(tol)
                times.setdefault((name, i), []).append(time.perf_counter() - t0)
    rows, found_t = [], {}
    for name in runs:
        row, ts = [name], []
        for i, (tol, err) in enumerate(tols[name]):
            if math.isnan(tol):
                row.append("not reached")
                ts.append(math.nan)
                continue
            t = min(times[name, i][1:])
            ts.append(t)
            row.append(f"{t:.3f} s (rtol {tol:.1e}, err {err:.1e})")
        found_t[name] = ts
        rows.append(row)
    ours = found_t[next(iter(runs))]
    for row, (_name, ts) in zip(rows, found_t.items(), strict=True):
        row.append(" / ".join(f"{t / o:.2f}x" for t, o in zip(ts, ours, strict=True)))
    head = [title] + [f"final attitude error <= {t:.0e}" for t in TARGETS]
    head.append(f"time / poinsot (min of {REPEAT} interleaved rounds)")
    print(table(rows, head))


def free_bodies(n: int) -> None:
    from poinsot.dynamics import FreeRigidBody

    rng = np.random.default_rng(0)
    moments = rng.uniform(1.0, 2.0, (n, 3))
    omega = rng.normal(size=(n, 3))
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    t = np.array([0.0, DURATION])
    exact = FreeRigidBody(moments, rotation0=quat, omega0=omega)
    ref = exact.rotation(t).as_quat()[:, -1]
    t_exact = best(lambda: exact.rotation(t).as_quat())
    runs = _integrators(moments, quat, omega, None, None)
    integrate_table(f"{n} free bodies, {DURATION:g} s", ref, runs)
    print(f"  (exact FreeRigidBody, the same final states: {t_exact:.3f} s)")


def _integrators(moments, quat, omega, torque, mgc):
    runs: dict[str, Callable[[float], np.ndarray]] = {}
    base = poinsot_run(moments, quat, omega, torque)
    cores = os.cpu_count() or 1

    def all_cores(rtol: float, base=base) -> np.ndarray:
        set_threads(cores)  # pinned: the default follows the load average
        try:
            return base(rtol)
        finally:
            set_threads(None)

    runs[f"poinsot dop853 ({cores} threads)"] = all_cores

    def one_thread(rtol: float, base=base) -> np.ndarray:
        set_threads(1)
        try:
            return base(rtol)
        finally:
            set_threads(None)

    runs["poinsot dop853 (1 thread)"] = one_thread

    def scalar_kernel(rtol: float, base=base) -> np.ndarray:
        from poinsot.dynamics import _fused_run

        set_threads(1)
        _fused_run.LANES = False
        try:
            return base(rtol)
        finally:
            _fused_run.LANES = True
            set_threads(None)

    # the kernel before the lanes: one body per loop iteration (the same results)
    runs["poinsot dop853, one body at a time (1 thread)"] = scalar_kernel
    try:
        dfx = diffrax_run(moments, quat, omega, mgc)
        runs[f"diffrax Dopri8 (7N system, jit; XLA on {cores} cores)"] = dfx
        # (XLA's thread pool cannot be shrunk once JAX runs: to time diffrax on one
        # core, run this script under `taskset -c 0`, poinsot then takes 1 thread too)
    except ImportError as e:
        missing("diffrax", e)
    from bench_fused import gravity_numpy

    sc = scipy_run(moments, quat, omega, None if mgc is None else gravity_numpy(mgc))

    def scipy_pinned(rtol: float) -> np.ndarray:
        with blas_one_thread():
            return sc(rtol)

    with blas_one_thread() as note:
        pass
    runs[f"SciPy DOP853 (7N system, {note})"] = scipy_pinned
    return runs


def heavy_tops(n: int) -> None:
    from poinsot.dynamics import GravityTorque, LagrangeTop

    rng = np.random.default_rng(1)
    mass, g = 1.0, 9.81
    moments, com, quat, omega, ref = [], [], [], [], []
    skipped = 0
    t0 = time.perf_counter()
    while len(ref) < n:
        a = rng.uniform(1.0, 2.0)
        mom = np.array([a, a, a * rng.uniform(0.4, 1.6)])
        c = np.array([0.0, 0.0, rng.uniform(0.05, 0.3)])
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w = rng.normal(size=3) + [0.0, 0.0, rng.uniform(2.0, 10.0)]
        top = LagrangeTop.from_state(mom, mass * g * c[2], q, w)
        lo, hi = top.nutation_bounds
        if not (0.05 < lo and hi < np.pi - 0.05):
            # an axis passing within 0.05 rad of a pole: the closed form (z-x-z angles)
            # is only good to about 1e-9 there (measured), too coarse a reference
            skipped += 1
            continue
        moments.append(mom)
        com.append(c)
        quat.append(q)
        omega.append(w)
        ref.append(top.rotation(DURATION).as_quat())
    moments, com, quat, omega, ref = map(np.array, (moments, com, quat, omega, ref))
    t_ref = time.perf_counter() - t0
    torque = GravityTorque(mass, com, g=g)
    runs = _integrators(moments, quat, omega, torque, mass * g * com)
    integrate_table(f"{n} heavy (Lagrange) tops, {DURATION:g} s", ref, runs)
    print(
        f"  (reference: the exact LagrangeTop, one object per top, {t_ref:.1f} s in all; "
        f"{skipped} random tops whose axis passes within 0.05 rad of a pole redrawn)"
    )


# ------------------------------------------------------- n-link pendulum RHS
def _pendulum_system(n: int):
    from bench_symbolic import pendulum
    from sympy.physics import mechanics as me

    from poinsot.symbolic import LagrangeSystem

    q, u, _mlg, N, *_rest, parts = pendulum(n)
    T = me.kinetic_energy(N, *parts)
    P = sum(p.potential_energy for p in parts)
    return LagrangeSystem(q, T, P)


def _pinocchio_pendulum(n: int):
    import pinocchio as pin

    model = pin.Model()
    model.gravity.linear = np.array([0.0, -9.81, 0.0])
    parent = 0
    for i in range(n):
        place = pin.SE3(np.eye(3), np.array([0.0, 0.0 if i == 0 else -1.0, 0.0]))
        j = model.addJoint(parent, pin.JointModelRZ(), place, f"j{i}")
        inertia = pin.Inertia(1.0, np.array([0.0, -1.0, 0.0]), np.zeros((3, 3)))
        model.appendBodyToJoint(j, inertia, pin.SE3.Identity())
        parent = j
    data = model.createData()
    return pin, model, data


def _mujoco_pendulum(n: int):
    import mujoco

    body = ""
    for i in range(n):
        pos = "0 0 0" if i == 0 else "0 -1 0"
        body += (
            f'<body pos="{pos}"><joint type="hinge" axis="0 0 1"/>'
            '<inertial pos="0 -1 0" mass="1" diaginertia="1e-12 1e-12 1e-12"/>'
        )
    body += "</body>" * n
    xml = (
        '<mujoco><option gravity="0 -9.81 0" integrator="Euler">'
        '<flag contact="disable" constraint="disable"/></option>'
        f"<worldbody>{body}</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    return mujoco, model, mujoco.MjData(model)


def pendulum_rhs(ns: tuple[int, ...]) -> None:
    rows = []
    for n in ns:
        f = _pendulum_system(n).to_numeric({"m": 1.0, "l": 1.0, "g": 9.81}).compile()
        rng = np.random.default_rng(n)
        y = rng.normal(size=2 * n)
        acc = f(0.0, y)[n:]
        # poinsot's pendulum uses absolute link angles; Pinocchio and MuJoCo joint angles
        # are relative to the previous link (the same system in other coordinates)
        qv, vv = np.diff(y[:n], prepend=0.0), np.diff(y[n:], prepend=0.0)
        number = 20_000
        fns: dict[str, Callable[[], object]] = {"ours": lambda f=f, y=y: f(0.0, y)}
        try:
            pin, model, data = _pinocchio_pendulum(n)
            tau = np.zeros(n)
            a_pin = pin.aba(model, data, qv, vv, tau)
            assert np.allclose(np.cumsum(a_pin), acc, rtol=1e-9, atol=1e-9), (a_pin, acc)
            fns["pin"] = lambda: pin.aba(model, data, qv, vv, tau)
        except ImportError as e:
            missing("pinocchio", e)
        try:
            mj, model_mj, data_mj = _mujoco_pendulum(n)

            def mj_acc():
                data_mj.qpos[:] = qv
                data_mj.qvel[:] = vv
                mj.mj_forward(model_mj, data_mj)
                return data_mj.qacc

            a_mj = mj_acc().copy()
            assert np.allclose(np.cumsum(a_mj), acc, rtol=1e-6, atol=1e-6), (a_mj, acc)
            fns["mj"] = mj_acc
        except ImportError as e:
            missing("mujoco", e)
        t = interleaved(fns, number)
        t_ours = t["ours"]
        row = [str(n), f"{1e6 * t_ours:.2f}"]
        for key in ("pin", "mj"):
            if key in t:
                row += [f"{1e6 * t[key]:.2f}", f"{t[key] / t_ours:.2f}x"]
            else:
                row += ["-", "-"]
        rows.append(row)
    head = ["n-link pendulum, one state (us/call)", "poinsot f(t, y)", "Pinocchio aba"]
    head += ["aba / poinsot", "MuJoCo mj_forward", "mj_forward / poinsot"]
    print(table(rows, head))
    print(
        "  (each checked against poinsot's accelerations; MuJoCo's point masses carry an "
        "inertia of 1e-12, its mj_forward computes more than the accelerations; their joint "
        "angles are relative, poinsot's absolute: the same system in other coordinates)"
    )


def derivation(n: int) -> None:
    try:
        from bench_symbolic import kane_setup
    except ImportError as e:
        missing("sympy", e)
        return

    def ours():
        s = _pendulum_system(n)
        s._MF  # noqa: B018  (the mass matrix and forcing, what KanesMethod builds)
        return s

    def kane():
        k, parts, loads = kane_setup(n)
        k.kanes_equations(parts, loads)
        return k

    t = interleaved({"ours": ours, "kane": kane}, repeat=max(1, REPEAT // 2))
    t_ours, t_kane = t["ours"], t["kane"]
    rows = [[str(n), f"{t_ours:.2f}", f"{t_kane:.2f}", f"{t_kane / t_ours:.2f}x"]]
    head = ["n-link pendulum derivation (s)", "poinsot LagrangeSystem", "SymPy KanesMethod"]
    head.append("Kane / poinsot")
    print(table(rows, head))


# ---------------------------------------------------------------------- main
def main() -> None:
    global REPEAT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--only", default="rot,free,heavy,pend,derive")
    ap.add_argument("--n-rot", type=int, default=1_000_000)
    ap.add_argument("--n-bodies", type=int, default=10_000)
    a = ap.parse_args()
    REPEAT = a.repeat
    only = set(a.only.split(","))
    import numba
    import scipy

    print(
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, NumPy {np.__version__}, SciPy {scipy.__version__}, "
        f"numba {numba.__version__}; min of {REPEAT} runs"
    )
    print(f"start: {load()}")
    sections = [
        ("rot", "rotations", lambda: rotations(a.n_rot)),
        ("free", "free bodies", lambda: free_bodies(a.n_bodies)),
        ("heavy", "heavy tops", lambda: heavy_tops(a.n_bodies)),
        ("pend", "pendulum RHS", lambda: pendulum_rhs((2, 5, 10))),
        ("derive", "derivation", lambda: derivation(10)),
    ]
    for key, title, fn in sections:
        if key in only:
            print(f"\n## {title} ({load()})")
            fn()
    print(f"\nend: {load()}")


if __name__ == "__main__":
    main()
