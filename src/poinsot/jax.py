"""poinsot's formulas on JAX: ``jit``-, ``vmap``- and ``grad``-able (``pip install poinsot[jax]``).

The functions here are not new formulas: each runs the one source of
:mod:`poinsot.rotations._scalar` (and :func:`poinsot.dynamics.euler_equations._rhs`)
re-bound to ``jax.numpy`` (:func:`poinsot._jit.rebind`). A branch on the data
(``if f <= pi``, the largest square of a matrix) becomes a select: every path
through the formula is traced once and each element takes the value of its own
path (``jnp.where`` on the conditions that path met), so values near singular
points are those of the scalar formula. Gradients are those of the path taken;
exactly *at* a branch point whose other path divides by zero (a zero rotation
vector, a zero quaternion vector part) the gradient may be NaN.

**float64.** Importing this module turns on ``jax_enable_x64``: poinsot's results
are float64 (the numba path's precision, 1e-13 parity), and float32 (JAX's
default) would lose 8 digits in the elliptic and rotation formulas.

Conventions as in ``docs/conventions.md``: Hamilton quaternions scalar first
``(w, x, y, z)``, angles in radians, leading axes are batch axes (theory §1-§3).

>>> import jax.numpy as jnp
>>> from poinsot import jax as pj
>>> q = pj.quat_from_rotvec(jnp.array([0.0, 0.0, jnp.pi / 2]))
>>> pj.quat_rotate(q, jnp.array([1.0, 0.0, 0.0])).round(12).tolist()
[0.0, 1.0, 0.0]
"""

from __future__ import annotations

import functools
import types
from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp

from ._jit import NAMESPACES, math_namespace, rebind
from .rotations import _scalar as S
from .rotations.euler import parse_sequence

jax.config.update("jax_enable_x64", True)  # type: ignore[no-untyped-call]  # float64: notes

__all__ = [
    "quat_multiply",
    "quat_inverse",
    "quat_rotate",
    "matrix_from_quat",
    "quat_from_matrix",
    "rotvec_from_quat",
    "quat_from_rotvec",
    "mrp_from_quat",
    "quat_from_mrp",
    "quat_from_euler",
    "euler_from_quat",
    "quat_log",
    "quat_exp",
    "slerp",
    "quat_rate",
    "omega_from_quat_rate",
    "euler_rhs",
    "euler_poisson",
    "integrate",
    "free_body_omega",
    "heavy_top_omega",
]

NAMESPACES["jax"] = {
    "math": math_namespace(jnp),
    "np": jnp,
    "max": lambda *a: functools.reduce(jnp.maximum, a),
    "min": lambda *a: functools.reduce(jnp.minimum, a),
    "_cross": jnp.cross,  # the array cross product is a primitive of the library
}


# ------------------------------------------------------------ branches as selects
class _Paths:
    """Decisions for the traced conditions of one run (True beyond the prefix)."""

    active: _Paths | None = None

    def __init__(self, prefix: list[bool]) -> None:
        self.prefix = prefix
        self.met: list[tuple[Any, bool]] = []

    def decide(self, cond: Any) -> bool:
        i = len(self.met)
        take = self.prefix[i] if i < len(self.prefix) else True
        self.met.append((cond, take))
        return take


_TRACER_BOOL = jax.core.Tracer.__bool__


def _tracer_bool(self: Any) -> bool:
    paths = _Paths.active
    if paths is None:
        return bool(_TRACER_BOOL(self))  # type: ignore[no-untyped-call]
    return paths.decide(self)


def _run(fn: Callable[..., Any], args: tuple[Any, ...], prefix: list[bool]) -> Any:
    # The truth value of a tracer is JAX's error everywhere except inside this call
    # (restored after it, also when nested); tracing is not meant to be shared by threads.
    paths, outer = _Paths(prefix), _Paths.active
    _Paths.active, jax.core.Tracer.__bool__ = paths, _tracer_bool  # type: ignore[method-assign]
    try:
        out = fn(*args)
    finally:
        _Paths.active = outer
        if outer is None:
            jax.core.Tracer.__bool__ = _TRACER_BOOL  # type: ignore[method-assign]
    return out, paths.met


def _explore(fn: Callable[..., Any], args: tuple[Any, ...], prefix: list[bool]) -> list[Any]:
    out, met = _run(fn, args, prefix)
    mask: Any = True
    for cond, take in met:
        mask = jnp.logical_and(mask, cond if take else jnp.logical_not(cond))
    leaves = [(mask, out)]
    for i in range(len(prefix), len(met)):  # the other side of every new branch point
        leaves += _explore(fn, args, [t for _, t in met[:i]] + [False])
    return leaves


def selects(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` (a scalar formula) on JAX arrays, its data branches as selects (module notes)."""
    g = rebind(fn, "jax")

    def run(*args: Any) -> Any:
        leaves = _explore(g, args, [])
        mask, out = leaves[-1]
        for m, o in reversed(leaves[:-1]):
            out = jax.tree_util.tree_map(lambda a, b, m=m: jnp.where(m, a, b), o, out)
        return out

    return run


def _cols(a: Any, k: int) -> list[Any]:
    a = jnp.asarray(a, dtype=jnp.float64)
    return [a[..., i] for i in range(k)]


def _stack(t: Any) -> Any:
    return jnp.stack(jnp.broadcast_arrays(*t), axis=-1)


_hamilton = selects(S.hamilton)
_rotate = selects(S.rotate)
_to_matrix = selects(S.to_matrix)
_from_matrix = selects(S.from_matrix)
_from_rotvec = selects(S.from_rotvec)
_canonical = selects(S.canonical)
_to_rotvec = selects(S.to_rotvec)
_to_mrp = selects(S.to_mrp)
_from_mrp = selects(S.from_mrp)
_to_euler = selects(S.to_euler)


@jax.jit
def quat_multiply(p: Any, q: Any) -> Any:
    """Hamilton product ``P o Q = (p0 q0 - p.q, p0 q + q0 p + p x q)`` (theory §1),
    ``(..., 4)`` each, broadcasting.

    >>> quat_multiply(jnp.array([0.0, 1, 0, 0]), jnp.array([0.0, 0, 1, 0])).tolist()
    [0.0, 0.0, 0.0, 1.0]
    """
    return _stack(_hamilton(*_cols(p, 4), *_cols(q, 4)))


@jax.jit
def quat_inverse(q: Any) -> Any:
    """Inverse of unit quaternions: the conjugate ``(w, -x, -y, -z)`` (theory §1).

    >>> quat_inverse(jnp.array([1.0, 2, 3, 4])).tolist()
    [1.0, -2.0, -3.0, -4.0]
    """
    q = jnp.asarray(q, dtype=jnp.float64)
    return q * jnp.array([1.0, -1.0, -1.0, -1.0])


@jax.jit
def quat_rotate(q: Any, v: Any) -> Any:
    """``v' = R(q) v``: the sandwich ``q o v o q~`` (theory §2), unit ``q`` (..., 4),
    ``v`` (..., 3).

    >>> quat_rotate(jnp.array([0.0, 0, 0, 1]), jnp.array([1.0, 0, 0])).tolist()
    [-1.0, 0.0, 0.0]
    """
    return _stack(_rotate(*_cols(q, 4), *_cols(v, 3)))


@jax.jit
def matrix_from_quat(q: Any) -> Any:
    """``A = (2 l0^2 - 1) E + 2 l0 l^ + 2 l l^T`` (theory §2): unit ``q`` (..., 4) ->
    (..., 3, 3).

    >>> matrix_from_quat(jnp.array([1.0, 0, 0, 0])).tolist()[0]
    [1.0, 0.0, 0.0]
    """
    m = _stack(_to_matrix(*_cols(q, 4)))
    return m.reshape(m.shape[:-1] + (3, 3))


@jax.jit
def quat_from_matrix(m: Any) -> Any:
    """Unit quaternion of rotation matrices (..., 3, 3), largest square first (theory §2).

    >>> quat_from_matrix(jnp.eye(3)).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    m = jnp.asarray(m, dtype=jnp.float64)
    return _stack(_from_matrix(*_cols(m.reshape(m.shape[:-2] + (9,)), 9)))


@jax.jit
def quat_from_rotvec(v: Any) -> Any:
    """``L = cos(f/2) + e sin(f/2)`` from ``phi = f e`` (..., 3) (theory §2).

    >>> quat_from_rotvec(jnp.zeros(3)).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    return _stack(_from_rotvec(*_cols(v, 3)))


@jax.jit
def rotvec_from_quat(q: Any) -> Any:
    """``phi = 2 atan2(|l|, l0) l / |l|`` of the canonical sign (``f in [0, pi]``) for
    unit ``q`` (..., 4) (theory §2).

    >>> rotvec_from_quat(jnp.array([0.0, 0, 0, 1])).round(12).tolist()
    [0.0, 0.0, 3.14159265359]
    """
    return _stack(_to_rotvec(*_canonical(*_cols(q, 4))))


@jax.jit
def mrp_from_quat(q: Any) -> Any:
    """Modified Rodrigues parameters ``p = l / (1 + l0)``, ``|p| <= 1`` (theory §2).

    >>> mrp_from_quat(jnp.array([0.0, 1, 0, 0])).tolist()
    [1.0, 0.0, 0.0]
    """
    return _stack(_to_mrp(*_canonical(*_cols(q, 4))))


@jax.jit
def quat_from_mrp(p: Any) -> Any:
    """``L = ((1 - |p|^2) + 2 p) / (1 + |p|^2)`` (theory §2), ``p`` (..., 3).

    >>> quat_from_mrp(jnp.array([1.0, 0, 0])).tolist()
    [0.0, 1.0, 0.0, 0.0]
    """
    return _stack(_from_mrp(*_cols(p, 3)))


@functools.partial(jax.jit, static_argnums=0)
def quat_from_euler(seq: str, angles: Any) -> Any:
    """``L = L_a1(f1) o L_a2(f2) o L_a3(f3)`` for a 3-axis sequence (theory §3):
    ``"XYZ"`` intrinsic, ``"xyz"`` extrinsic, angles (..., 3) in radians.

    >>> quat_from_euler("ZYX", jnp.array([0.0, 0.0, 0.0])).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    axes, intrinsic = parse_sequence(seq)
    a = _cols(angles, len(axes))
    if not intrinsic:  # extrinsic abc (f1, f2, f3) == intrinsic CBA (f3, f2, f1)
        axes, a = axes[::-1], a[::-1]
    a += [jnp.zeros_like(a[0])] * (3 - len(a))
    return _stack(selects(S.from_euler)(axes, *a))


@functools.partial(jax.jit, static_argnums=0)
def euler_from_quat(seq: str, q: Any) -> Any:
    """Angles (..., 3) in ``[-pi, pi]`` of a 3-axis sequence for unit ``q`` (theory §3),
    Bernardes & Viollet's algorithm; at gimbal lock the third angle is 0.

    >>> euler_from_quat("ZYX", jnp.array([1.0, 0, 0, 0])).tolist()
    [0.0, 0.0, 0.0]
    """
    axes, intrinsic = parse_sequence(seq)
    i, j, k = axes if not intrinsic else axes[::-1]
    a, b, c, _ = _to_euler(*_cols(q, 4), i, j, k, not intrinsic, 1e-7)
    return _stack((a, b, c))


@jax.jit
def quat_log(q: Any) -> Any:
    """``log q = phi / 2`` as a pure vector (..., 3): half the rotation vector (theory §2).

    >>> quat_log(jnp.array([1.0, 0, 0, 0])).tolist()
    [0.0, 0.0, 0.0]
    """
    return 0.5 * rotvec_from_quat(q)


@jax.jit
def quat_exp(u: Any) -> Any:
    """``exp u = cos|u| + u/|u| sin|u|`` for pure ``u`` (..., 3): :func:`quat_from_rotvec`
    of ``2 u`` (theory §2).

    >>> quat_exp(jnp.zeros(3)).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    return quat_from_rotvec(2.0 * jnp.asarray(u, dtype=jnp.float64))


@jax.jit
def slerp(q0: Any, q1: Any, t: Any) -> Any:
    """``q0 o exp(t log(q0~ o q1))``: the shortest arc from ``q0`` to ``q1`` at ``t``
    (theory §2); ``t`` broadcasts against the batch.

    >>> slerp(jnp.array([1.0, 0, 0, 0]), jnp.array([0.0, 0, 0, 1]), 0.5).round(12).tolist()
    [0.707106781187, 0.0, 0.0, 0.707106781187]
    """
    d = quat_multiply(quat_inverse(q0), q1)
    t = jnp.asarray(t, dtype=jnp.float64)[..., None]
    return quat_multiply(q0, quat_from_rotvec(t * rotvec_from_quat(d)))


def _euler_rhs_source() -> Callable[..., Any]:
    from .dynamics.euler_equations import _rhs

    return rebind(_rhs, "jax")


@jax.jit
def euler_rhs(moments: Any, omega: Any, torque: Any = None) -> Any:
    """Euler's equations ``w' = J^-1 (M - w x J w)`` (theory §5) for principal
    ``moments`` (..., 3) (kg m^2), ``omega`` (..., 3) rad/s, body ``torque`` (N m).

    >>> euler_rhs(jnp.array([1.0, 2.0, 3.0]), jnp.array([1.0, 1.0, 0.0])).tolist()
    [-0.0, -0.0, -0.3333333333333333]
    """
    j = jnp.asarray(moments, dtype=jnp.float64)
    w = jnp.asarray(omega, dtype=jnp.float64)
    m = None if torque is None else jnp.asarray(torque, dtype=jnp.float64)
    return _euler_rhs_source()(j, None, w, m, True)


@jax.jit
def euler_poisson(moments: Any, mgc: Any, omega: Any, gamma: Any) -> tuple[Any, Any]:
    """The Euler-Poisson right-hand side ``(w', gamma')`` of a heavy top (theory §10):
    ``w' = J^-1 (gamma x m g c - w x J w)`` (:func:`euler_rhs` with the gravity
    torque), ``gamma' = gamma x w``; principal ``moments`` (..., 3) kg m^2, ``mgc``
    the centre of mass times ``m g`` in body axes (N m), ``gamma`` the upward
    vertical in body axes.

    >>> w, g = euler_poisson(jnp.array([2.0, 2, 1]), jnp.array([0.0, 0, 5]),
    ...                      jnp.zeros(3), jnp.array([0.0, 1, 0]))
    >>> w.tolist()                     # tipping about x
    [2.5, 0.0, 0.0]
    """
    gam = jnp.asarray(gamma, dtype=jnp.float64)
    w = jnp.asarray(omega, dtype=jnp.float64)
    return euler_rhs(moments, w, jnp.cross(gam, mgc)), jnp.cross(gam, w)


def integrate(
    rhs: Callable[[Any, Any], Any],
    y0: Any,
    t: Any,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_steps: int = 100_000,
) -> Any:
    """``y(t)`` of ``y' = rhs(t, y)`` (any pytree ``y``) at the times ``t`` (ascending,
    ``t[0]`` the start) by diffrax's adaptive 8th-order Dormand-Prince (``Dopri8``);
    differentiable (diffrax's checkpointed adjoint). Needs ``diffrax``.

    >>> import jax.numpy as jnp
    >>> y = integrate(lambda t, y: -y, jnp.array(1.0), jnp.array([0.0, 1.0]))
    >>> round(float(y[1]), 10)
    0.3678794412
    """
    import diffrax

    ts = jnp.asarray(t, dtype=jnp.float64)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(lambda s, y, args: rhs(s, y)),
        diffrax.Dopri8(),
        t0=ts[0],
        t1=ts[-1],
        dt0=None,
        y0=y0,
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
        max_steps=max_steps,
    )
    return sol.ys


@jax.jit
def free_body_omega(moments: Any, omega0: Any, t: Any) -> Any:
    """Body angular velocity (len(t), 3) of a torque-free body: :func:`euler_rhs`
    through :func:`integrate`, from ``omega0`` at ``t[0]``.

    >>> w = free_body_omega(jnp.array([1.0, 2, 3]), jnp.array([0.0, 0, 1]), jnp.linspace(0, 1, 3))
    >>> w[-1].tolist()                 # a steady spin about a principal axis
    [0.0, 0.0, 1.0]
    """
    return integrate(lambda s, w: euler_rhs(moments, w), jnp.asarray(omega0, jnp.float64), t)


@jax.jit
def heavy_top_omega(moments: Any, mgc: Any, omega0: Any, gamma0: Any, t: Any) -> tuple[Any, Any]:
    """``(omega, gamma)`` (len(t), 3) each of a heavy top about a fixed point:
    :func:`euler_poisson` through :func:`integrate`.

    >>> w, g = heavy_top_omega(jnp.array([2.0, 2, 1]), jnp.array([0.0, 0, 5]), jnp.zeros(3),
    ...                        jnp.array([0.0, 0, 1]), jnp.linspace(0, 1, 3))
    >>> w[-1].tolist()                 # upright and at rest: stays so
    [0.0, 0.0, 0.0]
    """
    y0 = (jnp.asarray(omega0, jnp.float64), jnp.asarray(gamma0, jnp.float64))
    return integrate(lambda s, y: euler_poisson(moments, mgc, y[0], y[1]), y0, t)


# The quaternion product the kinematic rates call, on JAX (rebind's globals for "jax"
# take these in place of the NumPy-facing modules' functions).
NAMESPACES["jax"]["_quat"] = types.SimpleNamespace(multiply=quat_multiply, conjugate=quat_inverse)


@functools.partial(jax.jit, static_argnames="frame")
def quat_rate(q: Any, omega: Any, *, frame: str = "body") -> Any:
    """``q' = q o (0, w) / 2`` (``frame="body"``) or ``(0, w) o q / 2`` (``"space"``)
    (theory §5): unit ``q`` (..., 4), ``omega`` (..., 3) rad/s.

    >>> quat_rate(jnp.array([1.0, 0, 0, 0]), jnp.array([0.0, 0, 2])).tolist()
    [0.0, 0.0, 0.0, 1.0]
    """
    from .kinematics.rates import _quat_rate

    return rebind(_quat_rate, "jax")(q, jnp.asarray(omega, jnp.float64), frame)


@functools.partial(jax.jit, static_argnames="frame")
def omega_from_quat_rate(q: Any, qdot: Any, *, frame: str = "body") -> Any:
    """``w = 2 vec(q~ o q')`` (body) or ``2 vec(q' o q~)`` (space), inverse of
    :func:`quat_rate` (theory §5).

    >>> omega_from_quat_rate(jnp.array([1.0, 0, 0, 0]), jnp.array([0.0, 0, 0, 1])).tolist()
    [0.0, 0.0, 2.0]
    """
    from .kinematics.rates import _omega_from_quat_rate

    return rebind(_omega_from_quat_rate, "jax")(q, jnp.asarray(qdot, jnp.float64), frame)
