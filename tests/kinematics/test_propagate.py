"""Attitude propagation (SPEC S5 task (a)): ``propagate`` against closed forms.

Oracles are independent of poinsot: SciPy's ``Rotation`` builds the exact
attitudes, and the coning motion ``L(t) = exp(A t/2) o exp(B t/2)`` has the
closed-form angular velocities (SPEC S5, ``w_xi = 2 L~ o L'``, ``w_x = 2 L' o L~``)

``w_xi(t) = R(B t)^T A + B``,    ``w_x(t) = A + R(A t) B``,

where ``R(v)`` is the rotation by the rotation vector ``v``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation as SR

import poinsot
from poinsot.errors import IntegrationError, InvalidInputError, InvalidTypeError
from poinsot.kinematics.propagation import propagate

A = np.array([0.3, -0.2, 1.1])
B = np.array([0.7, 0.5, -0.4])
T = 3.0


def coning_truth(t):
    """Exact attitude (as SciPy rotations) of the coning motion started at L = 1."""
    return SR.from_rotvec(np.outer(t, A)) * SR.from_rotvec(np.outer(t, B))


def w_body(t):
    return SR.from_rotvec(B * t).inv().apply(A) + B


def w_space(t):
    return A + SR.from_rotvec(A * t).apply(B)


W = {"body": w_body, "space": w_space}


def qdist(q, r):
    """Largest distance between quaternions and SciPy rotations, sign-blind."""
    qt = r.as_quat(scalar_first=True)
    d = np.minimum(np.linalg.norm(q - qt, axis=-1), np.linalg.norm(q + qt, axis=-1))
    return float(np.max(d))


def scipy_rot(q):
    return SR.from_quat(np.asarray(q), scalar_first=True)


def test_doc_example_quarter_turn():
    tr = propagate([1, 0, 0, 0], lambda t: [0.0, 0.0, 1.0], [0.0, np.pi / 2])
    assert isinstance(tr, poinsot.Trajectory)
    assert tr.rotation.shape == (2,)
    np.testing.assert_allclose(tr.rotation.apply([1.0, 0.0, 0.0])[-1], [0, 1, 0], atol=1e-15)
    assert tr.method == "magnus4"


# ----------------------------------------------------------------- constant omega


@pytest.mark.parametrize("method", ["exponential", "magnus4", "magnus6"])
@pytest.mark.parametrize("frame", ["body", "space"])
def test_constant_omega_closed_form_to_roundoff(method, frame):
    """Constant w: L(t) = L0 o exp(w t/2) (body) or exp(w t/2) o L0 (space), exactly."""
    rng = np.random.default_rng(1)
    q0 = rng.normal(size=4)
    w = np.array([2.0, -1.0, 3.5])
    t = np.sort(rng.uniform(0.0, 10.0, 200))
    tr = propagate(q0, lambda s: w, t, frame=frame, method=method)
    r0 = scipy_rot(q0)
    rw = SR.from_rotvec(np.outer(t - t[0], w))
    truth = r0 * rw if frame == "body" else rw * r0
    assert qdist(tr.quat, truth) < 1e-13  # 5.1e-15 observed
    # omega is returned in body axes: w_xi = L~ o w_x o L
    expect = np.broadcast_to(w, (len(t), 3)) if frame == "body" else truth.inv().apply(w)
    np.testing.assert_allclose(tr.omega, expect, atol=1e-13)


finite = st.floats(-5.0, 5.0, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(
    q0=st.lists(finite, min_size=4, max_size=4).filter(lambda q: np.linalg.norm(q) > 1e-3),
    w=st.lists(finite, min_size=3, max_size=3),
    dts=st.lists(st.floats(1e-3, 1.0), min_size=1, max_size=8),
    method=st.sampled_from(["exponential", "magnus4", "magnus6"]),
    frame=st.sampled_from(["body", "space"]),
)
def test_constant_omega_property(q0, w, dts, method, frame):
    """Any attitude, constant rate and time grid: the Lie-group methods are exact."""
    t = np.concatenate([[0.0], np.cumsum(dts)])
    tr = propagate(q0, lambda s: w, t, frame=frame, method=method)
    rw = SR.from_rotvec(np.outer(t, w))
    r0 = scipy_rot(q0)
    assert qdist(tr.quat, r0 * rw if frame == "body" else rw * r0) < 1e-13


def test_zero_omega_keeps_attitude():
    q0 = np.array([0.5, -0.5, 0.5, 0.5])
    for method in ("exponential", "magnus4", "magnus6", "rk4", "adaptive"):
        tr = propagate(q0, lambda s: np.zeros(3), np.linspace(0.0, 5.0, 11), method=method)
        np.testing.assert_allclose(tr.quat, np.broadcast_to(q0, (11, 4)), atol=1e-16)


@pytest.mark.parametrize(
    ("method", "kind", "order"),
    [("magnus6", "callable", 6), ("magnus6", "samples", 4), ("exponential", "samples", 1)],
)
def test_info_reports_steps_and_order(method, kind, order):
    t = np.linspace(0.0, 1.0, 6)
    w = w_body if kind == "callable" else np.array([w_body(s) for s in t])
    tr = propagate([1, 0, 0, 0], w, t, method=method, steps_per_sample=3)
    assert tr.info["order"] == order
    assert tr.info["steps"] == 15
    assert tr.info["omega_input"] == kind
    assert tr.info["frame"] == "body"


@pytest.mark.parametrize("frame", ["body", "space"])
def test_exact_with_piecewise_constant_samples_is_exact(frame):
    """Samples under method="exponential" are held on [t_k, t_{k+1}): a product of exponentials,
    L_{k+1} = L_k o exp(w_k h_k/2) (body) or exp(w_k h_k/2) o L_k (space)."""
    rng = np.random.default_rng(2)
    t = np.cumsum(rng.uniform(0.05, 0.3, 30))
    w = rng.normal(size=(30, 3))
    tr = propagate([1, 0, 0, 0], w, t, frame=frame, method="exponential", steps_per_sample=3)
    r = SR.identity()
    expect = [r]
    for k in range(29):
        step = SR.from_rotvec(w[k] * (t[k + 1] - t[k]))
        r = r * step if frame == "body" else step * r
        expect.append(r)
    expect = SR.concatenate(expect)
    assert qdist(tr.quat, expect) < 1e-14
    assert tr.info["interpolation"] == "zero-order hold"
    np.testing.assert_allclose(
        tr.omega, w if frame == "body" else expect.inv().apply(w), atol=1e-14
    )


# ----------------------------------------------------------------- coning motion


@pytest.mark.parametrize("frame", ["body", "space"])
@pytest.mark.parametrize(
    ("method", "tol"),
    [
        ("magnus4", 1e-9),
        ("magnus6", 1e-13),
        ("rk4", 1e-9),
        ("exponential", 2e-4),  # first order: 1.0e-5 observed
        ("adaptive", 1e-9),
    ],
)
def test_coning_motion_against_closed_form(frame, method, tol):
    t = np.linspace(0.0, T, 31)
    kw = {"max_step": 0.01} if method != "adaptive" else {}
    tr = propagate([1, 0, 0, 0], W[frame], t, frame=frame, method=method, **kw)
    assert qdist(tr.quat, coning_truth(t)) < tol
    np.testing.assert_allclose(tr.omega, np.array([w_body(s) for s in t]), atol=10 * tol)


@pytest.mark.parametrize("frame", ["body", "space"])
def test_adaptive_from_samples_and_tolerance(frame):
    t = np.linspace(0.0, T, 301)
    w = np.array([W[frame](s) for s in t])
    tr = propagate([1, 0, 0, 0], w, t, frame=frame, method="adaptive", rtol=1e-12, atol=1e-14)
    # error dominated by the cubic spline through samples spaced 0.01 apart (~h^4)
    assert qdist(tr.quat, coning_truth(t)) < 1e-8
    assert tr.info["evaluations"] > 0 and tr.info["interpolation"].startswith("cubic")
    loose = propagate([1, 0, 0, 0], W[frame], t, frame=frame, method="adaptive", rtol=1e-4)
    tight = propagate([1, 0, 0, 0], W[frame], t, frame=frame, method="adaptive", rtol=1e-12)
    assert qdist(tight.quat, coning_truth(t)) < qdist(loose.quat, coning_truth(t))
    assert tight.info["evaluations"] > loose.info["evaluations"]


def hamilton(p, q):
    """Hamilton product written out here, independently of poinsot (SPEC S1)."""
    p0, pv, q0, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[p0 * q0 - pv @ qv], p0 * qv + q0 * pv + np.cross(pv, qv)])


@pytest.mark.parametrize("frame", ["body", "space"])
@pytest.mark.parametrize("method", ["magnus4", "magnus6", "rk4"])
def test_generic_rates_against_tight_scipy_integration(frame, method):
    """A non-coning w(t) against SciPy's DOP853 at rtol 1e-13 on Poisson's equation."""
    from scipy.integrate import solve_ivp

    def w(s):
        return np.array([np.sin(1.3 * s), 2.0 * np.cos(0.7 * s), 0.5 * s - 1.0])

    def rhs(s, y):
        wq = np.concatenate([[0.0], w(s)])
        return 0.5 * (hamilton(y, wq) if frame == "body" else hamilton(wq, y))

    q0 = np.array([0.4, -0.2, 0.5, 0.74])
    q0 /= np.linalg.norm(q0)
    t = np.linspace(0.0, 4.0, 9)
    ref = solve_ivp(rhs, (0, 4), q0, method="DOP853", t_eval=t, rtol=1e-13, atol=1e-14).y.T
    tr = propagate(q0, w, t, frame=frame, method=method, max_step=0.005)
    assert qdist(tr.quat, scipy_rot(ref)) < (1e-11 if method == "magnus6" else 1e-9)


ORDERS = [
    ("exponential", "callable", 2),
    ("exponential", "samples", 1),
    ("rk4", "callable", 4),
    ("rk4", "samples", 4),
    ("magnus4", "callable", 4),
    ("magnus4", "samples", 4),
    ("magnus6", "callable", 6),
    ("magnus6", "samples", 4),  # limited by the cubic spline through the samples
]


@pytest.mark.parametrize("frame", ["body", "space"])
@pytest.mark.parametrize(("method", "kind", "order"), ORDERS)
def test_observed_order_matches_claim(frame, method, kind, order):
    """Halving h divides the global error by 2^p (coning motion, T = 3 s)."""
    errs = []
    # magnus6 through samples reaches its spline-limited order 4 from below: finer grids
    grids = (96, 192, 384) if (method, kind) == ("magnus6", "samples") else (24, 48, 96)
    for n in grids:
        t = np.linspace(0.0, T, n + 1)
        w = W[frame] if kind == "callable" else np.array([W[frame](s) for s in t])
        tr = propagate([1, 0, 0, 0], w, t, frame=frame, method=method)
        errs.append(qdist(tr.quat, coning_truth(t)))
    slopes = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    np.testing.assert_allclose(slopes, order, atol=0.15)


def test_magnus_beats_rk4_per_evaluation_on_fast_spin():
    """Lie-group steps keep the error bounded for a fast spin where RK4 degrades."""
    t = np.linspace(0.0, 10.0, 101)  # 10 rad/s spin: w h = 1 rad per step
    w = np.array([0.0, 0.0, 10.0])
    truth = SR.from_rotvec(np.outer(t, w))
    magnus = propagate([1, 0, 0, 0], lambda s: w, t, method="magnus4")
    rk4 = propagate([1, 0, 0, 0], lambda s: w, t, method="rk4")
    assert qdist(magnus.quat, truth) < 1e-13
    assert qdist(rk4.quat, truth) > 1e-4


# ----------------------------------------------------------------- invariants


@pytest.mark.parametrize("n_bodies", [3, 40])  # scan chaining / step-by-step chaining
@pytest.mark.parametrize("method", ["magnus4", "magnus6", "rk4", "exponential", "adaptive"])
def test_unit_norm_within_1e15(method, n_bodies):
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 20.0, 201)
    kw = {} if method == "adaptive" else {"steps_per_sample": 10}  # 2000 steps
    q0 = rng.normal(size=(n_bodies, 4)) * 5
    tr = propagate(q0, lambda s: [8.0 * np.sin(s), 5.0, -3.0], t, method=method, **kw)
    assert np.max(np.abs(np.linalg.norm(tr.quat, axis=-1) - 1.0)) <= 3e-15  # 1 ulp seen


@pytest.mark.parametrize("frame", ["body", "space"])
@pytest.mark.parametrize("method", ["magnus4", "magnus6", "rk4", "exponential"])
def test_constant_factor_invariance(frame, method):
    """SPEC S5: if L* solves the equation, so does L* o L0 (space) / L0 o L* (body)."""
    rng = np.random.default_rng(4)
    q0 = rng.normal(size=4)
    q0 /= np.linalg.norm(q0)
    t = np.linspace(0.0, T, 40)
    star = propagate([1, 0, 0, 0], W[frame], t, frame=frame, method=method)
    tr = propagate(q0, W[frame], t, frame=frame, method=method)
    rs, r0 = scipy_rot(star.quat), scipy_rot(q0)
    assert qdist(tr.quat, r0 * rs if frame == "body" else rs * r0) < 1e-14


@pytest.mark.parametrize("method", ["magnus4", "magnus6", "rk4", "adaptive"])
def test_space_and_body_frames_agree(method):
    """The same motion described by w_x or by w_xi = L~ o w_x o L gives the same L(t)."""
    t = np.linspace(0.0, T, 61)
    kw = {"steps_per_sample": 4} if method != "adaptive" else {}
    trb = propagate([1, 0, 0, 0], w_body, t, frame="body", method=method, **kw)
    trs = propagate([1, 0, 0, 0], w_space, t, frame="space", method=method, **kw)
    assert qdist(trb.quat, scipy_rot(trs.quat)) < 2e-9  # rk4: 1.2e-10 observed
    np.testing.assert_allclose(trs.omega, trb.omega, atol=1e-8)
    np.testing.assert_allclose(trs.omega_space, np.array([w_space(s) for s in t]), atol=1e-8)


@pytest.mark.parametrize("method", ["magnus4", "rk4", "exponential"])
def test_substeps_equal_finer_output_grid(method):
    """steps_per_sample=k on a grid equals one step per sample on the k-times finer grid."""
    fine = np.linspace(0.0, T, 4 * 15 + 1)
    coarse = fine[::4]
    a = propagate([1, 0, 0, 0], w_body, coarse, method=method, steps_per_sample=4)
    b = propagate([1, 0, 0, 0], w_body, fine, method=method)
    c = propagate([1, 0, 0, 0], w_body, coarse, method=method, max_step=T / 60)
    assert qdist(a.quat, scipy_rot(b.quat[::4])) < 1e-14
    assert qdist(c.quat, scipy_rot(a.quat)) < 1e-14
    assert a.info["steps"] == c.info["steps"] == 60
    np.testing.assert_allclose(a.info["step_size"], T / 60)


# ----------------------------------------------------------------- batches


def batch_omega(t):
    k = np.arange(1.0, 6.0)[:, None]
    return np.column_stack([np.sin(k[:, 0] * t), np.cos(t) * k[:, 0], 0.5 + 0 * k[:, 0]])


@pytest.mark.parametrize("n_bodies", [5, 40])  # both the scan and the per-step chaining
@pytest.mark.parametrize("method", ["magnus4", "magnus6", "rk4", "exponential", "adaptive"])
def test_batch_equals_loop(n_bodies, method):
    rng = np.random.default_rng(5)
    q0 = rng.normal(size=(n_bodies, 4))
    amp = rng.uniform(0.5, 3.0, (n_bodies, 3))

    def w_all(s):
        return amp * np.array([np.sin(s), np.cos(2 * s), 1.0])

    t = np.linspace(0.0, 2.0, 21)
    tr = propagate(q0, w_all, t, method=method, steps_per_sample=1 if method == "adaptive" else 3)
    assert tr.rotation.shape == (21, n_bodies)
    assert tr.omega.shape == (21, n_bodies, 3)
    tol = 1e-9 if method == "adaptive" else 1e-14
    for i in (0, n_bodies - 1):
        one = propagate(
            q0[i],
            lambda s, i=i: w_all(s)[i],
            t,
            method=method,
            steps_per_sample=1 if method == "adaptive" else 3,
        )
        assert qdist(tr.quat[:, i], scipy_rot(one.quat)) < tol
        np.testing.assert_allclose(tr.omega[:, i], one.omega, atol=1e-15)


def test_batch_shared_omega_and_samples():
    """A (3,)-valued callable or (n, 3) samples drive all bodies of a (N, 4) batch."""
    rng = np.random.default_rng(6)
    q0 = rng.normal(size=(4, 4))
    t = np.linspace(0.0, T, 41)
    shared = propagate(q0, w_body, t)
    samples = propagate(q0, np.array([w_body(s) for s in t]), t)
    per_body = propagate(q0, np.repeat(np.array([w_body(s) for s in t])[:, None], 4, 1), t)
    assert shared.rotation.shape == samples.rotation.shape == per_body.rotation.shape == (41, 4)
    for i in range(4):
        expect = scipy_rot(q0[i]) * coning_truth(t)
        assert qdist(shared.quat[:, i], expect) < 3e-6  # 2.1e-7 observed
    assert qdist(samples.quat.reshape(-1, 4), scipy_rot(per_body.quat.reshape(-1, 4))) < 1e-14
    # one q0 with per-body samples broadcasts to a batch
    one_q0 = propagate(q0[0], np.repeat(np.array([w_body(s) for s in t])[:, None], 4, 1), t)
    assert one_q0.rotation.shape == (41, 4)


def test_vectorized_callable_equals_scalar_calls():
    t = np.linspace(0.0, T, 50)

    def w_vec(s):
        return np.array([w_body(x) for x in np.atleast_1d(s)])

    a = propagate([1, 0, 0, 0], w_body, t, steps_per_sample=2)
    b = propagate([1, 0, 0, 0], w_vec, t, steps_per_sample=2, vectorized=True)
    np.testing.assert_allclose(b.quat, a.quat, atol=1e-15)
    np.testing.assert_allclose(b.omega, a.omega, atol=1e-15)


def test_rotation_input_and_normalisation():
    rng = np.random.default_rng(7)
    q0 = rng.normal(size=4)
    t = np.linspace(0.0, 1.0, 5)
    a = propagate(poinsot.Rotation.from_quat(q0), w_body, t)
    b = propagate(7.5 * q0, w_body, t)
    c = propagate(scipy_rot(q0), w_body, t)  # SciPy's Rotation (scalar-last inside)
    assert qdist(a.quat, scipy_rot(b.quat)) < 1e-14
    assert qdist(c.quat, scipy_rot(b.quat)) < 1e-14
    assert qdist(a.quat[:1], scipy_rot(q0)) < 1e-15


def test_single_time_returns_q0():
    tr = propagate([0, 0, 2, 0], w_body, [1.5])
    np.testing.assert_allclose(tr.quat, [[0, 0, 1, 0]])
    assert tr.rotation.shape == (1,)
    tr = propagate([0, 0, 2, 0], w_body, [1.5], method="adaptive")
    np.testing.assert_allclose(tr.quat, [[0, 0, 1, 0]])


# ----------------------------------------------------------------- bad input


def test_error_unknown_method_and_frame():
    with pytest.raises(InvalidInputError, match="Expected `method` to be one of"):
        propagate([1, 0, 0, 0], w_body, [0, 1], method="euler")
    with pytest.raises(InvalidInputError, match="Expected `frame` to be one of"):
        propagate([1, 0, 0, 0], w_body, [0, 1], frame="inertial")


def test_error_times():
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        propagate([1, 0, 0, 0], w_body, [0.0, 2.0, 1.0])
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\)"):
        propagate([1, 0, 0, 0], w_body, [[0.0, 1.0]])
    with pytest.raises(InvalidInputError, match="`t` to have at least 1 samples"):
        propagate([1, 0, 0, 0], w_body, [])
    with pytest.raises(InvalidInputError, match="`t` to contain only finite"):
        propagate([1, 0, 0, 0], w_body, [0.0, np.nan])


def test_error_q0():
    with pytest.raises(InvalidInputError, match="`rotation0` to be non-zero"):
        propagate([0, 0, 0, 0], w_body, [0, 1])
    with pytest.raises(InvalidInputError, match=r"`rotation0` to have shape \(\.\.\., 4\)"):
        propagate([1, 0, 0], w_body, [0, 1])
    with pytest.raises(InvalidInputError, match="batch .leading. shapes of `rotation0`"):
        propagate(np.ones((2, 3, 4)), lambda s: np.zeros((2, 3)), [0, 1])


def test_error_samples():
    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(InvalidInputError, match=r"`omega` samples to have shape \(len\(t\), 3\)"):
        propagate([1, 0, 0, 0], np.zeros((4, 3)), t)
    with pytest.raises(InvalidInputError, match=r"`omega` samples to have shape"):
        propagate([1, 0, 0, 0], np.zeros((5, 2)), t)
    with pytest.raises(InvalidInputError, match=r"`omega` samples to have shape"):
        propagate([1, 0, 0, 0], [1.0, 2.0, 3.0], t)
    w = np.zeros((5, 3))
    w[2, 1] = np.nan
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        propagate([1, 0, 0, 0], w, t)
    with pytest.raises(InvalidInputError, match="at least 4 samples of `omega`.*'magnus4'"):
        propagate([1, 0, 0, 0], np.zeros((3, 3)), t[:3])
    with pytest.raises(InvalidInputError, match="at least 2 samples of `omega`.*'exponential'"):
        propagate([1, 0, 0, 0], np.zeros((1, 3)), t[:1], method="exponential")
    with pytest.raises(InvalidInputError, match="batch .leading. shapes of `rotation0`"):
        propagate(np.ones((3, 4)), np.zeros((5, 2, 3)), t)
    with pytest.raises(InvalidTypeError, match="`omega` to be array-like"):
        propagate([1, 0, 0, 0], "fast", t)


def test_error_callable_output():
    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(InvalidInputError, match=r"`omega\(t\)` to return shape \(\.\.\., 3\)"):
        propagate([1, 0, 0, 0], lambda s: [1.0, 2.0], t)
    with pytest.raises(InvalidInputError, match=r"`omega\(t\)` to return only finite.*t = 0.5"):
        propagate([1, 0, 0, 0], lambda s: [0.0, np.nan if s >= 0.5 else 0.0, 0.0], t, method="rk4")
    with pytest.raises(InvalidInputError, match=r"`omega\(t\)` to return shape \(3,\) at every"):
        propagate([1, 0, 0, 0], lambda s: np.zeros((2, 3)) if s > 0.5 else np.zeros(3), t)
    with pytest.raises(InvalidTypeError, match=r"`omega\(t\)` to be array-like of"):
        propagate([1, 0, 0, 0], lambda s: ["a", "b", "c"], t)
    with pytest.raises(InvalidInputError, match="batch .leading. shapes of `rotation0`"):
        propagate(np.ones((3, 4)), lambda s: np.zeros((2, 3)), t)
    with pytest.raises(InvalidInputError, match=r"`vectorized=True` to return shape \(m, 3\)"):
        propagate([1, 0, 0, 0], lambda s: np.zeros(3), t, vectorized=True)
    with pytest.raises(
        InvalidInputError, match=r"`vectorized=True` to return shape \(\d+, 3\), got \(1, 3\)"
    ):
        propagate([1, 0, 0, 0], lambda s: np.zeros((1, 3)), t, vectorized=True)


def test_error_options():
    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(InvalidInputError, match="`steps_per_sample` to be an integer >= 1"):
        propagate([1, 0, 0, 0], w_body, t, steps_per_sample=0)
    with pytest.raises(InvalidTypeError, match="`steps_per_sample` to be an integer, got float"):
        propagate([1, 0, 0, 0], w_body, t, steps_per_sample=2.5)
    with pytest.raises(InvalidInputError, match="`max_step` to be positive"):
        propagate([1, 0, 0, 0], w_body, t, max_step=0.0)
    with pytest.raises(InvalidInputError, match="`rtol` and `atol` apply to method='adaptive'"):
        propagate([1, 0, 0, 0], w_body, t, rtol=1e-6)
    with pytest.raises(InvalidInputError, match="`steps_per_sample` applies to fixed-step"):
        propagate([1, 0, 0, 0], w_body, t, method="adaptive", steps_per_sample=3)
    with pytest.raises(InvalidInputError, match="`rtol` and `atol` to be positive"):
        propagate([1, 0, 0, 0], w_body, t, method="adaptive", atol=-1.0)
    with pytest.raises(InvalidTypeError, match="`vectorized` to be a bool"):
        propagate([1, 0, 0, 0], w_body, t, vectorized="yes")


def test_error_adaptive_failure_is_integration_error():
    """A rate so large that DOP853's step underflows: IntegrationError, not garbage."""
    with pytest.raises(IntegrationError, match="Adaptive attitude propagation failed"):
        propagate([1, 0, 0, 0], lambda s: [0.0, 0.0, 1e20], [1.0, 2.0], method="adaptive")


def test_exact_is_reserved_for_exact_solutions_and_scipy_rotations_are_converted():
    from scipy.spatial.transform import Rotation as SciRotation

    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(InvalidInputError, match="method='exact' means an exact solution only"):
        propagate([1, 0, 0, 0], lambda s: [0.0, 0.0, 1.0], t, method="exact")
    r0 = SciRotation.from_rotvec([0.2, -0.4, 1.0])
    a = propagate(r0, lambda s: [0.0, 0.0, 1.0], t)
    b = propagate(r0.as_quat(scalar_first=True), lambda s: [0.0, 0.0, 1.0], t)
    np.testing.assert_array_equal(a.quat, b.quat)
    # SciPy's own scalar-last order is never read as scalar-first
    assert not np.allclose(a.quat[0], r0.as_quat())
    with pytest.raises(InvalidInputError, match="rtol.*adaptive"):
        propagate(r0, lambda s: [0.0, 0.0, 1.0], t, rtol=1e-6)


@pytest.mark.parametrize("kind", ["callable", "samples", "vectorized"])
def test_any_leading_batch_shape_broadcasts_like_numpy(kind):
    """Batches along any leading axes (one contract): a (2, 3) batch of attitudes with a
    (3,) batch of angular velocities equals the six single-body runs."""
    rng = np.random.default_rng(3)
    q0 = rng.normal(size=(2, 3, 4))
    rates = rng.normal(size=(3, 3))
    t = np.linspace(0.0, 1.0, 6)

    def w_of(s):
        return rates * (1.0 + 0.3 * np.sin(s))

    if kind == "callable":
        tr = propagate(q0, w_of, t)
    elif kind == "vectorized":
        tr = propagate(q0, lambda s: np.stack([w_of(x) for x in s]), t, vectorized=True)
    else:
        tr = propagate(q0, np.stack([w_of(x) for x in t]), t)
    assert tr.quat.shape == (6, 2, 3, 4) and tr.omega.shape == (6, 2, 3, 3)
    for i in range(2):
        for j in range(3):
            if kind == "samples":
                one = propagate(q0[i, j], np.stack([w_of(x)[j] for x in t]), t)
            else:
                one = propagate(q0[i, j], lambda s, j=j: w_of(s)[j], t)
            np.testing.assert_allclose(tr.quat[:, i, j], one.quat, atol=1e-15)
            np.testing.assert_allclose(tr.omega[:, i, j], one.omega, atol=0)
