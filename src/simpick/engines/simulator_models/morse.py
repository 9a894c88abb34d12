"""MORSE: the robot on flat ground as a ``morse.builder`` script (the file a MORSE user runs with ``morse run``) that
builds it in Blender from the robot's own parts, with the values simpick's PyBullet adapter reproduces a MORSE profile
with (:class:`simpick.engines.pybullet_engine.PyBulletSettings`): the game engine's frame rate (its physics step) and
its physics substeps, each driven wheel's friction and anisotropic friction, the ground's friction.

How the URDF maps onto Blender objects: MORSE robots are Blender objects, a chassis with its wheels as separate rigid
bodies that MORSE's wheeled-robot class joins to it at start-up, one 6-DoF constraint per wheel with its rotation
about the wheel's own z axis freed and driven by the constraint's motor (morse-simulator/morse 5f9d9897
src/morse/core/wheeled_robot.py:128-140, src/morse/helpers/joints.py:14-73). The script builds

- the chassis as one Blender cube: the box around the base's collision boxes (every link fixed to the base folded
  in, :attr:`simpick.inputs.robot.RobotSpec.rigid`), with the folded mass; it is the robot's object, whose class is
  MORSE's four-wheel skid-steer robot, SegwayRMP400 (src/morse/robots/segwayrmp400.py:5: a PhysicsDifferentialRobot
  whose own action does nothing), told where its wheels are by name (WheelFLName ... WheelRRName, as the builder's
  SegwayRMP400 and Pioneer3DX set them, src/morse/builder/robots/morserobots.py:78-87, 111-118);
- each driven wheel as a Blender cylinder of the wheel's radius, width and mass, turned so its z axis is the axle
  (MORSE turns the left and right wheels at -(v -+ e w) / r about z, wheeled_robot.py:167-182, so z points to the
  robot's right), centred where the URDF puts the wheel;
- the wheels' actuation as a MORSE user drives it: a MotionVWDiff actuator (v, w), whose set_speed service and
  stream MORSE's socket interface exposes, with the robot's FixTurningSpeed set to simpick's command track so that
  MORSE shares w between the sides as simpick's controller does (wheeled_robot.py:84-90, 103-104, 167-168);
- every robot object's material friction 1 and the ground's the ground's friction (Bullet multiplies two bodies'
  coefficients, as the PyBullet adapter relies on), and on the wheels, for a friction ratio r other than 1, Blender's
  anisotropic friction: 1 along the wheel's rolling axes (x, y) and r along its axle (z); Blender's coefficients stop
  at 1, so a ratio above 1 is written as 1/r along the rolling axes, 1 along the axle and the wheel's friction r
  (resources/simulators/calibration.yaml, morse);
- the ground as MORSE's empty environment's Ground object, its friction set;
- the game engine's frame rate 1/time_step (MORSE runs the physics at it) and its physics substeps.

What is approximated: the chassis is one box (not the base's several collision shapes), its centre of mass the box's
centre and its inertia Blender's own from the box, its mass and its form factor (not the URDF's inertia); the wheels'
inertia likewise Blender's from the cylinder; each wheel motor's bound is MORSE's fixed 300 (joints.py:72-73), not
the study's wheel torque; Bullet's solver iterations are Blender's fixed 10 and its contact ERP Bullet's own 0.2.

Every MORSE and Blender name the script uses is quoted in :data:`NAMES`, MORSE's from morse-simulator/morse 5f9d9897
(2022-03-22, MORSE 1.4), Blender's from Blender 2.78a's source (Microvellum/BlenderFD-2.78a 380db4b, the copy
resources/simulators/calibration.yaml cites). No MORSE installs here (it needs Blender 2.79's game engine):
tests/test_vendor_models.py checks every name the script uses against that table and every value against the
profile, but no MORSE runs it, and the gains it claims are simpick's PyBullet multibody's (the catalog's "differs"
says why they are not MORSE's rigid bodies').

What the profile may not set here: compliant contacts and spinning friction (MORSE's rigid bodies have none),
solver iterations other than Blender's 10 and a contact ERP other than Bullet's 0.2 (not exposed), a step whose
inverse is not a whole frame rate. A robot is written where MORSE's wheeled robot can hold it: two or four driven
cylinder wheels of one radius, as many on each side, no casters, suspension or couplings, and a chassis of boxes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from simpick.engines.pybullet_engine import SPAWN_CLEARANCE, PyBulletSettings
from simpick.engines.simulator_files.common import _header, _num
from simpick.engines.simulator_models.common import ModelRequest
from simpick.engines.simulator_models.python_script import assign, claim_lines, wheels_block
from simpick.inputs.robot.settings import RobotParams

VERSION = "MORSE 1.4 (Blender 2.79b's game engine)"
_MORSE = "morse-simulator/morse 5f9d9897 src/morse"
_RNA = "Microvellum/BlenderFD-2.78a 380db4b source/blender/makesrna/intern"
_GE = "Microvellum/BlenderFD-2.78a 380db4b source/gameengine"
# every MORSE and Blender name the script uses -> where it is defined; tests/test_vendor_models.py holds the script to
# it (module-level imports, every call and attribute the script's code names, every key of its data)
NAMES = {
    # MORSE's builder
    "morse.builder": f"{_MORSE}/builder/__init__.py:1-6 (morsebuilder, environment, robots, actuators)",
    "bpymorse": f"{_MORSE}/builder/bpymorse.py (imported by morse/builder/morsebuilder.py:5)",
    "Cube": f"{_MORSE}/builder/blenderobjects.py:25-26 (Mesh, :5-15: bpy.ops.mesh.primitive_cube_add, 2 m a side, "
    "Microvellum/BlenderFD-2.78a 380db4b source/blender/editors/mesh/editmesh_add.c:175; NO_COLLISION until set)",
    "Cylinder": f"{_MORSE}/builder/blenderobjects.py:34-35 (bpy.ops.mesh.primitive_cylinder_add: radius 1, depth 2 "
    "along z, editmesh_add.c:297-300, 326-327)",
    "MotionVWDiff": f"{_MORSE}/builder/actuators.py:115-116 (morse.actuators.v_omega_diff_drive.MotionVWDiff: "
    "src/morse/actuators/v_omega_diff_drive.py:9-76, set_speed(v, w) :51-60, robot.apply_vw_wheels :72-76)",
    "Environment": f"{_MORSE}/builder/environment.py:10, 20-86 (set_gravity(9.81) at :86, :537-544)",
    "simulator_frequency": f"{_MORSE}/builder/environment.py:799-825 (scene.game_settings.fps = base_frequency: "
    f"'physics fixed timestep = 1/fps', {_RNA}/rna_scene.c:4520-4527)",
    "set_physics_step_sub": f"{_MORSE}/builder/environment.py:654-664 (written at create: "
    "scene.game_settings.physics_step_sub, :349; Bullet, :348)",
    "create_new_material": f"{_MORSE}/builder/bpymorse.py:93-95",
    "get_object": f"{_MORSE}/builder/bpymorse.py:235",
    "morseable": f"{_MORSE}/builder/abstractcomponent.py:587-618 ('calling.robot_action': Robot_Tag, the MORSE logic)",
    "calling.robot_action": f"{_MORSE}/builder/abstractcomponent.py:599-600, 617 (the robot's logic module)",
    "properties": f"{_MORSE}/builder/abstractcomponent.py:271-292 (game properties)",
    "append": f"{_MORSE}/builder/abstractcomponent.py:150-171 (parents the actuator to the robot)",
    "add_interface": f"{_MORSE}/builder/abstractcomponent.py:516-523 (add_service and add_stream)",
    "name": f"{_MORSE}/builder/abstractcomponent.py:220-229 (sets the builder's basename: not renamed after)",
    "location": f"{_MORSE}/builder/abstractcomponent.py:230-235",
    "scale": f"{_MORSE}/builder/abstractcomponent.py:236-241",
    "rotate": f"{_MORSE}/builder/abstractcomponent.py:256-263 (euler, radians)",
    "x": f"{_MORSE}/builder/abstractcomponent.py:256 (rotate's x)",
    "base_frequency": f"{_MORSE}/builder/environment.py:799",
    "fastmode": f"{_MORSE}/builder/environment.py:20-28",
    "_bpy_object": f"{_MORSE}/builder/abstractcomponent.py:148 (as the builder's own robots use it, "
    "src/morse/builder/robots/morserobots.py:14)",
    "socket": f"{_MORSE}/builder/data.py:117-118 (an actuator's default socket reader), :553-554 (socket services)",
    "empty": "morse-simulator/morse 5f9d9897 data/environments/empty.blend (holds an object named Ground; MORSE's "
    "tests build on it, testing/base/builder_wheeled_robot.py:34)",
    "Ground": "morse-simulator/morse 5f9d9897 data/environments/empty.blend (its ground object)",
    # the robot's class and the properties it reads
    "morse.robots.segwayrmp400.SegwayRMP400": f"{_MORSE}/robots/segwayrmp400.py:5-39 (PhysicsDifferentialRobot)",
    "classpath": f"{_MORSE}/blender/main.py:196-202 (a Robot_Tag object's class)",
    "HasSuspension": f"{_MORSE}/core/wheeled_robot.py:18-21 (False: build_model_without_suspension, :123-140)",
    "FixTurningSpeed": f"{_MORSE}/core/wheeled_robot.py:84-90, 103-104 (replaces the wheel separation in (v, w))",
    "WheelFLName": f"{_MORSE}/core/wheeled_robot.py:24, 43-48 ('Wheel%sName' % index)",
    "WheelFRName": f"{_MORSE}/core/wheeled_robot.py:24, 43-48",
    "WheelRLName": f"{_MORSE}/core/wheeled_robot.py:24, 43-48 ('None': absent, morserobots.py:85)",
    "WheelRRName": f"{_MORSE}/core/wheeled_robot.py:24, 43-48",
    # Blender 2.78a: object game settings (bpy Object.game), material physics, the active material
    "game": f"{_RNA}/rna_object.c:2519",
    "physics_type": f"{_RNA}/rna_object.c:1684 (items :1630-1632: STATIC, RIGID_BODY)",
    "RIGID_BODY": f"{_RNA}/rna_object.c:1632",
    "use_actor": f"{_RNA}/rna_object.c:1697 (MORSE's set_rigid_body, src/morse/builder/morsebuilder.py:225-229)",
    "use_sleep": f"{_RNA}/rna_object.c:1718 ('No Sleeping'; morsebuilder.py:229)",
    "mass": f"{_RNA}/rna_object.c:1705-1708 (0.01-10000 kg)",
    "use_collision_bounds": f"{_RNA}/rna_object.c:1858",
    "collision_bounds_type": f"{_RNA}/rna_object.c:1863 (items :111-113: BOX, CYLINDER)",
    "BOX": f"{_RNA}/rna_object.c:111",
    "CYLINDER": f"{_RNA}/rna_object.c:113 (btCylinderShapeZ, {_GE}/Physics/Bullet/CcdPhysicsController.cpp:2524)",
    "use_anisotropic_friction": f"{_RNA}/rna_object.c:1847-1849",
    "friction_coefficients": f"{_RNA}/rna_object.c:1851-1856 (x, y, z of the object, range 0-1; to Bullet: "
    f"{_GE}/Converter/BL_BlenderDataConversion.cpp:1199-1201, Physics/Bullet/CcdPhysicsController.cpp:515, 595)",
    "active_material": "Blender 2.78a rna_object.c (Object.active_material; MORSE's Mesh.color, "
    "src/morse/builder/blenderobjects.py:18-19; the game engine reads the first slot, "
    f"{_GE}/Converter/BL_BlenderDataConversion.cpp:1153, 1159: no material, friction 0.5, :1168)",
    "physics": f"{_RNA}/rna_material.c:2077 (MaterialPhysics; MORSE's Robot.set_friction, morsebuilder.py:184-185)",
    "friction": f"{_RNA}/rna_material.c:1735-1738 (Coulomb friction, 0-100)",
}
ENVIRONMENT = "empty"
GROUND_OBJECT = "Ground"
ROBOT_CLASS = "morse.robots.segwayrmp400.SegwayRMP400"
ROBOT_FRICTION = 1.0  # every robot object's: Bullet multiplies it by the ground's (as the adapter sets it)
RIGID = {"physics_type": "RIGID_BODY", "use_actor": True, "use_sleep": True}  # MORSE's set_rigid_body
MORSE_ITERATIONS = 10  # Blender's CcdPhysicsEnvironment m_numIterations(10), CcdPhysicsEnvironment.cpp:407
BULLET_ERP = 0.2  # Bullet 2.84's contact ERP (the catalog's morse contact_erp)
MOTOR_BOUND = 300.0  # MORSE's wheel motor bound, src/morse/helpers/joints.py:72-73

IMPORTS = """from morse.builder import Cube, Cylinder, Environment, MotionVWDiff, bpymorse
"""

BODY = '''

def game_object(component, part: dict):
    """A Blender object's game physics (its keys of ``part["game"]``) and a material of its own with its friction
    (the game engine reads the first material; without one an object's friction is 0.5)."""
    obj = component._bpy_object
    for key, value in part["game"].items():
        setattr(obj.game, key, value)
    obj.active_material = bpymorse.create_new_material()
    obj.active_material.physics.friction = part["friction"]
    return obj


chassis = Cube(CHASSIS["name"])
chassis.name = CHASSIS["name"]
chassis.scale = tuple(side / 2 for side in CHASSIS["size"])  # the cube primitive is 2 m a side
chassis.location = CHASSIS["location"]
game_object(chassis, CHASSIS)
chassis.morseable("calling.robot_action")
chassis.properties(**ROBOT_PROPERTIES)

for part in WHEEL_BODIES:
    wheel = Cylinder(part["name"])
    wheel.name = part["name"]
    wheel.scale = (part["radius"], part["radius"], part["width"] / 2)  # the primitive: radius 1, 2 m along z
    wheel.rotate(x=WHEEL_ROLL)  # z along the axle, to the robot's right
    wheel.location = part["location"]
    game_object(wheel, part)

motion = MotionVWDiff()
motion.name = ACTUATOR
chassis.append(motion)
motion.add_interface(INTERFACE)

env = Environment(ENVIRONMENT, fastmode=True)
ground = bpymorse.get_object(GROUND["object"])
ground.active_material = bpymorse.create_new_material()
ground.active_material.physics.friction = GROUND["friction"]
env.simulator_frequency(base_frequency=FPS)
env.set_physics_step_sub(PHYSICS_STEP_SUB)
'''


def physics_values(settings: Mapping, timestep: float) -> dict:
    """The game engine's frame rate and physics substeps from the PyBullet adapter's settings of a MORSE profile;
    raises where the profile sets what MORSE does not expose."""
    s = PyBulletSettings.model_validate(dict(settings))
    if s.contact_stiffness > 0 or s.spinning_friction > 0:
        raise ValueError("MORSE's rigid bodies have no compliant contacts or spinning friction")
    if s.solver_iterations != MORSE_ITERATIONS:
        raise ValueError(f"Blender's game engine keeps Bullet's {MORSE_ITERATIONS} solver iterations")
    if s.contact_erp is not None and not math.isclose(s.contact_erp, BULLET_ERP):
        raise ValueError(f"MORSE does not expose Bullet's contact ERP ({BULLET_ERP})")
    step = float(s.time_step if s.time_step is not None else timestep)
    fps = round(1.0 / step)
    if not math.isclose(1.0 / step, fps, rel_tol=1e-4) or not 1 <= fps <= 10000:
        raise ValueError(f"Blender steps at a whole frame rate (1-10000 Hz): 1 / {step} s is not one")
    substeps = max(1, int(s.sub_steps))  # the adapter's 0 is one step
    if substeps > 50:
        raise ValueError("Blender's physics_step_sub is 1 to 50")
    return {"FPS": fps, "PHYSICS_STEP_SUB": substeps, "friction_ratio": float(s.friction_ratio)}


def wheel_friction(ratio: float) -> tuple[float, dict]:
    """A wheel's material friction and anisotropic game settings for a lateral/longitudinal ratio (the wheel's z is
    its axle): none at 1; below it (1, 1, r); above it, Blender's coefficients stopping at 1, (1/r, 1/r, 1) and the
    friction r."""
    if ratio == 1.0:
        return ROBOT_FRICTION, {"use_anisotropic_friction": False}
    if ratio < 1.0:
        return ROBOT_FRICTION, {"use_anisotropic_friction": True, "friction_coefficients": (1.0, 1.0, ratio)}
    return ROBOT_FRICTION * ratio, {
        "use_anisotropic_friction": True,
        "friction_coefficients": (1.0 / ratio, 1.0 / ratio, 1.0),
    }


def corners(driven) -> dict[str, object]:
    """MORSE's wheel slots (FL, FR, RL, RR) of the driven wheels: on each side the front-most first."""
    out = {}
    for side, letter in (("left", "L"), ("right", "R")):
        wheels = sorted((w for w in driven if w.side == side), key=lambda w: -w.position[0])
        for slot, wheel in zip(("F", "R"), wheels):
            out[slot + letter] = wheel
    return out


def writes_morse(robot) -> bool:
    """What MORSE's wheeled robot holds (src/morse/core/wheeled_robot.py:24, 43-48, 128-140, 167-182): two or four
    driven cylinder wheels of one radius, as many on each side (its FL, FR and RL, RR slots, one speed a side), no
    casters (MORSE's caster has no swivel), passive suspension or couplings (its wheels hang on the chassis), and a
    chassis of boxes (one Blender box)."""
    model = getattr(robot, "rigid", None)
    driven = robot.driven
    sides = [sum(w.side == s for w in driven) for s in ("left", "right")]
    return (
        model is not None
        and not (robot.casters or robot.suspension or robot.couplings)
        and sides[0] == sides[1]
        and sides[0] in (1, 2)
        and len(driven) == sum(sides)
        and len({w.radius for w in driven}) == 1
        and all(w.shape == "cylinder" for w in driven)
        and bool(model.chassis.shapes)
        and all(kind == "box" for kind, *_ in model.chassis.shapes)
    )


def _box(shapes) -> tuple[np.ndarray, np.ndarray]:
    """(centre, size) of the axis-aligned box around box shapes, in the base frame."""
    lows, highs = [], []
    for _, dims, position, rotation in shapes:
        half = np.abs(np.asarray(rotation, dtype=float)) @ (np.asarray(dims, dtype=float) / 2)
        lows.append(np.asarray(position, dtype=float) - half)
        highs.append(np.asarray(position, dtype=float) + half)
    low, high = np.min(lows, axis=0), np.max(highs, axis=0)
    return (low + high) / 2, high - low


def _name(text: str) -> str:
    return text.replace(".", "_")  # MORSE's builder refuses dots in a name


def morse_values(spec, settings: Mapping, ground_mu: float, robot: RobotParams, timestep: float) -> dict:
    """The script's data (variable -> value) for the robot ``spec`` with a MORSE profile's adapter ``settings``."""
    physics = physics_values(settings, timestep)
    model = spec.rigid
    lift = float(spec.base_height) + SPAWN_CLEARANCE
    centre, size = _box(model.chassis.shapes)
    friction, anisotropic = wheel_friction(physics["friction_ratio"])
    slots = corners(spec.driven)
    by_joint = {w.joint: slot for slot, w in slots.items()}
    bodies = []
    for wheel, (xyz, _, _, body) in zip(spec.driven, model.wheels, strict=True):
        bodies.append(
            {
                "name": _name(wheel.link),
                "joint": wheel.joint,
                "slot": by_joint[wheel.joint],
                "radius": float(wheel.radius),
                "width": float(wheel.width),
                "location": (float(xyz[0]), float(xyz[1]), float(xyz[2]) + lift),
                "game": {
                    **RIGID,
                    "mass": float(body.mass),
                    "use_collision_bounds": True,
                    "collision_bounds_type": "CYLINDER",
                    **anisotropic,
                },
                "friction": friction,
            }
        )
    names = {b["slot"]: b["name"] for b in bodies}
    return {
        "FPS": physics["FPS"],
        "PHYSICS_STEP_SUB": physics["PHYSICS_STEP_SUB"],
        "ENVIRONMENT": ENVIRONMENT,
        "GROUND": {"object": GROUND_OBJECT, "friction": float(ground_mu)},
        "CHASSIS": {
            "name": _name(spec.base_link),
            "size": tuple(float(v) for v in size),
            "location": (float(centre[0]), float(centre[1]), float(centre[2]) + lift),
            "game": {
                **RIGID,
                "mass": float(model.chassis.mass),
                "use_collision_bounds": True,
                "collision_bounds_type": "BOX",
            },
            "friction": ROBOT_FRICTION,
        },
        "ROBOT_PROPERTIES": {
            "classpath": ROBOT_CLASS,
            "HasSuspension": False,
            "FixTurningSpeed": float(robot.track),
            **{f"Wheel{slot}Name": names.get(slot, "None") for slot in ("FL", "FR", "RL", "RR")},
        },
        "WHEEL_BODIES": bodies,
        "WHEEL_ROLL": math.pi / 2,
        "ACTUATOR": "motion",
        "INTERFACE": "socket",
    }


def write_morse_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text}: ``py``, the builder script (run as ``<stem>.py``, the request's stem, "": ``morse``): the
    ``request``'s robot on a ground of its ground friction with the PyBullet adapter's settings of a MORSE profile,
    claiming its claims."""
    stem = request.stem or "morse"
    spec = request.robot.spec(request.robot_urdf)
    if not writes_morse(spec):
        raise ValueError(
            f"the MORSE model of {spec.name} is not written: MORSE's wheeled robot holds two or four driven cylinder "
            "wheels of one radius on a chassis of boxes, with no casters, suspension or couplings"
        )
    values = morse_values(spec, request.settings, request.ground_mu, request.robot, request.timestep)
    rows = [{"case": c.case, "v": c.v, "w": c.w, "duration": c.duration, "gain": c.gain} for c in request.claims]
    comments = {
        "FPS": "Hz: the game engine's frame rate, its physics step 1 / FPS (env.simulator_frequency)",
        "PHYSICS_STEP_SUB": "Bullet substeps per physics step (env.set_physics_step_sub)",
        "GROUND": "the empty environment's ground object and its friction",
        "CHASSIS": "the base as one box (m, kg; location: its centre, the robot resting on its wheels)",
        "ROBOT_PROPERTIES": "the chassis' game properties: MORSE's skid-steer robot class and its wheels by slot",
        "WHEEL_BODIES": "the driven wheels: Blender cylinders, their game physics and material friction",
        "WHEEL_ROLL": "rad about x: each cylinder's z turned onto its axle",
    }
    data = [
        assign(
            "CLAIMS",
            rows,
            "The yaw-rate gains simpick's validation measured on its PyBullet adapter with this profile (run_case):\n"
            "the robot at rest, (v m/s, w rad/s) held from the first step for duration s, the mean of the base's\n"
            "yaw rate about its own z axis over the second half of the run, over w. Not measured in MORSE.",
        ),
        wheels_block(spec, request.robot.track),
        *(assign(k, v, comments.get(k, "")) for k, v in values.items()),
    ]
    ratio = float(PyBulletSettings.model_validate(dict(request.settings)).friction_ratio)
    wheels = values["WHEEL_BODIES"]
    wheel = wheels[0]
    coefficients = ", ".join(_num(c) for c in wheel["game"].get("friction_coefficients", ()))
    anisotropic = (
        f"anisotropic friction ratio {_num(ratio)} (friction_coefficients ({coefficients}) along x, y, z)"
        if wheel["game"]["use_anisotropic_friction"]
        else "isotropic friction"
    )
    chassis = values["CHASSIS"]
    header = [
        *request.header_lines,
        "NOT OPENED IN MORSE HERE: MORSE needs Blender 2.79's game engine, which does not install on simpick's "
        "machine; the names the script uses are checked against MORSE's and Blender's sources as quoted in "
        "simpick.engines.simulator_models.morse.NAMES and its values against the profile (tests/test_vendor_models.py)",
        f"runs in {VERSION}: morse run {stem}.py; drive it through MORSE's socket interface: the {values['ACTUATOR']} "
        "actuator's set_speed(v, w) service or its (v, w) stream",
        f"writes: the chassis {spec.base_link} as a box {' x '.join(_num(v) for v in chassis['size'])} m of "
        f"{_num(chassis['game']['mass'])} kg (MORSE's SegwayRMP400 class, FixTurningSpeed "
        f"{_num(request.robot.track)} m); {len(wheels)} cylinder wheels r {_num(wheel['radius'])} m, width "
        f"{_num(wheel['width'])} m, "
        f"{_num(wheel['game']['mass'])} kg, friction {_num(wheel['friction'])}, {anisotropic}; a MotionVWDiff "
        f"actuator; the empty environment's Ground, friction {_num(request.ground_mu)}; {values['FPS']} Hz "
        f"(step {_num(1.0 / values['FPS'])} s), {values['PHYSICS_STEP_SUB']} physics substeps",
        f"approximated: one box for the chassis, Blender's own inertia from the shapes, MORSE's wheel motor bound "
        f"{_num(MOTOR_BOUND)} (not {_num(request.robot.max_wheel_torque)} N m), Blender's {MORSE_ITERATIONS} solver "
        "iterations",
        *claim_lines(request.claims),
        "the gains claimed are simpick's PyBullet multibody's at this step and substeps, not MORSE's rigid bodies' "
        "(resources/simulators/simulators.yaml, morse, differs)",
    ]
    doc = (
        f"{request.name or spec.name}: MORSE (Blender's game engine, Bullet) on flat ground, built with "
        "morse.builder.\n\n"
        f"morse run {stem}.py builds the scene and starts the simulation.\n"
    )
    text = _header("#", header) + f'"""{doc}"""\n\n' + IMPORTS + "\n" + "\n".join(data) + BODY
    return {"py": text}


__all__ = ["NAMES", "morse_values", "physics_values", "wheel_friction", "write_morse_model", "writes_morse"]
