"""Worked example: a point on the rim of a spinning, precessing disc.

A horizontal arm of length L turns about the vertical z axis (precession rate
Omega(t) = Omega0 + alpha t). At its end a disc of radius R, whose axis is the
arm, spins relative to the arm at the constant rate omega_s. A point P on the
rim moves in composite motion: the arm is the moving (transport) frame, the
spin is the relative motion. Its absolute acceleration splits into

    W = W_e (transport) + W_c (Coriolis, 2 Omega x V_r) + W_r (relative),

computed here with :func:`poinsot.kinematics.point_motion` and checked against
a brute-force second difference of P's position.

Run ``python docs/examples/disc_acceleration.py`` to (re)make
``docs/_static/disc_acceleration.png``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from poinsot.kinematics import FrameMotion, point_motion

L, R = 1.0, 0.25  # arm length, disc radius (m)
OMEGA0, ALPHA = 2.0, 1.0  # precession rate (rad/s) and its rate of change (rad/s^2)
OMEGA_S = 6.0  # spin of the disc relative to the arm (rad/s)


def basis(t):
    """Arm frame at time t in fixed components: e_r (along the arm), e_t, e_z."""
    psi = OMEGA0 * t + 0.5 * ALPHA * t**2
    e_r = np.stack([np.cos(psi), np.sin(psi), 0 * t], -1)
    e_t = np.stack([-np.sin(psi), np.cos(psi), 0 * t], -1)
    e_z = np.broadcast_to([0.0, 0.0, 1.0], e_r.shape)
    return e_r, e_t, e_z


def position(t):
    """Position of the rim point: r = L e_r + R (cos phi e_t + sin phi e_z)."""
    e_r, e_t, e_z = basis(t)
    phi = (OMEGA_S * t)[..., None]
    return L * e_r + R * (np.cos(phi) * e_t + np.sin(phi) * e_z)


def disc_motion(t):
    """CompositeMotion of the rim point at the times t (batch shape t.shape)."""
    e_r, e_t, e_z = basis(t)
    phi = (OMEGA_S * t)[..., None]
    arm = FrameMotion(
        omega=(OMEGA0 + ALPHA * t)[..., None] * e_z,  # transport angular velocity
        eps=np.broadcast_to([0.0, 0.0, ALPHA], e_z.shape),  # its derivative
    )  # the arm's origin (the pivot) is fixed
    s = position(t)
    # relative motion, as seen on the arm: a circle of radius R at rate OMEGA_S
    v_rel = R * OMEGA_S * (-np.sin(phi) * e_t + np.cos(phi) * e_z)
    a_rel = -R * OMEGA_S**2 * (np.cos(phi) * e_t + np.sin(phi) * e_z)
    return point_motion(arm, s, v_rel, a_rel)


def main(out: str | Path | None = None) -> float:
    """Make the figure; return the largest deviation from brute force (m/s^2)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from poinsot.plotting.motion import plot_acceleration_terms

    t = np.linspace(0.0, 2 * np.pi / OMEGA_S * 2, 400)  # two spin periods
    m = disc_motion(t)

    h = 1e-4  # brute force: central second difference of the position
    brute = (position(t + h) - 2 * position(t) + position(t - h)) / h**2
    err = float(np.abs(m.acceleration - brute).max())

    fig, axes = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
    plot_acceleration_terms(t, m, ax=axes[0])
    axes[0].set_title("Rim point of a spinning, precessing disc: |W| by term")
    e_r = basis(t)[0]  # along the arm, outwards
    plot_acceleration_terms(t, m, ax=axes[1], component=e_r)
    axes[1].set_title("component along the arm (outwards)")
    axes[1].get_legend().remove()
    out = (
        Path(out)
        if out
        else Path(__file__).resolve().parents[1] / "_static" / "disc_acceleration.png"
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(f"wrote {out}; max |W - brute force| = {err:.2e} m/s^2")
    return err


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
