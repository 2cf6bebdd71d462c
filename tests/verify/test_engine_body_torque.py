"""The ``body-torque`` case (a constant torque fixed in body axes, issue 44) in the
engines: MuJoCo adds it to the free joint's rotational ``qfrc_passive`` entries (their
generalized force is the torque in body axes) at every evaluation of the dynamics
(``mjcb_passive``); PyBullet (reduced coordinates) turns it to world axes before every
step (``applyExternalTorque``). Drake skips it with its reason; Basilisk
(``extForceTorque``) is tested in tests/verify/test_engine_basilisk.py.

Truths: the case's stored 32-digit reference (its scoring) and the closed-form angular
velocity ``w_3 = w_30 + M t / C`` with ``w_1 + i w_2`` turning; a torque about the
symmetry axis of a body with a transverse rate, so a torque read in world axes would
be far off (checked).

Observed (mujoco 4.0.0, pybullet 3.2.7), attitude errors (rad), 10 s:

- MuJoCo RK4 5.19e-8 at 10 ms, 3.22e-9 at 5 ms (ratio 16.1), 4.9e-12 at 1 ms (pass);
  Euler 3.51e-2 at 1 ms, 1.74e-2 at 0.5 ms (ratio 2.02); implicitfast 2.94e-2 at 1 ms.
- PyBullet (reduced) 3.51e-2 at 1 ms, 1.74e-2 at 0.5 ms (ratio 2.02): first order, it
  fails at every practical step.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from poinsot.verify import cases, make, run

HAVE = {name: importlib.util.find_spec(module) is not None
        for name, module in (("mujoco", "mujoco"), ("pybullet", "pybullet"))}  # fmt: skip


def need(engine: str) -> None:
    if not HAVE[engine]:
        pytest.skip(
            f"THE {engine.upper()} ADAPTER'S BODY TORQUE IS NOT TESTED: the {engine} "
            "package is not installed; pip install 'poinsot[verify]'"
        )


def attitude(res) -> float:
    return float(res.metrics["attitude"]["value"])


CASE = cases("body-torque")[0]


def test_the_case_is_a_body_torque_with_a_transverse_rate():
    i = CASE.inputs
    assert np.array_equal(i["body_torque"], [0.0, 0.0, 0.5]) and i["omega0"][0] != 0.0
    loads = CASE.spec.engine_loads(CASE)
    assert loads["rotor_momentum"] is None
    q = np.array([0.5, 0.5, 0.5, 0.5])  # any attitude, rate: the same body-axes torque
    assert loads["torque"](3.0, q, np.ones(3)).tolist() == [0.0, 0.0, 0.5]
    assert CASE.spec.constant_torque(CASE).tolist() == [0.0, 0.0, 0.5]


def test_mujoco_rk4_passes_at_fourth_order():
    need("mujoco")
    res = [run(make("mujoco", integrator="RK4", timestep=h), CASE) for h in (1e-2, 5e-3, 1e-3)]
    assert all(r.status == "pass" for r in res), [r.reason for r in res]
    e = [attitude(r) for r in res]  # observed 5.19e-8, 3.22e-9, 4.9e-12
    assert 12.0 < e[0] / e[1] < 20.0 and e[2] < 5e-11, e
    assert res[2].work == 10_000


def test_mujoco_euler_fails_at_first_order():
    need("mujoco")
    res = [run(make("mujoco", integrator="Euler", timestep=h), CASE) for h in (1e-3, 5e-4)]
    assert all(r.status == "fail" for r in res)
    e = [attitude(r) for r in res]  # observed 3.51e-2, 1.74e-2
    assert e[1] > 1e-3 and 1.7 < e[0] / e[1] < 2.3, e


def test_mujoco_torque_in_world_axes_would_fail(monkeypatch):
    """The passive callback adds the torque to the free joint's rotational entries as
    body-axes components: turning it to world axes first (the wrong frame) fails by far
    (the right one 4.9e-12 rad at RK4 1 ms)."""
    need("mujoco")
    from poinsot.rotations.rotation import Rotation

    spec = type(CASE.spec)
    right = spec.torque

    def in_world(self, case):
        m = right(self, case)
        return lambda t, q, w: Rotation.from_quat(q).apply(m(t, q, w))

    monkeypatch.setattr(spec, "torque", in_world)
    res = run(make("mujoco", integrator="RK4", timestep=1e-3), CASE)
    assert res.status == "fail" and attitude(res) > 1e-2, attitude(res)


def test_pybullet_converges_at_first_order():
    need("pybullet")
    res = [run(make("pybullet", timestep=h), CASE) for h in (1e-3, 5e-4)]
    assert all(r.status == "fail" for r in res)
    e = [attitude(r) for r in res]  # observed 3.51e-2, 1.74e-2
    assert e[1] > 1e-3 and 1.7 < e[0] / e[1] < 2.3, e


def test_skips_with_reasons():
    assert "LeafSystem" in make("drake").skip_reason(CASE)
    assert "maximal-coordinates" in make("pybullet", coordinates="maximal").skip_reason(CASE)
    reason = make("basilisk").skip_reason(CASE)
    assert reason is None or "not installed" in reason
