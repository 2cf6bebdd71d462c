"""The ``[draw]`` table: how ``report.html`` draws a system given by formulas.

A Lagrangian system (docs/theory.md §11) has no body to draw; its scenario says
where its points are as formulas of the generalized coordinates, the
parameters and the time ``t``, read by the same whitelist parser as the
Lagrangian (:func:`poinsot.symbolic.parse_expression`, never evaluated as code)::

    [draw]
    points = { pivot = [0, 0], bob1 = ["l1*sin(theta1)", "-l1*cos(theta1)"] }
    links = [["pivot", "bob1"]]
    trail = ["bob1"]

``points`` gives each point 2 coordinates (a plane drawing, in the scene's
x-z plane, z up, seen face on) or 3 (space axes, m); every point has the same
number. ``links`` are segments drawn between two points at every frame,
``trail`` the points whose path up to the frame's time is drawn, fading with age.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..symbolic import ExpressionError, parse_expression
from .kind import Drawing

if TYPE_CHECKING:  # pragma: no cover
    from ._toml import Table

__all__ = ["DrawSpec", "read_draw"]

_KEYS = ("points", "links", "trail")


@dataclass(frozen=True)
class DrawSpec:
    """The ``[draw]`` table read: point formulas (SymPy), links and trails.

    Attributes
    ----------
    points : tuple of (str, tuple)
        Each point's name and its 2 or 3 coordinates (SymPy expressions of the
        coordinate symbols, the parameter symbols and ``t``).
    links, trails : tuples
        Pairs of point names; point names.
    dimension : int
        2 (a plane drawing in the x-z plane) or 3 (space axes).
    """

    points: tuple[tuple[str, tuple[Any, ...]], ...]
    links: tuple[tuple[str, str], ...] = ()
    trails: tuple[str, ...] = ()
    dimension: int = 3
    symbols: tuple[Any, ...] = field(default=(), repr=False)  # t, then the coordinates

    def evaluate(self, t: np.ndarray, q: np.ndarray, parameters: dict[str, float]) -> Drawing:
        """The points at times ``t`` (n,) with coordinates ``q`` (n, k), parameters
        by name: a :class:`~poinsot.scenarios.Drawing` (positions (n, 3) in m; a
        plane point ``(a, b)`` is drawn at ``(a, 0, b)``)."""
        import sympy

        subs = {sympy.Symbol(k, real=True): v for k, v in parameters.items()}
        exprs = [sympy.sympify(e).subs(subs) for _, xs in self.points for e in xs]
        # the expressions came from the whitelist parser: lambdify prints them as NumPy calls
        f = sympy.lambdify(list(self.symbols), exprs, modules="numpy")
        t = np.asarray(t, dtype=float)
        cols = [np.broadcast_to(np.asarray(v, dtype=float), t.shape)
                for v in f(t, *np.asarray(q, dtype=float).T)]  # fmt: skip
        d = self.dimension
        out: dict[str, np.ndarray] = {}
        for k, (name, _) in enumerate(self.points):
            c = cols[d * k : d * k + d]
            xyz = (c[0], np.zeros_like(t), c[1]) if d == 2 else tuple(c)
            out[name] = np.column_stack(xyz)
        return Drawing(out, self.links, self.trails, face_on=d == 2)


def read_draw(top: Table, coordinates: tuple[str, ...], parameters: tuple[str, ...]) -> Any:
    """Read the ``[draw]`` table of ``top`` (None if absent). Formulas may use the
    ``coordinates``, the ``parameters`` and ``t``; errors name the file, line and key."""
    import sympy

    t = top.table("draw")
    if t is None:
        return None
    t.known(_KEYS)
    time = sympy.Symbol("t", real=True)
    coords = [sympy.Symbol(c, real=True) for c in coordinates]
    symbols: dict[str, Any] = {"t": time, **dict(zip(coordinates, coords, strict=True))}
    symbols.update({p: sympy.Symbol(p, real=True) for p in parameters})
    raw = t.require("points", "a table {name = [x, y] or [x, y, z]} of formulas")
    pts = t.table("points", required=True)
    if not raw:
        raise t.expected("points", "at least one point {name = [x, y] or [x, y, z]}", raw)
    points: list[tuple[str, tuple[Any, ...]]] = []
    dim = None
    for name in list(pts.data):
        v = pts.raw(name)
        ok = isinstance(v, list) and len(v) in (2, 3)
        ok = ok and all(isinstance(x, str | int | float) and not isinstance(x, bool) for x in v)
        if not ok:
            raise pts.expected(name, "2 or 3 coordinates, each a formula string or a number (m)", v)
        if dim is None:
            dim = len(v)
        elif len(v) != dim:
            raise pts.error(
                name,
                f"expected {dim} coordinates like the first point, found {len(v)}: all points "
                "are in a plane (2) or all in space (3).",
            )
        xs = []
        for x in v:
            if isinstance(x, str):
                try:
                    xs.append(parse_expression(x, symbols))
                except ExpressionError as exc:
                    raise pts.error(name, str(exc)) from None
            else:
                xs.append(sympy.Float(x))
        points.append((name, tuple(xs)))
    names = [n for n, _ in points]

    def name_list(key: Any, pairs: Any) -> Any:
        v = t.raw(key, [])
        flat = None
        if isinstance(v, list) and not pairs:
            flat = v
        elif isinstance(v, list) and all(isinstance(p, list) and len(p) == 2 for p in v):
            flat = [x for p in v for x in p]
        if flat is None or not all(isinstance(x, str) for x in flat):
            what = "a list of [point, point] pairs" if pairs else "a list of point names"
            raise t.expected(key, what, v)
        for x in flat:
            if x not in names:
                raise t.error(key, f"expected a point among {names}, found {x!r}.")
        return v

    links = tuple((a, b) for a, b in name_list("links", True))
    trails = tuple(name_list("trail", False))
    t.finish(_KEYS)
    pts.finish()
    return DrawSpec(tuple(points), links, trails, int(dim or 3), (time, *coords))
