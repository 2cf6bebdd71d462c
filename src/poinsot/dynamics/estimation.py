"""Attitude estimation: sensor models and the multiplicative extended Kalman filter
(docs/theory.md §10.4).

Sensors sample a poinsot :class:`~poinsot.Trajectory` (the truth, e.g. an exact
:class:`~poinsot.dynamics.FreeRigidBody` motion) reproducibly from a seed:
:class:`Gyro` (Farrenkopf's rate-gyro model: angle and rate random walks, a bias that
wanders, an optional scale-factor error), :class:`StarTracker` (attitude quaternions
with small-angle noise, optionally larger about the boresight ``z``) and
:class:`VectorSensor` (unit directions: Sun sensor, magnetometer). :func:`run_mekf`
fuses them in the MEKF of Lefferts, Markley & Shuster (1982) as written in Crassidis &
Junkins, *Optimal Estimation of Dynamic Systems*, §7.2: quaternion and gyro bias, a
6 x 6 error covariance, the exact constant-rate quaternion propagation, sequential
updates and the multiplicative reset. :func:`attitude_error`, :func:`nees` and
:func:`nis` measure the result.

**Convention:** scalar-first Hamilton quaternions of ``C_nb`` (body -> inertial);
vector observations ``b = A r`` with ``A = C_nb^T``; attitude errors are small-angle
vectors in body axes (rad): ``L_est = L_true o exp(dtheta/2)``; rates in rad/s, biases
in rad/s, times in s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _quat
from .._typing import ArrayLike, FloatArray
from .._validate import as_choice, as_float_array, as_rotation_quat
from .._vec import hat
from ..errors import InvalidInputError, InvalidTypeError
from ..rotations.rotvec import rotvec_from_quat
from ..trajectory import Trajectory

__all__ = [
    "Gyro",
    "GyroSamples",
    "GYRO_KINDS",
    "StarTracker",
    "AttitudeSamples",
    "VectorSensor",
    "VectorSamples",
    "MEKF",
    "EstimationResult",
    "run_mekf",
    "attitude_error",
    "nees",
    "nis",
]

#: Below this rotation angle ``theta = |w| dt`` (rad) the transition matrix uses its
#: Taylor series (two terms; the first omitted term is below ``theta^4 / 120 ~ 1e-14``).
_SERIES_THETA = 1e-3

#: The sampling kinds of :class:`Gyro`.
GYRO_KINDS = ("integrating", "rate")

_EYE3 = np.eye(3)
_EYE6 = np.eye(6)


def _rng(rng: object) -> np.random.Generator:
    if rng is None or isinstance(rng, int | np.integer | np.random.Generator):
        return np.random.default_rng(rng)
    raise InvalidTypeError(
        f"Expected `rng` to be a numpy Generator, an int seed or None, got {type(rng).__name__}."
    )


def _sigma(x: object, name: str) -> float:
    a = as_float_array(x, name)
    if a.ndim != 0:
        raise InvalidInputError(f"Expected `{name}` to be a scalar, got shape {a.shape}.")
    if a < 0.0:
        raise InvalidInputError(f"Expected `{name}` to be >= 0, got {float(a)!r}.")
    return float(a)


def _truth(truth: object) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(t, quat, omega)`` of one body's Trajectory, times strictly increasing."""
    if not isinstance(truth, Trajectory):
        raise InvalidTypeError(
            f"Expected `truth` to be a poinsot Trajectory, got {type(truth).__name__}."
        )
    q = np.asarray(truth.quat)
    if q.ndim != 2:
        raise InvalidInputError(
            f"Expected `truth` to hold one body (quat of shape (n, 4)), got {q.shape}."
        )
    t = np.asarray(truth.t, dtype=np.float64)
    if t.size > 1 and not np.all(np.diff(t) > 0.0):
        raise InvalidInputError("Expected the times of `truth` to be strictly increasing.")
    return t, q, np.asarray(truth.omega, dtype=np.float64)


def _readonly(**arrays: Any) -> None:
    for a in arrays.values():
        if isinstance(a, np.ndarray):
            a.setflags(write=False)


def _perpendicular_basis(u: FloatArray) -> FloatArray:
    """Two unit vectors ``(2, 3)`` perpendicular to unit ``u`` and to each other."""
    k = int(np.argmin(np.abs(u)))
    e1 = np.cross(u, _EYE3[k])
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(u, e1)])


# --------------------------------------------------------------------------- sensors
@dataclass(frozen=True, repr=False)
class GyroSamples:
    """Rate-gyro samples and the truth they were drawn from.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times (s).
    rate : ndarray, shape (n, 3)
        Measured angular velocity in body axes (rad/s).
    omega : ndarray, shape (n, 3)
        True angular velocity in body axes (rad/s).
    bias : ndarray, shape (n, 3)
        True bias ``b_k`` at each sample (rad/s).
    quat : ndarray, shape (n, 4)
        True attitude (scalar-first, body -> inertial) at each sample.
    arw, rrw : float
        The model's ``sigma_v`` (rad/s^0.5) and ``sigma_u`` (rad/s^1.5), read by
        :func:`run_mekf` as its gyro noise unless overridden.
    kind : str
        ``"integrating"``: ``rate[k]`` (k >= 1) is the mean over ``(t_{k-1}, t_k]``;
        ``"rate"``: the rate at ``t_k`` (see :class:`Gyro`).

    Notes
    -----
    **Convention:** body axes, rad/s; docs/theory.md §10.4. Frozen; arrays read-only.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory(np.arange(3.0))
    >>> Gyro(0.0, 0.0).sample(truth, rng=0).rate.round(12) + 0.0
    array([[0., 0., 1.],
           [0., 0., 1.],
           [0., 0., 1.]])
    """

    t: FloatArray
    rate: FloatArray
    omega: FloatArray
    bias: FloatArray
    quat: FloatArray
    arw: float
    rrw: float
    kind: str = "integrating"

    def __post_init__(self) -> None:
        _readonly(t=self.t, rate=self.rate, omega=self.omega, bias=self.bias, quat=self.quat)

    def __repr__(self) -> str:
        return f"GyroSamples({self.t.size} samples, arw={self.arw:g}, rrw={self.rrw:g})"


@dataclass(frozen=True, repr=False)
class Gyro:
    """Farrenkopf's rate-integrating gyro (docs/theory.md §10.4).

    Continuous model ``w_m = (1 + s) w + b + eta_v``, ``b' = eta_u``, with white noises
    of spectral densities ``sigma_v^2`` (angle random walk) and ``sigma_u^2`` (rate
    random walk). Sampled at the truth's times ``t_k`` (``dt = t_{k+1} - t_k``) with the
    exact discretisation of Crassidis & Junkins (Optimal Estimation, §7.2)::

        b_{k+1} = b_k + sigma_u sqrt(dt) N_u
        w_m,{k+1} = (1 + s) w_{k+1} + (b_{k+1} + b_k)/2
                    + sqrt(sigma_v^2/dt + sigma_u^2 dt/12) N_v

    with ``N_u, N_v`` independent standard normal 3-vectors; the first sample uses
    ``b_0`` and the noise of the first interval.

    Parameters
    ----------
    arw : float
        ``sigma_v`` (rad/s^0.5), >= 0.
    rrw : float
        ``sigma_u`` (rad/s^1.5), >= 0.
    bias0 : array_like, shape (3,)
        The bias at the first sample (rad/s).
    scale_factor : float
        ``s``, the (unmodelled by :func:`run_mekf`) scale-factor error.
    kind : {"integrating", "rate"}
        ``"integrating"`` (a rate-integrating gyro, the model above): sample ``k >= 1``
        is the mean rate over ``(t_{k-1}, t_k]``, ``w = log(L_{k-1}~ o L_k) / dt``
        (the constant body rate that carries the true attitude across the interval,
        so that a perfect gyro and the exact constant-rate propagation reproduce the
        truth; steps of less than ``pi`` rad); sample 0 is ``w(t_0)``. ``"rate"``:
        the rate at ``t_k``, ``(1 + s) w(t_k) + b_k`` plus the same noise; the filter
        then holds it over ``[t_k, t_{k+1})``, a first-order approximation.

    Notes
    -----
    **Convention:** body axes (the gyro axes are the body axes), rad/s.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory(np.arange(3.0))
    >>> Gyro(0.0, 0.0, bias0=[0.01, 0.0, 0.0]).sample(truth, rng=1).rate[0]
    array([0.01, 0.  , 1.  ])
    """

    arw: float
    rrw: float
    bias0: Any = (0.0, 0.0, 0.0)
    scale_factor: float = 0.0
    kind: str = "integrating"

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", as_choice(self.kind, "kind", GYRO_KINDS))
        object.__setattr__(self, "arw", _sigma(self.arw, "arw"))
        object.__setattr__(self, "rrw", _sigma(self.rrw, "rrw"))
        b = as_float_array(self.bias0, "bias0")
        if b.shape != (3,):
            raise InvalidInputError(f"Expected `bias0` to have shape (3,), got {b.shape}.")
        b.setflags(write=False)
        object.__setattr__(self, "bias0", b)
        s = as_float_array(self.scale_factor, "scale_factor")
        if s.ndim != 0:
            raise InvalidInputError(f"Expected `scale_factor` to be a scalar, got {s.shape}.")
        object.__setattr__(self, "scale_factor", float(s))

    def __repr__(self) -> str:
        return (
            f"Gyro(arw={self.arw:g}, rrw={self.rrw:g}, scale_factor={self.scale_factor:g}, "
            f"kind={self.kind!r})"
        )

    def sample(self, truth: Trajectory, *, rng: object = None) -> GyroSamples:
        """Gyro samples at the times of ``truth`` (at least two), drawn from ``rng``."""
        t, q, w = _truth(truth)
        if t.size < 2:
            raise InvalidInputError(f"Expected `truth` to have >= 2 samples, got {t.size}.")
        g = _rng(rng)
        dt = np.diff(t)
        n = t.size
        bias = np.empty((n, 3))
        bias[0] = self.bias0
        steps = self.rrw * np.sqrt(dt)[:, None] * g.standard_normal((n - 1, 3))
        bias[1:] = self.bias0 + np.cumsum(steps, axis=0)
        sd = np.sqrt(self.arw**2 / dt + self.rrw**2 * dt / 12.0)
        sd = np.concatenate([sd[:1], sd])
        if self.kind == "integrating":
            # the constant rate that carries L_{k-1} to L_k: log(L_{k-1}~ o L_k) / dt
            inc = _quat.mul(_quat.conj(q[:-1]), q[1:])
            inc = np.where(inc[:, :1] < 0.0, -inc, inc)
            mean = np.concatenate([w[:1], rotvec_from_quat(inc) / dt[:, None]])
            mean_bias = np.concatenate([bias[:1], 0.5 * (bias[1:] + bias[:-1])])
        else:
            mean, mean_bias = w, bias
        noise = sd[:, None] * g.standard_normal((n, 3))
        rate = (1.0 + self.scale_factor) * mean + mean_bias + noise
        return GyroSamples(t, rate, w.copy(), bias, q.copy(), self.arw, self.rrw, self.kind)


@dataclass(frozen=True, repr=False)
class AttitudeSamples:
    """Star-tracker quaternion measurements.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s).
    quat : ndarray, shape (n, 4)
        Measured attitude ``L_m = L o exp(nu/2)`` (scalar-first, body -> inertial).
    true_quat : ndarray, shape (n, 4)
        The true attitude ``L``.
    sigma : ndarray, shape (3,)
        Standard deviations of ``nu`` about the body axes x, y, z (rad).

    Notes
    -----
    **Convention:** ``nu`` in body axes (the sensor axes), rad; docs/theory.md §10.4.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, StarTracker
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory([0.0, 1.0])
    >>> StarTracker(1e-4, boresight_sigma=1e-3).sample(truth, rng=0).sigma
    array([0.0001, 0.0001, 0.001 ])
    """

    t: FloatArray
    quat: FloatArray
    true_quat: FloatArray
    sigma: FloatArray

    def __post_init__(self) -> None:
        _readonly(t=self.t, quat=self.quat, true_quat=self.true_quat, sigma=self.sigma)

    def __repr__(self) -> str:
        return f"AttitudeSamples({self.t.size} samples, sigma={self.sigma.tolist()} rad)"


@dataclass(frozen=True, repr=False)
class StarTracker:
    """A star tracker: the attitude with small-angle noise ``L_m = L o exp(nu/2)``.

    ``nu ~ N(0, diag(sigma^2, sigma^2, sigma_b^2))`` in body axes, the boresight along
    body ``z`` (``sigma_b = boresight_sigma``, default ``sigma``) (docs/theory.md §10.4).

    Parameters
    ----------
    sigma : float
        Cross-boresight standard deviation (rad), >= 0.
    boresight_sigma : float, optional
        About the boresight ``z`` (rad), >= 0; typically several times ``sigma``.

    Notes
    -----
    **Convention:** scalar-first quaternions body -> inertial; noise in body axes.

    Examples
    --------
    >>> from poinsot.dynamics import StarTracker
    >>> StarTracker(1e-4)
    StarTracker(sigma=0.0001, boresight_sigma=0.0001)
    """

    sigma: float
    boresight_sigma: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "sigma", _sigma(self.sigma, "sigma"))
        b = self.sigma if self.boresight_sigma is None else self.boresight_sigma
        object.__setattr__(self, "boresight_sigma", _sigma(b, "boresight_sigma"))

    def __repr__(self) -> str:
        return f"StarTracker(sigma={self.sigma:g}, boresight_sigma={self.boresight_sigma:g})"

    def sample(self, truth: Trajectory, *, rng: object = None) -> AttitudeSamples:
        """Measurements at the times of ``truth``, drawn from ``rng``."""
        t, q, _ = _truth(truth)
        sigma = np.array([self.sigma, self.sigma, float(self.boresight_sigma)])  # type: ignore[arg-type]
        nu = sigma * _rng(rng).standard_normal((t.size, 3))
        qm = _quat.normalize(_quat.mul(q, _quat.from_rotvec(nu)))
        return AttitudeSamples(t.copy(), qm, q.copy(), sigma)


@dataclass(frozen=True, repr=False)
class VectorSamples:
    """Unit-vector measurements (Sun sensor, magnetometer).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s).
    observed : ndarray, shape (n, 3)
        Measured unit directions in body axes.
    reference : ndarray, shape (n, 3)
        The unit directions ``r`` in inertial axes (known to the filter).
    true : ndarray, shape (n, 3)
        The true body directions ``A r``.
    sigma : float
        Standard deviation of the noise per perpendicular axis (rad).

    Notes
    -----
    **Convention:** ``b = A r`` with ``A = C_nb^T``; docs/theory.md §10.4.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, VectorSensor
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory([0.0])
    >>> VectorSensor([2.0, 0.0, 0.0], 0.0).sample(truth, rng=0).observed
    array([[1., 0., 0.]])
    """

    t: FloatArray
    observed: FloatArray
    reference: FloatArray
    true: FloatArray
    sigma: float

    def __post_init__(self) -> None:
        _readonly(t=self.t, observed=self.observed, reference=self.reference, true=self.true)

    def __repr__(self) -> str:
        return f"VectorSamples({self.t.size} samples, sigma={self.sigma:g} rad)"


@dataclass(frozen=True, repr=False)
class VectorSensor:
    """A direction sensor: ``b = normalize(A r + sigma (E1 n1 + E2 n2))``.

    The noise is Gaussian in the plane perpendicular to the true ``A r`` (unit basis
    ``E1, E2``), ``sigma`` per axis, then renormalised (Shuster's QUEST measurement
    model; docs/theory.md §10.4).

    Parameters
    ----------
    reference : array_like, shape (3,), or callable
        The inertial direction ``r`` (normalised), or ``t -> r(t)`` returning
        ``(n, 3)`` for times ``(n,)`` (e.g. the :func:`dipole_field` along an orbit).
    sigma : float
        Noise per perpendicular axis (rad), >= 0.

    Notes
    -----
    **Convention:** ``A = C_nb^T`` maps inertial to body components.

    Examples
    --------
    >>> from poinsot.dynamics import VectorSensor
    >>> VectorSensor([0.0, 0.0, 3.0], 1e-3)
    VectorSensor(reference=[0.0, 0.0, 1.0], sigma=0.001)
    """

    reference: Any
    sigma: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "sigma", _sigma(self.sigma, "sigma"))
        if not callable(self.reference):
            r = as_float_array(self.reference, "reference")
            n = float(np.linalg.norm(r)) if r.shape == (3,) else 0.0
            if r.shape != (3,) or n == 0.0:
                raise InvalidInputError(
                    f"Expected `reference` to be a non-zero vector of shape (3,) or a "
                    f"callable, got {r.tolist()}."
                )
            r = r / n
            r.setflags(write=False)
            object.__setattr__(self, "reference", r)

    def __repr__(self) -> str:
        r = "<callable>" if callable(self.reference) else self.reference.tolist()
        return f"VectorSensor(reference={r}, sigma={self.sigma:g})"

    def directions(self, t: ArrayLike) -> FloatArray:
        """The unit inertial directions ``r(t)`` (n, 3) at times ``t`` (n,)."""
        t = np.asarray(t, dtype=np.float64)
        if callable(self.reference):
            r = as_float_array(self.reference(t), "reference(t)")
            if r.shape != t.shape + (3,):
                raise InvalidInputError(
                    f"Expected `reference(t)` to have shape {t.shape + (3,)}, got {r.shape}."
                )
        else:
            r = np.broadcast_to(self.reference, t.shape + (3,))
        n = np.linalg.norm(r, axis=-1, keepdims=True)
        if np.any(n == 0.0):
            raise InvalidInputError("Expected `reference(t)` to be non-zero at every time.")
        return r / n

    def sample(self, truth: Trajectory, *, rng: object = None) -> VectorSamples:
        """Measurements at the times of ``truth``, drawn from ``rng``."""
        t, q, _ = _truth(truth)
        r = self.directions(t)
        b = _quat.to_body(q, r)
        noise = self.sigma * _rng(rng).standard_normal((t.size, 2))
        m = b.copy()
        for k in range(t.size):
            m[k] += noise[k] @ _perpendicular_basis(b[k])
        m /= np.linalg.norm(m, axis=-1, keepdims=True)
        return VectorSamples(t.copy(), m, r, b, self.sigma)


# ----------------------------------------------------------------------------- MEKF
def _transition(w: FloatArray, dt: float) -> FloatArray:
    """Crassidis & Junkins' discrete ``Phi`` (6 x 6) for the estimated rate ``w``."""
    u = w * dt
    th = float(np.linalg.norm(u))
    if th < _SERIES_THETA:
        t2 = th * th
        a, c, d = 1.0 - t2 / 6.0, 0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0
    else:
        a, c, d = math.sin(th) / th, (1.0 - math.cos(th)) / th**2, (th - math.sin(th)) / th**3
    ux = hat(u)
    ux2 = ux @ ux
    phi = np.eye(6)
    phi[:3, :3] = _EYE3 - a * ux + c * ux2
    phi[:3, 3:] = dt * (c * ux - _EYE3 - d * ux2)
    return phi


def _process_noise(arw: float, rrw: float, dt: float) -> FloatArray:
    """Crassidis & Junkins' discrete ``Q`` (6 x 6) over ``dt``."""
    q = np.zeros((6, 6))
    v, u = arw * arw, rrw * rrw
    q[:3, :3] = (v * dt + u * dt**3 / 3.0) * _EYE3
    q[:3, 3:] = q[3:, :3] = -0.5 * u * dt**2 * _EYE3
    q[3:, 3:] = u * dt * _EYE3
    return q


class MEKF:
    """The multiplicative extended Kalman filter for attitude and gyro bias.

    State: the attitude ``L`` (scalar-first, body -> inertial) and the gyro bias
    ``b`` (rad/s); error state ``x = (dtheta, db)`` with ``L_true = L o exp(dtheta/2)``
    (``dtheta`` in body axes, rad) and ``b_true = b + db``, covariance ``P`` (6 x 6).
    Lefferts, Markley & Shuster (1982); Crassidis & Junkins, Optimal Estimation of
    Dynamic Systems, §7.2 (docs/theory.md §10.4):

    - propagation over ``dt`` with the estimated rate ``w = w_m - b`` held constant:
      ``L <- L o exp(w dt / 2)`` (exact for that rate), ``P <- Phi P Phi^T + Q`` with
      ``Phi11 = I - sin(f)/f [u x] + (1 - cos f)/f^2 [u x]^2``,
      ``Phi12 = dt ((1 - cos f)/f^2 [u x] - I - (f - sin f)/f^3 [u x]^2)``,
      ``u = w dt``, ``f = |u|``, and ``Q11 = (sigma_v^2 dt + sigma_u^2 dt^3/3) I``,
      ``Q12 = -sigma_u^2 dt^2/2 I``, ``Q22 = sigma_u^2 dt I``;
    - a vector update (``b_m``, ``r``): predicted ``h = A r``, innovation
      ``y = E^T (b_m - h)`` in the plane perpendicular to ``h`` (2 dof),
      ``H = E^T [[h x], 0]``, ``R = sigma^2 I_2``;
    - a star-tracker update: ``y = log(L~ o L_m)`` (rad), ``H = [I, 0]``,
      ``R = diag(sigma^2)`` (3 dof);
    - ``K = P H^T S^-1``, ``S = H P H^T + R``, ``x = K y``, Joseph's form
      ``P <- (I - K H) P (I - K H)^T + K R K^T``, then the reset
      ``L <- normalize(L o exp(dtheta/2))``, ``b <- b + db``, ``x <- 0``.

    Parameters
    ----------
    rotation0 : Rotation or array_like, shape (4,)
        Initial attitude estimate.
    covariance0 : array_like, shape (6, 6) or (6,)
        Initial error covariance (rad^2, rad^2/s^2), full or its diagonal.
    bias0 : array_like, shape (3,)
        Initial bias estimate (rad/s).
    arw, rrw : float
        The gyro's ``sigma_v`` (rad/s^0.5) and ``sigma_u`` (rad/s^1.5).

    Notes
    -----
    **Convention:** scalar-first Hamilton quaternions body -> inertial; errors in body
    axes; ``b = A r``, ``A = C_nb^T``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import MEKF
    >>> f = MEKF([1.0, 0.0, 0.0, 0.0], np.full(6, 1e-4), arw=1e-4, rrw=1e-6)
    >>> f.propagate([0.0, 0.0, np.pi], 1.0)
    >>> f.quat.round(12) + 0.0
    array([0., 0., 0., 1.])
    >>> y, s = f.update_vector([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1e-3)
    >>> y.round(12) + 0.0
    array([0., 0.])
    """

    def __init__(
        self,
        rotation0: Any,
        covariance0: ArrayLike,
        *,
        bias0: ArrayLike = (0.0, 0.0, 0.0),
        arw: float,
        rrw: float,
    ) -> None:
        q = as_rotation_quat(rotation0, "rotation0")
        if q.shape != (4,):
            raise InvalidInputError(f"Expected `rotation0` to be one attitude, got {q.shape}.")
        p = as_float_array(covariance0, "covariance0")
        if p.shape == (6,):
            p = np.diag(p)
        if p.shape != (6, 6):
            raise InvalidInputError(
                f"Expected `covariance0` to have shape (6, 6) or (6,), got {p.shape}."
            )
        if not np.allclose(p, p.T) or np.any(np.linalg.eigvalsh(0.5 * (p + p.T)) < 0.0):
            raise InvalidInputError("Expected `covariance0` to be symmetric positive semidefinite.")
        b = as_float_array(bias0, "bias0")
        if b.shape != (3,):
            raise InvalidInputError(f"Expected `bias0` to have shape (3,), got {b.shape}.")
        self.quat: FloatArray = q.copy()
        self.bias: FloatArray = b.copy()
        self.covariance: FloatArray = 0.5 * (p + p.T)
        self.arw = _sigma(arw, "arw")
        self.rrw = _sigma(rrw, "rrw")

    def __repr__(self) -> str:
        s = np.sqrt(np.diag(self.covariance))
        return f"MEKF(quat={self.quat.round(6).tolist()}, sigma={s.round(9).tolist()})"

    def propagate(self, rate: ArrayLike, dt: float) -> None:
        """Propagate over ``dt`` (s, >= 0) with the measured rate ``rate`` (rad/s)."""
        w = np.asarray(rate, dtype=np.float64) - self.bias
        if dt < 0.0:
            raise InvalidInputError(f"Expected `dt` to be >= 0, got {dt!r}.")
        if dt == 0.0:
            return
        self.quat = _quat.normalize(_quat.mul(self.quat, _quat.from_rotvec(w * dt)))
        phi = _transition(w, dt)
        p = phi @ self.covariance @ phi.T + _process_noise(self.arw, self.rrw, dt)
        self.covariance = 0.5 * (p + p.T)

    def _update(self, y: FloatArray, h: FloatArray, r: FloatArray) -> FloatArray:
        p = self.covariance
        s = h @ p @ h.T + r
        k = np.linalg.solve(s, h @ p).T  # P H^T S^-1 (S, P symmetric)
        x = k @ y
        ikh = _EYE6 - k @ h
        p = ikh @ p @ ikh.T + k @ r @ k.T
        self.covariance = 0.5 * (p + p.T)
        self.quat = _quat.normalize(_quat.mul(self.quat, _quat.from_rotvec(x[:3])))
        self.bias = self.bias + x[3:]
        return s

    def update_vector(
        self, observed: ArrayLike, reference: ArrayLike, sigma: float
    ) -> tuple[FloatArray, FloatArray]:
        """Update with one unit vector ``observed`` (body) of ``reference`` (inertial),
        noise ``sigma`` (rad); returns the innovation (2,) and its covariance (2, 2)."""
        b = np.asarray(observed, dtype=np.float64)
        r = np.asarray(reference, dtype=np.float64)
        hv = _quat.to_body(self.quat, r / np.linalg.norm(r))
        e = _perpendicular_basis(hv)
        y = e @ (b / np.linalg.norm(b) - hv)
        h = np.zeros((2, 6))
        h[:, :3] = e @ hat(hv)
        s = self._update(y, h, sigma * sigma * np.eye(2))
        return y, s

    def update_attitude(self, quat: ArrayLike, sigma: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Update with a measured attitude ``quat`` (4,), noise ``sigma`` (3,) about the
        body axes (rad); returns the innovation (3,) and its covariance (3, 3)."""
        qm = np.asarray(quat, dtype=np.float64)
        d = _quat.mul(_quat.conj(self.quat), qm)
        y = rotvec_from_quat(-d if d[0] < 0.0 else d)  # the short way: L_m and -L_m alike
        h = np.zeros((3, 6))
        h[:, :3] = _EYE3
        s = self._update(y, h, np.diag(np.asarray(sigma, dtype=np.float64) ** 2))
        return y, s


@dataclass(frozen=True, repr=False)
class EstimationResult:
    """What :func:`run_mekf` estimated, at the gyro times, with its innovations.

    Attributes
    ----------
    t : ndarray, shape (n,)
        The gyro sample times (s).
    quat : ndarray, shape (n, 4)
        Attitude estimates (scalar-first, body -> inertial), after the updates at
        ``t_k``.
    bias : ndarray, shape (n, 3)
        Gyro-bias estimates (rad/s).
    covariance : ndarray, shape (n, 6, 6)
        Error covariance of ``(dtheta, db)`` (rad^2, rad^2/s, rad^2/s^2).
    update_t : ndarray, shape (m,)
        Times of the ``m`` scalar-or-vector updates (s), in processing order.
    sensor : ndarray of int, shape (m,)
        Index in ``measurements`` of the sensor of each update.
    innovation : ndarray, shape (m, 3)
        Innovations ``y`` (rad); a vector update fills the first two entries (the rest
        NaN).
    innovation_covariance : ndarray, shape (m, 3, 3)
        ``S = H P H^T + R`` (rad^2), NaN-padded like ``innovation``.
    dof : ndarray of int, shape (m,)
        Dimension of each innovation (2 for a vector, 3 for an attitude).
    diverged : bool
        True when the NIS exceeded ``gate`` for ``consecutive`` updates in a row.
    message : str
        Why it diverged (times, NIS and the gate), or ``""``.
    gate : float
        The probability of the chi-square gate (e.g. 0.999).
    consecutive : int
        The number of consecutive updates that declare divergence.

    Notes
    -----
    **Convention:** errors in body axes, ``L_true = L o exp(dtheta/2)``;
    docs/theory.md §10.4. Frozen; arrays read-only.

    Examples
    --------
    See :func:`run_mekf`.
    """

    t: FloatArray
    quat: FloatArray
    bias: FloatArray
    covariance: FloatArray
    update_t: FloatArray
    sensor: np.ndarray
    innovation: FloatArray
    innovation_covariance: FloatArray
    dof: np.ndarray
    diverged: bool
    message: str
    gate: float
    consecutive: int
    info: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        _readonly(**{f: getattr(self, f) for f in self.__dataclass_fields__})

    @property
    def sigma(self) -> FloatArray:
        """Standard deviations ``sqrt(diag P)`` (n, 6): rad, then rad/s."""
        return np.sqrt(np.einsum("nii->ni", self.covariance))

    def __repr__(self) -> str:
        state = f"diverged: {self.message}" if self.diverged else "converged"
        return f"EstimationResult({self.t.size} samples, {self.update_t.size} updates, {state})"


def _as_gyro_samples(x: object) -> GyroSamples:
    if not isinstance(x, GyroSamples):
        raise InvalidTypeError(
            f"Expected `gyro_data` to be GyroSamples (Gyro.sample), got {type(x).__name__}."
        )
    return x


def run_mekf(
    gyro_data: GyroSamples,
    measurements: Sequence[AttitudeSamples | VectorSamples],
    rotation0: Any,
    covariance0: ArrayLike,
    *,
    bias0: ArrayLike = (0.0, 0.0, 0.0),
    arw: float | None = None,
    rrw: float | None = None,
    gate: float = 0.999,
    consecutive: int = 10,
) -> EstimationResult:
    """Estimate attitude and gyro bias with the :class:`MEKF` (docs/theory.md §10.4).

    The filter starts at the first gyro time with ``rotation0``, ``bias0`` and
    ``covariance0``; between events it propagates with a constant measured rate,
    ``L <- L o exp((w_m - b) dt / 2)`` (exact for that rate): over ``(t_{k-1}, t_k]``
    the sample at ``t_k`` for an ``"integrating"`` gyro (its mean over the interval),
    the sample at ``t_{k-1}`` for a ``"rate"`` gyro (zero-order hold); each
    measurement is applied at its own time, sequentially (one direction or one
    attitude at a time, each followed by the multiplicative reset). Measurements at a
    gyro time are applied after the propagation to that time.

    Divergence is reported, not silent: the normalised innovation squared
    ``NIS = y^T S^-1 y`` of every update is compared with the chi-square quantile
    ``chi2.ppf(gate, dof)`` (13.8 for 2 dof, 16.3 for 3 dof at ``gate = 0.999``);
    ``consecutive`` updates in a row above it set ``diverged`` and ``message``.

    Parameters
    ----------
    gyro_data : GyroSamples
        The gyro samples (:meth:`Gyro.sample`).
    measurements : sequence of AttitudeSamples or VectorSamples
        The other sensors, any times within the gyro's span.
    rotation0 : Rotation or array_like, shape (4,)
        Initial attitude estimate.
    covariance0 : array_like, shape (6, 6) or (6,)
        Initial error covariance (full or diagonal; rad^2 and rad^2/s^2).
    bias0 : array_like, shape (3,)
        Initial bias estimate (rad/s).
    arw, rrw : float, optional
        The filter's ``sigma_v``, ``sigma_u``; default those of ``gyro_data``.
    gate : float
        Probability of the NIS gate, in (0, 1).
    consecutive : int
        Updates in a row above the gate that declare divergence (>= 1).

    Returns
    -------
    EstimationResult

    Notes
    -----
    **Convention:** scalar-first Hamilton quaternions body -> inertial; errors in body
    axes. Lefferts, Markley & Shuster, J. Guidance 5 (1982) 417; Crassidis & Junkins,
    Optimal Estimation of Dynamic Systems (2nd ed., 2012), §7.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro, VectorSensor, run_mekf
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 0.2, 0.3]).trajectory(
    ...     np.arange(0.0, 20.0, 0.1))
    >>> gyro = Gyro(1e-5, 1e-7, bias0=[1e-3, -1e-3, 5e-4]).sample(truth, rng=0)
    >>> sun = VectorSensor([1.0, 0.0, 0.0], 1e-3).sample(truth, rng=1)
    >>> mag = VectorSensor([0.0, 0.6, 0.8], 1e-3).sample(truth, rng=2)
    >>> res = run_mekf(gyro, [sun, mag], truth.quat[0], np.r_[[1e-4] * 3, [1e-5] * 3])
    >>> bool(res.diverged), bool(np.abs(res.bias[-1] - gyro.bias[-1]).max() < 1e-4)
    (False, True)
    """
    from scipy.stats import chi2

    g = _as_gyro_samples(gyro_data)
    if isinstance(measurements, AttitudeSamples | VectorSamples):
        measurements = [measurements]
    if not isinstance(measurements, Sequence):
        raise InvalidTypeError(
            f"Expected `measurements` to be a sequence of AttitudeSamples or VectorSamples, "
            f"got {type(measurements).__name__}."
        )
    for j, m in enumerate(measurements):
        if not isinstance(m, AttitudeSamples | VectorSamples):
            raise InvalidTypeError(
                f"Expected `measurements[{j}]` to be AttitudeSamples or VectorSamples, "
                f"got {type(m).__name__}."
            )
        if m.t.size and (m.t[0] < g.t[0] or m.t[-1] > g.t[-1]):
            raise InvalidInputError(
                f"Expected the times of `measurements[{j}]` to lie within the gyro's "
                f"[{g.t[0]:g}, {g.t[-1]:g}] s, got [{m.t[0]:g}, {m.t[-1]:g}] s."
            )
    gate = float(as_float_array(gate, "gate"))
    if not 0.0 < gate < 1.0:
        raise InvalidInputError(f"Expected `gate` to be in (0, 1), got {gate!r}.")
    if isinstance(consecutive, bool) or not isinstance(consecutive, int | np.integer):
        raise InvalidTypeError(f"Expected `consecutive` to be an int, got {consecutive!r}.")
    if consecutive < 1:
        raise InvalidInputError(f"Expected `consecutive` to be >= 1, got {consecutive}.")
    f = MEKF(
        rotation0,
        covariance0,
        bias0=bias0,
        arw=g.arw if arw is None else arw,
        rrw=g.rrw if rrw is None else rrw,
    )
    bound = {2: float(chi2.ppf(gate, 2)), 3: float(chi2.ppf(gate, 3))}

    events = sorted(
        (float(m.t[i]), j, i) for j, m in enumerate(measurements) for i in range(m.t.size)
    )
    n, m_total = g.t.size, len(events)
    quat, bias, cov = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, 6, 6))
    inn = np.full((m_total, 3), np.nan)
    inn_cov = np.full((m_total, 3, 3), np.nan)
    dof = np.zeros(m_total, dtype=int)
    upd_t = np.array([e[0] for e in events])
    sensor = np.array([e[1] for e in events], dtype=int)
    run, diverged, message = 0, False, ""
    now, rate, e = float(g.t[0]), g.rate[0], 0
    for k in range(n):
        tk = float(g.t[k])
        if g.kind == "integrating":
            rate = g.rate[k]  # the mean over (t_{k-1}, t_k]
        while e < m_total and events[e][0] <= tk:
            te, j, i = events[e]
            f.propagate(rate, te - now)
            now = te
            ms = measurements[j]
            if isinstance(ms, VectorSamples):
                y, s = f.update_vector(ms.observed[i], ms.reference[i], ms.sigma)
            else:
                y, s = f.update_attitude(ms.quat[i], ms.sigma)
            d = y.size
            inn[e, :d], inn_cov[e, :d, :d], dof[e] = y, s, d
            value = float(y @ np.linalg.solve(s, y))
            run = run + 1 if value > bound[d] else 0
            if run >= consecutive and not diverged:
                diverged = True
                message = (
                    f"NIS above the chi-square {gate:g} gate for {consecutive} consecutive "
                    f"updates, up to t = {te:g} s (last NIS {value:.3g} > {bound[d]:.3g} "
                    f"for {d} dof): the filter is inconsistent with its measurements."
                )
            e += 1
        f.propagate(rate, tk - now)
        now = tk
        quat[k], bias[k], cov[k] = f.quat, f.bias, f.covariance
        rate = g.rate[k]  # "rate": held over [t_k, t_{k+1})
    return EstimationResult(
        g.t.copy(),
        quat,
        bias,
        cov,
        upd_t,
        sensor,
        inn,
        inn_cov,
        dof,
        diverged,
        message,
        gate,
        int(consecutive),
        {"nis_bound": bound},
    )


def attitude_error(estimate_quat: ArrayLike, true_quat: ArrayLike) -> FloatArray:
    """The small-angle attitude error ``dtheta`` (..., 3) in body axes (rad).

    ``dtheta = log(L_true~ o L_est)``, i.e. ``L_est = L_true o exp(dtheta/2)``: the
    rotation vector of the estimate relative to the truth, in body axes; the same for
    ``L`` and ``-L`` (the shortest rotation, ``|dtheta| <= pi``). Arrays broadcast.

    Notes
    -----
    **Convention:** scalar-first quaternions body -> inertial; docs/theory.md §10.4.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import attitude_error
    >>> est = [np.cos(0.005), 0.0, 0.0, np.sin(0.005)]   # 0.01 rad about z
    >>> attitude_error(est, [-1.0, 0.0, 0.0, 0.0]).round(12) + 0.0
    array([0.  , 0.  , 0.01])
    """
    qe = as_rotation_quat(estimate_quat, "estimate_quat")
    qt = as_rotation_quat(true_quat, "true_quat")
    d = _quat.mul(_quat.conj(qt), qe)
    d = np.where(d[..., :1] < 0.0, -d, d)
    return rotvec_from_quat(np.ascontiguousarray(d))


def nees(result: EstimationResult, truth: GyroSamples) -> FloatArray:
    """Normalised estimation error squared ``e^T P^-1 e`` (n,) for the 6 states.

    ``e = (attitude_error(L_est, L_true), b_est - b_true)``; for a consistent filter
    its mean over Monte-Carlo runs is chi-square with 6 dof per run (mean 6).

    Parameters
    ----------
    result : EstimationResult
    truth : GyroSamples
        The gyro samples the filter ran on; they carry the true attitude and bias at
        the same times.

    Notes
    -----
    **Convention:** errors in body axes (rad) and rad/s; docs/theory.md §10.4.

    Examples
    --------
    See ``tests/dynamics/test_estimation.py``; for one sample ``e = 0`` gives 0.

    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro, run_mekf, nees
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory([0.0, 0.1])
    >>> g = Gyro(0.0, 0.0).sample(truth, rng=0)
    >>> float(nees(run_mekf(g, [], truth.quat[0], np.ones(6)), g)[0])
    0.0
    """
    if not isinstance(result, EstimationResult):
        raise InvalidTypeError(
            f"Expected `result` to be an EstimationResult, got {type(result).__name__}."
        )
    g = _as_gyro_samples(truth) if isinstance(truth, GyroSamples) else None
    if g is None:
        raise InvalidTypeError(f"Expected `truth` to be GyroSamples, got {type(truth).__name__}.")
    if g.t.shape != result.t.shape or not np.array_equal(g.t, result.t):
        raise InvalidInputError(
            f"Expected `truth` at the times of `result` ({result.t.size} samples), "
            f"got {g.t.size} samples."
        )
    err = np.concatenate([attitude_error(result.quat, g.quat), result.bias - g.bias], axis=-1)
    return np.einsum("ni,ni->n", err, np.linalg.solve(result.covariance, err[..., None])[..., 0])


def nis(result: EstimationResult) -> FloatArray:
    """Normalised innovation squared ``y^T S^-1 y`` (m,) of every update.

    Chi-square with ``result.dof`` degrees of freedom (2 for a direction, 3 for an
    attitude) for a consistent filter.

    Notes
    -----
    **Convention:** as :func:`run_mekf`; docs/theory.md §10.4.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro, StarTracker, run_mekf, nis
    >>> truth = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0]).trajectory([0.0, 0.1])
    >>> g = Gyro(0.0, 0.0).sample(truth, rng=0)
    >>> st = StarTracker(0.0).sample(truth, rng=0)
    >>> nis(run_mekf(g, [st], truth.quat[0], np.full(6, 1e-6))).round(12) + 0.0
    array([0., 0.])
    """
    if not isinstance(result, EstimationResult):
        raise InvalidTypeError(
            f"Expected `result` to be an EstimationResult, got {type(result).__name__}."
        )
    out = np.empty(result.dof.size)
    for e, d in enumerate(result.dof):
        y = result.innovation[e, :d]
        out[e] = y @ np.linalg.solve(result.innovation_covariance[e, :d, :d], y)
    return out
