"""The `poinsot` command, called in-process: exit codes, messages, outputs."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot.cli import ProgressBar, main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CSVS = ("trajectory.csv", "reference.csv")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def numbers(text: str) -> np.ndarray:
    return np.array([float(x) for x in text.split()])


def canon(q):
    q = np.asarray(q, dtype=float)
    return q if q[0] >= 0 else -q


# --------------------------------------------------------------------------- help, usage
@pytest.mark.parametrize("command", ["run", "demo", "check", "convert", "inertia"])
def test_help_has_example(capsys, command):
    code, out, _ = run(capsys, command, "--help")
    assert code == 0
    assert "example" in out and f"poinsot {command}" in out


def test_top_level_help_and_version(capsys):
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "run" in out and "convert" in out
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.startswith("poinsot ")


def test_usage_errors_exit_2(capsys):
    code, _, err = run(capsys)
    assert code == 2 and "required: COMMAND" in err
    code, _, err = run(capsys, "fly")
    assert code == 2 and "invalid choice" in err
    code, _, err = run(capsys, "run")
    assert code == 2 and "SCENARIO.toml" in err


# --------------------------------------------------------------------------- convert
def test_convert_issue_example_against_scipy(capsys):
    code, out, err = run(capsys, "convert", "euler:ZXZ", "quat", "30", "45", "60", "--degrees")
    assert code == 0 and err == ""
    x, y, z, w = SciPyRotation.from_euler("ZXZ", [30, 45, 60], degrees=True).as_quat()
    np.testing.assert_allclose(canon(numbers(out)), canon([w, x, y, z]), atol=1e-14)


REPRS = [
    "quat",
    "quat:xyzw",
    "matrix",
    "rotvec",
    "axis-angle",
    "euler:ZXZ",
    "euler:zyx",
    "euler:krylov",
    "gibbs",
    "mrp",
]


@pytest.mark.parametrize("target", REPRS)
@pytest.mark.parametrize("degrees", [False, True])
def test_convert_round_trip_every_representation(capsys, target, degrees):
    q = canon(np.array([0.8, 0.2, -0.4, 0.4]) / np.linalg.norm([0.8, 0.2, -0.4, 0.4]))
    flag = ["--degrees"] if degrees else []
    code, out, _ = run(capsys, "convert", "quat", target, *map(repr, q.tolist()), *flag)
    assert code == 0
    values = out.split()
    code, back, _ = run(capsys, "convert", target, "quat", *values, *flag)
    assert code == 0
    np.testing.assert_allclose(canon(numbers(back)), q, atol=1e-13)


def test_convert_values_against_scipy(capsys):
    r = SciPyRotation.from_rotvec([0.3, -0.5, 0.9])
    x, y, z, w = r.as_quat()
    q = [repr(float(v)) for v in (w, x, y, z)]
    _, out, _ = run(capsys, "convert", "quat", "matrix", *q)
    np.testing.assert_allclose(numbers(out).reshape(3, 3), r.as_matrix(), atol=1e-14)
    _, out, _ = run(capsys, "convert", "quat", "rotvec", *q, "--degrees")
    np.testing.assert_allclose(numbers(out), r.as_rotvec(degrees=True), atol=1e-12)
    _, out, _ = run(capsys, "convert", "quat", "euler:zyx", *q)
    np.testing.assert_allclose(numbers(out), r.as_euler("zyx"), atol=1e-14)
    _, out, _ = run(capsys, "convert", "quat", "mrp", *q)
    np.testing.assert_allclose(numbers(out), r.as_mrp(), atol=1e-14)
    _, out, _ = run(capsys, "convert", "rotvec", "axis-angle", "0", "0", "-90", "--degrees")
    axis_angle = numbers(out)
    np.testing.assert_allclose(axis_angle, [0, 0, -1, 90], atol=1e-12)


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["convert", "euler", "quat", "1", "2", "3"], "unknown source representation 'euler'"),
        (["convert", "quat", "dcm", "1", "0", "0", "0"], "unknown target representation 'dcm'"),
        (["convert", "quat", "matrix", "1", "0", "0"], "quat takes 4 values, found 3"),
        (["convert", "rotvec", "quat", "1", "x", "0"], "expected numbers as VALUES, found 'x'"),
        (["convert", "euler:ZZX", "quat", "1", "2", "3"], "ZZX"),
        (["convert", "quat", "matrix", "0", "0", "0", "0"], "zero"),
        (["convert", "matrix", "quat", "1", "0", "0", "0", "1", "0", "0", "0", "-1"], "det"),
        (["convert", "axis-angle", "quat", "0", "0", "0", "1"], "axis"),
    ],
)
def test_convert_errors_exit_2_without_traceback(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.startswith("poinsot: error: ") and match in err
    assert "Traceback" not in err


def test_convert_negative_values_are_not_options(capsys):
    code, out, _ = run(capsys, "convert", "rotvec", "quat", "-1.0", "0", "0")
    assert code == 0
    np.testing.assert_allclose(numbers(out), [np.cos(0.5), -np.sin(0.5), 0, 0], atol=1e-15)


def test_gimbal_lock_warning_is_reported(capsys):
    code, out, err = run(capsys, "convert", "euler:ZXZ", "euler:ZXZ", "10", "0", "20", "--degrees")
    assert code == 0 and "poinsot: warning:" in err
    np.testing.assert_allclose(numbers(out), [30, 0, 0], atol=1e-12)  # third angle set to 0


# --------------------------------------------------------------------------- inertia
def test_inertia_box_textbook(capsys):
    code, out, _ = run(capsys, "inertia", "box", "--mass", "2", "--dims", "0.3", "0.2", "0.1")
    assert code == 0
    lines = out.splitlines()
    tensor = np.array([numbers(ln) for ln in lines[2:5]])
    m, a, b, c = 2.0, 0.3, 0.2, 0.1
    np.testing.assert_allclose(
        tensor, np.diag(m / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b]))
    )
    moments = numbers(lines[5].split(":")[1])
    np.testing.assert_allclose(moments, np.sort(np.diag(tensor)))
    axes = np.array([numbers(ln) for ln in lines[7:10]])
    np.testing.assert_allclose(axes.T @ tensor @ axes, np.diag(moments), atol=1e-15)
    assert np.linalg.det(axes) == pytest.approx(1.0)


def test_inertia_hollow_sphere(capsys):
    code, out, _ = run(capsys, "inertia", "sphere", "--mass", "3", "--dims", "0.5", "--hollow")
    assert code == 0 and "hollow sphere" in out
    assert numbers(out.splitlines()[2])[0] == pytest.approx(2 / 3 * 3 * 0.25)


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["inertia", "box", "--mass", "1", "--dims", "1", "2"], "a box takes 3 dimension(s)"),
        (["inertia", "box", "--mass", "1"], "found none"),
        (["inertia", "sphere", "--mass", "-1", "--dims", "1"], "mass"),
        (["inertia", "sphere", "--mass", "1", "--dims", "0"], "radius"),
        (
            ["inertia", "box", "--mass", "1", "--dims", "1", "1", "1", "--hollow"],
            "--hollow applies to a sphere or a cylinder only",
        ),
        (["inertia", "cube", "--mass", "1", "--dims", "1"], "invalid choice"),
    ],
)
def test_inertia_errors(capsys, argv, match):
    code, _, err = run(capsys, *argv)
    assert code == 2 and match in err and "Traceback" not in err


# --------------------------------------------------------------------------- check
@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_check_examples(capsys, path):
    code, out, _ = run(capsys, "check", str(path))
    assert code == 0 and out.startswith(f"ok: {path}: scenario ")


def test_check_invalid_names_file_key_line(capsys, tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(
        (EXAMPLES / "satellite_torque.toml").read_text().replace('model = "body"', 'modle = "body"')
    )
    code, out, err = run(capsys, "check", str(p))
    line = next(k for k, ln in enumerate(p.read_text().splitlines(), 1) if "modle" in ln)
    assert code == 2 and out == ""
    assert f"{p}:{line}: `torque.modle` unknown key. Did you mean `model`?" in err
    assert "Traceback" not in err
    code, _, err = run(capsys, "check", str(tmp_path / "missing.toml"))
    assert code == 2 and "missing.toml: no such file" in err
    code, out, _ = run(capsys, "check", "--quiet", str(EXAMPLES / "coning.toml"))
    assert code == 0 and out == ""


# --------------------------------------------------------------------------- run, demo
def test_run_writes_outputs_and_refuses_overwrite(capsys, tmp_path):
    out = tmp_path / "o"
    argv = [
        "run",
        str(EXAMPLES / "coning.toml"),
        "--out",
        str(out),
        "--no-report",
        "--duration",
        "0.5",
    ]
    code, stdout, err = run(capsys, *argv)
    assert code == 0 and err == ""
    assert "conventions: Hamilton quaternions, scalar first" in stdout
    assert f"outputs: {out}" in stdout
    assert {"trajectory.csv", "summary.json", "omega.png"} <= {p.name for p in out.iterdir()}
    assert not (out / "report.html").exists()
    code, _, err = run(capsys, *argv)
    assert code == 2 and "already exists" in err and "--force" in err
    code, _, _ = run(capsys, *argv, "--force", "--format", "npz", "--quiet")
    assert code == 0 and (out / "trajectory.npz").exists()


def test_run_quiet_prints_nothing(capsys, tmp_path):
    code, out, err = run(
        capsys,
        "run",
        str(EXAMPLES / "attitude_propagation.toml"),
        "--out",
        str(tmp_path / "o"),
        "--no-report",
        "--quiet",
        "--duration",
        "1",
    )
    assert code == 0 and out == "" and err == ""


def test_run_default_out_directory(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, _ = run(
        capsys, "run", str(EXAMPLES / "coning.toml"), "--no-report", "--quiet", "--duration", "0.2"
    )
    assert code == 0 and (tmp_path / "poinsot-out" / "coning" / "summary.json").exists()


def test_run_invalid_scenario_exit_2(capsys, tmp_path):
    p = tmp_path / "x.toml"
    p.write_text("[body]\nmass = -1\ninertia = [1, 1, 1]\n")
    code, _, err = run(capsys, "run", str(p), "--out", str(tmp_path / "o"))
    assert code == 2 and f"{p}:2: `body.mass`" in err and "Traceback" not in err
    code, _, err = run(
        capsys,
        "run",
        str(EXAMPLES / "coning.toml"),
        "--duration",
        "-3",
        "--out",
        str(tmp_path / "o2"),
    )
    assert code == 2 and "duration" in err


def test_demo(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "demo", "--no-report", "--no-figures", "--duration", "0.5")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("poinsot demo: tennis-racket-flip")
    assert lines[1].startswith("conventions: Hamilton quaternions, scalar first (w, x, y, z)")
    assert "vs exact: attitude differs by up to" in out
    assert "B * A = C = [0 1 0; 0 0 -1; -1 0 0]" in out  # docs/theory.md §4 worked example
    first = tmp_path / "poinsot-out" / "tennis-racket-flip"
    summary = json.loads((first / "summary.json").read_text())
    assert summary["run"]["method"] == "midpoint" and summary["run"]["reference_method"] == "exact"
    # the written files against hand values: box 0.3 x 0.1 x 0.02 m of 0.35 kg, moments
    # m (b^2 + c^2) / 12 etc.; T = w.Jw/2 and K = R J w conserved; printed difference
    tr, ref = (np.loadtxt(first / f, delimiter=",", skiprows=1) for f in CSVS)
    moments = 0.35 / 12 * np.array([0.1**2 + 0.02**2, 0.3**2 + 0.02**2, 0.3**2 + 0.1**2])
    for data in (tr, ref):
        q, w, k, energy = data[:, 1:5], data[:, 5:8], data[:, 8:11], data[:, 11]
        np.testing.assert_allclose(w[0], [0.02, 6.0, 0.02], rtol=1e-14)
        np.testing.assert_allclose(energy, 0.5 * np.sum(moments * w**2, axis=-1), rtol=1e-12)
        np.testing.assert_allclose(energy, 0.5 * np.sum(moments * w[0] ** 2), rtol=1e-12)
        k_space = SciPyRotation.from_quat(q, scalar_first=True).apply(moments * w)
        np.testing.assert_allclose(k, k_space, atol=1e-15)
        np.testing.assert_allclose(k, np.broadcast_to(k[0], k.shape), atol=1e-15)
    rq = SciPyRotation.from_quat(ref[:, 1:5], scalar_first=True)
    diff = (rq.inv() * SciPyRotation.from_quat(tr[:, 1:5], scalar_first=True)).magnitude()
    printed = float(out.split("vs exact: attitude differs by up to ")[1].split()[0])
    assert printed == pytest.approx(diff.max(), rel=1e-2) and 0 < printed < 1e-3
    # a second demo never overwrites the first: it takes a numbered directory
    code, out, _ = run(capsys, "demo", "--no-report", "--no-figures", "--duration", "0.5")
    assert code == 0 and (tmp_path / "poinsot-out" / "tennis-racket-flip-2").is_dir()
    assert "tennis-racket-flip-2" in out


def test_unexpected_failure_exit_1(capsys, monkeypatch):
    import poinsot.cli.check as cli_check

    def boom(args):
        raise RuntimeError("kaboom")

    monkeypatch.setattr(cli_check, "_cmd_check", boom)
    code, _, err = run(capsys, "check", "x.toml")
    assert code == 1
    assert "unexpected failure: RuntimeError: kaboom" in err and "--debug" in err
    assert "Traceback" not in err
    code, _, err = run(capsys, "--debug", "check", "x.toml")
    assert code == 1 and "Traceback" in err
    code, _, err = run(capsys, "check", "x.toml", "--debug")
    assert code == 1 and "Traceback" in err


# --------------------------------------------------------------------------- progress bar
class FakeTTY(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_only_on_terminal_after_delay():
    s = FakeTTY()
    bar = ProgressBar(stream=s, delay=0.0)
    bar(0.5, "integrating")
    bar(1.0, "integrating")
    bar.close()
    text = s.getvalue()
    assert "50.0%" in text and "100.0%" in text and text.endswith("\n")
    quiet = FakeTTY()
    bar = ProgressBar(stream=quiet, delay=0.0, quiet=True)
    bar(0.5, "x")
    bar.close()
    assert quiet.getvalue() == ""
    pipe = io.StringIO()  # not a terminal
    bar = ProgressBar(stream=pipe, delay=0.0)
    bar(0.5, "x")
    bar.close()
    assert pipe.getvalue() == ""
    slow = FakeTTY()
    bar = ProgressBar(stream=slow, delay=60.0)  # runs shorter than the delay show nothing
    bar(0.5, "x")
    bar.close()
    assert slow.getvalue() == ""


def test_integration_failure_exit_2_with_advice(capsys, monkeypatch):
    import poinsot.cli.check as cli_check
    from poinsot import IntegrationError

    def fail(args):
        raise IntegrationError("midpoint integration diverged: reduce `max_step`.")

    monkeypatch.setattr(cli_check, "_cmd_check", fail)
    code, _, err = run(capsys, "check", "x.toml")
    assert code == 2 and "the integration failed: midpoint integration diverged" in err
    assert "max_step" in err and "adaptive" in err  # advice
    assert "Traceback" not in err


def test_library_warning_printed_once(capsys, monkeypatch):
    import warnings

    import poinsot.cli.check as cli_check
    from poinsot import SingularityWarning

    def warn(args):
        for _ in range(3):
            warnings.warn("near the separatrix", SingularityWarning, stacklevel=1)
        return 0

    monkeypatch.setattr(cli_check, "_cmd_check", warn)
    code, _, err = run(capsys, "check", "x.toml")
    assert code == 0 and err.count("poinsot: warning: near the separatrix") == 1


def test_keyboard_interrupt_exit_130(capsys, monkeypatch):
    import poinsot.cli.check as cli_check

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_check, "_cmd_check", interrupted)
    code, _, err = run(capsys, "check", "x.toml")
    assert code == 130 and "interrupted" in err


def test_unwritable_output_exit_2(capsys, tmp_path, monkeypatch):
    import errno

    from poinsot.scenarios import output as output_mod

    def full(path, write, mode="w"):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(output_mod, "_atomic", full)
    code, _, err = run(
        capsys, "run", str(EXAMPLES / "coning.toml"), "--out", str(tmp_path / "o"), "--quiet"
    )
    assert code == 2 and "Traceback" not in err
    assert "cannot write the outputs: " in err and "No space left on device" in err
