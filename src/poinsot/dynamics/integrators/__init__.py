"""The integrators of Euler's equations with the attitude, one module per method
(theory §10).

:func:`poinsot.dynamics.simulate` checks its arguments, builds a :class:`RigidProblem`
and runs ``RIGID[method]``; each method is a :class:`RigidIntegrator` whose facts (order,
adaptive, the options it takes, what runs it) are its row of
:data:`poinsot.integrators.INTEGRATORS`. Adding a method is one module here and one row
there (``docs/adding-an-integrator.md``).

Examples
--------
>>> from poinsot.dynamics.integrators import RIGID
>>> sorted(RIGID)
['adaptive', 'dop853', 'midpoint', 'rk4', 'splitting']
>>> RIGID["rk4"].facts.order, RIGID["dop853"].facts.adaptive
(4, True)
"""

from __future__ import annotations

from ._common import COMPOSITIONS, RigidIntegrator, RigidProblem, RunOptions
from .adaptive import SOLVERS, Adaptive
from .dop853 import DOP853, FAILURE_REASONS
from .midpoint import Midpoint
from .rk4 import RK4
from .splitting import Splitting

__all__ = [
    "RIGID",
    "RigidProblem",
    "RunOptions",
    "RigidIntegrator",
    "COMPOSITIONS",
    "SOLVERS",
    "FAILURE_REASONS",
]

#: The integrators of Euler's equations, by name (``simulate(method=...)``).
RIGID: dict[str, RigidIntegrator] = {
    i.name: i for i in (Midpoint(), Splitting(), RK4(), DOP853(), Adaptive())
}
