"""The ``poinsot`` command: thin wrappers around library functions.

Subcommands: ``run`` (a scenario file), ``demo`` (the embedded tennis-racket flip),
``check`` (validate a scenario and estimate its cost), ``convert`` (between rotation
representations), ``inertia`` (inertia tensor of a solid), ``ensemble`` (a Monte-Carlo
ensemble), ``verify`` (an engine against exact solutions). Exit codes: 0 success,
2 invalid input, a run refused by its limits or a diverging integration (a
one-line message with advice, no traceback), 1 a failure: a verdict of failure with
its outputs written (``verify`` FAIL; ``ensemble``: more than ``--max-failed`` of the
samples failed) or an unexpected failure (a bug; traceback with ``--debug``), 130
interrupted (Ctrl-C; ``ensemble`` says how many chunks are kept for ``--resume``). The
scenario format and every option are documented in ``docs/cli.md``.

Examples
--------
>>> from poinsot.cli import main
>>> main(["convert", "euler:ZXZ", "quat", "90", "0", "0", "--degrees"])
0.70710678 0 0 0.70710678
0
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import traceback
import warnings
from pathlib import Path
from typing import Any

__all__ = ["main", "build_parser"]

PROG = "poinsot"


class _Usage(Exception):
    """Invalid command-line input detected by the CLI itself (exit code 2)."""


# ------------------------------------------------------------------------- progress bar
class ProgressBar:
    """A progress bar on stderr, drawn only on a terminal, after ``delay`` seconds,
    and not when ``quiet``."""

    def __init__(self, *, quiet: bool = False, delay: float = 1.0, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = not quiet and bool(isatty and isatty())
        self.delay = delay
        self.start = time.monotonic()
        self.shown = False
        self._last = -1.0

    def __call__(self, fraction: float, stage: str) -> None:
        if not self.enabled or time.monotonic() - self.start < self.delay:
            return
        fraction = min(max(float(fraction), 0.0), 1.0)
        now = time.monotonic()
        if self.shown and now - self._last < 0.1 and fraction < 1.0:
            return
        self._last = now
        width = 30
        filled = int(round(width * fraction))
        bar = "#" * filled + "-" * (width - filled)
        elapsed = now - self.start
        self.stream.write(f"\r[{bar}] {100 * fraction:5.1f}% {elapsed:6.1f} s  {stage:<28.28}")
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()
            self.shown = False


# ------------------------------------------------------------------------- subcommands
def _default_out(name: str) -> Path:
    return Path("poinsot-out") / name


def _warn(message: str) -> None:
    print(f"{PROG}: warning: {message}", file=sys.stderr)


def _print_result(
    result: Any,
    out: Path,
    files: Any,
    *,
    quiet: bool,
    title: str,
    extra: Any = (),
) -> None:
    acc = result.summary["accuracy"]
    for w in acc["warnings"]:  # on stderr, also with --quiet: results may be poor
        _warn(f"accuracy: {w}")
    if acc["warnings"]:
        if acc["suggested_max_step"]:
            _warn(
                f"suggestion: set [simulation] max_step = {acc['suggested_max_step']:g} s "
                f"(the integration step is {acc['integration_step']:g} s; thresholds in "
                "docs/cli.md, 'Accuracy')"
            )
        elif acc["integration_step"] is not None:
            _warn("suggestion: a shorter `step` or `max_step` (docs/cli.md, 'Accuracy')")
        else:  # adaptive methods only: their tolerances, or a motion sensitive to its start
            _warn(
                "suggestion: tighter tolerances where the scenario sets them, or a shorter "
                "duration; methods that disagree while each keeps its integrals often mean a "
                "motion sensitive to its initial state (docs/cli.md, 'Accuracy')"
            )
    if quiet:
        return
    from .scenarios.describe import describe

    text = describe(result, title=title, notes=getattr(files, "notes", ()))
    lines = [
        ln
        for ln in text.splitlines()
        if not ln.startswith(("accuracy warning", "suggestion"))  # already on stderr
    ]
    if acc["warnings"]:
        lines.append(
            f"accuracy: {len(acc['warnings'])} warning(s), on stderr, in summary.json and "
            "report.html"
        )
    print("\n".join(lines))
    for line in extra:
        print(line)
    names = ", ".join(p.name for p in files)
    print(f"outputs: {out}{'/' if not str(out).endswith('/') else ''} ({names})")
    report = [p for p in files if p.name == "report.html"]
    if report:  # the one file to open: said last, as a path a browser takes
        print(f"report: {Path(report[0]).resolve().as_uri()}")


def _run_with_progress(scenario: Any, out: Path, args: argparse.Namespace) -> Any:
    """Run ``scenario`` into ``out`` (already prepared) with the options of ``run``/``demo``."""
    from .scenarios import run_scenario

    bar = ProgressBar(quiet=args.quiet)
    try:
        with _compile_note(quiet=args.quiet):
            return run_scenario(
                scenario,
                out,
                fmt=args.format,
                report=not args.no_report,
                figures=not args.no_figures,
                force=args.force,
                duration=args.duration,
                progress=bar,
                allow_large=args.allow_large,
            )
    finally:
        bar.close()


class _compile_note:
    """Say "compiling (first run only)" once when numba starts compiling a kernel (a cold
    cache: the first run after an install or an upgrade sits ~10-15 s in compilation);
    a cached kernel is loaded without a word. Listens to numba's ``numba:compile``
    event, which fires for a compilation and not for a load from the cache."""

    said = False

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self._stack: Any = None

    def __enter__(self) -> _compile_note:
        import contextlib

        from ._jit import NUMBA, mute_compile_notice

        # the CLI says it in its own words (or not at all, --quiet): not the library too
        self._stack = contextlib.ExitStack()
        self._stack.enter_context(mute_compile_notice())
        if self.quiet or _compile_note.said or not NUMBA:
            return self
        from numba.core import event

        class Listener(event.Listener):
            def on_start(self, ev: Any) -> None:
                if not _compile_note.said:
                    _compile_note.said = True
                    print(f"\r{PROG}: compiling (first run only) ...", file=sys.stderr, flush=True)

            def on_end(self, ev: Any) -> None:
                pass

        self._stack.enter_context(event.install_listener("numba:compile", Listener()))
        return self

    def __exit__(self, *exc: object) -> None:
        if self._stack is not None:
            self._stack.close()


def _refuse_large(scenario: Any, args: argparse.Namespace) -> None:
    """Refuse a run beyond the limits before anything is created (exit 2)."""
    from .scenarios.solve import check_cost

    check_cost(scenario, duration=args.duration, allow_large=args.allow_large)


def _cmd_run(args: argparse.Namespace) -> int:
    from .errors import IntegrationError
    from .scenarios import load_scenario

    scenario = load_scenario(args.scenario, allow_paths=args.allow_paths)
    _refuse_large(scenario, args)
    out = Path(args.out) if args.out else _default_out(scenario.name)
    # run_scenario checks the directory before any work and removes it again if it
    # made it and the run fails
    try:
        result, files = _run_with_progress(scenario, out, args)
    except IntegrationError as exc:
        exc.advice = _advice(scenario)  # type: ignore[attr-defined]
        raise
    _print_result(result, out, files, quiet=args.quiet, title=f"{PROG} run")
    return 0


def _advice(scenario: Any) -> str:
    """What to try after a failed integration, among the methods this kind has."""
    methods = list(getattr(scenario.adapter, "methods", ()))
    used = scenario.simulation.method
    if "adaptive" in methods:
        return (
            'set a shorter [simulation] max_step, or method = "adaptive" '
            "(docs/cli.md, 'Accuracy')."
        )
    others = ", ".join(f'"{m}"' for m in methods if m != used)
    if scenario.kind == "lagrangian":
        return (
            f"a smaller [lagrangian] rtol, or another method of this kind ({others}; a "
            'stiff problem wants "Radau" or "BDF") (docs/cli.md, \'Accuracy\').'
        )
    return (
        f"set a shorter [simulation] max_step, or another method ({others}) "
        "(docs/cli.md, 'Accuracy')."
    )


def _cmd_demo(args: argparse.Namespace) -> int:
    from .scenarios import demo_scenario

    scenario = demo_scenario()
    _refuse_large(scenario, args)
    if args.out:
        out = Path(args.out)
    else:
        # the default directory is never overwritten: a new one is numbered instead
        out = _default_out(scenario.name)
        k = 1
        while not args.force and out.exists() and (not out.is_dir() or any(out.iterdir())):
            k += 1
            out = _default_out(f"{scenario.name}-{k}")
    result, files = _run_with_progress(scenario, out, args)
    from .rotations.rotation import Rotation

    a = Rotation.from_axis_angle([1.0, 0.0, 0.0], 90.0, degrees=True)
    b = Rotation.from_axis_angle([0.0, 1.0, 0.0], 90.0, degrees=True)
    rows = "; ".join(" ".join(_nums(row)) for row in (b * a).as_matrix())
    tour = (
        "composition (docs/theory.md §4): A = 90 deg about x, then B = 90 deg about y, both about "
        f"fixed axes: B * A = C = [{rows}]",
    )
    _print_result(result, out, files, quiet=args.quiet, title=f"{PROG} demo", extra=tour)
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    from .scenarios import describe_scenario, estimate_cost, load_scenario

    scenario = load_scenario(args.scenario, allow_paths=args.allow_paths)
    cost = estimate_cost(scenario, duration=args.duration)
    problems = cost.problems(allow_large=args.allow_large)
    if problems:
        raise _Usage(
            f"{args.scenario}: valid, but `poinsot run` would refuse it: "
            + "; ".join(problems)
            + "."
        )
    if not args.quiet:
        print(f"ok: {args.scenario}: {describe_scenario(scenario)}", flush=True)
        # what `run` does: both methods (an adaptive one timed on a short piece) and
        # the outputs
        with _compile_note(quiet=False):
            cost = estimate_cost(scenario, duration=args.duration, measure=True, outputs=True)
        print(f"{cost.describe()} (rough; limits in docs/cli.md)")
    return 0


_REPRS = {
    "quat": 4,
    "quat:wxyz": 4,
    "quat:xyzw": 4,
    "matrix": 9,
    "rotvec": 3,
    "axis-angle": 4,
    "gibbs": 3,
    "mrp": 3,
}


def _repr_size(name: str, role: str) -> int:
    if name.lower().startswith("euler:"):
        return 3
    if name not in _REPRS:
        raise _Usage(
            f"unknown {role} representation {name!r}: expected one of quat (scalar first "
            "w,x,y,z), quat:xyzw (scalar last), matrix (9 values, row by row), rotvec, "
            "axis-angle (x y z angle), euler:SEQ (e.g. euler:ZXZ intrinsic, euler:zxz "
            "extrinsic, euler:euler, euler:krylov), gibbs, mrp."
        )
    return _REPRS[name]


def _from(name: str, v: Any, degrees: bool, tolerance: float) -> Any:
    from .rotations.rotation import Rotation

    if name.lower().startswith("euler:"):
        return Rotation.from_euler(name[6:], v, degrees=degrees)
    if name in ("quat", "quat:wxyz"):
        return Rotation.from_quat(v, scalar_first=True)
    if name == "quat:xyzw":
        return Rotation.from_quat(v, scalar_first=False)
    if name == "matrix":
        from .scenarios.io import rotation_from_matrix

        return rotation_from_matrix(v.reshape(3, 3), tolerance, where="convert", knob="--tolerance")
    if name == "rotvec":
        return Rotation.from_rotvec(v, degrees=degrees)
    if name == "axis-angle":
        return Rotation.from_axis_angle(v[:3], v[3], degrees=degrees)
    if name == "gibbs":
        return Rotation.from_gibbs(v)
    return Rotation.from_mrp(v)


def _to(name: str, r: Any, degrees: bool) -> Any:
    import numpy as np

    if name.lower().startswith("euler:"):
        return r.as_euler(name[6:], degrees=degrees)
    if name in ("quat", "quat:wxyz"):
        return _canonical(r.as_quat(scalar_first=True), 0)
    if name == "quat:xyzw":
        return _canonical(r.as_quat(scalar_first=False), 3)
    if name == "matrix":
        return r.as_matrix()
    if name == "rotvec":
        return r.as_rotvec(degrees=degrees)
    if name == "axis-angle":
        axis, angle = r.as_axis_angle(degrees=degrees)
        return np.append(axis, angle)
    if name == "gibbs":
        return r.as_gibbs()
    return r.as_mrp()


def _canonical(q: Any, scalar: int) -> Any:
    """The sign of ``q`` (``q`` and ``-q`` are the same rotation) with the scalar part
    ``w >= 0``; if ``w = 0`` (to round-off, as printed), the first non-zero vector
    component positive."""
    from .scenarios.describe import clean

    q = clean(q, 1.0)
    order = [scalar] + [k for k in range(4) if k != scalar]
    for k in order:
        if q[k] != 0.0:
            return -q if q[k] < 0 else q
    return q


def _num(x: float) -> str:
    s = f"{x:.15g}"
    return "0" if s in ("0", "-0") else s


def _nums(values: Any, scale: float | None = None) -> list[str]:
    """15 significant digits, round-off noise (below 1e-12 of the largest) as 0."""
    from .scenarios.describe import clean

    return [_num(x) for x in clean(values, scale)]


#: Library argument names -> the names a user of `convert` sees.
_CONVERT_NAMES = {
    "seq": "the Euler sequence (euler:SEQ)",
    "sequence": "the Euler sequence (euler:SEQ)",
    "angles": "the angles (VALUES)",
    "quat": "the quaternion (VALUES)",
    "rotvec": "the rotation vector (VALUES)",
    "axis": "the axis (first 3 VALUES)",
    "angle": "the angle (last VALUE)",
    "gibbs": "the Gibbs vector (VALUES)",
    "mrp": "the MRP vector (VALUES)",
}


def _user_names(message: str, names: dict[str, str]) -> str:
    """Replace the library's argument names (`seq`) by what the user typed."""
    for internal, user in names.items():
        message = message.replace(f"`{internal}`", user)
    return message


def _cmd_convert(args: argparse.Namespace) -> int:
    import numpy as np

    from .errors import PoinsotError

    n = _repr_size(args.source, "source")
    _repr_size(args.target, "target")
    values = []
    for s in args.values:
        try:
            values.append(float(s))
        except ValueError:
            raise _Usage(f"expected numbers as VALUES, found {s!r}.") from None
    if len(values) != n:
        raise _Usage(
            f"{args.source} takes {n} values, found {len(values)}: {' '.join(args.values)}."
        )
    # Values so large that the conversion overflows must give a clear error, not a
    # NumPy warning followed by "nan" or a zero quaternion.
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            r = _from(args.source, np.array(values), args.degrees, args.tolerance)
        except PoinsotError as exc:
            raise _Usage(_user_names(str(exc), _CONVERT_NAMES)) from None
        q = np.asarray(r.as_quat(), dtype=float)
        if not (np.all(np.isfinite(q)) and abs(float(q @ q) - 1.0) < 1e-6):
            raise _Usage(
                f"the {args.source} values {' '.join(args.values)} are out of the range "
                "that can be converted in double precision."
            )
        out = np.asarray(_to(args.target, r, args.degrees))
    if np.any(np.isnan(out)):
        raise _Usage(f"the conversion to {args.target} overflowed for these values.")
    if out.shape == (3, 3):
        for row in out:
            print(" ".join(_nums(row, 1.0)))
    else:
        # angles: noise relative to the largest value; other representations: to 1
        print(" ".join(_nums(out, None if args.degrees else max(1.0, np.max(np.abs(out))))))
    return 0


def _cmd_inertia(args: argparse.Namespace) -> int:
    import numpy as np

    from .mass import principal_axes, solids
    from .scenarios.io import SHAPES

    names = SHAPES[args.shape]
    if args.dims is None or len(args.dims) != len(names):
        found = "none" if args.dims is None else f"{len(args.dims)}"
        raise _Usage(
            f"a {args.shape} takes {len(names)} dimension(s) with --dims "
            f"({', '.join(names)}; m), found {found}."
        )
    kwargs = {}
    if args.hollow:
        if args.shape not in ("sphere", "cylinder"):
            raise _Usage("--hollow applies to a sphere or a cylinder only.")
        kwargs["hollow"] = True
    import inspect

    from .errors import PoinsotError

    fn = getattr(solids, args.shape)
    params = [p for p in inspect.signature(fn).parameters if p not in ("mass", "hollow")]
    names_map = {"mass": "--mass"}
    for k, (p, what) in enumerate(zip(params, names, strict=False)):
        names_map[p] = f"--dims value {k + 1} ({what})"
    try:
        j = fn(args.mass, *args.dims, **kwargs)
    except PoinsotError as exc:
        raise _Usage(_user_names(str(exc), names_map)) from None
    moments, axes = principal_axes(j)
    m = axes.as_matrix()
    with np.printoptions(precision=10, suppress=True):
        kind = ("hollow " if args.hollow else "") + args.shape
        print(
            f"{kind}: mass {_num(args.mass)} kg, dims "
            f"{' x '.join(_num(d) for d in args.dims)} m ({', '.join(names)})"
        )
        print("inertia tensor about the centre of mass, body axes (kg m^2):")
        scale = float(np.max(np.abs(j)))
        for row in j:
            print("  " + "  ".join(f"{x:>20}" for x in _nums(row, scale)))
        print("principal moments A <= B <= C (kg m^2): " + "  ".join(_nums(moments, scale)))
        print("principal axes (columns, in body axes):")
        for row in m:
            print("  " + "  ".join(f"{x:>6}" for x in _nums(row, 1.0)))
    return 0


# ------------------------------------------------------------------------- parser
_RUN_EPILOG = """\
example:
  poinsot run examples/tennis_racket.toml --out out/racket --format npz
  poinsot run examples/satellite_torque.toml --duration 5 --no-report --force

Writes trajectory.csv (or .npz), summary.json, PNG figures and report.html into
--out (default ./poinsot-out/<scenario name>). An existing, non-empty output
directory is only overwritten with --force. Scenario format: docs/cli.md.

The integration step of a fixed-step method is the output spacing, unless
[simulation] max_step is shorter. A run beyond the limits (5000000 output
samples; 2 GiB of memory or 5e7 integration steps without --allow-large) is
refused before any work; `poinsot check` prints the estimate. When a conserved
quantity drifts by more than 1e-6 (relative), or the method and the reference
differ by more than 1e-2 rad in attitude or by more than 1e-2 of its scale in any
other state quantity (omega, a particle's position and velocity, each coordinate
and rate), a warning is printed with a suggestion.
"""
_DEMO_EPILOG = """\
example:
  poinsot demo
  poinsot demo --out /tmp/demo --force

Runs the embedded tennis-racket flip (spin about the intermediate axis) twice,
with the exact solution and with a numerical integrator, and writes the same
outputs as `poinsot run`. Without --out a fresh ./poinsot-out/tennis-racket-flip[-N]
directory is used, so the demo never overwrites earlier results.
"""
_CHECK_EPILOG = """\
example:
  poinsot check examples/symmetric_top.toml

Exit code 0 if the file is a valid scenario, 2 with a message naming the file,
the key and its line otherwise.
"""
_CONVERT_EPILOG = """\
representations:
  quat        scalar-first unit quaternion w x y z (Hamilton), also quat:xyzw
  matrix      9 entries of the rotation matrix, row by row
  rotvec      rotation vector (axis times angle)
  axis-angle  x y z angle
  euler:SEQ   three angles of sequence SEQ: upper case intrinsic (euler:ZXZ),
              lower case extrinsic (euler:zxz), presets euler:euler (= ZXZ) and
              euler:krylov (= ZXY)
  gibbs       Gibbs/Rodrigues vector e tan(f/2)
  mrp         modified Rodrigues parameters e tan(f/4)
A rotation maps body components to space components (v_space = R v_body).
--degrees applies to the angles read and printed (euler, rotvec, axis-angle).

examples:
  poinsot convert euler:ZXZ quat 30 45 60 --degrees
  poinsot convert quat matrix 0.7071 0.7071 0 0
  poinsot convert rotvec axis-angle 0 0 90 --degrees
"""
_INERTIA_EPILOG = """\
dimensions (m):
  box        length x, width y, height z      sphere     radius
  cylinder   radius, height (axis z)          cone       base radius, height (axis z)
  ellipsoid  semi-axes a, b, c                rod        length (along z)
  disc       radius (in the xy plane)         ring       radius (in the xy plane)

example:
  poinsot inertia box --mass 2 --dims 0.3 0.2 0.1
  poinsot inertia cylinder --mass 1 --dims 0.05 0.4 --hollow
"""


class _Formatter(argparse.RawDescriptionHelpFormatter):
    pass


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``poinsot`` command."""
    from . import __version__

    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Kinematics and dynamics of rigid bodies, built on quaternions.",
        epilog="example: poinsot demo    (run `poinsot COMMAND --help` for each command)",
        formatter_class=_Formatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show the full traceback of unexpected errors"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def command(name: str, **kwargs: Any) -> argparse.ArgumentParser:
        # every subcommand also accepts --debug after its own arguments (hidden)
        p = sub.add_parser(name, formatter_class=_Formatter, **kwargs)
        p.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS
        )
        return p

    def common_run(p: argparse.ArgumentParser) -> None:
        p.add_argument(
            "--out", metavar="DIR", help="output directory (default ./poinsot-out/<scenario name>)"
        )
        p.add_argument(
            "--format",
            choices=("csv", "npz"),
            default="csv",
            help="trajectory file format (default csv)",
        )
        p.add_argument("--no-report", action="store_true", help="do not write report.html")
        p.add_argument("--no-figures", action="store_true", help="do not write the PNG figures")
        p.add_argument(
            "--quiet",
            action="store_true",
            help="print nothing on success and hide the progress bar",
        )
        p.add_argument(
            "--force",
            action="store_true",
            help="overwrite the files of an existing output directory",
        )
        p.add_argument(
            "--duration", type=float, metavar="SECONDS", help="override [simulation] duration"
        )
        allow_large(p)

    def allow_paths(p: argparse.ArgumentParser) -> None:
        p.add_argument(
            "--allow-paths",
            action="store_true",
            help="let the scenario read a mesh file outside its own directory",
        )

    def allow_large(p: argparse.ArgumentParser) -> None:
        p.add_argument(
            "--allow-large",
            action="store_true",
            help="run even if the estimated memory (> 2 GiB) or integration steps (> 5e7) "
            "exceed the limits (the limit of 5000000 output samples always holds)",
        )

    p = command(
        "run",
        help="run a scenario file",
        epilog=_RUN_EPILOG,
        description="Run a TOML scenario and write its outputs.",
    )
    p.add_argument("scenario", metavar="SCENARIO.toml")
    common_run(p)
    allow_paths(p)
    p.set_defaults(func=_cmd_run)

    p = command(
        "demo",
        help="run the embedded tennis-racket flip",
        epilog=_DEMO_EPILOG,
        description="Run the embedded demo scenario (the tennis-racket flip).",
    )
    common_run(p)
    p.set_defaults(func=_cmd_demo)

    p = command(
        "check",
        help="validate a scenario file",
        epilog=_CHECK_EPILOG,
        description="Validate a TOML scenario file without running it.",
    )
    p.add_argument("scenario", metavar="SCENARIO.toml")
    p.add_argument("--quiet", action="store_true", help="print nothing when valid")
    p.add_argument("--duration", type=float, metavar="SECONDS", help="check with this duration (s)")
    allow_large(p)
    allow_paths(p)
    p.set_defaults(func=_cmd_check)

    p = command(
        "convert",
        help="convert a rotation between representations",
        epilog=_CONVERT_EPILOG,
        description="Convert one rotation from one representation to another.",
    )
    p.add_argument("source", metavar="FROM", help="input representation")
    p.add_argument("target", metavar="TO", help="output representation")
    p.add_argument("values", metavar="VALUES", nargs="+", help="the input numbers")
    p.add_argument("--degrees", action="store_true", help="angles in degrees (in and out)")
    p.add_argument(
        "--tolerance",
        type=float,
        default=1e-6,
        metavar="TOL",
        help="largest max|A^T A - E| of a `matrix` input (default 1e-6); a matrix that "
        "is not orthogonal to round-off is projected onto the nearest rotation, with a warning",
    )
    p.set_defaults(func=_cmd_convert)

    from .scenarios.io import SHAPES

    p = command(
        "inertia",
        help="inertia tensor and principal axes of a solid",
        epilog=_INERTIA_EPILOG,
        description="Inertia tensor of a uniform solid about its centre of "
        "mass, its principal moments and axes.",
    )
    p.add_argument(
        "shape", choices=tuple(SHAPES), metavar="SHAPE", help="one of " + ", ".join(SHAPES)
    )
    p.add_argument("--mass", type=float, required=True, metavar="M", help="mass (kg)")
    p.add_argument("--dims", type=float, nargs="+", metavar="D", help="dimensions (m)")
    p.add_argument("--hollow", action="store_true", help="hollow sphere / thin-walled cylinder")
    p.set_defaults(func=_cmd_inertia)

    p = command(
        "ensemble",
        help="Monte-Carlo ensemble of a dispersed scenario (Dask)",
        epilog=_ENSEMBLE_EPILOG,
        description="Run N dispersed samples of a rigid-body scenario with [dispersion] and "
        "[[metric]] tables, in chunks on a local or existing Dask cluster.",
    )
    p.add_argument("scenario", metavar="SCENARIO.toml")
    p.add_argument("--samples", type=int, required=True, metavar="N", help="number of samples")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--chunk-size",
        type=int,
        default=1000,
        metavar="M",
        help="samples per chunk and Parquet file (default 1000)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="an existing Dask scheduler (tcp://host:port); default: a local cluster",
    )
    p.add_argument(
        "--workers",
        type=int,
        metavar="K",
        help="local worker processes (default: one per core; 0: in this process)",
    )
    p.add_argument("--seed", type=int, default=0, metavar="S", help="root seed (default 0)")
    p.add_argument(
        "--resume",
        action="store_true",
        help="complete an interrupted run in DIR (only missing chunks are computed)",
    )
    p.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="how long to wait for --scheduler to answer (default 10)",
    )
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    allow_paths(p)
    p.add_argument(
        "--max-failed",
        type=float,
        default=0.5,
        metavar="FRACTION",
        help="exit 1 when more than this fraction of the samples fail (default 0.5)",
    )
    p.add_argument(
        "--allow-large",
        action="store_true",
        help="run even if the estimated memory or disk (> 2 GiB) or time (> 1 h) exceed "
        "the limits (at most 1e8 samples, and the disk that is free, always hold)",
    )
    p.set_defaults(func=_cmd_ensemble)

    p = command(
        "verify",
        help="check a physics engine against exact solutions",
        epilog=_VERIFY_EPILOG,
        description="Run the reference cases (exact free-body, Lagrange-top, Kepler and "
        "Foucault motions) in an engine and score its states against the exact ones, or "
        "export the cases to files.",
    )
    p.add_argument("engine", choices=("scipy", "poinsot", "mujoco", "file", "export"),
                   metavar="ENGINE", help="scipy, poinsot, mujoco, file or export")  # fmt: skip
    p.add_argument("path", nargs="?", metavar="DIR",
                   help="the directory of the files (file) or to write (export)")  # fmt: skip
    p.add_argument("--cases", metavar="NAMES", help="case names or groups, comma separated "
                   "(free-body, heavy-top, orbit, frame); default all")  # fmt: skip
    p.add_argument("--method", help="solve_ivp method (scipy), integrator (poinsot), or "
                   "Euler, RK4, implicitfast (mujoco)")  # fmt: skip
    p.add_argument("--step", type=float, metavar="SECONDS",
                   help="step (poinsot's fixed-step methods) or timestep (mujoco)")  # fmt: skip
    p.add_argument("--rtol", type=float, help="tolerance (scipy, poinsot's adaptive methods)")
    p.add_argument(
        "--order", type=int, choices=(2, 4, 6), help="order (poinsot midpoint/splitting)"
    )
    p.add_argument("--quat-order", choices=("wxyz", "xyzw"),
                   help="file: order of the four quaternion columns in the file, whatever "
                   "their names (default: qw, qx, qy, qz by name; q0..q3 scalar "
                   "first)")  # fmt: skip
    p.add_argument("--omega-frame", choices=("body", "space"), help="file: axes of w")
    p.add_argument("--degrees", action="store_true", help="file: w in deg/s")
    p.add_argument("--sweep", nargs="?", const="", metavar="VALUES",
                   help="work-precision sweep over rtol/step/timestep (comma-separated "
                   "values; default a standard set)")  # fmt: skip
    p.add_argument("--format", choices=("csv", "parquet"), default="csv", help="export format")
    p.add_argument("--out", metavar="DIR", help="write verify.json, verify.html and case pages")
    p.add_argument("--require-all", action="store_true",
                   help="a skipped case (one the engine does not model, e.g. an orbit in "
                   "MuJoCo) fails the verdict: every selected case must be scored")  # fmt: skip
    p.add_argument("--allow-missing", action="store_true",
                   help="file: a case without a file does not fail the verdict (it is listed "
                   "as missing; a run that scores no case still fails)")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="print only the verdict line")
    p.set_defaults(func=_cmd_verify)
    return parser


_VERIFY_EPILOG = """examples:
  poinsot verify scipy --method DOP853 --rtol 1e-12
  poinsot verify mujoco --method RK4 --step 0.001 --cases free-body
  poinsot verify export cases/          (then, after your engine wrote cases/*.csv)
  poinsot verify file cases/ --quat-order xyzw

Verdict: PASS when at least one case was scored and every scored case is within its
thresholds; a missing case (no file) fails unless --allow-missing; a skipped case
(outside what the engine models) is listed and fails only with --require-all.
Exit codes: 0 PASS; 1 FAIL (a case over a threshold, a missing case, no case scored;
the outputs of --out are written); 2 bad input (options, unreadable or malformed
files, files in other conventions, an engine that models none of the selected
cases). Cases, metrics, thresholds and conventions: docs/verify.md.
"""


def _cmd_verify(args: argparse.Namespace) -> int:
    from .verify import cases, export, make
    from .verify.suite import SWEEPS, check, sweep, write

    if args.engine == "export":
        if not args.path:
            raise _Usage("verify export needs the directory to write: poinsot verify export DIR")
        files = export(args.path, args.cases, format=args.format)
        if not args.quiet:
            print(f"wrote {len(files)} files to {args.path} (docs/verify.md, 'Exported cases')")
        return 0
    if args.engine == "file" and not args.path:
        raise _Usage(
            "verify file needs the directory of the engine's files: poinsot verify file DIR"
        )
    opts: dict[str, Any] = {}
    if args.engine == "scipy":
        opts = {"method": args.method, "rtol": args.rtol}
    elif args.engine == "poinsot":
        opts = {"method": args.method, "step": args.step, "rtol": args.rtol, "order": args.order}
    elif args.engine == "mujoco":
        opts = {"integrator": args.method, "timestep": args.step}
    else:
        opts = {"directory": args.path, "quat_order": args.quat_order,
                "omega_frame": args.omega_frame, "degrees": args.degrees or None}  # fmt: skip
    engine = make(args.engine, **opts)

    def each(case: Any, res: Any) -> None:
        if not args.quiet:
            print(f"  {case.name}: {res.status}" + (f" ({res.reason})" if res.reason else ""),
                  file=sys.stderr, flush=True)  # fmt: skip

    selected = cases(args.cases)
    reasons = {c.name: engine.skip_reason(c) for c in selected}
    if all(reasons.values()):
        why = "; ".join(dict.fromkeys(str(r) for r in reasons.values()))
        raise _Usage(
            f"the {args.engine} engine models none of the selected cases "
            f"({', '.join(reasons)}): {why}; select others with --cases (docs/verify.md)"
        )
    verdict = check(engine, args.cases, progress=each, require_all=args.require_all,
                    allow_missing=args.allow_missing)  # fmt: skip
    if args.sweep is not None:
        if args.engine not in SWEEPS:
            raise _Usage(f"--sweep: the {args.engine} engine has no setting to sweep")
        try:
            values = [float(v) for v in args.sweep.split(",") if v.strip()] or None
        except ValueError:
            raise _Usage(f"--sweep: expected comma-separated numbers, got {args.sweep!r}") from None
        key = SWEEPS[args.engine][0]
        base = {k: v for k, v in opts.items() if k != key}
        verdict.sweep = sweep(args.engine, values, args.cases, **base)
    if not args.quiet:
        print(f"poinsot verify: {engine.label}")
        print(verdict.table())
        if verdict.sweep:
            print("work-precision (setting, value, case, error, work):")
            for row in verdict.sweep:
                print(f"  {row['setting']}={row['value']:g}  {row['case']}  {row['error']:.2e} "
                      f"{row['units']}  {row['work']}")  # fmt: skip
    if args.out:
        files = write(verdict, args.out)
        if not args.quiet:
            print(f"wrote {args.out}/verify.json, {args.out}/verify.html and {len(files) - 2} "
                  "case pages in cases/")  # fmt: skip
    print(f"verdict: {verdict.summary()}")
    return 0 if verdict.passed else 1


_ENSEMBLE_EPILOG = """example:
  poinsot ensemble examples/tennis_racket_ensemble.toml --samples 10000 --out flips

writes DIR/chunks/chunk-NNNNNN.parquet (one per chunk, a Parquet dataset),
DIR/ensemble.json (what defines the samples), DIR/summary.json (statistics of
every metric) and DIR/report.html. The result does not depend on --workers,
--chunk order, retries or --resume. Failed samples are counted and listed by
reason (N x reason) on stderr. Exit codes: 0 done (failures within
--max-failed: a warning); 1 more than --max-failed of the samples failed (the
outputs are written), or a bug; 2 bad input or an unreachable scheduler; 130
interrupted (Ctrl-C): the chunks written so far stay valid, and the same
command with --resume completes the run.
"""


def _cmd_ensemble(args: argparse.Namespace) -> int:
    from .ensemble import EnsembleInterrupted, run_scenario_ensemble

    client = None
    workers = args.workers
    if workers is not None and workers < 0:
        raise _Usage(f"--workers must be >= 0, got {workers}")
    if workers == 0:
        if args.scheduler:
            raise _Usage("--workers 0 (in this process) and --scheduler exclude each other")
        client, workers = "serial", None

    if not 0.0 <= args.max_failed <= 1.0:
        raise _Usage(f"--max-failed must be a fraction in [0, 1], got {args.max_failed}")
    tty = sys.stderr.isatty()

    def on_chunk(done: int, total: int) -> None:
        if args.quiet:
            return
        if tty:  # one line redrawn in place
            print(f"\rchunks {done}/{total}", end="", file=sys.stderr, flush=True)
        else:  # a log: whole lines
            print(f"chunks {done}/{total}", file=sys.stderr, flush=True)

    try:
        res = run_scenario_ensemble(
            args.scenario,
            args.samples,
            args.out,
            chunk_size=args.chunk_size,
            scheduler=args.scheduler,
            workers=workers,
            seed=args.seed,
            resume=args.resume,
            client=client,
            timeout=args.timeout,
            on_chunk=on_chunk,
            allow_paths=args.allow_paths,
            allow_large=args.allow_large,
        )
    except EnsembleInterrupted as exc:  # Ctrl-C: the chunks written so far stay valid
        import atexit
        import gc

        # the run is stopped within ~0.1 s, but the interpreter's last garbage
        # collections over Numba's and Dask's objects took 0.6-1 s more before the
        # prompt came back; the process ends, so they are skipped
        atexit.register(gc.freeze)
        if not args.quiet and tty:
            print(file=sys.stderr)
        print(
            f"{PROG}: interrupted: {exc.kept} of {exc.total} chunks kept in {args.out}; run "
            "the same command with --resume to complete it",
            file=sys.stderr,
        )
        return 130
    s = res.summary
    failed = int(s["failures"]) / max(int(s["samples"]), 1)
    if not args.quiet and tty:
        print(file=sys.stderr)  # end the 'chunks k/n' line
    reasons = _failure_reasons(s.get("failure_reasons") or {})
    if failed > args.max_failed:
        # the outputs are written (the failures and their reasons are data), but a run in
        # which most samples fail is not a success
        _error(
            f"{s['failures']} of {s['samples']} samples failed ({100 * failed:.3g} %, more "
            f"than --max-failed {args.max_failed:g}); outputs in {res.out}"
            + ("; reasons:\n" + reasons if reasons else "")
        )
        return 1
    if s["failures"]:  # within --max-failed: a success, but never a silent one
        print(
            f"{PROG}: warning: {s['failures']} of {s['samples']} samples failed "
            f"({100 * failed:.3g} %, within --max-failed {args.max_failed:g}; their metrics "
            f"are NaN, their reasons in {res.out}/summary.json); reasons:\n{reasons}",
            file=sys.stderr,
        )
    if not args.quiet:
        print(f"{s['samples']} samples, {s['failures']} failed; outputs in {res.out}")
        for name, m in s["metrics"].items():
            q = m["quantiles"]
            label = name if m["unit"] in ("", "1") else f"{name} ({m['unit']})"
            print(
                f"  {label}: mean {m['mean']:.6g}, median {q['50%']:.6g}, "
                f"5%-95% [{q['5%']:.6g}, {q['95%']:.6g}], never {m['never']}"
            )
    return 0


def _failure_reasons(reasons: dict[str, int], most: int = 5) -> str:
    """``summary["failure_reasons"]`` (reason -> count) as indented lines
    ``  N x reason``, the most frequent first, at most ``most`` of them."""
    ranked = sorted(reasons.items(), key=lambda kv: (-kv[1], kv[0]))
    lines = [f"  {n} x {r if len(r) <= 200 else r[:197] + '...'}" for r, n in ranked[:most]]
    if len(ranked) > most:
        rest = sum(n for _, n in ranked[most:])
        lines.append(f"  {rest} x {len(ranked) - most} other reasons (summary.json)")
    return "\n".join(lines)


def _error(message: str) -> None:
    message = str(message).strip()
    print(f"{PROG}: error: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """Run the ``poinsot`` command with ``argv`` (default ``sys.argv[1:]``).

    Returns the exit code: 0 success, 2 invalid input (also a run refused by its
    limits, or an integration that diverged), 1 a failure: a verdict of failure
    (``verify`` FAIL, ``ensemble`` over ``--max-failed``) or an unexpected one (a bug),
    130 interrupted (Ctrl-C).
    """
    from .errors import IntegrationError, InvalidInputError, InvalidTypeError, PoinsotWarning

    argv = sys.argv[1:] if argv is None else list(argv)
    debug = "--debug" in argv
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help, --version, or a usage error (code 2)
            return int(exc.code or 0) if not isinstance(exc.code, str) else 2
        debug = debug or getattr(args, "debug", False)
        seen: set[str] = set()
        original = warnings.showwarning

        def show(
            message: Any,
            category: type[Warning],
            filename: str,
            lineno: int,
            file: Any = None,
            line: str | None = None,
        ) -> None:
            if issubclass(category, PoinsotWarning):
                text = f"{PROG}: warning: {message}"
                if text not in seen:  # the same warning once, however often it is issued
                    seen.add(text)
                    print(text, file=sys.stderr)
            else:
                original(message, category, filename, lineno, file, line)

        with warnings.catch_warnings():
            warnings.simplefilter("always", PoinsotWarning)
            warnings.showwarning = show
            return args.func(args)
    except (_Usage, InvalidInputError, InvalidTypeError) as exc:
        if debug:
            traceback.print_exc()
        _error(str(exc))
        return 2
    except IntegrationError as exc:  # a valid input the chosen method cannot handle
        if debug:
            traceback.print_exc()
        advice = getattr(exc, "advice", None) or (
            'set a shorter [simulation] max_step, or method = "adaptive" '
            "(docs/cli.md, 'Accuracy')."
        )
        _error(f"the integration failed: {exc} Advice: {advice}")
        return 2
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `poinsot convert ... | head` (an OSError: caught first)
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - no flush error at exit
        except OSError:
            pass
        return 0
    except OSError as exc:  # an output that cannot be written (permissions, disk full...)
        if debug:
            traceback.print_exc()
        where = f": {exc.filename}" if getattr(exc, "filename", None) else ""
        _error(f"cannot write the outputs{where}: {exc.strerror or exc}.")
        return 2
    except Exception as exc:
        if debug:
            traceback.print_exc()
        _error(
            f"unexpected failure: {type(exc).__name__}: {exc}"
            + ("" if debug else " (run with --debug for the traceback)")
        )
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
