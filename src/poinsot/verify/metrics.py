"""Errors, drifts, event phases and the verdict of ``poinsot verify`` (docs/verify.md).

For a rigid body: the geodesic attitude error ``|log(R_exact^-1 R)|`` (rad, the
angle of the rotation between the two attitudes, docs/theory.md §4) and the
angular-velocity error ``|w - w_exact|`` relative to the largest ``|w_exact|``; for a
point: ``|r - r_exact|`` and ``|v - v_exact|`` relative to the largest exact
magnitudes. The drift of each first integral is ``max |I(t) - I(0)|`` relative to
``|I(0)|`` (the energy ``T + V``, the angular momentum ``K`` in space axes for a free
body, its vertical component ``K_z`` relative to ``|K|`` for a top; ``E`` and
``L`` for an orbit; the Jacobi integral in the turning frame; for the cases of
version 2: the energy and ``K_z`` of the Kovalevskaya top, the energy and
``K = R (J w + h)`` of the gyrostat, the transverse kinetic energy under a
constant axial body torque, the orbit frame's Jacobi integral of the pitch
libration). An attitude estimate (the ``estimation`` cases, version 4) is scored by its
group (:meth:`poinsot.verify.groups.Estimation.score`): the attitude error over the
run's second half (largest and RMS), the bias error at the end, and the time-averaged
NEES, which passes within a two-sided band (``thresholds["nees_min"]`` to
``thresholds["nees"]``). Events are the
times a signal crosses a level (flips, nutation, apsides, swings), found by
linear interpolation on the case's grid for both runs alike; their error is the
largest time difference of matching crossings (a missing or extra crossing is an
infinite error).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._drift import relative_drift
from .._quat import attitude_distance
from ..trajectory import Result, compare
from .cases import Case
from .groups import Estimate, _deprecated_states, as_result

#: metric name -> (units, what it measures)
METRICS: dict[str, tuple[str, str]] = {
    "attitude": ("rad", "largest geodesic attitude error |log(R_exact^-1 R)|"),
    "omega": ("1", "largest |w - w_exact| / max |w_exact| (body axes)"),
    "position": ("1", "largest |r - r_exact| / max |r_exact|"),
    "velocity": ("1", "largest |v - v_exact| / max |v_exact|"),
    "energy": (
        "1",
        "relative drift of the energy (Jacobi integral in a turning frame; "
        "transverse kinetic energy under an axial body torque)",
    ),
    "momentum": ("1", "relative drift of the angular momentum (K_z for a top, relative to |K|)"),
    "events": ("s", "largest time error of the characteristic events"),
    "attitude_rms": ("rad", "RMS attitude error of an estimate over the run's second half"),
    "bias": ("rad/s", "|b - b_exact| of an estimate's gyro bias at the end of the run"),
    "nees": (
        "1",
        "time-averaged NEES sum_i (e_i / s_i)^2 of an estimate's attitude error (3 dof); "
        "passes within [nees_min, nees], chi-square 3 dof two-sided 95 %",
    ),
}


@dataclass
class CaseResult:
    """The check of one case by one engine.

    Attributes
    ----------
    case : str
    group : str
    status : {"pass", "fail", "skip", "missing"}
        ``"skip"``: the case is outside what the engine models (e.g. an orbit in
        MuJoCo's rigid-body adapter); ``"missing"``: the engine should have given
        the states and did not (e.g. no file).
    reason : str
        Why a case failed (the metrics over their thresholds, or a defect of the
        states), was skipped or is missing.
    metrics : dict
        ``name -> {"value", "threshold", "units", "passed"}`` (see :data:`METRICS`).
    errors : dict
        Error over time: ``"t"`` and the per-sample attitude (rad) / omega, or
        position / velocity errors (relative), for the charts.
    seconds : float
        Wall time of the engine's run (s).
    work : int or None
        The engine's own count of work (right-hand-side evaluations or steps).
    states : dict
        The engine's state arrays as scored (``quat``, ``omega`` or ``position``,
        ``velocity``).
    result : Trajectory, PointTrajectory or None
        The engine's motion as scored (for the case pages).
    """

    case: str
    group: str
    status: str
    reason: str = ""
    metrics: dict[str, dict[str, Any]] = field(default_factory=dict)
    errors: dict[str, np.ndarray] = field(default_factory=dict)
    seconds: float = 0.0
    work: int | None = None
    states: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    result: Result | None = field(default=None, repr=False)

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (without the per-sample errors)."""
        return {
            "case": self.case,
            "group": self.group,
            "status": self.status,
            "reason": self.reason,
            "metrics": {k: {**v, "value": _finite(v["value"])} for k, v in self.metrics.items()},
            "seconds": self.seconds,
            "work": self.work,
        }


def _finite(x: float) -> float | str:
    return float(x) if math.isfinite(x) else "inf" if x > 0 else "nan"


def integrals(case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The first integrals of the case along ``states`` (see the module docstring).

    Returns ``{"energy": (n,), "momentum": (n, 3) or (n,)}`` (J or J/kg, kg m^2/s or
    m^2/s); ``momentum`` is absent where none is conserved (the turning frame).
    """
    return case.spec.integrals(case, states)


def event_signal(case: Case, states: dict[str, np.ndarray]) -> np.ndarray | None:
    """The signal whose level crossings are the case's events, or None.

    ``"omega_1"``: the body-axis 2 component of ``w`` (its sign flips with the body
    in the tennis-racket flip); ``"cos_tilt"``: ``cos theta = R_33``, the vertical
    component of the body axis 3; ``"radius"``: ``|r|``.
    """
    if case.event is None:
        return None
    name = case.event["signal"]
    if name == "omega_1":
        return states["omega"][:, 1]
    if name == "cos_tilt":
        q = states["quat"]
        return 1.0 - 2.0 * (q[:, 1] ** 2 + q[:, 2] ** 2) / np.sum(q * q, axis=-1)
    return np.linalg.norm(states["position"], axis=-1)


def crossings(t: np.ndarray, s: np.ndarray, level: float) -> np.ndarray:
    """Times at which ``s`` crosses ``level`` (linear interpolation between samples).

    >>> import numpy as np
    >>> t = np.linspace(0.0, 2.0 * np.pi, 2001)
    >>> np.round(crossings(t, np.cos(t), 0.0), 5).tolist()
    [1.5708, 4.71239]
    """
    d = s - level
    k = np.nonzero((d[:-1] < 0.0) != (d[1:] < 0.0))[0]
    frac = d[k] / (d[k] - d[k + 1])
    return t[k] + frac * (t[k + 1] - t[k])


def evaluate(
    case: Case,
    result: Result | Estimate | dict[str, np.ndarray],
    *,
    seconds: float = 0.0,
    work: int | None = None,
    defects: list[str] | None = None,
) -> CaseResult:
    """Compare an engine's motion with the exact one and give the verdict.

    Parameters
    ----------
    case : Case
    result : Trajectory, PointTrajectory or Estimate
        The engine's motion on ``case.t``: a :class:`poinsot.Trajectory` (attitude
        body -> space, angular velocity in body axes, rad/s) for a rigid body, a
        :class:`poinsot.PointTrajectory` (m, m/s) for a point; an
        :class:`poinsot.verify.groups.Estimate` for an estimation case. The former dict of
        arrays (``quat`` (n, 4) scalar first and ``omega`` (n, 3), or ``position``
        and ``velocity`` (n, 3)) is still read, with a DeprecationWarning.
    seconds, work : optional
        The engine's wall time (s) and work count, reported as given.
    defects : list of str, optional
        Findings about the states that fail the case whatever its metrics (e.g.
        an attitude and angular velocity that violate the kinematic equation).

    Returns
    -------
    CaseResult
        ``status`` ``"pass"`` when every metric is within its threshold (a
        non-finite value never passes) and there is no defect.

    Notes
    -----
    The errors are those of :func:`poinsot.compare` against :meth:`Case.reference`
    (the attitude distance of :func:`poinsot._quat.attitude_distance`, docs/theory.md
    §4; the vector differences relative to the exact scale), a non-finite one
    counting as infinite; the drifts those of :func:`poinsot._drift.relative_drift`.

    Examples
    --------
    >>> from poinsot.verify import cases
    >>> from poinsot.verify.metrics import evaluate
    >>> case = cases("kepler-e0.5")[0]
    >>> res = evaluate(case, case.reference())
    >>> res.status, res.metrics["position"]["value"]
    ('pass', 0.0)
    """
    if isinstance(result, dict):
        _deprecated_states()
    got = as_result(case, result)
    own = case.spec.score(case, got)
    values, errors, states = own if own is not None else _compare(case, got)
    return _verdict(case, got, values, errors, states, seconds, work, defects)


def _compare(
    case: Case, result: Result
) -> tuple[dict[str, float], dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The metric values, per-sample errors and state arrays of ``result`` against the
    exact motion (see :func:`evaluate`)."""
    reference = case.reference()
    exact = case.exact()
    states = case.spec.arrays(result)
    diff = compare(result, reference)
    values: dict[str, float] = {}
    errors: dict[str, np.ndarray] = {"t": case.t}
    spec = case.spec
    for name, key in zip(spec.errors, spec.states, strict=True):
        d = diff[name]
        if name == "attitude":
            # geodesic angle 2 atan2(|vec(qe~ q)|, |w(qe~ q)|), whatever the norm of q
            errors[name] = attitude_distance(exact[key], states[key])
            values[name] = _max(d.max)
        else:  # relative to the largest exact magnitude
            errors[name] = np.linalg.norm(states[key] - exact[key], axis=-1) / d.scale
            values[name] = _max(d.max) / d.scale
    finite = all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in states.values())
    if not finite:  # a diverged engine: no integral or event to measure, every one fails
        values["energy"] = math.inf
        if spec.has_momentum:
            values["momentum"] = math.inf
        if case.event is not None:
            values["events"] = math.inf
    else:
        got, ref = integrals(case, states), integrals(case, exact)
        values["energy"] = relative_drift(got["energy"], abs(float(ref["energy"][0])))
        if "momentum" in got:
            k = got["momentum"]
            k0 = float(np.linalg.norm(ref["momentum"][0]))
            k = spec.conserved_momentum(k)  # K_z only for a top
            values["momentum"] = relative_drift(k, k0, vector=k.ndim > 1)
        if case.event is not None:
            level = float(case.event["level"])
            te = crossings(case.t, event_signal(case, exact), level)  # type: ignore[arg-type]
            tg = crossings(case.t, event_signal(case, states), level)  # type: ignore[arg-type]
            values["events"] = (
                float(np.max(np.abs(tg - te), initial=0.0)) if tg.size == te.size else math.inf
            )
    return values, errors, states


def _verdict(case: Case, result: Any, values: dict[str, float], errors: dict[str, np.ndarray],
             states: dict[str, np.ndarray], seconds: float, work: int | None,
             defects: list[str] | None) -> CaseResult:  # fmt: skip
    """Each metric against its threshold (and, for ``name``, a lower bound
    ``thresholds[name + "_min"]`` when the case has one)."""
    metrics = {}
    failed = []
    for name, value in values.items():
        thr = float(case.thresholds[name])
        low = case.thresholds.get(f"{name}_min")
        passed = bool(math.isfinite(value) and value <= thr and (low is None or value >= low))
        metrics[name] = {
            "value": value,
            "threshold": thr,
            "units": METRICS[name][0],
            "passed": passed,
        }
        if low is not None:
            metrics[name]["minimum"] = float(low)
        if not passed:
            unit = METRICS[name][0]
            what = f"> {thr:.3g}" if low is None else f"outside [{low:.3g}, {thr:.3g}]"
            failed.append(f"{name} {value:.3g} {what}" + ("" if unit == "1" else f" {unit}"))
    failed.extend(defects or ())
    return CaseResult(
        case=case.name,
        group=case.group,
        status="fail" if failed else "pass",
        reason="; ".join(failed),
        metrics=metrics,
        errors=errors,
        seconds=seconds,
        work=work,
        states=states,
        result=result,
    )


def _max(x: float) -> float:
    """A largest error, infinite when it is not finite (NaN states never pass)."""
    return float(x) if math.isfinite(x) else math.inf
