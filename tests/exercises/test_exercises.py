"""Exercises with worked solutions (issue 46): for every problem type, 100 seeded
variants whose two answers (the worked solution's own formulas, poinsot's API) agree;
the checker accepts the right answer and names each listed mistake from the answer it
gives; mistakes differ from the right answer; seeds reproduce; every step cites
docs/theory.md; the renderers, the Moodle XML against Moodle's format rules, and the CLI."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from poinsot.cli import main
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.exercises import EXERCISE_TYPES, FORMATS, check, generate, render

TYPES = list(EXERCISE_TYPES)
SEEDS = range(100)
THEORY = (Path(__file__).resolve().parents[2] / "docs" / "theory.md").read_text()
SECTIONS = set(re.findall(r"^#+ (§\d+)", THEORY, re.M))


@pytest.fixture(scope="module", params=TYPES)
def variants(request):
    return request.param, [generate(request.param, s) for s in SEEDS]


def test_at_least_fifteen_types_with_three_mistakes_each(variants):
    kind, exs = variants
    assert len(TYPES) >= 15  # issue 46
    # each type lists at least 3 mistakes (a variant drops those that coincide)
    names = set().union(*(ex.mistakes for ex in exs))
    assert len(names) >= 3, (kind, names)
    assert max(len(ex.mistakes) for ex in exs) >= 3


def test_the_two_answers_agree(variants):
    kind, exs = variants
    for ex in exs:
        assert ex.answer.shape == ex.answer_api.shape == (len(ex.labels),)
        scale = max(1.0, float(np.abs(ex.answer).max()))
        np.testing.assert_allclose(
            ex.answer, ex.answer_api, rtol=1e-9, atol=1e-9 * scale, err_msg=f"{kind} {ex.seed}"
        )


def test_checker_accepts_the_answer_and_names_each_mistake(variants):
    kind, exs = variants
    for ex in exs:
        v = check(ex, ex.answer)
        assert v.correct and v.mistake is None
        # within the tolerance still right, a quiz's one number too
        assert check(ex, ex.answer + 0.5 * ex.tolerance).correct
        assert check(ex, ex.answer[ex.quiz_index]).correct
        for name, wrong in ex.mistakes.items():
            assert np.abs(wrong - ex.answer).max() > ex.tolerance, (kind, ex.seed, name)
            v = check(ex, wrong)
            assert not v.correct and v.mistake == name, (kind, ex.seed, name, v)
            assert name in v.message


def test_an_unlisted_wrong_answer_is_not_a_listed_mistake(variants):
    kind, exs = variants
    for ex in exs[:20]:
        v = check(ex, ex.answer + 7.77 * max(1.0, float(np.abs(ex.answer).max())))
        assert v == type(v)(False, None, "Wrong: not a listed mistake.")


def test_seeds_reproduce_and_differ(variants):
    kind, exs = variants
    for ex in exs[:10]:
        again = generate(kind, ex.seed)
        assert again.statement == ex.statement
        assert render(again, "md") == render(ex, "md")
        np.testing.assert_array_equal(again.answer, ex.answer)
    assert len({ex.statement for ex in exs}) > 10  # the seeds draw different problems


def test_steps_cite_the_theory_page_and_the_record_is_frozen(variants):
    kind, exs = variants
    ex = exs[0]
    assert ex.type == kind and ex.seed == 0 and ex.units and ex.tolerance > 0
    for ex in exs[:20]:
        assert ex.steps
        for step in ex.steps:
            assert step.section in SECTIONS, (kind, step.section)
            assert step.text and np.all(np.isfinite(step.result))
    with pytest.raises(ValueError):
        ex.answer[0] = 1.0  # read-only
    with pytest.raises(AttributeError):
        ex.seed = 3  # type: ignore[misc]


# ------------------------------------------------------------ textbook values
def test_composition_worked_example_of_the_theory_page():
    """docs/theory.md §4: 90 deg about x then 90 deg about y, fixed axes:
    C = B A = [[0, 1, 0], [0, 0, -1], [-1, 0, 0]]."""
    from poinsot.exercises.problems import matmul, rot

    C = np.array(matmul(rot("y", np.pi / 2), rot("x", np.pi / 2)))
    np.testing.assert_allclose(C, [[0, 1, 0], [0, 0, -1], [-1, 0, 0]], atol=1e-15)


def test_euler_angles_has_gimbal_lock_variants_with_phi_zero():
    locked = [ex for ex in (generate("euler-angles", s) for s in SEEDS) if ex.answer[1] in (0, 180)]
    assert locked
    for ex in locked:
        assert ex.answer[2] == 0.0 and "gimbal lock" in ex.steps[1].text


def test_eig3_against_numpy():
    from poinsot.exercises.problems import eig3

    rng = np.random.default_rng(0)
    for _ in range(50):
        m = rng.normal(size=(3, 3))
        j = m @ m.T
        np.testing.assert_allclose(eig3(j.tolist()), np.linalg.eigvalsh(j), atol=1e-12)


# -------------------------------------------------------------------- errors
def test_bad_inputs_name_the_argument():
    with pytest.raises(InvalidInputError, match=r"Expected `kind` to be one of .*'nope'"):
        generate("nope")
    with pytest.raises(InvalidTypeError, match="`kind`"):
        generate(3)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="`seed`"):
        generate("kepler", -1)
    ex = generate("kepler", 0)
    with pytest.raises(InvalidInputError, match=r"`student_answer` to have 3 components"):
        check(ex, [1.0, 2.0])
    with pytest.raises(InvalidTypeError, match="`exercise`"):
        check("kepler", 1.0)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"Expected `format` to be one of md, html"):
        render(ex, "pdf")


# ----------------------------------------------------------------- renderers
@pytest.mark.parametrize("fmt", FORMATS)
def test_every_format_renders_every_type(fmt):
    exs = [generate(k, 7) for k in TYPES]
    text = render(exs, fmt)
    for ex in exs:
        assert ex.type in text
    if fmt == "html":
        assert text.startswith("<!DOCTYPE html>") and "http" not in text  # no CDN
    if fmt == "md":
        assert "$" in text and "(theory §" in text
    if fmt == "tex":
        assert r"\subsection*" in text and "§" not in text and r"\S" in text


def _moodle_conforms(root: ET.Element) -> None:
    """Moodle's XML format (docs.moodle.org/en/Moodle_XML_format), numerical questions:
    <quiz> holds <question type=...>; each has <name><text>, <questiontext format=...>
    <text>, <generalfeedback><text>, <defaultgrade>, and one or more <answer fraction=F>
    with F in 0..100, a numeric <text>, a non-negative <tolerance> and a
    <feedback><text>; at least one answer scores 100."""
    assert root.tag == "quiz"
    questions = root.findall("question")
    assert questions
    for q in questions:
        assert q.get("type") == "numerical"
        assert (q.findtext("name/text") or "").strip()
        qt = q.find("questiontext")
        assert qt is not None and qt.get("format") in ("html", "moodle_auto_format", "plain_text")
        assert (qt.findtext("text") or "").strip()
        assert (q.findtext("generalfeedback/text") or "").strip()
        float(q.findtext("defaultgrade") or "x")
        answers = q.findall("answer")
        assert answers
        fractions = []
        for a in answers:
            f = float(a.get("fraction") or "x")
            assert 0 <= f <= 100
            fractions.append(f)
            float(a.findtext("text") or "x")
            assert float(a.findtext("tolerance") or "x") >= 0
            assert (a.findtext("feedback/text") or "").strip()
        assert 100 in fractions
        assert q.find("unitgradingtype") is not None


@pytest.mark.parametrize("kind", TYPES)
def test_moodle_xml_parses_and_follows_the_format(kind):
    exs = [generate(kind, s) for s in range(5)]
    root = ET.fromstring(render(exs, "moodle"))
    _moodle_conforms(root)
    for q, ex in zip(root.findall("question"), exs, strict=True):
        right = [a for a in q.findall("answer") if a.get("fraction") == "100"]
        assert float(right[0].findtext("text")) == ex.answer[ex.quiz_index]
        wrong = {
            a.findtext("feedback/text") for a in q.findall("answer") if a.get("fraction") == "0"
        }
        for text in wrong:
            name = text.removeprefix("Typical mistake: ").removesuffix(".")
            assert name in ex.mistakes
            assert check(ex, ex.mistakes[name][ex.quiz_index]).mistake == name
        assert "theory §" in q.findtext("generalfeedback/text")


# ----------------------------------------------------------------------- CLI
def test_cli_md_and_list(capsys):
    assert main(["exercise", "composition", "--seed", "1", "--format", "md"]) == 0
    out = capsys.readouterr().out
    assert out == render(generate("composition", 1), "md")
    assert main(["exercise", "--list"]) == 0
    out = capsys.readouterr().out
    assert [line.split()[0] for line in out.splitlines()] == TYPES


def test_cli_count_and_moodle(capsys):
    assert main(["exercise", "kepler", "--seed", "4", "--count", "3", "--format", "moodle"]) == 0
    root = ET.fromstring(capsys.readouterr().out)
    assert len(root.findall("question")) == 3
    _moodle_conforms(root)


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["exercise", "nope"], "unknown TYPE 'nope'"),
        (["exercise"], "TYPE is required"),
        (["exercise", "kepler", "--format", "pdf"], "argument --format: invalid choice: 'pdf'"),
        (["exercise", "kepler", "--count", "0"], "--count must be between 1"),
        (["exercise", "kepler", "--seed", "-2"], "--seed must be >= 0"),
    ],
)
def test_cli_errors_exit_2_naming_the_argument(capsys, argv, match):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert match in captured.err and captured.out == "" and "Traceback" not in captured.err


def test_docs_page_shows_what_its_block_prints_today():
    """docs/exercises.md: the worked examples between its markers are the output of its
    code block (seed 0 of every type)."""
    page = (Path(__file__).resolve().parents[2] / "docs" / "exercises.md").read_text()
    shown = page.split("<!-- generated: begin -->\n")[1].split("\n<!-- generated: end -->")[0]
    assert shown == render([generate(kind, seed=0) for kind in TYPES], "md")
    for kind in TYPES:
        assert f"`{kind}`" in page


@pytest.mark.parametrize("kind", TYPES)
def test_quiz_answers_are_not_a_guessable_zero(kind):
    """The component a quiz asks for is non-zero whenever another component would
    separate a mistake (an answer that is always 0 is a guess away from right)."""
    for seed in SEEDS:
        ex = generate(kind, seed)
        if np.any(np.abs(ex.answer) > ex.tolerance):
            assert abs(ex.answer[ex.quiz_index]) > ex.tolerance or not ex.mistakes, (kind, seed)


@pytest.mark.parametrize("kind", TYPES)
def test_html_answers_are_mathml(kind):
    """The HTML page writes each answer as presentation MathML (browsers render it
    offline): well-formed XML whose <mn> values are the answer."""
    import re

    ex = generate(kind, 3)
    page = render(ex, "html")
    (math,) = re.findall(r"<math.*?</math>", page)
    root = ET.fromstring(
        math.replace('display="inline"', 'xmlns="http://www.w3.org/1998/Math/MathML"')
    )
    numbers = [float(n.text) for n in root.iter("{http://www.w3.org/1998/Math/MathML}mn")]
    np.testing.assert_allclose(numbers, ex.answer, rtol=1e-5, atol=1e-6)


def test_moodle_xml_is_valid_against_the_schema_of_the_format():
    """Every type's quiz against tests/data/moodle_numerical.xsd (Moodle's XML format for
    numerical questions, XSD 1.1); a broken document is refused by the same schema."""
    xmlschema = pytest.importorskip("xmlschema", reason="the schema check needs xmlschema")
    from pathlib import Path

    xsd = xmlschema.XMLSchema11(Path(__file__).parents[1] / "data" / "moodle_numerical.xsd")
    text = render([generate(kind, seed) for kind in TYPES for seed in range(3)], "moodle")
    xsd.validate(text)
    broken = text.replace('fraction="100"', 'fraction="150"', 1)
    assert not xsd.is_valid(broken)
    assert not xsd.is_valid(text.replace("<tolerance>", "<tolerance>-", 1))
