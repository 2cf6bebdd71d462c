"""What a Lagrangian simulation refuses, and how (issue 38): a start where the equations
give NaN or divide by zero (named with the state and the term, never a hang nor a
ZeroDivisionError), a non-finite derivative during a run (stopped at its time), a
kinetic energy that is not positive definite (as the CLI refuses it); the units the CLI
would give; pickling (multiprocessing, Dask)."""

from __future__ import annotations

import multiprocessing
import operator
import pickle
import re

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")
from sympy.physics.mechanics import dynamicsymbols  # noqa: E402

from deadline import deadline  # noqa: E402
from poinsot._jit import NUMBA  # noqa: E402
from poinsot.errors import IntegrationError, InvalidInputError  # noqa: E402
from poinsot.symbolic import LagrangeSystem  # noqa: E402

x, th = dynamicsymbols("x theta")
k, m = sympy.symbols("k m")
KE = x.diff() ** 2 / 2


SQRT = LagrangeSystem([x], KE, k * sympy.sqrt(x))


@pytest.mark.parametrize("method", ["DOP853", "LSODA"])
def test_nan_at_the_start_is_refused_at_once_naming_state_and_term(method):
    # the old code: solve_ivp's first step size is NaN and its loop never ends
    with deadline(60), pytest.raises(InvalidInputError) as info:
        SQRT.simulate([-1.0], [0.0], [0.0, 1.0], parameters={"k": 1.0}, method=method)
    msg = str(info.value)
    assert "give NaN at t = 0, x = -1, x' = 0" in msg
    assert "the potential k*sqrt(x) is not real" in msg and "(k = 1)" in msg
    assert "`q0`" in msg


def test_the_state_named_is_the_one_of_the_batch_that_fails():
    with deadline(60), pytest.raises(InvalidInputError, match=r"x = -2, x' = 0\.5"):
        SQRT.simulate([[1.0], [-2.0]], [[0.0], [0.5]], [0.0, 1.0], parameters={"k": 1.0})


@pytest.mark.parametrize(
    ("potential", "q0", "params", "named"),
    [
        (k / (x - 1), 1.0, {"k": 1.0}, "the potential k/(x - 1) is infinite there (k = 1)"),
        (x**2 / k, 0.5, {"k": 0.0}, "the potential x**2/k is infinite there (k = 0)"),
    ],
)
def test_a_division_by_zero_at_the_start_is_an_invalid_input(potential, q0, params, named):
    s = LagrangeSystem([x], KE, potential)
    with deadline(60), pytest.raises(InvalidInputError) as info:
        s.simulate([q0], [0.0], [0.0, 1.0], parameters=params)
    # numba raises ZeroDivisionError, NumPy gives inf: the same words
    assert f"give an infinite value (a division by zero) at t = 0, x = {q0:g}, x' = 0" in str(
        info.value
    ) or f"give an infinite value at t = 0, x = {q0:g}, x' = 0" in str(info.value)
    assert named in str(info.value)
    f = s.to_numeric(params)
    assert f.compile() is f  # compiling evaluates the zero state: no ZeroDivisionError
    if not NUMBA:  # the right-hand side called directly: inf, as NumPy divides
        assert np.isinf(f(0.0, np.array([q0, 0.0]))[1])
        return
    # numba's ZeroDivisionError from the right-hand side called directly: the same error
    # as simulate's, on both one-state paths
    for _ in range(2):  # the second call takes the entry point the first one set up
        with pytest.raises(InvalidInputError, match="a division by zero"):
            f(0.0, np.array([q0, 0.0]))
    with pytest.raises(InvalidInputError, match="a division by zero"):
        f.mass_matrix(0.0, [[q0, 0.0]])


def test_a_non_finite_derivative_during_a_run_stops_it_at_its_time():
    """x'' = -k / (2 sqrt(x)) from x = 1 at rest reaches x = 0 at t = 8 / (3 sqrt(2k))
    (energy x'^2/2 + k sqrt(x) = k); beyond, sqrt(x) is NaN: the run stops there,
    naming the time, the coordinate and the term."""
    with deadline(60), pytest.raises(IntegrationError) as info:
        SQRT.simulate([1.0], [0.0], np.linspace(0.0, 3.0, 4), parameters={"k": 1.0})
    msg = str(info.value)
    found = re.search(r"give NaN at t = ([-\d.e]+), x = ([-\d.e]+), x' = ([-\d.e]+)", msg)
    assert found, msg
    t, q, u = map(float, found.groups())
    assert t == pytest.approx(8 / (3 * np.sqrt(2.0)), rel=1e-6)
    assert -1e-6 < q < 0.0 and u == pytest.approx(-np.sqrt(2.0), rel=1e-4)  # u^2 = 2k
    assert "the potential k*sqrt(x) is not real" in msg


def test_the_check_of_a_state_is_the_same_compiled_or_interpreted():
    f = SQRT.to_numeric({"k": 1.0})
    messages = []
    for compiled in (False, True):
        f.check_state(0.0, [4.0, 1.0], compiled=compiled)  # a good state passes
        with pytest.raises(InvalidInputError) as info:
            f.check_state(0.0, [[4.0, 1.0], [-1.0, 0.0]], compiled=compiled)
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "x = -1" in messages[0]


def test_a_kinetic_energy_not_positive_definite_is_refused_as_the_cli_refuses_it():
    neg = LagrangeSystem([x], -m * KE, x**2 / 2)
    with pytest.raises(InvalidInputError, match=r"positive definite.*\[\[-1\.0\]\]"):
        neg.simulate([1.0], [0.0], [0.0, 1.0], parameters={"m": 1.0})
    # a double pendulum with m1 = -5: M = [[(m1 + m2) l^2, ...], ...] has -4 on its diagonal
    t1, t2 = dynamicsymbols("theta1 theta2")
    m1, m2, g = sympy.symbols("m1 m2 g")
    T = (m1 + m2) * t1.diff() ** 2 / 2 + m2 * t2.diff() ** 2 / 2
    T += m2 * t1.diff() * t2.diff() * sympy.cos(t1 - t2)
    P = -(m1 + m2) * g * sympy.cos(t1) - m2 * g * sympy.cos(t2)
    dp = LagrangeSystem([t1, t2], T, P)
    good = {"m1": 1.0, "m2": 1.0, "g": 9.81}
    tr = dp.simulate([2.0, 1.0], [0.0, 0.0], [0.0, 0.5], parameters=good)
    assert abs(tr.energy[-1] - tr.energy[0]) < 1e-8  # the same system with m1 > 0 runs
    with pytest.raises(InvalidInputError, match=r"positive definite.*\[\[-4\.0, "):
        dp.simulate([2.0, 1.0], [0.0, 0.0], [0.0, 0.5], parameters={**good, "m1": -5.0})


def test_a_python_built_system_has_the_units_the_cli_guesses():
    q = dynamicsymbols("q")
    s = LagrangeSystem([th, x, q], (th.diff() ** 2 + KE * 2 + q.diff() ** 2) / 2, 0)
    tr = s.simulate([0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0])
    pd = pytest.importorskip("pandas")
    assert isinstance(tr.to_pandas(), pd.DataFrame)
    units = tr.to_pandas().attrs["units"]
    assert (units["theta"], units["theta_dot"]) == ("rad", "rad/s")
    assert (units["x"], units["x_dot"], units["q"], units["q_dot"]) == ("m", "m/s", "", "1/s")
    # a mapping overrides some names; the others keep the guess
    tr = s.simulate([0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0], units={"x": "", "q": "m"})
    assert tr.units == ("rad", "", "m")
    with pytest.raises(InvalidInputError, match="'y'"):
        s.simulate([0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0], units={"y": "m"})


def _pendulum():
    g = sympy.Symbol("g")
    return LagrangeSystem([th], th.diff() ** 2 / 2, -g * sympy.cos(th))


def _simulate(system):
    return system.simulate([1.0], [0.0], np.linspace(0.0, 3.0, 4), parameters={"g": 9.81}).q


def test_a_system_and_its_numeric_form_pickle_and_simulate_the_same():
    s = _pendulum()
    before = _simulate(s)  # compiled: the kernels (a module) are in the object graph
    again = pickle.loads(pickle.dumps(s))
    np.testing.assert_array_equal(_simulate(again), before)
    f = pickle.loads(pickle.dumps(s.to_numeric({"g": 9.81})))
    np.testing.assert_array_equal(f.simulate([1.0], [0.0], np.linspace(0.0, 3.0, 4)).q, before)
    # the right-hand side against the pendulum's own: theta'' = -g sin(theta)
    np.testing.assert_allclose(f(0.0, np.array([1.0, 0.5])), [0.5, -9.81 * np.sin(1.0)])
    cloudpickle = pytest.importorskip("cloudpickle")  # what Dask uses
    np.testing.assert_array_equal(_simulate(cloudpickle.loads(cloudpickle.dumps(s))), before)


def test_a_system_goes_to_a_fresh_process():
    """multiprocessing with spawn: a new interpreter rebuilds the coordinates, the
    parameters and the kernels from the pickle and gets the same bits."""
    s = _pendulum()
    before = _simulate(s)
    # a callable the child can import (not this test module's function)
    run = operator.methodcaller(
        "simulate", [1.0], [0.0], np.linspace(0.0, 3.0, 4), parameters={"g": 9.81}
    )
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        after = pool.apply_async(run, (s,)).get(timeout=120)
    np.testing.assert_array_equal(after.q, before)
    assert after.units == ("rad",)
