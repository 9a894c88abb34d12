"""The Isaac Lab, CoppeliaSim and MORSE models rule simulator_models writes (simpick.studies.simulator_models),
checked keyword by keyword. None of the three installs here (Isaac Sim needs an NVIDIA driver and Omniverse Kit,
CoppeliaSim is a binary download, MORSE needs Blender 2.79's game engine), so no test runs these scripts in the
simulator or measures a gain there. Each script is compiled and parsed with ``ast``: every keyword it passes must be
in the writer's table of the simulator's own names (each quoted from the simulator's source), and every value must
be the profile's, read here from the catalog (resources/simulators/simulators.yaml, with yaml) and the study, not
from the writer. A setting changed in the profile changes the file, and the gains a file claims are the job's."""

from __future__ import annotations

import ast
import builtins
from pathlib import Path

import pytest
import yaml
from lxml import etree

from conftest import ROOT, study_config
from simpick.config import Study
from simpick.engines.simulator_models import WRITERS, coppeliasim, isaac_lab, morse
from simpick.inputs.robot.settings import RobotParams
from simpick.plan import Plan
from simpick.studies.simulator_models import simulator_models_job

DURATION = 1.0  # s, each claimed case cut to it (the claims are compared with the job's, not measured here)
CATALOG = ROOT / "resources/simulators/simulators.yaml"
PROFILES = {
    "isaac_sim": ("isaac_sim-shipped", "isaac_sim-tuned"),
    "coppeliasim": ("coppeliasim-shipped", "coppeliasim-tuned"),
    "morse": ("morse-shipped", "morse-tuned"),
}


@pytest.fixture(scope="module")
def plan():
    config = study_config()
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture(scope="module")
def study(plan) -> dict:
    params = plan.simulator_models_params()
    return {
        "timestep": params["physics"]["timestep"],
        "torque": params["robot"]["max_wheel_torque"],
        "track": params["robot"]["track"],
        "ground_mu": params["ground_mu"],
    }


@pytest.fixture(scope="module")
def models(tmp_path_factory, plan):
    """The job's models of the profiles in PROFILES, and their claims."""
    tmp = tmp_path_factory.mktemp("vendor")
    params = plan.simulator_models_params()
    params["profiles"] = {p: params["profiles"][p] for names in PROFILES.values() for p in names}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": []}
    claims = simulator_models_job(inputs, params, str(tmp / "models"))
    return tmp / "models", claims


def quoted(simulator: str, variant: str) -> dict:
    """The catalog's quoted values of a profile: the shipped settings, the tuned ones over them (tuned)."""
    entry = yaml.safe_load(CATALOG.read_text())["simulators"][simulator]
    values = {k: v["value"] for k, v in entry["shipped"]["settings"].items()}
    if variant == "tuned":
        values |= {k: v["value"] for k, v in (entry.get("tuned") or {}).get("settings", {}).items()}
    return values


def assigned(text: str) -> dict:
    """The script compiled (valid Python), then every module-level ``NAME = literal`` it holds."""
    compile(text, "model.py", "exec")
    out = {}
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            try:
                out[node.targets[0].id] = ast.literal_eval(node.value)
            except ValueError:
                continue
    return out


def urdf_wheels(path: Path) -> set[str]:
    return {j.get("name") for j in etree.parse(str(path)).getroot().findall("joint") if j.get("type") == "continuous"}


class Findings(list):
    """What a script gets wrong, one line each naming the field, what the script holds and what it should."""

    def expect(self, what: str, got, want) -> None:
        if got != pytest.approx(want):
            self.append(f"{what}: {got} != {want}")

    def unknown(self, used, table, kind: str) -> None:
        """Each used name that the writer's quoted table of the simulator's own names lacks."""
        self.extend(f"{n} is not a quoted {kind} name" for n in sorted(used, key=str) if n not in table)


def writer(plan, study: dict, simulator: str):
    """The simulator's model writer as rule simulator_models calls it, on the study's robot: settings -> script."""
    params = plan.simulator_models_params()
    robot = RobotParams.model_validate(params["robot"])
    urdf = str(ROOT / plan.config["robot"]["urdf"])

    def write(settings: dict) -> str:
        files = WRITERS[simulator].write(
            urdf, settings, study["ground_mu"], [], robot=robot, timestep=study["timestep"]
        )
        return files["py"]

    return write


def check_claims(data: dict, claims) -> None:
    stated = {c["case"]: (c["v"], c["w"], c["duration"], c["gain"]) for c in data["CLAIMS"]}
    assert stated and stated == {c.case: (c.v, c.w, DURATION, c.gain) for c in claims}


# --- Isaac Lab -----------------------------------------------------------------------------------------------------


def check_isaac_lab(data: dict, q: dict, study: dict) -> list[str]:
    """What in the Isaac Lab script differs from Isaac Lab's names (the writer's quoted table), the catalog's
    quoted values ``q`` and the study."""
    bad = Findings()
    for variable, cls in isaac_lab.VARIABLES.items():
        bad.unknown(data[variable], isaac_lab.FIELDS[cls][1], f"{cls} field ({variable})")
    expect = bad.expect
    expect("solver_type", data["PHYSX"]["solver_type"], {"pgs": 0, "tgs": 1}[q["solver"]])
    expect("bounce_threshold_velocity", data["PHYSX"]["bounce_threshold_velocity"], q["bounce_threshold"])
    root = data["ARTICULATION_ROOT"]
    expect("position iterations", root["solver_position_iteration_count"], q["position_iterations"])
    expect("velocity iterations", root["solver_velocity_iteration_count"], q["velocity_iterations"])
    actuator = data["WHEEL_ACTUATOR"]
    expect("wheel stiffness", actuator["stiffness"], 0.0)
    expect("wheel damping", actuator["damping"], q["wheel_drive_damping"])
    expect("effort_limit_sim", actuator["effort_limit_sim"], study["torque"])
    expect("dt", data["SIMULATION"]["dt"], study["timestep"])
    expect("TIMESTEP", data["TIMESTEP"], study["timestep"])
    expect("gravity", data["SIMULATION"]["gravity"], (0.0, 0.0, -9.81))
    wheel, ground = data["WHEEL_MATERIAL"], data["GROUND_MATERIAL"]
    for m in (wheel, ground):
        expect("static = dynamic", m["static_friction"], m["dynamic_friction"])
        expect("restitution", m["restitution"], 0.0)
    if {wheel["friction_combine_mode"], ground["friction_combine_mode"]} != {"multiply"}:
        bad.append("friction_combine_mode is not multiply on both materials")
    expect("contact friction", wheel["static_friction"] * ground["static_friction"], study["ground_mu"])
    expect("ground friction", ground["static_friction"], study["ground_mu"])
    expect("COMMAND_TRACK", data["COMMAND_TRACK"], study["track"])
    return bad


@pytest.mark.parametrize("profile", PROFILES["isaac_sim"])
def test_the_isaac_lab_script_holds_isaac_lab_s_names_and_the_profile_s_values(models, study, profile):
    folder, claims = models
    text = (folder / f"{profile}.py").read_text()
    data = assigned(text)
    assert check_isaac_lab(data, quoted("isaac_sim", profile.split("-")[1]), study) == []
    check_claims(data, claims[profile])
    assert data["URDF"] == f"{profile}.urdf"
    assert {w["joint"] for w in data["WHEELS"]} == urdf_wheels(folder / f"{profile}.urdf")
    assert "NOT OPENED IN ISAAC SIM HERE" in text
    # every class the script calls is one of the table's
    called = {n.func.attr for n in ast.walk(ast.parse(text)) if isinstance(n, ast.Call) and hasattr(n.func, "attr")}
    classes = {c.rsplit(".", 1)[-1] for c in isaac_lab.FIELDS}
    assert {c for c in called if c.endswith("Cfg")} <= classes


def test_a_changed_profile_setting_or_a_wrong_value_changes_or_fails_the_isaac_lab_script(plan, study):
    settings = dict(plan.simulator_models_params()["profiles"]["isaac_sim-tuned"]["settings"])
    write = writer(plan, study, "isaac_sim")

    text = write(settings)
    q = quoted("isaac_sim", "tuned")
    assert check_isaac_lab(assigned(text), q, study) == []
    changed = assigned(write(settings | {"position_iterations": 7, "solver": "tgs", "wheel_drive_damping": 50.0}))
    assert changed["ARTICULATION_ROOT"]["solver_position_iteration_count"] == 7
    assert changed["PHYSX"]["solver_type"] == 1 and changed["WHEEL_ACTUATOR"]["damping"] == 50.0
    assert len(check_isaac_lab(changed, q, study)) == 3
    wrong = text.replace("'static_friction': 0.8", "'static_friction': 0.9", 1)
    assert wrong != text and check_isaac_lab(assigned(wrong), q, study)
    wrong = text.replace("'restitution_combine_mode'", "'restitution_mode'", 1)
    assert check_isaac_lab(assigned(wrong), q, study)


# --- CoppeliaSim ---------------------------------------------------------------------------------------------------


def coppeliasim_names(text: str, data: dict) -> set[str]:
    """Every CoppeliaSim name the script uses: the quoted constants in its data and the sim / simURDF functions its
    code calls."""
    names = set()

    def walk(value):
        if isinstance(value, dict):
            for k, v in value.items():
                walk(k)
                walk(v)
        elif isinstance(value, str) and value.startswith("sim."):
            names.add(value)

    for variable in ("INT32_PARAMS", "ENGINE_INT32_PARAMS", "FLOAT_PARAMS", "GROUND", "ROBOT_SHAPE", "WHEEL_JOINT"):
        walk(data[variable])
    for node in ast.walk(ast.parse(text)):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and isinstance(node.func.value, ast.Name)
        ):
            owner = {"sim": "sim", "simurdf": "simURDF"}.get(node.func.value.id)
            if owner:
                names.add(f"{owner}.{node.func.attr}")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "named":
            if isinstance(node.args[1], ast.Constant):
                names.add(node.args[1].value)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "RemoteAPIClient":
            names.add("RemoteAPIClient")
    return names


def check_coppeliasim(text: str, q: dict, study: dict) -> list[str]:
    data = assigned(text)
    used = coppeliasim_names(text, data)
    bad = Findings()
    bad.unknown(used, coppeliasim.NAMES, "CoppeliaSim")
    expect = bad.expect
    expect(
        "iterations",
        data["ENGINE_INT32_PARAMS"]["sim.bullet_global_constraintsolvingiterations"],
        q["solver_iterations"],
    )
    for key in ("sim.floatparam_physicstimestep", "sim.floatparam_simulation_time_step"):
        expect(key, data["FLOAT_PARAMS"][key], q["time_step"])
    expect("PHYSICS_STEP", data["PHYSICS_STEP"], q["time_step"])
    if data["INT32_PARAMS"] != {"sim.intparam_dynamic_engine": "sim.physics_bullet"}:
        bad.append(f"engine: {data['INT32_PARAMS']}")
    ground = data["GROUND"]["engine_float"]["sim.bullet_body_friction"]
    robot = data["ROBOT_SHAPE"]["engine_float"]["sim.bullet_body_friction"]
    expect("contact friction (Bullet's product)", ground * robot, study["ground_mu"])
    expect("ground friction", ground, study["ground_mu"])
    if data["GROUND"]["int32"] != {"sim.shapeintparam_static": 1, "sim.shapeintparam_respondable": 1}:
        bad.append("the ground is not static and respondable")
    expect("max torque", data["WHEEL_JOINT"]["max_torque"], study["torque"])
    if data["WHEEL_JOINT"]["int32"] != {"sim.jointintparam_dynctrlmode": "sim.jointdynctrl_velocity"}:
        bad.append("the wheels are not in velocity control")
    expect("COMMAND_TRACK", data["COMMAND_TRACK"], study["track"])
    return bad


@pytest.mark.parametrize("profile", PROFILES["coppeliasim"])
def test_the_coppeliasim_script_holds_coppeliasim_s_names_and_the_profile_s_values(models, study, profile):
    folder, claims = models
    text = (folder / f"{profile}.py").read_text()
    assert check_coppeliasim(text, quoted("coppeliasim", profile.split("-")[1]), study) == []
    data = assigned(text)
    check_claims(data, claims[profile])
    assert {w["joint"] for w in data["WHEELS"]} == urdf_wheels(folder / f"{profile}.urdf")
    assert "NOT OPENED IN COPPELIASIM HERE" in text
    # the check sees the script's calls: a name CoppeliaSim does not have fails it
    wrong = text.replace("sim.setJointTargetForce(", "sim.setJointMaxForce(", 1)
    assert wrong != text and check_coppeliasim(wrong, quoted("coppeliasim", profile.split("-")[1]), study)


def test_a_changed_profile_setting_changes_the_coppeliasim_script_and_an_unexposed_one_is_refused(plan, study):
    settings = dict(plan.simulator_models_params()["profiles"]["coppeliasim-tuned"]["settings"])
    write = writer(plan, study, "coppeliasim")

    q = quoted("coppeliasim", "tuned")
    assert check_coppeliasim(write(settings), q, study) == []
    changed = write(settings | {"solver_iterations": 70, "time_step": 0.004})
    data = assigned(changed)
    assert data["ENGINE_INT32_PARAMS"]["sim.bullet_global_constraintsolvingiterations"] == 70
    assert data["FLOAT_PARAMS"]["sim.floatparam_physicstimestep"] == 0.004
    assert len(check_coppeliasim(changed, q, study)) == 4
    for unexposed in ({"friction_ratio": 0.7}, {"contact_stiffness": 1e6}, {"spinning_friction": 0.01}):
        with pytest.raises(ValueError):
            write(settings | unexposed)


def test_the_plan_notes_the_vendor_models_as_not_opened_here(plan):
    files, notes = plan.model_files(), plan.model_notes()
    for simulator, profiles in PROFILES.items():
        label = plan.catalog.simulators[simulator].label
        for p in profiles:
            assert files[p] == f"results/simulators/models/{p}.py"
            assert notes[p] == f"fields checked; not opened in {label} here"


# --- MORSE ---------------------------------------------------------------------------------------------------------

PYTHON_OWN = {"items"}  # the script's own Python: a dict's items()


def morse_names(text: str, data: dict) -> set[str]:
    """Every MORSE and Blender name the builder script uses: what it imports from morse.builder, every attribute,
    keyword and called name its code holds (its own functions and Python's builtins aside), the module it makes the
    robot's logic, and the keys and names its data hands to Blender and MORSE."""
    tree = ast.parse(text)
    own = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            names.add(node.module)
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.Attribute) and node.attr not in PYTHON_OWN:
            names.add(node.attr)
        elif isinstance(node, ast.Call):
            names |= {k.arg for k in node.keywords if k.arg}
            if isinstance(node.func, ast.Name) and node.func.id not in own and node.func.id not in dir(builtins):
                names.add(node.func.id)
            if isinstance(node.func, ast.Attribute) and node.func.attr == "morseable":
                names |= {a.value for a in node.args if isinstance(a, ast.Constant)}
    for part in (data["CHASSIS"], *data["WHEEL_BODIES"]):
        names |= set(part["game"])
        names |= {part["game"].get("physics_type"), part["game"].get("collision_bounds_type")} - {None}
    names |= set(data["ROBOT_PROPERTIES"]) | {data["ROBOT_PROPERTIES"]["classpath"]}
    names |= {data["ENVIRONMENT"], data["GROUND"]["object"], data["INTERFACE"]}
    return names


def urdf_parts(path: Path) -> dict:
    """The description read here, apart from the writer: each continuous joint's child link -> (origin xyz, mass,
    cylinder radius, length), and the whole robot's mass."""
    root = etree.parse(str(path)).getroot()
    links = {link.get("name"): link for link in root.findall("link")}
    mass = {n: float(link.find("inertial/mass").get("value")) for n, link in links.items()}
    wheels = {}
    for joint in root.findall("joint"):
        if joint.get("type") == "continuous":
            child = joint.find("child").get("link")
            cylinder = links[child].find("collision/geometry/cylinder")
            xyz = tuple(float(v) for v in joint.find("origin").get("xyz").split())
            wheels[child] = (xyz, mass[child], float(cylinder.get("radius")), float(cylinder.get("length")))
    return {"wheels": wheels, "mass": sum(mass.values())}


def check_morse(text: str, q: dict, study: dict, parts: dict) -> list[str]:
    """What in the MORSE builder script differs from MORSE's and Blender's names (the writer's quoted table), the
    catalog's quoted values ``q``, the study and the robot's description (``parts``)."""
    data = assigned(text)
    bad = Findings()
    bad.unknown(morse_names(text, data), morse.NAMES, "MORSE or Blender")
    expect = bad.expect
    expect("FPS (1 / time_step)", data["FPS"], round(1.0 / q["time_step"]))
    expect("PHYSICS_STEP_SUB", data["PHYSICS_STEP_SUB"], q["sub_steps"])
    ground = data["GROUND"]["friction"]
    expect("ground friction", ground, study["ground_mu"])
    expect("chassis contact (Bullet's product)", data["CHASSIS"]["friction"] * ground, study["ground_mu"])
    ratio = q.get("friction_ratio", 1.0)
    wheels = {w["name"]: w for w in data["WHEEL_BODIES"]}
    if set(wheels) != set(parts["wheels"]):
        bad.append(f"wheels {sorted(wheels)} are not the description's {sorted(parts['wheels'])}")
    for name, (xyz, mass, radius, length) in parts["wheels"].items():
        w = wheels.get(name)
        if w is None:
            continue
        expect(f"{name} mass", w["game"]["mass"], mass)
        expect(f"{name} radius", w["radius"], radius)
        expect(f"{name} width", w["width"], length)
        expect(f"{name} x, y", w["location"][:2], xyz[:2])
        coefficients = w["game"].get("friction_coefficients", (1.0, 1.0, 1.0))
        lateral = coefficients[2] * w["friction"] * ground
        rolling = coefficients[0] * w["friction"] * ground
        expect(f"{name} rolling friction", rolling, study["ground_mu"])
        expect(f"{name} lateral / rolling", lateral / rolling, ratio)
        expect(f"{name} anisotropic", w["game"]["use_anisotropic_friction"], ratio != 1.0)
        if (w["game"].get("physics_type"), w["game"].get("collision_bounds_type")) != ("RIGID_BODY", "CYLINDER"):
            bad.append(f"{name} is not a rigid cylinder")
    chassis_mass = parts["mass"] - sum(m for _, m, _, _ in parts["wheels"].values())
    expect("chassis mass (the rest of the robot)", data["CHASSIS"]["game"]["mass"], chassis_mass)
    chassis = data["CHASSIS"]["game"]
    if (chassis.get("physics_type"), chassis.get("collision_bounds_type")) != ("RIGID_BODY", "BOX"):
        bad.append("the chassis is not a rigid box")
    props = data["ROBOT_PROPERTIES"]
    expect("FixTurningSpeed", props["FixTurningSpeed"], study["track"])
    if props["HasSuspension"] is not False:
        bad.append("HasSuspension is not False")
    slots = {slot: props[f"Wheel{slot}Name"] for slot in ("FL", "FR", "RL", "RR")}
    for slot, name in slots.items():
        w = wheels.get(name)
        if w is None or (w["location"][0] > 0) != (slot[0] == "F") or (w["location"][1] > 0) != (slot[1] == "L"):
            bad.append(f"Wheel{slot}Name {name} is not the {slot} wheel")
    expect("WHEEL_ROLL", data["WHEEL_ROLL"], 1.5707963267948966)
    return bad


@pytest.fixture(scope="module")
def husky(plan) -> dict:
    return urdf_parts(ROOT / plan.config["robot"]["urdf"])


@pytest.mark.parametrize("profile", PROFILES["morse"])
def test_the_morse_script_holds_morse_s_and_blender_s_names_and_the_profile_s_values(models, study, husky, profile):
    folder, claims = models
    assert not (folder / f"{profile}.urdf").exists()  # the robot is built from its parts
    text = (folder / f"{profile}.py").read_text()
    q = quoted("morse", profile.split("-")[1])
    assert check_morse(text, q, study, husky) == []
    data = assigned(text)
    check_claims(data, claims[profile])
    assert "NOT OPENED IN MORSE HERE" in text
    # a name MORSE does not have fails the check: a builder call, a Blender key in the data
    wrong = text.replace("env.set_physics_step_sub(", "env.set_physics_substeps(", 1)
    assert wrong != text and check_morse(wrong, q, study, husky)
    wrong = text.replace("'collision_bounds_type'", "'collision_shape'", 1)
    assert wrong != text and check_morse(wrong, q, study, husky)


def test_a_changed_profile_setting_changes_the_morse_script_and_an_unexposed_one_is_refused(plan, study, husky):
    settings = dict(plan.simulator_models_params()["profiles"]["morse-tuned"]["settings"])
    write = writer(plan, study, "morse")

    q = quoted("morse", "tuned")
    assert check_morse(write(settings), q, study, husky) == []
    changed = write(settings | {"sub_steps": 3, "time_step": 0.01})
    data = assigned(changed)
    assert (data["FPS"], data["PHYSICS_STEP_SUB"]) == (100, 3)
    assert len(check_morse(changed, q, study, husky)) == 2
    # the friction ratio as Blender holds it: below 1 along the axle, above 1 over the rolling axes and the friction
    for ratio in (0.3, 1.5):
        text = write(settings | {"friction_ratio": ratio})
        assert check_morse(text, q | {"friction_ratio": ratio}, study, husky) == []
        assert check_morse(text, q, study, husky)
        wheel = assigned(text)["WHEEL_BODIES"][0]
        assert all(0 < c <= 1 for c in wheel["game"]["friction_coefficients"])
        assert wheel["friction"] == pytest.approx(max(1.0, ratio))
    for unexposed in (
        {"contact_stiffness": 1e6},
        {"spinning_friction": 0.01},
        {"solver_iterations": 50},
        {"contact_erp": 0.08},
        {"time_step": 0.007},
    ):
        with pytest.raises(ValueError):
            write(settings | unexposed)


def test_the_morse_writer_takes_only_robots_morse_s_wheeled_robot_holds(plan):
    from dataclasses import replace

    spec = plan.robot
    writes = WRITERS["morse"].writes
    assert writes(spec)
    assert not writes(replace(spec, wheels=spec.wheels[:3]))  # one side short
    assert not writes(
        replace(spec, wheels=tuple(replace(w, radius=w.radius * (1 + i)) for i, w in enumerate(spec.wheels)))
    )
    assert not writes(replace(spec, rigid=None))
    from simpick.inputs.robot import load_robot

    warthog = load_robot(ROOT / "resources" / "robot" / "warthog.urdf")  # its rockers: no wheel on the chassis
    assert warthog.suspension and not writes(warthog)
