"""The figures every kind shares: angular velocity and the invariants' changes.

A kind's :meth:`~poinsot.scenarios.kind.ScenarioKind.figures` returns
:func:`default_figures` plus its own (e.g. MacCullagh's and Poinsot's pictures of a
free body). Each :class:`~poinsot.scenarios.kind.FigureSpec` draws with a function
of :mod:`poinsot.plotting` on axes the writer provides.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..plotting.scenario import plot_angular_velocity, plot_relative_change
from .facts import FigureSpec

if TYPE_CHECKING:
    from .summary import ScenarioResult

__all__ = ["default_figures", "omega_figure", "invariants_figure"]


def omega_figure(result: ScenarioResult) -> FigureSpec:
    """``omega.png``: body angular velocity of the method (and the reference, dashed)."""

    def draw(ax: Any) -> Any:
        return plot_angular_velocity(
            result.trajectory,
            result.reference,
            ax=ax,
            title=f"{result.scenario.name}: angular velocity",
        )

    return FigureSpec("omega.png", draw)


def invariants_figure(result: ScenarioResult) -> FigureSpec | None:
    """``invariants.png``: relative change of every checked quantity, or None."""
    if not result.checks:
        return None
    tr, ref = result.trajectory, result.reference

    def draw(ax: Any) -> Any:
        curves = {f"{c.label} ({tr.method})": c.relative_change() for c in result.checks}
        dashed = set()
        if ref is not None:
            for c in result.reference_checks:
                label = f"{c.label} ({ref.method})"
                curves[label] = c.relative_change()
                dashed.add(label)
        conserved = any(c.conserved for c in result.checks)
        title = "conserved quantities (relative change)" if conserved else "relative change"
        return plot_relative_change(tr.t, curves, dashed=dashed, ax=ax, title=title)

    return FigureSpec("invariants.png", draw)


def default_figures(result: ScenarioResult) -> list[FigureSpec]:
    """:func:`omega_figure` and, when there are checks, :func:`invariants_figure`."""
    figs = [omega_figure(result), invariants_figure(result)]
    return [f for f in figs if f is not None]
