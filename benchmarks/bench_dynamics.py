"""Benchmark: the structure-preserving integrator of ``poinsot.dynamics.simulate``.

Measures (median of several runs, printed as a table):

1. body-steps per second of the default method (implicit midpoint + Cayley) for
   one body and for a batch of 100,000 bodies;
2. the ratio of its time to SciPy ``solve_ivp(method="DOP853")`` reaching the
   same error (the loosest ``rtol`` whose error is no larger), for one body and
   for the batch (SciPy both as one big vectorised system and body by body,
   the latter timed on a subset and scaled);
3. the relative drift of the energy, ``|K|`` and the space vector ``K`` after
   10^6 steps;
4. ``euler_rhs`` for one state against a hand-written NumPy expression of the
   same formula, ``np.array([(B - C) q r / A, ...])`` (the practical floor;
   target: within 2x) and the invariants of one state.

Errors are measured against the exact Euler-Poinsot solution
(``poinsot.dynamics.FreeRigidBody``) when available, else against DOP853 at
``rtol=1e-13``. Run: ``.venv/bin/python benchmarks/bench_dynamics.py [--quick]``.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation as SciRotation

from poinsot import Rotation
from poinsot.dynamics import euler_rhs, kinetic_energy, simulate


def _median_time(fn, repeat):
    times = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def _bodies(n, seed=1):
    rng = np.random.default_rng(seed)
    moments = rng.uniform(1.5, 2.9, size=(n, 3))
    w0 = rng.normal(size=(n, 3))
    q0 = SciRotation.random(n, rng=seed).as_quat(scalar_first=True)
    return moments, q0, w0


def _rhs_batch(moments):
    """Lean vectorised RHS of (q, w) for solve_ivp: SPEC S10 + L' = L o w / 2."""
    a, b, c = moments[:, 0], moments[:, 1], moments[:, 2]
    n = moments.shape[0]

    def f(_, y):
        y = y.reshape(n, 7)
        l0, l1, l2, l3, p, q, r = y.T
        out = np.empty((n, 7))
        out[:, 0] = 0.5 * (-l1 * p - l2 * q - l3 * r)
        out[:, 1] = 0.5 * (l0 * p + l2 * r - l3 * q)
        out[:, 2] = 0.5 * (l0 * q + l3 * p - l1 * r)
        out[:, 3] = 0.5 * (l0 * r + l1 * q - l2 * p)
        out[:, 4] = (b - c) * q * r / a
        out[:, 5] = (c - a) * r * p / b
        out[:, 6] = (a - b) * p * q / c
        return out.ravel()

    return f


def _scipy(moments, q0, w0, t_end, rtol):
    y0 = np.concatenate([q0, w0], axis=1).ravel()
    sol = solve_ivp(
        _rhs_batch(moments),
        (0.0, t_end),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=rtol * 1e-2,
        t_eval=[t_end],
    )
    y = sol.y[:, -1].reshape(-1, 7)
    q = y[:, :4] / np.linalg.norm(y[:, :4], axis=1, keepdims=True)
    return q, y[:, 4:]


def _exact(moments, q0, w0, t_end):
    """Exact final state per body (FreeRigidBody) or tight DOP853."""
    try:
        from poinsot.dynamics import FreeRigidBody
    except ImportError:
        FreeRigidBody = None
    if FreeRigidBody is not None:
        qs, ws = [], []
        for i in range(moments.shape[0]):
            fb = FreeRigidBody(moments[i], rotation0=Rotation.from_quat(q0[i]), omega0=w0[i])
            ws.append(fb.omega([t_end])[0])
            qs.append(fb.rotation([t_end]).as_quat()[0])
        return np.array(qs), np.array(ws), "FreeRigidBody (exact)"
    q, w = _scipy(moments, q0, w0, t_end, 1e-13)
    return q, w, "DOP853 rtol=1e-13"


def _error(q, w, q_ref, w_ref):
    """max over bodies of max(|w - w_ref|, attitude angle error)."""
    r = SciRotation.from_quat(q, scalar_first=True)
    r_ref = SciRotation.from_quat(q_ref, scalar_first=True)
    return float(max(np.abs(w - w_ref).max(), (r_ref.inv() * r).magnitude().max()))


def _matched_rtol(moments, q0, w0, t_end, target, q_ref, w_ref):
    """Loosest rtol in a decade ladder whose DOP853 error is <= target."""
    for rtol in 10.0 ** -np.arange(1.0, 14.0, 0.5):
        q, w = _scipy(moments, q0, w0, t_end, rtol)
        err = _error(q, w, q_ref, w_ref)
        if err <= target:
            return rtol, err
    return 1e-13, err


def _energy_drift(moments, w0, w):
    e0 = np.sum(moments * w0**2, axis=-1)
    return float(np.max(np.abs(np.sum(moments * w**2, axis=-1) / e0 - 1)))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller sizes (smoke run)")
    args = ap.parse_args(argv)
    quick = args.quick
    n_batch = 10_000 if quick else 100_000
    n_sub = 100 if quick else 200  # bodies checked for the error / looped in SciPy
    repeat = 3
    t_end = 1.0
    rows = []

    def row(name, value, note=""):
        rows.append((name, value, note))

    # warm-up (numba compile / cache load)
    simulate([1.0, 2.0, 3.0], [1.0, 0, 0, 0], [0.1, 1.0, 0.1], [0.0, 0.1], max_step=0.01)

    # ---- one state: euler_rhs against the hand-written NumPy expression -------------------
    j1, w1 = np.array([1.0, 2.0, 3.0]), np.array([0.3, 1.0, -0.2])

    def hand_rhs(j=j1, w=w1):
        a, b, c = j
        p, q, r = w
        return np.array([(b - c) * q * r / a, (c - a) * r * p / b, (a - b) * p * q / c])

    def hand_energy(j=j1, w=w1):
        return 0.5 * float(j @ (w * w))

    n_calls = 20_000
    for name, ours, hand in (
        ("euler_rhs, 1 state (float64 arrays)", lambda: euler_rhs(j1, w1), hand_rhs),
        (
            "euler_rhs, 1 state (lists)",
            lambda: euler_rhs([1.0, 2.0, 3.0], [0.3, 1.0, -0.2]),
            hand_rhs,
        ),
        ("kinetic_energy, 1 state", lambda: kinetic_energy(j1, w1), hand_energy),
    ):
        t_ours = _median_time(lambda f=ours: [f() for _ in range(n_calls)], 5)[0]
        t_hand = _median_time(lambda f=hand: [f() for _ in range(n_calls)], 5)[0]
        row(
            name,
            f"{t_ours / n_calls * 1e6:.2f} us vs {t_hand / n_calls * 1e6:.2f} us",
            f"{t_ours / t_hand:.2f}x the hand NumPy expression (target <= 2x)",
        )

    # ---- one body, 10^6 steps: speed and invariants ---------------------------------------
    h = 0.01
    t_long = np.linspace(0.0, 1e6 * h, 1001)
    w0_one = np.array([0.4, 1.2, 0.3])
    q0_one = np.array([1.0, 0.0, 0.0, 0.0])
    sec, tr = _median_time(
        lambda: simulate([1.0, 2.0, 3.0], q0_one, w0_one, t_long, max_step=h), repeat
    )
    steps = tr.info["steps"]
    row("midpoint, 1 body, 10^6 steps", f"{steps / sec:,.0f} body-steps/s", f"{sec:.3f} s")
    row("  energy drift after 10^6 steps", f"{tr.energy_drift:.2e}", "target <= 1e-12")
    row("  |K| drift after 10^6 steps", f"{tr.momentum_drift:.2e}")
    row("  space K drift after 10^6 steps", f"{tr.momentum_vector_drift:.2e}")

    for method, order in (("midpoint", 6), ("splitting", 2), ("splitting", 6)):
        sec, tr = _median_time(
            lambda m=method, o=order: simulate(
                [1.0, 2.0, 3.0], q0_one, w0_one, t_long, method=m, order=o, max_step=h
            ),
            1,
        )
        row(
            f"{method} order {order}, 1 body, 10^6 steps",
            f"{tr.info['steps'] / sec:,.0f} body-steps/s",
            f"energy {tr.energy_drift:.1e}, |K| {tr.momentum_drift:.1e}",
        )

    # ---- batch: speed ----------------------------------------------------------------------
    mb, qb, wb = _bodies(n_batch, seed=7)
    sub = slice(0, n_sub)
    q_ref, w_ref, ref_name = _exact(mb[sub], qb[sub], wb[sub], t_end)
    row(f"reference for errors ({n_sub} bodies, T = {t_end})", ref_name)

    def loop(rtol):
        for i in range(n_sub):
            _scipy(mb[i : i + 1], qb[i : i + 1], wb[i : i + 1], t_end, rtol)

    cases = (
        ("midpoint", 2, 0.01),
        ("midpoint", 6, 0.1),
        ("splitting", 2, 0.01),
        ("splitting", 6, 0.1),
    )
    for method, order, hh in cases:
        sec_b, trb = _median_time(
            lambda m=method, o=order, s=hh: simulate(
                mb, qb, wb, [0.0, t_end], method=m, max_step=s, order=o
            ),
            repeat,
        )
        body_steps = n_batch * trb.info["steps"]
        row(
            f"{method} order {order}, h = {hh}: {n_batch:,} bodies x {trb.info['steps']} steps",
            f"{body_steps / sec_b:,.0f} body-steps/s",
            f"{sec_b:.3f} s",
        )
        err_b = _error(trb.quat[-1, sub], trb.omega[-1, sub], q_ref, w_ref)
        row("  error (max over the checked bodies)", f"{err_b:.2e}")
        rtol, err_sp = _matched_rtol(mb[sub], qb[sub], wb[sub], t_end, err_b, q_ref, w_ref)
        sec_vec, (qv, wv) = _median_time(lambda r=rtol: _scipy(mb, qb, wb, t_end, r), repeat)
        err_vec = _error(qv[sub], wv[sub], q_ref, w_ref)
        row(
            f"  DOP853 rtol={rtol:.0e}, one vectorised system",
            f"error {err_vec:.2e}",
            f"{sec_vec:.3f} s",
        )
        row("  speed-up vs DOP853 vectorised", f"{sec_vec / sec_b:.1f}x", "target >= 50x")
        sec_loop, _ = _median_time(lambda r=rtol: loop(r), 1)
        sec_all = sec_loop * n_batch / n_sub
        row(f"  DOP853 body by body (scaled from {n_sub})", f"{sec_all:.1f} s")
        row("  speed-up vs DOP853 body by body", f"{sec_all / sec_b:.0f}x", "target >= 50x")

    # ---- invariants: DOP853 tolerance (and time) needed to keep the energy as well ----------
    t_inv = 10.0 if quick else 100.0
    ms, qs, ws = mb[sub], qb[sub], wb[sub]
    sec_mid, tr = _median_time(lambda: simulate(ms, qs, ws, [0.0, t_inv], max_step=0.01), repeat)
    drift_mid = float(np.max(np.abs(tr.energy[-1] / tr.energy[0] - 1)))
    row(
        f"energy drift, {n_sub} bodies over T = {t_inv:g}, midpoint h = 0.01",
        f"{drift_mid:.1e}",
        f"{sec_mid:.3f} s",
    )
    for rtol in (1e-8, 1e-10, 1e-12, 1e-13):
        sec_sp, (_, w) = _median_time(lambda r=rtol: _scipy(ms, qs, ws, t_inv, r), repeat)
        drift = _energy_drift(ms, ws, w)
        note = f"{sec_sp:.3f} s"
        if drift <= drift_mid * 2:
            note += f" ({sec_sp / sec_mid:.1f}x the midpoint's time)"
        row(f"  DOP853 rtol={rtol:.0e}, vectorised", f"{drift:.1e}", note)

    width = max(len(r[0]) for r in rows)
    print(f"{'quantity':<{width}}  {'value':>28}  note")
    print("-" * (width + 48))
    for name, value, note in rows:
        print(f"{name:<{width}}  {value:>28}  {note}")


if __name__ == "__main__":
    main()
