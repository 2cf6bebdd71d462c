"""Write ``src/poinsot/dynamics/_fused_lanes.py``: the lane-blocked DOP853 kernels.

The compiled DOP853 of ``simulate(method="dop853")`` steps ``L`` bodies together
(``_fused_lanes.L``), every stage sum and right-hand side an inner loop over the
lanes on a flat work array with constant offsets, so that LLVM vectorises it
across bodies (each lane keeps its own step size, error and accept/reject: see
``_fused_lanes``). The stage sums are written out with the tableau's non-zero
coefficients as literals (in the order of the scalar kernel's sums, so that every
lane computes bit for bit what ``_fused.one_body`` computes), one set of kernels
per built-in torque ``kind``. Run after editing the tableau, the right-hand side or
the template below::

    python tools/gen_fused_lanes.py

``tests/dynamics/test_fused_lanes.py`` checks that the file is up to date.
"""

from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TARGET = os.path.join(HERE, "..", "src", "poinsot", "dynamics", "_fused_lanes.py")

KINDS = (0, 1, 2, 3, 4)

sys.path.insert(0, os.path.join(HERE, "..", "src"))
# the work-array layout is the control module's (one place)
from poinsot.dynamics._fused_lanes_ctl import (  # noqa: E402
    N_WORK,
    OFF_ERR,
    OFF_F,
    OFF_H,
    OFF_J,
    OFF_JI,
    OFF_K,
    OFF_P,
    OFF_Y,
    OFF_YN,
    OFF_Z,
    OFF_KOUT,
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
    to right (the scalar kernel's sum from 0.0, whose zero terms change nothing)."""
    terms = [f"{lit(coef[j])} * {stage(j, c)}" for j in range(upto) if coef[j] != 0.0]
    return " + ".join(terms) if terms else "0.0"


def torque_lines(kind: int) -> list[str]:
    """The body torque ``t0, t1, t2`` of ``_fused._torque`` for one ``kind``, the state
    quaternion in ``z0..z3``, the parameters read from the lane's ``par``."""
    if kind == 0:
        return ["t0, t1, t2 = 0.0, 0.0, 0.0"]
    if kind == 1:
        return ["t0, t1, t2 = p0, p1, p2"]
    if kind == 2:
        return ["t0, t1, t2 = nh.qrot_inverse(z0, z1, z2, z3, p0, p1, p2)"]
    if kind == 3:
        return [
            "b0, b1, b2 = nh.qrot_inverse(z0, z1, z2, z3, 0.0, 0.0, 1.0)",
            "t0, t1, t2 = nh.cross(b0, b1, b2, p1, p2, p3)",
            "t0, t1, t2 = p0 * t0, p0 * t1, p0 * t2",
        ]
    return [
        "b0, b1, b2 = nh.qrot_inverse(z0, z1, z2, z3, p1, p2, p3)",
        "j0, j1, j2 = nh.matvec(a00, a01, a02, a10, a11, a12, a20, a21, a22, b0, b1, b2)",
        "t0, t1, t2 = nh.cross(b0, b1, b2, j0, j1, j2)",
        "t0, t1, t2 = p0 * t0, p0 * t1, p0 * t2",
    ]


def rhs_function(kind: int) -> str:
    """``_f{kind}(W, l, z0..z6)``: ``_fused._rhs`` of lane ``l`` as seven scalars."""
    lines = [
        "@njit(cache=True, inline='always', error_model='numpy')",
        f"def _f{kind}(W, l, z0, z1, z2, z3, z4, z5, z6):  # pragma: no cover",
        f'    """``_fused._rhs`` of lane ``l`` for torque kind {kind} (returns ``f``)."""',
    ]
    names = [f"a{r}{c}" for r in range(3) for c in range(3)]
    lines.append(f"    {', '.join(names)} = (")
    lines.append("        " + ", ".join(f"W[{OFF_J + i * L} + l]" for i in range(9)) + ",")
    lines.append("    )")
    inames = [f"i{r}{c}" for r in range(3) for c in range(3)]
    lines.append(f"    {', '.join(inames)} = (")
    lines.append("        " + ", ".join(f"W[{OFF_JI + i * L} + l]" for i in range(9)) + ",")
    lines.append("    )")
    if kind > 0:
        lines.append(
            "    p0, p1, p2, p3 = " + ", ".join(f"W[{OFF_P + i * L} + l]" for i in range(4))
        )
    lines += [
        "    d0, d1, d2, d3 = nh.qmul(z0, z1, z2, z3, 0.0, z4, z5, z6)",
        "    k0, k1, k2 = nh.matvec(a00, a01, a02, a10, a11, a12, a20, a21, a22, z4, z5, z6)",
    ]
    lines += ["    " + t for t in torque_lines(kind)]
    lines += [
        "    m0, m1, m2 = nh.euler_momentum_rate(k0, k1, k2, z4, z5, z6, t0, t1, t2)",
        "    f4, f5, f6 = nh.matvec(i00, i01, i02, i10, i11, i12, i20, i21, i22, m0, m1, m2)",
        "    return 0.5 * d0, 0.5 * d1, 0.5 * d2, 0.5 * d3, f4, f5, f6",
    ]
    return "\n".join(lines)


def rhs_pass(kind: int) -> str:
    """``_rhs{kind}(W)``: ``K_out = f(z)`` for every lane, ``z`` and ``K_out`` in fixed slots
    (compiled once per kind, vectorised over the lanes in its own module; the stage loops
    copy ``K_out`` to its stage)."""
    zs = ", ".join(f"z{c}" for c in range(7))
    out = [
        "@njit(cache=True, error_model='numpy')",
        f"def _rhs{kind}(W):  # pragma: no cover",
        '    """``W[out] = f(W[z])`` for every lane (the stage right-hand sides)."""',
        "    for l in range(L):",
    ]
    for c in range(7):
        out.append(f"        z{c} = {z(c)}")
    out.append(f"        r0, r1, r2, r3, r4, r5, r6 = _f{kind}(W, l, {zs})")
    for c in range(7):
        out.append(f"        {kout(c)} = r{c}")
    return "\n".join(out)


def function(name: str, args: str, doc: str, body: list[str]) -> str:
    head = [
        "@njit(cache=True, error_model='numpy')",
        f"def {name}({args}):  # pragma: no cover",
        f'    """{doc}"""',
    ]
    return "\n".join(head + body)


def lane_loop(body: list[str]) -> list[str]:
    return ["    for l in range(L):", f"        h = W[{OFF_H} + l]"] + ["        " + x for x in body]


def copy_out(s: int) -> list[str]:
    """``K_s = K_out`` (the right-hand side just evaluated)."""
    return [f"{k(s, c)} = {kout(c)}" for c in range(7)]


def stage_function(s: int, tab) -> str:
    """``_stage{s}(W)``: ``z = y + h sum_j a_sj K_j`` of every lane (``K_{s-1}`` first
    copied from the output slot of the last right-hand side, but for s = 1 and 13)."""
    body = [] if s in (1, tab.N_STAGES + 1) else copy_out(s - 1)
    body += [f"{z(c)} = {y(c)} + h * ({wsum(tab.A[s], k, c, s)})" for c in range(7)]
    return function(f"_stage{s}", "W", f"The argument ``z`` of stage {s}, every lane.", lane_loop(body))


def ynew_function(tab) -> str:
    ns = tab.N_STAGES
    body = copy_out(ns - 1)
    for c in range(7):
        body += [f"n{c} = {y(c)} + h * ({wsum(tab.B, k, c, ns)})", f"{yn(c)} = n{c}", f"{z(c)} = n{c}"]
    return function("_ynew", "W", "``y_new = y + h sum_j b_j K_j`` (also ``z``), every lane.", lane_loop(body))


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
    return function("_err", "W, rtol, atol", "The error norm of the attempt (``K_12`` stored first), every lane.", lane_loop(body))


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
    return function("_fcoef", "W", "The dense-output coefficients ``F`` (``K_15`` stored first), every lane.", lane_loop(body))


def attempt_function(kind: int, tab) -> str:
    """``_attempt{kind}(W, rtol, atol)``: stages 1-11, ``y_new``, the FSAL stage 12 and
    the scaled error of every lane (``_fused.one_body``'s step, lane by lane)."""
    body = []
    for s in range(1, tab.N_STAGES):
        body += [f"    _stage{s}(W)", f"    _rhs{kind}(W)"]
    body += ["    _ynew(W)", f"    _rhs{kind}(W)", "    _err(W, rtol, atol)"]
    return function(
        f"_attempt{kind}", "W, rtol, atol",
        f"One DOP853 step attempt of every lane (torque kind {kind}): the stages, ``y_new``, "
        "the\n    FSAL stage and the error norm ``err`` of each lane.", body,
    )


def dense_function(kind: int, tab) -> str:
    """``_dense{kind}(W)``: the three extra stages and the interpolant ``F`` of every lane."""
    body = []
    for s in range(tab.N_STAGES + 1, tab.N_STAGES + 4):
        body += [f"    _stage{s}(W)", f"    _rhs{kind}(W)"]
    body.append("    _fcoef(W)")
    return function(
        f"_dense{kind}", "W",
        f"The 7th-order dense output of the step just taken by every lane (torque kind {kind}):"
        "\n    the stages 13-15 and the coefficients ``F``.", body,
    )


DRIVER = '''
@njit(cache=True)
def _chunk{kind}(
    lo, hi, y0, J, Ji, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):  # pragma: no cover
    """Bodies ``lo`` to ``hi - 1`` through the ``L`` lanes (torque kind {kind}): a lane whose
    body ends takes the next one; see :func:`poinsot.dynamics._fused_lanes.lane_fill`."""
    W = np.zeros(N_WORK)
    ls = np.zeros((N_LS, L))
    li = np.zeros((N_LI, L), dtype=np.int64)
    li[BODY, :] = -1
    scratch = np.empty((5, 7))
    nxt = lo
    while True:
        nxt, active = lane_fill(
            nxt, hi, W, ls, li, scratch, y0, J, Ji, {kind}, par, t_out, rtol, atol, max_step,
            max_steps, oq, ow, stats, cancel, done,
        )
        if active == 0:
            break
        _attempt{kind}(W, rtol, atol)
        if lane_control(W, ls, li, t_out):
            _dense{kind}(W)
        lane_accept(W, ls, li, scratch, t_out, oq, ow, stats)


@njit(cache=True, parallel=True, nogil=True)
def batch{kind}(
    y0, J, Ji, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):  # pragma: no cover
    """:func:`poinsot.dynamics._fused.integrate_batch` for torque kind {kind}, in chunks of
    ``CHUNK`` bodies (fixed by body index) stepped ``L`` at a time."""
    n = y0.shape[0]
    for c in prange((n + CHUNK - 1) // CHUNK):
        _chunk{kind}(
            c * CHUNK, min(n, (c + 1) * CHUNK), y0, J, Ji, par, t_out, rtol, atol, max_step,
            max_steps, oq, ow, stats, cancel, done,
        )
'''


HEADER = '''"""Lane-blocked DOP853 kernels, GENERATED by ``tools/gen_fused_lanes.py``: do not edit.

Every function below works on the flat work array ``W`` of one block of ``L`` lanes
(layout: :mod:`poinsot.dynamics._fused_lanes_ctl`); the lane loops are what LLVM
vectorises across bodies. The per-lane step control is hand-written, in
:mod:`poinsot.dynamics._fused_lanes_ctl`.
"""

# ruff: noqa: E501
# fmt: off
from __future__ import annotations

import math

import numpy as np

from .. import _numba_helpers as nh
from .._jit import njit, prange
from .._numba_cache import depends_on
from . import _fused_lanes_ctl as ctl
from ._fused_lanes_ctl import (
    BODY,
    CHUNK,
    L,
    N_LI,
    N_LS,
    N_WORK,
    lane_accept,
    lane_control,
    lane_fill,
)

depends_on(__file__, nh, ctl)
'''


def generate() -> str:
    from poinsot.dynamics import _dop853_tableau as tab

    parts = [HEADER]
    ns = tab.N_STAGES
    parts += [stage_function(s, tab) for s in range(1, ns)]
    parts += [ynew_function(tab), err_function(tab)]
    parts += [stage_function(s, tab) for s in range(ns + 1, ns + 4)]
    parts.append(fcoef_function(tab))
    for kind in KINDS:
        parts.append(rhs_function(kind))
        parts.append(rhs_pass(kind))
        parts.append(attempt_function(kind, tab))
        parts.append(dense_function(kind, tab))
        parts.append(DRIVER.replace("{kind}", str(kind)).strip("\n"))
    parts.append("BATCH = (" + ", ".join(f"batch{kind}" for kind in KINDS) + ")")
    return "\n\n\n".join(p.strip("\n") for p in parts) + "\n"


if __name__ == "__main__":
    with open(TARGET, "w") as fh:
        fh.write(generate())
    print(f"wrote {os.path.normpath(TARGET)}")
