"""Bad-input and singularity regressions for ``poinsot.dynamics``, ``poinsot.plotting``
and the ``poinsot`` command (audit)."""

import numpy as np
import pytest

import poinsot.dynamics as D
from poinsot import InvalidInputError, InvalidTypeError, SingularityWarning
from poinsot.cli import main

J = np.diag([1.0, 2.0, 3.0])
T = np.linspace(0.0, 1.0, 11)
W0 = [0.1, 1.0, 0.1]


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"rtol": -1.0}, InvalidInputError, "`rtol` to be a positive scalar"),
        ({"rtol": np.ones(2)}, InvalidInputError, "`rtol` to be a positive scalar"),
        ({"atol": "x"}, InvalidTypeError, "`atol` to be array-like of numbers"),
        ({"atol": -1e-9}, InvalidInputError, "`atol` to be a non-negative scalar"),
        ({"solver": "bogus"}, InvalidInputError, "`solver` to be one of"),
        ({"solver": "rk4"}, InvalidInputError, "`solver` to be one of"),
    ],
)
def test_simulate_adaptive_options(kwargs, exc, match):
    # these reached solve_ivp (a raw UFuncTypeError, or a negative rtol silently floored)
    with pytest.raises(exc, match=match):
        D.simulate(J, [1.0, 0, 0, 0], W0, T, method="adaptive", **kwargs)


@pytest.mark.parametrize("n", [None, "x", 1, 0, -5, 2.5, True])
def test_free_body_curve_samples(n):
    body = D.FreeRigidBody([1.0, 2.0, 3.0], omega0=W0)
    with pytest.raises(InvalidInputError, match="`n` to be an integer >= 2"):
        body.maccullagh(n)
    with pytest.raises(InvalidInputError, match="`n` to be an integer >= 2"):
        body.poinsot(n=n)


def test_free_body_poinsot_empty_t():
    body = D.FreeRigidBody([1.0, 2.0, 3.0], omega0=W0)
    with pytest.raises(InvalidInputError, match=r"`t` to have shape \(n,\) with n >= 1"):
        body.poinsot(np.empty(0))


def test_separatrix_stays_accurate():
    """On the separatrix (K^2 = 2 B T: w1 = sqrt(3) w3 for (1, 2, 3)) the exact
    solution warns and still matches an independent DOP853 integration."""
    w0 = [np.sqrt(3.0), 1e-8, 1.0]
    with pytest.warns(SingularityWarning, match="separatrix"):
        body = D.FreeRigidBody([1.0, 2.0, 3.0], omega0=w0)
    t = np.linspace(0.0, 6.0, 13)
    ref = D.simulate(J, [1.0, 0, 0, 0], w0, t, method="adaptive", rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(body.omega(t), ref.omega, atol=1e-10)
    dots = np.abs(np.einsum("ij,ij->i", body.rotation(t).as_quat(), ref.quat))
    np.testing.assert_allclose(dots, 1.0, atol=1e-10)


def test_plot_functions_bad_arguments():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from poinsot.plotting import plot_maccullagh, plot_omega, plot_poinsot

    body = D.FreeRigidBody([1.0, 2.0, 3.0], omega0=W0)
    with pytest.raises(InvalidInputError, match="`t` to be strictly increasing"):
        plot_omega(body, T[::-1])
    with pytest.raises(InvalidInputError, match="`n` to be an integer >= 2"):
        plot_maccullagh(body, n=3.0)
    with pytest.raises(InvalidInputError, match="`t` to have shape"):
        plot_poinsot(body, np.empty(0))
    plt.close("all")


def test_write_report_bad_path(tmp_path):
    from poinsot.plotting import write_report

    tr = D.simulate(J, [1.0, 0, 0, 0], W0, T)
    with pytest.raises(InvalidTypeError, match="`path` to be a str or os.PathLike"):
        write_report(None, trajectory=tr)
    with pytest.raises(InvalidInputError, match="`path` to name a file, got the directory"):
        write_report(tmp_path, trajectory=tr)
    assert list(tmp_path.iterdir()) == []  # no temporary file left behind


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        # used to leak a RuntimeWarning and blame `inertia`
        (["inertia", "box", "--mass", "1", "--dims", "1", "1e200", "3"], "representable inertia"),
    ],
)
def test_cli_overflow_exit_code_2(argv, match, capsys):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "Traceback" not in captured.err and "RuntimeWarning" not in captured.err
    assert match in captured.err


def test_cli_convert_guards_non_finite_results(monkeypatch, capsys):
    """A conversion that overflows in the core (it did for MRP/Gibbs 1e200 before the
    core was fixed) ends with exit code 2 and a message, never "nan" on stdout."""
    import poinsot.cli.convert as cli_convert

    class Broken:
        def as_quat(self, **kwargs):
            return np.array([np.nan, 0.0, 0.0, 0.0])

    monkeypatch.setattr(cli_convert, "_from", lambda *a: Broken())
    assert main(["convert", "mrp", "quat", "1e200", "0", "0"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "out of the range" in captured.err

    monkeypatch.setattr(cli_convert, "_from", lambda *a: __import__("poinsot").Rotation.identity())
    monkeypatch.setattr(cli_convert, "_to", lambda *a: np.array([np.nan, 0.0, 0.0]))
    assert main(["convert", "mrp", "rotvec", "0", "0", "0"]) == 2
    assert "overflowed" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"method": 3}, InvalidTypeError, "`method` to be one of .* got int"),
        ({"method": "exact"}, InvalidInputError, "`method` to be one of"),
        ({"order": 4.0}, InvalidTypeError, "`order` to be an integer, got float"),
        ({"order": "4"}, InvalidTypeError, "`order` to be an integer, got str"),
        ({"order": True}, InvalidTypeError, "`order` to be an integer, got bool"),
        ({"order": 3}, InvalidInputError, "`order` to be one of 2, 4, 6, got 3"),
        ({"torque": "gravity"}, InvalidTypeError, "`torque`"),
        ({"torque": {"x": 1.0}}, InvalidTypeError, "`torque`"),
        ({"max_step": "0.1"}, InvalidTypeError, "`max_step`"),
    ],
)
def test_simulate_wrong_types_are_type_errors(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        D.simulate(J, [1.0, 0, 0, 0], W0, T, **kwargs)


def test_invariants_and_torques_wrong_types():
    with pytest.raises(InvalidTypeError, match="`rotation`"):
        D.invariants([1.0, 2.0, 3.0], "identity", W0)
    with pytest.raises(InvalidTypeError, match="`mass`"):
        D.GravityTorque("heavy", [0.0, 0.0, 1.0])
    with pytest.raises(InvalidTypeError, match="`frame` to be one of"):
        D.CallableTorque(lambda t, q, w: w, frame=None)
    with pytest.raises(InvalidTypeError, match="`inertia`"):
        D.kinetic_energy(None, W0)


def test_apsides_index_like_the_pair_they_unpack_to():
    """Issue 38: ``CentralOrbit.apsides[0]`` raised TypeError."""
    from poinsot.dynamics import CentralOrbit

    orbit = CentralOrbit(lambda r: -1.0 / r, energy=-0.3, angular_momentum=1.0)
    r_min, r_max = orbit.apsides
    assert orbit.apsides[0] == r_min and orbit.apsides[1] == r_max and len(orbit.apsides) == 2
    # Kepler, mu = m = 1: r = p / (1 +- e), p = L^2, e = sqrt(1 + 2 E L^2)
    e = (1.0 + 2.0 * -0.3) ** 0.5
    assert abs(r_min - 1.0 / (1.0 + e)) < 1e-12 and abs(r_max - 1.0 / (1.0 - e)) < 1e-12
