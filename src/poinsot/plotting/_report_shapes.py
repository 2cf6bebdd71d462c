"""Triangle meshes of the solids drawn by the HTML report (body axes, metres).

Each solid is centred on its centre of mass, in the canonical axes of
:mod:`poinsot.mass.solids` (axisymmetric solids along ``z``; a disc and a ring in
the ``x``-``y`` plane; a rod along ``z``). :func:`part_mesh` places one at its
centre of mass and turns it to the axes of its inertia tensor.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

#: Solids the report draws, with the meaning of their ``dims`` (m).
SOLIDS = {
    "box": "full edge lengths (a, b, c) along x, y, z",
    "ellipsoid": "semi-axes (a, b, c) along x, y, z",
    "sphere": "radius (r,)",
    "cylinder": "radius and height (r, h), axis along z",
    "cone": "base radius and height (r, h), axis along z, base at z = -h/4",
    "disc": "radius (r,), in the x-y plane",
    "ring": "radius (r,), in the x-y plane",
    "rod": "length (l,), along z",
}
NDIMS = {
    "box": 3,
    "ellipsoid": 3,
    "sphere": 1,
    "cylinder": 2,
    "cone": 2,
    "disc": 1,
    "ring": 1,
    "rod": 1,
}


def sphere_grid(n_lat: int = 11, n_lon: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Unit-sphere vertices and triangles (latitude-longitude grid)."""
    th = np.linspace(0.0, np.pi, n_lat)
    ph = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False)
    th, ph = np.meshgrid(th, ph, indexing="ij")
    v = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1)
    tri = []
    for a in range(n_lat - 1):
        for b in range(n_lon):
            p, q = a * n_lon + b, a * n_lon + (b + 1) % n_lon
            tri += [(p, q, p + n_lon), (q, q + n_lon, p + n_lon)]
    return v.reshape(-1, 3), np.array(tri)


def box(a: float, b: float, c: float) -> tuple[np.ndarray, np.ndarray]:
    s = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    v = 0.5 * s * [a, b, c]
    tri = np.array(
        [
            (0, 1, 3),
            (0, 3, 2),
            (4, 6, 7),
            (4, 7, 5),  # x = -a/2, +a/2
            (0, 4, 5),
            (0, 5, 1),
            (2, 3, 7),
            (2, 7, 6),  # y
            (0, 2, 6),
            (0, 6, 4),
            (1, 5, 7),
            (1, 7, 3),  # z
        ]
    )
    return v, tri


def frustum(
    r0: float, r1: float, z0: float, z1: float, n: int = 28
) -> tuple[np.ndarray, np.ndarray]:
    """A closed cylinder (``r0 == r1``) or cone (``r1 == 0``) along ``z``."""
    ph = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    c, s = np.cos(ph), np.sin(ph)
    v = np.concatenate(
        [
            np.column_stack([r0 * c, r0 * s, np.full(n, z0)]),
            np.column_stack([r1 * c, r1 * s, np.full(n, z1)]),
            [[0.0, 0.0, z0], [0.0, 0.0, z1]],
        ]
    )
    tri = []
    for k in range(n):
        k1 = (k + 1) % n
        tri += [(k, k1, n + k), (k1, n + k1, n + k), (2 * n, k1, k), (2 * n + 1, n + k, n + k1)]
    return v, np.array(tri)


def torus(big: float, small: float, n: int = 28, m: int = 8) -> tuple[np.ndarray, np.ndarray]:
    u = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    w = np.linspace(0.0, 2.0 * np.pi, m, endpoint=False)
    U, W = np.meshgrid(u, w, indexing="ij")
    rr = big + small * np.cos(W)
    v = np.stack([rr * np.cos(U), rr * np.sin(U), small * np.sin(W)], -1).reshape(-1, 3)
    tri = []
    for a in range(n):
        for b in range(m):
            p, q = a * m + b, a * m + (b + 1) % m
            p2, q2 = ((a + 1) % n) * m + b, ((a + 1) % n) * m + (b + 1) % m
            tri += [(p, q, p2), (q, q2, p2)]
    return v, np.array(tri)


def solid_mesh(kind: str, dims: Iterable[float]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (centred on the solid's centre of mass) and triangles of a solid."""
    d = [float(x) for x in dims]
    if kind == "box":
        return box(*d)
    if kind in ("sphere", "ellipsoid"):
        v, tri = sphere_grid()
        return v * (d if kind == "ellipsoid" else d[0]), tri
    if kind == "cylinder":
        return frustum(d[0], d[0], -d[1] / 2, d[1] / 2)
    if kind == "cone":  # centre of mass at h/4 above the base
        return frustum(d[0], 0.0, -d[1] / 4, 3 * d[1] / 4)
    if kind == "disc":
        return frustum(d[0], d[0], -d[0] / 40, d[0] / 40)
    if kind == "ring":
        return torus(d[0], d[0] / 25)
    if kind == "rod":
        return frustum(d[0] / 60, d[0] / 60, -d[0] / 2, d[0] / 2, n=12)
    raise ValueError(kind)  # pragma: no cover - checked by the caller


def axes_from_inertia(canonical: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """A proper rotation ``R`` with ``R J_c R^T = J`` (principal axes matched in order).

    Equal moments leave ``R`` free in their plane, where the canonical solids are
    symmetric, so the drawing does not depend on that choice.
    """
    _, s_c = np.linalg.eigh(canonical)
    _, s_p = np.linalg.eigh(inertia)
    r = s_p @ s_c.T
    if np.linalg.det(r) < 0:
        s_p[:, 0] = -s_p[:, 0]
        r = s_p @ s_c.T
    return r


def equivalent_ellipsoid(mass: float, inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Semi-axes (m) and axes (columns) of the uniform ellipsoid of the same mass and
    inertia about its centre: ``A = m (b^2 + c^2) / 5`` and cyclically, so
    ``a^2 = 5 (B + C - A) / (2 m)`` (flat bodies get a small thickness)."""
    lam, s = np.linalg.eigh(np.asarray(inertia, dtype=float))
    a2 = 5.0 * (lam.sum() - 2.0 * lam) / (2.0 * mass)
    a2 = np.maximum(a2, 1e-4 * a2.max())
    return np.sqrt(a2), s


def decimate(
    vertices: np.ndarray, faces: np.ndarray, max_faces: int = 3000
) -> tuple[np.ndarray, np.ndarray]:
    """A mesh cut to at most ``max_faces`` triangles by vertex clustering.

    Vertices are merged per cell of a cubic grid over the bounding box (each
    cluster replaced by its mean), triangles that collapse are dropped and
    duplicates removed; the grid is coarsened until the count fits. A mesh with
    few enough faces is returned unchanged. Returns ``(vertices, faces)``.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) <= max_faces:
        return v, f
    lo = v.min(axis=0)
    span = float(np.max(v.max(axis=0) - lo)) or 1.0
    cells = 2.0 * np.sqrt(max_faces)  # a closed surface of g^2 cells has ~4 g^2 triangles
    while True:
        key = np.floor((v - lo) / (span / cells)).astype(np.int64)
        _, cluster, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        cluster = cluster.reshape(-1)
        centre = np.zeros((counts.size, 3))
        np.add.at(centre, cluster, v)
        centre /= counts[:, None]
        g = cluster[f]
        keep = (g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 0] != g[:, 2])
        g = g[keep]
        _, first = np.unique(np.sort(g, axis=1), axis=0, return_index=True)
        g = g[np.sort(first)]
        if len(g) <= max_faces or cells < 2:
            used, g = np.unique(g, return_inverse=True)
            return centre[used], g.reshape(-1, 3)
        cells *= 0.8
