"""What `check` and `run` refuse alike for a Lagrangian scenario, and the advice after
a failed integration (issue 23)."""

from __future__ import annotations

from pathlib import Path

import pytest

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
