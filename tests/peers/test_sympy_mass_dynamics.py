"""Peer cross-checks of poinsot's mass geometry and Euler's equations against SymPy.

Expected values come from ``sympy.physics.mechanics`` (``inertia``,
``inertia_of_point_mass``, ``RigidBody.kinetic_energy`` / ``angular_momentum`` /
``parallel_axis``, ``Dyadic.to_matrix`` in rotated frames, ``KanesMethod``) and
from symbolic volume integrals, evaluated at random seeded points.

Conventions matched: ``inertia(B, ixx, iyy, izz, ixy, iyz, izx)`` takes the
*tensor entries* (``ixy`` is the ``B.x|B.y`` coefficient, i.e. already minus the
product of inertia), the same as poinsot's tensor ``J[0, 1]``;
``RigidBody.angular_momentum(O, N)`` is ``J_c w + OC x m V_c``, as
``poinsot.mass.angular_momentum(..., r_oc=OC)``.
"""

from __future__ import annotations

import numpy as np
import pytest

sp = pytest.importorskip("sympy")
me = pytest.importorskip("sympy.physics.mechanics")

import poinsot.mass as pm  # noqa: E402
from poinsot import Rotation  # noqa: E402
from poinsot.dynamics import euler_rhs  # noqa: E402

TOL = 1e-12

_J = sp.symbols("Ixx Iyy Izz Ixy Iyz Izx")


def _as_sympy_args(j: np.ndarray) -> list[float]:
    """poinsot tensor -> SymPy ``inertia`` arguments (ixx, iyy, izz, ixy, iyz, izx)."""
    return [j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[1, 2], j[2, 0]]


def _random_inertia(rng) -> np.ndarray:
    """A physical, non-diagonal inertia tensor: random points plus a ball."""
    pos = rng.normal(size=(6, 3))
    masses = rng.uniform(0.5, 2.0, size=6)
    pos -= masses @ pos / masses.sum()
    j = np.einsum(
        "k,kij->ij",
        masses,
        np.einsum("ki,ki->k", pos, pos)[:, None, None] * np.eye(3)
        - pos[:, :, None] * pos[:, None, :],
    )
    return j + 0.3 * np.eye(3)


def _vec(x) -> np.ndarray:
    return np.asarray(x, dtype=float).reshape(-1)


# ---------------------------------------------------------------------------
# 4. Mass geometry
# ---------------------------------------------------------------------------


def test_points_vs_inertia_of_point_mass():
    rng = np.random.default_rng(20)
    N = me.ReferenceFrame("N")
    masses = rng.uniform(0.1, 3.0, size=7)
    pos = rng.normal(size=(7, 3))
    dyadic = sum(
        (
            me.inertia_of_point_mass(
                float(m), sum(float(c) * e for c, e in zip(p, N, strict=True)), N
            )
            for m, p in zip(masses, pos, strict=True)
        ),
        start=0 * (N.x | N.x),
    )
    want = np.asarray(dyadic.to_matrix(N), dtype=float)
    np.testing.assert_allclose(pm.points(masses, pos), want, rtol=0, atol=TOL * 10)
    # the same as a RigidBody built from the points, moved back to O
    body = pm.RigidBody.from_points(masses, pos)
    np.testing.assert_allclose(body.inertia_about([0, 0, 0]), want, atol=TOL * 10)


def test_parallel_axis_vs_sympy():
    rng = np.random.default_rng(21)
    N = me.ReferenceFrame("N")
    for _ in range(5):
        j_c = _random_inertia(rng)
        m = float(rng.uniform(0.5, 5.0))
        c, o = rng.normal(size=3), rng.normal(size=3)
        C = me.Point("C")
        O = C.locatenew("O", sum(float(v) * e for v, e in zip(o - c, N, strict=True)))
        body = me.RigidBody("b", C, N, m, (me.inertia(N, *_as_sympy_args(j_c)), C))
        want = np.asarray(body.parallel_axis(O).to_matrix(N), dtype=float)
        np.testing.assert_allclose(pm.parallel_axis(j_c, m, o - c), want, atol=TOL)
        np.testing.assert_allclose(pm.to_center_of_mass(want, m, o - c), j_c, atol=TOL)
        rb = pm.RigidBody(m, j_c, center_of_mass=c)
        np.testing.assert_allclose(rb.inertia_about(o), want, atol=TOL)


def test_rotate_inertia_vs_sympy_dyadic():
    """An inertia dyadic given in B, read in N (and back) with ``Dyadic.to_matrix``."""
    rng = np.random.default_rng(22)
    for _ in range(5):
        j_b = _random_inertia(rng)
        R = Rotation.random(rng=rng)  # attitude of B relative to N: C_nb
        N = me.ReferenceFrame("N")
        B = me.ReferenceFrame("B")
        B.orient_explicit(N, sp.Matrix(R.as_matrix()))  # takes N.dcm(B) (its docs)
        np.testing.assert_allclose(np.asarray(N.dcm(B), dtype=float), R.as_matrix(), atol=TOL)
        dyadic = me.inertia(B, *_as_sympy_args(j_b))
        j_n = np.asarray(dyadic.to_matrix(N), dtype=float)
        np.testing.assert_allclose(pm.rotate_inertia(j_b, R.inv()), j_n, atol=TOL)
        np.testing.assert_allclose(pm.rotate_inertia(j_n, R), j_b, atol=TOL)
        np.testing.assert_allclose(pm.rotate_inertia(j_n, R.as_matrix()), j_b, atol=TOL)
        # moment about an axis: e . J . e
        e = rng.normal(size=3)
        e /= np.linalg.norm(e)
        e_vec = sum(float(v) * u for v, u in zip(e, N, strict=True))
        want = float(e_vec.dot(dyadic.dot(e_vec)))
        assert abs(float(pm.moment_about(j_n, e)) - want) < TOL


@pytest.fixture(scope="module")
def sympy_moving_body():
    """A rigid body that rotates (z-y-x angles) and translates, and a fixed point O."""
    q = me.dynamicsymbols("q1:4")
    x = me.dynamicsymbols("x1:4")
    qd = [v.diff() for v in q]
    xd = [v.diff() for v in x]
    o = sp.symbols("o1:4")
    m = sp.symbols("m", positive=True)
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "zyx")
    N0 = me.Point("N0")
    N0.set_vel(N, 0)
    C = N0.locatenew("C", x[0] * N.x + x[1] * N.y + x[2] * N.z)
    C.set_vel(N, C.pos_from(N0).dt(N))
    O = N0.locatenew("O", o[0] * N.x + o[1] * N.y + o[2] * N.z)
    O.set_vel(N, 0)
    body = me.RigidBody("b", C, B, m, (me.inertia(B, *_J), C))
    exprs = [
        body.kinetic_energy(N),
        body.angular_momentum(O, N).to_matrix(B),
        body.angular_momentum(O, N).to_matrix(N),
        body.angular_momentum(C, N).to_matrix(B),
        B.ang_vel_in(N).to_matrix(B),
        C.vel(N).to_matrix(B),
        C.pos_from(O).to_matrix(B),
        N.dcm(B),
    ]
    return sp.lambdify([q, qd, x, xd, o, m, _J], exprs, "numpy")


def test_kinetic_energy_and_momentum_vs_sympy_rigid_body(sympy_moving_body):
    rng = np.random.default_rng(23)
    for _ in range(8):
        j_c = _random_inertia(rng)
        m = float(rng.uniform(0.5, 5.0))
        q, qd, x, xd, o = rng.uniform(-2, 2, size=(5, 3))
        t, k_o_b, k_o_n, k_c_b, w_b, v_b, r_oc_b, c_nb = sympy_moving_body(
            q, qd, x, xd, o, m, _as_sympy_args(j_c)
        )
        t = float(t)
        k_o_b, k_o_n, k_c_b = _vec(k_o_b), _vec(k_o_n), _vec(k_c_b)
        w_b, v_b, r_oc_b = _vec(w_b), _vec(v_b), _vec(r_oc_b)
        c_nb = np.asarray(c_nb, dtype=float)
        scale = 1.0 + abs(t)
        # body axes
        assert abs(float(pm.kinetic_energy(m, j_c, w_b, v_b)) - t) < TOL * scale
        np.testing.assert_allclose(pm.angular_momentum(m, j_c, w_b, v_b, r_oc_b), k_o_b, atol=1e-11)
        np.testing.assert_allclose(pm.angular_momentum(m, j_c, w_b, v_b), k_c_b, atol=1e-11)
        # space axes: the same functions with every argument rotated to N
        j_n = pm.rotate_inertia(j_c, Rotation.from_matrix(c_nb).inv())
        args_n = (c_nb @ w_b, c_nb @ v_b, c_nb @ r_oc_b)
        assert abs(float(pm.kinetic_energy(m, j_n, *args_n[:2])) - t) < TOL * scale
        np.testing.assert_allclose(pm.angular_momentum(m, j_n, *args_n), k_o_n, atol=1e-11)
        # RigidBody: reference point = O, centre of mass at OC (body axes)
        rb = pm.RigidBody(m, j_c, center_of_mass=r_oc_b)
        assert abs(float(rb.kinetic_energy(w_b, v_b)) - t) < TOL * scale
        np.testing.assert_allclose(rb.angular_momentum(w_b, v_b), k_o_b, atol=1e-11)
        np.testing.assert_allclose(rb.angular_momentum(w_b, v_b, point=r_oc_b), k_c_b, atol=1e-11)


def test_composite_body_vs_sympy():
    """Two bodies and a particle: SymPy's summed T and K about O vs ``combine``."""
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    rng = np.random.default_rng(24)
    R = Rotation.random(rng=rng)
    B.orient_explicit(N, sp.Matrix(R.as_matrix()))
    w_n = rng.normal(size=3)
    B.set_ang_vel(N, sum(float(v) * e for v, e in zip(w_n, N, strict=True)))
    O = me.Point("O")
    O.set_vel(N, 0)  # a point of the body, at rest: the body turns about O

    def vec(a, frame):
        return sum(float(v) * e for v, e in zip(a, frame, strict=True))

    parts, pieces = [], []
    for k in range(2):
        j_c = _random_inertia(rng)
        m = float(rng.uniform(0.5, 3.0))
        c = rng.normal(size=3)  # body axes
        C = O.locatenew(f"C{k}", vec(c, B))
        C.v2pt_theory(O, N, B)
        parts.append(me.RigidBody(f"b{k}", C, B, m, (me.inertia(B, *_as_sympy_args(j_c)), C)))
        pieces.append(pm.RigidBody(m, j_c, center_of_mass=c))
    mp, cp = 0.7, rng.normal(size=3)
    P = O.locatenew("P", vec(cp, B))
    P.v2pt_theory(O, N, B)
    parts.append(me.Particle("p", P, mp))
    pieces.append(pm.RigidBody(mp, np.zeros((3, 3)), center_of_mass=cp))

    t_want = float(sum(p.kinetic_energy(N) for p in parts))
    k_want = _vec(sum((p.angular_momentum(O, N) for p in parts), start=0 * N.x).to_matrix(B))
    whole = pm.combine(*pieces)
    w_b = R.apply(w_n, inverse=True)
    v_cm_b = np.cross(w_b, whole.center_of_mass)
    assert abs(float(whole.kinetic_energy(w_b, v_cm_b)) - t_want) < 1e-11
    np.testing.assert_allclose(whole.angular_momentum(w_b, v_cm_b), k_want, atol=1e-11)
    # about the fixed point: K = J_O w, T = w . J_O w / 2
    j_o = whole.inertia_about([0, 0, 0])
    np.testing.assert_allclose(j_o @ w_b, k_want, atol=1e-11)
    assert abs(0.5 * w_b @ j_o @ w_b - t_want) < 1e-11


# uniform solids: SymPy volume / surface / line integrals of the density --------

_x, _y, _z, _r, _phi, _th = sp.symbols("x y z r phi theta", real=True)
_a, _b, _c, _h, _R = sp.symbols("a b c h R", positive=True)


def _tensor(density, jac, bounds, xyz):
    """Mass, centre of mass and inertia about the centre of mass by integration."""

    def integ(f):
        e = f * density * jac
        for v, lo, hi in bounds:
            e = sp.integrate(e, (v, lo, hi))
        return sp.simplify(e)

    mass = integ(sp.Integer(1))
    com = [integ(u) / mass for u in xyz]
    rel = [u - c0 for u, c0 in zip(xyz, com, strict=True)]
    r2 = sum(u**2 for u in rel)
    j = sp.Matrix(3, 3, lambda i, k: integ((r2 if i == k else 0) - rel[i] * rel[k]))
    return mass, j


def _solid_cases():
    cyl = (_r * sp.cos(_phi), _r * sp.sin(_phi), _z)
    sph = (
        _r * sp.sin(_th) * sp.cos(_phi),
        _r * sp.sin(_th) * sp.sin(_phi),
        _r * sp.cos(_th),
    )
    two_pi = (_phi, 0, 2 * sp.pi)
    return {
        # name: (density, coordinates, jacobian, bounds (inner first), poinsot function)
        "box": (
            1,
            (_x, _y, _z),
            1,
            [(_x, -_a / 2, _a / 2), (_y, -_b / 2, _b / 2), (_z, -_c / 2, _c / 2)],
            lambda m, v: pm.box(m, v["a"], v["b"], v["c"]),
        ),
        "cylinder": (
            1,
            cyl,
            _r,
            [(_r, 0, _R), two_pi, (_z, 0, _h)],
            lambda m, v: pm.cylinder(m, v["R"], v["h"]),
        ),
        "tube": (
            1,
            (_R * sp.cos(_phi), _R * sp.sin(_phi), _z),
            1,
            [two_pi, (_z, 0, _h)],
            lambda m, v: pm.cylinder(m, v["R"], v["h"], hollow=True),
        ),
        "cone": (
            1,
            cyl,
            _r,
            [(_r, 0, _R * (1 - _z / _h)), two_pi, (_z, 0, _h)],
            lambda m, v: pm.cone(m, v["R"], v["h"]),
        ),
        "ball": (
            1,
            sph,
            _r**2 * sp.sin(_th),
            [(_r, 0, _R), (_th, 0, sp.pi), two_pi],
            lambda m, v: pm.sphere(m, v["R"]),
        ),
        "shell": (
            1,
            tuple(u.subs(_r, _R) for u in sph),
            sp.sin(_th),
            [(_th, 0, sp.pi), two_pi],
            lambda m, v: pm.sphere(m, v["R"], hollow=True),
        ),
        # ellipsoid = unit ball scaled by (a, b, c)
        "ellipsoid": (
            1,
            (_a * sph[0], _b * sph[1], _c * sph[2]),
            _r**2 * sp.sin(_th),
            [(_r, 0, 1), (_th, 0, sp.pi), two_pi],
            lambda m, v: pm.ellipsoid(m, v["a"], v["b"], v["c"]),
        ),
        "rod": (1, (0, 0, _z), 1, [(_z, -_h / 2, _h / 2)], lambda m, v: pm.rod(m, v["h"])),
        "disc": (
            1,
            (cyl[0], cyl[1], 0),
            _r,
            [(_r, 0, _R), two_pi],
            lambda m, v: pm.disc(m, v["R"]),
        ),
        "ring": (
            1,
            (_R * sp.cos(_phi), _R * sp.sin(_phi), 0),
            1,
            [two_pi],
            lambda m, v: pm.ring(m, v["R"]),
        ),
    }


@pytest.mark.parametrize("name", sorted(_solid_cases()))
def test_solids_vs_sympy_integrals(name):
    density, xyz, jac, bounds, fn = _solid_cases()[name]
    mass, j = _tensor(sp.Integer(density), jac, bounds, [sp.sympify(u) for u in xyz])
    vals = {"a": 0.7, "b": 1.3, "c": 2.1, "h": 1.7, "R": 0.45}
    subs = {_a: vals["a"], _b: vals["b"], _c: vals["c"], _h: vals["h"], _R: vals["R"]}
    m_num = 3.5
    # inertia for total mass m_num: J * m_num / mass
    want = np.asarray((j / mass).subs(subs).evalf(), dtype=float) * m_num
    np.testing.assert_allclose(fn(m_num, vals), want, rtol=1e-13, atol=1e-14)


# ---------------------------------------------------------------------------
# 5. Euler's dynamic equations via Kane's method
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def kane_euler():
    """Body-frame generalised speeds u = omega_B; returns (mass matrix, forcing) functions."""
    q = me.dynamicsymbols("q1:4")
    u = me.dynamicsymbols("u1:4")
    torque = sp.symbols("M1:4")
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "zxz")
    w_q = B.ang_vel_in(N)
    kd = [w_q.dot(B.x) - u[0], w_q.dot(B.y) - u[1], w_q.dot(B.z) - u[2]]
    B.set_ang_vel(N, u[0] * B.x + u[1] * B.y + u[2] * B.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    body = me.RigidBody("b", O, B, sp.Symbol("m"), (me.inertia(B, *_J), O))
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations([body], [(B, torque[0] * B.x + torque[1] * B.y + torque[2] * B.z)])
    mm = sp.lambdify([_J], km.mass_matrix, "numpy")
    fo = sp.lambdify([u, torque, _J], km.forcing, "numpy")
    return mm, fo


def test_euler_rhs_vs_kane(kane_euler):
    mm, fo = kane_euler
    rng = np.random.default_rng(25)
    js, ws, ms, want = [], [], [], []
    for _ in range(10):
        j = _random_inertia(rng)
        w, m = rng.normal(size=3) * 2, rng.normal(size=3)
        a = np.linalg.solve(
            np.asarray(mm(_as_sympy_args(j)), dtype=float), _vec(fo(w, m, _as_sympy_args(j)))
        )
        np.testing.assert_allclose(euler_rhs(j, w, m), a, rtol=1e-12, atol=1e-12)
        js.append(j)
        ws.append(w)
        ms.append(m)
        want.append(a)
        # principal moments: the diagonal form
        d = np.diag(np.diag(j))
        a_d = np.linalg.solve(
            np.asarray(mm(_as_sympy_args(d)), dtype=float), _vec(fo(w, m, _as_sympy_args(d)))
        )
        np.testing.assert_allclose(euler_rhs(np.diag(j), w, m), a_d, rtol=1e-12, atol=1e-12)
        a_free = np.linalg.solve(
            np.asarray(mm(_as_sympy_args(j)), dtype=float),
            _vec(fo(w, np.zeros(3), _as_sympy_args(j))),
        )
        np.testing.assert_allclose(euler_rhs(j, w), a_free, rtol=1e-12, atol=1e-12)
    # batched call
    np.testing.assert_allclose(
        euler_rhs(np.array(js), np.array(ws), np.array(ms)), np.array(want), rtol=1e-12, atol=1e-12
    )


def test_mesh_tetrahedron_vs_sympy_integral():
    """A random tetrahedron as a mesh vs SymPy integrals over the mapped unit simplex."""
    u, v, w = sp.symbols("u v w", nonnegative=True)
    rng = np.random.default_rng(26)
    verts = rng.normal(size=(4, 3))
    if np.linalg.det(verts[1:] - verts[0]) < 0:
        verts[[1, 2]] = verts[[2, 1]]
    # x = v0 + u (v1 - v0) + v (v2 - v0) + w (v3 - v0) over the unit simplex
    e = sp.Matrix(verts[1:] - verts[0]).T
    x = sp.Matrix(verts[0]) + e * sp.Matrix([u, v, w])
    det = abs(float(np.linalg.det(verts[1:] - verts[0])))

    def integ(f):
        g = sp.integrate(f * det, (w, 0, 1 - u - v))
        g = sp.integrate(g, (v, 0, 1 - u))
        return float(sp.integrate(g, (u, 0, 1)))

    vol = integ(sp.Integer(1))
    com = np.array([integ(x[i]) for i in range(3)]) / vol
    p = np.array([[integ(x[i] * x[k]) for k in range(3)] for i in range(3)])
    p -= vol * np.outer(com, com)  # int (r - c)(r - c)^T dV
    j_want = np.trace(p) * np.eye(3) - p
    faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    props = pm.mesh(verts, faces)
    assert abs(props.volume - vol) < 1e-14
    np.testing.assert_allclose(props.center_of_mass, com, atol=1e-14)
    np.testing.assert_allclose(props.inertia, j_want, atol=1e-14)
    props = pm.mesh(verts, faces, mass=2.5)
    np.testing.assert_allclose(props.inertia, j_want * 2.5 / vol, atol=1e-13)


def test_placed_vs_sympy_dyadic_and_parallel_axis():
    """``RigidBody.placed(C_ab, position)``: SymPy dyadic in b read in a, moved to a's origin."""
    rng = np.random.default_rng(27)
    for _ in range(2):
        j_c = _random_inertia(rng)
        m = float(rng.uniform(0.5, 3.0))
        c_b = rng.normal(size=3)  # centre of mass from the body reference point, b axes
        pos = rng.normal(size=3)  # body reference point in a
        R = Rotation.random(rng=rng)  # C_ab
        A = me.ReferenceFrame("A")
        Bf = me.ReferenceFrame("B")
        Bf.orient_explicit(A, sp.Matrix(R.as_matrix()))  # takes A.dcm(B)
        OA = me.Point("OA")
        ref = OA.locatenew("ref", sum(float(v) * e for v, e in zip(pos, A, strict=True)))
        C = ref.locatenew("C", sum(float(v) * e for v, e in zip(c_b, Bf, strict=True)))
        body = me.RigidBody("b", C, Bf, m, (me.inertia(Bf, *_as_sympy_args(j_c)), C))
        placed = pm.RigidBody(m, j_c, center_of_mass=c_b).placed(R, pos)
        np.testing.assert_allclose(
            placed.center_of_mass, _vec(C.pos_from(OA).to_matrix(A)), atol=1e-14
        )
        np.testing.assert_allclose(
            placed.inertia, np.asarray(body.central_inertia.to_matrix(A), dtype=float), atol=1e-12
        )
        np.testing.assert_allclose(
            placed.inertia_about([0, 0, 0]),
            np.asarray(body.parallel_axis(OA, A).to_matrix(A), dtype=float),
            atol=1e-12,
        )
