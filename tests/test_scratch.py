"""``poinsot._scratch``: reused per-thread arrays, and that reuse never leaks into results.

Independent truths: the same ``simulate`` calls with the reuse switched off
(``MAX_BYTES = 0``: every array fresh) give the same bits; results of an earlier call
are unchanged by later calls; arrays handed to ``simulate`` stay the caller's.
"""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from poinsot import _scratch
from poinsot._jit import NUMBA
from poinsot.dynamics import invariants, simulate


def _problem(seed: int, n: int = 300):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.0, 2.0, (n, 3))
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    omega = rng.normal(size=(n, 3))
    return moments, quat, omega


def _run(moments, quat, omega, duration=2.0, **kw):
    t = np.linspace(0.0, duration, 5)
    return simulate(moments, quat, omega, t, method="dop853", rtol=1e-9, atol=1e-11, **kw)


def _arrays(tr):
    return [tr.quat.copy(), tr.omega.copy(), tr.energy.copy(), tr.momentum.copy()] + [
        np.array(tr.info["steps"]),
        np.array(tr.info["rejected"]),
    ]


def _same(a, b):
    return all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


def test_hold_reuses_its_arrays_but_never_inside_itself():
    with _scratch.hold() as s:
        a = s.zeros("t1", (4, 3))
        with _scratch.hold() as inner:  # re-entry: fresh arrays, a is not overwritten
            b = inner.empty("t1", (4, 3))
            b.fill(5.0)
        assert not np.shares_memory(a, b)
        assert not a.any()
    with _scratch.hold() as s:
        c = s.empty("t1", (2, 6))
    assert np.shares_memory(a, c)
    with _scratch.hold() as s:  # a larger request replaces the kept array
        d = s.empty("t1", (10, 3))
    assert d.shape == (10, 3) and not np.shares_memory(a, d)


def test_hold_keeps_nothing_beyond_max_bytes_and_drops_arrays_after_an_error(monkeypatch):
    monkeypatch.setattr(_scratch, "MAX_BYTES", 1024)
    with _scratch.hold() as s:
        big = s.empty("t2", (200,))  # 1600 bytes: fresh, not kept
    with _scratch.hold() as s:
        assert not np.shares_memory(big, s.empty("t2", (200,)))
    with _scratch.hold() as s:
        small = s.empty("t3", (10,))
    with pytest.raises(KeyboardInterrupt), _scratch.hold() as s:
        s.empty("t3", (10,))
        raise KeyboardInterrupt
    with _scratch.hold() as s:  # a kernel might still write the old one: not reused
        assert not np.shares_memory(small, s.empty("t3", (10,)))


def test_reused_arrays_give_the_bits_of_fresh_ones_and_leave_earlier_results_alone(
    monkeypatch,
):
    p1, p2 = _problem(1), _problem(2)
    first = _run(*p1)
    kept = _arrays(first)
    second = _run(*p2)  # same sizes: every scratch array of `first` is reused
    assert _same(_arrays(first), kept)
    monkeypatch.setattr(_scratch, "MAX_BYTES", 0)
    assert _same(_arrays(_run(*p1)), kept)
    assert _same(_arrays(_run(*p2)), _arrays(second))


def test_energy_and_momentum_are_the_invariants_of_the_states():
    from scipy.spatial.transform import Rotation as SciRotation

    moments, quat, omega = _problem(3)
    tr = _run(moments, quat, omega)
    # independent truth: T = sum J_i w_i^2 / 2 and K_s = R (J w) with SciPy's rotation
    # (scalar last); round-off only
    k_body = moments * tr.omega
    np.testing.assert_allclose(tr.energy, 0.5 * np.sum(k_body * tr.omega, axis=-1), rtol=5e-14)
    sci = SciRotation.from_quat(np.roll(tr.quat.reshape(-1, 4), -1, axis=-1))
    k_space = sci.apply(k_body.reshape(-1, 3)).reshape(k_body.shape)
    np.testing.assert_allclose(tr.momentum, k_space, rtol=0, atol=1e-13 * np.abs(k_space).max())
    inv = invariants(moments, tr.rotation, tr.omega)
    assert np.array_equal(tr.energy, inv.kinetic)
    assert np.array_equal(tr.momentum, inv.momentum_space)
    # the same through a full tensor (the non-principal path)
    tr2 = _run(moments[:, :, None] * np.eye(3), quat, omega)
    assert _same(_arrays(tr2), _arrays(tr))


def test_the_callers_arrays_stay_theirs_and_results_are_read_only():
    moments, quat, omega = _problem(4)
    t = np.linspace(0.0, 1.0, 3)
    before = [moments.copy(), quat.copy(), omega.copy(), t.copy()]
    tr = simulate(moments, quat, omega, t, method="dop853", rtol=1e-8)
    for a, b in zip((moments, quat, omega, t), before, strict=True):
        assert a.flags.writeable and np.array_equal(a, b)
    for a in (tr.t, tr.omega, tr.energy, tr.momentum):
        assert not a.flags.writeable
    assert not np.shares_memory(tr.t, t)


@pytest.mark.skipif(not NUMBA, reason="half a second compiled: minutes as Python")
def test_a_progress_callback_that_simulates_again_does_not_disturb_the_outer_run():
    # long enough (>= 0.5 s on this CPU, however fast) for the progress reports of the
    # running kernel (every 0.1 s): 300 s of motion took 0.5 s on one machine and under
    # 0.1 s on a faster one, where no report came before the end
    moments, quat, omega = _problem(5, n=3000)
    small = _problem(6, n=3000)  # the same sizes: the outer run's arrays would fit
    _run(*small)  # compiled (or loaded from the cache) before anything is timed
    duration = 300.0
    while True:
        start = time.perf_counter()
        expected = _arrays(_run(moments, quat, omega, duration=duration))
        if time.perf_counter() - start >= 0.5 or duration > 1e5:
            break
        duration *= 2.0
    inner = []

    def progress(fraction):
        if fraction < 1.0:
            inner.append(_run(*small))

    got = _run(moments, quat, omega, duration=duration, progress=progress)
    assert inner  # called while the kernel ran
    assert _same(_arrays(got), expected)
    assert _same(_arrays(inner[-1]), _arrays(_run(*small)))


def test_threads_each_get_their_own_arrays():
    problems = [_problem(10 + i) for i in range(4)]
    expected = [_arrays(_run(*p)) for p in problems]
    barrier = threading.Barrier(2)

    def work(i):
        barrier.wait(timeout=60) if i < 2 else None
        return _arrays(_run(*problems[i]))

    with ThreadPoolExecutor(2) as ex:
        got = list(ex.map(work, range(4)))
    for g, e in zip(got, expected, strict=True):
        assert _same(g, e)
