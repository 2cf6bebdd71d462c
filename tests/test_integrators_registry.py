"""One table of integration methods (poinsot.integrators): every API, scenario kind
and the docs read it; a name means the same integrator everywhere."""

from pathlib import Path

import numpy as np
import pytest

from poinsot import integrators
from poinsot.dynamics import HEAVY_METHODS, METHODS, PARTICLE_SOLVERS, simulate, simulate_particle
from poinsot.errors import InvalidInputError
from poinsot.integrators import INTEGRATORS, check_method, names
from poinsot.kinematics import FrameMotion, propagate
from poinsot.scenarios.registry import KINDS

DOCS = Path(__file__).parents[1] / "docs"


def test_docs_page_holds_the_registry_table():
    assert integrators.markdown_table() in (DOCS / "integrators.md").read_text()


def test_public_constants_come_from_the_table():
    assert set(METHODS) == set(HEAVY_METHODS) == set(names("rigid"))
    assert set(PARTICLE_SOLVERS) == set(names("lagrangian"))
    from poinsot.kinematics.propagation import METHODS as ATT

    assert set(ATT) == set(names("attitude"))


def test_no_name_is_two_integrators():
    lowered = {}
    for name, i in INTEGRATORS.items():
        assert name == i.name
        assert not (name.lower() in lowered and lowered[name.lower()] == i.implementation)
        lowered[name.lower()] = i.implementation
    # the two DOP853: poinsot's compiled one for rigid bodies, SciPy's for the others
    assert INTEGRATORS["dop853"].systems == ("rigid",)
    assert "rigid" not in INTEGRATORS["DOP853"].systems


def test_every_method_a_kind_accepts_is_registered_for_it():
    for kind in KINDS.values():
        for m in kind.methods:
            assert m in INTEGRATORS, (kind.name, m)
        for m, order in kind.orders.items():
            assert INTEGRATORS[m].order == order, (kind.name, m)


@pytest.mark.parametrize(
    ("call", "wrong", "match"),
    [
        (lambda m: simulate([1.0, 2, 3], [1.0, 0, 0, 0], [0, 0, 1.0], [0.0, 1.0], method=m),
         "Radau", "methods for a rigid body.*'Radau' is SciPy"),
        (lambda m: simulate([1.0, 2, 3], [1.0, 0, 0, 0], [0, 0, 1.0], [0.0, 1.0], method=m),
         "magnus4", "methods for a rigid body.*attitude"),
        (lambda m: propagate([1.0, 0, 0, 0], np.zeros((2, 3)), [0.0, 1.0], method=m),
         "splitting", "methods for attitude propagation.*rigid"),
        (lambda m: simulate_particle(FrameMotion(), None, [1.0, 0, 0], [0, 0, 0], [0, 1.0],
                                     method=m),
         "dop853", "methods for a particle.*poinsot's compiled.*did you mean 'DOP853'"),
    ],
)  # fmt: skip
def test_a_method_of_another_system_is_refused_with_the_table_s_words(call, wrong, match):
    with pytest.raises(InvalidInputError, match=match):
        call(wrong)


def test_check_method_messages():
    assert check_method("rk4", names("rigid"), "x") == "rk4"
    with pytest.raises(InvalidInputError, match="one of 'DOP853'"):
        check_method("nope", names("lagrangian"), "a Lagrangian system")


def test_every_rigid_method_is_one_integrator_object_with_its_row():
    """Issue 39: simulate runs RIGID[method] (one module per method); its facts are the
    row of INTEGRATORS, and the names, the row and the class agree."""
    from poinsot.dynamics.integrators import RIGID, RigidIntegrator

    assert set(RIGID) == set(names("rigid")) - {"exact"}
    for name, runner in RIGID.items():
        assert isinstance(runner, RigidIntegrator) and runner.name == name
        assert runner.facts is INTEGRATORS[name]
        assert "rigid" in runner.facts.cost and runner.facts.cost["rigid"] > 0
        assert "max_step" in runner.facts.options
        assert ("rtol" in runner.facts.options) == runner.facts.adaptive


@pytest.mark.parametrize("option", ["rtol", "atol", "solver", "order", "failures"])
def test_option_refusals_follow_the_rows(option):
    """Each method takes exactly the options of its row: given to another method, the
    refusal names the methods that take it (read from the table, not written per method)."""
    value = {"solver": "RK45", "order": 4, "failures": "mark"}.get(option, 1e-8)
    t = np.linspace(0.0, 0.1, 3)
    takers = [m for m in METHODS if option in INTEGRATORS.get(m).options]
    assert takers  # someone takes it
    for m in METHODS:
        if m == "exact":
            continue
        if option in INTEGRATORS[m].options:
            simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0.1, 1.0, 0.1], t, method=m, **{option: value})
        else:
            with pytest.raises(InvalidInputError, match=f"`{option}` applies to method=") as e:
                simulate(
                    [1.0, 2.0, 3.0], [1, 0, 0, 0], [0.1, 1.0, 0.1], t, method=m, **{option: value}
                )
            assert all(repr(k) in str(e.value) for k in takers), str(e.value)
