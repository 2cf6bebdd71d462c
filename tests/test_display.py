"""Rich display in Jupyter (issue 21): ``_repr_html_``, short ``__repr__``, ``_repr_latex_``.

Independent truths: the numbers shown against SciPy (axis-angle and Euler angles),
NumPy (principal moments), the objects' own documented properties; the HTML parses;
strings are escaped; a batch shows only its first rows; the LaTeX is SymPy's.
"""

from __future__ import annotations

import html.parser
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot

import poinsot
from poinsot.dynamics import CentralOrbit, FreeRigidBody, LagrangeTop, kepler
from poinsot.mass import RigidBody


class _Checker(html.parser.HTMLParser):
    VOID = {"br", "rect", "line", "path", "meta", "img"}

    def __init__(self):
        super().__init__()
        self.stack, self.text, self.tags = [], [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.append(tag)

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        assert self.stack and self.stack[-1] == tag, (tag, self.stack[-3:])
        self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def _parse(h: str) -> _Checker:
    c = _Checker()
    c.feed(h)
    c.close()
    assert not c.stack, c.stack  # every element closed
    assert "<script" not in h and "http" not in h.replace("http://www.w3.org/2000/svg", "")
    assert "display failed" not in h  # the normal path, not the fallback
    return c


def _numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", text)]


def _row(c: _Checker, label: str) -> str:
    text = "\n".join(c.text)
    i = text.index(label)
    return text[i + len(label) : i + len(label) + 200]


def test_rotation_html_matches_scipy():
    rv = np.array([0.3, -0.2, 0.5])
    r = poinsot.Rotation.from_rotvec(rv)
    c = _parse(r._repr_html_())
    sci = SciRot.from_rotvec(rv)
    angle = _numbers(_row(c, "angle"))[0]
    assert angle == pytest.approx(np.degrees(np.linalg.norm(rv)), rel=1e-5)
    eul = _numbers(_row(c, "Euler ZYX"))[:3]
    assert eul == pytest.approx(sci.as_euler("ZYX", degrees=True), rel=1e-5)
    q = _numbers(_row(c, "quaternion (w, x, y, z)"))[:4]
    assert q == pytest.approx(np.roll(sci.as_quat(), 1), rel=1e-5)
    axis = _numbers(_row(c, "axis"))[:3]
    assert axis == pytest.approx(rv / np.linalg.norm(rv), rel=1e-5)
    assert "deg" in "".join(c.text) and "scalar-first" in "".join(c.text)


def test_rotation_batch_shows_first_rows_and_short_repr():
    rv = np.random.default_rng(1).normal(size=(100_000, 3))
    r = poinsot.Rotation.from_rotvec(rv)
    h = r._repr_html_()
    c = _parse(h)
    assert h.count("<tr>") < 12 and "first 5 of 100000" in "".join(c.text)
    assert len(h) < 10_000
    text = repr(r)
    assert "\n" not in text and len(text) < 120 and "(100000,)" in text
    assert repr(poinsot.Rotation.from_rotvec(rv[0])).startswith("Rotation(quat=[")


def test_rigid_body_principal_moments():
    j = np.array([[2.0, 0.3, 0.0], [0.3, 1.5, 0.1], [0.0, 0.1, 1.0]])
    body = RigidBody(3.0, j, [0.1, 0.0, 0.2])
    c = _parse(body._repr_html_())
    moments = _numbers(_row(c, "principal moments"))[:3]
    assert sorted(moments) == pytest.approx(np.linalg.eigvalsh(j), rel=1e-5)
    assert "kg m^2" in "".join(c.text) and "kg" in _row(c, "mass")
    assert "\n" not in repr(body) and "mass=3" in repr(body)


def test_exact_solutions_show_their_integrals():
    body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 1.0, 0.1])
    c = _parse(body._repr_html_())
    assert _numbers(_row(c, "period of omega"))[0] == pytest.approx(body.period, rel=1e-5)
    assert _numbers(_row(c, "energy T"))[0] == pytest.approx(body.energy, rel=1e-5)
    assert body.regime in "".join(c.text)
    top = LagrangeTop(2.0, 1.0, 4.0, theta=0.6, spin=6.0, precession_rate=-0.8)
    c = _parse(top._repr_html_())
    assert "loops" in "".join(c.text)
    bounds = _numbers(_row(c, "nutation theta"))[:2]
    assert bounds == pytest.approx(np.degrees(top.nutation_bounds), rel=1e-5)
    assert _numbers(_row(c, "nutation period"))[0] == pytest.approx(top.nutation_period, rel=1e-5)
    orbit = CentralOrbit.from_state(kepler(1.0), [1.0, 0, 0], [0, 1.2, 0])
    c = _parse(orbit._repr_html_())
    assert _numbers(_row(c, "radial period"))[0] == pytest.approx(orbit.radial_period, rel=1e-5)
    assert _numbers(_row(c, "conic e, a"))[:2] == pytest.approx(
        [orbit.conic.e, orbit.conic.a], rel=1e-5
    )
    batch = FreeRigidBody([[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]], omega0=[0.3, 0.2, 1.0])
    c = _parse(batch._repr_html_())
    assert "symmetric" in "".join(c.text)


def test_every_result_type_renders(tmp_path):
    from test_results_contract import CASES

    for name, make in CASES:
        res = make()
        h = res._repr_html_()
        c = _parse(h)
        text = "".join(c.text)
        assert res.method in text, name
        assert str(res.t.size) in text, name
        assert "<svg" in h and "<path" in h, name  # the small chart
        n = max(len(re.findall(r" L", p)) for p in re.findall(r"d='M[^']*'", h))
        assert n <= 240, name  # decimated
        # a drift is shown only for a quantity the result says its motion conserves
        from poinsot.trajectory import CONSERVED_LABELS

        for key in getattr(res, "conserved_drifts", dict)():
            assert f"{CONSERVED_LABELS[key]} drift (relative)" in text, name
        if "drift" in text:
            assert "docs/theory.md" in text, name


def test_strings_are_escaped_and_display_never_raises():
    t = np.linspace(0, 1, 5)
    tr = poinsot.Trajectory(t, poinsot.Rotation.from_rotvec(np.outer(t, [0, 0, 1.0])),
                            np.tile([0, 0, 1.0], (5, 1)), "<script>alert(1)</script>")  # fmt: skip
    h = tr._repr_html_()
    assert "<script>" not in h and "&lt;script&gt;" in h

    class Broken(poinsot.Rotation):
        def as_rotvec(self):
            raise RuntimeError("boom")

    h = Broken.from_rotvec([0.1, 0, 0])._repr_html_()
    assert h.startswith("<pre>") and "display failed" in h


def test_lagrange_system_latex_is_sympys():
    sympy = pytest.importorskip("sympy", reason="symbolic extra")
    from sympy.physics.mechanics import dynamicsymbols

    from poinsot.symbolic import LagrangeSystem

    th = dynamicsymbols("theta")
    m, l_, g = sympy.symbols("m l g", positive=True)
    pend = LagrangeSystem([th], m * l_**2 * th.diff() ** 2 / 2, -m * g * l_ * sympy.cos(th))
    tex = pend._repr_latex_()
    eq = pend.printable(pend.equations()[0], latex=True)
    assert tex.startswith("$\\begin{aligned}") and tex.endswith("\\end{aligned}$")
    assert sympy.latex(eq.lhs) in tex and sympy.latex(eq.rhs) in tex
    assert "\\ddot{\\theta}" in tex and "\\sin" in tex


def test_show_draws_every_result_with_the_report_viewer():
    from poinsot.plotting._report_page import viewer_js  # the report's own script
    from test_results_contract import CASES

    for name, make in CASES:
        res = make()
        v = res.show()
        assert viewer_js() in v.html, name  # the same viewer
        frame = v._repr_html_()
        assert (
            frame.startswith('<iframe class="poinsot-viewer" srcdoc="')
            and 'sandbox="allow-scripts"' in frame
        )
        assert "<script src=" not in v.html and "https://" not in v.html, name
        if type(res).__name__ == "CoordinateTrajectory":
            assert "theta1" in v.html  # the coordinates charted


def test_show_and_explore_bad_input(monkeypatch):
    from poinsot.errors import InvalidInputError, InvalidTypeError, PoinsotError
    from poinsot.plotting import explore, show

    with pytest.raises(InvalidTypeError, match="result"):
        show(np.zeros(3))
    t = np.linspace(0, 1, 5)
    batch = poinsot.Trajectory(t, poinsot.Rotation.from_rotvec(np.zeros((5, 2, 3))),
                               np.zeros((5, 2, 3)), "x")  # fmt: skip
    with pytest.raises(InvalidInputError, match="one body"):
        show(batch)
    with pytest.raises(InvalidInputError, match="preset"):
        explore("top")
    with pytest.raises(InvalidInputError, match="slider names"):
        explore("kepler", spin=3.0)
    with pytest.raises(InvalidInputError, match=r"`e` in \[0.0, 0.97\]"):
        explore("kepler", e=1.5)
    monkeypatch.setitem(__import__("sys").modules, "ipywidgets", None)
    with pytest.raises(PoinsotError, match=r"poinsot\[notebook\]"):
        explore("kepler")


@pytest.mark.parametrize(
    "preset", ["racket", "symmetric-top", "lagrange-top", "foucault", "kepler"]
)
def test_explore_recomputes_from_the_exact_solution(preset):
    pytest.importorskip("ipywidgets", reason="explore() needs ipywidgets (poinsot[notebook])")
    from poinsot.plotting import explore

    ex = explore(preset)
    first = ex.view.value
    assert "<iframe" in first and "recomputed in" in ex.status.value
    name, s = next(iter(ex.sliders.items()))
    s.value = min(s.max, s.value + 10 * s.step)
    assert ex.view.value != first  # redrawn


def _drifts(c: _Checker) -> dict[str, float]:
    """``label -> value`` of the drift rows of a result's display."""
    lines = c.text
    out = {}
    for i, line in enumerate(lines):
        if line.endswith("drift (relative)"):
            out[line] = _numbers(lines[i + 1])[0]
    return out


def test_heavy_top_display_shows_t_plus_v_drift():
    """issue 38: the display showed the kinetic energy's change (1e-3) as "energy drift"
    while T + V drifts 1e-12: it now shows T + V and K_z, recomputed here from the state."""
    from poinsot.dynamics import HeavyRigidBody

    m, g, c = 1.5, 9.81, np.array([0.0, 0.0, 0.4])
    inertia = np.array([2.0, 2.0, 1.0])
    top = HeavyRigidBody(inertia, m, c, g=g)
    q0 = poinsot.Rotation.from_euler("x", 0.5).as_quat()
    tr = top.simulate(q0, [0.5, 0.0, 20.0], np.linspace(0, 10, 501), rtol=1e-10)
    w = np.asarray(tr.omega)
    t_kin = 0.5 * np.sum(inertia * w**2, axis=-1)
    z_c = tr.rotation.apply(c)[:, 2]  # height of the centre of mass above the pin (m)
    e = t_kin + m * g * z_c
    rel_e = np.max(np.abs(e - e[0])) / max(abs(e[0]), np.max(t_kin))
    k = tr.rotation.apply(inertia * w)  # K in space axes
    rel_kz = np.max(np.abs(k[:, 2] - k[0, 2])) / np.linalg.norm(k[0])
    shown = _drifts(_parse(tr._repr_html_()))
    assert set(shown) == {"energy T + V drift (relative)", "K_z drift (relative)"}
    assert shown["energy T + V drift (relative)"] == pytest.approx(rel_e, rel=2e-3)
    assert shown["K_z drift (relative)"] == pytest.approx(rel_kz, rel=2e-3)
    assert rel_e < 1e-9  # and it is small, unlike the kinetic energy's change
    assert np.ptp(t_kin) / t_kin[0] > 1e-4


def test_torqued_body_display_claims_no_conservation():
    from poinsot.dynamics import ConstantSpaceTorque, simulate

    t = np.linspace(0, 5, 101)
    for torque in ([0.0, 0.0, 1.0], ConstantSpaceTorque([0.0, 1.0, 0.0])):
        tr = simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0.1, 1, 0], t, torque=torque)
        assert np.ptp(tr.momentum_norm) > 0.1  # |K| changes: no invariant
        text = "".join(_parse(tr._repr_html_()).text)
        assert "drift" not in text
    for torque in (None, [0.0, 0.0, 0.0]):  # a zero torque is a free body
        free = simulate([1.0, 2.0, 3.0], [1, 0, 0, 0], [0.1, 1, 0], t, torque=torque,
                        max_step=1e-3)  # fmt: skip
        w = np.asarray(free.omega)
        kin = 0.5 * np.sum(np.array([1.0, 2.0, 3.0]) * w**2, axis=-1)  # T from omega, J
        k = np.linalg.norm(np.array([1.0, 2.0, 3.0]) * w, axis=-1)  # |K| = |J w|
        shown = _drifts(_parse(free._repr_html_()))
        assert set(shown) == {"energy T drift (relative)", "|K| drift (relative)"}
        # round-off sized: compare on an absolute scale of the relative numbers
        assert shown["energy T drift (relative)"] == pytest.approx(
            np.max(np.abs(kin - kin[0])) / kin[0], abs=1e-14
        )
        assert shown["|K| drift (relative)"] == pytest.approx(
            np.max(np.abs(k - k[0])) / k[0], abs=1e-14
        )


def test_a_blank_viewer_says_why_where_jupyter_strips_it():
    """Issue 38: an untrusted notebook strips frames and scripts, so show() was blank and
    explore() printed 'VBox(children=...)'. What is left after the stripping (and the
    text form) says why and what to do."""
    from poinsot.plotting import show
    from poinsot.plotting.notebook import UNTRUSTED_NOTE

    tr = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.1, 2.0, 0.1]).trajectory(np.linspace(0, 1, 5))
    v = show(tr)
    frame = v._repr_html_()
    # what an untrusted notebook keeps: the frame (and any script) removed
    kept = re.sub(r"<iframe.*?</iframe>|<script.*?</script>", "", frame, flags=re.S)
    text = re.sub(r"<[^>]+>", "", kept)
    assert "not trusted" in text and "Trust Notebook" in text and ".save(" in text
    bundle = v._repr_mimebundle_()
    assert bundle["text/html"] == frame and UNTRUSTED_NOTE in bundle["text/plain"]
    pytest.importorskip("ipywidgets", reason="explore() needs ipywidgets (poinsot[notebook])")
    from poinsot.plotting import explore

    plain = explore("kepler")._repr_mimebundle_()["text/plain"]
    assert not plain.startswith("VBox") and "show(" in plain and "docs/notebook.md" in plain


def test_show_charts_a_point_result():
    """Issue 38: point results (orbits, Foucault) got no charts in show(). Now the
    position with the distance |r| and the velocity with the speed: on a Kepler orbit the
    distance runs between the apsides and the speed obeys the vis-viva law."""
    from poinsot.plotting.notebook import _point_series

    orbit = CentralOrbit.from_state(kepler(1.0), [1.0, 0, 0], [0, 1.2, 0])
    t = np.linspace(0.0, orbit.radial_period, 4001)
    tr = orbit.trajectory(t)
    charts = {title: series for title, _, series in _point_series(tr)}
    pos = next(s for k, s in charts.items() if k.startswith("position"))
    vel = next(s for k, s in charts.items() if k.startswith("velocity"))
    peri, apo = orbit.apsides[0], orbit.apsides[1]
    assert np.min(pos["|r|"]) == pytest.approx(peri, rel=1e-6)
    assert np.max(pos["|r|"]) == pytest.approx(apo, rel=1e-5)
    a = (peri + apo) / 2  # vis-viva, mu = 1
    assert np.allclose(vel["|v|"] ** 2, 2 / pos["|r|"] - 1 / a, rtol=1e-9)
    html = tr.show().html
    assert "distance |r|" in html and "speed |v|" in html
