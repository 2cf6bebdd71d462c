"""Exact solutions as a conformance suite for physics engines (docs/verify.md).

:func:`cases` gives named, versioned reference motions with their exact states
(free bodies, Lagrange and Kovalevskaya tops, a body under a constant torque, a
gyrostat, pitch libration in orbit, Kepler orbits, the Foucault pendulum, a thrown
spinning box in six degrees of freedom); an engine
(:mod:`poinsot.verify.engines`: SciPy, poinsot, MuJoCo, PyBullet, Drake, Basilisk, files) runs
them, and
:func:`evaluate` scores its states against the exact ones with stated thresholds.
:func:`export` writes the cases to files for engines in any language.

>>> from poinsot.verify import cases, engines, run
>>> res = run(engines.SciPyEngine(rtol=1e-12), cases("kepler-e0.95")[0])
>>> res.status
'pass'
"""

from __future__ import annotations

from . import engines
from .cases import CASES_VERSION, GROUPS, Case, cases, describe
from .engines import make, run
from .files import FileEngine, export
from .metrics import METRICS, CaseResult, evaluate

__all__ = [
    "CASES_VERSION",
    "GROUPS",
    "METRICS",
    "Case",
    "CaseResult",
    "FileEngine",
    "cases",
    "describe",
    "engines",
    "evaluate",
    "export",
    "make",
    "run",
]
