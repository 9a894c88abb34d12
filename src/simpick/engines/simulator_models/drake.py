"""Drake: the robot on flat ground as three files a Drake user loads with Drake's own code alone, written from the
settings the Drake adapter (:mod:`simpick.engines.drake_engine`) sets in code, so that what a user loads is the plant
simpick stepped:

- ``<stem>.urdf``: the robot's description with its collision shapes (no visual mesh, so it names no file), each
  collision's ``<drake:proximity_properties>`` as the adapter assigns them (every number written, Drake's
  SceneGraphConfig defaults included), the wheels' actuators as ``<transmission>`` elements with
  ``<drake:controller_gains>`` and the joints' effort limit, and a ``<drake:collision_filter_group>`` that keeps the
  robot's own links apart (the adapter's collision filter);
- ``<stem>.ground.sdf``: the ground, a static SDFormat model whose ``<plane>`` Drake parses as the adapter's
  HalfSpace (URDF has no half space);
- ``<stem>.plant.yaml``: ``plant_config``, every MultibodyPlantConfig field (read by Drake's own loader,
  ``yaml_load_typed(..., child_name="plant_config")``: its other keys are left to the user), beside the base's
  starting pose (a URDF cannot place a free body), the gravity, the map from a command (v, w) to the actuators'
  desired state, and the yaw-rate gains simpick's validation measured on the adapter (``claims``). A second key in
  the YAML, rather than comments, because Drake's loader still checks its part strictly and the rest is plain
  data a test or a user reads with any YAML reader.

Each tag was checked against Drake 1.51.1's parser (RobotLocomotion/drake v1.51.1); the header names the lines.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence

from simpick.engines.base import GRAVITY, engine_step_multiple
from simpick.engines.drake_engine import (
    ROBOT_FRICTION,
    SPAWN_CLEARANCE,
    SUSPENSION_FRICTION_DAMPING,
    WHEEL_MESH_PER_RADIUS,
    DrakeSettings,
    _terrain_friction,
)
from simpick.engines.simulator_files.common import _num, xml_comment
from simpick.engines.simulator_models.common import ModelRequest, TurningClaim
from simpick.engines.suspension import coupled_urdf
from simpick.inputs.robot.settings import RobotParams

DRAKE_NS = "http://drake.mit.edu"
# where Drake 1.51.1 reads each element the files write (RobotLocomotion/drake at tag v1.51.1), and where its
# parsing docs (multibody/parsing/parsing_doxygen.h) describe it
SOURCES = [
    "read by Drake 1.51.1 (RobotLocomotion/drake v1.51.1, multibody/parsing/; docs parsing_doxygen.h): URDF "
    "<collision><drake:proximity_properties> detail_urdf_geometry.cc:715-716 (docs :1437); in it "
    "<drake:rigid_hydroelastic/>, <drake:compliant_hydroelastic/> :739-742 (docs :1493, :849) and, as value "
    "attributes, <drake:mesh_resolution_hint> detail_common.cc:87 (docs :1289), <drake:hydroelastic_modulus> :95 "
    "(:1046), <drake:hunt_crossley_dissipation> :111 (:1014), <drake:point_contact_stiffness> :113 (:1410), "
    "<drake:mu_dynamic> :114 (:1320), <drake:mu_static> :115 (:1335), <drake:relaxation_time> :132 (:1478)",
    "URDF <transmission> of type SimpleTransmission: detail_urdf_parser.cc:1392, :887; its <joint name> :914, "
    "<actuator name> :908 with <drake:controller_gains p d> :999-1021 (docs :862); the actuator's effort limit is "
    "its joint's <limit effort> :373, :946-964",
    "URDF <drake:collision_filter_group> (docs :819) with <drake:member link> (:1257) and "
    "<drake:ignored_collision_filter_group name> (:1062): detail_urdf_parser.cc:262-299, detail_common.cc:328-369, "
    ":394-399 (a group that ignores itself filters its members' pairs, :367-369)",
    "SDFormat <plane> -> HalfSpace: detail_sdf_geometry.cc:158-164, :291-303; a <static> model's links welded to "
    "the world: detail_sdf_parser.cc:2448-2462; its <drake:proximity_properties> elements: "
    "detail_sdf_geometry.cc:579-606",
    "plant_config: MultibodyPlantConfig's fields, multibody/plant/multibody_plant_config.h:35-97; the loader's "
    "child_name: bindings/pydrake/common/yaml.py:658-659",
]


def write_drake_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text} of the model's files (``urdf``, ``ground.sdf``, ``plant.yaml``; the request's stem, "":
    ``drake``, is their shared name, by which each names the others): the ``request``'s robot on a half space of its
    ground friction, with the Drake adapter's settings and the study's step (the plant's own step is the adapter's:
    a whole multiple of it); each headed by the header lines and what this writer knows; the claims into the
    YAML."""
    stem = request.stem or "drake"
    import pydrake
    import yaml
    from pydrake.common.yaml import yaml_dump_typed
    from pydrake.geometry import SceneGraphConfig
    from pydrake.multibody.plant import MultibodyPlantConfig

    spec = request.robot.spec(request.robot_urdf)
    typed = DrakeSettings.model_validate(dict(request.settings))
    hydro = typed.contact_model == "hydroelastic"
    defaults = SceneGraphConfig().default_proximity_properties
    plant_step = request.timestep * engine_step_multiple(typed.time_step, request.timestep)
    files = {suffix: f"{stem}.{suffix}" for suffix in ("urdf", "ground.sdf", "plant.yaml")}
    version = getattr(pydrake, "__version__", "") or _drake_version()

    # --- the robot ---
    ET.register_namespace("drake", DRAKE_NS)
    root = ET.parse(coupled_urdf(spec)).getroot()
    dropped = _drop_files(root)
    radius = {w.link: w.radius for w in spec.driven}
    for link in root.iter("link"):
        for collision in link.findall("collision"):
            for old in [
                *collision.findall(f"{{{DRAKE_NS}}}proximity_properties"),
                *collision.findall("drake_compliance"),
            ]:
                collision.remove(old)
            wheel = radius.get(link.get("name"))
            props = ET.SubElement(collision, _d("proximity_properties"))
            if hydro and wheel is not None:
                ET.SubElement(props, _d("compliant_hydroelastic"))
                _value(props, "hydroelastic_modulus", typed.hydroelastic_modulus)
                _value(props, "mesh_resolution_hint", min(typed.mesh_resolution, wheel / WHEEL_MESH_PER_RADIUS))
            dissipation = typed.wheel_dissipation if wheel is not None else defaults.hunt_crossley_dissipation
            _value(props, "hunt_crossley_dissipation", dissipation)
            _value(props, "point_contact_stiffness", defaults.point_stiffness)
            _value(props, "relaxation_time", defaults.relaxation_time)
            _value(props, "mu_dynamic", ROBOT_FRICTION)
            _value(props, "mu_static", ROBOT_FRICTION)
    joints = {j.get("name"): j for j in root.iter("joint")}
    for old in root.findall("transmission"):  # the adapter adds the actuators itself
        root.remove(old)
    actuators = []
    for wheel in spec.driven:
        actuators.append(
            _transmission(
                root,
                joints[wheel.joint],
                f"{wheel.joint}_drive",
                request.robot.max_wheel_torque,
                0.0,
                typed.wheel_drive_damping,
            )
        )
    friction_actuators = []
    for sus in spec.suspension:
        joint = joints[sus.joint]
        limit = joint.find("limit")
        if limit is None:
            limit = ET.SubElement(joint, "limit")
        limit.set("lower", repr(float(sus.lower)))
        limit.set("upper", repr(float(sus.upper)))
        dynamics = joint.find("dynamics")
        if dynamics is None:
            dynamics = ET.SubElement(joint, "dynamics")
        dynamics.attrib.pop("friction", None)  # MultibodyPlant has none: the actuator below is its friction
        dynamics.set("damping", repr(float(sus.damping)))
        if sus.friction > 0:
            friction_actuators.append(
                _transmission(root, joint, f"{sus.joint}_friction", sus.friction, 0.0, SUSPENSION_FRICTION_DAMPING)
            )
    group = ET.SubElement(root, _d("collision_filter_group"), name="robot_self")
    for link in root.iter("link"):
        if link.get("name") != "world":
            ET.SubElement(group, _d("member"), link=link.get("name"))
    ET.SubElement(group, _d("ignored_collision_filter_group"), name="robot_self")
    ET.indent(root)
    urdf_text = ET.tostring(root, encoding="unicode")
    if " filename=" in urdf_text:
        raise ValueError(
            f"the Drake model of {request.robot_urdf} names files (a collision mesh): it would not open alone"
        )

    # --- the ground ---
    ground_f = _terrain_friction(request.ground_mu, "the model's ground friction")
    sdf = ET.Element("sdf", {"version": "1.9", "xmlns:drake": DRAKE_NS})
    model = ET.SubElement(sdf, "model", name="ground")
    ET.SubElement(model, "static").text = "true"
    link = ET.SubElement(model, "link", name="ground")
    collision = ET.SubElement(link, "collision", name="ground")
    plane = ET.SubElement(ET.SubElement(collision, "geometry"), "plane")
    ET.SubElement(plane, "normal").text = "0 0 1"
    ET.SubElement(plane, "size").text = "100 100"
    gp = ET.SubElement(collision, "drake:proximity_properties")
    if hydro:
        ET.SubElement(gp, "drake:rigid_hydroelastic")
    for key, value in (
        ("hunt_crossley_dissipation", defaults.hunt_crossley_dissipation),
        ("point_contact_stiffness", defaults.point_stiffness),
        ("relaxation_time", defaults.relaxation_time),
        ("mu_dynamic", ground_f),
        ("mu_static", ground_f),
    ):
        ET.SubElement(gp, f"drake:{key}").text = repr(float(value))
    ET.indent(sdf)
    sdf_text = ET.tostring(sdf, encoding="unicode")

    # --- the plant and what drives it ---
    config = MultibodyPlantConfig(
        time_step=plant_step,
        stiction_tolerance=typed.stiction_tolerance,
        contact_model="hydroelastic_with_fallback" if hydro else "point",
        discrete_contact_approximation=typed.discrete_approximation,
    )
    driven = spec.driven
    data = {
        "plant_config": yaml.safe_load(yaml_dump_typed(config)),
        "models": [files["urdf"], files["ground.sdf"]],
        "gravity": [0.0, 0.0, -GRAVITY],
        "base": {"body": spec.base_link, "xyz": [0.0, 0.0, spec.base_height + SPAWN_CLEARANCE], "yaw": 0.0},
        "drive": {
            "command_track": float(request.robot.track),
            "wheel_track": float(spec.track),
            "actuators": [
                {
                    "name": a,
                    "joint": w.joint,
                    "side": 1 if w.side == "left" else -1,
                    "axis_sign": int(w.axis_sign),
                    "radius": float(w.radius),
                }
                for a, w in zip(actuators, driven, strict=True)
            ],
            "still": friction_actuators,
        },
        "claims": {
            c.case: {"v": c.v, "w": c.w, "duration": c.duration, "gain": round(c.gain, 6)} for c in request.claims
        },
    }
    yaml_text = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=200)

    lines = [
        *request.header_lines,
        *_load_lines(files, spec.base_link),
        *_drive_lines(typed, request.robot, spec, actuators, friction_actuators, plant_step, request.timestep),
        *_contact_lines(typed, hydro, request.ground_mu, ground_f, defaults),
        *_claim_lines(request.claims),
        f"files: {files['urdf']} (the robot), {files['ground.sdf']} (the ground), {files['plant.yaml']} (the plant "
        "and the commands); they name no other file"
        + (f"; the description's visual meshes are left out ({', '.join(dropped)})" if dropped else ""),
        *SOURCES,
        f"written with Drake {version}",
    ]
    name_line = [f"model: {request.name}"] if request.name else []
    return {
        "urdf": '<?xml version="1.0"?>\n' + xml_comment([*name_line, *lines]) + urdf_text + "\n",
        "ground.sdf": '<?xml version="1.0"?>\n'
        + xml_comment([*name_line, f"the ground of {files['urdf']} (its header says all)", *request.header_lines[:1]])
        + sdf_text
        + "\n",
        "plant.yaml": "".join(f"# {line}\n" for line in [*name_line, *lines]) + yaml_text,
    }


def _drake_version() -> str:
    import importlib.metadata

    return importlib.metadata.version("drake")


def _d(tag: str) -> str:
    return f"{{{DRAKE_NS}}}{tag}"


def _value(parent, tag: str, value) -> None:
    ET.SubElement(parent, _d(tag), value=repr(float(value)))


def _drop_files(root) -> list[str]:
    """Removes the visuals that name a file (meshes; Drake's collision shapes are what moves the robot) and any
    material texture; returns what went."""
    dropped = []
    for link in root.iter("link"):
        for visual in link.findall("visual"):
            mesh = visual.find("geometry/mesh")
            if mesh is not None:
                dropped.append(mesh.get("filename", "?"))
                link.remove(visual)
    for material in root.iter("material"):
        for texture in material.findall("texture"):
            dropped.append(texture.get("filename", "?"))
            material.remove(texture)
    return dropped


def _transmission(root, joint, actuator: str, effort: float, p: float, d: float) -> str:
    """A SimpleTransmission driving ``joint`` through ``actuator`` with implicit PD gains (p, d), its effort limit
    on the joint's <limit effort>."""
    limit = joint.find("limit")
    if limit is None:
        limit = ET.SubElement(joint, "limit")
    limit.set("effort", repr(float(effort)))
    t = ET.SubElement(root, "transmission", name=f"{actuator}_transmission")
    ET.SubElement(t, "type").text = "transmission_interface/SimpleTransmission"
    ET.SubElement(t, "joint", name=joint.get("name"))
    a = ET.SubElement(t, "actuator", name=actuator)
    ET.SubElement(a, _d("controller_gains"), p=repr(float(p)), d=repr(float(d)))
    return actuator


def _load_lines(files: Mapping[str, str], base: str) -> list[str]:
    return [
        "load with Drake alone (pydrake): config = yaml_load_typed(schema=MultibodyPlantConfig, filename="
        f"'{files['plant.yaml']}', child_name='plant_config'); plant, scene_graph = AddMultibodyPlant(config, "
        f"builder); (robot,) = Parser(plant).AddModels('{files['urdf']}'); Parser(plant).AddModels("
        f"'{files['ground.sdf']}'); plant.SetDefaultFloatingBaseBodyPose(plant.GetBodyByName('{base}', robot), "
        "RigidTransform(base xyz)); plant.Finalize(); then drive plant.get_desired_state_input_port(robot) and fix "
        "plant.get_actuation_input_port(robot) to zeros (Drake warns that a rigid half space has no deformable "
        "contact: there is no deformable body here)",
    ]


def _drive_lines(typed, robot: RobotParams, spec, actuators, still, plant_step: float, timestep: float) -> list[str]:
    radius = " / ".join(dict.fromkeys(_num(w.radius) for w in spec.driven))
    lines = [
        f"plant: MultibodyPlantConfig time_step {_num(plant_step)} s (the adapter's time_step "
        f"{_num(typed.time_step) if typed.time_step else 'unset'} on the study's {_num(timestep)} s step), "
        f"discrete_contact_approximation {typed.discrete_approximation}, stiction_tolerance "
        f"{_num(typed.stiction_tolerance)} m/s, the other fields Drake's defaults written out (plant_config); "
        f"gravity {_num(GRAVITY)} m/s^2 down (MultibodyPlant's default; gravity in the YAML)",
        f"robot: {spec.name}'s links, joints and collision shapes as its description gives them; its base "
        f"{spec.base_link} is a free body that starts at rest at base xyz (its resting height plus "
        f"{_num(SPAWN_CLEARANCE)} m), heading 0",
        f"drive: actuators {', '.join(actuators)} (drive.actuators, in the order of the desired state's rows), each "
        f"on its wheel joint with Drake's implicit PD controller p 0, d {_num(typed.wheel_drive_damping)} N m s/rad "
        f"(<drake:controller_gains>) and effort limit {_num(robot.max_wheel_torque)} N m (<limit effort>)"
        + (
            f"; then {', '.join(still)} (drive.still): the suspension joints' Coulomb friction as an implicit PD "
            f"towards speed 0 (p 0, d {_num(SUSPENSION_FRICTION_DAMPING)}, effort limit the friction)"
            if still
            else ""
        ),
        "desired state of the robot's model instance (plant.get_desired_state_input_port(robot)): the actuated "
        "joints' positions, all 0 (ignored: p is 0), then their speeds in rad/s; a wheel's speed for (v, w) in "
        "m/s and rad/s = (v - w x side x command_track / 2) x axis_sign / radius (drive.actuators: side 1 on the "
        f"left, y > 0, -1 on the right), command_track {_num(robot.track)} m, the controller's effective track "
        f"(the wheels' own spacing is wheel_track {_num(spec.track)} m), radius {radius} m"
        + ("; drive.still's speeds 0" if still else ""),
    ]
    return lines


def _contact_lines(typed, hydro: bool, mu: float, ground_f: float, defaults) -> list[str]:
    if hydro:
        contact = (
            "contact_model hydroelastic_with_fallback: the wheels <drake:compliant_hydroelastic/> (modulus "
            f"{_num(typed.hydroelastic_modulus)} Pa, mesh resolution hint min({_num(typed.mesh_resolution)}, "
            f"radius / {WHEEL_MESH_PER_RADIUS}) m) on the <drake:rigid_hydroelastic/> ground, a pressure patch per "
            "wheel; the other robot shapes set no compliance (point contact where they touch)"
        )
    else:
        contact = "contact_model point: one point per wheel, no hydroelastic tag"
    return [
        contact,
        f"friction: Drake combines two surfaces' coefficients as 2 a b / (a + b); the robot's shapes have "
        f"{_num(ROBOT_FRICTION)} (<drake:mu_dynamic>, <drake:mu_static>) and the ground mu / (2 - mu) = "
        f"{ground_f!r}, so a wheel on the ground has exactly mu = {_num(mu)}, as the adapter sets them",
        f"dissipation: Hunt-Crossley {_num(typed.wheel_dissipation)} s/m on the wheels (the tyres' rolling "
        f"resistance), {_num(defaults.hunt_crossley_dissipation)} s/m on every other shape and the ground; point "
        f"stiffness {_num(defaults.point_stiffness)} N/m and relaxation time {_num(defaults.relaxation_time)} s on "
        "every shape (the values Drake's SceneGraphConfig default_proximity_properties gives a shape that sets "
        "none, written out); the robot's links never collide with each other (<drake:collision_filter_group> "
        "robot_self)",
    ]


def _claim_lines(claims: Sequence[TurningClaim]) -> list[str]:
    if not claims:
        return ["claims no yaw-rate gain: the study's validation has no turning case on this ground from heading 0"]
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [
        "claims the yaw-rate gain simpick's validation measured on the adapter's plant of these settings (claims: "
        "v, w, duration, gain): from base xyz at rest, the desired state held at (v, w)'s from the first step, "
        "the mean over the steps after the first half of the run of the base's yaw rate about its own z axis, "
        f"over w: {runs}"
    ]
