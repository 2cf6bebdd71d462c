"""Kinematic equations of every representation (SPEC S3, S5).

Truth: the closed-form motion ``R(t) = exp(t w1^) exp(t w2^)``, whose angular
velocity is ``w_xi(t) = exp(-t w2^) w1 + w2`` (body) and
``w_x(t) = w1 + exp(t w1^) w2`` (space) -- differentiate ``R`` by the product
rule. Every rate is compared with a central finite difference of the
representation along this motion, and the error must behave like ``h^2``
(halving ``h`` divides it by ~4).
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import (
    GimbalLockWarning,
    InvalidInputError,
    InvalidTypeError,
    Rotation,
    SingularityWarning,
)
from poinsot import quaternion as Q
from poinsot.kinematics import rates as K

W1 = np.array([0.3, -0.7, 1.1])
W2 = np.array([1.3, 0.4, -0.5])
T0 = 0.37


def attitude(t) -> Rotation:
    t = np.asarray(t, dtype=float)
    return Rotation.from_rotvec(t[..., None] * W1) * Rotation.from_rotvec(t[..., None] * W2)


def quat(t) -> np.ndarray:
    """Continuous (not canonicalised) quaternion path ``exp(t w1/2) o exp(t w2/2)``."""
    t = np.asarray(t, dtype=float)[..., None]
    return Q.multiply(
        Q.exp(np.concatenate([0 * t, 0.5 * t * W1], -1)),
        Q.exp(np.concatenate([0 * t, 0.5 * t * W2], -1)),
    )


def omega_body(t) -> np.ndarray:
    return Rotation.from_rotvec(-np.asarray(t)[..., None] * W2).apply(W1) + W2


def omega_space(t) -> np.ndarray:
    return W1 + Rotation.from_rotvec(np.asarray(t)[..., None] * W1).apply(W2)


OMEGA = {"body": omega_body, "space": omega_space}


def central(f, t, h):
    return (f(t + h) - f(t - h)) / (2 * h)


def assert_second_order(err_of_h, h=2e-2):
    """Error at h and h/2: must be small and shrink by ~4 (central difference)."""
    e1, e2 = err_of_h(h), err_of_h(h / 2)
    assert e2 < 2e-3  # 1.05e-4 observed (dcm rate)
    assert 3.6 < e1 / e2 < 4.4, (e1, e2)


# --------------------------------------------------------------------------
# quaternion
# --------------------------------------------------------------------------
@pytest.mark.parametrize("frame", ["body", "space"])
def test_quat_rate_matches_central_difference(frame):
    q, w = quat(T0), OMEGA[frame](T0)
    qdot = K.quat_rate(q, w, frame=frame)
    assert_second_order(lambda h: np.abs(central(quat, T0, h) - qdot).max())


@pytest.mark.parametrize("frame", ["body", "space"])
def test_omega_from_quat_rate_matches_closed_form(frame):
    q, w = quat(T0), OMEGA[frame](T0)
    assert_second_order(
        lambda h: np.abs(K.omega_from_quat_rate(q, central(quat, T0, h), frame=frame) - w).max()
    )


def test_quat_rate_frames_agree_and_are_tangent():
    """SPEC S5: 1/2 L o w_xi = 1/2 w_x o L with w_x = R w_xi; q . q' = 0."""
    ts = np.linspace(0, 2, 7)
    q = quat(ts)
    a = K.quat_rate(q, omega_body(ts), frame="body")
    b = K.quat_rate(q, omega_space(ts), frame="space")
    np.testing.assert_allclose(a, b, atol=1e-14)
    np.testing.assert_allclose(np.einsum("...i,...i", q, a), 0.0, atol=5e-15)


def test_quat_rate_accepts_rotation_and_broadcasts():
    R = Rotation.random((5, 3), rng=1)
    w = np.array([0.1, 0.2, 0.3])
    qd = K.quat_rate(R, w)
    assert qd.shape == (5, 3, 4)
    np.testing.assert_allclose(K.omega_from_quat_rate(R, qd), np.broadcast_to(w, (5, 3, 3)))
    np.testing.assert_allclose(
        K.omega_from_quat_rate(R.as_quat(), qd, frame="space"), R.apply(w), atol=1e-14
    )
    sci = SciRotation.from_quat(R.as_quat().reshape(-1, 4), scalar_first=True)  # (N,): any SciPy
    np.testing.assert_allclose(K.quat_rate(sci, w), qd.reshape(-1, 4), atol=1e-15)


def test_non_unit_quaternion_is_normalised():
    q = quat(T0)
    w = omega_body(T0)
    np.testing.assert_allclose(K.quat_rate(3.0 * q, w), K.quat_rate(q, w), atol=1e-15)
    qd = K.quat_rate(q, w)
    np.testing.assert_allclose(K.omega_from_quat_rate(3.0 * q, qd), w, atol=1e-14)


def test_quat_errors():
    with pytest.raises(InvalidInputError, match="`q` to be non-zero"):
        K.quat_rate([0, 0, 0, 0], [1, 2, 3])
    with pytest.raises(InvalidInputError, match=r"`q` to have shape \(\.\.\., 4\)"):
        K.quat_rate([1, 0, 0], [1, 2, 3])
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        K.quat_rate([1, 0, 0, 0], [np.nan, 2, 3])
    with pytest.raises(InvalidInputError, match="`frame` to be one of 'body', 'space'"):
        K.quat_rate([1, 0, 0, 0], [1, 2, 3], frame="inertial")
    with pytest.raises(InvalidInputError, match=r"`qdot` to have shape \(\.\.\., 4\)"):
        K.omega_from_quat_rate([1, 0, 0, 0], [1, 2, 3])


# --------------------------------------------------------------------------
# direction cosine matrix
# --------------------------------------------------------------------------
def matrix(t):
    return attitude(t).as_matrix()


@pytest.mark.parametrize("frame", ["body", "space"])
def test_dcm_rate_matches_central_difference(frame):
    C, w = matrix(T0), OMEGA[frame](T0)
    Cdot = K.dcm_rate(C, w, frame=frame)
    assert_second_order(lambda h: np.abs(central(matrix, T0, h) - Cdot).max())
    assert_second_order(
        lambda h: np.abs(K.omega_from_dcm_rate(C, central(matrix, T0, h), frame=frame) - w).max()
    )


def test_dcm_columns_obey_poisson():
    """SPEC S5: each column moves as a_k' = w_x x a_k."""
    C, w = matrix(T0), omega_space(T0)
    Cdot = K.dcm_rate(C, w, frame="space")
    np.testing.assert_allclose(Cdot, np.cross(w, C.T).T, atol=1e-14)


def test_dcm_errors():
    with pytest.raises(InvalidInputError, match="`C` to be rotation matrices"):
        K.dcm_rate(np.diag([1.0, 1.0, 1.1]), [1, 2, 3])
    with pytest.raises(InvalidInputError, match="`C` to be rotation matrices"):
        K.omega_from_dcm_rate(np.diag([1.0, 1.0, -1.0]), np.zeros((3, 3)))
    with pytest.raises(InvalidInputError, match=r"`Cdot` to have shape \(\.\.\., 3, 3\)"):
        K.omega_from_dcm_rate(np.eye(3), np.zeros(3))
    with pytest.raises(InvalidInputError, match="`frame`"):
        K.dcm_rate(np.eye(3), [1, 2, 3], frame="fixed")


# --------------------------------------------------------------------------
# Euler angles, all 12 sequences
# --------------------------------------------------------------------------
PROPER = ["ZXZ", "XYX", "YZY", "ZYZ", "XZX", "YXY"]
TAIT = ["XYZ", "YZX", "ZXY", "XZY", "ZYX", "YXZ"]
SEQS = PROPER + TAIT + [s.lower() for s in PROPER + TAIT] + ["euler", "krylov"]


def euler_path(seq):
    """Smooth angles away from gimbal lock, and their exact rates."""
    proper = seq.lower() in [s.lower() for s in PROPER] or seq == "euler"
    a0 = np.array([0.4, 1.1 if proper else 0.5, -0.8])
    a1 = np.array([0.9, -0.3, 1.7])
    a2 = np.array([-0.5, 0.2, 0.6])

    def angles(t):
        t = np.asarray(t, dtype=float)[..., None]
        return a0 + a1 * t + a2 * t**2

    def rates(t):
        return a1 + 2 * a2 * np.asarray(t, dtype=float)[..., None]

    return angles, rates


@pytest.mark.parametrize("seq", SEQS)
@pytest.mark.parametrize("frame", ["body", "space"])
def test_euler_rates_match_finite_difference(seq, frame):
    angles, rates = euler_path(seq)
    ts = np.array([0.0, 0.3, 0.8])

    def q(t):
        return Rotation.from_euler(seq, angles(t)).as_quat()

    h = 1e-4
    q_now = q(ts)
    qd = central(q, ts, h)
    qd = qd * np.sign(np.einsum("...i,...i", q(ts + h), q(ts - h)))[..., None]
    w_fd = K.omega_from_quat_rate(q_now, qd, frame=frame)
    w = K.omega_from_euler_rates(seq, angles(ts), rates(ts), frame=frame)
    np.testing.assert_allclose(w, w_fd, atol=1e-7)
    np.testing.assert_allclose(
        K.euler_rates(seq, angles(ts), w, frame=frame), rates(ts), atol=1e-12
    )


@pytest.mark.parametrize("seq", ["ZXZ", "zyx", "krylov"])
def test_euler_rates_second_order(seq):
    angles, rates = euler_path(seq)

    def q(t):
        return Rotation.from_euler(seq, angles(t)).as_quat()

    w = K.omega_from_euler_rates(seq, angles(T0), rates(T0))
    assert_second_order(
        lambda h: np.abs(K.omega_from_quat_rate(q(T0), central(q, T0, h)) - w).max()
    )


def test_euler_preset_is_spec_s3_exactly():
    """SPEC S3 (z-x-z, body rates (p, q, r)), both directions, random points."""
    rng = np.random.default_rng(3)
    ang = rng.uniform([-np.pi, 0.2, -np.pi], [np.pi, np.pi - 0.2, np.pi], (50, 3))
    dot = rng.normal(size=(50, 3))
    psi, th, ph = ang.T
    dpsi, dth, dph = dot.T
    p = dpsi * np.sin(th) * np.sin(ph) + dth * np.cos(ph)
    q = dpsi * np.sin(th) * np.cos(ph) - dth * np.sin(ph)
    r = dpsi * np.cos(th) + dph
    w = np.stack([p, q, r], -1)
    np.testing.assert_allclose(K.omega_from_euler_rates("euler", ang, dot), w, atol=1e-14)
    s = p * np.sin(ph) + q * np.cos(ph)
    expected = np.stack([s / np.sin(th), p * np.cos(ph) - q * np.sin(ph), r - s / np.tan(th)], -1)
    np.testing.assert_allclose(K.euler_rates("euler", ang, w), expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(expected, dot, rtol=1e-10, atol=1e-10)


def test_euler_preset_symbolic():
    """The body-frame matrix of z-x-z from SymPy's C^T C' (independent derivation)."""
    sp = pytest.importorskip("sympy")
    t = sp.symbols("t")
    psi, th, ph = (sp.Function(n)(t) for n in ("psi", "theta", "phi"))
    Rz = lambda a: sp.rot_axis3(-a)  # noqa: E731  (sympy's rot_axis3 is passive)
    Rx = lambda a: sp.rot_axis1(-a)  # noqa: E731
    C = Rz(psi) * Rx(th) * Rz(ph)
    W = C.T * C.diff(t)
    w = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    vals = {psi: 0.3, th: 0.9, ph: -1.2}
    rates = {psi.diff(t): 0.7, th.diff(t): -0.4, ph.diff(t): 1.9}
    num = np.array(w.subs(rates).subs(vals).evalf(30), dtype=float).ravel()
    ours = K.omega_from_euler_rates("euler", [0.3, 0.9, -1.2], [0.7, -0.4, 1.9])
    np.testing.assert_allclose(ours, num, atol=1e-14)


@pytest.mark.parametrize("abc", ["ZXY", "XYX", "YZX"])
def test_intrinsic_equals_reversed_extrinsic(abc):
    """SPEC S3: intrinsic abc (f1, f2, f3) is extrinsic cba (f3, f2, f1)."""
    a, r = np.array([0.3, 0.6, -1.0]), np.array([1.0, -2.0, 0.5])
    for frame in ("body", "space"):
        np.testing.assert_allclose(
            K.omega_from_euler_rates(abc, a, r, frame=frame),
            K.omega_from_euler_rates(abc[::-1].lower(), a[::-1], r[::-1], frame=frame),
            atol=1e-15,
        )


def test_euler_degrees():
    """degrees=True: angles in deg, angle rates in deg/s, omega always rad/s."""
    a, r = np.array([10.0, 35.0, -70.0]), np.array([20.0, -5.0, 90.0])
    w = K.omega_from_euler_rates("XYZ", a, r, degrees=True)
    np.testing.assert_allclose(
        w, K.omega_from_euler_rates("XYZ", np.deg2rad(a), np.deg2rad(r)), atol=1e-15
    )
    np.testing.assert_allclose(K.euler_rates("XYZ", a, w, degrees=True), r, atol=1e-12)
    M = K.euler_rate_matrix("XYZ", a, degrees=True)
    np.testing.assert_allclose(M @ np.deg2rad(r), w, atol=1e-15)


@pytest.mark.parametrize(
    "seq, lock",
    [
        ("euler", [0.3, 0.0, 0.2]),
        ("zyx", [0.3, np.pi / 2, 0.2]),
        ("XZX", [0.1, np.pi, 2.0]),
        ("krylov", [0.0, -np.pi / 2, 1.0]),
    ],
)
def test_gimbal_lock(seq, lock):
    w = [0.1, 0.2, 0.3]
    with pytest.raises(InvalidInputError, match="gimbal lock"):
        K.euler_rates(seq, lock, w)
    near = np.array(lock) + [0.0, 1e-4, 0.0]
    with pytest.warns(GimbalLockWarning):
        rates = K.euler_rates(seq, near, w)
    assert np.all(np.isfinite(rates))
    # and the rates are still right: they reproduce omega
    np.testing.assert_allclose(K.omega_from_euler_rates(seq, near, rates), w, atol=1e-10)
    # the forward map is never singular
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.all(np.isfinite(K.omega_from_euler_rates(seq, lock, [1.0, 2.0, 3.0])))
        K.euler_rates(seq, np.array(lock) + [0.0, 0.01, 0.0], w)  # far enough: silent


def test_euler_batch_shapes():
    """Batched angles: every entry's rates reproduce omega through SciPy's matrices
    (central difference of C(angles + s rates): C^T C' = w_b^, C' C^T = w_n^)."""
    ang = np.random.default_rng(0).uniform(0.2, 1.2, (4, 2, 3))
    w_b = np.array([1.0, 0.0, 0.0])
    rates = K.euler_rates("ZYZ", ang, w_b)
    assert rates.shape == (4, 2, 3)
    m_space = K.euler_rate_matrix("ZYZ", ang, frame="space")
    assert m_space.shape == (4, 2, 3, 3)
    h = 5e-4  # fourth-order differences: ~2e-12 from the truth (second order, 1e-5: 2.6e-10)
    for idx in np.ndindex(4, 2):

        def c(s, idx=idx):
            return SciRotation.from_euler("ZYZ", ang[idx] + s * rates[idx]).as_matrix()

        dc = (8 * (c(h) - c(-h)) - (c(2 * h) - c(-2 * h))) / (12 * h)
        wb_hat, wn_hat = c(0.0).T @ dc, dc @ c(0.0).T
        np.testing.assert_allclose(wb_hat[[2, 0, 1], [1, 2, 0]], w_b, atol=1e-9)
        wn = wn_hat[[2, 0, 1], [1, 2, 0]]
        np.testing.assert_allclose(m_space[idx] @ rates[idx], wn, atol=1e-9)
        np.testing.assert_allclose(wn, c(0.0) @ w_b, atol=1e-9)


def test_euler_errors():
    with pytest.raises(InvalidInputError, match="`seq`"):
        K.euler_rates("ZZX", [0.1, 0.2, 0.3], [1, 2, 3])
    with pytest.raises(InvalidInputError, match="`seq` to have 3 axes"):
        K.omega_from_euler_rates("ZX", [0.1, 0.2, 0.3], [1, 2, 3])
    with pytest.raises(InvalidTypeError, match="`seq` to be a string, got int"):
        K.euler_rates(3, [0.1, 0.2, 0.3], [1, 2, 3])
    with pytest.raises(InvalidInputError, match=r"`angles` to have shape \(\.\.\., 3\)"):
        K.euler_rates("ZXZ", [0.1, 0.2], [1, 2, 3])
    with pytest.raises(InvalidInputError, match="`rates` to contain only finite"):
        K.omega_from_euler_rates("ZXZ", [0.1, 0.2, 0.3], [1, np.inf, 3])
    with pytest.raises(InvalidInputError, match="`omega`"):
        K.euler_rates("ZXZ", [0.1, 0.2, 0.3], [1, 2])
    with pytest.raises(InvalidInputError, match="`frame`"):
        K.euler_rates("ZXZ", [0.1, 0.2, 0.3], [1, 2, 3], frame="Body")


# --------------------------------------------------------------------------
# Gibbs, MRP, rotation vector
# --------------------------------------------------------------------------
def gibbs(t):
    return attitude(t).as_gibbs()


def mrp(t):
    return attitude(t).as_mrp()


def rotvec(t):
    return attitude(t).as_rotvec()


PARAMS = {
    "gibbs": (gibbs, K.gibbs_rate, K.omega_from_gibbs_rate),
    "mrp": (mrp, K.mrp_rate, K.omega_from_mrp_rate),
    "rotvec": (rotvec, K.rotvec_rate, K.omega_from_rotvec_rate),
}


@pytest.mark.parametrize("name", list(PARAMS))
@pytest.mark.parametrize("frame", ["body", "space"])
@pytest.mark.parametrize("t", [T0, 1.1])
def test_parameter_rates_match_finite_difference(name, frame, t):
    path, rate, inverse = PARAMS[name]
    x, w = path(t), OMEGA[frame](t)
    xdot = rate(x, w, frame=frame)
    assert_second_order(lambda h: np.abs(central(path, t, h) - xdot).max())
    assert_second_order(lambda h: np.abs(inverse(x, central(path, t, h), frame=frame) - w).max())


@pytest.mark.parametrize("name", list(PARAMS))
@pytest.mark.parametrize("frame", ["body", "space"])
def test_parameter_rates_round_trip_batched(name, frame):
    _, rate, inverse = PARAMS[name]
    rng = np.random.default_rng(5)
    x = rng.normal(size=(6, 2, 3)) * 0.8
    w = rng.normal(size=(2, 3))
    np.testing.assert_allclose(
        inverse(x, rate(x, w, frame=frame), frame=frame), np.broadcast_to(w, x.shape), atol=1e-13
    )


def test_mrp_shadow_set_obeys_same_equation():
    """The shadow path p_s(t) = -p/|p|^2 satisfies the same kinematic equation."""

    def shadow(t):
        return K.mrp_shadow(mrp(t))

    t = 1.1
    for frame in ("body", "space"):
        ps = shadow(t)
        assert np.linalg.norm(ps) > 1
        pdot = K.mrp_rate(ps, OMEGA[frame](t), frame=frame)
        assert_second_order(lambda h, pd=pdot: np.abs(central(shadow, t, h) - pd).max(), h=4e-3)
    # same rotation
    p = mrp(T0)
    assert Rotation.from_mrp(K.mrp_shadow(p)).approx_equal(Rotation.from_mrp(p), atol=1e-14)


def test_mrp_switch():
    p = np.array([[0.0, 0.0, 2.0], [0.3, 0.0, 0.0], [0.0, 1.0, 0.0]])
    out = K.mrp_switch(p)
    np.testing.assert_allclose(out, [[0, 0, -0.5], [0.3, 0, 0], [0, 1, 0]])
    assert np.all(Rotation.from_mrp(out).approx_equal(Rotation.from_mrp(p), atol=1e-14))
    np.testing.assert_allclose(K.mrp_switch(p, threshold=3.0), p)
    with pytest.raises(InvalidInputError, match="`threshold` to be a number >= 1"):
        K.mrp_switch(p, threshold=0.5)
    with pytest.raises(InvalidInputError, match="`p` to be non-zero"):
        K.mrp_shadow([0.0, 0.0, 0.0])


def test_gibbs_rate_equals_quaternion_rate():
    """g = l/l0: g' = l'/l0 - l l0'/l0^2 with l' from SPEC S5 (independent route)."""
    rng = np.random.default_rng(9)
    q = Rotation.random(20, rng=rng).as_quat(canonical=True)
    w = rng.normal(size=(20, 3))
    for frame in ("body", "space"):
        qd = K.quat_rate(q, w, frame=frame)
        g_dot = qd[:, 1:] / q[:, :1] - q[:, 1:] * qd[:, :1] / q[:, :1] ** 2
        np.testing.assert_allclose(
            K.gibbs_rate(q[:, 1:] / q[:, :1], w, frame=frame), g_dot, rtol=1e-11, atol=1e-11
        )


def test_rotvec_coefficients_against_mpmath():
    """The closed forms and the Taylor series (below 0.1 rad) against 50-digit values."""
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 50
    fs = [1e-9, 1e-4, 0.05, 0.1 - 1e-12, 0.1, 0.1 + 1e-12, 0.7, 2.0, 3.1, 5.0]
    c, k1, k2 = K._rotvec_coefficients(np.array(fs))
    for i, f in enumerate(fs):
        x = mpmath.mpf(f)
        assert c[i] == pytest.approx(float((1 - x / 2 * mpmath.cot(x / 2)) / x**2), rel=1e-13)
        assert k1[i] == pytest.approx(float((1 - mpmath.cos(x)) / x**2), rel=1e-13)
        assert k2[i] == pytest.approx(float((x - mpmath.sin(x)) / x**3), rel=1e-13)


def test_rotvec_rate_small_angles():
    """Near phi = 0: phi' -> w + s/2 phi x w (+ O(phi^2))."""
    w = np.array([0.2, -1.0, 0.5])
    phi = np.array([1e-10, 2e-10, -1e-10])
    for frame, s in (("body", 1), ("space", -1)):
        np.testing.assert_allclose(
            K.rotvec_rate(phi, w, frame=frame), w + s * 0.5 * np.cross(phi, w), rtol=0, atol=1e-16
        )
    np.testing.assert_allclose(K.rotvec_rate(np.zeros(3), w), w)
    np.testing.assert_allclose(K.omega_from_rotvec_rate(np.zeros(3), w), w)


def test_rotvec_rate_near_two_pi():
    w = [0.1, 0.2, 0.3]
    with pytest.warns(SingularityWarning, match="2 pi"):
        K.rotvec_rate([0.0, 0.0, 2 * np.pi - 1e-3], w)
    with pytest.raises(InvalidInputError, match="`rotvec` to have a norm different"):
        K.rotvec_rate([0.0, 0.0, 2 * np.pi], w)


@pytest.mark.parametrize(
    "fn, args",
    [
        (K.gibbs_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.omega_from_gibbs_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.mrp_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.omega_from_mrp_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.rotvec_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.omega_from_rotvec_rate, ([0.1, 0.2, 0.3], [1, 2, 3])),
        (K.omega_from_quat_rate, ([1, 0, 0, 0], [0, 1, 2, 3])),
        (K.omega_from_dcm_rate, (np.eye(3), np.zeros((3, 3)))),
    ],
)
def test_unknown_frame_rejected(fn, args):
    with pytest.raises(InvalidInputError, match="Expected `frame` to be one of"):
        fn(*args, frame="world")


@pytest.mark.parametrize(
    "fn, first, name",
    [(K.gibbs_rate, "g", "g"), (K.mrp_rate, "p", "p"), (K.rotvec_rate, "rotvec", "rotvec")],
)
def test_parameter_shape_errors(fn, first, name):
    with pytest.raises(InvalidInputError, match=rf"`{name}` to have shape \(\.\.\., 3\)"):
        fn([0.1, 0.2], [1, 2, 3])
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        fn([0.1, 0.2, 0.3], [1, np.nan, 3])


def test_all_sequences_covered():
    """The 24 explicit sequences are all distinct and valid (guards SEQS above)."""
    assert len(set(SEQS)) == 26
    for a, b, c in itertools.product("XYZ", repeat=3):
        if a != b and b != c:
            assert a + b + c in SEQS and (a + b + c).lower() in SEQS


# --------------------------------------------------------------------------
# property tests (hypothesis): exact product-rule derivative of the quaternion
# --------------------------------------------------------------------------

_angle = st.floats(-3.0, 3.0, allow_nan=False)
_rate = st.floats(-5.0, 5.0, allow_nan=False)


def _elementary_quat(axis, angle, rate):
    """(e, e') of the elementary quaternion cos(f/2) + sin(f/2) i_axis and its rate."""
    e = np.zeros(4)
    d = np.zeros(4)
    e[0], e[1 + axis] = np.cos(angle / 2), np.sin(angle / 2)
    d[0], d[1 + axis] = -0.5 * rate * np.sin(angle / 2), 0.5 * rate * np.cos(angle / 2)
    return e, d


@settings(max_examples=60, deadline=None)
@given(
    seq=st.sampled_from(SEQS),
    angles=st.tuples(_angle, _angle, _angle),
    rates=st.tuples(_rate, _rate, _rate),
    frame=st.sampled_from(["body", "space"]),
)
def test_euler_rates_against_product_rule(seq, angles, rates, frame):
    """omega from the exact derivative of q = e1 o e2 o e3 (SPEC S5), any sequence."""
    from poinsot.rotations.euler import parse_sequence

    axes, intrinsic = parse_sequence(seq)
    angles, rates = np.array(angles), np.array(rates)
    order = [0, 1, 2] if intrinsic else [2, 1, 0]
    factors = [_elementary_quat(axes[k], angles[k], rates[k]) for k in order]
    (a, da), (b, db), (c, dc) = factors
    q = Q.multiply(Q.multiply(a, b), c)
    qdot = (
        Q.multiply(Q.multiply(da, b), c)
        + Q.multiply(Q.multiply(a, db), c)
        + Q.multiply(Q.multiply(a, b), dc)
    )
    ref = Rotation.from_euler(seq, angles).as_quat()
    assert min(np.abs(q - ref).max(), np.abs(q + ref).max()) < 1e-12  # same rotation
    w = K.omega_from_euler_rates(seq, angles, rates, frame=frame)
    np.testing.assert_allclose(w, K.omega_from_quat_rate(q, qdot, frame=frame), atol=1e-12)
    det = abs(np.linalg.det(K.euler_rate_matrix(seq, angles, frame=frame)))
    if det > 1e-2:
        np.testing.assert_allclose(
            K.euler_rates(seq, angles, w, frame=frame), rates, atol=1e-10 / det
        )


@settings(max_examples=60, deadline=None)
@given(
    q=st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4).filter(lambda v: 0.1 < np.linalg.norm(v)),
    w=st.tuples(_rate, _rate, _rate),
    frame=st.sampled_from(["body", "space"]),
)
def test_parameter_rates_against_quaternion_rate(q, w, frame):
    """Gibbs, MRP and rotation-vector rates = chain rule applied to SPEC S5's L'."""
    q = np.array(q) / np.linalg.norm(q)
    q = q if q[0] >= 0 else -q
    assume(q[0] >= 0.05)  # keep away from f = pi (Gibbs infinite, rotvec wraps)
    w = np.array(w)
    qd = K.quat_rate(q, w, frame=frame)
    q0, v, d0, dv = q[0], q[1:], qd[0], qd[1:]
    np.testing.assert_allclose(
        K.gibbs_rate(v / q0, w, frame=frame), dv / q0 - v * d0 / q0**2, atol=1e-9
    )
    np.testing.assert_allclose(
        K.mrp_rate(v / (1 + q0), w, frame=frame),
        dv / (1 + q0) - v * d0 / (1 + q0) ** 2,
        atol=1e-12,
    )
    # rotation vector phi = 2 atan2(|v|, q0) v/|v|: its derivative by the chain rule
    n = np.linalg.norm(v)
    if n > 1e-3:
        f = 2 * np.arctan2(n, q0)
        dn = v @ dv / n
        df = 2 * (q0 * dn - n * d0)  # d/dt 2 atan2(n, q0) with n^2 + q0^2 = 1
        dphi = df * v / n + f * (dv / n - v * dn / n**2)
        np.testing.assert_allclose(K.rotvec_rate(f * v / n, w, frame=frame), dphi, atol=1e-10)


# ------------------------------------------------------------------ one state
_SEQS12 = ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"]


@pytest.mark.parametrize("frame", ["body", "space"])
def test_one_state_equals_its_row_in_a_batch(frame):
    """The one-state short paths compute what the batch (array) paths compute."""
    rng = np.random.default_rng(21)
    n = 25
    q = rng.standard_normal((n, 4))
    x, y = rng.uniform(-0.9, 0.9, (n, 3)), rng.standard_normal((n, 3))
    C = Rotation.from_quat(q).as_matrix()
    Cd = rng.standard_normal((n, 3, 3))
    qd = rng.standard_normal((n, 4))
    cases = [
        (K.quat_rate, q, y),
        (K.omega_from_quat_rate, q, qd),
        (K.dcm_rate, C, y),
        (K.omega_from_dcm_rate, C, Cd),
        (K.gibbs_rate, x, y),
        (K.omega_from_gibbs_rate, x, y),
        (K.mrp_rate, x, y),
        (K.omega_from_mrp_rate, x, y),
        (K.rotvec_rate, 3 * x, y),
        (K.omega_from_rotvec_rate, 3 * x, y),
    ]
    for f, a, b in cases:
        batch = f(a, b, frame=frame)
        one = np.array([f(a[i], b[i], frame=frame) for i in range(n)])
        lists = np.array([f(a[i].tolist(), b[i].tolist(), frame=frame) for i in range(n)])
        # two code paths, a few ulp apart (8.9e-16 observed on values ~ 1-10)
        np.testing.assert_allclose(one, batch, rtol=0, atol=2e-14, err_msg=f.__name__)
        np.testing.assert_allclose(lists, batch, rtol=0, atol=2e-14, err_msg=f.__name__)
    one_rot = np.array([K.quat_rate(Rotation.from_quat(q[i]), y[i], frame=frame) for i in range(n)])
    np.testing.assert_allclose(one_rot, K.quat_rate(q, y, frame=frame), rtol=0, atol=2e-14)
    ang = rng.uniform(-3, 3, (n, 3))
    ang[:, 1] = rng.uniform(0.2, 1.3, n)  # away from gimbal lock for every sequence
    for seq in _SEQS12 + [s.lower() for s in _SEQS12] + ["euler", "krylov"]:
        for deg, a in ((False, ang), (True, np.rad2deg(ang))):
            m = K.euler_rate_matrix(seq, a, frame=frame, degrees=deg)
            m1 = np.array(
                [K.euler_rate_matrix(seq, a[i], frame=frame, degrees=deg) for i in range(n)]
            )
            np.testing.assert_allclose(m1, m, rtol=0, atol=4e-16, err_msg=seq)
            for f in (K.euler_rates, K.omega_from_euler_rates):
                batch = f(seq, a, y, frame=frame, degrees=deg)
                one = np.array([f(seq, a[i], y[i], frame=frame, degrees=deg) for i in range(n)])
                np.testing.assert_allclose(
                    one, batch, rtol=1e-14, atol=1e-13, err_msg=f"{f.__name__} {seq} {deg}"
                )


def test_one_state_keeps_the_checks():
    with pytest.raises(InvalidInputError, match="`frame`"):
        K.quat_rate([1.0, 0, 0, 0], [1.0, 2, 3], frame="world")
    with pytest.raises(InvalidInputError, match="finite"):
        K.quat_rate([1.0, 0, 0, 0], [1.0, np.nan, 3])
    with pytest.raises(InvalidInputError, match="non-zero"):
        K.quat_rate([0.0, 0, 0, 0], [1.0, 2, 3])
    with pytest.raises(InvalidInputError, match="`C` to be rotation matrices"):
        K.dcm_rate(2 * np.eye(3), [1.0, 2, 3])
    with pytest.raises(InvalidTypeError, match="`degrees` to be a bool"):
        K.euler_rates("ZXZ", [0.1, 0.5, 0.2], [1.0, 2, 3], degrees="no")
    with pytest.warns(GimbalLockWarning):
        K.euler_rates("ZXZ", [0.1, 1e-4, 0.2], [1.0, 2, 3])
    with pytest.raises(InvalidInputError, match="overflows"):
        K.gibbs_rate([1e200, 0, 0], [1.0, 1.0, 0])
