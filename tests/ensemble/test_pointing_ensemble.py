"""Monte-Carlo ensembles of the pointing error relative to LVLH under the gravity
gradient along a Kepler orbit (torque model "gravity-gradient", metric
"pointing_error"; docs/ensembles.md, docs/theory.md §10.2)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed")
pytest.importorskip("pyarrow")

from poinsot.dynamics import KeplerOrbit, Spacecraft, gravity_gradient_stability  # noqa: E402
from poinsot.ensemble import (  # noqa: E402
    Choice,
    EnsembleProblem,
    Metric,
    Normal,
    load_ensemble,
    run,
)
from poinsot.errors import InvalidInputError  # noqa: E402
from poinsot.rotations.rotation import Rotation  # noqa: E402
from poinsot.scenarios import load_scenario  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXAMPLE = EXAMPLES / "gravity_gradient_ensemble.toml"

ORBIT = {"a": 6878137.0, "e": 0.0, "inclination": 0.9, "raan": 0.3, "argp": 0.0,
         "anomaly0": 0.2}  # fmt: skip
KEPLER = KeplerOrbit(**ORBIT)
N = KEPLER.mean_motion  # rad/s
STABLE = np.array([80.0, 100.0, 40.0])  # I2 > I1 > I3: the Lagrange region


def _problem(inertia, omega0, t, dispersions, metrics, rotation0=(1.0, 0, 0, 0)):
    return EnsembleProblem(
        "gg",
        np.diag(inertia),
        np.asarray(rotation0, dtype=float),
        np.asarray(omega0, dtype=float),
        t,
        torque_model="gravity-gradient",
        orbit=ORBIT,
        dispersions=tuple(dispersions),
        metrics=tuple(metrics),
    )


def _lvlh(t):
    """R_io (n, 3, 3) from r and v directly: z nadir, y = -h/|h|, x = y x z."""
    r, v = KEPLER.state(t)
    z = -r / np.linalg.norm(r, axis=-1, keepdims=True)
    h = np.cross(r, v)
    y = -h / np.linalg.norm(h, axis=-1, keepdims=True)
    x = np.cross(y, z)
    return np.stack([x, y, z], axis=-1)


METRICS = (
    Metric("max", "pointing_error"),
    Metric("final", "pointing_error", statistic="final"),
    Metric("rms", "pointing_error", statistic="rms"),
)


def test_zero_dispersion_equals_a_direct_spacecraft_run():
    t = np.linspace(0.0, 1.5 * KEPLER.period, 121)
    r_ob = Rotation.from_rotvec([0.02, -0.03, 0.05])
    w_rel = np.array([0.03, 0.05, -0.02]) * N
    p = _problem(STABLE, w_rel, t, [("omega0", Normal(sigma=0.0))], METRICS, r_ob.as_quat())
    res = run(p, 3, chunk_size=3, client="serial", seed=4)
    # the direct path: LVLH from r and v, LVLH turning at -n about its y axis
    c_io0 = _lvlh(0.0)
    q0 = Rotation.from_matrix(c_io0) * r_ob
    w0 = w_rel + r_ob.inv().apply([0.0, -N, 0.0])
    tr = Spacecraft(STABLE, KEPLER).simulate(q0, w0, t)
    c_ob = np.einsum("nji,njk->nik", _lvlh(t), tr.rotation.as_matrix())
    cos = np.clip((np.trace(c_ob, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    err = np.degrees(np.arccos(cos))
    assert err.max() > 1.0  # a motion, not the equilibrium
    for name, want in (("max", err.max()), ("final", err[-1]),
                       ("rms", np.sqrt(np.mean(err**2)))):  # fmt: skip
        np.testing.assert_allclose(res.column(name), want, rtol=0, atol=1e-6)
    assert not res.column("failed").any()


def test_unstable_inertia_drifts_stable_ones_stay_within_the_libration_amplitude():
    """A pitch rate ``w`` alone, principal axes along LVLH in a circular orbit: the motion
    stays a pure pitch libration ``theta'' = -3 n^2 k2 sin(theta) cos(theta)``, ``k2 =
    (I1 - I3) / I2``. Stable (k2 > 0): the linear amplitude ``w / (n sqrt(3 k2))``
    bounds the angle (the exact one, ``arcsin`` of it, differs by 0.03 % here) and is
    reached within a libration period (< an orbit). Pitch-unstable (I1 < I3, k2 < 0):
    the angle grows as ``exp(n sqrt(3 |k2|) t)`` out of any small neighbourhood."""
    w = 0.05 * N
    t = np.linspace(0.0, 2.0 * KEPLER.period, 241)
    choices = [STABLE, [85.0, 100.0, 40.0], [40.0, 100.0, 80.0]]  # the last: I1 < I3
    p = _problem(STABLE, [0.0, w, 0.0], t, [("inertia", Choice(choices))],
                 (Metric("max", "pointing_error"),
                  Metric("leaves", "first_time", component="pointing_error",
                         above=20.0)))  # fmt: skip
    res = run(p, 8, chunk_size=8, client="serial", seed=3)
    j = np.column_stack([res.column(f"inertia_{c}") for c in "xyz"])
    region = gravity_gradient_stability(j).region
    stable, unstable = region == "lagrange", region == "unstable"
    assert stable.any() and unstable.any() and (stable | unstable).all()
    k2 = (j[:, 0] - j[:, 2]) / j[:, 1]
    bound = np.degrees(w / (N * np.sqrt(3.0 * np.abs(k2))))  # ~2.6 deg
    mx = res.column("max")
    assert np.all(mx[stable] <= 1.001 * bound[stable])
    assert np.all(mx[stable] >= 0.99 * bound[stable])
    assert np.all(np.isnan(res.column("leaves")[stable]))
    assert np.all(mx[unstable] > 20 * bound[unstable])
    assert np.all(res.column("leaves")[unstable] < 2.0 * KEPLER.period)


def test_dask_gives_the_local_table():
    from dask.distributed import Client, LocalCluster

    t = np.linspace(0.0, 0.5 * KEPLER.period, 41)
    p = _problem(STABLE, [0.0, 0.0, 0.0], t,
                 [("inertia", Normal(sigma=[4.0, 5.0, 2.0])),
                  ("omega0", Normal(sigma=0.1 * N))], METRICS)  # fmt: skip
    local = run(p, 12, chunk_size=4, client="serial", seed=8)
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,  # fmt: skip
        Client(cluster) as client,
    ):
        dask = run(p, 12, chunk_size=4, client=client, seed=8)
    assert dask.table.equals(local.table)
    assert np.ptp(local.column("max")) > 0


def test_bad_orbit_keys_are_named(tmp_path):
    t = np.linspace(0.0, 100.0, 3)
    metrics = [Metric("max", "pointing_error")]
    good = _problem(STABLE, np.zeros(3), t, [], metrics)
    for orbit, key in (
        ({**ORBIT, "ecc": 0.1}, "orbit.ecc"),
        ({k: v for k, v in ORBIT.items() if k != "argp"}, "orbit.argp"),
        ({**ORBIT, "e": 1.5}, "`e`"),
        ({**ORBIT, "a": -1.0}, "`a`"),
        ({**ORBIT, "raan": "north"}, "orbit.raan"),
    ):
        with pytest.raises(InvalidInputError, match=key):
            replace(good, orbit=orbit)
    with pytest.raises(InvalidInputError, match="needs an `orbit`"):
        replace(good, orbit=None)
    with pytest.raises(InvalidInputError, match="'gravity-gradient'"):
        EnsembleProblem("x", np.eye(3), [1.0, 0, 0, 0], np.zeros(3), t, metrics=tuple(metrics))
    with pytest.raises(InvalidInputError, match="statistic"):
        Metric("m", "pointing_error", statistic="median")
    # the TOML [orbit]: the spacecraft kind's own reader names the key and its line
    text = EXAMPLE.read_text()
    for old, new, key in (
        ("inclination = 51.6", "inclinaton = 51.6", "inclinaton"),
        ("altitude = 500e3", "altitude = -500e3", "altitude"),
        ('frame = "lvlh"', 'frame = "rtn"', "orbit.frame"),
    ):
        bad = tmp_path / "bad.toml"
        bad.write_text(text.replace(old, new))
        with pytest.raises(InvalidInputError, match=key):
            load_ensemble(bad)


def test_the_example_is_a_gravity_gradient_ensemble():
    scenario, p = load_ensemble(EXAMPLE)
    assert p.torque_model == "gravity-gradient"
    assert str(gravity_gradient_stability(np.diag(p.inertia)).region) == "lagrange"
    orbit = load_scenario(EXAMPLE).spec.orbit
    assert dict(p.orbit)["a"] == orbit.a and dict(p.orbit)["inclination"] == orbit.inclination
    short = replace(p, t=p.t[:12])
    res = run(short, 4, chunk_size=4, client="serial", seed=0)
    assert res.summary["failures"] == 0
    assert np.all(res.column("final_pointing_error") <= res.column("max_pointing_error"))
