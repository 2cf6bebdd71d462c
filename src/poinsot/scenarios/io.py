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
from typing import Any

from .._validate import read_regular_file
from ..errors import InvalidInputError, InvalidTypeError
from . import registry  # read at call time: a test (or a plug-in) may add a kind
from ._toml import ScenarioError, Table, locate_keys
from .readers import (
    _ALLOW_PATHS,
    MATRIX_TOLERANCE,
    SHAPES,
    read_angular_velocity,
    read_attitude,
    read_body,
    read_omega_profile,
    read_torque,
    rotation_from_matrix,
)
from .schema import MAX_SAMPLES, Scenario, SimulationSpec

__all__ = [
    "load_scenario",
    "parse_scenario",
    "demo_scenario_text",
    "ScenarioError",
    "SHAPES",
    "MAX_NAME_LENGTH",
    "MATRIX_TOLERANCE",
    "rotation_from_matrix",
    "read_attitude",
    "read_body",
    "read_angular_velocity",
    "read_torque",
    "read_omega_profile",
]

#: Tables read by ``poinsot ensemble`` (:mod:`poinsot.ensemble`), passed over by ``run``.
_ENSEMBLE_KEYS = ("dispersion", "metric")
#: Top-level keys read for every kind (each kind adds its own tables).
_COMMON_KEYS = ("name", "description", "kind", "attitude", "simulation", *_ENSEMBLE_KEYS)


def demo_scenario_text() -> str:
    """The embedded demo scenario (the tennis-racket flip), as TOML text."""
    return resources.files("poinsot.scenarios").joinpath("tennis_racket.toml").read_text("utf-8")


#: Largest scenario file read (bytes): 1 MiB, a hundred times the longest shipped
#: example; a larger file is refused before it is read (docs/cli.md, 'Limits').
MAX_SCENARIO_BYTES = 2**20


def load_scenario(path: str | os.PathLike[str], *, allow_paths: bool = False) -> Scenario:
    """Read and validate a scenario file.

    Parameters
    ----------
    path : str or path-like
        A TOML scenario file (format: ``docs/cli.md``).
    allow_paths : bool, optional
        Let the file read a mesh (``[body] file``) outside its own directory (an
        absolute path or one through ``..``). Default False: scenario files may come
        from elsewhere, and a file outside the scenario's directory is refused
        before it is opened (the CLI's ``--allow-paths``).

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
    ('spin', 'free-body', 11)
    """
    if not isinstance(path, str | os.PathLike):
        raise InvalidTypeError(
            f"Expected `path` to be a str or os.PathLike, got {type(path).__name__}."
        )
    p = Path(path)
    try:
        raw = read_regular_file(p, max_bytes=MAX_SCENARIO_BYTES, what="a TOML scenario file")
        text = raw.decode("utf-8-sig")  # a UTF-8 byte-order mark is skipped
    except InvalidInputError as exc:
        raise ScenarioError(str(exc).removeprefix(f"{p}: "), file=str(path)) from None
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
    return parse_scenario(text, source=str(path), name=p.stem, allow_paths=allow_paths)


_TOML_LINE = re.compile(r"\(at line (\d+), column (\d+)\)")


def parse_scenario(
    text: str, *, source: str = "<string>", name: str | None = None, allow_paths: bool = False
) -> Scenario:
    """Parse and validate scenario TOML ``text`` (``source`` names it in errors).

    Mesh files are read relative to the directory of ``source`` (the current
    directory for a string), and only inside it unless ``allow_paths``.

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
    ('attitude', [0.0, 0.5, 1.0, 1.5, 2.0])
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
    text = text.removeprefix("\ufeff")  # a byte-order mark left by some editors
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
    token = _ALLOW_PATHS.set(bool(allow_paths))
    try:
        return _scenario(top, data, source, name or "scenario")
    finally:
        _ALLOW_PATHS.reset(token)


# ------------------------------------------------------------------------------------------
#: Longest scenario name: it names the output directory (file names have 255 bytes).
MAX_NAME_LENGTH = 100


def _scenario(top: Table, data: dict[str, Any], source: str, default_name: str) -> Scenario:
    kind_tables = tuple(dict.fromkeys(t for k in registry.KINDS.values() for t in k.tables))
    top.known(_COMMON_KEYS + kind_tables)
    name = top.string("name", default_name)
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]*", name) or len(name) > MAX_NAME_LENGTH:
        raise top.expected(
            "name",
            f"a name of at most {MAX_NAME_LENGTH} letters, digits, '.', '_', '-' "
            "(it names the output directory)",
            name if len(name) <= 40 else f"{name[:40]}... ({len(name)} characters)",
        )
    description = top.string("description", "")
    if top.has("kind"):
        kind = registry.get_kind(top.string("kind", choices=tuple(registry.KINDS), required=True))
    else:
        kind = registry.kind_for(data)
    attitude = read_attitude(top.table("attitude"), top)
    fields = kind.parse(top, attitude)
    for other in kind_tables:
        if other not in kind.tables and top.has(other):
            raise top.error(
                other,
                f"not used by a {kind.name!r} scenario ({kind.title}), which reads "
                + ", ".join(f"[{t}]" for t in kind.tables)
                + ".",
            )
    simulation = _simulation(top.table("simulation", required=True), kind, fields)
    for key in _ENSEMBLE_KEYS:  # read by poinsot.ensemble
        if top.has(key):
            top.raw(key)
    top.finish(_COMMON_KEYS + kind.tables)
    return Scenario(
        name=name,
        source=source,
        description=description,
        attitude=attitude,
        simulation=simulation,
        data=copy.deepcopy(data),
        kind=kind.name,
        adapter=kind,
        **fields,
    )


def _simulation(t: Table, kind: Any, fields: Any) -> SimulationSpec:
    keys = (
        "duration",
        "step",
        "samples",
        "method",
        "reference",
        "max_step",
        "drift_threshold",
        "attitude_threshold",
        "agreement_threshold",
    )
    t.known(keys)
    duration = t.number("duration", positive=True, required=True)
    how = t.exclusive(("step", "samples"), what="the output times")
    step: float | None = None
    samples: int | None = None
    if how == "step":  # the key is present (exclusive)
        step = t.number("step", positive=True, required=True)
        if step > duration:
            raise t.error("step", f"expected a step <= duration ({duration:g} s), found {step:g}.")
        if duration / step > MAX_SAMPLES:
            raise t.error(
                "step",
                f"expected at most {MAX_SAMPLES} output samples (duration / step), found "
                f"{duration / step:.3g}: choose a longer step.",
            )
    else:
        samples = t.integer("samples", minimum=2, required=True)
        if samples > MAX_SAMPLES:
            raise t.expected("samples", f"at most {MAX_SAMPLES} samples", samples)
    methods = kind.methods
    method = t.string("method", choices=methods, required=True)
    reference = t.string("reference", choices=methods)
    for key, m in (("method", method), ("reference", reference)):
        why = None if m is None else kind.refuse_method(m, fields)
        if why:
            raise t.error(key, why)
    max_step = t.number("max_step", positive=True)
    drift_threshold = t.number("drift_threshold", positive=True)
    attitude_threshold = t.number("attitude_threshold", positive=True)
    agreement_threshold = t.number("agreement_threshold", positive=True)
    if reference is not None and reference == method:
        raise t.error("reference", f"expected a method other than `method` ({method!r}).")
    sim = SimulationSpec(
        duration=duration,
        method=method,
        step=step,
        samples=samples,
        reference=reference,
        max_step=max_step,
        drift_threshold=drift_threshold,
        attitude_threshold=attitude_threshold,
        agreement_threshold=agreement_threshold,
    )
    bad = kind.check_simulation(sim, fields)
    if bad is not None:
        raise t.error(*bad)
    t.finish(keys)
    return sim
