"""filter_monte_carlo (docs/theory.md §10.4): the MEKF's chi-square consistency over
seeded runs on the exact racket flip; the verdict fails for an over-confident sensor
model; Dask chunks give the serial result bit for bit; bad arguments are named."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.stats import chi2

from poinsot.dynamics import FreeRigidBody, Gyro, VectorSensor
from poinsot.ensemble import FilterConsistency, filter_monte_carlo
from poinsot.errors import InvalidInputError, InvalidTypeError

RACKET = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.05, 1.5, 0.05])
T = np.arange(0.0, 10.0 + 1e-9, 0.1)
GYRO = Gyro(1e-4, 1e-6)
SUN, MAG = [1.0, 0.0, 0.0], [0.0, 0.6, 0.8]


@dataclasses.dataclass(frozen=True)
class _Overconfident:
    """A direction sensor whose samples claim a sigma ``factor`` times too small."""

    sensor: VectorSensor
    factor: float

    def sample(self, truth, rng):
        s = self.sensor.sample(truth, rng=rng)
        return dataclasses.replace(s, sigma=s.sigma / self.factor)


@pytest.fixture(scope="module")
def truths():
    return RACKET.trajectory(T), RACKET.trajectory(T[::10])


def _sensors(tv, factor=None):
    sun, mag = VectorSensor(SUN, 2e-3), VectorSensor(MAG, 2e-3)
    if factor is not None:
        sun, mag = _Overconfident(sun, factor), _Overconfident(mag, factor)
    return [(sun, tv), (mag, tv)]


def test_a_tuned_filter_is_consistent_over_500_runs_on_dask(truths):
    """M = 500 runs (the first 5 s of the flip each: 51 gyro samples, 12 updates) on a
    local Dask cluster of two worker processes (stopped by the call): the average NEES
    lies in chi2(6M)/M's 99 % band at >= 95 % of the times, the average NIS in
    chi2(2M)/M's at >= 95 % of the updates; the bands are the chi-square distribution's,
    independent of the filter. Measured: inside at 100 % and 100 %, grand means 6.06 and
    1.99. (docs/ensembles.md: 500 runs of 30 s.)"""
    truth, tv = RACKET.trajectory(T[:51]), RACKET.trajectory(T[:51:10])
    fc = filter_monte_carlo(
        truth, GYRO, _sensors(tv), runs=500, attitude_sigma=1e-2, bias_sigma=2e-3,
        seed=3, chunk_size=125, workers=2,
    )  # fmt: skip
    assert isinstance(fc, FilterConsistency) and fc.runs == 500
    assert fc.consistent, fc
    lo, hi = chi2.ppf([0.005, 0.995], 6 * 500) / 500
    assert fc.nees_band == pytest.approx((lo, hi), rel=1e-12)
    assert fc.nees_inside >= 0.95 and lo < fc.mean_nees.mean() < hi
    assert fc.nis_inside >= 0.95 and set(fc.dof.tolist()) == {2}
    assert fc.mean_nis.shape == fc.update_t.shape == (2 * tv.t.size,)
    # ~99.7 % of Gaussian errors lie within 3 sigma; 500 x 51 correlated samples per axis
    assert np.all(fc.within_3sigma >= 0.99), fc.within_3sigma
    assert fc.diverged == 0 and "consistent" in repr(fc)


def test_an_overconfident_sensor_model_fails_the_verdict(truths):
    """The sensors' sigma claimed 5x too small: the average NIS and NEES leave their
    bands (measured: NIS grand mean 40 for 2 dof, inside at 4.5 % of the updates; NEES
    grand mean 113 for 6; 4 of 20 runs report divergence), and the verdict says so."""
    fc = filter_monte_carlo(
        truths[0], GYRO, _sensors(truths[1], factor=5.0), runs=20, attitude_sigma=1e-2,
        bias_sigma=2e-3, seed=3,
    )  # fmt: skip
    assert not fc.consistent
    assert fc.nis_inside < 0.5 and fc.mean_nis.mean() > 10.0
    assert "NOT consistent" in repr(fc)


def test_dask_chunks_equal_the_serial_runs(truths):
    """A Dask cluster (in-process, two workers) and another chunk size: the same runs
    (seeded per run), so the same numbers bit for bit."""
    distributed = pytest.importorskip("distributed")
    kw = dict(runs=12, attitude_sigma=1e-2, bias_sigma=2e-3, seed=9)
    serial = filter_monte_carlo(truths[0], GYRO, _sensors(truths[1]), chunk_size=12, **kw)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        dask = filter_monte_carlo(
            truths[0], GYRO, _sensors(truths[1]), chunk_size=5, client=client, **kw
        )
    np.testing.assert_array_equal(dask.mean_nees, serial.mean_nees)
    np.testing.assert_array_equal(dask.mean_nis, serial.mean_nis)
    np.testing.assert_array_equal(dask.within_3sigma, serial.within_3sigma)


def test_bad_arguments_are_named(truths):
    truth, tv = truths
    ok = dict(attitude_sigma=1e-2, bias_sigma=2e-3)
    with pytest.raises(InvalidTypeError, match="`truth`"):
        filter_monte_carlo(truth.quat, GYRO, [], **ok)
    with pytest.raises(InvalidTypeError, match="`gyro`"):
        filter_monte_carlo(truth, "gyro", [], **ok)
    with pytest.raises(InvalidTypeError, match=r"`sensors\[0\]`"):
        filter_monte_carlo(truth, GYRO, [VectorSensor(SUN, 2e-3)], **ok)
    with pytest.raises(InvalidInputError, match="`runs`"):
        filter_monte_carlo(truth, GYRO, [], runs=1, **ok)
    with pytest.raises(InvalidInputError, match="`bias_sigma`"):
        filter_monte_carlo(truth, GYRO, [], attitude_sigma=1e-2, bias_sigma=-1.0)
    with pytest.raises(InvalidInputError, match="`level`"):
        filter_monte_carlo(truth, GYRO, [], level=1.5, **ok)
