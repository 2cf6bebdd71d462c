"""The Sphinx site builds with warnings as errors (what `make docs` and CI run).

Skipped when Sphinx, MyST or numpydoc is not installed (the ``docs`` extra).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_parser")
pytest.importorskip("numpydoc")

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("docs")
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html"]
    cmd += ["-d", str(out / "doctrees"), str(DOCS), str(out / "html")]
    # ~1 min alone; it took over 300 s on a loaded machine
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, f"sphinx -W failed:\n{proc.stdout}\n{proc.stderr}"
    return out / "html"


def test_every_page_is_built(site):
    sources = [p for p in DOCS.glob("*.md") if p.name != "README.md"]
    assert sources, "no pages in docs/"
    for src in sources:
        assert (site / f"{src.stem}.html").is_file(), src.name


def test_notebooks_are_in_the_site(site):
    for nb in (DOCS / "notebooks").glob("*.ipynb"):
        page = site / "notebooks" / f"{nb.stem}.html"
        assert page.is_file(), nb.name
        assert "poinsot" in page.read_text(encoding="utf-8")


def test_conventions_page_comes_first(site):
    index = (site / "index.html").read_text(encoding="utf-8")
    first = re.search(r'<li class="toctree-l1"><a class="reference internal" href="([^"#]+)', index)
    assert first is not None and first.group(1) == "conventions.html"


@pytest.mark.parametrize(
    ("page", "anchor"),
    [
        ("api/rotation.html", 'id="poinsot.Rotation.from_quat"'),
        ("api/quaternion.html", 'id="poinsot.quaternion.multiply"'),
        ("api/poinsot.html", 'id="poinsot.Trajectory"'),
        ("api/plotting.html", 'id="poinsot.plotting.write_report"'),
        ("api/kinematics.html", 'id="poinsot.kinematics.propagate"'),
        ("api/mass.html", 'id="poinsot.mass.box"'),
        ("api/dynamics.html", 'id="poinsot.dynamics.simulate"'),
        ("api/scenarios.html", 'id="poinsot.scenarios.load_scenario"'),
    ],
)
def test_api_reference_documents_public_names(site, page, anchor):
    assert anchor in (site / page).read_text(encoding="utf-8")


def test_guide_examples_run():
    """The `>>>` examples of the rotations guide are doctests (outputs checked)."""
    import doctest

    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    result = doctest.testfile(
        str(DOCS / "guide-rotations.md"), module_relative=False, optionflags=flags, verbose=False
    )
    assert result.attempted > 10 and result.failed == 0, result
