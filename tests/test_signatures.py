"""One spelling per concept in the public signatures (docs/conventions.md, "Names" and
"energy"; issue 39).

Every public function and method of ``poinsot``, ``poinsot.dynamics``,
``poinsot.kinematics``, ``poinsot.symbolic``, ``poinsot.mass`` and ``poinsot.rotations``
is read with :func:`inspect.signature`:

- no ``params`` keyword (``parameters``);
- an initial state is ``<quantity>0`` from one set (``rotation0``, ``omega0``,
  ``position0``, ``velocity0``, ``q0``, ``qdot0``); a ``0``-name outside it is a
  documented exception that is no initial state;
- ``t`` is first (callbacks, evaluations) or last among the positionals (an
  initial-value problem), and a ``t`` with a default after other arguments is
  keyword-only;
- an old spelling exists only through ``poinsot._deprecate.renamed``, and each one
  warns (``DeprecationWarning`` naming the new one) and gives what the new one gives.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from poinsot.errors import InvalidTypeError

NAMESPACES = (
    "poinsot",
    "poinsot.dynamics",
    "poinsot.kinematics",
    "poinsot.symbolic",
    "poinsot.mass",
    "poinsot.rotations",
)

#: the initial-state names (docs/conventions.md, "Names")
INITIAL_STATE = {
    "rotation0",
    "omega0",
    "position0",
    "velocity0",
    "q0",
    "qdot0",
    "wheel_speed0",
    "anomaly0",  # KeplerOrbit: the true anomaly at the epoch
    "theta0",  # PitchLibration: the pitch angle at t = 0
    "rate0",  # PitchLibration: the pitch rate at t = 0
    "bias0",  # Gyro: the true bias at the first sample; MEKF/run_mekf: its estimate
    "covariance0",  # MEKF/run_mekf: the initial error covariance
}

#: ``0``-names that are no initial state: (function, name) -> what it is
NOT_INITIAL_STATE = {
    ("slerp", "r0"): "the rotation at t = 0 of the interpolation (with r1)",
    ("velocity_field", "v0"): "the velocity of the pole",
    ("screw_axis", "v0"): "the velocity of the pole",
    ("acceleration_field", "a0"): "the acceleration of the pole",
    ("fornberg_weights", "x0"): "the point the finite-difference weights are for",
}

#: a time with a default that stays positional (reordering it would silently change
#: what existing positional calls mean): docs/conventions.md, "Names"
T_POSITIONAL_WITH_DEFAULT: set[str] = set()

#: every rename: qualified name -> {old: new}
RENAMES = {
    "simulate_particle": {"r0": "position0", "v0": "velocity0"},
    "NumericLagrangian.__call__": {"params": "parameters"},
    "NumericLagrangian.check_state": {"params": "parameters"},
    "NumericLagrangian.multipliers": {"params": "parameters"},
    "NumericLagrangian.mass_matrix": {"params": "parameters"},
    "NumericLagrangian.energy": {"params": "parameters"},
    "NumericLagrangian.kinetic": {"params": "parameters"},
    "NumericLagrangian.jacobi": {"params": "parameters"},
    "NumericLagrangian.simulate": {"params": "parameters"},
}
OLD_NAMES = {old for m in RENAMES.values() for old in m}


def _public():
    """(qualified name, callable, signature, is a dataclass's generated __init__)."""
    seen: set[int] = set()
    out = []
    for ns in NAMESPACES:
        mod = importlib.import_module(ns)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            if inspect.isclass(obj):
                for klass in obj.__mro__:
                    if not klass.__module__.startswith("poinsot"):
                        continue
                    for key, member in vars(klass).items():
                        if key.startswith("_") and key not in ("__init__", "__call__"):
                            continue
                        fn = getattr(member, "__func__", member)
                        if isinstance(fn, property) or not callable(fn) or id(fn) in seen:
                            continue
                        seen.add(id(fn))
                        try:
                            sig = inspect.signature(fn)
                        except (TypeError, ValueError):
                            continue
                        generated = key == "__init__" and dataclasses.is_dataclass(klass)
                        out.append((f"{klass.__name__}.{key}", fn, sig, generated))
            elif callable(obj):
                try:
                    sig = inspect.signature(obj)
                except (TypeError, ValueError):
                    continue
                out.append((name, obj, sig, False))
    return out


PUBLIC = _public()


def _short(qualname: str) -> str:
    return qualname.rsplit(".", 1)[-1]


def test_the_survey_sees_the_api():
    names = {q for q, *_ in PUBLIC}
    assert len(PUBLIC) > 300
    assert {"simulate", "simulate_particle", "simulate_free_motion"} <= names
    assert "NumericLagrangian.simulate" in names and "NumericLagrangian.__call__" in names


@pytest.mark.parametrize(
    ("qualname", "fn", "sig", "generated"), PUBLIC, ids=[q for q, *_ in PUBLIC]
)
def test_names(qualname, fn, sig, generated):
    params = [p for p in sig.parameters.values() if p.name not in ("self", "cls")]
    names = [p.name for p in params]
    assert "params" not in names, f"{qualname}: `params` is spelled `parameters`"
    leftover = OLD_NAMES & set(names) - {n for (f, n) in NOT_INITIAL_STATE if f == _short(qualname)}
    assert not leftover, f"{qualname}: old spelling {leftover} outside @renamed"
    for p in params:
        if re.fullmatch(r"[a-z_]+0", p.name) and p.name not in INITIAL_STATE:
            key = (_short(qualname), p.name)
            assert key in NOT_INITIAL_STATE, (
                f"{qualname}: `{p.name}` is not an initial-state name "
                f"({sorted(INITIAL_STATE)}) nor a documented exception"
            )
    if "t" in names and not generated:
        positional = [
            p.name for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
        ]
        if "t" in positional:
            k = positional.index("t")
            assert k in (0, len(positional) - 1), (
                f"{qualname}: `t` is argument {k} of {positional}: first (evaluations, "
                "callbacks) or last among the positionals (initial-value problems)"
            )
            if k > 0 and sig.parameters["t"].default is not inspect.Parameter.empty:
                assert _short(qualname) in T_POSITIONAL_WITH_DEFAULT, (
                    f"{qualname}: a `t` with a default after other arguments is keyword-only"
                )


def test_old_names_only_through_the_decorator():
    found = {}
    for qualname, fn, sig, _ in PUBLIC:
        renamed = getattr(fn, "__renamed__", None)
        if renamed is not None:
            found[qualname] = renamed
            for old, new in renamed.items():
                assert new in sig.parameters and old not in sig.parameters, qualname
    assert found == RENAMES


# ------------------------------------------------------------ the aliases still work


def _same(a, b):
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            x, y = getattr(a, f.name), getattr(b, f.name)
            if isinstance(x, np.ndarray):
                np.testing.assert_array_equal(x, y)
        return
    if a is None:
        assert b is None
        return
    np.testing.assert_array_equal(a, b)


def _warns_and_matches(call_new, call_old, old, new):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # the new name does not warn
        expected = call_new()
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        got = call_old()
    said = [w for w in record if re.search(rf"\({old}=\.\.\.\).*use `{new}=`", str(w.message))]
    assert said and said[0].category is DeprecationWarning, [str(w.message) for w in record]
    assert said[0].filename == __file__  # points at the caller
    _same(expected, got)


def test_simulate_particle_r0_v0():
    from poinsot.dynamics import simulate_particle
    from poinsot.kinematics import FrameMotion

    frame = FrameMotion(omega=[0.0, 0.0, 1.0])
    t = [0.0, 0.5, 1.0]
    new = {"position0": [1.0, 0.0, 0.0], "velocity0": [0.0, 0.3, 0.0]}
    old = {"r0": new["position0"], "v0": new["velocity0"]}
    _warns_and_matches(
        lambda: simulate_particle(frame, None, t=t, **new),
        lambda: simulate_particle(frame, None, t=t, **old),
        "r0",
        "position0",
    )
    with pytest.warns(DeprecationWarning, match="velocity0"):
        simulate_particle(frame, None, [1.0, 0.0, 0.0], v0=[0.0, 0.3, 0.0], t=t)
    # positional calls never warn
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        simulate_particle(frame, None, new["position0"], new["velocity0"], t)
    with pytest.raises(InvalidTypeError, match="both"), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        simulate_particle(frame, None, r0=[1, 0, 0], position0=[1, 0, 0], v0=[0, 0, 0], t=t)


@pytest.fixture(scope="module")
def numeric():
    sympy = pytest.importorskip("sympy")
    from poinsot.symbolic import LagrangeSystem

    time = sympy.Symbol("t")
    x = sympy.Function("x")(time)
    k = sympy.Symbol("k")
    return LagrangeSystem([x], x.diff(time) ** 2 / 2, k * x**2 / 2).to_numeric({"k": 4.0})


@pytest.mark.parametrize(
    "method",
    ["__call__", "rhs", "check_state", "multipliers", "mass_matrix", "energy", "kinetic",
     "jacobi"],
)  # fmt: skip
def test_numeric_lagrangian_params(numeric, method):
    f = getattr(numeric, method)
    y = np.array([1.0, 0.5])
    p = {"k": 1.0}
    _warns_and_matches(
        lambda: f(0.0, y, parameters=p), lambda: f(0.0, y, params=p), "params", "parameters"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        _same(f(0.0, y, p), f(0.0, y, parameters=p))  # positional: unchanged
    with pytest.raises(InvalidTypeError, match="both"), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        f(0.0, y, parameters=p, params=p)
    with pytest.raises(TypeError, match="unexpected keyword"):
        f(0.0, y, parameter=p)


def test_numeric_lagrangian_simulate_params(numeric):
    t = [0.0, 0.5, 1.0]
    p = {"k": 1.0}
    _warns_and_matches(
        lambda: numeric.simulate([1.0], [0.0], t, parameters=p),
        lambda: numeric.simulate([1.0], [0.0], t, params=p),
        "params",
        "parameters",
    )


# ------------------------------------------------------- energy, once per result type

#: what ``energy`` is, per result type: the phrase the class docstring and the table
#: of docs/conventions.md ("energy") both state
ENERGY = {
    "Trajectory": "rotational kinetic energy",
    "PoseTrajectory": "whole kinetic energy",
    "PointTrajectory": "mechanical energy t + v",
    "CoordinateTrajectory": "mechanical energy t + p + v0",
}


def _plain(text: str) -> str:
    return " ".join(text.replace("`", "").lower().split())


@pytest.mark.parametrize(("name", "phrase"), ENERGY.items())
def test_energy_is_defined_once_per_result_type(name, phrase):
    import poinsot

    cls = getattr(poinsot, name)
    assert phrase in _plain(cls.__doc__), name
    text = (Path(__file__).parents[1] / "docs" / "conventions.md").read_text()
    rows = [line for line in text.splitlines() if line.startswith(f"| `poinsot.{name}` ")]
    assert any(phrase in _plain(row) for row in rows), name


def test_every_result_type_has_its_energy():
    import poinsot
    from poinsot.trajectory import Result

    kinds = {
        n
        for n in poinsot.__all__
        if inspect.isclass(getattr(poinsot, n))
        and issubclass(getattr(poinsot, n), Result)
        and dataclasses.is_dataclass(getattr(poinsot, n))
        and any(f.name == "energy" for f in dataclasses.fields(getattr(poinsot, n)))
        and getattr(poinsot, n).__name__ == n
    }
    assert kinds == set(ENERGY)


def test_inertial_forces_positional_t_is_deprecated_and_means_the_same():
    import warnings

    from poinsot.dynamics import inertial_forces
    from poinsot.kinematics import FrameMotion

    def frame(t):  # a frame whose spin grows with time: t changes the answer
        return FrameMotion(omega=[0.0, 0.0, 1.0 + t])

    new = inertial_forces(frame, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 2.0, t=0.5)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        old = inertial_forces(frame, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 2.0, 0.5)
    assert any(issubclass(x.category, DeprecationWarning) and "t=" in str(x.message) for x in w)
    np.testing.assert_array_equal(old.coriolis, new.coriolis)
    assert new.centrifugal[0] == pytest.approx(2.0 * 1.5**2)  # -m w x (w x r) = m w^2 r, w = 1 + t
    with pytest.raises(InvalidTypeError, match="4 positional"):
        inertial_forces(frame, [1.0, 0, 0], [0, 1.0, 0], 2.0, 0.5, 0.6)
