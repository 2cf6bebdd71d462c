"""Mass properties of a uniform solid bounded by a closed triangle mesh (theory §8).

The volume integrals ``int dV``, ``int r dV`` and ``int r r^T dV`` are sums over
signed tetrahedra, each spanned by one face and a common apex (the divergence
theorem); they are exact for the polyhedron the mesh bounds. :func:`read_mesh`
reads the vertices and triangles of a Wavefront OBJ or STL file.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._typing import ArrayLike, FloatArray, IntArray
from .._validate import as_int, as_positive, as_trailing, read_regular_file
from ..errors import InvalidInputError, InvalidTypeError

__all__ = ["MeshProperties", "mesh", "read_mesh"]


@dataclass(frozen=True, eq=False)
class MeshProperties:
    """Mass properties of a uniform closed mesh, as returned by :func:`mesh`.

    Attributes
    ----------
    mass : float
        Total mass.
    volume : float
        Enclosed volume (> 0).
    density : float
        Mass per unit volume.
    center_of_mass : ndarray, shape (3,)
        Centre of mass (the centroid), in the mesh's coordinates.
    inertia : ndarray, shape (3, 3)
        Inertia tensor about the centre of mass, in the mesh's axes.

    Notes
    -----
    A :class:`~poinsot.mass.RigidBody` is made from a mesh in one way,
    :meth:`RigidBody.from_mesh` (this module does not know about bodies).
    """

    mass: float
    volume: float
    density: float
    center_of_mass: np.ndarray
    inertia: np.ndarray


def _as_faces(faces: ArrayLike, n_vertices: int) -> np.ndarray:
    try:
        f = np.asarray(faces)
    except (TypeError, ValueError):
        raise InvalidTypeError(
            "Expected `faces` to be an integer array of vertex indices of shape (m, 3), "
            "got a ragged sequence."
        ) from None
    if f.dtype == object or not np.issubdtype(f.dtype, np.integer):
        raise InvalidTypeError(
            f"Expected `faces` to be an integer array of vertex indices, got dtype {f.dtype}."
        )
    if f.ndim != 2 or f.shape[1] != 3:
        raise InvalidInputError(f"Expected `faces` to have shape (m, 3), got {f.shape}.")
    if f.shape[0] < 4:
        raise InvalidInputError(
            f"Expected `faces` to describe a closed surface (at least 4 triangles), "
            f"got {f.shape[0]}."
        )
    if f.min() < 0 or f.max() >= n_vertices:
        raise InvalidInputError(
            f"Expected `faces` to hold indices in [0, {n_vertices}), "
            f"got values in [{f.min()}, {f.max()}]."
        )
    f = f.astype(np.int64)
    deg = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
    if np.any(deg):
        k = int(np.argmax(deg))
        raise InvalidInputError(
            f"Expected `faces` to be triangles with three distinct vertices, "
            f"face {k} is {f[k].tolist()}."
        )
    return f


def _check_closed(f: np.ndarray, n: int) -> None:
    """Each directed edge once, and its reverse present: closed and consistently oriented."""
    tail = f.ravel()
    head = np.roll(f, -1, axis=1).ravel()
    keys = np.sort(tail * n + head)
    dup = keys[1:] == keys[:-1]
    if np.any(dup):
        k = int(keys[np.argmax(dup)])
        raise InvalidInputError(
            "Expected `faces` to be consistently oriented (each edge traversed once in each "
            f"direction), but edge ({k // n}, {k % n}) is traversed twice in the same direction."
        )
    rev = head * n + tail
    idx = np.minimum(np.searchsorted(keys, rev), keys.size - 1)
    missing = keys[idx] != rev
    if np.any(missing):
        k = int(np.argmax(missing))
        raise InvalidInputError(
            "Expected `faces` to form a closed surface, but edge "
            f"({tail[k]}, {head[k]}) borders only one face (the mesh has a hole)."
        )


def _scalar_positive(x: ArrayLike, name: str) -> float:
    a = as_positive(x, name)
    if a.ndim != 0:
        raise InvalidInputError(f"Expected `{name}` to be a scalar, got shape {a.shape}.")
    return float(a)


def mesh(
    vertices: ArrayLike,
    faces: ArrayLike,
    *,
    mass: ArrayLike | None = None,
    density: ArrayLike | None = None,
) -> MeshProperties:
    """Mass, centre of mass and inertia of a uniform solid bounded by a triangle mesh.

    With the tetrahedra ``(O', v0, v1, v2)`` over the faces (``O'`` the mean vertex)
    and signed volumes ``V_f = v0 . (v1 x v2) / 6``, the divergence theorem gives
    ``V = sum V_f``, ``int r dV = sum V_f s_f / 4`` and
    ``int r r^T dV = sum V_f (v0 v0^T + v1 v1^T + v2 v2^T + s_f s_f^T) / 20`` with
    ``s_f = v0 + v1 + v2``; then ``J_C = rho (tr(P) E - P)`` with
    ``P = int (r - r_c)(r - r_c)^T dV`` (theory §8).

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        Vertex coordinates.
    faces : array_like of int, shape (m, 3)
        Vertex indices of each triangle, counter-clockwise seen from outside
        (outward normals by the right-hand rule). The surface must be closed and
        consistently oriented: every edge is shared by faces that traverse it in
        opposite directions.
    mass, density : float, optional
        Give at most one (> 0). Default: ``density = 1`` (so ``mass = volume``).

    Returns
    -------
    MeshProperties
        ``mass``, ``volume``, ``density``, ``center_of_mass`` and ``inertia``
        (about the centre of mass).

    Raises
    ------
    InvalidInputError
        Open mesh (an edge borders one face), inconsistent orientation (an edge
        traversed twice the same way), degenerate or out-of-range faces, or a
        non-positive volume (faces oriented inwards: reverse each triangle).
    InvalidTypeError
        Non-integer ``faces``.

    Notes
    -----
    Exact for the polyhedron (up to round-off); a triangulated curved surface
    converges to the smooth solid as the mesh is refined (error ~ h^2).

    **Convention:** the result is in the coordinates of ``vertices``; consistent
    units (``density`` in mass per length^3).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.mass import mesh
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    >>> props = mesh(v, f, mass=1.0)
    >>> round(props.volume, 12), props.center_of_mass
    (0.166667, array([0.25, 0.25, 0.25]))
    """
    v = as_trailing(vertices, "vertices", (3,))
    if v.ndim != 2:
        raise InvalidInputError(f"Expected `vertices` to have shape (n, 3), got {v.shape}.")
    n = v.shape[0]
    f = _as_faces(faces, n)
    if mass is not None and density is not None:
        raise InvalidInputError("Give at most one of `mass` and `density`, got both.")
    _check_closed(f, n)

    origin = v.mean(axis=0)
    p = v - origin
    a, b, c = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
    vol6 = np.einsum("ij,ij->i", a, np.cross(b, c))
    volume = vol6.sum() / 6.0
    scale = np.max(np.abs(p)) ** 3
    if not volume > 1e-12 * scale:
        raise InvalidInputError(
            f"Expected `faces` to enclose a positive volume with outward normals, got volume "
            f"{volume:.6g}; if it is negative, the faces are oriented inwards (reverse them)."
        )
    s = a + b + c
    com = (vol6 @ s) / (24.0 * volume)
    second = np.einsum("i,ij,ik->jk", vol6, a, a)
    second += np.einsum("i,ij,ik->jk", vol6, b, b)
    second += np.einsum("i,ij,ik->jk", vol6, c, c)
    second += np.einsum("i,ij,ik->jk", vol6, s, s)
    second /= 120.0
    pc = second - volume * np.outer(com, com)
    pc = 0.5 * (pc + pc.T)
    if mass is not None:
        rho = _scalar_positive(mass, "mass") / volume
    elif density is not None:
        rho = _scalar_positive(density, "density")
    else:
        rho = 1.0
    inertia = rho * (np.trace(pc) * np.eye(3) - pc)
    return MeshProperties(
        mass=rho * volume,
        volume=float(volume),
        density=rho,
        center_of_mass=origin + com,
        inertia=inertia,
    )


# ------------------------------------------------------------------------------ reading
#: Largest mesh file :func:`read_mesh` reads by default (bytes): 256 MiB, a binary STL
#: of 5 million triangles.
MAX_MESH_BYTES = 256 * 2**20


def read_mesh(
    path: str | os.PathLike[str], *, max_bytes: int = MAX_MESH_BYTES
) -> tuple[FloatArray, IntArray]:
    """Vertices and triangles of a Wavefront OBJ or an STL (ASCII or binary) file.

    OBJ (``.obj``): ``v x y z`` lines are vertices and ``f i j k ...`` lines
    faces (1-based indices, ``i/t/n``, ``i//n`` and negative, i.e. relative, forms
    accepted); a polygon ``f a b c d ...`` is split into the fan ``(a, b, c)``,
    ``(a, c, d)``, ... Other lines (``vt``, ``vn``, ``o``, ``g``, ``usemtl``, ...)
    are passed over. STL (``.stl``): binary when the file
    size is ``84 + 50 n`` for the ``n`` triangles its header announces, else ASCII
    (``solid ... facet ... vertex x y z ... endsolid``); the facet normals are
    not used and equal vertices are merged so that triangles share edges.
    Triangles with a repeated vertex (zero area) are dropped.

    Parameters
    ----------
    path : str or path-like
        The file: ``.obj`` (OBJ) or ``.stl`` (STL), any case; another suffix is
        refused before the file is opened (a ``.ply`` is not an STL). Only a regular
        file is read (a FIFO or a device is refused without blocking).
    max_bytes : int, optional
        Largest file size read (bytes), default :data:`MAX_MESH_BYTES` (256 MiB): a
        larger file is refused before it is read.

    Returns
    -------
    vertices : ndarray, shape (n, 3)
        Vertex coordinates, in the file's units (poinsot's scenarios take metres).
    faces : ndarray of int64, shape (m, 3)
        0-based vertex indices, in the order of the file (counter-clockwise seen
        from outside in both formats, as :func:`mesh` expects).

    Raises
    ------
    InvalidInputError
        Missing or unreadable file, a malformed line (the message names the file
        and line), an index out of range, or a file without any triangle.
    InvalidTypeError
        ``path`` is not a str or path-like.

    Notes
    -----
    The file is only read: whether the triangles bound a closed solid is checked
    by :func:`mesh` (theory §8), which gives its mass properties. NumPy only.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> obj = pathlib.Path(tempfile.mkdtemp()) / "tet.obj"
    >>> _ = obj.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nv 0 0 1\\n"
    ...                    "f 1 3 2\\nf 1 2 4\\nf 1 4 3\\nf 2 3 4\\n")
    >>> v, f = read_mesh(obj)
    >>> v.shape, f.tolist()
    ((4, 3), [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> print(round(mesh(v, f, density=6.0).mass, 12))   # volume 1/6
    1.0
    """
    if not isinstance(path, str | os.PathLike):
        raise InvalidTypeError(
            f"Expected `path` to be a str or os.PathLike, got {type(path).__name__}."
        )
    max_bytes = as_int(max_bytes, "max_bytes", minimum=1)
    p = Path(path)
    if p.suffix.lower() not in (".obj", ".stl"):
        raise InvalidInputError(
            f"{path}: expected a mesh file ending in .obj or .stl, got the suffix "
            f"{p.suffix or '(none)'!r}."
        )
    try:
        raw = read_regular_file(p, max_bytes=max_bytes, what="a mesh file")
    except FileNotFoundError:
        raise InvalidInputError(f"{path}: no such mesh file.") from None
    except IsADirectoryError:
        raise InvalidInputError(f"{path}: is a directory, expected a mesh file.") from None
    except OSError as exc:
        raise InvalidInputError(f"{path}: cannot be read ({exc.strerror}).") from None
    if p.suffix.lower() == ".obj":
        v, f = _read_obj(_text(raw, path), path)
    elif _is_binary_stl(raw):
        v, f = _read_binary_stl(raw)
    else:
        v, f = _read_ascii_stl(_text(raw, path), path)
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
    if f.shape[0] == 0:
        raise InvalidInputError(f"{path}: expected triangles (faces), found none.")
    return v, f


def _text(raw: bytes, path: object) -> str:
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InvalidInputError(f"{path}: not a text mesh file ({exc.reason}).") from None


def _xyz(words: Iterable[str], where: str, what: str, line: str) -> list[float]:
    try:
        xyz = [float(x) for x in words]
    except ValueError:
        xyz = []
    if len(xyz) != 3 or not np.all(np.isfinite(xyz)):
        raise InvalidInputError(
            f"{where}: expected {what} with 3 finite numbers, found {line.strip()!r}."
        )
    return xyz


def _read_obj(text: str, path: object) -> tuple[np.ndarray, np.ndarray]:
    verts: list[list[float]] = []
    faces: list[tuple[int, int, int]] = []
    for no, line in enumerate(text.splitlines(), start=1):
        parts = line.split("#", 1)[0].split()
        if not parts:
            continue
        if parts[0] == "v":  # an optional 4th number (w) is passed over
            verts.append(_xyz(parts[1:4], f"{path}:{no}", "a vertex `v x y z`", line))
        elif parts[0] == "f":
            idx = []
            for item in parts[1:]:
                head = item.split("/", 1)[0]
                try:
                    k = int(head)
                except ValueError:
                    k = 0
                n = len(verts)
                if k == 0 or not -n <= k <= n:
                    raise InvalidInputError(
                        f"{path}:{no}: expected vertex indices in 1..{n} (or -{n}..-1, "
                        f"relative) of the vertices read so far, found {item!r}."
                    )
                idx.append(k - 1 if k > 0 else n + k)
            if len(idx) < 3:
                raise InvalidInputError(
                    f"{path}:{no}: expected a face of at least 3 vertices, found {line.strip()!r}."
                )
            faces.extend((idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1))
    if not verts:
        raise InvalidInputError(f"{path}: expected vertices (`v x y z` lines), found none.")
    return np.array(verts, dtype=float), np.array(faces, dtype=np.int64).reshape(-1, 3)


def _is_binary_stl(raw: bytes) -> bool:
    if len(raw) < 84:
        return False
    n = int.from_bytes(raw[80:84], "little")
    return len(raw) == 84 + 50 * n


_STL_RECORD = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def _merged(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices of the triangles ``corners`` (m, 3, 3), equal ones merged."""
    v, inv = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
    return v, inv.reshape(-1, 3).astype(np.int64)


def _read_binary_stl(raw: bytes) -> tuple[np.ndarray, np.ndarray]:
    rec = np.frombuffer(raw, dtype=_STL_RECORD, offset=84)
    return _merged(rec["v"].astype(float))


def _read_ascii_stl(text: str, path: object) -> tuple[np.ndarray, np.ndarray]:
    corners: list[list[float]] = []
    in_facet = 0
    for no, line in enumerate(text.splitlines(), start=1):
        parts = line.split()
        if not parts:
            continue
        word = parts[0].lower()
        if word == "vertex":
            corners.append(_xyz(parts[1:], f"{path}:{no}", "`vertex x y z`", line))
            in_facet += 1
        elif word == "facet":
            in_facet = 0
        elif word == "endfacet" and in_facet != 3:
            raise InvalidInputError(
                f"{path}:{no}: expected a facet of 3 vertices (triangles), found {in_facet}."
            )
        elif word not in ("solid", "outer", "endloop", "endfacet", "endsolid"):
            raise InvalidInputError(
                f"{path}:{no}: expected an ASCII STL line (solid, facet, outer loop, vertex, "
                f"endloop, endfacet, endsolid) or a binary STL, found {line.strip()[:40]!r}."
            )
    if not corners or len(corners) % 3:
        raise InvalidInputError(
            f"{path}: expected triangles (3 `vertex` lines per facet), found "
            f"{len(corners)} vertices."
        )
    return _merged(np.array(corners, dtype=float).reshape(-1, 3, 3))
