"""Reading scenario files (TOML, with :mod:`tomllib`) into :class:`~.schema.Scenario`.

Every error is a :class:`ScenarioError` (an :class:`~poinsot.InvalidInputError`)
whose message names the file, the key (``body.parts[1].dims``), the line where it
is written, what was expected and what was found. Unknown keys are errors, with
the closest valid key suggested. The format is documented in ``docs/cli.md``.
"""

from __future__ import annotations

import copy
import os
import re
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import InvalidTypeError, PoinsotError
from ._toml import ScenarioError, Table, locate_keys
from .schema import (
    DYNAMICS_METHODS,
    KINEMATICS_METHODS,
    OMEGA_UNITS,
    STANDARD_GRAVITY,
    TORQUE_MODELS,
    AngularVelocitySpec,
    AttitudeSpec,
    BodySpec,
    OmegaProfileSpec,
    PartSpec,
    Scenario,
    SimulationSpec,
    TorqueSpec,
)

__all__ = ["load_scenario", "parse_scenario", "demo_scenario_text", "ScenarioError", "SHAPES"]

#: Solids accepted by ``shape =`` and the meaning of their ``dims`` (m), in order.
#: Axisymmetric solids have their axis along body ``z``; a rod lies along ``z``.
SHAPES: dict[str, tuple[str, ...]] = {
    "box": ("length along x", "width along y", "height along z"),
    "sphere": ("radius",),
    "cylinder": ("radius", "height"),
    "cone": ("base radius", "height"),
    "ellipsoid": ("semi-axis a along x", "semi-axis b along y", "semi-axis c along z"),
    "rod": ("length",),
    "disc": ("radius",),
    "ring": ("radius",),
}

_TOP_KEYS = (
    "name",
    "description",
    "body",
    "attitude",
    "angular_velocity",
    "torque",
    "omega_profile",
    "simulation",
)
_ATTITUDE_KEYS = ("quat", "matrix", "rotvec", "axis", "euler", "gibbs", "mrp")
_EVERY_ATTITUDE_KEY = (*_ATTITUDE_KEYS, "scalar_first", "degrees", "angle", "sequence")


def demo_scenario_text() -> str:
    """The embedded demo scenario (the tennis-racket flip), as TOML text."""
    return resources.files("poinsot.scenarios").joinpath("tennis_racket.toml").read_text("utf-8")


def load_scenario(path) -> Scenario:
    """Read and validate a scenario file.

    Parameters
    ----------
    path : str or path-like
        A TOML scenario file (format: ``docs/cli.md``).

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        The file is missing, not valid TOML, or does not describe a valid scenario;
        the message names the file, the key and its line.

    Notes
    -----
    **Convention:** SI units; attitude body -> space; quaternions scalar first.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "spin.toml").write_text('''
    ... [body]
    ... mass = 1.0
    ... inertia = [1.0, 2.0, 3.0]
    ... [angular_velocity]
    ... vector = [0.0, 0.0, 1.0]
    ... frame = "body"
    ... [simulation]
    ... duration = 1.0
    ... samples = 11
    ... method = "exact"
    ... ''')
    >>> s = load_scenario(d / "spin.toml")
    >>> s.name, s.kind, s.simulation.times().size
    ('spin', 'dynamics', 11)
    """
    if not isinstance(path, str | os.PathLike):
        raise InvalidTypeError(
            f"Expected `path` to be a str or os.PathLike, got {type(path).__name__}."
        )
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ScenarioError("no such file.", file=str(path)) from None
    except IsADirectoryError:
        raise ScenarioError(
            "is a directory, expected a TOML scenario file.", file=str(path)
        ) from None
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"not UTF-8 text ({exc.reason}).", file=str(path)) from None
    except OSError as exc:
        raise ScenarioError(f"cannot be read ({exc.strerror}).", file=str(path)) from None
    return parse_scenario(text, source=str(path), name=p.stem)


_TOML_LINE = re.compile(r"\(at line (\d+), column (\d+)\)")


def parse_scenario(text: str, *, source: str = "<string>", name: str | None = None) -> Scenario:
    """Parse and validate scenario TOML ``text`` (``source`` names it in errors).

    Examples
    --------
    >>> s = parse_scenario('''
    ... [omega_profile]
    ... kind = "constant"
    ... vector = [0.0, 0.0, 90.0]
    ... units = "deg/s"
    ... frame = "body"
    ... [simulation]
    ... duration = 2.0
    ... step = 0.5
    ... method = "exact"
    ... ''', name="turn")
    >>> s.kind, s.simulation.times().tolist()
    ('kinematics', [0.0, 0.5, 1.0, 1.5, 2.0])
    >>> parse_scenario("[simulaton]\\nduration = 1.0")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    poinsot.scenarios._toml.ScenarioError: <string>:1: `simulaton` unknown key. \
Did you mean `simulation`? ...
    """
    if not isinstance(text, str):
        raise InvalidTypeError(
            f"Expected `text` to be a str (TOML), got {type(text).__name__}; "
            "decode bytes first or use load_scenario(path)."
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        msg = str(exc)
        m = _TOML_LINE.search(msg)
        line = int(m.group(1)) if m else None
        msg = _TOML_LINE.sub("", msg).strip().rstrip(".")
        raise ScenarioError(
            f"invalid TOML: {msg} (column {m.group(2)})." if m else f"invalid TOML: {msg}.",
            file=source,
            line=line,
        ) from None
    lines = locate_keys(text)
    top = Table(data, "", source, lines)
    return _scenario(top, data, source, name or "scenario")


# ------------------------------------------------------------------------------------------
def _scenario(top: Table, data: dict, source: str, default_name: str) -> Scenario:
    top.known(_TOP_KEYS)
    name = top.string("name", default_name)
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]*", name):
        raise top.expected(
            "name",
            "a name made of letters, digits, '.', '_', '-' (it names the output directory)",
            name,
        )
    description = top.string("description", "")
    # tables are read in the order they usually appear, so the first error reported is
    # the first one in the file
    profile_t = top.table("omega_profile")
    body_t = top.table("body", required=profile_t is None)
    body = _body(body_t) if body_t is not None else None
    attitude = _attitude(top.table("attitude"), top)
    if profile_t is not None:
        top.forbid(
            ["angular_velocity"],
            "a scenario with [omega_profile] takes its angular "
            "velocity from the profile (remove [angular_velocity])",
        )
        top.forbid(
            ["torque"],
            "[omega_profile] scenarios propagate the attitude only (no dynamics, no torque)",
        )
        profile = _omega_profile(profile_t)
        angular_velocity = None
        torque = TorqueSpec()
    else:
        profile = None
        angular_velocity = _angular_velocity(top.table("angular_velocity", required=True), attitude)
        torque = _torque(top.table("torque"))
    simulation = _simulation(top.table("simulation", required=True), profile, torque)
    top.finish(_TOP_KEYS)
    if torque.model == "gravity" and not np.any(body.center_of_mass):
        raise top.error(
            "body.center_of_mass",
            "gravity about a fixed point needs the centre "
            "of mass away from the fixed point (the origin of the body axes), "
            "found [0, 0, 0]: add `center_of_mass = [x, y, z]` to [body].",
        )
    return Scenario(
        name=name,
        source=source,
        description=description,
        body=body,
        attitude=attitude,
        angular_velocity=angular_velocity,
        torque=torque,
        omega_profile=profile,
        simulation=simulation,
        data=copy.deepcopy(data),
    )


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
    from ..mass import check_inertia

    try:
        check_inertia(j)
    except PoinsotError as exc:
        raise _wrap(t, key, exc) from None
    return j


def _solid(t: Table) -> tuple[str, tuple[float, ...], float, np.ndarray]:
    shape = t.string("shape", choices=tuple(SHAPES), required=True)
    names = SHAPES[shape]
    dims = t.vector(
        "dims",
        len(names),
        what=f"{len(names)} positive number(s) for a {shape}: [{', '.join(names)}] (m)",
    )
    if any(d <= 0 for d in dims):
        raise t.expected("dims", f"positive dimensions [{', '.join(names)}] (m)", list(dims))
    mass = t.number("mass", positive=True, required=True)
    from ..mass import solids

    try:
        j = getattr(solids, shape)(mass, *dims)
    except PoinsotError as exc:
        raise _wrap(t, "dims", exc) from None
    return shape, dims, mass, np.asarray(j, dtype=float)


def _part(t: Table, index: int) -> PartSpec:
    keys = ("name", "shape", "dims", "mass", "inertia", "position", "orientation")
    t.known(keys)
    name = t.string("name", f"part {index}")
    position = np.array(t.vector("position", 3, required=False, default=(0.0, 0.0, 0.0)))
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
    orientation = t.table("orientation")
    if orientation is not None:  # the part's own axes relative to the body axes
        q = _attitude(orientation, t).quat
        from ..rotations.rotation import Rotation

        c_bp = Rotation.from_quat(q).as_matrix()
        j = c_bp @ j @ c_bp.T  # J_b = C J_p C^T (SPEC S8)
    t.finish(keys)
    return PartSpec(name=name, mass=mass, inertia=j, position=position, shape=shape, dims=dims)


def _body(t: Table) -> BodySpec:
    t.known(("mass", "inertia", "center_of_mass", "shape", "dims", "parts"))
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
        from ..mass import RigidBody, check_inertia, combine

        t.finish(("parts",))
        try:
            whole = combine(*(RigidBody(p.mass, p.inertia, p.position) for p in parts))
            mass, j, com = whole.mass, whole.inertia, whole.center_of_mass
            check_inertia(j)
        except PoinsotError as exc:
            raise _wrap(t, "parts", exc) from None
        return BodySpec(mass=mass, inertia=j, center_of_mass=com, parts=parts)
    com = np.array(t.vector("center_of_mass", 3, required=False, default=(0.0, 0.0, 0.0)))
    if how == "shape":
        shape, dims, mass, j = _solid(t)
        from ..mass import check_inertia

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


def _attitude(t: Table | None, top: Table) -> AttitudeSpec:
    from ..rotations.rotation import Rotation

    if t is None:
        return AttitudeSpec("identity", (), np.array([1.0, 0.0, 0.0, 0.0]))
    t.known(_EVERY_ATTITUDE_KEY)
    rep = t.exclusive(_ATTITUDE_KEYS, what="the initial attitude (body -> space)")
    seq = deg = sf = None
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
            r = Rotation.from_matrix(values)
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
                from ..rotations.euler import parse_sequence

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
        "matrix": ("matrix",),
        "rotvec": ("rotvec", "degrees"),
        "axis": ("axis", "angle", "degrees"),
        "euler": ("euler", "sequence", "degrees"),
        "gibbs": ("gibbs",),
        "mrp": ("mrp",),
    }[rep]
    _finish_rep(t, rep, allowed)
    return AttitudeSpec(rep, values, r.as_quat(), sequence=seq, degrees=deg, scalar_first=sf)


def _finish_rep(t: Table, rep: str, allowed) -> None:
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


def _angular_velocity(t: Table, attitude: AttitudeSpec) -> AngularVelocitySpec:
    t.known(("vector", "frame", "units"))
    vector = t.vector("vector", 3)
    frame = t.string("frame", choices=("body", "space"), required=True)
    units = t.string("units", "rad/s", choices=tuple(OMEGA_UNITS))
    t.finish(("vector", "frame", "units"))
    w = np.array(vector) * OMEGA_UNITS[units]
    if frame == "space":
        w = attitude.rotation.apply(w, inverse=True)
    return AngularVelocitySpec(vector=vector, frame=frame, units=units, omega_body=w)


def _torque(t: Table | None) -> TorqueSpec:
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


def _omega_profile(t: Table) -> OmegaProfileSpec:
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


def _simulation(t: Table, profile: OmegaProfileSpec | None, torque: TorqueSpec) -> SimulationSpec:
    t.known(("duration", "step", "samples", "method", "reference", "max_step"))
    duration = t.number("duration", positive=True, required=True)
    how = t.exclusive(("step", "samples"), what="the output times")
    step = samples = None
    if how == "step":
        step = t.number("step", positive=True)
        if step > duration:
            raise t.error("step", f"expected a step <= duration ({duration:g} s), found {step:g}.")
        if duration / step > 5e6:
            raise t.error("step", f"expected at most 5e6 steps, found {duration / step:.3g}.")
    else:
        samples = t.integer("samples", minimum=2)
        if samples > 5_000_000:
            raise t.expected("samples", "at most 5000000 samples", samples)
    methods = KINEMATICS_METHODS if profile is not None else DYNAMICS_METHODS
    method = t.string("method", choices=methods, required=True)
    reference = t.string("reference", choices=methods)
    for key, m in (("method", method), ("reference", reference)):
        if m == "exact" and profile is not None and profile.kind == "samples":
            raise t.error(
                key,
                '"exact" needs a closed form, and a tabulated angular '
                "velocity has none: expected one of "
                + ", ".join(f'"{x}"' for x in methods if x != "exact")
                + ".",
            )
        if m == "exact" and torque.model != "none":
            raise t.error(
                key,
                f'"exact" is the closed-form torque-free solution (SPEC S10), '
                f'but [torque] model is "{torque.model}": expected one of '
                + ", ".join(f'"{x}"' for x in methods if x != "exact")
                + ".",
            )
    max_step = t.number("max_step", positive=True)
    if reference is not None and reference == method:
        raise t.error("reference", f"expected a method other than `method` ({method!r}).")
    if profile is not None and profile.kind == "samples" and duration > profile.t[-1]:
        raise t.error(
            "duration",
            f"expected at most the last time of [omega_profile] t ({profile.t[-1]:g} s): the "
            f"angular velocity is not known after it, found {duration:g}.",
        )
    t.finish(("duration", "step", "samples", "method", "reference", "max_step"))
    return SimulationSpec(
        duration=duration,
        method=method,
        step=step,
        samples=samples,
        reference=reference,
        max_step=max_step,
    )
