"""Benchmark of poinsot.kinematics fields, composite motion and the Frenet frame.

Peers measured in the same process: the bare NumPy expressions (``np.cross``)
for Euler/Rivals/Coriolis -- so the ratio is the cost of validation and of
returning every term -- and, for the Frenet frame, the obvious hand pipeline
with ``numpy.gradient`` (2nd order) on the same samples, compared for time and
for accuracy on a helix. Prints the median of several runs; ratio = peer time /
poinsot time (> 1 = poinsot faster).

Run: ``.venv/bin/python benchmarks/bench_fields.py``
"""

from __future__ import annotations

import numpy as np
from _timing import median_time

from poinsot.kinematics import FrameMotion, acceleration_field, frenet, point_motion, velocity_field


def gradient_frenet(t, r):
    v = np.gradient(r, t, axis=0, edge_order=2)
    a = np.gradient(v, t, axis=0, edge_order=2)
    j = np.gradient(a, t, axis=0, edge_order=2)
    vxa = np.cross(v, a)
    c = np.linalg.norm(vxa, axis=-1)
    kappa = c / np.linalg.norm(v, axis=-1) ** 3
    tau = np.einsum("ni,ni->n", vxa, j) / c**2
    return kappa, tau


def main():
    rng = np.random.default_rng(0)
    rows = []

    n = 1_000_000
    v0, w, eps, a0 = rng.normal(size=(4, 3))
    r = rng.normal(size=(n, 3))
    t_p = median_time(lambda: velocity_field(v0, w, r))
    t_n = median_time(lambda: v0 + np.cross(w, r))
    rows.append(("velocity_field, 1e6 points", t_p, t_n, ""))
    t_p = median_time(lambda: acceleration_field(a0, w, eps, r))
    t_n = median_time(lambda: a0 + np.cross(eps, r) + np.cross(w, np.cross(w, r)))
    rows.append(("acceleration_field, 1e6 points", t_p, t_n, ""))

    m = 100_000
    fm = FrameMotion(rng.normal(size=(m, 3)), rng.normal(size=(m, 3)), rng.normal(size=(m, 3)))
    s, vr, ar = rng.normal(size=(3, m, 3))

    def bare():
        ve = fm.origin_velocity + np.cross(fm.omega, s)
        we = (
            fm.origin_acceleration + np.cross(fm.eps, s) + np.cross(fm.omega, np.cross(fm.omega, s))
        )
        return ve + vr, we + 2 * np.cross(fm.omega, vr) + ar

    t_p = median_time(lambda: point_motion(fm, s, vr, ar))
    t_n = median_time(bare)
    rows.append(("point_motion (all terms), 1e5 times", t_p, t_n, ""))

    A, B = 2.0, 0.7
    kappa, tau = A / (A * A + B * B), B / (A * A + B * B)
    for k in (1_000, 100_000):
        t = np.linspace(0, 20, k)
        rr = np.stack([A * np.cos(t), A * np.sin(t), B * t], -1)
        f = frenet(t, rr)
        kg, tg = gradient_frenet(t, rr)
        inner = slice(5, -5)
        acc = (
            f"torsion err {np.abs(f.torsion - tau)[inner].max():.1e} vs "
            f"{np.abs(tg - tau)[inner].max():.1e}; curvature "
            f"{np.abs(f.curvature - kappa)[inner].max():.1e} vs "
            f"{np.abs(kg - kappa)[inner].max():.1e}"
        )
        t_p = median_time(lambda t=t, rr=rr: frenet(t, rr), repeat=3)
        t_n = median_time(lambda t=t, rr=rr: gradient_frenet(t, rr), repeat=3)
        rows.append((f"frenet vs np.gradient, n={k}", t_p, t_n, acc))

    print(f"{'case':40s} {'poinsot [ms]':>12s} {'peer [ms]':>10s} {'ratio':>6s}  notes")
    for name, tp, tn, note in rows:
        print(f"{name:40s} {tp * 1e3:12.2f} {tn * 1e3:10.2f} {tn / tp:6.2f}  {note}")


if __name__ == "__main__":
    main()
