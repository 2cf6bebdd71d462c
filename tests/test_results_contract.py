"""One contract for every result type the library returns (API.md "result": frozen,
picklable, ``t``, ``info`` keys of INFO_KEYS, ``channels()`` with units, ``to_pandas()``,
a short repr) and :func:`poinsot.compare` on each kind's own state."""

from __future__ import annotations

import dataclasses
import multiprocessing
import pickle
import re

import numpy as np
import pytest

import poinsot
from poinsot import Rotation
from poinsot.dynamics import (
    CentralOrbit,
    FreeRigidBody,
    HeavyRigidBody,
    LagrangeTop,
    foucault_pendulum,
    kepler,
    simulate,
    simulate_particle,
)
from poinsot.kinematics import FrameMotion, propagate
from poinsot.mass import RigidBody
from poinsot.trajectory import (
    INFO_KEYS,
    CoordinateTrajectory,
    PointTrajectory,
    Result,
    Trajectory,
    compare,
)

T = np.linspace(0.0, 1.0, 21)
J = [1.0, 2.0, 3.0]
W0 = [0.3, 1.0, 0.2]


def _double_pendulum(method, t):
    sympy = pytest.importorskip("sympy")
    from sympy.physics.mechanics import dynamicsymbols

    from poinsot.symbolic import LagrangeSystem

    th1, th2 = dynamicsymbols("theta1 theta2")
    g, m, ell = sympy.symbols("g m l", positive=True)
    x1, y1 = ell * sympy.sin(th1), -ell * sympy.cos(th1)
    x2, y2 = x1 + ell * sympy.sin(th2), y1 - ell * sympy.cos(th2)
    tt = dynamicsymbols._t
    kin = m * (x1.diff(tt) ** 2 + y1.diff(tt) ** 2 + x2.diff(tt) ** 2 + y2.diff(tt) ** 2) / 2
    pot = m * g * (y1 + y2)
    f = LagrangeSystem([th1, th2], kin, pot).to_numeric({"g": 9.81, "m": 1.0, "l": 1.0})
    return f.simulate(
        [2.0, 2.5], [0.0, 0.0], t, method=method, rtol=1e-10, atol=1e-12, units=("rad", "rad")
    )


def _results():
    """(label, factory) for every result the library returns."""
    heavy = HeavyRigidBody([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.3])
    frame = FrameMotion(omega=[0.0, 0.0, 0.5])
    orbit = CentralOrbit.from_state(kepler(1.0), [1.0, 0.0, 0.0], [0.0, 1.1, 0.0])
    return [
        ("simulate-rk4", lambda: simulate(J, [1.0, 0, 0, 0], W0, T, method="rk4")),
        ("simulate-dop853", lambda: simulate(J, [1.0, 0, 0, 0], W0, T, method="dop853")),
        ("propagate", lambda: propagate([1.0, 0, 0, 0], np.tile([0.0, 0.2, 1.0], (T.size, 1)), T)),
        (
            "propagate-adaptive",
            lambda: propagate([1.0, 0, 0, 0], lambda t: [0.0, 0.2, 1.0], T, method="adaptive"),
        ),
        ("simulate-midpoint", lambda: simulate(J, [1.0, 0, 0, 0], W0, T, method="midpoint")),
        ("simulate-splitting", lambda: simulate(J, [1.0, 0, 0, 0], W0, T, method="splitting")),
        ("simulate-adaptive", lambda: simulate(J, [1.0, 0, 0, 0], W0, T, method="adaptive")),
        (
            "simulate-python-torque",
            lambda: simulate(
                J, [1.0, 0, 0, 0], W0, T, method="dop853", torque=lambda t, r, w: [0.0, 0.0, 0.1]
            ),
        ),
        ("free-body", lambda: FreeRigidBody(J, omega0=W0).trajectory(T)),
        ("lagrange-top", lambda: LagrangeTop(1.0, 0.5, 1.0, theta=0.5, spin=10.0).trajectory(T)),
        ("heavy", lambda: heavy.simulate([1.0, 0, 0, 0], [0.1, 0.0, 5.0], T)),
        (
            "particle",
            lambda: simulate_particle(
                frame, None, [1.0, 0.0, 0.0], [0.0, 0.1, 0.0], T, inertial=True
            ),
        ),
        ("foucault", lambda: foucault_pendulum(1.0, 0.8, T, amplitude=0.01)),
        ("orbit", lambda: orbit.trajectory(T)),
        ("lagrangian", lambda: _double_pendulum("DOP853", T)),
        (
            "free-motion",
            lambda: poinsot.dynamics.simulate_free_motion(
                RigidBody.box(1.0, 0.3, 0.2, 0.1),
                [0, 0, 0],
                [1.0, 0, 2.0],
                [1.0, 0, 0, 0],
                W0,
                T,
                force=[0.0, 0.0, -9.81],
            ),
        ),
    ]


CASES = _results()


def _fields_equal(a, b):
    assert type(a) is type(b)
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "info":
            assert x.keys() == y.keys()
            for k in x:  # arrays (potential_energy, failed) element by element
                np.testing.assert_array_equal(np.asarray(x[k]), np.asarray(y[k]), err_msg=k)
        elif isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y)
        elif isinstance(x, Rotation):
            np.testing.assert_array_equal(x.as_quat(), y.as_quat())
        elif f.name == "frame":
            assert type(x) is type(y)
        else:
            assert x == y, f.name


@pytest.fixture(scope="module", params=[c[0] for c in CASES])
def result(request):
    return dict(CASES)[request.param]()


def test_family_and_info_keys(result):
    assert isinstance(result, Result)
    assert isinstance(
        result, Trajectory | PointTrajectory | CoordinateTrajectory
    )  # Pose is a Trajectory
    assert set(result.info) <= set(INFO_KEYS), set(result.info) - set(INFO_KEYS)
    assert isinstance(result.method, str) and result.method
    assert not isinstance(result, Trajectory) or not isinstance(result, PointTrajectory)


def test_pickle_round_trip_field_by_field(result):
    back = pickle.loads(pickle.dumps(result))
    _fields_equal(result, back)


def test_frozen_and_read_only(result):
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.method = "other"  # type: ignore[misc]
    with pytest.raises(TypeError):
        result.info["steps"] = 1  # type: ignore[index]
    for f in dataclasses.fields(result):
        values = getattr(result, f.name)
        if isinstance(values, np.ndarray):
            assert not values.flags.writeable, f.name


def test_channels_have_units_and_match_t(result):
    chans = result.channels()
    assert chans and set(result.state_channels()) <= set(chans) | {"attitude"}
    for name, ch in chans.items():
        assert ch.name == name and isinstance(ch.units, str)
        assert ch.values.shape[0] == result.t.size
        if ch.components:
            assert ch.values.shape[-1] == len(ch.components)
    if isinstance(result, Trajectory):
        assert chans["omega"].units == "rad/s"
    elif isinstance(result, PointTrajectory):
        assert (chans["position"].units, chans["velocity"].units) == ("m", "m/s")


def test_to_pandas(result):
    pytest.importorskip("pandas")
    df = result.to_pandas()
    assert len(df) == result.t.size
    np.testing.assert_array_equal(df.index.to_numpy(), result.t)
    assert set(df.columns) == set(df.attrs["units"])
    first = next(iter(result.channels().values()))
    flat = np.asarray(first.values).reshape(result.t.size, -1)
    np.testing.assert_array_equal(df.iloc[:, 0].to_numpy(), flat[:, 0])


def test_repr_is_one_short_line(result):
    text = repr(result)
    assert "\n" not in text and len(text) < 160 and type(result).__name__ in text
    assert re.search(r"\d+ samples", text)


def test_compare_with_itself_is_zero(result):
    c = compare(result, result)
    assert c.differences and all(d.max == 0.0 for d in c.differences)
    assert not c.exceeding()


def _echo(x):
    return x


def test_results_cross_a_process_boundary():
    """One of each type through a real spawned worker process (as Dask/multiprocessing do)."""
    pytest.importorskip("sympy")
    picks = {
        "simulate-rk4": Trajectory,
        "particle": PointTrajectory,
        "orbit": PointTrajectory,
        "lagrangian": CoordinateTrajectory,
    }
    results = [dict(CASES)[k]() for k in picks]
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(1) as pool:
        back = pool.map(_echo, results)
    pool.join()
    for a, b in zip(results, back, strict=True):
        _fields_equal(a, b)


def test_compare_double_pendulum_on_its_own_state():
    """The false agreement of issue 19: two methods on a chaotic double pendulum differ
    visibly in the coordinates, and compare() says so in rad and rad/s (the differences
    recomputed here directly from the samples)."""
    t = np.linspace(0.0, 20.0, 401)
    a, b = _double_pendulum("DOP853", t), _double_pendulum("Radau", t)
    c = compare(a, b)
    assert c.names() == ("theta1", "theta2", "theta1_dot", "theta2_dot")
    for k, name in enumerate(a.coordinates):
        d = np.abs(a.q[:, k] - b.q[:, k])
        assert c[name].max == d.max() and c[name].units == "rad"
        assert c[name].time_of_max == t[np.argmax(d)]
        dv = np.abs(a.qdot[:, k] - b.qdot[:, k])
        assert c[f"{name}_dot"].max == dv.max() and c[f"{name}_dot"].units == "rad/s"
    assert c["theta1"].max > 1e-3  # chaotic: the two solutions part
    assert "theta1 differs by up to" in c.describe()[0]


def test_compare_rigid_bodies_on_attitude_angle_and_omega():
    a = simulate(J, [1.0, 0, 0, 0], W0, T, method="rk4")
    b = FreeRigidBody(J, omega0=W0).trajectory(T)
    c = compare(a, b)
    angle = 2 * np.arcsin(
        np.minimum(1, np.linalg.norm((b.rotation.inv() * a.rotation).as_quat()[:, 1:], axis=-1))
    )
    np.testing.assert_allclose(c["attitude"].max, angle.max(), rtol=1e-6, atol=1e-15)
    dw = np.linalg.norm(a.omega - b.omega, axis=-1)
    assert c["omega"].max == dw.max() and c["omega"].units == "rad/s"
    assert 0 < c["attitude"].max < 1e-3


def test_compare_refuses_different_kinds_and_times():
    a = simulate(J, [1.0, 0, 0, 0], W0, T, method="rk4")
    p = CentralOrbit.from_state(kepler(1.0), [1.0, 0, 0], [0, 1.0, 0]).trajectory(T)
    with pytest.raises(poinsot.InvalidTypeError, match="same kind"):
        compare(a, p)
    with pytest.raises(poinsot.InvalidInputError, match="same times"):
        compare(a, simulate(J, [1.0, 0, 0, 0], W0, T[:-1], method="rk4"))


def test_info_keys_are_documented_in_conventions():
    """docs/conventions.md lists exactly INFO_KEYS (one documented set)."""
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "conventions.md").read_text()
    listed = set(re.findall(r"^\| `(\w+)` \|", text, flags=re.M))
    assert listed == set(INFO_KEYS), (set(INFO_KEYS) - listed, listed - set(INFO_KEYS))
