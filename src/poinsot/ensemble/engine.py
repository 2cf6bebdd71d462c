"""Monte-Carlo ensembles of rigid-body motions, chunked, on Dask or in-process.

An :class:`EnsembleProblem` is a nominal rigid-body scenario (free, torqued or
heavy body about a fixed point) plus dispersions of its inputs and the metrics
to record. :func:`run` splits the ``samples`` into chunks of ``chunk_size``;
each chunk draws its inputs from its own seed and integrates all its samples
in **one** call of the compiled batch integrator (``simulate(method="dop853")``'s
kernel, every sample with its own step-size control), then evaluates the
metrics. Chunks run on a Dask cluster (a local one by default) and are written
as Parquet files as they arrive.

**Reproducibility.** Chunk ``i`` draws from
``numpy.random.SeedSequence(seed, spawn_key=(i,))`` (the ``i``-th child that
``SeedSequence(seed).spawn`` gives), and every sample of the compiled
integrator is independent of the others: the table is bit-identical whatever
the number of workers, the order in which chunks finish, a retry after a
worker died, or a resumed run.

**Failures.** A sample whose inputs are not physical (an inertia violating the
triangle inequality, a negative mass) or whose integration fails is recorded
with ``failed = True`` and the reason; its metrics are NaN. It never stops the
ensemble.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from .._jit import NUMBA
from .._progress import Progress, as_progress
from .._validate import as_rotation_quat
from ..dynamics import simulate
from ..dynamics.orbit import KeplerOrbit
from ..dynamics.spacecraft import Spacecraft
from ..dynamics.torques import (
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityTorque,
    OrbitGravityGradientTorque,
    TorqueModel,
)
from ..errors import InvalidInputError, InvalidTypeError
from ..mass import parallel_axis
from ..rotations.rotation import Rotation
from ..trajectory import Trajectory
from .dispersion import Dispersion, SmallRotation, UniformRotation
from .metrics import Metric

__all__ = [
    "EnsembleProblem",
    "EnsembleResult",
    "EnsembleError",
    "EnsembleInterrupted",
    "run",
    "run_chunk",
    "QUANTITIES",
    "TORQUE_MODELS",
    "ORBIT_ELEMENTS",
    "orbit_elements",
]

#: Quantities a ``[dispersion]`` table may name, with their units and shapes.
QUANTITIES = {
    "omega0": (
        "rad/s",
        (3,),
        "initial angular velocity, body axes (gravity-gradient: relative to LVLH)",
    ),
    "attitude": (
        "1",
        (4,),
        "initial attitude, a unit quaternion (w, x, y, z) body -> space (gravity-gradient: "
        "body -> LVLH) (dispersed by small_rotation, sigma in deg, or uniform_rotation only)",
    ),
    "inertia": ("kg m^2", (3,), "diagonal of the inertia tensor about the centre of mass"),
    "mass": ("kg", (), "mass"),
    "center_of_mass": ("m", (3,), "centre of mass from the fixed point, body axes"),
    "torque": ("N m", (3,), "constant torque vector ([torque] model body or space)"),
}

#: Torque models of an :class:`EnsembleProblem`.
TORQUE_MODELS = ("none", "body", "space", "gravity", "gravity-gradient")

#: Elements of the Kepler orbit of torque model ``"gravity-gradient"`` (SI units, rad):
#: ``mu`` may be left out (the Earth's), the others are required.
ORBIT_ELEMENTS = ("a", "e", "inclination", "raan", "argp", "anomaly0", "mu")

CHUNK_DIR = "chunks"
MANIFEST = "ensemble.json"


class EnsembleError(InvalidInputError):
    """An ensemble that cannot run as asked (bad options, a scheduler that does not
    answer, an output directory of another scenario)."""


class EnsembleInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`run`: a ``KeyboardInterrupt`` that says what is kept.

    ``kept`` chunks of ``total`` are written in ``out`` (``None``: no directory,
    nothing kept); ``run(..., out=out, resume=True)`` with the same problem, sample
    count, chunk size and seed completes the run.
    """

    def __init__(self, kept: int, total: int, out: Path | None) -> None:
        self.kept, self.total, self.out = kept, total, out
        where = f"kept in {out}" if out is not None else "computed, none kept (no `out`)"
        super().__init__(f"interrupted: {kept} of {total} chunks {where}")


@dataclass(frozen=True)
class EnsembleProblem:
    """A nominal rigid-body motion, its dispersions and the metrics to record.

    Parameters are in SI units and body axes; ``rotation0`` (body -> space) is a
    poinsot or SciPy ``Rotation`` or a scalar-first quaternion. ``torque_model``
    is ``"none"``, ``"body"``, ``"space"`` (a constant
    ``torque`` vector), ``"gravity"`` (``g`` along ``-z`` of space, the body
    turning about the origin of its axes, ``center_of_mass`` from there) or
    ``"gravity-gradient"``: the gravity-gradient torque along the Kepler ``orbit``
    (:class:`~poinsot.dynamics.OrbitGravityGradientTorque`, docs/theory.md §10.2) with each
    sample's own inertia, so a dispersed inertia changes the torque too.
    ``dispersions`` maps names of :data:`QUANTITIES` to
    :class:`~poinsot.ensemble.dispersion.Dispersion` objects.

    **Frames under "gravity-gradient".** ``orbit`` holds the elements
    :data:`ORBIT_ELEMENTS` (a mapping, or a :class:`~poinsot.dynamics.KeplerOrbit`):
    ``a`` (m), ``e``, ``inclination``, ``raan``, ``argp``, ``anomaly0`` (the true
    anomaly at t = 0; rad) and optionally ``mu`` (m^3/s^2). ``rotation0`` and
    ``omega0`` (and their dispersions) are then **relative to the LVLH frame** at
    ``t[0]``, as the ``spacecraft`` scenario kind reads them: ``rotation0`` is
    ``R_ob`` (body -> LVLH), ``omega0`` the body's rate relative to LVLH in body
    axes, so the inertial start is ``R_ib = R_io R_ob``, ``w_b = omega0 + R_ib^T R_io
    w_o`` (:meth:`~poinsot.dynamics.Spacecraft.orbit_attitude`,
    :meth:`~poinsot.dynamics.Spacecraft.orbit_rate`). The metric ``pointing_error``
    reads the attitude against that frame.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.ensemble import EnsembleProblem, Metric
    >>> orbit = {"a": 6.878e6, "e": 0.0, "inclination": 0.9, "raan": 0.0, "argp": 0.0,
    ...          "anomaly0": 0.0}
    >>> p = EnsembleProblem("gg", np.diag([80.0, 100.0, 40.0]), [1.0, 0, 0, 0], np.zeros(3),
    ...     np.linspace(0.0, 5700.0, 20), torque_model="gravity-gradient", orbit=orbit,
    ...     metrics=(Metric("err", "pointing_error"),))
    >>> dict(p.orbit)["mu"]                       # the Earth's, as KeplerOrbit's
    398600441800000.0
    """

    name: str
    inertia: np.ndarray  # (3, 3) about the centre of mass, body axes
    rotation0: np.ndarray  # (4,) scalar first, body -> space
    omega0: np.ndarray
    t: np.ndarray
    mass: float = 1.0
    center_of_mass: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque_model: str = "none"
    torque: np.ndarray = field(default_factory=lambda: np.zeros(3))
    g: float = 9.80665
    rtol: float = 1e-10
    atol: float = 1e-12
    dispersions: tuple[tuple[str, Dispersion], ...] = ()
    metrics: tuple[Metric, ...] = ()
    orbit: Any = None  # torque_model "gravity-gradient": ((element, value), ...)

    def __post_init__(self) -> None:
        q = as_rotation_quat(self.rotation0, "rotation0")
        if q.shape != (4,):
            raise InvalidInputError(f"Expected one `rotation0`, got shape {q.shape[:-1]}.")
        object.__setattr__(self, "rotation0", q)
        if self.torque_model not in TORQUE_MODELS:
            raise InvalidInputError(
                f"Unknown `torque_model` {self.torque_model!r}; expected one of "
                + ", ".join(TORQUE_MODELS)
                + "."
            )
        orbital = self.torque_model == "gravity-gradient"
        if orbital:
            if self.orbit is None:
                raise InvalidInputError(
                    "The torque model 'gravity-gradient' needs an `orbit` (elements "
                    + ", ".join(ORBIT_ELEMENTS)
                    + ")."
                )
            object.__setattr__(self, "orbit", orbit_elements(self.orbit))
        elif self.orbit is not None:
            raise InvalidInputError(
                f"`orbit` is read by the torque model 'gravity-gradient' only, this "
                f"problem's is {self.torque_model!r}."
            )
        for m in self.metrics:
            if isinstance(m, Metric) and m.orbital and not orbital:
                raise InvalidInputError(
                    f"Metric {m.name!r} reads the pointing error relative to LVLH: it needs "
                    f"the torque model 'gravity-gradient' (an orbit), not {self.torque_model!r}."
                )
            if isinstance(m, Metric) and orbital and m.kind == "energy_drift":
                raise InvalidInputError(
                    f"Metric {m.name!r} (energy_drift): the gravity gradient along an orbit "
                    "conserves no energy of the attitude alone (theory §10.2)."
                )
        for name, d in self.dispersions:
            if name not in QUANTITIES:
                raise InvalidInputError(
                    f"Unknown dispersed quantity {name!r}; expected one of "
                    + ", ".join(QUANTITIES)
                    + "."
                )
            rotational = isinstance(d, SmallRotation | UniformRotation)
            if (name == "attitude") != rotational:
                raise InvalidInputError(
                    f"`dispersion.{name}`: the attitude takes small_rotation or "
                    "uniform_rotation, and those apply to the attitude only."
                )
            if name == "torque" and self.torque_model not in ("body", "space"):
                raise InvalidInputError(
                    "`dispersion.torque` needs a constant torque ([torque] model = "
                    f"'body' or 'space'), the scenario has {self.torque_model!r}."
                )
            if name in ("mass", "center_of_mass") and self.torque_model != "gravity":
                raise InvalidInputError(
                    f"`dispersion.{name}` changes the motion only under gravity about a fixed "
                    f"point; this scenario's torque is {self.torque_model!r}."
                )
        if not self.metrics:
            raise InvalidInputError("An ensemble needs at least one [[metric]].")
        names = [m.name for m in self.metrics]
        if len(set(names)) != len(names):
            raise InvalidInputError(f"Metric names must be distinct, got {names}.")

    def digest(self) -> str:
        """SHA-256 of everything that defines the samples (stored with the chunks)."""

        def enc(x: Any) -> Any:
            if isinstance(x, np.ndarray):
                return x.tolist()
            if isinstance(x, Dispersion | Metric):
                return [type(x).__name__, {k: enc(v) for k, v in vars(x).items()}]
            if isinstance(x, tuple | list):
                return [enc(v) for v in x]
            if isinstance(x, float | int | str | bool) or x is None:
                return x
            return repr(np.asarray(x).tolist())

        blob = json.dumps({k: enc(v) for k, v in vars(self).items()}, sort_keys=True)
        return hashlib.sha256(blob.encode()).hexdigest()


def orbit_elements(orbit: Any) -> tuple[tuple[str, float], ...]:
    """The orbit of torque model ``"gravity-gradient"`` as ``((element, value), ...)`` in
    the order of :data:`ORBIT_ELEMENTS` (rad, SI units), checked by
    :class:`~poinsot.dynamics.KeplerOrbit` (docs/theory.md §10.2).

    ``orbit`` is a mapping of the elements (``mu`` optional: the Earth's) or a
    :class:`~poinsot.dynamics.KeplerOrbit` (its epoch must be 0). An unknown,
    missing or bad element raises :class:`~poinsot.errors.InvalidInputError`
    naming it.

    Examples
    --------
    >>> from poinsot.ensemble import orbit_elements
    >>> el = orbit_elements({"a": 7.0e6, "e": 0.01, "inclination": 0.9, "raan": 0.0,
    ...                      "argp": 0.0, "anomaly0": 0.0, "mu": 3.986e14})
    >>> [k for k, _ in el]
    ['a', 'e', 'inclination', 'raan', 'argp', 'anomaly0', 'mu']
    >>> from poinsot.errors import InvalidInputError
    >>> try:
    ...     orbit_elements({"a": 7.0e6, "e": 0.0, "inclination": 0.9, "raan": 0.0,
    ...                     "argp": 0.0, "anomaly": 0.0})
    ... except InvalidInputError as exc:
    ...     print(str(exc)[:27])
    Unknown key `orbit.anomaly`
    """
    if isinstance(orbit, KeplerOrbit):
        if orbit.epoch != 0.0:
            raise InvalidInputError(
                f"Expected an `orbit` with its epoch at t = 0, got epoch {orbit.epoch!r} s."
            )
        values = {k: getattr(orbit, k) for k in ORBIT_ELEMENTS}
    else:
        if isinstance(orbit, tuple) and all(isinstance(p, tuple) and len(p) == 2 for p in orbit):
            orbit = dict(orbit)
        if not isinstance(orbit, dict):
            raise InvalidTypeError(
                "Expected `orbit` to be a mapping of the elements "
                f"{', '.join(ORBIT_ELEMENTS)} or a KeplerOrbit, got {type(orbit).__name__}."
            )
        for key in orbit:
            if key not in ORBIT_ELEMENTS:
                raise InvalidInputError(
                    f"Unknown key `orbit.{key}`; expected the elements "
                    f"{', '.join(ORBIT_ELEMENTS)} (rad, SI units)."
                )
        for key in ORBIT_ELEMENTS[:-1]:
            if key not in orbit:
                raise InvalidInputError(f"Missing key `orbit.{key}` (the orbit's {key}).")
        values = dict(orbit)
        for key, v in values.items():
            if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
                raise InvalidInputError(f"Expected `orbit.{key}` to be a number, got {v!r}.")
        try:
            checked = KeplerOrbit(**values)  # its errors name the element
        except InvalidInputError as exc:
            raise type(exc)(f"`orbit`: {exc}") from None
        values = {k: getattr(checked, k) for k in ORBIT_ELEMENTS}
    return tuple((k, float(values[k])) for k in ORBIT_ELEMENTS)


def _kepler(problem: EnsembleProblem) -> KeplerOrbit:
    return KeplerOrbit(**dict(problem.orbit))


def _nominal(problem: EnsembleProblem, name: str) -> np.ndarray:
    return {
        "omega0": problem.omega0,
        "attitude": problem.rotation0,
        "inertia": np.diag(problem.inertia).copy(),
        "mass": np.asarray(float(problem.mass)),
        "center_of_mass": problem.center_of_mass,
        "torque": problem.torque,
    }[name]


def _columns_of(name: str, values: np.ndarray) -> dict[str, np.ndarray]:
    if values.ndim == 1:
        return {name: values}
    labels = "wxyz" if name == "attitude" else "xyz"
    return {f"{name}_{c}": values[:, i] for i, c in enumerate(labels)}


def _draw(problem: EnsembleProblem, rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """Inputs of ``n`` samples (one draw per dispersion, in name order)."""
    inputs = {
        name: np.broadcast_to(
            _nominal(problem, name), (n, *np.shape(_nominal(problem, name)))
        ).copy()
        for name in QUANTITIES
    }
    for name, d in sorted(problem.dispersions, key=lambda p: p[0]):
        try:
            v = np.asarray(d.sample(_nominal(problem, name), rng, n), dtype=float)
        except ValueError as exc:  # parameters that do not broadcast with the quantity
            if isinstance(exc, InvalidInputError):
                raise
            raise InvalidInputError(
                f"`dispersion.{name}`: its parameters do not fit the quantity's shape "
                f"{np.shape(_nominal(problem, name))} ({QUANTITIES[name][2]}): {exc}"
            ) from None
        if v.ndim == 1 and inputs[name].ndim == 2:  # one scalar per sample, every component
            v = v[:, None]
        try:
            inputs[name] = np.broadcast_to(v, inputs[name].shape).copy()
        except ValueError:
            raise InvalidInputError(
                f"`dispersion.{name}` draws values of shape {v.shape[1:]}, expected "
                f"{inputs[name].shape[1:]} ({QUANTITIES[name][2]})."
            ) from None
    return inputs


def _physical(inputs: dict[str, np.ndarray]) -> np.ndarray:
    """Reason per sample ('' when physical)."""
    n = inputs["mass"].shape[0]
    reason = np.full(n, "", dtype=object)
    moments = np.sort(inputs["inertia"], axis=1)
    reason[moments[:, 0] + moments[:, 1] < moments[:, 2] * (1 - 1e-12)] = (
        "inertia violates the triangle inequality A + B >= C"
    )
    reason[moments[:, 0] <= 0] = "inertia has a non-positive moment"
    reason[inputs["mass"] <= 0] = "mass <= 0"
    bad = ~np.all(np.isfinite(np.concatenate([v.reshape(n, -1) for v in inputs.values()], 1)), 1)
    reason[bad] = "non-finite input"
    return reason


def run_chunk(problem: EnsembleProblem, index: int, size: int, seed: int) -> dict[str, Any]:
    """Draw and integrate chunk ``index`` (``size`` samples); return its columns.

    The ``sample`` column counts from 0 within the chunk (:func:`run` adds the
    chunk's first sample number); ``size`` is the chunk's true size.
    """

    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
    inputs = _draw(problem, rng, size)
    reason = _physical(inputs)
    ok = reason == ""
    # the nominal sample rides along as body 0 (final attitude error, shared steps)
    nominal = {k: _nominal(problem, k)[None] for k in QUANTITIES}
    arr = {
        k: np.concatenate(
            [nominal[k], np.where(ok.reshape((-1,) + (1,) * (v.ndim - 1)), v, nominal[k])]
        )
        for k, v in inputs.items()
    }
    j_cm = np.broadcast_to(problem.inertia, (size + 1, 3, 3)).copy()
    j_cm[:, [0, 1, 2], [0, 1, 2]] = arr["inertia"]
    model: TorqueModel | None
    sat: Spacecraft | None = None
    q0 = arr["attitude"] / np.linalg.norm(arr["attitude"], axis=1, keepdims=True)
    w0 = arr["omega0"]
    if problem.torque_model == "gravity":
        j = parallel_axis(j_cm, arr["mass"], arr["center_of_mass"])
        model = GravityTorque(arr["mass"], arr["center_of_mass"], g=problem.g)
    elif problem.torque_model == "gravity-gradient":
        # every sample's own J in the torque; the start relative to LVLH at t[0] made
        # inertial as the spacecraft kind does: R_ib = R_io R_ob, w_b = w_rel + R_ib^T R_io w_o
        j = j_cm
        orbit = _kepler(problem)
        sat = Spacecraft(problem.inertia, orbit)
        t0 = float(problem.t[0])
        r_ib = sat.orbit_attitude(t0) * Rotation.from_quat(q0)
        q0 = r_ib.as_quat()
        w0 = w0 + sat.orbit_rate(r_ib, t0)
        model = OrbitGravityGradientTorque(j, orbit)
    else:
        j = j_cm
        kind = {"none": None, "body": ConstantBodyTorque, "space": ConstantSpaceTorque}[
            problem.torque_model
        ]
        model = None if kind is None else kind(arr["torque"])
    with np.errstate(all="ignore"):
        # the public batch integrator (poinsot's compiled DOP853); a failing sample is
        # data here, not an error: marked, its reason kept, its metrics dropped below
        tr = simulate(
            j,
            q0,
            w0,
            problem.t,
            torque=model,
            method="dop853",
            rtol=problem.rtol,
            atol=problem.atol,
            failures="mark",
        )
        quat, omega = np.array(tr.quat), np.array(tr.omega)
        why: Any = tr.info.get("failed")  # per-body reasons ("" = fine) or None
        failed_int = np.zeros(size + 1, dtype=bool) if why is None else why != ""
        for i in np.flatnonzero(failed_int[1:]):
            if ok[i]:
                reason[i] = f"integration failed: {why[i + 1]}"
        if failed_int[0]:
            raise EnsembleError(f"The nominal motion itself fails: {why[0]}.")
        kinetic = np.array(tr.energy)  # T = w.J w / 2, from the one kernel
        if failed_int.any():  # held outputs: stand in the nominal motion, metrics dropped below
            quat[:, failed_int] = quat[:, :1]
            omega[:, failed_int] = omega[:, :1]
            kinetic[:, failed_int] = kinetic[:, :1]
        # the samples' motion (time first, then samples; the nominal body 0 apart) with
        # what gives its V (gravity: m g c per sample): T + V from the Trajectory
        info = {k: np.asarray(tr.info[k])[1:] for k in ("gravity_moment",) if k in tr.info}
        motion = Trajectory(
            problem.t,
            Rotation._wrap(quat[:, 1:]),
            omega[:, 1:],
            tr.method,
            energy=kinetic[:, 1:],
            info=info,
        )
        nominal_final = quat[-1, 0]
        failed = reason != ""
        cols: dict[str, Any] = {
            "sample": np.arange(size, dtype=np.int64),
            "chunk": np.full(size, index, dtype=np.int64),
        }
        for name, _d in problem.dispersions:
            cols.update(_columns_of(name, inputs[name]))
        for metric in problem.metrics:
            v = np.asarray(metric.evaluate(motion, nominal_final, spacecraft=sat), dtype=float)
            cols[metric.name] = np.where(failed, np.nan, v)
    cols["failed"] = failed
    cols["reason"] = reason.astype(str)
    # steps per sample (-1: not counted per sample, a torque evaluated in Python
    # integrates the chunk as one system)
    steps = np.asarray(tr.info["steps"])[1:] if "steps" in tr.info else np.full(size, -1)
    cols["steps"] = np.where(failed, 0, steps).astype(np.int64)
    return cols


@dataclass(frozen=True)
class EnsembleResult:
    """The per-sample table (a :class:`pyarrow.Table`, sorted by ``sample``) and
    its statistics (``summary``: per metric mean, std, quantiles, failures)."""

    table: Any
    summary: dict[str, Any]
    out: Path | None = None

    def column(self, name: str) -> np.ndarray:
        return self.table.column(name).to_numpy(zero_copy_only=False)


def _summary(
    problem: EnsembleProblem, table: Any, samples: int, seed: int, chunk_size: int
) -> dict[str, Any]:
    failed = table.column("failed").to_numpy(zero_copy_only=False)
    reasons = table.column("reason").to_pylist()
    out: dict[str, Any] = {
        "scenario": problem.name,
        "samples": samples,
        "seed": seed,
        "chunk_size": chunk_size,
        "failures": int(failed.sum()),
        "failure_reasons": {r: reasons.count(r) for r in sorted(set(reasons)) if r},
        "integrator": f"compiled DOP853, rtol {problem.rtol:g}, atol {problem.atol:g}",
        "metrics": {},
    }
    for m in problem.metrics:
        v = table.column(m.name).to_numpy(zero_copy_only=False)
        good = v[~failed & np.isfinite(v)]
        q = np.quantile(good, [0.05, 0.25, 0.5, 0.75, 0.95]) if good.size else [math.nan] * 5
        out["metrics"][m.name] = {
            "kind": m.kind,
            "unit": m.unit,
            "count": int(good.size),
            "never": int((~failed & ~np.isfinite(v)).sum()),
            "mean": float(good.mean()) if good.size else math.nan,
            "std": float(good.std(ddof=1)) if good.size > 1 else math.nan,
            "min": float(good.min()) if good.size else math.nan,
            "max": float(good.max()) if good.size else math.nan,
            "quantiles": dict(
                zip(("5%", "25%", "50%", "75%", "95%"), (float(x) for x in q), strict=True)
            ),
        }
    return out


def _table(cols: dict[str, Any], first: int, digest: str, index: int) -> Any:
    import pyarrow as pa

    cols = dict(cols)
    cols["sample"] = cols["sample"] + first
    t = pa.table(cols)
    return t.replace_schema_metadata({"poinsot.digest": digest, "poinsot.chunk": str(index)})


def _write_atomic_parquet(table: Any, path: Path) -> None:
    import pyarrow.parquet as pq

    # Ctrl-C or a full disk: no half-written file left behind (the one atomic writer)
    atomic_write(path, lambda fh: pq.write_table(table, fh), mode="b")


def _chunk_path(out: Path, index: int) -> Path:
    return out / CHUNK_DIR / f"chunk-{index:06d}.parquet"


def _prepare(out: Path, digest: str, manifest: dict[str, Any], resume: bool) -> set[int]:
    """Create or check the output directory; the chunks already done."""
    mpath = out / MANIFEST
    if mpath.exists():
        try:
            old = json.loads(mpath.read_text())
        except (OSError, ValueError) as exc:
            raise EnsembleError(f"{mpath} is unreadable ({exc}); use a new --out.") from None
        if old.get("digest") != digest:
            raise EnsembleError(
                f"{out} holds an ensemble of a different scenario, seed, sample count or chunk "
                f"size (digest {str(old.get('digest'))[:12]} != {digest[:12]}): refusing to "
                f"{'resume' if resume else 'overwrite'} it; use a new --out."
            )
        if not resume:
            raise EnsembleError(
                f"{out} already holds this ensemble: pass --resume to complete "
                "it, or use a new --out."
            )
    elif resume and (out / CHUNK_DIR).exists():
        raise EnsembleError(f"{out} has chunks but no {MANIFEST}: cannot resume safely.")
    (out / CHUNK_DIR).mkdir(parents=True, exist_ok=True)
    atomic_write(mpath, lambda fh: fh.write(json.dumps(manifest, indent=2)))
    done = set()
    import pyarrow.parquet as pq

    for p in (out / CHUNK_DIR).glob("chunk-*.parquet"):
        meta = pq.read_schema(p).metadata or {}
        if meta.get(b"poinsot.digest", b"").decode() == digest:
            done.add(int(meta[b"poinsot.chunk"]))
    return done


def _chunk_task(
    problem: EnsembleProblem,
    index: int,
    size: int,
    seed: int,
    first: int,
    digest: str,
    threads: int,
) -> Any:
    if threads and NUMBA:
        import numba

        numba.set_num_threads(threads)
    return _table(run_chunk(problem, index, size, seed), first, digest, index)


def _connect(client_type: Any, scheduler: str, timeout: float) -> Any:
    """A Client of the Dask scheduler at ``scheduler``, or :class:`EnsembleError` within
    ``timeout`` s.

    The address is checked first (a malformed one is a usage error, not a crash). The
    connection runs in a daemon thread that the caller stops waiting for at the
    deadline: a peer that is not a Dask scheduler (an HTTP server, say) may answer with
    bytes that Dask reads as the length of a huge frame and then wait for ever, or try
    to allocate exabytes; neither may hold the run past ``--timeout``.
    """
    import threading

    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, loc = parse_address(scheduler, strict=False)
        parse_host_port(loc)
    except (ValueError, TypeError) as exc:
        raise EnsembleError(
            f"Expected `scheduler` to be a Dask scheduler address such as "
            f"'tcp://127.0.0.1:8786', got {scheduler!r} ({exc})."
        ) from None
    out: dict[str, Any] = {}
    done = threading.Event()

    def connect() -> None:
        try:
            out["client"] = client_type(scheduler, timeout=f"{timeout}s")
        except BaseException as exc:  # kept for the caller (MemoryError included)
            out["error"] = exc
        finally:
            done.set()

    threading.Thread(target=connect, name="poinsot-dask-connect", daemon=True).start()
    if not done.wait(timeout + 1.0):
        raise EnsembleError(
            f"The Dask scheduler at {scheduler!r} did not answer within {timeout} s (is it a "
            "Dask scheduler? its address and port are those `dask scheduler` prints)."
        )
    if "error" in out:
        err = out["error"]
        if isinstance(err, OSError | TimeoutError):
            raise EnsembleError(
                f"The Dask scheduler at {scheduler!r} did not answer within {timeout} s "
                f"({str(err)[:200]})."
            ) from None
        raise EnsembleError(
            f"The peer at {scheduler!r} is not a usable Dask scheduler "
            f"({type(err).__name__}: {str(err)[:200]})."
        ) from None
    return out["client"]


def _client(scheduler: str | None, workers: int | None, timeout: float) -> tuple[Any, Any]:
    """``(client, cluster)``: a connection to ``scheduler``, or a local cluster we own."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:  # pragma: no cover - the extra is part of make test
        raise EnsembleError("Ensembles need Dask: pip install 'poinsot[ensemble]'.") from exc
    if scheduler is not None:
        return _connect(Client, scheduler, timeout), None
    n = workers or os.cpu_count() or 1

    def start() -> tuple[Any, Any]:
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            host="127.0.0.1",
            preload=["poinsot.ensemble._worker"],
        )
        return Client(cluster), cluster

    return _start_ignoring_sigint(start, n)


def _start_ignoring_sigint(start: Callable[[], tuple[Any, Any]], n: int) -> tuple[Any, Any]:
    """``start()`` a local cluster of ``n`` worker processes that ignore Ctrl-C.

    Ctrl-C reaches the whole process group, the workers too, and a Dask worker
    process prints tracebacks on it (the preload makes a worker ignore it only once
    Dask is imported there). So the workers are spawned while this process ignores
    SIGINT, and inherit that; the cluster starts in a thread meanwhile and this
    thread takes Ctrl-C back as soon as the ``n`` processes exist. A Ctrl-C before
    the cluster is up stops it once it is (:func:`_stop`).
    """
    import multiprocessing
    import signal
    import threading
    import time

    if threading.current_thread() is not threading.main_thread():
        return start()  # no signal handling to do outside the main thread
    before = set(multiprocessing.active_children())
    box: dict[str, Any] = {}

    def target() -> None:
        try:
            box["result"] = start()
        except BaseException as exc:  # for the caller
            box["error"] = exc

    handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
    thread = threading.Thread(target=target, name="poinsot-cluster-start", daemon=True)
    try:
        thread.start()
        while thread.is_alive() and len(set(multiprocessing.active_children()) - before) < n:
            time.sleep(0.01)
    finally:
        if handler is not None:
            signal.signal(signal.SIGINT, handler)
    try:
        while thread.is_alive():
            thread.join(0.05)
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            thread.join(120)
            if "result" in box:
                client, cluster = box["result"]
                _stop(client, cluster, [])
        finally:
            if handler is not None:
                signal.signal(signal.SIGINT, handler)
        raise
    if "error" in box:
        raise box["error"]
    return box["result"]


def _stop(client: Any, own: Any, futures: list[Any]) -> None:
    """Stop the chunks of an interrupted or failed run at once, quietly.

    A cluster of ours (``own``): its worker processes are killed (Dask's own close
    waits up to 4 s for a running chunk, then kills them anyway), then it is closed.
    A cluster not ours: our chunks are cancelled there; its workers go on. Dask's
    loggers are silenced meanwhile (a cancelled task logs ``CancelledError``), and a
    second Ctrl-C cannot cut this short (which would leave workers running).
    """
    import logging
    import signal
    import threading

    loggers = [logging.getLogger(n) for n in ("distributed", "tornado", "asyncio")]
    levels = [lg.level for lg in loggers]
    main = threading.current_thread() is threading.main_thread()
    handler = signal.getsignal(signal.SIGINT) if main else None
    if main:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        for lg in loggers:
            lg.setLevel(logging.CRITICAL + 1)
        if own is None:
            if futures:
                client.cancel(futures, force=True)
            return
        kill = getattr(signal, "SIGKILL", signal.SIGTERM)
        for nanny in list(own.workers.values()):
            try:
                # not restarted when it dies (a shutdown, as Dask's own close says it)
                own.loop.add_callback(nanny.close_gracefully, "poinsot-interrupted")
                pid = nanny.pid
                if pid:
                    os.kill(pid, kill)
            except (OSError, AttributeError):  # gone already, or never started
                pass
        try:  # best effort: the exception being raised is the caller's
            if client is not None:
                client.close(timeout=2)
        except Exception:
            pass
        try:
            own.close(timeout=5)
        except Exception:
            pass
    finally:
        for lg, level in zip(loggers, levels, strict=True):
            lg.setLevel(level)
        if main and handler is not None:
            signal.signal(signal.SIGINT, handler)


def run(
    problem: EnsembleProblem,
    samples: int,
    *,
    chunk_size: int = 1000,
    client: Any = None,
    scheduler: str | None = None,
    workers: int | None = None,
    seed: int = 0,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
    timeout: float = 10.0,
    progress: Progress = None,
    on_chunk: Callable[[int, int], object] | None = None,
) -> EnsembleResult:
    """Run ``samples`` dispersed motions of ``problem``; return the per-sample table.

    Parameters
    ----------
    problem : EnsembleProblem
    samples : int
        Number of samples (> 0).
    chunk_size : int
        Samples per chunk (one compiled batch call, one Parquet file).
    client : dask.distributed.Client or "serial", optional
        An existing Dask client; ``"serial"`` runs every chunk in this process
        (no Dask); ``None`` connects to ``scheduler`` if given, else starts a local
        cluster of ``workers`` processes (default: one per core) and stops it at
        the end.
    seed : int
        Root seed; chunk ``i`` uses ``SeedSequence(seed, spawn_key=(i,))``.
    out : path, optional
        Directory for ``chunks/chunk-NNNNNN.parquet`` (each written atomically
        as it arrives), ``ensemble.json`` (the digest of the problem, seed, sample
        count and chunk size) and, by the caller, ``summary.json``.
    resume : bool
        Complete an interrupted run in ``out``: only missing chunks are computed.
    progress : bool or callable, optional
        As everywhere in poinsot: ``True`` draws a bar (tqdm in terminals and
        notebooks), a callable receives the fraction of chunks done in [0, 1].
    on_chunk : callable, optional
        ``on_chunk(done, total)`` after each chunk arrives (chunk counts; the CLI's
        ``chunks i/n`` line).

    Ctrl-C raises :class:`EnsembleInterrupted` (a ``KeyboardInterrupt`` that says
    how many chunks are kept) within a step of the integrator (serial) or at once
    (Dask): the chunks still queued are cancelled, and the worker processes of a
    cluster this call started are killed and the cluster closed (well under a
    second). Chunks already written to ``out`` stay valid: ``resume=True``
    completes the run.

    Returns
    -------
    EnsembleResult

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.ensemble import EnsembleProblem, Metric, Normal, run
    >>> p = EnsembleProblem("racket", np.diag([1.0, 2.0, 3.0]), np.array([1.0, 0, 0, 0]),
    ...     np.array([0.01, 2.0, 0.01]), np.linspace(0, 20, 401),
    ...     dispersions=(("omega0", Normal(sigma=[0.005, 0.0, 0.005])),),
    ...     metrics=(Metric("flip", "first_flip_time"),))
    >>> res = run(p, 40, chunk_size=16, client="serial", seed=1)
    >>> res.table.num_rows, res.summary["failures"]
    (40, 0)
    """
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer):
        raise InvalidTypeError(f"Expected `samples` to be an integer, got {samples!r}.")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int | np.integer):
        raise InvalidTypeError(f"Expected `chunk_size` to be an integer, got {chunk_size!r}.")
    if samples <= 0:
        raise EnsembleError(f"Expected `samples` > 0, got {samples}.")
    if chunk_size <= 0:
        raise EnsembleError(f"Expected `chunk_size` > 0, got {chunk_size}.")
    if workers is not None and (not isinstance(workers, int) or workers <= 0):
        raise EnsembleError(f"Expected `workers` to be a positive integer, got {workers!r}.")

    samples, chunk_size = int(samples), int(chunk_size)
    n_chunks = -(-samples // chunk_size)
    digest = hashlib.sha256(
        f"{problem.digest()}|{samples}|{chunk_size}|{seed}".encode()
    ).hexdigest()
    sizes = [min(chunk_size, samples - i * chunk_size) for i in range(n_chunks)]
    done: set[int] = set()
    own: Any = None
    made = False  # a client this call made (and closes)
    if client is None and scheduler is not None:
        # before the output directory is touched: a scheduler that does not answer
        # leaves nothing behind that would block a retry into the same `out`
        client, own = _client(scheduler, workers, timeout)
        made = True
    try:
        report = as_progress(progress, "ensemble")
        try:
            result = _run(problem, samples, chunk_size, client, own, made, scheduler,
                          workers, seed, out, resume, timeout, report, on_chunk, digest,
                          n_chunks, sizes, done)  # fmt: skip
        finally:
            if report is not None:
                report.close()  # a bar is closed also on Ctrl-C
        return result
    finally:
        if made:
            client.close()


def _run(
    problem: EnsembleProblem,
    samples: int,
    chunk_size: int,
    client: Any,
    own: Any,
    made: bool,
    scheduler: str | None,
    workers: int | None,
    seed: int,
    out: Any,
    resume: bool,
    timeout: float,
    report: Any,
    on_chunk: Any,
    digest: str,
    n_chunks: int,
    sizes: list[int],
    done: set[int],
) -> EnsembleResult:
    import pyarrow as pa

    outp = None if out is None else Path(out)
    if outp is not None:
        manifest = {
            "digest": digest,
            "scenario": problem.name,
            "samples": samples,
            "chunk_size": chunk_size,
            "seed": seed,
            "chunks": n_chunks,
        }
        done = _prepare(outp, digest, manifest, resume)
    todo = [i for i in range(n_chunks) if i not in done]
    tables: dict[int, Any] = {}
    kept: list[int] = []  # chunks of this call written to `out` (or held in `tables`)

    def arrived(i: int, table: Any) -> None:
        if outp is not None:
            _write_atomic_parquet(table, _chunk_path(outp, i))
        else:
            tables[i] = table
        kept.append(i)
        count = len(done) + len(kept)
        if report is not None:
            report(count / n_chunks)
        if on_chunk is not None:
            on_chunk(count, n_chunks)

    try:
        if client == "serial":
            for i in todo:
                arrived(i, _chunk_task(problem, i, sizes[i], seed, i * chunk_size, digest, 0))
        elif todo:
            if client is None:
                client, own = _client(scheduler, workers, timeout)
            _run_dask(client, own, problem, todo, sizes, seed, chunk_size, digest, arrived)
    except KeyboardInterrupt:
        # what is kept stays valid: every chunk file is whole (written under another
        # name, then renamed) and carries the digest, so resume=True completes the run
        raise EnsembleInterrupted(
            len(done) + len(kept) if outp is not None else 0, n_chunks, outp
        ) from None
    if outp is not None:
        import pyarrow.parquet as pq

        parts = [pq.read_table(_chunk_path(outp, i)) for i in range(n_chunks)]
    else:
        parts = [tables[i] for i in range(n_chunks)]
    table = pa.concat_tables([p.replace_schema_metadata(None) for p in parts])
    summary = _summary(problem, table, samples, seed, chunk_size)
    return EnsembleResult(table=table, summary=summary, out=outp)


def _run_dask(
    client: Any,
    own: Any,
    problem: EnsembleProblem,
    todo: list[int],
    sizes: list[int],
    seed: int,
    chunk_size: int,
    digest: str,
    arrived: Callable[[int, Any], None],
) -> None:
    """The chunks ``todo`` on Dask, each passed to ``arrived`` as it finishes; a
    cluster of ours (``own``) is closed at the end, stopped at once on Ctrl-C."""
    from dask.distributed import as_completed

    futures: dict[Any, int] = {}
    try:
        # a fresh key: a hashed key may still be being released by a previous run
        pf = client.scatter(problem, broadcast=True, hash=False)

        def submit(i: int) -> Any:
            fut = client.submit(
                _chunk_task,
                pf,
                i,
                sizes[i],
                seed,
                i * chunk_size,
                digest,
                1,
                key=f"poinsot-chunk-{digest[:16]}-{i}",
                retries=3,
                pure=False,
            )
            futures[fut] = i
            return fut

        # a window of chunks in flight, not all of them: the scheduler holds a few
        # tasks per worker thread and Ctrl-C has little to cancel
        threads = sum(client.nthreads().values()) or 1
        queue = iter(todo)
        first = itertools.islice(queue, 4 * threads + 4)
        pending = as_completed([submit(i) for i in first])
        for fut in pending:
            i = futures.pop(fut)
            arrived(i, fut.result())
            nxt = next(queue, None)
            if nxt is not None:
                pending.add(submit(nxt))
    except BaseException:
        # Ctrl-C (also while submitting) or a failed chunk: nothing queued may keep
        # running for us, and nothing of Dask's shutdown is printed
        _stop(client, own, list(futures))
        raise
    if own is not None:  # a local cluster of ours (a remote client: closed by run)
        client.close()
        own.close()
