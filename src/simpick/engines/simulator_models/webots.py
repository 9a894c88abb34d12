"""Webots: the robot on flat ground as one world file (``.wbt``, Webots R2023b and later: the Pose node), written
from the values simpick's ODE adapter reproduces a Webots profile with (:mod:`simpick.engines.ode_settings`): the
WorldInfo with the step, ERP and CFM, its contactProperties (the settings fragment's ContactProperties,
:func:`simpick.engines.simulator_files.webots.contact_properties`), a static ground Solid whose boundingObject is a
Plane, and the robot as a Robot node built from the description's collision primitives, rigid body by rigid body
as the ODE adapter builds it (:attr:`simpick.inputs.robot.RobotSpec.rigid`: fixed-joint chains folded): the base
with its Boxes, each driven wheel a HingeJoint whose RotationalMotor has the robot's maximum torque and whose
endPoint Solid has the wheel's Cylinder, its mass, centre of mass and inertia. The shapes are the ones the
anisotropy of a three-value coulombFriction needs (the wheels' Cylinder, the ground's Plane); the visuals are the
same shapes.

Node and field names are Webots' reference's (cyberbotics/webots docs/reference, :data:`WEBOTS_DOCS`). No Webots
installs here: the file is checked field by field against the catalog's quoted values and the robot's description
(tests/test_classic_models.py, with a tokenizer of VRML's syntax), but no Webots code opens it, and the gains it
claims are simpick's reproduction's (ODE 0.16 through simpick's adapter), not Webots'.
"""

from __future__ import annotations

import math

import numpy as np

from simpick.engines.base import GRAVITY
from simpick.engines.ode_settings import OdeSettings
from simpick.engines.ode_world import SPAWN_CLEARANCE
from simpick.engines.simulator_files.common import _num
from simpick.engines.simulator_files.webots import WEBOTS_FRICTION_SOURCE, contact_properties
from simpick.engines.simulator_models.common import ModelRequest
from simpick.inputs.robot.settings import RobotParams

VERSION = "R2025a"
# where each node's fields are read: cyberbotics/webots docs/reference/<node>.md, the field block at its head
WEBOTS_DOCS = (
    "cyberbotics/webots docs/reference: worldinfo.md:4-28 (gravity, CFM, ERP, basicTimeStep, contactProperties), "
    "contactproperties.md:4-19 (material1, material2, coulombFriction, frictionRotation, bounce, bounceVelocity, "
    "forceDependentSlip, softERP, softCFM, maxContactJoints), solid.md:6-20 and pose.md:4-9 (translation, rotation, "
    'name, contactMaterial, boundingObject, physics), robot.md (controller "<extern>"), physics.md:4-10 (density, '
    "mass, centerOfMass, inertiaMatrix about the centre of mass), hingejoint.md:6-9 and hingejointparameters.md:6-14 "
    "(device, axis, anchor in the parent's frame), rotationalmotor.md:6-10 and motor.md:6-15 (maxTorque, "
    "maxVelocity), cylinder.md (axis along z), plane.md (normal along z)"
)
# Webots' Motor default maxVelocity, rad/s (motor.md:12): written out, and above every claimed command's wheel speed
MAX_VELOCITY = 10.0
# the contact materials: the wheels', the rest of the robot's and the ground's (Webots' own "default")
WHEEL, BODY, GROUND = "wheel", "body", "default"


def _vec(values) -> str:
    return " ".join(repr(float(v)) for v in values)


def _axis_angle(rotation: np.ndarray) -> tuple[float, float, float, float]:
    """A rotation matrix as Webots' SFRotation (unit axis, angle)."""
    r = np.asarray(rotation, dtype=float)
    angle = math.acos(max(-1.0, min(1.0, (np.trace(r) - 1.0) / 2.0)))
    if angle < 1e-12:
        return (0.0, 0.0, 1.0, 0.0)
    if math.pi - angle < 1e-6:  # a half turn: the axis from the symmetric part
        axis = np.sqrt(np.maximum((np.diag(r) + 1.0) / 2.0, 0.0))
        i = int(np.argmax(axis))
        for j in range(3):
            if j != i:
                axis[j] = math.copysign(axis[j], r[i, j] + r[j, i])
    else:
        axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2.0 * math.sin(angle))
    axis = axis / np.linalg.norm(axis)
    return (float(axis[0]), float(axis[1]), float(axis[2]), float(angle))


def _geometry(kind: str, dims) -> str:
    if kind == "box":
        return f"Box {{ size {_vec(dims)} }}"
    if kind == "cylinder":
        radius, length = dims
        return f"Cylinder {{ height {float(length)!r} radius {float(radius)!r} }}"
    return f"Sphere {{ radius {float(dims[0])!r} }}"


def _shapes(body, pad: str) -> tuple[list[str], list[str]]:
    """(children, boundingObject) lines of a body's collision shapes, each in a Pose at its place in the body."""
    children, bounds = [], []
    for kind, dims, position, rotation in body.shapes:
        pose = f"translation {_vec(position)} rotation {_vec(_axis_angle(rotation))}"
        geometry = _geometry(kind, dims)
        children.append(f"{pad}Pose {{ {pose} children [ Shape {{ geometry {geometry} }} ] }}")
        bounds.append(f"{pad}  Pose {{ {pose} children [ {geometry} ] }}")
    return children, bounds


def _physics(body) -> str:
    i = body.inertia
    return (
        f"Physics {{ density -1 mass {float(body.mass)!r} centerOfMass [ {_vec(body.com)} ] inertiaMatrix "
        f"[ {_vec((i[0, 0], i[1, 1], i[2, 2]))} {_vec((i[0, 1], i[0, 2], i[1, 2]))} ] }}"
    )


def _solid_fields(body, material: str, pad: str, name: str = "") -> list[str]:
    children, bounds = _shapes(body, pad + "  ")
    return [
        f'{pad}name "{name or body.link}"',
        f'{pad}contactMaterial "{material}"',
        f"{pad}children [",
        *children,
        f"{pad}]",
        f"{pad}boundingObject Group {{ children [",
        *bounds,
        f"{pad}] }}",
        f"{pad}physics {_physics(body)}",
    ]


def write_webots_model(request: ModelRequest) -> str:
    """The .wbt text of the ``request``'s robot on a Plane of its ground friction, with the ODE adapter's settings
    (a Webots profile's in full) and the request's step; headed by its header lines and what this writer knows; its
    name the world's title."""
    spec = request.robot.spec(request.robot_urdf)
    s = OdeSettings.of(dict(request.settings), "ode")
    model = spec.rigid
    if model is None or model.suspension or model.passive or spec.couplings:
        raise ValueError(
            f"the Webots model writes a robot whose moving joints are its driven wheels on its base; {spec.name} "
            "has suspension joints, couplings or casters"
        )
    if s.stepper != "world":
        raise ValueError("Webots steps with dWorldStep (the catalog's stepper 'world'); the profile sets 'quick'")
    if s.friction_direction not in ("plane", "wheel") or (s.friction_direction == "plane" and s.friction_ratio != 1):
        raise ValueError(
            f"Webots gives friction_direction 'plane' (one coulombFriction value) or 'wheel' (three, on the wheels' "
            f"Cylinder), not {s.friction_direction!r} with friction_ratio {s.friction_ratio}"
        )
    if s.contact_kp is not None or s.surface_mu is not None or s.contact_min_depth is not None:
        raise ValueError("Webots has no field for contact_kp, surface_mu or contact_min_depth")
    if not (math.isinf(s.contact_max_correcting_vel) and s.contact_surface_layer == 0.0):
        raise ValueError(
            "Webots exposes neither ODE's contact_max_correcting_vel nor its contact_surface_layer: the profile must "
            "keep ODE's defaults (inf, 0)"
        )
    driven = spec.driven
    speeds = [abs(c.v) + abs(c.w) * float(request.robot.track) / 2 for c in request.claims]
    fastest = max(speeds, default=0.0) / min(w.radius for w in driven)
    if fastest >= MAX_VELOCITY:
        raise ValueError(f"a claimed command turns a wheel at {fastest:.3g} rad/s, above maxVelocity {MAX_VELOCITY}")
    wheel_directions = s.friction_direction == "wheel"
    info = [
        f"simpick model: {request.name or spec.name}; its gains are simpick's ODE reproduction's, not Webots'",
        *(
            f"simpick yaw_rate_gain {c.case}: v {c.v!r} w {c.w!r} duration {c.duration!r} gain {c.gain!r}"
            for c in request.claims
        ),
    ]
    body_settings = {**s.model_dump(mode="json"), "friction_ratio": 1.0}
    lines = [
        f"#VRML_SIM {VERSION} utf8",
        *(
            f"# {line}".rstrip()
            for line in _header(
                request.header_lines, s, request.robot, spec, request.claims, request.ground_mu, request.timestep
            )
        ),
        "WorldInfo {",
        "  info [",
        *(f'    "{text}"' for text in info),
        "  ]",
        f'  title "{request.name or spec.name}"',
        f"  gravity {float(GRAVITY)!r}",
        f"  CFM {float(s.cfm)!r}",
        f"  ERP {float(s.erp)!r}",
        f"  basicTimeStep {float(request.timestep) * 1000.0!r}  # ms",
        "  contactProperties [",
        *(
            f"    {line}"
            for line in contact_properties(s.model_dump(mode="json"), request.ground_mu, WHEEL, wheel_directions)
        ),
        *(f"    {line}" for line in contact_properties(body_settings, request.ground_mu, BODY)),
        "  ]",
        "}",
        "Viewpoint {",
        "  orientation 0 0 1 0",
        "  position -6 0 1.5",
        "}",
        "Solid {",
        '  name "ground"',
        f'  contactMaterial "{GROUND}"',
        "  children [ Shape { geometry Plane { size 100 100 } } ]",
        "  boundingObject Plane { size 100 100 }",
        "}",
        "Robot {",
        f"  translation {_vec((0.0, 0.0, spec.base_height + SPAWN_CLEARANCE))}",
        "  rotation 0 0 1 0",
        '  controller "<extern>"',
        *_solid_fields(model.chassis, BODY, "  ", spec.name)[:3],
    ]
    chassis = _solid_fields(model.chassis, BODY, "  ", spec.name)
    for wheel, (xyz, rotation, axis, body) in zip(driven, model.wheels, strict=True):
        hinge_axis = np.asarray(rotation) @ np.asarray(axis, dtype=float)
        lines += [
            "    HingeJoint {",
            f"      jointParameters HingeJointParameters {{ axis {_vec(hinge_axis)} anchor {_vec(xyz)} }}",
            "      device [",
            f'        RotationalMotor {{ name "{wheel.joint}" maxTorque {float(request.robot.max_wheel_torque)!r} '
            f"maxVelocity {MAX_VELOCITY!r} }}",
            f'        PositionSensor {{ name "{wheel.joint} sensor" }}',
            "      ]",
            "      endPoint Solid {",
            f"        translation {_vec(xyz)}",
            f"        rotation {_vec(_axis_angle(rotation))}",
            *_solid_fields(body, WHEEL, "        "),
            "      }",
            "    }",
        ]
    lines += [*chassis[3:], "}"]
    return "\n".join(lines) + "\n"


def _header(header_lines, s: OdeSettings, robot: RobotParams, spec, claims, mu: float, timestep: float) -> list[str]:
    motors = ", ".join(w.joint for w in spec.driven)
    left = ", ".join(w.joint for w in spec.driven if w.side == "left")
    right = ", ".join(w.joint for w in spec.driven if w.side == "right")
    ratio = float(s.friction_ratio)
    friction = (
        f"three values [{_num(ratio * mu)} {_num(mu)} 0] on the wheels' Cylinder: across the wheel, along it, the "
        f"ground's share ({WEBOTS_FRICTION_SOURCE}); the ground's Plane gives friction directions too"
        if s.friction_direction == "wheel"
        else f"one value {_num(mu)}, symmetric: ODE's own directions (dPlaneSpace, the world's x and y)"
    )
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [
        *header_lines,
        "NOT OPENED IN WEBOTS HERE: no Webots installs on simpick's machine; the fields are checked against the "
        "catalog's quoted values and the robot's description (tests/test_classic_models.py), the node and field "
        f"names against Webots' reference ({WEBOTS_DOCS})",
        f"opens as it is in Webots {VERSION} (R2023b or later: the Pose node): webots FILE; the robot's controller "
        "is <extern>: a controller started beside it (webots-controller, or webots_ros2_driver) drives it",
        f"robot: {spec.name}'s collision primitives as rigid bodies, fixed joints folded (the ODE adapter's bodies); "
        f"its base {_num(SPAWN_CLEARANCE)} m above resting height, contactMaterial {BODY!r}; each driven wheel a "
        f"HingeJoint with a RotationalMotor named after its joint ({motors}), maxTorque "
        f"{_num(robot.max_wheel_torque)} N m, maxVelocity {_num(MAX_VELOCITY)} rad/s (Webots' default), its "
        f"endPoint Solid's boundingObject a Cylinder, contactMaterial {WHEEL!r}",
        f"drive: per motor setPosition(inf), then setVelocity: left motors ({left}) (v - w x {_num(robot.track)} / 2) "
        f"/ r, right motors ({right}) (v + w x {_num(robot.track)} / 2) / r, r {_num(spec.wheel_radius)} m, with "
        f"{_num(robot.track)} m the controller's effective track (the wheels' own spacing is {_num(spec.track)} m); "
        "Webots' velocity control applies it as ODE's joint motor with fmax maxTorque (motor.md)",
        f"ground: a static Solid with a Plane boundingObject, contactMaterial {GROUND!r}; ContactProperties "
        f"{WHEEL!r} x {GROUND!r}: coulombFriction {friction}; {BODY!r} x {GROUND!r} the same coefficient, "
        "symmetric; both with the profile's forceDependentSlip, softERP, softCFM, bounce, bounceVelocity and "
        "maxContactJoints",
        f"physics: basicTimeStep {_num(timestep * 1000)} ms (the step simpick ran; Webots' default is 32), ERP "
        f"{_num(s.erp)}, CFM {_num(s.cfm)}, dWorldStep (Webots' own stepper); ODE's contact_max_correcting_vel "
        "(inf) and contact_surface_layer (0) are not exposed and keep ODE's defaults",
        "claims the yaw-rate gains simpick's reproduction of this profile measured, not Webots': ODE 0.16 through "
        "simpick's ODE adapter with these values, the validation's run_case (WorldInfo info: case, v, w, duration, "
        f"gain), from this pose at rest, the wheels' commands from the first step, the mean of {spec.base_link}'s yaw "
        f"rate about its own z axis over the second half of the run, over w: {runs or 'none'}",
    ]


__all__ = ["WEBOTS_DOCS", "write_webots_model"]
