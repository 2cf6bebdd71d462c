"""numba on-disk caching that also sees edits of shared helper modules (private).

numba stamps a cached kernel with the hash of the one source file that defines
it. A kernel that inlines ``@njit`` helpers from another module (as the
steppers do with :mod:`poinsot._numba_helpers`) would then keep running the
old helper after the helper file is edited. :func:`depends_on` declares such a
dependency: the kernels of that file get a cache locator whose stamp is
``(numba's own stamp, sha256 of every helper file)``, so editing a helper
invalidates every cached kernel that uses it (numba recompiles on the next
call and overwrites the stale index). Everything else about the cache (where it
lives, ``NUMBA_CACHE_DIR``) is numba's. A process that sets
``NUMBA_CACHE_LOCATOR_CLASSES`` replaces numba's locator list and so this one.

Importing this module imports numba (unless the NumPy executor of :mod:`poinsot._jit`
is in use): only kernel modules (imported lazily) do.

Usage, at the top of a kernel module, before its ``@njit(cache=True)`` kernels::

    from .. import _numba_helpers as nh
    from .._numba_cache import depends_on

    depends_on(__file__, nh)
"""

from __future__ import annotations

import functools
import hashlib
import os
from types import ModuleType
from typing import Any

from ._jit import NUMBA

__all__ = ["depends_on"]

if NUMBA:
    from numba.core import caching

    # numba >= 0.62 names it CacheImpl, older versions _CacheImpl
    _IMPL = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # type: ignore[attr-defined]
    _LocatorBase: Any = caching._CacheLocator
else:  # the NumPy executor (poinsot._jit) compiles nothing, so caches nothing
    _LocatorBase = object

#: kernel source file (absolute) -> helper source files (absolute) it depends on
_DEPENDS: dict[str, tuple[str, ...]] = {}


@functools.cache
def _file_hash(path: str, mtime_ns: int, size: int) -> str:
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def _stamp(paths: tuple[str, ...]) -> tuple[str, ...]:
    out = []
    for p in paths:
        st = os.stat(p)
        out.append(_file_hash(p, st.st_mtime_ns, st.st_size))
    return tuple(out)


class _DependentLocator(_LocatorBase):  # type: ignore[misc]  # numba's, or object
    """Wraps numba's own locator for a kernel file; adds the helpers' hashes to the stamp."""

    def __init__(self, inner, deps: tuple[str, ...]):
        self._inner = inner
        self._deps = deps

    def __getattr__(self, name):
        # anything else numba reads of a locator (e.g. `_py_file` in its "cannot cache"
        # warning) is the wrapped locator's
        if name == "_inner":
            raise AttributeError(name)
        return getattr(self._inner, name)

    def ensure_cache_path(self):
        self._inner.ensure_cache_path()

    def get_cache_path(self):
        return self._inner.get_cache_path()

    def get_disambiguator(self):
        return self._inner.get_disambiguator()

    def get_source_stamp(self):
        return (self._inner.get_source_stamp(), _stamp(self._deps))

    @classmethod
    def from_function(cls, py_func, py_file):
        deps = _DEPENDS.get(os.path.abspath(py_file))
        if deps is None:
            return None
        for other in _IMPL._locator_classes:
            if other is cls:
                continue
            inner = other.from_function(py_func, py_file)
            if inner is not None:
                return cls(inner, deps)
        return None


def depends_on(kernel_file: str, *helpers: ModuleType | str) -> None:
    """Make the cached kernels of ``kernel_file`` depend on the ``helpers``' sources.

    ``helpers`` are modules (their ``__file__``) or paths; a helper module's own
    ``DEPENDS`` (modules it is built from) are followed, transitively. Call it
    before the kernels are decorated (numba picks the locator when
    ``@njit(cache=True)`` runs).
    """
    if not NUMBA:
        return
    paths: list[str] = []
    todo = list(helpers)
    while todo:  # a helper module lists the files it is built from in ``DEPENDS``
        h = todo.pop(0)
        path = os.path.abspath(getattr(h, "__file__", h))
        if path not in paths:
            paths.append(path)
            todo.extend(getattr(h, "DEPENDS", ()))
    _DEPENDS[os.path.abspath(kernel_file)] = tuple(paths)
    classes = _IMPL._locator_classes
    if _DependentLocator not in classes:
        classes.insert(0, _DependentLocator)
