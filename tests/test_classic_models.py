"""The Gazebo Classic and Webots models rule simulator_models writes (simpick.studies.simulator_models), checked field
by field. No Gazebo Classic or Webots loader runs here: neither installs on this machine (Gazebo Classic 11 is end of
life and not packaged for it; Webots is not packaged either), so no test opens these files in the simulator or
measures a gain there. Instead each file is parsed by a parser of its own (lxml for the SDF world, a small tokenizer
of VRML's syntax for the .wbt) and its fields are compared with values read independently of the writer: the
catalog's quoted settings and defaults (resources/simulators/simulators.yaml, read with yaml), SDF 1.7's own
defaults (sdformat's surface.sdf), the robot's URDF (read with lxml: its wheel joints, radii, track and masses) and
the study's step, track and torque; sdformat 12 validates the Gazebo Classic world (``ign sdf -k``, which reads SDF 1.7
by converting it, not Gazebo Classic's own sdformat 9). The gains the files claim are the job's (simpick's ODE
reproduction), compared with the job's return value only. A file with one wrong friction value fails the checks
(the tampering tests)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml
from lxml import etree

from conftest import ROOT, study_config
from simpick.config import Study
from simpick.engines.gzphysics_engine import PROGRAM
from simpick.engines.simulators import SIMULATORS
from simpick.plan import Plan
from simpick.studies.simulator_models import simulator_models_job

DURATION = 1.0  # s, each claimed case cut to it (the claims are compared with the job's, not measured here)
CATALOG = ROOT / "resources/simulators/simulators.yaml"
SURFACE_SDF = Path("/usr/share/sdformat12/1.7/surface.sdf")
# calibrated-like fits, as rule simulator_calibrate writes them (calibration.yaml's spaces: Gazebo Classic's ratio
# and slip; Webots' ratio with the wheel friction directions it requires)
FITS = {
    "gazebo_classic": {"friction_ratio": 0.7, "contact_slip": 0.003},
    "webots": {"friction_ratio": 0.7, "friction_direction": "wheel"},
}
PROFILES = {
    "gazebo_classic": ("gazebo_classic-shipped", "gazebo_classic-tuned", "gazebo_classic-calibrated"),
    "webots": ("webots-shipped", "webots-tuned", "webots-calibrated"),
}


@pytest.fixture(scope="module")
def plan():
    config = study_config()
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture(scope="module")
def models(tmp_path_factory, plan):
    """The job's models of every Gazebo Classic and Webots profile (calibrated: over FITS), and their claims."""
    if not PROGRAM.is_file():
        pytest.skip(f"{PROGRAM} is not built (make gzphysics): no sdformat URDF conversion for Gazebo Classic")
    tmp = tmp_path_factory.mktemp("classic")
    params = plan.simulator_models_params()
    wanted = [p for names in PROFILES.values() for p in names]
    params["profiles"] = {p: params["profiles"][p] for p in wanted}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    calibrations = []
    for simulator, settings in FITS.items():
        fit = {"searchable": True, "source": "a test's runs", "settings": settings, "fit": {}, "per_class": {}}
        path = tmp / f"{simulator}.yaml"  # named as rule simulator_calibrate names a simulator's fit
        path.write_text(yaml.safe_dump(fit))
        calibrations.append(str(path))
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": calibrations}
    claims = simulator_models_job(inputs, params, str(tmp / "models"))
    return tmp / "models", claims


# --- what the files must hold, read without the writers ---------------------------------------------------------


def quoted(simulator: str, variant: str, robot: str) -> dict:
    """The catalog's quoted values of a profile: the shipped settings, the robot's maker tags over them, the tuned
    settings over those (tuned, calibrated) and the test's fit (calibrated)."""
    entry = yaml.safe_load(CATALOG.read_text())["simulators"][simulator]
    values = {k: v["value"] for k, v in entry["shipped"]["settings"].items()}
    values |= {k: v["value"] for k, v in ((entry["shipped"].get("robots") or {}).get(robot) or {}).items()}
    if variant in ("tuned", "calibrated"):
        values |= {k: v["value"] for k, v in (entry.get("tuned") or {}).get("settings", {}).items()}
    if variant == "calibrated":
        values |= FITS[simulator]
    return values


def urdf_robot(path: Path) -> dict:
    """The URDF's wheels (continuous joints: name -> (child link, y, radius)), its total mass."""
    root = etree.parse(str(path)).getroot()
    links = {link.get("name"): link for link in root.findall("link")}
    wheels = {}
    for joint in root.findall("joint"):
        if joint.get("type") != "continuous":
            continue
        child = joint.find("child").get("link")
        y = float(joint.find("origin").get("xyz").split()[1])
        wheels[joint.get("name")] = (child, y, float(links[child].find("collision/geometry/cylinder").get("radius")))
    mass = sum(float(m.get("value")) for m in root.findall("link/inertial/mass"))
    return {"wheels": wheels, "mass": mass}


def sdf_default(element: str) -> float:
    """SDF 1.7's default of a <surface> element, from sdformat's own description of it (the first of that name)."""
    description = etree.parse(str(SURFACE_SDF)).getroot()
    return float(description.xpath(f"//element[@name='{element}']")[0].get("default"))


def close(a: float, b: float, rel: float = 1e-6) -> bool:
    return abs(float(a) - float(b)) <= rel * max(1.0, abs(float(b)))


# --- Gazebo Classic ----------------------------------------------------------------------------------------------


def check_classic(root, q: dict, robot: dict, study: dict) -> list[str]:
    """What in the Gazebo Classic world differs from the quoted values ``q``, the URDF's ``robot`` and the study."""
    bad = []

    def expect(what, got, want):
        if got is None or not (close(got, want) if isinstance(want, float) else got == want):
            bad.append(f"{what}: {got} != {want}")

    def number(element, path, default=None):
        text = element.findtext(path)
        return default if text is None else float(text)

    expect("version", root.get("version"), "1.7")
    physics = root.find("world/physics")
    expect("physics type", physics.get("type"), "ode")
    expect("max_step_size", number(physics, "max_step_size"), study["timestep"])
    expect("max_contacts", number(physics, "max_contacts"), float(q["max_contacts"]))
    expect("solver type", physics.findtext("ode/solver/type"), q["stepper"])
    expect("iters", number(physics, "ode/solver/iters"), float(q["quick_iterations"]))
    for key in ("cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"):
        expect(key, number(physics, f"ode/constraints/{key}"), float(q[key]))
    ground = root.find("world/model[@name='ground_plane']/link/collision")
    if ground.find("geometry/plane") is None:
        bad.append("the ground is no plane")
    g_mu, g_mu2 = number(ground, "surface/friction/ode/mu"), number(ground, "surface/friction/ode/mu2")
    g_kp = number(ground, "surface/contact/ode/kp", sdf_default("kp"))
    g_kd = number(ground, "surface/contact/ode/kd", sdf_default("kd"))
    (model,) = [m for m in root.findall("world/model") if m.find("plugin") is not None]
    ratio = float(q.get("friction_ratio", 1.0))
    joints = {j.get("name"): j for j in model.findall("joint")}
    links = {link.get("name"): link for link in model.findall("link")}
    if sorted(n for n, j in joints.items() if j.get("type") == "revolute") != sorted(robot["wheels"]):
        bad.append(f"wheel joints {sorted(joints)} != the URDF's {sorted(robot['wheels'])}")
    for name, (child, y, radius) in robot["wheels"].items():
        joint = joints.get(name)
        if joint is None:
            continue
        expect(f"{name} effort", number(joint, "axis/limit/effort"), study["max_wheel_torque"])
        expect(f"{name} y", float(joint.findtext("pose").split()[1]), y)
        collision = links[child].find("collision")
        expect(f"{name} radius", number(collision, "geometry/cylinder/radius"), radius)
        friction, contact = collision.find("surface/friction/ode"), collision.find("surface/contact/ode")
        # the contact's values as Gazebo Classic combines the two surfaces (ODEPhysics.cc:1107-1186)
        w_mu = number(friction, "mu", sdf_default("mu")) if friction is not None else sdf_default("mu")
        w_mu2 = number(friction, "mu2", sdf_default("mu2")) if friction is not None else sdf_default("mu2")
        expect(f"{name} contact mu", min(w_mu, g_mu), study["ground_mu"])
        expect(f"{name} contact mu2", min(w_mu2, g_mu2), ratio * study["ground_mu"])
        fdir1 = friction.findtext("fdir1") if friction is not None else None
        expect(f"{name} fdir1", fdir1 or "none", "1 0 0" if q["friction_direction"] == "wheel_x" else "none")
        slip = number(friction, "slip1", 0.0) if friction is not None else 0.0
        expect(f"{name} contact slip", 2 * slip, float(q.get("contact_slip", 0.0)))
        kp = number(contact, "kp", sdf_default("kp")) if contact is not None else sdf_default("kp")
        kd = number(contact, "kd", sdf_default("kd")) if contact is not None else sdf_default("kd")
        expect(f"{name} contact kp", 1.0 / (1.0 / kp + 1.0 / g_kp), float(q["contact_kp"]))
        expect(f"{name} contact kd", kd + g_kd, float(q["contact_kd"]))
        expect(f"{name} min_depth", number(contact, "min_depth", 0.0), float(q["contact_min_depth"]))
    mass = sum(float(m.text) for m in model.findall("link/inertial/mass"))
    expect("mass", mass, robot["mass"])
    plugin = model.find("plugin")
    expect("plugin", plugin.get("filename"), "libgazebo_ros_diff_drive.so")
    left = [e.text for e in plugin.findall("left_joint")]
    right = [e.text for e in plugin.findall("right_joint")]
    expect("left joints", sorted(left), sorted(n for n, w in robot["wheels"].items() if w[1] > 0))
    expect("right joints", sorted(right), sorted(n for n, w in robot["wheels"].items() if w[1] < 0))
    expect("num_wheel_pairs", number(plugin, "num_wheel_pairs"), float(len(left)))
    for e in plugin.findall("wheel_separation"):
        expect("wheel_separation", float(e.text), study["track"])
    for e in plugin.findall("wheel_diameter"):
        expect("wheel_diameter", float(e.text), 2 * next(iter(robot["wheels"].values()))[2])
    expect("max_wheel_torque", number(plugin, "max_wheel_torque"), study["max_wheel_torque"])
    return bad


@pytest.fixture(scope="module")
def study(plan):
    params = plan.simulator_models_params()
    return {
        "timestep": float(params["physics"]["timestep"]),
        "ground_mu": float(params["ground_mu"]),
        "track": float(plan.config["robot"]["track"]),
        "max_wheel_torque": float(plan.config["robot"]["max_wheel_torque"]),
    }


@pytest.mark.parametrize("profile", PROFILES["gazebo_classic"])
def test_the_gazebo_classic_world_holds_the_profile_s_quoted_values_and_the_robot(models, plan, study, profile):
    folder, claims = models
    root = etree.parse(str(folder / f"{profile}.world")).getroot()
    variant = profile.split("-")[1]
    q = quoted("gazebo_classic", variant, plan.robot.name)
    assert check_classic(root, q, urdf_robot(ROOT / plan.config["robot"]["urdf"]), study) == []
    ns = {"simpick": "urn:simpick:model"}
    written = {e.get("case"): float(e.get("gain")) for e in root.iterfind(".//simpick:yaw_rate_gain", ns)}
    assert written and written == {c.case: c.gain for c in claims[profile]}
    text = (folder / f"{profile}.world").read_text()
    assert "NOT OPENED IN GAZEBO CLASSIC HERE" in text and "not Gazebo Classic's" in text


def test_a_wrong_friction_or_slip_in_the_gazebo_classic_world_is_caught(models, plan, study):
    folder, _ = models
    robot = urdf_robot(ROOT / plan.config["robot"]["urdf"])
    q = quoted("gazebo_classic", "tuned", plan.robot.name)
    for path, value in (("world/model[@name='ground_plane']//mu", "0.9"), (".//slip1", "0.001")):
        root = etree.parse(str(folder / "gazebo_classic-tuned.world")).getroot()
        root.find(path).text = value
        assert check_classic(root, q, robot, study), path


@pytest.mark.skipif(shutil.which("ign") is None, reason="no ign (Debian's ruby-ignition tools with sdformat 12)")
def test_sdformat_12_validates_the_gazebo_classic_worlds(models):
    """sdformat 12 reads SDF 1.7 by converting it to 1.9: a check of the file's structure, not Gazebo Classic's."""
    folder, _ = models
    for profile in PROFILES["gazebo_classic"]:
        done = subprocess.run(
            ["ign", "sdf", "-k", str(folder / f"{profile}.world")], capture_output=True, text=True, check=False
        )
        assert done.returncode == 0 and "Valid." in done.stdout, (profile, done.stdout, done.stderr)


# --- Webots: a tokenizer of VRML's syntax and the checks -------------------------------------------------------

TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]|[^\s\[\]{}"#,]+')


def parse_wbt(text: str) -> list[dict]:
    """The top-level nodes of a .wbt: each {"type", field -> value}, a value a node, a list (of nodes or numbers
    and strings) or a list of tokens (numbers as float, strings unquoted, TRUE/FALSE as bool)."""
    lines = text.splitlines()
    assert lines[0] == "#VRML_SIM R2025a utf8", lines[0]
    tokens = TOKEN.findall("\n".join(_strip(line) for line in lines))
    pos = 0

    def atom(t):
        if t.startswith('"'):
            return t[1:-1]
        if t in ("TRUE", "FALSE"):
            return t == "TRUE"
        try:
            return float(t)
        except ValueError:
            return t

    def value():
        nonlocal pos
        t = tokens[pos]
        if t == "[":
            pos += 1
            items = []
            while tokens[pos] != "]":
                items.append(node() if _is_node(tokens, pos) else atom(tokens[pos]))
                if not isinstance(items[-1], dict):
                    pos += 1
            pos += 1
            return items
        if _is_node(tokens, pos):
            return node()
        out = []
        while re.match(r'^[-+.\d"]|^TRUE$|^FALSE$|^inf$', tokens[pos]):
            out.append(atom(tokens[pos]))
            pos += 1
        return out

    def node():
        nonlocal pos
        out = {"type": tokens[pos]}
        assert tokens[pos + 1] == "{", tokens[pos : pos + 2]
        pos += 2
        while tokens[pos] != "}":
            field = tokens[pos]
            pos += 1
            out[field] = value()
        pos += 1
        return out

    nodes = []
    while pos < len(tokens):
        nodes.append(node())
    return nodes


def _strip(line: str) -> str:
    """A line without its comment, where a # inside a string is not one."""
    out, quoted = [], False
    for ch in line:
        if ch == '"':
            quoted = not quoted
        if ch == "#" and not quoted:
            break
        out.append(ch)
    return "".join(out)


def _is_node(tokens, pos) -> bool:
    return pos + 1 < len(tokens) and tokens[pos + 1] == "{" and tokens[pos][:1].isupper()


def walk(node):
    """Every node under ``node`` (itself included)."""
    if isinstance(node, dict):
        yield node
        for key, v in node.items():
            if key != "type":
                yield from walk(v)
    elif isinstance(node, list):
        for v in node:
            yield from walk(v)


def check_webots(nodes: list[dict], q: dict, robot: dict, study: dict) -> list[str]:
    """What in the Webots world differs from the quoted values ``q``, the URDF's ``robot`` and the study."""
    bad = []

    def expect(what, got, want):
        if isinstance(want, list) and all(isinstance(b, float) for b in want):
            ok = len(got) == len(want) and all(close(a, b) for a, b in zip(got, want, strict=True))
        else:
            ok = close(got, want) if isinstance(want, float) else got == want
        if not ok:
            bad.append(f"{what}: {got} != {want}")

    by_type = {}
    for n in nodes:
        by_type.setdefault(n["type"], []).append(n)
    (info,) = by_type["WorldInfo"]
    expect("basicTimeStep", info["basicTimeStep"][0], study["timestep"] * 1000)
    expect("CFM", info["CFM"][0], float(q["cfm"]))
    expect("ERP", info["ERP"][0], float(q["erp"]))
    contacts = {c["material1"][0]: c for c in info["contactProperties"]}
    wheel = contacts["wheel"]
    expect("material2", wheel.get("material2", ["default"])[0], "default")
    mu, ratio = study["ground_mu"], float(q.get("friction_ratio", 1.0))
    anisotropic = q["friction_direction"] == "wheel"
    expect("coulombFriction", wheel["coulombFriction"], [ratio * mu, mu, 0.0] if anisotropic else [mu])
    if anisotropic:
        expect("frictionRotation", wheel["frictionRotation"], [0.0, 0.0])
    for field, key in (
        ("forceDependentSlip", "contact_slip"),
        ("softERP", "contact_soft_erp"),
        ("softCFM", "contact_soft_cfm"),
        ("bounce", "contact_bounce"),
        ("bounceVelocity", "contact_bounce_vel"),
        ("maxContactJoints", "max_contacts"),
    ):
        got = wheel.get(field)
        got = got[0] if isinstance(got, list) and got else got
        want = float(q.get(key, 0.0))
        expect(field, got, want)
    (ground,) = [s for s in by_type["Solid"] if s["name"] == ["ground"]]
    expect("ground material", ground["contactMaterial"][0], "default")
    expect("ground shape", ground["boundingObject"]["type"], "Plane")
    (bot,) = by_type["Robot"]
    hinges = [n for n in bot["children"] if n["type"] == "HingeJoint"]
    expect("wheels", sorted(h["device"][0]["name"][0] for h in hinges), sorted(robot["wheels"]))
    masses = [bot["physics"]["mass"][0]]
    for h in hinges:
        joint = h["device"][0]["name"][0]
        if joint not in robot["wheels"]:
            continue
        _, y, radius = robot["wheels"][joint]
        expect(f"{joint} motor", h["device"][0]["type"], "RotationalMotor")
        expect(f"{joint} maxTorque", h["device"][0]["maxTorque"][0], study["max_wheel_torque"])
        expect(f"{joint} anchor y", h["jointParameters"]["anchor"][1], y)
        end = h["endPoint"]
        expect(f"{joint} material", end["contactMaterial"][0], "wheel")
        cylinders = [n for n in walk(end["boundingObject"]) if n["type"] == "Cylinder"]
        expect(f"{joint} Cylinder radius", [c["radius"][0] for c in cylinders], [radius])
        masses.append(end["physics"]["mass"][0])
    expect("mass", sum(masses), robot["mass"])
    return bad


@pytest.mark.parametrize("profile", PROFILES["webots"])
def test_the_webots_world_holds_the_profile_s_quoted_values_and_the_robot(models, plan, study, profile):
    folder, claims = models
    text = (folder / f"{profile}.wbt").read_text()
    nodes = parse_wbt(text)
    q = quoted("webots", profile.split("-")[1], plan.robot.name)
    assert check_webots(nodes, q, urdf_robot(ROOT / plan.config["robot"]["urdf"]), study) == []
    (info,) = [n for n in nodes if n["type"] == "WorldInfo"]
    written = {}
    for line in info["info"]:
        m = re.match(r"simpick yaw_rate_gain (\S+): v \S+ w \S+ duration \S+ gain (\S+)$", line)
        if m:
            written[m.group(1)] = float(m.group(2))
    assert written and written == {c.case: c.gain for c in claims[profile]}
    assert "NOT OPENED IN WEBOTS HERE" in text and "not Webots'" in text


def test_a_wrong_friction_in_the_webots_world_is_caught(models, plan, study):
    folder, _ = models
    robot = urdf_robot(ROOT / plan.config["robot"]["urdf"])
    text = (folder / "webots-tuned.wbt").read_text()
    q = quoted("webots", "tuned", plan.robot.name)
    assert check_webots(parse_wbt(text), q, robot, study) == []
    wrong = text.replace("coulombFriction [ 0.8 ]", "coulombFriction [ 0.9 ]", 1)
    assert wrong != text and check_webots(parse_wbt(wrong), q, robot, study)
    wrong = text.replace('material1 "wheel"', 'material1 "tyre"', 1)
    with pytest.raises(KeyError):
        check_webots(parse_wbt(wrong), q, robot, study)


# --- the plan and the report -----------------------------------------------------------------------------------


def test_the_plan_writes_these_models_for_gazebo_classic_and_webots_only_and_notes_them(plan):
    """Both simulators share the ODE adapter, the only ones that do: the writers are keyed by simulator, so no other
    profile of the engine gets their file, and the report's note names the simulator."""
    assert sorted(s for s, engine in SIMULATORS.items() if engine == "ode") == ["gazebo_classic", "webots"]
    files, notes = plan.model_files(), plan.model_notes()
    assert files["webots-tuned"] == "results/simulators/models/webots-tuned.wbt"
    assert files["gazebo_classic-tuned"] == "results/simulators/models/gazebo_classic-tuned.world"
    assert [p for p, f in files.items() if f.endswith(".world")] == list(PROFILES["gazebo_classic"])
    assert [p for p, f in files.items() if f.endswith(".wbt")] == list(PROFILES["webots"])
    assert notes["webots-shipped"] == "fields checked; not opened in Webots here"
    assert notes["gazebo_classic-calibrated"] == "fields checked; not opened in Gazebo Classic 11 here"
    # the others not opened here are the Python scripts of tests/test_vendor_models.py
    vendors = ("isaac_sim-", "coppeliasim-", "morse-")
    assert not [p for p in notes if not p.startswith(("webots-", "gazebo_classic-", *vendors))]
