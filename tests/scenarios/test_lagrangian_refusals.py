"""What `check` and `run` refuse alike for a Lagrangian scenario, and the advice after
a failed integration (issue 23)."""

from __future__ import annotations

from pathlib import Path

import pytest

from deadline import deadline
from poinsot.cli import main

pytest.importorskip("sympy")

EXAMPLES = Path(__file__).parents[2] / "examples"
DP = (EXAMPLES / "double_pendulum.toml").read_text()


def _run_and_check(path: Path, tmp_path: Path) -> tuple[int, int]:
    run = main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet", "--duration", "0.1"])
    return main(["check", str(path), "--quiet"]), run


def test_an_unused_parameter_is_refused_by_check_and_run(tmp_path, capsys):
    path = tmp_path / "dp.toml"
    path.write_text(DP.replace("parameters = { m1 = 1.0,", "parameters = { k = 3.0, m1 = 1.0,"))
    assert _run_and_check(path, tmp_path) == (2, 2)
    err = capsys.readouterr().err
    line = 1 + DP.split("parameters = {")[0].count("\n")
    assert err.count(f"dp.toml:{line}: `lagrangian.parameters` 'k' appears in no equation") == 2


@pytest.mark.parametrize(
    "kinetic",
    [
        '"""-(m1 + m2)*l1**2*theta1_dot**2/2 + m2*l2**2*theta2_dot**2/2"""',  # negative
        '"""(m1 + m2)*l1**2*theta1_dot**2/2"""',  # theta2 has no velocity term
    ],
)
def test_a_kinetic_energy_not_positive_definite_is_refused(tmp_path, capsys, kinetic):
    start = DP.index("kinetic = ")
    end = DP.index("potential = ")
    path = tmp_path / "dp.toml"
    path.write_text(DP[:start] + f"kinetic = {kinetic}\n" + DP[end:])
    assert _run_and_check(path, tmp_path) == (2, 2)
    err = capsys.readouterr().err
    assert err.count("`lagrangian.kinetic` expected a kinetic energy that is positive") == 2


def test_the_advice_after_a_failed_integration_names_this_kind_s_methods(tmp_path, capsys):
    """x'' = 4 x^3 from x = 1, x' = 1 blows up before t = 1: the advice names the
    Lagrangian kind's methods, not the rigid body's "adaptive"."""
    path = tmp_path / "blow.toml"
    path.write_text(
        'kind = "lagrangian"\n[lagrangian]\ncoordinates = ["x"]\nkinetic = "x_dot**2/2"\n'
        'potential = "-x**4"\nq0 = [1.0]\nqdot0 = [1.0]\n'
        '[simulation]\nduration = 10.0\nsamples = 101\nmethod = "DOP853"\n'
    )
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    err = capsys.readouterr().err
    advice = err.split("Advice:")[1]
    assert '"Radau"' in advice and '"adaptive"' not in advice and '"DOP853"' not in advice
    assert not (tmp_path / "o").exists()


ONE = (
    'kind = "lagrangian"\n[lagrangian]\ncoordinates = ["x"]\nparameters = {{ {params} }}\n'
    'kinetic = "x_dot**2/2"\npotential = "{potential}"\nq0 = [{q0}]\nqdot0 = [0.0]\n'
    '[simulation]\nduration = 1.0\nsamples = 11\nmethod = "DOP853"\n'
)


@pytest.mark.parametrize(
    ("params", "potential", "q0", "said"),
    [
        # the old code: check ok, run spinning at full CPU (a NaN first step of solve_ivp)
        (
            "k = 1.0",
            "k*sqrt(x)",
            "-1.0",
            "give NaN at t = 0, x = -1, x_dot = 0: the potential k*sqrt(x) is not real",
        ),
        # the old code: check ok, run exit 1 "unexpected failure: ZeroDivisionError"
        ("k = 1.0", "k/(x - 1)", "1.0", "x = 1, x_dot = 0: the potential k/(x - 1) is infinite"),
        (
            "k = 0.0, m = 1.0",
            "m*x**2/k",
            "0.5",
            "the potential m*x**2/k is infinite there (k = 0, m = 1)",
        ),
    ],
)
def test_equations_not_finite_at_the_start_exit_2_in_check_and_run(
    tmp_path, capsys, params, potential, q0, said
):
    path = tmp_path / "nan.toml"
    path.write_text(ONE.format(params=params, potential=potential, q0=q0))
    with deadline(60):
        assert _run_and_check(path, tmp_path) == (2, 2)
    err = capsys.readouterr().err
    assert err.count("nan.toml:7: `lagrangian.q0` expected an initial state") == 2, err
    assert err.count(said) == 2, err
    assert not (tmp_path / "o").exists()
