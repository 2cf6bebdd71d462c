"""Attitude determination (Wahba's problem): poinsot against ahrs and SciPy.

poinsot's ``determine_attitude`` (quest, esoq2: compiled, and the NumPy executor of
``POINSOT_NUMBA=0``; svd, q-method, triad: NumPy) against ahrs 0.4's ``QUEST``,
``Davenport`` (the q-method) and ``TRIAD`` (ahrs has no ESOQ2) and SciPy's
``Rotation.align_vectors`` (SVD). ahrs and SciPy solve one set per call: they are timed
on a sample of the same sets, each in its fastest form (ahrs: one ``estimate`` per
set, the loop its batch constructors also run; SciPy: one ``align_vectors`` per set),
and the tables give the time per solve.

Data: random attitudes (uniform), references ``g = (0, 0, 1)`` and
``m = (cos 60 deg, 0, sin 60 deg)`` (ahrs's fixed references for ``magnetic_dip=60``)
plus, for three observations, a third random direction per set; observations
``b_i = C^T r_i`` with 1e-3 rad of Gaussian noise; equal weights (ahrs QUEST's 0.5,
0.5). Accuracy: the largest and the median angle between each solution and poinsot's
SVD on the same set (ahrs's QUEST has no sequential rotations: its largest errors are
at attitudes near 180 deg).

Rules: medians of ``--repeat`` runs after a warm-up (``_timing.median_time``); BLAS
pinned to one thread (threadpoolctl) for everything but the compiled rows; the
compiled rows on 1 and on 2 numba threads (``set_num_threads``); the machine load
(``os.getloadavg``, ``uptime``) printed at the start and the end.

Run: ``python benchmarks/bench_determination.py [--n 1000000] [--sample 10000] [--repeat 7]``
(``pip install poinsot[bench]`` brings ahrs and threadpoolctl).
"""

# ruff: noqa: B023  (the closures timed in each loop iteration run within it)
from __future__ import annotations

import argparse
import contextlib
import os
import platform
import subprocess
import sys
from collections.abc import Callable, Iterator

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_time, table  # noqa: E402

from poinsot import _jit  # noqa: E402
from poinsot.rotations import determine_attitude, set_num_threads  # noqa: E402

DIP = 60.0


@contextlib.contextmanager
def blas_one_thread() -> Iterator[str]:
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        yield "threadpoolctl not installed: BLAS threads NOT pinned"
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield "BLAS pinned to 1 thread"


@contextlib.contextmanager
def numpy_executor() -> Iterator[None]:
    """poinsot's NumPy executor (the path of ``POINSOT_NUMBA=0``) in this process."""
    old = _jit.NUMBA
    _jit.NUMBA = False
    try:
        yield
    finally:
        _jit.NUMBA = old


def load() -> str:
    a, b, c = os.getloadavg()
    up = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    return f"load average {a:.2f} / {b:.2f} / {c:.2f} on {os.cpu_count()} cores ({up})"


def problem(n_sets: int, n_obs: int, seed: int = 0):
    from scipy.spatial.transform import Rotation as SciRotation

    rng = np.random.default_rng(seed)
    c = SciRotation.random(n_sets, random_state=seed).as_matrix()  # C_nb
    m = np.array([np.cos(np.radians(DIP)), 0.0, np.sin(np.radians(DIP))])
    r = np.empty((n_sets, n_obs, 3))
    r[:, 0] = [0.0, 0.0, 1.0]
    r[:, 1] = m
    if n_obs > 2:
        extra = rng.normal(size=(n_sets, n_obs - 2, 3))
        r[:, 2:] = extra / np.linalg.norm(extra, axis=-1, keepdims=True)
    b = np.einsum("mji,mkj->mki", c, r)  # b_i = C^T r_i
    b += 1e-3 * rng.normal(size=b.shape)
    b /= np.linalg.norm(b, axis=-1, keepdims=True)
    return b, r


def angle(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """The rotation angle between unit quaternions (accurate for small angles: from the
    chord ``|q1 - s q2|``, ``s`` the sign that makes it the shorter)."""
    q1 = q1 / np.linalg.norm(q1, axis=-1, keepdims=True)
    q2 = q2 / np.linalg.norm(q2, axis=-1, keepdims=True)
    d = np.minimum(np.linalg.norm(q1 - q2, axis=-1), np.linalg.norm(q1 + q2, axis=-1))
    return 4.0 * np.arcsin(np.minimum(d / 2.0, 1.0))


def peers(b: np.ndarray, r: np.ndarray) -> dict[str, tuple[Callable[[], np.ndarray], str]]:
    """Per-call peers on the sets ``b, r``: name -> (solve all, poinsot method they match)."""
    out: dict[str, tuple[Callable[[], np.ndarray], str]] = {}
    n_obs = b.shape[1]
    from scipy.spatial.transform import Rotation as SciRotation

    def scipy_align() -> np.ndarray:
        q = np.empty((len(b), 4))
        for k in range(len(b)):  # align_vectors(a, b): a ~ R b, here r ~ C_nb b
            rot, _ = SciRotation.align_vectors(r[k], b[k])
            q[k] = rot.as_quat(scalar_first=True)
        return q

    out["SciPy align_vectors"] = (scipy_align, "svd")
    if n_obs != 2:
        return out
    try:
        import ahrs
        from ahrs.filters import QUEST, TRIAD, Davenport
    except ImportError as exc:
        print(f"ahrs not installed ({exc}): its rows are skipped")
        return out
    assert ahrs.__version__.startswith("0.4"), ahrs.__version__
    acc, mag = b[:, 0].copy(), b[:, 1].copy()
    quest = QUEST(magnetic_dip=DIP)
    dav = Davenport(magnetic_dip=DIP, gravity=1.0)
    triad = TRIAD(v1=r[0, 0].copy(), v2=r[0, 1].copy())

    def ahrs_quest() -> np.ndarray:
        est = quest.estimate
        return np.array([est(acc[k], mag[k]) for k in range(len(acc))])

    def ahrs_davenport() -> np.ndarray:
        est = dav.estimate
        return np.array([est(acc[k], mag[k]) for k in range(len(acc))])

    def ahrs_triad() -> np.ndarray:
        est = triad.estimate
        q = np.array([est(acc[k], mag[k], representation="quaternion") for k in range(len(acc))])
        return q * [1.0, -1.0, -1.0, -1.0]  # ahrs's A maps reference -> body: C_nb^T

    out["ahrs QUEST"] = (ahrs_quest, "quest")
    out["ahrs Davenport"] = (ahrs_davenport, "q-method")
    out["ahrs TRIAD"] = (ahrs_triad, "triad")
    return out


def run(
    n_sets: int, n_obs: int, sample: int, repeat: int
) -> tuple[str, list[list[str]], list[str]]:
    b, r = problem(n_sets, n_obs)
    svd = determine_attitude(b[:sample], r[:sample], method="svd").quat
    svd_all = None
    rows: list[list[str]] = []
    times: dict[str, float] = {}

    def row(name: str, fn: Callable[[], np.ndarray], m: int, ref: np.ndarray) -> None:
        t = median_time(fn, repeat=repeat) / m
        err = angle(fn(), ref)
        times[name] = t
        rows.append(
            [name, f"{m:.0e}", f"{t * 1e9:,.0f}", f"{1.0 / t:.2e}",
             f"{err.max():.1e}", f"{np.median(err):.1e}"]
        )  # fmt: skip

    # compiled: the whole batch, on 1 and 2 numba threads
    for method in ("quest", "esoq2"):
        for threads in (2, 1):
            for cov in (True, False):
                set_num_threads(threads)
                try:
                    if svd_all is None:
                        with blas_one_thread():
                            svd_all = determine_attitude(b, r, method="svd").quat
                    name = f"poinsot {method} compiled, {threads} thr" + ("" if cov else ", no cov")
                    row(
                        name,
                        lambda: determine_attitude(b, r, method=method, covariance=cov).quat,
                        n_sets,
                        svd_all,
                    )
                finally:
                    set_num_threads(None)
    # NumPy: poinsot's NumPy executor and NumPy methods on 1e5 sets, BLAS on one thread
    m = min(n_sets, 100_000)
    bs, rs = b[:m], r[:m]
    with blas_one_thread() as pin:
        for method in ("quest", "esoq2"):

            def np_fn() -> np.ndarray:
                with numpy_executor():
                    return determine_attitude(bs, rs, method=method).quat

            row(f"poinsot {method} NumPy executor", np_fn, m, svd_all[:m])
        methods = ["svd", "q-method"] + (["triad"] if n_obs == 2 else [])
        for method in methods:
            row(
                f"poinsot {method} (NumPy)",
                lambda: determine_attitude(bs, rs, method=method).quat,
                m,
                svd_all[:m],
            )
        bp, rp = b[:sample], r[:sample]
        for name, (fn, _) in peers(bp, rp).items():
            row(name, fn, sample, svd)
    # ratios: peer time / poinsot time for the method it matches (2 threads, covariance)
    match = {"ahrs QUEST": ["quest", "esoq2"], "ahrs Davenport": ["q-method"],
             "ahrs TRIAD": ["triad"], "SciPy align_vectors": ["svd", "quest"]}  # fmt: skip
    ratios = []
    for peer, ours in match.items():
        if peer not in times:
            continue
        for o in ours:
            key = (f"poinsot {o} compiled, 2 thr" if o in ("quest", "esoq2")
                   else f"poinsot {o} (NumPy)")  # fmt: skip
            if key in times:
                ratios.append(f"{key} is {times[peer] / times[key]:,.0f}x faster than {peer}")
    return pin, rows, ratios


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1_000_000, help="sets for the batched rows")
    p.add_argument("--sample", type=int, default=10_000, help="sets for the per-call peers")
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--obs", default="2,3", help="observations per set (comma-separated)")
    a = p.parse_args()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    print("start:", load())
    for n_obs in (int(x) for x in a.obs.split(",")):
        pin, rows, ratios = run(a.n, n_obs, a.sample, a.repeat)
        print(f"\n{n_obs} observations per set ({pin} for the NumPy rows and peers)\n")
        header = ["solver", "sets", "ns/solve", "solves/s", "max err vs SVD (rad)", "median err"]
        print(table(rows, header))
        for line in ratios:
            print(" ", line)
    print("\nend:", load())


if __name__ == "__main__":
    main()
