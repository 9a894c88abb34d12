"""The committed JSON schema of the config (schemas/config.schema.json) is the one the pydantic
models generate (`make schema` rewrites it), and it accepts the shipped configs and refuses a bad one."""

import json

import jsonschema
import pytest
import yaml

from conftest import ROOT, study_config, tiny_config
from simpick.schema import SCHEMA, schema_text


def validator():
    return jsonschema.Draft202012Validator(json.loads((ROOT / SCHEMA).read_text()))


def test_the_committed_schema_is_the_models_schema():
    assert (ROOT / SCHEMA).read_text() == schema_text(), "schemas/config.schema.json is stale: run make schema"


@pytest.mark.parametrize("config", ["config.yaml", ".test/config.yaml", "tiny"])
def test_the_shipped_configs_follow_the_schema(config, tmp_path):
    data = tiny_config(tmp_path) if config == "tiny" else yaml.safe_load((ROOT / config).read_text())
    errors = [f"{'.'.join(map(str, e.absolute_path))}: {e.message}" for e in validator().iter_errors(data)]
    assert errors == []


def test_the_sweep_config_follows_the_schema():
    base = study_config()
    sweep = yaml.safe_load((ROOT / "config/sweeps/timestep.yaml").read_text())
    assert list(validator().iter_errors(base | sweep)) == []


def test_a_bad_config_is_refused():
    config = study_config()
    config["physics"]["timestep"] = "fast"
    config["weights"]["free"] = -1
    config["engnies"] = {}
    paths = sorted(".".join(map(str, e.absolute_path)) for e in validator().iter_errors(config))
    assert paths == ["", "physics.timestep", "weights.free"]  # "" : the unknown top-level key
