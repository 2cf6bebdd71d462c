"""Exercises with worked solutions for theoretical mechanics (issue 46).

Each problem type draws clean parameters from a seeded generator (angles in multiples of
15 degrees, integer masses and lengths, distinct principal moments), solves the problem
step by step with its own formulas (each step citing ``docs/theory.md`` §N), solves it
again with poinsot's numeric API, and lists typical mistakes with the answers they give.
:func:`check` marks a student's answer and names the mistake that explains it;
:func:`render` writes Markdown, HTML, LaTeX or a Moodle XML quiz. NumPy only (no SymPy).

Examples
--------
>>> from poinsot.exercises import EXERCISE_TYPES, generate, check
>>> "composition" in EXERCISE_TYPES
True
>>> ex = generate("composition", seed=1)
>>> bool(abs(ex.answer - ex.answer_api).max() < 1e-9)
True
>>> check(ex, ex.answer)
Verdict(correct=True, mistake=None, message='Correct.')
"""

from __future__ import annotations

from . import problems as _problems  # noqa: F401 - registers the problem types
from .core import EXERCISE_TYPES, Exercise, Step, Verdict, check, generate
from .render import FORMATS, render

__all__ = [
    "EXERCISE_TYPES",
    "FORMATS",
    "Exercise",
    "Step",
    "Verdict",
    "check",
    "generate",
    "render",
]


def __dir__() -> list[str]:
    return sorted(__all__)
