"""Bracketed root finding for the cubic of the Lagrange top (docs/theory.md §10).

:class:`poinsot.dynamics.LagrangeTop` finds the roots of its cubic ``P(u0 + x)``
(and of ``P`` written in ``y = 1 - u``) with these: Newton's method kept inside a
sign-changing bracket, brought to round-off (see the module docstring of
:mod:`poinsot.dynamics.lagrange_top`, "Roots to full precision").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

_EPS = float(np.finfo(float).eps)


def _rtsafe(
    f: Callable[[float], float], df: Callable[[float], float], lo: float, hi: float
) -> float:
    """A root of ``f`` in ``[lo, hi]`` with ``f(lo) f(hi) <= 0``: Newton kept in the bracket."""
    flo, fhi = f(lo), f(hi)
    if flo == 0.0:
        return lo
    if fhi == 0.0:
        return hi
    if flo > 0.0:  # orient so that f(lo) < 0 < f(hi)
        lo, hi = hi, lo
    x = 0.5 * (lo + hi)
    dx_old = abs(hi - lo)
    dx = dx_old
    fx, dfx = f(x), df(x)
    for _ in range(300):
        newton_ok = dfx != 0.0 and ((x - hi) * dfx - fx) * ((x - lo) * dfx - fx) < 0.0
        if not newton_ok or abs(2.0 * fx) > abs(dx_old * dfx):
            dx_old = dx
            dx = 0.5 * (hi - lo)
            x = lo + dx
        else:
            dx_old = dx
            dx = fx / dfx
            x = x - dx
        if abs(dx) <= 2.0 * _EPS * max(abs(x), 1e-300) or x in (lo, hi):
            break
        fx, dfx = f(x), df(x)
        if fx == 0.0:
            break
        if fx < 0.0:
            lo = x
        else:
            hi = x
    return float(x)


def _cubic(
    c3: float, c2: float, c1: float, c0: float
) -> tuple[Callable[[float], float], Callable[[float], float]]:
    def f(x: float) -> float:
        return ((c3 * x + c2) * x + c1) * x + c0

    def df(x: float) -> float:
        return (3.0 * c3 * x + 2.0 * c2) * x + c1

    return f, df


def _polish(
    f: Callable[[float], float], df: Callable[[float], float], x: float, lo: float, hi: float
) -> float:
    """Bracketed root near ``x`` in ``[lo, hi]`` (expanded until it brackets)."""
    if f(lo) * f(hi) > 0:
        return x
    return _rtsafe(f, df, lo, hi)
