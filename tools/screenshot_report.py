"""Screenshot a poinsot ``report.html`` in headless Chromium (for the docs).

Usage: python tools/screenshot_report.py REPORT.html OUT.png [--at FRACTION]

Opens the report offline, jumps the animation to FRACTION of its frames
(default 0.45) and saves a PNG of the title, the controls, the 3-D scene and
the charts (``--full``: the whole page, with the summary). Uses the same
Chromium and flags as ``tests/browser/test_report_browser.py`` (install it with
tools/install_browser.sh). Pages without animation (an ensemble's) are shot as
they are.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

CHROMIUM = os.environ.get("POINSOT_CHROMIUM", "/usr/bin/chromium")
ARGS = [
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


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("report", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--at", type=float, default=0.45, help="fraction of the animation (0..1)")
    p.add_argument("--width", type=int, default=1400)
    p.add_argument("--full", action="store_true", help="the whole page (default: the figure)")
    a = p.parse_args(argv)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": a.width, "height": 1000})
        page.route(
            "**/*",
            lambda r: r.continue_() if r.request.url.startswith(("file:", "data:")) else r.abort(),
        )
        page.goto(a.report.resolve().as_uri(), wait_until="load", timeout=120_000)
        page.wait_for_function(
            "() => { const g = document.getElementById('poinsot-figure');"
            " return g && g.dataset.ready === '1'; }",
            timeout=120_000,
        )
        page.evaluate(
            "(at) => window.poinsotDraw"
            " && window.poinsotDraw(Math.round(at * (window.poinsotFrames - 1)))",
            a.at,
        )
        page.wait_for_timeout(300)
        if a.full:
            page.screenshot(path=str(a.out), full_page=True)
        else:
            box = page.locator("#poinsot-figure").bounding_box()  # title, controls, figure
            clip = {"x": 0, "y": 0, "width": a.width, "height": box["y"] + box["height"] + 10}
            page.screenshot(path=str(a.out), clip=clip, full_page=True)
        browser.close()
    print(f"wrote {a.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
