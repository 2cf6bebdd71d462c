"""Euler's dynamic equations and structure-preserving integrators (theory §10).

The rotational motion of a rigid body about its centre of mass (or a fixed
point) is governed by Euler's dynamic equations, written in body axes,

``dK/dt + w x K = M``,  ``K = J w``,

closed by Poisson's kinematic equation for the attitude quaternion
``L' = 1/2 L o w`` (theory §5). :func:`euler_rhs` evaluates ``w'``;
:func:`simulate` integrates the attitude and the angular velocity together, for
one body or a batch of bodies, with a choice of methods:

``"midpoint"`` (default)
    Implicit midpoint rule on the body angular momentum ``m = J w`` (a
    Lie-Poisson integrator) with the attitude advanced by the Cayley map of the
    midpoint angular velocity. Second order. For the free body it keeps the
    energy, ``|K|`` and the space angular momentum vector to round-off.
``"splitting"``
    Lie-Poisson splitting of the free-body Hamiltonian into exactly
    integrable rotations (Touma & Wisdom 1994, McLachlan 1993, Reich 1994, in
    the form of Dullweber, Leimkuhler & McLachlan 1997), composed
    symmetrically. Second order; keeps ``|K|`` and the space vector ``K`` to
    round-off and the energy bounded (no drift); exact for a symmetric body.
``"rk4"``
    Classical explicit Runge-Kutta of order 4 on ``(L, w)`` with the quaternion
    renormalised after each step. Conserves nothing exactly. With no torque or a
    built-in one (constant in body or space axes, gravity about a fixed point,
    gravity gradient) it runs in one compiled loop per body (``info["path"] ==
    "compiled"``, bodies on numba's threads); a Python torque takes the NumPy
    stages, one batch step at a time.
``"adaptive"``
    :func:`scipy.integrate.solve_ivp` (``DOP853`` by default) on ``(L, w)``,
    the quaternion renormalised at the outputs: the reference.
``"dop853"``
    poinsot's own compiled DOP853 (order 8, Hairer's coefficients): one fused
    numba loop per body with its own step size and error control, torques of
    :mod:`poinsot.dynamics.torques` (constant body/space, gravity about a fixed
    point, gravity gradient) evaluated inside the loop, 7th-order dense output
    at the output times (no step is shortened to hit them), the quaternion
    projected onto ``|q| = 1`` after every step (a projection onto an invariant
    of the exact flow, which keeps order 8). Batches run on the idle cores, as
    large rotation batches do (:func:`poinsot.rotations.set_num_threads`: on a busy
    machine a thread that waits for a core costs more than it saves); results are
    bit-identical for any thread count.
    The fastest route to a given accuracy; chosen by default when ``rtol`` or
    ``atol`` is given. A torque given as a Python callable takes the slower
    vectorised ``solve_ivp`` path (``info["path"]`` says so).

Both symmetric methods can be composed to order 4 or 6 (``order=``) with
the same invariants. Compiled (numba) kernels step the free body and constant
torques; a torque given as a Python function is stepped with NumPy,
vectorised over the batch.

**Convention:** ``rotation`` maps body to space components (``v_s = R v_b``);
``omega`` and ``torque`` are in body axes (rad/s, N m); the angular momentum
returned is the space vector ``K_s = R J w``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _quat, integrators
from .._progress import _Report, as_progress
from .._scratch import hold
from .._typing import ArrayLike, FloatArray, IntArray
from .._validate import (
    as_choice,
    as_float_array,
    as_int,
    as_rotation_quat,
    as_times,
    as_vec3,
    batch_shape,
    plain_vec3,
)
from .._vec import all_diagonal3, diagonal3, inverse3
from .._vec import cross as _cross
from .._vec import hat as _hat
from ..errors import IntegrationError, InvalidInputError
from ..mass.tensor import _momentum, single_principal_moments
from ..rotations.rotation import Rotation

if TYPE_CHECKING:
    from ..mass.body import RigidBody
    from .torques import TorqueModel
from ..trajectory import Trajectory
from .invariants import _kinetic_space
from .torques import ConstantBodyTorque, GravityTorque, as_torque

__all__ = ["euler_rhs", "simulate", "METHODS"]

#: Names accepted by ``simulate(method=...)``.
#: The integrators of Euler's equations (from :data:`poinsot.integrators.INTEGRATORS`).
METHODS = integrators.names("rigid")

_EPS = np.finfo(float).eps
_MAXIT = 100


# ---------------------------------------------------------------------------
# Inertia
# ---------------------------------------------------------------------------


def _as_inertia(inertia: object, name: str) -> tuple[np.ndarray, bool]:
    from ..mass.tensor import as_inertia

    return as_inertia(inertia, name)


def _body_inertia(body: Any) -> tuple[np.ndarray, bool]:
    """The body-axes inertia of ``body`` (RigidBody or array): ``(moments (..., 3), True)``
    for principal moments, else ``(tensor (..., 3, 3), False)``."""
    if hasattr(body, "inertia") and hasattr(body, "mass"):
        mass = np.asarray(body.mass, dtype=float)
        if not np.all(np.isfinite(mass)) or np.any(mass <= 0):
            raise InvalidInputError(
                f"Expected `body.mass` to be positive and finite, got {body.mass!r}."
            )
        inertia = body.inertia
        name = "body.inertia"
    else:
        inertia = body
        name = "body"
    return _as_inertia(inertia, name)


# ---------------------------------------------------------------------------
# Kernels (no validation)
# ---------------------------------------------------------------------------


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


_qmul = _quat.mul
_qrot = _quat.rotate
_pure = _quat.pure
_normalize = _quat.normalize
_cayley_quat = _quat.from_gibbs
_rotvec_quat = _quat.from_rotvec
_axis_quat = _quat.axis_angle_principal


# ---------------------------------------------------------------------------
# Public: Euler's equations
# ---------------------------------------------------------------------------


def _euler_rhs_single(inertia: object, omega: object, torque: object) -> np.ndarray | None:
    """Short path of :func:`euler_rhs` for one state given by principal moments.

    Same checks as the general path (finite numbers, positive moments with
    ``A + B >= C`` within the same tolerance) and the same floating-point
    operations, so the result is bit-identical; anything else (a batch, a
    tensor, a bad value or type) returns ``None`` and goes the general way,
    which raises the documented error.
    """
    j = single_principal_moments(inertia)
    if j is None:
        return None
    w = plain_vec3(omega)
    if w is None:
        return None
    a, b, c = j
    p, q, r = w
    k0, k1, k2 = a * p, b * q, c * r
    # -(w x K), as _vec.cross computes w x K
    f0 = -(q * k2 - r * k1)
    f1 = -(r * k0 - p * k2)
    f2 = -(p * k1 - q * k0)
    if torque is not None:
        m = plain_vec3(torque)
        if m is None:
            return None
        f0, f1, f2 = f0 + m[0], f1 + m[1], f2 + m[2]
    return np.array((f0 / a, f1 / b, f2 / c))


def euler_rhs(inertia: ArrayLike, omega: ArrayLike, torque: ArrayLike | None = None) -> FloatArray:
    """Angular acceleration from Euler's dynamic equations, ``J w' = M - w x J w``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3)
        Principal moments ``(A, B, C)`` (``omega`` then in principal axes) or the
        inertia tensor in body axes. An array whose last two dimensions are
        ``(3, 3)`` is read as a tensor; pass a batch of three bodies' principal
        moments as tensors (``moments[..., None] * np.eye(3)``).
    omega : array_like, shape (..., 3)
        Angular velocity in body axes (rad/s).
    torque : array_like, shape (..., 3), optional
        External torque about the centre of mass in body axes. Default zero.

    Returns
    -------
    ndarray, shape (..., 3)
        ``w' = dw/dt`` in body axes (rad/s^2); leading shapes broadcast.

    Raises
    ------
    InvalidInputError
        If ``inertia`` is not physical (not symmetric positive definite, or
        violating ``A + B >= C``) or a shape is wrong.

    Notes
    -----
    theory §10: ``dK/dt + w x K = M`` with ``K = J w``; in principal axes

    ``A p' + (C - B) q r = M1``, ``B q' + (A - C) r p = M2``,
    ``C r' + (B - A) p q = M3``.

    **Convention:** body axes throughout; SI units (kg m^2, rad/s, N m).

    Examples
    --------
    >>> from poinsot.dynamics import euler_rhs
    >>> euler_rhs([1.0, 2.0, 3.0], [1.0, 1.0, 1.0])   # (B - C) q r / A ...
    array([-1.        ,  1.        , -0.33333333])
    >>> euler_rhs([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], torque=[0.0, 0.0, 3.0])
    array([0., 0., 1.])
    """
    fast = _euler_rhs_single(inertia, omega, torque)
    if fast is not None:
        return fast
    j, principal = _as_inertia(inertia, "inertia")
    w = as_vec3(omega, "omega")
    m = None if torque is None else as_vec3(torque, "torque")
    shapes = {"inertia": (j, 1 if principal else 2), "omega": (w, 1)}
    if m is not None:
        shapes["torque"] = (m, 1)
    batch_shape(**shapes)
    return _rhs(j, None if principal else inverse3(j), w, m, principal)


# ---------------------------------------------------------------------------
# Public: simulate
# ---------------------------------------------------------------------------


#: ``scipy.integrate.solve_ivp`` methods accepted by ``simulate(..., method="adaptive")``.
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _tolerances(rtol: ArrayLike, atol: ArrayLike) -> tuple[float, float]:
    """``rtol > 0`` and ``atol >= 0`` as floats (scalars; solve_ivp's own floor still applies)."""
    out = []
    for name, x, strict in (("rtol", rtol, True), ("atol", atol, False)):
        a = as_float_array(x, name)
        if a.ndim != 0 or not (a > 0 if strict else a >= 0):
            word = "positive" if strict else "non-negative"
            raise InvalidInputError(f"Expected `{name}` to be a {word} scalar, got {x!r}.")
        out.append(float(a))
    return out[0], out[1]


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


def simulate(
    body: RigidBody | ArrayLike,
    rotation0: Rotation | ArrayLike,
    omega0: ArrayLike,
    t: ArrayLike,
    *,
    torque: TorqueModel | ArrayLike | Callable[..., ArrayLike] | None = None,
    method: str | None = None,
    max_step: float | None = None,
    order: int | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    solver: str | None = None,
    failures: str = "raise",
    progress: bool | Callable[[float], object] | None = None,
) -> Trajectory:
    """Integrate Euler's dynamic equations with the attitude (theory §10, §5).

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3) or (..., 3, 3)
        A :class:`poinsot.mass.RigidBody` (its inertia about the centre of mass,
        in body axes, is used), an inertia tensor in body axes, or principal
        moments ``(A, B, C)`` (then body axes are principal axes). A leading
        shape makes a batch of bodies.
    rotation0 : Rotation or array_like, shape (..., 4)
        Initial attitude, body -> space: a :class:`poinsot.Rotation` or
        scalar-first quaternions.
    omega0 : array_like, shape (..., 3)
        Initial angular velocity in body axes (rad/s).
    t : array_like, shape (n,)
        Output times, strictly increasing; the motion starts at ``t[0]``.
    torque : None, TorqueModel, array_like (..., 3) or callable, optional
        External torque about the centre of mass (or the fixed point), in
        **body** axes: ``None`` (free body); a
        :class:`~poinsot.dynamics.TorqueModel` (``GravityTorque``,
        ``ConstantSpaceTorque``, ``ConstantBodyTorque``, ``CallableTorque``...);
        a constant body vector; or a function ``torque(t, rotation, omega) ->
        (..., 3)`` of the time (float), the attitude (a
        :class:`~poinsot.Rotation` with the batch shape) and the body angular
        velocity (batch shape + ``(3,)``), returning body components with the
        batch shape (or ``(3,)``). See :func:`~poinsot.dynamics.as_torque`.
    method : {"midpoint", "splitting", "rk4", "adaptive", "dop853"}, optional
        Integrator (see the module docs). Default: ``"dop853"`` when ``rtol``
        or ``atol`` is given (an accuracy is asked for), else ``"midpoint"``
        (invariants to round-off).
    max_step : float, optional
        Longest step. The fixed-step methods take, in each output interval,
        the fewest equal steps no longer than ``max_step`` (one step per
        interval if ``None``: steps are never longer than the output
        spacing). Passed to ``solve_ivp`` for ``"adaptive"``.
    order : {2, 4, 6}, optional
        For ``"midpoint"`` and ``"splitting"``: compose the symmetric
        second-order step into a method of order 4 (3 stages, the "triple
        jump") or 6 (7 stages, Yoshida 1990). The invariants are kept exactly
        as by the basic step. Default 2.
    rtol, atol : float, optional
        Tolerances of ``"adaptive"`` and ``"dop853"`` (defaults ``1e-10``,
        ``1e-12``): the local error of each step, per body, is kept below
        ``atol + rtol |y|`` componentwise (RMS over the 7 components). With
        ``atol=0`` a component that is exactly 0 (the identity's vector part, a
        zero rate) allows no error at all, and ``"dop853"`` raises
        :class:`~poinsot.IntegrationError` naming ``atol``. The
        fixed-step methods have none: passing ``rtol``/``atol`` (or ``solver``)
        with them raises :class:`~poinsot.InvalidInputError` instead of being
        ignored.
    solver : str, optional
        ``solve_ivp`` method for ``"adaptive"`` (default ``"DOP853"``).
    failures : {"raise", "mark"}, optional
        What a body of a ``"dop853"`` batch that fails (step below round-off,
        more than 10^6 steps, a non-finite state) does: ``"raise"`` (default) an
        :class:`~poinsot.IntegrationError` for the whole call; ``"mark"`` (for
        Monte-Carlo ensembles, where a few diverging samples are data) keeps the
        others, holds the failed body at its last finite state from the time it
        failed on, and names the reason in ``info["failed"]`` (an array of
        strings, one per body, ``""`` for a body that succeeded).
    progress : bool or callable, optional
        ``True``: a progress bar (tqdm in terminals and notebooks when installed,
        else a line on stderr every 10 %); a callable: called with the fraction
        done in ``[0, 1]`` (about every 0.1 s); default None: nothing. The
        compiled ``"dop853"`` and ``"rk4"`` runs report as they go and stop within
        one step of Ctrl-C (``KeyboardInterrupt``, nothing partial returned, no
        thread left running); the other methods report when done.

    Returns
    -------
    Trajectory
        ``t`` (n,), ``rotation`` (n, ...), ``omega`` (n, ..., 3) in body axes,
        ``energy`` ``T = w.J w / 2`` (n, ...), ``momentum`` ``K_s = R J w``
        (n, ..., 3) in space axes, ``method`` and ``info`` (keys of
        :data:`poinsot.trajectory.INFO_KEYS`: ``steps`` per body, ``step_size``
        the longest step, ``order``...; ``rtol``, ``atol``, ``solver``,
        ``evaluations`` for ``"adaptive"``). The invariants'
        drifts are ``energy_drift``, ``momentum_drift``,
        ``momentum_vector_drift``.

    Raises
    ------
    InvalidInputError
        Non-physical inertia, non-positive mass, non-finite state, bad shapes,
        a torque function returning the wrong shape, an unknown method.
    IntegrationError
        If the state becomes non-finite (a stiff or diverging problem) or the
        implicit step does not converge; the message gives the time reached.

    Notes
    -----
    Midpoint step of length ``h`` (``W = J^-1``, body momentum ``m = J w``):
    solve ``m* = m_n + h/2 (m* x W m* + M*)`` by Newton's method to round-off,
    with ``w* = W m*``, ``a = h w*/2`` (the Gibbs vector of the step) and the
    torque at the midpoint ``M* = M(t_n + h/2, L*, w*)``, ``L* = L_n o (1, b) /
    sqrt(1 + b.b)`` with ``b = a / (1 + sqrt(1 + a.a))`` (half of the step's
    rotation, which keeps the scheme symmetric); then

    ``L_n+1 = L_n o (1, a)/sqrt(1 + a.a)``,
    ``m_n+1 = (E + a^)^-1 ((E - a^) m_n + h M*)``,

    which equals ``2 m* - m_n``. For ``M = 0`` the momentum update is an exact
    rotation, ``m_n+1 = cay(-a)^ m_n`` while ``L_n+1 = L_n o cay(a)``, so
    ``|K|`` and the space vector ``L m L~`` are kept to round-off; the energy,
    a quadratic invariant, is kept by the midpoint rule itself. With a torque
    the scheme stays symmetric and second order; the Newton iteration then
    treats the torque's dependence on the state by fixed point (it must be
    contracting: ``h |dM/dw| / 2 < |J|`` roughly), otherwise an
    :class:`~poinsot.IntegrationError` asks for a smaller ``max_step``.

    What runs: ``"midpoint"``, ``"rk4"`` and ``"dop853"`` run compiled (one loop per
    body, no Python per step) with no torque or a built-in torque model
    (:mod:`poinsot.dynamics.torques`); a torque given as a Python function must be
    called from Python at every step (or Newton iteration), so these methods then
    take NumPy steps vectorised over the batch (``info["path"]`` says so).
    ``"splitting"`` runs compiled with no torque, a constant body torque or
    gravity about a fixed point (its exact kicks); its kicks for other torques are
    NumPy steps over the batch (the kick of a general torque has no compiled flow
    yet). ``"adaptive"`` is SciPy's ``solve_ivp``.

    Orders: midpoint 2 (4 or 6 with ``order``), splitting 2 (4 or 6 with
    ``order``; with a torque that depends on ``omega`` the half kicks are
    explicit and the order drops to 1), rk4 4, adaptive as set by
    ``rtol``/``atol``. The splitting sub-flows are given in the docs page
    ``docs/dynamics.md``.

    **Convention:** body -> space attitude; ``omega``, ``torque`` in body axes;
    ``momentum`` in space axes; SI units.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import simulate
    >>> tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1],
    ...               np.linspace(0.0, 10.0, 101), max_step=1e-3)
    >>> tr.omega.shape, tr.quat.shape
    ((101, 3), (101, 4))
    >>> bool(tr.energy_drift < 1e-13), bool(tr.momentum_vector_drift < 1e-13)
    (True, True)
    """
    if method is None:
        # an accuracy asked for picks the compiled adaptive integrator
        method = "dop853" if (rtol is not None or atol is not None) else "midpoint"
    method = integrators.check_method(method, METHODS, "a rigid body")
    failures = as_choice(failures, "failures", ("raise", "mark"))
    if failures == "mark" and method != "dop853":
        raise InvalidInputError(
            f"`failures='mark'` applies to method='dop853' (the compiled batch integrator), "
            f"got method={method!r}."
        )
    j, principal = _body_inertia(body)
    q0 = as_rotation_quat(rotation0, "rotation0")
    omega0 = as_vec3(omega0, "omega0")
    tt = as_times(t, "t")
    named = {"body": (j, 1 if principal else 2), "rotation0": (q0, 1), "omega0": (omega0, 1)}
    model = as_torque(torque)
    torque_fn = None
    m_const = None
    if isinstance(model, ConstantBodyTorque):
        m_const = model.torque
        named["torque"] = (m_const, 1)
    elif model is not None:
        torque_fn = model
    batch = batch_shape(**named)
    if max_step is None:
        h_max = math.inf
    else:
        h_arr = as_float_array(max_step, "max_step")
        if h_arr.ndim != 0:
            raise InvalidInputError(f"Expected `max_step` to be a scalar, got shape {h_arr.shape}.")
        h_max = float(h_arr)
        if not h_max > 0:
            raise InvalidInputError(f"Expected `max_step` to be positive, got {max_step!r}.")
    n_body = math.prod(batch)
    # refusals from the methods' facts (integrators.INTEGRATORS[...].options)
    integrators.check_options(
        method, {"order": order, "rtol": rtol, "atol": atol, "solver": solver}, METHODS
    )
    rtol, atol = _tolerances(1e-10 if rtol is None else rtol, 1e-12 if atol is None else atol)
    solver = as_choice("DOP853" if solver is None else solver, "solver", SOLVERS)
    if order is None:
        order = 2
    comp = COMPOSITIONS[as_int(order, "order", choices=tuple(COMPOSITIONS))]
    report = as_progress(progress, "simulate")

    # flatten the batch to N bodies
    q = np.ascontiguousarray(np.broadcast_to(q0, batch + (4,)).reshape(n_body, 4))
    # the batch flattened to N bodies (the kernels take (N, 3))
    omega0_n = np.ascontiguousarray(np.broadcast_to(omega0, batch + (3,)).reshape(n_body, 3))
    moments: FloatArray | None = None
    if principal:
        # principal moments (N, 3) (the usual batch): the diagonal forms of the kernels and
        # of the invariants; the compiled DOP853 packs its own tensors, without a temporary
        moments = np.ascontiguousarray(np.broadcast_to(j, batch + (3,)).reshape(n_body, 3))
        jb = np.empty((0, 3, 3)) if method == "dop853" else diagonal3(moments)
        diagonal = True
    else:
        if j.shape[:-2] == batch:
            jb = j.reshape(-1, 3, 3)
        else:
            jb = np.ascontiguousarray(np.broadcast_to(j, batch + (3, 3)).reshape(n_body, 3, 3))
        diagonal = all_diagonal3(jb)
        if diagonal:
            moments = np.diagonal(jb, axis1=-2, axis2=-1)
    tfn = None if torque_fn is None else _TorqueCall(torque_fn, batch, method)
    mc = None
    if m_const is not None:
        mc = np.ascontiguousarray(np.broadcast_to(m_const, batch + (3,)).reshape(n_body, 3))

    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            if method == "midpoint":
                qs, ws, info = _run_midpoint(
                    jb, inverse3(jb, diagonal), q, omega0_n, tt, h_max, comp, mc, tfn, report
                )
            elif method == "splitting":
                grav = None
                if isinstance(model, GravityTorque) and model.moment.shape[:-1] in ((), batch):
                    # gravity about a fixed point: exact kicks inside the compiled stepper
                    grav = np.broadcast_to(model.moment, batch + (3,)).reshape(n_body, 3)
                if grav is not None:
                    qs, ws, info = _run_splitting(
                        jb, q, omega0_n, tt, h_max, comp, mc, None, grav, report
                    )
                else:
                    qs, ws, info = _run_splitting(
                        jb, q, omega0_n, tt, h_max, comp, mc, tfn, None, report
                    )
            elif method == "rk4":
                qs, ws, info = _run_rk4_compiled(jb, q, omega0_n, tt, h_max, model, report)
                if qs is None:  # a Python torque: the NumPy stages, one batch step at a time
                    qs, ws, info = _run_rk4(
                        jb, inverse3(jb, diagonal), q, omega0_n, tt, h_max, mc, tfn
                    )
                    info["path"] = "NumPy (torque is a Python callable)"
            elif method == "dop853":
                from . import _fused  # numba, loaded on first use

                fused = _fused.integrate(
                    moments if principal else jb,
                    q,
                    omega0_n,
                    tt,
                    model,
                    rtol=rtol,
                    atol=atol,
                    max_step=h_max,
                    progress=report,
                    diagonal=diagonal,
                    principal=principal,
                )
                if fused is None:  # a Python torque: the slower, vectorised solve_ivp path
                    if principal and moments is not None:  # (always set then)
                        jb = diagonal3(moments)
                    qs, ws, info = _run_adaptive(
                        jb,
                        inverse3(jb, diagonal),
                        q,
                        omega0_n,
                        tt,
                        h_max,
                        mc,
                        tfn,
                        rtol,
                        atol,
                        "DOP853",
                    )
                    info["path"] = "solve_ivp DOP853 (torque is a Python callable)"
                else:
                    qs, ws, info = _fused_info(fused, tt, rtol, atol, mark=failures == "mark")
            else:
                qs, ws, info = _run_adaptive(
                    jb, inverse3(jb, diagonal), q, omega0_n, tt, h_max, mc, tfn, rtol, atol, solver
                )
    except BaseException:
        if report is not None:
            report.close()
        raise
    if report is not None:
        report.finish()  # the compiled runs reported as they went; the others now
    if method not in ("adaptive", "dop853"):
        info["order"] = 4 if method == "rk4" else int(order)
    if tfn is not None:
        info["torque_calls"] = tfn.calls

    n = tt.shape[0]
    # principal axes: the moments' products instead of 3x3 ones, the same values (the
    # tensor's off-diagonal terms add exact zeros)
    with hold() as scratch:  # J w is a temporary here: only T and K_s are kept
        k = scratch.empty("momentum_body", ws.shape)
        if moments is not None:  # diagonal
            k = _momentum(moments, True, ws, out=k)
        else:
            k = _momentum(jb, False, ws, out=k)
        energy, momentum = _kinetic_space(qs, ws, k)
    out = batch
    quat = qs.reshape((n,) + out + (4,))
    info.update(_system_info(model, quat))
    compiled_dop853 = method == "dop853" and "path" not in info
    # arrays made here (and the compiled kernel's outputs) are handed over, not copied
    return Trajectory._own(
        ("omega", "energy", "momentum") if compiled_dop853 else ("energy", "momentum"),
        t=tt,
        # the compiled DOP853 returns unit quaternions (held, for a marked failure)
        rotation=Rotation._wrap(quat) if compiled_dop853 else Rotation.from_quat(quat),
        omega=ws.reshape((n,) + out + (3,)),
        method=method,
        energy=energy.reshape((n,) + out),
        momentum=momentum.reshape((n,) + out + (3,)),
        info=info,
    )


def _system_info(model: TorqueModel | None, quat: np.ndarray) -> dict[str, Any]:
    """``info`` keys saying what the motion conserves (docs/theory.md §8, §10): a free
    body ``T`` and ``K``; gravity about a fixed point ``T + V`` and ``K_z``, with ``m g c``
    (``V = gamma . m g c`` is evaluated only when asked: at each sample it cost a batch
    of heavy tops 19% of its run); another conservative torque ``T + V`` with ``V`` at
    each sample; any other torque nothing."""
    from .torques import GravityTorque

    if model is None or (isinstance(model, ConstantBodyTorque) and not np.any(model.torque)):
        return {"torque": "none", "conserved": ("energy", "momentum")}
    info: dict[str, Any] = {"torque": type(model).__name__, "conserved": ()}
    if isinstance(model, GravityTorque):
        info["gravity_moment"] = model.moment
        info["conserved"] = ("total_energy", "momentum_z")
    elif model.conservative:
        try:  # a user's potential_function may not take the (n, ..., 4) samples at once
            v = model.potential(quat)
            v = None if v is None else np.asarray(v, dtype=float).reshape(quat.shape[:-1])
        except Exception:  # noqa: BLE001 - then the result just does not claim T + V
            v = None
        if v is not None:
            info["potential_energy"] = v
            info["conserved"] = ("total_energy",)
    return info


# ---------------------------------------------------------------------------
# Methods
# ---------------------------------------------------------------------------


#: Why a body of a compiled DOP853 batch failed (``info["failed"]`` with failures="mark").
FAILURE_REASONS = {
    1: "the step size fell below round-off",
    2: "it needed more than 10^6 steps",
    3: "the state became non-finite",
}


def _fused_info(
    fused: tuple[FloatArray, FloatArray, Any],
    tt: FloatArray,
    rtol: float,
    atol: float,
    *,
    mark: bool = False,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """Outputs and ``info`` of the compiled DOP853 run; raise if any body failed
    (``mark``: hold each failed body at its last finite state and name the reason)."""
    from . import _fused

    qs, ws, stats = fused
    bad = np.flatnonzero(stats[:, 3] != _fused.OK)
    failed = None
    if bad.size and mark:
        failed = np.full(stats.shape[0], "", dtype=object)
        for b in bad:
            failed[b] = FAILURE_REASONS[int(stats[b, 3])]
            ok = np.isfinite(qs[:, b]).all(axis=-1) & np.isfinite(ws[:, b]).all(axis=-1)
            last = int(np.flatnonzero(ok)[-1]) if ok.any() else -1
            if last < 0:  # not even the start: the identity at rest stands in
                qs[:, b], ws[:, b] = (1.0, 0.0, 0.0, 0.0), 0.0
            else:
                qs[last + 1 :, b], ws[last + 1 :, b] = qs[last, b], ws[last, b]
    elif bad.size:
        first = int(bad[0])
        status = int(stats[first, 3])
        alive = np.flatnonzero(np.isfinite(ws[:, first, 0]))
        t_reached = float(tt[alive[-1]]) if alive.size else float(tt[0])
        if atol == 0.0 and status == _fused.STEP_TOO_SMALL:
            # the error scale atol + rtol |y| is 0 where a component is exactly 0
            hint = (
                "With `atol=0` a component that is exactly 0 (the identity's vector part, "
                "a zero rate) allows no error at all: give `atol > 0`."
            )
        else:
            hint = (
                "The problem may be stiff or diverging: loosen `rtol`, shorten the run, "
                "or check the torque."
            )
        raise IntegrationError(
            f"dop853 integration failed for {bad.size} of {stats.shape[0]} bodies (first: body "
            f"{first}): {FAILURE_REASONS[status]} after t = {t_reached:.6g}. {hint}"
        )
    info = {
        "steps": stats[:, 0].copy(),
        "rejected": stats[:, 1].copy(),
        "evaluations": int(stats[:, 2].sum()),
        "order": 8,
        "rtol": rtol,
        "atol": atol,
        "solver": "DOP853 (compiled, per-body step control)",
    }
    if failed is not None:
        info["failed"] = failed
    return qs, ws, info


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
    from .._progress import run_compiled

    cancel = np.zeros(1, dtype=np.int64)
    done = np.zeros(1, dtype=np.int64)
    n_body, n_int = q.shape[0], t.shape[0] - 1
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


def _run_midpoint(
    j: FloatArray,
    j_inv: FloatArray,
    q: FloatArray,
    w: FloatArray,
    t: FloatArray,
    h_max: float,
    comp: Sequence[float],
    m_const: Any,
    tfn: Any,
    report: _Report | None = None,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    nsub = _substeps(t, h_max)
    m = np.einsum("...ij,...j->...i", j, w)
    info = _fixed_step_info(t, nsub, comp)
    if tfn is None:
        from . import _euler_numba

        torque = np.zeros((1, 3)) if m_const is None else m_const
        args = _kernel_args(q, m, j_inv, torque, t, nsub, comp)
        Q, MO, status, body, k, it = _run_kernel(_euler_numba.midpoint, args, q, t, nsub, report)
        if status == 2:
            raise _fail_nonfinite("midpoint", float(t[k]), f"the state of body {body}")
        if status == 1:
            raise IntegrationError(
                f"midpoint integration failed: the implicit step did not converge after "
                f"t = {float(t[k]):.6g} (body {body}); reduce `max_step`."
            )
        info["max_newton_iterations"] = int(it)
    else:
        from . import _fused  # numba, loaded on first use

        out = _fused.midpoint(j, j_inv, q, m, t, nsub, comp, tfn.model, tfn.batch, report)
        if out is None:  # a Python torque: the NumPy step, vectorised over the batch
            Q, MO, it = _midpoint_numpy(j_inv, q, m, t, nsub, comp, tfn)
            info["path"] = "NumPy (torque is a Python callable)"
        else:
            Q, MO, res = out
            failed = np.flatnonzero(res[:, 0] != 0)
            if failed.size:
                b = int(failed[0])
                status, k = int(res[b, 0]), int(res[b, 1])
                if status == 2:
                    raise _fail_nonfinite("midpoint", float(t[k]), f"the state of body {b}")
                raise IntegrationError(
                    f"midpoint integration failed: the implicit step did not converge after "
                    f"t = {float(t[k]):.6g} (body {b}; the torque's dependence on the state "
                    f"is too strong for the step): reduce `max_step`."
                )
            it = int(res[:, 2].max()) if res.shape[0] else 0
        info["max_newton_iterations"] = int(it)
    ws = np.einsum("...ij,...j->...i", j_inv, MO)
    return Q, ws, info


def _midpoint_numpy(
    j_inv: FloatArray,
    q: FloatArray,
    m: FloatArray,
    t: FloatArray,
    nsub: IntArray,
    comp: Sequence[float],
    tfn: Any,
) -> tuple[FloatArray, FloatArray, int]:
    """The midpoint step of :mod:`._euler_numba`, vectorised over the batch with NumPy,
    for a torque that is a Python function of ``(t, rotation, omega)``."""
    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    MO = np.empty((n,) + m.shape)
    Q[0], MO[0] = q, m
    worst = 0
    mt = None
    for k, tn, h, last in _stages(t, nsub, comp):
        q, m, mt, it = _midpoint_step_numpy(j_inv, q, m, tn, h, tfn, mt)
        worst = max(worst, it)
        if last:
            if not (np.all(np.isfinite(m)) and np.all(np.isfinite(q))):
                raise _fail_nonfinite("midpoint", float(t[k]), "the angular momentum")
            Q[k + 1], MO[k + 1] = q, m
    return Q, MO, worst


def _midpoint_step_numpy(
    j_inv: FloatArray,
    q: FloatArray,
    m: FloatArray,
    tn: float,
    h: float,
    tfn: Any,
    mt: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, int]:
    """One midpoint step ``(q, m) -> (q+, m+)`` of length ``h`` from ``tn`` (see simulate).

    ``mt`` (the previous step's midpoint torque) seeds the first guess; returns
    ``(q+, m+, midpoint torque, Newton iterations)``.
    """
    eye = np.eye(3)
    h2 = 0.5 * h
    w = np.einsum("...ij,...j->...i", j_inv, m)
    if mt is None:
        mt = tfn(tn, q, w)
    x = m + h2 * (_cross(m, w) + mt)
    prev = math.inf
    it = 0
    while True:
        it += 1
        w = np.einsum("...ij,...j->...i", j_inv, x)
        # midpoint attitude: half of the step's rotation, L_n o sqrt(cay(a)), a = h w / 2,
        # whose Gibbs vector is a / (1 + sqrt(1 + a.a)): symmetric in n <-> n + 1
        a = h2 * w
        b = a / (1.0 + np.sqrt(1.0 + np.einsum("...i,...i->...", a, a)))[..., None]
        mt = tfn(tn + h2, _qmul(q, _cayley_quat(b)), w)
        r = x - m - h2 * (_cross(x, w) + mt)
        jac = eye - h2 * (_hat(x) @ j_inv - _hat(w))
        dx = np.linalg.solve(jac, r[..., None])[..., 0]
        x = x - dx
        num, den = np.abs(dx).max(-1), np.abs(x).max(-1)
        rel = float(np.max(np.where(num == 0.0, 0.0, num / np.where(den == 0.0, 1.0, den))))
        # converged: at round-off, the next update predicted below round-off
        # (rel^2 / prev, valid for linear and quadratic convergence), or stagnating
        if rel <= 2 * _EPS or (it >= 2 and (rel * rel <= _EPS * prev or 1e-12 >= rel >= prev / 2)):
            break
        if it >= _MAXIT or not rel < 1.0:  # too slow, or diverging
            raise IntegrationError(
                f"midpoint integration failed: the implicit step did not converge at "
                f"t = {tn:.6g} (the torque's dependence on the state is too strong "
                f"for the step): reduce `max_step`."
            )
        prev = rel
    w = np.einsum("...ij,...j->...i", j_inv, x)
    a = h2 * w
    u = m - _cross(a, m) + h * mt
    au = np.einsum("...i,...i->...", a, u)[..., None]
    m = (u - _cross(a, u) + au * a) / (1.0 + np.einsum("...i,...i->...", a, a))[..., None]
    q = _normalize(_qmul(q, _cayley_quat(a)))
    return q, m, mt, it


def _run_splitting(
    j: FloatArray,
    q: FloatArray,
    w: FloatArray,
    t: FloatArray,
    h_max: float,
    comp: Sequence[float],
    m_const: Any,
    tfn: Any,
    gravity: Any = None,
    report: _Report | None = None,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """Strang splitting of the free-body Hamiltonian, with the torque as kicks.

    In principal axes (moments ``I0 <= I1 <= I2``) write
    ``H = |m|^2 / (2 I1) + c0 m0^2 / 2 + c2 m2^2 / 2``, ``c_i = 1/I_i - 1/I1``
    (Dullweber, Leimkuhler & McLachlan 1997). Each part has an exact flow: the
    first turns the body about the constant ``m`` by ``h |m| / I1``; the others
    turn ``m`` by ``-theta`` and the body by ``+theta`` about axis ``i``,
    ``theta = h c_i m_i``. Every flow keeps ``K_s = L m L~`` and ``|m|``; for a
    symmetric body one of ``c0, c2`` vanishes and the composition is exact.
    Step: kick h/2, F0 h/2, F2 h/2, F_iso h, F2 h/2, F0 h/2, kick h/2.
    ``gravity`` (N, 3), optional: ``m g c`` in body axes, a gravity torque about a
    fixed point given to the compiled stepper, whose kicks ``h gamma x (m g c)``
    (``gamma = R^T e_z`` frozen) are the exact flow of the potential.
    """
    from ..mass import principal_axes

    nsub = _substeps(t, h_max)
    moments, rot = principal_axes(j)  # J_b = S diag(I) S^T, S = C_bp, I ascending
    s_bp = np.broadcast_to(np.asarray(rot.as_quat(), dtype=float), (q.shape[0], 4))
    s_pb = s_bp * np.array([1.0, -1.0, -1.0, -1.0])
    inv_i = np.broadcast_to(1.0 / moments, q.shape[:-1] + (3,))
    c_axis = inv_i - inv_i[:, 1:2]
    q_np = _qmul(q, s_bp)
    m = _qrot(s_pb, np.einsum("...ij,...j->...i", j, w))  # principal-axes momentum

    def kick(tn: float, q_np: FloatArray, m: FloatArray, dt: float) -> FloatArray:
        if m_const is None and tfn is None:
            return m
        if tfn is None:
            mt = m_const
        else:
            mt = tfn(tn, _qmul(q_np, s_pb), _qrot(s_bp, m * inv_i))
        return m + dt * _qrot(s_pb, mt)

    def axis_flow(
        q_np: FloatArray, m: FloatArray, i: int, dt: float
    ) -> tuple[FloatArray, FloatArray]:
        theta = dt * c_axis[:, i] * m[:, i]
        a, b = (i + 1) % 3, (i + 2) % 3
        c, s = np.cos(theta), np.sin(theta)
        ma, mb = m[:, a], m[:, b]
        m = m.copy()
        m[:, a] = c * ma + s * mb
        m[:, b] = c * mb - s * ma
        return _qmul(q_np, _axis_quat(theta, i)), m

    def iso_flow(q_np: FloatArray, m: FloatArray, dt: float) -> FloatArray:
        return _qmul(q_np, _rotvec_quat(dt * inv_i[:, 1:2] * m))

    if tfn is None:
        from . import _euler_numba

        mt = np.zeros((1, 3)) if m_const is None else _qrot(s_pb, m_const)
        args: tuple[Any, ...] = _kernel_args(q_np, m, inv_i, mt, t, nsub, comp)
        grav = None if gravity is None else np.ascontiguousarray(_qrot(s_pb, gravity), dtype=float)
        Q, MO, status, body, k = _run_kernel(
            _euler_numba.splitting, args, q_np, t, nsub, report, grav
        )
        if status == 2:
            raise _fail_nonfinite("splitting", float(t[k]), f"the state of body {body}")
        return _qmul(Q, s_pb), _qrot(s_bp, MO * inv_i), _fixed_step_info(t, nsub, comp)

    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    Wo = np.empty((n,) + w.shape)
    Q[0], Wo[0] = q, w
    for k, tn, h, last in _stages(t, nsub, comp):
        m = kick(tn, q_np, m, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 0, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 2, 0.5 * h)
        q_np = iso_flow(q_np, m, h)
        q_np, m = axis_flow(q_np, m, 2, 0.5 * h)
        q_np, m = axis_flow(q_np, m, 0, 0.5 * h)
        q_np = _normalize(q_np)
        m = kick(tn + h, q_np, m, 0.5 * h)
        if last:
            if not (np.all(np.isfinite(m)) and np.all(np.isfinite(q_np))):
                raise _fail_nonfinite("splitting", float(t[k]), "the angular momentum")
            Q[k + 1] = _qmul(q_np, s_pb)
            Wo[k + 1] = _qrot(s_bp, m * inv_i)
    return Q, Wo, _fixed_step_info(t, nsub, comp)


def _torque_value(m_const: Any, tfn: Any, tn: float, q: FloatArray, w: FloatArray) -> Any:
    if tfn is not None:
        return tfn(tn, q, w)
    return m_const


def _run_rk4_compiled(
    j: FloatArray,
    q: FloatArray,
    w: FloatArray,
    t: FloatArray,
    h_max: float,
    model: Any,
    report: _Report | None = None,
) -> tuple[Any, Any, Any]:
    """RK4 in one compiled loop per body (built-in torques); ``(None, None, None)``
    for a Python torque."""
    from . import _fused  # numba, loaded on first use

    nsub = _substeps(t, h_max)
    out = _fused.rk4(j, q, w, t, nsub, model, progress=report)
    if out is None:
        return None, None, None
    qs, ws, failed = out
    bad = np.flatnonzero(failed >= 0)
    if bad.size:
        k = int(failed[bad].min())
        raise _fail_nonfinite("rk4", float(t[k]), "the state")
    info = _fixed_step_info(t, nsub)
    info["path"] = "compiled"
    return qs, ws, info


def _run_rk4(
    j: FloatArray,
    j_inv: FloatArray,
    q: FloatArray,
    w: FloatArray,
    t: FloatArray,
    h_max: float,
    m_const: Any,
    tfn: Any,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    nsub = _substeps(t, h_max)
    n = t.shape[0]
    Q = np.empty((n,) + q.shape)
    Wo = np.empty((n,) + w.shape)
    Q[0], Wo[0] = q, w

    def f(tn: float, q: FloatArray, w: FloatArray) -> tuple[FloatArray, FloatArray]:
        mt = _torque_value(m_const, tfn, tn, q, w)
        return 0.5 * _qmul(q, _pure(w)), _rhs(j, j_inv, w, mt)

    for k, tn, h, last in _stages(t, nsub, (1.0,)):
        k1q, k1w = f(tn, q, w)
        k2q, k2w = f(tn + h / 2, q + h / 2 * k1q, w + h / 2 * k1w)
        k3q, k3w = f(tn + h / 2, q + h / 2 * k2q, w + h / 2 * k2w)
        k4q, k4w = f(tn + h, q + h * k3q, w + h * k3w)
        q = _normalize(q + h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q))
        w = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w)
        if last:
            if not np.all(np.isfinite(w)):
                raise _fail_nonfinite("rk4", float(t[k]), "the angular velocity")
            if not np.all(np.isfinite(q)):
                raise _fail_nonfinite("rk4", float(t[k]), "the attitude quaternion")
            Q[k + 1], Wo[k + 1] = q, w
    return Q, Wo, _fixed_step_info(t, nsub)


def _run_adaptive(
    j: FloatArray,
    j_inv: FloatArray,
    q: FloatArray,
    w: FloatArray,
    t: FloatArray,
    h_max: float,
    m_const: Any,
    tfn: Any,
    rtol: float,
    atol: float,
    solver: str,
) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    from scipy.integrate import solve_ivp

    nb = q.shape[0]

    def fun(tn: float, y: FloatArray) -> FloatArray:
        y = y.reshape(nb, 7)
        qq, ww = y[:, :4], y[:, 4:]
        mt = _torque_value(m_const, tfn, tn, qq, ww)
        dq = 0.5 * _qmul(qq, _pure(ww))
        return np.concatenate([dq, _rhs(j, j_inv, ww, mt)], axis=1).ravel()

    y0 = np.concatenate([q, w], axis=1).ravel()
    n = t.shape[0]
    if n == 1:
        ys = y0[None]
        info = {"evaluations": 0, "solver": solver, "rtol": rtol, "atol": atol, "message": ""}
    else:
        try:
            sol = solve_ivp(
                fun,
                (t[0], t[-1]),
                y0,
                method=solver,
                t_eval=t,
                rtol=rtol,
                atol=atol,
                max_step=h_max,
            )
        except ValueError as exc:
            raise InvalidInputError(
                f"`solver`, `rtol` or `atol` rejected by solve_ivp: {exc}"
            ) from None
        if sol.status != 0 or sol.y.shape[1] != n or not np.all(np.isfinite(sol.y)):
            reached = float(sol.t[-1]) if sol.t.size else float(t[0])
            raise IntegrationError(
                f"adaptive integration ({solver}) failed after t = {reached:.6g}: "
                f"{sol.message} The state may have become non-finite (a stiff or diverging "
                f"problem): try method='midpoint' with a small `max_step`."
            )
        ys = sol.y.T
        info = {
            "evaluations": int(sol.nfev),
            "solver": solver,
            "rtol": rtol,
            "atol": atol,
            "message": sol.message,
        }
    ys = ys.reshape(n, nb, 7)
    return _normalize(ys[..., :4]), ys[..., 4:], info
