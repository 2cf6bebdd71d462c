"""Finite displacements of a rigid body: :class:`RigidTransform` (SE(3)) and the finite
screw of Chasles' theorem (docs/theory.md §4, §6).

A transform maps a point ``x`` (components in the moved frame, or the point before the
displacement) to ``R x + t``: a rotation :class:`~poinsot.Rotation` ``R`` (body ->
space, as everywhere in poinsot) and a translation ``t`` (m, space axes). Composition
reads as for rotations: ``a * b`` is ``b`` then ``a`` (``(a * b).apply(x) ==
a.apply(b.apply(x))``), as in SciPy's ``RigidTransform`` (SciPy >= 1.16), whose
constructors and readers this class mirrors (with scalar-first quaternions).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_float_array, as_trailing, batch_shape
from .._vec import cross, dot
from ..errors import InvalidInputError, InvalidTypeError
from ._lazy import big, flat, kernels, threaded
from .quaternion import conjugate_array, multiply
from .rotation import Rotation

__all__ = ["RigidTransform", "FiniteScrew", "sclerp"]

# below this angle (rad) the coefficients of V(phi) and V(phi)^-1 use their series:
# the closed forms lose relative accuracy as 1/theta^2 and 1/theta^3
_SMALL = 1e-3


def _v_coefficients(theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``B = (1 - cos f)/f^2``, ``C = (f - sin f)/f^3`` of ``V = E + B f^ + C f^^2``."""
    small = theta < _SMALL
    f = np.where(small, 1.0, theta)
    f2 = theta * theta
    b = np.where(small, 0.5 - f2 / 24.0 + f2 * f2 / 720.0, (1.0 - np.cos(f)) / (f * f))
    c = np.where(small, 1.0 / 6.0 - f2 / 120.0 + f2 * f2 / 5040.0, (f - np.sin(f)) / f**3)
    return b, c


def _v_inverse_coefficient(theta: FloatArray) -> FloatArray:
    """``D = (1 - (f/2) cot(f/2)) / f^2`` of ``V^-1 = E - f^/2 + D f^^2``."""
    small = theta < _SMALL
    f = np.where(small, 1.0, theta)
    f2 = theta * theta
    half = 0.5 * f
    closed = (1.0 - half * np.cos(half) / np.sin(half)) / (f * f)
    return np.where(small, 1.0 / 12.0 + f2 / 720.0 + f2 * f2 / 30240.0, closed)


def _apply_v(phi: FloatArray, rho: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
    """``V rho = rho + B phi x rho + C phi x (phi x rho)``."""
    pr = cross(phi, rho)
    return rho + b[..., None] * pr + c[..., None] * cross(phi, pr)


@dataclass(frozen=True)
class FiniteScrew:
    """The finite screw of a displacement (Chasles' theorem, docs/theory.md §6).

    Every displacement is a rotation by ``angle`` about an axis and a slide along it.

    Attributes
    ----------
    direction : ndarray, shape (..., 3)
        Unit direction of the axis (space axes); for a pure translation, that of
        the translation; zero for the identity.
    point : ndarray, shape (..., 3)
        The point of the axis closest to the origin (m).
    angle : ndarray, shape (...)
        Rotation angle about ``direction`` (rad, in ``[0, pi]``).
    slide : ndarray, shape (...)
        Translation along the axis (m): the projection of any point's displacement
        on ``direction`` (the same for every point).
    pitch : ndarray, shape (...)
        ``slide / angle`` (m/rad): 0 for a pure rotation, ``inf`` for a pure
        translation, ``nan`` for the identity.
    """

    direction: FloatArray
    point: FloatArray
    angle: FloatArray
    slide: FloatArray
    pitch: FloatArray


class RigidTransform:
    """Rigid displacements ``x -> R x + t`` (SE(3)), any leading shape.

    Build one with ``from_components``, ``from_rotation``, ``from_translation``,
    ``from_matrix`` (4x4), ``from_exp_coords`` (twist) or ``from_dual_quat``; read it
    with the matching ``as_*``; ``apply`` moves points; ``a * b`` is ``b`` then ``a``;
    ``inv``; ``screw`` gives Chasles' finite screw; :func:`sclerp` interpolates.

    Notes
    -----
    **Convention:** ``R`` maps body components to space components (theory §2), ``t``
    is in space axes (m); ``(a * b).apply(x) = a.apply(b.apply(x))``; quaternions
    scalar first; the exponential coordinates are ``(phi, rho)`` with ``phi`` the
    rotation vector (rad) and ``t = V(phi) rho``, as SciPy's ``RigidTransform``.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.rotations import RigidTransform
    >>> from poinsot import Rotation
    >>> a = RigidTransform.from_components([1.0, 0.0, 0.0],
    ...                                    Rotation.from_rotvec([0, 0, 90], degrees=True))
    >>> a.apply([1.0, 0.0, 0.0]).round(12) + 0.0
    array([1., 1., 0.])
    >>> (a * a.inv()).as_matrix().round(12) + 0.0
    array([[1., 0., 0., 0.],
           [0., 1., 0., 0.],
           [0., 0., 1., 0.],
           [0., 0., 0., 1.]])
    """

    __slots__ = ("_rotation", "_t")

    def __init__(self, rotation: Rotation, translation: FloatArray) -> None:
        # private: use the from_* constructors (validated there)
        self._rotation = rotation
        t = np.array(translation, dtype=np.float64)
        t.setflags(write=False)
        self._t = t

    # ------------------------------------------------------------------ build
    @classmethod
    def from_components(cls, translation: ArrayLike, rotation: Rotation | Any) -> RigidTransform:
        """From a translation ``t`` (..., 3) (m, space axes) and a rotation ``R`` (a
        poinsot or SciPy ``Rotation``, or scalar-first quaternions (..., 4)):
        ``x -> R x + t``. Shapes broadcast.

        Examples
        --------
        >>> RigidTransform.from_components([1.0, 2.0, 3.0], [1.0, 0, 0, 0]).as_components()[0]
        array([1., 2., 3.])
        """
        rot = _as_rotation(rotation)
        t = as_trailing(translation, "translation", (3,))
        shape = batch_shape(translation=(t, 1), rotation=(rot.shape, 0))
        q = np.broadcast_to(rot.as_quat(), shape + (4,))
        return cls(Rotation.from_quat(q), np.broadcast_to(t, shape + (3,)))

    @classmethod
    def from_rotation(cls, rotation: Rotation | Any) -> RigidTransform:
        """A pure rotation about the origin (``t = 0``).

        Examples
        --------
        >>> RigidTransform.from_rotation(Rotation.identity()).as_matrix()[:3, 3]
        array([0., 0., 0.])
        """
        rot = _as_rotation(rotation)
        return cls(rot, np.zeros(rot.shape + (3,)))

    @classmethod
    def from_translation(cls, translation: ArrayLike) -> RigidTransform:
        """A pure translation (m, space axes).

        Examples
        --------
        >>> RigidTransform.from_translation([0.0, 0.0, 2.0]).apply([1.0, 0, 0])
        array([1., 0., 2.])
        """
        t = as_trailing(translation, "translation", (3,))
        return cls(Rotation.identity(t.shape[:-1]), t)

    @classmethod
    def identity(cls, shape: int | tuple[int, ...] = ()) -> RigidTransform:
        """The identity (a batch of identities for a ``shape``).

        Examples
        --------
        >>> RigidTransform.identity((2,)).shape
        (2,)
        """
        shape = (shape,) if isinstance(shape, int) else tuple(shape)
        return cls(Rotation.identity(shape), np.zeros(shape + (3,)))

    @classmethod
    def from_matrix(cls, matrix: ArrayLike, *, atol: float = 1e-6) -> RigidTransform:
        """From homogeneous matrices (..., 4, 4) ``[[R, t], [0, 0, 0, 1]]``.

        The bottom row must be ``(0, 0, 0, 1)`` within ``atol``; the rotation block is
        read by :meth:`Rotation.from_matrix` (orthogonal within ``atol``, else
        refused).

        Examples
        --------
        >>> m = np.eye(4); m[:3, 3] = [1.0, 2.0, 3.0]
        >>> RigidTransform.from_matrix(m).as_components()[0]
        array([1., 2., 3.])
        """
        m = as_trailing(matrix, "matrix", (4, 4))
        bottom = m[..., 3, :]
        if np.any(np.abs(bottom - (0.0, 0.0, 0.0, 1.0)) > atol):
            bad = bottom.reshape(-1, 4)[np.any(np.abs(bottom - (0, 0, 0, 1)) > atol, axis=-1)]
            raise InvalidInputError(
                f"Expected `matrix` to have the bottom row (0, 0, 0, 1), got {bad[0].tolist()}."
            )
        rot = Rotation.from_matrix(m[..., :3, :3], atol=atol)
        return cls(rot, m[..., :3, 3])

    @classmethod
    def from_exp_coords(cls, exp_coords: ArrayLike) -> RigidTransform:
        """From exponential coordinates (..., 6) ``(phi, rho)`` (the twist times 1):
        ``R = exp(phi^)``, ``t = V(phi) rho``, ``V = E + (1 - cos f)/f^2 phi^ +
        (f - sin f)/f^3 phi^^2`` (series for small ``f = |phi|``).

        Examples
        --------
        >>> RigidTransform.from_exp_coords([0, 0, 0, 1.0, 2.0, 3.0]).as_components()[0]
        array([1., 2., 3.])
        """
        x = as_trailing(exp_coords, "exp_coords", (6,))
        phi, rho = x[..., :3], x[..., 3:]
        b, c = _v_coefficients(np.linalg.norm(phi, axis=-1))
        return cls(Rotation.from_rotvec(phi), _apply_v(phi, rho, b, c))

    @classmethod
    def from_dual_quat(cls, dual_quat: ArrayLike, *, scalar_first: bool = True) -> RigidTransform:
        """From unit dual quaternions (..., 8): real part ``q`` then dual part
        ``q_d = (0, t) o q / 2`` (scalar first by default; ``scalar_first=False`` for
        SciPy's order). The real part is normalised (zero refused); the translation is
        ``t = 2 vec(q_d o q~)`` after that normalisation.

        Examples
        --------
        >>> RigidTransform.from_dual_quat([1.0, 0, 0, 0, 0, 0.5, 0, 0]).as_components()[0]
        array([1., 0., 0.])
        """

        first = as_bool(scalar_first, "scalar_first")
        dq = as_trailing(dual_quat, "dual_quat", (8,))
        real, dual = dq[..., :4], dq[..., 4:]
        if not first:
            real, dual = np.roll(real, 1, axis=-1), np.roll(dual, 1, axis=-1)
        norm = np.linalg.norm(real, axis=-1)
        if np.any(norm == 0):
            raise InvalidInputError("Expected `dual_quat` to have a non-zero real part.")
        real = real / norm[..., None]
        dual = dual / norm[..., None]
        t = 2.0 * multiply(dual, conjugate_array(real))[..., 1:]
        return cls(Rotation.from_quat(real), t)

    # ------------------------------------------------------------------ read
    @property
    def shape(self) -> tuple[int, ...]:
        """Leading shape (``()`` for one transform)."""
        return self._t.shape[:-1]

    @property
    def rotation(self) -> Rotation:
        """The rotation part ``R``."""
        return self._rotation

    @property
    def translation(self) -> FloatArray:
        """The translation ``t`` (..., 3) (m, space axes)."""
        return self._t.copy()

    def as_components(self) -> tuple[FloatArray, Rotation]:
        """``(translation (..., 3), rotation)``, as SciPy's ``as_components``.

        Examples
        --------
        >>> RigidTransform.identity().as_components()[0]
        array([0., 0., 0.])
        """
        return self._t.copy(), self._rotation

    def as_matrix(self) -> FloatArray:
        """Homogeneous matrices (..., 4, 4) ``[[R, t], [0, 0, 0, 1]]``.

        Examples
        --------
        >>> RigidTransform.from_translation([1.0, 0, 0]).as_matrix()[0]
        array([1., 0., 0., 1.])
        """
        if big(self.shape):  # one compiled pass
            m = np.empty(self.shape + (4, 4))
            q = flat(self._rotation._q, 4)
            threaded(kernels().to_matrix_flat, q, flat(self._t, 3), m.reshape(-1, 16))
            return m
        m = np.zeros(self.shape + (4, 4))
        m[..., :3, :3] = self._rotation.as_matrix()
        m[..., :3, 3] = self._t
        m[..., 3, 3] = 1.0
        return m

    def as_exp_coords(self) -> FloatArray:
        """Exponential coordinates (..., 6) ``(phi, rho)``: ``phi`` the rotation vector,
        ``rho = V(phi)^-1 t``, ``V^-1 = E - phi^/2 + D phi^^2``,
        ``D = (1 - (f/2) cot(f/2)) / f^2`` (series for small ``f``; exact up to
        ``f = pi``).

        Examples
        --------
        >>> x = [0.1, -0.2, 0.3, 1.0, 2.0, 3.0]
        >>> bool(np.allclose(RigidTransform.from_exp_coords(x).as_exp_coords(), x))
        True
        """
        phi = self._rotation.as_rotvec()
        d = _v_inverse_coefficient(np.linalg.norm(phi, axis=-1))
        pt = cross(phi, self._t)
        rho = self._t - 0.5 * pt + d[..., None] * cross(phi, pt)
        return np.concatenate([phi, rho], axis=-1)

    def as_dual_quat(self, *, scalar_first: bool = True) -> FloatArray:
        """Unit dual quaternions (..., 8): ``q`` then ``q_d = (0, t) o q / 2``.

        Examples
        --------
        >>> RigidTransform.from_translation([2.0, 0, 0]).as_dual_quat()
        array([1., 0., 0., 0., 0., 1., 0., 0.])
        """

        first = as_bool(scalar_first, "scalar_first")
        q = self._rotation.as_quat()
        pure = np.concatenate([np.zeros(self.shape + (1,)), self._t], axis=-1)
        dual = 0.5 * multiply(pure, q)
        if not first:
            q, dual = np.roll(q, -1, axis=-1), np.roll(dual, -1, axis=-1)
        return np.concatenate([q, dual], axis=-1)

    # ------------------------------------------------------------------ use
    def apply(self, points: ArrayLike, inverse: bool = False) -> FloatArray:
        """Move points (..., 3): ``R x + t`` (``inverse=True``: ``R^T (x - t)``).

        Examples
        --------
        >>> RigidTransform.from_translation([0, 0, 1.0]).apply([0, 0, 0], inverse=True)
        array([ 0.,  0., -1.])
        """
        x = as_trailing(points, "points", (3,))
        if as_bool(inverse, "inverse"):
            return self._rotation.apply(x - self._t, inverse=True)
        return self._rotation.apply(x) + self._t

    def inv(self) -> RigidTransform:
        """The inverse ``x -> R^T (x - t)``.

        Examples
        --------
        >>> RigidTransform.from_translation([1.0, 0, 0]).inv().as_components()[0]
        array([-1., -0., -0.])
        """
        rinv = self._rotation.inv()
        return RigidTransform(rinv, -rinv.apply(self._t))

    def __mul__(self, other: object) -> RigidTransform:
        """``self * other``: ``other`` then ``self`` (``R = R_a R_b``, ``t = R_a t_b + t_a``)."""
        if not isinstance(other, RigidTransform):
            return NotImplemented
        rot = self._rotation * other._rotation
        return RigidTransform(rot, self._rotation.apply(other._t) + self._t)

    def __pow__(self, n: float) -> RigidTransform:
        """``n``-th power along the screw: ``exp(n log(self))`` (any real ``n``).

        Examples
        --------
        >>> (RigidTransform.from_translation([0.0, 0.0, 2.0]) ** 0.5).as_components()[0]
        array([0., 0., 1.])
        """
        k = as_float_array(n, "n")
        if k.ndim:
            raise InvalidInputError(f"Expected `n` to be a real number, got shape {k.shape}.")
        return RigidTransform.from_exp_coords(float(k) * self.as_exp_coords())

    def __getitem__(self, index: Any) -> RigidTransform:
        if self.shape == ():
            raise InvalidTypeError("A single RigidTransform cannot be indexed.")
        return RigidTransform(self._rotation[index], self._t[index])

    def __len__(self) -> int:
        if self.shape == ():
            raise InvalidTypeError("A single RigidTransform has no len().")
        return self.shape[0]

    def __repr__(self) -> str:
        if self.shape == ():
            t = ", ".join(f"{x:.6g}" for x in self._t)
            q = ", ".join(f"{x:.6g}" for x in self._rotation.as_quat())
            return f"RigidTransform(translation=[{t}], quat=[{q}])"
        return f"RigidTransform(shape={self.shape})"

    def screw(self) -> FiniteScrew:
        """The finite screw of Chasles' theorem (docs/theory.md §6).

        With ``R`` a rotation by ``f`` in ``[0, pi]`` about the unit ``e``, the slide is
        ``d = e . t`` and the point of the axis closest to the origin is
        ``p = (t_n + cot(f/2) e x t_n) / 2``, ``t_n = t - d e`` (the solution of
        ``(E - R) p = t_n`` with ``p . e = 0``). Pure translations (``f = 0``) and
        pure rotations (``d = 0``) are exact.

        Examples
        --------
        >>> r = Rotation.from_rotvec([0, 0, 90], degrees=True)
        >>> s = RigidTransform.from_components([0.0, 2.0, 0.5], r).screw()
        >>> s.direction, s.point.round(12) + 0.0, float(s.slide), float(s.pitch) * np.pi / 2
        (array([0., 0., 1.]), array([-1.,  1.,  0.]), 0.5, 0.5)
        """
        phi = self._rotation.as_rotvec()
        angle = np.linalg.norm(phi, axis=-1)
        rotating = angle > 0
        safe = np.where(rotating, angle, 1.0)[..., None]
        t = self._t
        tn_len = np.linalg.norm(t, axis=-1)
        # a pure translation: the axis along t through the origin
        t_dir = np.divide(t, np.where(tn_len > 0, tn_len, 1.0)[..., None])
        e = np.where(rotating[..., None], phi / safe, t_dir)
        slide = dot(e, t)
        tn = t - slide[..., None] * e
        half = 0.5 * np.where(rotating, angle, 1.0)
        cot = np.cos(half) / np.sin(half)
        point = np.where(rotating[..., None], 0.5 * (tn + cot[..., None] * cross(e, tn)), 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            pitch = np.where(rotating, slide / safe[..., 0], np.where(tn_len > 0, np.inf, np.nan))
        return FiniteScrew(e, point, angle, slide, pitch)


def _as_rotation(rotation: object) -> Rotation:
    if isinstance(rotation, Rotation):
        return rotation
    if type(rotation).__name__ == "Rotation" and hasattr(rotation, "as_quat"):
        return Rotation.from_scipy(rotation)
    q = as_float_array(rotation, "rotation")
    if q.ndim == 0 or q.shape[-1] != 4:
        # named as the caller's argument (Rotation.from_quat would name its own `quat`)
        raise InvalidInputError(
            "Expected `rotation` to be a Rotation (poinsot or SciPy) or scalar-first "
            f"quaternions of shape (..., 4), got shape {q.shape}."
        )
    return Rotation.from_quat(q)


def sclerp(a: RigidTransform, b: RigidTransform, s: ArrayLike) -> RigidTransform:
    """Screw linear interpolation: ``a * (a^-1 * b) ** s`` (docs/theory.md §6).

    The body moves from ``a`` (``s = 0``) to ``b`` (``s = 1``) along one screw, at a
    constant rate of rotation and slide: the dual-quaternion ScLERP. ``s`` of any
    shape (with single ``a``, ``b``) or broadcasting with their batch shape.

    Examples
    --------
    >>> a = RigidTransform.identity()
    >>> b = RigidTransform.from_components([0, 0, 2.0], Rotation.from_rotvec([0, 0, np.pi]))
    >>> m = sclerp(a, b, 0.5)
    >>> m.as_components()[0].round(12) + 0.0, float(m.rotation.magnitude()) * 2 / np.pi
    (array([0., 0., 1.]), 1.0)
    """
    if not isinstance(a, RigidTransform) or not isinstance(b, RigidTransform):
        raise InvalidTypeError(
            f"Expected `a` and `b` to be RigidTransform, got {type(a).__name__} and "
            f"{type(b).__name__}."
        )
    sv = as_float_array(s, "s")
    x = (a.inv() * b).as_exp_coords()
    shape = np.broadcast_shapes(sv.shape, a.shape, b.shape)
    step = RigidTransform.from_exp_coords(sv[..., None] * np.broadcast_to(x, shape + (6,)))
    base = RigidTransform(
        Rotation.from_quat(np.broadcast_to(a.rotation.as_quat(), shape + (4,))),
        np.broadcast_to(a._t, shape + (3,)),
    )
    return base * step
