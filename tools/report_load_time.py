"""Size and load time of poinsot ``report.html`` files in headless Chromium.

Usage: python tools/report_load_time.py [--runs N] REPORT.html [REPORT.html ...]

Load time: navigation start to the first animation frame after the figure is
ready (``#poinsot-figure[data-ready="1"]``: scene and charts drawn, animation
ready), the median of N fresh pages (default 5). Reports written before the
built-in viewer (plotly.js pages, the figure div with frames added) are timed
to their first frame after ``Plotly.addFrames`` resolved, so old and new pages
can be compared. Uses the Chromium of tools/install_browser.sh; works offline.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from screenshot_report import ARGS, CHROMIUM  # noqa: E402  (same browser and flags)

# polled on every animation frame from the first one; the time is taken one frame
# after the page says it is ready (what was drawn is then painted)
_INIT = r"""
(function () {
  function check() {
    const g = document.getElementById('poinsot-figure');
    const ok = g && ((g.dataset && g.dataset.ready === '1') ||
      (g._fullLayout && g._transitionData && g._transitionData._frames &&
       g._transitionData._frames.length > 0));
    if (ok) { requestAnimationFrame(() => { window.__poinsotReadyT = performance.now(); }); }
    else requestAnimationFrame(check);
  }
  requestAnimationFrame(check);
})();
"""


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("reports", type=Path, nargs="+")
    p.add_argument("--runs", type=int, default=5)
    a = p.parse_args(argv)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        for path in a.reports:
            times: list[float] = []
            errors: list[str] = []
            note = errors.append
            for _ in range(a.runs):
                page = browser.new_page(viewport={"width": 1400, "height": 1000})
                page.on("console", lambda m, note=note: note(m.text) if m.type == "error" else 0)
                page.on("pageerror", lambda e, note=note: note(str(e)))
                page.route(
                    "**/*",
                    lambda r: (
                        r.continue_()
                        if r.request.url.startswith(("file:", "data:", "blob:"))
                        else r.abort()
                    ),
                )
                page.add_init_script(_INIT)
                page.goto(path.resolve().as_uri(), wait_until="load", timeout=180_000)
                page.wait_for_function(
                    "() => window.__poinsotReadyT !== undefined", timeout=180_000, polling=50
                )
                times.append(page.evaluate("() => window.__poinsotReadyT") / 1000)
                page.close()
            runs = ", ".join(f"{x:.2f}" for x in times)
            err = f"  console errors: {errors[0][:100]}" if errors else ""
            size = path.stat().st_size / 1e6
            print(
                f"{path}: {size:.3f} MB, load {statistics.median(times):.2f} s "
                f"median of {a.runs} ({runs}){err}",
                flush=True,
            )
        browser.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
