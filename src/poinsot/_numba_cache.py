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

__all__ = ["depends_on", "install_safe_saves"]

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


# ------------------------------------------------------- saves safe across processes
@functools.cache
def _our_cache_paths() -> frozenset[str]:
    """Where numba's locators put the caches of poinsot's kernel files (one folder per
    source folder: in the tree, under NUMBA_CACHE_DIR, or in the user-wide cache)."""
    root = os.path.dirname(os.path.abspath(__file__))
    out = set()

    def probe() -> None:
        pass

    for folder, _dirs, files in os.walk(root):
        py = [f for f in files if f.endswith(".py")]
        if not py:
            continue
        for cls in _IMPL._locator_classes:
            if cls is _DependentLocator:
                continue
            try:
                loc = cls.from_function(probe, os.path.join(folder, py[0]))
            except Exception:  # a locator that does not apply here
                continue
            if loc is not None:
                out.add(os.path.normpath(loc.get_cache_path()))
                break
    return frozenset(out)


_SAVES_SAFE = False


def _safe_save(self: Any, key: Any, data: Any) -> None:
    """numba's ``IndexDataCacheFile.save`` for poinsot's caches, safe when several
    processes fill one cold cache at once (pytest-xdist workers, a process pool).

    numba names a new data file by the first number its index does not use, and
    writes the index before the data. Two processes that read the index at the same
    time give *different* signatures the same data file, and the index then points
    one signature to the other's machine code: a later load runs it on the wrong
    argument types and segfaults (the crash this replaces). Here a data file is named
    by a hash of its index key, so it can only ever hold that key's code; it is
    written before the index entry that points to it, and the index is read again
    just before it is written, so a concurrent entry is rarely lost (a lost one is
    compiled again, never wrong)."""

    digest = hashlib.sha256(repr(key).encode()).hexdigest()[:20]
    data_name = self._data_name_pattern.replace("{number:d}", "k" + digest)
    self._save_data(data_name, data)
    overloads = self._load_index()
    if overloads.get(key) != data_name:
        overloads[key] = data_name
        self._save_index(overloads)


def install_safe_saves() -> None:
    """Route numba's cache saves of poinsot's kernels through :func:`_safe_save`
    (other packages' caches keep numba's own save). Idempotent."""
    global _SAVES_SAFE
    if _SAVES_SAFE or not NUMBA:
        return
    original = caching.IndexDataCacheFile.save

    @functools.wraps(original)
    def save(self: Any, key: Any, data: Any) -> None:
        if os.path.normpath(str(getattr(self, "_cache_path", ""))) in _our_cache_paths():
            _safe_save(self, key, data)
        else:
            original(self, key, data)

    caching.IndexDataCacheFile.save = save  # type: ignore[method-assign]
    _SAVES_SAFE = True
