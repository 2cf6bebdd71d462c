"""Draw the figures of docs/heavy-top.md (docs/theory.md §10).

``docs/_static/heavy_top.png``: the symmetry axis of three Lagrange tops on the
unit sphere (waves, cusps, loops), the cubic ``P(u)`` of the loops top and its
``theta(t)`` exact against the default integrator.
``docs/_static/heavy_top_invariants.png``: the invariants of an asymmetric heavy
body along 10^5 steps of the splitting (orders 2 and 4), and the Kovalevskaya
integral for ``A = B = 2 C`` and ``A = B = 2.2 C``.

Run: ``.venv/bin/python examples/heavy_top_figures.py``
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from poinsot import Rotation
from poinsot.dynamics import HeavyRigidBody, LagrangeTop
from poinsot.plotting.heavy_top import (
    plot_axis_track,
    plot_cubic,
    plot_invariant_drift,
    plot_kovalevskaya,
    plot_nutation,
)

OUT = Path(__file__).resolve().parents[1] / "docs" / "_static"
A, C, MGL = 2.0, 1.0, 4.0


def tops():
    return {
        "waves": LagrangeTop(A, C, MGL, theta=0.6, spin=6.0, precession_rate=1.2),
        "cusps": LagrangeTop(A, C, MGL, theta=0.6, spin=6.0),
        "loops": LagrangeTop(A, C, MGL, theta=0.6, spin=6.0, precession_rate=-0.8),
    }


def main():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13, 8), layout="constrained")
    grid = fig.add_gridspec(2, 3)
    for k, (name, top) in enumerate(tops().items()):
        ax = fig.add_subplot(grid[0, k], projection="3d")
        plot_axis_track(top, periods=4.0, ax=ax)
        ax.view_init(elev=55, azim=-60)
        ax.set_title(name)
    loops = tops()["loops"]
    plot_cubic(loops, ax=fig.add_subplot(grid[1, 0]))
    body = HeavyRigidBody([A, A, C], 1.0, [0.0, 0.0, MGL / 9.80665])
    t = np.linspace(0.0, 3 * loops.nutation_period, 301)
    tr = body.simulate(loops.rotation(0.0), loops.omega(0.0), t, max_step=2e-3)
    plot_nutation(loops, tr, ax=fig.add_subplot(grid[1, 1:]))
    fig.savefig(OUT / "heavy_top.png", dpi=90)

    fig = Figure(figsize=(12, 4), layout="constrained")
    j = [[1.2, 0.1, -0.05], [0.1, 1.6, 0.02], [-0.05, 0.02, 2.1]]
    heavy = HeavyRigidBody(j, 2.0, [0.05, -0.02, 0.3], g=9.81)
    q0 = Rotation.from_euler("ZXZ", [0.3, 0.8, -0.2]).as_quat()
    t = np.linspace(0.0, 100.0, 2001)
    ax = fig.add_subplot(1, 2, 1)
    tr4 = heavy.simulate(q0, [1.0, -2.0, 6.0], t, order=4, max_step=1e-3)
    plot_invariant_drift(heavy, tr4, ax=ax)
    ax.set_title("invariants, splitting order 4, h = 1e-3 s (1e5 steps)")
    runs = []
    for ratio in (2.0, 2.2):
        b = HeavyRigidBody([ratio, ratio, 1.0], 1.0, [0.3, 0.0, 0.0], g=9.81)
        tk = np.linspace(0.0, 30.0, 1501)
        trk = b.simulate(q0, [1.5, -0.7, 2.0], tk, method="dop853", rtol=1e-13, atol=1e-13)
        runs.append((f"A = B = {ratio:g} C", b, trk))
    plot_kovalevskaya(runs, ax=fig.add_subplot(1, 2, 2))
    fig.savefig(OUT / "heavy_top_invariants.png", dpi=90)
    print("wrote", OUT / "heavy_top.png", "and", OUT / "heavy_top_invariants.png")


if __name__ == "__main__":
    main()
