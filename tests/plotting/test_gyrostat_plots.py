"""plot_gyrostat_polhodes: the drawn curves lie on both integrals, the drawn equilibria
are permanent rotations, their stability agrees with gyrostat_spin_stable (Agg backend).

Observed (moments (1, 2, 3), |K| = 2, four h): |m| within 2.2e-16 relative, T constant
along a curve to 8.7e-16 relative, |gyrostat_rhs| at the drawn equilibria <= 1.1e-16."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from poinsot import InvalidInputError, InvalidTypeError  # noqa: E402
from poinsot.dynamics import FreeGyrostat, gyrostat_rhs, gyrostat_spin_stable  # noqa: E402
from poinsot.plotting import plot_gyrostat_polhodes  # noqa: E402

MOMENTS = np.array([1.0, 2.0, 3.0])
K = 2.0
HS = {
    "rigid": [0.0, 0.0, 0.0],
    "weak": [0.0, 0.4, 0.0],
    "strong": [0.0, 1.2, 0.0],
    "oblique": [0.3, -0.4, 0.5],
}


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _lines(ax, gid):
    return [np.asarray(ln.get_data_3d(), dtype=float).T for ln in ax.lines if ln.get_gid() == gid]


@pytest.fixture(scope="module")
def drawn():
    axes = plot_gyrostat_polhodes(MOMENTS, list(HS.values()), momentum=K, levels=6, n=32)
    return dict(zip(HS, axes, strict=True))


@pytest.mark.parametrize("name", list(HS))
def test_curves_satisfy_both_integrals(drawn, name):
    ax, h = drawn[name], np.array(HS[name])
    curves = _lines(ax, "polhode")
    assert len(curves) >= 6
    for gid in ("polhode", "separatrix"):
        for c in _lines(ax, gid):
            # |J w + h| = |K| and T = w . J w / 2 constant along each curve (w = J^-1 (m - h))
            np.testing.assert_allclose(np.linalg.norm(c, axis=-1), K, rtol=1e-10)
            w = (c - h) / MOMENTS
            energy = 0.5 * np.sum(MOMENTS * w * w, axis=-1)
            assert np.ptp(energy) <= 1e-10 * np.max(energy)
    # a polhode is the body momentum of the exact motion started on it: FreeGyrostat's
    # momentum_body over a period stays on the curve's energy (closed form for h on an axis)
    if name in ("rigid", "weak", "strong"):
        m0 = curves[len(curves) // 2][0]
        g = FreeGyrostat(MOMENTS, h, omega0=(m0 - h) / MOMENTS)
        mb = g.momentum_body(np.linspace(0.0, 3.0, 7))
        np.testing.assert_allclose(np.linalg.norm(mb, axis=-1), K, rtol=1e-12)


@pytest.mark.parametrize("name", list(HS))
def test_equilibria_are_permanent_rotations(drawn, name):
    ax, h = drawn[name], np.array(HS[name])
    stable = _lines(ax, "equilibrium-stable")
    unstable = _lines(ax, "equilibrium-unstable")
    pts = np.concatenate(stable + unstable)
    assert len(pts) >= 2
    np.testing.assert_allclose(np.linalg.norm(pts, axis=-1), K, rtol=1e-12)
    w = (pts - h) / MOMENTS
    # gyrostat_rhs vanishes there (relative to the scale |w|^2 of its terms)
    resid = np.abs(gyrostat_rhs(MOMENTS, w, h))
    assert np.max(resid) <= 1e-12 * max(1.0, np.max(np.sum(w * w, -1)))
    # a separatrix goes through every saddle
    if unstable and _lines(ax, "separatrix"):
        seps = np.concatenate(_lines(ax, "separatrix"))
        for p in unstable[0]:
            assert np.min(np.linalg.norm(seps - p, axis=-1)) < 0.1 * K


def test_rotor_stabilises_the_intermediate_axis(drawn):
    # the equilibrium m = +K e2: unstable without the rotor and with a weak one, stable with
    # h2 > K / 3 (W = (K - h2) / I2, (K - I1 W)(K - I3 W) > 0), as gyrostat_spin_stable says
    e2 = np.array([0.0, K, 0.0])
    for name, expect in (("rigid", False), ("weak", False), ("strong", True)):
        ax, h = drawn[name], np.array(HS[name])
        spin = (K - h[1]) / MOMENTS[1]
        stable_here = gyrostat_spin_stable(MOMENTS, h, [0.0, spin, 0.0])
        assert stable_here == expect
        gid = "equilibrium-stable" if expect else "equilibrium-unstable"
        pts = np.concatenate(_lines(ax, gid))
        assert np.min(np.linalg.norm(pts - e2, axis=-1)) < 1e-12


def test_ax_is_respected_and_returned():
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    before = plt.get_fignums()
    out = plot_gyrostat_polhodes(MOMENTS, [0.0, 0.5, 0.0], momentum=K, levels=2, n=16, ax=ax)
    assert out is ax and plt.get_fignums() == before
    fig2 = plt.figure()
    pair = [fig2.add_subplot(1, 2, i + 1, projection="3d") for i in range(2)]
    out2 = plot_gyrostat_polhodes(MOMENTS, [[0, 0, 0], [0, 1, 0]], momentum=K, n=16, ax=pair)
    assert out2 == pair and all(a.lines for a in pair)


@pytest.mark.parametrize(
    "kwargs, err",
    [
        (dict(inertia=[1.0, 2.0]), InvalidInputError),
        (dict(inertia=np.diag([1.0, 2.0, 3.0])), InvalidInputError),
        (dict(h=[0.0, 1.0]), InvalidInputError),
        (dict(h=[0.0, np.nan, 0.0]), InvalidInputError),
        (dict(momentum=0.0), InvalidInputError),
        (dict(momentum=np.inf), InvalidInputError),
        (dict(levels=-1), InvalidInputError),
        (dict(levels=2.5), InvalidTypeError),
        (dict(n=4), InvalidInputError),
        (dict(ax="not axes"), InvalidInputError),
    ],
)
def test_bad_input(kwargs, err):
    args = dict(inertia=MOMENTS, h=[0.0, 1.0, 0.0], momentum=K, n=16)
    args.update(kwargs)
    with pytest.raises(err):
        plot_gyrostat_polhodes(args.pop("inertia"), args.pop("h"), **args)


def test_2d_ax_refused():
    _, ax = plt.subplots()
    with pytest.raises(InvalidInputError, match="3D"):
        plot_gyrostat_polhodes(MOMENTS, [0.0, 1.0, 0.0], momentum=K, n=16, ax=ax)
