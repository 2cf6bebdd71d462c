"""Ctrl-C in `poinsot ensemble` and failed samples within --max-failed (issue 38).

A real `poinsot ensemble` in a subprocess gets a real Ctrl-C: SIGINT to its whole
process group, as a terminal sends it (so a local cluster's worker processes get it
too), once a chunk is on disk. It must exit 130 within seconds with one line naming
the chunks kept and --resume, no Dask traceback, CancelledError or log line, leave no
process behind, and `--resume` must complete it into the table and summary of an
uninterrupted run with the same seed.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("dask.distributed")
pytest.importorskip("pyarrow")

from poinsot.cli import main  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "tennis_racket_ensemble.toml"
SRC = str(Path(__file__).resolve().parents[2] / "src")
# 40 chunks of 50 samples: ~0.1 s a chunk, a few seconds in all
ARGS = ["--samples", "2000", "--chunk-size", "50", "--seed", "5"]


def _command(out: Path, *extra: str) -> list[str]:
    return [sys.executable, "-c", "import sys; from poinsot.cli import main; "
            "sys.exit(main(sys.argv[1:]))", "ensemble", str(EXAMPLE), *ARGS,
            "--out", str(out), *extra]  # fmt: skip


def _sigint_default() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _env() -> dict[str, str]:
    return dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # pragma: no cover - a member we may not signal
        return True
    return True


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """summary.json and table of the uninterrupted run (in this process, serial:
    the result does not depend on the workers)."""
    import pyarrow.parquet as pq

    out = tmp_path_factory.mktemp("ref") / "out"
    argv = ["ensemble", str(EXAMPLE), *ARGS, "--out", str(out), "--workers", "0", "--quiet"]
    assert main(argv) == 0
    return (out / "summary.json").read_text(), pq.read_table(out / "chunks")


@pytest.mark.skipif(not hasattr(os, "killpg"), reason="process groups (POSIX)")
@pytest.mark.parametrize("workers", ["0", "1"], ids=["serial", "local-cluster"])
def test_ctrl_c_exits_130_with_a_resume_hint_and_resume_completes_it(workers, tmp_path, reference):
    import pyarrow.parquet as pq

    out = tmp_path / "out"
    chunks = out / "chunks"
    proc = subprocess.Popen(
        _command(out, "--workers", workers),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=_env(),
        start_new_session=True,  # its own process group, as a shell job
        # Ctrl-C reaches a foreground job: a test run started in the background (make in a
        # non-interactive shell, as CI) inherits SIGINT ignored, which Python then keeps
        preexec_fn=_sigint_default,
    )
    pgid = proc.pid
    try:
        deadline = time.monotonic() + 90
        while not list(chunks.glob("chunk-*.parquet")):
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "no chunk written within 90 s"
            time.sleep(0.02)
        t0 = time.monotonic()
        os.killpg(pgid, signal.SIGINT)  # Ctrl-C in a terminal
        proc.wait(timeout=20)
        stop = time.monotonic() - t0
        _, err = proc.communicate(timeout=20)
        # every process of the run is gone (the workers killed, not left running)
        for _ in range(100):
            if not _group_alive(pgid):
                break
            time.sleep(0.05)
        assert not _group_alive(pgid), "a process of the interrupted run is still alive"
    finally:
        if proc.poll() is None or _group_alive(pgid):
            try:
                os.killpg(pgid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait()
    print(f"workers {workers}: exit {stop:.2f} s after SIGINT")
    assert proc.returncode == 130, err
    for noise in ("Traceback", "CancelledError", "distributed.", "KeyboardInterrupt"):
        assert noise not in err, err
    m = re.search(
        r"^poinsot: interrupted: (\d+) of 40 chunks kept in (.+); run the same command "
        r"with --resume to complete it$",
        err,
        re.M,
    )
    assert m, err
    assert m.group(2) == str(out)
    kept = sorted(chunks.glob("chunk-*.parquet"))
    assert int(m.group(1)) == len(kept) and 0 < len(kept) < 40, err
    assert not [p for p in chunks.iterdir() if p.name.startswith(".")]  # no half files
    assert stop < 4.0, f"{stop:.1f} s from Ctrl-C to exit"  # seen 0.1-0.2 s (was 1.7-5.4 s)

    # --resume (the same command) completes it: the result of an uninterrupted run
    done = subprocess.run(
        _command(out, "--workers", workers, "--resume", "--quiet"),
        capture_output=True,
        text=True,
        env=_env(),
        timeout=120,
        start_new_session=True,
    )
    assert done.returncode == 0, done.stderr
    summary, table = reference
    assert (out / "summary.json").read_text() == summary
    assert pq.read_table(chunks).equals(table)


def _plate(tmp_path: Path) -> Path:
    """A body whose inertia is drawn from six values: one breaks A + B >= C, one has a
    negative moment; the other samples run."""
    path = tmp_path / "plate.toml"
    path.write_text(
        'name = "plate"\n\n[body]\nmass = 1.0\ninertia = [1.0, 2.0, 3.0]\n\n'
        '[angular_velocity]\nvector = [0.1, 2.0, 0.1]\nframe = "body"\n\n'
        '[simulation]\nduration = 1.0\nstep = 0.1\nmethod = "dop853"\n\n'
        '[dispersion.inertia]\ndistribution = "choice"\nvalues = [[1.0, 2.0, 3.0], '
        "[1.0, 2.0, 3.0], [1.0, 2.0, 3.0], [1.0, 2.0, 3.0], [1.0, 2.0, 9.0], "
        "[-1.0, 2.0, 3.0]]\n\n"
        '[[metric]]\nname = "wmax"\nkind = "max"\ncomponent = "omega_y"\n'
    )
    return path


def test_failed_samples_within_max_failed_are_listed_with_reasons(tmp_path, capsys):
    """issue 38: failures under --max-failed were only a count on stdout; now a warning
    on stderr lists them by reason with counts, most frequent first (also with
    --quiet); over the limit the error lists them the same way."""
    import json

    base = ["ensemble", str(_plate(tmp_path)), "--samples", "40", "--chunk-size", "20",
            "--workers", "0", "--seed", "2"]  # fmt: skip
    assert main([*base, "--out", str(tmp_path / "a")]) == 0
    captured = capsys.readouterr()
    reasons = json.loads((tmp_path / "a" / "summary.json").read_text())["failure_reasons"]
    assert set(reasons) == {
        "inertia violates the triangle inequality A + B >= C",
        "inertia has a non-positive moment",
    }
    n = sum(reasons.values())
    assert 0 < n < 20
    ranked = sorted(reasons.items(), key=lambda kv: (-kv[1], kv[0]))
    listing = "".join(f"\n  {count} x {reason}" for reason, count in ranked)
    assert (
        f"poinsot: warning: {n} of 40 samples failed ({100 * n / 40:.3g} %, within "
        f"--max-failed 0.5; their metrics are NaN, their reasons in {tmp_path / 'a'}"
        f"/summary.json); reasons:{listing}\n"
    ) in captured.err, captured.err
    assert f"40 samples, {n} failed; outputs in" in captured.out
    # --quiet keeps the warning (a success, but not a silent one)
    assert main([*base, "--out", str(tmp_path / "b"), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and f"reasons:{listing}\n" in captured.err
    # over --max-failed: the error lists the same reasons
    assert main([*base, "--out", str(tmp_path / "c"), "--max-failed", "0.05"]) == 1
    err = capsys.readouterr().err
    assert "poinsot: error: " in err and "more than --max-failed 0.05" in err
    assert f"reasons:{listing}\n" in err, err


def test_failure_reasons_are_capped():
    from poinsot.cli.ensemble import _failure_reasons

    reasons = {f"reason {i}": i for i in range(1, 9)}
    text = _failure_reasons(reasons)
    assert text.splitlines() == [
        "  8 x reason 8",
        "  7 x reason 7",
        "  6 x reason 6",
        "  5 x reason 5",
        "  4 x reason 4",
        "  6 x 3 other reasons (summary.json)",
    ]
    assert _failure_reasons({"x" * 300: 1}) == "  1 x " + "x" * 197 + "..."
