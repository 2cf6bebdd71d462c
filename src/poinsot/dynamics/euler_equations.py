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
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import integrators
from .._progress import as_progress
from .._scratch import hold
from .._typing import ArrayLike, FloatArray
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
from .._vec import inverse3
from ..errors import InvalidInputError
from ..mass.tensor import _momentum, as_inertia, single_principal_moments
from ..rotations.rotation import Rotation

if TYPE_CHECKING:
    from ..mass.body import RigidBody
    from .torques import TorqueModel
from ..events import Event, EventLog, as_events, locate, solve_dense
from ..trajectory import Trajectory
from .integrators import (  # noqa: F401 - SOLVERS, FAILURE_REASONS: their old home
    COMPOSITIONS,
    FAILURE_REASONS,
    RIGID,
    SOLVERS,
    RigidProblem,
    RunOptions,
)
from .integrators._common import _rhs, batch_rhs
from .invariants import _kinetic_space
from .torques import ConstantBodyTorque, GravityTorque, GyrostaticTorque, as_torque

__all__ = ["euler_rhs", "simulate", "METHODS"]

#: Names accepted by ``simulate(method=...)``.
#: The integrators of Euler's equations (from :data:`poinsot.integrators.INTEGRATORS`).
METHODS = integrators.names("rigid")


# ---------------------------------------------------------------------------
# Inertia
# ---------------------------------------------------------------------------


def _as_inertia(inertia: object, name: str) -> tuple[np.ndarray, bool]:
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


def _max_step(max_step: ArrayLike | None) -> float:
    """``max_step`` as a positive float (``inf`` for ``None``: no limit)."""
    if max_step is None:
        return math.inf
    h_arr = as_float_array(max_step, "max_step")
    if h_arr.ndim != 0:
        raise InvalidInputError(f"Expected `max_step` to be a scalar, got shape {h_arr.shape}.")
    h_max = float(h_arr)
    if not h_max > 0:
        raise InvalidInputError(f"Expected `max_step` to be positive, got {max_step!r}.")
    return h_max


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
    events: Any = None,
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
    events : callable, Event or list of them, optional
        Functions ``g(t, y)`` of the state ``y = (q_w, q_x, q_y, q_z, w_x, w_y,
        w_z)`` (attitude body -> space, body rates in rad/s) whose zeros are events,
        with SciPy's ``terminal`` and ``direction`` (:class:`poinsot.dynamics.Event`).
        Each event is located per body by root finding on a DOP853 re-integration
        of its output interval (theory §11.1, :mod:`poinsot.events`); the
        times and states are ``info["events"]`` (an
        :class:`~poinsot.dynamics.EventLog`). A terminal event ends one body's run
        at the event (its last sample); in a batch the stopped body is held there.

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
    h_max = _max_step(max_step)
    # refusals from the methods' facts (integrators.INTEGRATORS[...].options)
    marked = None if failures == "raise" else failures
    opts = {"order": order, "rtol": rtol, "atol": atol, "solver": solver, "failures": marked}
    integrators.check_options(method, opts, METHODS)
    rtol, atol = _tolerances(1e-10 if rtol is None else rtol, 1e-12 if atol is None else atol)
    solver = as_choice("DOP853" if solver is None else solver, "solver", SOLVERS)
    if order is None:
        order = 2
    comp = COMPOSITIONS[as_int(order, "order", choices=tuple(COMPOSITIONS))]
    report = as_progress(progress, "simulate")
    event_list = as_events(events)

    problem = RigidProblem.flatten(
        j, principal, q0, omega0, tt, batch, h_max=h_max, comp=comp, model=model,
        m_const=m_const, torque_fn=torque_fn, method=method, report=report,
    )  # fmt: skip
    runner = RIGID[method]
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            qs, ws, info = runner.run(problem, RunOptions(int(order), rtol, atol, solver, failures))
    except BaseException:
        if report is not None:
            report.close()
        raise
    if report is not None:
        report.finish()  # the compiled runs reported as they went; the others now
    if event_list:
        tt, qs, ws, info["events"] = _rigid_events(event_list, problem, tt, qs, ws, batch)
    facts = runner.facts
    if not facts.adaptive:  # a fixed-step method: its order (composed, where it is)
        info["order"] = int(order) if "order" in facts.options else facts.order
    if problem.tfn is not None:
        info["torque_calls"] = problem.tfn.calls

    n = tt.shape[0]
    # principal axes: the moments' products instead of 3x3 ones, the same values (the
    # tensor's off-diagonal terms add exact zeros)
    with hold() as scratch:  # J w is a temporary here: only T and K_s are kept
        k = scratch.empty("momentum_body", ws.shape)
        if problem.moments is not None:  # diagonal
            k = _momentum(problem.moments, True, ws, out=k)
        else:
            k = _momentum(problem.j, False, ws, out=k)
        energy, momentum = _kinetic_space(qs, ws, k)
    out = batch
    quat = qs.reshape((n,) + out + (4,))
    info.update(_system_info(model, quat))
    compiled_dop853 = runner.unit_output(info)
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


def _rigid_events(
    events: tuple[Event, ...],
    p: RigidProblem,
    t: FloatArray,
    qs: FloatArray,
    ws: FloatArray,
    batch: tuple[int, ...],
) -> tuple[FloatArray, FloatArray, FloatArray, EventLog]:
    """Locate ``events`` on the samples (theory §11.1): a body's interval is integrated
    again alone (or with the whole batch, for a torque evaluated on the batch)."""

    def flow(bodies: np.ndarray, t0: float, t1: float, y0: np.ndarray) -> Any:
        if p.tfn is None:
            return solve_dense(batch_rhs(p, bodies), t0, t1, y0[bodies])
        whole = solve_dense(batch_rhs(p), t0, t1, y0)
        return lambda s: whole(s)[bodies]

    y = np.concatenate([qs, ws], axis=-1)
    t_new, y, log = locate(events, t, y, flow, batch)
    q = y[..., :4] / np.linalg.norm(y[..., :4], axis=-1, keepdims=True)
    return t_new, np.ascontiguousarray(q), np.ascontiguousarray(y[..., 4:]), log


def _system_info(model: TorqueModel | None, quat: np.ndarray) -> dict[str, Any]:
    """``info`` keys saying what the motion conserves (docs/theory.md §8, §10): a free
    body ``T`` and ``K``; gravity about a fixed point ``T + V`` and ``K_z``, with ``m g c``
    (``V = gamma . m g c`` is evaluated only when asked: at each sample it cost a batch
    of heavy tops 19% of its run); another conservative torque ``T + V`` with ``V`` at
    each sample; any other torque nothing."""

    if model is None or (isinstance(model, ConstantBodyTorque) and not np.any(model.torque)):
        return {"torque": "none", "conserved": ("energy", "momentum")}
    info: dict[str, Any] = {"torque": type(model).__name__, "conserved": ()}
    if isinstance(model, GravityTorque):
        info["gravity_moment"] = model.moment
        info["conserved"] = ("total_energy", "momentum_z")
    elif isinstance(model, GyrostaticTorque):  # h x w does no work (theory §10.1)
        if model.rate is None or not np.any(model.rate):  # (- U does)
            info["conserved"] = ("energy",)
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
