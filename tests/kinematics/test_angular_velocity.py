"""Angular velocity from attitude samples, and the C2 rotation spline (SPEC S5 (b)).

Truths: the closed-form motion ``R(t) = exp(t w1^) exp(t w2^)`` with
``w_xi = exp(-t w2^) w1 + w2``, ``eps_xi = w_xi' = -w2 x (exp(-t w2^) w1)``;
uniform rotation ``R0 exp(t w^)``; SciPy's ``RotationSpline`` as the oracle for
the shared construction.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation
from scipy.spatial.transform import RotationSpline as SciSpline

from poinsot import InvalidInputError, Rotation
from poinsot.kinematics.attitude_history import (
    RotationSpline,
    angular_velocity,
    fornberg_weights,
    rotation_spline,
)

W1 = np.array([0.3, -0.7, 1.1])
W2 = np.array([1.3, 0.4, -0.5])


def attitude(t) -> Rotation:
    t = np.asarray(t, dtype=float)[..., None]
    return Rotation.from_rotvec(t * W1) * Rotation.from_rotvec(t * W2)


def omega_body(t):
    return Rotation.from_rotvec(-np.asarray(t)[..., None] * W2).apply(W1) + W2


def alpha_body(t):
    return -np.cross(W2, Rotation.from_rotvec(-np.asarray(t)[..., None] * W2).apply(W1))


def grid(n, T=3.0):
    """A smoothly non-uniform grid on [0, T] (spacing varies by a factor ~3)."""
    s = np.linspace(0.0, 1.0, n)
    return T * (s + 0.08 * np.sin(2 * np.pi * s))


def flip_some(q, seed=0):
    q = np.array(q)
    q[np.random.default_rng(seed).random(q.shape[:-1]) < 0.4] *= -1
    return q


def rot_error(a: Rotation, b: Rotation):
    return (a.inv() * b).magnitude()


# --------------------------------------------------------------------------
# fornberg_weights
# --------------------------------------------------------------------------
def test_fornberg_classical_stencils():
    np.testing.assert_allclose(
        fornberg_weights(0.0, [-2, -1, 0, 1, 2]), [1 / 12, -2 / 3, 0, 2 / 3, -1 / 12], atol=1e-15
    )
    np.testing.assert_allclose(fornberg_weights(0.0, [-1, 0, 1], deriv=2), [1, -2, 1], atol=1e-15)
    np.testing.assert_allclose(fornberg_weights(0.0, [0, 1, 2]), [-1.5, 2, -0.5], atol=1e-15)


def test_fornberg_exact_for_polynomials_on_random_nodes():
    rng = np.random.default_rng(2)
    x = np.sort(rng.uniform(-1, 1, (10, 5)), axis=-1)
    x0 = rng.uniform(-1, 1, 10)
    coef = rng.normal(size=5)
    w = fornberg_weights(x0, x)
    f = np.polynomial.polynomial.polyval(x, coef)
    df = np.polynomial.polynomial.polyval(x0, np.polynomial.polynomial.polyder(coef))
    np.testing.assert_allclose(np.sum(w * f, -1), df, rtol=1e-9, atol=1e-9)


def test_fornberg_errors():
    with pytest.raises(InvalidInputError, match="`deriv` to be an integer in"):
        fornberg_weights(0.0, [0.0, 1.0], deriv=2)
    with pytest.raises(InvalidInputError, match="`x` to have distinct nodes"):
        fornberg_weights(0.0, [0.0, 1.0, 1.0])


# --------------------------------------------------------------------------
# angular_velocity
# --------------------------------------------------------------------------
@pytest.mark.parametrize("frame", ["body", "space"])
def test_uniform_rotation_is_exact_at_any_step(frame):
    """Constant omega: exact whatever the (large, non-uniform) step."""
    rng = np.random.default_rng(4)
    t = np.cumsum(rng.uniform(0.1, 0.4, 12))
    w = np.array([1.0, -2.0, 2.5])  # up to ~1.3 rad per step
    R0 = Rotation.random(rng=5)
    R = R0 * Rotation.from_rotvec(t[:, None] * w)
    expected = w if frame == "body" else R0.apply(w)
    got = angular_velocity(t, flip_some(R.as_quat()), frame=frame)
    np.testing.assert_allclose(got, np.broadcast_to(expected, got.shape), atol=1e-12)


@pytest.mark.parametrize("order, ratio", [(2, 4), (4, 16), (6, 64)])
def test_observed_order(order, ratio):
    """Halving h on a smooth non-uniform grid divides the error by ~2^order."""
    errs = []
    for n in (41, 81):
        t = grid(n)
        errs.append(np.abs(angular_velocity(t, attitude(t), order=order) - omega_body(t)).max())
    observed = errs[0] / errs[1]
    assert 0.7 * ratio < observed < 1.5 * ratio, (errs, observed)


def test_fourth_order_accuracy_figures():
    """Documented figure: 4.3e-6 rad/s with 81 samples over 3 s (|w| ~ 2 rad/s)."""
    t = grid(81)
    err = np.abs(angular_velocity(t, attitude(t)) - omega_body(t)).max()
    assert err < 5e-5


def test_sign_flips_and_inputs_agree():
    t = grid(30)
    R = attitude(t)
    a = angular_velocity(t, R)
    b = angular_velocity(t, flip_some(R.as_quat(), seed=3))
    c = angular_velocity(t, 2.5 * R.as_quat())  # non-unit quaternions are normalised
    np.testing.assert_allclose(b, a, atol=1e-14)
    np.testing.assert_allclose(c, a, atol=1e-14)
    np.testing.assert_allclose(angular_velocity(t, R, frame="space"), R.apply(a), atol=1e-14)
    d = angular_velocity(t, scipy_rot(R.as_quat()))  # a SciPy Rotation (scalar last inside)
    np.testing.assert_allclose(d, a, atol=1e-14)


def test_batch_of_bodies():
    t = grid(40)
    qa = attitude(t).as_quat()
    qb = (Rotation.from_rotvec([0.2, 0.0, 0.0]) * Rotation.from_rotvec(t[:, None] * W2)).as_quat()
    q = np.stack([qa, qb], axis=1)  # (n, 2, 4)
    w = angular_velocity(t, q)
    assert w.shape == (40, 2, 3)
    np.testing.assert_allclose(w[:, 0], angular_velocity(t, qa), atol=1e-15)
    np.testing.assert_allclose(w[:, 1], np.broadcast_to(W2, (40, 3)), atol=1e-12)


def test_more_than_half_turn_across_the_stencil():
    """Steps of 0.9 rad: a 5-point stencil spans 3.6 rad > pi; still exact."""
    t = np.arange(10) * 0.3
    w = np.array([0.0, 3.0, 0.0])
    got = angular_velocity(t, Rotation.from_rotvec(t[:, None] * w))
    np.testing.assert_allclose(got, np.broadcast_to(w, got.shape), atol=1e-12)


def test_angular_velocity_errors():
    t = np.linspace(0, 1, 6)
    q = attitude(t).as_quat()
    with pytest.raises(InvalidInputError, match="`rotations` to have 6 samples along axis 0"):
        angular_velocity(t, q[:5])
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        angular_velocity(t[::-1], q)
    with pytest.raises(InvalidInputError, match="`t` to have at least 5 samples, got 4"):
        angular_velocity(t[:4], q[:4])
    with pytest.raises(InvalidInputError, match="`t` to have at least 7 samples"):
        angular_velocity(t, q, order=6)
    q0 = q.copy()
    q0[2] = 0.0
    with pytest.raises(InvalidInputError, match="`rotations` to be non-zero"):
        angular_velocity(t, q0)
    with pytest.raises(InvalidInputError, match="`frame` to be one of"):
        angular_velocity(t, q, frame="world")
    with pytest.raises(InvalidInputError, match="`order` to be one of"):
        angular_velocity(t, q, order=3)
    with pytest.raises(InvalidInputError, match="a single rotation"):
        angular_velocity(t, Rotation.identity())
    with pytest.raises(InvalidInputError, match=r"`rotations` to have shape \(n, \.\.\., 4\)"):
        angular_velocity(t, [1.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\)"):
        angular_velocity(t[None], q)
    qn = q.copy()
    qn[1, 1] = np.nan
    with pytest.raises(InvalidInputError, match="`rotations` to contain only finite"):
        angular_velocity(t, qn)


# --------------------------------------------------------------------------
# rotation_spline
# --------------------------------------------------------------------------
def scipy_rot(q):
    return SciRotation.from_quat(np.asarray(q)[..., [1, 2, 3, 0]])


def test_chord_spline_matches_scipy():
    """Same construction and end rule as SciPy's RotationSpline: same curve."""
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.5, 1.5, 12))
    q = Rotation.from_rotvec(rng.normal(size=(12, 3)) * 0.5).as_quat()
    ref = SciSpline(t, scipy_rot(q))
    ours = rotation_spline(t, flip_some(q), end_omega="chord")
    tt = np.linspace(t[0] - 0.2, t[-1] + 0.2, 301)  # includes extrapolation
    rq = ref(tt).as_quat()[:, [3, 0, 1, 2]]
    assert np.max(1 - np.abs(np.sum(rq * ours.rotation(tt).as_quat(), -1))) < 1e-13
    # SciPy stops its fixed-point iteration at a relative change of 1e-9
    np.testing.assert_allclose(ours.omega(tt), ref(tt, 1), atol=1e-7)
    np.testing.assert_allclose(ours.alpha(tt), ref(tt, 2), atol=1e-6)
    np.testing.assert_allclose(ours(tt, 1), ref(tt, 1), atol=1e-7)


def test_large_steps_converge_to_scipys_fixed_point():
    """Random attitudes (steps up to ~pi): Newton converges where SciPy's default 10
    fixed-point iterations do not; SciPy iterated to convergence gives the same curve."""
    rng = np.random.default_rng(0)
    R = Rotation.random(30, rng=rng)
    t = np.cumsum(rng.uniform(0.1, 2, 30))
    ours = rotation_spline(t, R, end_omega="chord")

    class Converged(SciSpline):
        MAX_ITER = 1000
        TOL = 1e-14

    ref = Converged(t, scipy_rot(R.as_quat()))
    tt = np.linspace(t[0], t[-1], 500)
    np.testing.assert_allclose(ours.omega(tt), ref(tt, 1), atol=1e-8)
    np.testing.assert_allclose(ours.alpha(tt), ref(tt, 2), atol=1e-6)
    jump = np.abs(ours.alpha(t[1:-1] + 1e-9) - ours.alpha(t[1:-1] - 1e-9)).max()
    assert jump < 1e-4


def test_spline_non_convergence_is_reported(monkeypatch):
    import sys

    monkeypatch.setattr(sys.modules["poinsot.kinematics.attitude_history"], "_SPLINE_MAX_ITER", 1)
    rng = np.random.default_rng(0)
    R = Rotation.random(10, rng=rng)
    with pytest.raises(InvalidInputError, match="rotation_spline did not converge"):
        rotation_spline(np.arange(10.0), R)


def test_spline_passes_through_the_samples():
    t = grid(15)
    R = attitude(t)
    s = rotation_spline(t, R)
    assert np.max(rot_error(s.rotation(t), R)) < 1e-14
    assert isinstance(s, RotationSpline)
    assert t.flags.writeable and not s.t.flags.writeable  # the caller's array is untouched
    assert s(t[3]).shape == ()


def test_spline_is_c2():
    t = grid(15)
    s = rotation_spline(t, attitude(t))
    e = 1e-9  # a jump of a continuous f is ~2 e |f'| (3.7e-9 for omega)
    knots = t[1:-1]
    for f, tol in ((s.omega, 1e-6), (s.alpha, 1e-5)):
        jump = np.abs(f(knots + e) - f(knots - e)).max()
        assert jump < tol
    # and alpha is the derivative of omega (both frames)
    tm = np.linspace(0.1, 2.9, 6)  # off the knots (1.5 is one): there the difference is O(h)
    h = 1e-5
    for frame in ("body", "space"):
        fd = (s.omega(tm + h, frame=frame) - s.omega(tm - h, frame=frame)) / (2 * h)
        np.testing.assert_allclose(s.alpha(tm, frame=frame), fd, atol=1e-7)


def test_spline_uniform_rotation_exact():
    t = np.linspace(0, 2, 7)
    w = np.array([0.5, -1.0, 2.0])
    R0 = Rotation.random(rng=8)
    s = rotation_spline(t, R0 * Rotation.from_rotvec(t[:, None] * w))
    tt = np.linspace(0, 2, 41)
    np.testing.assert_allclose(s.omega(tt), np.broadcast_to(w, (41, 3)), atol=1e-12)
    np.testing.assert_allclose(
        s.omega(tt, frame="space"), np.broadcast_to(R0.apply(w), (41, 3)), atol=1e-12
    )
    np.testing.assert_allclose(s.alpha(tt), 0.0, atol=1e-11)


def spline_errors(s, tt):
    if isinstance(s, SciSpline):
        att = Rotation.from_quat(s(tt).as_quat(), scalar_first=False)
        w, a = s(tt, 1), s(tt, 2)
    else:
        att, w, a = s.rotation(tt), s.omega(tt), s.alpha(tt)
    return np.array(
        [
            rot_error(att, attitude(tt)).max(),
            np.abs(w - omega_body(tt)).max(),
            np.abs(a - alpha_body(tt)).max(),
        ]
    )


def test_spline_beats_scipy_and_converges():
    """Figures (n = 20 -> 40 over 3 s): attitude ~O(h^4), omega ~O(h^3), alpha ~O(h^2);
    SciPy's chord end rule limits it to O(h^2), O(h) and no convergence of alpha."""
    tt = np.linspace(0, 3, 1001)
    ours, scipy = [], []
    for n in (20, 40):
        t = np.linspace(0, 3, n)
        R = attitude(t)
        ours.append(spline_errors(rotation_spline(t, R), tt))
        scipy.append(spline_errors(SciSpline(t, scipy_rot(R.as_quat())), tt))
    ours, scipy = np.array(ours), np.array(scipy)
    assert np.all(ours[1] * 100 < scipy[1])  # >100x better at n = 40
    rate = ours[0] / ours[1]
    assert rate[0] > 12 and rate[1] > 6 and rate[2] > 3, rate


def test_clamped_with_exact_end_omega():
    t = np.linspace(0, 3, 20)
    R = attitude(t)
    ends = np.stack([omega_body(t[0]), omega_body(t[-1])])
    s = rotation_spline(t, R, end_omega=ends)
    np.testing.assert_allclose(s.omega(t[[0, -1]]), ends, atol=1e-14)
    tt = np.linspace(0, 3, 301)
    assert spline_errors(s, tt)[1] < 1e-3


def test_spline_small_data():
    t = np.array([0.0, 1.0])
    R = Rotation.from_rotvec([[0, 0, 0], [0, 0, 0.5]])
    s = rotation_spline(t, R)
    np.testing.assert_allclose(s.omega([0.0, 0.5, 1.0]), [[0, 0, 0.5]] * 3, atol=1e-15)
    t3 = np.array([0.0, 1.0, 2.5])
    s3 = rotation_spline(t3, attitude(t3))  # 2nd-order end estimate
    assert np.max(rot_error(s3.rotation(t3), attitude(t3))) < 1e-14


def test_spline_errors():
    t = np.linspace(0, 1, 6)
    q = attitude(t).as_quat()
    with pytest.raises(InvalidInputError, match="`t` to have at least 2 samples"):
        rotation_spline(t[:1], q[:1])
    with pytest.raises(InvalidInputError, match="`rotations` to have 6 samples"):
        rotation_spline(t, q[:4])
    with pytest.raises(InvalidInputError, match=r"`rotations` to have shape \(n, 4\)"):
        rotation_spline(t, np.stack([q, q], 1))
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        rotation_spline(np.r_[0.0, 0.0, 1, 2, 3, 4], q)
    with pytest.raises(InvalidInputError, match="`end_omega` to be one of"):
        rotation_spline(t, q, end_omega="natural")
    with pytest.raises(InvalidInputError, match=r"`end_omega` to have shape \(2, 3\)"):
        rotation_spline(t, q, end_omega=np.zeros((3, 3)))
    s = rotation_spline(t, q)
    with pytest.raises(InvalidInputError, match="`order` to be 0, 1 or 2"):
        s(0.5, order=3)
    with pytest.raises(InvalidInputError, match="`frame` to be one of"):
        s.omega(0.5, frame="inertial")
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(\) or \(m,\)"):
        s.alpha(np.zeros((2, 2)))
