"""What the integrators of Euler's equations share (theory §10): the problem, the base
class, the right-hand side, the steps between output times, the compositions.

:class:`RigidProblem` is the flattened, checked problem :func:`poinsot.dynamics.simulate`
builds (N bodies, their inertia, initial attitude and angular velocity, output times,
step limit, torque); each method is a :class:`RigidIntegrator` (one module of this
package) whose facts are its row of :data:`poinsot.integrators.INTEGRATORS` and whose
:meth:`~RigidIntegrator.run` returns the sampled quaternions (n, N, 4), angular
velocities (n, N, 3) and ``info``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ... import _quat
from ..._jit import first_call
from ..._progress import _Report, run_compiled
from ..._typing import ArrayLike, FloatArray, IntArray
from ..._vec import all_diagonal3, diagonal3, inverse3
from ..._vec import cross as _cross
from ...errors import IntegrationError, InvalidInputError
from ...integrators import INTEGRATORS, Integrator
from ...mass.tensor import _momentum

__all__ = ["RigidProblem", "RunOptions", "RigidIntegrator", "COMPOSITIONS"]


class RigidProblem:
    """Euler's equations with the attitude for N bodies, flattened and checked.

    Attributes: ``q`` (N, 4) initial quaternions (body -> space, scalar first),
    ``omega0`` (N, 3) initial angular velocities (body axes, rad/s), ``t`` (n,) output
    times (s), ``h_max`` the longest step (s, ``inf``: one step per output interval),
    ``comp`` the composition coefficients of one step (``(1.0,)``: the plain step),
    ``moments`` (N, 3) principal moments or None, ``tensor`` (N, 3, 3) or None (the
    inertia in body axes, kg m^2, when not principal), ``principal``, ``diagonal``
    (every tensor diagonal), ``model`` the torque model (or None), ``m_const`` (N, 3) a
    constant body torque or None, ``tfn`` a torque evaluated from Python (or None),
    ``batch`` the caller's batch shape, ``report`` the progress reporter (or None).
    """

    def __init__(
        self,
        *,
        q: FloatArray,
        omega0: FloatArray,
        t: FloatArray,
        h_max: float,
        comp: Sequence[float],
        moments: FloatArray | None,
        tensor: FloatArray | None,
        principal: bool,
        diagonal: bool,
        model: Any,
        m_const: FloatArray | None,
        tfn: Any,
        batch: tuple[int, ...],
        report: _Report | None,
    ) -> None:
        self.q, self.omega0, self.t, self.h_max, self.comp = q, omega0, t, h_max, comp
        self.moments, self.tensor = moments, tensor
        self.principal, self.diagonal = principal, diagonal
        self.model, self.m_const, self.tfn = model, m_const, tfn
        self.batch, self.report = batch, report

    @classmethod
    def flatten(
        cls,
        j: FloatArray,
        principal: bool,
        q0: FloatArray,
        omega0: FloatArray,
        t: FloatArray,
        batch: tuple[int, ...],
        *,
        h_max: float,
        comp: Sequence[float],
        model: Any,
        m_const: FloatArray | None,
        torque_fn: Any,
        method: str,
        report: _Report | None,
    ) -> RigidProblem:
        """The problem of checked arguments broadcast to ``batch``, flattened to N bodies
        (the kernels take (N, 3), (N, 4), (N, 3, 3)): ``j`` principal moments (...,
        3) when ``principal``, else tensors (..., 3, 3); ``torque_fn`` a torque model
        evaluated from Python (called by ``method``'s steps), or None."""
        n_body = math.prod(batch)
        q = np.ascontiguousarray(np.broadcast_to(q0, batch + (4,)).reshape(n_body, 4))
        w = np.ascontiguousarray(np.broadcast_to(omega0, batch + (3,)).reshape(n_body, 3))
        moments: FloatArray | None = None
        tensor: FloatArray | None = None
        if principal:
            # principal moments (N, 3) (the usual batch): the diagonal forms of the kernels
            # and of the invariants; the compiled DOP853 packs its own tensors
            moments = np.ascontiguousarray(np.broadcast_to(j, batch + (3,)).reshape(n_body, 3))
            diagonal = True
        else:
            if j.shape[:-2] == batch:
                tensor = j.reshape(-1, 3, 3)
            else:
                full = np.broadcast_to(j, batch + (3, 3)).reshape(n_body, 3, 3)
                tensor = np.ascontiguousarray(full)
            diagonal = all_diagonal3(tensor)
            if diagonal:
                moments = np.diagonal(tensor, axis1=-2, axis2=-1)
        mc = None
        if m_const is not None:
            mc = np.ascontiguousarray(np.broadcast_to(m_const, batch + (3,)).reshape(n_body, 3))
        tfn = None if torque_fn is None else _TorqueCall(torque_fn, batch, method)
        return cls(
            q=q, omega0=w, t=t, h_max=h_max, comp=comp, moments=moments, tensor=tensor,
            principal=principal, diagonal=diagonal, model=model, m_const=mc, tfn=tfn,
            batch=batch, report=report,
        )  # fmt: skip

    @cached_property
    def j(self) -> FloatArray:
        """The inertia tensors (N, 3, 3) in body axes (diagonal from principal moments)."""
        if self.principal and self.moments is not None:
            return diagonal3(self.moments)
        assert self.tensor is not None
        return self.tensor

    @cached_property
    def j_inv(self) -> FloatArray:
        """Their inverses (N, 3, 3)."""
        return inverse3(self.j, self.diagonal)


@dataclass(frozen=True)
class RunOptions:
    """The options of a run beyond the problem (``None``: not given); which a method
    takes is its row's ``options`` in :data:`poinsot.integrators.INTEGRATORS`."""

    order: int = 2
    rtol: float = 1e-10
    atol: float = 1e-12
    solver: str = "DOP853"
    failures: str = "raise"


class RigidIntegrator:
    """One method of :func:`poinsot.dynamics.simulate`. A subclass sets ``name`` (its
    row of :data:`poinsot.integrators.INTEGRATORS`: order, adaptive, options...) and
    implements :meth:`run`; ``docs/adding-an-integrator.md`` says how to add one."""

    name: str = ""

    @property
    def facts(self) -> Integrator:
        """The method's row of :data:`poinsot.integrators.INTEGRATORS`."""
        return INTEGRATORS[self.name]

    def run(self, p: RigidProblem, o: RunOptions) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
        """``(q (n, N, 4), omega (n, N, 3), info)`` at the output times ``p.t``."""
        raise NotImplementedError

    def unit_output(self, info: dict[str, Any]) -> bool:
        """Whether the run returned unit quaternions and arrays the result may own."""
        return False

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"


_qmul = _quat.mul
_qrot = _quat.rotate
_pure = _quat.pure
_normalize = _quat.normalize
_cayley_quat = _quat.from_gibbs
_rotvec_quat = _quat.from_rotvec
_axis_quat = _quat.axis_angle_principal


def _rhs(
    j: np.ndarray,
    j_inv: Any,  # (..., 3, 3); None when `principal`
    w: np.ndarray,
    torque: np.ndarray | None,
    principal: bool = False,
) -> np.ndarray:
    """Euler's right-hand side ``w' = J^-1 (M - w x J w)``: the one implementation.

    ``j`` principal moments (..., 3) when ``principal`` (then ``j_inv`` is
    unused) or a tensor (..., 3, 3) with its inverse ``j_inv``; ``torque`` (..., 3)
    in body axes or ``None``. The compiled steppers of :mod:`._euler_numba` use the
    scalar form of the same formula from :mod:`poinsot._numba_helpers`.
    """
    rhs = -_cross(w, _momentum(j, principal, w))
    if torque is not None:
        rhs = rhs + torque
    if principal:
        return rhs / j
    return np.einsum("...ij,...j->...i", j_inv, rhs)


class _TorqueCall:
    """Evaluates a :class:`~poinsot.dynamics.TorqueModel` on a flattened batch."""

    def __init__(self, model: Any, batch: tuple[int, ...], method: str) -> None:
        self.model = model
        self.method = method
        self.batch = batch
        self.n = math.prod(batch)
        self.calls = 0

    def __call__(self, t: float, q: FloatArray, w: FloatArray) -> FloatArray:
        """``q`` (N, 4), ``w`` (N, 3) -> torque (N, 3) in body axes."""
        self.calls += 1
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(w))) or np.any(
            np.einsum("...i,...i->...", q, q) == 0.0
        ):
            raise IntegrationError(
                f"{self.method} integration diverged: the state became non-finite at "
                f"t = {float(t):.6g} (at or after the last finite output time). The problem "
                f"may be stiff or the step too long: reduce `max_step` or use "
                f"method='adaptive'."
            )
        qb = np.asarray(q).reshape(self.batch + (4,))
        wb = np.array(w).reshape(self.batch + (3,))
        m = np.asarray(self.model.body_torque(float(t), qb, wb), dtype=float)
        if m.shape not in (self.batch + (3,), (3,)):
            raise InvalidInputError(
                f"Expected `torque` to return shape {self.batch + (3,)} (body axes) or (3,), "
                f"got {m.shape}."
            )
        if not np.all(np.isfinite(m)):
            raise IntegrationError(
                f"The torque became non-finite at t = {float(t):.6g}: `torque` returned NaN/inf."
            )
        return np.broadcast_to(m.reshape(-1, 3), (self.n, 3))


def _substeps(t: np.ndarray, max_step: float) -> np.ndarray:
    dt = np.diff(t)
    if math.isinf(max_step):
        return np.ones(dt.shape, dtype=np.int64)
    # a step longer than max_step by round-off (1e-12 relative) is accepted
    return np.maximum(1, np.ceil(dt / max_step * (1.0 - 1e-12))).astype(np.int64)


def _fail_nonfinite(method: str, t_reached: float, what: str) -> IntegrationError:
    return IntegrationError(
        f"{method} integration diverged: {what} became non-finite after t = {t_reached:.6g} "
        f"(the last finite output time). The problem may be stiff or the step too long: "
        f"reduce `max_step` or use method='adaptive'."
    )


def _run_kernel(
    kernel: Callable[..., Any],
    args: tuple[Any, ...],
    q: FloatArray,
    t: FloatArray,
    nsub: IntArray,
    report: _Report | None,
    *extra: Any,
) -> Any:
    """A compiled fixed-step kernel of :mod:`._euler_numba` through
    :func:`poinsot._progress.run_compiled`: progress, and Ctrl-C within one step."""

    cancel = np.zeros(1, dtype=np.int64)
    done = np.zeros(1, dtype=np.int64)
    n_body, n_int = q.shape[0], t.shape[0] - 1
    # a first call on a cold cache runs in the interpreter when that is quicker than
    # compiling (poinsot._jit.first_call: ~0.5 ms a step and body, taken high)
    kernel = first_call(kernel, n_body * float(np.sum(nsub)) * 1e-3)
    return run_compiled(
        kernel,
        (*args, cancel, done, *extra),
        cancel=cancel,
        done=done,
        total=max(n_body * n_int, 1),
        progress=report,
        background=n_body * int(np.sum(nsub)) > 20_000,
    )


def _fixed_step_info(
    t: FloatArray, nsub: IntArray, comp: Sequence[float] = (1.0,)
) -> dict[str, Any]:
    h = np.diff(t) / nsub if t.size > 1 else np.zeros(0)
    return {
        "steps": int(nsub.sum()),
        "stages_per_step": len(comp),
        "step_size": float(h.max()) if h.size else 0.0,
        "min_step_size": float(h.min()) if h.size else 0.0,
    }


# Symmetric compositions of a symmetric 2nd-order step: orders 4 (the triple
# jump, Yoshida 1990; Suzuki 1990) and 6 (Yoshida 1990, solution A).
_CBRT2 = 2.0 ** (1.0 / 3.0)


_Y6 = (0.784513610477560, 0.235573213359357, -1.17767998417887)


COMPOSITIONS = {
    2: (1.0,),
    4: (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2)),
    6: (*_Y6, 1.0 - 2.0 * sum(_Y6), *_Y6[::-1]),
}


def _stages(
    t: FloatArray, nsub: IntArray, comp: Sequence[float]
) -> Iterator[tuple[int, float, float, bool]]:
    """Yield ``(k, t_start, h, last)`` for every stage of every step in output interval
    ``k``; ``last`` marks the stage that ends the interval."""
    nc = len(comp)
    for k in range(t.shape[0] - 1):
        hk = (t[k + 1] - t[k]) / nsub[k]
        for s in range(nsub[k]):
            tn = float(t[k]) + s * hk
            for j, c in enumerate(comp):
                yield k, tn, hk * c, (s == nsub[k] - 1 and j == nc - 1)
                tn += hk * c


def _kernel_args(
    q: ArrayLike,
    m: ArrayLike,
    inertia: ArrayLike,
    torque: ArrayLike,
    t: ArrayLike,
    nsub: ArrayLike,
    comp: Sequence[float],
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, Any, FloatArray]:
    """Contiguous float64 (int64 for ``nsub``) arrays in the order the compiled
    steppers of :mod:`._euler_numba` take them."""
    c = np.ascontiguousarray
    return (
        c(q, dtype=float),
        c(m, dtype=float),
        c(inertia, dtype=float),
        c(torque, dtype=float),
        c(t, dtype=float),
        c(nsub, dtype=np.int64),
        c(comp, dtype=float),
    )


def batch_rhs(p: RigidProblem, bodies: IntArray | None = None) -> Callable[..., FloatArray]:
    """The right-hand side ``(t, Y (N, 7)) -> Y'`` of the bodies ``bodies`` (all: None)
    of the problem, ``Y = (q, w)`` with ``q' = q o (0, w) / 2`` and Euler's ``w'`` (the
    adaptive method and the events' dense re-integration). A torque evaluated from
    Python is a function of the whole batch: then ``bodies`` must be None."""
    j, j_inv, m_const, tfn = p.j, p.j_inv, p.m_const, p.tfn
    if bodies is not None:
        assert tfn is None
        j, j_inv = j[bodies], j_inv[bodies]
        m_const = None if m_const is None else m_const[bodies]

    def fun(tn: float, y: FloatArray) -> FloatArray:
        qq, ww = y[:, :4], y[:, 4:]
        mt = _torque_value(m_const, tfn, tn, qq, ww)
        dq = 0.5 * _qmul(qq, _pure(ww))
        return np.concatenate([dq, _rhs(j, j_inv, ww, mt)], axis=1)

    return fun


def _torque_value(m_const: Any, tfn: Any, tn: float, q: FloatArray, w: FloatArray) -> Any:
    if tfn is not None:
        return tfn(tn, q, w)
    return m_const
