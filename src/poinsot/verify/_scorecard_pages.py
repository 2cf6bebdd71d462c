"""The Markdown pages and work-precision charts of the scorecard
(:mod:`poinsot.verify.scorecard`); written from the stored rows alone, so that
``poinsot verify scorecard --from-json`` regenerates them without any engine."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._files import atomic_write
from .scorecard import CHART_CASES, STEP_SETTINGS, diagnose, fmt_setting

if TYPE_CHECKING:
    from .scorecard import EngineCard, Scorecard, Sweep

COMMAND = (
    "poinsot verify scorecard --out docs/verify/scorecard   "
    "# runs every installed engine (< 10 min on 2 cores)\n"
    "poinsot verify scorecard --from-json docs/verify/scorecard/scorecard.json "
    "--out docs/verify/scorecard   # the pages only, no engine"
)


def _e(x: Any) -> str:
    """A number as the pages write it (``1.04e-02``; ``inf``; ``-`` for none)."""
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    return f"{x:.2e}" if x != 0 else "0"


def _err(row: dict[str, Any]) -> tuple[str, float, float]:
    key = "attitude" if "attitude" in row["metrics"] else "position"
    m = row["metrics"][key]
    return key, float(m["value"]), float(m["threshold"])


def _unit(key: str) -> str:
    return " rad" if key == "attitude" else " (relative)"


def _chart_cases(card: EngineCard) -> list[str]:
    scored = card.cases()
    out = [c for c in CHART_CASES if c in scored][:3]
    return out or scored[:1]


def _default_row(card: EngineCard, sweep: Sweep, case: str) -> dict[str, Any] | None:
    for r in card.series(sweep, case):
        if math.isclose(r["value"], sweep.default, rel_tol=1e-9):
            return r
    return None


def engine_page(card: EngineCard, cases_version: str) -> str:
    """The Markdown page of one engine version."""
    title = f"{card.engine} {card.version or '(not installed)'}"
    lines = [f"# Scorecard: {title}", ""]
    lines += [
        f"Cases version {cases_version}. Every integrator of the engine on every case "
        "it models, over a sweep of its step or tolerance, against the exact "
        "solutions ([poinsot verify](../../verify.md)). Regenerate:",
        "",
        "```console",
        COMMAND,
        "```",
        "",
    ]
    if card.reason:
        return "\n".join(lines + [f"Not run: {card.reason}.", ""])
    lines += ["| integrator | setting | values (coarsest first) | default |",
              "|---|---|---|---|"]  # fmt: skip
    for s in card.sweeps:
        vals = ", ".join(fmt_setting(s.setting, v) for v in s.values)
        lines.append(f"| {s.integrator} | {s.setting} | {vals} | "
                     f"{fmt_setting(s.setting, s.default)} |")  # fmt: skip
    scored = card.cases()
    sweeps = [s for s in card.sweeps if any(card.series(s, c) for c in scored)]
    lines += ["", "## Cases x integrators", "",
              "Each cell: the first (coarsest) setting from which the integrator passes "
              "every metric of the case (`-`: none swept); the verdict at the adapter's "
              "default setting (`-`: not run there); the energy drift per revolution "
              "(`/rev`, the case's period) or per second (`/s`) at the finest setting.",
              "",
              "| case | " + " | ".join(s.integrator for s in sweeps) + " |",
              "|---" * (len(sweeps) + 1) + "|"]  # fmt: skip
    diags: dict[tuple[str, str], dict[str, Any]] = {}
    for case in scored:
        cells = [case]
        for s in sweeps:
            rows = card.series(s, case)
            if not rows:
                cells.append("skip")
                continue
            d = diagnose(s.setting, rows)
            diags[s.integrator, case] = d
            first = "-" if d["first"] is None else fmt_setting(s.setting, d["first"])
            dr = _default_row(card, s, case)
            default = "-" if dr is None else dr["status"]
            fin = rows[-1]
            cells.append(f"{first}; {default}; {_e(fin['energy_per'])}/{fin['drift_unit']}")
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "## What fails and why", ""]
    lines += _findings(card, sweeps, scored, diags)
    skipped = card.skipped()
    if skipped:
        lines += ["", "## Cases not run", ""]
        for case, why in skipped.items():
            lines.append(f"- {case}: {why}")
    charts = _chart_cases(card)
    if charts:
        lines += ["", "## Work-precision", "",
                  "The largest attitude error (rad; relative position error for a point) "
                  "against the engine's own count of work (steps for MuJoCo, PyBullet and "
                  "poinsot's fixed-step methods, derivative evaluations otherwise), "
                  "log-log, the dashed line the threshold.", ""]  # fmt: skip
        for c in charts:
            lines += [f"![{c}]({card.slug}-{c}.png)", ""]
    lines += ["## Every run", "",
              "| integrator | setting | case | status | error | energy drift | "
              "momentum drift | work | seconds |",
              "|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in card.rows:
        if "metrics" not in r:
            continue
        key, err, _ = _err(r)
        u = r["drift_unit"]
        lines.append(
            f"| {r['integrator']} | {fmt_setting(r['setting'], r['value'])} | {r['case']} | "
            f"{r['status']} | {_e(err)}{_unit(key)} | {_e(r['energy_per'])}/{u} | "
            f"{_e(r['momentum_per'])}/{u} | {r['work'] if r['work'] is not None else '-'} | "
            f"{r['seconds']:.2f} |"
        )
    return "\n".join(lines) + "\n"


def _findings(card: EngineCard, sweeps: list[Sweep], scored: list[str],
              diags: dict[tuple[str, str], dict[str, Any]]) -> list[str]:  # fmt: skip
    """The plain summary: per integrator, which cases fail and why (from the data)."""
    out: list[str] = []
    for s in sweeps:
        mine = {c: diags[s.integrator, c] for c in scored if (s.integrator, c) in diags}
        if not mine:
            continue
        fails = {c: d for c, d in mine.items() if d["kind"] != "pass"}
        orders = [d["order"] for d in mine.values() if d["order"] is not None]
        order_text = ""
        if orders:
            what = "order" if s.setting in STEP_SETTINGS else f"slope against {s.setting}"
            order_text = f" Observed {what}: {min(orders):.1f} to {max(orders):.1f}."
        if not fails:
            worst = min((d["first"] for d in mine.values()), default=None)
            out.append(f"- **{s.integrator}** passes all {len(mine)} cases, each from the "
                       f"setting of the table on, all of them from "
                       f"{fmt_setting(s.setting, worst)}.{order_text}")  # fmt: skip
            continue
        out.append(f"- **{s.integrator}** fails {len(fails)} of {len(mine)} cases at the "
                   f"finest setting swept.{order_text}")  # fmt: skip
        for case, d in fails.items():
            rows = card.series(s, case)
            dr = _default_row(card, s, case) or rows[-1]
            key, err, thr = _err(dr)
            where = fmt_setting(s.setting, dr["value"])
            text = f"{s.integrator} at {where}: {_e(err)}{_unit(key)} on {case} - {d['text']}"
            fixed = _fixed_pass(card, s, case)
            if fixed:
                text += f"; the same integrator at a fixed step passes from {fixed}"
            if d["energy_growth"]:
                text += (
                    "; energy growth (the energy grows past its threshold where the "
                    "attitude is within 10x of its own)"
                )
            bad = [k for k, m in rows[-1]["metrics"].items() if not m["passed"]]
            text += f" (failing at {fmt_setting(s.setting, rows[-1]['value'])}: {', '.join(bad)})"
            out.append(f"  - {text}")
    return out or ["Nothing was scored."]


def _fixed_pass(card: EngineCard, sweep: Sweep, case: str) -> str:
    """The first passing fixed step of the same integrator on ``case`` ("" if none)."""
    if sweep.setting in STEP_SETTINGS:
        return ""
    for s in card.sweeps:
        if s.setting in STEP_SETTINGS and dict(s.options) == dict(sweep.options):
            rows = card.series(s, case)
            if rows:
                d = diagnose(s.setting, rows)
                if d["first"] is not None:
                    return fmt_setting(s.setting, d["first"])
    return ""


def index_page(sc: Scorecard) -> str:
    """The index of the scorecard: one line per engine, links to the pages."""
    lines = ["# Scorecard of the engines", "",
             f"Cases version {sc.cases_version}: every installed engine's integrators on "
             "every case over a sweep of steps or tolerances, scored against the exact "
             "solutions ([poinsot verify](../../verify.md)). Regenerate:", "",
             "```console", COMMAND, "```", "",
             "| engine | version | integrators | cases scored | passing at the finest "
             "setting | seconds |", "|---|---|---|---|---|---|"]  # fmt: skip
    for card in sc.cards:
        if card.reason:
            lines.append(f"| {card.engine} | - | - | - | not run: {card.reason} | - |")
            continue
        scored = card.cases()
        per = []
        for s in card.sweeps:
            rows = [card.series(s, c) for c in scored]
            rows = [r for r in rows if r]
            if rows:
                ok = sum(r[-1]["status"] == "pass" for r in rows)
                per.append(f"{s.integrator} {ok}/{len(rows)}")
        link = f"[{card.engine}]({card.slug}.md)"
        lines.append(f"| {link} | {card.version} | {len(card.sweeps)} | {len(scored)} | "
                     f"{', '.join(per)} | {card.seconds:.0f} |")  # fmt: skip
    lines += ["", "```{toctree}", ":hidden:", ""]
    lines += [f"{c.slug}" for c in sc.cards if not c.reason]
    lines += ["```", ""]
    return "\n".join(lines)


def chart(card: EngineCard, case: str, path: Path) -> Path:
    """The work-precision chart (PNG) of ``case``: error vs work per integrator."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.6, 3.6), dpi=80)
    ax = fig.add_subplot()
    thr = None
    key = "attitude"
    for s in card.sweeps:
        rows = [r for r in card.series(s, case) if r["work"]]
        if not rows:
            continue
        key, _, thr = _err(rows[0])
        pts = sorted((r["work"], max(_err(r)[1], 1e-17)) for r in rows
                     if math.isfinite(_err(r)[1]))  # fmt: skip
        if pts:
            x, y = zip(*pts, strict=True)
            ax.loglog(x, y, marker="o", ms=3, lw=1, label=s.integrator)
    if thr is not None:
        ax.axhline(thr, color="k", ls="--", lw=0.8, label=f"threshold {thr:g}")
    ax.set_xlabel("work (steps or evaluations)")
    ax.set_ylabel("largest attitude error (rad)" if key == "attitude" else
                  "largest position error (rel.)")  # fmt: skip
    ax.set_title(f"{card.engine} {card.version}: {case}", fontsize=9)
    ax.legend(fontsize=7, frameon=False)
    ax.grid(True, which="major", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, format="png", metadata={"Software": None})
    return path


def write_pages(sc: Scorecard, out: Path, *, charts: bool = True) -> list[Path]:
    """Write ``index.md``, ``ENGINE-VERSION.md`` and the charts to ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    files = []
    index = index_page(sc)
    atomic_write(out / "index.md", lambda fh: fh.write(index))
    files.append(out / "index.md")
    for card in sc.cards:
        if card.reason:
            continue
        page = engine_page(card, sc.cases_version)
        atomic_write(out / f"{card.slug}.md", lambda fh, page=page: fh.write(page))
        files.append(out / f"{card.slug}.md")
        if charts:
            for c in _chart_cases(card):
                files.append(chart(card, c, out / f"{card.slug}-{c}.png"))
    return files
