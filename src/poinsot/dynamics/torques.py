"""Torque models for Euler's equations, with their potential energy (theory §10).

A :class:`TorqueModel` gives the external torque about the centre of mass or the
fixed point, in **body** axes, as a function of the time, the attitude and the
body angular velocity; where the torque derives from a potential it also gives
the potential energy, so that :func:`poinsot.dynamics.invariants` can report the
total energy ``T + V``. :func:`poinsot.dynamics.simulate` takes any of them.

Models
------
:class:`ConstantBodyTorque`
    ``M_b`` fixed in the body (a thruster). No potential.
:class:`ConstantSpaceTorque`
    ``M_s`` fixed in space, ``M_b = R^T M_s``. No potential (its work depends
    on the path), but ``dK_s/dt = M_s``: ``K_s(t) = K_s(0) + M_s t``.
:class:`GravityTorque`
    Uniform gravity ``g`` along ``-z`` of space acting on a body of mass ``m``
    turning about a fixed point ``O``, with centre of mass at ``c`` (body axes,
    from ``O``). With ``gamma = R^T e_z`` the upward vertical in body axes,
    ``M_b = m g (gamma x c)`` and ``V = m g (R c)_z = m g c . gamma``.
:class:`GyrostaticTorque`
    ``h x w``, the reaction of rotors of constant relative momentum ``h`` (body
    axes) on the body: a gyrostat (theory §10.1). No potential, no work
    (``T = w . J w / 2`` is conserved).
:class:`TorqueSum`
    Several models at once, written ``a + b``.
:class:`OrbitGravityGradientTorque`
    The gravity gradient ``(3 mu / r^3) n_b x J n_b`` along an orbit,
    ``r = orbit.position(t)`` (theory §10.2). No potential (the field turns).
:class:`MagneticTorque`
    ``m_b x B_b`` of a constant body dipole in a field ``B(t, r)`` along an orbit,
    by default the Earth's tilted dipole (theory §10.2). No potential.
:class:`CallableTorque`
    Any function ``function(t, quat, omega) -> (..., 3)``, in body or space axes.

:func:`as_torque` turns what ``simulate(torque=...)`` accepts (``None``, a
constant body vector, a callable or a model) into a model.

**Convention:** attitude as scalar-first unit quaternions ``(..., 4)`` mapping
body to space components (``v_s = R v_b``); ``omega`` in body axes (rad/s);
torques in N m, energies in J; parameters broadcast with the state's batch
shape.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._quat import gravity_potential
from .._quat import to_body as _to_body
from .._quat import up_body as _up_body
from .._validate import as_choice, as_positive, as_vec3, batch_shape
from .._vec import cross, diagonal3
from ..errors import InvalidInputError, InvalidTypeError
from ..mass.tensor import as_inertia
from ..rotations.rotation import Rotation
from .orbit import dipole_field

__all__ = [
    "TorqueModel",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "GravityTorque",
    "GyrostaticTorque",
    "GravityGradientTorque",
    "OrbitGravityGradientTorque",
    "MagneticTorque",
    "CallableTorque",
    "TorqueSum",
    "as_torque",
    "STANDARD_GRAVITY",
]

#: Standard acceleration of gravity (m/s^2).
STANDARD_GRAVITY = 9.80665


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64)
    a.setflags(write=False)
    return a


class TorqueModel:
    """Base class of torque models: override :meth:`body_torque` (and :meth:`potential`).

    Subclasses are frozen dataclasses (hashable by identity, picklable when
    their parameters are).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import TorqueModel
    >>> class Damping(TorqueModel):
    ...     def body_torque(self, t, quat, omega):
    ...         return -0.1 * np.asarray(omega)
    >>> Damping().body_torque(0.0, [1.0, 0, 0, 0], [0.0, 0.0, 2.0])
    array([-0. , -0. , -0.2])
    """

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """Torque in body axes (N m), shape ``(..., 3)``.

        ``t`` the time (s), ``quat`` (..., 4) the attitude (scalar-first, body ->
        space), ``omega`` (..., 3) the body angular velocity (rad/s).
        """
        raise NotImplementedError

    def potential(self, quat: np.ndarray) -> np.ndarray | None:
        """Potential energy ``V`` (J), shape ``(...)``, or ``None`` if the torque has none."""
        return None

    @property
    def conservative(self) -> bool:
        """Whether the torque derives from a potential of the attitude."""
        return type(self).potential is not TorqueModel.potential

    def __add__(self, other: object) -> TorqueSum:
        """``a + b``: the :class:`TorqueSum` of two models (the torques add)."""
        if not isinstance(other, TorqueModel):
            return NotImplemented
        parts: list[TorqueModel] = []
        for m in (self, other):
            parts.extend(m.parts if isinstance(m, TorqueSum) else (m,))
        return TorqueSum(tuple(parts))


@dataclass(frozen=True, eq=False)
class ConstantBodyTorque(TorqueModel):
    """A torque fixed in the body, ``M_b`` (N m, body axes).

    Parameters
    ----------
    torque : array_like, shape (..., 3)
        ``M_b`` in body axes (N m); a leading shape gives one per body of a batch.

    Examples
    --------
    >>> from poinsot.dynamics import ConstantBodyTorque
    >>> ConstantBodyTorque([0.0, 0.0, 2.0]).body_torque(0.0, [1.0, 0, 0, 0], [0.0, 0, 0])
    array([0., 0., 2.])
    """

    torque: Any

    def __post_init__(self) -> None:
        object.__setattr__(self, "torque", _readonly(as_vec3(self.torque, "torque")))

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        shape = batch_shape(torque=(self.torque, 1), quat=(np.shape(quat), 1))
        return np.broadcast_to(self.torque, shape + (3,))


@dataclass(frozen=True, eq=False)
class ConstantSpaceTorque(TorqueModel):
    """A torque fixed in space, ``M_s`` (N m, space axes): ``M_b = R^T M_s``.

    It has no potential (the work ``int M_s . w_s dt`` depends on the path), but
    the space angular momentum grows linearly, ``K_s(t) = K_s(0) + M_s t``
    (theory §9).

    Parameters
    ----------
    torque : array_like, shape (..., 3)
        ``M_s`` in space axes (N m).

    Examples
    --------
    >>> from poinsot.dynamics import ConstantSpaceTorque
    >>> quarter_z = [2 ** -0.5, 0.0, 0.0, 2 ** -0.5]   # body x -> space y
    >>> ConstantSpaceTorque([0.0, 1.0, 0.0]).body_torque(0.0, quarter_z, [0.0, 0, 0]).round(12)
    array([1., 0., 0.])
    """

    torque: Any

    def __post_init__(self) -> None:
        object.__setattr__(self, "torque", _readonly(as_vec3(self.torque, "torque")))

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        return _to_body(np.asarray(quat, dtype=float), self.torque)


@dataclass(frozen=True, eq=False)
class GravityTorque(TorqueModel):
    """Uniform gravity on a body turning about a fixed point ``O`` (theory §10).

    Gravity ``g`` points along ``-z`` of space. With ``gamma = R^T e_z`` the
    upward vertical in body axes and ``c`` the centre of mass from ``O`` in body
    axes, the torque about ``O`` is

    ``M_b = c x (R^T (-m g e_z)) = m g (gamma x c)``,

    and the potential energy ``V = m g (R c)_z = m g c . gamma`` (zero when the
    centre of mass is level with ``O``). For a symmetric top with ``c = l e_3``
    tilted by the nutation angle ``theta``, ``|M| = m g l sin(theta)`` and
    ``V = m g l cos(theta)``. Use the inertia about ``O`` (not about the centre
    of mass) in the equations of motion.

    Parameters
    ----------
    mass : array_like, shape (...)
        Mass ``m`` (kg), > 0.
    center_of_mass : array_like, shape (..., 3)
        ``c``, the centre of mass relative to the fixed point, in body axes (m).
    g : float, optional
        Acceleration of gravity (m/s^2), >= 0; default ``9.80665``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.dynamics import GravityTorque
    >>> top = GravityTorque(2.0, [0.0, 0.0, 0.5], g=10.0)
    >>> q = Rotation.from_euler("x", 30, degrees=True).as_quat()   # tilted by 30 deg
    >>> m = top.body_torque(0.0, q, np.zeros(3))
    >>> round(float(np.linalg.norm(m)), 12)   # m g l sin(theta) = 2 * 10 * 0.5 * 0.5
    5.0
    >>> round(float(top.potential(q)), 12)    # m g l cos(theta) = 10 * cos(30 deg)
    8.660254037844
    """

    mass: Any
    center_of_mass: Any
    g: float = STANDARD_GRAVITY

    def __post_init__(self) -> None:
        m = _readonly(as_positive(self.mass, "mass"))
        c = _readonly(as_vec3(self.center_of_mass, "center_of_mass"))
        g = as_positive(self.g, "g", strict=False)
        if g.ndim != 0:
            raise InvalidInputError(f"Expected `g` to be a scalar (m/s^2), got shape {g.shape}.")
        batch_shape(mass=(m, 0), center_of_mass=(c, 1))
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "center_of_mass", c)
        object.__setattr__(self, "g", float(g))

    @property
    def moment(self) -> np.ndarray:
        """``m g c`` (N m), the vector whose cross product with ``gamma`` is the torque."""
        return (self.mass * self.g)[..., None] * self.center_of_mass

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        return cross(_up_body(np.asarray(quat, dtype=float)), self.moment)

    def potential(self, quat: np.ndarray) -> np.ndarray:
        return gravity_potential(np.asarray(quat, dtype=float), self.moment)


@dataclass(frozen=True, eq=False)
class GyrostaticTorque(TorqueModel):
    """The reaction of rotors on their body (theory §10.1): of constant relative momentum,
    or driven by constant motor torques.

    A gyrostat is a rigid body carrying rotors that spin relative to it about axes
    fixed in it; with ``h`` their angular momentum relative to the body (body axes,
    constant) and ``J`` the inertia of the whole system with the rotors locked, the
    Euler-Zhukovsky equations ``J w' + w x (J w + h) = M`` (docs/theory.md §10.1) are
    Euler's equations of a rigid body under the extra body torque

    ``M_b = h x w``.

    With ``rate`` (``U = h'``, constant, body axes) the rotors' momentum grows linearly,
    ``h(t) = h + U t`` (``h`` its value at ``t = 0``), and the equations
    ``J w' + w x (J w + h(t)) = M - U`` are Euler's under

    ``M_b = (h + U t) x w - U``.

    That is a body with reaction wheels under constant motor torques ``u_i`` and no
    friction, ``J`` then the inertia with the wheels' axial moments taken out (``J_f``),
    ``h`` their absolute axial momenta and ``U = sum_i u_i a_i``
    (:func:`poinsot.dynamics.simulate_wheels` runs it so).

    So ``simulate(J, rotation0, omega0, t, torque=GyrostaticTorque(h))`` integrates the
    gyrostat (:class:`poinsot.dynamics.FreeGyrostat` is its exact torque-free motion);
    the compiled integrators (``method="dop853"``, ``"rk4"``, ``"midpoint"``) run it
    inside their loops. The torque does no work (``(h x w) . w = 0``): the kinetic
    energy ``T = w . J w / 2`` and the space vector ``K = R (J w + h)`` are conserved
    when it acts alone; it has no potential of the attitude. With ``rate`` the motors
    do work on the body, ``T' = -U . w``, and ``K = R (J w + h + U t)`` is still
    conserved (the motors are internal). Add other models with
    ``+`` (:class:`TorqueSum`, then evaluated from Python).

    Parameters
    ----------
    h : array_like, shape (..., 3)
        The rotors' angular momentum relative to the body, in body axes (kg m^2/s),
        at ``t = 0`` when ``rate`` is given; a leading shape gives one per body of a
        batch.
    rate : array_like, shape (..., 3), optional
        ``U = h'``, the constant rate of the rotors' momentum in body axes (N m): the
        sum of the motor torques along the rotors' axes. Default ``None``: constant
        ``h`` (``M_b = h x w``, bit for bit).

    Raises
    ------
    InvalidInputError
        If ``h`` or ``rate`` is not finite or not of shape (..., 3).

    Notes
    -----
    **Convention:** ``h`` and ``omega`` in body axes (kg m^2/s, rad/s), torque in body
    axes (N m); ``J`` in ``simulate`` is the inertia of the body with the rotors locked.
    Rotors accelerated by motors (``h'`` not zero): :func:`poinsot.dynamics.simulate_wheels`
    or :func:`poinsot.dynamics.gyrostat_rhs` with ``h_rate``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeGyrostat, GyrostaticTorque, simulate
    >>> GyrostaticTorque([0.0, 0.0, 2.0]).body_torque(0.0, [1.0, 0, 0, 0], [1.0, 0.0, 0.0])
    array([0., 2., 0.])
    >>> J, h, w0 = [1.0, 2.0, 3.0], [0.0, 0.5, 0.0], [0.1, 1.0, 0.1]
    >>> t = np.linspace(0.0, 10.0, 11)
    >>> tr = simulate(J, [1.0, 0, 0, 0], w0, t, torque=GyrostaticTorque(h), rtol=1e-12)
    >>> exact = FreeGyrostat(J, h, omega0=w0)
    >>> bool(np.abs(tr.omega - exact.omega(t)).max() < 1e-9)
    True

    Motors spinning the rotors up about z at 0.1 N m: ``M_b = (h + U t) x w - U``.

    >>> GyrostaticTorque([0.0, 0.0, 2.0], rate=[0.0, 0.0, 0.1]).body_torque(
    ...     10.0, [1.0, 0, 0, 0], [1.0, 0.0, 0.0])
    array([ 0. ,  3. , -0.1])
    """

    h: Any
    rate: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "h", _readonly(as_vec3(self.h, "h")))
        if self.rate is not None:
            object.__setattr__(self, "rate", _readonly(as_vec3(self.rate, "rate")))

    def momentum(self, t: float) -> np.ndarray:
        """The rotors' momentum at time ``t``, ``h + U t`` (body axes, kg m^2/s).

        Examples
        --------
        >>> from poinsot.dynamics import GyrostaticTorque
        >>> GyrostaticTorque([0.0, 0.0, 2.0], rate=[0.0, 0.0, 0.1]).momentum(10.0)
        array([0., 0., 3.])
        """
        if self.rate is None:
            return self.h
        return self.h + self.rate * t

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        shape = batch_shape(
            h=(self.h, 1), rate=(np.zeros(3) if self.rate is None else self.rate, 1),
            quat=(np.shape(quat), 1), omega=(np.shape(omega), 1),
        )  # fmt: skip
        w = np.asarray(omega, dtype=float)
        if self.rate is None:
            return np.broadcast_to(cross(self.h, w), shape + (3,))
        return np.broadcast_to(cross(self.h + self.rate * t, w) - self.rate, shape + (3,))


@dataclass(frozen=True, eq=False)
class TorqueSum(TorqueModel):
    """Several torque models acting together: ``M_b = sum_k M_b,k`` (theory §9, §10).

    Written ``a + b + c`` with models ``a, b, c`` (environment torques and a control
    law, say). The potential is the sum of the parts' potentials when every part
    has one, else ``None``.

    Parameters
    ----------
    parts : tuple of TorqueModel
        The models (at least one).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import ConstantBodyTorque, GravityTorque
    >>> both = ConstantBodyTorque([0.0, 0.0, 0.1]) + GravityTorque(2.0, [0.0, 0.0, 0.5])
    >>> q = np.array([np.cos(0.25), np.sin(0.25), 0.0, 0.0])   # tilted 0.5 rad about x
    >>> both.body_torque(0.0, q, np.zeros(3)).round(6)  # m g (gamma x c) + (0, 0, 0.1)
    array([4.701558, 0.      , 0.1     ])
    >>> both.conservative
    False
    """

    parts: tuple[TorqueModel, ...]

    def __post_init__(self) -> None:
        parts = tuple(self.parts) if isinstance(self.parts, list | tuple) else None
        if not parts or not all(isinstance(p, TorqueModel) for p in parts):
            raise InvalidTypeError(
                "Expected `parts` to be a non-empty tuple of TorqueModel, got "
                f"{type(self.parts).__name__}."
            )
        object.__setattr__(self, "parts", parts)

    @property
    def conservative(self) -> bool:
        return all(p.conservative for p in self.parts)

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        total = self.parts[0].body_torque(t, quat, omega)
        for p in self.parts[1:]:
            total = total + p.body_torque(t, quat, omega)
        return total

    def potential(self, quat: np.ndarray) -> np.ndarray | None:
        if not self.conservative:
            return None
        total = np.zeros(())
        for p in self.parts:
            total = total + np.asarray(p.potential(quat))
        return total


@dataclass(frozen=True, eq=False)
class CallableTorque(TorqueModel):
    """A torque given by a Python function of the time, attitude and angular velocity.

    Parameters
    ----------
    function : callable
        ``function(t, attitude, omega) -> array_like (..., 3)`` with ``t`` the
        time (float, s), ``attitude`` the attitude (see ``attitude``), ``omega``
        the body angular velocity ``(..., 3)`` (rad/s). It returns the torque
        (N m) in the axes named by ``frame``, with the batch shape of the state
        or shape ``(3,)``.
    frame : {"body", "space"}, optional
        Axes of the returned torque; a space torque is turned into body axes by
        ``R^T``. Default ``"body"``.
    attitude : {"quat", "rotation"}, optional
        What the function receives: scalar-first quaternions ``(..., 4)``
        (default) or a :class:`poinsot.Rotation` (as ``simulate`` passes to a
        plain callable, see :func:`as_torque`).
    potential_function : callable, optional
        ``potential_function(quat) -> (...)``, the potential energy (J) if the
        torque derives from one; default none.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import CallableTorque
    >>> drag = CallableTorque(lambda t, q, w: -0.5 * w)
    >>> drag.body_torque(0.0, [1.0, 0, 0, 0], np.array([0.0, 0.0, 2.0]))
    array([-0., -0., -1.])
    """

    function: Callable[..., Any]
    frame: str = "body"
    attitude: str = "quat"
    potential_function: Callable[..., Any] | None = None

    def __post_init__(self) -> None:
        if not callable(self.function):
            raise InvalidTypeError(
                f"Expected `function` to be callable, got {type(self.function).__name__}."
            )
        as_choice(self.frame, "frame", ("body", "space"))
        as_choice(self.attitude, "attitude", ("quat", "rotation"))
        if self.potential_function is not None and not callable(self.potential_function):
            raise InvalidTypeError(
                "Expected `potential_function` to be callable or None, got "
                f"{type(self.potential_function).__name__}."
            )

    @property
    def conservative(self) -> bool:
        return self.potential_function is not None

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        quat = np.asarray(quat, dtype=float)
        omega = np.asarray(omega, dtype=float)
        if self.attitude == "rotation":
            att: Rotation | np.ndarray = Rotation.from_quat(quat)
        else:
            att = quat
        out = self.function(t, att, omega)
        try:
            m = np.asarray(out, dtype=float)
        except (TypeError, ValueError):
            raise InvalidTypeError(
                f"Expected `torque` to return an array of shape (..., 3), got {type(out).__name__}."
            ) from None
        batch = np.broadcast_shapes(quat.shape[:-1], omega.shape[:-1])
        if m.shape not in (batch + (3,), (3,)):
            raise InvalidInputError(
                f"Expected `torque` to return shape {batch + (3,)} ({self.frame} axes) "
                f"or (3,), got {m.shape}."
            )
        if self.frame == "space":
            m = _to_body(quat, m)
        return np.broadcast_to(m, batch + (3,))

    def potential(self, quat: np.ndarray) -> np.ndarray | None:
        if self.potential_function is None:
            return None
        return np.asarray(self.potential_function(np.asarray(quat, dtype=float)), dtype=float)


def _gravity_gradient(inertia: np.ndarray, nb: np.ndarray, coefficient: Any) -> np.ndarray:
    """The ONE gravity-gradient formula ``M_b = k n_b x J n_b`` (N m), ``k = 3 mu / R^3``
    (1/s^2, shape (...)), ``n_b`` the unit direction from the field's centre in body
    axes (..., 3), ``J`` (..., 3, 3) about the centre of mass (theory §10, §10.2)."""
    jn = np.einsum("...ij,...j->...i", inertia, nb)
    return np.asarray(coefficient)[..., None] * cross(nb, jn)


@dataclass(frozen=True, eq=False)
class GravityGradientTorque(TorqueModel):
    """Gravity-gradient torque on a body in a central field (theory §10, §9).

    A body at distance ``R`` from the centre of a field of gravitational
    parameter ``mu``, along the unit space direction ``n`` (from the centre to
    the body, fixed here: the orbit is not integrated), feels about its centre
    of mass, to first order in (size / R),

    ``M_b = (3 mu / R^3) n_b x J n_b``,  ``n_b = R^T n``,

    with potential ``V = (3 mu / (2 R^3)) n_b . J n_b`` (up to a constant). ``J``
    is the body's inertia tensor about its centre of mass, in body axes: give
    the same inertia as the one being integrated.

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3)
        Principal moments or tensor about the centre of mass (kg m^2).
    radius : float
        Distance from the field's centre (m), > 0.
    direction : array_like, shape (3,)
        Direction from the field's centre to the body, space axes (normalised).
    mu : float, optional
        Gravitational parameter (m^3/s^2); default the Earth's ``3.986004418e14``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> gg = GravityGradientTorque([1.0, 2.0, 3.0], 7.0e6, [1.0, 0.0, 0.0])
    >>> q = Rotation.from_euler("z", 30, degrees=True).as_quat()
    >>> m = gg.body_torque(0.0, q, np.zeros(3))        # n_b in the x-y plane: M along z
    >>> k = 3 * 3.986004418e14 / 7.0e6**3
    >>> bool(np.isclose(m[2], k * (2.0 - 1.0) * np.sin(np.pi / 6) * np.cos(np.pi / 6) * -1))
    True
    """

    inertia: Any
    radius: Any
    direction: Any
    mu: float = 3.986004418e14

    def __post_init__(self) -> None:
        j, principal = as_inertia(self.inertia, "inertia")
        if principal:
            j = diagonal3(j)
        r = as_positive(self.radius, "radius")
        mu = as_positive(self.mu, "mu")
        n = as_vec3(self.direction, "direction")
        norm = np.linalg.norm(n, axis=-1, keepdims=True)
        if np.any(norm == 0):
            raise InvalidInputError("Expected `direction` to be a non-zero vector.")
        object.__setattr__(self, "inertia", _readonly(j))
        object.__setattr__(self, "radius", _readonly(r))
        object.__setattr__(self, "mu", float(mu))
        object.__setattr__(self, "direction", _readonly(n / norm))

    @property
    def coefficient(self) -> np.ndarray:
        """``3 mu / R^3`` (1/s^2)."""
        return 3.0 * self.mu / self.radius**3

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        nb = _to_body(np.asarray(quat, dtype=float), self.direction)
        return _gravity_gradient(self.inertia, nb, self.coefficient)

    def potential(self, quat: np.ndarray) -> np.ndarray:
        nb = _to_body(np.asarray(quat, dtype=float), self.direction)
        jn = np.einsum("...ij,...j->...i", self.inertia, nb)
        return 0.5 * self.coefficient * np.einsum("...i,...i->...", nb, jn)


def _orbit_position(orbit: Any, t: float) -> np.ndarray:
    r = np.asarray(orbit.position(t), dtype=float)
    if r.shape[-1:] != (3,):
        raise InvalidInputError(
            f"Expected `orbit.position(t)` to return shape (..., 3), got {r.shape}."
        )
    return r


def _check_orbit(orbit: object) -> None:
    if not callable(getattr(orbit, "position", None)):
        raise InvalidTypeError(
            "Expected `orbit` to be a KeplerOrbit or an object with a position(t) method, "
            f"got {type(orbit).__name__}."
        )


@dataclass(frozen=True, eq=False)
class OrbitGravityGradientTorque(TorqueModel):
    """Gravity-gradient torque on a body moving along an orbit (theory §10.2).

    The same formula as :class:`GravityGradientTorque` with the body's position
    taken from the orbit at each time, ``r = orbit.position(t)`` (inertial axes):

    ``M_b = (3 mu / |r|^3) n_b x J n_b``,  ``n_b = R^T r / |r|``.

    The field turns with the orbit, so the torque has no potential of the attitude
    alone (``potential`` is ``None``).

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3)
        Principal moments or tensor about the centre of mass, body axes (kg m^2).
    orbit : KeplerOrbit or object with ``position(t)``
        ``position(t) -> (3,)`` (m, inertial axes) at a float time ``t`` (s).
    mu : float, optional
        Gravitational parameter (m^3/s^2); default ``orbit.mu`` if the orbit has
        one, else the Earth's ``3.986004418e14``.

    Notes
    -----
    **Convention:** attitude body -> inertial; torque in body axes (N m); see
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.dynamics import KeplerOrbit, OrbitGravityGradientTorque
    >>> orbit = KeplerOrbit(7.0e6, 0.0, 0.0, 0.0, 0.0, 0.0)   # at +x at t = 0
    >>> gg = OrbitGravityGradientTorque([1.0, 2.0, 3.0], orbit)
    >>> q = Rotation.from_euler("z", 30, degrees=True).as_quat()
    >>> m = gg.body_torque(0.0, q, np.zeros(3))
    >>> k = 3 * 3.986004418e14 / 7.0e6**3
    >>> bool(np.isclose(m[2], -k * (2.0 - 1.0) * np.sin(np.pi / 6) * np.cos(np.pi / 6)))
    True
    """

    inertia: Any
    orbit: Any
    mu: Any = None

    def __post_init__(self) -> None:
        j, principal = as_inertia(self.inertia, "inertia")
        if principal:
            j = diagonal3(j)
        _check_orbit(self.orbit)
        mu = self.mu if self.mu is not None else getattr(self.orbit, "mu", 3.986004418e14)
        mu = as_positive(mu, "mu")
        if mu.ndim != 0:
            raise InvalidInputError(
                f"Expected `mu` to be a scalar (m^3/s^2), got shape {mu.shape}."
            )
        object.__setattr__(self, "inertia", _readonly(j))
        object.__setattr__(self, "mu", float(mu))

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        r = _orbit_position(self.orbit, t)
        rn = np.linalg.norm(r, axis=-1)
        nb = _to_body(np.asarray(quat, dtype=float), r / rn[..., None])
        return _gravity_gradient(self.inertia, nb, 3.0 * self.mu / rn**3)


@dataclass(frozen=True, eq=False)
class MagneticTorque(TorqueModel):
    """Torque of a magnetic field on a constant body dipole (theory §10.2).

    ``M_b = m_b x B_b``,  ``B_b = R^T B(t, r(t))``, ``r(t) = orbit.position(t)``,

    with ``m_b`` the body's magnetic dipole moment (A m^2, body axes) and ``B`` the
    field (T, inertial axes), by default the Earth's tilted dipole
    :func:`poinsot.dynamics.dipole_field`.

    Parameters
    ----------
    dipole : array_like, shape (..., 3)
        ``m_b`` (A m^2), body axes.
    orbit : KeplerOrbit or object with ``position(t)``
        The body's position (m, inertial axes) at a float time (s).
    field : callable, optional
        ``field(t, r) -> (..., 3)`` in tesla, inertial axes; default ``dipole_field``.

    Notes
    -----
    **Convention:** attitude body -> inertial; torque in body axes (N m); see
    ``docs/theory.md`` §10.2.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import KeplerOrbit, MagneticTorque
    >>> orbit = KeplerOrbit(7.0e6, 0.0, 0.0, 0.0, 0.0, 0.0)
    >>> north = lambda t, r: np.array([0.0, 0.0, 3e-5])       # a uniform field, T
    >>> MagneticTorque([1.0, 0.0, 0.0], orbit, field=north).body_torque(
    ...     0.0, [1.0, 0, 0, 0], np.zeros(3))
    array([ 0.e+00, -3.e-05,  0.e+00])
    """

    dipole: Any
    orbit: Any
    field: Callable[..., Any] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "dipole", _readonly(as_vec3(self.dipole, "dipole")))
        _check_orbit(self.orbit)
        if self.field is None:
            object.__setattr__(self, "field", dipole_field)
        elif not callable(self.field):
            raise InvalidTypeError(
                f"Expected `field` to be callable, got {type(self.field).__name__}."
            )

    def body_torque(self, t: float, quat: np.ndarray, omega: np.ndarray) -> np.ndarray:
        field = self.field if self.field is not None else dipole_field
        r = _orbit_position(self.orbit, t)
        b = np.asarray(field(t, r), dtype=float)
        bb = _to_body(np.asarray(quat, dtype=float), b)
        return cross(self.dipole, bb)


def as_torque(torque: object) -> TorqueModel | None:
    """The torque model for what ``simulate(torque=...)`` accepts.

    Parameters
    ----------
    torque : None, TorqueModel, array_like (..., 3) or callable
        ``None`` (no torque) -> ``None``; a :class:`TorqueModel` -> itself; an
        array -> :class:`ConstantBodyTorque` (body axes); a callable
        ``f(t, rotation, omega)`` -> ``CallableTorque(f, attitude="rotation")``
        (it receives a :class:`poinsot.Rotation`, as ``simulate`` has always
        passed; wrap it in ``CallableTorque(f)`` to receive quaternions).

    Returns
    -------
    TorqueModel or None

    Examples
    --------
    >>> from poinsot.dynamics import as_torque
    >>> as_torque([0.0, 0.0, 1.0])
    ConstantBodyTorque(torque=array([0., 0., 1.]))
    >>> as_torque(None) is None
    True
    """
    if torque is None or isinstance(torque, TorqueModel):
        return torque
    if callable(torque):
        return CallableTorque(torque, attitude="rotation")
    if isinstance(torque, str | bytes | dict):
        raise InvalidTypeError(
            "Expected `torque` to be None, a TorqueModel, a (..., 3) body vector or a "
            f"callable, got {type(torque).__name__}."
        )
    return ConstantBodyTorque(torque)
