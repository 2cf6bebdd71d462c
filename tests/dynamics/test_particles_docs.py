"""The `>>>` examples of docs/particles.md run as doctests (outputs checked)."""

from __future__ import annotations

import doctest
from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_particles_guide_examples_run():
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    result = doctest.testfile(
        str(DOCS / "particles.md"), module_relative=False, optionflags=flags, verbose=False
    )
    assert result.attempted >= 15 and result.failed == 0, result
