"""The implicit midpoint rule (Lie-Poisson) on the body momentum, attitude by the Cayley
map of the midpoint angular velocity (theory §10): second order, composable to 4 and 6;
for the free body it keeps T, |K| and the space vector K to round-off."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..._jit import source
from ..._typing import FloatArray, IntArray
from ..._vec import cross as _cross
from ..._vec import hat as _hat
from ...errors import IntegrationError
from ._common import (
    RigidIntegrator,
    RigidProblem,
    RunOptions,
    _cayley_quat,
    _fail_nonfinite,
    _fixed_step_info,
    _kernel_args,
    _normalize,
    _qmul,
    _run_kernel,
    _stages,
    _substeps,
)


def _newton_done(rel: float, prev: float, it: int) -> int:
    """The stop rule of the compiled midpoint steps, run as plain Python here (no
    dispatch); its kernel module is loaded on first use (it imports numba)."""
    from ... import _numba_helpers

    return int(source(_numba_helpers.midpoint_newton_done)(rel, prev, it))


def _run_midpoint(p: RigidProblem) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    j, j_inv, q, w, t, h_max = p.j, p.j_inv, p.q, p.omega0, p.t, p.h_max
    comp, m_const, tfn, report = p.comp, p.m_const, p.tfn, p.report
    nsub = _substeps(t, h_max)
    m = np.einsum("...ij,...j->...i", j, w)
    info = _fixed_step_info(t, nsub, comp)
    if tfn is None:
        from .. import _euler_numba

        torque = np.zeros((1, 3)) if m_const is None else m_const
        args = _kernel_args(q, m, j_inv, torque, t, nsub, comp)
        Q, MO, status, body, k, it = _run_kernel(_euler_numba.midpoint, args, q, t, nsub, report)
        if status == 2:
            raise _fail_nonfinite("midpoint", float(t[k]), f"the state of body {body}")
        if status == 1:
            raise IntegrationError(
                f"midpoint integration failed: the implicit step did not converge after "
                f"t = {float(t[k]):.6g} (body {body}); reduce `max_step`."
            )
        info["max_newton_iterations"] = int(it)
    else:
        from .. import _fused_run  # numba, loaded on first use

        out = _fused_run.midpoint(j, j_inv, q, m, t, nsub, comp, tfn.model, tfn.batch, report)
        if out is None:  # a Python torque: the NumPy step, vectorised over the batch
            Q, MO, it = _midpoint_numpy(j_inv, q, m, t, nsub, comp, tfn)
            info["path"] = "NumPy (torque is a Python callable)"
        else:
            Q, MO, res = out
            failed = np.flatnonzero(res[:, 0] != 0)
            if failed.size:
                b = int(failed[0])
                status, k = int(res[b, 0]), int(res[b, 1])
                if status == 2:
                    raise _fail_nonfinite("midpoint", float(t[k]), f"the state of body {b}")
                raise IntegrationError(
                    f"midpoint integration failed: the implicit step did not converge after "
                    f"t = {float(t[k]):.6g} (body {b}; the torque's dependence on the state "
                    f"is too strong for the step): reduce `max_step`."
                )
            it = int(res[:, 2].max()) if res.shape[0] else 0
        info["max_newton_iterations"] = int(it)
    ws = np.einsum("...ij,...j->...i", j_inv, MO)
    return Q, ws, info


def _midpoint_numpy(
    j_inv: FloatArray,
    q: FloatArray,
    m: FloatArray,
    t: FloatArray,
    nsub: IntArray,
    comp: Sequence[float],
    tfn: Any,
) -> tuple[FloatArray, FloatArray, int]:
    """The midpoint step of :mod:`._euler_numba`, vectorised over the batch with NumPy,
    for a torque that is a Python function of ``(t, rotation, omega)``."""
    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    MO = np.empty((n,) + m.shape)
    Q[0], MO[0] = q, m
    worst = 0
    mt = None
    for k, tn, h, last in _stages(t, nsub, comp):
        q, m, mt, it = _midpoint_step_numpy(j_inv, q, m, tn, h, tfn, mt)
        worst = max(worst, it)
        if last:
            if not (np.all(np.isfinite(m)) and np.all(np.isfinite(q))):
                raise _fail_nonfinite("midpoint", float(t[k]), "the angular momentum")
            Q[k + 1], MO[k + 1] = q, m
    return Q, MO, worst


def _midpoint_step_numpy(
    j_inv: FloatArray,
    q: FloatArray,
    m: FloatArray,
    tn: float,
    h: float,
    tfn: Any,
    mt: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, int]:
    """One midpoint step ``(q, m) -> (q+, m+)`` of length ``h`` from ``tn`` (see simulate).

    ``mt`` (the previous step's midpoint torque) seeds the first guess; returns
    ``(q+, m+, midpoint torque, Newton iterations)``.
    """
    eye = np.eye(3)
    h2 = 0.5 * h
    w = np.einsum("...ij,...j->...i", j_inv, m)
    if mt is None:
        mt = tfn(tn, q, w)
    x = m + h2 * (_cross(m, w) + mt)
    prev = math.inf
    it = 0
    while True:
        it += 1
        w = np.einsum("...ij,...j->...i", j_inv, x)
        # midpoint attitude: half of the step's rotation, L_n o sqrt(cay(a)), a = h w / 2,
        # whose Gibbs vector is a / (1 + sqrt(1 + a.a)): symmetric in n <-> n + 1
        a = h2 * w
        b = a / (1.0 + np.sqrt(1.0 + np.einsum("...i,...i->...", a, a)))[..., None]
        mt = tfn(tn + h2, _qmul(q, _cayley_quat(b)), w)
        r = x - m - h2 * (_cross(x, w) + mt)
        jac = eye - h2 * (_hat(x) @ j_inv - _hat(w))
        dx = np.linalg.solve(jac, r[..., None])[..., 0]
        x = x - dx
        num, den = np.abs(dx).max(-1), np.abs(x).max(-1)
        rel = float(np.max(np.where(num == 0.0, 0.0, num / np.where(den == 0.0, 1.0, den))))
        stop = _newton_done(rel, prev, it)  # the compiled paths' own rule
        if stop > 0:
            break
        if stop < 0:  # too slow, or diverging
            raise IntegrationError(
                f"midpoint integration failed: the implicit step did not converge at "
                f"t = {tn:.6g} (the torque's dependence on the state is too strong "
                f"for the step): reduce `max_step`."
            )
        prev = rel
    w = np.einsum("...ij,...j->...i", j_inv, x)
    a = h2 * w
    u = m - _cross(a, m) + h * mt
    au = np.einsum("...i,...i->...", a, u)[..., None]
    m = (u - _cross(a, u) + au * a) / (1.0 + np.einsum("...i,...i->...", a, a))[..., None]
    q = _normalize(_qmul(q, _cayley_quat(a)))
    return q, m, mt, it


class Midpoint(RigidIntegrator):
    """``method="midpoint"``: compiled for no torque, a constant body torque or a built-in
    torque (:mod:`poinsot.dynamics.torques`), NumPy steps for a Python torque."""

    name = "midpoint"

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        return _run_midpoint(p)
