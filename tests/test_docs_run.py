"""Every Python block of the docs runs as printed (issue 23: "docs that run as printed").

``>>>`` examples are run by :mod:`test_docs_examples` (``doctest.testfile`` on every
page that has them); here every fenced ``python`` block *without* prompts is executed
as a script, the blocks of one page in order in one namespace, from the repository
root (where the pages' relative paths such as ``examples/...`` point). A block that
cannot run in a test (it starts a long computation, needs a display) is preceded by
``<!-- not run: the reason -->`` in the page, and this test checks the reason is given.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
_BLOCK = re.compile(r"(<!--\s*not run:([^>]*)-->\s*\n)?```python\n(.*?)```", re.S)


def _blocks(page: Path) -> list[tuple[str | None, str]]:
    """``(reason not run or None, code)`` of the page's prompt-less python blocks."""
    out = []
    for m in _BLOCK.finditer(page.read_text()):
        code = m.group(3)
        if ">>>" in code:
            continue
        out.append((None if m.group(1) is None else m.group(2).strip(), code))
    return out


PAGES = sorted(p for p in DOCS.glob("*.md") if _blocks(p))


def test_every_page_with_prompts_is_doctested():
    from test_docs_examples import PAGES, SLOW_PAGES

    DOCTESTED = PAGES + SLOW_PAGES

    with_prompts = {p.name for p in DOCS.glob("*.md") if ">>> " in p.read_text()}
    assert with_prompts <= set(DOCTESTED), sorted(with_prompts - set(DOCTESTED))


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_python_blocks_run_as_printed(page, monkeypatch, tmp_path):
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    namespace: dict[str, object] = {"__name__": "__main__"}
    # `make demo` (the README's first command) leaves ./poinsot-out in the checkout: a
    # block may not add to it, whatever was there before
    before = _tree(ROOT / "poinsot-out")
    ran = 0
    for reason, code in _blocks(page):
        if reason is not None:
            assert len(reason) > 10, f"docs/{page.name}: a block marked not run needs a reason"
            continue
        exec(compile(code, f"docs/{page.name}", "exec"), namespace)  # noqa: S102
        ran += 1
    # outputs a block wrote into the repository would be left behind: none may be
    assert _tree(ROOT / "poinsot-out") == before


def _tree(folder: Path) -> dict[str, int]:
    """Every file below ``folder`` with its modification time (ns); {} if none."""
    if not folder.exists():
        return {}
    return {str(p): p.stat().st_mtime_ns for p in folder.rglob("*")}


def test_cli_page_lists_every_kind_and_every_example():
    """docs/cli.md names every scenario kind in its table and every shipped example."""
    from poinsot.scenarios.registry import KINDS

    text = (DOCS / "cli.md").read_text()
    for kind in KINDS:
        assert f'| `"{kind}"` |' in text, kind
    for example in sorted((ROOT / "examples").glob("*.toml")):
        assert f"`{example.name}`" in text or example.stem in text, example.name
