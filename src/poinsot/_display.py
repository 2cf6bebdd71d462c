"""Rich display in Jupyter: small HTML tables and inline SVG charts.

The ``_repr_html_`` of poinsot's objects (rotations, bodies, exact solutions,
results) are thin methods over these helpers. Everything is plain HTML and inline
SVG: no JavaScript, nothing fetched from a network; every string is escaped. A
display must never break a notebook: :func:`safe_html` falls back to the escaped
``repr`` if building the HTML fails. Cheap by construction: callers pass the first
rows of a batch only, and :func:`sparkline` keeps at most ``max_points`` samples.
"""

from __future__ import annotations

import functools
import html
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")
_STYLE = "border-collapse:collapse;font-size:12px;font-family:system-ui,sans-serif;margin:2px 0"


#: Relative size below which a component is round-off noise and printed as 0.
NOISE = 1e-12


def clean(values: Any, scale: float | None = None) -> np.ndarray:
    """``values`` with the entries smaller than ``NOISE * scale`` set to 0
    (``scale``: the largest ``|value|`` by default); ``-0.0`` becomes ``0.0``.

    Examples
    --------
    >>> clean([1.0, 2.2e-16, -0.0]).tolist()
    [1.0, 0.0, 0.0]
    """
    a = np.array(values, dtype=float, copy=True)
    if scale is None:
        finite = a[np.isfinite(a)]
        scale = float(np.max(np.abs(finite), initial=0.0))
    a[np.abs(a) < NOISE * scale] = 0.0
    return a + 0.0


def esc(x: object) -> str:
    """HTML-escaped ``str(x)``."""
    return html.escape(str(x), quote=True)


def num(v: Any, digits: int = 6) -> str:
    """A number (or array) with ``digits`` significant digits, plain text.

    >>> num(3.14159265), num([1.0, 2.5e-9]), num(float("inf"))
    ('3.14159', '[1, 2.5e-09]', 'inf')
    """
    a = np.asarray(v)
    if a.ndim == 0:
        x = a.item()
        if isinstance(x, bool | np.bool_):
            return str(bool(x))
        if isinstance(x, int | np.integer):
            return str(int(x))
        if isinstance(x, float | np.floating):
            return f"{float(x):.{digits}g}" if math.isfinite(float(x)) else str(float(x))
        return str(x)
    return "[" + ", ".join(num(x, digits) for x in a.reshape(-1)[:12]) + (
        ", ..." if a.size > 12 else "") + "]"  # fmt: skip


def value(v: Any, units: str = "", digits: int = 6) -> str:
    """``num(v)`` with its units, escaped, as HTML."""
    text = num(v, digits)
    return esc(text) + (f" <span style='color:#666'>{esc(units)}</span>" if units else "")


def table(title: str, rows: Sequence[tuple[str, str]], note: str = "", extra: str = "") -> str:
    """A two-column table ``(label, html value)`` under a bold title.

    ``rows`` values are HTML (already escaped by :func:`value` or :func:`esc`);
    labels and ``title``/``note`` are escaped here.
    """
    body = "".join(
        f"<tr><th style='text-align:left;padding:1px 8px 1px 0;font-weight:600;"
        f"vertical-align:top'>{esc(k)}</th><td style='text-align:left;padding:1px 0'>{v}</td></tr>"
        for k, v in rows
    )
    foot = f"<div style='color:#666;font-size:11px'>{esc(note)}</div>" if note else ""
    return (
        f"<div class='poinsot-repr'><b style='font-family:system-ui,sans-serif'>{esc(title)}"
        f"</b><table style='{_STYLE}'>{body}</table>{extra}{foot}</div>"
    )


def matrix(m: Any, digits: int = 6) -> str:
    """A small matrix as an HTML table of numbers."""
    a = np.atleast_2d(np.asarray(m, dtype=float))
    cell = "<td style='text-align:right;padding:0 6px;font-family:monospace'>"
    rows = "".join(
        "<tr>" + "".join(f"{cell}{esc(num(x, digits))}</td>" for x in row) + "</tr>" for row in a
    )
    return f"<table style='{_STYLE}'>{rows}</table>"


def grid(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A table with a header row; cells are HTML (escape them first)."""
    head = "".join(f"<th style='padding:1px 6px;text-align:right'>{esc(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td style='padding:1px 6px;text-align:right;font-family:monospace'>"
                         f"{c}</td>" for c in row) + "</tr>"
        for row in rows
    )  # fmt: skip
    return f"<table style='{_STYLE}'><tr>{head}</tr>{body}</table>"


def sparkline(
    t: Any,
    series: Mapping[str, Any],
    units: str = "",
    *,
    width: int = 360,
    height: int = 90,
    max_points: int = 240,
) -> str:
    """A small inline SVG line chart of ``series`` (label -> values (n,)) against ``t``.

    At most ``max_points`` samples per line (evenly strided); non-finite values are
    dropped. Returns ``""`` when there is nothing to draw.

    >>> import numpy as np
    >>> svg = sparkline(np.linspace(0, 1, 5000), {"x": np.linspace(0, 1, 5000)}, "m")
    >>> svg.startswith("<svg"), svg.count(" L") < 240
    (True, True)
    """
    tt = np.asarray(t, dtype=float).reshape(-1)
    if tt.size < 2 or not series:
        return ""
    step = max(1, math.ceil(tt.size / max_points))
    idx = np.arange(0, tt.size, step)
    if idx[-1] != tt.size - 1:
        idx = np.append(idx, tt.size - 1)
    lines = {k: np.asarray(v, dtype=float).reshape(tt.size, -1)[idx, 0] for k, v in series.items()}
    finite = [y[np.isfinite(y)] for y in lines.values()]
    if not any(f.size for f in finite):
        return ""
    lo = min(float(f.min()) for f in finite if f.size)
    hi = max(float(f.max()) for f in finite if f.size)
    if hi == lo:
        lo, hi = lo - 0.5, hi + 0.5
    x0, x1 = float(tt[0]), float(tt[-1])
    pad_l, pad_b, pad_t = 48, 14, 4
    w, h = width - pad_l - 4, height - pad_b - pad_t

    def sx(x: np.ndarray) -> np.ndarray:
        return pad_l + (x - x0) / (x1 - x0 or 1.0) * w

    def sy(y: np.ndarray) -> np.ndarray:
        return pad_t + (hi - y) / (hi - lo) * h

    parts = [
        f"<svg xmlns='http://www.w3.org/2000/svg' width='{width}' height='{height}' "
        f"style='font:10px sans-serif'>",
        f"<rect x='{pad_l}' y='{pad_t}' width='{w}' height='{h}' fill='none' stroke='#ddd'/>",
        f"<text x='{pad_l - 3}' y='{pad_t + 8}' text-anchor='end'>{esc(num(hi, 3))}</text>",
        f"<text x='{pad_l - 3}' y='{pad_t + h}' text-anchor='end'>{esc(num(lo, 3))}</text>",
        f"<text x='{pad_l}' y='{height - 2}'>{esc(num(x0, 3))} s</text>",
        f"<text x='{pad_l + w}' y='{height - 2}' text-anchor='end'>{esc(num(x1, 3))} s</text>",
    ]
    xs = sx(tt[idx])
    for k, (label, y) in enumerate(lines.items()):
        ok = np.isfinite(y)
        if not ok.any():
            continue
        ys = sy(y)
        pts = [f"{x:.1f} {v:.1f}" for x, v, g in zip(xs, ys, ok, strict=True) if g]
        c = COLOURS[k % len(COLOURS)]
        parts.append(f"<path d='M{' L'.join(pts)}' fill='none' stroke='{c}' stroke-width='1.2'>"
                     f"<title>{esc(label)}</title></path>")  # fmt: skip
        parts.append(
            f"<text x='{pad_l + 4 + 46 * k}' y='{pad_t + 10}' fill='{c}'>{esc(label)}</text>"
        )
    if units:
        parts.append(f"<text x='2' y='{pad_t + h / 2:.0f}' fill='#666'>{esc(units)}</text>")
    parts.append("</svg>")
    return "".join(parts)


def safe_html(fn: Callable[[Any], str]) -> Callable[[Any], str]:
    """Wrap a ``_repr_html_``: on any error, the escaped ``repr`` (a display never raises)."""

    @functools.wraps(fn)
    def wrapper(self: Any) -> str:
        import warnings

        try:
            with warnings.catch_warnings():  # e.g. gimbal lock of displayed angles
                warnings.simplefilter("ignore")
                return fn(self)
        except Exception as exc:  # noqa: BLE001 - the notebook must keep working
            return f"<pre>{esc(repr(self))}</pre><!-- poinsot display failed: {esc(exc)} -->"

    return wrapper
