"""Force systems on a rigid body (theory §9): principal vector and moment computed here
by hand, the moment's change of pole, the invariant, and the four simplest
equivalents; the central axis: every point on it has the smallest moment, parallel
to R."""

import numpy as np
import pytest

from poinsot.dynamics import reduce_forces
from poinsot.errors import InvalidInputError

RNG = np.random.default_rng(4)


def test_principal_vector_moment_and_invariant():
    f, p = RNG.normal(size=(2, 5, 3))
    c = RNG.normal(size=(2, 3))
    pole = RNG.normal(size=3)
    s = reduce_forces(list(zip(f, p, strict=True)), list(c), pole=pole)
    np.testing.assert_allclose(s.resultant, f.sum(0), atol=1e-14)
    m = np.cross(p - pole, f).sum(0) + c.sum(0)
    np.testing.assert_allclose(s.moment, m, atol=1e-13)
    other = RNG.normal(size=3)
    s2 = reduce_forces(list(zip(f, p, strict=True)), list(c), pole=other)
    np.testing.assert_allclose(s.moment_about(other), s2.moment, atol=1e-13)
    assert s.invariant == pytest.approx(s2.invariant, rel=1e-12)
    assert s.kind == "wrench"
    axis = s.central_axis
    # on the central axis the moment is parallel to R and the smallest
    for x in (0.0, 1.3, -2.0):
        q = axis.point + x * axis.direction
        mq = s.moment_about(q)
        np.testing.assert_allclose(np.cross(mq, s.resultant), 0.0, atol=1e-12)
        assert np.linalg.norm(mq) == pytest.approx(float(axis.min_speed), rel=1e-12)
    r = s.resultant
    assert float(axis.parameter) == pytest.approx(r @ s.moment / (r @ r), rel=1e-12)


def test_simplest_equivalents():
    assert reduce_forces([([0, 0, 1.0], [1.0, 2.0, 0])]).kind == "resultant"
    couple = reduce_forces([([1.0, 0, 0], [0, 1.0, 0]), ([-1.0, 0, 0], [0, -1.0, 0])])
    assert couple.kind == "couple" and couple.central_axis is None
    np.testing.assert_allclose(couple.moment, [0.0, 0.0, -2.0], atol=1e-15)
    assert reduce_forces([([1.0, 0, 0], [0, 0, 0]), ([-1.0, 0, 0], [3.0, 0, 0])]).kind == (
        "equilibrium"
    )
    # two forces whose lines cross: a single resultant through the crossing point
    s = reduce_forces([([1.0, 0, 0], [0, 2.0, 0]), ([0, 1.0, 0], [5.0, 0, 0])])
    assert s.kind == "resultant"
    np.testing.assert_allclose(s.central_axis.closest_point([5.0, 2.0, 0.0]), [5.0, 2.0, 0.0],
                               atol=1e-14)  # fmt: skip


def test_bad_inputs_name_forces_and_couples():
    with pytest.raises(InvalidInputError, match=r"`forces\[0\]` to be a pair"):
        reduce_forces([[1.0, 2.0, 3.0]])
    with pytest.raises(InvalidInputError, match=r"`couples\[1\]`"):
        reduce_forces([], [[0, 0, 1.0], [1.0, 2.0]])


def test_fully_dissipative_versus_merely_dissipative():
    """-beta v has F . v = -beta |v|^2 < 0 for every v != 0 (fully); a force damping
    v_x alone has F . v = 0 for v along y (merely dissipative); quadratic drag
    -c |v| v is fully dissipative; a linear damping matrix with an undamped oblique
    direction is found by the Jacobian's softest direction."""
    from poinsot.dynamics import classify_force

    full = classify_force(lambda t, r, v: -0.3 * v)
    assert full.kind == "dissipative" and full.fully_dissipative
    partial = classify_force(lambda t, r, v: np.array([-0.3 * v[0], 0.0, 0.0]))
    assert partial.kind == "dissipative" and not partial.fully_dissipative
    drag = classify_force(lambda t, r, v: -0.2 * np.linalg.norm(v) * v)
    assert drag.kind == "dissipative" and drag.fully_dissipative
    n = np.array([1.0, 2.0, -0.7]) / np.linalg.norm([1.0, 2.0, -0.7])
    d = np.eye(3) - np.outer(n, n)  # damps everything but v along n
    oblique = classify_force(lambda t, r, v: -d @ v)
    assert oblique.kind == "dissipative" and not oblique.fully_dissipative
    assert not classify_force(lambda t, r, v: -2.0 * r).fully_dissipative
