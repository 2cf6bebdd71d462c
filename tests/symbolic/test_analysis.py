"""Analytical-mechanics tools (theory §11): generalized forces against -dV/dq and
against a direct computation in other coordinates; Frobenius' test on the course's
constraints (x x' + y y' = 0 integrable, the Chaplygin skate not); first integrals of
Lagrangian systems with and without damping."""

import pytest

sympy = pytest.importorskip("sympy")
from sympy.physics.mechanics import dynamicsymbols  # noqa: E402

from poinsot.errors import InvalidInputError  # noqa: E402
from poinsot.symbolic import (  # noqa: E402
    LagrangeSystem,
    constraint_kind,
    generalized_forces,
    is_first_integral,
    transform_generalized_forces,
)


def test_gravity_on_a_double_pendulum_is_minus_grad_v():
    th1, th2 = dynamicsymbols("theta1 theta2")
    m1, m2, l1, l2, g = sympy.symbols("m1 m2 l1 l2 g", positive=True)
    r1 = [l1 * sympy.sin(th1), -l1 * sympy.cos(th1)]
    r2 = [r1[0] + l2 * sympy.sin(th2), r1[1] - l2 * sympy.cos(th2)]
    q = generalized_forces([r1, r2], [[0, -m1 * g], [0, -m2 * g]], [th1, th2])
    v = m1 * g * r1[1] + m2 * g * r2[1]
    for qk, c in zip(q, [th1, th2], strict=True):
        assert sympy.simplify(qk + v.diff(c)) == 0


@pytest.mark.parametrize(
    "form",
    [
        lambda r, f: ([sympy.Matrix(r[0]), sympy.Matrix(r[1])], [sympy.Matrix(v) for v in f]),
        lambda r, f: ([sympy.Matrix(r[0]).T, sympy.ImmutableMatrix(r[1])], f),
        lambda r, f: (sympy.Matrix(r), sympy.Matrix(f)),  # one point per row
    ],
    ids=["columns", "row-and-immutable", "one-per-row"],
)
def test_positions_and_forces_as_sympy_matrices(form):
    """Issue 38: a sympy.Matrix position was refused; any of its forms gives the same
    -dV/dq as the lists (gravity on the double pendulum)."""
    th1, th2 = dynamicsymbols("theta1 theta2")
    m1, m2, l1, l2, g = sympy.symbols("m1 m2 l1 l2 g", positive=True)
    r1 = [l1 * sympy.sin(th1), -l1 * sympy.cos(th1)]
    r2 = [r1[0] + l2 * sympy.sin(th2), r1[1] - l2 * sympy.cos(th2)]
    positions, forces = form([r1, r2], [[0, -m1 * g], [0, -m2 * g]])
    q = generalized_forces(positions, forces, sympy.Matrix([th1, th2]))
    v = m1 * g * r1[1] + m2 * g * r2[1]
    assert len(q) == 2
    for qk, c in zip(q, [th1, th2], strict=True):
        assert sympy.simplify(qk + v.diff(c)) == 0


def test_covariant_change_matches_the_direct_computation():
    """A force (fx, fy) at (x, y): Q in polar coordinates from J^T Q_cartesian equals
    the generalized forces computed directly in (r, phi)."""
    r, phi = dynamicsymbols("r phi")
    fx, fy = sympy.symbols("f_x f_y")
    x, y = sympy.symbols("x y")
    cart = generalized_forces([[x, y]], [[fx, fy]], [x, y])
    mapping = [r * sympy.cos(phi), r * sympy.sin(phi)]
    via_j = transform_generalized_forces(cart, [x, y], [r, phi], mapping)
    direct = generalized_forces([mapping], [[fx, fy]], [r, phi])
    assert all(sympy.simplify(a - b) == 0 for a, b in zip(via_j, direct, strict=True))


def test_constraint_kinds():
    x, y, phi, t = sympy.symbols("x y phi t")
    circle = constraint_kind([x, y], [x, y], time=t)
    assert circle.holonomic and circle.stationary
    df = [circle.integral.diff(v) for v in (x, y)]
    mu = circle.integrating_factor
    assert all(sympy.simplify(d - mu * a) == 0 for d, a in zip(df, [x, y], strict=True))
    skate = constraint_kind([-sympy.tan(phi), 1, 0], [x, y, phi], time=t)
    assert not skate.holonomic and skate.stationary and skate.integral is None
    assert any(r != 0 for r in skate.residual)
    moving = constraint_kind([1], [x], bias=-t, time=t)  # x' = t: x - t^2/2 = const
    assert moving.holonomic and not moving.stationary
    assert sympy.simplify(moving.integral - (x - t**2 / 2)) == 0
    rot = constraint_kind([y, -x], [x, y], time=t)  # y x' - x y' = 0: needs a factor
    assert rot.holonomic and rot.integrating_factor != 1
    f = rot.integral
    assert sympy.simplify(f.diff(x) * (-x) - f.diff(y) * y) == 0  # df parallel to (y, -x)


def test_constraint_with_functions_of_time_and_a_velocity_is_refused():
    x, y = dynamicsymbols("x y")
    assert constraint_kind([x, y], [x, y]).holonomic
    with pytest.raises(InvalidInputError, match="without velocities"):
        constraint_kind([x.diff(), y], [x, y])


def test_first_integrals_of_lagrangian_systems():
    x = dynamicsymbols("x")
    m, k, c = sympy.symbols("m k c", positive=True)
    energy = m * x.diff() ** 2 / 2 + k * x**2 / 2
    osc = LagrangeSystem([x], m * x.diff() ** 2 / 2, k * x**2 / 2)
    assert is_first_integral(energy, osc).is_integral
    damped = LagrangeSystem(
        [x], m * x.diff() ** 2 / 2, k * x**2 / 2, generalized_forces=[-c * x.diff()]
    )
    check = is_first_integral(energy, damped)
    assert not check.is_integral
    assert sympy.simplify(check.residual + c * x.diff() ** 2) == 0
    assert osc.degrees_of_freedom == 1


def test_generalized_forces_run_numerically_through_to_numeric():
    """Gravity on a pendulum bob given as an applied force (through generalized_forces)
    moves the bob exactly as the same gravity given as a potential."""
    import numpy as np

    th = dynamicsymbols("theta")
    m, g, ell = 1.3, 9.81, 0.7
    kin = m * ell**2 * th.diff() ** 2 / 2
    q = generalized_forces([[ell * sympy.sin(th), -ell * sympy.cos(th)]], [[0, -m * g]], [th])
    by_force = LagrangeSystem([th], kin, 0, generalized_forces=q).to_numeric()
    by_potential = LagrangeSystem([th], kin, -m * g * ell * sympy.cos(th)).to_numeric()
    t = np.linspace(0.0, 2.0, 21)
    a = by_force.simulate([1.0], [0.0], t, rtol=1e-12, atol=1e-14)
    b = by_potential.simulate([1.0], [0.0], t, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(a.q, b.q, atol=1e-10)
