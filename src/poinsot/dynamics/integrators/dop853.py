"""poinsot's compiled DOP853 (Hairer's 8(5,3) pair) on Euler's equations with the attitude
(theory §10): one fused loop per body with its own step control, built-in torques inside
the loop, dense output at the output times; a Python torque takes SciPy's DOP853."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._typing import FloatArray
from ...errors import IntegrationError
from ._common import (
    RigidIntegrator,
    RigidProblem,
    RunOptions,
)
from .adaptive import _run_adaptive

#: Why a body of a compiled DOP853 batch failed (``info["failed"]`` with failures="mark").
FAILURE_REASONS = {
    1: "the step size fell below round-off",
    2: "it needed more than 10^6 steps",
    3: "the state became non-finite",
}


def _fused_info(
    fused: tuple[FloatArray, FloatArray, Any],
    tt: FloatArray,
    rtol: float,
    atol: float,
    *,
    mark: bool = False,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """Outputs and ``info`` of the compiled DOP853 run; raise if any body failed
    (``mark``: hold each failed body at its last finite state and name the reason)."""
    from .. import _fused

    qs, ws, stats = fused
    bad = np.flatnonzero(stats[:, 3] != _fused.OK)
    failed = None
    if bad.size and mark:
        failed = np.full(stats.shape[0], "", dtype=object)
        for b in bad:
            failed[b] = FAILURE_REASONS[int(stats[b, 3])]
            ok = np.isfinite(qs[:, b]).all(axis=-1) & np.isfinite(ws[:, b]).all(axis=-1)
            last = int(np.flatnonzero(ok)[-1]) if ok.any() else -1
            if last < 0:  # not even the start: the identity at rest stands in
                qs[:, b], ws[:, b] = (1.0, 0.0, 0.0, 0.0), 0.0
            else:
                qs[last + 1 :, b], ws[last + 1 :, b] = qs[last, b], ws[last, b]
    elif bad.size:
        first = int(bad[0])
        status = int(stats[first, 3])
        alive = np.flatnonzero(np.isfinite(ws[:, first, 0]))
        t_reached = float(tt[alive[-1]]) if alive.size else float(tt[0])
        if atol == 0.0 and status == _fused.STEP_TOO_SMALL:
            # the error scale atol + rtol |y| is 0 where a component is exactly 0
            hint = (
                "With `atol=0` a component that is exactly 0 (the identity's vector part, "
                "a zero rate) allows no error at all: give `atol > 0`."
            )
        else:
            hint = (
                "The problem may be stiff or diverging: loosen `rtol`, shorten the run, "
                "or check the torque."
            )
        raise IntegrationError(
            f"dop853 integration failed for {bad.size} of {stats.shape[0]} bodies (first: body "
            f"{first}): {FAILURE_REASONS[status]} after t = {t_reached:.6g}. {hint}"
        )
    info = {
        "steps": stats[:, 0].copy(),
        "rejected": stats[:, 1].copy(),
        "evaluations": int(stats[:, 2].sum()),
        "order": 8,
        "rtol": rtol,
        "atol": atol,
        "solver": "DOP853 (compiled, per-body step control)",
    }
    if failed is not None:
        info["failed"] = failed
    return qs, ws, info


class DOP853(RigidIntegrator):
    """``method="dop853"`` (the default of ``simulate`` when ``rtol`` or ``atol`` is given)."""

    name = "dop853"

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        from .. import _fused_run  # numba, loaded on first use

        fused = _fused_run.integrate(
            p.moments if p.principal else p.j,
            p.q,
            p.omega0,
            p.t,
            p.model,
            rtol=o.rtol,
            atol=o.atol,
            max_step=p.h_max,
            progress=p.report,
            diagonal=p.diagonal,
            principal=p.principal,
        )
        if fused is None:  # a Python torque: the slower, vectorised solve_ivp path
            qs, ws, info = _run_adaptive(p, o.rtol, o.atol, "DOP853")
            info["path"] = "solve_ivp DOP853 (torque is a Python callable)"
            return qs, ws, info
        return _fused_info(fused, p.t, o.rtol, o.atol, mark=o.failures == "mark")

    def unit_output(self, info: dict[str, Any]) -> bool:
        # the compiled loop returns unit quaternions (held, for a marked failure)
        return "path" not in info
