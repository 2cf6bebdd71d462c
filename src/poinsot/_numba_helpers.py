"""Scalar ``@njit`` helpers shared by the compiled kernels: one place for each formula.

Every helper works on scalars and returns a tuple, and is compiled with
``inline="always"``, so a kernel that calls it runs exactly the code it would
run if the formula were written in place (no call, no allocation). Kernel modules
import this module and declare it with :func:`poinsot._numba_cache.depends_on`,
so that editing a helper invalidates their on-disk caches (see
``docs/conventions.md``, "Compiled kernels").

Formulas (theory §1, §5, §10):

- :func:`qmul` Hamilton product ``P o Q = (p0 q0 - p.q, p0 q + q0 p + p x q)``
  (from :mod:`poinsot.rotations._scalar`, whose plain-Python formulas also serve
  the one-rotation short paths);
- :func:`qmul_gibbs` ``L o (1, a)`` (unnormalised Cayley step);
- :func:`qnormalize` ``L / |L|``;
- :func:`qaxis` ``L o (c, s e_i)``: a turn about body axis ``i`` given ``cos``
  and ``sin`` of the half angle;
- :func:`qrot` ``R v`` (body -> space components) for a unit ``L``;
- :func:`qrot_inverse` ``R^T v`` (space -> body components) for any non-zero ``L``;
- :func:`kepler` the eccentric anomaly of Kepler's equation ``E - e sin E = M`` with
  ``cos E``, ``sin E`` (Newton; the NumPy twin is ``poinsot.dynamics.orbit._solve_kepler``);
- :func:`cross` ``a x b``; :func:`matvec` ``W x`` for a 3x3 matrix given by rows;
- :func:`vertical` ``|L|^2 R^T e_z``, the third row of ``R(L)`` times ``|L|^2``;
- :func:`gravity_kick` ``m + h gamma x (m g c)``, the exact gravity kick about a
  fixed point with the attitude frozen (``gamma = R^T e_z``);
- :func:`fma` ``a b + c`` rounded once (the hardware's fused multiply-add);
- :func:`euler_momentum_rate` Euler's equations in momentum form,
  ``dm/dt = m x W m + M`` (``m = J w`` body momentum, ``W = J^-1``, ``M``
  the body torque).

Importing this module imports numba: only kernel modules (imported lazily) do.
"""

from __future__ import annotations

import math
from typing import Any

from ._jit import NUMBA, njit, twin
from .rotations import _scalar as _S

#: Files these helpers are built from: :func:`poinsot._numba_cache.depends_on` adds
#: them to the cache stamp of every kernel that declares this module.
DEPENDS = (_S,)

__all__ = [
    "qmul",
    "qmul_gibbs",
    "qnormalize",
    "qaxis",
    "qrot",
    "qrot_inverse",
    "kepler",
    "KEPLER_MAXIT",
    "cross",
    "matvec",
    "euler_momentum_rate",
    "fma",
    "store_nt",
    "fence",
    "prefetch",
    "cancelled",
    "gravity_kick",
    "vertical",
    "midpoint_newton_step",
    "midpoint_newton_done",
    "midpoint_momentum",
    "MIDPOINT_MAXIT",
]

# typed Any: numba's stubs want literal option values, a plain dict[str, str] matches none
_INLINE: dict[str, Any] = {"inline": "always"}


# the plain-Python forms of the intrinsics below (NumPy executor, and the interpreter's
# first calls: poinsot._jit.first_call): one rounding more than the compiled fma


def _fma_numpy(a: Any, b: Any, c: Any) -> Any:
    return a * b + c


def _store_numpy(a: Any, i: Any, v: Any) -> None:
    a[i] = v


def _fence_numpy() -> None:
    pass


def _prefetch_numpy(a: Any, i: Any) -> None:
    pass


def _cancelled_numpy(a: Any) -> bool:
    return bool(a[0] != 0)


fma: Any
store_nt: Any
fence: Any
prefetch: Any
cancelled: Any
if NUMBA:
    from llvmlite import ir
    from numba.core import types
    from numba.extending import intrinsic

    @intrinsic
    def _fma(typingctx, a, b, c):  # pragma: no cover - compiled
        """``a b + c`` rounded once: ``llvm.fma``, which LLVM vectorises (``vfmadd``) and
        which is correctly rounded on every CPU (a libm call where the CPU has no FMA), so
        the scalar and the lane kernels that both use it agree bit for bit."""
        sig = types.float64(types.float64, types.float64, types.float64)

        def codegen(context, builder, signature, args):
            f64 = ir.DoubleType()
            fnty = ir.FunctionType(f64, [f64, f64, f64])
            fn = builder.module.declare_intrinsic("llvm.fma", [f64], fnty)
            return builder.call(fn, list(args))

        return sig, codegen

    fma = _fma

    class _VolatileStore(ir.StoreInstr):  # type: ignore[misc]
        """``store volatile`` (llvmlite's builder has no volatile store)."""

        def descr(self, buf: list[str]) -> None:
            super().descr(buf)
            buf[-1] = buf[-1].replace("store ", "store volatile ", 1)

    @intrinsic
    def _store_nt(typingctx, a, i, v):  # pragma: no cover - compiled
        """``a[i] = v`` (``a`` a 1-D C array, ``i`` in bounds, ``v`` cast to its dtype)
        as a streaming store: LLVM's ``!nontemporal`` store (``movnti`` on x86), which
        writes around the caches and skips reading the line first; consecutive stores
        fill whole lines in the write-combining buffers. Order them with :func:`fence`
        before another thread reads them.

        A float is stored as the integer of its bits (the same bytes): x86 has no
        streaming store of a float held in a vector register but AMD's ``movntsd``, and
        on Intel LLVM silently emitted a plain store instead. Mixed with streamed
        stores into the same lines (``conj_flat``: ``w`` kept, its three negations
        streamed as integers) the lines went back and forth between the caches and the
        write-combining buffers: 10^6 inverses took 600 ns per rotation instead of 5
        (Intel AVX-512 VM, measured); ``from_matrix_flat`` and ``to_matrix_flat``,
        whose stores were all plain there, read every line of their result first."""
        sig = types.void(a, i, v)

        def codegen(context, builder, signature, args):
            from numba.core import cgutils

            arrty = signature.args[0]
            ary = context.make_array(arrty)(context, builder, value=args[0])
            ptr = cgutils.get_item_pointer(
                context, builder, arrty, ary, [args[1]], wraparound=False, boundscheck=False
            )
            value = context.cast(builder, args[2], signature.args[2], arrty.dtype)
            if isinstance(value.type, (ir.DoubleType, ir.FloatType)):
                bits = ir.IntType(64 if isinstance(value.type, ir.DoubleType) else 32)
                value = builder.bitcast(value, bits)
                ptr = builder.bitcast(ptr, bits.as_pointer())
                # volatile: else LLVM folds the cast back into a store of the float
                store = _VolatileStore(builder.block, value, ptr)
                store.align = None
                builder._insert(store)
            else:
                store = builder.store(value, ptr)
            one = builder.module.add_metadata([ir.Constant(ir.IntType(32), 1)])
            store.set_metadata("nontemporal", one)
            return context.get_dummy_value()

        return sig, codegen

    @intrinsic
    def _fence(typingctx):  # pragma: no cover - compiled
        """A full memory fence (``mfence``): streaming stores before it are visible to
        every thread after it."""

        def codegen(context, builder, signature, args):
            builder.fence("seq_cst")
            return context.get_dummy_value()

        return types.void(), codegen

    @intrinsic
    def _prefetch(typingctx, a, i):  # pragma: no cover - compiled
        """Ask for the cache line of ``a[i]`` (``a`` a 1-D C array; ``i`` may be out of
        bounds: a prefetch never faults): ``llvm.prefetch`` (``prefetcht0`` on x86). It
        changes no value, only when a later load finds its line in the caches."""
        sig = types.void(a, i)

        def codegen(context, builder, signature, args):
            from numba.core import cgutils

            arrty = signature.args[0]
            ary = context.make_array(arrty)(context, builder, value=args[0])
            ptr = cgutils.get_item_pointer(
                context, builder, arrty, ary, [args[1]], wraparound=False, boundscheck=False
            )
            i8p, i32 = ir.IntType(8).as_pointer(), ir.IntType(32)
            fnty = ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32])
            fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0")
            # read, keep in every cache level, data (not instruction) cache
            flags = [ir.Constant(i32, 0), ir.Constant(i32, 3), ir.Constant(i32, 1)]
            builder.call(fn, [builder.bitcast(ptr, i8p), *flags])
            return context.get_dummy_value()

        return sig, codegen

    @intrinsic
    def _cancelled(typingctx, a):  # pragma: no cover - compiled
        """``a[0] != 0`` (``a`` a 1-D int64 C array) read anew at every call: an atomic
        (acquire) load, a plain ``mov`` on x86. The flag is set by a signal handler or
        another thread, which the kernel cannot see: a plain ``cancel[0]`` may be
        hoisted out of a loop that never writes it, and a minute-long step loop then
        ignored Ctrl-C until its output interval ended (issue 38)."""
        sig = types.boolean(a)

        def codegen(context, builder, signature, args):
            from numba.core import cgutils

            arrty = signature.args[0]
            ary = context.make_array(arrty)(context, builder, value=args[0])
            ptr = cgutils.get_item_pointer(
                context, builder, arrty, ary, [ir.Constant(ir.IntType(64), 0)],
                wraparound=False, boundscheck=False,
            )  # fmt: skip
            value = builder.load_atomic(ptr, "acquire", 8)
            return builder.icmp_signed("!=", value, ir.Constant(value.type, 0))

        return sig, codegen

    store_nt = _store_nt
    fence = _fence
    prefetch = _prefetch
    cancelled = _cancelled
    for compiled, plain in (
        (_fma, _fma_numpy),
        (_store_nt, _store_numpy),
        (_fence, _fence_numpy),
        (_prefetch, _prefetch_numpy),
        (_cancelled, _cancelled_numpy),
    ):
        twin(compiled, plain)  # what the plain-Python executor runs in their place
else:  # the NumPy executor: one rounding more (its results are not numba's bit for bit)
    fma = _fma_numpy
    cancelled = _cancelled_numpy
    store_nt = _store_numpy
    fence = _fence_numpy
    prefetch = _prefetch_numpy


#: ``P o Q = (p0 q0 - p.q, p0 q + q0 p + p x q)`` (theory §1): the plain-Python
#: :func:`poinsot.rotations._scalar.hamilton`, compiled inline (one formula, one place).
qmul = njit(**_INLINE)(_S.hamilton)


@njit(**_INLINE)
def qmul_gibbs(q0, q1, q2, q3, a0, a1, a2):  # pragma: no cover - compiled
    """``L o (1, a)``: the (unnormalised) Cayley step with Gibbs vector ``a``."""
    return qmul(q0, q1, q2, q3, 1.0, a0, a1, a2)


@njit(**_INLINE)
def qnormalize(q0, q1, q2, q3):  # pragma: no cover - compiled
    """``L / |L|`` for a non-zero ``L``."""
    s = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return q0 * s, q1 * s, q2 * s, q3 * s


@njit(**_INLINE)
def qaxis(q0, q1, q2, q3, c, s, i):  # pragma: no cover - compiled
    """``L o (c, s e_i)``, ``c, s = cos(f/2), sin(f/2)``: turn by ``f`` about body axis ``i``."""
    if i == 0:
        return qmul(q0, q1, q2, q3, c, s, 0.0, 0.0)
    if i == 1:
        return qmul(q0, q1, q2, q3, c, 0.0, s, 0.0)
    return qmul(q0, q1, q2, q3, c, 0.0, 0.0, s)


_rotate = njit(**_INLINE)(_S.rotate)
#: ``R v = L o (0, v) o L~``: space components of the body vector ``v`` for a unit ``L``
#: (scaled by ``|L|^2`` otherwise; :func:`poinsot.rotations._scalar.rotate`)
qrot = _rotate

#: Most Newton iterations of :func:`kepler` (from ``M + e sin M`` it takes 2 at
#: ``e = 0.01``, at most 4 at 0.5, 7 at 0.95 and 9 at 0.99, over 20001 ``M`` in
#: [-pi, pi), measured).
KEPLER_MAXIT = 50


@njit(**_INLINE)
def kepler(mean, e):  # pragma: no cover - compiled
    """``(E, cos E, sin E)`` with ``E - e sin E = M`` (Kepler's equation, theory §10.2),
    for ``M`` in ``[-pi, pi)`` and ``0 <= e < 1``: one body's scalar solve inside the
    compiled torque of an orbit (kind 6 of :mod:`poinsot.dynamics._fused`). The NumPy
    solve of :class:`poinsot.dynamics.KeplerOrbit` (``orbit._solve_kepler``, vectorised,
    Danby's start) is its twin; they agree to a few ulp (tested).

    Newton from ``E = M + e sin M``. A step ``d`` leaves an error of about
    ``e |sin E| d^2 / (2 (1 - e cos E))`` (the quadratic term); once that is below
    ``1e-17`` and ``|d| <= 1e-6``, the last step is taken and ``cos E``, ``sin E`` are
    carried to the new ``E`` by their Taylor series to second order (error ``d^3 / 6``)
    instead of two more library calls: 2 sine-cosine pairs at ``e = 0.01`` rather than
    3. ``e = 0`` returns at once; at most :data:`KEPLER_MAXIT` steps.

    >>> import math
    >>> from poinsot._numba_helpers import kepler
    >>> E, c, s = kepler(1.0, 0.5)  # E - e sin E = M (docs/theory.md §10.2)
    >>> abs(E - 0.5 * math.sin(E) - 1.0) < 1e-15, abs(c - math.cos(E)) < 1e-15
    (True, True)
    """
    if e == 0.0:
        return mean, math.cos(mean), math.sin(mean)
    E = mean + e * math.sin(mean)
    c, s = math.cos(E), math.sin(E)
    for _ in range(KEPLER_MAXIT):
        g = 1.0 - e * c
        d = (E - e * s - mean) / g
        E -= d
        if abs(d) <= 1e-6 and e * abs(s) * d * d <= 2e-17 * g:
            h = 1.0 - 0.5 * d * d  # cos d, sin d = d to O(d^3)
            c, s = c * h + s * d, s * h - c * d
            break
        c, s = math.cos(E), math.sin(E)
    return E, c, s


@njit(**_INLINE)
def qrot_inverse(q0, q1, q2, q3, v0, v1, v2):  # pragma: no cover - compiled
    """``R^T v = L~ o (0, v) o L / |L|^2``: body components of the space vector ``v``
    (the sandwich of :func:`poinsot.rotations._scalar.rotate` with ``L~``; theory §2)."""
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    a, b, c = _rotate(q0, -q1, -q2, -q3, v0, v1, v2)
    return a / n2, b / n2, c / n2


@njit(**_INLINE)
def cross(a0, a1, a2, b0, b1, b2):  # pragma: no cover - compiled
    """``a x b``."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(**_INLINE)
def matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, x0, x1, x2):  # pragma: no cover
    """``W x`` for the 3x3 matrix with rows ``(w00, w01, w02)``..."""
    return (
        w00 * x0 + w01 * x1 + w02 * x2,
        w10 * x0 + w11 * x1 + w12 * x2,
        w20 * x0 + w21 * x1 + w22 * x2,
    )


#: ``|L|^2 R^T e_z``, the third row of ``R(L)`` times ``|L|^2``: the upward vertical in
#: body axes for a unit ``L``; :func:`qrot_inverse` of ``e_z`` without its products with
#: zero (the formula of :func:`poinsot.rotations._scalar.vertical`)
vertical = njit(**_INLINE)(_S.vertical)


@njit(**_INLINE)
def gravity_kick(q0, q1, q2, q3, m0, m1, m2, g0, g1, g2, h):  # pragma: no cover - compiled
    """``m + h gamma x G`` with ``gamma = R^T e_z`` (third row of ``R(L)``), ``G = m g c``.

    The exact flow over ``h`` of the gravity potential ``V = G . gamma`` about a fixed
    point (theory §10): the attitude, hence ``gamma``, is frozen during the kick.
    """
    y0, y1, y2 = vertical(q0, q1, q2, q3)
    c0, c1, c2 = cross(y0, y1, y2, g0, g1, g2)
    return m0 + h * c0, m1 + h * c1, m2 + h * c2


@njit(**_INLINE)
def euler_momentum_rate(m0, m1, m2, o0, o1, o2, t0, t1, t2):  # pragma: no cover - compiled
    """Euler's equations for the body momentum: ``dm/dt = m x w + M`` with ``w = W m``.

    Same as ``J w' = M - w x J w`` (theory §10); ``o`` is ``w = W m``, ``t`` is ``M``.
    """
    c0, c1, c2 = cross(m0, m1, m2, o0, o1, o2)
    return c0 + t0, c1 + t1, c2 + t2


@njit(**_INLINE)
def midpoint_newton_step(
    x0, x1, x2, o0, o1, o2, w00, w01, w02, w10, w11, w12, w20, w21, w22, h2, r0, r1, r2
):  # pragma: no cover - compiled
    """Newton's update ``d = Jac^-1 r`` for the midpoint momentum ``x`` of the implicit
    Lie-Poisson midpoint rule, residual ``r = x - m - h/2 (x x W x + M)`` (theory §10):
    ``Jac = E - h/2 (x^ W - (W x)^)`` (the torque held), ``o = W x``, ``h2 = h/2``;
    solved by cofactors."""
    a00 = 1.0 - h2 * (-x2 * w10 + x1 * w20)
    a01 = -h2 * (-x2 * w11 + x1 * w21) - h2 * o2
    a02 = -h2 * (-x2 * w12 + x1 * w22) + h2 * o1
    a10 = -h2 * (x2 * w00 - x0 * w20) + h2 * o2
    a11 = 1.0 - h2 * (x2 * w01 - x0 * w21)
    a12 = -h2 * (x2 * w02 - x0 * w22) - h2 * o0
    a20 = -h2 * (-x1 * w00 + x0 * w10) - h2 * o1
    a21 = -h2 * (-x1 * w01 + x0 * w11) + h2 * o0
    a22 = 1.0 - h2 * (-x1 * w02 + x0 * w12)
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    det = a00 * c00 + a01 * c01 + a02 * c02
    c10 = a02 * a21 - a01 * a22
    c20 = a01 * a12 - a02 * a11
    d0 = (c00 * r0 + c10 * r1 + c20 * r2) / det
    c11 = a00 * a22 - a02 * a20
    c21 = a02 * a10 - a00 * a12
    d1 = (c01 * r0 + c11 * r1 + c21 * r2) / det
    c12 = a01 * a20 - a00 * a21
    c22 = a00 * a11 - a01 * a10
    d2 = (c02 * r0 + c12 * r1 + c22 * r2) / det
    return d0, d1, d2


#: The most Newton iterations of one implicit midpoint step before it is declared failed.
MIDPOINT_MAXIT = 100
_EPS = 2.220446049250313e-16


@njit(**_INLINE)
def midpoint_newton_done(rel, prev, it):  # pragma: no cover - compiled
    """The stop rule of the midpoint rule's Newton iteration (every path: compiled and
    NumPy): ``1`` converged, ``-1`` failed, ``0`` go on. ``rel`` is the update relative
    to the iterate (``max |dx| / max |x|``), ``prev`` the previous one, ``it`` the
    iterations done. Converged at round-off, or when the next update is predicted below
    round-off (``rel^2 / prev``: valid for linear and quadratic convergence), or when
    stagnating at ``<= 1e-12``; failed after :data:`MIDPOINT_MAXIT` iterations or when
    the update does not shrink below the iterate (diverging)."""
    if rel <= 2.0 * _EPS or (it >= 2 and (rel * rel <= _EPS * prev or 1e-12 >= rel >= prev / 2)):
        return 1
    if it >= MIDPOINT_MAXIT or not rel < 1.0:
        return -1
    return 0


@njit(**_INLINE)
def midpoint_momentum(m0, m1, m2, a0, a1, a2, h, t0, t1, t2):  # pragma: no cover - compiled
    """``m+ = (E + a^)^-1 ((E - a^) m + h M*)`` of the midpoint rule, ``a = h w* / 2`` the
    Gibbs vector of the step, ``M*`` the midpoint torque (theory §10): an exact rotation
    of ``m`` when ``M* = 0``."""
    aa = 1.0 + a0 * a0 + a1 * a1 + a2 * a2
    c0, c1, c2 = cross(a0, a1, a2, m0, m1, m2)
    u0 = m0 - c0 + h * t0
    u1 = m1 - c1 + h * t1
    u2 = m2 - c2 + h * t2
    au = a0 * u0 + a1 * u1 + a2 * u2
    c0, c1, c2 = cross(a0, a1, a2, u0, u1, u2)
    return (u0 - c0 + au * a0) / aa, (u1 - c1 + au * a1) / aa, (u2 - c2 + au * a2) / aa
