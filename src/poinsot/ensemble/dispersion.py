"""Dispersions: how each uncertain input of an ensemble is drawn.

A dispersion draws ``n`` values of one quantity from a seeded
:class:`numpy.random.Generator`. Scalar and vector quantities use the
distributions of :data:`DISTRIBUTIONS`; the attitude uses a dispersion on SO(3)
(:class:`SmallRotation` about the nominal, or :class:`UniformRotation`).

Every distribution is written about the **nominal** value of the scenario
unless it gives absolute bounds:

========================  =====================================================
``normal``                ``nominal + sigma * N(0, 1)``, per component
``truncated_normal``      the same, redrawn until inside ``[low, high]``
                          (exact rejection: the truncated law, not clipping)
``uniform``               ``U(low, high)``, or ``nominal + U(-half_width, +half_width)``
``lognormal``             ``nominal * exp(sigma * N(0, 1))`` (positive quantities)
``truncated_lognormal``   the same, inside ``[low, high]``
``choice``                one of ``values`` (a fixed list), equally likely
``small_rotation``        attitude ``R = exp(phi^) R_nominal`` (space-axes
                          perturbation), ``phi ~ N(0, sigma^2 E)``, sigma in degrees
``uniform_rotation``      attitude uniform on SO(3) (Haar measure)
========================  =====================================================

Units are those of the quantity (rad/s for ``omega0``, kg m^2 for
``inertia``, ...); the attitude's ``sigma`` is in degrees (the scenario
file's convention for angles).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array
from ..errors import InvalidInputError, InvalidTypeError
from ..rotations import quaternion as qa

__all__ = [
    "Dispersion",
    "Normal",
    "TruncatedNormal",
    "Uniform",
    "LogNormal",
    "TruncatedLogNormal",
    "Choice",
    "SmallRotation",
    "UniformRotation",
    "DISTRIBUTIONS",
    "from_table",
]

_MAX_REJECTION_ROUNDS = 200


def _nonneg(x: ArrayLike, name: str) -> np.ndarray:
    a = as_float_array(x, name)
    if np.any(a < 0):
        raise InvalidInputError(f"Expected `{name}` to be >= 0 (a spread), got {a.tolist()}.")
    return a


class Dispersion:
    """Base class: ``sample(nominal, rng, n) -> (n, *shape)`` draws."""

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        raise NotImplementedError


def _truncate(
    draw: Callable[[tuple[int, ...]], np.ndarray],
    low: ArrayLike,
    high: ArrayLike,
    n: int,
    shape: tuple[int, ...],
    name: str,
) -> np.ndarray:
    """Exact rejection sampling of ``draw(k)`` restricted to ``[low, high]``."""
    out = np.empty((n, *shape))
    todo = np.ones((n, *shape), dtype=bool)
    for _ in range(_MAX_REJECTION_ROUNDS):
        k = int(todo.sum())
        if k == 0:
            return out
        x = draw((n, *shape))
        take = todo & (x >= low) & (x <= high)
        out[take] = x[take]
        todo &= ~take
    raise InvalidInputError(
        f"The truncation interval of `{name}` has almost no probability under its "
        f"distribution (rejection sampling did not finish); widen [low, high]."
    )


@dataclass(frozen=True)
class Normal(Dispersion):
    """``nominal + sigma * N(0, 1)`` (``mean`` replaces the nominal if given).

    Examples
    --------
    >>> import numpy as np
    >>> x = Normal(sigma=0.1).sample(np.array([1.0, 2.0]), np.random.default_rng(0), 4000)
    >>> x.shape, bool(abs(x[:, 1].std() - 0.1) < 0.01)
    ((4000, 2), True)
    """

    sigma: Any
    mean: Any = None

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        sigma = _nonneg(self.sigma, "sigma")
        mean = nominal if self.mean is None else as_float_array(self.mean, "mean")
        shape = np.broadcast_shapes(np.shape(mean), sigma.shape)
        return mean + sigma * rng.standard_normal((n, *shape))


@dataclass(frozen=True)
class TruncatedNormal(Normal):
    """:class:`Normal` restricted to ``[low, high]`` (exact truncated law)."""

    low: Any = -np.inf
    high: Any = np.inf

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        sigma = _nonneg(self.sigma, "sigma")
        mean = nominal if self.mean is None else as_float_array(self.mean, "mean")
        low = as_float_array(self.low, "low", finite=False)
        high = as_float_array(self.high, "high", finite=False)
        if np.any(low >= high):
            raise InvalidInputError(f"Expected `low` < `high`, got {low} and {high}.")
        shape = np.broadcast_shapes(np.shape(mean), sigma.shape, low.shape, high.shape)
        return _truncate(
            lambda s: mean + sigma * rng.standard_normal(s), low, high, n, shape, "truncated_normal"
        )


@dataclass(frozen=True)
class Uniform(Dispersion):
    """``U(low, high)``, or ``nominal + U(-half_width, half_width)``.

    Examples
    --------
    >>> import numpy as np
    >>> x = Uniform(half_width=0.5).sample(np.array(2.0), np.random.default_rng(1), 1000)
    >>> bool(x.min() >= 1.5 and x.max() <= 2.5)
    True
    """

    low: Any = None
    high: Any = None
    half_width: Any = None

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.half_width is not None:
            if self.low is not None or self.high is not None:
                raise InvalidInputError(
                    "A uniform dispersion takes either `low` and `high` or `half_width`, not both."
                )
            hw = _nonneg(self.half_width, "half_width")
            low, high = nominal - hw, nominal + hw
        else:
            if self.low is None or self.high is None:
                raise InvalidInputError(
                    "A uniform dispersion needs `low` and `high` (or `half_width`)."
                )
            low = as_float_array(self.low, "low")
            high = as_float_array(self.high, "high")
            if np.any(low > high):
                raise InvalidInputError(f"Expected `low` <= `high`, got {low} and {high}.")
        shape = np.broadcast_shapes(np.shape(low), np.shape(high))
        return low + (high - low) * rng.random((n, *shape))


@dataclass(frozen=True)
class LogNormal(Dispersion):
    """``nominal * exp(sigma N(0, 1))``: a positive quantity with relative spread."""

    sigma: Any

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        sigma = _nonneg(self.sigma, "sigma")
        if np.any(np.asarray(nominal) <= 0):
            raise InvalidInputError(
                "A lognormal dispersion needs a positive nominal value, got "
                f"{np.asarray(nominal).tolist()}."
            )
        shape = np.broadcast_shapes(np.shape(nominal), sigma.shape)
        return nominal * np.exp(sigma * rng.standard_normal((n, *shape)))


@dataclass(frozen=True)
class TruncatedLogNormal(LogNormal):
    """:class:`LogNormal` restricted to ``[low, high]``."""

    low: Any = 0.0
    high: Any = np.inf

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        sigma = _nonneg(self.sigma, "sigma")
        low = as_float_array(self.low, "low", finite=False)
        high = as_float_array(self.high, "high", finite=False)
        if np.any(low >= high):
            raise InvalidInputError(f"Expected `low` < `high`, got {low} and {high}.")
        LogNormal(sigma).sample(nominal, rng, 0)  # validates the nominal
        shape = np.broadcast_shapes(np.shape(nominal), sigma.shape)
        return _truncate(
            lambda s: nominal * np.exp(sigma * rng.standard_normal(s)),
            low,
            high,
            n,
            shape,
            "truncated_lognormal",
        )


@dataclass(frozen=True)
class Choice(Dispersion):
    """One of a fixed list of ``values``, equally likely."""

    values: Any

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        v = as_float_array(self.values, "values")
        if v.ndim == 0 or len(v) == 0:
            raise InvalidInputError("Expected `values` to be a non-empty list.")
        return v[rng.integers(0, len(v), n)]


@dataclass(frozen=True)
class SmallRotation(Dispersion):
    """Attitude ``exp(phi^) R_nominal``, ``phi ~ N(0, sigma^2)`` per axis, sigma in degrees.

    ``nominal`` and the draws are scalar-first unit quaternions (body -> space);
    the perturbation is about space axes (left multiplication).
    """

    sigma: Any

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        sigma = float(_nonneg(self.sigma, "sigma"))
        phi = np.deg2rad(sigma) * rng.standard_normal((n, 3))
        return qa.multiply(qa.exp(np.concatenate([np.zeros((n, 1)), phi / 2], axis=1)), nominal)


@dataclass(frozen=True)
class UniformRotation(Dispersion):
    """Attitude uniform on SO(3): a normalised 4-D Gaussian (Haar measure)."""

    def sample(self, nominal: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
        q = rng.standard_normal((n, 4))
        q /= np.linalg.norm(q, axis=1, keepdims=True)
        return q * np.where(q[:, :1] < 0, -1.0, 1.0)


#: Distribution name -> (class, accepted keys).
DISTRIBUTIONS: dict[str, tuple[type, tuple[str, ...]]] = {
    "normal": (Normal, ("sigma", "mean")),
    "truncated_normal": (TruncatedNormal, ("sigma", "mean", "low", "high")),
    "uniform": (Uniform, ("low", "high", "half_width")),
    "lognormal": (LogNormal, ("sigma",)),
    "truncated_lognormal": (TruncatedLogNormal, ("sigma", "low", "high")),
    "choice": (Choice, ("values",)),
    "small_rotation": (SmallRotation, ("sigma",)),
    "uniform_rotation": (UniformRotation, ()),
}


def from_table(table: dict[str, Any], name: str) -> Dispersion:
    """Build a dispersion from a TOML table ``{distribution = "...", ...}``.

    Examples
    --------
    >>> from_table({"distribution": "normal", "sigma": 0.1}, "omega0")
    Normal(sigma=0.1, mean=None)
    >>> from poinsot.errors import InvalidInputError
    >>> try:
    ...     from_table({"distribution": "gauss"}, "omega0")
    ... except InvalidInputError as exc:
    ...     print(str(exc)[:60])
    Unknown distribution 'gauss' for `dispersion.omega0`; expect
    """
    if not isinstance(table, dict):
        raise InvalidTypeError(
            f"Expected `dispersion.{name}` to be a table, got {type(table).__name__}."
        )
    kind = table.get("distribution")
    if kind not in DISTRIBUTIONS:
        raise InvalidInputError(
            f"Unknown distribution {kind!r} for `dispersion.{name}`; expected one of "
            + ", ".join(DISTRIBUTIONS)
            + "."
        )
    cls, keys = DISTRIBUTIONS[kind]
    extra = sorted(set(table) - {"distribution", *keys})
    if extra:
        raise InvalidInputError(
            f"Unknown key(s) {', '.join(extra)} in `dispersion.{name}` ({kind}); "
            f"accepted: {', '.join(keys) or 'none'}."
        )
    kwargs = {k: table[k] for k in keys if k in table}
    try:
        d = cls(**kwargs)
    except TypeError as exc:
        raise InvalidInputError(f"`dispersion.{name}` ({kind}) is missing a key: {exc}") from None
    for key in ("sigma", "half_width"):
        if key in kwargs:
            _nonneg(kwargs[key], f"dispersion.{name}.{key}")
    return d
