"""Running scenarios: every shipped example, physics checks on the outputs, atomic files."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import InvalidInputError
from poinsot.kinematics import coning_omega, coning_quat
from poinsot.scenarios import (
    demo_scenario,
    load_scenario,
    parse_scenario,
    run_scenario,
    simulate_scenario,
)
from poinsot.trajectory import Trajectory

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXAMPLE_FILES = sorted(EXAMPLES.glob("*.toml"))

# short durations keep the whole file fast; each still covers many output samples
SHORT = {
    "tennis_racket": 1.0,
    "symmetric_top": 0.2,
    "satellite_torque": 60.0,
    "attitude_propagation": 10.0,
    "coning": 1.0,
}


def read_csv(path: Path):
    """``(header lines, units, columns)``: the CSV read by pandas and by NumPy's
    genfromtxt (both must see the same names and values), its sidecar JSON."""
    import json

    pd = pytest.importorskip("pandas")
    frame = pd.read_csv(path)
    arr = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
    assert list(frame.columns) == list(arr.dtype.names)
    cols = {n: frame[n].to_numpy() for n in frame.columns}
    for n in cols:
        np.testing.assert_array_equal(np.atleast_1d(arr[n]), cols[n])
    meta = json.loads(path.with_name(f"{path.stem}.columns.json").read_text())
    assert list(meta["columns"]) == list(cols)
    return meta["header"], meta["columns"], cols


def test_examples_shipped():
    names = {p.stem for p in EXAMPLE_FILES}
    assert {"tennis_racket", "symmetric_top", "satellite_torque", "attitude_propagation"} <= names


def first_example_of_each_kind() -> set[Path]:
    """Figures are drawn (about a second each on a loaded machine) for the first example
    of each kind only; the others run with the same code path minus the PNGs."""
    first: dict[str, Path] = {}
    for p in EXAMPLE_FILES:
        try:
            first.setdefault(load_scenario(p).kind, p)
        except Exception:  # a broken example fails its own case, not every case
            continue
    return set(first.values())


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=lambda p: p.stem)
def test_every_example_runs(path, tmp_path):
    scenario = load_scenario(path)
    out = tmp_path / scenario.name
    figures = path in first_example_of_each_kind()
    result, files = run_scenario(
        scenario, out, report=False, figures=figures, duration=SHORT.get(path.stem, 1.0)
    )
    names = {p.name for p in files}
    assert {"trajectory.csv", "summary.json"} <= names
    if figures:  # every figure the kind offers was drawn (none skipped with a note)
        assert {spec.name for spec in result.figures()} <= names, files.notes
        assert not any("skipped" in n for n in files.notes), files.notes
    assert sorted(p.name for p in out.iterdir()) == sorted(names)  # no temporary left
    header, units, cols = read_csv(out / "trajectory.csv")
    tr = result.trajectory
    np.testing.assert_allclose(cols["t"], tr.t, rtol=0, atol=0)  # exact repr
    if isinstance(tr, Trajectory):  # a rigid body: attitude and omega
        assert any("scalar first" in h for h in header) and any("rad/s" in h for h in header)
        q = np.stack([cols[k] for k in ("qw", "qx", "qy", "qz")], axis=-1)
        np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-12)
    else:  # the kind's own state, in its units; no dead attitude columns
        assert not {"qw", "qx", "qy", "qz", "wx", "wy", "wz"} & set(cols)
        for name, ch in tr.state_channels().items():
            v = np.asarray(ch.values).reshape(tr.t.size, -1)
            keys = [k for k in cols if k == name or k.startswith(f"{name}_")][: v.shape[1]]
            assert len(keys) == v.shape[1], (name, list(cols))
            np.testing.assert_array_equal(np.column_stack([cols[k] for k in keys]), v)
            assert {units[k] for k in keys} == {ch.units or "1"}
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scenario"]["name"] == scenario.name
    assert summary["scenario"]["file"] == scenario.data
    assert set(summary["run"]["versions"]) >= {"poinsot", "numpy", "scipy", "python"}
    assert summary["run"]["method"] == scenario.simulation.method
    assert summary["run"]["files"][-1] == "summary.json"
    if scenario.simulation.reference:
        assert (out / "reference.csv").exists()
        assert summary["accuracy"]["comparison"]["reference"] == scenario.simulation.reference


def test_free_body_invariants_and_exact_vs_numerical():
    """Torque-free: T, |K| and the space vector K are conserved (theory §10); the midpoint
    integrator converges to the exact (Jacobi elliptic) solution."""
    result = simulate_scenario(demo_scenario(), duration=4.0)
    inv = result.summary["accuracy"]["invariants"]
    for key in ("energy", "momentum_norm", "momentum_vector"):
        assert inv[key]["conserved"] and inv[key]["max_relative_drift"] < 1e-12
    tr, ref = result.trajectory, result.reference
    assert tr.method == "midpoint" and ref.method == "exact"
    # the invariants recomputed here from the raw states, not read from the summary
    j = np.asarray(result.scenario.body.inertia)
    for traj, tol in ((tr, 1e-12), (ref, 1e-13)):
        w = np.asarray(traj.omega)
        energy = 0.5 * np.einsum("ni,ij,nj->n", w, j, w)
        k_space = traj.rotation.apply(w @ j)  # K_n = C_nb J w_b
        assert np.max(np.abs(energy / energy[0] - 1)) < tol
        k0 = np.linalg.norm(k_space[0])
        assert np.max(np.linalg.norm(k_space - k_space[0], axis=-1)) / k0 < tol
    # second-order method at h = 1 ms on a spin of 6 rad/s: close to the exact solution
    angle = SciRotation.from_quat(ref.quat, scalar_first=True).inv() * SciRotation.from_quat(
        tr.quat, scalar_first=True
    )
    assert 1e-9 < angle.magnitude().max() < 1e-3  # an O(h^2) error, neither zero nor large
    assert result.summary["accuracy"]["comparison"]["max_attitude_error_rad"] == pytest.approx(
        angle.magnitude().max(), rel=1e-6
    )
    # the closed form: 2T and |K| from the initial state (theory §8)
    j = np.asarray(result.scenario.body.inertia)
    w0 = np.asarray(result.scenario.angular_velocity.omega_body)
    cf = result.summary["results"]
    assert cf["energy"] == pytest.approx(0.5 * w0 @ j @ w0, rel=1e-14)
    assert cf["momentum_norm"] == pytest.approx(np.linalg.norm(j @ w0), rel=1e-14)


def test_tennis_racket_flips():
    """Spin about the intermediate axis: omega_y reverses (the flip), within one period."""
    s = load_scenario(EXAMPLES / "tennis_racket.toml")
    result = simulate_scenario(s)
    w = result.trajectory.omega
    assert w[0, 1] > 10 and w[:, 1].min() < -10
    period = result.summary["results"]["period"]
    t_flip = result.trajectory.t[np.argmax(w[:, 1] < 0)]
    assert 0 < t_flip < period


def test_heavy_top_regular_precession():
    """Lagrange top started on the slow regular precession of theory §10
    (A psi'^2 cos(theta) - H psi' + m g l = 0): the tilt stays 30 deg and the axis
    precesses at psi' computed here independently."""
    s = load_scenario(EXAMPLES / "symmetric_top.toml")
    result = simulate_scenario(s, duration=0.4)
    m, g, l = s.body.mass, s.torque.g, s.body.center_of_mass[2]
    r, h = s.body.dims
    a = m * (3 * r**2 + h**2) / 12 + m * l**2  # about the pin (Huygens-Steiner)
    c = m * r**2 / 2
    theta = np.radians(30.0)
    spin = 150.0
    big_h = c * spin
    psi_dot = (big_h - np.sqrt(big_h**2 - 4 * a * np.cos(theta) * m * g * l)) / (
        2 * a * np.cos(theta)
    )
    np.testing.assert_allclose(s.angular_velocity.omega_body, [0, psi_dot * np.sin(theta), spin])
    tr = result.trajectory
    axis = tr.rotation.apply(np.array([0.0, 0.0, 1.0]))  # symmetry axis in space
    tilt = np.arccos(axis[:, 2])
    np.testing.assert_allclose(tilt, theta, atol=1e-7)
    psi = np.unwrap(np.arctan2(axis[:, 0], -axis[:, 1]))
    rate = np.polyfit(tr.t, psi, 1)[0]
    assert rate == pytest.approx(psi_dot, rel=1e-7)
    inv = result.summary["accuracy"]["invariants"]
    assert inv["total_energy"]["max_relative_drift"] < 1e-9
    assert inv["momentum_z"]["max_relative_drift"] < 1e-9
    assert inv["spin_momentum_H"]["initial"] == pytest.approx(big_h, rel=1e-12)
    assert inv["spin_momentum_H"]["max_relative_drift"] < 1e-9
    cf = result.summary["results"]
    assert cf["motion"] == "regular precession" and cf["H"] == pytest.approx(big_h)
    assert cf["nutation_theta_min"] == pytest.approx(theta, abs=1e-7)
    assert cf["nutation_theta_max"] == pytest.approx(theta, abs=1e-7)


def test_constant_space_torque_momentum_balance():
    """dK/dt = M in space axes: K(t) = K(0) + M t exactly (theory §9)."""
    s = parse_scenario(
        textwrap.dedent("""
        [body]
        mass = 3.0
        inertia = [1.0, 2.0, 2.5]
        [attitude]
        euler = [10.0, 20.0, 30.0]
        sequence = "zyx"
        degrees = true
        [angular_velocity]
        vector = [0.3, -0.2, 0.5]
        frame = "body"
        [torque]
        model = "space"
        vector = [0.1, 0.0, -0.05]
        [simulation]
        duration = 5.0
        step = 0.05
        method = "adaptive"
        """)
    )
    result = simulate_scenario(s)
    tr = result.trajectory
    j = np.diag([1.0, 2.0, 2.5])
    # K_n = C_nb J w_b from the raw states, against K(0) + M t with K(0) from the input
    r0 = SciRotation.from_euler("zyx", [10.0, 20.0, 30.0], degrees=True)
    k0 = r0.apply(j @ np.array([0.3, -0.2, 0.5]))
    expected = k0 + np.outer(tr.t, [0.1, 0.0, -0.05])
    k_space = tr.rotation.apply(np.asarray(tr.omega) @ j)
    np.testing.assert_allclose(k_space, expected, atol=1e-8 * np.abs(expected).max())
    assert result.summary["accuracy"]["invariants"]["momentum_balance"]["max_relative_drift"] < 1e-8
    assert not result.summary["accuracy"]["invariants"]["energy"]["conserved"]


def test_constant_body_torque_work_energy():
    """With a body torque the kinetic energy changes at the rate M . w (theory §9)."""
    s = load_scenario(EXAMPLES / "satellite_torque.toml")
    tr = simulate_scenario(s, duration=60.0).trajectory
    power = tr.omega @ np.asarray(s.torque.vector)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(tr.t))])
    # trapezoidal quadrature on the 0.5 s output grid limits the agreement
    np.testing.assert_allclose(tr.energy - tr.energy[0], work, atol=1e-4 * np.abs(work).max())
    assert abs(tr.energy[-1] - tr.energy[0]) > 1e-3 * tr.energy[0]  # it does change


def test_coning_closed_form():
    """Coning body rates equal 2 q~ o q' of the closed-form attitude (finite differences),
    and the Magnus integrator reproduces the closed form."""
    a, w, t = 0.3, 2.0, np.linspace(0.0, 3.0, 31)
    from poinsot import quaternion as qa

    eps = 1e-6
    dq = (coning_quat(a, w, t + eps) - coning_quat(a, w, t - eps)) / (2 * eps)
    omega_fd = 2 * qa.multiply(qa.conjugate(coning_quat(a, w, t)), dq)
    np.testing.assert_allclose(omega_fd[:, 0], 0.0, atol=1e-8)
    np.testing.assert_allclose(omega_fd[:, 1:], coning_omega(a, w, t), atol=1e-8)
    # Lc(t) written out here from the textbook form (not via coning_quat)
    lc = np.stack(
        [np.full_like(t, np.cos(a / 2)), np.sin(a / 2) * np.cos(w * t)]
        + [np.sin(a / 2) * np.sin(w * t), 0 * t],
        axis=-1,
    )
    np.testing.assert_allclose(coning_quat(a, w, t), lc, atol=1e-15)
    result = simulate_scenario(load_scenario(EXAMPLES / "coning.toml"))
    # the example: half-angle 5 deg, 2 Hz, identity start: L(t) = Lc(0)~ o Lc(t)
    a5, w2, tt = np.radians(5.0), 4 * np.pi, result.trajectory.t
    lc0 = SciRotation.from_quat([np.cos(a5 / 2), np.sin(a5 / 2), 0, 0], scalar_first=True)
    lct = SciRotation.from_quat(
        np.stack(
            [np.full_like(tt, np.cos(a5 / 2)), np.sin(a5 / 2) * np.cos(w2 * tt)]
            + [np.sin(a5 / 2) * np.sin(w2 * tt), 0 * tt],
            axis=-1,
        ),
        scalar_first=True,
    )
    truth = lc0.inv() * lct
    for traj in (result.trajectory, result.reference):  # exact, then magnus4
        got = SciRotation.from_quat(traj.quat, scalar_first=True)
        assert (truth.inv() * got).magnitude().max() < 1e-9, traj.method
    assert result.summary["accuracy"]["comparison"]["max_attitude_error_rad"] < 1e-9
    q = result.trajectory.quat
    period = result.summary["results"]["period"]
    k = int(np.argmin(np.abs(result.trajectory.t - period)))
    assert abs(abs(q[k] @ q[0]) - 1.0) < 1e-12  # periodic attitude


def test_constant_profile_exact_matches_rotvec():
    s = parse_scenario(
        '[omega_profile]\nkind = "constant"\nframe = "space"\nvector = [0.0, 90.0, 0.0]\n'
        'units = "deg/s"\n[attitude]\nrotvec = [0.0, 0.0, 90.0]\ndegrees = true\n'
        '[simulation]\nduration = 1.0\nsamples = 3\nmethod = "exact"\nreference = "magnus4"\n'
    )
    result = simulate_scenario(s)
    r = result.trajectory.rotation[-1]
    # 90 deg about space y after 90 deg about z: x_body -> y_space stays y_space
    np.testing.assert_allclose(r.apply([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(r.apply([0.0, 1.0, 0.0]), [0.0, 0.0, 1.0], atol=1e-12)
    assert result.summary["accuracy"]["invariants"] == {}  # no body: no T, no K
    # magnus4 is exact for a constant angular velocity too: the reference trajectory
    # against R(t) = Ry(90 deg t) Rz(90 deg) built here with SciPy
    tt = result.reference.t
    truth = SciRotation.from_rotvec(np.outer(tt, [0.0, np.pi / 2, 0.0])) * SciRotation.from_rotvec(
        [0.0, 0.0, np.pi / 2]
    )
    got = SciRotation.from_quat(result.reference.quat, scalar_first=True)
    assert result.reference.method == "magnus4"
    assert (truth.inv() * got).magnitude().max() < 1e-13
    assert result.summary["accuracy"]["comparison"]["max_attitude_error_rad"] < 1e-13


def test_chunked_run_equals_single_call(monkeypatch):
    """Progress reporting splits long runs into chunks; fixed-step results are unchanged."""
    from poinsot.scenarios import solve as solve_mod

    s = demo_scenario()
    calls = []
    whole = simulate_scenario(s, duration=2.0)
    monkeypatch.setattr(solve_mod, "_CHUNK_SAMPLES", 50)
    chunked = simulate_scenario(s, duration=2.0, progress=lambda f, st: calls.append(f))
    assert chunked.trajectory.info["chunks"] > 1
    np.testing.assert_allclose(chunked.trajectory.quat, whole.trajectory.quat, atol=1e-13)
    np.testing.assert_allclose(chunked.trajectory.omega, whole.trajectory.omega, atol=1e-12)
    assert (
        calls[0] == 0.0
        and calls[-1] == 1.0
        and calls == sorted(calls)  # one sweep over the method and the reference
    )


def test_chunked_joins_any_result_type(monkeypatch):
    """chunked() never assumes a rotation: a PointTrajectory of uniform motion
    r = r0 + v t (closed form) is joined chunk by chunk from the state ``resume``
    gives, and equals one call; without ``resume`` it says what is missing."""
    from poinsot import InvalidTypeError
    from poinsot.scenarios import solve as solve_mod
    from poinsot.trajectory import PointTrajectory

    monkeypatch.setattr(solve_mod, "_CHUNK_SAMPLES", 50)
    t = np.linspace(0.0, 2.0, 201)

    def uniform(r0, v, tt):
        r = np.asarray(r0) + np.outer(tt - tt[0], v)
        return PointTrajectory(tt, r, np.broadcast_to(v, r.shape), "exact")

    r0, v = np.array([1.0, 2.0, 3.0]), np.array([0.5, -1.0, 0.25])
    joined = solve_mod.chunked(
        uniform, r0, v, t, solve_mod.quiet_progress, "moving",
        resume=lambda p: (p.position[-1], p.velocity[-1]),
    )  # fmt: skip
    assert isinstance(joined, PointTrajectory) and joined.info["chunks"] > 1
    np.testing.assert_array_equal(joined.t, t)
    np.testing.assert_allclose(joined.position, r0 + np.outer(t, v), rtol=0, atol=1e-14)
    with pytest.raises(InvalidTypeError, match="resume"):
        solve_mod.chunked(uniform, r0, v, t, solve_mod.quiet_progress, "moving")


def test_npz_output(tmp_path):
    result, files = run_scenario(
        demo_scenario(), tmp_path / "o", fmt="npz", report=False, duration=0.5, figures=False
    )
    with np.load(tmp_path / "o" / "trajectory.npz") as z:
        np.testing.assert_array_equal(z["t"], result.trajectory.t)
        np.testing.assert_array_equal(z["quat"], result.trajectory.quat)
        assert z["omega_body"].shape == (z["t"].size, 3)
        assert z["momentum_space"].shape == (z["t"].size, 3)
        assert "scalar first" in str(z["header"])


def test_output_directory_not_overwritten(tmp_path):
    out = tmp_path / "o"
    run_scenario(demo_scenario(), out, report=False, duration=0.2, figures=False)
    before = (out / "summary.json").read_text()
    with pytest.raises(InvalidInputError, match=r"already exists and is not empty; pass --force"):
        run_scenario(demo_scenario(), out, report=False, duration=0.3, figures=False)
    assert (out / "summary.json").read_text() == before
    run_scenario(demo_scenario(), out, report=False, duration=0.3, force=True, figures=False)
    assert json.loads((out / "summary.json").read_text())["run"]["times"]["duration"] == 0.3
    (tmp_path / "file").write_text("x")
    with pytest.raises(InvalidInputError, match=r"exists and is not a directory"):
        run_scenario(demo_scenario(), tmp_path / "file", report=False, duration=0.2, figures=False)
    with pytest.raises(
        InvalidInputError, match=r"Expected `format` \(--format\) to be 'csv' or 'npz'"
    ):
        run_scenario(demo_scenario(), tmp_path / "p", fmt="xlsx", figures=False)
    with pytest.raises(
        InvalidInputError, match=r"Expected `duration` \(--duration\) to be a positive"
    ):
        simulate_scenario(demo_scenario(), duration=-1.0)


def test_interrupted_write_leaves_no_complete_file(tmp_path, monkeypatch):
    """A failure while writing leaves neither the file nor its temporary."""
    from poinsot.scenarios import output as output_mod

    def boom(fh):
        fh.write("partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        output_mod._atomic(tmp_path / "summary.json", boom)
    assert list(tmp_path.iterdir()) == []


def test_report_written(tmp_path):
    run_scenario(demo_scenario(), tmp_path / "o", duration=0.5, figures=False)
    html = (tmp_path / "o" / "report.html").read_text()
    assert "tennis-racket-flip" in html and '<script src="http' not in html  # offline


def test_free_symmetric_top_regular_precession():
    """A = B: the symmetry axis precesses about the fixed K at psi' = |K| / A (theory §10)."""
    s = parse_scenario(
        "[body]\nmass = 1.0\ninertia = [1.0, 1.0, 1.6]\n"
        '[attitude]\neuler = [0.0, 20.0, 0.0]\nsequence = "ZXZ"\ndegrees = true\n'
        '[angular_velocity]\nvector = [0.3, 0.0, 1.0]\nframe = "body"\n'
        '[simulation]\nduration = 3.0\nsamples = 301\nmethod = "exact"\nreference = "rk4"\n'
        "max_step = 0.002\n"
    )
    result = simulate_scenario(s)
    k_body = np.array([0.3, 0.0, 1.6])
    rate = np.linalg.norm(k_body) / 1.0
    cf = result.summary["results"]
    assert cf["regime"] == "symmetric" and cf["precession_rate"] == pytest.approx(rate)
    tr = result.trajectory
    k = tr.momentum[0] / np.linalg.norm(tr.momentum[0])
    axis = tr.rotation.apply(np.array([0.0, 0.0, 1.0]))
    e1 = np.cross(k, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(k, e1)
    angle = np.unwrap(np.arctan2(axis @ e2, axis @ e1))
    np.testing.assert_allclose(np.diff(angle) / np.diff(tr.t), rate, rtol=1e-9)
    np.testing.assert_allclose(axis @ k, axis[0] @ k, atol=1e-13)  # constant nutation
    assert result.summary["accuracy"]["comparison"]["max_attitude_error_rad"] < 1e-8


def test_a_broken_report_install_skips_the_report_with_a_note(tmp_path, monkeypatch):
    # The report needs only NumPy (its viewer is built in); an ImportError there (a
    # broken install) must cost the report alone, with a note, not the run.
    import poinsot.plotting.report as report

    def broken(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'poinsot.plotting._report_page'")

    monkeypatch.setattr(report, "write_report", broken)
    result, files = run_scenario(demo_scenario(), tmp_path / "o", duration=0.2, figures=False)
    assert "report.html" not in {p.name for p in files}
    notes = json.loads((tmp_path / "o" / "summary.json").read_text())["run"]["notes"]
    assert notes == files.notes
    assert any("report.html skipped: No module named" in n for n in notes)


def test_heavy_top_released_nutation_band_and_period():
    """A top released with spin only (theta' = psi' = 0) nutates between its initial tilt
    and the other root of P(u) with cusps (theory §10); the closed-form band and period
    agree with the adaptive integration of Euler's equations."""
    text = (EXAMPLES / "symmetric_top.toml").read_text()
    text = text.replace("vector = [0.0, 2.25686547819487, 150.0]", "vector = [0.0, 0.0, 40.0]")
    text = text.replace("duration = 3.0", "duration = 0.8").replace("step = 0.0005", "step = 0.002")
    text = text.replace('reference = "splitting"', "")
    result = simulate_scenario(parse_scenario(text))
    cf = result.summary["results"]
    assert cf["motion"] == "cusps"
    tr = result.trajectory
    axis = tr.rotation.apply(np.array([0.0, 0.0, 1.0]))
    tilt = np.arccos(axis[:, 2])
    assert cf["nutation_theta_min"] == pytest.approx(np.radians(30.0), abs=1e-9)
    k = int(np.argmax(tilt[: tilt.size // 2 + 50]))  # first lowest point, half a period
    # parabola through the three samples around the maximum
    y0, y1, y2 = tilt[k - 1 : k + 2]
    d = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    t_max = tr.t[k] + d * (tr.t[1] - tr.t[0])
    theta_max = y1 - 0.25 * (y0 - y2) * d
    assert theta_max == pytest.approx(cf["nutation_theta_max"], rel=1e-5)
    assert 2 * t_max == pytest.approx(cf["nutation_period"], rel=1e-4)
    assert tilt.max() <= cf["nutation_theta_max"] + 1e-9
    assert tilt.min() >= cf["nutation_theta_min"] - 1e-9


def test_write_outputs_rejects_unknown_format(tmp_path):
    from poinsot.scenarios import write_outputs

    result = simulate_scenario(demo_scenario(), duration=0.1)
    with pytest.raises(
        InvalidInputError, match=r"Expected `format` \(--format\) to be 'csv' or 'npz'"
    ):
        write_outputs(result, tmp_path / "o", fmt="xml")
    assert not (tmp_path / "o").exists()


def test_missing_matplotlib_skips_figures_with_note(tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import fails
    result, files = run_scenario(demo_scenario(), tmp_path / "o", report=False, duration=0.1)
    assert {p.name for p in files} == {
        "trajectory.csv",
        "trajectory.columns.json",
        "reference.csv",
        "reference.columns.json",
        "summary.json",
    }
    assert any("figures skipped: matplotlib is not installed" in n for n in files.notes)
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["run"]["notes"] == files.notes


def test_duration_override_beyond_the_table_is_refused():
    s = load_scenario(EXAMPLES / "attitude_propagation.toml")
    with pytest.raises(
        InvalidInputError, match=r"at most the last time of \[omega_profile\] t \(10 s\)"
    ):
        simulate_scenario(s, duration=11.0)


def test_forced_rerun_removes_stale_outputs_only(tmp_path):
    out = tmp_path / "o"
    run_scenario(demo_scenario(), out, report=False, duration=0.2)  # csv, figures
    (out / "notes.txt").write_text("mine")
    run_scenario(
        demo_scenario(), out, fmt="npz", report=False, figures=False, duration=0.2, force=True
    )
    names = {p.name for p in out.iterdir()}
    assert names == {"trajectory.npz", "reference.npz", "summary.json", "notes.txt"}
