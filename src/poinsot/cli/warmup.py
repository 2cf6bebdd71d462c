"""``poinsot warmup``: compile every numba kernel into numba's cache, once per install.

A cold cache makes a kernel's first call either compile (10-60 s) or, when the problem
is small, run on the interpreter while a background ``poinsot warmup --background``
fills the cache (docs/performance.md, "Cold start"). Running ``poinsot warmup`` at
install time (a Docker image's build step, a site install) makes every first call as
fast as the later ones.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

from .. import _jit
from ..dynamics import (
    ConstantBodyTorque,
    ConstantSpaceTorque,
    FreeRigidBody,
    GravityGradientTorque,
    GravityTorque,
    GyrostaticTorque,
    HeavyRigidBody,
    KeplerOrbit,
    LagrangeTop,
    OrbitGravityGradientTorque,
    TorqueModel,
    simulate,
)
from ..rotations import PARALLEL_MIN_SIZE, determine_attitude
from ..rotations.rotation import Rotation

DESCRIPTION = (
    "Compile every poinsot kernel for this machine into numba's cache (NUMBA_CACHE_DIR, "
    "else the package's __pycache__), so that no first call compiles or is interpreted."
)
EPILOG = """examples:
  poinsot warmup                          # once after installing or upgrading
  NUMBA_CACHE_DIR=/opt/cache poinsot warmup   # a shared cache (set the same at run time)

docs/performance.md, 'Cold start'.
"""

#: a background build younger than this (s) holds the lock; an older lock is stale
LOCK_S = 20 * 60


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quiet", action="store_true", help="print nothing")
    p.add_argument(
        "--background",
        action="store_true",
        help="low priority, at most one at a time per cache (what poinsot starts itself)",
    )
    p.set_defaults(func=_cmd_warmup)


def exercise() -> None:
    """Call every compiled path once on small inputs (the same argument types as any
    call): rotations (small and threaded batches), simulate with each method and
    built-in torque (one body, and a batch wide enough for the SIMD lanes, whose kernel
    is compiled per torque kind and inertia form: every one of them), the heavy top,
    the exact free body and the Lagrange top."""

    rng = np.random.default_rng(0)
    for n in (3, PARALLEL_MIN_SIZE):
        r = Rotation.from_euler("ZXZ", rng.uniform(-3.0, 3.0, (n, 3)))
        r.apply([1.0, 0.0, 0.0])
        for seq in ("ZYX", "ZXZ"):
            Rotation.from_euler(seq, r.as_euler(seq))
        Rotation.from_matrix(r.as_matrix())
        Rotation.from_rotvec(r.as_rotvec())
        (r * r.inv()).magnitude()
        obs = r.as_matrix()[:, :2, :]  # b_i = C^T e_i, the rows of C
        for method in ("quest", "esoq2"):  # one catalogue for the batch, and one per set
            determine_attitude(obs, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], method=method)
            determine_attitude(obs, np.broadcast_to([[1.0, 0, 0], [0, 1.0, 0]], obs.shape),
                               [1.0, 2.0], method=method)  # fmt: skip
    t = np.linspace(0.0, 0.2, 3)
    for n in (2, 1, 9):  # 2 first: one body then runs the (compiled) batch kernel
        j = np.tile([1.0, 2.0, 2.5], (n, 1))
        q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        w = np.tile([0.1, 1.0, 0.1], (n, 1))
        for torque in (None, ConstantBodyTorque([0.0, 0.1, 0.0]), GravityTorque(1.0, [0, 0, 0.1])):
            simulate(j, q, w, t, torque=torque, rtol=1e-8)
            for method in ("midpoint", "splitting", "rk4"):
                simulate(j, q, w, t, torque=torque, method=method, max_step=0.1)
    # the SIMD lanes are compiled per torque kind and inertia form: every other one
    j, q, w = j[0], np.tile([1.0, 0.0, 0.0, 0.0], (9, 1)), np.tile([0.1, 1.0, 0.1], (9, 1))
    orbit = KeplerOrbit(7.0e6, 0.01, 0.9, 0.4, 0.0, 0.3)
    others: tuple[TorqueModel, ...] = (
        ConstantSpaceTorque([0.0, 0.1, 0.0]),
        GravityGradientTorque(j, 7.0e6, [0.3, -0.4, 0.8]),
        GyrostaticTorque([0.0, 0.0, 0.5]),
        OrbitGravityGradientTorque(j, orbit),
    )
    for other in others:
        simulate(j, q, w, t, torque=other, rtol=1e-8)
    tensor = np.array([[1.0, 0.1, 0.0], [0.1, 2.0, 0.0], [0.0, 0.0, 2.5]])  # not principal
    for torque in (None, GravityTorque(1.0, [0, 0, 0.1])):
        simulate(tensor, q, w, t, torque=torque, rtol=1e-8)
    top = HeavyRigidBody([1.0, 1.0, 0.4], 2.0, [0.0, 0.0, 0.3])
    top.simulate([1.0, 0.0, 0.0, 0.0], [0.0, 0.5, 15.0], t)
    FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1]).trajectory(t)
    lt = LagrangeTop(1.0, 0.4, 0.6, theta=0.5, spin=15.0)
    lt.trajectory(t)


def _lock(marker: Path) -> Path | None:
    """Take the build lock next to ``marker`` (None: another build holds it)."""
    lock = marker.with_name(marker.name + ".lock")
    lock.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        try:
            if time.time() - lock.stat().st_mtime < LOCK_S:
                return None
            lock.unlink()
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except OSError:
            return None
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    return lock


def _cmd_warmup(args: argparse.Namespace) -> int:
    os.environ["POINSOT_INTERPRET_FIRST"] = "0"  # compile, never interpret, here
    if not _jit.NUMBA:
        if not args.quiet:
            print("poinsot warmup: numba is not in use (POINSOT_NUMBA=0 or not installed); "
                  "nothing to compile.")  # fmt: skip
        return 0
    marker = _jit._marker()
    if args.background:
        if hasattr(os, "nice"):
            os.nice(10)
        lock = _lock(marker)
        if lock is None:
            return 0
    else:
        lock = None
    t0 = time.perf_counter()
    try:
        with _jit.mute_compile_notice():
            exercise()
        _jit.mark_warm()
    finally:
        if lock is not None:
            lock.unlink(missing_ok=True)
    if not args.quiet:
        print(
            f"poinsot warmup: every kernel compiled and cached in {time.perf_counter() - t0:.1f} s "
            f"({marker.parent}); first calls now load them (docs/performance.md, 'Cold start')."
        )
    sys.stdout.flush()
    return 0
