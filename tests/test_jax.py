"""poinsot.jax (issue 25): the same formula source on JAX.

Values equal the numba path (poinsot's NumPy-facing functions) to 1e-13 on the
rotation parity cases (edge quaternions: angles 0, near and at pi, gimbal lock);
gradients equal central finite differences to 1e-7 on random inputs, including
rotations near angle pi; jit/vmap give the same values as the batched call.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotation_cases import all_quaternions

jax = pytest.importorskip("jax", reason="JAX is not installed (pip install poinsot[jax])")
jnp = pytest.importorskip("jax.numpy")
pj = pytest.importorskip("poinsot.jax")

from poinsot import Rotation  # noqa: E402
from poinsot._jit import upto  # noqa: E402
from poinsot.dynamics import euler_rhs  # noqa: E402

Q = all_quaternions()
R = Rotation.from_quat(Q)


def _close(got, want, rtol=1e-13):
    got, want = np.asarray(got), np.asarray(want)
    assert got.shape == want.shape
    np.testing.assert_allclose(got, want, rtol=rtol, atol=rtol)


def _same_rotation(p, q):
    p, q = np.asarray(p), np.asarray(q)
    d = np.minimum(np.abs(p - q).max(axis=-1), np.abs(p + q).max(axis=-1))
    assert d.max() <= 1e-13


def test_conversions_equal_the_numba_path():
    q = R.as_quat(canonical=False)
    _close(pj.matrix_from_quat(q), R.as_matrix())
    _close(pj.rotvec_from_quat(q), R.as_rotvec())
    _close(pj.mrp_from_quat(q), R.as_mrp())
    m = R.as_matrix()
    _same_rotation(pj.quat_from_matrix(m), Rotation.from_matrix(m).as_quat())
    v = R.as_rotvec()
    _close(pj.quat_from_rotvec(v), Rotation.from_rotvec(v).as_quat(canonical=False))
    p = R.as_mrp()
    _close(pj.quat_from_mrp(p), Rotation.from_mrp(p).as_quat(canonical=False))


@pytest.mark.parametrize("seq", ["ZYX", "xyz", "ZXZ", "zxz"])
def test_euler_equals_the_numba_path(seq):
    import warnings

    q = R.as_quat(canonical=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # gimbal lock is among the cases
        a = R.as_euler(seq)
    _close(pj.euler_from_quat(seq, q), a)
    _close(pj.quat_from_euler(seq, a), Rotation.from_euler(seq, a).as_quat(canonical=False))


def test_compose_apply_inverse_slerp_equal_the_numba_path():
    rng = np.random.default_rng(2)
    r2 = Rotation.from_quat(rng.normal(size=(len(Q), 4)))
    p, q = R.as_quat(canonical=False), r2.as_quat(canonical=False)
    _close(pj.quat_multiply(p, q), (R * r2).as_quat(canonical=False))
    v = rng.normal(size=(len(Q), 3))
    _close(pj.quat_rotate(p, v), R.apply(v))
    _close(pj.quat_inverse(p), R.inv().as_quat(canonical=False))
    from poinsot.rotations.rotation import slerp

    t = np.linspace(0.0, 1.0, 7)
    want = slerp(R[5], r2[5], t).as_quat()
    _same_rotation(pj.slerp(p[5], q[5], t), want)


def test_euler_rhs_equals_the_numba_path():
    rng = np.random.default_rng(3)
    j = rng.uniform(1.0, 1.9, size=(20, 3))  # physical: the triangle inequality holds
    w, m = rng.normal(size=(20, 3)), rng.normal(size=(20, 3))
    _close(pj.euler_rhs(j, w, m), euler_rhs(j, w, m))
    _close(pj.euler_rhs(j, w), euler_rhs(j, w))


def test_vmap_equals_the_batch_call():
    q = jnp.asarray(Q)
    _close(jax.vmap(pj.matrix_from_quat)(q), pj.matrix_from_quat(q), rtol=1e-15)
    _close(jax.vmap(pj.rotvec_from_quat)(q), pj.rotvec_from_quat(q), rtol=1e-15)


def _fd_jacobian(f, x, h=1e-6):
    x = np.asarray(x, dtype=float)
    cols = []
    for i in range(x.size):
        e = np.zeros_like(x)
        e.flat[i] = h
        cols.append((np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2 * h))
    return np.stack(cols, axis=-1)


def _check_grad(f, x):
    got = np.asarray(jax.jacfwd(f)(jnp.asarray(x)))
    want = _fd_jacobian(f, x)
    got = got.reshape(want.shape)
    # central differences: O(h^2) truncation and eps/h rounding, ~1e-9 here
    np.testing.assert_allclose(got, want, atol=1e-7, rtol=1e-7)


@pytest.mark.parametrize("seed", range(3))
def test_gradients_equal_central_differences(seed):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=3)
    _check_grad(pj.quat_from_rotvec, v)
    q = pj.quat_from_rotvec(v)
    _check_grad(pj.rotvec_from_quat, np.asarray(q))
    _check_grad(pj.matrix_from_quat, np.asarray(q))
    _check_grad(pj.quat_from_matrix, np.asarray(pj.matrix_from_quat(q)))
    _check_grad(lambda a: pj.quat_from_euler("ZYX", a), rng.uniform(-1, 1, 3))
    _check_grad(lambda a: pj.euler_from_quat("ZYX", a), np.asarray(q))
    j = rng.uniform(1.0, 3.0, 3)
    _check_grad(lambda w: pj.euler_rhs(j, w), rng.normal(size=3))
    _check_grad(lambda jj: pj.euler_rhs(jj, np.array([0.3, -0.2, 0.5])), j)


@pytest.mark.parametrize("gap", [1e-3, 1e-5])
def test_gradients_near_angle_pi(gap):
    rng = np.random.default_rng(11)
    e = rng.normal(size=3)
    e /= np.linalg.norm(e)
    v = (np.pi - gap) * e
    _check_grad(pj.quat_from_rotvec, v)
    q = np.asarray(pj.quat_from_rotvec(v))
    _check_grad(pj.rotvec_from_quat, q)
    _check_grad(pj.quat_from_matrix, np.asarray(pj.matrix_from_quat(q)))


def test_grad_of_a_scalar_loss_through_a_rotation_chain():
    # d/dphi |R(phi) a - b|^2 against central differences, with jit around it
    a, b = jnp.array([1.0, 0.0, 0.0]), jnp.array([0.0, 0.6, 0.8])

    def loss(phi):
        return jnp.sum((pj.quat_rotate(pj.quat_from_rotvec(phi), a) - b) ** 2)

    phi = np.array([0.2, -0.4, 2.9])
    g = np.asarray(jax.jit(jax.grad(loss))(jnp.asarray(phi)))
    np.testing.assert_allclose(g, _fd_jacobian(loss, phi), atol=1e-7)


def test_euler_poisson_equals_the_heavy_top():
    from poinsot.dynamics import HeavyRigidBody

    rng = np.random.default_rng(4)
    top = HeavyRigidBody([2.0, 2.5, 1.5], 1.3, [0.1, -0.2, 0.5], g=9.81)
    w, gam = rng.normal(size=(10, 3)), rng.normal(size=(10, 3))
    want_w, want_g = top.euler_poisson(w, gam)
    mgc = 1.3 * 9.81 * np.array([0.1, -0.2, 0.5])
    got_w, got_g = pj.euler_poisson(np.array([2.0, 2.5, 1.5]), mgc, w, gam)
    _close(got_w, want_w)
    _close(got_g, want_g)


def test_integrated_free_body_follows_the_exact_solution():
    from poinsot.dynamics import FreeRigidBody

    j, w0 = np.array([1.0, 2.0, 3.0]), np.array([0.3, 0.2, 0.9])
    t = np.linspace(0.0, 10.0, 21)
    want, _ = FreeRigidBody(j, omega0=w0).state(t)
    got = pj.free_body_omega(j, w0, t)
    # Dopri8 at rtol 1e-10, atol 1e-12 over ~3 periods: observed ~1e-11
    np.testing.assert_allclose(got, want, atol=1e-9)


def test_gradient_through_the_integrator_equals_central_differences():
    w0, t = np.array([0.3, 0.2, 0.9]), np.linspace(0.0, 3.0, 7)

    def loss(j):
        return jnp.sum(pj.free_body_omega(j, w0, t)[-1] ** 2)

    j = np.array([1.0, 2.0, 2.5])
    g = np.asarray(jax.grad(loss)(jnp.asarray(j)))
    # the adaptive step sequence changes with j, so the finite difference sees the
    # integrator's error (rtol 1e-10) over 2h: h = 1e-4 keeps it below 1e-6
    np.testing.assert_allclose(g, _fd_jacobian(loss, j, h=1e-4), rtol=1e-6, atol=1e-7)


def test_a_users_traced_branch_still_raises_jaxs_error():
    # the select executor lends tracers a truth value only while it traces a formula
    pj.quat_from_matrix(np.eye(3))

    @jax.jit
    def f(x):
        return x if x > 0 else -x

    with pytest.raises(jax.errors.TracerBoolConversionError):
        f(1.0)


@pytest.mark.parametrize("frame", ["body", "space"])
def test_quaternion_rates_equal_the_numpy_path_and_have_true_gradients(frame):
    from poinsot.kinematics import omega_from_quat_rate, quat_rate

    rng = np.random.default_rng(8)
    q = R.as_quat(canonical=False)
    w = rng.normal(size=(len(q), 3))
    qd = quat_rate(q, w, frame=frame)
    _close(pj.quat_rate(q, w, frame=frame), qd)
    _close(pj.omega_from_quat_rate(q, qd, frame=frame), omega_from_quat_rate(q, qd, frame=frame))
    _check_grad(lambda x: pj.quat_rate(x, w[0], frame=frame), q[0])
    _check_grad(lambda x: pj.omega_from_quat_rate(q[0], x, frame=frame), qd[0])


# ------------------------------------------------- table loops as one loop (issue 40)
def _eqns(jaxpr, names=None):
    """The number of equations of ``jaxpr`` with its inner ones (``names`` collects
    the primitives' names)."""
    n = 0
    for e in jaxpr.eqns:
        n += 1
        if names is not None:
            names.add(e.primitive.name)
        for p in e.params.values():
            inner = getattr(p, "jaxpr", p)
            if hasattr(inner, "eqns"):
                n += _eqns(inner, names)
    return n


def test_carlson_loops_are_one_loop_and_equal_the_numba_path():
    # Carlson's duplication (24 steps on JAX) is one lax loop, not 24 traced copies:
    # R_J's program was 5,759 equations unrolled
    from poinsot.dynamics import _elliptic as E

    rng = np.random.default_rng(40)
    x, y, z = rng.uniform(0.0, 2.0, (3, 50))
    p = rng.uniform(0.1, 3.0, 50)
    x[:5] = 0.0  # an argument at zero (the complete integrals' form)
    rj = pj.selects(E.carlson_rj)
    jaxpr = jax.make_jaxpr(lambda *a: rj(*a))(x, y, z, p).jaxpr
    names = set()
    assert _eqns(jaxpr, names) < 1500
    assert names & {"while", "scan"}
    want = np.array([E.carlson_rj(*a) for a in zip(x, y, z, p, strict=True)])
    _close(jax.jit(rj)(x, y, z, p), want, rtol=1e-14)


def test_a_constant_zero_in_a_rolled_loop_keeps_derivatives_finite():
    # R_J(0, y, z, p): sqrt(x) at x = 0 has an infinite derivative; the constant 0 has
    # none. The loop's first step is traced apart, so 0 * inf never forms (NaN before)
    from poinsot.dynamics import _elliptic as E

    rj = pj.selects(E.carlson_rj)
    a = np.array([0.6, 1.0, 1.3])

    def f(v):
        return rj(0.0, v[0], v[1], v[2])

    got = np.asarray(jax.jacfwd(f)(jnp.asarray(a)))
    back = np.asarray(jax.grad(f)(jnp.asarray(a)))
    h = 1e-6
    want = np.array(
        [(E.carlson_rj(0.0, *(a + h * e)) - E.carlson_rj(0.0, *(a - h * e))) / (2 * h)
         for e in np.eye(3)]
    )  # fmt: skip
    np.testing.assert_allclose(got, want, rtol=1e-7)
    np.testing.assert_allclose(back, want, rtol=1e-7)


def _rollable(x):
    s = 0.0
    for k in range(upto(8, 8)):
        t = x * k
        s = s + t
    return s


def _temporary_read_after(x):
    s = 0.0
    for k in range(upto(8, 8)):
        t = x * k
        s = s + t
    return s + t


def _early_return(x):
    s = 0.0
    for k in range(upto(8, 8)):
        s = s + x
        if k == 3:
            return s
    return s


def _plain_range(x):
    s = 0.0
    for k in range(8):
        s = s + x * k
    return s


def test_only_loops_that_can_be_one_call_are_rewritten():
    from poinsot._rolled import rolled_code

    code = rolled_code(_rollable)
    assert code is not None and "_poinsot_loop_" in code.co_names
    for fn in (_temporary_read_after, _early_return, _plain_range):
        assert rolled_code(fn) is None, fn.__name__
    # the rewritten function computes what the loop did (the JAX executor's loop)
    g = pj.rebind(_rollable, "jax")
    assert float(g(jnp.asarray(1.5))) == 1.5 * sum(range(8))
