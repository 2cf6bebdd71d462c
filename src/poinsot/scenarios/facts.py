"""What a scenario kind returns besides its motion: summary entries, the facts known
in closed form, the checked quantities and the figures (the pieces of
:class:`~poinsot.scenarios.kind.ScenarioKind`'s contract, re-exported there).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._drift import relative_change

__all__ = ["Progress", "Entry", "section", "jsonable", "Facts", "Check", "FigureSpec"]

#: ``progress(fraction, stage)``: called as a computation advances (fraction in [0, 1]).
Progress = Callable[[float, str], None]


@dataclass(frozen=True)
class Entry:
    """One summary entry: a value, its units (``""`` for none) and a text label.

    Examples
    --------
    >>> Entry(1.5, "J", "kinetic energy T")
    Entry(value=1.5, units='J', label='kinetic energy T')
    """

    value: Any
    units: str = ""
    label: str = ""


def section(entries: Mapping[str, Entry | Any]) -> dict[str, Any]:
    """A summary section as written to ``summary.json``: ``{key: value, ...,
    "units": {key: units}}`` (arrays become lists; non-finite floats strings).

    Examples
    --------
    >>> section({"energy": Entry(1.5, "J"), "regime": "rotation about z"})
    {'energy': 1.5, 'regime': 'rotation about z', 'units': {'energy': 'J'}}
    """
    out: dict[str, Any] = {}
    units: dict[str, str] = {}
    for key, e in entries.items():
        if isinstance(e, Entry):
            out[key] = jsonable(e.value)
            if e.units:
                units[key] = e.units
        else:
            out[key] = jsonable(e)
    if units:
        out["units"] = units
    return out


def jsonable(obj: Any) -> Any:
    """Convert NumPy values, tuples and non-finite floats to JSON-safe Python values
    (``nan`` -> ``None``, ``inf`` -> ``"inf"``).

    Examples
    --------
    >>> jsonable({"a": np.array([1.0, np.inf]), "b": (np.float64(2.0), None)})
    {'a': [1.0, 'inf'], 'b': [2.0, None]}
    """
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray | np.generic):
        return jsonable(obj.tolist())
    if isinstance(obj, float) and not np.isfinite(obj):
        return None if np.isnan(obj) else ("inf" if obj > 0 else "-inf")
    if obj is None or isinstance(obj, bool | int | float | str):
        return obj
    return str(obj)


@dataclass(frozen=True)
class Facts:
    """What is known about a motion in closed form, for the ``results`` section.

    The base class holds ordered :class:`Entry` objects and text lines; a kind may
    return it directly (``Facts(entries={...}, lines=(...))``) or subclass it and
    override :meth:`entries_` / :meth:`describe`.

    Attributes
    ----------
    entries : Mapping[str, Entry]
        Key -> value with units (the ``results`` section of ``summary.json``).
    lines : tuple of str
        Sentences printed by ``poinsot run`` (each cites ``docs/theory.md §N``
        where it states a result of the theory).

    Examples
    --------
    >>> f = Facts({"period": Entry(2.0, "s", "period")}, ("periodic with period 2 s",))
    >>> f.section()
    {'period': 2.0, 'units': {'period': 's'}}
    >>> f.describe()
    ['periodic with period 2 s']
    """

    entries: Mapping[str, Entry] = field(default_factory=dict)
    lines: tuple[str, ...] = ()

    def entries_(self) -> Mapping[str, Entry]:
        """The entries of the ``results`` section."""
        return self.entries

    def section(self) -> dict[str, Any]:
        """The ``results`` section (JSON-ready, with units)."""
        return section(self.entries_())

    def describe(self) -> list[str]:
        """Text lines for ``poinsot run``."""
        return list(self.lines)


@dataclass(frozen=True, eq=False)
class Check:
    """A quantity whose behaviour along the motion is known: conserved, or equal to
    a law (e.g. ``K(t) = K(0) + M t``). Its deviation measures the accuracy.

    Attributes
    ----------
    name : str
        Key in the ``accuracy`` section (``"energy"``, ``"momentum_z"``, ...).
    label : str
        Text label (``"kinetic energy T"``).
    units : str
        Units of ``values``.
    values : ndarray, shape (n,) or (n, 3)
        The quantity at each output time.
    expected : ndarray or None
        What it should be at each time; ``None``: its initial value (conserved).
    scale : float or None
        Reference size for the relative deviation; ``None``: ``|values[0]|``.
    conserved : bool
        True if it must stay constant (or follow ``expected``): its deviation is
        then compared with the drift threshold; False: only reported.
    law : str
        The law, in words, for the text (``"K(t) = K(0) + M t"``).

    Examples
    --------
    >>> c = Check("energy", "T", "J", np.array([1.0, 1.0, 1.001]))
    >>> round(c.max_relative_deviation, 6)
    0.001
    """

    name: str
    label: str
    units: str
    values: np.ndarray
    expected: np.ndarray | None = None
    scale: float | None = None
    conserved: bool = True
    law: str = ""

    def relative_change(self) -> np.ndarray:
        """``(values - expected) / scale`` at each time, shape (n,) (the norm of the
        difference for vectors; signed for scalars)."""
        v = np.asarray(self.values, dtype=float)
        return relative_change(v, self.scale, expected=self.expected, vector=v.ndim > 1)

    @property
    def max_relative_deviation(self) -> float:
        """``max_t |values - expected| / scale`` (vector norms for vectors)."""
        return float(np.max(np.abs(self.relative_change()), initial=0.0))

    def entry(self) -> dict[str, Any]:
        """The JSON entry: initial and final values, units, the maximum relative
        drift (or deviation from the law) and whether it must be conserved."""
        v = np.asarray(self.values, dtype=float)
        out = {
            "initial": jsonable(v[0]),
            "final": jsonable(v[-1]),
            "units": self.units,
            "max_relative_drift": self.max_relative_deviation,
            "conserved": bool(self.conserved),
        }
        if self.law:
            out["law"] = self.law
        return out


@dataclass(frozen=True)
class FigureSpec:
    """One PNG figure a kind offers: ``draw(ax)`` draws on a new axes.

    ``projection`` is ``None`` or ``"3d"``; ``size`` in inches. The writer makes a
    :class:`matplotlib.figure.Figure` (no pyplot state), calls ``draw`` and saves it
    as ``name``; a failing figure is skipped with a note, never sinks the run.
    """

    name: str
    draw: Callable[[Any], Any]
    size: tuple[float, float] = (7.0, 3.6)
    projection: str | None = None
