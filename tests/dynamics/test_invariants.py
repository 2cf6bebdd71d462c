"""``poinsot.dynamics.invariants`` against hand-computed values (theory §8, §10).

Truths: ``T = (A p^2 + B q^2 + C r^2)/2`` written out by components, ``K = J w``
with the tensor rotated by SciPy (``J_b = S diag S^T`` gives the same ``T`` and
``|K|`` for ``w_b = S w_p``), ``K_s = R K`` with SciPy's rotation, and the
free-body/heavy-top integrals along a SciPy DOP853 reference solution.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.dynamics import (
    GravityTorque,
    Invariants,
    angular_momentum,
    invariants,
    kinetic_energy,
)

RNG = np.random.default_rng(88)


def test_principal_components_by_hand():
    a, b, c = 1.5, 2.0, 3.25
    p, q, r = 0.3, -1.1, 0.7
    assert kinetic_energy([a, b, c], [p, q, r]) == pytest.approx(
        0.5 * (a * p * p + b * q * q + c * r * r), rel=1e-15
    )
    np.testing.assert_array_equal(angular_momentum([a, b, c], [p, q, r]), [a * p, b * q, c * r])


def test_tensor_equals_rotated_principal_form():
    moments = np.array([1.0, 2.0, 2.5])
    s = SciRotation.from_rotvec([0.4, -0.3, 1.1]).as_matrix()
    j_b = s @ np.diag(moments) @ s.T
    w_p = RNG.normal(size=(6, 3))
    w_b = w_p @ s.T
    np.testing.assert_allclose(kinetic_energy(j_b, w_b), kinetic_energy(moments, w_p), rtol=1e-14)
    np.testing.assert_allclose(angular_momentum(j_b, w_b), (moments * w_p) @ s.T, atol=1e-14)


def test_invariants_space_momentum_and_area_integral():
    j = np.array([1.0, 2.0, 3.0])
    rot = SciRotation.random(5, random_state=2)
    w = RNG.normal(size=(5, 3))
    for attitude in (
        rot,
        Rotation.from_quat(rot.as_quat(scalar_first=True)),
        rot.as_quat(scalar_first=True),
    ):
        inv = invariants(j, attitude, w)
        assert isinstance(inv, Invariants)
        np.testing.assert_allclose(inv.momentum_space, rot.apply(j * w), atol=1e-14)
        np.testing.assert_allclose(inv.momentum_z, rot.apply(j * w)[:, 2], atol=1e-14)
        np.testing.assert_allclose(inv.momentum_norm, np.linalg.norm(j * w, axis=-1), rtol=1e-14)
        assert inv.potential is None
        np.testing.assert_array_equal(inv.energy, inv.kinetic)


def test_heavy_top_energy_with_potential_by_hand():
    # upright top (identity attitude): V = m g l; spinning about e3: T = C r^2 / 2, K_z = C r
    inv = invariants(
        [1.0, 1.0, 0.4],
        [1.0, 0, 0, 0],
        [0.0, 0.0, 20.0],
        torque=GravityTorque(0.5, [0.0, 0.0, 0.2], g=9.8),
    )
    assert float(inv.potential) == pytest.approx(0.5 * 9.8 * 0.2, rel=1e-15)
    assert float(inv.kinetic) == pytest.approx(0.5 * 0.4 * 400.0, rel=1e-15)
    assert float(inv.energy) == pytest.approx(80.0 + 0.98, rel=1e-15)
    assert float(inv.momentum_z) == pytest.approx(8.0, rel=1e-15)


def test_batch_broadcast_and_errors():
    inv = invariants(np.ones((4, 1, 3)), [1.0, 0, 0, 0], np.ones((5, 3)))
    assert inv.kinetic.shape == (4, 5) and inv.momentum_space.shape == (4, 5, 3)
    with pytest.raises(InvalidInputError, match="batch"):
        kinetic_energy(np.ones((2, 3)), np.ones((3, 3)))
    with pytest.raises(InvalidInputError, match="triangle"):
        kinetic_energy([1.0, 1.0, 5.0], [1.0, 0, 0])
    with pytest.raises(InvalidInputError, match=r"`omega` to have shape \(\.\.\., 3\)"):
        angular_momentum([1.0, 1.0, 1.0], [1.0, 0])
    with pytest.raises(InvalidTypeError, match="`rotation`"):
        invariants([1.0, 1.0, 1.0], {"w": 1}, [1.0, 0, 0])
    with pytest.raises(InvalidTypeError, match="`inertia`"):
        kinetic_energy("J", [1.0, 0, 0])


def test_single_state_short_path_agrees_and_keeps_checks():
    rng = np.random.default_rng(5)
    for _ in range(100):
        j = np.sort(rng.uniform(0.5, 3.0, 3))
        j[2] = min(j[2], j[0] + j[1])
        w = rng.normal(size=3)
        one = kinetic_energy(j, w)
        batch = kinetic_energy(j[None], w[None])[0]
        assert one.shape == () and abs(one - batch) <= 2e-14 * batch  # 2 ulp seen
    with pytest.raises(InvalidInputError, match="triangle"):
        kinetic_energy([1.0, 1.0, 2.5], [1.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="`omega` to contain only finite"):
        kinetic_energy([1.0, 1.0, 1.0], [np.nan, 0.0, 0.0])
