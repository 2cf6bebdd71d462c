"""Bad-input regressions for ``poinsot.mass`` (audit): each case used to end in a
raw NumPy traceback, an inf/zero tensor or a RuntimeWarning."""

import numpy as np
import pytest

import poinsot.mass as M
from poinsot import InvalidInputError, InvalidTypeError

SOLIDS = [
    (M.box, (1.0, 1.0, 2.0, 3.0)),
    (M.sphere, (1.0, 1.0)),
    (M.cylinder, (1.0, 1.0, 2.0)),
    (M.cone, (1.0, 1.0, 2.0)),
    (M.ellipsoid, (1.0, 1.0, 2.0, 3.0)),
    (M.rod, (1.0, 1.0)),
    (M.disc, (1.0, 1.0)),
    (M.ring, (1.0, 1.0)),
]


@pytest.mark.parametrize(("fn", "args"), SOLIDS)
@pytest.mark.parametrize("value", [1e200, 1e-200])
def test_solids_unrepresentable_dimension(fn, args, value):
    """m d^2 overflowing to inf (or underflowing to a zero tensor) is an error."""
    bad = (args[0],) + tuple(value * d for d in args[1:])
    with pytest.raises(InvalidInputError, match=f"dimensions of the {fn.__name__} to give a"):
        fn(*bad)


@pytest.mark.parametrize(("fn", "args"), SOLIDS)
def test_solids_mismatched_batch(fn, args):
    bad = (np.ones(2), np.ones(5)) + args[2:]
    with pytest.raises(InvalidInputError, match=r"shapes of `mass` \(2,\), `\w+` \(5,\)"):
        fn(*bad)


@pytest.mark.parametrize("fn", [M.sphere, M.cylinder])
@pytest.mark.parametrize("hollow", [np.ones(3), "yes", None, 1])
def test_hollow_must_be_bool(fn, hollow):
    args = (1.0, 1.0) if fn is M.sphere else (1.0, 1.0, 2.0)
    with pytest.raises(InvalidTypeError, match="`hollow` to be a bool"):
        fn(*args, hollow=hollow)


def test_huge_mass_is_fine():
    # only the product matters: a large mass with small dimensions is representable
    np.testing.assert_allclose(M.sphere(1e200, 1.0).diagonal(), [0.4e200] * 3)


@pytest.mark.parametrize(
    ("tol", "exc", "match"),
    [
        (None, InvalidTypeError, "`{}` to be array-like of numbers"),
        ("x", InvalidTypeError, "`{}` to be array-like of numbers"),
        (np.ones(2), InvalidInputError, r"`rtol` and `atol` to be >= 0 \(scalars\)"),
        ([[1, 2], [3]], InvalidTypeError, "`{}` to be array-like of real numbers"),
    ],
)
@pytest.mark.parametrize("which", ["rtol", "atol"])
def test_check_inertia_tolerances(tol, exc, match, which):
    with pytest.raises(exc, match=match.format(which)):
        M.check_inertia(np.diag([1.0, 2.0, 3.0]), **{which: tol})
    with pytest.raises(exc, match=match.format(which)):
        M.check_principal_moments([1.0, 2.0, 3.0], **{which: tol})


@pytest.mark.parametrize("flag", [np.ones(2), "yes", None])
def test_check_inertia_allow_singular_bool(flag):
    with pytest.raises(InvalidTypeError, match="`allow_singular` to be a bool"):
        M.check_inertia(np.diag([1.0, 2.0, 3.0]), allow_singular=flag)


@pytest.mark.parametrize("scale", [1e-200, 1.0, 1e200])
def test_moment_about_scale_free_axis(scale):
    J = np.diag([1.0, 2.0, 3.0])
    np.testing.assert_allclose(M.moment_about(J, [scale, scale, 0.0]), 1.5, rtol=1e-14)


def test_moment_about_mismatched_batch():
    J = np.tile(np.diag([1.0, 2.0, 3.0]), (2, 1, 1))
    with pytest.raises(InvalidInputError, match=r"`inertia` \(2,\) and `axis` \(5,\)"):
        M.moment_about(J, np.ones((5, 3)))


def test_mesh_ragged_faces():
    v = np.eye(3)
    with pytest.raises(InvalidTypeError, match="`faces` to be an integer array"):
        M.mesh(v, [[0, 1, 2], [0, 1]], mass=1.0)


def test_energy_and_momentum_mismatched_batch():
    J = np.diag([1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match=r"`omega` \(2,\), `v_cm` \(5,\)"):
        M.kinetic_energy(1.0, J, np.ones((2, 3)), np.ones((5, 3)))
    with pytest.raises(InvalidInputError, match=r"`omega` \(2,\), `v_cm` \(5,\)"):
        M.angular_momentum(1.0, J, np.ones((2, 3)), np.ones((5, 3)))
    body = M.RigidBody(1.0, J)
    with pytest.raises(InvalidInputError, match=r"`omega` \(2,\), `v_cm` \(5,\)"):
        body.kinetic_energy(np.ones((2, 3)), v_cm=np.ones((5, 3)))
    with pytest.raises(InvalidInputError, match=r"`omega` \(2,\), `v_cm` \(5,\)"):
        body.angular_momentum(np.ones((2, 3)), v_cm=np.ones((5, 3)))


def test_rigid_body_wrong_types():
    from poinsot.mass import RigidBody

    with pytest.raises(InvalidTypeError, match="`inertia` to be array-like"):
        RigidBody(1.0, "diag(1, 2, 3)")
    with pytest.raises(InvalidInputError, match=r"`inertia` to have shape \(\.\.\., 3\)"):
        RigidBody(1.0, [1.0, 2.0])
    with pytest.raises(InvalidTypeError, match="`rotation`"):
        RigidBody(1.0, [1.0, 2.0, 2.5]).placed(rotation="x")
