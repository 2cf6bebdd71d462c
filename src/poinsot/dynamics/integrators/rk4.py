"""The classical Runge-Kutta method of order 4 on (L, w), the quaternion renormalised
after each step (theory §5, §10): one compiled loop per body with a built-in torque,
NumPy stages for a Python torque."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._typing import FloatArray
from ._common import (
    RigidIntegrator,
    RigidProblem,
    RunOptions,
    _fail_nonfinite,
    _fixed_step_info,
    _normalize,
    _pure,
    _qmul,
    _rhs,
    _stages,
    _substeps,
    _torque_value,
)


def _run_rk4_compiled(p: RigidProblem) -> tuple[Any, Any, Any]:
    """RK4 in one compiled loop per body (built-in torques); ``(None, None, None)``
    for a Python torque."""
    j, q, w, t, h_max, model, report = p.j, p.q, p.omega0, p.t, p.h_max, p.model, p.report
    from .. import _fused_run  # numba, loaded on first use

    nsub = _substeps(t, h_max)
    out = _fused_run.rk4(j, q, w, t, nsub, model, progress=report)
    if out is None:
        return None, None, None
    qs, ws, failed = out
    bad = np.flatnonzero(failed >= 0)
    if bad.size:
        k = int(failed[bad].min())
        raise _fail_nonfinite("rk4", float(t[k]), "the state")
    info = _fixed_step_info(t, nsub)
    info["path"] = "compiled"
    return qs, ws, info


def _run_rk4(p: RigidProblem) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    j, j_inv, q, w = p.j, p.j_inv, p.q, p.omega0
    t, h_max, m_const, tfn = p.t, p.h_max, p.m_const, p.tfn
    nsub = _substeps(t, h_max)
    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    Wo = np.empty((n,) + w.shape)
    Q[0], Wo[0] = q, w

    def f(tn: float, q: FloatArray, w: FloatArray) -> tuple[FloatArray, FloatArray]:
        mt = _torque_value(m_const, tfn, tn, q, w)
        return 0.5 * _qmul(q, _pure(w)), _rhs(j, j_inv, w, mt)

    for k, tn, h, last in _stages(t, nsub, (1.0,)):
        k1q, k1w = f(tn, q, w)
        k2q, k2w = f(tn + h / 2, q + h / 2 * k1q, w + h / 2 * k1w)
        k3q, k3w = f(tn + h / 2, q + h / 2 * k2q, w + h / 2 * k2w)
        k4q, k4w = f(tn + h, q + h * k3q, w + h * k3w)
        q = _normalize(q + h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q))
        w = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w)
        if last:
            if not np.all(np.isfinite(w)):
                raise _fail_nonfinite("rk4", float(t[k]), "the angular velocity")
            if not np.all(np.isfinite(q)):
                raise _fail_nonfinite("rk4", float(t[k]), "the attitude quaternion")
            Q[k + 1], Wo[k + 1] = q, w
    return Q, Wo, _fixed_step_info(t, nsub)


class RK4(RigidIntegrator):
    """``method="rk4"``."""

    name = "rk4"

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        qs, ws, info = _run_rk4_compiled(p)
        if qs is None:  # a Python torque: the NumPy stages, one batch step at a time
            qs, ws, info = _run_rk4(p)
            info["path"] = "NumPy (torque is a Python callable)"
        return qs, ws, info
