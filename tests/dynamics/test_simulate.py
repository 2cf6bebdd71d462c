"""``simulate``: integrators of Euler's equations with the attitude (SPEC S5, S10).

Independent truths used here: a tight ``scipy.integrate.solve_ivp`` (DOP853,
rtol 1e-13) on the SPEC S10 component equations with a hand-written quaternion
kinematics; the regular precession of the free symmetric body (SPEC S10:
``psi' = K/A``, ``phi' = (A - C) r / A``, ``cos theta = C r / K``); closed forms
for a spherical body under damping and under a space-fixed torque; the
conservation of T, |K| and the space vector K for the free body.
"""

import types

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation as SciRotation

import poinsot
from poinsot import IntegrationError, InvalidInputError, InvalidTypeError, Rotation
from poinsot.dynamics import simulate
from poinsot.dynamics.torques import (
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityGradientTorque,
    GravityTorque,
)

MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.4, 1.2, 0.3])
Q0 = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])


def _reference(moments, q0, w0, t):
    """DOP853 at rtol 1e-13 on SPEC S10 (principal axes) + ``L' = L o w / 2`` (SPEC S5)."""
    a, b, c = moments

    def f(_, y):
        l0, l1, l2, l3, p, q, r = y
        return [
            0.5 * (-l1 * p - l2 * q - l3 * r),
            0.5 * (l0 * p + l2 * r - l3 * q),
            0.5 * (l0 * q + l3 * p - l1 * r),
            0.5 * (l0 * r + l1 * q - l2 * p),
            -(c - b) * q * r / a,
            -(a - c) * r * p / b,
            -(b - a) * p * q / c,
        ]

    sol = solve_ivp(f, (t[0], t[-1]), [*q0, *w0], method="DOP853", t_eval=t, rtol=1e-13, atol=1e-14)
    q = sol.y[:4].T
    return q / np.linalg.norm(q, axis=-1, keepdims=True), sol.y[4:].T


def _angle(q1, q2):
    """Rotation angle between attitudes given as scalar-first quaternions."""
    r1 = SciRotation.from_quat(np.asarray(q1)[..., [1, 2, 3, 0]])
    r2 = SciRotation.from_quat(np.asarray(q2)[..., [1, 2, 3, 0]])
    return (r1.inv() * r2).magnitude()


# ---------------------------------------------------------------------------
# Invariants
# ---------------------------------------------------------------------------


def test_midpoint_keeps_free_body_invariants_to_round_off_over_1e5_steps():
    """Free body: T, |K| and the space vector K are first integrals (SPEC S10)."""
    t = np.linspace(0.0, 1000.0, 101)
    tr = simulate(MOMENTS, Q0, OMEGA0, t, max_step=0.01)
    assert tr.info["steps"] == 100_000
    assert tr.energy_drift <= 5e-12  # round-off random walk: 2.4e-13 observed
    assert tr.momentum_drift <= 5e-12
    assert tr.momentum_vector_drift <= 5e-12
    # the energy and |K| are those of the initial state
    np.testing.assert_allclose(tr.energy[0], 0.5 * np.sum(MOMENTS * OMEGA0**2), rtol=2e-14)
    np.testing.assert_allclose(tr.momentum_norm[0], np.linalg.norm(MOMENTS * OMEGA0), rtol=2e-14)
    # the body-axes momentum stays on the MacCullagh sphere/ellipsoid intersection
    k_b = MOMENTS * tr.omega
    np.testing.assert_allclose(
        np.sum(k_b**2 / MOMENTS, axis=-1), 2 * tr.energy[0], rtol=1e-11, atol=0
    )


def test_splitting_keeps_momentum_exactly_and_energy_bounded():
    t = np.linspace(0.0, 200.0, 201)
    tr = simulate(MOMENTS, Q0, OMEGA0, t, method="splitting", max_step=0.02)
    assert tr.momentum_drift <= 1e-12
    assert tr.momentum_vector_drift <= 1e-12
    rel = np.abs(tr.energy / tr.energy[0] - 1)
    assert 1e-9 < rel.max() < 1e-3  # not conserved, but bounded: no drift
    assert rel[100:].max() < 2.0 * rel[:101].max()


def test_rk4_and_adaptive_drift_but_stay_accurate():
    t = np.linspace(0.0, 20.0, 21)
    rk4 = simulate(MOMENTS, Q0, OMEGA0, t, method="rk4", max_step=0.01)
    assert 0 < rk4.energy_drift < 1e-9
    ada = simulate(MOMENTS, Q0, OMEGA0, t, method="adaptive", rtol=1e-12, atol=1e-14)
    assert ada.energy_drift < 1e-10
    assert ada.info["evaluations"] > 0 and ada.info["solver"] == "DOP853"


# ---------------------------------------------------------------------------
# Accuracy and order against a tight reference
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("method", "steps", "order"),
    [
        ("midpoint", (0.04, 0.02, 0.01), 2),
        ("midpoint", (0.2, 0.1, 0.05), 4),
        ("midpoint", (0.2, 0.1, 0.05), 6),
        ("splitting", (0.04, 0.02, 0.01), 2),
        ("splitting", (0.2, 0.1, 0.05), 4),
        ("splitting", (0.4, 0.2, 0.1), 6),
        ("rk4", (0.2, 0.1, 0.05), 4),
    ],
)
def test_observed_order_of_convergence(method, steps, order):
    t = np.array([0.0, 1.0, 3.0, 4.0])
    q_ref, w_ref = _reference(MOMENTS, Q0, OMEGA0, t)
    errors = []
    kw = {} if method == "rk4" else {"order": order}
    for h in steps:
        tr = simulate(MOMENTS, Q0, OMEGA0, t, method=method, max_step=h, **kw)
        assert tr.info["order"] == order
        err_w = np.abs(tr.omega - w_ref).max()
        err_q = _angle(tr.quat, q_ref).max()
        errors.append(max(err_w, err_q))
    observed = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(observed - order) < 0.25), (errors, observed)


def test_higher_order_compositions_keep_the_invariants():
    t = np.linspace(0.0, 100.0, 11)
    for order, stages in ((4, 3), (6, 7)):
        tr = simulate(MOMENTS, Q0, OMEGA0, t, order=order, max_step=0.05)
        assert tr.info["stages_per_step"] == stages and tr.info["steps"] == 2000
        assert max(tr.energy_drift, tr.momentum_drift, tr.momentum_vector_drift) < 1e-12
        sp = simulate(MOMENTS, Q0, OMEGA0, t[:3], method="splitting", order=order, max_step=0.1)
        assert max(sp.momentum_drift, sp.momentum_vector_drift) < 1e-12


def test_agrees_with_exact_free_body_near_the_separatrix():
    """Dzhanibekov flip: spin close to the middle axis (K^2 slightly above 2 B T, SPEC
    S10 MacCullagh); the exact Euler-Poinsot solution is ``FreeRigidBody``."""
    free_body = pytest.importorskip("poinsot.dynamics.free_body")
    w0 = np.array([1e-3, 2.0, 2e-3])
    t = np.linspace(0.0, 20.0, 81)
    exact = free_body.FreeRigidBody(MOMENTS, rotation0=poinsot.Rotation.from_quat(Q0), omega0=w0)
    w_ex, q_ex = exact.omega(t), exact.rotation(t).as_quat()
    assert np.ptp(np.sign(w_ex[:, 1])) == 2  # the middle-axis component flips
    tr = simulate(MOMENTS, Q0, w0, t, order=6, max_step=0.01)
    # observed 5.3e-9 / 3.1e-9: round-off amplified by the flip (it does not shrink with
    # the step); the exact solution agrees with DOP853 (rtol 1e-13) to 6e-11
    np.testing.assert_allclose(tr.omega, w_ex, atol=1e-7)
    assert _angle(tr.quat, q_ex).max() < 1e-7


def test_adaptive_matches_reference():
    t = np.linspace(0.0, 10.0, 11)
    q_ref, w_ref = _reference(MOMENTS, Q0, OMEGA0, t)
    tr = simulate(MOMENTS, Q0, OMEGA0, t, method="adaptive", rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(tr.omega, w_ref, atol=1e-10)
    assert _angle(tr.quat, q_ref).max() < 1e-10
    # the looser default reaches about its tolerance
    tr = simulate(MOMENTS, Q0, OMEGA0, t, method="adaptive")
    np.testing.assert_allclose(tr.omega, w_ref, atol=1e-7)


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_symmetric_body_regular_precession_closed_form(method):
    """SPEC S10, free symmetric body ``A = B``: with K along space z the ZXZ Euler angles
    are ``psi = K t / A``, ``theta`` constant with ``cos theta = C r / K``,
    ``phi = phi0 + (A - C) r t / A``; ``r`` is constant."""
    a, c = 2.0, 1.2
    moments = np.array([a, a, c])
    k, theta, phi0 = 3.0, 0.7, 0.4
    k_b = k * np.array([np.sin(theta) * np.sin(phi0), np.sin(theta) * np.cos(phi0), np.cos(theta)])
    w0 = k_b / moments
    r = w0[2]
    assert np.isclose(np.cos(theta), c * r / k)
    t = np.linspace(0.0, 10.0, 41)
    angles = np.stack([k * t / a, np.full_like(t, theta), phi0 + (a - c) * r * t / a], axis=-1)
    exact = SciRotation.from_euler("ZXZ", angles).as_quat(scalar_first=True)
    step = {"midpoint": 1e-3, "splitting": 1e-3, "rk4": 2e-2, "adaptive": None}[method]
    tols = dict(rtol=1e-12, atol=1e-13) if method == "adaptive" else {}
    tr = simulate(moments, exact[0], w0, t, method=method, max_step=step, **tols)
    # observed: midpoint 8.6e-6, rk4 3.7e-8, splitting 3.0e-12, adaptive 4.6e-12
    tol = {"midpoint": 1e-4, "splitting": 1e-10, "rk4": 1e-6, "adaptive": 1e-10}[method]
    assert _angle(tr.quat, exact).max() < tol
    np.testing.assert_allclose(tr.omega[:, 2], r, rtol=2e-11)
    np.testing.assert_allclose(tr.momentum, np.broadcast_to([0, 0, k], (41, 3)), atol=2e-5)


# ---------------------------------------------------------------------------
# Torques (closed forms)
# ---------------------------------------------------------------------------


def test_constant_axial_torque_on_spinning_symmetric_body():
    """Symmetric body spinning about its axis, constant axial body torque ``M3``:
    ``r = r0 + M3 t / C``, rotation about z by ``r0 t + M3 t^2 / (2 C)``."""
    moments = np.array([2.0, 2.0, 1.5])
    r0, m3 = 1.0, 0.6
    t = np.linspace(0.0, 5.0, 11)
    angle = r0 * t + m3 * t**2 / (2 * moments[2])
    exact = np.stack([np.cos(angle / 2), 0 * t, 0 * t, np.sin(angle / 2)], axis=-1)
    errs = []
    for h in (0.02, 0.01):
        tr = simulate(moments, [1.0, 0, 0, 0], [0, 0, r0], t, torque=[0, 0, m3], max_step=h)
        np.testing.assert_allclose(tr.omega[:, 2], r0 + m3 * t / moments[2], rtol=1e-12)
        np.testing.assert_allclose(tr.omega[:, :2], 0.0, atol=1e-15)
        errs.append(_angle(tr.quat, exact).max())
    assert errs[1] < 5e-3  # 4.2e-4 observed
    assert 3.5 < errs[0] / errs[1] < 4.5  # second order with a torque


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_damping_torque_on_spherical_body(method):
    """``M = -c w`` on a sphere (``J = I E``): ``w = w0 exp(-c t / I)`` about a fixed axis,
    turned angle ``|w0| I / c (1 - exp(-c t / I))``."""
    inertia, damping = 2.0, 0.5
    w0 = np.array([0.3, -1.0, 0.6])
    t = np.linspace(0.0, 4.0, 9)
    decay = np.exp(-damping * t / inertia)
    q_ref = SciRotation.from_rotvec((inertia / damping * (1 - decay))[:, None] * w0).as_quat(
        scalar_first=True
    )
    calls = []

    def torque(tn, rotation, omega):
        calls.append(tn)
        assert isinstance(rotation, poinsot.Rotation) and rotation.shape == ()
        return -damping * omega

    step = 0.01 if method in ("midpoint", "splitting") else 0.05
    tr = simulate(
        inertia * np.ones(3), [1.0, 0, 0, 0], w0, t, torque=torque, method=method, max_step=step
    )
    # splitting is first order for a torque depending on omega, the others 2 (h = 0.01) or 4
    # observed (attitude): midpoint 1.8e-5, splitting 8.0e-4, rk4 7.0e-9, adaptive 5.8e-16
    tol = {"midpoint": 2e-4, "splitting": 1e-2, "rk4": 1e-6, "adaptive": 1e-8}[method]
    np.testing.assert_allclose(tr.omega, decay[:, None] * w0, atol=tol)
    assert _angle(tr.quat, q_ref).max() < tol
    assert tr.info["torque_calls"] == len(calls) > 0
    assert np.all(np.diff(tr.energy) < 0)  # damping dissipates


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_space_fixed_torque_uses_body_to_space_attitude(method):
    """A sphere at rest under a constant *space* torque ``M_s`` (given to the body as
    ``R^T M_s``) spins up about the fixed space axis: ``w_s = M_s t / I``, angle
    ``|M_s| t^2 / (2 I)``; wrong frames would bend the axis."""
    inertia = 1.5
    m_s = np.array([0.2, 0.5, -0.4])
    q0 = SciRotation.from_rotvec([0.3, -0.2, 1.0]).as_quat(scalar_first=True)
    t = np.linspace(0.0, 3.0, 7)
    tr = simulate(
        inertia * np.eye(3),
        q0,
        [0.0, 0.0, 0.0],
        t,
        method=method,
        max_step=0.01,
        torque=lambda tn, rot, w: rot.apply(m_s, inverse=True),
    )
    np.testing.assert_allclose(tr.omega_space, m_s * t[:, None] / inertia, atol=1e-9)
    turn = SciRotation.from_rotvec(m_s * (t**2 / (2 * inertia))[:, None])
    exact = (turn * SciRotation.from_quat(q0, scalar_first=True)).as_quat(scalar_first=True)
    assert _angle(tr.quat, exact).max() < 2e-4  # midpoint: 1.5e-5 observed
    np.testing.assert_allclose(tr.momentum, m_s * t[:, None], atol=1e-9)  # K_s' = M_s


@pytest.mark.parametrize("method", ["midpoint", "splitting"])
@pytest.mark.parametrize("order", [2, 4])
def test_constant_torque_compiled_path_equals_callable_path(method, order):
    """The compiled kernels (constant torque) and the NumPy ones (callable) are one scheme."""
    m = np.array([0.1, -0.3, 0.2])
    j = np.array([[2.0, 0.1, 0.0], [0.1, 1.5, -0.2], [0.0, -0.2, 2.5]])
    t = np.linspace(0.0, 5.0, 6)
    kw = dict(method=method, order=order, max_step=0.05)
    a = simulate(j, Q0, OMEGA0, t, torque=m, **kw)
    b = simulate(j, Q0, OMEGA0, t, torque=lambda tn, r, w: m, **kw)
    np.testing.assert_allclose(a.omega, b.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.quat, b.quat, rtol=0, atol=1e-12)
    # free body: same again
    a = simulate(j, Q0, OMEGA0, t, **kw)
    b = simulate(j, Q0, OMEGA0, t, torque=lambda tn, r, w: np.zeros(3), **kw)
    np.testing.assert_allclose(a.omega, b.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.quat, b.quat, rtol=0, atol=1e-12)


# ---------------------------------------------------------------------------
# Frames, bodies, batches, steps
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_general_inertia_equals_principal_axes_result_rotated(method):
    """``J_b = S diag(I) S^T``: the body frame ``b`` and principal frame ``p`` give
    ``R_nb = R_np S^T`` and ``w_b = S w_p`` (SPEC S8)."""
    s = SciRotation.from_rotvec([0.4, -0.7, 0.2])
    s_m = s.as_matrix()
    j_b = s_m @ np.diag(MOMENTS) @ s_m.T
    w_b0 = s_m @ OMEGA0
    r_nb0 = SciRotation.from_quat(Q0, scalar_first=True)
    r_np0 = r_nb0 * s
    t = np.linspace(0.0, 5.0, 6)
    kw = dict(method=method, max_step=0.05)
    if method == "adaptive":
        kw.update(rtol=1e-12, atol=1e-13)
    tb = simulate(j_b, Q0, w_b0, t, **kw)
    tp = simulate(MOMENTS, r_np0.as_quat(scalar_first=True), OMEGA0, t, **kw)
    tol = 1e-8 if method == "adaptive" else 1e-11
    np.testing.assert_allclose(tb.omega, tp.omega @ s_m.T, atol=tol)
    r_nb = SciRotation.from_quat(tp.quat, scalar_first=True) * s.inv()
    assert _angle(tb.quat, r_nb.as_quat(scalar_first=True)).max() < tol
    np.testing.assert_allclose(tb.energy, tp.energy, rtol=tol)


def test_rigid_body_and_rotation_inputs():
    from poinsot.mass import RigidBody

    body = RigidBody(3.0, np.diag(MOMENTS), center_of_mass=[0.1, 0.0, 0.0])
    t = np.linspace(0.0, 1.0, 5)
    a = simulate(body, poinsot.Rotation.from_quat(Q0), OMEGA0, t)
    b = simulate(MOMENTS, Q0, OMEGA0, t)
    np.testing.assert_array_equal(a.omega, b.omega)
    np.testing.assert_array_equal(a.quat, b.quat)
    assert a.method == "midpoint" and a.rotation.shape == (5,)


def test_batch_equals_loop():
    rng = np.random.default_rng(7)
    n = 4
    moments = rng.uniform(1.5, 2.9, size=(n, 3))
    w0 = rng.normal(size=(n, 3))
    q0 = SciRotation.random(n, 3).as_quat(scalar_first=True)
    t = np.linspace(0.0, 2.0, 5)
    for method in ("midpoint", "splitting", "rk4", "adaptive"):
        tr = simulate(moments, q0, w0, t, method=method, max_step=0.05)
        assert tr.omega.shape == (5, n, 3) and tr.rotation.shape == (5, n)
        assert tr.energy.shape == (5, n) and tr.momentum.shape == (5, n, 3)
        for i in range(n):
            one = simulate(moments[i], q0[i], w0[i], t, method=method, max_step=0.05)
            tol = 1e-9 if method == "adaptive" else 1e-13
            np.testing.assert_allclose(tr.omega[:, i], one.omega, atol=tol)
            np.testing.assert_allclose(tr.quat[:, i], one.quat, atol=tol)


def test_batch_shapes_broadcast():
    """One body, a (2, 3) grid of initial angular velocities, one attitude."""
    w0 = np.arange(18, dtype=float).reshape(2, 3, 3) / 10
    t = np.linspace(0.0, 1.0, 4)
    tr = simulate(MOMENTS, Q0, w0, t, max_step=0.1)
    assert tr.omega.shape == (4, 2, 3, 3) and tr.quat.shape == (4, 2, 3, 4)
    one = simulate(MOMENTS, Q0, w0[1, 2], t, max_step=0.1)
    np.testing.assert_allclose(tr.omega[:, 1, 2], one.omega, atol=1e-15)

    def torque(tn, rotation, omega):
        assert rotation.shape == (2, 3) and omega.shape == (2, 3, 3)
        return -0.1 * omega

    tr = simulate(MOMENTS, Q0, w0, t, torque=torque, max_step=0.1)
    assert tr.omega.shape == (4, 2, 3, 3)


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_body_at_rest_stays_at_rest(method):
    t = np.linspace(0.0, 1.0, 3)
    for torque in (None, [0.0, 0.0, 0.0], lambda tn, r, w: np.zeros(3)):
        tr = simulate(MOMENTS, Q0, np.zeros(3), t, method=method, torque=torque)
        np.testing.assert_array_equal(tr.omega, 0.0)
        np.testing.assert_allclose(tr.quat, np.broadcast_to(Q0, (3, 4)), atol=1e-15)
        assert np.all(tr.energy == 0.0) and np.all(tr.momentum == 0.0)


def test_steps_never_longer_than_output_spacing_or_max_step():
    t = np.array([0.0, 0.1, 0.35, 1.0, 1.05])
    tr = simulate(MOMENTS, Q0, OMEGA0, t)
    assert tr.info["steps"] == 4 and tr.info["step_size"] == pytest.approx(0.65)
    tr = simulate(MOMENTS, Q0, OMEGA0, t, max_step=0.1)
    assert tr.info["steps"] == 1 + 3 + 7 + 1
    assert tr.info["step_size"] <= 0.1 * (1 + 1e-12)
    np.testing.assert_array_equal(tr.t, t)
    single = simulate(MOMENTS, Q0, OMEGA0, [2.0])
    assert single.omega.shape == (1, 3)
    np.testing.assert_allclose(single.omega[0], OMEGA0)
    np.testing.assert_allclose(single.quat[0], Q0)


# ---------------------------------------------------------------------------
# Bad input and failures
# ---------------------------------------------------------------------------


def test_bad_inputs_name_the_argument():
    t = np.linspace(0.0, 1.0, 3)
    with pytest.raises(InvalidInputError, match="`method`.*'midpoint'"):
        simulate(MOMENTS, Q0, OMEGA0, t, method="euler")
    with pytest.raises(InvalidInputError, match="`body`.*triangle"):
        simulate([1.0, 1.0, 3.0], Q0, OMEGA0, t)
    with pytest.raises(InvalidInputError, match="`body`.*positive definite"):
        simulate(np.diag([0.0, 1.0, 1.0]), Q0, OMEGA0, t)
    with pytest.raises(InvalidInputError, match="`body.mass`"):
        simulate(types.SimpleNamespace(mass=0.0, inertia=np.eye(3)), Q0, OMEGA0, t)
    with pytest.raises(InvalidInputError, match="`body.mass`"):
        simulate(types.SimpleNamespace(mass=-1.0, inertia=np.eye(3)), Q0, OMEGA0, t)
    with pytest.raises(InvalidInputError, match="`omega0`.*finite"):
        simulate(MOMENTS, Q0, [np.nan, 0.0, 0.0], t)
    with pytest.raises(InvalidInputError, match="`rotation0`.*finite"):
        simulate(MOMENTS, [np.nan, 0, 0, 1.0], OMEGA0, t)
    with pytest.raises(InvalidInputError, match=r"`rotation0` to have shape \(\.\.\., 4\)"):
        simulate(MOMENTS, [1.0, 0, 0], OMEGA0, t)
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        simulate(MOMENTS, Q0, OMEGA0, [0.0, 1.0, 1.0])
    with pytest.raises(InvalidInputError, match="`max_step` to be positive"):
        simulate(MOMENTS, Q0, OMEGA0, t, max_step=0.0)
    with pytest.raises(InvalidInputError, match="`max_step` to be a scalar"):
        simulate(MOMENTS, Q0, OMEGA0, t, max_step=[0.1, 0.2])
    with pytest.raises(InvalidInputError, match="`torque`.*finite"):
        simulate(MOMENTS, Q0, OMEGA0, t, torque=[np.inf, 0, 0])
    with pytest.raises(InvalidInputError, match="`omega0` .* to broadcast"):
        simulate(MOMENTS, Q0, np.ones((3, 3)), t, torque=np.ones((2, 3)))
    with pytest.raises(InvalidInputError, match="`order` to be one of 2, 4, 6, got 3"):
        simulate(MOMENTS, Q0, OMEGA0, t, order=3)
    with pytest.raises(InvalidInputError, match="`order` applies to method='midpoint'"):
        simulate(MOMENTS, Q0, OMEGA0, t, method="rk4", order=4)
    with pytest.raises(InvalidInputError, match="`solver`"):
        simulate(MOMENTS, Q0, OMEGA0, t, method="adaptive", solver="nope")


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4", "adaptive"])
def test_torque_returning_wrong_shape_or_nan(method):
    t = np.linspace(0.0, 1.0, 3)
    with pytest.raises(InvalidInputError, match=r"`torque` to return shape \(3,\).*got \(2,\)"):
        simulate(MOMENTS, Q0, OMEGA0, t, method=method, torque=lambda tn, r, w: [1.0, 2.0])
    with pytest.raises(InvalidInputError, match=r"`torque` to return shape \(4, 3\)"):
        simulate(
            MOMENTS, Q0, np.ones((4, 3)), t, method=method, torque=lambda tn, r, w: np.ones((2, 3))
        )
    with pytest.raises(InvalidTypeError, match="`torque` to return an array"):
        simulate(MOMENTS, Q0, OMEGA0, t, method=method, torque=lambda tn, r, w: {"x": 1})
    with pytest.raises(IntegrationError, match="`torque` returned NaN"):
        simulate(MOMENTS, Q0, OMEGA0, t, method=method, torque=lambda tn, r, w: np.full(3, np.nan))


def test_diverging_or_stiff_runs_raise_instead_of_returning_nan():
    t = np.linspace(0.0, 10.0, 11)
    sphere = np.ones(3)
    # stiff damping: explicit RK4 with c h / I = 50 explodes
    with pytest.raises(IntegrationError, match=r"rk4 integration diverged.*non-finite at t ="):
        simulate(sphere, Q0, OMEGA0, t, method="rk4", torque=lambda tn, r, w: -50.0 * w)
    # ... and the implicit step's fixed point on the torque cannot converge
    with pytest.raises(IntegrationError, match="did not converge at t = 0"):
        simulate(sphere, Q0, OMEGA0, t, torque=lambda tn, r, w: -50.0 * w)
    # finite-time blow-up w' = |w|^2 w / I: the adaptive solver stalls
    with pytest.raises(IntegrationError, match=r"adaptive integration \(DOP853\) failed after t ="):
        simulate(
            sphere, Q0, OMEGA0, t, method="adaptive", torque=lambda tn, r, w: np.sum(w * w) * w
        )
    # a free-body step so long (h |w| ~ 200) that Newton finds no root of the midpoint equation
    with pytest.raises(IntegrationError, match="implicit step did not converge after t = 0"):
        simulate([2.3, 2.5, 1.7], Q0, [1.0, 6.0, 1.0], [0.0, 32.0])
    # overflow inside the compiled step
    with pytest.raises(IntegrationError, match="midpoint integration diverged.*non-finite"):
        simulate(MOMENTS, Q0, [1e200, 1e200, 0.0], [0.0, 1.0])


def test_attitude_inputs_and_options_contract():
    """One contract: poinsot/SciPy Rotation or scalar-first quaternions; ``rtol``/``atol``
    only where the method has tolerances (never silently ignored)."""
    from scipy.spatial.transform import Rotation as SciRotation

    from poinsot import Rotation

    t = np.linspace(0.0, 1.0, 3)
    r0 = SciRotation.from_rotvec([0.5, -0.1, 0.3])
    q0 = r0.as_quat(scalar_first=True)
    ref = simulate(MOMENTS, q0, OMEGA0, t)
    for attitude in (r0, Rotation.from_quat(q0)):
        np.testing.assert_array_equal(simulate(MOMENTS, attitude, OMEGA0, t).quat, ref.quat)
    for method in ("midpoint", "splitting", "rk4"):
        # the tolerances apply to both adaptive methods (the refusal named 'adaptive' only,
        # though dop853 takes them: issue 39; now read from integrators.INTEGRATORS)
        both = "'dop853' or 'adaptive'"
        for option, takers in (("rtol", both), ("atol", both), ("solver", "'adaptive'")):
            value = "RK45" if option == "solver" else 1e-8
            with pytest.raises(InvalidInputError, match=f"`{option}` applies to method={takers} "):
                simulate(MOMENTS, q0, OMEGA0, t, method=method, **{option: value})
    simulate(MOMENTS, q0, OMEGA0, t, method="dop853", rtol=1e-8, atol=1e-10)  # taken
    with pytest.raises(InvalidTypeError, match="`rotation0`"):
        simulate(MOMENTS, {"w": 1.0}, OMEGA0, t)


@pytest.mark.parametrize(
    "torque",
    [
        None,
        ConstantBodyTorque([0.1, 0.0, 0.2]),
        ConstantSpaceTorque([0.0, 0.3, 0.0]),
        GravityTorque(mass=2.0, center_of_mass=[0.0, 0.0, 0.3], g=9.81),
        GravityGradientTorque([1.0, 2.0, 2.5], 1.0, [0.0, 0.6, 0.8], mu=0.5),
    ],
    ids=["free", "body", "space", "gravity", "gradient"],
)
def test_compiled_rk4_takes_the_same_steps_as_the_numpy_stages(torque):
    # Built-in torques run rk4 in one compiled loop per body; a Python callable takes
    # the NumPy stages. The same model both ways must give the same steps (to
    # round-off: the torque's rotation is evaluated in another order).
    moments, q0 = [1.0, 2.0, 2.5], Rotation.from_rotvec([0.2, -0.4, 0.1])
    w0 = [[0.3, 2.0, 0.1], [1.0, -0.2, 0.5]]
    t = np.linspace(0.0, 2.0, 21)
    fast = simulate(moments, q0, w0, t, method="rk4", max_step=1e-3, torque=torque)
    if torque is None:
        model = lambda t, att, w: np.zeros(np.shape(w))  # noqa: E731
    else:
        model = lambda t, att, w: torque.body_torque(t, att.as_quat(), w)  # noqa: E731
    slow = simulate(moments, q0, w0, t, method="rk4", max_step=1e-3, torque=model)
    assert fast.info["path"] == "compiled" and "NumPy" in slow.info["path"]
    assert fast.info["steps"] == slow.info["steps"] == 2000
    # observed: <= 1.1e-15 (omega) and 5e-16 (quaternion), host and generic CPU
    np.testing.assert_allclose(fast.omega, slow.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast.quat, slow.quat, rtol=0, atol=1e-12)
