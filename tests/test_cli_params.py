"""The command-line helpers read the typed study (simpick.config.read_study) as the workflow does: the tuning
search's params are its typed model, filled from the study's sections, and give the search what the plain
settings gave it; the validation helper's engine settings are the ones the validate job is given."""

import pytest

from conftest import ROOT
from simpick.cli.simulator_tuning import tuning_params
from simpick.config import read_study
from simpick.config.load import configured, entry_settings
from simpick.inputs.robot import load_from_config
from simpick.studies.simulator_tuning import TuningParams


@pytest.mark.parametrize("files", [(), ("config/robots/warthog.yaml",)])
def test_the_tuning_params_are_the_studys_slice(files):
    study, config = read_study([ROOT / "config.yaml", *(ROOT / f for f in files)])
    p = tuning_params(study)
    assert isinstance(p, TuningParams)
    # what run() read by key before, now typed
    assert p.physics.timestep == config["physics"]["timestep"]
    assert p.robot.max_wheel_torque == config["robot"]["max_wheel_torque"]
    assert p.robot.track == config["robot"]["track"]
    assert {name: case.model_dump(mode="json") for name, case in p.cases.items()} == config["validation"]["cases"]
    assert list(p.cases) == list(config["validation"]["cases"])  # the config's order: the table's rows
    assert p.tolerances == config["validation"]["tolerances"]
    # the robot: the same model as the config's robot block loads
    urdf = ROOT / study.robot.urdf
    typed, plain = p.robot.spec(urdf), load_from_config(dict(config["robot"], urdf=str(urdf)))
    assert typed == plain
    # the model refuses what the search does not read
    with pytest.raises(ValueError):
        TuningParams.model_validate(p.model_dump() | {"seed": 1})


@pytest.mark.parametrize("files", [(), ("config/robots/warthog.yaml",)])
def test_the_validation_helpers_engine_settings_are_the_plain_settings(files):
    study, config = read_study([ROOT / "config.yaml", *(ROOT / f for f in files)])
    assert sorted(configured(study.engines)) == sorted(config["engines"])  # a plain mapping keyed by engine
    for engine in configured(study.engines):
        assert entry_settings(study.engines, engine) == config["engines"][engine]
