"""The gyrostat in the fused compiled integrators (issue 41): ``simulate(...,
torque=GyrostaticTorque(h))`` (kind 5 of :mod:`poinsot.dynamics._fused`, the torque
``h x w``) against :class:`poinsot.dynamics.FreeGyrostat` (docs/theory.md §10.1).

Oracles: the exact dual-spin solution (``h`` along a principal axis; Jacobi elliptic
functions, omega to ~1e-15, tests/dynamics/test_gyrostat.py); for a general ``h``
(Volterra's gyrostat, no closed form) the integrals ``T = w . J w / 2``, ``|J w + h|``
and the space vector ``K = R (J w + h)``, and FreeGyrostat's own numeric fallback
(SciPy DOP853 at rtol 1e-12); the same torque as a Python callable
(:class:`~poinsot.dynamics.CallableTorque`, the NumPy/SciPy paths) for RK4, the midpoint
rule and a heterogeneous batch. Every tolerance is >= 10x the error observed (noted).
"""

from __future__ import annotations

import numpy as np
import pytest

from poinsot import InvalidInputError, Rotation
from poinsot.dynamics import (
    CallableTorque,
    ConstantBodyTorque,
    FreeGyrostat,
    GyrostaticTorque,
    TorqueSum,
    simulate,
)

J = np.array([1.0, 2.0, 3.0])
Q0 = Rotation.from_rotvec([0.3, -0.2, 0.5])
W0 = np.array([0.1, 1.0, 0.1])


def _angle(r, s):
    """Rotation angle of ``r^-1 s`` (rad)."""
    return (r.inv() * s).magnitude()


def _python_gyro(h):
    """The same torque as a Python function: the slower paths of ``simulate``."""
    h = np.asarray(h, dtype=float)
    return CallableTorque(lambda t, q, w: np.cross(h, w))


def test_torque_model_formula_shapes_and_errors():
    g = GyrostaticTorque([0.0, 0.0, 2.0])
    np.testing.assert_array_equal(g.body_torque(0.0, [1.0, 0, 0, 0], [1.0, 0.0, 0.0]),
                                  [0.0, 2.0, 0.0])  # fmt: skip
    hb = np.random.default_rng(0).normal(size=(4, 3))
    w = np.random.default_rng(1).normal(size=(4, 3))
    q = np.tile([1.0, 0, 0, 0], (4, 1))
    np.testing.assert_array_equal(GyrostaticTorque(hb).body_torque(0.0, q, w), np.cross(hb, w))
    assert GyrostaticTorque(hb).body_torque(0.0, q[0], w[0]).shape == (4, 3)  # broadcast
    assert not g.conservative and g.potential(q) is None
    with pytest.raises(InvalidInputError, match="`h`"):
        GyrostaticTorque([1.0, 2.0])
    with pytest.raises(InvalidInputError, match="`h`"):
        GyrostaticTorque([1.0, np.nan, 0.0])


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_dual_spin_matches_the_exact_solution(axis):
    """``h`` along a principal axis: exact omega and attitude over 3 periods."""
    h = np.zeros(3)
    h[axis] = 0.5
    exact = FreeGyrostat(J, h, rotation0=Q0, omega0=W0)
    assert exact.regime in ("four_roots", "two_roots")
    t = np.linspace(0.0, 3.0 * exact.period, 61)
    tr = simulate(J, Q0, W0, t, torque=GyrostaticTorque(h), rtol=1e-12, atol=1e-14)
    assert tr.info["solver"].startswith("DOP853 (compiled")
    assert tr.info["conserved"] == ("energy",)
    w_ref = exact.omega(t)
    # observed <= 8.6e-10 (omega, relative) and 7.0e-10 rad (h along axis 2, the longest
    # period: 77 s; 2.2e-12 and 7.7e-12 along the others)
    assert np.abs(tr.omega - w_ref).max() / np.abs(w_ref).max() < 1e-8
    assert _angle(tr.rotation, exact.rotation(t)).max() < 1e-8


def test_volterra_gyrostat_keeps_its_integrals_and_matches_the_fallback():
    """A general ``h`` (no closed form): T, |J w + h| and K = R (J w + h) conserved."""
    h = np.array([0.3, -0.4, 0.25])
    t = np.linspace(0.0, 60.0, 61)
    tr = simulate(J, Q0, W0, t, torque=GyrostaticTorque(h), rtol=1e-12, atol=1e-14)
    m = J * tr.omega + h
    k = np.linalg.norm(m, axis=-1)
    energy = 0.5 * np.sum(J * tr.omega**2, axis=-1)
    ks = tr.rotation.apply(m)
    # observed 1.1e-12, 1.8e-12, 2.7e-12
    assert np.abs(k / k[0] - 1.0).max() < 3e-11
    assert np.abs(energy / energy[0] - 1.0).max() < 3e-11
    assert np.abs(ks - ks[0]).max() / k[0] < 3e-11
    np.testing.assert_allclose(tr.energy, energy, rtol=1e-14)
    fallback = FreeGyrostat(J, h, rotation0=Q0, omega0=W0)
    assert fallback.regime == "numeric"
    # observed 2.9e-13 and 1.4e-12 rad (the fallback's own error is of this order)
    assert np.abs(tr.omega - fallback.omega(t)).max() < 1e-11
    assert _angle(tr.rotation, fallback.rotation(t)).max() < 3e-11


def _batch(n, seed=3):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))  # the triangle inequality holds
    h = rng.normal(size=(n, 3)) * rng.uniform(0.0, 2.0, (n, 1))
    h[: n // 3] = 0.0  # dual spin: h along one principal axis
    h[: n // 3, 2] = rng.uniform(-1.0, 1.0, n // 3)
    omega = rng.normal(size=(n, 3))
    quat = rng.normal(size=(n, 4))
    return moments, quat / np.linalg.norm(quat, axis=1, keepdims=True), omega, h


def test_heterogeneous_batch_lanes_and_python_path():
    """A batch of gyrostats (the lane kernel): each body equals its own exact motion
    (dual spin) or keeps its integrals, and the Python-callable path agrees."""
    n = 27
    moments, quat, omega, h = _batch(n)
    t = np.linspace(0.0, 8.0, 9)
    tr = simulate(moments, quat, omega, t, torque=GyrostaticTorque(h), rtol=1e-12, atol=1e-14)
    ref = simulate(moments, quat, omega, t, torque=_python_gyro(h), method="dop853",
                   rtol=1e-12, atol=1e-14)  # fmt: skip
    assert ref.info["path"].startswith("solve_ivp")
    # observed 4.9e-12 (omega) and 3.6e-12 rad between the two solvers
    assert np.abs(tr.omega - ref.omega).max() < 1e-10
    assert _angle(tr.rotation, ref.rotation).max() < 1e-10
    exact = FreeGyrostat(moments[: n // 3], h[: n // 3], rotation0=quat[: n // 3],
                         omega0=omega[: n // 3])  # fmt: skip
    w_ref = np.moveaxis(exact.omega(t), 0, 1)  # (bodies, t, 3) -> (t, bodies, 3)
    q_ref = Rotation.from_quat(np.moveaxis(exact.rotation(t).as_quat(), 0, 1))
    # observed 5.4e-13 and 1.8e-12 rad
    assert np.abs(tr.omega[:, : n // 3] - w_ref).max() < 1e-11
    assert _angle(Rotation.from_quat(tr.quat[:, : n // 3]), q_ref).max() < 3e-11
    m = moments * tr.omega + h
    energy = 0.5 * np.sum(moments * tr.omega**2, axis=-1)
    # observed 2.5e-12 and 2.6e-12
    assert np.abs(energy / energy[0] - 1.0).max() < 3e-11
    ks = tr.rotation.apply(m)
    assert (np.linalg.norm(ks - ks[0], axis=-1) / np.linalg.norm(m[0], axis=-1)).max() < 3e-11


@pytest.mark.parametrize("method", ["rk4", "midpoint"])
def test_fixed_step_methods_compiled_equal_their_python_paths(method):
    moments, quat, omega, h = _batch(5, seed=8)
    t = np.linspace(0.0, 2.0, 5)
    a = simulate(moments, quat, omega, t, torque=GyrostaticTorque(h), method=method,
                 max_step=1e-2)  # fmt: skip
    b = simulate(moments, quat, omega, t, torque=_python_gyro(h), method=method, max_step=1e-2)
    assert a.info.get("path", "compiled") == "compiled"
    assert b.info["path"].startswith("NumPy")
    # observed: rk4 omega equal bit for bit (1.6e-16 rad); midpoint 7.5e-15 and 8.7e-15
    # rad (the NumPy step's products in another order)
    tol = 1e-13 if method == "rk4" else 1e-11
    assert np.abs(a.omega - b.omega).max() < tol
    assert _angle(a.rotation, b.rotation).max() < tol
    # the conserved energy: observed 2.8e-12 (rk4, its truncation error), 4.9e-14 (midpoint)
    energy = 0.5 * np.sum(moments * a.omega**2, axis=-1)
    assert np.abs(energy / energy[0] - 1.0).max() < 3e-11


def test_composes_with_other_torques():
    """``GyrostaticTorque + ConstantBodyTorque`` (a TorqueSum, evaluated from Python)
    equals the same sum written as one Python function."""
    h, m = np.array([0.2, 0.0, 0.7]), np.array([0.01, -0.02, 0.005])
    both = GyrostaticTorque(h) + ConstantBodyTorque(m)
    assert isinstance(both, TorqueSum)
    t = np.linspace(0.0, 3.0, 7)
    a = simulate(J, Q0, W0, t, torque=both, rtol=1e-12, atol=1e-14)
    b = simulate(J, Q0, W0, t, torque=CallableTorque(lambda t, q, w: np.cross(h, w) + m),
                 rtol=1e-12, atol=1e-14)  # fmt: skip
    np.testing.assert_allclose(a.omega, b.omega, rtol=0, atol=1e-14)
    # and without the constant part it is the compiled kind: the same motion
    c = simulate(J, Q0, W0, t, torque=GyrostaticTorque(h) + ConstantBodyTorque([0.0, 0, 0]),
                 rtol=1e-12, atol=1e-14)  # fmt: skip
    d = simulate(J, Q0, W0, t, torque=GyrostaticTorque(h), rtol=1e-12, atol=1e-14)
    # observed 1.1e-13 (two solvers)
    assert np.abs(c.omega - d.omega).max() < 1e-11


def test_free_gyrostat_torque_property_integrates_the_same_batch():
    """``FreeGyrostat.torque``: ``simulate`` on a batch mixing closed-form and numeric
    regimes reproduces ``omega(t)`` and ``rotation(t)`` of each body."""
    h = np.array([[0.0, 0.0, 0.8], [0.3, 0.0, 0.4], [0.0, -1.2, 0.0], [0.5, 0.5, -0.2]])
    w0 = np.array([[0.3, 0.5, 0.7], [0.3, 0.5, 0.7], [1.0, 0.2, -0.4], [0.1, -1.0, 0.3]])
    g = FreeGyrostat(J, h, rotation0=Q0, omega0=w0)
    assert list(g.regime) == ["four_roots", "numeric", "four_roots", "numeric"]
    t = np.linspace(0.0, 10.0, 11)
    tr = simulate(g.inertia, g.rotation0, g.omega0, t, torque=g.torque, rtol=1e-12, atol=1e-14)
    # observed 1.8e-12 and 2.2e-12 rad (the fallback's own error is of this order)
    assert np.abs(tr.omega - np.moveaxis(g.omega(t), 0, 1)).max() < 3e-11
    ref = Rotation.from_quat(np.moveaxis(g.rotation(t).as_quat(), 0, 1))
    assert _angle(tr.rotation, ref).max() < 3e-11
