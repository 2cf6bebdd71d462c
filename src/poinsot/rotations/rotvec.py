"""Rotation vectors ``phi = f e`` (theory §2, ``A = exp(phi^)``) <-> unit quaternions.

**Convention:** ``f`` in radians, right-handed about ``e``; :func:`rotvec_from_quat`
returns the shortest rotation, ``|phi| = f in [0, pi]``.
"""

from __future__ import annotations

import numpy as np

from ._lazy import big, chunked, flat, kernels, threaded

__all__ = ["angle_from_quat", "quat_from_rotvec", "rotvec_from_quat"]

_D3 = np.zeros(3)
_D4 = np.zeros(4)


def quat_from_rotvec(v: np.ndarray) -> np.ndarray:
    """``L = cos(f/2) + e sin(f/2)`` from ``phi = f e`` (..., 3) -> (..., 4)."""
    if big(v.shape[:-1]):
        q = np.empty(v.shape[:-1] + (4,))
        vf, qf, k = flat(v, 3), q.reshape(-1, 4), kernels()

        def step(lo: int, hi: int) -> None:
            buf = np.empty((2, hi - lo))
            k.rotvec_angle_flat(vf[lo:hi], buf)
            np.tan(buf[1], out=buf[1])
            k.from_rotvec_tan_flat(vf[lo:hi], buf, qf[lo:hi])

        chunked(step, vf.shape[0])
        return q
    return kernels().rotvec_to_quat(v, _D4)


def rotvec_from_quat(q: np.ndarray) -> np.ndarray:
    """``phi = 2 atan2(|l|, l0) l / |l|`` (with ``l0 >= 0``) for unit ``q`` (..., 4) -> (..., 3)."""
    if big(q.shape[:-1]):
        v = np.empty(q.shape[:-1] + (3,))
        threaded(kernels().to_rotvec_flat, flat(q, 4), v.reshape(-1, 3))
        return v
    return kernels().quat_to_rotvec(q, _D3)


def angle_from_quat(q: np.ndarray) -> np.ndarray:
    """``f = |phi| = 2 atan2(|l|, |l0|)`` in ``[0, pi]`` for unit ``q`` (..., 4) -> (...)."""
    if big(q.shape[:-1]):
        qf = flat(q, 4)
        f = np.empty(qf.shape[0])
        k = kernels()

        def step(lo: int, hi: int) -> None:
            buf = np.empty((2, hi - lo))
            k.angle_atan2_args_flat(qf[lo:hi], buf)
            out = f[lo:hi]
            np.arctan2(buf[0], buf[1], out=out)
            out *= 2.0

        chunked(step, qf.shape[0])
        return f.reshape(q.shape[:-1])
    return 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))
