"""The figures of docs/spacecraft.md: attitude in orbit.

Run ``python docs/examples/spacecraft_figures.py`` to (re)make, in ``docs/_static/``:

* ``gravity_gradient_stability.png``: the Lagrange and DeBra-Delp regions in the
  ``(k1, k3)`` plane (:func:`poinsot.plotting.plot_gravity_gradient_stability`) with
  the inertia ratios of the bodies of docs/spacecraft.md marked;
* ``pitch_libration.png``: the pitch angle ``theta(t)`` of a satellite in a circular
  500 km orbit, the exact pendulum (:class:`poinsot.dynamics.PitchLibration`) against
  the integrated 3-D attitude (:meth:`poinsot.dynamics.Spacecraft.simulate`), for a
  libration and a circulation;
* ``nadir_pointing.png``: the pointing error (deg, log scale) and the wheel speeds of
  ``examples/nadir_pointing_wheels.toml`` (quaternion PD with feedforward through four
  reaction wheels, docs/theory.md §10.3).

It prints the largest differences it finds (exact vs integrated pitch).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from poinsot import Rotation
from poinsot.dynamics import (
    KeplerOrbit,
    PitchLibration,
    QuaternionPD,
    ReactionWheels,
    Spacecraft,
    gravity_gradient_stability,
)
from poinsot.plotting import plot_gravity_gradient_stability

STATIC = Path(__file__).resolve().parents[1] / "_static"
R_EARTH = 6378.137e3  # m, as the spacecraft scenario kind's `altitude`

# (label, principal moments (roll along-track, pitch orbit normal, yaw nadir), kg m^2)
BODIES = (
    ("gravity_gradient_libration.toml", [80.0, 100.0, 40.0]),
    ("nadir_pointing_wheels.toml", [120.0, 100.0, 80.0]),
    ("bdot_detumbling.toml (3U, long axis nadir)", [0.035, 0.035, 0.008]),
    ("moments (2.047, 1, 1.102)", [2.047, 1.0, 1.102]),
)


def stability(fig: object) -> None:
    ax = fig.add_subplot(1, 1, 1)  # type: ignore[attr-defined]
    plot_gravity_gradient_stability(ax=ax, resolution=401)
    for (label, moments), marker in zip(BODIES, "os^D", strict=True):
        s = gravity_gradient_stability(moments)
        ax.plot(float(s.k1), float(s.k3), marker, ms=7, label=f"{label}: {s.region}")
    ax.legend(loc="upper left", fontsize=6)


def pitch(fig: object) -> list[float]:
    orbit = KeplerOrbit(R_EARTH + 500e3, 0.0, 51.6, 0.0, 0.0, 0.0, degrees=True)
    inertia = [80.0, 100.0, 40.0]
    sat = Spacecraft(inertia, orbit)
    n = orbit.mean_motion
    t = np.linspace(0.0, 2.0 * orbit.period, 401)
    axes = fig.subplots(2, 1, sharex=True)  # type: ignore[attr-defined]
    diffs = []
    cases = ((np.radians(25.0), 0.0, "libration: theta0 = 25 deg, theta0' = 0"),
             (0.0, 2.5 * n, "circulation: theta0 = 0, theta0' = 2.5 n"))  # fmt: skip
    for ax, (theta0, rate0, title) in zip(axes, cases, strict=True):
        lib = PitchLibration(inertia, n, theta0=theta0, rate0=rate0)
        q0 = sat.orbit_attitude(0.0) * Rotation.from_rotvec([0.0, theta0, 0.0])
        w0 = sat.orbit_rate(q0, 0.0) + [0.0, rate0, 0.0]  # body rate w2 = theta' - n
        tr = sat.simulate(q0, w0, t)
        m = sat.relative(tr).as_matrix()  # R_ob = R2(theta)
        theta = 0.5 * np.unwrap(2.0 * np.arctan2(m[:, 0, 2], m[:, 0, 0]))
        exact = lib.theta(t)
        diffs.append(float(np.max(np.abs(theta - exact))))
        ax.plot(t / orbit.period, np.degrees(exact), "k-", lw=2.5, alpha=0.4,
                label="exact (PitchLibration)")  # fmt: skip
        ax.plot(t[::8] / orbit.period, np.degrees(theta[::8]), "o", ms=3, color="tab:blue",
                label="integrated 3-D attitude (DOP853)")  # fmt: skip
        ax.set_ylabel("pitch theta (deg)")
        ax.set_title(f"{title}  ({lib.regime}, max difference {diffs[-1]:.1e} rad)",
                     fontsize=9)  # fmt: skip
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("t / orbit period")
    return diffs


def nadir(fig: object) -> float:
    orbit = KeplerOrbit(R_EARTH + 600e3, 0.0, 97.8, 30.0, 0.0, 0.0, degrees=True)
    inertia = [120.0, 100.0, 80.0]
    ref = Spacecraft(inertia, orbit).orbit_reference()
    law = QuaternionPD(0.5, 7.0, target=ref, inertia=inertia)
    wheels = ReactionWheels(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.57735027] * 3], 0.05,
        max_torque=0.2, max_speed=6000.0 * 2.0 * np.pi / 60.0,
    )  # fmt: skip
    sat = Spacecraft(inertia, orbit, dipole=[0.05, 0.0, 0.02], control=law, wheels=wheels)
    q0 = sat.orbit_attitude(0.0) * Rotation.from_euler("ZYX", [20.0, -15.0, 10.0], degrees=True)
    w0 = sat.orbit_rate(q0, 0.0) + [0.01, -0.005, 0.008]
    t = np.linspace(0.0, 600.0, 301)
    tr = sat.simulate(q0, w0, t)
    err = np.degrees(sat.pointing_error(tr))
    ax1, ax2 = fig.subplots(2, 1, sharex=True)  # type: ignore[attr-defined]
    ax1.semilogy(t, np.maximum(err, 1e-12), color="tab:red")
    ax1.set_ylabel("pointing error (deg)")
    ax1.set_title("nadir_pointing_wheels.toml: quaternion PD + feedforward, four wheels",
                  fontsize=9)  # fmt: skip
    ax1.grid(alpha=0.3, which="both")
    rpm = tr.wheel_speed * 60.0 / (2.0 * np.pi)
    for i in range(rpm.shape[1]):
        ax2.plot(t, rpm[:, i], label=f"wheel {i + 1}")
    ax2.set_ylabel("wheel speed (rpm)")
    ax2.set_xlabel("t (s)")
    ax2.legend(fontsize=7, ncol=4)
    ax2.grid(alpha=0.3)
    return float(err[-1])


def main() -> int:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 5.6), layout="constrained")
    stability(fig)
    fig.savefig(STATIC / "gravity_gradient_stability.png", dpi=80)
    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    diffs = pitch(fig)
    fig.savefig(STATIC / "pitch_libration.png", dpi=80)
    print(f"pitch, exact vs integrated: max difference {diffs[0]:.2e} rad (libration), "
          f"{diffs[1]:.2e} rad (circulation)")  # fmt: skip
    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    final = nadir(fig)
    fig.savefig(STATIC / "nadir_pointing.png", dpi=80)
    print(f"nadir pointing: error after 600 s {final:.2e} deg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
