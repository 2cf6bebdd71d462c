"""The compiled right-hand side: batches equal state-by-state evaluation, solve_ivp runs
it directly, parameters by name, clear errors, and the generated source holds only
names poinsot chose."""

from __future__ import annotations

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")
from scipy.integrate import solve_ivp  # noqa: E402
from sympy.physics.mechanics import dynamicsymbols  # noqa: E402

from poinsot.errors import InvalidInputError, InvalidTypeError  # noqa: E402
from poinsot.symbolic import LagrangeSystem  # noqa: E402

q1, q2 = dynamicsymbols("q1 q2")
m, k, c = sympy.symbols("m k c", positive=True)
# two coupled, damped oscillators: M q'' = -K q - c q' (linear: exact reference)
T = m * (q1.diff() ** 2 + q2.diff() ** 2) / 2
P = k * (q1**2 + q2**2 + (q1 - q2) ** 2) / 2
SYSTEM = LagrangeSystem([q1, q2], T, P, generalized_forces=[-c * q1.diff(), -c * q2.diff()])
PARAMS = {"m": 2.0, "k": 3.0, "c": 0.1}


@pytest.fixture(scope="module")
def f():
    return SYSTEM.to_numeric(PARAMS)


def _exact_rhs(y, p=PARAMS):
    K = p["k"] * np.array([[2.0, -1.0], [-1.0, 2.0]])
    q, u = y[..., :2], y[..., 2:]
    return np.concatenate([u, (-(q @ K.T) - p["c"] * u) / p["m"]], axis=-1)


@pytest.mark.parametrize("shape", [(), (1,), (5, 3)])
def test_batches_match_the_exact_rhs(f, shape):
    y = np.random.default_rng(0).normal(size=(*shape, 4))
    got = f(0.0, y)
    assert got.shape == y.shape
    np.testing.assert_allclose(got, _exact_rhs(y), rtol=1e-14, atol=1e-14)


def test_parameters_by_name_and_time_broadcast(f):
    y = np.ones((3, 4))
    p = {"m": 1.0, "k": 1.0, "c": 0.0}
    np.testing.assert_allclose(f(np.arange(3.0), y, p), _exact_rhs(y, p), rtol=1e-14)
    assert f.parameters == ("c", "k", "m")


def test_solve_ivp_runs_it_directly(f):
    y0 = np.array([1.0, 0.0, 0.0, 0.0])
    a = solve_ivp(f, (0, 3), y0, rtol=1e-11, atol=1e-13)
    b = solve_ivp(lambda t, y: _exact_rhs(y), (0, 3), y0, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(a.y[:, -1], b.y[:, -1], atol=1e-9)


def test_simulate_batch_of_initial_states(f):
    ts = np.linspace(0.0, 2.0, 5)
    q0 = np.array([[1.0, 0.0], [0.0, 1.0], [0.5, 0.5]])
    tr = f.simulate(q0, np.zeros((3, 2)), ts)
    assert tr.q.shape == (5, 3, 2) and tr.energy.shape == (5, 3)
    one = f.simulate(q0[1], [0.0, 0.0], ts)
    np.testing.assert_allclose(tr.q[:, 1], one.q, atol=1e-9)
    assert np.all(np.diff(tr.energy, axis=0) <= 1e-12)  # damping only removes energy
    assert tr.jacobi_conserved is False


def test_errors_name_the_argument(f):
    with pytest.raises(InvalidInputError, match=r"shape \(\.\.\., 4\)"):
        f(0.0, np.ones(3))
    with pytest.raises(InvalidInputError, match="'mass'"):
        f(0.0, np.ones(4), {"mass": 1.0})
    with pytest.raises(InvalidTypeError, match=r"parameters\['m'\]"):
        f(0.0, np.ones(4), {"m": "heavy"})
    with pytest.raises(InvalidInputError, match=r"\['c', 'k', 'm'\]"):
        SYSTEM.to_numeric()(0.0, np.ones(4))
    with pytest.raises(InvalidInputError, match="q0"):
        f.simulate([1.0], [0.0, 0.0], [0.0, 1.0])
    with pytest.raises(InvalidInputError, match="method"):
        f.simulate([1.0, 0.0], [0.0, 0.0], [0.0, 1.0], method="euler")


def test_singular_mass_matrix_is_reported():
    x, y = dynamicsymbols("x y")
    g = LagrangeSystem([x, y], (x.diff() + y.diff()) ** 2 / 2).to_numeric()
    with pytest.raises(InvalidInputError, match="singular"):
        g(0.0, np.zeros(4))


def test_unknown_functions_are_refused_and_names_stay_out_of_the_source():
    x = dynamicsymbols("x")
    evil = sympy.Function("__import__")
    with pytest.raises(InvalidInputError, match="__import__"):
        LagrangeSystem([x], x.diff() ** 2 / 2, evil(x)).to_numeric()
    odd = sympy.Symbol("os.system('rm')")
    src = LagrangeSystem([x], x.diff() ** 2 / 2, odd * x**2).to_numeric().source
    assert "os.system" not in src and "rm" not in src


def test_one_state_entry_point_equals_the_batch_kernel(f):
    # one state takes numba's entry point compiled for exact types (issue 24); every
    # other input the validating path: both run the same formula, so the same bits
    rng = np.random.default_rng(4)
    ys = rng.normal(size=(6, 4))
    batch = f(0.0, ys)
    f.compile()
    assert f._one is not None
    for i, y in enumerate(ys):
        np.testing.assert_array_equal(f(0.0, y), batch[i])
        np.testing.assert_allclose(f(0.0, y), _exact_rhs(y), rtol=1e-13, atol=1e-14)
    strided = np.empty((4, 2))
    strided[:, 0] = ys[2]
    readonly = ys[3].copy()
    readonly.flags.writeable = False
    for y, i, t in ((strided[:, 0], 2, 0.0), (readonly, 3, np.float64(1.0)), (ys[4], 4, 1)):
        np.testing.assert_array_equal(f(t, y), batch[i])  # t = 1: an int, the general path
    assert f(0.0, ys[5]) is not f(0.0, ys[5])  # a fresh result array each call


def test_the_one_state_path_leaves_y_alone_and_refers_other_inputs_to_the_general_one(f):
    # the entry point overwrites a copy of y and checks only its length; a wrong length,
    # another dtype or a 2-D state get the general path's answers
    f.compile()
    y = np.array([0.1, -0.2, 0.3, 0.4])
    before = y.copy()
    np.testing.assert_allclose(f(0.0, y), _exact_rhs(y), rtol=1e-13, atol=1e-14)
    np.testing.assert_array_equal(y, before)
    for bad in (np.zeros(3), np.zeros(5)):
        with pytest.raises(InvalidInputError, match=r"Expected `y` to have shape \(\.\.\., 4\)"):
            f(0.0, bad)
    np.testing.assert_array_equal(f(0.0, np.array([1, 2, 0, -1])), f(0.0, [1.0, 2.0, 0.0, -1.0]))
    np.testing.assert_array_equal(f(0.0, y[None]), f(0.0, y)[None])


def test_singular_mass_matrix_is_reported_by_the_one_state_path():
    x = dynamicsymbols("x")
    s = LagrangeSystem([x], m * x.diff() ** 2 / 2, k * x**2 / 2)
    g = s.to_numeric({"m": 0.0, "k": 1.0}).compile()
    with pytest.raises(InvalidInputError, match="singular"):
        g(0.0, np.array([1.0, 0.5]))
