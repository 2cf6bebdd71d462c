"""poinsot.mass.read_mesh: OBJ and STL files read back into the arrays they were
written from (mass properties compared with poinsot.mass.mesh and closed forms)."""

from __future__ import annotations

import numpy as np
import pytest

from mass.test_mesh import box_mesh, icosphere
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.mass import mesh, read_mesh


def write_obj(path, v, f, *, negative=False, slashes=False):
    lines = ["# written by the test", "o body"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(v, float).tolist()]
    lines += ["vn 0 0 1"]
    for tri in f:
        if negative:
            idx = [str(int(i) - len(v)) for i in tri]
        else:
            idx = [str(int(i) + 1) for i in tri]
        if slashes:
            idx = [f"{i}/1/1" if k % 2 else f"{i}//1" for k, i in enumerate(idx)]
        lines.append("f " + " ".join(idx))
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ascii_stl(path, v, f):
    out = ["solid test"]
    for tri in f:
        a, b, c = np.asarray(v, float)[tri].tolist()
        n = np.cross(np.subtract(b, a), np.subtract(c, a)).tolist()
        out += [f"  facet normal {n[0]!r} {n[1]!r} {n[2]!r}", "    outer loop"]
        out += [f"      vertex {p[0]!r} {p[1]!r} {p[2]!r}" for p in (a, b, c)]
        out += ["    endloop", "  endfacet"]
    out.append("endsolid test")
    path.write_text("\n".join(out) + "\n")
    return path


def write_binary_stl(path, v, f):
    rec = np.zeros(len(f), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = v[f]
    path.write_bytes(
        b"solid binary header".ljust(80, b" ") + np.uint32(len(f)).tobytes() + rec.tobytes()
    )
    return path


def same_mesh(v1, f1, v2, f2):
    """The same triangles (as coordinate triples), whatever the vertex numbering."""
    t1 = np.sort([tuple(map(tuple, v1[t])) for t in f1], axis=0)
    t2 = np.sort([tuple(map(tuple, v2[t])) for t in f2], axis=0)
    return np.array_equal(t1, t2)


def test_obj_round_trip_cube_closed_form(tmp_path):
    a, m = 0.3, 2.0
    v, f = box_mesh(a, a, a)
    for kw in ({}, {"negative": True}, {"slashes": True}):
        v2, f2 = read_mesh(write_obj(tmp_path / "cube.obj", v, f, **kw))
        np.testing.assert_array_equal(v2, v)
        np.testing.assert_array_equal(f2, f)
        props = mesh(v2, f2, mass=m)
        np.testing.assert_allclose(props.inertia, m * a**2 / 6 * np.eye(3), rtol=1e-13, atol=1e-16)
        np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-15)


def test_obj_quads_are_fan_triangulated(tmp_path):
    a, b, c, m = 1.0, 2.0, 0.5, 3.0
    v = np.array([[x, y, z] for x in (-a / 2, a / 2) for y in (-b / 2, b / 2)
                  for z in (-c / 2, c / 2)])  # fmt: skip
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in v)
    text += "".join("f " + " ".join(str(i + 1) for i in q) + "\n" for q in quads)
    (tmp_path / "box.obj").write_text(text)
    v2, f2 = read_mesh(tmp_path / "box.obj")
    assert f2.shape == (12, 3)
    props = mesh(v2, f2, mass=m)
    closed = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(props.inertia, closed, rtol=1e-13)
    assert props.volume == pytest.approx(a * b * c, rel=1e-14)


@pytest.mark.parametrize("fmt", ["obj", "ascii", "binary"])
def test_icosphere_round_trip(tmp_path, fmt):
    v, f = icosphere(2)
    v = 0.7 * v + [0.1, -0.2, 0.3]
    if fmt == "binary":  # float32 storage: compare with the arrays rounded the same way
        v = v.astype(np.float32).astype(float)
    writer = {"obj": write_obj, "ascii": write_ascii_stl, "binary": write_binary_stl}[fmt]
    v2, f2 = read_mesh(writer(tmp_path / ("s.obj" if fmt == "obj" else "s.stl"), v, f))
    assert len(v2) == len(v)  # STL corners merged back into shared vertices
    assert same_mesh(v, f, v2, f2)
    p1, p2 = mesh(v, f, density=1000.0), mesh(v2, f2, density=1000.0)
    assert p2.mass == pytest.approx(p1.mass, rel=1e-13)
    np.testing.assert_allclose(p2.center_of_mass, p1.center_of_mass, rtol=0, atol=1e-14)
    np.testing.assert_allclose(p2.inertia, p1.inertia, rtol=1e-12, atol=1e-14 * p1.mass)


def test_binary_and_ascii_stl_same_body(tmp_path):
    v, f = icosphere(1)
    v = (v * [1.0, 0.5, 0.25]).astype(np.float32).astype(float)
    va, fa = read_mesh(write_ascii_stl(tmp_path / "a.stl", v, f))
    vb, fb = read_mesh(write_binary_stl(tmp_path / "b.stl", v, f))
    np.testing.assert_array_equal(va, vb)
    np.testing.assert_array_equal(fa, fb)


def test_degenerate_triangles_dropped(tmp_path):
    v, f = box_mesh(1.0, 1.0, 1.0)
    f = np.vstack([f, [[0, 0, 1]]])
    _, f2 = read_mesh(write_obj(tmp_path / "c.obj", v, f))
    assert f2.shape == (12, 3)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n", r"bad\.obj:4: expected vertex indices in 1\.\.3"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", r":4: .*found '-4'"),
        ("v 0 0 0\nv 1 0 x\n", r"bad\.obj:2: expected a vertex"),
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", r":3: expected a face of at least 3"),
        ("v 0 0 0\n", r"found none"),
        ("# nothing\n", r"expected vertices"),
    ],
)
def test_bad_obj(tmp_path, text, match):
    (tmp_path / "bad.obj").write_text(text)
    with pytest.raises(InvalidInputError, match=match):
        read_mesh(tmp_path / "bad.obj")


def test_bad_stl_and_paths(tmp_path):
    (tmp_path / "bad.stl").write_text(
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n"
    )
    with pytest.raises(InvalidInputError, match=r"bad\.stl:7: expected a facet of 3"):
        read_mesh(tmp_path / "bad.stl")
    (tmp_path / "junk.stl").write_text("hello\n")
    with pytest.raises(InvalidInputError, match=r"junk\.stl:1: expected an ASCII STL"):
        read_mesh(tmp_path / "junk.stl")
    with pytest.raises(InvalidInputError, match="no such mesh file"):
        read_mesh(tmp_path / "missing.obj")
    (tmp_path / "dir.obj").mkdir()
    with pytest.raises(InvalidInputError, match="is a directory"):
        read_mesh(tmp_path / "dir.obj")
    (tmp_path / "mesh.ply").write_text("ply\nformat ascii 1.0\n")  # not read as an STL
    with pytest.raises(InvalidInputError, match=r"\.obj or \.stl, got the suffix '\.ply'"):
        read_mesh(tmp_path / "mesh.ply")
    with pytest.raises(InvalidTypeError, match="`path`"):
        read_mesh(3)


def test_open_mesh_refused_by_mesh(tmp_path):
    v, f = box_mesh(1.0, 1.0, 1.0)
    v2, f2 = read_mesh(write_obj(tmp_path / "open.obj", v, f[:-1]))
    with pytest.raises(InvalidInputError, match="closed surface"):
        mesh(v2, f2, mass=1.0)
