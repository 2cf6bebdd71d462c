"""Writing outputs leaves the caller's state alone; results summarise themselves; a new
kind of motion plugs in through the registry exactly as docs/adding-a-motion.md says."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot.cli import main
from poinsot.scenarios import (
    Check,
    Entry,
    Facts,
    ScenarioKind,
    demo_scenario,
    load_scenario,
    parse_scenario,
    run_scenario,
    simulate_scenario,
    write_outputs,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_run_keeps_the_callers_backend_and_figures(tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    backend = matplotlib.get_backend()
    mine = plt.figure()
    before = plt.get_fignums()
    _, files = run_scenario(demo_scenario(), tmp_path / "o", report=False, duration=0.5)
    names = {p.name for p in files}
    assert {"omega.png", "invariants.png", "maccullagh.png", "poinsot.png"} <= names
    assert matplotlib.get_backend() == backend
    assert plt.get_fignums() == before and plt.fignum_exists(mine.number)  # none closed/added
    for name in ("omega.png", "maccullagh.png"):
        assert (tmp_path / "o" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    plt.close(mine)


def test_write_outputs_is_idempotent(tmp_path):
    result = simulate_scenario(demo_scenario(), duration=0.3)
    before = json.dumps(result.summary, sort_keys=True)
    f1 = write_outputs(result, tmp_path / "a", report=False, figures=False)
    f2 = write_outputs(result, tmp_path / "a", report=False, figures=False, force=True)
    write_outputs(result, tmp_path / "b", report=False, figures=False)
    assert json.dumps(result.summary, sort_keys=True) == before  # the result is unchanged
    s1 = (tmp_path / "a" / "summary.json").read_text()
    assert s1 == (tmp_path / "b" / "summary.json").read_text()
    summary = json.loads(s1)
    assert summary["run"]["notes"] == ["report.html not written (--no-report)"]  # once
    assert [p.name for p in f1] == [p.name for p in f2] == summary["run"]["files"]


def test_summary_sections_have_units():
    result = simulate_scenario(load_scenario(EXAMPLES / "symmetric_top.toml"), duration=0.05)
    s = result.summary
    assert list(s) == [
        "scenario",
        "conventions",
        "body",
        "initial_state",
        "results",
        "accuracy",
        "run",
    ]
    assert s["body"]["units"]["mass"] == "kg" and s["body"]["units"]["inertia"] == "kg m^2"
    assert s["initial_state"]["units"]["omega_body"] == "rad/s"
    assert s["results"]["units"]["nutation_period"] == "s"
    assert s["results"]["units"]["H"] == "kg m^2/s"
    inv = s["accuracy"]["invariants"]
    assert inv["total_energy"]["units"] == "J" and inv["momentum_z"]["units"] == "kg m^2/s"
    # every numeric entry of the body, initial state and results sections has units
    for name in ("body", "initial_state", "results"):
        sec = s[name]
        for key, value in sec.items():
            if key != "units" and isinstance(value, float | list) and value:
                assert key in sec["units"], (name, key)


def test_result_describes_itself_in_words():
    text = simulate_scenario(demo_scenario(), duration=0.5).describe(title="x")
    assert text.startswith("x: tennis-racket-flip")
    assert "exact solution, Jacobi elliptic functions (docs/theory.md §10)" in text
    assert "unstable about y" in text


# ------------------------------------------------------------------ a new kind, by the recipe
@dataclass(frozen=True)
class SpinSpec:
    axis: np.ndarray
    rate: float


class Spin(ScenarioKind):
    """A toy kind: uniform rotation about a fixed space axis (a closed form)."""

    name = "spin"
    title = "uniform spin about a fixed axis"
    tables = ("spin",)
    methods = ("exact", "rk4")
    orders = {"rk4": 4}

    def claims(self, data):
        return "spin" in data

    def parse(self, top, attitude):
        t = top.table("spin", required=True)
        t.known(("axis", "rate"))
        axis = np.array(t.vector("axis", 3))
        spec = SpinSpec(axis / np.linalg.norm(axis), t.number("rate", required=True))
        t.finish(("axis", "rate"))
        return {"spec": spec}

    def solve(self, scenario, method, t, progress):
        from poinsot.kinematics import propagate
        from poinsot.rotations.rotation import Rotation
        from poinsot.trajectory import Trajectory

        w = scenario.spec.rate * scenario.spec.axis
        r0 = scenario.attitude.rotation
        if method == "exact":
            rot = Rotation.from_rotvec(np.outer(t, w)) * r0
            return Trajectory(t, rot, rot.apply(w, inverse=True), "exact")
        return propagate(r0, lambda tt: w, t, frame="space", method=method)

    def facts(self, scenario):
        period = 2 * np.pi / abs(scenario.spec.rate)
        return Facts({"period": Entry(period, "s")}, (f"period {period:.4g} s",))

    def checks(self, scenario, tr):
        angle = (tr.rotation * scenario.attitude.rotation.inv()).magnitude()
        expected = np.abs((scenario.spec.rate * tr.t + np.pi) % (2 * np.pi) - np.pi)
        return (Check("angle", "angle turned", "rad", angle, expected=expected, scale=np.pi),)


SPIN_TOML = """
name = "toy"
[spin]
axis = [0.0, 0.0, 2.0]
rate = 3.0
[simulation]
duration = 2.0
step = 0.01
method = "rk4"
reference = "exact"
"""


def test_a_new_kind_needs_one_adapter_and_one_registry_line(capsys, tmp_path, monkeypatch):
    from poinsot.scenarios import registry

    monkeypatch.setattr(registry, "KINDS", MappingProxyType({"spin": Spin(), **registry.KINDS}))
    s = parse_scenario(SPIN_TOML)
    assert s.kind == "spin" and s.spec.rate == 3.0
    with pytest.raises(Exception, match=r"`spin\.rat` unknown key"):
        parse_scenario(SPIN_TOML.replace("rate =", "rat ="))
    p = tmp_path / "toy.toml"
    p.write_text(SPIN_TOML)
    code = main(["run", str(p), "--out", str(tmp_path / "o"), "--no-report"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "period 2.094 s" in out and "(spin)" not in err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["scenario"]["kind"] == "spin"
    assert summary["results"]["period"] == pytest.approx(2 * np.pi / 3)
    # rk4 (h = 0.01 s, w = 3 rad/s: error ~ t (w h)^5 / 120 ~ 4e-10 rad) against
    # SciPy's rotation about z by 3 t
    data = np.loadtxt(tmp_path / "o" / "trajectory.csv", delimiter=",", skiprows=1)
    truth = SciRotation.from_rotvec(np.outer(data[:, 0], [0, 0, 3.0]))
    got = SciRotation.from_quat(data[:, 1:5], scalar_first=True)
    err = (truth.inv() * got).magnitude().max()
    assert 0 < err < 1e-7
    drift = summary["accuracy"]["invariants"]["angle"]["max_relative_drift"]
    assert drift == pytest.approx(err / np.pi, rel=1e-3)
    assert {"omega.png", "invariants.png"} <= set(summary["run"]["files"])
