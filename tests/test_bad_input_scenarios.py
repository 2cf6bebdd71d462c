"""Bad-input regressions for ``poinsot.scenarios`` entry points (audit): wrong types
used to end in raw TypeError/AttributeError tracebacks from pathlib or tomllib."""

import pytest

import poinsot.scenarios as S
from poinsot import InvalidTypeError


@pytest.mark.parametrize("bad", [None, 3, b"name = 'x'"])
def test_parse_scenario_text_type(bad):
    with pytest.raises(InvalidTypeError, match="`text` to be a str .TOML."):
        S.parse_scenario(bad)


@pytest.mark.parametrize("bad", [None, 3.0, ["a.toml"]])
def test_load_scenario_path_type(bad):
    with pytest.raises(InvalidTypeError, match="`path` to be a str or os.PathLike"):
        S.load_scenario(bad)


@pytest.mark.parametrize("bad", [None, 3])
def test_prepare_output_dir_type(bad):
    with pytest.raises(InvalidTypeError, match="`out` to be a str or os.PathLike"):
        S.prepare_output_dir(bad)


def test_scenario_object_types(tmp_path):
    with pytest.raises(InvalidTypeError, match="`scenario` to be a Scenario"):
        S.simulate_scenario("examples/tennis_racket.toml")
    with pytest.raises(InvalidTypeError, match="`scenario` to be a Scenario"):
        S.run_scenario({"name": "x"}, tmp_path / "out")
    assert not (tmp_path / "out").exists()  # nothing created for a bad call
    with pytest.raises(InvalidTypeError, match="`result` to be a ScenarioResult"):
        S.write_outputs(None, tmp_path / "out2")
