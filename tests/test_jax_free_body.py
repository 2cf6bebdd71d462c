"""poinsot.jax (issue 25): the exact free body and the kinematic rates on JAX.

Values equal the numba path (FreeRigidBody, poinsot.kinematics) to 1e-13 on the
parity cases (major, minor, separatrix, symmetric, spherical, rest, axis spins);
derivatives (forward and reverse mode) equal central differences to 1e-7 (relative
to the largest entry), including 1e-3 from the separatrix on both sides; vmap equals
the batch call; the constants are a pytree. The gradient compiles are slow (tens of
seconds each): one per test.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="JAX is not installed (pip install poinsot[jax])")
jnp = pytest.importorskip("jax.numpy")
pj = pytest.importorskip("poinsot.jax")

from poinsot.dynamics import FreeRigidBody  # noqa: E402
from poinsot.errors import InvalidInputError  # noqa: E402

_S3 = np.sqrt(1.0 / 3.0)  # omega0 = (1, 0.5, w3) with J = (1, 2, 3): separatrix at w3 = 1/sqrt(3)
# the same with J = (1.1, 2, 3), off the edge A + B = C (differences step both ways):
# I3 (I3 - I2) w3^2 = I1 (I2 - I1) w1^2, w3 = sqrt(0.33)
_S3G = np.sqrt(0.33)
CASES = [
    ([1.0, 2.0, 3.0], [0.3, 0.2, 0.9]),  # major
    ([1.0, 2.0, 3.0], [0.1, 1.0, 0.1]),  # major, near the middle axis
    ([3.0, 1.0, 2.0], [0.9, 0.3, -0.2]),  # axes in another order
    ([1.0, 2.0, 3.0], [1.0, 0.5, 0.3]),  # minor
    ([1.0, 2.0, 3.0], [1.0, 0.5, _S3 * (1 + 1e-9)]),  # near the separatrix, both sides
    ([1.0, 2.0, 3.0], [1.0, 0.5, _S3 * (1 - 1e-9)]),
    ([1.0, 2.0, 3.0], [2.0, 0.0, np.sqrt(2.0 / 3.0)]),  # on the separatrix (D = 0 exactly)
    ([2.0, 2.0, 1.0], [1.0, 0.0, 2.0]),  # symmetric
    ([1.0, 1.0, 1.0], [1.0, 2.0, 3.0]),  # spherical
    ([1.0, 2.0, 3.0], [0.0, 0.0, 0.0]),  # rest
    ([1.0, 2.0, 3.0], [0.0, 1.0, 0.0]),  # about the middle axis
    ([1.0, 2.0, 3.0], [0.0, 0.0, 1.0]),  # about the major axis
    ([1.0, 2.0, 3.0], [1e3, 0.0, 0.0]),  # about the minor axis, fast
]
T = np.linspace(-30.0, 30.0, 61)


def _reference(j, w, t):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # near-separatrix warnings
        return FreeRigidBody(j, omega0=w).omega(t)


def test_exact_free_body_equals_the_numba_path():
    j = np.array([c[0] for c in CASES])
    w = np.array([c[1] for c in CASES])
    # One body and two times per call: the shapes of poinsot.jax's doctests, so that the
    # suite compiles the constants and the evaluation once (the JAX compilation cache
    # shared by the workers, conftest.py), not again for a batch of 13 bodies and 61
    # times (112 s of XLA compiling). Every regime's path runs in the one program either
    # way: a batch only broadcasts the same selects.
    got = np.stack(
        [
            np.concatenate(
                [np.asarray(pj.free_body_omega_exact(jnp.asarray(jk), jnp.asarray(wk),
                                                     jnp.asarray(T[i : i + 2])))
                 for i in range(0, T.size - 1, 2)]
                + [np.asarray(pj.free_body_omega_exact(jnp.asarray(jk), jnp.asarray(wk),
                                                       jnp.asarray(T[-2:])))[1:]]
            )
            for jk, wk in zip(j, w, strict=True)
        ]
    )  # fmt: skip
    want = _reference(j, w, T)
    assert got.shape == want.shape == (len(CASES), T.size, 3)
    scale = np.maximum(np.abs(want).max(axis=(1, 2), keepdims=True), 1e-300)
    err = np.abs(got - want) / scale
    assert err.max() <= 1e-13, err.max(axis=(1, 2))
    codes = np.asarray(pj.free_body_exact(j, w).regime)
    names = np.array(
        ["rest", "spherical", "separatrix", "symmetric", "major", "minor", "separatrix"]
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert names[codes].tolist() == FreeRigidBody(j, omega0=w).regime.tolist()


def _fd(f, x, h):
    """Central differences of 4th order (truncation ~h^4 f^(5) / 30): near the separatrix
    the derivatives change on the scale of the distance to it (1e-3 here), where the
    2nd-order ones' error (~h^2 f^(3) / 6) came within 10x of the tests' tolerance."""
    cols = []
    for i in range(x.size):
        e = np.zeros_like(x)
        e.flat[i] = h

        def d(k, e=e):
            return np.asarray(f(x + k * e)) - np.asarray(f(x - k * e))

        cols.append((8.0 * d(1) - d(2)) / (12.0 * h))
    return np.stack(cols, axis=-1)


def _gradient_points(rng):
    """(moments, omega0) rows of three bodies: random, and 1e-3 (relative in omega_3)
    on each side of the separatrix."""
    return np.array(
        [
            np.concatenate([rng.uniform(1.0, 2.0, 3), rng.normal(size=3)]),
            [1.1, 2.0, 3.0, 1.0, 0.5, _S3G * (1 + 1e-3)],
            [1.1, 2.0, 3.0, 1.0, 0.5, _S3G * (1 - 1e-3)],
        ]
    )


@pytest.mark.slow  # ~30 s of XLA compiling: `make test-slow`
def test_gradients_equal_central_differences():
    # one function of (moments, omega0) for three bodies: random, and 1e-3 (relative
    # in omega_3) on each side of the separatrix
    rng = np.random.default_rng(5)
    x = _gradient_points(rng)
    t = np.array([0.7, 4.0, 11.0])

    def f(xx):
        return pj.free_body_omega_exact(xx[..., :3], xx[..., 3:], t)

    fwd = np.asarray(jax.jacfwd(f)(jnp.asarray(x)))  # (3, 3, 3, 3, 6), bodies are lanes
    fwd = np.einsum("bpcbk->bpck", fwd)
    for b in range(3):
        want = _fd(lambda y, b=b: f(np.concatenate([x[:b], y[None], x[b + 1 :]]))[b], x[b], 1e-6)
        scale = np.abs(want).max()
        # central differences: O(h^2 f''') and eps/h, ~1e-9 relative here
        assert np.abs(fwd[b] - want).max() <= 1e-7 * scale, (b, np.abs(fwd[b] - want).max())


@pytest.mark.slow  # ~45 s of XLA compiling: `make test-slow`
def test_reverse_mode_equals_forward_mode():
    # the selects of every regime are in the graph: reverse mode sees no NaN from them
    t = np.array([0.5, 3.0])
    x0 = jnp.array([1.1, 2.0, 3.0])  # off the edge A + B = C (differences step both ways)
    w0 = jnp.array([0.4, -0.3, 0.8])

    def loss(j):
        return jnp.sum(pj.free_body_omega_exact(j, w0, t) ** 2)

    g = np.asarray(jax.grad(loss)(x0))
    want = _fd(lambda j: loss(j), np.asarray(x0), 1e-6)
    assert np.all(np.isfinite(g))
    np.testing.assert_allclose(g, want, rtol=1e-7, atol=1e-9)


@pytest.mark.slow  # ~15 s of XLA compiling (four programs): `make test-slow`
def test_vmap_and_pytree():
    j = np.array([c[0] for c in CASES[:4]])
    w = np.array([c[1] for c in CASES[:4]])
    t = np.linspace(0.0, 5.0, 4)
    batch = np.asarray(pj.free_body_omega_exact(j, w, t))
    mapped = np.asarray(jax.vmap(pj.free_body_omega_exact, (0, 0, None))(j, w, t))
    np.testing.assert_allclose(mapped, batch, rtol=1e-15, atol=1e-15)
    loop = np.stack([np.asarray(pj.free_body_omega_exact(j[k], w[k], t)) for k in range(4)])
    np.testing.assert_allclose(loop, batch, rtol=1e-15, atol=1e-15)
    # the constants pass through jit and vmap as a pytree
    motion = pj.free_body_exact(j, w)
    leaves, tree = jax.tree_util.tree_flatten(motion)
    again = jax.tree_util.tree_unflatten(tree, leaves)
    assert isinstance(again, pj.FreeBodyMotion) and again.shape == (4,)
    ev = jax.jit(lambda m, tt: m.omega(tt))(motion, t)
    np.testing.assert_allclose(np.asarray(ev), batch, rtol=1e-15, atol=1e-15)


def test_bad_shapes_name_the_argument():
    with pytest.raises(InvalidInputError, match="`moments`"):
        pj.free_body_exact(np.ones(2), np.ones(3))
    with pytest.raises(InvalidInputError, match="`omega0`"):
        pj.free_body_exact(np.ones(3), np.ones(4))
    with pytest.raises(InvalidInputError, match="`q0`"):
        pj.free_body_exact(np.ones(3), np.ones(3), np.ones(3))
    with pytest.raises(InvalidInputError, match="`C`"):
        pj.dcm_rate(np.eye(2), np.ones(3))
    with pytest.raises(InvalidInputError, match="`omega`"):
        pj.euler_rhs(np.ones(3), np.ones(2))


# --------------------------------------------------------------- kinematic rates
def _check_grad(f, x):
    got = np.asarray(jax.jacfwd(f)(jnp.asarray(x)))
    want = _fd(f, np.asarray(x, dtype=float), 1e-6)
    np.testing.assert_allclose(got.reshape(want.shape), want, rtol=1e-7, atol=1e-7)


@pytest.mark.parametrize("frame", ["body", "space"])
def test_dcm_rates_equal_the_numpy_path(frame):
    from poinsot import Rotation
    from poinsot.kinematics import dcm_rate, omega_from_dcm_rate

    rng = np.random.default_rng(6)
    C = Rotation.from_quat(rng.normal(size=(8, 4))).as_matrix()
    w = rng.normal(size=(8, 3))
    cd = dcm_rate(C, w, frame=frame)
    np.testing.assert_allclose(pj.dcm_rate(C, w, frame=frame), cd, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(
        pj.omega_from_dcm_rate(C, cd, frame=frame),
        omega_from_dcm_rate(C, cd, frame=frame),
        rtol=1e-13,
        atol=1e-13,
    )
    _check_grad(lambda x: pj.dcm_rate(C[0], x, frame=frame), w[0])


@pytest.mark.parametrize("seq", ["ZXZ", "ZYX", "xyz"])
@pytest.mark.parametrize("frame", ["body", "space"])
def test_euler_rates_equal_the_numpy_path(seq, frame):
    from poinsot.kinematics import euler_rates, omega_from_euler_rates

    rng = np.random.default_rng(7)
    a = rng.uniform(0.3, 1.2, size=(6, 3))  # away from gimbal lock
    d = rng.normal(size=(6, 3))
    w = omega_from_euler_rates(seq, a, d, frame=frame)
    np.testing.assert_allclose(
        pj.omega_from_euler_rates(seq, a, d, frame=frame), w, rtol=1e-13, atol=1e-13
    )
    np.testing.assert_allclose(
        pj.euler_rates(seq, a, w, frame=frame),
        euler_rates(seq, a, w, frame=frame),
        rtol=1e-13,
        atol=1e-13,
    )
    _check_grad(lambda x: pj.euler_rates(seq, x, w[0], frame=frame), a[0])
    _check_grad(lambda x: pj.omega_from_euler_rates(seq, a[0], x, frame=frame), d[0])


def test_euler_rhs_with_a_tensor_equals_the_numpy_path():
    from poinsot import Rotation
    from poinsot.dynamics import euler_rhs

    rng = np.random.default_rng(9)
    R = Rotation.from_quat(rng.normal(size=(5, 4))).as_matrix()
    mom = rng.uniform(1.0, 1.9, size=(5, 3))
    J = np.einsum("nik,nk,njk->nij", R, mom, R)
    w, m = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    np.testing.assert_allclose(pj.euler_rhs(J, w, m), euler_rhs(J, w, m), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(pj.euler_rhs(J, w), euler_rhs(J, w), rtol=1e-13, atol=1e-13)
    _check_grad(lambda x: pj.euler_rhs(J[0], x), w[0])


# ------------------------------------------------------------- the attitude
def _unit_quats(n, seed):
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


@pytest.mark.slow  # ~10 s of XLA compiling (every regime's attitude): `make test-slow`;
# `make test` keeps the attitude's doctests (FreeBodyMotion.attitude, free_body_state_exact)
def test_attitude_equals_the_numba_path():
    # every regime, a random initial attitude; the same formulas, so the same sign
    j = np.array([c[0] for c in CASES])
    w = np.array([c[1] for c in CASES])
    q0 = _unit_quats(len(CASES), 11)
    got_w, got_q = (np.asarray(a) for a in pj.free_body_state_exact(j, w, q0, T))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        want_w, rot = FreeRigidBody(j, omega0=w, rotation0=q0).state(T)
    want_q = rot.as_quat()
    assert got_q.shape == want_q.shape == (len(CASES), T.size, 4)
    err = np.abs(got_q - want_q).max(axis=(1, 2))
    assert err.max() <= 1e-13, err
    scale = np.maximum(np.abs(want_w).max(axis=(1, 2), keepdims=True), 1e-300)
    assert (np.abs(got_w - want_w) / scale).max() <= 1e-13
    np.testing.assert_allclose(got_q[:, T.size // 2], q0, rtol=0, atol=1e-14)  # t = 0


@pytest.mark.slow  # ~30 s of XLA compiling on the shared 2-core machine: `make test-slow`
def test_attitude_vmap_and_defaults():
    j = np.array([c[0] for c in CASES[:4]] + [CASES[7][0], CASES[8][0]])
    w = np.array([c[1] for c in CASES[:4]] + [CASES[7][1], CASES[8][1]])
    q0 = _unit_quats(len(j), 12)
    t = np.linspace(-3.0, 5.0, 4)
    _, batch = pj.free_body_state_exact(j, w, q0, t)
    mapped = jax.vmap(pj.free_body_state_exact, (0, 0, 0, None))(j, w, q0, t)[1]
    np.testing.assert_allclose(np.asarray(mapped), np.asarray(batch), rtol=0, atol=1e-15)
    motion = pj.free_body_exact(j, w, 3.0 * q0)  # normalised
    np.testing.assert_allclose(np.asarray(motion.attitude(t)), batch, rtol=0, atol=1e-15)
    # q0 = None: the identity, broadcast over the batch
    ident = np.asarray(pj.free_body_exact(j, w).attitude(0.0))
    np.testing.assert_allclose(ident, np.broadcast_to([1.0, 0, 0, 0], ident.shape), atol=1e-15)


@pytest.mark.slow  # ~45 s of tracing and XLA compiling, 1.3 GB (>18 GB before issue 40)
def test_attitude_gradients_equal_central_differences():
    # d/d(moments, omega0) of a scalar of the attitude (forward and reverse mode), three bodies:
    # random, and 1e-3 (relative in omega_3) on each side of the separatrix
    rng = np.random.default_rng(5)
    x = _gradient_points(rng)
    q0 = _unit_quats(3, 13)
    t = np.array([0.7, 4.0, 11.0])
    weights = rng.normal(size=(t.size, 4))

    @jax.jit
    def f(xx):  # per body: the bodies are independent lanes
        q = pj.free_body_exact(xx[:, :3], xx[:, 3:], q0).attitude(t)
        return jnp.sum(q * weights, axis=(1, 2))

    d = _fd(f, x, 1e-5)  # (3 bodies, 3 x 6 entries of x)
    want = np.stack([d[b, 6 * b : 6 * b + 6].reshape(6) for b in range(3)])
    # forward mode, and reverse mode (which compiled for 287 s in 12.6 GB before each
    # selects rule saved one array of derivatives per result: now ~20 s)
    for mode in (jax.jacfwd, jax.jacrev):
        g = np.asarray(mode(f)(jnp.asarray(x)))  # (3, 3, 6): the bodies are lanes
        g = np.stack([g[b, b] for b in range(3)])
        assert np.all(np.isfinite(g))
        for b in range(3):
            err = np.abs(g[b] - want[b]).max()
            assert err <= 1e-7 * np.abs(want[b]).max(), (mode.__name__, b, err)


def test_unphysical_moments_name_the_argument():
    # concrete inputs are checked like FreeRigidBody's; A + B < C is no rigid body
    for bad in ([1.0, 1.0, 3.0], [-1.0, 2.0, 2.0], [np.nan, 1.0, 1.0]):
        with pytest.raises(InvalidInputError, match="`moments`"):
            pj.free_body_exact(np.array(bad), np.ones(3))
    with pytest.raises(InvalidInputError, match="triangle inequality"):  # the same rule
        FreeRigidBody([1.0, 1.0, 3.0], omega0=np.ones(3))


def test_rotation0_is_q0_under_the_name_of_free_rigid_body():
    # API.md: exact solutions take the initial attitude as `rotation0`; here it is the
    # same as `q0` for a JAX array, a poinsot Rotation and a SciPy Rotation (whose
    # scalar-last quaternions must not be misread). The pytree's leaves are compared:
    # no attitude program is compiled.
    from scipy.spatial.transform import Rotation as SciPyRotation

    from poinsot import Rotation

    rng = np.random.default_rng(7)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    moments, omega = jnp.array([1.0, 2.0, 3.0]), jnp.array([0.3, 0.2, 0.9])
    want = jax.tree_util.tree_leaves(pj.free_body_exact(moments, omega, jnp.asarray(q)))
    for r0 in (
        jnp.asarray(q),
        Rotation.from_quat(q),
        SciPyRotation.from_quat(np.roll(q, -1)),  # SciPy: scalar last
    ):
        got = jax.tree_util.tree_leaves(pj.free_body_exact(moments, omega, rotation0=r0))
        for a, b in zip(got, want, strict=True):
            np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-15)
    with pytest.raises(InvalidInputError, match="not both"):
        pj.free_body_exact(moments, omega, jnp.asarray(q), rotation0=jnp.asarray(q))
    with pytest.raises(InvalidInputError, match="`rotation0`"):
        pj.free_body_exact(moments, omega, rotation0=np.zeros(4))
