"""``poinsot ensemble``: a Monte-Carlo ensemble of a dispersed scenario, in chunks on
Dask."""

from __future__ import annotations

import argparse
import atexit
import gc
import sys

from ..ensemble import EnsembleInterrupted, run_scenario_ensemble
from ._common import PROG, _error, _Usage, add_allow_paths

DESCRIPTION = (
    "Run N dispersed samples of a rigid-body scenario with [dispersion] and "
    "[[metric]] tables, in chunks on a local or existing Dask cluster."
)
EPILOG = """example:
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


def add_arguments(p: argparse.ArgumentParser) -> None:
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
    add_allow_paths(p)
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


def _cmd_ensemble(args: argparse.Namespace) -> int:
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
