"""The ``estimation`` scenario kind (docs/theory.md §10.4): the MEKF on exact motion,
consistent with its own covariance, through the CLI; errors that name the key."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import chi2

from poinsot.cli import main
from poinsot.scenarios import parse_scenario
from poinsot.scenarios._toml import ScenarioError
from poinsot.scenarios.kinds.estimation import estimate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
MEKF = (EXAMPLES / "mekf_tumbling.toml").read_text()


def test_filter_on_the_exact_flip_is_consistent_and_finds_the_bias():
    s = parse_scenario(MEKF, source="mekf.toml")
    t = np.arange(601) * 0.1
    est = estimate(s, t)
    sig = est.result.sigma
    assert not est.result.diverged
    # after the transient (10 s) the errors lie within 3 sigma almost always
    late = t > 10.0
    inside = np.abs(est.attitude_error[late]) <= 3 * sig[late, :3]
    assert inside.mean() > 0.97
    assert np.abs(est.bias_error[-1]).max() < 3 * sig[-1, 3:].max()
    assert np.abs(est.bias_error[-1]).max() < 1e-2 * np.abs(est.gyro.bias[0]).max()
    # NIS: the innovations are white for a consistent filter, so the mean of each dof's
    # NIS over the run lies in the chi-square band of a mean of independent draws
    for d in (2, 3):
        v = est.nis[est.result.dof == d]
        lo, hi = chi2.ppf([0.0005, 0.9995], d * v.size) / v.size
        assert lo < v.mean() < hi, (d, v.mean())


def test_nees_over_independent_runs_is_chi_square_6():
    """The NEES at a given time, averaged over 20 independent runs (other seeds), lies in
    the 99.9 % band of chi-square(6 x 20) / 20 (measured: 6.4, 5.9, 6.0 over 40 runs)."""
    s = parse_scenario(MEKF, source="mekf.toml")
    t = np.arange(151) * 0.1
    runs = 20
    values = []
    for k in range(runs):
        spec = dataclasses.replace(
            s.spec,
            gyro={**s.spec.gyro, "seed": 100 + k},
            tracker={**s.spec.tracker, "seed": 200 + k},
            vectors=tuple({**v, "seed": 300 + k} for v in s.spec.vectors),
        )
        values.append(estimate(dataclasses.replace(s, spec=spec), t).nees[[50, 100, 150]])
    lo, hi = chi2.ppf([0.0005, 0.9995], 6 * runs) / runs
    mean = np.mean(values, axis=0)
    assert np.all((lo < mean) & (mean < hi)), (mean, lo, hi)


def test_example_through_the_cli(tmp_path, capsys):
    out = tmp_path / "mekf"
    code = main(["run", str(EXAMPLES / "mekf_tumbling.toml"), "--out", str(out), "--no-figures"])
    assert code == 0, capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["accuracy"]["invariants"]["attitude_error"]["final"] < 1e-3
    cols = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    assert {"attitude_error_x", "attitude_sigma_x", "bias_error_z", "nees"} <= set(cols.dtype.names)
    html = (out / "report.html").read_text()
    assert "+-3 sigma" in html and "Innovations (NIS)" in html


def test_estimation_needs_a_measurement_and_a_filter():
    bare = MEKF.split("[star_tracker]")[0] + "[filter]\nsigma_attitude = 0.1\nsigma_bias = 1e-3\n"
    with pytest.raises(ScenarioError, match="measurement"):
        parse_scenario(bare, source="bad.toml")
    with pytest.raises(ScenarioError, match="sigma_bias"):
        parse_scenario(MEKF.replace("sigma_bias = 2e-3", "sigma_bias = -1"), source="bad.toml")
