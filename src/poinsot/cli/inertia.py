"""``poinsot inertia``: the inertia tensor of a uniform solid, its principal moments
and axes."""

from __future__ import annotations

import argparse
import inspect

import numpy as np

from ..errors import PoinsotError
from ..mass import principal_axes, solids
from ..mass.solids import SHAPES
from ._common import _num, _nums, _Usage, _user_names

DESCRIPTION = (
    "Inertia tensor of a uniform solid about its centre of mass, its principal moments and axes."
)
EPILOG = """\
dimensions (m):
  box        length x, width y, height z      sphere     radius
  cylinder   radius, height (axis z)          cone       base radius, height (axis z)
  ellipsoid  semi-axes a, b, c                rod        length (along z)
  disc       radius (in the xy plane)         ring       radius (in the xy plane)

example:
  poinsot inertia box --mass 2 --dims 0.3 0.2 0.1
  poinsot inertia cylinder --mass 1 --dims 0.05 0.4 --hollow
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "shape", choices=tuple(SHAPES), metavar="SHAPE", help="one of " + ", ".join(SHAPES)
    )
    p.add_argument("--mass", type=float, required=True, metavar="M", help="mass (kg)")
    p.add_argument("--dims", type=float, nargs="+", metavar="D", help="dimensions (m)")
    p.add_argument("--hollow", action="store_true", help="hollow sphere / thin-walled cylinder")
    p.set_defaults(func=_cmd_inertia)


def _cmd_inertia(args: argparse.Namespace) -> int:
    names = SHAPES[args.shape]
    if args.dims is None or len(args.dims) != len(names):
        found = "none" if args.dims is None else f"{len(args.dims)}"
        raise _Usage(
            f"a {args.shape} takes {len(names)} dimension(s) with --dims "
            f"({', '.join(names)}; m), found {found}."
        )
    kwargs = {}
    if args.hollow:
        if args.shape not in ("sphere", "cylinder"):
            raise _Usage("--hollow applies to a sphere or a cylinder only.")
        kwargs["hollow"] = True
    fn = getattr(solids, args.shape)
    params = [p for p in inspect.signature(fn).parameters if p not in ("mass", "hollow")]
    names_map = {"mass": "--mass"}
    for k, (p, what) in enumerate(zip(params, names, strict=False)):
        names_map[p] = f"--dims value {k + 1} ({what})"
    try:
        j = fn(args.mass, *args.dims, **kwargs)
    except PoinsotError as exc:
        raise _Usage(_user_names(str(exc), names_map)) from None
    moments, axes = principal_axes(j)
    m = axes.as_matrix()
    with np.printoptions(precision=10, suppress=True):
        kind = ("hollow " if args.hollow else "") + args.shape
        print(
            f"{kind}: mass {_num(args.mass)} kg, dims "
            f"{' x '.join(_num(d) for d in args.dims)} m ({', '.join(names)})"
        )
        print("inertia tensor about the centre of mass, body axes (kg m^2):")
        scale = float(np.max(np.abs(j)))
        for row in j:
            print("  " + "  ".join(f"{x:>20}" for x in _nums(row, scale)))
        print("principal moments A <= B <= C (kg m^2): " + "  ".join(_nums(moments, scale)))
        print("principal axes (columns, in body axes):")
        for row in m:
            print("  " + "  ".join(f"{x:>6}" for x in _nums(row, 1.0)))
    return 0
