"""(Re)make the figures of the docs' example pages.

Usage: python tools/make_doc_figures.py

Runs every shipped scenario (``examples/*.toml``) and the demo with the
``poinsot`` command, in a temporary directory, copies the PNG figures each run
makes to ``docs/_static/examples/<scenario>-<figure>.png``, and screenshots the
demo's ``report.html`` in headless Chromium to ``docs/_static/report.png``
(skipped with a message when Chromium is missing: tools/install_browser.sh).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STATIC = ROOT / "docs" / "_static"


def main() -> int:
    from poinsot.cli import main as poinsot

    dest = STATIC / "examples"
    dest.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for toml in sorted((ROOT / "examples").glob("*.toml")):
            out = tmp / toml.stem
            code = poinsot(["run", str(toml), "--out", str(out), "--quiet"])
            if code != 0:
                print(f"poinsot run {toml.name} failed ({code})", file=sys.stderr)
                return code
            for png in sorted(out.glob("*.png")):
                shutil.copyfile(png, dest / f"{toml.stem}-{png.name}")
                print(f"docs/_static/examples/{toml.stem}-{png.name}")
        demo = tmp / "demo"
        if poinsot(["demo", "--out", str(demo), "--quiet"]) != 0:
            return 1
        shot = [sys.executable, str(ROOT / "tools" / "screenshot_report.py")]
        shot += [str(demo / "report.html"), str(STATIC / "report.png"), "--at", "0.3"]
        if subprocess.run(shot).returncode != 0:
            print("report screenshot skipped (Chromium/Playwright missing?)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
