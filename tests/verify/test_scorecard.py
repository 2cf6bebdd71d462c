"""``poinsot verify scorecard``: the sweeps, the analysis of the rows, the pages, and the
committed pages under docs/verify/scorecard (regenerated from the committed JSON, so
that no engine is needed)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from poinsot.verify.scorecard import (
    EngineCard,
    Scorecard,
    Sweep,
    diagnose,
    first_passing,
    observed_order,
    scorecard,
)

STORED = Path(__file__).resolve().parents[2] / "docs" / "verify" / "scorecard"

SWEEPS = {
    "scipy": [Sweep("scipy", "DOP853", {"method": "DOP853"}, "rtol", (1e-6, 1e-12), 1e-12)],
    "poinsot": [
        Sweep("poinsot", "rk4", {"method": "rk4"}, "step", (0.02, 0.01, 0.005), 0.01),
        Sweep("poinsot", "DOP853 (points)", {"method": "DOP853"}, "rtol", (1e-6, 1e-12), 1e-12),
    ],
}


@pytest.fixture(scope="module")
def card() -> Scorecard:
    return scorecard(SWEEPS, ["free-symmetric", "kepler-e0.5"], jobs=1)


def test_the_scorecard_runs_every_sweep_on_every_case(card):
    scipy, poinsot = card.cards
    assert scipy.version and poinsot.version
    assert [(r["value"], r["case"], r["status"]) for r in scipy.rows] == [
        (1e-6, "free-symmetric", "fail"),
        (1e-6, "kepler-e0.5", "fail"),
        (1e-12, "free-symmetric", "pass"),
        (1e-12, "kepler-e0.5", "pass"),
    ]
    rk4 = [r for r in poinsot.rows if r["integrator"] == "rk4"]
    # rk4 integrates rigid bodies: the orbit is skipped with the reason
    assert {r["status"] for r in rk4 if r["case"] == "kepler-e0.5"} == {"skip"}
    scored = [r for r in rk4 if "metrics" in r]
    assert [r["value"] for r in scored] == [0.02, 0.01, 0.005]
    for r in scored:
        assert r["drift_unit"] == "rev" and r["work"] > 0 and r["energy_per"] >= 0
    d = diagnose("step", poinsot.series(poinsot.sweeps[0], "free-symmetric"))
    assert d["order"] is None or d["order"] > 3  # rk4: fourth order (or exact already)


def test_json_round_trip_gives_the_same_pages(card, tmp_path):
    path = card.to_json(tmp_path / "scorecard.json")
    back = Scorecard.from_json(path)
    assert back.to_dict() == json.loads(path.read_text())
    for engine in ("scipy", "poinsot", None):
        assert back.to_markdown(engine) == card.to_markdown(engine)
    files = back.write(tmp_path / "pages")
    names = {f.name for f in files}
    assert {"scorecard.json", "index.md"} <= names
    assert any(n.endswith(".png") for n in names)
    page = card.to_markdown("scipy")
    assert "## Cases x integrators" in page and "## What fails and why" in page


def test_first_passing_is_the_coarsest_setting_from_which_all_pass():
    assert first_passing([1e-2, 1e-3, 1e-4], [False, True, True]) == 1e-3
    assert first_passing([1e-2, 1e-3, 1e-4], [True, True, True]) == 1e-2
    # a lucky pass at a coarse setting, failing finer, does not count
    assert first_passing([1e-2, 1e-3, 1e-4], [True, False, True]) == 1e-4
    assert first_passing([1e-2, 1e-3, 1e-4], [True, True, False]) is None
    assert first_passing([], []) is None


def _rows(values, errors, *, energy=0.0, change=0.0, thr=1e-6):
    energies = energy if isinstance(energy, list) else [energy] * len(values)
    return [
        {
            "value": v,
            "status": "pass" if e <= thr and en <= 1e-8 else "fail",
            "energy_change": change,
            "metrics": {
                "attitude": {"value": e, "threshold": thr, "passed": e <= thr},
                "energy": {"value": en, "threshold": 1e-8, "passed": en <= 1e-8},
            },
        }
        for v, e, en in zip(values, errors, energies, strict=True)
    ]


STEPS = [1e-2, 1e-3, 1e-4]


@pytest.mark.parametrize(
    ("errors", "kind", "order"),
    [
        ([1e-1 * 0.99, 1e-2, 1e-3], "first-order", 1.0),  # saturated point left out
        ([5e-2, 5e-3, 5e-4], "first-order", 1.0),
        ([2e-2, 2e-4, 2e-6], "order 2", 2.0),
        ([1e-4, 1e-8, 1e-11], "pass", 4.0),  # the point near round-off left out
        ([0.5, 0.5, 0.5], "no convergence", None),  # saturated everywhere
        ([3e-3, 2.9e-3, 3.1e-3], "no convergence", 0.0),  # a wrong answer, whatever the step
    ],
)
def test_order_of_convergence_classification(errors, kind, order):
    d = diagnose("timestep", _rows(STEPS, errors))
    assert d["kind"] == kind
    if order is None:
        assert d["order"] is None
    else:
        assert d["order"] == pytest.approx(order, abs=0.05)
    if kind == "first-order":
        assert d["text"].startswith("a first-order method")
    if kind == "no convergence":
        assert "wrong physics?" in d["text"]


def test_an_unstable_motion_is_not_read_as_wrong_physics():
    # the attitude stays wrong (a flip lost) while the energy drift converges at order 1
    d = diagnose("step", _rows(STEPS, [2.6, 2.9, 1.9], energy=[1e-1, 1e-2, 1e-3]))
    assert d["kind"] == "unstable" and "not wrong physics" in d["text"]
    # a tolerance sweep whose error stays while the energy is kept: the error control
    d = diagnose("accuracy", _rows([1e-6, 1e-8, 1e-10], [5e-4, 3e-2, 6e-4], energy=1e-14))
    assert d["kind"] == "error control"


def test_observed_order_skips_roundoff_saturation_and_non_finite():
    assert observed_order(STEPS, [math.inf, 1e-3, 1e-4]) == pytest.approx(1.0)
    assert observed_order(STEPS, [1.0, 2.0, 3.0]) is None
    assert observed_order(STEPS, [1e-11, 1e-12, 1e-13]) is None


def test_energy_growth_is_flagged_where_the_attitude_is_nearly_right():
    rows = _rows(STEPS, [5e-4, 5e-5, 5e-6], energy=1e-6, change=1e-6)
    assert diagnose("timestep", rows)["energy_growth"]
    rows = _rows(STEPS, [5e-4, 5e-5, 5e-6], energy=1e-6, change=-1e-6)  # decay: not growth
    assert not diagnose("timestep", rows)["energy_growth"]


def test_a_tolerance_sweep_is_not_read_as_an_order():
    d = diagnose("rtol", _rows([1e-6, 1e-8], [1e-4, 1e-6 * 1.5]))
    assert d["kind"] == "tolerance" and "rtol" in d["text"]


def test_unknown_engine_is_refused():
    from poinsot.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match="Expected engines among"):
        scorecard(["bullet3"], "free-symmetric")


def test_mujoco_takes_the_implicit_integrator():
    pytest.importorskip("mujoco")
    from poinsot.verify import cases, make, run

    res = run(make("mujoco", integrator="implicit", timestep=0.01), cases("free-symmetric")[0])
    assert res.status in ("pass", "fail") and math.isfinite(res.metrics["attitude"]["value"])


@pytest.mark.skipif(not (STORED / "scorecard.json").is_file(), reason="no stored scorecard")
def test_committed_pages_are_those_of_the_committed_json(tmp_path):
    stored = Scorecard.from_json(STORED / "scorecard.json")
    files = stored.write_pages(tmp_path, charts=False)
    for f in files:
        committed = STORED / f.name
        assert committed.is_file(), f"{f.name} is not committed"
        assert committed.read_text(encoding="utf-8") == f.read_text(encoding="utf-8"), (
            f"{f.name} differs from the pages of scorecard.json: rerun poinsot verify "
            "scorecard --from-json docs/verify/scorecard/scorecard.json --out docs/verify/scorecard"
        )
    for c in stored.cards:
        assert isinstance(c, EngineCard)
    for png in STORED.glob("*.png"):
        assert png.stat().st_size < 100_000, png.name
        assert f"]({png.name})" in "".join(f.read_text() for f in files if f.suffix == ".md")


def test_cli_from_json_writes_the_pages(tmp_path, card):
    from poinsot.cli import main

    path = card.to_json(tmp_path / "s.json")
    assert main(["verify", "scorecard", "--from-json", str(path), "--out", str(tmp_path)]) == 0
    assert (tmp_path / "index.md").read_text() == card.to_markdown()


def test_a_fitted_slope_of_zero_is_written_without_a_sign():
    # the least-squares slope of a flat error comes out as +-1e-17, its sign set by the
    # machine's LAPACK: the committed pages must be the same on every machine
    from poinsot.verify.scorecard import _f1

    assert _f1(-1e-17) == _f1(1e-17) == _f1(0.0) == "0.0"
    assert _f1(-0.04) == "0.0"
    assert _f1(-0.06) == "-0.1"
    assert _f1(7.96) == "8.0"
