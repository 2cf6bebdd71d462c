"""The Foucault pendulum's two linear models against their closed forms (theory §9):
in w = x + i y, w'' + 2 i Oz w' + k w = 0 with k = omega0^2 - Oz^2 (full: the frame's
centrifugal force kept) or k = omega0^2 (textbook), released at rest at w(0) = a."""

import math

import numpy as np
import pytest

from poinsot.dynamics import foucault_pendulum
from poinsot.errors import InvalidInputError

G, L = 9.81, 2.0
OMEGA0 = math.sqrt(G / L)


def _closed_form(t, a, oz, k):
    w1 = math.sqrt(k + oz * oz)  # roots of s^2 + 2 i oz s + k: s = i(-oz +- w1)
    amp_p = 0.5 * a * (1.0 + oz / w1)
    amp_m = 0.5 * a * (1.0 - oz / w1)
    w = np.exp(-1j * oz * t) * (amp_p * np.exp(1j * w1 * t) + amp_m * np.exp(-1j * w1 * t))
    return np.stack([w.real, w.imag], axis=-1)


@pytest.mark.parametrize("model", ["full", "textbook"])
def test_models_match_their_closed_forms(model):
    """Omega_z / omega0 = 0.05: large enough that the two models differ visibly."""
    oz = 0.05 * OMEGA0
    lat = math.pi / 2  # Omega_z = omega
    t = np.linspace(0.0, 30.0, 301)
    tr = foucault_pendulum(L, lat, t, amplitude=0.1, g=G, omega=oz, model=model,
                           rtol=1e-12, atol=1e-15)  # fmt: skip
    k = OMEGA0**2 - oz**2 if model == "full" else OMEGA0**2
    ref = _closed_form(t, 0.1, oz, k)
    # observed 2e-13 m; the integrator's rtol 1e-12 bounds it
    np.testing.assert_allclose(tr.position[:, :2], ref, rtol=0, atol=1e-10)


def test_models_differ_by_the_dropped_centrifugal_term():
    """The two differ by the swing-frequency change w1 - omega0 ~ Oz^2/(2 omega0):
    measured against the two closed forms' own difference."""
    oz = 0.05 * OMEGA0
    t = np.linspace(0.0, 30.0, 301)
    kw = dict(amplitude=0.1, g=G, omega=oz, rtol=1e-12, atol=1e-15)
    full = foucault_pendulum(L, math.pi / 2, t, model="full", **kw)
    text = foucault_pendulum(L, math.pi / 2, t, model="textbook", **kw)
    d = np.linalg.norm(full.position - text.position, axis=-1).max()
    ref = np.linalg.norm(
        _closed_form(t, 0.1, oz, OMEGA0**2 - oz**2) - _closed_form(t, 0.1, oz, OMEGA0**2), axis=-1
    ).max()
    assert d == pytest.approx(ref, rel=1e-6)
    assert d > 1e-3  # a visible difference at this ratio


def test_bad_model_is_refused():
    with pytest.raises(InvalidInputError, match="model"):
        foucault_pendulum(L, 0.5, [0.0, 1.0], model="exact")
