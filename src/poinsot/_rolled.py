"""A formula's table loops as one call, for an executor that traces (private).

An executor that traces the formula source (``poinsot.jax``) would otherwise unroll
every ``for _ in range(upto(n, nmax)):`` to its static bound: Carlson's duplication
(24 steps), the AGM, the Landen tables, each step a copy in the traced program. The
copies, not the arithmetic, cost its compile time (XLA compiles each fused piece of a
straight-line program apart). :func:`rolled_code` rewrites such a loop, in the
executor's copy of the function only, as

.. code-block:: python

    def _body(i, _carry):
        a, b = _carry
        ...                      # the loop's body, as written
        return a, b
    a, b = _poinsot_loop_(range(...), _body, (a, b), _going)

where ``a, b`` are the names the body assigns that the function had before the loop
(the carried state), and ``_poinsot_loop_`` is the executor's loop
(:attr:`poinsot._jit.Executor.loop`: ``jax.lax.fori_loop`` on JAX). A table read by
the loop index (``ks[lv]``) becomes ``_poinsot_item_(ks, lv)``, the executor's read
at a traced index, and a table written at one (``ks[lv] = k``, ``ks`` a table of the
caller's) becomes ``ks = _poinsot_put_(ks, lv, k)``, carried by the loop and written
back into the caller's table after it. An ``if not going(cond): break`` that opens the body becomes
``_going(i, carry) -> cond`` (``None`` if there is none), which the executor may test
for the whole batch (JAX stops once no lane is still going; the lanes that converged
first run the remaining steps, which leave their values unchanged to rounding); one
elsewhere in the body is dropped (every step runs). A loop this cannot express (another ``break``, a
``return`` inside, a name first assigned in the body and read after it) is left as it
is, unrolled: the rewrite changes how many copies are traced, never what is computed.
Numba, NumPy and the interpreter run the source as written.
"""

from __future__ import annotations

import ast
import inspect
import sys
import textwrap
import types as _pytypes

__all__ = ["rolled_code", "LOOP", "ITEM", "PUT"]

#: the global names the rewritten code calls (set by :func:`poinsot._jit.rebind`)
LOOP = "_poinsot_loop_"
ITEM = "_poinsot_item_"
PUT = "_poinsot_put_"


def _names(nodes: list[ast.stmt], ctx: type[ast.expr_context]) -> set[str]:
    """The names ``nodes`` store (``ast.Store``) or read (``ast.Load``)."""
    return {
        n.id
        for st in nodes
        for n in ast.walk(st)
        if isinstance(n, ast.Name) and isinstance(n.ctx, ctx)
    }


def _stored(nodes: list[ast.stmt]) -> set[str]:
    return _names(nodes, ast.Store)


def _loaded(nodes: list[ast.stmt]) -> set[str]:
    return _names(nodes, ast.Load)


def _is_upto_range(it: ast.expr) -> bool:
    if not (isinstance(it, ast.Call) and isinstance(it.func, ast.Name) and it.func.id == "range"):
        return False
    return any(
        isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "upto"
        for a in it.args
        for n in ast.walk(a)
    )


def _is_going_break(st: ast.stmt) -> bool:
    """``if not going(...): break``"""
    return (
        isinstance(st, ast.If)
        and not st.orelse
        and len(st.body) == 1
        and isinstance(st.body[0], ast.Break)
        and isinstance(st.test, ast.UnaryOp)
        and isinstance(st.test.op, ast.Not)
        and isinstance(st.test.operand, ast.Call)
        and isinstance(st.test.operand.func, ast.Name)
        and st.test.operand.func.id == "going"
    )


def _escapes(body: list[ast.stmt]) -> bool:
    """A ``break``/``continue``/``return``/``yield`` of the loop itself."""
    for st in body:
        for n in ast.walk(st):
            if isinstance(n, (ast.Break, ast.Continue, ast.Return, ast.Yield, ast.YieldFrom)):
                return True
            if isinstance(n, (ast.FunctionDef, ast.Lambda, ast.While, ast.For)):
                return True  # nested scopes and loops: not rewritten
    return False


def _puts(body: list[ast.stmt], bound: set[str]) -> tuple[list[ast.stmt] | None, set[str]]:
    """``t[i] = v`` (``t`` bound before the loop) -> ``t = _poinsot_put_(t, i, v)``: the
    table is carried; ``(None, ...)`` if the body writes into anything else."""
    out: list[ast.stmt] = []
    tables: set[str] = set()
    for st in body:
        target = st.targets[0] if isinstance(st, ast.Assign) and len(st.targets) == 1 else None
        if (
            isinstance(st, ast.Assign)
            and isinstance(target, ast.Subscript)
            and isinstance(target.value, ast.Name)
            and target.value.id in bound
        ):
            t = target.value.id
            tables.add(t)
            put = ast.Call(
                ast.Name(PUT, ast.Load()), [ast.Name(t, ast.Load()), target.slice, st.value], []
            )
            out.append(ast.copy_location(ast.Assign([ast.Name(t, ast.Store())], put), st))
            continue
        for n in ast.walk(st):
            if isinstance(n, (ast.Subscript, ast.Attribute)) and isinstance(n.ctx, ast.Store):
                return None, tables
        out.append(st)
    return out, tables


class _Items(ast.NodeTransformer):
    """``t[i]`` (a load, ``i`` the loop index, ``t`` not assigned in the body) ->
    ``_poinsot_item_(t, i)``."""

    def __init__(self, index: str, assigned: set[str]) -> None:
        self.index, self.assigned = index, assigned

    def visit_Subscript(self, node: ast.Subscript) -> ast.AST:
        self.generic_visit(node)
        if (
            isinstance(node.ctx, ast.Load)
            and isinstance(node.slice, ast.Name)
            and node.slice.id == self.index
            and isinstance(node.value, ast.Name)
            and node.value.id not in self.assigned
        ):
            call = ast.Call(ast.Name(ITEM, ast.Load()), [node.value, node.slice], [])
            return ast.copy_location(call, node)
        return node


class _Rewrite:
    def __init__(self, fdef: ast.FunctionDef) -> None:
        self.params = {a.arg for a in fdef.args.args}
        self.count = 0

    def block(self, stmts: list[ast.stmt], before: set[str]) -> list[ast.stmt]:
        """``stmts`` with their table loops rewritten; ``before``: names bound so far."""
        out: list[ast.stmt] = []
        bound = set(before)
        for k, st in enumerate(stmts):
            if isinstance(st, ast.For):
                new = self.loop(st, bound, stmts[k + 1 :])
                if new is not None:
                    out += new
                    bound |= _stored([st])
                    continue
            elif isinstance(st, ast.If):
                st.body = self.block(st.body, bound)
                st.orelse = self.block(st.orelse, bound)
            out.append(st)
            bound |= _stored([st])
        return out

    def loop(self, st: ast.For, bound: set[str], after: list[ast.stmt]) -> list[ast.stmt] | None:
        if st.orelse or not isinstance(st.target, ast.Name) or not _is_upto_range(st.iter):
            return None
        # a convergence test first in the body: the loop may stop once every lane
        # has met it (the executor's choice); elsewhere it is dropped (all steps run)
        first = st.body[0] if st.body else None
        test = first.test.operand.args[0] if first and _is_going_break(first) else None  # type: ignore[attr-defined]
        body = [s for s in st.body if not _is_going_break(s)]
        if not body or _escapes(body):
            return None
        written, tables = _puts(body, bound)
        if written is None:
            return None
        body = written
        index = st.target.id
        assigned = _stored(body)
        carried = sorted((assigned & bound) - {index})
        temporaries = assigned - set(carried) - {index}
        if not carried or temporaries & _loaded(after) or index in _loaded(after):
            return None
        if test is not None and temporaries & {
            n.id for n in ast.walk(test) if isinstance(n, ast.Name)
        }:
            test = None  # it reads a value of the previous step's body: all steps run
        body = [_Items(index, assigned).visit(s) for s in body]
        self.count += 1
        name, carry = f"_poinsot_body_{self.count}", f"_poinsot_carry_{self.count}"

        def names(ctx: ast.expr_context) -> ast.Tuple:
            return ast.Tuple([ast.Name(c, ctx) for c in carried], ctx)

        def step_function(fname: str, tail: list[ast.stmt]) -> ast.stmt:
            """``def fname(index, carry): <carried names> = carry; <tail>``"""
            args = [ast.arg(index), ast.arg(carry)]
            fdef = ast.FunctionDef(
                name=fname,
                args=ast.arguments(
                    posonlyargs=[], args=args, kwonlyargs=[], kw_defaults=[], defaults=[]
                ),
                body=[ast.Assign([names(ast.Store())], ast.Name(carry, ast.Load()))] + tail,
                decorator_list=[],
                returns=None,
            )
            if sys.version_info >= (3, 12):  # a field of Python 3.12's AST
                fdef.type_params = []
            return ast.copy_location(fdef, st)

        out = [step_function(name, body + [ast.Return(names(ast.Load()))])]
        going: ast.expr = ast.Constant(None)
        if test is not None:
            tname = f"_poinsot_going_{self.count}"
            out.append(step_function(tname, [ast.Return(_Items(index, assigned).visit(test))]))
            going = ast.Name(tname, ast.Load())
        call = ast.Call(
            ast.Name(LOOP, ast.Load()),
            [st.iter, ast.Name(name, ast.Load()), names(ast.Load()), going],
            [],
        )
        # a table written by the loop is written back into the caller's table
        fresh = {t: f"_poinsot_{t}_{self.count}" for t in tables}
        targets = ast.Tuple([ast.Name(fresh.get(c, c), ast.Store()) for c in carried], ast.Store())
        out.append(ast.copy_location(ast.Assign([targets], call), st))
        for t, f in fresh.items():
            whole = ast.Subscript(ast.Name(t, ast.Load()), ast.Slice(), ast.Store())
            out.append(ast.copy_location(ast.Assign([whole], ast.Name(f, ast.Load())), st))
        return out


def rolled_code(fn: _pytypes.FunctionType) -> _pytypes.CodeType | None:
    """The code of ``fn`` with its table loops as calls of ``_poinsot_loop_`` (module
    notes), or ``None`` when it has none that can be so written."""
    try:
        src = textwrap.dedent(inspect.getsource(fn))
    except (OSError, TypeError):
        return None
    tree = ast.parse(src)
    fdef = tree.body[0]
    if not isinstance(fdef, ast.FunctionDef) or fn.__code__.co_freevars:
        return None
    fdef.decorator_list = []
    rw = _Rewrite(fdef)
    fdef.body = rw.block(fdef.body, set(rw.params))
    if not rw.count:
        return None
    ast.fix_missing_locations(tree)
    ast.increment_lineno(tree, fn.__code__.co_firstlineno - 1)
    module = compile(tree, fn.__code__.co_filename, "exec")
    for const in module.co_consts:
        if isinstance(const, _pytypes.CodeType) and const.co_name == fn.__name__:
            return const
    return None  # pragma: no cover - compile() always holds the function's code
