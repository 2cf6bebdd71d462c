"""The dual-spin gyrostat and the gravity-gradient pitch libration in the engines
(issue 44): the rotor as a second body on a hinge (MuJoCo, Drake, PyBullet), the
gravity-gradient torque at every stage of MuJoCo's integrator (``mjcb_passive``) and
before every PyBullet step.

Truths: poinsot's exact dual-spin and pitch-libration solutions (the cases' own
scoring), the total angular momentum ``K = R (J w + h)`` of the case at ``t = 0``, and
a general gyrostat (turned inertia, rotor axis off the principal axes) integrated by
SciPy's DOP853 on ``J w' + w x (J w + h) = 0`` (docs/theory.md §10.1).

Observed (mujoco 4.0.0, pybullet 3.2.7, drake 1.51.1), attitude errors (rad):

- dual-spin: MuJoCo RK4 1.49e-9 at 10 ms, 1.59e-13 at 1 ms (order 4: ratio 9.4e3);
  Euler 3.14e-2 at 10 ms, 2.76e-3 at 1 ms (order 1: ratio 11.4); implicit 2.63e-3 and
  implicitfast 2.76e-3 at 1 ms. Drake runge_kutta5 at accuracy 1e-13 5.1e-13 (pass);
  runge_kutta2 at a fixed 2 ms and 1 ms 1.58e-5 and 3.94e-6 (fail, order 2).
  PyBullet (reduced) 2.76e-3 at 1 ms, 2.73e-4 at 0.1 ms (order 1).
- pitch-libration (a 1e3 times longer time scale): MuJoCo RK4 5.0e-10 at 10 s,
  3.15e-11 at 5 s (ratio 15.9 = 2^4: each RK4 stage sees its own torque), 4.4e-14 at
  1 s; Euler 2.42e-3 at 10 s, 4.8e-4 at 2 s, 2.4e-4 at 1 s (order 1). PyBullet
  (reduced) the same to 4 digits: 2.42e-3 at 10 s, 4.8e-4 at 2 s, 2.4e-4 at 1 s.
- a wrong mapping on dual-spin (MuJoCo RK4, 1 ms): the hinge rate ``|h| / I_r`` without
  ``- a . w0`` 0.146 rad, the platform given ``J`` (rotor's transverse inertia counted
  twice) 0.163 rad; the right one 1.6e-13 rad.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from poinsot import Rotation
from poinsot.dynamics import euler_rhs
from poinsot.errors import InvalidInputError
from poinsot.kinematics import quat_rate
from poinsot.verify import _mujoco as mj
from poinsot.verify import cases, make, run

HAVE = {name: importlib.util.find_spec(module) is not None
        for name, module in (("mujoco", "mujoco"), ("pybullet", "pybullet"),
                             ("drake", "pydrake"))}  # fmt: skip


def need(engine: str) -> None:
    if not HAVE[engine]:
        pytest.skip(
            f"THE {engine.upper()} ADAPTER'S GYROSTAT AND PITCH LIBRATION ARE NOT TESTED: "
            f"the {engine} package is not installed; pip install 'poinsot[verify]'"
        )


def attitude(res) -> float:
    return float(res.metrics["attitude"]["value"])


def general_gyrostat():
    """A turned, non-flat inertia, a rotor axis off its principal axes, a turned q0."""
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8])
    inertia = turn.as_matrix() @ np.diag([1.5, 2.0, 2.5]) @ turn.as_matrix().T
    h = np.array([0.6, 1.2, -0.9])
    q0 = np.asarray(Rotation.from_rotvec([0.7, 0.2, -0.4]).as_quat(), dtype=float)
    w0 = np.array([0.4, 1.1, -0.6])
    return inertia, h, q0, w0


def reference(inertia, h, q0, w0, t):
    """DOP853 on the gyrostat's equations (torque -w x h), rtol 1e-12."""

    def rhs(_, y):
        return np.concatenate(
            [quat_rate(y[:4], y[4:]), euler_rhs(inertia, y[4:], -np.cross(y[4:], h))]
        )

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q0, w0]), method="DOP853",
                    t_eval=t, rtol=1e-12, atol=1e-15)  # fmt: skip
    return sol.y[:4].T, sol.y[4:].T


def momentum(q, w, inertia, h):
    return Rotation.from_quat(q).apply(w @ inertia.T + h)


# --- the mapping ----------------------------------------------------------------------


def test_rotor_inputs_reproduce_the_gyrostat():
    """``J_p + J_r - I_r a a^T = J`` and ``I_r (a . w0 + W0) = |h|``; a rotor too thin
    for its own triangle inequality, or too fat for the platform, is refused."""
    inertia, h, _, w0 = general_gyrostat()
    jp, jr, a, rate0 = mj.rotor_inputs(inertia, h, w0)
    ir = mj.ROTOR_AXIAL
    assert np.allclose(jp + jr - ir * np.outer(a, a), inertia, rtol=0, atol=1e-15)
    assert abs(ir * (a @ w0 + rate0) - np.linalg.norm(h)) < 1e-14
    assert np.allclose(jr @ a, ir * a)
    with pytest.raises(InvalidInputError, match="transverse"):
        mj.rotor_inputs(inertia, h, w0, axial=0.25, transverse=0.1)
    with pytest.raises(InvalidInputError, match="platform"):
        mj.rotor_inputs(inertia, h, w0, axial=1.0, transverse=1.4)
    with pytest.raises(InvalidInputError, match="rotor_momentum"):
        mj.rotor_inputs(inertia, np.zeros(3), w0)


# --- MuJoCo ---------------------------------------------------------------------------


def test_mujoco_total_momentum_at_the_start_is_the_case_s():
    """MuJoCo's angular momentum of the whole tree about its centre of mass (world
    axes, ``mj_subtreeVel``) at ``t = 0`` is the case's ``K = R (J w + h)``."""
    need("mujoco")
    import mujoco

    for inertia, h, q0, w0 in (
        general_gyrostat(),
        tuple(
            cases("dual-spin")[0].inputs[k] for k in ("inertia", "rotor_momentum", "q0", "omega0")
        ),
    ):
        model, data = mj.build(inertia=inertia, mass=1.0, com=np.zeros(3), q0=q0, omega0=w0,
                               gravity=np.zeros(3), fixed_point=False, integrator="RK4",
                               timestep=1e-3, rotor_momentum=h)  # fmt: skip
        mujoco.mj_subtreeVel(model, data)
        k = momentum(q0[None], w0[None], inertia, h)[0]
        assert np.max(np.abs(data.subtree_angmom[1] - k)) < 1e-13 * np.linalg.norm(k)


def test_mujoco_general_gyrostat_matches_dop853():
    need("mujoco")
    inertia, h, q0, w0 = general_gyrostat()
    t = np.linspace(0.0, 5.0, 51)
    q, w = mj.run_mujoco(inertia=inertia, mass=1.0, com=np.zeros(3), q0=q0, omega0=w0,
                         gravity=np.zeros(3), fixed_point=False, t=t, integrator="RK4",
                         timestep=1e-3, rotor_momentum=h)  # fmt: skip
    qe, we = reference(inertia, h, q0, w0, t)
    assert np.max(np.abs(w - we)) < 2e-11  # observed 1.3e-12
    assert np.max((Rotation.from_quat(qe).inv() * Rotation.from_quat(q)).magnitude()) < 2e-11


def test_mujoco_rk4_passes_dual_spin_at_fourth_order():
    need("mujoco")
    case = cases("dual-spin")[0]
    res = {h: run(make("mujoco", integrator="RK4", timestep=h), case) for h in (1e-2, 1e-3)}
    assert all(r.status == "pass" for r in res.values()), [r.reason for r in res.values()]
    assert attitude(res[1e-2]) < 1.5e-8  # observed 1.49e-9
    assert attitude(res[1e-3]) < 1.6e-12  # observed 1.59e-13
    assert attitude(res[1e-2]) / attitude(res[1e-3]) > 2e3  # order 4: observed 9.4e3


def test_mujoco_euler_fails_dual_spin_at_first_order():
    need("mujoco")
    case = cases("dual-spin")[0]
    res = {h: run(make("mujoco", integrator="Euler", timestep=h), case) for h in (1e-2, 1e-3)}
    assert all(r.status == "fail" for r in res.values())
    ratio = attitude(res[1e-2]) / attitude(res[1e-3])
    assert 8.0 < ratio < 15.0  # observed 11.4 (3.14e-2 and 2.76e-3 rad)
    assert attitude(res[1e-3]) > 1e-3


def test_mujoco_rk4_passes_pitch_libration_at_fourth_order():
    """The torque is re-evaluated at each RK4 stage (``mjcb_passive``) at the stage's
    time: halving the step divides the error by 2^4 (a torque frozen over the step
    would leave a first-order error of ~1e-3 rad, as Euler's)."""
    need("mujoco")
    case = cases("pitch-libration")[0]
    res = {h: run(make("mujoco", integrator="RK4", timestep=h), case) for h in (10.0, 5.0)}
    assert all(r.status == "pass" for r in res.values()), [r.reason for r in res.values()]
    assert attitude(res[10.0]) < 5e-9  # observed 5.0e-10
    ratio = attitude(res[10.0]) / attitude(res[5.0])
    assert 12.0 < ratio < 20.0  # observed 15.9


def test_mujoco_euler_fails_pitch_libration_at_first_order():
    need("mujoco")
    case = cases("pitch-libration")[0]
    res = {h: run(make("mujoco", integrator="Euler", timestep=h), case) for h in (10.0, 2.0)}
    assert all(r.status == "fail" for r in res.values())
    ratio = attitude(res[10.0]) / attitude(res[2.0])
    assert 4.0 < ratio < 6.5  # observed 5.03 (2.42e-3 and 4.8e-4 rad)


def test_mujoco_restores_the_passive_callback():
    need("mujoco")
    import mujoco

    def mine(m, d):  # pragma: no cover - never called: no model is stepped with it
        pass

    mujoco.set_mjcb_passive(mine)
    try:
        case = cases("pitch-libration")[0]
        run(make("mujoco", timestep=10.0), case)
        assert mujoco.get_mjcb_passive() is mine
    finally:
        mujoco.set_mjcb_passive(None)


@pytest.mark.parametrize("wrong", ["rate0 without a.w0", "rotor left out of J'"])
def test_mujoco_a_wrong_rotor_mapping_fails(monkeypatch, wrong):
    """The conventions matter: a hinge rate ``|h| / I_r`` (not minus ``a . w0``) or a
    platform of inertia ``J`` (the rotor's transverse inertia left out) fails the case
    by a wide margin, where the right mapping passes (1.6e-13 rad)."""
    need("mujoco")
    right = mj.rotor_inputs

    def mapped(inertia, h, w0, **kw):
        jp, jr, a, rate0 = right(inertia, h, w0, **kw)
        if wrong == "rate0 without a.w0":
            return jp, jr, a, rate0 + float(a @ np.asarray(w0))
        return np.asarray(inertia, dtype=float), jr, a, rate0

    monkeypatch.setattr(mj, "rotor_inputs", mapped)
    res = run(make("mujoco", integrator="RK4", timestep=1e-3), cases("dual-spin")[0])
    assert res.status == "fail"
    # observed 0.146 rad (the rate) and 0.163 rad (the inertia), 1e5 times the threshold
    assert attitude(res) > 1e-2, attitude(res)


# --- Drake ----------------------------------------------------------------------------


def test_drake_passes_dual_spin_and_skips_pitch():
    need("drake")
    res = run(make("drake"), cases("dual-spin")[0])
    assert res.status == "pass", res.reason
    assert attitude(res) < 5e-12  # observed 5.1e-13
    skip = run(make("drake"), cases("pitch-libration")[0])
    assert skip.status == "skip" and "LeafSystem" in skip.reason


def test_drake_fixed_step_rk2_fails_dual_spin_at_second_order():
    need("drake")
    case = cases("dual-spin")[0]
    res = {h: run(make("drake", integrator="runge_kutta2", step=h), case) for h in (2e-3, 1e-3)}
    assert all(r.status == "fail" for r in res.values())
    ratio = attitude(res[2e-3]) / attitude(res[1e-3])
    assert 3.0 < ratio < 5.5  # observed 4.00 (1.58e-5 and 3.94e-6 rad)


def test_drake_total_momentum_and_general_gyrostat():
    need("drake")
    import pydrake.multibody.plant as mplant
    import pydrake.multibody.tree as tree

    from poinsot.verify import _drake

    inertia, h, q0, w0 = general_gyrostat()
    plant, context, _ = _drake.build(tree, mplant, inertia, 1.0, q0, w0, np.zeros(3),
                                     np.zeros(3), np.zeros(3), h)  # fmt: skip
    k = plant.CalcSpatialMomentumInWorldAboutPoint(context, np.zeros(3)).rotational()
    assert np.max(np.abs(k - momentum(q0[None], w0[None], inertia, h)[0])) < 1e-13
    t = np.linspace(0.0, 5.0, 51)
    q, w, _ = _drake.run_drake(inertia=inertia, mass=1.0, q0=q0, omega0=w0,
                               gravity=np.zeros(3), t=t, rotor_momentum=h)  # fmt: skip
    qe, we = reference(inertia, h, q0, w0, t)
    assert np.max(np.abs(w - we)) < 1e-10  # observed 6.6e-12
    assert np.max((Rotation.from_quat(qe).inv() * Rotation.from_quat(q)).magnitude()) < 1e-10


# --- PyBullet -------------------------------------------------------------------------


def test_pybullet_dual_spin_converges_at_first_order():
    need("pybullet")
    case = cases("dual-spin")[0]
    res = {h: run(make("pybullet", timestep=h), case) for h in (1e-3, 1e-4)}
    assert all(r.status == "fail" for r in res.values())
    ratio = attitude(res[1e-3]) / attitude(res[1e-4])
    assert 8.0 < ratio < 12.0  # observed 10.1 (2.76e-3 and 2.73e-4 rad)


def test_pybullet_pitch_libration_converges_at_first_order():
    need("pybullet")
    case = cases("pitch-libration")[0]
    res = {h: run(make("pybullet", timestep=h), case) for h in (10.0, 2.0)}
    assert all(r.status == "fail" for r in res.values())
    ratio = attitude(res[10.0]) / attitude(res[2.0])
    assert 4.0 < ratio < 6.5  # observed 5.03 (2.42e-3 and 4.8e-4 rad)


def test_pybullet_general_gyrostat_is_first_order_close():
    need("pybullet")
    from poinsot.verify._pybullet import run_pybullet

    inertia, h, q0, w0 = general_gyrostat()
    t = np.linspace(0.0, 2.0, 21)
    qe, we = reference(inertia, h, q0, w0, t)
    err = []
    for step in (1e-3, 1e-4):
        q, w = run_pybullet(inertia=inertia, mass=1.0, q0=q0, omega0=w0, gravity=np.zeros(3),
                            t=t, timestep=step, rotor_momentum=h)  # fmt: skip
        err.append(np.max(np.abs(w - we)))
    assert 8.0 < err[0] / err[1] < 12.0 and err[1] < 1e-3  # observed 5.8e-4, 5.8e-5 rad/s


def test_pybullet_maximal_coordinates_skip_with_the_reason():
    eng = make("pybullet", coordinates="maximal")
    for name in ("dual-spin", "pitch-libration"):
        assert "maximal-coordinates" in eng.skip_reason(cases(name)[0])


def test_a_python_torque_at_a_tiny_step_is_skipped_with_the_step_to_use(capsys):
    """The engines' default 1 ms step on the 20000 s pitch libration would be 2e7 steps
    with the torque evaluated in Python (hours): skipped, naming the step that runs."""
    from poinsot.cli import main

    case = cases("pitch-libration")[0]
    for name in ("mujoco", "pybullet"):
        reason = make(name).skip_reason(case)
        assert reason and "2e+07 steps" in reason and "0.2 s or more" in reason
        assert make(name, timestep=0.2).skip_reason(case) in (None, "") or not HAVE[name]
    assert make("mujoco").skip_reason(cases("dual-spin")[0]) in (None, "") or not HAVE["mujoco"]
    need("mujoco")
    # dual-spin fails at a 10 s step (its wobble period is 3.8 s)
    assert main(["verify", "mujoco", "--step", "10", "--cases", "gyrostat,gravity-gradient",
                 "--quiet"]) == 1  # fmt: skip
    assert main(["verify", "mujoco", "--step", "10", "--cases", "pitch-libration",
                 "--quiet"]) == 0  # fmt: skip
    assert "1 passed" in capsys.readouterr().out


def test_basilisk_runs_dual_spin_and_skips_pitch_with_its_reason():
    """Basilisk's adapter runs dual-spin with a reaction wheel
    (tests/verify/test_engine_basilisk.py); without Basilisk the only reason is that."""
    eng = make("basilisk")
    reason = eng.skip_reason(cases("dual-spin")[0])
    assert reason is None or "not installed" in reason
    assert "gravity-gradient" in eng.skip_reason(cases("pitch-libration")[0])
