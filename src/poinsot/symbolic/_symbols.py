"""Coordinates as SymPy objects: names, plain symbols and functions of time.

Internally every derivation differentiates with respect to plain symbols (fast and
unambiguous): a coordinate ``q`` is the symbol ``q``, its velocity ``u`` and its
acceleration ``a``; the results are handed back in terms of ``dynamicsymbols``
(``q(t)``, ``q'(t)``, ``q''(t)``), as ``sympy.physics.mechanics`` users expect.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from ..errors import InvalidInputError, InvalidTypeError

_GREEK = frozenset(
    "alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi omicron pi "
    "sigma tau upsilon phi chi psi omega varphi vartheta".split()
)
_LENGTHS = frozenset("x y z r s l d h rho".split())


def coordinate_unit(name: str) -> str:
    """SI unit of a generalized coordinate guessed from its name: a Greek letter
    (``theta1``, ``phi``) is an angle (``"rad"``); ``x``, ``y``, ``z``, ``r``, ``s``,
    ``l``, ``d``, ``h``, ``rho`` (with digits or ``_`` after) a length (``"m"``);
    else unknown (``""``). The default units of :meth:`NumericLagrangian.simulate` and
    of the ``lagrangian`` scenario kind (whose ``[lagrangian] units`` overrides it).

    Examples
    --------
    >>> [coordinate_unit(n) for n in ("theta1", "phi", "x", "rho", "z_2", "q")]
    ['rad', 'rad', 'm', 'm', 'm', '']
    """
    stem = name.rstrip("0123456789_").lower()
    if stem in _GREEK:
        return "rad"
    if stem in _LENGTHS:
        return "m"
    return ""


def default_time() -> Any:
    """SymPy's time symbol ``t`` used by :func:`sympy.physics.mechanics.dynamicsymbols`."""
    from sympy.physics.mechanics import dynamicsymbols

    return dynamicsymbols._t


@dataclass(frozen=True)
class Coordinates:
    """Generalized coordinates in three spellings.

    ``given`` as the user passed them (symbols or functions of time), ``funcs``
    ``q(t)``, ``plain`` the symbols ``q``, ``vel`` / ``acc`` plain symbols standing
    for ``q'`` and ``q''``; ``time`` the time symbol.
    """

    given: tuple[Any, ...]
    funcs: tuple[Any, ...]
    plain: tuple[Any, ...]
    vel: tuple[Any, ...]
    acc: tuple[Any, ...]
    time: Any

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(str(getattr(f, "func", f)) for f in self.funcs)

    @property
    def velocities(self) -> tuple[Any, ...]:
        """``q'(t)`` for each coordinate."""
        return tuple(f.diff(self.time) for f in self.funcs)

    @cached_property
    def _plain_sub(self) -> dict[Any, Any]:
        t = self.time
        sub = {}
        for f, p, v, a in zip(self.funcs, self.plain, self.vel, self.acc, strict=True):
            sub[f.diff(t, 2)] = a
            sub[f.diff(t)] = v
            sub[f] = p
        return sub

    def to_plain(self, expr: Any) -> Any:
        """``q(t), q'(t), q''(t)`` (and given plain symbols) -> plain symbols."""
        import sympy

        sub = self._plain_sub
        # one xreplace (exact node matches, top-down: a derivative is replaced before the
        # function inside it is reached) is much faster than subs on large expressions
        out = sympy.sympify(expr).xreplace(sub)
        if out.has(sympy.Derivative):  # derivatives spelt differently (unevaluated forms)
            derivs = {k: v for k, v in sub.items() if isinstance(k, sympy.Derivative)}
            out = sympy.sympify(expr).subs(derivs).xreplace(sub)
        return out

    def to_funcs(self, expr: Any) -> Any:
        """Plain symbols -> ``q(t), q'(t), q''(t)``."""
        import sympy

        t = self.time
        sub = {}
        for f, p, v, a in zip(self.funcs, self.plain, self.vel, self.acc, strict=True):
            sub[p] = f
            sub[v] = f.diff(t)
            sub[a] = f.diff(t, 2)
        return sympy.sympify(expr).xreplace(sub)

    def time_derivative(self, expr: Any) -> Any:
        """``d/dt`` of an expression in plain symbols (``q, u`` -> ``u, a``)."""
        out = expr.diff(self.time)
        for p, v, a in zip(self.plain, self.vel, self.acc, strict=True):
            out += expr.diff(p) * v + expr.diff(v) * a
        return out


def as_coordinates(coordinates: Any, time: Any = None, name: str = "coordinates") -> Coordinates:
    """Validate ``coordinates``: names, SymPy symbols or functions of ``time``."""
    import sympy
    from sympy.core.function import AppliedUndef

    t = default_time() if time is None else time
    if not isinstance(t, sympy.Symbol):
        raise InvalidTypeError(f"Expected `time` to be a SymPy Symbol, got {t!r}.")
    if isinstance(coordinates, str):
        coordinates = coordinates.replace(",", " ").split()
    if not isinstance(coordinates, Sequence) or isinstance(coordinates, sympy.Basic):
        coordinates = list(coordinates) if isinstance(coordinates, sympy.MatrixBase) else None
    if not coordinates:
        raise InvalidInputError(
            f"Expected `{name}` to be a non-empty sequence of names, SymPy symbols or "
            f"functions of time, got {coordinates!r}."
        )
    given, funcs, plain = [], [], []
    for c in coordinates:
        if isinstance(c, str):
            if not c.isidentifier() or c.startswith("_"):
                raise InvalidInputError(
                    f"Expected `{name}` names to be identifiers not starting with '_', got {c!r}."
                )
            funcs.append(sympy.Function(c)(t))
            plain.append(sympy.Symbol(c))  # expressions may use Symbol(c) or c(t)
            given.append(funcs[-1])
            continue
        if isinstance(c, AppliedUndef) and c.args == (t,):
            fname = c.func.__name__
            funcs.append(c)
            plain.append(sympy.Dummy(fname))
        elif isinstance(c, sympy.Symbol) and c != t:
            funcs.append(sympy.Function(c.name)(t))
            plain.append(c)
        else:
            raise InvalidTypeError(
                f"Expected each of `{name}` to be a name, a SymPy Symbol or a function of "
                f"{t} (dynamicsymbols), got {c!r}."
            )
        given.append(c)
    if len(set(funcs)) != len(funcs):
        raise InvalidInputError(f"Expected `{name}` to be distinct, got {given}.")
    vel = tuple(sympy.Dummy(f"{f.func.__name__}_dot") for f in funcs)
    acc = tuple(sympy.Dummy(f"{f.func.__name__}_ddot") for f in funcs)
    return Coordinates(tuple(given), tuple(funcs), tuple(plain), vel, acc, t)
