"""MuJoCo: the robot on flat ground as one MJCF file that opens as it is (``mujoco.MjModel.from_xml_path``, the
``simulate`` viewer), written from the adapter's own world (:meth:`simpick.engines.mujoco_engine.MujocoEngine.spec`,
``MjSpec.to_xml``), so that what a user opens is what simpick stepped: the robot's collision shapes, its free
joint, the wheel servos, the wheel x ground contact pairs, the <option>, the IMU site and sensors.

What a user needs to drive it goes into MJCF ``<custom>`` elements beside the header: the actuators' order, the
track and wheel radius that map a command (v, w) to the wheels' ctrl, and the yaw-rate gains simpick's validation
measured on this model at its turning commands (:class:`TurningClaim`), each with its command and duration.
``to_xml`` writes numbers to 6 significant digits; measured on the Husky (MuJoCo 4.0.0), the file's gains match the
adapter's to 1e-9.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence

from simpick.engines.mujoco_engine import SENSORS, SPAWN_CLEARANCE, MujocoEngine, MujocoSettings
from simpick.engines.simulator_files.common import _num, xml_comment
from simpick.engines.simulator_models.common import ModelRequest, TurningClaim
from simpick.inputs.robot.settings import RobotParams

# the names the file gives the recorded robot's sensors (the adapter leaves them unnamed), in SENSORS' order
SENSOR_NAMES = {
    "accel": "imu_accelerometer",
    "gyro": "imu_gyro",
    "pos": "base_pos",
    "quat": "base_quat",
    "linvel": "base_linvel",
    "angvel": "base_angvel",
}
# attributes through which an MJCF names another file (an asset's, or the folders they are read from)
FILE_ATTRIBUTES = ("file", "meshdir", "texturedir", "assetdir")


def write_mujoco_model(request: ModelRequest) -> str:
    """The MJCF text of the ``request``'s robot on a plane of its ground friction, with MuJoCo's adapter's settings
    and the request's step; headed by its header lines and the lines this writer knows (what drives it, its ground,
    its claims); its name the model's (<mujoco model>)."""
    import mujoco

    spec_robot = request.robot.spec(request.robot_urdf)
    typed = MujocoSettings.model_validate(dict(request.settings))
    scenario = request.flat_world(spec_robot, typed.model_dump(mode="json"))
    spec = MujocoEngine().spec(scenario)
    spec.modelname = request.name or spec_robot.name
    labels = [SENSOR_NAMES[k] for k, _ in SENSORS if k in SENSOR_NAMES]
    for sensor, label in zip(spec.sensors, labels + [f"r0/{j}/speed" for j in spec_robot.wheel_joints], strict=True):
        sensor.name = label
    actuators = [a.name for a in spec.actuators]
    driven = spec_robot.driven
    spec.add_text(name="wheel_actuators", data=" ".join(actuators))
    numerics = {
        "command_track": [request.robot.track],
        "wheel_track": [spec_robot.track],
        # each driven wheel's own, as simpick's commands divide by it (RobotSpec.joint_speeds)
        "wheel_radius": [w.radius for w in driven],
        "wheel_side": [1.0 if w.side == "left" else -1.0 for w in driven],
        "wheel_axis_sign": [float(w.axis_sign) for w in driven],
        "ground_friction": [request.ground_mu],
        **{f"yaw_rate_gain/{c.case}": [c.v, c.w, c.duration, c.gain] for c in request.claims},
    }
    for key, data in numerics.items():
        spec.add_numeric(name=key, data=data)
    text = spec.to_xml()
    named = sorted({f"{e.tag} {a}" for e in ET.fromstring(text).iter() for a in e.attrib if a in FILE_ATTRIBUTES})
    if named:  # simpick's robot reader drops a description's meshes, so an engine's model names no file
        raise ValueError(
            f"the MuJoCo model of {request.robot_urdf} names files ({', '.join(named)}): it would not open alone"
        )
    lines = [
        *request.header_lines,
        *_drive_lines(typed, request.robot, spec_robot, actuators, request.ground_mu),
        *_claim_lines(request.claims),
    ]
    lines.append(f"written with MuJoCo {mujoco.__version__} (MjSpec.to_xml: numbers to 6 significant digits)")
    return xml_comment(lines) + text


def _drive_lines(settings: MujocoSettings, robot: RobotParams, spec_robot, actuators: list[str], mu: float) -> list:
    """What drives the model and what it stands on, as the header states it."""
    if settings.wheel_servo == "intvelocity":
        servo = f"an intvelocity servo (kp {_num(settings.wheel_servo_kp)} N m/rad, critically damped)"
    else:
        servo = f"a velocity servo (kv {_num(settings.wheel_servo_gain)} N m s/rad)"
    radius = " / ".join(dict.fromkeys(_num(w.radius) for w in spec_robot.driven))
    lines = [
        "opens as it is: mujoco.MjModel.from_xml_path(this file) or MuJoCo's simulate viewer, nothing else to load",
        f"robot: {spec_robot.name}'s collision shapes as simpick loads them (a description's meshes are dropped by "
        "simpick's reader, its visuals by MuJoCo's URDF importer), so the file names no other file; its bodies "
        f"are prefixed r0/ (robot 0 of simpick's world), its base {_num(SPAWN_CLEARANCE)} m above resting height",
        f"drive: ctrl = the driven wheels' joint speeds in rad/s, in actuator order {', '.join(actuators)} (custom "
        f"text wheel_actuators), each {servo} with torque within +-{_num(robot.max_wheel_torque)} N m",
        f"(v, w) in m/s and rad/s: a wheel's ctrl = (v - w x wheel_side x command_track / 2) x wheel_axis_sign / "
        f"wheel_radius (custom numerics, wheel_side, wheel_axis_sign and wheel_radius one per actuator; wheel_side 1 "
        f"on the left, y > 0, -1 on the right), with command_track {_num(robot.track)} m, the controller's "
        f"effective track (the wheels' own spacing is wheel_track {_num(spec_robot.track)} m), wheel_radius {radius} m",
    ]
    if settings.wheel_contact == "decoupled":
        across = (
            f", across the wheel {_num(settings.friction_ratio)} x mu (the wheels collide as capsules)"
            if settings.friction_ratio != 1.0
            else ""
        )
        contact = f"the wheels touch it through one <pair> each, of the ground's friction{across}"
    else:
        contact = "the wheels touch it through MuJoCo's default geom contact"
    lines.append(
        f"ground: the plane ground0, Coulomb friction {_num(mu)} (custom numeric ground_friction; priority 1, so "
        f"its friction is every contact's); {contact}"
    )
    lines.append(
        "sensors: imu_accelerometer and imu_gyro at site imu (REP-145 axes), the base's pose and velocity "
        "(base_pos, base_quat, base_linvel, base_angvel), each driven wheel's joint speed"
    )
    return lines


def _claim_lines(claims: Sequence[TurningClaim]) -> list[str]:
    if not claims:
        return ["claims no yaw-rate gain: the study's validation has no turning case on this ground from heading 0"]
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [
        "claims the yaw-rate gain simpick's validation measured on this model (custom numerics "
        "yaw_rate_gain/<case>: v, w, duration, gain): from this pose at rest, ctrl held at (v, w)'s from the first "
        "step, the mean over the steps after the first half of the run of the base's yaw rate about its own z axis "
        f"(the free joint's qvel[5]), over w: {runs}"
    ]
