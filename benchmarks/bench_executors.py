"""The executors of the one formula source (issue 25), same run: numba, the NumPy
executor (``POINSOT_NUMBA=0``, in a subprocess), poinsot.jax (jit on the batch, and
jit of vmap of one rotation) and jaxlie (jit of vmap), on batch rotation conversions
and a batch of free bodies. Prints a Markdown table of medians in ms.

    python benchmarks/bench_executors.py [--n 100000] [--bodies 200]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

CONVERSIONS = ("as_matrix", "from_matrix", "as_rotvec", "from_rotvec", "as_euler ZYX")
OMEGA, STATE = "free body omega (exact)", "free body omega + attitude (exact)"
DIFFRAX = "free body omega (Dopri8, rtol 1e-10)"


def _median_ms(f: Callable[[], Any], repeat: int = 5) -> float:
    f()  # compile / warm up
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times))


def _data(n: int) -> dict[str, np.ndarray]:
    from poinsot import Rotation

    r = Rotation.from_quat(np.random.default_rng(0).normal(size=(n, 4)))
    return {"q": r.as_quat(), "m": r.as_matrix(), "v": r.as_rotvec()}


def bench_poinsot(n: int, bodies: int) -> dict[str, float]:
    """The public API, whichever executor this process runs."""
    from poinsot import Rotation
    from poinsot.dynamics import FreeRigidBody

    d = _data(n)
    r = Rotation.from_quat(d["q"])
    out = {
        "as_matrix": _median_ms(r.as_matrix),
        "from_matrix": _median_ms(lambda: Rotation.from_matrix(d["m"])),
        "as_rotvec": _median_ms(r.as_rotvec),
        "from_rotvec": _median_ms(lambda: Rotation.from_rotvec(d["v"])),
        "as_euler ZYX": _median_ms(lambda: r.as_euler("ZYX")),
    }
    rng = np.random.default_rng(1)
    j = np.sort(rng.uniform(1.0, 1.9, size=(bodies, 3)), axis=1)
    w0 = rng.normal(size=(bodies, 3))
    t = np.linspace(0.0, 10.0, 101)
    out[OMEGA] = _median_ms(lambda: FreeRigidBody(j, omega0=w0).omega(t), repeat=3)
    out[STATE] = _median_ms(lambda: FreeRigidBody(j, omega0=w0).state(t), repeat=3)
    return out


def bench_jax(n: int, bodies: int) -> dict[str, dict[str, float]]:
    import jax
    import jax.numpy as jnp

    from poinsot import jax as pj

    d = {k: jnp.asarray(v) for k, v in _data(n).items()}

    def run(f: Callable[[Any], Any], x: Any) -> Callable[[], Any]:
        return lambda: jax.block_until_ready(f(x))

    batch = {
        "as_matrix": (pj.matrix_from_quat, d["q"]),
        "from_matrix": (pj.quat_from_matrix, d["m"]),
        "as_rotvec": (pj.rotvec_from_quat, d["q"]),
        "from_rotvec": (pj.quat_from_rotvec, d["v"]),
        "as_euler ZYX": (lambda q: pj.euler_from_quat("ZYX", q), d["q"]),
    }
    jit = {k: _median_ms(run(jax.jit(f), x)) for k, (f, x) in batch.items()}
    vmap = {k: _median_ms(run(jax.jit(jax.vmap(f)), x)) for k, (f, x) in batch.items()}
    rng = np.random.default_rng(1)
    j = jnp.asarray(np.sort(rng.uniform(1.0, 1.9, size=(bodies, 3)), axis=1))
    w0 = jnp.asarray(rng.normal(size=(bodies, 3)))
    t = jnp.linspace(0.0, 10.0, 101)
    # the exact solution (the same source as numba's), then Euler's equations in diffrax
    exact = {OMEGA: pj.free_body_omega_exact}
    if hasattr(pj, "free_body_state_exact"):
        exact[STATE] = lambda j, w, t: pj.free_body_state_exact(j, w, None, t)
    for row, f in exact.items():
        fj, fv = jax.jit(f), jax.jit(jax.vmap(f, in_axes=(0, 0, None)))
        jit[row] = _median_ms(lambda fj=fj: jax.block_until_ready(fj(j, w0, t)), repeat=3)
        vmap[row] = _median_ms(lambda fv=fv: jax.block_until_ready(fv(j, w0, t)), repeat=3)
    fb = jax.jit(jax.vmap(pj.free_body_omega, in_axes=(0, 0, None)))
    vmap[DIFFRAX] = _median_ms(lambda: jax.block_until_ready(fb(j, w0, t)), repeat=3)
    out = {"jax jit": jit, "jax vmap": vmap}
    try:
        import jaxlie
    except ImportError:
        return out
    q = d["q"] / jnp.linalg.norm(d["q"], axis=-1, keepdims=True)
    lie = {
        "as_matrix": (lambda x: jaxlie.SO3(x).as_matrix(), q),
        "from_matrix": (lambda m: jaxlie.SO3.from_matrix(m).wxyz, d["m"]),
        "as_rotvec": (lambda x: jaxlie.SO3(x).log(), q),
        "from_rotvec": (lambda v: jaxlie.SO3.exp(v).wxyz, d["v"]),
        "as_euler ZYX": (lambda x: jnp.stack(jaxlie.SO3(x).as_rpy_radians()), q),
    }
    out["jaxlie vmap"] = {k: _median_ms(run(jax.jit(jax.vmap(f)), x)) for k, (f, x) in lie.items()}
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--bodies", type=int, default=200)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        print(json.dumps(bench_poinsot(a.n, a.bodies)))
        return
    cols = {"numba": bench_poinsot(a.n, a.bodies)}
    env = dict(os.environ, POINSOT_NUMBA="0")
    child = [sys.executable, __file__, "--child", "--n", str(a.n), "--bodies", str(a.bodies)]
    res = subprocess.run(child, env=env, capture_output=True, text=True, check=True)
    cols["NumPy executor"] = json.loads(res.stdout.splitlines()[-1])
    cols.update(bench_jax(a.n, a.bodies))
    load = os.getloadavg()[0]
    print(f"{a.n} rotations, {a.bodies} free bodies x 101 times; load {load:.1f}; ms")
    names = list(cols)
    print("| operation | " + " | ".join(names) + " |")
    print("| --- |" + " --- |" * len(names))
    for op in (*CONVERSIONS, OMEGA, STATE, DIFFRAX):
        cells = [f"{cols[c][op]:.2f}" if op in cols[c] else "-" for c in names]
        print(f"| {op} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
