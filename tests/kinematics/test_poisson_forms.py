"""Theory §5: Poisson's equation is linear, with the constant factor on the side away
from omega: body form L' = L o w_xi / 2 is solved by L0 o L*, space form
L' = w_x o L / 2 by L* o L0 (checked by integrating each form with SciPy at tight
tolerance, and showing the wrong side does not solve it)."""

import numpy as np
from scipy.integrate import solve_ivp

from poinsot.rotations.quaternion import multiply, normalize

T = np.linspace(0.0, 3.0, 31)


def _omega(t):
    return np.array([0.0, np.sin(t), 0.3 * np.cos(2 * t), 0.5 + 0.2 * t])  # pure quaternion


def _solve(l_init, form):
    def rhs(t, y):
        w = _omega(t)
        return 0.5 * (multiply(y, w) if form == "body" else multiply(w, y))

    sol = solve_ivp(rhs, (T[0], T[-1]), l_init, t_eval=T, rtol=1e-12, atol=1e-14, method="DOP853")
    return sol.y.T


def test_constant_factor_sides():
    rng = np.random.default_rng(1)
    l_star_0 = normalize(rng.normal(size=4))
    l0 = normalize(rng.normal(size=4))
    for form in ("body", "space"):
        l_star = _solve(l_star_0, form)
        good = multiply(l0, l_star) if form == "body" else multiply(l_star, l0)
        wrong = multiply(l_star, l0) if form == "body" else multiply(l0, l_star)
        direct = _solve(good[0], form)
        # observed ~1e-13; the integrations' tolerance bounds both
        np.testing.assert_allclose(good, direct, atol=1e-9)
        assert np.max(np.abs(wrong - _solve(wrong[0], form))) > 1e-2
