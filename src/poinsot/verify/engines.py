"""Engine adapters of ``poinsot verify``: run a case, return its states on the case's grid.

An engine follows the :class:`Engine` protocol: a ``name``, a ``label`` (the
settings, e.g. ``"scipy DOP853 rtol=1e-12"``), ``skip_reason(case)`` (None when it can
run the case, else why the case is outside what the engine models: the case is
*skipped*) and ``run(case) -> (result, work)``: the motion as a poinsot result on the
case's grid ``case.t`` -- a :class:`poinsot.Trajectory` for a rigid body (attitude
body -> space, angular velocity in body axes) or a :class:`poinsot.PointTrajectory`
for a point (position, velocity), docs/theory.md §2 -- and the engine's own count of
work (or None). Optionally ``missing_reason(case)``: why an engine that should have
given the case's states did not (e.g. no file): the case is *missing*, which fails
the verdict unless allowed (docs/verify.md). An engine with findings that fail the
case whatever its metrics (e.g. an attitude and angular velocity that are not one
motion) returns them third: ``(result, work, defects)``, a list of strings.
:func:`poinsot.verify.metrics.evaluate` scores the result. (A ``run`` that returns
the former dict of arrays ``{"quat", "omega"}`` / ``{"position", "velocity"}``, with
``"defects"`` among them, still works for one release, with a DeprecationWarning.)

- :class:`SciPyEngine`: ``scipy.integrate.solve_ivp`` (any method, any tolerance) on
  the Euler(-Poisson) equations ``J_O w' + w x J_O w = m c x (R^T g)`` with
  ``q' = q (0, w) / 2`` (docs/theory.md §5, §10), on ``r'' = -mu r / r^3`` for an
  orbit and on the relative motion with the inertial forces for a turning frame
  (§9); the right-hand sides are poinsot's own (:func:`poinsot.dynamics.euler_rhs`,
  :func:`poinsot.kinematics.quat_rate`, :func:`poinsot.dynamics.inertial_forces`).
- :class:`PoinsotEngine`: poinsot's integrators (:func:`poinsot.dynamics.simulate`,
  :meth:`poinsot.dynamics.HeavyRigidBody.simulate`,
  :func:`poinsot.dynamics.simulate_particle`), every registered method.
- :class:`MuJoCoEngine`: MuJoCo (``pip install poinsot[verify]``) with a free joint
  (free bodies) or a ball joint at the fixed point (tops), no contacts.
- :class:`FileEngine`: states that any engine wrote to CSV/Parquet files, one per case
  (``CASE.csv``), with the conventions given as options and checked.
"""

from __future__ import annotations

import math
import time
import warnings
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import InvalidInputError, InvalidTypeError
from ..rotations.rotation import Rotation
from ..trajectory import PointTrajectory, Result, Trajectory
from .cases import Case

ENGINES = ("scipy", "poinsot", "mujoco", "file")


@runtime_checkable
class Engine(Protocol):
    """What ``poinsot verify`` runs a case in (see the module docstring, docs/verify.md).

    ``run(case)`` returns ``(result, work)`` -- or ``(result, work, defects)`` -- with
    ``result`` a :class:`poinsot.Trajectory` (rigid cases) or
    :class:`poinsot.PointTrajectory` (point cases) on ``case.t``. An engine may also
    define ``missing_reason(case)`` (None, or why the case's states are missing).
    """

    name: str
    label: str

    def skip_reason(self, case: Case) -> str | None: ...

    def run(self, case: Case) -> tuple[Any, ...]: ...


def rigid_result(case: Case, quat: Any, omega: Any, method: str) -> Trajectory:
    """A :class:`poinsot.Trajectory` of ``case`` on its grid from scalar-first
    quaternions (body -> space) and body-axes angular velocities, the quaternions
    kept as given (bit for bit: the metrics see exactly the engine's numbers)."""
    q = np.ascontiguousarray(quat, dtype=float)
    return Trajectory(case.t, Rotation._wrap(q), np.asarray(omega, dtype=float), method)


def point_result(case: Case, position: Any, velocity: Any, method: str) -> PointTrajectory:
    """A :class:`poinsot.PointTrajectory` of ``case`` on its grid (m, m/s)."""
    return PointTrajectory(case.t, position, velocity, method)


def as_result(case: Case, states: Any, method: str = "") -> Result:
    """``states`` as a result: a result as it is, a dict of arrays (the form of
    poinsot 1.x engines, deprecated) converted."""
    if isinstance(states, Result):
        return states
    if not isinstance(states, dict):
        raise InvalidTypeError(
            "Expected an engine's states to be a poinsot Trajectory or PointTrajectory, got "
            f"{type(states).__name__}."
        )
    if "quat" in states:
        return rigid_result(case, states["quat"], states["omega"], method)
    return point_result(case, states["position"], states["velocity"], method)


def _deprecated_states() -> None:
    warnings.warn(
        "A dict of states is deprecated: an engine's run(case) returns a poinsot "
        "Trajectory (rigid cases) or PointTrajectory (point cases) on case.t, and "
        "evaluate() reads one (docs/verify.md).",
        DeprecationWarning,
        stacklevel=3,
    )


def _quat_unit(q: np.ndarray) -> np.ndarray:
    from ..kinematics.attitude_history import _make_continuous

    q = np.asarray(q, dtype=float)
    return _make_continuous(q / np.linalg.norm(q, axis=-1, keepdims=True))


class SciPyEngine:
    """``scipy.integrate.solve_ivp`` on the case's equations of motion.

    Parameters
    ----------
    method : str, optional
        A ``solve_ivp`` method (default ``"DOP853"``).
    rtol : float, optional
        Relative tolerance (default 1e-12); ``atol`` defaults to ``rtol * 1e-3``
        (the states are of order 1 in SI units in every case).
    atol : float, optional

    Examples
    --------
    >>> from poinsot.verify import cases, engines, evaluate
    >>> case = cases("free-symmetric")[0]
    >>> result, work = engines.SciPyEngine(rtol=1e-12).run(case)
    >>> evaluate(case, result).status
    'pass'
    """

    name = "scipy"

    def __init__(self, method: str = "DOP853", rtol: float = 1e-12, atol: float | None = None):
        from ..dynamics import PARTICLE_SOLVERS

        solvers = tuple(s for s in PARTICLE_SOLVERS if s != "adaptive")
        if not isinstance(method, str) or method not in solvers:
            raise InvalidInputError(
                f"Expected `method` to be a solve_ivp method ({', '.join(solvers)}), "
                f"got {method!r}."
            )
        self.method = method
        self.rtol = _positive(rtol, "rtol")
        self.atol = self.rtol * 1e-3 if atol is None else _positive(atol, "atol")
        self.label = f"scipy {method} rtol={self.rtol:g}"

    def skip_reason(self, case: Case) -> str | None:
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        from scipy.integrate import solve_ivp

        rhs, y0, unpack = _equations(case)
        sol = solve_ivp(rhs, (case.t[0], case.t[-1]), y0, method=self.method, t_eval=case.t,
                        rtol=self.rtol, atol=self.atol)  # fmt: skip
        if sol.status != 0 or sol.y.shape[1] != case.t.size:
            return _nan_result(case, self.label), int(sol.nfev)
        return as_result(case, unpack(sol.y.T), self.label), int(sol.nfev)


def _equations(case: Case) -> tuple[Any, np.ndarray, Any]:
    """``(rhs(t, y), y0, unpack(y) -> states)`` of the case for a generic ODE solver."""
    i = case.inputs
    if case.kind == "rigid":
        from ..dynamics import GravityTorque, euler_rhs
        from ..kinematics import quat_rate

        jo = case.inertia_about_origin
        g = -float(i["gravity"][2])
        torque = GravityTorque(i["mass"], i["com"], g) if i["fixed_point"] and g else None

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            q, w = y[:4], y[4:]
            m = None if torque is None else torque.body_torque(t, q[None], w[None])[0]
            return np.concatenate([quat_rate(q, w), euler_rhs(jo, w, m)])

        def unpack(y: np.ndarray) -> dict[str, np.ndarray]:
            return {"quat": _quat_unit(y[:, :4]), "omega": y[:, 4:].copy()}

        return rhs, np.concatenate([i["q0"], i["omega0"]]), unpack
    if case.group == "orbit":
        from ..dynamics import kepler

        pot = kepler(i["mu"])

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            r = y[:3]
            rn = math.sqrt(float(r @ r))
            return np.concatenate([y[3:], -float(pot.derivative(rn)) * r / rn])

    else:
        from ..dynamics import PendulumForce, inertial_forces
        from ..kinematics import FrameMotion

        frame = FrameMotion(omega=i["frame_rate"])
        spring = PendulumForce(1.0, i["g"], i["length"])

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            r, v = y[:3], y[3:]
            f = inertial_forces(frame, r, v)
            return np.concatenate([v, spring(t, r, v) + f.transport + f.coriolis])

    def unpack_point(y: np.ndarray) -> dict[str, np.ndarray]:
        return {"position": y[:, :3].copy(), "velocity": y[:, 3:].copy()}

    return rhs, np.concatenate([i["position0"], i["velocity0"]]), unpack_point


class PoinsotEngine:
    """poinsot's own integrators.

    Parameters
    ----------
    method : str, optional
        For rigid bodies a method of :data:`poinsot.dynamics.METHODS`
        (``"midpoint"``, ``"splitting"``, ``"rk4"``, ``"dop853"``, ``"adaptive"``);
        for points a ``solve_ivp`` method of :func:`poinsot.dynamics.simulate_particle`
        (a rigid-body method skips the point cases, a point method the rigid ones).
        Default ``"dop853"`` (rigid) and ``"DOP853"`` (points).
    step : float, optional
        Longest step (s) of the fixed-step methods (``max_step``).
    rtol : float, optional
        Tolerance of the adaptive methods (``atol = rtol * 1e-3``).
    order : {2, 4, 6}, optional
        Order of ``"midpoint"`` / ``"splitting"``.
    """

    name = "poinsot"

    def __init__(self, method: str | None = None, step: float | None = None,
                 rtol: float | None = None, order: int | None = None):  # fmt: skip
        from ..dynamics import METHODS, PARTICLE_SOLVERS

        if method is not None and method not in METHODS and method not in PARTICLE_SOLVERS:
            raise InvalidInputError(
                f"Expected `method` to be one of {', '.join(METHODS)} (rigid bodies) or "
                f"{', '.join(PARTICLE_SOLVERS)} (points), got {method!r}."
            )
        self.method = method
        self.step = None if step is None else _positive(step, "step")
        self.rtol = None if rtol is None else _positive(rtol, "rtol")
        self.order = order
        parts = [f"poinsot {method or 'dop853/DOP853'}"]
        parts += [f"step={self.step:g} s"] if self.step else []
        parts += [f"rtol={self.rtol:g}"] if self.rtol else []
        parts += [f"order={order}"] if order else []
        self.label = " ".join(parts)

    def _rigid_method(self) -> str | None:
        from ..dynamics import METHODS

        if self.method is None:
            return "dop853"
        return self.method if self.method in METHODS else None

    def _point_method(self) -> str | None:
        from ..dynamics import PARTICLE_SOLVERS

        if self.method is None:
            return "DOP853"
        return (
            self.method if self.method in PARTICLE_SOLVERS and self.method != "adaptive" else None
        )

    def skip_reason(self, case: Case) -> str | None:
        if case.kind == "rigid" and self._rigid_method() is None:
            return f"method {self.method!r} integrates points, not rigid bodies"
        if case.kind == "point" and self._point_method() is None:
            return f"method {self.method!r} integrates rigid bodies, not points"
        return None

    def run(self, case: Case) -> tuple[Result, int | None]:
        i = case.inputs
        tol: dict[str, Any] = {}
        if case.kind == "rigid":
            from ..dynamics import HeavyRigidBody, simulate

            method = self._rigid_method()
            if self.rtol is not None:
                tol = {"rtol": self.rtol, "atol": self.rtol * 1e-3}
            opts: dict[str, Any] = {
                "method": method,
                "max_step": self.step,
                "order": self.order,
                **tol,
            }
            if i["fixed_point"]:
                body = HeavyRigidBody(case.inertia_about_origin, i["mass"], i["com"],
                                      g=-float(i["gravity"][2]))  # fmt: skip
                tr = body.simulate(i["q0"], i["omega0"], case.t, **opts)
            else:
                tr = simulate(i["inertia"], i["q0"], i["omega0"], case.t, **opts)
            steps = tr.info.get("evaluations", tr.info.get("steps"))
            work = int(np.sum(steps)) if steps is not None else None
            return rigid_result(case, _quat_unit(tr.quat), tr.omega, self.label), work
        from ..dynamics import PendulumForce, kepler, simulate_particle
        from ..kinematics import FrameMotion

        rtol = 1e-12 if self.rtol is None else self.rtol
        opts = {"method": self._point_method(), "rtol": rtol, "atol": rtol * 1e-3}
        if self.step is not None:
            opts["max_step"] = self.step
        if case.group == "orbit":
            pot = kepler(i["mu"])

            def gravity(t: float, r: np.ndarray, v: np.ndarray) -> np.ndarray:
                rn = math.sqrt(float(r @ r))
                return -float(pot.derivative(rn)) * r / rn

            pt = simulate_particle(FrameMotion(), gravity, i["position0"], i["velocity0"],
                                   case.t, **opts)  # fmt: skip
        else:
            frame = FrameMotion(omega=i["frame_rate"])
            spring = PendulumForce(1.0, i["g"], i["length"])
            pt = simulate_particle(frame, spring, i["position0"], i["velocity0"], case.t, **opts)
        nfev = pt.info.get("evaluations")
        return (
            point_result(case, pt.position, pt.velocity, self.label),
            None if nfev is None else int(np.sum(nfev)),
        )


class MuJoCoEngine:
    """MuJoCo (the ``mujoco`` package) with the integrator and timestep given.

    Parameters
    ----------
    integrator : {"Euler", "RK4", "implicitfast"}, optional
        MuJoCo's integrator (default ``"RK4"``).
    timestep : float, optional
        MuJoCo's step (s), default 1e-3. A time of the case's grid between two steps
        (e.g. the tops' 0.005 s grid at MuJoCo's default 0.002 s) is read by one
        shorter MuJoCo step from the last whole step, on a copy of the state
        (:mod:`poinsot.verify._mujoco`); the label says so when a grid needs it.

    Notes
    -----
    Free bodies are a body with a free joint and no gravity; tops a body with a
    ball joint at the fixed point. Contacts are disabled. The conversion of
    MuJoCo's ``qpos``/``qvel`` to poinsot's conventions is in
    :func:`poinsot.verify._mujoco.run_mujoco`. A point case (orbit, turning frame)
    has no MuJoCo model here and is skipped.
    """

    name = "mujoco"

    def __init__(self, integrator: str = "RK4", timestep: float = 1e-3):
        if integrator not in ("Euler", "RK4", "implicitfast"):
            raise InvalidInputError(
                f"Expected `integrator` to be 'Euler', 'RK4' or 'implicitfast', got {integrator!r}."
            )
        self.integrator = integrator
        self.timestep = _positive(timestep, "timestep")
        self.label = f"mujoco {integrator} timestep={self.timestep:g} s"
        from ._mujoco import sampling
        from .cases import cases

        grids = {float(c.t[1]) for c in cases() if c.kind == "rigid"}
        if any(np.any(sampling(np.array([g]), self.timestep)[1]) for g in grids):
            self.label += " (times between steps: one shorter step from the last whole step)"

    def skip_reason(self, case: Case) -> str | None:
        if case.kind != "rigid":
            return "MuJoCo models rigid bodies with joints; a point in a central field or a " \
                   "turning frame is not expressed by this adapter"  # fmt: skip
        try:
            import mujoco  # noqa: F401
        except ImportError as exc:
            return f"the mujoco package is not installed: pip install 'poinsot[verify]' ({exc})"
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        from ._mujoco import run_mujoco

        i = case.inputs
        q, w = run_mujoco(
            inertia=i["inertia"], mass=i["mass"], com=i["com"], q0=i["q0"], omega0=i["omega0"],
            gravity=i["gravity"], fixed_point=i["fixed_point"], t=case.t,
            integrator=self.integrator, timestep=self.timestep,
        )  # fmt: skip
        from ._mujoco import sampling

        whole, frac = sampling(case.t, self.timestep)
        steps = int(whole[-1]) + int(np.count_nonzero(frac))  # whole and shorter steps
        return rigid_result(case, _quat_unit(q), w, self.label), steps


def _nan_states(case: Case) -> dict[str, np.ndarray]:
    n = case.t.size
    if case.kind == "rigid":
        return {"quat": np.full((n, 4), np.nan), "omega": np.full((n, 3), np.nan)}
    return {"position": np.full((n, 3), np.nan), "velocity": np.full((n, 3), np.nan)}


def _nan_result(case: Case, method: str) -> Result:
    """The result of a diverged engine: NaN states, which fail every metric."""
    return as_result(case, _nan_states(case), method)


def _positive(x: Any, name: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise InvalidTypeError(f"Expected `{name}` to be a positive number, got {x!r}.") from None
    if not (math.isfinite(v) and v > 0):
        raise InvalidInputError(f"Expected `{name}` to be a positive finite number, got {x!r}.")
    return v


def run(engine: Any, case: Case) -> Any:
    """Run ``case`` in ``engine`` and evaluate it (a skipped or missing case carries
    its reason).

    Returns a :class:`poinsot.verify.metrics.CaseResult`.
    """
    from .metrics import CaseResult, evaluate

    reason = engine.skip_reason(case)
    if reason:
        return CaseResult(case=case.name, group=case.group, status="skip", reason=reason)
    missing = getattr(engine, "missing_reason", None)
    reason = missing(case) if missing is not None else None
    if reason:
        return CaseResult(case=case.name, group=case.group, status="missing", reason=reason)
    case.reference()  # outside the engine's timing
    t0 = time.perf_counter()
    out = engine.run(case)
    seconds = time.perf_counter() - t0
    result, work, *rest = out
    defects = list(rest[0] or ()) if rest else []
    if isinstance(result, dict):  # an engine of the former protocol
        _deprecated_states()
        result = dict(result)
        defects += list(result.pop("defects", None) or ())
        result = as_result(case, result, getattr(engine, "label", ""))
    return evaluate(case, result, seconds=seconds, work=work, defects=defects)


def make(name: str, **options: Any) -> Any:
    """The engine ``name`` (:data:`ENGINES`) with its options (None values dropped)."""
    from .files import FileEngine

    opts = {k: v for k, v in options.items() if v is not None}
    classes = {"scipy": SciPyEngine, "poinsot": PoinsotEngine, "mujoco": MuJoCoEngine,
               "file": FileEngine}  # fmt: skip
    if name not in classes:
        raise InvalidInputError(f"Expected an engine in {', '.join(ENGINES)}, got {name!r}.")
    try:
        return classes[name](**opts)
    except TypeError as exc:
        raise InvalidInputError(f"Engine {name!r} does not take these options: {exc}.") from None


def _path(x: Any, name: str) -> Path:
    if not isinstance(x, (str, Path)):
        raise InvalidTypeError(f"Expected `{name}` to be a path, got {type(x).__name__}.")
    return Path(x)
