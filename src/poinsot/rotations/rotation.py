"""The :class:`Rotation` facade, :func:`compose` and :func:`slerp` (theory §2-§4).

A :class:`Rotation` is an immutable array of rotations of any leading shape,
stored as unit scalar-first quaternions. It is a thin, documented layer over
the array functions of :mod:`poinsot.quaternion` and the representation modules
(``dcm``, ``rotvec``, ``euler``, ``rodrigues``, ``frames``): the quaternion is
the hub, each representation converts to and from it.

**Conventions** (see ``docs/conventions.md``):

* Active rotations. ``r.apply(v)`` rotates ``v``; equivalently, if ``r`` is the
  attitude of a body B relative to a frame N, it maps body components to N
  components, ``v_n = C_nb v_b`` (theory §2, ``e_k = L o i_k o L~``).
* ``r2 * r1`` is ``r1`` followed by ``r2``, both about the fixed axes (theory §4,
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
* ``r ** n`` accepts an array ``n`` broadcasting with the shape;
* flags (``degrees``, ``scalar_first``, ``canonical``, ``inverse``,
  ``normalize``) must be bools (``degrees="no"`` is a type error, not "true");
  ``r * 3`` raises :class:`~poinsot.InvalidTypeError` with a hint (``apply`` for
  vectors, ``**`` for powers); ``Rotation(q, normalize=False)`` refuses
  quaternions farther than ``UNIT_ATOL`` (1e-10) from unit length instead of
  storing a scaling "rotation".
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Iterable, Iterator, Sequence
from typing import Any, NoReturn

import numpy as np

from .. import _display
from .._typing import ArrayLike, BoolArray, FloatArray
from .._validate import (
    as_bool,
    as_choice,
    as_float_array,
    as_out,
    as_trailing,
    as_vec3,
    plain_floats,
    plain_vec3,
)
from .._vec import length as length_array
from ..errors import InvalidInputError, InvalidTypeError
from . import _scalar as S
from . import dcm, euler, frames, rodrigues
from . import rotvec as rotvec_mod
from ._lazy import big, flat, kernels, one, threaded
from .quaternion import canonical_array as _canonical
from .quaternion import conjugate_array, normalize_array

__all__ = ["Rotation", "compose", "slerp"]


def _as_shape(shape: Any, name: str = "shape") -> tuple[int, ...]:
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


#: ``Rotation(q, normalize=False)`` accepts quaternions whose length differs from 1
#: by at most this (the caller vouches they are unit; they are stored as given).
UNIT_ATOL = 1e-10

_EPS4 = 4.0 * float(np.finfo(np.float64).eps)
_DEG = math.pi / 180.0  # the constants of np.deg2rad / np.rad2deg: same bits
_RAD = 180.0 / math.pi


def _new(values: Sequence[float]) -> Rotation:
    """A single rotation from four trusted Python floats (the short path).

    Its ``(4,)`` array is left writable: no other object shares it (batches are made
    read-only because views share them), no method writes or returns it (``as_quat``
    copies), and ``setflags`` would cost a third of a one-rotation call."""
    q = np.array(values)
    obj = object.__new__(Rotation)
    obj._q = q
    return obj


def _unit4(t: Sequence[float]) -> tuple[float, float, float, float] | None:
    """``q / |q|`` on Python floats as :func:`normalize_array` does it, or ``None`` when
    ``|q|^2`` leaves the range where that is exact (zero, tiny, huge: general path)."""
    w, x, y, z = t
    n2 = w * w + x * x + y * y + z * z
    if not 1e-290 <= n2 <= 1e290:
        return None
    n = math.sqrt(n2)
    if abs(n - 1.0) <= _EPS4:
        return w, x, y, z
    return w / n, x / n, y / n, z / n


_GENERATOR: tuple[int, np.random.Generator] | None = None


def _generator() -> np.random.Generator:
    """The process's generator for ``random(rng=None)``: seeded once from fresh entropy
    (building a Generator costs ~10 us, more than the rotation); a forked child
    reseeds its own, so processes do not repeat each other's rotations."""
    global _GENERATOR
    if _GENERATOR is None or _GENERATOR[0] != os.getpid():
        _GENERATOR = (os.getpid(), np.random.default_rng())
    return _GENERATOR[1]


def _real(x: Any) -> float | None:
    """A Python float for a real number (int/float/NumPy scalar, not bool) that is finite."""
    if type(x) in (float, int, np.float64) and math.isfinite(x):
        return float(x)
    return None


#: seq -> (axes as an intrinsic sequence, extrinsic?, code for to_euler) (short paths)
_SEQS: dict[str, tuple[tuple[int, ...], bool, np.ndarray | None]] = {}


def _seq(seq: Any) -> tuple[tuple[int, ...], bool, np.ndarray | None]:
    """Parsed ``seq`` (cached): its axes as an intrinsic sequence, whether it is
    extrinsic, and for three axes the code ``(i, j, k, extrinsic)`` (int64) of
    :func:`poinsot.rotations._scalar.to_euler` (axes in extrinsic order)."""
    got = _SEQS.get(seq) if type(seq) is str else None
    if got is None:
        axes, intrinsic = euler.parse_sequence(seq)
        ext = axes[::-1] if intrinsic else axes
        code = np.array([*ext, 0 if intrinsic else 1], dtype=np.int64) if len(axes) == 3 else None
        got = (axes if intrinsic else axes[::-1]), not intrinsic, code
        if len(_SEQS) < 256:
            _SEQS[seq] = got
    return got


def _broadcast_shapes(what: str, *shapes: tuple[int, ...]) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(*shapes)
    except ValueError:
        raise InvalidInputError(
            f"Expected the shapes of {what} to broadcast, got {', '.join(map(str, shapes))}."
        ) from None


class Rotation:
    """Rotations in 3D, any leading shape, stored as unit quaternions (theory §2).

    Build one with a ``from_*`` constructor and read it with the matching
    ``as_*`` method; ``r2 * r1`` composes (``r1`` first, fixed axes),
    ``r.apply(v)`` rotates vectors. Immutable.

    Parameters
    ----------
    quat : array_like, shape (..., 4)
        Scalar-first quaternions ``(w, x, y, z)`` (prefer :meth:`from_quat`).
    normalize : bool
        ``True`` (default): ``q / |q|`` is stored. ``False``: the quaternions are
        stored as given, and must be unit to within :data:`UNIT_ATOL` (1e-10 in
        ``| |q| - 1 |``; otherwise :class:`~poinsot.InvalidInputError`): a non-unit
        quaternion would scale the vectors ``apply`` rotates by ``|q|^2``.

    Notes
    -----
    **Empty sets.** As in SciPy, a set of zero rotations (``quat`` of shape
    ``(0, 4)``) is valid: every conversion and ``apply`` return empty arrays of the
    matching shape; only :meth:`mean` raises (an empty set has no mean).

    **One rotation at a time.** A single rotation (shape ``()``) takes a short path
    in plain Python on the same scalar formulas the compiled batch kernels use
    (:mod:`poinsot.rotations._scalar`), with the same checks (type, shape, finite
    values); batches of at least ``PARALLEL_MIN_SIZE`` rotations run on every
    numba thread (:func:`poinsot.rotations.set_num_threads`).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> a = Rotation.from_euler("x", 90, degrees=True)   # theory §4 worked example
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
    #: Recognised by the bottom-layer validators (poinsot._validate), which may not
    #: import this module (imports flow one way: _validate -> rotations).
    _is_poinsot_rotation = True

    def __init__(self, quat: ArrayLike, *, normalize: bool = True) -> None:
        q = as_trailing(quat, "quat", (4,))
        if as_bool(normalize, "normalize"):
            q = normalize_array(q, "quat")  # also rejects zero quaternions
        else:
            err = np.abs(length_array(q) - 1.0)
            if np.any(err > UNIT_ATOL):
                raise InvalidInputError(
                    f"Expected `quat` to be unit quaternions (| |q| - 1 | <= {UNIT_ATOL:g}) "
                    f"with normalize=False, got | |q| - 1 | = {float(np.max(err)):.3g}; "
                    "pass normalize=True to normalise them."
                )
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

    def __getitem__(self, index: Any) -> Rotation:
        if self.single:
            raise InvalidTypeError("A single rotation is not subscriptable.")
        idx = index if isinstance(index, tuple) else (index,)
        return Rotation._wrap(self._q[(*idx, slice(None))])

    def __iter__(self) -> Iterator[Rotation]:
        if self.single:
            raise InvalidTypeError("A single rotation is not iterable.")
        for k in range(len(self)):
            yield self[k]

    def reshape(self, *shape: Any) -> Rotation:
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
        if self._q.ndim > 1 and self._q.shape[0] * self._q[0].size > 16:  # a batch: one line
            first = np.array2string(self._q.reshape(-1, 4)[0], precision=6, separator=", ")
            return f"Rotation(shape={self.shape}, quat[0]={first}, scalar first)"
        return f"Rotation(quat={np.array2string(self._q, precision=6, separator=', ')})"

    @_display.safe_html
    def _repr_html_(self) -> str:
        """Jupyter: quaternion, axis-angle (degrees), ZYX Euler angles and the matrix
        (a batch: its shape and the first rows). Conventions: scalar-first quaternions,
        body -> space; Euler angles intrinsic Z-Y'-X'' (yaw, pitch, roll), degrees."""
        d = _display
        note = "scalar-first quaternion; body -> space; angles in degrees (docs/conventions.md)"
        if self._q.ndim == 1:
            rv = np.asarray(self.as_rotvec(), dtype=float)
            angle = float(np.linalg.norm(rv))
            axis = d.value(rv / angle) if angle > 0 else "any (no rotation)"
            rows = [
                ("quaternion (w, x, y, z)", d.value(self._q)),
                ("axis", axis),
                ("angle", d.value(np.degrees(angle), "deg")),
                (
                    "Euler ZYX (yaw, pitch, roll)",
                    d.value(self.as_euler("ZYX", degrees=True), "deg"),
                ),
                ("matrix", d.matrix(self.as_matrix())),
            ]
            return d.table("Rotation", rows, note)
        flat = self._q.reshape(-1, 4)
        first = Rotation.from_quat(flat[:5])
        ang = np.degrees(np.asarray(first.magnitude(), dtype=float))
        eul = np.asarray(first.as_euler("ZYX", degrees=True), dtype=float)
        cells = [
            [d.esc(k)] + [d.esc(d.num(x)) for x in flat[k]] + [d.esc(d.num(ang[k]))]
            + [d.esc(d.num(x)) for x in eul[k]]
            for k in range(len(ang))
        ]  # fmt: skip
        head = ["#", "w", "x", "y", "z", "angle deg", "yaw deg", "pitch deg", "roll deg"]
        more = f"first {len(ang)} of {flat.shape[0]}" if flat.shape[0] > len(ang) else "all"
        rows = [("shape", d.esc(self.shape)), ("rows", d.esc(more))]
        return d.table("Rotation batch", rows, note, d.grid(head, cells))

    def __reduce__(self) -> tuple[type[Rotation], tuple[np.ndarray]]:
        return (Rotation, (np.array(self._q),))

    # ----------------------------------------------------------- constructors
    @classmethod
    def from_quat(cls, quat: ArrayLike, *, scalar_first: bool = True) -> Rotation:
        """From quaternions (..., 4), normalised; scalar first ``(w, x, y, z)`` by default.

        A zero quaternion raises :class:`~poinsot.InvalidInputError`.

        .. warning:: **SciPy's quaternions are scalar last** ``(x, y, z, w)``:
           ``Rotation.from_quat(scipy_rotation.as_quat())`` silently gives
           *another* rotation. Use :meth:`from_scipy`, or pass
           ``scalar_first=False`` (or ``scipy_rotation.as_quat(scalar_first=True)``).

        Examples
        --------
        >>> Rotation.from_quat([2.0, 0.0, 0.0, 0.0]).as_quat()
        array([1., 0., 0., 0.])
        >>> Rotation.from_quat([0, 0, 0, 1], scalar_first=False).as_quat()
        array([1., 0., 0., 0.])
        """
        first = as_bool(scalar_first, "scalar_first")
        t = plain_floats(quat, 4)
        if t is not None and cls is Rotation:
            u = _unit4(t if first else (t[3], t[0], t[1], t[2]))
            if u is not None:
                return _new(u)
        q = normalize_array(as_trailing(quat, "quat", (4,)), "quat")
        if not first:
            q = np.roll(q, 1, axis=-1)
        return cls._wrap(q)

    @classmethod
    def from_scipy(cls, rotation: Any) -> Rotation:
        """From a :class:`scipy.spatial.transform.Rotation` (one or a batch).

        The same rotations (SciPy's scalar-last quaternions are reordered, so the
        quaternion order trap of :meth:`from_quat` cannot occur); a SciPy batch of
        ``N`` gives shape ``(N,)``, a single SciPy rotation shape ``()``.

        Examples
        --------
        >>> from scipy.spatial.transform import Rotation as SciPyRotation
        >>> r = SciPyRotation.from_euler("z", 90, degrees=True)
        >>> Rotation.from_scipy(r).as_quat().round(6)
        array([0.707107, 0.      , 0.      , 0.707107])
        """
        from scipy.spatial.transform import Rotation as SciPyRotation

        if not isinstance(rotation, SciPyRotation):
            raise InvalidTypeError(
                "Expected `rotation` to be a scipy.spatial.transform.Rotation, "
                f"got {type(rotation).__name__}."
            )
        return cls.from_quat(rotation.as_quat(), scalar_first=False)

    def to_scipy(self) -> Any:
        """The same rotation(s) as a :class:`scipy.spatial.transform.Rotation`.

        SciPy holds one rotation or a 1-D batch: a batch of shape ``(..., )`` with
        more than one axis is flattened (C order).

        Examples
        --------
        >>> r = Rotation.from_rotvec([0.0, 0.0, 0.5])
        >>> bool(abs(r.to_scipy().magnitude() - 0.5) < 1e-15)
        True
        """
        from scipy.spatial.transform import Rotation as SciPyRotation

        q = self.as_quat(scalar_first=False)
        return SciPyRotation.from_quat(q if q.ndim <= 2 else q.reshape(-1, 4))

    @classmethod
    def from_matrix(cls, matrix: ArrayLike, *, atol: float = dcm.ORTHOGONALITY_ATOL) -> Rotation:
        """From direction cosine matrices (..., 3, 3) (theory §2).

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
        if type(matrix) is np.ndarray and matrix.shape == (3, 3) and cls is Rotation:
            t = plain_floats(matrix.ravel(), 9)
            tol = _real(atol)
            if t is not None and tol is not None:
                err, det = S.matrix_check(*t)
                if det > 0.0 and err <= dcm.EXACT_ATOL and err <= tol:  # else: general path
                    return _new(S.from_matrix(*t))
        tol = float(as_float_array(atol, "atol"))
        if tol < 0:
            raise InvalidInputError(f"Expected `atol` to be non-negative, got {atol!r}.")
        return cls._wrap(dcm.quat_from_user_matrix(matrix, "matrix", atol=tol))

    @classmethod
    def from_rotvec(cls, rotvec: ArrayLike, *, degrees: bool = False) -> Rotation:
        """From rotation vectors ``phi = f e`` (..., 3) (theory §2, ``A = exp(phi^)``).

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 180], degrees=True).as_quat().round(12) + 0.0
        array([0., 0., 0., 1.])
        """
        deg = as_bool(degrees, "degrees")
        t = plain_vec3(rotvec)
        if t is not None and cls is Rotation:
            a, b, c = t
            if deg:
                a, b, c = a * _DEG, b * _DEG, c * _DEG
            return _new(S.from_rotvec(a, b, c))
        v = as_vec3(rotvec, "rotvec")
        if deg:
            v = np.deg2rad(v)
        return cls._wrap(rotvec_mod.quat_from_rotvec(v))

    @classmethod
    def from_axis_angle(
        cls, axis: ArrayLike, angle: ArrayLike, *, degrees: bool = False
    ) -> Rotation:
        """From a (not necessarily unit) axis (..., 3) and angle (...), right-handed.

        ``L = cos(f/2) + e sin(f/2)`` with ``e = axis / |axis|`` (theory §2). A zero
        axis raises :class:`~poinsot.InvalidInputError`.

        Examples
        --------
        >>> Rotation.from_axis_angle([0, 0, 2], 90, degrees=True).apply([1, 0, 0]).round(12) + 0.0
        array([0., 1., 0.])
        """
        deg = False if degrees is False else as_bool(degrees, "degrees")
        t, f1 = plain_vec3(axis), _real(angle)
        if t is not None and f1 is not None and cls is Rotation:
            a, b, c = t
            n1 = math.hypot(a, b, c)
            if n1 > 0.0:
                h1 = 0.5 * (f1 * _DEG if deg else f1)
                s = math.sin(h1)
                return _new((math.cos(h1), s * (a / n1), s * (b / n1), s * (c / n1)))
        ax = as_vec3(axis, "axis")
        f = as_float_array(angle, "angle")
        n = length_array(ax)  # no overflow/underflow for huge or tiny axes
        if np.any(n == 0):
            raise InvalidInputError("Expected `axis` to be non-zero vectors, got a zero one.")
        if deg:
            f = np.deg2rad(f)
        shape = _broadcast_shapes("`axis` and `angle`", ax.shape[:-1], f.shape)
        half = 0.5 * f
        q = np.empty((*shape, 4))
        q[..., 0] = np.cos(half)
        q[..., 1:] = np.sin(half)[..., None] * (ax / n[..., None])
        return cls._wrap(q)

    @classmethod
    def from_euler(cls, seq: str, angles: ArrayLike, *, degrees: bool = False) -> Rotation:
        """From Euler/Tait-Bryan angles (theory §3).

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
        ``C = A_z(psi) A_x(theta) A_z(phi)`` (theory §3); extrinsic ``"zxz"`` is
        ``C = A_z(f3) A_x(f2) A_z(f1)``.

        Examples
        --------
        >>> r = Rotation.from_euler("euler", [90, 90, 0], degrees=True)
        >>> r.as_matrix().round(12) + 0.0
        array([[0., 0., 1.],
               [1., 0., 0.],
               [0., 1., 0.]])
        """
        deg = as_bool(degrees, "degrees")
        axes, extrinsic, _ = _seq(seq)
        signs = euler.preset_signs(seq)
        k = len(axes)
        if signs is not None:  # e.g. "ship": the first angle turns the other way
            angles = euler.as_angles(angles, k) * np.asarray(signs)  # shape checked first
        t: Sequence[float] | None = plain_vec3(angles) if k == 3 else None
        if k == 1:
            a0 = _real(angles)
            t = None if a0 is None else (a0, 0.0, 0.0)
        if t is not None and cls is Rotation:
            a0, a1, a2 = t
            if deg:
                a0, a1, a2 = a0 * _DEG, a1 * _DEG, a2 * _DEG
            if extrinsic and k == 3:  # extrinsic abc (f1, f2, f3) = intrinsic CBA (f3, f2, f1)
                a0, a1, a2 = a2, a1, a0
            return _new(S.from_euler(axes, a0, a1, a2))
        a = euler.as_angles(angles, k)
        if deg:
            a = np.deg2rad(a)
        return cls._wrap(euler.quat_from_euler(seq, a))

    @classmethod
    def from_gibbs(cls, gibbs: ArrayLike) -> Rotation:
        """From Gibbs (Rodrigues) vectors ``g = e tan(f/2)`` (..., 3) (theory §2).

        Examples
        --------
        >>> Rotation.from_gibbs([0, 0, 1]).as_rotvec(degrees=True)
        array([ 0.,  0., 90.])
        """
        t = plain_vec3(gibbs)
        if t is not None and cls is Rotation:
            u = _unit4((1.0, *t))
            if u is not None:
                return _new(u)
        return cls._wrap(rodrigues.quat_from_gibbs(as_vec3(gibbs, "gibbs")))

    @classmethod
    def from_mrp(cls, mrp: ArrayLike) -> Rotation:
        """From modified Rodrigues parameters ``p = e tan(f/4)`` (..., 3).

        Examples
        --------
        >>> Rotation.from_mrp([0, 0, 1]).as_rotvec(degrees=True)
        array([  0.,   0., 180.])
        """
        t = plain_vec3(mrp)
        if t is not None and cls is Rotation:
            a, b, c = t
            if a * a + b * b + c * c <= 1e200:  # else the shadow set (general path)
                return _new(S.from_mrp(a, b, c))
        return cls._wrap(rodrigues.quat_from_mrp(as_vec3(mrp, "mrp")))

    @classmethod
    def from_basis(cls, e1: ArrayLike, e2: ArrayLike, e3: ArrayLike) -> Rotation:
        """The rotation taking the reference basis ``i_k`` onto ``e_k`` (theory §2, Theorem 1).

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
    def align_vectors(
        cls,
        a: ArrayLike,
        b: ArrayLike,
        weights: ArrayLike | None = None,
        *,
        return_sensitivity: bool = False,
    ) -> tuple[Rotation, float] | tuple[Rotation, float, FloatArray]:
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
        if type(shape) is tuple and shape == () and cls is Rotation:
            return _new((1.0, 0.0, 0.0, 0.0))
        shape = _as_shape(shape)
        q = np.zeros((*shape, 4))
        q[..., 0] = 1.0
        return cls._wrap(q)

    @classmethod
    def random(
        cls, shape: int | Sequence[int] = (), rng: int | np.random.Generator | None = None
    ) -> Rotation:
        """Rotations uniformly distributed on SO(3) (normalised Gaussian quaternions).

        ``rng``: ``None`` (a generator seeded once per process from fresh entropy,
        as NumPy's global one), a seed or a :class:`numpy.random.Generator`.

        Examples
        --------
        >>> Rotation.random(3, rng=42).shape
        (3,)
        """
        g = _generator() if rng is None else np.random.default_rng(rng)
        if type(shape) is tuple and shape == () and cls is Rotation:
            u = _unit4(g.standard_normal(4).tolist())
            if u is not None:
                return _new(u)
            return cls.random(shape, g)  # pragma: no cover - |q| ~ 0 or huge: never seen
        shape = _as_shape(shape)
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
        if scalar_first is True and canonical is False:
            return self._q.copy()  # any shape: the stored array, unit, scalar first
        first = as_bool(scalar_first, "scalar_first")
        canon = as_bool(canonical, "canonical")
        if self._q.ndim == 1:
            w, x, y, z = self._q.tolist()
            if canon:  # + 0.0: no negative zeros, as the batch path
                w, x, y, z = S.canonical(w, x, y, z)
                w, x, y, z = w + 0.0, x + 0.0, y + 0.0, z + 0.0
            return np.array((w, x, y, z) if first else (x, y, z, w))
        q = _canonical(self._q) + 0.0 if canon else np.array(self._q)
        return q if first else np.roll(q, -1, axis=-1)

    def as_matrix(self, *, out: np.ndarray | None = None) -> np.ndarray:
        """Direction cosine matrices (..., 3, 3): ``A = E + 2 l0 l^ + 2 l^ l^`` (theory §2).

        ``out`` (NumPy's convention): a C-contiguous float64 array of shape
        ``self.shape + (3, 3)`` to write the matrices into; it is returned. Reusing one
        spares a large batch the first touch of a fresh result's pages (about a third
        of the time of 10^6 rotations, docs/performance.md).

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 90], degrees=True).as_matrix().round(12) + 0.0
        array([[ 0., -1.,  0.],
               [ 1.,  0.,  0.],
               [ 0.,  0.,  1.]])
        >>> r = Rotation.random(5, rng=0)
        >>> m = np.empty((5, 3, 3))
        >>> r.as_matrix(out=m) is m, bool(np.all(m == r.as_matrix()))
        (True, True)
        """
        if out is not None:
            out = as_out(out, "out", self._q.shape[:-1] + (3, 3))
        if self._q.ndim == 1:
            m = np.empty((3, 3)) if out is None else out
            one.to_matrix1(self._q, m)
            return m
        return dcm.matrix_from_quat(self._q, out)

    def as_rotvec(self, *, degrees: bool = False) -> np.ndarray:
        """Rotation vectors ``f e`` (..., 3) with ``f in [0, pi]`` (shortest rotation).

        Examples
        --------
        >>> Rotation.from_euler("z", -90, degrees=True).as_rotvec(degrees=True)
        array([  0.,   0., -90.])
        """
        deg = False if degrees is False else as_bool(degrees, "degrees")
        if self._q.ndim == 1:
            v = np.empty(3)
            one.to_rotvec1(self._q, v)
            return v * _RAD if deg else v
        v = rotvec_mod.rotvec_from_quat(self._q)
        return np.rad2deg(v) if deg else v

    def as_axis_angle(self, *, degrees: bool = False) -> tuple[FloatArray, FloatArray | np.float64]:
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
        deg = False if degrees is False else as_bool(degrees, "degrees")
        if self._q.ndim == 1:
            a, b, c, f = S.axis_angle(*S.canonical(*self._q.tolist()))
            return np.array((a, b, c)), np.float64(f * _RAD if deg else f)
        q = _canonical(self._q)
        v = q[..., 1:]
        n = np.sqrt(np.einsum("...i,...i->...", v, v))
        angle = 2.0 * np.arctan2(n, q[..., 0])
        axis = np.where((n > 0)[..., None], v / np.where(n > 0, n, 1.0)[..., None], [1.0, 0.0, 0.0])
        if deg:
            angle = np.rad2deg(angle)
        return axis, angle[()]

    def as_euler(self, seq: str, *, degrees: bool = False) -> np.ndarray:
        """Euler/Tait-Bryan angles (..., 3) in ``[-pi, pi]`` for a 3-axis ``seq`` (theory §3).

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
        deg = as_bool(degrees, "degrees")
        code = _seq(seq)[2]
        signs = euler.preset_signs(seq)
        if self._q.ndim == 1 and code is not None:
            a = np.empty(3)
            if one.to_euler1(self._q, code, a):
                euler.warn_gimbal_lock(seq, stacklevel=2)
        else:
            a = euler.euler_from_quat(seq, self._q)
        if signs is not None:
            a = a * np.asarray(signs)
        return a * _RAD if deg else a

    def as_gibbs(self) -> np.ndarray:
        """Gibbs vectors ``e tan(f/2)`` (..., 3); ``+-inf`` along the axis at ``f = pi``.

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 90], degrees=True).as_gibbs().round(12) + 0.0
        array([0., 0., 1.])
        """
        if self._q.ndim == 1:
            w, x, y, z = S.canonical(*self._q.tolist())
            if w != 0.0:  # (at pi: the general path warns)
                return np.array((x / w, y / w, z / w))
        return rodrigues.gibbs_from_quat(self._q)

    def as_mrp(self) -> np.ndarray:
        """Modified Rodrigues parameters ``e tan(f/4)`` (..., 3), ``|p| <= 1``.

        Examples
        --------
        >>> Rotation.from_rotvec([0, 0, 180], degrees=True).as_mrp().round(12) + 0.0
        array([0., 0., 1.])
        """
        if self._q.ndim == 1:
            p = np.empty(3)
            one.to_mrp1(self._q, p)
            return p
        return rodrigues.mrp_from_quat(self._q)

    # ------------------------------------------------------------- operations
    def __mul__(self, other: Rotation) -> Rotation:
        """``self * other``: ``other`` first, then ``self``, about fixed axes (theory §4)."""
        if not isinstance(other, Rotation):
            _not_composable(other, "r * other")
        p, q = self._q, other._q
        if p.ndim == 1 and q.ndim == 1:
            return _new(S.hamilton(*p.tolist(), *q.tolist()))
        if p.shape != q.shape:
            shape = _broadcast_shapes("the two rotations", p.shape[:-1], q.shape[:-1])
        else:
            shape = p.shape[:-1]
        k = kernels()
        if big(shape) and p.shape[:-1] in (shape, ()) and q.shape[:-1] in (shape, ()):
            out = np.empty(shape + (4,))
            threaded(k.qmul_flat, flat(p, 4), flat(q, 4), out.reshape(-1, 4))
        else:
            out = k.qmul(p, q)
        # `out` is fresh and contiguous: no need for _wrap's copy checks
        out.setflags(write=False)
        obj = object.__new__(Rotation)
        obj._q = out
        return obj

    def __rmul__(self, other: object) -> NoReturn:
        _not_composable(other, "other * r")

    def inv(self) -> Rotation:
        """Inverse rotations (conjugate quaternions).

        Examples
        --------
        >>> r = Rotation.random(rng=1)
        >>> bool((r * r.inv()).magnitude() < 1e-15)
        True
        """
        q = self._q
        if q.ndim == 1:
            out = np.empty(4)
            one.conj1(q, out)  # private and unshared: see _new
            obj = object.__new__(Rotation)
            obj._q = out
            return obj
        if big(q.shape[:-1]):
            out = np.empty(q.shape)
            threaded(kernels().conj_flat, flat(q, 4), out.reshape(-1, 4))
            return Rotation._wrap(out)
        return Rotation._wrap(conjugate_array(q))

    def apply(self, vectors: ArrayLike, *, inverse: bool = False) -> FloatArray:
        """Rotate vectors (..., 3): ``v' = L o v o L~`` (theory §2), or the inverse.

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
        inv = as_bool(inverse, "inverse")
        q = self._q
        if q.ndim == 1:
            t = plain_vec3(vectors)
            if t is not None:
                w, x, y, z = q.tolist()
                if inv:
                    x, y, z = -x, -y, -z
                return np.array(S.rotate(w, x, y, z, *t))
        v = as_vec3(vectors, "vectors")
        shape = self.shape
        if v.shape[:-1] != shape:
            shape = _broadcast_shapes("the rotations and `vectors`", shape, v.shape[:-1])
        k = kernels()
        if big(shape) and self.shape in (shape, ()) and v.shape[:-1] in (shape, ()):
            out = np.empty(shape + (3,))
            threaded(k.qrot_flat, flat(q, 4), flat(v, 3), -1.0 if inv else 1.0, out.reshape(-1, 3))
            return out
        if inv:
            q = conjugate_array(q)
        return k.qrot(q, v)

    def magnitude(self) -> FloatArray | np.float64:
        """Rotation angles in ``[0, pi]`` (radians), ``2 atan2(|l|, |l0|)``.

        Examples
        --------
        >>> float(Rotation.from_rotvec([0, 0.3, 0.4]).magnitude())
        0.5
        """
        q = self._q
        if q.ndim == 1:
            return np.float64(one.angle1(q))
        return rotvec_mod.angle_from_quat(q)[()]

    def __pow__(self, n: ArrayLike) -> Rotation:
        """``r ** n``: the rotation about the same axis by ``n`` times its angle.

        ``n`` a real number (or array broadcasting with the shape); uses the
        shortest rotation (angle in ``[0, pi]``), like SciPy: ``r ** 0.5`` is the
        half-way rotation, ``r ** -1`` the inverse.

        Examples
        --------
        >>> (Rotation.from_rotvec([0, 0, 0.6]) ** 0.5).as_rotvec().round(15)
        array([0. , 0. , 0.3])
        """
        f = _real(n)
        if f is not None and self._q.ndim == 1:
            if f == 1.0:
                return self
            if f == -1.0:
                return self.inv()
            out = np.empty(4)
            one.pow1(self._q, f, out)
            obj = object.__new__(Rotation)
            obj._q = out  # private and unshared: see _new
            return obj
        p = as_float_array(n, "n")
        if p.ndim == 0 and p == 1:
            return self
        if p.ndim == 0 and p == -1:
            return self.inv()
        if p.shape != self.shape:
            _broadcast_shapes("the rotations and `n`", self.shape, p.shape)
        return Rotation._wrap(rotvec_mod.quat_from_rotvec(p[..., None] * self.as_rotvec()))

    def approx_equal(
        self, other: Rotation, *, atol: float | None = None, degrees: bool = False
    ) -> BoolArray | np.bool_:
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
            if as_bool(degrees, "degrees"):
                tol = float(np.deg2rad(tol))
        if self._q.ndim == 1 and other._q.ndim == 1:
            w, x, y, z = other._q.tolist()
            return np.bool_(S.angle(*S.hamilton(w, -x, -y, -z, *self._q.tolist())) <= tol)
        return (other.inv() * self).magnitude() <= tol

    def mean(self, weights: ArrayLike | None = None, axis: Any = None) -> Rotation:
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
        if q.ndim == 1 and weights is None and axis is None:
            return self  # the mean of one rotation (immutable: no copy needed)
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
        m = _outer_sums(qk, wk)
        _, vecs = np.linalg.eigh(m)
        return Rotation._wrap(vecs[..., :, -1])


#: Rotations per partial sum of :func:`_outer_sums` (fixed: no dependence on threads).
_MEAN_CHUNK = 4096
#: (row, column) of the 10 entries :func:`_outer_sums`'s kernel returns.
_UPPER = np.triu_indices(4)


def _outer_sums(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``M = sum_i w_i q_i q_i^T`` (..., 4, 4) over the next-to-last axis of ``q``
    (..., n, 4), ``w`` (..., n): one compiled pass for large sets (partial sums over
    fixed chunks, added in order), NumPy's ``einsum`` otherwise."""
    if not big(q.shape[:-1]):
        return np.einsum("...i,...ij,...ik->...jk", w, q, q)
    lead, n = q.shape[:-2], q.shape[-2]
    qf = np.ascontiguousarray(q).reshape(-1, n, 4)
    wf = np.ascontiguousarray(w, dtype=float).reshape(-1, n)
    parts = np.empty((qf.shape[0], -(-n // _MEAN_CHUNK), 10))
    threaded(kernels().outer_sums_flat, qf, wf, _MEAN_CHUNK, parts)
    upper = parts.sum(axis=1)
    m = np.empty((qf.shape[0], 4, 4))
    m[:, _UPPER[0], _UPPER[1]] = upper
    m[:, _UPPER[1], _UPPER[0]] = upper
    return m.reshape(*lead, 4, 4)


def _as_rotation(r: object, name: str) -> Rotation:
    if not isinstance(r, Rotation):
        kind = type(r)
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot.Rotation, got {kind.__module__}.{kind.__qualname__}"
            " (convert SciPy rotations with Rotation.from_scipy(r))."
            if kind.__name__ == "Rotation"
            else f"Expected `{name}` to be a poinsot.Rotation, got {kind.__name__}."
        )
    return r


def _not_composable(other: object, expr: str) -> NoReturn:
    kind = type(other)
    if kind.__name__ == "Rotation":
        hint = " (convert SciPy rotations with Rotation.from_scipy(r))"
    elif isinstance(other, numbers.Number | np.ndarray):
        hint = " (rotations compose with rotations: use r.apply(v) for vectors, r ** n for powers)"
    else:
        hint = ""
    name = (
        kind.__qualname__
        if kind.__module__ == "builtins"
        else f"{kind.__module__}.{kind.__qualname__}"
    )
    raise InvalidTypeError(f"Expected a poinsot.Rotation in `{expr}`, got {name}{hint}.")


def compose(rotations: Sequence[Rotation] | Rotation, *, axes: str = "fixed") -> Rotation:
    """Compose rotations ``L_1, ..., L_n`` listed in the order they are performed (theory §4).

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


def slerp(r0: Rotation, r1: Rotation, t: ArrayLike) -> Rotation:
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
    f = _real(t)
    if f is not None and r0._q.ndim == 1 and r1._q.ndim == 1:
        w0, x0, y0, z0 = r0._q.tolist()
        w1, x1, y1, z1 = r1._q.tolist()
        a, b, c = S.to_rotvec(*S.canonical(*S.hamilton(w1, x1, y1, z1, w0, -x0, -y0, -z0)))
        step1 = S.from_rotvec(f * a, f * b, f * c)
        return _new(S.hamilton(*step1, w0, x0, y0, z0))
    t = as_float_array(t, "t")
    shape = _broadcast_shapes("`r0`, `r1` and `t`", r0.shape, r1.shape, t.shape)
    delta = (r1 * r0.inv()).as_rotvec()
    step = rotvec_mod.quat_from_rotvec(t[..., None] * delta)
    return Rotation._wrap(kernels().qmul(step, np.broadcast_to(r0._q, (*shape, 4))))
