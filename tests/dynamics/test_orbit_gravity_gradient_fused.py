"""The orbit's gravity gradient in the fused compiled integrators: ``simulate(...,
torque=OrbitGravityGradientTorque(J, KeplerOrbit(...)))`` runs as torque kind 6 of
:mod:`poinsot.dynamics._fused` (Kepler's equation solved inside the right-hand side,
docs/theory.md §10.2).

Oracles: the same model on the Python path (a subclass of the model, which the kernels
do not take: SciPy's DOP853 for ``method="dop853"``, the NumPy steps for RK4 and the
midpoint rule); the exact planar pitch libration (:class:`PitchLibration`, Jacobi
elliptic functions) in a circular orbit; the one-body kernel against the lanes (bit for
bit); orbit.py's NumPy Kepler solve against the kernel's; the fixed-step methods'
orders against a tight DOP853 run. Every tolerance is >= 10x the error observed (noted).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poinsot import Rotation
from poinsot._jit import NUMBA
from poinsot.dynamics import (
    KeplerOrbit,
    OrbitGravityGradientTorque,
    PitchLibration,
    orbit_frame,
    simulate,
)
from poinsot.dynamics.orbit import _solve_kepler

COMPILED = "DOP853 (compiled"


class _PythonOrbitGG(OrbitGravityGradientTorque):
    """The same model, but not the kernels' own class: ``simulate`` evaluates it from
    Python (its ``body_torque``, the NumPy formula of torques.py)."""


CIRCULAR = KeplerOrbit(7.0e6, 0.0, 0.9, 0.4, 0.0, 0.3)
ECCENTRIC = KeplerOrbit(7.5e6, 0.3, 1.1, -0.7, 2.0, 0.4, epoch=-1234.5)


def _bodies(n, seed, tensor):
    """Heterogeneous bodies: principal moments with the triangle inequality, random
    attitudes, rates of a few orbit rates; principal axes turned when ``tensor``."""
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))
    if tensor:
        axes = Rotation.random((n,), rng=seed).as_matrix()
        j = np.einsum("nij,nj,nkj->nik", axes, moments, axes)
    else:
        j = moments
    quat = Rotation.random((n,), rng=seed + 1).as_quat()
    omega = rng.normal(size=(n, 3)) * 3e-3
    return j, quat, omega


def _angle(a, b):
    """Rotation angle between unit quaternions ``a`` and ``b`` (rad)."""
    d = np.minimum(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))
    return 4.0 * np.arcsin(np.minimum(d / 2.0, 1.0))  # |q - p| = 2 sin(angle / 4)


@pytest.mark.parametrize(("orbit", "tensor"), [(CIRCULAR, False), (CIRCULAR, True),
                                               (ECCENTRIC, False), (ECCENTRIC, True)])  # fmt: skip
def test_compiled_equals_the_python_path(orbit, tensor):
    n = 11  # the lanes (8) and a short block
    j, quat, omega = _bodies(n, seed=3, tensor=tensor)
    t = np.linspace(100.0, 100.0 + orbit.period, 9)
    a = simulate(j, quat, omega, t, torque=OrbitGravityGradientTorque(j, orbit),
                 rtol=1e-12, atol=1e-14)  # fmt: skip
    b = simulate(j, quat, omega, t, torque=_PythonOrbitGG(j, orbit), rtol=1e-12, atol=1e-14)
    assert a.info["solver"].startswith(COMPILED) and "path" not in a.info
    assert b.info["path"].startswith("solve_ivp")
    # observed over one orbit (two solvers, each at rtol 1e-12): omega <= 2.1e-14 rad/s
    # (rates ~3e-3 rad/s) and attitude <= 1.9e-11 rad
    assert np.abs(a.omega - b.omega).max() < 3e-13
    assert _angle(a.quat, b.quat).max() < 3e-10


def test_kernel_torque_equals_the_model():
    """The kernel's torque (kind 6, par from torque_kernel) at given t and attitudes
    against ``OrbitGravityGradientTorque.body_torque``."""
    from poinsot.dynamics import _fused, _fused_run

    j = np.array([[3.0, 0.1, 0.2], [0.1, 4.0, -0.3], [0.2, -0.3, 5.0]])
    q = Rotation.random((7,), rng=5).as_quat()
    for orbit in (CIRCULAR, ECCENTRIC, KeplerOrbit(7e6, 0.95, 0.2, 0.3, 0.4, 3.0)):
        model = OrbitGravityGradientTorque(j, orbit)
        kind, par = _fused_run.torque_kernel(model, ())
        assert kind == _fused.KEPLER
        for t in (-5e4, 0.0, 777.0, 3.3e5):
            want = model.body_torque(t, q, np.zeros(3))
            got = np.array([_fused._torque(t, *qq, 0.0, 0.0, 0.0, j, kind, par) for qq in q])
            # observed <= 6.7e-14 relative: the rounding of M = M_0 + n t at t = 3.3e5 s
            # (M ~ 360 rad), which the two write differently
            scale = np.abs(want).max()
            assert np.abs(got - want).max() < 1e-12 * scale


def test_other_orbits_and_mu_take_the_python_path():
    from poinsot.dynamics import _fused_run

    class Circle:
        def position(self, t):
            return 7e6 * np.array([np.cos(1e-3 * t), np.sin(1e-3 * t), 0.0])

    j = [1.0, 2.0, 3.0]
    assert _fused_run.torque_kernel(OrbitGravityGradientTorque(j, Circle()), ()) is None
    other_mu = OrbitGravityGradientTorque(j, CIRCULAR, mu=3.0e14)
    assert _fused_run.torque_kernel(other_mu, ()) is None
    assert _fused_run.torque_kernel(_PythonOrbitGG(j, CIRCULAR), ()) is None
    # the model's inertia is not the body's: the Python path, which uses the model's
    t = np.linspace(0.0, 500.0, 3)
    tr = simulate([1.0, 2.0, 2.5], [1.0, 0, 0, 0], [0.0, 1e-3, 0.0], t,
                  torque=OrbitGravityGradientTorque(j, CIRCULAR), method="dop853")  # fmt: skip
    assert tr.info["path"].startswith("solve_ivp")


def test_pitch_libration_of_a_batch_in_a_circular_orbit():
    """Bodies started in the orbit plane (pitch axis along the orbit normal) librate in
    pitch exactly as :class:`PitchLibration` says; 9 bodies (the lanes)."""
    orbit = KeplerOrbit(6.9e6, 0.0, 0.5, 1.0, 0.0, 2.0)
    n = orbit.mean_motion
    k = 9
    rng = np.random.default_rng(11)
    inertia = np.stack([rng.uniform(2.0, 2.5, k), rng.uniform(2.6, 2.8, k),
                        rng.uniform(0.8, 1.2, k)], axis=-1)  # fmt: skip
    theta0 = rng.uniform(-0.8, 0.8, k)
    rate0 = rng.uniform(-0.6, 0.6, k) * n
    t = np.linspace(0.0, 2.0 * orbit.period, 41)
    frame0 = orbit_frame(*orbit.state(0.0), frame="lvlh")
    rot0 = frame0 * Rotation.from_euler("y", theta0)
    omega0 = np.stack([np.zeros(k), rate0 - n, np.zeros(k)], axis=-1)
    tr = simulate(inertia, rot0, omega0, t, torque=OrbitGravityGradientTorque(inertia, orbit),
                  rtol=1e-12, atol=1e-14)  # fmt: skip
    assert tr.info["solver"].startswith(COMPILED) and "path" not in tr.info
    frames = orbit_frame(*orbit.state(t), frame="lvlh")
    for b in range(k):
        lib = PitchLibration(inertia[b], n, theta0=theta0[b], rate0=rate0[b])
        rel = frames.inv() * Rotation.from_quat(tr.quat[:, b])
        rv = rel.as_rotvec()
        # observed: out of plane 6.1e-15 rad, pitch 2.7e-11 rad, rate 4.6e-11 n (all librate)
        assert np.abs(rv[:, [0, 2]]).max() < 1e-9
        err = np.abs(np.angle(np.exp(1j * (rv[:, 1] - lib.theta(t))))).max()
        assert err < 1e-8
        assert np.abs(tr.omega[:, b, 1] + n - lib.rate(t)).max() / n < 1e-8


@pytest.mark.skipif(not NUMBA, reason="the lane kernels are numba's")
@pytest.mark.parametrize("tensor", [False, True])
def test_lanes_equal_the_one_body_kernel_bit_for_bit(tensor):
    from poinsot.dynamics import _fused_lanes, _fused_run

    n = 2 * _fused_lanes.L + 3
    j, quat, omega = _bodies(n, seed=7, tensor=tensor)
    omega[::3] *= 10.0  # uneven step counts: lanes take new bodies at different times
    t = np.linspace(-300.0, -300.0 + 0.7 * ECCENTRIC.period, 6)  # t0 != 0, dense outputs
    model = OrbitGravityGradientTorque(j, ECCENTRIC)
    j = model.inertia  # validated (symmetric): the kernels take the model's own inertia
    out = []
    for lanes in (True, False):
        _fused_run.LANES = lanes
        try:
            out.append(_fused_run.integrate(j, quat, omega, t, model, rtol=1e-10, atol=1e-12,
                                            max_step=None))  # fmt: skip
        finally:
            _fused_run.LANES = True
    for x, y in zip(out[0], out[1], strict=True):
        np.testing.assert_array_equal(x, y)
    assert np.all(out[0][2][..., 3] == 0)


@pytest.mark.parametrize("e", [0.0, 0.5, 0.95])
def test_kernel_kepler_solve_equals_orbit_py(e):
    from poinsot import _numba_helpers as nh

    mean = np.linspace(-math.pi, math.pi, 4001, endpoint=False)
    mean = np.concatenate([mean, [-1e-300, 1e-12, -1e-7, math.pi - 1e-9, -math.pi]])
    want = _solve_kepler(mean, e)
    got = np.array([nh.kepler(m, e) for m in mean])
    # observed: E within 5.6e-16 of the NumPy solve (e = 0.95; 4.4e-16 at 0.5, 0 at 0);
    # cos E and sin E within 3.3e-16 of those of E; residual of Kepler's equation
    # <= 8.9e-16 = 2 ulp(pi)
    assert np.abs(got[:, 0] - want).max() <= 4 * np.spacing(math.pi)
    assert np.abs(got[:, 1] - np.cos(got[:, 0])).max() < 4e-15
    assert np.abs(got[:, 2] - np.sin(got[:, 0])).max() < 4e-15
    resid = got[:, 0] - e * np.sin(got[:, 0]) - mean
    assert np.abs(resid).max() <= 4 * np.spacing(math.pi)


@pytest.mark.parametrize(("method", "order"), [("rk4", 4), ("midpoint", 2)])
def test_fixed_step_methods_converge_at_their_orders(method, order):
    j, quat, omega = _bodies(3, seed=21, tensor=True)
    orbit = ECCENTRIC
    t = np.linspace(50.0, 50.0 + 0.25 * orbit.period, 3)
    model = OrbitGravityGradientTorque(j, orbit)
    ref = simulate(j, quat, omega, t, torque=model, rtol=1e-13, atol=1e-15)
    errs, angles = [], []
    for h in (10.0, 5.0):
        tr = simulate(j, quat, omega, t, torque=model, method=method, max_step=h)
        assert tr.info.get("path", "compiled") == "compiled"
        errs.append(np.abs(tr.omega - ref.omega).max())
        angles.append(_angle(tr.quat, ref.quat).max())
    # observed: rk4 omega errors 2.3e-10, 1.5e-11 (order 3.995, attitude 4.000); midpoint
    # 2.2e-6, 5.5e-7 (1.9995, attitude 1.9988)
    assert abs(math.log2(errs[0] / errs[1]) - order) < 0.05
    assert abs(math.log2(angles[0] / angles[1]) - order) < 0.05
    # the Python path's steps (the torque's times: RK4's stage times, the midpoint time)
    py = simulate(j, quat, omega, t, torque=_PythonOrbitGG(j, orbit), method=method, max_step=5.0)
    assert py.info["path"].startswith("NumPy")
    dw, da = np.abs(tr.omega - py.omega).max(), _angle(tr.quat, py.quat).max()
    if method == "midpoint":  # the same operations: observed 1.1e-16 rad/s, 8.9e-14 rad
        assert dw < 3e-15 and da < 3e-12
    else:
        # the NumPy torque takes RK4's stage quaternions (not unit) as unit ones (the
        # kernel divides by |q|^2): the paths differ within the truncation error, observed
        # 1/11 (omega, 1.3e-12 rad/s) and 1/21 (attitude, 1.0e-9 rad) of it
        assert dw < errs[1] and da < angles[1]
