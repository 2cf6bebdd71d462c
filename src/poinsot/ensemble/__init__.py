"""Monte-Carlo ensembles: dispersed rigid-body motions on Dask (``poinsot[ensemble]``).

``import poinsot`` does not import this package, Dask or pyarrow; they load when
an ensemble runs. See :func:`run`, :mod:`poinsot.ensemble.dispersion` (how inputs
are drawn) and :mod:`poinsot.ensemble.metrics` (what is recorded), and the docs
page ``docs/ensembles.md``.
"""

from .dispersion import (
    DISTRIBUTIONS,
    Choice,
    Dispersion,
    LogNormal,
    Normal,
    SmallRotation,
    TruncatedLogNormal,
    TruncatedNormal,
    Uniform,
    UniformRotation,
)
from .engine import (
    ORBIT_ELEMENTS,
    QUANTITIES,
    TORQUE_MODELS,
    EnsembleError,
    EnsembleInterrupted,
    EnsembleProblem,
    EnsembleResult,
    orbit_elements,
    run,
    run_chunk,
)
from .filters import FilterConsistency, filter_monte_carlo
from .metrics import COMPONENTS, METRICS, STATISTICS, Metric
from .scenario import load_ensemble, problem_from_scenario, run_scenario_ensemble

__all__ = [
    "run",
    "filter_monte_carlo",
    "FilterConsistency",
    "run_chunk",
    "EnsembleProblem",
    "EnsembleResult",
    "EnsembleError",
    "EnsembleInterrupted",
    "QUANTITIES",
    "TORQUE_MODELS",
    "ORBIT_ELEMENTS",
    "orbit_elements",
    "Metric",
    "METRICS",
    "COMPONENTS",
    "STATISTICS",
    "Dispersion",
    "Normal",
    "TruncatedNormal",
    "Uniform",
    "LogNormal",
    "TruncatedLogNormal",
    "Choice",
    "SmallRotation",
    "UniformRotation",
    "DISTRIBUTIONS",
    "load_ensemble",
    "problem_from_scenario",
    "run_scenario_ensemble",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
