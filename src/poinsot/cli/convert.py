"""``poinsot convert``: one rotation from one representation to another. Light: NumPy
and the rotations only (no numba, SciPy or Matplotlib)."""

from __future__ import annotations

import argparse
import warnings
from typing import Any

import numpy as np

from .._display import clean
from ..errors import PoinsotError
from ..rotations._from_matrix import rotation_from_matrix
from ..rotations.rotation import Rotation
from ._common import _nums, _Usage, _user_names

DESCRIPTION = "Convert one rotation from one representation to another."
EPILOG = """\
representations:
  quat        scalar-first unit quaternion w x y z (Hamilton), also quat:xyzw
  matrix      9 entries of the rotation matrix, row by row
  rotvec      rotation vector (axis times angle)
  axis-angle  x y z angle
  euler:SEQ   three angles of sequence SEQ: upper case intrinsic (euler:ZXZ),
              lower case extrinsic (euler:zxz), presets euler:euler (= ZXZ) and
              euler:krylov (= ZXY)
  gibbs       Gibbs/Rodrigues vector e tan(f/2)
  mrp         modified Rodrigues parameters e tan(f/4)
A rotation maps body components to space components (v_space = R v_body).
--degrees applies to the angles read and printed (euler, rotvec, axis-angle).

examples:
  poinsot convert euler:ZXZ quat 30 45 60 --degrees
  poinsot convert quat matrix 0.7071 0.7071 0 0
  poinsot convert rotvec axis-angle 0 0 90 --degrees
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("source", metavar="FROM", help="input representation")
    p.add_argument("target", metavar="TO", help="output representation")
    p.add_argument("values", metavar="VALUES", nargs="+", help="the input numbers")
    p.add_argument("--degrees", action="store_true", help="angles in degrees (in and out)")
    p.add_argument(
        "--tolerance",
        type=float,
        default=1e-6,
        metavar="TOL",
        help="largest max|A^T A - E| of a `matrix` input (default 1e-6); a matrix that "
        "is not orthogonal to round-off is projected onto the nearest rotation, with a warning",
    )
    p.set_defaults(func=_cmd_convert)


_REPRS = {
    "quat": 4,
    "quat:wxyz": 4,
    "quat:xyzw": 4,
    "matrix": 9,
    "rotvec": 3,
    "axis-angle": 4,
    "gibbs": 3,
    "mrp": 3,
}


def _repr_size(name: str, role: str) -> int:
    if name.lower().startswith("euler:"):
        return 3
    if name not in _REPRS:
        raise _Usage(
            f"unknown {role} representation {name!r}: expected one of quat (scalar first "
            "w,x,y,z), quat:xyzw (scalar last), matrix (9 values, row by row), rotvec, "
            "axis-angle (x y z angle), euler:SEQ (e.g. euler:ZXZ intrinsic, euler:zxz "
            "extrinsic, euler:euler, euler:krylov), gibbs, mrp."
        )
    return _REPRS[name]


def _from(name: str, v: Any, degrees: bool, tolerance: float) -> Any:
    if name.lower().startswith("euler:"):
        return Rotation.from_euler(name[6:], v, degrees=degrees)
    if name in ("quat", "quat:wxyz"):
        return Rotation.from_quat(v, scalar_first=True)
    if name == "quat:xyzw":
        return Rotation.from_quat(v, scalar_first=False)
    if name == "matrix":
        return rotation_from_matrix(v.reshape(3, 3), tolerance, where="convert", knob="--tolerance")
    if name == "rotvec":
        return Rotation.from_rotvec(v, degrees=degrees)
    if name == "axis-angle":
        return Rotation.from_axis_angle(v[:3], v[3], degrees=degrees)
    if name == "gibbs":
        return Rotation.from_gibbs(v)
    return Rotation.from_mrp(v)


def _to(name: str, r: Any, degrees: bool) -> Any:
    if name.lower().startswith("euler:"):
        return r.as_euler(name[6:], degrees=degrees)
    if name in ("quat", "quat:wxyz"):
        return _canonical(r.as_quat(scalar_first=True), 0)
    if name == "quat:xyzw":
        return _canonical(r.as_quat(scalar_first=False), 3)
    if name == "matrix":
        return r.as_matrix()
    if name == "rotvec":
        return r.as_rotvec(degrees=degrees)
    if name == "axis-angle":
        axis, angle = r.as_axis_angle(degrees=degrees)
        return np.append(axis, angle)
    if name == "gibbs":
        return r.as_gibbs()
    return r.as_mrp()


def _canonical(q: Any, scalar: int) -> Any:
    """The sign of ``q`` (``q`` and ``-q`` are the same rotation) with the scalar part
    ``w >= 0``; if ``w = 0`` (to round-off, as printed), the first non-zero vector
    component positive."""
    q = clean(q, 1.0)
    order = [scalar] + [k for k in range(4) if k != scalar]
    for k in order:
        if q[k] != 0.0:
            return -q if q[k] < 0 else q
    return q


#: Library argument names -> the names a user of `convert` sees.
_CONVERT_NAMES = {
    "seq": "the Euler sequence (euler:SEQ)",
    "sequence": "the Euler sequence (euler:SEQ)",
    "angles": "the angles (VALUES)",
    "quat": "the quaternion (VALUES)",
    "rotvec": "the rotation vector (VALUES)",
    "axis": "the axis (first 3 VALUES)",
    "angle": "the angle (last VALUE)",
    "gibbs": "the Gibbs vector (VALUES)",
    "mrp": "the MRP vector (VALUES)",
}


def _cmd_convert(args: argparse.Namespace) -> int:
    n = _repr_size(args.source, "source")
    _repr_size(args.target, "target")
    values = []
    for s in args.values:
        try:
            values.append(float(s))
        except ValueError:
            raise _Usage(f"expected numbers as VALUES, found {s!r}.") from None
    if len(values) != n:
        raise _Usage(
            f"{args.source} takes {n} values, found {len(values)}: {' '.join(args.values)}."
        )
    # Values so large that the conversion overflows must give a clear error, not a
    # NumPy warning followed by "nan" or a zero quaternion.
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            r = _from(args.source, np.array(values), args.degrees, args.tolerance)
        except PoinsotError as exc:
            raise _Usage(_user_names(str(exc), _CONVERT_NAMES)) from None
        q = np.asarray(r.as_quat(), dtype=float)
        if not (np.all(np.isfinite(q)) and abs(float(q @ q) - 1.0) < 1e-6):
            raise _Usage(
                f"the {args.source} values {' '.join(args.values)} are out of the range "
                "that can be converted in double precision."
            )
        out = np.asarray(_to(args.target, r, args.degrees))
    if np.any(np.isnan(out)):
        raise _Usage(f"the conversion to {args.target} overflowed for these values.")
    if out.shape == (3, 3):
        for row in out:
            print(" ".join(_nums(row, 1.0)))
    else:
        # angles: noise relative to the largest value; other representations: to 1
        print(" ".join(_nums(out, None if args.degrees else max(1.0, np.max(np.abs(out))))))
    return 0
