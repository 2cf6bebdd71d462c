"""Monte-Carlo consistency of the attitude filter (MEKF) on Dask (docs/theory.md §10.4).

:func:`filter_monte_carlo` runs :func:`poinsot.dynamics.run_mekf` ``runs`` times on one
exact truth, each run with its own seeded sensor noise, true gyro bias and initial
error drawn from the filter's prior, in chunks on a Dask cluster (or in this process),
and judges the filter by the classical chi-square tests (Bar-Shalom, Li & Kirubarajan,
*Estimation with Applications to Tracking and Navigation*, §5.4):

- the average NEES over the ``M`` runs at each time, ``(1/M) sum e^T P^-1 e``, is
  ``chi2(6 M) / M`` for a consistent filter (6 states: attitude and bias);
- the average NIS of each update, ``(1/M) sum y^T S^-1 y``, is ``chi2(d M) / M`` with
  ``d`` its dimension (2 for a direction, 3 for an attitude).

The filter is declared consistent when both averages lie in their two-sided ``level``
bands at no fewer than 95 % of the times (updates) and their grand means lie in the
band of the pooled statistic. Run ``i`` draws from ``SeedSequence(seed,
spawn_key=(i,))``: the result does not depend on the chunks, the workers or their
order.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _quat
from ..dynamics.estimation import Gyro, attitude_error, nees, nis, run_mekf
from ..errors import InvalidInputError, InvalidTypeError
from ..trajectory import Trajectory
from .engine import _client, _stop

__all__ = ["FilterConsistency", "filter_monte_carlo"]

#: fraction of times (updates) whose average NEES (NIS) must lie in its band
INSIDE = 0.95


@dataclass(frozen=True)
class FilterConsistency:
    """What :func:`filter_monte_carlo` measured over ``runs`` seeded runs.

    Attributes
    ----------
    runs : int
    t : ndarray, shape (n,)
        Gyro times (s).
    mean_nees : ndarray, shape (n,)
        Average NEES over the runs at each time (6 dof per run).
    nees_band : tuple of float
        Its two-sided ``level`` band, ``chi2.ppf((1 -+ level)/2, 6 M) / M``.
    nees_inside : float
        Fraction of the times whose average NEES lies in the band.
    update_t : ndarray, shape (m,)
        Times of the updates (s), in processing order.
    dof : ndarray of int, shape (m,)
        Dimension of each update (2 for a direction, 3 for an attitude).
    mean_nis : ndarray, shape (m,)
        Average NIS over the runs of each update.
    nis_inside : float
        Fraction of the updates whose average NIS lies in its band
        ``chi2.ppf((1 -+ level)/2, d M) / M``.
    within_3sigma : ndarray, shape (3,)
        Pooled fraction of the attitude errors within 3 sigma, per body axis.
    final_bias_within_3sigma : float
        Fraction of the final bias errors (all runs and axes) within 3 sigma.
    diverged : int
        Runs whose filter reported divergence (:func:`~poinsot.dynamics.run_mekf`).
    level : float
    consistent : bool
        The verdict (module notes).
    """

    runs: int
    t: np.ndarray
    mean_nees: np.ndarray
    nees_band: tuple[float, float]
    nees_inside: float
    update_t: np.ndarray
    dof: np.ndarray
    mean_nis: np.ndarray
    nis_inside: float
    within_3sigma: np.ndarray
    final_bias_within_3sigma: float
    diverged: int
    level: float
    consistent: bool

    def __repr__(self) -> str:
        verdict = "consistent" if self.consistent else "NOT consistent"
        return (
            f"FilterConsistency({self.runs} runs, {verdict}: average NEES inside its "
            f"{self.level:.0%} band at {self.nees_inside:.1%} of times (grand mean "
            f"{self.mean_nees.mean():.3f}, 6 expected), average NIS at {self.nis_inside:.1%} "
            f"of updates, {self.diverged} diverged)"
        )


def _runs(
    truth: Trajectory,
    gyro: Gyro,
    sensors: Sequence[tuple[Any, Trajectory]],
    attitude_sigma: float,
    bias_sigma: float,
    seed: int,
    first: int,
    count: int,
) -> dict[str, np.ndarray]:
    """Runs ``first .. first + count - 1``: NEES (count, n), NIS (count, m), the
    attitude errors within 3 sigma (count, 3), the final bias ones (count, 3),
    divergence (count,)."""
    p0 = np.r_[[attitude_sigma**2] * 3, [bias_sigma**2] * 3]
    out: dict[str, list[Any]] = {k: [] for k in ("nees", "nis", "inside", "bias", "div")}
    update_t = dof = None
    for i in range(first, first + count):
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(i,)))
        b0 = bias_sigma * rng.standard_normal(3)
        g = dataclasses.replace(gyro, bias0=b0).sample(truth, rng=rng)
        meas = [sensor.sample(traj, rng=rng) for sensor, traj in sensors]
        q0 = _quat.mul(truth.quat[0], _quat.from_rotvec(attitude_sigma * rng.standard_normal(3)))
        r = run_mekf(g, meas, q0, p0)
        sigma = r.sigma
        out["nees"].append(nees(r, g))
        out["nis"].append(nis(r))
        out["inside"].append((np.abs(attitude_error(r.quat, g.quat)) <= 3 * sigma[:, :3]).mean(0))
        out["bias"].append(np.abs(r.bias[-1] - g.bias[-1]) <= 3 * sigma[-1, 3:])
        out["div"].append(r.diverged)
        update_t, dof = r.update_t, r.dof
    res = {k: np.asarray(v) for k, v in out.items()}
    res["update_t"], res["dof"] = np.asarray(update_t), np.asarray(dof)
    return res


def filter_monte_carlo(
    truth: Trajectory,
    gyro: Gyro,
    sensors: Sequence[tuple[Any, Trajectory]],
    runs: int = 500,
    *,
    attitude_sigma: float,
    bias_sigma: float,
    seed: int = 0,
    chunk_size: int = 50,
    level: float = 0.99,
    client: Any = None,
    scheduler: str | None = None,
    workers: int | None = None,
    timeout: float = 30.0,
) -> FilterConsistency:
    """Judge the MEKF's consistency over ``runs`` seeded Monte-Carlo runs (module notes;
    docs/theory.md §10.4).

    Each run draws the true gyro bias ``b ~ N(0, bias_sigma^2 I)`` (``gyro``'s own
    ``bias0`` is replaced), the gyro and sensor noise, and the filter's initial attitude
    ``q0 = q_true(t0) o exp(dtheta / 2)``, ``dtheta ~ N(0, attitude_sigma^2 I)``; the
    filter starts at that attitude, bias 0 and covariance
    ``diag(attitude_sigma^2 I, bias_sigma^2 I)``, and knows ``gyro``'s noise.

    Parameters
    ----------
    truth : Trajectory
        The true motion at the gyro times (an exact solution: ``FreeRigidBody``,
        ``LagrangeTop``, ``FreeGyrostat`` trajectories).
    gyro : Gyro
        The gyro model (ARW, RRW, scale factor, kind).
    sensors : sequence of (sensor, Trajectory)
        Each sensor (``StarTracker``, ``VectorSensor``) with the true motion at its
        sample times.
    runs : int
        Number of runs, >= 2.
    attitude_sigma, bias_sigma : float
        The prior: rad and rad/s, > 0.
    seed : int
        Run ``i`` draws from ``numpy.random.SeedSequence(seed, spawn_key=(i,))``.
    chunk_size : int
        Runs per Dask task.
    level : float
        Probability of the two-sided chi-square bands, in (0, 1).
    client : dask.distributed.Client, optional
        A cluster to run the chunks on; else ``scheduler`` (an address) or ``workers``
        (a local cluster of that many processes, stopped afterwards); with none of the
        three, the runs execute in this process.
    timeout : float
        Seconds to connect to ``scheduler``.

    Returns
    -------
    FilterConsistency

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.dynamics import FreeRigidBody, Gyro, VectorSensor
    >>> from poinsot.ensemble import filter_monte_carlo
    >>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.05, 1.5, 0.05])   # the racket flip
    >>> t = np.arange(0.0, 10.0 + 1e-9, 0.1)
    >>> sun = (VectorSensor([1.0, 0.0, 0.0], 2e-3), body.trajectory(t[::10]))
    >>> mag = (VectorSensor([0.0, 0.6, 0.8], 2e-3), body.trajectory(t[::10]))
    >>> fc = filter_monte_carlo(body.trajectory(t), Gyro(1e-4, 1e-6), [sun, mag], runs=20,
    ...                         attitude_sigma=1e-2, bias_sigma=2e-3)
    >>> fc.consistent, fc.diverged
    (True, 0)
    """
    from scipy.stats import chi2

    if not isinstance(truth, Trajectory):
        raise InvalidTypeError(f"Expected `truth` to be a Trajectory, got {type(truth).__name__}.")
    if not isinstance(gyro, Gyro):
        raise InvalidTypeError(f"Expected `gyro` to be a Gyro, got {type(gyro).__name__}.")
    pairs = list(sensors)
    for k, pair in enumerate(pairs):
        if not (isinstance(pair, tuple) and len(pair) == 2 and isinstance(pair[1], Trajectory)):
            raise InvalidTypeError(
                f"Expected `sensors[{k}]` to be a (sensor, Trajectory) pair, got {pair!r:.80}."
            )
        if not callable(getattr(pair[0], "sample", None)):
            raise InvalidTypeError(
                f"Expected `sensors[{k}][0]` to be a sensor model with sample(), got "
                f"{type(pair[0]).__name__}."
            )
    for name, value in (("runs", runs), ("chunk_size", chunk_size), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise InvalidTypeError(f"Expected `{name}` to be an integer, got {value!r}.")
    if runs < 2 or chunk_size < 1 or seed < 0:
        raise InvalidInputError(
            f"Expected `runs` >= 2, `chunk_size` >= 1 and `seed` >= 0, got {runs}, "
            f"{chunk_size}, {seed}."
        )
    for label, sigma in (("attitude_sigma", attitude_sigma), ("bias_sigma", bias_sigma)):
        if not (isinstance(sigma, int | float) and math.isfinite(sigma) and sigma > 0):
            raise InvalidInputError(f"Expected `{label}` to be a positive number, got {sigma!r}.")
    if not (isinstance(level, float) and 0.0 < level < 1.0):
        raise InvalidInputError(f"Expected `level` to be a probability in (0, 1), got {level!r}.")

    starts = list(range(0, runs, chunk_size))
    sizes = [min(chunk_size, runs - s) for s in starts]
    args = (truth, gyro, pairs, float(attitude_sigma), float(bias_sigma), int(seed))
    if client is None and scheduler is None and workers is None:
        parts = [_runs(*args, s, n) for s, n in zip(starts, sizes, strict=True)]
    else:
        own = None
        if client is None:
            client, own = _client(scheduler, workers, timeout)
        futures: list[Any] = []
        try:
            futures = [
                client.submit(_runs, *args, s, n, pure=False)
                for s, n in zip(starts, sizes, strict=True)
            ]
            parts = client.gather(futures)
        except BaseException:
            _stop(client, own, futures)
            raise
        if own is not None:  # our local cluster: its workers stopped at once, quietly
            _stop(client, own, [])
    cat = {k: np.concatenate([p[k] for p in parts]) for k in ("nees", "nis", "inside", "bias")}
    m = runs
    half = (1.0 - level) / 2.0
    lo, hi = (float(x) for x in chi2.ppf([half, 1.0 - half], 6 * m) / m)
    mean_nees = cat["nees"].mean(axis=0)
    nees_inside = float(np.mean((mean_nees >= lo) & (mean_nees <= hi)))
    dof = parts[0]["dof"]
    mean_nis = cat["nis"].mean(axis=0) if dof.size else np.zeros(0)
    lo2, hi2 = chi2.ppf(half, dof * m) / m, chi2.ppf(1.0 - half, dof * m) / m
    nis_inside = float(np.mean((mean_nis >= lo2) & (mean_nis <= hi2))) if dof.size else 1.0
    # the grand means against the per-time bands (the times of one run are correlated:
    # a pooled chi-square band would be too narrow)
    grand = bool(lo <= mean_nees.mean() <= hi)
    if dof.size:
        grand = grand and bool(np.min(lo2 / dof) <= np.mean(mean_nis / dof) <= np.max(hi2 / dof))
    diverged = int(np.sum(np.concatenate([p["div"] for p in parts])))
    return FilterConsistency(
        runs=m,
        t=np.asarray(truth.t),
        mean_nees=mean_nees,
        nees_band=(lo, hi),
        nees_inside=nees_inside,
        update_t=parts[0]["update_t"],
        dof=dof,
        mean_nis=mean_nis,
        nis_inside=nis_inside,
        within_3sigma=cat["inside"].mean(axis=0),
        final_bias_within_3sigma=float(cat["bias"].mean()),
        diverged=diverged,
        level=level,
        consistent=bool(nees_inside >= INSIDE and nis_inside >= INSIDE and grand and not diverged),
    )
