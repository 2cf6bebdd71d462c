"""Adapter: a satellite's attitude in orbit (docs/theory.md §10.2, §10.3).

Tables:

* ``[orbit]``: the Kepler orbit (:class:`poinsot.dynamics.KeplerOrbit`): ``a`` (m)
  or ``altitude`` (m above the Earth's equatorial radius 6378.137 km), ``e``
  (default 0), ``inclination``, ``raan``, ``argp``, ``anomaly`` (true anomaly at
  t = 0) (default 0; rad, or degrees with ``degrees = true``) and ``frame``, the
  orbit frame the attitude is judged in: ``"lvlh"`` (default: z nadir, y minus the
  orbit normal, x along the velocity of a circular orbit) or ``"rtn"``
  (:func:`poinsot.dynamics.orbit_frame`);
* ``[body]``: the inertia about the centre of mass (body axes; wheels locked);
* ``[attitude]`` and ``[angular_velocity]``: **relative to the orbit frame** at
  t = 0: ``R_ob`` and the body's angular velocity relative to the frame (frame
  ``"body"``: body axes; ``"space"``: orbit-frame axes);
* ``[environment]``: ``gravity_gradient`` (default true) and a residual magnetic
  ``dipole = [mx, my, mz]`` (A m^2, body axes) in the Earth's tilted-dipole field;
* ``[control]``: ``law`` ``"none"`` (default), ``"pd"`` (quaternion PD: ``kp``
  N m, ``kd`` N m s, optional ``feedforward = true``), ``"mrp"`` (MRP feedback:
  ``K`` N m, ``P`` N m s) or ``"bdot"`` (``gain`` A m^2 s/T, ``max_dipole`` A m^2);
  ``target = "orbit"`` (default: hold ``target_quat``, default identity, in the
  orbit frame) or ``"inertial"`` (hold ``target_quat``, body -> inertial), a
  scalar-first quaternion;
* ``[wheels]``: reaction wheels as the ``gyrostat`` kind reads them (without a
  ``command``): the PD and MRP laws then drive the wheels.

Solved by :meth:`poinsot.dynamics.Spacecraft.simulate` (``"dop853"``, ``"rk4"``).
When nothing but the gravity gradient acts in a circular orbit and the body starts
with a pitch angle and pitch rate only (principal axes along the LVLH axes), the
pitch follows the exact libration :class:`poinsot.dynamics.PitchLibration`: the
check compares them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ...dynamics import (
    BDot,
    KeplerOrbit,
    MRPFeedback,
    PitchLibration,
    QuaternionPD,
    Spacecraft,
    dipole_field,
    gravity_gradient_stability,
)
from ...plotting.spec import Drawing
from ...rotations.rotation import Rotation
from ..describe import fmt
from ..kind import Chart, Check, Entry, Facts
from ..readers import read_angular_velocity, read_body
from . import _rigid
from .gyrostat import GyrostatSpec, _read_wheels, _wheels

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

#: The Earth's equatorial radius (m, WGS 84), for ``altitude``.
EARTH_EQUATORIAL_RADIUS = 6378137.0
METHODS = ("dop853", "rk4")
LAWS = ("none", "pd", "mrp", "bdot")
_ORBIT_KEYS = ("a", "altitude", "e", "inclination", "raan", "argp", "anomaly", "degrees", "frame")
_CONTROL_KEYS = ("law", "kp", "kd", "feedforward", "K", "P", "gain", "max_dipole", "target",
                 "target_quat")  # fmt: skip


@dataclass(frozen=True, eq=False)
class SpacecraftSpec:
    """What the file says, in SI units: the orbit, the frame, the environment, the
    control law's parameters and the wheels (a :class:`.gyrostat.GyrostatSpec`)."""

    orbit: KeplerOrbit
    frame: str
    gravity_gradient: bool
    dipole: np.ndarray | None
    law: str
    gains: Mapping[str, float]
    feedforward: bool
    target: str
    target_quat: np.ndarray
    wheels: GyrostatSpec | None


def _read_orbit(o: Table) -> tuple[KeplerOrbit, str]:
    o.known(_ORBIT_KEYS)
    how = o.exclusive(("a", "altitude"), what="the semi-major axis `a` (m) or `altitude` (m)")
    degrees = o.boolean("degrees", False)
    if how == "a":
        a = o.number("a", positive=True, required=True)
    else:
        a = EARTH_EQUATORIAL_RADIUS + o.number("altitude", positive=True, required=True)
    e = o.number("e", 0.0, nonnegative=True)
    if not e < 1.0:
        raise o.expected("e", "an elliptic eccentricity, 0 <= e < 1", e)
    angles = [o.number(k, 0.0) for k in ("inclination", "raan", "argp", "anomaly")]
    frame = o.string("frame", "lvlh", choices=("lvlh", "rtn"))
    o.finish(_ORBIT_KEYS)
    return KeplerOrbit(a, e, *angles, degrees=degrees), frame


def _read_control(c: Table | None) -> dict[str, Any]:
    if c is None:
        return {"law": "none", "gains": {}, "feedforward": False, "target": "orbit",
                "target_quat": np.array([1.0, 0.0, 0.0, 0.0])}  # fmt: skip
    c.known(_CONTROL_KEYS)
    law = c.string("law", "none", choices=LAWS)
    need = {"none": (), "pd": ("kp", "kd"), "mrp": ("K", "P"), "bdot": ("gain", "max_dipole")}
    for other, keys in need.items():
        for k in keys:
            if other != law and c.has(k) and k not in need[law]:
                raise c.error(k, f'`{k}` is a parameter of law "{other}", not of law "{law}".')
    gains = {k: c.number(k, positive=True, required=True) for k in need[law]}
    feedforward = c.boolean("feedforward", False)
    target = c.string("target", "orbit", choices=("orbit", "inertial"))
    q = c.vector("target_quat", 4, required=False, default=(1.0, 0.0, 0.0, 0.0),
                 what="a scalar-first quaternion [w, x, y, z]")  # fmt: skip
    qa = np.asarray(q, dtype=float)
    if not np.linalg.norm(qa) > 0:
        raise c.expected("target_quat", "a non-zero quaternion", list(q))
    c.finish(_CONTROL_KEYS)
    return {"law": law, "gains": gains, "feedforward": feedforward, "target": target,
            "target_quat": qa / np.linalg.norm(qa)}  # fmt: skip


def spacecraft_of(scenario: Any) -> Spacecraft:
    """The :class:`poinsot.dynamics.Spacecraft` a ``spacecraft`` scenario describes."""
    s: SpacecraftSpec = scenario.spec
    j = np.asarray(scenario.body.inertia, dtype=float)
    sat = Spacecraft(j, s.orbit, frame=s.frame, gravity_gradient=s.gravity_gradient,
                     dipole=s.dipole)  # fmt: skip
    if s.law == "none":
        return sat
    if s.law == "bdot":
        law: Any = BDot(s.gains["gain"], s.gains["max_dipole"],
                        field=lambda t: dipole_field(t, s.orbit.position(t)))  # fmt: skip
    else:
        target = (sat.orbit_reference(s.target_quat) if s.target == "orbit"
                  else s.target_quat)  # fmt: skip
        if s.law == "pd":
            law = QuaternionPD(s.gains["kp"], s.gains["kd"], target=target,
                               inertia=j if s.feedforward else None)  # fmt: skip
        else:
            law = MRPFeedback(s.gains["K"], s.gains["P"], j, target)
    wheels = None if s.wheels is None else _wheels(s.wheels)
    return dataclasses.replace(sat, control=law, wheels=wheels)


def initial_state(scenario: Any) -> tuple[Rotation, np.ndarray]:
    """``(R_ib, w_b)`` at t = 0 from the file's attitude and rate relative to the orbit
    frame: ``R_ib = R_io R_ob``, ``w_b = w_rel + R_ib^T R_io w_o`` (theory §5, §10.2)."""
    sat = spacecraft_of(scenario)
    r_ob = scenario.attitude.rotation
    r_ib = sat.orbit_attitude(0.0) * r_ob
    w_rel = np.asarray(scenario.angular_velocity.omega_body, dtype=float)
    return r_ib, w_rel + sat.orbit_rate(r_ib, 0.0)


def libration(scenario: Any) -> PitchLibration | None:
    """The exact pitch libration that the motion follows, or None: a circular orbit,
    the ``"lvlh"`` frame, the gravity gradient alone, principal body axes, and a start
    turned and turning about the pitch axis (y) only."""
    s: SpacecraftSpec = scenario.spec
    j = np.asarray(scenario.body.inertia, dtype=float)
    if (s.orbit.e != 0.0 or s.frame != "lvlh" or not s.gravity_gradient or s.dipole is not None
            or s.law != "none" or not np.array_equal(j, np.diag(np.diag(j)))):  # fmt: skip
        return None
    rv = scenario.attitude.rotation.as_rotvec()
    w = np.asarray(scenario.angular_velocity.omega_body, dtype=float)
    if rv[0] != 0.0 or rv[2] != 0.0 or w[0] != 0.0 or w[2] != 0.0:
        return None
    return PitchLibration(np.diag(j), s.orbit.mean_motion, theta0=float(rv[1]),
                          rate0=float(w[1]))  # fmt: skip


class SpacecraftKind(_rigid.RigidKind):
    name = "spacecraft"
    title = "a satellite's attitude in orbit: gravity gradient, magnetic torque, control, wheels"
    tables = ("orbit", "body", "angular_velocity", "environment", "control", "wheels")
    methods = METHODS
    orders = {"rk4": 4}
    theory = "docs/theory.md §10.2"
    # cost estimate, one core, per output sample: the shipped examples took 8.6e-3 s
    # (libration), 3.9e-2 s (nadir pointing with wheels) and 8.0e-2 s (B-dot) per sample
    # with dop853, and rk4 1.2e-2 s on the nadir example at a 2 s step (the torques and
    # the control law are Python right-hand sides)
    seconds_per_step = {"dop853": 4e-2, "rk4": 1.5e-2}

    def claims(self, data: Mapping[str, Any]) -> bool:
        # a point on a central orbit (kind "central-orbit") has no attitude
        return "orbit" in data and "body" in data and "angular_velocity" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        orbit, frame = _read_orbit(top.table("orbit", required=True))
        body = read_body(top.table("body", required=True))
        omega = read_angular_velocity(top.table("angular_velocity", required=True), attitude)
        env = top.table("environment")
        gg, dipole = True, None
        if env is not None:
            env.known(("gravity_gradient", "dipole"))
            gg = env.boolean("gravity_gradient", True)
            if env.has("dipole"):
                dipole = np.array(env.vector("dipole", 3, what="[mx, my, mz] (A m^2, body axes)"))
            env.finish(("gravity_gradient", "dipole"))
        control = _read_control(top.table("control"))
        wt = top.table("wheels")
        wheels = None
        if wt is not None:
            wheels = _read_wheels(wt)
            if wheels.command is not None:
                raise wt.error("command", "the [control] law drives the wheels here: remove "
                               "[wheels.command].")  # fmt: skip
            if control["law"] not in ("pd", "mrp"):
                raise wt.error(None, 'reaction wheels need a [control] law "pd" or "mrp" '
                               "to drive them.")  # fmt: skip
        spec = SpacecraftSpec(orbit=orbit, frame=frame, gravity_gradient=gg, dipole=dipole,
                              wheels=wheels, **control)  # fmt: skip
        return {"body": body, "angular_velocity": omega, "spec": spec}

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        sat = spacecraft_of(scenario)
        r0, w0 = initial_state(scenario)
        spec: SpacecraftSpec = scenario.spec
        speed0 = None if spec.wheels is None else spec.wheels.speed0
        progress(0.0, f"integrating ({method})")
        tr = sat.simulate(r0, w0, t, wheel_speed0=speed0, method=method,
                          max_step=scenario.simulation.max_step)  # fmt: skip
        progress(1.0, f"integrating ({method})")
        return tr

    def facts(self, scenario: Scenario) -> Facts:
        s: SpacecraftSpec = scenario.spec
        o = s.orbit
        j = np.asarray(scenario.body.inertia, dtype=float)
        entries: dict[str, Entry] = {
            "orbit_period": Entry(o.period, "s"),
            "mean_motion": Entry(o.mean_motion, "rad/s"),
            "perigee_altitude": Entry(o.a * (1 - o.e) - EARTH_EQUATORIAL_RADIUS, "m"),
        }
        lines = [
            f"Kepler orbit a = {fmt(o.a)} m, e = {fmt(o.e)}, i = "
            f"{fmt(np.degrees(o.inclination))} deg: period {fmt(o.period)} s; attitude "
            f"judged in the {s.frame.upper()} frame (docs/theory.md §10.2)"
        ]
        if np.array_equal(j, np.diag(np.diag(j))):
            st = gravity_gradient_stability(np.diag(j))
            region = str(st.region)
            entries["gravity_gradient_region"] = Entry(region, "", "of the LVLH-aligned attitude")
            lines.append(
                f"gravity-gradient stability of the orbit-frame-aligned attitude: {region} "
                f"(k1 = {fmt(float(st.k1))}, k3 = {fmt(float(st.k3))}; docs/theory.md §10.2)"
            )
        lib = libration(scenario)
        if lib is not None:
            entries["libration_period"] = Entry(lib.period, "s", "exact pitch libration")
            lines.append(f"planar pitch libration, exact (Jacobi functions): period "
                         f"{fmt(lib.period)} s")  # fmt: skip
        if s.law != "none":
            gains = ", ".join(f"{k} = {fmt(v)}" for k, v in s.gains.items())
            via = " through the reaction wheels" if s.wheels is not None else ""
            lines.append(f"control law {s.law} ({gains}){via}, target {s.target} "
                         "(docs/theory.md §10.3)")  # fmt: skip
        return Facts(entries, tuple(lines))

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        sat = spacecraft_of(scenario)
        rate = Check("rate", "|w| (body rate)", "rad/s", np.linalg.norm(tr.omega, axis=-1),
                     conserved=False)  # fmt: skip
        pointing = Check("pointing_error", "angle from the target attitude", "rad",
                         _pointing(scenario, sat, tr), conserved=False)  # fmt: skip
        # detumbling has no target attitude: its measure is the rate
        out = [rate] if scenario.spec.law == "bdot" else [pointing]
        lib = libration(scenario)
        if lib is not None:
            theta = sat.relative(tr).as_euler("YXZ")[:, 0]
            exact = lib.theta(tr.t)
            wrapped = exact + 2 * np.pi * np.round((theta - exact) / (2 * np.pi))
            out.append(Check("pitch", "pitch angle relative to LVLH", "rad", theta,
                             expected=wrapped, scale=max(float(np.max(np.abs(wrapped))), 1e-3),
                             law="exact libration (docs/theory.md §10.2)"))  # fmt: skip
        out.append(Check("energy", "kinetic energy", "J", np.asarray(tr.energy), conserved=False))
        return out

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        """``pointing_error`` (rad), the attitude relative to the orbit frame as
        ``roll, pitch, yaw`` (rad, ``"XYZ"`` intrinsic: about the frame's x, y, z) and,
        with wheels, their speeds (rad/s) and motor torques (N m)."""
        sat = spacecraft_of(scenario)
        rel = sat.relative(tr).as_euler("XYZ")
        out = {"pointing_error": (_pointing(scenario, sat, tr), "rad")}
        for i, name in enumerate(("roll", "pitch", "yaw")):
            out[name] = (rel[:, i], "rad")
        if getattr(tr, "wheel_speed", None) is not None:
            for i in range(tr.wheel_speed.shape[-1]):
                out[f"wheel_speed_{i}"] = (tr.wheel_speed[:, i], "rad/s")
                out[f"motor_torque_{i}"] = (tr.motor_torque[:, i], "N m")
        return out

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        s: SpacecraftSpec = scenario.spec
        wheels = "" if s.wheels is None else f", {s.wheels.axes.shape[0]} wheel(s)"
        return [f"{self.title}: control {s.law}{wheels}, frame {s.frame}"]

    def report(self, result: ScenarioResult) -> ReportSpec:
        """The rigid body's report with the nadir direction drawn from the body (the
        Earth is that way), the pointing error (deg), the attitude relative to the
        orbit frame (deg), the torques acting (N m) and, with wheels, their speeds
        against their limits (rad/s) (docs/theory.md §10.2, §10.3)."""
        s, tr = result.scenario, result.trajectory
        sat = spacecraft_of(s)
        spec: SpacecraftSpec = s.spec
        n = tr.t.size
        charts = [Chart("pointing error", "deg",
                        {"error": np.degrees(_pointing(s, sat, tr))})]  # fmt: skip
        rel = np.degrees(sat.relative(tr).as_euler("XYZ"))
        charts.append(Chart(f"attitude relative to {spec.frame.upper()} (XYZ)", "deg",
                            {"roll": rel[:, 0], "pitch": rel[:, 1], "yaw": rel[:, 2]}))  # fmt: skip
        torques: dict[str, np.ndarray] = {}
        env = sat.environment()
        if env is not None:
            torques["|environment|"] = np.linalg.norm(_along(env, tr), axis=-1)
        if sat.control is not None:
            torques["|control|"] = np.linalg.norm(_along(sat.control, tr), axis=-1)
        if torques:
            charts.append(Chart("torque magnitudes", "N m", torques))
        if getattr(tr, "wheel_speed", None) is not None and spec.wheels is not None:
            speeds: dict[str, np.ndarray] = {}
            dashed = []
            for i in range(tr.wheel_speed.shape[-1]):
                speeds[f"Omega_{i}"] = tr.wheel_speed[:, i]
                lim = np.asarray(spec.wheels.max_speed)[i]
                if np.isfinite(lim):
                    for sign, label in ((1.0, f"+max_speed {i}"), (-1.0, f"-max_speed {i}")):
                        speeds[label] = np.full(n, sign * lim)
                        dashed.append(label)
            charts.append(Chart("wheel speeds and their limits", "rad/s", speeds, tuple(dashed)))
        r = s.spec.orbit.position(tr.t)
        size = float(np.sqrt(np.max(np.diag(np.asarray(s.body.inertia))) / max(s.body.mass, 1e-9)))
        nadir = -r / np.linalg.norm(r, axis=-1, keepdims=True) * 3.0 * size
        guides = {"nadir (to the Earth)": np.stack([np.zeros_like(nadir), nadir], axis=1)}
        out = _rigid.rigid_report(result)
        return dataclasses.replace(out, charts=tuple(charts) + tuple(out.charts),
                                   drawing=Drawing(guides=guides))  # fmt: skip


def _along(model: Any, tr: Any) -> np.ndarray:
    """A torque model's body torque at each sample of ``tr`` (N m, (n, 3))."""
    return np.array([model.body_torque(float(t), q, w)
                     for t, q, w in zip(tr.t, tr.quat, tr.omega, strict=True)])  # fmt: skip


def _pointing(scenario: Any, sat: Spacecraft, tr: Any) -> np.ndarray:
    """The pointing error (rad) from the control target (the orbit frame turned by
    ``target_quat``, or the inertial ``target_quat``; without control, the orbit frame)."""
    s: SpacecraftSpec = scenario.spec
    if s.law in ("pd", "mrp") and s.target == "inertial":
        err = Rotation.from_quat(s.target_quat).inv() * tr.rotation
        return np.asarray(err.magnitude())
    offset = s.target_quat if s.law in ("pd", "mrp") else None
    return sat.pointing_error(tr, offset)


KIND = SpacecraftKind()
