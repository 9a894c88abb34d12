"""The settings files a simulator's user pastes, read by the simulators' own readers: every XML file through a
strict parser, the wheels' <gazebo> tags through sdformat's URDF conversion (Debian's sdformat 12, ``ign sdf``)
with each value asserted at the element Gazebo reads, the MJCF merged into the robot and stepped in MuJoCo, the
Drake YAML and tags through Drake's own loaders, the Genesis and Newton blocks through their own classes (in
their venvs), and the names of the simulators no reader here installs against tables quoted from their source."""

from __future__ import annotations

import shutil
import subprocess
import xml.etree.ElementTree as ET

import pandas as pd
import pytest
from lxml import etree

from conftest import ROOT, tiny_config
from simpick.config import Study
from simpick.engines import get_engine
from simpick.engines import simulator_files as formats
from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import SIMULATORS, VARIANTS
from simpick.plan import Plan

CATALOG = ROOT / "resources/simulators/simulators.yaml"
HUSKY_URDF = ROOT / "resources/robot/husky_a200.urdf"
HUSKY = "husky_a200"
WHEELS = ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"]


@pytest.fixture(scope="module")
def catalog():
    return load_catalog(CATALOG)


def _settings(catalog, simulator: str, variant: str, robot: str = HUSKY, **over) -> dict:
    model = get_engine(catalog.simulators[simulator].engine).settings_model
    return model.model_validate({**catalog.settings(simulator, variant, robot), **over}).model_dump(mode="json")


@pytest.fixture(scope="module")
def written(tmp_path_factory, catalog):
    """Every file rule simulator_settings writes for every runnable profile, with the job's real header."""
    from simpick.score.simulator_settings import settings_files_job

    tmp = tmp_path_factory.mktemp("settings")
    config = tiny_config(tmp)
    config["simulators"]["run"] = None
    from simpick.engines import PROFILE_ADAPTERS

    # the study's engines: every simulator's, less those that run only behind a simulator's profiles (gz-physics)
    config["engines"] = {
        SIMULATORS[s]: None for s in SIMULATORS if SIMULATORS[s] is not None and SIMULATORS[s] not in PROFILE_ADAPTERS
    }
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    params = {k: v for k, v in plan.simulator_settings_params().items() if k != "code"}
    rows = [
        {
            "simulator": s,
            "variant": v,
            "gain_flat": 0.47,
            "gain_flat_min": 0.46,
            "gain_flat_max": 0.48,
            "gain_coulomb": 0.478,
            "mechanics": "passes",
            "mechanics_cases": 20,
            "mechanics_failed": 0,
            "gain_error": 0.2,
            "gain_outcome": "undetermined",
        }
        for s in SIMULATORS
        for v in VARIANTS
    ]
    table = tmp / "table.csv"
    pd.DataFrame(rows).to_csv(table, index=False)
    out = tmp / "out"
    settings_files_job({"catalog": str(CATALOG), "table": str(table)}, params, str(out))
    return out, params


def test_every_xml_file_the_job_writes_parses_in_a_strict_parser(written):
    out, params = written
    xml = sorted(p for p in out.iterdir() if p.suffix in (".sdf", ".urdf", ".xml"))
    # the Gazebo pair for both Gazebos, the MJCF, Drake's tags: every simulator with an XML format
    assert {p.name.split("-")[0] for p in xml} >= {"gazebo", "gazebo_classic", "mujoco", "drake"}, xml
    for path in xml:
        text = path.read_text()
        assert "regenerate: snakemake" in text, path.name  # the job's own header, not a test's
        etree.fromstring(text.encode(), etree.XMLParser(resolve_entities=False))  # raises on `--` in a comment
        ET.fromstring(text)


def test_a_long_option_in_a_header_stays_a_legal_comment():
    text = formats.xml_comment(["snakemake --cores 2 --configfile x.yaml", "ends with -"])
    root = etree.fromstring((text + "<robot/>").encode(), etree.XMLParser())
    assert root.tag == "robot"
    assert "- -cores 2" in text


# --- Gazebo Classic and Gazebo: sdformat's own conversion ---


def _ign(*args: str) -> str:
    ign = shutil.which("ign")
    if ign is None:
        pytest.fail("ign (Debian ignition-tools with sdformat 12) is not installed: make (the set-up) installs it")
    done = subprocess.run([ign, "sdf", *args], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


def _merged(tags: str, tmp_path) -> str:
    """The Husky URDF with the file's <gazebo> tags pasted into its <robot>, converted by sdformat (ign sdf -p)."""
    robot = ET.parse(HUSKY_URDF).getroot()
    for gazebo in ET.fromstring(tags).findall("gazebo"):
        robot.append(gazebo)
    path = tmp_path / "husky_with_tags.urdf"
    ET.ElementTree(robot).write(path)
    _ign("-k", str(path))
    return _ign("-p", str(path))


def _surfaces(sdf: str) -> dict[str, ET.Element]:
    """link name -> the surface of its (first) collision in the converted SDF."""
    model = ET.fromstring(sdf).find("model")
    return {link.get("name"): link.find("collision/surface") for link in model.findall("link")}


def test_gazebo_classic_tags_land_in_each_wheel_collision_s_surface_after_sdformat(catalog, tmp_path):
    # the tuned Husky profile with every surface setting the writer knows set, as a calibrated one may
    settings = _settings(catalog, "gazebo_classic", "tuned", friction_ratio=0.62, contact_max_vel=0.02)
    texts = formats.write_profile_file("sdf", "ode", settings, ["t"], WHEELS, ground_mu=0.8)
    sdf = _merged(texts["wheels.urdf"], tmp_path)
    surfaces = _surfaces(sdf)
    for wheel in WHEELS:
        s = surfaces[wheel]
        assert s is not None, wheel
        f, c = s.find("friction/ode"), s.find("contact/ode")
        assert float(f.findtext("mu")) == pytest.approx(0.8)
        assert float(f.findtext("mu2")) == pytest.approx(0.62 * 0.8)
        assert f.findtext("fdir1").split() == ["1", "0", "0"]
        # Gazebo Classic sums the two surfaces' slip and multiplies by the pair's contact count (2 here)
        assert float(f.findtext("slip1")) == pytest.approx(settings["contact_slip"] / 2)
        assert float(f.findtext("slip2")) == pytest.approx(settings["contact_slip"] / 2)
        # kp in series with the ground's 1e12 gives the contact's; kd summed with its 1
        kp = float(c.findtext("kp"))
        assert 1 / (1 / kp + 1 / 1e12) == pytest.approx(settings["contact_kp"], rel=1e-5)
        assert float(c.findtext("kd")) + 1.0 == pytest.approx(settings["contact_kd"])
        assert float(c.findtext("max_vel")) == pytest.approx(0.02)
        assert float(c.findtext("min_depth")) == pytest.approx(0.0)
    # nothing left on the links, where Gazebo reads no surface
    model = ET.fromstring(sdf).find("model")
    assert not [e for link in model.findall("link") for e in link if e.tag in ("slip1", "slip2", "surface")]


def test_the_old_way_leaves_slip_on_the_link(tmp_path):
    # the reason for the <collision> blob: sdformat maps only a list of <gazebo> children into <collision>
    tags = '<robot name="t"><gazebo reference="front_left_wheel"><mu1>0.8</mu1><slip1>0.002</slip1></gazebo></robot>'
    sdf = _merged(tags, tmp_path)
    link = ET.fromstring(sdf).find("model/link[@name='front_left_wheel']")
    assert link.find("slip1") is not None and link.find("collision/surface/friction/ode/slip1") is None
    assert float(link.findtext("collision/surface/friction/ode/mu")) == pytest.approx(0.8)


def test_gazebo_sdf_settings_named_after_the_elements_reach_their_elements(tmp_path):
    # a gz-physics profile names its settings after the SDF elements (and friction_ratio for mu2)
    settings = {
        "collision_detector": "bullet",
        "solver_type": "pgs",
        "mu": 0.9,
        "friction_ratio": 0.6,
        "fdir1": [1, 0, 0],
        "slip1": 0.003,
        "slip2": 0.001,
        "kp": 1e6,
        "kd": 50.0,
    }
    texts = formats.write_profile_file("sdf", "gz_physics", settings, ["snakemake --cores 2"], WHEELS)
    world = tmp_path / "world.sdf"
    world.write_text(texts["world.sdf"])
    _ign("-k", str(world))
    physics = ET.fromstring(_ign("-p", str(world))).find("world/physics")
    assert physics.get("type") == "dart"
    assert physics.findtext("dart/collision_detector") == "bullet"
    assert physics.findtext("dart/solver/solver_type") == "pgs"
    s = _surfaces(_merged(texts["wheels.urdf"], tmp_path))["rear_right_wheel"]
    f, c = s.find("friction/ode"), s.find("contact/ode")
    assert float(f.findtext("mu")) == pytest.approx(0.9) and float(f.findtext("mu2")) == pytest.approx(0.54)
    assert f.findtext("fdir1").split() == ["1", "0", "0"]
    assert float(f.findtext("slip1")) == pytest.approx(0.003) and float(f.findtext("slip2")) == pytest.approx(0.001)
    assert float(c.findtext("kp")) == pytest.approx(1e6) and float(c.findtext("kd")) == pytest.approx(50.0)
    assert formats.read("sdf", "gz_physics", texts)["slip2"] == pytest.approx(0.001)


@pytest.mark.parametrize("simulator", ["gazebo", "gazebo_classic"])
@pytest.mark.parametrize("variant", VARIANTS)
def test_the_catalog_s_gazebo_worlds_are_valid_sdf(catalog, simulator, variant, tmp_path):
    sim = catalog.simulators[simulator]
    settings = _settings(catalog, simulator, variant)
    texts = formats.write_profile_file("sdf", sim.engine, settings, ["t"], WHEELS, catalog.entries(simulator, variant))
    path = tmp_path / "world.sdf"
    path.write_text(texts["world.sdf"])
    _ign("-k", str(path))
    physics = ET.fromstring(_ign("-p", str(path))).find("world/physics")
    if sim.engine == "ode":
        assert physics.findtext("ode/solver/type") == settings["stepper"]
        assert int(physics.findtext("ode/solver/iters")) == settings["quick_iterations"]
        assert float(physics.findtext("ode/constraints/contact_max_correcting_vel")) == pytest.approx(
            settings["contact_max_correcting_vel"]
        )
    else:
        assert physics.findtext("dart/collision_detector") == settings["collision_detector"]


# --- Drake: its own YAML loader and URDF parser ---


@pytest.mark.parametrize("variant", VARIANTS)
def test_the_drake_files_load_through_drake_s_own_readers(catalog, variant, tmp_path):
    from pydrake.common.yaml import yaml_load_typed
    from pydrake.geometry import Role
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
    from pydrake.systems.framework import DiagramBuilder

    settings = _settings(catalog, "drake", variant)
    texts = formats.write_profile_file("drake", "drake", settings, ["t"], WHEELS, catalog.entries("drake", variant))
    config = yaml_load_typed(schema=MultibodyPlantConfig, data=texts["yaml"])
    assert config.time_step == pytest.approx(settings.get("time_step") or 0.001)
    assert config.contact_model == (
        "hydroelastic_with_fallback" if settings["contact_model"] == "hydroelastic" else "point"
    )
    assert config.discrete_contact_approximation == settings["discrete_approximation"]
    assert config.stiction_tolerance == pytest.approx(settings["stiction_tolerance"])

    # the tags pasted inside each wheel's <collision> of the Husky URDF, parsed by Drake
    props = ET.fromstring(texts["wheels.urdf"]).find("{http://drake.mit.edu}proximity_properties")
    text = HUSKY_URDF.read_text().replace("<robot ", '<robot xmlns:drake="http://drake.mit.edu" ', 1)
    robot = ET.fromstring(text)
    for link in robot.findall("link"):
        if link.get("name") in WHEELS:
            link.find("collision").append(props)
    ET.register_namespace("drake", "http://drake.mit.edu")  # Drake's parser reads the literal drake: prefix
    path = tmp_path / "husky.urdf"
    path.write_text(ET.tostring(robot, encoding="unicode"))
    assert "<drake:hunt_crossley_dissipation" in path.read_text()
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(config, builder)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    inspector = scene_graph.model_inspector()
    for wheel in WHEELS:
        (geometry,) = plant.GetCollisionGeometriesForBody(plant.GetBodyByName(wheel))
        p = inspector.GetProperties(geometry, Role.kProximity)
        assert p.GetProperty("material", "hunt_crossley_dissipation") == pytest.approx(settings["wheel_dissipation"])
        if settings["contact_model"] == "hydroelastic":
            assert p.GetProperty("hydroelastic", "hydroelastic_modulus") == pytest.approx(
                settings["hydroelastic_modulus"]
            )
            assert p.HasProperty("hydroelastic", "compliance_type")
            assert p.GetProperty("hydroelastic", "resolution_hint") == pytest.approx(settings["mesh_resolution"])


def test_a_fitted_drake_drive_damping_reaches_the_wheels_transmissions_as_drake_reads_them(catalog, tmp_path):
    """The calibrated Drake profile fits its wheels' PD damping: the fragment carries it as <drake:controller_gains>,
    which Drake's parser gives each wheel's actuator once pasted into a SimpleTransmission's <actuator>."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
    from pydrake.systems.framework import DiagramBuilder

    settings = {**_settings(catalog, "drake", "tuned"), "wheel_drive_damping": 750.0, "hydroelastic_modulus": 2.0e6}
    texts = formats.write_profile_file("drake", "drake", settings, ["t"], WHEELS, catalog.entries("drake", "tuned"))
    assert formats.read("drake", "drake", texts)["wheel_drive_damping"] == 750.0
    assert formats.read("drake", "drake", texts)["hydroelastic_modulus"] == 2.0e6
    gains = ET.fromstring(texts["wheels.urdf"]).find("{http://drake.mit.edu}controller_gains")
    text = HUSKY_URDF.read_text().replace("<robot ", '<robot xmlns:drake="http://drake.mit.edu" ', 1)
    robot = ET.fromstring(text)
    joints = {j.find("child").get("link"): j.get("name") for j in robot.findall("joint")}
    for wheel in WHEELS:
        transmission = ET.SubElement(robot, "transmission", name=f"{wheel}_trans")
        ET.SubElement(transmission, "type").text = "transmission_interface/SimpleTransmission"
        ET.SubElement(transmission, "joint", name=joints[wheel])
        ET.SubElement(transmission, "actuator", name=f"{wheel}_motor").append(gains)
    ET.register_namespace("drake", "http://drake.mit.edu")
    path = tmp_path / "husky.urdf"
    path.write_text(ET.tostring(robot, encoding="unicode"))
    plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=0.001), DiagramBuilder())
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    for wheel in WHEELS:
        actuator = plant.GetJointActuatorByName(f"{wheel}_motor")
        assert (actuator.get_controller_gains().p, actuator.get_controller_gains().d) == (0.0, 750.0)


# --- Newton and Genesis: their own classes, in their own venvs ---


def _venv_run(engine: str, code: str, *args: str) -> list[str]:
    """The ``R ...`` lines ``code`` prints in ``engine``'s own venv."""
    from simpick.engines import isolated

    python = isolated.venv_python(engine)
    if not python or not shutil.os.path.exists(python):
        pytest.fail(f"{engine}'s venv is missing: make engine-venvs")
    done = subprocess.run([python, "-c", code, *args], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-3000:]
    return [line[2:] for line in done.stdout.splitlines() if line.startswith("R ")]


NEWTON_CHECK = """
import runpy, sys, newton
from newton.solvers import SolverMuJoCo
for path in sys.argv[1:]:
    file = runpy.run_path(path)
    builder = newton.ModelBuilder()
    SolverMuJoCo.register_custom_attributes(builder)
    ground = builder.add_ground_plane()
    wheel = builder.add_shape_sphere(builder.add_body(), radius=0.1)
    pairs = file.get("add_custom_values_kwargs")
    if pairs is not None:
        builder.add_shape_collision_filter_pair(ground, wheel)
        builder.add_custom_values(**{"mujoco:pair_geom1": ground, "mujoco:pair_geom2": wheel, **pairs})
    solver = SolverMuJoCo(builder.finalize(device="cpu"), use_mujoco_cpu=True, **file["solvermujoco_kwargs"])
    m = solver.mj_model
    row = [m.npair, int(m.opt.cone), float(m.opt.impratio)]
    if m.npair:
        row += [*m.pair_friction[0][:2], *m.pair_solref[0], *m.pair_solreffriction[0], m.pair_solimp[0][0]]
    print("R", *row)
"""


@pytest.mark.slow  # Newton's own venv (make engine-venvs)
def test_the_newton_file_s_keywords_build_newton_s_solver_and_pairs(catalog, tmp_path):
    paths, profiles = [], []
    for variant in VARIANTS:
        settings = _settings(catalog, "isaac_lab_newton", variant)
        text = formats.write_profile_file("newton", "newton", settings, ["t"], WHEELS, ground_mu=0.7)["py"]
        assert "contact_kwargs" not in text
        path = tmp_path / f"newton_{variant}.py"
        path.write_text(text)
        paths.append(str(path))
        profiles.append(settings)
    rows = _venv_run("newton", NEWTON_CHECK, *paths)
    assert len(rows) == len(profiles)
    for settings, row in zip(profiles, rows, strict=True):
        values = [float(x) for x in row.split()]
        assert int(values[1]) == (1 if settings["mujoco_cone"] == "elliptic" else 0)
        if settings["wheel_contact"] == "pairs":
            d, df = settings["wheel_contact_impedance"], settings["wheel_friction_impedance"]
            assert int(values[0]) == 1
            assert values[2] == pytest.approx(((1 - d) / d) / ((1 - df) / df), rel=1e-5)
            f1, f2, r1, _, rf1, _, solimp = values[3:]
            assert (f1, f2) == pytest.approx((0.7, 0.7))  # the ground's, not MuJoCo's pair default 1
            assert (r1, rf1, solimp) == pytest.approx((0.02, 0.02 * 0.95 / d, d), rel=1e-5)
        else:
            assert int(values[0]) == 0


GENESIS_CHECK = """
import runpy, sys, genesis as gs
gs.init(backend=gs.cpu, logging_level="warning")
urdf_file = sys.argv[1]
for path in sys.argv[2:]:
    file = runpy.run_path(path)
    rigid = gs.options.RigidOptions(**file["rigidoptions_kwargs"])
    urdf = gs.morphs.URDF(file=urdf_file, **file["urdf_kwargs"])
    name = file["rigidoptions_kwargs"]["friction_cone"].name
    try:
        gs.options.RigidOptions(friction_cone=name)
        refused = False
    except Exception:
        refused = True
    print("R", name, rigid.friction_cone == getattr(gs.friction_cone, name), urdf.default_armature, refused)
"""


@pytest.mark.slow  # Genesis's own venv (make engine-venvs)
def test_the_genesis_file_s_keywords_pass_genesis_s_strict_options(catalog, tmp_path):
    paths, profiles = [], []
    for variant in VARIANTS:
        settings = _settings(catalog, "genesis", variant)
        path = tmp_path / f"genesis_{variant}.py"
        path.write_text(formats.write_profile_file("genesis", "genesis", settings, ["t"], WHEELS)["py"])
        paths.append(str(path))
        profiles.append(settings)
    rows = _venv_run("genesis", GENESIS_CHECK, str(HUSKY_URDF), *paths)
    assert len(rows) == len(profiles)
    for settings, row in zip(profiles, rows, strict=True):
        name, same, armature, refused = row.split()
        assert name == settings["friction_cone"] and same == "True"
        assert armature == str(settings["default_armature"])
        assert refused == "True"  # Genesis's strict options take the enum, not its name: why the file gives the enum


# --- Webots, CoppeliaSim, Isaac Lab: every name the files use, in the simulator's own source ---


def _names(fmt: str, text: str) -> set[str]:
    import re

    body = "\n".join(line.split("#")[0] if fmt == "webots" else line for line in text.splitlines())
    if fmt == "webots":
        return set(re.findall(r"^\s*([A-Za-z]\w*)\b", body, re.M)) - {"}"}
    if fmt == "coppeliasim":
        code = "\n".join(line for line in body.splitlines() if not line.lstrip().startswith("--"))
        return set(re.findall(r"\bsim\.\w+", code))
    import ast

    names = set()
    for node in ast.parse(text).body:
        if isinstance(node, ast.ImportFrom):
            names |= {f"{node.module}.{a.name}" for a in node.names}
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            cls = node.targets[0].id.removesuffix("_kwargs")
            names |= {f"{cls}.{ast.literal_eval(k)}" for k in node.value.keys}
    return names


@pytest.mark.parametrize(
    "simulator,fmt", [("webots", "webots"), ("coppeliasim", "coppeliasim"), ("isaac_sim", "isaaclab")]
)
@pytest.mark.parametrize("variant", VARIANTS)
def test_every_name_a_file_uses_is_in_the_simulator_s_quoted_reference(catalog, simulator, fmt, variant):
    from simpick.engines.simulator_names import NAMES

    settings = _settings(catalog, simulator, variant)
    texts = formats.write_profile_file(fmt, SIMULATORS[simulator], settings, ["t"], WHEELS)
    (text,) = texts.values()
    used = _names(fmt, text)
    table = NAMES[fmt]
    assert used and used <= set(table["names"]), sorted(used - set(table["names"]))
    assert table["version"] and all(table["names"][n].strip() for n in used)


def test_webots_coulomb_friction_is_lateral_then_longitudinal_on_the_wheel_as_webots_reads_it(catalog):
    """Webots' rule (simpick.engines.simulator_files, quoted in simulator_names): ODE's fdir1 is material1's first
    friction direction, a Cylinder's is its axis on its side, and three values give mu = [0] + [2] along fdir1 and
    mu2 = [1] + [2] across it. The Husky's wheel Cylinder lies along its joint's axis, so [0] is the friction across
    the wheel and [1] along its rolling direction: their ratio is the profile's friction_ratio."""
    import math
    import re

    from simpick.engines.simulator_names import NAMES

    quoted = NAMES["webots"]["names"]
    assert "[0] + [2]" in quoted["coulombFriction"] and "WbCylinder.cpp:549-556" in quoted["coulombFriction"]
    assert "fdir1" in quoted["material1"]
    # the wheel Cylinder's axis (URDF: the collision frame's z, turned by its rpy) is its joint's axis, the axle
    robot = ET.parse(HUSKY_URDF).getroot()
    link = robot.find(f"link[@name='{WHEELS[0]}']")
    roll, pitch, _ = (float(x) for x in link.find("collision/origin").get("rpy").split())
    cylinder_axis = (math.sin(pitch), -math.sin(roll) * math.cos(pitch), math.cos(roll) * math.cos(pitch))
    joint_axis = [float(x) for x in robot.find(f"joint[@name='{WHEELS[0]}_joint']/axis").get("xyz").split()]
    assert link.find("collision/geometry/cylinder") is not None
    assert abs(sum(a * b for a, b in zip(cylinder_axis, joint_axis))) == pytest.approx(1.0)

    settings = _settings(catalog, "webots", "tuned", friction_ratio=0.6, friction_direction="wheel")  # calibration.yaml
    text = formats.write_profile_file("webots", SIMULATORS["webots"], settings, ["t"], WHEELS)["wbt"]
    body = "\n".join(line.split("#")[0] for line in text.splitlines())
    assert re.search(r'material1\s+"wheel"', body) and "material2" not in body  # the wheel's directions first
    values = [float(v) for v in re.search(r"coulombFriction\s+\[([^\]]*)\]", body).group(1).split()]
    assert len(values) == 3  # the ground symmetric: no mixing by the heading
    along_axle, along_rolling = values[0] + values[2], values[1] + values[2]
    assert along_rolling == pytest.approx(formats.GROUND_MU)
    assert along_axle / along_rolling == pytest.approx(0.6)
    rotation = re.search(r"frictionRotation\s+(\S+)\s+(\S+)", body)
    assert rotation is None or float(rotation.group(1)) == 0.0  # fdir1 not turned off the axis
    assert formats.read_webots(text)["friction_ratio"] == pytest.approx(0.6)


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_newton_file_says_why_it_has_no_friction_ratio_in_the_calibration_s_words(catalog, variant):
    """The Newton adapter has no friction_ratio, so no Isaac Lab 3 profile carries one (calibration.yaml's
    if_unbound): the file writes the pairs' tangential frictions equal and its header quotes that reason."""
    import ast

    import yaml

    from simpick.engines.newton_engine import NewtonSettings

    assert "friction_ratio" not in NewtonSettings.model_fields  # else the ratio belongs in mujoco:pair_friction
    reason = yaml.safe_load((ROOT / "resources/simulators/calibration.yaml").read_text())["simulators"][
        "isaac_lab_newton"
    ]["if_unbound"]
    settings = _settings(catalog, "isaac_lab_newton", variant)
    text = formats.write_profile_file("newton", SIMULATORS["isaac_lab_newton"], settings, ["t"], WHEELS)["py"]
    header = " ".join(line.removeprefix("# ") for line in text.splitlines() if line.startswith("#"))
    assert reason in header and "no friction ratio" in header
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            values = dict(zip(map(ast.literal_eval, node.value.keys), node.value.values, strict=True))
            if "mujoco:pair_friction" in values:
                tangent1, tangent2, *_ = ast.literal_eval(values["mujoco:pair_friction"])
                assert tangent1 == tangent2 == formats.GROUND_MU


# --- MuJoCo: the fragment merged into the robot's MJCF, loaded and stepped by MuJoCo ---


def _husky_mjcf() -> str:
    """The Husky as MuJoCo imports its URDF, with a floor, a free base and the adapter's wheel servos (intvelocity,
    kp 1000, 100 N m), its wheel geoms named after their links: the robot file a user pastes the fragment into."""
    import mujoco

    spec = mujoco.MjSpec.from_file(str(HUSKY_URDF))
    spec.compiler.discardvisual = False  # the URDF importer's default would drop the non-colliding wheel geoms
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], friction=[1.0, 0, 0])
    spec.body("base_link").add_freejoint()
    spec.body("base_link").pos = [0, 0, 0.1323 + 0.002]
    for wheel in WHEELS:
        (geom,) = spec.body(wheel).geoms
        geom.name = wheel
        geom.contype = geom.conaffinity = 0  # the pairs alone touch the floor, as in the adapter
        act = spec.add_actuator(name=wheel, target=f"{wheel}_joint", trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_intvelocity(kp=1000.0, dampratio=1.0)
        act.actlimited = mujoco.mjtLimited.mjLIMITED_FALSE
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-100.0, 100.0]
    spec.option.timestep = 0.001
    return spec.to_xml()


def _merge(robot: str, fragment: str) -> str:
    root, frag = ET.fromstring(robot), ET.fromstring(fragment)
    option = root.find("option")
    if option is None:
        option = ET.SubElement(root, "option")
    option.attrib.update(frag.find("option").attrib)
    root.append(frag.find("contact"))
    return ET.tostring(root, encoding="unicode")


def _mjcf_gain(xml: str, v: float = 0.5, w: float = 0.5, track: float = 0.555, seconds: float = 4.0) -> float:
    import mujoco
    import numpy as np

    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    radius = 0.1651
    left, right = (v - w * track / 2) / radius, (v + w * track / 2) / radius
    data.ctrl[:] = [left if "left" in model.actuator(i).name else right for i in range(model.nu)]
    steps = int(seconds / model.opt.timestep)
    yaw = []
    for k in range(steps):
        mujoco.mj_step(model, data)
        if k >= steps // 2:
            yaw.append(data.qvel[5])
    return float(np.mean(yaw)) / w


@pytest.fixture(scope="module")
def husky_mjcf():
    return _husky_mjcf()


def test_the_mjcf_pairs_carry_the_ground_s_friction_in_mujoco(catalog, husky_mjcf):
    import mujoco

    settings = _settings(catalog, "mujoco", "tuned")
    fragment = formats.write_profile_file("mjcf", "mujoco", settings, ["snakemake --cores 2"], WHEELS, ground_mu=0.3)
    model = mujoco.MjModel.from_xml_string(_merge(husky_mjcf, fragment["xml"]))
    assert model.npair == 4
    for i in range(model.npair):
        assert model.pair_friction[i][:2] == pytest.approx([0.3, 0.3])  # the ground's, not MuJoCo's pair default 1
        assert model.pair_solimp[i][0] == pytest.approx(settings["wheel_contact_impedance"])
    assert model.opt.impratio == pytest.approx(
        ((1 - settings["wheel_contact_impedance"]) / settings["wheel_contact_impedance"])
        / ((1 - settings["wheel_friction_impedance"]) / settings["wheel_friction_impedance"]),
        rel=1e-5,
    )


def test_a_friction_ratio_gives_the_pairs_two_tangential_frictions_in_mujoco(catalog, husky_mjcf):
    import mujoco

    settings = _settings(catalog, "mujoco", "tuned", friction_ratio=0.6)
    fragment = formats.write_profile_file("mjcf", "mujoco", settings, ["t"], WHEELS, ground_mu=0.8)["xml"]
    model = mujoco.MjModel.from_xml_string(_merge(husky_mjcf, fragment))
    # tangent 1 along the axle (ratio x mu), tangent 2 rolling (mu), as the adapter's capsule pairs
    assert [list(model.pair_friction[i][:2]) for i in range(model.npair)] == [pytest.approx([0.48, 0.8])] * 4
    assert "capsule" in fragment  # the file says why the wheel geoms must be capsules for the two directions


def test_the_merged_mjcf_turns_as_the_adapter_at_both_ground_frictions(catalog, husky_mjcf, tmp_path):
    from test_simulators import _gain

    settings = _settings(catalog, "mujoco", "tuned")
    for mu in (0.8, 0.2):
        fragment = formats.write_profile_file("mjcf", "mujoco", settings, ["t"], WHEELS, ground_mu=mu)["xml"]
        pasted = _mjcf_gain(_merge(husky_mjcf, fragment))
        adapter = _gain("mujoco", {**settings}, tmp_path, mu=mu)
        # measured 2026-11-28: 0.4617 / 0.4617 at mu 0.8, 0.4664 / 0.4665 at mu 0.2 (pasted / adapter); the same
        # pairs without the friction attribute (MuJoCo's pair default 1) turn at 0.4616 on the 0.2 ground,
        # 0.005 off: the tolerance tells the ground's friction from the default
        assert pasted == pytest.approx(adapter, abs=0.002), (mu, pasted, adapter)


def test_isaac_lab_iteration_counts_are_written_as_the_integers_its_fields_take(catalog):
    settings = {**_settings(catalog, "isaac_sim", "shipped"), "position_iterations": 32.0}  # as a JSON round trip gives
    text = formats.write_profile_file("isaaclab", "physx", settings, ["t"], WHEELS)["py"]
    assert "'solver_position_iteration_count': 32," in text and "32.0" not in text
    assert formats.read("isaaclab", "physx", {"py": text})["position_iterations"] == 32


def test_a_fitted_friction_ratio_reaches_the_gazebo_wheels_as_the_contact_s_coefficients():
    """The calibrated Gazebo profile sets the ratio on the ground's <mu2> in the gz-physics adapter; the file a user
    pastes carries it on the wheels: the ground's mu along fdir1 and ratio x mu across it, whatever the wheels' own
    Clearpath values were, so that DART's lower-of-the-two rule gives the fitted contact."""
    from simpick.engines.gzphysics_engine import GzPhysicsSettings

    settings = GzPhysicsSettings.model_validate(
        {"fdir1": "wheel_x", "wheel_mu": 1.0, "wheel_mu2": 1.0, "friction_ratio": 0.7306, "contact_kp": 1e7}
    ).model_dump(mode="json")
    texts = formats.write_profile_file("sdf", "gzphysics", settings, ["test"], ["front_left_wheel"], ground_mu=0.8)
    surface = ET.fromstring(texts["wheels.urdf"]).find("gazebo/collision/surface")
    assert float(surface.findtext("friction/ode/mu")) == pytest.approx(0.8)
    assert float(surface.findtext("friction/ode/mu2")) == pytest.approx(0.8 * 0.7306, rel=1e-4)
    assert surface.findtext("friction/ode/fdir1") == "1 0 0"
    back = formats.read_sdf("gzphysics", texts, ground_mu=0.8)
    assert back["friction_ratio"] == pytest.approx(0.7306, rel=1e-4)


# --- the headers state what the file holds ---


def test_a_fitted_value_is_stated_as_written_and_the_catalog_s_beside_it(catalog):
    """A calibrated profile's value differs from the catalog's: the header gives the written one (the catalog's
    beside it as the start), never the catalog's alone; Gazebo's wheels' mu/mu2 are stated as written."""
    from simpick.engines.catalog import Setting

    fitted = _settings(catalog, "mujoco", "tuned", friction_ratio=0.7)
    start = Setting(value=1.0, exposed_as="the pairs' friction", source="the tuned profile")
    entries = {**catalog.entries("mujoco", "tuned"), "friction_ratio": ("calibrated", start)}
    text = formats.write_profile_file("mjcf", "mujoco", fitted, ["t"], WHEELS, entries)["xml"]
    assert "friction_ratio = 0.7 (written; the calibrated profile's catalog value is 1.0)" in text
    iterations = fitted["solver_iterations"]
    assert f"solver_iterations = {iterations} (tuned)" in text  # an unfitted value: the catalog's, as written

    sim = catalog.simulators["gazebo"]
    # as the calibrated file is written (simpick.score.simulator_settings): the fit's ratio with what it requires
    settings = _settings(catalog, "gazebo", "tuned", friction_ratio=0.7, wheel_mu2=1.0)
    fitted_entry = Setting(value=1.0, exposed_as="the wheels' <mu2>", source="fitted: a test")
    entries = {**catalog.entries("gazebo", "calibrated"), "wheel_mu2": ("calibrated", fitted_entry)}
    texts = formats.write_profile_file("sdf", sim.engine, settings, ["t"], WHEELS, entries)
    header = texts["wheels.urdf"].split("<robot")[0]
    mu = float(ET.fromstring(texts["wheels.urdf"]).find(".//friction/ode/mu").text)
    mu2 = float(ET.fromstring(texts["wheels.urdf"]).find(".//friction/ode/mu2").text)
    assert mu2 == pytest.approx(0.7 * mu)
    assert f"<mu> {mu:g}, <mu2> {mu2:g}" in header
    assert "wheel_mu2 =" not in header and "wheel_mu =" not in header  # not in the file: not stated


@pytest.mark.parametrize("variant", VARIANTS)
def test_the_drake_header_names_drake_s_own_keys_and_values(catalog, variant):
    settings = _settings(catalog, "drake", variant)
    texts = formats.write_profile_file("drake", "drake", settings, ["t"], WHEELS, catalog.entries("drake", variant))
    header = [line for line in texts["yaml"].splitlines() if line.startswith("#")]
    said = "\n".join(header)
    assert "discrete_approximation =" not in said and "contact_model = 'hydroelastic' " not in said
    if settings["contact_model"] == "hydroelastic":
        assert "contact_model = 'hydroelastic_with_fallback'" in said
    assert f"discrete_contact_approximation = '{settings['discrete_approximation']}'" in said


def test_the_webots_file_states_the_ground_shapes_its_anisotropy_needs(catalog):
    """Webots takes the friction direction from the geometry in contact, and only a Box, Plane or Cylinder gives
    one: an anisotropic file says so before its values, an isotropic one has nothing to assume."""
    entries = catalog.entries("webots", "tuned")
    settings = _settings(catalog, "webots", "tuned", friction_ratio=0.7, friction_direction="wheel")
    text = formats.write_profile_file("webots", "ode", settings, ["t"], WHEELS, entries)["wbt"]
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert header[1].startswith("# ASSUMES the ground the wheels touch is a Box, a Plane or a Cylinder")
    assert "ElevationGrid or a Mesh" in header[1] and "0.56, across the wheel" in header[1]
    settings = _settings(catalog, "webots", "tuned", friction_ratio=1.0)
    assert "ASSUMES" not in formats.write_profile_file("webots", "ode", settings, ["t"], WHEELS, entries)["wbt"]
