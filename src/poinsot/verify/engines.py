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
  (free bodies) or a ball joint at the fixed point (tops), no contacts; a gyrostat's
  rotor as a second body on a hinge, the gravity-gradient torque and the constant body
  torque at every stage (``Group.engine_loads``).
- :class:`PyBulletEngine`: PyBullet (``pip install poinsot[verify]``), a free base in a
  ``DIRECT`` client, no gravity, no contact (free bodies, and in reduced coordinates
  the gyrostat's rotor link, the gravity-gradient torque and the constant body torque).
- :class:`DrakeEngine`: Drake (``pip install poinsot[verify]``), a free body in a
  continuous-time ``MultibodyPlant`` and Drake's ``Simulator`` with a named integrator
  (free bodies and the gyrostat's rotor on a revolute joint).
- :class:`BasiliskEngine`: Basilisk (``pip install bsk``, in an environment of its
  own), a ``spacecraft.Spacecraft`` hub with one of Basilisk's state integrators (free
  bodies; the gyrostat's rotor a balanced reaction wheel, the constant body torque an
  ``extForceTorque`` effector).
- :class:`FileEngine`: states that any engine wrote to CSV/Parquet files, one per case
  (``CASE.csv``), with the conventions given as options and checked.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..dynamics import METHODS, PARTICLE_SOLVERS
from ..errors import InvalidInputError, InvalidTypeError
from ..trajectory import Result
from ._basilisk import ADAPTIVE as BASILISK_ADAPTIVE
from ._basilisk import INTEGRATORS as BASILISK_INTEGRATORS
from ._basilisk import run_basilisk
from ._drake import FIXED_STEP as DRAKE_FIXED_STEP
from ._drake import INTEGRATORS as DRAKE_INTEGRATORS
from ._drake import run_drake, run_drake_pose
from ._mujoco import INTEGRATORS as MUJOCO_INTEGRATORS
from ._mujoco import run_mujoco, run_mujoco_pose, sampling
from ._pybullet import COORDINATES, MAXIMAL_SKIP, run_pybullet, run_pybullet_pose
from .cases import Case, cases
from .files import FileEngine
from .groups import (
    _deprecated_states,
    as_result,
    point_result,
    pose_result,
    quat_unit,
    rigid_result,
)
from .metrics import CaseResult, evaluate

__all__ = [
    "ENGINES",
    "Engine",
    "SciPyEngine",
    "PoinsotEngine",
    "MuJoCoEngine",
    "PyBulletEngine",
    "DrakeEngine",
    "BasiliskEngine",
    "as_result",
    "make",
    "point_result",
    "pose_result",
    "rigid_result",
    "run",
]

ENGINES = ("scipy", "poinsot", "mujoco", "pybullet", "drake", "basilisk", "file")


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


_quat_unit = quat_unit  # the former private name (poinsot.verify.files used it)


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
        return case.spec.scipy_skip

    def run(self, case: Case) -> tuple[Result, int]:
        from scipy.integrate import solve_ivp

        rhs, y0, unpack = case.spec.equations(case)
        sol = solve_ivp(rhs, (case.t[0], case.t[-1]), y0, method=self.method, t_eval=case.t,
                        rtol=self.rtol, atol=self.atol)  # fmt: skip
        if sol.status != 0 or sol.y.shape[1] != case.t.size:
            return _nan_result(case, self.label), int(sol.nfev)
        return unpack(sol.y.T, self.label), int(sol.nfev)


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

        if method is not None and method not in METHODS and method not in PARTICLE_SOLVERS:
            raise InvalidInputError(
                f"Expected `method` to be one of {', '.join(METHODS)} (rigid bodies) or "
                f"{', '.join(PARTICLE_SOLVERS)} (points), got {method!r}."
            )
        self.method = method
        self.step = None if step is None else _positive(step, "step")
        self.rtol = None if rtol is None else _positive(rtol, "rtol")
        self.order = order
        settings = [f"step={self.step:g} s"] if self.step else []
        settings += [f"rtol={self.rtol:g}"] if self.rtol else []
        settings += [f"order={order}"] if order else []
        self._settings = settings
        # without a method each case runs its group's default, named in its own result
        head = f"poinsot {method}" if method else "poinsot (each case's default method)"
        self.label = " ".join([head, *settings])

    def skip_reason(self, case: Case) -> str | None:
        if case.spec.poinsot_method(self.method) is None:
            return f"method {self.method!r} integrates {case.spec.poinsot_other}"
        return None

    def run(self, case: Case) -> tuple[Result, int | None]:
        method = case.spec.poinsot_method(self.method)
        assert method is not None
        label = " ".join([f"poinsot {method}", *self._settings])
        return case.spec.poinsot_run(case, method, self.step, self.rtol, self.order, label)


class MuJoCoEngine:
    """MuJoCo (the ``mujoco`` package) with the integrator and timestep given.

    Parameters
    ----------
    integrator : {"Euler", "RK4", "implicit", "implicitfast"}, optional
        MuJoCo's integrator (default ``"RK4"``): ``mjINT_EULER`` (semi-implicit
        Euler), ``mjINT_RK4``, ``mjINT_IMPLICIT`` and ``mjINT_IMPLICITFAST`` (implicit
        in the velocity; ``implicit`` keeps the Coriolis and gyroscopic derivatives
        that ``implicitfast`` drops).
    timestep : float, optional
        MuJoCo's step (s), default 1e-3. A time of the case's grid between two steps
        (e.g. the tops' 0.005 s grid at MuJoCo's default 0.002 s) is read by one
        shorter MuJoCo step from the last whole step, on a copy of the state
        (:mod:`poinsot.verify._mujoco`); the label says so when a grid needs it.

    Notes
    -----
    Free bodies are a body with a free joint and no gravity; tops a body with a
    ball joint at the fixed point; a gyrostat a free body with its rotor on a hinge
    (:func:`poinsot.verify._mujoco.rotor_inputs`); the pitch libration a free body
    with the gravity-gradient torque added at every stage (``mjcb_passive``), the
    body-torque case likewise with its constant body-axes torque: run the pitch libration
    at a step of seconds (a run with a Python torque of more than
    :data:`TORQUE_MAX_STEPS` steps is skipped). Contacts are disabled. The conversion of
    MuJoCo's ``qpos``/``qvel`` to poinsot's conventions is in
    :func:`poinsot.verify._mujoco.run_mujoco`. A point case (orbit, turning frame)
    has no MuJoCo model here and is skipped.
    """

    name = "mujoco"

    def __init__(self, integrator: str = "RK4", timestep: float = 1e-3):
        if integrator not in MUJOCO_INTEGRATORS:
            raise InvalidInputError(
                "Expected `integrator` to be 'Euler', 'RK4', 'implicit' or 'implicitfast', "
                f"got {integrator!r}."
            )
        self.integrator = integrator
        self.timestep = _positive(timestep, "timestep")
        self.label = f"mujoco {integrator} timestep={self.timestep:g} s"

        grids = {float(c.t[1]) for c in cases() if c.spec.mujoco_skip is None}
        if any(np.any(sampling(np.array([g]), self.timestep)[1]) for g in grids):
            self.label += " (times between steps: one shorter step from the last whole step)"

    def skip_reason(self, case: Case) -> str | None:
        if case.spec.mujoco_skip is not None:
            return case.spec.mujoco_skip
        reason = _torque_steps(case, self.timestep, "MuJoCo")
        if reason:
            return reason
        try:
            import mujoco  # noqa: F401
        except ImportError as exc:
            return f"the mujoco package is not installed: pip install 'poinsot[verify]' ({exc})"
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        i = case.inputs
        whole, frac = sampling(case.t, self.timestep)
        steps = int(whole[-1]) + int(np.count_nonzero(frac))  # whole and shorter steps
        if case.kind == "pose":  # a free joint at the centre of mass, gravity on
            r, v, q, w = run_mujoco_pose(
                inertia=i["inertia"], mass=i["mass"], position0=i["position0"],
                velocity0=i["velocity0"], q0=i["q0"], omega0=i["omega0"], gravity=i["gravity"],
                t=case.t, integrator=self.integrator, timestep=self.timestep,
            )  # fmt: skip
            return _pose(case, r, v, q, w, self.label), steps
        q, w = run_mujoco(
            inertia=i["inertia"], mass=i["mass"], com=i["com"], q0=i["q0"], omega0=i["omega0"],
            gravity=i["gravity"], fixed_point=i["fixed_point"], t=case.t,
            integrator=self.integrator, timestep=self.timestep, **case.spec.engine_loads(case),
        )  # fmt: skip
        return rigid_result(case, quat_unit(q), w, self.label), steps


def _pose(case: Case, r: Any, v: Any, q: Any, w: Any, label: str) -> Result:
    """The :class:`poinsot.PoseTrajectory` of an adapter's six-degree-of-freedom run."""
    states = {"position": r, "velocity": v, "quat": quat_unit(q), "omega": w}
    return case.spec.of_states(case, states, label)


def _free_body_only(case: Case, engine: str) -> str | None:
    """Why ``engine`` (an adapter of free bodies only) skips ``case``, or None."""
    if case.kind == "point":
        return (f"{engine} models rigid bodies; a point in a central field or a turning "
                "frame is not expressed by this adapter")  # fmt: skip
    if case.inputs["fixed_point"]:
        return _TOP_SKIP[engine]
    # a free body with a torque, a rotor or an orbit: what MuJoCo's adapter skips too,
    # and what this adapter does not model
    return case.spec.mujoco_skip or case.spec.adapter_skip.get(engine)


#: the most steps of a run whose torque is evaluated in Python (about 0.2 ms a call,
#: once per MuJoCo RK4 stage or PyBullet step): more is skipped with the reason
TORQUE_MAX_STEPS = 100_000


def _torque_steps(case: Case, timestep: float, engine: str) -> str | None:
    """Why a run of ``case`` with an external torque (``engine_loads``) at ``timestep``
    is skipped: too many steps with a Python torque; None when it is not."""
    if case.spec.engine_loads(case)["torque"] is None:
        return None
    duration = float(case.t[-1] - case.t[0])
    steps = duration / timestep
    if steps <= TORQUE_MAX_STEPS:
        return None
    return (f"{engine} at a {timestep:g} s step takes {steps:.3g} steps over the case's "
            f"{duration:g} s, each with the torque evaluated in Python: more than "
            f"{TORQUE_MAX_STEPS}; run it with a step of {duration / TORQUE_MAX_STEPS:g} s "
            "or more (--step)")  # fmt: skip


_TOP_SKIP = {
    "PyBullet": (
        "PyBullet's adapter runs free bodies only: a top pinned by a point-to-point "
        "constraint (createConstraint JOINT_POINT2POINT) was tried and is first order, "
        "0.16 rad off on top-loops at a 0.1 ms step and 0.013 rad at 0.01 ms, so it "
        "would fail at every practical step (docs/verify.md)"
    ),
    "Drake": (
        "Drake's adapter runs free bodies only: Drake's only ball joint is BallRpyJoint "
        "(roll-pitch-yaw angles, singular at pitch +-90 deg), no quaternion ball joint, "
        "and its ball constraint needs a discrete plant (docs/verify.md)"
    ),
    "Basilisk": (
        "Basilisk's adapter runs free bodies only: a spacecraft.Spacecraft hub is a free "
        "body and the spacecraft module has no joint that pins a hub at a fixed point "
        "(a fixed-point top has no Basilisk hub model; docs/verify.md)"
    ),
}


class PyBulletEngine:
    """PyBullet (the ``pybullet`` package): a free body stepped with ``stepSimulation``.

    Parameters
    ----------
    timestep : float, optional
        PyBullet's step (s), ``setTimeStep``; default 1e-3. A time of the case's grid
        between two steps is read by one shorter step from the last whole step
        (:mod:`poinsot.verify._pybullet`).
    coordinates : {"reduced", "maximal"}, optional
        ``"reduced"`` (default, PyBullet's own default): a Featherstone multibody, its
        gyroscopic term explicit in the step; ``"maximal"``: a maximal-coordinates
        rigid body (``useMaximalCoordinates=True``), whose gyroscopic term Bullet
        integrates implicitly in body axes.

    Notes
    -----
    Bullet's step is semi-implicit Euler, first order: the attitude error of the
    free-body cases falls tenfold per tenfold shorter step (1.0 rad at 0.01 s,
    0.1 rad at 1 ms, 0.01 rad at 0.1 ms on the racket flip), so it passes no case's
    1e-6 thresholds at a step that runs in seconds. Conventions (scalar-last
    quaternions of the inertial frame, world-axes angular velocity) are converted by
    :func:`poinsot.verify._pybullet.run_pybullet`. Tops and point cases are skipped
    (their reason says why).
    """

    name = "pybullet"

    def __init__(self, timestep: float = 1e-3, coordinates: str = "reduced"):
        if coordinates not in COORDINATES:
            raise InvalidInputError(
                f"Expected `coordinates` to be 'reduced' or 'maximal', got {coordinates!r}."
            )
        self.timestep = _positive(timestep, "timestep")
        self.coordinates = coordinates
        self.label = f"pybullet {coordinates} coordinates timestep={self.timestep:g} s"

    def skip_reason(self, case: Case) -> str | None:
        reason = _free_body_only(case, "PyBullet")
        if reason:
            return reason
        if self.coordinates == "maximal" and any(
            v is not None for v in case.spec.engine_loads(case).values()
        ):
            return MAXIMAL_SKIP
        reason = _torque_steps(case, self.timestep, "PyBullet")
        if reason:
            return reason
        try:
            import pybullet  # noqa: F401
        except ImportError as exc:
            return f"the pybullet package is not installed: pip install 'poinsot[verify]' ({exc})"
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        i = case.inputs
        whole, frac = sampling(case.t, self.timestep)
        steps = int(whole[-1]) + int(np.count_nonzero(frac))
        if case.kind == "pose":  # the base's centre of mass moves, gravity on
            r, v, q, w = run_pybullet_pose(
                inertia=i["inertia"], mass=i["mass"], position0=i["position0"],
                velocity0=i["velocity0"], q0=i["q0"], omega0=i["omega0"], gravity=i["gravity"],
                t=case.t, timestep=self.timestep, coordinates=self.coordinates,
            )  # fmt: skip
            return _pose(case, r, v, q, w, self.label), steps
        q, w = run_pybullet(inertia=i["inertia"], mass=i["mass"], q0=i["q0"],
                            omega0=i["omega0"], gravity=i["gravity"], t=case.t,
                            timestep=self.timestep, coordinates=self.coordinates,
                            **case.spec.engine_loads(case))  # fmt: skip
        return rigid_result(case, quat_unit(q), w, self.label), steps


class DrakeEngine:
    """Drake (the ``drake`` package): a free body in a continuous-time
    ``MultibodyPlant``, run by Drake's ``Simulator``.

    Parameters
    ----------
    integrator : str, optional
        A Drake integration scheme (:data:`poinsot.verify._drake.INTEGRATORS`:
        ``"runge_kutta5"`` (default), ``"runge_kutta3"``, ``"bogacki_shampine3"``,
        ``"radau3"``, ``"radau1"``, ``"implicit_euler"``, ``"velocity_implicit_euler"``,
        and the fixed-step-only ``"runge_kutta2"``, ``"explicit_euler"``,
        ``"semi_explicit_euler"``).
    accuracy : float, optional
        Target accuracy of an error-controlled scheme (``set_target_accuracy``);
        default 1e-13 when no ``step`` is given. Drake's accuracy bounds each step's
        error estimate, not the error of the run: on the racket flip (an unstable
        motion) ``runge_kutta5`` is 2.7e-7 rad off at 1e-12 and 3.1e-8 rad at 1e-13
        (docs/verify.md).
    step : float, optional
        A fixed step (s) (``set_fixed_step_mode``); required by the fixed-step-only
        schemes.

    Notes
    -----
    Drake's state is ``q = [qw, qx, qy, qz, x, y, z]`` (scalar first, body -> world)
    and ``v = [w_WB, v_WBo]`` (world axes), converted by
    :func:`poinsot.verify._drake.run_drake`. The work is Drake's count of derivative
    evaluations. Tops and point cases are skipped (their reason says why).
    """

    name = "drake"

    def __init__(self, integrator: str = "runge_kutta5", accuracy: float | None = None,
                 step: float | None = None):  # fmt: skip
        if integrator not in DRAKE_INTEGRATORS:
            raise InvalidInputError(
                f"Expected `integrator` to be one of {', '.join(DRAKE_INTEGRATORS)}, "
                f"got {integrator!r}."
            )
        self.integrator = integrator
        self.step = None if step is None else _positive(step, "step")
        if self.step is not None and accuracy is not None:
            raise InvalidInputError(
                "Expected either `accuracy` (error control) or `step` (fixed step), not both."
            )
        if self.step is None and integrator in DRAKE_FIXED_STEP:
            raise InvalidInputError(
                f"Expected a fixed `step` for Drake's {integrator!r} (it has no error "
                "estimation, so no `accuracy`)."
            )
        self.accuracy = None if self.step is not None else (
            1e-13 if accuracy is None else _positive(accuracy, "accuracy"))  # fmt: skip
        setting = f"step={self.step:g} s" if self.step else f"accuracy={self.accuracy:g}"
        self.label = f"drake {integrator} {setting}"

    def skip_reason(self, case: Case) -> str | None:
        reason = _free_body_only(case, "Drake")
        if reason:
            return reason
        try:
            import pydrake  # noqa: F401
        except ImportError as exc:
            return f"the drake package is not installed: pip install 'poinsot[verify]' ({exc})"
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        i = case.inputs
        if case.kind == "pose":  # the body origin, its centre of mass, moves; gravity on
            r, v, q, w, n = run_drake_pose(
                inertia=i["inertia"], mass=i["mass"], position0=i["position0"],
                velocity0=i["velocity0"], q0=i["q0"], omega0=i["omega0"], gravity=i["gravity"],
                t=case.t, integrator=self.integrator, accuracy=self.accuracy, step=self.step,
            )  # fmt: skip
            return _pose(case, r, v, q, w, self.label), n
        loads = case.spec.engine_loads(case)  # a torque: skipped (skip_reason)
        q, w, evaluations = run_drake(
            inertia=i["inertia"], mass=i["mass"], q0=i["q0"], omega0=i["omega0"],
            gravity=i["gravity"], t=case.t, integrator=self.integrator,
            accuracy=self.accuracy, step=self.step, rotor_momentum=loads["rotor_momentum"],
        )  # fmt: skip
        return rigid_result(case, quat_unit(q), w, self.label), evaluations


class BasiliskEngine:
    """Basilisk (the ``bsk`` package): a free body as a ``spacecraft.Spacecraft`` hub
    with no gravity body, stepped by one of Basilisk's state integrators; a gyrostat's
    rotor a balanced ``reactionWheelStateEffector`` with no motor torque, a constant body
    torque an ``extForceTorque`` effector (:mod:`poinsot.verify._basilisk`).

    Parameters
    ----------
    integrator : {"RK4", "Euler", "RK2", "RKF45", "RKF78"}, optional
        Basilisk's ``svIntegrators`` class ``svIntegrator<integrator>`` (default
        ``"RK4"``, Basilisk's own default).
    timestep : float, optional
        The task period (s), default 1e-3: the step of ``RK4``/``RK2``/``Euler``, the
        longest step of the adaptive ``RKF45``/``RKF78``. The case's grid times must be
        whole multiples of it.
    rtol : float, optional
        ``relTol`` of ``RKF45``/``RKF78`` (``absTol = rtol * 1e-3``); default Basilisk's
        (``relTol = 1e-4``, ``absTol = 1e-8``).

    Notes
    -----
    Basilisk's attitude is ``sigma_BN``, the MRPs of ``[BN]`` (inertial -> body
    components), and ``omega_BN_B`` in body axes; converted by
    :func:`poinsot.verify._basilisk.run_basilisk`. Basilisk is not in poinsot's extras
    (``bsk`` caps pandas and matplotlib): ``pip install bsk`` in an environment of its
    own. Tops and point cases are skipped (their reason says why).
    """

    name = "basilisk"

    def __init__(self, integrator: str = "RK4", timestep: float = 1e-3,
                 rtol: float | None = None):  # fmt: skip
        if integrator not in BASILISK_INTEGRATORS:
            raise InvalidInputError(
                f"Expected `integrator` to be one of {', '.join(BASILISK_INTEGRATORS)}, "
                f"got {integrator!r}."
            )
        if rtol is not None and integrator not in BASILISK_ADAPTIVE:
            raise InvalidInputError(
                f"Expected `rtol` only with an adaptive integrator "
                f"({', '.join(BASILISK_ADAPTIVE)}), not {integrator!r}."
            )
        self.integrator = integrator
        self.timestep = _positive(timestep, "timestep")
        self.rtol = None if rtol is None else _positive(rtol, "rtol")
        self.label = f"basilisk {integrator} timestep={self.timestep:g} s"
        if self.rtol is not None:
            self.label += f" rtol={self.rtol:g}"

    def skip_reason(self, case: Case) -> str | None:
        reason = _free_body_only(case, "Basilisk") or case.spec.basilisk_skip
        if reason:
            return reason
        try:
            import Basilisk  # noqa: F401
        except ImportError as exc:
            return (f"Basilisk is not installed: pip install bsk (in an environment of its "
                    f"own: it caps pandas and matplotlib) ({exc})")  # fmt: skip
        return None

    def run(self, case: Case) -> tuple[Result, int]:
        i = case.inputs
        loads = case.spec.engine_loads(case)  # a torque not constant: skipped (skip_reason)
        q, w, steps = run_basilisk(
            inertia=i["inertia"], mass=i["mass"], q0=i["q0"], omega0=i["omega0"], t=case.t,
            integrator=self.integrator, timestep=self.timestep, rtol=self.rtol,
            rotor_momentum=loads["rotor_momentum"], torque=case.spec.constant_torque(case),
        )  # fmt: skip
        return rigid_result(case, quat_unit(q), w, self.label), steps


def _nan_result(case: Case, method: str) -> Result:
    """The result of a diverged engine: NaN states, which fail every metric."""
    return case.spec.nan_result(case, method)


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

    opts = {k: v for k, v in options.items() if v is not None}
    classes = {"scipy": SciPyEngine, "poinsot": PoinsotEngine, "mujoco": MuJoCoEngine,
               "pybullet": PyBulletEngine, "drake": DrakeEngine,
               "basilisk": BasiliskEngine, "file": FileEngine}  # fmt: skip
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
