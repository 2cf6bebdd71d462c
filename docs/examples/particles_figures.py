"""Worked examples of docs/particles.md: free fall on the rotating Earth, a Foucault
pendulum, and a precessing central-force orbit.

Run ``python docs/examples/particles_figures.py`` to (re)make
``docs/_static/particles_fall.png``, ``particles_foucault.png`` and
``particles_orbit.png``; it prints the numbers quoted on the page.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from poinsot.dynamics import (
    CentralOrbit,
    earth_frame,
    eastward_deflection,
    foucault_pendulum,
    foucault_precession_rate,
    inverse_square,
    kepler,
    simulate_particle,
)

STATIC = Path(__file__).resolve().parents[1] / "_static"


def free_fall(ax_path, ax_err):
    """A stone dropped from 158 m at 50.9 deg N (Reich's Freiberg shaft, 1831)."""
    g, h, lat = 9.81, 158.0, np.deg2rad(50.9)
    fall = np.sqrt(2 * h / g)
    t = np.linspace(0.0, fall, 200)
    tr = simulate_particle(
        earth_frame(lat), [0, 0, -g], [0, 0, h], [0, 0, 0], t, rtol=1e-12, atol=1e-14, inertial=True
    )
    east = tr.position[:, 0]
    ax_path.plot(1000 * east, tr.position[:, 2], label="simulated")
    first = eastward_deflection(h - tr.position[:, 2], lat, g)  # as a function of the drop
    ax_path.plot(
        1000 * first,
        tr.position[:, 2],
        "k--",
        lw=0.8,
        label=r"$\frac{1}{3}\Omega g t^3\cos\varphi$",
    )
    ax_path.set_xlabel("east of the plumb line (mm)")
    ax_path.set_ylabel("height (m)")
    ax_path.set_title("Free fall from 158 m at 50.9 deg N")
    ax_path.legend(fontsize="small")
    # relative error of the first-order formula against Omega: slope 2 on log axes
    oms = np.geomspace(1e-5, 1e-2, 7)
    errs = []
    for om in oms:
        r = simulate_particle(
            earth_frame(lat, om),
            [0, 0, -g],
            [0, 0, h],
            [0, 0, 0],
            [0.0, fall],
            rtol=1e-13,
            atol=1e-15,
        )
        d = eastward_deflection(h, lat, g, om)
        errs.append(abs(r.position[-1, 0] / d - 1))
    ax_err.loglog(oms, errs, "o-", label="simulated vs first order")
    ax_err.loglog(oms, errs[-1] * (oms / oms[-1]) ** 2, "k--", lw=0.8, label=r"$\propto\Omega^2$")
    ax_err.axvline(7.2921159e-5, color="gray", lw=0.6)
    ax_err.set_xlabel(r"$\Omega$ (rad/s)")
    ax_err.set_ylabel("relative error of the deflection")
    ax_err.legend(fontsize="small")
    print(
        f"deflection: simulated {1000 * east[-1]:.4f} mm, first order "
        f"{1000 * eastward_deflection(h, lat, g):.4f} mm, relative errors {errs}"
    )


def foucault(ax):
    lat = np.deg2rad(48.85)
    om = 50 * 7.2921159e-5  # a 50x faster Earth, to see the plane turn in 10 minutes
    t = np.linspace(0, 600, 60001)
    tr = foucault_pendulum(67.0, lat, t, omega=om, amplitude=3.0)
    from poinsot.plotting import plot_swing_plane

    plot_swing_plane(tr, rate=foucault_precession_rate(lat, om), ax=ax)
    ax.set_title(r"Foucault pendulum (67 m, Paris, $\Omega$ x 50)")


def orbit(ax):
    orb = CentralOrbit.from_state(
        kepler(1.0) + inverse_square(0.05), [1.0, 0.0, 0.0], [0.0, 1.2, 0.0]
    )
    from poinsot.plotting import plot_orbit

    plot_orbit(orb, np.linspace(0, 4 * orb.radial_period, 2000), ax=ax)
    print(
        f"orbit: apsides {tuple(orb.apsides)}, apsidal angle / pi "
        f"{orb.apsidal_angle / np.pi:.12f}, closed form "
        f"{1 / np.sqrt(1 + 2 * 0.05 / (1.2**2)):.12f}, radial period {orb.radial_period:.12f}"
    )


def main() -> int:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9, 3.8), layout="constrained")
    a, b = fig.subplots(1, 2)
    free_fall(a, b)
    fig.savefig(STATIC / "particles_fall.png", dpi=100)
    fig = Figure(figsize=(7, 3.6), layout="constrained")
    foucault(fig.subplots())
    fig.savefig(STATIC / "particles_foucault.png", dpi=100)
    fig = Figure(figsize=(5.5, 5.5), layout="constrained")
    orbit(fig.subplots())
    fig.savefig(STATIC / "particles_orbit.png", dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main())
