"""The plan (simpick.plan): built from the validated config, it hands the rules
typed settings with every default filled in by its model, and the rules read nothing else."""

import copy
import re

import pytest
import yaml

from conftest import ROOT, tiny_config
from simpick.config import Study, plain
from simpick.engines import get_engine
from simpick.inputs.terrain import TILES
from simpick.plan import Plan
from simpick.studies.validation import DEFAULT_HEADING


def plan_of(config: dict) -> Plan:
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture
def config(tmp_path):
    return tiny_config(tmp_path)


def test_a_default_left_out_of_the_config_reaches_the_jobs_from_its_model(config):
    for spec in config["terrains"].values():
        spec.pop("tiles", None)
    config["validation"]["cases"]["gain_v0.5_w0.5_mu0.8"].pop("heading", None)
    config["engines"]["ode"] = None  # an empty entry: the adapter's defaults
    plan = plan_of(config)

    assert {t: s["tiles"] for t, s in plan.config["terrains"].items()} == {"grass": TILES, "bumps": TILES}
    case = plan.validation_params("ode")["cases"]["gain_v0.5_w0.5_mu0.8"]
    assert case["heading"] == DEFAULT_HEADING
    params = plan.simulation_params("ode", "grass", "straight")
    defaults = get_engine("ode").settings_model().model_dump(mode="json")
    assert set(params["engine_settings"]) == set(defaults) and defaults  # every setting, from the adapter's model
    assert params["engine_settings"]["erp"] == pytest.approx(defaults["erp"])


def test_a_setting_written_as_a_string_reaches_the_job_as_its_type(config):
    # YAML 1.1 reads 5.0e3 as a string; the raw dict handed it on as one, the validated settings as a number
    config["engines"]["pybullet"] = yaml.safe_load("contact_damping: 5.0e3")
    assert config["engines"]["pybullet"]["contact_damping"] == "5.0e3"
    params = plan_of(config).simulation_params("pybullet", "grass", "straight")
    assert params["engine_settings"]["contact_damping"] == 5000.0


def test_the_engines_keep_the_config_order_and_only_the_configured_ones(config):
    config["engines"] = {"mujoco": None, "ode": {}, "pybullet": None}
    config["baselines"] = {"coulomb": None}
    plan = plan_of(config)
    assert plan.engines == ["mujoco", "ode", "pybullet"]
    assert plan.baselines == ["coulomb"]
    assert list(plain(Study.model_validate(config), config)["engines"]) == ["mujoco", "ode", "pybullet"]
    assert plan.sources["lab"]["models"] == ["mujoco", "ode", "pybullet"]
    assert plan.sources["segments"]["models"] == ["mujoco", "ode", "pybullet", "coulomb"]


def test_the_plan_does_not_change_the_config_it_was_given(config):
    before = copy.deepcopy(config)
    plan_of(config)
    assert config == before


def test_the_rules_read_the_validated_settings_not_the_raw_config():
    """Every `config[...]` / `config.get(...)` in the rules goes through the plan (PLAN.config)."""
    raw = []
    for path in [ROOT / "Snakefile", *sorted((ROOT / "rules").glob("*.smk"))]:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if re.search(r"(?<![.\w])config(\[|\.get\()", line):
                raw.append(f"{path.name}:{number}: {line.strip()}")
    assert not raw, "rules reading the raw config (use PLAN.config):\n" + "\n".join(raw)
