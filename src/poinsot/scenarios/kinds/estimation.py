"""Adapter: attitude estimation scored against exact motion (docs/theory.md §10.4).

The truth is the exact torque-free motion of ``[body]`` from ``[attitude]`` and
``[angular_velocity]`` (:class:`poinsot.dynamics.FreeRigidBody`, Jacobi elliptic
functions); sensors sample it and the multiplicative EKF
(:func:`poinsot.dynamics.run_mekf`) estimates attitude and gyro bias. Tables:

* ``[gyro]``: ``arw`` (rad/s^0.5), ``rrw`` (rad/s^1.5), ``bias0 = [bx, by, bz]``
  (rad/s), ``kind`` (``"integrating"`` or ``"rate"``), ``seed`` (int); sampled at
  every output time (``[simulation]`` ``step``);
* ``[star_tracker]`` (optional): ``sigma`` (rad), ``boresight_sigma`` (rad),
  ``every`` (an update every this many gyro samples, default 10), ``seed``;
* ``[sun_sensor]``, ``[magnetometer]`` (optional): ``reference = [x, y, z]`` (the
  inertial direction), ``sigma`` (rad), ``every``, ``seed``;
* ``[filter]``: ``sigma_attitude`` (rad) and ``sigma_bias`` (rad/s) of the initial
  covariance, ``initial_error = [x, y, z]`` (rad, a rotation vector in body axes: the
  filter starts there), ``gate`` (default 0.999).

The method is ``"mekf"``. The result is the estimate as a trajectory (the estimated
attitude and the bias-corrected gyro rate); the checks, the series and the report
compare it with the truth: attitude and bias errors with their +-3 sigma bounds, the
normalised estimation error squared (NEES, 6 dof) and the innovation statistics (NIS).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ...dynamics import (
    FreeRigidBody,
    Gyro,
    StarTracker,
    VectorSensor,
    attitude_error,
    nees,
    nis,
    run_mekf,
)
from ...rotations.rotation import Rotation
from ...trajectory import Trajectory
from ..describe import fmt
from ..kind import Chart, Check, Entry, Facts
from ..readers import read_angular_velocity, read_body
from . import _rigid

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

_GYRO = ("arw", "rrw", "bias0", "kind", "seed")
_TRACKER = ("sigma", "boresight_sigma", "every", "seed")
_VECTOR = ("reference", "sigma", "every", "seed")
_FILTER = ("sigma_attitude", "sigma_bias", "initial_error", "gate")


@dataclass(frozen=True, eq=False)
class EstimationSpec:
    """What the file says, in SI units (the sensors as dicts of their parameters)."""

    gyro: Mapping[str, Any]
    tracker: Mapping[str, Any] | None
    vectors: tuple[Mapping[str, Any], ...]
    sigma_attitude: float
    sigma_bias: float
    initial_error: np.ndarray
    gate: float


@dataclass(frozen=True, eq=False)
class Estimate:
    """The truth, the gyro samples and the filter's result of one run."""

    truth: Any
    gyro: Any
    result: Any
    attitude_error: np.ndarray
    bias_error: np.ndarray
    nees: np.ndarray
    nis: np.ndarray


def _sensor(t: Table | None, keys: tuple[str, ...], vector: bool) -> dict[str, Any] | None:
    if t is None:
        return None
    t.known(keys)
    out: dict[str, Any] = {"sigma": t.number("sigma", positive=True, required=True),
                           "every": int(t.number("every", 10, positive=True)),
                           "seed": int(t.number("seed", 0, nonnegative=True))}  # fmt: skip
    if vector:
        ref = np.array(t.vector("reference", 3, what="[x, y, z] (inertial)", required=True))
        if not np.linalg.norm(ref) > 0:
            raise t.expected("reference", "a non-zero direction", list(ref))
        out["reference"] = ref / np.linalg.norm(ref)
    elif t.has("boresight_sigma"):
        out["boresight_sigma"] = t.number("boresight_sigma", positive=True)
    t.finish(keys)
    return out


def estimate(scenario: Any, t: np.ndarray) -> Estimate:
    """Run the scenario's sensors and MEKF on its exact motion at the times ``t``."""
    s: EstimationSpec = scenario.spec
    body = FreeRigidBody(np.asarray(scenario.body.inertia), rotation0=scenario.attitude.rotation,
                         omega0=np.asarray(scenario.angular_velocity.omega_body))  # fmt: skip
    truth = body.trajectory(t)
    g = s.gyro
    gyro = Gyro(g["arw"], g["rrw"], bias0=g["bias0"], kind=g["kind"]).sample(truth, rng=g["seed"])
    measurements: list[Any] = []
    if s.tracker is not None:
        k = s.tracker["every"]
        sub = body.trajectory(t[::k])
        tracker = StarTracker(s.tracker["sigma"], s.tracker.get("boresight_sigma"))
        measurements.append(tracker.sample(sub, rng=s.tracker["seed"]))
    for v in s.vectors:
        sub = body.trajectory(t[:: v["every"]])
        measurements.append(VectorSensor(v["reference"], v["sigma"]).sample(sub, rng=v["seed"]))
    q0 = (truth.rotation[0] * Rotation.from_rotvec(s.initial_error)).as_quat()
    p0 = np.r_[[s.sigma_attitude**2] * 3, [s.sigma_bias**2] * 3]
    res = run_mekf(gyro, measurements, q0, p0, gate=s.gate)
    return Estimate(truth, gyro, res, attitude_error(res.quat, gyro.quat), res.bias - gyro.bias,
                    nees(res, gyro), nis(res))  # fmt: skip


class EstimationKind(_rigid.RigidKind):
    name = "estimation"
    title = "attitude estimation (gyro, star tracker, vector sensors, MEKF) on exact motion"
    tables = ("body", "angular_velocity", "gyro", "star_tracker", "sun_sensor", "magnetometer",
              "filter")  # fmt: skip
    methods = ("mekf",)
    orders: dict[str, int] = {}
    theory = "docs/theory.md §10.4"
    # measured on the shipped example: ~1.5e-4 s per gyro sample (the filter's Python loop)
    seconds_per_step = {"mekf": 1.5e-4}

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "gyro" in data and "body" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        body = read_body(top.table("body", required=True))
        omega = read_angular_velocity(top.table("angular_velocity", required=True), attitude)
        gt = top.table("gyro", required=True)
        gt.known(_GYRO)
        gyro = {
            "arw": gt.number("arw", 0.0, nonnegative=True),
            "rrw": gt.number("rrw", 0.0, nonnegative=True),
            "bias0": np.array(
                gt.vector(
                    "bias0", 3, what="[bx, by, bz] (rad/s)", required=False, default=(0.0, 0.0, 0.0)
                )
            ),  # fmt: skip
            "kind": gt.string("kind", "integrating", choices=("integrating", "rate")),
            "seed": int(gt.number("seed", 0, nonnegative=True)),
        }
        gt.finish(_GYRO)
        tracker = _sensor(top.table("star_tracker"), _TRACKER, vector=False)
        vectors = tuple(v for v in (_sensor(top.table("sun_sensor"), _VECTOR, True),
                                    _sensor(top.table("magnetometer"), _VECTOR, True))
                        if v is not None)  # fmt: skip
        if tracker is None and not vectors:
            raise top.error(None, "the filter needs a measurement besides the gyro: add "
                            "[star_tracker], [sun_sensor] or [magnetometer].")  # fmt: skip
        ft = top.table("filter", required=True)
        ft.known(_FILTER)
        spec = EstimationSpec(
            gyro=gyro, tracker=tracker, vectors=vectors,
            sigma_attitude=ft.number("sigma_attitude", positive=True, required=True),
            sigma_bias=ft.number("sigma_bias", positive=True, required=True),
            initial_error=np.array(ft.vector("initial_error", 3, what="[x, y, z] (rad)",
                                             required=False, default=(0.0, 0.0, 0.0))),
            gate=ft.number("gate", 0.999, positive=True),
        )  # fmt: skip
        if not spec.gate < 1.0:
            raise ft.expected("gate", "a probability in (0, 1)", spec.gate)
        ft.finish(_FILTER)
        return {"body": body, "angular_velocity": omega, "spec": spec}

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        progress(0.0, "sensors and MEKF")
        est = estimate(scenario, t)
        progress(1.0, "sensors and MEKF")
        res = est.result
        info = {"solver": "MEKF (Lefferts, Markley & Shuster)"}
        if res.diverged:
            info["stopped"] = res.message
        return Trajectory(t=res.t, rotation=Rotation.from_quat(res.quat),
                          omega=est.gyro.rate - res.bias, method="mekf", info=info)  # fmt: skip

    def _estimate(self, scenario: Scenario, tr: Any) -> Estimate:
        # deterministic (seeded): the same run as solve()
        return estimate(scenario, np.asarray(tr.t))

    def facts(self, scenario: Scenario) -> Facts:
        s: EstimationSpec = scenario.spec
        sensors = (["star tracker"] if s.tracker is not None else []) + [
            f"vector sensor (sigma {fmt(v['sigma'])} rad)" for v in s.vectors
        ]
        return Facts({"sigma_attitude0": Entry(s.sigma_attitude, "rad"),
                      "sigma_bias0": Entry(s.sigma_bias, "rad/s")},
                     (f"MEKF on exact torque-free motion with a gyro (arw {fmt(s.gyro['arw'])} "
                      f"rad/s^0.5, rrw {fmt(s.gyro['rrw'])} rad/s^1.5) and "
                      f"{', '.join(sensors)} (docs/theory.md §10.4)",))  # fmt: skip

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        est = self._estimate(scenario, tr)
        return [
            Check("attitude_error", "|attitude error| against the exact motion", "rad",
                  np.linalg.norm(est.attitude_error, axis=-1), conserved=False),
            Check("bias_error", "|bias error|", "rad/s", np.linalg.norm(est.bias_error, axis=-1),
                  conserved=False),
            Check("nees", "NEES (6 dof, mean 6 when consistent)", "", est.nees,
                  conserved=False),
        ]  # fmt: skip

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        est = self._estimate(scenario, tr)
        sig = est.result.sigma
        out: dict[str, tuple[np.ndarray, str]] = {}
        for i, c in enumerate("xyz"):
            out[f"attitude_error_{c}"] = (est.attitude_error[:, i], "rad")
            out[f"attitude_sigma_{c}"] = (sig[:, i], "rad")
            out[f"bias_error_{c}"] = (est.bias_error[:, i], "rad/s")
            out[f"bias_sigma_{c}"] = (sig[:, 3 + i], "rad/s")
        out["nees"] = (est.nees, "1")
        return out

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        return [self.title]

    def report(self, result: ScenarioResult) -> ReportSpec:
        """The estimated body, the attitude and bias errors (body axes) with their
        +-3 sigma bounds, the NEES with its 99 % band, and the innovation statistics."""
        from scipy.stats import chi2

        est = self._estimate(result.scenario, result.trajectory)
        sig = est.result.sigma
        charts = []
        for what, err, k0, units in (("attitude", est.attitude_error, 0, "rad"),
                                     ("gyro bias", est.bias_error, 3, "rad/s")):  # fmt: skip
            series: dict[str, np.ndarray] = {}
            dashed = []
            for i, c in enumerate("xyz"):
                series[f"{c} error"] = err[:, i]
                series[f"+3 sigma {c}"] = 3 * sig[:, k0 + i]
                series[f"-3 sigma {c}"] = -3 * sig[:, k0 + i]
                dashed += [f"+3 sigma {c}", f"-3 sigma {c}"]
            charts.append(Chart(f"{what} error (body axes) and +-3 sigma", units, series,
                                tuple(dashed)))  # fmt: skip
        n = est.nees.size
        lo, hi = chi2.ppf(0.005, 6), chi2.ppf(0.995, 6)
        charts.append(Chart("NEES (6 dof) and its 99 % band", "1",
                            {"NEES": est.nees, "0.5 %": np.full(n, lo), "99.5 %": np.full(n, hi)},
                            ("0.5 %", "99.5 %")))  # fmt: skip
        dof = est.result.dof
        rows = []
        for d in sorted(set(dof.tolist())):
            v = est.nis[dof == d]
            outside = float(np.mean(v > chi2.ppf(est.result.gate, d))) if v.size else 0.0
            rows.append(f"<tr><td>{d}</td><td>{v.size}</td><td>{fmt(float(np.mean(v)))}</td>"
                        f"<td>{fmt(outside)}</td></tr>")  # fmt: skip
        verdict = est.result.message or "no divergence detected"
        table = ("<table><tr><th>dof</th><th>updates</th>"
                 "<th>mean NIS (expected: dof)</th><th>fraction above the gate</th></tr>"
                 + "".join(rows) + f"</table><p>{verdict} (docs/theory.md §10.4)</p>")  # fmt: skip
        out = _rigid.rigid_report(result)
        sections = (*out.sections, ("Innovations (NIS)", table))
        return dataclasses.replace(out, charts=tuple(charts) + tuple(out.charts),
                                   sections=sections)  # fmt: skip


KIND = EstimationKind()
