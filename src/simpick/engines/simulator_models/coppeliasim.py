"""CoppeliaSim: the robot on flat ground as a Python script for CoppeliaSim's ZeroMQ remote API
(``coppeliasim_zmqremoteapi_client``) that builds it in the running CoppeliaSim from the values simpick's PyBullet
adapter reproduces a CoppeliaSim profile with (:class:`simpick.engines.pybullet_engine.PyBulletSettings`): the
Bullet engine, its constraint-solving iterations and the physics step; a static respondable cuboid as the ground
with the ground's Bullet friction; the robot's URDF (``<stem>.urdf``, beside the script) through the URDF plugin;
every robot shape with Bullet friction 1 (Bullet multiplies two shapes' coefficients, so a wheel contact has the
ground's, as in the adapter); the wheels in velocity control with the study's torque as their force bound. It then
steps the simulation at each claimed command and prints the yaw-rate gain it measures (:mod:`.python_script`).

Every function and constant is CoppeliaSim's own, quoted in :data:`NAMES` from CoppeliaRobotics/coppeliaSimLib at
aea88174 (2025-05-18, CoppeliaSim 4.10), the URDF plugin CoppeliaRobotics/simURDF d6263b6 and the client
CoppeliaRobotics/zmqRemoteApi 66684dd. No CoppeliaSim installs here: tests/test_vendor_models.py checks every name the
script uses against that table and every value against the profile, but no CoppeliaSim runs it, and the gains it
claims are simpick's PyBullet multibody's (the catalog's "differs" says why it is not CoppeliaSim's rigid bodies).

What the profile may not set here: a lateral/longitudinal friction ratio (CoppeliaSim's Bullet material has one
coefficient per shape), compliant contacts or spinning friction (no Bullet 2.78 setting in CoppeliaSim) and Bullet
substeps (CoppeliaSim steps Bullet once per pass); the contact ERP is Bullet 2.78's own, which CoppeliaSim does not
expose. A robot with passive suspension or coupled joints is not written: the adapter's joint friction motors and
gears have no counterpart here.
"""

from __future__ import annotations

from collections.abc import Mapping

from simpick.engines.pybullet_engine import PyBulletSettings
from simpick.engines.simulator_files.common import _num
from simpick.engines.simulator_models.common import ModelRequest
from simpick.engines.simulator_models.python_script import (
    assign,
    claim_lines,
    claims_block,
    script,
    standalone_urdf,
    wheels_block,
)
from simpick.inputs.robot.settings import RobotParams

VERSION = "CoppeliaSim 4.10"
_LIB = "CoppeliaRobotics/coppeliaSimLib aea88174 sourceCode/interfaces/luaScriptFunctions.cpp"
_OLD = "CoppeliaRobotics/coppeliaSimLib aea88174 sourceCode/backwardCompatibility/interfaces/luaScriptFunctions-old.cpp"
# every CoppeliaSim name the script uses -> where it is registered; tests/test_vendor_models.py holds the script to it
NAMES = {
    "RemoteAPIClient": "CoppeliaRobotics/zmqRemoteApi 66684dd clients/python/src/coppeliasim_zmqremoteapi_client/"
    "__init__.py:41 (require :212)",
    "sim.setStepping": "zmqRemoteApi 66684dd coppeliasim_zmqremoteapi_client/__init__.py:288 (calls 'sim.setStepping')",
    "sim.step": "zmqRemoteApi 66684dd coppeliasim_zmqremoteapi_client/__init__.py:291 (calls 'sim.step')",
    "simURDF.importFile": (
        "CoppeliaRobotics/simURDF d6263b6 lua/simURDF.lua:7 (simURDF.importFile = simURDF.import; "
        "manual/simURDF.htm:75: import(fileName, options=0); links' collision shapes named "
        "<link>_respondable, sourceCode/link.cpp:670; joints by their URDF names, robot.cpp:638)"
    ),
    "sim.setInt32Param": f"{_OLD}:8743",
    "sim.setFloatParam": f"{_OLD}:8812",
    "sim.setEngineInt32Param": f"{_OLD}:9562",
    "sim.setObjectInt32Param": f"{_OLD}:9269",
    "sim.setEngineFloatParam": f"{_LIB}:680",
    "sim.createPrimitiveShape": f"{_LIB}:292",
    "sim.setObjectPosition": f"{_LIB}:156",
    "sim.getObjectsInTree": f"{_LIB}:322",
    "sim.getObjectAlias": f"{_LIB}:212",
    "sim.setJointTargetVelocity": f"{_LIB}:162",
    "sim.setJointTargetForce": f"{_LIB}:310",
    "sim.getObjectVelocity": f"{_LIB}:253",
    "sim.getObjectMatrix": f"{_LIB}:188",
    "sim.startSimulation": f"{_LIB}:187",
    "sim.stopSimulation": f"{_LIB}:185",
    "sim.getSimulationState": f"{_LIB}:167",
    "sim.intparam_dynamic_engine": f"{_LIB}:1452",
    "sim.physics_bullet": f"{_LIB}:928 (Bullet 2.78 by default, dynamicsContainer.cpp:33-34)",
    "sim.bullet_global_constraintsolvingiterations": f"{_LIB}:1736",
    "sim.floatparam_physicstimestep": f"{_LIB}:1494 (the physics step: dt / it passes a simulation step)",
    "sim.floatparam_simulation_time_step": f"{_LIB}:1490 (the simulation step, dt)",
    "sim.bullet_body_friction": f"{_LIB}:1749 (a shape's Bullet friction; dynMaterialObject.cpp:38-39)",
    "sim.primitiveshape_cuboid": f"{_LIB}:938",
    "sim.shapeintparam_static": f"{_LIB}:1649",
    "sim.shapeintparam_respondable": f"{_LIB}:1651",
    "sim.jointintparam_dynctrlmode": f"{_LIB}:1641",
    "sim.jointdynctrl_velocity": f"{_LIB}:923",
    "sim.handle_scene": f"{_LIB}:827",
    "sim.handle_world": f"{_LIB}:816",
    "sim.object_joint_type": f"{_LIB}:1057",
    "sim.object_shape_type": f"{_LIB}:1056",
    "sim.simulation_stopped": f"{_LIB}:743",
}
ROBOT_FRICTION = 1.0  # every robot shape's: Bullet multiplies it by the ground's (as the adapter sets it)
GROUND_SIZE = (100.0, 100.0, 0.1)  # m, the cuboid's sides; its top face at z = 0

IMPORTS = """import numpy as np
from coppeliasim_zmqremoteapi_client import RemoteAPIClient
"""

BODY = '''
CLIENT = None


def sim_api():
    """The running CoppeliaSim's sim and simURDF (CoppeliaSim started first, its ZeroMQ remote API on port 23000)."""
    global CLIENT
    if CLIENT is None:
        CLIENT = RemoteAPIClient()
    return CLIENT.require("sim"), CLIENT.require("simURDF")


def named(sim, name: str):
    """A CoppeliaSim constant by its quoted name ("sim.physics_bullet" -> sim.physics_bullet)."""
    return getattr(sim, name.removeprefix("sim."))


def build(sim, simurdf) -> tuple[int, list[int]]:
    """The scene's options, the ground and the robot: (the base's shape handle, the wheel joints' handles)."""
    for param, value in INT32_PARAMS.items():
        sim.setInt32Param(named(sim, param), named(sim, value))
    for param, value in ENGINE_INT32_PARAMS.items():
        sim.setEngineInt32Param(named(sim, param), -1, value)
    for param, value in FLOAT_PARAMS.items():
        sim.setFloatParam(named(sim, param), value)
    ground = sim.createPrimitiveShape(named(sim, "sim.primitiveshape_cuboid"), list(GROUND["size"]))
    sim.setObjectPosition(ground, [0.0, 0.0, -GROUND["size"][2] / 2], named(sim, "sim.handle_world"))
    for param, value in GROUND["int32"].items():
        sim.setObjectInt32Param(ground, named(sim, param), value)
    for param, value in GROUND["engine_float"].items():
        sim.setEngineFloatParam(named(sim, param), ground, value)
    before = set(sim.getObjectsInTree(named(sim, "sim.handle_scene"), named(sim, "sim.object_shape_type")))
    simurdf.importFile(str(Path(__file__).resolve().with_name(URDF)), URDF_OPTIONS)
    scene = named(sim, "sim.handle_scene")
    shapes = {sim.getObjectAlias(h): h for h in sim.getObjectsInTree(scene, named(sim, "sim.object_shape_type"))}
    for handle in set(shapes.values()) - before:  # every robot shape
        for param, value in ROBOT_SHAPE["engine_float"].items():
            sim.setEngineFloatParam(named(sim, param), handle, value)
    joints = {sim.getObjectAlias(h): h for h in sim.getObjectsInTree(scene, named(sim, "sim.object_joint_type"))}
    wheels = [joints[w["joint"]] for w in WHEELS]
    for handle in wheels:
        for param, value in WHEEL_JOINT["int32"].items():
            sim.setObjectInt32Param(handle, named(sim, param), named(sim, value))
        sim.setJointTargetForce(handle, WHEEL_JOINT["max_torque"])
    return shapes[BASE_LINK + "_respondable"], wheels


def run(v: float, w: float, duration: float) -> np.ndarray:
    """The scene built anew at rest, the wheels' command (v, w) set before the first step, ``duration`` s stepped
    (one physics pass a step): the base's yaw rate about its own z axis after each step."""
    sim, simurdf = sim_api()
    if sim.getSimulationState() != named(sim, "sim.simulation_stopped"):
        sim.stopSimulation()
    base, wheels = build(sim, simurdf)
    for handle, speed in zip(wheels, wheel_speeds(v, w)):
        sim.setJointTargetVelocity(handle, speed)
    sim.setStepping(True)
    sim.startSimulation()
    steps = int(round(duration / PHYSICS_STEP))
    rates = np.empty(steps)
    for k in range(steps):
        sim.step()
        m = sim.getObjectMatrix(base, named(sim, "sim.handle_world"))  # 3 x 4, row-major
        _, angular = sim.getObjectVelocity(base)
        rates[k] = float(np.dot([m[2], m[6], m[10]], angular))
    sim.stopSimulation()
    return rates
'''


def coppeliasim_values(settings: Mapping, ground_mu: float, robot: RobotParams, timestep: float) -> dict:
    """The script's data (variable -> value) from the PyBullet adapter's settings of a CoppeliaSim profile; raises
    where the profile sets what CoppeliaSim does not expose."""
    s = PyBulletSettings.model_validate(dict(settings))
    if s.friction_ratio != 1.0:
        raise ValueError("CoppeliaSim's Bullet material has one friction coefficient per shape: no friction_ratio")
    if s.contact_stiffness > 0 or s.spinning_friction > 0 or s.sub_steps > 1:
        raise ValueError("CoppeliaSim exposes no Bullet contact stiffness, spinning friction or substeps")
    step = float(s.time_step if s.time_step is not None else timestep)
    return {
        "PHYSICS_STEP": step,
        "INT32_PARAMS": {"sim.intparam_dynamic_engine": "sim.physics_bullet"},
        "ENGINE_INT32_PARAMS": {"sim.bullet_global_constraintsolvingiterations": int(s.solver_iterations)},
        "FLOAT_PARAMS": {"sim.floatparam_simulation_time_step": step, "sim.floatparam_physicstimestep": step},
        "GROUND": {
            "size": GROUND_SIZE,
            "int32": {"sim.shapeintparam_static": 1, "sim.shapeintparam_respondable": 1},
            "engine_float": {"sim.bullet_body_friction": float(ground_mu)},
        },
        "ROBOT_SHAPE": {"engine_float": {"sim.bullet_body_friction": ROBOT_FRICTION}},
        "WHEEL_JOINT": {
            "int32": {"sim.jointintparam_dynctrlmode": "sim.jointdynctrl_velocity"},
            "max_torque": float(robot.max_wheel_torque),
        },
        "URDF_OPTIONS": 0,
    }


def write_coppeliasim_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text}: ``py``, the remote-API script, and ``urdf``, the robot's description it imports
    (``<stem>.urdf``, the request's stem, "": ``coppeliasim``): the ``request``'s robot on a ground of its ground
    friction with the PyBullet adapter's settings of a CoppeliaSim profile, claiming its claims."""
    stem = request.stem or "coppeliasim"
    spec = request.robot.spec(request.robot_urdf)
    if spec.suspension or spec.couplings:
        raise ValueError(f"the CoppeliaSim model of {spec.name} is not written: its passive suspension is not")
    values = coppeliasim_values(request.settings, request.ground_mu, request.robot, request.timestep)
    comments = {
        "PHYSICS_STEP": "s: the physics step, and the simulation step (one pass a step)",
        "URDF_OPTIONS": "simURDF.import's options: none (the robot centred above the ground, resting on it)",
    }
    data = [
        claims_block(request.claims),
        assign("URDF", f"{stem}.urdf", "the robot's description, beside this file (the one simpick's adapter loads)"),
        assign("BASE_LINK", spec.base_link),
        wheels_block(spec, request.robot.track),
        *(assign(k, v, comments.get(k, "")) for k, v in values.items()),
    ]
    step = values["PHYSICS_STEP"]
    iterations = values["ENGINE_INT32_PARAMS"]["sim.bullet_global_constraintsolvingiterations"]
    header = [
        *request.header_lines,
        "NOT OPENED IN COPPELIASIM HERE: no CoppeliaSim installs on simpick's machine; the names the script uses are "
        "checked against CoppeliaSim's sources as quoted in simpick.engines.simulator_models.coppeliasim.NAMES and "
        "its values against the profile (tests/test_vendor_models.py)",
        f"runs against {VERSION} started with its ZeroMQ remote API (pip install coppeliasim-zmqremoteapi-client): "
        f"python {stem}.py (every claim), or --v V --w W [--duration S]; it imports {stem}.urdf from its own folder "
        "into the open scene (one scene per run: start from an empty one) and prints, per run, the yaw-rate gain",
        f"sets: Bullet (2.78), {iterations} constraint-solving iterations, physics and simulation step "
        f"{_num(step)} s; a static respondable cuboid ground, Bullet friction {_num(request.ground_mu)}; every "
        f"robot shape friction {_num(ROBOT_FRICTION)} (Bullet multiplies them: each wheel contact "
        f"{_num(request.ground_mu)}); the wheels in velocity control, max torque "
        f"{_num(request.robot.max_wheel_torque)} N m; Bullet 2.78's own contact ERP (0.2), which CoppeliaSim does not "
        "expose",
        *claim_lines(request.claims),
        "the gains claimed are simpick's PyBullet multibody's at this step and iterations, not CoppeliaSim's rigid "
        "bodies' (resources/simulators/simulators.yaml, coppeliasim, differs)",
    ]
    doc = (
        f"{request.name or spec.name}: CoppeliaSim (Bullet) on flat ground, built over the ZeroMQ remote API.\n\n"
        f"python {stem}.py runs every claim (CLAIMS) and prints the gain measured beside the one claimed;\n"
        f"python {stem}.py --v 0.5 --w 0.5 --duration 6 runs one command.\n"
    )
    return {"py": script(header, doc, IMPORTS, data, BODY), "urdf": standalone_urdf(spec.urdf)}


__all__ = ["NAMES", "coppeliasim_values", "write_coppeliasim_model"]
