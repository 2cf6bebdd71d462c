"""dir() of each public package lists its public API: __all__ (no `annotations` from
`from __future__ import annotations`, no submodule names), and every name exists."""

import importlib

import pytest

PACKAGES = [
    "poinsot.rotations",
    "poinsot.kinematics",
    "poinsot.dynamics",
    "poinsot.mass",
    "poinsot.symbolic",
    "poinsot.scenarios",
    "poinsot.plotting",
    "poinsot.ensemble",
    "poinsot.exercises",
]


@pytest.mark.parametrize("name", PACKAGES)
def test_dir_is_all(name):
    if name in ("poinsot.symbolic",):
        pytest.importorskip("sympy")
    if name == "poinsot.ensemble":
        pytest.importorskip("dask")
    if name == "poinsot.plotting":
        pytest.importorskip("matplotlib")
    mod = importlib.import_module(name)
    assert dir(mod) == sorted(mod.__all__)
    assert "annotations" not in dir(mod)
    for attr in mod.__all__:
        assert hasattr(mod, attr), f"{name}.{attr} listed in __all__ but missing"


def test_top_level_dir_is_public():
    import poinsot

    names = dir(poinsot)
    assert "annotations" not in names and "importlib" not in names
    assert {"Rotation", "compare", "dynamics", "kinematics", "__version__"} <= set(names)
    for attr in poinsot.__all__:
        assert hasattr(poinsot, attr)
