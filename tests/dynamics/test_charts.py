"""Chart switching (theory §11.4): the spherical pendulum through its pole, against the
exact planar pendulum and a Cartesian integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import ellipj, ellipk

from poinsot.dynamics import simulate_charts, spherical_pendulum_charts
from poinsot.errors import InvalidInputError, InvalidTypeError

G, L = 9.81, 1.3


def test_planar_swing_through_the_pole_follows_the_exact_pendulum():
    theta0 = 1.2
    atlas = spherical_pendulum_charts(L, g=G)
    t = np.linspace(0.0, 6.0, 601)
    r0 = L * np.array([math.sin(theta0), 0.0, -math.cos(theta0)])
    tr = simulate_charts(atlas, r0, np.zeros(3), t)
    # sin(theta / 2) = k sn(K - w0 t, k), k = sin(theta0 / 2)
    k = math.sin(theta0 / 2)
    sn, cn, dn, _ = ellipj(ellipk(k * k) - math.sqrt(G / L) * t, k * k)
    theta = 2 * np.arcsin(k * sn)
    exact = L * np.stack([np.sin(theta), 0 * theta, -np.cos(theta)], axis=1)
    np.testing.assert_allclose(tr.position, exact, atol=1e-9)
    # it went through the bottom (the first chart's pole) in the second chart
    assert set(tr.chart.tolist()) == {0, 1}
    bottom = np.argmin(np.abs(theta))
    assert tr.chart[bottom] == 1
    switches = tr.info["events"].times("switch")
    assert switches.size >= 4  # twice per swing through the bottom


def test_spherical_pendulum_near_the_pole_matches_cartesian_coordinates():
    atlas = spherical_pendulum_charts(L, g=G)
    r0 = L * np.array([math.sin(0.8), 0.0, -math.cos(0.8)])
    v0 = np.array([0.0, 0.05, 0.0])  # passes 2 cm from the bottom point
    t = np.linspace(0.0, 8.0, 401)
    tr = simulate_charts(atlas, r0, v0, t)

    def rhs(_, y):  # r'' = g - lambda r with lambda keeping |r| = L
        r, v = y[:3], y[3:]
        gv = np.array([0.0, 0.0, -G])
        lam = (v @ v + gv @ r) / (r @ r)
        return np.concatenate([v, gv - lam * r])

    ref = solve_ivp(rhs, (0, 8), np.concatenate([r0, v0]), method="DOP853", rtol=1e-13,
                    atol=1e-15, t_eval=t)  # fmt: skip
    np.testing.assert_allclose(tr.position, ref.y[:3].T, atol=1e-8)
    energy = 0.5 * np.sum(tr.velocity**2, axis=1) + G * tr.position[:, 2]
    np.testing.assert_allclose(energy, energy[0], atol=1e-10)
    lz = tr.position[:, 0] * tr.velocity[:, 1] - tr.position[:, 1] * tr.velocity[:, 0]
    np.testing.assert_allclose(lz, lz[0], atol=1e-10)


def test_bad_atlases():
    a, _ = spherical_pendulum_charts(1.0)
    with pytest.raises(InvalidTypeError, match="charts"):
        simulate_charts([a], [0, 0, -1.0], [0, 0, 0], [0, 1.0])
    with pytest.raises(InvalidInputError, match="switch_below"):
        simulate_charts([a, a], [0, 0, -1.0], [0, 0, 0], [0, 1.0], switch_below=2)
    with pytest.raises(InvalidInputError, match="length"):
        spherical_pendulum_charts(-1.0)
