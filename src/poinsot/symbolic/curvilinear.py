"""Curvilinear coordinates of a point (docs/theory.md §7).

For a position ``r = r(q)`` in Cartesian components:

- tangent vectors ``g_k = dr/dq^k``, metric ``g_ik = g_i . g_k``,
- Lame coefficients ``H_k = |g_k|`` and unit vectors ``e_k = g_k / H_k``,
- ``v = q'^k g_k``, ``v^2 = g_ik q'^i q'^k``, ``v . e_k = g_kj q'^j / H_k``,
- ``w . g_k = d/dt d(v^2/2)/dq'^k - d(v^2/2)/dq^k`` and ``w . e_k = (1/H_k)(same)``,
- under a change ``q = q(q~)`` the metric transforms as a covariant tensor,
  ``g~_ik = (dq^a/dq~^i)(dq^b/dq~^k) g_ab``.
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

from ..errors import InvalidInputError, InvalidTypeError
from ._symbols import Coordinates, as_coordinates

__all__ = ["curvilinear", "CurvilinearCoordinates"]


def _reduce_squares(expr: Any) -> Any:
    """``cos^2 -> 1 - sin^2`` and ``cosh^2 -> 1 + sinh^2`` (even powers only)."""
    import sympy

    def is_even_power(p: Any) -> bool:
        return (
            p.is_Pow
            and p.base.func in (sympy.cos, sympy.cosh)
            and p.exp.is_Integer
            and p.exp > 0
            and p.exp % 2 == 0
        )

    def reduce(p: Any) -> Any:
        s = sympy.sin(p.base.args[0]) if p.base.func is sympy.cos else sympy.sinh(p.base.args[0])
        sign = -1 if p.base.func is sympy.cos else 1
        return (1 + sign * s**2) ** (p.exp // 2)

    return expr.replace(is_even_power, reduce)


def _simplify(expr: Any) -> Any:
    """A cheap simplification: the shorter of ``trigsimp`` and the Pythagorean reduction.

    ``sympy.simplify`` is avoided (seconds per component for elliptic coordinates).
    """
    import sympy

    if not isinstance(expr, sympy.Expr) or expr.is_number:
        return expr
    candidates = [sympy.trigsimp(expr)]
    reduced = sympy.factor_terms(sympy.expand(_reduce_squares(expr)))
    candidates.append(sympy.trigsimp(reduced))
    candidates.append(sympy.factor_terms(sympy.cancel(candidates[0])))
    return min(candidates, key=sympy.count_ops)


def _positive_sqrt(expr: Any) -> Any:
    """``sqrt(expr)`` simplified on the chart where the factors are positive."""
    import sympy

    root = sympy.powdenest(sympy.sqrt(_simplify(expr)), force=True)
    root = root.replace(sympy.Abs, lambda a: a)
    return sympy.factor_terms(_simplify(root))


class CurvilinearCoordinates:
    """A point's position ``r(q)`` and everything derived from it (theory §7).

    Built by :func:`curvilinear`. Position-level quantities (``tangent_vectors``,
    ``metric``, ``lame``, ``unit_vectors``) are expressed in the coordinates as
    given; velocity-level ones (``speed_squared``, ``velocity_components``,
    ``acceleration_components``) in the functions of time ``q(t)``, ``q'(t)``,
    ``q''(t)`` (``sympy.physics.mechanics.dynamicsymbols`` style).

    **Convention:** ``H_k`` is the positive root ``|g_k|``, simplified on the part
    of the chart where its factors are positive (``r sin(theta)``, not
    ``r |sin(theta)|``); the ``e_k`` and the components along them follow that sign.
    For non-orthogonal coordinates the components are the projections
    ``v . e_k``, ``w . e_k`` (not expansion coefficients).

    Examples
    --------
    >>> import sympy
    >>> r, phi, z = sympy.symbols("r phi z", positive=True)
    >>> cyl = curvilinear([r * sympy.cos(phi), r * sympy.sin(phi), z], [r, phi, z])
    >>> cyl.lame
    (1, r, 1)
    >>> cyl.acceleration_components[0]
    -r(t)*Derivative(phi(t), t)**2 + Derivative(r(t), (t, 2))
    """

    def __init__(self, position: Any, coords: Coordinates) -> None:
        self._c = coords
        self._r = position  # Matrix in plain symbols

    @property
    def coordinates(self) -> tuple[Any, ...]:
        """The coordinates as given."""
        return self._c.given

    @property
    def time(self) -> Any:
        """The time symbol."""
        return self._c.time

    @cached_property
    def position(self) -> Any:
        """``r(q)``, Cartesian components (a column ``Matrix``)."""
        return self._given(self._r)

    def _given(self, expr: Any) -> Any:
        """Plain symbols -> the coordinates as given (functions of t if given so)."""
        sub = dict(zip(self._c.plain, self._c.given, strict=True))
        return expr.xreplace(sub)

    @cached_property
    def _tangents(self) -> Any:
        return tuple(self._r.diff(q) for q in self._c.plain)

    @cached_property
    def _metric(self) -> Any:
        import sympy

        n = len(self._c.plain)
        g = sympy.zeros(n, n)
        for i in range(n):
            for k in range(i, n):
                g[i, k] = g[k, i] = _simplify(self._tangents[i].dot(self._tangents[k]))
        return g

    @cached_property
    def _lame(self) -> Any:
        return tuple(_positive_sqrt(self._metric[k, k]) for k in range(len(self._c.plain)))

    @property
    def tangent_vectors(self) -> tuple[Any, ...]:
        """``g_k = dr/dq^k`` (column matrices, Cartesian components)."""
        return tuple(self._given(g) for g in self._tangents)

    @property
    def metric(self) -> Any:
        """Metric tensor ``g_ik = g_i . g_k`` (symmetric ``Matrix``)."""
        return self._given(self._metric)

    @property
    def lame(self) -> tuple[Any, ...]:
        """Lame coefficients ``H_k = |g_k|``."""
        return tuple(self._given(h) for h in self._lame)

    @property
    def is_orthogonal(self) -> bool:
        """Whether ``g_ik = 0`` for ``i != k`` (identically)."""
        n = len(self._c.plain)
        return all(self._metric[i, k] == 0 for i in range(n) for k in range(i + 1, n))

    @cached_property
    def unit_vectors(self) -> tuple[Any, ...]:
        """``e_k = g_k / H_k`` (column matrices, Cartesian components)."""
        return tuple(
            self._given((g / h).applyfunc(_simplify))
            for g, h in zip(self._tangents, self._lame, strict=True)
        )

    @cached_property
    def _half_v2(self) -> Any:
        u = self._c.vel
        n = len(u)
        return (
            sum(
                (self._metric[i, k] * u[i] * u[k] for i in range(n) for k in range(n)),
                start=0,
            )
            / 2
        )

    @property
    def speed_squared(self) -> Any:
        """``v^2 = g_ik q'^i q'^k`` in ``q(t)``, ``q'(t)``."""
        import sympy

        return self._c.to_funcs(sympy.expand(2 * self._half_v2))

    @cached_property
    def velocity_components(self) -> tuple[Any, ...]:
        """``v . e_k = (1/H_k) d(v^2/2)/dq'^k`` (``= H_k q'^k`` if orthogonal)."""
        return tuple(
            self._c.to_funcs(_simplify(self._half_v2.diff(u) / h))
            for u, h in zip(self._c.vel, self._lame, strict=True)
        )

    @cached_property
    def acceleration_components(self) -> tuple[Any, ...]:
        """``w . e_k = (1/H_k)(d/dt d(v^2/2)/dq'^k - d(v^2/2)/dq^k)`` (theory §7)."""
        import sympy

        out = []
        for q, u, h in zip(self._c.plain, self._c.vel, self._lame, strict=True):
            lag = self._c.time_derivative(self._half_v2.diff(u)) - self._half_v2.diff(q)
            # expand only: trigsimp of these sums costs seconds (elliptic coordinates)
            lag = sympy.expand(lag)
            if any(isinstance(f, sympy.Add) for f in sympy.Mul.make_args(h)) or any(
                isinstance(f, sympy.Pow) and isinstance(f.base, sympy.Add)
                for f in sympy.Mul.make_args(h)
            ):
                comp = sympy.factor_terms(lag) / h
            else:
                comp = sympy.expand(lag / h)  # a monomial H_k cancels term by term
            out.append(self._c.to_funcs(comp))
        return tuple(out)

    def _substitution(self, old_in_new: Any, new_coordinates: Any) -> Any:
        import sympy

        new = as_coordinates(new_coordinates, self._c.time, name="new_coordinates")
        exprs = list(old_in_new) if not isinstance(old_in_new, sympy.Basic) else [old_in_new]
        if len(exprs) != len(self._c.plain):
            raise InvalidInputError(
                f"Expected `old_in_new` to give each of the {len(self._c.plain)} old "
                f"coordinates, got {len(exprs)} expressions."
            )
        if len(new.plain) != len(self._c.plain):
            raise InvalidInputError(
                f"Expected {len(self._c.plain)} `new_coordinates`, got {len(new.plain)}."
            )
        exprs = [new.to_plain(sympy.sympify(e)) for e in exprs]
        return new, dict(zip(self._c.plain, exprs, strict=True)), exprs

    def transformed_metric(self, old_in_new: Any, new_coordinates: Any) -> Any:
        """The metric in new coordinates by the tensor law (theory §7).

        ``g~_ik = J^a_i J^b_k g_ab`` with ``J^a_i = dq^a/dq~^i``; velocities
        transform contravariantly (``q' = J q~'``).

        Parameters
        ----------
        old_in_new : sequence of sympy.Expr
            Each old coordinate ``q^a`` as a function of the new ones.
        new_coordinates : sequence
            The new coordinates (names, symbols or functions of time).

        Returns
        -------
        sympy.Matrix
            ``J^T g J``, simplified, in the new coordinates as given.

        Examples
        --------
        >>> import sympy
        >>> x, y, r, phi = sympy.symbols("x y r phi", positive=True)
        >>> plane = curvilinear([x, y], [x, y])
        >>> plane.transformed_metric([r * sympy.cos(phi), r * sympy.sin(phi)], [r, phi])
        Matrix([
        [1,    0],
        [0, r**2]])
        """
        import sympy

        new, sub, exprs = self._substitution(old_in_new, new_coordinates)
        jac = sympy.Matrix(exprs).jacobian(list(new.plain))
        g = (jac.T * self._metric.xreplace(sub) * jac).applyfunc(_simplify)
        return g.xreplace(dict(zip(new.plain, new.given, strict=True)))

    def change_coordinates(self, old_in_new: Any, new_coordinates: Any) -> CurvilinearCoordinates:
        """The same point described by new coordinates ``q = q(q~)``.

        Examples
        --------
        >>> import sympy
        >>> x, y, r, phi = sympy.symbols("x y r phi", positive=True)
        >>> polar = curvilinear([x, y], [x, y]).change_coordinates(
        ...     [r * sympy.cos(phi), r * sympy.sin(phi)], [r, phi])
        >>> polar.lame
        (1, r)
        """
        new, sub, _ = self._substitution(old_in_new, new_coordinates)
        return CurvilinearCoordinates(self._r.xreplace(sub), new)

    def __repr__(self) -> str:
        pos, coords = list(self.position), list(self.coordinates)
        return f"CurvilinearCoordinates(position={pos}, coordinates={coords})"


def curvilinear(position: Any, coordinates: Any, *, time: Any = None) -> CurvilinearCoordinates:
    """Curvilinear coordinates ``r = r(q)`` of a point (theory §7).

    Parameters
    ----------
    position : sequence of sympy.Expr
        Cartesian components of the position (2 or 3 of them, or any number),
        in terms of the coordinates.
    coordinates : sequence of str, sympy.Symbol or dynamicsymbols
        The curvilinear coordinates ``q^k``.
    time : sympy.Symbol, optional
        The time symbol (default ``dynamicsymbols._t``).

    Returns
    -------
    CurvilinearCoordinates
        With ``lame``, ``metric``, ``unit_vectors``, ``speed_squared``,
        ``velocity_components``, ``acceleration_components`` and the
        transformation of the metric under a change of coordinates.

    Examples
    --------
    >>> import sympy
    >>> rho, theta, phi = sympy.symbols("rho theta phi", positive=True)
    >>> sph = curvilinear([rho * sympy.sin(theta) * sympy.cos(phi),
    ...                    rho * sympy.sin(theta) * sympy.sin(phi),
    ...                    rho * sympy.cos(theta)], [rho, theta, phi])
    >>> sph.lame
    (1, rho, rho*sin(theta))
    """
    import sympy

    coords = as_coordinates(coordinates, time)
    if isinstance(position, sympy.MatrixBase):
        position = list(position)
    if isinstance(position, str) or not hasattr(position, "__len__") or len(position) == 0:
        raise InvalidTypeError(
            f"Expected `position` to be a sequence of SymPy expressions, got {position!r}."
        )
    comps = []
    for i, x in enumerate(position):
        if isinstance(x, str):
            raise InvalidTypeError(
                f"Expected `position[{i}]` to be a SymPy expression, got the string {x!r} "
                "(use poinsot.symbolic.parse_expression for text)."
            )
        comps.append(coords.to_plain(sympy.sympify(x)))
    r = sympy.Matrix(comps)
    extra = r.free_symbols & {coords.time}
    if extra:
        raise InvalidInputError(
            "Expected `position` not to depend on time explicitly (a moving chart is a "
            f"LagrangeSystem), got {list(position)}."
        )
    if r.jacobian(list(coords.plain)).rank() < len(coords.plain):
        raise InvalidInputError(
            f"Expected the coordinates {list(coords.given)} to be independent: the Jacobian "
            f"of `position` {list(position)} has rank below {len(coords.plain)}."
        )
    return CurvilinearCoordinates(r, coords)
