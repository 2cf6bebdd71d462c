"""Cases to files and states from files: ``poinsot verify export`` and the file engine.

Each case is written as ``CASE.csv`` (and ``CASE.parquet`` with ``format="parquet"``),
one row per sample of its grid, with a plain header row:

- rigid body: ``t, qw, qx, qy, qz, wx, wy, wz`` (s; scalar-first unit quaternion,
  body -> space; angular velocity in body axes, rad/s);
- point: ``t, x, y, z, vx, vy, vz`` (s, m, m/s);
- pose (a rigid body in six degrees of freedom, version 3): ``t, x, y, z, vx, vy,
  vz, qw, qx, qy, qz, wx, wy, wz``: the centre of mass's position and velocity (m,
  m/s, space axes), then the rigid columns;
- attitude estimate (the ``estimation`` cases, version 4): ``t, qw, qx, qy, qz, bx,
  by, bz`` (the truth: attitude, gyro bias in rad/s), and the sensor samples an
  estimator runs on, ``CASE.gyro.csv`` (``t, wx, wy, wz``: s, rad/s, body axes) and
  ``CASE.star_tracker.csv`` (``t, qw, qx, qy, qz``); an estimator's file
  ``CASE.csv`` holds ``t, qw, qx, qy, qz`` and optionally ``bx, by, bz`` (rad/s) and
  ``sx, sy, sz`` (1-sigma attitude errors about the body axes, rad)
  (:func:`write_estimate`),

and ``CASE.json``: the inputs (SI), the grid, the thresholds, units and conventions
(:func:`poinsot.verify.cases.describe`), with ``index.json`` listing the cases and
the version. Numbers are written with 17 significant digits, so a file read back
holds the exact states to the last bit.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from ..errors import InvalidInputError, InvalidTypeError
from ..kinematics import quat_rate
from ..kinematics.attitude_history import _make_continuous
from ..rotations.rotation import Rotation
from ..trajectory import Result
from .cases import CASES_VERSION, Case, cases, describe
from .groups import ESTIMATE_COLUMNS, POINT_COLUMNS, Estimate, as_result, point_result, quat_unit

MATRIX_COLUMNS = tuple(f"r{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3))


def state_table(
    case: Case, states: Result | dict[str, np.ndarray]
) -> tuple[tuple[str, ...], np.ndarray]:
    """``(columns, (n, k) array)`` of ``states`` (a result, or a dict of arrays) on the
    case's grid, as exported."""
    spec = case.spec
    if isinstance(states, Result):
        states = spec.arrays(states)
    return spec.columns, np.column_stack([case.t, *(states[k] for k in spec.states)])


def _text_writer(text: str) -> Callable[[Any], object]:
    return lambda fh: fh.write(text)


def _csv_writer(table: np.ndarray, header: str) -> Callable[[Any], object]:
    def write(fh: Any) -> None:
        np.savetxt(fh, table, delimiter=",", header=header, comments="", fmt="%.17g")

    return write


def _parquet(pq: Any, table: Any, fh: Any) -> None:
    pq.write_table(table, fh)


def export(directory: str | Path, select: str | Iterable[str] | None = None, *,
           format: str = "csv") -> list[Path]:  # fmt: skip
    """Write the exact states of the cases, with their descriptions, to ``directory``.

    Parameters
    ----------
    directory : str or Path
        Created if missing.
    select : str or iterable of str, optional
        Case names or groups (default every case), as :func:`poinsot.verify.cases`.
    format : {"csv", "parquet"}, optional
        Parquet needs ``pyarrow`` (``pip install poinsot[ensemble]``); the CSV is
        always written.

    Returns
    -------
    list of Path
        The files written.

    Examples
    --------
    >>> import tempfile, pandas as pd
    >>> from poinsot.verify import export
    >>> out = tempfile.mkdtemp()
    >>> files = export(out, "kepler-e0.5")
    >>> sorted(p.name for p in files)
    ['index.json', 'kepler-e0.5.csv', 'kepler-e0.5.json']
    >>> list(pd.read_csv(files[1]).columns)
    ['t', 'x', 'y', 'z', 'vx', 'vy', 'vz']
    """
    if not isinstance(directory, (str, Path)):
        raise InvalidTypeError(
            f"Expected `directory` to be a path, got {type(directory).__name__}."
        )
    if format not in ("csv", "parquet"):
        raise InvalidInputError(f"Expected `format` to be 'csv' or 'parquet', got {format!r}.")
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    chosen = cases(select)
    for case in chosen:
        columns, table = state_table(case, case.exact())
        csv = out / f"{case.name}.csv"
        atomic_write(csv, _csv_writer(table, ",".join(columns)))
        written.append(csv)
        if format == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            arrow = pa.table({c: table[:, k] for k, c in enumerate(columns)})
            atomic_write(out / f"{case.name}.parquet", functools.partial(_parquet, pq, arrow), "b")
            written.append(out / f"{case.name}.parquet")
        for suffix, (cols, tab) in case.spec.sensor_files(case).items():
            extra = out / f"{case.name}.{suffix}.csv"
            atomic_write(extra, _csv_writer(tab, ",".join(cols)))
            written.append(extra)
        desc = out / f"{case.name}.json"
        atomic_write(desc, _text_writer(json.dumps(describe(case), indent=2) + "\n"))
        written.append(desc)
    index = out / "index.json"
    listing = json.dumps({"cases_version": CASES_VERSION, "cases": [c.name for c in chosen],
                          "docs": "docs/verify.md"}, indent=2) + "\n"  # fmt: skip
    atomic_write(index, _text_writer(listing))
    written.append(index)
    return sorted(written)


def write_estimate(directory: str | Path, case: Case, estimate: Estimate) -> Path:
    """Write an attitude estimate of an estimation case as the file engine reads it:
    ``DIRECTORY/CASE.csv``, columns ``t, qw, qx, qy, qz`` then, when the estimate has
    them, ``bx, by, bz`` (rad/s) and ``sx, sy, sz`` (rad), 17 significant digits (read
    back bit for bit; docs/verify.md, docs/theory.md §10.4).

    Examples
    --------
    >>> import tempfile
    >>> from poinsot.verify import cases
    >>> from poinsot.verify.groups import mekf_estimate
    >>> case = cases("mekf-racket")[0]
    >>> path = write_estimate(tempfile.mkdtemp(), case, mekf_estimate(case))
    >>> path.name, path.read_text().splitlines()[0]
    ('mekf-racket.csv', 't,qw,qx,qy,qz,bx,by,bz,sx,sy,sz')
    """
    if not isinstance(estimate, Estimate):
        raise InvalidTypeError(
            f"Expected `estimate` to be an Estimate, got {type(estimate).__name__}."
        )
    names = list(ESTIMATE_COLUMNS[:5])
    parts = [case.t, estimate.quat]
    for cols, arr in (
        (ESTIMATE_COLUMNS[5:8], estimate.bias),
        (ESTIMATE_COLUMNS[8:], estimate.sigma),
    ):
        if arr is not None:
            names += cols
            parts.append(arr)
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{case.name}.csv"
    atomic_write(path, _csv_writer(np.column_stack(parts), ",".join(names)))
    return path


def read_table(path: Path) -> dict[str, np.ndarray]:
    """Columns of a CSV (header row) or Parquet file as float arrays, in file order.

    Raises
    ------
    InvalidInputError
        For an empty file, a header without data rows, a row with the wrong number
        of fields, or a field that is not a number (naming the file, the line and
        the column).
    """
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        tab = pq.read_table(path)
        if tab.num_rows == 0:
            raise InvalidInputError(
                f"{path}: expected one row per sample of the case's grid, found no rows "
                f"(columns {', '.join(tab.column_names) or 'none'})."
            )
        cols: dict[str, np.ndarray] = {}
        for c in tab.column_names:
            try:
                cols[c] = np.asarray(tab.column(c).to_numpy(zero_copy_only=False), dtype=float)
            except (TypeError, ValueError):
                raise InvalidInputError(
                    f"{path}: expected column `{c}` to hold numbers, found type "
                    f"{tab.schema.field(c).type}."
                ) from None
        return cols
    import csv

    with open(path, newline="", encoding="utf-8-sig") as f:
        rows = [r for r in csv.reader(f) if r and any(x.strip() for x in r)]
    if not rows:
        raise InvalidInputError(
            f"{path}: expected a header row (e.g. t, qw, qx, qy, qz, wx, wy, wz) and one row "
            "per sample of the case's grid, found an empty file."
        )
    header = [h.strip() for h in rows[0]]
    if len(rows) == 1:
        raise InvalidInputError(
            f"{path}: expected one row per sample of the case's grid after the header "
            f"({', '.join(header)}), found the header alone."
        )
    data = np.empty((len(rows) - 1, len(header)))
    for n, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise InvalidInputError(
                f"{path}: expected {len(header)} fields per row (the header's), found "
                f"{len(row)} in data row {n + 1}."
            )
        for k, x in enumerate(row):
            try:  # an empty field is a missing value (NaN), as pandas writes it
                data[n, k] = float(x) if x.strip() else np.nan
            except ValueError:
                raise InvalidInputError(
                    f"{path}: expected column `{header[k]}` to hold numbers, found "
                    f"{x.strip()!r} in data row {n + 1}."
                ) from None
    return {name: data[:, k] for k, name in enumerate(header)}


class FileEngine:
    """States that an engine wrote to files: ``DIRECTORY/CASE.csv`` (or ``.parquet``).

    Parameters
    ----------
    directory : str or Path
        Where the files are; a case without a file is skipped.
    quat_order : {"wxyz", "xyzw"}, optional
        Order of the four quaternion columns (``q0..q3``, or ``qw, qx, qy, qz``) as
        they stand in the file, whatever their names: scalar first (poinsot,
        MuJoCo) or scalar last (SciPy, Eigen's coefficients, ROS). Default None:
        ``qw, qx, qy, qz`` by name, ``q0..q3`` scalar first. A file with
        ``r11..r33`` gives the attitude matrix (body -> space) instead.
    omega_frame : {"body", "space"}, optional
        Axes of ``wx, wy, wz`` (default body).
    degrees : bool, optional
        Angular velocity in deg/s.

    Notes
    -----
    Every file is checked before it is scored: the grid must be the case's, the
    quaternions unit, and the motion must satisfy the kinematic equation
    ``q' = q (0, w) / 2`` (docs/theory.md §5) to a relative 1e-2, by a 4th-order
    central difference of ``q``. When it does not, the other conventions are tried
    (the other quaternion order, space-axes or degree angular velocity): if one
    fits, the error names it (bad input); if none does, the engine's attitude and
    angular velocity are not one motion, and the case is scored as given and fails
    with that finding. A case without a file is *missing* (``missing_reason``).
    Non-finite states (a diverged engine) are scored as given: they fail.
    """

    name = "file"

    def __init__(self, directory: str | Path, quat_order: str | None = None,
                 omega_frame: str = "body", degrees: bool = False):  # fmt: skip
        if not isinstance(directory, (str, Path)):
            raise InvalidTypeError(
                f"Expected `directory` to be a path, got {type(directory).__name__}."
            )
        self.directory = Path(directory)
        if not self.directory.is_dir():
            raise InvalidInputError(
                f"Expected `directory` to be an existing directory, got {str(directory)!r}."
            )
        if quat_order not in (None, "wxyz", "xyzw"):
            raise InvalidInputError(
                f"Expected `quat_order` to be 'wxyz', 'xyzw' or None (by column name), got "
                f"{quat_order!r}."
            )
        if omega_frame not in ("body", "space"):
            raise InvalidInputError(
                f"Expected `omega_frame` to be 'body' or 'space', got {omega_frame!r}."
            )
        if not isinstance(degrees, bool):
            raise InvalidTypeError(f"Expected `degrees` to be True or False, got {degrees!r}.")
        self.quat_order, self.omega_frame, self.degrees = quat_order, omega_frame, degrees
        order = quat_order or "quaternion columns by name"
        self.label = f"file {self.directory} ({order}, omega in {omega_frame} axes" + (
            ", deg/s)" if degrees else ", rad/s)"
        )

    def _file(self, case: Case) -> Path | None:
        for ext in (".csv", ".parquet"):
            p = self.directory / f"{case.name}{ext}"
            if p.is_file():
                return p
        return None

    def skip_reason(self, case: Case) -> str | None:
        return None  # a file may hold any case

    def missing_reason(self, case: Case) -> str | None:
        return (
            None if self._file(case) else f"no file {case.name}.csv or .parquet in {self.directory}"
        )

    def run(self, case: Case) -> tuple[Result, None, list[str]]:
        path = self._file(case)
        assert path is not None
        cols = read_table(path)
        if "t" not in cols:
            raise InvalidInputError(f"{path}: expected a column `t` (s).")
        t = cols["t"]
        grid = (
            f"the case's time grid ({case.t.size} samples, step {case.t[1] - case.t[0]:g} s "
            f"from 0; see {case.name}.json of `poinsot verify export`)"
        )
        if t.shape != case.t.shape:
            raise InvalidInputError(f"{path}: expected {grid} in column `t`, got {t.size} samples.")
        bad = np.nonzero(~(np.abs(t - case.t) <= 1e-9))[0]
        if bad.size:
            k = int(bad[0])
            raise InvalidInputError(
                f"{path}: expected {grid} in column `t`, got t = {float(t[k])!r} s in data row "
                f"{k + 1} where the grid has {float(case.t[k])!r} s ({bad.size} samples off by "
                "more than 1e-9 s)."
            )
        own = case.spec.read_columns(path, case, cols, self.label)
        if own is not None:  # an estimate (the estimation cases)
            return own[0], None, own[1]
        if case.kind in ("point", "pose"):
            need = POINT_COLUMNS[1:]
            missing = [c for c in need if c not in cols]
            if missing:
                raise InvalidInputError(
                    f"{path}: expected columns {', '.join(need)}; missing {', '.join(missing)}."
                )
            pos = np.column_stack([cols[c] for c in need[:3]])
            vel = np.column_stack([cols[c] for c in need[3:]])
            if case.kind == "point":
                return point_result(case, pos, vel, self.label), None, []
        states = _rigid_from_columns(
            path, case, cols, self.quat_order, self.omega_frame, self.degrees
        )
        defects = list(states.pop("defects"))
        if case.kind == "pose":  # the centre of mass's columns, then the rigid ones
            if all(np.all(np.isfinite(a)) for a in (pos, vel)):
                states.update(position=pos, velocity=vel)
            else:  # a diverged engine: NaN states that fail every metric
                states = _diverged(path, case, cols)
                defects = list(states.pop("defects"))
        return as_result(case, states, self.label), None, defects


def _rigid_from_columns(path: Path, case: Case, cols: dict[str, np.ndarray], order: str | None,
                        frame: str, degrees: bool) -> dict[str, Any]:  # fmt: skip
    wcols = ("wx", "wy", "wz")
    if any(c not in cols for c in wcols):
        raise InvalidInputError(f"{path}: expected the angular velocity columns wx, wy, wz.")
    w = np.column_stack([cols[c] for c in wcols])
    alternatives: list[tuple[str, np.ndarray]] = []
    if all(c in cols for c in MATRIX_COLUMNS):
        m = np.stack([cols[c] for c in MATRIX_COLUMNS], axis=-1).reshape(-1, 3, 3)
        if not np.all(np.isfinite(m)):
            return _diverged(path, case, cols)
        q = np.asarray(Rotation.from_matrix(m).as_quat(), dtype=float)
        given = "attitude matrix r11..r33"
    else:
        named = ("qw", "qx", "qy", "qz")
        names = named if all(c in cols for c in named) else ("q0", "q1", "q2", "q3")
        if any(c not in cols for c in names):
            raise InvalidInputError(
                f"{path}: expected quaternion columns qw, qx, qy, qz (or q0..q3) or matrix "
                f"columns r11..r33, found {', '.join(cols)}."
            )
        # the four quaternion columns in file order; --quat-order reads them by position
        in_file = [c for c in cols if c in names]
        raw = np.column_stack([cols[c] for c in in_file])
        by_order = {"wxyz": raw, "xyzw": raw[:, [3, 0, 1, 2]]}
        if order is None:
            q = np.column_stack([cols[c] for c in names])  # by name (q0..q3: scalar first)
            given = "quaternion columns by name" if names == named else "q0..q3 scalar first"
        else:
            q = by_order[order]
            given = f"{order}: columns {', '.join(in_file)} read as {', '.join(order)}"
        for o, label in (("xyzw", "scalar-last quaternions (quat_order='xyzw')"),
                         ("wxyz", "scalar-first quaternions (quat_order='wxyz')")):  # fmt: skip
            if not np.array_equal(by_order[o], q, equal_nan=True):
                alternatives.append((label, by_order[o]))
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(w))):
        return _diverged(path, case, cols)
    norm = np.linalg.norm(q, axis=-1)
    if np.max(np.abs(norm - 1.0)) > 1e-6:
        raise InvalidInputError(
            f"{path}: expected unit quaternions, found |q| from {np.min(norm):.6g} to "
            f"{np.max(norm):.6g}."
        )
    defects = []
    fit = _kinematic_residual(case.t, q, w, frame, degrees)
    if not fit < 1e-2:
        hints = []
        for label, qq, fr, dg in (
            *[(lab, qa, frame, degrees) for lab, qa in alternatives],
            ("angular velocity in space axes (omega_frame='space')", q, "space", degrees),
            ("angular velocity in body axes (omega_frame='body')", q, "body", degrees),
            ("angular velocity in deg/s (degrees=True)", q, frame, True),
        ):
            if (fr, dg) == (frame, degrees) and qq is q:
                continue
            if _kinematic_residual(case.t, qq, w, fr, dg) < 1e-2:
                hints.append(label)
        conventions = f"({given}, omega in {frame} axes, {'deg/s' if degrees else 'rad/s'})"
        if hints:
            raise InvalidInputError(
                f"{path}: the attitude and the angular velocity violate the kinematic equation "
                f"q' = q (0, w) / 2 (relative residual {fit:.2g}) with the conventions given "
                f"{conventions}. The data fit {' or '.join(hints)}."
            )
        # no convention fits: not a convention error but an engine whose attitude and
        # angular velocity are not one motion (e.g. explicit Euler at a coarse step)
        defects.append(
            f"kinematics: attitude and angular velocity violate q' = q (0, w) / 2 (relative "
            f"residual {fit:.3g} >= 0.01 with the conventions given {conventions}, and no "
            "other convention fits): they are not one motion (docs/theory.md §5)"
        )
    if degrees:
        w = np.radians(w)
    if frame == "space":
        w = np.asarray(Rotation.from_quat(q).inv().apply(w), dtype=float)
    return {"quat": quat_unit(q), "omega": w, "defects": defects}


def _diverged(path: Path, case: Case, cols: dict[str, np.ndarray]) -> dict[str, Any]:
    """States of a file with non-finite values: NaN states that fail every metric."""
    bad = [c for c, v in cols.items() if c != "t" and not np.all(np.isfinite(v))]
    out: dict[str, Any] = case.spec.nan_states(case)
    out["defects"] = [f"non-finite values in column(s) {', '.join(bad)} of {path.name}"]
    return out


def _kinematic_residual(
    t: np.ndarray, q: np.ndarray, w: np.ndarray, frame: str, degrees: bool
) -> float:
    """``max |q'_fd - q_rate(q, w)| / max |q_rate|`` by 4th-order central differences."""

    if t.size < 5:
        return 0.0
    q = _make_continuous(q / np.linalg.norm(q, axis=-1, keepdims=True))
    h = t[1] - t[0]
    dq = (q[:-4] - 8.0 * q[1:-3] + 8.0 * q[3:-1] - q[4:]) / (12.0 * h)
    ww = np.radians(w) if degrees else w
    rate = np.asarray(quat_rate(q[2:-2], ww[2:-2], frame=frame), dtype=float)
    scale = float(np.max(np.linalg.norm(rate, axis=-1)))
    if not np.isfinite(scale) or scale == 0.0:
        return 0.0 if np.allclose(dq, 0.0) else np.inf
    return float(np.max(np.linalg.norm(dq - rate, axis=-1)) / scale)
