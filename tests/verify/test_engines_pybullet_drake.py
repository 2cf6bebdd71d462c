"""The PyBullet and Drake adapters of poinsot verify against the real engines (issue 44).

Truths: poinsot's exact Euler-Poinsot solutions, and a steady spin about a principal
axis (constant body-axes omega, attitude ``q0 * (cos(wt/2), sin(wt/2) n)``), which
checks the quaternion order and the frame of the angular velocity on their own.

Observed (pybullet 3.2.7, drake 1.51.1): Drake's runge_kutta5 at accuracy 1e-13 (the default)
passes every free body (attitude <= 3.1e-8 rad, on the racket flip); its fixed-step
runge_kutta2 fails the racket flip (2.7e-4 rad at 1 ms). PyBullet steps by first-order
semi-implicit Euler: the racket flip is 1.0 rad off at 10 ms, 0.10 rad at 1 ms and 0.010
rad at 0.1 ms, so it passes no case at a practical step; the test holds it to that order.
"""

from __future__ import annotations

import importlib.util
import sys

import numpy as np
import pytest

from poinsot import Rotation
from poinsot.cli import main
from poinsot.dynamics import FreeRigidBody
from poinsot.errors import InvalidInputError
from poinsot.verify import cases, make, run

HAVE = {
    "pybullet": importlib.util.find_spec("pybullet") is not None,
    "drake": importlib.util.find_spec("pydrake") is not None,
}


def need(engine: str) -> None:
    if not HAVE[engine]:
        pytest.skip(
            f"THE {engine.upper()} ADAPTER IS NOT TESTED: the {engine} package is not "
            f"installed; pip install {engine}  (or pip install 'poinsot[verify]')"
        )


#: the free bodies of cases version 1 (version 2 adds the near-separatrix pair, which
#: Drake's error control does not pass: see test_drake_error_control_misses_the_separatrix)
FREE4 = "free-minor-axis,free-major-axis,racket-flip,free-symmetric"


def attitude_error(q: np.ndarray, exact: np.ndarray) -> float:
    return float(np.max((Rotation.from_quat(exact).inv() * Rotation.from_quat(q)).magnitude()))


def steady_spin(rate: float, t: np.ndarray):
    """A non-diagonal inertia, a turned attitude and a spin about a principal axis:
    body and space axes differ, and the inertia's principal frame is not the body's."""
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8])
    inertia = turn.as_matrix() @ np.diag([1.0, 2.0, 3.0]) @ turn.as_matrix().T
    axis = turn.as_matrix()[:, 2]  # the axis of greatest inertia, in body axes
    q0 = np.asarray(Rotation.from_rotvec([0.7, 0.2, -0.4]).as_quat(), dtype=float)
    spin = Rotation.from_rotvec(rate * t[:, None] * axis[None, :])
    exact_q = np.asarray((Rotation.from_quat(q0) * spin).as_quat(), dtype=float)
    return inertia, q0, rate * axis, exact_q


# --- PyBullet -------------------------------------------------------------------------


def test_pybullet_converges_at_first_order_to_the_exact_free_bodies():
    need("pybullet")
    for case in cases(FREE4):
        coarse = run(make("pybullet", timestep=1e-3), case)
        fine = run(make("pybullet", timestep=1e-4), case)
        assert coarse.status == fine.status == "fail", case.name  # first order: 1e-6 is out
        e1, e2 = (r.metrics["attitude"]["value"] for r in (coarse, fine))
        assert 8.0 < e1 / e2 < 12.0, (case.name, e1, e2)  # observed 9.96-10.1
        assert e2 < 2e-2  # observed <= 1.05e-2 rad (the racket flip)


def test_pybullet_maximal_coordinates_also_converge():
    need("pybullet")
    case = cases("free-symmetric")[0]
    e = [run(make("pybullet", timestep=h, coordinates="maximal"), case).metrics["attitude"]
         ["value"] for h in (1e-3, 1e-4)]  # fmt: skip
    assert 8.0 < e[0] / e[1] < 12.0 and e[1] < 2e-3  # observed 9.5e-3, 9.6e-4 rad


def test_pybullet_coarse_step_fails_the_racket_flip():
    need("pybullet")
    res = run(make("pybullet", timestep=1e-2), cases("racket-flip")[0])
    assert res.status == "fail" and res.metrics["attitude"]["value"] > 0.5  # observed 1.08


@pytest.mark.parametrize("coordinates", ["reduced", "maximal"])
def test_pybullet_conventions_steady_spin(coordinates):
    need("pybullet")
    from poinsot.verify._pybullet import run_pybullet

    t = np.linspace(0.0, 2.0, 21)
    inertia, q0, w0, exact_q = steady_spin(1.5, t)
    q, w = run_pybullet(inertia=inertia, mass=2.0, q0=q0, omega0=w0, gravity=np.zeros(3),
                        t=t, timestep=1e-3, coordinates=coordinates)  # fmt: skip
    assert np.max(np.abs(w - w0)) < 1e-9  # body-axes omega, constant
    assert attitude_error(q, exact_q) < 1e-6
    # the same run read as world-axes omega, or with the scalar last, would be far off
    assert np.max(np.abs(Rotation.from_quat(q).apply(w) - w0)) > 0.1
    assert attitude_error(np.roll(q, -1, axis=1), exact_q) > 0.1


def test_pybullet_times_between_steps_leave_the_run_unchanged():
    """A grid time between two steps (0.005 s at a 2 ms step) is read by one shorter
    step from a saved state: the run itself is unchanged, bit for bit."""
    need("pybullet")
    from poinsot.verify._pybullet import run_pybullet

    kw = dict(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0, q0=[1.0, 0.0, 0.0, 0.0],
              omega0=[0.1, 4.0, 0.1], gravity=np.zeros(3), timestep=0.002)  # fmt: skip
    qa, wa = run_pybullet(t=np.arange(201) * 0.005, **kw)
    qb, wb = run_pybullet(t=np.arange(101) * 0.01, **kw)
    assert np.array_equal(qa[::2], qb) and np.array_equal(wa[::2], wb)
    qc, _ = run_pybullet(t=np.arange(1001) * 0.001, **{**kw, "timestep": 0.001})
    assert np.max(np.abs(qa - qc[::5])) < 1e-3  # first order: observed 8.3e-5


# --- Drake ----------------------------------------------------------------------------


def test_drake_rk5_passes_the_free_bodies():
    need("drake")
    for case in cases(FREE4):
        res = run(make("drake"), case)
        assert res.status == "pass", (case.name, res.reason)
        assert res.metrics["attitude"]["value"] < 2e-7  # observed <= 3.1e-8 rad
        assert res.work and res.work > 0


def test_drake_error_control_misses_the_separatrix():
    """A finding of the scorecard (docs/verify.md): near the separatrix (1 - k^2 = 1e-6)
    runge_kutta5 under error control at accuracy 1e-13 ends ~7e-5 rad off (observed
    6.97e-05), while its energy holds; the same scheme at a fixed 1 ms step passes."""
    need("drake")
    res = run(make("drake"), cases("separatrix-minor")[0])
    assert res.status == "fail" and 1e-5 < res.metrics["attitude"]["value"] < 1e-3


def test_drake_fixed_step_rk2_fails_the_racket_flip():
    need("drake")
    res = run(make("drake", integrator="runge_kutta2", step=1e-3), cases("racket-flip")[0])
    assert res.status == "fail" and res.metrics["attitude"]["value"] > 1e-4  # observed 2.7e-4


def test_drake_conventions_steady_spin_and_general_axes():
    need("drake")
    from poinsot.verify._drake import run_drake

    t = np.linspace(0.0, 2.0, 21)
    inertia, q0, w0, exact_q = steady_spin(1.5, t)
    q, w, _ = run_drake(inertia=inertia, mass=2.0, q0=q0, omega0=w0, gravity=np.zeros(3), t=t)
    assert np.max(np.abs(w - w0)) < 1e-9
    assert attitude_error(q, exact_q) < 1e-9
    assert np.max(np.abs(Rotation.from_quat(q).apply(w) - w0)) > 0.1
    assert attitude_error(np.roll(q, -1, axis=1), exact_q) > 0.1
    # a general motion: not a principal axis, so the products of inertia count
    w1 = np.array([0.4, 1.5, -0.6])
    t = np.linspace(0.0, 5.0, 51)
    q, w, _ = run_drake(inertia=inertia, mass=2.0, q0=q0, omega0=w1, gravity=np.zeros(3), t=t)
    we, re = FreeRigidBody(inertia, rotation0=q0, omega0=w1).state(t)
    assert np.max(np.abs(w - we)) < 1e-8
    assert np.max((re.inv() * Rotation.from_quat(q)).magnitude()) < 1e-8


# --- both -----------------------------------------------------------------------------


def test_bad_options_are_named():
    for name, opts, word in (
        ("pybullet", {"coordinates": "full"}, "coordinates"),
        ("pybullet", {"timestep": -1.0}, "timestep"),
        ("drake", {"integrator": "rk4"}, "integrator"),
        ("drake", {"integrator": "runge_kutta2"}, "step"),
        ("drake", {"step": 1e-3, "accuracy": 1e-9}, "not both"),
        ("drake", {"accuracy": 0.0}, "accuracy"),
    ):
        with pytest.raises(InvalidInputError, match=word):
            make(name, **opts)


def test_skips_are_explained(monkeypatch):
    for name, word in (("pybullet", "point-to-point"), ("drake", "BallRpyJoint")):
        eng = make(name)
        assert word in eng.skip_reason(cases("top-loops")[0])
        assert "turning frame" in eng.skip_reason(cases("foucault")[0])
    # an engine that is not installed skips with the pip command
    monkeypatch.setitem(sys.modules, "pybullet", None)
    monkeypatch.setitem(sys.modules, "pydrake", None)
    for name in ("pybullet", "drake"):
        assert "pip install" in make(name).skip_reason(cases("racket-flip")[0])


def test_cli_verdicts(capsys):
    need("pybullet")
    need("drake")
    assert main(["verify", "drake", "--cases", FREE4, "--quiet"]) == 0
    assert "4 passed" in capsys.readouterr().out
    assert main(["verify", "drake", "--method", "runge_kutta2", "--step", "0.001", "--cases",
                 "racket-flip", "--quiet"]) == 1  # fmt: skip
    assert main(["verify", "pybullet", "--step", "0.01", "--cases", "racket-flip,top-loops",
                 "--quiet"]) == 1  # fmt: skip
    assert "verdict: FAIL (0 passed, 1 failed, 0 missing, 1 skipped)" in capsys.readouterr().out
