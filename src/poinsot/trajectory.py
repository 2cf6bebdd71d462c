"""The results of every time-stepping computation: one family of frozen result types.

Each kind of motion returns its own kind of result (never a dummy attitude):

- :class:`Trajectory` for a rigid body's rotation (attitude propagation,
  :func:`poinsot.kinematics.propagate`, theory §5; rigid-body simulation and the
  exact solutions, :func:`poinsot.dynamics.simulate`, theory §10);
- :class:`PointTrajectory` for a point's motion (particles in moving frames,
  central orbits, theory §7, §9);
- :class:`CoordinateTrajectory` for a system in generalized coordinates
  (Lagrange's equations, theory §11).

They share one small protocol, :class:`Result`: ``t`` (s), ``method``, ``info``
(read-only, keys of :data:`INFO_KEYS`), :meth:`~Result.channels` (named series with
units), :meth:`~Result.state_channels` (the quantities that make up the state),
:meth:`~Result.to_pandas`, pickling and a one-line ``repr``. :func:`compare` measures
how far two results of the same kind differ, on their own state and in its units.

Conventions: ``rotation[k]`` maps body components to space components at time
``t[k]`` (``v_space = R v_body``, theory §2); ``omega`` is the angular velocity in
**body** axes (rad/s); ``momentum`` is the angular momentum in **space** axes;
a point's vectors are in the axes of the frame its ``frame_name`` names; SI units;
angles in radians.

The keys of ``info`` are listed once, in :data:`INFO_KEYS` (and in
``docs/conventions.md``); every method uses these names and only these.
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from . import _display
from ._drift import relative_drift
from ._quat import attitude_distance, gravity_potential
from ._typing import FloatArray
from ._validate import as_float_array
from .errors import InvalidInputError, InvalidTypeError
from .rotations.rotation import Rotation

__all__ = [
    "Result",
    "Channel",
    "Trajectory",
    "PoseTrajectory",
    "PointTrajectory",
    "CoordinateTrajectory",
    "Comparison",
    "Difference",
    "compare",
    "quantity_label",
    "INFO_KEYS",
]

#: The documented keys of ``info`` of every result (a method sets those that apply to it).
INFO_KEYS = {
    "steps": "number of steps taken per body (int; fixed-step methods)",
    "step_size": "longest step taken (s)",
    "min_step_size": "shortest step taken (s)",
    "order": "order of accuracy of the method (int)",
    "stages_per_step": "stages of a composed step (int; 1, 3 or 7)",
    "rtol": "relative tolerance (adaptive methods)",
    "atol": "absolute tolerance (adaptive methods)",
    "solver": "scipy.integrate.solve_ivp method (adaptive methods)",
    "evaluations": "right-hand-side evaluations (adaptive methods, int)",
    "rejected": "steps rejected by the error control (adaptive methods, int)",
    "status": "solve_ivp status (adaptive propagation, int)",
    "message": "solver message (adaptive methods)",
    "impacts": "the impacts of a run, in order (poinsot.dynamics.ImpactResult; theory §11.3)",
    "stopped": "why a run ended before its last output time (str; empty: it did not)",
    "events": "the events found (poinsot.dynamics.EventLog: times, states, stops; theory §11.1)",
    "torque_calls": "calls of a torque model evaluated in Python (int)",
    "max_newton_iterations": "most Newton iterations of one implicit step (int)",
    "regime": "motion regime of an exact solution (e.g. 'symmetric', 'rotating')",
    "frame": "axes of a prescribed angular velocity ('body' or 'space')",
    "omega_input": "kind of prescribed angular velocity ('constant', 'callable', 'samples')",
    "interpolation": "interpolation of sampled angular velocities",
    "chunks": "number of pieces a long run was split into (int)",
    "closed_form": "name of the closed-form solution used (e.g. 'coning', 'jacobi')",
    "motion_type": "kind of motion of a closed form (e.g. a Lagrange top's nutation type)",
    "path": "which implementation ran (e.g. compiled kernel or solve_ivp fallback)",
    "failed": "why each body of a batch failed ('' if it did not; failures='mark' only)",
    "orthonormality_drift": "largest entry of abs(C^T C - E), matrix integration (propagate)",
    "torque": "the torque acting ('none' for a free body, else the torque model's class name)",
    "conserved": "names of the quantities the motion conserves (docs/theory.md §8, §10): "
    "'energy' (T), 'momentum' (K), 'total_energy' (T + V), 'momentum_z' (K_z); "
    "empty when a torque does work",
    "total_energy": "T + V at each sample (J), exact heavy-top solutions",
    "potential_energy": "potential energy V of a conservative torque at each sample (J), "
    "the shape of `energy`",
    "gravity_moment": "m g c (N m, body axes) of gravity about the fixed point: "
    "V = gamma . m g c with gamma = R^T e_z (theory §10)",
}

#: ``info`` keys holding one value per sample (arrays of the shape of ``energy``).
PER_SAMPLE_INFO = ("potential_energy", "total_energy")

#: Display names of the conserved quantities of ``info["conserved"]``.
CONSERVED_LABELS = {
    "energy": "energy T",
    "momentum": "|K|",
    "total_energy": "energy T + V",
    "momentum_z": "K_z",
}

_XYZ = ("x", "y", "z")


@dataclass(frozen=True)
class Channel:
    """One named series of a result, with its units.

    Attributes
    ----------
    name : str
        Key of the series (``"omega"``, ``"position"``, ``"theta1"``...).
    values : ndarray, shape (n, ...)
        Samples, first axis the result's times ``t``.
    units : str
        SI units of ``values`` (``"1"`` for a pure number).
    components : tuple of str
        Labels of the last axis (``("x", "y", "z")``), empty for a scalar series.
    description : str
        What it is, in words.

    Examples
    --------
    >>> import numpy as np
    >>> c = Channel("omega", np.zeros((2, 3)), "rad/s", ("x", "y", "z"), "angular velocity")
    >>> c.units, c.components
    ('rad/s', ('x', 'y', 'z'))
    """

    name: str
    values: FloatArray
    units: str
    components: tuple[str, ...] = ()
    description: str = ""


#: ``names``: the fields whose arrays the producer hands over (see ``Trajectory._own``).
_HANDED = threading.local()


def _readonly(a: object, name: str) -> FloatArray:
    if name in getattr(_HANDED, "names", ()) and type(a) is np.ndarray and a.dtype == np.float64:
        a.setflags(write=False)  # the producer's own array: frozen, not copied
        return a
    arr = np.array(as_float_array(a, name, finite=False), dtype=float)
    arr.setflags(write=False)
    return arr


def _rebuild(cls: type, kwargs: dict[str, Any]) -> Any:
    return cls(**kwargs)


class Result:
    """The protocol every poinsot result follows (a mixin of the frozen dataclasses
    :class:`Trajectory`, :class:`PointTrajectory`, :class:`CoordinateTrajectory`).

    Each result has ``t`` (s), ``method`` (the name of the method that produced it)
    and ``info`` (read-only mapping with the keys of :data:`INFO_KEYS`); it lists its
    series with their units (:meth:`channels`), names those that make up the state
    (:meth:`state_channels`, compared by :func:`compare`), converts to a pandas
    DataFrame (:meth:`to_pandas`), pickles (results cross process boundaries in
    ``multiprocessing`` and Dask) and has a one-line ``repr``.

    Examples
    --------
    >>> import numpy as np, pickle, poinsot
    >>> tr = poinsot.dynamics.simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 1.0, 0.0],
    ...                                np.linspace(0.0, 1.0, 11))
    >>> isinstance(tr, Result), list(tr.state_channels())
    (True, ['attitude', 'omega'])
    >>> {name: c.units for name, c in tr.channels().items()}
    {'quat': '1', 'omega': 'rad/s', 'energy': 'J', 'momentum': 'kg m^2/s'}
    >>> compare(pickle.loads(pickle.dumps(tr)), tr).worst.max
    0.0
    """

    t: FloatArray
    method: str
    info: Mapping[str, Any]

    #: names of the channels that make up the state (compared by :func:`compare`)
    _state: tuple[str, ...] = ()

    def channels(self) -> dict[str, Channel]:
        """Every series of the result, ``name -> Channel`` (values with units)."""
        raise NotImplementedError

    def state_channels(self) -> dict[str, Channel]:
        """The channels that make up the state (what :func:`compare` compares)."""
        ch = self.channels()
        return {name: ch[name] for name in self._state_names() if name in ch}

    def _state_names(self) -> tuple[str, ...]:
        return self._state

    def to_pandas(self) -> Any:
        """The channels as a :class:`pandas.DataFrame` indexed by ``t`` (s).

        One column per component (``omega_x``; for a batch ``omega_x[2]``, the
        batch index in brackets); ``df.attrs["units"]`` maps each column to its units.
        Needs pandas (not a dependency of poinsot).
        """
        try:
            import pandas as pd
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError(
                "to_pandas() needs pandas, which poinsot does not install: pip install pandas"
            ) from exc
        columns: dict[str, FloatArray] = {}
        units: dict[str, str] = {}
        n = self.t.size
        for ch in self.channels().values():
            v = np.asarray(ch.values, dtype=float)
            comps = ch.components
            inner = v.shape[1:-1] if comps else v.shape[1:]
            flat = v.reshape(n, -1, len(comps)) if comps else v.reshape(n, -1)
            for b, idx in enumerate(np.ndindex(*inner)):
                tag = "" if not inner else "[" + ",".join(str(i) for i in idx) + "]"
                for c, comp in enumerate(comps or ("",)):
                    col = f"{ch.name}_{comp}{tag}" if comp else f"{ch.name}{tag}"
                    columns[col] = flat[:, b, c] if comps else flat[:, b]
                    units[col] = ch.units
        df = pd.DataFrame(columns, index=pd.Index(np.asarray(self.t), name="t"))
        df.attrs["units"] = units
        return df

    def __reduce__(self) -> tuple[Any, ...]:
        # MappingProxyType does not pickle: rebuild from plain values
        kwargs = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}  # type: ignore[arg-type]
        kwargs["info"] = dict(self.info)
        return (_rebuild, (type(self), self._picklable(kwargs)))

    def _picklable(self, kwargs: dict[str, Any]) -> dict[str, Any]:
        return kwargs

    def _span(self) -> str:
        n = self.t.size
        if n == 0:
            return "0 samples"
        return f"{n} samples, t = {float(self.t[0]):.4g}..{float(self.t[-1]):.4g} s"

    def _batch(self) -> str:
        return ""

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._span()}{self._batch()}, method={self.method!r})"

    def show(self, **options: Any) -> Any:
        """Draw this result with the report's viewer inside a notebook cell.

        Shorthand for :func:`poinsot.plotting.show` (``options`` are passed on);
        returns its :class:`~poinsot.plotting.notebook.Viewer`.
        """
        from .plotting.notebook import show

        return show(self, **options)

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: duration, samples, method, the accuracy achieved and a small chart of
        the first state quantity (the first body of a batch)."""
        d = _display
        t = np.asarray(self.t)
        rows = [("samples", d.esc(f"{t.size}" + self._batch()))]
        if t.size:
            rows.append(("duration", d.value(float(t[-1] - t[0]), "s")))
        rows.append(("method", d.esc(self.method)))
        for key, units in (("steps", ""), ("step_size", "s"), ("rtol", ""), ("atol", ""),
                           ("evaluations", ""), ("order", "")):  # fmt: skip
            if key in self.info:
                v = np.asarray(self.info[key])
                rows.append((key.replace("_", " "), d.value(v if v.size < 4 else v.max(), units)))
        for label, drift in self._drift_rows():
            rows.append((label, d.value(drift, "", 3)))
        chart, label = "", ""
        for ch in self.state_channels().values():
            if ch.name == "attitude":
                continue
            v = np.asarray(ch.values, dtype=float)
            comps = ch.components or (ch.name,)
            v = v.reshape(t.size, -1, len(comps))[:, 0, :] if v.size else v
            chart = d.sparkline(t, {c: v[:, k] for k, c in enumerate(comps)}, ch.units)
            label = f"{ch.name} ({ch.units})"
            break
        extra = (
            f"<div style='font-size:11px;color:#666'>{d.esc(label)}</div>{chart}" if chart else ""
        )
        note = "SI units; docs/conventions.md"
        if any(lab.endswith("drift (relative)") for lab, _ in rows):
            note += "; conserved quantities: docs/theory.md §8, §10"
        return d.table(type(self).__name__, rows, note, extra)

    def _drift_rows(self) -> list[tuple[str, float]]:
        """``(label, relative drift)`` of the quantities this result conserves."""
        return []

    def _freeze_info(self) -> None:
        if not isinstance(self.method, str):
            raise InvalidTypeError(f"Expected `method` to be a string, got {self.method!r}.")
        object.__setattr__(self, "info", MappingProxyType(dict(self.info)))


@dataclass(frozen=True, eq=False, repr=False)
class Trajectory(Result):
    """Samples of a rigid body's rotational motion.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times (s).
    rotation : Rotation, shape (n,) or (n, N)
        Attitude (body -> space) at each time, for one body or a batch of N.
    omega : ndarray, shape (n, 3) or (n, N, 3)
        Angular velocity in body axes (rad/s).
    method : str
        Name of the method that produced the samples.
    energy : ndarray, shape (n,) or (n, N), optional
        Rotational kinetic energy ``T = w^T J w / 2`` (J, theory §8), for every
        method, torque-free or not: never ``T + V`` (an exact heavy top's
        ``T + V`` is ``info["total_energy"]``, ``V`` is ``info["potential_energy"]``).
        For a :class:`PoseTrajectory` it also holds the translation (see there).
        What ``energy`` means per result type: docs/conventions.md, "energy".
    momentum : ndarray, shape (n, 3) or (n, N, 3), optional
        Angular momentum ``K = R J w`` in space axes (kg m^2/s, theory §8, §10).
    info : mapping
        Read-only details of the method, with the keys of :data:`INFO_KEYS`
        (each method sets those that apply).
    position : ndarray, shape (n, 3) or (n, N, 3), optional
        Translational part: position of the body's reference point in space axes (m).
    velocity : ndarray, shape (n, 3) or (n, N, 3), optional
        Its velocity in space axes (m/s).

    Notes
    -----
    Frozen and picklable (ensembles send trajectories between processes); the
    arrays are read-only. The state compared by :func:`compare` is the attitude
    (``"attitude"``, rad) and ``"omega"`` (rad/s).

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> tr = Trajectory(t, poinsot.Rotation.identity((3,)), np.zeros((3, 3)), "none")
    >>> tr.quat.shape
    (3, 4)
    >>> tr
    Trajectory(3 samples, t = 0..1 s, method='none')
    >>> import pickle
    >>> pickle.loads(pickle.dumps(tr)).omega.shape
    (3, 3)
    >>> sorted(tr.channels())
    ['omega', 'quat']
    """

    t: FloatArray
    rotation: Rotation
    omega: FloatArray
    method: str
    energy: FloatArray | None = None
    momentum: FloatArray | None = None
    info: Mapping[str, Any] = field(default_factory=dict)
    position: FloatArray | None = None
    velocity: FloatArray | None = None

    _state = ("attitude", "omega")

    def __post_init__(self) -> None:
        if not isinstance(self.rotation, Rotation):
            raise InvalidTypeError(
                f"Expected `rotation` to be a poinsot.Rotation, got {type(self.rotation).__name__}."
            )
        self._freeze_info()
        n = self.rotation.shape[:1]
        expected = {
            "t": n,
            "omega": (*self.rotation.shape, 3),
            "energy": self.rotation.shape,
            "momentum": (*self.rotation.shape, 3),
            "position": (*self.rotation.shape, 3),
            "velocity": (*self.rotation.shape, 3),
        }
        for name, shape in expected.items():
            a = getattr(self, name)
            if a is None:
                continue
            arr = _readonly(a, name)
            if arr.shape != shape:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape {shape} to match `rotation` "
                    f"{self.rotation.shape}, got {arr.shape}."
                )
            object.__setattr__(self, name, arr)

    @classmethod
    def _own(cls, names: tuple[str, ...], **fields: Any) -> Trajectory:
        """A Trajectory that takes the arrays of the fields ``names`` as they are (made
        read-only, not copied): for a producer handing over arrays it made and nobody else
        holds. The copies cost 1-2 MB of fresh memory per ``simulate`` call on 10,000
        bodies, and its page faults (poinsot._scratch)."""
        _HANDED.names = names
        try:
            return cls(**fields)
        finally:
            _HANDED.names = ()

    def _batch(self) -> str:
        shape = self.rotation.shape[1:]
        return f", batch {shape}" if shape else ""

    def channels(self) -> dict[str, Channel]:
        """``quat`` (1; w, x, y, z), ``omega`` (rad/s, body axes), and where present
        ``energy`` (J), ``momentum`` (kg m^2/s, space axes), ``position`` (m) and
        ``velocity`` (m/s)."""
        out = {
            "quat": Channel(
                "quat", self.quat, "1", ("w", "x", "y", "z"), "attitude quaternion body -> space"
            ),
            "omega": Channel("omega", self.omega, "rad/s", _XYZ, "angular velocity, body axes"),
        }
        if self.energy is not None:
            out["energy"] = Channel("energy", self.energy, "J", (), "kinetic energy T")
        if self.momentum is not None:
            out["momentum"] = Channel(
                "momentum", self.momentum, "kg m^2/s", _XYZ, "angular momentum K, space axes"
            )
        if self.position is not None:
            out["position"] = Channel("position", self.position, "m", _XYZ, "position, space axes")
        if self.velocity is not None:
            out["velocity"] = Channel(
                "velocity", self.velocity, "m/s", _XYZ, "velocity, space axes"
            )
        return out

    def state_channels(self) -> dict[str, Channel]:
        """``attitude`` (the quaternion channel, compared as an angle in rad) and
        ``omega`` (rad/s)."""
        ch = self.channels()
        att = dataclasses.replace(ch["quat"], name="attitude")
        return {"attitude": att, "omega": ch["omega"]}

    @property
    def quat(self) -> FloatArray:
        """Scalar-first unit quaternions, shape ``rotation.shape + (4,)``."""
        return self.rotation.as_quat()

    @property
    def omega_space(self) -> FloatArray:
        """Angular velocity in space axes, ``w_x = R w_xi`` (rad/s)."""
        return self.rotation.apply(self.omega)

    @property
    def momentum_norm(self) -> FloatArray | None:
        """``|K|`` at each sample."""
        return None if self.momentum is None else np.linalg.norm(self.momentum, axis=-1)

    @property
    def energy_drift(self) -> float | None:
        """``max_k |T_k - T_0| / |T_0|`` (relative drift of the kinetic energy).

        Absolute (``max_k |T_k - T_0|``) where ``T_0 = 0``, e.g. a body at rest.
        """
        return None if self.energy is None else relative_drift(self.energy)

    @property
    def momentum_drift(self) -> float | None:
        """``max_k ||K_k| - |K_0|| / |K_0|`` (relative drift of ``|K|``; absolute at 0)."""
        k = self.momentum_norm
        return None if k is None else relative_drift(k)

    def conserved_drifts(self) -> dict[str, float]:
        """Relative drift of each quantity the motion conserves, ``name -> drift``.

        The names are those of ``info["conserved"]`` (docs/theory.md §8, §10):
        ``"energy"`` (:attr:`energy_drift`) and ``"momentum"``
        (:attr:`momentum_drift`, ``|K|``) for a free body; ``"total_energy"``,
        ``max_k |E_k - E_0| / max(|E_0|, max_k T_k)`` with ``E = T + V``
        (``V`` from ``info["potential_energy"]`` or ``info["gravity_moment"]``), and
        ``"momentum_z"``, ``max_k |K_z,k - K_z,0| / |K_0|``, for a body with a fixed point in
        gravity. Empty when the result does not say what its motion conserves
        (``info`` without ``"conserved"``) or a torque does work: the kinetic
        energy and ``|K|`` are then no invariants, and their changes no error.

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import HeavyRigidBody
        >>> top = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.4], g=10.0)
        >>> tr = top.simulate([0.99, 0.1, 0.0, 0.0], [0.5, 0.0, 20.0], np.linspace(0, 1, 11),
        ...                   max_step=1e-3)
        >>> sorted(tr.conserved_drifts())
        ['momentum_z', 'total_energy']
        """
        out: dict[str, float] = {}
        for name in self.info.get("conserved", ()):
            value: float | None = None
            if name == "energy":
                value = self.energy_drift
            elif name == "momentum":
                value = self.momentum_drift
            elif name == "total_energy" and self.energy is not None:
                v = self._potential_energy()
                if v is not None:
                    scale = np.max(np.abs(self.energy), axis=0)
                    total = self.energy + np.asarray(v, dtype=float)
                    value = relative_drift(total, floor=scale)
            elif name == "momentum_z" and self.momentum is not None:
                k0 = np.linalg.norm(self.momentum[0], axis=-1)
                value = relative_drift(self.momentum[..., 2], k0)
            if value is not None:
                out[name] = value
        return out

    def _potential_energy(self) -> FloatArray | None:
        """``V`` at each sample (J): ``info["potential_energy"]``, or from
        ``info["gravity_moment"]`` as ``gamma . m g c`` (the formula of
        :class:`~poinsot.dynamics.GravityTorque`, :func:`poinsot._quat.gravity_potential`)."""
        v = self.info.get("potential_energy")
        if v is not None:
            return np.asarray(v, dtype=float)
        mgc = self.info.get("gravity_moment")
        if mgc is None:
            return None
        return gravity_potential(np.asarray(self.rotation.as_quat()), np.asarray(mgc, dtype=float))

    def _drift_rows(self) -> list[tuple[str, float]]:
        return [
            (f"{CONSERVED_LABELS[k]} drift (relative)", v)
            for k, v in self.conserved_drifts().items()
        ]

    @property
    def momentum_vector_drift(self) -> float | None:
        """``max_k |K_k - K_0| / |K_0|``: for a free body the space vector is constant."""
        return None if self.momentum is None else relative_drift(self.momentum, vector=True)


@dataclass(frozen=True, eq=False, repr=False)
class PoseTrajectory(Trajectory):
    """Samples of a free rigid body's six-degree-of-freedom motion: a
    :class:`Trajectory` whose ``position`` and ``velocity`` (of the centre of mass,
    space axes, m and m/s) are part of the state.

    The state compared by :func:`compare` is ``"position"`` (m), ``"velocity"``
    (m/s), ``"attitude"`` (rad) and ``"omega"`` (rad/s). Returned by
    :func:`poinsot.dynamics.simulate_free_motion`.

    ``energy`` is the whole kinetic energy ``T = m |v|^2 / 2 + w^T J w / 2``
    (J: translation of the centre of mass plus rotation about it), never ``T + V``
    (docs/conventions.md, "energy").

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> p = PoseTrajectory(t, poinsot.Rotation.identity((3,)), np.zeros((3, 3)), "x",
    ...                    position=np.zeros((3, 3)), velocity=np.zeros((3, 3)))
    >>> list(p.state_channels())
    ['position', 'velocity', 'attitude', 'omega']
    """

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.position is None or self.velocity is None:
            raise InvalidInputError(
                "Expected `position` and `velocity` for a PoseTrajectory (the state of a "
                "six-degree-of-freedom motion)."
            )

    def state_channels(self) -> dict[str, Channel]:
        """``position`` (m), ``velocity`` (m/s), ``attitude`` (rad) and ``omega`` (rad/s)."""
        ch = self.channels()
        rot = super().state_channels()
        return {"position": ch["position"], "velocity": ch["velocity"], **rot}


@dataclass(frozen=True, eq=False, repr=False)
class PointTrajectory(Result):
    """Samples of a point's motion (a particle, a body's centre of mass on an orbit).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times (s).
    position, velocity : ndarray, shape (n, ..., 3)
        ``r`` (m) and ``v`` (m/s) in the axes of the frame named by ``frame_name``
        (for a moving frame: the motion relative to it).
    method : str
        Name of the method that produced the samples.
    frame_name : str
        The frame whose axes ``position`` and ``velocity`` are in (``"inertial"``,
        ``"frame"`` for a moving frame, ``"earth"`` for east, north, up axes...).
    frame : FrameMotion, callable or None
        The moving frame itself (None: inertial). A frame given as a Python
        callable is not pickled (it may be a lambda): it is ``None`` after a round
        trip, everything else is kept.
    mass : ndarray, shape (...), optional
        Masses (kg).
    acceleration : ndarray, shape (n, ..., 3), optional
        Acceleration (m/s^2) in the same axes.
    energy : ndarray, shape (n, ...), optional
        Mechanical energy ``T + V = m |v|^2 / 2 + V(r)`` (J, inertial frame), given
        where the motion has one potential (``CentralOrbit.trajectory``); None
        otherwise (``simulate_particle``, ``foucault_pendulum``: relative to a
        moving frame the conserved quantity is
        :func:`~poinsot.dynamics.jacobi_integral`). docs/conventions.md, "energy".
    inertial_position, inertial_velocity : ndarray, shape (n, ..., 3), optional
        The same motion seen from the inertial frame (inertial axes, m and m/s).
    frame_rotation : Rotation, shape (n,), optional
        Attitude of the moving frame (frame -> inertial components).
    frame_origin : ndarray, shape (n, 3), optional
        Position of the moving frame's origin in the inertial frame (m).
    info : mapping
        Read-only details of the method (keys of :data:`INFO_KEYS`).

    Notes
    -----
    Frozen, picklable, arrays read-only. The state compared by :func:`compare` is
    ``"position"`` (m) and ``"velocity"`` (m/s).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> r = np.stack([t, 0 * t, 0 * t], axis=-1)
    >>> p = PointTrajectory(t, r, np.ones((5, 3)) * [1, 0, 0], "exact", frame_name="inertial")
    >>> p
    PointTrajectory(5 samples, t = 0..1 s, method='exact')
    >>> p.channels()["velocity"].units
    'm/s'
    """

    t: FloatArray
    position: FloatArray
    velocity: FloatArray
    method: str
    frame_name: str = "inertial"
    frame: Any = None
    mass: FloatArray | None = None
    acceleration: FloatArray | None = None
    energy: FloatArray | None = None
    inertial_position: FloatArray | None = None
    inertial_velocity: FloatArray | None = None
    frame_rotation: Rotation | None = None
    frame_origin: FloatArray | None = None
    info: Mapping[str, Any] = field(default_factory=dict)

    _state = ("position", "velocity")

    def __post_init__(self) -> None:
        self._freeze_info()
        if not isinstance(self.frame_name, str):
            raise InvalidTypeError(
                f"Expected `frame_name` to be a string, got {self.frame_name!r}."
            )
        t = _readonly(self.t, "t")
        object.__setattr__(self, "t", t)
        pos = _readonly(self.position, "position")
        if pos.ndim < 2 or pos.shape[0] != t.size or pos.shape[-1] != 3:
            raise InvalidInputError(
                f"Expected `position` to have shape ({t.size}, ..., 3), got {pos.shape}."
            )
        object.__setattr__(self, "position", pos)
        vec = {"velocity": pos.shape, "acceleration": pos.shape}
        vec["inertial_position"] = vec["inertial_velocity"] = pos.shape
        for name, shape in vec.items():
            a = getattr(self, name)
            if a is None:
                continue
            arr = _readonly(a, name)
            if arr.shape != shape:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape {shape} to match `position`, got {arr.shape}."
                )
            object.__setattr__(self, name, arr)
        for name in ("mass", "energy", "frame_origin"):
            a = getattr(self, name)
            if a is not None:
                object.__setattr__(self, name, _readonly(a, name))
        if self.frame_rotation is not None and not isinstance(self.frame_rotation, Rotation):
            raise InvalidTypeError(
                f"Expected `frame_rotation` to be a poinsot.Rotation, "
                f"got {type(self.frame_rotation).__name__}."
            )

    def _picklable(self, kwargs: dict[str, Any]) -> dict[str, Any]:
        import pickle

        if kwargs["frame"] is not None:
            try:  # a lambda or a local function cannot cross a process boundary
                pickle.dumps(kwargs["frame"])
            except Exception:
                kwargs["frame"] = None
        return kwargs

    def _batch(self) -> str:
        shape = self.position.shape[1:-1]
        return f", batch {shape}" if shape else ""

    def channels(self) -> dict[str, Channel]:
        """``position`` (m), ``velocity`` (m/s) in the ``frame_name`` axes, and where
        present ``acceleration`` (m/s^2), ``energy`` (J), ``inertial_position`` (m)
        and ``inertial_velocity`` (m/s)."""
        where = f"{self.frame_name} axes"
        out = {
            "position": Channel("position", self.position, "m", _XYZ, f"position, {where}"),
            "velocity": Channel("velocity", self.velocity, "m/s", _XYZ, f"velocity, {where}"),
        }
        extra = (
            ("acceleration", "m/s^2", _XYZ, f"acceleration, {where}"),
            ("energy", "J", (), "energy"),
            ("inertial_position", "m", _XYZ, "position, inertial axes"),
            ("inertial_velocity", "m/s", _XYZ, "velocity, inertial axes"),
        )
        for name, units, comps, what in extra:
            v = getattr(self, name)
            if v is not None:
                out[name] = Channel(name, v, units, comps, what)
        return out


def _rate_units(units: str) -> str:
    return f"{units}/s" if units else "1/s"


@dataclass(frozen=True, eq=False, repr=False)
class CoordinateTrajectory(Result):
    """Samples of a motion in generalized coordinates (docs/theory.md §11).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s).
    q, qdot : ndarray, shape (n, ..., k)
        Coordinates and their rates (units of each coordinate, and per second).
    coordinates : tuple of str
        The coordinate names, in the order of the last axis.
    method : str
        Name of the method that produced the samples.
    units : tuple of str
        The SI unit of each coordinate (``"rad"``, ``"m"``; ``""`` when unknown).
    energy : ndarray, shape (n, ...), optional
        Mechanical energy ``T + P + V0`` (J in SI; ``P`` the potential,
        ``V0`` the velocity-free part of the generalized potential), as
        :meth:`~poinsot.symbolic.LagrangeSystem.energy`; the kinetic energy alone is
        ``kinetic``. docs/conventions.md, "energy".
    kinetic : ndarray, shape (n, ...), optional
        Kinetic energy ``T`` (J in SI).
    jacobi : ndarray, shape (n, ...), optional
        Jacobi integral ``q' . dL/dq' - L`` (None if ``L`` depends on time).
    multipliers : ndarray, shape (n, ..., m), optional
        Constraint multipliers (None without kept constraints).
    multiplier_names : tuple of str
        Their names (default ``lambda1``, ``lambda2``...).
    jacobi_conserved : bool
        Whether the Jacobi integral is a first integral of this system.
    info : mapping
        Read-only details of the method (keys of :data:`INFO_KEYS`).

    Notes
    -----
    Frozen, picklable, arrays read-only. The state compared by :func:`compare` is
    each coordinate (``"theta1"``, in its units) and each rate (``"theta1_dot"``).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 1.0, 4)
    >>> c = CoordinateTrajectory(t, np.zeros((4, 2)), np.zeros((4, 2)), ("x", "phi"),
    ...                          "DOP853", units=("m", "rad"))
    >>> c
    CoordinateTrajectory(4 samples, t = 0..1 s, coordinates (x, phi), method='DOP853')
    >>> c.channels()["phi_dot"].units
    'rad/s'
    """

    t: FloatArray
    q: FloatArray
    qdot: FloatArray
    coordinates: tuple[str, ...]
    method: str = ""
    units: tuple[str, ...] = ()
    energy: FloatArray | None = None
    kinetic: FloatArray | None = None
    jacobi: FloatArray | None = None
    multipliers: FloatArray | None = None
    multiplier_names: tuple[str, ...] = ()
    jacobi_conserved: bool = False
    info: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self._freeze_info()
        names = tuple(str(c) for c in self.coordinates)
        object.__setattr__(self, "coordinates", names)
        for name in ("t", "q", "qdot", "energy", "kinetic", "jacobi", "multipliers"):
            a = getattr(self, name)
            if a is not None:
                object.__setattr__(self, name, _readonly(a, name))
        k = len(names)
        for name in ("q", "qdot"):
            a = getattr(self, name)
            if a.ndim < 2 or a.shape[0] != self.t.size or a.shape[-1] != k:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape ({self.t.size}, ..., {k}), got {a.shape}."
                )
        units = tuple(self.units) if self.units else ("",) * k
        if len(units) != k or not all(isinstance(u, str) for u in units):
            raise InvalidInputError(
                f"Expected `units` to be {k} strings (one per coordinate), got {self.units!r}."
            )
        object.__setattr__(self, "units", units)
        m = 0 if self.multipliers is None else self.multipliers.shape[-1]
        lam = tuple(self.multiplier_names) or tuple(f"lambda{i + 1}" for i in range(m))
        if len(lam) != m:
            raise InvalidInputError(
                f"Expected `multiplier_names` to have {m} names, got {self.multiplier_names!r}."
            )
        object.__setattr__(self, "multiplier_names", lam)
        object.__setattr__(self, "jacobi_conserved", bool(self.jacobi_conserved))

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}({self._span()}{self._batch()}, coordinates "
            f"({', '.join(self.coordinates)}), method={self.method!r})"
        )

    def _batch(self) -> str:
        shape = self.q.shape[1:-1]
        return f", batch {shape}" if shape else ""

    def _state_names(self) -> tuple[str, ...]:
        return (*self.coordinates, *(f"{c}_dot" for c in self.coordinates))

    def channels(self) -> dict[str, Channel]:
        """One channel per coordinate (its units) and per rate (``<name>_dot``, its
        units per second), then ``energy``, ``kinetic``, ``jacobi`` (J) and the
        multipliers where present."""
        out: dict[str, Channel] = {}
        for i, (c, u) in enumerate(zip(self.coordinates, self.units, strict=True)):
            out[c] = Channel(c, self.q[..., i], u, (), f"coordinate {c}")
        for i, (c, u) in enumerate(zip(self.coordinates, self.units, strict=True)):
            out[f"{c}_dot"] = Channel(f"{c}_dot", self.qdot[..., i], _rate_units(u), (), f"{c}'")
        for name, what in (
            ("energy", "energy T + P"),
            ("kinetic", "kinetic energy T"),
            ("jacobi", "Jacobi integral h"),
        ):
            v = getattr(self, name)
            if v is not None:
                out[name] = Channel(name, v, "J", (), what)
        if self.multipliers is not None:
            for i, lam in enumerate(self.multiplier_names):
                out[lam] = Channel(lam, self.multipliers[..., i], "", (), "constraint multiplier")
        return out

    def coordinate(self, name: str) -> FloatArray:
        """The samples of one coordinate by name, shape (n, ...)."""
        if name not in self.coordinates:
            raise InvalidInputError(
                f"Expected a coordinate among {list(self.coordinates)}, got {name!r}."
            )
        return self.q[..., self.coordinates.index(name)]

    def _scale(self) -> FloatArray | None:
        """``max_t |T|`` per batch member: the size energies are compared with."""
        return None if self.kinetic is None else np.max(np.abs(self.kinetic), axis=0)

    @property
    def energy_drift(self) -> float | None:
        """``max_t |E - E_0| / max(|E_0|, max_t T)`` over the batch (relative to the
        larger of the initial energy and the largest kinetic energy, so that an
        energy that starts at 0 is judged on the scale of the motion)."""
        return None if self.energy is None else relative_drift(self.energy, floor=self._scale())

    def _drift_rows(self) -> list[tuple[str, float]]:
        # the Jacobi integral only where it is a first integral (autonomous system,
        # gyroscopic forces); T + P is conserved only in a subset of those, where h = T + P
        drift = self.jacobi_drift if self.jacobi_conserved else None
        return [] if drift is None else [("Jacobi integral h drift (relative)", drift)]

    @property
    def jacobi_drift(self) -> float | None:
        """``max_t |h - h_0| / max(|h_0|, max_t T)`` (as :attr:`energy_drift`), or None."""
        return None if self.jacobi is None else relative_drift(self.jacobi, floor=self._scale())


# --------------------------------------------------------------------------- compare
@dataclass(frozen=True)
class Difference:
    """How far one state quantity of two results differs.

    Attributes
    ----------
    name : str
        The quantity (``"attitude"``, ``"omega"``, ``"position"``, ``"theta1"``,
        ``"theta1_dot"``...).
    units : str
        Its units (of ``max``, ``final`` and ``scale``).
    max : float
        Largest difference over the samples (and the batch).
    time_of_max : float
        When it occurs (s).
    final : float
        Largest difference at the last sample.
    scale : float
        The size of the quantity: its largest magnitude along the second result
        (``pi`` rad for an attitude).
    """

    name: str
    units: str
    max: float
    time_of_max: float
    final: float
    scale: float

    @property
    def relative(self) -> float:
        """``max / scale`` (``max`` itself when the scale is 0)."""
        return self.max / self.scale if self.scale > 0 else self.max

    def describe(self) -> str:
        """``"theta1 differs by up to 0.19 rad (at t = 8.3 s)"``."""
        units = f" {self.units}" if self.units and self.units != "1" else ""
        at = f"(at t = {self.time_of_max:.4g} s)"
        return f"{quantity_label(self.name)} differs by up to {self.max:.3g}{units} {at}"


def quantity_label(name: str) -> str:
    """How a state quantity is written in text: a rate ``theta1_dot`` as ``theta1'``
    (channel names, CSV columns and JSON keys keep ``theta1_dot``).

    Examples
    --------
    >>> quantity_label("theta1_dot"), quantity_label("omega")
    ("theta1'", 'omega')
    """
    return name[:-4] + "'" if name.endswith("_dot") else name


@dataclass(frozen=True)
class Comparison:
    """The differences between two results on their own state (:func:`compare`).

    Attributes
    ----------
    differences : tuple of Difference
        One per state quantity, in the order of the result's state channels.
    methods : tuple of str
        The ``method`` of the two results compared.
    """

    differences: tuple[Difference, ...]
    methods: tuple[str, str] = ("", "")

    def __getitem__(self, name: str) -> Difference:
        for d in self.differences:
            if d.name == name:
                return d
        raise KeyError(name)

    def names(self) -> tuple[str, ...]:
        """The names of the compared quantities."""
        return tuple(d.name for d in self.differences)

    @property
    def worst(self) -> Difference:
        """The difference largest relative to its scale."""
        return max(self.differences, key=lambda d: d.relative)

    def exceeding(self, rtol: float = 0.0, atol: float = 0.0) -> tuple[Difference, ...]:
        """The differences with ``max > rtol * scale + atol`` (each in its units)."""
        return tuple(d for d in self.differences if d.max > rtol * d.scale + atol)

    def describe(self) -> list[str]:
        """One line per quantity, e.g. ``"theta1 differs by up to 0.19 rad (at t = 8.3 s)"``."""
        return [d.describe() for d in self.differences]


def _family(r: object) -> type:
    for cls in (PoseTrajectory, Trajectory, PointTrajectory, CoordinateTrajectory):
        if isinstance(r, cls):
            return cls
    raise InvalidTypeError(
        "Expected a poinsot result (Trajectory, PointTrajectory or CoordinateTrajectory), "
        f"got {type(r).__name__}."
    )


def compare(a: Result, b: Result) -> Comparison:
    """Compare two results of the same kind on their own state, in its units.

    ``b`` is the reference. A rigid body (:class:`Trajectory`) is compared on its
    attitude, the angle of ``R_b^-1 R_a`` (rad, theory §4), and on ``|w_a - w_b|``
    (rad/s); a point (:class:`PointTrajectory`) on ``|r_a - r_b|`` (m) and
    ``|v_a - v_b|`` (m/s); a system in generalized coordinates
    (:class:`CoordinateTrajectory`) on each coordinate ``|q_k,a - q_k,b|`` and each
    rate, in their own units. Each :class:`Difference` gives the largest difference
    over the samples (and the batch), when it occurs, the final difference and the
    quantity's scale (its largest magnitude along ``b``).

    Parameters
    ----------
    a, b : Result
        Two results of the same type on the same times (and batch shape).

    Returns
    -------
    Comparison

    Raises
    ------
    InvalidTypeError
        ``a`` and ``b`` are not results of the same kind.
    InvalidInputError
        Different times, batch shapes or coordinates.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 2.0, 3)
    >>> a = CoordinateTrajectory(t, [[0.0], [0.1], [0.2]], [[0.1]] * 3, ("theta",), "a",
    ...                          units=("rad",))
    >>> b = CoordinateTrajectory(t, [[0.0], [0.1], [0.5]], [[0.1]] * 3, ("theta",), "b",
    ...                          units=("rad",))
    >>> c = compare(a, b)
    >>> c.describe()[0]
    'theta differs by up to 0.3 rad (at t = 2 s)'
    >>> [d.name for d in c.exceeding(rtol=0.1)]
    ['theta']
    """
    fa, fb = _family(a), _family(b)
    if fa is not fb:
        raise InvalidTypeError(
            f"Expected two results of the same kind, got {type(a).__name__} and {type(b).__name__}."
        )
    if a.t.shape != b.t.shape or not np.array_equal(a.t, b.t):
        raise InvalidInputError(
            f"Expected the two results on the same times, got {a.t.size} and {b.t.size} samples"
            + (" with different values." if a.t.shape == b.t.shape else ".")
        )
    if isinstance(a, CoordinateTrajectory) and isinstance(b, CoordinateTrajectory):
        if a.coordinates != b.coordinates:
            raise InvalidInputError(
                f"Expected the same coordinates, got {a.coordinates} and {b.coordinates}."
            )
    sa, sb = a.state_channels(), b.state_channels()
    out = []
    for name, ca in sa.items():
        cb = sb[name]
        va, vb = np.asarray(ca.values, dtype=float), np.asarray(cb.values, dtype=float)
        if va.shape != vb.shape:
            raise InvalidInputError(
                f"Expected `{name}` of the same shape in both results, got {va.shape} and "
                f"{vb.shape}."
            )
        if name == "attitude":
            ra, rb = a.rotation, b.rotation  # type: ignore[attr-defined]
            d = attitude_distance(rb.as_quat(), ra.as_quat())
            units, scale = "rad", float(np.pi)
        elif ca.components:
            d = np.linalg.norm(va - vb, axis=-1)
            units, scale = ca.units, float(np.max(np.linalg.norm(vb, axis=-1), initial=0.0))
        else:
            d = np.abs(va - vb)
            units, scale = ca.units, float(np.max(np.abs(vb), initial=0.0))
        per_time = d.reshape(d.shape[0], -1).max(axis=1) if d.size else np.zeros(0)
        k = int(np.argmax(per_time)) if per_time.size else 0
        out.append(
            Difference(
                name,
                units,
                float(per_time[k]) if per_time.size else 0.0,
                float(a.t[k]) if per_time.size else 0.0,
                float(per_time[-1]) if per_time.size else 0.0,
                scale,
            )
        )
    return Comparison(tuple(out), (a.method, b.method))
