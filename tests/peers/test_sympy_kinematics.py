"""Peer cross-checks of poinsot's kinematics against SymPy (``sympy.physics.vector``).

SymPy is an independent oracle: every expected value below is a SymPy expression
(orientation, ``ang_vel_in``, ``v2pt_theory``, ``a1pt_theory``, symbolic
differentiation of positions and curves) evaluated numerically at random seeded
points. Conventions matched (checked, not assumed):

* ``B.orient_body_fixed(N, angles, "zxz")`` is poinsot's intrinsic ``"ZXZ"``;
  ``B.orient_space_fixed(N, angles, "xyz")`` is poinsot's extrinsic ``"xyz"``,
  angles in the same order.
* ``N.dcm(B)`` maps B components to N components (``v_N = N.dcm(B) v_B``), i.e.
  poinsot's ``Rotation.as_matrix()`` of B relative to N.
* ``B.orient_quaternion(N, (q0, q1, q2, q3))`` is scalar first and gives
  ``N.dcm(B)`` equal to the active rotation matrix of the quaternion, i.e.
  poinsot's ``Rotation.from_quat(q)``.
* ``B.ang_vel_in(N).to_matrix(B)`` is ``frame="body"``, ``.to_matrix(N)``
  ``frame="space"``.
"""

from __future__ import annotations

import numpy as np
import pytest

sp = pytest.importorskip("sympy")
me = pytest.importorskip("sympy.physics.mechanics")

from poinsot import Rotation  # noqa: E402
from poinsot.kinematics import (  # noqa: E402
    FrameMotion,
    acceleration_field,
    chain,
    euler_rates,
    frenet,
    omega_from_euler_rates,
    omega_from_quat_rate,
    point_motion,
    quat_rate,
    velocity_field,
)

TOL = 1e-12
N_POINTS = 12

_PROPER = ["xyx", "xzx", "yxy", "yzy", "zxz", "zyz"]
_TAIT = ["xyz", "xzy", "yxz", "yzx", "zxy", "zyx"]
SEQUENCES = _PROPER + _TAIT


def _vec(m) -> np.ndarray:
    return np.asarray(m, dtype=float).reshape(-1)


def _mat(m) -> np.ndarray:
    return np.asarray(m, dtype=float).reshape(3, 3)


def _random_angles(rng, seq: str, n: int) -> np.ndarray:
    """Angles away from gimbal lock (middle angle in (0.2, pi - 0.2) or |.| < pi/2 - 0.2)."""
    a = rng.uniform(-np.pi, np.pi, size=(n, 3))
    if seq[0] == seq[2]:
        a[:, 1] = rng.uniform(0.2, np.pi - 0.2, size=n)
    else:
        a[:, 1] = rng.uniform(-np.pi / 2 + 0.2, np.pi / 2 - 0.2, size=n)
    return a


# ---------------------------------------------------------------------------
# 1. Euler angles: DCM and angular velocity in both frames, and the inverse
# ---------------------------------------------------------------------------


def _sympy_euler(seq: str, kind: str):
    q = me.dynamicsymbols("q1:4")
    qd = [x.diff() for x in q]
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    if kind == "body":
        B.orient_body_fixed(N, q, seq)
    else:
        B.orient_space_fixed(N, q, seq)
    w = B.ang_vel_in(N)
    return sp.lambdify([q, qd], [w.to_matrix(B), w.to_matrix(N), N.dcm(B)], "numpy")


@pytest.mark.parametrize(
    ("seq", "kind"),
    [(s, "body") for s in SEQUENCES] + [(s, "space") for s in SEQUENCES],
)
def test_euler_dcm_and_omega_vs_sympy(seq, kind):
    seq_p = seq.upper() if kind == "body" else seq  # intrinsic upper, extrinsic lower
    f = _sympy_euler(seq, kind)
    rng = np.random.default_rng(SEQUENCES.index(seq) + (100 if kind == "space" else 0))
    angles = _random_angles(rng, seq, N_POINTS)
    rates = rng.normal(size=(N_POINTS, 3))
    wb = np.empty((N_POINTS, 3))
    ws = np.empty((N_POINTS, 3))
    dcm = np.empty((N_POINTS, 3, 3))
    for k in range(N_POINTS):
        b, s, c = f(angles[k], rates[k])
        wb[k], ws[k], dcm[k] = _vec(b), _vec(s), _mat(c)

    np.testing.assert_allclose(
        Rotation.from_euler(seq_p, angles).as_matrix(), dcm, rtol=0, atol=TOL
    )
    np.testing.assert_allclose(
        omega_from_euler_rates(seq_p, angles, rates, frame="body"), wb, rtol=0, atol=TOL
    )
    np.testing.assert_allclose(
        omega_from_euler_rates(seq_p, angles, rates, frame="space"), ws, rtol=0, atol=TOL
    )
    # the inverse: SymPy's omega back to the Euler rates
    np.testing.assert_allclose(euler_rates(seq_p, angles, wb, frame="body"), rates, atol=1e-11)
    np.testing.assert_allclose(euler_rates(seq_p, angles, ws, frame="space"), rates, atol=1e-11)


@pytest.mark.parametrize(("preset", "seq"), [("euler", "zxz"), ("krylov", "zxy")])
def test_euler_presets_vs_sympy(preset, seq):
    f = _sympy_euler(seq, "body")
    rng = np.random.default_rng(7)
    angles = _random_angles(rng, seq, 5)
    rates = rng.normal(size=(5, 3))
    for k in range(5):
        b, s, c = f(angles[k], rates[k])
        np.testing.assert_allclose(
            Rotation.from_euler(preset, angles[k]).as_matrix(), _mat(c), atol=TOL
        )
        np.testing.assert_allclose(
            omega_from_euler_rates(preset, angles[k], rates[k]), _vec(b), atol=TOL
        )
        np.testing.assert_allclose(
            euler_rates(preset, angles[k], _vec(s), frame="space"), rates[k], atol=1e-11
        )


def test_euler_degrees_vs_sympy():
    """``degrees=True`` means angles in deg and rates in deg/s; omega stays rad/s."""
    f = _sympy_euler("zyx", "body")
    rng = np.random.default_rng(11)
    angles = _random_angles(rng, "zyx", 4)
    rates = rng.normal(size=(4, 3))
    for k in range(4):
        b, _, _ = f(angles[k], rates[k])
        got = omega_from_euler_rates(
            "ZYX", np.degrees(angles[k]), np.degrees(rates[k]), degrees=True
        )
        np.testing.assert_allclose(got, _vec(b), atol=TOL)
        back = euler_rates("ZYX", np.degrees(angles[k]), _vec(b), degrees=True)
        np.testing.assert_allclose(back, np.degrees(rates[k]), atol=1e-10)


# ---------------------------------------------------------------------------
# 2. Quaternion orientation and quaternion rates
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sympy_quaternion():
    e = me.dynamicsymbols("e0:4")
    ed = [x.diff() for x in e]
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_quaternion(N, e)
    w = B.ang_vel_in(N)
    return sp.lambdify([e, ed], [N.dcm(B), w.to_matrix(B), w.to_matrix(N)], "numpy")


def _random_unit_quats(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def test_quaternion_dcm_vs_sympy(sympy_quaternion):
    rng = np.random.default_rng(3)
    q = _random_unit_quats(rng, N_POINTS)
    for k in range(N_POINTS):
        c, _, _ = sympy_quaternion(q[k], np.zeros(4))
        np.testing.assert_allclose(Rotation.from_quat(q[k]).as_matrix(), _mat(c), atol=TOL)
        # scalar-last reading of the same numbers
        np.testing.assert_allclose(
            Rotation.from_quat(np.roll(q[k], -1), scalar_first=False).as_matrix(),
            _mat(c),
            atol=TOL,
        )


def test_quaternion_rates_vs_sympy(sympy_quaternion):
    """SymPy's omega from a tangent ``qdot`` (``q . qdot = 0``) in both frames."""
    rng = np.random.default_rng(4)
    q = _random_unit_quats(rng, N_POINTS)
    qd = rng.normal(size=(N_POINTS, 4))
    qd -= np.sum(qd * q, axis=-1, keepdims=True) * q  # tangent to the unit sphere
    for k in range(N_POINTS):
        _, b, s = sympy_quaternion(q[k], qd[k])
        np.testing.assert_allclose(
            omega_from_quat_rate(q[k], qd[k], frame="body"), _vec(b), atol=TOL
        )
        np.testing.assert_allclose(
            omega_from_quat_rate(q[k], qd[k], frame="space"), _vec(s), atol=TOL
        )
        # and back: poinsot's qdot from SymPy's omega is the tangent qdot
        np.testing.assert_allclose(quat_rate(q[k], _vec(b), frame="body"), qd[k], atol=TOL)
        np.testing.assert_allclose(quat_rate(q[k], _vec(s), frame="space"), qd[k], atol=TOL)


# ---------------------------------------------------------------------------
# 3. Point kinematics: Euler/Rivals fields, Coriolis theorem, chains of frames
# ---------------------------------------------------------------------------


def _subs_args(*groups):
    """Flatten lists of dynamicsymbols with their first and second derivatives."""
    out = []
    for g in groups:
        out += list(g) + [x.diff() for x in g] + [x.diff(me.dynamicsymbols._t, 2) for x in g]
    return out


def _eval(f, rng, n_args, n=N_POINTS):
    """Evaluate ``f`` at ``n`` random points; one (n, 3) array per output vector."""
    vals = rng.uniform(-1.5, 1.5, size=(n, n_args))
    res = [[np.asarray(r, dtype=float).reshape(-1) for r in f(*v)] for v in vals]
    return [np.array(z) for z in zip(*res, strict=True)]


def test_rigid_body_fields_vs_sympy_2pt_theory():
    """``P.v2pt_theory(O, N, B)`` / ``a2pt_theory`` against Euler / Rivals."""
    q = me.dynamicsymbols("q1:4")
    x = me.dynamicsymbols("x1:4")
    c = sp.symbols("c1:4")
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "zyx")
    N0 = me.Point("N0")
    N0.set_vel(N, 0)
    O = N0.locatenew("O", x[0] * N.x + x[1] * N.y + x[2] * N.z)
    O.set_vel(N, O.pos_from(N0).dt(N))
    O.set_acc(N, O.pos_from(N0).dt(N).dt(N))
    P = O.locatenew("P", c[0] * B.x + c[1] * B.y + c[2] * B.z)
    v = P.v2pt_theory(O, N, B)
    a = P.a2pt_theory(O, N, B)
    exprs = [
        P.pos_from(N0).to_matrix(N),
        O.pos_from(N0).to_matrix(N),
        O.vel(N).to_matrix(N),
        O.acc(N).to_matrix(N),
        B.ang_vel_in(N).to_matrix(N),
        B.ang_acc_in(N).to_matrix(N),
        v.to_matrix(N),
        a.to_matrix(N),
        # brute force: differentiate the position of P twice in N
        P.pos_from(N0).dt(N).to_matrix(N),
        P.pos_from(N0).dt(N).dt(N).to_matrix(N),
    ]
    args = _subs_args(q, x) + list(c)
    f = sp.lambdify(args, exprs, "numpy")
    rng = np.random.default_rng(5)
    r, o, v0, a0, w, eps, v_s, a_s, v_bf, a_bf = _eval(f, rng, len(args))
    np.testing.assert_allclose(v_s, v_bf, atol=TOL)  # SymPy agrees with itself
    np.testing.assert_allclose(a_s, a_bf, atol=TOL)
    np.testing.assert_allclose(velocity_field(v0, w, r, pole=o), v_s, atol=TOL)
    np.testing.assert_allclose(acceleration_field(a0, w, eps, r, pole=o), a_s, atol=TOL)
    # rho given directly (pole at the origin)
    np.testing.assert_allclose(velocity_field(v0, w, r - o), v_s, atol=TOL)
    np.testing.assert_allclose(acceleration_field(a0, w, eps, r - o), a_s, atol=TOL)
    # FrameMotion's own field methods
    fm = FrameMotion(origin_velocity=v0, origin_acceleration=a0, omega=w, eps=eps)
    np.testing.assert_allclose(fm.velocity_at(r - o), v_s, atol=TOL)
    np.testing.assert_allclose(fm.acceleration_at(r - o), a_s, atol=TOL)


def test_point_motion_vs_sympy_1pt_theory():
    """A point moving in a moving frame: every term of the Coriolis theorem.

    Expected terms from SymPy: total = ``a1pt_theory`` (and brute-force
    differentiation); transport = ``a2pt_theory`` of the point of B that
    coincides with P; relative = ``P.acc(B)``; Coriolis = total - transport -
    relative.
    """
    q = me.dynamicsymbols("q1:4")
    x = me.dynamicsymbols("x1:4")
    s = me.dynamicsymbols("s1:4")
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "zxz")
    N0 = me.Point("N0")
    N0.set_vel(N, 0)
    O = N0.locatenew("O", x[0] * N.x + x[1] * N.y + x[2] * N.z)
    O.set_vel(N, O.pos_from(N0).dt(N))
    O.set_acc(N, O.pos_from(N0).dt(N).dt(N))
    O.set_vel(B, 0)
    O.set_acc(B, 0)
    s_vec = s[0] * B.x + s[1] * B.y + s[2] * B.z
    P = O.locatenew("P", s_vec)
    P.set_vel(B, s_vec.dt(B))
    P.set_acc(B, s_vec.dt(B).dt(B))
    v = P.v1pt_theory(O, N, B)
    a = P.a1pt_theory(O, N, B)
    Q = O.locatenew("Q", s_vec)  # the point of B that coincides with P now
    v_tr = Q.v2pt_theory(O, N, B)
    a_tr = Q.a2pt_theory(O, N, B)
    exprs = [
        s_vec.to_matrix(N),
        P.vel(B).to_matrix(N),
        P.acc(B).to_matrix(N),
        O.vel(N).to_matrix(N),
        O.acc(N).to_matrix(N),
        B.ang_vel_in(N).to_matrix(N),
        B.ang_acc_in(N).to_matrix(N),
        v.to_matrix(N),
        a.to_matrix(N),
        v_tr.to_matrix(N),
        a_tr.to_matrix(N),
        P.pos_from(N0).dt(N).to_matrix(N),
        P.pos_from(N0).dt(N).dt(N).to_matrix(N),
    ]
    args = _subs_args(q, x, s)
    f = sp.lambdify(args, exprs, "numpy")
    rng = np.random.default_rng(6)
    s_n, v_r, a_r, v0, a0, w, eps, v_s, a_s, v_e, a_e, v_bf, a_bf = _eval(f, rng, len(args))
    np.testing.assert_allclose(a_s, a_bf, atol=TOL)
    m = point_motion(
        FrameMotion(origin_velocity=v0, origin_acceleration=a0, omega=w, eps=eps), s_n, v_r, a_r
    )
    np.testing.assert_allclose(m.velocity, v_s, atol=TOL)
    np.testing.assert_allclose(m.velocity, v_bf, atol=TOL)
    np.testing.assert_allclose(m.transport_velocity, v_e, atol=TOL)
    np.testing.assert_allclose(m.relative_velocity, v_r, atol=TOL)
    np.testing.assert_allclose(m.acceleration, a_s, atol=TOL)
    np.testing.assert_allclose(m.transport_acceleration, a_e, atol=TOL)
    np.testing.assert_allclose(m.relative_acceleration, a_r, atol=TOL)
    np.testing.assert_allclose(m.coriolis_acceleration, a_s - a_e - a_r, atol=TOL)
    np.testing.assert_allclose(m.origin_acceleration, a0, atol=TOL)
    np.testing.assert_allclose(
        m.origin_acceleration + m.rotational_acceleration + m.centripetal_acceleration,
        a_e,
        atol=TOL,
    )


def test_chain_of_three_frames_vs_sympy():
    """N -> A -> B -> point: ``chain`` of relative motions vs SymPy's absolute motion."""
    a = me.dynamicsymbols("a")
    b = me.dynamicsymbols("b1:4")
    x = me.dynamicsymbols("x1:4")
    d = me.dynamicsymbols("d1:4")
    s = me.dynamicsymbols("s1:4")
    N = me.ReferenceFrame("N")
    A = me.ReferenceFrame("A")
    B = me.ReferenceFrame("B")
    A.orient_axis(N, N.z, a)
    B.orient_body_fixed(A, b, "xyz")
    N0 = me.Point("N0")
    N0.set_vel(N, 0)
    OA = N0.locatenew("OA", x[0] * N.x + x[1] * N.y + x[2] * N.z)
    d_vec = d[0] * A.x + d[1] * A.y + d[2] * A.z
    OB = OA.locatenew("OB", d_vec)
    s_vec = s[0] * B.x + s[1] * B.y + s[2] * B.z
    P = OB.locatenew("P", s_vec)
    r_p = P.pos_from(N0)
    r_b = OB.pos_from(N0)
    w_ba = B.ang_vel_in(A)
    exprs = [
        # outer frame A relative to N
        OA.pos_from(N0).dt(N).to_matrix(N),
        OA.pos_from(N0).dt(N).dt(N).to_matrix(N),
        A.ang_vel_in(N).to_matrix(N),
        A.ang_acc_in(N).to_matrix(N),
        # inner frame B relative to A (local derivatives in A), N components
        d_vec.to_matrix(N),
        d_vec.dt(A).to_matrix(N),
        d_vec.dt(A).dt(A).to_matrix(N),
        w_ba.to_matrix(N),
        w_ba.dt(A).to_matrix(N),
        # point relative to B
        s_vec.to_matrix(N),
        s_vec.dt(B).to_matrix(N),
        s_vec.dt(B).dt(B).to_matrix(N),
        # absolute truths
        r_b.dt(N).to_matrix(N),
        r_b.dt(N).dt(N).to_matrix(N),
        B.ang_vel_in(N).to_matrix(N),
        B.ang_acc_in(N).to_matrix(N),
        r_p.dt(N).to_matrix(N),
        r_p.dt(N).dt(N).to_matrix(N),
    ]
    args = _subs_args([a], b, x, d, s)
    f = sp.lambdify(args, exprs, "numpy")
    rng = np.random.default_rng(8)
    (va, aa, wa, ea, off, vd, ad, wr, er, s_n, vs, as_, vb, ab, wb, eb, vp, ap) = _eval(
        f, rng, len(args), n=6
    )
    outer = FrameMotion(origin_velocity=va, origin_acceleration=aa, omega=wa, eps=ea)
    inner = FrameMotion(origin_velocity=vd, origin_acceleration=ad, omega=wr, eps=er)
    total = chain([outer, inner], [off])
    np.testing.assert_allclose(total.origin_velocity, vb, atol=TOL)
    np.testing.assert_allclose(total.origin_acceleration, ab, atol=TOL)
    np.testing.assert_allclose(total.omega, wb, atol=TOL)
    np.testing.assert_allclose(total.eps, eb, atol=TOL)
    m = point_motion(total, s_n, vs, as_)
    np.testing.assert_allclose(m.velocity, vp, atol=TOL)
    np.testing.assert_allclose(m.acceleration, ap, atol=TOL)


# ---------------------------------------------------------------------------
# 7. Frenet: curvature and torsion of a helix and a twisted cubic
# ---------------------------------------------------------------------------

_t = sp.symbols("t", real=True)
CURVES = {
    "helix": sp.Matrix([2 * sp.cos(_t), 2 * sp.sin(_t), sp.Rational(7, 10) * _t]),
    "twisted_cubic": sp.Matrix([_t, _t**2, _t**3]),
    "conical_spiral": sp.Matrix([_t * sp.cos(3 * _t), _t * sp.sin(3 * _t), 2 * _t]),
}


def _sympy_frenet(r):
    """Lambdified SymPy Frenet quantities; returns ``f(t) -> list`` of (n, 3) / (n,) arrays."""
    r1, r2, r3 = r.diff(_t), r.diff(_t, 2), r.diff(_t, 3)
    c = r1.cross(r2)
    speed = sp.sqrt(r1.dot(r1))
    kappa = sp.sqrt(c.dot(c)) / speed**3
    tau = c.dot(r3) / c.dot(c)
    tangent = r1 / speed
    binormal = c / sp.sqrt(c.dot(c))
    normal = binormal.cross(tangent)
    a_t = r1.dot(r2) / speed  # d|v|/dt
    a_n = speed**2 * kappa
    outs = [r, r1, r2, r3, kappa, tau, speed, tangent, normal, binormal, a_t, a_n]
    flat, sizes = [], []
    for o in outs:
        items = list(o) if isinstance(o, sp.MatrixBase) else [o]
        flat += items
        sizes.append(len(items))
    g = sp.lambdify(_t, flat, "numpy")

    def f(t):
        t = np.asarray(t, dtype=float)
        vals = [np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in g(t)]
        res, i = [], 0
        for n in sizes:
            res.append(np.stack(vals[i : i + n], axis=-1) if n == 3 else vals[i])
            i += n
        return res

    return f


@pytest.mark.parametrize("name", sorted(CURVES))
def test_frenet_vs_sympy(name):
    f = _sympy_frenet(CURVES[name])
    t = np.linspace(0.3, 2.5, 9)
    r, r1, r2, r3, kappa, tau, speed, tng, nrm, bnm, a_t, a_n = f(t)

    def curve(tt):
        return f(tt)[0]

    def deriv(k):
        return lambda tt: f(tt)[k]

    # with the exact derivatives poinsot only evaluates the formulas
    ex = frenet(t, curve, derivatives=(deriv(1), deriv(2), deriv(3)))
    for got, want in [
        (ex.curvature, kappa),
        (ex.torsion, tau),
        (ex.speed, speed),
        (ex.tangent, tng),
        (ex.normal, nrm),
        (ex.binormal, bnm),
        (ex.tangential_acceleration, a_t),
        (ex.normal_acceleration, a_n),
    ]:
        np.testing.assert_allclose(got, want, rtol=0, atol=TOL)
    # default: finite differences of the callable (documented O(h^8) / O(h^6))
    fd = frenet(t, curve)
    np.testing.assert_allclose(fd.curvature, kappa, rtol=1e-9, atol=0)  # 1.5e-11 seen
    np.testing.assert_allclose(fd.torsion, tau, rtol=1e-7, atol=0)
    np.testing.assert_allclose(fd.normal, nrm, atol=1e-9)
    # samples on a dense grid (7-point stencil)
    ts = np.linspace(0.0, 3.0, 2001)
    sm = frenet(ts, curve(ts))
    inner = (ts > 0.3) & (ts < 2.7)
    kap_s, tau_s = f(ts)[4:6]
    np.testing.assert_allclose(sm.curvature[inner], kap_s[inner], rtol=1e-8)
    np.testing.assert_allclose(sm.torsion[inner], tau_s[inner], rtol=1e-6)


# ---------------------------------------------------------------------------
# 2b. Other representations: DCM, Gibbs, MRP and rotation-vector rates
# ---------------------------------------------------------------------------


def _quat_of(kind: str, p):
    """Scalar-first unit quaternion as SymPy expressions of the parameters ``p``."""
    pp = sum(v**2 for v in p)
    if kind == "gibbs":  # g = l / l0
        return [1 / sp.sqrt(1 + pp)] + [v / sp.sqrt(1 + pp) for v in p]
    if kind == "mrp":  # p = l / (1 + l0)
        return [(1 - pp) / (1 + pp)] + [2 * v / (1 + pp) for v in p]
    f = sp.sqrt(pp)  # rotation vector phi = f e
    return [sp.cos(f / 2)] + [sp.sin(f / 2) * v / f for v in p]


@pytest.mark.parametrize("kind", ["gibbs", "mrp", "rotvec"])
def test_parameter_rates_vs_sympy(kind):
    from poinsot.kinematics import (
        gibbs_rate,
        mrp_rate,
        omega_from_gibbs_rate,
        omega_from_mrp_rate,
        omega_from_rotvec_rate,
        rotvec_rate,
    )

    rate, inverse = {
        "gibbs": (gibbs_rate, omega_from_gibbs_rate),
        "mrp": (mrp_rate, omega_from_mrp_rate),
        "rotvec": (rotvec_rate, omega_from_rotvec_rate),
    }[kind]
    p = me.dynamicsymbols("p1:4")
    pd = [v.diff() for v in p]
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_quaternion(N, _quat_of(kind, p))
    w = B.ang_vel_in(N)
    f = sp.lambdify([p, pd], [w.to_matrix(B), w.to_matrix(N), N.dcm(B)], "numpy")
    rng = np.random.default_rng(40)
    for _ in range(8):
        x = rng.normal(size=3) * 0.8
        xd = rng.normal(size=3)
        wb, ws, c = (np.asarray(v, dtype=float) for v in f(x, xd))
        wb, ws = wb.reshape(-1), ws.reshape(-1)
        from_param = {
            "gibbs": Rotation.from_gibbs,
            "mrp": Rotation.from_mrp,
            "rotvec": Rotation.from_rotvec,
        }[kind]
        np.testing.assert_allclose(from_param(x).as_matrix(), c, atol=TOL)
        np.testing.assert_allclose(inverse(x, xd, frame="body"), wb, atol=TOL)
        np.testing.assert_allclose(inverse(x, xd, frame="space"), ws, atol=TOL)
        np.testing.assert_allclose(rate(x, wb, frame="body"), xd, atol=TOL)
        np.testing.assert_allclose(rate(x, ws, frame="space"), xd, atol=TOL)


def test_dcm_rates_vs_sympy():
    from poinsot.kinematics import dcm_rate, omega_from_dcm_rate

    q = me.dynamicsymbols("q1:4")
    qd = [v.diff() for v in q]
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "yzx")
    w = B.ang_vel_in(N)
    c = N.dcm(B)
    f = sp.lambdify([q, qd], [c, c.diff(me.dynamicsymbols._t), w.to_matrix(B), w.to_matrix(N)])
    rng = np.random.default_rng(41)
    for _ in range(8):
        a = _random_angles(rng, "yzx", 1)[0]
        cc, cd, wb, ws = (np.asarray(v, dtype=float) for v in f(a, rng.normal(size=3)))
        wb, ws = wb.reshape(-1), ws.reshape(-1)
        np.testing.assert_allclose(omega_from_dcm_rate(cc, cd, frame="body"), wb, atol=TOL)
        np.testing.assert_allclose(omega_from_dcm_rate(cc, cd, frame="space"), ws, atol=TOL)
        np.testing.assert_allclose(dcm_rate(cc, wb, frame="body"), cd, atol=TOL)
        np.testing.assert_allclose(dcm_rate(cc, ws, frame="space"), cd, atol=TOL)


# ---------------------------------------------------------------------------
# 2c. Attitude histories: propagation and angular velocity from samples
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sympy_history():
    """A smooth attitude history (Z-X-Y angles as functions of t), its omega and alpha."""
    t = me.dynamicsymbols._t
    angles = (0.7 * t + 0.3 * sp.sin(2 * t), 0.6 + 0.4 * sp.cos(1.3 * t), -0.5 * t + 0.2 * t**2)
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, angles, "zxy")
    w = B.ang_vel_in(N)
    eps = B.ang_acc_in(N)
    outs = [N.dcm(B), w.to_matrix(B), w.to_matrix(N), eps.to_matrix(B), eps.to_matrix(N)]
    g = sp.lambdify(t, outs, "numpy")

    def f(tt):
        tt = np.atleast_1d(np.asarray(tt, dtype=float))
        res = [[np.asarray(v, dtype=float) for v in g(x)] for x in tt]
        c, wb, ws, eb, es = (np.array(z) for z in zip(*res, strict=True))
        return c, wb[..., 0], ws[..., 0], eb[..., 0], es[..., 0]

    return f


@pytest.mark.parametrize(
    ("method", "kwargs", "tol"),
    [
        ("magnus4", {"max_step": 0.01}, 1e-8),
        ("magnus6", {"max_step": 0.02}, 1e-10),
        ("rk4", {"max_step": 0.01}, 1e-8),
        ("adaptive", {"rtol": 1e-12, "atol": 1e-13}, 1e-9),
    ],
)
@pytest.mark.parametrize("frame", ["body", "space"])
def test_propagate_vs_sympy_attitude(sympy_history, method, kwargs, tol, frame):
    from poinsot.kinematics import propagate

    t = np.linspace(0.0, 3.0, 31)
    c, wb, ws, _, _ = sympy_history(t)
    k = 1 if frame == "body" else 2

    def omega(tt):
        return sympy_history(tt)[k][0]

    tr = propagate(Rotation.from_matrix(c[0]), omega, t, frame=frame, method=method, **kwargs)
    np.testing.assert_allclose(tr.rotation.as_matrix(), c, atol=tol)
    np.testing.assert_allclose(tr.omega, wb, atol=1e-12)  # returned omega is body


@pytest.mark.parametrize("frame", ["body", "space"])
def test_angular_velocity_from_samples_vs_sympy(sympy_history, frame):
    from poinsot.kinematics import angular_velocity, rotation_spline

    rng = np.random.default_rng(42)
    t = np.sort(np.concatenate(([0.0, 3.0], rng.uniform(0.0, 3.0, size=299))))
    c, wb, ws, eb, es = sympy_history(t)
    want = wb if frame == "body" else ws
    rot = Rotation.from_matrix(c)
    quats = rot.as_quat() * rng.choice([-1.0, 1.0], size=(len(t), 1))  # q/-q flips
    got4 = angular_velocity(t, quats, frame=frame)
    got6 = angular_velocity(t, quats, frame=frame, order=6)
    assert np.abs(got4 - want).max() < 1e-5
    assert np.abs(got6 - want).max() < 1e-6
    # the spline, between the knots
    spl = rotation_spline(t, rot)
    tm = 0.5 * (t[1:] + t[:-1])
    cm, wbm, wsm, ebm, esm = sympy_history(tm)
    np.testing.assert_allclose(spl.rotation(tm).as_matrix(), cm, atol=3e-6)  # 1.6e-7 seen
    np.testing.assert_allclose(
        spl.omega(tm, frame=frame), wbm if frame == "body" else wsm, atol=1e-4
    )
    inner = (tm > 0.3) & (tm < 2.7)
    np.testing.assert_allclose(
        spl.alpha(tm, frame=frame)[inner], (ebm if frame == "body" else esm)[inner], atol=1e-2
    )


@pytest.mark.parametrize("kind", ["body", "space"])
def test_as_euler_round_trip_through_sympy(kind):
    """``as_euler`` of SymPy's DCM gives angles whose SymPy DCM is the same matrix.

    Including exactly singular middle angles and ones 1e-9 rad away: within
    ``GIMBAL_LOCK_ATOL`` of the singularity poinsot (like SciPy) sets the third
    angle to 0 and warns, so the matrix is then reproduced to about twice the
    distance to the singularity.
    """
    import warnings

    from poinsot.errors import GimbalLockWarning
    from poinsot.rotations.euler import GIMBAL_LOCK_ATOL

    q = me.dynamicsymbols("q1:4")
    rng = np.random.default_rng(43 if kind == "body" else 44)
    for seq in SEQUENCES:
        N = me.ReferenceFrame("N")
        B = me.ReferenceFrame("B")
        (B.orient_body_fixed if kind == "body" else B.orient_space_fixed)(N, q, seq)
        f = sp.lambdify([q], N.dcm(B), "numpy")
        seq_p = seq.upper() if kind == "body" else seq
        if seq[0] == seq[2]:
            special = [0.0, np.pi, 1e-9, np.pi - 1e-9, 1e-5]
        else:
            special = [np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-9, -np.pi / 2 + 1e-5]
        for mid in special + list(_random_angles(rng, seq, 4)[:, 1]):
            a = np.array([rng.uniform(-np.pi, np.pi), mid, rng.uniform(-np.pi, np.pi)])
            c = np.asarray(f(a), dtype=float)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                back = Rotation.from_matrix(c).as_euler(seq_p)
            locked = any(issubclass(w.category, GimbalLockWarning) for w in caught)
            if seq[0] == seq[2]:  # proper Euler: singular at 0 and pi
                dist = min(abs(mid), abs(abs(mid) - np.pi))
            else:  # Tait-Bryan: singular at +-pi/2
                dist = abs(abs(mid) - np.pi / 2)
            assert locked == (dist < GIMBAL_LOCK_ATOL)
            tol = 2.5 * GIMBAL_LOCK_ATOL if locked else 1e-14
            np.testing.assert_allclose(np.asarray(f(back), dtype=float), c, atol=tol)


@pytest.mark.parametrize("frame", ["body", "space"])
def test_propagate_sampled_omega_vs_sympy(sympy_history, frame):
    """omega given as samples (cubic-spline interpolated): 4th-order convergence."""
    from poinsot.kinematics import propagate

    errs = []
    for n in (61, 121):
        t = np.linspace(0.0, 3.0, n)
        c, wb, ws, _, _ = sympy_history(t)
        w = wb if frame == "body" else ws
        tr = propagate(Rotation.from_matrix(c[0]), w, t, frame=frame, method="magnus4")
        errs.append(np.abs(tr.rotation.as_matrix() - c).max())
    assert errs[1] < 1e-7  # 5.2e-9 seen
    assert np.log2(errs[0] / errs[1]) > 3.5


def test_propagate_batch_vs_sympy(sympy_history):
    """N bodies with the same body omega: ``R_k(t) = R_k(0) C(0)^T C(t)`` (SymPy's C)."""
    from poinsot.kinematics import propagate

    t = np.linspace(0.0, 3.0, 16)
    c, _, _, _, _ = sympy_history(t)
    r0 = Rotation.random((4,), rng=np.random.default_rng(45))

    def omega(tt):
        return sympy_history(tt)[1][0]

    tr = propagate(r0, omega, t, method="magnus6", max_step=0.02)
    want = np.einsum("bij,kj,tkl->tbil", r0.as_matrix(), c[0], c)
    assert tr.rotation.shape == (16, 4)
    np.testing.assert_allclose(tr.rotation.as_matrix(), want, atol=1e-10)


# ---------------------------------------------------------------------------
# 3b. Screw axis and reduction of motions (SymPy solves the axis equations)
# ---------------------------------------------------------------------------


def test_screw_axis_vs_sympy_linsolve():
    """The axis point nearest ``origin``: ``V0 + w x (r - O) = lam w``, ``(r - O) . w = 0``."""
    from poinsot.kinematics import screw_axis

    rng = np.random.default_rng(46)
    r = sp.symbols("r1:4")
    lam = sp.Symbol("lam")
    for _ in range(5):
        v0, w, o = rng.normal(size=(3, 3))
        rv = sp.Matrix(r)
        rel = rv - sp.Matrix(o)
        eqs = list(sp.Matrix(v0) + sp.Matrix(w).cross(rel) - lam * sp.Matrix(w))
        eqs.append(rel.dot(sp.Matrix(w)))
        (sol,) = sp.linsolve(eqs, [*r, lam])
        point = np.array([float(x) for x in sol[:3]])
        lam_v = float(sol[3])
        s = screw_axis(v0, w, pole=o)
        np.testing.assert_allclose(s.point, point, atol=1e-12)
        np.testing.assert_allclose(s.direction, w / np.linalg.norm(w), atol=TOL)
        assert abs(float(s.parameter) - lam_v) < 1e-12
        assert abs(float(s.min_speed) - abs(lam_v) * np.linalg.norm(w)) < 1e-12


def test_reduce_motions_vs_sympy_velocity_field():
    """Sum of rotation and translation fields (SymPy) at the pole, and the resulting axis."""
    from poinsot.kinematics import reduce_motions

    rng = np.random.default_rng(47)
    x = sp.Matrix(sp.symbols("x1:4"))
    rotations = [(rng.normal(size=3), rng.normal(size=3)) for _ in range(3)]
    translations = [rng.normal(size=3) for _ in range(2)]
    field = sum(
        (sp.Matrix(w).cross(x - sp.Matrix(p)) for w, p in rotations), start=sp.zeros(3, 1)
    ) + sum((sp.Matrix(v) for v in translations), start=sp.zeros(3, 1))
    pole = rng.normal(size=3)
    want_v = np.array([float(c) for c in field.subs(dict(zip(x, pole, strict=True)))])
    m = reduce_motions(rotations, translations, pole=pole)
    np.testing.assert_allclose(m.omega, sum(w for w, _ in rotations), atol=TOL)
    np.testing.assert_allclose(m.velocity, want_v, atol=1e-12)
    assert m.kind == "screw"
    # every point of the axis moves along it with the field's velocity lam w
    for s in (0.0, 1.7, -2.3):
        pt = m.screw.point + s * m.screw.direction
        v_pt = np.array([float(c) for c in field.subs(dict(zip(x, pt, strict=True)))])
        np.testing.assert_allclose(v_pt, float(m.screw.parameter) * m.omega, atol=1e-12)
