"""Lazy access to the compiled kernels (numba loads on first use, not on import)."""

from __future__ import annotations

import importlib
from types import ModuleType

_MODULE: ModuleType | None = None


def kernels() -> ModuleType:
    """Return :mod:`poinsot.rotations._kernels`, importing (and compiling) it once."""
    global _MODULE
    if _MODULE is None:
        _MODULE = importlib.import_module("poinsot.rotations._kernels")
    return _MODULE
