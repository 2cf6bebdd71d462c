"""Mass properties of closed triangle meshes against closed forms (exact and converging)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.mass import RigidBody, box, cone, ellipsoid, mesh, sphere

# -- mesh generators (outward, counter-clockwise seen from outside) -------------------


def box_mesh(a, b, c):
    v = np.array(
        [[x, y, z] for x in (-a / 2, a / 2) for y in (-b / 2, b / 2) for z in (-c / 2, c / 2)]
    )
    # vertex index = 4 ix + 2 iy + iz
    quads = [
        (0, 1, 3, 2),  # x = -a/2
        (4, 6, 7, 5),  # x = +a/2
        (0, 4, 5, 1),  # y = -b/2
        (2, 3, 7, 6),  # y = +b/2
        (0, 2, 6, 4),  # z = -c/2
        (1, 5, 7, 3),  # z = +c/2
    ]
    f = [[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads]
    return v, np.array(f)


def icosphere(level):
    t = (1 + 5**0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]  # fmt: skip
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]  # fmt: skip
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(level):
        cache, new_f = {}, []

        def mid(i, j, cache=cache):
            key = (min(i, j), max(i, j))
            if key not in cache:
                p = v[i] + v[j]
                v.append(p / np.linalg.norm(p))
                cache[key] = len(v) - 1
            return cache[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_f += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = new_f
    return np.array(v), np.array(f)


def cone_mesh(radius, height, n):
    t = 2 * np.pi * np.arange(n) / n
    ring = np.stack([radius * np.cos(t), radius * np.sin(t), 0 * t], axis=-1)
    v = np.vstack([ring, [[0, 0, height], [0, 0, 0]]])
    apex, centre = n, n + 1
    i = np.arange(n)
    j = (i + 1) % n
    side = np.stack([i, j, np.full(n, apex)], axis=-1)
    base = np.stack([np.full(n, centre), j, i], axis=-1)
    return v, np.vstack([side, base])


# -- exact and converging values --------------------------------------------------------


def test_box_mesh_exact_any_pose():
    """A box is a polyhedron: the divergence-theorem sums are exact (to round-off)."""
    a, b, c, m = 1.0, 2.0, 3.0, 4.5
    v, f = box_mesh(a, b, c)
    s = SciRotation.from_rotvec([0.3, 1.2, -0.5]).as_matrix()
    shift = np.array([10.0, -3.0, 7.0])
    props = mesh(v @ s.T + shift, f, mass=m)
    np.testing.assert_allclose(props.volume, a * b * c, rtol=1e-13)
    np.testing.assert_allclose(props.mass, m, rtol=1e-13)
    np.testing.assert_allclose(props.density, m / (a * b * c), rtol=1e-13)
    np.testing.assert_allclose(props.center_of_mass, shift, atol=1e-12)
    np.testing.assert_allclose(props.inertia, s @ box(m, a, b, c) @ s.T, atol=1e-12)


def test_single_tetrahedron_centroid():
    """A tetrahedron's centroid is the mean of its vertices; volume |det| / 6."""
    rng = np.random.default_rng(0)
    v = rng.normal(size=(4, 3))
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    if np.linalg.det(v[1:] - v[0]) < 0:
        v[[1, 2]] = v[[2, 1]]
    props = mesh(v, f)
    np.testing.assert_allclose(props.volume, abs(np.linalg.det(v[1:] - v[0])) / 6, rtol=1e-12)
    np.testing.assert_allclose(props.center_of_mass, v.mean(axis=0), atol=1e-12)
    # covariance of a uniform tetrahedron: V/20 (sum d d^T + s s^T), d about the centroid
    d = v - v.mean(axis=0)
    cov = props.volume / 20 * (d.T @ d)
    np.testing.assert_allclose(props.inertia, np.trace(cov) * np.eye(3) - cov, atol=1e-12)


def test_sphere_and_ellipsoid_converge():
    """Inscribed icospheres converge to 2/5 m r^2 (and m (b^2 + c^2)/5) at O(h^2)."""
    errors = []
    for level in (2, 3, 4):
        v, f = icosphere(level)
        props = mesh(1.5 * v, f, mass=2.0)
        err = np.max(np.abs(props.inertia - sphere(2.0, 1.5))) / (0.4 * 2.0 * 1.5**2)
        errors.append(err)
        np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-12)
    assert errors[-1] < 2e-2  # discretisation error 1.44e-3 at level 4; the order check is sharp
    assert errors[0] / errors[1] > 3.5 and errors[1] / errors[2] > 3.5  # second order
    v, f = icosphere(4)
    props = mesh(v * [1.0, 2.0, 3.0], f, density=1.0)
    np.testing.assert_allclose(props.volume, 4 / 3 * np.pi * 6.0, rtol=3e-2)  # 2.2e-3 seen
    np.testing.assert_allclose(
        props.inertia,
        ellipsoid(props.mass, 1.0, 2.0, 3.0),
        rtol=3e-2,
        atol=3e-2 * props.inertia.max(),
    )


def test_cone_mesh_converges_and_center_of_mass():
    """Pyramids over a fine polygon: centre of mass at h/4 above the base (exact for any n)."""
    v, f = cone_mesh(0.7, 2.0, 2000)
    props = mesh(v, f, mass=3.0)
    np.testing.assert_allclose(props.center_of_mass, [0, 0, 0.5], atol=1e-12)
    np.testing.assert_allclose(props.inertia, cone(3.0, 0.7, 2.0), rtol=5e-5, atol=1e-12)


def test_density_mass_and_to_body():
    v, f = box_mesh(1.0, 2.0, 3.0)
    dense = mesh(v, f, density=2.0)
    unit = mesh(v, f)
    assert unit.density == 1.0
    np.testing.assert_allclose(unit.mass, 6.0)
    np.testing.assert_allclose(dense.inertia, 2.0 * unit.inertia)
    body = RigidBody.from_mesh(v + 1.0, f, mass=12.0)
    np.testing.assert_allclose(body.inertia, box(12.0, 1.0, 2.0, 3.0), atol=1e-12)
    np.testing.assert_allclose(body.center_of_mass, [1.0, 1.0, 1.0], atol=1e-12)


def test_convex_hulls_against_qhull():
    """Peer check: volume of random convex polyhedra against SciPy's ConvexHull (Qhull);
    inertia is invariant under translation and rotates as S J S^T."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(11)
    for _ in range(5):
        p = rng.normal(size=(40, 3)) * [1.0, 2.0, 0.5]
        hull = ConvexHull(p)
        f = hull.simplices.copy()
        # orient every face outwards (its normal away from the interior point)
        centre = p[hull.vertices].mean(axis=0)
        a, b, c = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
        inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a - centre) < 0
        f[inward] = f[inward][:, ::-1]
        props = mesh(p, f)
        np.testing.assert_allclose(props.volume, hull.volume, rtol=1e-12)
        s = SciRotation.random(random_state=rng.integers(1 << 30)).as_matrix()
        moved = mesh(p @ s.T + rng.normal(size=3) * 100, f)
        np.testing.assert_allclose(moved.inertia, s @ props.inertia @ s.T, rtol=1e-9, atol=1e-11)


# -- errors --------------------------------------------------------------------------


def test_open_mesh():
    v, f = box_mesh(1.0, 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="closed surface, but edge .* borders only one"):
        mesh(v, f[:-1])


def test_inconsistent_orientation():
    v, f = box_mesh(1.0, 1.0, 1.0)
    f = f.copy()
    f[3] = f[3][::-1]
    with pytest.raises(InvalidInputError, match="consistently oriented .* twice in the same"):
        mesh(v, f)


def test_inward_faces_negative_volume():
    v, f = box_mesh(1.0, 1.0, 1.0)
    with pytest.raises(InvalidInputError, match=r"positive volume .* got volume -1\b.*inwards"):
        mesh(v, f[:, ::-1])


def test_flat_mesh_zero_volume():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(InvalidInputError, match="positive volume"):
        mesh(v, f)


def test_bad_faces_and_vertices():
    v, f = box_mesh(1.0, 1.0, 1.0)
    with pytest.raises(InvalidTypeError, match="`faces` to be an integer array"):
        mesh(v, f.astype(float))
    with pytest.raises(InvalidInputError, match=r"`faces` to have shape \(m, 3\)"):
        mesh(v, f.reshape(-1, 2))
    with pytest.raises(InvalidInputError, match="at least 4 triangles"):
        mesh(v, f[:3])
    with pytest.raises(InvalidInputError, match=r"indices in \[0, 8\)"):
        mesh(v, f + 1)
    bad = f.copy()
    bad[0] = [0, 0, 1]
    with pytest.raises(InvalidInputError, match="three distinct vertices, face 0"):
        mesh(v, bad)
    with pytest.raises(InvalidInputError, match=r"`vertices` to have shape \(\.\.\., 3\)"):
        mesh(v[:, :2], f)
    with pytest.raises(InvalidInputError, match=r"`vertices` to have shape \(n, 3\)"):
        mesh(v[None], f)
    with pytest.raises(InvalidInputError, match="at most one of `mass` and `density`"):
        mesh(v, f, mass=1.0, density=1.0)
    with pytest.raises(InvalidInputError, match="`mass` to be a scalar"):
        mesh(v, f, mass=[1.0, 2.0])
    with pytest.raises(InvalidInputError, match="`density` to be positive"):
        mesh(v, f, density=0.0)
