"""Scenario kind ``lagrangian``: the physics of the outputs against closed forms, and
untrusted formulas refused with file, key and token (nothing is evaluated)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("sympy")

from poinsot.scenarios import parse_scenario  # noqa: E402
from poinsot.scenarios.solve import simulate_scenario  # noqa: E402

CHARGED = """
name = "charge"
kind = "lagrangian"
[lagrangian]
coordinates = ["x", "y", "z"]
parameters = {{ m = 2.0, q = 0.5, E = 3.0, B = 4.0 }}
kinetic = "m*(x_dot**2 + y_dot**2 + z_dot**2)/2"
generalized_potential = "{V}"
q0 = [0.0, 0.0, 0.0]
qdot0 = [0.0, 0.0, 0.0]
[simulation]
duration = {T}
samples = 41
method = "DOP853"
"""
V_OK = "-q*E*x - q*(x_dot*(-B*y/2) + y_dot*(B*x/2))"


def test_charged_particle_outputs_match_the_drift():
    """At one cyclotron period 2 pi m/(q B) the charge is at rest, displaced by -(E/B) T
    along y (E x B drift); the Jacobi integral is conserved."""
    period = 2 * np.pi * 2.0 / (0.5 * 4.0)
    sc = parse_scenario(CHARGED.format(V=V_OK, T=period), source="charge.toml")
    result = simulate_scenario(sc)
    tr = result.trajectory  # the kind's own CoordinateTrajectory
    assert tuple(tr.coordinates) == ("x", "y", "z") and tuple(tr.units) == ("m", "m", "m")
    assert tr.q[-1, 0] == pytest.approx(0.0, abs=1e-7)
    assert tr.q[-1, 1] == pytest.approx(-3.0 / 4.0 * period, rel=1e-7)
    assert abs(tr.qdot[-1, 1]) < 1e-7
    acc = result.summary["accuracy"]
    assert acc["invariants"]["jacobi"]["max_relative_drift"] < 1e-8
    assert acc["warnings"] == []
    assert result.summary["results"]["cyclic_coordinates"] == ["z"]


@pytest.mark.parametrize(
    ("formula", "token"),
    [
        ("__import__('os').system('touch HACKED')", "__import__"),
        ("x.__class__", ".__class__"),
        ("9**9**9", "9**9**9"),
        ("w*x", "w"),
    ],
)
def test_malicious_formula_names_file_key_and_token(formula, token, tmp_path, monkeypatch):
    from poinsot.scenarios._toml import ScenarioError

    monkeypatch.chdir(tmp_path)
    text = CHARGED.format(V=formula.replace('"', "'"), T=1.0)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, source="evil.toml")
    msg = str(info.value)
    assert "evil.toml" in msg and "lagrangian.generalized_potential" in msg
    assert repr(token) in msg or f"'{token}'" in msg
    assert list(tmp_path.iterdir()) == []


def test_velocity_quadratic_generalized_potential_is_refused_with_the_reason():
    from poinsot.scenarios._toml import ScenarioError

    with pytest.raises(ScenarioError, match="linear in the velocities"):
        parse_scenario(CHARGED.format(V="x_dot**2", T=1.0), source="bad.toml")


def test_wrong_initial_state_length():
    from poinsot.scenarios._toml import ScenarioError

    text = CHARGED.format(V=V_OK, T=1.0).replace("q0 = [0.0, 0.0, 0.0]", "q0 = [0.0]")
    with pytest.raises(ScenarioError, match="lagrangian.q0"):
        parse_scenario(text, source="bad.toml")


def test_report_has_the_typeset_equations(tmp_path):
    """report.html carries the equations as inline SVG (offline: no MathJax, no fetch)."""
    from poinsot.scenarios.output import run_scenario

    sc = parse_scenario(CHARGED.format(V=V_OK, T=1.0), source="charge.toml")
    _, files = run_scenario(sc, tmp_path / "out")
    names = {p.name for p in files}
    assert {"report.html", "equations.svg", "coordinates.png", "phase.png"} <= names
    page = (tmp_path / "out" / "report.html").read_text()
    head = page.index("Lagrange&#x27;s equations (docs/theory.md §11)</h2>")
    assert "<svg" in page[head : head + 2000]
    assert "<script src=" not in page  # self-contained: nothing fetched
