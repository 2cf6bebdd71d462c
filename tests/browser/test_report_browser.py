"""End-to-end: ``report.html`` opened in a real headless Chromium.

Debian's ``chromium`` package (``/usr/bin/chromium``, installed by
``tools/install_browser.sh``) is driven by Playwright for Python. The test
asserts that the page makes no network request (it works offline), logs no
console error, draws the body as its shape (body-coloured pixels where the
body's centre projects, gone when its legend item hides it), titles the scene
axes with units, has no empty chart and units in every chart's axis titles,
that pressing Play advances the animation frame by frame (slider, time label,
the scene's pixels and every chart's time cursor move), Pause stops it, the
speed control skips frames, dragging turns the view and a double-click resets
it, the wheel zooms, hovering a chart reads its values out and a legend click
hides a series; the load time (navigation start to the scene and charts drawn,
animation ready) is printed and recorded as a junit property.

If Playwright or Chromium is missing or cannot start, the test is SKIPPED with
the reason printed to the terminal, never passed silently. Set
``POINSOT_REPORT_SCREENSHOT=path.png`` to keep the screenshot (the docs use it).
"""

from __future__ import annotations

import io
import os
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot

import poinsot
from poinsot.plotting.report import write_report

CHROMIUM = os.environ.get("POINSOT_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",  # containers often have a tiny /dev/shm
]
FIG = "document.getElementById('poinsot-figure')"


def _skip_loudly(reason: str):
    msg = f"BROWSER TEST SKIPPED: {reason}"
    print(f"\n{'!' * 8} {msg} {'!' * 8}", file=sys.__stderr__, flush=True)
    pytest.skip(msg)


@pytest.fixture(scope="module")
def browser():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError as exc:
        _skip_loudly(f"Playwright for Python is not installed ({exc}); pip install playwright.")
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        _skip_loudly(
            f"no Chromium at {CHROMIUM}; run `bash tools/install_browser.sh` "
            "(apt-get install chromium) or set POINSOT_CHROMIUM."
        )
    pw = sync_playwright().start()
    try:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, timeout=60_000)
    except Exception as exc:  # any launch failure: skip with the browser's own words
        pw.stop()
        _skip_loudly(f"Chromium at {CHROMIUM} could not be started: {exc}")
    yield b
    b.close()
    pw.stop()


def _precession(n=300, A=2.0, C=1.0, K=1.0, theta=0.6, t1=25.0):
    """Closed-form regular precession of a free symmetric body (SPEC S10)."""
    t = np.linspace(0.0, t1, n)
    r = K * np.cos(theta) / C
    psid, phid = K / A, (A - C) * r / A
    psi, phi = psid * t, 0.3 + phid * t
    sci = SciRot.from_euler("ZXZ", np.column_stack([psi, np.full(n, theta), phi]))
    st = np.sin(theta)
    w = np.column_stack(
        [psid * st * np.sin(phi), psid * st * np.cos(phi), np.full(n, psid * np.cos(theta) + phid)]
    )
    J = np.diag([A, A, C])
    tr = poinsot.Trajectory(
        t,
        poinsot.Rotation.from_quat(sci.as_quat(scalar_first=True)),
        w,
        "closed form",
        energy=0.5 * np.einsum("ni,ij,nj->n", w, J, w),
        momentum=sci.apply(w @ J),
    )
    return tr, J


def _png(data: bytes) -> np.ndarray:
    """Decode a PNG screenshot to uint8 RGB (matplotlib's reader)."""
    import matplotlib.image

    img = matplotlib.image.imread(io.BytesIO(data), format="png")
    if img.dtype != np.uint8:
        img = np.round(img * 255).astype(np.uint8)
    return img[..., :3]


def _distinct_colours(img: np.ndarray) -> int:
    return len(np.unique(img.reshape(-1, 3), axis=0))


def _has_colour(img: np.ndarray, hex_colour: str, tol: int = 40, min_pixels: int = 15) -> bool:
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)])
    close = np.all(np.abs(img.astype(int) - rgb) <= tol, axis=-1)
    return int(close.sum()) >= min_pixels


def _box(page, selector: str) -> dict:
    box = page.locator(selector).first.bounding_box()
    assert box is not None and box["width"] > 50 and box["height"] > 50, (selector, box)
    return box


def test_report_renders_and_animates_in_chromium(browser, tmp_path, record_property):
    from poinsot.scenarios import Check

    tr, J = _precession()
    ref = poinsot.Trajectory(tr.t, tr.rotation, tr.omega, "exact")
    checks = [
        Check("energy", "kinetic energy T", "J", tr.energy),
        Check("momentum_vector", "K (space axes)", "kg m^2/s", tr.momentum),
    ]
    path = write_report(
        tmp_path / "report.html",
        trajectory=tr,
        reference=ref,
        inertia=J,
        mass=2.0,
        shape={"kind": "cylinder", "dims": [0.8, 0.4]},
        checks=checks,
        summary={"run": {"method": "closed form", "wall_time_s": 0.5, "notes": []}},
        title="regular precession",
    )

    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    errors: list[str] = []
    external: list[str] = []
    page.on("console", lambda m: errors.append(f"console: {m.text}") if m.type == "error" else 0)
    page.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))

    def offline(route):
        url = route.request.url
        if url.startswith(("file:", "data:", "blob:")):
            route.continue_()
        else:
            external.append(url)
            route.abort()

    page.route("**/*", offline)
    page.goto(path.resolve().as_uri(), wait_until="load", timeout=120_000)
    page.wait_for_function(f"() => {FIG} && {FIG}.dataset.ready === '1'", timeout=120_000)
    # load time: navigation start -> scene and charts drawn, animation ready (recorded,
    # asserted only loosely: speed is measured by tools/report_load_time.py, and this
    # machine may be loaded)
    load_s = page.evaluate("() => performance.now() / 1000")
    size_mb = path.stat().st_size / 1e6
    record_property("report_load_time_s", round(load_s, 2))
    record_property("report_size_mb", round(size_mb, 3))
    print(
        f"\nreport.html: {size_mb:.3f} MB, loaded and drawn in {load_s:.2f} s (headless Chromium)",
        file=sys.__stderr__,
        flush=True,
    )
    assert 0 < load_s < 30
    assert size_mb < 0.5

    assert page.title() == "regular precession"
    assert page.locator("#summary-run").count() == 1
    assert page.locator("table.summary td", has_text="0.5 s").count() == 1  # units on numbers
    assert page.locator("details pre").count() == 1  # the raw JSON, collapsed

    # --- the scene: axes titled with units, the body drawn as its shape where it is
    scene_box = _box(page, "#poinsot-scene")
    assert page.evaluate("() => window.poinsotViewer.scene.labels") == ["x (m)", "y (m)", "z (m)"]
    scene0 = _png(page.screenshot(clip=scene_box))
    assert _distinct_colours(scene0) > 100, "3-D scene looks blank"
    assert np.any(scene0 < 245, axis=-1).mean() > 0.03, "3-D scene almost empty"
    assert _has_colour(scene0, "#d62728"), "body x axis (red) not visible in the scene"
    assert _has_colour(scene0, "#ff7f0e"), "angular velocity (orange) not visible in the scene"
    legend = page.evaluate(
        "() => Array.from(document.querySelectorAll('#poinsot-legend .pv-item'))"
        ".map(e => e.textContent)"
    )
    assert "body: cylinder" in legend and any("1 rad/s = " in x for x in legend), legend

    def body_pixels(img):
        """Share of body-grey pixels (shaded #a9b3c1: r < g < b, saturation low) in a
        window around where the cylinder's centre (the origin) is drawn."""
        x, y = page.evaluate("() => window.poinsotViewer.scene.project(0, 0, 0)")
        win = img[int(y) - 6 : int(y) + 7, int(x) - 6 : int(x) + 7].astype(int)
        r, b = win[..., 0], win[..., 2]
        grey = (b - r > 4) & (b - r < 40) & (r > 40) & (b < 235)
        return grey.mean()

    assert body_pixels(scene0) > 0.5, "the body is not drawn where its centre projects"
    body_item = page.locator("#poinsot-legend .pv-item", has_text="body: cylinder")
    body_item.click()
    hidden = _png(page.screenshot(clip=scene_box))
    assert body_pixels(hidden) < 0.2, "hiding the body left its pixels"
    body_item.click()

    # --- the charts: no empty chart, units in every axis title
    charts = page.evaluate(
        """() => Array.from(document.querySelectorAll('.pv-panel')).map(p => ({
            title: p.querySelector('.pv-title').textContent,
            axes: Array.from(p.querySelectorAll('.pv-axis-title')).map(e => e.textContent),
            lines: Array.from(p.querySelectorAll('polyline.pv-series')).map(l => {
                const ys = l.getAttribute('points').trim().split(' ').map(s => +s.split(',')[1]);
                return [ys.length, Math.max(...ys) - Math.min(...ys)]; }),
            cursor: +p.querySelector('.pv-cursor').getAttribute('x1')}))"""
    )
    assert len(charts) >= 3, [c["title"] for c in charts]  # w, angles, conserved
    for c in charts:
        assert c["axes"][0] == "t (s)" and re.fullmatch(r"\(.+\)", c["axes"][1]), c
        assert c["lines"] and all(n >= 2 for n, _ in c["lines"]), c
        assert max(span for _, span in c["lines"]) > 5, f"chart {c['title']!r} is flat/empty"
    plots = _png(page.screenshot(clip=_box(page, "#poinsot-panels")))
    for colour in ("#d62728", "#2ca02c", "#1f77b4"):  # w1, w2, w3
        assert _has_colour(plots, colour), f"omega component {colour} not drawn"

    # --- Play advances the animation frame by frame at 1x; the cursors follow
    state = (
        "() => [+document.getElementById('poinsot-slider').value, "
        "document.getElementById('poinsot-time').textContent]"
    )
    active0, label0 = page.evaluate(state)
    assert active0 == 0 and label0 == "t = 0 s"
    page.evaluate(
        "() => { window.__frames = []; new MutationObserver(() => window.__frames.push("
        f"+{FIG}.dataset.frame)).observe({FIG}, {{attributes: true, "
        "attributeFilter: ['data-frame']}); }"
    )
    page.locator("#poinsot-play").click()
    page.wait_for_function(
        "() => +document.getElementById('poinsot-slider').value >= 5", timeout=60_000
    )
    page.locator("#poinsot-play").click()  # Pause
    page.wait_for_timeout(300)
    active1, label1 = page.evaluate(state)
    frames = page.evaluate("() => window.__frames")
    assert active1 >= 5 and label1 != label0 and label1.startswith("t = ")
    steps = np.diff([int(f) for f in frames])
    assert len(frames) >= 5 and np.all(steps == 1), frames  # frames played in order
    scene1 = _png(page.screenshot(clip=scene_box))
    changed = np.any(scene1 != scene0, axis=-1).mean()
    assert changed > 0.002, f"the scene did not move ({changed:.4%} pixels changed)"
    cursors = page.evaluate(
        "() => Array.from(document.querySelectorAll('.pv-cursor')).map(c => +c.getAttribute('x1'))"
    )
    assert all(x1 > c["cursor"] + 1 for x1, c in zip(cursors, charts, strict=True)), cursors

    # --- Pause stops it
    page.wait_for_timeout(700)
    active2, _ = page.evaluate(state)
    assert active2 - active1 <= 1, (active1, active2)

    # --- the speed control: 4x skips frames (4 per step)
    page.select_option("#poinsot-speed", "4")
    page.evaluate("() => { window.__frames = []; }")
    page.locator("#poinsot-play").click()
    page.wait_for_function("() => window.__frames.length >= 3", timeout=60_000)
    page.locator("#poinsot-play").click()
    fast = np.diff(page.evaluate("() => window.__frames"))
    assert np.all(fast[fast > 0] == 4), fast

    # --- drag turns the view, double-click resets it, the wheel zooms
    page.wait_for_timeout(200)
    before = _png(page.screenshot(clip=scene_box))
    cx, cy = scene_box["x"] + scene_box["width"] / 2, scene_box["y"] + scene_box["height"] / 2
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx + 120, cy + 40, steps=5)
    page.mouse.up()
    turned = _png(page.screenshot(clip=scene_box))
    assert np.any(turned != before, axis=-1).mean() > 0.01, "dragging did not turn the view"
    page.mouse.dblclick(cx, cy)
    reset = _png(page.screenshot(clip=scene_box))
    assert np.array_equal(reset, before), "double-click did not restore the view"
    page.mouse.wheel(0, -300)
    assert page.evaluate("() => window.poinsotViewer.scene.cam.zoom") > 1.2

    # --- hover read-out and legend toggles on a chart
    chart = _box(page, "#poinsot-panel-0 svg")
    page.mouse.move(chart["x"] + chart["width"] * 0.5, chart["y"] + chart["height"] * 0.4)
    tip = page.locator("#poinsot-panel-0 .pv-tip")
    assert tip.is_visible()
    text = tip.inner_text()
    assert text.startswith("t = ") and "w1 (body x): " in text and "rad/s" in text, text
    n_lines = page.locator("#poinsot-panel-0 polyline.pv-series").count()
    page.locator("#poinsot-panel-0 .pv-item", has_text="w1 (body x)").click()
    assert page.locator("#poinsot-panel-0 polyline.pv-series").count() == n_lines - 1

    shot = tmp_path / "report.png"
    page.screenshot(path=str(shot), full_page=True)
    if os.environ.get("POINSOT_REPORT_SCREENSHOT"):
        shutil.copyfile(shot, Path(os.environ["POINSOT_REPORT_SCREENSHOT"]))
    page.close()

    assert external == [], f"the report tried to reach the network: {external}"
    assert errors == [], "console errors:\n" + "\n".join(errors)


def test_charts_only_pages_in_chromium(browser, tmp_path):
    """Pages without a 3-D scene: a Lagrangian-like run (charts of q(t) with the
    animation's cursor) and an ensemble-like page (a histogram and a scatter, no
    animation): drawn without console errors, hover read-outs of bars and points."""
    from poinsot.plotting._report_page import chart, page_html

    t = np.linspace(0.0, 4.0, 401)
    tr = poinsot.Trajectory(
        t, poinsot.Rotation.identity((t.size,)), np.zeros((t.size, 3)), "dop853"
    )
    run_page = write_report(
        tmp_path / "q.html",
        trajectory=tr,
        series=[("generalised coordinates q(t): angles", "rad", {"theta": np.sin(2 * t)})],
    )
    rng = np.random.default_rng(0)
    v = rng.normal(1.0, 0.1, 500)
    counts, edges = np.histogram(v, bins=10)
    payload = {"t": "", "q": "", "qref": None, "t0": 0.0, "t1": 1.0, "scene": None,
               "interval": 40, "panels": [
                   chart("Histogram of flip", "samples", [("flip", edges, counts, "#4477aa",
                                                           "bars")], x_name="flip", x_units="s"),
                   chart("flip against omega0_x", "s", [("flip", v * 0.1, v, "#aa3377",
                                                         "markers")], x_name="omega0_x",
                         x_units="rad/s")]}  # fmt: skip
    ens_page = tmp_path / "e.html"
    ens_page.write_text(
        page_html(
            title="ensemble", meta="m", notes=[], payload=payload, summary={"a": 1}, animated=False
        )  # fmt: skip
    )
    for path in (run_page, ens_page):
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        errors: list[str] = []
        page.on("console", lambda m, e=errors: e.append(m.text) if m.type == "error" else 0)
        page.on("pageerror", lambda x, e=errors: e.append(str(x)))
        page.goto(path.resolve().as_uri(), wait_until="load", timeout=120_000)
        page.wait_for_function(f"() => {FIG}.dataset.ready === '1'", timeout=120_000)
        assert page.locator("#poinsot-scene").count() == 0
        assert page.locator(".pv-panel svg").count() >= 1
        if path == run_page:
            assert page.locator(".pv-axis-title", has_text="(rad)").count() == 1
            x0 = float(page.locator(".pv-cursor").get_attribute("x1"))
            page.evaluate("() => window.poinsotDraw(window.poinsotFrames - 1)")
            assert float(page.locator(".pv-cursor").get_attribute("x1")) > x0 + 100
        else:
            assert page.locator("#poinsot-play").count() == 0  # no animation
            assert page.locator(".pv-cursor").count() == 0
            assert page.locator("#poinsot-panel-0 rect[width]").count() >= 10  # the bars
            assert page.locator("#poinsot-panel-1 circle").count() == v.size
            assert page.locator(".pv-axis-title", has_text="flip (s)").count() == 1
            box = _box(page, "#poinsot-panel-0 svg")
            page.mouse.move(box["x"] + box["width"] * 0.5, box["y"] + box["height"] * 0.5)
            text = page.locator("#poinsot-panel-0 .pv-tip").inner_text()
            m = re.search(r"flip: (\d+) samples in \[([0-9.e-]+), ([0-9.e-]+)\) s", text)
            assert m is not None, text
            k = int(np.searchsorted(edges, float(m.group(2)) + 1e-6, side="right")) - 1
            assert int(m.group(1)) == counts[k]  # the count of the bin under the mouse
            box = _box(page, "#poinsot-panel-1 svg")
            page.mouse.move(box["x"] + box["width"] * 0.5, box["y"] + box["height"] * 0.5)
            text = page.locator("#poinsot-panel-1 .pv-tip").inner_text()
            assert re.search(r"flip: \([0-9.e-]+ rad/s, [0-9.e-]+ s\)", text), text
        page.close()
        assert errors == [], errors


def _open(browser, path):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    errors: list[str] = []
    page.on("console", lambda m, e=errors: e.append(m.text) if m.type == "error" else 0)
    page.on("pageerror", lambda x, e=errors: e.append(str(x)))
    page.goto(path.resolve().as_uri(), wait_until="load", timeout=120_000)
    page.wait_for_function(f"() => {FIG} && {FIG}.dataset.ready === '1'", timeout=120_000)
    return page, errors


def _frame_points(page, layer_type, frame):
    """The points of the first scene layer of ``layer_type`` at ``frame`` and where they
    are drawn (CSS pixels in the canvas)."""
    return page.evaluate(
        """([type, f]) => {
            const S = window.poinsotViewer.scene, L = S.layers.find(l => l.type === type);
            const out = [];
            for (let k = 0; k < L.m; k++) {
                const o = 3 * (L.m * f + k), p = [L.v[o], L.v[o + 1], L.v[o + 2]];
                out.push({p, xy: S.project(p[0], p[1], p[2])});
            }
            return out; }""",
        [layer_type, frame],
    )


def _near(img, xy, hex_colour, r=4, tol=60):
    """Pixels of ``hex_colour`` within ``r`` pixels of ``xy`` (device pixels = CSS here)."""
    x, y = int(round(xy[0])), int(round(xy[1]))
    win = img[max(0, y - r) : y + r + 1, max(0, x - r) : x + r + 1].astype(int)
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(win - rgb) <= tol, axis=-1).sum())


def _legend_click(page, text):
    page.locator("#poinsot-legend .pv-item", has_text=text).first.click()


def test_drawn_systems_in_chromium(browser, tmp_path):
    """The new scenes, judged by their pixels: a Lagrangian example's links (the double
    pendulum's rods, dark pixels along each rod, gone when hidden), the Foucault swing
    plane (the dashed green guide lies along the direction turned by -Omega sin(lat) t:
    at the last frame, green where the turned guide runs and not where the first one
    ran), and a heavy top's stem (with the body hidden) and its axis-tip trail (more
    trail pixels late than early)."""
    from poinsot.scenarios import load_scenario, simulate_scenario, write_scenario_report

    examples = Path(__file__).resolve().parents[2] / "examples"
    runs = {
        "double_pendulum": 3.0,
        "foucault": 300.0,
        "top_loops": None,
    }
    pages = {}
    for name, duration in runs.items():
        res = simulate_scenario(load_scenario(examples / f"{name}.toml"), duration=duration)
        pages[name] = write_scenario_report(tmp_path / f"{name}.html", res)

    # --- the double pendulum: dark pixels along both rods at a late frame
    page, errors = _open(browser, pages["double_pendulum"])
    scene_box = _box(page, "#poinsot-scene")
    f = page.evaluate("() => window.poinsotFrames") - 1
    page.evaluate(f"() => window.poinsotDraw({f})")
    pts = _frame_points(page, "rig", f)
    img = _png(page.screenshot(clip=scene_box))
    for i, j in ((0, 1), (1, 2)):
        a, b = np.array(pts[i]["xy"]), np.array(pts[j]["xy"])
        for u in (0.3, 0.5, 0.7):
            assert _near(img, a + u * (b - a), "#3a3a3a") >= 3, ("rod", i, j, u)
    np.testing.assert_allclose(np.linalg.norm(np.array(pts[1]["p"]) - pts[0]["p"]), 1.0, rtol=1e-5)
    _legend_click(page, "links and points")
    hidden = _png(page.screenshot(clip=scene_box))
    a, b = np.array(pts[0]["xy"]), np.array(pts[1]["xy"])
    assert _near(hidden, a + 0.5 * (b - a), "#3a3a3a") == 0, "hiding the links left them"
    page.close()
    assert errors == [], errors

    # --- Foucault: the guide turns with the swing plane
    page, errors = _open(browser, pages["foucault"])
    scene_box = _box(page, "#poinsot-scene")
    n = page.evaluate("() => window.poinsotFrames")
    ends = []
    for f in (0, n - 1):
        page.evaluate(f"() => window.poinsotDraw({f})")
        ends.append(_frame_points(page, "rig", f))
    img = _png(page.screenshot(clip=scene_box))  # at the last frame
    (a0, b0), (a1, b1) = ([np.array(e["xy"]) for e in g] for g in ends)
    turned = np.degrees(
        np.arctan2(ends[1][1]["p"][1], ends[1][1]["p"][0])
        - np.arctan2(ends[0][1]["p"][1], ends[0][1]["p"][0])
    )
    assert turned == pytest.approx(np.degrees(-2.745e-3 * 300.0), abs=0.5)  # -Omega sin(lat) t
    green_now = sum(_near(img, a1 + u * (b1 - a1), "#2ca02c", r=6) for u in (0.1, 0.2, 0.8, 0.9))
    green_then = sum(_near(img, a0 + u * (b0 - a0), "#2ca02c", r=6) for u in (0.1, 0.2, 0.8, 0.9))
    assert green_now >= 10 and green_then <= green_now / 5, (green_now, green_then)
    notes = page.locator(".note").first.inner_text()
    assert re.search(r"at least (\d+(\.\d+)?) per period", notes), notes
    assert float(re.search(r"at least (\d+(\.\d+)?) per period", notes).group(1)) >= 24
    page.close()
    assert errors == [], errors

    # --- the heavy top: the stem (body hidden) and the trail of the axis tip
    page, errors = _open(browser, pages["top_loops"])
    scene_box = _box(page, "#poinsot-scene")
    n = page.evaluate("() => window.poinsotFrames")
    counts = []  # trail-coloured pixels that hiding the trail removes, early and late
    for f in (1, n - 1):
        page.evaluate(f"() => window.poinsotDraw({f})")
        shown = _has_colour_count(_png(page.screenshot(clip=scene_box)), "#8c564b")
        _legend_click(page, "trail of axis tip")
        gone = _has_colour_count(_png(page.screenshot(clip=scene_box)), "#8c564b")
        _legend_click(page, "trail of axis tip")
        counts.append(shown - gone)
    assert counts[1] > max(5 * counts[0], 150), counts  # the trail grows with the loops
    _legend_click(page, "body: ")
    pts = _frame_points(page, "rig", n - 1)
    img = _png(page.screenshot(clip=scene_box))
    a, b = np.array(pts[0]["xy"]), np.array(pts[1]["xy"])  # fixed point -> centre of mass
    assert sum(_near(img, a + u * (b - a), "#3a3a3a", r=3) for u in (0.3, 0.5, 0.7)) >= 6
    shot = tmp_path / "top.png"
    page.screenshot(path=str(shot))
    page.close()
    assert errors == [], errors


def _has_colour_count(img: np.ndarray, hex_colour: str, tol: int = 40) -> int:
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(img.astype(int) - rgb) <= tol, axis=-1).sum())


def test_legends_stay_inside_their_charts_in_chromium(browser, tmp_path):
    """Every legend item of every chart (and of the scene) lies within its box, even a
    long label on a narrow window: the Kepler run's law legend wraps, it is not cut."""
    from poinsot.scenarios import load_scenario, simulate_scenario, write_scenario_report

    examples = Path(__file__).resolve().parents[2] / "examples"
    res = simulate_scenario(load_scenario(examples / "kepler_orbit.toml"), duration=3.0)
    kepler = write_scenario_report(tmp_path / "kepler.html", res)
    t = res.trajectory.t
    long = "a deliberately long legend label " * 6  # ~200 characters
    other = write_report(
        tmp_path / "long.html", trajectory=res.trajectory, series=[("c", "m", {long: t})]
    )
    for path, width in ((kepler, 1400), (kepler, 700), (other, 700)):
        page = browser.new_page(viewport={"width": width, "height": 900})
        page.goto(path.resolve().as_uri(), wait_until="load", timeout=120_000)
        page.wait_for_function(f"() => {FIG}.dataset.ready === '1'", timeout=120_000)
        out = page.evaluate(
            """() => Array.from(document.querySelectorAll('.pv-panel, .pv-legend#poinsot-legend'))
                .flatMap(box => { const b = box.getBoundingClientRect();
                    return Array.from(box.querySelectorAll('.pv-item')).map(it => {
                        const r = it.getBoundingClientRect();
                        return {text: it.textContent, over: r.right - b.right,
                                left: r.left - b.left}; }); })"""
        )
        want = "Kepler's equation" if path.name == "kepler.html" else long.strip()
        assert any(want in o["text"] for o in out), [o["text"] for o in out]
        bad = [o for o in out if o["over"] > 1 or o["left"] < -1]
        assert bad == [], (width, bad)
        page.close()
