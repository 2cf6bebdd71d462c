"""The Python driver of the fused compiled kernels (private): from validated arrays to
a kernel call and back.

:mod:`._fused` holds the per-body kernels (DOP853, RK4, midpoint) and
:mod:`._fused_lanes` the lane-blocked DOP853 (eight bodies stepped together, SIMD
across bodies); this module flattens a problem for them (:func:`torque_kernel`,
:func:`_flat_problem`), chooses the kernel and runs it threaded with progress and
Ctrl-C (:func:`poinsot._progress.run_compiled`). Loading it loads numba (both kernel
modules): the integrators import it when they first run.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._jit import NUMBA, first_call, ready
from .._progress import run_compiled
from .._scratch import hold
from .._vec import all_diagonal3, diagonal3, inverse3
from ..rotations import Rotation
from ..rotations._lazy import threaded
from . import _fused_lanes
from . import torques as _tq
from ._fused import (
    DIAGONAL,
    KEPLER,
    NPAR,
    integrate_batch,
    integrate_serial,
    midpoint_batch,
    rk4_batch,
)
from .orbit import KeplerOrbit

#: Whether :func:`integrate` runs the lane-blocked kernels (:mod:`._fused_lanes`, the same
#: results bit for bit) rather than :func:`integrate_batch`'s one body per iteration;
#: the benchmarks and tests switch it to time and check one against the other.
LANES = True


def _kepler_par(torque):
    """Kind 6's parameters ``(n, e, M_0, sqrt(1 - e^2), p)`` (:mod:`._fused`) of an
    :class:`~poinsot.dynamics.OrbitGravityGradientTorque` on a
    :class:`~poinsot.dynamics.KeplerOrbit` of the same ``mu``, else ``None`` (another
    orbit, a subclass that may change the formulas, another ``mu``: the Python path).
    ``M_0 = M(epoch) - n epoch`` reduced to ``[-pi, pi)``; ``p`` the unit quaternion of
    the perifocal axes ``[P Q W]``."""
    orbit = torque.orbit
    if type(torque) is not _tq.OrbitGravityGradientTorque or type(orbit) is not KeplerOrbit:
        return None
    if torque.mu != orbit.mu:
        return None
    n = orbit.mean_motion
    m0 = math.remainder(orbit._mean0 - n * orbit.epoch, 2.0 * math.pi)
    m0 = -math.pi if m0 >= math.pi else m0
    p = Rotation.from_matrix(orbit.perifocal).as_quat()
    e = orbit.e
    return np.array([n, e, m0, math.sqrt((1.0 - e) * (1.0 + e)), *p])


def _same_inertia(torque, j, batch) -> bool:
    """Whether a gravity-gradient model's own inertia is the integrated body's ``J``
    (kind 6 takes ``J`` from the body; another inertia takes the Python path)."""
    mine = np.asarray(torque.inertia, dtype=float)
    try:
        return bool(
            np.array_equal(np.broadcast_to(mine, batch + (3, 3)), j.reshape(batch + (3, 3)))
        )
    except ValueError:
        return False


def torque_kernel(torque, batch: tuple[int, ...], par=None):
    """``(kind, par (batch + (NPAR,)))`` for a built-in torque model, else ``None``.

    ``None`` (no torque) is kind 0. A torque the kernel does not know (a Python
    callable) returns ``None``: the caller takes its slower path. ``par``: an array of
    that shape to fill (else a new one). Kind 6 (the orbit's gravity gradient) takes the
    body's inertia: the caller checks that it is the model's (:func:`_same_inertia`).
    """

    if par is None:
        par = np.zeros(batch + (NPAR,))
    else:
        par.fill(0.0)
    if torque is None:
        return 0, par
    if isinstance(torque, _tq.ConstantBodyTorque | _tq.ConstantSpaceTorque):
        par[..., :3] = torque.torque
        return (1 if isinstance(torque, _tq.ConstantBodyTorque) else 2), par
    if isinstance(torque, _tq.GravityTorque):
        par[..., 0] = 1.0
        par[..., 1:4] = torque.moment
        return 3, par
    if isinstance(torque, _tq.GyrostaticTorque):
        par[..., :3] = torque.h
        if torque.rate is not None:
            par[..., 3:6] = torque.rate
        return 5, par
    if isinstance(torque, _tq.OrbitGravityGradientTorque):
        kp = _kepler_par(torque)
        if kp is None:
            return None
        par[...] = kp
        return KEPLER, par
    gradient = getattr(_tq, "GravityGradientTorque", None)
    if gradient is not None and isinstance(torque, gradient):
        par[..., 0] = torque.coefficient
        par[..., 1:4] = torque.direction
        return 4, par
    return None


def _flat_problem(j, q0, omega0, torque, diagonal=None, scratch=None, principal=None):
    """``(batch, kind, par, J, J^-1, y0)`` flattened to ``N`` bodies, or ``None`` when
    the torque is not built in (``diagonal``: whether every ``J`` is, if known;
    ``scratch``: a :func:`poinsot._scratch.hold` block for the packed arrays, which then
    live as long as it; ``principal``: whether ``j`` holds principal moments (..., 3)
    rather than tensors, ``None``: from its shape)."""
    j = np.asarray(j, dtype=float)
    if j.shape[-2:] != (3, 3) if principal is None else principal:
        out = None if scratch is None else scratch.empty("j", j.shape[:-1] + (3, 3))
        j = diagonal3(j, out=out)
    batch = np.broadcast_shapes(j.shape[:-2], q0.shape[:-1], omega0.shape[:-1])
    n_body = int(np.prod(batch, dtype=np.int64))
    kp = torque_kernel(
        torque, batch, None if scratch is None else scratch.empty("par", batch + (NPAR,))
    )
    if kp is None:
        return None
    kind, par = kp
    jj = np.ascontiguousarray(np.broadcast_to(j, batch + (3, 3)).reshape(n_body, 3, 3))
    if kind == KEPLER and not _same_inertia(torque, jj, batch):
        return None
    if scratch is None:
        ji = inverse3(jj, diagonal)
        y0 = np.empty((n_body, 7))
    else:
        ji = inverse3(jj, diagonal, out=scratch.empty("ji", (n_body, 3, 3)))
        y0 = scratch.empty("y0", (n_body, 7))
    y0[:, :4] = np.broadcast_to(q0, batch + (4,)).reshape(n_body, 4)
    y0[:, 4:] = np.broadcast_to(omega0, batch + (3,)).reshape(n_body, 3)
    par = np.ascontiguousarray(par.reshape(n_body, NPAR))
    return batch, kind, par, jj, ji, y0


def _long(y0, t, steps=0):
    """Whether a run may last long enough (~> 10 ms) to be worth making interruptible by
    Ctrl-C (:func:`poinsot._progress.run_compiled`): many bodies times outputs, many
    fixed steps, or many turns (an adaptive step takes a fraction of a turn)."""
    w = y0[:, 4:]  # max |w| without a temporary |w| array
    w_max = max(float(w.max(initial=0.0)), -float(w.min(initial=0.0)))
    turns = w_max * float(t[-1] - t[0]) / (2.0 * np.pi)
    return y0.shape[0] * max(t.size, steps, 50.0 * turns) > 20_000


#: Interpreted seconds per body and step (the first-call estimate, :func:`poinsot._jit.
#: first_call`): a DOP853 step 0.5-0.8 ms measured, a fixed step of RK4 or the midpoint
#: rule less; taken high so that a long problem is compiled rather than interpreted.
_INTERPRETED_STEP_S = 1e-3


def _forced_steps(t, max_step):
    """The steps a ``max_step`` imposes over the span of ``t`` (0 with none), plus one
    an output interval may cut short."""
    if max_step is None or not t.size or not np.isfinite(max_step) or max_step <= 0:
        return 0.0
    return float(abs(t[-1] - t[0])) / float(max_step) + t.size


def _adaptive_seconds(y0, t, rtol, max_step=None):
    """Estimated interpreted seconds of DOP853 on ``y0``: ~3 steps per radian turned at
    rtol 1e-10 (measured 2.3-2.7 on free bodies and tops), times ``(1e-10/rtol)^(1/8)``
    (an 8th-order method's steps), and at least the steps ``max_step`` imposes (a
    Kovalevskaya top's 20 s at ``max_step = 5e-5``: 400,000 steps, not ~400)."""
    w = np.abs(y0[:, 4:]).max(axis=-1)
    span = float(abs(t[-1] - t[0])) if t.size else 0.0
    steps = 3.0 * (1e-10 / max(float(rtol), 1e-16)) ** 0.125 * w * span + 10.0 + t.size
    steps = np.maximum(steps, _forced_steps(t, max_step))
    return float(steps.sum()) * _INTERPRETED_STEP_S


def rk4(j, q0, w0, t, nsub, torque, progress=None):
    """Run the compiled RK4 on validated arrays (``nsub`` (n - 1,) steps per output
    interval). Returns ``(quat (n, ..., 4), omega (n, ..., 3), failed (...))`` with
    ``failed`` the first output interval whose end is non-finite (-1: none), or
    ``None`` when the torque is not built in."""
    flat = _flat_problem(j, q0, w0, torque)
    if flat is None:
        return None
    batch, kind, par, jj, ji, y0 = flat
    t = np.ascontiguousarray(t, dtype=float)
    oq = np.empty((t.size, y0.shape[0], 4))
    ow = np.empty((t.size, y0.shape[0], 3))
    failed = np.empty(y0.shape[0], dtype=np.int64)
    nsub = np.ascontiguousarray(nsub, dtype=np.int64)
    cancel = np.zeros(1, dtype=np.int64)
    done = np.zeros(y0.shape[0], dtype=np.int64)
    kernel = first_call(rk4_batch, y0.shape[0] * float(nsub.sum()) * _INTERPRETED_STEP_S)
    run_compiled(
        functools.partial(threaded, kernel),
        (y0, jj, ji, kind, par, t, nsub, oq, ow, failed, cancel, done),
        cancel=cancel,
        done=done,
        total=max(y0.shape[0] * (t.size - 1), 1),
        progress=progress,
        background=_long(y0, t, int(nsub.sum())),
    )
    return (
        oq.reshape((t.size,) + batch + (4,)),
        ow.reshape((t.size,) + batch + (3,)),
        failed.reshape(batch),
    )


def integrate(
    j,
    q0,
    omega0,
    t,
    torque,
    *,
    rtol,
    atol,
    max_step,
    max_steps=10**6,
    progress=None,
    diagonal=None,
    principal=None,
):
    """Run the fused kernel on validated arrays.

    ``j`` (..., 3, 3) inertia tensor (or (..., 3) principal moments) in body
    axes, ``q0`` (..., 4) unit quaternions, ``omega0`` (..., 3) rad/s, ``t`` (n,)
    increasing output times; ``torque`` ``None`` or a built-in model of
    :mod:`poinsot.dynamics.torques`; ``diagonal`` whether every ``j`` is diagonal, if
    the caller knows (``None``: checked here); ``principal`` whether ``j`` holds principal
    moments (``None``: from its shape, ambiguous for three bodies). Returns ``(quat (n,
    ..., 4), omega (n, ..., 3), stats (..., 4))`` or ``None`` when the torque is not built
    in.
    """
    j = np.asarray(j, dtype=float)
    if principal is None:
        principal = j.shape[-2:] != (3, 3)
    if diagonal is None:  # (moments (..., 3) are made diagonal tensors below)
        diagonal = True if principal else all_diagonal3(j)
    with hold() as scratch:
        flat = _flat_problem(j, q0, omega0, torque, diagonal, scratch, principal)
        return _integrate(flat, t, rtol, atol, max_step, max_steps, progress, diagonal, scratch)


def _integrate(flat, t, rtol, atol, max_step, max_steps, progress, diagonal, scratch):
    """:func:`integrate` on the flattened problem, inside its scratch block."""
    if flat is None:
        return None
    batch, kind, par, jj, ji, y0 = flat
    n_body = y0.shape[0]
    t = np.ascontiguousarray(t, dtype=float)
    oq = np.empty((t.size, n_body, 4))
    ow = np.empty((t.size, n_body, 3))
    stats = np.zeros((n_body, 4), dtype=np.int64)
    cancel = np.zeros(1, dtype=np.int64)
    done = scratch.zeros("done", (n_body,), dtype=np.int64)
    if kind in (0, 3) and diagonal:  # the lane kernel's diagonal forms
        kind += DIAGONAL
    seconds = _adaptive_seconds(y0, t, rtol, max_step)
    kernel = None
    if NUMBA and LANES and n_body >= _fused_lanes.L:  # L at a time, SIMD across bodies
        kernel = first_call(_fused_lanes.integrate_batch, seconds, _fused_lanes.compiled(kind))
        if getattr(kernel, "interpreted", False):  # its intrinsics (_borrow) run compiled
            kernel = None  # only: interpret the one-body kernel (the same operations)
        else:  # compiled (and cached) for this kind only
            kind = _fused_lanes.Kind(kind)
    if kernel is None:  # one body per loop iteration (and the NumPy executor, as Python)
        kernel = integrate_batch
        if n_body == 1 and not ready(integrate_batch):  # cold: no parallel region to compile
            kernel = integrate_serial
        kernel = first_call(kernel, seconds)
    run_compiled(
        functools.partial(threaded, kernel),
        (
            y0,
            jj,
            ji,
            kind,
            par,
            t,
            float(rtol),
            float(atol),
            float(np.inf if max_step is None else max_step),
            int(max_steps),
            oq,
            ow,
            stats,
            cancel,
            done,
        ),
        cancel=cancel,
        done=done,
        total=max(n_body * (t.size - 1), 1),
        progress=progress,
        background=_long(y0, t, _forced_steps(t, max_step)),
    )
    return (
        oq.reshape((t.size,) + batch + (4,)),
        ow.reshape((t.size,) + batch + (3,)),
        stats.reshape(batch + (4,)),
    )


def midpoint(j, j_inv, q, m, t, nsub, comp, torque, batch, progress=None):
    """Run the compiled midpoint rule on validated, flattened arrays (``j``, ``j_inv``
    (N, 3, 3), ``q`` (N, 4), ``m`` (N, 3) body momenta) under a built-in torque model
    given for the batch shape ``batch``. Returns ``(quat (n, N, 4), momentum (n, N, 3),
    res (N, 3))`` (see :func:`midpoint_batch`), or ``None`` when the torque is not built
    in."""
    kp = torque_kernel(torque, batch)
    if kp is None:
        return None
    kind, par = kp
    n_body = q.shape[0]
    jb = np.broadcast_to(j, (n_body, 3, 3))
    if kind == KEPLER and not _same_inertia(torque, jb, batch):
        return None
    par = np.ascontiguousarray(np.broadcast_to(par, batch + (NPAR,)).reshape(n_body, NPAR))
    t = np.ascontiguousarray(t, dtype=float)
    oq = np.empty((t.size, n_body, 4))
    om = np.empty((t.size, n_body, 3))
    res = np.empty((n_body, 3), dtype=np.int64)
    c = np.ascontiguousarray
    cancel = np.zeros(1, dtype=np.int64)
    done = np.zeros(n_body, dtype=np.int64)
    args = (
        c(q, dtype=float),
        c(m, dtype=float),
        c(np.broadcast_to(j, (n_body, 3, 3)), dtype=float),
        c(np.broadcast_to(j_inv, (n_body, 3, 3)), dtype=float),
        kind,
        par,
        t,
        c(nsub, dtype=np.int64),
        c(comp, dtype=float),
        oq,
        om,
        res,
        cancel,
        done,
    )
    steps = n_body * float(np.sum(nsub)) * len(comp)
    kernel = first_call(midpoint_batch, steps * _INTERPRETED_STEP_S)
    run_compiled(
        functools.partial(threaded, kernel),
        args,
        cancel=cancel,
        done=done,
        total=max(n_body * (t.size - 1), 1),
        progress=progress,
        background=n_body * int(np.sum(nsub)) * len(comp) > 20_000,
    )
    return oq, om, res
