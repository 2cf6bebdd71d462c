"""``docs/math-to-code.md`` cites only names that exist.

Every backticked ``poinsot.a.b...`` on the page must resolve: the longest
importable module prefix, then attributes (classes, functions, methods,
constants). A formula moved without updating its row fails here.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

PAGE = Path(__file__).resolve().parents[1] / "docs" / "math-to-code.md"
NAME = re.compile(r"`(poinsot(?:\.[A-Za-z_][A-Za-z0-9_]*)+)`")


def _cited() -> list[str]:
    return sorted(set(NAME.findall(PAGE.read_text(encoding="utf-8"))))


def _resolve(dotted: str):
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)  # AttributeError: the name does not exist
        return obj
    raise ImportError(dotted)


def test_page_cites_many_names():
    names = _cited()
    assert len(names) > 60, names  # the regex finds the table entries
    assert "poinsot.dynamics.GravityTorque" in names


@pytest.mark.parametrize("name", _cited())
def test_cited_name_exists(name):
    _resolve(name)


def test_resolver_rejects_a_missing_name():
    with pytest.raises(AttributeError):
        _resolve("poinsot.dynamics.no_such_formula")
