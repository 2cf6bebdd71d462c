"""Poisson's kinematic equations for the direction cosine matrix, integrated directly
(docs/theory.md §5), so that a course can compare matrices with quaternions.

Body form ``C' = C w_xi^`` (``C`` body -> space, ``w_xi`` in body axes) or space form
``C' = w_x^ C``: nine equations, or the course's six, with the third column (row for
the space form) the cross product of the other two. A matrix integration does not
keep ``C`` orthogonal: the drift ``|C^T C - E|`` is reported at every sample.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_choice, as_float_array, as_rotation_quat, as_times
from .._vec import cross, hat
from ..errors import IntegrationError, InvalidInputError
from ..rotations.rotation import Rotation

__all__ = ["PoissonMatrixRun", "integrate_poisson_matrix"]


@dataclass(frozen=True, eq=False)
class PoissonMatrixRun:
    """Direction cosine matrices from Poisson's equations (:func:`integrate_poisson_matrix`).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s).
    matrix : ndarray, shape (n, 3, 3)
        ``C(t)`` as integrated (body -> space; not exactly orthogonal).
    orthonormality_drift : ndarray, shape (n,)
        ``max |C^T C - E|`` at each sample.
    rotation : Rotation, shape (n,)
        The nearest rotations (for a comparison with a quaternion run).
    equations : int
        9 or 6.
    """

    t: FloatArray
    matrix: FloatArray
    orthonormality_drift: FloatArray
    rotation: Rotation
    equations: int


def integrate_poisson_matrix(
    rotation0: Any,
    omega: ArrayLike | Callable[[float], ArrayLike],
    t: ArrayLike,
    *,
    frame: str = "body",
    equations: int = 9,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> PoissonMatrixRun:
    """Integrate Poisson's matrix equation (theory §5) with SciPy's DOP853.

    Parameters
    ----------
    rotation0 : Rotation or array_like, shape (4,)
        Initial attitude (body -> space).
    omega : array_like, shape (3,), or callable
        Angular velocity (rad/s): a constant or ``omega(t)``, in the axes ``frame``
        names.
    t : array_like, shape (n,)
        Output times (s).
    frame : {"body", "space"}, optional
        ``C' = C w^`` with ``w`` in body axes, or ``C' = w^ C`` in space axes.
    equations : {9, 6}, optional
        All nine entries, or the course's six: the first two columns (body form) or
        rows (space form), the third their cross product.
    rtol, atol : float, optional
        Tolerances.

    Examples
    --------
    >>> import numpy as np
    >>> run = integrate_poisson_matrix([1.0, 0, 0, 0], [0.0, 0.0, 1.0], [0.0, np.pi / 2])
    >>> run.matrix[-1].round(9) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    >>> bool(run.orthonormality_drift.max() < 1e-9)
    True
    """
    from scipy.integrate import solve_ivp

    frame = as_choice(frame, "frame", ("body", "space"))
    if equations not in (9, 6) or isinstance(equations, bool):
        raise InvalidInputError(f"Expected `equations` to be 9 or 6, got {equations!r}.")
    q0 = as_rotation_quat(rotation0, "rotation0")
    if q0.shape != (4,):
        raise InvalidInputError(f"Expected one `rotation0`, got shape {q0.shape[:-1]}.")
    c0 = Rotation.from_quat(q0).as_matrix()
    tt = as_times(t, "t")
    if callable(omega):
        w_of = omega
    else:
        w_c = np.asarray(omega, dtype=float)
        if w_c.shape != (3,):
            raise InvalidInputError(
                f"Expected `omega` of shape (3,) or a callable, got {w_c.shape}."
            )
        w_of = lambda _t: w_c  # noqa: E731

    def full(c: FloatArray, time: float) -> FloatArray:
        w = as_float_array(w_of(time), "omega(t)")
        if w.shape != (3,):  # checked at every call: a callable may change its mind
            raise InvalidInputError(
                f"Expected `omega(t)` to return shape (3,) (rad/s), got {w.shape} at t = {time:g}."
            )
        return c @ hat(w) if frame == "body" else hat(w) @ c

    def unpack(y: FloatArray) -> FloatArray:
        if equations == 9:
            return y.reshape(3, 3)
        a, b = y[:3], y[3:]
        if frame == "body":  # columns c1, c2; c3 = c1 x c2
            return np.stack([a, b, cross(a, b)], axis=-1)
        return np.stack([a, b, cross(a, b)], axis=0)  # rows r1, r2; r3 = r1 x r2

    def pack(c: FloatArray) -> FloatArray:
        if equations == 9:
            return c.reshape(9)
        return np.concatenate([c[:, 0], c[:, 1]] if frame == "body" else [c[0], c[1]])

    def rhs(time: float, y: FloatArray) -> FloatArray:
        return pack(full(unpack(y), time))

    y0 = pack(c0)
    if tt.size == 1:
        ys = y0[None]
    else:
        sol = solve_ivp(rhs, (tt[0], tt[-1]), y0, t_eval=tt, method="DOP853", rtol=rtol, atol=atol)
        if sol.status != 0:
            raise IntegrationError(f"Poisson matrix integration failed: {sol.message}")
        ys = sol.y.T
    mats = np.stack([unpack(y) for y in ys])
    drift = np.abs(np.swapaxes(mats, -1, -2) @ mats - np.eye(3)).max(axis=(-2, -1))
    return PoissonMatrixRun(tt, mats, drift, Rotation.from_matrix(mats, atol=1.0), equations)
