"""The heavy-top scenario kind (docs/theory.md §10): gravity files, the exact Lagrange
top as method or reference, the Kovalevskaya top.

Oracles: the integrals and the cubic ``P(u)`` recomputed here from the file's numbers
(Huygens-Steiner by hand, Goldstein §5.7); Maievskii's ratio ``C^2 r^2 / (4 A m g l)``;
the tilt of the numerical reference run (not the library's closed form).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from poinsot import InvalidInputError
from poinsot.scenarios import load_scenario, parse_scenario, simulate_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

M, L, G = 0.5, 0.04, 9.80665
A = 2e-4 + M * L * L  # about the pin
C = 3e-4


def _tilt(tr):
    axis = tr.rotation.apply(np.array([0.0, 0.0, 1.0]))
    return np.arccos(np.clip(axis[:, 2], -1.0, 1.0))


def test_released_top_results_against_hand_integrals_and_the_numerical_run():
    s = load_scenario(EXAMPLES / "top_released.toml")
    result = simulate_scenario(s, duration=0.2)
    res = result.summary["results"]
    assert res["motion"] == "cusps"
    r, theta0 = 200.0, math.radians(30.0)
    h = C * r
    mgl = M * G * L
    kz = h * math.cos(theta0)
    e = mgl * math.cos(theta0)
    assert res["H"] == pytest.approx(h, rel=1e-14)
    assert res["K_z"] == pytest.approx(kz, rel=1e-14)
    assert res["E"] == pytest.approx(e, rel=1e-14)
    assert res["maievskii_ratio"] == pytest.approx(h * h / (4 * A * mgl), rel=1e-14)

    def p(u):
        return 2 / A * (e - mgl * u) * (1 - u * u) - (kz - h * u) ** 2 / A**2

    for u in res["cos_theta_roots"]:
        assert abs(p(u)) < 1e-9 * h * h / A**2
    assert res["nutation_theta_min"] == pytest.approx(theta0, abs=1e-15)
    # the numerical reference (splitting) stays in the band and fills it
    tilt = _tilt(result.reference)
    assert tilt.min() >= res["nutation_theta_min"] - 1e-6
    assert tilt.max() <= res["nutation_theta_max"] + 1e-6
    assert tilt.max() == pytest.approx(res["nutation_theta_max"], abs=2e-4)
    acc = result.summary["accuracy"]
    assert acc["comparison"]["reference"] == "splitting"
    assert acc["invariants"]["momentum_z"]["max_relative_drift"] < 1e-14


@pytest.mark.parametrize("tag, stable", [("above", True), ("below", False)])
def test_sleeping_top_above_and_below_the_critical_spin(tag, stable):
    s = load_scenario(EXAMPLES / f"sleeping_top_{tag}.toml")
    r = float(s.angular_velocity.omega_body[2])
    mgl = M * G * L
    ratio = (C * r) ** 2 / (4 * A * mgl)
    assert (ratio > 1) is stable
    result = simulate_scenario(s, duration=1.5)
    res = result.summary["results"]
    assert res["maievskii_ratio"] == pytest.approx(ratio, rel=1e-13)
    assert res["critical_spin"] == pytest.approx(2 * math.sqrt(A * mgl) / C, rel=1e-14)
    tilt_max = _tilt(result.reference).max()  # the splitting run
    if stable:
        assert tilt_max < math.radians(3.0)
    else:
        assert tilt_max > math.radians(40.0)


def test_kovalevskaya_scenario_conserves_the_fourth_integral():
    result = simulate_scenario(load_scenario(EXAMPLES / "kovalevskaya_top.toml"), duration=2.0)
    acc = result.summary["accuracy"]["invariants"]
    assert result.summary["results"]["case"].startswith("Kovalevskaya top")
    assert acc["kovalevskaya_integral"]["max_relative_drift"] < 1e-9
    # the same body with A = B = 2.2 C about the pin is not a Kovalevskaya top
    text = (EXAMPLES / "kovalevskaya_top.toml").read_text()
    text = text.replace("inertia = [2e-3, 1.8e-3, 0.8e-3]", "inertia = [2.2e-3, 2.0e-3, 0.8e-3]")
    res = simulate_scenario(parse_scenario(text), duration=0.1).summary
    assert "kovalevskaya_integral" not in res["accuracy"]["invariants"]


def test_exact_is_refused_for_a_body_that_is_not_a_lagrange_top():
    text = textwrap.dedent(
        """
        [body]
        mass = 1.0
        inertia = [1.0, 1.5, 2.0]
        center_of_mass = [0.0, 0.0, 0.1]
        [angular_velocity]
        vector = [0.0, 0.0, 5.0]
        frame = "body"
        [torque]
        model = "gravity"
        [simulation]
        duration = 0.1
        step = 0.01
        method = "exact"
        """
    )
    with pytest.raises(InvalidInputError, match="A = B"):
        parse_scenario(text)


def test_top_summary_says_its_energies_counts_its_steps_and_has_no_empty_rows():
    """The top of examples/top_loops.toml (given by its inertia, no shape): no shape,
    dims or parts rows; both energies explained, E = T + V - H^2/(2C); the step count
    is the whole run's (duration / max_step), not one chunk's."""
    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "top_loops.toml"))
    s = res.summary
    assert not {"shape", "dims", "parts"} & set(s["body"])
    r = s["results"]
    C = s["body"]["inertia_about_fixed_point"][2][2]
    assert r["E"] == pytest.approx(r["energy"] - r["H"] ** 2 / (2 * C), rel=1e-12)
    line = next(x for x in res.facts.describe() if x.startswith("energies:"))
    assert "total T + V" in line and "H^2/(2C)" in line
    sim = res.scenario.simulation
    assert s["run"]["info"]["chunks"] > 1
    assert s["run"]["info"]["steps"] == round(sim.duration / sim.max_step)


def _vector_after(text: str, label: str) -> np.ndarray:
    rest = text[text.index(label) + len(label) :]
    return np.array([float(x) for x in rest[rest.index("[") + 1 : rest.index("]")].split(",")])


def test_describe_says_about_which_point_each_moment_is():
    """issue 38: the console printed the principal moments about the centre of mass
    ([0.0008, 0.0018, 0.002]) beside "A = B = 2C", which holds about the pin only.
    Oracle: Huygens-Steiner by hand, J_O = J_C + m (|c|^2 E - c c^T)."""
    from poinsot.scenarios.describe import describe

    s = load_scenario(EXAMPLES / "kovalevskaya_top.toml")
    text = describe(simulate_scenario(s, duration=0.05))
    body_line = next(x for x in text.splitlines() if x.startswith("body:"))
    j_c = np.asarray(s.body.inertia, dtype=float)
    m, c = float(s.body.mass), np.asarray(s.body.center_of_mass, dtype=float)
    j_o = j_c + m * (c @ c * np.eye(3) - np.outer(c, c))
    about_cm = _vector_after(body_line, "principal moments about the centre of mass")
    np.testing.assert_allclose(about_cm, np.linalg.eigvalsh(j_c), rtol=1e-3)
    about_pin = _vector_after(body_line, "about the fixed point (body axes) A, B, C =")
    np.testing.assert_allclose(about_pin, np.diag(j_o), rtol=1e-3)
    a, b, cc = about_pin
    assert a == pytest.approx(b) and a == pytest.approx(2 * cc)  # the statement, about O
    assert not np.isclose(about_cm[0], 2 * about_cm[2])  # ... not about the centre of mass
    assert "A = B = 2C about the fixed point" in text
    assert "kg m^2" in body_line.split("about the fixed point")[1]


def test_chunked_run_keeps_v_per_sample_and_out_of_summary():
    """A long run is split in chunks: V (from info["gravity_moment"], evaluated when
    asked) must cover every sample, recomputed here as m g z_c from the attitude, and no
    per-sample series may reach summary.json."""
    s = load_scenario(EXAMPLES / "kovalevskaya_top.toml")
    res = simulate_scenario(s)
    tr = res.trajectory
    assert res.summary["run"]["info"]["chunks"] > 1
    assert "potential_energy" not in res.summary["run"]["info"]
    m, c = float(s.body.mass), np.asarray(s.body.center_of_mass, dtype=float)
    v = m * float(s.torque.g) * tr.rotation.apply(c)[:, 2]
    np.testing.assert_allclose(tr._potential_energy(), v, rtol=1e-12, atol=1e-15)
    e = np.asarray(tr.energy) + v
    drift = np.max(np.abs(e - e[0])) / max(abs(e[0]), np.max(np.abs(tr.energy)))
    assert tr.conserved_drifts()["total_energy"] == pytest.approx(drift, rel=1e-9)
