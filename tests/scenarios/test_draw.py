"""The ``[draw]`` table of a Lagrangian scenario: points as formulas of the
coordinates (the same whitelist parser), links and trails, checked against the
geometry they describe; malformed tables refused with file:line: key; every shipped
Lagrangian example draws itself in report.html."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sympy")

from poinsot.scenarios import load_scenario, parse_scenario  # noqa: E402
from poinsot.scenarios._toml import ScenarioError  # noqa: E402
from poinsot.scenarios.solve import simulate_scenario  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

PENDULUM = """
kind = "lagrangian"
[lagrangian]
coordinates = ["theta1", "theta2"]
parameters = {{ m1 = 1.0, m2 = 2.0, l1 = 0.7, l2 = 1.3, g = 9.81 }}
kinetic = \"\"\"(m1 + m2)*l1**2*theta1_dot**2/2 + m2*l2**2*theta2_dot**2/2
             + m2*l1*l2*theta1_dot*theta2_dot*cos(theta1 - theta2)\"\"\"
potential = "-(m1 + m2)*g*l1*cos(theta1) - m2*g*l2*cos(theta2)"
q0 = [1.0, -0.5]
qdot0 = [0.0, 0.0]
[simulation]
duration = 2.0
samples = 201
method = "DOP853"
[draw]
{draw}
"""
DRAW_OK = """points = { pivot = [0, 0], bob1 = ["l1*sin(theta1)", "-l1*cos(theta1)"], \
bob2 = ["l1*sin(theta1) + l2*sin(theta2)", "-l1*cos(theta1) - l2*cos(theta2)"] }
links = [["pivot", "bob1"], ["bob1", "bob2"]]
trail = ["bob2"]"""

LAGRANGIAN_EXAMPLES = ("double_pendulum", "bead_on_hoop", "chaplygin_sleigh", "charged_particle")


def test_points_follow_the_coordinates_with_the_parameters():
    """Plane points go to the scene's x-z plane; the rods keep their lengths l1, l2 at
    every sample and the angle of rod 1 from the downward vertical is theta1."""
    sc = parse_scenario(PENDULUM.format(draw=DRAW_OK), source="p.toml")
    res = simulate_scenario(sc)
    spec = sc.adapter.report(res)
    d = spec.drawing
    assert d is not None and d.face_on and d.trails == ("bob2",)
    assert d.links == (("pivot", "bob1"), ("bob1", "bob2"))
    p0, p1, p2 = (d.points[k] for k in ("pivot", "bob1", "bob2"))
    n = res.trajectory.t.size
    assert p1.shape == (n, 3) and np.all(p0 == 0.0) and np.all(p1[:, 1] == 0.0)
    np.testing.assert_allclose(np.linalg.norm(p1 - p0, axis=1), 0.7, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(p2 - p1, axis=1), 1.3, rtol=1e-12)
    theta1 = np.arctan2(p1[:, 0], -p1[:, 2])
    np.testing.assert_allclose(theta1, res.trajectory.q[:, 0], atol=1e-12)


def test_time_and_space_points():
    """Formulas may use t; three coordinates are space axes (not face on)."""
    draw = 'points = { a = ["cos(t)", "sin(t)", "theta1"] }'
    sc = parse_scenario(PENDULUM.format(draw=draw), source="p.toml")
    res = simulate_scenario(sc)
    d = sc.adapter.report(res).drawing
    t = res.trajectory.t
    assert not d.face_on
    want = np.column_stack([np.cos(t), np.sin(t), res.trajectory.q[:, 0]])
    np.testing.assert_allclose(d.points["a"], want)


@pytest.mark.parametrize(
    ("draw", "key", "words"),
    [
        ("points = { a = [0, 0], b = [0, 0, 1] }", "draw.points.b", "expected 2 coordinates"),
        ('points = { a = ["l1*sin(theta1)"] }', "draw.points.a", "2 or 3 coordinates"),
        ('points = { a = ["w*theta1", 0] }', "draw.points.a", "'w'"),
        ("points = { a = [\"__import__('os')\", 0] }", "draw.points.a", "__import__"),
        ('points = { a = ["theta1_dot", 0] }', "draw.points.a", "theta1_dot"),
        ('points = { a = [0, 0] }\nlinks = [["a", "b"]]', "draw.links", "'b'"),
        ('points = { a = [0, 0] }\nlinks = ["a"]', "draw.links", "[point, point] pairs"),
        ('points = { a = [0, 0] }\ntrail = ["c"]', "draw.trail", "'c'"),
        ('points = { a = [0, 0] }\ntrails = ["a"]', "draw.trails", "Did you mean `trail`"),
        ("points = {}", "draw.points", "at least one point"),
    ],
)
def test_bad_draw_tables_name_file_line_and_key(draw, key, words):
    text = PENDULUM.format(draw=draw)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, source="bad.toml")
    msg = str(info.value)
    line = text.splitlines().index("[draw]") + 1  # the table's line at least
    m = re.match(r"bad\.toml:(\d+): ", msg)
    assert m is not None and int(m.group(1)) >= line, msg
    assert key in msg and words in msg, msg


def test_draw_belongs_to_the_lagrangian_kind():
    text = """
[orbit]
mu = 1.0
position = [1.0, 0.0, 0.0]
velocity = [0.0, 1.0, 0.0]
[draw]
points = { a = [0, 0] }
"""
    with pytest.raises(ScenarioError, match="draw"):
        parse_scenario(text, source="o.toml")


@pytest.mark.parametrize("name", LAGRANGIAN_EXAMPLES)
def test_every_shipped_lagrangian_example_draws_itself(name, tmp_path):
    """Each example's report has a scene with links or a trail, frames from the
    motion's time scale, and the phase/coordinates figures inline."""
    from poinsot.scenarios.output import run_scenario

    sc = load_scenario(EXAMPLES / f"{name}.toml")
    assert sc.spec.draw is not None
    run_scenario(sc, tmp_path / "out")
    page = (tmp_path / "out" / "report.html").read_text()
    data = json.loads(re.search(r'id="poinsot-data"[^>]*>(.*?)</script>', page, re.S).group(1))
    types = [layer["type"] for layer in data["scene"]["layers"]]
    assert "rig" in types and "trail" in types, types
    assert "Phase portraits" in page and "Coordinates q(t)" in page


def test_lagrangian_printed_as_math_with_parameter_values():
    """summary.json's Lagrangian reads as math (q, q' without (t) or Derivative) and
    round-trips: the text, with ' read as _dot, parses back to the system's L; the
    LaTeX writes rates with dots; the parameters' values are given."""
    import sympy

    from poinsot.symbolic import parse_expression

    sc = parse_scenario(PENDULUM.format(draw=DRAW_OK), source="p.toml")
    res = simulate_scenario(sc, duration=0.1)
    r = res.summary["results"]
    text = r["lagrangian"]
    assert "(t)" not in text and "Derivative" not in text and "theta1'" in text
    system = sc.spec.system
    names = {}
    for f in system.coordinates:
        s = f.func.__name__
        names[s], names[f"{s}_dot"] = sympy.Symbol(s), sympy.Symbol(f"{s}_d")
    names.update({p.name: p for p in system.parameters})
    back = parse_expression(text.replace("'", "_dot"), names)
    plain = system.lagrangian
    for f in system.coordinates:
        s = f.func.__name__
        plain = plain.subs(f.diff(system.time), names[f"{s}_dot"]).subs(f, names[s])
    assert sympy.simplify(back - plain) == 0
    assert r"\dot{\theta_{1}}" in r["lagrangian_latex"]
    assert r["parameter_values"] == {"m1": 1.0, "m2": 2.0, "l1": 0.7, "l2": 1.3, "g": 9.81}
    assert len(r["equations"]) == 2 and all("''" in e for e in r["equations"])
    line = next(x for x in res.facts.describe() if x.startswith("Lagrange's equations"))
    assert "with m1 = 1, m2 = 2, l1 = 0.7, l2 = 1.3, g = 9.81" in line


@pytest.mark.parametrize(
    ("name", "says", "never"),
    [
        ("double_pendulum", "generalized coordinate", ("quaternion", "particle", "omega")),
        ("kepler_orbit", "position (m) and velocity", ("quaternion", "generalized", "omega")),
    ],
)
def test_non_rigid_runs_print_no_rigid_body_boilerplate(name, says, never, tmp_path):
    """Console, summary.json and the CSV header of a Lagrangian or particle run speak
    of their own state only: no quaternion/omega conventions, no qw..wz columns."""
    from poinsot.scenarios.output import run_scenario

    sc = load_scenario(EXAMPLES / f"{name}.toml")
    res, _ = run_scenario(sc, tmp_path / "out", duration=1.0)
    conv = res.summary["conventions"]
    assert says in conv and not any(w in conv for w in never), conv
    head = (tmp_path / "out" / "trajectory.csv").read_text().splitlines()[0]
    text = head + "\n" + (tmp_path / "out" / "trajectory.columns.json").read_text()
    assert says in text and "qw" not in text and "wx" not in text, text
    start = next(x for x in res.describe().splitlines() if x.startswith("start: "))
    assert "quat" not in start and "omega" not in start, start


def test_inertia_round_off_is_written_as_zero():
    """The tennis racket's handle is a cylinder turned by 90 deg: its inertia carries
    round-off (about 1e-19 kg m^2 off the diagonal, 1e-15 in the principal axes); the
    summary writes those as 0 and keeps every real value as computed."""
    sc = load_scenario(EXAMPLES / "tennis_racket.toml")
    J = np.asarray(sc.body.inertia)
    assert 0 < abs(J[0, 2]) < 1e-12 * np.max(np.abs(J))  # the round-off is there
    body = simulate_scenario(sc, duration=0.01).summary["body"]
    np.testing.assert_array_equal(body["inertia"], np.diag(np.diag(J)))
    np.testing.assert_array_equal(body["principal_axes_columns"], np.eye(3))
    np.testing.assert_allclose(body["principal_moments"], np.sort(np.diag(J)), rtol=1e-14)
