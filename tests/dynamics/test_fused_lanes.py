"""The lane-blocked DOP853 (``_fused_lanes``, issue 24) against the one-body kernel.

Every lane runs exactly the operations of :func:`poinsot.dynamics._fused.one_body`
(the stage sums in the same order, the same right-hand side, the same step
control), so the results must be equal bit for bit, for every torque kind, dense
output, bodies that end early or fail while the other lanes go on, and a batch that
is not a multiple of the lanes or chunks.
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import numpy as np
import pytest

from poinsot.dynamics import (
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityGradientTorque,
    GravityTorque,
    GyrostaticTorque,
    simulate,
)

pytest.importorskip("numba")
from poinsot._jit import NUMBA  # noqa: E402

if not NUMBA:  # the NumPy executor runs the one-body kernel only
    pytest.skip("the lane kernels are numba's", allow_module_level=True)

from poinsot.dynamics import _fused, _fused_lanes, _fused_run  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _bodies(n, seed=2):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))
    omega = rng.normal(size=(n, 3)) * rng.uniform(0.1, 5.0, (n, 1))  # uneven step counts
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return moments, quat, omega


def _both(*args, **kw):
    """``_fused_run.integrate`` with the lanes and with one body per iteration."""
    out = []
    for lanes in (True, False):
        _fused_run.LANES = lanes
        try:
            out.append(_fused_run.integrate(*args, **kw))
        finally:
            _fused_run.LANES = True
    return out


def _assert_same(a, b):
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)


def test_generated_stages_up_to_date():
    spec = importlib.util.spec_from_file_location(
        "gen_fused_lanes", os.path.join(ROOT, "tools", "gen_fused_lanes.py")
    )
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    with open(_fused_lanes.G.__file__) as fh:
        assert fh.read() == gen.generate(), "run python tools/gen_fused_lanes.py"


@pytest.mark.parametrize(
    "torque",
    [
        None,
        ConstantBodyTorque([0.05, -0.02, 0.03]),
        ConstantSpaceTorque([0.1, 0.0, -0.05]),
        GravityTorque(2.0, [0.01, -0.02, 0.1]),
        "gradient",
        "gyrostat",
    ],
    ids=["free", "body", "space", "gravity", "gravity-gradient", "gyrostat"],
)
def test_bit_identical_to_one_body_kernel(torque):
    n = 4 * 4 * _fused_lanes.L + 7  # chunks, the last one not a multiple of the lanes
    moments, quat, omega = _bodies(n)
    if torque == "gradient":  # the field sees the same inertia as the integrator
        moments = np.broadcast_to(moments[0], moments.shape)
        torque = GravityGradientTorque(moments[0], 7.0e6, [0.3, -0.4, 0.8], mu=3.986e14 * 1e5)
    if torque == "gyrostat":  # a rotor momentum per body (kind 5, the torque h x w)
        torque = GyrostaticTorque(np.random.default_rng(4).normal(size=(n, 3)))
    for t in (np.array([0.0, 3.0]), np.linspace(0.0, 3.0, 41)):  # end only; dense output
        a, b = _both(moments, quat, omega, t, torque, rtol=1e-9, atol=1e-11, max_step=np.inf)
        _assert_same(a, b)
        assert np.ptp(a[2][:, 0]) > 5  # the lanes took different numbers of steps


@pytest.mark.parametrize(
    "torque",
    [None, GravityTorque(2.0, [0.01, -0.02, 0.1]), GyrostaticTorque([0.3, -0.5, 0.4])],
    ids=["free", "gravity", "gyrostat"],
)
def test_bit_identical_with_full_inertia_tensors(torque):
    """Tensors off their principal axes: the right-hand side with 3x3 products (a batch
    of diagonal tensors takes the diagonal form, checked above)."""
    n = 2 * _fused_lanes.L + 3
    moments, quat, omega = _bodies(n, seed=6)
    rot = np.linalg.qr(np.random.default_rng(7).normal(size=(n, 3, 3)))[0]
    tensors = np.einsum("nij,nj,nkj->nik", rot, moments, rot)
    assert not np.all(tensors[:, 0, 1] == 0.0)
    a, b = _both(tensors, quat, omega, np.linspace(0.0, 2.0, 5), torque, rtol=1e-9,
                 atol=1e-11, max_step=np.inf)  # fmt: skip
    _assert_same(a, b)
    assert np.all(a[2][:, 3] == _fused.OK)


@pytest.mark.parametrize("kind", [0, 3])
def test_diagonal_form_equals_the_full_products(kind):
    """Principal axes: the diagonal right-hand side skips products with exact zeros,
    which change at most the sign of a zero, so the motion is the same bit for bit."""
    n = 2 * _fused_lanes.L + 3
    moments, quat, omega = _bodies(n, seed=8)
    torque = None if kind == 0 else GravityTorque(2.0, [0.01, -0.02, 0.1])
    _, k, par, jj, ji, y0 = _fused_run._flat_problem(moments, quat, omega, torque)
    assert k == kind
    t = np.linspace(0.0, 2.0, 5)
    out = []
    for kd in (kind, kind + _fused.DIAGONAL):
        oq, ow = np.empty((5, n, 4)), np.empty((5, n, 3))
        stats = np.zeros((n, 4), dtype=np.int64)
        cancel, done = np.zeros(1, dtype=np.int64), np.zeros(n, dtype=np.int64)
        _fused_lanes.integrate_batch(y0, jj, ji, _fused_lanes.Kind(kd), par, t, 1e-9, 1e-11,
                                     np.inf, 10**6, oq, ow, stats, cancel, done)  # fmt: skip
        out.append((oq, ow, stats))
    _assert_same(*out)
    assert np.all(out[0][2][:, 3] == _fused.OK)


def test_bit_identical_with_failures_and_limits():
    moments, quat, omega = _bodies(23, seed=4)
    omega[5] = 1e200  # overflows at once: non-finite while the other lanes go on
    omega[11] = np.nan
    t = np.linspace(0.0, 2.0, 9)
    a, b = _both(moments, quat, omega, t, None, rtol=1e-10, atol=1e-12, max_step=0.3)
    _assert_same(a, b)
    status = a[2][:, 3]
    assert status[5] == _fused.NONFINITE and status[11] == _fused.NONFINITE
    assert np.all(np.delete(status, [5, 11]) == _fused.OK)
    assert np.isnan(a[0][1:, 5]).all() and np.isfinite(a[0][:, 0]).all()
    # too many steps for some bodies only
    a, b = _both(moments, quat, omega, t, None, rtol=1e-12, atol=1e-14, max_step=np.inf,
                 max_steps=40)  # fmt: skip
    _assert_same(a, b)
    assert (a[2][:, 3] == _fused.TOO_MANY_STEPS).any() and (a[2][:, 3] == _fused.OK).any()
    # one output time: the initial state only
    a, b = _both(moments, quat, omega, np.array([0.5]), None, rtol=1e-8, atol=1e-10,
                 max_step=np.inf)  # fmt: skip
    _assert_same(a, b)


def test_bit_identical_negative_times_and_step_too_small():
    moments, quat, omega = _bodies(21, seed=5)
    omega[::3] *= 40.0  # fast bodies: steps that shrink below 10 ulp(t) at large t
    # negative times crossing zero: 10 ulp(t) from the bits of t < 0, t = 0
    a, b = _both(moments, quat, omega, np.linspace(-2.0, 1.0, 7), None, rtol=1e-9,
                 atol=1e-11, max_step=np.inf)  # fmt: skip
    _assert_same(a, b)
    assert np.all(a[2][:, 3] == _fused.OK)
    t = np.array([1e13, 1e13 + 2.0])  # ulp(1e13) = 2e-3: fast bodies cannot keep rtol 1e-13
    a, b = _both(moments, quat, omega, t, None, rtol=1e-13, atol=1e-15, max_step=np.inf)
    _assert_same(a, b)
    status = a[2][:, 3]
    assert (status == _fused.STEP_TOO_SMALL).any() and (status == _fused.OK).any()


def test_next_up_is_nextafter():
    from numba import njit

    @njit
    def up(x, out):
        for i in range(x.shape[0]):
            out[i] = _fused_lanes._next_up(x[i])

    tiny = np.finfo(float).tiny
    x = np.array([0.0, -0.0, 5e-324, -5e-324, tiny, -tiny, 1.0, -1.0, 2.0, -2.0, 0.1, -3.5e7,
                  np.finfo(float).max, -np.finfo(float).max, np.inf, -np.inf, np.nan])  # fmt: skip
    rng = np.random.default_rng(1)  # every magnitude, both signs, denormals included
    x = np.concatenate([x, rng.normal(size=2000) * 10.0 ** rng.uniform(-320, 300, 2000)])
    out = np.empty_like(x)
    up(x, out)
    with np.errstate(over="ignore"):  # nextafter(max, inf) = inf
        np.testing.assert_array_equal(out, np.nextafter(x, np.inf))


def test_cancel_flag_stops_every_lane():
    moments, quat, omega = _bodies(9)
    y0 = np.concatenate([quat, omega], axis=1)
    jj = np.ascontiguousarray(np.broadcast_to(np.eye(3), (9, 3, 3)) * moments[:, None, :])
    ji = np.linalg.inv(jj)
    t = np.linspace(0.0, 1.0, 5)
    oq, ow = np.empty((5, 9, 4)), np.empty((5, 9, 3))
    stats = np.zeros((9, 4), dtype=np.int64)
    cancel = np.ones(1, dtype=np.int64)
    done = np.zeros(9, dtype=np.int64)
    _fused_lanes.integrate_batch(
        y0, jj, ji, _fused_lanes.Kind(0), np.zeros((9, _fused.NPAR)), t, 1e-8, 1e-10, np.inf,
        10**6, oq, ow, stats, cancel, done,
    )  # fmt: skip
    assert np.all(stats[:, 3] == _fused.CANCELLED)
    assert np.isfinite(oq[0]).all() and np.isnan(oq[1:]).all()


def test_simulate_uses_the_lanes_and_marks_failures():
    moments, quat, omega = _bodies(6, seed=8)
    omega[2] = 1e200  # overflows in the first step
    t = np.linspace(0.0, 1.0, 5)
    tr = simulate(moments, quat, omega, t, method="dop853", failures="mark")
    assert tr.info["failed"][2] and not tr.info["failed"][0]
    _fused_run.LANES = False
    try:
        ref = simulate(moments, quat, omega, t, method="dop853", failures="mark")
    finally:
        _fused_run.LANES = True
    np.testing.assert_array_equal(tr.quat, ref.quat)
    np.testing.assert_array_equal(tr.omega, ref.omega)


@pytest.mark.parametrize("kind", [0, 3, _fused.DIAGONAL, _fused.DIAGONAL + 3])
def test_first_steps_of_the_lanes_are_the_one_body_initial_step(kind):
    # the lanes take every body's f and first step from one vectorised pass per chunk
    # (_first_steps): the same bits as _initial_step's, in each of its branches
    n = 2 * _fused_lanes.L + 5  # the last block is short: it repeats the last body
    moments, quat, omega = _bodies(n, seed=8)
    omega[3] = 0.0  # at rest: f = 0, the 1e-6 / 1e-3 h0 branch
    omega[4] = 1e-7  # d1 < 1e-5: h0 = 1e-6
    omega[5] = 3e3  # fast: the step from d2
    omega[6] = np.nan  # non-finite: NaN steps, as one body's
    torque = None if kind % _fused.DIAGONAL == 0 else GravityTorque(2.0, [0.01, -0.02, 0.1])
    _, k, par, jj, ji, y0 = _fused_run._flat_problem(moments, quat, omega, torque)
    assert k == kind % _fused.DIAGONAL
    cases = [  # (span, max_step, rtol, atol): h0 or h1 cut by the span, by max_step
        (10.0, np.inf, 1e-7, 1e-9),
        (1e-12, np.inf, 1e-9, 1e-11),
        (10.0, 2e-3, 1e-12, 1e-14),
        (3.0, np.inf, 1e-6, 1e-12),
    ]
    for span, max_step, rtol, atol in cases:
        first = np.empty((n - 3, 8))
        W = np.full(_fused_lanes.N_WORK, np.nan)  # rows it does not load are never read
        _fused_lanes._first_steps(3, n, W, y0, jj, ji, _fused_lanes.Kind(kind), par, 0.0, span,
                                  rtol, atol, max_step, first)  # fmt: skip
        for b in range(3, n):
            f, tmp, k1, scale = np.empty(7), np.empty(7), np.empty(7), np.empty(7)
            _fused._rhs(0.0, y0[b], jj[b], ji[b], kind, par[b], f)
            h = _fused._initial_step(0.0, y0[b], f, span, rtol, atol, max_step, jj[b], ji[b],
                                     kind, par[b], tmp, k1, scale)  # fmt: skip
            np.testing.assert_array_equal(first[b - 3, :7], f)
            np.testing.assert_array_equal(first[b - 3, 7], h)


@pytest.mark.parametrize("lanes", [True, False])
def test_zero_atol_with_an_exact_zero_in_the_state_is_an_integration_error(lanes):
    # scale = atol + rtol |y| = 0 for the identity's zero components: the first step is
    # NaN (no Python error model in a threaded kernel: both kernels crashed with a
    # SystemError), and the message names atol = 0 as the cause
    from poinsot import IntegrationError

    _fused_run.LANES = lanes
    try:
        with pytest.raises(IntegrationError, match=r"below round-off.*`atol=0`"):
            simulate([1.0, 2.0, 3.0], [1.0, 0.0, 0.0, 0.0], [0.1, 0.2, 0.3], [0.0, 1.0],
                     rtol=1e-8, atol=0.0)  # fmt: skip
        # the same body with atol > 0, or without an exact zero, integrates
        simulate([1.0, 2.0, 3.0], [1.0, 0.0, 0.0, 0.0], [0.1, 0.2, 0.3], [0.0, 1.0],
                 rtol=1e-8, atol=1e-14)  # fmt: skip
        simulate([1.0, 2.0, 3.0], [0.7, 0.1, 0.5, 0.5], [0.1, 0.2, 0.3], [0.0, 1.0],
                 rtol=1e-8, atol=0.0)  # fmt: skip
    finally:
        _fused_run.LANES = True


def test_the_lane_kernel_is_compiled_per_kind(monkeypatch):
    """A call compiles the lanes of its own torque kind only (issue 40: a first call
    compiles one right-hand side, not nine), and the first-call test of readiness asks
    for that kind."""
    from poinsot import _jit

    monkeypatch.setenv("POINSOT_INTERPRET_FIRST", "0")  # compile, do not interpret
    moments, quat, omega = _bodies(_fused_lanes.L + 1, seed=5)
    simulate(moments, quat, omega, np.linspace(0.0, 0.5, 3), rtol=1e-8)  # kind 0, diagonal
    kinds = [sig[3] for sig in _fused_lanes.integrate_batch.signatures]
    assert kinds and all(hasattr(k, "literal_value") for k in kinds), kinds
    assert _fused.DIAGONAL in [k.literal_value for k in kinds]
    assert _jit.ready(_fused_lanes.integrate_batch, _fused_lanes.compiled(_fused.DIAGONAL))
    assert not _jit.ready(_fused_lanes.integrate_batch, _fused_lanes.compiled(7))  # no kind 7
    # a new process reads the kinds off numba's cache index (nothing compiled in it yet)
    code = (
        "from poinsot import _jit\n"
        "from poinsot.dynamics import _fused_lanes as FL\n"
        "print(_jit.ready(FL.integrate_batch, FL.compiled(8)),"
        " _jit.ready(FL.integrate_batch, FL.compiled(7)), len(FL.integrate_batch.overloads))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "False", "0"], out


def test_a_plain_int_kind_is_refused_by_name():
    """The lanes compile per constant kind: a plain ``int`` would make numba type the
    whole kernel again on every call, so it is refused, naming what to pass instead."""
    with pytest.raises(TypeError, match=r"Kind\(kind\)"):
        _fused_lanes._rhs_lanes(np.zeros(_fused_lanes.N_WORK), 8)
