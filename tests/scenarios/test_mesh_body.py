"""Scenario bodies and parts given as triangle meshes (`shape = "mesh"`): the same
mass properties as the equivalent solid, placed the same way, drawn in the report."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot

from mass.test_mesh import box_mesh, icosphere
from plotting.test_report import _f32, _named, _page, _u32
from poinsot.mass import mesh
from poinsot.scenarios import ScenarioError, describe_scenario, load_scenario, parse_scenario

REST = """
[angular_velocity]
vector = [0.3, 2.0, 0.1]
frame = "body"

[simulation]
duration = 0.5
samples = 11
method = "midpoint"
"""
A, B, C, M = 0.4, 0.3, 0.2, 2.5  # a box (m) and its mass (kg)


def toml_list(a) -> str:
    return "[" + ", ".join(toml_list(x) if np.ndim(x) else repr(x.item()) for x in a) + "]"


def parse(text: str, source="case.toml"):
    return parse_scenario(textwrap.dedent(text) + REST, source=source)


def inline(v, f, extra="") -> str:
    return (
        f"vertices = {toml_list(np.asarray(v, float))}\nfaces = {toml_list(np.asarray(f))}\n{extra}"
    )


def assert_same_body(b1, b2, tol=1e-12):
    assert b1.mass == pytest.approx(b2.mass, rel=tol)
    np.testing.assert_allclose(b1.center_of_mass, b2.center_of_mass, rtol=0, atol=tol)
    np.testing.assert_allclose(b1.inertia, b2.inertia, rtol=0, atol=tol * np.abs(b2.inertia).max())


def test_inline_mesh_box_equals_box_body():
    v, f = box_mesh(A, B, C)
    s1 = parse(f'[body]\nshape = "mesh"\nmass = {M}\n' + inline(v, f))
    s2 = parse(f'[body]\nshape = "box"\ndims = [{A}, {B}, {C}]\nmass = {M}\n')
    assert_same_body(s1.body, s2.body)
    closed = M / 12 * np.diag([B * B + C * C, A * A + C * C, A * A + B * B])
    np.testing.assert_allclose(s1.body.inertia, closed, rtol=1e-13, atol=1e-16)
    assert s1.body.shape == "mesh" and s1.body.faces.shape == (12, 3)
    assert "mesh body" in describe_scenario(s1)


def test_mesh_body_centre_of_mass_from_vertices_and_density():
    """A mesh not centred on its origin: the body axes are the mesh's coordinates, so
    the centre of mass is where the vertices put it; density gives mass = rho V."""
    v, f = box_mesh(A, B, C)
    d = np.array([0.1, -0.2, 0.35])
    s = parse('[body]\nshape = "mesh"\ndensity = 800.0\n' + inline(v + d, f))
    assert s.body.mass == pytest.approx(800.0 * A * B * C, rel=1e-13)
    np.testing.assert_allclose(s.body.center_of_mass, d, atol=1e-14)


def test_placed_mesh_part_equals_placed_box_part():
    """position/orientation place the mesh's own axes: a box mesh offset by d in its own
    coordinates lands at position + C d, turned by C, like the box part placed there."""
    v, f = box_mesh(A, B, C)
    d = np.array([0.05, 0.1, -0.02])
    pos = np.array([0.3, -0.1, 0.2])
    orient = (
        '[body.parts.orientation]\neuler = [30.0, 20.0, -40.0]\nsequence = "ZYX"\ndegrees = true\n'
    )
    cbp = SciRot.from_euler("ZYX", [30.0, 20.0, -40.0], degrees=True).as_matrix()
    ball = (
        '[[body.parts]]\nshape = "sphere"\ndims = [0.1]\nmass = 1.0\nposition = [0.0, 0.0, -0.3]\n'
    )
    s1 = parse(
        f'[[body.parts]]\nname = "m"\nshape = "mesh"\nmass = {M}\nposition = {toml_list(pos)}\n'
        + inline(v + d, f)
        + orient
        + ball
    )
    s2 = parse(
        f'[[body.parts]]\nname = "b"\nshape = "box"\ndims = [{A}, {B}, {C}]\nmass = {M}\n'
        f"position = {toml_list(pos + cbp @ d)}\n" + orient + ball
    )
    assert_same_body(s1.body, s2.body)
    p1, p2 = s1.body.parts[0], s2.body.parts[0]
    np.testing.assert_allclose(p1.position, p2.position, atol=1e-14)
    np.testing.assert_allclose(p1.inertia, p2.inertia, atol=1e-14)
    np.testing.assert_allclose(p1.vertices, (v + d) @ cbp.T + pos, atol=1e-14)


def write_obj(path, v, f):
    path.parent.mkdir(parents=True, exist_ok=True)
    text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in np.asarray(v, float).tolist())
    text += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in np.asarray(f).tolist())
    path.write_text(text)


def test_mesh_file_relative_to_scenario(tmp_path):
    v, f = icosphere(2)
    v = v * [0.5, 0.3, 0.2]
    write_obj(tmp_path / "meshes" / "rock.obj", v, f)
    body = '[body]\nshape = "mesh"\nfile = "meshes/rock.obj"\nmass = 3.0\n'
    (tmp_path / "rock.toml").write_text(body + REST)
    s = load_scenario(tmp_path / "rock.toml")
    ref = mesh(v, f, mass=3.0)
    np.testing.assert_allclose(s.body.inertia, ref.inertia, rtol=1e-13, atol=1e-16)
    s2 = parse('[body]\nshape = "mesh"\nmass = 3.0\n' + inline(v, f))
    assert_same_body(s.body, s2.body)
    with pytest.raises(ScenarioError, match=r"case\.toml:\d+: `body\.file`.*no such mesh file"):
        parse(body)  # relative to the working directory for a string


def test_report_draws_the_mesh(tmp_path):
    from poinsot.scenarios import simulate_scenario, write_scenario_report

    v, f = icosphere(1)
    v = v * [0.3, 0.2, 0.1]
    pos = np.array([0.0, 0.0, 0.2])
    s = parse(
        f'[[body.parts]]\nshape = "mesh"\nmass = 1.0\nposition = {toml_list(pos)}\n'
        + inline(v, f)
        + "[[body.parts]]\nmass = 0.5\nposition = [0.0, 0.0, -0.4]\n"
    )
    P, _ = _page(write_scenario_report(tmp_path / "r.html", simulate_scenario(s)))
    a = _named(P, "body: mesh")
    # the body's solids are one layer: the mesh first, then the point mass's sphere
    np.testing.assert_allclose(_f32(a["v"]).reshape(-1, 3)[: len(v)], v + pos, atol=1e-6)
    np.testing.assert_array_equal(_u32(a["f"]).reshape(-1, 3)[: len(f)], f)


CUBE_V, CUBE_F = box_mesh(1.0, 1.0, 1.0)


@pytest.mark.parametrize(
    ("body", "match"),
    [
        (inline(CUBE_V, CUBE_F[:-1], "mass = 1.0"), r"case\.toml:4: `body\.faces`.*closed surface"),
        (
            inline(CUBE_V, np.where(CUBE_F == 7, 8, CUBE_F), "mass = 1.0"),
            r"`body\.faces`.*indices in \[0, 8\)",
        ),  # fmt: skip
        (inline(CUBE_V, CUBE_F[:, ::-1], "mass = 1.0"), r"`body\.faces`.*oriented inwards"),
        (inline(CUBE_V, CUBE_F, "mass = 1.0\ndensity = 2.0"), r"`body\.density`.*conflicts"),
        (inline(CUBE_V, CUBE_F), r"`body`.*missing key.*`mass`, `density`"),
        (inline(CUBE_V, CUBE_F, "mass = 1.0\ndims = [1.0]"), r"`body\.dims`.*not allowed"),
        (
            inline(CUBE_V, CUBE_F, "mass = 1.0\ncenter_of_mass = [0.0, 0.0, 0.1]"),
            r"`body\.center_of_mass`.*follows from its vertices",
        ),  # fmt: skip
        (inline(CUBE_V, [[0, 1, 2.5]], "mass = 1.0"), r"`body\.faces`.*0-based vertex indices"),
        ("vertices = [[0.0, 0.0, 0.0]]\nmass = 1.0\n", r"missing key `faces`"),
        ('file = "nowhere.obj"\nmass = 1.0\n', r"`body\.file`.*nowhere\.obj: no such mesh file"),
        ("mass = 1.0\n", r"missing key: expected one of `file`, `vertices`"),
    ],
)
def test_bad_mesh_bodies(body, match):
    with pytest.raises(ScenarioError, match=match):
        parse('[body]\nshape = "mesh"\n' + body)


def test_bad_mesh_files_and_parts(tmp_path):
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    src = str(tmp_path / "s.toml")
    with pytest.raises(ScenarioError, match=r"`body\.file`.*bad\.obj:4: expected vertex indices"):
        parse('[body]\nshape = "mesh"\nfile = "bad.obj"\nmass = 1.0\n', source=src)
    write_obj(tmp_path / "open.obj", CUBE_V, CUBE_F[1:])
    with pytest.raises(ScenarioError, match=r"`body\.parts\[0\]\.file`.*open\.obj: .*closed"):
        parse('[[body.parts]]\nshape = "mesh"\nfile = "open.obj"\nmass = 1.0\n', source=src)
    with pytest.raises(ScenarioError, match=r"`body\.parts\[0\]\.density`.*mesh"):
        parse('[[body.parts]]\nshape = "box"\ndims = [1.0, 1.0, 1.0]\ndensity = 1.0\n')
    with pytest.raises(ScenarioError, match=r"`body\.parts\[0\]\.inertia`.*not allowed"):
        parse('[[body.parts]]\nshape = "mesh"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n'
              + inline(CUBE_V, CUBE_F))  # fmt: skip


def test_mesh_top_under_gravity_equals_box_top():
    """Under gravity the fixed point is the mesh's origin: a box mesh lifted by h along z
    is the box body with center_of_mass = [0, 0, h] (same inertia about the pin)."""
    v, f = box_mesh(A, B, C)
    h = 0.35
    grav = '[torque]\nmodel = "gravity"\n'
    s1 = parse(f'[body]\nshape = "mesh"\nmass = {M}\n' + inline(v + [0.0, 0.0, h], f) + grav)
    s2 = parse(
        f'[body]\nshape = "box"\ndims = [{A}, {B}, {C}]\nmass = {M}\n'
        f"center_of_mass = [0.0, 0.0, {h}]\n" + grav
    )
    assert_same_body(s1.body, s2.body)
    np.testing.assert_allclose(
        s1.body.inertia_about_origin(), s2.body.inertia_about_origin(), rtol=1e-13, atol=1e-15
    )


def test_summary_gives_the_mesh_triangle_count(tmp_path):
    # a mesh has no dims: the summary's body section says how many triangles it has
    from poinsot.scenarios import simulate_scenario

    v, f = icosphere(1)
    write_obj(tmp_path / "rock.obj", v * [0.5, 0.3, 0.2], f)
    (tmp_path / "rock.toml").write_text(
        '[body]\nshape = "mesh"\nfile = "rock.obj"\nmass = 3.0\n' + REST
    )
    body = simulate_scenario(load_scenario(tmp_path / "rock.toml"), duration=0.1).summary["body"]
    assert body["shape"] == "mesh" and "dims" not in body  # no empty rows
    assert body["mesh_triangles"] == len(f)
