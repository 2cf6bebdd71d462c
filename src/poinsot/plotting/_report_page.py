"""The HTML page of the report: the built-in viewer, the data, the summary.

The viewer (``_report_viewer.js``, about 500 lines of plain JavaScript shipped with
poinsot) draws the 3-D scene on a 2-D ``<canvas>`` (painter's algorithm, shaded
triangles) and the time series as SVG charts, all driven by one animation clock;
no plotting library is embedded and nothing is fetched. Numbers travel as base64
little-endian float32 (uint32 for triangle indices): each frame carries only the
attitude quaternion and the scaled vectors; the browser turns the body.
"""

from __future__ import annotations

import base64
import functools
import html
import json
import math
from collections.abc import Mapping, Sequence
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

DIV_ID = "poinsot-figure"


@functools.lru_cache(maxsize=1)
def viewer_js() -> str:
    """The viewer's JavaScript (``poinsot/plotting/_report_viewer.js``)."""
    return (
        resources.files("poinsot.plotting")
        .joinpath("_report_viewer.js")
        .read_text(encoding="utf-8")
    )


def chart(
    title: str,
    units: str,
    series: Sequence[tuple[Any, ...]],
    *,
    x_name: str | None = None,
    x_units: str = "",
) -> dict[str, Any]:
    """One chart of the viewer (its data for the page).

    ``series``: ``(name, x, y, colour[, mode[, dash]])`` with mode ``"line"``
    (default), ``"markers"`` or ``"bars"`` (``x`` the ``k + 1`` bin edges, ``y`` the
    ``k`` heights) and dash ``None``, ``"dash"`` or ``"dot"`` (lines). Without
    ``x_name`` the x axis is the time ``t (s)`` and the chart has a cursor at the
    animation's time; with it, the x axis is titled ``x_name (x_units)``. ``units``
    titles the y axis, in parentheses.
    """
    out = {
        "title": title,
        "ytitle": f"({units})",
        "unit": "" if units in ("relative", "1") else units,
        "series": [
            {
                "name": s[0],
                "x": b64(s[1]),
                "y": b64(s[2]),
                "colour": s[3],
                "mode": s[4] if len(s) > 4 else "line",
                "dash": s[5] if len(s) > 5 else None,
            }
            for s in series
        ],
    }
    if x_name is not None:
        out.update(
            xtitle=f"{x_name} ({x_units})" if x_units else x_name, xname=x_name, xunit=x_units
        )
    return out


def b64(a: ArrayLike, dtype: DTypeLike = np.float32) -> str:
    """Little-endian ``dtype`` array as base64 (decoded by ``f32()``/``u32()`` in the page)."""
    return base64.b64encode(
        np.ascontiguousarray(a, dtype=dtype).astype("<" + np.dtype(dtype).str[1:]).tobytes()
    ).decode("ascii")


_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 1.2em 2em;
       color: #222; max-width: 1500px; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; margin-top: 1.4em; }
h3 { font-size: 1.02em; margin: 1.1em 0 0.3em; }
h1 span.accuracy { font-size: 0.6em; font-weight: 600; padding: 2px 8px; margin-left: 0.6em;
       border-radius: 3px; vertical-align: middle; }
h1 span.accuracy.ok { background: #e3f4e3; color: #1b5e20; }
h1 span.accuracy.warn { background: #fff1d6; color: #8a4b00; }
h1 span.accuracy.none { background: #eee; color: #555; }
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
#poinsot-figure { display: grid; grid-template-columns: minmax(0, 56fr) minmax(0, 44fr);
       gap: 1.6em; align-items: start; }
#poinsot-figure.pv-noscene { display: block; }
.pv-noscene #poinsot-panels { display: grid; gap: 0 1.6em;
       grid-template-columns: repeat(auto-fill, minmax(520px, 1fr)); }
#poinsot-scene-col { position: sticky; top: 0; background: #fff; }
@media (max-width: 900px) { #poinsot-figure { display: block; }
       #poinsot-scene-col { position: static; } }
#poinsot-scene { display: block; cursor: grab; touch-action: none; }
.pv-legend { font-size: 0.82em; line-height: 1.7; margin: 0.2em 0; }
.pv-item { cursor: pointer; margin-right: 1.1em; user-select: none; display: inline-block;
           max-width: 100%; overflow-wrap: anywhere; vertical-align: top; }
.pv-item i { display: inline-block; width: 1.5em; height: 0.35em; margin: 0 0.35em 0.2em 0;
       vertical-align: middle; }
.pv-item.off { color: #aaa; text-decoration: line-through; }
.pv-item.off i { opacity: 0.25; }
.pv-hint { color: #777; font-size: 0.8em; margin: 0.2em 0; }
.pv-panel { margin-bottom: 0.9em; }
.pv-title { font-size: 0.9em; font-weight: 600; color: #333; }
.pv-chart { position: relative; }
.pv-chart svg { display: block; font-family: system-ui, sans-serif; }
.pv-tick { font-size: 10px; fill: #555; }
.pv-axis-title { font-size: 11px; fill: #333; }
.pv-tip { position: absolute; display: none; pointer-events: none;
       background: rgba(255,255,255,0.94); border: 1px solid #bbb; border-radius: 3px;
       padding: 3px 6px; font-size: 11px;
       white-space: nowrap; z-index: 2; }
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
        if key.endswith("_s") and not isinstance(v, Mapping):  # seconds, whatever the section
            u = "s"
        elif isinstance(units, str):  # one unit for the values (initial, final...)
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
        rows = "".join(_rows(sec, sec.get("units")))
        parts.append(
            f'<h3 id="summary-{esc(k)}">{esc(title)}</h3>\n'
            + (f'<table class="summary">{rows}</table>' if rows else "<p>none</p>")
        )
    raw = json.dumps(summary, indent=2, default=str, allow_nan=True)
    parts.append(
        "<details><summary>raw summary (JSON, as in summary.json)</summary>"
        f"<pre>{esc(raw)}</pre></details>"
    )
    return "\n".join(parts)


# ----------------------------------------------------------------------------- page


def _accuracy_head(summary: Mapping[str, Any] | None) -> tuple[str, str]:
    """The pass/warn mark of the header line and the warnings listed under it, from
    ``summary["accuracy"]`` (docs/cli.md "Accuracy"); nothing without that section.

    >>> _accuracy_head({"accuracy": {"warnings": [], "drift_threshold": 1e-6}})[0]
    ' <span class="accuracy ok" id="poinsot-accuracy">accuracy: ok</span>'
    >>> mark, listed = _accuracy_head({"accuracy": {"warnings": ["K drifts by 0.1"]}})
    >>> "accuracy: 1 warning<" in mark, "<li>K drifts by 0.1</li>" in listed
    (True, True)
    """
    acc = summary.get("accuracy") if isinstance(summary, Mapping) else None
    if not isinstance(acc, Mapping) or "warnings" not in acc:
        return "", ""
    esc = html.escape
    warnings = [str(w) for w in acc.get("warnings") or ()]
    if not warnings:
        assessed = any(
            acc.get(k) is not None
            for k in ("drift_threshold", "attitude_threshold", "agreement_threshold")
        )
        text, cls = ("accuracy: ok", "ok") if assessed else ("accuracy: not checked", "none")
        return f' <span class="accuracy {cls}" id="poinsot-accuracy">{text}</span>', ""
    n = len(warnings)
    mark = (
        f' <span class="accuracy warn" id="poinsot-accuracy">'
        f"accuracy: {n} warning{'s' if n > 1 else ''}</span>"
    )
    items = "".join(f"<li>{esc(w)}</li>" for w in warnings)
    listed = (
        '<section id="poinsot-accuracy-warnings"><h2>Accuracy warnings</h2>'
        f'<ul class="warnings">{items}</ul><p class="note">The thresholds and what to '
        'change: docs/cli.md, "Accuracy".</p></section>\n'
    )
    return mark, listed


def page_html(
    *,
    title: str,
    meta: str,
    notes: Sequence[str],
    payload: dict[str, Any],
    summary: Mapping[str, Any] | None,
    sections: Sequence[tuple[str, str]] = (),
    speeds: Sequence[float] = (0.25, 0.5, 1, 2, 4, 8),
    animated: bool = True,
    lead: str = "",
) -> str:
    """The page: title with the accuracy mark of ``summary`` (``accuracy: ok`` or
    ``accuracy: N warnings``), meta line, the accuracy warnings, ``lead`` (trusted
    HTML), controls (if ``animated``), the viewer's figure (scene and charts from
    ``payload``), notes, extra sections, the summary."""
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
    if not animated:
        controls = ""
    mark, warned = _accuracy_head(summary)
    lead = warned + lead
    note_html = "".join(f'<p class="note">{esc(n)}</p>' for n in notes)
    table = "" if summary is None else summary_html(summary)
    extra = "".join(f"<h2>{esc(head)}</h2>\n<div>{content}</div>\n" for head, content in sections)
    table = extra + table
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{esc(title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n"
        f'<h1>{esc(title)}{mark}</h1>\n<p class="meta">{meta}</p>\n<p id="poinsot-error"></p>\n'
        f'{lead}{controls}\n<div id="{DIV_ID}"><div id="poinsot-scene-col"></div>'
        '<div id="poinsot-panels"></div></div>\n'
        f"{note_html}\n{table}\n"
        f'<script type="application/json" id="poinsot-data">{data}</script>\n'
        f"<script>{viewer_js()}</script>\n"
        "</body>\n</html>\n"
    )
