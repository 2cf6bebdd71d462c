"""The groups of ``poinsot verify``'s cases: one object per group, the one place for
what differs between them (docs/verify.md).

Each :class:`Group` holds, for its cases: the kind of motion (a rigid body, result
:class:`poinsot.Trajectory`, or a point, :class:`poinsot.PointTrajectory`), the
exact model and states (docs/theory.md §9, §10), the characteristic facts, the
units and file columns, the adapter hooks (the equations a generic ODE solver
integrates, poinsot's own integrator, whether MuJoCo's adapter expresses it), the
first integrals and which of them the metrics read, and the report's options.
:data:`GROUP_TABLE` maps the names of :data:`poinsot.verify.GROUPS` to them;
``case.spec`` is the group object of a case. Nothing else branches on a case's
group or kind.

- :class:`FreeBody` (``free-body``): Euler-Poinsot motion (:class:`FreeRigidBody`);
- :class:`HeavyTop` (``heavy-top``): the Lagrange top (:class:`LagrangeTop`), only
  ``K_z`` conserved;
- :class:`Kovalevskaya` (``kovalevskaya``): the Kovalevskaya top, a stored
  32-digit reference; energy and ``K_z`` scored;
- :class:`BodyTorque` (``body-torque``): a constant torque along the symmetry axis,
  a stored 32-digit reference; the transverse kinetic energy scored;
- :class:`Gyrostat` (``gyrostat``): a dual-spin gyrostat (:class:`FreeGyrostat`);
- :class:`GravityGradient` (``gravity-gradient``): pitch libration in a circular
  orbit (:class:`PitchLibration`); the orbit frame's Jacobi integral scored;
- :class:`Orbit` (``orbit``): Kepler orbits (:class:`CentralOrbit`);
- :class:`Frame` (``frame``): the Foucault pendulum in its turning frame (closed
  form, the Jacobi integral conserved);
- :class:`FreeFlight` (``free-flight``, version 3): a rigid body thrown in uniform
  gravity, six degrees of freedom (result :class:`poinsot.PoseTrajectory`): the
  centre of mass on its parabola, the attitude Euler-Poinsot motion about it;
- :class:`Estimation` (``estimation``, version 4): an attitude estimator run on stored
  gyro and star-tracker samples of an exact tumbling motion (result :class:`Estimate`):
  attitude and bias errors against the truth and a NEES consistency verdict.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics import (
    METHODS,
    PARTICLE_SOLVERS,
    CentralOrbit,
    FreeGyrostat,
    FreeRigidBody,
    GravityTorque,
    HeavyRigidBody,
    LagrangeTop,
    PendulumForce,
    PitchLibration,
    euler_rhs,
    inertial_forces,
    kepler,
    regular_precession_rates,
    simulate,
    simulate_free_motion,
    simulate_particle,
)
from ..dynamics.estimation import AttitudeSamples, Gyro, GyroSamples, StarTracker, run_mekf
from ..errors import InvalidInputError, InvalidTypeError, SingularityWarning
from ..kinematics import FrameMotion, quat_rate
from ..kinematics.attitude_history import _make_continuous
from ..mass import RigidBody
from ..rotations.rotation import Rotation
from ..trajectory import PointTrajectory, PoseTrajectory, Result, Trajectory

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .cases import Case

RIGID_COLUMNS = ("t", "qw", "qx", "qy", "qz", "wx", "wy", "wz")
#: an estimate's columns: the attitude, then (optional) the gyro bias and the 1-sigma
#: attitude errors about the body axes
ESTIMATE_COLUMNS = ("t", "qw", "qx", "qy", "qz", "bx", "by", "bz", "sx", "sy", "sz")
POINT_COLUMNS = ("t", "x", "y", "z", "vx", "vy", "vz")
POSE_COLUMNS = POINT_COLUMNS + RIGID_COLUMNS[1:]

Equations = tuple[Callable[[float, np.ndarray], np.ndarray], np.ndarray,
                  Callable[[np.ndarray, str], Result]]  # fmt: skip


def quat_unit(q: np.ndarray) -> np.ndarray:
    """Unit, sign-continuous quaternions (the form every engine's attitude is scored in)."""
    q = np.asarray(q, dtype=float)
    return _make_continuous(q / np.linalg.norm(q, axis=-1, keepdims=True))


def rigid_result(case: Case, quat: Any, omega: Any, method: str) -> Trajectory:
    """A :class:`poinsot.Trajectory` of ``case`` on its grid from scalar-first
    quaternions (body -> space) and body-axes angular velocities, the quaternions
    kept as given (bit for bit: the metrics see exactly the engine's numbers)."""
    q = np.ascontiguousarray(quat, dtype=float)
    return Trajectory(case.t, Rotation._wrap(q), np.asarray(omega, dtype=float), method)


def point_result(case: Case, position: Any, velocity: Any, method: str) -> PointTrajectory:
    """A :class:`poinsot.PointTrajectory` of ``case`` on its grid (m, m/s)."""
    return PointTrajectory(case.t, position, velocity, method)


class Group:
    """What the cases of one group share (see the module docstring)."""

    #: the group's name, one of :data:`poinsot.verify.GROUPS`
    name = ""
    #: ``"rigid"``, ``"point"`` or ``"pose"`` (the ``kind`` of its cases)
    kind = ""
    #: the state arrays of its results, in file order
    states: tuple[str, ...] = ("", "")
    #: the columns of its files (:func:`poinsot.verify.files.export`)
    columns: tuple[str, ...] = ()
    #: the units of its files and inputs (:func:`poinsot.verify.cases.describe`)
    units: dict[str, str] = {}
    #: the error metrics of its state (:data:`poinsot.verify.METRICS`)
    errors: tuple[str, ...] = ("", "")
    #: whether a first integral besides the energy is conserved (``"momentum"``)
    has_momentum = True
    #: why MuJoCo's adapter cannot run its cases, or None
    mujoco_skip: str | None = None
    #: why Basilisk's adapter cannot run its cases (besides MuJoCo's reason), or None
    basilisk_skip: str | None = None
    #: why the PyBullet and Drake adapters cannot run its cases (besides MuJoCo's
    #: reason), by the engine's name ("PyBullet", "Drake")
    adapter_skip: dict[str, str] = {}
    #: what poinsot's engine integrates when its method skips this group
    poinsot_other = ""
    #: why the SciPy engine (a generic ODE solver) cannot run its cases, or None
    scipy_skip: str | None = None
    #: the types an engine's result may have for its cases
    result_types: tuple[type, ...] = (Result,)

    def score(self, case: Case, result: Any) -> tuple[dict[str, float], dict[str, np.ndarray],
                                                       dict[str, np.ndarray]] | None:  # fmt: skip
        """``(values, errors, states)`` when the group scores its results itself (the
        metric values, the per-sample errors for the charts, the state arrays as
        scored), or None: :func:`poinsot.verify.metrics.evaluate`'s comparison with the
        exact motion."""
        return None

    def sensor_files(self, case: Case) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Extra input files of ``poinsot verify export``: ``suffix -> (columns,
        table)``, written as ``CASE.SUFFIX.csv`` (none but for the estimation cases)."""
        return {}

    def describe(self, case: Case) -> dict[str, Any]:
        """What ``CASE.json`` adds for this group (:func:`poinsot.verify.cases.describe`)."""
        return {}

    def read_columns(self, path: Path, case: Case, cols: dict[str, np.ndarray],
                     label: str) -> tuple[Any, list[str]] | None:  # fmt: skip
        """``(result, defects)`` of a file's columns (on the case's grid, checked) when
        the group reads its files itself, or None (the file engine's states)."""
        return None

    def model(self, case: Case) -> Any:
        """The poinsot exact-solution object of the case, or None."""
        return None

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        """The exact states on ``case.t``, ``{"t", *states}``."""
        raise NotImplementedError

    def prepare(self, case: Case) -> None:
        """Fill in the inputs that need the model (before :meth:`facts`)."""

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        """Exact characteristic figures (and the event level where it needs the model)."""
        raise NotImplementedError

    def result(self, case: Case, a: Any, b: Any, method: str) -> Result:
        """The result of the two state arrays (:attr:`states`) on ``case.t``."""
        raise NotImplementedError

    def nan_states(self, case: Case) -> dict[str, np.ndarray]:
        """NaN state arrays on ``case.t`` (a diverged engine)."""
        shapes = {"quat": 4, "omega": 3, "position": 3, "velocity": 3}
        return {s: np.full((case.t.size, shapes[s]), np.nan) for s in self.states}

    def arrays(self, result: Result) -> dict[str, np.ndarray]:
        """The state arrays of a result, ``name -> array`` (:attr:`states`)."""
        raise NotImplementedError

    def of_states(self, case: Case, states: dict[str, np.ndarray], method: str) -> Result:
        """The result of the state arrays ``states`` (``name -> array``, :attr:`states`)."""
        a, b = (states[k] for k in self.states)
        return self.result(case, a, b, method)

    def nan_result(self, case: Case, method: str) -> Result:
        """The result of a diverged engine: NaN states, which fail every metric."""
        return self.of_states(case, self.nan_states(case), method)

    def engine_loads(self, case: Case) -> dict[str, Any]:
        """What an engine adapter adds to the free body (docs/verify.md):
        ``{"rotor_momentum": h (3,) or None, "torque": torque(t, q, w) or None}``, a
        gyrostat's rotor (a second body on a hinge) or an external torque (the rigid
        group's ``torque``) applied at each evaluation of the dynamics."""
        return {"rotor_momentum": None, "torque": None}

    def constant_torque(self, case: Case) -> np.ndarray | None:
        """The external torque of :meth:`engine_loads` when it is constant in body axes
        (N m, (3,); an engine effector holding a fixed body torque, Basilisk's
        ``extForceTorque``), or None."""
        return None

    def equations(self, case: Case) -> Equations:
        """``(rhs(t, y), y0, unpack(y, method) -> result)`` for a generic ODE solver."""
        raise NotImplementedError

    def poinsot_method(self, method: str | None) -> str | None:
        """The method of poinsot's engine for this group (None: it integrates the
        other kind)."""
        raise NotImplementedError

    def poinsot_run(self, case: Case, method: str, step: float | None, rtol: float | None,
                    order: int | None, label: str) -> tuple[Any, Any]:  # fmt: skip
        """poinsot's integrator on the case: ``(poinsot result, evaluations or steps)``."""
        raise NotImplementedError

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """The first integrals along ``states`` (:func:`poinsot.verify.metrics.integrals`)."""
        raise NotImplementedError

    def conserved_momentum(self, k: np.ndarray) -> np.ndarray:
        """The part of the momentum integral that is conserved."""
        return k

    def report_options(self, case: Case, errors: dict[str, np.ndarray]) -> dict[str, Any]:
        """Options of the case page's report (:func:`poinsot.plotting.report.write_report`)
        beyond the trajectory, title and summary; ``errors`` the per-sample errors."""
        raise NotImplementedError


class RigidGroup(Group):
    """A rigid body: attitude and body angular velocity (docs/theory.md §5, §10)."""

    kind, poinsot_other = "rigid", "points, not rigid bodies"
    states: tuple[str, ...] = ("quat", "omega")
    errors: tuple[str, ...] = ("attitude", "omega")
    columns: tuple[str, ...] = RIGID_COLUMNS
    units = {"t": "s", "qw,qx,qy,qz": "1", "wx,wy,wz": "rad/s", "inertia": "kg m^2",
             "mass": "kg", "com": "m", "gravity": "m/s^2"}  # fmt: skip
    euler_seq = "ZYX"

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        omega, rot = case.model().state(case.t)
        q = _make_continuous(np.asarray(rot.as_quat(), dtype=float))
        return {"t": case.t.copy(), "quat": q, "omega": np.asarray(omega, dtype=float)}

    def result(self, case: Case, a: Any, b: Any, method: str) -> Result:
        return rigid_result(case, a, b, method)

    def arrays(self, result: Result) -> dict[str, np.ndarray]:
        assert isinstance(result, Trajectory)
        return {"quat": result.quat, "omega": np.asarray(result.omega)}

    def equations(self, case: Case) -> Equations:
        i = case.inputs
        jo = case.inertia_about_origin
        g = -float(i["gravity"][2])
        torque = GravityTorque(i["mass"], i["com"], g) if i["fixed_point"] and g else None
        extra = self.torque(case)

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            q, w = y[:4], y[4:]
            m = None if torque is None else torque.body_torque(t, q[None], w[None])[0]
            if extra is not None:
                m = extra(t, q, w) if m is None else m + extra(t, q, w)
            return np.concatenate([quat_rate(q, w), euler_rhs(jo, w, m)])

        def unpack(y: np.ndarray, method: str) -> Result:
            return rigid_result(case, quat_unit(y[:, :4]), y[:, 4:].copy(), method)

        return rhs, np.concatenate([i["q0"], i["omega0"]]), unpack

    def poinsot_method(self, method: str | None) -> str | None:
        if method is None:
            return "dop853"
        return method if method in METHODS else None

    def poinsot_run(self, case: Case, method: str, step: float | None, rtol: float | None,
                    order: int | None, label: str) -> tuple[Any, Any]:  # fmt: skip
        i = case.inputs
        tol = {} if rtol is None else {"rtol": rtol, "atol": rtol * 1e-3}
        opts: dict[str, Any] = {"method": method, "max_step": step, "order": order, **tol}
        if i["fixed_point"]:
            body = HeavyRigidBody(case.inertia_about_origin, i["mass"], i["com"],
                                  g=-float(i["gravity"][2]))  # fmt: skip
            tr = body.simulate(i["q0"], i["omega0"], case.t, **opts)
        else:
            extra = self.torque(case)
            if extra is not None:

                def body_torque(t: float, rot: Any, w: Any) -> np.ndarray:
                    return extra(t, np.asarray(rot.as_quat(), dtype=float), np.asarray(w))

                opts["torque"] = body_torque
            tr = simulate(i["inertia"], i["q0"], i["omega0"], case.t, **opts)
        steps = tr.info.get("evaluations", tr.info.get("steps"))
        work = int(np.sum(steps)) if steps is not None else None
        return rigid_result(case, quat_unit(tr.quat), tr.omega, label), work

    def torque(self, case: Case) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None:
        """The external torque besides gravity, ``torque(t, q, w) -> (3,)`` in body axes
        (N m) of one state (scalar-first ``q``, body ``w``), or None (free body, top)."""
        return None

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        i = case.inputs
        jo = case.inertia_about_origin
        w = states["omega"]
        rmat = np.asarray(Rotation.from_quat(states["quat"]).as_matrix(), dtype=float)
        kb = w @ jo.T
        energy = 0.5 * np.einsum("ni,ni->n", w, kb)
        if np.any(i["gravity"]):
            # V = -m g . (R c): the weight's potential with c from the fixed point
            energy = energy - i["mass"] * np.einsum("nij,j,i->n", rmat, i["com"], i["gravity"])
        k_space = np.einsum("nij,nj->ni", rmat, kb)
        return {"energy": energy, "momentum": k_space}

    def report_options(self, case: Case, errors: dict[str, np.ndarray]) -> dict[str, Any]:
        i = case.inputs
        return {"reference": case.reference(), "inertia": i["inertia"], "mass": i["mass"],
                "center_of_mass": i["com"], "fixed_point": bool(i["fixed_point"]),
                "free_body": isinstance(self, FreeBody), "euler_seq": self.euler_seq}  # fmt: skip


class FreeBody(RigidGroup):
    """Euler-Poinsot motion: a free rigid body (docs/theory.md §10)."""

    name = "free-body"

    def model(self, case: Case) -> Any:
        i = case.inputs
        with warnings.catch_warnings():  # the separatrix cases are near it on purpose
            warnings.simplefilter("ignore", SingularityWarning)
            return FreeRigidBody(i["inertia"], rotation0=i["q0"], omega0=i["omega0"])

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        facts = {"regime": str(model.regime), "period_s": float(model.period)}
        if case.event is not None:
            facts["flip_period_s"] = float(model.period) / 2.0
        return facts


class HeavyTop(RigidGroup):
    """The Lagrange top about its fixed point (docs/theory.md §10): ``K_z`` conserved."""

    name = "heavy-top"
    euler_seq = "ZXZ"

    def model(self, case: Case) -> Any:
        i = case.inputs
        g = -float(i["gravity"][2])
        body = HeavyRigidBody(case.inertia_about_origin, i["mass"], i["com"], g=g)
        return LagrangeTop.from_state(body, rotation=i["q0"], omega=i["omega0"])

    def prepare(self, case: Case) -> None:
        """A NaN precession rate becomes the slow regular-precession rate."""
        i = case.inputs
        if np.isfinite(i["omega0"][1]):
            return
        ct = 1.0 - 2.0 * float(np.sum(i["q0"][1:3] ** 2))
        theta = math.acos(ct)
        jo = case.inertia_about_origin
        mgl = float(i["mass"] * -i["gravity"][2] * i["com"][2])
        rates = regular_precession_rates(jo[0, 0], jo[2, 2], mgl, theta, i["omega0"][2])
        slow = float(np.asarray(rates).flat[int(np.argmin(np.abs(np.asarray(rates))))])
        i["omega0"] = np.array([0.0, slow * math.sin(theta), i["omega0"][2]])

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        lo, hi = model.nutation_bounds
        facts = {
            "motion_type": model.motion_type,
            "nutation_period_s": float(model.nutation_period),
            "nutation_bounds_rad": [float(lo), float(hi)],
        }
        i = case.inputs
        jo = case.inertia_about_origin
        mgl = float(i["mass"] * -i["gravity"][2] * i["com"][2])
        crit = 2.0 * math.sqrt(jo[0, 0] * mgl) / jo[2, 2]  # C^2 w^2 = 4 A_O m g l
        facts["critical_spin_rad_per_s"] = crit
        facts["spin_over_critical"] = float(i["omega0"][2]) / crit
        if case.event is not None:
            case.event["level"] = 0.5 * (math.cos(lo) + math.cos(hi))
        return facts

    def conserved_momentum(self, k: np.ndarray) -> np.ndarray:
        return k[:, 2]  # only K_z is conserved under gravity


def _stored(case: Case, name: str) -> dict[str, np.ndarray]:
    """The exact states of ``case`` stored in ``poinsot/verify/data/NAME.npz`` (a
    32-digit Taylor integration, ``tools/make_NAME_reference.py``), checked against
    the case's grid and inputs."""
    path = Path(__file__).parent / "data" / f"{name}.npz"
    with np.load(path) as d:
        data = {k: d[k] for k in d.files}
    same = data["t"].shape == case.t.shape and np.array_equal(data["t"], case.t)
    for k, v in case.inputs.items():
        stored = data.get(f"input_{k}")
        same = same and stored is not None and np.array_equal(stored, np.asarray(v, dtype=float))
    if not same:
        raise RuntimeError(
            f"The stored reference {path} was computed for other inputs or another grid "
            f"than the case {case.name!r}: regenerate it (tools/make_{name}_reference.py)."
        )
    q = _make_continuous(np.ascontiguousarray(data["quat"], dtype=float))
    return {"t": case.t.copy(), "quat": q, "omega": np.ascontiguousarray(data["omega"])}


class Kovalevskaya(RigidGroup):
    """The Kovalevskaya top (``A = B = 2 C`` about the fixed point, the centre of mass
    in the equatorial plane; docs/theory.md §10): no closed form in poinsot, the exact
    states a stored 32-digit Taylor integration; the energy, ``K_z``, ``|gamma| = 1``
    and Kovalevskaya's integral conserved (the first two scored)."""

    name = "kovalevskaya"
    euler_seq = "ZXZ"

    def model(self, case: Case) -> Any:
        i = case.inputs
        return HeavyRigidBody(case.inertia_about_origin, i["mass"], i["com"],
                              g=-float(i["gravity"][2]))  # fmt: skip

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        return _stored(case, "kovalevskaya")

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        i = case.inputs
        q0, w0 = i["q0"], i["omega0"]
        ints = self.integrals(case, {"quat": q0[None], "omega": w0[None]})
        gamma = np.asarray(model.gamma(q0), dtype=float)
        return {
            "energy_J": float(ints["energy"][0]),
            "area_integral_kg_m2_per_s": float(ints["momentum"][0, 2]),
            "poisson_gamma_norm": float(np.linalg.norm(gamma)),
            "kovalevskaya_K_rad4_per_s4": float(model.kovalevskaya_integral(q0, w0)),
        }

    def conserved_momentum(self, k: np.ndarray) -> np.ndarray:
        return k[:, 2]  # the area integral K_z


class BodyTorque(RigidGroup):
    """A free axisymmetric body under a constant torque along its symmetry axis: the
    exact states a stored 32-digit Taylor integration (the angular velocity also in
    closed form, :meth:`omega`); the transverse kinetic energy conserved."""

    name = "body-torque"
    has_momentum = False
    units = {**RigidGroup.units, "body_torque": "N m"}
    adapter_skip = {
        "Drake": ("Drake's adapter applies no external torque: a torque fixed in body axes "
                  "would need a LeafSystem wired to the plant's applied-force port, not "
                  "built here (docs/verify.md)"),
    }  # fmt: skip

    def engine_loads(self, case: Case) -> dict[str, Any]:
        """The constant body-axes torque of :meth:`torque`, applied at each stage
        (MuJoCo ``mjcb_passive``, PyBullet ``applyExternalTorque`` turned to world axes)."""
        return {"rotor_momentum": None, "torque": self.torque(case)}

    def constant_torque(self, case: Case) -> np.ndarray | None:
        return np.asarray(case.inputs["body_torque"], dtype=float)

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        return _stored(case, "body_torque")

    @staticmethod
    def omega(case: Case, t: np.ndarray) -> np.ndarray:
        """The closed form: ``w_3 = w_30 + M t / C``; ``w_1 + i w_2`` turns by
        ``((C - A) / A) (w_30 t + M t^2 / (2 C))``."""
        i = case.inputs
        a, c = float(i["inertia"][0, 0]), float(i["inertia"][2, 2])
        m = float(i["body_torque"][2])
        w1, w2, w30 = (float(x) for x in i["omega0"])
        phase = (c - a) / a * (w30 * t + 0.5 * m * t * t / c)
        z = (w1 + 1j * w2) * np.exp(1j * phase)
        return np.stack([z.real, z.imag, w30 + m * t / c], axis=-1)

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        i = case.inputs
        a, c = float(i["inertia"][0, 0]), float(i["inertia"][2, 2])
        m = float(i["body_torque"][2])
        w0 = i["omega0"]
        t1 = float(case.t[-1])
        return {
            "spin_rate_end_rad_per_s": float(w0[2] + m * t1 / c),
            "transverse_rate_rad_per_s": float(math.hypot(w0[0], w0[1])),
            "transverse_phase_end_rad": float((c - a) / a * (w0[2] * t1 + 0.5 * m * t1**2 / c)),
        }

    def torque(self, case: Case) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None:
        m = np.asarray(case.inputs["body_torque"], dtype=float)
        return lambda t, q, w: m

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        a = float(case.inputs["inertia"][0, 0])
        w = states["omega"]
        return {"energy": 0.5 * a * (w[:, 0] ** 2 + w[:, 1] ** 2)}


class Gyrostat(RigidGroup):
    """A free gyrostat with constant rotor momentum ``h`` (:class:`FreeGyrostat`,
    docs/theory.md §10.1): ``J w' + w x (J w + h) = 0``; the energy ``w . J w / 2``
    and ``K = R (J w + h)`` conserved."""

    name = "gyrostat"
    units = {**RigidGroup.units, "rotor_momentum": "kg m^2/s"}

    def engine_loads(self, case: Case) -> dict[str, Any]:
        """The rotor: a second body on a hinge (:func:`poinsot.verify._mujoco.rotor_inputs`)."""
        return {"rotor_momentum": np.asarray(case.inputs["rotor_momentum"], dtype=float),
                "torque": None}  # fmt: skip

    def model(self, case: Case) -> Any:
        i = case.inputs
        return FreeGyrostat(np.diag(i["inertia"]), i["rotor_momentum"], rotation0=i["q0"],
                            omega0=i["omega0"])  # fmt: skip

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        if case.event is not None:  # w_2 crossing the middle of its range (257 samples)
            w2 = np.asarray(model.omega(np.linspace(0.0, float(model.period), 257)))[:, 1]
            case.event["level"] = 0.5 * float(w2.min() + w2.max())
        return {"regime": str(model.regime), "period_s": float(model.period)}

    def torque(self, case: Case) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None:
        h = np.asarray(case.inputs["rotor_momentum"], dtype=float)
        return lambda t, q, w: -np.cross(w, h)

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        out = super().integrals(case, states)
        rmat = np.asarray(Rotation.from_quat(states["quat"]).as_matrix(), dtype=float)
        out["momentum"] = out["momentum"] + rmat @ np.asarray(case.inputs["rotor_momentum"])
        return out


class GravityGradient(RigidGroup):
    """Planar pitch libration in a circular orbit under the gravity-gradient torque
    (:class:`PitchLibration`, docs/theory.md §10.2). The space frame is the orbit
    frame at ``t = 0`` (``x`` along-track, ``y`` minus the orbit normal, ``z``
    nadir), which turns at ``-n`` about ``y``; the attitude is ``R_y(theta - n t)``
    and ``w = (0, theta' - n, 0)``. The torque is ``3 n^2 c x J c`` with ``c`` the
    nadir in body axes; the Jacobi integral of the orbit frame is conserved."""

    name = "gravity-gradient"
    has_momentum = False
    units = {**RigidGroup.units, "mean_motion": "rad/s"}
    adapter_skip = {
        "Drake": ("Drake's adapter applies no state-dependent external torque: the "
                  "gravity-gradient torque would need a LeafSystem wired to the plant's "
                  "applied-force port, not built here (docs/verify.md)"),
    }  # fmt: skip
    basilisk_skip = ("Basilisk's adapter runs a spacecraft hub alone, without the gravity "
                     "body and gravity-gradient effector an orbit would need "
                     "(docs/verify.md)")  # fmt: skip

    def engine_loads(self, case: Case) -> dict[str, Any]:
        """The gravity-gradient torque of :meth:`torque`, re-evaluated at each stage."""
        return {"rotor_momentum": None, "torque": self.torque(case)}

    def model(self, case: Case) -> Any:
        i = case.inputs
        q0 = i["q0"]
        theta0 = 2.0 * math.atan2(q0[2], q0[0])
        return PitchLibration(np.diag(i["inertia"]), i["mean_motion"], theta0=theta0,
                              rate0=float(i["omega0"][1]) + i["mean_motion"])  # fmt: skip

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        lib = case.model()
        n = case.inputs["mean_motion"]
        a = np.asarray(lib.theta(case.t)) - n * case.t
        z = np.zeros_like(a)
        q = _make_continuous(np.stack([np.cos(a / 2), z, np.sin(a / 2), z], axis=-1))
        w = np.stack([z, np.asarray(lib.rate(case.t)) - n, z], axis=-1)
        return {"t": case.t.copy(), "quat": q, "omega": w}

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        n = case.inputs["mean_motion"]
        if case.event is not None:  # the pitch rate theta' crossing half its largest value
            case.event["level"] = -n + 0.5 * model.modulus * model.omega0
        return {"regime": model.regime, "libration_period_s": float(model.period),
                "orbit_period_s": 2.0 * math.pi / case.inputs["mean_motion"],
                "small_libration_rate_rad_per_s": float(model.omega0)}  # fmt: skip

    def _nadir(self, case: Case, t: Any, rmat: np.ndarray) -> np.ndarray:
        n = case.inputs["mean_motion"]
        t = np.asarray(t, dtype=float)
        nadir = np.stack([-np.sin(n * t), np.zeros_like(t), np.cos(n * t)], axis=-1)
        return np.einsum("...ji,...j->...i", rmat, nadir)  # R^T nadir

    def torque(self, case: Case) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None:
        j = np.asarray(case.inputs["inertia"], dtype=float)
        k = 3.0 * case.inputs["mean_motion"] ** 2

        def gravity_gradient(t: float, q: np.ndarray, w: np.ndarray) -> np.ndarray:
            c = self._nadir(case, t, _matrix(q))
            return k * np.cross(c, j @ c)

        return gravity_gradient

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """The Jacobi integral of the orbit frame, ``w_r . J w_r / 2 - n^2 o . J o / 2
        + 3 n^2 c . J c / 2`` (``w_r = w - n o``, ``o`` the orbit normal in body axes)."""
        j = np.asarray(case.inputs["inertia"], dtype=float)
        n = case.inputs["mean_motion"]
        rmat = np.asarray(Rotation.from_quat(states["quat"]).as_matrix(), dtype=float)
        o = -rmat[:, 1, :]  # R^T (0, -1, 0)
        c = self._nadir(case, case.t, rmat)
        wr = states["omega"] - n * o

        def quad(u: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.einsum("ni,ij,nj->n", u, j, u)

        return {"energy": 0.5 * quad(wr) - 0.5 * n * n * quad(o) + 1.5 * n * n * quad(c)}


def _matrix(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of one scalar-first quaternion (normalised)."""
    w, x, y, z = np.asarray(q, dtype=float) / math.sqrt(float(np.dot(q, q)))
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])  # fmt: skip


class PointGroup(Group):
    """A point: position and velocity (docs/theory.md §7, §9)."""

    kind, states, errors = "point", ("position", "velocity"), ("position", "velocity")
    columns, poinsot_other = POINT_COLUMNS, "rigid bodies, not points"
    units = {"t": "s", "x,y,z": "m", "vx,vy,vz": "m/s", "mu": "m^3/s^2",
             "frame_rate": "rad/s", "length": "m", "g": "m/s^2"}  # fmt: skip
    mujoco_skip = ("MuJoCo models rigid bodies with joints; a point in a central field or a "
                   "turning frame is not expressed by this adapter")  # fmt: skip

    def result(self, case: Case, a: Any, b: Any, method: str) -> Result:
        return point_result(case, a, b, method)

    def arrays(self, result: Result) -> dict[str, np.ndarray]:
        assert isinstance(result, PointTrajectory)
        return {"position": np.asarray(result.position), "velocity": np.asarray(result.velocity)}

    def acceleration(self, case: Case) -> tuple[Any, Callable[..., np.ndarray]]:
        """``(frame, force(t, r, v))`` of the motion (force per unit mass)."""
        raise NotImplementedError

    def equations(self, case: Case) -> Equations:
        i = case.inputs
        rhs = self._rhs(case)

        def unpack_point(y: np.ndarray, method: str) -> Result:
            return point_result(case, y[:, :3].copy(), y[:, 3:].copy(), method)

        return rhs, np.concatenate([i["position0"], i["velocity0"]]), unpack_point

    def _rhs(self, case: Case) -> Callable[[float, np.ndarray], np.ndarray]:
        raise NotImplementedError

    def poinsot_method(self, method: str | None) -> str | None:
        if method is None:
            return "DOP853"
        return method if method in PARTICLE_SOLVERS and method != "adaptive" else None

    def poinsot_run(self, case: Case, method: str, step: float | None, rtol: float | None,
                    order: int | None, label: str) -> tuple[Any, Any]:  # fmt: skip
        i = case.inputs
        rtol = 1e-12 if rtol is None else rtol
        opts: dict[str, Any] = {"method": method, "rtol": rtol, "atol": rtol * 1e-3}
        if step is not None:
            opts["max_step"] = step
        frame, force = self.acceleration(case)
        pt = simulate_particle(frame, force, i["position0"], i["velocity0"], case.t, **opts)
        nfev = pt.info.get("evaluations")
        return (
            point_result(case, pt.position, pt.velocity, label),
            None if nfev is None else int(np.sum(nfev)),
        )

    def report_options(self, case: Case, errors: dict[str, np.ndarray]) -> dict[str, Any]:
        errs = {k: np.asarray(errors[k]) for k in self.errors}
        return {"series": [("error vs the exact solution", "1 (relative)", errs)]}


class Orbit(PointGroup):
    """Kepler orbits (docs/theory.md §9): energy and angular momentum conserved."""

    name = "orbit"

    def model(self, case: Case) -> Any:
        i = case.inputs
        return CentralOrbit.from_state(kepler(i["mu"]), i["position0"], i["velocity0"])

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        r, v = case.model().state(case.t)
        return {"t": case.t.copy(), "position": np.asarray(r), "velocity": np.asarray(v)}

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        return {"eccentricity": float(model.conic.e), "period_s": float(model.radial_period)}

    def _rhs(self, case: Case) -> Callable[[float, np.ndarray], np.ndarray]:
        pot = kepler(case.inputs["mu"])

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            r = y[:3]
            rn = math.sqrt(float(r @ r))
            return np.concatenate([y[3:], -float(pot.derivative(rn)) * r / rn])

        return rhs

    def acceleration(self, case: Case) -> tuple[Any, Callable[..., np.ndarray]]:
        pot = kepler(case.inputs["mu"])

        def gravity(t: float, r: np.ndarray, v: np.ndarray) -> np.ndarray:
            rn = math.sqrt(float(r @ r))
            return -float(pot.derivative(rn)) * r / rn

        return FrameMotion(), gravity

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        r, v = states["position"], states["velocity"]
        rn = np.linalg.norm(r, axis=-1)
        energy = 0.5 * np.einsum("ni,ni->n", v, v) + kepler(case.inputs["mu"])(rn)
        return {"energy": energy, "momentum": np.cross(r, v)}


class Frame(PointGroup):
    """The linear Foucault pendulum in its turning frame (docs/theory.md §9): the
    Jacobi integral conserved."""

    name = "frame"
    has_momentum = False

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        """The linear Foucault pendulum in its frame, exactly (docs/theory.md §9).

        In the inertial frame the bob is a plane isotropic oscillator,
        ``x_in(t) = x0 cos(w0 t) + (v0_in / w0) sin(w0 t)``, ``w0 = sqrt(g / l)``, with
        the inertial velocity ``v0_in = v0 + Omega x x0``; the frame turns at ``Omega``
        about the vertical, so ``x(t) = R_z(-Omega t) x_in(t)`` and
        ``v(t) = R_z(-Omega t) (v_in(t) - Omega x x_in(t))``.
        """
        i = case.inputs
        w0 = math.sqrt(i["g"] / i["length"])
        om = np.asarray(i["frame_rate"], dtype=float)
        x0 = np.asarray(i["position0"], dtype=float)
        v0 = np.asarray(i["velocity0"], dtype=float) + np.cross(om, x0)
        t = case.t[:, None]
        x_in = x0 * np.cos(w0 * t) + v0 / w0 * np.sin(w0 * t)
        v_in = -x0 * w0 * np.sin(w0 * t) + v0 * np.cos(w0 * t)
        v_rel_in = v_in - np.cross(om, x_in)
        c, s = np.cos(om[2] * case.t), np.sin(om[2] * case.t)

        def back(u: np.ndarray) -> np.ndarray:  # R_z(-Omega t) u
            return np.stack([c * u[:, 0] + s * u[:, 1], -s * u[:, 0] + c * u[:, 1], u[:, 2]], -1)

        return {"t": case.t.copy(), "position": back(x_in), "velocity": back(v_rel_in)}

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        i = case.inputs
        w0 = math.sqrt(i["g"] / i["length"])
        return {"swing_frequency_rad_per_s": w0,
                "plane_rate_rad_per_s": -float(i["frame_rate"][2])}  # fmt: skip

    def _rhs(self, case: Case) -> Callable[[float, np.ndarray], np.ndarray]:
        frame, spring = self.acceleration(case)

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            r, v = y[:3], y[3:]
            f = inertial_forces(frame, r, v)
            return np.concatenate([v, spring(t, r, v) + f.transport + f.coriolis])

        return rhs

    def acceleration(self, case: Case) -> tuple[Any, Callable[..., np.ndarray]]:
        i = case.inputs
        return FrameMotion(omega=i["frame_rate"]), PendulumForce(1.0, i["g"], i["length"])

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        i = case.inputs
        r, v = states["position"], states["velocity"]
        om = np.asarray(i["frame_rate"], dtype=float)
        w0sq = i["g"] / i["length"]
        horiz = r[:, :2]
        jacobi = (
            0.5 * np.einsum("ni,ni->n", v, v)
            + 0.5 * w0sq * np.einsum("ni,ni->n", horiz, horiz)
            - 0.5 * np.sum(np.cross(om, r) ** 2, axis=-1)
        )
        return {"energy": jacobi}


def pose_result(case: Case, position: Any, velocity: Any, quat: Any, omega: Any,
                method: str) -> PoseTrajectory:  # fmt: skip
    """A :class:`poinsot.PoseTrajectory` of ``case`` on its grid (docs/theory.md §9,
    §10): the centre of mass's position and velocity (m, m/s, space axes), scalar-first
    quaternions (body -> space, kept bit for bit) and body-axes angular velocities (rad/s).

    Examples
    --------
    >>> from poinsot.verify import cases
    >>> case = cases("thrown-box")[0]
    >>> ex = case.exact()
    >>> tr = pose_result(case, ex["position"], ex["velocity"], ex["quat"], ex["omega"], "x")
    >>> list(tr.state_channels()), tr.position.shape
    (['position', 'velocity', 'attitude', 'omega'], (301, 3))
    """
    q = np.ascontiguousarray(quat, dtype=float)
    return PoseTrajectory(case.t, Rotation._wrap(q), np.asarray(omega, dtype=float), method,
                          position=np.asarray(position, dtype=float),
                          velocity=np.asarray(velocity, dtype=float))  # fmt: skip


class FreeFlight(FreeBody):
    """A rigid body thrown in uniform gravity, six degrees of freedom (docs/theory.md
    §9, §10): the centre of mass moves on the parabola ``r0 + v0 t + g t^2 / 2``
    (``m r'' = m g``); gravity has no moment about the centre of mass, so the
    attitude is Euler-Poinsot motion (:class:`FreeRigidBody`). The mechanical energy
    ``m |v|^2 / 2 + w . J w / 2 - m g . r`` and the angular momentum about the
    centre of mass ``K = R J w`` (space axes) are conserved. Results are
    :class:`poinsot.PoseTrajectory` (states ``position``, ``velocity``, ``quat``,
    ``omega``)."""

    name = "free-flight"
    kind = "pose"
    states: tuple[str, ...] = ("position", "velocity", "quat", "omega")
    errors: tuple[str, ...] = ("position", "velocity", "attitude", "omega")
    columns: tuple[str, ...] = POSE_COLUMNS
    units = {**RigidGroup.units, "x,y,z": "m", "vx,vy,vz": "m/s", "position0": "m",
             "velocity0": "m/s"}  # fmt: skip
    poinsot_other = ("a rotation or a point, not a pose: poinsot's six-degree-of-freedom "
                     "motion (simulate_free_motion) is method 'dop853'")  # fmt: skip
    basilisk_skip = ("Basilisk's gravity is a planet's field (gravityEffector), not a uniform "
                     "one, and this adapter runs the attitude of a hub alone")  # fmt: skip

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        i = case.inputs
        t = case.t[:, None]
        g = np.asarray(i["gravity"], dtype=float)
        r = i["position0"] + i["velocity0"] * t + 0.5 * g * t * t
        v = i["velocity0"] + g * t
        return {**super().exact(case), "position": r, "velocity": v}

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        i = case.inputs
        g = -float(i["gravity"][2])
        vz = float(i["velocity0"][2])
        ints = self.integrals(case, {k: v[:1] for k, v in self.exact(case).items()})
        return {
            **super().facts(case, model),
            "apex_time_s": vz / g,
            "apex_height_m": float(i["position0"][2]) + 0.5 * vz * vz / g,
            "mechanical_energy_J": float(ints["energy"][0]),
            "angular_momentum_about_com_kg_m2_per_s": float(np.linalg.norm(ints["momentum"][0])),
        }

    def result(self, case: Case, a: Any, b: Any, method: str) -> Result:
        raise NotImplementedError("a pose has four state arrays: use of_states")

    def of_states(self, case: Case, states: dict[str, np.ndarray], method: str) -> Result:
        r, v, q, w = (states[k] for k in self.states)
        return pose_result(case, r, v, q, w, method)

    def arrays(self, result: Result) -> dict[str, np.ndarray]:
        assert isinstance(result, PoseTrajectory)
        assert result.position is not None and result.velocity is not None
        return {"position": np.asarray(result.position), "velocity": np.asarray(result.velocity),
                "quat": result.quat, "omega": np.asarray(result.omega)}  # fmt: skip

    def equations(self, case: Case) -> Equations:
        """The 13 states ``(r, v, q, w)``: ``r' = v``, ``v' = g``, the attitude and
        Euler's equations of the free body (the rigid groups' right-hand side)."""
        i = case.inputs
        rot_rhs, rot0, _ = super().equations(case)  # no torque: Euler-Poinsot
        g = np.asarray(i["gravity"], dtype=float)

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            return np.concatenate([y[3:6], g, rot_rhs(t, y[6:])])

        def unpack(y: np.ndarray, method: str) -> Result:
            return pose_result(case, y[:, :3].copy(), y[:, 3:6].copy(), quat_unit(y[:, 6:10]),
                               y[:, 10:].copy(), method)  # fmt: skip

        return rhs, np.concatenate([i["position0"], i["velocity0"], rot0]), unpack

    def poinsot_method(self, method: str | None) -> str | None:
        return "dop853" if method in (None, "dop853") else None

    def poinsot_run(self, case: Case, method: str, step: float | None, rtol: float | None,
                    order: int | None, label: str) -> tuple[Any, Any]:  # fmt: skip
        """:func:`poinsot.dynamics.simulate_free_motion` with the weight ``m g`` at the
        centre of mass (``rtol`` default 1e-12, ``atol = rtol * 1e-3``; no step option)."""
        i = case.inputs
        rtol = 1e-12 if rtol is None else rtol
        body = RigidBody(i["mass"], i["inertia"])
        tr = simulate_free_motion(body, i["position0"], i["velocity0"], i["q0"], i["omega0"],
                                  case.t, force=i["mass"] * np.asarray(i["gravity"]), rtol=rtol,
                                  atol=rtol * 1e-3)  # fmt: skip
        assert tr.position is not None and tr.velocity is not None
        return pose_result(case, tr.position, tr.velocity, quat_unit(tr.quat), tr.omega,
                           label), None  # fmt: skip

    def integrals(self, case: Case, states: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        i = case.inputs
        out = super().integrals(case, states)  # w . J w / 2 and K = R J w
        v = states["velocity"]
        g = np.asarray(i["gravity"], dtype=float)
        translation = i["mass"] * (0.5 * np.einsum("ni,ni->n", v, v) - states["position"] @ g)
        return {"energy": out["energy"] + translation, "momentum": out["momentum"]}


class Estimate:
    """An attitude estimate on an estimation case's grid, as scored (docs/verify.md;
    the attitude-error convention of docs/theory.md §10.4).

    Parameters
    ----------
    t : array_like, shape (n,)
        The case's grid (s).
    quat : array_like, shape (n, 4)
        Estimated attitude, scalar-first quaternions body -> space (any norm, either
        sign).
    bias : array_like, shape (n, 3), optional
        Estimated gyro bias (rad/s, body axes); None when the estimator gives none.
    sigma : array_like, shape (n, 3), optional
        The estimator's 1-sigma attitude error about the body axes (rad), the square
        roots of the diagonal of its attitude-error covariance; None when not given.
    method : str
        The estimator's label.

    Examples
    --------
    >>> import numpy as np
    >>> est = Estimate(np.arange(3.0), np.tile([1.0, 0.0, 0.0, 0.0], (3, 1)))
    >>> est.quat.shape, est.bias is None, est.sigma is None
    ((3, 4), True, True)
    """

    def __init__(self, t: Any, quat: Any, bias: Any = None, sigma: Any = None,
                 method: str = ""):  # fmt: skip
        self.t = np.asarray(t, dtype=float)
        self.quat = np.asarray(quat, dtype=float)
        self.bias = None if bias is None else np.asarray(bias, dtype=float)
        self.sigma = None if sigma is None else np.asarray(sigma, dtype=float)
        self.method = method

    def __repr__(self) -> str:
        given = [k for k in ("bias", "sigma") if getattr(self, k) is not None]
        return f"Estimate({self.t.size} samples, {', '.join(['quat', *given])}, {self.method!r})"

    def arrays(self) -> dict[str, np.ndarray]:
        """The given arrays, ``quat`` and (when given) ``bias``, ``sigma``."""
        out = {"quat": self.quat}
        if self.bias is not None:
            out["bias"] = self.bias
        if self.sigma is not None:
            out["sigma"] = self.sigma
        return out


def attitude_error_vectors(q_exact: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The attitude errors ``log(q_exact~ o q)`` (n, 3) in body axes (rad): the rotation
    vector that carries the exact attitude to ``q``, whatever the norm or sign of ``q``
    (NaN for a NaN ``q``; docs/theory.md §4, §10.4).

    >>> import numpy as np
    >>> q = [np.cos(0.005), 0.0, 0.0, -np.sin(0.005)]
    >>> attitude_error_vectors(np.array([[1.0, 0, 0, 0]]), np.array([q])).round(12) + 0.0
    array([[ 0.  ,  0.  , -0.01]])
    """
    qt = np.asarray(q_exact, dtype=float)
    qe = np.asarray(q, dtype=float)
    qe = qe / np.linalg.norm(qe, axis=-1, keepdims=True)
    tw, tv = qt[:, 0], -qt[:, 1:]
    ew, ev = qe[:, 0], qe[:, 1:]
    w = tw * ew - np.einsum("ni,ni->n", tv, ev)
    v = tw[:, None] * ev + ew[:, None] * tv + np.cross(tv, ev)
    sign = np.where(w < 0.0, -1.0, 1.0)
    w, v = w * sign, v * sign[:, None]
    nv = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(nv, w)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(nv > 0.0, angle / np.where(nv > 0.0, nv, 1.0), 2.0)
    return v * scale[:, None]


#: the stored sensor data of the estimation cases: case name -> file stem in data/
_SENSOR_DATA = {"mekf-racket": "mekf_racket"}

_ESTIMATE_SKIP = (
    "an attitude-estimation case (sensor data in, an attitude estimate out): run an "
    "estimator on the exported sensor files (poinsot verify export) and score its "
    "estimate with the file engine, or poinsot's MEKF (the poinsot engine)"
)


def draw_sensors(case: Case) -> dict[str, np.ndarray]:
    """Draw the sensor samples of an estimation case from its seed (the stored data
    come from this; ``tools/make_estimation_reference.py``).

    The truth is :meth:`Case.model`'s exact motion; the gyro (:class:`poinsot.dynamics.Gyro`,
    rate-integrating, the case's ``gyro_arw``, ``gyro_rrw``, ``gyro_bias0``) samples
    it on the case's grid, the star tracker (:class:`poinsot.dynamics.StarTracker`,
    ``star_tracker_sigma`` about x, y, z) every ``star_tracker_period``, each from its
    own PCG64 stream of ``numpy.random.SeedSequence(seed).spawn(2)`` (docs/theory.md
    §10.4).

    >>> from poinsot.verify import cases
    >>> d = draw_sensors(cases("mekf-racket")[0])
    >>> d["gyro_rate"].shape, d["star_tracker_quat"].shape
    ((2001, 3), (201, 4))
    """
    i = case.inputs
    model = case.model()
    streams = np.random.SeedSequence(int(i["seed"])).spawn(2)
    g_rng, s_rng = (np.random.Generator(np.random.PCG64(s)) for s in streams)
    gyro = Gyro(float(i["gyro_arw"]), float(i["gyro_rrw"]), bias0=i["gyro_bias0"])
    g = gyro.sample(model.trajectory(case.t), rng=g_rng)
    every = _tracker_every(case)
    sig = np.asarray(i["star_tracker_sigma"], dtype=float)
    if sig[0] != sig[1]:
        raise InvalidInputError("Expected equal star-tracker sigmas about x and y.")
    st = StarTracker(float(sig[0]), boresight_sigma=float(sig[2]))
    s = st.sample(model.trajectory(case.t[::every]), rng=s_rng)
    return {"gyro_rate": np.asarray(g.rate), "gyro_bias": np.asarray(g.bias),
            "star_tracker_t": np.asarray(s.t), "star_tracker_quat": np.asarray(s.quat)}  # fmt: skip


def _tracker_every(case: Case) -> int:
    """The star tracker samples every this many points of the grid."""
    return int(round(float(case.inputs["star_tracker_period"]) / float(case.t[1] - case.t[0])))


class Estimation(Group):
    """Attitude estimation against exact truth (docs/theory.md §10.4, docs/verify.md):
    a free body tumbling near its intermediate axis (:class:`FreeRigidBody`, exact)
    sampled by a gyro and a star tracker (stored, seeded samples); an estimator's
    attitude (and optionally bias and 1-sigma attitude errors) scored against the
    truth, with a NEES consistency verdict. Results are :class:`Estimate`; poinsot's
    engine runs :func:`poinsot.dynamics.run_mekf`, the integrators skip the group."""

    name = "estimation"
    kind = "estimate"
    states: tuple[str, ...] = ("quat", "bias")
    errors: tuple[str, ...] = ("attitude", "attitude_rms", "bias", "nees")
    columns: tuple[str, ...] = ESTIMATE_COLUMNS[:8]
    units = {"t": "s", "qw,qx,qy,qz": "1", "bx,by,bz": "rad/s", "sx,sy,sz": "rad",
             "wx,wy,wz": "rad/s", "inertia": "kg m^2", "mass": "kg", "com": "m",
             "gravity": "m/s^2", "gyro_arw": "rad/s^0.5", "gyro_rrw": "rad/s^1.5",
             "gyro_bias0": "rad/s", "star_tracker_period": "s", "star_tracker_sigma": "rad",
             "bias_estimate0": "rad/s", "covariance0": "rad^2 (attitude), rad^2/s^2 (bias)",
             "seed": "1"}  # fmt: skip
    has_momentum = False
    mujoco_skip = _ESTIMATE_SKIP
    basilisk_skip = _ESTIMATE_SKIP
    scipy_skip = _ESTIMATE_SKIP
    poinsot_other = ("rigid-body or point motion, not an attitude estimate: poinsot's engine "
                     "runs its MEKF (run_mekf) with the default method")  # fmt: skip
    result_types = (Estimate,)

    def model(self, case: Case) -> Any:
        i = case.inputs
        return FreeRigidBody(i["inertia"], rotation0=i["q0"], omega0=i["omega0"])

    def stored(self, case: Case) -> dict[str, np.ndarray]:
        """The stored sensor samples of the case (``poinsot/verify/data/NAME.npz``),
        checked against its grid and inputs (cached)."""
        cache = case.__dict__.setdefault("_sensors", {})
        if cache:
            return dict(cache)
        name = _SENSOR_DATA[case.name]
        path = Path(__file__).parent / "data" / f"{name}.npz"
        with np.load(path) as d:
            data = {k: d[k] for k in d.files}
        same = data["t"].shape == case.t.shape and np.array_equal(data["t"], case.t)
        for k, v in case.inputs.items():
            got = data.get(f"input_{k}")
            same = same and got is not None and np.array_equal(got, np.asarray(v, dtype=float))
        if not same:
            raise RuntimeError(
                f"The stored sensor data {path} were drawn for other inputs or another grid "
                f"than the case {case.name!r}: regenerate them "
                "(tools/make_estimation_reference.py)."
            )
        for k in ("gyro_rate", "gyro_bias", "star_tracker_t", "star_tracker_quat"):
            data[k].setflags(write=False)
            cache[k] = data[k]
        return dict(cache)

    def exact(self, case: Case) -> dict[str, np.ndarray]:
        omega, rot = case.model().state(case.t)
        q = _make_continuous(np.asarray(rot.as_quat(), dtype=float))
        return {"t": case.t.copy(), "quat": q, "bias": np.array(self.stored(case)["gyro_bias"]),
                "omega": np.asarray(omega, dtype=float)}  # fmt: skip

    def facts(self, case: Case, model: Any) -> dict[str, Any]:
        lo, hi = nees_band(case)
        return {"regime": str(model.regime), "period_s": float(model.period),
                "flip_period_s": float(model.period) / 2.0,
                "nees_dof": 3, "nees_band_95": [lo, hi],
                "star_tracker_samples": int(case.t[::_tracker_every(case)].size)}  # fmt: skip

    def sensors(self, case: Case) -> tuple[GyroSamples, AttitudeSamples]:
        """The case's gyro and star-tracker samples as :func:`poinsot.dynamics.run_mekf`
        reads them (with the truth they were drawn from)."""
        i, d, ex = case.inputs, self.stored(case), case.exact()
        every = _tracker_every(case)
        gyro = GyroSamples(case.t.copy(), np.array(d["gyro_rate"]), np.array(ex["omega"]),
                           np.array(d["gyro_bias"]), np.array(ex["quat"]), float(i["gyro_arw"]),
                           float(i["gyro_rrw"]), "integrating")  # fmt: skip
        st = AttitudeSamples(np.array(d["star_tracker_t"]), np.array(d["star_tracker_quat"]),
                             np.array(ex["quat"][::every]),
                             np.asarray(i["star_tracker_sigma"], dtype=float))  # fmt: skip
        return gyro, st

    def sensor_files(self, case: Case) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        d = self.stored(case)
        return {
            "gyro": (("t", "wx", "wy", "wz"), np.column_stack([case.t, d["gyro_rate"]])),
            "star_tracker": (("t", "qw", "qx", "qy", "qz"),
                             np.column_stack([d["star_tracker_t"], d["star_tracker_quat"]])),
        }  # fmt: skip

    def describe(self, case: Case) -> dict[str, Any]:
        lo, hi = nees_band(case)
        return {
            "sensor_files": {
                f"{case.name}.gyro.csv": "t (s), wx, wy, wz (rad/s, body axes): a "
                "rate-integrating gyro, the row at t_k (k >= 1) the mean rate over "
                "(t_{k-1}, t_k] plus bias and noise; the row at t = 0 the rate at 0",
                f"{case.name}.star_tracker.csv": "t (s), qw, qx, qy, qz: measured attitude "
                "L o exp(nu / 2), scalar first, body -> space, nu ~ N(0, diag(sigma^2)) in "
                "body axes (star_tracker_sigma)",
            },
            "estimate_file": {
                "name": f"{case.name}.csv",
                "columns": list(ESTIMATE_COLUMNS),
                "required": ["t", "qw", "qx", "qy", "qz"],
                "meaning": "attitude estimate (scalar first, body -> space); optional gyro "
                "bias bx, by, bz (rad/s) and 1-sigma attitude errors sx, sy, sz (rad, about "
                "the body axes), each group all or none",
            },
            "initial_estimate": "the first star-tracker sample, bias_estimate0 and covariance0 "
            "(diagonal: attitude about x, y, z, then bias)",
            "verdict": f"the time average over the grid of NEES = sum_i (e_i / s_i)^2 (e the "
            f"attitude error in body axes) within [{lo:.4g}, {hi:.4g}], the two-sided 95 % "
            "interval of chi-square with 3 dof: one run, its samples taken as fully "
            "correlated (docs/verify.md)",
        }

    def poinsot_method(self, method: str | None) -> str | None:
        return "mekf" if method in (None, "mekf") else None

    def poinsot_run(self, case: Case, method: str, step: float | None, rtol: float | None,
                    order: int | None, label: str) -> tuple[Any, Any]:  # fmt: skip
        """:func:`poinsot.dynamics.run_mekf` with the case's noise model, started at the
        first star-tracker sample, ``bias_estimate0`` and ``covariance0``."""
        return mekf_estimate(case, label=label), None

    def score(self, case: Case, result: Any) -> tuple[dict[str, float], dict[str, np.ndarray],
                                                       dict[str, np.ndarray]] | None:  # fmt: skip
        assert isinstance(result, Estimate)
        ex = case.exact()
        err = attitude_error_vectors(ex["quat"], result.quat)
        angle = np.linalg.norm(err, axis=-1)
        half = case.t >= 0.5 * case.t[-1]
        values = {"attitude": _worst(float(np.max(angle[half]))),
                  "attitude_rms": _worst(float(np.sqrt(np.mean(angle[half] ** 2))))}  # fmt: skip
        errors = {"t": case.t, "attitude": angle}
        if result.bias is not None:
            values["bias"] = _worst(float(np.linalg.norm(result.bias[-1] - ex["bias"][-1])))
        if result.sigma is not None:
            nees = np.sum((err / result.sigma) ** 2, axis=-1)
            errors["nees"] = nees
            values["nees"] = float(np.mean(nees)) if np.all(np.isfinite(nees)) else math.nan
        return values, errors, result.arrays()

    def read_columns(self, path: Path, case: Case, cols: dict[str, np.ndarray],
                     label: str) -> tuple[Any, list[str]] | None:  # fmt: skip
        q = _columns(path, cols, ("qw", "qx", "qy", "qz"), required=True, what="attitude")
        assert q is not None
        bias = _columns(path, cols, ("bx", "by", "bz"), required=False, what="gyro bias")
        sigma = _columns(path, cols, ("sx", "sy", "sz"), required=False, what="1-sigma")
        defects = []
        bad = [c for c in ESTIMATE_COLUMNS[1:] if c in cols and not np.all(np.isfinite(cols[c]))]
        if bad:
            defects.append(f"non-finite values in column(s) {', '.join(bad)} of {path.name}")
        else:
            norm = np.linalg.norm(q, axis=-1)
            if np.max(np.abs(norm - 1.0)) > 1e-6:
                raise InvalidInputError(
                    f"{path}: expected unit quaternions in columns qw, qx, qy, qz, found |q| "
                    f"from {np.min(norm):.6g} to {np.max(norm):.6g}."
                )
            if sigma is not None and not np.all(sigma > 0.0):
                k = int(np.nonzero(~np.all(sigma > 0.0, axis=-1))[0][0])
                c = ("sx", "sy", "sz")[int(np.argmin(sigma[k] > 0.0))]
                raise InvalidInputError(
                    f"{path}: expected column `{c}` to hold positive 1-sigma attitude errors "
                    f"(rad), found {float(sigma[k, 'xyz'.index(c[1])])!r} in data row {k + 1}."
                )
        return Estimate(case.t, q, bias, sigma, label), defects

    def nan_states(self, case: Case) -> dict[str, np.ndarray]:
        return {"quat": np.full((case.t.size, 4), np.nan)}

    def arrays(self, result: Any) -> dict[str, np.ndarray]:
        assert isinstance(result, Estimate)
        return result.arrays()

    def of_states(self, case: Case, states: dict[str, np.ndarray], method: str) -> Any:
        return Estimate(case.t, states["quat"], states.get("bias"), states.get("sigma"), method)


def _worst(x: float) -> float:
    return x if math.isfinite(x) else math.inf


def _columns(path: Path, cols: dict[str, np.ndarray], names: tuple[str, ...], *,
             required: bool, what: str) -> np.ndarray | None:  # fmt: skip
    """The columns ``names`` stacked (n, k): all of them, or (not ``required``) none."""
    present = [c for c in names if c in cols]
    if not present and not required:
        return None
    if len(present) < len(names):
        missing = [c for c in names if c not in cols]
        raise InvalidInputError(
            f"{path}: expected the {what} columns {', '.join(names)}"
            + ("" if required else " (all or none)")
            + f"; missing {', '.join(f'`{c}`' for c in missing)}."
        )
    return np.column_stack([cols[c] for c in names])


def nees_band(case: Case, probability: float = 0.95) -> tuple[float, float]:
    """The pass band of the time-averaged NEES of an estimation case: the two-sided
    ``probability`` interval of chi-square with 3 degrees of freedom (docs/verify.md).

    One run's NEES samples are correlated in time (the filter remembers); in the
    limit of full correlation their average is one chi-square(3) draw, and with any
    less correlation it is more concentrated about its mean 3, so the interval of a
    single draw holds the average of a consistent estimator with at least about that
    probability. (Independent samples would give ``chi2(3 n) / n``, far too narrow for
    one correlated run.) ``scipy.stats.chi2``; docs/theory.md §10.4.

    >>> from poinsot.verify import cases
    >>> [round(x, 4) for x in nees_band(cases("mekf-racket")[0])]
    [0.2158, 9.3484]
    """
    from scipy.stats import chi2

    a = 0.5 * (1.0 - probability)
    lo, hi = chi2.ppf([a, 1.0 - a], 3)
    return float(lo), float(hi)


def mekf_estimate(case: Case, *, arw: float | None = None, rrw: float | None = None,
                  label: str = "poinsot mekf") -> Estimate:  # fmt: skip
    """poinsot's MEKF (:func:`poinsot.dynamics.run_mekf`) on an estimation case's
    sensor data: started at the first star-tracker sample with ``bias_estimate0`` and
    ``covariance0``, the gyro noise the case's (or ``arw``, ``rrw``: a mis-stated
    model); the estimate with its bias and 1-sigma attitude errors (docs/theory.md §10.4).

    >>> from poinsot.verify import cases
    >>> est = mekf_estimate(cases("mekf-racket")[0])
    >>> est.quat.shape, est.sigma.shape
    ((2001, 4), (2001, 3))
    """
    i = case.inputs
    gyro, st = case.spec.sensors(case)  # type: ignore[attr-defined]
    res = run_mekf(gyro, [st], st.quat[0], np.asarray(i["covariance0"], dtype=float),
                   bias0=i["bias_estimate0"], arw=arw, rrw=rrw)  # fmt: skip
    return Estimate(case.t, np.asarray(res.quat), np.asarray(res.bias),
                    np.asarray(res.sigma)[:, :3], label)  # fmt: skip


#: group name -> its object (the order of :data:`poinsot.verify.GROUPS`)
GROUP_TABLE: dict[str, Group] = {
    g.name: g
    for g in (FreeBody(), HeavyTop(), Kovalevskaya(), BodyTorque(), Gyrostat(),
              GravityGradient(), Orbit(), Frame(), FreeFlight(), Estimation())
}  # fmt: skip


def as_result(case: Any, states: Any, method: str = "") -> Any:
    """``states`` as a result: a result as it is, a dict of arrays (the form of
    poinsot 1.x engines, deprecated) converted."""
    if isinstance(states, case.spec.result_types):
        return states
    if not isinstance(states, dict):
        raise InvalidTypeError(
            "Expected an engine's states to be a poinsot Trajectory or PointTrajectory, got "
            f"{type(states).__name__}."
        )
    return case.spec.of_states(case, states, method)


def _deprecated_states() -> None:
    warnings.warn(
        "A dict of states is deprecated: an engine's run(case) returns a poinsot "
        "Trajectory (rigid cases) or PointTrajectory (point cases) on case.t, and "
        "evaluate() reads one (docs/verify.md).",
        DeprecationWarning,
        stacklevel=3,
    )
