"""Adapter: the gyrostat, a rigid body with a constant rotor or reaction wheels
(docs/theory.md §10.1).

Tables: [body] (the inertia ``J`` of the whole system, rotor or wheels **locked**,
about the centre of mass, body axes), [angular_velocity], and one of

* ``[rotor]`` ``h = [hx, hy, hz]``: a rotor of constant momentum ``h`` relative to
  the body (body axes, kg m^2/s), the dual-spin spacecraft. ``method = "exact"`` is
  :class:`poinsot.dynamics.FreeGyrostat` (Jacobi functions; offered when ``h`` is
  along a principal axis of a diagonal ``J``, where that solution is exact);
  ``"dop853"`` and ``"rk4"`` run :func:`poinsot.dynamics.simulate_wheels` with the
  rotor as one wheel along ``h`` held at its speed by its motor (the library's speed
  hold locks it: ``h`` stays constant exactly);
* ``[wheels]``: reaction wheels (:class:`poinsot.dynamics.ReactionWheels`) with
  ``axes`` (N x 3, body axes), axial ``inertia`` (kg m^2), optional ``max_torque``
  (N m), ``max_speed``, ``viscous`` (N m s), ``coulomb`` (N m) (each a number or N
  numbers), ``speed0`` (N initial speeds), ``speed_units`` (``"rad/s"``, ``"rpm"``,
  ...) and ``[wheels.command]``: constant motor torques ``torque = [u_1, ..., u_N]``
  or a piecewise-constant profile ``times = [0, t_1, ...]`` with ``torques`` (one
  row of N torques per time, applied from that time to the next). Solved by
  :func:`poinsot.dynamics.simulate_wheels` (``"dop853"``, ``"rk4"``).

No external torque: the total angular momentum ``K = R (J w + h)`` is conserved (the
checks); with a constant rotor the energy ``T = w . J w / 2`` too.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ...dynamics import (
    FreeGyrostat,
    ReactionWheels,
    WheelTrajectory,
    gyrostat_spin_stable,
    simulate_wheels,
)
from ...plotting.gyrostat import plot_momentum_exchange, plot_wheel_speeds
from ...rotations.rotation import Rotation
from ...trajectory import Trajectory
from ..describe import fmt
from ..kind import Chart, Check, Entry, Facts, FigureSpec
from ..readers import read_angular_velocity, read_body
from ..schema import OMEGA_UNITS
from . import _rigid

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

#: The methods of this kind: the exact dual-spin solution and simulate_wheels' two.
METHODS = ("exact", "dop853", "rk4")
_WHEEL_KEYS = (
    "axes",
    "inertia",
    "max_torque",
    "max_speed",
    "viscous",
    "coulomb",
    "speed0",
    "speed_units",
    "command",
)


@dataclass(frozen=True, eq=False)
class WheelCommand:
    """A built-in motor command: torques ``torques[k]`` (N m, one per wheel) applied
    from ``times[k]`` (s) to ``times[k + 1]`` (the last one to the end of the run); a
    constant command has ``times = (0,)``.

    Examples
    --------
    >>> c = WheelCommand((0.0, 10.0), ((0.1,), (-0.1,)))
    >>> c(5.0, None, None, None).tolist(), c(12.0, None, None, None).tolist()
    ([0.1], [-0.1])
    """

    times: tuple[float, ...]
    torques: tuple[tuple[float, ...], ...]

    def __call__(self, t: float, q: Any, w: Any, speed: Any) -> np.ndarray:
        """The torques asked for at time ``t`` (s), as ``simulate_wheels(command=...)``
        calls it (N m, shape (N,))."""
        k = int(np.searchsorted(np.asarray(self.times), t, side="right")) - 1
        return np.array(self.torques[max(k, 0)], dtype=float)


@dataclass(frozen=True, eq=False)
class GyrostatSpec:
    """What the file says, in SI units: a constant rotor ``h`` (kg m^2/s, body axes)
    or reaction wheels (axes, axial inertia (kg m^2), limits (N m, rad/s), friction
    (N m s, N m), initial speeds ``speed0`` (rad/s) and the command)."""

    h: np.ndarray | None = None
    axes: np.ndarray | None = None
    inertia: np.ndarray | None = None
    max_torque: np.ndarray | None = None
    max_speed: np.ndarray | None = None
    viscous: np.ndarray | None = None
    coulomb: np.ndarray | None = None
    speed0: np.ndarray | None = None
    command: WheelCommand | None = None

    @property
    def rotor(self) -> bool:
        """A constant rotor (``[rotor]``), not driven wheels."""
        return self.h is not None


def _per_wheel(t: Table, key: str, n: int, default: float, *, positive: bool) -> np.ndarray:
    """A number or N numbers (``inf`` written as a missing key: no limit)."""
    what = f"{'a positive' if positive else 'a non-negative'} number or an array of {n} of them"
    if not t.has(key):
        t.raw(key)
        return np.full(n, default)
    v = t.raw(key)
    vals = v if isinstance(v, list) else [v]
    ok = (
        len(vals) == (n if isinstance(v, list) else 1)
        and all(isinstance(x, int | float) and not isinstance(x, bool) for x in vals)
        and all(np.isfinite(x) and (x > 0 if positive else x >= 0) for x in vals)
    )
    if not ok:
        raise t.expected(key, what, v)
    return np.array(np.broadcast_to(np.asarray(vals, dtype=float), (n,)))


def _command(w: Table, n: int) -> WheelCommand | None:
    c = w.table("command")
    if c is None:
        return None
    c.known(("torque", "times", "torques"))
    how = c.exclusive(
        ("torque", "times"),
        what="constant motor torques `torque`, or a profile: `times` with `torques`",
    )
    if how == "torque":
        c.forbid(["torques"], "`torques` goes with `times` (a profile)")
        u = c.vector("torque", n, what=f"an array of {n} motor torques (N m)")
        c.finish(("torque",))
        return WheelCommand((0.0,), (u,))
    times = c.vector("times", None, what="an array of increasing times (s) starting at 0")
    if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:], strict=False)):
        raise c.expected("times", "increasing times (s) starting at 0", list(times))
    if not c.has("torques"):
        raise c.error(None, "missing key `torques`: expected one row of motor torques per time.")
    rows = c.matrix(
        "torques", len(times), n, what=f"{len(times)} rows (one per time) of {n} torques (N m)"
    )
    c.finish(("times", "torques"))
    return WheelCommand(tuple(times), rows)


def _read_wheels(w: Table) -> GyrostatSpec:
    w.known(_WHEEL_KEYS)
    if not w.has("axes"):
        raise w.error(None, "missing key `axes`: expected the wheels' spin axes (body axes).")
    axes = np.array(w.matrix("axes", None, 3, what="an array of rows [ax, ay, az] (body axes)"))
    norms = np.linalg.norm(axes, axis=1)
    if np.any(np.abs(norms - 1.0) > 1e-6):
        raise w.expected("axes", "unit vectors (|a| = 1 within 1e-6)", w.raw("axes"))
    n = axes.shape[0]
    if not w.has("inertia"):
        raise w.error(None, "missing key `inertia`: expected the wheels' axial inertia (kg m^2).")
    inertia = _per_wheel(w, "inertia", n, 0.0, positive=True)
    max_torque = _per_wheel(w, "max_torque", n, np.inf, positive=True)
    max_speed_raw = _per_wheel(w, "max_speed", n, np.inf, positive=True)
    viscous = _per_wheel(w, "viscous", n, 0.0, positive=False)
    coulomb = _per_wheel(w, "coulomb", n, 0.0, positive=False)
    units = w.string("speed_units", "rad/s", choices=tuple(OMEGA_UNITS))
    speed_raw = w.vector("speed0", n, required=False, default=(0.0,) * n,
                         what=f"an array of {n} initial wheel speeds")  # fmt: skip
    factor = OMEGA_UNITS[units]
    speed0 = np.asarray(speed_raw) * factor
    max_speed = max_speed_raw * factor
    over = np.abs(speed0) > max_speed
    if np.any(over):
        i = int(np.flatnonzero(over)[0])
        raise w.error(
            "speed0",
            f"wheel {i} starts at {speed_raw[i]!r} {units}, beyond its `max_speed` "
            f"{float(max_speed_raw[i])!r} {units}.",
        )
    command = _command(w, n)
    w.finish(_WHEEL_KEYS)
    return GyrostatSpec(
        axes=axes / norms[:, None],
        inertia=inertia,
        max_torque=max_torque,
        max_speed=max_speed,
        viscous=viscous,
        coulomb=coulomb,
        speed0=speed0,
        command=command,
    )


def _wheels(spec: GyrostatSpec) -> Any:
    """The :class:`poinsot.dynamics.ReactionWheels` of a ``[wheels]`` spec."""

    return ReactionWheels(
        spec.axes,
        spec.inertia,
        max_torque=spec.max_torque,
        max_speed=spec.max_speed,
        viscous=spec.viscous,
        coulomb=spec.coulomb,
    )


def _rotor_wheel(inertia: np.ndarray, h: np.ndarray) -> tuple[Any, np.ndarray, Any]:
    """The constant rotor as ``simulate_wheels`` takes it: one wheel along ``h`` at its
    speed limit, asked for more torque than holding needs, so that the library's speed
    hold locks it (``Omega`` and ``h`` constant; the result does not depend on the
    wheel's axial inertia, a thousandth of the smallest principal moment here).
    Returns ``(wheels, speed0, command)``."""

    norm = float(np.linalg.norm(h))
    axis = h / norm
    i_r = 1e-3 * float(np.min(np.linalg.eigvalsh(inertia)))
    speed = norm / i_r
    wheels = ReactionWheels([axis], i_r, max_speed=speed)
    return wheels, np.array([speed]), WheelCommand((0.0,), ((1e300,),))


def _run_wheels(
    j: np.ndarray, wheels: Any, rotation0: Any, omega0: Any, speed0: Any, t: np.ndarray,
    command: WheelCommand | None, method: str, max_step: float | None,
) -> Any:  # fmt: skip
    """:func:`poinsot.dynamics.simulate_wheels` on ``t``, one call per piece of a
    piecewise-constant command (each continuing from the state where the last ended),
    so that no integration step straddles a jump of the motor torques; the pieces'
    samples joined in one :class:`poinsot.dynamics.WheelTrajectory` (at a jump, the
    sample is the next piece's first: the command is right-continuous)."""

    cuts = [] if command is None else [c for c in command.times[1:] if t[0] < c < t[-1]]
    edges = [float(t[0]), *cuts, float(t[-1])]
    state = (rotation0, omega0, speed0)
    parts = []
    info: dict[str, Any] = {}
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        last = k == len(edges) - 2
        sel = t[(t >= a) & ((t <= b) if last else (t < b))]
        tt = np.union1d(sel, [a, b])
        piece = None
        if command is not None:  # the torques of this piece, constant over it
            piece = WheelCommand((0.0,), (tuple(command(a, None, None, None)),))
        seg = simulate_wheels(
            j, wheels, state[0], state[1], state[2], tt, command=piece, method=method,
            max_step=max_step,
        )  # fmt: skip
        keep = np.isin(tt, sel)
        parts.append((seg, keep))
        # a held wheel may end a piece above its limit by the step's error (~1e-9
        # relative, simulate_wheels' notes): the next piece starts at the limit
        speed = np.clip(np.asarray(seg.wheel_speed)[-1], -wheels.max_speed, wheels.max_speed)
        state = (seg.quat[-1], seg.omega[-1], speed)
        for key, v in seg.info.items():
            summed = key in ("evaluations", "steps") and key in info
            info[key] = info[key] + v if summed else v
    if len(parts) == 1 and bool(np.all(parts[0][1])):
        return parts[0][0]
    info["pieces"] = len(parts)

    def cat(name: str) -> np.ndarray:
        return np.concatenate([np.asarray(getattr(s, name))[m] for s, m in parts])

    return WheelTrajectory(
        cat("t"), Rotation.from_quat(cat("quat")), cat("omega"), method, energy=cat("energy"),
        momentum=cat("momentum"), info=info, wheel_speed=cat("wheel_speed"),
        wheel_momentum=cat("wheel_momentum"), motor_torque=cat("motor_torque"),
    )  # fmt: skip


def _exchange(scenario: Any, tr: Any) -> tuple[np.ndarray, np.ndarray]:
    """``(J w, h)`` along ``tr``, body axes (kg m^2/s): the body's momentum from
    :func:`poinsot.dynamics.invariants`, the rotor's constant ``h`` or the wheels'
    ``wheel_momentum`` of the :class:`poinsot.dynamics.WheelTrajectory`."""
    jw = _rigid.invariants_of(_tensor(scenario), tr).momentum_body
    spec = scenario.spec
    if spec.rotor:
        return jw, np.array(np.broadcast_to(spec.h, jw.shape))
    return jw, np.asarray(tr.wheel_momentum)


def _vec(x: Any) -> str:
    """``[a, b, c]`` with :func:`~poinsot.scenarios.describe.fmt` numbers (text)."""
    return "[" + ", ".join(fmt(float(v)) for v in x) + "]"


def _tensor(scenario: Any) -> np.ndarray:
    return np.asarray(scenario.body.inertia, dtype=float)


def _principal(j: np.ndarray) -> np.ndarray | None:
    """The principal moments of a diagonal tensor, else None."""
    d = np.diag(j)
    return d.copy() if np.array_equal(j, np.diag(d)) else None


def _gyrostat(scenario: Any) -> Any:
    """The :class:`poinsot.dynamics.FreeGyrostat` of a ``[rotor]`` scenario."""

    return FreeGyrostat(
        _tensor(scenario),
        scenario.spec.h,
        rotation0=scenario.attitude.rotation,
        omega0=np.asarray(scenario.angular_velocity.omega_body),
    )


def spin_stability(inertia: Any, h: Any, omega: Any) -> tuple[str, float, bool, bool] | None:
    """The stability of the nominal spin about the rotor axis, with and without the
    rotor (docs/theory.md §10.1, :func:`poinsot.dynamics.gyrostat_spin_stable`).

    The spin is the component ``W = omega . e`` (rad/s) of ``omega`` along the
    principal axis ``e`` of ``h``; stable iff ``(m - I1 W)(m - I2 W) > 0`` with
    ``m = I3 W + h``. Returns ``(axis name, W, stable with h, stable with h = 0)``, or
    None when ``inertia`` (kg m^2, body axes) is not diagonal, ``h`` (kg m^2/s) is
    not along one body axis or ``W = 0``.

    Examples
    --------
    >>> spin_stability(np.diag([300.0, 200.0, 100.0]), [0.0, 150.0, 0.0], [0.01, 1.0, 0.0])
    ('y', 1.0, True, False)
    """

    moments = _principal(np.asarray(inertia, dtype=float))
    hv = np.asarray(h, dtype=float)
    nz = np.flatnonzero(hv)
    if moments is None or nz.size != 1:
        return None
    k = int(nz[0])
    spin = float(np.asarray(omega, dtype=float)[k])
    if spin == 0.0:
        return None
    w = np.zeros(3)
    w[k] = spin
    with_h = bool(gyrostat_spin_stable(moments, hv, w))
    rigid = bool(gyrostat_spin_stable(moments, np.zeros(3), w))
    return "xyz"[k], spin, with_h, rigid


class Gyrostat(_rigid.RigidKind):
    name = "gyrostat"
    title = "gyrostat: a rigid body with a constant rotor (dual spin) or reaction wheels"
    tables = ("body", "angular_velocity", "rotor", "wheels")
    methods = METHODS
    orders = {"rk4": 4}
    theory = "docs/theory.md §10.1"
    # cost estimate, one core, measured on the shipped examples (Python right-hand side)
    seconds_per_step = {"exact": 2e-5, "dop853": 1.5e-3, "rk4": 4e-4}
    seconds_per_run = {"exact": 5e-3}

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "rotor" in data or "wheels" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        body = read_body(top.table("body", required=True))
        omega = read_angular_velocity(top.table("angular_velocity", required=True), attitude)
        how = top.exclusive(
            ("rotor", "wheels"),
            what="a constant rotor momentum [rotor] h, or reaction wheels [wheels]",
        )
        if how == "rotor":
            r = top.table("rotor", required=True)
            r.known(("h",))
            h = np.array(r.vector("h", 3, what="the rotor momentum [hx, hy, hz] (kg m^2/s)"))
            if not np.any(h):
                raise r.error("h", "expected a non-zero rotor momentum (h = 0 is a free body).")
            r.finish(("h",))
            spec = GyrostatSpec(h=h)
        else:
            spec = _read_wheels(top.table("wheels", required=True))
            eig = np.linalg.eigvalsh(np.asarray(body.inertia) - _wheels(spec).axial_inertia)
            if np.any(eig <= 0.0):
                raise top.error(
                    "wheels.inertia",
                    "the body inertia contains the wheels locked: J - sum_i I_i a_i a_i^T must "
                    f"be positive definite, found eigenvalues {[float(e) for e in eig]} (the "
                    "wheels' inertia too large for [body] inertia?).",
                )
        return {"body": body, "angular_velocity": omega, "spec": spec}

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        if method != "exact":
            return None
        spec = fields["spec"]
        if not spec.rotor:
            return (
                '"exact" is the constant-rotor solution (docs/theory.md §10.1); driven '
                'reaction wheels are integrated: expected "dop853" or "rk4".'
            )
        j = np.asarray(fields["body"].inertia, dtype=float)
        if _principal(j) is None or np.count_nonzero(spec.h) != 1:
            return (
                '"exact" needs body axes that are principal (a diagonal inertia) and [rotor] h '
                'along one of them (docs/theory.md §10.1): expected "dop853" or "rk4".'
            )
        return None

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:

        spec = scenario.spec
        if method == "exact":
            progress(0.0, "exact solution")
            tr = _gyrostat(scenario).trajectory(t)
            progress(1.0, "exact solution")
            return tr
        j = _tensor(scenario)
        if spec.rotor:
            wheels, speed0, command = _rotor_wheel(j, spec.h)
        else:
            wheels, speed0, command = _wheels(spec), spec.speed0, spec.command
        progress(0.0, f"integrating ({method})")
        tr = _run_wheels(
            j,
            wheels,
            scenario.attitude.quat,
            np.asarray(scenario.angular_velocity.omega_body),
            speed0,
            t,
            command,
            method,
            scenario.simulation.max_step,
        )
        progress(1.0, f"integrating ({method})")
        if not spec.rotor:
            return tr
        # the rotor's speed is the constant of [rotor]: the rigid body's own result, with
        # K = R (J w + h) of the library and T = w . J w / 2 (the gyrostat's energy)
        return Trajectory(
            tr.t,
            tr.rotation,
            tr.omega,
            tr.method,
            energy=_rigid.invariants_of(j, tr).kinetic,
            momentum=tr.momentum,
            info={**tr.info, "rotor": "one wheel along h, held at its speed"},
        )

    def facts(self, scenario: Scenario) -> Facts:
        spec = scenario.spec
        w0 = np.asarray(scenario.angular_velocity.omega_body)
        if not spec.rotor:
            n = spec.axes.shape[0]
            entries = {
                "wheels": Entry(n, "", "number of wheels"),
                "wheel_axes": Entry(spec.axes, "1", "spin axes (body axes)"),
                "wheel_inertia": Entry(spec.inertia, "kg m^2", "axial inertia"),
                "max_torque": Entry(spec.max_torque, "N m"),
                "max_speed": Entry(spec.max_speed, "rad/s"),
                "wheel_momentum_capacity": Entry(
                    spec.inertia * spec.max_speed, "kg m^2/s", "I_i Omega_max per wheel"
                ),
            }
            lines = [
                f"{n} reaction wheel(s), h = sum_i I_i Omega_i a_i (docs/theory.md §10.1); "
                "no external torque: K = R (J w + h) is conserved while the motors move "
                "momentum between the body and the wheels"
            ]
            if spec.command is not None:
                lines.append(
                    "motor command: "
                    + "; ".join(
                        f"from t = {fmt(tk)} s: {_vec(row)} N m"
                        for tk, row in zip(spec.command.times, spec.command.torques, strict=True)
                    )
                    + f" (clipped at max_torque {_vec(spec.max_torque)} N m)"
                )
            return Facts(entries, tuple(lines))
        g = _gyrostat(scenario)
        entries = {
            "solution": Entry(
                "Jacobi elliptic functions (docs/theory.md §10.1)"
                if g.regime != "numeric"
                else "DOP853 (no closed form: h not along a principal axis)"
            ),
            "rotor_momentum": Entry(spec.h, "kg m^2/s", "h, body axes"),
            "energy": Entry(g.energy, "J"),
            "momentum": Entry(g.momentum, "kg m^2/s"),
            "momentum_norm": Entry(g.momentum_norm, "kg m^2/s"),
            "regime": Entry(g.regime, ""),
            "period": Entry(g.period, "s"),
        }
        if g.regime == "numeric":
            per = "no closed form (h not along a principal axis): DOP853 at rtol 1e-12"
        elif np.isfinite(g.period):
            per = f"omega periodic with period {fmt(g.period)} s"
        else:
            per = "omega not periodic"
        lines = [
            f"gyrostat with constant rotor momentum h = {_vec(spec.h)} kg m^2/s "
            f"(docs/theory.md §10.1): regime {g.regime}, T = {fmt(g.energy)} J, "
            f"|K| = {fmt(g.momentum_norm)} kg m^2/s, {per}"
        ]
        st = spin_stability(_tensor(scenario), spec.h, w0)
        if st is not None:
            axis, spin, with_h, rigid = st
            word = {True: "stable", False: "unstable"}
            entries["spin_stable"] = Entry(with_h, "", f"spin about {axis} with the rotor")
            entries["spin_stable_without_rotor"] = Entry(rigid, "", f"spin about {axis}, h = 0")
            lines.append(
                f"spin about {axis} at {fmt(spin)} rad/s: {word[rigid]} for the rigid body "
                f"(h = 0), {word[with_h]} with the rotor (gyrostat_spin_stable, "
                "docs/theory.md §10.1)"
            )
        return Facts(entries, tuple(lines))

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        k = np.asarray(tr.momentum)
        out = [
            Check("momentum_norm", "|K|", "kg m^2/s", np.linalg.norm(k, axis=-1)),
            Check("momentum_vector", "K = R (J w + h) (space axes)", "kg m^2/s", k),
        ]
        if scenario.spec.rotor:
            out.insert(0, Check("energy", "kinetic energy T = w.Jw/2", "J", tr.energy))
        else:
            out.insert(
                0, Check("energy", "kinetic energy (body and wheels)", "J", tr.energy,
                         conserved=False)
            )  # fmt: skip
        return out

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        """The shared figures, ``momentum.png`` (``J w``, ``h``, ``J w + h`` in body
        axes) and, with wheels, ``wheel_speed.png`` (speeds against ``+-max_speed``),
        drawn by :mod:`poinsot.plotting.gyrostat` (docs/theory.md §10.1)."""
        figs = super().figures(result)
        s, tr = result.scenario, result.trajectory

        def momentum(ax: Any) -> Any:

            jw, h = _exchange(s, tr)
            return plot_momentum_exchange(tr.t, jw, h, ax=ax)

        figs.append(FigureSpec("momentum.png", momentum))
        if not s.spec.rotor:

            def speeds(ax: Any) -> Any:

                return plot_wheel_speeds(tr.t, tr.wheel_speed, s.spec.max_speed, ax=ax)

            figs.append(FigureSpec("wheel_speed.png", speeds))
        return figs

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        """With wheels, the columns ``wheel_speed_i`` (rad/s), ``motor_torque_i`` (N m)
        and ``hx, hy, hz`` (the wheels' momentum relative to the body, body axes,
        kg m^2/s) of the :class:`poinsot.dynamics.WheelTrajectory` (docs/theory.md §10.1)."""
        if scenario.spec.rotor or getattr(tr, "wheel_speed", None) is None:
            return {}
        out: dict[str, tuple[np.ndarray, str]] = {}
        for i in range(tr.wheel_speed.shape[-1]):
            out[f"wheel_speed_{i}"] = (tr.wheel_speed[:, i], "rad/s")
            out[f"motor_torque_{i}"] = (tr.motor_torque[:, i], "N m")
        for c, name in enumerate("xyz"):
            out[f"h{name}"] = (tr.wheel_momentum[:, c], "kg m^2/s")
        return out

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        spec = scenario.spec
        if spec.rotor:
            return [f"{self.title}: rotor h = {_vec(spec.h)} kg m^2/s"]
        return [f"{self.title}: {spec.axes.shape[0]} wheel(s)"]

    def report(self, result: ScenarioResult) -> ReportSpec:
        """The rigid body's report (:func:`._rigid.rigid_report`) with the momentum
        exchange in body axes: the body's ``J w``, the rotor or wheels' ``h`` and their
        sum (kg m^2/s, docs/theory.md §10.1); with wheels, their speeds against
        ``+-max_speed`` (rad/s) and the motor torques (N m)."""
        s, tr = result.scenario, result.trajectory
        spec = s.spec
        n = tr.t.size
        jw, h = _exchange(s, tr)
        charts = []
        for c, name in enumerate("xyz"):
            charts.append(
                Chart(
                    f"momentum exchange, body {name} axis: J w, h and J w + h",
                    "kg m^2/s",
                    {
                        f"(J w)_{name}": jw[:, c],
                        f"h_{name}": h[:, c],
                        f"(J w + h)_{name}": jw[:, c] + h[:, c],
                    },
                )  # fmt: skip
            )
        charts.append(
            Chart(
                "momentum norms: |J w|, |h|, |K|",
                "kg m^2/s",
                {
                    "|J w|": np.linalg.norm(jw, axis=-1),
                    "|h|": np.linalg.norm(h, axis=-1),
                    "|K|": np.linalg.norm(np.asarray(tr.momentum), axis=-1),
                },
            )  # fmt: skip
        )
        if not spec.rotor:
            speeds: dict[str, np.ndarray] = {}
            dashed = []
            for i in range(spec.axes.shape[0]):
                speeds[f"Omega_{i}"] = tr.wheel_speed[:, i]
                if np.isfinite(spec.max_speed[i]):
                    for sign in (1.0, -1.0):
                        label = f"{'+' if sign > 0 else '-'}max_speed {i}"
                        speeds[label] = np.full(n, sign * spec.max_speed[i])
                        dashed.append(label)
            charts.append(Chart("wheel speeds and their limits", "rad/s", speeds, tuple(dashed)))
            charts.append(
                Chart(
                    "motor torques",
                    "N m",
                    {f"u_{i}": tr.motor_torque[:, i] for i in range(spec.axes.shape[0])},
                )
            )
        spec_out = _rigid.rigid_report(result)
        return dataclasses.replace(spec_out, charts=tuple(charts) + tuple(spec_out.charts))


KIND = Gyrostat()
