"""The exercise record, the registry of problem types and the answer checker (issue 46).

Light: NumPy only. A problem type is a function ``draw(rng) -> Draft`` registered with
:func:`problem`; :func:`generate` seeds the generator, draws, drops the mistakes that
give the right answer (or the answer of an earlier mistake) and freezes the result.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InvalidInputError, InvalidTypeError

__all__ = ["Exercise", "Step", "Verdict", "EXERCISE_TYPES", "generate", "check"]


def _frozen(x: ArrayLike) -> np.ndarray:
    a = np.array(x, dtype=float).reshape(-1)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Step:
    """One step of a worked solution: what is done, the section of ``docs/theory.md``
    it uses (``"§4"``) and the intermediate numbers it gives (flattened, read-only)."""

    text: str
    section: str
    result: np.ndarray = field(default_factory=lambda: _frozen([]))


@dataclass(frozen=True, eq=False)
class Exercise:
    """A generated exercise with its worked solution (see :func:`generate`).

    Attributes
    ----------
    type : str
        The problem type (a key of :data:`EXERCISE_TYPES`).
    seed : int
        The seed of ``numpy.random.default_rng`` that drew it.
    statement : str
        The problem as given to the student (plain text, ``$...$`` math).
    steps : tuple of Step
        The worked solution.
    answer : ndarray, shape (n,)
        The answer by the worked solution's own formulas.
    answer_api : ndarray, shape (n,)
        The same answer by poinsot's numeric API (a cross-check; they agree).
    labels : tuple of str
        The name of each component of ``answer``.
    units : str
        Units of the answer.
    tolerance : float
        Largest absolute error accepted in each component.
    mistakes : mapping of str to ndarray
        A typical mistake -> the answer it produces.
    quiz_index : int
        The component asked in a single-number quiz (Moodle): the one that tells the
        most mistakes apart from the right answer.
    """

    type: str
    seed: int
    statement: str
    steps: tuple[Step, ...]
    answer: np.ndarray
    answer_api: np.ndarray
    labels: tuple[str, ...]
    units: str
    tolerance: float
    mistakes: Mapping[str, np.ndarray]
    quiz_index: int = 0


@dataclass(frozen=True)
class Verdict:
    """The verdict of :func:`check`: right or wrong, the listed mistake that explains a
    wrong answer (None if none does), and a message for the student."""

    correct: bool
    mistake: str | None
    message: str


@dataclass
class Draft:
    """What a problem type draws (mutable; :func:`generate` freezes it)."""

    statement: str
    steps: list[Step]
    answer: Any
    answer_api: Any
    labels: tuple[str, ...]
    units: str
    mistakes: dict[str, Any]
    tolerance: float | None = None


#: name -> (one-line description, draw function)
_REGISTRY: dict[str, tuple[str, Callable[[np.random.Generator], Draft]]] = {}

#: The problem types: name -> one-line description (filled by ``problems``).
EXERCISE_TYPES: dict[str, str] = {}


def problem(
    name: str, description: str
) -> Callable[[Callable[[np.random.Generator], Draft]], Callable[[np.random.Generator], Draft]]:
    """Register ``draw(rng) -> Draft`` as the problem type ``name``."""

    def register(
        draw: Callable[[np.random.Generator], Draft],
    ) -> Callable[[np.random.Generator], Draft]:
        _REGISTRY[name] = (description, draw)
        EXERCISE_TYPES[name] = description
        return draw

    return register


def _check_kind(kind: object) -> str:
    if not isinstance(kind, str):
        raise InvalidTypeError(f"Expected `kind` to be a str, got {type(kind).__name__}.")
    if kind not in _REGISTRY:
        raise InvalidInputError(
            f"Expected `kind` to be one of {', '.join(sorted(_REGISTRY))}, got {kind!r}."
        )
    return kind


def _check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise InvalidInputError(f"Expected `seed` to be an integer >= 0, got {seed!r}.")
    return int(seed)


def generate(kind: str, seed: int = 0) -> Exercise:
    """Draw the exercise of type ``kind`` with ``seed`` (the same seed, the same one).

    Parameters
    ----------
    kind : str
        A key of :data:`EXERCISE_TYPES` (``"composition"``, ``"euler-angles"``, ...).
    seed : int, optional
        Seed of ``numpy.random.default_rng`` (default 0).

    Returns
    -------
    Exercise
        The statement, the worked solution (each step citing ``docs/theory.md``), the
        answer computed twice (own formulas, poinsot's API), and the typical mistakes
        with the answers they give; mistakes that give the right answer, or the answer
        of a mistake listed before, are left out.

    Examples
    --------
    >>> from poinsot.exercises import generate, check
    >>> ex = generate("coriolis", seed=3)
    >>> check(ex, ex.answer).correct
    True
    >>> name = next(iter(ex.mistakes))
    >>> check(ex, ex.mistakes[name]).mistake == name
    True
    """
    kind = _check_kind(kind)
    seed = _check_seed(seed)
    draft = _REGISTRY[kind][1](np.random.default_rng(seed))
    answer = _frozen(draft.answer)
    scale = max(1.0, float(np.max(np.abs(answer)))) if answer.size else 1.0
    tol = draft.tolerance if draft.tolerance is not None else 1e-3 * scale
    kept: dict[str, np.ndarray] = {}
    for name, value in draft.mistakes.items():
        wrong = _frozen(value)
        if wrong.shape != answer.shape or not np.all(np.isfinite(wrong)):
            continue
        others = [answer, *kept.values()]
        if all(np.max(np.abs(wrong - o)) > 4 * tol for o in others):
            kept[name] = wrong

    # the component that separates the most mistakes from the answer (and each other);
    # a component whose answer is 0 is a guess away from right: taken only when no other
    # separates any mistake
    def separated(k: int) -> int:
        vals = [answer[k]] + [w[k] for w in kept.values()]
        return sum(
            all(abs(v - u) > 4 * tol for j, u in enumerate(vals) if j != i)
            for i, v in enumerate(vals)
        )

    score = [separated(k) for k in range(answer.size)]
    nonzero = [k for k in range(answer.size) if abs(answer[k]) > tol]
    pool = nonzero if nonzero and max(score[k] for k in nonzero) > 0 else range(answer.size)
    index = max(pool, key=lambda k: (score[k], -k))
    return Exercise(
        type=kind,
        seed=seed,
        statement=draft.statement,
        steps=tuple(draft.steps),
        answer=answer,
        answer_api=_frozen(draft.answer_api),
        labels=tuple(draft.labels),
        units=draft.units,
        tolerance=float(tol),
        mistakes=dict(kept),
        quiz_index=index,
    )


def check(exercise: Exercise, student_answer: ArrayLike) -> Verdict:
    """Say whether ``student_answer`` is right and, if not, which listed mistake gives it.

    Parameters
    ----------
    exercise : Exercise
        The exercise (from :func:`generate`).
    student_answer : array_like
        Every component of the answer, in the order of ``exercise.labels``, or one
        number: the component ``exercise.quiz_index`` (the one a quiz asks for).

    Returns
    -------
    Verdict
        Right within ``exercise.tolerance`` in every component; otherwise the listed
        mistake nearest to the answer given, if it is within the tolerance, else
        ``mistake=None`` ("not a listed mistake").

    Examples
    --------
    >>> from poinsot.exercises import generate, check
    >>> ex = generate("gyroscope", seed=1)
    >>> check(ex, ex.answer + 10 * ex.tolerance)
    Verdict(correct=False, mistake=None, message='Wrong: not a listed mistake.')
    """
    if not isinstance(exercise, Exercise):
        raise InvalidTypeError(
            f"Expected `exercise` to be an Exercise, got {type(exercise).__name__}."
        )
    try:
        given = np.asarray(student_answer, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidTypeError(
            f"Expected `student_answer` to be numbers, got {student_answer!r}."
        ) from None
    k = exercise.quiz_index
    if given.size == 1 and exercise.answer.size > 1:
        right = exercise.answer[k : k + 1]
        wrongs = {n: w[k : k + 1] for n, w in exercise.mistakes.items()}
    elif given.size == exercise.answer.size:
        right, wrongs = exercise.answer, dict(exercise.mistakes)
    else:
        raise InvalidInputError(
            f"Expected `student_answer` to have {exercise.answer.size} components "
            f"({', '.join(exercise.labels)}) or 1 ({exercise.labels[k]}), got {given.size}."
        )
    tol = exercise.tolerance
    if np.max(np.abs(given - right)) <= tol:
        return Verdict(True, None, "Correct.")
    dist = {n: float(np.max(np.abs(given - w))) for n, w in wrongs.items()}
    near = [n for n in dist if dist[n] <= tol]
    if near:
        name = min(near, key=dist.__getitem__)
        return Verdict(False, name, f"Wrong: the answer a typical mistake gives ({name}).")
    return Verdict(False, None, "Wrong: not a listed mistake.")
