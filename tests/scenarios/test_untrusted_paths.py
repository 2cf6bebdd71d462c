"""A scenario file reads mesh files only inside its own directory (issue 23)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from poinsot.cli import main
from poinsot.scenarios import ScenarioError, load_scenario

SECRET = "solid SECRET-CONTENT-42"
TET = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def _scenario(directory: Path, mesh: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / "s.toml"
    path.write_text(
        f'[body]\nshape = "mesh"\nfile = {mesh!r}\nmass = 1.0\n'
        '[angular_velocity]\nvector = [0.0, 0.0, 1.0]\nframe = "body"\n'
        '[simulation]\nduration = 1.0\nsamples = 11\nmethod = "exact"\n'.replace("'", '"')
    )
    return path


@pytest.mark.parametrize("how", ["absolute", "dotdot", "symlink"])
def test_a_mesh_outside_the_scenario_directory_is_refused_unread(tmp_path, how, capsys):
    outside = tmp_path / "secret.stl"
    outside.write_text(SECRET + "\nnot an stl\n")
    inner = tmp_path / "scenarios"
    if how == "absolute":
        path = _scenario(inner, str(outside))
    elif how == "dotdot":
        path = _scenario(inner, "../secret.stl")
    else:
        inner.mkdir()
        os.symlink(outside, inner / "link.stl")
        path = _scenario(inner, "link.stl")
    with pytest.raises(ScenarioError, match="inside the scenario's directory") as err:
        load_scenario(path)
    assert "SECRET" not in str(err.value) and "--allow-paths" in str(err.value)
    assert main(["check", str(path)]) == 2
    assert "SECRET" not in capsys.readouterr().err
    # asked for, the file is read (and found not to be a mesh)
    with pytest.raises(ScenarioError, match="secret.stl|link.stl"):
        load_scenario(path, allow_paths=True)


def test_a_mesh_inside_the_directory_is_read(tmp_path):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "tet.obj").write_text(TET)
    s = load_scenario(_scenario(tmp_path, "meshes/tet.obj"))
    assert s.body is not None and s.body.mass == 1.0


@pytest.mark.parametrize("name", ["mesh.ply", "mesh", "mesh.txt"])
def test_unknown_mesh_formats_are_refused_by_suffix(tmp_path, name):
    (tmp_path / name).write_text(SECRET + "\n")
    with pytest.raises(ScenarioError, match=r"\.obj or \.stl") as err:
        load_scenario(_scenario(tmp_path, name))
    assert "SECRET" not in str(err.value)
