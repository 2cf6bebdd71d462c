"""The figure of docs/gyrostat.md: polhodes of a dual-spin gyrostat as the rotor grows.

Run ``python docs/examples/gyrostat_figures.py`` to (re)make
``docs/_static/gyrostat_polhodes.png``: moments ``(1, 2, 3)`` kg m^2, ``|K| = 2``
kg m^2/s, the rotor along the intermediate axis with ``h2 = 0, 0.4, 1`` kg m^2/s. The
permanent rotation ``m = +|K| e2`` is stable for ``h2 > (1 - I2 / I3) |K| = 2/3``
(docs/gyrostat.md, "Dual-spin stabilisation"). It prints the stability of that spin.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from poinsot.dynamics import gyrostat_spin_stable
from poinsot.plotting import plot_gyrostat_polhodes

STATIC = Path(__file__).resolve().parents[1] / "_static"
MOMENTS = np.array([1.0, 2.0, 3.0])
K = 2.0
H2 = (0.0, 0.4, 1.0)


def main() -> int:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.5, 4.8), layout="constrained")
    axes = [fig.add_subplot(1, 3, i + 1, projection="3d") for i in range(3)]
    hs = [[0.0, h2, 0.0] for h2 in H2]
    plot_gyrostat_polhodes(MOMENTS, hs, momentum=K, levels=10, n=60, ax=axes)
    for ax in axes:
        ax.view_init(elev=20, azim=-35)
    fig.savefig(STATIC / "gyrostat_polhodes.png", dpi=70)
    for h2 in H2:
        spin = (K - h2) / MOMENTS[1]  # m2 = I2 W + h2 = |K|
        stable = gyrostat_spin_stable(MOMENTS, [0.0, h2, 0.0], [0.0, spin, 0.0])
        print(f"h2 = {h2}: spin W = {spin} about e2 stable: {stable}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
