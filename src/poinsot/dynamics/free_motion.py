"""A free rigid body in space, six degrees of freedom (docs/theory.md §9, §10).

The centre of mass moves by the theorem on the motion of the centre of mass,
``m r_c'' = R^e``; the body turns about it by Euler's equations
``J w' + w x J w = M_c`` with the attitude's kinematic equation ``L' = L o w / 2``.
Forces may act at the centre of mass or at any body point (a force ``F`` at the body
point ``p`` adds the torque ``p x R^T F`` about the centre of mass).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .. import _quat
from .._typing import ArrayLike, FloatArray
from .._validate import as_rotation_quat, as_times, as_vec3
from .._vec import cross, inverse3
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError
from ..mass import RigidBody
from ..rotations.rotation import Rotation
from ..trajectory import PoseTrajectory
from .torques import as_torque

__all__ = ["simulate_free_motion"]


def _vector_or_callable(x: Any, name: str) -> Callable[..., FloatArray] | FloatArray | None:
    if x is None or callable(x):
        return x
    v = as_vec3(x, name)
    if v.shape != (3,):
        raise InvalidInputError(f"Expected `{name}` to have shape (3,), got {v.shape}.")
    return v


def simulate_free_motion(
    body: Any,
    position0: ArrayLike,
    velocity0: ArrayLike,
    rotation0: Any,
    omega0: ArrayLike,
    t: ArrayLike,
    *,
    force: Any = None,
    torque: Any = None,
    point_forces: Sequence[tuple[Any, ArrayLike]] = (),
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> PoseTrajectory:
    """Integrate the six-degree-of-freedom motion of a free rigid body (theory §9, §10).

    Parameters
    ----------
    body : RigidBody
        Mass and inertia **about the centre of mass** (body axes).
    position0, velocity0 : array_like, shape (3,)
        Centre of mass position and velocity (m, m/s, space axes).
    rotation0 : Rotation or array_like, shape (4,)
        Initial attitude (body -> space; scalar-first quaternion).
    omega0 : array_like, shape (3,)
        Initial angular velocity in body axes (rad/s).
    t : array_like, shape (n,)
        Output times (s), increasing.
    force : array_like (3,) or callable, optional
        The force at the centre of mass, space axes (N): a constant, or
        ``force(t, r, v)`` of the centre's position and velocity.
    torque : optional
        A torque about the centre of mass, as :func:`poinsot.dynamics.simulate` takes
        it (body axes; ``torque(t, rotation, omega)`` for a callable).
    point_forces : sequence of (force, point)
        Forces (space axes, N; a constant or ``force(t, r, v, rotation, omega)``)
        applied at body points (m, body axes, from the centre of mass): each adds to
        the resultant and adds the torque ``p x R^T F``.
    rtol, atol : float, optional
        Tolerances of SciPy's DOP853 on the 13 states.

    Returns
    -------
    PoseTrajectory
        ``position``, ``velocity`` (space axes) of the centre of mass, ``rotation``
        and body ``omega``; ``energy`` the kinetic energy (translation plus rotation,
        J) and ``momentum`` the angular momentum about the centre of mass (space
        axes).

    Examples
    --------
    A spinning box thrown in uniform gravity: the centre of mass follows the parabola.

    >>> import numpy as np
    >>> from poinsot.mass import RigidBody
    >>> from poinsot.dynamics import simulate_free_motion
    >>> box = RigidBody.box(2.0, 0.3, 0.2, 0.1)
    >>> tr = simulate_free_motion(box, [0, 0, 0], [3.0, 0, 4.0], [1.0, 0, 0, 0], [0.2, 5.0, 0.1],
    ...                           [0.0, 0.5], force=[0.0, 0.0, -2.0 * 9.81])
    >>> tr.position[-1].round(9)
    array([1.5    , 0.     , 0.77375])
    """
    from scipy.integrate import solve_ivp

    if not isinstance(body, RigidBody) or body.shape != ():
        raise InvalidTypeError(
            f"Expected `body` to be one poinsot.mass.RigidBody, got {type(body).__name__}."
        )
    m = float(body.mass)
    j = np.asarray(body.inertia, dtype=float)
    if not np.all(np.linalg.eigvalsh(j) > 0):
        raise InvalidInputError(
            "Expected `body` to have a positive definite inertia about its centre of mass."
        )
    j_inv = inverse3(j)
    r0 = as_vec3(position0, "position0")
    v0 = as_vec3(velocity0, "velocity0")
    w0 = as_vec3(omega0, "omega0")
    for name, a in (("position0", r0), ("velocity0", v0), ("omega0", w0)):
        if a.shape != (3,):
            raise InvalidInputError(f"Expected `{name}` to have shape (3,), got {a.shape}.")
    q0 = as_rotation_quat(rotation0, "rotation0")
    if q0.shape != (4,):
        raise InvalidInputError(f"Expected one `rotation0`, got shape {q0.shape[:-1]}.")
    tt = as_times(t, "t")
    f_cm = _vector_or_callable(force, "force")
    model = as_torque(torque)
    points = []
    for i, item in enumerate(point_forces):
        try:
            f_i, p_i = item
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"Expected `point_forces[{i}]` to be a pair (force, point), got {item!r}."
            ) from None
        p = as_vec3(p_i, f"point_forces[{i}][1]")
        if p.shape != (3,):
            raise InvalidInputError(f"Expected `point_forces[{i}][1]` of shape (3,).")
        points.append((_vector_or_callable(f_i, f"point_forces[{i}][0]"), p))

    def value(f: Any, *args: Any) -> FloatArray:
        out = np.asarray(f(*args) if callable(f) else f, dtype=float)
        if out.shape != (3,):
            raise InvalidInputError(f"Expected a force or torque of shape (3,), got {out.shape}.")
        return out

    def rhs(time: float, y: FloatArray) -> FloatArray:
        r, v, q, w = y[:3], y[3:6], y[6:10], y[10:]
        q = q / math.sqrt(float(q @ q))
        rot = Rotation.from_quat(q)
        total = np.zeros(3) if f_cm is None else value(f_cm, time, r, v)
        m_body = np.zeros(3) if model is None else model.body_torque(time, q, w)
        for f_j, p_j in points:
            fj = value(f_j, time, r, v, rot, w)
            total = total + fj
            m_body = m_body + cross(p_j, rot.apply(fj, inverse=True))
        dq = 0.5 * _quat.mul(q, _quat.pure(w))  # Poisson: L' = L o w_body / 2
        dw = j_inv @ (np.asarray(m_body, dtype=float) - cross(w, j @ w))
        return np.concatenate([v, total / m, dq, dw])

    y0 = np.concatenate([r0, v0, q0, w0])
    if tt.size == 1:
        ys = y0[None]
    else:
        sol = solve_ivp(rhs, (tt[0], tt[-1]), y0, method="DOP853", t_eval=tt, rtol=rtol,
                        atol=atol)  # fmt: skip
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            raise IntegrationError(f"6-DOF integration failed: {sol.message}")
        ys = sol.y.T
    quat = ys[:, 6:10] / np.linalg.norm(ys[:, 6:10], axis=-1, keepdims=True)
    rot = Rotation.from_quat(quat)
    w = ys[:, 10:]
    jw = w @ j.T
    energy = 0.5 * m * np.sum(ys[:, 3:6] ** 2, axis=-1) + 0.5 * np.sum(w * jw, axis=-1)
    free = force is None and model is None and not points
    return PoseTrajectory(
        tt,
        rot,
        w,
        "DOP853",
        energy=energy,
        momentum=rot.apply(jw),
        info={
            "solver": "DOP853",
            "rtol": float(rtol),
            "atol": float(atol),
            # no force, no torque: T (translation + rotation) and K are conserved
            **({"torque": "none", "conserved": ("energy", "momentum")} if free else {}),
        },
        position=ys[:, :3],
        velocity=ys[:, 3:6],
    )
