"""Velocity and acceleration fields of a rigid body; composite motion (theory §6).

Euler's formula ``V = V0 + w x rho`` and Rivals' formula
``W = W0 + eps x rho + w x (w x rho)`` give the velocity and acceleration of
every point of a rigid body from those of one point (the *pole*), the angular
velocity ``w`` and the angular acceleration ``eps = w'``.

A point moving in a moving frame (composite motion) has
``V = V0 + w x s + V_r`` and
``W = W0 + eps x s + w x (w x s) + 2 w x V_r + W_r``; :func:`point_motion`
returns each of these terms by name, and :class:`FrameMotion` chains any
number of moving frames (:meth:`FrameMotion.compose`, :func:`chain`).

**Convention:** every vector is given in *one* frame (normally the fixed
frame) at the instant considered, in consistent units (m, s, rad). Relative
quantities (``V_r``, ``W_r``, ``w_r``, ``eps_r``) are the derivatives seen by
an observer attached to the moving (transport) frame -- the *local*
derivatives of theory §6 -- but expressed in the same fixed-frame components as
everything else. Every function broadcasts over leading batch dimensions
(points, times, ...).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_vec3, batch_shape
from ..errors import InvalidInputError, InvalidTypeError

__all__ = [
    "velocity_field",
    "acceleration_field",
    "compose_angular",
    "AngularMotion",
    "FrameMotion",
    "CompositeMotion",
    "point_motion",
    "chain",
]


# ---------------------------------------------------------------------------
# Kernels (no validation; arrays of shape (..., 3), broadcasting)
# ---------------------------------------------------------------------------


def _euler(v0: np.ndarray, omega: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """Euler's formula ``V0 + w x rho``."""
    return v0 + np.cross(omega, rho)


def _rivals_terms(
    a0: np.ndarray, omega: np.ndarray, eps: np.ndarray, rho: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The three terms of Rivals' formula: ``W0``, ``eps x rho``, ``w x (w x rho)``."""
    rotational = np.cross(eps, rho)
    centripetal = np.cross(omega, np.cross(omega, rho))
    return a0, rotational, centripetal


def _compose_angular(
    omega_e: np.ndarray, eps_e: np.ndarray, omega_r: np.ndarray, eps_r: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``w = w_e + w_r``, ``eps = eps_e + eps_r + w_e x w_r``."""
    return omega_e + omega_r, eps_e + eps_r + np.cross(omega_e, omega_r)


def _broadcast_shape(arrays: dict[str, np.ndarray]) -> tuple[int, ...]:
    """The broadcast shape of named arrays (``poinsot._validate.batch_shape``)."""
    return batch_shape(**{k: (a, 0) for k, a in arrays.items()})


def _vectors(**named: object) -> list[np.ndarray]:
    """Validate named (..., 3) arguments and check that they broadcast together."""
    arrays = {k: as_vec3(v, k) for k, v in named.items()}
    _broadcast_shape(arrays)
    return list(arrays.values())


def _as_list(x: Any, name: str, what: str) -> list[Any]:
    """``list(x)`` for a sequence argument; a non-iterable (or a string) is a type error."""
    if isinstance(x, str | bytes) or not hasattr(x, "__iter__"):
        raise InvalidTypeError(f"Expected `{name}` to be {what}, got {type(x).__name__}.")
    return list(x)


def _scalar(x: ArrayLike, name: str, *, strict: bool = False) -> float:
    """A real scalar that must be >= 0 (> 0 if ``strict``), e.g. a tolerance or a step."""
    a = as_float_array(x, name)
    ok = a.ndim == 0 and (a > 0 if strict else a >= 0)
    if not ok:
        word = "positive" if strict else "non-negative"
        raise InvalidInputError(f"Expected `{name}` to be a {word} number, got {x!r}.")
    return float(a)


def _rho_args(**named: ArrayLike | None) -> list[np.ndarray]:
    """Validate the vectors and the pole; return them with ``rho = point - pole`` last."""
    pole = named.pop("pole")
    if pole is not None:
        named["pole"] = pole
    arrays = _vectors(**named)
    if pole is None:
        return arrays
    *rest, point, pole = arrays
    return [*rest, point - pole]


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64)  # own copy
    a.setflags(write=False)
    return a


# ---------------------------------------------------------------------------
# Rigid-body fields
# ---------------------------------------------------------------------------


def velocity_field(
    v0: ArrayLike, omega: ArrayLike, point: ArrayLike, *, pole: ArrayLike | None = None
) -> FloatArray:
    """Velocity of the points ``point`` of a rigid body (Euler's formula, theory §6).

    Parameters
    ----------
    v0 : array_like, shape (..., 3)
        Velocity of the pole.
    omega : array_like, shape (..., 3)
        Angular velocity of the body.
    point : array_like, shape (..., 3)
        Positions of the points.
    pole : array_like, shape (..., 3), optional
        Position of the pole (the reference point whose velocity is ``v0``);
        ``rho = point - pole`` is the offset. Default (None): the coordinate
        origin, so that ``point`` *is* ``rho``.

    Returns
    -------
    ndarray, shape (..., 3)
        ``V = V0 + w x rho`` (all arguments broadcast together).

    Notes
    -----
    **Convention:** all vectors in one frame (normally the fixed frame) at the
    instant; ``omega`` in rad/s.

    Examples
    --------
    A wheel of radius 1 rolling without slipping along x at 1 m/s: the
    contact point is at rest and the top moves at 2 m/s.

    >>> from poinsot.kinematics import velocity_field
    >>> velocity_field([1, 0, 0], [0, 0, -1], [[0, -1, 0], [0, 1, 0]]) + 0.0
    array([[0., 0., 0.],
           [2., 0., 0.]])
    """
    v0, omega, rho = _rho_args(v0=v0, omega=omega, point=point, pole=pole)
    return _euler(v0, omega, rho)


def acceleration_field(
    a0: ArrayLike,
    omega: ArrayLike,
    eps: ArrayLike,
    point: ArrayLike,
    *,
    pole: ArrayLike | None = None,
) -> FloatArray:
    """Acceleration of the points ``point`` of a rigid body (Rivals' formula, theory §6).

    Parameters
    ----------
    a0 : array_like, shape (..., 3)
        Acceleration of the pole.
    omega : array_like, shape (..., 3)
        Angular velocity of the body.
    eps : array_like, shape (..., 3)
        Angular acceleration ``eps = dw/dt``.
    point : array_like, shape (..., 3)
        Positions of the points.
    pole : array_like, shape (..., 3), optional
        Position of the pole; ``rho = point - pole`` (default None: the coordinate
        origin).

    Returns
    -------
    ndarray, shape (..., 3)
        ``W = W0 + eps x rho + w x (w x rho)``.

    Notes
    -----
    **Convention:** all vectors in one frame (normally the fixed frame) at the
    instant; ``eps`` is the derivative of ``omega`` in that frame (for the
    angular velocity the fixed-frame and body-frame derivatives coincide).

    Examples
    --------
    A point at distance 2 on a disc spinning at 3 rad/s: centripetal
    acceleration ``2 * 3**2 = 18`` towards the centre.

    >>> from poinsot.kinematics import acceleration_field
    >>> acceleration_field([0, 0, 0], [0, 0, 3], [0, 0, 0], [2, 0, 0]) + 0.0
    array([-18., 0., 0.])
    """
    a0, omega, eps, rho = _rho_args(a0=a0, omega=omega, eps=eps, point=point, pole=pole)
    w0, rot, cen = _rivals_terms(a0, omega, eps, rho)
    return w0 + rot + cen


# ---------------------------------------------------------------------------
# Composite motion
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class AngularMotion:
    """Angular velocity and angular acceleration of a composite rotation.

    Attributes
    ----------
    omega : ndarray, shape (..., 3)
        Absolute angular velocity ``w = w_e + w_r``.
    eps : ndarray, shape (..., 3)
        Absolute angular acceleration ``eps = eps_e + eps_r + w_e x w_r``.

    Unpacks as ``omega, eps = compose_angular(...)``.
    """

    omega: np.ndarray
    eps: np.ndarray

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.omega, self.eps))


def compose_angular(
    omega_e: ArrayLike, eps_e: ArrayLike, omega_r: ArrayLike, eps_r: ArrayLike
) -> AngularMotion:
    """Compose a transport and a relative rotation (theory §6).

    Parameters
    ----------
    omega_e, eps_e : array_like, shape (..., 3)
        Angular velocity and acceleration of the moving (transport) frame.
    omega_r, eps_r : array_like, shape (..., 3)
        Angular velocity of the body relative to the moving frame, and its
        *local* derivative (the rate of change seen in the moving frame).

    Returns
    -------
    AngularMotion
        ``w = w_e + w_r`` and ``eps = eps_e + eps_r + w_e x w_r``.

    Notes
    -----
    **Convention:** all vectors in fixed-frame components at the instant. The
    term ``w_e x w_r`` comes from the local-derivative rule ``da/dt = d~a/dt +
    w_e x a`` applied to ``w_r``.

    Examples
    --------
    A disc spinning at 10 rad/s about its x axis, carried round the vertical
    z axis at 2 rad/s (a gyroscope's precession):

    >>> from poinsot.kinematics import compose_angular
    >>> w, eps = compose_angular([0, 0, 2], [0, 0, 0], [10, 0, 0], [0, 0, 0])
    >>> w + 0.0, eps + 0.0
    (array([10., 0., 2.]), array([ 0., 20., 0.]))
    """
    we, ee, wr, er = _vectors(omega_e=omega_e, eps_e=eps_e, omega_r=omega_r, eps_r=eps_r)
    omega, eps = _compose_angular(we, ee, wr, er)
    return AngularMotion(omega, eps)


@dataclass(frozen=True, eq=False, init=False)
class FrameMotion:
    """The motion of a moving frame at one instant (or a batch of instants).

    Attributes
    ----------
    origin_velocity : ndarray, shape (..., 3)
        Velocity ``V0`` of the frame's origin.
    origin_acceleration : ndarray, shape (..., 3)
        Acceleration ``W0`` of the frame's origin.
    omega : ndarray, shape (..., 3)
        Angular velocity ``w`` of the frame.
    eps : ndarray, shape (..., 3)
        Angular acceleration ``eps = w'``.

    Every attribute defaults to zero and accepts any array_like of shape
    ``(..., 3)``; the shapes must broadcast together, and are stored broadcast
    to their common shape (read-only arrays).

    Notes
    -----
    **Convention:** all vectors in fixed-frame components at the instant
    (m, m/s, m/s^2, rad/s, rad/s^2). A :class:`FrameMotion` used as the
    *inner* argument of :meth:`compose` describes motion *relative to* the
    outer frame (local derivatives), still in fixed-frame components.

    Examples
    --------
    A turntable spinning at 2 rad/s; a point at 0.5 m from the axis:

    >>> from poinsot.kinematics import FrameMotion
    >>> table = FrameMotion(omega=[0, 0, 2])
    >>> table.velocity_at([0.5, 0, 0]) + 0.0
    array([0., 1., 0.])
    >>> table.acceleration_at([0.5, 0, 0]) + 0.0
    array([-2., 0., 0.])
    """

    origin_velocity: np.ndarray
    origin_acceleration: np.ndarray
    omega: np.ndarray
    eps: np.ndarray

    # Written out (not generated) so that it takes array_like and stores arrays: the
    # attributes are read-only float arrays whatever was passed.
    def __init__(
        self,
        origin_velocity: ArrayLike = (0.0, 0.0, 0.0),
        origin_acceleration: ArrayLike = (0.0, 0.0, 0.0),
        omega: ArrayLike = (0.0, 0.0, 0.0),
        eps: ArrayLike = (0.0, 0.0, 0.0),
    ) -> None:
        object.__setattr__(self, "origin_velocity", origin_velocity)
        object.__setattr__(self, "origin_acceleration", origin_acceleration)
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "eps", eps)
        self.__post_init__()

    def __post_init__(self) -> None:
        arrays = {f.name: as_vec3(getattr(self, f.name), f.name) for f in fields(self)}
        shape = _broadcast_shape(arrays)
        for name, a in arrays.items():
            object.__setattr__(self, name, _frozen(np.broadcast_to(a, shape)))

    @property
    def shape(self) -> tuple[int, ...]:
        """Batch shape of the attributes (without the trailing 3)."""
        return self.omega.shape[:-1]

    def velocity_at(self, offset: ArrayLike) -> FloatArray:
        """Velocity ``V0 + w x rho`` of the point fixed in the frame at the offset
        ``rho = offset`` from the frame's origin (fixed-frame components)."""
        rho = as_vec3(offset, "offset")
        _broadcast_shape({"offset": rho, "omega": self.omega})
        return _euler(self.origin_velocity, self.omega, rho)

    def acceleration_at(self, offset: ArrayLike) -> FloatArray:
        """Acceleration ``W0 + eps x rho + w x (w x rho)`` of the point fixed in
        the frame at the offset ``rho = offset`` from the frame's origin."""
        rho = as_vec3(offset, "offset")
        _broadcast_shape({"offset": rho, "omega": self.omega})
        w0, rot, cen = _rivals_terms(self.origin_acceleration, self.omega, self.eps, rho)
        return w0 + rot + cen

    def compose(self, inner: FrameMotion, offset: ArrayLike) -> FrameMotion:
        """Absolute motion of a frame that moves relative to this one.

        Parameters
        ----------
        inner : FrameMotion
            Motion of the inner frame *relative to* this frame: velocity and
            acceleration of its origin and its angular velocity/acceleration as
            seen by an observer attached to this frame (local derivatives),
            in fixed-frame components.
        offset : array_like, shape (..., 3)
            Position of the inner frame's origin relative to this frame's
            origin (fixed-frame components).

        Returns
        -------
        FrameMotion
            The inner frame's motion relative to the fixed frame:
            ``V = V0 + w x s + V_r``,
            ``W = W0 + eps x s + w x (w x s) + 2 w x V_r + W_r``,
            ``w = w_e + w_r``, ``eps = eps_e + eps_r + w_e x w_r`` (theory §6).

        Examples
        --------
        A carousel (1 rad/s about z) carrying, 2 m from its axis, a cup that
        spins at 3 rad/s about its own vertical axis:

        >>> from poinsot.kinematics import FrameMotion
        >>> carousel = FrameMotion(omega=[0, 0, 1])
        >>> cup = carousel.compose(FrameMotion(omega=[0, 0, 3]), offset=[2, 0, 0])
        >>> cup.origin_velocity + 0.0, cup.omega + 0.0
        (array([0., 2., 0.]), array([0., 0., 4.]))
        """
        if not isinstance(inner, FrameMotion):
            raise InvalidTypeError(
                f"Expected `inner` to be a FrameMotion, got {type(inner).__name__}."
            )
        offset = as_vec3(offset, "offset")
        _broadcast_shape({"offset": offset, "self": self.omega, "inner": inner.omega})
        m = _point_motion(self, offset, inner.origin_velocity, inner.origin_acceleration)
        omega, eps = _compose_angular(self.omega, self.eps, inner.omega, inner.eps)
        return FrameMotion(m.velocity, m.acceleration, omega, eps)


def chain(motions: Sequence[FrameMotion], offsets: Sequence[ArrayLike]) -> FrameMotion:
    """Absolute motion of the last frame of a chain of moving frames.

    Parameters
    ----------
    motions : sequence of FrameMotion, length m >= 1
        ``motions[0]`` is the motion of frame 1 relative to the fixed frame;
        ``motions[k]`` the motion of frame k+1 relative to frame k (local
        derivatives, fixed-frame components).
    offsets : sequence of array_like, length m - 1
        ``offsets[k]`` is the position of frame k+2's origin relative to frame
        k+1's origin (fixed-frame components).

    Returns
    -------
    FrameMotion
        The last frame's motion relative to the fixed frame (repeated
        :meth:`FrameMotion.compose`).

    Examples
    --------
    >>> from poinsot.kinematics import FrameMotion, chain
    >>> m = chain([FrameMotion(omega=[0, 0, 1]), FrameMotion(omega=[1, 0, 0])], [[0, 0, 0]])
    >>> m.eps + 0.0
    array([0., 1., 0.])
    """
    motions = _as_list(motions, "motions", "a sequence of FrameMotion")
    offsets = _as_list(offsets, "offsets", "a sequence of 3-vectors")
    if not motions:
        raise InvalidInputError("Expected `motions` to hold at least one FrameMotion, got none.")
    if len(offsets) != len(motions) - 1:
        raise InvalidInputError(
            f"Expected `offsets` to have len(motions) - 1 = {len(motions) - 1} entries, "
            f"got {len(offsets)}."
        )
    for k, m in enumerate(motions):
        if not isinstance(m, FrameMotion):
            raise InvalidTypeError(
                f"Expected `motions[{k}]` to be a FrameMotion, got {type(m).__name__}."
            )
    total = motions[0]
    for inner, offset in zip(motions[1:], offsets, strict=True):
        total = total.compose(inner, offset)
    return total


@dataclass(frozen=True, eq=False)
class CompositeMotion:
    """Velocity and acceleration of a point in composite motion, term by term.

    Attributes
    ----------
    velocity : ndarray, shape (..., 3)
        Absolute velocity ``V = V_e + V_r``.
    acceleration : ndarray, shape (..., 3)
        Absolute acceleration ``W = W_e + W_c + W_r``.
    transport_velocity : ndarray, shape (..., 3)
        ``V_e = V0 + w x s`` (velocity of the frame point the particle occupies).
    relative_velocity : ndarray, shape (..., 3)
        ``V_r`` (seen in the moving frame).
    transport_acceleration : ndarray, shape (..., 3)
        ``W_e = W0 + eps x s + w x (w x s)``, the sum of the next three terms.
    origin_acceleration : ndarray, shape (..., 3)
        ``W0``, acceleration of the moving frame's origin.
    rotational_acceleration : ndarray, shape (..., 3)
        ``eps x s`` (also called the tangential or Euler term).
    centripetal_acceleration : ndarray, shape (..., 3)
        ``w x (w x s)`` (axipetal term).
    coriolis_acceleration : ndarray, shape (..., 3)
        ``W_c = 2 w x V_r``.
    relative_acceleration : ndarray, shape (..., 3)
        ``W_r`` (seen in the moving frame).
    """

    velocity: np.ndarray
    acceleration: np.ndarray
    transport_velocity: np.ndarray
    relative_velocity: np.ndarray
    transport_acceleration: np.ndarray
    origin_acceleration: np.ndarray
    rotational_acceleration: np.ndarray
    centripetal_acceleration: np.ndarray
    coriolis_acceleration: np.ndarray
    relative_acceleration: np.ndarray

    def as_dict(self) -> dict[str, np.ndarray]:
        """The terms by name (a new dict)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def _point_motion(
    frame: FrameMotion, s: np.ndarray, v_rel: np.ndarray, a_rel: np.ndarray
) -> CompositeMotion:
    shape = np.broadcast_shapes(s.shape, v_rel.shape, a_rel.shape, frame.omega.shape)
    ve = _euler(frame.origin_velocity, frame.omega, s)
    w0, rot, cen = _rivals_terms(frame.origin_acceleration, frame.omega, frame.eps, s)
    we = w0 + rot + cen
    wc = 2.0 * np.cross(frame.omega, v_rel)

    def full(a: np.ndarray) -> np.ndarray:
        return np.broadcast_to(a, shape).copy()

    return CompositeMotion(
        velocity=full(ve + v_rel),
        acceleration=full(we + wc + a_rel),
        transport_velocity=full(ve),
        relative_velocity=full(v_rel),
        transport_acceleration=full(we),
        origin_acceleration=full(w0),
        rotational_acceleration=full(rot),
        centripetal_acceleration=full(cen),
        coriolis_acceleration=full(wc),
        relative_acceleration=full(a_rel),
    )


def point_motion(
    frame: FrameMotion,
    s: ArrayLike,
    v_rel: ArrayLike = (0.0, 0.0, 0.0),
    a_rel: ArrayLike = (0.0, 0.0, 0.0),
) -> CompositeMotion:
    """Velocity and acceleration of a point moving in a moving frame (theory §6).

    Parameters
    ----------
    frame : FrameMotion
        Motion of the moving (transport) frame; chain several frames with
        :func:`chain` or :meth:`FrameMotion.compose` first.
    s : array_like, shape (..., 3)
        Position of the point relative to the frame's origin.
    v_rel, a_rel : array_like, shape (..., 3), optional
        Velocity and acceleration of the point relative to the frame (as seen
        by an observer attached to it). Default zero (a point fixed in the frame).

    Returns
    -------
    CompositeMotion
        ``V = V0 + w x s + V_r`` and
        ``W = W0 + eps x s + w x (w x s) + 2 w x V_r + W_r``, every term by name.

    Notes
    -----
    **Convention:** all vectors in fixed-frame components at the instant;
    ``v_rel`` and ``a_rel`` are the local (relative) derivatives of ``s``
    expressed in those components.

    Examples
    --------
    A bead sliding outwards at 1 m/s along a rod that turns at 2 rad/s about z,
    when it is 0.5 m from the axis:

    >>> from poinsot.kinematics import FrameMotion, point_motion
    >>> m = point_motion(FrameMotion(omega=[0, 0, 2]), s=[0.5, 0, 0], v_rel=[1, 0, 0])
    >>> m.coriolis_acceleration + 0.0
    array([0., 4., 0.])
    >>> m.centripetal_acceleration + 0.0
    array([-2., 0., 0.])
    >>> m.acceleration + 0.0
    array([-2., 4., 0.])
    """
    if not isinstance(frame, FrameMotion):
        raise InvalidTypeError(f"Expected `frame` to be a FrameMotion, got {type(frame).__name__}.")
    s, v_rel, a_rel = _vectors(s=s, v_rel=v_rel, a_rel=a_rel)
    _broadcast_shape({"s": s, "v_rel": v_rel, "a_rel": a_rel, "frame": frame.omega})
    return _point_motion(frame, s, v_rel, a_rel)
