"""Symbolic mechanics with SymPy (docs/theory.md §7, §11): Lagrange's equations of
the second kind, curvilinear coordinates, fast compiled right-hand sides, and a safe
parser for formulas read from files.

This subpackage is the only part of poinsot that imports SymPy (the ``symbolic``
extra); ``import poinsot`` never loads it. See ``docs/lagrange.md``.

>>> import sympy
>>> from poinsot.symbolic import LagrangeSystem
>>> from sympy.physics.mechanics import dynamicsymbols
>>> x = dynamicsymbols("x")
>>> m, k = sympy.symbols("m k", positive=True)
>>> osc = LagrangeSystem([x], m * x.diff() ** 2 / 2, k * x**2 / 2)
>>> osc.equations()[0]
Eq(k*x(t) + m*Derivative(x(t), (t, 2)), 0)
"""

from __future__ import annotations

from .analysis import (
    ConstraintKind,
    FirstIntegralCheck,
    constraint_kind,
    generalized_forces,
    is_first_integral,
    transform_generalized_forces,
)
from .curvilinear import CurvilinearCoordinates, curvilinear
from .lagrange import LagrangeSystem
from .numeric import SOLVERS, LagrangeTrajectory, NumericLagrangian
from .parser import (
    FUNCTIONS,
    MAX_DEPTH,
    MAX_EXPONENT,
    MAX_LENGTH,
    MAX_POWER_DIGITS,
    ExpressionError,
    parse_expression,
)

__all__ = [
    "LagrangeSystem",
    "generalized_forces",
    "transform_generalized_forces",
    "constraint_kind",
    "ConstraintKind",
    "is_first_integral",
    "FirstIntegralCheck",
    "NumericLagrangian",
    "LagrangeTrajectory",
    "SOLVERS",
    "curvilinear",
    "CurvilinearCoordinates",
    "parse_expression",
    "ExpressionError",
    "FUNCTIONS",
    "MAX_LENGTH",
    "MAX_DEPTH",
    "MAX_EXPONENT",
    "MAX_POWER_DIGITS",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
