"""The estimation cases of ``poinsot verify`` (version 4): an attitude estimator on
stored, seeded gyro and star-tracker samples of an exact tumbling motion, scored
against the truth with a NEES consistency verdict (docs/verify.md)."""

from __future__ import annotations

import json
import re
from xml.etree import ElementTree

import numpy as np
import pandas as pd
import pytest
from scipy.stats import chi2

from poinsot._quat import mul
from poinsot.dynamics import AttitudeSamples, GyroSamples, run_mekf
from poinsot.errors import InvalidInputError
from poinsot.verify import CASES_VERSION, FileEngine, cases, engines, evaluate, export, run
from poinsot.verify.cases import ESTIMATION_THRESHOLDS
from poinsot.verify.files import write_estimate
from poinsot.verify.groups import Estimate, draw_sensors, mekf_estimate, nees_band
from poinsot.verify.suite import Verdict, _time_svg, write

CASE = cases("mekf-racket")[0]


@pytest.fixture(scope="module")
def mekf():
    return run(engines.PoinsotEngine(), CASE)


def _rotated(q, angle):
    """``q o exp(angle e_x / 2)``: the attitude off by ``angle`` about body x."""
    return mul(q, np.array([np.cos(angle / 2), np.sin(angle / 2), 0.0, 0.0]))


def test_the_case_is_version_4_and_states_its_verdict():
    assert CASES_VERSION == "4" and [c.name for c in cases("estimation")] == ["mekf-racket"]
    assert CASE.kind == "estimate" and CASE.t.size == 2001 and CASE.t[1] == 0.1
    # the band: chi-square, 3 dof, two-sided 95 %, as stated
    lo, hi = chi2.ppf([0.025, 0.975], 3)
    assert nees_band(CASE) == pytest.approx((lo, hi), rel=1e-12)
    assert (ESTIMATION_THRESHOLDS["nees_min"], ESTIMATION_THRESHOLDS["nees"]) == pytest.approx(
        (lo, hi), rel=1e-12
    )
    # the truth: the exact motion near the intermediate axis (it flips), the stored bias
    ex = CASE.exact()
    assert CASE.facts["flip_period_s"] == pytest.approx(11.498131, abs=1e-6)
    assert np.sum(np.diff(np.sign(ex["omega"][:, 1])) != 0) >= 16  # 200 s / 11.5 s
    assert np.allclose(ex["bias"][0], CASE.inputs["gyro_bias0"], rtol=0, atol=0)


def test_poinsot_mekf_passes_with_a_consistent_nees(mekf):
    assert mekf.status == "pass", mekf.reason
    v = {k: m["value"] for k, m in mekf.metrics.items()}
    assert set(v) == {"attitude", "attitude_rms", "bias", "nees"}
    # measured: 5.7e-4 rad, 2.3e-4 rad, 2.5e-5 rad/s, NEES 3.58 (mean 3 when consistent)
    assert v["attitude"] < 6e-4 and v["attitude_rms"] < 2.5e-4 and v["bias"] < 3e-5
    assert 2.5 < v["nees"] < 4.5
    assert mekf.metrics["nees"]["minimum"] == ESTIMATION_THRESHOLDS["nees_min"]


def test_an_overconfident_filter_fails_the_consistency_verdict():
    """The MEKF with the gyro noise under-stated 100x: attitude still near, but its
    covariance is far too small: NEES in the thousands."""
    bad = evaluate(CASE, mekf_estimate(CASE, arw=1e-6, rrw=1e-8))
    assert bad.status == "fail"
    assert not bad.metrics["nees"]["passed"] and bad.metrics["nees"]["value"] > 1e3
    assert "nees" in bad.reason and "outside [0.216, 9.35]" in bad.reason


def test_truth_off_by_a_degree_with_tiny_sigma_fails():
    ex = CASE.exact()
    q = _rotated(np.array(ex["quat"]), np.radians(1.0))
    est = Estimate(CASE.t, q, ex["bias"], np.full((CASE.t.size, 3), 1e-6), "off")
    res = evaluate(CASE, est)
    assert res.status == "fail"
    assert res.metrics["attitude"]["value"] == pytest.approx(np.radians(1.0), rel=1e-9)
    assert res.metrics["attitude_rms"]["value"] == pytest.approx(np.radians(1.0), rel=1e-9)
    assert res.metrics["bias"]["value"] == 0.0 and res.metrics["bias"]["passed"]
    assert res.metrics["nees"]["value"] == pytest.approx((np.radians(1.0) / 1e-6) ** 2, rel=1e-6)
    # an estimator too cautious fails too (NEES below the band)
    wide = evaluate(CASE, Estimate(CASE.t, ex["quat"], None, np.full((CASE.t.size, 3), 1.0)))
    assert wide.status == "fail" and wide.metrics["nees"]["value"] < 0.2


def test_integrators_skip_the_group_with_a_reason():
    for eng in (engines.SciPyEngine(), engines.MuJoCoEngine(), engines.PyBulletEngine(),
                engines.DrakeEngine(), engines.BasiliskEngine()):  # fmt: skip
        res = run(eng, CASE)
        assert res.status == "skip" and "attitude-estimation case" in res.reason, eng.name
    res = run(engines.PoinsotEngine("rk4", step=0.01), CASE)
    assert res.status == "skip" and "MEKF" in res.reason


def test_export_then_an_outside_estimator_scores_as_the_direct_run(tmp_path, mekf):
    """An estimator that reads only the exported files (the MEKF here, fed from the CSVs
    and the JSON) writes CASE.csv; the file engine scores it as the direct run."""
    files = {p.name for p in export(tmp_path, "estimation")}
    assert {"mekf-racket.gyro.csv", "mekf-racket.star_tracker.csv", "mekf-racket.csv",
            "mekf-racket.json"} <= files  # fmt: skip
    desc = json.loads((tmp_path / "mekf-racket.json").read_text())
    i = desc["inputs"]
    gyro = pd.read_csv(tmp_path / "mekf-racket.gyro.csv")
    st = pd.read_csv(tmp_path / "mekf-racket.star_tracker.csv")
    assert list(gyro.columns) == ["t", "wx", "wy", "wz"] and desc["units"]["bx,by,bz"] == "rad/s"
    assert list(st.columns) == ["t", "qw", "qx", "qy", "qz"] and len(st) == 201
    t, n = gyro["t"].to_numpy(), len(gyro)
    zeros = np.zeros((n, 3))
    g = GyroSamples(t, gyro[["wx", "wy", "wz"]].to_numpy(), zeros, zeros,
                    np.tile([1.0, 0, 0, 0], (n, 1)), i["gyro_arw"], i["gyro_rrw"])  # fmt: skip
    qm = st[["qw", "qx", "qy", "qz"]].to_numpy()
    s = AttitudeSamples(st["t"].to_numpy(), qm, qm, np.array(i["star_tracker_sigma"]))
    r = run_mekf(g, [s], qm[0], np.array(i["covariance0"]), bias0=i["bias_estimate0"])
    out = tmp_path / "estimator"
    write_estimate(out, CASE, Estimate(t, r.quat, r.bias, r.sigma[:, :3], "outside"))
    res = run(FileEngine(out), CASE)
    assert res.status == "pass"
    assert {k: m["value"] for k, m in res.metrics.items()} == {
        k: m["value"] for k, m in mekf.metrics.items()
    }


def test_the_sensor_data_are_reproducible(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    export(a, "mekf-racket")
    export(b, "mekf-racket")
    for name in ("mekf-racket.gyro.csv", "mekf-racket.star_tracker.csv", "mekf-racket.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes()
    # the stored samples are the seed's draw (PCG64) with this NumPy: the same noise;
    # the truth under it (elliptic functions, compiled or not) to a few ulps, which the
    # gyro's log(L_{k-1}~ o L_k) / dt turns into 1e-14 rad/s: hence stored data
    drawn = draw_sensors(CASE)
    stored = CASE.spec.stored(CASE)
    for k, v in drawn.items():
        np.testing.assert_allclose(v, stored[k], rtol=0, atol=1e-12, err_msg=k)


def test_an_estimate_with_the_attitude_alone_is_scored_on_it(tmp_path):
    ex = CASE.exact()
    write_estimate(tmp_path, CASE, Estimate(CASE.t, ex["quat"]))
    res = run(FileEngine(tmp_path), CASE)
    assert res.status == "pass" and set(res.metrics) == {"attitude", "attitude_rms"}


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda df: df.drop(columns="qz"), "missing `qz`"),
        (
            lambda df: df.drop(columns=["by", "bz"]),
            r"bx, by, bz \(all or none\); missing `by`, `bz`",
        ),
        (lambda df: df.assign(sy=0.0), "column `sy` to hold positive"),
        (lambda df: df.assign(sx="x"), "column `sx` to hold numbers"),
        (lambda df: df.assign(qw=2.0), "unit quaternions in columns qw, qx, qy, qz"),
        (lambda df: df.iloc[:-1], "in column `t`"),
    ],
    ids=["no-qz", "partial-bias", "zero-sigma", "text", "not-unit", "short"],
)
def test_bad_files_raise_naming_the_column(tmp_path, edit, match):
    ex = CASE.exact()
    sig = np.full((CASE.t.size, 3), 1e-4)
    path = write_estimate(tmp_path, CASE, Estimate(CASE.t, ex["quat"], ex["bias"], sig))
    edit(pd.read_csv(path)).to_csv(path, index=False)
    with pytest.raises(InvalidInputError, match=match):
        run(FileEngine(tmp_path), CASE)


def test_a_diverged_estimate_fails(tmp_path):
    ex = CASE.exact()
    q = np.array(ex["quat"])
    q[-1] = np.nan
    write_estimate(tmp_path, CASE, Estimate(CASE.t, q))
    res = run(FileEngine(tmp_path), CASE)
    assert res.status == "fail" and "non-finite values in column(s) qw, qx, qy, qz" in res.reason


def test_the_case_page_draws_the_errors_against_their_limits(tmp_path, mekf):
    # the run is labelled by the method it ran (the MEKF), the engine by its default
    assert mekf.result.method == "poinsot mekf"
    assert engines.PoinsotEngine().label == "poinsot (each case's default method)"
    verdict = Verdict("poinsot", engines.PoinsotEngine().label, [mekf])
    files = write(verdict, tmp_path)
    page = tmp_path / "cases" / "mekf-racket.html"
    assert page in files
    text = page.read_text(encoding="utf-8")
    root = ElementTree.fromstring(text[text.index("<svg") : text.index("</svg>") + 6])
    assert root.tag.endswith("svg")
    # the two charts, each with its limits written as the metrics state them
    assert text.count("<svg") == 2
    nees = mekf.metrics["nees"]
    assert f"band, upper {nees['threshold']:.3g}" in text
    assert f"band, lower {nees['minimum']:.3g}" in text
    assert f"time average {nees['value']:.3g}" in text
    assert f"threshold (second half) {mekf.metrics['attitude']['threshold']:.3g}" in text
    index = (tmp_path / "verify.html").read_text(encoding="utf-8")
    assert 'href="cases/mekf-racket.html"' in index


def test_a_long_series_keeps_its_spike_when_thinned():
    t = np.linspace(0.0, 100.0, 50001)
    y = np.full(t.size, 1e-3)
    y[25001] = 1e3  # one sample in 50001: 2500 bins of 21 samples must keep it
    svg = _time_svg(t, y, "error", [])
    pts = re.search(r'polyline[^>]*points="([^"]+)"', svg).group(1).split()
    ys = np.array([float(p.split(",")[1]) for p in pts])
    assert 2000 <= ys.size <= 2500
    ticks = {
        m.group(2): float(m.group(1)) - 4 for m in re.finditer(r'y="([\d.]+)"[^>]*>1e(-?\d+)<', svg)
    }
    assert ys.min() == pytest.approx(ticks["3"], abs=0.05)  # the top of the chart: 1e3
    assert ys.max() == pytest.approx(ticks["-3"], abs=0.05)
