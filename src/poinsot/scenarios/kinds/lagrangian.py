"""Adapter: a system given by its Lagrangian (docs/theory.md §11).

Table: [lagrangian] with ``coordinates`` (names), ``parameters`` (name = number),
``kinetic`` and ``potential`` (formulas), optional ``generalized_potential``,
``generalized_forces`` (one formula per coordinate), ``holonomic``,
``nonholonomic`` (lists of formulas, ``= 0``), ``eliminate`` (coordinates solved
from the holonomic constraints), and the initial state ``q0``, ``qdot0``.
Formulas use the coordinates, their rates ``<name>_dot``, the parameters, ``t`` and
the functions of :data:`poinsot.symbolic.FUNCTIONS`; they are read by the
whitelist parser :func:`poinsot.symbolic.parse_expression` (never evaluated as
code; the rules are in ``docs/lagrange.md``). Solved by
:class:`poinsot.symbolic.LagrangeSystem` (compiled right-hand side,
``solve_ivp``).

The trajectory files carry the coordinates and rates as extra columns; the
attitude columns of a rigid-body run hold the identity (there is no body
attitude in a generalized-coordinate system).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..kind import Check, Entry, Facts, FigureSpec, ScenarioKind

#: ``[simulation] method`` -> ``solve_ivp`` method.
_METHODS = {"dop853": "DOP853", "rk45": "RK45", "radau": "Radau", "lsoda": "LSODA"}
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
)
#: the LagrangeTrajectory of each Trajectory solved here (for series, checks, figures)
_RUNS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


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


def _strings(t, key, n=None):
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


def _parse_formula(t, key, text, symbols):
    from ...symbolic import ExpressionError, parse_expression

    try:
        return parse_expression(text, symbols)
    except ExpressionError as exc:
        raise t.error(key, str(exc)) from None


def _build(t, coords, params, formulas):
    """Parse every formula (errors name file, key, token) and build the system."""
    import sympy
    from sympy.physics.mechanics import dynamicsymbols

    from ...errors import InvalidInputError
    from ...symbolic import LagrangeSystem

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


class Lagrangian(ScenarioKind):
    name = "lagrangian"
    title = "a system given by its Lagrangian (Lagrange's equations of the second kind)"
    tables = ("lagrangian",)
    methods = tuple(_METHODS)
    orders: dict = {}
    theory = "docs/theory.md §11"

    def claims(self, data):
        return "lagrangian" in data

    def parse(self, top, attitude):
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
        from ...symbolic import FUNCTIONS

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
        t.finish(_KEYS)
        spec = LagrangianSpec(coords, tuple(params), tuple(formulas), q0, qdot0, rtol, atol,
                              system)  # fmt: skip
        return {"spec": spec}

    def solve(self, scenario, method, t, progress):
        from ...rotations.rotation import Rotation
        from ...trajectory import Trajectory

        spec = scenario.spec
        f = spec.system.to_numeric(dict(spec.parameters))
        progress(0.0, method)
        sim = scenario.simulation
        lt = f.simulate(
            spec.q0,
            spec.qdot0,
            t,
            method=_METHODS[method],
            rtol=spec.rtol,
            atol=spec.atol,
            max_step=sim.max_step if sim.max_step is not None else np.inf,
        )
        progress(1.0, method)
        info = {k: v for k, v in lt.info.items() if k != "message"}
        info["coordinates"] = list(lt.coordinates)
        tr = Trajectory(t, Rotation.identity((t.size,)), np.zeros((t.size, 3)), method, info=info)
        _RUNS[tr] = lt
        return tr

    def motion_inertia(self, scenario):
        return None

    def facts(self, scenario):
        system = scenario.spec.system
        entries = {
            "coordinates": Entry(", ".join(str(f.func) for f in system.coordinates)),
            "parameters": Entry(", ".join(str(p) for p in system.parameters)),
            "equations": Entry([str(e) for e in system.equations()]),
            "cyclic_coordinates": Entry([str(c.func) for c in system.cyclic_coordinates]),
            "jacobi_integral_conserved": Entry(bool(system.jacobi_conserved)),
        }
        lines = [f"Lagrange's equations E_k L = Q*_k (docs/theory.md §11), L = {system.lagrangian}"]
        lines += [f"  {e.lhs} = {e.rhs}" for e in system.equations()]
        if system.cyclic_coordinates:
            names = ", ".join(str(c.func) for c in system.cyclic_coordinates)
            lines.append(f"cyclic coordinates: {names} (their momenta are conserved)")
        lines.append(
            "Jacobi integral h = q'.dL/dq' - L is conserved"
            if system.jacobi_conserved
            else "no Jacobi integral (time-dependent or non-conservative)"
        )
        return Facts(entries, tuple(lines))

    def series(self, scenario, tr):
        lt = _RUNS.get(tr)
        if lt is None:
            return {}
        out = {}
        for k, name in enumerate(lt.coordinates):
            out[name] = (lt.q[:, k], "")
            out[f"{name}_dot"] = (lt.qdot[:, k], "1/s")
        out["E"] = (lt.energy, "J")
        if lt.jacobi is not None:
            out["h"] = (lt.jacobi, "J")
        return out

    def checks(self, scenario, tr):
        lt = _RUNS.get(tr)
        if lt is None:
            return ()
        system = scenario.spec.system
        out = []
        # relative to the larger of |initial value| and the largest kinetic energy
        big = float(np.max(np.abs(lt.kinetic)))
        if lt.jacobi is not None:
            out.append(
                Check(
                    "jacobi",
                    "Jacobi integral h",
                    "J",
                    lt.jacobi,
                    scale=max(abs(float(lt.jacobi[0])), big) or None,
                    conserved=bool(system.jacobi_conserved),
                )  # fmt: skip
            )
        same = lt.jacobi is not None and np.allclose(lt.energy, lt.jacobi, rtol=1e-12, atol=0)
        if not same:
            out.append(Check("energy", "energy T + P", "J", lt.energy,
                             scale=max(abs(float(lt.energy[0])), big) or None,
                             conserved=False))  # fmt: skip
        return tuple(out)

    def figures(self, result):
        from ..figures import invariants_figure

        lt = _RUNS.get(result.trajectory)
        figs = [invariants_figure(result)]
        system = result.scenario.spec.system
        if lt is not None:

            def coords(ax, lt=lt):
                from ...plotting.lagrange import plot_coordinates

                return plot_coordinates(lt, ax=ax, title=f"{result.scenario.name}: coordinates")

            def phase(ax, lt=lt):
                from ...plotting.lagrange import plot_phase

                return plot_phase(lt, ax=ax)

            figs += [FigureSpec("coordinates.png", coords), FigureSpec("phase.png", phase)]

        def eqs(ax, system=system):
            from ...plotting.lagrange import plot_equations

            return plot_equations(system, ax=ax)

        n = len(system.coordinates) + len(system.multipliers)
        figs.append(FigureSpec("equations.svg", eqs, size=(9.0, 0.9 + 0.7 * n)))
        return [f for f in figs if f is not None]

    def report_sections(self, result):
        """The equations typeset as inline SVG for ``report.html`` (offline)."""
        import io

        from matplotlib.figure import Figure

        from ...plotting.lagrange import plot_equations

        system = result.scenario.spec.system
        n = len(system.coordinates)
        fig = Figure(figsize=(9.0, 0.9 + 0.7 * n))
        plot_equations(system, ax=fig.add_subplot())
        buf = io.StringIO()
        fig.savefig(buf, format="svg")
        svg = buf.getvalue()
        return [("Lagrange's equations (docs/theory.md §11)", svg[svg.index("<svg") :])]

    def describe_scenario(self, scenario):
        s = scenario.spec.system
        return [
            f"{self.title}: coordinates {', '.join(str(f.func) for f in s.coordinates)}, "
            f"{len(s.multipliers)} constraint multiplier(s)"
        ]


KIND = Lagrangian()
