"""poinsot's formulas on JAX: ``jit``-, ``vmap``- and ``grad``-able (``pip install poinsot[jax]``).

The functions here are not new formulas: each runs the one source of
:mod:`poinsot.rotations._scalar` (and :func:`poinsot.dynamics.integrators._common._rhs`)
re-bound to ``jax.numpy`` (:func:`poinsot._jit.rebind`). A branch on the data
(``if f <= pi``, the largest square of a matrix) becomes a select: every path
through the formula is traced once and each element takes the value of its own
path (``jnp.where`` on the conditions that path met), so values near singular
points are those of the scalar formula. Gradients are those of the path taken;
exactly *at* a branch point whose other path divides by zero (a zero rotation
vector, a zero quaternion vector part) the gradient may be NaN.

**float64.** Importing this module turns on ``jax_enable_x64``, process-wide, and
it is the only place in poinsot that does: poinsot's results are float64 (the
numba path's precision, 1e-13 parity), and float32 (JAX's default) would lose 8
digits in the elliptic and rotation formulas. It cannot be scoped to poinsot's calls
(``jax.experimental.enable_x64()`` around them): the caller's arrays, made before
the call, would be float32 already, and a jitted function traced once under one
mode would not be re-traced under the other.

**The executor.** This module adds the ``"jax"`` entry of
:data:`poinsot._jit.EXECUTORS`: ``math``/``np``/``max``/``min`` become
``jax.numpy``'s, the declared primitives (:func:`poinsot._jit.primitive`: the array
cross product, the quaternion product and conjugate, ``going``/``upto``/``pick``)
become JAX implementations, and the poinsot functions a formula calls are wrapped as
merged selects (:func:`_nested`). Branches are explored with the truth value of a
tracer patched only inside :func:`_deciding` (a context manager, restored on exit,
also on an exception).

Conventions as in ``docs/conventions.md``: Hamilton quaternions scalar first
``(w, x, y, z)``, angles in radians, leading axes are batch axes (theory §1-§3).

>>> import jax.numpy as jnp
>>> from poinsot import jax as pj
>>> q = pj.quat_from_rotvec(jnp.array([0.0, 0.0, jnp.pi / 2]))
>>> pj.quat_rotate(q, jnp.array([1.0, 0.0, 0.0])).round(12).tolist()
[0.0, 1.0, 0.0]
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from . import _vec
from ._jit import EXECUTORS, Executor, _going, _pick, _upto, math_namespace, rebind
from ._validate import as_rotation_quat
from .dynamics.free_body import _pow2, _snap_symmetric
from .dynamics.integrators._common import _rhs
from .errors import InvalidInputError
from .kinematics.rates import (
    _dcm_rate,
    _euler_adjugate,
    _euler_rates,
    _omega_from_dcm_rate,
    _omega_from_euler_rates,
    _omega_from_quat_rate,
    _quat_rate,
)
from .mass.tensor import check_principal_moments
from .rotations import _scalar as S
from .rotations import quaternion as _quaternion
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
    "dcm_rate",
    "omega_from_dcm_rate",
    "omega_from_euler_rates",
    "euler_rates",
    "euler_rhs",
    "euler_poisson",
    "integrate",
    "free_body_omega",
    "heavy_top_omega",
    "FreeBodyMotion",
    "free_body_exact",
    "free_body_omega_exact",
    "free_body_state_exact",
]


def _primitives() -> dict[str, Callable[..., Any]]:
    """The JAX implementations of poinsot's declared primitives, keyed by the function."""
    impls: dict[Callable[..., Any], Callable[..., Any]] = {
        _vec.cross: jnp.cross,
        # the quaternion product and conjugate the kinematic rates call (defined below)
        _quaternion.multiply: lambda p, q: quat_multiply(p, q),
        _quaternion.conjugate: lambda q: quat_inverse(q),
        # a converging loop runs all its steps; a table loop its static maximum
        _going: lambda cond: True,
        _upto: lambda n, nmax: nmax,
        _pick: jnp.where,
    }
    return {f"{f.__module__}.{f.__qualname__}": impl for f, impl in impls.items()}


EXECUTORS["jax"] = Executor(
    "jax",
    {
        "math": math_namespace(jnp),
        "np": jnp,
        "max": lambda *a: functools.reduce(jnp.maximum, a),
        "min": lambda *a: functools.reduce(jnp.minimum, a),
    },
    _primitives(),
    wrap=None,  # _nested, once defined below
    branches="every path traced once, merged by jnp.where on its conditions (selects)",
    loops="going(cond) is True (all N steps), upto(n, nmax) is nmax, pick is jnp.where",
)


# ------------------------------------------------------------ branches as selects
class _Paths:
    """Decisions for the traced conditions of one run (True beyond the prefix)."""

    active: _Paths | None = None

    def __init__(self, prefix: list[bool], memo: dict[Any, Any]) -> None:
        self.prefix = prefix
        self.met: list[tuple[Any, bool]] = []
        self.memo = memo  # shared by the runs of one exploration
        self.calls = 0

    def decide(self, cond: Any) -> bool:
        for c, t in self.met:  # the same tracer again (``if e01 ...`` twice): one decision
            if c is cond:
                return t
        i = len(self.met)
        take = self.prefix[i] if i < len(self.prefix) else True
        self.met.append((cond, take))
        self.calls = 0
        return take

    def call_key(self, fn: Any) -> tuple[Any, ...]:
        """Where the run is: the same after the same decisions, in every run (a run is
        deterministic), so a formula called there computes the same values."""
        self.calls += 1
        return (fn, tuple(t for _, t in self.met), self.calls)


_TRACER_BOOL = jax.core.Tracer.__bool__


def _tracer_bool(self: Any) -> bool:
    paths = _Paths.active
    if paths is None:
        return bool(_TRACER_BOOL(self))  # type: ignore[no-untyped-call]
    return paths.decide(self)


@contextlib.contextmanager
def _deciding(paths: _Paths) -> Iterator[_Paths]:
    """``with _deciding(paths):`` the truth value of a tracer is ``paths``' decision
    (:meth:`_Paths.decide`); JAX's own (an error) everywhere else. The patch of
    ``jax.core.Tracer.__bool__`` is made on entering the outermost block and undone on
    leaving it, also on an exception; nested blocks (a formula's callees) only swap
    :attr:`_Paths.active`. The only place the patch is made; tracing is not meant to be
    shared by threads."""
    outer = _Paths.active
    _Paths.active = paths
    if outer is None:
        jax.core.Tracer.__bool__ = _tracer_bool  # type: ignore[method-assign]
    try:
        yield paths
    finally:
        _Paths.active = outer
        if outer is None:
            jax.core.Tracer.__bool__ = _TRACER_BOOL  # type: ignore[method-assign]


def _run(
    fn: Callable[..., Any], args: tuple[Any, ...], prefix: list[bool], memo: dict[Any, Any]
) -> Any:
    with _deciding(_Paths(prefix, memo)) as paths:
        out = fn(*args)
    return out, paths.met


def _explore(
    fn: Callable[..., Any], args: tuple[Any, ...], prefix: list[bool], memo: dict[Any, Any]
) -> list[Any]:
    """Every path of ``fn``: ``[(mask, result)]``. A formula ``fn`` calls at the same
    place of two runs (:meth:`_Paths.call_key`) is traced once (``memo``): the runs
    share the part of ``fn`` before their first different decision."""
    out, met = _run(fn, args, prefix, memo)
    mask: Any = True
    for cond, take in met:
        mask = jnp.logical_and(mask, cond if take else jnp.logical_not(cond))
    leaves = [(mask, out)]
    for i in range(len(prefix), len(met)):  # the other side of every new branch point
        leaves += _explore(fn, args, [t for _, t in met[:i]] + [False], memo)
    return leaves


def _merged(g: Callable[..., Any]) -> Callable[..., Any]:
    def run(*args: Any) -> Any:
        leaves = _explore(g, args, [], {})
        mask, out = leaves[-1]
        for m, o in reversed(leaves[:-1]):
            out = jax.tree_util.tree_map(lambda a, b, m=m: jnp.where(m, a, b), o, out)
        return out

    return run


def _static(x: Any) -> Any:
    """What a formula's paths can depend on: values of Python scalars, kinds of arrays."""
    if isinstance(x, jax.Array):
        return ("array", jnp.result_type(x).kind)
    return x if isinstance(x, (int, float, bool, str, type(None))) else ("other", type(x))


def _is_float(x: Any) -> bool:
    return isinstance(x, jax.Array) and jnp.issubdtype(x.dtype, jnp.floating)


def selects(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` (a scalar formula) on JAX arrays, its data branches as selects (module notes).

    The arguments and results are lanes: arrays (or tuples, lists of them) of which
    element ``e`` of a result depends on element ``e`` of the arguments only (they
    broadcast). Derivatives: each lane's partial derivatives are those of its own
    path, taken in forward mode (``jax.jvp`` with a unit tangent per argument, the
    paths merged by the selects); the tangent of a result is their sum weighted by the
    argument tangents, a map without the untaken paths, so reverse mode sees no
    ``0 * inf`` from them either. The poinsot functions ``fn`` calls are merged
    selects too (:func:`_nested`, :attr:`poinsot._jit.Executor.wrap`).
    """
    g = rebind(fn, "jax")
    merged = _merged(g)

    npaths: dict[Any, int] = {}

    def call(*args: Any) -> Any:
        flat, tree = jax.tree_util.tree_flatten(args)
        arr = [k for k, x in enumerate(flat) if isinstance(x, jax.Array)]
        pos = [p for p, k in enumerate(arr) if _is_float(flat[k])]
        if not pos:
            return merged(*args)
        # one path (no data branch for these static arguments): JAX's own derivatives
        sig = (tree, tuple(_static(x) for x in flat))
        if sig not in npaths:
            loops = _LOOPS[0]
            leaves = _explore(g, args, [], {})
            # a rolled loop (:func:`_loop`) merges its step's paths inside the loop,
            # where JAX's own reverse mode would meet the untaken paths: the rule below
            npaths[sig] = len(leaves) if _LOOPS[0] == loops else 2
            if npaths[sig] == 1:
                return leaves[0][1]
        if npaths[sig] == 1:
            return merged(*args)
        kinds: list[Any] = []

        def f(*a: Any) -> Any:  # the array leaves as arguments (no tracer closed over)
            full = list(flat)
            for k, x in zip(arr, a, strict=True):
                full[k] = x
            out = merged(*jax.tree_util.tree_unflatten(tree, full))
            leaves, otree = jax.tree_util.tree_flatten(out)
            kinds[:] = [otree] + [jnp.result_type(o) for o in leaves]
            # results as float lanes for the derivative rule (ints, bools back below)
            return [jnp.asarray(o, dtype=jnp.float64) for o in leaves]

        fj = jax.custom_jvp(f)

        @fj.defjvp
        def f_jvp(primals: Any, tangents: Any) -> Any:
            def g(*fa: Any) -> Any:  # of the float arguments
                a = list(primals)
                for p, x in zip(pos, fa, strict=True):
                    a[p] = x
                return f(*a)

            fprim = [primals[p] for p in pos]
            n = len(pos)
            units = [jnp.zeros((n,) + jnp.shape(x)).at[k].set(1.0) for k, x in enumerate(fprim)]
            # d result / d argument k, lane by lane, for every k at once (and the
            # result itself, traced once: it does not depend on the unit tangent)
            out, parts = jax.vmap(lambda *u: jax.jvp(g, tuple(fprim), u), out_axes=(None, 0))(
                *units
            )
            # one product with the stacked tangents per result: in reverse mode the
            # derivatives ``d`` are then one saved array per result, not one per result
            # and argument (JAX's linearisation saves what the tangent side reads; the
            # attitude's many saved slices made XLA compile its program for 156 s)
            tan = []
            for o, d in zip(out, parts, strict=True):
                shape = jnp.shape(o)
                cols = [
                    jnp.broadcast_to(tangents[pos[k]], shape)
                    if jnp.broadcast_shapes(jnp.shape(d[k]), jnp.shape(tangents[pos[k]])) == shape
                    else jnp.zeros(shape)
                    for k in range(n)
                ]
                tan.append(jnp.sum(d * jnp.stack(cols), axis=0))
            return out, tan

        res = fj(*[flat[k] for k in arr])
        otree, dtypes = kinds[0], kinds[1:]
        return jax.tree_util.tree_unflatten(
            otree, [r.astype(t) for r, t in zip(res, dtypes, strict=True)]
        )

    return call


def _nested(fn: Callable[..., Any]) -> Callable[..., Any]:
    """A poinsot function called by a formula run by :func:`selects`: its own paths
    merged by selects where it returns (they do not multiply its caller's), traced once
    per place of its caller's runs (:meth:`_Paths.call_key`). Its derivatives are JAX's
    own: forward mode, as the outer :func:`selects` takes them, sees only the taken
    path's tangents."""
    merged = _merged(rebind(fn, "jax"))

    def run(*args: Any) -> Any:
        paths = _Paths.active
        if paths is None:
            return merged(*args)
        key = paths.call_key(run)
        if key not in paths.memo:
            paths.memo[key] = merged(*args)
        return paths.memo[key]

    return run


class _Vec(list):  # type: ignore[type-arg]
    """Lanes indexable like a small array by a traced index (``jnp.choose``): the
    moments, angular velocity and tables of the free-body kernels on JAX."""

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, (int, slice)):
            return list.__getitem__(self, i)
        k = jnp.clip(jnp.asarray(i, dtype=jnp.int32), 0, len(self) - 1)
        cases = jnp.broadcast_arrays(k, *jnp.broadcast_arrays(*self))
        return jax.lax.select_n(cases[0], *cases[1:])


jax.tree_util.register_pytree_node(_Vec, lambda v: (list(v), None), lambda _, c: _Vec(c))

EXECUTORS["jax"].wrap = _nested


#: how many loops :func:`_loop` has traced (read by :func:`selects`)
_LOOPS = [0]


def _loop(
    steps: range,
    body: Callable[..., Any],
    carry: tuple[Any, ...],
    going: Callable[..., Any] | None = None,
) -> Any:
    """A formula's table loop (:mod:`poinsot._rolled`) as one ``jax.lax.fori_loop``
    (a ``while_loop`` that stops once no lane is ``going``, when the loop has a
    convergence test): its body traced once, its branches merged as selects within the
    step (the :func:`_nested` rule), instead of one traced copy per step. Forward mode
    differentiates it; reverse mode goes through the forward-mode rule of
    :func:`selects`."""
    _LOOPS[0] += 1
    n, start, stride = len(steps), steps.start, steps.step
    step = _merged(lambda k, c: body(start + k * stride, c))
    if n == 0:
        return carry
    # the first step on its own: a constant of the formula (x = 0 in R_J(0, y, z, p))
    # keeps its symbolic zero tangent there, where sqrt(x)'s infinite derivative
    # would meet it; in the loop every carried value has a tangent (0 * inf = NaN)
    carry = step(0, carry)
    if n == 1:
        return carry
    try:  # the first step's results are the loop's types, as a rule
        return _rest(step, carry, n, start, stride, going)
    except TypeError:  # a carried value that a later step widens (rare): fitted first
        return _rest(step, _carry_types(step, carry), n, start, stride, going)


def _rest(
    step: Callable[..., Any],
    carry: Any,
    n: int,
    start: int,
    stride: int,
    going: Callable[..., Any] | None,
) -> Any:
    """Steps ``1 .. n - 1`` of :func:`_loop`."""
    if going is None:
        return jax.lax.fori_loop(1, n, step, carry)

    def more(state: tuple[Any, Any]) -> Any:
        k, c = state
        return (k < n) & jnp.any(going(start + k * stride, c))

    def advance(state: tuple[Any, Any]) -> tuple[Any, Any]:
        k, c = state
        return k + 1, step(k, c)

    return jax.lax.while_loop(more, advance, (jnp.asarray(1), carry))[1]


def _carry_types(step: Callable[..., Any], carry: tuple[Any, ...]) -> tuple[Any, ...]:
    """``carry`` broadcast to the shapes and types a step returns (a Python float that
    a step makes a lane array): a loop's carry keeps one type through its steps."""
    k = jnp.asarray(0)

    def fit(c: Any, o: Any) -> Any:
        shape = jnp.broadcast_shapes(jnp.shape(c), o.shape)
        return jnp.broadcast_to(jnp.asarray(c, dtype=o.dtype), shape)

    for _ in range(4):
        out = jax.eval_shape(step, k, carry)
        carry = jax.tree_util.tree_map(fit, carry, out)
        same = jax.tree_util.tree_map(lambda c, o: jnp.shape(c) == o.shape, carry, out)
        if all(jax.tree_util.tree_leaves(same)):
            return carry
    raise TypeError("a loop's carried values change shape from step to step")  # pragma: no cover


def _item(table: Any, k: Any) -> Any:
    """``table[k]`` at a traced loop index ``k`` (a select among the table's lanes)."""
    return _Vec(table)[k]


def _put(table: Any, k: Any, value: Any) -> Any:
    """``table`` with entry ``k`` (a traced loop index) set to ``value`` (selects)."""
    return [jnp.where(k == i, value, x) for i, x in enumerate(table)]


EXECUTORS["jax"].loop = _loop
EXECUTORS["jax"].item = _item
EXECUTORS["jax"].put = _put


def _cols(a: Any, k: int) -> list[Any]:
    a = jnp.asarray(a, dtype=jnp.float64)
    return [a[..., i] for i in range(k)]


def _stack(t: Any) -> Any:
    """The components ``t`` as the last axis, written one by one (in-place updates): a
    stack fused with the components' computation made XLA's CPU code evaluate their
    shared terms once per component and element by element, unvectorised (the exact
    attitude: 2.3 us per body and time in that one fusion; 0.47 us written so)."""
    parts = jnp.broadcast_arrays(*t)
    out = jnp.zeros(parts[0].shape + (len(parts),), jnp.result_type(*parts))
    for i, p in enumerate(parts):
        out = out.at[..., i].set(p)
    return out


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
    return rebind(_rhs, "jax")


@jax.jit
def euler_rhs(moments: Any, omega: Any, torque: Any = None) -> Any:
    """Euler's equations ``w' = J^-1 (M - w x J w)`` (theory §5) for principal
    ``moments`` (..., 3) (kg m^2) or inertia tensors (..., 3, 3) in body axes (an
    array whose last two dimensions are ``(3, 3)`` is a tensor, as in
    :func:`poinsot.dynamics.euler_rhs`), ``omega`` (..., 3) rad/s, body ``torque`` (N m).

    >>> euler_rhs(jnp.array([1.0, 2.0, 3.0]), jnp.array([1.0, 1.0, 0.0])).tolist()
    [-0.0, -0.0, -0.3333333333333333]
    >>> euler_rhs(jnp.diag(jnp.array([1.0, 2.0, 3.0])), jnp.array([1.0, 1.0, 0.0])).tolist()
    [0.0, 0.0, -0.3333333333333333]
    """
    j = jnp.asarray(moments, dtype=jnp.float64)
    w = _vec3(omega, "omega")
    m = None if torque is None else _vec3(torque, "torque")
    if j.ndim >= 2 and j.shape[-2:] == (3, 3):
        return _euler_rhs_source()(j, jnp.linalg.inv(j), w, m, False)
    return _euler_rhs_source()(_vec3(j, "moments"), None, w, m, True)


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


def _vec3(a: Any, name: str) -> Any:
    a = jnp.asarray(a, dtype=jnp.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InvalidInputError(f"Expected `{name}` to have shape (..., 3), got {a.shape}.")
    return a


def _mat3(a: Any, name: str) -> Any:
    a = jnp.asarray(a, dtype=jnp.float64)
    if a.ndim < 2 or a.shape[-2:] != (3, 3):
        raise InvalidInputError(f"Expected `{name}` to have shape (..., 3, 3), got {a.shape}.")
    return a


def _euler_seq(seq: Any) -> str:
    axes, _ = parse_sequence(seq)
    if len(axes) != 3:
        raise InvalidInputError(f"Expected `seq` to have 3 axes, got {seq!r}.")
    return str(seq)


@functools.partial(jax.jit, static_argnames="frame")
def quat_rate(q: Any, omega: Any, *, frame: str = "body") -> Any:
    """``q' = q o (0, w) / 2`` (``frame="body"``) or ``(0, w) o q / 2`` (``"space"``)
    (theory §5): unit ``q`` (..., 4), ``omega`` (..., 3) rad/s.

    >>> quat_rate(jnp.array([1.0, 0, 0, 0]), jnp.array([0.0, 0, 2])).tolist()
    [0.0, 0.0, 0.0, 1.0]
    """

    return rebind(_quat_rate, "jax")(q, jnp.asarray(omega, jnp.float64), frame)


@functools.partial(jax.jit, static_argnames="frame")
def omega_from_quat_rate(q: Any, qdot: Any, *, frame: str = "body") -> Any:
    """``w = 2 vec(q~ o q')`` (body) or ``2 vec(q' o q~)`` (space), inverse of
    :func:`quat_rate` (theory §5).

    >>> omega_from_quat_rate(jnp.array([1.0, 0, 0, 0]), jnp.array([0.0, 0, 0, 1])).tolist()
    [0.0, 0.0, 2.0]
    """

    return rebind(_omega_from_quat_rate, "jax")(q, jnp.asarray(qdot, jnp.float64), frame)


@functools.partial(jax.jit, static_argnames="frame")
def dcm_rate(C: Any, omega: Any, *, frame: str = "body") -> Any:
    """Poisson's equation ``A' = A w^`` (``frame="body"``, ``w`` in body axes) or
    ``A' = w^ A`` (``"space"``) (theory §5): rotation matrices ``C`` (..., 3, 3) (body ->
    space), ``omega`` (..., 3) rad/s; the formula of :func:`poinsot.kinematics.dcm_rate`.

    >>> dcm_rate(jnp.eye(3), jnp.array([0.0, 0.0, 1.0])).tolist()[0]
    [0.0, -1.0, 0.0]
    """

    return rebind(_dcm_rate, "jax")(_mat3(C, "C"), _vec3(omega, "omega"), _frame(frame))


@functools.partial(jax.jit, static_argnames="frame")
def omega_from_dcm_rate(C: Any, Cdot: Any, *, frame: str = "body") -> Any:
    """``w = vee(A^T A')`` (body) or ``vee(A' A^T)`` (space), the product antisymmetrised
    (theory §5): the inverse of :func:`dcm_rate`.

    >>> C = jnp.eye(3)
    >>> omega_from_dcm_rate(C, dcm_rate(C, jnp.array([1.0, 2.0, 3.0]))).tolist()
    [1.0, 2.0, 3.0]
    """

    f = rebind(_omega_from_dcm_rate, "jax")
    return f(_mat3(C, "C"), _mat3(Cdot, "Cdot"), _frame(frame))


@functools.partial(jax.jit, static_argnames=("seq", "frame"))
def omega_from_euler_rates(seq: str, angles: Any, rates: Any, *, frame: str = "body") -> Any:
    """``omega = M(angles) angles'`` (theory §3, §5): column ``k`` of ``M`` is the axis of
    the ``k``-th elementary rotation of ``seq`` in ``frame`` axes; radians, rad/s; any
    of the 12 sequences (``"ZXZ"`` intrinsic, ``"zxz"`` extrinsic).

    >>> omega_from_euler_rates("ZXZ", jnp.array([0.0, 0.5, 0.0]), jnp.array([1.0, 0, 0]))
    ... # doctest: +ELLIPSIS
    Array([0.        , 0.47942554, 0.87758256], dtype=float64)
    """

    f = rebind(_omega_from_euler_rates, "jax")
    return f(_euler_seq(seq), _vec3(angles, "angles"), _vec3(rates, "rates"), _frame(frame))


@functools.partial(jax.jit, static_argnames=("seq", "frame"))
def euler_rates(seq: str, angles: Any, omega: Any, *, frame: str = "body") -> Any:
    """The Euler kinematic equations ``angles' = M^-1 omega = adj(M) omega / det M``
    (theory §3, §5), ``M`` as in :func:`omega_from_euler_rates`; ``det M`` is the sine
    (proper Euler) or cosine (Tait-Bryan) of the middle angle: at gimbal lock the
    result is inf/NaN (no error is raised inside a traced function).

    >>> euler_rates("ZXZ", jnp.array([0.0, 0.5, 0.0]), jnp.array([0.0, 0.0, 1.0])).tolist()
    [0.0, 0.0, 1.0]
    """

    a, w = _vec3(angles, "angles"), _vec3(omega, "omega")
    adj, det = rebind(_euler_adjugate, "jax")(_euler_seq(seq), a, _frame(frame))
    return rebind(_euler_rates, "jax")(adj, det, w)


def _frame(frame: Any) -> str:
    if frame not in ("body", "space"):
        raise InvalidInputError(f"Expected `frame` to be 'body' or 'space', got {frame!r}.")
    return str(frame)


# ------------------------------------------------------------ the exact free body
def _free_body_kernels() -> Any:
    from .dynamics import _free_body_numba

    return _free_body_numba


@functools.cache
def _free_body_lanes() -> tuple[Callable[..., Any], Callable[..., Any], Callable[..., Any]]:
    k = _free_body_kernels()
    return selects(k.setup_lanes), selects(k.attitude_setup_lanes), selects(k.state_lanes)


@dataclass(frozen=True)
class FreeBodyMotion:
    """The exact torque-free motion of a body (or a batch): the constants of
    :func:`free_body_exact`, a JAX pytree (it passes through ``jit``, ``vmap``, ``grad``).

    ``scale`` is the power of two ``|omega0|`` was divided by (the motion is computed
    for ``|w| ~ 1``, ``max(I) ~ 1``); ``constants`` the per-body constants of the
    elliptic (or symmetric, uniform) solution, in the layout of
    ``poinsot.dynamics._free_body_numba.setup_lanes``; ``moments``, ``omega0`` the
    scaled initial data (..., 3) and ``q0`` the initial attitude (..., 4), unit, from
    which :meth:`attitude` computes its offsets. Evaluate with :meth:`omega`,
    :meth:`attitude` or :meth:`state`.
    """

    scale: Any
    constants: tuple[Any, ...]
    moments: Any
    omega0: Any
    q0: Any

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape."""
        return tuple(jnp.shape(self.scale))

    @property
    def regime(self) -> Any:
        """Regime codes (int array, batch shape): indices into
        ``poinsot.dynamics._free_body_numba.REGIMES`` (``"major"`` is 4, ``"minor"`` 5,
        ``"separatrix"`` 6, ``"symmetric"`` 3, ``"spherical"`` 1, ``"rest"`` 0, a
        rotation exactly about the middle axis 2)."""
        return self.constants[0]

    def omega(self, t: Any) -> Any:
        """Body angular velocity (rad/s), shape ``shape + t.shape + (3,)``, at times ``t`` (s).

        ``w_i = a_i dn(u)``, ``w_m = a_m sn(u)``, ``w_j = a_j cn(u)``, ``u = lam t + u0``
        (theory §10; :class:`poinsot.dynamics.FreeRigidBody`).

        >>> m = free_body_exact(jnp.array([2.0, 2.0, 1.0]), jnp.array([1.0, 0.0, 2.0]))
        >>> m.omega(jnp.array([0.0, 1.0])).round(6).tolist()[1]
        [0.540302, -0.841471, 2.0]
        """
        return _motion_eval(self, t, False)

    def attitude(self, t: Any) -> Any:
        """Attitude quaternions (body -> space, scalar first), shape ``shape + t.shape +
        (4,)``, at times ``t`` (s); ``attitude(0) = q0``.

        Theory §10 (:meth:`poinsot.dynamics.FreeRigidBody.rotation`, the same source):
        an elliptic motion is ``q = qs o Rz(psi) Rx(theta) Rz(phi) o qp``, the z-x-z
        Euler angles of the body unit momentum about the axis ``j`` the polhode does
        not encircle (``qp`` permutes the axes so that ``j`` is z; ``qs`` is fixed by
        ``q0``), ``theta, phi`` from ``J w / |K|``, the precession
        ``psi = K t / I + kappa (...) (J(u) - J(u0)) / lam`` with the third-kind
        integral ``J(u) = int sn^2 / (1 + n sn^2)`` by Carlson's ``R_J`` (whole periods
        by quasi-periodicity); two equal moments: ``q = Rot(k, K t / I_p) q0
        Rot(e_s, -phi' t)`` (regular precession about the momentum direction ``k``);
        equal moments, rest, spins about the middle axis: ``q = q0 Rot(w, |w| t)``.

        >>> m = free_body_exact(jnp.array([1.0, 2.0, 3.0]), jnp.array([0.0, 0.0, 1.0]))
        >>> m.attitude(jnp.linspace(0.0, jnp.pi, 5))[-1].round(12).tolist()  # half a turn about z
        [0.0, 0.0, 0.0, 1.0]
        """
        return _motion_eval(self, t, True)[1]

    def rotation(self, t: Any) -> Any:
        """:meth:`attitude` under the name of the NumPy exact solutions
        (``FreeRigidBody.rotation``): here the scalar-first quaternions themselves,
        ``shape + t.shape + (4,)``, not a :class:`~poinsot.Rotation` (which cannot hold
        traced values).

        >>> m = free_body_exact(jnp.array([1.0, 2.0, 3.0]), jnp.array([0.0, 0.0, 1.0]))
        >>> t = jnp.linspace(0.0, jnp.pi, 5)  # the shapes of attitude's example: compiled once
        >>> bool((m.rotation(t) == m.attitude(t)).all())
        True
        """
        return self.attitude(t)

    def state(self, t: Any) -> tuple[Any, Any]:
        """``(omega(t), attitude(t))`` in one pass (:meth:`omega`, :meth:`attitude`).

        >>> m = free_body_exact(jnp.array([1.0, 2.0, 3.0]), jnp.array([0.3, 0.2, 0.9]))
        >>> w, q = m.state(jnp.linspace(0.0, 1.0, 5))
        >>> w.shape, q.shape
        ((5, 3), (5, 4))
        """
        return _motion_eval(self, t, True)


@functools.partial(jax.jit, static_argnums=2)
def _motion_eval(motion: FreeBodyMotion, t: Any, want_q: bool) -> Any:
    t = jnp.asarray(t, dtype=jnp.float64)
    extra = (None,) * t.ndim

    def expand(tree: Any) -> Any:  # the batch against the times
        return jax.tree_util.tree_map(lambda a: a[(..., *extra)], tree)

    _, attitude_setup, state = _free_body_lanes()
    ws = motion.scale[(..., *extra)]
    im = _Vec(_cols(motion.moments, 3))
    a = None
    if want_q:
        q0 = _cols(motion.q0, 4)
        a = expand(attitude_setup(im, _Vec(_cols(motion.omega0, 3)), q0, motion.constants))
    out = state(ws * t, expand(motion.constants), a, expand(im), want_q)  # traced: selects
    w = _stack(out[:3]) * ws[..., None]
    return (w, _stack(out[3:])) if want_q else w


jax.tree_util.register_pytree_node(
    FreeBodyMotion,
    lambda m: ((m.scale, m.constants, m.moments, m.omega0, m.q0), None),
    lambda _, c: FreeBodyMotion(*c),
)


def _quat4(q: Any, name: str) -> Any:
    q = jnp.asarray(q, dtype=jnp.float64)
    if q.ndim == 0 or q.shape[-1] != 4:
        raise InvalidInputError(f"Expected `{name}` to have shape (..., 4), got {q.shape}.")
    return q


def free_body_exact(
    moments: Any, omega0: Any, q0: Any = None, *, rotation0: Any = None
) -> FreeBodyMotion:
    """The exact torque-free (Euler-Poinsot) motion of bodies with principal ``moments``
    (..., 3) (kg m^2, any order), body angular velocity ``omega0`` (..., 3) (rad/s)
    and attitude ``q0`` (..., 4) (principal body -> space, scalar first, normalised;
    the identity if ``None``) at ``t = 0``: a :class:`FreeBodyMotion` (a pytree),
    evaluated by its ``omega``, ``attitude`` (alias ``rotation``) and ``state``.
    ``rotation0=`` (keyword, the name of ``FreeRigidBody``'s argument) takes the
    initial attitude instead of ``q0``: a JAX array of quaternions (traced or not), or
    anything :class:`poinsot.dynamics.FreeRigidBody` accepts (a :class:`~poinsot.Rotation`,
    a SciPy ``Rotation``, quaternions), checked and converted with NumPy.

    The algorithm of :class:`poinsot.dynamics.FreeRigidBody`, run from the same
    source (``poinsot.dynamics._free_body_numba``, ``_elliptic``; theory §10): with
    ``D = K^2 - 2 T B`` in double-double arithmetic, ``D > 0`` (``D < 0``) the polhode
    encircles the major (minor) axis ``i``; ``w_i = a_i dn(u | k^2)``,
    ``w_m = a_m sn(u | k^2)``, ``w_j = a_j cn(u | k^2)``, ``u = lam t + u0`` with
    ``1 - k^2 = (I_i - I_j) D / ((I_i - I_m) (K^2 - 2 T I_j))``, ``K(k)`` by the AGM,
    ``u0`` by Carlson's ``R_F``, ``sn, cn, dn`` by the descending Landen
    transformation; ``D = 0`` (within ``2^-100``): ``sn = tanh``, ``cn = dn = sech``;
    two equal moments: ``w_perp`` turns at ``(I_s - I_p) w_s / I_p``; three equal, rest,
    a spin about the middle axis: ``w`` constant. The attitude: :meth:`FreeBodyMotion.attitude`.
    ``omega`` is differentiable w.r.t. ``moments`` and ``omega0`` (each path's
    derivative; NaN exactly at a spin about a principal axis, where ``k^2 = 0`` enters
    through a square root, and on the separatrix itself), and so is the attitude
    (forward mode compiles fastest: docs/jax.md).

    >>> m = free_body_exact(jnp.array([1.0, 2.0, 3.0]), jnp.array([0.1, 1.0, 0.1]))
    >>> int(m.regime)                      # 4: "major", near the middle axis
    4
    >>> w = m.omega(jnp.array([0.0, 22.9963]))   # one period (FreeRigidBody.period)
    >>> bool(jnp.allclose(w[0], w[1], atol=1e-4))
    True
    """
    # concrete moments are checked like FreeRigidBody's (positive, A + B >= C); traced
    # ones (under an outer jit, vmap or grad) cannot be, a jitted function cannot raise
    if not isinstance(moments, jax.core.Tracer):
        check_principal_moments(np.asarray(moments, dtype=float), "moments")
    if rotation0 is not None:
        if q0 is not None:
            raise InvalidInputError(
                "Give the initial attitude as `q0` or as `rotation0`, not both."
            )
        if isinstance(rotation0, jax.Array):  # traced or not: left to _quat4
            q0 = rotation0
        else:
            q0 = as_rotation_quat(rotation0, "rotation0")
    if q0 is None:  # one compiled program with or without q0 (the same shapes)
        q0 = jnp.array([1.0, 0.0, 0.0, 0.0])
    return _free_body_exact(moments, omega0, q0)


@jax.jit
def _free_body_exact(moments: Any, omega0: Any, q0: Any) -> FreeBodyMotion:
    j, w = _vec3(moments, "moments"), _vec3(omega0, "omega0")
    q = _quat4(q0, "q0")
    shape = jnp.broadcast_shapes(j.shape[:-1], w.shape[:-1], q.shape[:-1])
    j, w = jnp.broadcast_to(j, shape + (3,)), jnp.broadcast_to(w, shape + (3,))
    q = jnp.broadcast_to(q, shape + (4,))
    q = q / jnp.sqrt(jnp.sum(q * q, axis=-1, keepdims=True))
    mom = rebind(_snap_symmetric, "jax")(j)
    pow2 = rebind(_pow2, "jax")
    # exact powers of two (piecewise constant: no derivative)
    ws = pow2(jax.lax.stop_gradient(jnp.sqrt(jnp.sum(w * w, axis=-1))))
    iscale = pow2(jax.lax.stop_gradient(jnp.max(mom, axis=-1)))
    ms, wsc = mom / iscale[..., None], w / ws[..., None]
    c = _free_body_lanes()[0](_Vec(_cols(ms, 3)), _Vec(_cols(wsc, 3)))
    return FreeBodyMotion(ws, c, ms, wsc, q)


def free_body_omega_exact(moments: Any, omega0: Any, t: Any) -> Any:
    """Body angular velocity ``shape + t.shape + (3,)`` of the exact torque-free motion:
    ``free_body_exact(moments, omega0).omega(t)`` (:func:`free_body_exact`, theory §10:
    ``w_i = a_i dn(u)``, ``w_m = a_m sn(u)``, ``w_j = a_j cn(u)``, ``u = lam t + u0``).
    Its two halves are compiled separately, as :func:`free_body_state_exact`'s (the
    constants, then the evaluation at ``t``: programs that :func:`free_body_exact`'s
    ``omega`` shares; one program for both took 2-3 times as long to compile); wrap it
    in ``jax.jit`` inside a larger function as usual.

    >>> w = free_body_omega_exact(jnp.array([1.0, 2, 3]), jnp.array([0.0, 0, 1]),
    ...                           jnp.array([0.0, 1.0]))
    >>> w[-1].tolist()                     # a steady spin about a principal axis
    [0.0, 0.0, 1.0]
    """
    return free_body_exact(moments, omega0).omega(t)


def free_body_state_exact(moments: Any, omega0: Any, q0: Any, t: Any) -> tuple[Any, Any]:
    """``(omega, q)`` of the exact torque-free motion, shapes ``shape + t.shape + (3,)``
    and ``(4,)``: ``free_body_exact(moments, omega0, q0).state(t)`` (theory §10;
    :meth:`FreeBodyMotion.attitude` for the formula; ``q`` body -> space, scalar
    first, ``q(0) = q0``). Its two halves are compiled separately (the constants, then
    the evaluation at ``t``; compiled as one program they took 2.6 times as
    long); wrap it in ``jax.jit`` inside a larger function as usual.

    >>> w, q = free_body_state_exact(jnp.array([1.0, 2, 3]), jnp.array([0.0, 0, 1]),
    ...                              jnp.array([1.0, 0, 0, 0]), jnp.linspace(0.0, jnp.pi, 5))
    >>> q[::4].round(12).tolist()          # t = 0 and pi: half a turn about the spin axis z
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    """
    return free_body_exact(moments, omega0, q0).state(t)
