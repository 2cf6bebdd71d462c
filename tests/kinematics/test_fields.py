"""Velocity/acceleration fields and composite motion (SPEC S6).

Truths used: brute-force differentiation (8th-order central differences with
the classical coefficients, written out below) of positions built from closed
forms ``r(t) = R0(t) + C(t) s(t)``, chained over 2 and 3 frames; textbook
cases (rolling wheel, bead on a rotating rod, gyroscope precession).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from poinsot.errors import InvalidInputError, InvalidTypeError
from poinsot.kinematics.fields import (
    AngularMotion,
    CompositeMotion,
    FrameMotion,
    acceleration_field,
    chain,
    compose_angular,
    point_motion,
    velocity_field,
)

# 8th-order central differences (Fornberg 1988, table 1), step H.
D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
D2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])
OFFS = np.arange(-4, 5)
H = 1e-2


def fd(f, t, order):
    """Central difference of f (returns arrays (..., k)) at times t (shape (T,))."""
    vals = np.stack([f(t + k * H) for k in OFFS], axis=0)
    w = D1 / H if order == 1 else D2 / H**2
    return np.tensordot(w, vals, axes=(0, 0))


def rot(e, f):
    """Rodrigues: rotation matrices (T, 3, 3) by angles f (T,) about unit axis e."""
    e = np.asarray(e, float) / np.linalg.norm(e)
    E = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
    f = np.asarray(f)[..., None, None]
    return np.eye(3) + np.sin(f) * E + (1 - np.cos(f)) * (E @ E)


def vee(m):
    return np.stack([m[..., 2, 1], m[..., 0, 2], m[..., 1, 0]], axis=-1)


class Frame:
    """Closed-form motion of frame k relative to frame k-1.

    Attitude ``C(t) = Rot(a, f(t)) Rot(b, g(t))`` (a precession-like angle and a
    spin about a carried axis), origin ``R(t) = p0 + p1 t + p2 sin(nu t)``.
    Derivatives by hand: ``w = f' a + g' Rot(a, f) b`` and its local derivative
    ``f'' a + g'' Rot(a, f) b + f' g' a x Rot(a, f) b``.
    """

    def __init__(self, rng):
        self.a = rng.normal(size=3)
        self.a /= np.linalg.norm(self.a)
        self.b = rng.normal(size=3)
        self.b /= np.linalg.norm(self.b)
        self.fc = rng.uniform(-1.5, 1.5, 3)  # f = c0 + c1 t + c2 sin(1.3 t)
        self.gc = rng.uniform(-1.5, 1.5, 3)
        self.p = rng.uniform(-1, 1, (3, 3))
        self.nu = rng.uniform(0.5, 2.0)

    @staticmethod
    def _ang(c, t, k):
        if k == 0:
            return c[0] + c[1] * t + c[2] * np.sin(1.3 * t)
        if k == 1:
            return c[1] + 1.3 * c[2] * np.cos(1.3 * t)
        return -(1.3**2) * c[2] * np.sin(1.3 * t)

    def C(self, t):
        return rot(self.a, self._ang(self.fc, t, 0)) @ rot(self.b, self._ang(self.gc, t, 0))

    def R(self, t, k=0):
        t = np.asarray(t)[..., None]
        p0, p1, p2 = self.p
        if k == 0:
            return p0 + p1 * t + p2 * np.sin(self.nu * t)
        if k == 1:
            return p1 + self.nu * p2 * np.cos(self.nu * t)
        return -(self.nu**2) * p2 * np.sin(self.nu * t)

    def omega(self, t):
        ab = rot(self.a, self._ang(self.fc, t, 0)) @ self.b
        return (
            self._ang(self.fc, t, 1)[..., None] * self.a + self._ang(self.gc, t, 1)[..., None] * ab
        )

    def eps(self, t):
        ab = rot(self.a, self._ang(self.fc, t, 0)) @ self.b
        f1, g1 = self._ang(self.fc, t, 1), self._ang(self.gc, t, 1)
        return (
            self._ang(self.fc, t, 2)[..., None] * self.a
            + self._ang(self.gc, t, 2)[..., None] * ab
            + (f1 * g1)[..., None] * np.cross(self.a, ab)
        )


def build(frames, t):
    """Attitudes Q_k (fixed <- frame k) and origins O_k of a chain at times t."""
    Q = np.broadcast_to(np.eye(3), (*np.shape(t), 3, 3))
    O = np.zeros((*np.shape(t), 3))
    Qs, Os = [Q], [O]
    for fr in frames:
        O = O + np.einsum("...ij,...j->...i", Q, fr.R(t))
        Q = Q @ fr.C(t)
        Qs.append(Q)
        Os.append(O)
    return Qs, Os


def analytic_chain(frames, t):
    """FrameMotion list and offsets of a chain, from the hand derivatives."""
    Qs, _ = build(frames, t)
    motions, offsets = [], []

    def q(k, v):
        return np.einsum("...ij,...j->...i", Qs[k], v)

    for k, fr in enumerate(frames):
        motions.append(
            FrameMotion(q(k, fr.R(t, 1)), q(k, fr.R(t, 2)), q(k, fr.omega(t)), q(k, fr.eps(t)))
        )
        if k > 0:
            offsets.append(q(k, fr.R(t)))
    return motions, offsets, Qs


def point_local(t, k=0):
    """The point's path in the innermost frame: s(t) = (cos 2t, t^2/3, sin t)."""
    t = np.asarray(t)
    if k == 0:
        return np.stack([np.cos(2 * t), t**2 / 3, np.sin(t)], -1)
    if k == 1:
        return np.stack([-2 * np.sin(2 * t), 2 * t / 3, np.cos(t)], -1)
    return np.stack([-4 * np.cos(2 * t), np.full_like(t, 2 / 3), -np.sin(t)], -1)


@pytest.mark.parametrize("nframes", [1, 2, 3])
def test_chain_point_motion_matches_brute_force(nframes):
    """V and W of a point moving in the last frame of a chain equal the
    derivatives of its composed position r = O_n + Q_n s (finite differences)."""
    rng = np.random.default_rng(10 + nframes)
    frames = [Frame(rng) for _ in range(nframes)]
    t = np.linspace(-1.0, 2.0, 7)

    def position(tt):
        Qs, Os = build(frames, tt)
        return Os[-1] + np.einsum("...ij,...j->...i", Qs[-1], point_local(tt))

    motions, offsets, Qs = analytic_chain(frames, t)
    frame = chain(motions, offsets)
    Qn = Qs[-1]
    m = point_motion(
        frame,
        np.einsum("...ij,...j->...i", Qn, point_local(t)),
        np.einsum("...ij,...j->...i", Qn, point_local(t, 1)),
        np.einsum("...ij,...j->...i", Qn, point_local(t, 2)),
    )
    v_fd, a_fd = fd(position, t, 1), fd(position, t, 2)
    scale_v = np.abs(v_fd).max()
    scale_a = np.abs(a_fd).max()
    np.testing.assert_allclose(m.velocity, v_fd, atol=1e-10 * scale_v)
    np.testing.assert_allclose(m.acceleration, a_fd, atol=1e-8 * scale_a)
    # the named terms add up
    np.testing.assert_allclose(
        m.acceleration,
        m.origin_acceleration
        + m.rotational_acceleration
        + m.centripetal_acceleration
        + m.coriolis_acceleration
        + m.relative_acceleration,
        atol=1e-13 * scale_a,
    )
    np.testing.assert_allclose(m.velocity, m.transport_velocity + m.relative_velocity)


@pytest.mark.parametrize("nframes", [2, 3])
def test_chain_angular_and_origin_motion_match_brute_force(nframes):
    """The composed frame's w = vee(Q' Q^T), eps = w' and origin V, W agree
    with finite differences of the composed attitude Q_n and origin O_n."""
    rng = np.random.default_rng(20 + nframes)
    frames = [Frame(rng) for _ in range(nframes)]
    t = np.linspace(0.0, 1.5, 5)
    motions, offsets, _ = analytic_chain(frames, t)
    total = chain(motions, offsets)

    def attitude(tt):
        return build(frames, tt)[0][-1]

    def omega_fd(tt):
        return vee(np.einsum("...ij,...kj->...ik", fd(attitude, tt, 1), attitude(tt)))

    def origin(tt):
        return build(frames, tt)[1][-1]

    np.testing.assert_allclose(total.omega, omega_fd(t), atol=1e-10)
    np.testing.assert_allclose(total.eps, fd(omega_fd, t, 1), atol=1e-7)
    np.testing.assert_allclose(total.origin_velocity, fd(origin, t, 1), atol=1e-10)
    np.testing.assert_allclose(total.origin_acceleration, fd(origin, t, 2), atol=1e-8)


def test_compose_angular_matches_two_frame_brute_force():
    """eps = eps_e + eps_r + w_e x w_r (SPEC S6) against d/dt of vee(Q' Q^T)."""
    rng = np.random.default_rng(3)
    fe, fr = Frame(rng), Frame(rng)
    t = np.linspace(0, 2, 6)
    Ce = fe.C(t)

    def q(v):
        return np.einsum("...ij,...j->...i", Ce, v)

    am = compose_angular(fe.omega(t), fe.eps(t), q(fr.omega(t)), q(fr.eps(t)))
    assert isinstance(am, AngularMotion)

    def omega_fd(tt):
        Q = fe.C(tt) @ fr.C(tt)
        Qd = fd(lambda s: fe.C(s) @ fr.C(s), tt, 1)
        return vee(np.einsum("...ij,...kj->...ik", Qd, Q))

    w, eps = am
    np.testing.assert_allclose(w, omega_fd(t), atol=1e-10)
    np.testing.assert_allclose(eps, fd(omega_fd, t, 1), atol=1e-7)
    # without the w_e x w_r term the result would be wrong (the test can fail)
    assert np.abs(fe.eps(t) + q(fr.eps(t)) - eps).max() > 1e-2


def test_compose_angular_gyroscope_textbook():
    """Spin s about a horizontal axis that precesses at p about z: eps = p x s."""
    w, eps = compose_angular([0, 0, 0.5], [0, 0, 0], [0, 30.0, 0], [0, 0, 0])
    np.testing.assert_allclose(w, [0, 30, 0.5])
    np.testing.assert_allclose(eps, [-15.0, 0, 0])


def test_velocity_and_acceleration_fields_rigid_body_brute_force():
    """Euler and Rivals formulas against finite differences of
    r(t) = O(t) + C(t) rho_b for body-fixed points."""
    rng = np.random.default_rng(5)
    fr = Frame(rng)
    t = np.linspace(0, 1, 4)[:, None]  # (T, 1) times x (1, P) points
    rho_b = rng.normal(size=(6, 3))

    def pos(tt):
        return fr.R(tt) + np.einsum("...ij,...j->...i", fr.C(tt), rho_b)

    r = pos(t)
    O = fr.R(t)
    v = velocity_field(fr.R(t, 1), fr.omega(t), r, pole=O)
    a = acceleration_field(fr.R(t, 2), fr.omega(t), fr.eps(t), r, pole=O)
    assert v.shape == a.shape == (4, 6, 3)
    np.testing.assert_allclose(v, fd(pos, t, 1), atol=1e-10)
    np.testing.assert_allclose(a, fd(pos, t, 2), atol=1e-8)
    # rho measured from the pole: the default pole is the coordinate origin
    np.testing.assert_allclose(velocity_field(fr.R(t, 1), fr.omega(t), r - O), v, atol=1e-14)


def test_rolling_wheel_textbook():
    """Wheel of radius R rolling at speed u: contact point at rest with
    acceleration u^2/R upwards; top moves at 2u."""
    R, u = 0.4, 3.0
    w = [0, 0, -u / R]
    pts = [[0, -R, 0], [0, R, 0], [R, 0, 0]]
    v = velocity_field([u, 0, 0], w, pts)
    np.testing.assert_allclose(v, [[0, 0, 0], [2 * u, 0, 0], [u, -u, 0]], atol=1e-14)
    a = acceleration_field([0, 0, 0], w, [0, 0, 0], pts)
    np.testing.assert_allclose(a[0], [0, u**2 / R, 0], atol=1e-13)


vec = arrays(np.float64, 3, elements=st.floats(-10, 10))


@settings(max_examples=50, deadline=None)
@given(vec, vec, vec, vec)
def test_velocity_field_projections_equal(v0, w, A, B):
    """Rigidity: velocities of two points have equal projections on AB."""
    vA, vB = velocity_field(v0, w, np.stack([A, B]))
    d = A - B
    scale = (np.abs(v0).max() + np.abs(w).max() * 20 + 1) * (np.abs(d).max() + 1)
    assert abs((vA - vB) @ d) <= 1e-12 * scale


def test_bead_on_rotating_rod_textbook():
    """Bead sliding at u along a rod turning at w about z, at distance x:
    Coriolis 2 w u (perpendicular), centripetal -w^2 x."""
    w, u, x = 2.0, 1.5, 0.7
    m = point_motion(FrameMotion(omega=[0, 0, w]), [x, 0, 0], [u, 0, 0])
    assert isinstance(m, CompositeMotion)
    np.testing.assert_allclose(m.coriolis_acceleration, [0, 2 * w * u, 0])
    np.testing.assert_allclose(m.centripetal_acceleration, [-(w**2) * x, 0, 0])
    np.testing.assert_allclose(m.transport_velocity, [0, w * x, 0])
    np.testing.assert_allclose(m.acceleration, [-(w**2) * x, 2 * w * u, 0])
    d = m.as_dict()
    assert set(d) >= {"coriolis_acceleration", "transport_acceleration", "relative_velocity"}


def test_frame_motion_immutable_and_broadcast():
    fm = FrameMotion(origin_velocity=np.zeros((5, 3)), omega=[0, 0, 1])
    assert fm.shape == (5,)
    assert fm.omega.shape == (5, 3)
    with pytest.raises(ValueError, match="read-only"):
        fm.omega[0, 0] = 1.0
    with pytest.raises(AttributeError):
        fm.omega = np.zeros(3)
    m = point_motion(fm, np.ones((2, 1, 3)))
    assert m.acceleration.shape == (2, 5, 3)
    np.testing.assert_allclose(fm.acceleration_at([1, 0, 0]), np.tile([-1.0, 0, 0], (5, 1)))


def test_frame_compose_carousel():
    """Cup on a carousel: w adds, eps = w_e x w_r, origin on a circle."""
    car = FrameMotion(omega=[0, 0, 1])
    cup = car.compose(FrameMotion(omega=[3, 0, 0]), offset=[2, 0, 0])
    np.testing.assert_allclose(cup.origin_velocity, [0, 2, 0])
    np.testing.assert_allclose(cup.origin_acceleration, [-2, 0, 0])
    np.testing.assert_allclose(cup.omega, [3, 0, 1])
    np.testing.assert_allclose(cup.eps, [0, 3, 0])


# ---------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------


def test_errors_shapes_and_values():
    with pytest.raises(InvalidInputError, match=r"Expected `omega` to have shape \(\.\.\., 3\)"):
        velocity_field([0, 0, 0], [0, 1], [1, 0, 0])
    with pytest.raises(InvalidInputError, match="`point` to contain only finite"):
        velocity_field([0, 0, 0], [0, 0, 1], [np.nan, 0, 0])
    with pytest.raises(InvalidInputError, match="shapes of .* to broadcast"):
        acceleration_field(np.zeros((4, 3)), [0, 0, 1], [0, 0, 0], np.zeros((5, 3)))
    with pytest.raises(InvalidInputError, match="`pole`"):
        velocity_field([0, 0, 0], [0, 0, 1], [1, 0, 0], pole=[0, 0])
    with pytest.raises(InvalidTypeError, match="`eps_r`"):
        compose_angular([0, 0, 1], [0, 0, 0], [1, 0, 0], "zero")
    with pytest.raises(InvalidInputError, match="`omega` to have shape"):
        FrameMotion(omega=[1, 2])
    with pytest.raises(InvalidInputError, match="shapes of .* to broadcast"):
        FrameMotion(omega=np.zeros((2, 3)), eps=np.zeros((3, 3)))


def test_errors_composite():
    fm = FrameMotion(omega=[0, 0, 1])
    with pytest.raises(InvalidTypeError, match="`frame` to be a FrameMotion"):
        point_motion([0, 0, 1], [1, 0, 0])
    with pytest.raises(InvalidInputError, match="`v_rel` to have shape"):
        point_motion(fm, [1, 0, 0], [1, 0])
    with pytest.raises(InvalidTypeError, match="`inner` to be a FrameMotion"):
        fm.compose([0, 0, 1], [0, 0, 0])
    with pytest.raises(InvalidInputError, match="`offset` to contain only finite"):
        fm.compose(fm, [np.inf, 0, 0])
    with pytest.raises(InvalidInputError, match="at least one FrameMotion"):
        chain([], [])
    with pytest.raises(InvalidInputError, match="`offsets` to have len"):
        chain([fm, fm], [])
    with pytest.raises(InvalidTypeError, match=r"`motions\[1\]` to be a FrameMotion"):
        chain([fm, 3], [[0, 0, 0]])
    with pytest.raises(InvalidInputError, match="`offset`"):
        fm.velocity_at([1, 2])


def test_plot_acceleration_terms_smoke(tmp_path):
    """The plotting helper draws one line per contribution (Agg backend)."""
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    from poinsot.plotting.motion import plot_acceleration_terms

    t = np.linspace(0, 1, 20)
    m = point_motion(
        FrameMotion(omega=[0, 0, 2]), np.stack([np.cos(t), np.sin(t), 0 * t], -1), [0, 1, 0]
    )
    ax = plot_acceleration_terms(t, m)
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert len(labels) == 4
    np.testing.assert_allclose(
        ax.get_lines()[2].get_ydata(), np.linalg.norm(m.coriolis_acceleration, axis=-1)
    )
    ax2 = plot_acceleration_terms(t, {"a": np.ones((20, 3))}, component=2, ax=ax)
    assert ax2 is ax
    ax.figure.savefig(tmp_path / "x.png")
    ax3 = plot_acceleration_terms(t, m, component=m.velocity)  # projection on a moving vector
    np.testing.assert_allclose(
        ax3.get_lines()[3].get_ydata(), np.einsum("ni,ni->n", m.acceleration, m.velocity)
    )
    with pytest.raises(InvalidInputError, match="`component`"):
        plot_acceleration_terms(t, m, component="w")
    with pytest.raises(InvalidInputError, match=r"`component`.*\(20, 3\)"):
        plot_acceleration_terms(t, m, component=[1, 0])
    with pytest.raises(InvalidInputError, match="`component`"):
        plot_acceleration_terms(t, m, component=True)
    with pytest.raises(InvalidInputError, match=r"`terms\['a'\]` to have shape \(20, 3\)"):
        plot_acceleration_terms(t, {"a": np.ones((19, 3))})
    with pytest.raises(InvalidInputError, match="`terms` to be a CompositeMotion"):
        plot_acceleration_terms(t, np.ones((20, 3)))
    with pytest.raises(InvalidInputError, match="`terms` to hold at least one"):
        plot_acceleration_terms(t, {})
    import matplotlib.pyplot as plt

    plt.close("all")


def test_docs_disc_example(tmp_path):
    """The docs' worked example runs, matches brute force, and its Coriolis
    term is the hand result 2 Omega R omega_s sin(phi) e_r."""
    import runpy
    from pathlib import Path

    pytest.importorskip("matplotlib")
    path = Path(__file__).resolve().parents[2] / "docs" / "examples" / "disc_acceleration.py"
    ns = runpy.run_path(str(path))
    err = ns["main"](tmp_path / "disc.png")
    assert (tmp_path / "disc.png").stat().st_size > 10_000
    assert err < 1e-4
    t = np.linspace(0, 2, 50)
    m = ns["disc_motion"](t)
    e_r = ns["basis"](t)[0]
    omega = ns["OMEGA0"] + ns["ALPHA"] * t
    expected = (2 * omega * ns["R"] * ns["OMEGA_S"] * np.sin(ns["OMEGA_S"] * t))[:, None] * e_r
    np.testing.assert_allclose(m.coriolis_acceleration, expected, atol=1e-12)
