"""The Moodle XML of ``poinsot.exercises`` read by a real Moodle-format parser:
amc2moodle's ``moodle2amc`` (``pip install amc2moodle``; it needs ImageMagick's
MagickWand library, e.g. Debian's ``libmagickwand-6.q16-6``), which converts a Moodle
question bank to Auto Multiple Choice LaTeX. Skipped, with that reason, where either is
missing (CI installs neither: the structural check of test_exercises.py always runs)."""

from __future__ import annotations

import logging
import re

import pytest

from poinsot.exercises import EXERCISE_TYPES, generate, render

quiz = pytest.importorskip(
    "amc2moodle.moodle2amc._quiz",
    reason="the Moodle import check needs `pip install amc2moodle` and ImageMagick's "
    "MagickWand library (apt install libmagickwand-6.q16-6)",
)


@pytest.mark.parametrize("kind", EXERCISE_TYPES)
def test_moodle2amc_reads_every_type_and_finds_the_answer(kind, tmp_path):
    logging.disable(logging.WARNING)  # it warns that AMC keeps one numeric answer
    try:
        exs = [generate(kind, seed) for seed in range(3)]
        for ex in exs:
            xml = tmp_path / f"{kind}-{ex.seed}.xml"
            xml.write_text(render([ex], "moodle"), encoding="utf-8")
            tex = tmp_path / f"{kind}-{ex.seed}.tex"
            quiz.Quiz(str(xml)).convert(str(tex))
            numbers = re.findall(r"AMCnumericChoices\{([^}]*)\}", tex.read_text())
            assert len(numbers) == 1
            right = ex.answer[ex.quiz_index]
            assert float(numbers[0]) == pytest.approx(right, rel=1e-9, abs=1e-12)
    finally:
        logging.disable(logging.NOTSET)
