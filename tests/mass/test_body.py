"""RigidBody, composites, Koenig's theorem and angular momentum against point-mass sums."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import Rotation
from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.mass import (
    RigidBody,
    angular_momentum,
    box,
    combine,
    cone,
    cylinder,
    disc,
    ellipsoid,
    kinetic_energy,
    points,
    ring,
    rod,
    sphere,
)


def _cloud(seed, n=9):
    rng = np.random.default_rng(seed)
    return rng.uniform(0.1, 2.0, n), rng.normal(size=(n, 3)) + [0.5, -1.0, 2.0]


def test_from_points_center_and_inertia():
    m, r = _cloud(0)
    body = RigidBody.from_points(m, r)
    c = m @ r / m.sum()
    assert body.mass == pytest.approx(m.sum())
    np.testing.assert_allclose(body.center_of_mass, c, rtol=1e-13)
    np.testing.assert_allclose(body.inertia, points(m, r - c), atol=1e-12)
    # about any point: the points' tensor about that point
    p = np.array([0.3, 0.1, -2.0])
    np.testing.assert_allclose(body.inertia_about(p), points(m, r - p), atol=1e-12)
    np.testing.assert_allclose(body.inertia_about(), points(m, r), atol=1e-12)


def test_combine_two_boxes_is_one_long_box():
    half = RigidBody.box(1.5, 1.0, 0.4, 0.7)
    body = half.placed(position=[0.5, 0, 0]) + half.placed(position=[-0.5, 0, 0])
    assert body.mass == 3.0
    np.testing.assert_allclose(body.center_of_mass, 0.0, atol=1e-15)
    np.testing.assert_allclose(body.inertia, box(3.0, 2.0, 0.4, 0.7), rtol=1e-14)
    # stacked along z with an offset reference point: same body, centre of mass moved
    body = combine(half.placed(position=[5.0, 1.0, 1.0]), half.placed(position=[4.0, 1.0, 1.0]))
    np.testing.assert_allclose(body.center_of_mass, [4.5, 1.0, 1.0])
    np.testing.assert_allclose(body.inertia, box(3.0, 2.0, 0.4, 0.7), rtol=1e-13)


def test_combine_against_point_clouds_and_sum():
    parts = [_cloud(s) for s in (1, 2, 3)]
    bodies = [RigidBody.from_points(m, r) for m, r in parts]
    whole = RigidBody.from_points(
        np.concatenate([m for m, _ in parts]), np.concatenate([r for _, r in parts])
    )
    for composite in (combine(*bodies), bodies[0] + bodies[1] + bodies[2], sum(bodies)):
        np.testing.assert_allclose(composite.mass, whole.mass, rtol=1e-14)
        np.testing.assert_allclose(composite.center_of_mass, whole.center_of_mass, rtol=1e-13)
        np.testing.assert_allclose(composite.inertia, whole.inertia, atol=1e-12)
    assert RigidBody.combine(bodies[0]).mass == bodies[0].mass


def test_placed_against_transformed_points():
    m, r_b = _cloud(4)
    c_ab = SciRotation.from_rotvec([0.2, -0.7, 1.1]).as_matrix()
    pos = np.array([1.0, 2.0, 3.0])
    r_a = r_b @ c_ab.T + pos
    expected = RigidBody.from_points(m, r_a)
    for rot in (c_ab, Rotation.from_matrix(c_ab)):
        got = RigidBody.from_points(m, r_b).placed(rot, pos)
        np.testing.assert_allclose(got.center_of_mass, expected.center_of_mass, atol=1e-12)
        np.testing.assert_allclose(got.inertia, expected.inertia, atol=1e-12)


def test_koenig_energy_and_momentum_against_point_cloud():
    """Rigid motion v_k = V_O + w x r_k of point masses: T = sum m v^2/2, K_P = sum m (r-P) x v."""
    m, r = _cloud(5, n=12)
    body = RigidBody.from_points(m, r)
    rng = np.random.default_rng(6)
    w, v_o = rng.normal(size=3), rng.normal(size=3)
    v = v_o + np.cross(w, r)
    v_cm = v_o + np.cross(w, body.center_of_mass)
    t_sum = 0.5 * np.sum(m * np.sum(v * v, axis=-1))
    np.testing.assert_allclose(body.kinetic_energy(w, v_cm), t_sum, rtol=1e-13)
    np.testing.assert_allclose(kinetic_energy(body.mass, body.inertia, w, v_cm), t_sum, rtol=1e-13)
    for p in (np.zeros(3), body.center_of_mass, np.array([3.0, -1.0, 0.5])):
        k_sum = np.sum(m[:, None] * np.cross(r - p, v), axis=0)
        np.testing.assert_allclose(body.angular_momentum(w, v_cm, point=p), k_sum, atol=1e-12)
        np.testing.assert_allclose(
            angular_momentum(body.mass, body.inertia, w, v_cm, body.center_of_mass - p),
            k_sum,
            atol=1e-12,
        )


def test_pure_rotation_defaults():
    """With V_c = 0 and O = C: T = w^T J w / 2 = (A p^2 + B q^2 + C r^2)/2, K = J w."""
    j = ellipsoid(2.0, 1.0, 2.0, 3.0)
    w = np.array([0.3, -0.2, 0.7])
    a, b, c = j.diagonal()
    np.testing.assert_allclose(
        kinetic_energy(2.0, j, w), 0.5 * (a * w[0] ** 2 + b * w[1] ** 2 + c * w[2] ** 2)
    )
    np.testing.assert_allclose(angular_momentum(2.0, j, w), [a * w[0], b * w[1], c * w[2]])


def test_batch_bodies():
    masses = np.array([1.0, 2.0, 3.0])
    body = RigidBody(masses, sphere(masses, 1.0), [[0, 0, 1.0]] * 3)
    assert body.shape == (3,)
    w = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
    np.testing.assert_allclose(body.kinetic_energy(w), 0.5 * 0.4 * masses)
    moments = body.principal_moments
    assert moments.shape == (3, 3)
    np.testing.assert_allclose(moments, 0.4 * masses[:, None] * np.ones(3))  # 2/5 m r^2
    mom, rot = body.principal_axes()
    np.testing.assert_allclose(mom, moments, rtol=1e-14)
    s = rot.as_matrix()
    diag = np.swapaxes(s, -1, -2) @ body.inertia @ s
    np.testing.assert_allclose(diag, moments[..., None] * np.eye(3), atol=1e-14)
    both = body + RigidBody(1.0, sphere(1.0, 1.0))
    assert both.shape == (3,)
    np.testing.assert_allclose(both.mass, masses + 1.0)
    # two balls 1 apart on z: each moved d = m_other / M from the common centre of mass
    # (Huygens-Steiner): J_xx = J_yy = 0.4 (m + 1) + m * 1 / (m + 1), J_zz = 0.4 (m + 1)
    np.testing.assert_allclose(both.center_of_mass[:, 2], masses / (masses + 1.0))
    side = 0.4 * (masses + 1.0) + masses / (masses + 1.0)
    np.testing.assert_allclose(
        both.inertia,
        np.stack([np.diag([s, s, 0.4 * (m + 1.0)]) for s, m in zip(side, masses, strict=True)]),
    )
    with pytest.raises(ValueError, match="read-only"):
        body.inertia[0, 0, 0] = 5.0


def test_classmethods_match_functions():
    cases = [
        (RigidBody.box(2.0, 1.0, 2.0, 3.0), box(2.0, 1.0, 2.0, 3.0)),
        (RigidBody.sphere(2.0, 1.0, hollow=True), sphere(2.0, 1.0, hollow=True)),
        (RigidBody.cylinder(2.0, 1.0, 3.0), cylinder(2.0, 1.0, 3.0)),
        (RigidBody.cone(2.0, 1.0, 3.0), cone(2.0, 1.0, 3.0)),
        (RigidBody.ellipsoid(2.0, 1.0, 2.0, 3.0), ellipsoid(2.0, 1.0, 2.0, 3.0)),
        (RigidBody.rod(2.0, 1.0), rod(2.0, 1.0)),
        (RigidBody.disc(2.0, 1.0), disc(2.0, 1.0)),
        (RigidBody.ring(2.0, 1.0), ring(2.0, 1.0)),
    ]
    for body, j in cases:
        assert body.mass == 2.0 and body.shape == ()
        np.testing.assert_array_equal(body.inertia, j)
        np.testing.assert_array_equal(body.center_of_mass, 0.0)


def test_dumbbell_textbook():
    """Two spheres on a massless rod: J = 2 (2/5 m r^2 + m d^2) about the transverse axis."""
    s = RigidBody.sphere(1.0, 0.1)
    bell = s.placed(position=[0, 0, 1.0]) + s.placed(position=[0, 0, -1.0])
    np.testing.assert_allclose(bell.inertia, np.diag([2 * (0.004 + 1)] * 2 + [2 * 0.004]))
    np.testing.assert_allclose(bell.center_of_mass, 0.0, atol=1e-15)


def test_rigid_body_errors():
    with pytest.raises(InvalidInputError, match="`mass` to be positive"):
        RigidBody(0.0, np.eye(3))
    with pytest.raises(InvalidInputError, match="`inertia` is not a physical inertia tensor"):
        RigidBody(1.0, np.diag([1.0, 1.0, 5.0]))
    with pytest.raises(InvalidInputError, match="`inertia` to be positive semi-definite"):
        RigidBody(1.0, np.diag([-1.0, 1.0, 1.0]))
    with pytest.raises(InvalidInputError, match=r"`center_of_mass` to have shape \(\.\.\., 3\)"):
        RigidBody(1.0, np.eye(3), [0.0, 1.0])
    with pytest.raises(
        InvalidInputError, match="batch .leading. shapes of .mass. .2,.*to broadcast"
    ):
        RigidBody([1.0, 2.0], np.eye(3), np.zeros((3, 3)))
    with pytest.raises(InvalidInputError, match="at least one body"):
        combine()
    with pytest.raises(InvalidTypeError, match="every body to be a RigidBody, got ndarray at"):
        combine(RigidBody(1.0, np.eye(3)), np.eye(3))
    with pytest.raises(TypeError, match="unsupported operand"):
        RigidBody(1.0, np.eye(3)) + 1.0
    with pytest.raises(InvalidInputError, match=r"`omega` to have shape \(\.\.\., 3\)"):
        RigidBody(1.0, np.eye(3)).kinetic_energy([1.0, 2.0])
    with pytest.raises(InvalidInputError, match="`inertia_cm` is not a physical"):
        kinetic_energy(1.0, np.diag([1.0, 1.0, 3.0]), [1.0, 0, 0])
    with pytest.raises(InvalidInputError, match="`mass` to be positive"):
        angular_momentum(-1.0, np.eye(3), [1.0, 0, 0])
    with pytest.raises(InvalidInputError, match=r"`r_oc` to have shape"):
        angular_momentum(1.0, np.eye(3), [1.0, 0, 0], [0, 0, 0], [1.0])
    with pytest.raises(InvalidInputError, match=r"`point` to have shape"):
        RigidBody(1.0, np.eye(3)).inertia_about([1.0])
    with pytest.raises(InvalidInputError, match=r"`rotation` to be a rotation matrix"):
        RigidBody(1.0, np.eye(3)).placed(np.ones((3, 3)))


def test_against_sympy_physics_mechanics():
    """Peer check: SymPy's inertia_of_point_mass, RigidBody.kinetic_energy and
    RigidBody.angular_momentum (sympy.physics.mechanics) on the same data."""
    pytest.importorskip("sympy")
    from sympy.physics.mechanics import Point as SymPoint
    from sympy.physics.mechanics import ReferenceFrame, inertia, inertia_of_point_mass
    from sympy.physics.mechanics import RigidBody as SymBody

    n = ReferenceFrame("N")
    r = np.array([1.0, 2.0, 3.0])
    sym = inertia_of_point_mass(2.0, r[0] * n.x + r[1] * n.y + r[2] * n.z, n).to_matrix(n)
    np.testing.assert_allclose(points([2.0], [r]), np.array(sym, dtype=float), rtol=1e-14)

    j_c = np.array([[2.0, 0.1, 0.2], [0.1, 3.0, -0.3], [0.2, -0.3, 4.0]])
    m, r_oc = 1.5, np.array([1.0, -2.0, 0.5])
    w, v_c = np.array([0.5, -0.7, 0.2]), np.array([0.3, 0.1, -0.2])

    def vec(a):
        return a[0] * n.x + a[1] * n.y + a[2] * n.z

    o = SymPoint("O")
    o.set_vel(n, 0)
    c = o.locatenew("C", vec(r_oc))
    c.set_vel(n, vec(v_c))
    b = n.orientnew("B", "Axis", [0, n.z])
    b.set_ang_vel(n, vec(w))
    dyad = inertia(n, j_c[0, 0], j_c[1, 1], j_c[2, 2], j_c[0, 1], j_c[1, 2], j_c[2, 0])
    body = SymBody("body", c, b, m, (dyad, c))
    np.testing.assert_allclose(
        kinetic_energy(m, j_c, w, v_c), float(body.kinetic_energy(n)), rtol=1e-14
    )
    k_sym = np.array(body.angular_momentum(o, n).to_matrix(n), dtype=float).ravel()
    np.testing.assert_allclose(angular_momentum(m, j_c, w, v_c, r_oc), k_sym, rtol=1e-14)
    ours = RigidBody(m, j_c, r_oc)
    np.testing.assert_allclose(ours.angular_momentum(w, v_c), k_sym, rtol=1e-14)


def test_principal_moments_accepted_like_every_entry_point():
    """``RigidBody(m, (A, B, C))`` is ``RigidBody(m, diag(A, B, C))`` (issue 9), checked
    physical the same way (a rod's zero moment allowed, the triangle inequality not)."""
    a = RigidBody(2.0, [1.0, 2.0, 2.5], [0.0, 0.0, 1.0])
    b = RigidBody(2.0, np.diag([1.0, 2.0, 2.5]), [0.0, 0.0, 1.0])
    np.testing.assert_array_equal(a.inertia, b.inertia)
    np.testing.assert_array_equal(a.inertia_about(), b.inertia_about())
    rod = RigidBody(3.0, [1.0, 1.0, 0.0])
    np.testing.assert_array_equal(rod.inertia, np.diag([1.0, 1.0, 0.0]))
    batch = RigidBody([1.0, 2.0], [[1.0, 1.0, 1.0], [2.0, 3.0, 4.0]])
    assert batch.shape == (2,) and batch.inertia.shape == (2, 3, 3)
    with pytest.raises(InvalidInputError, match="triangle inequality"):
        RigidBody(1.0, [1.0, 1.0, 5.0])


def test_one_way_from_a_mesh_and_scipy_rotations_in_placed():
    from scipy.spatial.transform import Rotation as SciRotation

    import poinsot.mass.meshes as meshes

    assert not hasattr(meshes.MeshProperties, "to_body")
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    body = RigidBody.from_mesh(v, f, mass=6.0)
    props = meshes.mesh(v, f, mass=6.0)
    np.testing.assert_array_equal(body.inertia, props.inertia)
    np.testing.assert_array_equal(body.center_of_mass, props.center_of_mass)
    r = SciRotation.from_rotvec([0.3, -0.2, 0.9])
    moved = body.placed(r)
    s = r.as_matrix()
    np.testing.assert_allclose(moved.inertia, s @ body.inertia @ s.T, atol=1e-15)


def test_module_functions_take_principal_moments_too():
    from poinsot.mass import angular_momentum, kinetic_energy

    m, j, w, v, r = 2.0, [1.0, 2.0, 2.5], [0.3, -1.0, 0.4], [0.1, 0.2, -0.3], [0.0, 1.0, 0.5]
    assert kinetic_energy(m, j, w, v) == kinetic_energy(m, np.diag(j), w, v)
    np.testing.assert_array_equal(
        angular_momentum(m, j, w, v, r), angular_momentum(m, np.diag(j), w, v, r)
    )
