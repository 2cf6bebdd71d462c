"""Input validation at the public entry points.

Every public function turns its array arguments into float64 NumPy arrays here,
so that a wrong shape, a non-numeric or a non-finite value is reported with the
argument's name and what was expected, e.g.
``Expected `quat` to have shape (..., 4), got (3,).`` Internal kernels then
trust their inputs (no validation inside hot loops).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Collection, Sequence
from typing import Any

import numpy as np

from ._typing import BoolArray, FloatArray
from ._vec import length, unit
from .errors import InvalidInputError, InvalidTypeError

__all__ = [
    "as_float_array",
    "as_trailing",
    "as_out",
    "as_quat",
    "as_vec3",
    "as_matrix3",
    "as_positive",
    "as_bool",
    "read_regular_file",
    "plain_vec3",
    "plain_floats",
    "as_choice",
    "as_int",
    "as_times",
    "as_rotation_quat",
    "batch_shape",
    "check_rotation_matrix",
    "ROTATION_MATRIX_ATOL",
]

#: The ONE rotation-matrix tolerance of poinsot: a user matrix is a rotation when
#: ``max |S^T S - E| <= 1e-6`` (absolute) and ``det S > 0``. 1e-6 accepts matrices
#: typed with six or more significant digits (``0.707107``) and rejects anything
#: that is not a rotation; it equals ``poinsot.rotations.dcm.ORTHOGONALITY_ATOL``
#: (``Rotation.from_matrix``, which then projects onto the nearest rotation).
ROTATION_MATRIX_ATOL = 1e-6


def _shape_str(tail: Sequence[int | None]) -> str:
    parts = ["..."] + ["n" if d is None else str(d) for d in tail]
    return "(" + ", ".join(parts) + ")"


def as_float_array(x: object, name: str, *, finite: bool = True) -> FloatArray:
    """Convert ``x`` to a float64 array, checking it is numeric (and finite)."""
    if isinstance(x, str | bytes):
        raise InvalidTypeError(f"Expected `{name}` to be array-like of numbers, got a string.")
    if x is None:
        raise InvalidTypeError(f"Expected `{name}` to be array-like of numbers, got None.")
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(
            f"Expected `{name}` to be array-like of real numbers, got {type(x).__name__}: {exc}"
        ) from None
    if finite and not np.all(np.isfinite(a)):
        raise InvalidInputError(f"Expected `{name}` to contain only finite values (no NaN/inf).")
    return a


def as_trailing(
    x: object, name: str, tail: Sequence[int | None], *, finite: bool = True
) -> FloatArray:
    """Array with trailing shape ``tail`` (``None`` = any length) and any leading shape."""
    a = as_float_array(x, name, finite=finite)
    k = len(tail)
    ok = a.ndim >= k and all(
        t is None or s == t for s, t in zip(a.shape[a.ndim - k :], tail, strict=True)
    )
    if not ok:
        raise InvalidInputError(
            f"Expected `{name}` to have shape {_shape_str(tail)}, got {a.shape}."
        )
    return a


def as_out(out: object, name: str, shape: tuple[int, ...]) -> FloatArray:
    """An ``out=`` argument (NumPy's convention): a float64 array of exactly ``shape``,
    C-contiguous, aligned and writeable, which the result is written into.

    >>> import numpy as np
    >>> as_out(np.empty((2, 3, 3)), "out", (2, 3, 3)).shape
    (2, 3, 3)
    >>> as_out(np.empty((3, 3), dtype=np.float32), "out", (3, 3))
    Traceback (most recent call last):
    ...
    poinsot.errors.InvalidTypeError: Expected `out` to be a float64 array, got dtype float32.
    """
    if not isinstance(out, np.ndarray):
        raise InvalidTypeError(f"Expected `{name}` to be a NumPy array, got {type(out).__name__}.")
    if out.dtype != np.float64:
        raise InvalidTypeError(f"Expected `{name}` to be a float64 array, got dtype {out.dtype}.")
    if out.shape != shape:
        raise InvalidInputError(f"Expected `{name}` to have shape {shape}, got {out.shape}.")
    flags = out.flags
    for ok, what in (
        (flags.c_contiguous, "C-contiguous"),
        (flags.aligned, "aligned"),
        (flags.writeable, "writeable"),
    ):
        if not ok:
            raise InvalidInputError(f"Expected `{name}` to be a {what} array, got one that is not.")
    return out


def as_quat(q: object, name: str = "quat", *, normalize: bool = True) -> FloatArray:
    """Quaternions of shape ``(..., 4)``, scalar first; non-zero; normalised if asked."""
    a = as_trailing(q, name, (4,))
    n = length(a)  # overflow/underflow-free: (1e200, 1e200, 0, 0) is a valid quaternion
    if np.any(n == 0.0):
        raise InvalidInputError(f"Expected `{name}` to be non-zero quaternions, got a zero one.")
    if normalize:
        a = unit(a, n)
    return a


def as_vec3(v: object, name: str) -> FloatArray:
    """3-vectors of shape ``(..., 3)``."""
    return as_trailing(v, name, (3,))


def as_matrix3(m: object, name: str) -> FloatArray:
    """3x3 matrices of shape ``(..., 3, 3)``."""
    return as_trailing(m, name, (3, 3))


def as_positive(x: object, name: str, *, strict: bool = True) -> FloatArray:
    """Real numbers that must be > 0 (or >= 0 if ``strict=False``)."""
    a = as_float_array(x, name)
    bad = a <= 0 if strict else a < 0
    if np.any(bad):
        word = "positive" if strict else "non-negative"
        raise InvalidInputError(
            f"Expected `{name}` to be {word}, got {float(a[bad].ravel()[0])!r}."
        )
    return a


_SCALAR_TYPES = (float, int, np.float64)


def plain_vec3(x: Any) -> list[float] | None:
    """Short path for one 3-vector: ``[a, b, c]`` as Python floats when ``x`` is a list or
    tuple of three real numbers (not bools) or a float64 array of shape ``(3,)``, all
    finite; else ``None`` (the caller then takes its general, validating path, which
    reports the error). Used where one state must cost about what NumPy costs.

    >>> plain_vec3([1, 2.5, 3.0]), plain_vec3([1.0, float("nan"), 0.0])
    ([1.0, 2.5, 3.0], None)
    """
    return plain_floats(x, 3)


def plain_floats(x: Any, n: int) -> list[float] | None:
    """Short path for one ``n``-vector (a quaternion, a flattened 3x3 matrix...): a list
    of ``n`` finite Python floats when ``x`` is a float64 array of shape ``(n,)``, or a
    list/tuple of ``n`` real numbers (not bools); else ``None`` (the caller then takes
    its general, validating path, which reports the error). The finiteness check is
    one ``isfinite`` of the sum (NaN/inf propagate; a sum that merely overflows sends
    the caller to its general path, never to a wrong answer).

    >>> plain_floats([1, 0.0, 0.0, 0.0], 4), plain_floats((1.0, float("inf")), 2)
    ([1.0, 0.0, 0.0, 0.0], None)
    """
    if type(x) is np.ndarray:
        if x.shape != (n,) or x.dtype != np.float64:
            return None
        t = x.tolist()
    elif type(x) in (list, tuple) and len(x) == n:
        for e in x:
            if type(e) not in _SCALAR_TYPES:
                return None
        t = [float(e) for e in x]
    else:
        return None
    return t if math.isfinite(sum(t)) else None


def as_bool(value: object, name: str) -> bool:
    """A Python or NumPy bool (e.g. ``degrees``); anything else is a type error."""
    if not isinstance(value, bool | np.bool_):
        raise InvalidTypeError(f"Expected `{name}` to be a bool, got {value!r}.")
    return bool(value)


def as_choice(value: object, name: str, choices: Sequence[str]) -> str:
    """A string that must be one of ``choices`` (a non-string is a type error)."""
    opts = ", ".join(repr(c) for c in choices)
    if not isinstance(value, str):
        raise InvalidTypeError(
            f"Expected `{name}` to be one of {opts} (a string), got {type(value).__name__} "
            f"{value!r}."
        )
    if value not in choices:
        raise InvalidInputError(f"Expected `{name}` to be one of {opts}, got {value!r}.")
    return value


def as_int(
    value: Any,
    name: str,
    *,
    minimum: int | None = None,
    choices: Collection[int] | None = None,
    what: str = "",
) -> int:
    """A Python or NumPy integer (not a bool, float or string: those are type errors),
    ``>= minimum`` and in ``choices`` when given (else a value error).

    >>> as_int(4, "order", choices=(2, 4, 6))
    4
    """
    if not is_integer(value) and not (
        isinstance(value, np.integer) and not isinstance(value, np.bool_)
    ):
        raise InvalidTypeError(
            f"Expected `{name}` to be an integer{what}, got {type(value).__name__} {value!r}."
        )
    v = int(value)
    if (minimum is not None and v < minimum) or (choices is not None and v not in choices):
        if what:
            want = f" to be an integer{what}"
        elif choices is not None:
            want = " to be one of " + ", ".join(str(c) for c in choices)
        else:
            want = f" to be an integer >= {minimum}"
        raise InvalidInputError(f"Expected `{name}`{want}, got {value!r}.")
    return v


def as_times(
    t: object, name: str = "t", *, min_len: int = 1, strictly_increasing: bool = True
) -> FloatArray:
    """A 1-D array of finite, strictly increasing times with at least ``min_len`` samples."""
    a = as_float_array(t, name)
    if a.ndim != 1:
        raise InvalidInputError(f"Expected `{name}` to have shape (n,), got {a.shape}.")
    if a.size < min_len:
        raise InvalidInputError(
            f"Expected `{name}` to have at least {min_len} samples, got {a.size}."
        )
    if strictly_increasing and a.size > 1 and not np.all(np.diff(a) > 0):
        raise InvalidInputError(f"Expected `{name}` to be strictly increasing.")
    return a


def is_integer(x: object) -> bool:
    return isinstance(x, numbers.Integral) and not isinstance(x, bool)


def batch_shape(**named: tuple[Any, int]) -> tuple[int, ...]:
    """The broadcast batch (leading) shape of ``name=(array_or_shape, core_ndim)`` pairs.

    The ONE batch-broadcast checker: each argument contributes its shape minus its
    ``core_ndim`` trailing (core) dimensions, e.g. ``omega=(w, 1)`` for ``(..., 3)``,
    ``inertia=(j, 2)`` for ``(..., 3, 3)``, ``mass=(m, 0)``. A shape (a tuple of ints)
    may be given instead of an array. Raises
    ``InvalidInputError("Expected the batch (leading) shapes of `a` (2,), `b` (3,) to
    broadcast.")`` when they do not.

    >>> import numpy as np
    >>> batch_shape(omega=(np.zeros((4, 3)), 1), mass=(np.ones(()), 0))
    (4,)
    """
    shapes = {}
    for k, (a, nd) in named.items():
        s = tuple(a) if isinstance(a, tuple) else np.shape(a)
        shapes[k] = s[: len(s) - nd]
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        desc = ", ".join(f"`{k}` {s}" for k, s in shapes.items())
        raise InvalidInputError(
            f"Expected the batch (leading) shapes of {desc} to broadcast."
        ) from None


def _is_scipy_rotation(x: object) -> bool:
    cls = type(x)
    return cls.__name__ == "Rotation" and cls.__module__.startswith("scipy.spatial")


def as_rotation_quat(x: Any, name: str = "rotation0") -> FloatArray:
    """Unit scalar-first quaternions ``(..., 4)`` from any accepted attitude.

    The ONE attitude converter at public entry points (docs/conventions.md, "one
    contract"): a poinsot :class:`~poinsot.Rotation` (its quaternions), a SciPy
    ``scipy.spatial.transform.Rotation`` (converted with
    ``as_quat(scalar_first=True)``, or by moving SciPy's trailing scalar to the front
    on SciPy < 1.14, so it is never misread), or an array of scalar-first
    quaternions ``(w, x, y, z)`` (normalised; zero rejected). Anything else is an
    :class:`InvalidTypeError`.

    >>> from scipy.spatial.transform import Rotation as SciPyRotation
    >>> as_rotation_quat(SciPyRotation.from_quat([0.0, 0.0, 1.0, 1.0])).round(6)
    array([0.707107, 0.      , 0.      , 0.707107])
    """
    if getattr(type(x), "_is_poinsot_rotation", False):  # a poinsot Rotation
        return np.asarray(x.as_quat(), dtype=np.float64)
    if _is_scipy_rotation(x):
        try:
            q = x.as_quat(scalar_first=True)
        except TypeError:  # SciPy < 1.14: (x, y, z, w)
            q = np.roll(x.as_quat(), 1, axis=-1)
        return as_quat(q, name)
    if isinstance(x, dict | set) or (hasattr(x, "as_quat") and not hasattr(x, "__array__")):
        raise InvalidTypeError(
            f"Expected `{name}` to be a poinsot Rotation, a SciPy Rotation or scalar-first "
            f"quaternions (..., 4), got {type(x).__name__}."
        )
    return as_quat(x, name)


def _first_bad(values: FloatArray, bad: BoolArray) -> tuple[str, float]:
    """`` at batch index (i, ...)`` of the first bad entry (empty if unbatched), and its value."""
    if bad.ndim == 0:
        return "", float(values)
    idx = tuple(int(i) for i in np.argwhere(bad)[0])
    return f" at batch index {idx}", float(values[idx])


def check_rotation_matrix(
    matrix: object, name: str = "matrix", *, atol: float = ROTATION_MATRIX_ATOL
) -> FloatArray:
    """Proper rotation matrices ``(..., 3, 3)``: ``max |S^T S - E| <= atol`` and ``det S > 0``.

    The ONE rotation-matrix validator; its default tolerance is
    :data:`ROTATION_MATRIX_ATOL` (``1e-6``). Returns the float64 array unchanged.

    >>> check_rotation_matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]).shape
    (3, 3)
    """
    s = as_matrix3(matrix, name)
    err = np.max(np.abs(np.swapaxes(s, -1, -2) @ s - np.eye(3)), axis=(-2, -1))
    bad = err > atol
    if np.any(bad):
        where, worst = _first_bad(err, bad)
        raise InvalidInputError(
            f"Expected `{name}` to be a rotation matrix (S^T S = E within {atol:g}){where}, "
            f"got max |S^T S - E| = {worst:.3g}."
        )
    det = np.linalg.det(s)
    bad = det <= 0
    if np.any(bad):
        where, worst = _first_bad(det, bad)
        raise InvalidInputError(
            f"Expected `{name}` to be a proper rotation matrix (det +1){where}, "
            f"got det = {worst:.6g}."
        )
    return s


def read_regular_file(path: Any, *, max_bytes: int, what: str) -> bytes:
    """The bytes of the regular file ``path``, refused before reading if it is not one.

    A scenario names its files, so a FIFO would block the reader forever, a link to
    ``/dev/zero`` would fill the memory and a junk file of hundreds of MB would be parsed
    whole: the file is opened without blocking, checked to be a regular file of at most
    ``max_bytes`` bytes (``fstat`` on the open descriptor: what is read is what was
    checked), and read with that bound. Raises :class:`InvalidInputError` naming the
    file and ``what`` it should have been; ``FileNotFoundError``, ``IsADirectoryError``
    and other ``OSError`` pass through for the caller to word.

    Examples
    --------
    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> p = os.path.join(d, "a.txt")
    >>> _ = open(p, "w").write("hello")
    >>> read_regular_file(p, max_bytes=16, what="a text file")
    b'hello'
    >>> pipe = os.path.join(d, "pipe")
    >>> os.mkfifo(pipe)
    >>> read_regular_file(pipe, max_bytes=16, what="a text file")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    poinsot.errors.InvalidInputError: .../pipe: expected a text file (a regular file), got a FIFO.
    """
    import os
    import stat

    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(21, "Is a directory", str(path))
        if not stat.S_ISREG(st.st_mode):
            kinds = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                     (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))  # fmt: skip
            kind = next((name for test, name in kinds if test(st.st_mode)), "another file type")
            raise InvalidInputError(f"{path}: expected {what} (a regular file), got {kind}.")
        if st.st_size > max_bytes:
            raise InvalidInputError(
                f"{path}: expected {what} of at most {max_bytes / 2**20:g} MiB, got "
                f"{st.st_size / 2**20:.4g} MiB; the limit guards against reading a wrong "
                "file whole."
            )
        chunks = []
        left = max_bytes + 1  # a file that grows while read is still bounded
        while left > 0:
            chunk = os.read(fd, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        if left <= 0:
            raise InvalidInputError(
                f"{path}: expected {what} of at most {max_bytes / 2**20:g} MiB; it grew "
                "beyond that while being read."
            )
        return b"".join(chunks)
    finally:
        os.close(fd)
