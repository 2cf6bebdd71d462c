"""First calls on a cold numba cache (issue 40): small problems are answered by the
interpreter running the kernels' own source (rotations by their NumPy-executor twin),
with the compiled results to round-off, compiling nothing; large ones compile; a
background ``poinsot warmup`` fills the cache once per install.

Each cold case runs in a fresh process with an empty ``NUMBA_CACHE_DIR``.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from poinsot import _jit

pytestmark = pytest.mark.skipif(not _jit.NUMBA, reason="the cold cache is numba's")


def _cold(code: str, cache, **env: str) -> dict:
    """Run ``code`` (which sets ``out``, a JSON-able dict) in a fresh process with the
    empty cache ``cache`` and interpreting on; returns ``out`` plus the seconds compiled
    and interpreted there."""
    full = (
        "import json, numpy as np\nfrom poinsot import _jit\n" + code + "\n"
        "out['compiled_s'] = _jit.compile_seconds()\n"
        "out['interpreted_s'] = _jit.interpreted_seconds()\n"
        "print(json.dumps(out))\n"
    )
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(cache),
        "POINSOT_INTERPRET_FIRST": "1",
        "POINSOT_BACKGROUND_BUILD": "0",
        "POINSOT_COMPILE_NOTICE": "0",
        **env,
    }
    res = subprocess.run(
        [sys.executable, "-c", full], env=env, capture_output=True, text=True, timeout=300
    )
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.strip().splitlines()[-1])


SIMULATE = """
from poinsot.dynamics import simulate
tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 10, 51), {kw})
out = {{'quat': tr.rotation.as_quat(scalar_first=True).tolist(), 'omega': tr.omega.tolist()}}
"""


@pytest.mark.parametrize(
    "kw", ["rtol=1e-10", "method='midpoint', max_step=0.01", "method='rk4', max_step=0.01"]
)
def test_a_small_first_simulate_is_interpreted_and_equals_the_compiled(tmp_path, kw):
    out = _cold(SIMULATE.format(kw=kw), tmp_path)
    assert out["compiled_s"] == 0.0 and out["interpreted_s"] > 0.0
    from poinsot.dynamics import simulate  # compiled here (interpreting off in the suite)

    tr = simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 2.0, 0.1], np.linspace(0, 10, 51),
                  **eval(f"dict({kw})"))  # fmt: skip
    # the same operations; a fused multiply-add of the compiled kernel is two roundings
    # here (observed <= 3.4e-13 over 10 s of a tumbling body)
    np.testing.assert_allclose(out["omega"], tr.omega, rtol=0, atol=1e-11)
    np.testing.assert_allclose(out["quat"], tr.rotation.as_quat(scalar_first=True), atol=1e-11)


def test_a_cold_free_body_and_rotations_compile_nothing(tmp_path):
    code = """
from poinsot import Rotation
from poinsot.dynamics import FreeRigidBody
from poinsot.rotations import _lazy
tr = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1]).trajectory(np.linspace(0, 10, 101))
e = np.random.default_rng(0).uniform(-3, 3, (500, 3))
r = Rotation.from_euler('ZXZ', e)
out = {'omega': tr.omega.tolist(), 'euler': r.as_euler('ZXZ').tolist(),
       'matrix': r.as_matrix().tolist(), 'twin': _lazy._TWIN}
"""
    out = _cold(code, tmp_path)
    assert out["compiled_s"] == 0.0 and out["twin"] is True
    from poinsot import Rotation
    from poinsot.dynamics import FreeRigidBody

    tr = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1]).trajectory(np.linspace(0, 10, 101))
    np.testing.assert_allclose(out["omega"], tr.omega, rtol=0, atol=1e-13)
    r = Rotation.from_euler("ZXZ", np.random.default_rng(0).uniform(-3, 3, (500, 3)))
    np.testing.assert_allclose(out["matrix"], r.as_matrix(), rtol=0, atol=1e-15)
    np.testing.assert_allclose(out["euler"], r.as_euler("ZXZ"), rtol=0, atol=1e-13)


def test_first_call_interprets_small_calls_then_compiles(monkeypatch):
    from numba import njit

    @njit(cache=False)
    def kernel(x):  # a kernel no cache holds
        return 2.0 * x + 1.0

    monkeypatch.setenv("POINSOT_INTERPRET_FIRST", "1")
    monkeypatch.setenv("POINSOT_BACKGROUND_BUILD", "0")
    monkeypatch.setattr(_jit, "_INTERPRETED", {})
    assert not _jit.ready(kernel)
    assert _jit.first_call(kernel, seconds=_jit.INTERPRET_MAX_S * 2) is kernel  # too long
    f = _jit.first_call(kernel, seconds=0.01)
    assert f is not kernel and getattr(f, "interpreted", False) and f(3.0) == 7.0
    assert not kernel.signatures  # the interpreter compiled nothing
    (key,) = _jit._INTERPRETED  # the seconds interpreted, per kernel
    _jit._INTERPRETED[key] = _jit.INTERPRET_TOTAL_S
    assert _jit.first_call(kernel, seconds=0.01) is kernel  # rent-or-buy: now compile
    assert kernel(3.0) == 7.0 and _jit.ready(kernel)  # compiled: ready from now on
    monkeypatch.setenv("POINSOT_INTERPRET_FIRST", "0")
    assert _jit.first_call(kernel, seconds=0.0) is kernel


def test_warm_marker_and_the_build_lock(tmp_path, monkeypatch):
    from poinsot.cli import warmup

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not _jit.is_warm()
    _jit.mark_warm()
    assert _jit.is_warm() and _jit._marker().parent == tmp_path
    lock = warmup._lock(_jit._marker())
    assert lock is not None and lock.exists()
    assert warmup._lock(_jit._marker()) is None  # one build at a time
    old = time.time() - warmup.LOCK_S - 1
    os.utime(lock, (old, old))
    assert warmup._lock(_jit._marker()) is not None  # a stale lock is taken over


def test_the_background_build_is_a_detached_warmup_started_once(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("POINSOT_BACKGROUND_BUILD", "1")
    monkeypatch.setattr(_jit, "_BUILDING", {})
    _jit.build_in_background()
    proc = _jit._BUILDING.get("process")
    try:
        assert proc is not None and proc.args[-3:] == ["warmup", "--background", "--quiet"]
        assert os.getsid(proc.pid) == proc.pid  # its own session: the terminal's Ctrl-C
        _jit.build_in_background()  # once per process
        assert _jit._BUILDING["process"] is proc
    finally:
        if proc is not None:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(30)
    monkeypatch.setattr(_jit, "_BUILDING", {})
    _jit.mark_warm()  # a warm cache starts no build
    _jit.build_in_background()
    assert "process" not in _jit._BUILDING


def test_warmup_without_numba_says_so(tmp_path):
    env = dict(os.environ, POINSOT_NUMBA="0")
    res = subprocess.run([sys.executable, "-m", "poinsot.cli", "warmup"], env=env,
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert res.returncode == 0 and "nothing to compile" in res.stdout


def test_a_large_rotation_batch_leaves_the_twin_for_the_compiled_kernels(tmp_path):
    code = """
from poinsot import Rotation
from poinsot.rotations import PARALLEL_MIN_SIZE, _lazy
r = Rotation.from_euler('ZXZ', np.random.default_rng(1).uniform(-3, 3, (100, 3)))
small = _lazy._TWIN
big = Rotation.from_euler('ZXZ', np.random.default_rng(1).uniform(-3, 3, (PARALLEL_MIN_SIZE, 3)))
out = {'small_twin': small, 'twin_after': _lazy._TWIN, 'm': big.as_matrix()[:50].tolist()}
"""
    out = _cold(code, tmp_path)
    assert out["small_twin"] is True and out["twin_after"] is False
    assert out["compiled_s"] > 0.0  # rent or buy: the large batch paid for compiling
    from poinsot import Rotation
    from poinsot.rotations import PARALLEL_MIN_SIZE

    e = np.random.default_rng(1).uniform(-3, 3, (PARALLEL_MIN_SIZE, 3))
    np.testing.assert_allclose(out["m"], Rotation.from_euler("ZXZ", e).as_matrix()[:50], atol=1e-15)


def test_a_large_batch_as_the_very_first_use_takes_the_compiled_kernels(tmp_path):
    # the large batch is the first call that needs the kernels: it used to be decided
    # before the kernels were resolved (and so ran on the twin, its result in the twin's
    # F order, which as_matrix(out=np.empty_like(result)) refuses)
    code = """
from poinsot import Rotation
from poinsot.rotations import PARALLEL_MIN_SIZE, _lazy
r = Rotation.from_quat(np.random.default_rng(2).standard_normal((PARALLEL_MIN_SIZE, 4)))
m = r.as_matrix()
same = r.as_matrix(out=np.empty_like(m)).tolist() == m.tolist()
out = {'twin': _lazy._TWIN, 'c': bool(m.flags.c_contiguous), 'same': same}
"""
    out = _cold(code, tmp_path)
    assert out["twin"] is False and out["c"] is True and out["same"] is True
    assert out["compiled_s"] > 0.0


def test_a_cache_that_holds_the_rotation_kernels_is_used_without_the_marker(tmp_path):
    """A cache filled by ordinary use (no ``poinsot warmup`` marker) is warm for the
    rotations: the compiled kernels load, the twin is not used."""
    code = """
from poinsot import Rotation
from poinsot.rotations import _lazy
Rotation.from_euler('ZXZ', [[0.1, 0.2, 0.3]] * 3).as_matrix()
out = {'twin': _lazy._TWIN}
"""
    fill = _cold(code, tmp_path, POINSOT_INTERPRET_FIRST="0")  # compiles into the cache
    assert fill["twin"] is False
    again = _cold(code, tmp_path)
    assert again["twin"] is False and again["compiled_s"] == 0.0


@pytest.mark.parametrize("max_step", [None, 1e-2, 2e-4])
def test_the_first_call_estimate_counts_the_steps_taken(monkeypatch, max_step):
    # a first call is interpreted when its estimate is small: the estimate must count at
    # least the steps the kernel takes, those a max_step forces included (a Kovalevskaya
    # top's chunks at max_step 5e-5 were estimated at ~70 steps, took 10,000 each, and
    # were interpreted for 14 s before compiling)
    from poinsot.dynamics import _fused_run, torques

    seen = []

    def record(fn, seconds, match=None):
        seen.append(seconds)
        return fn

    monkeypatch.setattr(_fused_run, "first_call", record)
    monkeypatch.setattr(_fused_run, "LANES", False)
    rng = np.random.default_rng(4)
    j = rng.uniform(1.0, 3.0, (3, 3))
    q0 = rng.normal(size=(3, 4))
    q0 /= np.linalg.norm(q0, axis=-1, keepdims=True)
    w0 = rng.normal(scale=4.0, size=(3, 3))
    gravity = torques.GravityTorque(1.0, [0.0, 0.0, 0.1])
    for torque in (None, gravity):
        seen.clear()
        _, _, stats = _fused_run.integrate(
            j, q0, w0, np.linspace(0.0, 2.0, 11), torque,
            rtol=1e-10, atol=1e-12, max_step=max_step, principal=True,
        )  # fmt: skip
        assert np.all(stats[:, 3] == 0)
        (seconds,) = seen
        taken = stats[:, 0].sum()
        assert seconds >= taken * _fused_run._INTERPRETED_STEP_S, (torque, taken, seconds)
