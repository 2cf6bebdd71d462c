"""Imports flow one way (docs/conventions.md, "Layout"): every ``poinsot`` import in the
package, at module level or inside a function, goes from a module to one of the same
layer or a lower one. Read with ``ast`` from the source files (nothing imported)."""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

SRC = Path(__file__).parents[1] / "src" / "poinsot"

#: lowest first; a module may import its own layer and those below it
LAYERS: list[tuple[str, ...]] = [
    (
        "errors",
        "_typing",
        "_vec",
        "_validate",
        "_jit",
        "_rolled",
        "_numba_cache",
        "_progress",
        "_scratch",
        "_files",
        "_drift",
        "_deprecate",
        "_display",
        "__version__",
        "integrators",
        "events",
    ),
    ("rotations", "_quat", "_numba_helpers", "mass"),  # mass stands beside rotations
    ("kinematics", "trajectory"),
    ("dynamics",),
    ("symbolic", "plotting", "jax"),  # leaves: nothing below imports them
    # verify: exact solutions + plotting, for engines; exercises: generated problems
    ("scenarios", "verify", "exercises"),
    ("ensemble",),
    ("cli", ""),  # "" is the package poinsot itself (its __init__)
]
LEVEL = {name: k for k, names in enumerate(LAYERS) for name in names}


def _part(module: str) -> str:
    """``poinsot.dynamics.heavy`` -> ``dynamics``; ``poinsot`` -> ``""``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def _edges():
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC.parent).with_suffix("")
        module = ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)
        package = module if rel.name == "__init__" else module.rsplit(".", 1)[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = []
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if target == "poinsot":  # from poinsot import X / from .. import X
                    targets = [f"poinsot.{a.name}" for a in node.names]
                else:
                    targets = [target]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            for target in targets:
                if target == "poinsot" or target.startswith("poinsot."):
                    yield module, target, path.relative_to(SRC.parent), node.lineno


def test_every_module_is_in_a_layer():
    parts = {_part(m) for m, *_ in _edges()} | {_part(t) for _, t, *_ in _edges()}
    assert parts <= set(LEVEL), parts - set(LEVEL)


#: The one upward import allowed: ``Result.show()`` is the shorthand of
#: ``poinsot.plotting.show(result)`` asked for by issue 21; it imports the viewer only
#: when called, so no lower layer loads plotting until the user asks for a drawing.
UPWARD_ALLOWED = {("poinsot.trajectory", "poinsot.plotting.notebook")}


def test_imports_flow_from_higher_to_lower_layers_only():
    bad = []
    for module, target, path, line in _edges():
        src, dst = _part(module), _part(target)
        if LEVEL[dst] > LEVEL[src] and (module, target) not in UPWARD_ALLOWED:
            bad.append(f"{path}:{line}: {module} imports {target} (a higher layer)")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("leaf", ["plotting", "symbolic"])
def test_leaves_are_imported_only_from_above(leaf):
    users = {
        _part(m)
        for m, t, *_ in _edges()
        if _part(t) == leaf and _part(m) != leaf and (m, t) not in UPWARD_ALLOWED
    }
    assert all(LEVEL[u] >= LEVEL[leaf] for u in users), users


def test_plotting_never_imports_scenarios():
    bad = [
        f"{p}:{n}" for m, t, p, n in _edges() if _part(m) == "plotting" and _part(t) == "scenarios"
    ]
    assert not bad, bad


# ------------------------------------------------- function-level imports and circles
def _module_name(path: Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    return ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)


MODULES = {_module_name(p): p for p in sorted(SRC.rglob("*.py"))}


def _resolve(module: str, path: Path, node: ast.ImportFrom, modules: dict[str, Path]) -> list[str]:
    """The poinsot modules an ``ImportFrom`` loads: ``from pkg import sub`` -> ``pkg.sub``."""
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    if node.level:
        base = package.split(".")[: len(package.split(".")) - node.level + 1]
        target = ".".join(base + ([node.module] if node.module else []))
    else:
        target = node.module or ""
    if not target.startswith("poinsot"):
        return []
    return [f"{target}.{a.name}" if f"{target}.{a.name}" in modules else target for a in node.names]


@functools.cache
def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), str(path))


def _imports(module: str, modules: dict[str, Path]) -> list[tuple[str, bool, int]]:
    """``(target, inside a function, line)`` of every poinsot import of ``module``
    (not those under ``if TYPE_CHECKING``: they never run)."""
    path = modules[module]
    tree = _tree(path)
    typing_only = {
        id(n)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
        for n in ast.walk(node)
    }
    inner = {
        id(n)
        for fn in ast.walk(tree)
        if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef)
        for n in ast.walk(fn)
    }
    out = []
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.ImportFrom):
            targets = _resolve(module, path, node, modules)
        elif isinstance(node, ast.Import):
            targets = [a.name for a in node.names if a.name.startswith("poinsot")]
        else:
            continue
        out += [(t, id(node) in inner, node.lineno) for t in targets]
    return out


def _loads_numba(modules: dict[str, Path]) -> set[str]:
    """The kernel modules: loading one compiles (or loads from numba's cache) kernels,
    because it takes ``njit``/``guvectorize``/``prange`` from ``poinsot._jit`` at module
    level, or imports such a module at module level."""
    kernels = set()
    for module, path in modules.items():
        for node in _tree(path).body:
            if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("_jit"):
                if {a.name for a in node.names} & {"njit", "guvectorize", "prange"}:
                    kernels.add(module)
    tops = {m: {t for t, inner, _ in _imports(m, modules) if not inner} for m in modules}
    grew = True
    while grew:
        grew = False
        for module in modules:
            if module not in kernels and tops[module] & kernels:
                kernels.add(module)
                grew = True
    return kernels


#: Function-level imports of poinsot modules that are not kernel modules, each with its
#: reason (issue 39: fewer than 40; every other import is at module level, where a
#: circle it closes shows). Optional third-party dependencies are not counted.
LAZY_ALLOWED = {
    ("poinsot.trajectory", "poinsot.plotting.notebook"): "Result.show(): the viewer on demand",
    ("poinsot.dynamics.particles", "poinsot.dynamics.earth"): "the old home of the Earth "
    "applications (names looked up on first use; earth imports particles)",
}


def _lazy(modules: dict[str, Path]) -> list[tuple[str, str, int]]:
    kernels = _loads_numba(modules)
    return [
        (m, t, line)
        for m in modules
        for t, inner, line in _imports(m, modules)
        if inner and t not in kernels and t != m
    ]


def _circles(modules: dict[str, Path]) -> list[list[str]]:
    """Every import (module level and inside functions, except :data:`LAZY_ALLOWED`) as an
    arrow; the strongly connected components with more than one module (Tarjan)."""
    edges = {
        m: {t for t, _, _ in _imports(m, modules) if t in modules and t != m}
        - {t for (a, t) in LAZY_ALLOWED if a == m}
        for m in modules
    }
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    circles = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in modules:
        if v not in index:
            visit(v)
    return circles


def test_function_level_imports_are_kernels_or_listed():
    kernels = _loads_numba(MODULES)
    assert {"poinsot.dynamics._euler_numba", "poinsot.dynamics._fused_run"} <= kernels
    assert not kernels & {"poinsot.dynamics.heavy", "poinsot._jit", "poinsot.dynamics"}
    lazy = _lazy(MODULES)
    unlisted = [f"{MODULES[m]}:{n}: {m} -> {t}" for m, t, n in lazy if (m, t) not in LAZY_ALLOWED]
    assert not unlisted, "import at module level (or list with a reason):\n" + "\n".join(unlisted)
    assert len(lazy) < 40


def test_the_house_has_no_import_circle():
    assert not _circles(MODULES)


def test_the_checks_see_a_circle_and_a_lazy_import(tmp_path):
    """The two checks above on a made-up package: they find what they should."""
    pkg = tmp_path / "poinsot"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "_jit.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "a.py").write_text("from . import b\n")
    (pkg / "sub" / "b.py").write_text("def f():\n    from . import a\n")
    (pkg / "sub" / "k.py").write_text("from .._jit import njit\n")
    (pkg / "sub" / "c.py").write_text("def f():\n    from . import k\n")
    rel = {".".join(p.relative_to(tmp_path).with_suffix("").parts).removesuffix(".__init__"): p
           for p in pkg.rglob("*.py")}  # fmt: skip
    assert [(m, t) for m, t, _ in _lazy(rel)] == [("poinsot.sub.b", "poinsot.sub.a")]
    assert _circles(rel) == [["poinsot.sub.a", "poinsot.sub.b"]]


#: The layers inside a package, lowest first (docs/conventions.md, "Layout"); a module
#: imports only modules of its own package listed before it (or in its own group).
INNER = {
    "poinsot.scenarios": [
        ("_toml",),
        ("facts",),
        ("schema",),
        ("readers", "figures", "describe"),
        ("kind",),
        ("summary",),
        ("solve", "report", "draw"),
        ("kinds",),
        ("registry",),
        ("io",),
        ("output",),
    ],
    "poinsot.verify": [
        ("_mujoco", "groups", "_pybullet", "_drake", "_basilisk"),
        ("cases",),
        ("metrics", "files"),
        ("engines",),
        ("suite", "scorecard"),
    ],
}


@pytest.mark.parametrize("package", sorted(INNER))
def test_imports_inside_a_package_flow_downward(package):
    rank = {name: k for k, names in enumerate(INNER[package]) for name in names}
    bad = []
    for module in MODULES:
        if not module.startswith(package + ".") or module == package:
            continue
        src = module[len(package) + 1 :].split(".")[0]
        for target, _, line in _imports(module, MODULES):
            if not target.startswith(package + ".") or target == package:
                continue
            dst = target[len(package) + 1 :].split(".")[0]
            if src == dst:
                continue
            assert src in rank and dst in rank, (module, target)
            if rank[dst] > rank[src]:
                bad.append(f"{MODULES[module]}:{line}: {module} imports {target} (above it)")
    assert not bad, "\n".join(bad)
