"""The HTML page of the report: compressed plotly.js, the animation driver, the summary.

Size: plotly.js (about 4.8 MB minified, shipped by the ``plotly`` Python package
as ``package_data/plotly.min.js``; no smaller partial bundle is on PyPI) is
embedded gzip-compressed and base64-encoded (about 1.9 MB) and unpacked in the
browser with ``DecompressionStream`` (Chromium 80, Firefox 113, Safari 16.4).
Numbers travel as base64 float32 arrays. The animation is driven here: each
frame carries only the attitude quaternion and the two scaled vectors; the
browser turns the body, its axes and the polhode (no per-frame copy of meshes).
"""

from __future__ import annotations

import base64
import functools
import gzip
import html
import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

DIV_ID = "poinsot-figure"


@functools.lru_cache(maxsize=1)
def plotly_js_gzip_b64() -> str:
    """plotly.js, gzip-compressed (level 9, fixed mtime: reproducible) and base64."""
    import plotly.offline

    js = plotly.offline.get_plotlyjs().encode("utf-8")
    return base64.b64encode(gzip.compress(js, compresslevel=9, mtime=0)).decode("ascii")


def b64(a, dtype=np.float32) -> str:
    """Little-endian ``dtype`` array as base64 (decoded by ``f32()`` in the page)."""
    return base64.b64encode(
        np.ascontiguousarray(a, dtype=dtype).astype("<" + np.dtype(dtype).str[1:]).tobytes()
    ).decode("ascii")


# Plotly.animate is not used (the driver below calls Plotly.update), but a rejected
# promise WITHOUT a reason is plotly's signal of an interrupted update, not an error.
_JS = r"""
window.addEventListener("unhandledrejection", function (e) {
  if (e.reason === undefined) { e.preventDefault(); }
});
function poinsotBytes(s) {
  const b = atob(s), u = new Uint8Array(b.length);
  for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
  return u;
}
function f32(s) { return s === null ? null : new Float32Array(poinsotBytes(s).buffer); }
async function poinsotLoad() {
  const z = document.getElementById("poinsot-plotlyjs").textContent;
  const stream = new Blob([poinsotBytes(z)]).stream().pipeThrough(new DecompressionStream("gzip"));
  const t0 = performance.now();
  const code = await new Response(stream).text();
  console.debug("poinsot: plotly.js unpacked in " + Math.round(performance.now() - t0) + " ms");
  const s = document.createElement("script");  // a blob: URL, compiled off the main thread
  s.src = URL.createObjectURL(new Blob([code], {type: "text/javascript"}));
  await new Promise((ok, fail) => {
    s.onload = ok;
    s.onerror = () => fail(new Error("plotly.js did not load"));
    document.head.appendChild(s);
  });
  URL.revokeObjectURL(s.src);
  console.debug("poinsot: plotly.js run in " + Math.round(performance.now() - t0) + " ms");
}
function rot(q, o, v, out, k) {  // out[k..k+2] = R(q) v  (v_space = q v q~), q = (w, x, y, z)
  const w = q[o], x = q[o + 1], y = q[o + 2], z = q[o + 3];
  const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]);
  const tz = 2 * (x * v[1] - y * v[0]);
  out[0][k] = v[0] + w * tx + (y * tz - z * ty);
  out[1][k] = v[1] + w * ty + (z * tx - x * tz);
  out[2][k] = v[2] + w * tz + (x * ty - y * tx);
}
function cloud(q, o, v, shift) {  // rotate an (m, 3) cloud, then translate
  const m = v.length / 3, out = [new Array(m), new Array(m), new Array(m)];
  for (let k = 0; k < m; k++) {
    rot(q, o, [v[3 * k], v[3 * k + 1], v[3 * k + 2]], out, k);
    if (shift) { out[0][k] += shift[0]; out[1][k] += shift[1]; out[2][k] += shift[2]; }
  }
  return out;
}
async function poinsotStart() {
  await poinsotLoad();
  const P = JSON.parse(document.getElementById("poinsot-data").textContent);
  const g = document.getElementById("%(div)s");
  const t = f32(P.t), q = f32(P.q), qref = f32(P.qref);
  const anim = P.anim.map(a => Object.assign({}, a, {v: f32(a.v)}));
  const n = t.length;
  const t1 = performance.now();
  await Plotly.newPlot(g, P.fig.data, P.fig.layout, P.config);
  console.debug("poinsot: newPlot in " + Math.round(performance.now() - t1) + " ms");
  const slider = document.getElementById("poinsot-slider");
  const label = document.getElementById("poinsot-time");
  const play = document.getElementById("poinsot-play");
  const speed = document.getElementById("poinsot-speed");
  slider.max = String(n - 1);
  let busy = false, pending = null;
  function draw(f) {
    if (busy) { pending = f; return; }
    busy = true;
    const o = 4 * f, X = [], Y = [], Z = [], ids = [];
    for (const a of anim) {
      let c;
      if (a.kind === "cloud") c = cloud(a.ref ? qref : q, o, a.v, null);
      else if (a.kind === "seg") {
        c = [[0, 0], [0, 0], [0, 0]];
        rot(a.ref ? qref : q, o, a.e, c, 1);
      }
      else if (a.kind === "vec") c = [[0, a.v[3 * f]], [0, a.v[3 * f + 1]], [0, a.v[3 * f + 2]]];
      else if (a.kind === "point") c = [[a.v[3 * f]], [a.v[3 * f + 1]], [a.v[3 * f + 2]]];
      else if (a.kind === "track") {  // the first upto[f] points, fixed in space
        const m = a.upto[f], v = a.v;
        c = [[], [], []];
        for (let k = 0; k < m; k++) {
          c[0].push(v[3 * k]); c[1].push(v[3 * k + 1]); c[2].push(v[3 * k + 2]);
        }
      }
      X.push(c[0]); Y.push(c[1]); Z.push(c[2]); ids.push(a.trace);
    }
    const lay = {};
    for (let k = 0; k < P.cursors; k++) {
      lay["shapes[" + k + "].x0"] = t[f];
      lay["shapes[" + k + "].x1"] = t[f];
    }
    slider.value = String(f);
    label.textContent = "t = " + (+t[f].toPrecision(4)) + " s";
    g.dataset.frame = String(f);
    Plotly.update(g, ids.length ? {x: X, y: Y, z: Z} : {}, lay, ids).then(() => {
      busy = false;
      if (pending !== null) { const p = pending; pending = null; draw(p); }
    }, () => { busy = false; });
  }
  let timer = null;
  function stop() {
    if (timer) { clearInterval(timer); timer = null; }
    play.textContent = "\u25b6 Play";
  }
  function tick() {
    if (busy) return;
    const s = +speed.value, step = s > 1 ? Math.round(s) : 1;
    let f = +slider.value + step;
    if (f >= n) { f = n - 1; stop(); }
    draw(f);
  }
  play.addEventListener("click", () => {
    if (timer) { stop(); return; }
    if (+slider.value >= n - 1) draw(0);
    const s = +speed.value;
    timer = setInterval(tick, Math.round(P.interval / Math.min(s, 1)));
    play.textContent = "\u275a\u275a Pause";
  });
  speed.addEventListener("change", () => { if (timer) { stop(); play.click(); } });
  slider.addEventListener("input", () => draw(+slider.value));
  window.poinsotDraw = draw;
  window.poinsotFrames = n;
  g.dataset.frame = "0";  // the figure was built at frame 0: no redraw needed
  label.textContent = "t = " + (+t[0].toPrecision(4)) + " s";
  g.dataset.ready = "1";
}
poinsotStart().catch(e => {
  console.error(e);
  document.getElementById("poinsot-error").textContent = "The report could not start: " + e;
});
"""

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 1.2em 2em;
       color: #222; max-width: 1500px; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; margin-top: 1.4em; }
h3 { font-size: 1.02em; margin: 1.1em 0 0.3em; }
p.meta, p.note { color: #555; margin: 0.2em 0; font-size: 0.93em; }
div.controls { display: flex; gap: 1em; align-items: center; margin: 0.4em 0; }
div.controls input[type=range] { flex: 1; max-width: 700px; }
div.controls button { min-width: 6em; }
table.summary { border-collapse: collapse; font-size: 0.92em; }
table.summary th, table.summary td { border: 1px solid #ddd; padding: 3px 10px;
       text-align: left; vertical-align: top; }
table.summary th { background: #f4f6f9; font-weight: 600; width: 18em; }
table.summary td.num { font-variant-numeric: tabular-nums; }
table.summary table.summary { margin: 0; }
details pre { font-size: 0.8em; background: #f7f7f7; padding: 0.6em; overflow-x: auto; }
#poinsot-error { color: #b00; }
"""

# ----------------------------------------------------------------------------- summary

_SECTION_TITLES = {
    "scenario": "Scenario",
    "body": "Body",
    "initial_state": "Initial state",
    "results": "Results (closed form)",
    "accuracy": "Accuracy",
    "run": "Run",
}
#: units of entries whose section does not list them
_KNOWN_UNITS = {
    "wall_time_s": "s",
    "memory_bytes": "bytes",
    "seconds": "s",
    "duration": "s",
    "step": "s",
    "integration_step": "s",
    "suggested_max_step": "s",
    "max_step": "s",
    "step_size": "s",
    "min_step_size": "s",
    "max_attitude_error_rad": "rad",
    "final_attitude_error_rad": "rad",
    "attitude_threshold": "rad",
    "max_omega_error": "rad/s",
    "max_relative_drift": "relative",
    "drift_threshold": "relative",
    "max_relative_omega_error": "relative",
    "samples": "samples",
    "integration_steps": "steps",
    "steps": "steps",
    "evaluations": "evaluations",
}
#: raw or machine-only entries, kept in the JSON block
_HIDDEN = {"file", "units", "principal_axes_columns"}


def _words(key: str) -> str:
    for suffix in ("_s", "_rad"):  # the units are written with the value
        if key.endswith(suffix):
            key = key[: -len(suffix)]
    return key.replace("_", " ")


def fmt_number(v: float) -> str:
    if not math.isfinite(v):
        return "infinite" if v > 0 else "minus infinite" if v < 0 else "not a number"
    if v == 0:
        return "0"
    a = abs(v)
    if 1e-3 <= a < 1e6:
        s = f"{v:.6g}"
    else:
        s = f"{v:.3e}"
        m, e = s.split("e")
        s = f"{m.rstrip('0').rstrip('.')}e{int(e)}"
    return s


def fmt_value(v: Any, units: str = "") -> str:
    """A value in words: yes/no, none, numbers with their units, short lists."""
    u = "" if units in ("", "1") else f" {units}"
    if v is None:
        return "none"
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return f"{int(v)}{u}"
    if isinstance(v, float | np.floating):
        return fmt_number(float(v)) + u
    if isinstance(v, str):
        return v if v not in ("inf", "-inf") else ("infinite" if v == "inf" else "minus infinite")
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, Sequence):
        if len(v) == 0:
            return "none"
        if all(isinstance(x, int | float) and not isinstance(x, bool) for x in v):
            return "[" + ", ".join(fmt_number(float(x)) for x in v) + "]" + u
        if all(isinstance(x, Sequence) and not isinstance(x, str) for x in v):
            return "[" + ", ".join(fmt_value(x) for x in v) + "]" + u
        return ", ".join(fmt_value(x) for x in v)
    return str(v)


def _rows(d: Mapping[str, Any], units: Mapping[str, str] | str | None) -> list[str]:
    esc = html.escape
    rows = []
    for key, v in d.items():
        if key in _HIDDEN:
            continue
        if isinstance(units, str):  # one unit for the values (initial, final...)
            u = _KNOWN_UNITS.get(key, units)
        else:
            u = (units or {}).get(key) or _KNOWN_UNITS.get(key, "")
        if isinstance(v, Mapping):
            if not v:
                cell = "none"
            else:
                inner_units = v.get("units", None)
                cell = '<table class="summary">' + "".join(_rows(v, inner_units)) + "</table>"
            rows.append(f"<tr><th>{esc(_words(key))}</th><td>{cell}</td></tr>")
        else:
            cls = ' class="num"' if isinstance(v, int | float) and not isinstance(v, bool) else ""
            rows.append(f"<tr><th>{esc(_words(key))}</th><td{cls}>{esc(fmt_value(v, u))}</td></tr>")
    return rows


def summary_html(summary: Mapping[str, Any]) -> str:
    """The summary as grouped sections (units on numbers, values in words), then the
    raw JSON in a collapsed ``<details>`` block."""
    esc = html.escape
    parts = ["<h2>Summary</h2>"]
    loose = {k: v for k, v in summary.items() if not isinstance(v, Mapping)}
    order = [k for k in _SECTION_TITLES if isinstance(summary.get(k), Mapping)]
    order += [k for k, v in summary.items() if isinstance(v, Mapping) and k not in order]
    if loose:
        parts.append(
            '<table class="summary" id="summary-general">'
            + "".join(_rows(loose, None))
            + "</table>"
        )
    for k in order:
        sec = summary[k]
        title = _SECTION_TITLES.get(k, _words(k).capitalize())
        parts.append(
            f'<h3 id="summary-{esc(k)}">{esc(title)}</h3>\n<table class="summary">'
            + "".join(_rows(sec, sec.get("units")))
            + "</table>"
        )
    raw = json.dumps(summary, indent=2, default=str, allow_nan=True)
    parts.append(
        "<details><summary>raw summary (JSON, as in summary.json)</summary>"
        f"<pre>{esc(raw)}</pre></details>"
    )
    return "\n".join(parts)


# ----------------------------------------------------------------------------- page


def page_html(
    *,
    title: str,
    meta: str,
    notes: Sequence[str],
    payload: dict,
    summary: Mapping[str, Any] | None,
    sections=(),
    speeds=(0.25, 0.5, 1, 2, 4, 8),
) -> str:
    esc = html.escape
    data = json.dumps(payload, separators=(",", ":")).replace("</", "<\\/")
    opts = "".join(
        f'<option value="{s}"{" selected" if s == 1 else ""}>{s}x</option>' for s in speeds
    )
    controls = (
        '<div class="controls"><button id="poinsot-play" type="button">\u25b6 Play</button>'
        '<input id="poinsot-slider" type="range" min="0" max="0" value="0" step="1" '
        'aria-label="animation frame">'
        '<span id="poinsot-time">t = 0 s</span>'
        '<label>speed <select id="poinsot-speed">' + opts + "</select></label></div>"
    )
    note_html = "".join(f'<p class="note">{esc(n)}</p>' for n in notes)
    table = "" if summary is None else summary_html(summary)
    extra = "".join(f"<h2>{esc(head)}</h2>\n<div>{content}</div>\n" for head, content in sections)
    table = extra + table
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{esc(title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n"
        f'<h1>{esc(title)}</h1>\n<p class="meta">{meta}</p>\n<p id="poinsot-error"></p>\n'
        f'{controls}\n<div id="{DIV_ID}"></div>\n{note_html}\n{table}\n'
        f'<script type="application/octet-stream" id="poinsot-plotlyjs">'
        f"{plotly_js_gzip_b64()}</script>\n"
        f'<script type="application/json" id="poinsot-data">{data}</script>\n'
        f'<script type="text/javascript">{_JS % {"div": DIV_ID}}</script>\n'
        "</body>\n</html>\n"
    )
