"""The cases that version 2 of ``poinsot verify`` added (issue 44): their exact states
satisfy the equations of motion, checked independently of the code that made them.

Each exact motion is differentiated on its own grid (a sixth-order central
difference) and compared with Euler's equations and the kinematic equation written
out here in plain NumPy (``J_O w' + w x J_O w = M``, ``q' = q (0, w) / 2``, with the
case's torque: gravity, a constant body torque, a rotor's ``-w x h``, the
gravity-gradient torque); its first integrals are conserved. The two stored
32-digit references (Kovalevskaya, body torque) are checked against their integrals
or closed form and against poinsot's own DOP853 at rtol 1e-13.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poinsot.verify import CASES_VERSION, cases

NEW = (
    "top-waves",
    "sleeping-near-stable",
    "sleeping-near-unstable",
    "separatrix-minor",
    "separatrix-major",
    "kovalevskaya",
    "body-torque",
    "dual-spin",
    "pitch-libration",
)


def _matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = (q / np.linalg.norm(q, axis=-1, keepdims=True)).T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def _rhs(case, t, q, w):
    """Euler's equations and the kinematic equation, written out (body axes)."""
    i = case.inputs
    m, c = i["mass"], np.asarray(i["com"])
    jo = np.asarray(i["inertia"]) + m * (c @ c * np.eye(3) - np.outer(c, c))
    rmat = _matrix(q)
    torque = np.zeros_like(w)
    if i["fixed_point"]:  # the weight: m g gamma x c, gamma = R^T e_z
        torque += m * -i["gravity"][2] * np.cross(rmat[:, 2, :], c)
    if "body_torque" in i:
        torque += i["body_torque"]
    if "rotor_momentum" in i:
        torque -= np.cross(w, i["rotor_momentum"])
    if "mean_motion" in i:  # 3 n^2 c x J c, c the nadir (-sin nt, 0, cos nt) in body axes
        n = i["mean_motion"]
        nadir = np.stack([-np.sin(n * t), 0 * t, np.cos(n * t)], -1)
        cb = np.einsum("nji,nj->ni", rmat, nadir)
        torque += 3 * n * n * np.cross(cb, cb @ jo.T)
    dw = np.linalg.solve(jo, (torque - np.cross(w, w @ jo.T)).T).T
    q0, qv = q[:, :1], q[:, 1:]
    dq = 0.5 * np.concatenate([-(qv * w).sum(-1, keepdims=True), q0 * w + np.cross(qv, w)], -1)
    return dq, dw


def _derivative(y: np.ndarray, h: float) -> np.ndarray:
    """Sixth-order central difference on the interior samples (3 lost at each end)."""
    c = np.array([-1.0, 9.0, -45.0, 0.0, 45.0, -9.0, 1.0]) / (60.0 * h)
    n = y.shape[0]
    return sum(c[k] * y[k : n - 6 + k] for k in range(7))


# the largest relative residual of the difference vs the equations: 10-30x the observed
# one (in brackets), which is the difference's own error h^6 |y^(7)| / 140
RESIDUAL = {
    "top-waves": 5e-5,  # (3.9e-6) spin 60 rad/s on a 5 ms grid
    "sleeping-near-stable": 1e-7,  # (8.8e-9)
    "sleeping-near-unstable": 1e-7,  # (7.0e-9)
    "separatrix-minor": 3e-9,  # (2.9e-10)
    "separatrix-major": 3e-9,  # (2.9e-10)
    "kovalevskaya": 2e-7,  # (1.4e-8)
    "body-torque": 2e-10,  # (1.4e-11)
    "dual-spin": 5e-12,  # (5.1e-13)
    "pitch-libration": 5e-12,  # (3.8e-13)
}


def test_version_2_adds_nine_cases():
    names = [c.name for c in cases()]
    assert int(CASES_VERSION) >= 2 and len(names) >= 21 and set(NEW) <= set(names)
    assert cases("top-waves")[0].facts["motion_type"] == "waves"


@pytest.mark.parametrize("name", NEW)
def test_exact_states_satisfy_the_equations(name):
    case = cases(name)[0]
    ex = case.exact()
    t, q, w = ex["t"], ex["quat"], ex["omega"]
    h = float(t[1] - t[0])
    dq, dw = _rhs(case, t, q, w)
    fq, fw = _derivative(q, h), _derivative(w, h)
    res_w = np.max(np.abs(fw - dw[3:-3])) / np.max(np.abs(dw))
    res_q = np.max(np.abs(fq - dq[3:-3])) / np.max(np.abs(dq))
    assert max(res_w, res_q) < RESIDUAL[name], (res_w, res_q)
    assert np.max(np.abs(np.linalg.norm(q, axis=-1) - 1.0)) < 1e-14


def test_separatrix_pair_straddles_the_separatrix():
    minor, major = cases("separatrix-minor")[0], cases("separatrix-major")[0]
    assert minor.facts["regime"] == "minor" and major.facts["regime"] == "major"
    for c in (minor, major):
        assert c.model().complementary_parameter == pytest.approx(1e-6, rel=1e-12)
        i = np.diag(c.inputs["inertia"])
        ex = c.exact()
        k = np.einsum("nij,nj->ni", _matrix(ex["quat"]), ex["omega"] * i)
        energy = 0.5 * np.sum(i * ex["omega"] ** 2, axis=-1)
        assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-13
        assert np.max(np.linalg.norm(k - k[0], axis=-1)) / np.linalg.norm(k[0]) < 1e-13
        # two flips within the span, half a period apart
        from poinsot.verify.metrics import crossings

        flips = crossings(c.t, ex["omega"][:, 1], 0.0)
        assert flips.size == 3
        assert np.diff(flips) == pytest.approx(c.facts["flip_period_s"], abs=1e-4)


def test_sleeping_tops_near_the_critical_spin():
    from poinsot.dynamics import critical_spin

    stable, unstable = cases("sleeping-near-stable")[0], cases("sleeping-near-unstable")[0]
    wc = critical_spin(0.06, 0.02, 9.80665 * 0.1)
    for c, ratio in ((stable, 1.02), (unstable, 0.98)):
        assert c.facts["critical_spin_rad_per_s"] == pytest.approx(wc, rel=1e-15)
        assert c.facts["spin_over_critical"] == pytest.approx(ratio, rel=1e-15)
    assert stable.facts["nutation_bounds_rad"][1] < 0.006  # stays up
    assert unstable.facts["nutation_bounds_rad"][1] > 0.3  # falls away


def test_waves_precession_rate_keeps_its_sign():
    case = cases("top-waves")[0]
    ex = case.exact()
    rmat = _matrix(ex["quat"])
    # psi' = (K_z - C' w_3 cos theta) / (A_O sin^2 theta) > 0: from the states, the
    # rate of the axis e_3 about the vertical, (e3 x e3')_z / sin^2 theta
    axis = rmat[:, :, 2]
    rate = np.cross(axis, np.einsum("nij,nj->ni", rmat, np.cross(ex["omega"], [0, 0, 1])))
    psi_dot = rate[:, 2] / (1.0 - axis[:, 2] ** 2)
    assert np.min(psi_dot) > 0.4 and np.max(psi_dot) < 1.3  # observed 0.5 and 1.18


def _kovalevskaya_k(case, q, w):
    i = case.inputs
    c_axial = i["inertia"][2, 2] + i["mass"] * i["com"][0] ** 2
    nu = i["mass"] * -i["gravity"][2] * i["com"][0] / c_axial
    g = _matrix(q)[:, 2, :]
    p, r = w[:, 0], w[:, 1]
    return (p * p - r * r - nu * g[:, 0]) ** 2 + (2 * p * r - nu * g[:, 1]) ** 2


def test_kovalevskaya_reference_keeps_its_integrals_and_matches_dop853():
    from poinsot.dynamics import HeavyRigidBody
    from poinsot.verify.metrics import integrals

    case = cases("kovalevskaya")[0]
    jo = case.inertia_about_origin
    assert jo[0, 0] == jo[1, 1] == 2.0 * jo[2, 2] and case.inputs["com"][2] == 0.0
    ex = case.exact()
    k = _kovalevskaya_k(case, ex["quat"], ex["omega"])
    assert k[0] == pytest.approx(case.facts["kovalevskaya_K_rad4_per_s4"], rel=1e-15)
    assert np.max(np.abs(k / k[0] - 1.0)) < 1.5e-14  # observed 1.3e-15
    ints = integrals(case, ex)
    e, kz = ints["energy"], ints["momentum"][:, 2]
    assert np.max(np.abs(e / e[0] - 1.0)) < 1e-14  # observed 6.7e-16
    assert np.max(np.abs(kz / kz[0] - 1.0)) < 3e-14  # observed 2.2e-15
    i = case.inputs
    body = HeavyRigidBody(jo, i["mass"], i["com"], g=9.80665)
    tr = body.simulate(i["q0"], i["omega0"], case.t, method="dop853", rtol=1e-13, atol=1e-16)
    # observed 8.2e-13 rad/s and 1.1e-13
    assert np.max(np.abs(tr.omega - ex["omega"])) < 1e-11
    assert (
        np.max(np.abs(tr.quat * np.sign(tr.quat[:, :1] * ex["quat"][:, :1]) - ex["quat"])) < 1e-11
    )


def test_body_torque_reference_matches_the_closed_form_and_dop853():
    from poinsot.dynamics import simulate
    from poinsot.verify.groups import BodyTorque

    case = cases("body-torque")[0]
    ex = case.exact()
    assert np.max(np.abs(ex["omega"] - BodyTorque.omega(case, case.t))) < 3e-14  # obs. 2.5e-15
    i = case.inputs
    tr = simulate(i["inertia"], i["q0"], i["omega0"], case.t, torque=i["body_torque"],
                  method="dop853", rtol=1e-13, atol=1e-16)  # fmt: skip
    # observed 1.6e-13 rad/s and 1.4e-13
    assert np.max(np.abs(tr.omega - ex["omega"])) < 2e-12
    assert (
        np.max(np.abs(tr.quat * np.sign(tr.quat[:, :1] * ex["quat"][:, :1]) - ex["quat"])) < 2e-12
    )


def test_gyrostat_and_pitch_integrals():
    from poinsot.verify.metrics import integrals

    for name, keys in (("dual-spin", ("energy", "momentum")), ("pitch-libration", ("energy",))):
        case = cases(name)[0]
        ints = integrals(case, case.exact())
        assert sorted(ints) == sorted(keys)
        for key in keys:
            v = np.atleast_2d(ints[key].T).T
            assert np.max(np.linalg.norm(v - v[0], axis=-1)) / np.linalg.norm(v[0]) < 1e-12
    pitch = cases("pitch-libration")[0]
    q = pitch.exact()["quat"]
    assert np.max(np.abs(q[:, [1, 3]])) == 0.0  # planar: about the orbit normal
    assert pitch.facts["regime"] == "libration"
    assert pitch.facts["libration_period_s"] == pytest.approx(2 * math.pi / 1e-3 * 1.0663, rel=1e-3)
