"""Lagrange's equations of the second kind (docs/theory.md §11).

For generalized coordinates ``q`` with velocities ``q'``, kinetic energy
``T(q, q', t)``, potential ``P(q, t)``, a generalized potential
``V = q'^T Y(q, t) + V0(q, t)`` and non-potential generalized forces ``Q*``:

``E_k L = Q*_k + sum_j lambda_j A_jk``,  ``L = T - P - V``,
``E_k = d/dt d/dq'^k - d/dq^k``,

with the constraints kept as ``A(q, t) q' + b(q, t) = 0`` (a holonomic
``f(q, t) = 0`` enters through ``A = df/dq``, ``b = df/dt``; a kinematic,
possibly non-holonomic one ``C(q, t) q' + b = 0`` as it is) and their
multipliers ``lambda``. Writing ``E_k L = sum_j M_kj q''_j - (F_k - Q*_k)``:

``M = d^2 L / dq' dq'``,
``F = Q* + dL/dq - (d^2 L / dq' dq) q' - d^2 L / dq' dt``,

and the equations of motion are the linear system

``[[M, -A^T], [A, 0]] [q'', lambda] = [F, -gamma]``,  ``gamma = (d/dt)(A q' + b) - A q''``.

The derivation differentiates with respect to plain symbols standing for ``q``,
``q'`` (no time derivatives of ``dynamicsymbols``); ``M`` is never inverted
symbolically: :meth:`LagrangeSystem.to_numeric` solves the system numerically.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import as_float_array, as_times
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError, PoinsotWarning
from ..events import EventLog
from ..trajectory import CoordinateTrajectory
from ._symbols import Coordinates, as_coordinates
from .numeric import NumericLagrangian

if TYPE_CHECKING:
    from .._typing import ArrayLike
    from .numeric import LagrangeTrajectory, NumericLagrangian

__all__ = ["LagrangeSystem"]


def _is_zero(expr: Any) -> bool:
    import sympy

    if expr == 0:
        return True
    e = sympy.expand(expr)
    if e == 0:
        return True
    return sympy.simplify(e) == 0


def _expr(value: Any, name: str, coords: Coordinates) -> Any:
    import sympy
    from sympy.core.function import AppliedUndef

    if isinstance(value, str):
        raise InvalidTypeError(
            f"Expected `{name}` to be a SymPy expression, got the string {value!r} "
            "(parse text with poinsot.symbolic.parse_expression)."
        )
    try:
        e = sympy.sympify(value, strict=True)
    except (sympy.SympifyError, TypeError):
        raise InvalidTypeError(
            f"Expected `{name}` to be a SymPy expression or a number, got {type(value).__name__}."
        ) from None
    if not isinstance(e, sympy.Expr):
        raise InvalidTypeError(f"Expected `{name}` to be a scalar expression, got {e!r}.")
    plain = coords.to_plain(e)
    stray = [f for f in plain.atoms(AppliedUndef)] + [d for d in plain.atoms(sympy.Derivative)]
    if stray:
        raise InvalidInputError(
            f"Expected `{name}` to depend on the coordinates {list(coords.funcs)}, their "
            f"first derivatives, parameters and {coords.time} only, found {stray[0]}."
        )
    if set(coords.acc) & plain.free_symbols:
        raise InvalidInputError(f"Expected `{name}` not to depend on accelerations, got {e}.")
    return plain


def _matrix(value: Any, name: str, coords: Coordinates, n: int) -> Any:
    import sympy

    m = sympy.Matrix(value)
    if m.shape != (n, n):
        raise InvalidInputError(f"Expected `{name}` to be a {n}x{n} matrix, got shape {m.shape}.")
    return m.applyfunc(lambda e: _expr(e, name, coords))


class LagrangeSystem:
    """A mechanical system given by its Lagrangian (theory §11).

    ``E_k L = Q*_k`` with ``L = T - P`` (minus a generalized potential), plus
    constraint forces with multipliers.

    Parameters
    ----------
    coordinates : sequence of str, sympy.Symbol or dynamicsymbols
        Generalized coordinates ``q^k``; names and symbols become functions of
        ``time`` (``dynamicsymbols``).
    kinetic : sympy.Expr
        Kinetic energy ``T(q, q', t)``, written with ``q(t)`` and ``q(t).diff(t)``.
    potential : sympy.Expr, optional
        Potential energy ``P(q, t)`` (default 0).
    generalized_forces : sequence of n expressions or (n, n) matrix, optional
        Non-potential forces ``Q*_k(q, q', t)``, or an antisymmetric gyroscopic
        matrix ``G(q, t)`` meaning ``Q* = G q'`` (``G^T = -G``; checked).
    generalized_potential : sympy.Expr or (n, n) matrix, optional
        ``V(q, q', t)`` with ``Q_k = E_k V``; it must be linear in the velocities,
        ``V = q'^T Y(q, t) + V0(q, t)`` (anything else is rejected with the
        reason). A constant antisymmetric matrix ``G`` means ``V = q'^T G q / 2``
        (gyroscopic forces ``Q = G q'``).
    holonomic : sequence of sympy.Expr, optional
        Constraints ``f_j(q, t) = 0``, kept with multipliers unless eliminated.
    nonholonomic : sequence of sympy.Expr, optional
        Kinematic constraints ``c_j = C_j(q, t) q' + b_j(q, t) = 0`` (linear in the
        velocities; checked), e.g. the Chaplygin sleigh ``y' cos(phi) - x' sin(phi)``.
    eliminate : sequence, optional
        Coordinates to eliminate with the holonomic constraints (as many as
        there are constraints): the constraints are solved for them and
        substituted (the reduced system has the other coordinates and no
        multipliers for them). Default: keep every coordinate, with multipliers.
    time : sympy.Symbol, optional
        The time symbol (default ``dynamicsymbols._t``).

    Notes
    -----
    Sign of the multipliers: ``E_k L = Q*_k + sum_j lambda_j A_jk`` where the
    constraints read ``A q' + b = 0`` at the velocity level (``A = df/dq`` for a
    holonomic ``f``). Equations, energy, momenta are returned in terms of
    ``q(t)``, ``q'(t)``, ``q''(t)``. See ``docs/lagrange.md``.

    **Convention:** SI units; ``mass_matrix``/``forcing`` are ``M``, ``F`` with
    ``M q'' = F + A^T lambda``; parameters are the remaining free symbols.

    Examples
    --------
    A pendulum of length ``l``, angle ``theta`` from the downward vertical:

    >>> import sympy
    >>> from sympy.physics.mechanics import dynamicsymbols
    >>> th = dynamicsymbols("theta")
    >>> m, g, l = sympy.symbols("m g l", positive=True)
    >>> pend = LagrangeSystem([th], m * l**2 * th.diff() ** 2 / 2, -m * g * l * sympy.cos(th))
    >>> pend.mass_matrix, pend.forcing
    (Matrix([[l**2*m]]), Matrix([[-g*l*m*sin(theta(t))]]))
    >>> pend.energy()
    -g*l*m*cos(theta(t)) + l**2*m*Derivative(theta(t), t)**2/2
    """

    def __init__(
        self,
        coordinates: Any,
        kinetic: Any,
        potential: Any = 0,
        *,
        generalized_forces: Any = None,
        generalized_potential: Any = None,
        holonomic: Any = (),
        nonholonomic: Any = (),
        eliminate: Any = (),
        time: Any = None,
    ) -> None:
        import sympy

        c = as_coordinates(coordinates, time)
        n = len(c.plain)
        t = c.time
        T = _expr(kinetic, "kinetic", c)
        P = _expr(potential, "potential", c)
        if set(c.vel) & P.free_symbols:
            raise InvalidInputError(
                f"Expected `potential` not to depend on the velocities, got {potential} "
                "(velocity-dependent forces go in `generalized_potential`)."
            )
        # generalized potential
        V = sympy.Integer(0)
        if generalized_potential is not None:
            if isinstance(generalized_potential, sympy.MatrixBase | list | tuple):
                G = _matrix(generalized_potential, "generalized_potential", c, n)
                if not all(_is_zero(e) for e in G + G.T):
                    raise InvalidInputError(
                        "Expected `generalized_potential` given as a matrix to be antisymmetric "
                        f"(G^T = -G), got {G}."
                    )
                if (G.free_symbols & (set(c.plain) | {t})) or (G.free_symbols & set(c.vel)):
                    raise InvalidInputError(
                        "Expected the gyroscopic matrix in `generalized_potential` to be "
                        f"constant (V = q'^T G q / 2), got {G}; pass a G(q, t) as "
                        "`generalized_forces`."
                    )
                V = (sympy.Matrix([c.vel]) * G * sympy.Matrix(c.plain))[0, 0] / 2
            else:
                V = _expr(generalized_potential, "generalized_potential", c)
            for i in range(n):
                for k in range(i, n):
                    d2 = V.diff(c.vel[i], c.vel[k])
                    if not _is_zero(d2):
                        raise InvalidInputError(
                            "Expected `generalized_potential` to be linear in the velocities "
                            "(V = q'^T Y(q, t) + V0(q, t), docs/theory.md §11), but "
                            f"d^2V/d{c.velocities[i]}d{c.velocities[k]} = "
                            f"{c.to_funcs(d2)} is not zero."
                        )
        # non-potential forces
        Q = sympy.zeros(n, 1)
        self._gyroscopic = True
        if generalized_forces is not None:
            gf = generalized_forces
            if (
                isinstance(gf, sympy.MatrixBase)
                and gf.shape == (n, n)
                and n > 1
                or (isinstance(gf, list | tuple) and gf and isinstance(gf[0], list | tuple))
            ):
                G = _matrix(gf, "generalized_forces", c, n)
                if not all(_is_zero(e) for e in G + G.T):
                    raise InvalidInputError(
                        "Expected the gyroscopic matrix `generalized_forces` to be "
                        f"antisymmetric (G^T = -G), got {G}."
                    )
                if G.free_symbols & set(c.vel):
                    raise InvalidInputError(
                        "Expected the gyroscopic matrix G(q, t) not to depend on velocities, "
                        f"got {G}."
                    )
                Q = G * sympy.Matrix(c.vel)
            else:
                items = list(gf) if not isinstance(gf, sympy.Basic) or gf.is_Matrix else [gf]
                if len(items) != n:
                    raise InvalidInputError(
                        f"Expected `generalized_forces` to have {n} components (one per "
                        f"coordinate) or be an {n}x{n} gyroscopic matrix, got {len(items)}."
                    )
                Q = sympy.Matrix([_expr(e, "generalized_forces", c) for e in items])
                self._gyroscopic = all(_is_zero(e) for e in Q)
        hol = [_expr(f, "holonomic", c) for f in _seq(holonomic, "holonomic")]
        for f in hol:
            if f.free_symbols & set(c.vel):
                raise InvalidInputError(
                    f"Expected `holonomic` constraints f(q, t) without velocities, got "
                    f"{c.to_funcs(f)} (put kinematic constraints in `nonholonomic`)."
                )
        nonhol = [_expr(f, "nonholonomic", c) for f in _seq(nonholonomic, "nonholonomic")]
        for f in nonhol:
            for i in range(n):
                for k in range(i, n):
                    if not _is_zero(f.diff(c.vel[i], c.vel[k])):
                        raise InvalidInputError(
                            "Expected `nonholonomic` constraints linear in the velocities "
                            f"(C(q, t) q' + b = 0), got {c.to_funcs(f)}."
                        )
        elim = list(_seq(eliminate, "eliminate"))
        if elim:
            c, T, P, V, Q, hol, nonhol = _eliminate(c, elim, T, P, V, Q, hol, nonhol)
        self._c = c
        self._T, self._P, self._V, self._Q = T, P, V, Q
        self._hol, self._nonhol = tuple(hol), tuple(nonhol)

    # ------------------------------------------------------------------ basics
    @property
    def coordinates(self) -> tuple[Any, ...]:
        """The generalized coordinates ``q(t)`` (after any elimination)."""
        return self._c.funcs

    @property
    def velocities(self) -> tuple[Any, ...]:
        """``q'(t)``."""
        return self._c.velocities

    @property
    def time(self) -> Any:
        """The time symbol."""
        return self._c.time

    @cached_property
    def _L(self) -> Any:
        return self._T - self._P - self._V

    @property
    def lagrangian(self) -> Any:
        """``L = T - P - V`` in ``q(t)``, ``q'(t)``."""
        return self._c.to_funcs(self._L)

    def printable(self, expr: Any, *, latex: bool = False) -> Any:
        """``expr`` with each coordinate ``q(t)``, its rates and the multipliers as
        plain symbols, for text (``theta1``, ``theta1'``, ``theta1''``, ``lambda1``)
        or, with ``latex``, for LaTeX (``\\theta_{1}``, ``\\dot{\\theta_{1}}``...).

        Examples
        --------
        >>> import sympy
        >>> from sympy.physics.mechanics import dynamicsymbols
        >>> x = dynamicsymbols("x")
        >>> s = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2)
        >>> str(s.printable(s.lagrangian))
        "-x**2/2 + x'**2/2"
        >>> sympy.latex(s.printable(s.lagrangian, latex=True))
        '\\\\frac{\\\\dot{x}^{2}}{2} - \\\\frac{x^{2}}{2}'
        """
        import sympy

        t = self.time
        rates, plain = {}, {}
        for f in self.coordinates:
            name = f.func.__name__
            base = sympy.latex(sympy.Symbol(name)) if latex else name
            rates[f.diff(t, 2)] = sympy.Symbol(rf"\ddot{{{base}}}" if latex else f"{name}''")
            rates[f.diff(t)] = sympy.Symbol(rf"\dot{{{base}}}" if latex else f"{name}'")
            plain[f] = sympy.Symbol(base)
        for lam in self.multipliers:
            k = lam.func.__name__[3:]
            rates[lam] = sympy.Symbol(rf"\lambda_{{{k}}}" if latex else f"lambda{k}")
        return sympy.sympify(expr).xreplace(rates).xreplace(plain)

    @property
    def kinetic(self) -> Any:
        """The kinetic energy ``T``."""
        return self._c.to_funcs(self._T)

    @property
    def potential(self) -> Any:
        """The potential energy ``P``."""
        return self._c.to_funcs(self._P)

    @cached_property
    def parameters(self) -> tuple[Any, ...]:
        """The free symbols other than coordinates and time, sorted by name."""
        exprs = [self._T, self._P, self._V, *self._Q, *self._hol, *self._nonhol]
        known = set(self._c.plain) | set(self._c.vel) | {self._c.time}
        free = set().union(*(e.free_symbols for e in exprs)) - known
        return tuple(sorted(free, key=lambda s: s.name))

    @property
    def degrees_of_freedom(self) -> int:
        """Coordinates minus kept constraints, holonomic and nonholonomic (theory §11).

        Examples
        --------
        >>> import sympy
        >>> from sympy.physics.mechanics import dynamicsymbols
        >>> x, y = dynamicsymbols("x y")
        >>> LagrangeSystem([x, y], (x.diff() ** 2 + y.diff() ** 2) / 2,
        ...                holonomic=[x**2 + y**2 - 1]).degrees_of_freedom
        1
        """
        return len(self._c.plain) - len(self._hol) - len(self._nonhol)

    @property
    def multipliers(self) -> tuple[Any, ...]:
        """The multiplier functions ``lambda_j(t)``, one per kept constraint."""
        from sympy.physics.mechanics import dynamicsymbols

        m = len(self._hol) + len(self._nonhol)
        return tuple(dynamicsymbols(f"lam{j + 1}") for j in range(m))

    # ------------------------------------------------------------- derivation
    @cached_property
    def _MF(self) -> Any:
        import sympy

        c, L = self._c, self._L
        n = len(c.plain)
        parts = _quadratic_parts(L, c.vel)
        if parts is None:  # L not a quadratic polynomial in q': the general formula
            return self._MF_general()
        # L = q'.M q'/2 + b.q' + L0 exactly (M, b, L0 free of q'): M, b and L0 are read
        # off L's terms, and L_q, L_q'q q', L_q't come from the derivatives of the small
        # entries of M and b (Christoffel's form), never of the whole Lagrangian (n = 10
        # chain: ~5x faster to derive than n + n(n+1)/2 derivatives of L)
        M2, b, L0 = parts
        M = sympy.zeros(n, n)
        for (i, j), e in M2.items():
            M[i, j] = M[j, i] = 2 * e if i == j else e
        qs, u = c.plain, c.vel

        def grad(e: Any) -> dict[int, Any]:
            """The non-zero ``de/dq_k`` (a derivative only where q_k occurs)."""
            free = e.free_symbols
            return {k: _diff(e, q) for k, q in enumerate(qs) if q in free}

        dM = {key: grad(M[key]) for key in ((i, j) for i in range(n) for j in range(i, n))}
        db = [grad(bi) for bi in b]

        def m_q(i: int, j: int, k: int) -> Any:
            return dM[min(i, j), max(i, j)].get(k, sympy.S.Zero)

        explicit = c.time in sympy.Matrix([[*b, L0]]).free_symbols or any(
            c.time in M[i, j].free_symbols for i in range(n) for j in range(n)
        )
        F = sympy.zeros(n, 1)
        half = sympy.Rational(1, 2)
        for k in range(n):
            # one Add of all the terms: Python's sum() re-flattens the growing Add at every
            # term (n = 10 chain: 100 terms per row, half of the derivation's time)
            terms = [self._Q[k], _diff(L0, qs[k])]
            for i in range(n):
                for j in range(n):
                    a, v = m_q(i, j, k), m_q(k, i, j)
                    if a != 0:
                        terms.append(half * a * u[i] * u[j])
                    if v != 0:
                        terms.append(-v * u[i] * u[j])
            for i in range(n):
                if k in db[i]:
                    terms.append(db[i][k] * u[i])
                if i in db[k]:
                    terms.append(-db[k][i] * u[i])
            if explicit:
                terms.append(-b[k].diff(c.time))
                terms += [-M[k, j].diff(c.time) * u[j] for j in range(n)]
            F[k] = sympy.Add(*terms)
        return M, F

    def _MF_general(self) -> Any:
        """``M`` and ``F`` by differentiating ``L`` itself (any ``L``, e.g. not quadratic)."""
        import sympy

        c, L = self._c, self._L
        n = len(c.plain)
        dLdu = [L.diff(u) for u in c.vel]
        M = sympy.zeros(n, n)
        for k in range(n):
            for j in range(k, n):
                M[k, j] = M[j, k] = dLdu[k].diff(c.vel[j])
        F = sympy.zeros(n, 1)
        for k in range(n):
            f = self._Q[k] + L.diff(c.plain[k]) - dLdu[k].diff(c.time)
            for j in range(n):
                f -= dLdu[k].diff(c.plain[j]) * c.vel[j]
            F[k] = f
        return M, F

    @cached_property
    def _constraints(self) -> Any:
        """``A`` (m, n), ``b`` (m,), ``gamma`` (m,) in plain symbols."""
        import sympy

        c = self._c
        n = len(c.plain)
        rows, bias = [], []
        for f in self._hol:
            rows.append([f.diff(q) for q in c.plain])
            bias.append(f.diff(c.time))
        for f in self._nonhol:
            row = [f.diff(u) for u in c.vel]
            rows.append(row)
            bias.append(sympy.expand(f - sum(r * u for r, u in zip(row, c.vel, strict=True))))
        m = len(rows)
        A = sympy.Matrix(m, n, [e for r in rows for e in r]) if m else sympy.zeros(0, n)
        b = sympy.Matrix(bias) if m else sympy.zeros(0, 1)
        zero_acc = dict.fromkeys(c.acc, 0)
        gamma = (
            sympy.Matrix(
                [
                    c.time_derivative(
                        sum((A[j, k] * c.vel[k] for k in range(n)), start=b[j])
                    ).xreplace(zero_acc)
                    for j in range(m)
                ]
            )
            if m
            else sympy.zeros(0, 1)
        )
        return A, b, gamma

    @property
    def mass_matrix(self) -> Any:
        """``M = d^2 L / dq' dq'`` (n, n), in ``q(t)``, ``q'(t)``."""
        return self._c.to_funcs(self._MF[0])

    @property
    def forcing(self) -> Any:
        """``F`` with ``M q'' = F + A^T lambda`` (n, 1): ``Q* + dL/dq - L_q'q q' - L_q't``."""
        return self._c.to_funcs(self._MF[1])

    @property
    def constraint_matrix(self) -> Any:
        """``A`` (m, n) of the kept constraints ``A q' + b = 0``."""
        return self._c.to_funcs(self._constraints[0])

    @property
    def constraint_bias(self) -> Any:
        """``b`` (m, 1) of the kept constraints ``A q' + b = 0``."""
        return self._c.to_funcs(self._constraints[1])

    @property
    def constraint_acceleration(self) -> Any:
        """``gamma`` (m, 1): the constraints differentiated read ``A q'' + gamma = 0``."""
        return self._c.to_funcs(self._constraints[2])

    def equations(self, *, simplify: bool = True) -> list[Any]:
        """Lagrange's equations ``E_k L = Q*_k + sum_j lambda_j A_jk`` (theory §11).

        Returns
        -------
        list of sympy.Eq
            One per coordinate: the left side is ``E_k L`` (``T - P - V``
            differentiated), the right side the non-potential force plus the
            constraint forces. ``simplify`` applies ``trigsimp``.

        Examples
        --------
        >>> import sympy
        >>> x = sympy.Function("x")(sympy.Symbol("t"))
        >>> LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2).equations()
        [Eq(x(t) + Derivative(x(t), (t, 2)), 0)]
        """
        import sympy

        c = self._c
        M, F = self._MF
        A = self._constraints[0]
        lam = self.multipliers
        out = []
        for k in range(len(c.plain)):
            lhs = sum((M[k, j] * c.acc[j] for j in range(len(c.plain))), start=0)
            lhs = lhs - (F[k] - self._Q[k])
            rhs = self._Q[k] + sum((lam[j] * A[j, k] for j in range(A.shape[0])), start=0)
            lhs, rhs = sympy.expand(lhs), c.to_funcs(rhs)
            if simplify:
                lhs, rhs = sympy.trigsimp(lhs), sympy.trigsimp(rhs)
            out.append(sympy.Eq(c.to_funcs(lhs), rhs))
        return out

    # ----------------------------------------------------------- integrals
    @cached_property
    def _energy_plain(self) -> Any:
        import sympy

        c = self._c
        V0 = self._V - sum((self._V.diff(u) * u for u in c.vel), start=0)
        return self._T + self._P + sympy.expand(V0)

    def energy(self) -> Any:
        """Mechanical energy ``T + P + V0`` (``V0`` the velocity-free part of ``V``).

        Conserved when nothing depends on time explicitly and ``T`` is quadratic
        in the velocities (then it equals the Jacobi integral).
        """
        return self._c.to_funcs(self._energy_plain)

    @cached_property
    def _jacobi_plain(self) -> Any:
        import sympy

        c, L = self._c, self._L
        return sympy.expand(sum((L.diff(u) * u for u in c.vel), start=0) - L)

    @property
    def is_autonomous(self) -> bool:
        """Whether ``L``, the forces and the constraints do not depend on time explicitly."""
        t = self._c.time
        exprs = [self._L, *self._Q, *self._hol, *self._nonhol]
        return not any(t in e.free_symbols for e in exprs)

    @property
    def jacobi_conserved(self) -> bool:
        """Whether the Jacobi integral is a first integral.

        True when the system is autonomous, the non-potential forces are
        gyroscopic (or absent) and the kept constraints are ``A(q) q' = 0``
        (holonomic time-independent, or homogeneous kinematic ones).
        """
        if not self.is_autonomous or not self._gyroscopic:
            return False
        b = self._constraints[1]
        return all(_is_zero(e) for e in b)

    def jacobi_integral(self) -> Any:
        """The Jacobi integral ``h = q'^k dL/dq'^k - L`` (theory §11).

        Equal to ``T2 - T0 + P + V0`` when ``T = T2 + T1 + T0`` by degree in the
        velocities; the energy when ``T = T2``.

        Raises
        ------
        InvalidInputError
            If ``L`` depends on time explicitly (then ``h`` is not conserved).

        Examples
        --------
        A bead on a hoop of radius ``R`` spinning at ``w`` about the vertical:

        >>> import sympy
        >>> th = sympy.Function("theta")(sympy.Symbol("t"))
        >>> m, R, w, g = sympy.symbols("m R omega g", positive=True)
        >>> T = m * R**2 * (th.diff() ** 2 + w**2 * sympy.sin(th) ** 2) / 2
        >>> h = LagrangeSystem([th], T, -m * g * R * sympy.cos(th)).jacobi_integral()
        >>> sympy.expand(h - (T - 2 * m * R**2 * w**2 * sympy.sin(th) ** 2 / 2
        ...                   - m * g * R * sympy.cos(th)))
        0
        """
        if self._c.time in self._L.free_symbols:
            raise InvalidInputError(
                "The Lagrangian depends on time explicitly, so there is no Jacobi integral "
                f"(L = {self.lagrangian})."
            )
        return self._c.to_funcs(self._jacobi_plain)

    @cached_property
    def _cyclic(self) -> Any:
        c = self._c
        A, b, _ = self._constraints
        cons = [*self._hol, *self._nonhol]
        out = []
        for k, q in enumerate(c.plain):
            if q in self._L.free_symbols or not _is_zero(self._Q[k]):
                continue
            if any(q in e.free_symbols for e in cons):
                continue
            if any(A[j, k] != 0 for j in range(A.shape[0])):
                continue
            out.append(k)
        return tuple(out)

    @property
    def cyclic_coordinates(self) -> tuple[Any, ...]:
        """Coordinates absent from ``L`` with no force or constraint acting on them."""
        return tuple(self._c.funcs[k] for k in self._cyclic)

    @property
    def momenta(self) -> tuple[Any, ...]:
        """Generalized momenta ``p_k = dL/dq'^k``."""
        return tuple(self._c.to_funcs(self._L.diff(u)) for u in self._c.vel)

    @property
    def cyclic_momenta(self) -> dict[Any, Any]:
        """``{q_k: p_k}`` for each cyclic coordinate: conserved momenta."""
        mom = self.momenta
        return {self._c.funcs[k]: mom[k] for k in self._cyclic}

    def conserved_quantities(self) -> dict[str, Any]:
        """First integrals found: ``"jacobi"`` (when conserved) and ``"p_<q>"`` per
        cyclic coordinate, as expressions in ``q(t)``, ``q'(t)``."""
        out = {}
        if self.jacobi_conserved:
            out["jacobi"] = self.jacobi_integral()
        for q, p in self.cyclic_momenta.items():
            out[f"p_{q.func.__name__}"] = p
        return out

    def _first_undefined(
        self, values: Mapping[Any, float], rate: str = "'"
    ) -> tuple[str, str, str, set[Any]] | None:
        """The first term of the system that is not a finite real number at ``values``
        (plain symbols -> floats): ``(label, expression, what it is, its symbols)``, the
        user's terms (potential, kinetic energy...) before those derived from them (the
        mass matrix, the forcing). Evaluated by SymPy: only to explain a failure."""
        import sympy

        c = self._c
        names = {q: sympy.Symbol(nm) for q, nm in zip(c.plain, c.names, strict=True)}
        names.update({u: sympy.Symbol(nm + rate) for u, nm in zip(c.vel, c.names, strict=True)})
        M, F = self._MF
        A, _, gamma = self._constraints
        n = len(c.plain)
        terms: list[tuple[str, Any]] = [("the potential", self._P), ("the kinetic energy", self._T)]
        terms.append(("the generalized potential", self._V))
        terms += [(f"the generalized force on {c.names[k]}", self._Q[k]) for k in range(n)]
        terms += [(f"the holonomic constraint {f}", f) for f in self._hol]
        terms += [(f"the kinematic constraint {f}", f) for f in self._nonhol]
        for i in range(n):
            for j in range(i, n):
                entry = f"d^2T/d{c.names[i]}{rate}d{c.names[j]}{rate}"
                terms.append((f"the mass matrix entry {entry} =", M[i, j]))
        terms += [(f"the force term of the equation of {c.names[k]},", F[k]) for k in range(n)]
        terms += [(f"the constraint acceleration term {j + 1},", g) for j, g in enumerate(gamma)]
        # exact values (the floats' own): 0/0 is nan, 1/0 zoo, sqrt(-1) I (with Floats
        # mpmath raises ZeroDivisionError for 0.0/0.0)
        sub = {s: sympy.Rational(v) for s, v in values.items()}
        for label, expr in terms:
            e = sympy.sympify(expr)
            if e.is_number and e.is_finite:
                continue
            defect = _defect(e, sub)
            if defect is not None:
                return label, str(e.xreplace(names)), defect, e.free_symbols
        return None

    # ---------------------------------------------------------------- numbers
    def to_numeric(self, parameters: Mapping[str, float] | None = None) -> NumericLagrangian:
        """A compiled right-hand side ``f(t, y, parameters=None)``, ``y = [q, q']``.

        See :class:`poinsot.symbolic.NumericLagrangian`.

        Parameters
        ----------
        parameters : mapping of str or Symbol to float, optional
            Default values of the parameters (overridable per call).

        Examples
        --------
        >>> import numpy as np, sympy
        >>> th = sympy.Function("theta")(sympy.Symbol("t"))
        >>> g = sympy.Symbol("g")
        >>> f = LagrangeSystem([th], th.diff() ** 2 / 2, -g * sympy.cos(th)).to_numeric({"g": 9.81})
        >>> f(0.0, np.array([np.pi / 2, 0.0]))
        array([ 0.  , -9.81])
        """

        key = None
        if parameters is None or isinstance(parameters, Mapping):
            key = tuple(sorted((str(k), float(v)) for k, v in (parameters or {}).items()))
            cache = self.__dict__.setdefault("_numeric_cache", {})
            if key in cache:
                return cache[key]
        out = NumericLagrangian(self, parameters)
        if key is not None:
            self.__dict__["_numeric_cache"][key] = out
        return out

    def simulate(
        self,
        q0: ArrayLike,
        qdot0: ArrayLike,
        t: ArrayLike,
        *,
        parameters: Mapping[str, float] | ArrayLike | None = None,
        **options: Any,
    ) -> LagrangeTrajectory:
        """Integrate the equations of motion (see :meth:`NumericLagrangian.simulate`).

        Examples
        --------
        >>> import numpy as np, sympy
        >>> x = sympy.Function("x")(sympy.Symbol("t"))
        >>> osc = LagrangeSystem([x], x.diff() ** 2 / 2, x**2 / 2)
        >>> tr = osc.simulate([1.0], [0.0], np.linspace(0.0, np.pi, 3))
        >>> np.round(tr.q[:, 0], 8)
        array([ 1.,  0., -1.])
        """
        num = self.to_numeric(parameters if isinstance(parameters, Mapping) else None)
        return num.simulate(q0, qdot0, t, parameters=parameters, **options)

    def simulate_unilateral(
        self,
        constraint: Any,
        q0: ArrayLike,
        qdot0: ArrayLike,
        t: ArrayLike,
        *,
        parameters: Mapping[str, float] | None = None,
        restitution: float = 0.0,
        landing_speed: float = 1e-9,
        rtol: float = 1e-12,
        atol: float = 1e-14,
        max_switches: int = 1000,
    ) -> Any:
        """Integrate with the unilateral constraint ``constraint <= 0`` (theory §11.2).

        While the system is on ``f(q, t) = 0`` and the constraint pushes, Lagrange's
        equations with the multiplier, ``E_k L = Q*_k + lambda df/dq_k``, hold, and the
        reaction pushes into ``f < 0`` while ``lambda <= 0``; the system leaves at the
        event ``lambda = 0`` (increasing). Off the constraint it moves freely until the
        event ``f = 0`` (increasing), an impact by Newton's law in the metric of the
        mass matrix: ``q'+ = q'- - (1 + e) (a . q'-) M^-1 a / (a . M^-1 a)``, ``a =
        df/dq`` (theory §11.3); with ``e = 0`` (or a rebound slower than
        ``landing_speed``) it stays on the constraint.

        Parameters
        ----------
        constraint : sympy expression
            ``f(q, t)`` (in the coordinates ``q(t)``), allowed where ``f <= 0``.
        q0, qdot0 : array_like, shape (n,)
            The initial state, with ``f(q0) <= 0``.
        t : array_like, shape (k,)
            Output times.
        parameters : mapping, optional
            Values of the parameters (of the system and of ``constraint``).
        restitution : float, optional
            Newton's ``e`` in [0, 1] (default 0).
        landing_speed, rtol, atol, max_switches : optional
            A slower rebound lands; DOP853's tolerances; at most this many switches.

        Returns
        -------
        CoordinateTrajectory
            ``q``, ``qdot``, ``energy``; ``multipliers`` (k, 1) the constraint's
            ``lambda`` (0 off it; its units: the generalized force per unit of ``f``);
            ``info["events"]``: ``"leave"``, ``"impact"``, ``"land"``.

        Examples
        --------
        A pendulum on a string of length 1 m (polar coordinates, ``f = r - 1 <= 0``)
        launched from the bottom with ``v0^2 = 3.5 g`` goes slack at 120 degrees:

        >>> import numpy as np, sympy
        >>> t = sympy.Symbol("t")
        >>> r, th = sympy.Function("r")(t), sympy.Function("theta")(t)
        >>> pend = LagrangeSystem([r, th], (r.diff() ** 2 + r**2 * th.diff() ** 2) / 2,
        ...                       -9.81 * r * sympy.cos(th))
        >>> tr = pend.simulate_unilateral(r - 1, [1.0, 0.0], [0.0, np.sqrt(3.5 * 9.81)],
        ...                               np.linspace(0, 1, 101))
        >>> round(float(np.degrees(tr.info["events"].states("leave")[0, 1])), 6)
        120.0
        """
        import sympy
        from scipy.integrate import solve_ivp

        c = self._c
        f = _expr(constraint, "constraint", c)
        if f.free_symbols & set(c.vel):
            raise InvalidInputError(
                f"Expected the unilateral `constraint` f(q, t) without velocities, got "
                f"{c.to_funcs(f)}."
            )
        e = float(as_float_array(restitution, "restitution"))
        if not 0.0 <= e <= 1.0:
            raise InvalidInputError(f"Expected `restitution` in [0, 1], got {e!r}.")
        tt = as_times(t, "t")
        n = len(c.plain)
        y0 = np.concatenate([as_float_array(q0, "q0"), as_float_array(qdot0, "qdot0")])
        if y0.shape != (2 * n,):
            raise InvalidInputError(f"Expected `q0` and `qdot0` of shape ({n},), got {y0.shape}.")
        # the same system with the constraint as a bilateral one, for the contact phases
        con = LagrangeSystem.__new__(LagrangeSystem)
        con.__dict__.update(
            {
                k: v
                for k, v in self.__dict__.items()
                if k in ("_c", "_T", "_P", "_V", "_Q", "_gyroscopic", "_nonhol")
            }
        )
        con._hol = (*self._hol, f)
        free_n = self.to_numeric(parameters)
        con_n = con.to_numeric(parameters)
        pvec = con_n._params(None)
        names = list(con_n._params_sym)
        tsym = c.time
        f_fun = sympy.lambdify([tsym, list(c.plain), names], f, modules="numpy")
        g_fun = sympy.lambdify([tsym, list(c.plain), names], [f.diff(x) for x in c.plain],
                               modules="numpy")  # fmt: skip
        values = dict(zip(con_n.parameters, pvec.tolist(), strict=True))
        con_p = values or None
        free_p = {k: v for k, v in values.items() if k in free_n.parameters} or None

        def fval(tn: float, y: np.ndarray) -> float:
            return float(f_fun(tn, list(y[:n]), list(pvec)))

        def grad(tn: float, y: np.ndarray) -> np.ndarray:
            return np.asarray(g_fun(tn, list(y[:n]), list(pvec)), dtype=float)

        def lam(tn: float, y: np.ndarray) -> float:
            return float(con_n.multipliers(tn, y, con_p)[..., -1])

        def free_rhs(tn: float, y: np.ndarray) -> np.ndarray:
            return np.asarray(free_n(tn, y, free_p), dtype=float)

        def con_rhs(tn: float, y: np.ndarray) -> np.ndarray:
            return np.asarray(con_n(tn, y, con_p), dtype=float)

        def leave(tn: float, y: np.ndarray) -> float:
            return lam(tn, y)

        def hit(tn: float, y: np.ndarray) -> float:
            return fval(tn, y)

        leave.terminal, leave.direction = True, 1  # type: ignore[attr-defined]
        hit.terminal, hit.direction = True, 1  # type: ignore[attr-defined]
        scale = max(1.0, float(np.abs(y0[:n]).max()))
        if fval(float(tt[0]), y0) > 1e-9 * scale:
            raise InvalidInputError(
                f"Expected `q0` where the constraint holds (f <= 0), got f = "
                f"{fval(float(tt[0]), y0)!r}."
            )
        a0 = grad(float(tt[0]), y0)
        contact = (abs(fval(float(tt[0]), y0)) <= 1e-9 * scale
                   and float(a0 @ y0[n:]) <= 1e-12 * max(1.0, float(np.abs(y0[n:]).max()))
                   and lam(float(tt[0]), y0) < 0.0)  # fmt: skip
        k_out = tt.size
        ys = np.empty((k_out, 2 * n))
        lams = np.zeros((k_out, 1))
        on = np.zeros(k_out, dtype=bool)
        ys[0], on[0] = y0, contact
        if contact:
            lams[0, 0] = lam(float(tt[0]), y0)
        rows: list[tuple[float, int, np.ndarray, float]] = []
        y, t_now, k = y0, float(tt[0]), 1
        for _ in range(max_switches):
            if t_now >= tt[-1]:
                break
            rhs, ev = (con_rhs, leave) if contact else (free_rhs, hit)
            sol = solve_ivp(rhs, (t_now, float(tt[-1])), y, method="DOP853", rtol=rtol,
                            atol=atol, events=ev, dense_output=True)  # fmt: skip
            if sol.status < 0:
                raise IntegrationError(f"simulate_unilateral failed after t = {t_now:.6g}: "
                                       f"{sol.message}")  # fmt: skip
            t_end = float(sol.t[-1])
            while k < k_out and tt[k] <= t_end:
                ys[k] = sol.sol(tt[k])
                on[k] = contact
                if contact:
                    lams[k, 0] = lam(float(tt[k]), ys[k])
                k += 1
            if sol.status == 0:
                break
            t_now, y = t_end, sol.y[:, -1].copy()
            if contact:
                rows.append((t_now, 0, y.copy(), 1.0))
                contact = False
                continue
            rows.append((t_now, 1, y.copy(), 1.0))
            a = grad(t_now, y)
            m_inv_a = np.linalg.solve(free_n.mass_matrix(t_now, y, free_p), a)
            speed = float(a @ y[n:])
            y = y.copy()
            y[n:] -= (1.0 + e) * speed / float(a @ m_inv_a) * m_inv_a
            if e * speed / float(np.linalg.norm(a)) <= landing_speed:
                y[n:] += e * speed / float(a @ m_inv_a) * m_inv_a  # lands: a . q' = 0
                if lam(t_now, y) < 0.0:
                    contact = True
                    rows.append((t_now, 2, y.copy(), 1.0))
        else:
            raise IntegrationError(f"more than max_switches = {max_switches} phase changes")
        log = EventLog.of_one_body(("leave", "impact", "land"), rows, 2 * n)
        tb = tt
        return CoordinateTrajectory(
            t=tt, method="DOP853 (phases)", units=free_n._units(None), q=ys[:, :n],
            qdot=ys[:, n:], coordinates=free_n.coordinates,
            energy=free_n.energy(tb, ys, free_p), kinetic=free_n.kinetic(tb, ys, free_p),
            multipliers=lams, jacobi_conserved=False,
            info={"solver": "DOP853", "rtol": rtol, "atol": atol, "events": log},
        )  # fmt: skip

    def _repr_latex_(self) -> str:
        """Jupyter: Lagrange's equations ``E_k L = Q*_k`` (theory §11), one per line, with
        the coordinates and their rates as plain symbols (:meth:`printable`)."""
        import sympy

        lines = []
        for eq in self.equations():
            e = self.printable(eq, latex=True)
            lines.append(f"{sympy.latex(e.lhs)} &= {sympy.latex(e.rhs)}")
        return "$\\begin{aligned}" + " \\\\ ".join(lines) + "\\end{aligned}$"

    def __repr__(self) -> str:
        return (
            f"LagrangeSystem(coordinates={list(self.coordinates)}, "
            f"constraints={len(self._hol)} holonomic + {len(self._nonhol)} kinematic)"
        )


def _defect(expr: Any, values: Mapping[Any, Any]) -> str | None:
    """What keeps ``expr`` at ``values`` from being a finite float (``"infinite"``,
    ``"not real"``...), or None when it is one."""
    import sympy

    try:
        v = expr.xreplace(values).evalf()
    except ZeroDivisionError:
        return "infinite"
    except (TypeError, ValueError, ArithmeticError):  # no number there
        return "undefined"
    if v.has(sympy.nan):
        return "undefined (NaN)"
    if v.has(sympy.zoo, sympy.oo, -sympy.oo):
        return "infinite"
    try:
        z = complex(v)
    except (TypeError, ValueError):
        return "undefined"
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        return "beyond the floating-point range"
    if z.imag != 0 and abs(z.imag) > 1e-12 * max(1.0, abs(z.real)):
        return f"not real ({v})"
    return None


def _seq(value: Any, name: str) -> Any:
    import sympy

    if value is None:
        return ()
    if isinstance(value, str):
        raise InvalidTypeError(
            f"Expected `{name}` to be a sequence of SymPy expressions, got the string {value!r}."
        )
    if isinstance(value, sympy.Basic) and not isinstance(value, sympy.MatrixBase):
        return (value,)
    if not isinstance(value, Sequence | sympy.MatrixBase):
        raise InvalidTypeError(f"Expected `{name}` to be a sequence, got {type(value).__name__}.")
    return tuple(value)


def _eliminate(
    c: Coordinates, elim: Any, T: Any, P: Any, V: Any, Q: Any, hol: Any, nonhol: Any
) -> Any:
    """Solve the holonomic constraints for the coordinates ``elim`` and substitute."""
    import sympy

    if len(elim) != len(hol):
        raise InvalidInputError(
            f"Expected one coordinate in `eliminate` per holonomic constraint ({len(hol)}), "
            f"got {len(elim)}."
        )
    idx = []
    for e in elim:
        key = c.to_plain(e) if isinstance(e, sympy.Basic) else None
        if isinstance(e, str):
            key = next((p for p, nm in zip(c.plain, c.names, strict=True) if nm == e), None)
        if key not in c.plain:
            raise InvalidInputError(
                f"Expected `eliminate` to name coordinates among {list(c.funcs)}, got {e!r}."
            )
        idx.append(c.plain.index(key))
    targets = [c.plain[i] for i in idx]
    sols = sympy.solve(hol, targets, dict=True)
    if not sols:
        raise InvalidInputError(
            f"Could not solve the holonomic constraints {[c.to_funcs(f) for f in hol]} "
            f"for {[c.funcs[i] for i in idx]}."
        )
    sol = sols[0]
    if len(sols) > 1:
        import warnings

        warnings.warn(
            f"The holonomic constraints have {len(sols)} solutions for "
            f"{[c.funcs[i] for i in idx]}; using {[c.to_funcs(sol[x]) for x in targets]}.",
            PoinsotWarning,
            stacklevel=3,
        )
    keep = [i for i in range(len(c.plain)) if i not in idx]
    new = Coordinates(
        tuple(c.given[i] for i in keep),
        tuple(c.funcs[i] for i in keep),
        tuple(c.plain[i] for i in keep),
        tuple(c.vel[i] for i in keep),
        tuple(c.acc[i] for i in keep),
        c.time,
    )
    sub = {x: sol[x] for x in targets}
    for i in idx:
        sub[c.vel[i]] = new.time_derivative(sol[c.plain[i]])

    def s(e: Any) -> Any:
        return e.xreplace(sub)

    # Q_reduced_i = Q_i + sum_e Q_e dq_e/dq_i
    Qr = sympy.Matrix(
        [
            s(Q[i] + sum((Q[e] * sol[c.plain[e]].diff(c.plain[i]) for e in idx), start=0))
            for i in keep
        ]
    )
    return new, s(T), s(P), s(V), Qr, [], [s(f) for f in nonhol]


def _quadratic_parts(
    expr: Any, vel: Sequence[Any]
) -> tuple[dict[tuple[int, int], Any], list[Any], Any] | None:
    """``expr`` as ``sum_{i<=j} c_ij u_i u_j + sum_i b_i u_i + L0`` (``u = vel``), or None
    when it is not a polynomial of degree <= 2 in ``vel``.

    Only the parts that hold a velocity are multiplied out: a velocity-free subtree is
    one coefficient, never expanded (no blow-up of ``(1 + cos q)**20``)."""
    import sympy

    index = {v: i for i, v in enumerate(vel)}
    vset = set(vel)

    def poly(e: Any) -> dict[tuple[int, ...], Any] | None:
        if not (e.free_symbols & vset):
            return {(): e}
        if e in index:
            return {(index[e],): sympy.S.One}
        if e.is_Add:
            out: dict[tuple[int, ...], list[Any]] = {}
            for a in e.args:
                pa = poly(a)
                if pa is None:
                    return None
                for mono, cf in pa.items():
                    out.setdefault(mono, []).append(cf)
            return {m: sympy.Add(*cs) for m, cs in out.items()}
        if e.is_Mul:
            acc: dict[tuple[int, ...], Any] | None = {(): sympy.S.One}
            for a in e.args:
                pa = poly(a)
                if pa is None or acc is None:
                    return None
                acc = _times(acc, pa)
            return acc
        if e.is_Pow and e.exp.is_Integer and 0 < int(e.exp) <= 2:
            pb = poly(e.base)
            if pb is None:
                return None
            return pb if int(e.exp) == 1 else _times(pb, pb)
        return None  # a velocity inside a function, a division, a fractional power...

    def _times(
        a: dict[tuple[int, ...], Any], b: dict[tuple[int, ...], Any]
    ) -> dict[tuple[int, ...], Any] | None:
        out: dict[tuple[int, ...], list[Any]] = {}
        for ma, ca in a.items():
            for mb, cb in b.items():
                mono = tuple(sorted(ma + mb))
                if len(mono) > 2:
                    return None
                out.setdefault(mono, []).append(sympy.Mul(ca, cb))
        return {m: sympy.Add(*cs) for m, cs in out.items()}

    p = poly(sympy.sympify(expr))
    if p is None:
        return None
    quad = {(m[0], m[1]): cf for m, cf in p.items() if len(m) == 2}
    b = [sympy.S.Zero] * len(vel)
    for m, cf in p.items():
        if len(m) == 1:
            b[m[0]] = cf
    return quad, b, p.get((), sympy.S.Zero)


def _diff(e: Any, x: Any) -> Any:
    """``de/dx`` by the sum, product, power and sine/cosine rules, SymPy's ``diff``
    for anything else: the same derivative, ~14x faster on the small trigonometric
    entries of a mass matrix (SymPy's ``Derivative`` asks the assumptions system
    about every new expression, ~20 ms each on a cold cache)."""
    import sympy

    if x not in e.free_symbols:
        return sympy.S.Zero
    if e == x:
        return sympy.S.One
    if e.is_Add:
        return sympy.Add(*[_diff(a, x) for a in e.args])
    if e.is_Mul:
        a = e.args
        terms = []
        for i, f in enumerate(a):
            df = _diff(f, x)
            if df != 0:
                terms.append(sympy.Mul(*a[:i], df, *a[i + 1 :]))
        return sympy.Add(*terms)
    if e.is_Pow and x not in e.exp.free_symbols:
        return e.exp * e.base ** (e.exp - 1) * _diff(e.base, x)
    if isinstance(e, sympy.sin):
        return sympy.cos(e.args[0]) * _diff(e.args[0], x)
    if isinstance(e, sympy.cos):
        return -sympy.sin(e.args[0]) * _diff(e.args[0], x)
    return e.diff(x)
