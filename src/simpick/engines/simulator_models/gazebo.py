"""Gazebo (gz-sim): the robot on flat ground as one SDF 1.9 world that opens as it is (``ign gazebo FILE`` on
Fortress, ``gz sim FILE`` from Garden on), written from the adapter's own world
(:func:`simpick.engines.gzphysics_engine.world_tree`), so that what a user opens is what simpick stepped: the
``<physics>`` with the step and the profile's ``<dart>`` options, the ground, the robot as sdformat 12's URDF parser
converts it with the wheels' ``<surface>`` and the joints' effort limits.

Two things are added, neither read by the physics: what a gz-sim user drives it with, gz-sim's DiffDrive system on
the robot's model (the element names are its Configure's: gz-sim ign-gazebo6 aab5556f
src/systems/diff_drive/DiffDrive.cc:190-206 left_joint, right_joint, wheel_separation, wheel_radius; :336-340
topic; its wheel speeds :647-650, (v -+ w wheel_separation / 2) / wheel_radius; the same names at gz-sim10
ccd66949 DiffDrive.cc:191-206, 337), and what simpick claims, in SDF custom elements of the namespace
:data:`NAMESPACE` (sdformat copies an element whose name has a declared prefix and reads nothing in it): the
recorded base link and, per claimed case, its command, duration and yaw-rate gain (:class:`TurningClaim`).
Numbers are written at full double precision (``repr``), as the adapter writes them.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence

from simpick.engines.gzphysics_engine import (
    PLUGIN,
    PROGRAM,
    SPAWN_CLEARANCE,
    GzPhysicsEngine,
    GzPhysicsSettings,
    world_tree,
)
from simpick.engines.simulator_files.common import _num, xml_comment
from simpick.engines.simulator_models.common import ModelRequest, TurningClaim, add_sdf_claims
from simpick.inputs.robot.settings import RobotParams

# the custom elements' namespace, declared on <sdf> as xmlns:simpick (an SDF custom element needs its prefix declared)
NAMESPACE = "urn:simpick:model"
# gz-sim's DiffDrive system: Fortress reads "gz-sim" in a plugin's filename as "ignition-gazebo" (gz-sim
# ign-gazebo6 aab5556f src/SystemLoader.cc:73-79), so this one name loads it on Fortress and on gz-sim 7 and later,
# and the class by its alias (DiffDrive.cc:682 on ign-gazebo6, :665 on gz-sim10)
DIFF_DRIVE = {"filename": "gz-sim-diff-drive-system", "name": "gz::sim::systems::DiffDrive"}
# elements through which an SDF names another file
FILE_ELEMENTS = ("uri", "include")


def write_gazebo_model(request: ModelRequest) -> str:
    """The SDF text of the ``request``'s robot on a plane of its ground friction, with the Gazebo adapter's
    settings and the request's step; headed by its header lines and the lines this writer knows (what drives it, its
    ground, its claims); its name the world's, its characters outside [A-Za-z0-9_] made ``_`` (gz-sim puts it in
    topic names)."""
    spec_robot = request.robot.spec(request.robot_urdf)
    typed = GzPhysicsSettings.of(dict(request.settings), GzPhysicsEngine.name)
    scenario = request.flat_world(spec_robot, typed.model_dump(mode="json"))
    root = world_tree(scenario, typed)
    root.set("xmlns:simpick", NAMESPACE)
    world = root.find("world")
    if request.name:
        world.set("name", re.sub(r"[^A-Za-z0-9_]+", "_", request.name).strip("_"))
    model = world.find("model[@name='robot0']")
    driven = spec_robot.driven
    radii = {w.radius for w in driven}
    if any(w.axis_sign != 1 for w in driven) or len(radii) != 1:
        # DiffDrive gives each side's joints one speed, (v -+ w s / 2) / r: no mirrored axis, one radius
        raise ValueError(
            f"gz-sim's DiffDrive cannot drive {spec_robot.name}: it needs every driven wheel's joint to roll the "
            "robot forward at a positive speed and one wheel radius"
        )
    radius = radii.pop()
    topic = f"/model/{model.get('name')}/cmd_vel"
    plugin = ET.SubElement(model, "plugin", DIFF_DRIVE)
    for side in ("left", "right"):
        for wheel in driven:
            if wheel.side == side:
                ET.SubElement(plugin, f"{side}_joint").text = wheel.joint
    ET.SubElement(plugin, "wheel_separation").text = repr(float(request.robot.track))
    ET.SubElement(plugin, "wheel_radius").text = repr(float(radius))
    ET.SubElement(plugin, "topic").text = topic
    add_sdf_claims(
        model, spec_robot.base_link, request.robot.track, spec_robot.track, request.ground_mu, request.claims
    )
    named = sorted({e.tag for e in root.iter() if e.tag in FILE_ELEMENTS})
    if named:  # simpick's robot reader drops a description's meshes, so an engine's world names no file
        raise ValueError(
            f"the Gazebo model of {request.robot_urdf} names files ({', '.join(named)}): it would not open alone"
        )
    lines = [
        *request.header_lines,
        *_drive_lines(typed, request.robot, spec_robot, plugin, radius, topic, request.ground_mu, request.timestep),
        *_claim_lines(request.claims, spec_robot.base_link),
        f"written with {GzPhysicsEngine().version()} ({PROGRAM.name} convert: sdformat's URDF parser; numbers at "
        "full double precision)",
    ]
    ET.indent(root)  # whitespace between elements only: sdformat reads no element's text that it changes
    return xml_comment(lines) + ET.tostring(root, encoding="unicode") + "\n"


def _drive_lines(
    settings: GzPhysicsSettings, robot: RobotParams, spec_robot, plugin, radius: float, topic: str, mu: float, timestep
) -> list[str]:
    """What drives the model and what it stands on, as the header states it."""
    left = [e.text for e in plugin.findall("left_joint")]
    right = [e.text for e in plugin.findall("right_joint")]
    wheel_mu = settings.wheel_mu if settings.wheel_mu is not None else max(1.0, mu)
    wheel_mu2 = settings.wheel_mu2 if settings.wheel_mu2 is not None else wheel_mu
    fdir1 = "fdir1 1 0 0 (along the wheel)" if settings.fdir1 == "wheel_x" else "no fdir1 (the world's x and y)"
    return [
        "opens as it is: ign gazebo FILE (Fortress) or gz sim FILE (Garden and later), nothing else to load; no world "
        "<plugin>, so gz-sim loads its default systems, its Physics system with the dartsim plugin "
        f"({PLUGIN}) among them (gz-sim ign-gazebo6 src/SimulationRunner.cc:199-209, "
        "src/systems/physics/Physics.cc:726-729)",
        f"robot: model robot0, {spec_robot.name}'s URDF as sdformat 12 converts it (fixed joints lumped; primitive "
        f"shapes only, so the file names no other file), its base {_num(SPAWN_CLEARANCE)} m above resting height; "
        f"each driven wheel joint's <limit><effort> {_num(robot.max_wheel_torque)} N m, which dartsim makes the "
        "bound of DART's velocity servo (gz-physics ignition-physics5_5.1.0 dartsim/src/SDFFeatures.cc:138-139, "
        "JointFeatures.cc:162-165)",
        f"drive: gz-sim's DiffDrive system on robot0 (<plugin {DIFF_DRIVE['filename']}>), a gz.msgs.Twist on {topic} "
        f"(linear.x v m/s, angular.z w rad/s); left joints {', '.join(left)}, right joints {', '.join(right)}",
        f"(v, w) to each wheel joint's velocity command, rad/s (DiffDrive.cc:647-650): left joints (v - w x "
        f"wheel_separation / 2) / wheel_radius, right joints (v + w x wheel_separation / 2) / wheel_radius, with "
        f"wheel_separation {_num(robot.track)} m, the controller's effective track (the wheels' own spacing is "
        f"{_num(spec_robot.track)} m, custom element simpick:drive wheel_track), wheel_radius {_num(radius)} m; "
        "gz-sim's Physics system applies it each step as a joint velocity command",
        f"ground: model terrain, a plane of <mu> {_num(mu)} and <mu2> {_num(settings.friction_ratio * mu)} "
        f"(friction_ratio {_num(settings.friction_ratio)}; simpick:drive ground_friction); the wheels' <surface> "
        f"<mu> {_num(wheel_mu)}, <mu2> {_num(wheel_mu2)}, {fdir1}; DART takes the lower of two surfaces' "
        "coefficients in each direction",
        f"physics: <physics type dart>, max_step_size {_num(timestep)} s, <dart> collision_detector "
        f"{settings.collision_detector}, solver_type {settings.solver_type}",
    ]


def _claim_lines(claims: Sequence[TurningClaim], base_link: str) -> list[str]:
    if not claims:
        return ["claims no yaw-rate gain: the study's validation has no turning case on this ground from heading 0"]
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [
        "claims the yaw-rate gain simpick's validation measured on this world (custom elements "
        "simpick:yaw_rate_gain: case, v, w, duration, gain): from this pose at rest, the wheels' velocity commands "
        f"at (v, w)'s from the first step, the mean over the steps after the first half of the run of {base_link}'s "
        f"yaw rate about its own z axis (simpick:drive base_link), over w: {runs}"
    ]
