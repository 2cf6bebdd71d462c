"""Torque models (theory §10) against hand-derived values and SciPy rotations.

Independent truths:
- gravity on a symmetric top with ``c = l e3`` tilted by the ZXZ nutation angle
  ``theta``: ``|M| = m g l sin(theta)``, ``M`` horizontal and along the line of
  nodes, ``V = m g l cos(theta)``; ``M_b = R^T (c_s x F)`` computed with SciPy;
- the potential is the work: ``V(t1) - V(t0) = -int M_b . w dt`` along a motion
  with known ``w(t)`` (Poisson's equation integrated by SciPy);
- a constant space torque is ``R^T M_s`` (SciPy), and ``simulate`` gives
  ``K_s(t) = K_s(0) + M_s t``.
"""

import pickle

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.dynamics import (
    STANDARD_GRAVITY,
    CallableTorque,
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityTorque,
    TorqueModel,
    as_torque,
    simulate,
)

RNG = np.random.default_rng(8)


@pytest.mark.parametrize("theta", [0.0, 0.3, 1.2, np.pi / 2, 2.5])
def test_gravity_on_tilted_symmetric_top(theta):
    m, g, l = 1.7, 9.81, 0.25
    psi, phi = 0.7, -1.1
    top = GravityTorque(m, [0.0, 0.0, l], g=g)
    q = SciRotation.from_euler("ZXZ", [psi, theta, phi]).as_quat(scalar_first=True)
    mb = top.body_torque(0.0, q, np.zeros(3))
    assert np.linalg.norm(mb) == pytest.approx(m * g * l * np.sin(theta), abs=1e-13)
    ms = SciRotation.from_quat(q, scalar_first=True).apply(mb)
    assert abs(ms[2]) < 1e-13  # horizontal
    # along the line of nodes (cos psi, sin psi, 0): the top falls about it
    node = np.array([np.cos(psi), np.sin(psi), 0.0])
    assert np.linalg.norm(np.cross(ms, node)) < 1e-13
    assert float(top.potential(q)) == pytest.approx(m * g * l * np.cos(theta), abs=1e-13)


def test_gravity_matches_cross_product_in_space_for_any_center_of_mass():
    m = RNG.uniform(0.5, 3.0, 5)
    c = RNG.normal(size=(5, 3))
    rot = SciRotation.random(5, random_state=3)
    top = GravityTorque(m, c)
    assert top.g == STANDARD_GRAVITY
    got = top.body_torque(1.0, rot.as_quat(scalar_first=True), np.zeros((5, 3)))
    c_s = rot.apply(c)
    force = m[:, None] * np.array([0.0, 0.0, -STANDARD_GRAVITY])
    np.testing.assert_allclose(got, rot.apply(np.cross(c_s, force), inverse=True), atol=1e-13)
    v = top.potential(rot.as_quat(scalar_first=True))
    np.testing.assert_allclose(v, m * STANDARD_GRAVITY * c_s[:, 2], rtol=1e-13)


def test_gravity_potential_difference_is_minus_the_work():
    """``dV/dt = -M . w``: integrate the attitude under a known ``w(t)`` and compare."""
    top = GravityTorque(2.0, [0.1, -0.2, 0.4], g=9.8)

    def omega(t):
        return np.array([1.0 + np.sin(t), 0.5 * np.cos(2 * t), 0.3 - 0.2 * t])

    def poisson(t, q):
        w = omega(t)
        q0, qv = q[0], q[1:]
        return 0.5 * np.concatenate([[-qv @ w], q0 * w + np.cross(qv, w)])

    q0 = SciRotation.from_rotvec([0.3, -0.5, 0.2]).as_quat(scalar_first=True)
    sol = solve_ivp(poisson, (0.0, 3.0), q0, rtol=1e-13, atol=1e-14, dense_output=True)

    def power(t):
        q = sol.sol(t)
        q = q / np.linalg.norm(q)
        return float(top.body_torque(t, q, omega(t)) @ omega(t))

    work, _ = quad(power, 0.0, 3.0, epsabs=1e-13, limit=200)
    q1 = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])
    dv = float(top.potential(q1) - top.potential(q0))
    assert abs(dv) > 0.1  # a real change
    assert dv == pytest.approx(-work, abs=1e-8)


def test_constant_torques_and_callable_frames():
    rot = SciRotation.random(4, random_state=1)
    q = rot.as_quat(scalar_first=True)
    m_s = np.array([0.3, -1.0, 2.0])
    want = rot.apply(m_s, inverse=True)
    np.testing.assert_allclose(
        ConstantSpaceTorque(m_s).body_torque(0.0, q, 0 * want), want, atol=1e-14
    )
    np.testing.assert_allclose(
        CallableTorque(lambda t, qq, w: m_s, frame="space").body_torque(0.0, q, 0 * want),
        want,
        atol=1e-14,
    )
    got = ConstantBodyTorque(m_s).body_torque(0.0, q, 0 * want)
    assert got.shape == (4, 3) and np.all(got == m_s)
    seen = {}

    def f(t, rotation, w):
        seen["type"] = type(rotation)
        return rotation.apply(m_s, inverse=True)

    np.testing.assert_allclose(as_torque(f).body_torque(0.0, q, 0 * want), want, atol=1e-14)
    assert seen["type"] is Rotation
    for model in (ConstantBodyTorque(m_s), ConstantSpaceTorque(m_s)):
        assert model.potential(q) is None and not model.conservative
    assert GravityTorque(1.0, [0, 0, 1.0]).conservative


def test_space_torque_momentum_balance_in_simulate():
    """``dK_s/dt = M_s`` (theory §9): ``K_s(t) = K_s(0) + M_s t`` for any body."""
    m_s = np.array([0.2, -0.1, 0.3])
    t = np.linspace(0.0, 4.0, 9)
    tr = simulate(
        [1.0, 2.0, 2.5],
        [1.0, 0, 0, 0],
        [0.3, 1.0, -0.2],
        t,
        torque=ConstantSpaceTorque(m_s),
        max_step=0.02,
        order=4,
    )
    # fourth-order midpoint with h = 0.02: observed error 2.3e-8
    np.testing.assert_allclose(tr.momentum, tr.momentum[0] + t[:, None] * m_s, atol=5e-7)


def test_gravity_model_in_simulate_conserves_energy_and_area_integral():
    from poinsot.dynamics import invariants

    top = GravityTorque(1.0, [0.05, 0.0, 0.3], g=9.81)
    j = [1.2, 1.0, 0.5]
    t = np.linspace(0.0, 1.5, 16)
    q0 = SciRotation.from_euler("ZXZ", [0.0, 0.5, 0.0]).as_quat(scalar_first=True)
    tr = simulate(j, q0, [0.5, 0.2, 12.0], t, torque=top, method="midpoint", order=4, max_step=5e-3)
    inv = invariants(j, tr.rotation, tr.omega, torque=top)
    e = inv.energy
    assert np.ptp(inv.potential) > 0.5  # the top does nutate (V changes by 0.77 J)
    # order 4, h = 5e-3: observed 1.9e-8 (relative energy), 5.4e-8 (K_z, kg m^2/s)
    assert np.max(np.abs(e - e[0])) < 5e-7 * abs(e[0])
    assert np.max(np.abs(inv.momentum_z - inv.momentum_z[0])) < 1e-6
    np.testing.assert_allclose(inv.kinetic, tr.energy, rtol=1e-13)
    np.testing.assert_allclose(inv.momentum_space, tr.momentum, atol=1e-12)


def test_batched_gravity_parameters_in_simulate():
    tops = GravityTorque([1.0, 2.0], [[0, 0, 0.3], [0, 0, 0.1]], g=9.81)
    t = np.linspace(0.0, 0.5, 3)
    tr = simulate(
        [1.0, 1.0, 0.5],
        [1.0, 0, 0, 0],
        np.zeros((2, 3)) + [0.1, 0, 5.0],
        t,
        torque=tops,
        max_step=1e-2,
    )
    for i in range(2):
        one = simulate(
            [1.0, 1.0, 0.5],
            [1.0, 0, 0, 0],
            [0.1, 0, 5.0],
            t,
            torque=GravityTorque(tops.mass[i], tops.center_of_mass[i], g=9.81),
            max_step=1e-2,
        )
        np.testing.assert_allclose(tr.omega[:, i], one.omega, atol=1e-14)


def test_models_pickle_and_are_frozen():
    top = GravityTorque(1.0, [0, 0, 1.0], g=3.0)
    back = pickle.loads(pickle.dumps(top))
    assert back.g == 3.0 and np.all(back.center_of_mass == [0, 0, 1.0])
    with pytest.raises(AttributeError):
        top.g = 1.0
    with pytest.raises(ValueError, match="read-only"):
        top.center_of_mass[0] = 1.0


def test_custom_subclass_used_by_simulate():
    class Damping(TorqueModel):
        def body_torque(self, t, quat, omega):
            return -0.2 * omega

    t = np.linspace(0.0, 2.0, 5)
    tr = simulate(
        [2.0, 2.0, 2.0], [1.0, 0, 0, 0], [0.0, 0.0, 1.0], t, torque=Damping(), method="adaptive"
    )
    np.testing.assert_allclose(tr.omega[:, 2], np.exp(-0.1 * t), rtol=1e-9)


def test_bad_torque_models():
    with pytest.raises(InvalidInputError, match="`mass` to be positive"):
        GravityTorque(-1.0, [0, 0, 1.0])
    with pytest.raises(InvalidInputError, match=r"`center_of_mass` to have shape \(\.\.\., 3\)"):
        GravityTorque(1.0, [0, 1.0])
    with pytest.raises(InvalidInputError, match="`g` to be non-negative"):
        GravityTorque(1.0, [0, 0, 1.0], g=-9.8)
    with pytest.raises(InvalidInputError, match="`g` to be a scalar"):
        GravityTorque(1.0, [0, 0, 1.0], g=[9.8, 9.8])
    with pytest.raises(InvalidInputError, match="batch"):
        GravityTorque([1.0, 2.0], [[0, 0, 1.0]] * 3)
    with pytest.raises(InvalidTypeError, match="`function` to be callable"):
        CallableTorque(3.0)
    with pytest.raises(InvalidInputError, match="`frame` to be one of"):
        CallableTorque(lambda t, q, w: w, frame="inertial")
    with pytest.raises(InvalidTypeError, match="`torque`"):
        as_torque("gravity")
    with pytest.raises(InvalidTypeError, match="`torque`"):
        ConstantBodyTorque("x")
    with pytest.raises(InvalidInputError, match=r"`torque` to return shape"):
        CallableTorque(lambda t, q, w: [1.0, 2.0]).body_torque(0.0, [1.0, 0, 0, 0], [0, 0, 1.0])


def test_torque_sum_adds_parts_and_their_potentials():
    """``a + b`` is the TorqueSum whose torque is the sum of the parts' (evaluated
    separately here) and whose potential is the sum when every part has one; a sum
    flattens (``(a + b) + c`` has three parts); simulate under a sum equals simulate
    under a CallableTorque of the same total."""
    from poinsot.dynamics import (
        CallableTorque,
        ConstantBodyTorque,
        GravityGradientTorque,
        GravityTorque,
        TorqueSum,
        simulate,
    )

    rng = np.random.default_rng(3)
    q = rng.normal(size=(5, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    w = rng.normal(size=(5, 3))
    a = GravityTorque(2.0, [0.0, 0.1, 0.5])
    b = GravityGradientTorque([1.0, 2.0, 3.0], 7.0e6, [1.0, 0.0, 0.0])
    c = ConstantBodyTorque([0.0, 0.0, 0.1])
    ab = a + b
    assert isinstance(ab, TorqueSum) and ab.conservative
    np.testing.assert_allclose(
        ab.body_torque(0.0, q, w), a.body_torque(0.0, q, w) + b.body_torque(0.0, q, w), rtol=1e-15
    )
    np.testing.assert_allclose(ab.potential(q), a.potential(q) + b.potential(q), rtol=1e-15)
    abc = ab + c
    assert len(abc.parts) == 3 and not abc.conservative and abc.potential(q) is None
    t = np.linspace(0.0, 2.0, 5)
    j = [1.0, 2.0, 3.0]
    by_sum = simulate(j, q[0], w[0], t, torque=abc, rtol=1e-11)
    total = CallableTorque(lambda tt, qq, ww: sum(m.body_torque(tt, qq, ww) for m in (a, b, c)))
    by_call = simulate(j, q[0], w[0], t, torque=total, rtol=1e-11)
    np.testing.assert_allclose(by_sum.omega, by_call.omega, rtol=0, atol=1e-12)
    with pytest.raises(InvalidTypeError, match="`parts`"):
        TorqueSum(())
    with pytest.raises(TypeError):
        a + 1.0
