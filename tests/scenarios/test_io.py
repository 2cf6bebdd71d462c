"""Scenario files: parsing into frozen dataclasses, and every error naming file/key/line."""

from __future__ import annotations

import dataclasses
import textwrap

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciPyRotation

from poinsot import InvalidInputError
from poinsot.scenarios import ScenarioError, load_scenario, parse_scenario
from poinsot.scenarios._toml import locate_keys

BODY = """
[body]
mass = 2.0
inertia = [1.0, 2.0, 3.0]
"""
OMEGA = """
[angular_velocity]
vector = [0.1, 0.2, 0.3]
frame = "body"
"""
SIM = """
[simulation]
duration = 1.0
samples = 11
method = "midpoint"
"""


def parse(text: str, **kw):
    return parse_scenario(textwrap.dedent(text), source="case.toml", **kw)


def errors(text: str, match: str):
    with pytest.raises(ScenarioError, match=match) as info:
        parse(text)
    return info.value


# --------------------------------------------------------------------------- valid files
def test_minimal_dynamics_scenario():
    s = parse(BODY + OMEGA + SIM, name="x")
    assert s.kind == "free-body" and s.name == "x" and s.source == "case.toml"
    np.testing.assert_array_equal(s.body.inertia, np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_array_equal(s.attitude.quat, [1.0, 0.0, 0.0, 0.0])  # default identity
    np.testing.assert_allclose(s.angular_velocity.omega_body, [0.1, 0.2, 0.3])
    assert s.torque.model == "none"
    np.testing.assert_allclose(s.simulation.times(), np.linspace(0, 1, 11))
    assert s.data["body"]["mass"] == 2.0  # the file is echoed


def test_scenario_is_frozen():
    s = parse(BODY + OMEGA + SIM)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "y"
    with pytest.raises(ValueError, match="read-only"):
        s.body.inertia[0, 0] = 5.0  # read-only arrays


def test_load_from_file_uses_stem_as_name(tmp_path):
    p = tmp_path / "my-case.toml"
    p.write_text(BODY + OMEGA + SIM)
    assert load_scenario(p).name == "my-case"
    p.write_text('name = "other"\n' + BODY + OMEGA + SIM)
    assert load_scenario(p).name == "other"


@pytest.mark.parametrize(
    ("inertia", "expected"),
    [
        ("[1.0, 2.0, 2.5]", np.diag([1.0, 2.0, 2.5])),
        ("[2.0, 3.0, 4.0, 0.1, 0.2, 0.3]", [[2.0, 0.1, 0.2], [0.1, 3.0, 0.3], [0.2, 0.3, 4.0]]),
        (
            "[[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]]",
            [[2.0, 0.1, 0.0], [0.1, 3.0, 0.0], [0.0, 0.0, 4.0]],
        ),
    ],
)
def test_inertia_forms(inertia, expected):
    s = parse(f"[body]\nmass = 1.0\ninertia = {inertia}\n" + OMEGA + SIM)
    np.testing.assert_allclose(s.body.inertia, expected)


def test_shape_body_matches_textbook_box():
    s = parse('[body]\nshape = "box"\ndims = [0.3, 0.2, 0.1]\nmass = 2.0\n' + OMEGA + SIM)
    a, b, c, m = 0.3, 0.2, 0.1, 2.0  # Landau-Lifshitz Sec. 32
    np.testing.assert_allclose(
        s.body.inertia, np.diag(m / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2]))
    )  # the whole tensor: no products of inertia about the box's own axes
    assert s.body.shape == "box" and s.body.dims == (0.3, 0.2, 0.1)


def test_parts_combine_with_huygens_steiner():
    # two solid spheres of mass m, radius r at x = +-d and a point mass 2m at y = e
    m, r, d, e = 1.5, 0.1, 0.4, 0.3
    s = parse(
        f"""
    [[body.parts]]
    shape = "sphere"
    dims = [{r}]
    mass = {m}
    position = [{d}, 0.0, 0.0]
    [[body.parts]]
    shape = "sphere"
    dims = [{r}]
    mass = {m}
    position = [{-d}, 0.0, 0.0]
    [[body.parts]]
    name = "ballast"
    mass = {2 * m}
    position = [0.0, {e}, 0.0]
    """
        + OMEGA
        + SIM
    )
    total = 4 * m
    com = np.array([0.0, 2 * m * e / total, 0.0])
    np.testing.assert_allclose(s.body.center_of_mass, com)
    # independent: sum over parts of J_i + m_i (|p|^2 E - p p^T) with p relative to the com
    j = np.zeros((3, 3))
    for mi, ji, p in [
        (m, 0.4 * m * r**2, [d, 0, 0]),
        (m, 0.4 * m * r**2, [-d, 0, 0]),
        (2 * m, 0.0, [0, e, 0]),
    ]:
        p = np.array(p) - com
        j += ji * np.eye(3) + mi * (p @ p * np.eye(3) - np.outer(p, p))
    np.testing.assert_allclose(s.body.inertia, j, atol=1e-15)
    assert s.body.mass == total and [p.name for p in s.body.parts][2] == "ballast"


def test_part_orientation_turns_its_inertia():
    """A cylinder whose own axis z is turned onto body x: J = diag(C, A, A) with the
    textbook A = m (3 r^2 + h^2) / 12, C = m r^2 / 2."""
    m, r, h = 2.0, 0.1, 0.8
    s = parse(
        f"""
    [[body.parts]]
    shape = "cylinder"
    dims = [{r}, {h}]
    mass = {m}
    orientation = {{ axis = [0.0, 1.0, 0.0], angle = 90.0, degrees = true }}
    """
        + OMEGA
        + SIM
    )
    a, c = m * (3 * r**2 + h**2) / 12, m * r**2 / 2
    np.testing.assert_allclose(s.body.inertia, np.diag([c, a, a]), atol=1e-15)
    errors(
        '[[body.parts]]\nmass = 1.0\nshape = "sphere"\ndims = [0.1]\n'
        "orientation = { axis = [0, 0, 1], angle = 1.0 }\n" + OMEGA + SIM,
        r"case\.toml:5: `body\.parts\[0\]\.orientation` missing key `degrees`",
    )


def _scipy_quat(r: SciPyRotation) -> np.ndarray:
    x, y, z, w = r.as_quat()
    q = np.array([w, x, y, z])
    return q if q[0] >= 0 else -q


def _canon(q):
    q = np.asarray(q)
    return q if q[0] >= 0 else -q


@pytest.mark.parametrize(
    ("table", "oracle"),
    [
        (
            'euler = [30.0, 45.0, 60.0]\nsequence = "ZXZ"\ndegrees = true',
            SciPyRotation.from_euler("ZXZ", [30, 45, 60], degrees=True),
        ),
        (
            'euler = [0.3, -0.2, 1.0]\nsequence = "xyz"\ndegrees = false',
            SciPyRotation.from_euler("xyz", [0.3, -0.2, 1.0]),
        ),
        (
            "quat = [0.5, 0.5, 0.5, 0.5]\nscalar_first = true",
            SciPyRotation.from_quat([0.5, 0.5, 0.5, 0.5]),
        ),
        (
            "quat = [0.0, 0.0, 0.6, 0.8]\nscalar_first = false",
            SciPyRotation.from_quat([0.0, 0.0, 0.6, 0.8]),
        ),
        (
            "rotvec = [0.0, 90.0, 0.0]\ndegrees = true",
            SciPyRotation.from_rotvec([0, 90, 0], degrees=True),
        ),
        (
            "axis = [1.0, 1.0, 0.0]\nangle = 2.0\ndegrees = false",
            SciPyRotation.from_rotvec(2.0 * np.array([1, 1, 0]) / np.sqrt(2)),
        ),
        (
            "matrix = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]",
            SciPyRotation.from_matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
        ),
        ("gibbs = [0.0, 0.0, 1.0]", SciPyRotation.from_rotvec([0, 0, np.pi / 2])),
        ("mrp = [0.1, 0.2, 0.3]", SciPyRotation.from_mrp([0.1, 0.2, 0.3])),
    ],
)
def test_attitude_representations_against_scipy(table, oracle):
    s = parse(BODY + "[attitude]\n" + table + "\n" + OMEGA + SIM)
    np.testing.assert_allclose(_canon(s.attitude.quat), _scipy_quat(oracle), atol=1e-14)


def test_angular_velocity_in_space_axes_and_units():
    s = parse(
        BODY + "[attitude]\nrotvec = [0.0, 0.0, 90.0]\ndegrees = true\n"
        '[angular_velocity]\nvector = [0.0, 60.0, 0.0]\nframe = "space"\n'
        'units = "rpm"\n' + SIM
    )
    # space y is body -x after a +90 deg turn about z; 60 rpm = 2 pi rad/s
    np.testing.assert_allclose(s.angular_velocity.omega_body, [2 * np.pi, 0.0, 0.0], atol=1e-12)


def test_step_that_does_not_divide_the_duration_ends_on_it():
    s = parse(BODY + OMEGA + '[simulation]\nduration = 1.0\nstep = 0.3\nmethod = "rk4"\n')
    np.testing.assert_allclose(s.simulation.times(), [0.0, 0.3, 0.6, 0.9, 1.0])


def test_omega_profile_scenarios():
    s = parse(
        '[omega_profile]\nkind = "samples"\nframe = "space"\nunits = "deg/s"\n'
        "t = [0.0, 1.0, 2.0]\nomega = [[0, 0, 90], [0, 0, 90], [0, 0, 0]]\n"
        '[simulation]\nduration = 2.0\nstep = 0.5\nmethod = "magnus4"\n'
    )
    assert s.kind == "attitude" and s.body is None
    np.testing.assert_allclose(s.omega_profile.omega[0], [0, 0, np.pi / 2])
    s = parse(
        '[omega_profile]\nkind = "coning"\nframe = "body"\nhalf_angle = 10.0\n'
        'degrees = true\nrate = 1.0\nunits = "Hz"\n'
        '[simulation]\nduration = 2.0\nstep = 0.5\nmethod = "exact"\n'
    )
    assert s.omega_profile.half_angle == pytest.approx(np.radians(10))
    assert s.omega_profile.rate == pytest.approx(2 * np.pi)


def test_locate_keys_tables_arrays_and_multiline():
    text = textwrap.dedent("""\
        name = "a"          # 1
        [body]              # 2
        mass = 1            # 3
        [[body.parts]]      # 4
        dims = [1,          # 5
          2]                # 6
        [[body.parts]]      # 7
        dims = [3]          # 8
        [simulation]        # 9
        "method" = "x"      # 10
        """)
    lines = locate_keys(text)
    assert lines["name"] == 1 and lines["body"] == 2 and lines["body.mass"] == 3
    assert lines["body.parts[0].dims"] == 5 and lines["body.parts[1]"] == 7
    assert lines["body.parts[1].dims"] == 8 and lines["simulation.method"] == 10


# --------------------------------------------------------------------------- errors
def test_error_is_invalid_input_and_carries_location():
    exc = errors(
        BODY + OMEGA + SIM.replace("duration = 1.0", 'duration = "ten"'),
        r"case\.toml:\d+: `simulation\.duration` expected a positive number, "
        r"found 'ten' \(a string\)",
    )
    assert isinstance(exc, InvalidInputError)
    assert exc.file == "case.toml" and exc.key == "simulation.duration"
    text = textwrap.dedent(BODY + OMEGA + SIM)
    assert text.splitlines()[exc.line - 1].startswith("duration")


def test_toml_syntax_error_has_line():
    errors(BODY + "oops = \n" + OMEGA + SIM, r"case\.toml:5: invalid TOML: .*column")


def test_unknown_top_level_key_suggests():
    errors(
        BODY + OMEGA + SIM.replace("[simulation]", "[simulaton]"),
        r"`simulaton` unknown key\. Did you mean `simulation`\?",
    )


def test_unknown_nested_key_suggests():
    errors(
        BODY + OMEGA + SIM + "duraton = 3\n",
        r"case\.toml:\d+: `simulation\.duraton` unknown key\. Did you mean `duration`\?",
    )


def test_unknown_choice_suggests():
    errors(
        BODY + OMEGA + SIM.replace('"midpoint"', '"mid-point"'),
        r'`simulation\.method` expected one of "exact", .*found \'mid-point\'\. '
        r'Did you mean "midpoint"\?',
    )


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (BODY + OMEGA, r"missing table `\[simulation\]`"),
        (OMEGA + SIM, r"missing table `\[body\]`"),
        (BODY + SIM, r"missing table `\[angular_velocity\]`"),
        (
            BODY + OMEGA + SIM.replace("duration = 1.0", "duration = -1.0"),
            r"`simulation\.duration` expected a positive number, found -1\.0",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "samples = 11\nstep = 0.1"),
            r"`simulation\.(step|samples)` conflicts with `simulation\.(step|samples)`: give "
            r"only one of `step`, `samples`",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", ""),
            r"`simulation` missing key: expected one of `step`, `samples`",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "samples = 1"),
            r"`simulation\.samples` expected an integer >= 2, found 1",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "samples = 2.5"),
            r"`simulation\.samples` expected an integer >= 2, found 2\.5",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "step = 2.0"),
            r"`simulation\.step` expected a step <= duration",
        ),
        (
            BODY + OMEGA + SIM + 'reference = "midpoint"\n',
            r"`simulation\.reference` expected a method other than `method`",
        ),
        (
            BODY
            + OMEGA
            + '[torque]\nmodel = "body"\nvector = [1, 0, 0]\n'
            + SIM.replace('"midpoint"', '"exact"'),
            r'`simulation\.method` "exact" is the closed-form torque-free solution',
        ),
        (
            BODY + OMEGA + '[torque]\nmodel = "body"\n' + SIM,
            r"`torque` missing key `vector`: expected an array of 3 numbers",
        ),
        (
            BODY + OMEGA + '[torque]\nmodel = "none"\nvector = [1, 0, 0]\n' + SIM,
            r'`torque\.vector` not allowed here: the torque model "none" takes no parameters',
        ),
        (
            BODY + OMEGA + '[torque]\nmodel = "gravity"\n' + SIM,
            r"`body\.center_of_mass` gravity about a fixed point needs the centre of mass",
        ),
        (
            BODY + OMEGA + '[torque]\nmodel = "drag"\n' + SIM,
            r'`torque\.model` expected one of "none", "body", "space", "gravity"',
        ),
        (
            BODY + OMEGA.replace('"body"', '"inertial"') + SIM,
            r'`angular_velocity\.frame` expected one of "body", "space", found \'inertial\'',
        ),
        (
            BODY + OMEGA.replace('frame = "body"', "") + SIM,
            r"`angular_velocity` missing key `frame`",
        ),
        (
            BODY + OMEGA.replace("[0.1, 0.2, 0.3]", "[0.1, 0.2]") + SIM,
            r"`angular_velocity\.vector` expected an array of 3 numbers, found \[0\.1, 0\.2\]",
        ),
        (
            BODY + OMEGA + 'units = "rad/sec"\n' + SIM,
            r'`angular_velocity\.units` .*Did you mean "rad/s"\?',
        ),
        ('name = "a b"\n' + BODY + OMEGA + SIM, r"`name` expected a name of at most 100 letters"),
    ],
)
def test_errors_name_key(text, match):
    errors(text, match)


@pytest.mark.parametrize(
    ("body", "match"),
    [
        ("mass = 1.0\ninertia = [1.0, 1.0, 3.0]", r"`body\.inertia` .*triangle"),
        ("mass = 1.0\ninertia = [1.0, 2.0]", r"`body\.inertia` expected 3 principal moments"),
        ("mass = 1.0\ninertia = [1.0, 2.0, -3.0]", r"`body\.inertia` .*positive"),
        (
            "mass = 0.0\ninertia = [1.0, 2.0, 2.0]",
            r"`body\.mass` expected a positive number, found 0\.0",
        ),
        ("inertia = [1.0, 2.0, 2.0]", r"`body` missing key `mass`"),
        ("mass = 1.0", r"`body` missing key: expected one of `inertia`, `shape`, `parts`"),
        (
            'mass = 1.0\nshape = "spere"\ndims = [1.0]',
            r'`body\.shape` expected one of "box", .*found \'spere\'\. Did you mean "sphere"\?',
        ),
        (
            'mass = 1.0\nshape = "box"\ndims = [1.0, 2.0]',
            r"`body\.dims` expected 3 positive number\(s\) for a box",
        ),
        (
            'mass = 1.0\nshape = "cylinder"\ndims = [1.0, -2.0]',
            r"`body\.dims` expected positive dimensions \[radius, height\]",
        ),
        (
            'mass = 1.0\nshape = "sphere"\ndims = [1.0]\ninertia = [1.0, 1.0, 1.0]',
            r"`body\.shape` conflicts with `body\.inertia`",
        ),
        (
            "mass = 1.0\n[[body.parts]]\nmass = 1.0",
            r"`body\.mass` not allowed here: the mass and centre of mass of a body made of",
        ),
        (
            '[[body.parts]]\nmass = 1.0\nshape = "sphere"\ndims = [0.1]\n'
            '[[body.parts]]\nmass = 1.0\nshape = "box"\ndims = [0.1, 0.1]',
            r"case\.toml:\d+: `body\.parts\[1\]\.dims` expected 3 positive",
        ),
        (
            '[[body.parts]]\nmass = 1.0\nshape = "sphere"\ndims = [0.1]\ninertia = [1, 1, 1]',
            r"`body\.parts\[0\]\.inertia` not allowed here",
        ),
        ('mass = 1.0\nshape = "rod"\ndims = [1.0]', r"`body\.shape` .*positive definite"),
        (
            "[[body.parts]]\nmass = 1.0\nposition = [1.0, 0.0, 0.0]",
            r"`body\.parts` .*(singular|positive)",
        ),
        (
            '[[body.parts]]\nmass = 1.0\nshape = "sphere"\ndims = [0.1]\ncolour = "red"',
            r"`body\.parts\[0\]\.colour` unknown key",
        ),
    ],
)
def test_body_errors(body, match):
    errors("[body]\n" + body + "\n" + OMEGA + SIM, match)


@pytest.mark.parametrize(
    ("attitude", "match"),
    [
        (
            "quat = [1.0, 0.0, 0.0, 0.0]",
            r"`attitude` missing key `scalar_first`: expected true or false \(true: \[w, x, y, z\]",
        ),
        (
            "quat = [0.0, 0.0, 0.0, 0.0]\nscalar_first = true",
            r"`attitude\.quat` expected a non-zero quaternion",
        ),
        (
            "quat = [1.0, 0.0, 0.0]\nscalar_first = true",
            r"`attitude\.quat` expected an array of 4 numbers",
        ),
        ("euler = [1.0, 2.0, 3.0]\ndegrees = true", r"`attitude` missing key `sequence`"),
        (
            'euler = [1.0, 2.0, 3.0]\nsequence = "ZXZ"',
            r"`attitude` missing key `degrees`: expected true or false \(true: angles in degrees; "
            r"false: in radians\)",
        ),
        (
            'euler = [1.0, 2.0, 3.0]\nsequence = "ZZX"\ndegrees = true',
            r"`attitude\.sequence` .*ZZX",
        ),
        (
            'euler = [1.0, 2.0, 3.0]\nsequence = "ZXZ"\ndegrees = "yes"',
            r"`attitude\.degrees` expected true or false, found 'yes'",
        ),
        (
            'euler = [1.0, 2.0, 3.0]\nsequence = "ZXZ"\ndegrees = true\nscalar_first = true',
            r"`attitude\.scalar_first` not used by an attitude given as `euler`",
        ),
        (
            "rotvec = [1.0, 0.0, 0.0]\ndegrees = true\nmrp = [0.0, 0.0, 0.0]",
            r"`attitude\.mrp` conflicts with `attitude\.rotvec`",
        ),
        (
            "axis = [0.0, 0.0, 0.0]\nangle = 1.0\ndegrees = false",
            r"`attitude\.axis` expected a non-zero axis",
        ),
        (
            "matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]",
            r"`attitude\.matrix` .*det",
        ),
        ("matrix = [[1.0, 0.0], [0.0, 1.0]]", r"`attitude\.matrix` expected a 3x3 array"),
        ("angle = 1.0", r"`attitude` missing key: expected one of `quat`, `matrix`"),
        (
            "quaternion = [1.0, 0.0, 0.0, 0.0]",
            r"`attitude\.quaternion` unknown key\. Did you mean `quat`\? Valid keys here: ",
        ),
    ],
)
def test_attitude_errors(attitude, match):
    errors(BODY + "[attitude]\n" + attitude + "\n" + OMEGA + SIM, match)


@pytest.mark.parametrize(
    ("profile", "match"),
    [
        (
            'kind = "samples"\nframe = "body"\nt = [0.0, 1.0]\nomega = [[0, 0, 1]]',
            r"`omega_profile\.omega` expected one row per time in `t` \(2 rows\), found 1",
        ),
        (
            'kind = "samples"\nframe = "body"\nt = [0.0, 0.0]\nomega = [[0, 0, 1], [0, 0, 1]]',
            r"`omega_profile\.t` expected at least 2 strictly increasing times",
        ),
        (
            'kind = "coning"\nframe = "space"\nhalf_angle = 0.1\ndegrees = false\nrate = 1.0',
            r"`omega_profile\.frame` coning motion is defined by its body rates",
        ),
        (
            'kind = "coning"\nframe = "body"\nhalf_angle = 95.0\ndegrees = true\nrate = 1.0',
            r"`omega_profile\.half_angle` expected an angle in \(0, 90\) degrees",
        ),
        ('kind = "spin"\nframe = "body"', r'`omega_profile\.kind` expected one of "constant"'),
        (
            'kind = "samples"\nframe = "body"\nt = [0.5, 1.0]\nomega = [[0, 0, 1], [0, 0, 1]]',
            r"`omega_profile\.t` expected the table to start at or before t = 0",
        ),
        (
            'kind = "samples"\nframe = "body"\nt = [0.0, 0.5]\nomega = [[0, 0, 1], [0, 0, 1]]',
            r"`simulation\.duration` expected at most the last time of \[omega_profile\] t "
            r"\(0\.5 s\)",
        ),
    ],
)
def test_omega_profile_errors(profile, match):
    errors(
        "[omega_profile]\n" + profile + "\n"
        '[simulation]\nduration = 1.0\nsamples = 5\nmethod = "magnus4"\n',
        match,
    )


def test_profile_conflicts_and_exact_samples():
    prof = '[omega_profile]\nkind = "constant"\nframe = "body"\nvector = [0.0, 0.0, 1.0]\n'
    errors(
        prof + OMEGA + '[simulation]\nduration = 1.0\nsamples = 5\nmethod = "magnus4"\n',
        r"`angular_velocity` not allowed here: a scenario with \[omega_profile\]",
    )
    errors(
        prof + '[torque]\nmodel = "none"\n'
        '[simulation]\nduration = 1.0\nsamples = 5\nmethod = "magnus4"\n',
        r"`torque` not allowed here",
    )
    errors(
        prof + '[simulation]\nduration = 1.0\nsamples = 5\nmethod = "midpoint"\n',
        r'`simulation\.method` expected one of "exact", "magnus4"',
    )
    samples = (
        '[omega_profile]\nkind = "samples"\nframe = "body"\nt = [0.0, 1.0]\n'
        "omega = [[0, 0, 1], [0, 0, 1]]\n"
    )
    errors(
        samples + '[simulation]\nduration = 1.0\nsamples = 5\nmethod = "exact"\n',
        r'`simulation\.method` "exact" needs a closed form',
    )


def test_file_errors(tmp_path):
    with pytest.raises(ScenarioError, match=r"nope\.toml: no such file"):
        load_scenario(tmp_path / "nope.toml")
    with pytest.raises(ScenarioError, match=r"is a directory"):
        load_scenario(tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"name = '\xff'\n")
    with pytest.raises(ScenarioError, match=r"bad\.toml: not UTF-8"):
        load_scenario(bad)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("body = 3\n" + OMEGA + SIM, r"`body` expected a table, found 3 \(a number\)"),
        (
            "[body]\nparts = 3\n" + OMEGA + SIM,
            r"`body\.parts` expected an array of tables \(\[\[body\.parts\]\]\), found 3",
        ),
        (
            BODY + OMEGA.replace('frame = "body"', "frame = 1") + SIM,
            r'`angular_velocity\.frame` expected one of "body", "space", found 1 \(a number\)',
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "step = 1e-7"),
            r"`simulation\.step` expected at most 5000000 output samples "
            r"\(duration / step\), found 1e\+07",
        ),
        (
            BODY + OMEGA + SIM.replace("samples = 11", "samples = 6000000"),
            r"`simulation\.samples` expected at most 5000000 samples, found 6000000",
        ),
        (
            '[body]\nshape = "box"\ndims = [1.0, 1.0, 1.0]\n' + OMEGA + SIM,
            r"`body` missing key `mass`: expected a positive number",
        ),
        (
            "description = 5\n" + BODY + OMEGA + SIM,
            r"`description` expected a string, found 5 \(a number\)",
        ),
    ],
)
def test_more_type_errors(text, match):
    errors(text, match)
