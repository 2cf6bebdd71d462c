"""Peer cross-checks of the free rigid body and of ``simulate`` against SciPy.

The reference is ``scipy.integrate.solve_ivp(DOP853, rtol=1e-13, atol=1e-14)`` of
Euler's dynamic equations and Poisson's quaternion equation written here, from
docs/theory.md §5, §10, without any poinsot code:

    J w' = M - w x J w,        L' = 1/2 L o (0, w)      (body-frame w, Hamilton,
                                                        scalar-first L: body -> space)

and the period of ``omega`` against Landau & Lifshitz, *Mechanics*, S37 with
``scipy.special.ellipk`` (its argument is the parameter ``m = k^2``).

Tolerances: the reference's own error is measured in every call by comparing it
with the solution at a 10x looser ``rtol`` (observed up to 3.6e-12 |w0| in omega
and 1.8e-11 in the attitude matrix) and must stay 100x below the
tolerance ``TOL = 2e-8`` (a bound with 10x headroom itself, as machines differ);
poinsot's exact solution agrees with the reference to <= 1.2e-12 (the
integrator's error), >= 1000x inside ``TOL``.
"""

from __future__ import annotations

import numpy as np
import pytest

scipy_integrate = pytest.importorskip("scipy.integrate")
scipy_special = pytest.importorskip("scipy.special")

from poinsot import Rotation  # noqa: E402
from poinsot.dynamics import FreeRigidBody, simulate  # noqa: E402

RTOL, ATOL = 1e-13, 1e-14
TOL = 2e-8


def _qmul(p, q):
    """Hamilton product, scalar first (written out, docs/theory.md §1)."""
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return np.array(
        [
            p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
            p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
            p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
            p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
        ]
    )


def _quat_to_matrix(q):
    """Active rotation matrix of a unit quaternion (docs/theory.md §2), body -> space."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _solve(j, w0, q0, t, torque, rtol, atol):
    j = np.asarray(j, dtype=float)
    j_inv = np.linalg.inv(j)

    def rhs(tt, y):
        w, q = y[:3], y[3:]
        m = np.zeros(3) if torque is None else torque(tt, _quat_to_matrix(q), w)
        wdot = j_inv @ (m - np.cross(w, j @ w))
        qdot = 0.5 * _qmul(q, np.concatenate(([0.0], w)))
        return np.concatenate((wdot, qdot))

    sol = scipy_integrate.solve_ivp(
        rhs,
        (t[0], t[-1]),
        np.concatenate((w0, q0)),
        method="DOP853",
        t_eval=t,
        rtol=rtol,
        atol=atol,
    )
    assert sol.success
    w = sol.y[:3].T
    dcm = np.array([_quat_to_matrix(q) for q in sol.y[3:].T])
    return w, dcm


def _reference(j, w0, q0, t, torque=None):
    """DOP853 solution of Euler + Poisson: body omega (n, 3) and space-from-body DCMs.

    Its error, bounded by the difference to the solution at 10x looser tolerances,
    is asserted <= TOL / 100 (relative to |w0| for omega)."""
    w, dcm = _solve(j, w0, q0, t, torque, RTOL, ATOL)
    w2, dcm2 = _solve(j, w0, q0, t, torque, 10 * RTOL, 10 * ATOL)
    assert np.max(np.abs(w - w2)) <= TOL / 100 * max(np.linalg.norm(w0), 1.0)
    assert np.max(np.abs(dcm - dcm2)) <= TOL / 100
    return w, dcm


def _landau_period(moments, w0):
    """Landau & Lifshitz S37: ``4 K(k) sqrt(I1 I2 I3 / ((I3 - I2)(M^2 - 2 E I1)))``.

    Landau orders ``I1 < I2 < I3`` and takes ``M^2 > 2 E I2``; with SPEC's
    ``A > B > C`` that is ``I3 = A``, ``I1 = C``. For ``M^2 < 2 E I2`` the roles
    of ``I1`` and ``I3`` swap.
    """
    order = np.argsort(moments)[::-1]  # A > B > C
    a, b, c = np.asarray(moments, dtype=float)[order]
    w = np.asarray(w0, dtype=float)[order]
    two_t = a * w[0] ** 2 + b * w[1] ** 2 + c * w[2] ** 2
    k2 = (a * w[0]) ** 2 + (b * w[1]) ** 2 + (c * w[2]) ** 2
    if k2 > two_t * b:
        m = (b - c) * (two_t * a - k2) / ((a - b) * (k2 - two_t * c))
        scale = np.sqrt(a * b * c / ((a - b) * (k2 - two_t * c)))
    else:
        m = (a - b) * (k2 - two_t * c) / ((b - c) * (two_t * a - k2))
        scale = np.sqrt(a * b * c / ((b - c) * (two_t * a - k2)))
    return 4.0 * scipy_special.ellipk(m) * scale, ("major" if k2 > two_t * b else "minor")


def _random_case(rng):
    while True:
        moments = rng.uniform(1.0, 3.0, size=3)
        s = np.sort(moments)
        if s[0] + s[1] > s[2] * 1.05 and np.min(np.diff(s)) > 0.1:
            break
    w0 = rng.normal(size=3) * 1.5
    return moments, w0, Rotation.random(rng=rng)


# seeds 31, 36: polhode about the major axis; 34: about the minor axis; plus the
# tennis-racket (Dzhanibekov) flip near the separatrix (1 - k^2 ~ 5e-3)
CASES = [_random_case(np.random.default_rng(seed)) for seed in (31, 34, 36)] + [
    (np.array([1.0, 2.0, 3.0]), np.array([0.05, 1.0, 0.05]), Rotation.from_rotvec([0.3, -0.2, 1.0]))
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_free_body_vs_dop853(case):
    moments, w0, r0 = CASES[case]
    body = FreeRigidBody(moments, rotation0=r0, omega0=w0)
    period, regime = _landau_period(moments, w0)
    assert body.regime == regime
    assert abs(body.period - period) <= 1e-12 * period
    t = np.linspace(0.0, 2.0 * period, 241)
    w_ref, c_ref = _reference(np.diag(moments), w0, r0.as_quat(), t)
    w, rot = body.state(t)
    scale = np.linalg.norm(w0)
    np.testing.assert_allclose(w, w_ref, rtol=0, atol=TOL * scale)
    np.testing.assert_allclose(body.omega(t), w_ref, rtol=0, atol=TOL * scale)
    np.testing.assert_allclose(rot.as_matrix(), c_ref, rtol=0, atol=TOL)
    np.testing.assert_allclose(body.rotation(t).as_matrix(), c_ref, rtol=0, atol=TOL)
    # the reference itself is periodic with Landau's period
    np.testing.assert_allclose(w_ref[-1], w0, atol=TOL * scale)
    np.testing.assert_allclose(w_ref[120], w0, atol=TOL * scale)
    # space momentum K = R J w from the reference
    k_ref = np.einsum("nij,nj->ni", c_ref, w_ref * moments)
    np.testing.assert_allclose(
        k_ref, np.broadcast_to(body.momentum, k_ref.shape), atol=TOL * np.linalg.norm(body.momentum)
    )


@pytest.mark.parametrize("case", range(len(CASES)))
def test_precession_per_period_vs_dop853(case):
    """``R(P) R(0)^-1`` is a rotation about ``K`` by ``precession_per_period`` (mod 2 pi)."""
    moments, w0, r0 = CASES[case]
    body = FreeRigidBody(moments, rotation0=r0, omega0=w0)
    _, c_ref = _reference(np.diag(moments), w0, r0.as_quat(), np.array([0.0, body.period]))
    d = c_ref[1] @ c_ref[0].T
    k_hat = body.momentum / np.linalg.norm(body.momentum)
    # rotation about k_hat by angle a: d = cos a E + sin a k^ + (1 - cos a) k k^T
    cos_a = (np.trace(d) - 1.0) / 2.0
    sin_a = 0.5 * k_hat @ np.array([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
    np.testing.assert_allclose(d @ k_hat, k_hat, atol=TOL)  # the axis is K
    angle = np.arctan2(sin_a, cos_a)
    diff = (body.precession_per_period - angle + np.pi) % (2 * np.pi) - np.pi
    assert abs(diff) < TOL


def test_free_body_full_tensor_vs_dop853():
    """A non-diagonal inertia tensor: omega and attitude stay in the given axes."""
    rng = np.random.default_rng(34)
    moments, w0, r0 = _random_case(rng)
    s = Rotation.random(rng=rng).as_matrix()
    j = s @ np.diag(moments) @ s.T
    body = FreeRigidBody(j, rotation0=r0, omega0=w0)
    period, _ = _landau_period(moments, s.T @ w0)
    assert abs(body.period - period) <= 1e-12 * period
    t = np.linspace(0.0, 2.0 * period, 121)
    w_ref, c_ref = _reference(j, w0, r0.as_quat(), t)
    w, rot = body.state(t)
    np.testing.assert_allclose(w, w_ref, atol=TOL * np.linalg.norm(w0))
    np.testing.assert_allclose(rot.as_matrix(), c_ref, atol=TOL)


def test_symmetric_body_period_vs_dop853():
    """``A = B``: the period of omega is ``2 pi A / |(A - C) r|`` (docs/theory.md §10)."""
    a, c = 2.0, 1.2
    w0 = np.array([0.4, -0.3, 1.1])
    body = FreeRigidBody([a, a, c], rotation0=Rotation.from_rotvec([0.1, 0.2, 0.3]), omega0=w0)
    period = 2 * np.pi * a / abs((a - c) * w0[2])
    assert abs(body.period - period) <= 1e-12 * period
    t = np.linspace(0.0, 2 * period, 81)
    w_ref, c_ref = _reference(np.diag([a, a, c]), w0, body.rotation(0.0).as_quat(), t)
    w, rot = body.state(t)
    np.testing.assert_allclose(w, w_ref, atol=TOL * np.linalg.norm(w0))
    np.testing.assert_allclose(rot.as_matrix(), c_ref, atol=TOL)


def test_simulate_with_torque_vs_dop853():
    """``simulate`` under an attitude- and omega-dependent torque (full tensor)."""
    rng = np.random.default_rng(35)
    moments, w0, r0 = _random_case(rng)
    s = Rotation.random(rng=rng).as_matrix()
    j = s @ np.diag(moments) @ s.T
    m_space = np.array([0.1, -0.2, 0.3])

    def torque_ref(tt, c_sb, w):
        return c_sb.T @ m_space - 0.05 * w + 0.02 * np.sin(tt) * np.array([1.0, 0.0, 0.0])

    def torque(tt, rotation, w):
        return (
            rotation.apply(m_space, inverse=True)
            - 0.05 * w
            + 0.02 * np.sin(tt) * np.array([1.0, 0.0, 0.0])
        )

    t = np.linspace(0.0, 6.0, 31)
    w_ref, c_ref = _reference(j, w0, r0.as_quat(), t, torque=torque_ref)
    # observed: midpoint order 6 at h = 0.02 4e-11 (omega), 5e-10 (matrix); adaptive 2e-11
    tr = simulate(j, r0, w0, t, torque=torque, method="midpoint", order=6, max_step=0.02)
    np.testing.assert_allclose(tr.omega, w_ref, atol=TOL)
    np.testing.assert_allclose(tr.rotation.as_matrix(), c_ref, atol=TOL)
    ad = simulate(j, r0, w0, t, torque=torque, method="adaptive", rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(ad.omega, w_ref, atol=TOL)
    np.testing.assert_allclose(ad.rotation.as_matrix(), c_ref, atol=TOL)


EDGE_CASES = {
    "flat_plate": ([1.0, 2.0, 3.0], [0.3, 0.8, -0.5]),  # A + B = C
    "major_axis_exactly": ([1.0, 2.0, 3.0], [0.0, 0.0, 1.3]),
    "minor_axis_exactly": ([1.0, 2.0, 3.0], [1.3, 0.0, 0.0]),
    "perturbed_major_axis": ([1.0, 2.0, 3.0], [1e-7, 1e-7, 1.3]),
    "tiny_body_fast_spin": ([1e-6, 2e-6, 2.5e-6], [3e3, -2e3, 1e3]),
    "moments_unordered": ([2.5, 1.0, 2.0], [0.3, 0.8, -0.5]),
    "near_symmetric_1e-9": ([1.0, 1.0 + 1e-9, 1.8], [0.5, 0.2, 1.0]),
}


@pytest.mark.parametrize("name", sorted(EDGE_CASES))
def test_free_body_edge_cases_vs_dop853(name):
    """Permanent rotations, the flat plate, extreme scales, unordered moments."""
    moments, w0 = (np.array(v) for v in EDGE_CASES[name])
    r0 = Rotation.from_rotvec([0.2, -0.4, 0.7])
    body = FreeRigidBody(moments, rotation0=r0, omega0=w0)
    period, _ = _landau_period(moments, w0)
    assert abs(body.period - period) <= 1e-12 * period
    t = np.linspace(0.0, 2.0 * period, 101)
    w_ref, c_ref = _reference(np.diag(moments), w0, r0.as_quat(), t)
    w, rot = body.state(t)
    np.testing.assert_allclose(w, w_ref, rtol=0, atol=TOL * np.linalg.norm(w0))
    np.testing.assert_allclose(rot.as_matrix(), c_ref, rtol=0, atol=TOL)


def test_middle_axis_rotation_vs_dop853():
    """Exactly about the middle axis: a uniform (unstable) permanent rotation."""
    w0 = np.array([0.0, 1.3, 0.0])
    body = FreeRigidBody([1.0, 2.0, 3.0], omega0=w0)
    assert body.regime == "separatrix"
    assert body.period == np.inf
    t = np.linspace(0.0, 10.0, 21)
    w_ref, c_ref = _reference(np.diag([1.0, 2.0, 3.0]), w0, np.array([1.0, 0, 0, 0]), t)
    w, rot = body.state(t)
    np.testing.assert_allclose(w, w_ref, atol=TOL * np.linalg.norm(w0))
    np.testing.assert_allclose(rot.as_matrix(), c_ref, atol=TOL)


@pytest.mark.parametrize("case", range(len(CASES)))
def test_poinsot_picture_vs_dop853(case):
    """Polhode ``w / sqrt(2T)`` and herpolhode ``R w / sqrt(2T)`` from the reference motion."""
    moments, w0, r0 = CASES[case]
    body = FreeRigidBody(
        moments, rotation0=r0, omega0=w0
    )  # diagonal moments: principal axes = body axes
    t = np.linspace(0.0, 1.5 * body.period, 61)
    w_ref, c_ref = _reference(np.diag(moments), w0, r0.as_quat(), t)
    two_t = float(w0 @ (moments * w0))
    k = np.linalg.norm(moments * w0)
    g = body.poinsot(t)
    # given principal moments keep their order (docs: "body axes = principal axes")
    np.testing.assert_array_equal(body.principal_moments, moments)
    np.testing.assert_allclose(g.polhode, w_ref / np.sqrt(two_t), atol=TOL)
    herp = np.einsum("nij,nj->ni", c_ref, w_ref) / np.sqrt(two_t)
    np.testing.assert_allclose(g.herpolhode, herp, atol=TOL)
    assert abs(g.plane_distance - np.sqrt(two_t) / k) < 1e-14
    np.testing.assert_allclose(herp @ g.plane_normal, np.sqrt(two_t) / k, atol=TOL)
    np.testing.assert_allclose(g.ellipsoid_semi_axes, 1.0 / np.sqrt(moments), atol=1e-15)
    mc = body.maccullagh(50)
    assert abs(mc.momentum_radius - k) < 1e-13 * k
    np.testing.assert_allclose(mc.ellipsoid_semi_axes, np.sqrt(two_t * moments), rtol=1e-14)
