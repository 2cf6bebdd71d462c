"""Rigid bodies as mass, centre of mass and central inertia; composites; Koenig (theory §8).

Conventions
-----------
A :class:`RigidBody` is described in its own *body axes* with a *reference
point* ``O`` (the origin of the body coordinates): ``center_of_mass`` is the
position of the centre of mass ``C`` relative to ``O`` and ``inertia`` is the
tensor about ``C`` in the body axes. All vectors passed to the methods
(``omega``, ``v_cm``, points) are in the same body axes; positions are relative
to ``O``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _display
from .._typing import ArrayLike, FloatArray
from .._validate import as_positive, as_vec3, batch_shape
from .._vec import cross, diagonal3
from ..errors import InvalidInputError, InvalidTypeError
from . import solids
from .meshes import mesh as _mesh
from .tensor import _as_rotation_matrix, _kinetic, _momentum, _steiner, _transpose, as_inertia
from .tensor import points as _points
from .tensor import principal_axes as _principal_axes

if TYPE_CHECKING:
    from ..rotations.rotation import Rotation

__all__ = ["RigidBody", "combine", "kinetic_energy", "angular_momentum"]


# ---------------------------------------------------------------------------
# Kernels (no validation)
# ---------------------------------------------------------------------------


def _kinetic_energy(
    m: np.ndarray, j: np.ndarray, w: np.ndarray, v: np.ndarray, principal: bool = False
) -> np.ndarray:
    """Koenig: ``T = m V_c^2 / 2 + w^T J_c w / 2`` (the rotational part from
    :func:`poinsot.mass.tensor._kinetic`, the one place of ``w^T J w / 2``)."""
    return 0.5 * m * np.einsum("...i,...i->...", v, v) + _kinetic(j, principal, w)


def _angular_momentum(
    m: ArrayLike,
    j: np.ndarray,
    w: np.ndarray,
    v: np.ndarray,
    r_oc: np.ndarray,
    principal: bool = False,
) -> np.ndarray:
    """``K_O = J_c w + OC x m V_c`` (``J_c w`` from :func:`poinsot.mass.tensor._momentum`)."""
    return _momentum(j, principal, w) + cross(r_oc, np.asarray(m)[..., None] * v)


# ---------------------------------------------------------------------------
# Module functions
# ---------------------------------------------------------------------------


def kinetic_energy(
    mass: ArrayLike, inertia_cm: ArrayLike, omega: ArrayLike, v_cm: ArrayLike = (0.0, 0.0, 0.0)
) -> FloatArray:
    """Kinetic energy of a rigid body by Koenig's theorem.

    ``T = m V_c^2 / 2 + w^T J_c w / 2`` (theory §8); in principal axes
    ``T = m V_c^2 / 2 + (A p^2 + B q^2 + C r^2) / 2``.

    Parameters
    ----------
    mass : array_like, shape (...)
        Mass, > 0.
    inertia_cm : array_like, shape (..., 3, 3) or (..., 3)
        Inertia about the centre of mass: a tensor, or principal moments (then
        the vectors are in principal axes).
    omega : array_like, shape (..., 3)
        Angular velocity.
    v_cm : array_like, shape (..., 3), optional
        Velocity of the centre of mass (default zero: pure rotation).

    Returns
    -------
    ndarray, shape (...)
        ``T``.

    Notes
    -----
    **Convention:** ``inertia_cm``, ``omega`` and ``v_cm`` in the same axes
    (usually body axes); SI or any consistent units.

    Examples
    --------
    >>> from poinsot.mass import kinetic_energy, sphere
    >>> float(kinetic_energy(5.0, sphere(5.0, 1.0), [0, 0, 2.0], [1.0, 0, 0]))
    6.5
    """
    m = as_positive(mass, "mass")
    j, principal = as_inertia(inertia_cm, "inertia_cm", allow_singular=True)
    w = as_vec3(omega, "omega")
    v = as_vec3(v_cm, "v_cm")
    batch_shape(mass=(m, 0), inertia_cm=(j, 1 if principal else 2), omega=(w, 1), v_cm=(v, 1))
    return _kinetic_energy(m, j, w, v, principal)


def angular_momentum(
    mass: ArrayLike,
    inertia_cm: ArrayLike,
    omega: ArrayLike,
    v_cm: ArrayLike = (0.0, 0.0, 0.0),
    r_oc: ArrayLike = (0.0, 0.0, 0.0),
) -> FloatArray:
    """Angular momentum of a rigid body about a point ``O``.

    ``K_O = J_c w + OC x m V_c`` (theory §8): the spin about the centre of mass
    plus the moment of the linear momentum.

    Parameters
    ----------
    mass : array_like, shape (...)
        Mass, > 0.
    inertia_cm : array_like, shape (..., 3, 3) or (..., 3)
        Inertia about the centre of mass ``C``: a tensor, or principal moments
        (then the vectors are in principal axes).
    omega : array_like, shape (..., 3)
        Angular velocity.
    v_cm : array_like, shape (..., 3), optional
        Velocity of ``C`` (default zero).
    r_oc : array_like, shape (..., 3), optional
        Position of ``C`` relative to ``O`` (the vector ``OC``; default zero:
        ``O = C``).

    Returns
    -------
    ndarray, shape (..., 3)
        ``K_O``, in the same axes as the inputs.

    Notes
    -----
    **Convention:** all arguments in one set of axes (usually body axes).
    For a body turning about a fixed point ``O`` (``V_c = w x OC``) this equals
    ``J_O w``.

    Examples
    --------
    >>> from poinsot.mass import angular_momentum, sphere
    >>> angular_momentum(5.0, sphere(5.0, 1.0), [0, 0, 2.0], [1.0, 0, 0], [0, 1.0, 0])
    array([ 0.,  0., -1.])
    """
    m = as_positive(mass, "mass")
    j, principal = as_inertia(inertia_cm, "inertia_cm", allow_singular=True)
    w = as_vec3(omega, "omega")
    v = as_vec3(v_cm, "v_cm")
    r = as_vec3(r_oc, "r_oc")
    nd = 1 if principal else 2
    batch_shape(mass=(m, 0), inertia_cm=(j, nd), omega=(w, 1), v_cm=(v, 1), r_oc=(r, 1))
    return _angular_momentum(m, j, w, v, r, principal)


def combine(*bodies: RigidBody) -> RigidBody:
    """Composite of rigid bodies described about a common reference point and axes.

    ``m = sum m_i``, ``r_c = sum m_i r_i / m``,
    ``J_c = sum (J_i + m_i (d_i^T d_i E - d_i d_i^T))`` with ``d_i = r_i - r_c``
    (Huygens-Steiner, theory §8).

    Parameters
    ----------
    *bodies : RigidBody
        At least one body, all in the same axes about the same reference point
        (use :meth:`RigidBody.placed` to put a part in position first). Batch
        shapes broadcast.

    Returns
    -------
    RigidBody
        The composite body.

    Notes
    -----
    **Convention:** the result uses the common axes and reference point.

    Examples
    --------
    >>> from poinsot.mass import RigidBody, combine
    >>> a = RigidBody.box(1.0, 1.0, 1.0, 1.0).placed(position=[0.5, 0, 0])
    >>> b = RigidBody.box(1.0, 1.0, 1.0, 1.0).placed(position=[-0.5, 0, 0])
    >>> body = combine(a, b)   # = RigidBody.box(2.0, 2.0, 1.0, 1.0)
    >>> body.mass, body.inertia.diagonal().round(12)
    (2.0, array([0.333333, 0.833333, 0.833333]))
    """
    if not bodies:
        raise InvalidInputError("Expected at least one body to combine, got none.")
    for k, b in enumerate(bodies):
        if not isinstance(b, RigidBody):
            raise InvalidTypeError(
                f"Expected every body to be a RigidBody, got {type(b).__name__} at position {k}."
            )
    masses = [np.asarray(b.mass) for b in bodies]
    m = sum(masses[1:], masses[0])
    com = sum(mi[..., None] * b.center_of_mass for mi, b in zip(masses, bodies, strict=True))
    com = com / m[..., None]
    j = sum(
        b.inertia + _steiner(mi, b.center_of_mass - com)
        for mi, b in zip(masses, bodies, strict=True)
    )
    return RigidBody(m, j, com)


# ---------------------------------------------------------------------------
# RigidBody
# ---------------------------------------------------------------------------


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False, repr=False)
class RigidBody:
    """A rigid body: mass, centre of mass and inertia about the centre of mass.

    Parameters
    ----------
    mass : array_like, shape (...)
        Mass, > 0.
    inertia : array_like, shape (..., 3, 3) or (..., 3)
        Inertia **about the centre of mass**, in the body axes: a tensor, or
        principal moments ``(A, B, C)`` (then the body axes are principal axes),
        read as everywhere in poinsot (an array whose last two dimensions are
        ``(3, 3)`` is a tensor). Checked physical with ``allow_singular=True``
        (a thin rod or a point mass has a zero moment). Stored as the tensor.
    center_of_mass : array_like, shape (..., 3), optional
        Position of the centre of mass relative to the body reference point
        ``O``, in body axes. Default: the origin.

    Notes
    -----
    A batch of bodies is one ``RigidBody`` whose parameters have leading
    dimensions (they broadcast); :attr:`shape` is the batch shape.

    **Convention:** every vector (``omega``, ``v_cm``, points) given to or
    returned by the methods is in body axes, positions relative to ``O``
    (theory §8).

    Examples
    --------
    >>> from poinsot.mass import RigidBody
    >>> body = RigidBody.box(12.0, 1.0, 2.0, 3.0)
    >>> body.inertia.diagonal()
    array([13., 10.,  5.])
    >>> body.inertia_about([0.5, 0, 0]).diagonal()     # at the middle of a face
    array([13., 13.,  8.])
    >>> float(body.kinetic_energy([1.0, 0, 0], v_cm=[0, 1.0, 0]))
    12.5
    >>> RigidBody(2.0, [1.0, 2.0, 2.5]).inertia.diagonal()   # principal moments
    array([1. , 2. , 2.5])
    """

    mass: Any
    inertia: Any
    center_of_mass: Any = field(default=(0.0, 0.0, 0.0))

    def __post_init__(self) -> None:
        m = as_positive(self.mass, "mass")
        j, principal = as_inertia(self.inertia, "inertia", allow_singular=True)
        if principal:
            j = diagonal3(j)
        c = as_vec3(self.center_of_mass, "center_of_mass")
        batch_shape(mass=(m, 0), inertia=(j, 2), center_of_mass=(c, 1))
        m = _readonly(m)
        object.__setattr__(self, "mass", float(m) if m.ndim == 0 else m)
        object.__setattr__(self, "inertia", _readonly(j))
        object.__setattr__(self, "center_of_mass", _readonly(c))

    def __repr__(self) -> str:
        if self.shape != ():
            return f"RigidBody(shape={self.shape})"
        j = " ".join(np.array2string(np.asarray(self.inertia), precision=6, separator=", ").split())
        c = np.array2string(np.asarray(self.center_of_mass), precision=6, separator=", ")
        return f"RigidBody(mass={self.mass:.6g}, inertia={j}, center_of_mass={c})"

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: mass, centre of mass, inertia, principal moments and axes (SI units)."""
        d = _display
        if self.shape != ():
            rows = [("batch shape", d.esc(self.shape)),
                    ("mass", d.value(np.ravel(self.mass)[:5], "kg"))]  # fmt: skip
            return d.table("RigidBody batch", rows, "first values shown")
        moments, axes = self.principal_axes()
        rows = [
            ("mass", d.value(self.mass, "kg")),
            ("centre of mass", d.value(self.center_of_mass, "m (body axes, from O)")),
            ("inertia about the centre of mass", d.matrix(self.inertia)),
            ("principal moments", d.value(moments, "kg m^2")),
            ("principal axes (columns, body axes)", d.matrix(axes.as_matrix())),
        ]
        return d.table("RigidBody", rows, "inertia in kg m^2, body axes (docs/theory.md §8)")

    # -- construction ------------------------------------------------------

    @classmethod
    def box(cls, mass: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> RigidBody:
        """Uniform box with edges ``a, b, c`` (see :func:`poinsot.mass.box`), centred at ``O``."""
        return cls(mass, solids.box(mass, a, b, c))

    @classmethod
    def sphere(cls, mass: ArrayLike, radius: ArrayLike, *, hollow: bool = False) -> RigidBody:
        """Uniform ball or shell (see :func:`poinsot.mass.sphere`), centred at ``O``."""
        return cls(mass, solids.sphere(mass, radius, hollow=hollow))

    @classmethod
    def cylinder(
        cls, mass: ArrayLike, radius: ArrayLike, height: ArrayLike, *, hollow: bool = False
    ) -> RigidBody:
        """Uniform cylinder or tube, axis ``z`` (see :func:`poinsot.mass.cylinder`), centred."""
        return cls(mass, solids.cylinder(mass, radius, height, hollow=hollow))

    @classmethod
    def cone(cls, mass: ArrayLike, radius: ArrayLike, height: ArrayLike) -> RigidBody:
        """Uniform cone, axis ``z`` (see :func:`poinsot.mass.cone`), centre of mass at ``O``."""
        return cls(mass, solids.cone(mass, radius, height))

    @classmethod
    def ellipsoid(cls, mass: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> RigidBody:
        """Uniform ellipsoid (see :func:`poinsot.mass.ellipsoid`), centred at ``O``."""
        return cls(mass, solids.ellipsoid(mass, a, b, c))

    @classmethod
    def rod(cls, mass: ArrayLike, length: ArrayLike) -> RigidBody:
        """Thin rod along ``z`` (see :func:`poinsot.mass.rod`), midpoint at ``O``."""
        return cls(mass, solids.rod(mass, length))

    @classmethod
    def disc(cls, mass: ArrayLike, radius: ArrayLike) -> RigidBody:
        """Thin disc, normal ``z`` (see :func:`poinsot.mass.disc`), centred at ``O``."""
        return cls(mass, solids.disc(mass, radius))

    @classmethod
    def ring(cls, mass: ArrayLike, radius: ArrayLike) -> RigidBody:
        """Thin ring, normal ``z`` (see :func:`poinsot.mass.ring`), centred at ``O``."""
        return cls(mass, solids.ring(mass, radius))

    @classmethod
    def from_points(cls, masses: ArrayLike, positions: ArrayLike) -> RigidBody:
        """Point masses ``masses`` (..., n) at ``positions`` (..., n, 3) relative to ``O``.

        ``r_c = sum m r / sum m`` and ``J_c = J_O - m (r_c^T r_c E - r_c r_c^T)``
        with ``J_O`` from :func:`poinsot.mass.points`.

        Examples
        --------
        >>> from poinsot.mass import RigidBody
        >>> b = RigidBody.from_points([1.0, 3.0], [[0, 0, 0], [4.0, 0, 0]])
        >>> b.mass, b.center_of_mass, b.inertia.diagonal()
        (4.0, array([3., 0., 0.]), array([ 0., 12., 12.]))
        """
        j_o = _points(masses, positions)
        m_i = np.asarray(masses, dtype=np.float64)
        r = np.asarray(positions, dtype=np.float64)
        m = m_i.sum(axis=-1)
        com = np.einsum("...n,...ni->...i", m_i, r) / m[..., None]
        return cls(m, j_o - _steiner(m, com), com)

    @classmethod
    def from_mesh(
        cls,
        vertices: ArrayLike,
        faces: ArrayLike,
        *,
        mass: ArrayLike | None = None,
        density: ArrayLike | None = None,
    ) -> RigidBody:
        """Uniform solid bounded by a closed triangle mesh (see :func:`poinsot.mass.mesh`)."""
        props = _mesh(vertices, faces, mass=mass, density=density)
        return cls(props.mass, props.inertia, props.center_of_mass)

    def placed(
        self, rotation: Rotation | ArrayLike | None = None, position: ArrayLike | None = None
    ) -> RigidBody:
        """The same body described in an assembly frame ``a``.

        The body's own axes ``b`` have attitude ``rotation = C_ab`` relative to
        ``a`` and its reference point sits at ``position`` (in ``a``). Then
        ``r_c,a = C_ab r_c,b + position`` and ``J_a = C_ab J_b C_ab^T`` (theory §8).

        Parameters
        ----------
        rotation : Rotation or array_like, shape (..., 3, 3), optional
            ``C_ab`` (body -> assembly components). Default: identity.
        position : array_like, shape (..., 3), optional
            Position of the body reference point in the assembly frame. Default:
            the origin.

        Returns
        -------
        RigidBody
            The body with the assembly frame's axes and origin as its own.

        Examples
        --------
        >>> import numpy as np
        >>> from poinsot import Rotation
        >>> from poinsot.mass import RigidBody
        >>> r = Rotation.from_axis_angle([0, 1.0, 0], np.pi / 2)   # body z -> assembly x
        >>> b = RigidBody.rod(3.0, 2.0).placed(r, [0, 0, 1.0])
        >>> b.inertia.diagonal().round(12) + 0.0, b.center_of_mass
        (array([0., 1., 1.]), array([0., 0., 1.]))
        """
        j, c = self.inertia, self.center_of_mass
        if rotation is not None:
            s = _as_rotation_matrix(rotation)
            j = s @ j @ _transpose(s)
            c = np.einsum("...ij,...j->...i", s, c)
        if position is not None:
            c = c + as_vec3(position, "position")
        return RigidBody(self.mass, j, c)

    # -- queries -------------------------------------------------------------

    @property
    def shape(self) -> tuple[int, ...]:
        """Batch shape (``()`` for one body)."""
        return np.broadcast_shapes(
            np.shape(self.mass), self.inertia.shape[:-2], self.center_of_mass.shape[:-1]
        )

    def inertia_about(self, point: ArrayLike = (0.0, 0.0, 0.0)) -> FloatArray:
        """Inertia about ``point`` (relative to ``O``, body axes; default ``O``).

        ``J_P = J_C + m (a^T a E - a a^T)``, ``a = P - C`` (Huygens-Steiner, theory §8).
        """
        p = as_vec3(point, "point")
        return self.inertia + _steiner(self.mass, p - self.center_of_mass)

    def principal_axes(self) -> tuple[FloatArray, Rotation]:
        """Principal moments and axes of the central inertia: ``(moments, S)``.

        ``moments`` ascending ``(..., 3)`` (= :attr:`principal_moments`); ``S`` a
        :class:`~poinsot.Rotation` whose matrix has the principal axes as columns, in
        body axes: ``S^T J S = diag(moments)``. A method with the same result on
        every class (:meth:`poinsot.dynamics.FreeRigidBody.principal_axes`); see
        :func:`poinsot.mass.principal_axes` for the choice of axes.
        """
        return _principal_axes(self.inertia)

    @property
    def principal_moments(self) -> np.ndarray:
        """Principal moments ``A <= B <= C`` of the central inertia, shape (..., 3)."""
        return np.linalg.eigvalsh(self.inertia)

    def kinetic_energy(self, omega: ArrayLike, v_cm: ArrayLike = (0.0, 0.0, 0.0)) -> FloatArray:
        """Koenig: ``T = m V_c^2 / 2 + w^T J_c w / 2`` (body axes; see :func:`kinetic_energy`)."""
        w = as_vec3(omega, "omega")
        v = as_vec3(v_cm, "v_cm")
        batch_shape(body=(self.mass, 0), omega=(w, 1), v_cm=(v, 1))
        return _kinetic_energy(self.mass, self.inertia, w, v)

    def angular_momentum(
        self,
        omega: ArrayLike,
        v_cm: ArrayLike = (0.0, 0.0, 0.0),
        point: ArrayLike = (0.0, 0.0, 0.0),
    ) -> FloatArray:
        """``K_P = J_c w + PC x m V_c`` about ``point`` ``P`` (relative to ``O``).

        ``point`` defaults to the reference point ``O``.

        See :func:`angular_momentum`; all vectors in body axes.

        Examples
        --------
        >>> from poinsot.mass import RigidBody
        >>> rod = RigidBody.rod(3.0, 2.0).placed(position=[0, 0, 1.0])
        >>> w = [1.0, 0, 0]
        >>> rod.angular_momentum(w, v_cm=[0, -1.0, 0])   # pinned at O: J_O w
        array([4., 0., 0.])
        """
        w = as_vec3(omega, "omega")
        v = as_vec3(v_cm, "v_cm")
        p = as_vec3(point, "point")
        batch_shape(body=(self.mass, 0), omega=(w, 1), v_cm=(v, 1), point=(p, 1))
        return _angular_momentum(self.mass, self.inertia, w, v, self.center_of_mass - p)

    # -- composition -----------------------------------------------------------

    def __add__(self, other: object) -> RigidBody:
        if not isinstance(other, RigidBody):
            return NotImplemented
        return combine(self, other)

    def __radd__(self, other: object) -> RigidBody:
        # lets sum(bodies) work (it starts from 0)
        if isinstance(other, int) and not isinstance(other, bool) and other == 0:
            return self
        return NotImplemented

    combine = staticmethod(combine)
