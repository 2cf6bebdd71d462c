"""Tests of the self-contained HTML report (poinsot.plotting.report).

The trajectory is the closed-form regular precession of a free symmetric body
(docs/theory.md §10: ``psi' = K/A``, ``phi' = (A - C) r / A``, ``cos theta = C r / K``),
built with SciPy's Rotation as an independent oracle. The page's data (the
animation frames, the clouds the browser turns, the panels) is decoded from the
HTML and checked against that oracle and the Poinsot construction (theory §8,
§10): the polhode lies on the inertia ellipsoid ``r^T J r = s^2`` and the
herpolhode in the invariable plane at distance ``s sqrt(2T)/|K|``.
"""

from __future__ import annotations

import base64
import gzip
import json
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


def _traces(P):
    """{name: (trace, animation entry or None)} of the figure."""
    anim = {a["trace"]: a for a in P["anim"]}
    out = {}
    for k, d in enumerate(P["fig"]["data"]):
        out[d.get("name")] = (d, anim.get(k))
    return out


def _arr(v):
    if isinstance(v, dict):
        return np.frombuffer(base64.b64decode(v["bdata"]), dtype=np.dtype(v["dtype"])).astype(float)
    return np.asarray(v, dtype=float)


def _named(P, prefix):
    hits = [v for k, v in _traces(P).items() if k and k.startswith(prefix)]
    assert len(hits) == 1, (prefix, list(_traces(P)))
    return hits[0]


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
    P, text = page
    import plotly.offline

    m = re.search(r'id="poinsot-plotlyjs">([A-Za-z0-9+/=]+)</script>', text)
    assert m is not None  # plotly.js inlined once, gzip + base64, unpacked by the page
    assert gzip.decompress(base64.b64decode(m.group(1))).decode() == plotly.offline.get_plotlyjs()
    assert "<script src=" not in text and "cdn.plot.ly" not in text
    assert "DecompressionStream" in text
    assert len(text) < 0.5 * len(plotly.offline.get_plotlyjs())  # half the library alone


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


def test_body_cloud_and_axes_follow_the_rotation(prec, page):
    tr, sci, J = prec
    P, _ = page
    d, a = _named(P, "body: ellipsoid")
    v_body = _f32(a["v"]).reshape(-1, 3)
    first = np.column_stack([_arr(d["x"]), _arr(d["y"]), _arr(d["z"])])
    np.testing.assert_allclose(first, sci[0].apply(v_body), atol=1e-5)
    for lab, col in zip("xyz", range(3), strict=True):
        d, a = _named(P, f"body {lab} axis")
        e = np.asarray(a["e"])
        assert np.count_nonzero(e) == 1 and e[col] > 0
        np.testing.assert_allclose([_arr(d[c])[1] for c in "xyz"], sci[0].apply(e), atol=1e-9)


def test_equivalent_ellipsoid_has_the_mass_and_inertia(page):
    """The drawn solid is the uniform ellipsoid with J: A = m (b^2 + c^2) / 5."""
    P, _ = page
    _, a = _named(P, "body: ellipsoid")
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
    d, a = _named(P, "polhode")
    pol = _f32(a["v"]).reshape(-1, 3)
    q = np.einsum("ni,ij,nj->n", pol, J, pol)
    np.testing.assert_allclose(q, q[0], rtol=1e-5)  # on r^T J r = s^2
    s = np.sqrt(q[0])
    d, a = _named(P, "herpolhode")
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
        d, a = _named(P, prefix)
        v = _f32(a["v"]).reshape(-1, 3)
        c = np.linalg.norm(v, axis=-1) / np.linalg.norm(truth, axis=-1)
        np.testing.assert_allclose(c, c[0], rtol=1e-5)  # one scale for the animation
        np.testing.assert_allclose(v / c[:, None], truth, atol=1e-5)
        stated = float(re.search(r"= ([0-9.e+-]+) m\)", d["name"]).group(1))
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
    d, a = _named(P, f"body: {kind}")
    assert d["type"] == "mesh3d"
    v = _f32(a["v"]).reshape(-1, 3) - com
    np.testing.assert_allclose(np.abs(v).max(axis=0), extent, rtol=2e-3, atol=1e-7)
    if kind == "cone":  # centre of mass h/4 above the base
        assert v[:, 2].min() == pytest.approx(-0.25, rel=1e-5)
    d, _ = _named(P, "fixed point")
    assert [_arr(d[c])[0] for c in "xyz"] == [0.0, 0.0, 0.0]
    scene = P["fig"]["layout"]["scene"]
    assert [scene[f"{c}axis"]["title"]["text"] for c in "xyz"] == ["x (m)", "y (m)", "z (m)"]


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
    _, a = _named(P, "body: cylinder, point")
    v = _f32(a["v"]).reshape(-1, 3)
    assert v[:, 0].min() == pytest.approx(-0.25, rel=1e-5)  # the handle lies along x


def test_panels_free_body(page):
    P, _ = page
    titles = [a["text"] for a in P["fig"]["layout"]["annotations"]]
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
    titles = [a["text"] for a in P["fig"]["layout"]["annotations"]]
    cons = next(t for t in titles if t.startswith("conserved quantities"))
    assert "round-off only" in cons
    names = [d["name"] for d in P["fig"]["data"]]
    assert any(re.match(r"kinetic energy T: max [0-9.]+e-1[56]$", n) for n in names), names
    assert any(t.startswith("T (reported)") for t in titles)
    assert "deviation from the known law (relative)" in titles
    assert any(re.match(r"T vs closed form: max 1e-9$", n) for n in names), names
    dev = next(d for d in P["fig"]["data"] if d["name"].startswith("T vs closed form"))
    np.testing.assert_allclose(_arr(dev["y"]), 1e-9, rtol=1e-5)
    ylabels = [
        v["title"]["text"]
        for k, v in P["fig"]["layout"].items()
        if k.startswith("yaxis") and "title" in v
    ]
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
    names = {d.get("name"): d for d in P["fig"]["data"]}
    assert "polhode (on the inertia ellipsoid, moves with the body)" not in names
    dT, work = _arr(names["T(t) - T(0)"]["y"]), _arr(names["int N . w dt"]["y"])
    np.testing.assert_allclose(work, dT, atol=1e-4 * dT.max())
    assert _arr(names["Nz"]["y"]).max() == pytest.approx(N)


def test_particle_path(tmp_path):
    t = np.linspace(0.0, 6.0, 301)
    pos = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    tr = poinsot.Trajectory(
        t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "x", position=pos
    )
    P, _ = _write(tmp_path, tr)
    d, a = _named(P, "position")
    np.testing.assert_allclose(np.linalg.norm(_f32(a["v"]).reshape(-1, 3), axis=-1), 1.0, rtol=1e-6)
    names = [d.get("name") for d in P["fig"]["data"]]
    assert "path" in names and not any(n and n.startswith("w1") for n in names)  # no empty panel


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
    d, _ = _named(P, "w1")
    x, y = _arr(d["x"]), _arr(d["y"])
    assert len(x) <= report._MAX_SERIES + 2 and np.all(np.diff(x) > 0)
    assert y.max() == pytest.approx(tr.omega[:, 0].max(), rel=1e-6)  # envelope kept
    assert y.min() == pytest.approx(tr.omega[:, 0].min(), rel=1e-6)
    _, a = _named(P, "polhode")
    assert len(_f32(a["v"])) // 3 <= report._MAX_TRACK + 2
    assert len(text) < 2.6e6
