"""Bad-input and singularity regressions for ``poinsot.kinematics`` (audit).

Each case used to end in a raw NumPy traceback, a silent inf/NaN or a wrong
answer; now it raises a :class:`poinsot.PoinsotError` naming the argument, or
returns the accurate value.
"""

import numpy as np
import pytest

import poinsot.kinematics as K
from poinsot import InvalidInputError, InvalidTypeError, Rotation

W2 = np.ones((2, 3))
W5 = np.ones((5, 3))
Q2 = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
C2 = np.tile(np.eye(3), (2, 1, 1))

# (function, args, regex of the message): leading batch shapes that do not broadcast
MISMATCHED_BATCH = [
    (K.quat_rate, (Q2, W5), r"`q` \(2,\), `omega` \(5,\)"),
    (K.omega_from_quat_rate, (Q2, np.ones((5, 4))), r"`q` \(2,\), `qdot` \(5,\)"),
    (K.dcm_rate, (C2, W5), r"`C` \(2,\), `omega` \(5,\)"),
    (K.omega_from_dcm_rate, (C2, np.zeros((5, 3, 3))), r"`C` \(2,\), `Cdot` \(5,\)"),
    (lambda a, w: K.euler_rates("ZXZ", a, w), (0.5 * W2, W5), r"`angles` \(2,\), `omega`"),
    (
        lambda a, r: K.omega_from_euler_rates("ZXZ", a, r),
        (0.5 * W2, W5),
        r"`angles` \(2,\), `rates`",
    ),
    (K.gibbs_rate, (W2, W5), r"`g` \(2,\), `omega` \(5,\)"),
    (K.omega_from_gibbs_rate, (W2, W5), r"`g` \(2,\), `gdot` \(5,\)"),
    (K.mrp_rate, (0.1 * W2, W5), r"`p` \(2,\), `omega` \(5,\)"),
    (K.omega_from_mrp_rate, (0.1 * W2, W5), r"`p` \(2,\), `pdot` \(5,\)"),
    (K.rotvec_rate, (0.1 * W2, W5), r"`rotvec` \(2,\), `omega` \(5,\)"),
    (K.omega_from_rotvec_rate, (0.1 * W2, W5), r"`rotvec` \(2,\), `rotvec_dot` \(5,\)"),
]


@pytest.mark.parametrize(("fn", "args", "match"), MISMATCHED_BATCH)
def test_rates_mismatched_batch_shapes(fn, args, match):
    with pytest.raises(InvalidInputError, match="batch .leading. shapes of " + match):
        fn(*args)


@pytest.mark.parametrize("degrees", [np.ones(3), np.empty(0), "yes", None, 1.0])
@pytest.mark.parametrize("fn", [K.euler_rates, K.omega_from_euler_rates])
def test_euler_degrees_must_be_bool(fn, degrees):
    with pytest.raises(InvalidTypeError, match="`degrees` to be a bool"):
        fn("ZXZ", [0.1, 0.5, 0.2], [1.0, 2.0, 3.0], degrees=degrees)


def test_euler_rate_matrix_degrees_must_be_bool():
    with pytest.raises(InvalidTypeError, match="`degrees` to be a bool"):
        K.euler_rate_matrix("ZXZ", [0.1, 0.5, 0.2], degrees=np.ones(2))
    # numpy bools are bools
    m = K.euler_rate_matrix("ZXZ", [0.0, 90.0, 0.0], degrees=np.bool_(True))
    np.testing.assert_allclose(m, K.euler_rate_matrix("ZXZ", [0.0, np.pi / 2, 0.0]))


def test_mrp_overflow_is_an_error_not_nan():
    with pytest.raises(InvalidInputError, match="`p` to have a moderate magnitude"):
        K.mrp_rate([1e200, 0.0, 0.0], [0.0, 1.0, 0.0])
    with pytest.raises(InvalidInputError, match="`p` to have a moderate magnitude"):
        K.omega_from_mrp_rate([1e154, 0.0, 0.0], [0.0, 1.0, 0.0])


def test_mrp_shadow_scale_free():
    # shadow = -p / |p|^2 must not underflow to 0 nor overflow to inf
    np.testing.assert_allclose(K.mrp_shadow([1e200, 0.0, 0.0]), [-1e-200, 0.0, 0.0], rtol=1e-15)
    np.testing.assert_allclose(K.mrp_shadow([0.0, 1e-200, 0.0]), [0.0, -1e200, 0.0], rtol=1e-15)
    p = np.array([0.3, -0.4, 1.2])
    np.testing.assert_allclose(K.mrp_shadow(p), -p / (p @ p), rtol=1e-15)
    with pytest.raises(InvalidInputError, match="`p` to be non-zero"):
        K.mrp_shadow([0.0, 0.0, 0.0])


@pytest.mark.parametrize("threshold", [1e200, True, np.inf])
def test_mrp_switch_threshold_range(threshold):
    with pytest.raises(InvalidInputError, match="`threshold` to be a number >= 1"):
        K.mrp_switch([0.1, 0.2, 0.3], threshold=threshold)


@pytest.mark.parametrize("fn", [K.rotvec_rate, K.omega_from_rotvec_rate])
def test_rotvec_huge_angle(fn):
    with pytest.raises(InvalidInputError, match="`rotvec` to have a norm .rotation angle. below"):
        fn([1e200, 0.0, 0.0], [0.0, 1.0, 0.0])


def test_fornberg_deriv_bool_rejected():
    # True used to index as a boolean mask and return a (3, 2, 1) array
    with pytest.raises(InvalidTypeError, match="`deriv` to be an integer"):
        K.fornberg_weights(0.0, [-1.0, 0.0, 1.0], deriv=True)
    np.testing.assert_allclose(K.fornberg_weights(0.0, [-1.0, 0.0, 1.0], deriv=1), [-0.5, 0, 0.5])


@pytest.mark.parametrize("bad", [None, 3.0, object()])
def test_chain_non_sequence(bad):
    m = K.FrameMotion(omega=[0.0, 0.0, 1.0])
    with pytest.raises(InvalidTypeError, match="`motions` to be a sequence"):
        K.chain(bad, [])
    with pytest.raises(InvalidTypeError, match="`offsets` to be a sequence"):
        K.chain([m, m], bad)


@pytest.mark.parametrize("bad", [None, 3.0, "ab", object()])
def test_reduce_motions_non_sequence(bad):
    with pytest.raises(InvalidTypeError, match="`rotations` to be a sequence"):
        K.reduce_motions(bad, [])
    with pytest.raises(InvalidTypeError, match="`translations` to be a sequence"):
        K.reduce_motions([], bad)


@pytest.mark.parametrize("scale", [1e-200, 1.0, 1e200])
def test_screw_axis_scale_free(scale):
    """The Mozzi axis of (s v0, s w) is that of (v0, w): point, direction unchanged,
    parameter unchanged, min_speed scaled (closed form: point = w x v0 / |w|^2)."""
    v0, w = np.array([0.0, -2.0, 0.5]), np.array([0.0, 0.0, 2.0])
    s = K.screw_axis(scale * v0, scale * w, atol=0.0)
    np.testing.assert_allclose(s.point, [1.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(s.direction, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(s.parameter, 0.25, rtol=1e-15)
    np.testing.assert_allclose(s.min_speed, 0.5 * scale, rtol=1e-15)


def test_screw_axis_reports_tiny_omega_correctly():
    with pytest.raises(InvalidInputError, match=r"\|omega\| = 1e-200"):
        K.screw_axis([1.0, 0.0, 0.0], [0.0, 0.0, 1e-200])


def test_already_fine_cases_stay_errors():
    """Cases found fine in the audit: keep them that way."""
    t = np.linspace(0.0, 1.0, 11)
    r = Rotation.from_rotvec(np.outer(t, [0.1, 0.2, 0.3]))
    with pytest.raises(InvalidInputError, match="strictly increasing"):
        K.angular_velocity(t[::-1], r)
    with pytest.raises(InvalidInputError, match="11 samples along axis 0"):
        K.angular_velocity(t, r.as_quat()[:5])
    with pytest.raises(InvalidInputError, match="`omega.t.` to return only finite"):
        K.propagate([1.0, 0, 0, 0], lambda s: np.full(3, np.nan), t, method="adaptive")
    with pytest.raises(InvalidInputError, match="`method` to be one of"):
        K.propagate([1.0, 0, 0, 0], np.ones((11, 3)), t, method="cfree4")
    with pytest.raises(InvalidInputError, match="'ZXZ' are singular at these `angles`"):
        K.euler_rates("ZXZ", [0.1, 0.0, 0.2], [1.0, 2.0, 3.0])


def _helix(s):
    return np.stack([np.cos(s), np.sin(s), 0.5 * s], axis=-1)


@pytest.mark.parametrize("stencil", [None, "7", 3, 0, True])
def test_frenet_stencil_checked_for_callables_too(stencil):
    # a wrong type is a type error, a wrong integer a value error (both name `stencil`)
    exc = (
        InvalidInputError if isinstance(stencil, int) and stencil is not True else InvalidTypeError
    )
    with pytest.raises(exc, match="`stencil` to be an integer"):
        K.frenet(np.linspace(0.0, 1.0, 5), _helix, stencil=stencil)


def test_frenet_unresolvable_or_overflowing_step():
    # t + step == t: used to return NaN silently (with only a SingularityWarning)
    with pytest.raises(InvalidInputError, match="`step` .* to be resolvable at the times"):
        K.frenet(np.array([1e200]), _helix)
    # step**3 underflows: used to raise a RuntimeWarning and return inf
    with pytest.raises(InvalidInputError, match="the derivatives overflow"):
        K.frenet(np.array([0.0]), _helix, step=1e-200)
    # a moderate step stays accurate: helix curvature a/(a^2 + b^2) = 0.8
    f = K.frenet(np.array([0.0, 1.0]), _helix, step=0.01)
    np.testing.assert_allclose(f.curvature, 0.8, rtol=1e-8)


@pytest.mark.parametrize("scale", [1e-200, 1e-100, 1e100, 1e300])
def test_frenet_any_length_scale(scale):
    """A helix (cos t, sin t, t/2) scaled by L has kappa = 0.8/L and tau = 0.4/L.
    At L = 1e-200 every point used to be reported straight (|v x a| underflowed),
    at L = 1e200 the rounding bound overflowed (RuntimeWarning, NaN)."""
    t = np.linspace(0.0, 2 * np.pi, 60)
    f = K.frenet(t, scale * _helix(t))
    assert not f.singular.any()
    np.testing.assert_allclose(f.curvature * scale, 0.8, rtol=5e-5)  # 2.3e-6 seen
    np.testing.assert_allclose(f.torsion * scale, 0.4, rtol=5e-3)  # 9.5e-5 seen
    g = K.frenet(t[10:12], lambda s: scale * _helix(s))
    np.testing.assert_allclose(g.curvature * scale, 0.8, rtol=1e-9)
    np.testing.assert_allclose(g.torsion * scale, 0.4, rtol=1e-7)


def test_frenet_unrepresentable_derivatives():
    t = np.linspace(0.0, 2 * np.pi, 60)
    with pytest.raises(InvalidInputError, match="finite first to third derivatives"):
        K.frenet(1e-200 * t, _helix(t))  # r''' ~ 1e600


# ---------------------------------------------------------------- issue 38: raw NumPy errors
@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: K.centrodes(np.zeros((5, 2)), np.ones((4, 2)), np.zeros(5), np.ones(5)),
         r"`point` \(5,\), `velocity` \(4,\)"),
        (lambda: K.centrodes(np.zeros((5, 2)), np.ones((5, 2)), np.zeros(4), np.ones(5)),
         r"`angle` \(4,\)"),
        (lambda: K.velocity_center(np.zeros((5, 2)), np.ones((4, 2)), 1.0), r"`velocity` \(4,\)"),
        (lambda: K.acceleration_center(np.zeros((5, 2)), np.ones((5, 2)), np.ones(3), 0.0),
         r"`omega` \(3,\)"),
        (lambda: K.integrate_poisson_matrix(Rotation.identity(), lambda t: np.zeros(4), [0, 1]),
         r"`omega\(t\)` to return shape \(3,\).*got \(4,\) at t = 0"),
        (lambda: K.coning_quat([0.1, 0.2], 1.0, [0.0]), r"`half_angle` to be a real number"),
        (lambda: Rotation.from_euler("ship", [1.0, 2.0]), r"`angles` to have shape \(\.\.\., 3\)"),
    ],
)  # fmt: skip
def test_named_errors_instead_of_numpy_tracebacks(call, match):
    with pytest.raises(InvalidInputError, match=match):
        call()


def test_rigid_transform_bad_inputs_are_named():
    from poinsot.rotations.transform import RigidTransform

    with pytest.raises(InvalidInputError, match=r"`translation` \(3,\), `rotation` \(2,\)"):
        RigidTransform.from_components(np.zeros((3, 3)), Rotation.from_quat(np.ones((2, 4))))
    with pytest.raises(InvalidTypeError, match="`n`"):
        RigidTransform.identity() ** "x"
    # a real power is a screw motion: half of a translation by 2 is a translation by 1
    half = RigidTransform.from_translation([0.0, 0.0, 2.0]) ** np.float64(0.5)
    np.testing.assert_allclose(half.as_components()[0], [0.0, 0.0, 1.0], atol=1e-15)


def test_acceleration_center_of_a_translation_is_at_infinity():
    """Its docstring said inf for omega = eps = 0; it returned NaN (0/0)."""
    q = K.acceleration_center([[0.0, 0.5], [1.0, 1.0]], [[1.0, 0.0], [0.0, 0.0]], 0.0, 0.0)
    assert np.isinf(q[0]).all() and np.isnan(q[1]).all()  # a_A = 0 too: every point
    # and the ordinary case still solves a_Q = 0: a_A + eps k x AQ - omega^2 AQ = 0
    a, acc, w, e = np.array([0.3, -0.2]), np.array([1.5, 0.7]), 2.0, -3.0
    d = K.acceleration_center(a, acc, w, e) - a
    np.testing.assert_allclose(acc + e * np.array([-d[1], d[0]]) - w**2 * d, 0.0, atol=1e-14)
