"""Inertia of uniform solids against textbook values, exact integration and sampling."""

from __future__ import annotations

import numpy as np
import pytest

from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.mass import box, cone, cylinder, disc, ellipsoid, points, ring, rod, sphere

M = 2.5


# Landau & Lifshitz, Mechanics, 3rd ed., Sec. 32, Problem 2 (a)-(f) and the standard
# table (e.g. Wikipedia "List of moments of inertia") for the shells and plane figures.
# (function, args, kwargs, expected diagonal as a function of the args)
TEXTBOOK = [
    ("solid sphere 2/5 m r^2", sphere, (M, 1.5), {}, [0.4 * M * 1.5**2] * 3),
    ("hollow sphere 2/3 m r^2", sphere, (M, 1.5), {"hollow": True}, [2 / 3 * M * 1.5**2] * 3),
    (
        "solid cylinder m/4 (r^2 + h^2/3), m r^2/2",
        cylinder,
        (M, 0.5, 2.0),
        {},
        [M / 4 * (0.25 + 4.0 / 3)] * 2 + [M * 0.25 / 2],
    ),
    (
        "thin-walled tube m (r^2/2 + h^2/12), m r^2",
        cylinder,
        (M, 0.5, 2.0),
        {"hollow": True},
        [M * (0.25 / 2 + 4.0 / 12)] * 2 + [M * 0.25],
    ),
    (
        "cone 3/20 m (r^2 + h^2/4), 3/10 m r^2",
        cone,
        (M, 0.5, 2.0),
        {},
        [3 / 20 * M * (0.25 + 1.0)] * 2 + [0.3 * M * 0.25],
    ),
    (
        "box m/12 (b^2 + c^2)",
        box,
        (M, 1.0, 2.0, 3.0),
        {},
        [M / 12 * 13, M / 12 * 10, M / 12 * 5],
    ),
    (
        "ellipsoid m/5 (b^2 + c^2)",
        ellipsoid,
        (M, 1.0, 2.0, 3.0),
        {},
        [M / 5 * 13, M / 5 * 10, M / 5 * 5],
    ),
    ("thin rod m l^2/12", rod, (M, 3.0), {}, [M * 9 / 12] * 2 + [0.0]),
    ("thin disc m r^2/4, m r^2/2", disc, (M, 2.0), {}, [M * 4 / 4] * 2 + [M * 4 / 2]),
    ("thin hoop m r^2/2, m r^2", ring, (M, 2.0), {}, [M * 4 / 2] * 2 + [M * 4]),
]


@pytest.mark.parametrize(("label", "fn", "args", "kwargs", "expected"), TEXTBOOK)
def test_textbook_values(label, fn, args, kwargs, expected):
    """Landau-Lifshitz, Mechanics, Sec. 32 Problem 2; standard tables of moments of inertia."""
    j = fn(*args, **kwargs)
    assert j.shape == (3, 3)
    np.testing.assert_allclose(j, np.diag(expected), rtol=1e-14, atol=0, err_msg=label)


def test_solids_of_revolution_exact_sympy():
    """Exact moments by symbolic integration in cylindrical coordinates (SymPy)."""
    sp = pytest.importorskip("sympy")
    r, z = sp.symbols("r z", real=True)
    m, rad, h = sp.Rational(17, 10), sp.Rational(3, 5), sp.Rational(23, 10)

    def central_moments(r_of_z, z0, z1):
        # uniform solid of revolution about z, radius r_of_z(z) for z in [z0, z1];
        # volume element r dr dphi dz, phi integrated out (2 pi, and <y^2> = r^2/2)
        def integral(f):
            return sp.integrate(sp.integrate(f * r * 2 * sp.pi, (r, 0, r_of_z)), (z, z0, z1))

        rho = m / integral(1)
        zc = integral(rho * z) / m
        jzz = integral(rho * r**2)
        jxx = integral(rho * (r**2 / 2 + (z - zc) ** 2))
        return zc, float(jxx), float(jzz)

    # cone, apex at the origin, base at z = h: centre of mass 3h/4 from the apex
    zc, jxx, jzz = central_moments(rad * z / h, 0, h)
    assert zc == 3 * h / 4
    np.testing.assert_allclose(cone(1.7, 0.6, 2.3).diagonal(), [jxx, jxx, jzz], rtol=1e-14)
    _, jxx, jzz = central_moments(rad, -h / 2, h / 2)
    np.testing.assert_allclose(cylinder(1.7, 0.6, 2.3).diagonal(), [jxx, jxx, jzz], rtol=1e-14)
    _, jxx, jzz = central_moments(sp.sqrt(rad**2 - z**2), -rad, rad)
    np.testing.assert_allclose(sphere(1.7, 0.6).diagonal(), [jxx, jxx, jzz], rtol=1e-14)


def test_thin_bodies_against_point_sums():
    """Rod, hoop, disc, shells and tube as dense point sets (exact or O(1/n^2) sums)."""
    n = 4000
    # rod: midpoint samples; sum gives m L^2/12 (1 - 1/n^2)
    zs = ((np.arange(n) + 0.5) / n - 0.5) * 3.0
    pts = np.stack([0 * zs, 0 * zs, zs], axis=-1)
    np.testing.assert_allclose(rod(M, 3.0), points(np.full(n, M / n), pts), rtol=1e-6, atol=1e-12)
    # hoop: equally spaced points are exact for n >= 3
    t = 2 * np.pi * np.arange(n) / n
    pts = np.stack([2 * np.cos(t), 2 * np.sin(t), 0 * t], axis=-1)
    np.testing.assert_allclose(ring(M, 2.0), points(np.full(n, M / n), pts), atol=1e-12)
    # thin-walled tube: hoops stacked along z
    zs = ((np.arange(200) + 0.5) / 200 - 0.5) * 2.0
    tt, zz = np.meshgrid(2 * np.pi * np.arange(64) / 64, zs)
    pts = np.stack([0.5 * np.cos(tt), 0.5 * np.sin(tt), zz], axis=-1).reshape(-1, 3)
    got = points(np.full(len(pts), M / len(pts)), pts)
    np.testing.assert_allclose(cylinder(M, 0.5, 2.0, hollow=True), got, rtol=5e-4, atol=1e-12)
    # disc: polar midpoint grid weighted by area r dr dphi
    nr, nt = 400, 64
    rr = (np.arange(nr) + 0.5) / nr * 2.0
    r2, t2 = np.meshgrid(rr, 2 * np.pi * np.arange(nt) / nt)
    w = (r2 / r2.sum() * M).ravel()
    pts = np.stack([r2 * np.cos(t2), r2 * np.sin(t2), 0 * r2], axis=-1).reshape(-1, 3)
    np.testing.assert_allclose(disc(M, 2.0), points(w, pts), rtol=1e-4, atol=1e-12)
    # hollow sphere: Fibonacci lattice (nearly uniform points on the sphere)
    k = np.arange(n) + 0.5
    zc = 1 - 2 * k / n
    th = np.pi * (1 + 5**0.5) * k
    s = np.sqrt(1 - zc**2)
    pts = 1.5 * np.stack([s * np.cos(th), s * np.sin(th), zc], axis=-1)
    got = points(np.full(n, M / n), pts)
    np.testing.assert_allclose(sphere(M, 1.5, hollow=True), got, rtol=1e-3, atol=1e-3)


def test_monte_carlo_cone():
    """Seeded Monte-Carlo over a cone (rejection sampling); loose tolerance (~1e6 samples)."""
    rng = np.random.default_rng(12345)
    rad, h, n = 0.8, 1.9, 1_000_000
    p = rng.uniform([-rad, -rad, 0.0], [rad, rad, h], size=(n, 3))
    # apex at z = h, base at z = 0
    inside = np.hypot(p[:, 0], p[:, 1]) <= rad * (h - p[:, 2]) / h
    p = p[inside]
    com = p.mean(axis=0)
    assert abs(com[2] - h / 4) < 1e-2  # 8.8e-4 seen (standard error ~7e-4)
    d = p - com
    cov = d.T @ d / len(d)
    j_mc = M * (np.trace(cov) * np.eye(3) - cov)
    np.testing.assert_allclose(cone(M, rad, h), j_mc, atol=2e-2 * np.trace(j_mc))


def test_broadcasting():
    """Array parameters broadcast; each batch entry equals the scalar call."""
    m = np.array([1.0, 2.0, 3.0])[:, None]
    a = np.array([0.5, 1.0])
    j = box(m, a, 2.0, 3.0)
    assert j.shape == (3, 2, 3, 3)
    np.testing.assert_allclose(j[2, 1], box(3.0, 1.0, 2.0, 3.0))
    for fn, args in [
        (sphere, (m, a)),
        (cylinder, (m, a, 1.0)),
        (cone, (m, a, 1.0)),
        (ellipsoid, (m, a, 1.0, 2.0)),
        (rod, (m, a)),
        (disc, (m, a)),
        (ring, (m, a)),
    ]:
        out = fn(*args)
        assert out.shape == (3, 2, 3, 3)
        scalar = fn(*(np.broadcast_to(x, (3, 2))[1, 0] for x in args))
        np.testing.assert_allclose(out[1, 0], scalar)
    assert sphere(1.0, 1.0).shape == (3, 3)


@pytest.mark.parametrize(
    ("fn", "args", "name"),
    [
        (box, (0.0, 1.0, 1.0, 1.0), "mass"),
        (box, (1.0, 1.0, -1.0, 1.0), "b"),
        (sphere, (-1.0, 1.0), "mass"),
        (sphere, (1.0, 0.0), "radius"),
        (cylinder, (1.0, 1.0, 0.0), "height"),
        (cone, (1.0, -2.0, 1.0), "radius"),
        (ellipsoid, (1.0, 1.0, 1.0, 0.0), "c"),
        (rod, (1.0, 0.0), "length"),
        (disc, (1.0, [1.0, -1.0]), "radius"),
        (ring, (0.0, 1.0), "mass"),
    ],
)
def test_non_positive_parameters(fn, args, name):
    with pytest.raises(InvalidInputError, match=f"Expected `{name}` to be positive"):
        fn(*args)


def test_non_finite_and_non_numeric():
    with pytest.raises(InvalidInputError, match="`radius` to contain only finite"):
        sphere(1.0, np.nan)
    with pytest.raises(InvalidTypeError, match="`mass` to be array-like of numbers"):
        box("1", 1.0, 1.0, 1.0)
