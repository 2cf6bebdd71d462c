"""A scenario file reads mesh files only inside its own directory (issue 23)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from poinsot.cli import main
from poinsot.scenarios import ScenarioError, load_scenario

SECRET = "solid SECRET-CONTENT-42"
CLI = "import sys; from poinsot.cli import main; sys.exit(main(sys.argv[1:]))"
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


# issue 38: a FIFO named *.obj blocked `check` forever, a link to /dev/zero grew to
# 13.8 GB in 30 s, and a 300 MB junk file was read whole. Only regular files of bounded
# size are read.


def test_a_fifo_named_as_a_mesh_or_a_scenario_is_refused_at_once(tmp_path):
    import subprocess
    import sys

    os.mkfifo(tmp_path / "rock.obj")
    path = _scenario(tmp_path, "rock.obj")
    os.mkfifo(tmp_path / "pipe.toml")
    for target, where in ((path, "rock.obj"), (tmp_path / "pipe.toml", "pipe.toml")):
        # in a subprocess: a regression blocks in open(), which must fail the test, not
        # hang the suite (nobody ever writes to the FIFO)
        proc = subprocess.run(
            [sys.executable, "-c", CLI, "check", str(target)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert proc.returncode == 2, proc.stderr
        assert where in proc.stderr and "FIFO" in proc.stderr, proc.stderr


def test_a_link_to_a_device_is_refused_even_with_allow_paths(tmp_path, capsys):
    # /dev/null, not /dev/zero: a regression then fails on its content instead of reading
    # without end
    os.symlink("/dev/null", tmp_path / "zero.stl")
    path = _scenario(tmp_path, "zero.stl")
    with pytest.raises(ScenarioError, match="regular file.*character device"):
        load_scenario(path, allow_paths=True)
    assert main(["check", "--allow-paths", str(path)]) == 2
    assert "character device" in capsys.readouterr().err


def test_files_over_their_size_limit_are_refused_before_they_are_read(tmp_path):
    from poinsot.errors import InvalidInputError
    from poinsot.mass import read_mesh
    from poinsot.scenarios.io import MAX_SCENARIO_BYTES

    big = tmp_path / "big.obj"
    big.write_text(TET + "# padding\n" * 200)  # a valid mesh, 2,058 bytes
    v, f = read_mesh(big)  # under the default limit: read
    assert v.shape == (4, 3) and f.shape == (4, 3)
    with pytest.raises(InvalidInputError, match=r"big.obj: expected a mesh file of at most"):
        read_mesh(big, max_bytes=big.stat().st_size - 1)
    assert read_mesh(big, max_bytes=big.stat().st_size)[0].shape == (4, 3)  # the bound is <=
    # a scenario file of 1 MiB + 1 byte (comments): refused, its size named
    path = _scenario(tmp_path / "s", "../big.obj")
    text = path.read_text()
    path.write_text(text + "#" * (MAX_SCENARIO_BYTES - len(text.encode())) + "\n")
    with pytest.raises(ScenarioError, match="at most 1 MiB"):
        load_scenario(path)
