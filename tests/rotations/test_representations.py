"""Every rotation representation: SPEC S2-S3 formulas, round trips on edge sets and
random samples, and SciPy's ``Rotation`` as an oracle."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation
from scipy.spatial.transform import Slerp

from poinsot import GimbalLockWarning, InvalidTypeError, Rotation
from rotation_cases import (
    SCIPY_POWER,
    all_quaternions,
    assert_same_rotation,
    edge_quaternions,
    quat_distance,
    random_quaternions,
)

Q = all_quaternions()
SCIPY = SciPyRotation.from_quat(Q, scalar_first=True)
SEQUENCES = [
    "".join(s) for s in itertools.product("xyz", repeat=3) if s[0] != s[1] and s[1] != s[2]
]
SEQUENCES = SEQUENCES + [s.upper() for s in SEQUENCES]
assert len(SEQUENCES) == 24


def hat(v):
    x, y, z = v
    return np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def test_matrix_spec_formula_and_eigenstructure():
    """SPEC S2: A = E + 2 l0 l^ + 2 l^ l^; eigenvalues 1, cos f +- i sin f; axis eigvec of 1."""
    r = Rotation.from_quat(Q)
    a = r.as_matrix()
    for q, m in zip(Q, a, strict=True):
        lh = hat(q[1:])
        np.testing.assert_allclose(m, np.eye(3) + 2 * q[0] * lh + 2 * lh @ lh, atol=1e-15)
    f = r.magnitude()
    axis, _ = r.as_axis_angle()
    for m, fk, e in zip(a[-300:], f[-300:], axis[-300:], strict=True):
        ev = np.linalg.eigvals(m)
        expected = np.array([1, np.exp(1j * fk), np.exp(-1j * fk)])
        np.testing.assert_allclose(np.sort_complex(ev), np.sort_complex(expected), atol=1e-12)
        np.testing.assert_allclose(m @ e, e, atol=1e-14)
    np.testing.assert_allclose(a, SCIPY.as_matrix(), atol=2e-14)


def test_rodrigues_formula():
    """SPEC S2: A = E cos f + e^ sin f + (1 - cos f) e e^T."""
    rng = np.random.default_rng(3)
    e = rng.standard_normal((40, 3))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    f = rng.uniform(0, np.pi, 40)
    a = Rotation.from_rotvec(e * f[:, None]).as_matrix()
    for m, ek, fk in zip(a, e, f, strict=True):
        ref = np.eye(3) * np.cos(fk) + hat(ek) * np.sin(fk) + (1 - np.cos(fk)) * np.outer(ek, ek)
        np.testing.assert_allclose(m, ref, atol=1e-15)


def test_matrix_round_trip_and_scipy():
    r = Rotation.from_quat(Q)
    back = Rotation.from_matrix(r.as_matrix())
    assert_same_rotation(back.as_quat(), Q, atol=2e-14)
    assert_same_rotation(
        Rotation.from_matrix(SCIPY.as_matrix()).as_quat(), SCIPY.as_quat(scalar_first=True), 2e-14
    )


def test_rotvec_round_trip_and_scipy():
    r = Rotation.from_quat(Q)
    v = r.as_rotvec()
    assert np.all(np.linalg.norm(v, axis=1) <= np.pi + 1e-14)
    assert_same_rotation(Rotation.from_rotvec(v).as_quat(), Q, 2e-14)
    sv = SCIPY.as_rotvec()
    # at exactly pi the sign of the rotation vector is arbitrary: compare rotations there
    same = np.linalg.norm(sv, axis=1) < np.pi - 1e-6
    np.testing.assert_allclose(v[same], sv[same], atol=1e-14)
    assert_same_rotation(Rotation.from_rotvec(sv).as_quat(), Q, 2e-14)
    np.testing.assert_allclose(
        Rotation.from_rotvec(np.rad2deg(sv), degrees=True).as_matrix(),
        SCIPY.as_matrix(),
        atol=2e-14,
    )
    # tiny angles keep full relative precision
    tiny = np.array([1e-12, -3e-13, 2e-13])
    np.testing.assert_allclose(Rotation.from_rotvec(tiny).as_rotvec(), tiny, rtol=1e-15)


def test_axis_angle_round_trip():
    r = Rotation.from_quat(Q)
    axis, angle = r.as_axis_angle()
    np.testing.assert_allclose(np.linalg.norm(axis, axis=1), 1.0, atol=1e-15)
    assert np.all((angle >= 0) & (angle <= np.pi))
    assert_same_rotation(Rotation.from_axis_angle(axis, angle).as_quat(), Q, 2e-14)
    ax2, ang2 = r.as_axis_angle(degrees=True)
    np.testing.assert_allclose(ang2, np.rad2deg(angle))
    np.testing.assert_allclose(angle, r.magnitude(), atol=0)
    np.testing.assert_allclose(r.magnitude(), SCIPY.magnitude(), atol=1e-15)


def test_gibbs_and_mrp():
    r = Rotation.from_quat(Q)
    mrp = r.as_mrp()
    assert np.all(np.linalg.norm(mrp, axis=1) <= 1 + 1e-14)
    assert_same_rotation(Rotation.from_mrp(mrp).as_quat(), Q, 2e-14)
    np.testing.assert_allclose(
        Rotation.from_mrp(SCIPY.as_mrp()).as_matrix(), SCIPY.as_matrix(), atol=2e-14
    )
    # MRP = e tan(f/4), Gibbs = e tan(f/2)
    axis, f = r.as_axis_angle()
    np.testing.assert_allclose(mrp, axis * np.tan(f / 4)[:, None], atol=1e-14)
    finite = f < np.pi - 1e-6
    g = r[finite].as_gibbs()
    # tan(f/2) amplifies the reference's own rounding near pi, hence rtol
    np.testing.assert_allclose(
        g, axis[finite] * np.tan(f[finite] / 2)[:, None], rtol=1e-11, atol=1e-15
    )
    assert_same_rotation(Rotation.from_gibbs(g).as_quat(), Q[finite], 2e-14)


def test_gibbs_at_pi_warns_and_is_infinite():
    from poinsot import SingularityWarning

    with pytest.warns(SingularityWarning, match="infinite"):
        g = Rotation.from_quat([0.0, 0.0, 0.0, 1.0]).as_gibbs()
    assert g[2] == np.inf and g[0] == 0 and g[1] == 0


@pytest.mark.parametrize("seq", SEQUENCES)
def test_euler_against_scipy_and_round_trip(seq):
    angles_in = np.random.default_rng(abs(hash(seq)) % 2**32).uniform(-np.pi, np.pi, (200, 3))
    r = Rotation.from_euler(seq, angles_in)
    np.testing.assert_allclose(
        r.as_matrix(), SciPyRotation.from_euler(seq, angles_in).as_matrix(), atol=1e-15
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ang = Rotation.from_quat(Q).as_euler(seq)
    singular = np.array([bool(caught)] * len(Q))
    back = Rotation.from_euler(seq, ang).as_quat()
    d = quat_distance(back, Q)
    # Away from gimbal lock: a few ulp. Within the documented 1e-7 rad of it: at most that.
    sp = SCIPY.as_euler(seq) if not caught else None
    assert np.max(d) <= (5e-8 if singular.any() else 1e-14), np.max(d)
    if sp is not None:
        assert_same_rotation(Rotation.from_euler(seq, sp).as_quat(), Q, 1e-14)
    # degrees
    np.testing.assert_allclose(
        Rotation.from_euler(seq, np.rad2deg(angles_in[:5]), degrees=True).as_quat(),
        r[:5].as_quat(),
        atol=1e-15,
    )


@pytest.mark.parametrize("seq", SEQUENCES)
def test_euler_random_round_trip_exact(seq):
    q = random_quaternions(500, seed=11)
    with warnings.catch_warnings():
        warnings.simplefilter("error", GimbalLockWarning)
        ang = Rotation.from_quat(q).as_euler(seq)
    assert_same_rotation(Rotation.from_euler(seq, ang).as_quat(), q, 1e-14)
    ref = SciPyRotation.from_quat(q, scalar_first=True).as_euler(seq)
    # same angles as SciPy (up to the wrap of exactly +-pi)
    d = np.abs((ang - ref + np.pi) % (2 * np.pi) - np.pi)
    assert np.max(d) < 1e-12


def test_intrinsic_equals_reversed_extrinsic():
    """SPEC S3: intrinsic abc with (a1, a2, a3) equals extrinsic cba with (a3, a2, a1)."""
    a = np.random.default_rng(1).uniform(-3, 3, (20, 3))
    for seq in SEQUENCES[:12]:
        r1 = Rotation.from_euler(seq.upper(), a)
        r2 = Rotation.from_euler(seq[::-1], a[:, ::-1])
        assert_same_rotation(r1.as_quat(), r2.as_quat(), 2e-14)


def test_euler_presets_match_spec_matrices():
    """SPEC S3: C = A_psi A_theta A_phi for the classical Euler angles (z, x', z'')."""
    psi, theta, phi = 0.4, 1.1, -0.7

    def rz(a):
        return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])

    def rx(a):
        return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])

    def ry(a):
        return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])

    c = Rotation.from_euler("euler", [psi, theta, phi]).as_matrix()
    np.testing.assert_allclose(c, rz(psi) @ rx(theta) @ rz(phi), atol=1e-15)
    k = Rotation.from_euler("krylov", [psi, theta, phi]).as_matrix()
    np.testing.assert_allclose(k, rz(psi) @ rx(theta) @ ry(phi), atol=1e-15)
    np.testing.assert_allclose(
        Rotation.from_matrix(c).as_euler("euler"), [psi, theta, phi], atol=1e-15
    )


@pytest.mark.parametrize("seq", ["ZXZ", "zyz", "XYZ", "zyx", "krylov"])
@pytest.mark.parametrize("offset", [0.0, 1e-9, 5e-8])
def test_gimbal_lock(seq, offset):
    """At (or within 1e-7 rad of) the singular middle angle: warning, third angle 0,
    and the rotation is reproduced to within the threshold."""
    proper = seq.lower() in ("euler", "zxz", "zyz")
    for middle in [0.0, np.pi] if proper else [np.pi / 2, -np.pi / 2]:
        m = middle + (offset if middle <= 0 or not proper else -offset)
        ang = np.array([0.7, m, -0.4])
        r = Rotation.from_euler(seq, ang)
        with pytest.warns(GimbalLockWarning, match="third angle is set to 0"):
            got = r.as_euler(seq)
        assert got[2] == 0.0
        d = (Rotation.from_euler(seq, got).inv() * r).magnitude()
        assert d <= 1e-7 + 1e-15, d


def test_from_euler_one_and_two_axes():
    r = Rotation.from_euler("z", [0.1, 0.2, 0.3])
    assert r.shape == (3,)
    np.testing.assert_allclose(r.as_rotvec()[:, 2], [0.1, 0.2, 0.3], atol=1e-16)
    r2 = Rotation.from_euler("xy", [0.3, 0.2])
    np.testing.assert_allclose(
        r2.as_matrix(), SciPyRotation.from_euler("xy", [0.3, 0.2]).as_matrix(), atol=1e-16
    )


def test_operations_against_scipy():
    rng = np.random.default_rng(9)
    a = Rotation.from_quat(Q)
    b = Rotation.random(len(Q), rng=rng)
    sb = SciPyRotation.from_quat(b.as_quat(), scalar_first=True)
    np.testing.assert_allclose((a * b).as_matrix(), (SCIPY * sb).as_matrix(), atol=2e-15)
    np.testing.assert_allclose(a.inv().as_matrix(), SCIPY.inv().as_matrix(), atol=2e-14)
    v = rng.standard_normal((len(Q), 3))
    np.testing.assert_allclose(a.apply(v), SCIPY.apply(v), atol=1e-14)
    np.testing.assert_allclose(a.apply(v, inverse=True), SCIPY.apply(v, inverse=True), atol=1e-14)
    assert_same_rotation(a.mean().as_quat(), SCIPY.mean().as_quat(scalar_first=True), 1e-12)
    w = rng.uniform(0.1, 2, len(Q))
    assert_same_rotation(a.mean(w).as_quat(), SCIPY.mean(w).as_quat(scalar_first=True), 1e-12)
    # fractional powers of a rotation by exactly pi depend on the arbitrary axis sign
    ok = a.magnitude() < np.pi - 1e-6
    # (an older SciPy's r ** -1.3 is off by ~1e-7: not an oracle for that power)
    for p in (0.5, 2, -1.3, 3) if SCIPY_POWER else (0.5, 2, 3):
        np.testing.assert_allclose(
            (a[ok] ** p).as_matrix(), (SCIPY[ok] ** p).as_matrix(), atol=5e-14
        )
    np.testing.assert_allclose(
        a.as_quat(canonical=True), SCIPY.as_quat(canonical=True, scalar_first=True), atol=0
    )
    np.testing.assert_allclose(a.as_quat(scalar_first=False), np.roll(Q, -1, axis=1), atol=0)


def test_align_vectors_against_scipy():
    rng = np.random.default_rng(4)
    true = Rotation.random(rng=rng)
    b = rng.standard_normal((10, 3))
    a = true.apply(b) + 1e-3 * rng.standard_normal((10, 3))
    w = rng.uniform(0.5, 2.0, 10)
    r, rssd = Rotation.align_vectors(a, b, weights=w)
    sr, srssd = SciPyRotation.align_vectors(a, b, weights=w)
    np.testing.assert_allclose(r.as_matrix(), sr.as_matrix(), atol=1e-12)
    np.testing.assert_allclose(rssd, srssd, rtol=5e-8)  # 3e-10 apart (two SVD routes)
    exact, zero = Rotation.align_vectors(true.apply(b), b)
    assert zero < 1e-13 and exact.approx_equal(true, atol=1e-13)


def test_slerp_against_scipy():
    r = Rotation.random(2, rng=3)
    t = np.linspace(0, 1, 11)
    from poinsot import slerp

    got = slerp(r[0], r[1], t)
    ref = Slerp([0, 1], SciPyRotation.from_quat(r.as_quat(), scalar_first=True))(t)
    np.testing.assert_allclose(got.as_matrix(), ref.as_matrix(), atol=1e-14)


def test_from_basis_theorem_1():
    """SPEC S2 Theorem 1 against the matrix route, including degenerate cases."""
    r = Rotation.from_quat(Q)
    m = r.as_matrix()
    got = Rotation.from_basis(m[..., 0], m[..., 1], m[..., 2])
    assert_same_rotation(got.as_quat(), Q, 2e-14)
    ident = Rotation.from_basis([1, 0, 0], [0, 1, 0], [0, 0, 1])
    np.testing.assert_array_equal(ident.as_quat(), [1, 0, 0, 0])


def test_near_orthogonal_matrix_is_projected():
    rng = np.random.default_rng(2)
    r = Rotation.random(20, rng=rng)
    m = r.as_matrix()
    noisy = m + 1e-8 * rng.standard_normal(m.shape)
    got = Rotation.from_matrix(noisy)
    assert np.all(got.approx_equal(r, atol=5e-8))
    # the projection is the nearest rotation (SVD polar factor)
    u, _, vt = np.linalg.svd(noisy)
    np.testing.assert_allclose(got.as_matrix(), u @ vt, atol=1e-14)


def test_shapes_and_container_protocol():
    for shape in [(), (1,), (5, 3)]:
        q = random_quaternions(int(np.prod(shape)), seed=1).reshape(*shape, 4)
        r = Rotation.from_quat(q)
        assert r.shape == shape
        assert r.as_matrix().shape == (*shape, 3, 3)
        assert r.as_euler("ZYX").shape == (*shape, 3)
        assert r.as_rotvec().shape == (*shape, 3)
        assert r.magnitude().shape == shape
        assert (r * r.inv()).shape == shape
        assert r.apply(np.ones(3)).shape == (*shape, 3)
    r = Rotation.random((5, 3), rng=0)
    assert len(r) == 5 and r[1].shape == (3,) and r[1, 2].shape == () and r[..., 0].shape == (5,)
    assert len(list(r)) == 5
    np.testing.assert_array_equal(r[2, 1].as_quat(), r.as_quat()[2, 1])
    with pytest.raises(InvalidTypeError, match="single rotation has no len"):
        len(Rotation.identity())
    import pickle

    assert pickle.loads(pickle.dumps(r)).approx_equal(r).all()
    with pytest.raises(ValueError, match="read-only"):
        r._q[0, 0, 0] = 2.0
    assert Rotation.identity((2, 2)).shape == (2, 2)


def test_random_is_uniform():
    """Uniform on SO(3): E[cos f] over the Haar measure is -1/3 ... (trace mean = 0)."""
    r = Rotation.random(200_000, rng=0)
    tr = np.trace(r.as_matrix(), axis1=1, axis2=2)
    assert abs(tr.mean()) < 0.02  # Haar: E[tr A] = 0, std of the mean ~ 0.0022 (0.0019 seen)
    # angle density (1 - cos f)/pi on [0, pi]: E[f] = pi/2 + 2/pi
    assert abs(r.magnitude().mean() - (np.pi / 2 + 2 / np.pi)) < 0.01


def test_edge_set_is_complete():
    assert len(edge_quaternions()) >= 80 + 28 + 12


def test_rotvec_to_quat_against_high_precision():
    """cos(f/2), e sin(f/2) against 40-digit mpmath over (0, pi] and at the edges."""
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 40
    rng = np.random.default_rng(1)
    angles = [*rng.uniform(0, np.pi, 300), 1e-300, 1e-12, 1e-8, 1e-4, np.pi - 1e-8, np.pi, 4.0, 7.5]
    worst = 0.0
    for f in angles:
        e = rng.standard_normal(3)
        v = f * e / np.linalg.norm(e)
        q = Rotation.from_rotvec(v).as_quat()
        big_f = mp.sqrt(sum(mp.mpf(x) ** 2 for x in v))
        ref = [mp.cos(big_f / 2)] + [mp.sin(big_f / 2) / big_f * mp.mpf(x) for x in v]
        worst = max(worst, max(abs(float(q[i] - ref[i])) for i in range(4)))
    assert worst <= 4e-15, worst  # 3.0e-16 observed against 40-digit mpmath
