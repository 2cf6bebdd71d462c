"""Rotation core vs SciPy's Rotation (and numpy-quaternion / quaternionic if installed).

1. One rotation at a time: microseconds per call (median of several interleaved
   rounds, same process) of every single-rotation constructor, conversion,
   ``apply``, ``inv``, ``magnitude``, composition, ``slerp`` and every one-state
   kinematic rate, with the ratio to SciPy's equivalent (target >= 3x) and to a
   hand-written NumPy expression of the same formula (the practical floor; target
   ours / hand <= 2). Each hand expression is checked against poinsot's result.
2. For N = 1,000,000 rotations: nanoseconds per rotation on one thread and on
   every numba thread, the ratio to SciPy (target >= 2x), and for the
   memory-bound operations the ratio to the memory-bandwidth floor measured in
   the same run (time of ``q.copy()`` per byte moved, times the bytes the
   operation reads and writes).

Run: ``python benchmarks/bench_rotations.py [N] [--single-only|--batch-only]``
(``make bench`` runs all). On a shared machine run it a few times.
"""

from __future__ import annotations

import os
import sys
import time
import warnings

import numpy as np
from _timing import median_time, table
from scipy.spatial.transform import Rotation as SciPyRotation
from scipy.spatial.transform import Slerp

from poinsot import Rotation, slerp
from poinsot.kinematics import rates as K
from poinsot.rotations import RigidTransform, get_num_threads, set_num_threads

try:  # SciPy >= 1.16
    from scipy.spatial.transform import RigidTransform as SciPyTransform
except ImportError:
    SciPyTransform = None

_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def _cr(a, b):  # hand cross product (np.cross costs ~10x more on 3-vectors)
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def _h_mul(p, q):
    p0, pv, q0, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate(([p0 * q0 - pv @ qv], p0 * qv + q0 * pv + _cr(pv, qv)))


def _h_from_euler_zxz(a):
    c, s = np.cos(0.5 * a), np.sin(0.5 * a)
    return np.array(
        [
            c[0] * c[1] * c[2] - s[0] * c[1] * s[2],
            c[0] * s[1] * c[2] + s[0] * s[1] * s[2],
            s[0] * s[1] * c[2] - c[0] * s[1] * s[2],
            s[0] * c[1] * c[2] + c[0] * c[1] * s[2],
        ]
    )


def _h_pow(q, n):
    v = q[1:]
    half = np.arctan2(np.sqrt(v @ v), q[0])
    return np.concatenate(([np.cos(n * half)], np.sin(n * half) * v / np.sqrt(v @ v)))


def _h_as_matrix(q):
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _h_as_euler_zxz(q):  # Bernardes & Viollet for ZXZ (no wrap needed for this q)
    a, b, c, d = q[0], q[3], q[1], q[2]
    mid = 2 * np.arctan2(np.hypot(c, d), np.hypot(a, b))
    hs, hd = np.arctan2(b, a), np.arctan2(d, c)
    return np.array([hs + hd, mid, hs - hd])


def _h_apply(q, v):
    w, u = q[0], q[1:]
    return (w * w - u @ u) * v + 2 * (u @ v) * u + 2 * w * _cr(u, v)


def _h_from_matrix(m):  # trace branch of the largest-square formula
    w4 = 2.0 * np.sqrt(1.0 + np.trace(m))
    return np.array(
        [0.25 * w4, (m[2, 1] - m[1, 2]) / w4, (m[0, 2] - m[2, 0]) / w4, (m[1, 0] - m[0, 1]) / w4]
    )


def _h_slerp(p, q, t):
    d = p @ q
    om = np.arccos(d)
    so = np.sin(om)
    return np.sin((1 - t) * om) / so * p + np.sin(t * om) / so * q


def _h_rotvec_rate(v, w):
    f = np.sqrt(v @ v)
    c = (1 - 0.5 * f / np.tan(0.5 * f)) / f**2
    pxw = _cr(v, w)
    return w + 0.5 * pxw + c * _cr(v, pxw)


def _h_omega_from_rotvec_rate(v, d):
    f = np.sqrt(v @ v)
    k1, k2 = (1 - np.cos(f)) / f**2, (f - np.sin(f)) / f**3
    pxd = _cr(v, d)
    return d - k1 * pxd + k2 * _cr(v, pxd)


def _h_euler_rates_zxz(a, w):
    st, ct, sf, cf = np.sin(a[1]), np.cos(a[1]), np.sin(a[2]), np.cos(a[2])
    u = w[0] * sf + w[1] * cf
    return np.array([u / st, w[0] * cf - w[1] * sf, w[2] - u * ct / st])


def _h_omega_from_euler_rates_zxz(a, d):
    st, ct, sf, cf = np.sin(a[1]), np.cos(a[1]), np.sin(a[2]), np.cos(a[2])
    return np.array([d[0] * st * sf + d[1] * cf, d[0] * st * cf - d[1] * sf, d[0] * ct + d[2]])


def _h_euler_rate_matrix_zxz(a):
    st, ct, sf, cf = np.sin(a[1]), np.cos(a[1]), np.sin(a[2]), np.cos(a[2])
    return np.array([[st * sf, cf, 0.0], [st * cf, -sf, 0.0], [ct, 0.0, 1.0]])


def _best(fn, number: int, repeat: int) -> float:
    """Fastest of ``repeat`` timings of ``number`` calls (s per call): the least disturbed
    by other processes on a shared machine. A round's figure; the tables report the
    median of several interleaved rounds."""
    fn()
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        out.append((time.perf_counter() - t0) / number)
    return min(out)


def single(rounds: int = 9, number: int = 200) -> None:
    """Table 1: one rotation / one state at a time (us per call)."""
    q = np.array([0.8, 0.2, -0.4, 0.4])  # unit (|q| = 1 exactly in binary? no: normalised)
    q = q / np.sqrt(q @ q)
    q2 = np.array([0.6, -0.3, 0.5, 0.55])
    q2 = q2 / np.sqrt(q2 @ q2)
    q4 = np.array([1.0, 2.0, 3.0, 4.0])
    v = np.array([0.3, -1.2, 2.0])
    rv = np.array([0.4, -0.5, 0.6])
    ang = np.array([0.3, 0.9, -0.4])
    w = np.array([0.7, -0.2, 1.1])
    g = np.array([0.2, -0.1, 0.3])
    r, r2 = Rotation.from_quat(q), Rotation.from_quat(q2)
    s, s2 = (
        SciPyRotation.from_quat(q, scalar_first=True),
        SciPyRotation.from_quat(q2, scalar_first=True),
    )
    m = r.as_matrix()
    qd = K.quat_rate(q, w)
    md = K.dcm_rate(m, w)
    pair = SciPyRotation.concatenate([s, s2])
    gen = np.random.default_rng(5)
    cases = [
        # name, poinsot, SciPy (or None), hand NumPy, comparison of results (None: skip)
        (
            "from_quat",
            lambda: Rotation.from_quat(q4),
            lambda: SciPyRotation.from_quat(q4, scalar_first=True),
            lambda: q4 / np.sqrt(q4 @ q4),
            lambda a: a.as_quat(),
        ),
        (
            "from_euler ZXZ",
            lambda: Rotation.from_euler("ZXZ", ang),
            lambda: SciPyRotation.from_euler("ZXZ", ang),
            lambda: _h_from_euler_zxz(ang),
            lambda a: a.as_quat(),
        ),
        (
            "from_rotvec",
            lambda: Rotation.from_rotvec(rv),
            lambda: SciPyRotation.from_rotvec(rv),
            lambda: np.concatenate(
                (
                    [np.cos(0.5 * np.sqrt(rv @ rv))],
                    np.sin(0.5 * np.sqrt(rv @ rv)) / np.sqrt(rv @ rv) * rv,
                )
            ),
            lambda a: a.as_quat(),
        ),
        (
            "from_matrix",
            lambda: Rotation.from_matrix(m),
            lambda: SciPyRotation.from_matrix(m),
            lambda: _h_from_matrix(m),
            lambda a: a.as_quat(),
        ),
        (
            "from_mrp",
            lambda: Rotation.from_mrp(g),
            lambda: SciPyRotation.from_mrp(g),
            lambda: np.concatenate(([1 - g @ g], 2 * g)) / (1 + g @ g),
            lambda a: a.as_quat(),
        ),
        (
            "from_gibbs",
            lambda: Rotation.from_gibbs(g),
            None,
            lambda: np.concatenate(([1.0], g)) / np.sqrt(1 + g @ g),
            lambda a: a.as_quat(),
        ),
        (
            "from_axis_angle",
            lambda: Rotation.from_axis_angle(v, 0.7),
            None,
            lambda: np.concatenate(([np.cos(0.35)], np.sin(0.35) * v / np.sqrt(v @ v))),
            lambda a: a.as_quat(),
        ),
        (
            "identity",
            lambda: Rotation.identity(),
            lambda: SciPyRotation.identity(),
            lambda: np.array([1.0, 0.0, 0.0, 0.0]),
            lambda a: a.as_quat(),
        ),
        (
            "random(rng=Generator)",
            lambda: Rotation.random(rng=gen),
            lambda: SciPyRotation.random(rng=gen),
            lambda: (lambda x: x / np.sqrt(x @ x))(gen.standard_normal(4)),
            None,
        ),
        (
            "random(rng=seed)",
            lambda: Rotation.random(rng=7),
            lambda: SciPyRotation.random(rng=7),
            lambda: (lambda x: x / np.sqrt(x @ x))(np.random.default_rng(7).standard_normal(4)),
            lambda a: a.as_quat(),
        ),
        (
            "as_quat",
            lambda: r.as_quat(),
            lambda: s.as_quat(scalar_first=True),
            lambda: q.copy(),
            None,
        ),
        ("as_matrix", lambda: r.as_matrix(), lambda: s.as_matrix(), lambda: _h_as_matrix(q), None),
        (
            "as_rotvec",
            lambda: r.as_rotvec(),
            lambda: s.as_rotvec(),
            lambda: 2 * np.arctan2(np.sqrt(q[1:] @ q[1:]), q[0]) / np.sqrt(q[1:] @ q[1:]) * q[1:],
            None,
        ),
        (
            "as_euler ZXZ",
            lambda: r.as_euler("ZXZ"),
            lambda: s.as_euler("ZXZ"),
            lambda: _h_as_euler_zxz(q),
            None,
        ),
        ("as_mrp", lambda: r.as_mrp(), lambda: s.as_mrp(), lambda: q[1:] / (1 + q[0]), None),
        (
            "as_gibbs",
            lambda: r.as_gibbs(),
            None,
            lambda: q[1:] / q[0],
            None,
        ),
        (
            "as_axis_angle",
            lambda: r.as_axis_angle(),
            None,
            lambda: (q[1:] / np.sqrt(q[1:] @ q[1:]), 2 * np.arctan2(np.sqrt(q[1:] @ q[1:]), q[0])),
            lambda a: np.concatenate((a[0], [a[1]])),
        ),
        ("apply", lambda: r.apply(v), lambda: s.apply(v), lambda: _h_apply(q, v), None),
        ("inv", lambda: r.inv(), lambda: s.inv(), lambda: q * _CONJ, lambda a: a.as_quat()),
        (
            "magnitude",
            lambda: r.magnitude(),
            lambda: s.magnitude(),
            lambda: 2 * np.arctan2(np.sqrt(q[1:] @ q[1:]), abs(q[0])),
            None,
        ),
        (
            "r ** 0.3",
            lambda: r**0.3,
            lambda: s**0.3,
            lambda: _h_pow(q, 0.3),
            lambda a: a.as_quat(),
        ),
        (
            "approx_equal",
            lambda: r.approx_equal(r2),
            lambda: s.approx_equal(s2),
            lambda: 2 * np.arccos(min(1.0, abs(q @ q2))) <= 1e-8,
            None,
        ),
        (
            "mean (one rotation)",
            lambda: r.mean(),
            lambda: s.mean(),
            lambda: q.copy(),
            lambda a: a.as_quat(),
        ),
        (
            "compose r2 * r",
            lambda: r2 * r,
            lambda: s2 * s,
            lambda: _h_mul(q2, q),
            lambda a: a.as_quat(),
        ),
        (
            "slerp(r, r2, 0.3)",
            lambda: slerp(r, r2, 0.3),
            lambda: Slerp([0.0, 1.0], pair)(0.3),
            lambda: _h_slerp(q, q2, 0.3),
            lambda a: a.as_quat(),
        ),
        (
            "quat_rate",
            lambda: K.quat_rate(q, w),
            None,
            lambda: 0.5 * _h_mul(q, np.concatenate(([0.0], w))),
            None,
        ),
        (
            "omega_from_quat_rate",
            lambda: K.omega_from_quat_rate(q, qd),
            None,
            lambda: 2 * _h_mul(q * _CONJ, qd)[1:],
            None,
        ),
        (
            "dcm_rate",
            lambda: K.dcm_rate(m, w),
            None,
            lambda: m @ np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]),
            None,
        ),
        (
            "omega_from_dcm_rate",
            lambda: K.omega_from_dcm_rate(m, md),
            None,
            lambda: (
                lambda a: 0.5 * np.array([a[2, 1] - a[1, 2], a[0, 2] - a[2, 0], a[1, 0] - a[0, 1]])
            )(m.T @ md),
            None,
        ),
        (
            "euler_rates ZXZ",
            lambda: K.euler_rates("ZXZ", ang, w),
            None,
            lambda: _h_euler_rates_zxz(ang, w),
            None,
        ),
        (
            "omega_from_euler_rates ZXZ",
            lambda: K.omega_from_euler_rates("ZXZ", ang, w),
            None,
            lambda: _h_omega_from_euler_rates_zxz(ang, w),
            None,
        ),
        (
            "euler_rate_matrix ZXZ",
            lambda: K.euler_rate_matrix("ZXZ", ang),
            None,
            lambda: _h_euler_rate_matrix_zxz(ang),
            None,
        ),
        (
            "gibbs_rate",
            lambda: K.gibbs_rate(g, w),
            None,
            lambda: 0.5 * (w + _cr(g, w) + (g @ w) * g),
            None,
        ),
        (
            "omega_from_gibbs_rate",
            lambda: K.omega_from_gibbs_rate(g, w),
            None,
            lambda: 2 * (w - _cr(g, w)) / (1 + g @ g),
            None,
        ),
        (
            "mrp_rate",
            lambda: K.mrp_rate(g, w),
            None,
            lambda: 0.25 * ((1 - g @ g) * w + 2 * _cr(g, w) + 2 * (g @ w) * g),
            None,
        ),
        (
            "omega_from_mrp_rate",
            lambda: K.omega_from_mrp_rate(g, w),
            None,
            lambda: 4 * ((1 - g @ g) * w - 2 * _cr(g, w) + 2 * (g @ w) * g) / (1 + g @ g) ** 2,
            None,
        ),
        ("rotvec_rate", lambda: K.rotvec_rate(rv, w), None, lambda: _h_rotvec_rate(rv, w), None),
        (
            "omega_from_rotvec_rate",
            lambda: K.omega_from_rotvec_rate(rv, w),
            None,
            lambda: _h_omega_from_rotvec_rate(rv, w),
            None,
        ),
    ]
    for name, ours, _, hand, get in cases:  # the hand expressions compute the same thing
        if name.startswith("random(rng=G"):
            continue  # draws from a running generator
        a, b = ours(), hand()
        a = get(a) if get else a
        if isinstance(b, tuple):  # (axis, angle)
            b = np.concatenate((b[0], [b[1]]))
        if name == "slerp(r, r2, 0.3)" and np.dot(a, b) < 0:
            b = -b
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-14, err_msg=name)
    fns = [f for c in cases for f in (c[1], c[2], c[3]) if f is not None]
    times: dict[int, list[float]] = {id(f): [] for f in fns}
    for _ in range(rounds):  # interleaved rounds: load changes hit every entry alike
        for f in fns:
            times[id(f)].append(_best(f, number, 5))
    med = {k: float(np.median(t)) * 1e6 for k, t in times.items()}
    rows = []
    for name, ours, theirs, hand, _ in cases:
        t_o, t_h = med[id(ours)], med[id(hand)]
        t_s = med[id(theirs)] if theirs is not None else None
        rows.append(
            [
                name,
                f"{t_o:.2f}",
                "-" if t_s is None else f"{t_s:.2f}",
                "-" if t_s is None else f"{t_s / t_o:.1f}x",
                f"{t_h:.2f}",
                f"{t_o / t_h:.2f}",
            ]
        )
    print(
        f"One rotation / one state at a time: us per call, median of {rounds} interleaved "
        f"rounds (each the best of 5 x {number} calls); load average {os.getloadavg()[0]:.1f}"
    )
    print(
        table(
            rows, ["operation", "poinsot", "SciPy", "SciPy/poinsot", "hand NumPy", "poinsot/hand"]
        )
    )
    print("(SciPy slerp includes building the Slerp object: SciPy has no one-shot slerp.)")


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
    m, rv, mrp = r.as_matrix(), r.as_rotvec(), r.as_mrp()
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
        (
            "apply inverse",
            lambda: r.apply(v, inverse=True),
            lambda: s.apply(v, inverse=True),
            f8 * (4 + 3 + 3),
        ),
        ("inverse", lambda: r.inv(), lambda: s.inv(), f8 * 8),
        ("magnitude", lambda: r.magnitude(), lambda: s.magnitude(), None),
        ("quat->mrp", lambda: r.as_mrp(), lambda: s.as_mrp(), f8 * (4 + 3)),
        ("mrp->quat", lambda: Rotation.from_mrp(mrp), lambda: SciPyRotation.from_mrp(mrp), None),
        ("mean", lambda: r.mean(), lambda: s.mean(), f8 * 4),
    ]
    if SciPyTransform is not None:
        tf, tf_s = RigidTransform.from_components(v, r), SciPyTransform.from_components(v, s)
        ops.append(("transform->matrix", tf.as_matrix, tf_s.as_matrix, f8 * (4 + 3 + 16)))
    rows, ratios = [], []
    threads = get_num_threads()
    try:  # SciPy's BLAS on one thread (its mean multiplies matrices; see bench_peers.py)
        from threadpoolctl import threadpool_limits

        pinned = threadpool_limits(1)
        blas = "SciPy's BLAS pinned to 1 thread"
    except ImportError:
        pinned, blas = None, "SciPy's BLAS not pinned (no threadpoolctl)"
    for name, ours, theirs, nbytes in ops:
        one, many, auto, sci = [], [], [], []
        for _ in range(5):  # interleaved: one thread, every thread, default, SciPy
            set_num_threads(1)
            one.append(_best(ours, 1, 3))
            set_num_threads(threads)
            many.append(_best(ours, 1, 3))
            set_num_threads(None)  # the default: numba's threads capped by the idle cores
            auto.append(_best(ours, 1, 3))
            sci.append(_best(theirs, 1, 3))
        t1, t_all, t_ours, t_scipy = (float(np.median(x)) for x in (one, many, auto, sci))
        ratio = t_scipy / t_ours
        ratios.append(ratio)
        floor = f"{t_ours / (per_byte * nbytes):.2f}x" if nbytes else "-"
        rows.append(
            [
                name,
                f"{1e9 * t1 / n:.1f}",
                f"{1e9 * t_all / n:.1f}",
                f"{1e9 * t_ours / n:.1f}",
                f"{1e9 * t_scipy / n:.1f}",
                f"{ratio:.2f}x",
                f"{t_scipy / t1:.2f}x",
                f"{t_scipy / t_all:.2f}x",
                floor,
            ]
        )
    if pinned is not None:
        pinned.unregister()
    print(
        f"N = {n:,} rotations (ns per rotation), {threads} numba threads, load average "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; medians of 5 interleaved rounds "
        f"(each the best of 3); {blas}; "
        f"memory floor from q.copy(): {2 * q.nbytes / floor_s / 1e9:.1f} GB/s"
    )
    head = ["operation", "1 thread", f"{threads} threads", "default", "SciPy"]
    head += ["SciPy/default", "SciPy/1 thread", f"SciPy/{threads} threads", "vs floor"]
    print(table(rows, head))
    print(f"geometric-mean speed-up over SciPy: {np.exp(np.mean(np.log(ratios))):.2f}x")
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
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if "--batch-only" not in sys.argv:
        single()
        print()
    if "--single-only" not in sys.argv:
        main(int(args[0]) if args else 1_000_000)
