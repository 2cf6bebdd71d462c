"""``simulate`` with an attitude-dependent torque: the heavy symmetric (Lagrange) top.

The Euler equations about a fixed point have the free-body form with the
inertia about that point and the gravity torque ``M = l e3 x R^T (-m g e_z)``
(body axes, centre of mass at ``l e3``, space ``z`` up). Independent truths
from SPEC S10:

- regular precession: ``A psi'^2 cos(theta) - H psi' + m g l = 0`` with
  ``H = C r``: starting on it, the ZXZ Euler angles are exactly
  ``psi = psi' t``, ``theta = theta0``, ``phi = phi' t``, ``phi' = r - psi' cos(theta)``;
- the integrals ``C r = H``, ``K_z``, ``E = T + m g l cos(theta)``.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot.dynamics import simulate

A, C, MGL = 1.0, 0.5, 0.8


def gravity(t, rotation, omega):
    """``l e3 x (body components of -m g e_z)`` with ``m g l = MGL``."""
    down_b = rotation.apply([0.0, 0.0, -1.0], inverse=True)
    return np.cross([0.0, 0.0, MGL], down_b)


@pytest.mark.parametrize("root", [-1, 1], ids=["slow", "fast"])
@pytest.mark.parametrize(
    ("method", "kw", "tol"),
    [
        ("midpoint", {"max_step": 1e-3}, 6e-3),  # observed 5.1e-4 (fast root)
        ("midpoint", {"max_step": 1e-2, "order": 6}, 1e-4),
        ("splitting", {"max_step": 1e-3}, 1e-6),
        ("splitting", {"max_step": 1e-2, "order": 4}, 1e-7),
        ("rk4", {"max_step": 1e-2}, 5e-5),
        ("adaptive", {"rtol": 1e-12, "atol": 1e-13}, 1e-9),
    ],
)
def test_heavy_top_regular_precession(root, method, kw, tol):
    theta, r = 0.6, 10.0
    h = C * r
    psi_dot = (h + root * np.sqrt(h**2 - 4 * A * MGL * np.cos(theta))) / (2 * A * np.cos(theta))
    phi_dot = r - psi_dot * np.cos(theta)
    # SPEC S3 kinematic equations at phi = 0: p = theta' = 0, q = psi' sin(theta), r
    w0 = np.array([0.0, psi_dot * np.sin(theta), r])
    q0 = SciRotation.from_euler("ZXZ", [0.0, theta, 0.0]).as_quat(scalar_first=True)
    t = np.linspace(0.0, 5.0, 11)
    tr = simulate([A, A, C], q0, w0, t, torque=gravity, method=method, **kw)
    exact = SciRotation.from_euler(
        "ZXZ", np.stack([psi_dot * t, np.full_like(t, theta), phi_dot * t], axis=-1)
    )
    err = (exact.inv() * SciRotation.from_quat(tr.quat, scalar_first=True)).magnitude()
    assert err.max() < tol
    np.testing.assert_allclose(tr.omega[:, 2], r, rtol=1e-9)


@pytest.mark.parametrize("method", ["midpoint", "splitting", "rk4"])
def test_lagrange_top_integrals(method):
    """Nutating top: ``C r``, ``K_z`` and ``E = T + m g l cos(theta)`` (SPEC S10)."""
    q0 = SciRotation.from_euler("ZXZ", [0.3, 0.9, -0.2]).as_quat(scalar_first=True)
    w0 = np.array([0.7, -0.4, 6.0])
    t = np.linspace(0.0, 20.0, 201)
    tr = simulate([A, A, C], q0, w0, t, torque=gravity, method=method, max_step=4e-3)
    cos_theta = tr.rotation.apply([0.0, 0.0, 1.0])[:, 2]
    energy = tr.energy + MGL * cos_theta
    k_z = tr.momentum[:, 2]
    e_err = np.abs(energy / energy[0] - 1)
    assert e_err.max() < 5e-5  # 2nd/4th order, no secular drift over 5000 steps (3.3e-6 seen)
    assert np.ptp(cos_theta) > 0.05  # it does nutate
    if method in ("midpoint", "splitting"):
        # the symmetric integrators keep C r exactly (A = B and M3 = 0)
        np.testing.assert_allclose(tr.omega[:, 2], w0[2], rtol=1e-13)
    if method == "splitting":
        # gravity kicks are exact rotations about the vertical: K_z to round-off
        np.testing.assert_allclose(k_z, k_z[0], rtol=1e-12)
        # and the energy error stays bounded: no growth from the first to the second half
        assert e_err[100:].max() < 3 * e_err[:101].max()
    else:
        np.testing.assert_allclose(k_z, k_z[0], rtol=5e-5)  # midpoint: 2.2e-6 seen


@pytest.mark.parametrize("method", ["midpoint", "splitting"])
@pytest.mark.parametrize("order", [2, 4])
def test_order_with_an_attitude_dependent_torque(method, order):
    """With the torque at the symmetric midpoint attitude the schemes stay symmetric,
    so the compositions keep their order under a torque (regular precession, slow root)."""
    theta, r = 0.6, 10.0
    h = C * r
    psi_dot = (h - np.sqrt(h**2 - 4 * A * MGL * np.cos(theta))) / (2 * A * np.cos(theta))
    phi_dot = r - psi_dot * np.cos(theta)
    w0 = np.array([0.0, psi_dot * np.sin(theta), r])
    q0 = SciRotation.from_euler("ZXZ", [0.0, theta, 0.0]).as_quat(scalar_first=True)
    t = np.array([0.0, 1.0, 2.0])
    exact = SciRotation.from_euler(
        "ZXZ", np.stack([psi_dot * t, np.full_like(t, theta), phi_dot * t], axis=-1)
    )
    errors = []
    for step in (0.02, 0.01, 0.005):
        tr = simulate(
            [A, A, C], q0, w0, t, torque=gravity, method=method, order=order, max_step=step
        )
        rot = SciRotation.from_quat(tr.quat, scalar_first=True)
        errors.append((exact.inv() * rot).magnitude().max())
    observed = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(observed - order) < 0.2), (errors, observed)
