"""Monte-Carlo ensembles (poinsot.ensemble): statistics against closed forms,
reproducibility across workers/chunks/retries/resume, failures recorded, bad input."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed")
pytest.importorskip("pyarrow")

from poinsot.cli import main  # noqa: E402
from poinsot.ensemble import (  # noqa: E402
    EnsembleError,
    EnsembleProblem,
    Metric,
    Normal,
    SmallRotation,
    Uniform,
    run,
)
from poinsot.errors import InvalidInputError  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _sphere(dispersions, metrics, t_end=2.0, n_t=21):
    """A spherical body (J = E): omega stays constant, the attitude turns uniformly."""
    return EnsembleProblem(
        "sphere",
        np.eye(3),
        np.array([1.0, 0, 0, 0]),
        np.array([0.3, -0.2, 0.5]),
        np.linspace(0.0, t_end, n_t),
        dispersions=tuple(dispersions),
        metrics=tuple(metrics),
    )


def _racket():
    return EnsembleProblem(
        "racket",
        np.diag([1.0, 2.0, 3.0]),
        np.array([1.0, 0, 0, 0]),
        np.array([0.01, 2.0, 0.01]),
        np.linspace(0.0, 15.0, 301),
        dispersions=(
            ("omega0", Normal(sigma=[0.005, 0.05, 0.005])),
            ("attitude", SmallRotation(2.0)),
        ),
        metrics=(
            Metric("flip", "first_flip_time"),
            Metric("err", "final_attitude_error"),
            Metric("drift", "energy_drift"),
            Metric("nmax", "nutation_max", axis="y"),
        ),
    )


def test_metric_equals_input_for_a_sphere():
    """J = E: |omega| is constant, so max |omega| over the run is |omega0| of the sample."""
    p = _sphere(
        [("omega0", Normal(sigma=[0.1, 0.1, 0.1]))], [Metric("wmax", "max", component="omega_norm")]
    )
    res = run(p, 50, chunk_size=20, client="serial", seed=3)
    w = np.stack([res.column(f"omega0_{c}") for c in "xyz"], axis=1)
    assert np.allclose(res.column("wmax"), np.linalg.norm(w, axis=1), rtol=1e-12, atol=0)
    assert not res.column("failed").any()
    # the draws are the normal law about the nominal (4 sigma / sqrt(n) bounds)
    assert abs(res.column("omega0_x").mean() - 0.3) < 4 * 0.1 / np.sqrt(50)


def test_small_rotation_error_follows_the_maxwell_law():
    """Free sphere: the angle between a perturbed and the nominal attitude stays the
    initial perturbation |phi|, phi ~ N(0, sigma^2 E): mean sigma 2 sqrt(2/pi)."""
    sigma = 2.0
    p = _sphere([("attitude", SmallRotation(sigma))], [Metric("err", "final_attitude_error")])
    res = run(p, 2000, chunk_size=500, client="serial", seed=5)
    err = res.column("err")
    mean = sigma * 2 * np.sqrt(2 / np.pi)
    sd = sigma * np.sqrt(3 - 8 / np.pi)
    assert abs(err.mean() - mean) < 5 * sd / np.sqrt(err.size)
    s = res.summary["metrics"]["err"]
    assert s["unit"] == "deg" and s["count"] == 2000
    assert abs(s["quantiles"]["50%"] - np.median(err)) < 1e-12


def test_same_seed_same_table_other_seed_other_draws(tmp_path):
    p = _racket()
    serial = run(p, 60, chunk_size=16, client="serial", seed=7)
    again = run(p, 60, chunk_size=16, client="serial", seed=7, out=tmp_path / "a")
    assert serial.table.equals(again.table)
    other_seed = run(p, 60, chunk_size=16, client="serial", seed=8)
    assert not np.array_equal(other_seed.column("omega0_x"), serial.column("omega0_x"))
    assert serial.column("flip").min() > 0  # every racket flips within 15 s here


def _plate_with_bad_inertia():
    """A plate whose C is drawn up to 3: A + B >= C fails for C > 2 (40 samples)."""
    p = EnsembleProblem(
        "plate",
        np.diag([1.0, 2.0, 3.0]),
        np.array([1.0, 0, 0, 0]),
        np.array([0.1, 2.0, 0.1]),
        np.linspace(0.0, 1.0, 11),
        dispersions=(("inertia", Uniform(low=[1.0, 1.0, 1.0], high=[1.0, 1.0, 3.0])),),
        metrics=(Metric("wmax", "max", component="omega_y"),),
    )
    return p, run(p, 40, chunk_size=40, client="serial", seed=1)


def test_failed_samples_are_recorded_not_dropped():
    p, res = _plate_with_bad_inertia()
    c = res.column("inertia_z")
    failed = res.column("failed")
    assert np.array_equal(failed, c > 2.0)  # A + B >= C fails exactly there
    assert np.all(np.isnan(res.column("wmax")[failed]))
    assert np.all(np.isfinite(res.column("wmax")[~failed]))
    assert set(res.table.column("reason").to_pylist()) == {
        "",
        "inertia violates the triangle inequality A + B >= C",
    }
    assert res.summary["failures"] == int(failed.sum())


def test_resume_recomputes_only_missing_chunks(tmp_path):
    p = _racket()
    out = tmp_path / "run"
    full = run(p, 50, chunk_size=10, client="serial", seed=2, out=out)
    for i in (1, 3):
        os.remove(out / "chunks" / f"chunk-{i:06d}.parquet")
    seen = []
    resumed = run(
        p,
        50,
        chunk_size=10,
        client="serial",
        seed=2,
        out=out,
        resume=True,
        on_chunk=lambda done, total: seen.append(done),
    )
    assert len(seen) == 2  # two chunks computed
    assert resumed.table.equals(full.table)
    with pytest.raises(EnsembleError, match="already holds this ensemble: pass --resume"):
        run(p, 50, chunk_size=10, client="serial", seed=2, out=out)
    with pytest.raises(EnsembleError, match="different scenario, seed"):
        run(p, 50, chunk_size=10, client="serial", seed=3, out=out, resume=True)


def test_dask_cluster_with_a_killed_worker_gives_the_serial_result():
    from dask.distributed import Client, LocalCluster

    p = _racket()
    serial = run(p, 96, chunk_size=8, client="serial", seed=11)
    with (
        LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            host="127.0.0.1",
        ) as cluster,
        Client(cluster) as client,
    ):
        victim = sorted(client.scheduler_info()["workers"])[0]
        killed = []

        def kill_one(done, total):
            if not killed:
                killed.append(done)
                try:
                    client.run(os._exit, 1, workers=[victim], wait=False)
                except Exception:  # the worker is gone before it answers
                    pass

        res = run(p, 96, chunk_size=8, client=client, seed=11, on_chunk=kill_one)
        # the same client again, right away (the problem is scattered under a fresh key)
        again = run(p, 96, chunk_size=8, client=client, seed=11)
    assert killed
    assert again.table.equals(serial.table)
    assert res.table.equals(serial.table)


def test_bad_input_is_named():
    p = _racket()
    with pytest.raises(EnsembleError, match="`samples` > 0"):
        run(p, 0, client="serial")
    with pytest.raises(InvalidInputError, match="`sigma` to be >= 0"):
        run(
            _sphere(
                [("omega0", Normal(sigma=[-0.1, 0, 0]))], [Metric("w", "max", component="omega_x")]
            ),
            4,
            client="serial",
        )
    with pytest.raises(InvalidInputError, match="Unknown dispersed quantity 'spin'"):
        _sphere([("spin", Normal(sigma=1.0))], [Metric("w", "max", component="omega_x")])
    with pytest.raises(EnsembleError, match="did not answer within 2"):
        run(p, 4, scheduler="tcp://127.0.0.1:9", timeout=2)


def _scenario_file(tmp_path, extra):
    text = (EXAMPLES / "tennis_racket_ensemble.toml").read_text()
    path = tmp_path / "s.toml"
    path.write_text(text + extra)
    return path


def test_cli_ensemble_writes_outputs_and_refuses_bad_files(tmp_path, capsys):
    src = EXAMPLES / "tennis_racket_ensemble.toml"
    out = tmp_path / "out"
    assert (
        main(
            [
                "ensemble",
                str(src),
                "--samples",
                "12",
                "--chunk-size",
                "5",
                "--out",
                str(out),
                "--workers",
                "0",
            ]
        )
        == 0
    )
    assert sorted(p.name for p in (out / "chunks").iterdir()) == [
        "chunk-000000.parquet",
        "chunk-000001.parquet",
        "chunk-000002.parquet",
    ]
    html = (out / "report.html").read_text()
    assert 'id="poinsot-data"' in html and "flip_time" in html and "<script src=" not in html
    printed = capsys.readouterr().out
    assert "  flip_time (s): mean " in printed and "  energy_drift: mean " in printed
    # resume of a complete run recomputes nothing and succeeds
    assert (
        main(
            [
                "ensemble",
                str(src),
                "--samples",
                "12",
                "--chunk-size",
                "5",
                "--out",
                str(out),
                "--workers",
                "0",
                "--resume",
            ]
        )
        == 0
    )
    bad = _scenario_file(tmp_path, '\n[dispersion.torque_x]\ndistribution = "normal"\n')
    assert (
        main(
            ["ensemble", str(bad), "--samples", "4", "--out", str(tmp_path / "b"), "--workers", "0"]
        )
        == 2
    )
    line = len(bad.read_text().splitlines()) - 1  # the [dispersion.torque_x] header
    assert f"s.toml:{line}: `dispersion.torque_x` unknown quantity" in capsys.readouterr().err
    shutil.rmtree(tmp_path / "b", ignore_errors=True)
    text = src.read_text().replace('distribution = "normal"', 'distribution = "gaussian"')
    (tmp_path / "g.toml").write_text(text)
    assert (
        main(
            [
                "ensemble",
                str(tmp_path / "g.toml"),
                "--samples",
                "4",
                "--out",
                str(tmp_path / "g"),
                "--workers",
                "0",
            ]
        )
        == 2
    )
    assert "Unknown distribution 'gaussian'" in capsys.readouterr().err
    assert not (tmp_path / "g").exists()  # nothing half-written


def test_failed_integrations_are_recorded_and_the_rest_kept():
    from poinsot.ensemble import Choice

    p = EnsembleProblem(
        "blowup",
        np.diag([1.0, 2.0, 3.0]),
        np.array([1.0, 0, 0, 0]),
        np.array([0.1, 2.0, 0.1]),
        np.linspace(0.0, 1.0, 11),
        dispersions=(("omega0", Choice(values=[[0.1, 2.0, 0.1], [1e300, 1e300, 1e300]])),),
        metrics=(Metric("w", "max", component="omega_y"),),
    )
    res = run(p, 12, chunk_size=12, client="serial", seed=0)
    bad = res.column("omega0_x") > 1
    assert bad.any() and (~bad).any()
    assert np.array_equal(res.column("failed"), bad)
    assert set(np.asarray(res.table.column("reason").to_pylist())[bad]) == {
        "integration failed: the state became non-finite"
    }
    # the good samples are the nominal motion: max omega_y = |K|/B-bounded, finite
    assert np.all(np.isfinite(res.column("w")[~bad])) and np.all(np.isnan(res.column("w")[bad]))


def test_heavy_top_nutation_band_matches_the_lagrange_top(tmp_path):
    """Each dispersed top's recorded nutation extremes are the band of the exact
    Lagrange top started from that sample's state (docs/theory.md §10)."""
    from poinsot.dynamics import LagrangeTop
    from poinsot.ensemble import load_ensemble

    text = (EXAMPLES / "top_loops.toml").read_text() + (
        '\n[dispersion.omega0]\ndistribution = "normal"\nsigma = [0.0, 0.2, 10.0]\n'
        '\n[[metric]]\nname = "nmin"\nkind = "nutation_min"\n'
        '\n[[metric]]\nname = "nmax"\nkind = "nutation_max"\n'
    )
    path = tmp_path / "top.toml"
    path.write_text(text)
    scenario, problem = load_ensemble(path)
    res = run(problem, 6, chunk_size=6, client="serial", seed=4)
    body = scenario.body
    j = np.diag(np.asarray(body.inertia_about_origin()))
    mgl = body.mass * scenario.torque.g * body.center_of_mass[2]
    for i in range(6):
        w = [res.column(f"omega0_{c}")[i] for c in "xyz"]
        top = LagrangeTop.from_state(j, mgl, scenario.attitude.quat, w)
        lo, hi = np.degrees(top.nutation_bounds)
        # sampled every 0.5 ms: extremes missed by <= 2e-5 deg (observed), 100x headroom
        assert abs(res.column("nmin")[i] - lo) < 2e-3
        assert abs(res.column("nmax")[i] - hi) < 2e-3


def _ranks(a):
    return np.argsort(np.argsort(a)).astype(float)


def test_sensitivity_ranks_the_input_that_drives_the_metric():
    """A spin about the major axis z (stable): max omega_z is omega0_z, so omega0_z
    comes first with rho = 1, and rho equals Spearman's formula computed here from
    the ranks (Pearson correlation of ranks, no ties); the attitude, which the metric
    ignores, is given as an angle in degrees within 5 sigma."""
    from poinsot.ensemble.scenario import physical_inputs, sensitivity

    p = EnsembleProblem(
        "spinner",
        np.diag([1.0, 2.0, 3.0]),
        np.array([1.0, 0, 0, 0]),
        np.array([0.01, 0.01, 2.0]),
        np.linspace(0.0, 1.0, 11),
        dispersions=(
            ("omega0", Normal(sigma=[0.001, 0.001, 0.3])),
            ("attitude", SmallRotation(sigma=2.0)),
        ),
        metrics=(Metric("wmax", "max", component="omega_z"),),
    )
    res = run(p, 60, chunk_size=60, client="serial", seed=3)
    inputs = physical_inputs(p, res)
    assert set(inputs) == {"omega0_x", "omega0_y", "omega0_z", "attitude_offset"}
    angle, unit, _ = inputs["attitude_offset"]
    assert unit == "deg" and np.all(angle >= 0) and np.all(angle < 5 * 2.0 * np.sqrt(3))
    ranked = sensitivity(p, res, inputs)["wmax"]
    assert ranked[0][0] == "omega0_z" and ranked[0][1] == pytest.approx(1.0)
    v = res.column("wmax")
    for name, rho in ranked:
        by_hand = np.corrcoef(_ranks(inputs[name][0]), _ranks(v))[0, 1]
        assert rho == pytest.approx(by_hand, abs=1e-12), name


def test_report_lists_failed_samples_and_reasons(tmp_path):
    from poinsot.ensemble.scenario import _report

    p, res = _plate_with_bad_inertia()
    n = int(res.column("failed").sum())
    assert 0 < n < 40
    _report(p, res, tmp_path / "report.html")
    text = (tmp_path / "report.html").read_text()
    assert f"Failed samples: {n} of 40" in text
    assert f"<li>{n} x inertia violates the triangle inequality A + B &gt;= C</li>" in text
    assert "<td>inertia_z</td><td>kg m^2</td>" in text  # the dispersed input's row


class _Peer:
    """A TCP server on 127.0.0.1 that is not a Dask scheduler: an HTTP server, or one
    that sends garbage (a huge frame length) and then stays silent. Stopped by the test."""

    def __init__(self, kind: str) -> None:
        import socket
        import threading

        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(8)
        self.port = self.sock.getsockname()[1]
        self.kind = kind
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:

        self.sock.settimeout(0.1)
        conns = []
        while not self.stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except (TimeoutError, OSError):
                continue
            conns.append(conn)
            try:
                if self.kind == "http":
                    conn.recv(65536)
                    conn.sendall(b"HTTP/1.0 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
                else:
                    conn.sendall(b"\xff" * 64)
            except OSError:
                pass
        for c in conns:
            c.close()

    def close(self) -> None:
        self.stop.set()
        self.thread.join(5)
        self.sock.close()


@pytest.mark.parametrize("kind", ["http", "garbage"])
def test_a_peer_that_is_not_dask_exits_2_within_the_timeout(tmp_path, capsys, kind):
    """It used to hang for minutes (HTTP) or fail with MemoryError (exit 1)."""
    import time

    peer = _Peer(kind)
    try:
        out = tmp_path / "out"
        t0 = time.perf_counter()
        code = main(
            ["ensemble", str(EXAMPLES / "tennis_racket_ensemble.toml"), "--samples", "10",
             "--out", str(out), "--scheduler", f"tcp://127.0.0.1:{peer.port}",
             "--timeout", "2", "--quiet"]
        )  # fmt: skip
        elapsed = time.perf_counter() - t0
    finally:
        peer.close()
    assert code == 2
    assert elapsed < 2 + 3.0, elapsed
    assert "Dask scheduler" in capsys.readouterr().err
    assert not out.exists()  # nothing that would block a retry into the same --out


@pytest.mark.parametrize("address", ["not an address", "tcp://127.0.0.1", "tcp://:x"])
def test_a_malformed_scheduler_address_exits_2(tmp_path, capsys, address):
    code = main(
        ["ensemble", str(EXAMPLES / "tennis_racket_ensemble.toml"), "--samples", "10",
         "--out", str(tmp_path / "o"), "--scheduler", address, "--timeout", "2"]
    )  # fmt: skip
    assert code == 2
    assert "scheduler" in capsys.readouterr().err


def test_dispersion_of_the_wrong_length_names_file_line_and_key(tmp_path, capsys):
    """It used to exit 1 with a NumPy broadcast error and no file, line or key."""
    text = (EXAMPLES / "tennis_racket_ensemble.toml").read_text()
    assert "sigma = [0.05, 0.2, 0.05]" in text
    path = tmp_path / "s.toml"
    path.write_text(text.replace("sigma = [0.05, 0.2, 0.05]", "sigma = [0.05, 0.2]"))
    line = 1 + text.split("sigma = [0.05, 0.2, 0.05]")[0].count("\n")
    code = main(["ensemble", str(path), "--samples", "10", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2
    assert f"s.toml:{line}: `dispersion.omega0.sigma`" in err and "(3,)" in err, err
    assert not (tmp_path / "o").exists()


def test_ensemble_size_limits_as_run(tmp_path, capsys):
    """1e11 samples used to be accepted (5 GB RSS and 1702 chunk files before it was
    killed): the limits hold before anything is written; --allow-large lifts the soft
    ones, never the hard one."""
    src = str(EXAMPLES / "tennis_racket_ensemble.toml")
    out = tmp_path / "o"
    assert main(["ensemble", src, "--samples", str(10**11), "--out", str(out)]) == 2
    assert "exceed the limit" in capsys.readouterr().err
    assert main(["ensemble", src, "--samples", str(10**11), "--out", str(out),
                 "--allow-large"]) == 2  # fmt: skip
    assert main(["ensemble", src, "--samples", str(3 * 10**7), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "memory" in err and "--allow-large" in err, err
    assert not out.exists()


def test_progress_in_a_log_is_whole_lines_and_most_failed_exits_1(tmp_path, capsys):
    """Not a terminal: 'chunks 1/2' lines, not 'chunks 1/2chunks 2/2'. A run whose
    samples mostly fail (inertia dispersed far past the triangle inequality) says so
    with the reasons and exits 1; --max-failed 1 accepts it."""
    src = EXAMPLES / "tennis_racket_ensemble.toml"
    args = ["ensemble", str(src), "--samples", "8", "--chunk-size", "4", "--workers", "0"]
    assert main([*args, "--out", str(tmp_path / "a")]) == 0
    err = capsys.readouterr().err
    assert "chunks 1/2\n" in err and "chunks 2/2\n" in err and "\r" not in err, err
    bad = _scenario_file(
        tmp_path, '\n[dispersion.inertia]\ndistribution = "normal"\nsigma = [0.0, 0.0, 1e3]\n'
    )
    base = ["ensemble", str(bad), "--samples", "8", "--chunk-size", "4", "--workers", "0"]
    assert main([*base, "--out", str(tmp_path / "b"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "samples failed" in err and "triangle inequality" in err, err
    assert (tmp_path / "b" / "summary.json").exists()  # the outputs are written
    assert main([*base, "--out", str(tmp_path / "c"), "--quiet", "--max-failed", "1"]) == 0
    assert main([*base, "--out", str(tmp_path / "d"), "--max-failed", "2"]) == 2


def test_file_without_spread_is_refused_not_run_as_identical_samples(tmp_path, capsys):
    """issue 38: a file without [dispersion] ran N identical samples silently (every
    metric had 5%-95% [x, x]); it is refused before anything is written, and so is a
    dispersion of zero spread. The example's own dispersions draw distinct samples."""
    import re

    text = (EXAMPLES / "tennis_racket_ensemble.toml").read_text()
    bare = re.sub(r"\[dispersion\.omega0\].*?(?=\[\[metric\]\])", "", text, flags=re.S)
    assert "dispersion" not in bare
    zero = re.sub(r"\[dispersion\.omega0\].*?(?=\[\[metric\]\])",
                  '[dispersion.omega0]\ndistribution = "normal"\nsigma = [0.0, 0.0, 0.0]\n\n',
                  text, flags=re.S)  # fmt: skip
    for name, body, words in (
        ("bare.toml", bare, "no [dispersion] table"),
        ("zero.toml", zero, "zero spread in [dispersion.omega0]"),
    ):
        path = tmp_path / name
        path.write_text(body)
        out = tmp_path / f"out-{name}"
        argv = ["ensemble", str(path), "--samples", "4", "--out", str(out), "--workers", "0"]
        assert main(argv) == 2, name
        err = capsys.readouterr().err
        assert f"{name}: {words}" in err and "every sample would be the same run" in err, err
        assert "docs/ensembles.md" in err and not out.exists()
    # what is accepted really varies: two samples of the example's draw differ
    from poinsot.ensemble.engine import _draw
    from poinsot.ensemble.scenario import load_ensemble

    _, problem = load_ensemble(EXAMPLES / "tennis_racket_ensemble.toml")
    drawn = _draw(problem, np.random.default_rng(1), 2)
    assert np.ptp(drawn["omega0"], axis=0).max() > 0


def test_metrics_read_a_trajectory_and_a_deprecated_motion_alike():
    """Issue 39: a chunk's motion is a poinsot Trajectory (time first, then samples);
    T + V comes from it (its kinetic energy and its gravity moment); the former
    Motion gives the same values, with a DeprecationWarning."""
    from poinsot.dynamics import GravityTorque, simulate
    from poinsot.ensemble.metrics import COMPONENTS, METRICS, Metric, Motion, total_energy

    t = np.linspace(0.0, 1.0, 51)
    model = GravityTorque([1.0, 1.2], [[0.0, 0.0, 0.1], [0.0, 0.01, 0.1]])
    q0 = [[1.0, 0, 0, 0], [0.99, 0.1, 0, 0]]
    w0 = [[0.0, 0.5, 40.0], [0.1, 0.0, 30.0]]
    tr = simulate(np.diag([0.05, 0.05, 0.02]), q0, w0, t, torque=model, method="dop853")
    total = total_energy(tr)
    np.testing.assert_array_equal(total, tr.energy + model.potential(tr.quat))
    old = Motion(t, tr.quat, np.asarray(tr.omega), tr.energy, total, tr.quat[-1, 0])
    for kind in METRICS:
        for comp in COMPONENTS if kind in ("max", "min", "first_time") else (None,):
            m = Metric("m", kind, comp, below=0.5 if kind == "first_time" else None)
            if m.orbital:  # reads an orbit frame: tests/ensemble/test_pointing_ensemble.py
                continue
            with pytest.warns(DeprecationWarning, match="Motion is deprecated"):
                expected = m.evaluate(old)
            np.testing.assert_array_equal(m.evaluate(tr, tr.quat[-1, 0]), expected)
