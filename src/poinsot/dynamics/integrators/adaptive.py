"""SciPy's ``solve_ivp`` on (L, w) with the quaternion renormalised at the outputs
(theory §5, §10): the reference (``solver``: DOP853 by default)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._typing import FloatArray
from ...errors import IntegrationError, InvalidInputError
from ._common import (
    RigidIntegrator,
    RigidProblem,
    RunOptions,
    _normalize,
    batch_rhs,
)

#: ``scipy.integrate.solve_ivp`` methods accepted by ``simulate(..., method="adaptive")``.
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _run_adaptive(
    p: RigidProblem, rtol: float, atol: float, solver: str
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    q, w, t, h_max = p.q, p.omega0, p.t, p.h_max
    from scipy.integrate import solve_ivp

    nb = q.shape[0]
    rhs = batch_rhs(p)

    def fun(tn: float, y: FloatArray) -> FloatArray:
        return rhs(tn, y.reshape(nb, 7)).ravel()

    y0 = np.concatenate([q, w], axis=1).ravel()
    n = t.shape[0]
    if n == 1:
        ys = y0[None]
        info = {"evaluations": 0, "solver": solver, "rtol": rtol, "atol": atol, "message": ""}
    else:
        try:
            sol = solve_ivp(
                fun,
                (t[0], t[-1]),
                y0,
                method=solver,
                t_eval=t,
                rtol=rtol,
                atol=atol,
                max_step=h_max,
            )
        except ValueError as exc:
            raise InvalidInputError(
                f"`solver`, `rtol` or `atol` rejected by solve_ivp: {exc}"
            ) from None
        if sol.status != 0 or sol.y.shape[1] != n or not np.all(np.isfinite(sol.y)):
            reached = float(sol.t[-1]) if sol.t.size else float(t[0])
            raise IntegrationError(
                f"adaptive integration ({solver}) failed after t = {reached:.6g}: "
                f"{sol.message} The state may have become non-finite (a stiff or diverging "
                f"problem): try method='midpoint' with a small `max_step`."
            )
        ys = sol.y.T
        info = {
            "evaluations": int(sol.nfev),
            "solver": solver,
            "rtol": rtol,
            "atol": atol,
            "message": sol.message,
        }
    ys = ys.reshape(n, nb, 7)
    return _normalize(ys[..., :4]), ys[..., 4:], info


class Adaptive(RigidIntegrator):
    """``method="adaptive"``."""

    name = "adaptive"

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        return _run_adaptive(p, o.rtol, o.atol, o.solver)
