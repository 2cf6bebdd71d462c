"""Running a scenario: solve it with the library, then write its outputs atomically.

:func:`simulate_scenario` turns a :class:`~.schema.Scenario` into trajectories and a
summary (no files); :func:`write_outputs` writes ``trajectory.csv`` (or ``.npz``),
the PNG figures, ``report.html`` and ``summary.json`` (last, so that its presence
marks a complete run) into an output directory, every file through a temporary
name in the same directory and :func:`os.replace`; :func:`run_scenario` does both.

The physics lives in the library: :func:`poinsot.dynamics.free_body.FreeRigidBody`
(exact torque-free motion), :func:`poinsot.dynamics.euler_equations.simulate`
(Euler's equations, SPEC S10) and :func:`poinsot.kinematics.propagate`
(Poisson's equation, SPEC S5). This module only wires the scenario to them.
"""

from __future__ import annotations

import dataclasses
import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError, InvalidTypeError
from ..trajectory import Trajectory
from .schema import Scenario

__all__ = [
    "ScenarioResult",
    "simulate_scenario",
    "write_outputs",
    "run_scenario",
    "prepare_output_dir",
    "CONVENTIONS",
    "coning_quat",
    "coning_omega",
    "describe",
    "describe_scenario",
    "versions",
]

#: The conventions of every output, in one line.
CONVENTIONS = (
    "Hamilton quaternions, scalar first (w, x, y, z); attitude R maps body to space "
    "components (v_space = R v_body); omega in body axes (rad/s); angular momentum K in "
    "space axes (kg m^2/s); SI units; angles in radians."
)

#: Every file a run may write; a forced rerun removes those it does not rewrite.
OUTPUT_FILES = (
    "trajectory.csv",
    "trajectory.npz",
    "reference.csv",
    "reference.npz",
    "omega.png",
    "invariants.png",
    "maccullagh.png",
    "poinsot.png",
    "report.html",
    "summary.json",
)

#: Above this many output samples a numerical run is done in chunks (progress reports).
_CHUNK_SAMPLES = 1000
_N_CHUNKS = 40

Progress = Callable[[float, str], None]


@dataclass(frozen=True, eq=False)
class ScenarioResult:
    """Outcome of :func:`simulate_scenario`.

    Attributes
    ----------
    scenario : Scenario
        The scenario run (with any override applied).
    trajectory : Trajectory
        The motion computed by ``simulation.method``.
    reference : Trajectory or None
        The motion computed by ``simulation.reference``, on the same times.
    summary : dict
        JSON-serialisable summary (written as ``summary.json``).
    potential : ndarray or None
        Potential energy (J) at each sample of ``trajectory`` (gravity scenarios).
    """

    scenario: Scenario
    trajectory: Trajectory
    reference: Trajectory | None
    summary: dict
    potential: np.ndarray | None = None


# ----------------------------------------------------------------------------- solving
def _quiet_progress(fraction: float, stage: str) -> None:
    pass


def _span(progress: Progress, lo: float, hi: float) -> Progress:
    """Map the fractions ``[0, 1]`` of one stage onto ``[lo, hi]`` of the whole run."""
    return lambda fraction, stage: progress(lo + (hi - lo) * fraction, stage)


def _body_inertia(scenario: Scenario) -> np.ndarray:
    """Inertia used by the equations of motion: about the centre of mass for a free
    or torqued body, about the fixed point (the body origin) under gravity."""
    body = scenario.body
    if scenario.torque.model == "gravity":
        return body.inertia_about_origin()
    return np.asarray(body.inertia)


def _torque(scenario: Scenario):
    """The torque model as ``simulate`` takes it: None, a body vector or a callable."""
    tq = scenario.torque
    if tq.model == "none":
        return None
    if tq.model == "body":
        return np.asarray(tq.vector)
    if tq.model == "space":
        m_n = np.asarray(tq.vector)

        def space_torque(t, rotation, omega):
            return _rotation_of(rotation).apply(m_n, inverse=True)

        return space_torque
    # gravity about the fixed point O (the body origin): M_b = r_c x (R^T m g_n)
    weight_n = scenario.body.mass * np.array([0.0, 0.0, -tq.g])
    r_c = np.asarray(scenario.body.center_of_mass)

    def gravity_torque(t, rotation, omega):
        return np.cross(r_c, _rotation_of(rotation).apply(weight_n, inverse=True))

    return gravity_torque


def _rotation_of(rotation):
    from ..rotations.rotation import Rotation

    if isinstance(rotation, Rotation):
        return rotation
    return Rotation.from_quat(rotation)


def _solve_dynamics(
    scenario: Scenario, method: str, t: np.ndarray, progress: Progress
) -> Trajectory:
    r0 = scenario.attitude.rotation
    w0 = np.asarray(scenario.angular_velocity.omega_body)
    inertia = _body_inertia(scenario)
    if method == "exact":
        from ..dynamics import FreeRigidBody

        fb = FreeRigidBody(inertia, w0, r0)
        progress(0.0, "exact solution")
        tr = fb.trajectory(t)
        progress(1.0, "exact solution")
        return tr
    from ..dynamics import simulate

    torque = _torque(scenario)
    return _chunked(
        lambda rot, w, tt: simulate(
            inertia, rot, w, tt, torque=torque, method=method, max_step=scenario.simulation.max_step
        ),
        r0,
        w0,
        t,
        progress,
        f"integrating ({method})",
    )


def _chunked(solve, r0, w0, t: np.ndarray, progress: Progress, stage: str) -> Trajectory:
    """Run ``solve(r0, w0, t)`` in consecutive chunks of ``t`` to report progress.

    Each chunk starts from the last state of the previous one, so a fixed-step method
    advances exactly as in one call (the step is tied to the output spacing).
    """
    n = t.size
    if n <= _CHUNK_SAMPLES:
        progress(0.0, stage)
        tr = solve(r0, w0, t)
        progress(1.0, stage)
        return tr
    edges = np.unique(np.linspace(0, n - 1, _N_CHUNKS + 1).round().astype(int))
    parts: list[Trajectory] = []
    rot, w = r0, w0
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        progress(k / (len(edges) - 1), stage)
        tr = solve(rot, w, t[a : b + 1])
        parts.append(tr)
        rot, w = tr.rotation[-1], np.asarray(tr.omega[-1])
    progress(1.0, stage)
    return _concatenate(parts)


def _concatenate(parts: list[Trajectory]) -> Trajectory:
    from ..rotations.rotation import Rotation

    def cat(name):
        arrays = [getattr(p, name) for p in parts]
        if any(a is None for a in arrays):
            return None
        return np.concatenate([arrays[0]] + [a[1:] for a in arrays[1:]])

    rotation = Rotation.concatenate([parts[0].rotation] + [p.rotation[1:] for p in parts[1:]])
    info = dict(parts[-1].info)
    info["chunks"] = len(parts)
    return Trajectory(
        cat("t"),
        rotation,
        cat("omega"),
        parts[0].method,
        energy=cat("energy"),
        momentum=cat("momentum"),
        info=info,
    )


def coning_quat(half_angle: float, rate: float, t) -> np.ndarray:
    """Attitude of classical coning motion, ``q_c(t) = (cos a/2, sin a/2 cos W t,
    sin a/2 sin W t, 0)`` (scalar first).

    Its body angular velocity ``w = 2 q_c~ o q_c'`` (SPEC S5) is
    ``(-W sin a sin W t, W sin a cos W t, -2 W sin^2(a/2))``: the axis ``z`` of the body
    describes a cone of half-angle ``a`` at rate ``W`` (rad/s).

    **Convention:** scalar-first quaternion, body -> space; angles in radians.

    Examples
    --------
    >>> coning_quat(0.2, 3.0, [0.0]).round(4)
    array([[0.995 , 0.0998, 0.    , 0.    ]])
    """
    t = np.asarray(t, dtype=float)
    c, s = np.cos(half_angle / 2.0), np.sin(half_angle / 2.0)
    phase = rate * t
    return np.stack(
        [np.full_like(t, c), s * np.cos(phase), s * np.sin(phase), np.zeros_like(t)], axis=-1
    )


def coning_omega(half_angle: float, rate: float, t) -> np.ndarray:
    """Body angular velocity of :func:`coning_quat` (rad/s), shape ``t.shape + (3,)``.

    Examples
    --------
    >>> coning_omega(np.pi / 2, 1.0, 0.0).round(6) + 0.0
    array([ 0.,  1., -1.])
    """
    t = np.asarray(t, dtype=float)
    phase = rate * t
    return np.stack(
        [
            -rate * np.sin(half_angle) * np.sin(phase),
            rate * np.sin(half_angle) * np.cos(phase),
            np.full_like(t, -2.0 * rate * np.sin(half_angle / 2.0) ** 2),
        ],
        axis=-1,
    )


def _omega_callable(profile):
    if profile.kind == "constant":
        w = np.asarray(profile.vector)
        return lambda t: w
    if profile.kind == "coning":
        return lambda t: coning_omega(profile.half_angle, profile.rate, t)
    ts, ws = np.asarray(profile.t), np.asarray(profile.omega)

    def sampled(t):
        # linear interpolation of the table (the times are checked to lie inside it)
        return np.array([np.interp(t, ts, ws[:, k]) for k in range(3)])

    return sampled


def _solve_kinematics(
    scenario: Scenario, method: str, t: np.ndarray, progress: Progress
) -> Trajectory:
    from ..kinematics import propagate
    from ..rotations.rotation import Rotation

    profile = scenario.omega_profile
    r0 = scenario.attitude.rotation
    if method == "exact" and profile.kind == "coning":
        from ..rotations import quaternion as qa

        qc = coning_quat(profile.half_angle, profile.rate, t)
        q = qa.multiply(qa.multiply(r0.as_quat(), qa.conjugate(qc[0])), qc)
        omega_b = coning_omega(profile.half_angle, profile.rate, t)
        progress(1.0, "exact solution")
        return Trajectory(
            t,
            Rotation.from_quat(q),
            omega_b,
            "exact",
            info={"frame": "body", "closed_form": "coning"},
        )
    omega = _omega_callable(profile)
    return _chunked(
        lambda rot, w, tt: propagate(
            rot,
            omega,
            tt,
            frame=profile.frame,
            method=method,
            max_step=scenario.simulation.max_step,
        ),
        r0,
        None,
        t,
        progress,
        f"propagating ({method})",
    )


def _with_invariants(scenario: Scenario, tr: Trajectory) -> Trajectory:
    """Add kinetic energy and angular momentum to a kinematic trajectory when the
    scenario gives a body (``T = w.J w / 2``, ``K = R J w``, SPEC S8)."""
    if scenario.body is None or tr.energy is not None:
        return tr
    j = np.asarray(scenario.body.inertia)
    jw = np.asarray(tr.omega) @ j.T
    energy = 0.5 * np.einsum("...i,...i->...", tr.omega, jw)
    momentum = tr.rotation.apply(jw)
    return dataclasses.replace(tr, energy=energy, momentum=momentum)


def _solve(scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Trajectory:
    if scenario.kind == "kinematics":
        return _with_invariants(scenario, _solve_kinematics(scenario, method, t, progress))
    return _solve_dynamics(scenario, method, t, progress)


def _override(scenario: Scenario, duration: float | None) -> Scenario:
    if duration is None:
        return scenario
    if not (isinstance(duration, int | float) and np.isfinite(duration) and duration > 0):
        raise InvalidInputError(f"Expected `duration` to be a positive number, got {duration!r}.")
    sim = scenario.simulation
    p = scenario.omega_profile
    if p is not None and p.kind == "samples" and duration > p.t[-1]:
        raise InvalidInputError(
            f"Expected `duration` to be at most the last time of the angular-velocity table "
            f"({p.t[-1]:g} s), got {duration:g}."
        )
    step = sim.step if sim.step is None else min(sim.step, duration)
    return dataclasses.replace(
        scenario, simulation=dataclasses.replace(sim, duration=float(duration), step=step)
    )


def simulate_scenario(
    scenario: Scenario, *, duration: float | None = None, progress: Progress | None = None
) -> ScenarioResult:
    """Solve a scenario with the library (no files written).

    Parameters
    ----------
    scenario : Scenario
        From :func:`poinsot.scenarios.load_scenario`.
    duration : float, optional
        Override of ``[simulation] duration`` (s), e.g. for a quick look.
    progress : callable, optional
        ``progress(fraction, stage)`` called as the computation advances.

    Returns
    -------
    ScenarioResult

    Notes
    -----
    **Convention:** see :data:`CONVENTIONS`.

    Examples
    --------
    >>> from poinsot.scenarios import parse_scenario, simulate_scenario
    >>> s = parse_scenario('''
    ... [body]
    ... mass = 1.0
    ... inertia = [1.0, 2.0, 3.0]
    ... [angular_velocity]
    ... vector = [0.0, 0.0, 1.0]
    ... frame = "body"
    ... [simulation]
    ... duration = 1.0
    ... samples = 11
    ... method = "exact"
    ... ''')
    >>> r = simulate_scenario(s)
    >>> round(r.summary["invariants"]["energy"]["initial"], 6)
    1.5
    """
    _expect(scenario, Scenario, "scenario", "a Scenario (from load_scenario/parse_scenario)")
    scenario = _override(scenario, duration)
    progress = progress or _quiet_progress
    t = scenario.simulation.times()
    start = time.perf_counter()
    has_ref = scenario.simulation.reference is not None
    tr = _solve(
        scenario, scenario.simulation.method, t, _span(progress, 0.0, 0.5 if has_ref else 1.0)
    )
    wall = time.perf_counter() - start
    ref = None
    if scenario.simulation.reference is not None:
        ref = _solve(scenario, scenario.simulation.reference, t, _span(progress, 0.5, 1.0))
    potential = _potential(scenario, tr)
    summary = _summary(scenario, tr, ref, potential, wall)
    return ScenarioResult(scenario, tr, ref, summary, potential)


def _potential(scenario: Scenario, tr: Trajectory) -> np.ndarray | None:
    """Potential energy of gravity ``V = m g z_c`` (``g`` along ``-z`` of space), or None."""
    if scenario.torque.model != "gravity":
        return None
    r_c_n = tr.rotation.apply(np.asarray(scenario.body.center_of_mass))
    return scenario.body.mass * scenario.torque.g * r_c_n[:, 2]


# ----------------------------------------------------------------------------- summary
def _f(x) -> Any:
    """JSON-friendly floats/lists."""
    a = np.asarray(x, dtype=float)
    return float(a) if a.ndim == 0 else a.tolist()


def _rel_drift(values: np.ndarray, scale: float | None = None) -> float:
    values = np.asarray(values, dtype=float)
    scale = abs(values[0]) if scale is None else scale
    d = np.max(np.abs(values - values[0]), initial=0.0)
    return float(d / scale) if scale > 0 else float(d)


def _invariants(scenario: Scenario, tr: Trajectory, potential) -> dict:
    out: dict[str, Any] = {}
    model = scenario.torque.model
    if tr.energy is None:
        out["note"] = "no body given: energy and angular momentum are not computed"
        return out
    energy, k = np.asarray(tr.energy), np.asarray(tr.momentum)
    if model == "gravity":
        total = energy + potential
        scale = max(abs(total[0]), abs(energy[0]), 1e-300)
        out["total_energy"] = {
            "initial": _f(total[0]),
            "units": "J",
            "max_relative_drift": _rel_drift(total, scale),
            "conserved": True,
        }
        out["momentum_z"] = {
            "initial": _f(k[0, 2]),
            "units": "kg m^2/s",
            "max_relative_drift": _rel_drift(k[:, 2], np.linalg.norm(k[0])),
            "conserved": True,
        }
        from ._lagrange import lagrange_top

        if lagrange_top(
            scenario.body.inertia_about_origin(),
            scenario.body.mass,
            scenario.body.center_of_mass,
            scenario.torque.g,
            scenario.attitude.quat,
            scenario.angular_velocity.omega_body,
        ):
            # Lagrange top: the momentum about the symmetry axis, H = C r, is conserved
            e = np.asarray(scenario.body.center_of_mass)
            e = e / np.linalg.norm(e)
            h = np.asarray(tr.omega) @ (scenario.body.inertia_about_origin() @ e)
            out["spin_momentum_H"] = {
                "initial": _f(h[0]),
                "units": "kg m^2/s",
                "max_relative_drift": _rel_drift(h, np.linalg.norm(k[0])),
                "conserved": True,
            }
        return out
    conserved = model == "none" and scenario.kind == "dynamics"
    kn = np.linalg.norm(k, axis=-1)
    out["energy"] = {
        "initial": _f(energy[0]),
        "final": _f(energy[-1]),
        "units": "J",
        "max_relative_drift": _rel_drift(energy),
        "conserved": conserved,
    }
    out["momentum_norm"] = {
        "initial": _f(kn[0]),
        "final": _f(kn[-1]),
        "units": "kg m^2/s",
        "max_relative_drift": _rel_drift(kn),
        "conserved": conserved,
    }
    out["momentum_vector"] = {
        "initial": _f(k[0]),
        "final": _f(k[-1]),
        "units": "kg m^2/s",
        "max_relative_drift": float(np.max(np.linalg.norm(k - k[0], axis=-1)) / kn[0])
        if kn[0] > 0
        else 0.0,
        "conserved": conserved,
    }
    if model == "space":
        # dK/dt = M (space axes), so K(t) = K0 + M t exactly (SPEC S9)
        m_n = np.asarray(scenario.torque.vector)
        expected = k[0] + np.outer(tr.t - tr.t[0], m_n)
        err = np.max(np.linalg.norm(k - expected, axis=-1))
        out["momentum_balance"] = {
            "law": "K(t) = K(0) + M t (constant space torque)",
            "max_error": float(err),
            "max_relative_error": float(
                err / max(np.max(np.linalg.norm(expected, axis=-1)), 1e-300)
            ),
        }
    if not conserved:
        out["note"] = (
            "energy and angular momentum are not conserved here (torque or "
            "prescribed angular velocity); the drifts are their changes"
        )
    return out


def _closed_form(scenario: Scenario) -> dict:
    if scenario.kind == "kinematics":
        p = scenario.omega_profile
        if p.kind == "constant":
            rate = float(np.linalg.norm(p.vector))
            return {
                "rotation_rate": rate,
                "period": 2 * np.pi / rate if rate > 0 else None,
                "axis": _f(np.asarray(p.vector) / rate) if rate > 0 else None,
            }
        if p.kind == "coning":
            return {
                "coning_half_angle": p.half_angle,
                "coning_rate": p.rate,
                "period": 2 * np.pi / abs(p.rate) if p.rate else None,
                "note": "the attitude is periodic: q(t + period) = q(t)",
            }
        return {}
    if scenario.torque.model == "gravity":
        from ._lagrange import lagrange_top

        props = lagrange_top(
            scenario.body.inertia_about_origin(),
            scenario.body.mass,
            scenario.body.center_of_mass,
            scenario.torque.g,
            scenario.attitude.quat,
            scenario.angular_velocity.omega_body,
        )
        return {} if props is None else _jsonable(props)
    if scenario.torque.model != "none":
        return {}
    try:
        from ..dynamics import FreeRigidBody
    except ImportError:  # pragma: no cover - module arrives with the dynamics area
        return {"note": "poinsot.dynamics.free_body not available"}
    fb = FreeRigidBody(
        np.asarray(scenario.body.inertia),
        np.asarray(scenario.angular_velocity.omega_body),
        scenario.attitude.rotation,
    )
    out = {"solution": "Jacobi elliptic functions (SPEC S10)"}
    for key in (
        "energy",
        "momentum",
        "momentum_norm",
        "principal_moments",
        "principal_axes",
        "regime",
        "polhode_axis",
        "stable_axes",
        "period",
        "precession_per_period",
        "complementary_parameter",
    ):
        try:
            out[key] = getattr(fb, key)
        except AttributeError:  # pragma: no cover - depends on the dynamics area
            continue
    m = np.asarray(out.get("principal_moments", []))
    if m.size == 3 and (m[0] == m[1] or m[1] == m[2]) and m[0] != m[2]:
        # symmetric body: regular precession about K at psi' = K / A (SPEC S10)
        a = m[0] if m[0] == m[1] else m[1]
        out["precession_rate"] = out["momentum_norm"] / a
    return _jsonable(out)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray | np.generic):
        return _jsonable(obj.tolist())
    if isinstance(obj, float) and not np.isfinite(obj):
        return None if np.isnan(obj) else ("inf" if obj > 0 else "-inf")
    if obj is None or isinstance(obj, bool | int | float | str):
        return obj
    return str(obj)


def _comparison(tr: Trajectory, ref: Trajectory | None) -> dict | None:
    if ref is None:
        return None
    err = (ref.rotation.inv() * tr.rotation).magnitude()
    dw = np.linalg.norm(np.asarray(tr.omega) - np.asarray(ref.omega), axis=-1)
    wmax = float(np.max(np.linalg.norm(ref.omega, axis=-1)))
    return {
        "reference": ref.method,
        "max_attitude_error_rad": float(np.max(err)),
        "final_attitude_error_rad": float(err[-1]),
        "max_omega_error": float(np.max(dw)),
        "max_relative_omega_error": float(np.max(dw) / wmax) if wmax > 0 else None,
    }


def versions() -> dict:
    """Versions of poinsot, Python, NumPy and SciPy (for ``summary.json``)."""
    import scipy

    from .. import __version__

    return {
        "poinsot": __version__,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
    }


def _summary(scenario: Scenario, tr: Trajectory, ref, potential, wall: float) -> dict:
    sim = scenario.simulation
    body = None
    if scenario.body is not None:
        from ..mass import principal_axes

        moments, axes = principal_axes(np.asarray(scenario.body.inertia))
        body = {
            "mass": scenario.body.mass,
            "inertia": _f(scenario.body.inertia),
            "center_of_mass": _f(scenario.body.center_of_mass),
            "principal_moments": _f(moments),
            "principal_axes_columns": _f(axes.as_matrix()),
            "shape": scenario.body.shape,
            "dims": scenario.body.dims,
            "parts": [p.name for p in scenario.body.parts] or None,
        }
        if scenario.torque.model == "gravity":
            body["inertia_about_fixed_point"] = _f(scenario.body.inertia_about_origin())
    out = {
        "scenario": {
            "name": scenario.name,
            "description": scenario.description,
            "source": scenario.source,
            "kind": scenario.kind,
            "file": _jsonable(scenario.data),
        },
        "conventions": CONVENTIONS,
        "method": tr.method,
        "reference_method": None if ref is None else ref.method,
        "times": {
            "duration": sim.duration,
            "samples": int(tr.t.size),
            "step": sim.step,
            "units": "s",
        },
        "initial": {
            "quat": _f(scenario.attitude.quat),
            "omega_body": _f(tr.omega[0]),
            "omega_space": _f(tr.rotation[0].apply(tr.omega[0])),
        },
        "torque": {
            "model": scenario.torque.model,
            "vector": None if scenario.torque.vector is None else _f(scenario.torque.vector),
            "g": scenario.torque.g,
        },
        "body": body,
        "invariants": _invariants(scenario, tr, potential),
        "reference_invariants": None
        if ref is None
        else _invariants(scenario, ref, _potential(scenario, ref)),
        "closed_form": _closed_form(scenario),
        "comparison": _comparison(tr, ref),
        "run": {"wall_time_s": wall, "info": _jsonable(dict(tr.info))},
        "versions": versions(),
        "notes": [],
    }
    return out


# ----------------------------------------------------------------------------- writing
def _expect(value, kind, name: str, what: str) -> None:
    if not isinstance(value, kind):
        raise InvalidTypeError(f"Expected `{name}` to be {what}, got {type(value).__name__}.")


def prepare_output_dir(out, *, force: bool = False) -> Path:
    """Create the output directory; refuse to overwrite a non-empty one unless ``force``.

    Raises
    ------
    InvalidInputError
        ``out`` is a file, or a non-empty directory and ``force`` is false.
    """
    _expect(out, str | os.PathLike, "out", "a str or os.PathLike")
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InvalidInputError(f"Output path {str(out)!r} exists and is not a directory.")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise InvalidInputError(
            f"Output directory {str(out)!r} already exists and is not "
            "empty; pass --force to overwrite its files, or choose "
            "another --out."
        )
    out.mkdir(parents=True, exist_ok=True)
    return out


def _atomic(path: Path, write: Callable[[Any], None], mode: str = "w") -> Path:
    """Write ``path`` through a temporary file in the same directory, then rename."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.partial")
    try:
        if mode == "w":
            with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
                write(fh)
                fh.flush()
                os.fsync(fh.fileno())
        else:
            with open(tmp, "wb") as fh:
                write(fh)
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _columns(result: ScenarioResult, tr: Trajectory) -> tuple[list[str], list[str], np.ndarray]:
    names = ["t", "qw", "qx", "qy", "qz", "wx", "wy", "wz"]
    units = ["s"] + ["1"] * 4 + ["rad/s"] * 3
    cols = [tr.t[:, None], tr.quat, tr.omega]
    if tr.momentum is not None:
        names += ["Kx", "Ky", "Kz", "T"]
        units += ["kg m^2/s"] * 3 + ["J"]
        cols += [tr.momentum, tr.energy[:, None]]
    if result.potential is not None and tr is result.trajectory:
        names.append("V")
        units.append("J")
        cols.append(result.potential[:, None])
    return names, units, np.hstack(cols)


def _header(result: ScenarioResult, tr: Trajectory, names, units) -> list[str]:
    s = result.scenario
    point = (
        "the fixed point (origin of the body axes)"
        if s.torque.model == "gravity"
        else "the centre of mass"
    )
    lines = [
        f"poinsot {versions()['poinsot']} trajectory of scenario {s.name!r} "
        f"(method {tr.method}, {tr.t.size} samples)",
        "conventions: " + CONVENTIONS,
        "t: time (s); qw,qx,qy,qz: unit quaternion of the attitude, scalar first, body -> "
        "space (v_space = q o v_body o q~)",
        "wx,wy,wz: angular velocity in BODY axes (rad/s)",
    ]
    if "Kx" in names:
        lines += [
            f"Kx,Ky,Kz: angular momentum about {point} in SPACE axes (kg m^2/s)",
            "T: rotational kinetic energy (J)",
        ]
    if "V" in names:
        lines.append("V: potential energy of gravity m g z_c, g along -z of space (J)")
    lines.append("units: " + ",".join(units))
    lines.append(",".join(names))
    return lines


def _write_trajectory(result: ScenarioResult, tr: Trajectory, path: Path, fmt: str) -> Path:
    names, units, data = _columns(result, tr)
    header = _header(result, tr, names, units)
    if fmt == "csv":

        def write(fh):
            fh.write("".join(f"# {line}\n" for line in header))
            rows = data.tolist()
            for k in range(0, len(rows), 10000):  # repr: shortest round-trip decimal
                fh.write("".join(",".join(map(repr, r)) + "\n" for r in rows[k : k + 10000]))

        return _atomic(path, write)

    arrays = {"t": tr.t, "quat": tr.quat, "omega_body": np.asarray(tr.omega)}
    if tr.momentum is not None:
        arrays["momentum_space"] = np.asarray(tr.momentum)
        arrays["energy"] = np.asarray(tr.energy)
    if "V" in names:
        arrays["potential"] = result.potential
    arrays["header"] = np.array("\n".join(header))
    return _atomic(path, lambda fh: np.savez(fh, **arrays), mode="b")


def _figures(result: ScenarioResult, out: Path, notes: list[str]) -> list[Path]:
    try:
        import matplotlib
    except ImportError:
        notes.append("figures skipped: matplotlib is not installed (pip install 'poinsot[plot]')")
        return []
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    tr, ref = result.trajectory, result.reference
    files = []

    def save(fig, name):
        def write(fh):
            fig.savefig(fh, format="png", dpi=110)

        files.append(_atomic(out / name, write, mode="b"))
        plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 3.6), layout="constrained")
    for k, (label, colour) in enumerate(zip("xyz", ("C3", "C2", "C0"), strict=True)):
        ax.plot(tr.t, tr.omega[:, k], color=colour, label=f"$\\omega_{label}$ ({tr.method})")
        if ref is not None:
            ax.plot(
                ref.t,
                ref.omega[:, k],
                color=colour,
                ls="--",
                lw=1,
                label=f"$\\omega_{label}$ ({ref.method})",
            )
    ax.set(
        xlabel="t (s)",
        ylabel="angular velocity, body axes (rad/s)",
        title=f"{result.scenario.name}: angular velocity",
    )
    ax.legend(fontsize=7, ncol=2 if ref is not None else 1)
    ax.grid(alpha=0.3)
    save(fig, "omega.png")

    if tr.energy is not None:
        fig, ax = plt.subplots(figsize=(7, 3.6), layout="constrained")
        if result.potential is not None:
            total = tr.energy + result.potential
            scale = max(abs(total[0]), abs(tr.energy[0]))
            ax.plot(tr.t, (total - total[0]) / scale, label="total energy T + V")
            kz = tr.momentum[:, 2]
            ax.plot(tr.t, (kz - kz[0]) / np.linalg.norm(tr.momentum[0]), label="$K_z$")
            title = "invariants of the heavy top (relative change)"
        else:
            e0 = abs(tr.energy[0]) or 1.0
            kn = np.linalg.norm(tr.momentum, axis=-1)
            ax.plot(tr.t, (tr.energy - tr.energy[0]) / e0, label=f"kinetic energy T ({tr.method})")
            ax.plot(tr.t, (kn - kn[0]) / (kn[0] or 1.0), label=f"|K| ({tr.method})")
            if ref is not None and ref.energy is not None:
                kr = np.linalg.norm(ref.momentum, axis=-1)
                ax.plot(
                    ref.t,
                    (ref.energy - ref.energy[0]) / e0,
                    color="C0",
                    ls="--",
                    lw=1,
                    label=f"T ({ref.method})",
                )
                ax.plot(
                    ref.t,
                    (kr - kr[0]) / (kr[0] or 1.0),
                    color="C1",
                    ls="--",
                    lw=1,
                    label=f"|K| ({ref.method})",
                )
            title = "energy and |K| (relative change)"
        ax.set(xlabel="t (s)", ylabel="relative change", title=title)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        save(fig, "invariants.png")

    if result.scenario.kind == "dynamics" and result.scenario.torque.model == "none":
        try:
            from ..plotting import free_body as fbp
        except ImportError:
            notes.append(
                "MacCullagh/Poinsot figures skipped: poinsot.plotting.free_body is not available"
            )
        else:
            from ..dynamics import FreeRigidBody

            fb = FreeRigidBody(
                np.asarray(result.scenario.body.inertia),
                np.asarray(result.scenario.angular_velocity.omega_body),
                result.scenario.attitude.rotation,
            )
            for name, draw in (
                ("maccullagh.png", lambda: fbp.plot_maccullagh(fb)),
                ("poinsot.png", lambda: fbp.plot_poinsot(fb, tr.t[:: max(1, tr.t.size // 800)])),
            ):
                try:
                    ax = draw()
                except Exception as exc:  # a figure must not sink the run
                    notes.append(f"{name} skipped: {type(exc).__name__}: {exc}")
                    plt.close("all")
                    continue
                save(ax.figure, name)
    return files


def _report(result: ScenarioResult, out: Path, notes: list[str]) -> list[Path]:
    try:
        from ..plotting.report import write_report
    except ImportError as exc:
        notes.append(f"report.html skipped: {exc}")
        return []
    s = result.scenario
    shape = None
    inertia = None
    if s.body is not None:
        # the report draws the body centred on the origin of the body axes: the solid
        # itself when its centre of mass is there, else the inertia ellipsoid about the
        # origin (the fixed point under gravity)
        centred = not np.any(s.body.center_of_mass)
        if centred and s.body.shape in ("box", "ellipsoid", "sphere", "cylinder"):
            shape = {"kind": s.body.shape, "dims": list(s.body.dims)}
        inertia = _body_inertia(s) if s.kind == "dynamics" else np.asarray(s.body.inertia)
    title = f"poinsot: {s.name}" + (f" ({s.description})" if s.description else "")
    try:
        path = write_report(
            out / "report.html",
            trajectory=result.trajectory,
            summary=result.summary,
            title=title,
            shape=shape,
            inertia=inertia,
            reference=result.reference,
        )
    except ImportError as exc:  # plotly is an optional dependency
        notes.append(f"report.html skipped: {exc} (pip install 'poinsot[plot]')")
        return []
    return [path]


def write_outputs(
    result: ScenarioResult,
    out,
    *,
    fmt: str = "csv",
    report: bool = True,
    figures: bool = True,
    force: bool = False,
    progress: Progress | None = None,
) -> list[Path]:
    """Write the outputs of a run into directory ``out``.

    Files: ``trajectory.csv`` or ``trajectory.npz`` (and ``reference.csv``/``.npz``
    with a reference method), ``omega.png``, ``invariants.png`` (and the MacCullagh
    and Poinsot pictures for a free body), ``report.html`` and, last,
    ``summary.json``. Each file is written to a temporary name in ``out`` and renamed.

    Raises
    ------
    InvalidInputError
        ``fmt`` is not ``"csv"`` or ``"npz"``; ``out`` exists, is not empty and
        ``force`` is false.

    Notes
    -----
    **Convention:** see :data:`CONVENTIONS` (written in the files' headers).
    """
    _expect(result, ScenarioResult, "result", "a ScenarioResult (from simulate_scenario)")
    if fmt not in ("csv", "npz"):
        raise InvalidInputError(f"Expected `format` to be one of 'csv', 'npz', got {fmt!r}.")
    progress = progress or _quiet_progress
    out = prepare_output_dir(out, force=force)
    # a forced rerun first removes the old summary, so that the directory never looks
    # complete until the new summary is written
    (out / "summary.json").unlink(missing_ok=True)
    notes = result.summary.setdefault("notes", [])
    files = [_write_trajectory(result, result.trajectory, out / f"trajectory.{fmt}", fmt)]
    if result.reference is not None:
        files.append(_write_trajectory(result, result.reference, out / f"reference.{fmt}", fmt))
    progress(0.0, "writing the trajectory")
    if figures:
        progress(0.2, "figures")
        files += _figures(result, out, notes)
    if report:
        progress(0.5, "report")
        files += _report(result, out, notes)
    else:
        notes.append("report.html not written (--no-report)")
    summary_path = out / "summary.json"
    result.summary["files"] = [p.name for p in files] + [summary_path.name]
    files.append(
        _atomic(
            summary_path,
            lambda fh: json.dump(_jsonable(result.summary), fh, indent=2, allow_nan=False),
        )
    )
    for name in OUTPUT_FILES:  # outputs of an earlier run that this one did not rewrite
        if name not in result.summary["files"]:
            (out / name).unlink(missing_ok=True)
    progress(1.0, "done")
    return files


def run_scenario(
    scenario: Scenario,
    out,
    *,
    fmt: str = "csv",
    report: bool = True,
    force: bool = False,
    duration: float | None = None,
    progress: Progress | None = None,
    figures: bool = True,
) -> tuple[ScenarioResult, list[Path]]:
    """Solve ``scenario`` and write its outputs into ``out`` (see :func:`write_outputs`).

    The output directory is checked before the computation, so a refused overwrite
    costs nothing.

    Examples
    --------
    >>> import tempfile, pathlib, json
    >>> from poinsot.scenarios import demo_scenario, run_scenario
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "demo"
    >>> result, files = run_scenario(demo_scenario(), out, report=False, figures=False,
    ...                              duration=1.0)
    >>> sorted(p.name for p in files)
    ['reference.csv', 'summary.json', 'trajectory.csv']
    """
    _expect(scenario, Scenario, "scenario", "a Scenario (from load_scenario/parse_scenario)")
    if fmt not in ("csv", "npz"):
        raise InvalidInputError(f"Expected `format` to be one of 'csv', 'npz', got {fmt!r}.")
    prepare_output_dir(out, force=force)
    progress = progress or _quiet_progress
    result = simulate_scenario(scenario, duration=duration, progress=_span(progress, 0.0, 0.8))
    files = write_outputs(
        result,
        out,
        fmt=fmt,
        report=report,
        figures=figures,
        force=True,
        progress=_span(progress, 0.8, 1.0),
    )
    return result, files


# ----------------------------------------------------------------------------- text
def _g(x, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def _vec(v, digits: int = 4) -> str:
    return "[" + ", ".join(_g(float(x) + 0.0, digits) for x in np.asarray(v)) + "]"


def describe_scenario(scenario: Scenario) -> str:
    """One line describing a scenario (used by ``poinsot check``).

    Examples
    --------
    >>> from poinsot.scenarios import demo_scenario
    >>> print(describe_scenario(demo_scenario()))  # doctest: +ELLIPSIS
    scenario 'tennis-racket-flip' (dynamics): box body of 0.35 kg, ...
    """
    sim = scenario.simulation
    n = sim.times().size
    head = f"scenario {scenario.name!r} ({scenario.kind}): "
    parts = []
    b = scenario.body
    if b is not None:
        what = f"{b.shape} body" if b.shape else f"{len(b.parts)}-part body" if b.parts else "body"
        parts.append(f"{what} of {_g(b.mass)} kg")
    if scenario.kind == "dynamics":
        parts.append(f"omega0 {_vec(scenario.angular_velocity.omega_body)} rad/s (body)")
        parts.append(f"torque {scenario.torque.model}")
    else:
        parts.append(
            f"{scenario.omega_profile.kind} angular velocity ({scenario.omega_profile.frame} axes)"
        )
    ref = f", reference {sim.reference}" if sim.reference else ""
    parts.append(f"{n} samples over {_g(sim.duration)} s, method {sim.method}{ref}")
    return head + ", ".join(parts)


def describe(result: ScenarioResult, *, title: str = "poinsot") -> str:
    """A short human summary of a run (printed by ``poinsot run`` and ``poinsot demo``)."""
    s, summ = result.scenario, result.summary
    lines = [f"{title}: {s.name}" + (f" - {s.description}" if s.description else "")]
    lines.append("conventions: " + CONVENTIONS)
    if s.body is not None:
        b = summ["body"]
        shape = (
            f"{s.body.shape} {' x '.join(_g(d) for d in s.body.dims)} m, "
            if s.body.shape
            else f"{len(s.body.parts)} parts, "
            if s.body.parts
            else ""
        )
        lines.append(
            f"body: {shape}{_g(s.body.mass)} kg; principal moments "
            f"{_vec(b['principal_moments'])} kg m^2"
        )
    lines.append(
        f"start: omega {_vec(summ['initial']['omega_body'])} rad/s (body), "
        f"quat {_vec(summ['initial']['quat'])}; {summ['times']['samples']} samples "
        f"over {_g(summ['times']['duration'])} s"
    )
    cf = summ.get("closed_form") or {}
    if "solution" in cf:  # torque-free body
        period = cf.get("period")
        per = (
            f"omega periodic with period {_g(period)} s"
            if isinstance(period, float)
            else "omega not periodic"
        )
        lines.append(
            f"exact solution, {cf['solution']}: T = {_g(cf['energy'])} J, "
            f"|K| = {_g(cf['momentum_norm'])} kg m^2/s, {per}"
        )
        stable, moments = cf.get("stable_axes"), cf.get("principal_moments")
        if stable and moments and len(set(moments)) == 3:
            j = np.asarray(s.body.inertia)
            diag = np.max(np.abs(j - np.diag(np.diag(j)))) <= 1e-12 * np.max(np.abs(j))
            names = [
                f"{'xyz'[k]} ({_g(m)} kg m^2)" if diag else f"the axis of moment {_g(m)}"
                for k, m in enumerate(moments)
            ]
            lines.append(
                "permanent rotations: stable about "
                + " and ".join(n for n, ok in zip(names, stable, strict=True) if ok)
                + ", unstable about "
                + " and ".join(n for n, ok in zip(names, stable, strict=True) if not ok)
                + " (SPEC S10)"
            )
        if "precession_rate" in cf:
            lines.append(f"regular precession about K at {_g(cf['precession_rate'])} rad/s")
    elif "case" in cf:  # Lagrange top
        line = f"{cf['case']}: {cf['motion']}"
        if "nutation_theta_min" in cf:
            line += (
                f", tilt {np.degrees(cf['nutation_theta_min']):.4f} to "
                f"{np.degrees(cf['nutation_theta_max']):.4f} deg"
            )
        if cf.get("nutation_period"):
            line += f", nutation period {_g(cf['nutation_period'])} s"
        line += f"; Maievskii ratio C^2 r^2/(4 A m g l) = {_g(cf['maievskii_ratio'])}"
        lines.append(line)
    else:
        facts = [
            f"{k.replace('_', ' ')} {_g(v) if isinstance(v, float) else v}"
            for k, v in cf.items()
            if isinstance(v, float | int | str) and k != "note"
        ]
        if facts:
            lines.append("closed form: " + "; ".join(facts[:6]))
    inv = summ["invariants"]

    def drifts(inv: dict) -> str:
        kept = [
            f"{k.replace('_', ' ')} drift {v['max_relative_drift']:.2e}"
            for k, v in inv.items()
            if isinstance(v, dict) and "max_relative_drift" in v and v.get("conserved")
        ]
        if kept:
            return "; ".join(kept)
        changes = [
            f"{k.replace('_', ' ')} {_g(v['initial'])} -> {_g(v['final'])} {v['units']}"
            for k, v in inv.items()
            if isinstance(v, dict) and isinstance(v.get("final"), float)
        ]
        return ", ".join(changes) if changes else "done"

    lines.append(f"{summ['method']}: {drifts(inv)} ({summ['run']['wall_time_s']:.2f} s)")
    if summ.get("reference_invariants"):
        lines.append(f"{summ['reference_method']}: {drifts(summ['reference_invariants'])}")
    cmp_ = summ.get("comparison")
    if cmp_:
        lines.append(
            f"vs {cmp_['reference']}: max attitude difference "
            f"{cmp_['max_attitude_error_rad']:.2e} rad, max |omega| difference "
            f"{cmp_['max_omega_error']:.2e} rad/s"
        )
    for note in summ.get("notes", []):
        lines.append(f"note: {note}")
    return "\n".join(lines)
