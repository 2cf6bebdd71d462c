"""Describing scenarios and runs in text (``poinsot check``, ``poinsot run``).

Numbers are printed without round-off noise: in a vector, a component smaller
than :data:`NOISE` times the largest one prints as ``0`` (see :func:`clean`).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from .._display import NOISE, clean
from ..trajectory import quantity_label
from .schema import Scenario

if TYPE_CHECKING:
    from .summary import ScenarioResult

__all__ = [
    "describe",
    "describe_scenario",
    "describe_comparison",
    "clean",
    "fmt",
    "fmt_vector",
    "NOISE",
]


def fmt(x: Any, digits: int = 4) -> str:
    """A number with ``digits`` significant digits (``-0`` printed as ``0``).

    Examples
    --------
    >>> fmt(0.123456), fmt(-0.0)
    ('0.1235', '0')
    """
    return f"{float(x) + 0.0:.{digits}g}"


def fmt_vector(v: Any, digits: int = 4) -> str:
    """``[a, b, c]`` with round-off noise printed as 0.

    Examples
    --------
    >>> fmt_vector([0.1, 12.0, 1e-17])
    '[0.1, 12, 0]'
    """
    return "[" + ", ".join(fmt(x, digits) for x in clean(np.ravel(v))) + "]"


def describe_scenario(scenario: Scenario) -> str:
    """One line describing a scenario (used by ``poinsot check``).

    Examples
    --------
    >>> from poinsot.scenarios import demo_scenario
    >>> print(describe_scenario(demo_scenario()))  # doctest: +ELLIPSIS
    scenario 'tennis-racket-flip' (free-body): torque-free ..., 0.35 kg box body, ...
    """
    sim = scenario.simulation
    n = sim.n_samples()
    kind = scenario.adapter
    head = f"scenario {scenario.name!r} ({scenario.kind}): "
    parts = kind.describe_scenario(scenario)
    b = scenario.body
    if b is not None:
        what = (
            f"{b.shape} body" if b.shape else f"body of {len(b.parts)} parts" if b.parts else "body"
        )
        parts.append(f"{fmt(b.mass)} kg {what}")
    if scenario.angular_velocity is not None:
        parts.append(f"omega0 {fmt_vector(scenario.angular_velocity.omega_body)} rad/s (body)")
    ref = f", reference {sim.reference}" if sim.reference else ""
    parts.append(f"{n} samples over {fmt(sim.duration)} s, method {sim.method}{ref}")
    if sim.method in kind.orders or (sim.reference in kind.orders):
        parts.append(f"integration step {fmt(sim.integration_step())} s")
    return head + ", ".join(parts)


def _drifts(inv: dict[str, Any]) -> str:
    kept = [
        f"{k.replace('_', ' ')} drift {v['max_relative_drift']:.2e}"
        for k, v in inv.items()
        if isinstance(v, dict) and "max_relative_drift" in v and v.get("conserved")
    ]
    if kept:
        return "; ".join(kept)
    changes = [
        f"{k.replace('_', ' ')} {fmt(v['initial'])} -> {fmt(v['final'])} {v['units']}"
        for k, v in inv.items()
        if isinstance(v, dict) and isinstance(v.get("final"), float)
    ]
    return ", ".join(changes) if changes else "done"


def _about_fixed_point(body: dict[str, Any]) -> str:
    """The moments about the fixed point of a body that turns about one (a heavy top):
    its diagonal in body axes ``A, B, C`` when the body axes are principal there (what
    ``A = B`` or ``A = B = 2C`` refer to, docs/theory.md §10), else its principal moments.

    >>> _about_fixed_point({"inertia_about_fixed_point": [[2, 0, 0], [0, 2, 0], [0, 0, 1]]})
    '; about the fixed point (body axes) A, B, C = [2, 2, 1] kg m^2'
    >>> _about_fixed_point({"principal_moments": [1, 2, 3]})
    ''
    """
    if "inertia_about_fixed_point" not in body:
        return ""
    j = np.asarray(body["inertia_about_fixed_point"], dtype=float)
    off = j - np.diag(np.diag(j))
    if np.max(np.abs(off)) <= 1e-12 * np.max(np.abs(j)):
        return f"; about the fixed point (body axes) A, B, C = {fmt_vector(np.diag(j))} kg m^2"
    moments = np.linalg.eigvalsh(0.5 * (j + j.T))
    return f"; principal moments about the fixed point {fmt_vector(moments)} kg m^2"


def describe_comparison(comparison: dict[str, Any]) -> str:
    """One line from ``accuracy.comparison`` of a summary: the largest difference of
    each state quantity from the reference run, in its units, and when.

    Examples
    --------
    >>> print(describe_comparison({"reference": "radau", "differences": {
    ...     "theta1": {"max": 0.1912, "time_of_max_s": 20.0, "units": "rad"},
    ...     "theta1_dot": {"max": 0.7562, "time_of_max_s": 19.9, "units": "rad/s"}}}))
    ... # doctest: +NORMALIZE_WHITESPACE
    vs radau: theta1 differs by up to 0.191 rad (at t = 20 s),
    theta1' by up to 0.756 rad/s (at t = 19.9 s)
    """
    parts = []
    for k, (name, d) in enumerate(comparison["differences"].items()):
        units = f" {d['units']}" if d.get("units") else ""
        verb = " differs" if k == 0 else ""
        parts.append(
            f"{quantity_label(name)}{verb} by up to {float(d['max']):.3g}{units} "
            f"(at t = {float(d['time_of_max_s']):.4g} s)"
        )
    return f"vs {comparison['reference']}: " + (", ".join(parts) if parts else "no difference")


def describe(result: ScenarioResult, *, title: str = "poinsot", notes: Iterable[str] = ()) -> str:
    """A short human summary of a run (printed by ``poinsot run`` and ``poinsot demo``).

    Examples
    --------
    >>> from poinsot.scenarios import demo_scenario, simulate_scenario
    >>> print(describe(simulate_scenario(demo_scenario(), duration=0.5)))  # doctest: +ELLIPSIS
    poinsot: tennis-racket-flip - ...
    conventions: ...
    """
    s = result.scenario
    summ = result.sections()
    lines = [f"{title}: {s.name}" + (f" - {s.description}" if s.description else "")]
    lines.append("conventions: " + summ["conventions"])
    if s.body is not None:
        b = summ["body"]
        body: Any = s.body  # a mesh has faces, a shape its dims (set by the parser)
        shape = (
            f"mesh of {len(body.faces)} triangles, "
            if body.shape == "mesh"
            else f"{body.shape} {' x '.join(fmt(d) for d in body.dims)} m, "
            if s.body.shape
            else f"{len(s.body.parts)} parts, "
            if s.body.parts
            else ""
        )
        lines.append(
            f"body: {shape}{fmt(s.body.mass)} kg; principal moments about the centre of mass "
            f"{fmt_vector(b['principal_moments'])} kg m^2" + _about_fixed_point(b)
        )
    init = summ["initial_state"]
    times = summ["run"]["times"]
    if "omega_body" in init:  # a rigid body
        start = (
            f"omega {fmt_vector(init['omega_body'])} rad/s (body), quat {fmt_vector(init['quat'])}"
        )
    else:  # the initial value of each state quantity of the kind's result
        units = init.get("units", {})
        start = ", ".join(
            f"{quantity_label(k)} {fmt_vector(v) if isinstance(v, list) else fmt(v)}"
            + (f" {units[k]}" if units.get(k) else "")
            for k, v in init.items()
            if k != "units" and v is not None
        )
    lines.append(f"start: {start}; {times['samples']} samples over {fmt(times['duration'])} s")
    lines += result.facts.describe()
    acc = summ["accuracy"]
    lines.append(f"{acc['method']}: {_drifts(acc['invariants'])} ({result.wall_time:.2f} s)")
    if acc["reference_invariants"]:
        took = "" if result.reference_time is None else f" ({result.reference_time:.2f} s)"
        lines.append(f"{acc['reference']}: {_drifts(acc['reference_invariants'])}{took}")
    if result.compile_time >= 0.05:
        lines.append(f"compiling (first run only): {result.compile_time:.2f} s")
    cmp_ = acc["comparison"]
    if cmp_:
        lines.append(describe_comparison(cmp_))
    for w in acc["warnings"]:
        lines.append(f"accuracy warning: {w}")
    if acc["warnings"] and acc["suggested_max_step"]:
        lines.append(
            f"suggestion: set [simulation] max_step = {acc['suggested_max_step']:g} "
            f"(the integration step is now {acc['integration_step']:g} s)"
        )
    for note in notes:
        lines.append(f"note: {note}")
    return "\n".join(lines)
