"""Closed-form properties of the Lagrange top (heavy symmetric top), docs/theory.md §10.

Used by :mod:`poinsot.scenarios.run` to report, for a gravity scenario whose body is
a Lagrange top, the first integrals, the nutation band and period, and the type of
motion. (A candidate for ``poinsot.dynamics`` once that area has a heavy-top module.)

With ``u = cos(theta)`` (``theta`` the tilt of the symmetry axis from the upward
vertical), ``A`` the equatorial moment about the fixed point, ``C`` the axial one,
``l`` the distance from the fixed point to the centre of mass, the integrals
``H = C r``, ``K_z = A psi' sin^2(theta) + H cos(theta)`` and
``E = A (theta'^2 + psi'^2 sin^2(theta)) / 2 + m g l cos(theta)`` give

    u'^2 = P(u) = (2/A)(E - m g l u)(1 - u^2) - (K_z - H u)^2 / A^2
         = (2 m g l / A)(u - u1)(u - u2)(u - u3),   -1 <= u1 <= u2 <= 1 <= u3,

so ``u`` oscillates in ``[u1, u2]`` with period
``4 K(k^2) / sqrt((2 m g l / A)(u3 - u1))``, ``k^2 = (u2 - u1)/(u3 - u1)``, and
``psi' = (K_z - H u) / (A (1 - u^2))``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["lagrange_top"]

#: Relative tolerance for "A = B" and "centre of mass on the symmetry axis".
SYMMETRY_RTOL = 1e-9


def lagrange_top(inertia_o, mass: float, r_c, g: float, quat0, omega0) -> dict | None:
    """Properties of the motion of a Lagrange top, or None if the body is not one.

    Parameters
    ----------
    inertia_o : array_like, shape (3, 3)
        Inertia about the fixed point, body axes.
    mass, g : float
        Mass (kg), gravity (m/s^2) along ``-z`` of space.
    r_c : array_like, shape (3,)
        Centre of mass relative to the fixed point, body axes (m).
    quat0, omega0 : array_like
        Initial attitude (scalar-first quaternion, body -> space) and body angular
        velocity (rad/s).

    Returns
    -------
    dict or None
        ``H``, ``K_z``, ``E``, ``maievskii_ratio`` (``C^2 r^2 / (4 A m g l)``, the
        sleeping top is stable above 1), the nutation bounds in ``theta``
        (``nutation_theta_min/max``, rad), ``nutation_period`` (s), ``psi_dot`` at
        both bounds and the motion type (``"regular precession"``, ``"waves"``,
        ``"loops"``, ``"cusps"``).

    Notes
    -----
    **Convention:** docs/theory.md §10; ``theta`` measured from the upward vertical ``+z``.

    Examples
    --------
    >>> import numpy as np
    >>> props = lagrange_top(np.diag([2.0, 2.0, 1.0]), 1.0, [0, 0, 0.5], 9.81,
    ...                      [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 30.0])
    >>> props["motion"], round(props["maievskii_ratio"], 3)
    ('sleeping top', 22.936)
    """
    from scipy.special import ellipk

    from ..rotations.rotation import Rotation

    j = np.asarray(inertia_o, dtype=float)
    r_c = np.asarray(r_c, dtype=float)
    w = np.asarray(omega0, dtype=float)
    l = float(np.linalg.norm(r_c))
    if l == 0.0:
        return None
    e = r_c / l
    c = float(e @ j @ e)
    scale = float(np.max(np.abs(j)))
    if np.linalg.norm(j @ e - c * e) > SYMMETRY_RTOL * scale:
        return None  # the centre of mass is not on a principal axis
    p = np.eye(3) - np.outer(e, e)
    jp = p @ j @ p
    moments = np.linalg.eigvalsh(jp)[1:]  # the two equatorial moments (one 0 dropped)
    if abs(moments[1] - moments[0]) > SYMMETRY_RTOL * scale:
        return None  # not symmetric about the axis through the centre of mass
    a = float(moments.mean())
    rot = Rotation.from_quat(quat0)
    mgl = mass * g * l
    r = float(w @ e)  # spin component
    big_h = c * r
    k_z = float(rot.apply(j @ w)[2])
    u0 = float(rot.apply(e)[2])
    energy = 0.5 * float(w @ j @ w) - 0.5 * c * r * r + mgl * u0
    out: dict = {
        "case": "Lagrange top (docs/theory.md §10)",
        "A": a,
        "C": c,
        "l": l,
        "H": big_h,
        "K_z": k_z,
        "E": energy,
        "maievskii_ratio": c * c * r * r / (4.0 * a * mgl),
    }
    if abs(abs(u0) - 1.0) < 1e-12 and np.linalg.norm(np.cross(e, w)) <= 1e-12 * np.linalg.norm(w):
        out["motion"] = "sleeping top"
        out["sleeping_top_stable"] = bool(u0 > 0 and out["maievskii_ratio"] > 1.0) or u0 < 0
        return out
    # P(u) = (2/A)(E - mgl u)(1 - u^2) - (K_z - H u)^2 / A^2, as a cubic in u; its
    # three roots are real (P(+-1) <= 0 <= P(u0), P -> +inf): u1 <= u0 <= u2 <= 1 <= u3.
    # A double root (regular precession) may come out as a pair with an O(sqrt(eps))
    # imaginary part: the real parts are kept.
    cubic = np.polysub(
        np.polymul([-2.0 * mgl / a, 2.0 * energy / a], [-1.0, 0.0, 1.0]),
        np.polymul([-big_h, k_z], [-big_h, k_z]) / a**2,
    )
    u1, u2, u3 = np.sort(np.roots(cubic).real)
    u1, u2 = max(min(float(u1), u0), -1.0), min(max(float(u2), u0), 1.0)
    u3 = float(u3)
    k2 = (u2 - u1) / (u3 - u1) if u3 > u1 else 0.0
    rate = 2.0 * mgl / a * (u3 - u1)
    out["nutation_theta_min"] = float(np.arccos(u2))
    out["nutation_theta_max"] = float(np.arccos(u1))
    out["nutation_period"] = float(4.0 * ellipk(k2) / np.sqrt(rate)) if rate > 0 else None

    def psi_dot(u):
        return (k_z - big_h * u) / (a * (1.0 - u * u))

    p1, p2 = psi_dot(u1), psi_dot(u2)
    out["psi_dot_at_theta_max"] = float(p1)
    out["psi_dot_at_theta_min"] = float(p2)
    tol = 1e-9 * max(abs(p1), abs(p2), 1e-300)
    if u2 - u1 <= 1e-7:
        out["motion"] = "regular precession"
    elif abs(p1) <= tol or abs(p2) <= tol:
        out["motion"] = "cusps"
    elif p1 * p2 > 0:
        out["motion"] = "waves"
    else:
        out["motion"] = "loops"
    return out
