"""Exercises as text: Markdown, a self-contained HTML page, LaTeX, or a Moodle XML quiz."""

from __future__ import annotations

import html
from collections.abc import Iterable
from xml.sax.saxutils import escape

from ..errors import InvalidInputError, InvalidTypeError
from .core import Exercise
from .problems import num, vec

__all__ = ["FORMATS", "render"]

#: The output formats of :func:`render`.
FORMATS = ("md", "html", "tex", "moodle")


def _answer(ex: Exercise) -> str:
    if ex.answer.size == 1:
        return f"{ex.labels[0]} = {num(ex.answer[0])} {ex.units}"
    return (
        ", ".join(f"{k} = {num(v)}" for k, v in zip(ex.labels, ex.answer, strict=True))
        + f" ({ex.units})"
    )


def _math(ex: Exercise) -> str:
    """The answer as TeX math: ``\\psi = 30,\\ \\theta = 45``."""
    greek = {"psi", "theta", "phi", "omega", "Omega"}
    names = [("\\" + k if k in greek else k) for k in ex.labels]
    return ",\\ ".join(f"{k} = {num(v)}" for k, v in zip(names, ex.answer, strict=True))


_GREEK = {"psi": "\u03c8", "theta": "\u03b8", "phi": "\u03c6", "omega": "\u03c9",
          "Omega": "\u03a9"}  # fmt: skip


def _mathml(ex: Exercise) -> str:
    """The answer as presentation MathML (rendered by browsers offline, no script):
    ``<math><mi>x</mi><mo>=</mo><mn>-2.12132</mn>...</math>``."""
    e = html.escape
    parts = []
    for k, v in zip(ex.labels, ex.answer, strict=True):
        name = _GREEK.get(k, k)
        base, _, sub = name.partition("_")
        mi = f"<msub><mi>{e(base)}</mi><mi>{e(sub)}</mi></msub>" if sub else f"<mi>{e(base)}</mi>"
        parts.append(f"{mi}<mo>=</mo><mn>{e(num(v))}</mn>")
    return '<math display="inline">' + '<mo>,</mo><mspace width="0.5em"/>'.join(parts) + "</math>"


def _md(exs: list[Exercise]) -> str:
    out = []
    for n, ex in enumerate(exs, 1):
        out.append(f"## Exercise {n}: {ex.type} (seed {ex.seed})\n\n{ex.statement}\n")
        out.append("**Solution.**\n")
        out += [f"{k}. {s.text} (theory {s.section})" for k, s in enumerate(ex.steps, 1)]
        out.append(f"\n**Answer:** ${_math(ex)}$ ({ex.units})\n")
        if ex.mistakes:
            out.append("**Typical mistakes:**\n")
            out += [f"- {name}: gives {vec(w)}" for name, w in ex.mistakes.items()]
            out.append("")
    return "\n".join(out)


def _html(exs: list[Exercise]) -> str:
    body = []
    for n, ex in enumerate(exs, 1):
        e = html.escape
        steps = "".join(
            f"<li>{e(s.text)} <small>(theory {e(s.section)})</small></li>" for s in ex.steps
        )
        wrong = "".join(f"<li>{e(k)}: gives {e(vec(w))}</li>" for k, w in ex.mistakes.items())
        body.append(
            f"<section><h2>Exercise {n}: {e(ex.type)} (seed {ex.seed})</h2>"
            f"<p>{e(ex.statement)}</p><h3>Solution</h3><ol>{steps}</ol>"
            f"<p><b>Answer:</b> {_mathml(ex)} ({e(ex.units)})</p>"
            + (f"<h3>Typical mistakes</h3><ul>{wrong}</ul>" if wrong else "")
            + "</section>"
        )
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        "<title>poinsot exercises</title><style>body{font-family:sans-serif;max-width:50em;"
        "margin:auto}small{color:#666}</style></head><body>\n"
        + "\n".join(body)
        + "\n</body></html>\n"
    )


def t(s: str) -> str:
    """Plain text as LaTeX (special characters escaped, § as \\S)."""
    return s.translate(_TEX).replace("§", r"\S")


_TEX = str.maketrans({"&": r"\&", "%": r"\%", "#": r"\#", "_": r"\_", "^": r"\^{}", "~": r"\~{}"})


def _tex(exs: list[Exercise]) -> str:
    out = []
    for n, ex in enumerate(exs, 1):
        out.append(
            f"\\subsection*{{Exercise {n}: {t(ex.type)} (seed {ex.seed})}}\n{t(ex.statement)}\n"
        )
        out.append("\\paragraph{Solution.}\n\\begin{enumerate}")
        out += [f"  \\item {t(s.text)} (theory {t(s.section)})" for s in ex.steps]
        out.append("\\end{enumerate}")
        out.append(f"\\paragraph{{Answer.}} {t(_answer(ex))}\n")
        if ex.mistakes:
            out.append("\\paragraph{Typical mistakes.}\n\\begin{itemize}")
            out += [f"  \\item {t(k)}: gives {t(vec(w))}" for k, w in ex.mistakes.items()]
            out.append("\\end{itemize}\n")
    return "\n".join(out)


def _moodle(exs: list[Exercise]) -> str:
    out = ['<?xml version="1.0" encoding="UTF-8"?>', "<quiz>"]
    for n, ex in enumerate(exs, 1):
        k = ex.quiz_index
        label = ex.labels[k]
        ask = ex.statement + (
            f" Give {label} ({ex.units})." if ex.answer.size > 1 else f" Give it in {ex.units}."
        )
        feedback = (
            "<ol>"
            + "".join(f"<li>{escape(s.text)} (theory {escape(s.section)})</li>" for s in ex.steps)
            + f"</ol><p>Answer: {escape(_answer(ex))}</p>"
        )
        out += [
            '  <question type="numerical">',
            f"    <name><text>{escape(ex.type)} {ex.seed} ({n})</text></name>",
            f'    <questiontext format="html"><text><![CDATA[<p>{escape(ask)}</p>]]></text>'
            "</questiontext>",
            f'    <generalfeedback format="html"><text><![CDATA[{feedback}]]></text>'
            "</generalfeedback>",
            "    <defaultgrade>1</defaultgrade>",
            "    <penalty>0.3333333</penalty>",
            "    <hidden>0</hidden>",
            f'    <answer fraction="100" format="moodle_auto_format">'
            f"<text>{float(ex.answer[k])!r}</text>",
            f"      <tolerance>{ex.tolerance!r}</tolerance>",
            '      <feedback format="html"><text>Correct.</text></feedback>',
            "    </answer>",
        ]
        shown = [float(ex.answer[k])]
        for name, wrong in ex.mistakes.items():
            if any(abs(wrong[k] - v) <= 4 * ex.tolerance for v in shown):
                continue  # this component does not tell the mistake apart
            shown.append(float(wrong[k]))
            out += [
                f'    <answer fraction="0" format="moodle_auto_format">'
                f"<text>{float(wrong[k])!r}</text>",
                f"      <tolerance>{ex.tolerance!r}</tolerance>",
                f'      <feedback format="html"><text>{escape(f"Typical mistake: {name}.")}'
                "</text></feedback>",
                "    </answer>",
            ]
        out += [
            "    <unitgradingtype>0</unitgradingtype>",
            "    <showunits>3</showunits>",
            "    <unitsleft>0</unitsleft>",
            "  </question>",
        ]
    out.append("</quiz>\n")
    return "\n".join(out)


def render(exercises: Exercise | Iterable[Exercise], format: str = "md") -> str:
    """The exercises with their worked solutions as text.

    Parameters
    ----------
    exercises : Exercise or iterable of Exercise
        From :func:`generate`.
    format : {"md", "html", "tex", "moodle"}
        Markdown; a self-contained HTML page (no network); a LaTeX article body; a
        Moodle XML quiz (one numerical question per exercise, the worked solution as
        general feedback, each typical mistake as a 0 % answer naming it).

    Returns
    -------
    str

    Examples
    --------
    >>> from poinsot.exercises import generate, render
    >>> print(render(generate("gyroscope", seed=2), "md").splitlines()[0])
    ## Exercise 1: gyroscope (seed 2)
    """
    if format not in FORMATS:
        raise InvalidInputError(
            f"Expected `format` to be one of {', '.join(FORMATS)}, got {format!r}."
        )
    exs = [exercises] if isinstance(exercises, Exercise) else list(exercises)
    for ex in exs:
        if not isinstance(ex, Exercise):
            raise InvalidTypeError(
                f"Expected `exercises` to hold Exercise objects, got {type(ex).__name__}."
            )
    return {"md": _md, "html": _html, "tex": _tex, "moodle": _moodle}[format](exs)
