"""Figures (matplotlib) and the interactive HTML report (its input: :class:`ReportSpec`).

A leaf package: importing it loads matplotlib, so ``import poinsot`` never
does. Every plot function takes ``ax=None`` and returns the axes it drew on.
"""

from __future__ import annotations

from .free_body import (
    plot_maccullagh,
    plot_omega,
    plot_poinsot,
)
from .gyrostat import (
    plot_gyrostat_polhodes,
    plot_momentum_exchange,
    plot_wheel_speeds,
)
from .heavy_top import (
    plot_axis_track,
    plot_cubic,
    plot_invariant_drift,
    plot_kovalevskaya,
    plot_nutation,
)
from .motion import (
    plot_acceleration_terms,
)
from .notebook import (
    explore,
    show,
)
from .orbit import (
    plot_gravity_gradient_stability,
)
from .particles import (
    plot_effective_potential,
    plot_orbit,
    plot_particle_path,
    plot_path,
    plot_swing_plane,
)
from .report import (
    write_report,
)
from .scenario import (
    plot_angular_velocity,
    plot_relative_change,
)
from .spec import (
    BodyLayer,
    Chart,
    Drawing,
    ReportSpec,
)

__all__ = [
    "plot_acceleration_terms",
    "plot_maccullagh",
    "plot_poinsot",
    "plot_omega",
    "plot_gyrostat_polhodes",
    "write_report",
    "ReportSpec",
    "BodyLayer",
    "Drawing",
    "Chart",
    "show",
    "explore",
    "plot_angular_velocity",
    "plot_relative_change",
    "plot_particle_path",
    "plot_path",
    "plot_orbit",
    "plot_effective_potential",
    "plot_swing_plane",
    "plot_axis_track",
    "plot_cubic",
    "plot_nutation",
    "plot_invariant_drift",
    "plot_kovalevskaya",
    "plot_momentum_exchange",
    "plot_wheel_speeds",
    "plot_gravity_gradient_stability",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
