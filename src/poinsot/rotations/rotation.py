"""The :class:`Rotation` facade, :func:`compose` and :func:`slerp` (SPEC S2-S4).

A :class:`Rotation` is an immutable array of rotations of any leading shape,
stored as unit scalar-first quaternions. It is a thin, documented layer over
the array functions of :mod:`poinsot.quaternion` and the representation modules
(``dcm``, ``rotvec``, ``euler``, ``rodrigues``, ``frames``): the quaternion is
the hub, each representation converts to and from it.

**Conventions** (see ``docs/conventions.md``):

* Active rotations. ``r.apply(v)`` rotates ``v``; equivalently, if ``r`` is the
  attitude of a body B relative to a frame N, it maps body components to N
  components, ``v_n = C_nb v_b`` (SPEC S2, ``e_k = L o i_k o L~``).
* ``r2 * r1`` is ``r1`` followed by ``r2``, both about the fixed axes (SPEC S4,
  "one point of view": ``C = B A``, ``N = M o L``).
* Radians unless ``degrees=True``; quaternions scalar first unless
  ``scalar_first=False``.

**Differences from SciPy's** ``Rotation`` (deliberate; everything else matches
it to a few ulp, see ``tests/rotations/test_parity_scipy.py``):

* scalar-first quaternions by default; keyword-only options
  (``approx_equal(other, atol=...)``, ``as_euler(seq, degrees=...)``);
* ``from_matrix`` rejects matrices farther than ``atol`` (1e-6) from orthogonal
  instead of silently orthogonalising them; ``align_vectors`` raises for fewer
  than two independent pairs (no single-pair or infinite-weight mode);
* one-axis ``from_euler``: a 1-D array is a list of angles, also of length 1
  (SciPy returns a single rotation for ``[a]``), and any shape is accepted;
* gimbal lock: the middle Euler angle is set to its singular value, so the
  round trip loses at most the 1e-7 rad threshold (SciPy: up to 2e-7);
* ``as_mrp`` at exactly pi uses the canonical sign of ``as_rotvec``;
* extreme inputs (quaternions or vectors of size 1e-300 .. 1e300, rotation
  vectors beyond 1e154) are handled where SciPy returns zeros or NaN, and an
  empty set has no mean (SciPy returns the identity for all-zero weights);
* ``r ** n`` accepts an array ``n`` broadcasting with the shape.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence

import numpy as np

from .._validate import as_choice, as_float_array, as_trailing, as_vec3
from ..errors import InvalidInputError, InvalidTypeError
from . import dcm, euler, frames, rodrigues
from . import rotvec as rotvec_mod
from ._lazy import kernels
from .quaternion import canonical_array as _canonical
from .quaternion import conjugate_array, length_array, normalize_array

__all__ = ["Rotation", "compose", "slerp"]


def _as_shape(shape, name: str = "shape") -> tuple[int, ...]:
    """A leading shape: ``None`` or ``()`` (single), an int, or a sequence of ints >= 0."""
    if shape is None:
        return ()
    dims = (shape,) if np.ndim(shape) == 0 else tuple(np.asarray(shape).ravel().tolist())
    for d in dims:
        if isinstance(d, bool) or not isinstance(d, int | np.integer):
            raise InvalidTypeError(
                f"Expected `{name}` to be an int or a tuple of ints, got {shape!r}."
            )
        if d < 0:
            raise InvalidInputError(f"Expected `{name}` to have no negative sizes, got {shape!r}.")
    return tuple(int(d) for d in dims)


def _broadcast_shapes(what: str, *shapes: tuple[int, ...]) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(*shapes)
    except ValueError:
        raise InvalidInputError(
            f"Expected the shapes of {what} to broadcast, got {', '.join(map(str, shapes))}."
        ) from None


class Rotation:
    """Rotations in 3D, any leading shape, stored as unit quaternions (SPEC S2).

    Build one with a ``from_*`` constructor and read it with the matching
    ``as_*`` method; ``r2 * r1`` composes (``r1`` first, fixed axes),
    ``r.apply(v)`` rotates vectors. Immutable.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> a = Rotation.from_euler("x", 90, degrees=True)   # SPEC S4 worked example
    >>> b = Rotation.from_euler("y", 90, degrees=True)
    >>> (b * a).as_matrix().round(12) + 0.0                # C = B A
    array([[ 0.,  1.,  0.],
           [ 0.,  0., -1.],
           [-1.,  0.,  0.]])
    >>> r = Rotation.random((5, 3), rng=0)
    >>> r.shape, len(r), r[0, 1].shape
    ((5, 3), 5, ())
    """

    __slots__ = ("_q",)

    def __init__(self, quat, *, normalize: bool = True):
        q = as_trailing(quat, "quat", (4,))
        n = normalize_array(q, "quat")  # also rejects zero quaternions
        if normalize:
            q = n
        q = np.array(q, dtype=np.float64)
        q.setflags(write=False)
        self._q = q

    @classmethod
    def _wrap(cls, q: np.ndarray) -> Rotation:
        obj = cls.__new__(cls)
        q = np.ascontiguousarray(q, dtype=np.float64)
        q.setflags(write=False)
        obj._q = q
        return obj

    # ------------------------------------------------------------------ shape
    @property
    def shape(self) -> tuple[int, ...]:
        """Leading shape (``()`` for a single rotation)."""
        return self._q.shape[:-1]

    @property
    def single(self) -> bool:
        """``True`` for a single rotation (shape ``()``)."""
        return self._q.ndim == 1

    def __len__(self) -> int:
        if self.single:
            raise InvalidTypeError("A single rotation has no len().")
        return self._q.shape[0]

    def __getitem__(self, index) -> Rotation:
        if self.single:
            raise InvalidTypeError("A single rotation is not subscriptable.")
        idx = index if isinstance(index, tuple) else (index,)
        return Rotation._wrap(self._q[(*idx, slice(None))])

    def __iter__(self) -> Iterator[Rotation]:
        if self.single:
            raise InvalidTypeError("A single rotation is not iterable.")
        for k in range(len(self)):
            yield self[k]

    def reshape(self, *shape) -> Rotation:
        """A view with another leading shape."""
        if len(shape) == 1 and isinstance(shape[0], tuple | list):
            shape = tuple(shape[0])
        try:
            return Rotation._wrap(self._q.reshape(*shape, 4))
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"Expected a shape with {int(np.prod(self.shape))} rotations, got {shape!r}."
            ) from None

    def __repr__(self) -> str:
        if self._q.size == 0:
            return f"Rotation(quat=np.empty({self._q.shape}))"
        return f"Rotation(quat={np.array2string(self._q, precision=6, separator=', ')})"

    def __reduce__(self):
        return (Rotation, (np.array(self._q),))

    # ----------------------------------------------------------- constructors
    @classmethod
    def from_quat(cls, quat, *, scalar_first: bool = True) -> Rotation:
        """From quaternions (..., 4), normalised; scalar first ``(w, x, y, z)`` by default.

        A zero quaternion raises :class:`~poinsot.InvalidInputError`.

        Examples
        --------
        >>> Rotation.from_quat([2.0, 0.0, 0.0, 0.0]).as_quat()
        array([1., 0., 0., 0.])
        >>> Rotation.from_quat([0, 0, 0, 1], scalar_first=False).as_quat()
        array([1., 0., 0., 0.])
        """
        q = normalize_array(as_trailing(quat, "quat", (4,)), "quat")
        if not scalar_first:
            q = np.roll(q, 1, axis=-1)
        return cls._wrap(q)

    @classmethod
    def from_matrix(cls, matrix, *, atol: float = dcm.ORTHOGONALITY_ATOL) -> Rotation:
        """From direction cosine matrices (..., 3, 3) (SPEC S2).

        Determinant must be > 0; the matrix must be orthogonal within ``atol``
        (``max |A^T A - E|``). Matrices orthogonal to within
        ``dcm.EXACT_ATOL = 1e-14`` are converted exactly (largest-square-first
        formula, machine precision); others are first projected onto the nearest
        rotation (SVD).

        Examples
        --------
        >>> Rotation.from_matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]).as_rotvec(degrees=True)
        array([ 0.,  0., 90.])
        """
        tol = float(as_float_array(atol, "atol"))
        if tol < 0:
            raise InvalidInputError(f"Expected `atol` to be non-negative, got {atol!r}.")
        return cls._wrap(dcm.quat_from_user_matrix(matrix, "matrix", atol=tol))

    @classmethod
    def from_rotvec(cls, rotvec, *, degrees: bool = False) -> Rotation:
        """From rotation vectors ``phi = f e`` (..., 3) (SPEC S2, ``A = exp(phi^)``).

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 180], degrees=True).as_quat().round(12) + 0.0
        array([0., 0., 0., 1.])
        """
        v = as_vec3(rotvec, "rotvec")
        if degrees:
            v = np.deg2rad(v)
        return cls._wrap(rotvec_mod.quat_from_rotvec(v))

    @classmethod
    def from_axis_angle(cls, axis, angle, *, degrees: bool = False) -> Rotation:
        """From a (not necessarily unit) axis (..., 3) and angle (...), right-handed.

        ``L = cos(f/2) + e sin(f/2)`` with ``e = axis / |axis|`` (SPEC S2). A zero
        axis raises :class:`~poinsot.InvalidInputError`.

        Examples
        --------
        >>> Rotation.from_axis_angle([0, 0, 2], 90, degrees=True).apply([1, 0, 0]).round(12) + 0.0
        array([0., 1., 0.])
        """
        ax = as_vec3(axis, "axis")
        f = as_float_array(angle, "angle")
        n = length_array(ax)  # no overflow/underflow for huge or tiny axes
        if np.any(n == 0):
            raise InvalidInputError("Expected `axis` to be non-zero vectors, got a zero one.")
        if degrees:
            f = np.deg2rad(f)
        shape = _broadcast_shapes("`axis` and `angle`", ax.shape[:-1], f.shape)
        half = 0.5 * f
        q = np.empty((*shape, 4))
        q[..., 0] = np.cos(half)
        q[..., 1:] = np.sin(half)[..., None] * (ax / n[..., None])
        return cls._wrap(q)

    @classmethod
    def from_euler(cls, seq: str, angles, *, degrees: bool = False) -> Rotation:
        """From Euler/Tait-Bryan angles (SPEC S3).

        Parameters
        ----------
        seq : str
            1 to 3 axes: ``"ZXZ"`` intrinsic (about moving axes), ``"zxz"``
            extrinsic (about fixed axes), as SciPy reads them; or a preset
            ``"euler"`` (= ``"ZXZ"``: precession, nutation, spin) or ``"krylov"``
            (= ``"ZXY"``: heading, pitch, roll).
        angles : array_like, shape (..., len(seq)) (or (...) for one axis)
        degrees : bool

        Notes
        -----
        **Convention:** intrinsic ``"ZXZ"`` with ``(psi, theta, phi)`` is
        ``C = A_z(psi) A_x(theta) A_z(phi)`` (SPEC S3); extrinsic ``"zxz"`` is
        ``C = A_z(f3) A_x(f2) A_z(f1)``.

        Examples
        --------
        >>> r = Rotation.from_euler("euler", [90, 90, 0], degrees=True)
        >>> r.as_matrix().round(12) + 0.0
        array([[0., 0., 1.],
               [1., 0., 0.],
               [0., 1., 0.]])
        """
        axes, _ = euler.parse_sequence(seq)
        a = euler.as_angles(angles, len(axes))
        if degrees:
            a = np.deg2rad(a)
        return cls._wrap(euler.quat_from_euler(seq, a))

    @classmethod
    def from_gibbs(cls, gibbs) -> Rotation:
        """From Gibbs (Rodrigues) vectors ``g = e tan(f/2)`` (..., 3) (SPEC S2).

        Examples
        --------
        >>> Rotation.from_gibbs([0, 0, 1]).as_rotvec(degrees=True)
        array([ 0.,  0., 90.])
        """
        return cls._wrap(rodrigues.quat_from_gibbs(as_vec3(gibbs, "gibbs")))

    @classmethod
    def from_mrp(cls, mrp) -> Rotation:
        """From modified Rodrigues parameters ``p = e tan(f/4)`` (..., 3).

        Examples
        --------
        >>> Rotation.from_mrp([0, 0, 1]).as_rotvec(degrees=True)
        array([  0.,   0., 180.])
        """
        return cls._wrap(rodrigues.quat_from_mrp(as_vec3(mrp, "mrp")))

    @classmethod
    def from_basis(cls, e1, e2, e3) -> Rotation:
        """The rotation taking the reference basis ``i_k`` onto ``e_k`` (SPEC S2, Theorem 1).

        ``e_k = L o i_k o L~``; the ``e_k`` (each (..., 3)) must be orthonormal
        and right-handed within ``dcm.ORTHOGONALITY_ATOL`` (projected if needed).
        Every degenerate case of the theorem (a fixed basis vector, rotations by
        pi, the identity) is handled by picking the best-conditioned pair.

        Examples
        --------
        >>> r = Rotation.from_basis([0, 1, 0], [-1, 0, 0], [0, 0, 1])
        >>> r.as_rotvec(degrees=True)
        array([ 0.,  0., 90.])
        """
        return cls._wrap(frames.quat_from_basis(e1, e2, e3))

    @classmethod
    def align_vectors(cls, a, b, weights=None, *, return_sensitivity: bool = False):
        """Solve Wahba's problem: the rotation ``R`` minimising ``sum w_i |a_i - R b_i|^2``.

        Same argument order as SciPy (``a ~ R b``). Returns ``(R, rssd)`` with
        ``rssd = sqrt(sum w_i |a_i - R b_i|^2)``, and SciPy's sensitivity matrix
        (3, 3) as a third value if ``return_sensitivity=True``. Needs two or more
        linearly independent pairs (with non-zero weight) and finite weights:
        unlike SciPy there is no single-pair or infinite-weight mode, an
        undetermined rotation raises :class:`~poinsot.InvalidInputError`.

        Examples
        --------
        >>> r, rssd = Rotation.align_vectors([[0, 1, 0], [0, 0, 1]], [[1, 0, 0], [0, 0, 1]])
        >>> r.as_rotvec(degrees=True).round(9) + 0.0, round(rssd, 12)
        (array([ 0.,  0., 90.]), 0.0)
        """
        out = frames.align_vectors(a, b, weights, return_sensitivity=return_sensitivity)
        return (cls._wrap(dcm.quat_from_matrix(out[0])), *out[1:])

    @classmethod
    def identity(cls, shape: int | Sequence[int] = ()) -> Rotation:
        """Identity rotations of the given leading shape.

        Examples
        --------
        >>> Rotation.identity(2).as_quat()
        array([[1., 0., 0., 0.],
               [1., 0., 0., 0.]])
        """
        shape = _as_shape(shape)
        q = np.zeros((*shape, 4))
        q[..., 0] = 1.0
        return cls._wrap(q)

    @classmethod
    def random(cls, shape: int | Sequence[int] = (), rng=None) -> Rotation:
        """Rotations uniformly distributed on SO(3) (normalised Gaussian quaternions).

        ``rng``: ``None``, a seed or a :class:`numpy.random.Generator`.

        Examples
        --------
        >>> Rotation.random(3, rng=42).shape
        (3,)
        """
        shape = _as_shape(shape)
        g = np.random.default_rng(rng)
        q = g.standard_normal((*shape, 4))
        return cls._wrap(q / np.linalg.norm(q, axis=-1, keepdims=True))

    @classmethod
    def concatenate(cls, rotations: Iterable[Rotation]) -> Rotation:
        """Join rotations along the first axis (single rotations count as length 1).

        Examples
        --------
        >>> Rotation.concatenate([Rotation.identity(), Rotation.identity(2)]).shape
        (3,)
        """
        if isinstance(rotations, Rotation):
            rotations = [rotations]
        qs = [np.atleast_2d(_as_rotation(r, "rotations")._q) for r in rotations]
        if not qs:
            raise InvalidInputError("Expected `rotations` to contain at least one rotation.")
        tails = {q.shape[1:] for q in qs}
        if len(tails) > 1:
            shapes = [q.shape[:-1] for q in qs]
            raise InvalidInputError(
                "Expected `rotations` to have the same shape after the first axis, "
                f"got shapes {shapes}."
            )
        return cls._wrap(np.concatenate(qs, axis=0))

    # ----------------------------------------------------------------- output
    def as_quat(self, *, scalar_first: bool = True, canonical: bool = False) -> np.ndarray:
        """Unit quaternions (..., 4); ``canonical=True`` picks the sign with ``w > 0``.

        (When ``w = 0``, the first non-zero component is made positive.)

        Examples
        --------
        >>> Rotation.from_quat([-1.0, 0, 0, 0]).as_quat(canonical=True)
        array([1., 0., 0., 0.])
        >>> Rotation.identity().as_quat(scalar_first=False)
        array([0., 0., 0., 1.])
        """
        q = _canonical(self._q) + 0.0 if canonical else np.array(self._q)
        return q if scalar_first else np.roll(q, -1, axis=-1)

    def as_matrix(self) -> np.ndarray:
        """Direction cosine matrices (..., 3, 3): ``A = E + 2 l0 l^ + 2 l^ l^`` (SPEC S2).

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 90], degrees=True).as_matrix().round(12) + 0.0
        array([[ 0., -1.,  0.],
               [ 1.,  0.,  0.],
               [ 0.,  0.,  1.]])
        """
        return dcm.matrix_from_quat(self._q)

    def as_rotvec(self, *, degrees: bool = False) -> np.ndarray:
        """Rotation vectors ``f e`` (..., 3) with ``f in [0, pi]`` (shortest rotation).

        Examples
        --------
        >>> Rotation.from_euler("z", -90, degrees=True).as_rotvec(degrees=True)
        array([  0.,   0., -90.])
        """
        v = rotvec_mod.rotvec_from_quat(self._q)
        return np.rad2deg(v) if degrees else v

    def as_axis_angle(self, *, degrees: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Unit axis (..., 3) and angle (...) in ``[0, pi]``.

        For the identity (angle 0) the axis is undetermined and ``(1, 0, 0)`` is
        returned. At exactly pi the axis sign is that of :meth:`as_rotvec` (first
        non-zero component positive, as SciPy's canonical quaternion).

        Examples
        --------
        >>> axis, angle = Rotation.from_rotvec([0, 0, -0.5]).as_axis_angle()
        >>> axis + 0.0, float(angle)
        (array([ 0.,  0., -1.]), 0.5)
        """
        q = _canonical(self._q)
        v = q[..., 1:]
        n = np.sqrt(np.einsum("...i,...i->...", v, v))
        angle = 2.0 * np.arctan2(n, q[..., 0])
        axis = np.where((n > 0)[..., None], v / np.where(n > 0, n, 1.0)[..., None], [1.0, 0.0, 0.0])
        if degrees:
            angle = np.rad2deg(angle)
        return axis, angle[()]

    def as_euler(self, seq: str, *, degrees: bool = False) -> np.ndarray:
        """Euler/Tait-Bryan angles (..., 3) in ``[-pi, pi]`` for a 3-axis ``seq`` (SPEC S3).

        See :meth:`from_euler` for sequences and presets. The middle angle is in
        ``[0, pi]`` (proper Euler) or ``[-pi/2, pi/2]`` (Tait-Bryan). At gimbal
        lock (middle angle within ``1e-7`` rad of singular) a
        :class:`~poinsot.GimbalLockWarning` is issued, the third angle is set to 0,
        the first holds the sum/difference and the middle one is set to its
        singular value, so the angles reproduce the rotation to within 1e-7 rad.

        Examples
        --------
        >>> r = Rotation.from_euler("ZXZ", [10, 20, 30], degrees=True)
        >>> r.as_euler("euler", degrees=True).round(10)
        array([10., 20., 30.])
        """
        a = euler.euler_from_quat(seq, self._q)
        return np.rad2deg(a) if degrees else a

    def as_gibbs(self) -> np.ndarray:
        """Gibbs vectors ``e tan(f/2)`` (..., 3); ``+-inf`` along the axis at ``f = pi``.

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 90], degrees=True).as_gibbs().round(12) + 0.0
        array([0., 0., 1.])
        """
        return rodrigues.gibbs_from_quat(self._q)

    def as_mrp(self) -> np.ndarray:
        """Modified Rodrigues parameters ``e tan(f/4)`` (..., 3), ``|p| <= 1``.

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 180], degrees=True).as_mrp().round(12) + 0.0
        array([0., 0., 1.])
        """
        return rodrigues.mrp_from_quat(self._q)

    # ------------------------------------------------------------- operations
    def __mul__(self, other) -> Rotation:
        """``self * other``: ``other`` first, then ``self``, about fixed axes (SPEC S4)."""
        if not isinstance(other, Rotation):
            return NotImplemented
        p, q = self._q, other._q
        if p.shape != q.shape:
            _broadcast_shapes("the two rotations", p.shape[:-1], q.shape[:-1])
        k = kernels()
        out = k.qmul1(p, q) if p.ndim == 1 and q.ndim == 1 else k.qmul(p, q)
        # `out` is fresh and contiguous: no need for _wrap's copy checks
        out.flags.writeable = False
        obj = object.__new__(Rotation)
        obj._q = out
        return obj

    def inv(self) -> Rotation:
        """Inverse rotations (conjugate quaternions).

        Examples
        --------
        >>> r = Rotation.random(rng=1)
        >>> bool((r * r.inv()).magnitude() < 1e-15)
        True
        """
        return Rotation._wrap(conjugate_array(self._q))

    def apply(self, vectors, *, inverse: bool = False) -> np.ndarray:
        """Rotate vectors (..., 3): ``v' = L o v o L~`` (SPEC S2), or the inverse.

        Rotation and vector leading shapes broadcast. **Convention:** if the
        rotation is the attitude ``C_nb`` of a body, ``apply`` maps body
        components to reference components and ``inverse=True`` the reverse.

        Examples
        --------
        >>> r = Rotation.from_rotvec([0, 0, 90], degrees=True)
        >>> r.apply([[1, 0, 0], [0, 1, 0]]).round(12) + 0.0
        array([[ 0.,  1.,  0.],
               [-1.,  0.,  0.]])
        """
        v = as_vec3(vectors, "vectors")
        if v.shape[:-1] != self.shape:
            _broadcast_shapes("the rotations and `vectors`", self.shape, v.shape[:-1])
        q = conjugate_array(self._q) if inverse else self._q
        return kernels().qrot(q, v)

    def magnitude(self) -> np.ndarray:
        """Rotation angles in ``[0, pi]`` (radians), ``2 atan2(|l|, |l0|)``.

        Examples
        --------
        >>> float(Rotation.from_rotvec([0, 0.3, 0.4]).magnitude())
        0.5
        """
        q = self._q
        return (2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0])))[()]

    def __pow__(self, n) -> Rotation:
        """``r ** n``: the rotation about the same axis by ``n`` times its angle.

        ``n`` a real number (or array broadcasting with the shape); uses the
        shortest rotation (angle in ``[0, pi]``), like SciPy: ``r ** 0.5`` is the
        half-way rotation, ``r ** -1`` the inverse.

        Examples
        --------
        >>> (Rotation.from_rotvec([0, 0, 0.6]) ** 0.5).as_rotvec().round(15)
        array([0. , 0. , 0.3])
        """
        p = as_float_array(n, "n")
        if p.ndim == 0 and p == 1:
            return self
        if p.ndim == 0 and p == -1:
            return self.inv()
        if p.shape != self.shape:
            _broadcast_shapes("the rotations and `n`", self.shape, p.shape)
        return Rotation._wrap(rotvec_mod.quat_from_rotvec(p[..., None] * self.as_rotvec()))

    def approx_equal(self, other: Rotation, *, atol=None, degrees: bool = False) -> np.ndarray:
        """Whether the rotations differ by an angle ``<= atol`` (q and -q are equal).

        ``atol`` is in radians (degrees if ``degrees=True``); ``None`` means 1e-8
        rad, as in SciPy. Shapes broadcast.

        Examples
        --------
        >>> r = Rotation.random(rng=2)
        >>> bool(r.approx_equal(Rotation.from_quat(-r.as_quat())))
        True
        """
        other = _as_rotation(other, "other")
        if atol is None:
            tol = 1e-8
        else:
            tol = float(as_float_array(atol, "atol"))  # type/finiteness named
            if tol < 0:
                raise InvalidInputError(f"Expected `atol` to be non-negative, got {atol!r}.")
            if degrees:
                tol = float(np.deg2rad(tol))
        return (other.inv() * self).magnitude() <= tol

    def mean(self, weights=None, axis=None) -> Rotation:
        """Chordal L2 mean (Markley et al. 2007), over all rotations or along ``axis``.

        The quaternion maximising ``sum w_i (q . q_i)^2``: the eigenvector of the
        largest eigenvalue of ``M = sum w_i q_i q_i^T`` (insensitive to q/-q).
        ``weights`` (non-negative, not all zero) broadcast to the rotations'
        shape; ``axis`` (int or tuple, default all) as in SciPy. An empty set
        raises :class:`~poinsot.InvalidInputError`.

        Examples
        --------
        >>> r = Rotation.from_rotvec([[0, 0, 0.1], [0, 0, -0.1]])
        >>> r.mean().as_rotvec().round(15) + 0.0
        array([0., 0., 0.])
        """
        q, shape = self._q, self.shape
        nd = len(shape)
        if axis is None:
            axes = tuple(range(nd))
        else:
            raw = (axis,) if np.ndim(axis) == 0 else tuple(axis)
            if not all(isinstance(a, int | np.integer) and not isinstance(a, bool) for a in raw):
                raise InvalidTypeError(
                    f"Expected `axis` to be an int or a tuple of ints, got {axis!r}."
                )
            if any(not -nd <= a < nd for a in raw):
                raise InvalidInputError(
                    f"Expected `axis` within the rotations' {nd} dimensions, got {axis!r}."
                )
            axes = tuple(sorted({int(a) % nd for a in raw}))
        kept = tuple(k for k in range(nd) if k not in axes)
        if weights is None:
            w = np.ones(shape)
        else:
            w = as_float_array(weights, "weights")
            try:
                w = np.broadcast_to(w, shape)
            except ValueError:
                raise InvalidInputError(
                    f"Expected `weights` to broadcast to the rotations' shape {shape}, "
                    f"got {w.shape}."
                ) from None
            if np.any(w < 0):
                raise InvalidInputError("Expected `weights` to be non-negative.")
        kept_shape = tuple(shape[k] for k in kept)
        n = int(np.prod([shape[k] for k in axes]))
        if n == 0:
            raise InvalidInputError("Expected at least one rotation to average, got none.")
        qk = np.transpose(q, (*kept, *axes, nd)).reshape(*kept_shape, n, 4)
        wk = np.transpose(w, (*kept, *axes)).reshape(*kept_shape, n)
        if np.any(np.sum(wk, axis=-1) == 0):
            raise InvalidInputError("Expected `weights` not to be all zero.")
        m = np.einsum("...i,...ij,...ik->...jk", wk, qk, qk)
        _, vecs = np.linalg.eigh(m)
        return Rotation._wrap(vecs[..., :, -1])


def _as_rotation(r, name: str) -> Rotation:
    if not isinstance(r, Rotation):
        kind = type(r)
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot.Rotation, got {kind.__module__}.{kind.__qualname__}"
            " (convert SciPy rotations with Rotation.from_quat(r.as_quat(scalar_first=True)))."
            if kind.__name__ == "Rotation"
            else f"Expected `{name}` to be a poinsot.Rotation, got {kind.__name__}."
        )
    return r


def compose(rotations: Sequence[Rotation] | Rotation, *, axes: str = "fixed") -> Rotation:
    """Compose rotations ``L_1, ..., L_n`` listed in the order they are performed (SPEC S4).

    Parameters
    ----------
    rotations : sequence of Rotation, or a Rotation whose first axis lists them
        (a single Rotation is returned as is)
    axes : {"fixed", "body"}
        ``"fixed"`` (one point of view): each rotation is about the fixed axes,
        ``N = L_n o ... o L_1`` (``C = A_n ... A_1``). ``"body"`` (two points of
        view): each rotation is about the axes of the frame it acts on (body
        axes), ``N = L_1 o ... o L_n`` (``C = A_1 ... A_n``).

    Examples
    --------
    >>> a = Rotation.from_euler("x", 90, degrees=True)
    >>> b = Rotation.from_euler("y", 90, degrees=True)
    >>> compose([a, b], axes="fixed").as_matrix().round(12) + 0.0   # C = B A
    array([[ 0.,  1.,  0.],
           [ 0.,  0., -1.],
           [-1.,  0.,  0.]])
    >>> bool(compose([a, b], axes="body").approx_equal(a * b))
    True
    """
    as_choice(axes, "axes", ("fixed", "body"))
    if isinstance(rotations, Rotation) and rotations.single:
        return rotations
    items = list(rotations)
    if not items:
        raise InvalidInputError("Expected `rotations` to contain at least one rotation.")
    out = _as_rotation(items[0], "rotations")
    for r in items[1:]:
        r = _as_rotation(r, "rotations")
        out = r * out if axes == "fixed" else out * r
    return out


def slerp(r0: Rotation, r1: Rotation, t) -> Rotation:
    """Spherical linear interpolation ``r(t) = (r1 r0^-1)^t r0`` along the shortest arc.

    ``t = 0`` gives ``r0``, ``t = 1`` gives ``r1``; ``t`` (any shape) broadcasts
    with the rotations' shapes; angular velocity is constant in between.

    Examples
    --------
    >>> r0 = Rotation.identity()
    >>> r1 = Rotation.from_rotvec([0, 0, 1.0])
    >>> slerp(r0, r1, [0.0, 0.25, 1.0]).as_rotvec().round(15)[:, 2]
    array([0.  , 0.25, 1.  ])
    """
    r0, r1 = _as_rotation(r0, "r0"), _as_rotation(r1, "r1")
    t = as_float_array(t, "t")
    shape = _broadcast_shapes("`r0`, `r1` and `t`", r0.shape, r1.shape, t.shape)
    delta = (r1 * r0.inv()).as_rotvec()
    step = rotvec_mod.quat_from_rotvec(t[..., None] * delta)
    return Rotation._wrap(kernels().qmul(step, np.broadcast_to(r0._q, (*shape, 4))))
