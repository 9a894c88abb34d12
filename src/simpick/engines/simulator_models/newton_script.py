"""Newton (Isaac Lab 3's physics): the robot on flat ground as a Python script that builds it with Newton's own API as
simpick's Newton adapter does (:class:`simpick.engines.newton_engine.NewtonWorld`): a ``newton.ModelBuilder`` with
SolverMuJoCo's custom attributes, a ground plane of the ground's friction and MuJoCo priority, the robot's URDF
through ``add_urdf`` (floating, no self-collision), the wheels' MuJoCo <intvelocity> actuators (or Newton's joint
velocity drive), the wheel x ground contact pairs (``mujoco:pair_*``) or the wheels' solimp, and SolverMuJoCo with
the adapter's options; beside it the URDF the adapter loads (:mod:`.python_script`).

SolverMuJoCo only: the profiles simpick runs are on it; the other solvers (XPBD, Steel, Kamino) are refused here.
"""

from __future__ import annotations

from simpick.engines.newton_engine import (
    GROUND_ATTRIBUTES,
    SPAWN_CLEARANCE,
    NewtonEngine,
    NewtonSettings,
    intvelocity_actuator,
    pair_values,
    robot_shape,
    solver_mujoco_options,
    wheel_solimp,
)
from simpick.engines.simulator_files.common import _num
from simpick.engines.simulator_files.python_setups import python_blocks
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
from simpick.engines.suspension import coupled_urdf

IMPORTS = """import numpy as np
import warp as wp

wp.config.quiet = True
import newton  # noqa: E402
from newton.solvers import mujoco as newton_mujoco  # noqa: E402
"""

BODY = '''

def build():
    """The model at rest, its solver, state and control: (model, solver, state, control, base body, wheel dofs,
    wheel actuators)."""
    builder = newton.ModelBuilder(gravity=GRAVITY)
    newton.solvers.SolverMuJoCo.register_custom_attributes(builder)
    ShapeConfig = newton.ModelBuilder.ShapeConfig
    builder.default_shape_cfg = ShapeConfig(**ROBOT_SHAPE)
    ground = builder.shape_count
    builder.add_shape_plane(
        cfg=ShapeConfig(mu=GROUND_FRICTION), width=0.0, length=0.0, custom_attributes=dict(GROUND_ATTRIBUTES)
    )
    joints0, bodies0 = builder.joint_count, builder.body_count
    builder.add_urdf(
        str(Path(__file__).resolve().with_name(URDF)),
        xform=wp.transform(BASE_POSITION, BASE_QUAT_XYZW),
        floating=True,
        enable_self_collisions=False,
    )
    joints = {builder.joint_label[j].rsplit("/", 1)[-1]: j for j in range(joints0, builder.joint_count)}
    bodies = {builder.body_label[b].rsplit("/", 1)[-1]: b for b in range(bodies0, builder.body_count)}
    wheel_dofs, wheel_shapes, actuators = [], [], []
    for wheel in WHEELS:
        j = joints[wheel["joint"]]
        dof = builder.joint_qd_start[j]
        if WHEEL_ACTUATOR is not None:  # a MuJoCo <intvelocity> actuator, no joint drive
            builder.joint_target_mode[dof] = int(newton.JointTargetMode.NONE)
            builder.joint_target_ke[dof] = builder.joint_target_kd[dof] = 0.0
            target = newton_mujoco.ActuatorTarget.joint(j)
            actuators.append(newton_mujoco.add_actuator_general(builder, target, **WHEEL_ACTUATOR))
        else:  # Newton's joint velocity drive, within the joint's effort limit
            builder.joint_target_mode[dof] = int(newton.JointTargetMode.VELOCITY)
            builder.joint_target_ke[dof] = 0.0
            builder.joint_target_kd[dof] = WHEEL_DRIVE_DAMPING
            builder.joint_effort_limit[dof] = MAX_WHEEL_TORQUE
        wheel_dofs.append(dof)
        child = builder.joint_child[j]
        wheel_shapes += [s for s in range(builder.shape_count) if builder.shape_body[s] == child]
    for name in PASSIVE_JOINTS:  # free
        j = joints[name]
        for dof in range(builder.joint_qd_start[j], builder.joint_qd_start[j] + builder.joint_dof_dim[j][1]):
            builder.joint_target_mode[dof] = int(newton.JointTargetMode.NONE)
            builder.joint_target_kd[dof] = builder.joint_target_ke[dof] = 0.0
    if WHEEL_SOLIMP is not None:  # the wheels' and the ground's contact impedance
        solimp = builder.custom_attributes["mujoco:geom_solimp"]
        if solimp.values is None:
            solimp.values = {}
        for s in [*wheel_shapes, ground]:
            solimp.values[s] = WHEEL_SOLIMP
    if PAIR is not None:  # a MuJoCo <pair> per wheel shape, the wheel's automatic ground contact filtered out
        for s in wheel_shapes:
            builder.add_shape_collision_filter_pair(ground, s)
            builder.add_custom_values(**{"mujoco:pair_geom1": ground, "mujoco:pair_geom2": s, **PAIR})
    model = builder.finalize(device="cpu")
    state, control = model.state(), model.control()
    newton.eval_fk(model, model.joint_q, model.joint_qd, state)
    solver = newton.solvers.SolverMuJoCo(model, **SOLVER)
    return model, solver, state, control, bodies[BASE_LINK], wheel_dofs, actuators


def run(v: float, w: float, duration: float) -> np.ndarray:
    """The model built at rest, the wheels' command (v, w) set before the first step, ``duration`` s stepped: the
    base's yaw rate about its own z axis after each step."""
    model, solver, state_0, control, base, dofs, actuators = build()
    state_1 = model.state()
    speeds = np.asarray(wheel_speeds(v, w), dtype=np.float32)
    if actuators:
        ctrl = control.mujoco.ctrl.numpy()
        ctrl[actuators] = speeds
        control.mujoco.ctrl.assign(ctrl)
    else:
        target = np.zeros(model.joint_dof_count, dtype=np.float32)
        target[dofs] = speeds
        control.joint_target_qd.assign(target)
    steps = int(round(duration / TIMESTEP))
    rates = np.empty(steps)
    for k in range(steps):
        state_0.clear_forces()
        solver.step(state_0, state_1, control, None, TIMESTEP)
        state_0, state_1 = state_1, state_0
        q = state_0.body_q.numpy()[base].astype(float)  # position, quaternion x y z w
        qd = state_0.body_qd.numpy()[base].astype(float)  # linear, angular (world frame)
        rates[k] = body_z_rate((q[6], q[3], q[4], q[5]), qd[3:])
    return rates
'''


def write_newton_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text}: ``py``, the script, and ``urdf``, the robot's description it loads (``<stem>.urdf``, the
    request's stem, "": ``newton``): the ``request``'s robot on a plane of its ground friction with the Newton
    adapter's settings and the request's step, claiming its claims."""
    stem = request.stem or "newton"
    spec_robot = request.robot.spec(request.robot_urdf)
    typed = NewtonSettings.model_validate(dict(request.settings))
    if typed.solver != "mujoco":
        raise ValueError(f"the Newton model is written for SolverMuJoCo only, not solver {typed.solver!r}")
    if spec_robot.suspension or spec_robot.couplings:
        raise ValueError(f"the Newton model of {spec_robot.name} is not written: its passive suspension is not")
    scenario = request.flat_world(spec_robot, typed.model_dump(mode="json"))
    NewtonEngine().check(scenario)
    blocks = {
        call: kwargs for _, call, kwargs in python_blocks("newton", typed.model_dump(mode="json"), request.ground_mu)
    }
    solver = over_fragment(blocks["SolverMuJoCo"], solver_mujoco_options(typed), "SolverMuJoCo")
    pair = None
    if typed.wheel_contact == "pairs":
        pair = over_fragment(
            blocks["newton.ModelBuilder.add_custom_values"], pair_values(typed, request.ground_mu), "the wheel pairs"
        )
    intvelocity = typed.wheel_drive == "intvelocity"
    version = NewtonEngine().version()
    data = [
        claims_block(request.claims),
        assign("URDF", f"{stem}.urdf", "the robot's description, beside this file (the one simpick's adapter loads)"),
        assign("BASE_LINK", spec_robot.base_link),
        assign(
            "BASE_POSITION",
            (0.0, 0.0, spec_robot.base_height + SPAWN_CLEARANCE),
            f"m: the base at rest height + {_num(SPAWN_CLEARANCE)} m, heading 0",
        ),
        assign("BASE_QUAT_XYZW", (0.0, 0.0, 0.0, 1.0)),
        assign("TIMESTEP", request.timestep, "s"),
        assign("GRAVITY", tuple(scenario.gravity), "m/s^2"),
        assign("GROUND_FRICTION", request.ground_mu, "the ground plane's friction coefficient"),
        assign("GROUND_ATTRIBUTES", GROUND_ATTRIBUTES, "MuJoCo takes every contact parameter of the ground's geom"),
        assign("ROBOT_SHAPE", robot_shape(request.ground_mu), "ShapeConfig of the robot's shapes"),
        wheels_block(spec_robot, request.robot.track),
        assign("PASSIVE_JOINTS", list(spec_robot.passive_joints), "joints left free"),
        assign("MAX_WHEEL_TORQUE", request.robot.max_wheel_torque, "N m, each wheel's torque bound"),
        assign(
            "WHEEL_ACTUATOR",
            intvelocity_actuator(typed.wheel_servo_kp, request.robot.max_wheel_torque) if intvelocity else None,
            "newton.solvers.mujoco.add_actuator_general's keywords: a MuJoCo <intvelocity> actuator per wheel\n"
            "(None: Newton's joint velocity drive, gain WHEEL_DRIVE_DAMPING)",
        ),
        assign("WHEEL_DRIVE_DAMPING", typed.wheel_drive_damping, "N m s/rad"),
        assign(
            "WHEEL_SOLIMP",
            wheel_solimp(typed) if typed.wheel_contact == "decoupled" else None,
            "mujoco:geom_solimp of the wheel and ground shapes (wheel_contact decoupled)",
        ),
        assign(
            "PAIR",
            pair,
            "mujoco:pair_* values of each wheel shape x ground pair (wheel_contact pairs; None: Newton's contact)",
        ),
        assign("SOLVER", solver, "SolverMuJoCo's keywords"),
    ]
    contact = {
        "pairs": "a MuJoCo <pair> per wheel shape and the ground (PAIR), the wheels' automatic contact filtered out",
        "decoupled": "Newton's automatic contact with the wheels' and the ground's solimp (WHEEL_SOLIMP)",
        "default": "Newton's automatic contact (its shape material converted to MuJoCo's)",
    }[typed.wheel_contact]
    drive = (
        f"a MuJoCo <intvelocity> actuator per wheel (kp {_num(typed.wheel_servo_kp)} N m/rad, critically damped, "
        f"torque within +-{_num(request.robot.max_wheel_torque)} N m)"
        if intvelocity
        else f"Newton's joint velocity drive (kd {_num(typed.wheel_drive_damping)} N m s/rad, effort limit "
        f"{_num(request.robot.max_wheel_torque)} N m)"
    )
    header = [
        *request.header_lines,
        f"runs as it is, with newton installed: python {stem}.py (every claim), or --v V --w W [--duration S]; "
        f"it loads {stem}.urdf from its own folder and prints, per run, the yaw-rate gain it measures",
        f"builds, with Newton's own API as simpick's Newton adapter does: a ModelBuilder with SolverMuJoCo's "
        f"attributes, a ground plane (friction {_num(request.ground_mu)}, MuJoCo priority 1), {spec_robot.name}'s URDF "
        f"(add_urdf, floating, no self-collision), wheels driven by {drive}, contact: {contact}; SolverMuJoCo "
        f"(SOLVER) on Warp's CPU device, step {_num(request.timestep)} s",
        *claim_lines(request.claims),
        f"written for Newton {version} (the version simpick's adapter ran)",
    ]
    doc = (
        f"{request.name or spec_robot.name}: Newton (SolverMuJoCo) on flat ground, as simpick's adapter builds it.\n\n"
        f"python {stem}.py runs every claim (CLAIMS) and prints the gain measured beside the one claimed;\n"
        f"python {stem}.py --v 0.5 --w 0.5 --duration 6 runs one command.\n"
    )
    return {
        "py": script(header, doc, IMPORTS, data, BODY),
        "urdf": standalone_urdf(coupled_urdf(spec_robot)),
    }
