"""Benchmark of angular velocity from attitude samples and of the rotation spline.

Peer measured in the same process: SciPy's ``RotationSpline`` (construction, and
its angular rate at the samples, the usual SciPy way to get omega from an
attitude history). Prints the median of several runs, the ratio (peer time /
poinsot time; > 1 = poinsot faster) and the max error of omega at the samples
against the closed form, for the motion ``R(t) = exp(t w1^) exp(t w2^)``.

Run: ``.venv/bin/python benchmarks/bench_angular_velocity.py``
"""

from __future__ import annotations

import numpy as np
from _timing import median_time
from scipy.spatial.transform import Rotation as SciRotation
from scipy.spatial.transform import RotationSpline as SciSpline

from poinsot import Rotation
from poinsot.kinematics.attitude_history import angular_velocity, rotation_spline

W1 = np.array([0.3, -0.7, 1.1])
W2 = np.array([1.3, 0.4, -0.5])


def motion(n, T=30.0):
    t = np.linspace(0.0, T, n)
    R = Rotation.from_rotvec(t[:, None] * W1) * Rotation.from_rotvec(t[:, None] * W2)
    w = Rotation.from_rotvec(-t[:, None] * W2).apply(W1) + W2
    return t, R, w


def main():
    rows = []
    for n in (1_000, 10_000, 100_000):
        t, R, w = motion(n)
        q = R.as_quat()
        sr = SciRotation.from_quat(q[:, [1, 2, 3, 0]])

        t_ours = median_time(lambda t=t, q=q: angular_velocity(t, q))
        t_spl = median_time(lambda t=t, q=q: rotation_spline(t, q)(t, 1))
        t_sci = median_time(lambda t=t, sr=sr: SciSpline(t, sr)(t, 1))
        e_ours = np.abs(angular_velocity(t, q) - w).max()
        e_spl = np.abs(rotation_spline(t, q)(t, 1) - w).max()
        e_sci = np.abs(SciSpline(t, sr)(t, 1) - w).max()
        rows.append((n, t_ours, t_spl, t_sci, t_sci / t_ours, t_sci / t_spl, e_ours, e_spl, e_sci))
    hdr = (
        f"{'n':>8} {'av [ms]':>9} {'spline':>9} {'scipy':>9} {'x av':>6} {'x spl':>6} "
        f"{'err av':>9} {'err spl':>9} {'err scipy':>9}"
    )
    print("omega at the samples of a 30 s attitude history (speed ratio = scipy / poinsot)")
    print(hdr)
    for n, a, s, c, ra, rs, ea, es, ec in rows:
        print(
            f"{n:>8} {a * 1e3:>9.2f} {s * 1e3:>9.2f} {c * 1e3:>9.2f} {ra:>6.2f} {rs:>6.2f} "
            f"{ea:>9.1e} {es:>9.1e} {ec:>9.1e}"
        )


if __name__ == "__main__":
    main()
