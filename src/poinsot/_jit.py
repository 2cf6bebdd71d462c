"""The executor of the formula source: numba when it is there, NumPy otherwise (private).

Every kernel module takes ``njit``, ``guvectorize``, ``prange`` and ``overload``
from here instead of from numba, so one source per formula runs two ways:

* **numba** (the default): the names are numba's own;
* **NumPy** (``POINSOT_NUMBA=0`` in the environment, or ``import numba`` fails,
  e.g. Pyodide or a Python release numba does not support yet): ``njit`` returns
  the plain Python function (same source, run by the interpreter), ``prange`` is
  ``range``, and ``guvectorize`` returns a *vectorised* executor (:func:`lanes`):
  the kernel body runs once on whole columns of the batch, not once per element.

**Branches as selects, by splitting.** The scalar formulas branch on their data
(``if f <= pi``, the largest square of a matrix...). :func:`lanes` runs a
function with NumPy arrays whose truth value is defined when every lane agrees;
when the lanes disagree, the call is re-run on the two subsets of lanes (each
then takes its own branch) and the results are merged. Every element therefore
runs exactly the operations of its scalar path: the accuracy near singular
points is that of the scalar formula, and the cost is a few vectorised passes
(one per distinct path taken in the batch). ``math`` (and ``max``/``min``) are
re-bound to NumPy in the globals of the executed functions (:func:`numpy_fn`),
so the formulas themselves are never written twice.

**The executors, in one table.** :data:`EXECUTORS` holds one :class:`Executor` per
way the formula source runs (``"numba"``, ``"numpy"``, and ``"jax"`` once
:mod:`poinsot.jax` is imported): the globals it replaces (``math``, ``np``,
``max``, ``min``), the implementations it gives to the declared
:func:`primitive` functions (matched by the function, never by the name a caller
imported it under), how it wraps the poinsot functions a formula calls, and how it
runs data branches and converging loops. What a formula may call: ``docs/conventions.md``,
"Writing a formula" (checked by ``tests/test_formulas.py``).
"""

from __future__ import annotations

import contextlib
import functools
import importlib.util
import math
import os
import re
import types as _pytypes
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import _rolled
from .errors import PoinsotWarning

__all__ = [
    "NUMBA",
    "njit",
    "guvectorize",
    "prange",
    "overload",
    "lanes",
    "numpy_fn",
    "rebind",
    "EXECUTORS",
    "Executor",
    "primitive",
    "PRIMITIVES",
    "NAMESPACES",
    "WRAP",
    "INPLACE",
    "going",
    "upto",
    "pick",
    "compiling",
    "compile_seconds",
    "mute_compile_notice",
    "first_call",
    "ready",
    "interpret_first",
    "interpreted_seconds",
    "is_warm",
    "mark_warm",
    "build_in_background",
    "numpy_twin",
]


def _numba_wanted() -> bool:
    if os.environ.get("POINSOT_NUMBA", "1").strip().lower() in ("0", "false", "no", "off"):
        return False
    # found, not imported: importing numba takes ~0.3 s, paid by the first kernel module
    # (:func:`_load`), not by every module that asks which executor runs
    try:
        return importlib.util.find_spec("numba") is not None
    except (ImportError, ValueError):  # a finder that refuses it, a broken install
        return False


#: Whether the kernels are compiled by numba (else run by the NumPy executor).
NUMBA: bool = _numba_wanted()


# ------------------------------------------------------------------ NumPy executor
class _Split(Exception):
    """Raised when the lanes of a condition disagree (carries the boolean mask)."""

    def __init__(self, mask: np.ndarray) -> None:
        self.mask = mask


class _Lanes(np.ndarray):
    """A column of a batch whose truth value is that of all its lanes when they agree."""

    def __bool__(self) -> bool:
        m = np.asarray(self, dtype=bool)
        if m.all():
            return True
        if not m.any():
            return False
        raise _Split(m)


def _vmax(*args: Any) -> Any:
    if len(args) == 1:
        args = tuple(args[0])
    return functools.reduce(np.maximum, args)


def _vmin(*args: Any) -> Any:
    if len(args) == 1:
        args = tuple(args[0])
    return functools.reduce(np.minimum, args)


#: ``math``'s names -> the element-wise functions of an array library (NumPy's and
#: ``jax.numpy``'s names agree)
_MATH_NAMES = {
    "sqrt": "sqrt",
    "sin": "sin",
    "cos": "cos",
    "tan": "tan",
    "atan": "arctan",
    "atan2": "arctan2",
    "asin": "arcsin",
    "acos": "arccos",
    "exp": "exp",
    "log": "log",
    "log1p": "log1p",
    "expm1": "expm1",
    "sinh": "sinh",
    "cosh": "cosh",
    "tanh": "tanh",
    "asinh": "arcsinh",
    "atanh": "arctanh",
    "fabs": "abs",
    "hypot": "hypot",
    "copysign": "copysign",
    "floor": "floor",
    "isfinite": "isfinite",
    "isnan": "isnan",
}


def math_namespace(lib: Any) -> Any:
    """``math`` for the arrays of ``lib`` (``numpy``, ``jax.numpy``): the same names."""
    consts = {k: getattr(math, k) for k in ("pi", "e", "inf", "nan", "tau")}
    funcs = {k: getattr(lib, v) for k, v in _MATH_NAMES.items() if hasattr(lib, v)}
    return _pytypes.SimpleNamespace(**consts, **funcs)


_NPMATH = math_namespace(np)

# ------------------------------------------------------------ the executors
#: qualified name (``module.qualname``) -> function, for every function declared a
#: :func:`primitive`
PRIMITIVES: dict[str, Callable[..., Any]] = {}


def primitive_name(fn: Any) -> str | None:
    """The key of ``fn`` in :data:`PRIMITIVES` (of its Python source: a numba dispatcher
    or a NumPy-executor wrapper counts as its function), or ``None`` if it is none."""
    f = source(fn)
    if not isinstance(f, _pytypes.FunctionType):
        return None
    key = f"{f.__module__}.{f.__qualname__}"
    return key if PRIMITIVES.get(key) is f else None


def primitive(fn: Callable[..., Any]) -> Callable[..., Any]:
    """Declare ``fn`` a primitive: an executor may replace the whole function by its own
    implementation (:attr:`Executor.primitives`, keyed by ``module.qualname``) instead of
    running its body, e.g. ``poinsot.jax`` runs ``jnp.cross`` for :func:`poinsot._vec.cross`
    (whose body writes into an array). Returns ``fn`` itself; an executor without an
    implementation runs ``fn`` as a formula."""
    PRIMITIVES[f"{fn.__module__}.{fn.__qualname__}"] = fn
    return fn


@dataclass
class Executor:
    """One way the formula source runs (an entry of :data:`EXECUTORS`)."""

    #: the key in :data:`EXECUTORS`
    name: str
    #: globals replaced in the formulas it re-binds (:func:`rebind`): ``math``, ``max``,
    #: ``min`` (and ``np`` for a library other than NumPy); empty for numba, which
    #: compiles the source as it is
    namespace: dict[str, Any]
    #: ``module.qualname`` of a :func:`primitive` -> the function run in its place
    primitives: dict[str, Callable[..., Any]] = field(default_factory=dict)
    #: how a re-bound formula's poinsot callees are wrapped (``None``: re-bound as they
    #: are, running inside their caller); the functions of :data:`INPLACE` never are
    wrap: Callable[[Callable[..., Any]], Callable[..., Any]] | None = None
    #: what ``if cond:`` on data becomes
    branches: str = ""
    #: what ``while going(cond)``, ``range(upto(n, nmax))`` and ``pick`` become
    loops: str = ""
    #: whether the poinsot modules a formula reaches as names (``nh.fma``) are re-bound
    #: too (the plain-Python executor: a compiled module's functions are dispatchers)
    modules: bool = False
    #: ``loop(range, body, carry)``: a ``for i in range(upto(n, nmax))`` loop of a
    #: formula as one call (its body a function ``body(i, carry) -> carry`` of the
    #: carried names; :mod:`poinsot._rolled` rewrites the executor's copy of the
    #: source), for an executor that traces; ``None``: the loop runs as written
    loop: Callable[..., Any] | None = None
    #: ``item(table, i)``: a table read at the loop index inside such a loop
    item: Callable[[Any, Any], Any] | None = None
    #: ``put(table, i, v)``: the table with entry ``i`` set to ``v`` (a write in such a loop)
    put: Callable[[Any, Any, Any], Any] | None = None


#: name -> executor: every way the one formula source runs (``"jax"`` is added by
#: importing :mod:`poinsot.jax`)
EXECUTORS: dict[str, Executor] = {
    "numba": Executor(
        "numba",
        {},
        branches="compiled branches: each element takes its own",
        loops="compiled loops: going(cond) is cond, upto(n, nmax) is n, pick a branch",
    ),
    "numpy": Executor(
        "numpy",
        {"math": _NPMATH, "max": _vmax, "min": _vmin},
        branches="lanes split where they disagree, each subset re-run, results merged (lanes)",
        loops="as numba (going(cond) is cond: all lanes must agree, else they split)",
    ),
    # the compiled kernels' own source run by the interpreter on scalars: the first call
    # of a kernel that is neither compiled nor in numba's cache (:func:`first_call`)
    "python": Executor(
        "python",
        {},
        branches="Python's own, element by element (as compiled)",
        loops="Python's own (going(cond) is cond, upto(n, nmax) is n)",
        modules=True,
    ),
}


class _View(Mapping[str, Any]):
    """A read-only view of one field of :data:`EXECUTORS` (the executors that set it)."""

    def __init__(self, attr: str) -> None:
        self._attr = attr

    def __getitem__(self, name: str) -> Any:
        value = getattr(EXECUTORS[name], self._attr)
        if value is None:
            raise KeyError(name)
        return value

    def __iter__(self) -> Iterator[str]:
        return (k for k, e in EXECUTORS.items() if getattr(e, self._attr) is not None)

    def __len__(self) -> int:
        return sum(1 for _ in self)


#: name -> the globals replaced for each executor (:attr:`Executor.namespace`; a view)
NAMESPACES: Mapping[str, dict[str, Any]] = _View("namespace")
#: name -> how that executor wraps a formula's poinsot callees (:attr:`Executor.wrap`;
#: a view: ``poinsot.jax`` wraps them as selects, so each one's branches are merged
#: where it returns instead of multiplying the paths of its caller)
WRAP: Mapping[str, Callable[[Callable[..., Any]], Callable[..., Any]]] = _View("wrap")
#: Functions that write into their array arguments (tables): never wrapped (a wrapper
#: would hand them copies), they run inside their caller's paths.
INPLACE = {"poinsot.dynamics._elliptic.landen_fill"}

_REBOUND: dict[tuple[Any, str], Any] = {}
_GLOBALS: dict[tuple[int, str], dict[str, Any]] = {}


def _globals_for(g: dict[str, Any], ns: str) -> dict[str, Any]:
    new = _GLOBALS.get((id(g), ns))
    if new is None:
        ex = EXECUTORS[ns]
        new = dict(g)
        _GLOBALS[(id(g), ns)] = new  # before filling: functions of one module call each other
        new.update(ex.namespace)
        if ex.loop is not None:
            new[_rolled.LOOP], new[_rolled.ITEM], new[_rolled.PUT] = ex.loop, ex.item, ex.put
        for k, v in g.items():
            if k in ex.namespace:
                continue
            prim = primitive_name(v)
            if prim is not None and prim in ex.primitives:  # the executor's own
                new[k] = ex.primitives[prim]
            elif ex.modules and isinstance(v, _pytypes.ModuleType) and _is_poinsot(v):
                new[k] = _ModuleView(v, ns)
            elif ex.modules and id(v) in TWINS:
                new[k] = TWINS[id(v)]
            elif _is_formula(v):
                f = source(v)
                if ex.wrap is None or f"{f.__module__}.{f.__name__}" in INPLACE:
                    new[k] = rebind(v, ns)
                else:
                    new[k] = ex.wrap(v)
    return new


def _is_poinsot(module: _pytypes.ModuleType) -> bool:
    return module.__name__ == "poinsot" or module.__name__.startswith("poinsot.")


#: id of a numba-only object (an ``@intrinsic``) -> the plain function the interpreter
#: runs in its place (:func:`twin`)
TWINS: dict[int, Callable[..., Any]] = {}


def twin(compiled: Any, plain: Callable[..., Any]) -> None:
    """Declare ``plain`` the Python form of ``compiled``, a numba-only object (an
    ``@intrinsic`` has no Python body): the plain-Python executor calls it instead."""
    TWINS[id(compiled)] = plain


class _ModuleView:
    """A poinsot module as a formula re-bound for executor ``ns`` sees it: its functions
    re-bound (:func:`rebind`), everything else as it is."""

    def __init__(self, module: _pytypes.ModuleType, ns: str) -> None:
        self._module, self._ns = module, ns

    def __getattr__(self, name: str) -> Any:
        v = getattr(self._module, name)
        out = TWINS.get(id(v)) or (rebind(v, self._ns) if _is_formula(v) else v)
        setattr(self, name, out)  # looked up once
        return out


def source(fn: Any) -> Any:
    """The plain Python function of ``fn``: a numba dispatcher's ``py_func``, or the
    function a :func:`njit` of the NumPy executor wrapped (else ``fn`` itself)."""
    f = getattr(fn, "py_func", None)
    if isinstance(f, _pytypes.FunctionType):
        return f
    f = getattr(fn, "__wrapped__", None)
    if isinstance(f, _pytypes.FunctionType) and getattr(fn, "_poinsot_quiet", False):
        return f
    return fn


def _is_formula(v: Any) -> bool:
    """A poinsot function (plain, or compiled by :func:`njit`) whose globals are re-bound."""
    v = source(v)
    return isinstance(v, _pytypes.FunctionType) and v.__module__.startswith("poinsot")


def named_copy(fn: Callable[..., Any], name: str) -> Callable[..., Any]:
    """``fn``'s code as a function called ``name``: to compile one source twice with other
    options (numba's cache files go by the function's name, so the same name would share
    the other compilation's entries)."""
    out = _pytypes.FunctionType(fn.__code__, fn.__globals__, name, fn.__defaults__)
    out.__qualname__ = name
    out.__doc__ = fn.__doc__
    return out


def rebind(fn: Callable[..., Any], ns: str) -> Callable[..., Any]:
    """``fn`` re-bound to globals where ``math``, ``max``, ``min`` (and ``np``) are those
    of the executor ``ns`` (a key of :data:`EXECUTORS`), the :func:`primitive` functions
    it calls are the executor's implementations and the other poinsot functions it calls
    are re-bound too (or wrapped: :attr:`Executor.wrap`): the same code, run on that
    library's arrays. ``fn`` may be compiled by :func:`njit` (its Python source is
    re-bound)."""
    fn = source(fn)
    out = _REBOUND.get((fn, ns))
    if out is None:
        f: Any = fn
        g = _globals_for(f.__globals__, ns)  # may re-bind fn itself (its module's functions)
        out = _REBOUND.get((fn, ns))
        if out is None:
            code = f.__code__
            if EXECUTORS[ns].loop is not None:
                code = _rolled.rolled_code(f) or code
            out = _pytypes.FunctionType(code, g, f.__name__, f.__defaults__, f.__closure__)
            _REBOUND[(fn, ns)] = out
    return out


def numpy_fn(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` re-bound for NumPy columns (:func:`rebind` with ``"numpy"``)."""
    return rebind(fn, "numpy")


def _take(a: Any, idx: np.ndarray) -> Any:
    return a[..., idx] if isinstance(a, np.ndarray) and a.ndim else a


def lanes(fn: Callable[..., Any], n: int, *args: Any, rebind: bool = True) -> Any:
    """Run ``fn`` (re-bound by :func:`numpy_fn`) once on ``n`` lanes: array arguments
    have the lanes on their last axis. Returns what ``fn`` returns (arrays with the
    lanes last). Lanes whose conditions disagree are split (module notes).

    >>> from poinsot.rotations import _scalar as S
    >>> w, x, y, z = lanes(S.canonical, 2, np.array([-1.0, 0.5]), 0.0, 0.0, 0.0)
    >>> w.tolist()  # each lane took its own branch of ``if w < 0``
    [1.0, 0.5]
    """
    # the caller's np.errstate applies, as to a numba gufunc: a lane computes only
    # its own branch, so there are no warnings from untaken branches to silence
    return _run(numpy_fn(fn) if rebind else fn, n, args)


def _run(g: Callable[..., Any], n: int, args: tuple[Any, ...]) -> Any:
    wrapped = tuple(a.view(_Lanes) if isinstance(a, np.ndarray) else a for a in args)
    try:
        out = g(*wrapped)
    except _Split as s:
        mask = s.mask
        if mask.shape != (n,):
            raise
        yes, no = np.flatnonzero(mask), np.flatnonzero(~mask)
        a = _run(g, yes.size, tuple(_take(x, yes) for x in args))
        b = _run(g, no.size, tuple(_take(x, no) for x in args))
        return _merge(a, b, yes, no, n)
    return _plain(out, n)


def _plain(out: Any, n: int) -> Any:
    if isinstance(out, tuple):
        return tuple(_plain(o, n) for o in out)
    if isinstance(out, np.ndarray):
        return np.asarray(out)
    return out


def _merge(a: Any, b: Any, yes: np.ndarray, no: np.ndarray, n: int) -> Any:
    if isinstance(a, tuple):
        return tuple(_merge(x, y, yes, no, n) for x, y in zip(a, b, strict=True))
    if a is None:
        return None
    a, b = np.asarray(a), np.asarray(b)
    shape = np.broadcast_shapes(a.shape[:-1] if a.ndim else (), b.shape[:-1] if b.ndim else ())
    out = np.empty(shape + (n,), dtype=np.result_type(a, b))
    out[..., yes] = a if a.ndim else a
    out[..., no] = b if b.ndim else b
    return out


_DIMS = re.compile(r"\(([^)]*)\)")


def _gufunc(body: Callable[..., Any], layout: str) -> Callable[..., Any]:
    """A NumPy executor for a ``guvectorize`` kernel ``body`` with ``layout``: inputs
    broadcast over their loop dimensions like a ufunc's; the body runs once (per
    split) with the core dimensions first and the batch last."""
    ins_s, outs_s = layout.replace(" ", "").split("->")
    ins = [tuple(d for d in m.split(",") if d) for m in _DIMS.findall(ins_s)]
    outs = [tuple(d for d in m.split(",") if d) for m in _DIMS.findall(outs_s)]

    def call(*args: Any) -> Any:
        arrs = [np.asarray(a) for a in args]
        sizes: dict[str, int] = {}
        loops = []
        for a, core in zip(arrs, ins, strict=True):
            for d, s in zip(core, a.shape[a.ndim - len(core) :], strict=True):
                sizes[d] = s
            loops.append(a.shape[: a.ndim - len(core)])
        batch = np.broadcast_shapes(*loops)
        n = int(np.prod(batch, dtype=np.int64))
        cols = []
        for a, core in zip(arrs, ins, strict=True):
            full = np.broadcast_to(a, batch + a.shape[a.ndim - len(core) :])
            flat = full.reshape((n,) + full.shape[len(batch) :])
            cols.append(np.moveaxis(flat, 0, -1))  # core dims first, lanes last

        shapes = [tuple(sizes[d] for d in core) or (1,) for core in outs]  # () -> one slot

        fn = numpy_fn(body)  # on first call: the module's globals are complete by then

        def kernel(*cs: Any) -> tuple[np.ndarray, ...]:
            res = [np.empty(s + (cs[0].shape[-1],)) for s in shapes]
            fn(*cs, *res)
            return tuple(res)

        if n == 0:
            results: Any = tuple(np.empty(s + (0,)) for s in shapes)
        else:
            results = lanes(kernel, n, *cols, rebind=False)
        final = []
        for r, core in zip(results, outs, strict=True):
            r = np.moveaxis(np.asarray(r), -1, 0)
            if not core:
                r = r[:, 0]
            final.append(r.reshape(batch + r.shape[1:]))
        return final[0] if len(final) == 1 else tuple(final)

    call.__wrapped__ = body  # type: ignore[attr-defined]
    return call


def _quiet(fn: Callable[..., Any]) -> Callable[..., Any]:
    # compiled code raises no floating-point warnings (an overflow gives inf, as the
    # callers expect): the plain function runs under the same rule
    @functools.wraps(fn)
    def run(*args: Any, **kwargs: Any) -> Any:
        with np.errstate(all="ignore"):
            return fn(*args, **kwargs)

    run._poinsot_quiet = True  # type: ignore[attr-defined]  # source() unwraps it
    return run


def _np_njit(*args: Any, **kwargs: Any) -> Any:
    """``njit`` of the NumPy executor: the plain function (inlined helpers as they are,
    kernels without floating-point warnings)."""
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return _quiet(args[0])
    if kwargs.get("inline") == "always":
        return lambda fn: fn
    return _quiet


def _np_guvectorize(sigs: Any, layout: str, **kwargs: Any) -> Callable[..., Any]:
    return lambda body: _gufunc(body, layout)


def _np_overload(fn: Any, **kwargs: Any) -> Callable[..., Any]:
    return lambda impl: impl


# ------------------------------------------------------- bounded loops for tracing
@primitive
def _going(cond: bool) -> bool:
    """The exit test of an iteration: ``cond`` itself here (numba, NumPy, plain Python)."""
    return cond


@primitive
def _upto(n: int, nmax: int) -> int:
    """The trip count of a loop over a table: ``n`` here (``nmax`` on JAX)."""
    return n


@primitive
def _pick(cond: bool, a: Any, b: Any) -> Any:
    """``a if cond else b`` for two cheap values that are both defined (no branch on JAX)."""
    return a if cond else b


# Any: the two executors' decorators have nothing in common but how they are called.
# Bound by :func:`_load` on first access (module ``__getattr__``): only the kernel
# modules ask for them, so ``import poinsot.dynamics`` does not import numba.
njit: Any
guvectorize: Any
prange: Any
overload: Any
#: ``while going(cond)``/``if not going(cond): break``: a converging iteration's test.
#: Compiled and plain runs see ``cond``; a tracing library (``poinsot.jax``) re-binds
#: ``going`` to "keep going" (always true), so a loop written ``for _ in range(N)`` with
#: this exit test runs all ``N`` steps there: the loops that use it are written so that
#: steps after convergence change nothing (beyond rounding).
going: Any
#: ``range(upto(n, nmax))``: ``n`` steps here, ``nmax`` on JAX (a static trip count;
#: the table entries beyond ``n`` make the extra steps identities).
upto: Any
#: ``pick(cond, a, b)``: ``a if cond else b`` where both are cheap and finite; a
#: tracing library re-binds it to its select (``jnp.where``), which is not a branch
#: (a branch doubles the paths a select executor traces).
pick: Any
_EXECUTOR_NAMES = ("njit", "guvectorize", "prange", "overload", "going", "upto", "pick")


def _load() -> None:
    """Bind the executor's names: numba's (importing numba, installing the compile
    watch) or the NumPy executor's. A numba that is installed but fails to import
    (e.g. built for another NumPy) falls back to NumPy with a warning."""
    global NUMBA
    g = globals()
    if NUMBA:
        try:
            import numba as _numba
            from numba import extending as _extending
        except ImportError as exc:
            import warnings

            NUMBA = False
            warnings.warn(
                f"numba is installed but does not import ({exc}); poinsot runs its kernels "
                "on the NumPy executor (slower; docs/performance.md)",
                PoinsotWarning,
                stacklevel=3,
            )
    if NUMBA:
        g.update(njit=_numba.njit, guvectorize=_numba.guvectorize, prange=_numba.prange)
        g["overload"] = _extending.overload
        for name, fn in (("going", _going), ("upto", _upto), ("pick", _pick)):
            g[name] = _numba.njit(inline="always")(fn)
        _install_compile_watch()
        install_safe_saves()
    else:
        g.update(njit=_np_njit, guvectorize=_np_guvectorize, prange=range, overload=_np_overload)
        g.update(going=_going, upto=_upto, pick=_pick)


def __getattr__(name: str) -> Any:
    if name in _EXECUTOR_NAMES:
        _load()
        return globals()[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# --------------------------------------------------------------- first calls
#: The interpreter answers a call whose kernel is neither compiled in this process nor
#: in numba's cache when its estimated time stays under this (s): compiling a kernel
#: takes 10-60 s, running a small problem in Python a fraction of a second.
INTERPRET_MAX_S = 2.0
#: ... and while the time this process has spent interpreting that kernel stays under
#: this (s): the rent-or-buy rule (after that much interpreting, compiling pays).
INTERPRET_TOTAL_S = 20.0
#: kernel name -> seconds this process spent interpreting it
_INTERPRETED: dict[str, float] = {}


def interpret_first() -> bool:
    """Whether first calls may be interpreted: numba in use and ``POINSOT_INTERPRET_FIRST``
    not ``0`` (docs/performance.md, "Cold start")."""
    flag = os.environ.get("POINSOT_INTERPRET_FIRST", "1").strip().lower()
    return NUMBA and flag not in ("0", "false", "no", "off")


def ready(fn: Any, match: Callable[[tuple[Any, ...]], bool] | None = None) -> bool:
    """Whether calling the compiled kernel ``fn`` now compiles nothing: it is compiled in
    this process, or numba's cache holds a fresh compilation of it (its index matches
    the source); with ``match``, a compilation whose argument types pass ``match`` (a
    kernel compiled per constant argument: :class:`poinsot.dynamics._fused_lanes.Kind`).
    True for anything that is not a numba dispatcher."""
    if match is None:
        match = _any_signature
    overloads = getattr(fn, "overloads", None)
    if overloads and any(match(tuple(sig)) for sig in overloads):
        return True
    cache = getattr(fn, "_cache", None)
    if cache is None or not hasattr(fn, "py_func"):
        return True
    try:  # the index's keys: (argument types, the codegen's magic, the source's hashes)
        return any(match(tuple(key[0])) for key in cache._cache_file._load_index())
    except Exception:  # an unreadable index: numba recompiles, so it is not ready
        return False


def _any_signature(sig: tuple[Any, ...]) -> bool:
    return True


def first_call(
    fn: Any, seconds: float, match: Callable[[tuple[Any, ...]], bool] | None = None
) -> Any:
    """The kernel to call: ``fn`` itself when that compiles nothing (:func:`ready`), or
    when interpreting is off or would take long; else ``fn``'s own source run by the
    interpreter (the ``"python"`` executor: the same operations, results equal to the
    compiled ones up to the rounding of fused multiply-adds), when the estimated
    ``seconds`` of the interpreted call stay under :data:`INTERPRET_MAX_S` and this
    process's interpreting of ``fn`` under :data:`INTERPRET_TOTAL_S`. ``match``: as
    :func:`ready`'s."""
    if not interpret_first() or ready(fn, match):
        return fn
    key = f"{source(fn).__module__}.{source(fn).__qualname__}"
    if seconds > INTERPRET_MAX_S or _INTERPRETED.get(key, 0.0) + seconds > INTERPRET_TOTAL_S:
        return fn
    plain = rebind(fn, "python")
    build_in_background()

    def interpreted(*args: Any) -> Any:
        import time

        t0 = time.perf_counter()
        try:
            return plain(*args)
        finally:
            _INTERPRETED[key] = _INTERPRETED.get(key, 0.0) + time.perf_counter() - t0

    interpreted.interpreted = True  # type: ignore[attr-defined]
    return interpreted


# ------------------------------------------------- the cache, warm or cold, and its build
def _marker() -> Any:
    """The file that says this install's kernels are all in numba's cache: in
    ``NUMBA_CACHE_DIR`` (else the package's ``__pycache__``), named by what a cached
    kernel depends on (poinsot's sources, numba's version, the CPU numba targets)."""
    import hashlib
    from pathlib import Path

    import numba
    from llvmlite import binding as llvm

    root = Path(__file__).parent
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        st = f.stat()
        h.update(f"{f.relative_to(root)}:{st.st_size}:{st.st_mtime_ns}".encode())
    cpu = os.environ.get("NUMBA_CPU_NAME") or llvm.get_host_cpu_name()
    h.update(f"{numba.__version__}:{cpu}".encode())
    folder = Path(os.environ.get("NUMBA_CACHE_DIR") or root / "__pycache__")
    return folder / f"poinsot-warm-{h.hexdigest()[:16]}"


def is_warm() -> bool:
    """Whether ``poinsot warmup`` has filled numba's cache for this install (its marker
    is there): a kernel's first call then loads it instead of compiling."""
    try:
        return bool(_marker().exists())
    except OSError:
        return False


def mark_warm() -> None:
    """Write the marker of :func:`is_warm` (``poinsot warmup`` does, once it compiled all)."""
    m = _marker()
    m.parent.mkdir(parents=True, exist_ok=True)
    m.write_text("numba's cache holds every poinsot kernel for this install\n")


@contextlib.contextmanager
def compile_lock(name: str) -> Iterator[None]:
    """Hold an inter-process lock named ``name`` (a file lock next to numba's cache).

    numba caches a gufunc as two files, the kernel and the wrapper that calls it by a
    symbol name numbered in the order of the process's compilations. Two processes
    that compile one gufunc module at once (pytest-xdist workers on a cold cache; a
    program and its background ``poinsot warmup``) can leave the kernel of one and
    the wrapper of the other, and the next process to load them segfaults. Importing
    such a module under this lock makes the second process wait and then load both
    files of the first. Without ``fcntl`` (Windows) or a writable folder, no lock."""
    import hashlib
    import tempfile
    from pathlib import Path

    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    here = Path(__file__).parent
    folders = [Path(os.environ.get("NUMBA_CACHE_DIR") or here / "__pycache__")]
    tag = hashlib.sha256(str(here).encode()).hexdigest()[:12]
    folders.append(Path(tempfile.gettempdir()) / f"poinsot-locks-{tag}")
    for folder in folders:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            fh = open(folder / f"poinsot-compile-{name}.lock", "a+")  # noqa: SIM115
            break
        except OSError:
            continue
    else:  # pragma: no cover - no writable folder at all
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


_BUILDING: dict[str, Any] = {}


def build_in_background() -> None:
    """Start ``poinsot warmup --background`` once per process (unless the cache is warm,
    or ``POINSOT_BACKGROUND_BUILD=0``): a detached, low-priority process that compiles
    every kernel into numba's cache while this one answers on the interpreter, so that
    the next process starts warm. A lock file keeps to one such build per cache."""
    import subprocess
    import sys

    if _BUILDING or os.environ.get("POINSOT_BACKGROUND_BUILD", "1").strip() in ("0", "no"):
        return
    _BUILDING["started"] = True
    try:
        if is_warm():
            return
        env = dict(os.environ, POINSOT_INTERPRET_FIRST="0", POINSOT_COMPILE_NOTICE="0")
        _BUILDING["process"] = subprocess.Popen(
            [sys.executable, "-m", "poinsot.cli", "warmup", "--background", "--quiet"],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,  # not stopped by this terminal's Ctrl-C
        )
    except OSError:  # no process to spare: the next call compiles in the foreground
        pass


def numpy_twin(name: str) -> Any:
    """The kernel module ``name`` executed again with the NumPy executor's ``njit``,
    ``guvectorize``, ``prange``, ``overload`` (as under ``POINSOT_NUMBA=0``): its kernels
    run at once, compiling nothing (a cold cache's first calls)."""
    import importlib
    import importlib.util
    import sys

    # the helpers it imports are loaded first, as they are (compiled): only the twin's
    # own decorators are the NumPy executor's
    for helper in ("poinsot._numba_helpers", "poinsot._numba_cache"):
        importlib.import_module(helper)
    spec = importlib.util.find_spec(name)
    assert spec is not None and spec.origin is not None
    twin = importlib.util.spec_from_file_location(name + "_interpreted", spec.origin)
    assert twin is not None and twin.loader is not None
    mod = importlib.util.module_from_spec(twin)
    mod.__package__ = name.rpartition(".")[0]
    g = globals()
    names = ("NUMBA", "njit", "guvectorize", "prange", "overload", "going", "upto", "pick")
    saved = {k: g[k] for k in names if k in g}
    g.update(NUMBA=False, njit=_np_njit, guvectorize=_np_guvectorize, prange=range)
    g.update(overload=_np_overload, going=_going, upto=_upto, pick=_pick)
    try:
        sys.modules[twin.name] = mod
        twin.loader.exec_module(mod)
    finally:
        for k in names:
            g.pop(k, None)
        g.update(saved)
    return mod


def interpreted_seconds() -> float:
    """Seconds this process has spent interpreting first calls (:func:`first_call`)."""
    return sum(_INTERPRETED.values())


# ------------------------------------------------------------ compilation watch
#: thread ident -> how many numba compilations are running in that thread now (nested:
#: a kernel compiles the functions it calls). :func:`compiling` reads it: a caller that
#: waits for a worker thread on Ctrl-C does not wait for a compilation to end.
_COMPILING: dict[int, int] = {}
#: the one-line notice printed when a poinsot kernel starts compiling: muted while a
#: caller says it itself (the CLI's "compiling (first run only)"), or by
#: ``POINSOT_COMPILE_NOTICE=0``; at most one line a minute.
_NOTICE: dict[str, float] = {"muted": 0, "last": -math.inf}
_NOTICE_EVERY_S = 60.0


#: Seconds a cold compile of poinsot's larger kernels took (``poinsot warmup`` into an
#: empty cache, one process, 2-core Intel Xeon, numba 0.68; docs/performance.md, "Cold
#: start"): the estimate the compile notices quote (:func:`compile_estimate`). The SIMD
#: lane kernel compiles per torque kind: 23 s for the first, 8-9 s for each other
#: (:data:`COMPILE_LANE_KIND_S`).
COMPILE_S = {
    "poinsot.dynamics._fused_lanes.integrate_batch": 23.0,
    "poinsot.rotations._wahba_kernels.solve_serial": 12.0,
    "poinsot.rotations._wahba_kernels.solve_flat": 10.0,
    "poinsot.dynamics._fused.integrate_batch": 9.0,
    "poinsot.dynamics._fused.integrate_serial": 7.0,
    "poinsot.dynamics._free_body_numba.setup": 7.0,
    "poinsot.dynamics._fused.midpoint_batch": 5.0,
    "poinsot.rotations._kernels.from_matrix_flat": 3.0,
    "poinsot.dynamics._free_body_numba.evaluate": 2.6,
    "poinsot.dynamics._fused.rk4_batch": 1.8,
    "poinsot.rotations._kernels.to_matrix_flat": 1.7,
    "poinsot.dynamics._euler_numba.midpoint": 1.5,
    "poinsot.rotations._kernels.to_euler_flat": 1.4,
}
#: the SIMD lane kernel compiled for another torque kind (s): measured 8.2-9.0 s
COMPILE_LANE_KIND_S = 9.0
#: what a kernel not in :data:`COMPILE_S` takes, at most (s): measured 0.04-1.1 s
COMPILE_OTHER_S = 1.0
#: the compiled equations of a Lagrangian system (:mod:`poinsot.symbolic.numeric`),
#: measured 0.8-1.4 s for the examples' systems
COMPILE_GENERATED_S = 1.5


def compile_estimate(dispatcher: Any) -> float:
    """Estimated seconds numba takes to compile ``dispatcher`` cold on a 2-core machine
    (:data:`COMPILE_S`; the equations of a Lagrangian system, generated by
    :mod:`poinsot.symbolic.numeric`: :data:`COMPILE_GENERATED_S`)."""
    fn = getattr(dispatcher, "py_func", None)
    module = getattr(fn, "__module__", None) or ""
    if module.startswith("poinsot_rhs"):
        return COMPILE_GENERATED_S
    name = f"{module}.{getattr(fn, '__qualname__', '')}"
    if name == "poinsot.dynamics._fused_lanes.integrate_batch" and getattr(
        dispatcher, "overloads", None
    ):
        return COMPILE_LANE_KIND_S
    return COMPILE_S.get(name, COMPILE_OTHER_S)


def say_seconds(seconds: float) -> str:
    """``about 7 s`` (``about 1 s or less`` from 1 s down): an estimate as the notices say it."""
    return "about 1 s or less" if seconds <= 1.0 else f"about {seconds:.0f} s"


#: seconds spent in outermost numba compilations so far (all threads), and the start time
#: of the one running in each thread
_COMPILE_TIME: dict[str, float] = {"total": 0.0}
_COMPILE_START: dict[int, float] = {}


#: 1 while the main thread compiles a numba kernel: read by the native SIGINT handler of
#: poinsot._progress, which then also makes Python's KeyboardInterrupt pending (the
#: compiler is Python code); never while a compiled kernel runs (numba's native code
#: calls back into Python, e.g. to box its results, and must not find an exception set)
MAIN_COMPILING = np.zeros(1, dtype=np.int64)


def compile_seconds() -> float:
    """Seconds this process has spent compiling numba kernels so far (0 without numba):
    the difference over a call is its compile time (loads from the cache not counted)."""
    return _COMPILE_TIME["total"]


def compiling(ident: int | None) -> bool:
    """Whether the thread ``ident`` is compiling a numba kernel now."""
    return ident is not None and _COMPILING.get(ident, 0) > 0


class mute_compile_notice:
    """``with mute_compile_notice():`` the library prints no compile notice in the block
    (the caller announces compilation its own way, or asked for quiet)."""

    def __enter__(self) -> None:
        _NOTICE["muted"] += 1

    def __exit__(self, *exc: object) -> None:
        _NOTICE["muted"] -= 1


def _notice(name: str, seconds: float) -> None:
    import sys
    import time

    if _NOTICE["muted"] or os.environ.get("POINSOT_COMPILE_NOTICE", "1").strip() in ("0", "no"):
        return
    now = time.monotonic()
    if now - _NOTICE["last"] < _NOTICE_EVERY_S:
        return
    _NOTICE["last"] = now
    print(
        f"poinsot: compiling {name} for this machine ({say_seconds(seconds)} on 2 cores; "
        "first use after an install or upgrade, then cached; Ctrl-C stops it; "
        "docs/performance.md, 'Cold start')",
        file=sys.stderr,
        flush=True,
    )


def _install_compile_watch() -> None:
    import threading
    import time

    from numba.core import event

    class Watch(event.Listener):
        """Counts the compilations of each thread; announces an outermost one of a poinsot
        kernel (a load from numba's cache fires no ``numba:compile`` event)."""

        def on_start(self, ev: Any) -> None:
            ident = threading.get_ident()
            depth = _COMPILING.get(ident, 0)
            _COMPILING[ident] = depth + 1
            if depth == 0:
                _COMPILE_START[ident] = time.perf_counter()
                if ident == threading.main_thread().ident:
                    MAIN_COMPILING[0] = 1
                disp = (ev.data or {}).get("dispatcher")
                fn: Any = getattr(disp, "py_func", None)
                module = getattr(fn, "__module__", None) or ""
                if module.startswith("poinsot_rhs"):  # generated: poinsot.symbolic.numeric
                    _notice(
                        "the equations of motion of a Lagrangian system", compile_estimate(disp)
                    )
                elif fn is not None and module.startswith("poinsot"):
                    _notice(f"{module}.{fn.__name__}", compile_estimate(disp))

        def on_end(self, ev: Any) -> None:
            ident = threading.get_ident()
            depth = _COMPILING.get(ident, 1) - 1
            if depth > 0:
                _COMPILING[ident] = depth
            else:
                _COMPILING.pop(ident, None)
                if ident == threading.main_thread().ident:
                    MAIN_COMPILING[0] = 0
                start = _COMPILE_START.pop(ident, None)
                if start is not None:
                    _COMPILE_TIME["total"] += time.perf_counter() - start

    event.register("numba:compile", Watch())  # type: ignore[no-untyped-call]


# ------------------------------------------------------- saves safe across processes
@functools.cache
def _our_cache_paths() -> frozenset[str]:
    """Where numba's locators put the caches of poinsot's kernel files (one folder per
    source folder: in the tree, under NUMBA_CACHE_DIR, or in the user-wide cache)."""
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # type: ignore[attr-defined]
    root = os.path.dirname(os.path.abspath(__file__))
    out = set()

    def probe() -> None:
        pass

    for folder, _dirs, files in os.walk(root):
        py = [f for f in files if f.endswith(".py")]
        if not py:
            continue
        for cls in impl._locator_classes:
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

    import hashlib

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
    from numba.core import caching

    original = caching.IndexDataCacheFile.save

    @functools.wraps(original)
    def save(self: Any, key: Any, data: Any) -> None:
        if os.path.normpath(str(getattr(self, "_cache_path", ""))) in _our_cache_paths():
            _safe_save(self, key, data)
        else:
            original(self, key, data)  # type: ignore[no-untyped-call]

    caching.IndexDataCacheFile.save = save  # type: ignore[method-assign]
    _key_gufunc_wrappers_by_kernel()
    _SAVES_SAFE = True


def _key_gufunc_wrappers_by_kernel() -> None:
    """Cache a poinsot gufunc's wrapper under its kernel's symbol name, not only its
    signature.

    numba caches a gufunc as two entries keyed by the signature alone: the kernel, and
    the wrapper that calls it by the kernel's symbol, numbered in the order of the
    compiling process's compilations (``...euler_to_quatB3v25...``). Two processes that
    compile the same gufunc at once (xdist workers on a cold cache, a program and its
    background warmup, an import outside :func:`compile_lock`) can each save both
    entries, and the cache may end with one process's kernel and the other's wrapper:
    every later process that loads them calls a symbol that is not there and segfaults
    (seen on CI with numba 0.60, and here with 0.68: kernel ``v25``, wrapper calling
    ``v28``). Keyed by the kernel's symbol, a wrapper can only be loaded beside the
    kernel it calls; a mismatch is a cache miss, and the small wrapper is compiled
    again."""
    from numba.np.ufunc import wrappers

    cls = wrappers._GufuncWrapper
    if getattr(cls._compile_wrapper, "_poinsot", False):
        return
    original = cls._compile_wrapper

    @functools.wraps(original)  # numba's own stays reachable (``__wrapped__``)
    def _compile_wrapper(self: Any, wrapper_name: str) -> Any:
        module = getattr(self.py_func, "__module__", "") or ""
        if self.is_parfors or not module.startswith("poinsot"):
            return original(self, wrapper_name)  # type: ignore[no-untyped-call]
        key = (self.cres.signature, self.fndesc.mangled_name)
        wrapperlib = self.cache.load_overload(key, self.cres.target_context)
        if wrapperlib is None:
            wrapperlib = self.context.codegen().create_library(str(self))
            wrapperlib.enable_object_caching()
            self._build_wrapper(wrapperlib, wrapper_name)
            self.cache.save_overload(key, wrapperlib)
        return wrapperlib

    _compile_wrapper._poinsot = True  # type: ignore[attr-defined]
    cls._compile_wrapper = _compile_wrapper  # type: ignore[method-assign]
