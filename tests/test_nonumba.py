"""poinsot without numba (issue 25): the NumPy executor of the same formula source.

* a subprocess where ``import numba`` raises ImportError (a meta-path blocker)
  imports poinsot and runs public functions; they equal this process's results
  (numba, or the NumPy executor when this run has ``POINSOT_NUMBA=0``) to 1e-13;
* the vectorised executor (:func:`poinsot._jit.lanes`) runs each element through
  exactly its scalar branch: equal to the plain-Python scalar formula, element by
  element, on batches that take every branch (all four largest squares of a
  matrix, angles at 0, near and at pi, gimbal lock).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from poinsot import _jit
from poinsot.rotations import _scalar as S

_SCRIPT = textwrap.dedent(
    """
    import json, sys
    import numpy as np
    import poinsot
    from poinsot import Rotation
    from poinsot.dynamics import FreeRigidBody
    from poinsot.dynamics import simulate
    from poinsot.rotations.rotation import slerp

    rng = np.random.default_rng(7)
    r = Rotation.from_quat(rng.normal(size=(64, 4)))
    out = {
        "matrix": r.as_matrix(),
        "from_matrix": Rotation.from_matrix(r.as_matrix()).as_quat(),
        "rotvec": r.as_rotvec(),
        "from_rotvec": Rotation.from_rotvec(r.as_rotvec()).as_quat(),
        "euler": r.as_euler("ZXZ"),
        "from_euler": Rotation.from_euler("xyz", r.as_euler("xyz")).as_quat(),
        "mrp": r.as_mrp(),
        "compose": (r * r[::-1]).as_quat(),
        "apply": r.apply(rng.normal(size=(64, 3))),
        "one_matrix": r[3].as_matrix(),
        "slerp": slerp(r[0], r[1], np.linspace(0.0, 1.0, 5)).as_quat(),
    }
    body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.3, 0.2, 0.9])
    w, rot = body.state(np.linspace(0.0, 5.0, 7))
    out["free_w"], out["free_q"] = w, rot.as_quat()
    traj = simulate([1.0, 2.0, 3.0], Rotation.identity(), [0.3, 0.2, 0.9], np.linspace(0, 1, 5))
    out["sim_w"] = traj.omega
    # issue 38: every method and the heavy body ran into `import numba` (ImportError)
    t = np.linspace(0.0, 1.0, 5)
    for m, opts in (("dop853", {}), ("rk4", {"max_step": 0.01}), ("adaptive", {}),
                    ("midpoint", {"max_step": 0.01})):
        tr = simulate([1.0, 2.0, 3.0], Rotation.identity(), [0.3, 0.2, 0.9], t, method=m, **opts)
        out["sim_" + m] = np.concatenate([tr.omega, tr.rotation.as_quat()], axis=-1)
        batch = simulate([[1.0, 2.0, 3.0], [2.0, 2.5, 1.0]], Rotation.identity(),
                         [[0.3, 0.2, 0.9], [1.0, -0.5, 0.2]], t, method=m, **opts)
        out["batch_" + m] = batch.omega
    # issue 41: the gyrostatic torque (kind 5) in the fused kernels of both executors
    from poinsot.dynamics import GyrostaticTorque
    gyro = GyrostaticTorque([[0.0, 0.0, 0.8], [0.3, -0.4, 0.2]])
    for m, opts in (("dop853", {}), ("rk4", {"max_step": 0.01}), ("midpoint", {"max_step": 0.01})):
        tr = simulate([[1.0, 2.0, 3.0], [2.0, 2.5, 1.0]], Rotation.identity(),
                      [[0.3, 0.2, 0.9], [1.0, -0.5, 0.2]], t, torque=gyro, method=m, **opts)
        out["sim_gyro_" + m] = np.concatenate([tr.omega, tr.rotation.as_quat()], axis=-1)
    from poinsot.dynamics import HeavyRigidBody
    top = HeavyRigidBody([1.0, 1.0, 0.5], mass=1.0, center_of_mass=[0.0, 0.0, 0.1])
    tr = top.simulate(Rotation.from_rotvec([0.3, 0.0, 0.0]), [0.1, 0.0, 5.0], t, method="dop853")
    out["heavy_dop853"] = np.concatenate([tr.omega, tr.rotation.as_quat()], axis=-1)
    big = Rotation.from_quat(rng.normal(size=(30000, 4)))  # the threaded large-batch path
    out["big_matrix"] = big.as_matrix()[::997]
    out["numba_loaded"] = np.array([float("numba" in sys.modules)])
    print(json.dumps({k: np.asarray(v, dtype=float).tolist() for k, v in out.items()}))
    """
)

_BLOCKER = textwrap.dedent(
    """
    import sys

    class _NoNumba:
        def find_spec(self, name, path=None, target=None):
            if name == "numba" or name.startswith("numba."):
                raise ImportError("numba is blocked for this test")
            return None

    sys.meta_path.insert(0, _NoNumba())
    """
)


def _run(blocked: bool) -> dict[str, np.ndarray]:
    env = dict(os.environ)
    env.pop("POINSOT_NUMBA", None)
    src = os.path.join(os.path.dirname(__file__), "..", "src")
    env["PYTHONPATH"] = os.pathsep.join([os.path.abspath(src), env.get("PYTHONPATH", "")])
    code = (_BLOCKER if blocked else "") + _SCRIPT
    res = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600
    )
    assert res.returncode == 0, res.stderr[-3000:]
    return {k: np.array(v) for k, v in json.loads(res.stdout.splitlines()[-1]).items()}


def test_without_numba_public_functions_equal_the_numba_path():
    blocked = _run(blocked=True)
    assert blocked["numba_loaded"][0] == 0.0  # nothing imported numba behind our back
    ref = _run(blocked=False)
    for key, want in ref.items():
        if key == "numba_loaded":
            continue
        got = blocked[key]
        assert got.shape == want.shape, key
        # integrations: round-off differences of the two executors grow along the run
        tol = 1e-12 if key.startswith(("sim_", "batch_", "heavy_")) else 1e-13
        np.testing.assert_allclose(got, want, rtol=tol, atol=tol / 10, err_msg=key)


def test_the_switch_selects_the_executor():
    env = dict(os.environ, POINSOT_NUMBA="0")
    # and it stays unloaded through the integrators and a large (threaded) batch
    code = (
        "import poinsot._jit as j, sys, numpy as np\n"
        "from poinsot import Rotation\nfrom poinsot.dynamics import simulate\n"
        "for m in ('dop853', 'rk4', 'adaptive'):\n"
        "    simulate([1.0, 2.0, 3.0], Rotation.identity(), [0.3, 0.2, 0.9], [0.0, 0.5],"
        " method=m, max_step=0.05)\n"
        "Rotation.from_quat(np.ones((30000, 4))).as_matrix()\n"
        "print(j.NUMBA, 'numba' in sys.modules)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.stdout.split() == ["False", "False"], out.stderr


def _matrices(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=(400, 4))
    # each component the largest in a quarter of the batch: all four branches taken
    for k in range(4):
        q[k * 100 : (k + 1) * 100, k] *= 20.0
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return np.array([S.to_matrix(*row) for row in q])


def test_lanes_take_each_elements_scalar_branch_exactly():
    m = _matrices(np.random.default_rng(3))
    got = _jit.lanes(S.from_matrix, len(m), *m.T)
    want = np.array([S.from_matrix(*row) for row in m])
    # arithmetic and sqrt only: IEEE-exact, so bit-identical to the scalar path
    np.testing.assert_array_equal(np.array(got).T, want)
    largest = np.argmax(np.abs(want), axis=1)
    assert set(largest.tolist()) == {0, 1, 2, 3}


@pytest.mark.parametrize("f", [0.0, 1e-300, 1e-8, 1.0, np.pi - 1e-9, np.pi, 4.0, 1e200])
def test_rotvec_branches_by_lanes_equal_scalar(f):
    rng = np.random.default_rng(int(f * 1e6) % 2**32)
    e = rng.normal(size=(50, 3))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    v = np.concatenate([f * e, rng.normal(size=(50, 3))])  # mixed: forces a split
    got = np.array(_jit.lanes(S.from_rotvec, len(v), *v.T)).T
    want = np.array([S.from_rotvec(*row) for row in v])
    np.testing.assert_allclose(got, want, rtol=4e-16 * 10, atol=1e-300)


def test_euler_lanes_at_gimbal_lock_equal_scalar():
    rng = np.random.default_rng(5)
    a = rng.uniform(-np.pi, np.pi, size=(60, 3))
    a[:20, 1] = 0.0  # symmetric sequence ZXZ: middle angle 0 and pi are singular
    a[20:40, 1] = np.pi
    q = np.array([S.from_euler((2, 0, 2), *row) for row in a])
    got = _jit.lanes(S.to_euler, len(q), *q.T, 2, 0, 2, False, 1e-7)
    want = [S.to_euler(*row, 2, 0, 2, False, 1e-7) for row in q]
    np.testing.assert_array_equal(got[3], [w[3] for w in want])
    assert got[3][:40].all() and not got[3][40:].any()
    np.testing.assert_allclose(
        np.array(got[:3]).T, np.array([w[:3] for w in want]), rtol=1e-15 * 10, atol=1e-15
    )
