"""Circular and nearly circular orbits (theory §9): the radial period and the apsidal
angle are smooth in the energy, so they must keep ~1e-13 there, against closed forms:
Kepler T = 2 pi sqrt(a^3/mu), apsidal angle pi; the oscillator T_r = pi/sqrt(k/m),
angle pi/2; U = -mu/r + beta/r^2: angle pi / sqrt(1 + 2 m beta / L^2) for every e."""

import math

import numpy as np
import pytest

from poinsot.dynamics import CentralOrbit, harmonic, inverse_square, kepler

# observed <= 5e-14; 1e-12 keeps 20x headroom (the target)
TOL = 1e-12


@pytest.mark.parametrize("e", [0.0, 1e-12, 1e-8, 1e-6, 1e-5, 1e-4, 1e-2])
@pytest.mark.parametrize("r0", [1.0, 3.0])
def test_kepler_near_circular_period_and_apsidal_angle(e, r0):
    """Released at pericentre r0 with the speed of eccentricity e (the 1e-8 orbit had a
    period 4.6e140 times too long before, the circular one 3e-11 off)."""
    mu = 1.0
    v = math.sqrt(mu * (1.0 + e) / r0)
    orb = CentralOrbit.from_state(kepler(mu), [r0, 0.0, 0.0], [0.0, v, 0.0])
    a = r0 / (1.0 - e)
    assert orb.radial_period == pytest.approx(2 * math.pi * math.sqrt(a**3 / mu), rel=TOL)
    assert orb.apsidal_angle == pytest.approx(math.pi, rel=TOL)


@pytest.mark.parametrize("k", [1.0, 4.0])
def test_oscillator_circular(k):
    r0 = 2.0
    orb = CentralOrbit.from_state(harmonic(k), [r0, 0.0, 0.0], [0.0, math.sqrt(k) * r0, 0.0])
    assert orb.is_circular
    assert orb.radial_period == pytest.approx(math.pi / math.sqrt(k), rel=TOL)
    assert orb.apsidal_angle == pytest.approx(math.pi / 2, rel=TOL)


@pytest.mark.parametrize("e", [0.0, 1e-9, 1e-7, 1e-3])
def test_perturbed_kepler_apsidal_angle_near_circular(e):
    """U = -1/r + 0.1/r^2 (a precessing ellipse): the apsidal angle is
    pi / sqrt(1 + 2 m beta / L^2) at every energy, the circular limit included."""
    beta = 0.1
    pot = kepler(1.0) + inverse_square(beta)
    r0 = 1.5
    # circular speed: m v^2 / r = U'(r) = 1/r^2 - 2 beta / r^3
    vc = math.sqrt(1.0 / r0 - 2.0 * beta / r0**2)
    orb = CentralOrbit.from_state(pot, [r0, 0.0, 0.0], [0.0, vc * (1 + e), 0.0])
    L = r0 * vc * (1 + e)
    assert orb.apsidal_angle == pytest.approx(math.pi / math.sqrt(1 + 2 * beta / L**2), rel=TOL)


def test_period_is_continuous_through_the_circular_limit():
    """T(E) near the bottom of the well: the near-circular branch and the quadratures
    (e = 1e-4 ... 1e-3, where both apply) agree with the closed form alike."""
    es = np.array([0.0, 1e-10, 1e-7, 3e-6, 1e-5, 2e-5, 1e-4])
    got = []
    for e in es:
        v = math.sqrt((1.0 + e) / 2.0)
        got.append(CentralOrbit.from_state(kepler(1.0), [2, 0, 0], [0, v, 0]).radial_period)
    ref = 2 * math.pi * np.sqrt((2.0 / (1.0 - es)) ** 3)
    np.testing.assert_allclose(got, ref, rtol=TOL)


def _kepler_mp(t, r0, v):
    """Position on the Kepler orbit (mu = 1) released at pericentre (r0, 0, 0) with speed
    v along y, from the same double inputs, by Kepler's equation in 50-digit mpmath."""
    mp = pytest.importorskip("mpmath")
    with mp.workdps(50):
        r0, v = mp.mpf(r0), mp.mpf(v)
        en = v**2 / 2 - 1 / r0
        a = -1 / (2 * en)
        e = mp.sqrt(1 + 2 * en * (r0 * v) ** 2)
        big_m = mp.sqrt(1 / a**3) * mp.mpf(t)
        big_m -= 2 * mp.pi * mp.floor(big_m / (2 * mp.pi) + mp.mpf(1) / 2)
        ea = mp.findroot(lambda x: x - e * mp.sin(x) - big_m, (-mp.pi, mp.pi), solver="anderson")
        return [float(a * (mp.cos(ea) - e)), float(a * mp.sqrt(1 - e**2) * mp.sin(ea)), 0.0]


@pytest.mark.parametrize(("e", "tol"), [(0.5, 1e-11), (0.99, 1e-9)])
def test_integrated_eccentric_orbit_over_three_periods(e, tol):
    """method='integrate' over three periods, through pericentre passages: observed
    4e-13 (e = 0.5) and 5e-11 (e = 0.99) relative to a, ~3x the problem's own
    sensitivity to one ulp of the speed at 0.99 (it was 4e-8 integrating in time)."""
    r0, v = 1.0, math.sqrt(1.0 + e)
    orb = CentralOrbit.from_state(kepler(1.0), [r0, 0.0, 0.0], [0.0, v, 0.0])
    a = r0 / (1.0 - e)
    period = 2 * math.pi * math.sqrt(a**3)
    t = np.array([-0.2, 0.37, 1.5, 2.99, 3.0]) * period
    ref = np.array([_kepler_mp(tk, r0, v) for tk in t])
    got = orb.orbit(t, method="integrate")
    assert np.max(np.linalg.norm(got - ref, axis=-1)) / a < tol


def test_a_nearly_parabolic_orbit_warns_with_the_size():
    """Integrated near e = 1 the orbit cannot be good to 1e-9 (one ulp of the speed moves
    a later pericentre by ~1.5 eps/(1-e) * periods * v_p T / a): it says so, with the
    size; at e = 0.5 it is silent (measured 4e-13)."""
    import warnings

    from poinsot import AccuracyWarning

    def orbit(e):
        return CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=math.sqrt(1.0 - e * e))

    near = orbit(0.9999)
    t = np.linspace(0.0, 3.0 * near.radial_period, 20)
    with pytest.warns(AccuracyWarning, match=r"e = 0\.9999.*good to ~[0-9.]+e-0[78] of a") as w:
        near.orbit(t, method="integrate")
    # issue 38: given by (E, L), the speed is no input: the warning names the kind of input
    # the bound holds for and the better-conditioned method
    text = str(w[0].message)
    assert "started from a state" in text and "(E, L)" in text and "method='kepler'" in text
    far = orbit(0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        far.orbit(np.linspace(0.0, 3.0 * far.radial_period, 20), method="integrate")
