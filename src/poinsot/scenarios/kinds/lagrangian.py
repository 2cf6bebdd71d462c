"""Adapter: a system given by its Lagrangian (docs/theory.md §11).

Table: [lagrangian] with ``coordinates`` (names), ``parameters`` (name = number),
``kinetic`` and ``potential`` (formulas), optional ``generalized_potential``,
``generalized_forces`` (one formula per coordinate), ``holonomic``,
``nonholonomic`` (lists of formulas, ``= 0``), ``eliminate`` (coordinates solved
from the holonomic constraints), ``units`` (the SI unit of each coordinate,
``{theta1 = "rad", x = "m"}``; default guessed from the name by
:func:`coordinate_unit`), and the initial state ``q0``, ``qdot0``.
Formulas use the coordinates, their rates ``<name>_dot``, the parameters, ``t`` and
the functions of :data:`poinsot.symbolic.FUNCTIONS`; they are read by the
whitelist parser :func:`poinsot.symbolic.parse_expression` (never evaluated as
code; the rules are in ``docs/lagrange.md``). Solved by
:class:`poinsot.symbolic.LagrangeSystem` (compiled right-hand side,
``solve_ivp``).

The kind returns the library's own result, a
:class:`~poinsot.trajectory.CoordinateTrajectory` (coordinates and rates in the
units of each coordinate, energies, multipliers); the trajectory files, the
comparison with a reference run and ``report.html`` read it directly.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...errors import InvalidInputError
from ...plotting.lagrange import plot_coordinates, plot_equations, plot_phase
from ...symbolic import FUNCTIONS, ExpressionError, LagrangeSystem, parse_expression
from ...symbolic._symbols import coordinate_unit as guess
from ...symbolic.numeric import _framed
from ..draw import read_draw
from ..figures import invariants_figure
from ..kind import Chart, ReportSpec
from ..report import figure_sections

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Facts, FigureSpec, Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ... import integrators
from ..describe import fmt
from ..kind import Check, Entry, Facts, FigureSpec, ScenarioKind

#: ``[simulation] method`` -> ``solve_ivp`` method.
#: ``[simulation] method``: SciPy's solve_ivp methods under SciPy's names (the one
#: table, :data:`poinsot.integrators.INTEGRATORS`; lower-case ``"dop853"`` is poinsot's
#: compiled rigid-body integrator, not this one).
_METHODS = integrators.names("lagrangian")
_KEYS = (
    "coordinates",
    "parameters",
    "kinetic",
    "potential",
    "generalized_potential",
    "generalized_forces",
    "holonomic",
    "nonholonomic",
    "eliminate",
    "q0",
    "qdot0",
    "rtol",
    "atol",
    "units",
)
#: Units a coordinate may have in ``[lagrangian] units`` ("": none stated).
UNITS = ("rad", "m", "")


def coordinate_unit(name: str) -> str:
    """SI unit of a generalized coordinate guessed from its name: a Greek letter
    (``theta1``, ``phi``) is an angle (``"rad"``); ``x``, ``y``, ``z``, ``r``, ``s``,
    ``l``, ``d``, ``h``, ``rho`` (with digits or ``_`` after) a length (``"m"``);
    else unknown (``""``). ``[lagrangian] units`` overrides the guess. The library's
    guess (:meth:`poinsot.symbolic.NumericLagrangian.simulate` without ``units``).

    Examples
    --------
    >>> [coordinate_unit(n) for n in ("theta1", "phi", "x", "rho", "z_2", "q")]
    ['rad', 'rad', 'm', 'm', 'm', '']
    """

    return guess(name)


def rate_unit(unit: str) -> str:
    """Unit of a coordinate's rate: ``"rad"`` -> ``"rad/s"``, ``""`` -> ``"1/s"``.

    Examples
    --------
    >>> rate_unit("m"), rate_unit("")
    ('m/s', '1/s')
    """
    return f"{unit}/s" if unit else "1/s"


@dataclass(frozen=True)
class LagrangianSpec:
    """What the [lagrangian] table says (formulas as text, numbers in SI)."""

    coordinates: tuple[str, ...]
    parameters: tuple[tuple[str, float], ...]
    formulas: tuple[tuple[str, Any], ...]  # (key, text or tuple of texts)
    q0: tuple[float, ...]
    qdot0: tuple[float, ...]
    rtol: float
    atol: float
    system: Any = field(default=None, repr=False, compare=False)  # LagrangeSystem
    units: tuple[str, ...] = ()  # of each kept coordinate (SI; "" unknown)
    draw: Any = None  # the [draw] table (poinsot.scenarios.draw.DrawSpec) or None


def _strings(t: Any, key: Any, n: Any = None) -> Any:
    v = t.raw(key)
    if isinstance(v, str):
        v = [v]
    if (
        not isinstance(v, list)
        or not all(isinstance(x, str) for x in v)
        or (n is not None and len(v) != n)
    ):
        what = "a list of formula strings" + (f" ({n} of them)" if n else "")
        raise t.expected(key, what, v)
    return tuple(v)


def _parse_formula(t: Any, key: Any, text: Any, symbols: Any) -> Any:
    try:
        return parse_expression(text, symbols)
    except ExpressionError as exc:
        raise t.error(key, str(exc)) from None


def _build(t: Any, coords: Any, params: Any, formulas: Any) -> Any:
    """Parse every formula (errors name file, key, token) and build the system."""
    import sympy
    from sympy.physics.mechanics import dynamicsymbols

    time = dynamicsymbols._t
    funcs = [sympy.Function(c)(time) for c in coords]
    symbols = {"t": time}
    for c, f in zip(coords, funcs, strict=True):
        symbols[c] = f
        symbols[f"{c}_dot"] = f.diff(time)
    for name, _ in params:
        symbols[name] = sympy.Symbol(name, real=True)
    parsed: dict[str, Any] = {}
    for key, text in formulas:
        if isinstance(text, tuple):
            parsed[key] = [_parse_formula(t, key, s, symbols) for s in text]
        else:
            parsed[key] = _parse_formula(t, key, text, symbols)
    elim = [funcs[coords.index(e)] for e in parsed.pop("eliminate", [])]
    try:
        return LagrangeSystem(
            funcs,
            parsed.get("kinetic"),
            parsed.get("potential", 0),
            generalized_potential=parsed.get("generalized_potential"),
            generalized_forces=parsed.get("generalized_forces"),
            holonomic=parsed.get("holonomic", ()),
            nonholonomic=parsed.get("nonholonomic", ()),
            eliminate=elim,
            time=time,
        )
    except InvalidInputError as exc:
        raise t.error(None, str(exc)) from None


def _check_system(t: Any, system: Any, params: Any, q0: Any, qdot0: Any) -> None:
    """What ``run`` would refuse, refused when the file is read (``check`` and ``run``
    agree): a parameter that no equation uses (a typo, most likely); a kinetic energy
    that is not positive definite in the velocities at the initial state (its mass
    matrix ``d^2 T / dq' dq'``: a negative ``m x'^2 / 2``, or a coordinate without
    velocity); equations of motion that are not finite there (``sqrt`` of a negative
    number, a division by zero: the message names the state and the term). The last
    two are the library's own test (``NumericLagrangian.check_state``), run on the
    generated source by the interpreter (no compilation for ``check``)."""
    import numpy as np

    used = {str(s) for s in system.parameters}
    unused = [name for name, _ in params if name not in used]
    if unused:
        raise t.error(
            "parameters",
            f"{', '.join(repr(u) for u in unused)} "
            + ("appears" if len(unused) == 1 else "appear")
            + " in no equation of motion; "
            "remove them (or use them in `kinetic`, `potential`, ...).",
        )
    f = system.to_numeric(dict(params))  # cached: `run` solves with this one
    y0 = np.ascontiguousarray([[*q0, *qdot0]], dtype=float)
    problem = f._start_problem(np.zeros(1), y0, f._params(None), f._interpreted(), "_dot")
    if problem is not None:
        kind, text = problem
        message = _framed(kind, text, "an initial state (`q0`, `qdot0`)")
        key = "kinetic" if kind == "kinetic" else "q0"
        raise t.error(key, message[0].lower() + message[1:])


class Lagrangian(ScenarioKind):
    name = "lagrangian"
    title = "a system given by its Lagrangian (Lagrange's equations of the second kind)"
    tables = ("lagrangian", "draw")
    methods = _METHODS
    orders: dict[str, Any] = {}
    theory = "docs/theory.md §11"
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {
        "DOP853": 5.5e-5,
        "RK45": 5e-5,
        "RK23": 5e-5,
        "Radau": 1.3e-3,
        "BDF": 1e-3,
        "LSODA": 2e-4,
    }

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "lagrangian" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        t = top.table("lagrangian", required=True)
        t.known(_KEYS)
        raw = t.require("coordinates", "a list of coordinate names")
        if (
            not isinstance(raw, list)
            or not raw
            or not all(isinstance(c, str) and c.isidentifier() for c in raw)
        ):
            raise t.expected("coordinates", "a non-empty list of names", raw)
        coords = tuple(raw)

        reserved = {"t", "pi", *FUNCTIONS}
        pt = t.table("parameters")
        params: list[tuple[str, float]] = []
        if pt is not None:
            for name in list(pt.data):
                params.append((name, pt.number(name, required=True)))
        names = list(coords) + [f"{c}_dot" for c in coords] + [p for p, _ in params]
        for name in names:
            if name.startswith("_") or name in reserved or not name.isidentifier():
                key = "parameters" if name in dict(params) else "coordinates"
                raise t.error(
                    key,
                    f"invalid name {name!r}: names are identifiers not starting with '_' "
                    f"and other than {', '.join(sorted(reserved))}.",
                )
        if len(set(names)) != len(names):
            raise t.error("parameters", f"duplicate names among {names}.")
        n = len(coords)
        formulas: list[tuple[str, Any]] = []
        formulas.append(("kinetic", t.string("kinetic", required=True)))
        for key in ("potential", "generalized_potential"):
            if t.has(key):
                formulas.append((key, t.string(key)))
        if t.has("generalized_forces"):
            formulas.append(("generalized_forces", _strings(t, "generalized_forces", n)))
        for key in ("holonomic", "nonholonomic"):
            if t.has(key):
                formulas.append((key, _strings(t, key)))
        if t.has("eliminate"):
            elim = t.raw("eliminate")
            if not isinstance(elim, list) or not all(e in coords for e in elim):
                raise t.expected("eliminate", f"a list of coordinates among {list(coords)}", elim)
            formulas.append(("eliminate", tuple(elim)))
        system = _build(t, coords, params, formulas)
        kept = [str(f.func) for f in system.coordinates]
        m = len(kept)
        q0 = t.vector("q0", m, what=f"an array of {m} numbers (initial {', '.join(kept)})")
        qdot0 = t.vector("qdot0", m, what=f"an array of {m} numbers (initial rates)")
        rtol = t.number("rtol", 1e-10, positive=True)
        atol = t.number("atol", 1e-12, positive=True)
        _check_system(t, system, params, q0, qdot0)
        units = self._units(t, kept)
        t.finish(_KEYS)

        draw = read_draw(top, tuple(kept), tuple(p for p, _ in params))
        spec = LagrangianSpec(coords, tuple(params), tuple(formulas), q0, qdot0, rtol, atol,
                              system, units, draw)  # fmt: skip
        return {"spec": spec}

    @staticmethod
    def _units(t: Any, kept: Any) -> tuple[str, ...]:
        """``[lagrangian] units`` (name -> "rad", "m" or ""), else the guess of
        :func:`coordinate_unit`, for each kept coordinate."""
        given = t.raw("units") if t.has("units") else {}
        if not isinstance(given, dict):
            raise t.expected("units", 'a table {coordinate = "rad" or "m"}', given)
        for name, unit in given.items():
            if name not in kept:
                raise t.error("units", f"expected a coordinate among {kept}, found {name!r}.")
            if unit not in UNITS:
                raise t.error(
                    "units",
                    f"expected the unit of {name!r} to be one of {list(UNITS)}, found {unit!r}.",
                )
        return tuple(given.get(c, coordinate_unit(c)) for c in kept)

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        spec = scenario.spec
        f = spec.system.to_numeric(dict(spec.parameters))
        progress(0.0, method)
        sim = scenario.simulation
        lt = f.simulate(
            spec.q0,
            spec.qdot0,
            t,
            method=method,
            rtol=spec.rtol,
            atol=spec.atol,
            max_step=sim.max_step if sim.max_step is not None else np.inf,
            units=spec.units or None,  # None: the library's guess from the names
        )
        progress(1.0, method)
        return dataclasses.replace(lt, method=method)  # named as the scenario names it

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        return None

    def facts(self, scenario: Scenario) -> Facts:
        """The Lagrangian and Lagrange's equations in readable text (``theta1'`` for a
        rate) and as LaTeX, with the parameter values; the cyclic coordinates and
        whether the Jacobi integral is conserved."""
        import sympy

        spec = scenario.spec
        system = spec.system
        pr = system.printable
        eqs = system.equations()
        values = ", ".join(f"{name} = {fmt(v)}" for name, v in spec.parameters)
        entries = {
            "coordinates": Entry(", ".join(str(f.func) for f in system.coordinates)),
            "parameters": Entry(", ".join(str(p) for p in system.parameters)),
            "parameter_values": Entry(dict(spec.parameters)),
            "lagrangian": Entry(str(pr(system.lagrangian))),
            "lagrangian_latex": Entry(sympy.latex(pr(system.lagrangian, latex=True))),
            "equations": Entry([f"{pr(e.lhs)} = {pr(e.rhs)}" for e in eqs]),
            "equations_latex": Entry(
                [
                    f"{sympy.latex(pr(e.lhs, latex=True))} = {sympy.latex(pr(e.rhs, latex=True))}"
                    for e in eqs
                ]
            ),  # fmt: skip
            "cyclic_coordinates": Entry([str(c.func) for c in system.cyclic_coordinates]),
            "jacobi_integral_conserved": Entry(bool(system.jacobi_conserved)),
        }
        lines = [
            f"Lagrange's equations E_k L = Q*_k (docs/theory.md §11), "
            f"L = {pr(system.lagrangian)}" + (f", with {values}" if values else "")
        ]
        lines += [f"  {pr(e.lhs)} = {pr(e.rhs)}" for e in eqs]
        if system.cyclic_coordinates:
            names = ", ".join(str(c.func) for c in system.cyclic_coordinates)
            lines.append(f"cyclic coordinates: {names} (their momenta are conserved)")
        lines.append(
            "Jacobi integral h = q'.dL/dq' - L is conserved"
            if system.jacobi_conserved
            else "no Jacobi integral (time-dependent or non-conservative)"
        )
        return Facts(entries, tuple(lines))

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        system = scenario.spec.system
        out = []
        # relative to the larger of |initial value| and the largest kinetic energy
        big = float(np.max(np.abs(tr.kinetic)))
        if tr.jacobi is not None:
            out.append(
                Check(
                    "jacobi",
                    "Jacobi integral h",
                    "J",
                    tr.jacobi,
                    scale=max(abs(float(tr.jacobi[0])), big) or None,
                    conserved=bool(system.jacobi_conserved),
                )  # fmt: skip
            )
        same = tr.jacobi is not None and np.allclose(tr.energy, tr.jacobi, rtol=1e-12, atol=0)
        if not same:
            out.append(Check("energy", "energy T + P", "J", tr.energy,
                             scale=max(abs(float(tr.energy[0])), big) or None,
                             conserved=False))  # fmt: skip
        return tuple(out)

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        lt = result.trajectory
        system = result.scenario.spec.system

        def coords(ax: Any, lt: Any = lt) -> Any:
            return plot_coordinates(lt, ax=ax, title=f"{result.scenario.name}: coordinates")

        def phase(ax: Any, lt: Any = lt) -> Any:
            return plot_phase(lt, ax=ax)

        def eqs(ax: Any, system: Any = system) -> Any:
            return plot_equations(system, ax=ax)

        n = len(system.coordinates) + len(system.multipliers)
        figs = [
            invariants_figure(result),
            FigureSpec("coordinates.png", coords),
            FigureSpec("phase.png", phase),
            FigureSpec("equations.svg", eqs, size=(9.0, 0.9 + 0.7 * n)),
        ]
        return [f for f in figs if f is not None]

    def report(self, result: ScenarioResult) -> ReportSpec:
        """``report.html``: the system drawn by its ``[draw]`` table (points, links,
        trails) when it has one; charts of ``q(t)`` and ``q'(t)`` grouped by unit
        (the reference run's dashed beside them), the constraint multipliers, the
        checks, and the equations, coordinates and phase portraits as inline SVG
        (offline)."""

        lt = result.trajectory
        ref = result.reference
        same = ref is not None and ref.t.shape == lt.t.shape and ref.q.shape == lt.q.shape
        groups: dict[tuple[str, str], dict[str, Any]] = {}
        what = {"rad": "angles", "m": "lengths"}
        for rate in (False, True):
            for k, (name, unit) in enumerate(zip(lt.coordinates, lt.units, strict=True)):
                head = f": {what[unit]}" if unit in what else ""
                if rate:
                    key = (f"generalised velocities q'(t){head}", rate_unit(unit))
                else:
                    key = (f"generalised coordinates q(t){head}", unit or "unit of q")
                label, values = (f"{name}'", lt.qdot) if rate else (name, lt.q)
                groups.setdefault(key, {})[label] = values[:, k]
                if same:
                    other = ref.qdot if rate else ref.q
                    groups[key][f"{label} ({ref.method}, reference)"] = other[:, k]
        charts = [
            Chart(title, units, d, tuple(k for k in d if k.endswith("reference)")))
            for (title, units), d in groups.items()
        ]
        if lt.multipliers is not None and lt.multipliers.size:
            lam = np.asarray(lt.multipliers).reshape(lt.t.size, -1)
            names = lt.multiplier_names or tuple(f"lambda{k + 1}" for k in range(lam.shape[1]))
            charts.append(
                Chart(
                    "constraint multipliers lambda: the constraint forces (N for a constraint "
                    "on velocities in m/s; docs/theory.md §11)",
                    "SI",
                    {n: lam[:, k] for k, n in enumerate(names)},
                )
            )
        spec = result.scenario.spec
        system = spec.system
        n = len(system.coordinates)

        def eqs(ax: Any) -> Any:
            return plot_equations(system, ax=ax)

        titles = {
            "coordinates.png": "Coordinates q(t) (coordinates.png)",
            "phase.png": "Phase portraits q' against q (phase.png)",
        }
        figs = [f for f in self.figures(result) if f.name in titles]
        sections = figure_sections(
            [FigureSpec("equations.svg", eqs, size=(9.0, 0.9 + 0.7 * n)), *figs],
            ["Lagrange's equations (docs/theory.md §11)", *(titles[f.name] for f in figs)],
        )
        drawing = None
        if spec.draw is not None:
            drawing = spec.draw.evaluate(lt.t, lt.q, dict(spec.parameters))
        return ReportSpec(
            motion=lt,
            charts=tuple(charts),
            checks=tuple(result.checks),
            sections=tuple(sections),
            drawing=drawing,
        )

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        s = scenario.spec.system
        return [
            f"{self.title}: coordinates {', '.join(str(f.func) for f in s.coordinates)}, "
            f"{len(s.multipliers)} constraint multiplier(s)"
        ]


KIND = Lagrangian()
