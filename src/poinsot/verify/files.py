"""Cases to files and states from files: ``poinsot verify export`` and the file engine.

Each case is written as ``CASE.csv`` (and ``CASE.parquet`` with ``format="parquet"``),
one row per sample of its grid, with a plain header row:

- rigid body: ``t, qw, qx, qy, qz, wx, wy, wz`` (s; scalar-first unit quaternion,
  body -> space; angular velocity in body axes, rad/s);
- point: ``t, x, y, z, vx, vy, vz`` (s, m, m/s),

and ``CASE.json``: the inputs (SI), the grid, the thresholds, units and conventions
(:func:`poinsot.verify.cases.describe`), with ``index.json`` listing the cases and
the version. Numbers are written with 17 significant digits, so a file read back
holds the exact states to the last bit.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ..errors import InvalidInputError, InvalidTypeError
from .cases import CASES_VERSION, Case, cases, describe

RIGID_COLUMNS = ("t", "qw", "qx", "qy", "qz", "wx", "wy", "wz")
MATRIX_COLUMNS = tuple(f"r{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3))
POINT_COLUMNS = ("t", "x", "y", "z", "vx", "vy", "vz")


def state_table(case: Case, states: dict[str, np.ndarray]) -> tuple[tuple[str, ...], np.ndarray]:
    """``(columns, (n, k) array)`` of ``states`` on the case's grid, as exported."""
    if case.kind == "rigid":
        return RIGID_COLUMNS, np.column_stack([case.t, states["quat"], states["omega"]])
    return POINT_COLUMNS, np.column_stack([case.t, states["position"], states["velocity"]])


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
        np.savetxt(csv, table, delimiter=",", header=",".join(columns), comments="", fmt="%.17g")
        written.append(csv)
        if format == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            pq.write_table(pa.table({c: table[:, k] for k, c in enumerate(columns)}),
                           out / f"{case.name}.parquet")  # fmt: skip
            written.append(out / f"{case.name}.parquet")
        desc = out / f"{case.name}.json"
        desc.write_text(json.dumps(describe(case), indent=2) + "\n")
        written.append(desc)
    index = out / "index.json"
    index.write_text(json.dumps({"cases_version": CASES_VERSION, "cases": [c.name for c in chosen],
                                 "docs": "docs/verify.md"}, indent=2) + "\n")  # fmt: skip
    written.append(index)
    return sorted(written)


def read_table(path: Path) -> dict[str, np.ndarray]:
    """Columns of a CSV (header row) or Parquet file as float arrays."""
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        tab = pq.read_table(path)
        return {c: np.asarray(tab.column(c), dtype=float) for c in tab.column_names}
    try:
        data = np.genfromtxt(path, delimiter=",", names=True, dtype=float, encoding="utf-8")
    except ValueError as exc:
        raise InvalidInputError(
            f"Expected {path} to be a CSV file of numbers with a header row: {exc}"
        ) from None
    return {
        name: np.atleast_1d(np.asarray(data[name], dtype=float)) for name in data.dtype.names or ()
    }


class FileEngine:
    """States that an engine wrote to files: ``DIRECTORY/CASE.csv`` (or ``.parquet``).

    Parameters
    ----------
    directory : str or Path
        Where the files are; a case without a file is skipped.
    quat_order : {"wxyz", "xyzw"}, optional
        Order of the quaternion columns ``q0..q3`` (or ``qw, qx, qy, qz`` by name):
        scalar first (default, poinsot, MuJoCo) or scalar last (SciPy, Eigen's
        coefficients, ROS). A file with ``r11..r33`` gives the attitude matrix
        (body -> space) instead.
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
    (scalar-last quaternions, space-axes or degree angular velocity) and the error
    names the one that fits.
    """

    name = "file"

    def __init__(self, directory: str | Path, quat_order: str = "wxyz",
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
        if quat_order not in ("wxyz", "xyzw"):
            raise InvalidInputError(
                f"Expected `quat_order` to be 'wxyz' or 'xyzw', got {quat_order!r}."
            )
        if omega_frame not in ("body", "space"):
            raise InvalidInputError(
                f"Expected `omega_frame` to be 'body' or 'space', got {omega_frame!r}."
            )
        if not isinstance(degrees, bool):
            raise InvalidTypeError(f"Expected `degrees` to be True or False, got {degrees!r}.")
        self.quat_order, self.omega_frame, self.degrees = quat_order, omega_frame, degrees
        self.label = f"file {self.directory} ({quat_order}, omega in {omega_frame} axes" + (
            ", deg/s)" if degrees else ", rad/s)"
        )

    def _file(self, case: Case) -> Path | None:
        for ext in (".csv", ".parquet"):
            p = self.directory / f"{case.name}{ext}"
            if p.is_file():
                return p
        return None

    def skip_reason(self, case: Case) -> str | None:
        return (
            None if self._file(case) else f"no file {case.name}.csv or .parquet in {self.directory}"
        )

    def run(self, case: Case) -> tuple[dict[str, np.ndarray], None]:
        path = self._file(case)
        assert path is not None
        cols = read_table(path)
        if "t" not in cols:
            raise InvalidInputError(f"{path}: expected a column `t` (s).")
        t = cols["t"]
        if t.shape != case.t.shape or not np.allclose(t, case.t, rtol=0.0, atol=1e-9):
            raise InvalidInputError(
                f"{path}: expected the case's time grid ({case.t.size} samples, step "
                f"{case.t[1] - case.t[0]:g} s from 0), got {t.size} samples from {t[0]:g} s "
                f"(see {case.name}.json of `poinsot verify export`)."
            )
        if case.kind == "point":
            need = POINT_COLUMNS[1:]
            missing = [c for c in need if c not in cols]
            if missing:
                raise InvalidInputError(
                    f"{path}: expected columns {', '.join(need)}; missing {', '.join(missing)}."
                )
            return {"position": np.column_stack([cols[c] for c in need[:3]]),
                    "velocity": np.column_stack([cols[c] for c in need[3:]])}, None  # fmt: skip
        return _rigid_from_columns(
            path, case, cols, self.quat_order, self.omega_frame, self.degrees
        ), None


def _rigid_from_columns(path: Path, case: Case, cols: dict[str, np.ndarray], order: str,
                        frame: str, degrees: bool) -> dict[str, np.ndarray]:  # fmt: skip
    from ..rotations.rotation import Rotation

    wcols = ("wx", "wy", "wz")
    if any(c not in cols for c in wcols):
        raise InvalidInputError(f"{path}: expected the angular velocity columns wx, wy, wz.")
    w = np.column_stack([cols[c] for c in wcols])
    if all(c in cols for c in MATRIX_COLUMNS):
        m = np.stack([cols[c] for c in MATRIX_COLUMNS], axis=-1).reshape(-1, 3, 3)
        q = np.asarray(Rotation.from_matrix(m).as_quat(), dtype=float)
    else:
        names = ("qw", "qx", "qy", "qz") if all(c in cols for c in ("qw", "qx", "qy", "qz")) else (
            "q0", "q1", "q2", "q3")  # fmt: skip
        if any(c not in cols for c in names):
            raise InvalidInputError(
                f"{path}: expected quaternion columns qw, qx, qy, qz (or q0..q3) or matrix "
                f"columns r11..r33."
            )
        q = np.column_stack([cols[c] for c in names])
        if names[0] == "q0" and order == "xyzw":
            q = q[:, [3, 0, 1, 2]]
    norm = np.linalg.norm(q, axis=-1)
    if not np.all(np.isfinite(q)) or np.max(np.abs(norm - 1.0)) > 1e-6:
        raise InvalidInputError(
            f"{path}: expected unit quaternions, found |q| from {np.min(norm):.6g} to "
            f"{np.max(norm):.6g}."
        )
    fit = _kinematic_residual(case.t, q, w, frame, degrees)
    if not fit < 1e-2:
        hints = []
        for label, qq, fr, dg in (
            ("scalar-last quaternions (quat_order='xyzw')", q[:, [3, 0, 1, 2]], frame, degrees),
            ("angular velocity in space axes (omega_frame='space')", q, "space", degrees),
            ("angular velocity in body axes (omega_frame='body')", q, "body", degrees),
            ("angular velocity in deg/s (degrees=True)", q, frame, True),
        ):
            if (fr, dg) == (frame, degrees) and qq is q:
                continue
            if _kinematic_residual(case.t, qq, w, fr, dg) < 1e-2:
                hints.append(label)
        hint = f" The data fit {' or '.join(hints)}." if hints else (
            " No other convention fits either: the attitude and the angular velocity do not "
            "belong to one motion.")  # fmt: skip
        raise InvalidInputError(
            f"{path}: the attitude and the angular velocity violate the kinematic equation "
            f"q' = q (0, w) / 2 (relative residual {fit:.2g}) with the conventions given "
            f"({order}, omega in {frame} axes, {'deg/s' if degrees else 'rad/s'}).{hint}"
        )
    if degrees:
        w = np.radians(w)
    if frame == "space":
        w = np.asarray(Rotation.from_quat(q).inv().apply(w), dtype=float)
    from .engines import _quat_unit

    return {"quat": _quat_unit(q), "omega": w}


def _kinematic_residual(
    t: np.ndarray, q: np.ndarray, w: np.ndarray, frame: str, degrees: bool
) -> float:
    """``max |q'_fd - q_rate(q, w)| / max |q_rate|`` by 4th-order central differences."""
    from ..kinematics import quat_rate
    from ..kinematics.attitude_history import _make_continuous

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
