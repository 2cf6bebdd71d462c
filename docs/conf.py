"""Sphinx configuration of the poinsot documentation.

Built by ``make docs`` (``python -m sphinx -W -b html docs docs/_build/html``):
warnings are errors. Pages are Markdown (MyST); docstrings are numpydoc; the
API reference is generated from each module's ``__all__`` by the small
``poinsot-api`` directive in ``_ext/poinsot_api.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent / "src"))  # build from the checkout, installed or not

import poinsot  # noqa: E402

project = "poinsot"
author = "the poinsot developers"
copyright = "the poinsot developers, BSD-3-Clause"  # noqa: A001
release = poinsot.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "myst_nb",  # MyST Markdown pages and the notebooks of docs/notebooks (MyST-NB)
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "poinsot_api",
]

source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = [
    "_build", "Thumbs.db", ".DS_Store", "examples/*.py", "**/README.md", "**/.ipynb_checkpoints",
]  # fmt: skip
# The notebooks are stored without outputs and executed by the test suite
# (tests/test_notebooks.py); the site shows their source, not a second execution.
nb_execution_mode = "off"
templates_path: list[str] = []

# ---- MyST: Markdown pages
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# ---- autodoc / autosummary / numpydoc
autosummary_generate = False  # the tables link to the autodoc entries on the same page
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
numpydoc_show_class_members = False  # autodoc lists the members once
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True  # dataclass fields: no duplicate object entries
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# No network while building (no intersphinx); noise that is not a documentation error:
suppress_warnings = [
    "myst.header",  # pages starting below level 1 or skipping levels
    "myst.xref_missing",  # links to source files outside docs/ (e.g. ../examples/*.toml)
    "autosectionlabel.*",
]
nitpicky = False

# ---- HTML
html_theme = "alabaster"
html_title = f"poinsot {release}"
html_static_path = ["_static"]
html_theme_options = {
    "description": "Rigid-body kinematics and dynamics on quaternions",
    "fixed_sidebar": True,
    "page_width": "1100px",
    "sidebar_width": "240px",
}
html_sidebars = {"**": ["about.html", "navigation.html", "relations.html", "searchbox.html"]}
html_show_sourcelink = False
