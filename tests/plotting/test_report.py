"""Tests of the self-contained HTML report (poinsot.plotting.report).

The trajectory is the closed-form regular precession of a free symmetric body
(SPEC S10: ``psi' = K/A``, ``phi' = (A - C) r / A``, ``cos theta = C r / K``),
built with SciPy's Rotation as an independent oracle. The geometry drawn in the
3-D scene is checked against that oracle and against the Poinsot construction
(SPEC S8, S10): the polhode lies on the inertia ellipsoid ``r^T J r = 1`` and the
herpolhode in the invariable plane at distance ``sqrt(2T)/|K|``.
"""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot

import poinsot
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.plotting import report
from poinsot.plotting.report import write_report

pytest.importorskip("plotly")

A_, C_, K_, THETA = 2.0, 1.0, 1.0, 0.6


def precession(n=120, t1=20.0, *, invariants=True, rot0=None, scale=1.0):
    """Regular precession of a symmetric free body about space z (closed form).

    ``scale`` multiplies the moments of inertia (|K| stays K_)."""
    A, C = A_ * scale, C_ * scale
    t = np.linspace(0.0, t1, n)
    r = K_ * np.cos(THETA) / C
    psid, phid = K_ / A, (A - C) * r / A
    psi, phi = psid * t, 0.3 + phid * t
    sci = SciRot.from_euler("ZXZ", np.column_stack([psi, np.full(n, THETA), phi]))
    if rot0 is not None:
        sci = rot0 * sci
    st = np.sin(THETA)
    w = np.column_stack(
        [psid * st * np.sin(phi), psid * st * np.cos(phi), np.full(n, psid * np.cos(THETA) + phid)]
    )
    J = np.diag([A, A, C])
    kw = {}
    if invariants:
        kw = {
            "energy": 0.5 * np.einsum("ni,ij,nj->n", w, J, w),
            "momentum": sci.apply(w @ J),
        }
    rot = poinsot.Rotation.from_quat(sci.as_quat(scalar_first=True))
    return poinsot.Trajectory(t, rot, w, "closed form", **kw), sci, J


def _frame_traces(fig, f):
    """{trace name: frame trace} for animation frame f (names from the base traces)."""
    fr = fig.frames[f]
    out = {}
    for idx, tr in zip(fr.traces, fr.data, strict=True):
        out.setdefault(fig.data[idx].name, []).append(tr)
    return out


def _xyz(tr):
    return np.column_stack(
        [np.asarray(tr.x, float), np.asarray(tr.y, float), np.asarray(tr.z, float)]
    )


def _frame_time(fig, f):
    """The time cursor's x value in frame f (the cursor traces have no name)."""
    return float(_frame_traces(fig, f)[None][0].x[0])


@pytest.fixture(scope="module")
def prec():
    return precession()


def test_oracle_is_a_free_motion(prec):
    """The fixture itself: K constant along space z with |K| = K_ (SPEC S10)."""
    tr, _, _ = prec
    np.testing.assert_allclose(tr.momentum, np.tile([0.0, 0.0, K_], (tr.t.size, 1)), atol=1e-12)


def test_page_is_self_contained(tmp_path, prec):
    tr, _, J = prec
    out = write_report(tmp_path / "report.html", trajectory=tr, summary={"a": 1}, inertia=J)
    text = out.read_text(encoding="utf-8")
    import plotly.offline

    head = plotly.offline.get_plotlyjs()[:60]
    assert text.count(head) == 1  # plotly.js inlined exactly once
    assert not re.search(r"<script[^>]*\bsrc\s*=", text)  # nothing fetched
    assert not re.search(r"<link[^>]*\bhref\s*=\s*[\"']?https?:", text)
    assert 'id="poinsot-figure"' in text
    assert out.stat().st_size < 10_000_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.html"]  # no temp left


def test_frames_bounded_and_slider_matches(prec):
    tr, _, J = prec
    fig = report._figure(tr, None, None, J, 25)
    steps = fig.layout.sliders[0].steps
    assert 2 <= len(fig.frames) <= 25
    assert len(steps) == len(fig.frames)
    assert [s.args[0][0] for s in steps] == [f.name for f in fig.frames]
    times = [_frame_time(fig, f) for f in range(len(fig.frames))]
    assert np.all(np.diff(times) > 0)
    assert times[0] == pytest.approx(tr.t[0]) and times[-1] == pytest.approx(tr.t[-1], rel=1e-6)
    labels = [float(s.label) for s in steps]
    np.testing.assert_allclose(labels, times, rtol=1e-2, atol=1e-9)  # rounded labels: 4e-4
    play = fig.layout.updatemenus[0].buttons[0]
    assert play.method == "animate" and play.args[1]["frame"]["redraw"] is True


def test_fewer_samples_than_frames(prec):
    tr, _, J = precession(n=7)
    fig = report._figure(tr, None, None, J, 150)
    assert len(fig.frames) == 7


def test_body_axes_follow_the_rotation(prec):
    """Axis lines end along the columns of the body -> space matrix (SciPy oracle)."""
    tr, sci, J = prec
    fig = report._figure(tr, None, None, J, 12)
    for f in range(len(fig.frames)):
        k = int(np.argmin(np.abs(tr.t - _frame_time(fig, f))))
        M = sci[k].as_matrix()
        traces = _frame_traces(fig, f)
        for a, lab in enumerate("xyz"):
            end = _xyz(traces[f"body {lab} axis"][0])[1]
            np.testing.assert_allclose(end / np.linalg.norm(end), M[:, a], atol=1e-4)


@pytest.mark.parametrize("scale", [1.0, 1e-4])
def test_polhode_on_ellipsoid_and_herpolhode_in_invariable_plane(scale):
    """Poinsot (S8, S10): the polhode lies on the drawn inertia ellipsoid, the herpolhode
    in the invariable plane normal to K at distance s sqrt(2T)/|K| (s: the drawing scale,
    which makes the longest semi-axis 1 whatever the units of J)."""
    tr, sci, J = precession(scale=scale)
    fig = report._figure(tr, None, None, J, 10)
    s = np.sqrt(np.min(np.diag(J)))  # longest semi-axis 1/sqrt(min moment) drawn as 1
    mesh = sci[0].apply(_xyz(fig.data[0]), inverse=True)
    assert np.max(np.linalg.norm(mesh, axis=1)) == pytest.approx(1.0, rel=0.02)
    np.testing.assert_allclose(np.einsum("ni,ij,nj->n", mesh, J, mesh), s**2, rtol=2e-5)
    T = tr.energy[0]
    dist = s * np.sqrt(2 * T) / K_
    for f in (0, 4, len(fig.frames) - 1):
        k = int(np.argmin(np.abs(tr.t - _frame_time(fig, f))))
        traces = _frame_traces(fig, f)
        p_space = _xyz(traces["polhode (on the ellipsoid)"][0])
        p_body = sci[k].apply(p_space, inverse=True)
        np.testing.assert_allclose(np.einsum("ni,ij,nj->n", p_body, J, p_body), s**2, rtol=2e-5)
        her = _xyz(traces["herpolhode (space)"][0])
        np.testing.assert_allclose(her[:, 2], dist, rtol=2e-4)  # K along space z (3.4e-6 seen)
        assert len(her) >= 1


def test_herpolhode_grows_with_time(prec):
    tr, _, J = prec
    fig = report._figure(tr, None, None, J, 10)
    sizes = [len(_frame_traces(fig, f)["herpolhode (space)"][0].x) for f in range(10)]
    assert sizes[0] == 1 and all(b >= a for a, b in zip(sizes, sizes[1:], strict=False))
    assert sizes[-1] > 50


def test_inertia_ellipsoid_mesh_general_tensor(prec):
    """Mesh: the ellipsoid r^T J r = 1 (SPEC S8) for a non-diagonal tensor, scaled so that
    its longest semi-axis (along the principal axis of the smallest moment) is 1."""
    tr, sci, _ = prec
    S = SciRot.from_rotvec([0.3, -0.5, 0.7]).as_matrix()
    J = S @ np.diag([3.0, 4.0, 5.0]) @ S.T
    fig = report._figure(tr, None, None, J, 5)
    for f in (0, 3):
        k = int(np.argmin(np.abs(tr.t - _frame_time(fig, f))))
        traces = _frame_traces(fig, f)
        v = sci[k].apply(_xyz(traces["inertia ellipsoid (scaled)"][0]), inverse=True)
        np.testing.assert_allclose(np.einsum("ni,ij,nj->n", v, J, v), 3.0, rtol=2e-5)
    v0 = sci[0].apply(_xyz(fig.data[0]), inverse=True)
    far = v0[np.argmax(np.linalg.norm(v0, axis=1))]
    assert np.linalg.norm(far) == pytest.approx(1.0, rel=0.02)
    assert abs(far @ S[:, 0]) == pytest.approx(1.0, rel=0.02)


@pytest.mark.parametrize(
    ("kind", "dims", "extent"),
    [
        ("box", [1.0, 0.6, 0.2], [0.5, 0.3, 0.1]),
        ("ellipsoid", [0.9, 0.5, 0.3], [0.9, 0.5, 0.3]),
        ("sphere", [0.4], [0.4, 0.4, 0.4]),
        ("cylinder", [0.25, 1.2], [0.25, 0.25, 0.6]),
    ],
)
def test_shapes_have_their_dimensions(prec, kind, dims, extent):
    tr, sci, _ = prec
    body = report._check_shape({"kind": kind, "dims": dims})
    fig = report._figure(tr, None, body, None, 5)
    assert fig.data[0].name == f"body ({kind})"
    v = sci[0].apply(_xyz(fig.data[0]), inverse=True)
    np.testing.assert_allclose(np.max(np.abs(v), axis=0), extent, rtol=2e-5)
    if kind == "box":
        np.testing.assert_allclose(np.sort(np.abs(v), axis=0), np.tile(extent, (8, 1)), rtol=2e-5)


def test_vectors_parallel_to_omega_and_momentum(prec):
    tr, sci, J = prec
    fig = report._figure(tr, None, None, J, 8)
    for f in range(8):
        k = int(np.argmin(np.abs(tr.t - _frame_time(fig, f))))
        traces = _frame_traces(fig, f)
        w_end = _xyz(traces["w (scaled)"][0])[1]
        w_s = sci[k].apply(np.array(tr.omega[k]))
        np.testing.assert_allclose(
            w_end / np.linalg.norm(w_end), w_s / np.linalg.norm(w_s), atol=1e-4
        )
        K_end = _xyz(traces["K (scaled)"][0])[1]
        np.testing.assert_allclose(K_end / np.linalg.norm(K_end), [0, 0, 1], atol=1e-4)


def test_without_inertia_or_invariants(prec):
    tr, _, _ = precession(invariants=False)
    fig = report._figure(tr, None, None, None, 5)
    names = {d.name for d in fig.data}
    assert "body (inertia not given: unit sphere)" in names
    assert "K (scaled)" not in names and "polhode (w tip, body-fixed)" in names
    assert any("no invariants recorded" in a.text for a in fig.layout.annotations)


def test_reference_attitude_error_is_the_known_offset():
    """Reference = fixed space rotation by alpha about z applied to the motion: error = alpha."""
    alpha = 0.37
    tr, _, J = precession()
    ref, _, _ = precession(rot0=SciRot.from_rotvec([0.0, 0.0, alpha]))
    fig = report._figure(tr, ref, None, J, 6)
    err = next(d for d in fig.data if d.name == "attitude error")
    np.testing.assert_allclose(np.asarray(err.y, float), alpha, atol=1e-5)
    names = [d.name for d in fig.data]
    assert "reference axes" in names and "reference w" in names
    assert len(fig.layout.sliders[0].steps) == 6


def test_reference_on_other_times_has_no_error_plot():
    tr, _, J = precession(n=50)
    ref, _, _ = precession(n=77)
    fig = report._figure(tr, ref, None, J, 6)
    names = [d.name for d in fig.data]
    assert "attitude error" not in names and "reference w" in names


def test_summary_table_flattens_and_escapes(tmp_path, prec):
    tr, _, J = prec
    summary = {
        "method": "<script>alert(1)</script>",
        "drift": {"energy": 1.234567891e-15, "momentum": 0.5},
        "periods": [1.0, 2.5],
        "flag": True,
        "nothing": None,
    }
    text = write_report(tmp_path / "r.html", trajectory=tr, summary=summary, inertia=J).read_text()
    table = text[text.index('<table class="summary">') :]
    assert "<script>alert" not in table and "&lt;script&gt;alert(1)&lt;/script&gt;" in table
    assert "<th>drift.energy</th><td>1.23457e-15</td>" in table
    assert "<th>drift.momentum</th><td>0.5</td>" in table
    assert "<th>periods</th><td>[1, 2.5]</td>" in table
    assert "<th>flag</th><td>True</td>" in table and "<th>nothing</th><td>None</td>" in table


def test_no_summary_no_table(tmp_path, prec):
    tr, _, _ = prec
    text = write_report(tmp_path / "r.html", trajectory=tr, title="A & B").read_text()
    assert '<table class="summary">' not in text and "<title>A &amp; B</title>" in text


def test_write_replaces_existing_file(tmp_path, prec):
    tr, _, _ = prec
    p = tmp_path / "report.html"
    p.write_text("old")
    write_report(str(p), trajectory=tr, max_frames=3)
    assert p.read_text().startswith("<!DOCTYPE html>")


def test_interrupted_write_keeps_old_file(tmp_path, prec, monkeypatch):
    tr, _, _ = prec
    p = tmp_path / "report.html"
    p.write_text("old")

    def boom(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(report.os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        write_report(p, trajectory=tr, max_frames=3)
    assert p.read_text() == "old"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["report.html"]


def test_import_does_not_load_plotly():
    code = (
        "import sys, poinsot.plotting.report; "
        "assert 'plotly' not in sys.modules, sorted(m for m in sys.modules if 'plotly' in m)"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


# ----------------------------------------------------------------- errors


def test_errors_trajectory(tmp_path, prec):
    tr, sci, _ = prec
    p = tmp_path / "r.html"
    with pytest.raises(InvalidTypeError, match="Expected `trajectory` to be a poinsot.Trajectory"):
        write_report(p, trajectory=np.zeros((3, 4)))
    with pytest.raises(InvalidTypeError, match="Expected `reference` to be a poinsot.Trajectory"):
        write_report(p, trajectory=tr, reference="exact")
    q = np.stack([sci.as_quat(scalar_first=True)] * 2, axis=1)
    batch = poinsot.Trajectory(
        tr.t, poinsot.Rotation.from_quat(q), np.stack([tr.omega] * 2, 1), "batch"
    )
    with pytest.raises(InvalidInputError, match="Expected `trajectory` to hold one body"):
        write_report(p, trajectory=batch)
    assert not p.exists()


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"summary": [1, 2]}, InvalidTypeError, "Expected `summary` to be a mapping"),
        ({"title": 3}, InvalidTypeError, "Expected `title` to be a string"),
        ({"max_frames": 2.5}, InvalidTypeError, "Expected `max_frames` to be an integer"),
        ({"max_frames": True}, InvalidTypeError, "Expected `max_frames` to be an integer"),
        ({"max_frames": 1}, InvalidInputError, r"Expected `max_frames` to be in \[2, 1000\]"),
        ({"max_frames": 5000}, InvalidInputError, r"Expected `max_frames` to be in \[2, 1000\]"),
        ({"shape": "box"}, InvalidTypeError, "Expected `shape` to be a mapping"),
        ({"shape": {"kind": "box"}}, InvalidInputError, "exactly the keys 'kind' and 'dims'"),
        (
            {"shape": {"kind": "box", "dims": [1, 1, 1], "mass": 2}},
            InvalidInputError,
            "exactly the keys 'kind' and 'dims'",
        ),
        (
            {"shape": {"kind": "cone", "dims": [1, 1]}},
            InvalidInputError,
            r"Expected `shape\['kind'\]` to be one of 'box'",
        ),
        (
            {"shape": {"kind": "box", "dims": [1, 2]}},
            InvalidInputError,
            r"Expected `shape\['dims'\]` for a box to have shape \(3,\)",
        ),
        (
            {"shape": {"kind": "sphere", "dims": -1.0}},
            InvalidInputError,
            r"Expected `shape\['dims'\]` to be positive",
        ),
        (
            {"shape": {"kind": "box", "dims": ["a", 1, 1]}},
            InvalidTypeError,
            r"Expected `shape\['dims'\]` to be array-like",
        ),
        ({"inertia": [1.0, 2.0]}, InvalidInputError, r"Expected `inertia` to have shape \(3,\)"),
        (
            {"inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]},
            InvalidInputError,
            "Expected `inertia` to be a symmetric matrix",
        ),
        ({"inertia": [1.0, -2.0, 3.0]}, InvalidInputError, "to be positive definite"),
        ({"inertia": [1.0, np.nan, 3.0]}, InvalidInputError, "only finite values"),
    ],
)
def test_errors_arguments(tmp_path, prec, kwargs, exc, match):
    tr, _, _ = prec
    with pytest.raises(exc, match=match):
        write_report(tmp_path / "r.html", trajectory=tr, **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_errors_missing_directory(tmp_path, prec):
    tr, _, _ = prec
    with pytest.raises(InvalidInputError, match="Expected the directory of `path` to exist"):
        write_report(tmp_path / "nope" / "r.html", trajectory=tr)


def test_long_runs_keep_the_page_small():
    """20001 samples: time series cut to a min/max envelope, tracks and frames bounded."""
    tr, _, J = precession(n=20001, t1=200.0)
    fig = report._figure(tr, None, None, J, 150)
    w1 = next(d for d in fig.data if d.name == "w1 (x)")
    assert len(w1.x) <= report._MAX_SERIES + 2
    y = np.asarray(w1.y, float)
    assert y.max() == pytest.approx(tr.omega[:, 0].max(), rel=1e-6)  # envelope kept
    assert y.min() == pytest.approx(tr.omega[:, 0].min(), rel=1e-6)
    assert np.all(np.diff(np.asarray(w1.x, float)) > 0)
    assert len(fig.frames) == 150
    assert len(_frame_traces(fig, 149)["polhode (on the ellipsoid)"][0].x) <= report._MAX_TRACK + 2
