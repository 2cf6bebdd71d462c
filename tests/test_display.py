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
        if getattr(res, "energy_drift", None) is not None:
            assert "energy drift" in text, name


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
