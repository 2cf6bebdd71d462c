"""Scenario kinds of particles (docs/theory.md §9): free fall, Foucault, central orbit.

The physics of the outputs is checked against independent truths: the first-order
eastward deflection (1/3) Omega g t^3 cos(lat) (relative error O((Omega t)^2)), the
Foucault rate -Omega sin(lat) measured from the simulated swing, the beta/r^2
apsidal angle pi / sqrt(1 + 2 beta m / L^2) and Kepler's period 2 pi a^(3/2)/sqrt(mu),
with a = -mu / (2E) computed here from the file's state.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from poinsot.scenarios import load_scenario, parse_scenario, run_scenario, simulate_scenario
from poinsot.scenarios._toml import ScenarioError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
OMEGA_EARTH = 7.2921159e-5


def test_free_fall_example_lands_east_by_the_first_order_deflection():
    s = load_scenario(EXAMPLES / "free_fall.toml")
    r = simulate_scenario(s)
    h, g, lat = 158.0, 9.81, math.radians(50.9)
    fall = math.sqrt(2 * h / g)
    first = OMEGA_EARTH * g * fall**3 * math.cos(lat) / 3
    res = r.summary["results"]
    assert res["eastward_deflection"] == pytest.approx(first, rel=1e-13)
    assert res["fall_time"] == pytest.approx(fall, rel=1e-14)
    # the simulated east displacement when the stone has dropped h (relative position,
    # east-north-up axes, of the kind's own PointTrajectory)
    pos = r.trajectory.position
    k = np.argmin(np.abs(pos[:, 2]))
    assert abs(pos[k, 2]) < 0.05  # the output grid reaches the ground
    # first order at the reached drop; neglected terms (Omega t)^2 ~ 2e-7
    d = OMEGA_EARTH * math.cos(lat) * math.sqrt(8 * (h - pos[k, 2]) ** 3 / g) / 3
    assert pos[k, 0] == pytest.approx(d, rel=2e-6)
    acc = r.summary["accuracy"]["invariants"]
    assert acc["jacobi_integral"]["max_relative_drift"] < 1e-9  # observed 2.5e-15


def test_foucault_example_plane_turns_at_minus_omega_sin_lat(tmp_path):
    s = load_scenario(EXAMPLES / "foucault.toml")
    result, files = run_scenario(s, tmp_path / "f", report=False, duration=200.0)
    assert "swing_plane.png" in {p.name for p in files}
    from poinsot.dynamics import swing_plane_angles

    tr = result.trajectory
    r, v = tr.position, tr.velocity  # relative to the Earth (east, north, up)
    tt, ang = swing_plane_angles(tr.t, r, v)
    rate = np.polyfit(tt, ang, 1)[0]
    om = 3.64605795e-3
    expected = -om * math.sin(math.radians(48.85))
    assert rate == pytest.approx(expected, rel=1e-4)  # extremes interpolated on 0.1 s samples
    summary = json.loads((tmp_path / "f" / "summary.json").read_text())
    assert summary["results"]["precession_rate"] == pytest.approx(expected, rel=1e-14)
    assert summary["results"]["units"]["precession_rate"] == "rad/s"
    # in space the swing stays in one plane: the inertial path is (nearly) a line
    x = tr.inertial_position[:, :2]
    ex = x[np.argmax(np.linalg.norm(x, axis=1))]
    ex = ex / np.linalg.norm(ex)
    across = np.abs(x @ np.array([-ex[1], ex[0]]))
    assert np.max(across) < 0.01 * 3.0


def test_precessing_orbit_example_apsidal_angle():
    s = load_scenario(EXAMPLES / "precessing_orbit.toml")
    r = simulate_scenario(s, duration=10.0)
    res = r.summary["results"]
    L, m, beta = 1.2, 1.0, 0.05
    assert res["apsidal_angle_over_pi"] == pytest.approx(
        1 / math.sqrt(1 + 2 * beta * m / L**2), rel=1e-12
    )
    assert res["closed"] is False and res["bound"] is True
    drift = r.summary["accuracy"]["invariants"]
    assert drift["energy"]["max_relative_drift"] < 1e-9
    assert drift["angular_momentum"]["max_relative_drift"] < 1e-12


def test_kepler_orbit_example_period_and_reference():
    s = load_scenario(EXAMPLES / "kepler_orbit.toml")
    r = simulate_scenario(s, duration=12.0)
    x0, v0 = np.array([1.0, 0.2, 0.1]), np.array([0.1, 1.1, 0.3])
    energy = 0.5 * v0 @ v0 - 1 / np.linalg.norm(x0)
    a = -1 / (2 * energy)
    res = r.summary["results"]
    assert res["kepler_period"] == pytest.approx(2 * math.pi * a**1.5, rel=1e-13)
    assert res["radial_period"] == pytest.approx(2 * math.pi * a**1.5, rel=1e-12)
    assert res["eccentricity"] == pytest.approx(
        np.linalg.norm(np.cross(v0, np.cross(x0, v0)) - x0 / np.linalg.norm(x0)), rel=1e-12
    )
    # the integrated reference against the closed form (positions)
    np.testing.assert_allclose(r.reference.position, r.trajectory.position, atol=1e-9)


def test_bad_tables_name_file_key_and_line():
    with pytest.raises(ScenarioError, match="latitude"):
        parse_scenario(
            "[free_fall]\nheight = 10.0\nlatitude = 95.0\n"
            '[simulation]\nduration = 1.0\nsamples = 3\nmethod = "adaptive"\n'
        )
    with pytest.raises(ScenarioError, match="fall time"):
        parse_scenario(
            "[free_fall]\nheight = 10.0\nlatitude = 45.0\n"
            '[simulation]\nduration = 100.0\nsamples = 3\nmethod = "adaptive"\n'
        )
    with pytest.raises(ScenarioError, match="potential term"):
        parse_scenario(
            "[orbit]\nmass = 1.0\nenergy = -0.5\nangular_momentum = 1.0\n"
            '[simulation]\nduration = 1.0\nsamples = 3\nmethod = "adaptive"\n'
        )
    with pytest.raises(ScenarioError, match="no orbit"):
        parse_scenario(
            "[orbit]\nmu = 1.0\nenergy = -0.6\nangular_momentum = 1.0\n"
            '[simulation]\nduration = 1.0\nsamples = 3\nmethod = "adaptive"\n'
        )
    with pytest.raises(ScenarioError, match="pure attractive Kepler"):
        parse_scenario(
            "[orbit]\nmu = 1.0\nbeta = 0.1\nenergy = -0.3\nangular_momentum = 1.0\n"
            '[simulation]\nduration = 1.0\nsamples = 3\nmethod = "exact"\n'
        )


def test_report_embeds_the_orbit_figures(tmp_path):
    s = load_scenario(EXAMPLES / "precessing_orbit.toml")
    _, files = run_scenario(s, tmp_path / "o", duration=10.0)
    names = {p.name for p in files}
    assert {"orbit.png", "effective_potential.png", "report.html"} <= names
    html = (tmp_path / "o" / "report.html").read_text()
    assert "The orbit, apsides marked" in html and html.count("<svg") >= 2


def test_precessing_orbit_report_draws_the_line_of_apsides_turning():
    """The report's guide runs through the latest pericentre: on the precessing orbit
    it turns by 2 Phi - 2 pi at each passage (apsidal angle Phi from the closed form,
    docs/theory.md §9), within the angle swept between two samples at pericentre."""
    from pathlib import Path

    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "precessing_orbit.toml"))
    guide = res.scenario.adapter.report(res).drawing.guides
    (ends,) = guide.values()
    peri = ends[:, 1]
    angle = np.unwrap(np.arctan2(peri[:, 1], peri[:, 0]))
    steps = np.diff(angle)
    jumps = steps[np.abs(steps) > 1e-9]
    r = res.summary["results"]
    assert jumps.size == 2  # pericentres at 20, 40, 60 s (radial period 20.1 s)
    want = 2 * r["apsidal_angle"] - 2 * np.pi
    tr = res.trajectory
    sweep = np.max(np.linalg.norm(np.diff(tr.position, axis=0), axis=1)) / r["pericentre"]
    np.testing.assert_allclose(jumps, want, atol=sweep)
    np.testing.assert_allclose(np.linalg.norm(peri, axis=1), r["pericentre"], rtol=1e-3)
