"""The heavy rigid body about a fixed point: the Euler-Poisson equations (docs/theory.md §10).

A rigid body turns about a fixed point ``O`` in uniform gravity ``g`` along ``-z``
of space. ``J`` is its inertia tensor about ``O`` and ``c`` its centre of mass
from ``O``, both in body axes; ``gamma = R^T e_z`` is the **upward** vertical in
body axes (``R`` maps body to space components). Then (Euler-Poisson)

    J w' + w x J w = m g (gamma x c),        gamma' = gamma x w,

(the gravity torque about ``O`` is ``c x (-m g R^T e_z) = m g gamma x c``, as
:class:`poinsot.dynamics.GravityTorque` computes it) with the integrals

    E = w . J w / 2 + m g c . gamma,   K_z = (J w) . gamma,   |gamma| = 1,

the last two Casimirs of the Lie-Poisson structure. Integrable cases: Euler
(``c = 0``), Lagrange (``A = B``, ``c`` on the axis: :class:`~poinsot.dynamics.LagrangeTop`),
Kovalevskaya (``A = B = 2 C``, ``c`` in the equatorial plane:
:func:`kovalevskaya_integral`).

:meth:`HeavyRigidBody.simulate` integrates by default with the splitting of the
Hamiltonian into the free body (the Lie-Poisson splitting of
:func:`poinsot.dynamics.simulate`, exact for a symmetric body) and the gravity
potential, whose flow is exact: with the attitude frozen, ``gamma`` is constant
and ``K <- K + h m g (gamma x c)``. The kick changes the space momentum by
``h e_z x (R m g c)``, perpendicular to ``e_z``: ``K_z`` and ``|gamma|`` are kept
to round-off and the energy error stays bounded. Strang composition gives order 2,
the triple jump (Yoshida 1990, Suzuki 1990) order 4, Yoshida's 7 stages order 6.

**Convention:** attitude body -> space (scalar-first quaternions), ``omega`` in
body axes (rad/s), ``gamma`` the upward vertical in body axes, SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _quat, integrators
from .._quat import up_body as _up_body
from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_rotation_quat, as_vec3, batch_shape
from .._vec import cross, diagonal3, inverse3
from ..errors import InvalidInputError
from ..mass import RigidBody
from ..mass.tensor import as_inertia
from ..trajectory import Trajectory
from .euler_equations import simulate
from .integrators._common import _rhs
from .invariants import invariants
from .torques import STANDARD_GRAVITY, GravityTorque

if TYPE_CHECKING:
    from ..mass.body import RigidBody
    from ..rotations.rotation import Rotation
    from .invariants import Invariants

__all__ = ["HeavyRigidBody", "kovalevskaya_integral", "HEAVY_METHODS"]

#: Methods of :meth:`HeavyRigidBody.simulate`.
#: The integrators of the heavy body (from :data:`poinsot.integrators.INTEGRATORS`).
HEAVY_METHODS = integrators.names("rigid")


def _upward(q: np.ndarray) -> np.ndarray:
    """``gamma = R^T e_z`` for unit quaternions ``q`` (..., 4) (the torque model's kernel)."""

    return _up_body(q)


class HeavyRigidBody:
    """A rigid body with a fixed point in uniform gravity (docs/theory.md §10).

    Parameters
    ----------
    inertia : array_like, shape (3,) or (3, 3), or RigidBody
        Inertia **about the fixed point** in body axes: principal moments
        ``(A, B, C)`` (body axes principal) or a tensor. A
        :class:`poinsot.mass.RigidBody` is fixed at its reference point ``O``:
        its inertia about the centre of mass is moved to ``O`` by the
        parallel-axis theorem, ``J_O = J_C + m (|c|^2 E - c c^T)`` (theory §8),
        and its mass and centre of mass are used.
    mass : float
        Mass ``m`` (kg), > 0 (optional with a RigidBody; if given, it must agree).
    center_of_mass : array_like, shape (3,)
        ``c``, the centre of mass from the fixed point in body axes (m)
        (optional with a RigidBody; if given, it must agree).
    g : float, optional
        Gravity (m/s^2) along ``-z`` of space; default ``9.80665``.

    Attributes
    ----------
    inertia_tensor : ndarray (3, 3)
    mass, g : float
    center_of_mass : ndarray (3,)
    torque : GravityTorque
        The torque model (``M = m g gamma x c``, ``V = m g c . gamma``).

    Notes
    -----
    Euler-Poisson equations ``J w' + w x J w = m g (gamma x c)``,
    ``gamma' = gamma x w`` with ``gamma = R^T e_z`` the upward vertical in body
    axes. **Convention:** body -> space attitude, body-axes ``omega``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import HeavyRigidBody
    >>> top = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.4], g=10.0)
    >>> tr = top.simulate([1.0, 0.0, 0.0, 0.0], [0.5, 0.0, 20.0], np.linspace(0, 2, 5),
    ...                   max_step=1e-3)
    >>> e = top.energy(tr.rotation, tr.omega)
    >>> bool(np.ptp(e) < 1e-6 * e[0]), bool(np.ptp(top.momentum_z(tr.rotation, tr.omega)) < 1e-12)
    (True, True)
    """

    def __init__(
        self,
        inertia: RigidBody | ArrayLike,
        mass: ArrayLike | None = None,
        center_of_mass: ArrayLike | None = None,
        *,
        g: float = STANDARD_GRAVITY,
    ) -> None:
        if isinstance(inertia, RigidBody):
            body = inertia
            if body.shape != ():
                raise InvalidInputError(
                    f"Expected `inertia` to be one RigidBody, got a batch of shape {body.shape}."
                )
            for name, given, own in (
                ("mass", mass, body.mass),
                ("center_of_mass", center_of_mass, body.center_of_mass),
            ):
                if given is not None and not np.allclose(given, own, rtol=1e-12, atol=0.0):
                    raise InvalidInputError(
                        f"Expected `{name}` to agree with the RigidBody's ({np.asarray(own)}), "
                        f"got {given!r} (leave it out to use the body's)."
                    )
            mass, center_of_mass = body.mass, body.center_of_mass
            inertia = body.inertia_about((0.0, 0.0, 0.0))  # about the fixed point O
        elif mass is None or center_of_mass is None:
            raise InvalidInputError(
                "Expected `mass` and `center_of_mass` (they are optional only when "
                "`inertia` is a RigidBody)."
            )
        j, principal = as_inertia(inertia, "inertia")
        if principal:
            j = diagonal3(j)
        if j.shape != (3, 3):
            raise InvalidInputError(
                f"Expected `inertia` of one body, shape (3,) or (3, 3), got {j.shape}."
            )
        self.torque = GravityTorque(mass, center_of_mass, g=g)
        if self.torque.mass.shape != () or self.torque.center_of_mass.shape != (3,):
            raise InvalidInputError(
                "Expected one body: `mass` a scalar and `center_of_mass` of shape (3,) "
                "(batch the initial states instead)."
            )
        self.inertia_tensor = np.array(j, dtype=float)
        self.inertia_tensor.setflags(write=False)
        self._j_inv = inverse3(self.inertia_tensor)
        self.mass = float(self.torque.mass)
        self.center_of_mass = self.torque.center_of_mass
        self.g = float(self.torque.g)

    @property
    def moment(self) -> np.ndarray:
        """``m g c`` (N m), body axes."""
        return self.torque.moment

    # -- the equations -------------------------------------------------------
    def euler_poisson(self, omega: ArrayLike, gamma: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The Euler-Poisson right-hand side ``(w', gamma')``.

        ``w' = J^-1 (m g gamma x c - w x J w)``, ``gamma' = gamma x w``.

        Parameters
        ----------
        omega, gamma : array_like, shape (..., 3)
            Body angular velocity (rad/s) and the upward vertical in body axes.

        Returns
        -------
        tuple of ndarray (..., 3)

        Examples
        --------
        >>> from poinsot.dynamics import HeavyRigidBody
        >>> top = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.5], g=10.0)
        >>> top.euler_poisson([0.0, 0.0, 0.0], [0.0, 1.0, 0.0])[0]   # tipping about x
        array([2.5, 0. , 0. ])
        """

        w = as_vec3(omega, "omega")
        gam = as_vec3(gamma, "gamma")
        batch_shape(omega=(w, 1), gamma=(gam, 1))
        m = cross(gam, self.moment)
        return _rhs(self.inertia_tensor, self._j_inv, w, m), cross(gam, w)

    def rhs(self, t: float, state: ArrayLike) -> FloatArray:
        """Time derivative of ``state = (quaternion (4), omega (3))`` (..., 7).

        ``L' = L o (0, w) / 2`` (theory §5) and the Euler-Poisson ``w'`` with
        ``gamma = R(L)^T e_z``; ``t`` is unused (the system is autonomous).

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import HeavyRigidBody
        >>> top = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.5], g=10.0)
        >>> top.rhs(0.0, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0])
        array([0., 0., 0., 1., 0., 0., 0.])
        """

        y = as_float_array(state, "state")
        if y.shape[-1:] != (7,):
            raise InvalidInputError(
                f"Expected `state` to have shape (..., 7) (quaternion, omega), got {y.shape}."
            )
        q, w = y[..., :4], y[..., 4:]
        gam = _upward(q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None])
        dw = _rhs(self.inertia_tensor, self._j_inv, w, cross(gam, self.moment))
        dq = 0.5 * _quat.mul(q, _quat.pure(w))
        return np.concatenate([dq, dw], axis=-1)

    # -- integrals -------------------------------------------------------------
    def gamma(self, rotation: Rotation | ArrayLike) -> FloatArray:
        """The upward vertical in body axes, ``gamma = R^T e_z`` (..., 3)."""
        return _upward(as_rotation_quat(rotation, "rotation"))

    def _inv(self, rotation: Rotation | ArrayLike, omega: ArrayLike) -> Invariants:
        return invariants(self.inertia_tensor, rotation, omega, torque=self.torque)

    def energy(self, rotation: Rotation | ArrayLike, omega: ArrayLike) -> FloatArray:
        """Total energy ``E = w . J w / 2 + m g c . gamma`` (J), conserved."""
        return self._inv(rotation, omega).energy

    def momentum_z(self, rotation: Rotation | ArrayLike, omega: ArrayLike) -> FloatArray:
        """The area integral ``K . e_z = (J w) . gamma`` (kg m^2/s), conserved."""
        return self._inv(rotation, omega).momentum_z

    def kovalevskaya_integral(self, rotation: Rotation | ArrayLike, omega: ArrayLike) -> FloatArray:
        """:func:`kovalevskaya_integral` at these states, with this body's ``C`` and ``m g c``."""
        return kovalevskaya_integral(
            omega, self.gamma(rotation), self.inertia_tensor[2, 2], self.moment
        )

    # -- integration -----------------------------------------------------------
    def simulate(
        self,
        rotation0: Rotation | ArrayLike,
        omega0: ArrayLike,
        t: ArrayLike,
        *,
        method: str | None = None,
        order: int | None = None,
        max_step: float | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        solver: str | None = None,
        progress: bool | Callable[[float], object] | None = None,
        events: Any = None,
    ) -> Trajectory:
        """Integrate the heavy body from ``(rotation0, omega0)`` at ``t[0]``.

        Parameters
        ----------
        rotation0 : Rotation, scipy Rotation or array_like (..., 4)
            Initial attitudes (body -> space); a leading shape is a batch.
        omega0 : array_like, shape (..., 3)
            Initial body angular velocities (rad/s).
        t : array_like, shape (n,)
            Output times (s), increasing.
        method : {"splitting", "midpoint", "rk4", "dop853", "adaptive"}, optional
            ``"splitting"`` (the default, unless ``rtol`` or ``atol`` is given: then
            ``"dop853"``, as :func:`poinsot.dynamics.simulate` chooses): free-body
            Lie-Poisson splitting with exact
            gravity kicks (compiled; keeps ``K_z`` and ``|gamma|`` to round-off,
            bounded energy error). ``"midpoint"``: the implicit Lie-Poisson
            midpoint rule with the torque at the midpoint. ``"rk4"``, ``"dop853"``
            (compiled DOP853), ``"adaptive"`` (``scipy.integrate.solve_ivp``).
        order : {2, 4, 6}, optional
            Composition order of ``"splitting"``/``"midpoint"`` (default 2).
        max_step, rtol, atol, solver, progress, events : optional
            As :func:`poinsot.dynamics.simulate` (``events``: functions ``g(t, y)`` of
            ``y = (q, omega)``, located to round-off, theory §11.1).

        Returns
        -------
        Trajectory
            ``energy`` is the kinetic energy and ``momentum`` the space angular
            momentum (as for every simulation); use :meth:`energy` and
            :meth:`momentum_z` for the integrals of the heavy body.

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot.dynamics import HeavyRigidBody
        >>> top = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.4], g=10.0)
        >>> q0 = [[1.0, 0.0, 0.0, 0.0], [0.9, 0.1, 0.0, 0.0]]       # a batch of two
        >>> top.simulate(q0, [0.0, 0.0, 20.0], [0.0, 1.0], max_step=1e-3).omega.shape
        (2, 2, 3)
        """

        if method is None:  # tolerances ask for an adaptive method, as in simulate()
            method = "dop853" if (rtol is not None or atol is not None) else "splitting"
        if method not in HEAVY_METHODS:
            integrators.check_method(method, HEAVY_METHODS, "a heavy body")
        return simulate(
            self.inertia_tensor,
            rotation0,
            omega0,
            t,
            torque=self.torque,
            method=method,
            order=order,
            max_step=max_step,
            rtol=rtol,
            atol=atol,
            solver=solver,
            progress=progress,
            events=events,
        )

    def __repr__(self) -> str:
        return (
            f"HeavyRigidBody(inertia={self.inertia_tensor.tolist()}, mass={self.mass!r}, "
            f"center_of_mass={self.center_of_mass.tolist()}, g={self.g!r})"
        )


def kovalevskaya_integral(
    omega: ArrayLike, gamma: ArrayLike, axial_moment: ArrayLike, moment: ArrayLike
) -> FloatArray:
    """The Kovalevskaya integral ``|(p + i q)^2 - (m g / C)(c1 + i c2)(gamma1 + i gamma2)|^2``.

    For ``A = B = 2 C`` and the centre of mass in the equatorial plane
    (``c3 = 0``), with ``gamma = R^T e_z`` the **upward** vertical in body axes and
    the Euler-Poisson equations of :class:`HeavyRigidBody`
    (``J w' + w x J w = m g gamma x c``), ``z = (p + i q)^2 - eps (gamma1 + i gamma2)``,
    ``eps = m g (c1 + i c2) / C``, obeys ``z' = -i r z``: ``|z|^2`` is constant
    (docs/theory.md §10). With ``c = (x0, 0, 0)``:
    ``k = (p^2 - q^2 - eps gamma1)^2 + (2 p q - eps gamma2)^2``, ``eps = m g x0 / C``.
    (With the downward vertical ``-gamma`` the sign of ``eps`` flips.)

    Parameters
    ----------
    omega : array_like, shape (..., 3)
        Body angular velocity (rad/s).
    gamma : array_like, shape (..., 3)
        Upward vertical in body axes.
    axial_moment : float
        ``C`` (kg m^2), the moment about the body ``z`` axis.
    moment : array_like, shape (3,)
        ``m g c`` (N m) in body axes; its ``z`` component must be 0.

    Returns
    -------
    ndarray, shape (...)
        ``k`` in (rad/s)^4. Conserved only in the Kovalevskaya case; computed for
        any body (to show that it is not conserved otherwise).

    Examples
    --------
    >>> from poinsot.dynamics import kovalevskaya_integral
    >>> float(kovalevskaya_integral([1.0, 0.0, 3.0], [0.0, 0.0, 1.0], 1.0, [2.0, 0.0, 0.0]))
    1.0
    """
    w = as_vec3(omega, "omega")
    gam = as_vec3(gamma, "gamma")
    c = as_float_array(axial_moment, "axial_moment")
    if c.ndim != 0 or not c > 0:
        raise InvalidInputError(
            f"Expected `axial_moment` to be a positive scalar, got {axial_moment!r}."
        )
    mg = as_vec3(moment, "moment")
    if mg.shape != (3,):
        raise InvalidInputError(f"Expected `moment` to have shape (3,), got {mg.shape}.")
    if abs(mg[2]) > 1e-12 * math.hypot(mg[0], mg[1]):
        raise InvalidInputError(
            "Expected the centre of mass in the equatorial plane (moment[2] = m g c3 = 0) for "
            f"the Kovalevskaya integral, got moment = {mg.tolist()}."
        )
    batch_shape(omega=(w, 1), gamma=(gam, 1))
    eps = (mg[0] + 1j * mg[1]) / float(c)
    z = (w[..., 0] + 1j * w[..., 1]) ** 2 - eps * (gam[..., 0] + 1j * gam[..., 1])
    return (z.real**2 + z.imag**2)[()]
