"""Imports flow one way (docs/conventions.md, "Layout"): every ``poinsot`` import in the
package, at module level or inside a function, goes from a module to one of the same
layer or a lower one. Read with ``ast`` from the source files (nothing imported)."""

from __future__ import annotations

import ast
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
        "_numba_cache",
        "_progress",
        "_scratch",
        "_files",
        "_drift",
        "_deprecate",
        "_display",
        "__version__",
        "integrators",
    ),
    ("rotations", "_quat", "_numba_helpers", "mass"),  # mass stands beside rotations
    ("kinematics", "trajectory"),
    ("dynamics",),
    ("symbolic", "plotting", "jax"),  # leaves: nothing below imports them
    ("scenarios", "verify"),  # verify: exact solutions + plotting, for engines
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
