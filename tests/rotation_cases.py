"""Shared fixtures: edge-case rotation sets (identity, tiny angles, angles near pi,
all normalised {0, +-1}^4 quaternions) plus seeded random samples."""

from __future__ import annotations

import itertools

import numpy as np


def _axis_angle_quats(angles, rng) -> np.ndarray:
    axes = rng.standard_normal((len(angles), 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    half = 0.5 * np.asarray(angles)[:, None]
    return np.hstack([np.cos(half), np.sin(half) * axes])


def edge_quaternions() -> np.ndarray:
    """Unit quaternions at the edges of every representation, scalar first."""
    rng = np.random.default_rng(12345)
    units = [
        np.array(c, dtype=float) / np.linalg.norm(c)
        for c in itertools.product((-1.0, 0.0, 1.0), repeat=4)
        if any(c)
    ]
    angles = [0.0, 1e-12, 1e-8, 1e-4, np.pi - 1e-8, np.pi, np.pi / 2]
    special = _axis_angle_quats(np.repeat(angles, 4), rng)
    # rotations about the coordinate axes by tiny and near-pi angles
    ax = []
    for k in range(3):
        for f in (1e-12, 1e-8, np.pi - 1e-8, np.pi):
            q = np.zeros(4)
            q[0], q[1 + k] = np.cos(f / 2), np.sin(f / 2)
            ax.append(q)
    return np.vstack([np.array(units), special, np.array(ax)])


def random_quaternions(n: int = 300, seed: int = 7) -> np.ndarray:
    q = np.random.default_rng(seed).standard_normal((n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def all_quaternions() -> np.ndarray:
    return np.vstack([edge_quaternions(), random_quaternions()])


def quat_distance(p, q) -> np.ndarray:
    """Distance between unit quaternions that treats q and -q as the same rotation."""
    p, q = np.asarray(p), np.asarray(q)
    return np.minimum(np.linalg.norm(p - q, axis=-1), np.linalg.norm(p + q, axis=-1))


def assert_same_rotation(p, q, atol=1e-14) -> None:
    d = quat_distance(p, q)
    assert np.all(d <= atol), f"max quaternion distance {np.max(d):.3e} > {atol:.1e}"


# What the installed SciPy can do as an oracle: `make test-min` runs the suite with the
# oldest SciPy pyproject.toml allows, which lacks some of what the newest one offers.
def _scipy_can(check) -> bool:
    from scipy.spatial.transform import Rotation as SciPyRotation

    try:
        return bool(check(SciPyRotation))
    except (TypeError, ValueError, IndexError):
        return False


#: N-D stacks of rotations (older SciPy: only (N,) and single rotations).
SCIPY_ND = _scipy_can(lambda R: R.from_quat(np.tile([0.0, 0, 0, 1], (2, 3, 1))).shape == (2, 3))
#: Empty rotation sets that convert (older SciPy refuses as_matrix on them).
SCIPY_EMPTY = _scipy_can(lambda R: R.from_quat(np.empty((0, 4))).as_matrix().shape == (0, 3, 3))
#: Accurate negative fractional powers (older SciPy: r ** -1.3 off by ~1e-7).
SCIPY_POWER = _scipy_can(
    lambda R: abs((R.from_rotvec([0.0, 0.0, 1.0]) ** -1.3).as_rotvec()[2] + 1.3) < 1e-13
)


def on_one_and_every_thread(fn):
    """``[fn() on one thread, fn() on every thread]`` (``poinsot.rotations``'
    ``set_num_threads``), the thread setting restored afterwards."""
    import numba

    from poinsot.rotations import get_num_threads, set_num_threads

    n0 = get_num_threads()
    try:
        out = []
        for threads in (1, numba.config.NUMBA_NUM_THREADS):
            set_num_threads(threads)
            out.append(fn())
        return out
    finally:
        set_num_threads(n0)
