"""``poinsot verify``: an engine against the exact solutions of the reference cases, or
the cases exported to files."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..verify import cases, export, make
from ..verify.scorecard import ENGINES, Scorecard, scorecard
from ..verify.suite import SWEEPS, check, sweep, write
from ._common import _Usage

DESCRIPTION = (
    "Run the reference cases (exact free-body, Lagrange-top, Kepler, Foucault and "
    "thrown-box motions) in an engine and score its states against the exact ones, or "
    "export the cases to files."
)
EPILOG = """examples:
  poinsot verify scipy --method DOP853 --rtol 1e-12
  poinsot verify mujoco --method RK4 --step 0.001 --cases free-body
  poinsot verify drake --method runge_kutta3 --rtol 1e-12 --cases free-body
  poinsot verify pybullet --step 0.0001 --cases free-body
  poinsot verify basilisk --method RK4 --step 0.001 --cases free-body
  poinsot verify export cases/          (then, after your engine wrote cases/*.csv)
  poinsot verify file cases/ --quat-order xyzw
  poinsot verify scorecard --engines mujoco,drake --quick --out scorecard/
  poinsot verify scorecard --from-json docs/verify/scorecard/scorecard.json --out DIR

Verdict: PASS when at least one case was scored and every scored case is within its
thresholds; a missing case (no file) fails unless --allow-missing; a skipped case
(outside what the engine models) is listed and fails only with --require-all.
Exit codes: 0 PASS; 1 FAIL (a case over a threshold, a missing case, no case scored;
the outputs of --out are written); 2 bad input (options, unreadable or malformed
files, files in other conventions, an engine that models none of the selected
cases). Cases, metrics, thresholds and conventions: docs/verify.md.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("engine", choices=("scipy", "poinsot", "mujoco", "pybullet", "drake",
                   "basilisk", "file", "export", "scorecard"), metavar="ENGINE",
                   help="scipy, poinsot, mujoco, pybullet, drake, basilisk, file, export, or "
                   "scorecard "
                   "(every installed engine's integrators over a sweep)")  # fmt: skip
    p.add_argument("path", nargs="?", metavar="DIR",
                   help="the directory of the files (file) or to write (export)")  # fmt: skip
    p.add_argument("--cases", metavar="NAMES", help="case names or groups, comma separated "
                   "(free-body, heavy-top, kovalevskaya, body-torque, gyrostat, gravity-gradient, "
                   "orbit, frame, free-flight); default all")  # fmt: skip
    p.add_argument("--method", help="solve_ivp method (scipy), integrator (poinsot), "
                   "Euler, RK4, implicit, implicitfast (mujoco), reduced or maximal coordinates "
                   "(pybullet), a Drake integrator, e.g. runge_kutta3 (drake), or RK4, Euler, RK2, "
                   "RKF45, RKF78 (basilisk)")  # fmt: skip
    p.add_argument("--step", type=float, metavar="SECONDS",
                   help="step (poinsot's fixed-step methods), timestep (mujoco, pybullet, "
                   "basilisk's task period) or fixed step (drake)")  # fmt: skip
    p.add_argument("--rtol", type=float, help="tolerance (scipy, poinsot's adaptive methods) "
                   "target accuracy (drake), or relTol of basilisk's RKF45/RKF78")  # fmt: skip
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
    p.add_argument("--engines", metavar="NAMES",
                   help="scorecard: engines, comma separated (poinsot, scipy, mujoco, "
                   "pybullet, drake, basilisk); default all")  # fmt: skip
    p.add_argument(
        "--quick",
        action="store_true",
        help="scorecard: two settings per integrator instead of the full sweep",
    )
    p.add_argument(
        "--jobs", type=int, metavar="N", help="scorecard: worker processes (default up to 2)"
    )
    p.add_argument(
        "--from-json",
        metavar="FILE",
        help="scorecard: write the pages of a stored scorecard.json (no engine runs)",
    )
    p.set_defaults(func=_cmd_verify)


def _cmd_scorecard(args: argparse.Namespace) -> int:
    if args.from_json:
        if not args.out:
            raise _Usage("verify scorecard --from-json FILE needs --out DIR for the pages")
        try:
            card = Scorecard.from_json(args.from_json)
        except (OSError, ValueError, KeyError) as exc:
            raise _Usage(f"--from-json: cannot read {args.from_json}: {exc}") from None
        files = card.write_pages(args.out)
        if not args.quiet:
            print(f"wrote {len(files)} files to {args.out} from {args.from_json}")
        return 0
    names = None
    if args.engines:
        names = [e.strip() for e in args.engines.split(",") if e.strip()]
        bad = [e for e in names if e not in ENGINES]
        if bad:
            raise _Usage(f"--engines: expected among {', '.join(ENGINES)}, got {', '.join(bad)}")

    def each(line: str) -> None:
        if not args.quiet:
            print(f"  {line}", file=sys.stderr, flush=True)

    result = scorecard(names, args.cases, quick=args.quick, jobs=args.jobs, progress=each)
    for c in result.cards:
        if c.reason:
            print(f"{c.engine}: not run: {c.reason}")
        else:
            n = sum(r["status"] == "pass" for r in c.rows)
            m = sum("metrics" in r for r in c.rows)
            print(f"{c.engine} {c.version}: {n} of {m} runs pass ({c.seconds:.0f} s)")
    if args.out:
        files = result.write(args.out)
        if not args.quiet:
            print(f"wrote {args.out}/scorecard.json and {len(files) - 1} pages and charts")
    return 0


def _cmd_verify(args: argparse.Namespace) -> int:
    if args.engine == "scorecard":
        return _cmd_scorecard(args)
    if args.from_json or args.engines or args.quick:
        raise _Usage("--from-json, --engines and --quick go with: poinsot verify scorecard")
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
    elif args.engine == "pybullet":
        opts = {"coordinates": args.method, "timestep": args.step}
    elif args.engine == "drake":
        opts = {"integrator": args.method, "step": args.step, "accuracy": args.rtol}
    elif args.engine == "basilisk":
        opts = {"integrator": args.method, "timestep": args.step, "rtol": args.rtol}
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
