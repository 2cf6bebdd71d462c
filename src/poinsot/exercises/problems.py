"""The problem types (issue 46). Each draws clean parameters from a seeded generator,
solves the problem with its own formulas written out here (the worked solution) and
again with poinsot's numeric API, and recomputes the answer under each typical mistake.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..dynamics import (
    CentralOrbit,
    FreeRigidBody,
    LagrangeTop,
    foucault_period,
    gyroscopic_moment,
    inertial_forces,
    kepler,
    reduce_forces,
    regular_precession_rates,
)
from ..kinematics import (
    FrameMotion,
    acceleration_field,
    omega_from_euler_rates,
    point_motion,
    velocity_center,
    velocity_field,
)
from ..mass import disc, parallel_axis, principal_axes, rod
from ..rotations.rotation import Rotation
from ..rotations.transform import RigidTransform
from .core import Draft, Step, problem

__all__: list[str] = []

D2R = math.pi / 180.0
AXES = "xyz"
UNIT = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


# ------------------------------------------------------------------ written-out helpers
def rot(axis: str, angle: float) -> list[list[float]]:
    """The matrix of a rotation by ``angle`` (rad) about the coordinate axis (§2)."""
    c, s = math.cos(angle), math.sin(angle)
    if axis == "x":
        return [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
    if axis == "y":
        return [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
    return [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]


def matmul(a: list[list[float]], b: list[list[float]]) -> list[list[float]]:
    """``(a b)_ij = sum_k a_ik b_kj``, written out."""
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(a: list[list[float]]) -> list[list[float]]:
    return [[a[j][i] for j in range(3)] for i in range(3)]


def matvec(a: list[list[float]], v: list[float]) -> list[float]:
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def cross(a: list[float], b: list[float]) -> list[float]:
    """``a x b`` by components."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def add(*vs: list[float]) -> list[float]:
    return [sum(v[i] for v in vs) for i in range(3)]


def scale(k: float, v: list[float]) -> list[float]:
    return [k * x for x in v]


def num(x: float) -> str:
    """A number as printed in statements and solutions (round-off noise removed)."""
    x = 0.0 if abs(x) < 1e-12 else float(x)
    s = f"{x:.6g}"
    return "0" if s in ("-0", "0") else s


def vec(v: object) -> str:
    return "(" + ", ".join(num(x) for x in np.asarray(v, dtype=float).reshape(-1)) + ")"


def mat(m: object) -> str:
    a = np.asarray(m, dtype=float).reshape(3, 3)
    return "[" + "; ".join(", ".join(num(x) for x in row) for row in a) + "]"


def ints(rng: np.random.Generator, n: int, low: int = -3, high: int = 3) -> list[float]:
    """``n`` integers in ``[low, high]``, not all zero."""
    while True:
        v = [float(x) for x in rng.integers(low, high + 1, size=n)]
        if any(v):
            return v


def angle15(rng: np.random.Generator, low: int, high: int, *, nonzero: bool = True) -> int:
    """A multiple of 15 degrees in ``[low, high]`` (0 excluded if ``nonzero``)."""
    choices = [a for a in range(low, high + 1, 15) if a or not nonzero]
    return int(rng.choice(choices))


def quiet(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Call the API without its warnings (a gimbal-lock variant warns by design)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


# ---------------------------------------------------------------- (1) composition
@problem("composition", "composition of two rotations, fixed or body axes (§4)")
def composition(rng: np.random.Generator) -> Draft:
    ax1, ax2 = (str(a) for a in rng.choice(list(AXES), size=2, replace=False))
    a1, a2 = angle15(rng, -180, 180), angle15(rng, -180, 180)
    r = ints(rng, 3)
    body = bool(rng.integers(2))
    A, B = rot(ax1, a1 * D2R), rot(ax2, a2 * D2R)
    where = (
        f"then about the *new* (body) axis {ax2}' obtained after the first rotation"
        if body
        else f"then about the *fixed* axis {ax2}"
    )
    statement = (
        f"A body is turned by {a1} deg about the fixed axis {ax1}, {where}, by {a2} deg. "
        f"Find the image of the body point with initial position r = {vec(r)} (m), i.e. "
        "r'' = C r with C the composite rotation."
    )
    C = matmul(A, B) if body else matmul(B, A)
    C_rev = matmul(B, A) if body else matmul(A, B)
    answer = matvec(C, r)
    ra, rb = (Rotation.from_axis_angle(UNIT[a], x * D2R) for a, x in ((ax1, a1), (ax2, a2)))
    api = ((ra * rb) if body else (rb * ra)).apply(r)
    rule = (
        "Body axes (two points of view): C = A B, the second matrix on the right."
        if body
        else "Fixed axes (one point of view): C = B A, the later rotation on the left."
    )
    deg_as_rad = matmul(rot(ax1, a1), rot(ax2, a2)) if body else matmul(rot(ax2, a2), rot(ax1, a1))
    steps = [
        Step(f"Matrix A of {a1} deg about {ax1}: A = {mat(A)}.", "§2", np.array(A)),
        Step(f"Matrix B of {a2} deg about {ax2}: B = {mat(B)}.", "§2", np.array(B)),
        Step(f"{rule} C = {mat(C)}.", "§4", np.array(C)),
        Step(f"Image r'' = C r = {vec(answer)} m.", "§4", np.array(answer)),
    ]
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("x", "y", "z"),
        "m",
        {
            "composition order reversed": matvec(C_rev, r),
            "transposed matrix (passive instead of active)": matvec(transpose(C), r),
            "degrees taken as radians": matvec(deg_as_rad, r),
        },
    )


# ------------------------------------------------------------- (2) Euler angles ZXZ
def zxz_angles(C: list[list[float]]) -> list[float]:
    """Classical Euler angles (deg) of ``C = A_psi A_theta A_phi`` (§3); at gimbal lock
    phi = 0 and psi takes the whole sum (or difference)."""
    theta = math.acos(max(-1.0, min(1.0, C[2][2])))
    if abs(math.sin(theta)) < 1e-9:
        return [math.atan2(C[1][0], C[0][0]) / D2R, theta / D2R, 0.0]
    psi = math.atan2(C[0][2], -C[1][2])
    phi = math.atan2(C[2][0], C[2][1])
    return [psi / D2R, theta / D2R, phi / D2R]


@problem("euler-angles", "classical Euler angles (ZXZ) of a matrix, gimbal lock too (§3)")
def euler_angles(rng: np.random.Generator) -> Draft:
    lock = rng.random() < 0.25
    while True:
        psi, phi = angle15(rng, -165, 165), angle15(rng, -165, 165)
        theta = int(rng.choice([0, 180])) if lock else angle15(rng, 15, 165)
        if lock:
            total = psi + phi if theta == 0 else psi - phi
            if total % 360 == 180:
                continue
            psi, phi = (total + 180) % 360 - 180, 0
        break
    C = matmul(matmul(rot("z", psi * D2R), rot("x", theta * D2R)), rot("z", phi * D2R))
    answer = zxz_angles(C)
    api = quiet(Rotation.from_matrix(np.array(C)).as_euler, "ZXZ", degrees=True)
    statement = (
        f"The attitude matrix of a body (body components to fixed components) is C = {mat(C)}. "
        "Find its classical Euler angles (precession psi, nutation theta, proper rotation "
        "phi; intrinsic Z X Z, C = A_psi A_theta A_phi) in degrees, psi and phi in "
        "[-180, 180], theta in [0, 180]. If theta is 0 or 180 (gimbal lock), take phi = 0."
    )
    steps = [
        Step(f"theta = arccos C33 = {num(answer[1])} deg.", "§3", np.array([answer[1]])),
    ]
    if lock:
        steps.append(
            Step(
                "sin theta = 0: gimbal lock, only psi + phi (theta = 0) or psi - phi "
                f"(theta = 180) is defined; with phi = 0, psi = atan2(C21, C11) = "
                f"{num(answer[0])} deg.",
                "§3",
                np.array([answer[0], answer[2]]),
            )
        )
    else:
        steps.append(
            Step(
                f"psi = atan2(C13, -C23) = {num(answer[0])} deg, phi = atan2(C31, C32) = "
                f"{num(answer[2])} deg.",
                "§3",
                np.array([answer[0], answer[2]]),
            )
        )
    back = matmul(
        matmul(rot("z", answer[0] * D2R), rot("x", answer[1] * D2R)), rot("z", answer[2] * D2R)
    )
    steps.append(Step(f"Back: A_psi A_theta A_phi = {mat(back)} = C.", "§3", np.array(back)))
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("psi", "theta", "phi"),
        "deg",
        {
            "psi and phi swapped": [answer[2], answer[1], answer[0]],
            "matrix read transposed": zxz_angles(transpose(C)),
            "answer in radians": [a * D2R for a in answer],
        },
        tolerance=0.05,
    )


# --------------------------------------------------------- (3) yaw, pitch, roll (ZYX)
def zyx_angles(C: list[list[float]]) -> list[float]:
    """Yaw, pitch, roll (deg) of ``C = A_z(yaw) A_y(pitch) A_x(roll)`` (§3)."""
    yaw = math.atan2(C[1][0], C[0][0])
    pitch = -math.asin(max(-1.0, min(1.0, C[2][0])))
    roll = math.atan2(C[2][1], C[2][2])
    return [yaw / D2R, pitch / D2R, roll / D2R]


@problem("yaw-pitch-roll", "ship/aircraft angles yaw-pitch-roll (intrinsic ZYX) of a matrix (§3)")
def yaw_pitch_roll(rng: np.random.Generator) -> Draft:
    yaw, roll = angle15(rng, -165, 165), angle15(rng, -165, 165)
    pitch = angle15(rng, -75, 75)
    C = matmul(matmul(rot("z", yaw * D2R), rot("y", pitch * D2R)), rot("x", roll * D2R))
    answer = zyx_angles(C)
    api = Rotation.from_matrix(np.array(C)).as_euler("ZYX", degrees=True)
    # the wrong sequence: C read as A_x(roll) A_y(pitch) A_z(yaw)
    b = math.asin(max(-1.0, min(1.0, C[0][2])))
    a = math.atan2(-C[1][2], C[2][2])
    c = math.atan2(-C[0][1], C[0][0])
    statement = (
        f"The attitude matrix of an aircraft (body to local axes) is C = {mat(C)}. Find the "
        "yaw psi, pitch theta and roll phi in degrees, for the aerospace sequence intrinsic "
        "Z Y X: C = A_z(psi) A_y(theta) A_x(phi), theta in [-90, 90]. (poinsot's Krylov "
        "preset is the ship sequence Z X Y, theory §3.)"
    )
    steps = [
        Step(
            "Third row: C31 = -sin theta, C32 = cos theta sin phi, C33 = cos theta cos phi; "
            "first column: C11 = cos psi cos theta, C21 = sin psi cos theta.",
            "§3",
        ),
        Step(f"theta = -arcsin C31 = {num(answer[1])} deg.", "§3", np.array([answer[1]])),
        Step(
            f"psi = atan2(C21, C11) = {num(answer[0])} deg, phi = atan2(C32, C33) = "
            f"{num(answer[2])} deg.",
            "§3",
            np.array([answer[0], answer[2]]),
        ),
    ]
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("yaw", "pitch", "roll"),
        "deg",
        {
            "sign of yaw": [-answer[0], answer[1], answer[2]],
            "sign of pitch (theta = arcsin C31)": [answer[0], -answer[1], answer[2]],
            "wrong sequence (C = A_x A_y A_z)": [c / D2R, b / D2R, a / D2R],
            "answer in radians": [x * D2R for x in answer],
        },
        tolerance=0.05,
    )


# ------------------------------------------------- (4) omega from Euler angle rates
def zxz_omega(angles: list[float], rates: list[float], frame: str) -> list[float]:
    """Euler's kinematic equations for Z X Z (§3), angles in rad."""
    psi, theta, phi = angles
    dpsi, dtheta, dphi = rates
    st, ct = math.sin(theta), math.cos(theta)
    if frame == "body":
        return [
            dpsi * st * math.sin(phi) + dtheta * math.cos(phi),
            dpsi * st * math.cos(phi) - dtheta * math.sin(phi),
            dpsi * ct + dphi,
        ]
    return [
        dtheta * math.cos(psi) + dphi * math.sin(psi) * st,
        dtheta * math.sin(psi) - dphi * math.cos(psi) * st,
        dpsi + dphi * ct,
    ]


@problem("euler-rates", "angular velocity from Euler angle rates, body or space axes (§3, §5)")
def euler_rates(rng: np.random.Generator) -> Draft:
    angles = [angle15(rng, -165, 165), angle15(rng, 15, 165), angle15(rng, -165, 165)]
    rates = ints(rng, 3)
    frame = "body" if rng.integers(2) else "space"
    other = "space" if frame == "body" else "body"
    rad = [a * D2R for a in angles]
    answer = zxz_omega(rad, rates, frame)
    api = omega_from_euler_rates("ZXZ", rad, rates, frame=frame)
    statement = (
        f"A body's classical Euler angles (Z X Z) are psi = {angles[0]} deg, theta = "
        f"{angles[1]} deg, phi = {angles[2]} deg, and their rates psi' = {num(rates[0])}, "
        f"theta' = {num(rates[1])}, phi' = {num(rates[2])} rad/s. Find the angular velocity "
        f"in {frame} components."
    )
    formula = (
        "p = psi' sin theta sin phi + theta' cos phi, q = psi' sin theta cos phi - theta' sin "
        "phi, r = psi' cos theta + phi'"
        if frame == "body"
        else "w = psi' e_z + theta' (cos psi, sin psi, 0) + phi' (sin psi sin theta, -cos psi "
        "sin theta, cos theta)"
    )
    steps = [
        Step(
            "w = psi' u1 + theta' u2 + phi' u3, the rates times the axes of the three "
            "rotations in their current positions.",
            "§3",
        ),
        Step(f"In {frame} components: {formula}.", "§3", np.array(answer)),
        Step(f"w = {vec(answer)} rad/s.", "§5", np.array(answer)),
    ]
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("x", "y", "z") if frame == "space" else ("p", "q", "r"),
        "rad/s",
        {
            "omega in the wrong frame": zxz_omega(rad, rates, other),
            "degrees taken as radians": zxz_omega([float(a) for a in angles], rates, frame),
            "angle rates taken as the components of omega": rates,
        },
    )


# ------------------------------------------- (5) velocity and acceleration of a point
@problem("rigid-point", "velocity and acceleration of a body point, Euler and Rivals (§6)")
def rigid_point(rng: np.random.Generator) -> Draft:
    v0, a0 = ints(rng, 3, -2, 2), ints(rng, 3, -2, 2)
    w, eps, rho = ints(rng, 3, -2, 2), ints(rng, 3, -2, 2), ints(rng, 3)
    v = add(v0, cross(w, rho))
    rot_t, cen = cross(eps, rho), cross(w, cross(w, rho))
    a = add(a0, rot_t, cen)
    api = np.concatenate([velocity_field(v0, w, rho), acceleration_field(a0, w, eps, rho)])
    statement = (
        f"The pole O of a rigid body has velocity v_O = {vec(v0)} m/s and acceleration "
        f"a_O = {vec(a0)} m/s^2; the body's angular velocity is w = {vec(w)} rad/s and its "
        f"angular acceleration eps = {vec(eps)} rad/s^2. Find the velocity and the "
        f"acceleration of the body point P with OP = {vec(rho)} m."
    )
    steps = [
        Step(
            f"w x OP = {vec(cross(w, rho))}; v_P = v_O + w x OP = {vec(v)} m/s.", "§6", np.array(v)
        ),
        Step(f"Rotational acceleration eps x OP = {vec(rot_t)}.", "§6", np.array(rot_t)),
        Step(f"Centripetal acceleration w x (w x OP) = {vec(cen)}.", "§6", np.array(cen)),
        Step(f"a_P = a_O + eps x OP + w x (w x OP) = {vec(a)} m/s^2.", "§6", np.array(a)),
    ]
    rev_v = add(v0, cross(rho, w))
    rev_a = add(a0, cross(rho, eps), cross(cross(rho, w), w))
    return Draft(
        statement,
        steps,
        v + a,
        api,
        ("vx", "vy", "vz", "ax", "ay", "az"),
        "m/s, m/s^2",
        {
            "missing centripetal term": v + add(a0, rot_t),
            "cross product order reversed": rev_v + rev_a,
            "centripetal term with the wrong sign": v + add(a0, rot_t, scale(-1, cen)),
            "acceleration of the pole forgotten": v + add(rot_t, cen),
        },
    )


# ------------------------------------------------------------------ (6) Coriolis
@problem("coriolis", "absolute acceleration of a point moving in a rotating frame (§6, §9)")
def coriolis(rng: np.random.Generator) -> Draft:
    w = [0.0, 0.0, float(rng.integers(1, 4))] if rng.integers(2) else ints(rng, 3, -2, 2)
    s, v_rel, a_rel = ints(rng, 3), ints(rng, 3), ints(rng, 3, -2, 2)
    while not any(cross(w, v_rel)):
        v_rel = ints(rng, 3)
    cor = scale(2.0, cross(w, v_rel))
    cen = cross(w, cross(w, s))
    a = add(cen, cor, a_rel)
    api = point_motion(FrameMotion(omega=w), s, v_rel, a_rel).acceleration
    statement = (
        f"A frame turns with constant angular velocity w = {vec(w)} rad/s about its fixed "
        f"origin. A point at s = {vec(s)} m in it moves relative to the frame with velocity "
        f"v_r = {vec(v_rel)} m/s and relative acceleration a_r = {vec(a_rel)} m/s^2. Find "
        "its Coriolis acceleration and its absolute acceleration."
    )
    steps = [
        Step(
            f"Transport (centripetal) acceleration w x (w x s) = {vec(cen)}.", "§6", np.array(cen)
        ),
        Step(f"Coriolis acceleration a_c = 2 w x v_r = {vec(cor)} m/s^2.", "§6", np.array(cor)),
        Step(f"a = w x (w x s) + 2 w x v_r + a_r = {vec(a)} m/s^2.", "§6", np.array(a)),
    ]
    return Draft(
        statement,
        steps,
        a,
        api,
        ("x", "y", "z"),
        "m/s^2",
        {
            "missing factor 2 in Coriolis": add(cen, scale(0.5, cor), a_rel),
            "Coriolis with the wrong sign (v_r x w)": add(cen, scale(-1, cor), a_rel),
            "Coriolis term forgotten": add(cen, a_rel),
            "centripetal term forgotten": add(cor, a_rel),
        },
    )


# --------------------------------------------------------- (7) composite inertia
@dataclass(frozen=True)
class Part:
    """A point mass, a thin rod (length ``size`` along ``axis``) or a thin disc (radius
    ``size``, its axis along ``axis``) of mass ``m`` centred at ``c``."""

    kind: str
    m: float
    size: float
    axis: str
    c: list[float]


def _part(rng: np.random.Generator) -> Part:
    kind = str(rng.choice(["point", "rod", "disc"]))
    return Part(
        kind,
        float(rng.integers(1, 5)),
        float(rng.integers(1, 4)) * (3.0 if kind == "rod" else 2.0),
        str(rng.choice(list(AXES))),
        ints(rng, 3, -2, 2),
    )


def _own_central(p: Part) -> list[list[float]]:
    """Inertia about the part's own centre (axes of the problem), §8."""
    m, size, axis = p.m, p.size, p.axis
    k = AXES.index(axis)
    if p.kind == "point":
        d = [0.0, 0.0, 0.0]
    elif p.kind == "rod":  # m L^2 / 12 about the transverse axes, 0 along the rod
        d = [m * size**2 / 12.0] * 3
        d[k] = 0.0
    else:  # disc: m R^2 / 2 about its axis, m R^2 / 4 about the diameters
        d = [m * size**2 / 4.0] * 3
        d[k] = m * size**2 / 2.0
    return [[d[i] if i == j else 0.0 for j in range(3)] for i in range(3)]


def steiner(
    m: float, a: list[float], sign: float = 1.0, products: bool = True
) -> list[list[float]]:
    """``m (a.a E - a a^T)``, written out (§8)."""
    aa = sum(x * x for x in a)
    return [
        [
            sign * m * ((aa if i == j else 0.0) - (a[i] * a[j] if (products or i == j) else 0.0))
            for j in range(3)
        ]
        for i in range(3)
    ]


def madd(*ms: list[list[float]]) -> list[list[float]]:
    return [[sum(m[i][j] for m in ms) for j in range(3)] for i in range(3)]


def eig3(J: list[list[float]]) -> list[float]:
    """Eigenvalues (ascending) of a symmetric 3 x 3 matrix: the characteristic cubic
    solved by the trigonometric formula (principal moments, §8)."""
    p1 = J[0][1] ** 2 + J[0][2] ** 2 + J[1][2] ** 2
    q = (J[0][0] + J[1][1] + J[2][2]) / 3.0
    if p1 < 1e-300:
        return sorted([J[0][0], J[1][1], J[2][2]])
    p2 = (J[0][0] - q) ** 2 + (J[1][1] - q) ** 2 + (J[2][2] - q) ** 2 + 2 * p1
    p = math.sqrt(p2 / 6.0)
    B = [[(J[i][j] - (q if i == j else 0.0)) / p for j in range(3)] for i in range(3)]
    det = (
        B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1])
        - B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0])
        + B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0])
    )
    phi = math.acos(max(-1.0, min(1.0, det / 2.0))) / 3.0
    big = q + 2 * p * math.cos(phi)
    small = q + 2 * p * math.cos(phi + 2 * math.pi / 3)
    return [small, 3 * q - big - small, big]


@problem("composite-inertia", "inertia tensor of a composite body about a point, Steiner (§8)")
def composite_inertia(rng: np.random.Generator) -> Draft:
    while True:
        parts = [_part(rng) for _ in range(int(rng.integers(2, 4)))]
        total = sum(p.m for p in parts)
        cm = [sum(p.m * p.c[i] for p in parts) / total for i in range(3)]
        J = madd(*[madd(_own_central(p), steiner(p.m, p.c)) for p in parts])
        lam = eig3(J)
        if lam[0] > 0.5 and lam[1] - lam[0] > 0.5 and lam[2] - lam[1] > 0.5:
            break
    answer = [J[i][j] for i in range(3) for j in range(3)] + lam
    J_api = np.sum([parallel_axis(_api_central(p), p.m, p.c) for p in parts], axis=0)
    api = np.concatenate([np.asarray(J_api).reshape(-1), principal_axes(J_api)[0]])
    desc = []
    for p in parts:
        where = vec(p.c)
        if p.kind == "point":
            desc.append(f"a point mass {num(p.m)} kg at {where}")
        elif p.kind == "rod":
            desc.append(
                f"a thin rod of mass {num(p.m)} kg and length {num(p.size)} m along "
                f"the {p.axis} axis, centred at {where}"
            )
        else:
            desc.append(
                f"a thin disc of mass {num(p.m)} kg and radius {num(p.size)} m, its "
                f"axis along {p.axis}, centred at {where}"
            )
    statement = (
        "A rigid body is made of " + "; ".join(desc) + " (coordinates in m). Find its inertia "
        "tensor J_O about the origin O (kg m^2, off-diagonal entries = minus the products of "
        "inertia) and its principal moments about O."
    )
    steps = []
    for p in parts:
        Jc = _own_central(p)
        St = steiner(p.m, p.c)
        steps.append(
            Step(
                f"{str(p.kind).capitalize()} at {vec(p.c)}: own J_C = {mat(Jc)}; Steiner "
                f"term m (a.a E - a a^T) = {mat(St)}.",
                "§8",
                np.array(madd(Jc, St)),
            )
        )
    steps += [
        Step(f"Sum: J_O = {mat(J)} kg m^2.", "§8", np.array(J)),
        Step(
            f"Principal moments (roots of det(J_O - lam E) = 0): {vec(lam)} kg m^2.",
            "§8",
            np.array(lam),
        ),
    ]

    def variant(sign: float = 1.0, products: bool = True) -> list[float]:
        Jm = madd(*[madd(_own_central(p), steiner(p.m, p.c, sign, products)) for p in parts])
        return [Jm[i][j] for i in range(3) for j in range(3)] + eig3(Jm)

    wrong_point = madd(
        *[madd(_own_central(p), steiner(p.m, [p.c[i] - cm[i] for i in range(3)])) for p in parts]
    )
    return Draft(
        statement,
        steps,
        answer,
        api,
        tuple(f"J{i}{j}" for i in "xyz" for j in "xyz") + ("A", "B", "C"),
        "kg m^2",
        {
            "Steiner applied the wrong way (subtracted)": variant(sign=-1.0),
            "product terms forgotten in Steiner": variant(products=False),
            "distances to the centre of mass instead of O": [
                wrong_point[i][j] for i in range(3) for j in range(3)
            ]
            + eig3(wrong_point),
        },
    )


def _api_central(p: Part) -> np.ndarray:
    """The part's central inertia from poinsot's solids (symmetry axis z, then permuted)."""
    m, size, axis = p.m, p.size, p.axis
    if p.kind == "point":
        return np.zeros((3, 3))
    J = rod(m, size) if p.kind == "rod" else disc(m, size)
    # the problem's axis k is the solid's symmetry axis z
    d = np.diag(J)
    new = np.empty(3)
    k = AXES.index(axis)
    others = [i for i in range(3) if i != k]
    new[k], new[others[0]], new[others[1]] = d[2], d[0], d[1]
    return np.diag(new)


# ------------------------------------------- (8) stability of permanent rotations
@problem("stability", "permanent rotations of a free body: stable axes, small oscillations (§10)")
def stability(rng: np.random.Generator) -> Draft:
    while True:  # distinct moments obeying the triangle inequality A + B > C
        A, B, C = (float(x) for x in sorted(rng.choice(np.arange(1, 10), size=3, replace=False)))
        if A + B > C:
            break
    w0 = float(rng.integers(1, 6))
    k = int(rng.choice([0, 2]))
    J = [A, B, C]
    i, j = [x for x in range(3) if x != k]

    def period(kk: int, denominator: str = "ij") -> float:
        ii, jj = [x for x in range(3) if x != kk]
        den = J[ii] * J[jj] if denominator == "ij" else J[kk] ** 2
        return 2 * math.pi / (w0 * math.sqrt((J[kk] - J[ii]) * (J[kk] - J[jj]) / den))

    answer = period(k)
    omega0 = [1e-7 * w0, 1e-7 * w0, 1e-7 * w0]
    omega0[k] = w0
    body = FreeRigidBody(J, omega0=omega0)
    api = float(body.period)
    wn = w0 * math.sqrt((J[k] - J[i]) * (J[k] - J[j]) / (J[i] * J[j]))
    name = "xyz"[k]
    statement = (
        f"A free rigid body has principal moments A = {num(A)}, B = {num(B)}, C = {num(C)} "
        f"kg m^2 (about its centre of mass). It spins at w0 = {num(w0)} rad/s about its {name} "
        "axis. Which permanent rotations are stable? Find the period of the small "
        "oscillations of w about the spin axis after a small disturbance."
    )
    stable = body.stable_axes
    steps = [
        Step(
            "Intermediate-axis theorem: rotation about the axes of the largest and the smallest "
            f"moment is stable, about the middle one unstable. Here x, y, z stable: "
            f"{tuple(bool(s) for s in stable)}; the spin axis {name} is stable.",
            "§10",
            np.array(stable, dtype=float),
        ),
        Step(
            "Linearised Euler equations about w = w0 e_k: the transverse components obey "
            "u'' + w_n^2 u = 0 with w_n = w0 sqrt((J_k - J_i)(J_k - J_j) / (J_i J_j)) = "
            f"{num(wn)} rad/s.",
            "§10",
            np.array([wn]),
        ),
        Step(f"Period T = 2 pi / w_n = {num(answer)} s.", "§10", np.array([answer])),
    ]
    return Draft(
        statement,
        steps,
        [answer],
        [api],
        ("T",),
        "s",
        {
            "wrong axis (the other stable axis)": [period(2 - k)],
            "moments swapped (J_k^2 in the denominator)": [period(k, "kk")],
            "angular frequency given instead of the period": [wn],
        },
    )


# --------------------------------------------------------------- (9) gyroscope
@problem("gyroscope", "gyroscopic moment of a fast top in regular precession (§10)")
def gyroscope(rng: np.random.Generator) -> Draft:
    A = float(rng.integers(1, 5))
    C = float(rng.integers(1, 2 * int(A) + 1))  # C <= 2 A (a rigid body)
    spin, prec = float(rng.integers(5, 21)) * 10.0, float(rng.integers(1, 6))
    theta = angle15(rng, 15, 75)
    M = C * spin * prec * math.sin(theta * D2R)
    api = float(gyroscopic_moment(A, C, theta * D2R, prec, spin).approximation)
    statement = (
        f"A fast top (equatorial moment A = {num(A)}, axial C = {num(C)} kg m^2) spins at "
        f"{num(spin)} rad/s about its axis, which precesses regularly at {num(prec)} rad/s "
        f"about the vertical at the angle theta = {theta} deg. Find the gyroscopic moment "
        "M = C w_spin w_prec sin theta that keeps the precession going (the elementary "
        "theory of the gyroscope)."
    )
    steps = [
        Step(
            "For a fast top K ~ C w_spin along the axis; the axis turns at w_prec about the "
            "vertical, so K' = w_prec x K has magnitude C w_spin w_prec sin theta.",
            "§10",
        ),
        Step(
            f"M = {num(C)} * {num(spin)} * {num(prec)} * sin {theta} deg = {num(M)} N m.",
            "§10",
            np.array([M]),
        ),
    ]
    return Draft(
        statement,
        steps,
        [M],
        [api],
        ("M",),
        "N m",
        {
            "cos theta instead of sin theta": [C * spin * prec * math.cos(theta * D2R)],
            "degrees taken as radians": [C * spin * prec * math.sin(theta)],
            "equatorial moment A instead of C": [A * spin * prec * math.sin(theta * D2R)],
        },
    )


# ------------------------------------------------------------------ (10) Kepler
@problem("kepler", "Kepler orbit: period and apsides from energy and angular momentum (§9)")
def kepler_orbit(rng: np.random.Generator) -> Draft:
    mu = float(rng.choice([2, 4, 6, 8]))
    a = float(rng.choice([2, 4, 5]))  # E = -mu / (2 a) a terminating decimal
    e = float(rng.choice([0.2, 0.25, 0.4, 0.5, 0.6, 0.75, 0.8]))
    E = -mu / (2 * a)
    K2 = mu * a * (1 - e * e)
    a_own = -mu / (2 * E)
    T = 2 * math.pi * math.sqrt(a_own**3 / mu)
    p = K2 / mu
    ecc = math.sqrt(1 + 2 * E * K2 / mu**2)
    rp, ra = p / (1 + ecc), p / (1 - ecc)
    orbit = CentralOrbit(kepler(mu), energy=E, angular_momentum=math.sqrt(K2))
    aps = orbit.apsides
    api = [orbit.conic.period, aps.pericentre, aps.apocentre]
    statement = (
        f"A particle of unit mass moves in the field of potential energy -mu / r with mu = "
        f"{num(mu)}. Its energy is E = {num(E)} and the square of its angular momentum "
        f"K^2 = {num(K2)} (consistent units). Find the period and the pericentre and "
        "apocentre distances."
    )
    steps = [
        Step(f"Semi-major axis a = -mu / (2 E) = {num(a_own)}.", "§9", np.array([a_own])),
        Step(f"Period T = 2 pi sqrt(a^3 / mu) = {num(T)}.", "§9", np.array([T])),
        Step(
            f"Parameter p = K^2 / mu = {num(p)}, eccentricity e = sqrt(1 + 2 E K^2 / mu^2) = "
            f"{num(ecc)}.",
            "§9",
            np.array([p, ecc]),
        ),
        Step(
            f"r_p = p / (1 + e) = {num(rp)}, r_a = p / (1 - e) = {num(ra)}.",
            "§9",
            np.array([rp, ra]),
        ),
    ]
    e_bad = math.sqrt(max(0.0, 1 + E * K2 / mu**2))
    a_bad = -mu / E
    return Draft(
        statement,
        steps,
        [T, rp, ra],
        api,
        ("T", "r_p", "r_a"),
        "time, length",
        {
            "factor 2 missing in a = -mu / (2 E)": [
                2 * math.pi * math.sqrt(a_bad**3 / mu),
                a_bad * (1 - ecc),
                a_bad * (1 + ecc),
            ],
            "apsides swapped": [T, ra, rp],
            "factor 2 missing in the eccentricity": [T, p / (1 + e_bad), p / (1 - e_bad)],
            "period with a^2 instead of a^3": [2 * math.pi * math.sqrt(a_own**2 / mu), rp, ra],
        },
    )


# ------------------------------------------------------------------ (11) Foucault
@problem("foucault", "Foucault pendulum: turning rate and period of the swing plane (§9)")
def foucault(rng: np.random.Generator) -> Draft:
    lat = int(rng.choice([10, 15, 20, 30, 40, 45, 50, 60, 70, 75, 80])) * int(rng.choice([-1, 1]))
    omega = 7.2921159e-5  # the sidereal rotation rate of the Earth, rad/s
    rate = omega * abs(math.sin(lat * D2R))
    hours = 2 * math.pi / rate / 3600.0
    api = float(foucault_period(lat, degrees=True)) / 3600.0
    solar = 2 * math.pi / 86400.0
    hemisphere = "north" if lat > 0 else "south"
    statement = (
        f"A Foucault pendulum swings at latitude {abs(lat)} deg {hemisphere}. With the Earth's "
        f"sidereal rotation rate Omega = {omega} rad/s, find the time (hours) its swing "
        "plane takes to turn through a full circle relative to the ground."
    )
    steps = [
        Step(
            "Only the local vertical component Omega sin(latitude) of the Earth's rotation "
            "turns the swing plane (the Coriolis force, horizontal part).",
            "§9",
        ),
        Step(f"Turning rate Omega |sin phi| = {num(rate)} rad/s.", "§9", np.array([rate])),
        Step(f"Period 2 pi / (Omega |sin phi|) = {num(hours)} h.", "§9", np.array([hours])),
    ]
    mistakes = {
        "cos of the latitude instead of sin": [
            2 * math.pi / (omega * abs(math.cos(lat * D2R))) / 3600.0
        ],
        "solar day (24 h) instead of the sidereal rate": [
            2 * math.pi / (solar * abs(math.sin(lat * D2R))) / 3600.0
        ],
        "degrees taken as radians": [2 * math.pi / (omega * abs(math.sin(lat))) / 3600.0],
    }
    # a tight tolerance: the solar and the sidereal day differ by 0.27 %
    return Draft(statement, steps, [hours], [api], ("T",), "h", mistakes, tolerance=1e-4 * hours)


# ------------------------------------------------------------ (12) instant centre
def kxv(w: float, r: list[float]) -> list[float]:
    """``w k x r`` for plane vectors: ``w (-r_y, r_x)``."""
    return [-w * r[1], w * r[0]]


@problem("instant-centre", "wheel rolling without slipping: instant centre, point velocity (§6)")
def instant_centre(rng: np.random.Generator) -> Draft:
    R = float(rng.integers(1, 4))
    xc = float(rng.integers(-3, 4))
    vc = float(rng.choice([-4, -3, -2, -1, 1, 2, 3, 4]))
    alpha = int(rng.choice([a for a in range(-165, 181, 15) if a != -90]))
    C = [xc, R]
    M = [xc + R * math.cos(alpha * D2R), R + R * math.sin(alpha * D2R)]
    w = -vc / R  # rolling to the right (v_C > 0) turns clockwise (omega < 0)
    P = [xc, 0.0]  # the contact point: the wheel's point at rest
    PM = [M[0] - P[0], M[1] - P[1]]
    vM = kxv(w, PM)
    answer = [w, P[0], P[1], vM[0], vM[1]]
    Papi = velocity_center(C, [vc, 0.0], w)
    vapi = velocity_field([vc, 0.0, 0.0], [0.0, 0.0, w], [M[0] - C[0], M[1] - C[1], 0.0])
    api = [w, float(Papi[0]), float(Papi[1]), float(vapi[0]), float(vapi[1])]
    statement = (
        f"A wheel of radius R = {num(R)} m rolls without slipping along the x axis (the "
        f"ground y = 0) in the plane x y; its centre C = {vec(C)} m moves with velocity "
        f"v_C = ({num(vc)}, 0) m/s. Find the wheel's angular velocity omega (about z, "
        "counterclockwise positive), its instantaneous centre of velocities P and the "
        f"velocity of the rim point M at the polar angle {alpha} deg from the centre, "
        f"M = {vec(M)} m."
    )
    steps = [
        Step(
            "Rolling without slipping: the contact point has zero velocity, so v_C = omega "
            f"k x (C - P) with C - P = (0, R); omega = -v_C / R = {num(w)} rad/s.",
            "§6",
            np.array([w]),
        ),
        Step(
            f"Instant centre P = C + k x v_C / omega = {vec(P)} m: the contact point.",
            "§6",
            np.array(P),
        ),
        Step(
            f"PM = M - P = {vec(PM)} m; v_M = omega k x PM = omega (-PM_y, PM_x) = "
            f"{vec(vM)} m/s (perpendicular to PM, |v_M| = |omega| |PM|).",
            "§6",
            np.array(vM),
        ),
    ]
    about_c = kxv(w, [M[0] - C[0], M[1] - C[1]])
    P_bad = [xc, 2 * R]  # C - k x v_C / omega: the top of the wheel
    v_bad = kxv(w, [M[0] - P_bad[0], M[1] - P_bad[1]])
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("omega", "P_x", "P_y", "v_x", "v_y"),
        "rad/s, m, m/s",
        {
            "rolling taken as pure rotation about the centre": [w, xc, R] + about_c,
            "cross product order reversed (PM x w)": [w, P[0], P[1], -vM[0], -vM[1]],
            "wrong sign in P = C + k x v_C / omega (the top point)": [w] + P_bad + v_bad,
            "wrong sense of rotation (omega = +v_C / R)": [-w, P[0], P[1], -vM[0], -vM[1]],
        },
    )


# --------------------------------------------------------- (13) finite screw
@problem("screw", "finite displacement as a screw: axis point, angle, slide (Chasles, §6)")
def screw(rng: np.random.Generator) -> Draft:
    ax = str(rng.choice(list(AXES)))
    sign = float(rng.choice([-1, 1]))
    e = scale(sign, list(UNIT[ax]))
    f = angle15(rng, 30, 165)
    a = ints(rng, 3, -2, 2)
    t = ints(rng, 3)
    while not any(cross(e, t)) and not any(cross(e, a)):
        t = ints(rng, 3)
    a[AXES.index(ax)] = 0.0  # the axis point in the plane through O normal to e
    fr = f * D2R
    Rm = rot(ax, sign * fr)
    Ra = matvec(Rm, a)
    tt = add(a, scale(-1, Ra), t)  # x -> R (x - a) + a + t = R x + (E - R) a + t
    d = sum(e[i] * tt[i] for i in range(3))
    tn = add(tt, scale(-d, e))
    cot = math.cos(fr / 2) / math.sin(fr / 2)
    p = scale(0.5, add(tn, scale(cot, cross(e, tn))))
    answer = p + [fr, d]
    rot_api = Rotation.from_axis_angle(e, fr)
    T = (
        RigidTransform.from_translation(np.add(a, t))
        * RigidTransform.from_rotation(rot_api)
        * RigidTransform.from_translation(np.negative(a))
    )
    sc = T.screw()
    api = np.concatenate([sc.point, [float(sc.angle), float(sc.slide)]])
    e_txt = ("-" if sign < 0 else "") + ax
    statement = (
        f"A body is turned by {f} deg (right-handed) about the line through a = {vec(a)} m "
        f"with direction e = {vec(e)} (the {e_txt} direction), then translated by "
        f"t = {vec(t)} m. By Chasles' theorem the displacement is a screw: a rotation about "
        "an axis of direction e and a slide along it. Find the point p of the screw axis "
        "closest to the origin, the rotation angle (rad) and the slide d along e (m)."
    )
    steps = [
        Step(
            f"As x -> R x + t': R = rotation by {f} deg about e = {mat(Rm)}; "
            f"t' = (E - R) a + t = {vec(tt)} m.",
            "§6",
            np.array(tt),
        ),
        Step(
            f"Slide d = e . t' = {num(d)} m (the same for every point; (E - R) a has no e "
            f"component, so d = e . t); angle f = {f} deg = {num(fr)} rad.",
            "§6",
            np.array([d, fr]),
        ),
        Step(
            f"Normal part t_n = t' - d e = {vec(tn)}; cot(f/2) = {num(cot)}; e x t_n = "
            f"{vec(cross(e, tn))}.",
            "§6",
            np.array(tn),
        ),
        Step(
            f"p = (t_n + cot(f/2) e x t_n) / 2 = {vec(p)} m (solves (E - R) p = t_n, p . e = 0).",
            "§6",
            np.array(p),
        ),
    ]

    def point(tv: list[float], c: float) -> list[float]:
        return scale(0.5, add(tv, scale(c, cross(e, tv))))

    tlen = math.sqrt(sum(x * x for x in t))
    cot_f = math.cos(fr) / math.sin(fr)
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("p_x", "p_y", "p_z", "angle", "slide"),
        "m, rad",
        {
            "slide taken as |t|": point(add(tt, scale(-tlen, e)), cot) + [fr, tlen],
            "axis point without the projection (t' for t_n)": point(tt, cot) + [fr, d],
            "angle in degrees": p + [float(f), d],
            "cot(f) instead of cot(f/2)": point(tn, cot_f) + [fr, d],
        },
    )


# ---------------------------------------------------- (14) heavy top: regular precession
@problem(
    "regular-precession",
    "heavy symmetric top: slow and fast regular precession, sleeping-top stability (§10)",
)
def regular_precession(rng: np.random.Generator) -> Draft:
    g = 9.8
    while True:
        A = float(rng.integers(1, 5))
        C = float(rng.integers(1, 2 * int(A) + 1))
        m = float(rng.integers(1, 5))
        ell = float(rng.choice([0.1, 0.2, 0.25, 0.5]))
        r = float(rng.integers(2, 21))
        theta = angle15(rng, 15, 75)
        mgl = m * g * ell
        H = C * r
        ct = math.cos(theta * D2R)
        D = H * H - 4 * A * mgl * ct
        if A != C and D > 0.05 * H * H:
            break

    def rates(a: float, h: float, k: float, c: float, four: float = 4.0) -> list[float]:
        disc_ = h * h - four * a * k * c
        if disc_ < 0:
            return [math.nan, math.nan]
        root = math.sqrt(disc_)
        return [(h - root) / (2 * a * c), (h + root) / (2 * a * c)]

    slow, fast = rates(A, H, mgl, ct)
    ratio = H * H / (4 * A * mgl)
    answer = [slow, fast, ratio]
    s_api, f_api = regular_precession_rates(A, C, mgl, theta, r, degrees=True)
    top = LagrangeTop(A, C, mgl, theta=0.0, spin=r)
    api = [float(s_api), float(f_api), float(top.maievskii_ratio)]
    verdict = "stable" if ratio > 1 else "unstable"
    statement = (
        f"A heavy symmetric top (moments about its fixed point: equatorial A = {num(A)}, "
        f"axial C = {num(C)} kg m^2; mass m = {num(m)} kg, centre of mass l = {num(ell)} m "
        f"above the point on the axis; g = {num(g)} m/s^2) spins at r = {num(r)} rad/s "
        f"about its axis. Find the slow and the fast rates psi' of regular precession with "
        f"the axis at theta = {theta} deg from the upward vertical, and Maievskii's ratio "
        "C^2 r^2 / (4 A m g l): is the sleeping (upright) top with this spin stable?"
    )
    steps = [
        Step(
            f"H = C r = {num(H)} kg m^2/s, m g l = {num(mgl)} N m.",
            "§10",
            np.array([H, mgl]),
        ),
        Step(
            "theta constant: A psi'^2 cos theta - H psi' + m g l = 0, discriminant "
            f"H^2 - 4 A m g l cos theta = {num(D)} > 0.",
            "§10",
            np.array([D]),
        ),
        Step(
            f"psi' = (H -+ sqrt(D)) / (2 A cos theta): slow {num(slow)} rad/s, fast "
            f"{num(fast)} rad/s.",
            "§10",
            np.array([slow, fast]),
        ),
        Step(
            f"Maievskii: C^2 r^2 / (4 A m g l) = {num(ratio)}, so the sleeping top is {verdict}.",
            "§10",
            np.array([ratio]),
        ),
    ]
    sw = rates(C, A * r, mgl, ct)
    no4 = rates(A, H, mgl, ct, four=1.0)
    no_l = rates(A, H, m * g, ct)
    no_cos = rates(A, H, mgl, 1.0)
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("slow", "fast", "ratio"),
        "rad/s, 1",
        {
            "A and C swapped": sw + [(A * r) ** 2 / (4 * C * mgl)],
            "missing factor 4": no4 + [H * H / (A * mgl)],
            "l forgotten (m g instead of m g l)": no_l + [H * H / (4 * A * m * g)],
            "cos theta forgotten in the quadratic": no_cos + [ratio],
        },
    )


# ------------------------------------------------------------- (15) bead on a hoop
@problem("bead-on-hoop", "bead on a spinning hoop: Lagrange equation, stable equilibrium (§11)")
def bead_on_hoop(rng: np.random.Generator) -> Draft:
    g = 9.8
    while True:
        R = float(rng.choice([0.2, 0.25, 0.4, 0.5, 0.8, 1.0]))
        w = float(rng.integers(2, 11))
        x = g / (R * w * w)  # the critical ratio: > 1 slow hoop, < 1 fast hoop
        if abs(x - 1) > 0.15:
            break
    fast = x < 1
    if fast:
        th = math.acos(x)
        Om = w * math.sin(th)  # w^2 - g^2/(R^2 w^2) = w^2 sin^2 theta*
    else:
        th = 0.0
        Om = math.sqrt(g / R - w * w)
    answer = [th / D2R, Om]

    # the API: the centrifugal force of the rotating frame (poinsot's inertial_forces)
    frame = FrameMotion(omega=[0.0, 0.0, w])
    grav = np.array([0.0, 0.0, -g])

    def pos(t: float) -> np.ndarray:
        return R * np.array([math.sin(t), 0.0, -math.cos(t)])

    def dpos(t: float) -> np.ndarray:
        return R * np.array([math.cos(t), 0.0, math.sin(t)])

    def cf(s: np.ndarray) -> np.ndarray:
        return inertial_forces(frame, s, np.zeros(3)).centrifugal

    def Q(t: float) -> float:  # generalized force per unit mass: (g + F_cf) . ds/dtheta
        return float((grav + cf(pos(t))) @ dpos(t))

    def dQ(t: float) -> float:  # F_cf linear in s; d^2 s / dtheta^2 = -s
        return float(cf(dpos(t)) @ dpos(t) - (grav + cf(pos(t))) @ pos(t))

    cands = [0.0, math.pi]
    lo, hi = 1e-9, math.pi / 2
    if Q(lo) > 0:  # a root between the bottom and the equator
        while True:
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            lo, hi = (mid, hi) if Q(mid) > 0 else (lo, mid)
        cands.append(0.5 * (lo + hi))
    stable = [c for c in cands if dQ(c) < 0]
    t_api = stable[0]
    api = [t_api / D2R, math.sqrt(-dQ(t_api) / R**2)]

    statement = (
        f"A bead slides without friction on a circular hoop of radius R = {num(R)} m that "
        f"turns at the constant rate w = {num(w)} rad/s about its vertical diameter "
        f"(g = {num(g)} m/s^2). With theta the angle of the bead from the lowest point, "
        "write Lagrange's equation, find the equilibria and their stability, and give the "
        "stable equilibrium theta* (deg, in [0, 90]) and the angular frequency of small "
        "oscillations about it."
    )
    ratio_txt = f"g / (R w^2) = {num(x)}"
    eq_txt = (
        f"{ratio_txt} < 1: theta = 0 and 180 deg and cos theta* = g / (R w^2), theta* = "
        f"{num(th / D2R)} deg; the bottom is unstable, theta* is stable."
        if fast
        else f"{ratio_txt} >= 1: only theta = 0 (stable) and theta = 180 deg (unstable)."
    )
    freq_txt = (
        f"Linearise about theta*: Omega^2 = w^2 sin^2 theta* = w^2 - g^2/(R^2 w^2), "
        f"Omega = {num(Om)} rad/s."
        if fast
        else f"Linearise about 0: Omega^2 = g/R - w^2, Omega = {num(Om)} rad/s."
    )
    steps = [
        Step(
            "T = m R^2 (theta'^2 + w^2 sin^2 theta) / 2, P = -m g R cos theta; "
            "Lagrange: theta'' = (w^2 cos theta - g / R) sin theta.",
            "§11",
        ),
        Step(eq_txt, "§11", np.array([th / D2R])),
        Step(freq_txt, "§11", np.array([Om])),
    ]
    mistakes: dict[str, Any] = {
        # theta'' = -(w^2 cos theta + g/R) sin theta: the bottom is always stable
        "sign of the centrifugal term": [0.0, math.sqrt(g / R + w * w)],
        # theta'' = (w^2 - g/R) sin theta
        "cos theta missing in the centrifugal term": [180.0, math.sqrt(w * w - g / R)]
        if fast
        else [0.0, math.sqrt(g / R - w * w)],
        "the unstable equilibrium": [0.0, math.sqrt(w * w - g / R)]
        if fast
        else [180.0, math.sqrt(g / R + w * w)],
    }
    if fast:
        mistakes["Omega = w (sin theta* forgotten)"] = [th / D2R, w]
    return Draft(
        statement, steps, answer, api, ("theta", "Omega"), "deg, rad/s", mistakes, tolerance=0.01
    )


# ------------------------------------------------------------- (16) virtual work
@problem("virtual-work", "ladder against a wall: generalized force by virtual work (§11)")
def virtual_work(rng: np.random.Generator) -> Draft:
    g = 9.8
    L = float(rng.integers(2, 7))
    m = float(rng.integers(1, 6))
    F = float(rng.integers(1, 9)) * 5.0
    theta = angle15(rng, 15, 75)
    th = theta * D2R
    s, c = math.sin(th), math.cos(th)
    W = m * g

    def q_and_f(sign_a: float = 1.0, arm: float = 0.5, swap: bool = False) -> list[float]:
        """Q_theta = sign_a F L sin - arm m g L cos (sin and cos swapped if asked) and
        the F that makes it vanish."""
        sa, ca = (c, s) if swap else (s, c)
        return [sign_a * F * L * sa - arm * W * L * ca, sign_a * arm * W * ca / sa]

    Q, Feq = q_and_f()
    answer = [Q, Feq]
    # the API: the forces reduced at A; the power of a force system is R . v_A + M_A . w
    A = [L * c, 0.0, 0.0]
    G = [L * c / 2, L * s / 2, 0.0]
    vA = [-L * s, 0.0, 0.0]  # dA/dtheta
    w = [0.0, 0.0, -1.0]  # the rod's angle to the floor grows: it turns clockwise
    red = reduce_forces([([-F, 0.0, 0.0], A), ([0.0, -W, 0.0], G)], pole=A)
    Q_api = float(np.dot(red.resultant, vA) + np.dot(red.moment, w))
    red1 = reduce_forces([([-1.0, 0.0, 0.0], A)], pole=A)
    q1 = float(np.dot(red1.resultant, vA) + np.dot(red1.moment, w))  # per newton of F
    api = [Q_api, F - Q_api / q1]
    statement = (
        f"A uniform ladder AB (length L = {num(L)} m, mass m = {num(m)} kg, g = {num(g)} "
        "m/s^2) stands with its foot A on the smooth floor y = 0 and its top B against the "
        "smooth wall x = 0; theta is its angle with the floor, so A = (L cos theta, 0) and "
        f"B = (0, L sin theta). A horizontal force of {num(F)} N pushes the foot A towards "
        f"the wall. At theta = {theta} deg find the generalized force Q_theta (the virtual "
        "work is Q_theta dtheta; the smooth constraints do no work) and the pushing "
        "force F that would hold the ladder in equilibrium at this angle."
    )
    steps = [
        Step(
            "Virtual displacements at frozen constraints: dx_A = -L sin theta dtheta, "
            "dy_G = (L / 2) cos theta dtheta (G the middle of the ladder); the wall and "
            "floor reactions are normal to them (ideal constraints).",
            "§11",
            np.array([-L * s, L * c / 2]),
        ),
        Step(
            "Q_theta = (-F)(-L sin theta) + (-m g)(L / 2) cos theta = "
            f"{num(F * L * s)} - {num(W * L * c / 2)} = {num(Q)} N m.",
            "§11",
            np.array([Q]),
        ),
        Step(
            f"Equilibrium: Q_theta = 0, F = m g cot(theta) / 2 = {num(Feq)} N.",
            "§11",
            np.array([Feq]),
        ),
    ]
    wrong_w = [F * L * s + W * L * c / 2, -W * c / (2 * s)]
    return Draft(
        statement,
        steps,
        answer,
        api,
        ("Q", "F"),
        "N m, N",
        {
            "sign of the virtual displacement of A": q_and_f(sign_a=-1.0),
            "weight at the top (L instead of L / 2)": q_and_f(arm=1.0),
            "sin and cos swapped": q_and_f(swap=True),
            "work of the weight with the wrong sign": wrong_w,
        },
    )
