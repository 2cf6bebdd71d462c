"""One rotation, a small batch and a threaded large batch give the same numbers.

A single rotation takes a short path (plain Python or a one-rotation numba call on
the scalar formulas of ``rotations._scalar``); small batches the broadcasting
gufuncs; batches of at least ``PARALLEL_MIN_SIZE`` the threaded flat loops. All
three run the same formula, so they must agree bit for bit (where the same
operations run) and the threaded result must not depend on the thread count.
Also the input defects of issue 8 section 4 / issue 9 (bools, unit quaternions
with ``normalize=False``, ``Rotation * 3``, empty sets).
"""

from __future__ import annotations

import warnings

import numba
import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import GimbalLockWarning, InvalidInputError, InvalidTypeError, Rotation, slerp
from poinsot.rotations import PARALLEL_MIN_SIZE, get_num_threads, set_num_threads
from rotation_cases import SCIPY_EMPTY, all_quaternions, on_one_and_every_thread

Q = all_quaternions()
SEQS = ["ZXZ", "zxz", "XYZ", "xyz", "ZYX", "yzy", "XZY", "euler", "krylov"]


def _singles(method, *args, **kw):
    return np.array([getattr(Rotation.from_quat(q), method)(*args, **kw) for q in Q])


@pytest.mark.parametrize(
    "method, args",
    [("as_matrix", ()), ("as_rotvec", ()), ("as_mrp", ()), ("magnitude", ()), ("as_quat", ())]
    + [("as_euler", (s,)) for s in SEQS],
)
def test_one_rotation_equals_its_row_in_a_batch(method, args):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GimbalLockWarning)
        batch = getattr(Rotation.from_quat(Q), method)(*args)
        one = _singles(method, *args)
    # the same scalar formula: equal to the last bit except magnitude (NumPy's norm
    # there sums in another order), within 2 ulp of pi
    atol = 2e-14 if method == "magnitude" else 0.0
    np.testing.assert_allclose(one, batch, rtol=0, atol=atol)


def test_single_constructors_equal_batch_constructors():
    rng = np.random.default_rng(3)
    angles = rng.uniform(-4, 4, (50, 3))
    for seq in SEQS:
        batch = Rotation.from_euler(seq, angles).as_quat()
        one = np.array([Rotation.from_euler(seq, a).as_quat() for a in angles])
        one_list = np.array([Rotation.from_euler(seq, a.tolist()).as_quat() for a in angles])
        np.testing.assert_array_equal(one, batch)
        np.testing.assert_array_equal(one_list, batch)
    for deg in (False, True):
        batch = Rotation.from_rotvec(angles, degrees=deg).as_quat()
        one = np.array([Rotation.from_rotvec(a, degrees=deg).as_quat() for a in angles])
        np.testing.assert_array_equal(one, batch)
    m = Rotation.from_quat(Q).as_matrix()
    np.testing.assert_array_equal(
        np.array([Rotation.from_matrix(a).as_quat() for a in m]), Rotation.from_matrix(m).as_quat()
    )
    # one-axis sequences with a scalar angle (single rotation)
    for seq in "xyzXYZ":
        np.testing.assert_array_equal(
            Rotation.from_euler(seq, 0.7).as_quat(), Rotation.from_euler(seq, [0.7]).as_quat()[0]
        )
    # non-unit quaternions, lists and scalar-last order
    raw = rng.standard_normal((40, 4)) * 3.0
    np.testing.assert_allclose(
        np.array([Rotation.from_quat(list(q)).as_quat() for q in raw]),
        Rotation.from_quat(raw).as_quat(),
        rtol=0,
        atol=1e-14,
    )
    np.testing.assert_array_equal(
        Rotation.from_quat(Q[5], scalar_first=False).as_quat(),
        Rotation.from_quat(Q[5:6], scalar_first=False).as_quat()[0],
    )


def test_single_operations_match_scipy():
    rng = np.random.default_rng(4)
    v = rng.standard_normal(3)
    for q, p in zip(Q[::7], Q[3::7], strict=False):
        r, s = Rotation.from_quat(q), Rotation.from_quat(p)
        sr, ss = (
            SciPyRotation.from_quat(q, scalar_first=True),
            SciPyRotation.from_quat(p, scalar_first=True),
        )
        np.testing.assert_allclose(r.apply(v), sr.apply(v), rtol=0, atol=1e-14)
        np.testing.assert_allclose(r.apply(v, inverse=True), sr.apply(v, inverse=True), atol=1e-14)
        d = (r * s).as_quat() - (sr * ss).as_quat(scalar_first=True)
        e = (r * s).as_quat() + (sr * ss).as_quat(scalar_first=True)
        assert min(np.abs(d).max(), np.abs(e).max()) < 1e-14
        assert (r.inv() * r).magnitude() < 1e-15
        np.testing.assert_allclose(r.magnitude(), sr.magnitude(), rtol=0, atol=2e-14)
        # slerp of singles against the batch formula and its end points
        for t in (0.0, 0.3, 1.0):
            one = slerp(r, s, t)
            many = slerp(r, s, [t])[0]
            np.testing.assert_array_equal(one.as_quat(), many.as_quat())
        assert slerp(r, s, 1.0).approx_equal(s, atol=1e-14)


def test_single_gimbal_lock_warns_like_batch():
    r = Rotation.from_euler("ZXZ", [0.3, 0.0, 0.2])
    with pytest.warns(GimbalLockWarning, match="Gimbal lock"):
        a = r.as_euler("ZXZ")
    np.testing.assert_allclose(a, [0.5, 0.0, 0.0], atol=1e-15)


@pytest.fixture(scope="module")
def big():
    rng = np.random.default_rng(11)
    n = PARALLEL_MIN_SIZE + 1001
    q = rng.standard_normal((n, 4))
    q[::97] = Q[: len(q[::97])] if len(Q) >= len(q[::97]) else q[::97]
    return Rotation.from_quat(q), rng.standard_normal((n, 3)), rng.uniform(-4, 4, (n, 3))


#: operations whose large batches call NumPy's atan2 / tan between compiled halves
_NUMPY_TRIG = ("from_rotvec", "euler", "euler_tb")


def _all_ops(r, v, ang):
    r2 = r[::-1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GimbalLockWarning)
        return {
            "matrix": r.as_matrix(),
            "from_matrix": Rotation.from_matrix(r.as_matrix()).as_quat(),
            "rotvec": r.as_rotvec(),
            "from_rotvec": Rotation.from_rotvec(v * 3).as_quat(),
            "euler": r.as_euler("ZXZ"),
            "euler_tb": r.as_euler("xyz"),
            "from_euler": Rotation.from_euler("ZXY", ang).as_quat(),
            "compose": (r * r2).as_quat(),
            "compose_one": (r * r[0]).as_quat(),
            "apply": r.apply(v),
            "apply_inv": r.apply(v, inverse=True),
            "apply_one": r[3].apply(v),
            "inv": r.inv().as_quat(),
            "magnitude": r.magnitude(),
            "mrp": r.as_mrp(),
            "from_mrp": Rotation.from_mrp(v * 2).as_quat(),
        }


def test_large_batches_equal_small_batches(big):
    r, v, ang = big
    whole = _all_ops(r, v, ang)
    k = 997  # the same rows through the small-batch (gufunc) kernels
    part = _all_ops(r[:k], v[:k], ang[:k])
    for name, got in part.items():
        if name in ("compose", "compose_one", "apply_one"):
            continue  # depend on other rows
        if name in _NUMPY_TRIG:
            # large batches take atan2 / tan from NumPy's vectorised loops (correctly
            # rounded to within 1 ulp like libm, but not always the same ulp):
            # observed on 2e5 rotations: <= 4.4e-16 on quaternions, 1.8e-15 on angles
            # (4 ulp of pi: the outer angles add two atan2 and may wrap)
            np.testing.assert_allclose(whole[name][:k], got, rtol=0, atol=2e-14, err_msg=name)
            assert np.mean(whole[name][:k] == got) > 0.5, name  # mostly the same bits
        else:
            np.testing.assert_array_equal(whole[name][:k], got, err_msg=name)
    small = Rotation.from_quat(r.as_quat()[:k])
    np.testing.assert_array_equal(whole["apply_one"][:k], r[3].apply(v[:k]))
    np.testing.assert_array_equal(whole["compose_one"][:k], (small * r[0]).as_quat())


def test_threads_give_bit_identical_results(big):
    r, v, ang = big
    one, many = on_one_and_every_thread(lambda: _all_ops(r, v, ang))
    for name in one:
        np.testing.assert_array_equal(one[name], many[name], err_msg=name)


def test_set_num_threads_checks_its_argument():
    with pytest.raises(InvalidTypeError, match="`n` to be an integer"):
        set_num_threads(1.5)
    with pytest.raises(InvalidInputError, match="`n` to be an integer >= 1"):
        set_num_threads(0)
    with pytest.raises(InvalidInputError, match="at most NUMBA_NUM_THREADS"):
        set_num_threads(numba.config.NUMBA_NUM_THREADS + 1)


# ------------------------------------------------------------------ input defects
def test_normalize_false_refuses_non_unit_quaternions():
    q = np.array([1.0, 1.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"`quat` to be unit quaternions .*normalize=True"):
        Rotation(q, normalize=False)
    # unit to round-off: stored as given, and apply preserves lengths
    u = q / np.linalg.norm(q)
    r = Rotation(u, normalize=False)
    np.testing.assert_array_equal(r.as_quat(), u)
    v = np.array([0.3, -2.0, 5.0])
    np.testing.assert_allclose(np.linalg.norm(r.apply(v)), np.linalg.norm(v), rtol=1e-14)
    np.testing.assert_allclose(Rotation(q).as_quat(), u, rtol=0, atol=1e-16)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: Rotation.from_quat([1, 0, 0, 0], scalar_first="no"), "scalar_first"),
        (lambda: Rotation.from_rotvec([0, 0, 1], degrees="no"), "degrees"),
        (lambda: Rotation.from_rotvec([[0, 0, 1]], degrees=1), "degrees"),
        (lambda: Rotation.from_euler("ZXZ", [1, 2, 3], degrees="no"), "degrees"),
        (lambda: Rotation.from_axis_angle([0, 0, 1], 1.0, degrees="yes"), "degrees"),
        (lambda: Rotation.identity().as_euler("ZXZ", degrees="no"), "degrees"),
        (lambda: Rotation.identity().as_rotvec(degrees=None), "degrees"),
        (lambda: Rotation.identity().as_axis_angle(degrees="no"), "degrees"),
        (lambda: Rotation.identity().as_quat(scalar_first="no"), "scalar_first"),
        (lambda: Rotation.identity().as_quat(canonical="no"), "canonical"),
        (lambda: Rotation.identity().apply([1, 0, 0], inverse="no"), "inverse"),
        (
            lambda: Rotation.identity().approx_equal(Rotation.identity(), atol=1, degrees="no"),
            "degrees",
        ),
        (lambda: Rotation([1, 0, 0, 0], normalize="no"), "normalize"),
    ],
)
def test_flags_must_be_bools(call, name):
    with pytest.raises(InvalidTypeError, match=f"Expected `{name}` to be a bool, got"):
        call()


def test_wrong_types_are_type_errors():
    with pytest.raises(InvalidTypeError, match="`seq` to be a string, got int"):
        Rotation.from_euler(3, [1, 2, 3])
    with pytest.raises(InvalidTypeError, match="`seq` to be a string"):
        Rotation.identity().as_euler(None)
    with pytest.raises(InvalidTypeError, match="`quat` to be array-like of real numbers"):
        Rotation.from_quat([1, 0, "a", 0])
    with pytest.raises(InvalidTypeError, match="`vectors` to be array-like"):
        Rotation.identity().apply("x")
    r = Rotation.identity()
    with pytest.raises(
        InvalidTypeError, match=r"poinsot.Rotation in `r \* other`, got int .*apply"
    ):
        r * 3
    with pytest.raises(InvalidTypeError, match=r"poinsot.Rotation in `other \* r`, got float"):
        2.0 * r
    with pytest.raises(InvalidTypeError, match=r"got numpy.ndarray"):
        r * np.eye(3)
    with pytest.raises(InvalidTypeError, match="convert SciPy rotations"):
        r * SciPyRotation.identity()


def test_short_paths_still_validate():
    with pytest.raises(InvalidInputError, match="finite"):
        Rotation.from_quat([1.0, np.nan, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="finite"):
        Rotation.from_rotvec(np.array([np.inf, 0.0, 0.0]))
    with pytest.raises(InvalidInputError, match="non-zero"):
        Rotation.from_quat(np.zeros(4))
    with pytest.raises(InvalidInputError, match=r"shape \(\.\.\., 3\)"):
        Rotation.identity().apply([1.0, 2.0])
    with pytest.raises(InvalidInputError, match="determinant"):
        Rotation.from_matrix(-np.eye(3))
    with pytest.raises(InvalidInputError, match="orthogonal within 0"):
        Rotation.from_matrix(np.diag([1.0, 1.0, 1.0 + 1e-15]), atol=0.0)
    with pytest.raises(InvalidInputError, match="finite"):
        Rotation.from_euler("ZXZ", [0.0, np.nan, 0.0])
    # huge and tiny quaternions go to the robust general path
    np.testing.assert_array_equal(
        Rotation.from_quat([1e200, 0, 0, 1e200]).as_quat(),
        Rotation.from_quat([1.0, 0, 0, 1.0]).as_quat(),
    )
    np.testing.assert_array_equal(
        Rotation.from_quat([0, 1e-200, 0, 0]).as_quat(), [0.0, 1.0, 0.0, 0.0]
    )


@pytest.mark.skipif(not SCIPY_EMPTY, reason="this SciPy refuses to convert empty rotations")
def test_empty_sets_follow_scipy():
    r = Rotation.from_quat(np.empty((0, 4)))
    s = SciPyRotation.from_quat(np.empty((0, 4)), scalar_first=True)
    assert r.shape == (0,) and len(r) == 0
    assert r.as_matrix().shape == s.as_matrix().shape == (0, 3, 3)
    assert r.as_rotvec().shape == s.as_rotvec().shape == (0, 3)
    assert r.as_euler("ZXZ").shape == s.as_euler("ZXZ").shape == (0, 3)
    assert r.apply(np.empty((0, 3))).shape == (0, 3)
    assert (r * r).shape == (0,) and r.inv().shape == (0,) and r.magnitude().shape == (0,)
    assert Rotation.from_rotvec(np.empty((0, 3))).shape == (0,)
    assert Rotation.from_euler("xyz", np.empty((0, 3))).shape == (0,)
    assert Rotation.from_matrix(np.empty((0, 3, 3))).shape == (0,)
    with pytest.raises(InvalidInputError, match="at least one rotation"):
        r.mean()


def test_default_threads_are_the_idle_cores(monkeypatch):
    from poinsot.rotations import _lazy

    monkeypatch.setattr(_lazy.os, "cpu_count", lambda: 2)
    for load, want in [(0.9, 2), (1.6, 1), (11.0, 1), (0.0, 2)]:
        monkeypatch.setattr(_lazy.os, "getloadavg", lambda load=load: (load, load, load))
        assert _lazy._idle_threads(2) == want
        assert _lazy._idle_threads(1) == 1


def test_every_single_rotation_stores_a_contiguous_float64_quaternion():
    # The one-rotation numba entry points (rotations._lazy.one) do not check their
    # arguments: every way of making a single rotation must store a C-contiguous
    # float64 (4,) array, and the short paths must then agree with the batch paths.
    rng = np.random.default_rng(11)
    batch = Rotation.random(6, rng=rng)
    fortran = Rotation.from_quat(np.asfortranarray(rng.standard_normal((3, 4))))
    a, b = Rotation.random(rng=rng), Rotation.random(rng=rng)
    made = {
        "from_quat": Rotation.from_quat([0.1, 0.2, 0.3, 0.4]),
        "from_quat int": Rotation.from_quat([1, 0, 0, 0]),
        "from_quat scalar last": Rotation.from_quat(np.arange(1.0, 5.0), scalar_first=False),
        "Rotation()": Rotation(np.array([1.0, 2.0, 3.0, 4.0])[::-1]),
        "from_matrix": Rotation.from_matrix(np.asfortranarray(a.as_matrix())),
        "from_rotvec": Rotation.from_rotvec([0.1, -0.2, 0.3]),
        "from_axis_angle": Rotation.from_axis_angle([0.0, 0.0, 2.0], 0.3),
        "from_euler": Rotation.from_euler("ZXZ", [0.1, 0.2, 0.3]),
        "from_gibbs": Rotation.from_gibbs([0.1, 0.2, 0.3]),
        "from_mrp": Rotation.from_mrp([0.1, 0.2, 0.3]),
        "from_basis": Rotation.from_basis(*a.as_matrix().T),
        "identity": Rotation.identity(),
        "random": Rotation.random(rng=1),
        "row of a batch": batch[3],
        "row of a strided batch": batch[::2][1],
        "row of a Fortran batch": fortran[1],
        "row of a reshaped batch": batch.reshape(2, 3)[1, 2],
        "product": b * a,
        "inverse": a.inv(),
        "power": a**0.3,
        "slerp": slerp(a, b, 0.4),
        "mean": batch.mean(),
        "align_vectors": Rotation.align_vectors(np.eye(3), a.apply(np.eye(3)))[0],
        "pickled": __import__("pickle").loads(__import__("pickle").dumps(a)),
    }
    for name, r in made.items():
        q = r._q
        assert q.shape == (4,) and q.dtype == np.float64 and q.flags.c_contiguous, name
        row = Rotation.from_quat(q[None, :])
        np.testing.assert_array_equal(r.as_matrix(), row.as_matrix()[0], err_msg=name)
        np.testing.assert_array_equal(r.as_rotvec(), row.as_rotvec()[0], err_msg=name)
        np.testing.assert_array_equal(r.as_mrp(), row.as_mrp()[0], err_msg=name)
        np.testing.assert_array_equal(r.inv().as_quat(), row.inv().as_quat()[0], err_msg=name)
        np.testing.assert_array_equal(r.as_quat(), q, err_msg=name)


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs os.fork")
@pytest.mark.filterwarnings("ignore::poinsot.GimbalLockWarning")
@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # fork of a threaded process
def test_chunked_batches_work_in_a_forked_child(big):
    # The chunked conversions keep a thread pool; a child forked after it was made has
    # none of its threads and must make its own (a stale pool would hang).
    import os

    r = big[0]
    n0 = get_num_threads()
    set_num_threads(numba.config.NUMBA_NUM_THREADS)
    try:
        a = r.as_euler("ZXZ")
        pid = os.fork()
        if pid == 0:  # pragma: no cover - the child
            os._exit(0 if np.array_equal(r.as_euler("ZXZ"), a) else 3)
        _, status = os.waitpid(pid, 0)
    finally:
        set_num_threads(n0)
    assert os.waitstatus_to_exitcode(status) == 0


def test_short_paths_of_the_other_constructors_and_conversions_equal_the_batch():
    # from_mrp, from_gibbs, from_axis_angle, as_gibbs, as_axis_angle, **, identity,
    # random and mean of one rotation take short paths (plain Python floats or one
    # compiled call); each must give its row of the batch result.
    rng = np.random.default_rng(21)
    vecs = rng.standard_normal((60, 3)) * rng.choice([1e-9, 0.3, 1.0, 5.0, 1e40], (60, 1))
    angles = rng.uniform(-7, 7, 60)
    for name, one, batch, atol in [
        ("from_mrp", lambda v: Rotation.from_mrp(v), lambda: Rotation.from_mrp(vecs), 2e-15),
        ("from_gibbs", lambda v: Rotation.from_gibbs(v), lambda: Rotation.from_gibbs(vecs), 2e-15),
    ]:
        # the same formula; NumPy's einsum / scaled length may round |p|^2 differently:
        # observed 1.1e-16 (and 4.7e-16 relative on components of 1e-40)
        got = np.array([one(v).as_quat() for v in vecs])
        np.testing.assert_allclose(got, batch().as_quat(), rtol=5e-15, atol=atol, err_msg=name)
    for deg in (False, True):
        pairs = zip(vecs, angles, strict=True)
        got = np.array([Rotation.from_axis_angle(v, f, degrees=deg).as_quat() for v, f in pairs])
        want = Rotation.from_axis_angle(vecs, angles, degrees=deg).as_quat()
        # math.hypot and NumPy's scaled length may differ by an ulp: observed 2.2e-16
        np.testing.assert_allclose(got, want, rtol=0, atol=3e-15)
        batch = Rotation.from_quat(Q)
        axes, angs = batch.as_axis_angle(degrees=deg)
        for k, q in enumerate(Q):
            ax, an = Rotation.from_quat(q).as_axis_angle(degrees=deg)
            assert type(an) is np.float64 and ax.shape == (3,)
            # |l| by einsum in the batch: observed 2.2e-16 apart
            np.testing.assert_allclose(ax, axes[k], rtol=0, atol=3e-15)
            np.testing.assert_allclose(an, angs[k], rtol=3e-15, atol=3e-15)
    finite = Q[np.abs(Rotation.from_quat(Q).magnitude() - np.pi) > 1e-12]
    np.testing.assert_array_equal(
        np.array([Rotation.from_quat(q).as_gibbs() for q in finite]),
        Rotation.from_quat(finite).as_gibbs(),
    )
    for n in (0.5, -0.3, 2.0, 3, -1, 1, np.float64(0.25)):
        got = np.array([(Rotation.from_quat(q) ** n).as_quat() for q in Q])
        np.testing.assert_array_equal(got, (Rotation.from_quat(Q) ** n).as_quat(), err_msg=n)
    np.testing.assert_array_equal(Rotation.identity().as_quat(), [1.0, 0.0, 0.0, 0.0])
    assert Rotation.identity().shape == () and Rotation.identity(()).shape == ()
    np.testing.assert_allclose(
        Rotation.random(rng=7).as_quat(), Rotation.random(1, rng=7).as_quat()[0], rtol=0, atol=3e-16
    )
    r = Rotation.from_quat(Q[4])
    np.testing.assert_array_equal(r.mean().as_quat(), r.as_quat())  # the mean of one is itself
    # ... as the eigenvector of the batch path finds it (up to the sign of q)
    one_of_batch = Rotation.from_quat(Q[4][None]).mean().as_quat()
    np.testing.assert_allclose(abs(r.mean().as_quat() @ one_of_batch), 1.0, rtol=0, atol=1e-14)


def test_random_without_a_seed_differs_between_calls_and_forked_children():
    import os

    a, b = Rotation.random(), Rotation.random()
    assert not np.array_equal(a.as_quat(), b.as_quat())
    if not hasattr(os, "fork"):
        return
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        os.write(w, Rotation.random().as_quat().tobytes())
        os._exit(0)
    os.waitpid(pid, 0)
    child = np.frombuffer(os.read(r, 32), dtype=np.float64)
    os.close(r), os.close(w)
    assert not np.array_equal(child, Rotation.random().as_quat())


def test_streamed_inverse_is_the_exact_conjugate():
    """A batch large enough for the streaming stores (``_kernels.STREAM_MIN_BYTES``)
    is the conjugate bit for bit (signed zeros included) on 1 and on every thread, and
    SciPy's inverse to round-off; rows past the last full part of the split are
    written too (an odd count)."""
    from poinsot.rotations._kernels import STREAM_MIN_BYTES

    n = STREAM_MIN_BYTES // 32 + 1001
    q = np.random.default_rng(5).normal(size=(n, 4))
    q[:7, 1:] = 0.0  # the identity's -0.0 in the conjugate
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    r = Rotation.from_quat(q)
    want = q * np.array([1.0, -1.0, -1.0, -1.0])
    for got in on_one_and_every_thread(lambda: r.inv().as_quat()):
        assert got.tobytes() == want.tobytes()
    s = SciPyRotation.from_quat(q, scalar_first=True).inv().as_quat(scalar_first=True)
    np.testing.assert_allclose(got, s, rtol=0, atol=1e-15)


def test_streamed_matrices_equal_plain_stores_bit_for_bit():
    """A batch whose (N, 3, 3) result is large enough for the streaming stores
    (``_kernels.STREAM_MIN_BYTES``) gives, bit for bit on 1 and on every thread, the
    matrices of sub-batches written with plain stores and of single rotations, and
    SciPy's to round-off; an odd count, so rows past the last full part are written."""
    from poinsot.rotations._kernels import STREAM_MIN_BYTES

    n = STREAM_MIN_BYTES // 72 + 1001
    q = np.random.default_rng(8).normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    r = Rotation.from_quat(q)
    step = max(PARALLEL_MIN_SIZE, n // 8)  # sub-batches below STREAM_MIN_BYTES
    assert 72 * step < STREAM_MIN_BYTES
    want = np.concatenate([r[i : i + step].as_matrix() for i in range(0, n, step)])
    rows = np.r_[0:3, n - 3 : n]
    singles = np.array([r[int(i)].as_matrix() for i in rows])
    np.testing.assert_array_equal(want[rows], singles)
    for got in on_one_and_every_thread(r.as_matrix):
        assert got.tobytes() == want.tobytes()
    # A = (2 l0^2 - 1) E + 2 l0 l^ + 2 l l^T in extended precision (where NumPy has it)
    ql = q.astype(np.longdouble)
    w, v = ql[:, 0], ql[:, 1:]
    exact = (2 * w * w - 1)[:, None, None] * np.eye(3, dtype=np.longdouble)
    exact += 2 * v[:, :, None] * v[:, None, :]
    x, y, z = v.T
    hat = np.zeros((n, 3, 3), dtype=np.longdouble)
    hat[:, 0, 1], hat[:, 0, 2], hat[:, 1, 2] = -z, y, -x
    exact += 2 * w[:, None, None] * (hat - hat.transpose(0, 2, 1))
    np.testing.assert_allclose(got, exact.astype(float), rtol=0, atol=2e-14)  # seen 1.3e-15


def test_large_batch_magnitude_is_the_angle():
    """A large batch's angles (compiled |l|, |l0|, then NumPy's atan2 in chunks) against
    the angles the rotations were built from, SciPy, and the one-rotation path; the
    sign of ``l0`` does not matter (q and -q), nor does 0 or pi exactly."""
    from poinsot.rotations._lazy import CHUNK

    n = max(PARALLEL_MIN_SIZE, 5 * CHUNK) + 17  # several chunks, the last one partial
    rng = np.random.default_rng(21)
    f = rng.uniform(0.0, np.pi, n)
    f[:3] = 0.0, np.pi, np.pi / 2
    e = rng.standard_normal((n, 3))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    q = np.concatenate([np.cos(f / 2)[:, None], np.sin(f / 2)[:, None] * e], axis=1)
    q[1::2] *= -1.0  # the same rotations
    r = Rotation.from_quat(q)
    got = r.magnitude()
    assert got.shape == (n,) and got[0] == 0.0
    np.testing.assert_allclose(got, f, rtol=0, atol=2e-14)  # seen 4.4e-16 (q rounded)
    s = SciPyRotation.from_quat(q, scalar_first=True).magnitude()
    np.testing.assert_allclose(got, s, rtol=0, atol=2e-14)
    rows = np.r_[0:5, n - 5 : n]
    singles = np.array([r[int(i)].magnitude() for i in rows])
    np.testing.assert_allclose(got[rows], singles, rtol=0, atol=2e-14)  # libm vs SIMD atan2
    assert r[: 17 * 1200].reshape(1200, 17).magnitude().shape == (1200, 17)


@pytest.mark.parametrize("scale", [1e99, 1e150, 1e300])
def test_large_mrp_batch_with_far_rows(scale):
    """A large batch of MRPs with one far row (``|p|^2`` near or past overflow): the
    compiled pass hands the batch back to the shadow-set path when ``|p|^2 > 1e199``,
    so every row equals its one-rotation result and the far row is the rotation by
    ``f = 4 atan(|p|) -> 2 pi``, ``L -> (-1, 2 e / |p|)``; the near rows agree with
    SciPy."""
    n = PARALLEL_MIN_SIZE + 3
    p = np.random.default_rng(9).uniform(-3, 3, (n, 3))
    p[n // 2] = 0.0, 0.0, scale
    got = Rotation.from_mrp(p).as_quat()
    rows = np.r_[0:3, n // 2, n - 3 : n]
    singles = np.array([Rotation.from_mrp(p[i]).as_quat() for i in rows])
    np.testing.assert_array_equal(got[rows], singles)
    np.testing.assert_allclose(got[n // 2], [-1.0, 0.0, 0.0, 2.0 / scale], rtol=1e-15)
    near = np.ones(n, bool)
    near[n // 2] = False
    s = SciPyRotation.from_mrp(p[near]).as_quat(scalar_first=True)
    np.testing.assert_allclose(got[near], s, rtol=0, atol=1e-14)


def test_large_mean_is_the_symmetric_centre_on_any_thread_count():
    """Rotations in pairs ``c exp(+d)``, ``c exp(-d)`` about a centre ``c`` have ``c``
    as their chordal mean (the cross terms of ``sum q q^T`` cancel, leaving ``c c^T``
    plus directions orthogonal to ``c``): a large set (compiled partial sums over
    fixed chunks, the last one partial), with equal weights per pair, over all
    rotations and per column; the same bits on 1 and on every thread; SciPy."""
    from poinsot.rotations.rotation import _MEAN_CHUNK

    half = (PARALLEL_MIN_SIZE + 3 * _MEAN_CHUNK) // 2 + 7
    rng = np.random.default_rng(17)
    centre = Rotation.from_rotvec([0.3, -1.2, 2.0])
    v = rng.normal(scale=0.4, size=(half, 3))
    v /= np.maximum(1.0, np.linalg.norm(v, axis=1))[:, None]  # |d| <= 1 < pi / 2: the
    d = Rotation.from_rotvec(v)  # centre stays the top eigenvector of every pair too
    r = Rotation.concatenate([centre * d, centre * d.inv()])
    w = np.tile(rng.uniform(0.1, 2.0, half), 2)
    (a, aw), (b, bw) = on_one_and_every_thread(lambda: (r.mean().as_quat(), r.mean(w).as_quat()))
    cols = r.reshape(2, half).mean(w.reshape(2, half), axis=0)
    assert a.tobytes() == b.tobytes() and aw.tobytes() == bw.tobytes()
    for q in (a, aw):
        assert (Rotation.from_quat(q).inv() * centre).magnitude() < 1e-13  # seen 2.2e-15
    assert ((cols.inv() * centre).magnitude() < 1e-13).all()
    s = SciPyRotation.from_quat(r.as_quat(), scalar_first=True).mean(w)
    assert (Rotation.from_scipy(s).inv() * Rotation.from_quat(aw)).magnitude() < 1e-13
