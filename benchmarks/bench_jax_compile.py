"""poinsot.jax's exact free body: compile times and speed (issue 40).

    python benchmarks/bench_jax_compile.py [--only NAME ...] [--points N T]

Each compile figure is one fresh process (no JAX compile cache): the wall time of the
first call (tracing, lowering and XLA's compile; the constants' program and the
evaluation's program are compiled apart, as a plain ``jax.grad`` compiles them) and,
from JAX's compile log, XLA's part of it; the process's peak memory. ``speed`` times
the compiled ``omega`` and ``attitude`` per body and time against numba's
``FreeRigidBody`` on the same batch (medians of 5). The machine's load is printed
first: quote it with the figures.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys

COMMON = """
import time, logging, numpy as np, jax, jax.numpy as jnp
jax.config.update("jax_log_compiles", True)
logging.basicConfig(level=logging.WARNING, format="%(message)s")
from poinsot import jax as pj
rng = np.random.default_rng(5)
x = np.array([np.concatenate([rng.uniform(1.0, 2.0, 3), rng.normal(size=3)]),
              [1.1, 2.0, 3.0, 1.0, 0.5, np.sqrt(0.33) * (1 + 1e-3)],
              [1.5, 2.0, 3.0, 1.0, -0.5, 0.3]])
q = rng.normal(size=(3, 4)); q0 = q / np.linalg.norm(q, axis=-1, keepdims=True)
t = np.array([0.7, 4.0, 11.0])
def om(xx):
    return pj.free_body_exact(xx[:, :3], xx[:, 3:]).omega(t).sum()
def att(xx):
    return pj.free_body_exact(xx[:, :3], xx[:, 3:], q0).attitude(t).sum()
t0 = time.perf_counter()
"""

#: name -> the first call timed (after COMMON)
FIGURES = {
    "omega": "om(jnp.asarray(x))",
    "attitude": "att(jnp.asarray(x))",
    "grad-omega": "jax.grad(om)(jnp.asarray(x))",
    "grad-omega-one-jit": "jax.jit(jax.grad(om))(jnp.asarray(x))",
    "jacfwd-attitude": "jax.jacfwd(att)(jnp.asarray(x))",
    "grad-attitude": "jax.grad(att)(jnp.asarray(x))",
}

SPEED = """
import time, numpy as np, jax
from poinsot import jax as pj
from poinsot.dynamics import FreeRigidBody
rng = np.random.default_rng(1)
N, T = {n}, {t}
moments = rng.uniform(1, 2, (N, 3)); w = rng.normal(size=(N, 3)); t = np.linspace(0, 10, T)
m = pj.free_body_exact(moments, w)
body = FreeRigidBody(moments, omega0=w)
def med(f):
    f()
    ts = []
    for _ in range(5):
        t0 = time.perf_counter(); f(); ts.append(time.perf_counter() - t0)
    return 1e9 * float(np.median(ts)) / (N * T)
fw = jax.jit(lambda m, t: m.omega(t)); fq = jax.jit(lambda m, t: m.attitude(t))
jw = med(lambda: fw(m, t).block_until_ready()); nw = med(lambda: body.omega(t))
jq = med(lambda: fq(m, t).block_until_ready()); nq = med(lambda: body.rotation(t).as_quat())
ew = float(np.abs(np.asarray(fw(m, t)) - body.omega(t)).max())
eq = float(np.abs(np.asarray(fq(m, t)) - body.rotation(t).as_quat()).max())
for name, j, nb, e in (("omega", jw, nw, ew), ("attitude", jq, nq, eq)):
    print(f"{{name:9s}} JAX {{j:8.1f}} ns, numba {{nb:8.1f}} ns: {{j / nb:5.2f}}x, diff {{e:.1e}}")
"""


def first_call(code: str) -> tuple[float, float, float]:
    """(wall s of the first call, XLA compile s, peak RSS GB) in a fresh process."""
    src = COMMON + code + "\nprint('WALL', time.perf_counter() - t0)\n"
    src += "import resource\nprint('RSS', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
    env = dict(os.environ, JAX_ENABLE_COMPILATION_CACHE="false")
    out = subprocess.run([sys.executable, "-c", src], env=env, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(out.stderr[-2000:])
    wall = float(re.search(r"WALL ([0-9.]+)", out.stdout).group(1))  # type: ignore[union-attr]
    rss = float(re.search(r"RSS ([0-9]+)", out.stdout).group(1))  # type: ignore[union-attr]
    pattern = r"Finished XLA compilation of .* in ([0-9.]+) sec"
    xla = sum(float(s) for s in re.findall(pattern, out.stderr))
    return wall, xla, rss / 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--points", nargs=2, type=int, default=(2000, 100), metavar=("N", "T"))
    args = ap.parse_args()
    print(f"load average (1, 5, 15 min): {os.getloadavg()}; {os.cpu_count()} CPUs")
    print(f"{'first call (3 bodies x 3 times)':34s} {'wall s':>8s} {'XLA s':>8s} {'peak GB':>8s}")
    for name, code in FIGURES.items():
        if args.only and name not in args.only:
            continue
        wall, xla, peak = first_call(code)
        print(f"{name:34s} {wall:8.1f} {xla:8.1f} {peak:8.2f}", flush=True)
    if not args.only or "speed" in args.only:
        n, t = args.points
        print(f"speed, {n} bodies x {t} times, per body and time:")
        out = subprocess.run(
            [sys.executable, "-c", SPEED.format(n=n, t=t)], capture_output=True, text=True
        )
        print(out.stdout or out.stderr[-2000:])


if __name__ == "__main__":
    main()
