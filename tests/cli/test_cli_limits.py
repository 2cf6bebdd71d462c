"""The command refuses what would hurt and says when results are poor (called in-process).

Covers: the sample limit after every override, the cost estimate of `check`, the
memory/steps limits and --allow-large, accuracy warnings with a suggested step,
long names, a UTF-8 BOM, matrix tolerance, user-facing names in messages, round-off
noise, the canonical quaternion sign, exit codes of a diverging integration and of a
broken pipe, and that no user-facing text cites a SPEC the project does not ship.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot.cli import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def forbid_solving(monkeypatch):
    """Make any attempt to solve a scenario fail loudly (the refusal must come first)."""
    from poinsot.scenarios.registry import KINDS

    def boom(*args, **kwargs):
        raise AssertionError("the scenario was solved although it must be refused")

    for kind in KINDS.values():
        monkeypatch.setattr(type(kind), "solve", boom)


# ------------------------------------------------------------------------ sample limit
@pytest.mark.parametrize("duration", ["1e5", "1e12", "1e300"])
def test_duration_override_beyond_the_sample_limit_is_refused_before_work(
    capsys, tmp_path, monkeypatch, duration
):
    forbid_solving(monkeypatch)
    out = tmp_path / "o"
    code, stdout, err = run(
        capsys, "run", EXAMPLES / "tennis_racket.toml", "--duration", duration, "--out", out
    )
    assert code == 2 and stdout == ""
    assert "refused before running" in err and "exceed the limit of 5000000" in err
    assert "Traceback" not in err and "MemoryError" not in err
    assert not out.exists()  # nothing created
    # the same refusal from `check`, with the override
    code, _, err = run(capsys, "check", EXAMPLES / "tennis_racket.toml", "--duration", duration)
    assert code == 2 and "exceed the limit of 5000000" in err


def test_sample_count_is_computed_without_allocating():
    from poinsot.scenarios import demo_scenario, estimate_cost

    s = demo_scenario()
    step = s.simulation.step
    for duration in (0.5, 1.0, 7.3):
        n = estimate_cost(s, duration=duration).samples
        from poinsot.scenarios.solve import _override

        assert n == _override(s, duration).simulation.times().size
    assert estimate_cost(s, duration=1e5).samples == pytest.approx(1e5 / step + 1, rel=1e-9)


# ------------------------------------------------------------------------ cost estimate
def test_check_prints_a_cost_estimate(capsys):
    code, out, _ = run(capsys, "check", EXAMPLES / "satellite_torque.toml")
    assert code == 0
    cost = out.splitlines()[1]
    # 600 s at step 0.5 s: 1201 samples; max_step 0.05 s: 10 steps per interval, for
    # the method and the reference: 2 * 1200 * 10 integration steps
    assert cost.startswith("cost: 1201 samples, 24000 integration steps, ~")
    assert re.search(r"~[0-9.]+ (B|kB|MB|GB) memory, ~[0-9.e+-]+ (s|min|h)", cost)


def test_steps_and_memory_limits_refuse_unless_allowed(capsys, tmp_path, monkeypatch):
    from poinsot.scenarios import solve

    monkeypatch.setattr(solve, "MAX_STEPS", 1000)
    code, _, err = run(
        capsys, "run", EXAMPLES / "coning.toml", "--out", tmp_path / "a", "--no-report"
    )
    assert code == 2 and "integration steps exceed the limit" in err and "--allow-large" in err
    assert not (tmp_path / "a").exists()
    code, _, err = run(capsys, "check", EXAMPLES / "coning.toml")
    assert code == 2 and "would refuse it" in err
    code, out, _ = run(capsys, "check", EXAMPLES / "coning.toml", "--allow-large")
    assert code == 0 and "cost:" in out
    code, _, err = run(
        capsys,
        "run",
        EXAMPLES / "coning.toml",
        "--out",
        tmp_path / "b",
        "--no-report",
        "--no-figures",
        "--quiet",
        "--allow-large",
        "--duration",
        "0.2",
    )
    assert code == 0 and (tmp_path / "b" / "summary.json").exists()
    monkeypatch.setattr(solve, "MAX_STEPS", 10**9)
    monkeypatch.setattr(solve, "MAX_MEMORY_BYTES", 1000)
    code, _, err = run(capsys, "run", EXAMPLES / "coning.toml", "--out", tmp_path / "c")
    assert code == 2 and "of memory, more than the limit" in err


# ------------------------------------------------------------------------ accuracy
def racket(tmp_path: Path, extra: str = "") -> Path:
    """The tennis-racket example integrated by rk4 at a step of 0.1 s (too long)."""
    text = (EXAMPLES / "tennis_racket.toml").read_text()
    text = text.replace("step = 0.002", "step = 0.1" + extra)
    text = text.replace('method = "exact"', 'method = "rk4"')
    text = text.replace('reference = "midpoint"', 'reference = "exact"')
    p = tmp_path / "racket.toml"
    p.write_text(text)
    return p


def test_poor_accuracy_warns_records_and_suggests_a_step_that_works(capsys, tmp_path):
    out = tmp_path / "o"
    code, stdout, err = run(capsys, "run", racket(tmp_path), "--out", out, "--no-report")
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    acc = summary["accuracy"]
    # the drift, recomputed here from the written trajectory (T = w.Jw/2, K = R J w)
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    j = np.asarray(summary["body"]["inertia"])
    w = data[:, 5:8]
    energy = 0.5 * np.einsum("ni,ij,nj->n", w, j, w)
    drift = np.max(np.abs(energy - energy[0])) / energy[0]
    assert drift > 1e-2  # the case: several percent
    assert acc["invariants"]["energy"]["max_relative_drift"] == pytest.approx(drift, rel=1e-9)
    assert acc["comparison"]["max_attitude_error_rad"] > 0.1
    assert any("kinetic energy T drifts" in w for w in acc["warnings"])
    assert any("differ by up to" in w for w in acc["warnings"])
    assert "poinsot: warning: accuracy: kinetic energy T drifts" in err
    assert "suggestion: set [simulation] max_step =" in err
    h = acc["suggested_max_step"]
    assert 0 < h < 0.1 and acc["integration_step"] == 0.1
    # the suggestion is honest: with it, the run is within the thresholds
    code, _, err = run(
        capsys,
        "run",
        racket(tmp_path, f"\nmax_step = {h!r}"),
        "--out",
        tmp_path / "o2",
        "--no-report",
        "--no-figures",
    )
    again = json.loads((tmp_path / "o2" / "summary.json").read_text())["accuracy"]
    assert code == 0 and again["warnings"] == [] and "warning" not in err
    assert again["invariants"]["energy"]["max_relative_drift"] < again["drift_threshold"]


def test_accurate_examples_run_without_warnings():
    from poinsot.scenarios import load_scenario, simulate_scenario

    for name, duration in (("tennis_racket", 6.0), ("symmetric_top", 0.3), ("coning", 2.0)):
        result = simulate_scenario(load_scenario(EXAMPLES / f"{name}.toml"), duration=duration)
        assert result.warnings == (), (name, result.warnings)


def test_thresholds_can_be_set_in_the_scenario(tmp_path):
    from poinsot.scenarios import load_scenario, simulate_scenario

    p = racket(tmp_path, "\ndrift_threshold = 0.5\nattitude_threshold = 3.0")
    result = simulate_scenario(load_scenario(p), duration=2.0)
    acc = result.summary["accuracy"]
    assert acc["drift_threshold"] == 0.5 and acc["attitude_threshold"] == 3.0
    # omega is judged on its own rule: agreement_threshold of its scale (default 1e-2)
    omega = acc["comparison"]["differences"]["omega"]
    assert omega["max"] > 1e-2 * omega["scale"] and result.warnings != ()
    assert all("in omega" in w for w in result.warnings)
    p = racket(
        tmp_path, "\ndrift_threshold = 0.5\nattitude_threshold = 3.0\nagreement_threshold = 0.5"
    )
    result = simulate_scenario(load_scenario(p), duration=2.0)
    assert result.summary["accuracy"]["agreement_threshold"] == 0.5
    assert result.warnings == ()


# ------------------------------------------------------------------------ smaller findings
def test_long_name_fails_in_check_and_leaves_nothing(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text = (
        (EXAMPLES / "coning.toml").read_text().replace('name = "coning"', f'name = "{"a" * 300}"')
    )
    p = tmp_path / "long.toml"
    p.write_text(text)
    code, _, err = run(capsys, "check", p)
    assert code == 2 and "at most 100" in err and "300 characters" in err
    code, _, err = run(capsys, "run", p, "--no-report")
    assert code == 2 and not (tmp_path / "poinsot-out").exists()


def test_failed_run_leaves_no_empty_directory(tmp_path, monkeypatch):
    from poinsot import IntegrationError
    from poinsot.scenarios import load_scenario, run_scenario
    from poinsot.scenarios.kinds.coning import Coning

    def diverge(*args, **kwargs):
        raise IntegrationError("diverged")

    monkeypatch.setattr(Coning, "solve", diverge)
    with pytest.raises(IntegrationError):
        run_scenario(load_scenario(EXAMPLES / "coning.toml"), tmp_path / "new" / "o")
    assert not (tmp_path / "new" / "o").exists()
    existing = tmp_path / "mine"
    existing.mkdir()
    with pytest.raises(IntegrationError):
        run_scenario(load_scenario(EXAMPLES / "coning.toml"), existing)
    assert existing.is_dir()  # a directory the user made is left alone


def test_utf8_bom_is_accepted(capsys, tmp_path):
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + (EXAMPLES / "coning.toml").read_bytes())
    code, out, err = run(capsys, "check", p)
    assert code == 0 and "ok:" in out, err
    from poinsot.scenarios import parse_scenario

    s = parse_scenario("\ufeff" + (EXAMPLES / "coning.toml").read_text())
    assert s.name == "coning"


MATRIX = "[[0.7071, -0.7071, 0.0], [0.7071, 0.7071, 0.0], [0.0, 0.0, 1.0]]"


def nearest_rotation(m):
    u, _, vt = np.linalg.svd(np.asarray(m, dtype=float))
    return u @ vt


def test_scenario_matrix_tolerance_and_projection_warning(tmp_path):
    from poinsot import AccuracyWarning, InvalidInputError
    from poinsot.scenarios import parse_scenario

    text = (EXAMPLES / "coning.toml").read_text() + f"\n[attitude]\nmatrix = {MATRIX}\n"
    with pytest.raises(InvalidInputError, match=r"orthogonal within 1e-06.*Raise `tolerance`"):
        parse_scenario(text)
    with pytest.warns(AccuracyWarning, match=r"projected onto the nearest rotation"):
        s = parse_scenario(text + "tolerance = 1e-3\n")
    m = np.array(eval(MATRIX))
    np.testing.assert_allclose(s.attitude.rotation.as_matrix(), nearest_rotation(m), atol=1e-14)


def test_convert_matrix_tolerance_flag(capsys):
    values = [str(x) for x in np.array(eval(MATRIX)).ravel()]
    code, _, err = run(capsys, "convert", "matrix", "quat", *values)
    assert code == 2 and "--tolerance" in err
    code, out, err = run(capsys, "convert", "matrix", "quat", *values, "--tolerance", "1e-3")
    assert code == 0 and "warning: convert: the matrix is not orthogonal" in err
    want = SciPyRotation.from_matrix(nearest_rotation(np.array(eval(MATRIX))))
    got = SciPyRotation.from_quat([float(x) for x in out.split()], scalar_first=True)
    assert (want.inv() * got).magnitude() < 1e-14


@pytest.mark.parametrize(
    ("argv", "wanted", "internal"),
    [
        (["convert", "euler:XYQ", "quat", "1", "2", "3"], "euler:SEQ", "`seq`"),
        (["inertia", "box", "--mass", "1", "--dims", "1", "-2", "1"], "--dims value 2", "`b`"),
        (["inertia", "cylinder", "--mass", "1", "--dims", "0.1", "0"], "--dims value 2", "`h"),
        (["inertia", "box", "--mass", "-1", "--dims", "1", "2", "1"], "--mass", "`mass`"),
    ],
)
def test_messages_use_user_facing_names(capsys, argv, wanted, internal):
    code, _, err = run(capsys, *argv)
    assert code == 2 and wanted in err and internal not in err


def test_no_round_off_noise_in_printed_numbers(capsys):
    code, out, _ = run(capsys, "convert", "axis-angle", "matrix", "1", "0", "0", "90", "--degrees")
    assert code == 0 and out.split() == ["1", "0", "0", "0", "0", "-1", "0", "1", "0"]
    code, out, _ = run(capsys, "inertia", "rod", "--mass", "1", "--dims", "2")
    axes = out.split("principal axes (columns, in body axes):")[1].split()
    assert code == 0 and all(a in ("0", "1", "-1") for a in axes)
    code, out, _ = run(capsys, "convert", "euler:ZXZ", "rotvec", "90", "0", "0", "--degrees")
    assert out.split() == ["0", "0", "90"]


def test_convert_quaternion_sign_is_canonical(capsys):
    rng = np.random.default_rng(5)
    for q in rng.normal(size=(20, 4)):
        code, out, _ = run(capsys, "convert", "quat", "quat", *(repr(float(x)) for x in q))
        got = np.array([float(x) for x in out.split()])
        want = q / np.linalg.norm(q) * np.sign(q[0])  # w >= 0
        assert code == 0 and got[0] >= 0
        np.testing.assert_allclose(got, want, atol=1e-14)
        code, out, _ = run(capsys, "convert", "quat", "quat:xyzw", *(repr(float(x)) for x in q))
        np.testing.assert_allclose([float(x) for x in out.split()], np.roll(want, -1), atol=1e-14)
    # w = 0: the first non-zero vector component is made positive
    code, out, _ = run(capsys, "convert", "axis-angle", "quat", "-1", "0", "0", "180", "--degrees")
    assert out.split() == ["0", "1", "0", "0"]


def test_broken_pipe_exits_0(capsys, monkeypatch):
    import poinsot.cli.convert as cli_convert

    def closed(args):
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(cli_convert, "_cmd_convert", closed)
    code, _, err = run(capsys, "convert", "quat", "quat", "1", "0", "0", "0")
    assert code == 0 and "cannot write" not in err


def test_diverging_integration_exits_2_with_advice(capsys, tmp_path):
    """rk4 with a step far beyond its stability limit (a fast spin): a real divergence."""
    text = (EXAMPLES / "tennis_racket.toml").read_text()
    text = text.replace("vector = [0.1, 12.0, 0.1]", "vector = [300.0, 2000.0, 300.0]")
    text = text.replace('method = "exact"', 'method = "rk4"').replace("step = 0.002", "step = 0.5")
    text = text.replace("duration = 6.0", "duration = 300.0")
    text = text.replace('reference = "midpoint"', "")
    p = tmp_path / "fast.toml"
    p.write_text(text)
    code, _, err = run(capsys, "run", p, "--out", tmp_path / "o", "--no-report")
    assert code == 2 and "the integration failed" in err and "max_step" in err
    assert "Traceback" not in err and not (tmp_path / "o").exists()


def test_user_facing_text_cites_the_theory_page_not_spec(capsys, tmp_path):
    files = [
        ROOT / "docs" / "cli.md",
        ROOT / "docs" / "examples.md",
        ROOT / "docs" / "adding-a-motion.md",
    ]
    files += sorted(EXAMPLES.glob("*.toml"))
    files += sorted((ROOT / "src" / "poinsot" / "scenarios").rglob("*.py"))
    files += [ROOT / "src" / "poinsot" / "scenarios" / "tennis_racket.toml"]
    files += sorted((ROOT / "src" / "poinsot" / "cli").glob("*.py"))
    for f in files:
        assert "SPEC" not in f.read_text(), f
    code, out, err = run(
        capsys, "demo", "--out", tmp_path / "d", "--no-figures", "--duration", "0.5"
    )
    assert code == 0 and "SPEC" not in out + err and "docs/theory.md §" in out
    # the demo ends by saying where its report is, as a path a browser opens
    last = out.splitlines()[-1]
    assert last.startswith("report: file://"), last
    assert Path(last.removeprefix("report: file://")) == (tmp_path / "d" / "report.html").resolve()
    assert (tmp_path / "d" / "report.html").is_file()


_FULL_DISK = """
import resource, signal, sys
from poinsot.cli import main
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG
resource.setrlimit(resource.RLIMIT_FSIZE, (int(sys.argv[1]), resource.RLIM_INFINITY))
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.parametrize("existing", [False, True])
def test_a_run_that_cannot_write_keeps_nothing_and_names_the_folder(tmp_path, existing):
    """Issue 38: a full disk during `run` left four files without summary.json, so a
    retry needed --force. The file-size limit of the OS (RLIMIT_FSIZE, in a subprocess)
    makes a real write fail part-way, as a full disk does."""
    import subprocess
    import sys

    out = tmp_path / "out"
    argv = [
        "run",
        "--no-figures",
        "--duration",
        "2",
        "--out",
        str(out),
        str(EXAMPLES / "tennis_racket.toml"),
    ]
    if existing:  # a forced rerun over a complete earlier run keeps that run intact
        assert main([*argv, "--quiet"]) == 0
        before = {p.name: p.read_bytes() for p in out.iterdir()}
        argv.append("--force")
    proc = subprocess.run(
        [sys.executable, "-c", _FULL_DISK, "20000", *argv],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert f"cannot write the outputs: {out}" in proc.stderr, proc.stderr
    assert "File too large" in proc.stderr and "nothing of this run was kept" in proc.stderr
    if existing:
        assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    else:
        assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name != "out"] == []  # no staging left
    # the retry needs nothing more than the same command
    assert main([*argv, "--quiet"]) == 0 and (out / "summary.json").is_file()


def _first_chart(page: str) -> int:
    """Where the viewer (its scene and charts) starts in report.html."""
    return page.index('<div id="poinsot-scene-col">')


def test_report_header_marks_accuracy_and_lists_warnings_first(capsys, tmp_path):
    """issue 38: the warnings were ~1500 px down the page, under the charts; the header
    line now says "accuracy: N warnings" (N = the summary's warnings) and lists them
    before the first chart; an accurate run says "accuracy: ok"."""
    import html

    out = tmp_path / "o"
    code, _, _ = run(capsys, "run", racket(tmp_path), "--out", out, "--no-figures")
    assert code == 0
    warnings = json.loads((out / "summary.json").read_text())["accuracy"]["warnings"]
    assert len(warnings) >= 2
    page = (out / "report.html").read_text()
    h1 = re.search(r"<h1>(.*?)</h1>", page, flags=re.S).group(1)
    assert f"accuracy: {len(warnings)} warnings" in h1
    chart = _first_chart(page)
    for w in warnings:
        assert 0 < page.index(html.escape(w)) < chart
    assert page.count("<h2>Accuracy warnings</h2>") == 1  # one list, not again below

    good = tmp_path / "good"
    code, _, _ = run(
        capsys, "run", EXAMPLES / "tennis_racket.toml", "--duration", 2.0, "--out", good,
        "--no-figures",
    )  # fmt: skip
    assert code == 0
    assert json.loads((good / "summary.json").read_text())["accuracy"]["warnings"] == []
    page = (good / "report.html").read_text()
    h1 = re.search(r"<h1>(.*?)</h1>", page, flags=re.S).group(1)
    assert "accuracy: ok" in h1 and "warning" not in h1
    assert "Accuracy warnings" not in page


def test_check_estimates_what_the_run_does(capsys):
    """Issue 38: `check examples/double_pendulum.toml` said ~2.7 s while a run took
    18-22 s (the adaptive Radau reference counted as one step per sample, the outputs
    not at all). The estimate now has a part per method (an adaptive one measured on a
    short first piece) and the outputs, and its total is their sum."""
    from poinsot.scenarios import estimate_cost, load_scenario

    s = load_scenario(EXAMPLES / "double_pendulum.toml")
    static = estimate_cost(s, duration=4.0)
    cost = estimate_cost(s, duration=4.0, measure=True, outputs=True)
    assert [m for m, _ in cost.methods] == ["DOP853", "Radau"]
    assert cost.measured == ("DOP853", "Radau")
    assert cost.outputs_seconds > 0
    assert cost.seconds == pytest.approx(sum(x for _, x in cost.methods) + cost.outputs_seconds)
    assert static.measured == () and static.outputs_seconds == 0
    # the pieces ran: the same samples and steps are reported as without measuring
    assert (cost.samples, cost.steps) == (static.samples, static.steps)
    code, out, _ = run(capsys, "check", EXAMPLES / "double_pendulum.toml", "--duration", "4")
    line = out.splitlines()[1]
    assert code == 0 and "Radau ~" in line and "measured on a piece" in line
    assert "outputs ~" in line


def test_fixed_step_methods_are_not_measured():
    from poinsot.integrators import INTEGRATORS
    from poinsot.scenarios import estimate_cost, load_scenario

    s = load_scenario(EXAMPLES / "satellite_torque.toml")
    sim = s.simulation
    cost = estimate_cost(s, measure=True)
    methods = [sim.method] + ([sim.reference] if sim.reference else [])
    assert not INTEGRATORS[sim.method].adaptive  # a fixed-step method: from its table
    assert sim.method not in cost.measured
    # exactly the adaptive ones among the run's methods are timed on a piece
    assert set(cost.measured) == {m for m in methods if INTEGRATORS[m].adaptive}


def test_the_summary_reports_solve_reference_and_compile_time_apart():
    """summary.json counted numba's compile time as the method's time (85 s for a cold
    Kovalevskaya run, 2.7 s warm): the parts are now apart and add up to wall_time_s."""
    from poinsot.scenarios import load_scenario, simulate_scenario

    r = simulate_scenario(load_scenario(EXAMPLES / "double_pendulum.toml"), duration=1.0)
    run_ = r.summary["run"]
    parts = [run_["solve_time_s"], run_["reference_time_s"], run_["compile_time_s"]]
    assert all(x is not None and x >= 0 for x in parts)
    assert run_["wall_time_s"] == pytest.approx(sum(parts))
    for k in ("solve_time_s", "reference_time_s", "compile_time_s"):
        assert run_["units"][k] == "s"
    assert "Radau: " in r.describe() and "s)" in r.describe().split("Radau: ")[1]


def test_compile_seconds_counts_a_compilation_and_nothing_else():
    import time

    from numba import njit

    from poinsot._jit import compile_seconds

    f = njit(lambda x: x * 5.0)
    c0, t0 = compile_seconds(), time.perf_counter()
    f(1.0)  # compiles
    took, counted = time.perf_counter() - t0, compile_seconds() - c0
    assert 0 < counted <= took
    c0 = compile_seconds()
    f(2.0)  # compiled: nothing to count
    assert compile_seconds() == c0
