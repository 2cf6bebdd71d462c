"""Central-force orbits (theory §9) against closed forms and 30-digit mpmath quadratures.

Truths: Kepler's period 2 pi a^(3/2) sqrt(m/mu) (2 pi a^(3/2)/sqrt(mu) for m = 1) and
apsidal angle pi; the oscillator's apsidal angle pi/2 and radial period pi sqrt(m/k);
U = -mu/r + beta/r^2 has apsidal angle pi / sqrt(1 + 2 beta m / L^2) (Goldstein,
Classical Mechanics, ch. 3 problems); a hyperbola's angle from pericentre to infinity
arccos(-1/e); for a generic potential mpmath's tanh-sinh quadrature at 30 digits.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from poinsot.dynamics import CentralOrbit, Potential, harmonic, inverse_square, kepler
from poinsot.errors import InvalidInputError, InvalidTypeError

PI = math.pi


@pytest.mark.parametrize(
    ("mu", "E", "L", "m"),
    [
        (1.0, -0.5, 0.8, 1.0),
        (3.0, -0.2, 0.3, 2.0),
        (1.0, -0.5, 0.05, 1.0),
        (1.0, -0.5, 0.999, 1.0),
        (4e14, -1.5e7, 5.2e10, 1.0),
    ],
)
def test_kepler_period_and_apsidal_angle(mu, E, L, m):
    orb = CentralOrbit(kepler(mu), energy=E, angular_momentum=L, mass=m)
    a = -mu / (2 * E)
    assert orb.radial_period == pytest.approx(2 * PI * a**1.5 * math.sqrt(m / mu), rel=1e-12)
    assert orb.apsidal_angle == pytest.approx(PI, rel=1e-12)  # observed <= 3e-16
    c = orb.conic
    r1, r2 = orb.apsides
    assert r1 == pytest.approx(c.p / (1 + c.e), rel=1e-12)
    assert r2 == pytest.approx(c.p / (1 - c.e), rel=1e-12)
    assert c.period == pytest.approx(orb.radial_period, rel=1e-12)
    assert orb.is_closed() and orb.closure() == 1


def test_kepler_unit_mass_period_formula():
    mu, a = 2.5, 1.7
    E = -mu / (2 * a)
    orb = CentralOrbit(kepler(mu), energy=E, angular_momentum=0.9)
    assert orb.radial_period == pytest.approx(2 * PI * a**1.5 / math.sqrt(mu), rel=1e-13)
    assert orb.areal_velocity * orb.radial_period == pytest.approx(
        PI * a * a * math.sqrt(1 - orb.conic.e**2), rel=1e-12
    )  # Kepler's second law: the ellipse's area


def test_harmonic_apsidal_angle_is_half_pi():
    k, m = 2.0, 1.5
    orb = CentralOrbit(harmonic(k), energy=3.0, angular_momentum=0.7, mass=m)
    assert orb.apsidal_angle == pytest.approx(PI / 2, rel=1e-12)
    assert orb.radial_period == pytest.approx(PI * math.sqrt(m / k), rel=1e-12)
    assert orb.closure() == pytest.approx(0.5)


@pytest.mark.parametrize("beta", [0.05, -0.1, 0.3])
def test_inverse_square_perturbation_precession(beta):
    m, L = 1.3, 0.9
    orb = CentralOrbit(kepler(1.0) + inverse_square(beta), energy=-0.3, angular_momentum=L, mass=m)
    expected = PI / math.sqrt(1 + 2 * beta * m / L**2)
    assert orb.apsidal_angle == pytest.approx(expected, rel=1e-12)  # observed <= 1e-14
    assert not orb.is_closed(max_denominator=20)


def test_unbound_orbits():
    hyp = CentralOrbit(kepler(1.0), energy=0.5, angular_momentum=1.2)
    assert math.isinf(hyp.apsides.apocentre) and math.isinf(hyp.radial_period)
    assert hyp.apsidal_angle == pytest.approx(math.acos(-1 / hyp.conic.e), rel=1e-12)
    par = CentralOrbit(kepler(1.0), energy=0.0, angular_momentum=1.2)
    assert par.apsidal_angle == pytest.approx(PI, rel=1e-12)
    assert par.apsides.pericentre == pytest.approx(1.2**2 / 2, rel=1e-14)
    assert not hyp.is_closed()


def test_generic_potential_against_mpmath():
    def U(r):
        return -1 / r + 0.1 * r**2 - 0.3 * np.exp(-r)

    def dU(r):
        return 1 / r**2 + 0.2 * r + 0.3 * np.exp(-r)

    E, L = 0.2, 0.6
    mp.mp.dps = 30

    def ueff(r):
        return (
            -1 / r + mp.mpf("0.1") * r**2 - mp.mpf("0.3") * mp.exp(-r) + mp.mpf(L) ** 2 / (2 * r**2)
        )

    for pot in (Potential(U), Potential(U, dU)):
        orb = CentralOrbit(pot, energy=E, angular_momentum=L)
        r1, r2 = orb.apsides
        R1 = mp.findroot(lambda r: ueff(r) - mp.mpf(E), r1)
        R2 = mp.findroot(lambda r: ueff(r) - mp.mpf(E), r2)
        ang = mp.quad(lambda r: mp.mpf(L) / r**2 / mp.sqrt(2 * (mp.mpf(E) - ueff(r))), [R1, R2])
        per = 2 * mp.quad(lambda r: 1 / mp.sqrt(2 * (mp.mpf(E) - ueff(r))), [R1, R2])
        assert r1 == pytest.approx(float(R1), rel=1e-14)
        assert r2 == pytest.approx(float(R2), rel=1e-14)
        assert orb.apsidal_angle == pytest.approx(float(ang), rel=1e-12)  # observed 5e-15
        assert orb.radial_period == pytest.approx(float(per), rel=1e-12)


def test_nearly_circular_and_circular_orbits():
    near = CentralOrbit(kepler(1.0), energy=-0.5 * (1 - 1e-8), angular_momentum=1.0)
    a = 1 / (1 - 1e-8)
    assert near.apsidal_angle == pytest.approx(PI, rel=1e-12)  # observed 4e-14
    assert near.radial_period == pytest.approx(2 * PI * a**1.5, rel=1e-12)
    circ = CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=1.0)
    assert circ.is_circular and circ.apsides.pericentre == pytest.approx(1.0, rel=1e-14)
    # limit pi phi'/omega_r from differences of U_eff': observed 3e-11
    assert circ.apsidal_angle == pytest.approx(PI, rel=1e-9)
    # the oscillator's circular orbit: omega_r = 2 phi'
    osc = CentralOrbit.from_state(harmonic(4.0), [1.0, 0, 0], [0, 2.0, 0])
    assert osc.is_circular and osc.apsidal_angle == pytest.approx(PI / 2, rel=1e-9)


def test_kepler_orbit_integration_agrees_with_closed_form():
    orb = CentralOrbit.from_state(kepler(1.0), [1.0, 0.2, 0.1], [0.1, 1.1, 0.3])
    t = np.linspace(-10, 20, 301)
    a = orb.orbit(t, method="kepler")
    b = orb.orbit(t, method="integrate")
    assert np.max(np.abs(a - b)) < 2e-10  # observed 1.8e-11 (rtol 1e-12)
    x0, v0 = orb.state(np.array(0.0))
    np.testing.assert_allclose(x0, [1.0, 0.2, 0.1], atol=1e-14)
    np.testing.assert_allclose(v0, [0.1, 1.1, 0.3], atol=1e-13)
    # the orbit lies in the plane normal to r0 x v0, energy conserved along it
    n = np.cross([1.0, 0.2, 0.1], [0.1, 1.1, 0.3])
    assert np.max(np.abs(b @ n)) < 1e-13
    x, v = orb.state(t, method="integrate")
    energy = 0.5 * np.sum(v * v, -1) - 1 / np.linalg.norm(x, axis=-1)
    assert np.max(np.abs(energy - orb.energy)) < 1e-10
    # angular momentum r x v constant (r^2 phi' exact by construction)
    np.testing.assert_allclose(np.cross(x, v), np.broadcast_to(n, x.shape), atol=1e-10)


def test_hyperbolic_kepler_integration_and_pericentre():
    orb = CentralOrbit.from_state(kepler(1.0), [1.0, 0.2, 0.1], [0.1, 2.1, 0.3])
    t = np.linspace(-10, 20, 301)
    a = orb.orbit(t, method="kepler")
    b = orb.orbit(t, method="integrate")
    assert np.max(np.abs(a - b) / np.linalg.norm(a, axis=-1)[:, None]) < 1e-10
    x, _ = orb.state(np.array(orb.pericentre_time))
    assert np.linalg.norm(x) == pytest.approx(orb.apsides.pericentre, rel=1e-12)
    np.testing.assert_allclose(x / np.linalg.norm(x), orb.pericentre_direction, atol=1e-10)


def test_precessing_orbit_pericentre_by_quadrature():
    orb = CentralOrbit.from_state(
        kepler(1.0) + inverse_square(0.05), [1.0, 0.2, 0.1], [0.1, 1.1, 0.3]
    )
    x, _ = orb.state(np.array([orb.pericentre_time, orb.pericentre_time + orb.radial_period]))
    r = np.linalg.norm(x, axis=-1)
    np.testing.assert_allclose(r, orb.apsides.pericentre, rtol=1e-10)
    np.testing.assert_allclose(x[0] / r[0], orb.pericentre_direction, atol=1e-9)
    # after one radial period the pericentre has turned by 2 * apsidal_angle
    cosang = np.dot(x[0], x[1]) / (r[0] * r[1])
    assert cosang == pytest.approx(math.cos(2 * orb.apsidal_angle), abs=1e-9)


def test_effective_potential_and_areal_velocity():
    orb = CentralOrbit(kepler(2.0), energy=-0.5, angular_momentum=1.5, mass=3.0)
    r = np.array([0.5, 1.0, 4.0])
    np.testing.assert_allclose(orb.effective_potential(r), -2 / r + 1.5**2 / (6 * r**2), rtol=1e-15)
    assert orb.areal_velocity == pytest.approx(1.5 / 6)
    np.testing.assert_allclose(orb.effective_potential(orb.apsides.pericentre), -0.5, rtol=1e-13)


def test_potential_numerical_derivative():
    p = Potential(lambda r: np.sin(r) / r)
    r = np.linspace(0.5, 5, 7)
    exact = np.cos(r) / r - np.sin(r) / r**2
    np.testing.assert_allclose(p.derivative(r), exact, atol=1e-11)
    q = kepler(1.0) + 2.0
    assert float(q(1.0)) == pytest.approx(1.0) and q.kepler_mu is None


# ---------------------------------------------------------------- bad input


def test_bad_input():
    with pytest.raises(InvalidInputError, match="angular_momentum"):
        CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=0.0)
    with pytest.raises(InvalidInputError, match="minimum of the effective potential"):
        CentralOrbit(kepler(1.0), energy=-0.6, angular_momentum=1.0)
    with pytest.raises(InvalidInputError, match="mass"):
        CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=1.0, mass=-1.0)
    with pytest.raises(InvalidInputError, match="energy"):
        CentralOrbit(kepler(1.0), energy=np.nan, angular_momentum=1.0)
    with pytest.raises(InvalidInputError, match="finite"):
        CentralOrbit(
            Potential(lambda r: np.where(r > 1, np.nan, -1 / r)),
            energy=1.0,
            angular_momentum=1.0,
            radius=0.5,
        )
    with pytest.raises(InvalidInputError, match="angular momentum is 0"):
        CentralOrbit.from_state(kepler(1.0), [1, 0, 0], [2, 0, 0])
    with pytest.raises(InvalidInputError, match="centre"):
        CentralOrbit(Potential(lambda r: -1 / r**3), energy=1.0, angular_momentum=1.0, radius=10.0)
    with pytest.raises(InvalidTypeError, match="potential"):
        CentralOrbit("kepler", energy=-0.5, angular_momentum=1.0)
    with pytest.raises(InvalidInputError, match="Kepler"):
        CentralOrbit(harmonic(1.0), energy=2.0, angular_momentum=1.0).conic  # noqa: B018
    with pytest.raises(InvalidTypeError, match="vectorised"):
        CentralOrbit(Potential(lambda r: -1 / math.sqrt(r)), energy=-0.1, angular_momentum=1.0)
    with pytest.raises(InvalidInputError, match="radius"):
        CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=0.8, radius=5.0)


def test_state_at_an_apsis_is_not_mistaken_for_a_circular_orbit():
    """From r' = 0 the start is an apsis: r = 1 is the pericentre for v = 1.2, the
    apocentre for v = 0.8 (mu = 1), with the beta/r^2 precession closed form."""
    orb = CentralOrbit.from_state(kepler(1.0) + inverse_square(0.05), [1, 0, 0], [0, 1.2, 0])
    assert not orb.is_circular
    assert orb.apsides.pericentre == pytest.approx(1.0, rel=1e-13)
    L2 = 1.2**2
    # apocentre: root of E = -1/r + (0.05 + L^2/2)/r^2 with E = 0.72 - 1 + 0.05
    E = 0.5 * L2 - 1 + 0.05
    c = 0.05 + L2 / 2
    r2 = (-1 - math.sqrt(1 + 4 * E * c)) / (2 * E)
    assert orb.apsides.apocentre == pytest.approx(r2, rel=1e-13)
    assert orb.apsidal_angle == pytest.approx(PI / math.sqrt(1 + 0.1 / L2), rel=1e-12)
    apo = CentralOrbit.from_state(kepler(1.0), [1, 0, 0], [0, 0.8, 0])
    c = apo.conic
    assert apo.apsides.apocentre == pytest.approx(c.p / (1 - c.e), rel=1e-13)
    assert apo.pericentre_time == pytest.approx(-c.period / 2, rel=1e-13)
    np.testing.assert_allclose(apo.pericentre_direction, [-1, 0, 0], atol=1e-13)


def test_trajectory_result():
    orb = CentralOrbit.from_state(kepler(1.0), [1.0, 0.2, 0.1], [0.1, 1.1, 0.3])
    t = np.linspace(0, 5, 11)
    tr = orb.trajectory(t)
    assert tr.method == "exact" and tr.info["closed_form"] == "kepler"
    x, v = orb.state(t)
    np.testing.assert_array_equal(tr.position, x)
    np.testing.assert_array_equal(tr.velocity, v)
    tr2 = orb.trajectory(t, method="integrate")
    assert tr2.method == "adaptive"
    np.testing.assert_allclose(tr2.position, x, atol=1e-10)


def test_trajectory_is_a_point_result_with_conserved_energy():
    """A central orbit is a point's motion (no dummy attitude); its energy
    m v^2/2 + U(r) is the orbit's own constant energy (theory §9)."""
    from poinsot.trajectory import PointTrajectory

    orb = CentralOrbit.from_state(kepler(1.0), [1.0, 0.2, 0.1], [0.1, 1.1, 0.3])
    tr = orb.trajectory(np.linspace(0, 5, 11))
    assert isinstance(tr, PointTrajectory) and not hasattr(tr, "rotation")
    np.testing.assert_allclose(tr.energy, orb.energy, rtol=1e-13)
