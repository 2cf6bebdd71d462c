"""The free-body figures draw without error and return their axes (Agg backend)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from poinsot import InvalidInputError, InvalidTypeError  # noqa: E402
from poinsot.dynamics import FreeRigidBody  # noqa: E402
from poinsot.plotting import plot_maccullagh, plot_omega, plot_poinsot  # noqa: E402

CASES = {
    "major": ([1.0, 2.0, 3.0], [0.2, 0.3, 1.0]),
    "flip": ([1.0, 2.0, 3.0], [0.05, 1.0, 0.05]),
    "separatrix": ([6.0, 5.0, 2.0], [1.0, 0.5, 1.0]),
    "symmetric": ([2.0, 2.0, 1.0], [0.2, 0.3, 1.0]),
    "spherical": ([2.0, 2.0, 2.0], [0.2, 0.3, 1.0]),
}
BODIES = {name: FreeRigidBody(m, omega0=w) for name, (m, w) in CASES.items()}


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.mark.parametrize("name", list(BODIES))
def test_plot_maccullagh(name):
    ax = plot_maccullagh(BODIES[name], n=60)
    assert ax.name == "3d"
    # track + separatrices (two for distinct moments)
    assert len(ax.lines) == (3 if name in ("major", "flip", "separatrix") else 1)
    track = np.asarray(ax.lines[-1].get_data_3d()).T
    np.testing.assert_allclose(track, BODIES[name].maccullagh(60).track)
    # the drawn body-axes K lies on the momentum sphere and the energy ellipsoid
    # (docs/theory.md §10),
    # both computed here from the initial state
    moments, w0 = (np.asarray(x) for x in CASES[name])
    k2, two_t = np.sum((moments * w0) ** 2), np.sum(moments * w0**2)
    np.testing.assert_allclose(np.sum(track**2, axis=-1), k2, rtol=1e-12)
    np.testing.assert_allclose(np.sum(track**2 / moments, axis=-1), two_t, rtol=1e-12)


@pytest.mark.parametrize("name", list(BODIES))
def test_plot_poinsot(name):
    body = BODIES[name]
    ax = plot_poinsot(body, n=80)
    assert ax.name == "3d"
    herp = np.asarray(ax.lines[1].get_data_3d()).T
    np.testing.assert_allclose(herp, body.poinsot(n=80).herpolhode)
    # in the invariable plane: normal K (= J w0 in space, identity start) at distance
    # sqrt(2T) / |K| from the fixed point (docs/theory.md §10), computed here from the initial state
    moments, w0 = (np.asarray(x) for x in CASES[name])
    k = moments * w0
    dist = np.sqrt(np.sum(moments * w0**2)) / np.linalg.norm(k)
    np.testing.assert_allclose(herp @ (k / np.linalg.norm(k)), dist, rtol=1e-12)


def test_plot_on_given_axes_and_times():
    fig = plt.figure()
    ax3 = fig.add_subplot(projection="3d")
    body = BODIES["flip"]
    assert plot_poinsot(body, t=np.linspace(0, 10, 50), ax=ax3) is ax3
    ax = fig.add_subplot(2, 1, 1)
    t = np.linspace(0.0, 2 * body.period, 200)
    assert plot_omega(body, t, ax=ax) is ax
    np.testing.assert_allclose(ax.lines[1].get_ydata(), body.omega(t)[:, 1])


def test_plot_errors():
    with pytest.raises(InvalidTypeError, match="`body` to be a poinsot.dynamics.FreeRigidBody"):
        plot_maccullagh(object())
    _, ax2 = plt.subplots()
    with pytest.raises(InvalidInputError, match="`ax` to be a 3D axes"):
        plot_maccullagh(BODIES["major"], ax=ax2)
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\)"):
        plot_omega(BODIES["major"], [[0.0, 1.0]])
    batch = FreeRigidBody([1.0, 2.0, 3.0], omega0=[[0.2, 0.3, 1.0], [1.0, 0.3, 0.2]])
    with pytest.raises(InvalidInputError, match=r"one body, got a batch of shape \(2,\)"):
        plot_omega(batch, [0.0, 1.0])
    # a body of a batch plots as the same single body
    ax = plot_omega(batch[1], np.linspace(0.0, 5.0, 11))
    np.testing.assert_array_equal(
        ax.lines[0].get_ydata(), batch.omega(np.linspace(0, 5, 11))[1, :, 0]
    )
