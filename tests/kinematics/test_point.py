"""Natural (Frenet) trihedron of a point's path (SPEC S7, numeric part).

Truths: closed forms for the helix ``(a cos t, a sin t, b t)`` (curvature
``a/(a^2+b^2)``, torsion ``b/(a^2+b^2)``, Frenet vectors by hand), the circle
(curvature ``1/R``, torsion 0, normal towards the centre), a circle run with
varying speed (``w = v' T + v^2/R N``), the Frenet-Serret formula
``dT/dt = |v| kappa N`` checked by an independent difference, and a straight
line (singular).
"""

from __future__ import annotations

import numpy as np
import pytest

from poinsot.errors import InvalidInputError, InvalidTypeError, SingularityWarning
from poinsot.kinematics.attitude_history import _fornberg
from poinsot.kinematics.point import FrenetFrame, frenet

A, B = 2.0, 0.7


def helix(t):
    t = np.asarray(t)
    return np.stack([A * np.cos(t), A * np.sin(t), B * t], axis=-1)


def helix_derivs():
    return (
        lambda t: np.stack([-A * np.sin(t), A * np.cos(t), B + 0 * t], axis=-1),
        lambda t: np.stack([-A * np.cos(t), -A * np.sin(t), 0 * t], axis=-1),
        lambda t: np.stack([A * np.sin(t), -A * np.cos(t), 0 * t], axis=-1),
    )


def helix_truth(t):
    c = np.hypot(A, B)
    T = np.stack([-A * np.sin(t), A * np.cos(t), B + 0 * t], -1) / c
    N = np.stack([-np.cos(t), -np.sin(t), 0 * t], -1)
    Bn = np.stack([B * np.sin(t), -B * np.cos(t), A + 0 * t], -1) / c
    return T, N, Bn, A / c**2, B / c**2, c


def check_helix(f: FrenetFrame, t, tol_vec, tol_k, tol_tau):
    T, N, Bn, kappa, tau, speed = helix_truth(t)
    np.testing.assert_allclose(f.tangent, T, atol=tol_vec)
    np.testing.assert_allclose(f.normal, N, atol=tol_vec)
    np.testing.assert_allclose(f.binormal, Bn, atol=tol_vec)
    np.testing.assert_allclose(f.curvature, kappa, atol=tol_k)
    np.testing.assert_allclose(f.torsion, tau, atol=tol_tau)
    np.testing.assert_allclose(f.speed, speed, atol=tol_vec)
    np.testing.assert_allclose(f.tangential_acceleration, 0.0, atol=tol_vec)
    np.testing.assert_allclose(f.normal_acceleration, speed**2 * kappa, atol=tol_vec)
    assert not f.singular.any()


def test_helix_callable_closed_form():
    t = np.linspace(-3, 3, 13)
    f = frenet(t, helix)
    check_helix(f, t, 2e-10, 1e-11, 1e-8)  # vectors: 1.2e-11 observed


def test_helix_exact_derivatives():
    t = np.linspace(-3, 3, 13)
    f = frenet(t, helix, derivatives=helix_derivs())
    check_helix(f, t, 1e-14, 1e-15, 1e-15)


def test_helix_samples_nonuniform_and_convergence():
    """Non-uniform samples: 7-point stencils give ~1e-8 on torsion at h ~ 0.01,
    and the error falls at least like h^4 when the sampling is refined."""
    rng = np.random.default_rng(0)
    errs = []
    for n in (200, 400):
        u = np.linspace(0, 4, n)
        t = u + rng.uniform(-0.3, 0.3, n) * (u[1] - u[0])  # jittered, still increasing
        f = frenet(t, helix(t), stride=1)
        check_helix(f, t, 1e-7, 1e-7, 1e-5)
        _, _, _, kappa, tau, _ = helix_truth(t)
        errs.append(np.abs(f.torsion - tau).max())
    assert errs[1] < errs[0] / 2**3.5


def test_dense_samples_auto_stride():
    """20,000 samples over 20 s (h = 1e-3): with every sample in the stencil,
    rounding (~1e-16 |r| / h^3) spoils the third derivative; the automatic
    stride keeps the torsion to ~1e-7 and the curvature to ~1e-10."""
    t = np.linspace(0, 20, 20_000)
    r = helix(t)
    _, _, _, kappa, tau, _ = helix_truth(t)
    auto = frenet(t, r)
    one = frenet(t, r, stride=1)
    assert np.abs(one.torsion - tau).max() > 1e-5
    assert np.abs(auto.torsion - tau).max() < 2e-6  # 1.25e-7 observed
    assert np.abs(auto.curvature - kappa).max() < 2e-9  # 1.6e-10 observed
    four = frenet(t, r, stride=4)
    assert np.abs(four.torsion - tau).max() < np.abs(one.torsion - tau).max() / 10


def test_stencil_controls_order():
    t = np.linspace(0, 4, 120)
    e5 = np.abs(frenet(t, helix(t), stencil=5).curvature - helix_truth(t)[3]).max()
    e9 = np.abs(frenet(t, helix(t), stencil=9).curvature - helix_truth(t)[3]).max()
    assert e9 < e5 / 50


def test_circle_with_varying_speed():
    """r = R (cos s, sin s, 0) with s = t^2/2: speed R t, tangential
    acceleration R, normal acceleration (R t)^2 / R, normal towards the centre."""
    R = 1.5
    t = np.linspace(0.5, 2.5, 300)
    s = t**2 / 2
    r = R * np.stack([np.cos(s), np.sin(s)], -1)  # a 2-D curve
    f = frenet(t, r)
    np.testing.assert_allclose(f.curvature, 1 / R, rtol=1e-6)
    np.testing.assert_allclose(f.radius_of_curvature, R, rtol=1e-6)
    np.testing.assert_allclose(f.torsion, 0, atol=1e-9)
    np.testing.assert_allclose(f.speed, R * t, rtol=1e-8)
    np.testing.assert_allclose(f.tangential_acceleration, R, rtol=1e-6)
    np.testing.assert_allclose(f.normal_acceleration, R * t**2, rtol=1e-6)
    np.testing.assert_allclose(f.normal, -f.position / R, atol=1e-6)
    np.testing.assert_allclose(f.binormal, np.tile([0, 0, 1.0], (t.size, 1)), atol=1e-12)
    # SPEC S7: w = v' T + (v^2 / rho) N
    rebuilt = (
        f.tangential_acceleration[:, None] * f.tangent
        + (f.speed**2 / f.radius_of_curvature)[:, None] * f.normal
    )
    np.testing.assert_allclose(rebuilt, f.acceleration, atol=1e-12)


def test_frenet_serret_by_independent_difference():
    """dT/dt = |v| kappa N and dB/dt = -|v| tau N (Frenet-Serret), with the
    time derivatives of T and B taken by the classical 5-point formula."""
    t = np.linspace(0, 2, 4001)
    h = t[1] - t[0]

    def d5(y):
        return (y[:-4] - 8 * y[1:-3] + 8 * y[3:-1] - y[4:]) / (12 * h)

    def curve(t):
        return np.stack([np.cos(t) + 0.3 * t**2, np.sin(2 * t), 0.5 * t**3 - t], -1)

    f = frenet(t, curve)
    dT, dB = d5(f.tangent), d5(f.binormal)
    sl = slice(2, -2)
    np.testing.assert_allclose(dT, (f.speed * f.curvature)[sl, None] * f.normal[sl], atol=1e-5)
    np.testing.assert_allclose(dB, -(f.speed * f.torsion)[sl, None] * f.normal[sl], atol=1e-5)
    # an orthonormal right-handed frame
    np.testing.assert_allclose(np.cross(f.tangent, f.normal), f.binormal, atol=1e-12)


def test_callable_layouts_and_batch():
    """r(t) may return (..., 3), (3, ...) or a tuple of components; the
    samples may hold several curves on the same times."""
    t = np.array([[0.1, 0.2], [0.3, 0.4]])
    ref = frenet(t, helix)
    assert ref.tangent.shape == (2, 2, 3) and ref.curvature.shape == (2, 2)
    check_helix(ref, t, 2e-10, 1e-11, 1e-8)  # the (2, 2) batch against the closed form
    f2 = frenet(t, lambda s: np.array([A * np.cos(s), A * np.sin(s), B * s]))
    f3 = frenet(t, lambda s: (A * np.cos(s), A * np.sin(s), B * s))
    np.testing.assert_allclose(f2.torsion, ref.torsion)
    np.testing.assert_allclose(f3.normal, ref.normal)
    f0 = frenet(0.3, helix)
    assert f0.curvature.shape == () and f0.tangent.shape == (3,)
    ts = np.linspace(0, 3, 50)
    two = np.stack([helix(ts), 2 * helix(ts)], axis=1)  # (n, 2, 3)
    fb = frenet(ts, two)
    assert fb.curvature.shape == (50, 2)
    np.testing.assert_allclose(fb.curvature[:, 1], fb.curvature[:, 0] / 2, rtol=1e-12)
    kappa = helix_truth(ts)[3]  # a / (a^2 + b^2); the curve scaled by 2 has half of it
    np.testing.assert_allclose(
        fb.curvature, np.stack([kappa, kappa / 2], -1) + 0 * ts[:, None], rtol=1e-5
    )


def test_straight_and_stationary_points_warn():
    t = np.linspace(0, 1, 20)
    r = np.stack([t**2, 2 * t**2, -(t**2)], -1) + [1e3, 0, 5]  # straight line, starts at rest
    with pytest.warns(SingularityWarning, match="20 point"):
        f = frenet(t, r)
    assert f.singular.all()
    assert np.all(f.normal == 0) and np.all(f.binormal == 0) and np.all(f.torsion == 0)
    assert np.all(np.isfinite(f.radius_of_curvature[1:]) == False)  # noqa: E712
    np.testing.assert_allclose(f.tangent[1:], np.tile([1, 2, -1] / np.sqrt(6), (19, 1)))
    assert np.all(f.tangent[0] == 0) and f.speed[0] < 1e-9  # stationary at t = 0
    np.testing.assert_allclose(f.tangential_acceleration[1:], 2 * np.sqrt(6), rtol=1e-8)
    # exact derivatives: the cusp of (t^3, t^2, 0) at t = 0 is stationary
    with pytest.warns(SingularityWarning, match="1 point"):
        g = frenet(
            np.array([0.0, 1.0]),
            lambda s: (s**3, s**2, 0 * s),
            derivatives=(
                lambda s: (3 * s**2, 2 * s, 0 * s),
                lambda s: (6 * s, 2 + 0 * s, 0 * s),
                lambda s: (6 + 0 * s, 0 * s, 0 * s),
            ),
        )
    np.testing.assert_array_equal(g.singular, [True, False])
    assert np.all(g.tangent[0] == 0) and g.curvature[0] == 0
    # at t = 1: v = (3, 2, 0), a = (6, 2, 0): kappa = |v x a| / |v|^3 = 6 / 13^1.5
    np.testing.assert_allclose(g.curvature[1], 6 / 13**1.5, rtol=1e-14)
    np.testing.assert_allclose(g.binormal[1], [0, 0, -1])


def test_fd_weights_uniform_textbook():
    """Classical central weights: (1, -8, 0, 8, -1)/12 and (-1, 16, -30, 16, -1)/12."""
    c = _fornberg(0.0, np.arange(-2.0, 3.0), 2)  # the kernel frenet uses
    np.testing.assert_allclose(c[:, 1] * 12, [1, -8, 0, 8, -1], atol=1e-13)
    np.testing.assert_allclose(c[:, 2] * 12, [-1, 16, -30, 16, -1], atol=1e-13)
    np.testing.assert_allclose(c[:, 0], [0, 0, 1, 0, 0], atol=1e-15)


# ---------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------


def test_errors_samples():
    t = np.linspace(0, 1, 10)
    r = helix(t)
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\)"):
        frenet(t[None], r)
    with pytest.raises(InvalidInputError, match="one sample per time"):
        frenet(t[:-1], r)
    with pytest.raises(InvalidInputError, match=r"`r` to have shape \(n, \.\.\., 3\)"):
        frenet(t, np.ones((10, 4)))
    with pytest.raises(InvalidInputError, match=r"`r` to have shape"):
        frenet(t, np.ones(10))
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        frenet(t[::-1], r)
    with pytest.raises(InvalidInputError, match="at least 7 samples"):
        frenet(t[:5], r[:5])
    with pytest.raises(InvalidInputError, match="`r` to contain only finite"):
        frenet(t, np.where(t[:, None] > 0.5, np.nan, r))
    with pytest.raises(InvalidInputError, match="`t` to contain only finite"):
        frenet(np.where(t > 0.5, np.inf, t), r)
    with pytest.raises(InvalidInputError, match="`stencil` to be an integer >= 4"):
        frenet(t, r, stencil=3)
    with pytest.raises(InvalidTypeError, match="`stencil` to be an integer, got float"):
        frenet(t, r, stencil=5.0)
    with pytest.raises(InvalidInputError, match="`stride` to be 'auto' or an integer >= 1"):
        frenet(t, r, stride=0)
    with pytest.raises(InvalidInputError, match=r"stride \* \(stencil - 1\) <= len\(t\) - 1 = 9"):
        frenet(t, r, stride=2)
    with pytest.raises(InvalidInputError, match="`stride`"):
        frenet(t, r, stride="fast")
    with pytest.raises(InvalidInputError, match="`derivatives` only with a callable"):
        frenet(t, r, derivatives=helix_derivs())
    with pytest.raises(InvalidInputError, match="`rtol` to be a non-negative number"):
        frenet(t, r, rtol=-1)
    with pytest.raises(InvalidTypeError, match="`r`"):
        frenet(t, "helix")


def test_errors_callable():
    with pytest.raises(InvalidInputError, match="`step` to be a positive number"):
        frenet(1.0, helix, step=0)
    with pytest.raises(InvalidInputError, match="`step` to be a positive number"):
        frenet(1.0, helix, step=[0.1, 0.2])
    with pytest.raises(InvalidInputError, match="Calling `r`.*failed"):
        frenet(1.0, lambda s: float(s))
    with pytest.raises(InvalidInputError, match=r"`r\(t\)` to return shape"):
        frenet(1.0, lambda s: np.ones(4))
    with pytest.raises(InvalidInputError, match=r"`r\(t\)` to contain only finite"):
        frenet(1.0, lambda s: np.stack([np.full_like(s, np.nan), s, s], -1))
    with pytest.raises(InvalidTypeError, match=r"`r\(t\)` to be array-like"):
        frenet(np.array([1.0, 2.0]), lambda s: (np.ones(2), np.ones(3), 0.0))
    with pytest.raises(InvalidInputError, match="tuple of three callables"):
        frenet(1.0, helix, derivatives=helix_derivs()[:2])
    with pytest.raises(InvalidInputError, match=r"`derivatives\[1\]\(t\)` to return shape"):
        d = helix_derivs()
        frenet(1.0, helix, derivatives=(d[0], lambda s: np.ones(4), d[2]))
    with pytest.raises(InvalidInputError, match="`t` to contain only finite"):
        frenet(np.nan, helix)
