"""The comparison with a reference run is measured on each kind's own state, in its
units (issue 19: it used to compare dummy attitudes and print 0 for every kind but
the rigid body).

Independent truths: the double pendulum solved here with SciPy ``solve_ivp`` from
its textbook equations of motion (DOP853 vs Radau at the scenario's tolerances);
a Kepler orbit from Kepler's equation solved here with ``scipy.optimize.brentq``;
the differences recomputed from the two runs' own arrays.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from poinsot.scenarios import load_scenario, parse_scenario, simulate_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
G = 9.81


def _double_pendulum_rhs(t, y):
    """Accelerations of the double pendulum with m1 = m2 = 1 kg, l1 = l2 = 1 m (angles
    from the downward vertical), the textbook closed form of Lagrange's equations."""
    a, b, ad, bd = y
    d = a - b
    den = 3.0 - math.cos(2.0 * d)
    add = (
        -3.0 * G * math.sin(a)
        - G * math.sin(a - 2.0 * b)
        - 2.0 * math.sin(d) * (bd**2 + ad**2 * math.cos(d))
    ) / den
    bdd = 2.0 * math.sin(d) * (2.0 * ad**2 + 2.0 * G * math.cos(a) + bd**2 * math.cos(d)) / den
    return [ad, bd, add, bdd]


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    """``poinsot run examples/double_pendulum.toml`` in-process: (stdout, stderr, out dir)."""
    pytest.importorskip("sympy")
    from poinsot.cli import main

    out = tmp_path_factory.mktemp("dp") / "run"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        code = main(["run", str(EXAMPLES / "double_pendulum.toml"), "--out", str(out)])
    assert code == 0, stderr.getvalue()
    return stdout.getvalue(), stderr.getvalue(), out


def test_double_pendulum_difference_matches_an_independent_solve(pendulum):
    """The chaotic double pendulum: DOP853 and Radau at rtol 1e-10 part by ~0.19 rad
    in theta1 within 20 s; the summary says so (it used to say 0), and SciPy's own
    DOP853 and Radau on the textbook equations part by the same amount."""
    from scipy.integrate import solve_ivp

    _, _, out = pendulum
    summary = json.loads((out / "summary.json").read_text())
    cmp = summary["accuracy"]["comparison"]
    assert cmp["reference"] == "Radau"
    diffs = cmp["differences"]
    assert list(diffs) == ["theta1", "theta2", "theta1_dot", "theta2_dot"]
    assert [diffs[k]["units"] for k in diffs] == ["rad", "rad", "rad/s", "rad/s"]
    s = load_scenario(EXAMPLES / "double_pendulum.toml")
    t = s.simulation.times()
    spec = s.spec
    sols = [
        solve_ivp(
            _double_pendulum_rhs,
            (t[0], t[-1]),
            [*spec.q0, *spec.qdot0],
            method=m,
            t_eval=t,
            rtol=spec.rtol,
            atol=spec.atol,
        )  # fmt: skip
        for m in ("DOP853", "Radau")
    ]
    independent = np.abs(sols[0].y - sols[1].y)  # theta1, theta2, theta1', theta2'
    assert independent[0].max() > 0.1 and diffs["theta1"]["max"] > 0.1
    for k, name in enumerate(diffs):
        # observed agreement 3e-4 relative (the methods' difference dwarfs round-off)
        assert diffs[name]["max"] == pytest.approx(independent[k].max(), rel=2e-2), name
        assert diffs[name]["time_of_max_s"] == pytest.approx(t[independent[k].argmax()], abs=0.2)


def test_double_pendulum_disagreement_warns_everywhere(pendulum):
    """Beyond 1e-2 of its scale a difference warns: on stderr, in summary.json and in
    report.html, naming the coordinate, the size and the time."""
    stdout, stderr, out = pendulum
    summary = json.loads((out / "summary.json").read_text())
    d = summary["accuracy"]["comparison"]["differences"]["theta1"]
    assert d["tolerance"] == pytest.approx(1e-2 * d["scale"], rel=1e-12)
    assert summary["accuracy"]["agreement_threshold"] == 1e-2
    warnings = [w for w in summary["accuracy"]["warnings"] if "in theta1 " in w]
    assert len(warnings) == 1
    w = warnings[0]
    assert f"differ by up to {d['max']:.3g} rad in theta1 (at t = {d['time_of_max_s']:.4g} s)" in w
    assert f"poinsot: warning: accuracy: {w}" in stderr
    assert "vs Radau: theta1 differs by up to" in stdout and "theta2' by up to" in stdout
    page = (out / "report.html").read_text()
    assert "Accuracy warnings" in page
    import html

    assert html.escape(w) in page


def test_double_pendulum_short_run_agrees_without_warning():
    """Over 1 s the two methods agree to ~1e-10 rad: no warning, and the reported
    difference equals the one recomputed from the two results' own arrays."""
    pytest.importorskip("sympy")
    r = simulate_scenario(load_scenario(EXAMPLES / "double_pendulum.toml"), duration=1.0)
    acc = r.summary["accuracy"]
    assert acc["warnings"] == []
    a, b = r.trajectory, r.reference
    diffs = acc["comparison"]["differences"]
    for k, name in enumerate(a.coordinates):
        dq = np.abs(a.q[:, k] - b.q[:, k])
        dv = np.abs(a.qdot[:, k] - b.qdot[:, k])
        assert diffs[name]["max"] == pytest.approx(dq.max(), rel=1e-12)
        assert diffs[name + "_dot"]["max"] == pytest.approx(dv.max(), rel=1e-12)
        assert 0 < dq.max() < 1e-7


def _kepler_position(t, x0, v0, mu=1.0):
    """Position on the Kepler ellipse from (x0, v0) at times t, by Kepler's equation
    solved with brentq (elements from the state: the textbook construction)."""
    from scipy.optimize import brentq

    r0 = np.linalg.norm(x0)
    h = np.cross(x0, v0)
    e_vec = np.cross(v0, h) / mu - x0 / r0
    e = np.linalg.norm(e_vec)
    a = 1.0 / (2.0 / r0 - v0 @ v0 / mu)
    n = math.sqrt(mu / a**3)
    p_hat = e_vec / e
    q_hat = np.cross(h / np.linalg.norm(h), p_hat)
    cos_e0 = (1.0 - r0 / a) / e
    sin_e0 = (x0 @ v0) / (e * math.sqrt(mu * a))
    m0 = math.atan2(sin_e0, cos_e0) - e * sin_e0
    out = []
    for tk in t:
        m = m0 + n * tk
        big_e = brentq(lambda x, m=m: x - e * math.sin(x) - m, m - 1.5, m + 1.5, xtol=1e-15)
        xp, yp = a * (math.cos(big_e) - e), a * math.sqrt(1 - e * e) * math.sin(big_e)
        out.append(xp * p_hat + yp * q_hat)
    return np.array(out)


def test_kepler_reports_position_and_velocity_differences():
    """Kepler's equation vs the integration: the reported position and velocity
    differences (m, m/s) equal the ones computed here from the two runs, are not 0,
    and are bounded by the two runs' own errors against an independent Kepler solver."""
    r = simulate_scenario(load_scenario(EXAMPLES / "kepler_orbit.toml"), duration=12.0)
    cmp = r.summary["accuracy"]["comparison"]
    assert cmp["reference"] == "adaptive"
    diffs = cmp["differences"]
    a, b = r.trajectory, r.reference
    dr = np.linalg.norm(a.position - b.position, axis=-1)
    dv = np.linalg.norm(a.velocity - b.velocity, axis=-1)
    assert diffs["position"]["units"] == "m" and diffs["velocity"]["units"] == "m/s"
    assert diffs["position"]["max"] == pytest.approx(dr.max(), rel=1e-12)
    assert diffs["position"]["time_of_max_s"] == a.t[dr.argmax()]
    assert diffs["velocity"]["max"] == pytest.approx(dv.max(), rel=1e-12)
    assert diffs["position"]["final"] == pytest.approx(dr[-1], rel=1e-12)
    truth = _kepler_position(a.t, np.array([1.0, 0.2, 0.1]), np.array([0.1, 1.1, 0.3]))
    err_a = np.linalg.norm(a.position - truth, axis=-1).max()
    err_b = np.linalg.norm(b.position - truth, axis=-1).max()
    assert err_a < 1e-11 and err_b < 1e-8  # observed 4e-15 and 8e-12
    assert 0 < diffs["position"]["max"] <= err_a + err_b + 1e-15
    assert r.summary["accuracy"]["warnings"] == []
    text = r.describe()
    assert f"vs adaptive: position differs by up to {dr.max():.3g} m" in text


def test_particle_disagreement_beyond_a_stated_threshold_warns():
    """An ``agreement_threshold`` below the observed difference gives a warning naming
    the quantity and its units (the rule of docs/cli.md)."""
    text = (EXAMPLES / "kepler_orbit.toml").read_text()
    text = text.replace(
        'reference = "adaptive"', 'reference = "adaptive"\nagreement_threshold = 1e-14'
    )
    r = simulate_scenario(parse_scenario(text, source="kepler.toml"), duration=6.0)
    w = r.summary["accuracy"]["warnings"]
    assert any(" m in position (at t = " in x for x in w), w
    assert any(" m/s in velocity (at t = " in x for x in w), w


def test_trajectory_files_carry_the_kind_s_own_channels(tmp_path):
    """A Lagrangian run's CSV has the coordinates and rates with their units, and no
    attitude or angular-velocity columns."""
    pytest.importorskip("sympy")
    from poinsot.scenarios import run_scenario

    r, _ = run_scenario(load_scenario(EXAMPLES / "double_pendulum.toml"), tmp_path / "o",
                        duration=0.5, report=False, figures=False)  # fmt: skip
    import json

    names = (tmp_path / "o" / "trajectory.csv").read_text().splitlines()[0].split(",")
    meta = json.loads((tmp_path / "o" / "trajectory.columns.json").read_text())
    assert list(meta["columns"]) == names
    assert not {"qw", "qx", "qy", "qz", "wx", "wy", "wz"} & set(names)
    # no rigid-body conventions (quaternions, body axes) for a system without a body
    conventions = next(ln for ln in meta["header"] if ln.startswith("conventions: "))
    assert "quaternion" not in conventions.lower() and "generalized coordinates" in conventions
    assert r.summary["conventions"] == conventions.removeprefix("conventions: ")
    cols = meta["columns"]
    assert cols["t"] == "s" and cols["theta1"] == "rad" and cols["theta2_dot"] == "rad/s"
    data = np.loadtxt(tmp_path / "o" / "trajectory.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(data[:, names.index("theta2")], r.trajectory.q[:, 1])
    np.testing.assert_array_equal(data[:, names.index("theta1_dot")], r.trajectory.qdot[:, 0])


def test_lagrangian_units_table():
    """``[lagrangian] units`` overrides the unit guessed from a coordinate's name; a
    wrong unit or coordinate is refused with the key."""
    pytest.importorskip("sympy")
    from poinsot.scenarios._toml import ScenarioError

    base = (EXAMPLES / "double_pendulum.toml").read_text()
    s = parse_scenario(
        base.replace("qdot0 = [0.0, 0.0]", 'qdot0 = [0.0, 0.0]\nunits = { theta2 = "" }')
    )
    assert s.spec.units == ("rad", "")
    for bad, match in (('{ theta2 = "deg" }', "one of"), ('{ phi = "rad" }', "among")):
        with pytest.raises(ScenarioError, match=f"lagrangian.units.*{match}"):
            parse_scenario(base.replace("qdot0 = [0.0, 0.0]", f"qdot0 = [0.0, 0.0]\nunits = {bad}"))


def test_time_of_max_is_in_seconds(pendulum):
    """issue 38: the report's accuracy table gave "time of max 20 rad" (the quantity's
    units); summary.json names the seconds in its key and the table writes "s"."""
    import re

    _, _, out = pendulum
    summary = json.loads((out / "summary.json").read_text())
    diffs = summary["accuracy"]["comparison"]["differences"]
    assert all("time_of_max" not in d and "time_of_max_s" in d for d in diffs.values())
    t = load_scenario(EXAMPLES / "double_pendulum.toml").simulation.times()
    for d in diffs.values():  # a time of the run, in s
        assert t[0] <= d["time_of_max_s"] <= t[-1]
    page = (out / "report.html").read_text()
    shown = re.findall(r"<th>time of max</th><td[^>]*>([^<]*)</td>", page)
    assert shown == [f"{d['time_of_max_s']:.6g} s" for d in diffs.values()]
