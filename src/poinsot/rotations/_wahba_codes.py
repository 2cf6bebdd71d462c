"""The constants of :mod:`poinsot.rotations._wahba` (tolerances, method codes and status
bits), apart from its formulas: :mod:`poinsot.rotations.determination` reads them at
import, while the formula source (which binds the compiled executor's names, and so
numba) is imported only when a set is solved."""

#: Observations count as parallel when ``det(sum w_i (E - u_i u_i^T)) <= 1e-12 lambda0^3``.
PARALLEL_RTOL = 1e-12
#: QUEST rotates the reference frame when the solved ``|l0|`` is below this.
QUEST_ROTATION_THRESHOLD = 0.3
#: Newton's iterations on the characteristic polynomial stop at this step (lambda0 = 1).
NEWTON_TOL = 1e-15
NEWTON_MAX = 50
#: ... of which the batch loops take this many on every set of a block at once (no
#: branch); a set whose iteration has not stopped by then is solved again on its own.
NEWTON_FAST = 5
#: ``|v|^2`` of an observation normalised as it is (``_wahba.unit``): squares of
#: normal numbers, no overflow; outside, ``v`` is first scaled by ``UNIT_UP`` (below
#: ``UNIT_MIN``) or ``UNIT_DOWN`` (above ``UNIT_MAX``), powers of two.
UNIT_MIN = 1e-290
UNIT_MAX = 1e290
UNIT_UP = 2.0**600
UNIT_DOWN = 2.0**-600

#: ``method`` codes of :func:`solve`
QUEST = 0
ESOQ2 = 1

#: Status bits of :func:`solve` (0: solved), in the order the errors are raised.
NONFINITE_OBSERVED = 1
NONFINITE_REFERENCE = 2
ZERO_OBSERVED = 4
ZERO_REFERENCE = 8
PARALLEL_OBSERVED = 16
PARALLEL_REFERENCE = 32
