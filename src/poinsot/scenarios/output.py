"""Writing the outputs of a run, atomically, into an output directory.

:func:`write_outputs` writes ``trajectory.csv`` (or ``.npz``), the PNG figures of
the scenario's kind, ``report.html`` and ``summary.json`` (last, so that its
presence marks a complete run), all of them into a staging folder beside the output
directory, moved into place once complete; :func:`run_scenario` solves and writes.

Figures are drawn on :class:`matplotlib.figure.Figure` objects made here, never
through pyplot: the caller's backend and figures are left alone.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from ..errors import InvalidInputError
from ..trajectory import Trajectory
from .facts import Progress
from .report import write_scenario_report
from .schema import Scenario
from .solve import _expect, check_cost, quiet_progress, simulate_scenario, span
from .summary import CONVENTIONS, ScenarioResult, conventions_of, versions

__all__ = ["write_outputs", "run_scenario", "prepare_output_dir", "OutputFiles", "OUTPUT_FILES"]

#: Every file a run may write; a forced rerun removes those it does not rewrite.
OUTPUT_FILES = (
    "trajectory.csv",
    "trajectory.npz",
    "trajectory.columns.json",
    "reference.csv",
    "reference.npz",
    "reference.columns.json",
    "omega.png",
    "invariants.png",
    "maccullagh.png",
    "poinsot.png",
    "report.html",
    "summary.json",
)

_ROWS_PER_WRITE = 10000


class OutputFiles(list[Any]):
    """The paths written (a list), with the ``notes`` of the writing (skipped figures,
    a missing optional dependency...), also recorded in ``summary.json``."""

    def __init__(self, paths: Any = (), notes: Any = ()) -> None:
        super().__init__(paths)
        self.notes = list(notes)


def prepare_output_dir(out: str | os.PathLike[str], *, force: bool = False) -> Path:
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


#: the one atomic writer (:func:`poinsot._files.atomic_write`); the writers below call it
#: by this name, which tests replace to simulate a full disk
_atomic = atomic_write


# ----------------------------------------------------------------------------- trajectory
def _columns(result: ScenarioResult, tr: Any) -> Any:
    """Column names, units, descriptions and data of a trajectory file: a rigid
    body's attitude, omega, K and T; any other result's own channels
    (:meth:`~poinsot.trajectory.Result.channels`); then the kind's extra series."""
    if isinstance(tr, Trajectory):
        names = ["t", "qw", "qx", "qy", "qz", "wx", "wy", "wz"]
        units = ["s"] + ["1"] * 4 + ["rad/s"] * 3
        cols = [tr.t[:, None], tr.quat, tr.omega]
        if tr.momentum is not None and tr.energy is not None:  # recorded together
            names += ["Kx", "Ky", "Kz", "T"]
            units += ["kg m^2/s"] * 3 + ["J"]
            cols += [tr.momentum, tr.energy[:, None]]
        described: list[str] = []
    else:
        names, units, cols, described = ["t"], ["s"], [tr.t[:, None]], ["t: time (s)"]
        for ch in tr.channels().values():
            v = np.asarray(ch.values, dtype=float).reshape(tr.t.size, -1)
            comps = list(getattr(ch, "components", None) or ())
            if v.shape[1] == 1:
                col_names = [ch.name]
            elif len(comps) == v.shape[1]:
                col_names = [f"{ch.name}_{c}" for c in comps]
            else:
                col_names = [f"{ch.name}_{k}" for k in range(v.shape[1])]
            names += col_names
            units += [ch.units or "1"] * v.shape[1]
            cols.append(v)
            what = getattr(ch, "description", "") or ch.name
            described.append(f"{','.join(col_names)}: {what} ({ch.units or '1'})")
    extra = result.scenario.adapter.series(result.scenario, tr)
    for name, (values, unit) in extra.items():
        if name in names:
            continue
        names.append(name)
        units.append(unit)
        cols.append(np.asarray(values)[:, None])
        described.append(f"{name}: a series of the {result.scenario.kind} kind ({unit or '1'})")
    return names, units, described, np.hstack(cols)


def _header(result: ScenarioResult, tr: Any, names: Any, units: Any, described: Any) -> list[str]:
    s = result.scenario
    lines = [
        f"poinsot {versions()['poinsot']} trajectory of scenario {s.name!r} "
        f"(kind {s.kind}, method {tr.method}, {tr.t.size} samples)",
    ]
    if isinstance(tr, Trajectory):
        lines.append("conventions: " + CONVENTIONS)
        gravity = s.torque is not None and s.torque.model == "gravity"
        point = "the fixed point (origin of the body axes)" if gravity else "the centre of mass"
        lines += [
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
    else:
        lines.append("conventions: " + conventions_of(tr))
        lines += described
    lines.append("units: " + ",".join(units))
    lines.append(",".join(names))
    return lines


def _write_trajectory(result: ScenarioResult, tr: Any, path: Path, fmt: str) -> list[Path]:
    """The trajectory file; for CSV also ``<stem>.columns.json`` (units and meaning).

    The CSV's first line names the columns and nothing precedes it, so that
    ``pandas.read_csv(path)`` and ``numpy.genfromtxt(path, delimiter=",", names=True)``
    read it as it is; the units, the conventions and each column's meaning go to the
    JSON file beside it (``columns``: name -> units; ``header``: the description).
    """
    names, units, described, data = _columns(result, tr)
    header = _header(result, tr, names, units, described)
    if fmt == "csv":

        def write(fh: Any) -> None:
            fh.write(",".join(names) + "\n")
            for k in range(0, len(data), _ROWS_PER_WRITE):  # repr: shortest round-trip
                rows = data[k : k + _ROWS_PER_WRITE].tolist()
                fh.write("".join(",".join(map(repr, r)) + "\n" for r in rows))

        meta = {
            "file": path.name,
            "columns": dict(zip(names, units, strict=True)),
            "header": header[:-2],  # the description (the units and names are above)
        }
        side = path.with_name(f"{path.stem}.columns.json")
        return [
            _atomic(path, write),
            _atomic(side, lambda fh: fh.write(json.dumps(meta, indent=2) + "\n")),
        ]

    if isinstance(tr, Trajectory):
        arrays = {"t": tr.t, "quat": tr.quat, "omega_body": np.asarray(tr.omega)}
        if tr.momentum is not None:
            arrays["momentum_space"] = np.asarray(tr.momentum)
            arrays["energy"] = np.asarray(tr.energy)
    else:
        arrays = {"t": tr.t}
        arrays.update({name: np.asarray(ch.values) for name, ch in tr.channels().items()})
    for name, (values, _) in result.scenario.adapter.series(result.scenario, tr).items():
        key = "potential" if name == "V" else name
        arrays.setdefault(key, np.asarray(values))
    arrays["header"] = np.array("\n".join(header))
    # numpy's stub lets **kwds fill savez's allow_pickle: bool (a false positive)
    return [_atomic(path, lambda fh: np.savez(fh, **arrays), mode="b")]  # type: ignore[arg-type]


# ----------------------------------------------------------------------------- figures
def _figures(result: ScenarioResult, out: Path, notes: list[str]) -> list[Path]:
    try:
        import matplotlib  # noqa: F401 - optional dependency
        from matplotlib.figure import Figure
    except ImportError:
        notes.append("figures skipped: matplotlib is not installed (pip install 'poinsot[plot]')")
        return []
    files = []
    for spec in result.figures():
        # a Figure of its own (no pyplot): the caller's backend and figures are untouched
        fig = Figure(figsize=spec.size, layout="constrained")
        try:
            ax = fig.add_subplot(projection=spec.projection)
            spec.draw(ax)
        except Exception as exc:  # a figure must not sink the run
            notes.append(f"{spec.name} skipped: {type(exc).__name__}: {exc}")
            continue

        def save_png(fh: Any, f: Any = fig) -> None:
            f.savefig(fh, format="png", dpi=110)

        files.append(_atomic(out / spec.name, save_png, "b"))
    return files


def _report(
    result: ScenarioResult, summary: dict[str, Any], out: Path, notes: list[str]
) -> list[Path]:
    try:  # the kind says what to show (ScenarioKind.report); plotting draws it
        path = write_scenario_report(out / "report.html", result, summary)
    except ImportError as exc:  # the report needs only NumPy/SciPy: a broken install
        notes.append(f"report.html skipped: {exc}")
        return []
    return [path]


# ----------------------------------------------------------------------------- public
def _publish(stage: Path, out: Path, names: list[str]) -> list[Path]:
    """Move the complete outputs ``names`` from ``stage`` into ``out``.

    An empty ``out`` is replaced by the staging folder in one rename. Into a non-empty
    one (``--force``) the old ``summary.json`` goes first and the new one last, so that
    the folder never looks complete in between; outputs of an earlier run that this one
    did not rewrite are removed.
    """
    if not any(out.iterdir()):
        out.rmdir()
        os.rename(stage, out)
    else:
        (out / "summary.json").unlink(missing_ok=True)
        for name in names:
            if name != "summary.json":
                os.replace(stage / name, out / name)
        for name in OUTPUT_FILES:  # outputs of an earlier run that this one did not rewrite
            if name not in names:
                (out / name).unlink(missing_ok=True)
        os.replace(stage / "summary.json", out / "summary.json")
    return [out / name for name in names]


def _check_fmt(fmt: Any) -> None:
    if fmt not in ("csv", "npz"):
        raise InvalidInputError(f"Expected `format` (--format) to be 'csv' or 'npz', got {fmt!r}.")


def write_outputs(
    result: ScenarioResult,
    out: str | os.PathLike[str],
    *,
    fmt: str = "csv",
    report: bool = True,
    figures: bool = True,
    force: bool = False,
    progress: Progress | None = None,
) -> OutputFiles:
    """Write the outputs of a run into directory ``out``.

    Files: ``trajectory.csv`` or ``trajectory.npz`` (and ``reference.csv``/``.npz``
    with a reference method), the figures of the scenario's kind (``omega.png``,
    ``invariants.png``, and MacCullagh's and Poinsot's pictures for a free body),
    ``report.html`` and, last, ``summary.json``. The files are written into a
    staging folder beside ``out`` and moved into place once all are complete, so a
    failure while writing (a full disk) leaves ``out`` as it was. ``result`` is not
    modified: writing twice gives the same files.

    Returns
    -------
    OutputFiles
        The paths written, with the ``notes`` of the writing.

    Raises
    ------
    InvalidInputError
        ``fmt`` is not ``"csv"`` or ``"npz"``; ``out`` exists, is not empty and
        ``force`` is false.
    OSError
        A file cannot be written (``filename`` is ``out``; nothing of the run is kept).

    Notes
    -----
    **Convention:** see :data:`~poinsot.scenarios.CONVENTIONS` (written in the
    files' headers).
    """
    _expect(result, ScenarioResult, "result", "a ScenarioResult (from simulate_scenario)")
    _check_fmt(fmt)
    progress = progress or quiet_progress
    out = prepare_output_dir(out, force=force)
    summary = result.sections()  # a fresh dict: the result itself is never changed
    notes: list[str] = summary["run"]["notes"]
    # every file goes into a staging folder beside ``out`` (same file system), moved into
    # place once all are written: a run that fails while writing (a full disk) leaves
    # ``out`` as it was, so a retry needs no --force
    stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".partial", dir=out.parent))
    try:
        files = _write_trajectory(result, result.trajectory, stage / f"trajectory.{fmt}", fmt)
        if result.reference is not None:
            files += _write_trajectory(result, result.reference, stage / f"reference.{fmt}", fmt)
        progress(0.0, "writing the trajectory")
        if figures:
            progress(0.2, "figures")
            files += _figures(result, stage, notes)
        if report:
            progress(0.5, "report")
            files += _report(result, summary, stage, notes)
        else:
            notes.append("report.html not written (--no-report)")
        summary["run"]["files"] = [p.name for p in files] + ["summary.json"]
        files.append(
            _atomic(
                stage / "summary.json",
                lambda fh: json.dump(summary, fh, indent=2, allow_nan=False),
            )
        )
        files = _publish(stage, out, [p.name for p in files])
    except OSError as exc:  # named by the folder the user chose, not the staging file
        raise OSError(
            exc.errno,
            f"{exc.strerror or exc} (while writing {Path(exc.filename or '').name or 'a file'};"
            " nothing of this run was kept)",
            str(out),
        ) from exc
    finally:
        shutil.rmtree(stage, ignore_errors=True)
    progress(1.0, "done")
    return OutputFiles(files, notes)


def run_scenario(
    scenario: Scenario,
    out: str | os.PathLike[str],
    *,
    fmt: str = "csv",
    report: bool = True,
    force: bool = False,
    duration: float | None = None,
    progress: Progress | None = None,
    figures: bool = True,
    allow_large: bool = False,
) -> tuple[ScenarioResult, OutputFiles]:
    """Solve ``scenario`` and write its outputs into ``out`` (see :func:`write_outputs`).

    The limits (:func:`~poinsot.scenarios.estimate_cost`) and the output directory
    are checked before the computation, so a refused run costs nothing; a run that
    fails leaves no empty directory it created behind.

    Examples
    --------
    >>> import tempfile, pathlib, json
    >>> from poinsot.scenarios import demo_scenario, run_scenario
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "demo"
    >>> result, files = run_scenario(demo_scenario(), out, report=False, figures=False,
    ...                              duration=1.0)
    >>> sorted(p.name for p in files)  # doctest: +NORMALIZE_WHITESPACE
    ['reference.columns.json', 'reference.csv', 'summary.json', 'trajectory.columns.json',
     'trajectory.csv']
    """
    _expect(scenario, Scenario, "scenario", "a Scenario (from load_scenario/parse_scenario)")
    _check_fmt(fmt)
    check_cost(scenario, duration=duration, allow_large=allow_large)
    created = not Path(out).exists() if isinstance(out, str | os.PathLike) else False
    prepare_output_dir(out, force=force)
    progress = progress or quiet_progress
    try:
        result = simulate_scenario(
            scenario,
            duration=duration,
            progress=span(progress, 0.0, 0.8),
            allow_large=allow_large,
        )
        files = write_outputs(
            result,
            out,
            fmt=fmt,
            report=report,
            figures=figures,
            force=True,
            progress=span(progress, 0.8, 1.0),
        )
    except BaseException:
        if created and Path(out).is_dir() and not any(Path(out).iterdir()):
            Path(out).rmdir()  # leave nothing behind for a run that did not happen
        raise
    return result, files
