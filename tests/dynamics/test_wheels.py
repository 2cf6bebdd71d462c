"""Tests of reaction wheels (docs/theory.md §10.1, "Reaction wheels").

Oracles: the balance laws of the section (``K = R (J w + h)`` constant without external
torque; ``T' = sum_i (u_i + f_i) Omega_i``, the work integrated by Simpson's rule from the
samples); :class:`poinsot.dynamics.FreeGyrostat` (its Jacobi elliptic closed form) for
wheels without torque or friction, with ``J_f = J - I_w e3 e3^T`` and the constant
``h_f = I_w (Omega + w3) e3``; the closed form of a single-axis slew,
``theta = -(I_w / J3) phi``, ``theta = -u0 (t - sin t) / (J3 - I_w)`` for
``u = u0 sin t`` (Wie, *Space Vehicle Dynamics and Control*, 2nd ed., §7.3, momentum
exchange). Every tolerance is >= 10x the error observed (noted at each).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson

from poinsot import IntegrationError, InvalidInputError, InvalidTypeError, Rotation, compare
from poinsot.dynamics import (
    FreeGyrostat,
    ReactionWheels,
    WheelTrajectory,
    pyramid,
    simulate_wheels,
)

BETA = np.arccos(1.0 / np.sqrt(3.0))  # the pyramid with equal capacity about x, y, z


def _inertia():
    """A body inertia that is not diagonal in body axes (kg m^2)."""
    r = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()
    return r @ np.diag([10.0, 12.0, 8.0]) @ r.T


def _kdrift(tr):
    k = tr.momentum
    return float(np.max(np.linalg.norm(k - k[0], axis=-1)) / np.linalg.norm(k[0]))


# ---------------------------------------------------------------------------
# (a) total angular momentum without external torque
# ---------------------------------------------------------------------------


def _saturating_run():
    rw = pyramid(BETA, 0.01, max_torque=0.02, max_speed=200.0, viscous=1e-5, coulomb=1e-4)

    def command(t, q, w, om):
        return np.array(
            [0.05 * np.sin(0.7 * t), 0.03, -0.01 * np.cos(1.3 * t), 0.015 * np.sin(0.2 * t) + 0.01]
        )

    t = np.linspace(0.0, 30.0, 601)
    tr = simulate_wheels(
        _inertia(), rw, [1.0, 0, 0, 0], [0.05, -0.02, 0.03], [150.0, 120.0, 140.0, 180.0], t,
        command=command,
    )  # fmt: skip
    return rw, command, tr


@pytest.fixture(scope="module")
def saturating():
    return _saturating_run()


def test_momentum_conserved_with_saturation_and_friction(saturating):
    """No external torque: ``K = R (J w + h)`` is constant in space whatever the motors,
    the torque and speed limits and the friction do (they are internal torques).
    Observed relative drift 3.2e-12 (rtol 1e-10) over 30 s with torque clipping on three
    wheels, wheel 3 held at its speed limit, viscous and Coulomb friction."""
    rw, _, tr = saturating
    assert isinstance(tr, WheelTrajectory)
    assert np.max(np.abs(tr.motor_torque)) == pytest.approx(0.02)  # the limit was reached
    assert np.any(np.abs(tr.wheel_speed[:, 3]) >= 200.0)  # and the speed limit
    assert _kdrift(tr) < 5e-11
    assert tr.info["conserved"] == ("momentum",)
    assert tr.conserved_drifts()["momentum"] < 5e-11
    # h channel: sum_i I_i Omega_i a_i, body axes; K = R (J w + h)
    h = rw.momentum(tr.wheel_speed)
    assert np.array_equal(tr.wheel_momentum, h)
    k = tr.rotation.apply(np.einsum("ij,nj->ni", _inertia(), tr.omega) + h)
    assert np.max(np.abs(k - tr.momentum)) < 1e-13


def test_momentum_conserved_rk4():
    """The fixed-step RK4 on the same kind of run: order 4, observed K drift 2.9e-12
    (relative) with steps of 0.05 s over 10 s."""
    rw = pyramid(BETA, 0.01, max_torque=0.02, viscous=1e-5)
    t = np.linspace(0.0, 10.0, 51)
    tr = simulate_wheels(
        _inertia(), rw, [1.0, 0, 0, 0], [0.05, -0.02, 0.03], [50.0, -20.0, 40.0, 80.0], t,
        command=lambda t, q, w, om: 0.03 * np.sin([t, 2 * t, 0.5 * t, 3 * t]), method="rk4",
        max_step=0.05,
    )  # fmt: skip
    assert tr.method == "rk4" and tr.info["order"] == 4 and tr.info["steps"] == 200
    assert _kdrift(tr) < 5e-10


# ---------------------------------------------------------------------------
# (b) the energy balance: T' = sum_i (u_i + f_i) Omega_i
# ---------------------------------------------------------------------------


def test_energy_changes_by_motor_and_friction_work():
    """The kinetic energy of body and wheels changes by the work of the motor and
    friction torques on the *relative* wheel speeds, ``T' = sum_i (u_i + f_i) Omega_i``
    (no external torque). The work is integrated by Simpson's rule from the samples of
    ``motor_torque`` and ``wheel_speed``. Observed ``max |T(t) - T(0) - W(t)|`` 6.0e-10 J
    for a change of 18 J (T ~ 445 J, rtol 1e-12, Simpson on 0.01 s samples); the same
    with the absolute axial speed ``Omega + a.w`` in place of ``Omega`` misses by
    1.7e-3 J, 10^6 times more."""
    rw = pyramid(BETA, 0.01, viscous=2e-5, coulomb=3e-4)

    def command(t, q, w, om):
        return 0.01 * np.array([np.sin(0.5 * t), np.cos(0.3 * t), 0.5, -np.sin(0.9 * t)])

    t = np.linspace(0.0, 20.0, 2001)
    tr = simulate_wheels(
        _inertia(), rw, [1.0, 0, 0, 0], [0.05, -0.02, 0.03], [150.0, -120.0, 140.0, 180.0], t,
        command=command, rtol=1e-12, atol=1e-12,
    )  # fmt: skip
    drive = tr.motor_torque + rw.friction(tr.wheel_speed)
    work = cumulative_simpson(np.sum(drive * tr.wheel_speed, axis=1), x=t, initial=0.0)
    change = tr.energy - tr.energy[0]
    assert np.max(np.abs(change)) > 10.0
    assert np.max(np.abs(change - work)) < 1e-8
    # the motors' torque is the command (no limit reached)
    u = np.array([command(tk, None, None, None) for tk in t])
    assert np.array_equal(tr.motor_torque, u)
    # the energy is the formula of ReactionWheels.kinetic_energy
    e = rw.kinetic_energy(_inertia(), tr.omega, tr.wheel_speed)
    assert np.array_equal(e, tr.energy)
    # the wrong power (absolute axial speed) is far off: the test can tell
    absolute = tr.wheel_speed + tr.omega @ rw.axes.T
    wrong = cumulative_simpson(np.sum(drive * absolute, axis=1), x=t, initial=0.0)
    assert np.max(np.abs(change - wrong)) > 1e-4


def test_energy_conserved_without_motors_or_friction():
    """No command, no friction, no limit: ``T`` and ``K`` are both conserved (and
    ``info["conserved"]`` says so). Observed relative drifts 3.9e-14 and 1.9e-13."""
    rw = pyramid(BETA, 0.02)
    t = np.linspace(0.0, 10.0, 21)
    tr = simulate_wheels(_inertia(), rw, [1.0, 0, 0, 0], [0.3, -0.2, 0.1], [30.0, 0, -10, 5], t)
    assert tr.info["conserved"] == ("energy", "momentum")
    drifts = tr.conserved_drifts()
    assert drifts["energy"] < 1e-11 and drifts["momentum"] < 1e-11


# ---------------------------------------------------------------------------
# (c) free wheels are a free gyrostat
# ---------------------------------------------------------------------------


def test_free_wheel_is_free_gyrostat():
    """A wheel with no motor torque and no friction keeps its *absolute* axial momentum
    ``I_w (Omega + a.w)``: the body moves as :class:`FreeGyrostat` with
    ``J_f = J - I_w a a^T`` and ``h_f = I_w (Omega0 + a.w0) a`` (constant), here along
    the principal axis 3 (the Jacobi closed form, regime "four_roots"). Observed
    ``max |w - w_exact|`` 1.0e-12 rad/s, attitude 2.3e-11 rad, wheel speed 4.9e-13 rad/s
    over 20 s (rtol 1e-12)."""
    inertia = np.array([2.0, 3.0, 4.0])
    iw, om0 = 0.2, 5.0
    w0 = np.array([0.4, 1.1, -0.3])
    q0 = Rotation.from_rotvec([0.1, 0.2, -0.3])
    t = np.linspace(0.0, 20.0, 201)
    tr = simulate_wheels(
        inertia, ReactionWheels([[0.0, 0.0, 1.0]], iw), q0, w0, [om0], t, rtol=1e-12, atol=1e-14
    )
    hf = iw * (om0 + w0[2])
    g = FreeGyrostat(inertia - [0.0, 0.0, iw], [0.0, 0.0, hf], rotation0=q0, omega0=w0)
    assert g.regime == "four_roots"
    w_exact = g.omega(t)
    assert np.max(np.abs(tr.omega - w_exact)) < 1e-10
    assert np.max((g.rotation(t).inv() * tr.rotation).magnitude()) < 1e-9
    assert np.max(np.abs(tr.wheel_speed[:, 0] - (hf / iw - w_exact[:, 2]))) < 1e-10
    # the relative speed is not constant: the constant-h gyrostat with the locked J
    # (a wheel held at constant speed) is another motion
    assert np.ptp(tr.wheel_speed) > 0.1


# ---------------------------------------------------------------------------
# (d) single-axis slew: momentum exchange
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("method", "n", "tol_theta", "tol_exchange"),
    [
        # observed 1.6e-11 rad and 1.6e-11 rad (Simpson on 0.01 s samples)
        ("dop853", 1001, 2e-10, 2e-10),
        # observed 2.4e-10 rad (order 4, steps 0.05 s) and 2.2e-9 rad (Simpson, 0.05 s)
        ("rk4", 201, 1e-8, 3e-8),
    ],
)
def test_single_axis_slew(method, n, tol_theta, tol_exchange):
    """A body at rest turned about its principal axis 3 by one wheel on that axis:
    ``J3 theta' + I_w Omega = 0`` (``K = 0``, J locked) gives
    ``theta = -(I_w / J3) phi`` with ``phi`` the wheel's angle relative to the body, and
    for ``u = u0 sin t``: ``theta = -u0 (t - sin t) / (J3 - I_w)``."""
    j3, iw, u0 = 5.0, 0.1, 0.05
    t = np.linspace(0.0, 10.0, n)
    tr = simulate_wheels(
        [10.0, 10.0, j3], ReactionWheels([[0.0, 0.0, 1.0]], iw), [1.0, 0, 0, 0], [0, 0, 0],
        [0.0], t, command=lambda t, q, w, om: [u0 * np.sin(t)], method=method,
    )  # fmt: skip
    q = tr.quat
    theta = np.unwrap(2.0 * np.arctan2(q[:, 3], q[:, 0]))
    assert np.max(np.abs(tr.omega[:, :2])) == 0.0  # about axis 3 only
    assert np.max(np.abs(theta + u0 * (t - np.sin(t)) / (j3 - iw))) < tol_theta
    phi = cumulative_simpson(tr.wheel_speed[:, 0], x=t, initial=0.0)
    assert np.max(np.abs(theta + iw / j3 * phi)) < tol_exchange
    assert abs(theta[-1]) > 0.1


# ---------------------------------------------------------------------------
# (e) saturation
# ---------------------------------------------------------------------------


def test_speed_limit_holds_the_wheel(saturating):
    """Torque clipping and the speed limit in the run of (a). The motor torque is the
    command clipped at ``max_torque``, except for a wheel at its speed limit, which is
    held (its torque keeps ``Omega' = 0``). Observed overshoot of the limit 3.5e-10
    relative (the adaptive step that crosses it)."""
    rw, command, tr = saturating
    om = tr.wheel_speed
    assert np.max(np.abs(om) / rw.max_speed) < 1.0 + 1e-8
    assert np.max(np.abs(tr.motor_torque)) <= 0.02
    asked = np.clip([command(tk, None, None, None) for tk in tr.t], -0.02, 0.02)
    held = np.abs(om) >= rw.max_speed * (1.0 - 1e-12)
    assert held[:, 3].sum() > 50 and not held[:, :3].any()
    assert np.array_equal(tr.motor_torque[~held], asked[~held])
    assert np.all(tr.motor_torque[held] != asked[held])
    # held: the speed stays at the limit
    assert np.ptp(om[held[:, 3], 3]) < 1e-6


def test_spin_up_to_the_limit_then_cut():
    """One wheel on the spin axis 3 of a body spinning about it, commanded far beyond
    its torque limit: it accelerates at ``Omega' = u_max J3 / (I_w (J3 - I_w))`` until
    ``max_speed``, where the torque is cut to zero (nothing else drives the wheel) and the
    body's rate stays constant. Observed: speed 50 + 1.9e-7 rad/s at most (3.7e-9
    relative: the adaptive step that crosses the limit), speed before it 2.1e-14 rad/s,
    rate after it 3.7e-10 rad/s, K drift 8.9e-16."""
    j3, iw, umax, smax = 5.0, 0.01, 0.05, 50.0
    rw = ReactionWheels([[0.0, 0.0, 1.0]], iw, max_torque=umax, max_speed=smax)
    t = np.linspace(0.0, 15.0, 151)
    tr = simulate_wheels(
        [10.0, 10.0, j3], rw, [1.0, 0, 0, 0], [0, 0, 1.0], [0.0], t,
        command=lambda t, q, w, om: [1.0],
    )  # fmt: skip
    om = tr.wheel_speed[:, 0]
    rate = umax * j3 / (iw * (j3 - iw))
    t_full = smax / rate
    before = t < t_full
    assert np.max(om) < smax * (1.0 + 1e-7) and np.max(om) > smax * (1.0 - 1e-12)
    assert np.max(np.abs(om[before] - rate * t[before])) < 1e-9
    assert np.all(tr.motor_torque[before] == umax)
    assert np.all(tr.motor_torque[t > t_full + 0.1] == 0.0)
    # body rate: J_f3 w3' = -u until t_full, then constant
    w_end = 1.0 - umax * t_full / (j3 - iw)
    assert np.max(np.abs(tr.omega[t > t_full, 2] - w_end)) < 5e-9
    assert _kdrift(tr) < 1e-11


def test_hold_beyond_the_motor_torque():
    """A wheel whose holding torque would exceed ``max_torque`` gets the full torque
    against the drift and moves past its limit (the limit is the motor's, not a stop);
    ``K`` is still conserved. Observed: three wheels reach 10.4 to 13.4 rad/s, the
    fourth is held at 10 rad/s; K drift 1.3e-10 (the hold switching on and off at the
    limit within the steps)."""
    rw = pyramid(BETA, 0.05, max_torque=1e-4, max_speed=10.0)
    t = np.linspace(0.0, 5.0, 51)
    speed0 = [10.0, -10.0, 10.0, -10.0]
    tr = simulate_wheels(_inertia(), rw, [1.0, 0, 0, 0], [2.0, -1.5, 1.0], speed0, t)
    assert np.max(np.abs(tr.motor_torque)) <= 1e-4
    assert np.max(np.abs(tr.wheel_speed)) > 13.0
    assert _kdrift(tr) < 2e-9


# ---------------------------------------------------------------------------
# results and helpers
# ---------------------------------------------------------------------------


def test_result_channels_and_compare(saturating):
    """Channels with units; the wheel speeds are part of the state compared."""
    _, _, tr = saturating
    ch = tr.channels()
    assert ch["wheel_speed"].units == "rad/s"
    assert ch["wheel_speed"].components == ("0", "1", "2", "3")
    assert ch["wheel_momentum"].units == "kg m^2/s" and ch["motor_torque"].units == "N m"
    assert ch["energy"].units == "J" and ch["momentum"].units == "kg m^2/s"
    assert list(tr.state_channels()) == ["attitude", "omega", "wheel_speed"]
    assert compare(tr, tr).worst.max == 0.0
    import pickle

    back = pickle.loads(pickle.dumps(tr))
    assert np.array_equal(back.wheel_speed, tr.wheel_speed)
    assert not tr.wheel_speed.flags.writeable


def test_pyramid_geometry():
    """``a_i = (sin b cos a_i, sin b sin a_i, cos b)``: ``sum a a^T = diag(2 s^2, 2 s^2,
    4 c^2)``, isotropic (4/3 E) at ``cos b = 1/sqrt 3``; degrees and radians agree."""
    rw = pyramid(BETA, 0.02)
    assert np.allclose(rw.axial_inertia, 0.02 * 4.0 / 3.0 * np.eye(3), atol=1e-15)
    deg = pyramid(np.degrees(BETA), 0.02, degrees=True)
    assert np.allclose(deg.axes, rw.axes, atol=1e-15)
    assert np.allclose(np.linalg.norm(rw.axes, axis=1), 1.0)


# ---------------------------------------------------------------------------
# (f) bad inputs
# ---------------------------------------------------------------------------

Z = [[0.0, 0.0, 1.0]]


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"axes": [0.0, 0.0, 1.0], "inertia": 0.1}, InvalidInputError, "`axes`.*shape \\(N, 3\\)"),
        ({"axes": [[0.0, 0.0, 2.0]], "inertia": 0.1}, InvalidInputError, "`axes` to be unit"),
        ({"axes": Z, "inertia": -0.1}, InvalidInputError, "`inertia` to be finite positive"),
        ({"axes": Z, "inertia": [0.1, 0.2]}, InvalidInputError, "`inertia`.*shape \\(1,\\)"),
        ({"axes": Z, "inertia": "a"}, InvalidTypeError, "`inertia`"),
        ({"axes": Z, "inertia": 0.1, "max_speed": 0.0}, InvalidInputError, "`max_speed`"),
        ({"axes": Z, "inertia": 0.1, "max_torque": np.nan}, InvalidInputError, "`max_torque`"),
        ({"axes": Z, "inertia": 0.1, "viscous": -1.0}, InvalidInputError, "`viscous`"),
        ({"axes": Z, "inertia": 0.1, "coulomb": np.inf}, InvalidInputError, "`coulomb`"),
    ],
)
def test_bad_wheels(kwargs, error, match):
    with pytest.raises(error, match=match):
        ReactionWheels(**kwargs)


def test_bad_pyramid():
    with pytest.raises(InvalidInputError, match="`beta` to be a scalar"):
        pyramid([0.1, 0.2], 0.1)
    with pytest.raises(InvalidTypeError, match="`degrees`"):
        pyramid(0.1, 0.1, degrees=1)


RW = ReactionWheels(Z, 0.1, max_speed=100.0)
GOOD = {"inertia": [1.0, 1.0, 1.0], "wheels": RW, "rotation0": [1.0, 0, 0, 0],
        "omega0": [0.0, 0, 0], "wheel_speed0": [0.0], "t": [0.0, 1.0]}  # fmt: skip


@pytest.mark.parametrize(
    ("change", "error", "match"),
    [
        ({"wheels": "x"}, InvalidTypeError, "`wheels` to be a ReactionWheels"),
        ({"wheel_speed0": [0.0, 1.0]}, InvalidInputError, "`wheel_speed0` to have shape \\(1,\\)"),
        ({"wheel_speed0": [101.0]}, InvalidInputError, "`wheel_speed0` within `max_speed`"),
        ({"inertia": [1.0, 1.0, 0.1]}, InvalidInputError, "`inertia` to contain the wheels"),
        ({"inertia": [[1.0, 1.0, 1.0]] * 2}, InvalidInputError, "`inertia` for one body"),
        ({"rotation0": [[1.0, 0, 0, 0]] * 2}, InvalidInputError, "`rotation0`.*one body"),
        ({"omega0": [0.0, 0.0]}, InvalidInputError, "`omega0`"),
        ({"t": [1.0, 0.0]}, InvalidInputError, "`t`"),
        ({"command": 3.0}, InvalidTypeError, "`command` to be callable"),
        ({"command": lambda t, q, w, om: [1.0, 2.0]}, InvalidInputError, "`command` to return"),
        ({"command": lambda t, q, w, om: [np.nan]}, IntegrationError, "`command` returned NaN"),
        ({"torque": lambda t, r, w: [1.0, 2.0]}, InvalidInputError, "`torque` to return"),
        ({"method": "euler"}, InvalidInputError, "`method`"),
        ({"method": "rk4", "rtol": 1e-8}, InvalidInputError, "`rtol`/`atol`"),
        ({"rtol": -1.0}, InvalidInputError, "`rtol`"),
        ({"max_step": 0.0}, InvalidInputError, "`max_step`"),
    ],
)
def test_bad_simulate(change, error, match):
    with pytest.raises(error, match=match):
        simulate_wheels(**{**GOOD, **change})


def test_bad_result_and_helpers():
    with pytest.raises(InvalidInputError, match="`wheel_speed`"):
        WheelTrajectory(np.zeros(2), Rotation.identity((2,)), np.zeros((2, 3)), "x")
    with pytest.raises(InvalidInputError, match="`wheel_speed` to have shape"):
        RW.momentum([1.0, 2.0])
