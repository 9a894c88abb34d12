"""The Drake models rule simulator_models writes (simpick.studies.simulator_models, simpick.engines.simulator_models.
drake) load with Drake's own code alone and do what their headers claim. Each model's files are read by Drake's
loaders only (``yaml_load_typed`` for the plant's config, ``AddMultibodyPlant``, ``Parser.AddModels`` for the URDF
and the ground's SDFormat file: nothing of simpick builds the plant), the PD actuators the URDF declares are driven
through the model instance's desired-state port at each claimed command, mapped by the YAML's own ``drive``, and
the plant steps by its own discrete update; the yaw-rate gain it gives is the one the file claims, which the job
took from simpick's validation (``run_case``, the validate job's function) on the Drake adapter."""

from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import ROOT, study_config
from simpick.config import Study
from simpick.plan import Plan
from simpick.studies.simulator_models import simulator_models_job

# s: each claimed case cut from its 6 s to 1 s. Measured on the Husky with Drake 1.51.1, the job's gains at 1 s
# against 6 s (spin, spin right, (0.5, -0.2), (0.5, -0.5), (0.5, 0.2), (0.5, 0.5)): tuned (hydroelastic, 4 ms)
# 0.4772 / 0.4776 / 0.4765 / 0.4785 / 0.4695 / 0.4687 against 0.4773 / 0.4775 / 0.4765 / 0.4785 / 0.4696 / 0.4686;
# shipped (point, 1 ms) 0.5362 / 0.5362 / 0.5354 / 0.5371 / 0.5346 / 0.5357 at both: within 1e-4, the wheels' PD
# (d 1e4) settled long before the measured second half. Job and loader take about 6 s for both profiles here.
DURATION = 1.0
STEMS = ("drake-tuned", "drake-shipped")


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """The job's models of Drake's tuned and shipped profiles, from the plan's params with the claimed cases cut to
    DURATION; and the claims the job measured, per model."""
    config = study_config()
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    tmp = tmp_path_factory.mktemp("drake_models")
    params = plan.simulator_models_params()
    params["profiles"] = {p: params["profiles"][p] for p in STEMS}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": []}
    claims = simulator_models_job(inputs, params, str(tmp / "models"))
    return tmp / "models", claims


def load(folder: Path, stem: str):
    """The model as a Drake user loads it, with Drake's code alone: (simulator, plant, plant context, robot
    instance, the YAML's own data)."""
    from pydrake.common.yaml import yaml_load_typed
    from pydrake.math import RigidTransform, RotationMatrix
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder

    plant_yaml = folder / f"{stem}.plant.yaml"
    config = yaml_load_typed(schema=MultibodyPlantConfig, filename=str(plant_yaml), child_name="plant_config")
    data = yaml.safe_load(plant_yaml.read_text())
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(config, builder)
    plant.mutable_gravity_field().set_gravity_vector(data["gravity"])
    robot_file, ground_file = data["models"]
    (robot,) = Parser(plant).AddModels(str(folder / robot_file))
    Parser(plant).AddModels(str(folder / ground_file))
    base = data["base"]
    plant.SetDefaultFloatingBaseBodyPose(
        plant.GetBodyByName(base["body"], robot), RigidTransform(RotationMatrix.MakeZRotation(base["yaw"]), base["xyz"])
    )
    plant.Finalize()
    simulator = Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    return simulator, plant, context, robot, data


def loader_gain(folder: Path, stem: str, v: float, w: float, duration: float) -> float:
    """The yaw-rate gain of the loaded model, measured as a validation turning case measures it
    (simpick.studies.validation.cases._yaw_gain): the command held from the first step for ``duration``, the
    base's yaw rate about its own z axis after each of the plant's discrete updates, its mean over the updates from
    half the run on, over ``w``. The desired state as the file says: positions 0, then each actuator's
    (v - w x side x command_track / 2) x axis_sign / radius, the still actuators' 0."""
    simulator, plant, context, robot, data = load(folder, stem)
    drive = data["drive"]
    track = drive["command_track"]
    speeds = [(v - w * a["side"] * track / 2) * a["axis_sign"] / a["radius"] for a in drive["actuators"]]
    speeds += [0.0] * len(drive["still"])
    names = [a["name"] for a in drive["actuators"]] + list(drive["still"])
    # the rows of the desired state are the instance's actuators in the file's order
    assert [plant.get_joint_actuator(i).name() for i in plant.GetJointActuatorIndices(robot)] == names
    plant.get_desired_state_input_port(robot).FixValue(context, np.r_[np.zeros(len(speeds)), speeds])
    plant.get_actuation_input_port(robot).FixValue(context, np.zeros(plant.num_actuated_dofs(robot)))
    base = plant.GetBodyByName(data["base"]["body"], robot)
    dt = plant.time_step()
    steps = round(duration / dt)
    rates = np.empty(steps)
    simulator.Initialize()
    for k in range(steps):
        simulator.AdvanceTo((k + 1) * dt)
        rotation = plant.EvalBodyPoseInWorld(context, base).rotation().matrix()
        rates[k] = (rotation.T @ plant.EvalBodySpatialVelocityInWorld(context, base).rotational())[2]
    return float(rates[steps // 2 :].mean() / w)


@pytest.mark.parametrize("stem", STEMS)
def test_drake_s_own_loaders_give_every_gain_the_model_claims(models, stem):
    folder, claims = models
    stated = yaml.safe_load((folder / f"{stem}.plant.yaml").read_text())["claims"]
    measured = {c.case: c for c in claims[stem]}
    assert stated and sorted(stated) == sorted(measured)
    for case, claim in stated.items():
        # the file's claim is the validation's figure (6 decimals in the file) ...
        assert claim["gain"] == pytest.approx(measured[case].gain, abs=1e-6), case
        assert claim["duration"] == DURATION
        # ... and Drake gives it from the files alone
        gain = loader_gain(folder, stem, claim["v"], claim["w"], claim["duration"])
        assert abs(gain - claim["gain"]) < 0.01, f"{stem} {case}: loaded {gain:.4f}, claimed {claim['gain']:.4f}"


def test_the_files_hold_the_adapter_s_numbers(models):
    """What the plant reads from the files is what the Drake adapter sets in code: the plant's config, the wheels'
    PD gains and effort limit, the friction that combines to the ground's 0.8, the tuned wheels' compliance."""
    from pydrake.geometry import Role, SceneGraph

    folder, _ = models
    for stem, step, contact in (
        ("drake-tuned", 0.004, "hydroelastic_with_fallback"),
        ("drake-shipped", 0.001, "point"),
    ):
        simulator, plant, context, robot, data = load(folder, stem)
        assert data["plant_config"]["time_step"] == plant.time_step() == step
        assert data["plant_config"]["contact_model"] == contact
        assert data["plant_config"]["discrete_contact_approximation"] == "lagged"
        for index in plant.GetJointActuatorIndices(robot):
            actuator = plant.get_joint_actuator(index)
            gains = actuator.get_controller_gains()
            assert (gains.p, gains.d, actuator.effort_limit()) == (0.0, 1.0e4, 100.0)
        diagram = simulator.get_system()
        graph = next(s for s in diagram.GetSystems() if isinstance(s, SceneGraph))
        inspector = graph.get_query_output_port().Eval(graph.GetMyContextFromRoot(simulator.get_context())).inspector()
        friction = {}
        for g in inspector.GetAllGeometryIds(Role.kProximity):
            props = inspector.GetProximityProperties(g)
            frame = inspector.GetName(inspector.GetFrameId(g)).split("::")[-1]
            friction[frame] = props.GetProperty("material", "coulomb_friction").dynamic_friction()
            if frame.endswith("wheel"):
                assert props.GetProperty("material", "hunt_crossley_dissipation") == (
                    0.2 if stem == "drake-tuned" else 50
                )
                # a compliant-hydroelastic wheel has its volume mesh; a point-contact one none
                assert (inspector.maybe_get_hydroelastic_mesh(g) is not None) == (stem == "drake-tuned")
        a, b = friction["front_left_wheel"], friction["ground"]
        assert 2 * a * b / (a + b) == pytest.approx(0.8, abs=1e-12)


def test_a_model_names_only_its_own_files_and_opens_alone_from_another_folder(models, tmp_path, monkeypatch):
    folder, _ = models
    for stem in STEMS:
        files = sorted(folder.glob(f"{stem}.*"))
        assert [f.name for f in files] == [f"{stem}.ground.sdf", f"{stem}.plant.yaml", f"{stem}.urdf"]
        for path in files:
            if path.suffix in (".urdf", ".sdf"):  # a strict parser reads them; no element names a file
                root = ET.parse(path).getroot()
                named = [v for e in root.iter() for a, v in e.attrib.items() if a in ("filename", "uri")]
                assert not named and not any(e.tag in ("uri", "include") for e in root.iter()), path.name
        alone = tmp_path / stem / "alone"
        alone.mkdir(parents=True)
        for path in files:
            shutil.copy(path, alone / path.name)
        (tmp_path / stem / "elsewhere").mkdir()
        monkeypatch.chdir(tmp_path / stem / "elsewhere")
        simulator, plant, context, robot, data = load(Path("../alone"), stem)
        simulator.AdvanceTo(10 * plant.time_step())
        assert np.isfinite(plant.GetPositions(context)).all()


def test_every_drake_profile_gets_a_model_named_by_its_urdf():
    config = study_config()
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    files = plan.model_files()
    assert files["drake-tuned"] == "results/simulators/models/drake-tuned.urdf"
    assert files["drake-shipped"] == "results/simulators/models/drake-shipped.urdf"


def test_a_suspended_robot_s_model_turns_as_the_adapter_turns_it(tmp_path):
    """The Warthog's rockers: their limits and damping on the joints, the coupling as the <mimic> Drake turns into
    a coupler constraint, their Coulomb friction as the still actuators (PD towards speed 0, effort limit the
    friction). Loaded by Drake alone it spins at the gain simpick's validation measures on the adapter (measured:
    0.5768 for 1 s at both)."""
    from simpick.engines.simulator_models import ModelRequest, write_drake_model
    from simpick.inputs.robot.settings import RobotParams
    from simpick.studies.validation.cases import Setup, run_case
    from simpick.studies.validation.settings import ValidationCase

    config = study_config()
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    urdf = str(ROOT / "resources/robot/warthog.urdf")
    robot = RobotParams.model_validate({"track": 1.1, "max_wheel_torque": 500.0})
    settings = plan.profile_settings["drake-tuned"]
    request = ModelRequest(urdf, settings, 0.8, ["a test"], robot=robot, timestep=0.001)
    for tail, text in write_drake_model(request).items():
        (tmp_path / f"drake.{tail}").write_text(text)
    _, plant, _, _, data = load(tmp_path, "drake")
    assert data["drive"]["still"] == ["left_diff_unit_jnt_friction", "right_diff_unit_jnt_friction"]
    assert plant.num_constraints() == 1  # the rockers' coupling
    setup = Setup(
        engine="drake", robot=robot.spec(urdf), timestep=0.001, max_wheel_torque=500.0, track=1.1, settings=settings
    )
    case = ValidationCase.model_validate({"kind": "yaw_gain", "v": 0.0, "w": 0.5, "mu": 0.8, "duration": DURATION})
    claimed = run_case(setup, "spin", case)["checks"][0]["engine_value"]
    assert abs(loader_gain(tmp_path, "drake", 0.0, 0.5, DURATION) - claimed) < 0.01


def test_a_calibrated_model_carries_the_fitted_compliance_and_drive(tmp_path):
    """The calibrated profile's fitted settings (the wheels' hydroelastic modulus, their PD drive's damping) reach
    the files a Drake user loads: the plant reads them from the URDF's tags, not from simpick."""
    from pydrake.geometry import Role, SceneGraph

    config = study_config()
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    params = plan.simulator_models_params()
    assert "drake-calibrated" in params["profiles"]
    params["profiles"] = {"drake-calibrated": params["profiles"]["drake-calibrated"]}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    fitted = {"hydroelastic_modulus": 3.0e6, "wheel_drive_damping": 500.0}
    fit = tmp_path / "drake.yaml"  # named as rule simulator_calibrate names a simulator's fit
    fit.write_text(yaml.safe_dump({"searchable": True, "source": "a test's runs", "settings": fitted}))
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": [str(fit)]}
    simulator_models_job(inputs, params, str(tmp_path / "models"))
    simulator, plant, context, robot, data = load(tmp_path / "models", "drake-calibrated")
    for index in plant.GetJointActuatorIndices(robot):
        gains = plant.get_joint_actuator(index).get_controller_gains()
        assert (gains.p, gains.d) == (0.0, 500.0)
    graph = next(s for s in simulator.get_system().GetSystems() if isinstance(s, SceneGraph))
    inspector = graph.get_query_output_port().Eval(graph.GetMyContextFromRoot(simulator.get_context())).inspector()
    wheels = 0
    for g in inspector.GetAllGeometryIds(Role.kProximity):
        if inspector.GetName(inspector.GetFrameId(g)).endswith("wheel"):
            props = inspector.GetProximityProperties(g)
            assert props.GetProperty("hydroelastic", "hydroelastic_modulus") == 3.0e6
            wheels += 1
    assert wheels == 4
