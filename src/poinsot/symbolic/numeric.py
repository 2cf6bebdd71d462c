"""Fast numeric right-hand sides generated from a :class:`LagrangeSystem`.

The symbolic ``M``, ``F``, ``A``, ``gamma`` of docs/theory.md §11 go through
SymPy's common-subexpression elimination (:func:`sympy.cse`) and SymPy's Python
code printer into the source of one scalar function, compiled with numba
(``@njit``) together with a loop over a batch of states that solves, for each,
the small dense system

``[[M, -A^T], [A, 0]] [q'', lambda] = [F, -gamma]``

by Gaussian elimination with partial pivoting (the mass matrix is never inverted
symbolically). Why numba: the rest of poinsot is compiled with it, it needs no C
compiler, and a generated scalar kernel looped in machine code is what beats
``lambdify`` (which evaluates one NumPy call per operation) on both one state and
a batch.

Safety: the generated source contains only names poinsot chose (``q_0``,
``u_0``, ``p_0``, ``c_0``...) and the functions of SymPy's printer; the
expressions' own symbol names never reach it, and expressions holding undefined
functions are refused.
"""

from __future__ import annotations

import itertools
import math
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from .. import _jit, integrators
from .._deprecate import renamed, take_renamed
from .._files import atomic_write
from .._progress import Progress, as_progress, ivp_progress
from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_times
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError, PoinsotError
from ..events import as_events, locate, solve_dense
from ._symbols import coordinate_unit

if TYPE_CHECKING:
    from .lagrange import LagrangeSystem
from ..trajectory import CoordinateTrajectory

__all__ = ["NumericLagrangian", "LagrangeTrajectory", "SOLVERS"]

#: ``solve_ivp`` methods accepted by :meth:`NumericLagrangian.simulate`.
#: SciPy's solve_ivp methods (from :data:`poinsot.integrators.INTEGRATORS`).
SOLVERS = integrators.names("lagrangian")

_ALLOWED_FUNCS = {
    "sin", "cos", "tan", "cot", "asin", "acos", "atan", "atan2", "sinh", "cosh",
    "tanh", "asinh", "acosh", "atanh", "exp", "log", "Abs", "sign", "sqrt",
}  # fmt: skip

_COMPILE_LOCK = threading.Lock()

_F64 = np.dtype(np.float64)
_NP_F64 = np.float64
_NDARRAY = np.ndarray

_SOLVER = None
_SOLVER_INLINE = None


def _solver(inline: bool = False) -> Any:
    """The compiled dense solver shared by every generated kernel (compiled once).

    ``inline=True``: the same function (:func:`_solve_py`) for the one-state kernel,
    inlined by numba into its caller, where the size is a constant: the loops are then
    unrolled for it and the views of the caller's scratch need no reference counting.
    Called, the solver took about 60 ns of a 2-link call's 0.3 us in numba (12 atomic
    reference counts of the views it is passed, loops of unknown length); inlined,
    about 20 (measured on the 2-core KVM machine of docs/performance.md)."""
    global _SOLVER, _SOLVER_INLINE
    if inline:
        if _SOLVER_INLINE is None:
            _SOLVER_INLINE = _jit.njit(inline="always")(_solve_py)
        return _SOLVER_INLINE
    if _SOLVER is None:
        _SOLVER = _jit.njit(cache=True, nogil=True)(_solve_py)
    return _SOLVER


def _solve_py(K: np.ndarray, b: np.ndarray, size: int) -> bool:
    """Solve ``K x = b`` (first ``size`` rows) in place by Gaussian elimination with
    partial pivoting; ``x`` is left in ``b``. False if ``K`` is singular."""
    for k in range(size):
        p = k
        big = abs(K[k, k])
        for i in range(k + 1, size):
            if abs(K[i, k]) > big:
                big = abs(K[i, k])
                p = i
        if big == 0.0:
            return False
        if p != k:
            for j in range(size):
                tmp = K[k, j]
                K[k, j] = K[p, j]
                K[p, j] = tmp
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
        inv = 1.0 / K[k, k]
        for i in range(k + 1, size):
            f = K[i, k] * inv
            if f != 0.0:
                for j in range(k + 1, size):
                    K[i, j] -= f * K[k, j]
                b[i] -= f * b[k]
    for k in range(size - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, size):
            s -= K[k, j] * b[j]
        b[k] = s / K[k, k]
    return True


_SOLVE_SOURCE = """
@njit(cache=CACHE, nogil=True)
def _batch(t, y, p, out, lam):
    n = NQ
    m = NC
    K = np.empty((n + m, n + m))
    b = np.empty(n + m)
    bad = -1
    nonfinite = -1
    for i in range(y.shape[0]):
        _system(t[i], y[i], p, K, b)
        if not _solve(K, b, n + m) and bad < 0:
            bad = i
        for k in range(n):
            out[i, k] = y[i, n + k]
            out[i, n + k] = b[k]
        for j in range(m):
            lam[i, j] = b[n + j]
        if nonfinite < 0:
            for k in range(n + m):
                if b[k] - b[k] != 0.0:  # NaN or infinite
                    nonfinite = i
                    break
    # the first singular state; else -2 - the first state with a non-finite q'' or
    # lambda; else -1
    if bad < 0 and nonfinite >= 0:
        return -2 - nonfinite
    return bad


@njit(cache=CACHE)
def _one(t, y, W):
    # one state, in place: y (a fresh copy of the caller's state, C-contiguous) becomes
    # its rate; False if the augmented mass matrix is singular or y is not of length 2n
    # (the caller's general path says which). W: the scratch K (rows :size), b (row
    # size) and the parameters (row size + 1). Two array arguments, not four (numba's
    # entry point takes about 30 ns to unbox each), plain slices of W (a reshape of a
    # flat W took 20-30 ns more) and the GIL kept (releasing and taking it again cost
    # about 45 ns; and W is shared by the caller's threads): measured, in a 2-link call
    # of about 0.3 us.
    n = NQ
    m = NC
    size = n + m
    if y.shape[0] != 2 * n:
        return False
    K = W[:size, :size]
    b = W[size, :size]
    p = W[size + 1]
    _system(t, y, p, K, b)  # reads y before anything is written to it
    if not _solve_inline(K, b, size):
        return False
    for k in range(n):
        y[k] = y[n + k]
        y[n + k] = b[k]
    return True


@njit(cache=CACHE, nogil=True)
def _mass(t, y, p, out):
    n = NQ
    m = NC
    K = np.empty((n + m, n + m))
    b = np.empty(n + m)
    for i in range(y.shape[0]):
        _system(t[i], y[i], p, K, b)
        for r in range(n):
            for s in range(n):
                out[i, r, s] = K[r, s]
"""


def _generate(system: LagrangeSystem, params: tuple[Any, ...]) -> tuple[str, dict[Any, Any]]:
    """Python source of ``_system(t, y, p, K, b)`` filling the augmented system."""
    import sympy
    from sympy.core.function import AppliedUndef
    from sympy.printing.pycode import PythonCodePrinter

    c = system._c
    n = len(c.plain)
    M, F = system._MF
    A, _, gamma = system._constraints
    m = A.shape[0]
    names = {}
    for k in range(n):
        names[c.plain[k]] = sympy.Symbol(f"q_{k}")
        names[c.vel[k]] = sympy.Symbol(f"u_{k}")
    for k, s in enumerate(params):
        names[s] = sympy.Symbol(f"p_{k}")
    names[c.time] = sympy.Symbol("t_")

    # (row, column[, "neg"]) entries of the matrix, or ("b", row[, "neg"]) of the vector
    targets: list[list[tuple[Any, ...]]] = []
    exprs: list[Any] = []
    for r in range(n):
        for s in range(r, n):
            targets.append([(r, s), (s, r)] if s != r else [(r, s)])
            exprs.append(M[r, s])
        targets.append([("b", r)])
        exprs.append(F[r])
    for j in range(m):
        for s in range(n):
            targets.append([(n + j, s), (s, n + j, "neg")])
            exprs.append(A[j, s])
        targets.append([("b", n + j, "neg")])
        exprs.append(gamma[j])
    exprs = [sympy.sympify(e).xreplace(names) for e in exprs]
    for e in exprs:
        bad = e.atoms(AppliedUndef) | {
            f for f in e.atoms(sympy.Function) if type(f).__name__ not in _ALLOWED_FUNCS
        }
        if bad:
            raise InvalidInputError(
                f"Cannot compile the function {sorted(map(str, bad))[0]}: allowed are "
                f"{', '.join(sorted(_ALLOWED_FUNCS))}."
            )
    repl, reduced = sympy.cse(exprs, symbols=sympy.numbered_symbols("c_"), optimizations="basic")
    printer = PythonCodePrinter({"fully_qualified_modules": True, "standard": "python3"})
    lines = ["@njit(cache=CACHE, nogil=True)", "def _system(t_, y, p, K, b):"]
    lines += [f"    q_{k} = y[{k}]" for k in range(n)]
    lines += [f"    u_{k} = y[{n + k}]" for k in range(n)]
    lines += [f"    p_{k} = p[{k}]" for k in range(len(params))]
    for sym, e in repl:
        lines.append(f"    {sym} = {printer.doprint(e)}")
    for j in range(m):
        for jj in range(m):
            lines.append(f"    K[{n + j}, {n + jj}] = 0.0")
    for tgt, e in zip(targets, reduced, strict=True):
        code = printer.doprint(e)
        for place in tgt:
            neg = len(place) == 3
            val = f"-({code})" if neg else f"{code}"
            if place[0] == "b":
                lines.append(f"    b[{place[1]}] = {val}")
            else:
                lines.append(f"    K[{place[0]}, {place[1]}] = {val}")
    lines.append("    return None")
    src = "\n".join(lines) + "\n" + _SOLVE_SOURCE.replace("NQ", str(n)).replace("NC", str(m))
    return src, names


def _cache_dir() -> Path | None:
    """Where generated kernels are written so numba can cache their machine code.

    ``POINSOT_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/poinsot`` or
    ``~/.cache/poinsot``; None (compile in memory, no cache) if not writable.
    """
    import os
    from pathlib import Path

    root = os.environ.get("POINSOT_CACHE_DIR")
    if root is None:
        xdg = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        root = str(Path(xdg) / "poinsot")
    path = Path(root) / "symbolic"
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return path if os.access(path, os.W_OK) else None


_HEADER = "# generated by poinsot.symbolic.numeric: do not edit\n"
_HEADER += "import math\nimport numpy as np\nfrom poinsot._jit import njit\n"
_HEADER += "from poinsot.symbolic.numeric import _solver\n\n"
_HEADER += "_solve = _solver()\n_solve_inline = _solver(inline=True)\nCACHE = {cache}\n\n"


def _compile(src: str) -> dict[str, Any]:
    """Compile the generated source: as a module file (numba caches the machine code
    across processes) or, if no cache directory is writable, in memory."""
    import hashlib
    import importlib.util

    with _COMPILE_LOCK:
        folder = _cache_dir() if _jit.NUMBA else None  # nothing to cache without numba
        if folder is None:
            namespace: dict[str, Any] = {"np": np, "math": math, "njit": _jit.njit, "CACHE": False}
            namespace["_solve"] = _solver()
            namespace["_solve_inline"] = _solver(inline=True)
            exec(compile(src, "<poinsot.symbolic generated rhs>", "exec"), namespace)  # noqa: S102
            return namespace
        import inspect

        # numba does not see a change of a callee: the solver's source is in the key
        solver_key = hashlib.sha256(inspect.getsource(_solve_py).encode()).hexdigest()[:16]
        text = f"# solver {solver_key}\n" + _HEADER.format(cache=True) + src
        digest = hashlib.sha256(text.encode()).hexdigest()[:24]
        name = f"poinsot_rhs_{digest}"
        path = folder / f"{name}.py"
        if not path.exists() or path.read_text() != text:
            atomic_write(path, lambda fh: fh.write(text))
        import sys

        module = sys.modules.get(name)
        if module is None:
            spec = importlib.util.spec_from_file_location(name, path)
            if spec is None or spec.loader is None:  # not for a .py path: for the type checker
                raise ImportError(f"cannot load the generated module {path}")
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module  # numba's cache locates functions by module
            spec.loader.exec_module(module)
        return vars(module)


def _passthrough(*args: Any, **kwargs: Any) -> Any:
    """``njit`` for the generated source run by the interpreter: the function itself."""
    if args and callable(args[0]):
        return args[0]
    return lambda fn: fn


#: What the generated kernels raise where a formula is not defined: a division by zero
#: (numba and Python), a math domain error or an overflow (Python's ``math``).
_UNDEFINED = (ArithmeticError, ValueError)


def _undefined(exc: BaseException) -> bool:
    """Whether ``exc`` is a formula evaluated outside its domain (not one of ours)."""
    return isinstance(exc, _UNDEFINED) and not isinstance(exc, PoinsotError)


def _num(v: float) -> str:
    return f"{float(v):.15g}"


def _positive_definite(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Whether each symmetric matrix of the stack ``m`` (..., n, n) is positive definite
    (every eigenvalue above ``1e-12`` times the largest in magnitude), and the
    eigenvalues: the test of a kinetic energy ``d^2T/dq'dq'`` (a mass matrix), shared by
    :meth:`NumericLagrangian.simulate` and the ``lagrangian`` scenario kind."""
    m = np.asarray(m, dtype=float)
    if m.shape[-1] == 0:
        return np.zeros(m.shape[:-2], dtype=bool), np.zeros((*m.shape[:-2], 0))
    eig = np.linalg.eigvalsh(0.5 * (m + np.swapaxes(m, -1, -2)))
    scale = np.maximum(np.max(np.abs(eig), axis=-1), 1e-300)
    return np.all(eig > 1e-12 * scale[..., None], axis=-1), eig


def _framed(kind: str, message: str, subject: str = "a state") -> str:
    """A message of :meth:`NumericLagrangian._start_problem` as a sentence of its own."""
    if kind == "state":
        return f"Expected {subject} where the equations of motion are finite, but {message}."
    return message[0].upper() + message[1:]


class NumericLagrangian:
    """Compiled right-hand side of a :class:`~poinsot.symbolic.LagrangeSystem`.

    ``f(t, y, parameters=None) -> y'`` with the state ``y = [q, q']`` (shape
    ``(..., 2n)``, any leading batch shape), ``t`` a float or an array
    broadcasting to the batch shape, and ``parameters`` a mapping from parameter
    names to floats (overriding the defaults given to ``to_numeric``). The same
    calling convention as :func:`scipy.integrate.solve_ivp` expects for
    ``fun(t, y)`` with a 1-D ``y``.

    Built by :meth:`LagrangeSystem.to_numeric` (docs/theory.md §11): the
    expressions are reduced by :func:`sympy.cse`, printed as Python and
    compiled by numba, with ``M q'' = F + A^T lambda``, ``A q'' + gamma = 0``
    solved numerically per state (partial pivoting). Compilation happens on the
    first call.

    Attributes
    ----------
    coordinates : tuple of str
        Names of ``q``.
    parameters : tuple of str
        Names of the parameters, in the order of :attr:`parameter_values`.
    n, n_constraints : int
        Number of coordinates and of kept constraints (multipliers).

    Examples
    --------
    >>> import numpy as np, sympy
    >>> x = sympy.Function("x")(sympy.Symbol("t"))
    >>> k = sympy.Symbol("k")
    >>> from poinsot.symbolic import LagrangeSystem
    >>> f = LagrangeSystem([x], x.diff() ** 2 / 2, k * x**2 / 2).to_numeric({"k": 4.0})
    >>> f(0.0, [1.0, 0.5])
    array([ 0.5, -4. ])
    >>> f(0.0, np.ones((5, 3, 2)), parameters={"k": 1.0}).shape
    (5, 3, 2)
    """

    def __init__(
        self, system: LagrangeSystem, parameters: Mapping[str, float] | None = None
    ) -> None:
        import sympy

        self._system = system
        c = system._c
        self.n = len(c.plain)
        self.n_constraints = system._constraints[0].shape[0]
        self._params_sym = system.parameters
        self.coordinates = c.names
        self.parameters = tuple(s.name for s in self._params_sym)
        defaults = np.full(len(self.parameters), np.nan)
        if parameters is not None:
            defaults = self._param_vector(parameters, defaults, "parameters")
        self._defaults = defaults
        self._defaults_ok = not np.isnan(defaults).any()
        self._src, self._names = _generate(system, self._params_sym)
        self._ns: dict[str, Any] | None = None
        self._one: Any = None  # see _one_entry
        self._work = np.empty(0)
        self._aux: dict[str, Any] = {}
        self._sympy = sympy

    # -------------------------------------------------------------- pickling
    #: What a pickle leaves out: the compiled kernels, their scratch and the lambdified
    #: functions (rebuilt on first use, from the generated source), and the sympy module.
    _TRANSIENT = ("_ns", "_one", "_work", "_aux", "_sympy")

    def __getstate__(self) -> dict[str, Any]:
        """The system, the parameters and the generated source: picklable (e.g. for
        ``multiprocessing`` or Dask); the kernels are compiled again where it lands
        (numba's disk cache makes that a load)."""
        return {k: v for k, v in self.__dict__.items() if k not in self._TRANSIENT}

    def __setstate__(self, state: dict[str, Any]) -> None:
        import sympy

        self.__dict__.update(state)
        self._ns = None
        self._one = None
        self._work = np.empty(0)
        self._aux = {}
        self._sympy = sympy

    # --------------------------------------------------------------- helpers
    @property
    def source(self) -> str:
        """The generated Python source (before numba compilation)."""
        return self._src

    @property
    def parameter_values(self) -> dict[str, float]:
        """The default parameter values (NaN where none was given)."""
        return dict(zip(self.parameters, self._defaults.tolist(), strict=True))

    def _param_vector(
        self,
        params: Mapping[str, float] | ArrayLike | None,
        base: np.ndarray,
        name: str = "parameters",
    ) -> np.ndarray:
        if not isinstance(params, Mapping):
            raise InvalidTypeError(
                f"Expected `{name}` to be a mapping of parameter names to floats, "
                f"got {type(params).__name__}."
            )
        out = np.array(base, dtype=float)
        for key, value in params.items():
            k = key if isinstance(key, str) else getattr(key, "name", str(key))
            if k not in self.parameters:
                raise InvalidInputError(
                    f"Expected `{name}` keys among the parameters {list(self.parameters)}, "
                    f"got {k!r}."
                )
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise InvalidTypeError(
                    f"Expected `{name}[{k!r}]` to be a real number, got {value!r}."
                ) from None
            if not math.isfinite(v):
                raise InvalidInputError(f"Expected `{name}[{k!r}]` to be finite, got {v}.")
            out[self.parameters.index(k)] = v
        return out

    def _params(self, params: Mapping[str, float] | ArrayLike | None) -> np.ndarray:
        p = self._defaults if params is None else self._param_vector(params, self._defaults)
        if np.isnan(p).any():
            missing = [nm for nm, v in zip(self.parameters, p, strict=True) if np.isnan(v)]
            raise InvalidInputError(
                f"Expected values for the parameters {missing} (pass `parameters` or "
                "`to_numeric(parameters)`)."
            )
        return p

    def _kernels(self) -> dict[str, Any]:
        if self._ns is None:
            self._ns = _compile(self._src)
        return self._ns

    def _one_entry(self) -> Any:
        """The one-state kernel compiled for ``(float64, float64 arrays)``: its entry
        point trusts its arguments' types, so :meth:`__call__` checks them first (``y``
        a 1-D float64 array, handed over as a copy the kernel overwrites with the rate;
        ``t`` a float; the scratch is its own; the kernel checks the length of ``y``)."""

        ns = self._kernels()
        size = self.n + self.n_constraints
        n_p = len(self._defaults)
        # the scratch K and b, then the parameters (see _one in the generated source)
        work = np.zeros((size + 2, max(size, n_p, 1)))
        work[size + 1, :n_p] = self._defaults
        self._work = work
        if not _jit.NUMBA:  # the NumPy executor: the plain Python function
            self._one = ns["_one"]
            return self._one
        from numba import types

        # y: the caller's copy (C-contiguous, writable); W: the scratch and parameters
        a1 = types.Array(types.float64, 1, "C")
        a2 = types.Array(types.float64, 2, "C")
        sig = (types.float64, a1, a2)
        self._one = ns["_one"].compile(sig)
        return self._one

    def compile(self) -> NumericLagrangian:
        """Compile now (otherwise done on the first call); returns ``self``."""
        ns = self._kernels()
        y = np.zeros((1, 2 * self.n))
        p = np.zeros(len(self.parameters))
        lam = np.empty((1, self.n_constraints))
        try:  # any state compiles the kernels (a formula undefined there is no matter)
            ns["_batch"](np.zeros(1), y, p, np.empty((1, 2 * self.n)), lam)
        except _UNDEFINED as exc:
            if not _undefined(exc):
                raise
        if self._defaults_ok:
            self._one_entry()
        return self

    def _state(self, y: ArrayLike) -> np.ndarray:
        try:
            a = np.asarray(y, dtype=float)
        except (TypeError, ValueError):
            raise InvalidTypeError(
                f"Expected `y` to be a real array, got {type(y).__name__}."
            ) from None
        if a.ndim == 0 or a.shape[-1] != 2 * self.n:
            raise InvalidInputError(
                f"Expected `y` to have shape (..., {2 * self.n}) ([q, q'] for "
                f"{list(self.coordinates)}), got {a.shape}."
            )
        return a

    # ------------------------------------------------------- states refused
    def _interpreted(self) -> dict[str, Any]:
        """The generated source run by the interpreter (the same formulas, no numba
        compilation): to probe a few states at once, e.g. when a scenario is checked."""
        ns = self._aux.get("interpreted")
        if ns is None:
            ns = {"np": np, "math": math, "njit": _passthrough, "CACHE": False}
            ns["_solve"] = ns["_solve_inline"] = _solve_py
            code = compile(self._src, "<poinsot.symbolic generated rhs, interpreted>", "exec")
            exec(code, ns)  # noqa: S102 - poinsot's own generated source (module docstring)
            self._aux["interpreted"] = ns
        return ns

    def _state_text(self, t: float, y: np.ndarray, rate: str = "'") -> str:
        """``t = 0, x = -1, x' = 0``: a state as the messages name it."""
        n = self.n
        parts = [f"t = {_num(t)}"]
        parts += [f"{c} = {_num(v)}" for c, v in zip(self.coordinates, y[:n], strict=True)]
        parts += [f"{c}{rate} = {_num(v)}" for c, v in zip(self.coordinates, y[n:], strict=True)]
        return ", ".join(parts)

    def _undefined_text(
        self, t: float, y: np.ndarray, p: np.ndarray, what: str, rate: str = "'"
    ) -> str:
        """``the equations of motion give NaN at t = 0, x = -1, x' = 0: the potential
        k*sqrt(x) is not real there (k = 1)``: ``what`` happened at the state and the
        first term of the system to blame (evaluated by SymPy: only after a failure)."""
        text = f"the equations of motion {what} at {self._state_text(t, y, rate)}"
        c = self._system._c
        values: dict[Any, float] = {c.time: float(t)}
        values.update(zip(c.plain, y[: self.n].tolist(), strict=True))
        values.update(zip(c.vel, y[self.n :].tolist(), strict=True))
        values.update(zip(self._params_sym, p.tolist(), strict=True))
        found = self._system._first_undefined(values, rate)
        if found is not None:
            label, expr, defect, used = found
            text += f": {label} {expr} is {defect} there"
            named = [f"{s} = {_num(values[s])}" for s in self._params_sym if s in used]
            if named:
                text += f" ({', '.join(named)})"
        return text

    def _start_problem(
        self, t: np.ndarray, y: np.ndarray, p: np.ndarray, ns: dict[str, Any], rate: str = "'"
    ) -> tuple[str, str] | None:
        """Why the equations cannot be integrated from the states ``y`` (N, 2n) at the
        times ``t`` (N,), or None: ``("state", ...)`` a term not finite (NaN, infinite,
        a division by zero), ``("kinetic", ...)`` a mass matrix not positive definite
        (no constraints kept), ``("singular", ...)`` an augmented matrix singular. The
        message starts in lower case (the caller frames it)."""
        n, m, N = self.n, self.n_constraints, y.shape[0]
        M = np.empty((N, n, n))
        out = np.empty_like(y)
        lam = np.empty((N, m))
        try:
            with np.errstate(all="ignore"):
                ns["_mass"](t, y, p, M)
                code = ns["_batch"](t, y, p, out, lam)
        except _UNDEFINED as exc:
            if not _undefined(exc):
                raise
            i = 0
            for i in range(N):  # the first state that raises
                try:
                    with np.errstate(all="ignore"):
                        ns["_batch"](t[i : i + 1], y[i : i + 1], p, out[:1], lam[:1])
                except _UNDEFINED:
                    break
            # numba raises ZeroDivisionError where NumPy gives inf: the same words for both
            zero = isinstance(exc, ZeroDivisionError)
            what = "give an infinite value (a division by zero)" if zero else "give NaN"
            return "state", self._undefined_text(t[i], y[i], p, what, rate)
        finite = np.isfinite(M.reshape(N, -1)).all(axis=1)
        if not finite.all():
            i = int(np.argmin(finite))
            what = "give a mass matrix that is not finite"
            return "state", self._undefined_text(t[i], y[i], p, what, rate)
        if m == 0:
            ok, eig = _positive_definite(M)
            if not ok.all():
                i = int(np.argmin(ok))
                rates = ", ".join(f"{c}{rate}" for c in self.coordinates)
                return "kinetic", (
                    "expected a kinetic energy that is positive definite in the velocities "
                    f"({rates}) at the initial state ({self._state_text(t[i], y[i], rate)}), "
                    f"got the mass matrix d^2T/dq'dq' = {np.round(M[i], 12).tolist()} "
                    f"(eigenvalues {np.round(eig[i], 12).tolist()}): a negative or missing "
                    "velocity term has no motion to integrate."
                )
        if code >= 0:
            return "singular", (
                "the mass matrix (augmented with the constraints) is singular at the initial "
                f"state {self._state_text(t[code], y[code], rate)}."
            )
        if code < -1:
            i = -2 - code
            bad = np.concatenate([out[i, n:], lam[i]])
            what = "give NaN" if np.isnan(bad).any() else "give an infinite value"
            return "state", self._undefined_text(t[i], y[i], p, what, rate)
        return None

    def _raise_undefined(
        self, exc: BaseException, t: Any, y: Any, params: Mapping[str, float] | ArrayLike | None
    ) -> NoReturn:
        """``exc`` raised by a kernel at the states ``y``: re-raised as it is if it is not
        a formula evaluated outside its domain, else as an :class:`InvalidInputError`
        naming the state and the term (a ``ZeroDivisionError`` is not a bug of poinsot)."""
        if not _undefined(exc):
            raise exc
        p = self._params(params)
        a = np.ascontiguousarray(np.asarray(y, dtype=float).reshape(-1, 2 * self.n))
        tt = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), a.shape[:1]))
        found = self._start_problem(tt, a, p, self._kernels())
        text = found[1] if found is not None else f"the equations of motion raise {exc!r}"
        raise InvalidInputError(_framed("state", text)) from None

    @renamed(params="parameters")
    def check_state(
        self,
        t: ArrayLike,
        y: ArrayLike,
        parameters: Mapping[str, float] | ArrayLike | None = None,
        *,
        compiled: bool = True,
    ) -> None:
        """Refuse states the equations of motion cannot be integrated from, as
        :meth:`simulate` does with its initial states.

        Parameters
        ----------
        t : array_like
            Times, broadcasting to the batch shape of ``y``.
        y : array_like, shape (..., 2n)
            States ``[q, q']``.
        parameters : mapping, optional
            Parameter values (override the defaults).
        compiled : bool, optional
            Evaluate with the compiled kernels (default) or run the same generated
            source with the interpreter (no compilation: quicker for a few states).

        Raises
        ------
        InvalidInputError
            If a term of the equations is not finite at a state (NaN, infinite, a
            division by zero: the message names the state and the term), if the
            mass matrix is not positive definite there (no constraints kept) or if
            the mass matrix augmented with the constraints is singular.

        Examples
        --------
        >>> import sympy
        >>> from poinsot.symbolic import LagrangeSystem
        >>> x = sympy.Function("x")(sympy.Symbol("t"))
        >>> f = LagrangeSystem([x], x.diff() ** 2 / 2, sympy.sqrt(x)).to_numeric()
        >>> f.check_state(0.0, [-1.0, 0.0])  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        poinsot.errors.InvalidInputError: Expected ... give NaN at t = 0, x = -1, x' = 0: ...
        """
        p = self._params(parameters)
        a = self._state(y)
        flat = np.ascontiguousarray(a.reshape(-1, 2 * self.n))
        tt = np.broadcast_to(np.asarray(t, dtype=float), a.shape[:-1]).reshape(-1)
        ns = self._kernels() if compiled else self._interpreted()
        problem = self._start_problem(np.ascontiguousarray(tt), flat, p, ns)
        if problem is not None:
            raise InvalidInputError(_framed(*problem))

    def _run(
        self, t: ArrayLike, y: ArrayLike, params: Mapping[str, float] | ArrayLike | None
    ) -> tuple[np.ndarray, np.ndarray]:
        ns = self._kernels()
        p = self._params(params)
        a = self._state(y)
        batch = a.shape[:-1]
        flat = np.ascontiguousarray(a.reshape(-1, 2 * self.n))
        tt = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), batch).reshape(-1))
        out = np.empty_like(flat)
        lam = np.empty((flat.shape[0], self.n_constraints))
        try:
            bad = ns["_batch"](tt, flat, p, out, lam)
        except _UNDEFINED as exc:
            self._raise_undefined(exc, tt, flat, params)
        if bad >= 0:
            raise InvalidInputError(
                "The mass matrix (augmented with the constraints) is singular at the state "
                f"y = {flat[bad].tolist()}, t = {tt[bad]}."
            )
        return out.reshape(a.shape), lam.reshape((*batch, self.n_constraints))

    @renamed(params="parameters")
    def __call__(
        self,
        t: ArrayLike,
        y: ArrayLike,
        parameters: Mapping[str, float] | ArrayLike | None = None,
        **deprecated: Any,
    ) -> FloatArray:
        """``y' = [q', q'']`` at time ``t`` (shape of ``y``)."""
        one = self._one
        if (
            one is not None
            and type(y) is _NDARRAY
            and (type(t) is float or type(t) is _NP_F64)
            and parameters is None
            and not deprecated
            and y.dtype is _F64
            and y.ndim == 1
        ):
            # one state as solve_ivp passes it: numba's entry point compiled for exactly
            # these types (no dispatcher type matching; the kernel checks the length), the
            # scratch kept (no allocation but the result's: the copy of y, overwritten).
            # Set up by the first such call (below). Every test here is a type, an
            # identity or a small int: a tuple comparison (y.shape == (2n,)) took 40 ns
            # of a 0.55 us call, measured.
            out = y.copy()
            try:
                if one(t, out, self._work):
                    return out
            except _UNDEFINED as exc:
                self._raise_undefined(exc, t, y, parameters)
        if deprecated:  # no wrapper on this hot path (see poinsot._deprecate)
            parameters = take_renamed(
                "NumericLagrangian.__call__",
                deprecated,
                {"parameters": parameters},
                params="parameters",
            )["parameters"]
        if (
            parameters is None
            and type(y) is np.ndarray
            and y.shape == (2 * self.n,)
            and y.dtype == np.float64
            and self._defaults_ok
        ):
            # fast path for one state (what solve_ivp passes): no validation copies
            if one is None:
                self._one_entry()
            ns = self._ns or self._kernels()
            aux = self._aux
            if "t1" not in aux:
                aux.update(t1=np.empty(1), lam1=np.empty((1, self.n_constraints)))
            aux["t1"][0] = t
            out = np.empty((1, 2 * self.n))
            try:
                if ns["_batch"](aux["t1"], y.reshape(1, -1), self._defaults, out, aux["lam1"]) < 0:
                    return out.reshape(-1)
            except _UNDEFINED as exc:
                self._raise_undefined(exc, t, y, parameters)
        return self._run(t, y, parameters)[0]

    rhs = __call__

    @renamed(params="parameters")
    def multipliers(
        self, t: ArrayLike, y: ArrayLike, parameters: Mapping[str, float] | ArrayLike | None = None
    ) -> FloatArray:
        """The constraint multipliers ``lambda`` (shape ``(..., m)``) at the states ``y``."""
        return self._run(t, y, parameters)[1]

    @renamed(params="parameters")
    def mass_matrix(
        self, t: ArrayLike, y: ArrayLike, parameters: Mapping[str, float] | ArrayLike | None = None
    ) -> FloatArray:
        """``M(q, t)`` (shape ``(..., n, n)``) at the states ``y``."""
        ns = self._kernels()
        p = self._params(parameters)
        a = self._state(y)
        flat = np.ascontiguousarray(a.reshape(-1, 2 * self.n))
        tt = np.broadcast_to(np.asarray(t, dtype=float), a.shape[:-1]).reshape(-1)
        tt = np.ascontiguousarray(tt)
        out = np.empty((flat.shape[0], self.n, self.n))
        try:
            ns["_mass"](tt, flat, p, out)
        except _UNDEFINED as exc:
            self._raise_undefined(exc, tt, flat, parameters)
        return out.reshape((*a.shape[:-1], self.n, self.n))

    def _lambdified(self, which: str) -> Any:
        if which not in self._aux:
            sp = self._sympy
            sysm = self._system
            expr = {
                "energy": sysm._energy_plain,
                "jacobi": sysm._jacobi_plain,
                "kinetic": sysm._T,
            }[which]
            expr = expr.xreplace(self._names)
            c = sysm._c
            q = [self._names[s] for s in c.plain]
            u = [self._names[s] for s in c.vel]
            p = [sp.Symbol(f"p_{k}") for k in range(len(self.parameters))]
            self._aux[which] = sp.lambdify([sp.Symbol("t_"), q, u, p], expr, modules="numpy")
        return self._aux[which]

    def _scalar(
        self, which: str, t: ArrayLike, y: ArrayLike, params: Mapping[str, float] | ArrayLike | None
    ) -> np.ndarray:
        a = self._state(y)
        p = self._params(params)
        fn = self._lambdified(which)
        q = np.moveaxis(a[..., : self.n], -1, 0)
        u = np.moveaxis(a[..., self.n :], -1, 0)
        val = fn(np.asarray(t, dtype=float), q, u, p)
        return np.broadcast_to(np.asarray(val, dtype=float), a.shape[:-1]).copy()

    @renamed(params="parameters")
    def energy(
        self, t: ArrayLike, y: ArrayLike, parameters: Mapping[str, float] | ArrayLike | None = None
    ) -> FloatArray:
        """Mechanical energy ``T + P + V0`` at the states ``y`` (shape ``y.shape[:-1]``)."""
        return self._scalar("energy", t, y, parameters)

    @renamed(params="parameters")
    def kinetic(
        self, t: ArrayLike, y: ArrayLike, parameters: Mapping[str, float] | ArrayLike | None = None
    ) -> FloatArray:
        """Kinetic energy ``T`` at the states ``y`` (shape ``y.shape[:-1]``)."""
        return self._scalar("kinetic", t, y, parameters)

    @renamed(params="parameters")
    def jacobi(
        self, t: ArrayLike, y: ArrayLike, parameters: Mapping[str, float] | ArrayLike | None = None
    ) -> FloatArray:
        """Jacobi integral ``q' . dL/dq' - L`` at the states ``y``."""
        return self._scalar("jacobi", t, y, parameters)

    def _units(self, units: Mapping[str, str] | Sequence[str] | None) -> tuple[str, ...]:
        """The units of the coordinates: given, else guessed from their names."""

        if units is None:
            units = {}
        if isinstance(units, Mapping):
            unknown = [k for k in units if k not in self.coordinates]
            if unknown:
                raise InvalidInputError(
                    f"Expected the keys of `units` among the coordinates "
                    f"{list(self.coordinates)}, got {unknown[0]!r}."
                )
            return tuple(str(units.get(c, coordinate_unit(c))) for c in self.coordinates)
        if isinstance(units, str):
            raise InvalidTypeError(
                f"Expected `units` to be a sequence of {self.n} strings or a mapping, got "
                f"the string {units!r}."
            )
        return tuple(units)

    @renamed(params="parameters")
    def simulate(
        self,
        q0: ArrayLike,
        qdot0: ArrayLike,
        t: ArrayLike,
        *,
        parameters: Mapping[str, float] | ArrayLike | None = None,
        method: str = "DOP853",
        rtol: float = 1e-10,
        atol: float = 1e-12,
        max_step: float = math.inf,
        units: Mapping[str, str] | Sequence[str] | None = None,
        progress: Progress = None,
        events: Any = None,
    ) -> CoordinateTrajectory:
        """Integrate from ``q(t[0]) = q0``, ``q'(t[0]) = qdot0`` with ``solve_ivp``.

        ``progress``: True (a progress bar, tqdm when installed), a callable receiving
        the fraction of the time span done, or None (default). The solver loop is
        Python: Ctrl-C stops it between steps (``KeyboardInterrupt``, nothing partial).

        Parameters
        ----------
        q0, qdot0 : array_like, shape (..., n)
            Initial coordinates and velocities; a leading batch shape integrates
            many initial states at once (one vectorised system).
        t : array_like, shape (k,)
            Output times, strictly increasing.
        parameters : mapping, optional
            Parameter values (override the defaults).
        method : str, optional
            A ``solve_ivp`` method (:data:`SOLVERS`), default ``"DOP853"``.
        rtol, atol, max_step : float, optional
            Passed to ``solve_ivp`` (defaults ``1e-10``, ``1e-12``, no limit).
        units : sequence of str or mapping, optional
            The SI unit of each coordinate (``"rad"``, ``"m"``; ``""`` unknown), or a
            mapping from some coordinate names to units; carried by the result and
            its channels. Default (and for a name the mapping leaves out): guessed
            from the name as the ``lagrangian`` scenario kind does (``theta1``, ``phi``
            an angle in rad; ``x``, ``r``, ``z_2`` a length in m; else ``""``).
        events : callable, Event or list of them, optional
            Functions ``g(t, y)`` of the state ``y = (q_1 .. q_n, q'_1 .. q'_n)`` whose
            zeros are events, with SciPy's ``terminal`` and ``direction``
            (:class:`poinsot.dynamics.Event`); located per initial state to round-off
            (theory §11.1) and returned as ``info["events"]`` (an
            :class:`~poinsot.dynamics.EventLog`). A terminal event ends the motion at
            the event (its last sample); in a batch the stopped state is held there.

        Returns
        -------
        CoordinateTrajectory
            ``q``, ``qdot`` (k, ..., n), ``energy`` and ``jacobi`` (k, ...) when
            defined, ``multipliers`` (k, ..., m) when there are constraints;
            ``method`` the ``solve_ivp`` method.

        Raises
        ------
        IntegrationError
            If ``solve_ivp`` fails (message with the time reached).

        Examples
        --------
        >>> import numpy as np, sympy
        >>> from poinsot.symbolic import LagrangeSystem
        >>> x = sympy.Function("x")(sympy.Symbol("t"))
        >>> f = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2).to_numeric()
        >>> tr = f.simulate([[1.0], [2.0]], [[0.0], [0.0]], [0.0, np.pi])
        >>> np.round(tr.q[-1, :, 0], 8)
        array([-1., -2.])
        """
        from scipy.integrate import solve_ivp

        method = integrators.check_method(method, SOLVERS, "a Lagrangian system")
        tt = as_times(t, "t")
        p = self._params(parameters)
        pmap = dict(zip(self.parameters, p.tolist(), strict=True))

        q0a = as_float_array(q0, "q0", finite=False)
        u0a = as_float_array(qdot0, "qdot0", finite=False)
        for name, a in (("q0", q0a), ("qdot0", u0a)):
            if a.ndim == 0 or a.shape[-1] != self.n:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape (..., {self.n}), got {a.shape}."
                )
            if not np.isfinite(a).all():
                raise InvalidInputError(f"Expected `{name}` to be finite, got {a.tolist()}.")
        batch = np.broadcast_shapes(q0a.shape[:-1], u0a.shape[:-1])
        y0 = np.concatenate(
            [np.broadcast_to(q0a, (*batch, self.n)), np.broadcast_to(u0a, (*batch, self.n))],
            axis=-1,
        )
        nb = max(1, math.prod(batch))
        ns = self._kernels()
        # what no step can start from, refused before solve_ivp (a NaN derivative at the
        # start makes its first step size NaN: it retried forever)
        start = np.ascontiguousarray(y0.reshape(nb, 2 * self.n))
        problem = self._start_problem(np.full(nb, float(tt[0])), start, p, ns)
        if problem is not None:
            raise InvalidInputError(_framed(*problem, "an initial state (`q0`, `qdot0`)"))
        flat_lam = np.empty((nb, self.n_constraints))
        t_buf = np.empty(nb)
        counter = itertools.count()

        def fun(time: float, yy: np.ndarray) -> np.ndarray:
            next(counter)
            t_buf.fill(time)
            flat_out = np.empty((nb, 2 * self.n))  # a new array: solve_ivp keeps them
            states = yy.reshape(nb, 2 * self.n)
            try:
                bad = ns["_batch"](t_buf, states, p, flat_out, flat_lam)
            except _UNDEFINED as exc:
                if not _undefined(exc):
                    raise
                # the first state that raises, named with the term to blame
                found = self._start_problem(t_buf.copy(), states.copy(), p, ns)
                text = (
                    found[1]
                    if found is not None and found[0] == "state"
                    else f"the equations of motion raised {exc!r} at t = {_num(time)}"
                )
                raise IntegrationError(f"{text[0].upper()}{text[1:]}.") from None
            if bad >= 0:
                raise IntegrationError(
                    f"The (augmented) mass matrix became singular at t = {time} "
                    f"(state {states[bad].tolist()})."
                )
            if bad < -1:  # a non-finite q'' or lambda: stop rather than let SciPy retry
                i = -2 - bad
                y_i = states[i]
                bad_values = np.concatenate([flat_out[i, self.n :], flat_lam[i]])
                what = "give NaN" if np.isnan(bad_values).any() else "give an infinite value"
                text = self._undefined_text(time, y_i, p, what)
                raise IntegrationError(f"{text[0].upper()}{text[1:]}.")
            return flat_out.reshape(-1)

        if tt.size == 1:
            ys = y0.reshape(1, *y0.shape)
            info = {"evaluations": 0, "status": 0, "message": "single output time"}
        else:
            report = as_progress(progress, "LagrangeSystem.simulate")
            try:
                sol = solve_ivp(
                    ivp_progress(fun, float(tt[0]), float(tt[-1]), report),
                    (tt[0], tt[-1]),
                    y0.reshape(-1),
                    method=method,
                    t_eval=tt,
                    rtol=rtol,
                    atol=atol,
                    max_step=max_step,
                )
            except BaseException:
                if report is not None:
                    report.close()
                raise
            if report is not None:
                report.finish()
            if sol.status != 0 or sol.y.shape[1] != tt.size:
                reached = sol.t[-1] if sol.t.size else tt[0]
                raise IntegrationError(
                    f"solve_ivp({method}) failed at t = {reached}: {sol.message}"
                )
            ys = sol.y.T.reshape(tt.size, *batch, 2 * self.n)
            info = {"status": int(sol.status), "message": sol.message}
        # evaluations of the compiled right-hand side (solve_ivp's nfev plus the
        # finite-difference Jacobians of the implicit methods)
        info.update(solver=method, rtol=float(rtol), atol=float(atol), evaluations=next(counter))
        event_list = as_events(events)
        if event_list:

            def flow(bodies: np.ndarray, t0: float, t1: float, y_start: np.ndarray) -> Any:
                # the compiled right-hand side takes the whole batch: all ride along
                whole = solve_dense(lambda s, y: fun(s, y).reshape(nb, 2 * self.n), t0, t1, y_start)
                return lambda s: whole(s)[bodies]

            flat = ys.reshape(tt.size, nb, 2 * self.n)
            tt, flat, info["events"] = locate(event_list, tt, flat, flow, tuple(batch))
            ys = flat.reshape(tt.size, *batch, 2 * self.n)
        tb = tt.reshape(tt.size, *([1] * len(batch)))
        energy = self.energy(tb, ys, pmap)
        kinetic = self.kinetic(tb, ys, pmap)
        jacobi = None
        if self._system.time not in self._system._L.free_symbols:
            jacobi = self.jacobi(tb, ys, pmap)
        lam = None
        if self.n_constraints:
            lam = self.multipliers(tb, ys, pmap)
        return CoordinateTrajectory(
            t=tt,
            method=method,
            units=self._units(units),
            q=ys[..., : self.n],
            qdot=ys[..., self.n :],
            coordinates=self.coordinates,
            energy=energy,
            kinetic=kinetic,
            jacobi=jacobi,
            multipliers=lam,
            jacobi_conserved=self._system.jacobi_conserved,
            info=info,
        )


#: The result of :meth:`NumericLagrangian.simulate` (the name of earlier versions):
#: a :class:`poinsot.trajectory.CoordinateTrajectory`.
LagrangeTrajectory = CoordinateTrajectory
