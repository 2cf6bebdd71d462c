"""Benchmark of poinsot.mass: batched principal axes, rotation of tensors, mesh integrals.

Peers measured in the same process: NumPy ``eigh`` + SciPy ``Rotation.from_matrix``
(the obvious hand-written pipeline) for principal axes, plain ``einsum`` for the
change of axes, and a per-face Python loop for the mesh integrals. Prints the
median of several runs and the ratio (peer time / poinsot time; > 1 = poinsot faster).

Run: ``.venv/bin/python benchmarks/bench_mass.py``
"""

from __future__ import annotations

import numpy as np
from _timing import median_time
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import Rotation
from poinsot.mass import mesh, points, principal_axes, rotate_inertia


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
        for a, b, c in f:
            m = []
            for i, j in ((a, b), (b, c), (c, a)):
                key = (min(i, j), max(i, j))
                if key not in cache:
                    p = v[i] + v[j]
                    v.append(p / np.linalg.norm(p))
                    cache[key] = len(v) - 1
                m.append(cache[key])
            ab, bc, ca = m
            new_f += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = new_f
    return np.array(v), np.array(f)


def mesh_loop(v, f):
    """Per-face Python loop of the same signed-tetrahedron sums (the naive peer)."""
    vol = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    for a, b, c in v[f]:
        d = a @ np.cross(b, c) / 6.0
        s = a + b + c
        vol += d
        first += d * s / 4.0
        second += d / 20.0 * (np.outer(a, a) + np.outer(b, b) + np.outer(c, c) + np.outer(s, s))
    com = first / vol
    pc = second - vol * np.outer(com, com)
    return vol, com, np.trace(pc) * np.eye(3) - pc


def main():
    rng = np.random.default_rng(0)
    rows = []

    n = 100_000
    j = points(rng.uniform(0.1, 1.0, (n, 5)), rng.normal(size=(n, 5, 3)))
    t_ours = median_time(lambda: principal_axes(j))

    def peer():
        w, v = np.linalg.eigh(j)
        v[..., :, 2] *= np.sign(np.linalg.det(v))[..., None]
        return w, SciRotation.from_matrix(v)

    rows.append((f"principal_axes, {n:,} tensors", t_ours, median_time(peer)))

    s = Rotation.random((n,), rng=1)
    sm = s.as_matrix()
    t_ours = median_time(lambda: rotate_inertia(j, s))
    t_peer = median_time(lambda: np.einsum("...ji,...jk,...kl->...il", sm, j, sm))
    rows.append((f"rotate_inertia, {n:,} tensors", t_ours, t_peer))

    v, f = icosphere(6)
    t_ours = median_time(lambda: mesh(v, f))
    t_peer = median_time(lambda: mesh_loop(v, f), repeat=1)
    rows.append((f"mesh, {len(f):,} faces", t_ours, t_peer))

    print(f"{'case':<34}{'poinsot [ms]':>14}{'peer [ms]':>12}{'ratio':>9}")
    for name, ours, peer_t in rows:
        print(f"{name:<34}{1e3 * ours:>14.2f}{1e3 * peer_t:>12.2f}{peer_t / ours:>9.2f}")
    props = mesh(v, f, mass=1.0)
    err = abs(props.inertia[0, 0] / 0.4 - 1.0)
    print(f"\nicosphere level 6 ({len(f):,} faces): relative error vs 2/5 m r^2 = {err:.2e}")


if __name__ == "__main__":
    main()
