"""Measure the headroom of every numerical tolerance in the test suite.

The rule (README, "Testing"): every tolerance is at least **10x** the error
observed, and the reference is at least 100x more accurate than the tolerance.
This tool checks the first half mechanically. It runs pytest with a plugin that,
in test code only (files under ``tests/``; the library is untouched), watches

* ``assert_allclose``, ``np.isclose``/``allclose``, ``math.isclose`` and
  ``pytest.approx`` (``rtol``/``atol``/``rel``/``abs``/``rel_tol``/``abs_tol``,
  their defaults included), and
* comparisons inside ``assert`` statements whose bound looks like a tolerance:
  ``err < b``, ``err <= b``, ``b > err``, ``b >= err`` where ``b`` contains a
  float literal <= 0.1 or a name containing ``tol`` or ``eps`` (any case),

records at each call site the **headroom** ``tolerance / observed error`` (its
minimum over every call and every element; for ``assert_allclose`` the error
of element ``i`` is ``|a_i - d_i| / (atol + rtol |d_i|)``), and prints the sites
whose headroom is below 10 with the test that came closest.

With ``--factor F`` (``F > 1``) every watched tolerance is also divided by ``F``
so that the tests without that much headroom fail, which is a direct
demonstration (the default, ``--factor 1``, changes nothing and only measures).

Usage (from the repository root; low priority, the machine is shared)::

    nice -n 10 .venv/bin/python tools/shake_tolerances.py [--factor F] [--min 10] [pytest args]
    NUMBA_CPU_NAME=generic nice -n 10 .venv/bin/python tools/shake_tolerances.py tests/rotations

The default pytest arguments are ``tests``. The full table goes to
``$SHAKE_OUT`` (default ``/tmp/shake_tolerances.tsv``). Bounds that are not
tolerances but look like one (a step-size limit, a statistical bound, a
distance to a singularity) show up too: judge each site.

It is a pytest plugin (``-p shake_tolerances``) that transforms the test
modules' syntax trees before pytest's assertion rewriting; compiled test modules
go to a private ``sys.pycache_prefix`` so that the normal ``__pycache__`` is
neither read (it would skip the transform) nor overwritten.
"""

from __future__ import annotations

import ast
import inspect
import math
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

FACTOR = float(os.environ.get("SHAKE_FACTOR", "1"))
_TOL_NAME = re.compile(r"tol|eps", re.IGNORECASE)
_CALLS = {"assert_allclose", "allclose", "isclose", "approx"}
_PARAMS = {"rtol", "atol", "rel", "abs", "rel_tol", "abs_tol"}

#: 'site\ttest id' -> [headroom, error, tolerance, test id, calls]
_RECORD: dict[str, list] = {}
_CURRENT = {"test": "?"}


# ---------------------------------------------------------------- recording
def _record(site, headroom, error, tol):
    site = f"{site}\t{_CURRENT['test']}"  # one entry per site and test (parametrized bounds)
    try:
        headroom = float(headroom)
    except (TypeError, ValueError):
        return
    if math.isnan(headroom):
        return
    entry = _RECORD.get(site)
    if entry is None:
        _RECORD[site] = [headroom, error, tol, _CURRENT["test"], 1]
        return
    entry[4] += 1
    if headroom < entry[0]:
        entry[:4] = [headroom, error, tol, _CURRENT["test"]]


def _scale(value):
    """``value / FACTOR`` for positive finite numbers (scalars or arrays); else as is."""
    if FACTOR == 1:
        return value
    import numpy as np

    if isinstance(value, np.ndarray):
        ok = np.isfinite(value) & (value > 0)
        return np.where(ok, value / FACTOR, value)
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
        return value
    if math.isfinite(value) and value > 0:
        return value / FACTOR
    return value


def _closeness(actual, desired, rtol, atol):
    """Worst ``|a - d| / (atol + rtol |d|)`` (0 where equal), its error and tolerance."""
    import numpy as np

    try:
        a, d = np.broadcast_arrays(np.asarray(actual), np.asarray(desired))
    except (TypeError, ValueError):
        return None
    if a.size == 0 or a.dtype.kind not in "biufc" or d.dtype.kind not in "biufc":
        return None
    with np.errstate(all="ignore"):
        diff = np.abs(a - d)
        same = (a == d) | (np.isnan(a) & np.isnan(d))
        diff = np.where(same, 0.0, diff)
        tol = atol + rtol * np.abs(d)
        ratio = np.where(diff == 0, 0.0, np.where(tol > 0, diff / tol, np.inf))
    i = int(np.nanargmax(ratio)) if np.isfinite(ratio).any() or ratio.size else 0
    return float(ratio.flat[i]), float(diff.flat[i]), float(tol.flat[i])


def _note_closeness(site, actual, desired, rtol, atol):
    got = _closeness(actual, desired, rtol, atol)
    if got is None:
        return
    ratio, err, tol = got
    _record(site, math.inf if ratio == 0 else 1.0 / ratio, err, tol)


def _shake_cmp(left, op, right, site):
    """``left op right`` with the bound tightened, recording ``bound / value``."""
    import numpy as np

    if op in ("lt", "le"):
        value, bound = left, _scale(right)
    else:
        value, bound = right, _scale(left)
    try:
        v = float(np.max(np.abs(np.asarray(value, dtype=float))))
        b = float(np.min(np.asarray(bound, dtype=float)))
        _record(site, math.inf if v == 0 else b / v, v, b)
    except (TypeError, ValueError):
        pass
    if op == "lt":
        return left < bound
    if op == "le":
        return left <= bound
    if op == "gt":
        return bound > right
    return bound >= right


def _approx_recorder(obj, site):
    cls = type(obj)

    def __eq__(self, actual):  # noqa: N807
        try:
            worst = None
            if hasattr(self, "_yield_comparisons"):
                pairs = list(self._yield_comparisons(actual))
            else:
                pairs = [(actual, self.expected)]
            for a, e in pairs:
                scalar = self._approx_scalar(e) if hasattr(self, "_approx_scalar") else self
                tol = float(scalar.tolerance)
                err = abs(float(a) - float(e))
                ratio = 0.0 if err == 0 else (err / tol if tol > 0 else math.inf)
                if worst is None or ratio > worst[0]:
                    worst = (ratio, err, tol)
            if worst is not None:
                _record(site, math.inf if worst[0] == 0 else 1 / worst[0], worst[1], worst[2])
        except Exception:  # noqa: BLE001 - recording must never change the test
            pass
        return cls.__eq__(self, actual)

    try:
        obj.__class__ = type("Recorded" + cls.__name__, (cls,), {"__eq__": __eq__})
    except TypeError:
        pass
    return obj


def _shake_call(func, site, *args, **kwargs):
    """Call an approximate-equality function, tolerances tightened, recording headroom."""
    name = getattr(func, "__name__", "")
    if name == "approx":
        rel, abs_ = kwargs.get("rel"), kwargs.get("abs")
        if len(args) > 1:  # approx(expected, rel, abs, nan_ok)
            rel = args[1]
        if len(args) > 2:
            abs_ = args[2]
        args = args[:1]
        if rel is None and abs_ is not None:
            kwargs["abs"] = _scale(abs_)
            kwargs.pop("rel", None)
        elif FACTOR != 1 or rel is not None or abs_ is not None:
            kwargs["rel"] = _scale(1e-6 if rel is None else rel)
            kwargs["abs"] = _scale(1e-12 if abs_ is None else abs_)
        return _approx_recorder(func(*args, **kwargs), site)
    try:
        bound = inspect.signature(func).bind(*args, **kwargs)
    except (TypeError, ValueError):
        return func(*args, **kwargs)
    bound.apply_defaults()
    arg = bound.arguments
    for key in list(arg):
        if key in _PARAMS and arg[key] is not None:
            arg[key] = _scale(arg[key])
    if name == "assert_allclose":
        _note_closeness(site, arg.get("actual"), arg.get("desired"), arg["rtol"], arg["atol"])
    elif name in ("isclose", "allclose") and "rtol" in arg:
        _note_closeness(site, arg.get("a"), arg.get("b"), arg["rtol"], arg["atol"])
    elif name == "isclose" and "rel_tol" in arg:  # math.isclose
        try:
            a, b = float(args[0]), float(args[1])
            tol = max(arg["rel_tol"] * max(abs(a), abs(b)), arg["abs_tol"])
            err = abs(a - b)
            _record(site, math.inf if err == 0 else tol / err, err, tol)
        except (TypeError, ValueError, IndexError):
            pass
    return func(*bound.args, **bound.kwargs)


# ---------------------------------------------------------------- AST transform
def _looks_like_tolerance(node: ast.AST) -> bool:
    for sub in ast.walk(node):
        if isinstance(sub, ast.Constant) and isinstance(sub.value, float):
            if 0 < sub.value <= 0.1:
                return True
        if isinstance(sub, ast.Name) and _TOL_NAME.search(sub.id):
            return True
        if isinstance(sub, ast.Attribute) and _TOL_NAME.search(sub.attr):
            return True
    return False


_OPS = {ast.Lt: "lt", ast.LtE: "le", ast.Gt: "gt", ast.GtE: "ge"}


class _Watch(ast.NodeTransformer):
    def __init__(self, filename: str):
        self.filename = filename
        self.in_assert = 0
        self.count = 0

    def _site(self, node) -> ast.Constant:
        return ast.Constant(f"{self.filename}:{node.lineno}")

    def visit_Assert(self, node):
        self.in_assert += 1
        node.test = self.visit(node.test)
        self.in_assert -= 1
        if node.msg is not None:
            node.msg = self.visit(node.msg)
        return node

    def visit_Compare(self, node):
        self.generic_visit(node)
        if not self.in_assert or len(node.ops) != 1 or type(node.ops[0]) not in _OPS:
            return node
        op = _OPS[type(node.ops[0])]
        bound = node.comparators[0] if op in ("lt", "le") else node.left
        if not _looks_like_tolerance(bound):
            return node
        self.count += 1
        call = ast.Call(
            func=ast.Name(id="__shake_cmp__", ctx=ast.Load()),
            args=[node.left, ast.Constant(op), node.comparators[0], self._site(node)],
            keywords=[],
        )
        return ast.copy_location(call, node)

    def visit_Call(self, node):
        self.generic_visit(node)
        func = node.func
        name = func.id if isinstance(func, ast.Name) else getattr(func, "attr", None)
        if name not in _CALLS:
            return node
        self.count += 1
        call = ast.Call(
            func=ast.Name(id="__shake_call__", ctx=ast.Load()),
            args=[func, self._site(node), *node.args],
            keywords=node.keywords,
        )
        return ast.copy_location(call, node)


def watch_tree(tree: ast.Module, filename: str) -> int:
    """Instrument a module's syntax tree in place; return the number of sites."""
    watch = _Watch(filename)
    watch.visit(tree)
    if watch.count:
        imp = ast.parse(
            "from shake_tolerances import _shake_cmp as __shake_cmp__, "
            "_shake_call as __shake_call__"
        ).body[0]
        body = tree.body
        i = 0
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            i = 1
        while (
            i < len(body) and isinstance(body[i], ast.ImportFrom) and body[i].module == "__future__"
        ):
            i += 1
        body.insert(i, imp)
        ast.fix_missing_locations(tree)
    return watch.count


# ---------------------------------------------------------------- pytest plugin
def pytest_configure(config):
    import _pytest.assertion.rewrite as rewrite
    import pytest

    sys.dont_write_bytecode = True
    sys.pycache_prefix = tempfile.mkdtemp(prefix="shake-pyc-")
    original = rewrite.rewrite_asserts
    root = Path(config.rootpath)
    tests_dir = str(root / "tests")

    def rewrite_asserts(mod, source, module_path=None, config=None):
        if module_path is not None and str(module_path).startswith(tests_dir):
            watch_tree(mod, str(Path(module_path).relative_to(root)))
        return original(mod, source, module_path, config)

    rewrite.rewrite_asserts = rewrite_asserts
    # helper modules imported from tests/ (not test_*.py) are rewritten too
    for path in Path(tests_dir).rglob("*.py"):
        if not path.name.startswith(("test_", "conftest")):
            pytest.register_assert_rewrite(path.stem)


def pytest_runtest_setup(item):
    _CURRENT["test"] = item.nodeid


def pytest_report_header(config):
    return f"shake_tolerances: recording headroom; tolerances divided by {FACTOR:g}"


def pytest_sessionfinish(session):
    out = Path(os.environ.get("SHAKE_OUT", "/tmp/shake_tolerances.tsv"))
    rows = sorted(_RECORD.items(), key=lambda kv: kv[1][0])
    with out.open("w") as f:
        f.write("site\ttest\theadroom\terror\ttolerance\tcalls\n")
        for site, (h, err, tol, _test, calls) in rows:
            f.write(f"{site}\t{h:.3g}\t{err:.3g}\t{tol:.3g}\t{calls}\n")
    limit = float(os.environ.get("SHAKE_MIN", "10"))
    low = [(s.split("\t")[0], r) for s, r in rows if r[0] < limit]
    tr = session.config.pluginmanager.get_plugin("terminalreporter")
    write = tr.write_line if tr is not None else print
    write(
        f"\nshake_tolerances: {len(rows)} (site, test) pairs, {len(low)} with headroom"
        f" < {limit:g} (full table: {out})"
    )
    for site, (h, err, tol, test, _calls) in low:
        write(f"  {site:<50} headroom {h:9.3g}  error {err:9.3g}  tol {tol:9.3g}  {test}")


# ---------------------------------------------------------------- command line
def main(argv: list[str]) -> int:
    env = dict(os.environ)
    while argv[:1] in (["--factor"], ["--min"]):
        env["SHAKE_FACTOR" if argv[0] == "--factor" else "SHAKE_MIN"] = argv[1]
        argv = argv[2:]
    root = Path(__file__).resolve().parents[1]
    path = [str(root / "tools"), *filter(None, [env.get("PYTHONPATH")])]
    env["PYTHONPATH"] = os.pathsep.join(path)
    env.setdefault("NUMBA_CACHE_DIR", tempfile.mkdtemp(prefix="shake-numba-"))
    cmd = [
        sys.executable,
        "-m",
        "pytest",
        "-p",
        "shake_tolerances",
        "-p",
        "no:cacheprovider",
        "-o",
        "addopts=-q -rs --import-mode=importlib",
        "--tb=no",
        "-rf",
        *(argv or ["tests"]),
    ]
    print("+", " ".join(cmd), flush=True)
    return subprocess.call(cmd, cwd=root, env=env)


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
