"""The one table of integration methods: each name is defined once, here.

Every public function that takes a ``method`` (:func:`poinsot.kinematics.propagate`,
:func:`poinsot.dynamics.simulate`, :meth:`poinsot.dynamics.HeavyRigidBody.simulate`,
:func:`poinsot.dynamics.simulate_particle`, :meth:`poinsot.symbolic.NumericLagrangian.simulate`),
the scenario kinds, the command line and the docs (``docs/integrators.md``) read
:data:`INTEGRATORS`: a name means the same integrator everywhere. poinsot's own
methods have lower-case names (``"dop853"`` is poinsot's compiled DOP853 with the
quaternion kept unit); SciPy's ``solve_ivp`` methods keep SciPy's spelling
(``"DOP853"``, ``"Radau"``...), so the two DOP853 cannot be confused.

Systems (what a method can integrate):

- ``"attitude"``: the kinematic equations with a given angular velocity (theory §5);
- ``"rigid"``: Euler's dynamic equations with the attitude, free or under a torque,
  the heavy top included (theory §10);
- ``"particle"``: a point in a moving frame or a central field (theory §9);
- ``"lagrangian"``: Lagrange's equations of a system in generalized coordinates
  (theory §11);
- ``"exact"``: a closed-form solution (whichever system has one).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from .errors import InvalidInputError, InvalidTypeError

__all__ = [
    "Integrator",
    "INTEGRATORS",
    "SYSTEMS",
    "names",
    "orders",
    "check_method",
    "check_options",
    "markdown_table",
]

#: The kinds of equations a method may integrate (see the module notes).
SYSTEMS = ("attitude", "rigid", "particle", "lagrangian", "estimation")


@dataclass(frozen=True)
class Integrator:
    """One integration method.

    Attributes
    ----------
    name : str
        The name every API and scenario file uses.
    description : str
        What it is, in one line.
    order : int or None
        Order of accuracy of a fixed-step method (the base step; ``None`` for an
        adaptive or exact method).
    adaptive : bool
        True if it controls its error (takes ``rtol``/``atol``).
    systems : tuple of str
        The systems of :data:`SYSTEMS` it integrates.
    implementation : str
        What runs it: ``"poinsot (compiled)"``, ``"poinsot (NumPy)"``,
        ``"scipy.integrate.solve_ivp"`` or ``"closed form"``.
    theory : str
        The section of ``docs/theory.md`` it implements.
    options : tuple of str
        The keyword options of :func:`poinsot.dynamics.simulate` it takes (beyond the
        problem): what :func:`check_options` lets through.
    cost : mapping of str to float
        Seconds per step (one body, one core) by system, for the cost estimates of
        ``poinsot check``/``run`` (measured by ``benchmarks/bench_estimates.py``).

    Examples
    --------
    >>> INTEGRATORS["rk4"].order, INTEGRATORS["rk4"].adaptive
    (4, False)
    """

    name: str
    description: str
    order: int | None
    adaptive: bool
    systems: tuple[str, ...]
    implementation: str
    theory: str
    options: tuple[str, ...] = ()
    cost: Mapping[str, float] = field(default_factory=dict, hash=False)


def _scipy(name: str, what: str) -> Integrator:
    return Integrator(
        name,
        f"SciPy's solve_ivp {name}: {what}",
        None,
        True,
        ("particle", "lagrangian"),
        "scipy.integrate.solve_ivp",
        "§9, §11",
    )


#: Every integration method, by name (the order of the docs table).
INTEGRATORS: dict[str, Integrator] = {
    i.name: i
    for i in (
        Integrator(
            "exact",
            "the closed-form solution (Euler-Poinsot, Lagrange top, coning, Kepler)",
            None,
            False,
            ("attitude", "rigid", "particle"),
            "closed form",
            "§5, §9, §10",
            cost={"rigid": 6e-07},
        ),
        Integrator(
            "mekf",
            "the multiplicative EKF: the attitude propagated exactly at the measured rate "
            "between sensor samples and updated by them (an estimator)",
            None,
            False,
            ("estimation",),
            "poinsot (NumPy)",
            "§10.4",
        ),
        Integrator(
            "magnus4",
            "fourth-order Magnus expansion of the rotation over a step",
            4,
            False,
            ("attitude",),
            "poinsot (NumPy)",
            "§5",
        ),
        Integrator(
            "magnus6",
            "sixth-order Magnus expansion of the rotation over a step",
            6,
            False,
            ("attitude",),
            "poinsot (NumPy)",
            "§5",
        ),
        Integrator(
            "exponential",
            "the exact rotation for omega held constant over each step",
            2,
            False,
            ("attitude",),
            "poinsot (NumPy)",
            "§5",
        ),
        Integrator(
            "midpoint",
            "implicit Lie-Poisson midpoint rule (composable to order 4, 6)",
            2,
            False,
            ("rigid",),
            "poinsot (compiled)",
            "§10",
            ("max_step", "order"),
            cost={"rigid": 2.5e-06},
        ),
        Integrator(
            "splitting",
            "free-body Lie-Poisson splitting with exact torque kicks (composable)",
            2,
            False,
            ("rigid",),
            "poinsot (compiled)",
            "§10",
            ("max_step", "order"),
            cost={"rigid": 1e-06},
        ),
        Integrator(
            "rk4",
            "classical Runge-Kutta, quaternion renormalised after each step",
            4,
            False,
            ("attitude", "rigid"),
            "poinsot (compiled)",
            "§5, §10",
            ("max_step",),
            cost={"rigid": 1e-06},
        ),
        Integrator(
            "dop853",
            "poinsot's compiled Dormand-Prince 8(5,3) with step control, quaternion kept unit",
            None,
            True,
            ("rigid",),
            "poinsot (compiled)",
            "§10",
            ("max_step", "rtol", "atol", "failures"),
            cost={"rigid": 5e-07},
        ),
        Integrator(
            "adaptive",
            "scipy.integrate.solve_ivp (its `solver`, DOP853 by default) with step control",
            None,
            True,
            ("attitude", "rigid", "particle"),
            "scipy.integrate.solve_ivp",
            "§5, §9, §10",
            ("max_step", "rtol", "atol", "solver"),
            cost={"rigid": 0.00015},
        ),
        _scipy("DOP853", "explicit Runge-Kutta of order 8"),
        _scipy("RK45", "explicit Runge-Kutta of order 5(4)"),
        _scipy("RK23", "explicit Runge-Kutta of order 3(2)"),
        _scipy("Radau", "implicit Runge-Kutta (Radau IIA) of order 5, for stiff problems"),
        _scipy("BDF", "implicit backward differentiation formulas, for stiff problems"),
        _scipy("LSODA", "Adams/BDF with automatic stiffness detection"),
    )
}


def names(system: str, *, exact: bool = False) -> tuple[str, ...]:
    """The method names that integrate ``system`` (``exact=True`` includes ``"exact"``).

    Examples
    --------
    >>> names("attitude")
    ('magnus4', 'magnus6', 'exponential', 'rk4', 'adaptive')
    """
    if system not in SYSTEMS:
        raise InvalidInputError(f"Expected `system` to be one of {SYSTEMS}, got {system!r}.")
    return tuple(
        n for n, i in INTEGRATORS.items() if system in i.systems and (exact or n != "exact")
    )


def orders(methods: Iterable[str]) -> dict[str, int]:
    """``name -> order`` of the fixed-step methods among ``methods`` (for step advice).

    Examples
    --------
    >>> orders(["midpoint", "rk4", "adaptive"])
    {'midpoint': 2, 'rk4': 4}
    """
    out = {}
    for m in methods:
        order = INTEGRATORS[m].order
        if order is not None:
            out[m] = order
    return out


def check_method(method: object, allowed: Iterable[str], what: str, name: str = "method") -> str:
    """``method`` if it is among ``allowed``; else a named error that lists them and,
    for a method of another system, says which one it is.

    Examples
    --------
    >>> check_method("rk4", names("rigid"), "a rigid body")
    'rk4'
    >>> check_method("Radau", names("rigid"), "a rigid body")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    poinsot.errors.InvalidInputError: Expected `method` to be one of ... got 'Radau' ...
    """
    allowed = tuple(allowed)
    opts = ", ".join(repr(a) for a in allowed)
    if not isinstance(method, str):
        raise InvalidTypeError(
            f"Expected `{name}` to be one of {opts} (a string naming a method for {what}), "
            f"got {type(method).__name__} {method!r}."
        )
    if method in allowed:
        return method
    hints = []
    known = INTEGRATORS.get(method)
    if known is not None:
        hints.append(f"{method!r} is {known.description}, for: {', '.join(known.systems)}")
    near = [a for a in allowed if a.lower() == method.lower()]
    if near:
        hints.append(f"did you mean {near[0]!r}?")
    hint = f" ({'; '.join(hints)})" if hints else ""
    raise InvalidInputError(
        f"Expected `{name}` to be one of {opts} (the methods for {what}), got {method!r}{hint}."
    )


def markdown_table() -> str:
    """The table of ``docs/integrators.md`` (a test checks that the page holds it).

    Examples
    --------
    >>> markdown_table().splitlines()[0]
    '| method | what it is | order | adaptive | systems | runs in | theory |'
    """
    rows = [
        "| method | what it is | order | adaptive | systems | runs in | theory |",
        "|---|---|---|---|---|---|---|",
    ]
    for i in INTEGRATORS.values():
        order = "-" if i.order is None else str(i.order)
        rows.append(
            f"| `{i.name}` | {i.description} | {order} | {'yes' if i.adaptive else 'no'} | "
            f"{', '.join(i.systems)} | {i.implementation} | {i.theory} |"
        )
    return "\n".join(rows)


def check_options(method: str, given: Mapping[str, object], among: Iterable[str]) -> None:
    """Refuse an option that ``method`` does not take (its row's ``options``), naming the
    methods of ``among`` that take it; options given as ``None`` are not given.

    Examples
    --------
    >>> check_options("dop853", {"rtol": 1e-8, "solver": None}, ["rk4", "dop853"])
    >>> try:
    ...     check_options("rk4", {"rtol": 1e-8}, ["rk4", "dop853", "adaptive"])
    ... except InvalidInputError as e:
    ...     print(str(e)[:60])
    `rtol` applies to method='dop853' or 'adaptive' only (method
    """
    facts = INTEGRATORS[method]
    for name, value in given.items():
        if value is None or name in facts.options:
            continue
        takers = " or ".join(repr(m) for m in among if name in INTEGRATORS[m].options)
        what = facts.description
        if name in ("rtol", "atol") and not facts.adaptive:
            what += ", without tolerances: set its accuracy with `max_step`"
            what += " and `order`" if "order" in facts.options else ""
        raise InvalidInputError(
            f"`{name}` applies to method={takers} only (method={method!r} is {what}), "
            f"got {name}={value!r}."
        )
