"""Curvilinear coordinates (docs/theory.md §7): Lame coefficients and metrics against
the textbook closed forms, and the velocity/acceleration components against the
Cartesian derivatives of r(q(t)) projected on the unit vectors (independent)."""

from __future__ import annotations

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")
from sympy.physics.mechanics import dynamicsymbols  # noqa: E402

from poinsot.errors import InvalidInputError, InvalidTypeError  # noqa: E402
from poinsot.symbolic import curvilinear  # noqa: E402

t = dynamicsymbols._t
r, phi, z, rho, th, xi, eta, u, v = sympy.symbols("r phi z rho theta xi eta u v", positive=True)
a = sympy.Symbol("a", positive=True)
S, C = sympy.sin, sympy.cos

SYSTEMS = {
    "cylindrical": ([r * C(phi), r * S(phi), z], [r, phi, z], [1, r, 1]),
    "spherical": (
        [rho * S(th) * C(phi), rho * S(th) * S(phi), rho * C(th)],
        [rho, th, phi],
        [1, rho, rho * S(th)],
    ),
    "parabolic": (
        [xi * eta * C(phi), xi * eta * S(phi), (eta**2 - xi**2) / 2],
        [xi, eta, phi],
        [sympy.sqrt(xi**2 + eta**2), sympy.sqrt(xi**2 + eta**2), xi * eta],
    ),
    "elliptic": (
        [a * sympy.cosh(u) * C(v), a * sympy.sinh(u) * S(v), z],
        [u, v, z],
        [a * sympy.sqrt(sympy.sinh(u) ** 2 + S(v) ** 2)] * 2 + [1],
    ),
}


@pytest.fixture(scope="module", params=list(SYSTEMS))
def system(request):
    pos, coords, lame = SYSTEMS[request.param]
    return request.param, curvilinear(pos, coords), pos, coords, lame


def _numbers(coords, seed):
    rng = np.random.default_rng(seed)
    vals = {}
    for q in coords:
        f = sympy.Function(q.name)(t)
        vals[f.diff(t, 2)] = sympy.Float(rng.normal())
        vals[f.diff(t)] = sympy.Float(rng.normal())
        vals[f] = sympy.Float(rng.uniform(0.3, 1.2))
        vals[q] = vals[f]
    vals[a] = sympy.Float(1.3)
    return vals


def _num(expr, vals):
    return float(sympy.sympify(expr).xreplace(vals).evalf(30))


def test_lame_and_metric_closed_forms(system):
    name, cc, _, _, lame = system
    for h, h_ref in zip(cc.lame, lame, strict=True):
        assert sympy.simplify(h - h_ref) == 0, (name, h, h_ref)
    g = cc.metric
    assert cc.is_orthogonal
    for k in range(3):
        assert sympy.simplify(g[k, k] - lame[k] ** 2) == 0


def test_unit_vectors_orthonormal(system):
    _, cc, _, coords, _ = system
    vals = _numbers(coords, 1)
    e = np.array([[_num(c, vals) for c in ek] for ek in cc.unit_vectors])
    np.testing.assert_allclose(e @ e.T, np.eye(3), atol=1e-12)


def test_velocity_and_acceleration_components_against_cartesian(system):
    """w . e_k from the Lagrange-form formula equals the Cartesian r'' projected on e_k."""
    name, cc, pos, coords, _ = system
    funcs = {q: sympy.Function(q.name)(t) for q in coords}
    rt = sympy.Matrix(pos).xreplace(funcs)
    vel, acc = rt.diff(t), rt.diff(t, 2)
    for seed in (2,):
        vals = _numbers(coords, seed)
        e = [np.array([_num(c, vals) for c in ek]) for ek in cc.unit_vectors]
        w = np.array([_num(c, vals) for c in acc])
        vv = np.array([_num(c, vals) for c in vel])
        got_w = np.array([_num(c, vals) for c in cc.acceleration_components])
        got_v = np.array([_num(c, vals) for c in cc.velocity_components])
        np.testing.assert_allclose(got_w, [w @ ek for ek in e], rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(got_v, [vv @ ek for ek in e], rtol=1e-10, atol=1e-12)
        assert _num(cc.speed_squared, vals) == pytest.approx(vv @ vv, rel=1e-12)


def test_cylindrical_acceleration_textbook():
    cc = curvilinear(*SYSTEMS["cylindrical"][:2])
    R, P = sympy.Function("r")(t), sympy.Function("phi")(t)
    expected = [R.diff(t, 2) - R * P.diff(t) ** 2, R * P.diff(t, 2) + 2 * R.diff(t) * P.diff(t)]
    for got, ref in zip(cc.acceleration_components[:2], expected, strict=True):
        assert sympy.simplify(got - ref) == 0


def test_metric_transforms_as_a_tensor():
    """Cartesian -> cylindrical and cylindrical -> spherical by g' = J^T g J equal the
    metrics computed directly (theory §7)."""
    x, y = sympy.symbols("x y", real=True)
    cart = curvilinear([x, y, z], [x, y, z])
    g_cyl = cart.transformed_metric([r * C(phi), r * S(phi), z], [r, phi, z])
    assert sympy.simplify(g_cyl - sympy.diag(1, r**2, 1)) == sympy.zeros(3, 3)
    cyl = curvilinear(*SYSTEMS["cylindrical"][:2])
    g_sph = cyl.transformed_metric([rho * S(th), phi, rho * C(th)], [rho, th, phi])
    ref = curvilinear(*SYSTEMS["spherical"][:2]).metric
    assert sympy.simplify(g_sph - ref) == sympy.zeros(3, 3)
    sph = cyl.change_coordinates([rho * S(th), phi, rho * C(th)], [rho, th, phi])
    assert [
        sympy.simplify(h - h0) for h, h0 in zip(sph.lame, [1, rho, rho * S(th)], strict=True)
    ] == [0] * 3


def test_names_and_dynamicsymbols_as_coordinates():
    R, P = dynamicsymbols("r phi")
    cc = curvilinear([R * sympy.cos(P), R * sympy.sin(P)], [R, P])
    assert cc.lame[1] == R
    polar = curvilinear([sympy.Symbol("r") * sympy.cos(sympy.Symbol("phi"))], ["r"])
    assert len(polar.lame) == 1


def test_bad_input():
    with pytest.raises(InvalidTypeError, match="position"):
        curvilinear("r*cos(phi)", [r])
    with pytest.raises(InvalidTypeError, match=r"position\[0\]"):
        curvilinear(["r"], [r])
    with pytest.raises(InvalidInputError, match="independent"):
        curvilinear([r + z, r + z, 0], [r, z])
    with pytest.raises(InvalidInputError, match="time"):
        curvilinear([r * C(t), r * S(t), z], [r, z])
    with pytest.raises(InvalidInputError, match="non-empty"):
        curvilinear([r], [])
    with pytest.raises(InvalidTypeError, match="coordinates"):
        curvilinear([r], [1])
    cyl = curvilinear(*SYSTEMS["cylindrical"][:2])
    with pytest.raises(InvalidInputError, match="old coordinates"):
        cyl.transformed_metric([rho], [rho, th, phi])
