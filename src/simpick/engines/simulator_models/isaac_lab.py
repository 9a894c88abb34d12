"""Isaac Sim / Isaac Lab (PhysX): the robot on flat ground as a Python script that sets it up with Isaac Lab's own
configuration classes from the values simpick's PhysX adapter runs (:class:`simpick.engines.physx_engine.PhysxEngine`,
PhysX 5 through SAPIEN): a ``SimulationCfg`` with the profile's ``PhysxCfg`` (solver type, bounce threshold) and
step, the wheels' ``RigidBodyMaterialCfg`` as the scene's default material, a ``GroundPlaneCfg`` with the ground's
own material, the robot's URDF (``<stem>.urdf``, beside the script) through ``UrdfFileCfg`` with the profile's
``ArticulationRootPropertiesCfg`` iterations, and an ``ArticulationCfg`` whose wheels are one
``ImplicitActuatorCfg`` (stiffness 0, damping the profile's drive damping, effort limit the study's wheel torque);
the script drives them at each claimed command and prints the yaw-rate gain it measures (:mod:`.python_script`).

Every class and keyword is Isaac Lab 2.3's, quoted in :data:`FIELDS` from isaac-sim/IsaacLab at tag v2.3.0 (the
source tree the isaaclab 2.3.0 wheel ships, extension isaaclab 0.47.2). No Isaac Sim installs here (it needs an
NVIDIA GPU driver and Omniverse Kit): tests/test_vendor_models.py parses the script and checks every keyword against
that table and every value against the profile, but no Isaac Lab code runs it, and the gains it claims are simpick's
PhysX adapter's (SAPIEN 3's PhysX 5.3 on the CPU), not Isaac Sim's.

What the adapter does that the script does not: it stands 4 turned 64-sided convex prisms in for each collision
cylinder (SAPIEN's own cylinder is coarser; Isaac Sim's URDF importer makes its own collider of the cylinder), and it
gives the contact the ground's coefficient as the average of 0 on the robot and twice the ground's; the script gives
the same coefficient with the wheels at 1 and PhysX's ``multiply`` combine mode, so the ground's material holds the
ground's own value. A robot with passive suspension or coupled joints is not written: the adapter's joint friction
(a force set before every step) and its fixed tendons have no configuration class here.
"""

from __future__ import annotations

from collections.abc import Mapping

from simpick.engines.base import GRAVITY
from simpick.engines.physx_engine import SPAWN_CLEARANCE, PhysxSettings
from simpick.engines.simulator_files.common import _num
from simpick.engines.simulator_files.python_setups import PHYSX_SOLVER, python_blocks
from simpick.engines.simulator_models.common import ModelRequest
from simpick.engines.simulator_models.python_script import (
    assign,
    claim_lines,
    claims_block,
    over_fragment,
    script,
    standalone_urdf,
    wheels_block,
)
from simpick.inputs.robot.settings import RobotParams

VERSION = "Isaac Lab 2.3 (Isaac Sim 5.1)"
_IL = "isaac-sim/IsaacLab v2.3.0 source/isaaclab/isaaclab/"
# class -> (where it is defined, {keyword the script passes: where it is declared}); tests/test_vendor_models.py
# holds every keyword of the script to this table
FIELDS: dict[str, tuple[str, dict[str, str]]] = {
    "PhysxCfg": (
        f"{_IL}sim/simulation_cfg.py:20",
        {
            "solver_type": "simulation_cfg.py:37 (Literal[0, 1] = 1; 0 PGS, 1 TGS)",
            "bounce_threshold_velocity": "simulation_cfg.py:110 (m/s, default 0.5)",
        },
    ),
    "SimulationCfg": (
        f"{_IL}sim/simulation_cfg.py:330",
        {
            "device": 'simulation_cfg.py:336 (default "cuda:0")',
            "dt": "simulation_cfg.py:346 (s, default 1 / 60)",
            "gravity": "simulation_cfg.py:352 (m/s^2, default (0, 0, -9.81))",
            "physx": "simulation_cfg.py:393 (PhysxCfg)",
            "physics_material": (
                "simulation_cfg.py:396 (RigidBodyMaterialCfg: the material of every rigid body prim with none of "
                "its own, the robot's shapes here)"
            ),
        },
    ),
    "RigidBodyMaterialCfg": (
        f"{_IL}sim/spawners/materials/physics_materials_cfg.py:30",
        {
            "static_friction": "physics_materials_cfg.py:38 (default 0.5)",
            "dynamic_friction": "physics_materials_cfg.py:41 (default 0.5)",
            "restitution": "physics_materials_cfg.py:44 (default 0.0)",
            "friction_combine_mode": 'physics_materials_cfg.py:47 ("average", "min", "multiply", "max")',
            "restitution_combine_mode": 'physics_materials_cfg.py:57 ("average", "min", "multiply", "max")',
        },
    ),
    "GroundPlaneCfg": (
        f"{_IL}sim/spawners/from_files/from_files_cfg.py:141",
        {
            "size": "from_files_cfg.py:158 (m, default (100, 100))",
            "physics_material": "from_files_cfg.py:161 (RigidBodyMaterialCfg)",
        },
    ),
    "UrdfFileCfg": (
        f"{_IL}sim/spawners/from_files/from_files_cfg.py:114 (FileCfg and UrdfConverterCfg)",
        {
            "asset_path": "sim/converters/asset_converter_base_cfg.py:15",
            "force_usd_conversion": "asset_converter_base_cfg.py:35 (default False)",
            "make_instanceable": "asset_converter_base_cfg.py:41 (default True)",
            "fix_base": "sim/converters/urdf_converter_cfg.py:90 (required)",
            "merge_fixed_joints": "urdf_converter_cfg.py:102 (default True)",
            "self_collision": "urdf_converter_cfg.py:126 (default False)",
            "joint_drive": "urdf_converter_cfg.py:108 (JointDriveCfg)",
            "articulation_props": "sim/spawners/from_files/from_files_cfg.py:39 (ArticulationRootPropertiesCfg)",
            "rigid_props": "sim/spawners/spawner_cfg.py:82 (RigidBodyPropertiesCfg)",
            "collision_props": "sim/spawners/spawner_cfg.py:89 (CollisionPropertiesCfg)",
        },
    ),
    "UrdfConverterCfg.JointDriveCfg": (
        f"{_IL}sim/converters/urdf_converter_cfg.py:18",
        {
            "drive_type": 'urdf_converter_cfg.py:71 ("acceleration" or "force", default "force")',
            "target_type": 'urdf_converter_cfg.py:79 ("none", "position" or "velocity")',
            "gains": "urdf_converter_cfg.py:87 (PDGainsCfg)",
        },
    ),
    "UrdfConverterCfg.JointDriveCfg.PDGainsCfg": (
        f"{_IL}sim/converters/urdf_converter_cfg.py:22",
        {
            "stiffness": "urdf_converter_cfg.py:25",
            "damping": "urdf_converter_cfg.py:33 (default None)",
        },
    ),
    "ArticulationRootPropertiesCfg": (
        f"{_IL}sim/schemas/schemas_cfg.py:15",
        {
            "enabled_self_collisions": "schemas_cfg.py:28",
            "solver_position_iteration_count": "schemas_cfg.py:31",
            "solver_velocity_iteration_count": "schemas_cfg.py:34",
        },
    ),
    "RigidBodyPropertiesCfg": (
        f"{_IL}sim/schemas/schemas_cfg.py:58",
        {"linear_damping": "schemas_cfg.py:83", "angular_damping": "schemas_cfg.py:86"},
    ),
    "CollisionPropertiesCfg": (
        f"{_IL}sim/schemas/schemas_cfg.py:121",
        {"contact_offset": "schemas_cfg.py:134 (m)", "rest_offset": "schemas_cfg.py:142 (m)"},
    ),
    "ArticulationCfg.InitialStateCfg": (
        f"{_IL}assets/articulation/articulation_cfg.py:20 (over AssetBaseCfg.InitialStateCfg)",
        {"pos": "assets/asset_base_cfg.py:35 (m)", "rot": "assets/asset_base_cfg.py:37 (w, x, y, z)"},
    ),
    "ImplicitActuatorCfg": (
        f"{_IL}actuators/actuator_cfg.py:173 (over ActuatorBaseCfg, :17)",
        {
            "joint_names_expr": "actuator_cfg.py:26",
            "effort_limit_sim": (
                "actuator_cfg.py:79 (the solver's effort bound; for an implicit actuator effort_limit is the same)"
            ),
            "stiffness": "actuator_cfg.py:112",
            "damping": "actuator_cfg.py:122",
            "friction": "actuator_cfg.py:143 (the joint's PhysX friction coefficient)",
        },
    ),
}
# the script's variables, each the keywords of one class above
VARIABLES = {
    "PHYSX": "PhysxCfg",
    "SIMULATION": "SimulationCfg",
    "WHEEL_MATERIAL": "RigidBodyMaterialCfg",
    "GROUND_MATERIAL": "RigidBodyMaterialCfg",
    "GROUND_PLANE": "GroundPlaneCfg",
    "URDF_FILE": "UrdfFileCfg",
    "JOINT_DRIVE": "UrdfConverterCfg.JointDriveCfg",
    "JOINT_GAINS": "UrdfConverterCfg.JointDriveCfg.PDGainsCfg",
    "ARTICULATION_ROOT": "ArticulationRootPropertiesCfg",
    "RIGID_BODY": "RigidBodyPropertiesCfg",
    "COLLISION": "CollisionPropertiesCfg",
    "INITIAL_STATE": "ArticulationCfg.InitialStateCfg",
    "WHEEL_ACTUATOR": "ImplicitActuatorCfg",
    "PASSIVE_ACTUATOR": "ImplicitActuatorCfg",
}
# both materials combine by multiplying (physics_materials_cfg.py:47; where two modes meet PhysX takes the one of
# higher priority, :50-53): the wheels at 1 give each contact the ground's own coefficient
WHEEL_FRICTION = 1.0
COMBINE = "multiply"

IMPORTS = """import numpy as np
from isaaclab.app import AppLauncher

# Isaac Sim's application starts before any other Isaac Lab module is imported
simulation_app = AppLauncher(headless=True).app
import isaaclab.sim as sim_utils  # noqa: E402
import torch  # noqa: E402
from isaaclab.actuators import ImplicitActuatorCfg  # noqa: E402
from isaaclab.assets import Articulation, ArticulationCfg  # noqa: E402
"""

BODY = '''

def build():
    """The simulation, the ground and the robot, reset: (simulation, articulation, wheel joint ids)."""
    JointDriveCfg = sim_utils.UrdfConverterCfg.JointDriveCfg
    sim = sim_utils.SimulationContext(
        sim_utils.SimulationCfg(
            physx=sim_utils.PhysxCfg(**PHYSX),
            physics_material=sim_utils.RigidBodyMaterialCfg(**WHEEL_MATERIAL),
            **SIMULATION,
        )
    )
    material = sim_utils.RigidBodyMaterialCfg(**GROUND_MATERIAL)
    ground = sim_utils.GroundPlaneCfg(physics_material=material, **GROUND_PLANE)
    ground.func("/World/ground", ground)
    actuators = {"wheels": ImplicitActuatorCfg(joint_names_expr=[w["joint"] for w in WHEELS], **WHEEL_ACTUATOR)}
    if PASSIVE_JOINTS:  # free: no drive, no joint friction
        actuators["passive"] = ImplicitActuatorCfg(joint_names_expr=list(PASSIVE_JOINTS), **PASSIVE_ACTUATOR)
    robot = Articulation(
        ArticulationCfg(
            prim_path="/World/robot",
            spawn=sim_utils.UrdfFileCfg(
                asset_path=str(Path(__file__).resolve().with_name(URDF)),
                joint_drive=JointDriveCfg(gains=JointDriveCfg.PDGainsCfg(**JOINT_GAINS), **JOINT_DRIVE),
                articulation_props=sim_utils.ArticulationRootPropertiesCfg(**ARTICULATION_ROOT),
                rigid_props=sim_utils.RigidBodyPropertiesCfg(**RIGID_BODY),
                collision_props=sim_utils.CollisionPropertiesCfg(**COLLISION),
                **URDF_FILE,
            ),
            init_state=ArticulationCfg.InitialStateCfg(**INITIAL_STATE),
            actuators=actuators,
        )
    )
    sim.reset()
    ids, _ = robot.find_joints([w["joint"] for w in WHEELS], preserve_order=True)
    return sim, robot, ids


SCENE = None


def run(v: float, w: float, duration: float) -> np.ndarray:
    """The robot put back at rest at its start, the wheels' command (v, w) set before the first step, ``duration`` s
    stepped: the base's yaw rate about its own z axis after each step (Isaac Lab's root_ang_vel_b)."""
    global SCENE
    if SCENE is None:
        SCENE = build()
    sim, robot, ids = SCENE
    root = robot.data.default_root_state.clone()
    robot.write_root_pose_to_sim(root[:, :7])
    robot.write_root_velocity_to_sim(root[:, 7:])
    robot.write_joint_state_to_sim(robot.data.default_joint_pos, robot.data.default_joint_vel)
    robot.reset()
    target = torch.tensor([wheel_speeds(v, w)], dtype=torch.float32, device=sim.device)
    steps = int(round(duration / TIMESTEP))
    rates = np.empty(steps)
    for k in range(steps):
        robot.set_joint_velocity_target(target, joint_ids=ids)
        robot.write_data_to_sim()
        sim.step(render=False)
        robot.update(TIMESTEP)
        rates[k] = float(robot.data.root_ang_vel_b[0, 2])
    return rates
'''


def isaac_lab_values(settings: Mapping, ground_mu: float, robot: RobotParams, timestep: float, spec) -> dict:
    """Each script variable's keywords (:data:`VARIABLES`), from the PhysX adapter's settings as it applies them."""
    s = PhysxSettings.model_validate(dict(settings))
    blocks = {call: kwargs for _, call, kwargs in python_blocks("isaaclab", s.model_dump(mode="json"))}
    physx = over_fragment(
        blocks["PhysxCfg"],
        {"solver_type": PHYSX_SOLVER[s.solver], "bounce_threshold_velocity": s.bounce_threshold},
        "PhysxCfg",
    )
    root = over_fragment(
        blocks["ArticulationRootPropertiesCfg"],
        {
            "solver_position_iteration_count": s.position_iterations,
            "solver_velocity_iteration_count": s.velocity_iterations,
        },
        "ArticulationRootPropertiesCfg",
    )
    root["enabled_self_collisions"] = False  # a robot's links never collide with each other, as in the adapter
    actuator = over_fragment(
        blocks["ImplicitActuatorCfg"], {"stiffness": 0.0, "damping": s.wheel_drive_damping}, "ImplicitActuatorCfg"
    )

    def material(mu: float) -> dict:
        return {
            "static_friction": mu,
            "dynamic_friction": mu,
            "restitution": 0.0,
            "friction_combine_mode": COMBINE,
            "restitution_combine_mode": "average",
        }

    return {
        "PHYSX": physx,
        "SIMULATION": {"device": "cpu", "dt": timestep, "gravity": (0.0, 0.0, -GRAVITY)},
        "WHEEL_MATERIAL": material(WHEEL_FRICTION),
        "GROUND_MATERIAL": material(ground_mu),
        "GROUND_PLANE": {"size": (100.0, 100.0)},
        "URDF_FILE": {
            "fix_base": False,
            "merge_fixed_joints": True,
            "self_collision": False,
            "force_usd_conversion": True,
            "make_instanceable": False,
        },
        "JOINT_DRIVE": {"drive_type": "force", "target_type": "none"},
        "JOINT_GAINS": {"stiffness": 0.0, "damping": 0.0},
        "ARTICULATION_ROOT": root,
        "RIGID_BODY": {"linear_damping": 0.0, "angular_damping": 0.0},
        "COLLISION": {"contact_offset": s.contact_offset, "rest_offset": 0.0},
        "INITIAL_STATE": {
            "pos": (0.0, 0.0, spec.base_height + SPAWN_CLEARANCE),
            "rot": (1.0, 0.0, 0.0, 0.0),
        },
        "WHEEL_ACTUATOR": {**actuator, "effort_limit_sim": robot.max_wheel_torque, "friction": 0.0},
        "PASSIVE_ACTUATOR": {"stiffness": 0.0, "damping": 0.0, "friction": 0.0},
    }


def write_isaac_lab_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text}: ``py``, the Isaac Lab script, and ``urdf``, the robot's description it loads
    (``<stem>.urdf``, the request's stem, "": ``isaac_sim``): the ``request``'s robot on a ground plane of its ground
    friction with the PhysX adapter's settings and the request's step, claiming its claims."""
    stem = request.stem or "isaac_sim"
    spec = request.robot.spec(request.robot_urdf)
    if spec.suspension or spec.couplings:
        raise ValueError(f"the Isaac Lab model of {spec.name} is not written: its passive suspension is not")
    values = isaac_lab_values(request.settings, request.ground_mu, request.robot, request.timestep, spec)
    doc_vars = [assign(var, value, f"{VARIABLES[var]}'s keywords") for var, value in values.items()]
    data = [
        claims_block(request.claims),
        assign("URDF", f"{stem}.urdf", "the robot's description, beside this file (the one simpick's adapter loads)"),
        assign("TIMESTEP", request.timestep, "s"),
        wheels_block(spec, request.robot.track),
        assign("PASSIVE_JOINTS", list(spec.passive_joints), "joints left free (no drive, no friction)"),
        *doc_vars,
    ]
    physx, root, actuator = values["PHYSX"], values["ARTICULATION_ROOT"], values["WHEEL_ACTUATOR"]
    header = [
        *request.header_lines,
        "NOT OPENED IN ISAAC SIM HERE: no Isaac Sim installs on simpick's machine; the script's keywords are checked "
        "against Isaac Lab's classes as quoted in simpick.engines.simulator_models.isaac_lab.FIELDS and its values "
        "against the profile (tests/test_vendor_models.py)",
        f"runs in {VERSION}: ./isaaclab.sh -p {stem}.py (every claim), or --v V --w W [--duration S]; it loads "
        f"{stem}.urdf from its own folder (the URDF importer converts it to USD) and prints, per run, the yaw-rate "
        "gain it measures",
        f"sets up: SimulationCfg (dt {_num(request.timestep)} s, CPU, PhysxCfg solver_type {physx['solver_type']} "
        f"(1 TGS, 0 PGS), bounce_threshold_velocity {_num(physx['bounce_threshold_velocity'])} m/s); a GroundPlaneCfg "
        f"whose material has friction {_num(request.ground_mu)} and the robot's (the scene's default material) "
        f"{_num(WHEEL_FRICTION)}, combined by {COMBINE!r}: each wheel contact has the ground's "
        f"{_num(request.ground_mu)}, restitution 0; {spec.name}'s URDF (UrdfFileCfg, floating, fixed joints merged, "
        f"no self-collision, solver iterations {root['solver_position_iteration_count']} position / "
        f"{root['solver_velocity_iteration_count']} velocity, link damping 0); the wheels one ImplicitActuatorCfg, "
        f"stiffness 0, damping {_num(actuator['damping'])} N m s/rad, effort_limit_sim "
        f"{_num(actuator['effort_limit_sim'])} N m, joint friction 0, velocity_limit_sim unset (the URDF's, as the "
        "adapter sets none)",
        "differs from simpick's adapter: its collision cylinders are 4 turned 64-sided convex prisms (the importer "
        "makes its own collider here) and it gives the contact the ground's coefficient as the average of 0 and twice "
        "the ground's (the same coefficient); PhysX 5.3 through SAPIEN 3 on the CPU, not Isaac Sim's PhysX",
        *claim_lines(request.claims),
    ]
    doc = (
        f"{request.name or spec.name}: Isaac Lab (PhysX) on flat ground, set up from simpick's PhysX adapter's "
        "values.\n\n"
        f"./isaaclab.sh -p {stem}.py runs every claim (CLAIMS) and prints the gain measured beside the one claimed;\n"
        f"./isaaclab.sh -p {stem}.py --v 0.5 --w 0.5 --duration 6 runs one command.\n"
    )
    return {"py": script(header, doc, IMPORTS, data, BODY), "urdf": standalone_urdf(spec.urdf)}


__all__ = ["FIELDS", "VARIABLES", "isaac_lab_values", "write_isaac_lab_model"]
