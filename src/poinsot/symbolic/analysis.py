"""Analytical-mechanics tools on SymPy expressions (docs/theory.md §11): generalized
forces from applied forces, their change of coordinates, the kind of a kinematic
constraint (holonomic or not: Frobenius), and the test of a first integral.

Coordinates are SymPy functions of time (``dynamicsymbols``) or plain symbols.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import Any

from ..errors import InvalidInputError, InvalidTypeError
from .lagrange import LagrangeSystem

__all__ = [
    "generalized_forces",
    "transform_generalized_forces",
    "constraint_kind",
    "ConstraintKind",
    "is_first_integral",
    "FirstIntegralCheck",
]


def _sympy() -> Any:
    import sympy

    return sympy


def _list(x: Any, name: str) -> list[Any]:
    if isinstance(x, _sympy().MatrixBase):
        # a column or row vector: its entries; a matrix: its rows (one vector each)
        return list(x) if 1 in x.shape else [x.row(i) for i in range(x.rows)]
    if isinstance(x, str | bytes) or not hasattr(x, "__iter__"):
        raise InvalidTypeError(f"Expected `{name}` to be a sequence, got {type(x).__name__}.")
    return list(x)


def _vector(v: Any, name: str) -> Any:
    sp = _sympy()
    items = _list(v, name)
    if len(items) not in (2, 3):
        raise InvalidInputError(f"Expected `{name}` to have 2 or 3 components, got {len(items)}.")
    return sp.Matrix([sp.sympify(e) for e in items])


def generalized_forces(
    positions: Sequence[Any], forces: Sequence[Any], coordinates: Any
) -> list[Any]:
    """The generalized forces of applied forces ``F_i`` at points ``r_i(q, t)`` (theory §11).

    ``Q_k = sum_i F_i . dr_i/dq_k``.

    Parameters
    ----------
    positions : sequence of vectors
        ``r_i`` (2 or 3 SymPy expressions each, a list or a ``sympy.Matrix`` column
        or row) in terms of the coordinates; a matrix holds one per row.
    forces : sequence of vectors
        ``F_i`` (same number of components), any expressions; the same forms.
    coordinates : sequence
        ``q_k`` (``dynamicsymbols`` or symbols).

    Returns
    -------
    list of sympy.Expr
        One ``Q_k`` per coordinate (simplified), ready for
        ``LagrangeSystem(..., generalized_forces=Q)``.

    Examples
    --------
    A pendulum bob at ``(l sin th, -l cos th)`` pushed by a horizontal force ``F``:

    >>> import sympy
    >>> from sympy.physics.mechanics import dynamicsymbols
    >>> th = dynamicsymbols("theta")
    >>> l, F = sympy.symbols("l F")
    >>> generalized_forces([[l * sympy.sin(th), -l * sympy.cos(th)]], [[F, 0]], [th])
    [F*l*cos(theta(t))]
    """
    sp = _sympy()
    rs = [_vector(r, f"positions[{i}]") for i, r in enumerate(_list(positions, "positions"))]
    fs = [_vector(f, f"forces[{i}]") for i, f in enumerate(_list(forces, "forces"))]
    if len(rs) != len(fs):
        raise InvalidInputError(
            f"Expected as many `forces` as `positions`, got {len(fs)} and {len(rs)}."
        )
    for i, (r, f) in enumerate(zip(rs, fs, strict=True)):
        if r.shape != f.shape:
            raise InvalidInputError(
                f"Expected `forces[{i}]` to have the {r.shape[0]} components of `positions[{i}]`."
            )
    qs = _list(coordinates, "coordinates")
    return [
        sp.simplify(sum((f.dot(r.diff(q)) for r, f in zip(rs, fs, strict=True)), sp.Integer(0)))
        for q in qs
    ]


def transform_generalized_forces(
    forces: Sequence[Any], old: Sequence[Any], new: Sequence[Any], mapping: Sequence[Any]
) -> list[Any]:
    """Generalized forces in new coordinates: ``Q_new = J^T Q_old`` (covariant),
    ``J_kl = d q_old_k / d q_new_l`` (theory §11).

    Parameters
    ----------
    forces : sequence
        ``Q_old`` (expressions in the old or new coordinates).
    old, new : sequence
        The old and new coordinates.
    mapping : sequence
        ``q_old_k`` as expressions of the new coordinates (and time).

    Examples
    --------
    A radial force ``f`` in Cartesian ``(x, y)``, read in polar ``(r, phi)``:

    >>> import sympy
    >>> x, y, r, phi, f = sympy.symbols("x y r phi f")
    >>> transform_generalized_forces(
    ...     [f * sympy.cos(phi), f * sympy.sin(phi)], [x, y], [r, phi],
    ...     [r * sympy.cos(phi), r * sympy.sin(phi)])
    [f, 0]
    """
    sp = _sympy()
    q_old = _list(forces, "forces")
    olds, news, maps = _list(old, "old"), _list(new, "new"), _list(mapping, "mapping")
    if not len(q_old) == len(olds) == len(maps):
        raise InvalidInputError(
            "Expected `forces`, `old` and `mapping` of one length (one per old coordinate), "
            f"got {len(q_old)}, {len(olds)} and {len(maps)}."
        )
    subs = dict(zip(olds, maps, strict=True))
    jac = sp.Matrix([[sp.sympify(m).diff(n) for n in news] for m in maps])
    q = sp.Matrix([sp.sympify(e).subs(subs) for e in q_old])
    return [sp.simplify(e) for e in (jac.T * q)]


@dataclass(frozen=True)
class ConstraintKind:
    """What :func:`constraint_kind` found for a kinematic constraint.

    The constraint is ``a(q, t) . q' + b(q, t) = 0``.

    Attributes
    ----------
    holonomic : bool
        Integrable (Frobenius: ``w ^ dw = 0`` for ``w = a . dq + b dt``): equivalent to
        ``f(q, t) = const``.
    stationary : bool
        ``b = 0`` and ``a`` independent of time.
    integrating_factor : sympy.Expr or None
        ``mu`` with ``mu (a . dq + b dt)`` exact, when one was found.
    integral : sympy.Expr or None
        ``f`` with ``df = mu (a . dq + b dt)`` (the holonomic form ``f = const``).
    residual : list of sympy.Expr
        The components of ``w ^ dw`` (all zero for an integrable constraint).
    """

    holonomic: bool
    stationary: bool
    integrating_factor: Any
    integral: Any
    residual: list[Any]


def _plain(coords: list[Any], time: Any) -> tuple[list[Any], dict[Any, Any], dict[Any, Any]]:
    """Plain symbols for coordinates given as functions of time, and the maps both ways."""
    sp = _sympy()
    plain, to_plain, back = [], {}, {}
    for k, q in enumerate(coords):
        if isinstance(q, sp.Symbol):
            plain.append(q)
        else:
            s = sp.Dummy(f"q{k}")
            plain.append(s)
            to_plain[q] = s
            back[s] = q
    return plain, to_plain, back


def constraint_kind(
    coefficients: Sequence[Any], coordinates: Sequence[Any], bias: Any = 0, *, time: Any = None
) -> ConstraintKind:
    """Whether a kinematic constraint linear in the velocities is holonomic (theory §11).

    The constraint is ``a(q, t) . q' + b(q, t) = 0``.

    Frobenius: the 1-form ``w = sum a_k dq_k + b dt`` is integrable iff
    ``w ^ dw = 0``, i.e. ``a_i (d_j a_k - d_k a_j) + a_j (d_k a_i - d_i a_k) +
    a_k (d_i a_j - d_j a_i) = 0`` for every triple of variables (time a variable when
    the constraint depends on it). In two variables every constraint is integrable.
    An integrating factor is searched among ``1``, ``1/a_k`` and factors of one
    variable; with it, the integral ``f`` with ``df = mu w``.

    Parameters
    ----------
    coefficients : sequence
        ``a_k(q, t)``, one per coordinate.
    coordinates : sequence
        ``q_k`` (symbols, or functions of ``time``).
    bias : expression, optional
        ``b(q, t)`` (default 0).
    time : sympy.Symbol, optional
        The time symbol (default ``sympy.physics.mechanics.dynamicsymbols._t``).

    Examples
    --------
    >>> import sympy
    >>> x, y, phi = sympy.symbols("x y phi")
    >>> c = constraint_kind([x, y], [x, y])              # x x' + y y' = 0
    >>> c.holonomic, c.stationary, sympy.simplify(c.integral - (x**2 + y**2) / 2)
    (True, True, 0)
    >>> constraint_kind([-sympy.tan(phi), 1, 0], [x, y, phi]).holonomic   # Chaplygin skate
    False
    """
    sp = _sympy()
    if time is None:
        from sympy.physics.mechanics import dynamicsymbols

        time = dynamicsymbols._t
    coords = _list(coordinates, "coordinates")
    a = [sp.sympify(e) for e in _list(coefficients, "coefficients")]
    if len(a) != len(coords):
        raise InvalidInputError(
            f"Expected one coefficient per coordinate, got {len(a)} for {len(coords)}."
        )
    plain, to_plain, back = _plain(coords, time)
    a = [e.subs(to_plain) for e in a]
    b = sp.sympify(bias).subs(to_plain)
    for e in (*a, b):
        if any(isinstance(d, sp.Derivative) for d in e.atoms(sp.Derivative)):
            raise InvalidInputError(
                "Expected coefficients a(q, t) and bias b(q, t) without velocities "
                f"(a constraint linear in q'), got {e}."
            )
    stationary = b == 0 and not any(e.has(time) for e in a)
    vars_ = list(plain)
    comps = list(a)
    if not stationary:
        vars_.append(time)
        comps.append(b)
    residual = []
    for i, j, k in combinations(range(len(vars_)), 3):
        ai, aj, ak = comps[i], comps[j], comps[k]
        xi, xj, xk = vars_[i], vars_[j], vars_[k]
        expr = (
            ai * (ak.diff(xj) - aj.diff(xk))
            + aj * (ai.diff(xk) - ak.diff(xi))
            + ak * (aj.diff(xi) - ai.diff(xj))
        )
        residual.append(sp.simplify(expr))
    holonomic = all(r == 0 for r in residual)
    mu, integral = (None, None)
    if holonomic:
        mu, integral = _integrate(comps, vars_)
    residual = [r.subs(back) for r in residual]
    return ConstraintKind(
        holonomic,
        bool(stationary),
        None if mu is None else mu.subs(back),
        None if integral is None else integral.subs(back),
        residual,
    )


def _integrate(comps: list[Any], vars_: list[Any]) -> tuple[Any, Any]:
    """An integrating factor and the integral of ``sum comps_k d vars_k``, if found."""
    sp = _sympy()
    candidates = [sp.Integer(1)] + [1 / c for c in comps if c != 0]
    n = len(vars_)
    if n == 2:  # mu of one variable: the classical tests
        p, q = comps
        x, y = vars_
        if q != 0:
            g = sp.simplify((p.diff(y) - q.diff(x)) / q)
            if not g.has(y):
                candidates.append(sp.exp(sp.integrate(g, x)))
        if p != 0:
            h = sp.simplify((q.diff(x) - p.diff(y)) / p)
            if not h.has(x):
                candidates.append(sp.exp(sp.integrate(h, y)))
    for mu in candidates:
        form = [sp.simplify(mu * c) for c in comps]
        exact = all(
            sp.simplify(form[i].diff(vars_[j]) - form[j].diff(vars_[i])) == 0
            for i, j in combinations(range(n), 2)
        )
        if not exact:
            continue
        f = sp.Integer(0)
        for k, x in enumerate(vars_):
            rest = sp.simplify(form[k] - f.diff(x))
            f = f + sp.integrate(rest, x)
        return mu, sp.simplify(f)
    return None, None


@dataclass(frozen=True)
class FirstIntegralCheck:
    """What :func:`is_first_integral` found.

    Attributes
    ----------
    is_integral : bool
        ``dG/dt + grad G . F`` simplifies to 0.
    residual : sympy.Expr
        That expression (its value when ``G`` is not conserved).
    """

    is_integral: bool
    residual: Any


def is_first_integral(
    quantity: Any, system: Any, states: Sequence[Any] | None = None, *, time: Any = None
) -> FirstIntegralCheck:
    """The symbolic test of a first integral ``G`` of ``x' = F(x, t)`` (theory §11).

    ``G`` is conserved iff ``dG/dt + grad G . F = 0``.

    Parameters
    ----------
    quantity : sympy.Expr
        ``G(x, t)``; for a :class:`LagrangeSystem`, an expression of its coordinates
        ``q(t)`` and their derivatives ``q'(t)``.
    system : sequence or LagrangeSystem
        The right-hand sides ``F`` (one per state), or a ``LagrangeSystem`` without
        constraints (then ``x = (q, q')`` and ``F = (q', M^-1 f)``).
    states : sequence, optional
        The states ``x`` (required with a sequence ``F``).
    time : sympy.Symbol, optional
        The time symbol (default ``dynamicsymbols._t``).

    Examples
    --------
    >>> import sympy
    >>> x, v, k, c = sympy.symbols("x v k c")
    >>> is_first_integral(v**2 / 2 + k * x**2 / 2, [v, -k * x], [x, v]).is_integral
    True
    >>> is_first_integral(v**2 / 2 + k * x**2 / 2, [v, -k * x - c * v], [x, v]).residual
    -c*v**2
    """
    sp = _sympy()

    if time is None:
        from sympy.physics.mechanics import dynamicsymbols

        time = dynamicsymbols._t
    g = sp.sympify(quantity)
    if isinstance(system, LagrangeSystem):
        if system.multipliers:
            raise InvalidInputError(
                "Expected a LagrangeSystem without constraints (eliminate them first), "
                f"got {len(system.multipliers)} constraint(s)."
            )
        qs = list(system.coordinates)
        vs = [q.diff(time) for q in qs]
        acc = system.mass_matrix.LUsolve(system.forcing)
        xs, fs = qs + vs, vs + list(acc)
        plain, to_plain, back = _plain(xs, time)
        # derivatives first: q'(t) before q(t), so that q' is not touched by q's symbol
        order = sorted(to_plain.items(), key=lambda kv: -sp.count_ops(kv[0]))
        g = g.subs(order)
        fs = [sp.sympify(f).subs(order) for f in fs]
        xs = plain
        from sympy.core.function import AppliedUndef

        if g.atoms(AppliedUndef) or g.atoms(sp.Derivative):
            raise InvalidInputError(
                f"Expected `quantity` in the system's coordinates and their rates, got {g}."
            )
    else:
        back = {}
        if states is None:
            raise InvalidInputError("Expected `states` with a sequence of right-hand sides.")
        xs = _list(states, "states")
        fs = [sp.sympify(f) for f in _list(system, "system")]
        if len(xs) != len(fs):
            raise InvalidInputError(
                f"Expected one right-hand side per state, got {len(fs)} for {len(xs)}."
            )
    residual = g.diff(time) + sum((g.diff(x) * f for x, f in zip(xs, fs, strict=True)), 0)
    residual = sp.simplify(residual).subs(back)  # in the system's own q(t), q'(t)
    return FirstIntegralCheck(residual == 0, residual)
