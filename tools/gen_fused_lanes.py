"""Write ``src/poinsot/dynamics/_fused_stages.py``: the stage sums of the lane DOP853.

The compiled DOP853 of ``simulate(method="dop853")`` steps ``L`` bodies together
(:mod:`poinsot.dynamics._fused_lanes`), every stage sum and right-hand side a loop over
the lanes of a flat work array, which LLVM vectorises across bodies. The stage sums
are written out here with the tableau's non-zero coefficients as literals and every
offset a constant (in the order of the scalar kernel's sums, so that every lane
computes bit for bit what ``_fused.one_body`` computes): with runtime offsets or
coefficient tables LLVM could not rule out that a store overlaps the next loads and
left the sums scalar. Run after editing the tableau or the work-array layout::

    python tools/gen_fused_lanes.py

``tests/dynamics/test_fused_lanes.py`` checks that the file is up to date.
"""

from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TARGET = os.path.join(HERE, "..", "src", "poinsot", "dynamics", "_fused_stages.py")


sys.path.insert(0, os.path.join(HERE, "..", "src"))
# the work-array layout is the lane module's (one place)
from poinsot.dynamics._fused_lanes import (  # noqa: E402
    OFF_ERR,
    OFF_F,
    OFF_H,
    OFF_K,
    OFF_KOUT,
    OFF_Y,
    OFF_YN,
    OFF_Z,
    L,
)


def y(c: int) -> str:
    return f"W[{OFF_Y + c * L} + l]"


def k(s: int, c: int) -> str:
    return f"W[{OFF_K + (s * 7 + c) * L} + l]"


def yn(c: int) -> str:
    return f"W[{OFF_YN + c * L} + l]"


def fd(i: int, c: int) -> str:
    return f"W[{OFF_F + (i * 7 + c) * L} + l]"


def z(c: int) -> str:
    return f"W[{OFF_Z + c * L} + l]"


def kout(c: int) -> str:
    return f"W[{OFF_KOUT + c * L} + l]"


def lit(x: float) -> str:
    return repr(float(x))


def wsum(coef, stage: callable, c: int, upto: int) -> str:
    """``c0 * K_0 + c1 * K_1 + ...`` over the non-zero coefficients below ``upto``, left
    to right, one fused multiply-add per term from 0.0 (the scalar kernel's sum, whose
    zero terms change nothing)."""
    acc = "0.0"
    for j in range(upto):
        if coef[j] != 0.0:
            acc = f"fma({lit(coef[j])}, {stage(j, c)}, {acc})"
    return acc


def function(name: str, args: str, doc: str, body: list[str]) -> str:
    head = [
        "@njit(cache=True, error_model='numpy')",
        f"def {name}({args}):  # pragma: no cover",
        f'    """{doc}"""',
    ]
    return "\n".join(head + body)


def lane_loop(body: list[str]) -> list[str]:
    return ["    for l in range(L):", f"        h = W[{OFF_H} + l]"] + [
        "        " + x for x in body
    ]


def copy_out(s: int) -> list[str]:
    """``K_s = K_out`` (the right-hand side just evaluated)."""
    return [f"{k(s, c)} = {kout(c)}" for c in range(7)]


def stage_function(s: int, tab) -> str:
    """``_stage{s}(W)``: ``z = y + h sum_j a_sj K_j`` of every lane (``K_{s-1}`` first
    copied from the output slot of the last right-hand side, but for s = 1 and 13)."""
    body = [] if s in (1, tab.N_STAGES + 1) else copy_out(s - 1)
    body += [f"{z(c)} = fma(h, {wsum(tab.A[s], k, c, s)}, {y(c)})" for c in range(7)]
    return function(
        f"_stage{s}", "W", f"The argument ``z`` of stage {s}, every lane.", lane_loop(body)
    )


def ynew_function(tab) -> str:
    ns = tab.N_STAGES
    body = copy_out(ns - 1)
    for c in range(7):
        body += [
            f"n{c} = fma(h, {wsum(tab.B, k, c, ns)}, {y(c)})",
            f"{yn(c)} = n{c}",
            f"{z(c)} = n{c}",
        ]
    return function(
        "_ynew", "W", "``y_new = y + h sum_j b_j K_j`` (also ``z``), every lane.", lane_loop(body)
    )


def err_function(tab) -> str:
    ns = tab.N_STAGES
    body = copy_out(ns) + ["e5 = 0.0", "e3 = 0.0"]
    for c in range(7):
        body += [
            f"sc = atol + max(abs({y(c)}), abs({yn(c)})) * rtol",
            f"a5 = ({wsum(tab.E5, k, c, ns + 1)}) / sc",
            f"a3 = ({wsum(tab.E3, k, c, ns + 1)}) / sc",
            "e5 += a5 * a5",
            "e3 += a3 * a3",
        ]
    body += [
        "err = h * e5 / math.sqrt((e5 + 0.01 * e3) * 7.0)",
        f"W[{OFF_ERR} + l] = 0.0 if (e5 == 0.0 and e3 == 0.0) else err",
    ]
    return function(
        "_err",
        "W, rtol, atol",
        "The error norm of the attempt (``K_12`` stored first), every lane.",
        lane_loop(body),
    )


def fcoef_function(tab) -> str:
    ns = tab.N_STAGES
    body = copy_out(ns + 3)
    for c in range(7):
        body += [
            f"dy = {yn(c)} - {y(c)}",
            f"{fd(0, c)} = dy",
            f"{fd(1, c)} = h * {k(0, c)} - dy",
            f"{fd(2, c)} = 2.0 * dy - h * ({k(ns, c)} + {k(0, c)})",
        ]
        body += [f"{fd(3 + i, c)} = h * ({wsum(tab.D[i], k, c, 16)})" for i in range(4)]
    return function(
        "_fcoef",
        "W",
        "The dense-output coefficients ``F`` (``K_15`` stored first), every lane.",
        lane_loop(body),
    )


HEADER = '''"""DOP853 stage sums of the lane kernels, GENERATED by ``tools/gen_fused_lanes.py``.

Do not edit: run ``python tools/gen_fused_lanes.py``. Each function is a loop over the
``L`` lanes of the work array ``W`` (layout: :mod:`poinsot.dynamics._fused_lanes`) with
the tableau's non-zero coefficients as literals and every offset a constant, so that
LLVM vectorises it across the lanes; the sums run in the order of the scalar kernel's
(:func:`poinsot.dynamics._fused.one_body`), whose zero terms change nothing.
"""

# ruff: noqa: E501
# fmt: off
from __future__ import annotations

import math

from .. import _numba_helpers as nh
from .._jit import njit
from .._numba_cache import depends_on
from .._numba_helpers import fma

depends_on(__file__, nh)  # the cache sees edits of the fused multiply-add

L = {L}
'''


def generate() -> str:
    from poinsot.dynamics import _dop853_tableau as tab

    parts = [HEADER.replace("{L}", str(L))]
    ns = tab.N_STAGES
    parts += [stage_function(s, tab) for s in range(1, ns)]
    parts += [ynew_function(tab), err_function(tab)]
    parts += [stage_function(s, tab) for s in range(ns + 1, ns + 4)]
    parts.append(fcoef_function(tab))
    return "\n\n\n".join(p.strip("\n") for p in parts) + "\n"


if __name__ == "__main__":
    with open(TARGET, "w") as fh:
        fh.write(generate())
    print(f"wrote {os.path.normpath(TARGET)}")
