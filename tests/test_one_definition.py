"""The shared definitions of issue 39, each against an independent truth: the relative
drift (:mod:`poinsot._drift`) against hand-computed values, the attitude distance
(:func:`poinsot._quat.attitude_distance`) against SciPy, the vertical row of ``R``
(:func:`poinsot.rotations._scalar.vertical`) against SciPy's matrix, and the atomic
writer (:mod:`poinsot._files`) when its callback fails."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from poinsot._drift import relative_change, relative_drift
from poinsot._files import atomic_write
from poinsot._quat import attitude_distance
from poinsot.rotations._scalar import vertical


# ------------------------------------------------------------------------- drift
def test_relative_drift_of_a_scalar_by_hand():
    # x0 = 4: changes 1, -2, 0.5 -> relative 0.25, -0.5, 0.125
    x = [4.0, 5.0, 2.0, 4.5]
    assert relative_change(x).tolist() == [0.0, 0.25, -0.5, 0.125]
    assert relative_drift(x) == 0.5
    assert relative_drift(x, 8.0) == 0.25  # a given reference replaces |x0|
    assert relative_drift(x, floor=10.0) == 0.2  # ref = max(|x0|, floor) = 10
    assert relative_drift(x, floor=1.0) == 0.5  # a floor below |x0| changes nothing
    # a law instead of the initial value: x - expected = 0, 1, -1, 0.5 over |x0| = 4
    assert relative_drift(x, expected=[4.0, 4.0, 3.0, 4.0]) == 0.25


def test_relative_drift_of_vectors_and_batches_by_hand():
    k = [[3.0, 4.0, 0.0], [3.0, 4.0, 1.0], [0.0, 4.0, 0.0]]  # |K0| = 5; |dK| = 1, 3
    assert relative_change(k, vector=True).tolist() == [0.0, 0.2, 0.6]
    assert relative_drift(k, vector=True) == 0.6
    # a batch of two scalars (time first): drifts 0.5 and 0.25, the largest is kept
    batch = [[2.0, 4.0], [3.0, 3.0], [2.0, 5.0]]
    assert relative_change(batch).tolist() == [[0.0, 0.0], [0.5, -0.25], [0.0, 0.25]]
    assert relative_drift(batch) == 0.5
    # per-member floors broadcast with the batch
    assert relative_drift(batch, floor=[10.0, 1.0]) == 0.25


def test_relative_drift_is_absolute_where_the_reference_is_zero():
    assert relative_change([0.0, 1e-3, -2e-3]).tolist() == [0.0, 1e-3, -2e-3]
    assert relative_drift([0.0, 1e-3, -2e-3]) == 2e-3
    assert relative_drift([[0.0, 1.0], [3e-3, 1.5]]) == 0.5  # member 1 at 0: absolute
    tiny = np.finfo(float).tiny  # a floor instead: divided, however small
    assert relative_drift([0.0, 1e-300], floor=tiny) == 1e-300 / tiny


def test_relative_drift_of_no_change_is_zero():
    assert relative_drift([1.0, 1.0, 1.0]) == 0.0
    assert relative_drift(np.zeros((3, 2, 3)), vector=True) == 0.0


# ------------------------------------------------------------- attitude distance
def _scipy_angle(q_ref: np.ndarray, q: np.ndarray) -> np.ndarray:
    r1 = SciRotation.from_quat(q_ref, scalar_first=True)
    r2 = SciRotation.from_quat(q, scalar_first=True)
    return np.asarray((r1.inv() * r2).magnitude())


@pytest.mark.parametrize(
    "angle", [0.0, 1e-12, 1e-8, 1e-4, 0.3, 1.0, 2.0, 3.0, np.pi - 1e-4, np.pi - 1e-8, np.pi]
)
def test_attitude_distance_equals_scipy_at_every_angle(angle):
    rng = np.random.default_rng(7)
    q_ref = SciRotation.random(50, rng=rng).as_quat(scalar_first=True)
    axes = rng.normal(size=(50, 3))
    axes /= np.linalg.norm(axes, axis=-1, keepdims=True)
    turn = SciRotation.from_rotvec(angle * axes)
    q = (SciRotation.from_quat(q_ref, scalar_first=True) * turn).as_quat(scalar_first=True)
    got = attitude_distance(q_ref, q)
    ref = _scipy_angle(q_ref, q)
    assert got.shape == (50,)
    # absolute accuracy of a few ulp of pi at every angle, also near 0 and near pi
    np.testing.assert_allclose(got, ref, rtol=0, atol=4e-15)
    np.testing.assert_allclose(got, angle, rtol=0, atol=4e-15)


@pytest.mark.parametrize("angle", [1e-100, 1e-15, 1e-9, 1e-4])
def test_attitude_distance_near_zero_is_relatively_accurate(angle):
    # arccos of the scalar part gives 0 below ~1e-8 (cos(f/2) rounds to 1)
    e = np.array([2.0, -1.0, 2.0]) / 3.0
    q_ref = np.array([np.cos(0.35), *(np.sin(0.35) * e)])  # 0.7 rad about e
    q = np.array([np.cos(0.35 + angle / 2), *(np.sin(0.35 + angle / 2) * e)])
    one = np.array([1.0, 0.0, 0.0, 0.0])
    small = np.array([np.cos(angle / 2), *(np.sin(angle / 2) * e)])
    assert abs(float(attitude_distance(one, small)) - angle) <= 2e-16 * angle
    assert abs(float(attitude_distance(q_ref, q)) - angle) <= 4e-16  # absolute: q rounded
    assert abs(float(attitude_distance(one, small)) - _scipy_angle(one, small)) <= 2e-16 * angle


def test_attitude_distance_near_pi_where_arccos_fails():
    # 1e-9 rad short of pi: arccos(|w|) with |w| = sin(5e-10) cannot resolve it ...
    q_ref = np.array([1.0, 0.0, 0.0, 0.0])
    d = 1e-9
    q = np.array([np.cos((np.pi - d) / 2), 0.0, np.sin((np.pi - d) / 2), 0.0])
    exact = np.pi - d
    got = float(attitude_distance(q_ref, q))
    assert abs(got - exact) < 1e-15
    assert abs(got - float(_scipy_angle(q_ref, q))) < 1e-15
    # ... nor arccos of the trace, (tr R - 1) / 2 = cos(pi - d) = -1 + d^2 / 2 rounds to -1
    tr = np.trace(SciRotation.from_quat(q, scalar_first=True).as_matrix())
    assert abs(np.arccos(np.clip((tr - 1) / 2, -1, 1)) - exact) > 1e-10


def test_attitude_distance_ignores_sign_and_norm_and_broadcasts():
    rng = np.random.default_rng(3)
    a = SciRotation.random(4, rng=rng).as_quat(scalar_first=True)
    b = SciRotation.random(4, rng=rng).as_quat(scalar_first=True)
    ref = _scipy_angle(a, b)
    np.testing.assert_allclose(attitude_distance(a, -3.0 * b), ref, rtol=0, atol=4e-15)
    np.testing.assert_allclose(attitude_distance(-a, b), ref, rtol=0, atol=4e-15)
    one = attitude_distance(a[0], b)  # one reference against four attitudes
    np.testing.assert_allclose(one, _scipy_angle(np.tile(a[0], (4, 1)), b), atol=4e-15)
    assert np.all((attitude_distance(a, b) >= 0) & (attitude_distance(a, b) <= np.pi))


# ------------------------------------------------------------------ vertical
def test_vertical_is_the_third_row_of_scipys_matrix_on_arrays_and_floats():
    q = SciRotation.random(20, rng=5).as_quat(scalar_first=True)
    mats = SciRotation.from_quat(q, scalar_first=True).as_matrix()
    rows = np.stack(vertical(*np.moveaxis(q, -1, 0)), axis=-1)
    np.testing.assert_allclose(rows, mats[:, 2, :], rtol=0, atol=1e-15)
    one = vertical(*(float(c) for c in q[0]))
    np.testing.assert_allclose(one, mats[0, 2, :], rtol=0, atol=1e-15)


# ------------------------------------------------------------------ atomic write
def test_atomic_write_keeps_the_old_file_when_the_callback_raises(tmp_path):
    path = tmp_path / "out.json"
    path.write_text("old\n")

    def boom(fh):
        fh.write("half of the new ")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        atomic_write(path, boom)
    assert path.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]  # no temporary left
    with pytest.raises(KeyboardInterrupt):  # Ctrl-C too
        atomic_write(path, lambda fh: (_ for _ in ()).throw(KeyboardInterrupt()), mode="b")
    assert path.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]


def test_atomic_write_replaces_text_and_binary(tmp_path):
    path = tmp_path / "a.txt"
    assert atomic_write(path, lambda fh: fh.write("é\n")) == path
    assert path.read_bytes() == "é\n".encode()
    atomic_write(str(path), lambda fh: fh.write(b"\x00\x01"), mode="b")
    assert path.read_bytes() == b"\x00\x01"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
