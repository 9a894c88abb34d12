"""The simulators as rows: the catalog's sources and checks, the profiles in the plan, the tuned profiles
against the search that chose them, and the settings files loading back into simpick's engines."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
import yaml

from conftest import ROOT, tiny_config
from simpick.config import Study
from simpick.engines import get_engine, unavailable
from simpick.engines import simulator_files as formats
from simpick.engines.catalog import CatalogError, load_catalog
from simpick.engines.simulators import SIMULATORS, VARIANTS, engine_of, model_name, split
from simpick.plan import Plan
from simpick.studies.simulator_tuning import choose, grid

CATALOG = ROOT / "resources/simulators/simulators.yaml"
TUNING = ROOT / "resources/simulators/tuning.csv"
HUSKY = "husky_a200"


@pytest.fixture(scope="module")
def catalog():
    return load_catalog(CATALOG)


def test_every_listed_simulator_is_in_the_catalog_with_a_source_for_every_fact_and_setting(catalog):
    assert set(catalog.simulators) == set(SIMULATORS)
    for name, sim in catalog.simulators.items():
        q = sim.qualitative
        assert all(q.sources[f].strip() for f in q.sources), name
        if sim.engine is None:
            assert sim.not_reproduced, name
            continue
        for variant in VARIANTS:
            profile = catalog.profile(name, variant)  # the calibrated variant starts from the tuned one
            assert profile.basis.strip(), (name, variant)
            for robot, settings in [(None, profile.settings), *profile.robots.items()]:
                for key, s in settings.items():
                    assert s.source.strip() and s.exposed_as.strip(), (name, variant, robot, key)


def test_the_paper_simulators_keep_their_rows(catalog):
    # the paper's four: CoppeliaSim, Gazebo (Classic, its Gazebo), MORSE, Webots
    for name in ("coppeliasim", "gazebo_classic", "morse", "webots"):
        assert name in catalog.simulators
    # MORSE runs as Bullet at its 60 Hz in two substeps (tests/test_bullet_simulators.py)
    assert catalog.simulators["morse"].engine == "pybullet"


def test_a_profile_is_named_by_simulator_and_variant_and_runs_on_its_engine():
    assert model_name("gazebo_classic", "tuned") == "gazebo_classic-tuned"
    assert split("gazebo_classic-tuned") == ("gazebo_classic", "tuned")
    assert split("ode") is None and split("gazebo-other") is None
    assert engine_of("webots-shipped") == "ode" and engine_of("gazebo-tuned") == "gzphysics"
    assert engine_of("mujoco") == "mujoco"
    assert type(get_engine("isaac_sim-shipped")).__name__ == type(get_engine("physx")).__name__


def _write(tmp_path, data) -> Path:
    path = tmp_path / "simulators.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_misspelt_setting_is_refused_naming_the_file_the_profile_and_the_setting(tmp_path):
    data = yaml.safe_load(CATALOG.read_text())
    data["simulators"]["webots"]["tuned"]["settings"]["contact_slipp"] = {
        "value": 0.001,
        "exposed_as": "forceDependentSlip",
        "source": "made up",
    }
    with pytest.raises(CatalogError) as err:
        load_catalog(_write(tmp_path, data))
    message = str(err.value)
    assert "simulators.webots.tuned" in message and "contact_slipp" in message and "simulators.yaml" in message


def test_an_unsourced_fact_and_an_unknown_simulator_are_refused(tmp_path):
    data = yaml.safe_load(CATALOG.read_text())
    del data["simulators"]["gazebo"]["qualitative"]["sources"]["ros"]
    with pytest.raises(CatalogError, match="ros"):
        load_catalog(_write(tmp_path, data))
    data = yaml.safe_load(CATALOG.read_text())
    data["simulators"]["carla"] = data["simulators"]["gazebo"]
    with pytest.raises(CatalogError, match="carla"):
        load_catalog(_write(tmp_path, data))


def test_the_maker_tags_apply_to_their_robot_only(catalog):
    husky = catalog.settings("gazebo_classic", "shipped", HUSKY)
    generic = catalog.settings("gazebo_classic", "shipped", "some_robot")
    assert husky["friction_direction"] == "wheel_x" and generic["friction_direction"] == "plane"
    assert husky["contact_kp"] == pytest.approx(1 / (1 / 1e7 + 1 / 1e12), rel=1e-4)
    assert catalog.settings("gazebo_classic", "shipped", "warthog")["surface_mu"] == 0.5


def _plan(config) -> Plan:
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


def test_the_profiles_run_the_validation_and_the_real_data_but_not_the_lab(tmp_path):
    config = tiny_config(tmp_path)
    config["simulators"]["run"] = ["gazebo_classic", "mujoco", "morse"]
    config["engines"] = {"mujoco": None, "ode": None}
    plan = _plan(config)
    assert plan.simulators == ["gazebo_classic", "mujoco"]
    assert "not among this study's engines" in plan.simulators_left_out["morse"]  # its engine, pybullet, is not
    assert "gazebo_classic-shipped" in plan.sources["segments"]["models"]
    assert "gazebo_classic-shipped" not in plan.sources["lab"]["models"]
    assert any("validation/gazebo_classic-tuned/" in p for p in plan.validation_results())
    # MuJoCo as tuned is simpick's MuJoCo block exactly: it reads the engine's results, runs nothing
    assert plan.profile_results["mujoco-tuned"] == "mujoco"
    assert "mujoco-tuned" not in plan.real_models
    assert plan.validation_params("gazebo_classic-shipped")["engine_settings"]["friction_direction"] == "wheel_x"


def test_an_engine_left_out_leaves_its_simulators_out_with_the_reason(tmp_path):
    config = tiny_config(tmp_path)
    config["simulators"]["run"] = None
    config["engines"] = {"mujoco": None}
    plan = _plan(config)
    # Gazebo's engine runs only behind its profiles (simpick.engines.PROFILE_ADAPTERS): its rows run
    # wherever the program is built, and are left out with the reason where it is not
    built = not unavailable(["gzphysics"])
    assert plan.simulators == (["gazebo", "mujoco"] if built else ["mujoco"])
    assert built or "make gzphysics" in plan.simulators_left_out["gazebo"]
    assert "not among this study's engines" in plan.simulators_left_out["webots"]


def test_the_tuned_profiles_are_the_choice_of_their_search(catalog):
    table = pd.read_csv(TUNING, comment="#")
    assert set(table.simulator) == set(yaml.safe_load((ROOT / "resources/simulators/tuning.yaml").read_text()))
    assert choose(table.drop(columns="chosen")).chosen.tolist() == table.chosen.tolist()
    for simulator, rows in table.groupby("simulator"):
        chosen = json.loads(rows[rows.chosen].iloc[0].settings)
        tuned = catalog.settings(simulator, "tuned", HUSKY)
        assert {k: tuned[k] for k in chosen} == chosen, simulator
        assert len(rows) == len(
            grid(yaml.safe_load((ROOT / "resources/simulators/tuning.yaml").read_text())[simulator])
        )


# every simulator with a settings file format of its own (MORSE has none: tests/test_bullet_simulators.py)
RUNNABLE = [
    (name, variant)
    for name, sim in load_catalog(CATALOG).simulators.items()
    if sim.engine is not None and sim.settings_format is not None
    for variant in VARIANTS
]


@pytest.mark.parametrize("simulator,variant", RUNNABLE)
def test_a_settings_file_reads_back_into_the_settings_it_was_written_from(catalog, simulator, variant):
    sim = catalog.simulators[simulator]
    model = get_engine(sim.engine).settings_model
    settings = model.model_validate(catalog.settings(simulator, variant, HUSKY)).model_dump(mode="json")
    entries = catalog.entries(simulator, variant, HUSKY)
    texts = formats.write(sim.settings_format, sim.engine, settings, entries, ["test"], ["front_left_wheel_link"])
    back = formats.read(sim.settings_format, sim.engine, texts)
    for key, value in back.items():
        assert (
            settings[key] == pytest.approx(value, rel=1e-5) if isinstance(value, float) else settings[key] == value
        ), key
    # every setting the profile states (over the adapter's defaults) is in the file
    assert set(entries) <= set(back) | {"contact_max_correcting_vel", "contact_surface_layer", "max_contacts"} | (
        {"contact_bounce", "contact_bounce_vel", "contact_soft_erp", "contact_soft_cfm"}
        if sim.settings_format == "sdf"
        else set()
    ) | (
        # values CoppeliaSim fixes (Bullet 2.78's rigid contacts and contact correction)
        {"contact_stiffness", "contact_damping", "contact_erp"} if sim.settings_format == "coppeliasim" else set()
    ) | ({"stepper", "friction_direction", "contact_surface_layer"} if sim.settings_format == "webots" else set()), (
        sorted(set(entries) - set(back))
    )


def _gain(engine: str, settings: dict, tmp_path, mu: float = 0.8) -> float:
    from simpick.inputs.robot import load_from_config
    from simpick.studies.validation.cases import Setup, run_case
    from simpick.studies.validation.judge import summarise

    config = tiny_config(tmp_path)
    setup = Setup(
        engine=engine,
        robot=load_from_config(config["robot"]),
        timestep=0.001,
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings=settings,
    )
    case = {"kind": "yaw_gain", "v": 0.5, "w": 0.5, "mu": mu, "duration": 2.0}
    summary = summarise([run_case(setup, "gain", case)], config["validation"]["tolerances"])
    return float(summary[summary.quantity == "yaw_rate_gain"].engine_value.iloc[0])


@pytest.mark.parametrize("simulator", ["gazebo_classic", "webots", "mujoco"])
def test_a_pasted_settings_file_reproduces_the_tuned_row_in_the_engine(catalog, simulator, tmp_path):
    sim = catalog.simulators[simulator]
    if unavailable([sim.engine]):
        pytest.fail(f"{sim.engine} is not installed: {unavailable([sim.engine])}")
    model = get_engine(sim.engine).settings_model
    tuned = model.model_validate(catalog.settings(simulator, "tuned", HUSKY)).model_dump(mode="json")
    texts = formats.write(
        sim.settings_format,
        sim.engine,
        tuned,
        catalog.entries(simulator, "tuned", HUSKY),
        ["test"],
        ["front_left_wheel_link"],
    )
    # the simulator as it ships (its defaults and the maker's tags), with the file pasted over it
    pasted = {
        **model().model_dump(mode="json"),
        **catalog.settings(simulator, "shipped", HUSKY),
        **formats.read(sim.settings_format, sim.engine, texts),
    }
    assert _gain(sim.engine, pasted, tmp_path) == pytest.approx(_gain(sim.engine, tuned, tmp_path), abs=1e-9)


def test_the_mjcf_file_compiles_in_mujoco(catalog):
    import mujoco

    settings = get_engine("mujoco").settings_model.model_validate(catalog.settings("mujoco", "tuned")).model_dump()
    text = formats.write("mjcf", "mujoco", settings, catalog.entries("mujoco", "tuned"), ["t"], ["wheel"])["xml"]
    body = (
        '<worldbody><geom name="floor" type="plane" size="5 5 .1"/>'
        '<body pos="0 0 .2"><freejoint/><geom name="wheel" type="cylinder" size=".16 .05"/></body></worldbody>'
    )
    xml = text.split("-->\n")[-1].replace("</mujoco>", body + "</mujoco>")
    model = mujoco.MjModel.from_xml_string(xml)
    assert model.npair == 1 and model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC


def test_the_drake_yaml_loads_as_drake_config(catalog):
    from pydrake.common.yaml import yaml_load_typed
    from pydrake.multibody.plant import MultibodyPlantConfig

    for variant in VARIANTS:
        settings = get_engine("drake").settings_model.model_validate(catalog.settings("drake", variant)).model_dump()
        texts = formats.write("drake", "drake", settings, catalog.entries("drake", variant), ["t"], ["wheel"])
        config = yaml_load_typed(schema=MultibodyPlantConfig, data=texts["yaml"])
        assert config.discrete_contact_approximation == settings["discrete_approximation"]
        assert config.stiction_tolerance == pytest.approx(settings["stiction_tolerance"])


def test_a_profile_takes_the_study_s_wheel_actuators_and_the_catalog_s_physics(tmp_path):
    config = tiny_config(tmp_path)
    config["simulators"]["run"] = ["mujoco"]
    config["engines"] = {"mujoco": {"wheel_servo_kp": 15000.0, "cone": "elliptic"}}
    plan = _plan(config)
    shipped = plan.config["profiles"]["mujoco-shipped"]
    assert shipped["wheel_servo_kp"] == 15000.0  # the robot's actuator, as the study describes it
    assert shipped["cone"] == "pyramidal" and shipped["wheel_contact"] == "default"  # MuJoCo's defaults


def test_a_tuned_profile_the_search_left_at_its_shipped_settings_reads_the_shipped_results(tmp_path):
    data = yaml.safe_load(CATALOG.read_text())
    data["simulators"]["coppeliasim"]["tuned"]["settings"] = {}
    config = tiny_config(tmp_path)
    config["simulators"] = {"catalog": str(_write(tmp_path, data)), "run": ["coppeliasim"]}
    plan = _plan(config)
    assert plan.profile_results == {
        "coppeliasim-shipped": "coppeliasim-shipped",
        "coppeliasim-tuned": "coppeliasim-shipped",
        # CoppeliaSim's Bullet exposes no turning setting: its calibrated row is its tuned one
        "coppeliasim-calibrated": "coppeliasim-shipped",
    }
    assert plan.profiles == ["coppeliasim-shipped"]
    assert "coppeliasim-tuned" not in plan.sources["segments"]["models"]
