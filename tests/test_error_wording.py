"""Error wording and small promises of issue 23 ("Error wording")."""

from __future__ import annotations

import math

import pytest

import poinsot
from poinsot import InvalidInputError, InvalidTypeError
from poinsot.dynamics import CentralOrbit, harmonic, kepler, simulate


def test_non_finite_input_says_finite():
    with pytest.raises(InvalidInputError, match="finite"):
        simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [math.nan, 0.0, 0.0], [0.0, 1.0])
    with pytest.raises(InvalidInputError, match="finite"):
        simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0.0, math.inf, 0.0], [0.0, 1.0])


def test_lagrange_simulate_names_its_argument():
    sympy = pytest.importorskip("sympy")
    from poinsot.symbolic import LagrangeSystem

    x = sympy.Function("x")(sympy.Symbol("t"))
    osc = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2)
    with pytest.raises(InvalidTypeError, match="`q0`"):
        osc.simulate("a", [0.0], [0.0, 1.0])
    with pytest.raises(InvalidTypeError, match="`qdot0`"):
        osc.simulate([1.0], "b", [0.0, 1.0])


def test_harmonic_zero_is_refused():
    with pytest.raises(InvalidInputError, match="`k`"):
        harmonic(0)
    assert float(harmonic(2.0)(3.0)) == 9.0  # U = k r^2 / 2


def test_central_orbit_repr_states_the_orbit():
    """The repr names the potential, the integrals and the apsides (E = -1/2, L = 0.8 for
    mu = 1: r = p / (1 +- e) with p = L^2 = 0.64, e = sqrt(1 + 2 E L^2) = 0.6)."""
    r = repr(CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=0.8))
    assert r.startswith("CentralOrbit(") and "-1/r" in r and "energy=-0.5" in r
    assert "bound" in r and "apsides=(0.4, 1.6)" in r
    assert "unbound" in repr(CentralOrbit(kepler(1.0), energy=0.5, angular_momentum=0.8))


def test_dir_poinsot_lists_the_public_api_only():
    names = set(dir(poinsot))
    assert not {"annotations", "importlib", "sys"} & names
    assert {"Rotation", "compare", "dynamics"} <= names
    assert names <= set(poinsot.__all__) | {"__version__", "cli", "dynamics", "ensemble",
                                             "kinematics", "mass", "plotting", "scenarios",
                                             "symbolic", "verify"}  # fmt: skip
