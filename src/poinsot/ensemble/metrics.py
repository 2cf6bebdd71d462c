"""Metrics: what an ensemble records per sample, from its integrated motion.

Each metric reads the batch of motions of one chunk, a :class:`poinsot.Trajectory`
with time first and the samples after it (``t`` (n,), attitude ``rotation`` (n, M)
body -> space, body angular velocity ``omega`` (n, M, 3) in rad/s, the kinetic
energy ``energy`` (n, M) and, for a torque with a potential, ``V`` in its ``info``
(``"potential_energy"`` or ``"gravity_moment"``, docs/theory.md §8, §10)), and
returns one value per sample (``NaN`` where the event never happens within the run,
documented per metric).

=========================  ===================================================
``first_flip_time``        first time (s) the body component ``component``
                           (default ``omega_y``: the middle axis of the tennis
                           racket) of omega changes sign; NaN if it never does
``first_time``             first time (s) ``component`` is ``below`` (or
                           ``above``) a threshold (e.g. detumbling:
                           ``omega_norm`` below 0.01 rad/s); NaN if never
``nutation_min``,          extreme angle (deg) between the body axis ``axis``
``nutation_max``           (default ``z``) and the space vertical ``e_z``
``max``, ``min``           extreme of ``component`` over the run
``final_attitude_error``   angle (deg) between the final attitude and the
                           final attitude of the nominal (undispersed) sample
``energy_drift``           ``max |E(t) - E(0)| / |E(0)|`` with ``E = T + V``
                           (kinetic plus the torque model's potential, if it
                           has one): the integration's accuracy
``pointing_error``         angle (deg) of the body attitude relative to the
                           LVLH attitude along the orbit,
                           ``|log(R_io(t)^T R_ib(t))|``
                           (:meth:`poinsot.dynamics.Spacecraft.pointing_error`),
                           reduced over time by ``statistic``: ``"max"``
                           (default), ``"final"`` or ``"rms"``; torque model
                           ``"gravity-gradient"`` only (theory §10.2)
=========================  ===================================================

Components: ``omega_x``, ``omega_y``, ``omega_z`` (rad/s, body axes),
``omega_norm`` (rad/s), ``nutation`` (deg), ``kinetic_energy`` (J),
``pointing_error`` (deg; torque model ``"gravity-gradient"`` only).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._drift import relative_change
from .._quat import attitude_distance
from ..dynamics.spacecraft import Spacecraft
from ..errors import InvalidInputError, InvalidTypeError
from ..rotations._scalar import vertical
from ..trajectory import Trajectory

__all__ = ["Metric", "METRICS", "COMPONENTS", "STATISTICS", "Motion", "from_table"]

COMPONENTS = (
    "omega_x",
    "omega_y",
    "omega_z",
    "omega_norm",
    "nutation",
    "kinetic_energy",
    "pointing_error",
)
METRICS = (
    "first_flip_time",
    "first_time",
    "nutation_min",
    "nutation_max",
    "max",
    "min",
    "final_attitude_error",
    "energy_drift",
    "pointing_error",
)
#: Reductions over time of the ``pointing_error`` metric.
STATISTICS = ("max", "final", "rms")
#: Metric kinds and components that read the orbit frame (torque model "gravity-gradient").
ORBIT_METRICS = ("pointing_error",)
_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Motion:
    """Deprecated: the integrated motion of one chunk (time first, then samples).

    :meth:`Metric.evaluate` reads a :class:`poinsot.Trajectory` (and the nominal
    final quaternion) instead; a Motion is still read, with a DeprecationWarning.
    """

    t: np.ndarray  # (n,)
    quat: np.ndarray  # (n, M, 4)
    omega: np.ndarray  # (n, M, 3)
    kinetic: np.ndarray  # (n, M)
    energy: np.ndarray  # (n, M): T + V
    nominal_final: np.ndarray  # (4,): final quaternion of the nominal sample


@dataclass(frozen=True)
class _Series:
    """What the metrics read of a chunk's motion (from a Trajectory or a Motion)."""

    t: np.ndarray
    quat: np.ndarray
    omega: np.ndarray
    kinetic: np.ndarray
    total: Any  # () -> T + V (n, M), computed only when a metric asks
    nominal_final: np.ndarray | None
    pointing: Any = None  # () -> pointing error (rad, (n, M)), or None: no orbit frame


def _series(
    motion: Trajectory | Motion, nominal_final: Any, spacecraft: Spacecraft | None = None
) -> _Series:
    if isinstance(motion, Motion):
        warnings.warn(
            "poinsot.ensemble.metrics.Motion is deprecated: pass a poinsot.Trajectory "
            "(time first, then samples) and nominal_final to Metric.evaluate.",
            DeprecationWarning,
            stacklevel=3,
        )
        e = motion.energy
        return _Series(motion.t, motion.quat, motion.omega, motion.kinetic, lambda: e,
                       motion.nominal_final)  # fmt: skip
    if not isinstance(motion, Trajectory) or motion.energy is None:
        raise InvalidTypeError(
            "Expected a poinsot.Trajectory with its kinetic energy (time first, then samples), "
            f"got {type(motion).__name__}."
        )
    pointing = None if spacecraft is None else lambda: spacecraft.pointing_error(motion)
    return _Series(motion.t, motion.quat, np.asarray(motion.omega), motion.energy,
                   lambda: total_energy(motion), nominal_final, pointing)  # fmt: skip


def total_energy(tr: Trajectory) -> np.ndarray:
    """``T + V`` along ``tr`` (J): its kinetic energy plus the potential of its
    ``info`` (docs/theory.md §8, §10); ``T`` alone for a torque without a potential."""
    v = tr._potential_energy()
    assert tr.energy is not None
    return tr.energy if v is None else tr.energy + v


def _nutation(quat: np.ndarray, axis: int = 2) -> np.ndarray:
    """Angle (deg) between body axis ``axis`` (R e_axis) and space ``e_z``."""
    # z-component of the column ``axis`` of R: the third row of R (theory §2)
    cz = vertical(*np.moveaxis(quat, -1, 0))[axis]
    return np.degrees(np.arccos(np.clip(cz, -1.0, 1.0)))


def _component(motion: _Series, name: str | None) -> np.ndarray:
    if name is None:  # __post_init__ requires a component for the kinds that read one
        raise InvalidInputError(f"Expected a component, one of {', '.join(COMPONENTS)}.")
    if name.startswith("omega_") and name[-1] in _AXES and len(name) == 7:
        return motion.omega[..., _AXES[name[-1]]]
    if name == "omega_norm":
        return np.linalg.norm(motion.omega, axis=-1)
    if name == "nutation":
        return _nutation(motion.quat)
    if name == "kinetic_energy":
        return motion.kinetic
    if name == "pointing_error":
        return np.degrees(_pointing(motion))
    raise InvalidInputError(f"Unknown component {name!r}; expected one of {', '.join(COMPONENTS)}.")


def _pointing(motion: _Series) -> np.ndarray:
    """The pointing error (rad, (n, M)) of the chunk against its orbit frame."""
    if motion.pointing is None:
        raise InvalidInputError(
            "The pointing error needs the orbit frame: `spacecraft` (torque model "
            "'gravity-gradient')."
        )
    return np.asarray(motion.pointing())


def _first(t: np.ndarray, hit: np.ndarray) -> np.ndarray:
    """First time where ``hit`` (n, M) holds, NaN where it never does."""
    any_hit = hit.any(axis=0)
    idx = np.argmax(hit, axis=0)
    return np.where(any_hit, t[idx], np.nan)


@dataclass(frozen=True)
class Metric:
    """One recorded quantity: ``kind`` from :data:`METRICS` with its options.

    Examples
    --------
    >>> Metric("flip", "first_flip_time").unit
    's'
    """

    name: str
    kind: str
    component: str | None = None
    axis: str = "z"
    below: float | None = None
    above: float | None = None
    statistic: str = "max"

    def __post_init__(self) -> None:
        if self.kind not in METRICS:
            raise InvalidInputError(
                f"Unknown metric kind {self.kind!r} for metric {self.name!r}; expected one of "
                + ", ".join(METRICS)
                + "."
            )
        if self.component is not None and self.component not in COMPONENTS:
            raise InvalidInputError(
                f"Unknown component {self.component!r} for metric {self.name!r}; expected one "
                f"of {', '.join(COMPONENTS)}."
            )
        if self.kind in ("max", "min", "first_time") and self.component is None:
            raise InvalidInputError(f"Metric {self.name!r} ({self.kind}) needs a `component`.")
        if self.kind == "first_time" and (self.below is None) == (self.above is None):
            raise InvalidInputError(
                f"Metric {self.name!r} (first_time) needs exactly one of `below` or `above`."
            )
        if self.axis not in _AXES:
            raise InvalidInputError(f"Expected `axis` of metric {self.name!r} in x, y, z.")
        if self.statistic not in STATISTICS:
            raise InvalidInputError(
                f"Unknown `statistic` {self.statistic!r} of metric {self.name!r}; expected "
                f"one of {', '.join(STATISTICS)}."
            )
        if self.statistic != "max" and self.kind != "pointing_error":
            raise InvalidInputError(
                f"Metric {self.name!r} ({self.kind}) takes no `statistic` (pointing_error does)."
            )

    @property
    def orbital(self) -> bool:
        """Whether the metric reads the orbit frame (torque model ``"gravity-gradient"``)."""
        return self.kind in ORBIT_METRICS or self.component in ORBIT_METRICS

    @property
    def unit(self) -> str:
        if self.kind in ("first_flip_time", "first_time"):
            return "s"
        if self.kind in ("nutation_min", "nutation_max", "final_attitude_error", "pointing_error"):
            return "deg"
        if self.kind == "energy_drift":
            return "1"
        return {"nutation": "deg", "pointing_error": "deg", "kinetic_energy": "J"}.get(
            self.component or "", "rad/s"
        )

    def evaluate(
        self,
        motion: Trajectory | Motion,
        nominal_final: np.ndarray | None = None,
        spacecraft: Spacecraft | None = None,
    ) -> np.ndarray:
        """One value per sample, shape (M,).

        Parameters
        ----------
        motion : Trajectory
            The chunk's motion, time first, then the M samples, with its kinetic
            energy (and ``V`` in ``info`` for a conservative torque).
        nominal_final : ndarray, shape (4,), optional
            The final quaternion of the nominal (undispersed) sample; needed by
            ``final_attitude_error``.
        spacecraft : Spacecraft, optional
            The orbit and its LVLH frame the ``pointing_error`` is measured against
            (:meth:`~poinsot.dynamics.Spacecraft.pointing_error`, docs/theory.md §10.2).

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import KeplerOrbit, Spacecraft
        >>> sat = Spacecraft([80.0, 100.0, 40.0], KeplerOrbit(7.0e6, 0.0, 0.9, 0.0, 0.0, 0.0))
        >>> q0 = sat.orbit_attitude(0.0)                      # LVLH-aligned, at rest in it
        >>> tr = sat.simulate(q0, sat.orbit_rate(q0, 0.0), np.linspace(0.0, 600.0, 4))
        >>> err = Metric("err", "pointing_error", statistic="rms").evaluate(tr, spacecraft=sat)
        >>> bool(err < 1e-6)                                  # an equilibrium (theory §10.2)
        True
        """
        if isinstance(motion, Trajectory) and np.ndim(motion.quat) == 2:  # one body
            motion = _batched(motion)
        m = _series(motion, nominal_final, spacecraft)
        k = self.kind
        if k == "first_flip_time":
            c = _component(m, self.component or "omega_y")
            return _first(m.t, np.sign(c) * np.sign(c[:1]) < 0)
        if k == "first_time":
            c = _component(m, self.component)
            return _first(m.t, c < self.below if self.below is not None else c > self.above)
        if k in ("nutation_min", "nutation_max"):
            nut = _nutation(m.quat, _AXES[self.axis])
            return nut.min(axis=0) if k == "nutation_min" else nut.max(axis=0)
        if k in ("max", "min"):
            c = _component(m, self.component)
            return c.max(axis=0) if k == "max" else c.min(axis=0)
        if k == "final_attitude_error":
            # the angle of the relative rotation (one definition: poinsot._quat)
            if m.nominal_final is None:
                raise InvalidInputError(
                    f"Metric {self.name!r} (final_attitude_error) needs `nominal_final`."
                )
            return np.degrees(attitude_distance(m.nominal_final, m.quat[-1]))
        if k == "pointing_error":
            # the angle relative to the orbit frame (one definition: Spacecraft.pointing_error)
            err = np.degrees(_pointing(m))
            if self.statistic == "final":
                return err[-1]
            if self.statistic == "rms":
                return np.sqrt(np.mean(err**2, axis=0))
            return err.max(axis=0)
        # relative drift of T + V (one definition: poinsot._drift)
        change = relative_change(m.total(), floor=np.finfo(float).tiny)
        return np.max(np.abs(change), axis=0)


def _batched(tr: Trajectory) -> Trajectory:
    """A one-body trajectory as a batch of one (time first, then one sample)."""
    energy = None if tr.energy is None else np.asarray(tr.energy)[:, None]
    return Trajectory(tr.t, tr.rotation.reshape(-1, 1), np.asarray(tr.omega)[:, None],
                      tr.method, energy=energy)  # fmt: skip


def from_table(table: dict[str, Any], index: int) -> Metric:
    """A :class:`Metric` from one ``[[metric]]`` TOML table."""
    if not isinstance(table, dict):
        raise InvalidInputError(f"Expected `metric[{index}]` to be a table.")
    known = {"name", "kind", "component", "axis", "below", "above", "statistic"}
    extra = sorted(set(table) - known)
    if extra:
        raise InvalidInputError(
            f"Unknown key(s) {', '.join(extra)} in `metric[{index}]`; accepted: "
            + ", ".join(sorted(known))
            + "."
        )
    if "kind" not in table:
        raise InvalidInputError(f"`metric[{index}]` needs a `kind` (one of {', '.join(METRICS)}).")
    return Metric(
        name=str(table.get("name", table["kind"])),
        **{
            k: table[k]
            for k in ("kind", "component", "axis", "below", "above", "statistic")
            if k in table
        },
    )
