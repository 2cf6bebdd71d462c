"""The ``gyrostat`` scenario kind (docs/theory.md §10.1): a constant rotor (the exact
dual-spin solution against DOP853) and reaction wheels (simulate_wheels), through the
CLI and the scenario API; bad tables name their key."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from poinsot.cli import main
from poinsot.scenarios import parse_scenario
from poinsot.scenarios._toml import ScenarioError
from poinsot.scenarios.solve import simulate_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
DUAL = (EXAMPLES / "dual_spin.toml").read_text()
SLEW = (EXAMPLES / "wheel_slew.toml").read_text()


def test_dual_spin_example_through_the_cli(tmp_path, capsys):
    out = tmp_path / "dual"
    code = main(["run", str(EXAMPLES / "dual_spin.toml"), "--out", str(out), "--duration", "10",
                 "--no-figures"])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 0, text
    assert "unstable for the rigid body (h = 0), stable with the rotor" in text
    summary = json.loads((out / "summary.json").read_text())
    res = summary["results"]
    assert res["spin_stable"] is True and res["spin_stable_without_rotor"] is False
    assert res["regime"] == "four_roots" and res["period"] > 0
    assert (out / "report.html").is_file() and (out / "reference.csv").is_file()


def test_wheel_slew_example_through_the_cli(tmp_path, capsys):
    """Rest to rest: the wheel peaks below its 500 rpm limit, the body turns ~1.2 rad
    and stops, K stays zero; the report charts the momentum exchange and the limits."""
    out = tmp_path / "slew"
    code = main(["run", str(EXAMPLES / "wheel_slew.toml"), "--out", str(out), "--no-figures"])
    assert code == 0, capsys.readouterr()
    cols = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    limit = 500.0 * np.pi / 30.0
    peak = np.max(np.abs(cols["wheel_speed_0"]))
    assert 0.9 * limit < peak <= limit
    angle = 2.0 * np.arctan2(cols["qz"][-1], cols["qw"][-1])
    assert abs(angle + 1.2) < 0.01 and abs(cols["wz"][-1]) < 1e-12
    assert np.max(np.abs(np.column_stack([cols["Kx"], cols["Ky"], cols["Kz"]]))) < 1e-12
    html = (out / "report.html").read_text()
    assert "wheel speeds and their limits" in html and "momentum exchange" in html


def test_exact_dual_spin_matches_dop853_and_conserves_k():
    res = simulate_scenario(parse_scenario(DUAL, source="dual_spin.toml"), duration=20.0)
    tr, ref = res.trajectory, res.reference
    assert tr.method == "exact" and ref.method == "dop853"
    acc = res.summary["accuracy"]
    diffs = acc["comparison"]["differences"]
    # measured: attitude 4e-12 rad, omega 1e-12 rad/s over 20 s
    assert diffs["attitude"]["max"] < 1e-9 and diffs["omega"]["max"] < 1e-10
    for key in ("energy", "momentum_norm", "momentum_vector"):
        assert acc["invariants"][key]["max_relative_drift"] < 1e-13, key
        assert acc["reference_invariants"][key]["max_relative_drift"] < 1e-10, key
    # the spin stays near y: stable (the rigid body would flip)
    assert np.min(tr.omega[:, 1]) > 0.9


def test_held_wheel_stops_at_its_limit():
    """A command that would spin the wheel past max_speed: the library holds it there;
    K is still conserved."""
    text = SLEW.replace("times = [0.0, 20.0, 60.0, 80.0]", "times = [0.0, 40.0, 60.0, 80.0]")
    res = simulate_scenario(parse_scenario(text, source="s.toml"), duration=60.0)
    tr = res.trajectory
    limit = 500.0 * np.pi / 30.0
    assert np.max(np.abs(tr.wheel_speed)) <= limit * (1 + 1e-8)
    assert np.sum(np.abs(tr.wheel_speed[:, 0]) >= limit * (1 - 1e-9)) > 10
    inv = res.summary["accuracy"]["invariants"]
    # measured 7.7e-10: the held speed's overshoot (~1e-9) clipped at the limit between pieces
    assert inv["momentum_vector"]["max_relative_drift"] < 1e-8


@pytest.mark.parametrize(
    ("text", "old", "new", "key"),
    [
        (DUAL, "h = [0.0, 150.0, 0.0]", "h = [0.0, 0.0, 0.0]", "rotor.h"),
        (DUAL, "h = [0.0, 150.0, 0.0]", "h = [0.0, 150.0]", "rotor.h"),
        (DUAL, "h = [0.0, 150.0, 0.0]", "hh = [0.0, 150.0, 0.0]", "rotor.hh"),
        (DUAL, "h = [0.0, 150.0, 0.0]", "h = [0.0, 150.0, 1.0]", "simulation.method"),
        (SLEW, "axes = [[0.0, 0.0, 1.0]]", "axes = [[0.0, 0.0, 2.0]]", "wheels.axes"),
        (SLEW, "inertia = 0.02 ", "inertia = -0.02 ", "wheels.inertia"),
        (SLEW, "inertia = 0.02 ", "inertia = 60.0 ", "wheels.inertia"),
        (SLEW, "max_torque = 0.06", "max_torque = [0.06, 0.1]", "wheels.max_torque"),
        (SLEW, "speed0 = [0.0]", "speed0 = [600.0]", "wheels.speed0"),
        (SLEW, 'speed_units = "rpm"', 'speed_units = "rpn"', "wheels.speed_units"),
        (
            SLEW,
            "times = [0.0, 20.0, 60.0, 80.0]",
            "times = [1.0, 20.0, 60.0, 80.0]",
            "wheels.command.times",
        ),  # fmt: skip
        (
            SLEW,
            "times = [0.0, 20.0, 60.0, 80.0]",
            "times = [0.0, 60.0, 20.0, 80.0]",
            "wheels.command.times",
        ),  # fmt: skip
        (
            SLEW,
            "[[0.05], [0.0], [-0.05], [0.0]]",
            "[[0.05], [0.0], [-0.05]]",
            "wheels.command.torques",
        ),  # fmt: skip
        (
            SLEW,
            "[[0.05], [0.0], [-0.05], [0.0]]",
            '[[0.05], [0.0], [-0.05], ["x"]]',
            "wheels.command.torques",
        ),  # fmt: skip
        (SLEW, 'method = "dop853"', 'method = "exact"', "simulation.method"),
        (SLEW, "[wheels]", "[rotor]\nh = [0.0, 0.0, 1.0]\n\n[wheels]", "wheels"),
    ],
)
def test_bad_values_name_the_key(text, old, new, key):
    assert old in text
    bad = text.replace(old, new)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(bad, source="bad.toml")
    msg = str(info.value)
    assert msg.startswith("bad.toml:") and f"`{key}`" in msg, msg
