"""The ``spacecraft`` scenario kind (docs/theory.md §10.2, §10.3): the examples through
the CLI, the exact libration check, and errors that name the key."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from poinsot.cli import main
from poinsot.dynamics import PitchLibration
from poinsot.scenarios import parse_scenario
from poinsot.scenarios._toml import ScenarioError
from poinsot.scenarios.solve import simulate_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LIBRATION = (EXAMPLES / "gravity_gradient_libration.toml").read_text()
NADIR = (EXAMPLES / "nadir_pointing_wheels.toml").read_text()


def test_libration_follows_the_exact_pendulum():
    """The integrated 3-D attitude's pitch relative to LVLH against
    PitchLibration (Jacobi functions, theory §10.2): measured 3.7e-8 of the
    amplitude at DOP853 rtol 1e-10 over two orbits; roll and yaw stay zero."""
    res = simulate_scenario(parse_scenario(LIBRATION, source="lib.toml"))
    s = res.scenario
    lib = PitchLibration([80.0, 100.0, 40.0], s.spec.orbit.mean_motion,
                         theta0=np.radians(25.0), rate0=0.0)  # fmt: skip
    from poinsot.scenarios.kinds.spacecraft import spacecraft_of

    rel = spacecraft_of(s).relative(res.trajectory).as_euler("YXZ")
    np.testing.assert_allclose(rel[:, 0], lib.theta(res.trajectory.t), rtol=0, atol=1e-6)
    assert np.max(np.abs(rel[:, 1:])) < 1e-9
    drift = res.summary["accuracy"]["invariants"]["pitch"]["max_relative_drift"]
    assert drift < 1e-6
    assert res.summary["results"]["gravity_gradient_region"] == "lagrange"


def test_nadir_example_through_the_cli(tmp_path, capsys):
    """Quaternion PD through four wheels brings the body to LVLH: the pointing error
    falls from ~28 deg to 2e-4 deg at 600 s (the PD law has no integral term: the
    disturbances hold a small error; asserted < 1e-2 deg); the wheels stay within their limits; the
    report draws the nadir direction and charts the wheel speeds."""
    out = tmp_path / "nadir"
    code = main(["run", str(EXAMPLES / "nadir_pointing_wheels.toml"), "--out", str(out),
                 "--no-figures"])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 0, text
    cols = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    err = np.degrees(cols["pointing_error"])
    assert err[0] > 20.0 and err[-1] < 1e-2
    limit = 6000.0 * np.pi / 30.0
    speeds = np.column_stack([cols[f"wheel_speed_{i}"] for i in range(4)])
    assert np.max(np.abs(speeds)) < limit
    html = (out / "report.html").read_text()
    assert "nadir (to the Earth)" in html and "wheel speeds and their limits" in html
    summary = json.loads((out / "summary.json").read_text())
    assert summary["results"]["orbit_period"] == pytest.approx(5801.0, rel=1e-3)


@pytest.mark.parametrize(
    ("text", "old", "new", "key"),
    [
        (LIBRATION, "altitude = 500e3", "altitude = -1.0", "orbit.altitude"),
        (LIBRATION, 'frame = "lvlh"', 'frame = "eci"', "orbit.frame"),
        (LIBRATION, "altitude = 500e3", "a = 7e6\naltitude = 500e3", "orbit.altitude"),
        (
            LIBRATION,
            "gravity_gradient = true",
            "gravity_gradient = 1",
            "environment.gravity_gradient",
        ),
        (NADIR, 'law = "pd"', 'law = "lqr"', "control.law"),
        (NADIR, "kp = 0.5", "kp = -0.5", "control.kp"),
        (NADIR, 'law = "pd"', 'law = "bdot"', "control.kp"),
        (
            NADIR,
            'law = "pd"\nkp = 0.5                      # N m\nkd = 7.0 ',
            'law = "none"\n#',
            "wheels",
        ),
    ],
)
def test_bad_values_name_the_key(text, old, new, key):
    assert old in text
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text.replace(old, new), source="bad.toml")
    msg = str(info.value)
    assert msg.startswith("bad.toml:") and f"`{key}`" in msg, msg
