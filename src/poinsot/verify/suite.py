"""Run cases in an engine, sweep its settings, and write the verdict (docs/verify.md).

Outputs of :func:`write`: ``verify.json`` (settings, per-case metrics with their
thresholds and units, the sweep), ``verify.html`` (the table, the work-precision
chart, links to one page per case) and ``cases/CASE.html``: the report's viewer
(docs/cli.md) with the engine's motion, the exact one as the reference (dashed body
axes) and the error over time.
"""

from __future__ import annotations

import dataclasses
import html
import json
import math
import re
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._files import atomic_write
from ..errors import InvalidInputError
from ..plotting.report import write_report
from ..trajectory import Result
from ._basilisk import ADAPTIVE as BASILISK_ADAPTIVE
from ._drake import FIXED_STEP as DRAKE_FIXED_STEP
from .cases import CASES_VERSION, Case, cases
from .engines import make, run
from .metrics import METRICS, CaseResult

#: the statuses of a case, in the order the verdict counts them
STATUSES = ("pass", "fail", "missing", "skip")


@dataclass
class Verdict:
    """The results of one engine on a set of cases.

    ``passed`` is True when at least one case was scored, none failed, none is
    missing (unless ``allow_missing``) and, with ``require_all``, none was skipped
    (:meth:`problems` says why not). A skipped case is outside what the engine
    models (an orbit in MuJoCo); a missing case is one the engine should have
    given and did not (no file).
    """

    engine: str
    label: str
    results: list[CaseResult]
    sweep: list[dict[str, Any]] = field(default_factory=list)
    require_all: bool = False
    allow_missing: bool = False

    @property
    def counts(self) -> dict[str, int]:
        """``{"pass", "fail", "missing", "skip"} -> number of cases``."""
        return {s: sum(r.status == s for r in self.results) for s in STATUSES}

    def problems(self) -> list[str]:
        """Why the verdict is not a pass (empty when it is)."""
        c = self.counts
        out = []
        if c["pass"] + c["fail"] == 0:
            out.append(f"no case was scored ({len(self.results)} selected)")
        if c["fail"]:
            out.append(f"{c['fail']} case(s) failed")
        if c["missing"] and not self.allow_missing:
            out.append(f"{c['missing']} case(s) missing (--allow-missing to accept)")
        if c["skip"] and self.require_all:
            out.append(f"{c['skip']} case(s) skipped under --require-all")
        return out

    @property
    def passed(self) -> bool:
        return not self.problems()

    def summary(self) -> str:
        """The verdict line, e.g. ``PASS (4 passed, 0 failed, 0 missing, 8 skipped)``."""
        c = self.counts
        line = (
            f"{'PASS' if self.passed else 'FAIL'} ({c['pass']} passed, {c['fail']} failed, "
            f"{c['missing']} missing, {c['skip']} skipped)"
        )
        return line + ("" if self.passed else ": " + "; ".join(self.problems()))

    def to_json(self) -> dict[str, Any]:
        return {
            "engine": self.engine,
            "settings": self.label,
            "cases_version": CASES_VERSION,
            "passed": self.passed,
            "verdict": self.summary(),
            "problems": self.problems(),
            "policy": {"require_all": self.require_all, "allow_missing": self.allow_missing},
            "counts": self.counts,
            "results": [r.to_json() for r in self.results],
            "metrics": {k: {"units": u, "meaning": m} for k, (u, m) in METRICS.items()},
            "sweep": self.sweep,
            "docs": "docs/verify.md",
        }

    def table(self) -> str:
        """A plain-text table: case, status, each metric as value/threshold."""
        names = list(METRICS)
        head = ["case", "status"] + names
        rows = [head]
        for r in self.results:
            cells = [r.case, r.status.upper()]
            for n in names:
                m = r.metrics.get(n)
                cells.append(
                    "" if m is None else f"{m['value']:.1e}" + ("" if m["passed"] else "!")
                )
            rows.append(cells)
        rows.append(["threshold", ""] + [_thresholds(self.results, n) for n in names])
        widths = [max(len(row[k]) for row in rows) for k in range(len(head))]
        lines = [
            "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip() for row in rows
        ]
        notes = [f"  {r.case}: {r.status}: {r.reason}" for r in self.results if r.reason]
        units = ", ".join(f"{n} ({METRICS[n][0]})" for n in names)
        return "\n".join(
            lines + ([""] + notes if notes else []) + [f"units: {units}; ! over threshold"]
        )


def check(engine: Any, select: str | Iterable[str] | None = None,
          progress: Callable[[Case, CaseResult], object] | None = None, *,
          require_all: bool = False, allow_missing: bool = False) -> Verdict:  # fmt: skip
    """Run every selected case in ``engine`` and score it.

    Parameters
    ----------
    engine : engine object
        From :func:`poinsot.verify.make` (or any object with ``name``, ``label``,
        ``skip_reason`` and ``run``: see :mod:`poinsot.verify.engines`).
    select : str or iterable of str, optional
        Case names or groups; default all.
    progress : callable, optional
        Called with ``(case, result)`` after each case.
    require_all : bool, optional
        A skipped case (outside what the engine models) fails the verdict.
    allow_missing : bool, optional
        A missing case (e.g. no file) does not fail the verdict.

    Returns
    -------
    Verdict

    Examples
    --------
    >>> from poinsot.verify import make
    >>> from poinsot.verify.suite import check
    >>> v = check(make("mujoco"), "orbit")   # MuJoCo cannot express an orbit: skipped
    >>> [r.status for r in v.results], v.passed     # and no case scored is no pass
    (['skip', 'skip'], False)
    >>> v.problems()
    ['no case was scored (2 selected)']
    """
    out = []
    for case in cases(select):
        res = run(engine, case)
        out.append(res)
        if progress is not None:
            progress(case, res)
    return Verdict(engine.name, engine.label, out, require_all=require_all,
                   allow_missing=allow_missing)  # fmt: skip


#: the setting a sweep varies, per engine (and its default values)
SWEEPS: dict[str, tuple[str, tuple[float, ...]]] = {
    "scipy": ("rtol", (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)),
    "poinsot": ("step", (0.01, 0.005, 0.002, 0.001, 0.0005)),
    "mujoco": ("timestep", (0.01, 0.005, 0.002, 0.001, 0.0005)),
    "pybullet": ("timestep", (0.01, 0.005, 0.002, 0.001, 0.0005)),
    "drake": ("accuracy", (1e-8, 1e-10, 1e-12, 1e-14)),
    "basilisk": ("timestep", (0.01, 0.005, 0.002, 0.001, 0.0005)),
}


def sweep(engine: str, values: Sequence[float] | None = None,
          select: str | Iterable[str] | None = None,
          **options: Any) -> list[dict[str, Any]]:  # fmt: skip
    """Work-precision: run the cases at each value of the engine's setting.

    The setting is ``rtol`` (SciPy, and poinsot with an adaptive method), ``step``
    (poinsot's fixed-step methods), ``timestep`` (MuJoCo, PyBullet) or ``accuracy``
    (Drake; ``step`` with a fixed step or a fixed-step scheme), ``timestep`` (Basilisk;
    ``rtol`` with its adaptive ``RKF45``/``RKF78``): :data:`SWEEPS`.

    Returns
    -------
    list of dict
        One per (value, case): ``{"setting", "value", "case", "error", "units",
        "threshold", "seconds", "work", "status"}``, ``error`` the attitude error (rad)
        of a rigid body or the relative position error of a point, ``threshold`` its
        threshold.
    """
    if engine not in SWEEPS:
        raise InvalidInputError(
            f"Expected an engine with a sweep ({', '.join(SWEEPS)}), got {engine!r}."
        )
    key, default = SWEEPS[engine]
    if engine == "poinsot" and options.get("method") in ("dop853", "adaptive"):
        key, default = "rtol", SWEEPS["scipy"][1]
    if engine == "drake" and (options.get("step") is not None
                              or options.get("integrator") in DRAKE_FIXED_STEP):  # fmt: skip
        key, default = "step", SWEEPS["mujoco"][1]
        options = {k: v for k, v in options.items() if k != "accuracy"}
    if engine == "basilisk" and options.get("integrator") in BASILISK_ADAPTIVE:
        key, default = "rtol", (1e-6, 1e-8, 1e-10, 1e-12)
        options = {k: v for k, v in options.items() if k != "rtol"}
    rows: list[dict[str, Any]] = []
    for value in default if values is None else values:
        eng = make(engine, **{**options, key: float(value)})
        for case in cases(select):
            t0 = time.perf_counter()
            res = run(eng, case)
            if res.status in ("skip", "missing"):
                continue
            err_key = "attitude" if "attitude" in res.metrics else "position"
            rows.append({
                "setting": key, "value": float(value), "case": case.name,
                "error": res.metrics[err_key]["value"], "units": METRICS[err_key][0],
                "threshold": res.metrics[err_key]["threshold"],
                "seconds": res.seconds or time.perf_counter() - t0, "work": res.work,
                "status": res.status,
            })  # fmt: skip
    return rows


def write(verdict: Verdict, out: str | Path, *, pages: bool = True) -> list[Path]:
    """Write ``verify.json``, ``verify.html`` and (``pages``) ``cases/CASE.html`` to ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "verify.json"]
    text = json.dumps(verdict.to_json(), indent=2, allow_nan=False, default=_json) + "\n"
    atomic_write(files[0], lambda fh: fh.write(text))
    links: dict[str, str] = {}
    if pages:
        (out / "cases").mkdir(exist_ok=True)
        for res in verdict.results:
            if res.status in ("skip", "missing") or not res.errors:
                continue
            p = _case_page(verdict, res, out / "cases" / f"{res.case}.html")
            if p is not None:
                links[res.case] = f"cases/{p.name}"
                files.append(p)
    page = out / "verify.html"
    index = _index_page(verdict, links)
    atomic_write(page, lambda fh: fh.write(index))
    files.append(page)
    return files


def _json(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(type(x).__name__)


def _case_page(verdict: Verdict, res: CaseResult, path: Path) -> Path | None:
    case = cases(res.case)[0]
    states = res.states
    if not states or not all(np.all(np.isfinite(v)) for v in states.values()):
        return None  # nothing to draw (a diverged engine): the index page has its figures
    if not isinstance(res.result, Result):  # an attitude estimate: its errors, not a motion
        return _estimate_page(verdict, res, path)
    title = f"poinsot verify: {case.name} in {verdict.label}"
    summary = {"verdict": {k: v["value"] for k, v in res.metrics.items()} | {"status": res.status},
               "thresholds": {k: v["threshold"] for k, v in res.metrics.items()}}  # fmt: skip
    got = dataclasses.replace(res.result, method=verdict.label)  # type: ignore[type-var]
    return write_report(path, trajectory=got, title=title, summary=summary,
                        **case.spec.report_options(case, res.errors))  # fmt: skip


def _estimate_page(verdict: Verdict, res: CaseResult, path: Path) -> Path | None:
    """The page of an estimation case: its metrics, the attitude error and the NEES
    against time with their thresholds and the NEES band (docs/verify.md)."""
    esc = html.escape
    t = res.errors.get("t")
    if t is None or "attitude" not in res.errors:
        return None
    rows = []
    for name, m in res.metrics.items():
        limit = f"{m['threshold']:.3g}"
        if m.get("minimum") is not None:
            limit = f"{m['minimum']:.3g} .. {limit}"
        cls = "ok" if m["passed"] else "bad"
        rows.append(
            f"<tr><td>{esc(name)}</td><td>{esc(METRICS[name][0])}</td>"
            f'<td class="{cls}">{m["value"]:.3g}</td><td>{esc(limit)}</td></tr>'
        )
    att = res.metrics.get("attitude")
    limits = [(att["threshold"], "threshold (second half)")] if att else []
    charts = [_time_svg(t, res.errors["attitude"], "attitude error (rad)", limits)]
    nees = res.metrics.get("nees")
    if "nees" in res.errors and nees is not None:
        lines = [(nees["threshold"], "band, upper"), (nees["value"], "time average")]
        lines += [(nees["minimum"], "band, lower")] if nees.get("minimum") else []
        charts.append(_time_svg(t, res.errors["nees"], "NEES (3 dof)", lines))
    title = f"poinsot verify: {res.case} in {getattr(res.result, 'method', verdict.label)}"
    text = f"""<!doctype html><html><head><meta charset="utf-8"><title>{esc(title)}</title>
<style>body{{font-family:system-ui,sans-serif;margin:2em;max-width:60em}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:.25em .5em}}
.ok{{background:#e8f5e9}}.bad{{background:#ffebee}}</style>
</head><body><h1>{esc(title)}</h1><p>Status: <b>{esc(res.status)}</b>. {esc(res.reason)}</p>
<table><tr><th>metric</th><th>units</th><th>value</th><th>threshold</th></tr>
{"".join(rows)}</table>
{"".join(charts)}
<p>The attitude error is the rotation angle between the exact attitude and the estimate;
NEES = sum_i (e_i / s_i)^2 over body axes, e the attitude error vector and s the estimator's
1-sigma. Metrics, thresholds and the NEES band: docs/verify.md (poinsot's documentation); the
exact motion: docs/theory.md §9.</p></body></html>
"""
    atomic_write(path, lambda fh: fh.write(text))
    return path


def _time_svg(t: np.ndarray, y: np.ndarray, label: str,
              lines: Sequence[tuple[float, str]]) -> str:  # fmt: skip
    """A chart of ``y`` (log scale) against time ``t`` (s), with labelled horizontal lines.

    Series longer than 2500 samples are drawn as the largest value of each of at most
    2500 bins, so that no spike of the error is lost to the thinning."""
    t = np.asarray(t, dtype=float)
    y = np.maximum(np.asarray(y, dtype=float), 1e-17)
    ok = np.isfinite(y)
    t, y = t[ok], y[ok]
    if t.size == 0:
        return ""
    t0 = float(t[0])
    t1 = float(t[-1]) if t[-1] > t[0] else t0 + 1.0
    k = -(-t.size // 2500)  # samples per bin
    starts = np.arange(0, t.size, k)
    t, y = t[starts], np.maximum.reduceat(y, starts)
    w, h, pad = 640, 280, 40
    ly = np.log10(np.concatenate([y, [v for v, _ in lines if v > 0]]))
    y0, y1 = math.floor(ly.min()), math.ceil(ly.max()) + (ly.min() == ly.max())

    def sx(v: float) -> float:
        return pad + (v - t0) / (t1 - t0) * (w - 2 * pad)

    def sy(v: float) -> float:
        return h - pad - (math.log10(v) - y0) / (y1 - y0) * (h - 2 * pad)

    parts = [f'<h2>{html.escape(label)}</h2><svg xmlns="http://www.w3.org/2000/svg" '
             f'width="{w}" height="{h}" role="img">']  # fmt: skip
    for e in range(y0, y1 + 1):
        ye = sy(10.0**e)
        parts.append(
            f'<line x1="{pad}" x2="{w - pad}" y1="{ye:.1f}" y2="{ye:.1f}" stroke="#eee"/>'
            f'<text x="{pad - 6}" y="{ye + 4:.1f}" font-size="11" text-anchor="end">1e{e}</text>'
        )
    for v in np.linspace(t0, t1, 5):
        parts.append(f'<text x="{sx(v):.1f}" y="{h - pad + 14}" font-size="11" '
                     f'text-anchor="middle">{v:.3g}</text>')  # fmt: skip
    xy = " ".join(f"{sx(a):.1f},{sy(b):.1f}" for a, b in zip(t, y, strict=True))
    parts.append(f'<polyline fill="none" stroke="#1f77b4" points="{xy}"/>')
    for v, name in lines:
        if v > 0:
            parts.append(f'<line x1="{pad}" x2="{w - pad}" y1="{sy(v):.1f}" y2="{sy(v):.1f}" '
                         f'stroke="#000" stroke-dasharray="6 4"/><text x="{w - pad - 4}" '
                         f'y="{sy(v) - 4:.1f}" font-size="11" text-anchor="end">'
                         f"{html.escape(name)} {v:.3g}</text>")  # fmt: skip
    parts.append(
        f'<text x="{w / 2}" y="{h - 6}" font-size="11" text-anchor="middle">time (s)</text></svg>'
    )
    return "".join(parts)


def _thresholds(results: list[CaseResult], name: str) -> str:
    """The threshold(s) of metric ``name`` over the scored cases (e.g. ``"1.0e-06"``)."""
    values = sorted({(r.metrics[name].get("minimum"), r.metrics[name]["threshold"])
                     for r in results if name in r.metrics}, key=lambda b: b[1])  # fmt: skip
    return " / ".join(f"{v:.1e}" if lo is None else f"{lo:.1e}..{v:.1e}" for lo, v in values)


def _index_page(verdict: Verdict, links: dict[str, str]) -> str:
    esc = html.escape
    names = list(METRICS)
    head = "".join(f"<th>{esc(n)}<br><small>{esc(METRICS[n][0])}</small></th>" for n in names)
    limits = "".join(f'<td class="num">{esc(_thresholds(verdict.results, n))}</td>' for n in names)
    rows = []
    for r in verdict.results:
        cells = []
        for n in names:
            m = r.metrics.get(n)
            if m is None:
                cells.append("<td></td>")
            else:
                cls = "ok" if m["passed"] else "bad"
                cells.append(
                    f'<td class="num {cls}" title="threshold {m["threshold"]:.1e}">'
                    f"{m['value']:.1e}</td>"
                )
        name = (
            f'<a href="{esc(links[r.case])}">{esc(r.case)}</a>' if r.case in links else esc(r.case)
        )
        rows.append(f'<tr><td>{name}</td><td class="{r.status}">{r.status}</td>{"".join(cells)}'
                    f'<td class="note">{_unbroken_numbers(r.reason)}</td></tr>')  # fmt: skip
    verdict_line = esc(verdict.summary())
    chart = _work_precision_svg(verdict.sweep) if verdict.sweep else ""
    title = f"poinsot verify: {esc(verdict.label)}"
    return f"""<!doctype html><html><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:system-ui,sans-serif;margin:2em;max-width:90em}}table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:.25em .5em;text-align:right;white-space:nowrap}}
td:first-child{{text-align:left}}td.note{{text-align:left;white-space:normal;min-width:20em}}
span.n{{white-space:nowrap}}
tr.limits td{{background:#f5f5f5;font-style:italic}}
.ok{{background:#e8f5e9}}.bad,.fail,.missing{{background:#ffebee}}.skip{{color:#777}}</style></head><body>
<h1>poinsot verify</h1><p><b>{esc(verdict.label)}</b>, cases version {CASES_VERSION}:
<b>{verdict_line}</b></p>
<table><tr><th>case</th><th>status</th>{head}<th>note</th></tr>
<tr class="limits"><td>threshold</td><td></td>{limits}<td class="note">a value passes when it is
at most its threshold</td></tr>{"".join(rows)}</table>
<p>Statuses: pass, fail, missing (no states from the engine: fails the verdict unless
allowed), skip (outside what the engine models). Metrics and thresholds: docs/verify.md
(poinsot's documentation); the exact solutions: docs/theory.md §9-§10.
Quaternions scalar first, body -> space; angular velocity in body axes; SI units, radians.</p>
{chart}</body></html>
"""


#: a number as the notes write it (``9.86e-05``, ``0.00153``, ``-3``)
_NUMBER = re.compile(r"[-+]?\d[\d.]*(?:e[-+]?\d+)?")


def _unbroken_numbers(text: str) -> str:
    """``text`` as HTML, each number in a ``span.n`` that never breaks: a browser
    breaks lines after the ``-`` of ``9.86e-05`` otherwise.

    >>> _unbroken_numbers("omega 9.86e-05 > 1e-06 'x'")
    'omega <span class="n">9.86e-05</span> &gt; <span class="n">1e-06</span> &#x27;x&#x27;'
    """
    out, last = [], 0
    for m in _NUMBER.finditer(text):  # escaped piece by piece: no span inside an entity
        out += [html.escape(text[last : m.start()]), f'<span class="n">{m.group(0)}</span>']
        last = m.end()
    return "".join(out) + html.escape(text[last:])


def _work_precision_svg(rows: list[dict[str, Any]]) -> str:
    """A log-log chart of error against work (right-hand-side evaluations or steps)."""
    pts = [r for r in rows if r["work"] and r["error"] > 0 and math.isfinite(r["error"])]
    if not pts:
        return ""
    names = list(dict.fromkeys(p["case"] for p in pts))
    thresholds = sorted({float(p["threshold"]) for p in pts if p.get("threshold")})
    plot_w, h, pad = 640, 400, 56
    legend = 16 + 7 * max(len(n) for n in names)  # 11 px text: under 7 px a character
    w = plot_w + legend
    lx = np.log10([p["work"] for p in pts])
    ly = np.log10([max(p["error"], 1e-17) for p in pts] + thresholds)
    x0, x1 = math.floor(lx.min()), math.ceil(lx.max()) + (lx.min() == lx.max())
    y0, y1 = math.floor(ly.min()), math.ceil(ly.max()) + (ly.min() == ly.max())

    def sx(v: float) -> float:
        return pad + (v - x0) / (x1 - x0) * (plot_w - 2 * pad)

    def sy(v: float) -> float:
        return h - pad - (v - y0) / (y1 - y0) * (h - 2 * pad)

    def text(x: float, y: float, s: str, anchor: str = "middle", extra: str = "") -> str:
        return (
            f'<text x="{x:.1f}" y="{y:.1f}" font-size="11" text-anchor="{anchor}" {extra}>'
            f"{html.escape(s)}</text>"
        )

    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
               "#7f7f7f", "#bcbd22", "#17becf", "#000000", "#aec7e8"]  # fmt: skip
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" role="img">']
    for k in range(x0, x1 + 1):
        parts.append(text(sx(k), h - pad + 18, f"1e{k}"))
    for k in range(y0, y1 + 1):
        parts.append(text(pad - 6, sy(k) + 4, f"1e{k}", "end"))
        parts.append(f'<line x1="{pad}" x2="{plot_w - pad}" y1="{sy(k):.1f}" y2="{sy(k):.1f}" '
                     'stroke="#eee"/>')  # fmt: skip
    for thr in thresholds:
        y = sy(math.log10(thr))
        parts.append(f'<line x1="{pad}" x2="{plot_w - pad}" y1="{y:.1f}" y2="{y:.1f}" '
                     'stroke="#000" stroke-dasharray="6 4"/>')  # fmt: skip
        parts.append(text(plot_w - pad - 4, y - 4, f"threshold {thr:.0e}", "end"))
    for j, name in enumerate(names):
        mine = sorted((p for p in pts if p["case"] == name), key=lambda p: p["work"])
        xy = " ".join(
            f"{sx(math.log10(p['work'])):.1f},{sy(math.log10(max(p['error'], 1e-17))):.1f}"
            for p in mine
        )
        c = colours[j % len(colours)]
        parts.append(f'<polyline fill="none" stroke="{c}" points="{xy}">'
                     f"<title>{html.escape(name)}</title></polyline>")  # fmt: skip
        parts.append(text(plot_w - pad + 12, pad + 14 * j, name, "start", f'fill="{c}"'))
    units = pts[0]["units"]
    parts.append(text(plot_w / 2, h - 8, "work (evaluations or steps)"))
    parts.append(text(14, h / 2, f"largest error ({units})", "middle",
                      f'transform="rotate(-90 14 {h / 2})"'))  # fmt: skip
    return "<h2>Work-precision</h2>" + "".join(parts) + "</svg>"
