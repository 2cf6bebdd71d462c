"""Motion of a particle under a central force (theory §9).

A force ``F = -U'(r) e_r`` towards a fixed centre keeps the angular momentum
``L = m r^2 phi'`` constant: the motion is planar, the areal velocity
``S' = r^2 phi' / 2 = L / (2 m)`` is constant (Kepler's second law) and the
energy ``E = m r'^2 / 2 + U_eff(r)`` with the effective potential
``U_eff(r) = U(r) + L^2 / (2 m r^2)`` reduces the problem to quadratures:

``t = int dr / sqrt(2 (E - U_eff) / m)``,
``phi = int (L / (m r^2)) dr / sqrt(2 (E - U_eff) / m)``.

:class:`CentralOrbit` finds the apsides (roots of ``U_eff = E``), the radial
period and the apsidal angle by quadratures whose endpoint singularities are
removed by substitution, and the orbit itself by integration (or, for the
Kepler problem, in closed form through Kepler's equation). Potentials are
:class:`Potential` objects, built by :func:`kepler`, :func:`inverse_square`,
:func:`harmonic` or from any callable, and added with ``+``.

**Convention:** ``U`` is a potential *energy* (J) of the distance ``r`` (m)
from the centre; ``m`` in kg, ``L`` in kg m^2/s (``L > 0``: ``phi`` increases).
Positions are in the orbit plane's axes ``(e1, e2, n)`` mapped to space: for
:meth:`CentralOrbit.from_state` ``e1`` points to the initial position and
``n = r0 x v0 / |r0 x v0|``; otherwise the plane is ``z = 0`` and the
particle is at the pericentre on the x axis at ``t = 0``.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _display
from .._progress import Progress, in_chunks
from .._typing import ArrayLike, FloatArray
from .._validate import as_choice, as_float_array, as_vec3
from .._vec import cross, dot
from ..errors import AccuracyWarning, IntegrationError, InvalidInputError, InvalidTypeError
from ..trajectory import PointTrajectory

if TYPE_CHECKING:
    from ..trajectory import PointTrajectory

__all__ = [
    "Potential",
    "kepler",
    "inverse_square",
    "harmonic",
    "power_law",
    "CentralOrbit",
    "KeplerConic",
    "Apsides",
]

#: Relative tolerance the apsidal quadratures aim for (two successive refinements agree).
QUADRATURE_RTOL = 1e-13
_MAX_NODES = 1 << 15
_EPS = float(np.finfo(float).eps)
#: Below this ``(r_max - r_min) / (r_max + r_min)`` the radial period and the apsidal
#: angle come from the circular limit (see ``CentralOrbit._near_circular``): there the
#: apsides, roots of ``E - U_eff`` ~ ``U_eff'' (r - r_c)^2 / 2``, are known only to
#: ~sqrt(eps), while the period and the angle are smooth functions of the energy.
_NEAR_CIRCULAR = 1e-5


# ---------------------------------------------------------------------------
# Potentials
# ---------------------------------------------------------------------------


class Potential:
    """A central potential energy ``U(r)`` (J) with its derivative ``dU/dr`` (N).

    Parameters
    ----------
    function : callable
        ``U(r)`` for an array of distances ``r > 0`` (m), vectorised
        (returns an array of the same shape).
    derivative : callable, optional
        ``dU/dr``; if omitted it is computed by 5-point central differences
        with step ``1e-3 r`` (relative error ~1e-12 for smooth ``U``).
    name : str, optional
        A label (shown by ``repr``).

    Notes
    -----
    Potentials add: ``kepler(1.0) + inverse_square(0.1)`` is
    ``U = -1/r + 0.1/r^2``; a number adds a constant. Values are checked: a
    potential returning NaN or inf raises :class:`InvalidInputError`.

    Examples
    --------
    >>> from poinsot.dynamics import Potential, kepler
    >>> U = kepler(2.0) + Potential(lambda r: 0.5 * r**2, lambda r: r, name="r^2/2")
    >>> float(U(1.0)), float(U.derivative(1.0))
    (-1.5, 3.0)
    """

    def __init__(
        self,
        function: Callable[..., Any],
        derivative: Callable[..., Any] | None = None,
        *,
        name: str | None = None,
    ) -> None:
        if not callable(function):
            raise InvalidTypeError(
                f"Expected `function` to be a callable U(r), got {type(function).__name__}."
            )
        if derivative is not None and not callable(derivative):
            raise InvalidTypeError(
                f"Expected `derivative` to be a callable dU/dr or None, got "
                f"{type(derivative).__name__}."
            )
        self._f = function
        self._df = derivative
        self.name = name or getattr(function, "__name__", "U")
        #: ``mu`` when the potential is exactly Kepler's ``-mu/r`` (closed forms), else None.
        self.kepler_mu: float | None = None

    def __repr__(self) -> str:
        return f"Potential({self.name})"

    def _raw(self, r: ArrayLike, f: Callable[[Any], Any] | None = None) -> FloatArray:
        f = self._f if f is None else f
        with np.errstate(all="ignore"):
            try:
                return np.asarray(f(r), dtype=np.float64) + np.zeros(np.shape(r))
            except (TypeError, ValueError) as exc:
                raise InvalidTypeError(
                    f"Expected the potential {self.name!r} to accept an array of distances "
                    f"and return numbers of the same shape (vectorised, e.g. with numpy), "
                    f"calling it failed: {type(exc).__name__}: {exc}"
                ) from None

    def __call__(self, r: ArrayLike) -> FloatArray:
        """``U(r)`` in J."""
        r = as_float_array(r, "r")
        return _checked(self._raw(r), r, "potential")

    @property
    def has_derivative(self) -> bool:
        """Whether ``dU/dr`` was given in closed form."""
        return self._df is not None

    def derivative(self, r: ArrayLike) -> FloatArray:
        """``dU/dr`` in N (given, or 5-point central differences with step ``1e-3 r``)."""
        r = as_float_array(r, "r")
        return _checked(self._deriv(r), r, "potential derivative")

    def _deriv(self, r: FloatArray) -> FloatArray:
        if self._df is not None:
            return self._raw(r, self._df)
        h = 1e-3 * np.abs(r)
        f = self._raw
        return (8.0 * (f(r + h) - f(r - h)) - (f(r + 2 * h) - f(r - 2 * h))) / (12.0 * h)

    def force(self, r: ArrayLike) -> FloatArray:
        """Radial force ``F_r = -dU/dr`` (N, positive outwards)."""
        return -self.derivative(r)

    def __add__(self, other: Potential | float) -> Potential:
        if isinstance(other, int | float | np.floating | np.integer):
            c = float(other)
            return Potential(lambda r, f=self._f: f(r) + c, self._df, name=f"{self.name} + {c:g}")
        if not isinstance(other, Potential):
            return NotImplemented
        a, b = self, other
        if a._df is not None and b._df is not None:
            d = lambda r: a._raw(r, a._df) + b._raw(r, b._df)  # noqa: E731
        elif a._df is None and b._df is None:
            d = None
        else:  # mix: the closed-form part exactly, the other by differences
            d = lambda r: a._deriv(r) + b._deriv(r)  # noqa: E731
        return Potential(lambda r: a._raw(r) + b._raw(r), d, name=f"{a.name} + {b.name}")

    __radd__ = __add__


def _as_potential(potential: object) -> Potential:
    """A Potential as is; a callable wrapped (derivative by differences)."""
    if isinstance(potential, Potential):
        return potential
    if not callable(potential):
        raise InvalidTypeError(
            f"Expected `potential` to be a Potential or a callable U(r), got "
            f"{type(potential).__name__}."
        )
    return Potential(potential)


def _checked(u: FloatArray, r: ArrayLike, what: str) -> FloatArray:
    if not np.all(np.isfinite(u)):
        bad = np.asarray(r)[~np.isfinite(u)] if np.ndim(u) else np.asarray(r)
        raise InvalidInputError(
            f"Expected `{what}` to return finite values, got NaN/inf at r = "
            f"{float(np.ravel(bad)[0])!r}."
        )
    return u


def _coef(x: ArrayLike, name: str) -> float:
    a = as_float_array(x, name)
    if a.ndim:
        raise InvalidInputError(f"Expected `{name}` to be a scalar, got shape {a.shape}.")
    return float(a)


def kepler(mu: float) -> Potential:
    """Kepler's potential ``U = -mu / r`` (attractive for ``mu > 0``).

    ``mu`` is in J m: for gravity ``mu = G M m`` (with the default ``mass=1``
    of :class:`CentralOrbit`, ``mu`` is the gravitational parameter ``G M``).

    >>> from poinsot.dynamics import kepler
    >>> float(kepler(3.0)(2.0)), float(kepler(3.0).derivative(2.0))
    (-1.5, 0.75)
    """
    mu = _coef(mu, "mu")
    p = Potential(lambda r: -mu / r, lambda r: mu / r**2, name=f"-{mu:g}/r")
    p.kepler_mu = mu
    return p


def inverse_square(beta: float) -> Potential:
    """``U = beta / r^2`` (repulsive for ``beta > 0``): with Kepler's, a precessing ellipse.

    >>> from poinsot.dynamics import inverse_square
    >>> float(inverse_square(0.5)(2.0))
    0.125
    """
    beta = _coef(beta, "beta")
    return Potential(lambda r: beta / r**2, lambda r: -2.0 * beta / r**3, name=f"{beta:g}/r^2")


def harmonic(k: float) -> Potential:
    """The isotropic oscillator ``U = k r^2 / 2`` (a centred ellipse for ``k > 0``).

    >>> from poinsot.dynamics import harmonic
    >>> float(harmonic(4.0)(0.5)), float(harmonic(4.0).derivative(0.5))
    (0.5, 2.0)
    """
    k = _coef(k, "k")
    if k == 0:
        raise InvalidInputError(
            "Expected `k` to be non-zero (k = 0 is no force: a straight line), got 0."
        )
    return Potential(lambda r: 0.5 * k * r**2, lambda r: k * r, name=f"{k:g} r^2/2")


def power_law(k: float, n: float) -> Potential:
    """``U = k r^n / n`` (``n != 0``; force ``-k r^(n-1)``); ``n = -1`` is Kepler with ``mu = k``.

    >>> from poinsot.dynamics import power_law
    >>> float(power_law(2.0, 3)(1.5))
    2.25
    """
    k, n = _coef(k, "k"), _coef(n, "n")
    if n == 0:
        raise InvalidInputError("Expected `n` to be non-zero (use a logarithm for n = 0), got 0.")
    return Potential(
        lambda r: k * r**n / n, lambda r: k * r ** (n - 1), name=f"{k:g} r^{n:g}/{n:g}"
    )


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Apsides:
    """Pericentre and apocentre distances (m); ``apocentre = inf`` for an unbound orbit.

    Unpacks and indexes as the pair ``(r_min, r_max)``: ``r_min, r_max = orbit.apsides``,
    ``orbit.apsides[0]``.

    Examples
    --------
    >>> a = Apsides(1.0, 3.0)
    >>> a[0], a[-1], len(a), tuple(a)
    (1.0, 3.0, 2, (1.0, 3.0))
    """

    pericentre: float
    apocentre: float

    def __iter__(self) -> Iterator[float]:
        return iter((self.pericentre, self.apocentre))

    def __len__(self) -> int:
        return 2

    def __getitem__(self, index: Any) -> Any:
        return (self.pericentre, self.apocentre)[index]


@dataclass(frozen=True)
class KeplerConic:
    """The conic of a Kepler orbit ``r = p / (1 + e cos nu)`` (theory §9).

    Attributes
    ----------
    p : float
        Semi-latus rectum ``L^2 / (m mu)`` (m).
    e : float
        Eccentricity ``sqrt(1 + 2 E L^2 / (m mu^2))``.
    a : float
        Semi-major axis ``-mu / (2 E)`` (m; negative for a hyperbola, ``inf``
        for a parabola).
    period : float
        ``2 pi sqrt(m a^3 / mu)`` (s; ``inf`` when unbound).
    mean_motion : float
        ``sqrt(mu / (m |a|^3))`` (rad/s; for a parabola ``sqrt(mu / (m p^3))``).
    """

    p: float
    e: float
    a: float
    period: float
    mean_motion: float


# ---------------------------------------------------------------------------
# The orbit
# ---------------------------------------------------------------------------


_MAX_GAUSS = 1024


@functools.lru_cache(maxsize=16)
def _leggauss(n: int) -> tuple[FloatArray, FloatArray]:
    return np.polynomial.legendre.leggauss(n)


class CentralOrbit:
    """The orbit of a particle in a central potential, by quadratures (theory §9).

    Parameters
    ----------
    potential : Potential or callable
        ``U(r)`` (J); a plain callable is wrapped in :class:`Potential`
        (derivative by differences).
    energy : float
        Total energy ``E = m |v|^2 / 2 + U(r)`` (J).
    angular_momentum : float
        ``L = m r^2 phi'`` (kg m^2/s), non-zero; its sign sets the sense of
        ``phi``.
    mass : float, optional
        ``m`` (kg, > 0), default 1.
    radius : float, optional
        A distance the particle reaches (``U_eff(radius) <= E``): selects the
        allowed interval when ``U_eff`` has several wells. Default: the
        interval around the minimum of ``U_eff`` (searched over
        ``1e-30 .. 1e30`` m).

    Raises
    ------
    InvalidInputError
        Non-finite values, ``mass <= 0``, ``angular_momentum = 0`` (a radial
        fall has no orbit plane), an energy below the effective potential's
        minimum (no orbit exists), an orbit that reaches the centre, or a
        potential returning non-finite values.

    Notes
    -----
    **Convention:** see the module docstring. Apsides are the roots of
    ``U_eff(r) = E`` (Brent's method, bracketed by halving/doubling from the
    chosen radius). ``radial_period`` and ``apsidal_angle`` are
    ``2 int dr/r'`` and ``int phi' dr / r'`` from ``r_min`` to ``r_max``
    computed with ``r = (r1 + r2)/2 + (r2 - r1)/2 sin s``, which cancels the
    inverse-square-root singularities at both ends and makes the integrand a
    smooth periodic function of ``s``: the midpoint rule then converges
    geometrically (Gauss-Chebyshev), refined until two estimates agree to
    :data:`QUADRATURE_RTOL`. For unbound orbits ``u = 1/r = u1 sin^2 s``
    (Gauss-Legendre) does the same on ``r in [r_min, inf)``.

    Examples
    --------
    A Kepler ellipse (``mu = 1``, ``E = -0.5``, ``L = 0.8``):

    >>> from poinsot.dynamics import CentralOrbit, kepler
    >>> orb = CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=0.8)
    >>> [round(x, 12) for x in orb.apsides]
    [0.4, 1.6]
    >>> round(orb.radial_period / (2 * 3.141592653589793), 12), round(orb.apsidal_angle, 12)
    (1.0, 3.14159265359)
    """

    def __init__(
        self,
        potential: Potential | Callable[[np.ndarray], ArrayLike],
        *,
        energy: float,
        angular_momentum: float,
        mass: float = 1.0,
        radius: float | None = None,
        _state: Any = None,
    ) -> None:
        self.potential = potential = _as_potential(potential)
        self.energy = _coef(energy, "energy")
        L = _coef(angular_momentum, "angular_momentum")
        if L == 0.0:
            raise InvalidInputError(
                "Expected `angular_momentum` to be non-zero: with L = 0 the motion is a "
                "radial fall through the centre and has no orbit plane or apsidal angle."
            )
        self.angular_momentum = L
        m = _coef(mass, "mass")
        if m <= 0:
            raise InvalidInputError(f"Expected `mass` to be positive (kg), got {m!r}.")
        self.mass = m
        if radius is not None:
            radius = _coef(radius, "radius")
            if radius <= 0:
                raise InvalidInputError(f"Expected `radius` to be positive (m), got {radius!r}.")
        self._find_apsides(radius)
        if _state is None:  # at the pericentre on the x axis, plane z = 0
            self._r0, self._rdot0 = self._r1, 0.0
            self._basis = np.eye(3)
            self._peri_time, self._peri_angle = 0.0, 0.0
        else:
            self._r0, self._rdot0, self._basis = _state
            self._peri_time, self._peri_angle = self._pericentre_offsets()

    # -- construction -------------------------------------------------------

    @classmethod
    def from_state(
        cls,
        potential: Potential | Callable[[np.ndarray], ArrayLike],
        position: ArrayLike,
        velocity: ArrayLike,
        mass: float = 1.0,
    ) -> CentralOrbit:
        """The orbit through a position and velocity (relative to the centre).

        Parameters
        ----------
        potential : Potential or callable
            ``U(r)`` (J).
        position, velocity : array_like, shape (3,)
            Initial position (m) and velocity (m/s), any Cartesian axes.
        mass : float, optional
            Mass (kg), default 1.

        Returns
        -------
        CentralOrbit
            With ``E = m |v|^2 / 2 + U(|r|)``, ``L = m |r x v| > 0``, the
            plane spanned by ``r0`` and ``v0`` and ``t = 0`` at this state.

        Examples
        --------
        A circular orbit of radius 2 (``mu = 1``, speed ``1/sqrt(2)``):

        >>> import numpy as np
        >>> from poinsot.dynamics import CentralOrbit, kepler
        >>> orb = CentralOrbit.from_state(kepler(1.0), [2, 0, 0], [0, 0, 1 / np.sqrt(2)])
        >>> [round(x, 9) for x in orb.apsides], round(orb.apsidal_angle / np.pi, 9)
        ([2.0, 2.0], 1.0)
        """
        x = as_vec3(position, "position")
        v = as_vec3(velocity, "velocity")
        if x.shape != (3,) or v.shape != (3,):
            raise InvalidInputError(
                f"Expected `position` and `velocity` of shape (3,), got {x.shape} and {v.shape}."
            )
        m = _coef(mass, "mass")
        if m <= 0:
            raise InvalidInputError(f"Expected `mass` to be positive (kg), got {m!r}.")
        r = float(np.linalg.norm(x))
        if r == 0:
            raise InvalidInputError("Expected `position` to be away from the centre, got 0.")
        potential = _as_potential(potential)
        n = cross(x, v)
        nn = float(np.linalg.norm(n))
        if nn <= 1e-14 * r * float(np.linalg.norm(v)):
            raise InvalidInputError(
                "Expected `velocity` to have a component across `position`: the angular "
                "momentum is 0 (radial motion), so there is no orbit plane."
            )
        e1 = x / r
        nz = n / nn
        basis = np.stack([e1, cross(nz, e1), nz], axis=-1)  # columns e1, e2, n
        u0 = potential(np.array(r))
        energy = 0.5 * m * float(dot(v, v)) + float(u0)
        return cls(
            potential,
            energy=energy,
            angular_momentum=m * nn,
            mass=m,
            radius=r,
            _state=(r, float(dot(x, v)) / r, basis),
        )

    # -- effective potential and apsides -------------------------------------

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: potential, integrals, apsides and periods (SI units)."""
        d = _display
        rows = [
            ("potential U(r)", d.esc(self.potential.name)),
            ("mass", d.value(self.mass, "kg")),
            ("energy E", d.value(self.energy, "J")),
            ("angular momentum L", d.value(self.angular_momentum, "kg m^2/s")),
            ("apsides r_min, r_max", d.value(list(self.apsides), "m")),
            ("radial period", d.value(self.radial_period, "s")),
        ]
        if self.potential.kepler_mu is not None:
            c = self.conic
            rows.append(("conic e, a", d.value([c.e, c.a], "1, m")))
        return d.table("CentralOrbit", rows, "docs/theory.md §9")

    def __repr__(self) -> str:
        kind = "unbound" if self.unbound else ("circular" if self._circular else "bound")
        return (
            f"CentralOrbit(potential={self.potential.name}, energy={self.energy!r}, "
            f"angular_momentum={self.angular_momentum!r}, mass={self.mass!r}, {kind}, "
            f"apsides={tuple(round(float(x), 12) for x in self.apsides)})"
        )

    def effective_potential(self, r: ArrayLike) -> FloatArray:
        """``U_eff(r) = U(r) + L^2 / (2 m r^2)`` (J)."""
        r = as_float_array(r, "r")
        return self.potential(r) + self.angular_momentum**2 / (2.0 * self.mass * r**2)

    def _ueff_raw(self, r: FloatArray) -> FloatArray:
        with np.errstate(over="ignore", under="ignore"):
            return self.potential._raw(r) + self.angular_momentum**2 / (2.0 * self.mass * r**2)

    def _gap(self, r: FloatArray) -> FloatArray:
        """``E - U_eff(r)`` (checked finite)."""
        u = self._ueff_raw(r)
        _checked(u, r, "potential")
        return self.energy - u

    def _gap_nodes(self, r: FloatArray, off1: FloatArray, off2: FloatArray) -> FloatArray:
        """``E - U_eff(r)`` at quadrature nodes, free of cancellation near the apsides.

        ``off1 = r - r_min`` and ``off2 = r_max - r`` are given accurately by the
        caller. Within 25 % of an apsis ``a`` (where ``U_eff(a) = E``) and when
        ``dU/dr`` is known in closed form, ``E - U_eff(r) = -int_a^r U_eff'``
        (32-point Gauss-Legendre): its relative accuracy does not degrade as
        ``r -> a``, unlike the difference of two nearly equal energies.
        """
        gap = self._gap(r)
        if not self.potential.has_derivative:
            return gap
        x, w = _leggauss(32)
        near1 = (off1 <= off2) & (off1 <= 0.25 * self._r1)
        near2 = (off2 < off1) & (off2 <= 0.25 * self._r2)
        for apsis, sel, off, sign in ((self._r1, near1, off1, 1.0), (self._r2, near2, off2, -1.0)):
            if not np.any(sel):
                continue
            h = 0.5 * off[sel]
            rho = apsis + sign * h[:, None] * (x + 1.0)
            gap[sel] = -sign * h * (self._ueff_deriv(rho) @ w)
        return gap

    def _ueff_deriv(self, r: FloatArray) -> FloatArray:
        """``U_eff'(r) = U'(r) - L^2 / (m r^3)``."""
        return self.potential._deriv(r) - self.angular_momentum**2 / (self.mass * r**3)

    def _find_apsides(self, radius: float | None) -> None:
        from scipy.optimize import brentq, minimize_scalar

        E = self.energy
        if radius is None:
            logr = np.linspace(-30.0, 30.0, 1201)
            r = 10.0**logr
            u = self._ueff_raw(r)
            if not np.any(np.isfinite(u)):
                raise InvalidInputError(
                    "Expected `potential` to return finite values, got NaN/inf everywhere "
                    "on 1e-30 .. 1e30 m."
                )
            k = int(np.nanargmin(np.where(np.isfinite(u), u, np.nan)))
            lo, hi = logr[max(k - 1, 0)], logr[min(k + 1, logr.size - 1)]
            res = minimize_scalar(
                lambda x: float(self._ueff_raw(10.0**x)),
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-13},
            )
            rs = 10.0 ** float(res.x)
            umin = float(self._ueff_raw(rs))
            if not np.isfinite(umin) or umin > u[k]:
                rs, umin = float(r[k]), float(u[k])
            if self.potential.has_derivative:  # the minimum as a root of U_eff' (to round-off)
                lo_r, hi_r = rs * (1 - 1e-5), rs * (1 + 1e-5)
                flo, fhi = self._ueff_deriv(np.array(lo_r)), self._ueff_deriv(np.array(hi_r))
                if flo < 0 < fhi:
                    rs = brentq(
                        lambda x: float(self._ueff_deriv(np.array(x))),
                        lo_r,
                        hi_r,
                        xtol=1e-300,
                        rtol=4 * _EPS,
                    )
                    umin = min(umin, float(self._ueff_raw(rs)))
            scale = abs(umin) + abs(E) + _EPS
            if E < umin - 1e-12 * scale:
                raise InvalidInputError(
                    f"Expected `energy` >= the minimum of the effective potential "
                    f"U_eff = U + L^2/(2 m r^2), {umin:.12g} J at r = {rs:.6g} m, got {E!r}: "
                    "no orbit has this energy and angular momentum."
                )
            start = rs
        else:
            gap = float(self._gap(np.array(radius)))
            scale = abs(E) + abs(float(self._ueff_raw(np.array(radius))))
            if gap < -1e-12 * scale:
                raise InvalidInputError(
                    f"Expected U_eff(radius) <= energy, got U_eff({radius:g}) = "
                    f"{E - gap:.12g} J > energy = {E:.12g} J: the particle cannot be there."
                )
            start = radius

        def f(r: float) -> float:
            return float(self._gap(np.array(r)))

        g0 = f(start)
        scale = abs(E) + abs(E - g0) + _EPS
        self._circular = False
        if g0 <= 4 * _EPS * scale:  # at an apsis, or at the bottom of a well
            slope = float(self._ueff_deriv(np.array(start)))
            size = abs(float(self.potential._deriv(np.array(start)))) + abs(
                self.angular_momentum**2 / (self.mass * start**3)
            )
            if abs(slope) <= 1e-11 * size:  # U_eff' = 0 too: a circular orbit
                self._r1 = self._r2 = start
                self._circular = True
                self.unbound = False
                return
            # step into the allowed side until E - U_eff > 0
            sgn = -1.0 if slope > 0 else 1.0
            delta = 1e-13
            while delta < 1e-4:
                probe = start * (1.0 + sgn * delta)
                if f(probe) > 0:
                    break
                delta *= 2.0
            else:  # E - U_eff never rises above round-off: circular to double precision
                self._r1 = self._r2 = start
                self._circular = True
                self.unbound = False
                return
            start = probe
        # inner root: halve until E - U_eff < 0 (at most 2^-200 of the start)
        prev, r, found = start, start, False
        for _ in range(200):
            r = 0.5 * prev
            g = float(self.energy - self._ueff_raw(np.array(r)))
            if np.isnan(g):
                f(r)  # raises the named error
            if g == np.inf:  # U_eff -> -inf: the centre attracts faster than L^2/r^2 repels
                break
            if g < 0:
                found = True
                break
            prev = r
        if not found:
            raise InvalidInputError(
                "Expected an orbit that stays away from the centre: E - U_eff stays positive "
                f"down to r = {r:.3g} m (the particle falls into the centre)."
            )
        self._r1 = brentq(f, r, prev, xtol=1e-300, rtol=4 * _EPS, maxiter=500)
        prev = start
        self.unbound = True
        for _ in range(2000):
            r = 2.0 * prev
            if r > 1e300:
                break
            if f(r) < 0:
                self.unbound = False
                break
            prev = r
        if self.unbound:
            self._r2 = math.inf
        else:
            self._r2 = brentq(f, prev, r, xtol=1e-300, rtol=4 * _EPS, maxiter=500)
            if self.potential.has_derivative and self._r2 - self._r1 <= 0.25 * self._r1:
                # nearly circular: make U_eff(r2) = U_eff(r1) hold through int_{r1}^{r2} U_eff'
                # (the roots of a near-double root are only ~sqrt(eps) accurate), bracketed
                # between the midpoint (rise < 0) and beyond r2 (rise > 0)
                x, w = _leggauss(32)
                r1 = self._r1

                def rise(r2: float) -> float:
                    h = 0.5 * (r2 - r1)
                    return h * float(self._ueff_deriv(r1 + h * (x + 1.0)) @ w)

                a = 0.5 * (r1 + self._r2)
                b = self._r2 + 0.5 * (self._r2 - r1)
                if rise(a) < 0 < rise(b):
                    self._r2 = brentq(rise, a, b, xtol=1e-300, rtol=4 * _EPS, maxiter=500)

    @property
    def apsides(self) -> Apsides:
        """Pericentre ``r_min`` and apocentre ``r_max`` (m); ``r_max = inf`` if unbound."""
        return Apsides(float(self._r1), float(self._r2))

    @property
    def is_circular(self) -> bool:
        """``E`` at the minimum of ``U_eff`` (``r_min = r_max``)."""
        return self._circular

    @property
    def areal_velocity(self) -> float:
        """``S' = r^2 phi' / 2 = L / (2 m)`` (m^2/s), constant (Kepler's second law)."""
        return self.angular_momentum / (2.0 * self.mass)

    # -- quadratures --------------------------------------------------------

    def _bound_integrals(self, n: int) -> tuple[float, float]:
        """``(half radial period, apsidal angle)`` by the midpoint rule with n nodes.

        ``r = r1 + 2 d sin^2(sigma/2) = r2 - 2 d cos^2(sigma/2)``, ``d = (r2 - r1)/2``,
        ``sigma = s + pi/2`` in ``(0, pi)``: ``dr = d sin(sigma) dsigma``.
        """
        r1, r2 = self._r1, self._r2
        d = 0.5 * (r2 - r1)
        sig = (np.arange(n) + 0.5) * (np.pi / n)
        off1 = 2.0 * d * np.sin(0.5 * sig) ** 2
        off2 = 2.0 * d * np.cos(0.5 * sig) ** 2
        r = np.where(sig < 0.5 * np.pi, r1 + off1, r2 - off2)
        gap = self._gap_nodes(r, off1, off2)
        inv = d * np.sin(sig) / np.sqrt(np.maximum(2.0 * gap / self.mass, 1e-300))
        w = np.pi / n
        half_t = w * np.sum(inv)
        ang = w * np.sum(inv * (abs(self.angular_momentum) / (self.mass * r * r)))
        return half_t, ang

    def _unbound_angle(self, n: int) -> float:
        """Angle from pericentre to infinity, ``u = 1/r = u1 cos^2 sigma`` (Gauss-Legendre
        on ``sigma`` in ``(0, pi/2)``): ``dphi = (L/m) du / sqrt(2 (E - U_eff) / m)``."""
        x, wts = _leggauss(n)
        sig = 0.25 * np.pi * (1.0 - x)
        u1 = 1.0 / self._r1
        cs, sn = np.cos(sig), np.sin(sig)
        with np.errstate(divide="ignore", over="ignore"):
            off1 = self._r1 * (sn / cs) ** 2
            r = self._r1 + off1
        gap = self._gap_nodes(r, off1, np.full(r.shape, np.inf))
        du = 2.0 * u1 * sn * cs
        integrand = (
            (abs(self.angular_momentum) / self.mass)
            * du
            / np.sqrt(np.maximum(2.0 * gap / self.mass, 1e-300))
        )
        return 0.25 * np.pi * np.sum(wts * integrand)

    def _converged(
        self, fn: Callable[[int], Any], start: int = 16, max_nodes: int = _MAX_NODES
    ) -> Any:
        prev = None
        n = start
        while n <= max_nodes:
            val = fn(n)
            if prev is not None and np.all(
                np.abs(np.asarray(val) - np.asarray(prev))
                <= QUADRATURE_RTOL * np.abs(np.asarray(val))
            ):
                return val
            prev = val
            n *= 2
        warnings.warn(
            f"Apsidal quadrature did not converge to {QUADRATURE_RTOL:g} with {max_nodes} "
            "nodes (an orbit grazing a maximum of U_eff?); the result is less accurate.",
            AccuracyWarning,
            stacklevel=3,
        )
        return val

    def _bottom(self) -> float:
        """``r_c``, the minimum of ``U_eff`` (``U_eff'(r_c) = 0``, a well-conditioned root)."""
        from scipy.optimize import brentq

        if self._circular:
            return self._r1

        def f(r: float) -> float:
            return float(self._ueff_deriv(np.array(r)))

        lo, hi = self._r1, self._r2
        for _ in range(60):  # the apsides may be off by ~sqrt(eps): widen the bracket
            if f(lo) < 0 < f(hi):
                return float(brentq(f, lo, hi, xtol=4 * _EPS * hi, rtol=4 * _EPS))
            lo, hi = lo * (1 - 1e-6), hi * (1 + 1e-6)
        return 0.5 * (self._r1 + self._r2)  # pragma: no cover - U_eff' without a sign change

    @functools.cached_property
    def _near_circular(self) -> tuple[float, float]:
        """``(radial period, apsidal angle)`` of a circular or nearly circular orbit.

        Both are smooth in the depth ``delta = E - U_eff(r_c)`` of the orbit in the
        well: ``T(delta) = T_0 + T_1 delta + O(delta^2)``. They are evaluated by the
        quadratures on two orbits of the same ``L`` with depths ``delta_1`` and
        ``2 delta_1`` (half-widths ~1e-4 r_c, where the quadratures keep 1e-13) and
        extrapolated linearly to ``delta`` (``0`` for a circular orbit): the neglected
        ``T_2 delta_1^2`` is ~1e-16 relative. This replaces both the degenerate
        quadrature and finite differences of ``U_eff''`` (which were 3e-11 off).
        """
        rc = self._bottom()
        u_min = float(self._ueff_raw(np.array(rc)))
        h = 1e-3 * rc  # U_eff'' only sets the depth's scale: a difference quotient will do
        upp = float(self._ueff_deriv(np.array(rc + h)) - self._ueff_deriv(np.array(rc - h)))
        upp /= 2.0 * h
        if not upp > 0:
            raise InvalidInputError(
                "The circular orbit sits on a maximum of U_eff (unstable): no radial "
                "oscillation, no apsidal angle."
            )
        delta1 = 0.5 * upp * (1e-4 * rc) ** 2
        values = []
        for k in (1.0, 2.0):
            orb = CentralOrbit(
                self.potential,
                energy=u_min + k * delta1,
                angular_momentum=self.angular_momentum,
                mass=self.mass,
                radius=rc,
            )
            values.append((orb.radial_period, orb.apsidal_angle))
        x = max(self.energy - u_min, 0.0) / delta1
        (t1, a1), (t2, a2) = values
        return t1 + (t2 - t1) * (x - 1.0), a1 + (a2 - a1) * (x - 1.0)

    def _is_near_circular(self) -> bool:
        if self._circular:
            return True
        if self.unbound:
            return False
        return (self._r2 - self._r1) <= _NEAR_CIRCULAR * (self._r2 + self._r1)

    @property
    def radial_period(self) -> float:
        """Time from pericentre to pericentre ``2 int_{r1}^{r2} dr / r'`` (s); ``inf`` if unbound.

        For a circular orbit, the period ``2 pi / omega_r`` of small radial
        oscillations, ``omega_r^2 = U_eff''(r) / m``.
        """
        if self.unbound:
            return math.inf
        if self._is_near_circular():
            return self._near_circular[0]
        return 2.0 * float(self._converged(self._bound_integrals)[0])

    @property
    def apsidal_angle(self) -> float:
        """Angle swept from pericentre to apocentre ``int phi' dr / r'`` (rad, > 0).

        ``pi`` for Kepler, ``pi/2`` for the oscillator; for an unbound orbit
        the angle from pericentre to infinity (the deflection is
        ``pi - 2 apsidal_angle``); for a circular orbit the limit
        ``pi phi' / omega_r``.
        """
        if self._is_near_circular():
            return self._near_circular[1]
        if self.unbound:
            return float(self._converged(self._unbound_angle, max_nodes=_MAX_GAUSS))
        return float(self._converged(self._bound_integrals)[1])

    def closure(self, *, rtol: float = 1e-9, max_denominator: int = 100) -> Fraction | None:
        """``apsidal_angle / pi`` as a fraction ``p/q`` (``q <= max_denominator``) within
        ``rtol``, or None: the orbit closes after ``q`` radial periods exactly when this
        is rational (Bertrand: for every bound orbit only Kepler and the oscillator)."""
        if self.unbound:
            return None
        x = self.apsidal_angle / math.pi
        f = Fraction(x).limit_denominator(max_denominator)
        return f if abs(float(f) - x) <= rtol * x else None

    def is_closed(self, *, rtol: float = 1e-9, max_denominator: int = 100) -> bool:
        """Whether the orbit closes: :meth:`closure` is not None."""
        return self.closure(rtol=rtol, max_denominator=max_denominator) is not None

    # -- pericentre of the initial state ---------------------------------------

    def _partial(self, r0: float, n: int) -> FloatArray:
        """Time and angle (>= 0) from the pericentre out to ``r0`` (Gauss-Legendre)."""
        r1, r2 = self._r1, self._r2
        x, wts = _leggauss(n)
        if self.unbound:  # u = u1 cos^2 sigma, sigma from 0 (pericentre) to sigma0
            sig0 = math.acos(min(1.0, math.sqrt(r1 / r0)))
            sig = 0.5 * sig0 * (x + 1.0)
            cs, sn = np.cos(sig), np.sin(sig)
            off1 = r1 * (sn / cs) ** 2
            r = r1 + off1
            gap = self._gap_nodes(r, off1, np.full(r.shape, np.inf))
            du = 2.0 / r1 * sn * cs
            inv = du * r * r / np.sqrt(np.maximum(2.0 * gap / self.mass, 1e-300))
            h = 0.5 * sig0
        else:  # r = r1 + 2 d sin^2(sigma/2), sigma from 0 to sigma0
            d = 0.5 * (r2 - r1)
            sig0 = 2.0 * math.asin(min(1.0, math.sqrt(max(0.0, (r0 - r1) / (2.0 * d)))))
            sig = 0.5 * sig0 * (x + 1.0)
            off1 = 2.0 * d * np.sin(0.5 * sig) ** 2
            off2 = 2.0 * d * np.cos(0.5 * sig) ** 2
            r = np.where(sig < 0.5 * np.pi, r1 + off1, r2 - off2)
            gap = self._gap_nodes(r, off1, off2)
            inv = d * np.sin(sig) / np.sqrt(np.maximum(2.0 * gap / self.mass, 1e-300))
            h = 0.5 * sig0
        t = h * np.sum(wts * inv)
        ang = h * np.sum(wts * inv * abs(self.angular_momentum) / (self.mass * r * r))
        return np.array([t, ang])

    def _pericentre_offsets(self) -> tuple[float, float]:
        """``(t_p, phi_p)``: time of the pericentre passage and its angle from ``e1``."""
        if self._circular or self._r0 <= self._r1:
            return 0.0, 0.0
        if self.potential.kepler_mu is not None and self.potential.kepler_mu > 0:
            tau = self._kepler_time_since_pericentre()
            nu = self._kepler_true_anomaly_at(self._r0, self._rdot0)
            return -tau, -nu * math.copysign(1.0, self.angular_momentum)
        t, ang = self._converged(
            lambda n: self._partial(self._r0, n), start=32, max_nodes=_MAX_GAUSS
        )
        sgn = 1.0 if self._rdot0 >= 0 else -1.0
        return -sgn * float(t), -sgn * float(ang) * math.copysign(1.0, self.angular_momentum)

    @property
    def pericentre_time(self) -> float:
        """A time (s) of passage through the pericentre (0 unless built by ``from_state``)."""
        return self._peri_time

    @property
    def pericentre_angle(self) -> float:
        """Angle (rad) of the pericentre from ``e1`` in the orbit plane."""
        return float(self._peri_angle)

    @property
    def pericentre_direction(self) -> np.ndarray:
        """Unit vector from the centre to the pericentre (space axes)."""
        a = self._peri_angle
        return self._basis @ np.array([math.cos(a), math.sin(a), 0.0])

    @property
    def normal(self) -> np.ndarray:
        """Unit normal ``n`` of the orbit plane (``L n`` is the angular momentum vector)."""
        return self._basis[:, 2].copy()

    # -- Kepler closed form --------------------------------------------------

    @property
    def conic(self) -> KeplerConic:
        """The conic of a pure Kepler potential (:func:`kepler`); InvalidInputError otherwise."""
        mu = self.potential.kepler_mu
        if mu is None or mu <= 0:
            raise InvalidInputError(
                "Expected a pure attractive Kepler potential kepler(mu), mu > 0, for the "
                f"conic, got {self.potential!r}."
            )
        m, L, E = self.mass, self.angular_momentum, self.energy
        p = L * L / (m * mu)
        e = math.sqrt(max(0.0, 1.0 + 2.0 * E * L * L / (m * mu * mu)))
        if E < 0:
            a = -mu / (2.0 * E)
            period = 2.0 * math.pi * math.sqrt(m * a**3 / mu)
            n = math.sqrt(mu / (m * a**3))
        elif E == 0:
            a, period, n = math.inf, math.inf, math.sqrt(mu / (m * p**3))
        else:
            a = -mu / (2.0 * E)
            period, n = math.inf, math.sqrt(mu / (m * (-a) ** 3))
        return KeplerConic(p=p, e=e, a=a, period=period, mean_motion=n)

    def _kepler_true_anomaly_at(self, r: float, rdot: float) -> float:
        """``nu`` from ``e cos nu = p/r - 1`` and ``e sin nu = r' m p / |L|`` (atan2)."""
        c = self.conic
        if c.e == 0:
            return 0.0
        return math.atan2(rdot * self.mass * c.p / abs(self.angular_momentum), c.p / r - 1.0)

    def _kepler_time_since_pericentre(self) -> float:
        c = self.conic
        r, rdot = self._r0, self._rdot0
        mu = self.potential.kepler_mu
        assert mu is not None  # only reached for a Kepler potential (self.conic exists)
        mus = mu / self.mass
        if c.e == 0:
            return 0.0
        if self.energy < 0:
            es = r * rdot / math.sqrt(mus * c.a)
            ec = 1.0 - r / c.a
            ea = math.atan2(es, ec)
            return (ea - c.e * math.sin(ea)) / c.mean_motion
        if self.energy > 0:
            aa = -c.a
            hs = r * rdot / math.sqrt(mus * aa) / c.e
            hh = math.asinh(hs)
            return (c.e * math.sinh(hh) - hh) / c.mean_motion
        nu = self._kepler_true_anomaly_at(r, rdot)
        dd = math.tan(0.5 * nu)
        return (dd + dd**3 / 3.0) / (2.0 * c.mean_motion)

    def _kepler_polar(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(r, nu)`` at times ``t`` (since ``t = 0``) from Kepler's equation."""
        c = self.conic
        tau = np.asarray(t, dtype=float) - self._peri_time
        e = c.e
        if self.energy < 0:
            M = c.mean_motion * tau
            k = np.round(M / (2 * np.pi))
            Mr = M - 2 * np.pi * k
            ea = _solve_kepler(Mr, e)
            r = c.a * (1.0 - e * np.cos(ea))
            nu = (
                2.0
                * np.arctan2(
                    math.sqrt(1 + e) * np.sin(0.5 * ea), math.sqrt(1 - e) * np.cos(0.5 * ea)
                )
                + 2 * np.pi * k
            )
        elif self.energy > 0:
            M = c.mean_motion * tau
            hh = _solve_hyperbolic(M, e)
            r = -c.a * (e * np.cosh(hh) - 1.0)
            nu = 2.0 * np.arctan2(
                math.sqrt(e + 1) * np.sinh(0.5 * hh), math.sqrt(e - 1) * np.cosh(0.5 * hh)
            )
        else:  # Barker's equation D + D^3/3 = 2 n tau, solved in closed form
            w = 3.0 * c.mean_motion * tau
            y = np.cbrt(w + np.sqrt(w * w + 1.0))
            dd = y - 1.0 / y
            nu = 2.0 * np.arctan(dd)
            r = c.p / (1.0 + np.cos(nu))
        return r, nu

    # -- the orbit -----------------------------------------------------------

    def _plane_to_space(self, r: FloatArray, phi: FloatArray) -> FloatArray:
        x = r * np.cos(phi)
        y = r * np.sin(phi)
        return x[..., None] * self._basis[:, 0] + y[..., None] * self._basis[:, 1]

    def polar(
        self, t: ArrayLike, *, method: str = "auto", rtol: float = 1e-12
    ) -> tuple[FloatArray, FloatArray]:
        """Distance ``r`` (m) and angle ``phi`` (rad, from ``e1``, continuous) at times ``t``.

        See :meth:`orbit` for ``method``. Returns a pair of arrays of ``t``'s shape.
        """
        r, _, phi = self._polar3(t, method, rtol)
        return r, phi

    def _polar3(
        self, t: ArrayLike, method: str, rtol: float
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(r, r', phi)`` at times ``t``."""
        t = as_float_array(t, "t")
        method = as_choice(method, "method", ("auto", "kepler", "integrate"))
        if method == "auto":
            pure = self.potential.kepler_mu is not None and self.potential.kepler_mu > 0
            method = "kepler" if pure else "integrate"
        if method == "integrate":
            return self._integrate(t, rtol)
        c = self.conic  # validates the potential
        if self._circular:
            wphi = self.angular_momentum / (self.mass * self._r1**2)
            return np.full(t.shape, self._r1), np.zeros(t.shape), wphi * t
        r, nu = self._kepler_polar(t)
        rdot = (abs(self.angular_momentum) / (self.mass * c.p)) * c.e * np.sin(nu)
        sgn = math.copysign(1.0, self.angular_momentum)
        return r, rdot, sgn * nu + self._peri_angle

    def orbit(self, t: ArrayLike, *, method: str = "auto", rtol: float = 1e-12) -> FloatArray:
        """Positions (m) at times ``t`` (s), shape ``t.shape + (3,)``, space axes.

        Parameters
        ----------
        t : array_like
            Times (s, any shape, any order; ``t = 0`` is the initial state).
        method : {"auto", "kepler", "integrate"}
            ``"kepler"``: the conic and Kepler's equation (pure :func:`kepler`
            potentials); ``"integrate"``: a bound orbit by DOP853 on Binet's
            equation ``u'' + u = m U'(1/u) / (L^2 u^2)`` in the swept angle
            (``u = 1/r``, ``t' = m / (L u^2)``) over one radial period, read at
            ``2 k A + psi(tau)`` for ``t = k T + tau`` (no error accumulates
            over periods; docs/particles.md gives the accuracy up to e = 0.9999);
            an unbound or nearly circular one by DOP853 in time on
            ``(r, r', phi)``; ``"auto"`` (default): Kepler's when it applies.
        rtol : float, optional
            Integration tolerance (default 1e-12; ``atol = rtol * r_min``).

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import CentralOrbit, kepler
        >>> orb = CentralOrbit(kepler(1.0), energy=-0.5, angular_momentum=0.8)
        >>> a = orb.orbit([0.0, np.pi], method="kepler")
        >>> b = orb.orbit([0.0, np.pi], method="integrate")
        >>> a.round(9) + 0.0, bool(np.allclose(a, b, atol=1e-9))
        (array([[ 0.4,  0. ,  0. ],
               [-1.6,  0. ,  0. ]]), True)
        """
        r, phi = self.polar(t, method=method, rtol=rtol)
        return self._plane_to_space(r, phi)

    def trajectory(
        self,
        t: ArrayLike,
        *,
        method: str = "auto",
        rtol: float = 1e-12,
        progress: Progress = None,
    ) -> PointTrajectory:
        """The orbit as a :class:`poinsot.trajectory.PointTrajectory` on times ``t`` (n,).

        ``position`` and ``velocity`` in inertial (space) axes (m, m/s), ``mass``
        (kg) and ``energy`` the total energy ``E = m v^2/2 + U(r)`` (J) at each
        sample (constant along the exact orbit). ``method`` as in :meth:`orbit`;
        the result's ``method`` is ``"exact"`` (Kepler's equation) or
        ``"adaptive"`` (integration). ``progress``: True (a bar), a callable receiving
        the fraction done, or None; Kepler's closed form on more than 65536 times is
        evaluated in chunks, between which Ctrl-C stops it (``KeyboardInterrupt``).
        """
        return _trajectory(self, t, method, rtol, progress)

    def _integrate(self, t: FloatArray, rtol: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        rtol = _coef(rtol, "rtol")
        if not rtol > 0:
            raise InvalidInputError(f"Expected `rtol` > 0, got {rtol!r}.")
        if not self.unbound and not self._is_near_circular():
            self._warn_sensitive(t)
            return self._integrate_binet(t, rtol)
        return self._integrate_time(t, rtol)

    def _warn_sensitive(self, t: FloatArray) -> None:
        """An :class:`AccuracyWarning` with the size when a nearly parabolic bound orbit
        is too sensitive to its inputs for ~1e-10 (docs/particles.md): one ulp of the
        speed moves ``E`` by ``eps / (1 - e)``, the period by 3/2 of that, and a later
        pericentre by ``v_p`` times the accumulated time shift; the integration's error
        is within ~10x of that."""
        r1, r2 = self._r1, self._r2
        e = (r2 - r1) / (r2 + r1)
        if t.size == 0 or e < 0.99:
            return
        a = 0.5 * (r1 + r2)
        period = self.radial_period
        periods = max(float(np.max(np.abs(t - t.flat[0]))) / period, 1.0)
        v_p = abs(self.angular_momentum) / (self.mass * r1)
        moved = 1.5 * _EPS / (1.0 - e) * periods * v_p * period / a
        # measured against 50-digit mpmath: 5.6x `moved` at e = 0.99, 22x at e = 0.9999
        if 25.0 * moved > 1e-9:
            warnings.warn(
                f"A nearly parabolic orbit (e = {e:.6g}) over {periods:.3g} radial periods: "
                f"the integrated orbit is good to ~{25 * moved:.1e} of a, the bound of the "
                f"integration in the swept angle near e = 1. It is what the problem allows "
                f"for an orbit started from a state (one ulp of the speed moves the position "
                f"by ~{moved:.1e} of a); an orbit given by (E, L) is better conditioned than "
                f"that, and for a Kepler potential method='kepler' keeps ~1e-13 "
                f"(docs/particles.md).",
                AccuracyWarning,
                stacklevel=4,
            )

    def _integrate_binet(
        self, t: FloatArray, rtol: float
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(r, r', phi)`` of a bound orbit by integrating in the swept angle ``psi``.

        Binet's form ``u'' + u = (m / (L^2 u^2)) U'(1/u)`` with ``u = 1/r`` and
        ``t' = m / (|L| u^2)`` (primes: ``d/dpsi``): the step follows the angle, not
        the time, so a pericentre passage of an orbit with ``e -> 1`` takes as many
        steps as any other arc (integrating in time lost 4e-8 at e = 0.99 and 2e-3
        at e = 0.999999 over three periods). The samples at the requested times are
        found by Newton's method on ``t(psi)`` through the dense output.
        """
        from scipy.integrate import solve_ivp

        m, L = self.mass, abs(self.angular_momentum)
        d = self.potential._deriv

        def rhs(_psi: float, y: FloatArray) -> FloatArray:
            u = y[0]
            return np.array(
                [y[1], -u + m * float(d(np.array(1.0 / u))) / (L * L * u * u), m / (L * u * u)]
            )

        flat = t.ravel()
        y0 = np.array([1.0 / self._r0, -self._rdot0 * m / L, 0.0])
        sgn_l = math.copysign(1.0, self.angular_momentum)
        period, angle = self.radial_period, self.apsidal_angle
        # One radial period suffices: (u, u') is periodic in psi with period 2 A and t
        # grows by T each time, so a time t = k T + tau is psi = 2 k A + psi(tau). No
        # error accumulates over many periods. The tolerance of t is tighter: near the
        # pericentre of an orbit with e -> 1 an error dt moves the point by v_p dt.
        tol = min(rtol, 1e-13)
        atol = [tol / self._r1, tol / self._r1, tol * 1e-3 * period]
        sol = solve_ivp(
            rhs, (0.0, 2.0 * angle), y0, method="DOP853", rtol=tol, atol=atol, dense_output=True
        )
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            raise IntegrationError(f"Orbit integration failed: {sol.message}")
        t_one = float(sol.y[2, -1])  # = T to the integration's accuracy
        k = np.floor(flat / t_one)
        tau = flat - k * t_one
        psi = np.interp(tau, sol.y[2], sol.t)
        for _ in range(8):  # Newton on t(psi) = tau, t' = m / (L u^2) > 0
            y = sol.sol(psi)
            step = (y[2] - tau) * (L * y[0] * y[0] / m)
            psi = np.clip(psi - step, 0.0, 2.0 * angle)
            if np.all(np.abs(step) <= 4 * _EPS * np.maximum(1.0, psi)):
                break
        y = sol.sol(psi)
        r = 1.0 / y[0]
        rdot = -y[1] * L / m
        phi = sgn_l * (psi + 2.0 * angle * k)
        return r.reshape(t.shape), rdot.reshape(t.shape), phi.reshape(t.shape)

    def _integrate_time(
        self, t: FloatArray, rtol: float
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(r, r', phi)`` by DOP853 in time (unbound and nearly circular orbits)."""
        from scipy.integrate import solve_ivp

        m, L = self.mass, self.angular_momentum
        d = self.potential._deriv

        def rhs(_t: float, y: FloatArray) -> FloatArray:
            r = y[0]
            acc = L * L / (m * m * r**3) - float(d(np.array(r))) / m
            return np.array([y[1], acc, L / (m * r * r)])

        flat = t.ravel()
        out_r = np.empty(flat.shape)
        out_v = np.empty(flat.shape)
        out_p = np.empty(flat.shape)
        y0 = np.array([self._r0, self._rdot0, 0.0])
        atol = rtol * self._r1
        for sgn in (1.0, -1.0):
            sel = (flat > 0) if sgn > 0 else (flat < 0)
            zero = flat == 0
            out_r[zero], out_v[zero], out_p[zero] = self._r0, self._rdot0, 0.0
            if not np.any(sel):
                continue
            ts = np.unique(flat[sel])
            if sgn < 0:
                ts = ts[::-1]
            sol = solve_ivp(
                rhs,
                (0.0, ts[-1]),
                y0,
                method="DOP853",
                t_eval=ts,
                rtol=rtol,
                atol=[atol, rtol * abs(L) / (m * self._r1), rtol],
            )
            if sol.status != 0 or not np.all(np.isfinite(sol.y)):
                raise IntegrationError(f"Orbit integration failed: {sol.message}")
            idx = np.searchsorted(ts[::-1] if sgn < 0 else ts, flat[sel])
            ys = sol.y[:, ::-1] if sgn < 0 else sol.y
            out_r[sel], out_v[sel], out_p[sel] = ys[0][idx], ys[1][idx], ys[2][idx]
        return out_r.reshape(t.shape), out_v.reshape(t.shape), out_p.reshape(t.shape)

    def state(
        self, t: ArrayLike, *, method: str = "auto", rtol: float = 1e-12
    ) -> tuple[FloatArray, FloatArray]:
        """``(position, velocity)`` at times ``t``: shape ``t.shape + (3,)`` each (m, m/s).

        ``v = r' e_r + r phi' e_phi`` with ``phi' = L / (m r^2)``; see :meth:`orbit`.
        """
        r, rdot, phi = self._polar3(t, method, rtol)
        phidot = self.angular_momentum / (self.mass * r * r)
        e_r = self._plane_to_space(np.ones_like(r), phi)
        e_phi = self._plane_to_space(np.ones_like(r), phi + 0.5 * np.pi)
        return r[..., None] * e_r, rdot[..., None] * e_r + (r * phidot)[..., None] * e_phi


def _trajectory(
    orbit: CentralOrbit, t: ArrayLike, method: str, rtol: float, progress: Progress = None
) -> PointTrajectory:
    t = as_float_array(t, "t")
    if t.ndim != 1:
        raise InvalidInputError(f"Expected `t` of shape (n,), got {t.shape}.")
    pure = orbit.potential.kepler_mu is not None and orbit.potential.kepler_mu > 0
    used = ("kepler" if pure else "integrate") if method == "auto" else method
    if used == "kepler":  # a closed form per sample: in chunks (Ctrl-C, progress)
        x, v = in_chunks(lambda tc: orbit.state(tc, method=method, rtol=rtol), t, progress,
                         "CentralOrbit")  # fmt: skip
    else:
        x, v = orbit.state(t, method=method, rtol=rtol)
    info = (
        {"closed_form": "kepler"}
        if used == "kepler"
        else {"solver": "DOP853", "rtol": rtol, "atol": rtol * orbit.apsides.pericentre}
    )
    energy = 0.5 * orbit.mass * np.sum(v * v, axis=-1) + orbit.potential(np.linalg.norm(x, axis=-1))
    return PointTrajectory(
        t,
        x,
        v,
        "exact" if used == "kepler" else "adaptive",
        frame_name="inertial",
        mass=np.asarray(orbit.mass, dtype=np.float64),
        energy=energy,
        info=info,
    )


def _solve_kepler(M: ArrayLike, e: float) -> FloatArray:
    """Eccentric anomaly ``E - e sin E = M`` for ``M`` in [-pi, pi] (Newton, vectorised)."""
    M = np.asarray(M, dtype=float)
    ea = np.where(e < 0.8, M, np.pi * np.sign(M))
    ea = np.where(M == 0, 0.0, ea)
    for _ in range(60):
        f = ea - e * np.sin(ea) - M
        step = f / (1.0 - e * np.cos(ea))
        ea = ea - step
        if np.all(np.abs(step) <= 4 * _EPS * np.maximum(1.0, np.abs(ea))):
            break
    return ea


def _solve_hyperbolic(M: ArrayLike, e: float) -> FloatArray:
    """Hyperbolic anomaly ``e sinh H - H = M`` (Newton from ``asinh(M/e)``-like start)."""
    M = np.asarray(M, dtype=float)
    hh = np.sign(M) * np.log(2.0 * np.abs(M) / e + 1.8)
    for _ in range(100):
        f = e * np.sinh(hh) - hh - M
        step = f / (e * np.cosh(hh) - 1.0)
        hh = hh - step
        if np.all(np.abs(step) <= 4 * _EPS * np.maximum(1.0, np.abs(hh))):
            break
    return hh
