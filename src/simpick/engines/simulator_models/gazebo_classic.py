"""Gazebo Classic 11: the robot on flat ground as one SDF 1.7 world (sdformat 9's, the one Gazebo Classic 11 reads),
written from the values simpick's ODE adapter reproduces a Gazebo Classic profile with
(:mod:`simpick.engines.ode_settings`): the ODE ``<physics>``, a ground plane with its friction, and the robot as
sdformat's URDF parser converts it (the gzphysics program's ``convert``, sdformat 12: Gazebo Classic 11 converts a
URDF with sdformat 9's parser of the same lineage, which was not run here) with the driven wheels' ``<surface>``
as the settings fragment writes it (:func:`simpick.engines.simulator_files.sdf.surface_values`: Gazebo Classic's
rules for combining two surfaces undone, ODEPhysics.cc:1107-1186) and the wheel joints' effort limits.

What a Gazebo Classic user drives it with is gazebo_ros_pkgs' diff drive plugin (ROS 2,
``libgazebo_ros_diff_drive.so``); its element names are those its Load reads, :data:`DIFF_DRIVE_SOURCE`. What
simpick claims is written as in the Gazebo model (:mod:`.gazebo`): SDF custom elements of the namespace
``urn:simpick:model``, which sdformat copies and no physics reads.

No Gazebo Classic installs here (Gazebo Classic 11 is end of life and not packaged for this machine's Debian): the
file is checked field by field against the catalog's quoted values and the robot's description, and sdformat 12
validates it (``ign sdf -k``, reading SDF 1.7 by converting it to its own 1.9), but no Gazebo Classic code opens it.
The gains it claims are simpick's reproduction's (ODE 0.16 through simpick's adapter), not Gazebo Classic's.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence

from simpick.engines import gzphysics_engine
from simpick.engines.base import GRAVITY
from simpick.engines.ode_settings import OdeSettings
from simpick.engines.ode_world import SPAWN_CLEARANCE
from simpick.engines.simulator_files.common import _num, xml_comment
from simpick.engines.simulator_files.sdf import CONTACTS_PER_WHEEL, GROUND_KD, GROUND_KP, surface_values
from simpick.engines.simulator_models.common import ModelRequest, TurningClaim, add_sdf_claims
from simpick.engines.simulator_models.gazebo import FILE_ELEMENTS, NAMESPACE
from simpick.inputs.robot.settings import RobotParams

# gazebo_ros_pkgs' ROS 2 diff drive plugin, as a Gazebo Classic user loads it on a model
DIFF_DRIVE = {"name": "simpick_diff_drive", "filename": "libgazebo_ros_diff_drive.so"}
# where its element names are read (branch ros2 d52f7c47; the same lines on foxy b6f7bf12, which differs by one
# spelling fix): num_wheel_pairs :247, max_wheel_acceleration and max_wheel_torque :257-258, each left_joint and
# right_joint (set to fmax = max_wheel_torque) :263-292, one wheel_separation and wheel_diameter per pair :311-337,
# update_rate :345, the cmd_vel subscription :353-354; wheel speeds v -+ w wheel_separation / 2 :545-546, set as
# each joint's "vel" over wheel_diameter / 2 :502-505
DIFF_DRIVE_SOURCE = (
    "ros-simulation/gazebo_ros_pkgs ros2 d52f7c47 gazebo_plugins/src/gazebo_ros_diff_drive.cpp:247, 257-258, "
    "263-292, 311-337, 345, 353-354, 502-505, 545-546"
)
# the ODE adapter's settings that an SDF 1.7 world has no element for, with the value that makes them moot
UNEXPRESSED = {"contact_soft_erp": None, "contact_soft_cfm": None, "contact_bounce": 0.0}
# ODE 0.16's and SDF 1.7's successive over-relaxation, which the ODE adapter leaves as ODE sets it
SOR = 1.3


def _text(parent: ET.Element, tag: str, value) -> ET.Element:
    element = ET.SubElement(parent, tag)
    if isinstance(value, (tuple, list)):
        element.text = " ".join(repr(float(v)) for v in value)
    elif isinstance(value, float):
        element.text = repr(value)
    else:
        element.text = str(value)
    return element


def _surface(values: Mapping[str, str]) -> ET.Element:
    surface = ET.Element("surface")
    for path, text in values.items():
        node = surface
        for part in path.split("/"):
            found = node.find(part)
            node = found if found is not None else ET.SubElement(node, part)
        node.text = text
    return surface


def write_gazebo_classic_model(request: ModelRequest) -> str:
    """The SDF 1.7 text of the ``request``'s robot on a plane of its ground friction, with the ODE adapter's
    settings (a Gazebo Classic profile's in full) and the request's step; headed by its header lines and what this
    writer knows; its name the world's, its characters outside [A-Za-z0-9_] made ``_``."""
    spec = request.robot.spec(request.robot_urdf)
    s = OdeSettings.of(dict(request.settings), "ode")
    if s.friction_direction not in ("plane", "wheel_x"):
        raise ValueError(
            f"Gazebo Classic has no friction direction {s.friction_direction!r}: an SDF <fdir1> gives 'wheel_x' "
            "(1 0 0 on the wheel), none gives 'plane'"
        )
    for key, moot in UNEXPRESSED.items():
        if getattr(s, key) != moot:
            raise ValueError(f"the Gazebo Classic model has no element for {key} = {getattr(s, key)!r}")
    if spec.couplings or spec.casters:
        raise ValueError(f"the Gazebo Classic model does not write {spec.name}'s couplings or casters")
    driven = spec.driven
    radii = {w.radius for w in driven}
    left = [w for w in driven if w.side == "left"]
    right = [w for w in driven if w.side == "right"]
    if any(w.axis_sign != 1 for w in driven) or len(radii) != 1 or len(left) != len(right):
        raise ValueError(
            f"gazebo_ros_diff_drive cannot drive {spec.name}: it drives pairs of joints, each rolling the robot "
            "forward at a positive speed, of one wheel diameter"
        )
    radius = radii.pop()

    root = ET.Element("sdf", {"version": "1.7", "xmlns:simpick": NAMESPACE})
    world = ET.SubElement(root, "world", name=re.sub(r"[^A-Za-z0-9_]+", "_", request.name).strip("_") or "simpick")
    _text(world, "gravity", (0.0, 0.0, -float(GRAVITY)))
    physics = ET.SubElement(world, "physics", name="simpick", type="ode")
    _text(physics, "max_step_size", float(request.timestep))
    _text(physics, "real_time_factor", 1.0)
    _text(physics, "real_time_update_rate", 1.0 / float(request.timestep))
    _text(physics, "max_contacts", int(s.max_contacts))
    ode = ET.SubElement(physics, "ode")
    solver = ET.SubElement(ode, "solver")
    _text(solver, "type", s.stepper)
    _text(solver, "iters", int(s.quick_iterations))
    _text(solver, "sor", SOR)
    constraints = ET.SubElement(ode, "constraints")
    for key in ("cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"):
        _text(constraints, key, float(getattr(s, key)))

    # the ground: the case's coefficient both ways (mu2 raised with a ratio above 1, as the minimum of the two
    # surfaces' would else cap the wheels' mu2), SDF's own kp/kd written out, in series with the wheels'
    ratio = float(s.friction_ratio)
    ground = ET.SubElement(world, "model", name="ground_plane")
    _text(ground, "static", "true")
    link = ET.SubElement(ground, "link", name="link")
    for kind in ("collision", "visual"):
        element = ET.SubElement(link, kind, name=kind)
        plane = ET.SubElement(ET.SubElement(element, "geometry"), "plane")
        _text(plane, "normal", (0.0, 0.0, 1.0))
        _text(plane, "size", (100.0, 100.0))
        if kind == "collision":
            surface = ET.SubElement(element, "surface")
            friction = ET.SubElement(ET.SubElement(surface, "friction"), "ode")
            _text(friction, "mu", float(request.ground_mu))
            _text(friction, "mu2", float(request.ground_mu) * max(1.0, ratio))
            contact = ET.SubElement(ET.SubElement(surface, "contact"), "ode")
            _text(contact, "kp", GROUND_KP)
            _text(contact, "kd", GROUND_KD)

    model = ET.fromstring(gzphysics_engine.converted_model(str(spec.urdf), spec.urdf.stat().st_mtime_ns)).find("model")
    if model is None:
        raise ValueError(f"sdformat's conversion of {spec.urdf} has no <model>")
    for old in model.findall("pose"):
        model.remove(old)
    pose = ET.Element("pose")
    pose.text = " ".join(repr(float(v)) for v in (0.0, 0.0, spec.base_height + SPAWN_CLEARANCE, 0.0, 0.0, 0.0))
    model.insert(0, pose)
    joints = {j.get("name"): j for j in model.findall("joint")}
    wheel_links = set()
    for wheel in driven:
        joint = joints.get(wheel.joint)
        if joint is None:
            raise ValueError(f"sdformat's conversion of {spec.urdf} has no joint {wheel.joint!r}")
        wheel_links.add(joint.findtext("child"))
        limit = joint.find("axis/limit")
        if limit is None:
            limit = ET.SubElement(joint.find("axis"), "limit")
        for old in limit.findall("effort"):
            limit.remove(old)
        _text(limit, "effort", float(request.robot.max_wheel_torque))
    values = surface_values("ode", s.model_dump(mode="json"), request.ground_mu)
    for link_xml in model.findall("link"):
        if link_xml.get("name") not in wheel_links:
            continue
        for collision in link_xml.findall("collision"):
            for old in collision.findall("surface"):
                collision.remove(old)
            collision.append(_surface(values))
    world.append(model)

    plugin = ET.SubElement(model, "plugin", DIFF_DRIVE)
    _text(plugin, "num_wheel_pairs", len(left))
    for a, b in zip(left, right, strict=True):  # pair i: left_joint i with right_joint i, front to back
        _text(plugin, "left_joint", a.joint)
        _text(plugin, "right_joint", b.joint)
    for _ in left:
        _text(plugin, "wheel_separation", float(request.robot.track))
        _text(plugin, "wheel_diameter", 2.0 * float(radius))
    _text(plugin, "max_wheel_torque", float(request.robot.max_wheel_torque))
    _text(plugin, "max_wheel_acceleration", 0.0)
    _text(plugin, "update_rate", 1.0 / float(request.timestep))
    add_sdf_claims(model, spec.base_link, request.robot.track, spec.track, request.ground_mu, request.claims)
    named = sorted({e.tag for e in root.iter() if e.tag in FILE_ELEMENTS})
    if named:
        raise ValueError(f"the Gazebo Classic model of {request.robot_urdf} names files ({', '.join(named)})")
    lines = [
        *request.header_lines,
        *_lines(s, request.robot, spec, model, values, radius, request.ground_mu, request.timestep),
        *_claim_lines(request.claims, spec.base_link),
        f"robot written with {gzphysics_engine.GzPhysicsEngine().version()} ({gzphysics_engine.PROGRAM.name} "
        "convert: sdformat 12's URDF parser); numbers at full double precision",
    ]
    ET.indent(root)
    return xml_comment(lines) + ET.tostring(root, encoding="unicode") + "\n"


def _lines(s: OdeSettings, robot: RobotParams, spec, model, values, radius, mu: float, timestep: float) -> list[str]:
    """What opens it, what drives it and what it stands on, as the header states it."""
    plugin = model.find("plugin")
    left = [e.text for e in plugin.findall("left_joint")]
    right = [e.text for e in plugin.findall("right_joint")]
    written = ", ".join(f"<{p.rsplit('/', 1)[1]}> {t}" for p, t in values.items()) or "nothing (SDF's defaults)"
    ratio = float(s.friction_ratio)
    return [
        "NOT OPENED IN GAZEBO CLASSIC HERE: no Gazebo Classic installs on simpick's machine; the fields are checked "
        "against the catalog's quoted values and the robot's description (tests/test_classic_models.py), and "
        "sdformat 12 validates the file (ign sdf -k, which reads SDF 1.7 by converting it), not Gazebo Classic's "
        "sdformat 9",
        "opens as it is in Gazebo Classic 11 with gazebo_ros (ROS 2 Foxy to Humble): gazebo -s libgazebo_ros_init.so "
        "FILE, or ros2 launch gazebo_ros gazebo.launch.py world:=FILE; without gazebo_ros the world loads and the "
        "plugin does not",
        f"robot: model {model.get('name')}, {spec.name}'s URDF as sdformat converts it (fixed joints lumped; "
        f"primitive shapes only), its base {_num(SPAWN_CLEARANCE)} m above resting height; each driven wheel "
        f"joint's <limit><effort> {_num(robot.max_wheel_torque)} N m",
        f"drive: gazebo_ros_diff_drive (<plugin {DIFF_DRIVE['filename']}>, {DIFF_DRIVE_SOURCE}), a "
        "geometry_msgs/Twist on cmd_vel (linear.x v m/s, angular.z w rad/s); "
        f"{len(left)} wheel pairs, left joints {', '.join(left)}, right joints {', '.join(right)}; each pair's "
        f"joint velocity (v -+ w x wheel_separation / 2) / (wheel_diameter / 2) with wheel_separation "
        f"{_num(robot.track)} m, the controller's effective track (the wheels' own spacing is {_num(spec.track)} m), "
        f"wheel_diameter {_num(2 * radius)} m, set as ODE's joint motor (fmax = max_wheel_torque "
        f"{_num(robot.max_wheel_torque)} N m) at update_rate {_num(1 / timestep)} Hz, every step",
        f"ground: model ground_plane, a plane of <mu> {_num(mu)} and <mu2> {_num(mu * max(1.0, ratio))}, SDF's "
        f"<kp> {GROUND_KP:g} and <kd> {GROUND_KD:g} written out; each driven wheel's collision <surface>: {written}. "
        "Gazebo Classic takes the lower of two surfaces' mu and mu2, puts their kp in series and sums their kd "
        f"(ODEPhysics.cc:1107-1170), and sums slip1/slip2 times the pair's contact count, {CONTACTS_PER_WHEEL} per "
        "wheel on level ground (ODEPhysics.cc:1172-1186): so the contact's are the profile's "
        f"(friction_direction {s.friction_direction}, friction_ratio {_num(ratio)}, contact_slip "
        f"{_num(s.contact_slip)}, contact_kp {'unset' if s.contact_kp is None else _num(s.contact_kp)}, "
        f"contact_kd {_num(s.contact_kd)})",
        "no <max_vel> is written: Gazebo Classic applies SDF's 0.01 m/s per body (surface.sdf:194), which simpick's "
        "reproduction does not (the catalog's differs: ODE 0.16 cannot cap only the velocity left after the step)",
        f"physics: <physics type ode>, max_step_size {_num(timestep)} s, <max_contacts> {s.max_contacts}, solver "
        f"<type> {s.stepper}, <iters> {s.quick_iterations}, <sor> {_num(SOR)} (SDF 1.7's and ODE 0.16's, "
        f"physics.sdf:193), <cfm> {_num(s.cfm)}, <erp> {_num(s.erp)}, <contact_max_correcting_vel> "
        f"{_num(s.contact_max_correcting_vel)}, <contact_surface_layer> {_num(s.contact_surface_layer)} "
        "(sdformat sdf/1.7/physics.sdf:178-233)",
    ]


def _claim_lines(claims: Sequence[TurningClaim], base_link: str) -> list[str]:
    if not claims:
        return ["claims no yaw-rate gain: the study's validation has no turning case on this ground from heading 0"]
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [
        "claims the yaw-rate gains simpick's reproduction of this profile measured, not Gazebo Classic's: ODE 0.16 "
        "through simpick's ODE adapter with these values, the validation's run_case (custom elements "
        "simpick:yaw_rate_gain: case, v, w, duration, gain): from this pose at rest, the wheels' velocity commands "
        f"at (v, w)'s from the first step, the mean over the steps after the first half of the run of {base_link}'s "
        f"yaw rate about its own z axis, over w: {runs}"
    ]


__all__ = ["DIFF_DRIVE", "DIFF_DRIVE_SOURCE", "write_gazebo_classic_model"]
