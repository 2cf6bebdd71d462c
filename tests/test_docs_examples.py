"""The ``>>>`` examples of the library docs pages run and give what they show.

The pages are Markdown read by MyST; their examples are plain doctest blocks,
so ``doctest.testfile`` runs them exactly as a reader would type them.
"""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = [  # every page with >>> examples (tests/test_docs_run.py checks it)
    "notebook.md",
    "verify.md",
    "mass.md",
    "dynamics.md",
    "conventions.md",
    "math-to-code.md",
    "kinematics-propagate.md",
    "guide-rotations.md",
    "integrators.md",
    "lagrange.md",
    "free-body.md",
    "gyrostat.md",
    "spacecraft.md",
    "heavy-top.md",
    "kinematics-fields.md",
    "kinematics-rates.md",
    "particles.md",
    "contact.md",
]
SLOW_PAGES = [  # minutes of XLA compiling: `make test-slow`
    "jax-fit.md",
    "jax.md",  # ~100 s: the exact attitude's programs (tests/test_jax_free_body.py checks them)
]


@pytest.mark.parametrize(
    "page", PAGES + [pytest.param(p, marks=pytest.mark.slow) for p in SLOW_PAGES]
)
def test_page_examples_run(page, monkeypatch, tmp_path):
    # files an example writes (docs/notebook.md saves "flip.html") go to a scratch folder
    monkeypatch.chdir(tmp_path)
    path = DOCS / page
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    result = doctest.testfile(str(path), module_relative=False, optionflags=flags, verbose=False)
    assert result.failed == 0, f"{result.failed} example(s) of docs/{page} failed"
