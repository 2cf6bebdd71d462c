"""Euler and Tait-Bryan (Krylov) angles, all 12 sequences in one code path (theory §3).

**Convention (as SciPy reads sequences):** upper-case letters (``"ZXZ"``) are
*intrinsic* rotations about the moving (body) axes, lower-case (``"zxz"``)
*extrinsic* rotations about the fixed axes. Intrinsic ``abc`` with angles
``(f1, f2, f3)`` is extrinsic ``cba`` with ``(f3, f2, f1)``, and the rotation is
``C = A_a(f1) A_b(f2) A_c(f3)`` (theory §3: ``C = A_psi A_theta A_phi``). Presets:

=========== ======== ==================================================
preset      sequence angles
=========== ======== ==================================================
``euler``   ``ZXZ``  precession psi, nutation theta, spin phi (theory §3)
``krylov``  ``ZXY``  heading (yaw), pitch, roll (theory §3)
``ship``    ``ZXY``  the course's ship angles: psi about axis 3 turns by
                     **minus** psi (heading measured the other way),
                     then theta about 1', then phi about 2''
``bryant``  ``XYZ``  Bryant (Cardan) angles: roll, pitch, yaw about the
                     moving axes 1, 2', 3''
``cardan``  ``XYZ``  the same as ``bryant``
=========== ======== ==================================================

``"ship"`` and ``"krylov"`` differ only in the sign of the first angle:
``from_euler("ship", [psi, theta, phi]) == from_euler("krylov", [-psi, theta, phi])``
(:data:`PRESET_SIGNS`).

**Gimbal lock.** The middle angle is singular at 0 or pi (proper Euler) or at
+-pi/2 (Tait-Bryan). Within :data:`GIMBAL_LOCK_ATOL` of it the first and third
angles are not separately determined: the third is set to 0, the first keeps
their sum/difference, the middle one is set to its singular value, and a
:class:`~poinsot.GimbalLockWarning` is issued. The rotation is then reproduced
to within the distance of the true middle angle from the singular one (the round
trip loses at most ``GIMBAL_LOCK_ATOL`` rad; SciPy, which keeps the computed
middle angle there, can lose up to twice that). Elsewhere the conversion
(Bernardes and Viollet, 2022, the algorithm SciPy uses) is accurate to a few ulp
and equals SciPy's.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array
from ..errors import GimbalLockWarning, InvalidInputError, InvalidTypeError
from ._lazy import big, chunked, flat, kernels, threaded

__all__ = [
    "PRESETS",
    "PRESET_SIGNS",
    "preset_signs",
    "GIMBAL_LOCK_ATOL",
    "parse_sequence",
    "quat_from_euler",
    "euler_from_quat",
]

PRESETS = {"euler": "ZXZ", "krylov": "ZXY", "ship": "ZXY", "bryant": "XYZ", "cardan": "XYZ"}
#: Presets whose angles enter with a sign: the rotation is that of the preset's
#: sequence with the angles multiplied by these signs (and ``as_euler`` gives them back).
PRESET_SIGNS = {"ship": (-1.0, 1.0, 1.0)}
#: Distance (rad) of the middle angle from its singular value inside which
#: :func:`euler_from_quat` reports gimbal lock.
GIMBAL_LOCK_ATOL = 1e-7

_D4 = np.zeros(4)
#: Rotations per chunk of a large batch for ``to_euler_flat`` (spread over the threads by
#: ``chunked``; each rotation's angles do not depend on the chunks).
_CHUNK = 1 << 16
_SEQ = re.compile(r"^([xyz]{1,3}|[XYZ]{1,3})$")


def preset_signs(seq: object) -> tuple[float, float, float] | None:
    """The signs of a preset's angles (``None``: all +1).

    Examples
    --------
    >>> preset_signs("ship"), preset_signs("ZXY")
    ((-1.0, 1.0, 1.0), None)
    """
    return PRESET_SIGNS.get(seq.lower()) if isinstance(seq, str) else None


def parse_sequence(seq: str) -> tuple[tuple[int, ...], bool]:
    """Axes (0, 1, 2 for x, y, z, in the order listed) and whether ``seq`` is intrinsic.

    Examples
    --------
    >>> parse_sequence("ZXZ")
    ((2, 0, 2), True)
    >>> parse_sequence("krylov")
    ((2, 0, 1), True)
    """
    if not isinstance(seq, str):
        raise InvalidTypeError(f"Expected `seq` to be a string, got {type(seq).__name__}.")
    s = PRESETS.get(seq.lower(), seq)
    if not _SEQ.match(s):
        raise InvalidInputError(
            "Expected `seq` to be 1 to 3 axes from 'xyz' (extrinsic) or 'XYZ' (intrinsic), "
            f"not mixed, or a preset {sorted(PRESETS)}, got {seq!r}."
        )
    if any(a == b for a, b in zip(s, s[1:], strict=False)):
        raise InvalidInputError(f"Expected consecutive axes of `seq` to differ, got {seq!r}.")
    return tuple("xyz".index(c) for c in s.lower()), s.isupper()


def quat_from_euler(seq: str, angles: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4) from angles (..., k) in radians, ``k = len(seq)``."""
    axes, intrinsic = parse_sequence(seq)
    ax = np.array(axes, dtype=np.int64)
    if not intrinsic:  # extrinsic abc (f1, f2, f3) == intrinsic CBA (f3, f2, f1)
        ax, angles = ax[::-1].copy(), angles[..., ::-1]
    if big(angles.shape[:-1]):
        q = np.empty(angles.shape[:-1] + (4,))
        threaded(kernels().euler_to_quat_flat, ax, flat(angles, angles.shape[-1]), q.reshape(-1, 4))
        return q
    return kernels().euler_to_quat(ax, angles, _D4)


def euler_from_quat(seq: str, q: np.ndarray, *, warn: bool = True) -> np.ndarray:
    """Angles (..., 3) in radians, in ``[-pi, pi]``, for unit quaternions (..., 4)."""
    axes, intrinsic = parse_sequence(seq)
    if len(axes) != 3:
        raise InvalidInputError(f"Expected `seq` to have 3 axes to recover angles, got {seq!r}.")
    ext = axes if not intrinsic else axes[::-1]
    code = np.array([*ext, 0 if intrinsic else 1], dtype=np.int64)
    f = flat(q, 4)
    angles = np.empty((f.shape[0], 3))
    k = kernels()
    if big(q.shape[:-1]):
        counts = np.zeros(-(-f.shape[0] // _CHUNK), dtype=np.int64)

        def step(lo: int, hi: int) -> None:
            counts[lo // _CHUNK] = k.to_euler_flat(f[lo:hi], code, angles[lo:hi])

        chunked(step, f.shape[0], _CHUNK)
        locked = bool(counts.any())
    else:
        singular = np.empty(f.shape[0], dtype=np.bool_)
        k.quat_to_euler_serial(f, code, angles, singular)
        locked = bool(singular.any())
    if warn and locked:
        warn_gimbal_lock(seq, stacklevel=3)
    return angles.reshape(q.shape[:-1] + (3,))


def warn_gimbal_lock(seq: str, stacklevel: int) -> None:
    """Issue the :class:`~poinsot.GimbalLockWarning` of :func:`euler_from_quat`."""
    warnings.warn(
        f"Gimbal lock: the middle angle of {seq!r} is within {GIMBAL_LOCK_ATOL:g} rad of "
        "its singular value; the third angle is set to 0 and the first holds the "
        "sum/difference of the first and third.",
        GimbalLockWarning,
        stacklevel=stacklevel + 1,
    )


def as_angles(angles: ArrayLike, k: int, name: str = "angles") -> np.ndarray:
    """Validate angles for a ``k``-axis sequence: shape (..., k), or (...) when k == 1.

    For one axis, an array of two or more dimensions whose last axis has length 1
    is read as SciPy reads it, shape (..., 1): ``(N, 1)`` angles give ``N``
    rotations. Otherwise every element is one angle (a scalar gives a single
    rotation, shape ``(N,)`` gives ``N`` rotations -- also for ``N = 1``, where
    SciPy returns a single rotation).
    """
    a = as_float_array(angles, name)
    if k == 1:
        return a if a.ndim >= 2 and a.shape[-1] == 1 else a[..., None]
    if a.ndim == 0 or a.shape[-1] != k:
        raise InvalidInputError(
            f"Expected `{name}` to have shape (..., {k}) for a {k}-axis sequence, got {a.shape}."
        )
    return a
