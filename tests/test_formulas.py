"""The rules for writing a formula (docs/conventions.md, "Writing a formula"), checked on
the source: every function the NumPy lanes executor or ``poinsot.jax`` runs re-bound
(``poinsot._jit.rebind``) must keep to what all executors can run.

The formulas are found from the code: the bodies of the ``guvectorize`` kernels (the
NumPy executor runs them as lanes), the functions handed to ``lanes``, and the functions
``poinsot.jax`` hands to ``rebind``/``selects``; then every poinsot function they call,
transitively, stopping at the declared primitives (``poinsot._jit.primitive``).
"""

from __future__ import annotations

import ast
import importlib
import inspect
import math
import os
import pathlib
import subprocess
import sys
import textwrap
import types
from collections.abc import Iterator
from typing import Any

import pytest

from poinsot import _jit

SRC = pathlib.Path(_jit.__file__).parent

#: the ``np.*`` a formula may call: names ``jax.numpy`` has with NumPy's meaning
#: (``np`` is ``jax.numpy`` on the JAX executor)
ALLOWED_NP = frozenset(
    {
        "abs",
        "asarray",
        "broadcast_to",
        "concatenate",
        "cos",
        "einsum",
        "eye",
        "frexp",
        "ldexp",
        "max",
        "multiply",
        "ones_like",
        "sin",
        "stack",
        "swapaxes",
        "where",
        "zeros",
        "zeros_like",
    }
)
#: what ``math.*`` may be: the names every executor's ``math`` has
ALLOWED_MATH = frozenset(_jit._MATH_NAMES) | {"pi", "e", "inf", "nan", "tau"}


class Formula:
    """One function checked: its AST, the globals its names resolve in, its name."""

    def __init__(self, key: str, node: ast.FunctionDef, glob: dict[str, Any], kernel: bool):
        self.key, self.node, self.glob, self.kernel = key, node, glob, kernel


def _function_node(fn: types.FunctionType) -> ast.FunctionDef:
    tree = ast.parse(textwrap.dedent(inspect.getsource(fn)))
    node = tree.body[0]
    assert isinstance(node, ast.FunctionDef), fn
    return node


def _is_module(v: Any) -> bool:
    return isinstance(v, types.ModuleType) and v.__name__.startswith("poinsot")


def _local_lists(node: ast.FunctionDef) -> set[str]:
    """Names bound to a Python list or dict in the function (item writes to them are fine)."""
    out = set()
    kinds = (ast.List, ast.ListComp, ast.Dict, ast.DictComp)
    for n in ast.walk(node):
        if isinstance(n, ast.Assign) and isinstance(n.value, kinds):
            out |= {t.id for t in n.targets if isinstance(t, ast.Name)}
        elif isinstance(n, ast.AnnAssign) and isinstance(n.value, kinds):
            out |= {n.target.id} if isinstance(n.target, ast.Name) else set()
    return out


def _is_going(t: ast.expr) -> bool:
    """``going(...)``, or ``going(...) and <more>`` (the rest static on JAX)."""
    if isinstance(t, ast.BoolOp) and isinstance(t.op, ast.And):
        t = t.values[0]
    return isinstance(t, ast.Call) and isinstance(t.func, ast.Name) and t.func.id == "going"


def _stores(target: ast.expr) -> Iterator[ast.Subscript]:
    if isinstance(target, ast.Subscript):
        yield target
    elif isinstance(target, (ast.Tuple, ast.List)):
        for t in target.elts:
            yield from _stores(t)


def _base(e: ast.expr) -> ast.expr:
    while isinstance(e, (ast.Subscript, ast.Attribute)):
        e = e.value
    return e


def violations(f: Formula) -> list[str]:
    """What ``f`` does that a formula may not (docs/conventions.md, "Writing a formula")."""
    out = []
    lists = _local_lists(f.node)
    params = {a.arg for a in f.node.args.args}
    for n in ast.walk(f.node):
        where = f"{f.key}, line {getattr(n, 'lineno', '?')}"
        if isinstance(n, (ast.Try, ast.TryStar)):
            out.append(f"{where}: try/except (a traced or split run cannot catch)")
        elif isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name):
            base, attr = n.value.id, n.attr
            if base == "math" and attr not in ALLOWED_MATH:
                out.append(f"{where}: math.{attr} is not in the executors' math")
        elif isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute):
            fn = n.func
            root = _base(fn)
            if isinstance(root, ast.Name) and root.id == "np":
                if not (isinstance(fn.value, ast.Name) and fn.attr in ALLOWED_NP):
                    out.append(f"{where}: {ast.unparse(fn)} (not in the allowed np names)")
            elif isinstance(fn.value, ast.Name):
                base, attr = fn.value.id, fn.attr
                if _is_module(f.glob.get(base)):
                    out.append(
                        f"{where}: {base}.{attr}(...): call formulas and primitives by a "
                        "bare name (rebind re-binds globals, not module attributes)"
                    )
        elif isinstance(n, (ast.Assign, ast.AugAssign)):
            targets = n.targets if isinstance(n, ast.Assign) else [n.target]
            for t in targets:
                for s in _stores(t):
                    b = _base(s)
                    name = b.id if isinstance(b, ast.Name) else "?"
                    if name in lists or f.key in _jit.INPLACE:
                        continue
                    if f.kernel and name in params:  # a kernel's output arrays
                        continue
                    out.append(f"{where}: writes into {name}[...] (arrays are immutable on JAX)")
        elif isinstance(n, ast.While):
            if not _is_going(n.test):
                out.append(f"{where}: while loop without going(...) (no static trip count)")
    return out


def _callees(f: Formula) -> Iterator[types.FunctionType]:
    """The poinsot functions ``f`` names (not the primitives: an executor may replace them)."""
    for n in ast.walk(f.node):
        if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load):
            v = f.glob.get(n.id)
            if v is None or _jit.primitive_name(v) is not None:
                continue
            if _jit._is_formula(v):
                yield _jit.source(v)


def _resolve(expr: ast.expr, glob: dict[str, Any], scope: ast.FunctionDef | None) -> Any:
    """A ``rebind``/``selects`` argument of poinsot.jax: ``name``, ``module.name``, or
    ``k.name`` with ``k = kernels()`` assigned in the enclosing function."""
    if isinstance(expr, ast.Name):
        return glob.get(expr.id)
    if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name):
        base = glob.get(expr.value.id)
        if base is None and scope is not None:
            for n in ast.walk(scope):
                if (
                    isinstance(n, ast.Assign)
                    and [ast.unparse(t) for t in n.targets] == [expr.value.id]
                    and isinstance(n.value, ast.Call)
                    and not n.value.args
                ):
                    base = _resolve(n.value.func, glob, None)()
        return getattr(base, expr.attr, None)
    return None


def _kernel_modules() -> list[types.ModuleType]:
    mods = []
    for path in sorted(SRC.rglob("*.py")):
        text = path.read_text()
        if "guvectorize" in text and "_jit import" in text:
            rel = path.relative_to(SRC.parent).with_suffix("")
            mods.append(importlib.import_module(".".join(rel.parts)))
    return mods


def _roots() -> list[Formula]:
    roots = []
    for mod in _kernel_modules():
        tree = ast.parse(inspect.getsource(mod))
        for node in tree.body:
            if isinstance(node, ast.FunctionDef) and any(
                isinstance(d, ast.Call) and getattr(d.func, "id", None) == "guvectorize"
                for d in node.decorator_list
            ):
                roots.append(Formula(f"{mod.__name__}.{node.name}", node, vars(mod), True))
        for node in ast.walk(tree):  # lanes(fn, ...)
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "lanes":
                fn = _resolve(node.args[0], vars(mod), None)
                roots.append(_formula(_jit.source(fn)))
    pj = pytest.importorskip("poinsot.jax")
    tree = ast.parse(inspect.getsource(pj))
    for scope in ast.walk(tree):
        if not isinstance(scope, (ast.FunctionDef, ast.Module)):
            continue
        for node in ast.walk(scope):
            call = isinstance(node, ast.Call) and getattr(node.func, "id", None)
            if call in ("rebind", "selects") and node.args:
                arg = node.args[0]
                if isinstance(arg, ast.Name) and arg.id == "fn":  # selects' own parameter
                    continue
                sc = scope if isinstance(scope, ast.FunctionDef) else None
                fn = _resolve(arg, vars(pj), sc)
                if fn is None and sc is None:  # a local of a function: seen in its scope
                    continue
                assert fn is not None, f"poinsot.jax: cannot resolve {ast.unparse(arg)}"
                roots.append(_formula(_jit.source(fn)))
    return roots


def _formula(fn: types.FunctionType) -> Formula:
    return Formula(f"{fn.__module__}.{fn.__qualname__}", _function_node(fn), fn.__globals__, False)


@pytest.fixture(scope="module")
def formulas() -> dict[str, Formula]:
    seen: dict[str, Formula] = {}
    todo = _roots()
    while todo:
        f = todo.pop()
        if f.key in seen:
            continue
        seen[f.key] = f
        todo.extend(_formula(c) for c in _callees(f))
    return seen


def test_the_formulas_are_found(formulas):
    # the scalar rotations, the elliptic functions, the free body, the kinematic rates
    for key in (
        "poinsot.rotations._scalar.from_matrix",
        "poinsot.dynamics._elliptic.carlson_rf",
        "poinsot.dynamics._free_body_numba.state_lanes",
        "poinsot.kinematics.rates._quat_rate",
        "poinsot.dynamics.integrators._common._rhs",
    ):
        assert key in formulas
    # a primitive is not a formula (its executor may replace it): not entered
    assert "poinsot._vec.cross" not in formulas
    assert "poinsot.rotations.quaternion.multiply" not in formulas


def test_every_formula_keeps_the_rules(formulas):
    bad = [v for f in formulas.values() for v in violations(f)]
    assert not bad, "\n".join(bad)


def test_the_allowed_numpy_names_are_jax_numpys():
    jnp = pytest.importorskip("jax.numpy")
    assert all(hasattr(jnp, name) for name in ALLOWED_NP)


BROKEN = """
def broken(x, out):
    try:
        y = math.erf(x)
    except ValueError:
        y = 0.0
    z = np.linalg.norm(x) + quaternion.multiply(x, x)
    out[0] = y
    while z > 1.0:
        z = z / 2.0
    return z
"""

FINE = """
def fine(x, n):
    rows = [x, x]
    rows[0] = pick(x > 0.0, x, -x)
    for _ in range(upto(n, 8)):
        if not going(x > 1.0):
            break
        x = math.sqrt(x)
    return np.stack(rows), cross(x, x)
"""


def _snippet(text: str, kernel: bool = False) -> Formula:
    from poinsot import _vec
    from poinsot.rotations import quaternion

    node = ast.parse(text).body[0]
    assert isinstance(node, ast.FunctionDef)
    glob = {"math": math, "np": None, "quaternion": quaternion, "cross": _vec.cross}
    return Formula(f"snippet.{node.name}", node, glob, kernel)


def test_a_broken_formula_fails_the_check():
    found = violations(_snippet(BROKEN))
    text = "\n".join(found)
    for what in (
        "try/except",
        "math.erf",
        "np.linalg",
        "quaternion.multiply",
        "writes into out",
        "while loop",
    ):
        assert what in text, (what, found)
    # a guvectorize kernel may write its output arrays (its parameters)
    assert "writes into out" not in "\n".join(violations(_snippet(BROKEN, kernel=True)))


def test_a_fine_formula_passes_the_check():
    assert violations(_snippet(FINE)) == []
    # the primitive it calls is no callee of the check
    assert list(_callees(_snippet(FINE))) == []


def test_only_poinsot_jax_turns_on_float64():
    # statically: no other module of poinsot names the flag
    users = [p for p in SRC.rglob("*.py") if "jax_enable_x64" in p.read_text()]
    assert [p.relative_to(SRC).as_posix() for p in users] == ["jax.py"]
    pytest.importorskip("jax")
    code = (
        "import jax, poinsot, poinsot.rotations, poinsot.dynamics, poinsot.kinematics\n"
        "before = jax.config.read('jax_enable_x64')\n"
        "import poinsot.jax\n"
        "print(before, jax.config.read('jax_enable_x64'))\n"
    )
    env = {**os.environ, "JAX_ENABLE_X64": "0", "JAX_PLATFORMS": "cpu"}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
    )
    assert out.stdout.split() == ["False", "True"]


def test_the_tracer_patch_is_undone_also_on_an_exception():
    jax = pytest.importorskip("jax")
    pj = pytest.importorskip("poinsot.jax")
    original = jax.core.Tracer.__bool__

    def fails(x):
        if x > 0.0:  # a data branch: explored under the patch
            raise ValueError("inside the traced run")
        return x

    with pytest.raises(ValueError, match="inside the traced run"):
        jax.jit(pj._merged(fails))(jax.numpy.array([1.0, -1.0]))
    assert jax.core.Tracer.__bool__ is original
    assert pj._Paths.active is None
    with pytest.raises(jax.errors.TracerBoolConversionError):  # a user's own branch
        jax.jit(lambda x: 1.0 if x > 0.0 else 0.0)(1.0)
