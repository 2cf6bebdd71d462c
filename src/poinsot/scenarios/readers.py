"""Readers of a scenario file's tables: body (solids, meshes, parts), attitude, angular
velocity, torque, angular-velocity profile.

The kinds (:mod:`poinsot.scenarios.kinds`) read their tables with these; the whole
file is read by :mod:`poinsot.scenarios.io`, which also knows the registry of kinds.
Every error names the table and key (:class:`~poinsot.scenarios._toml.Table`).
"""

from __future__ import annotations

import contextvars
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import PoinsotError
from ..mass import RigidBody, check_inertia, combine, mesh, read_mesh, solids
from ..mass.solids import SHAPES
from ..rotations._from_matrix import MATRIX_TOLERANCE, rotation_from_matrix
from ..rotations.euler import parse_sequence
from ..rotations.rotation import Rotation
from ._toml import ScenarioError, Table
from .schema import (
    OMEGA_UNITS,
    STANDARD_GRAVITY,
    TORQUE_MODELS,
    AngularVelocitySpec,
    AttitudeSpec,
    BodySpec,
    OmegaProfileSpec,
    PartSpec,
    TorqueSpec,
)

__all__ = [
    "SHAPES",
    "MATRIX_TOLERANCE",
    "rotation_from_matrix",
    "read_attitude",
    "read_body",
    "read_angular_velocity",
    "read_torque",
    "read_omega_profile",
]


_ATTITUDE_KEYS = ("quat", "matrix", "rotvec", "axis", "euler", "gibbs", "mrp")
_EVERY_ATTITUDE_KEY = (
    *_ATTITUDE_KEYS,
    "scalar_first",
    "degrees",
    "angle",
    "sequence",
    "tolerance",
)


#: Whether the scenario being parsed may read files outside its directory.
_ALLOW_PATHS: contextvars.ContextVar[bool] = contextvars.ContextVar("allow_paths", default=False)


def _wrap(t: Table, key: str | None, exc: Exception) -> ScenarioError:
    msg = str(exc).rstrip(".")
    return t.error(key, f"{msg[:1].lower()}{msg[1:]}.")


def _inertia(t: Table, key: str = "inertia") -> np.ndarray:
    v = t.raw(key)
    if isinstance(v, list) and len(v) == 3 and all(not isinstance(x, list) for x in v):
        moments = t.vector(key, 3, what="3 principal moments [A, B, C] or a 3x3 tensor")
        j = np.diag(moments)
    elif isinstance(v, list) and len(v) == 6 and all(not isinstance(x, list) for x in v):
        jxx, jyy, jzz, jxy, jxz, jyz = t.vector(key, 6)
        j = np.array([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]])
    else:
        j = np.array(
            t.matrix(
                key,
                3,
                3,
                what="3 principal moments [A, B, C], 6 components "
                "[Jxx, Jyy, Jzz, Jxy, Jxz, Jyz] or a 3x3 tensor",
            )
        )

    try:
        check_inertia(j)
    except PoinsotError as exc:
        raise _wrap(t, key, exc) from None
    return j


def _solid(t: Table) -> tuple[str, tuple[float, ...], float, np.ndarray]:
    shape = t.string("shape", choices=(*SHAPES, "mesh"), required=True)
    names = SHAPES[shape]
    dims = t.vector(
        "dims",
        len(names),
        what=f"{len(names)} positive number(s) for a {shape}: [{', '.join(names)}] (m)",
    )
    if any(d <= 0 for d in dims):
        raise t.expected("dims", f"positive dimensions [{', '.join(names)}] (m)", list(dims))
    mass = t.number("mass", positive=True, required=True)

    try:
        j = getattr(solids, shape)(mass, *dims)
    except PoinsotError as exc:
        raise _wrap(t, "dims", exc) from None
    return shape, dims, mass, np.asarray(j, dtype=float)


#: Keys of a ``shape = "mesh"`` body or part (besides ``shape``).
_MESH_KEYS = ("file", "vertices", "faces", "mass", "density")


def _mesh_faces(t: Table) -> np.ndarray:
    v = t.raw("faces")
    ok = (
        isinstance(v, list)
        and v
        and all(
            isinstance(r, list)
            and len(r) == 3
            and all(isinstance(x, int) and not isinstance(x, bool) for x in r)
            for r in v
        )
    )
    if not ok:
        raise t.expected(
            "faces", "an array of triangles [[i, j, k], ...] of 0-based vertex indices", v
        )
    return np.array(v, dtype=np.int64)


def _mesh(t: Table) -> Any:
    """A ``shape = "mesh"`` table: mass (kg), inertia about the mesh's centre of mass
    in the mesh's axes (kg m^2), that centre in the mesh's coordinates (m), and the
    mesh (vertices in m, faces)."""
    t.forbid(["dims"], 'a `shape = "mesh"` has no `dims`: its size is that of its vertices')
    how = t.exclusive(
        ("file", "vertices"),
        what="a mesh file (OBJ or STL, path relative to the scenario file) or inline "
        "`vertices` and `faces`",
    )
    if how == "file":
        t.forbid(["faces"], "the faces of a mesh given by `file` are read from the file")
        name = t.string("file", required=True)  # present: `how` is "file"
        path = Path(name)
        base = Path.cwd() if t.file.startswith("<") else Path(t.file).parent
        if not path.is_absolute():
            path = base / path
        if not _ALLOW_PATHS.get() and not path.resolve().is_relative_to(base.resolve()):
            # refused before it is opened: a scenario from elsewhere reads nothing else
            raise t.error(
                "file",
                f"expected a mesh file inside the scenario's directory ({base}), got "
                f"{name!r}, which is outside it; pass --allow-paths (allow_paths=True) to "
                "read it.",
            )

        try:
            v, f = read_mesh(path)
        except PoinsotError as exc:
            raise _wrap(t, "file", exc) from None
        where = "file"
    else:
        v = np.array(
            t.matrix("vertices", None, 3, what="an array of vertices [[x, y, z], ...] (m)")
        )
        if not t.has("faces"):
            raise t.error(None, "missing key `faces`: expected the triangles [[i, j, k], ...] "
                          "(0-based indices into `vertices`).")  # fmt: skip
        f = _mesh_faces(t)
        where = "faces"
    which = t.exclusive(
        ("mass", "density"), what="the mass (kg) or the density (kg/m^3) of the uniform solid"
    )
    amount = t.number(which, positive=True)

    try:
        props = mesh(v, f, **{which: amount})
    except PoinsotError as exc:
        msg = str(exc).rstrip(".")
        msg = f"{msg[:1].lower()}{msg[1:]}."
        raise t.error(where, f"{path}: {msg}" if where == "file" else msg) from None
    return (
        float(props.mass),
        np.asarray(props.inertia, dtype=float),
        np.asarray(props.center_of_mass, dtype=float),
        np.asarray(v, dtype=float),
        np.asarray(f, dtype=np.int64),
    )


def _part(t: Table, index: int) -> PartSpec:
    keys = ("name", "shape", "dims", "mass", "inertia", "position", "orientation")
    t.known((*keys, *_MESH_KEYS))
    name = t.string("name", f"part {index}")
    position = np.array(t.vector("position", 3, required=False, default=(0.0, 0.0, 0.0)))
    if t.raw("shape") == "mesh":
        return _mesh_part(t, name, position, keys)
    t.forbid(["file", "vertices", "faces", "density"], 'only a `shape = "mesh"` takes it')
    if t.has("shape"):
        t.forbid(
            ["inertia"],
            "a part is either a `shape` with `dims` or a `mass` with an `inertia`, not both",
        )
        shape, dims, mass, j = _solid(t)
    else:
        mass = t.number("mass", positive=True, required=True)
        shape, dims = None, None
        j = _inertia(t) if t.has("inertia") else np.zeros((3, 3))  # a point mass
    c_bp = _part_axes(t)
    if c_bp is not None:  # the part's own axes relative to the body axes
        j = c_bp @ j @ c_bp.T  # J_b = C J_p C^T (docs/theory.md §8)
    t.finish(keys)
    return PartSpec(name=name, mass=mass, inertia=j, position=position, shape=shape, dims=dims)


def _part_axes(t: Table) -> np.ndarray | None:
    """``C_bp`` of a part's ``[orientation]`` (columns: the part's axes in body axes)."""
    orientation = t.table("orientation")
    if orientation is None:
        return None

    return Rotation.from_quat(read_attitude(orientation, t).quat).as_matrix()


def _mesh_part(t: Table, name: str, origin: np.ndarray, keys: Any) -> PartSpec:
    """A mesh part: its vertices ``r_p`` go to ``r_b = position + C_bp r_p`` in body axes."""
    t.forbid(["inertia"], "the inertia of a mesh part follows from its vertices")
    mass, j, com, v, f = _mesh(t)
    c_bp = _part_axes(t)
    if c_bp is not None:
        j = c_bp @ j @ c_bp.T  # J_b = C J_p C^T (docs/theory.md §8)
        com, v = c_bp @ com, v @ c_bp.T
    t.finish((*keys, *_MESH_KEYS))
    return PartSpec(
        name=name,
        mass=mass,
        inertia=j,
        position=origin + com,
        shape="mesh",
        vertices=origin + v,
        faces=f,
    )


def read_body(t: Table) -> BodySpec:
    t.known(("mass", "inertia", "center_of_mass", "shape", "dims", "parts", *_MESH_KEYS))
    if t.raw("shape") != "mesh":
        t.forbid(["file", "vertices", "faces", "density"], 'only a `shape = "mesh"` takes it')
    how = t.exclusive(
        ("inertia", "shape", "parts"),
        what="a body is given by `mass` and "
        "`inertia`, or a `shape` with `dims` and `mass`, or [[body.parts]]",
    )
    if how == "parts":
        t.forbid(
            ["mass", "dims", "center_of_mass"],
            "the mass and centre of mass of a body made of [[body.parts]] follow from its parts",
        )
        parts = tuple(_part(p, i) for i, p in enumerate(t.tables("parts")))

        t.finish(("parts",))
        try:
            whole = combine(*(RigidBody(p.mass, p.inertia, p.position) for p in parts))
            mass, j, com = whole.mass, whole.inertia, whole.center_of_mass
            check_inertia(j)
        except PoinsotError as exc:
            raise _wrap(t, "parts", exc) from None
        return BodySpec(mass=mass, inertia=j, center_of_mass=com, parts=parts)
    if how == "shape" and t.raw("shape") == "mesh":
        t.forbid(
            ["center_of_mass"],
            "the centre of mass of a mesh body follows from its vertices (the mesh's "
            "coordinates are the body axes)",
        )
        mass, j, com, v, f = _mesh(t)
        t.finish(("shape", *_MESH_KEYS))
        return BodySpec(mass=mass, inertia=j, center_of_mass=com, shape="mesh", vertices=v, faces=f)
    com = np.array(t.vector("center_of_mass", 3, required=False, default=(0.0, 0.0, 0.0)))
    if how == "shape":
        shape, dims, mass, j = _solid(t)

        try:
            check_inertia(j)
        except PoinsotError as exc:  # a thin rod alone has a zero moment
            raise _wrap(t, "shape", exc) from None
        t.finish(("shape", "dims", "mass", "center_of_mass"))
        return BodySpec(mass=mass, inertia=j, center_of_mass=com, shape=shape, dims=dims)
    mass = t.number("mass", positive=True, required=True)
    j = _inertia(t)
    t.finish(("mass", "inertia", "center_of_mass"))
    return BodySpec(mass=mass, inertia=j, center_of_mass=com)


def _degrees(t: Table, what: str) -> bool:
    return t.boolean("degrees", required=True, why=f" (true: {what} in degrees; false: in radians)")


def read_attitude(t: Table | None, top: Table) -> AttitudeSpec:
    if t is None:
        return AttitudeSpec("identity", (), np.array([1.0, 0.0, 0.0, 0.0]))
    t.known(_EVERY_ATTITUDE_KEY)
    rep = t.exclusive(_ATTITUDE_KEYS, what="the initial attitude (body -> space)")
    seq = deg = sf = None
    values: tuple[Any, ...]  # numbers, or the rows of a matrix
    try:
        if rep == "quat":
            values = t.vector("quat", 4)
            sf = t.boolean(
                "scalar_first", required=True, why=" (true: [w, x, y, z]; false: [x, y, z, w])"
            )
            if not any(values):
                raise t.expected("quat", "a non-zero quaternion", list(values))
            r = Rotation.from_quat(values, scalar_first=sf)
        elif rep == "matrix":
            values = t.matrix("matrix", 3, 3)
            tol = t.number("tolerance", MATRIX_TOLERANCE, positive=True)
            r = rotation_from_matrix(values, tol, where=f"{t.file}: `{t.key_path('matrix')}`")
        elif rep == "rotvec":
            values = t.vector("rotvec", 3)
            deg = _degrees(t, "its length")
            r = Rotation.from_rotvec(values, degrees=deg)
        elif rep == "axis":
            values = t.vector("axis", 3)
            if not any(values):
                raise t.expected("axis", "a non-zero axis", list(values))
            angle = t.number("angle", required=True)
            deg = _degrees(t, "angle")
            values = (*values, angle)
            r = Rotation.from_axis_angle(values[:3], angle, degrees=deg)
        elif rep == "euler":
            values = t.vector("euler", 3)
            seq = t.string("sequence", required=True)
            deg = _degrees(t, "angles")
            try:
                parse_sequence(seq)
            except PoinsotError as exc:
                raise _wrap(t, "sequence", exc) from None
            r = Rotation.from_euler(seq, values, degrees=deg)
        elif rep == "gibbs":
            values = t.vector("gibbs", 3)
            r = Rotation.from_gibbs(values)
        else:
            values = t.vector("mrp", 3)
            r = Rotation.from_mrp(values)
    except ScenarioError:
        raise
    except PoinsotError as exc:
        raise _wrap(t, rep, exc) from None
    allowed = {
        "quat": ("quat", "scalar_first"),
        "matrix": ("matrix", "tolerance"),
        "rotvec": ("rotvec", "degrees"),
        "axis": ("axis", "angle", "degrees"),
        "euler": ("euler", "sequence", "degrees"),
        "gibbs": ("gibbs",),
        "mrp": ("mrp",),
    }[rep]
    _finish_rep(t, rep, allowed)
    return AttitudeSpec(rep, values, r.as_quat(), sequence=seq, degrees=deg, scalar_first=sf)


def _finish_rep(t: Table, rep: str, allowed: Any) -> None:
    every = _EVERY_ATTITUDE_KEY
    for key in t.data:
        if key in every and key not in allowed:
            raise t.error(
                key,
                f"not used by an attitude given as `{rep}` (it takes "
                + ", ".join(f"`{k}`" for k in allowed)
                + ").",
            )
    t.finish(every)


def _units(t: Table, key: str = "units") -> float:
    units = t.string(key, "rad/s", choices=tuple(OMEGA_UNITS))
    return OMEGA_UNITS[units]


def read_angular_velocity(t: Table, attitude: AttitudeSpec) -> AngularVelocitySpec:
    t.known(("vector", "frame", "units"))
    vector = t.vector("vector", 3)
    frame = t.string("frame", choices=("body", "space"), required=True)
    units = t.string("units", "rad/s", choices=tuple(OMEGA_UNITS))
    t.finish(("vector", "frame", "units"))
    w = np.array(vector) * OMEGA_UNITS[units]
    if frame == "space":
        w = attitude.rotation.apply(w, inverse=True)
    return AngularVelocitySpec(vector=vector, frame=frame, units=units, omega_body=w)


def read_torque(t: Table | None) -> TorqueSpec:
    if t is None:
        return TorqueSpec()
    t.known(("model", "vector", "g"))
    model = t.string("model", choices=TORQUE_MODELS, required=True)
    if model in ("body", "space"):
        vec = np.array(t.vector("vector", 3))
        t.finish(("model", "vector"))
        return TorqueSpec(model, vector=vec)
    if model == "gravity":
        g = t.number("g", STANDARD_GRAVITY, positive=True)
        t.finish(("model", "g"))
        return TorqueSpec(model, g=g)
    t.forbid(["vector", "g"], 'the torque model "none" takes no parameters')
    t.finish(("model",))
    return TorqueSpec()


def read_omega_profile(t: Table) -> OmegaProfileSpec:
    t.known(("kind", "frame", "vector", "units", "half_angle", "degrees", "rate", "t", "omega"))
    kind = t.string("kind", choices=("constant", "coning", "samples"), required=True)
    frame = t.string("frame", choices=("body", "space"), required=True)
    if kind == "constant":
        scale = _units(t)
        vec = np.array(t.vector("vector", 3)) * scale
        t.finish(("kind", "frame", "vector", "units"))
        return OmegaProfileSpec(kind, frame, vector=vec)
    if kind == "coning":
        if frame != "body":
            raise t.error(
                "frame",
                f'coning motion is defined by its body rates: expected "body", found {frame!r}.',
            )
        half = t.number("half_angle", required=True, positive=True)
        deg = _degrees(t, "half_angle")
        half = np.radians(half) if deg else half
        if not half < np.pi / 2:
            raise t.expected("half_angle", "an angle in (0, 90) degrees", t.data["half_angle"])
        rate = t.number("rate", required=True) * _units(t)
        t.finish(("kind", "frame", "half_angle", "degrees", "rate", "units"))
        return OmegaProfileSpec(kind, frame, half_angle=float(half), rate=float(rate))
    times = np.array(t.vector("t", None, what="an array of sample times (s)"))
    if times.size < 2 or np.any(np.diff(times) <= 0):
        raise t.expected("t", "at least 2 strictly increasing times (s)", t.data["t"])
    if times[0] > 0.0:
        raise t.error(
            "t",
            f"expected the table to start at or before t = 0 (the start of the "
            f"simulation), found {times[0]:g} s.",
        )
    omega = np.array(t.matrix("omega", None, 3)) * _units(t)
    if omega.shape[0] != times.size:
        raise t.error(
            "omega",
            f"expected one row per time in `t` ({times.size} rows), found {omega.shape[0]}.",
        )
    t.finish(("kind", "frame", "t", "omega", "units"))
    return OmegaProfileSpec(kind, frame, t=times, omega=omega)
