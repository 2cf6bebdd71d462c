"""The ``bouncing`` scenario kind (docs/theory.md §11.3): the shipped examples through
the CLI against closed forms, the report, and errors that name the key."""

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
BALL = (EXAMPLES / "bouncing_ball_spin.toml").read_text()
BOX = (EXAMPLES / "tumbling_box.toml").read_text()


def test_ball_example_comes_back_rolling_at_the_closed_form_speed():
    res = simulate_scenario(parse_scenario(BALL, source="ball.toml"))
    tr = res.trajectory
    g, radius, e = 9.80665, 0.1, 0.5
    t1 = np.sqrt(2 * (1.0 - radius) / g)
    after = (tr.t > t1 + 1e-9) & (tr.t < t1 + 0.2)
    # the horizontal velocity after the first impact: (5 v - 2 R |w|) / 7 = -1 m/s
    np.testing.assert_allclose(tr.velocity[after, 0], (5 * 1.0 - 2 * radius * 60.0) / 7,
                               atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(tr.omega[after, 1], tr.velocity[after, 0] / radius, atol=1e-8)
    np.testing.assert_allclose(tr.velocity[after, 2] + g * (tr.t[after] - t1), e * g * t1,
                               atol=1e-9)  # fmt: skip
    assert res.summary["accuracy"]["invariants"]["height"]["final"] >= radius - 1e-12


def test_box_example_through_the_cli(tmp_path, capsys):
    out = tmp_path / "box"
    code = main(["run", str(EXAMPLES / "tumbling_box.toml"), "--out", str(out), "--no-figures"])
    text = capsys.readouterr().out
    assert code == 0, text
    summary = json.loads((out / "summary.json").read_text())
    energy = summary["accuracy"]["invariants"]["mechanical_energy"]
    assert energy["final"] < energy["initial"]  # lost at the impacts
    cols = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    e = cols["mechanical_energy"]
    assert np.all(np.diff(e) <= 1e-9 * e[0])  # never gained (Newton, here)
    html = (out / "report.html").read_text()
    assert "heights" in html and "lowest point" in html


def test_bouncing_needs_a_shape_that_touches():
    bad = BOX.replace('shape = "box"\ndims = [0.3, 0.2, 0.1]     # edges a, b, c (m)',
                      'shape = "cylinder"\ndims = [0.1, 0.3]')  # fmt: skip
    with pytest.raises(ScenarioError, match="shape"):
        parse_scenario(bad, source="bad.toml")
    with pytest.raises(ScenarioError, match="restitution"):
        parse_scenario(BOX.replace("restitution = 0.5", "restitution = 1.5"), source="bad.toml")
