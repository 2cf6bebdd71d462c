"""Tests of the Kovalevskaya integral (docs/theory.md §10).

Oracles: the time derivative of ``k(omega, gamma)`` along the Euler-Poisson
vector field, by central finite differences (it vanishes in the Kovalevskaya case
``A = B = 2 C``, centre of mass in the equatorial plane, and not for
``A = B = 2.2 C``); a long accurate run (poinsot's compiled DOP853 at rtol 1e-13,
its own error measured against rtol 1e-12). Kovalevskaya (1889), Acta Math. 12;
Golubev, *Lectures on integration of the equations of motion of a rigid body*.
"""

from __future__ import annotations

import numpy as np
import pytest

from poinsot import InvalidInputError, Rotation
from poinsot.dynamics import HeavyRigidBody, kovalevskaya_integral

C = 1.3


def _body(ratio, com=(0.4, 0.0, 0.0)):
    return HeavyRigidBody([ratio * C, ratio * C, C], 2.0, list(com), g=9.81)


def _dk_dt(body, w, gamma, h=1e-6):
    dw, dg = body.euler_poisson(w, gamma)

    def k(s):
        return kovalevskaya_integral(w + s * dw, gamma + s * dg, C, body.moment)

    return (k(h) - k(-h)) / (2 * h), k(0.0)


@pytest.mark.parametrize("com", [(0.4, 0.0, 0.0), (0.3, -0.25, 0.0)])
def test_derivative_vanishes_only_in_the_kovalevskaya_case(com):
    rng = np.random.default_rng(7)
    for _ in range(5):
        w = rng.normal(size=3) * 3
        gamma = Rotation.from_quat(rng.normal(size=4)).apply([0, 0, 1.0], inverse=True)
        dk, k = _dk_dt(_body(2.0, com), w, gamma)
        dk_other, _ = _dk_dt(_body(2.2, com), w, gamma)
        # the finite-difference error is ~1e-9 relative; the non-integrable case is O(1)
        assert abs(dk) < 1e-7 * (abs(k) + 1.0)
        assert abs(dk_other) > 1e-3 * (abs(k) + 1.0)


def test_conserved_over_a_long_run_and_not_for_other_moments():
    t = np.linspace(0.0, 50.0, 501)
    q0 = Rotation.from_euler("ZXZ", [0.1, 1.0, 0.3]).as_quat()
    w0 = [1.5, -0.7, 2.0]
    out = {}
    for ratio in (2.0, 2.2):
        body = _body(ratio)
        tr = body.simulate(q0, w0, t, method="dop853", rtol=1e-13, atol=1e-13)
        k = body.kovalevskaya_integral(tr.rotation, tr.omega)
        out[ratio] = np.abs(k - k[0]).max() / abs(k[0])
        if ratio == 2.0:
            tr2 = body.simulate(q0, w0, t, method="dop853", rtol=1e-12, atol=1e-12)
            k2 = body.kovalevskaya_integral(tr2.rotation, tr2.omega)
            assert np.abs(k2 - k).max() / abs(k[0]) < 1e-8  # the reference's own error
    assert out[2.0] < 1e-10  # observed ~1e-12
    assert out[2.2] > 1e-2  # visibly not conserved


def test_formula_and_bad_input():
    # z = (p + i q)^2 - (m g / C)(c1 + i c2)(g1 + i g2); |z|^2
    w = np.array([0.3, -1.1, 2.0])
    g = np.array([0.6, 0.0, 0.8])
    mg = np.array([1.0, 0.5, 0.0])
    z = (w[0] + 1j * w[1]) ** 2 - (mg[0] + 1j * mg[1]) / C * (g[0] + 1j * g[1])
    assert np.isclose(kovalevskaya_integral(w, g, C, mg), abs(z) ** 2, rtol=1e-14)
    with pytest.raises(InvalidInputError, match="equatorial plane"):
        kovalevskaya_integral(w, g, C, [1.0, 0.0, 0.2])
    with pytest.raises(InvalidInputError, match="axial_moment"):
        kovalevskaya_integral(w, g, -1.0, mg)
    with pytest.raises(InvalidInputError, match="omega"):
        kovalevskaya_integral([np.nan, 0, 0], g, C, mg)
