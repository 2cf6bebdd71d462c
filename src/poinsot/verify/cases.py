"""The reference cases of ``poinsot verify``: classical motions with exact solutions.

Each :class:`Case` gives its inputs in SI units, a time grid and the exact states on
it, computed by poinsot's closed-form solutions (docs/theory.md §9, §10):

- ``free-body``: Euler-Poinsot motion (Jacobi elliptic functions), about the minor
  axis, about the major axis, near the separatrix (the tennis-racket flip), a
  free symmetric top, and (version 2) a pair with ``1 - k^2 = 1e-6`` on either
  side of the separatrix;
- ``heavy-top``: the Lagrange top (elliptic solution of the nutation, precession
  and spin) with loops, with cusps (released from rest), in regular precession,
  (version 2) with waves, and the sleeping top above and below its critical spin
  (far from it, and 2 % from it);
- ``kovalevskaya`` (version 2): the Kovalevskaya top, a stored 32-digit Taylor
  integration (``tools/make_kovalevskaya_reference.py``);
- ``body-torque`` (version 2): a free axisymmetric body under a constant torque
  along its symmetry axis, a stored 32-digit Taylor integration
  (``tools/make_body_torque_reference.py``; the angular velocity in closed form);
- ``gyrostat`` (version 2): a dual-spin gyrostat (:class:`FreeGyrostat`);
- ``gravity-gradient`` (version 2): pitch libration in a circular orbit
  (:class:`PitchLibration`);
- ``orbit``: Kepler orbits with e = 0.5 and e = 0.95 (Kepler's equation);
- ``frame``: the Foucault pendulum in its turning frame (Coriolis and centrifugal
  forces), linear theory, with the frame turning fast enough for the rate to show;
- ``free-flight`` (version 3): a homogeneous box thrown spinning near its
  intermediate axis in uniform gravity, six degrees of freedom: the centre of mass on
  its parabola, the attitude Euler-Poinsot motion (two flips in flight).

**Conventions** (docs/conventions.md): quaternions scalar first ``(w, x, y, z)``,
attitude body -> space (``v_space = R v_body``), angular velocity in body axes
(rad/s), inertia about the centre of mass in body axes (kg m^2), the centre of
mass from the fixed point ``O`` in body axes (m), gravity in space axes (m/s^2),
positions and velocities in the case's own frame (m, m/s). Times start at 0 s.
Version 2 inputs: ``body_torque`` (N m, body axes), ``rotor_momentum`` (kg m^2/s,
body axes, relative to the body), ``mean_motion`` (rad/s, the circular orbit's
rate; the space frame is the orbit frame at t = 0). Version 3 inputs:
``position0``, ``velocity0`` of a body's centre of mass (m, m/s, space axes).
Version 4 inputs (estimation): the gyro's ``gyro_arw`` (rad/s^0.5), ``gyro_rrw``
(rad/s^1.5), ``gyro_bias0`` (rad/s), the star tracker's ``star_tracker_period`` (s)
and ``star_tracker_sigma`` (rad, about body x, y, z), the ``seed`` of the samples,
the estimator's ``bias_estimate0`` (rad/s) and diagonal ``covariance0``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InvalidInputError, InvalidTypeError
from ..mass.solids import box
from ..mass.tensor import parallel_axis
from ..rotations.rotation import Rotation
from .groups import GROUP_TABLE, Group

#: version of the set of cases: bumped whenever a case's inputs, grid or thresholds change
CASES_VERSION = "4"

#: groups of cases (``--cases`` accepts a group or a case name); each is one object of
#: :data:`poinsot.verify.groups.GROUP_TABLE`
GROUPS = tuple(GROUP_TABLE)

#: default thresholds: attitude (rad, geodesic), angular velocity and velocity
#: (relative to the case's scale), position (relative to the case's length scale),
#: relative drift of each integral, and event times (s)
DEFAULT_THRESHOLDS: dict[str, float] = {
    "attitude": 1e-6,
    "omega": 1e-6,
    "position": 1e-6,
    "velocity": 1e-6,
    "energy": 1e-8,
    "momentum": 1e-8,
    "events": 1e-5,
}


@dataclass(frozen=True, eq=False)
class Case:
    """One reference motion: inputs (SI), a time grid and its exact states.

    Attributes
    ----------
    name : str
        Identifier, e.g. ``"racket-flip"``.
    group : str
        One of :data:`GROUPS`.
    description : str
        One line for people.
    kind : {"rigid", "point", "pose", "estimate"}
        A rigid body (states ``quat`` (n, 4), ``omega`` (n, 3) in body axes), a
        point (states ``position``, ``velocity`` (n, 3)), or a rigid body in six
        degrees of freedom (states ``position``, ``velocity`` of the centre of mass,
        space axes, then ``quat``, ``omega``), or an attitude estimate (states
        ``quat`` and, optionally, ``bias`` and ``sigma``; the truth ``quat``, ``bias``).
    inputs : dict
        SI inputs. Rigid: ``inertia`` (3, 3) about the centre of mass (kg m^2),
        ``mass`` (kg), ``com`` (3,) centre of mass from the fixed point (m, zero for
        a free body), ``gravity`` (3,) (m/s^2, space axes), ``fixed_point`` (bool),
        ``q0`` (4,) and ``omega0`` (3,) (rad/s, body axes). Orbit: ``mu``
        (m^3/s^2), ``position0``, ``velocity0``. Pose: the rigid inputs (a free
        body, ``gravity`` uniform) and the centre of mass's ``position0``,
        ``velocity0`` (m, m/s, space axes). Frame: ``frame_rate`` (3,) (rad/s,
        the frame's angular velocity in its own axes), ``length`` (m), ``g``
        (m/s^2), ``position0``, ``velocity0`` (relative to the frame).
    t : ndarray, shape (n,)
        The time grid (s), uniform, from 0.
    thresholds : dict
        The largest errors that pass (see :data:`DEFAULT_THRESHOLDS`).
    event : dict or None
        The characteristic event: ``{"name", "signal", "level"}``: the times at
        which ``signal`` (see :func:`poinsot.verify.metrics.event_signal`) crosses
        ``level`` (flips, nutation half-periods, the mean distance of an orbit, the
        half amplitude of a swing).
    facts : dict
        Exact characteristic figures of the motion (periods, regime...), with units
        in the key names.
    """

    name: str
    group: str
    description: str
    kind: str
    inputs: dict[str, Any]
    t: np.ndarray
    thresholds: dict[str, float]
    event: dict[str, Any] | None = None
    facts: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        return f"Case({self.name!r}, group={self.group!r}, n={self.t.size}, t_end={self.t[-1]:g} s)"

    @property
    def inertia_about_origin(self) -> np.ndarray:
        """Inertia about the fixed point ``J_O = J_C + m (|c|^2 E - c c^T)`` (kg m^2).

        The parallel-axis theorem (docs/theory.md §8); equal to ``inertia`` for a
        free body (``c = 0``).
        """

        i = self.inputs
        return np.asarray(parallel_axis(i["inertia"], i["mass"], i["com"]), dtype=float)

    def exact(self) -> dict[str, np.ndarray]:
        """The exact states on :attr:`t` (computed once, then cached; read-only arrays).

        Returns
        -------
        dict
            ``{"t", "quat", "omega"}`` for a rigid body (scalar-first quaternions
            body -> space, sign-continuous; body-axes rad/s), ``{"t", "position",
            "velocity"}`` for a point (m, m/s), all four for a pose.
        """
        cache = self.__dict__.setdefault("_exact", {})
        if not cache:
            cache.update(self.spec.exact(self))
            for v in cache.values():
                v.setflags(write=False)
        return dict(cache)

    def reference(self) -> Any:
        """The exact motion on :attr:`t` as a poinsot result (computed once, then cached):
        a :class:`poinsot.Trajectory` for a rigid body, a :class:`poinsot.PointTrajectory`
        for a point, a :class:`poinsot.PoseTrajectory` for a pose, ``method="exact"``; the
        states of :meth:`exact`, bit for bit."""
        ref = self.__dict__.get("_reference")
        if ref is None:
            ref = self.spec.of_states(self, self.exact(), "exact")
            self.__dict__["_reference"] = ref
        return ref

    def model(self) -> Any:
        """The poinsot exact-solution object of this case (FreeRigidBody, LagrangeTop,
        FreeGyrostat, PitchLibration, CentralOrbit; the HeavyRigidBody of the
        Kovalevskaya top), or None (the frame case, closed form,
        :meth:`poinsot.verify.groups.Frame.exact`; the body-torque case, stored)."""
        return self.spec.model(self)

    @property
    def spec(self) -> Group:
        """The object of the case's group (:mod:`poinsot.verify.groups`): its model,
        exact states, units, adapter hooks and integrals."""
        return GROUP_TABLE[self.group]


def _grid(duration: float, dt: float) -> np.ndarray:
    n = int(round(duration / dt))
    return np.arange(n + 1) * dt


def _zxz(psi: float, theta: float, phi: float) -> np.ndarray:
    return np.asarray(Rotation.from_euler("ZXZ", [psi, theta, phi]).as_quat(), dtype=float)


def _free(name: str, description: str, moments: Any, omega0: Any, event: Any = None,
          duration: float = 10.0) -> Case:  # fmt: skip
    return Case(
        name=name,
        group="free-body",
        description=description,
        kind="rigid",
        inputs={
            "inertia": np.diag(np.asarray(moments, dtype=float)),
            "mass": 1.0,
            "com": np.zeros(3),
            "gravity": np.zeros(3),
            "fixed_point": False,
            "q0": np.array([1.0, 0.0, 0.0, 0.0]),
            "omega0": np.asarray(omega0, dtype=float),
        },
        t=_grid(duration, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event=event,
    )


def _top(name: str, description: str, *, theta: float, spin: float, precession: float,
         event: bool = True, duration: float = 5.0) -> Case:  # fmt: skip
    # A = 0.05, C = 0.02 kg m^2 about the centre of mass, m = 1 kg, l = 0.1 m: about O,
    # A_O = 0.06 kg m^2; m g l = 0.980665 N m
    m, l_ = 1.0, 0.1
    # at psi = phi = 0 the precession rate psi' adds psi' sin(theta) to w_2 (z-x-z);
    # a NaN precession is filled in by _finish with the slow regular-precession rate
    omega0 = np.array([0.0, precession * math.sin(theta), spin])
    return Case(
        name=name,
        group="heavy-top",
        description=description,
        kind="rigid",
        inputs={
            "inertia": np.diag([0.05, 0.05, 0.02]),
            "mass": m,
            "com": np.array([0.0, 0.0, l_]),
            "gravity": np.array([0.0, 0.0, -9.80665]),
            "fixed_point": True,
            "q0": _zxz(0.0, theta, 0.0),
            "omega0": omega0,
        },
        t=_grid(duration, 0.005),  # 5 s: 15 nutation periods
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "nutation", "signal": "cos_tilt", "level": None} if event else None,
    )


#: the tops' critical spin ``2 sqrt(A_O m g l) / C`` (rad/s): a sleeping top is stable above it
_CRITICAL_SPIN = 2.0 * math.sqrt(0.06 * 1.0 * 9.80665 * 0.1) / 0.02


def kovalevskaya_case() -> Case:
    """The Kovalevskaya top: ``A = B = 2 C`` about the fixed point, the centre of mass
    in the equatorial plane; its exact states are a 32-digit Taylor integration
    stored in ``poinsot/verify/data/kovalevskaya.npz``
    (``tools/make_kovalevskaya_reference.py`` regenerates it)."""
    # about O: diag(1/8, 1/8, 1/16) kg m^2, exactly (binary fractions): m = 1 kg,
    # c = (1/8, 0, 0) m, so about the centre of mass diag(1/8, 7/64, 3/64)
    return Case(
        name="kovalevskaya",
        group="kovalevskaya",
        description="Kovalevskaya top (A = B = 2 C about the fixed point, centre of mass "
        "in the equatorial plane): four integrals, a stored 32-digit reference",
        kind="rigid",
        inputs={
            "inertia": np.diag([0.125, 0.109375, 0.046875]),
            "mass": 1.0,
            "com": np.array([0.125, 0.0, 0.0]),
            "gravity": np.array([0.0, 0.0, -9.80665]),
            "fixed_point": True,
            "q0": _zxz(0.2, 0.9, 0.4),
            "omega0": np.array([1.0, -0.5, 3.0]),
        },
        t=_grid(4.0, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "nutation", "signal": "cos_tilt", "level": 0.0},
    )


def body_torque_case() -> Case:
    """A free axisymmetric body under a constant torque along its symmetry axis: the
    spin grows linearly, the transverse rate turns in body axes at the growing rate
    ``(C - A) / A w_3(t)``; the attitude (no elementary closed form: a Landau-Zener
    problem) is a 32-digit Taylor integration stored in
    ``poinsot/verify/data/body_torque.npz`` (``tools/make_body_torque_reference.py``)."""
    return Case(
        name="body-torque",
        group="body-torque",
        description="free axisymmetric body (A = 2, C = 1 kg m^2) spun up by a constant "
        "0.5 N m about its symmetry axis",
        kind="rigid",
        inputs={
            "inertia": np.diag([2.0, 2.0, 1.0]),
            "mass": 1.0,
            "com": np.zeros(3),
            "gravity": np.zeros(3),
            "fixed_point": False,
            "q0": np.array([1.0, 0.0, 0.0, 0.0]),
            "omega0": np.array([1.0, 0.0, 2.0]),
            "body_torque": np.array([0.0, 0.0, 0.5]),
        },
        t=_grid(10.0, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        # w_2 starts at 0: the level is off it, so that no crossing sits on t = 0
        event={"name": "transverse turns", "signal": "omega_1", "level": 0.5},
    )


def _gyrostat() -> Case:
    # dual spin: a rotor along the intermediate axis (h = 3 kg m^2/s) stabilises the
    # rotation about that axis, which alone would tumble (the racket flip)
    return Case(
        name="dual-spin",
        group="gyrostat",
        description="dual-spin gyrostat: rotor momentum 3 kg m^2/s along the intermediate "
        "axis, spin 1 rad/s about it, nudged: a stable wobble, no flip",
        kind="rigid",
        inputs={
            "inertia": np.diag([1.0, 2.0, 3.0]),
            "mass": 1.0,
            "com": np.zeros(3),
            "gravity": np.zeros(3),
            "fixed_point": False,
            "q0": np.array([1.0, 0.0, 0.0, 0.0]),
            "omega0": np.array([0.1, 1.0, 0.1]),
            "rotor_momentum": np.array([0.0, 3.0, 0.0]),
        },
        t=_grid(20.0, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "wobble", "signal": "omega_1", "level": None},
    )


def _pitch() -> Case:
    # a 105-minute circular orbit (n = 1e-3 rad/s), moments (2, 3, 1) kg m^2
    # (roll, pitch, yaw): pitch libration of 0.5 rad amplitude, period 2 pi / n
    # times a factor 1.07; the orbit frame at t = 0 is the space frame
    n, theta0 = 1e-3, 0.5
    return Case(
        name="pitch-libration",
        group="gravity-gradient",
        description="gravity-gradient pitch libration in a circular orbit (n = 1e-3 rad/s), "
        "released at 0.5 rad from the local vertical at rest in the orbit frame",
        kind="rigid",
        inputs={
            "inertia": np.diag([2.0, 3.0, 1.0]),
            "mass": 1.0,
            "com": np.zeros(3),
            "gravity": np.zeros(3),
            "fixed_point": False,
            "q0": np.array([math.cos(theta0 / 2.0), 0.0, math.sin(theta0 / 2.0), 0.0]),
            "omega0": np.array([0.0, -n, 0.0]),
            "mean_motion": n,
        },
        t=_grid(20000.0, 10.0),
        # a time scale 10^3 times the others': events to 1e-3 s (1.5e-7 of a libration
        # period); the Jacobi integral is a quarter of its terms (n^2 I sums that
        # cancel), its drift to 1e-7
        thresholds={**DEFAULT_THRESHOLDS, "events": 1e-3, "energy": 1e-7},
        event={"name": "pitch rate", "signal": "omega_1", "level": None},
    )


def _kepler(name: str, e: float) -> Case:
    # mu = 1 m^3/s^2, a = 1 m: period 2 pi s; released at pericentre
    rp = 1.0 - e
    vp = math.sqrt((1.0 + e) / rp)
    return Case(
        name=name,
        group="orbit",
        description=f"Kepler orbit, e = {e} (mu = 1 m^3/s^2, a = 1 m, period 2 pi s)",
        kind="point",
        inputs={
            "mu": 1.0,
            "position0": np.array([rp, 0.0, 0.0]),
            "velocity0": np.array([0.0, vp, 0.0]),
        },
        t=_grid(4.0 * math.pi, 2.0 * math.pi / 2000.0),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "apsides", "signal": "radius", "level": 1.0},
    )


def _all_cases() -> list[Case]:
    w = 2.0
    cases = [
        _free("free-minor-axis", "free asymmetric body spinning near its axis of least inertia",
              [1.0, 2.0, 3.0], [w, 0.1, 0.1]),
        _free("free-major-axis", "free asymmetric body spinning near its axis of greatest inertia",
              [1.0, 2.0, 3.0], [0.1, 0.1, w]),
        _free("racket-flip", "tennis-racket flip: spin near the intermediate axis, flipping "
              "every half period", [1.0, 2.0, 3.0], [0.1, 4.0, 0.1],
              event={"name": "flip", "signal": "omega_1", "level": 0.0}),
        _free("free-symmetric", "free symmetric top: regular precession of the axis",
              [2.0, 2.0, 1.0], [0.5, 0.0, 3.0]),
        _top("top-loops", "Lagrange top with loops (precession rate reversing)",
             theta=math.radians(40.0), spin=60.0, precession=-2.0),
        _top("top-cusps", "Lagrange top released from rest: cusps", theta=math.radians(40.0),
             spin=60.0, precession=0.0),
        _top("top-regular", "Lagrange top in slow regular precession", theta=math.radians(40.0),
             spin=60.0, precession=float("nan"), event=False),
        _top("sleeping-stable", "sleeping top above the critical spin, nudged: stays up",
             theta=1e-3, spin=60.0, precession=0.0, event=False),
        _top("sleeping-unstable", "sleeping top below the critical spin, nudged: falls away",
             theta=1e-3, spin=15.0, precession=0.0, event=True, duration=4.0),
        _top("top-waves", "Lagrange top with waves (the precession rate keeps its sign)",
             theta=math.radians(40.0), spin=60.0, precession=0.5),
        _top("sleeping-near-stable", "sleeping top 2 % above the critical spin, nudged: "
             "stays up (the nutation reaches 5 mrad)", theta=1e-3, spin=1.02 * _CRITICAL_SPIN,
             precession=0.0, duration=8.0),
        _top("sleeping-near-unstable", "sleeping top 2 % below the critical spin, nudged: "
             "falls to 23 degrees", theta=1e-3, spin=0.98 * _CRITICAL_SPIN, precession=0.0,
             duration=8.0),
        # 1 - k^2 = 1e-6 on either side of the separatrix (brentq on poinsot's
        # complementary_parameter; its values for these doubles: 1 - 4e-15 and 1 + 2e-14)
        _free("separatrix-minor", "just inside the separatrix (1 - k^2 = 1e-6, polhode "
              "about the minor axis): spin near the intermediate axis, flips",
              [1.0, 2.0, 3.0], [0.1, 4.0, 0.05768879151678138],
              event={"name": "flip", "signal": "omega_1", "level": 0.0}, duration=20.0),
        _free("separatrix-major", "just outside the separatrix (1 - k^2 = 1e-6, polhode "
              "about the major axis): spin near the intermediate axis, flips",
              [1.0, 2.0, 3.0], [0.1, 4.0, 0.05778122537067445],
              event={"name": "flip", "signal": "omega_1", "level": 0.0}, duration=20.0),
        kovalevskaya_case(),
        body_torque_case(),
        _gyrostat(),
        _pitch(),
        _kepler("kepler-e0.5", 0.5),
        _kepler("kepler-e0.95", 0.95),
    ]  # fmt: skip
    cases.append(_frame_case())
    cases.append(thrown_box_case())
    cases.append(mekf_racket_case())
    return [_finish(c) for c in cases]


def _frame_case() -> Case:
    # Foucault pendulum with a frame turning at 5 % of the swing frequency: the swing
    # plane turns by 18 degrees per swing period, and the centrifugal force counts
    length, g = 9.80665, 9.80665  # w0 = 1 rad/s
    return Case(
        name="foucault",
        group="frame",
        description="Foucault pendulum (linear theory) in a frame turning at 0.05 rad/s",
        kind="point",
        inputs={
            "frame_rate": np.array([0.0, 0.0, 0.05]),
            "length": length,
            "g": g,
            "position0": np.array([1.0, 0.0, 0.0]),
            "velocity0": np.zeros(3),
        },
        t=_grid(40.0, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "swings", "signal": "radius", "level": 0.5},
    )


def thrown_box_case() -> Case:
    """A homogeneous box thrown spinning in uniform gravity (six degrees of freedom).

    Edges 0.3, 0.2, 0.1 m along the body axes ``x, y, z`` and 1.5 kg: the inertia
    ``m/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2)`` (:func:`poinsot.mass.box`),
    ``diag(0.00625, 0.0125, 0.01625)`` kg m^2, its axis ``y`` the intermediate one.
    Released 1.5 m up at ``(4, 1, 15)`` m/s, tilted, spinning at 15 rad/s about ``y``
    with a nudge of 0.1 rad/s about the others, under ``g = 9.81`` m/s^2 along
    ``-z``: the centre of mass flies its parabola (apex 12.97 m at 1.53 s) while the
    box flips twice (the tennis-racket flip, at 1.06 s and 2.88 s) in 3 s (no
    ground). Exact: the parabola and :class:`poinsot.dynamics.FreeRigidBody`
    (docs/theory.md §9, §10).

    Examples
    --------
    >>> case = thrown_box_case()
    >>> case.inputs["inertia"].diagonal().round(6).tolist()
    [0.00625, 0.0125, 0.01625]
    >>> case.exact()["position"][-1].round(9).tolist()
    [12.0, 3.0, 2.355]
    """
    return Case(
        name="thrown-box",
        group="free-flight",
        description="box (0.3 x 0.2 x 0.1 m, 1.5 kg) thrown in uniform gravity, spinning "
        "near its intermediate axis: a parabola and two tennis-racket flips",
        kind="pose",
        inputs={
            "inertia": np.asarray(box(1.5, 0.3, 0.2, 0.1), dtype=float),
            "mass": 1.5,
            "com": np.zeros(3),
            "gravity": np.array([0.0, 0.0, -9.81]),
            "fixed_point": False,
            "q0": np.asarray(Rotation.from_euler("ZYX", [0.3, -0.2, 0.1]).as_quat(), dtype=float),
            "omega0": np.array([0.1, 15.0, 0.1]),
            "position0": np.array([0.0, 0.0, 1.5]),
            "velocity0": np.array([4.0, 1.0, 15.0]),
        },
        t=_grid(3.0, 0.01),
        thresholds=dict(DEFAULT_THRESHOLDS),
        event={"name": "flip", "signal": "omega_1", "level": 0.0},
    )


#: the thresholds of the estimation cases: attitude error (rad, largest over the second
#: half of the run, and RMS over it), bias error at the end (rad/s), and the band of the
#: time-averaged NEES (``nees_min`` to ``nees``: chi-square, 3 dof, two-sided 95 %)
ESTIMATION_THRESHOLDS: dict[str, float] = {
    "attitude": 1.5e-3,
    "attitude_rms": 5e-4,
    "bias": 1e-4,
    "nees": 9.348403604496148,
    "nees_min": 0.21579528262389797,
}


def mekf_racket_case() -> Case:
    """Attitude estimation on the tumbling of a racket-like body (version 4).

    The truth: the free body ``diag(1, 2, 3)`` kg m^2 spun at ``(0.1, 1, 0.1)`` rad/s,
    near its intermediate axis (it flips every 11.5 s), exact
    (:class:`poinsot.dynamics.FreeRigidBody`, docs/theory.md §10), on a 10 Hz grid over
    200 s. A rate-integrating gyro (Farrenkopf: ARW 1e-4 rad/s^0.5, RRW 1e-6
    rad/s^1.5, initial bias ``(1, -2, 0.5) 1e-3`` rad/s) on the grid and a star tracker
    at 1 Hz (1e-4 rad about x and y, 5e-4 rad about its boresight z), drawn once from
    the seed and stored (``poinsot/verify/data/mekf_racket.npz``,
    ``tools/make_estimation_reference.py``). An estimator starts from the first
    star-tracker sample, a zero bias and the diagonal covariance ``covariance0``
    (docs/theory.md §10.4).

    Examples
    --------
    >>> case = mekf_racket_case()
    >>> case.t.size, case.inputs["star_tracker_sigma"].tolist()
    (2001, [0.0001, 0.0001, 0.0005])
    """
    return Case(
        name="mekf-racket",
        group="estimation",
        description="attitude estimation: gyro (10 Hz) and star tracker (1 Hz) on a body "
        "tumbling near its intermediate axis, 200 s; attitude, bias and NEES consistency",
        kind="estimate",
        inputs={
            "inertia": np.diag([1.0, 2.0, 3.0]),
            "mass": 1.0,
            "com": np.zeros(3),
            "gravity": np.zeros(3),
            "fixed_point": False,
            "q0": np.array([1.0, 0.0, 0.0, 0.0]),
            "omega0": np.array([0.1, 1.0, 0.1]),
            "gyro_arw": 1e-4,
            "gyro_rrw": 1e-6,
            "gyro_bias0": np.array([1e-3, -2e-3, 5e-4]),
            "star_tracker_period": 1.0,
            "star_tracker_sigma": np.array([1e-4, 1e-4, 5e-4]),
            "seed": 20261130,
            "bias_estimate0": np.zeros(3),
            "covariance0": np.array([1e-8, 1e-8, 2.5e-7, 9e-6, 9e-6, 9e-6]),
        },
        t=_grid(200.0, 0.1),
        thresholds=dict(ESTIMATION_THRESHOLDS),
    )


def _finish(case: Case) -> Case:
    """Fill in what needs the model: regular precession rates, event levels, facts."""
    case.spec.prepare(case)
    facts = case.spec.facts(case, case.model())
    case.facts.update(facts)
    return case


_CACHE: list[Case] = []


def cases(select: str | Iterable[str] | None = None) -> list[Case]:
    """The reference cases, in a fixed order (version :data:`CASES_VERSION`).

    Parameters
    ----------
    select : str or iterable of str, optional
        Case names and/or groups (:data:`GROUPS`); a string may hold several,
        separated by commas. Default: every case.

    Returns
    -------
    list of Case

    Raises
    ------
    InvalidInputError
        For a name that is neither a case nor a group (the message lists them).

    Examples
    --------
    >>> from poinsot.verify import cases
    >>> [c.name for c in cases("orbit")]
    ['kepler-e0.5', 'kepler-e0.95']
    >>> racket = cases("racket-flip")[0]
    >>> round(racket.facts["flip_period_s"], 6), racket.exact()["quat"].shape
    (4.093072, (1001, 4))
    """
    if not _CACHE:
        _CACHE.extend(_all_cases())
    if select is None:
        return list(_CACHE)
    if isinstance(select, str):
        items = [s.strip() for s in select.split(",") if s.strip()]
    elif isinstance(select, Iterable):
        items = []
        for s in select:
            if not isinstance(s, str):
                raise InvalidTypeError(f"Expected `cases` to hold strings, got {s!r}.")
            items.extend(x.strip() for x in s.split(",") if x.strip())
    else:
        raise InvalidTypeError(f"Expected `cases` to be a string or strings, got {select!r}.")
    names = {c.name: c for c in _CACHE}
    chosen: list[Case] = []
    for s in items:
        found = (
            [c for c in _CACHE if c.spec is GROUP_TABLE[s]]
            if s in GROUP_TABLE
            else [names[s]]
            if s in names
            else []
        )
        if not found:
            raise InvalidInputError(
                f"Expected `cases` to name cases or groups, got {s!r}; groups: "
                f"{', '.join(GROUPS)}; cases: {', '.join(names)}."
            )
        chosen.extend(c for c in found if c not in chosen)
    return chosen


def describe(case: Case) -> Mapping[str, Any]:
    """A JSON-ready description of a case: inputs, grid, thresholds, units, conventions."""

    def plain(x: Any) -> Any:
        return x.tolist() if isinstance(x, np.ndarray) else x

    return {
        "name": case.name,
        "group": case.group,
        "description": case.description,
        "kind": case.kind,
        "cases_version": CASES_VERSION,
        "inputs": {k: plain(v) for k, v in case.inputs.items()},
        "time_grid": {
            "start_s": 0.0,
            "step_s": float(case.t[1] - case.t[0]),
            "samples": int(case.t.size),
        },
        "thresholds": dict(case.thresholds),
        "event": None if case.event is None else dict(case.event),
        "facts": dict(case.facts),
        "units": case.spec.units,
        "conventions": CONVENTIONS,
        **case.spec.describe(case),
    }


#: the units of each kind of case, ``kind -> {column or input: units}`` (every group's)
UNITS: dict[str, dict[str, str]] = {}
for _g in GROUP_TABLE.values():
    UNITS.setdefault(_g.kind, {}).update(_g.units)
del _g

CONVENTIONS = (
    "quaternions scalar first (w, x, y, z), Hamilton product, attitude body -> space "
    "(v_space = R v_body); angular velocity in body axes; inertia about the centre of "
    "mass in body axes; com from the fixed point in body axes; gravity in space axes; "
    "a pose's position and velocity those of the centre of mass in space axes; "
    "SI units, radians (docs/conventions.md, docs/verify.md)"
)
