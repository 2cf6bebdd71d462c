"""Plots of a motion in generalized coordinates (docs/theory.md §11) and of its
equations as formulas.

Used by the scenario kind ``lagrangian`` (``coordinates.png``, ``phase.png``,
``equations.svg``) and usable directly with a
:class:`poinsot.symbolic.LagrangeTrajectory` / :class:`poinsot.symbolic.LagrangeSystem`.
matplotlib is imported here only; the formulas are typeset offline by matplotlib's
mathtext from SymPy's LaTeX (no TeX installation, nothing fetched).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..errors import InvalidTypeError
from .scenario import _new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..symbolic.lagrange import LagrangeSystem
    from ..symbolic.numeric import LagrangeTrajectory

__all__ = ["plot_coordinates", "plot_phase", "plot_equations", "equation_latex"]


def _finish(ax: Axes, title: str | None) -> Axes:
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title)
    return ax


def _lagrange_trajectory(tr: object) -> Any:
    if not all(hasattr(tr, a) for a in ("t", "q", "qdot", "coordinates")):
        raise InvalidTypeError(
            f"Expected `trajectory` to be a LagrangeTrajectory, got {type(tr).__name__}."
        )
    return tr


def plot_coordinates(
    trajectory: LagrangeTrajectory, *, ax: Axes | None = None, title: str | None = None
) -> Axes:
    """Plot each generalized coordinate ``q_k(t)`` against time.

    Parameters
    ----------
    trajectory : LagrangeTrajectory
        From :meth:`poinsot.symbolic.LagrangeSystem.simulate` (one initial state).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, sympy
    >>> from poinsot.symbolic import LagrangeSystem
    >>> x = sympy.Function("x")(sympy.Symbol("t"))
    >>> tr = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2).simulate(
    ...     [1.0], [0.0], np.linspace(0, 6, 61))
    >>> plot_coordinates(tr).get_lines()[0].get_label()
    'x'
    """
    tr = _lagrange_trajectory(trajectory)
    ax = _new_axes(ax)
    for k, name in enumerate(tr.coordinates):
        ax.plot(tr.t, tr.q[:, k], label=name)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("generalized coordinates")
    return _finish(ax, title)


def plot_phase(
    trajectory: LagrangeTrajectory,
    *,
    ax: Axes | None = None,
    title: str | None = "phase portrait",
) -> Axes:
    """Plot each coordinate's phase curve ``(q_k, q_k')``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, sympy
    >>> from poinsot.symbolic import LagrangeSystem
    >>> th = sympy.Function("theta")(sympy.Symbol("t"))
    >>> pendulum = LagrangeSystem([th], th.diff() ** 2 / 2, -sympy.cos(th))
    >>> len(plot_phase(pendulum.simulate([2.0], [0.0], np.linspace(0, 8, 81))).get_lines())
    1
    """
    tr = _lagrange_trajectory(trajectory)
    ax = _new_axes(ax)
    for k, name in enumerate(tr.coordinates):
        ax.plot(tr.q[:, k], tr.qdot[:, k], label=name)
    ax.set_xlabel("q")
    ax.set_ylabel("q' (1/s)")
    return _finish(ax, title)


def equation_latex(system: LagrangeSystem) -> list[str]:
    """Lagrange's equations of ``system`` as LaTeX, with ``q'`` written ``\\dot q``.

    Examples
    --------
    >>> import sympy
    >>> from poinsot.symbolic import LagrangeSystem
    >>> x = sympy.Function("x")(sympy.Symbol("t"))
    >>> equation_latex(LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2))
    ['\\\\ddot{x} + x = 0']
    """
    import sympy

    out = []
    for eq in system.equations():
        lhs = system.printable(eq.lhs, latex=True)
        rhs = system.printable(eq.rhs, latex=True)
        out.append(f"{sympy.latex(lhs)} = {sympy.latex(rhs)}")
    return out


def plot_equations(system: LagrangeSystem, *, ax: Axes | None = None, fontsize: float = 11) -> Axes:
    """Typeset Lagrange's equations ``E_k L = Q*_k + ...`` of ``system`` on ``ax``.

    Each line is SymPy's LaTeX drawn by matplotlib's mathtext (offline); a line
    mathtext cannot typeset is written as plain text instead.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import sympy
    >>> from poinsot.symbolic import LagrangeSystem
    >>> x = sympy.Function("x")(sympy.Symbol("t"))
    >>> ax = plot_equations(LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2))
    >>> ax.texts[-1].get_text()
    '$\\\\ddot{x} + x = 0$'
    """
    from matplotlib.mathtext import MathTextParser

    ax = _new_axes(ax, size=(9, 1.5))
    ax.set_axis_off()
    lines = equation_latex(system)
    parser = MathTextParser("path")
    n = len(lines)
    ax.text(0.0, 1.0, "Lagrange's equations (docs/theory.md §11)", fontsize=fontsize,
            va="top", ha="left", transform=ax.transAxes, weight="bold")  # fmt: skip
    for k, line in enumerate(lines):
        text = f"${line}$"
        try:
            parser.parse(text, dpi=72)
        except ValueError:
            text = str(system.equations()[k])
        y = 1.0 - (k + 1) / (n + 1)
        ax.text(0.0, y, text, fontsize=fontsize, va="top", ha="left", transform=ax.transAxes)
    return ax
