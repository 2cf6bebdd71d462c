"""Lie-Poisson splitting of the free-body Hamiltonian with the torque as kicks (theory
§10; Dullweber, Leimkuhler & McLachlan 1997): second order, composable; keeps |K| and
the space vector K to round-off, exact for a symmetric body."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._typing import FloatArray
from ...mass import principal_axes
from ..torques import GravityTorque
from ._common import (
    RigidIntegrator,
    RigidProblem,
    RunOptions,
    _axis_quat,
    _fail_nonfinite,
    _fixed_step_info,
    _kernel_args,
    _normalize,
    _qmul,
    _qrot,
    _rotvec_quat,
    _run_kernel,
    _stages,
    _substeps,
)


def _run_splitting(
    p: RigidProblem, tfn: Any, gravity: Any = None
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """Strang splitting of the free-body Hamiltonian, with the torque as kicks.

    In principal axes (moments ``I0 <= I1 <= I2``) write
    ``H = |m|^2 / (2 I1) + c0 m0^2 / 2 + c2 m2^2 / 2``, ``c_i = 1/I_i - 1/I1``
    (Dullweber, Leimkuhler & McLachlan 1997). Each part has an exact flow: the
    first turns the body about the constant ``m`` by ``h |m| / I1``; the others
    turn ``m`` by ``-theta`` and the body by ``+theta`` about axis ``i``,
    ``theta = h c_i m_i``. Every flow keeps ``K_s = L m L~`` and ``|m|``; for a
    symmetric body one of ``c0, c2`` vanishes and the composition is exact.
    Step: kick h/2, F0 h/2, F2 h/2, F_iso h, F2 h/2, F0 h/2, kick h/2.
    ``gravity`` (N, 3), optional: ``m g c`` in body axes, a gravity torque about a
    fixed point given to the compiled stepper, whose kicks ``h gamma x (m g c)``
    (``gamma = R^T e_z`` frozen) are the exact flow of the potential.
    """
    j, q, w, t, h_max, comp = p.j, p.q, p.omega0, p.t, p.h_max, p.comp
    m_const: Any = p.m_const
    report = p.report

    nsub = _substeps(t, h_max)
    moments, rot = principal_axes(j)  # J_b = S diag(I) S^T, S = C_bp, I ascending
    s_bp = np.broadcast_to(np.asarray(rot.as_quat(), dtype=float), (q.shape[0], 4))
    s_pb = s_bp * np.array([1.0, -1.0, -1.0, -1.0])
    inv_i = np.broadcast_to(1.0 / moments, q.shape[:-1] + (3,))
    c_axis = inv_i - inv_i[:, 1:2]
    q_np = _qmul(q, s_bp)
    m = _qrot(s_pb, np.einsum("...ij,...j->...i", j, w))  # principal-axes momentum

    def kick(tn: float, q_np: FloatArray, m: FloatArray, dt: float) -> FloatArray:
        if m_const is None and tfn is None:
            return m
        if tfn is None:
            mt = m_const
        else:
            mt = tfn(tn, _qmul(q_np, s_pb), _qrot(s_bp, m * inv_i))
        return m + dt * _qrot(s_pb, mt)

    def axis_flow(
        q_np: FloatArray, m: FloatArray, i: int, dt: float
    ) -> tuple[FloatArray, FloatArray]:
        theta = dt * c_axis[:, i] * m[:, i]
        a, b = (i + 1) % 3, (i + 2) % 3
        c, s = np.cos(theta), np.sin(theta)
        ma, mb = m[:, a], m[:, b]
        m = m.copy()
        m[:, a] = c * ma + s * mb
        m[:, b] = c * mb - s * ma
        return _qmul(q_np, _axis_quat(theta, i)), m

    def iso_flow(q_np: FloatArray, m: FloatArray, dt: float) -> FloatArray:
        return _qmul(q_np, _rotvec_quat(dt * inv_i[:, 1:2] * m))

    if tfn is None:
        from .. import _euler_numba

        mt = np.zeros((1, 3)) if m_const is None else _qrot(s_pb, m_const)
        args: tuple[Any, ...] = _kernel_args(q_np, m, inv_i, mt, t, nsub, comp)
        grav = None if gravity is None else np.ascontiguousarray(_qrot(s_pb, gravity), dtype=float)
        Q, MO, status, body, k = _run_kernel(
            _euler_numba.splitting, args, q_np, t, nsub, report, grav
        )
        if status == 2:
            raise _fail_nonfinite("splitting", float(t[k]), f"the state of body {body}")
        return _qmul(Q, s_pb), _qrot(s_bp, MO * inv_i), _fixed_step_info(t, nsub, comp)

    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    Wo = np.empty((n,) + w.shape)
    Q[0], Wo[0] = q, w
    for k, tn, h, last in _stages(t, nsub, comp):
        m = kick(tn, q_np, m, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 0, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 2, 0.5 * h)
        q_np = iso_flow(q_np, m, h)
        q_np, m = axis_flow(q_np, m, 2, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 0, 0.5 * h)
        q_np = _normalize(q_np)
        m = kick(tn + h, q_np, m, 0.5 * h)
        if last:
            if not (np.all(np.isfinite(m)) and np.all(np.isfinite(q_np))):
                raise _fail_nonfinite("splitting", float(t[k]), "the angular momentum")
            Q[k + 1] = _qmul(q_np, s_pb)
            Wo[k + 1] = _qrot(s_bp, m * inv_i)
    return Q, Wo, _fixed_step_info(t, nsub, comp)


class Splitting(RigidIntegrator):
    """``method="splitting"``: compiled for no torque, a constant body torque or gravity
    about a fixed point (exact kicks); NumPy steps for another torque."""

    name = "splitting"

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        model = p.model
        if isinstance(model, GravityTorque) and model.moment.shape[:-1] in ((), p.batch):
            # gravity about a fixed point: exact kicks inside the compiled stepper
            grav = np.broadcast_to(model.moment, p.batch + (3,)).reshape(p.q.shape[0], 3)
            return _run_splitting(p, None, grav)
        return _run_splitting(p, p.tfn)
