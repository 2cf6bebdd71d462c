"""Forces and the general theorems for systems of particles (theory §9).

The general theorems are checked on an integrated system (three particles joined by
springs -- internal forces that do work -- under gravity, linear drag and a Lorentz
force): the time derivatives of p, K_O' (about a moving point O') and T, taken by
finite differences of the integrated samples (Fornberg weights), against
R^e, M_O'^e - m V_O' x V_c and N^e + N^i computed from the forces.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from poinsot.dynamics import (
    ParticleSystem,
    classify_force,
    shift_angular_momentum,
)
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.kinematics import fornberg_weights

M = np.array([1.0, 2.0, 1.5])
K = 3.0  # spring stiffness
REST = 1.0
G = np.array([0.0, 0.0, -9.81])
BETA = 0.2  # drag
QB = np.array([0.0, 0.5, 1.0])  # charge times magnetic field (Lorentz force q v x B)


def _internal(x):
    f = np.zeros_like(x)
    for i in range(3):
        for j in range(i + 1, 3):
            d = x[j] - x[i]
            n = np.linalg.norm(d)
            fij = K * (n - REST) * d / n  # on i, towards j when stretched
            f[i] += fij
            f[j] -= fij
    return f


def _external(x, v):
    return M[:, None] * G - BETA * v + np.cross(v, QB) * np.array([1.0, 0.0, 1.0])[:, None]


def _rhs(_t, y):
    x, v = y[:9].reshape(3, 3), y[9:].reshape(3, 3)
    a = (_internal(x) + _external(x, v)) / M[:, None]
    return np.concatenate([v.ravel(), a.ravel()])


@pytest.fixture(scope="module")
def motion():
    x0 = np.array([[0.0, 0.0, 0.0], [1.2, 0.1, 0.0], [0.3, 0.9, 0.4]])
    v0 = np.array([[0.0, 0.5, 1.0], [-0.3, 0.0, 0.2], [0.4, -0.6, 0.0]])
    t = np.linspace(0.0, 2.0, 201)
    sol = solve_ivp(
        _rhs,
        (0, 2),
        np.concatenate([x0.ravel(), v0.ravel()]),
        method="DOP853",
        t_eval=t,
        rtol=1e-13,
        atol=1e-13,
    )
    x = sol.y[:9].T.reshape(-1, 3, 3)
    v = sol.y[9:].T.reshape(-1, 3, 3)
    return t, x, v


def _ddt(t, y):
    """Time derivative at the interior samples 4..n-5 (9-point Fornberg weights)."""
    out = []
    for k in range(4, t.size - 4):
        w = fornberg_weights(t[k], t[k - 4 : k + 5], 1)
        out.append(np.tensordot(w, y[k - 4 : k + 5], axes=(0, 0)))
    return np.array(out)


def test_momentum_theorem(motion):
    t, x, v = motion
    sys = ParticleSystem(M, x, v)
    fe = np.array([_external(xk, vk) for xk, vk in zip(x, v, strict=True)])
    dp = _ddt(t, sys.momentum)
    re = sys.resultant(fe)[4:-4]
    assert np.max(np.abs(dp - re)) < 1e-8 * np.max(np.abs(re))  # observed 1.5e-12 relative
    # the internal forces cancel: p' = R^e, not R^e + R^i
    fi = np.array([_internal(xk) for xk in x])
    assert np.max(np.abs(sys.resultant(fi))) < 1e-12


def test_angular_momentum_theorem_about_a_moving_point(motion):
    t, x, v = motion
    sys = ParticleSystem(M, x, v)
    o = np.stack([np.cos(t), np.sin(2 * t), 0.3 * t], -1)  # a moving point O'
    vo = np.stack([-np.sin(t), 2 * np.cos(2 * t), 0.3 + 0 * t], -1)
    k = sys.angular_momentum(o)
    fe = np.array([_external(xk, vk) for xk, vk in zip(x, v, strict=True)])
    rhs = sys.moment(fe, o) - sys.total_mass[..., None] * np.cross(vo, sys.center_velocity)
    dk = _ddt(t, k)
    assert np.max(np.abs(dk - rhs[4:-4])) < 1e-8 * np.max(np.abs(rhs))
    # the shift formula K_O' = K_O + O'O x p
    k0 = sys.angular_momentum()
    np.testing.assert_allclose(
        shift_angular_momentum(k0, sys.momentum, np.zeros(3), o), k, atol=1e-12
    )


def test_energy_theorem_internal_forces_do_work(motion):
    t, x, v = motion
    sys = ParticleSystem(M, x, v)
    fe = np.array([_external(xk, vk) for xk, vk in zip(x, v, strict=True)])
    fi = np.array([_internal(xk) for xk in x])
    dT = _ddt(t, sys.kinetic_energy)
    n_e, n_i = sys.power(fe), sys.power(fi)
    assert np.max(np.abs(dT - (n_e + n_i)[4:-4])) < 1e-8 * np.max(np.abs(n_e + n_i))
    assert np.max(np.abs(n_i)) > 0.1  # springs: N^i != 0 for a deformable system
    # the Lorentz part does no work
    lorentz = np.cross(v, QB) * np.array([1.0, 0.0, 1.0])[:, None]
    assert np.max(np.abs(np.sum(lorentz * v, -1))) < 1e-12


def test_koenig_split(motion):
    _, x, v = motion
    sys = ParticleSystem(M, x, v)
    kg = sys.koenig()
    vc = np.einsum("n,kni->ki", M, v) / M.sum()
    np.testing.assert_allclose(kg.center, 0.5 * M.sum() * np.sum(vc * vc, -1), rtol=1e-13)
    rel = v - vc[:, None]
    np.testing.assert_allclose(
        kg.relative, 0.5 * np.einsum("n,kn->k", M, np.sum(rel**2, -1)), rtol=1e-13
    )
    np.testing.assert_allclose(kg.center + kg.relative, kg.total, rtol=1e-13)
    np.testing.assert_allclose(sys.center_of_mass, np.einsum("n,kni->ki", M, x) / M.sum())


def test_classify_forces():
    mu = 2.0
    grav = classify_force(lambda t, r, v: -mu * r / np.linalg.norm(r) ** 3, center=[3, 0, 0])
    assert grav.kind == "potential" and grav.curl_free and not grav.velocity_dependent
    # the returned potential is -mu/r + const: differences against the exact one
    pts = np.array([[3.5, 0.2, -0.1], [2.4, -0.6, 0.5], [3.0, 0.0, 0.0]])
    u = grav.potential(pts)
    exact = -mu / np.linalg.norm(pts, axis=-1)
    np.testing.assert_allclose(u - u[2], exact - exact[2], atol=1e-12)
    assert grav.potential_residual < 1e-8

    w = np.array([0.2, -0.1, 0.9])
    cor = classify_force(lambda t, r, v: -2.0 * np.cross(w, v))
    assert cor.kind == "gyroscopic"
    assert classify_force(lambda t, r, v: 1.5 * np.cross(v, [0, 0, 2.0])).kind == "gyroscopic"
    drag = classify_force(lambda t, r, v: -0.7 * np.linalg.norm(v) * v)
    assert drag.kind == "dissipative"
    swirl = classify_force(lambda t, r, v: np.array([-r[1], r[0], 0.0]))
    assert swirl.kind == "none" and not swirl.curl_free
    assert swirl.asymmetry == pytest.approx(2.0, rel=1e-6)  # J - J^T has entries +-2, |J| 1
    timed = classify_force(lambda t, r, v: -(1.0 + t) * r)
    assert timed.kind == "none" and timed.curl_free and timed.time_dependent
    pushing = classify_force(lambda t, r, v: 0.3 * v)
    assert pushing.kind == "none"
    # symmetric Jacobian, non-central: U = x y z
    f = classify_force(lambda t, r, v: -np.array([r[1] * r[2], r[0] * r[2], r[0] * r[1]]))
    assert f.kind == "potential"
    p = np.array([[0.3, -0.2, 0.5]])
    assert f.potential(p)[0] == pytest.approx(0.3 * -0.2 * 0.5, abs=1e-13)


def test_bad_input():
    with pytest.raises(InvalidTypeError, match="callable"):
        classify_force(3.0)
    with pytest.raises(InvalidInputError, match="shape"):
        classify_force(lambda t, r, v: [1.0, 2.0])
    with pytest.raises(InvalidInputError, match="finite"):
        classify_force(lambda t, r, v: np.array([np.nan, 0, 0]))
    with pytest.raises(InvalidInputError, match="size"):
        classify_force(lambda t, r, v: -r, size=-1.0)
    with pytest.raises(InvalidInputError, match="masses"):
        ParticleSystem([-1.0, 1.0], np.zeros((2, 3)), np.zeros((2, 3)))
    with pytest.raises(InvalidInputError, match="positions"):
        ParticleSystem([1.0, 1.0], np.zeros((3, 3)), np.zeros((2, 3)))
    with pytest.raises(InvalidInputError, match="finite"):
        ParticleSystem([1.0, np.inf], np.zeros((2, 3)), np.zeros((2, 3)))
