"""Tests of the self-contained HTML report (poinsot.plotting.report).

The trajectory is the closed-form regular precession of a free symmetric body
(docs/theory.md §10: ``psi' = K/A``, ``phi' = (A - C) r / A``, ``cos theta = C r / K``),
built with SciPy's Rotation as an independent oracle. The page's data (the
animation frames, the meshes the browser turns, the charts) is decoded from the
HTML and checked against that oracle and the Poinsot construction (theory §8,
§10): the polhode lies on the inertia ellipsoid ``r^T J r = s^2`` and the
herpolhode in the invariable plane at distance ``s sqrt(2T)/|K|``. The viewer
itself (drawing, interaction) is tested in tests/browser/test_report_browser.py.
"""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot

import poinsot
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.plotting import report
from poinsot.plotting.report import write_report
from poinsot.scenarios.report import write_scenario_report

A_, C_, K_, THETA = 2.0, 1.0, 1.0, 0.6


def precession(n=120, t1=20.0, *, invariants=True, rot0=None, scale=1.0, spin=None):
    """Regular precession of a symmetric free body about space z (closed form).

    ``scale`` multiplies the moments of inertia (|K| stays K_); ``spin`` sets
    ``phi'`` directly (a kinematic fast spin, for the frame choice)."""
    A, C = A_ * scale, C_ * scale
    t = np.linspace(0.0, t1, n)
    r = K_ * np.cos(THETA) / C
    psid, phid = K_ / A, (A - C) * r / A
    if spin is not None:
        phid = spin
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


def _f32(s):
    return np.frombuffer(base64.b64decode(s), dtype="<f4").astype(float)


def _page(path):
    """(payload, text) of a written report: the JSON data block decoded."""
    text = path.read_text(encoding="utf-8")
    m = re.search(r'<script type="application/json" id="poinsot-data">(.*?)</script>', text, re.S)
    assert m is not None
    return json.loads(m.group(1)), text


def _u32(s):
    return np.frombuffer(base64.b64decode(s), dtype="<u4").astype(np.int64)


def _layers(P):
    """The scene's layers (drawn by the page), by name."""
    return {} if P["scene"] is None else {d["name"]: d for d in P["scene"]["layers"]}


def _series(P):
    """Every chart series, by name: (series, its panel)."""
    return {s["name"]: (s, p) for p in P["panels"] for s in p["series"]}


def _titles(P):
    return [p["title"] for p in P["panels"]]


def _named(P, prefix):
    """The one scene layer whose name starts with ``prefix``."""
    hits = [v for k, v in _layers(P).items() if k.startswith(prefix)]
    assert len(hits) == 1, (prefix, list(_layers(P)))
    return hits[0]


def _named_series(P, prefix):
    """(x, y) of the one series named ``prefix`` (or starting with ``prefix: ``)."""
    hits = [v for k, (v, _) in _series(P).items() if k == prefix or k.startswith(prefix + ":")]
    assert len(hits) == 1, (prefix, list(_series(P)))
    return _f32(hits[0]["x"]), _f32(hits[0]["y"])


def _write(tmp_path, tr, name="r.html", **kw):
    return _page(write_report(tmp_path / name, trajectory=tr, **kw))


@pytest.fixture(scope="module")
def prec():
    return precession()


@pytest.fixture(scope="module")
def page(prec, tmp_path_factory):
    tr, sci, J = prec
    return _write(tmp_path_factory.mktemp("rep"), tr, inertia=J, mass=3.0, summary={"a": 1})


def test_oracle_is_a_free_motion(prec):
    tr, _, _ = prec
    assert np.ptp(tr.energy) < 1e-12 and np.ptp(np.linalg.norm(tr.momentum, axis=-1)) < 1e-12
    np.testing.assert_allclose(tr.momentum, np.tile(tr.momentum[0], (tr.t.size, 1)), atol=1e-12)


def test_page_is_self_contained_and_small(page):
    """One inline viewer script and one data block: no library, no URL, no fetch."""
    P, text = page
    from poinsot.plotting._report_page import viewer_js

    js = viewer_js()
    assert text.count("<script") == 2 and text.count(js) == 1
    assert "</script" not in js and "<script src=" not in text
    assert not re.search(r"https?://(?!www\.w3\.org/2000/svg)", text)  # only the SVG namespace
    for word in ("plotly", "fetch(", "XMLHttpRequest", "import("):
        assert word not in text, word
    assert len(text) < 150_000  # was 2.0-2.3 MB with plotly.js, 6.6-7.3 MB before that


def test_frames_match_the_oracle(prec, page):
    tr, sci, _ = prec
    P, _ = page
    t = _f32(P["t"])
    q = _f32(P["q"]).reshape(-1, 4)
    assert t[0] == 0.0 and t[-1] == pytest.approx(tr.t[-1], rel=1e-6)
    assert np.all(np.diff(t) > 0) and 2 <= t.size <= tr.t.size
    k = np.searchsorted(tr.t, t - 1e-5)
    ref = sci[k].as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.einsum("ni,ni->n", q, ref)), 1.0, atol=1e-6)


def test_fast_spin_does_not_strobe(tmp_path):
    """171-176 deg per frame was seen: frames are added so the turn stays <= 20 deg."""
    tr, sci, J = precession(n=6001, t1=3.0, spin=100.0)  # 2.9 deg per sample
    P, text = _write(tmp_path, tr, inertia=J)
    q = _f32(P["q"]).reshape(-1, 4)
    turn = SciRot.from_quat(q[:-1], scalar_first=True).inv() * SciRot.from_quat(
        q[1:], scalar_first=True
    )
    assert np.degrees(turn.magnitude()).max() <= 20.0 + 1e-3
    assert "turns at most" in text
    P2, text2 = _write(tmp_path, tr, "r2.html", inertia=J, max_frames=100)
    assert "may appear to strobe" in text2 and "limited to 100" in text2


def test_body_mesh_and_axes_are_in_body_axes(prec, page):
    """The page turns body-axes geometry by the frame quaternions (tested above): the
    mesh is a closed surface of the body, the axes are the body's x, y, z."""
    tr, sci, J = prec
    P, _ = page
    a = _named(P, "body: ellipsoid")
    assert a["type"] == "mesh" and a["frame"] == "body" and a["opacity"] == 1.0
    v_body = _f32(a["v"]).reshape(-1, 3)
    f = _u32(a["f"]).reshape(-1, 3)
    assert f.min() == 0 and f.max() == len(v_body) - 1 and len(f) >= 100
    for lab, col in zip("xyz", range(3), strict=True):
        a = _named(P, f"body {lab} axis")
        e = np.asarray(a["b"])
        assert a["frame"] == "body" and np.count_nonzero(e) == 1 and e[col] > 0
    assert P["scene"]["unit"] == "m"
    ell = _named(P, "inertia ellipsoid")
    assert ell["visible"] is False and ell["opacity"] < 1  # an optional layer, off at first


def test_equivalent_ellipsoid_has_the_mass_and_inertia(page):
    """The drawn solid is the uniform ellipsoid with J: A = m (b^2 + c^2) / 5."""
    P, _ = page
    a = _named(P, "body: ellipsoid")
    v = _f32(a["v"]).reshape(-1, 3)
    semi = np.abs(v).max(axis=0)
    m = 3.0
    moments = (
        m
        / 5
        * np.array(
            [semi[1] ** 2 + semi[2] ** 2, semi[0] ** 2 + semi[2] ** 2, semi[0] ** 2 + semi[1] ** 2]
        )
    )
    np.testing.assert_allclose(moments, [A_, A_, C_], rtol=1e-5)


def test_polhode_on_ellipsoid_and_herpolhode_in_invariable_plane(prec, page):
    tr, sci, J = prec
    P, _ = page
    a = _named(P, "polhode")
    assert a["frame"] == "body"
    pol = _f32(a["v"]).reshape(-1, 3)
    q = np.einsum("ni,ij,nj->n", pol, J, pol)
    np.testing.assert_allclose(q, q[0], rtol=1e-5)  # on r^T J r = s^2
    s = np.sqrt(q[0])
    a = _named(P, "herpolhode")
    assert a["frame"] == "space"
    her = _f32(a["v"]).reshape(-1, 3)
    dist = s * np.sqrt(2 * tr.energy[0]) / K_  # distance of the invariable plane (K along z)
    np.testing.assert_allclose(her[:, 2], dist, rtol=1e-5)
    upto = np.asarray(a["upto"])
    assert np.all(np.diff(upto) >= 0) and upto[-1] == len(her)


def test_vectors_parallel_to_omega_and_momentum(prec, page):
    tr, sci, _ = prec
    P, _ = page
    t = _f32(P["t"])
    k = np.searchsorted(tr.t, t - 1e-5)
    for prefix, truth in (
        ("w, angular", sci[k].apply(tr.omega[k])),
        ("K, angular", tr.momentum[k]),
    ):
        a = _named(P, prefix)
        v = _f32(a["v"]).reshape(-1, 3)
        c = np.linalg.norm(v, axis=-1) / np.linalg.norm(truth, axis=-1)
        np.testing.assert_allclose(c, c[0], rtol=1e-5)  # one scale for the animation
        np.testing.assert_allclose(v / c[:, None], truth, atol=1e-5)
        stated = float(re.search(r"= ([0-9.e+-]+) m\)", a["name"]).group(1))
        assert stated == pytest.approx(c[0], rel=1e-3)  # the scale written in the legend


@pytest.mark.parametrize(
    ("kind", "dims", "extent"),
    [
        ("box", [1.0, 0.6, 0.2], [0.5, 0.3, 0.1]),
        ("ellipsoid", [0.5, 0.3, 0.2], [0.5, 0.3, 0.2]),
        ("sphere", [0.4], [0.4, 0.4, 0.4]),
        ("cylinder", [0.3, 1.0], [0.3, 0.3, 0.5]),
        ("cone", [0.3, 1.0], [0.3, 0.3, 0.75]),
        ("disc", [0.3], [0.3, 0.3, 0.3 / 40]),
        ("rod", [1.0], [1.0 / 60, 1.0 / 60, 0.5]),
    ],
)
def test_shapes_have_their_dimensions(tmp_path, prec, kind, dims, extent):
    tr, _, _ = prec
    com = np.array([0.0, 0.0, 0.2])
    P, _ = _write(tmp_path, tr, shape={"kind": kind, "dims": dims, "center": com}, fixed_point=True)
    a = _named(P, f"body: {kind}")
    assert a["type"] == "mesh"
    v = _f32(a["v"]).reshape(-1, 3) - com
    np.testing.assert_allclose(np.abs(v).max(axis=0), extent, rtol=2e-3, atol=1e-7)
    if kind == "cone":  # centre of mass h/4 above the base
        assert v[:, 2].min() == pytest.approx(-0.25, rel=1e-5)
    d = _named(P, "fixed point")
    assert d["p"] == [0.0, 0.0, 0.0] and d["type"] == "marker"
    assert P["scene"]["unit"] == "m"  # the viewer titles the axes "x (m)", "y (m)", "z (m)"
    lo, hi = np.asarray(P["scene"]["lo"]), np.asarray(P["scene"]["hi"])
    assert np.all(lo <= v.min(axis=0) + com) and np.all(hi >= v.max(axis=0) + com)


def test_turned_part_is_drawn_along_its_inertia_axes(tmp_path, prec):
    from poinsot.mass import solids
    from poinsot.plotting import _report_shapes as sh

    canon = np.asarray(solids.cylinder(1.0, 0.02, 0.5))
    R = SciRot.from_rotvec([0.0, np.pi / 2, 0.0]).as_matrix()  # axis along body x
    axes = sh.axes_from_inertia(canon, R @ canon @ R.T)
    np.testing.assert_allclose(axes @ canon @ axes.T, R @ canon @ R.T, atol=1e-12)
    assert np.linalg.det(axes) == pytest.approx(1.0)
    tr, _, _ = prec
    P, _ = _write(
        tmp_path,
        tr,
        shape=[
            {"kind": "cylinder", "dims": [0.02, 0.5], "axes": axes},
            {"kind": "point", "dims": [0], "center": [0.3, 0, 0]},
        ],
    )
    a = _named(P, "body: cylinder, point")
    v = _f32(a["v"]).reshape(-1, 3)
    assert v[:, 0].min() == pytest.approx(-0.25, rel=1e-5)  # the handle lies along x


def test_panels_free_body(page):
    P, _ = page
    titles = _titles(P)
    assert any(t.startswith("angular velocity") for t in titles)
    assert any(t.startswith("attitude: Euler angles ZYX") for t in titles)
    # no checks given: no invariant panel; no torque panel
    assert not any("torque" in t or "conserved" in t for t in titles)


def test_panels_from_checks_state_round_off(tmp_path, prec):
    from poinsot.scenarios import Check

    tr, _, J = prec
    ks = Check("momentum_vector", "K (space axes)", "kg m^2/s", tr.momentum)
    en = Check("energy", "kinetic energy T", "J", tr.energy * (1 + 1e-15 * np.sin(tr.t)))
    tq = Check("torque_free", "T (reported)", "J", tr.energy, conserved=False)
    law = Check(
        "law", "T vs closed form", "J", tr.energy * (1 + 1e-9), expected=tr.energy, conserved=False
    )
    P, _ = _write(tmp_path, tr, inertia=J, checks=[ks, en, tq, law])
    titles = _titles(P)
    cons = next(t for t in titles if t.startswith("conserved quantities"))
    assert "round-off only" in cons
    names = list(_series(P))
    assert any(re.match(r"kinetic energy T: max [0-9.]+e-1[56]$", n) for n in names), names
    assert any(t.startswith("T (reported)") for t in titles)
    assert "deviation from the known law (relative)" in titles
    assert any(re.match(r"T vs closed form: max 1e-9$", n) for n in names), names
    # an integrator's slow drift of 1e-11 is not round-off
    slow = Check("energy", "kinetic energy T", "J", tr.energy * (1 + 1e-11 * tr.t / tr.t[-1]))
    P2, _ = _write(tmp_path, tr, "r2.html", inertia=J, checks=[slow])
    cons = next(t for t in _titles(P2) if t.startswith("conserved quantities"))
    assert cons.startswith("conserved quantities: relative change (drift, max 1e-11")
    _, dev = _named_series(P, "T vs closed form")
    np.testing.assert_allclose(dev, 1e-9, rtol=1e-5)
    ylabels = [p["ytitle"] for p in P["panels"]]
    assert "(J)" in ylabels and "(relative)" in ylabels


def test_torqued_panels_energy_balance(tmp_path):
    """A constant body torque about z on a body spinning about z: T' = N . w."""
    t = np.linspace(0.0, 2.0, 201)
    Jz, N = 2.0, 0.5
    wz = 1.0 + N / Jz * t
    rot = poinsot.Rotation.from_rotvec(np.outer(t + N / (2 * Jz) * t**2, [0, 0, 1.0]))
    w = np.column_stack([np.zeros_like(t), np.zeros_like(t), wz])
    tr = poinsot.Trajectory(
        t,
        rot,
        w,
        "exact",
        energy=0.5 * Jz * wz**2,
        momentum=np.column_stack([0 * t, 0 * t, Jz * wz]),
    )
    torque = np.tile([0.0, 0.0, N], (t.size, 1))
    P, _ = _write(tmp_path, tr, inertia=[1.0, 1.5, Jz], torque=torque, free_body=False)
    assert not any(k.startswith("polhode") for k in _layers(P))
    dT, work = _named_series(P, "T(t) - T(0)")[1], _named_series(P, "int N . w dt")[1]
    np.testing.assert_allclose(work, dT, atol=1e-4 * dT.max())
    assert _named_series(P, "Nz")[1].max() == pytest.approx(N)


def test_particle_path(tmp_path):
    t = np.linspace(0.0, 6.0, 301)
    pos = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    tr = poinsot.Trajectory(
        t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x", position=pos
    )
    P, _ = _write(tmp_path, tr)
    a = _named(P, "position")
    np.testing.assert_allclose(np.linalg.norm(_f32(a["v"]).reshape(-1, 3), axis=-1), 1.0, rtol=1e-6)
    assert "whole path" in _layers(P) and not any(n.startswith("w1") for n in _series(P))
    assert not any(k.startswith("body") for k in _layers(P))
    # the path is drawn up to the frame's time: its last point at each frame is the
    # frame's own position (the trail holds every frame sample)
    trail = _named(P, "path up to the frame's time")
    v, tt = _f32(trail["v"]).reshape(-1, 3), _f32(trail["tt"])
    upto = np.asarray(trail["upto"])
    frames_t = _f32(P["t"])
    np.testing.assert_allclose(tt[upto - 1], frames_t - frames_t[0], atol=1e-6)
    np.testing.assert_allclose(v[upto - 1], _f32(a["v"]).reshape(-1, 3), atol=1e-6)
    assert np.all(np.diff(upto) > 0) and upto[-1] == len(tt)


def test_particle_frames_follow_the_motion_period(tmp_path):
    """A swing of period 2 s over 40 s sampled every 0.01 s: frames at most P/24 apart
    (the period is estimated from the velocity's sign changes), not 121 even frames."""
    from poinsot.plotting.report import _time_scale

    period = 2.0
    t = np.linspace(0.0, 40.0, 4001)
    pos = np.column_stack([np.cos(2 * np.pi * t / period), 0 * t, 0.01 * np.sin(np.pi * t)])
    assert _time_scale(t, [pos]) == pytest.approx(period, rel=0.01)
    tr = poinsot.Trajectory(
        t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x", position=pos
    )
    P, text = _write(tmp_path, tr)
    frames_t = _f32(P["t"])
    assert np.max(np.diff(frames_t)) <= period / 24 + 1e-6
    assert frames_t.size >= 40.0 / period * 24
    assert "per period of the motion (2 s" in text
    # a motion that never turns back: frames even in time (the rigid body's 121 minimum)
    line = np.column_stack([t, 0 * t, 0 * t])
    tr = poinsot.Trajectory(
        t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x", position=line
    )
    assert _time_scale(t, [line]) is None
    P, text = _write(tmp_path, tr, name="s.html")
    gaps = np.diff(_f32(P["t"]))[:-1]
    assert 120 <= gaps.size + 2 <= 125 and np.ptp(gaps) < 0.011 and "even in time" in text


def test_drawing_points_links_trails_and_guides(tmp_path):
    """A pendulum drawn by points: one rig layer with the points at each frame, the
    links by index, the trail of the bob; a guide turning with time."""
    t = np.linspace(0.0, 10.0, 1001)
    th = 0.5 * np.cos(2 * np.pi * t)
    bob = np.column_stack([np.sin(th), 0 * t, -np.cos(th)])
    ang = 0.1 * t
    g = np.column_stack([np.cos(ang), np.sin(ang), 0 * t])
    tr = poinsot.Trajectory(t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x")
    drawing = {
        "points": {"pivot": np.zeros((t.size, 3)), "bob": bob},
        "links": [("pivot", "bob")],
        "trails": ["bob"],
        "guides": {"plane": np.stack([-g, g], axis=1)},
        "face_on": True,
    }
    P, _ = _write(tmp_path, tr, drawing=drawing)
    rig = _named(P, "links and points: pivot, bob")
    frames = _f32(P["t"])
    pts = _f32(rig["v"]).reshape(frames.size, 2, 3)
    k = np.searchsorted(t, frames - 1e-6)
    np.testing.assert_allclose(pts[:, 1], bob[k], atol=1e-6)
    assert rig["pairs"] == [[0, 1]] and rig["big"] == [1]
    assert np.max(np.diff(frames)) <= 1.0 / 24 + 1e-6  # the swing's own period, 1 s
    guide = _f32(_named(P, "plane")["v"]).reshape(frames.size, 2, 3)
    np.testing.assert_allclose(np.arctan2(guide[:, 1, 1], guide[:, 1, 0]), 0.1 * frames,
                               atol=1e-5)  # fmt: skip
    assert _named(P, "trail of bob")["type"] == "trail"
    assert P["scene"]["view"]["el"] < 0.2  # a plane drawing starts face on
    lo, hi = np.array(P["scene"]["lo"]), np.array(P["scene"]["hi"])
    assert np.all(lo <= bob.min(0)) and np.all(hi >= bob.max(0))


@pytest.mark.parametrize(
    ("drawing", "words"),
    [
        ({"points": {"a": np.zeros((3, 3))}}, "shape (11, 3)"),
        ({"points": {"a": np.zeros((11, 3))}, "links": [("a", "b")]}, "'b'"),
        ({"points": {"a": np.zeros((11, 3))}, "trails": ["c"]}, "'c'"),
        ({"points": {}, "guides": {"g": np.zeros((11, 3))}}, "shape (11, 2, 3)"),
        ({"pts": {}}, "keys"),
    ],
)
def test_drawing_is_validated(tmp_path, drawing, words):
    from poinsot.errors import InvalidInputError

    t = np.linspace(0.0, 1.0, 11)
    tr = poinsot.Trajectory(t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x")
    with pytest.raises(InvalidInputError, match=re.escape(words)):
        write_report(tmp_path / "r.html", trajectory=tr, drawing=drawing)


def test_summary_sections_in_words(tmp_path, prec):
    tr, _, _ = prec
    summary = {
        "scenario": {"name": "x<y>", "file": {"raw": 1}},
        "body": {"mass": 2.5, "units": {"mass": "kg"}},
        "accuracy": {
            "invariants": {
                "energy": {
                    "initial": 1.5,
                    "units": "J",
                    "max_relative_drift": 3e-15,
                    "conserved": True,
                }
            },
            "warnings": [],
            "reference": None,
        },
        "run": {"wall_time_s": 0.25},
    }
    _, text = _write(tmp_path, tr, summary=summary)
    assert '<h3 id="summary-body">Body</h3>' in text
    assert '<td class="num">2.5 kg</td>' in text
    assert '<td class="num">0.25 s</td>' in text
    assert "3e-15 relative" in text and ">yes<" in text and ">none<" in text
    assert ">1.5 J<" in text and ">wall time<" in text
    assert "x&lt;y&gt;" in text and "<y>" not in text.split("<details>")[0]
    assert "<details><summary>raw summary" in text
    body = text.split("<details>")[0]
    assert ">None<" not in body and ">True<" not in body and ">[]<" not in body


def test_no_summary_no_table(tmp_path, prec):
    tr, _, _ = prec
    _, text = _write(tmp_path, tr)
    assert "<h2>Summary</h2>" not in text


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
        ({"max_frames": 1}, InvalidInputError, r"Expected `max_frames` to be in \[2, 20000\]"),
        ({"max_frames": 50000}, InvalidInputError, r"Expected `max_frames` to be in \[2, 20000\]"),
        ({"shape": "box"}, InvalidTypeError, "Expected `shape` to be a mapping"),
        ({"shape": {"kind": "box"}}, InvalidInputError, "to have the keys 'kind' and 'dims'"),
        (
            {"shape": {"kind": "box", "dims": [1, 1, 1], "mass": 2}},
            InvalidInputError,
            "to have the keys 'kind' and 'dims'",
        ),
        (
            {"shape": {"kind": "torus", "dims": [1, 1]}},
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
        ({"mass": -1.0}, InvalidInputError, "Expected `mass` to be a positive number"),
        ({"max_frame_angle": 180.0}, InvalidInputError, r"`max_frame_angle` to be in \(0, 90\]"),
        ({"euler_seq": 3}, InvalidTypeError, "Expected `euler_seq` to be a string"),
        ({"torque": np.zeros((2, 3))}, InvalidInputError, r"Expected `torque` to have shape"),
        ({"center_of_mass": [1.0, 2.0]}, InvalidInputError, r"`center_of_mass` to have shape"),
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


def test_long_runs_keep_the_page_small(tmp_path):
    """20001 samples: time series cut to a min/max envelope, tracks and frames bounded."""
    tr, _, J = precession(n=20001, t1=200.0)
    P, text = _write(tmp_path, tr, inertia=J)
    x, y = _named_series(P, "w1 (body x)")
    assert len(x) <= report._MAX_SERIES + 2 and np.all(np.diff(x) > 0)
    assert y.max() == pytest.approx(tr.omega[:, 0].max(), rel=1e-6)  # envelope kept
    assert y.min() == pytest.approx(tr.omega[:, 0].min(), rel=1e-6)
    a = _named(P, "polhode")
    assert len(_f32(a["v"])) // 3 <= report._MAX_TRACK + 2
    assert len(text) < 300_000


# ----------------------------------------------------------------- meshes, extra series


def _icosphere(levels):
    """A closed unit-sphere mesh (the subdivided icosahedron of the mass tests)."""
    from mass.test_mesh import icosphere

    return icosphere(levels)


def test_mesh_body_drawn_as_given(tmp_path, prec):
    """A small mesh is drawn as given (turned by ``axes``, moved by ``center``), and its
    mass properties (poinsot.mass.mesh) put the drawing at the body's centre of mass."""
    from poinsot.mass import mesh as mesh_props

    tr, _, _ = prec
    v, f = _icosphere(1)  # 80 faces
    v = v * [0.3, 0.2, 0.1]
    axes = SciRot.from_rotvec([0.0, 0.0, np.pi / 2]).as_matrix()
    com = np.array([0.0, 0.0, 0.4])
    P, _ = _write(tmp_path, tr, shape={"kind": "mesh", "vertices": v, "faces": f,
                                       "axes": axes, "center": com})  # fmt: skip
    a = _named(P, "body: mesh")
    np.testing.assert_allclose(_f32(a["v"]).reshape(-1, 3), v @ axes.T + com, atol=1e-6)
    np.testing.assert_array_equal(_u32(a["f"]).reshape(-1, 3), f)
    props = mesh_props(_f32(a["v"]).reshape(-1, 3), _u32(a["f"]).reshape(-1, 3), density=1.0)
    np.testing.assert_allclose(props.center_of_mass, com, atol=1e-6)


def test_dense_mesh_decimated_keeps_its_shape():
    """A 20480-face sphere cut to <= 3000 faces: still a closed surface (every edge
    shared by two faces) hugging the unit sphere within a grid cell."""
    from poinsot.plotting import _report_shapes as sh

    v, f = _icosphere(5)
    assert len(f) == 20480
    v2, f2 = sh.decimate(v, f, 3000)
    assert 500 <= len(f2) <= 3000 and f2.max() == len(v2) - 1
    r = np.linalg.norm(v2, axis=-1)
    assert np.all(np.abs(r - 1) < 0.05), (r.min(), r.max())
    np.testing.assert_allclose(np.abs(v2).max(axis=0), 1.0, atol=0.05)
    edges = np.sort(np.concatenate([f2[:, [0, 1]], f2[:, [1, 2]], f2[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.mean(counts == 2) > 0.95  # (clustering may pinch a few edges)
    same_v, same_f = sh.decimate(v[:12], _icosphere(0)[1], 3000)
    assert len(same_f) == 20  # small meshes unchanged


def test_mesh_errors(tmp_path, prec):
    tr, _, _ = prec
    v, f = _icosphere(0)
    bad = [
        ({"kind": "mesh", "vertices": v}, "'kind', 'vertices' and 'faces'"),
        ({"kind": "mesh", "vertices": v[:, :2], "faces": f}, r"shape \(m, 3\)"),
        ({"kind": "mesh", "vertices": v, "faces": f + 0.5}, "integer vertex indices"),
        ({"kind": "mesh", "vertices": v, "faces": f + 12}, "to index the 12 vertices"),
    ]
    for shape, match in bad:
        with pytest.raises(InvalidInputError, match=match):
            write_report(tmp_path / "r.html", trajectory=tr, shape=shape)
    assert list(tmp_path.iterdir()) == []


def test_extra_series_panels(tmp_path, prec):
    tr, _, _ = prec
    q = {"theta": np.sin(tr.t), "phi": np.cos(tr.t)}
    P, _ = _write(tmp_path, tr, series=[("generalised coordinates q(t)", "rad", q)])
    assert P["panels"][0]["title"] == "generalised coordinates q(t)"
    assert P["panels"][0]["ytitle"] == "(rad)"
    x, y = _named_series(P, "phi")
    np.testing.assert_allclose(y, np.cos(x), atol=1e-6)
    for series, exc, match in [
        ({"a": 1}, InvalidTypeError, "`series` to be a sequence"),
        ([("t", "rad")], InvalidTypeError, r"each of `series` to be \(title"),
        ([("t", "rad", {"a": np.zeros(3)})], InvalidInputError, r"to have shape \(120,\)"),
    ]:
        with pytest.raises(exc, match=match):
            write_report(tmp_path / "x.html", trajectory=tr, series=series)


def test_plotting_never_imports_scenarios():
    """The renderer is generic: poinsot.plotting.report loads no scenario module."""
    code = (
        "import sys, poinsot.plotting.report; "
        "bad = sorted(m for m in sys.modules if m.startswith('poinsot.scenarios')); "
        "assert not bad, bad"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_lagrangian_scenario_report_plots_coordinates(tmp_path):
    """The lagrangian kind: charts of q(t) and q'(t) (rad, rad/s for angles) equal to the
    solved coordinates, and the conserved Jacobi integral; the scene draws the example's
    [draw] table: the rods keep their lengths (1 m) in every frame."""
    pytest.importorskip("sympy")
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "double_pendulum.toml"), duration=2.0)
    lt = res.trajectory  # the kind's own result: q, q' in the units of each coordinate
    assert tuple(lt.units) == ("rad", "rad")
    P, _ = _page(write_scenario_report(tmp_path / "r.html", res))
    rig = _named(P, "links and points: pivot, bob1, bob2")
    pts = _f32(rig["v"]).reshape(-1, 3, 3)
    assert rig["pairs"] == [[0, 1], [1, 2]] and len(pts) == _f32(P["t"]).size
    for i, j in rig["pairs"]:
        np.testing.assert_allclose(np.linalg.norm(pts[:, j] - pts[:, i], axis=-1), 1.0, rtol=1e-6)
    titles = _titles(P)
    assert titles[:2] == [
        "generalised coordinates q(t): angles",
        "generalised velocities q'(t): angles",
    ]
    assert [p["ytitle"] for p in P["panels"][:2]] == ["(rad)", "(rad/s)"]
    for k, name in enumerate(lt.coordinates):
        x, y = _named_series(P, name)
        np.testing.assert_allclose(y, np.interp(x, lt.t, lt.q[:, k]), atol=1e-5)
        x, y = _named_series(P, name + "'")
        np.testing.assert_allclose(y, np.interp(x, lt.t, lt.qdot[:, k]), atol=1e-4)
    assert any(t.startswith("conserved quantities") for t in titles)
    assert any(n.startswith("Jacobi integral h: max") for n in _series(P))


def test_particle_scenario_report_plots_position_and_velocity(tmp_path):
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "kepler_orbit.toml"), duration=3.0)
    P, _ = _page(write_scenario_report(tmp_path / "r.html", res))
    assert _titles(P)[:2] == ["position: x, y, z", "velocity: vx, vy, vz"]
    assert [p["ytitle"] for p in P["panels"][:2]] == ["(m)", "(m/s)"]
    x, y = _named_series(P, "vx")
    tr = res.trajectory
    np.testing.assert_allclose(y, np.interp(x, tr.t, tr.velocity[:, 0]), atol=1e-5)
    assert "whole path" in _layers(P)


def test_ensemble_report_uses_the_viewer(tmp_path):
    """The ensemble page: one histogram per metric (counts summing to the finite
    samples, edges spanning their range) and metric-vs-parameter scatters holding
    the table's columns; no animation controls, no plotting library."""
    pytest.importorskip("pyarrow")
    from poinsot.ensemble.engine import run
    from poinsot.ensemble.scenario import _report, load_ensemble

    examples = Path(__file__).resolve().parents[2] / "examples"
    _, problem = load_ensemble(examples / "tennis_racket_ensemble.toml")
    res = run(problem, 12, chunk_size=6, client="serial", seed=1)
    _report(problem, res, tmp_path / "report.html")
    P, text = _page(tmp_path / "report.html")
    assert P["scene"] is None and 'id="poinsot-play"' not in text and "plotly" not in text
    failed = res.column("failed")
    for m in problem.metrics:
        v = res.column(m.name)
        good = v[~failed & np.isfinite(v)]
        hist = [p for p in P["panels"] if p["title"].startswith(f"Histogram of {m.name}:")]
        assert len(hist) == (1 if good.size else 0)
        if good.size:
            s = hist[0]["series"][0]
            edges, counts = _f32(s["x"]), _f32(s["y"])
            assert s["mode"] == "bars" and len(edges) == len(counts) + 1
            assert counts.sum() == good.size
            assert edges[0] <= good.min() + 1e-6 * abs(good.min()) and edges[-1] >= good.max() * (
                1 - 1e-6
            )
            assert hist[0]["xtitle"] == f"{m.name} ({m.unit})" if m.unit else m.name
        for p in P["panels"]:
            if p["title"].startswith(f"{m.name} against "):
                param = p["title"].split(" against ")[1]
                s = p["series"][0]
                assert s["mode"] == "markers"
                x, y = _f32(s["x"]), _f32(s["y"])
                ok = ~failed & np.isfinite(v)
                # physical inputs: omega0 components in rad/s; the attitude as the angle
                # (deg) from the nominal one, 2 acos |q_nominal . q|, not quaternion parts
                if param.startswith("omega0_"):
                    assert p["xtitle"] == f"{param} (rad/s)"
                    np.testing.assert_allclose(x, res.column(param)[ok], rtol=1e-6, atol=1e-30)
                else:
                    assert param == "attitude_offset" and p["xtitle"] == f"{param} (deg)"
                    q = np.column_stack([res.column(f"attitude_{c}") for c in "wxyz"])[ok]
                    dot = np.clip(np.abs(q @ problem.rotation0), 0.0, 1.0)
                    np.testing.assert_allclose(x, np.degrees(2 * np.arccos(dot)), atol=1e-4)
                np.testing.assert_allclose(y, v[ok], rtol=1e-6)
    assert not any(p["title"].endswith("attitude_w") for p in P["panels"])
    assert "Dispersed inputs" in text and "Which input matters most" in text
    assert "Failed samples: 0 of 12" in text


def test_heavy_top_scenario_report_panels(tmp_path):
    """A top on a pin: the disc drawn at its centre of mass (5 cm up body z), the pin
    marked, no polhode/herpolhode (not a free body), the conserved T + V and K_z, the
    ZXZ angles (precession, nutation, spin) and the gravity torque."""
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "symmetric_top.toml"), duration=0.2)
    P, text = _page(write_scenario_report(tmp_path / "r.html", res))
    disc = _f32(_named(P, "body: cylinder")["v"]).reshape(-1, 3)
    np.testing.assert_allclose(disc.mean(axis=0), [0.0, 0.0, 0.05], atol=1e-6)
    np.testing.assert_allclose(np.ptp(disc, axis=0), [0.08, 0.08, 0.01], rtol=1e-2)
    assert _named(P, "fixed point")["p"] == [0.0, 0.0, 0.0]
    assert not any(k.startswith(("polhode", "herpolhode")) for k in _layers(P))
    titles = _titles(P)
    assert any(t.startswith("attitude: Euler angles ZXZ") for t in titles)
    assert "torque N, body axes" in titles
    names = list(_series(P))
    assert any(n.startswith("total energy T + V: max") for n in names), names
    assert any(n.startswith("K_z") for n in names), names
    assert any(n.startswith("theta, nutation") for n in names), names
    assert "turns at most" in text  # the spin of 150 rad/s does not strobe
    # regular precession: gravity does no work, T is constant; the balance says so
    balance = [t for t in titles if t.startswith("energy balance")]
    assert len(balance) == 1 and "T constant here: round-off only, max" in balance[0], balance
    # released from rest in nutation, T changes: a real balance, no round-off label
    released = simulate_scenario(load_scenario(examples / "top_released.toml"), duration=0.5)
    P2, _ = _page(write_scenario_report(tmp_path / "r2.html", released))
    balance = [t for t in _titles(P2) if t.startswith("energy balance")]
    assert balance == ["energy balance: T(t) - T(0) = work of the torque"]


def test_rotating_frame_particle_drawn_in_the_frame(tmp_path):
    """A body dropped on the turning Earth: the scene shows its path relative to the
    ground (east, north, up: the eastward deflection), not the Earth frame's attitude
    as a body; no angular-velocity or attitude chart of the frame."""
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "free_fall.toml"))
    P, text = _page(write_scenario_report(tmp_path / "r.html", res))
    layers = sorted(_layers(P))
    assert len(layers) == 4 and layers[2:] == ["position r(t)", "whole path"], layers
    assert layers[1].startswith("path up to the frame's time")
    assert layers[0].startswith("origin of ") and layers[0] != "origin of space axes"
    assert P["scene"]["unit"] == "m" and P["q"] is None  # no attitude of the frame drawn
    r = res.trajectory.position  # relative to the Earth: east, north, up (m)
    path = _f32(_layers(P)["whole path"]["v"]).reshape(-1, 3)
    assert path[0] == pytest.approx(r[0], abs=1e-4) and path[-1] == pytest.approx(r[-1], abs=1e-4)
    assert r[-1, 0] > 0  # it lands east of the point below its start
    titles = _titles(P)
    assert titles[0] == "position: x_east, y_north, z_up"
    assert not any(t.startswith(("angular velocity", "attitude")) for t in titles)
    assert "body axes x, y, z" not in text


def test_quantities_constant_in_this_motion_say_so(tmp_path):
    """Coning (a prescribed motion): T and |K| are not conserved in general (there is a
    torque), but T is constant along this one; its chart says so with the size of its
    change instead of calling it a change (issue: no noise-only panels)."""
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "coning.toml"), duration=0.5)
    P, _ = _page(write_scenario_report(tmp_path / "r.html", res))
    titles = _titles(P)
    energy = [t for t in titles if t.startswith("kinetic energy T")]
    assert energy == ["kinetic energy T (not conserved in general, constant in this motion)"]
    names = list(_series(P))
    assert any(n.startswith("kinetic energy T (constant here: max change") for n in names), names
    # K in space axes turns with the coning: a real change, no such label
    assert any(t.startswith("|K|, K (space axes) (changes along this motion)") for t in titles)


def test_attitude_error_title_gives_its_size(tmp_path):
    """The attitude-error chart states its maximum; when two methods agree to round-off
    (attitude propagation from a piecewise-linear rate: Magnus and RK4 both exact to
    rounding) the title says so rather than showing noise as an error."""
    from poinsot.scenarios import load_scenario, simulate_scenario

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "attitude_propagation.toml"))
    err = (res.reference.rotation.inv() * res.trajectory.rotation).magnitude()
    P, _ = _page(write_scenario_report(tmp_path / "r.html", res))
    title = [t for t in _titles(P) if t.startswith("attitude error vs reference")]
    assert len(title) == 1 and "round-off only, max" in title[0], title
    assert err.max() < 1e-12
    res = simulate_scenario(load_scenario(examples / "tennis_racket.toml"), duration=1.0)
    P, _ = _page(write_scenario_report(tmp_path / "r2.html", res))
    title = [t for t in _titles(P) if t.startswith("attitude error vs reference")]
    assert len(title) == 1 and "round-off" not in title[0] and title[0].endswith(" rad)"), title


def test_point_and_coordinate_results_need_no_attitude(tmp_path):
    """The renderer draws a PointTrajectory as its path (no attitude in the page, no
    body, no angular-velocity chart) and a CoordinateTrajectory as charts only. The
    path is a circle r = (cos t, sin t, 0) m, written here in closed form."""
    from poinsot.trajectory import CoordinateTrajectory, PointTrajectory

    t = np.linspace(0.0, 2 * np.pi, 200)
    r = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    v = np.column_stack([-np.sin(t), np.cos(t), 0 * t])
    p = PointTrajectory(t, r, v, "exact", frame_name="inertial")
    P, text = _page(
        write_report(tmp_path / "p.html", trajectory=p, series=[("x", "m", {"x": r[:, 0]})])
    )
    assert P["q"] is None and P["qref"] is None
    assert sorted(_layers(P)) == [
        "origin of inertial axes",
        "path up to the frame's time (fading with age)",
        "position r(t)",
        "whole path",
    ]
    path = _f32(_layers(P)["whole path"]["v"]).reshape(-1, 3)
    np.testing.assert_allclose(np.linalg.norm(path[:, :2], axis=1), 1.0, atol=1e-6)
    assert not any(s.startswith(("angular velocity", "attitude")) for s in _titles(P))
    x, y = _named_series(P, "x")
    np.testing.assert_allclose(y, np.cos(x), atol=1e-6)
    with pytest.raises(InvalidInputError, match="no rigid body"):
        write_report(tmp_path / "bad.html", trajectory=p, torque=np.zeros((200, 3)))
    c = CoordinateTrajectory(t, r[:, :1], v[:, :1], ("x",), "exact", units=("m",))
    P, _ = _page(
        write_report(tmp_path / "c.html", trajectory=c, series=[("q", "m", {"x": r[:, 0]})])
    )
    assert P["scene"] is None and P["q"] is None and _titles(P) == ["q"]


def test_euler_angles_wrapped_alike_and_law_legends_not_doubled(tmp_path):
    """A fast spin about z with a slow yaw: the spin angle would need wrapping, so all
    three angles are wrapped to (-180, 180] (said in the title), none unwrapped alone;
    a check whose label already says what it is compared with keeps that label."""
    from poinsot.scenarios import Check

    t = np.linspace(0.0, 10.0, 2001)
    rot = poinsot.Rotation.from_euler("ZXZ", np.column_stack([0.9 * t, 0 * t + 0.3, 20.0 * t]))
    tr = poinsot.Trajectory(t, rot, np.tile([0.0, 0.0, 20.0], (t.size, 1)), "x")
    values = np.ones((t.size, 3)) + 1e-3 * np.sin(t)[:, None]
    law = Check(
        "position",
        "position vs Kepler's equation",
        "m",
        values,
        expected=np.ones((t.size, 3)),
        conserved=False,
        law="the conic r = p/(1 + e cos nu)",
    )
    P, _ = _write(tmp_path, tr, euler_seq="ZXZ", checks=[law])
    title = next(x for x in _titles(P) if x.startswith("attitude: Euler angles ZXZ"))
    # and why not unwrapped: the spin runs over 20 rad/s x 10 s / 2 pi = 31.8 turns
    assert title.endswith(
        "(each wrapped to (-180, 180]: unwrapped, phi would run over 31.8 turns and "
        "flatten the others)"
    ), title
    for name in ("psi, precession (Z)", "theta, nutation (X)", "phi, spin (Z)"):
        y = _named_series(P, name)[1]
        assert np.all(np.abs(y) <= 180.0 + 1e-3), name
    assert np.ptp(_named_series(P, "psi, precession (Z)")[1]) > 300  # 9 rad of yaw, wrapped
    names = list(_series(P))
    assert any(n.startswith("position vs Kepler's equation: max ") for n in names), names


# ----------------------------------------------------------------- the spec (issue 39)


def test_spec_and_keyword_forms_give_the_same_page(tmp_path, prec):
    """``write_report(path, spec)`` and the keyword form read one ReportSpec: the same
    page; ``show(spec)`` draws it too; the scenario kinds' names are the same classes."""
    from poinsot import scenarios
    from poinsot.plotting import BodyLayer, Chart, Drawing, ReportSpec, show

    tr, _, J = prec
    series = [("q", "rad", {"a": np.sin(tr.t), "b": np.cos(tr.t)}, ("b",))]
    drawing = {"points": {"tip": np.ones((tr.t.size, 3))}, "trails": ["tip"]}
    kw = dict(inertia=J, mass=2.0, fixed_point=True, free_body=False, euler_seq="ZXZ",
              torque=np.zeros((tr.t.size, 3)), series=series, drawing=drawing,
              title="t", summary={"a": 1}, max_frames=200)  # fmt: skip
    spec = ReportSpec(
        tr,
        BodyLayer(inertia=J, mass=2.0, fixed_point=True),
        torque=np.zeros((tr.t.size, 3)),
        euler_seq="ZXZ",
        charts=(Chart("q", "rad", series[0][2], ("b",)),),
        drawing=Drawing({"tip": np.ones((tr.t.size, 3))}, trails=("tip",)),
        title="t",
        summary={"a": 1},
        max_frames=200,
    )
    a = write_report(tmp_path / "a.html", spec).read_text()
    b = write_report(tmp_path / "b.html", trajectory=tr, **kw).read_text()
    assert a == b == report.report_html(spec) == report.report_html(trajectory=tr, **kw)
    assert show(spec).html == a
    for name in ("ReportSpec", "BodyLayer", "Drawing", "Chart"):
        assert getattr(scenarios, name) is getattr(scenarios.kind, name)
        assert getattr(scenarios, name).__module__ == "poinsot.plotting.spec"


def test_spec_errors(tmp_path, prec):
    from poinsot.plotting import ReportSpec, show

    tr, _, _ = prec
    spec = ReportSpec(tr)
    with pytest.raises(InvalidTypeError, match="not both"):
        write_report(tmp_path / "r.html", spec, title="x")
    with pytest.raises(InvalidTypeError, match="`spec` to be a poinsot.plotting.ReportSpec"):
        report.report_html(tr)
    with pytest.raises(InvalidTypeError, match="each of `charts` to be a poinsot.plotting.Chart"):
        report.report_html(ReportSpec(tr, charts=(("q", "rad", {}),)))
    with pytest.raises(InvalidTypeError, match="`drawing` to be a poinsot.plotting.Drawing"):
        report.report_html(ReportSpec(tr, drawing={"points": {}}))
    with pytest.raises(InvalidTypeError, match="no options with a ReportSpec"):
        show(spec, inertia=[1.0, 2.0, 3.0])
    assert list(tmp_path.iterdir()) == []
